#include "script/skills/skill_script.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

#include <lua.hpp>

#include "core/error.h"
#include "core/fileio.h"
#include "core/text.h"
#include "control/primitives.h"
#include "script/control/lua_control.h"
#include "script/sandbox/lua_tokens.h"
#include "script/scenario/scenario.h"

namespace roger {
namespace fs = std::filesystem;

namespace {

// Joins items with a separator.
// ---------------------------------------------------------------------------------------------
// Where the fields of the returned table are written. A Lua table carries no line numbers, so a
// missing goal or a misspelt field would otherwise be reported without one: the source text is
// scanned for the table constructors instead (tokens, with strings, comments and blocks handled),
// and each key remembers its line.

// The keys of the table constructors in a source text (LuaTableMap), and which constructor is
// returned.
class SourceMap {
 public:
  explicit SourceMap(const std::string& text) : map_(text) {
    returned_ = map_.returned();
    for (size_t n = 0; n < map_.nodes().size() && returned_ < 0; ++n)
      if (map_.entry(int(n), "policies")) returned_ = int(n);
  }

  // The line of the returned table's constructor (or of the last top-level return), else 0.
  int return_line() const { return returned_ >= 0 ? map_.nodes()[size_t(returned_)].line : map_.return_line(); }

  // The line of a key of the returned table, else return_line().
  int top_key(const std::string& key) const {
    const auto* e = map_.entry(returned_, key);
    return e ? e->line : return_line();
  }

  // Whether the returned table is written with a `policies` key.
  bool has_policies() const { return map_.entry(returned_, "policies") != nullptr; }

  // The line of policies[name], else of `policies`, else return_line().
  int policy(const std::string& name) const {
    const auto* e = map_.entry(policies_node(), name);
    return e ? e->line : top_key("policies");
  }

  // The line of a field of policies[name], else policy(name).
  int policy_field(const std::string& name, const std::string& field) const {
    const auto* p = map_.entry(policies_node(), name);
    const auto* e = p ? map_.entry(map_.value_node(*p), field) : nullptr;
    return e ? e->line : policy(name);
  }

 private:
  int policies_node() const {
    const auto* e = map_.entry(returned_, "policies");
    return e ? map_.value_node(*e) : -1;
  }

