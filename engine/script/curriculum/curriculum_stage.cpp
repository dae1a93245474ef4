// Reading one stage table of a curriculum (roger.stage{...} or a plain table in 'stages'): its
// scenario, absorbing state, reward, learner, budget, checkpoints, contexts and skill.
#include <algorithm>
#include <map>
#include <set>

#include "core/text.h"
#include "core/error.h"
#include "control/primitives.h"
#include "script/curriculum/curriculum_internal.h"
#include "script/control/lua_control.h"
#include "script/scenario/scenario.h"

namespace roger {
namespace curriculum_detail {

LuaCallback LuaCallback::keep(lua_State* L) {
  lua_Debug ar;
  lua_pushvalue(L, -1);
  lua_getinfo(L, ">S", &ar);
  LuaCallback fn;
  fn.file = ar.source && ar.source[0] == '@' ? ar.source + 1 : ar.short_src;
  fn.line = ar.linedefined;
  fn.ref = luaL_ref(L, LUA_REGISTRYINDEX);
  return fn;
}

namespace {

// Collects the learned stand-ins a controller reaches.
void find_learned(const Controller* c, std::set<const Controller*>& seen, std::vector<std::string>& out) {
  if (!seen.insert(c).second) return;
  if (dynamic_cast<const LearnedRef*>(c)) {
    if (std::find(out.begin(), out.end(), c->name()) == out.end()) out.push_back(c->name());
    return;  // a bound stand-in's insides belong to the earlier stage
  }
  for (const Controller* child : c->children()) find_learned(child, seen, out);
}

// A positive (or, with lo 0, non-negative) integer field of at most 10^8, a bound the message
// names when it is the one crossed (found by a probe: "must be a positive integer, got
// 2147483647" did not say why).
int positive_int(const LuaFields& f, const char* key, int64_t fallback, int64_t lo, const std::string& what) {
  constexpr int64_t kMost = 100000000;
  const int64_t v = f.integer(key, fallback);
  if (v < lo || v > kMost)
    f.fail("field '" + std::string(key) + "' must be " + what + (v > kMost ? " of at most " + std::to_string(kMost) : "") +
           ", got " + std::to_string(v));
  return int(v);
}

// Reads a stage's or context's `params` table at `index` into `out`, sorted by key.
void read_params_table(lua_State* L, int index, const std::string& where, ParamList& out) {
  lua_read_params(L, index, where + ": field 'params'", out, where + ": params.");
}

// A context's entry: its name, the stack index of its action list and of its params (0: none).
struct ContextEntry {
  std::string name;
  int actions = 0, params = 0;
  std::string init_stage, init_context;  // init = {stage = ..., context = ...} (stage: this one's)
};

// A context given as a table {name = ..., actions = {...}, params = {...}} (`named`) or, in the
// map form, {actions = {...}, params = {...}} (a table with a field 'actions'): pushes its fields.
void read_context_fields(lua_State* L, int e, const std::string& ctx, bool named, ContextEntry& entry) {
  std::vector<std::string> known = {"actions", "init", "params"};
  if (named) known.push_back("name");
  LuaFields f(L, e, ctx, known);
  if (named) {
    entry.name = f.string("name");
    if (entry.name.empty()) f.fail("field 'name' must not be empty");
    if (const std::string problem = name_text_problem(entry.name); !problem.empty()) f.fail("field 'name' " + problem);
  }
  if (f.push("actions") == LUA_TNIL) f.fail("missing required field 'actions' (the list of controllers, Psi)");
  entry.actions = lua_gettop(L);
  if (f.push("init") == LUA_TTABLE) {
    LuaFields init(L, lua_gettop(L), ctx + ": init", {"context", "stage"});
    entry.init_stage = init.string("stage", "");
    entry.init_context = init.string("context");
    if (entry.init_context.empty()) init.fail("field 'context' must name a context, e.g. init = {stage = 'SG', context = 'DC2'}");
  } else if (!lua_isnil(L, -1)) {
    f.wrong_type("init", "a table {stage = ..., context = ...} (the context whose table this one starts from)");
  }
  lua_pop(L, 1);
  if (f.push("params") == LUA_TNIL) lua_pop(L, 1);
  else entry.params = lua_gettop(L);
}

// Whether the table at `index` has a string key 'actions' (a context with fields, not a list).
bool has_actions_field(lua_State* L, int index) {
  if (!lua_istable(L, index)) return false;
  lua_getfield(L, index, "actions");
  const bool has = !lua_isnil(L, -1);
  lua_pop(L, 1);
  return has;
}

// The entries of contexts written as a list {{name = 'A', actions = {...}}, ...} (the table at t, of
// n entries).
std::vector<ContextEntry> context_list(lua_State* L, int t, lua_Integer n, const std::string& where) {
  // A named context beside the list (`{ {name = 'A', ...}, B = {...} }`) would be dropped without
  // a word: found by a probe, whose context B was not trained and roger check said ok.
  if (const std::string key = lua_key_beside_list(L, t); !key.empty())
    luaL_error(L, "%s: field 'contexts' mixes a list with the named entry %s: write it in the list as {name = "
               "..., actions = {...}}, or every context as a map {A = {...}, B = {...}}", where.c_str(), key.c_str());
  std::vector<ContextEntry> entries;
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, t, i);
    const int e = lua_gettop(L);
    const std::string ctx = where + ": context " + std::to_string(i);
    if (!lua_istable(L, e))
      luaL_error(L, "%s must be a table {name = ..., actions = {...}}, got %s", ctx.c_str(),
                 lua_describe_value(L, e).c_str());
    ContextEntry entry;
    read_context_fields(L, e, ctx, true, entry);
    entries.push_back(entry);
  }
  return entries;
}

// The entries of contexts written as a map {B1 = {...}, ...} (the table at t), in name order: a
// map has no order, and name order is reproducible.
std::vector<ContextEntry> context_map(lua_State* L, int t, const CurriculumStage& st) {
  std::vector<std::string> names;
  lua_pushnil(L);
  while (lua_next(L, t)) {
    lua_pop(L, 1);
    if (lua_type(L, -1) != LUA_TSTRING)
      luaL_error(L, "%s: contexts must be named (B1 = {...}) or a list of {name = ..., actions = ...}, got the key %s",
                 st.where().c_str(), lua_describe_value(L, -1).c_str());
    names.push_back(lua_tostring(L, -1));
    if (const std::string problem = name_text_problem(names.back()); !problem.empty())
      luaL_error(L, "%s: a context's name %s", st.where().c_str(), problem.c_str());
  }
  std::sort(names.begin(), names.end());
  std::vector<ContextEntry> entries;
  for (const auto& name : names) {
    lua_getfield(L, t, name.c_str());
    ContextEntry entry;
    entry.name = name;
    entry.actions = lua_gettop(L);
    if (has_actions_field(L, entry.actions)) {
      read_context_fields(L, entry.actions, st.where(name), false, entry);
    } else if (lua_istable(L, entry.actions)) {
      // A table of fields without 'actions' is no list of actions either (found by a probe: a typo
      // 'action' was told "the actions must be a plain list {a, b, ...}, got the key string 'action'").
      const std::string key = lua_key_beside_list(L, entry.actions);
      if (!key.empty() && key.front() == '\'')
        luaL_error(L, "%s: a context of the map form is a list of actions {a, b, ...} or a table {actions = {...}, "
                   "params = {...}, init = {...}}; this one has the field %s%s and no field 'actions'",
                   st.where(name).c_str(), key.c_str(),
                   suggestion(key.substr(1, key.size() - 2), {"actions", "params", "init"}).c_str());
    }
    entries.push_back(entry);
  }
  return entries;
}

// The actions Psi of a context (the list at idx), checked: a plain list of 1 to 12 controllers
// with names that differ.
void read_actions(lua_State* L, int idx, const std::string& ctx, CurriculumContext& c) {
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
  std::map<std::string, std::pair<lua_Integer, ControllerPtr>> action_names;  // name -> its first action
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, idx, i);
    ControllerPtr a = lua_check_controller(L, -1, ctx, "action " + std::to_string(i));
    lua_pop(L, 1);
    const auto [it, fresh] = action_names.emplace(a->name(), std::make_pair(i, a));
    if (!fresh) {
      // Which two, and why they clash (found by a probe: roger.learned('Phi_Look') listed twice was
      // told of "a controller the script defines", and p.phi1 beside p.carry of no positions).
      const ControllerPtr& other = it->second.second;
      const bool a_learned = dynamic_cast<const LearnedRef*>(a.get()), other_learned = dynamic_cast<const LearnedRef*>(other.get());
      const std::string both = "actions " + std::to_string(it->second.first) + " and " + std::to_string(i);
      const std::string which =
          a.get() == other.get() || (a_learned && other_learned)
              ? " (" + both + " are the same action: list it once)"
          : a_learned || other_learned
              ? " (" + both + ": one is roger.learned('" + a->name() + "'), the skill a stage yields, the other a "
                "controller the script defines: give the stage's skill another name)"
              : " (" + both + ": a controller is named by its kind unless it is given name = \"...\", as the carrying "
                "phi1 of lib.skills is: give one of them another name)";
      luaL_error(L, "%s: two actions are named '%s'%s; the names of Psi must differ", ctx.c_str(), a->name().c_str(),
                 which.c_str());
    }
    c.actions.push_back(std::move(a));
  }
  std::set<const Controller*> visited;
  for (const auto& a : c.actions) find_learned(a.get(), visited, c.learned);
}

