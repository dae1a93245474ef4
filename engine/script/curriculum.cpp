#include "script/curriculum.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include <lua.hpp>

#include "core/error.h"
#include "script/lua_control.h"
#include "script/scenario.h"

namespace roger {
namespace fs = std::filesystem;

namespace {

char book_key;  // registry key of the loader's book (a light userdata)

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  if (in) text << in.rdbuf();
  return text.str();
}

// The stand-in roger.learned(name): behaves as the skill bound to it at train time; until then
// it has no reference (NOREF), so a stage trained without binding it simply never sees it act.
class LearnedRef final : public StandIn {
 public:
  explicit LearnedRef(std::string name) : StandIn(std::move(name)) {}
  const char* kind() const override { return "learned"; }
};

// A Lua function a stage keeps (absorbing or reward), with where it was defined.
struct LuaCallback {
  int ref = LUA_NOREF;
  std::string file;
  int line = 0;
};

// What the script's roger.stage / roger.learned calls have made so far.
struct Book {
  std::vector<CurriculumStage> stages;                   // parsed by roger.stage, in call order
  std::vector<LuaCallback> absorbing_fns, reward_fns;    // aligned with stages
  std::map<const void*, size_t> tables;                  // stage table -> index in stages
  std::map<std::string, std::shared_ptr<LearnedRef>> learned;
};

Book& book_of(lua_State* L) {
  lua_rawgetp(L, LUA_REGISTRYINDEX, &book_key);
  auto* b = static_cast<Book*>(lua_touserdata(L, -1));
  lua_pop(L, 1);
  if (!b) luaL_error(L, "the curriculum API is not installed in this Lua state");
  return *b;
}

// Where the caller of the running C function is, "" when it is C++.
std::pair<std::string, int> caller(lua_State* L) {
  lua_Debug ar;
  if (lua_getstack(L, 1, &ar) && lua_getinfo(L, "Sl", &ar) && ar.currentline > 0)
    return {ar.source && ar.source[0] == '@' ? ar.source + 1 : ar.short_src, ar.currentline};
  return {"", 0};
}

// Collects the learned stand-ins a controller reaches.
void find_learned(const Controller* c, std::set<const Controller*>& seen, std::vector<std::string>& out) {
  if (!seen.insert(c).second) return;
  if (dynamic_cast<const LearnedRef*>(c)) {
    if (std::find(out.begin(), out.end(), c->name()) == out.end()) out.push_back(c->name());
    return;  // a bound stand-in's insides belong to the earlier stage
  }
  for (const Controller* child : c->children()) find_learned(child, seen, out);
}

// A positive integer field.
int positive_int(const LuaFields& f, const char* key, int64_t fallback, int64_t lo, const std::string& what) {
  const int64_t v = f.integer(key, fallback);
  if (v < lo || v > 100000000)
    f.fail("field '" + std::string(key) + "' must be " + what + ", got " + std::to_string(v));
  return int(v);
}

// Reads the contexts of a stage (the value on top of the stack).
void parse_contexts(lua_State* L, CurriculumStage& st) {
  const int t = lua_gettop(L);
  const std::string where = st.where();
  if (!lua_istable(L, t))
    luaL_error(L, "%s: field 'contexts' must be a table: a list {{name = 'B1', actions = {...}}, ...} or a map "
               "{B1 = {...}, ...}, got %s", where.c_str(), lua_describe_value(L, t).c_str());
  // Each entry: its name and the stack index of its action list.
  std::vector<std::pair<std::string, int>> entries;
  if (lua_rawlen(L, t) > 0) {
    const lua_Integer n = lua_Integer(lua_rawlen(L, t));
    for (lua_Integer i = 1; i <= n; ++i) {
      lua_rawgeti(L, t, i);
      const int e = lua_gettop(L);
      const std::string ctx = where + ": context " + std::to_string(i);
      if (!lua_istable(L, e))
        luaL_error(L, "%s must be a table {name = ..., actions = {...}}, got %s", ctx.c_str(),
                   lua_describe_value(L, e).c_str());
      LuaFields f(L, e, ctx, {"name", "actions"});
      const std::string name = f.string("name");
      if (name.empty()) f.fail("field 'name' must not be empty");
      if (f.push("actions") == LUA_TNIL) f.fail("missing required field 'actions' (the list of controllers, Psi)");
      entries.push_back({name, lua_gettop(L)});
    }
  } else {
    std::vector<std::string> names;
    lua_pushnil(L);
    while (lua_next(L, t)) {
      lua_pop(L, 1);
      if (lua_type(L, -1) != LUA_TSTRING)
        luaL_error(L, "%s: contexts must be named (B1 = {...}) or a list of {name = ..., actions = ...}, got the key %s",
                   where.c_str(), lua_describe_value(L, -1).c_str());
      names.push_back(lua_tostring(L, -1));
    }
    std::sort(names.begin(), names.end());  // a map has no order: name order is reproducible
    for (const auto& name : names) {
      lua_getfield(L, t, name.c_str());
      entries.push_back({name, lua_gettop(L)});
    }
  }
  if (entries.empty()) luaL_error(L, "%s: field 'contexts' is empty: define at least one context", where.c_str());
  std::set<std::string> seen_names;
  for (const auto& [name, idx] : entries) {
    const std::string ctx = st.where(name);
    if (!seen_names.insert(name).second) luaL_error(L, "%s: a second context named '%s'", where.c_str(), name.c_str());
    if (!lua_istable(L, idx))
      luaL_error(L, "%s: the actions must be a list of controllers, got %s", ctx.c_str(),
                 lua_describe_value(L, idx).c_str());
    CurriculumContext c;
    c.name = name;
    const lua_Integer n = lua_Integer(lua_rawlen(L, idx));
    lua_pushnil(L);
    while (lua_next(L, idx)) {  // only 1..n: a named key is a slip
      lua_pop(L, 1);
      if (!lua_isinteger(L, -1) || lua_tointeger(L, -1) < 1 || lua_tointeger(L, -1) > n)
        luaL_error(L, "%s: the actions must be a plain list {a, b, ...}, got the key %s", ctx.c_str(),
                   lua_describe_value(L, -1).c_str());
    }
    if (n == 0) luaL_error(L, "%s: Psi is empty: a context needs at least one action", ctx.c_str());
    if (n > 12)
      luaL_error(L, "%s: Psi has %d actions; at most 12 are allowed (3^12 states)", ctx.c_str(), int(n));
    std::set<std::string> action_names;
    for (lua_Integer i = 1; i <= n; ++i) {
      lua_rawgeti(L, idx, i);
      ControllerPtr a = lua_check_controller(L, -1, ctx, "action " + std::to_string(i));
      lua_pop(L, 1);
      if (!action_names.insert(a->name()).second)
        luaL_error(L, "%s: two actions are named '%s'; the names of Psi must differ", ctx.c_str(), a->name().c_str());
      c.actions.push_back(std::move(a));
    }
    std::set<const Controller*> visited;
    for (const auto& a : c.actions) find_learned(a.get(), visited, c.learned);
    st.contexts.push_back(std::move(c));
  }
  lua_settop(L, t);
}

// Reads a stage table at `index` into `st`, raising Lua errors "stage 'X': ..." (at the caller's
// file:line when called from Lua). Functions given for absorbing/reward are kept in the registry.
void parse_stage(lua_State* L, int index, CurriculumStage& st, LuaCallback& absorb_fn, LuaCallback& reward_fn) {
  index = lua_absindex(L, index);
  if (!lua_istable(L, index))
    luaL_error(L, "a stage must be a table {name = ..., time_limit = ..., absorbing = ..., contexts = ...}, got %s",
               lua_describe_value(L, index).c_str());
  lua_getfield(L, index, "name");
  st.name = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : "";
  lua_pop(L, 1);
  const std::string where = st.name.empty() ? std::string("a stage") : st.where();
  LuaFields f(L, index, where,
              {"absorbing", "budget", "checkpoints", "contexts", "description", "learner", "name", "params",
               "reward", "scenario", "skill", "time_limit"});
  if (st.name.empty()) f.fail("missing required field 'name' (a string such as \"SG\")");
  st.description = f.string("description", "");
  st.scenario = f.string("scenario", "unobstructed");
  resolve_scenario_path(st.scenario);  // lists the shipped scenarios when unknown
  if (f.push("params") != LUA_TNIL) {
    const int p = lua_gettop(L);
    if (!lua_istable(L, p)) f.wrong_type("params", "a table of scenario parameters {key = value}");
    lua_pushnil(L);
    while (lua_next(L, p)) {
      if (lua_type(L, -2) != LUA_TSTRING) f.fail("field 'params' must have string keys");
      const std::string key = lua_tostring(L, -2);
      std::string value;
      switch (lua_type(L, -1)) {
        case LUA_TNUMBER: value = lua_isinteger(L, -1) ? std::to_string(lua_tointeger(L, -1)) : format_number(lua_tonumber(L, -1)); break;
        case LUA_TBOOLEAN: value = lua_toboolean(L, -1) ? "true" : "false"; break;
        case LUA_TSTRING: value = lua_tostring(L, -1); break;
        default: f.fail("params." + key + " must be a number, string or boolean, got " + lua_describe_value(L, -1));
      }
      st.params.push_back({key, value});
      lua_pop(L, 1);
    }
    std::sort(st.params.begin(), st.params.end());
  }
  lua_pop(L, 1);
  if (!f.has("time_limit")) f.fail("missing required field 'time_limit' (simulated seconds, e.g. 5)");
  st.time_limit = f.number("time_limit");
  if (!(st.time_limit > 0.0 && st.time_limit <= 3600.0))
    f.fail("field 'time_limit' must be in (0, 3600] simulated seconds, got " + format_number(st.time_limit));
  st.rewards.time_limit = st.time_limit;
  // absorbing: a predicate (evaluated in C++ every tick) or a Lua function (at decision points).
  const int at = f.push("absorbing");
  if (at == LUA_TNIL) f.fail("missing required field 'absorbing' (a predicate such as roger.converged(c), or a function(state))");
  if (at == LUA_TFUNCTION) {
    lua_Debug ar;
    lua_pushvalue(L, -1);
    lua_getinfo(L, ">S", &ar);
    absorb_fn.file = ar.source && ar.source[0] == '@' ? ar.source + 1 : ar.short_src;
    absorb_fn.line = ar.linedefined;
    absorb_fn.ref = luaL_ref(L, LUA_REGISTRYINDEX);
    st.absorbing_lua = true;
  } else {
    st.absorbing = lua_check_predicate(L, -1, where, "field 'absorbing'");
    lua_pop(L, 1);
  }
  // reward: the paper's constants by default, a table of them, or a Lua function.
  const int rt = f.push("reward");
  if (rt == LUA_TFUNCTION) {
    lua_Debug ar;
    lua_pushvalue(L, -1);
    lua_getinfo(L, ">S", &ar);
    reward_fn.file = ar.source && ar.source[0] == '@' ? ar.source + 1 : ar.short_src;
    reward_fn.line = ar.linedefined;
    reward_fn.ref = luaL_ref(L, LUA_REGISTRYINDEX);
    st.reward_lua = true;
  } else if (rt == LUA_TTABLE) {
    LuaFields r(L, lua_gettop(L), where + ": reward", {"absorbing", "timeout", "step"});
    st.rewards.success_reward = r.number("absorbing", 100.0);
    st.rewards.timeout_reward = r.number("timeout", -100.0);
    st.rewards.step_reward = r.number("step", 0.0);
    lua_pop(L, 1);
  } else if (rt != LUA_TNIL) {
    f.wrong_type("reward", "a table {absorbing = 100, timeout = -100, step = 0} or a function(state, action, event)");
  } else {
    lua_pop(L, 1);
  }
  try {
    st.rewards.validate();
  } catch (const Error& e) {
    f.fail(e.what());
  }
  if (f.push("learner") != LUA_TNIL) {
    if (!lua_istable(L, -1)) f.wrong_type("learner", "a table {alpha = ..., discount = ..., epsilon_start = ..., epsilon_end = ...}");
    LuaFields q(L, lua_gettop(L), where + ": learner", {"alpha", "discount", "epsilon_start", "epsilon_end", "initial_q"});
    st.learner.alpha = q.number("alpha", st.learner.alpha);
    st.learner.discount = q.number("discount", st.learner.discount);
    st.learner.epsilon_start = q.number("epsilon_start", st.learner.epsilon_start);
    st.learner.epsilon_end = q.number("epsilon_end", st.learner.epsilon_end);
    st.learner.initial_q = q.number("initial_q", st.learner.initial_q);
    try {
      st.learner.validate(where + ": learner");
    } catch (const Error& e) {
      q.fail(e.what());
    }
  }
  lua_pop(L, 1);
  if (f.push("budget") == LUA_TNIL) f.fail("missing required field 'budget' ({episodes = N})");
  if (!lua_istable(L, -1)) f.wrong_type("budget", "a table {episodes = N}");
  {
    LuaFields b(L, lua_gettop(L), where + ": budget", {"episodes"});
    if (!b.has("episodes")) b.fail("missing required field 'episodes' (training episodes)");
    st.budget_episodes = positive_int(b, "episodes", 0, 1, "a positive integer");
  }
  lua_pop(L, 1);
  if (f.push("checkpoints") != LUA_TNIL) {
    if (!lua_istable(L, -1)) f.wrong_type("checkpoints", "a table {every = ..., episodes = ..., threshold = ...}");
    LuaFields c(L, lua_gettop(L), where + ": checkpoints",
                {"every", "episodes", "threshold", "seeds", "stop_after", "final"});
    st.checkpoints.every = positive_int(c, "every", std::max(1, st.budget_episodes / 20), 1, "a positive integer");
    st.checkpoints.episodes = positive_int(c, "episodes", 20, 1, "a positive integer");
    st.checkpoints.threshold = c.number("threshold", 0.9);
    if (!(st.checkpoints.threshold > 0.0 && st.checkpoints.threshold <= 1.0))
      c.fail("field 'threshold' must be a success rate in (0, 1], got " + format_number(st.checkpoints.threshold));
    const int64_t seeds = c.integer("seeds", 1000000);
    if (seeds < 0) c.fail("field 'seeds' must be a non-negative integer, got " + std::to_string(seeds));
    st.checkpoints.seeds = uint64_t(seeds);
    st.checkpoints.stop_after = positive_int(c, "stop_after", 0, 0, "a non-negative integer");
    st.checkpoints.final_episodes = positive_int(c, "final", 50, 1, "a positive integer");
  } else {
    st.checkpoints.every = std::max(1, st.budget_episodes / 20);
  }
  lua_pop(L, 1);
  if (f.push("contexts") == LUA_TNIL) f.fail("missing required field 'contexts' (named action sets Psi)");
  parse_contexts(L, st);
  lua_pop(L, 1);
  if (f.push("skill") != LUA_TNIL) {
    if (!lua_istable(L, -1)) f.wrong_type("skill", "a table {name = ..., context = ...}");
    LuaFields s(L, lua_gettop(L), where + ": skill", {"name", "context"});
    const std::string name = s.string("name");
    const std::string ctx = s.string("context");
    if (name.empty()) s.fail("field 'name' must not be empty");
    std::vector<std::string> names;
    for (const auto& c : st.contexts) names.push_back(c.name);
    if (std::find(names.begin(), names.end(), ctx) == names.end())
      s.fail("unknown context '" + ctx + "'; the stage's contexts: " + join(names));
    if (st.absorbing_lua)
      s.fail("a stage whose absorbing state is a Lua function cannot yield a skill (its gamma is evaluated "
             "every tick): write absorbing as a predicate such as roger.converged(c)");
    st.skill = std::make_pair(name, ctx);
  }
  lua_pop(L, 1);
}

// roger.stage{...}: validates a stage where it is written and returns the same table.
int l_stage(lua_State* L) {
  return lua_protect(L, [&]() {
    Book& book = book_of(L);
    CurriculumStage st;
    LuaCallback a, r;
    parse_stage(L, 1, st, a, r);
    const auto [file, line] = caller(L);
    st.file = file, st.line = line;
    book.tables[lua_topointer(L, 1)] = book.stages.size();
    book.stages.push_back(std::move(st));
    book.absorbing_fns.push_back(a);
    book.reward_fns.push_back(r);
    lua_settop(L, 1);
    return 1;
  });
}

// roger.learned("Phi_SG"): the stand-in for a skill an earlier stage yields.
int l_learned(lua_State* L) {
  return lua_protect(L, [&]() {
    Book& book = book_of(L);
    if (lua_type(L, 1) != LUA_TSTRING)
      luaL_error(L, "roger.learned: expects the name of a skill an earlier stage yields (a string), got %s",
                 lua_describe_value(L, 1).c_str());
    const std::string name = lua_tostring(L, 1);
    if (name.empty()) luaL_error(L, "roger.learned: the name must not be empty");
    auto it = book.learned.find(name);
    if (it == book.learned.end()) it = book.learned.emplace(name, std::make_shared<LearnedRef>(name)).first;
    lua_push_controller(L, it->second);
    return 1;
  });
}

}  // namespace