  LuaTableMap map_;
  int returned_ = -1;
};

// Depth-first walk adding every controller once (name stand-ins are looked through).
void collect(const Controller* c, std::set<const Controller*>& seen,
             const std::map<const Controller*, ControllerPtr>& owners, std::vector<ControllerPtr>& out) {
  if (!seen.insert(c).second) return;
  if (!is_name_reference(*c)) {
    auto it = owners.find(c);
    if (it != owners.end()) out.push_back(it->second);
  }
  for (const Controller* child : c->children()) collect(child, seen, owners, out);
}

}  // namespace

// ---------------------------------------------------------------------------------------------

struct SkillScript::Impl {
  std::string path;  // as shown
  std::string name, description;
  std::map<std::string, NamedPolicy> policies;
  std::vector<ControllerPtr> controllers;
};

SkillScript::SkillScript() = default;
SkillScript::SkillScript(SkillScript&&) noexcept = default;
SkillScript& SkillScript::operator=(SkillScript&&) noexcept = default;
SkillScript::~SkillScript() = default;

const std::string& SkillScript::name() const { return impl_->name; }
const std::string& SkillScript::description() const { return impl_->description; }
const std::string& SkillScript::path() const { return impl_->path; }
std::vector<ControllerPtr> SkillScript::controllers() const { return impl_->controllers; }

std::vector<std::string> SkillScript::policy_names() const {
  std::vector<std::string> names;
  for (const auto& [name, p] : impl_->policies) names.push_back(name);
  return names;
}

const SkillScript::NamedPolicy& SkillScript::policy(const std::string& name) const {
  auto it = impl_->policies.find(name);
  if (it == impl_->policies.end())
    throw Error("skill script '" + impl_->name + "' (" + impl_->path + ") has no policy '" + name + "'" +
                suggestion(name, policy_names()) + "; its policies: " + join(policy_names()));
  return it->second;
}

Scenario SkillScript::scenario_of(const NamedPolicy& p, const std::string& chosen, const SandboxLimits& limits) const {
  Scenario scenario = Scenario::load(!chosen.empty() ? chosen : p.scenario.empty() ? "unobstructed" : p.scenario, limits);
  // Written in a Lua table, as a stage's params are, and every problem said at once (found by a
  // probe: `flag = 0` was taken as false, and of three mistakes only the last was said).
  const std::vector<std::string> problems = scenario.param_problems(p.params, /*from_lua=*/true);
  if (!problems.empty())
    throw ScriptError("policy '" + p.name + "': field 'params': " + join(problems, "; "), impl_->path, p.params_line, "");
  scenario.set_params(p.params);
  return scenario;
}

namespace {

// Checks that the returned value at `t` is a table with only the known keys. `line` follows the
// key being checked.
void check_script_keys(lua_State* L, int t, const std::vector<std::string>& known, const SourceMap& map,
                       int& line) {
  line = map.return_line();
  if (!lua_istable(L, t))
    luaL_error(L, "a skill script must return a table {name = ..., description = ..., policies = {...}}, got %s",
               lua_describe_value(L, t).c_str());
  lua_pushnil(L);
  while (lua_next(L, t)) {
    lua_pop(L, 1);
    const std::string key = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : "";
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      line = key.empty() ? map.return_line() : map.top_key(key);
      luaL_error(L, "the skill script's table has an unknown field %s; known fields: %s",
                 (key.empty() ? "(a key that is " + lua_describe_value(L, -1) + ")"
                              : "'" + key + "'" + suggestion(key, known)).c_str(),
                 join(known).c_str());
    }
  }
}

// Reads the script's name and description; pushes its 'policies' table and returns its index.
int read_script_fields(lua_State* L, const LuaFields& top, const SourceMap& map, int& line,
                       const std::string& path, std::string& name, std::string& description) {
  line = map.top_key("name");
  name = top.string("name", fs::path(path).stem().string());
  line = map.top_key("description");
  description = top.string("description", "");
  line = map.top_key("policies");
  if (top.push("policies") == LUA_TNIL)
    top.fail("missing required field 'policies' (a table of name = {action = ..., goal = ..., time_limit = ...})");
  if (!lua_istable(L, -1)) top.wrong_type("policies", "a table of name = {action = ..., goal = ..., time_limit = ...}");
  return lua_gettop(L);
}

// The names of the policies in the 'policies' table at `ps`, sorted (a table has no order).
std::vector<std::string> policy_keys(lua_State* L, int ps, const LuaFields& top) {
  std::vector<std::string> names;
  lua_pushnil(L);
  while (lua_next(L, ps)) {
    lua_pop(L, 1);
    if (lua_type(L, -1) != LUA_TSTRING)
      luaL_error(L, "the skill script: policies must be named (name = {...}), got the key %s",
                 lua_describe_value(L, -1).c_str());
    names.push_back(lua_tostring(L, -1));
  }
  if (names.empty()) top.fail("'policies' is empty: define at least one policy");
  std::sort(names.begin(), names.end());
  return names;
}

// A policy's params {name = value, ...}: scenario parameters as the text --set gives them (a
// number, a string or a boolean each), sorted by name. The scenario checks names and values when
// it is loaded (SkillScript::scenario_of).
std::vector<std::pair<std::string, std::string>> read_policy_params(lua_State* L, const LuaFields& f,
                                                                    const std::string& context) {
  if (f.push("params") != LUA_TTABLE) f.wrong_type("params", "a table of scenario parameters {objects = 4, ...}");
  std::vector<std::pair<std::string, std::string>> params;
  lua_read_params(L, -1, context + ": field 'params'", params, context + ": params.");
  lua_pop(L, 1);
  return params;
}

// Reads the policy `name` of the 'policies' table at `ps`, leaving its table on the stack. `line`
// follows the field being read; a scenario path is looked for beside `script_file` first.
SkillScript::NamedPolicy read_policy(lua_State* L, int ps, const std::string& name, const SourceMap& map,
                                     int& line, const std::string& script_file) {
  const std::vector<std::string> fields{"action", "description", "goal", "params", "scenario", "time_limit"};
  const std::string context = "policy '" + name + "'";
  line = map.policy(name);
  lua_getfield(L, ps, name.c_str());
  const int p = lua_gettop(L);
  if (!lua_istable(L, p))
    luaL_error(L, "%s must be a table {action = ..., goal = ..., time_limit = ...}, got %s", context.c_str(),
               lua_describe_value(L, p).c_str());
  lua_pushnil(L);
  while (lua_next(L, p)) {
    lua_pop(L, 1);
    const std::string key = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : "";
    if (std::find(fields.begin(), fields.end(), key) == fields.end()) {
      line = key.empty() ? map.policy(name) : map.policy_field(name, key);
      luaL_error(L, "%s: unknown field %s; known fields: %s", context.c_str(),
                 (key.empty() ? "(a key that is " + lua_describe_value(L, -1) + ")"
                              : "'" + key + "'" + suggestion(key, fields)).c_str(),
                 join(fields).c_str());
    }
  }
  LuaFields f(L, p, context, fields);
  if (const std::string problem = name_text_problem(name); !problem.empty()) f.fail("the policy's name " + problem);
  SkillScript::NamedPolicy np;
  np.name = name;
  line = map.policy(name);
  if (!f.has("action")) f.fail("missing required field 'action' (the controller to run)");
  if (!f.has("goal"))
    f.fail("missing required field 'goal' (a predicate such as roger.converged(c): reaching it ends the "
           "episode in success)");
  if (!f.has("time_limit")) f.fail("missing required field 'time_limit' (simulated seconds, e.g. 10)");
  line = map.policy_field(name, "action");
  f.push("action");
  np.action = lua_check_controller(L, -1, context, "field 'action'");
  lua_pop(L, 1);
  line = map.policy_field(name, "goal");
  f.push("goal");
  np.goal = lua_check_predicate(L, -1, context, "field 'goal'");
  lua_pop(L, 1);
  const std::string at_once = holds_at_once(*np.goal);
  if (!at_once.empty()) f.fail("field 'goal': " + at_once);
  line = map.policy_field(name, "time_limit");
  if (f.push("time_limit") == LUA_TTABLE) {
    // {per_object = s}: a task over however many objects the world holds (sorting).
    LuaFields limit(L, -1, context + ": field 'time_limit'", {"per_object"});
    np.time_per_object = limit.number("per_object");
    if (!(np.time_per_object > 0.0 && np.time_per_object <= kMaxTimeLimit))
      limit.fail("field 'per_object' must be in (0, 3600] simulated seconds, got " + format_number(np.time_per_object));
    lua_pop(L, 1);
  } else {
    lua_pop(L, 1);
    np.time_limit = f.number("time_limit");
    if (!(np.time_limit > 0.0 && np.time_limit <= kMaxTimeLimit))  // as a stage's
      f.fail("field 'time_limit' must be in (0, 3600] simulated seconds, or {per_object = s}, got " +
             format_number(np.time_limit));
    // A limit per object grows with the world; a fixed one bounds when the goal can first hold.
    const std::string never = never_holds_within(*np.goal, np.time_limit);
    if (!never.empty()) {
      line = map.policy_field(name, "goal");
      f.fail("field 'goal': " + never);
    }
  }
  line = map.policy_field(name, "scenario");
  np.scenario = f.string("scenario", "unobstructed");
  // Beside the script first, as a curriculum's stage and require find theirs: the same script
  // then runs from any folder.
  try {
    np.scenario = resolve_scenario_near(np.scenario, script_file);
  } catch (const Error& e) {
    f.fail(std::string("field 'scenario': ") + e.what());
  }
  line = map.policy_field(name, "params");
  np.params_line = line;
  if (f.has("params")) np.params = read_policy_params(L, f, context);
  line = map.policy_field(name, "description");
  np.description = f.string("description", "");
  np.goal_line = map.policy_field(name, "goal");
  return np;
}

// Every controller once: the named ones first, then what the policies reach. children() gives
// raw pointers; the script's own list gives their shared owners.
std::vector<ControllerPtr> script_controllers_once(
    LuaSandbox& sandbox, const std::map<std::string, SkillScript::NamedPolicy>& policies) {
  std::vector<ControllerPtr> controllers;
  std::map<const Controller*, ControllerPtr> owners;
  for (const auto& c : script_controllers(sandbox)) owners.emplace(c.get(), c);
  std::set<const Controller*> seen;
  for (const auto& n : named_controllers(sandbox)) collect(n.controller.get(), seen, owners, controllers);
  for (const auto& [name, p] : policies) {
    collect(p.action.get(), seen, owners, controllers);
    std::vector<const Controller*> read;
    p.goal->controllers(read);
    for (const Controller* c : read) collect(c, seen, owners, controllers);
  }
  return controllers;
}

}  // namespace

