// check.cpp: `roger check`, a script validated without running an episode: the static pass, then
// the loader of the script's kind (a scenario's worlds generated and built, a curriculum's callbacks
// called, a batch script against its curriculum), or a module run as the scripts requiring it run it.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "cli/cli_internal.h"
#include "control/control.h"
#include "control/planner.h"
#include "control/primitives.h"
#include "cli/commands.h"
#include "core/fileio.h"
#include "core/text.h"
#include "script/authoring/lua_static_check.h"
#include "script/authoring/script_api.h"
#include "script/batch/batch_script.h"
#include "script/curriculum/curriculum.h"
#include "script/sandbox/lua_tokens.h"
#include "script/scenario/scenario.h"
#include "script/skills/skill_script.h"
#include "sim/world.h"

namespace roger {
namespace {

// The static pass (a misspelt roger.* member, an undefined global), before anything runs: prints
// each problem as file:line and returns their number. A bare name is the scenario it names, as
// for the loader below (scenarios/<name>.lua of the project or the installed tree); a name that
// is neither is left to the loader, which says what exists.
size_t report_static_problems(const std::string& script) {
  std::string path;
  try {
    path = resolve_scenario_path(script);
  } catch (const Error&) {
    return 0;
  }
  std::vector<std::string> warnings;
  const std::vector<StaticProblem> problems = static_check(path, script_kind_of(path), &warnings);
  for (const auto& p : problems) std::fprintf(stderr, "roger: error: %s\n", p.what().c_str());
  for (const auto& w : warnings) std::fprintf(stderr, "roger: warning: %s\n", w.c_str());
  return problems.size();
}

// World seeds a curriculum's or a batch script's check builds of a scenario for its parameters'
// reads (with each choice and range end): a few, since the scenario's own check tries its 20.
constexpr int kUnreadSeeds = 5;

// The declared parameters of each scenario that no world roger check builds of it reads, by
// scenario as a stage names it (answered once each).
using UnreadCache = std::map<std::string, std::vector<std::string>>;

const std::vector<std::string>& unread_params_of(const std::string& scenario_name, const SandboxLimits& limits,
                                                 UnreadCache& cache) {
  const auto known = cache.find(scenario_name);
  if (known != cache.end()) return known->second;
  std::vector<std::string>& names = cache[scenario_name];
  try {
    Scenario scenario = Scenario::load(scenario_name, limits);
    QuietPrints prints(scenario.sandbox(), "roger check built the scenario's worlds");
    prints.quiet();
    for (int seed = 0; seed < kUnreadSeeds; ++seed) scenario.generate(uint64_t(seed));
    check_scenario(scenario, 0);
    names = scenario.unread_params();
  } catch (const std::exception&) {
    names.clear();  // a scenario that fails is the other checks' to say
  }
  return names;
}

// A parameter a curriculum or a batch script sets or draws, with where it names it ("tasks.shape")
// and, when known, the file and line that do ("cur.lua:12").
struct NamedParam {
  std::string name, where, at;
};
using NamedParams = std::vector<NamedParam>;

// Warns of those of `named` that scenario `scenario_name` never reads: a teacher's draws of one, a
// context's value or a run's would change no world (the scenario's own warning, said where the
// script names it: at the first one's file and line when known). `who`: "stage 'S'", "run 'R'", ...
void warn_unread(const std::string& who, const std::string& scenario_name, const NamedParams& named,
                 const SandboxLimits& limits, UnreadCache& cache) {
  const std::vector<std::string>& unread = unread_params_of(scenario_name, limits, cache);
  std::vector<std::string> said;  // each as 'name' (where the script names it)
  std::string at;
  for (const NamedParam& p : named)
    if (std::binary_search(unread.begin(), unread.end(), p.name)) {
      said.push_back("'" + p.name + "' (" + p.where + ")");
      if (at.empty() && !p.at.empty()) at = p.at + ": ";
    }
  if (said.empty()) return;
  const std::string listed = listed_with_and(said);
  std::fprintf(stderr,
               "roger: warning: %s%s: scenario '%s' never reads the parameter%s %s, in any world roger check builds of "
               "it (world seeds 0 to %d, and each choice and range end): setting %s changes no world\n",
               at.c_str(), who.c_str(), scenario_name.c_str(), said.size() == 1 ? "" : "s", listed.c_str(),
               kUnreadSeeds - 1, said.size() == 1 ? "it" : "them");
}

// A stage's task axes, its params and its contexts' params that its scenario never reads: an axis
// at its line, the others at the stage's (found by a probe: the warning had no file:line, where the
// teacher's beside it had).
void warn_unread_in_stage(const CurriculumStage& st, const SandboxLimits& limits, UnreadCache& cache) {
  const auto at = [](const std::string& file, int line) {
    return file.empty() || line <= 0 ? std::string() : file + ":" + std::to_string(line);
  };
  NamedParams named;
  for (const TaskDim& d : st.tasks.dims()) named.push_back({d.name, "tasks." + d.name, at(d.file, d.line)});
  for (const auto& [k, v] : st.params) named.push_back({k, "params." + k, at(st.file, st.line)});
  for (const auto& ctx : st.contexts)
    for (const auto& [k, v] : ctx.params)
      named.push_back({k, "context " + ctx.name + "'s params." + k, at(st.file, st.line)});
  warn_unread(st.where(), st.scenario, named, limits, cache);
}

// A batch script's runs' and evaluations' params that the scenario they play never reads (a sweep
// over one trains every run on the same worlds).
void warn_unread_in_batch(const BatchScript& b) {
  const Curriculum cur = Curriculum::load(b.curriculum_file, b.limits);
  UnreadCache cache;
  auto scenario_of = [&](const std::string& stage) -> const CurriculumStage* {
    for (const auto& st : cur.stages())
      if (st.name == stage) return &st;
    return nullptr;
  };
  auto named = [](const Params& params) {
    NamedParams out;
    for (const auto& [k, v] : params) out.push_back({k, "params." + k, ""});
    return out;
  };
  for (const BatchRun& r : b.runs)
    if (const CurriculumStage* st = scenario_of(r.stage))
      warn_unread("run '" + r.name + "'", st->scenario, named(r.params), b.limits, cache);
  for (const BatchEvaluation& e : b.evaluations) {
    std::string scenario = e.scenario;
    for (const BatchRun& r : b.runs)
      if (scenario.empty() && r.name == e.run)
        if (const CurriculumStage* st = scenario_of(r.stage)) scenario = st->scenario;
    if (!scenario.empty()) warn_unread("evaluation '" + e.name + "'", scenario, named(e.params), b.limits, cache);
  }
}

}  // namespace

std::string listed_with_and(const std::vector<std::string>& items) {
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) out += (i == 0 ? "" : i + 1 == items.size() ? " and " : ", ") + items[i];
  return out;
}