std::string CurriculumStage::where(const std::string& context) const {
  return "stage '" + name + "'" + (context.empty() ? "" : ", context '" + context + "'");
}

const CurriculumContext& CurriculumStage::context(const std::string& n) const {
  std::vector<std::string> names;
  for (const auto& c : contexts) {
    if (c.name == n) return c;
    names.push_back(c.name);
  }
  throw Error(where() + " has no context '" + n + "'; its contexts: " + join(names));
}

struct Curriculum::Impl {
  std::unique_ptr<LuaSandbox> sandbox;
  std::string path, file, name, description;
  Book book;
  std::vector<CurriculumStage> stages;
  std::map<std::string, LuaCallback> absorbing_fns, reward_fns;  // by stage name
};

Curriculum::Curriculum() = default;
Curriculum::Curriculum(Curriculum&&) noexcept = default;
Curriculum& Curriculum::operator=(Curriculum&&) noexcept = default;
Curriculum::~Curriculum() = default;

const std::string& Curriculum::name() const { return impl_->name; }
const std::string& Curriculum::description() const { return impl_->description; }
const std::string& Curriculum::path() const { return impl_->path; }
const std::vector<std::filesystem::path>& Curriculum::source_files() const { return impl_->sandbox->source_files(); }
const std::string& Curriculum::file() const { return impl_->file; }
const std::vector<CurriculumStage>& Curriculum::stages() const { return impl_->stages; }