SkillScript SkillScript::load(const std::string& path_in, const SandboxLimits& limits) {
  const std::string path = resolve_skill_script_path(path_in);
  SkillScript script;
  script.impl_ = std::make_unique<Impl>();
  Impl& impl = *script.impl_;
  LuaSandbox sandbox(limits);
  impl.path = sandbox.display_name(path);
  const SourceMap map(read_file_text(path));

  install_control_api(sandbox);
  sandbox.set_main_script(path);
  sandbox.run_file(path, 1);
  finish_control_definitions(sandbox);

  int line = 0;  // the line of what is being read, for errors raised without one
  sandbox.read_returned_table(impl.path, [&]() { return line; }, [&](lua_State* L) {
    const int t = lua_gettop(L);
    const std::vector<std::string> known{"description", "name", "policies"};
    check_script_keys(L, t, known, map, line);
    LuaFields top(L, t, "the skill script", known);
    const int ps = read_script_fields(L, top, map, line, path, impl.name, impl.description);
    for (const auto& name : policy_keys(L, ps, top)) {
      SkillScript::NamedPolicy np = read_policy(L, ps, name, map, line, impl.path);
      impl.policies.emplace(name, std::move(np));
      lua_settop(L, ps);
    }
  });
  impl.controllers = script_controllers_once(sandbox, impl.policies);
  return script;
}

