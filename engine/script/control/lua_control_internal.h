// lua_control_internal.h: what the files of the Lua control API share (private to
// engine/script/control).
// lua_control.cpp holds the script's book of definitions and the value bridge; the constructors
// live in lua_control_primitives.cpp (primitives and their parameters), lua_control_compose.cpp
// (subject-to compositions), lua_control_skills.cpp (sequences and policies),
// lua_control_predicates.cpp (predicates) and lua_control_metamethods.cpp (fields and tostring).
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <lua.hpp>

#include "control/primitives.h"
#include "script/control/lua_control.h"
#include "script/sandbox/lua_sandbox.h"

namespace roger {
namespace lua_control_detail {

constexpr const char* kControllerType = "roger.Controller";
constexpr const char* kPredicateType = "roger.Predicate";

// Raises a Lua error with the text as is, located at the Lua caller's file:line.
[[noreturn]] void raise(lua_State* L, const std::string& message);

// A place in a script: its file as shown in messages, and the line.
struct Location {
  std::string file;
  int line = 0;
};

// The stand-in for a controller named before it was defined. It behaves as the controller it is
// bound to when the script finishes loading; until then (or if never bound) it has no reference.
class NameReference final : public StandIn {
 public:
  explicit NameReference(std::string name) : StandIn(std::move(name)) {}
  const char* kind() const override { return target() ? target()->kind() : "reference"; }
  ControllerPtr copy() const override { return std::make_shared<NameReference>(*this); }
};

// A name used before its controller was defined, with where it was first used.
struct Reference {
  std::shared_ptr<NameReference> ref;
  std::string context;  // "roger.sequence('A'): step 2"
  Location where;
  // Lua's traceback when `where` is a library's line that another file called (a stage built by a
  // helper module): the error of a name never defined names the caller's line too.
  std::string traceback;
};

// What a script has defined: named controllers, default primitives, pending references. Lives in
// a userdata in the Lua registry, so it goes away with the state (the C++ objects it shares live
// on wherever the engine keeps them).
struct ControlBook {
  std::vector<NamedController> named;  // definition order
  std::map<std::string, size_t> by_name;
  std::map<std::string, PrimitivePtr> defaults;  // kind -> the shared default instance
  std::map<std::string, Reference> references;   // name -> its stand-in
  std::vector<std::string> reference_order;      // names in the order first referenced
  std::vector<ControllerPtr> made;               // every controller made, in order
  bool finished = false;
  size_t objects = 0;
  size_t table_entries = 0;
};

// The book of the state, or a Lua error when the control API is not installed.
ControlBook& book_of(lua_State* L);

// Counts one more object made by the script against the cap, and a little work against the
// instruction budget (constructing a controller costs far more than one VM instruction).
void count_object(lua_State* L, ControlBook& book);

// Records a controller the script made (the book shares its ownership until the state closes).
template <class T>
std::shared_ptr<T> made(ControlBook& book, std::shared_ptr<T> c) {
  book.made.push_back(c);
  return c;
}

// "phi0, search, phi1, ..." in make_primitive's order.
std::string kinds_text();

// Whether a name is one of the primitive kinds.
bool is_kind(const std::string& name);

// "named controllers: A, B; primitive kinds: phi0, ..." for unknown-name messages.
std::string known_names(const ControlBook& book);

// "controller 'Phi7' (sequence)", or "controller 'phi1'" when the name is the kind.
std::string controller_text(const Controller& c);

// Resolves a name among the script's named controllers, then as a primitive kind (that kind's
// shared default instance, made on first use). Null when it is neither.
ControllerPtr resolve_now(lua_State* L, ControlBook& book, const std::string& name);

// Checks a new controller name and records the controller under it, with the caller's location.
void register_name(lua_State* L, ControlBook& book, const std::string& context, const std::string& name,
                   const ControllerPtr& c);

// The controller held by the value at index, or null.
ControllerPtr* test_controller(lua_State* L, int index);

// The predicate held by the value at index, or null.
PredicatePtr* test_predicate(lua_State* L, int index);

// The controller a method is called on, with a hint for the `c.with{...}` slip.
ControllerPtr self_controller(lua_State* L, const char* method);

// ---- the functions install() puts into the `roger` table and the metatables ----

// lua_control_primitives.cpp
int l_primitive(lua_State* L);
int l_with(lua_State* L);
int l_param(lua_State* L);
int l_params(lua_State* L);

// lua_control_compose.cpp
int l_subject_to_method(lua_State* L);
int l_subject_to(lua_State* L);
int l_compose(lua_State* L);

// lua_control_skills.cpp
int l_sequence(lua_State* L);
int l_policy(lua_State* L);
int l_bind(lua_State* L);

// lua_control_predicates.cpp
int l_converged(lua_State* L);
int l_sorted(lua_State* L);
int l_gamma(lua_State* L);
int l_all(lua_State* L);
int l_any(lua_State* L);
int l_negate(lua_State* L);
int l_held(lua_State* L);

// lua_control_metamethods.cpp
int l_controller_index(lua_State* L);
int l_controller_newindex(lua_State* L);
int l_controller_tostring(lua_State* L);
int l_predicate_tostring(lua_State* L);
int l_predicate_index(lua_State* L);

}  // namespace lua_control_detail
}  // namespace roger