std::vector<std::string> unread_sets_in_batch(const BatchScript& b, const Params& sets) {
  if (sets.empty()) return {};
  const Curriculum cur = Curriculum::load(b.curriculum_file, b.limits);
  UnreadCache cache;
  std::map<std::pair<std::string, std::string>, std::vector<std::string>> runs_of;  // (set, scenario) -> runs
  std::vector<std::pair<std::string, std::string>> order;
  for (const BatchRun& r : b.runs)
    for (const CurriculumStage& st : cur.stages()) {
      if (st.name != r.stage) continue;
      const std::vector<std::string>& unread = unread_params_of(st.scenario, b.limits, cache);
      for (const auto& set : sets) {
        if (!std::binary_search(unread.begin(), unread.end(), set.first)) continue;
        auto& runs = runs_of[{set.first, st.scenario}];
        if (runs.empty()) order.push_back({set.first, st.scenario});
        runs.push_back(r.name);
      }
    }
  std::vector<std::string> out;
  for (const auto& key : order) {
    const std::vector<std::string>& runs = runs_of[key];
    out.push_back("--set " + key.first + " changes no world of run" + (runs.size() == 1 ? " " : "s ") +
                  listed_with_and(runs) + ": scenario '" + key.second + "' never reads it, in any world roger check "
                  "builds of it (world seeds 0 to " + std::to_string(kUnreadSeeds - 1) +
                  ", and each choice and range end)");
  }
  return out;
}

namespace {

// Each run's stage of the curriculum checked as its trials train it: with the run's parameters
// and the command's --set (check_curriculum: the ends of its task space, its test tasks), runs of
// the same parameters together. Prints each problem; returns their number.
size_t check_runs_stages(const BatchScript& b, const ParamList& sets) {
  // Each stage with each set of params once, named by the first run that trains it so (found by a
  // probe: grouped by params alone, a stage's refusal named a run of another stage, and a value
  // given by --set was blamed on a run's params).
  std::map<std::pair<Params, std::string>, std::string> first_run;
  for (const BatchRun& r : b.runs) first_run.emplace(std::make_pair(r.params, r.stage), r.name);
  size_t count = 0;
  for (const auto& [params_stage, run] : first_run) {
    const std::string fixed_by = "the params of run '" + run + "'" + (sets.empty() ? "" : " or --set");
    for (const std::string& p :
         check_curriculum(b.curriculum_file, b.limits, params_stage.first, {params_stage.second}, fixed_by)) {
      std::fprintf(stderr, "roger: error: %s\n", p.c_str());
      ++count;
    }
  }
  return count;
}

// roger check on a batch script: loads it and validates it against its curriculum, with the
// command's --set as roger run takes them. `shown`: the script as the command line named it.
int check_batch(const std::string& path, const std::string& shown, const LuaLimitArgs& lua, const ParamList& sets) {
  BatchOverrides overrides;
  overrides.sets = sets;
  overrides.instructions = lua.instructions;
  overrides.memory_mib = lua.memory_mib;
  BatchProblems problems;
  const BatchScript b = check_batch_script(path, overrides, problems);
  for (const ScriptError& e : problems.errors) std::fprintf(stderr, "roger: error: %s\n", e.what());
  if (!problems.unchecked.empty())
    std::fprintf(stderr, "roger: note: not checked, since %s a run or an evaluation that was not read: %s\n",
                 problems.unchecked.size() == 1 ? "it names" : "each names", join(problems.unchecked).c_str());
  if (!problems.errors.empty()) return 1;
  if (!b.curriculum_warning.empty()) std::fprintf(stderr, "roger: warning: %s\n", b.curriculum_warning.c_str());
  for (const std::string& n : b.notes) std::fprintf(stderr, "roger: note: %s\n", n.c_str());
  // The curriculum it runs, as `roger check CURRICULUM` reads it (found by a probe: a curriculum
  // whose check failed on an undefined global passed as its batch script's).
  std::error_code ec;
  const std::filesystem::path here = std::filesystem::relative(b.curriculum_file, ec);
  const bool below = !ec && !here.empty() && *here.begin() != "..";
  if (report_static_problems(below ? here.string() : b.curriculum_file) > 0) return 1;
  if (check_runs_stages(b, sets) > 0) return 1;
  warn_unread_in_batch(b);
  std::string runs;
  for (const auto& r : b.runs) {
    const size_t n = r.contexts.size();
    runs += (runs.empty() ? "" : ", ") + r.name + " (" + std::to_string(n) + (n == 1 ? " context)" : " contexts)");
  }
  const SandboxLimits defaults;
  std::string limits;
  if (b.limits.instructions != defaults.instructions || b.limits.memory_bytes != defaults.memory_bytes)
    limits = "; Lua limits " + std::to_string(b.limits.instructions) + " instructions, " +
             std::to_string(b.limits.memory_bytes >> 20) + " MiB";
  std::printf("%s: ok (batch script '%s' on %s; %d trial%s; runs %s%s)\n", shown.c_str(), b.name.c_str(),
              b.curriculum.c_str(), b.trials, b.trials == 1 ? "" : "s", runs.c_str(), limits.c_str());
  // Where roger run writes without --out: scripts/slurm/submit.sh reads this line, so that its
  // jobs write where roger run would (the script's name, not its file's).
  std::printf("  results folder: results/%s (roger run's default --out)\n", b.name.c_str());
  return 0;
}

}  // namespace


