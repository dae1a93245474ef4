// curriculum_teacher.cpp: a stage's Lua function as its teacher: teacher = function(history, rng)
// ... return {obstacles = 2, shape = "spade"} end, called between training episodes only, under
// the sandbox's budgets. `history` lists the trial's earlier training episodes in order, each
// {task = {...}, success = ..., reward = ..., time = ...} (reading another field is an error);
// `rng` is an rng object of its own, seeded from the trial. Axes the result leaves out are drawn
// uniformly; a value outside the space is an error naming the parameter and the space; a value
// for a parameter the run fixes (--set, a batch run's params) is ignored, the run's value standing.
#include <cmath>
#include <cstdlib>

#include "core/error.h"
#include "core/text.h"
#include "script/curriculum/curriculum_internal.h"
#include "script/sandbox/lua_sandbox.h"
#include "script/scenario/scenario.h"

namespace roger {
namespace curriculum_detail {
namespace {

// A parameter's text back as the Lua value a script would write: an integer, a number, a boolean
// or else a string.
void push_param_value(lua_State* L, const std::string& text) {
  char* end = nullptr;
  const long long i = std::strtoll(text.c_str(), &end, 10);
  if (!text.empty() && *end == '\0' && std::to_string(i) == text) return lua_pushinteger(L, i);
  const double d = std::strtod(text.c_str(), &end);
  if (!text.empty() && *end == '\0' && std::isfinite(d) && format_number(d) == text) return lua_pushnumber(L, d);
  if (text == "true" || text == "false") return lua_pushboolean(L, text == "true");
  lua_pushstring(L, text.c_str());
}

// A history entry's __index, reached only by a name it does not hold: an error at the teacher's
// line naming its fields, where a nil (`h.sucess`) would quietly change what the teacher picks.
int history_unknown_field(lua_State* L) {
  const std::vector<std::string> fields = {"reward", "success", "task", "time"};
  const std::string key = lua_type(L, 2) == LUA_TSTRING ? lua_tostring(L, 2) : luaL_tolstring(L, 2, nullptr);
  return raise_at_reader(L, "a history entry has no field '" + key + "'" + suggestion(key, fields) +
                                "; its fields: " + join(fields));
}

class LuaTeacher final : public Teacher {
 public:
  LuaTeacher(LuaSandbox& sandbox, const CurriculumStage& stage, const LuaCallback& fn, const TaskSpace& space,
             uint64_t seed)
      : sandbox_(sandbox), where_(stage.where() + ": teacher function"), fn_(fn), space_(space),
        fill_(Rng::mix(seed, 1)) {
    sandbox_.call_protected(0, [&](lua_State* L) {
      lua_newtable(L);
      history_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
      lua_push_rng(L, seed);
      rng_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
    });
  }
  ~LuaTeacher() override {
    lua_State* L = sandbox_.state();
    luaL_unref(L, LUA_REGISTRYINDEX, history_ref_);
    luaL_unref(L, LUA_REGISTRYINDEX, rng_ref_);
  }
  std::string kind() const override { return "function"; }

  TaskPick next() override {
    lua_State* L = sandbox_.state();
    LuaStackGuard guard(L);
    lua_rawgeti(L, LUA_REGISTRYINDEX, fn_.ref);
    lua_rawgeti(L, LUA_REGISTRYINDEX, history_ref_);
    lua_rawgeti(L, LUA_REGISTRYINDEX, rng_ref_);
    try {
      sandbox_.call(2, 1);
    } catch (const ScriptError& e) {
      throw ScriptError(where_ + ": " + e.message, e.file.empty() ? fn_.file : e.file, e.file.empty() ? fn_.line : e.line,
                        e.traceback);
    }
    const ParamList given = read_result();
    TaskPoint task = space_.sample(fill_);  // what the result leaves out is drawn uniformly
    for (const auto& [key, value] : given) {
      if (space_.is_fixed(key)) continue;  // --set (or a batch run's params) fixes it for this run
      const int i = space_.index(key);
      std::string why;
      const std::optional<double> v = i < 0 ? std::nullopt : space_.value_of(size_t(i), value, &why);
      if (i < 0)
        throw ScriptError(where_ + " returned '" + key + "', which is not a parameter of the task space (" +
                              space_.describe() + ")", fn_.file, fn_.line, "");
      if (!v)
        throw ScriptError(where_ + " returned " + key + " = " + value + ", outside the task space: " + key +
                              " takes " + why, fn_.file, fn_.line, "");
      task[size_t(i)] = *v;
    }
    return {task, {}, std::nullopt};
  }