// Reads the contexts of a stage (the value on top of the stack).
void parse_contexts(lua_State* L, CurriculumStage& st) {
  const int t = lua_gettop(L);
  const std::string where = st.where();
  if (!lua_istable(L, t))
    luaL_error(L, "%s: field 'contexts' must be a table: a list {{name = 'B1', actions = {...}}, ...} or a map "
               "{B1 = {...}, ...}, got %s", where.c_str(), lua_describe_value(L, t).c_str());
  const lua_Integer n = lua_Integer(lua_rawlen(L, t));
  const std::vector<ContextEntry> entries = n > 0 ? context_list(L, t, n, where) : context_map(L, t, st);
  if (entries.empty()) luaL_error(L, "%s: field 'contexts' is empty: define at least one context", where.c_str());
  std::map<std::string, size_t> seen_names;  // each name's position in the list
  for (size_t k = 0; k < entries.size(); ++k) {
    const ContextEntry& entry = entries[k];
    const std::string& name = entry.name;
    const std::string ctx = st.where(name);
    // At the second one's line ("context 2: " leads there), naming the first.
    if (const auto [first, added] = seen_names.emplace(name, k + 1); !added)
      luaL_error(L, "%s: context %d: a second context named '%s' (context %d is named so)", where.c_str(), int(k + 1),
                 name.c_str(), int(first->second));
    if (!lua_istable(L, entry.actions))
      luaL_error(L, "%s: the actions must be a list of controllers, got %s", ctx.c_str(),
                 lua_describe_value(L, entry.actions).c_str());
    CurriculumContext c;
    c.name = name;
    c.init_stage = entry.init_context.empty() || !entry.init_stage.empty() ? entry.init_stage : st.name;
    c.init_context = entry.init_context;
    if (entry.params) read_params_table(L, entry.params, ctx, c.params);
    read_actions(L, entry.actions, ctx, c);
    st.contexts.push_back(std::move(c));
  }
  lua_settop(L, t);
}