namespace {

// The file `roger check` checks: the path as given, else a path relative to the project (as the
// other commands take `curricula/paper.lua` from any folder), else a bare name of the project's
// scenarios/ (first, as check has always read a bare name), curricula/ or scripts/. A name that is
// none of them is refused as a script of any kind, not as a missing scenario.
std::string check_target(const std::string& arg) {
  namespace fs = std::filesystem;
  std::error_code ec;
  // A bare name is a file here, not a folder (found by a probe: after `roger run quick --out quick`,
  // `roger check quick` read the results folder, where roger run takes scripts/quick.lua).
  if (fs::is_regular_file(arg, ec) || (fs::exists(arg, ec) && arg.find('/') != std::string::npos)) return arg;
  if (arg.empty()) throw Error("no script given: the name is empty");
  if (arg.find('/') != std::string::npos) {
    if (fs::path(arg).is_relative() && fs::is_regular_file(project_root() / arg, ec))
      return (project_root() / arg).string();
    // A missing file: said as a script's (found by a probe: a curriculum's mistyped path was "no
    // scenario", the kind the check falls back to), with the folder's nearest name: the project's
    // folder where there is none here, as the path is looked for there too (found by a probe:
    // curricula/pape.lua from another folder said "no folder curricula either").
    fs::path folder = fs::path(arg).parent_path();
    if (!fs::is_directory(folder, ec) && folder.is_relative() && fs::is_directory(project_root() / folder, ec))
      folder = project_root() / folder;
    std::vector<std::string> beside;
    for (const auto& entry : fs::directory_iterator(folder, ec))
      if (entry.path().extension() == ".lua") beside.push_back(entry.path().filename().string());
    throw Error("no script '" + arg + "': no such file here or in the project" +
                (fs::is_directory(folder, ec) ? suggestion(fs::path(arg).filename().string(), beside)
                                              : " (no folder " + fs::path(arg).parent_path().string() + " either)") +
                installed_docs_hint(arg));
  }
  const std::string file = fs::path(arg).extension() == ".lua" ? arg : arg + ".lua";
  std::vector<std::string> found;
  for (const char* folder : {"scenarios", "curricula", "scripts"})
    if (fs::is_regular_file(project_root() / folder / file, ec)) found.push_back(std::string(folder) + "/" + file);
  if (!found.empty()) {
    // A bare name that several folders hold (paper: curricula/paper.lua and scripts/paper.lua) is
    // the first; say so, and how to name the others.
    if (found.size() > 1) {
      std::string others;
      for (size_t k = 1; k < found.size(); ++k) others += (k > 1 ? " or " : "") + found[k];
      std::fprintf(stderr, "roger: note: '%s' is the project's %s; to check %s, name it so\n", arg.c_str(),
                   found[0].c_str(), others.c_str());
    }
    return (project_root() / found[0]).string();
  }
  // Found by a probe: `roger check .` spoke of the project's scenarios/..lua, and a folder named
  // dir.lua here was "not a file here". (A project script of the name comes first, as above.)
  if (fs::is_directory(arg, ec))
    throw Error("'" + arg + "' is a folder here, not a script, and the project has no script of that name: give one "
                "script");
  const std::string here = lua_file_here(arg);
  throw Error("no script '" + arg + "': not a file here, and the project has no scenarios/" + file + ", curricula/" +
              file + " or scripts/" + file + " (project: " + project_in_use() + ")" +
              (here.empty() ? "" : "; " + here + " is a file here: name it with its \".lua\" (roger check " + here + ")"));
}

// The kind a script whose table names none of the keys that tell kinds apart (a misspelt
// `stagez`, `policy`) is checked as, so that the loader says which field is unknown, with the
// nearest one: a curriculum when it or a module it requires builds stages, a skill script when
// they build controllers, else a scenario, as before. The modules count (found by a probe: a
// script copying require("paper")'s table ran as a scenario, and lib.skills failed inside).
// Read from the tokens, so that a comment or a string naming roger.stage decides nothing (found by a
// probe: a scenario's comment "its roger.stage{...} trains here" ran it as a curriculum).
std::optional<ScriptKind> guessed_kind(const std::string& path) {
  std::set<std::string> words;  // "roger.X" as code, and string literals ("lib.skills")
  for (const std::filesystem::path& file : required_files(path)) try {
      const std::vector<LuaToken> t = lua_tokenize(read_file_text(file.string()));
      for (size_t i = 0; t[i].type != LuaToken::kEnd; ++i) {
        if (t[i].type == LuaToken::kString) words.insert(t[i].text);
        if (t[i].type == LuaToken::kName && t[i].text == "roger" && t[i + 1].type == LuaToken::kOp &&
            t[i + 1].text == "." && t[i + 2].type == LuaToken::kName)
          words.insert("roger." + t[i + 2].text);
      }
    } catch (const Error&) {
      // unreadable: the loader says so
    }
  const auto any_has = [&](const char* word) { return words.count(word) > 0; };
  if (any_has("roger.stage") || any_has("roger.learned")) return ScriptKind::kCurriculum;
  // The control API's functions, predicates among them (found by a probe: a skill script whose
  // goal was roger.converged(...) and whose 'policies' was misspelt ran as a scenario, where
  // roger.converged is nil).
  for (const char* builder : {"lib.skills", "roger.primitive", "roger.sequence", "roger.compose", "roger.subject_to",
                              "roger.policy", "roger.bind", "roger.converged", "roger.gamma", "roger.held",
                              "roger.all", "roger.any", "roger.negate", "roger.sorted"})
    if (any_has(builder)) return ScriptKind::kSkillScript;
  return std::nullopt;
}

}  // namespace