const CurriculumStage& Curriculum::stage(const std::string& n) const {
  std::vector<std::string> names;
  for (const auto& s : impl_->stages) {
    if (s.name == n) return s;
    names.push_back(s.name);
  }
  throw Error("curriculum '" + impl_->name + "' (" + impl_->path + ") has no stage '" + n + "'; its stages: " + join(names));
}

const CurriculumStage* Curriculum::producer(const std::string& skill) const {
  for (const auto& s : impl_->stages)
    if (s.skill && s.skill->first == skill) return &s;
  return nullptr;
}

bool Curriculum::has_learned(const std::string& n) const { return impl_->book.learned.count(n) > 0; }

void Curriculum::bind_learned(const std::string& n, ControllerPtr skill) {
  auto it = impl_->book.learned.find(n);
  if (it == impl_->book.learned.end()) throw Error("curriculum '" + impl_->name + "' never uses roger.learned('" + n + "')");
  it->second->bind(std::move(skill));
}

Curriculum Curriculum::load(const std::string& path_in, const SandboxLimits& limits) {
  const std::string path = resolve_curriculum_path(path_in);
  Curriculum cur;
  cur.impl_ = std::make_unique<Impl>();
  Impl& impl = *cur.impl_;
  impl.sandbox = std::make_unique<LuaSandbox>(limits);
  LuaSandbox& sandbox = *impl.sandbox;
  impl.file = path;
  impl.path = sandbox.display_name(path);
  install_control_api(sandbox);
  lua_State* L = sandbox.state();
  lua_pushlightuserdata(L, &impl.book);
  lua_rawsetp(L, LUA_REGISTRYINDEX, &book_key);
  lua_getglobal(L, "roger");
  lua_pushcfunction(L, l_stage);
  lua_setfield(L, -2, "stage");
  lua_pushcfunction(L, l_learned);
  lua_setfield(L, -2, "learned");
  lua_pop(L, 1);
  sandbox.set_main_script(path);
  sandbox.run_file(path, 1);
  finish_control_definitions(sandbox);

  // The line of a plain-table stage: where its name is written (a table carries no lines).
  const std::string text = read_text(path);
  auto line_of_stage = [&](const std::string& name) {
    const std::regex re("name\\s*=\\s*[\"']" + std::regex_replace(name, std::regex("[^A-Za-z0-9_]"), ".") + "[\"']");
    std::smatch m;
    if (std::regex_search(text, m, re)) return int(std::count(text.begin(), text.begin() + m.position(0), '\n')) + 1;
    return 0;
  };
  int line = 0;  // for errors raised while C++ reads the returned table
  lua_pushcfunction(L, [](lua_State* L) -> int {
    auto* fn = static_cast<std::function<void(lua_State*)>*>(lua_touserdata(L, -1));
    lua_pop(L, 1);
    return lua_protect(L, [&]() {
      (*fn)(L);
      return 0;
    });
  });
  lua_insert(L, -2);
  std::function<void(lua_State*)> body = [&](lua_State* L) {
    const int t = lua_gettop(L);
    if (!lua_istable(L, t))
      luaL_error(L, "a curriculum must return a table {name = ..., description = ..., stages = {...}}, got %s",
                 lua_describe_value(L, t).c_str());
    LuaFields top(L, t, "the curriculum", {"name", "description", "stages"});
    impl.name = top.string("name", fs::path(path).stem().string());
    impl.description = top.string("description", "");
    if (top.push("stages") == LUA_TNIL) top.fail("missing required field 'stages' (a list of roger.stage{...})");
    const int ss = lua_gettop(L);
    if (!lua_istable(L, ss)) top.wrong_type("stages", "a list of stages");
    const lua_Integer n = lua_Integer(lua_rawlen(L, ss));
    if (n == 0) top.fail("'stages' is empty (or not a list): define at least one stage");
    for (lua_Integer i = 1; i <= n; ++i) {
      lua_rawgeti(L, ss, i);
      auto it = impl.book.tables.find(lua_topointer(L, -1));
      CurriculumStage st;
      LuaCallback a, r;
      if (it != impl.book.tables.end()) {
        st = impl.book.stages[it->second];
        a = impl.book.absorbing_fns[it->second];
        r = impl.book.reward_fns[it->second];
      } else {
        lua_getfield(L, -1, "name");
        line = lua_type(L, -1) == LUA_TSTRING ? line_of_stage(lua_tostring(L, -1)) : 0;
        lua_pop(L, 1);
        parse_stage(L, -1, st, a, r);
        st.file = impl.path, st.line = line;
      }
      for (const auto& other : impl.stages)
        if (other.name == st.name) {
          line = st.line;
          luaL_error(L, "a second stage named '%s'", st.name.c_str());
        }
      impl.absorbing_fns[st.name] = a;
      impl.reward_fns[st.name] = r;
      impl.stages.push_back(std::move(st));
      lua_pop(L, 1);
    }
  };
  lua_pushlightuserdata(L, &body);
  try {
    sandbox.call(2, 0);
  } catch (const ScriptError& e) {
    if (!e.file.empty()) throw;
    throw ScriptError(e.message, impl.path, line, "");
  }

  // Across stages: a learned skill must come from an earlier stage.
  std::map<std::string, size_t> produced;
  for (size_t i = 0; i < impl.stages.size(); ++i) {
    const CurriculumStage& st = impl.stages[i];
    if (st.skill) {
      if (produced.count(st.skill->first))
        throw ScriptError(st.where() + ": a second stage yields the skill '" + st.skill->first + "'", st.file, st.line, "");
      produced[st.skill->first] = i;
    }
  }
  for (size_t i = 0; i < impl.stages.size(); ++i) {
    const CurriculumStage& st = impl.stages[i];
    for (const auto& ctx : st.contexts)
      for (const auto& name : ctx.learned) {
        auto it = produced.find(name);
        std::vector<std::string> known;
        for (const auto& [k, v] : produced) known.push_back(k);
        if (it == produced.end())
          throw ScriptError(st.where(ctx.name) + ": roger.learned('" + name + "') names no skill of this curriculum; " +
                                (known.empty() ? "no stage yields one (give a stage skill = {name = ..., context = ...})"
                                               : "skills: " + join(known)),
                            st.file, st.line, "");
        if (it->second == i)
          throw ScriptError(st.where(ctx.name) + ": uses the learned skill '" + name +
                                "', which this very stage yields; a learned skill can only be used by later stages",
                            st.file, st.line, "");
        if (it->second > i)
          throw ScriptError(st.where(ctx.name) + ": uses the learned skill '" + name + "', which the later stage '" +
                                impl.stages[it->second].name + "' yields; move that stage before this one",
                            st.file, st.line, "");
      }
  }
  return cur;
}

