// curriculum_tasks.cpp: teachers in Lua (docs/curricula.md, Teachers): the task-space axes
// roger.int, roger.real and roger.choice, the teachers roger.teacher.*, and a stage's fields
// `tasks`, `teacher` and `test`, checked against the stage's scenario where they are written.
#include <algorithm>
#include <cmath>
#include <set>

#include "core/error.h"
#include "core/text.h"
#include "script/control/lua_control.h"
#include "script/curriculum/curriculum_internal.h"
#include "script/sandbox/lua_sandbox.h"
#include "script/scenario/scenario.h"

namespace roger {
namespace curriculum_detail {
namespace {

// Whether `text` reads as a number ("2", "1e0"): the text of a number written in quotes.
bool is_number_text(const std::string& text) {
  double value;
  return parse_number_text(text, value);
}

constexpr const char* kAxisType = "roger.TaskAxis";
constexpr const char* kTeacherType = "roger.Teacher";
constexpr const char* kTeacherTable = "roger.teacher.makers";  // in the registry: the roger.teacher.* functions

template <class T>
int destroy(lua_State* L) {
  static_cast<T*>(lua_touserdata(L, 1))->~T();
  return 0;
}

// Where the Lua caller of the running C function is ("", 0 from C++).
std::pair<std::string, int> caller_of(lua_State* L) {
  lua_Debug ar;
  if (lua_getstack(L, 1, &ar) && lua_getinfo(L, "Sl", &ar) && ar.currentline > 0)
    return {ar.source && ar.source[0] == '@' ? ar.source + 1 : ar.short_src, ar.currentline};
  return {"", 0};
}

void push_axis(lua_State* L, TaskDim d) {
  std::tie(d.file, d.line) = caller_of(L);
  new (lua_newuserdatauv(L, sizeof(TaskDim), 0)) TaskDim(std::move(d));
  luaL_setmetatable(L, kAxisType);
}

// A bound of roger.int / roger.real: a finite number, an integer for roger.int.
double bound(lua_State* L, int index, const char* call, bool integer) {
  if (lua_type(L, index) != LUA_TNUMBER)
    luaL_error(L, "%s(lo, hi): %s must be a number, got %s", call, index == 1 ? "lo" : "hi",
               lua_describe_value(L, index).c_str());
  const double v = lua_tonumber(L, index);
  if (!std::isfinite(v) || (integer && v != std::floor(v)))
    luaL_error(L, "%s(lo, hi): %s must be %s, got %s", call, index == 1 ? "lo" : "hi",
               integer ? "an integer" : "finite", format_number(v).c_str());
  // An int axis's values travel as doubles (tasks, records, teachers' fits): beyond 2^53 a double
  // no longer holds every integer, so math.maxinteger would be drawn as 2^63, a value out of range.
  // The test is on the integer itself where Lua holds one (found by a probe: 2^53 + 1 rounded to 2^53
  // as a double, and passed as 2^53).
  constexpr double kExactIntegers = 9007199254740992.0;  // 2^53
  constexpr lua_Integer kExactInteger = 9007199254740992;
  const bool beyond = lua_isinteger(L, index) ? (lua_tointeger(L, index) > kExactInteger ||
                                                 lua_tointeger(L, index) < -kExactInteger)
                                              : std::fabs(v) > kExactIntegers;
  if (integer && beyond) {
    const std::string given = lua_isinteger(L, index) ? std::to_string(lua_tointeger(L, index)) : format_number(v);
    luaL_error(L, "%s(lo, hi): %s must lie within -2^53..2^53 (-9007199254740992..9007199254740992), got %s", call,
               index == 1 ? "lo" : "hi", given.c_str());
  }
  return v;
}

int l_int(lua_State* L) {
  TaskDim d;
  d.kind = TaskDim::Kind::kInt;
  lua_check_arity(L, "roger.int", 2, "2 arguments (lo, hi)");
  d.lo = bound(L, 1, "roger.int", true), d.hi = bound(L, 2, "roger.int", true);
  // One value is refused as roger.real's is (found by a probe: roger.int(2, 2) was taken, and
  // ALP-GMM fitted mixtures over its one point).
  if (d.lo >= d.hi)
    luaL_error(L, "roger.int(%s, %s): the range is %s (lo must be below hi; a single value needs no axis: give the "
               "value itself, in params or in a teacher's step)", format_number(d.lo).c_str(),
               format_number(d.hi).c_str(), d.lo == d.hi ? "a single value" : "reversed");
  push_axis(L, std::move(d));
  return 1;
}

int l_real(lua_State* L) {
  TaskDim d;
  d.kind = TaskDim::Kind::kReal;
  lua_check_arity(L, "roger.real", 2, "2 arguments (lo, hi)");
  d.lo = bound(L, 1, "roger.real", false), d.hi = bound(L, 2, "roger.real", false);
  if (d.lo >= d.hi)
    luaL_error(L, "roger.real(%s, %s): the range is %s (lo must be below hi; a single value needs no axis: give the "
               "value itself, in params or in a teacher's step)",
               format_number(d.lo).c_str(), format_number(d.hi).c_str(), d.lo == d.hi ? "a single value" : "reversed");
  push_axis(L, std::move(d));
  return 1;
}

int l_choice(lua_State* L) {
  lua_check_arity(L, "roger.choice", 1, "1 argument (a list of values)");
  if (!lua_istable(L, 1))
    luaL_error(L, "roger.choice{...}: expects a list of values, got %s", lua_describe_value(L, 1).c_str());
  TaskDim d;
  d.kind = TaskDim::Kind::kChoice;
  const lua_Integer n = lua_Integer(lua_rawlen(L, 1));
  if (const std::string key = lua_key_beside_list(L, 1); !key.empty())
    luaL_error(L, "roger.choice{...}: expects a plain list of values, got the key %s", key.c_str());
  std::set<std::string> seen;
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, 1, i);
    const std::string v = lua_param_text(L, -1, "roger.choice{...}: value " + std::to_string(i));
    if (!seen.insert(v).second) luaL_error(L, "roger.choice{...}: the value '%s' is listed twice", v.c_str());
    if (lua_type(L, -1) == LUA_TSTRING) d.string_choices.push_back(d.choices.size());
    d.choices.push_back(v);
    lua_pop(L, 1);
  }
  if (d.choices.empty()) luaL_error(L, "roger.choice{...}: the list is empty; give at least two values");
  if (d.choices.size() == 1)
    luaL_error(L, "roger.choice{%s}: one value (a single value needs no axis: give the value itself, in params or in a "
               "teacher's step); give at least two",
               d.choices[0].c_str());
  push_axis(L, std::move(d));
  return 1;
}

int l_axis_tostring(lua_State* L) {
  lua_pushstring(L, static_cast<TaskDim*>(luaL_checkudata(L, 1, kAxisType))->text().c_str());
  return 1;
}

// ---- roger.teacher.*

void push_teacher(lua_State* L, TeacherSpec spec) {
  std::tie(spec.file, spec.line) = caller_of(L);
  new (lua_newuserdatauv(L, sizeof(TeacherSpec), 0)) TeacherSpec(std::move(spec));
  luaL_setmetatable(L, kTeacherType);
}

// The options table of roger.teacher.<kind>{...} (none: {}).
LuaFields options(lua_State* L, const TeacherSpec& spec, std::vector<std::string> known) {
  lua_check_arity(L, spec.name().c_str(), 1, "1 argument (a table of options)");
  if (lua_isnoneornil(L, 1)) {
    lua_settop(L, 1);  // with no argument at all, slot 1 must exist before it is replaced
    lua_newtable(L);
    lua_replace(L, 1);
  }
  return LuaFields(L, 1, spec.name(), std::move(known));
}

int whole(const LuaFields& f, const char* key, int fallback, int lo, int hi) {
  const int64_t v = f.integer(key, fallback);
  if (v < lo || v > hi)
    f.fail("field '" + std::string(key) + "' must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
           "], got " + std::to_string(v));
  return int(v);
}

double fraction(const LuaFields& f, const char* key, double fallback, double lo, double hi, bool open_lo = false) {
  const double v = f.number(key, fallback);
  if (v < lo || v > hi || (open_lo && v == lo))
    f.fail("field '" + std::string(key) + "' must be in " + (open_lo ? "(" : "[") + format_number(lo) + ", " +
           format_number(hi) + "], got " + format_number(v));
  return v;
}

int l_teacher_random(lua_State* L) {
  TeacherSpec spec;
  // LuaFields would say "unknown field 'x'; known fields: " with nothing after it.
  if (lua_istable(L, 1)) {
    lua_pushnil(L);
    if (lua_next(L, 1))
      luaL_error(L, "roger.teacher.random{}: takes no fields (every task alike), got the field %s",
                 lua_describe_value(L, -2).c_str());
  }
  options(L, spec, {});
  push_teacher(L, std::move(spec));
  return 1;
}

// One step of roger.teacher.sequence: its parameters (a value, or an axis inside the task space's)
// and its promote, demote and window. The last step promotes to nothing: its demote is not held
// below a default promote it never uses (found by a probe: demote = 0.95 on the last step was
// refused as not below 0.9).
TeacherSpec::Step read_step(lua_State* L, int t, const std::string& where, bool last) {
  TeacherSpec::Step step;
  if (!lua_istable(L, t))
    luaL_error(L, "%s must be a table {param = value, ..., promote = 0.9, window = 20}, got %s", where.c_str(),
               lua_describe_value(L, t).c_str());
  lua_pushnil(L);
  while (lua_next(L, t)) {
    if (lua_type(L, -2) != LUA_TSTRING)
      luaL_error(L, "%s: expects named fields (param = value), got %s", where.c_str(), lua_describe_value(L, -2).c_str());
    const std::string key = lua_tostring(L, -2);
    if (key == "promote" || key == "demote" || key == "window") {
      lua_pop(L, 1);
      continue;
    }
    TaskDim d;
    if (auto* axis = static_cast<TaskDim*>(luaL_testudata(L, -1, kAxisType))) {
      d = *axis;
    } else {
      d.kind = TaskDim::Kind::kChoice;  // a single value: an axis of one
      d.choices = {lua_param_text(L, -1, where + ": " + key)};
      if (lua_type(L, -1) == LUA_TSTRING) step.string_values.push_back(key);
    }
    d.name = key;
    step.restrict.push_back(std::move(d));
    lua_pop(L, 1);
  }
  std::vector<std::string> known = {"promote", "demote", "window"};
  for (const auto& d : step.restrict) known.push_back(d.name);
  LuaFields f(L, t, where, known);
  step.promote = fraction(f, "promote", 0.9, 0.0, 1.0, true);
  step.demote = f.has("demote") ? fraction(f, "demote", 0.0, 0.0, 1.0) : -1.0;
  if (step.demote >= step.promote && !(last && !f.has("promote")))
    f.fail("field 'demote' (" + format_number(step.demote) + ") must be below 'promote' (" +
           format_number(step.promote) + ")");
  step.window = whole(f, "window", 20, 1, 100000);
  return step;
}

int l_teacher_sequence(lua_State* L) {
  TeacherSpec spec;
  spec.kind = TeacherSpec::Kind::kSequence;
  lua_check_arity(L, "roger.teacher.sequence", 1, "1 argument (a list of steps)");
  if (!lua_istable(L, 1))
    luaL_error(L, "roger.teacher.sequence{...}: expects a list of steps {{param = value, promote = 0.9, window = 20}, "
               "...}, got %s", lua_describe_value(L, 1).c_str());
  const lua_Integer n = lua_Integer(lua_rawlen(L, 1));
  if (const std::string key = lua_key_beside_list(L, 1); !key.empty())
    luaL_error(L, "roger.teacher.sequence{...}: expects a plain list of steps, got the key %s", key.c_str());
  if (n == 0) luaL_error(L, "roger.teacher.sequence{...}: the list of steps is empty");
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, 1, i);
    const std::string where = "roger.teacher.sequence: step " + std::to_string(i);
    spec.steps.push_back(read_step(L, lua_gettop(L), where, i == n));
    // A threshold that can never act is a misreading of the rule, not a harmless extra.
    const bool demote = lua_getfield(L, -1, "demote") != LUA_TNIL, promote = lua_getfield(L, -2, "promote") != LUA_TNIL;
    if (i == 1 && demote)
      luaL_error(L, "%s: field 'demote' needs a step before it to go back to (the first step has none)", where.c_str());
    if (i == n && promote)
      luaL_error(L, "%s: field 'promote' needs a step after it to go on to (the last step has none)", where.c_str());
    lua_pop(L, 3);
  }
  push_teacher(L, std::move(spec));
  return 1;
}