namespace {

// The project's scripts that may require a module at `path`: every .lua file of the project's
// scenarios/, curricula/ and scripts/ trees, and of the module's folder and the one above it (a
// script beside lib/ requires lib.x), each once, the module itself left out.
std::vector<std::filesystem::path> possible_requirers(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path module = fs::weakly_canonical(path, ec);
  std::vector<fs::path> out;
  auto add = [&](const fs::path& file) {
    const fs::path f = fs::weakly_canonical(file, ec);
    if (f.extension() == ".lua" && f != module && std::find(out.begin(), out.end(), f) == out.end()) out.push_back(f);
  };
  for (const fs::path& folder : {module.parent_path(), module.parent_path().parent_path()})
    for (const auto& e : fs::directory_iterator(folder, ec)) add(e.path());
  for (const char* tree : {"scenarios", "curricula", "scripts"})
    for (const auto& e : fs::recursive_directory_iterator(project_root() / tree, ec)) add(e.path());
  return out;
}

// The kinds a module is run as, most likely first: that of the script it is run for, then that of
// the project folder it lies in (scenarios/lib is the scenarios' library), then every kind.
std::vector<ScriptKind> module_kinds(const std::filesystem::path& module, std::optional<ScriptKind> user_kind) {
  std::vector<ScriptKind> kinds;
  auto add = [&](std::optional<ScriptKind> k) {
    if (k && std::find(kinds.begin(), kinds.end(), *k) == kinds.end()) kinds.push_back(*k);
  };
  add(user_kind);
  std::error_code ec;
  const std::string where = std::filesystem::weakly_canonical(module, ec).string();
  if (where.find("/scenarios/") != std::string::npos) add(ScriptKind::kScenario);
  if (where.find("/curricula/") != std::string::npos) add(ScriptKind::kCurriculum);
  for (ScriptKind k : script_kinds()) add(k);
  return kinds;
}

// What a module returned, in words: a table's fields, at most eight named.
std::string returned_summary(const ModuleValue& v) {
  // require gives true for a module that returns nothing (found by a probe: "it returns boolean").
  if (v.type == "boolean") return "it returns a boolean (or nothing: require then gives true)";
  if (v.type != "table") return "it returns a " + v.type;
  const size_t n = v.keys.size(), shown = std::min<size_t>(n, 8);
  std::string out = "it returns a table of " + std::to_string(n) + (n == 1 ? " field" : " fields");
  if (n == 0) return out;
  out += ": " + join(std::vector<std::string>(v.keys.begin(), v.keys.begin() + long(shown)), ", ");
  if (n > shown) out += ", and " + std::to_string(n - shown) + " more";
  return out;
}

// `roger check` of a module: a file scripts require, or one in a lib/ folder. Its loader is its
// user's: it is run once as a script requiring it runs it (one of a known kind, if any), under that
// script's kind, else under each kind until one runs it. A module is no scenario, curriculum or
// batch script, so its table's fields are listed, not judged: the scripts requiring it check how
// they are used.
int check_module(const std::string& path, const std::string& shown, const std::vector<ModuleUse>& users,
                 const SandboxLimits& limits) {
  const LuaSandbox namer;  // shows files as the loaders' messages do
  std::string used_by;
  for (size_t i = 0; i < users.size() && i < 3; ++i) used_by += (i ? ", " : "") + namer.display_name(users[i].script);
  if (users.size() > 3) used_by += " and " + std::to_string(users.size() - 3) + " more";
  const ModuleUse* user = users.empty() ? nullptr : &users.front();
  for (const auto& u : users)
    if (script_kind_of(u.script.string())) {
      user = &u;
      break;
    }
  const std::optional<ScriptKind> user_kind = user ? script_kind_of(user->script.string()) : std::nullopt;
  std::optional<ScriptError> first_error;
  for (ScriptKind kind : module_kinds(path, user_kind)) {
    try {
      const ModuleValue value = user ? run_module(path, kind, user->script.string(), user->name, limits)
                                     : run_module(path, kind, "", "", limits);
      std::string how = user ? "required as \"" + user->name + "\" by " + namer.display_name(user->script) : "run";
      if (kind != user_kind) how += std::string(" with a ") + script_kind_name(kind) + "'s API";
      std::printf("%s: ok (a module: %s, %s)\n", shown.c_str(), how.c_str(), returned_summary(value).c_str());
      if (users.empty())
        std::printf("  no script of the project or beside it requires it; checking one that does checks its use\n");
      else
        std::printf("  required by %s; checking %s checks its use\n", used_by.c_str(),
                    users.size() == 1 ? "it" : "them");
      return 0;
    } catch (const ScriptError& e) {
      if (!first_error) first_error = e;
    }
  }
  throw *first_error;
}

// Whether a script of no kind is a module: something requires it, or it lies in a lib/ folder.
bool is_module(const std::string& path, const std::vector<ModuleUse>& users) {
  return !users.empty() || std::filesystem::path(path).parent_path().filename() == "lib";
}

}  // namespace