// Reads the stage's 'params' (scenario parameters), sorted by key.
void read_stage_params(lua_State* L, const LuaFields& f, CurriculumStage& st) {
  if (f.push("params") != LUA_TNIL) {
    const int p = lua_gettop(L);
    if (!lua_istable(L, p)) f.wrong_type("params", "a table of scenario parameters {key = value}");
    read_params_table(L, p, f.context(), st.params);
  }
  lua_pop(L, 1);
}

// "field 'absorbing' is the function roger.converged itself, ": a control API function given where
// a callback is taken, its call forgotten. Called as a callback it would fail inside C, at no line of
// the script (found by a probe: blamed at "[C]:"), so it is refused at its field.
std::string function_itself(const char* field, const ApiFunction& fn) {
  return "field '" + std::string(field) + "' is the function " + fn.name + " itself, ";
}

// Reads the stage's 'absorbing': a predicate, or a Lua function kept in the registry.
void read_absorbing(lua_State* L, const LuaFields& f, const std::string& where, CurriculumStage& st,
                    LuaCallback& absorb_fn) {
  // absorbing: a predicate (evaluated in C++ every tick) or a Lua function (at decision points).
  const int at = f.push("absorbing");
  if (at == LUA_TNIL) f.fail("missing required field 'absorbing' (a predicate such as roger.converged(c), or a function(state))");
  const ApiFunction fn = lua_control_function(L, -1);
  if (!fn.name.empty())
    f.fail(function_itself("absorbing", fn) + "not a predicate: " +
           (fn.predicate_call.empty() ? "write a predicate such as roger.converged(c), or a function(state)"
                                      : "did you mean " + fn.predicate_call + "?"));
  if (at == LUA_TFUNCTION) {
    absorb_fn = LuaCallback::keep(L);
    st.absorbing_lua = true;
  } else {
    st.absorbing = lua_check_predicate(L, -1, where, "field 'absorbing'");
    lua_pop(L, 1);
    const std::string at_once = holds_at_once(*st.absorbing);
    if (!at_once.empty()) f.fail("field 'absorbing': " + at_once);
    // After read_time_limit: a fixed limit bounds when the absorbing state can first hold.
    const std::string never = st.time_per_object > 0.0 ? "" : never_holds_within(*st.absorbing, st.time_limit);
    if (!never.empty()) f.fail("field 'absorbing': " + never);
  }
}