  void record(const TaskOutcome& o) override {
    ++episodes_;
    const ParamList task = space_.params(o.task);
    sandbox_.call_protected(0, [&](lua_State* L) {
      lua_rawgeti(L, LUA_REGISTRYINDEX, history_ref_);
      lua_createtable(L, 0, 4);
      lua_createtable(L, 0, int(task.size()));
      for (const auto& [k, v] : task) {
        push_param_value(L, v);
        lua_setfield(L, -2, k.c_str());
      }
      lua_setfield(L, -2, "task");
      lua_pushboolean(L, o.success);
      lua_setfield(L, -2, "success");
      lua_pushnumber(L, o.reward);
      lua_setfield(L, -2, "reward");
      lua_pushnumber(L, o.sim_s);
      lua_setfield(L, -2, "time");
      set_strict_index(L, "roger.HistoryEntry", history_unknown_field);
      lua_rawseti(L, -2, episodes_);
      lua_pop(L, 1);
    });
  }

  nlohmann::json state() const override {
    return {{"kind", kind()}, {"episodes", episodes_}, {"function", fn_.file + ":" + std::to_string(fn_.line)}};
  }

 private:
  // The function's result (on the stack top) as task parameters; a bad one is an error at the
  // function's line. A string for a numeric axis is refused: "2" is a slip for 2 that would pass
  // unseen while `true` does not.
  ParamList read_result() {
    ParamList given;
    try {
      sandbox_.call_protected(1, [&](lua_State* L) {
        if (!lua_istable(L, -1))
          throw ScriptError(where_ + " must return a table of task parameters {" + space_.describe() + "}, got " +
                                std::string(luaL_typename(L, -1)), fn_.file, fn_.line, "");
        refuse_numeric_strings(L, lua_gettop(L));
        read_params_into(L, -1, where_ + "'s result", given);
      });
    } catch (const ScriptError& e) {
      if (!e.file.empty()) throw;
      throw ScriptError(e.message, fn_.file, fn_.line, "");  // a bad value in the result: the function's line
    }
    return given;
  }
  void refuse_numeric_strings(lua_State* L, int t) const {
    lua_pushnil(L);
    while (lua_next(L, t)) {
      const int i = lua_type(L, -2) == LUA_TSTRING ? space_.index(lua_tostring(L, -2)) : -1;
      if (i >= 0 && lua_type(L, -1) == LUA_TSTRING && space_.dims()[size_t(i)].kind != TaskDim::Kind::kChoice) {
        const TaskDim& d = space_.dims()[size_t(i)];
        throw ScriptError(where_ + " returned " + d.name + " = \"" + lua_tostring(L, -1) + "\" (a string), but " +
                              d.name + " takes a number: " + d.text() + "; return the number itself",
                          fn_.file, fn_.line, "");
      }
      lua_pop(L, 1);
    }
  }

  LuaSandbox& sandbox_;
  std::string where_;
  LuaCallback fn_;
  TaskSpace space_;
  Rng fill_;
  int history_ref_ = LUA_NOREF, rng_ref_ = LUA_NOREF;
  int episodes_ = 0;
};

}  // namespace

std::unique_ptr<Teacher> make_lua_teacher(LuaSandbox& sandbox, const CurriculumStage& stage, const LuaCallback& fn,
                                          const TaskSpace& space, uint64_t seed) {
  return std::make_unique<LuaTeacher>(sandbox, stage, fn, space, seed);
}

}  // namespace curriculum_detail
}  // namespace roger