// Found by a probe: roger run of a batch script's module said "unknown field 'all'" of the batch
// script it took it for, where roger check knew it for a module.
std::string module_given(const std::string& given, const std::string& path, const std::string& wanted) {
  if (script_kind_of(path)) return "";
  const std::vector<ModuleUse> users = module_users(path, possible_requirers(path));
  if (!is_module(path, users)) return "";
  const LuaSandbox namer;  // shows files as the loaders' messages do
  if (users.empty()) return given + " is a module (it lies in a lib/ folder), not a " + wanted + ": give the " +
                            wanted + " that requires it";
  const ModuleUse& u = users.front();
  return given + " is a module, not a " + wanted + ": required as \"" + u.name + "\" by " + namer.display_name(u.script) +
         ":" + std::to_string(u.line) + "; give " + (users.size() == 1 ? "that script" : "the script that requires it") +
         " (roger check " + given + " checks the module)";
}

// phi1 {goal = "region"} plans to the free cells of its static grid (walls and obstacles grown by
// the body's footprint) within the region's radius less phi1's margin of its centre, and has no
// reference where there are none (found by a probe: a goal 0.2 m from a wall passed check, and
// every episode failed at "no reference", the note naming other causes).
std::string goal_out_of_reach(const WorldModel& model) {
  static const double margin = make_primitive("phi1")->number("margin");
  HarmonicPlanner planner;  // its own goal cells, as the navigator sets them
  planner.set_grid(model.grid);
  for (const GoalRegion& goal : model.spec.goals) {
    const double reach = std::max(0.5 * model.grid.cell, goal.radius - margin);  // Navigate::prepare_region's
    planner.set_goal(goal.center, reach);
    if (planner.goal_cells() > 0) continue;
    return "goal '" + goal.name + "' at (" + format_number(goal.center.x()) + ", " +
           format_number(goal.center.y()) + ") lies where Roger's base cannot go: no point within " + format_number(reach) +
           " m of its centre (its radius less phi1's margin, " + format_number(margin) + " m) is " +
           format_number(model.grid_inflate) + " m clear of the walls and obstacles (the planner's growth for " +
           "this body), so phi1 {goal = \"region\"} has no reference there; move the goal inward, or make it larger";
  }
  return "";
}

namespace {

// A curriculum checked with --set: each parameter on the stages whose scenario declares it, as
// `roger train --stage` takes it for those (found by a probe: --set objects=3 on the sorting
// curriculum was refused for SG, whose scenario has no objects parameter). A parameter that no
// stage's scenario declares goes to the first stage, whose scenario refuses it with its suggestions.
// Says on stderr which stages a parameter skipped.
std::vector<std::string> check_curriculum_sets(Curriculum& cur, const SandboxLimits& limits, const ParamList& sets) {
  std::vector<std::pair<std::string, ParamList>> plan;  // stage -> the sets its scenario declares
  std::map<std::string, std::vector<std::string>> skipped;  // parameter -> the stages without it
  try {
    std::map<std::string, std::set<std::string>> declared;  // scenario -> its parameters
    for (const auto& st : cur.stages()) {
      if (!declared.count(st.scenario))
        for (const auto& p : Scenario::load(st.scenario, limits).params()) declared[st.scenario].insert(p.name);
      plan.push_back({st.name, {}});
    }
    for (const auto& [k, v] : sets) {
      const std::string& key = k;  // a lambda may not capture a structured binding (C++17)
      const bool anywhere = std::any_of(cur.stages().begin(), cur.stages().end(),
                                        [&](const CurriculumStage& st) { return declared[st.scenario].count(key) > 0; });
      for (size_t i = 0; i < plan.size(); ++i) {
        const CurriculumStage& st = cur.stages()[i];
        if (declared[st.scenario].count(k) || (!anywhere && i == 0)) plan[i].second.push_back({k, v});
        else skipped[k].push_back(st.name);
      }
    }
  } catch (const std::exception&) {
    return check_curriculum(cur, limits, sets);  // a scenario's error, as check_curriculum words it
  }
  // Stages of the same parameters in one check (each check loads the curriculum), groups in the order
  // of their first stage.
  std::vector<std::pair<ParamList, std::vector<std::string>>> groups;
  for (const auto& stage : plan) {  // not a structured binding: the lambda captures it
    auto it = std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first == stage.second; });
    if (it == groups.end()) it = groups.insert(groups.end(), {stage.second, {}});
    it->second.push_back(stage.first);
  }
  std::vector<std::string> problems;
  for (const auto& [group_sets, stages] : groups)
    for (const auto& p : check_curriculum(cur, limits, group_sets, stages)) problems.push_back(p);
  for (const auto& [k, stages] : skipped)
    if (problems.empty())
      std::fprintf(stderr, "roger check: --set %s not checked on stage%s %s, whose scenario has no such parameter\n",
                   k.c_str(), stages.size() == 1 ? "" : "s", join(stages).c_str());
  return problems;
}