// Reads the stage's 'reward' (a table of constants or a Lua function kept in the registry) and
// checks the constants.
void read_reward(lua_State* L, const LuaFields& f, const std::string& where, CurriculumStage& st,
                 LuaCallback& reward_fn) {
  // reward: the paper's constants by default, a table of them, or a Lua function.
  const int rt = f.push("reward");
  const ApiFunction fn = lua_control_function(L, -1);
  if (!fn.name.empty())
    f.fail(function_itself("reward", fn) + "not a reward: give a table {absorbing = 100, timeout = -100, step = 0} "
           "or a function(state, action, event)" +
           (fn.predicate_call.empty() ? "" : "; a condition such as " + fn.predicate_call + " belongs in 'absorbing'"));
  if (rt == LUA_TFUNCTION) {
    reward_fn = LuaCallback::keep(L);
    st.reward_lua = true;
  } else if (rt == LUA_TTABLE) {
    LuaFields r(L, lua_gettop(L), where + ": reward", {"absorbing", "timeout", "step"});
    st.rewards.success_reward = r.number("absorbing", 100.0);
    st.rewards.timeout_reward = r.number("timeout", -100.0);
    st.rewards.step_reward = r.number("step", 0.0);
    for (const auto& [key, v] : {std::pair<const char*, double>{"absorbing", st.rewards.success_reward},
                                 {"timeout", st.rewards.timeout_reward}, {"step", st.rewards.step_reward}})
      if (const std::string p = reward_magnitude_problem(v); !p.empty())
        r.fail(std::string("field '") + key + "' must be " + p);
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
}

// Reads the stage's optional 'learner' settings over the defaults and checks them.
void read_learner(lua_State* L, const LuaFields& f, const std::string& where, CurriculumStage& st) {
  if (f.push("learner") != LUA_TNIL) {
    if (!lua_istable(L, -1))
      f.wrong_type("learner", "a table {alpha = ..., discount = ..., discount_seconds = ..., epsilon_start = ..., epsilon_end = ...}");
    LuaFields q(L, lua_gettop(L), where + ": learner",
                {"alpha", "discount", "discount_seconds", "epsilon_start", "epsilon_end", "initial_q",
                 "referenced_only", "unconverged_first"});
    st.learner.alpha = q.number("alpha", st.learner.alpha);
    st.learner.discount = q.number("discount", st.learner.discount);
    st.learner.epsilon_start = q.number("epsilon_start", st.learner.epsilon_start);
    st.learner.epsilon_end = q.number("epsilon_end", st.learner.epsilon_end);
    st.learner.initial_q = q.number("initial_q", st.learner.initial_q);
    st.learner.referenced_only = q.boolean("referenced_only", st.learner.referenced_only);
    st.learner.unconverged_first = q.boolean("unconverged_first", st.learner.unconverged_first);
    // The discount's clock lives with the episode's options, where the semi-MDP reads it.
    st.rewards.discount_seconds = q.number("discount_seconds", st.rewards.discount_seconds);
    if (!(st.rewards.discount_seconds >= 0.0 && st.rewards.discount_seconds <= 1e6))
      q.fail("field 'discount_seconds' must be 0 (discount once per decision) or seconds up to 1e6, got " +
             format_number(st.rewards.discount_seconds));
    const std::string why = st.learner.problem();
    if (!why.empty()) q.fail(why);
  }
  lua_pop(L, 1);
}

// Reads the stage's 'budget' (training episodes) and its 'checkpoints' (every budget/20 episodes
// by default).
void read_budget_checkpoints(lua_State* L, const LuaFields& f, const std::string& where, CurriculumStage& st) {
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
                {"every", "episodes", "threshold", "seeds", "stop_after", "settle", "final"});
    st.checkpoints.every = positive_int(c, "every", std::max(1, st.budget_episodes / 20), 1, "a positive integer");
    // Found by a probe: every = 500 under a budget of 300 trained with one checkpoint, after the
    // last episode, and reported the threshold reached "after 300 episodes", the budget's figure.
    if (st.checkpoints.every > st.budget_episodes)
      c.fail("field 'every' is " + std::to_string(st.checkpoints.every) + ", more than the budget's " +
             std::to_string(st.budget_episodes) + " episodes: the only checkpoint would follow the last episode, "
             "and the time to the threshold would be the budget's; give every at most budget.episodes");
    st.checkpoints.episodes = positive_int(c, "episodes", 20, 1, "a positive integer");
    st.checkpoints.threshold = c.number("threshold", 0.9);
    if (!(st.checkpoints.threshold > 0.0 && st.checkpoints.threshold <= 1.0))
      c.fail("field 'threshold' must be a success rate in (0, 1], got " + format_number(st.checkpoints.threshold));
    const int64_t seeds = c.integer("seeds", 1000000);
    if (seeds < 0) c.fail("field 'seeds' must be a non-negative integer, got " + std::to_string(seeds));
    st.checkpoints.seeds = uint64_t(seeds);
    st.checkpoints.stop_after = positive_int(c, "stop_after", 0, 0, "a non-negative integer");
    st.checkpoints.settle = c.boolean("settle", true);
    st.checkpoints.final_episodes = positive_int(c, "final", 50, 1, "a positive integer");
  } else {
    st.checkpoints.every = std::max(1, st.budget_episodes / 20);
  }
  lua_pop(L, 1);
}


