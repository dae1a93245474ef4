// curriculum_teacher.cpp: a stage's Lua function as its teacher: teacher = function(history, rng)
// ... return {obstacles = 2, shape = "spade"} end, called between training episodes only, under
// the sandbox's budgets. `history` lists the trial's earlier training episodes in order, each
// {task = {...}, success = ..., reward = ..., time = ...} (reading another field is an error);
// `rng` is an rng object of its own, seeded from the trial. Axes the result leaves out are drawn
// uniformly; a value outside the space is an error naming the parameter and the space; a value
// for a parameter the run fixes (--set, a batch run's params) is ignored, the run's value standing.
#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "core/error.h"
#include "core/text.h"
#include "script/control/lua_control.h"
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

// The history a teacher function reads is a view of the trial's record, read-only: a write
// (`history[1].success = 7`, `table.remove(history)`) would change what every later call sees.
// A view is the sandbox's (lua_new_view): an empty table holding its data under a key no
// script can write, whose metatable reads through: a missing field of an entry or a task is an
// error naming the fields (a nil from `h.sucess` or `h.task.obstacls` would quietly change what
// the teacher picks), a list index past the end is nil, `#`, pairs and next see the data.
char kNote;  // a lightuserdata key: what a task view adds to its unknown-field message

// __index of an entry or a task view: the field, or an error naming the fields there are.
int view_index(lua_State* L) {
  lua_check_view_data(L, "the teacher's history");
  lua_pushvalue(L, 2);
  if (lua_rawget(L, -2) != LUA_TNIL) return 1;
  lua_pop(L, 1);
  std::vector<std::string> fields;
  lua_pushnil(L);
  while (lua_next(L, -2)) {
    lua_pop(L, 1);
    if (lua_type(L, -1) == LUA_TSTRING) fields.push_back(lua_tostring(L, -1));
  }
  std::sort(fields.begin(), fields.end());
  lua_pushlightuserdata(L, &kNote);
  const bool task = lua_rawget(L, 1) == LUA_TSTRING;
  const std::string note = task ? lua_tostring(L, -1) : "";
  const std::string key = lua_type(L, 2) == LUA_TSTRING ? lua_tostring(L, 2) : luaL_tolstring(L, 2, nullptr);
  return raise_at_reader(L, std::string(task ? "a history entry's task" : "a history entry") + " has no field '" + key +
                                "'" + suggestion(key, fields) +
                                (fields.empty() ? "; it has none" : "; its fields: " + join(fields)) + note);
}

// __index of the list: an entry, or nil past the end (`history[#history]` of an empty history).
// A name read on the list itself is an error (found by a probe: `if history.success then` read nil
// and the teacher never lifted, without a word); the rng's methods on it mean the arguments were
// taken in the wrong order (`function(rng, history)` read `rng:int` here).
int view_list_index(lua_State* L) {
  lua_check_view_data(L, "the teacher's history");
  if (lua_type(L, 2) != LUA_TSTRING) {
    lua_pushvalue(L, 2);
    lua_rawget(L, -2);
    return 1;
  }
  const std::string key = lua_tostring(L, 2);
  if (lua_is_rng_method(L, key))
    return raise_at_reader(L, "the history has no method '" + key + "': a teacher function takes the history "
                              "first and the rng second, function(history, rng) ... rng:" + key + "(...) ... end");
  return raise_at_reader(L, "the history is a list of the trial's training episodes, in order, and has no field '" +
                                key + "': read an entry's, history[i]." + key + " (the last: history[#history]." + key +
                                ", after checking #history > 0)");
}

int view_newindex(lua_State* L) {
  return raise_at_reader(L, "the history is read-only: a change would be seen by every later call of the "
                            "teacher; keep notes of your own in a table of your own (an upvalue, say)");
}

// pairs of a view visits its data as the sandbox's pairs visits a table: in the same order in every
// run (found by a probe: a teacher that read the fields of an entry with pairs took them in the
// order of Lua's string hashes, seeded per run, and chose other tasks from one seed).
int view_pairs(lua_State* L) {
  lua_check_view_data(L, "the teacher's history");
  return lua_pairs_in_order(L, -1);
}