// A stage whose worlds (five, of each context's parameters) have no object of the colour the eyes
// look for: a warning, as roger check says it of the scenario itself (found by a probe: a colour
// typo in the scenario passed the curriculum's check, and training blamed its absorbing function).
void warn_stimulus_unseen(const CurriculumStage& st, const SandboxLimits& limits, const ParamList& sets) {
  std::set<std::vector<std::pair<std::string, std::string>>> checked;
  for (const auto& ctx : st.contexts) {
    if (!checked.insert(st.scenario_params(ctx)).second) continue;
    // A --set the scenario does not declare is for other stages.
    const std::string note = stimulus_unseen_in(st.scenario, st.scenario_params(ctx), limits, 0, 5, sets);
    if (!note.empty())
      std::fprintf(stderr, "roger: warning: %s (scenario '%s'): %s\n",
                   (ctx.params.empty() ? st.where() : st.where(ctx.name)).c_str(), st.scenario.c_str(), note.c_str());
  }
}

// "  sequences: Phi6 2 steps, Phi7 2 steps\n" for each sequence reached from `roots` (once, in the
// order met), or "" when none is: a nil at the end of a step list (a misspelt field of one's own
// table) leaves no hole to refuse, and shows here as one step fewer (found by a probe).
std::string sequence_steps(const std::vector<const Controller*>& roots) {
  std::set<const Controller*> seen;
  std::string listed;
  std::function<void(const Controller*)> visit = [&](const Controller* c) {
    if (!c || !seen.insert(c).second) return;
    if (const auto* sequence = dynamic_cast<const Sequence*>(c)) {
      const size_t n = sequence->steps().size();
      listed += (listed.empty() ? "" : ", ") + c->name() + " " + std::to_string(n) + (n == 1 ? " step" : " steps");
    }
    for (const Controller* child : c->children()) visit(child);
  };
  for (const Controller* root : roots) visit(root);
  return listed.empty() ? "" : "  sequences: " + listed + "\n";
}

// A curriculum: its stages' callbacks called once each (check_curriculum), then its stages listed.
int check_curriculum_file(const std::string& path, const std::string& shown, const SandboxLimits& limits,
                          const ParamList& sets) {
  // Loaded once: its top level runs once (a curriculum that prints printed it twice).
  std::optional<Curriculum> loaded;
  try {
    loaded.emplace(Curriculum::load(path, limits));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "roger: error: %s\n", e.what());
    return 1;
  }
  Curriculum& cur = *loaded;
  const std::vector<std::string> problems =
      sets.empty() ? check_curriculum(cur, limits) : check_curriculum_sets(cur, limits, sets);
  for (const auto& p : problems) std::fprintf(stderr, "roger: error: %s\n", p.c_str());
  if (!problems.empty()) return 1;
  std::string stages;
  UnreadCache unread;
  std::set<std::string> scenarios;  // each stage's scenario, its generator's purity checked once
  for (const auto& st : cur.stages()) {
    if (scenarios.insert(st.scenario).second && !st.contexts.empty()) {
      // In its first context's world (the checks above built it); a world that cannot be built
      // here is said where it is built.
      std::string impure, path;
      try {
        Scenario scenario = Scenario::load(st.scenario, limits);
        path = scenario.path();
        for (const auto& [k, v] : st.scenario_params(st.contexts.front())) scenario.set_param(k, v);
        QuietPrints prints(scenario.sandbox(), "roger check built the world again");
        prints.quiet();
        impure = scenario.impurity(0);
      } catch (const std::exception&) {
      }
      if (!impure.empty()) {
        std::fprintf(stderr, "roger: error: %s%s: scenario '%s' (%s): %s\n", st.written_at().c_str(),
                     st.where().c_str(), st.scenario.c_str(), path.c_str(), impure.c_str());
        return 1;
      }
    }
    // What loads and trains, but not as its writer meant: a teacher that cannot move within the
    // budget, a scenario path found only from this folder, exploration that rises.
    for (const std::string& w : {st.teacher_window_warning(), st.scenario_warning(), st.learner_warning()})
      if (!w.empty()) std::fprintf(stderr, "roger: warning: %s\n", w.c_str());
    if (const std::string n = st.scenario_note(); !n.empty()) std::fprintf(stderr, "roger: note: %s\n", n.c_str());
    warn_stimulus_unseen(st, limits, sets);
    warn_unread_in_stage(st, limits, unread);
    std::string contexts;
    for (const auto& c : st.contexts) contexts += (contexts.empty() ? "" : " ") + c.name;
    stages += (stages.empty() ? "" : "; ") + st.name + ": " + contexts;
  }
  std::printf("%s: ok (curriculum '%s'; stages %s)\n", shown.c_str(), cur.name().c_str(), stages.c_str());
  // Each context's count of actions: a nil at the end of an action list (a name misspelt in a
  // table's field) leaves no hole for the load to refuse, but shows here as one action fewer.
  for (const auto& st : cur.stages()) {
    std::string counts;
    for (const auto& c : st.contexts)
      counts += (counts.empty() ? "" : ", ") + c.name + " " + std::to_string(c.actions.size()) +
                (c.actions.size() == 1 ? " action" : " actions");
    std::printf("  %s: %s\n", st.name.c_str(), counts.c_str());
  }
  std::vector<const Controller*> actions;
  for (const auto& st : cur.stages())
    for (const auto& c : st.contexts)
      for (const auto& a : c.actions) actions.push_back(a.get());
  std::printf("%s", sequence_steps(actions).c_str());
  return 0;
}