namespace {

// Pushes a state as a Lua table {[action name] = "CONV" | "!CONV" | "NOREF"}.
void push_state(lua_State* L, const CurriculumContext& ctx, const std::vector<Gamma>& state) {
  lua_createtable(L, 0, int(state.size()));
  for (size_t i = 0; i < state.size() && i < ctx.actions.size(); ++i) {
    lua_pushstring(L, gamma_name(state[i]));
    lua_setfield(L, -2, ctx.actions[i]->name().c_str());
  }
}

}  // namespace

bool Curriculum::call_absorbing(const CurriculumStage& stage, const CurriculumContext& context,
                                const std::vector<Gamma>& state, double time) {
  const LuaCallback& fn = impl_->absorbing_fns.at(stage.name);
  lua_State* L = impl_->sandbox->state();
  LuaStackGuard guard(L);
  lua_rawgeti(L, LUA_REGISTRYINDEX, fn.ref);
  push_state(L, context, state);
  lua_pushnumber(L, time);
  try {
    impl_->sandbox->call(2, 1);
  } catch (const ScriptError& e) {
    throw ScriptError(stage.where(context.name) + ": absorbing function: " + e.message,
                      e.file.empty() ? fn.file : e.file, e.file.empty() ? fn.line : e.line, e.traceback);
  }
  if (!lua_isboolean(L, -1))
    throw ScriptError(stage.where(context.name) + ": the absorbing function must return true or false, got " +
                          lua_describe_value(L, -1),
                      fn.file, fn.line, "");
  return lua_toboolean(L, -1);
}

