// lua_control.h: the control basis in Lua. Installs into a LuaSandbox the functions that build
// controllers (primitives, subject-to compositions, sequences, state-to-action policies) and
// predicates over their states:
//
//   roger.primitive(kind, {param = value, ..., name = "..."})   c:with{...}   c:subject_to(sup)
//   roger.subject_to(sub, sup)   roger.compose("phi1 <| phi4 <| phi5", {phi1 = carry})
//   roger.sequence(name, {step, ...})   roger.policy(name, {actions = {...}, table = {...}, ...})
//   roger.converged(c)   roger.gamma(c, "NOREF")   roger.all{...}   roger.any{...}
//   roger.negate(p) (also roger["not"])   roger.held(p, seconds)
//
// Controllers and predicates are Lua userdata that share ownership of the C++ objects, so what a
// script builds stays valid in C++ after the Lua state is closed. Every mistake is a Lua error at
// the calling script's file:line naming the function and what exists. docs/control.md is the
// reference.
#pragma once

#include <string>
#include <vector>

#include "control/control.h"
#include "script/sandbox/lua_sandbox.h"
#include "control/predicate.h"

struct lua_State;

namespace roger {

// The longest time limit a policy or a stage may set, and a time per object (simulated seconds):
// an hour of Roger's time; more is a unit mistake, or a goal that never holds run for ever.
constexpr double kMaxTimeLimit = 3600.0;

// Why `goal` can never hold within an episode of `time_limit` simulated seconds (a held() longer
// than the episode, often a count of ticks written where seconds are meant), or "" when it can.
std::string never_holds_within(const Predicate& goal, double time_limit);

// Why `goal` holds at an episode's first tick whatever happens (it rests on a roger.all() of no
// parts, which is true, or on the roger.negate of one that never holds), or after a roger.held's
// seconds of such a part, or "" when it does not: refused as roger.any() of none is, as a goal no
// learning can matter to. Whatever the time limit.
std::string holds_at_once(const Predicate& goal);

// Installs the control-basis API into the sandbox's global `roger` table, creating the table if
// the sandbox has none yet (a scenario loader may already have made it: it is extended, not
// replaced). Throws ScriptError if the state is out of memory. Call once per sandbox.
void install_control_api(LuaSandbox& sandbox);

// Ends the definition phase, once the script has finished loading: binds every controller that
// was referred to by name before it was defined, and checks that no skill contains itself.
// Throws ScriptError at the file:line of the reference or definition at fault ("skill 'A' contains
// itself: A -> B -> A"). After this, a name given where a controller is expected must name an
// existing controller, and the functions that make controllers and predicates refuse to
// (lua_refuse_after_load).
void finish_control_definitions(LuaSandbox& sandbox);

// Raises the error of an API function that makes `what` (controllers and predicates, stages)
// called once the script has loaded: from a function the engine calls as it runs (an absorbing,
// reward or teacher function), where each call would make another. Names the function called.
[[noreturn]] void lua_refuse_after_load(lua_State* L, const std::string& what);

// A controller the script gave a name (a sequence, a policy, or a primitive made with name=).
struct NamedController {
  std::string name;
  ControllerPtr controller;
  std::string file;  // where it was defined, as shown in messages
  int line = 0;
};

// The controllers the script named so far, in the order they were defined.
std::vector<NamedController> named_controllers(LuaSandbox& sandbox);

// Every controller the script made (primitives, defaults used by name, compositions, skills,
// policies' `done` predicates), in the order made; name stand-ins are not included.
std::vector<ControllerPtr> script_controllers(LuaSandbox& sandbox);

// Pushes a controller as a Lua value (the same userdata each time for the same controller).
void lua_push_controller(lua_State* L, const ControllerPtr& controller);

// Pushes a predicate as a Lua value.
void lua_push_predicate(lua_State* L, const PredicatePtr& predicate);

// The controller a Lua value holds, or null when it is not a controller.
ControllerPtr lua_to_controller(lua_State* L, int index);

// The predicate a Lua value holds, or null when it is not a predicate.
PredicatePtr lua_to_predicate(lua_State* L, int index);

// Reads a controller where one is expected: a controller value, or a string naming one (a
// controller the script named, before or after this point; or a primitive kind, meaning that
// kind's shared default instance). Anything else raises "context: <what> must be a controller ...,
// got <value>" at the caller's file:line. For sandboxes with the control API installed.
ControllerPtr lua_check_controller(lua_State* L, int index, const std::string& context,
                                   const std::string& what);

// Reads a predicate where one is expected, or raises "context: <what> must be a predicate ...".
PredicatePtr lua_check_predicate(lua_State* L, int index, const std::string& context,
                                 const std::string& what);

// One of the control API's functions, given itself where what it makes was meant (absorbing =
// roger.converged, its call forgotten): its name, "roger.converged", and for one that makes a
// predicate, a call of it as a script writes one, "roger.converged(c)" ("" for the others).
struct ApiFunction {
  std::string name;            // "" when the value is none of them
  std::string predicate_call;
};

// The control API function the value at `index` is, or empty names.
ApiFunction lua_control_function(lua_State* L, int index);

// Whether `path` ("roger.converged") names a control API function that makes a predicate: for
// roger check's static pass, which reports a call of one taken for a truth value by and, or, not.
bool makes_predicate(const std::string& path);

// A Lua value as messages show it: "number 3", "string 'x'", "nil", "a table",
// "controller 'phi1'", "predicate converged(phi3)".
std::string lua_describe_value(lua_State* L, int index);

// The value at `index` as a scenario parameter's text, as --set gives it (a number, a string or a
// boolean: "3", "0.95", "circle", "true"), or a Lua error "<where> must be a number, string or
// boolean, got ...". For a curriculum's task axes and levels and a skill script's policy params.
std::string lua_param_text(lua_State* L, int index, const std::string& where);

// A table {key = value} of scenario parameters at `index`, appended to `out` sorted by key. A
// wrong table is named `where`, a wrong value `<key_where><key>` (by default `<where>.<key>`).
void lua_read_params(lua_State* L, int index, const std::string& where,
                     std::vector<std::pair<std::string, std::string>>& out, const std::string& key_where = "");

// Whether a controller is the stand-in for a name used before its controller was defined. It
// behaves exactly as the controller it names (children() gives that controller); pictures and
// usage counts may look through it.
bool is_name_reference(const Controller& controller);

}  // namespace roger