// A skill script: each policy's controllers built, then its policies listed.
int check_skill_script_file(const std::string& path, const std::string& shown, const SandboxLimits& limits,
                            const ParamList& sets) {
  std::optional<SkillScript> loaded;
  const std::vector<std::string> problems = check_skill_script(path, limits, &loaded, sets);
  for (const auto& p : problems) std::fprintf(stderr, "roger: error: %s\n", p.c_str());
  if (!problems.empty()) return 1;
  const SkillScript& script = *loaded;
  std::string names;
  for (const auto& n : script.policy_names()) names += (names.empty() ? "" : ", ") + n;
  std::printf("%s: ok (skill script '%s'; policies: %s)\n", shown.c_str(), script.name().c_str(), names.c_str());
  std::vector<const Controller*> controllers;
  for (const ControllerPtr& c : script.controllers()) controllers.push_back(c.get());
  std::printf("%s", sequence_steps(controllers).c_str());
  return 0;
}

// A declared parameter that no generate read, over every world roger check built (each seed, and
// each choice and range end): setting it changes no world (found by a probe: a scenario declared
// `clutter` and placed its obstacles from `obstacles`, and a sweep over clutter trained on the same
// worlds at every level without a word).
void warn_unread_params(Scenario& scenario, int seeds) {
  const std::vector<std::string> unread = scenario.unread_params();
  if (unread.empty()) return;
  std::vector<std::string> quoted;
  for (const std::string& name : unread) quoted.push_back("'" + name + "'");
  const std::string names = listed_with_and(quoted);
  const char* it = unread.size() == 1 ? "it" : "them";
  std::fprintf(stderr,
               "roger: warning: generate never reads the parameter%s %s (world seeds 0 to %d, and each choice and "
               "range end, tried): setting %s changes no world; read %s from generate's params, or remove %s\n",
               unread.size() == 1 ? "" : "s", names.c_str(), seeds - 1, it, it, it);
}

// The range ends check_scenario could not build, each without Lua's traceback (the value and the
// line say it); those of noise parameters the world's Roger does not follow, one cause, said once
// (found by a probe: a generator that did not pass body.noise_of(params) got 40 warnings).
void warn_range_ends(const std::vector<std::string>& range_ends) {
  std::vector<std::string> unfollowed;  // "noise_base=1 (its max)"
  std::string where;                    // the generator's file and line the message names
  for (const auto& w : range_ends) {
    const std::string text = w.substr(0, w.find("\nstack traceback:"));
    const size_t seed = text.find(", seed ");
    const size_t at = seed == std::string::npos ? seed : text.find(": ", seed);
    if (text.find("body.noise_of(params) to world:robot{ noise = ... }") == std::string::npos || at == std::string::npos) {
      std::fprintf(stderr, "roger: warning: at a range's end: %s\n", text.c_str());
      continue;
    }
    unfollowed.push_back(text.substr(0, seed));
    if (where.empty()) where = text.substr(at + 2, text.find(": ", at + 2) - (at + 2));
  }
  if (unfollowed.empty()) return;
  constexpr size_t kNamed = 3;
  std::string named;
  for (size_t i = 0; i < std::min(kNamed, unfollowed.size()); ++i) named += (i ? ", " : "") + unfollowed[i];
  if (unfollowed.size() > kNamed) named += " and " + std::to_string(unfollowed.size() - kNamed) + " more";
  std::fprintf(stderr,
               "roger: warning: %s: at %s of the noise parameters (%s) the world's Roger has other noise than they "
               "ask for: its generator sets the noise itself rather than passing body.noise_of(params) to "
               "world:robot{ noise = ... } (scenarios/lib/body.lua); pass it, or leave the noise parameters at their "
               "defaults\n",
               where.c_str(), counted(int(unfollowed.size()), "range end").c_str(), named.c_str());
}

// A scenario: its worlds generated and built for seeds 0..N-1, then (without --set) every declared
// parameter choice and each end of every declared range.
int check_scenario_file(const CheckArgs& a, const std::string& shown, const SandboxLimits& limits) {
  Scenario scenario = Scenario::load(a.script, limits);
  apply_sets(scenario, a.sets);
  // A print in generate runs once per world built here: shown for the first world (seed 0), only
  // counted for the others.
  QuietPrints prints(scenario.sandbox(), "roger check built the other worlds");
  // A scenario is a function of its seed: try several, and build each world as an episode would.
  World world;
  // A failure names its seed after the first line, as training does: it may hold for some seeds only.
  std::vector<int> unseen;  // seeds whose objects none has the stimulus colour
  std::string unseen_text;
  std::vector<int> unreachable;  // seeds with a goal region the navigator cannot reach
  std::string unreachable_text;
  for (int seed = 0; seed < a.seeds; ++seed) {
    if (seed == 1) prints.quiet();
    try {
      const WorldSpec spec = scenario.generate(uint64_t(seed));
      if (const std::string text = stimulus_unseen(spec); !text.empty()) {
        if (unseen.empty()) unseen_text = text;
        unseen.push_back(seed);
      }
      world.reset(spec);
      if (const std::string text = goal_out_of_reach(world.model()); !text.empty()) {
        if (unreachable.empty()) unreachable_text = text;
        unreachable.push_back(seed);
      }
    } catch (const std::exception& e) {
      throw Error(with_note_on_first_line(e.what(), " (world seed " + std::to_string(seed) + ")"));
    }
  }
  // Found by a probe: a generator counting its calls in a global passed, and a seed's world
  // depended on the worlds built before it.
  if (const std::string impure = scenario.impurity(0); !impure.empty()) {
    std::fprintf(stderr, "roger: error: %s: %s\n", scenario.path().c_str(), impure.c_str());
    return 1;
  }
  // Found by a probe: a blue stimulus over a red ball passed, and every episode failed at search.
  if (!unseen.empty())
    std::fprintf(stderr, "roger: warning: in %d of %d worlds (the first: seed %d) %s\n", int(unseen.size()), a.seeds,
                 unseen.front(), unseen_text.c_str());
  if (!unreachable.empty())
    std::fprintf(stderr, "roger: warning: in %d of %d worlds (the first: seed %d) %s\n", int(unreachable.size()),
                 a.seeds, unreachable.front(), unreachable_text.c_str());
  // Without --set, also every declared choice of every parameter (each shape, say), and each end
  // of every declared range (the most obstacles, the longest arm): those are warnings, since an
  // end may hold only with other parameters changed too.
  std::vector<std::string> range_ends;
  if (a.sets.empty()) {
    prints.quiet();
    const std::vector<std::string> problems = check_scenario(scenario, 0, &range_ends);
    if (!problems.empty()) {
      for (const auto& p : problems) std::fprintf(stderr, "roger: error: %s\n", p.c_str());
      return 1;
    }
    warn_range_ends(range_ends);
    warn_unread_params(scenario, a.seeds);
  }
  prints.finish();
  // What eval and render note of the --set (found by a probe: a dropout that noise_scale carries
  // past 1, held at 1, was noted there and not here).
  if (const std::string noise = noise_sets_note(scenario_param_values(scenario), a.sets); !noise.empty())
    std::fprintf(stderr, "roger: warning: %s\n", noise.c_str());
  std::string tried;
  if (a.sets.empty())
    tried = ", every parameter choice and range end tried" +
            (range_ends.empty() ? std::string() : "; " + counted(int(range_ends.size()), "range end") +
                                                      " could not be built (warnings above)");
  std::printf("%s: ok (scenario '%s', %s generated and built%s)\n", shown.c_str(), scenario.name().c_str(),
              counted(a.seeds, "seed").c_str(), tried.c_str());
  return 0;
}

}  // namespace