double Curriculum::call_reward(const CurriculumStage& stage, const CurriculumContext& context,
                               const std::vector<Gamma>& state, int action, const std::string& event, double time) {
  const LuaCallback& fn = impl_->reward_fns.at(stage.name);
  lua_State* L = impl_->sandbox->state();
  LuaStackGuard guard(L);
  lua_rawgeti(L, LUA_REGISTRYINDEX, fn.ref);
  push_state(L, context, state);
  if (action >= 0 && size_t(action) < context.actions.size()) {
    lua_pushstring(L, context.actions[size_t(action)]->name().c_str());
  } else {
    lua_pushnil(L);
  }
  lua_pushstring(L, event.c_str());
  lua_pushnumber(L, time);
  try {
    impl_->sandbox->call(4, 1);
  } catch (const ScriptError& e) {
    throw ScriptError(stage.where(context.name) + ": reward function: " + e.message,
                      e.file.empty() ? fn.file : e.file, e.file.empty() ? fn.line : e.line, e.traceback);
  }
  if (lua_type(L, -1) != LUA_TNUMBER || !std::isfinite(lua_tonumber(L, -1)))
    throw ScriptError(stage.where(context.name) + ": the reward function must return a finite number, got " +
                          lua_describe_value(L, -1) + " (event '" + event + "')",
                      fn.file, fn.line, "");
  return lua_tonumber(L, -1);
}

