// curriculum_internal.h: what curriculum.cpp (the loader and roger.stage / roger.learned) shares
// with curriculum_stage.cpp (reading one stage table). Private to engine/script/curriculum.
#pragma once

#include <string>

#include <lua.hpp>

#include "script/curriculum/curriculum.h"

namespace roger {
namespace curriculum_detail {

// Pushes the world as the Lua callbacks see it (the task's judge, not Roger's senses): a table
// {objects = {{name, colour, x, y, held, region}, ...}, goals = {{name, x, y, radius}, ...}}.
void push_world(lua_State* L, const World& world);

// The stand-in roger.learned(name): behaves as the skill bound to it at train time; until then
// it has no reference (NOREF), so a stage trained without binding it simply never sees it act.
class LearnedRef final : public StandIn {
 public:
  explicit LearnedRef(std::string name) : StandIn(std::move(name)) {}
  const char* kind() const override { return "learned"; }
  ControllerPtr copy() const override { return std::make_shared<LearnedRef>(*this); }
};

// A Lua function a stage keeps (absorbing or reward), with where it was defined.
struct LuaCallback {
  int ref = LUA_NOREF;
  std::string file;
  int line = 0;
};

// Reads a stage table at `index` into `st`, raising Lua errors "stage 'X': ..." (at the caller's
// file:line when called from Lua). Functions given for absorbing/reward are kept in the registry.
// `naming_file` is the file the stage is written in (as messages show it): its `scenario`, when a
// path, is looked for beside it first (resolve_scenario_near).
void parse_stage(lua_State* L, int index, CurriculumStage& st, LuaCallback& absorb_fn, LuaCallback& reward_fn,
                 const std::string& naming_file);

// ---- parameters (curriculum_params.cpp)

// The line where the stage's `params` (or, with a context's name, that context's) is written in
// the stage's file, read from its text from the stage's line; the nearest line known (the
// context's, `contexts`, the stage's) when it is not written there.
int params_line(const CurriculumStage& st, const std::string& context);
// Checks the stage's params and each context's against the stage's scenario (once the stage's
// file and line are known): every parameter its scenario would refuse, at once, as a ScriptError
// at the line of the params table that gives it. Loads the scenario only when there are params.
void check_stage_params(const CurriculumStage& st);

}  // namespace curriculum_detail
}  // namespace roger