// The table `lift` (at that stack index) names one parameter: refused, naming them all in order,
// when it names more (the table's own order is Lua's hash order).
void check_one_lifted(lua_State* L, LuaFields& f, int lift) {
  std::vector<std::string> named;
  lua_pushnil(L);
  while (lua_next(L, lift)) {
    named.push_back(lua_type(L, -2) == LUA_TSTRING ? lua_tostring(L, -2) : lua_describe_value(L, -2));
    lua_pop(L, 1);
  }
  std::sort(named.begin(), named.end());
  if (named.size() > 1)
    f.fail("field 'lift' must name one parameter {param = {level 1, level 2, ...}}, got " +
           std::to_string(named.size()) + ": " + join(named));
}

// lift.<spec.lift>'s levels (the list at `levels`), the most constrained first: a plain list of two
// or more different levels. A lift that cannot change the level is a slip (one level, or one listed
// twice): refused rather than trained as a stage that holds the parameter fixed.
void read_lift_levels(lua_State* L, LuaFields& f, int levels, TeacherSpec& spec) {
  const std::string name = "lift." + spec.lift;
  if (!lua_istable(L, levels) || lua_rawlen(L, levels) == 0) {
    // A table of named levels is not empty (found by a probe: {a = 32, b = 64} was "an empty list").
    const bool named = lua_istable(L, levels) && (lua_pushnil(L), lua_next(L, levels) != 0);
    if (named) lua_pop(L, 2);
    f.fail(name + " must be a list of levels, the most constrained first, got " +
           (!lua_istable(L, levels) ? lua_describe_value(L, levels)
            : named ? std::string("a table of named levels with no levels 1, 2, ... (write {32, 64}, not {a = 32})")
                    : std::string("a table with no levels 1, 2, ... (an empty list)")));
  }
  // Found by a probe: {32, 64, x = 1} dropped the x without a word.
  if (const std::string key = lua_key_beside_list(L, levels); !key.empty())
    f.fail(name + " must be a plain list of levels, the most constrained first, got the key " + key);
  const lua_Integer count = lua_Integer(lua_rawlen(L, levels));
  for (lua_Integer i = 1; i <= count; ++i) {
    lua_rawgeti(L, levels, i);
    if (lua_type(L, -1) == LUA_TSTRING) spec.string_levels.push_back(size_t(i - 1));
    spec.levels.push_back(lua_param_text(L, -1, "roger.teacher.lcas: " + name + "[" + std::to_string(i) + "]"));
    lua_pop(L, 1);
  }
  if (spec.levels.size() == 1)
    f.fail(name + " = {" + spec.levels[0] + "} has one level, so nothing is ever lifted: give two or "
           "more, the most constrained first (to hold " + spec.lift + " at " + spec.levels[0] +
           ", set it in the stage's params instead)");
  for (size_t i = 0; i < spec.levels.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (spec.levels[i] == spec.levels[j])
        f.fail(name + ": the level " + spec.levels[i] + " is listed twice (levels " + std::to_string(j + 1) +
               " and " + std::to_string(i + 1) + ")");
}

int l_teacher_lcas(lua_State* L) {
  TeacherSpec spec;
  spec.kind = TeacherSpec::Kind::kLcas;
  LuaFields f = options(L, spec, {"lift", "window", "slope", "floor"});
  if (f.push("lift") != LUA_TTABLE) f.wrong_type("lift", "a table {param = {level 1, level 2, ...}}");
  const int lift = lua_gettop(L);
  check_one_lifted(L, f, lift);
  lua_pushnil(L);
  while (lua_next(L, lift)) {
    if (lua_type(L, -2) != LUA_TSTRING || !spec.lift.empty())
      f.fail("field 'lift' must name one parameter {param = {level 1, level 2, ...}}");
    spec.lift = lua_tostring(L, -2);
    read_lift_levels(L, f, lua_gettop(L), spec);
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  if (spec.lift.empty()) f.fail("field 'lift' must name one parameter {param = {level 1, level 2, ...}}");
  spec.window = whole(f, "window", 50, 1, 100000);
  spec.slope = fraction(f, "slope", 0.05, 0.0, 1.0, true);
  spec.floor = fraction(f, "floor", 0.0, 0.0, 1.0);
  push_teacher(L, std::move(spec));
  return 1;
}

int l_teacher_alp_gmm(lua_State* L) {
  TeacherSpec spec;
  spec.kind = TeacherSpec::Kind::kAlpGmm;
  LuaFields f = options(L, spec, {"fit_every", "k_max", "random_share", "history"});
  spec.k_max = whole(f, "k_max", 6, 2, 20);
  spec.fit_every = whole(f, "fit_every", 50, 2, 100000);
  spec.random_share = fraction(f, "random_share", 0.2, 0.0, 1.0);
  // At least k_max episodes, one per component: the message says where its lower end comes from
  // (found by a probe: "[20, 100000]" read as a fixed range, with k_max = 20).
  const int64_t history = f.integer("history", 250);
  if (history < spec.k_max || history > 100000)
    f.fail("field 'history' must be an integer in [" + std::to_string(spec.k_max) + ", 100000] (at least k_max = " +
           std::to_string(spec.k_max) + ": one episode per component), got " + std::to_string(history));
  spec.history = int(history);
  push_teacher(L, std::move(spec));
  return 1;
}

int l_teacher_plr(lua_State* L) {
  TeacherSpec spec;
  spec.kind = TeacherSpec::Kind::kPlr;
  LuaFields f = options(L, spec, {"replay", "temperature", "staleness", "score", "buffer"});
  spec.replay = fraction(f, "replay", 0.5, 0.0, 1.0);
  spec.temperature = fraction(f, "temperature", 0.1, 0.0, 10.0, true);
  spec.staleness = fraction(f, "staleness", 0.1, 0.0, 1.0);
  const std::string score = f.string("score", "td");
  if (score != "td" && score != "success")
    f.fail("field 'score' must be \"td\" (the episode's mean |TD error|) or \"success\" (1 - success), got '" + score + "'");
  spec.score_td = score == "td";
  spec.buffer = whole(f, "buffer", 500, 1, 1000000);
  push_teacher(L, std::move(spec));
  return 1;
}

int l_teacher_tostring(lua_State* L) {
  lua_pushstring(L, static_cast<TeacherSpec*>(luaL_checkudata(L, 1, kTeacherType))->name().c_str());
  return 1;
}

// ---- the stage's fields

// "stage 'T': tasks.obstacles = roger.int(0, 99)", for messages.
std::string axis_where(const CurriculumStage& st, const TaskDim& d) {
  return st.where() + ": tasks." + d.name + " = " + d.text();
}

[[noreturn]] void fail_at(const std::string& message, const std::string& file, int line) {
  throw ScriptError(message, file, line, "");
}

// Every axis, and the lifted parameter of an LCAS teacher, against the stage's scenario: each
// must be a parameter of it, and each end of a range and each choice a value it takes.
void check_against_scenario(const CurriculumStage& st) {
  Scenario s = Scenario::load(st.scenario);
  std::map<std::string, ScenarioParam> params;
  for (auto& p : s.params()) params[p.name] = p;
  auto check_value = [&](const std::string& name, const std::string& value, const std::string& where,
                         const std::string& file, int line) {
    try {
      s.set_param(name, value);
    } catch (const Error& e) {
      fail_at(where + ": " + e.what(), file, line);
    }
  };
  for (const TaskDim& d : st.tasks.dims()) {
    const std::string where = axis_where(st, d);
    const auto it = params.find(d.name);
    if (it == params.end()) {
      check_value(d.name, "", where, d.file, d.line);  // the scenario's message names the known ones
      continue;
    }
    if (it->second.type == ParamType::kInteger && d.kind == TaskDim::Kind::kReal)
      fail_at(where + ": '" + d.name + "' is an integer parameter of scenario '" + s.name() + "': use roger.int",
              d.file, d.line);
    if ((it->second.type == ParamType::kString || it->second.type == ParamType::kBoolean) && d.kind != TaskDim::Kind::kChoice)
      fail_at(where + ": '" + d.name + "' is a " + param_type_name(it->second.type) + " parameter of scenario '" +
                  s.name() + "': use roger.choice{...}", d.file, d.line);
    // A range over a parameter of a few values would draw the others (found by a probe: roger.int(1, 5)
    // over choices 1, 3, 5 passed its ends, and training failed at a 2 with no file or stage).
    if (!it->second.choices.empty() && d.kind != TaskDim::Kind::kChoice)
      fail_at(where + ": '" + d.name + "' of scenario '" + s.name() + "' takes only " + join(it->second.choices, ", ") +
                  ": vary it with roger.choice{" + join(it->second.choices, ", ") + "} (or some of them)",
              d.file, d.line);
    // A boolean's choices are true and false, as its params are (found by a probe: roger.choice{0, 1}
    // and {"yes", "no"} passed as --set's text, and a teacher returning false was outside the space).
    if (it->second.type == ParamType::kBoolean && d.kind == TaskDim::Kind::kChoice)
      for (size_t i = 0; i < d.choices.size(); ++i) {
        const bool quoted = std::find(d.string_choices.begin(), d.string_choices.end(), i) != d.string_choices.end();
        if (quoted || (d.choices[i] != "true" && d.choices[i] != "false"))
          fail_at(st.where() + ": tasks." + d.name + ": roger.choice's value " + std::to_string(i + 1) + " is " +
                      (quoted ? "the string \"" + d.choices[i] + "\"" : d.choices[i]) + ": parameter '" + d.name +
                      "' of scenario '" + s.name() + "' is a boolean: write roger.choice{true, false}",
                  d.file, d.line);
      }
    // A list parameter's choices are sets of items: the same items in another order build the same
    // worlds (found by a probe: "left_eye,right_eye" and "right_eye,left_eye" were two tasks).
    if (it->second.list && d.kind == TaskDim::Kind::kChoice) {
      std::vector<std::vector<std::string>> sets;
      for (size_t i = 0; i < d.choices.size(); ++i) {
        std::vector<std::string> items = list_param_items(d.choices[i]);
        items.erase(std::remove(items.begin(), items.end(), std::string()), items.end());
        std::sort(items.begin(), items.end());
        const auto same = std::find(sets.begin(), sets.end(), items);
        if (same != sets.end())
          fail_at(st.where() + ": tasks." + d.name + ": roger.choice's values " +
                      std::to_string(same - sets.begin() + 1) + " and " + std::to_string(i + 1) + " (\"" +
                      d.choices[size_t(same - sets.begin())] + "\" and \"" + d.choices[i] + "\") list the same items of '" +
                      d.name + "', which build the same worlds: give each set once",
                  d.file, d.line);
        sets.push_back(std::move(items));
      }
    }
    // A number parameter's choice written as a string ("1") is refused, as a teacher's step's and an
    // LCAS level's are (found by a probe: {"1", "01", "1e0"} were three slices of the one world).
    const bool number = it->second.type == ParamType::kInteger || it->second.type == ParamType::kNumber;
    if (d.kind == TaskDim::Kind::kChoice && number)
      for (size_t i : d.string_choices)  // not said through the axis's text, which writes every value bare
        fail_at(st.where() + ": tasks." + d.name + ": roger.choice's value " + std::to_string(i + 1) + " is the string \"" +
                    d.choices[i] + "\": parameter '" + d.name + "' of scenario '" + s.name() + "' takes a number" +
                    (is_number_text(d.choices[i]) ? ": write " + d.choices[i] + " without quotes" : ""),
                d.file, d.line);
    if (d.kind == TaskDim::Kind::kChoice)
      for (const auto& c : d.choices) check_value(d.name, c, where, d.file, d.line);
    else
      for (double v : {d.lo, d.hi}) check_value(d.name, format_number(v), where, d.file, d.line);
  }
  // A number parameter's level written as a string ("32") is refused, as a teacher function's is:
  // the level is a value, not the text of one.
  if (st.teacher && st.teacher->kind == TeacherSpec::Kind::kLcas && params.count(st.teacher->lift) &&
      (params[st.teacher->lift].type == ParamType::kInteger || params[st.teacher->lift].type == ParamType::kNumber))
    for (size_t i : st.teacher->string_levels)
      fail_at(st.where() + ": " + st.teacher->name() + ": lift." + st.teacher->lift + "[" + std::to_string(i + 1) +
                  "] is the string \"" + st.teacher->levels[i] + "\": parameter '" + st.teacher->lift +
                  "' of scenario '" + s.name() + "' takes a number" +
                  (is_number_text(st.teacher->levels[i]) ? ": write " + st.teacher->levels[i] + " without quotes" : ""),
              st.teacher->file, st.teacher->line);
  if (st.teacher && st.teacher->kind == TeacherSpec::Kind::kLcas && st.tasks.index(st.teacher->lift) < 0)
    for (const auto& level : st.teacher->levels)
      check_value(st.teacher->lift, level, st.where() + ": " + st.teacher->name() + ": lift." + st.teacher->lift,
                  st.teacher->file, st.teacher->line);
}

// A parameter given a fixed value by the stage or a context may not also vary. `advice` ends a
// context's refusal: a task axis can be fixed for a run with --set, an LCAS lift cannot (found by
// a probe: the lift's refusal advised the --set that is refused in turn).
void check_no_fixed(const CurriculumStage& st, const std::string& name, const std::string& what,
                    const std::string& file, int line,
                    const std::string& advice = "a task parameter is the teacher's (use --set to fix it for a run)") {
  auto set_by = [&](const std::vector<std::pair<std::string, std::string>>& params) {
    return std::any_of(params.begin(), params.end(), [&](const auto& p) { return p.first == name; });
  };
  if (set_by(st.params))
    fail_at(st.where() + ": " + what + " varies '" + name + "', which the stage's params fix; remove one of them",
            file, line);
  // A context's mistake at the context's line, where roger.stage's errors of a context are placed
  // (found by a probe: it was said at the teacher's line).
  for (const auto& c : st.contexts)
    if (set_by(c.params)) fail_at(st.where(c.name) + ": the context's params fix '" + name + "', which " + what +
                                      " varies; " + advice, "", 0);
}

void read_tasks(lua_State* L, const LuaFields& f, CurriculumStage& st) {
  if (f.push("tasks") == LUA_TNIL) {
    lua_pop(L, 1);
    return;
  }
  const int t = lua_gettop(L);
  if (!lua_istable(L, t)) f.wrong_type("tasks", "a table {param = roger.int(lo, hi) | roger.real(lo, hi) | roger.choice{...}}");
  std::vector<TaskDim> dims;
  lua_pushnil(L);
  while (lua_next(L, t)) {
    if (lua_type(L, -2) != LUA_TSTRING)
      f.fail("field 'tasks' must map scenario parameters to spaces {obstacles = roger.int(0, 6)}, got the key " +
             lua_describe_value(L, -2));
    const std::string key = lua_tostring(L, -2);
    auto* axis = static_cast<TaskDim*>(luaL_testudata(L, -1, kAxisType));
    if (!axis)
      f.fail("tasks." + key + " must be roger.int(lo, hi), roger.real(lo, hi) or roger.choice{...}, got " +
             lua_describe_value(L, -1) + " (a fixed value belongs in params)");
    dims.push_back(*axis);
    dims.back().name = key;
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  if (dims.empty()) f.fail("field 'tasks' is empty: give at least one parameter {obstacles = roger.int(0, 6)}");
  st.tasks = TaskSpace(std::move(dims));
}

// The name of roger.teacher.<kind> when the value at `index` is that function itself, else "".
std::string builtin_teacher_name(lua_State* L, int index) {
  index = lua_absindex(L, index);
  std::string name;
  if (lua_getfield(L, LUA_REGISTRYINDEX, kTeacherTable) == LUA_TTABLE) {
    lua_pushnil(L);
    while (lua_next(L, -2)) {
      if (name.empty() && lua_type(L, -2) == LUA_TSTRING && lua_rawequal(L, -1, index))
        name = std::string("roger.teacher.") + lua_tostring(L, -2);
      lua_pop(L, 1);
    }
  }
  lua_pop(L, 1);
  return name;
}

// What is wrong with `value`, written as a Lua string, for the parameter `name` of `space`: "" when
// the axis takes strings (or there is none). A number written as a string ("1") is refused, as a
// teacher function's return and an LCAS level are: the value is a number, not the text of one
// (found by a probe: a sequence's step and a test list took obstacles = "1" as 1).
std::string string_for_number(const TaskSpace& space, const std::string& name, const std::string& value) {
  const int i = space.index(name);
  if (i < 0 || space.dims()[size_t(i)].kind == TaskDim::Kind::kChoice) return "";
  return name + " = \"" + value + "\" is a string, but " + name + " takes a number (" + space.dims()[size_t(i)].text() +
         "): write " + value + " without quotes";
}

void read_teacher(lua_State* L, const LuaFields& f, CurriculumStage& st, LuaCallback& teacher_fn) {
  const int type = f.push("teacher");
  if (type == LUA_TFUNCTION && lua_iscfunction(L, -1)) {
    // A teacher function is written in Lua; a built-in one is the maker, its braces forgotten.
    const std::string name = builtin_teacher_name(L, -1);
    if (!name.empty())
      f.fail("field 'teacher' is the function " + name + " itself, not a teacher: did you mean " + name +
             (name == "roger.teacher.random" ? "{}" : "{...}") + "?");
    f.fail("field 'teacher' must be a teacher (roger.teacher.random{}, .sequence{...}, .lcas{...}, .alp_gmm{...}, "
           ".plr{...}) or a Lua function(history, rng), got a built-in function");
  }
  if (type == LUA_TFUNCTION) {
    teacher_fn = LuaCallback::keep(L);
    st.teacher_lua = true;
    if (st.tasks.empty()) f.fail("field 'teacher': a teacher function needs a task space to choose from: give 'tasks'");
    return;
  }
  if (type != LUA_TNIL) {
    auto* spec = static_cast<TeacherSpec*>(luaL_testudata(L, -1, kTeacherType));
    // A task axis given as the teacher read "got a userdata" (found by a probe).
    if (const auto* axis = static_cast<TaskDim*>(luaL_testudata(L, -1, kAxisType)))
      f.fail("field 'teacher' is the task axis " + axis->text() + ", not a teacher: an axis goes in 'tasks' "
             "(tasks = {" + (axis->name.empty() ? std::string("param") : axis->name) + " = " + axis->text() +
             "}), and the teacher draws from them (roger.teacher.random{}, .sequence{...}, ...)");
    if (!spec)
      f.fail("field 'teacher' must be a teacher (roger.teacher.random{}, .sequence{...}, .lcas{...}, "
             ".alp_gmm{...}, .plr{...}) or a function(history, rng), got " + lua_describe_value(L, -1));
    st.teacher = *spec;
  } else if (!st.tasks.empty()) {
    st.teacher = TeacherSpec{};  // domain randomization
  }
  lua_pop(L, 1);
  if (!st.teacher) return;
  const TeacherSpec& spec = *st.teacher;
  if (spec.kind != TeacherSpec::Kind::kLcas && st.tasks.empty())
    f.fail("field 'teacher': " + spec.name() + " needs a task space: give 'tasks' (only lcas may lift a parameter "
           "without one)");
  for (size_t i = 0; i < spec.steps.size(); ++i)
    for (const std::string& name : spec.steps[i].string_values) {
      const auto d = std::find_if(spec.steps[i].restrict.begin(), spec.steps[i].restrict.end(),
                                  [&](const TaskDim& r) { return r.name == name; });
      const std::string why = string_for_number(st.tasks, name, d->choices.front());
      if (!why.empty())
        fail_at(st.where() + ": " + spec.name() + ": step " + std::to_string(i + 1) + ": " + why, spec.file, spec.line);
    }
  try {
    make_teacher(spec, st.tasks, 0);  // the steps and levels against the space
  } catch (const Error& e) {
    fail_at(st.where() + ": " + e.what(), spec.file, spec.line);
  }
  if (spec.kind == TeacherSpec::Kind::kLcas && st.tasks.index(spec.lift) < 0)
    check_no_fixed(st, spec.lift, spec.name() + " (" + spec.file + ":" + std::to_string(spec.line) + ")", spec.file,
                   spec.line,
                   "the parameter lifted is the teacher's at every level, in every context, and --set cannot fix it "
                   "either: remove it from the context's params, or give the context a stage without the lift");
}

void read_test(lua_State* L, const LuaFields& f, CurriculumStage& st, bool episodes_given, bool final_given) {
  if (f.push("test") == LUA_TNIL) {
    lua_pop(L, 1);
    if (!st.teaches()) return;
    st.test.tasks = st.checkpoints.episodes;
    st.test.seed = st.checkpoints.seeds;
    return;
  }
  if (!st.teaches()) f.fail("field 'test' needs a task space or a teacher: give 'tasks' (or 'teacher')");
  if (!lua_istable(L, -1)) f.wrong_type("test", "a table {tasks = N, seed = S} or {list = {{param = value, ...}, ...}}");
  LuaFields t(L, lua_gettop(L), st.where() + ": test", {"tasks", "seed", "list"});
  if (episodes_given || final_given)
    t.fail(std::string("checkpoints.") + (episodes_given ? "episodes" : "final") +
           " does not apply with a test set: every checkpoint and the final evaluation run its tasks");
  st.test.given = true;
  // Refused below 0 as checkpoints.seeds is (found by a probe: -1 became 18446744073709551615).
  const int64_t seed = t.integer("seed", int64_t(st.checkpoints.seeds));
  if (seed < 0) t.fail("field 'seed' must be a non-negative integer, got " + std::to_string(seed));
  st.test.seed = uint64_t(seed);
  if (t.push("list") != LUA_TNIL) {
    if (t.has("tasks")) t.fail("give either 'tasks' (a number drawn from the space) or 'list', not both");
    const int list = lua_gettop(L);
    if (!lua_istable(L, list) || lua_rawlen(L, list) == 0) t.wrong_type("list", "a non-empty list of tasks {{param = value, ...}, ...}");
    // Found by a probe: {{...}, [3] = {...}} and {{...}, x = {...}} tested on the first task alone.
    if (const std::string key = lua_key_beside_list(L, list); !key.empty())
      t.fail("field 'list' must be a list of tasks {{param = value, ...}, ...}, got the key " + key);
    for (lua_Integer i = 1; i <= lua_Integer(lua_rawlen(L, list)); ++i) {
      lua_rawgeti(L, list, i);
      const std::string where = st.where() + ": test: list[" + std::to_string(i) + "]";  // "test: " finds its line
      ParamList task;
      lua_read_params(L, lua_gettop(L), where, task);
      for (const auto& [name, value] : task) {
        lua_getfield(L, -1, name.c_str());
        const bool written_as_string = lua_type(L, -1) == LUA_TSTRING;
        lua_pop(L, 1);
        const std::string wrong = written_as_string ? string_for_number(st.tasks, name, value) : "";
        if (!wrong.empty()) t.fail("list[" + std::to_string(i) + "]: " + wrong);
      }
      std::string why;
      if (!st.tasks.task_of(task, &why)) t.fail("list[" + std::to_string(i) + "]: " + why);
      st.test.list.push_back(std::move(task));
      lua_pop(L, 1);
    }
    st.test.tasks = int(st.test.list.size());
  } else {
    const int64_t n = t.integer("tasks", 200);
    if (n < 1 || n > 100000) t.fail("field 'tasks' must be an integer in [1, 100000], got " + std::to_string(n));
    st.test.tasks = int(n);
  }
  lua_pop(L, 2);
}

// roger.int, .real and .choice; roger.teacher's teachers (teaching_names lists them for messages).
const luaL_Reg kAxes[] = {{"int", l_int}, {"real", l_real}, {"choice", l_choice}, {nullptr, nullptr}};
const luaL_Reg kTeachers[] = {{"random", l_teacher_random}, {"sequence", l_teacher_sequence},
                              {"lcas", l_teacher_lcas},     {"alp_gmm", l_teacher_alp_gmm},
                              {"plr", l_teacher_plr},       {nullptr, nullptr}};

}  // namespace

void install_teaching_api(lua_State* L) {
  const luaL_Reg axis_entries[] = {{"__tostring", l_axis_tostring}, {"__gc", destroy<TaskDim>}, {nullptr, nullptr}};
  const luaL_Reg teacher_entries[] = {{"__tostring", l_teacher_tostring}, {"__gc", destroy<TeacherSpec>},
                                      {nullptr, nullptr}};
  for (const auto& [type, entries] : {std::make_pair(kAxisType, axis_entries), std::make_pair(kTeacherType, teacher_entries)}) {
    luaL_newmetatable(L, type);
    luaL_setfuncs(L, entries, 0);
    lua_pushboolean(L, 0);
    lua_setfield(L, -2, "__metatable");
    lua_pop(L, 1);
  }
  lua_getglobal(L, "roger");
  luaL_setfuncs(L, kAxes, 0);
  lua_newtable(L);
  luaL_setfuncs(L, kTeachers, 0);
  lua_pushvalue(L, -1);
  lua_setfield(L, LUA_REGISTRYINDEX, kTeacherTable);  // kept apart: a script may replace roger.teacher
  lua_setfield(L, -2, "teacher");
  lua_pop(L, 1);
}

void parse_teaching(lua_State* L, const LuaFields& f, CurriculumStage& st, LuaCallback& teacher_fn,
                    bool episodes_given, bool final_given) {
  read_tasks(L, f, st);
  for (const TaskDim& d : st.tasks.dims()) check_no_fixed(st, d.name, "tasks." + d.name + " = " + d.text(), d.file, d.line);
  read_teacher(L, f, st, teacher_fn);
  read_test(L, f, st, episodes_given, final_given);
  if (st.teaches()) check_against_scenario(st);
}

}  // namespace curriculum_detail

std::vector<std::string> teaching_names(bool teachers) {
  std::vector<std::string> out;
  for (const luaL_Reg* r = teachers ? curriculum_detail::kTeachers : curriculum_detail::kAxes; r->name; ++r)
    out.push_back(r->name);
  return out;
}

void CurriculumStage::check_played_in(const std::string& scenario_name, const TaskSpace& space) const {
  CurriculumStage st = *this;
  st.scenario = scenario_name;
  st.tasks = space;
  curriculum_detail::check_against_scenario(st);
}

void CurriculumStage::check_fixed(const std::vector<std::string>& fixed, const std::string& fixed_by) const {
  if (!teacher) return;
  const TeacherSpec& spec = *teacher;
  const std::string who = "its teacher (" + spec.name() + ")";
  if (spec.kind == TeacherSpec::Kind::kLcas && std::find(fixed.begin(), fixed.end(), spec.lift) != fixed.end())
    throw ScriptError(where() + ": '" + spec.lift + "' is fixed by " + fixed_by + ", and it is the parameter " +
                          who + " lifts: lifting it is all that teacher does; leave it to the teacher, or use a "
                          "stage with another teacher",
                      spec.file, spec.line, "");
  if (spec.kind == TeacherSpec::Kind::kAlpGmm && !tasks.empty() && tasks.without(fixed).empty()) {
    std::vector<std::string> axes;
    for (const auto& name : fixed)
      if (tasks.index(name) >= 0) axes.push_back(name);
    throw ScriptError(where() + ": every parameter of its task space (" + join(axes) + ") is fixed by " +
                          fixed_by + ", leaving " + who + " nothing to choose; leave one to the teacher, or fix fewer",
                      spec.file, spec.line, "");
  }
}

std::string CurriculumStage::teacher_window_warning() const {
  if (!teacher) return "";
  const TeacherSpec& spec = *teacher;
  const std::string at = spec.file.empty() ? "" : spec.file + ":" + std::to_string(spec.line) + ": ";
  const std::string budget = "the budget's " + std::to_string(budget_episodes) + " episodes";
  // A lift or move decided on the last episode's outcome sets no episode: a window that fills only
  // then is as good as none.
  // A lifted parameter that is an axis of the task space is drawn over the whole axis by the test
  // set; one outside it is held at its last level there (found by a probe: the warning said the
  // latter of the former).
  const bool drawn_by_test = spec.kind == TeacherSpec::Kind::kLcas && tasks.index(spec.lift) >= 0;
  if (spec.kind == TeacherSpec::Kind::kLcas && 2 * int64_t(spec.window) >= budget_episodes)
    return at + where() + ": " + spec.name() + ": window = " + std::to_string(spec.window) + " needs " +
           std::to_string(2 * int64_t(spec.window)) + " episodes at a level (two windows) before it can lift " +
           spec.lift + ", not fewer than " + budget + ": it will never lift it, and " +
           (drawn_by_test ? "the test set draws it over its whole axis, where no episode trained past the first level"
                          : "the test set runs at its last level");
  // Each lift needs two windows at its level: the last level is reached after (levels - 1) of them
  // at the earliest (found by a probe: 7 levels of window 10 in 60 episodes reached level 2, and the
  // test set ran at level 7, which no episode had trained at).
  const int64_t lifts = int64_t(spec.levels.size()) - 1;
  if (spec.kind == TeacherSpec::Kind::kLcas && lifts * 2 * int64_t(spec.window) >= budget_episodes)
    return at + where() + ": " + spec.name() + ": its " + std::to_string(lifts + 1) + " levels of " + spec.lift +
           " need " + std::to_string(lifts * 2 * int64_t(spec.window)) + " episodes (two windows of " +
           std::to_string(spec.window) + " per lift) before the last, not fewer than " + budget + ": no episode " +
           "will train at " + spec.lift + " = " + spec.levels.back() +
           (drawn_by_test ? ", a level the test set draws tasks at" : ", the level the test set runs at");
  // The first fit follows episode fit_every; one after the last episode draws no task (found by a
  // probe: fit_every = 100 in 40 episodes trained as a uniform teacher without a word).
  if (spec.kind == TeacherSpec::Kind::kAlpGmm && spec.fit_every >= budget_episodes)
    return at + where() + ": " + spec.name() + ": fit_every = " + std::to_string(spec.fit_every) + " is not below " +
           budget + ": it will never fit its mixture before the last episode, and draws every task uniformly, as "
           "roger.teacher.random does";
  // A replay every episode once a level is seen: the first level, for ever (found by a probe).
  if (spec.kind == TeacherSpec::Kind::kPlr && spec.replay >= 1.0 && budget_episodes > 1)
    return at + where() + ": " + spec.name() + ": replay = 1 replays a seen level at every episode: after the first "
           "it never draws a new one, and trains on that one task for the whole budget";
  // Teachers that are random{} under another name (found by a probe: neither was said).
  if (spec.kind == TeacherSpec::Kind::kAlpGmm && spec.random_share >= 1.0)
    return at + where() + ": " + spec.name() + ": random_share = 1 draws every task uniformly: it never uses its "
           "mixture, as roger.teacher.random does";
  if (spec.kind == TeacherSpec::Kind::kPlr && spec.replay <= 0.0)
    return at + where() + ": " + spec.name() + ": replay = 0 never replays a level: it draws every task afresh, as "
           "roger.teacher.random does";
  if (spec.kind != TeacherSpec::Kind::kSequence) return "";
  int64_t before = 0;  // the fewest episodes before step i + 2 can begin: the windows it waits for
  for (size_t i = 0; i + 1 < spec.steps.size(); ++i) {  // the last step never moves on
    if (spec.steps[i].window >= budget_episodes)
      return at + where() + ": " + spec.name() + ": step " + std::to_string(i + 1) + "'s window = " +
             std::to_string(spec.steps[i].window) + " is not below " + budget + ": the sequence will never move "
             "past it";
    // Found by a probe: three steps of window 10 in 30 episodes, each alone within the budget.
    before += spec.steps[i].window;
    if (before >= budget_episodes)
      return at + where() + ": " + spec.name() + ": steps 1 to " + std::to_string(i + 1) + " need " +
             std::to_string(before) + " episodes (a full window each) before step " + std::to_string(i + 2) +
             ", not fewer than " + budget + ": no episode will train at step " + std::to_string(i + 2);
  }
  return "";
}

std::vector<TaskPoint> CurriculumStage::test_tasks(const TaskSpace& space, int count) const {
  if (!test.given || test.list.empty()) return draw_test_tasks(space, count, test.seed);
  std::vector<TaskPoint> out;
  for (size_t i = 0; i < test.list.size(); ++i) {
    ParamList kept;  // without the parameters the trial fixed (--set)
    for (const auto& p : test.list[i])
      if (space.index(p.first) >= 0) kept.push_back(p);
    std::string why;
    const auto t = space.task_of(kept, &why);
    if (!t) throw Error(where() + ": test.list[" + std::to_string(i + 1) + "]: " + why);
    out.push_back(*t);
  }
  return out;
}

}  // namespace roger