// Replaces the table on the stack top with a read-only view of it, of metatable `type_name`
// (made once per state). A task view has a `note`, which ends its unknown-field message.
void make_view(lua_State* L, const char* type_name, lua_CFunction index, const std::string* note = nullptr) {
  const int data = lua_gettop(L);
  lua_new_view(L, data);
  if (note) {
    lua_pushlightuserdata(L, &kNote);
    lua_pushstring(L, note->c_str());
    lua_rawset(L, -3);
  }
  if (luaL_newmetatable(L, type_name)) {
    const luaL_Reg methods[] = {{"__index", index}, {"__newindex", view_newindex}, {"__len", lua_view_len},
                                {"__pairs", view_pairs}, {nullptr, nullptr}};
    luaL_setfuncs(L, methods, 0);
    lua_pushstring(L, "the teacher's history (read-only)");
    lua_setfield(L, -2, "__metatable");  // getmetatable shows this; setmetatable is refused
  }
  lua_setmetatable(L, -2);
  lua_replace(L, data);
}

class LuaTeacher final : public Teacher {
 public:
  LuaTeacher(LuaSandbox& sandbox, const CurriculumStage& stage, const LuaCallback& fn, const TaskSpace& space,
             uint64_t seed, const std::string& file_named)
      : sandbox_(sandbox), where_(stage.where() + ": teacher function"), fn_(fn), file_named_(file_named), space_(space),
        fixed_space_(space.fixed_space()), fill_(Rng::mix(seed, 1)) {
    for (const auto& name : space.fixed()) fixed_note_ += (fixed_note_.empty() ? "" : ", ") + name;
    if (!fixed_note_.empty())
      fixed_note_ = " (" + fixed_note_ + (space.fixed().size() == 1 ? " is" : " are") +
                    " fixed for this run, by --set or the batch run's params, and in no task)";
    sandbox_.call_protected(0, [&](lua_State* L) {
      lua_newtable(L);
      lua_pushvalue(L, -1);
      history_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
      make_view(L, "roger.History", view_list_index);
      view_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
      rng_key_ = lua_push_rng(L, seed);
      rng_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
    });
  }
  ~LuaTeacher() override {
    lua_State* L = sandbox_.state();
    luaL_unref(L, LUA_REGISTRYINDEX, history_ref_);
    luaL_unref(L, LUA_REGISTRYINDEX, view_ref_);
    luaL_unref(L, LUA_REGISTRYINDEX, rng_ref_);
  }
  std::string kind() const override { return "function"; }

  // A fault names the training episode it came before: one that shows only once the learner
  // succeeds comes late in a trial.
  TaskPick next() override {
    try {
      return pick();
    } catch (const ScriptError& e) {
      throw ScriptError(with_note_on_first_line(e.message, " (before training episode " + std::to_string(episodes_) + ")"),
                        e.file, e.line, e.traceback);
    }
  }

 private:
  TaskPick pick() {
    lua_State* L = sandbox_.state();
    LuaStackGuard guard(L);
    const int base = lua_gettop(L);
    lua_rawgeti(L, LUA_REGISTRYINDEX, fn_.ref);
    lua_rawgeti(L, LUA_REGISTRYINDEX, view_ref_);
    lua_rawgeti(L, LUA_REGISTRYINDEX, rng_ref_);
    try {
      // Its rng draws during this call alone, whatever ends it.
      struct RngCall {
        lua_State* L;
        RngCall(lua_State* l, int64_t key) : L(l) { lua_rng_calls_begin(L, key); }
        ~RngCall() { lua_rng_calls_end(L); }
      } rng_call(L, rng_key_);
      sandbox_.call(2, LUA_MULTRET);
    } catch (const ScriptError& e) {
      throw ScriptError(where_ + ": " + e.message, e.file.empty() ? fn_.file : e.file, e.file.empty() ? fn_.line : e.line,
                        e.traceback);
    }
    // One result, as the stage's other functions give (found by a probe: `return task, seed`
    // trained on with the seed dropped without a word).
    refuse_more_results(L, base, where_, "one table of task parameters", ": a value after the first would not be read",
                        fn_);
    const ParamList given = read_result();
    TaskPoint task = space_.sample(fill_);  // what the result leaves out is drawn uniformly
    for (const auto& [key, value] : given) {
      // --set (or a batch run's params) fixes it for this run: the run's value stands, but a value
      // outside the whole space is the function's fault all the same (found with --set or not).
      const bool fixed = space_.is_fixed(key);
      const TaskSpace& space = fixed ? fixed_space_ : space_;
      const int i = space.index(key);
      std::string why;
      const std::optional<double> v = i < 0 ? std::nullopt : space.value_of(size_t(i), value, &why);
      if (i < 0) {
        // Named against the whole space, the axes the run fixes too (found by a probe: with every
        // axis fixed, a misspelt one read "(no parameters)", with no suggestion).
        std::vector<TaskDim> dims = space_.dims();
        for (const TaskDim& d : fixed_space_.dims()) dims.push_back(d);
        std::vector<std::string> names;
        for (const TaskDim& d : dims) names.push_back(d.name);
        throw ScriptError(where_ + " returned '" + key + "', which is not a parameter of the task space" +
                              suggestion(key, names) + " (" + TaskSpace(dims).describe() + ")", fn_.file, fn_.line, "");
      }
      if (!v) {
        // A choice in another case ("Spade") gets its nearest (found by a probe).
        const TaskDim& d = space.dims()[size_t(i)];
        const std::string near = d.kind == TaskDim::Kind::kChoice ? suggestion(value, d.choices) : "";
        throw ScriptError(where_ + " returned " + key + " = " + value + ", outside the task space" + near + ": " +
                              key + " takes " + why, fn_.file, fn_.line, "");
      }
      if (!fixed) task[size_t(i)] = *v;
    }
    return {task, {}, std::nullopt};
  }


