// curriculum_internal.h: what curriculum.cpp (the loader and roger.stage / roger.learned) shares
// with curriculum_stage.cpp (reading one stage table). Private to engine/script/curriculum.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include <lua.hpp>

#include "script/curriculum/curriculum.h"

namespace roger {
namespace curriculum_detail {

// Pushes the world as the Lua callbacks see it (the task's judge, not Roger's senses): a table
// {objects = {{name, shape, colour, x, y, held, region}, ...}, goals = {{name, x, y, radius}, ...},
//  obstacles = {{name, x, y, shape}, ...}}.
void push_world(lua_State* L, const World& world);

// The stand-in roger.learned(name): behaves as the skill bound to it at train time; until then
// it has no reference (NOREF), so a stage trained without binding it simply never sees it act.
class LearnedRef final : public StandIn {
 public:
  explicit LearnedRef(std::string name) : StandIn(std::move(name)) {}
  const char* kind() const override { return "learned"; }
  ControllerPtr copy() const override { return std::make_shared<LearnedRef>(*this); }
};

// A Lua function a stage keeps (absorbing, reward or teacher), with where it was defined.
struct LuaCallback {
  int ref = LUA_NOREF;
  std::string file;
  int line = 0;
  // The function on top of L's stack, popped into the registry, with its file and line.
  static LuaCallback keep(lua_State* L);
};

// Reads a stage table at `index` into `st`, raising Lua errors "stage 'X': ..." (at the caller's
// file:line when called from Lua). Functions given for absorbing, reward and teacher are kept in
// the registry. `naming_file` is the file the stage is written in (as messages show it): its
// `scenario`, when a path, is looked for beside it first, then beside `curriculum_file` (the
// curriculum returning it, which may have set the field of a stage a library made:
// resolve_scenario_near).
void parse_stage(lua_State* L, int index, CurriculumStage& st, LuaCallback& absorb_fn, LuaCallback& reward_fn,
                 LuaCallback& teacher_fn, const std::string& naming_file, const std::string& curriculum_file = "");

// ---- strict tables: what callbacks read (curriculum.cpp)

// Gives the table on top of L's stack the metatable `type_name` (made once), whose __index is
// `unknown`: reading a name the table does not hold calls it, so a misspelt name is an error
// rather than a nil that quietly changes what a callback decides.
void set_strict_index(lua_State* L, const char* type_name, lua_CFunction unknown);
// An `unknown` above raises with raise_at_reader (script/sandbox/lua_sandbox.h).

// ---- teachers (curriculum_tasks.cpp, curriculum_teacher.cpp)

// Registers roger.int, roger.real, roger.choice and roger.teacher.* (on the `roger` global).
void install_teaching_api(lua_State* L);
// Reads a stage's `tasks`, `teacher` and `test` (after its contexts), checking them against the
// stage's scenario and params; `episodes_given`/`final_given`: its checkpoints write those fields.
void parse_teaching(lua_State* L, const LuaFields& f, CurriculumStage& st, LuaCallback& teacher_fn,
                    bool episodes_given, bool final_given);
// A callback's one result (those from `base` + 1 on): more are refused, as `what` must return
// `expected` (then `hint`), at the callback's line; none is pushed as nil.
void refuse_more_results(lua_State* L, int base, const std::string& what, const std::string& expected,
                         const std::string& hint, const LuaCallback& fn);

// A teacher that calls the stage's Lua function(history, rng) before each training episode; its
// state names the function's file as `file_named` (as results name it), its errors by fn.file.
std::unique_ptr<Teacher> make_lua_teacher(LuaSandbox& sandbox, const CurriculumStage& stage, const LuaCallback& fn,
                                          const TaskSpace& space, uint64_t seed, const std::string& file_named);

// Why `name` cannot name a learned skill (a primitive kind, which always means that kind's default
// primitive), or "" (curriculum_stage.cpp).
std::string skill_name_problem(const std::string& name);

// ---- parameters (curriculum_params.cpp)

// The line where the stage's `params` (or, with a context's name, that context's) is written in
// the stage's file, read from its text from the stage's line; the nearest line known (the
// context's, `contexts`, the stage's) when it is not written there.
int params_line(const CurriculumStage& st, const std::string& context);
// The same for another field of the stage or of its context (`init`, say).
int field_line(const CurriculumStage& st, const std::string& context, const std::string& field);
// Checks the stage's params and each context's against the stage's scenario (once the stage's
// file and line are known): every parameter its scenario would refuse, at once, as a ScriptError
// at the line of the params table that gives it. Loads the scenario only when there are params.
void check_stage_params(const CurriculumStage& st);
// `e` moved from a stage's roger.stage{ line (or plain table's name line) to the line its message's
// field is written on ("stage 'S': learner: unknown field 'alpah'": the alpah = line), read from
// the script's text; none when the field is not written there, or the error is not one of a
// roger.stage call (a field changed after the call is not what the text shows).
std::optional<ScriptError> at_stage_field(const ScriptError& e);

}  // namespace curriculum_detail
}  // namespace roger