// Reads the stage's optional 'skill' {name, context}: the skill the stage yields.
void read_skill(lua_State* L, const LuaFields& f, const std::string& where, CurriculumStage& st) {
  if (f.push("skill") != LUA_TNIL) {
    if (!lua_istable(L, -1)) f.wrong_type("skill", "a table {name = ..., context = ...}");
    LuaFields s(L, lua_gettop(L), where + ": skill", {"name", "context"});
    const std::string name = s.string("name");
    const std::string ctx = s.string("context");
    if (name.empty()) s.fail("field 'name' must not be empty");
    if (const std::string problem = name_text_problem(name); !problem.empty()) s.fail("field 'name' " + problem);
    if (const std::string problem = skill_name_problem(name); !problem.empty()) s.fail("field 'name': " + problem);
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

// time_limit: simulated seconds, or {per_object = s} for a task over however many objects its
// world holds (sorting), as a skill script's policy may have it.
void read_time_limit(lua_State* L, LuaFields& f, const std::string& where, CurriculumStage& st) {
  if (!f.has("time_limit"))
    f.fail("missing required field 'time_limit' (simulated seconds, e.g. 5, or {per_object = s})");
  if (f.push("time_limit") == LUA_TTABLE) {
    LuaFields limit(L, -1, where + ": field 'time_limit'", {"per_object"});
    if (!limit.has("per_object")) limit.fail("missing required field 'per_object' (simulated seconds per object)");
    st.time_per_object = limit.number("per_object");
    if (!(st.time_per_object > 0.0 && st.time_per_object <= kMaxTimeLimit))
      limit.fail("field 'per_object' must be in (0, 3600] simulated seconds, got " + format_number(st.time_per_object));
    lua_pop(L, 1);
    return;
  }
  lua_pop(L, 1);
  st.time_limit = f.number("time_limit");
  if (!(st.time_limit > 0.0 && st.time_limit <= kMaxTimeLimit))
    f.fail("field 'time_limit' must be in (0, 3600] simulated seconds, or {per_object = s}, got " +
           format_number(st.time_limit));
}

// Whether the stage's checkpoints table writes `key` (a test set replaces episodes and final).
bool checkpoints_field(lua_State* L, const LuaFields& f, const char* key) {
  bool has = false;
  if (f.push("checkpoints") == LUA_TTABLE) {
    lua_getfield(L, -1, key);
    has = !lua_isnil(L, -1);
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  return has;
}

}  // namespace

std::string skill_name_problem(const std::string& name) {
  const std::vector<std::string>& kinds = primitive_names();
  if (std::find(kinds.begin(), kinds.end(), name) == kinds.end()) return "";
  return "the name '" + name + "' is a primitive kind, which always means that kind's default primitive; a learned "
         "skill needs another name (e.g. '" + name + "_learned')";
}

// Reads a stage table at `index` into `st`, raising Lua errors "stage 'X': ..." (at the caller's
// file:line when called from Lua). Functions given for absorbing/reward are kept in the registry.
void parse_stage(lua_State* L, int index, CurriculumStage& st, LuaCallback& absorb_fn, LuaCallback& reward_fn,
                 LuaCallback& teacher_fn, const std::string& naming_file, const std::string& curriculum_file) {
  index = lua_absindex(L, index);
  if (!lua_istable(L, index))
    luaL_error(L, "a stage must be a table {name = ..., time_limit = ..., absorbing = ..., contexts = ...}, got %s",
               lua_describe_value(L, index).c_str());
  lua_getfield(L, index, "name");
  st.name = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : "";
  // Found by a probe: name = 5 was "missing required field 'name'", where every other field of the
  // wrong type says what it got.
  const std::string given = lua_isnil(L, -1) || lua_type(L, -1) == LUA_TSTRING ? "" : lua_describe_value(L, -1);
  lua_pop(L, 1);
  const std::string where = st.name.empty() ? std::string("a stage") : st.where();
  LuaFields f(L, index, where,
              {"absorbing", "budget", "checkpoints", "contexts", "description", "learner", "name", "params",
               "reward", "scenario", "skill", "tasks", "teacher", "test", "time_limit"});
  if (!given.empty()) f.fail("field 'name' must be a string such as \"SG\", got " + given);
  if (st.name.empty()) f.fail("missing required field 'name' (a string such as \"SG\")");
  if (const std::string problem = name_text_problem(st.name); !problem.empty()) f.fail("field 'name' " + problem);
  st.description = f.string("description", "");
  st.scenario = f.string("scenario", "unobstructed");
  try {
    st.scenario = resolve_scenario_near(st.scenario, naming_file, curriculum_file);  // beside the file, as require
  } catch (const Error& e) {
    f.fail(std::string("field 'scenario': ") + e.what());
  }
  st.scenario_beside = scenario_beside(st.scenario, naming_file, curriculum_file);
  read_stage_params(L, f, st);
  read_time_limit(L, f, where, st);
  read_absorbing(L, f, where, st, absorb_fn);
  read_reward(L, f, where, st, reward_fn);
  read_learner(L, f, where, st);
  read_budget_checkpoints(L, f, where, st);
  if (f.push("contexts") == LUA_TNIL) f.fail("missing required field 'contexts' (named action sets Psi)");
  parse_contexts(L, st);
  lua_pop(L, 1);
  read_skill(L, f, where, st);
  // After the contexts: a task parameter may not be one a context fixes.
  parse_teaching(L, f, st, teacher_fn, checkpoints_field(L, f, "episodes"), checkpoints_field(L, f, "final"));
}

}  // namespace curriculum_detail
}  // namespace roger