std::string resolve_curriculum_path(const std::string& arg) {
  return resolve_script_path(arg, "curricula", "curriculum", "curricula in curricula/",
                             is_curriculum_script);
}

bool is_curriculum_script(const std::string& path) {
  const std::string text = read_text(path);
  if (text.empty()) return false;
  // Outside comments: a `stages =` key.
  std::istringstream in(text);
  std::string l;
  static const std::regex key("(^|[{,;\\s])stages\\s*=[^=]");
  while (std::getline(in, l)) {
    const size_t c = l.find("--");
    if (c != std::string::npos) l.resize(c);
    if (std::regex_search(l + " ", key)) return true;
  }
  return false;
}

std::vector<std::string> check_curriculum(const std::string& path, const SandboxLimits& limits) {
  std::vector<std::string> problems;
  std::optional<Curriculum> cur;
  try {
    cur.emplace(Curriculum::load(path, limits));
  } catch (const std::exception& e) {
    problems.push_back(e.what());
    return problems;
  }
  for (const auto& st : cur->stages()) {
    try {
      Scenario s = Scenario::load(st.scenario, limits);
      for (const auto& [k, v] : st.params) s.set_param(k, v);
      s.generate(0);
    } catch (const std::exception& e) {
      problems.push_back(st.where() + ": scenario '" + st.scenario + "': " + e.what());
    }
  }
  return problems;
}

std::vector<std::filesystem::path> curriculum_source_files(const Curriculum& cur, const SandboxLimits& limits) {
  std::vector<std::filesystem::path> files = cur.source_files();
  std::set<std::string> scenarios;
  for (const auto& st : cur.stages()) {
    if (!scenarios.insert(st.scenario).second) continue;
    Scenario s = Scenario::load(st.scenario, limits);
    for (const auto& f : s.sandbox().source_files())
      if (std::find(files.begin(), files.end(), f) == files.end()) files.push_back(f);
  }
  return files;
}

}  // namespace roger