std::string resolve_skill_script_path(const std::string& arg) {
  return resolve_script_path(arg, "curricula", "skill script", "skill scripts in curricula/",
                             is_skill_script);
}

bool is_skill_script(const std::string& path) {
  const std::string text = read_file_text(path);
  return !text.empty() && SourceMap(text).has_policies();
}

namespace {

// The worlds of seeds 0..kCheckedSeeds-1 of each policy's scenario are generated (as roger check
// builds a scenario's), and each policy runs a few ticks in the first: a world that cannot be
// placed at some seed, or a goal that cannot work in the scenario's worlds (roger.sorted() with
// no object of a goal region's colour), is found here rather than by roger eval (found by a
// probe: check said ok, eval failed at seed 9, or at once with no file or line).
constexpr uint64_t kCheckedSeeds = 20;
constexpr double kCheckedSeconds = 0.1;

// "" or the first seed's problem of a scenario's worlds. A print in generate is shown for the first
// world only, and counted by `prints` after it, as roger check of a scenario does (found by a
// probe: one print in generate was shown 26 times).
std::string worlds_problem(Scenario& scenario, QuietPrints& prints) {
  for (uint64_t seed = 0; seed < kCheckedSeeds; ++seed) try {
      if (seed == 1) prints.quiet();
      scenario.generate(seed);
    } catch (const std::exception& e) {
      return with_note_on_first_line(e.what(), " (world seed " + std::to_string(seed) + ")");
    }
  return "";
}

// "" or what stopped the policy's first ticks in the world of seed 0.
std::string first_ticks_problem(const SkillScript& script, const SkillScript::NamedPolicy& p, Scenario& scenario) {
  EpisodeOptions o = p.episode_options();
  o.time_limit = kCheckedSeconds;
  o.time_per_object = 0.0;
  try {
    evaluate_action([&](uint64_t seed) { return scenario.generate(seed); }, *p.action, *p.goal, 1, 0, o);
  } catch (const ScriptError& e) {
    return e.what();
  } catch (const std::exception& e) {
    return script.path() + ":" + std::to_string(p.goal_line) + ": policy '" + p.name + "': " + e.what() +
           " (world seed 0 of scenario '" + p.scenario + "')";
  }
  return "";
}

// A goal region a binding or a navigator of the policy names that none of the scenario's first
// worlds has (found by a probe for bindings, and by a newcomer for a plain phi1 {goal = "region"}:
// check said ok, and eval named the controller only as NOREF at every tick), or "".
std::string region_problem(const SkillScript& script, const SkillScript::NamedPolicy& p, Scenario& scenario) {
  size_t regions = 0;
  try {
    for (uint64_t seed = 0; seed < 5; ++seed) regions = std::max(regions, scenario.generate(seed).goals.size());
  } catch (const std::exception&) {
    return "";  // the worlds' own problem, said by worlds_problem
  }
  const RegionUse use = first_region_beyond(p.action.get(), int(regions));
  if (!use.controller) return "";
  return script.path() + ":" + std::to_string(p.goal_line) + ": policy '" + p.name + "': " +
         region_use_problem(use, p.scenario, int(regions));
}

using SetList = std::vector<std::pair<std::string, std::string>>;  // scenario parameters as text

// `sets` (roger check's --set) on a policy's scenario: those it declares, as `roger eval` of the
// policy takes them; their names join `used`.
void set_declared(Scenario& scenario, const SetList& sets, std::set<std::string>& used) {
  std::set<std::string> declared;
  for (const ScenarioParam& p : scenario.params()) declared.insert(p.name);
  SetList mine;
  for (const auto& [name, value] : sets)
    if (declared.count(name)) mine.push_back({name, value}), used.insert(name);
  scenario.set_params(mine);
}

// A --set that no policy's scenario declares, refused by `first`, a scenario that loaded (the
// first by name: its message lists its parameters and the nearest), or "" when none did (their
// errors say why).
std::string undeclared_set_problem(const std::pair<std::string, std::string>& set, Scenario* first) {
  if (!first) return "";
  try {
    first->set_params({set});
  } catch (const std::exception& e) {
    return "--set " + set.first + "=" + set.second + ": no policy's scenario declares it; " + e.what();
  }
  return "";
}

}  // namespace