 public:
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
      make_view(L, "roger.HistoryTask", view_index, &fixed_note_);
      lua_setfield(L, -2, "task");
      lua_pushboolean(L, o.success);
      lua_setfield(L, -2, "success");
      lua_pushnumber(L, o.reward);
      lua_setfield(L, -2, "reward");
      lua_pushnumber(L, o.sim_s);
      lua_setfield(L, -2, "time");
      make_view(L, "roger.HistoryEntry", view_index);
      lua_rawseti(L, -2, episodes_);
      lua_pop(L, 1);
    });
  }

  nlohmann::json state() const override {
    return {{"kind", kind()}, {"episodes", episodes_}, {"function", file_named_ + ":" + std::to_string(fn_.line)}};
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
        // A history entry's task given back as it is (`return history[#history].task`): its data
        // (found by a probe: its private key was refused as "the key a userdata").
        if (lua_push_view_data(L, lua_gettop(L))) lua_replace(L, -2);
        refuse_history_entry(L, lua_gettop(L));
        refuse_numeric_strings(L, lua_gettop(L));
        lua_read_params(L, -1, where_ + "'s result", given);
      });
    } catch (const ScriptError& e) {
      if (!e.file.empty()) throw;
      throw ScriptError(e.message, fn_.file, fn_.line, "");  // a bad value in the result: the function's line
    }
    return given;
  }
  // A history entry given back whole (`return history[#history]`) rather than its task (found by
  // a probe: "result.task must be a number, string or boolean, got a table").
  void refuse_history_entry(lua_State* L, int t) const {
    if (space_.index("task") >= 0 || fixed_space_.index("task") >= 0) return;  // an axis named task
    const bool task = lua_getfield(L, t, "task") == LUA_TTABLE || lua_type(L, -1) == LUA_TUSERDATA;
    const bool success = lua_getfield(L, t, "success") != LUA_TNIL;
    lua_pop(L, 2);
    if (task && success)
      throw ScriptError(where_ + " returned a history entry (its fields task, success, reward, time), not a task: "
                            "return the entry's task, as `return history[#history].task`",
                        fn_.file, fn_.line, "");
  }
  void refuse_numeric_strings(lua_State* L, int t) const {
    lua_pushnil(L);
    while (lua_next(L, t)) {
      const std::string key = lua_type(L, -2) == LUA_TSTRING ? lua_tostring(L, -2) : "";
      const TaskSpace& space = space_.is_fixed(key) ? fixed_space_ : space_;
      const int i = space.index(key);
      if (i >= 0 && lua_type(L, -1) == LUA_TSTRING && space.dims()[size_t(i)].kind != TaskDim::Kind::kChoice) {
        const TaskDim& d = space.dims()[size_t(i)];
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
  std::string file_named_;  // fn_.file as the results name it (make_lua_teacher)
  TaskSpace space_;
  TaskSpace fixed_space_;  // the axes the run fixes: a result naming them is checked against them
  Rng fill_;
  std::string fixed_note_;  // ends a task view's unknown-field message: the axes the run fixes
  int history_ref_ = LUA_NOREF, view_ref_ = LUA_NOREF, rng_ref_ = LUA_NOREF;
  int64_t rng_key_ = 0;  // while its function runs, its rng draws (lua_push_rng)
  int episodes_ = 0;
};

}  // namespace

std::unique_ptr<Teacher> make_lua_teacher(LuaSandbox& sandbox, const CurriculumStage& stage, const LuaCallback& fn,
                                          const TaskSpace& space, uint64_t seed, const std::string& file_named) {
  return std::make_unique<LuaTeacher>(sandbox, stage, fn, space, seed, file_named);
}

}  // namespace curriculum_detail
}  // namespace roger