static int check_named_script(const CheckArgs& args);

// Every check that passes names the project folder its bare names and require came from. Several
// scripts are each checked, a problem in one not stopping the others (roger check curricula/*.lua).
int command_check(const CheckArgs& args) {
  if (args.scripts.size() == 1) {
    CheckArgs one = args;
    one.script = args.scripts[0];
    const int status = check_named_script(one);
    if (status == 0) std::printf("  (project folder: %s)\n", project_in_use().c_str());
    return status;
  }
  int failed = 0;
  for (const std::string& script : args.scripts) {
    CheckArgs one = args;
    one.script = script;
    int status = 1;
    try {
      status = check_named_script(one);
    } catch (const std::exception& e) {
      std::fflush(stdout);
      std::fprintf(stderr, "%s\n", error_line(e.what()).c_str());
    }
    std::fflush(stderr);
    failed += status != 0;
  }
  if (failed == 0) std::printf("roger check: all %zu scripts ok (project folder: %s)\n", args.scripts.size(), project_in_use().c_str());
  else std::printf("roger check: %d of %zu scripts have problems (above)\n", failed, args.scripts.size());
  return failed ? 1 : 0;
}

static int check_named_script(const CheckArgs& args) {
  CheckArgs a = args;
  a.script = check_target(args.script);
  if (report_static_problems(a.script) > 0) return 1;
  const SandboxLimits limits = sandbox_limits(a.lua);
  if (!script_kind_of(a.script)) {
    const std::vector<ModuleUse> users = module_users(a.script, possible_requirers(a.script));
    if (is_module(a.script, users)) {
      // Found by a newcomer: --set on a module was ignored, and the check said ok.
      if (!a.sets.empty())
        throw Error("roger check: --set sets a scenario's parameters, and " + args.script +
                    " is a module, which has none: check the scenario, skill script or curriculum that requires "
                    "it with the --set instead");
      return check_module(a.script, args.script, users, limits);
    }
    // Not a module: its loader throws what is unknown, with the nearest field; one that loads is
    // checked as that kind (found by a probe: a script copying require("paper")'s table into its own
    // loaded as a curriculum, and was then checked as a scenario).
    const std::optional<ScriptKind> guess = guessed_kind(a.script);
    if (guess == ScriptKind::kCurriculum) {
      Curriculum::load(a.script, limits);
      return check_curriculum_file(a.script, args.script, limits, split_sets(a.sets, "--set"));
    }
    if (guess == ScriptKind::kSkillScript) {
      SkillScript::load(a.script, limits);
      return check_skill_script_file(a.script, args.script, limits, split_sets(a.sets, "--set"));
    }
  }
  if (is_curriculum_script(a.script)) return check_curriculum_file(a.script, args.script, limits, split_sets(a.sets, "--set"));
  if (is_skill_script(a.script))
    return check_skill_script_file(a.script, args.script, limits, split_sets(a.sets, "--set"));
  if (is_batch_script(a.script)) return check_batch(a.script, args.script, a.lua, split_sets(a.sets, "--set"));
  if (script_kind_of(a.script)) return check_scenario_file(a, args.script, limits);
  // A script of no kind is checked as a scenario; one that returns no table at all is no more a
  // scenario than anything else (found by a probe: `return 42` was "a scenario script must return
  // a table").
  try {
    return check_scenario_file(a, args.script, limits);
  } catch (const ScriptError& e) {
    const std::string scenario_said = "a scenario script must return a table {";
    if (e.message.rfind(scenario_said, 0) != 0) throw;
    throw ScriptError("a script must return a table: a scenario's {generate = function(world, rng, params) ... end}, "
                      "a skill script's {policies = {...}}, a curriculum's {stages = {...}} or a batch script's "
                      "{curriculum = ..., runs = {...}}, got " + e.message.substr(e.message.rfind(", got ") + 6),
                      e.file, e.line, e.traceback);
  }
}

}  // namespace roger