std::vector<std::string> check_skill_script(const std::string& path, const SandboxLimits& limits,
                                            std::optional<SkillScript>* loaded, const SetList& sets) {
  std::vector<std::string> problems;
  std::optional<SkillScript> own;
  std::optional<SkillScript>& script = loaded ? *loaded : own;
  try {
    script.emplace(SkillScript::load(path, limits));
  } catch (const std::exception& e) {
    problems.push_back(e.what());
    return problems;
  }
  // Each scenario loaded with a policy's params, and its worlds generated, once however many
  // policies play it so.
  struct Loaded {
    std::unique_ptr<Scenario> scenario;
    std::unique_ptr<QuietPrints> prints;  // its worlds' prints after the first (before the scenario goes)
    std::string error;   // why it did not load
    bool own = false;    // an error at the script's own line (the policy's params)
    bool worlds_failed = false;  // its worlds could not be made: said once, for the first policy
  };
  std::map<std::pair<std::string, std::vector<std::pair<std::string, std::string>>>, Loaded> loaded_scenarios;
  std::set<std::string> used_sets;  // the --set names some policy's scenario declares
  for (const auto& name : script->policy_names()) {
    const SkillScript::NamedPolicy& policy = script->policy(name);
    const std::string where = "policy '" + name + "': scenario '" + policy.scenario + "': ";
    auto [it, fresh] = loaded_scenarios.emplace(std::make_pair(policy.scenario, policy.params), Loaded{});
    Loaded& l = it->second;
    if (fresh) try {
        auto scenario = std::make_unique<Scenario>(script->scenario_of(policy, "", limits));
        set_declared(*scenario, sets, used_sets);  // a value it refuses leaves no scenario
        l.scenario = std::move(scenario);
        l.prints = std::make_unique<QuietPrints>(l.scenario->sandbox(), "roger check built the policy's worlds");
        if (const std::string problem = worlds_problem(*l.scenario, *l.prints); !problem.empty()) {
          problems.push_back(where + problem);
          l.worlds_failed = true;
          continue;
        }
      } catch (const ScriptError& e) {
        l.error = e.what();
        l.own = e.file == script->path();
      } catch (const std::exception& e) {
        l.error = e.what();
      }
    // Found by a probe: a world refused for the first policy was refused again, without the policy's
    // name, for each other policy playing the same scenario.
    if (l.worlds_failed) continue;
    if (!l.scenario) {
      problems.push_back(l.own ? l.error : where + l.error);
      continue;
    }
    if (const std::string problem = first_ticks_problem(*script, policy, *l.scenario); !problem.empty())
      problems.push_back(problem);
    else if (const std::string region = region_problem(*script, policy, *l.scenario); !region.empty())
      problems.push_back(region);
  }
  Scenario* first = nullptr;
  for (auto& [key, l] : loaded_scenarios)
    if (l.scenario && !first) first = l.scenario.get();
  for (const auto& set : sets)
    if (!used_sets.count(set.first))
      if (const std::string problem = undeclared_set_problem(set, first); !problem.empty()) problems.push_back(problem);
  return problems;
}

}  // namespace roger
