#include "script/batch/batch_script.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include <lua.hpp>

#include "core/error.h"
#include "core/fileio.h"
#include "core/text.h"
#include "script/batch/batch_script_internal.h"
#include "script/curriculum/curriculum.h"
#include "script/scenario/scenario.h"
#include "script/skills/skill_script.h"

namespace roger {

namespace fs = std::filesystem;
using json = nlohmann::json;
using batch_detail::lua_to_json;
using batch_detail::has_no;
using batch_detail::quoted_list;
using batch_detail::Reader;
using batch_detail::default_title;

namespace {

// The budgets the command line sets over a script's.
void apply_limit_overrides(const BatchOverrides& overrides, SandboxLimits& limits) {
  if (overrides.instructions > 0) limits.instructions = overrides.instructions;
  if (overrides.memory_mib > 0) limits.memory_bytes = size_t(overrides.memory_mib) << 20;
}

void merge_params(Params& into, const Params& more) {
  for (const auto& kv : more) {  // not a structured binding: clang 14 cannot capture one in a lambda
    const auto& [k, v] = kv;
    auto it = std::find_if(into.begin(), into.end(), [&](const auto& p) { return p.first == kv.first; });
    if (it != into.end()) it->second = v;
    else into.emplace_back(k, v);
  }
}

// Finds the script: the path itself, or <project>/scripts/<name>.lua for a bare name.
std::string resolve_script(const std::string& arg) { return resolve_batch_script_path(arg); }


// The table the script returned (on top of the stack, then popped) as JSON.
json returned_table(lua_State* L, const Reader& rd, int top_line) {
  if (!lua_istable(L, -1))
    rd.fail(top_line, "a batch script must return a table {name = ..., curriculum = ..., runs = {...}}, got " +
                          std::string(luaL_typename(L, -1)));
  json top;
  try {
    top = lua_to_json(L, -1, "");
  } catch (const ScriptError&) {
    throw;
  } catch (const Error& e) {
    rd.fail(top_line, e.what());
  }
  lua_pop(L, 1);
  return top;
}

// Reads `limits = { instructions = N, memory = MiB }` into the script's sandbox limits, then the
// command line's --lua-instructions and --lua-memory over them.
void read_limits(const json& top, const Reader& rd, const BatchOverrides& overrides, BatchScript& b) {
  if (top.contains("limits")) {
    const int l = rd.line_of_key("limits", 1);
    const std::string what = "the batch script's limits";
    rd.check_object(top["limits"], what, {"instructions", "memory"}, l);
    b.limits.instructions = uint64_t(rd.integer(top["limits"], "instructions", what, l,
                                                int64_t(b.limits.instructions), 1000, int64_t(1) << 53));
    b.limits.memory_bytes = size_t(rd.integer(top["limits"], "memory", what, l, int64_t(b.limits.memory_bytes >> 20),
                                              16, int64_t(1) << 20)) << 20;
  }
  apply_limit_overrides(overrides, b.limits);
}

// A description or title is one line of the report (found by a probe: a line break let the rest
// of a description open a Markdown heading of tables.md).
void refuse_line_break(const Reader& rd, const std::string& text, const std::string& what, int line) {
  if (text.find_first_of("\r\n") != std::string::npos)
    rd.fail(line, what + " is one line of the report, and has a line break: join its lines");
}

// Reads the script's own fields (name, description, curriculum, trials, seed, params, limits),
// with the command line's overrides.
void read_header(const json& top, const Reader& rd, int top_line, const std::string& path,
                 const BatchOverrides& overrides, BatchScript& b) {
  rd.check_object(top, "the batch script",
                  {"name", "description", "curriculum", "trials", "seed", "params", "limits", "runs", "evaluations",
                   "tables", "figures"},
                  top_line);
  b.name = rd.str(top, "name", "the batch script", top_line, fs::path(path).stem().string());
  // The results go to results/<name> unless --out says otherwise: a name is one folder's name.
  // At most 200 bytes, as every name that names a folder (found by a probe: 300 passed roger check
  // and failed roger run with "File name too long").
  if (b.name.empty() || b.name == "." || b.name == ".." || b.name.find_first_of("/\\") != std::string::npos ||
      b.name.size() > 200)
    rd.fail(rd.line_of_key("name", top_line), "the batch script: 'name' names the results folder results/<name>: "
                                              "a folder's name without '/' or '\\', not empty, '.' or '..', at most "
                                              "200 bytes, got '" + (b.name.size() > 200 ? b.name.substr(0, 40) + "...' (" +
                                              std::to_string(b.name.size()) + " bytes)" : b.name + "'"));
  b.description = rd.str(top, "description", "the batch script", top_line, "");
  refuse_line_break(rd, b.description, "the batch script's 'description'", rd.line_of_key("description", top_line));
  b.curriculum = rd.str(top, "curriculum", "the batch script", top_line, "", true);
  b.trials = int(rd.integer(top, "trials", "the batch script", top_line, 1, 1, 100000));
  b.seed = uint64_t(rd.integer(top, "seed", "the batch script", top_line, 1, 0, int64_t(1) << 53));
  b.params = rd.params(top, "params", "the batch script", top_line);
  merge_params(b.params, overrides.sets);
  if (overrides.trials > 0) b.trials = overrides.trials;
  read_limits(top, rd, overrides, b);
}

// Every seed a batch derives (seed + i, first_seed + j) lies within 0..2^53, as 'seed' and
// 'first_seed' do: results name seeds as JSON numbers, which a browser's page reads as doubles, exact
// to 2^53 only. Found by a probe: seed = 2^53 with 3 trials passed, its trials past the bound.
void refuse_seeds_past_largest(const Reader& rd, uint64_t first, uint64_t count, int line, const std::string& what,
                               const std::string& last_said, const std::string& field,
                               const std::string& or_else = "") {
  const uint64_t largest = uint64_t(1) << 53;
  if (count == 0 || first + (count - 1) <= largest) return;
  rd.fail(line, what + ", so the last seed, " + last_said + " = " + std::to_string(first + (count - 1)) +
                    ", is past 2^53 (" + std::to_string(largest) + "), the largest seed a batch takes: give " +
                    field + " at most " + std::to_string(largest - (count - 1)) + or_else);
}

// Loads the script's curriculum and records its file.
std::unique_ptr<Curriculum> load_curriculum(const Reader& rd, const std::string& path, const SandboxLimits& limits,
                                            BatchScript& b) {
  // The curriculum: relative to the current folder, else the script's folder, else a shipped name.
  std::string cur_arg = b.curriculum;
  {
    std::error_code ec;
    const fs::path beside = fs::path(path).parent_path() / b.curriculum;
    const fs::path in_project = project_root() / b.curriculum;
    if (!fs::is_regular_file(cur_arg, ec)) {
      if (fs::is_regular_file(beside, ec)) cur_arg = beside.string();
      else if (fs::is_regular_file(in_project, ec)) cur_arg = in_project.string();
      // A path found nowhere: each place looked at is named (found by a probe: "no such file here
      // or in the project" named neither, nor the one beside the script).
      else if (b.curriculum.find('/') != std::string::npos || fs::path(b.curriculum).extension() == ".lua") {
        const std::string here = fs::absolute(b.curriculum, ec).lexically_normal().string(),
                          near = fs::absolute(beside, ec).lexically_normal().string(),
                          project = fs::absolute(in_project, ec).lexically_normal().string();
        // Each place once (found by a newcomer: run from the project, it was named twice).
        rd.fail(rd.line_of_key("curriculum", 1),
                "no curriculum '" + b.curriculum + "': looked at " + here +
                    (near == here ? " (from the current folder, beside the batch script)"
                                  : " (from the current folder), then " + near + " (beside the batch script)") +
                    (project == here || project == near ? std::string() : ", then " + project + " (in the project)"));
      }
    }
  }
  std::unique_ptr<Curriculum> cur;
  try {
    // A script of another kind fails inside (found by a probe: a scenario's file said
    // "scenarios/lib/shapes.lua:16: attempt to call a nil value"): named as what it is.
    require_script_kind(b.curriculum, resolve_curriculum_path(cur_arg), {"curriculum"}, "the curriculum");
    cur = std::make_unique<Curriculum>(Curriculum::load(cur_arg, limits));
  } catch (const ScriptError& e) {
    rd.fail(rd.line_of_key("curriculum", 1), "the curriculum '" + b.curriculum + "' does not load: " + e.what());
  } catch (const Error& e) {
    rd.fail(rd.line_of_key("curriculum", 1), e.what());
  }
  b.curriculum_file = fs::absolute(cur->file()).lexically_normal().string();
  // As a stage's scenario path (found by a probe: a batch script in batches/ naming
  // "mywork/x.lua" passed roger check from the lab's folder and failed from its own).
  if (const std::string w = scenario_found_from_here(b.curriculum, b.path, "curriculum"); !w.empty())
    b.curriculum_warning = b.path + ":" + std::to_string(rd.line_of_key("curriculum", 1)) + ": " + w;
  return cur;
}

// Reads a run's 'skills' (for each learned skill its contexts use, the earlier run that trains
// it) and checks that every skill it needs is given.
// Reads one entry `Skill = {run = ..., context = ...}` of a 'skills' table at line l: the run that
// trains it, which must have at least `trials` trials (trial i uses trial i's policy).
BatchSkill read_skill_source(const std::string& skill, const json& entry, const Reader& rd, const std::string& sw,
                             int l, const Curriculum& cur, const BatchScript& b, int trials,
                             const std::string& user) {
  rd.check_object(entry, sw, {"run", "context"}, l);
  BatchSkill s;
  s.skill = skill;
  s.run = rd.str(entry, "run", sw, l, "", true);
  const BatchRun* from = b.run(s.run);
  if (!from) {
    std::vector<std::string> earlier;
    for (const auto& e : b.runs) earlier.push_back(e.name);
    rd.fail(l, sw + ": no earlier run '" + s.run + "'; the runs before it are " + quoted_list(earlier));
  }
  const CurriculumStage* producer = cur.producer(s.skill);
  if (!producer) rd.fail(l, sw + ": the curriculum yields no skill '" + s.skill + "'");
  if (producer->name != from->stage)
    rd.fail(l, sw + ": run '" + s.run + "' trains stage '" + from->stage + "', but '" + s.skill +
                   "' is yielded by stage '" + producer->name + "'");
  const std::string own = producer->skill ? producer->skill->second : "";
  s.context = rd.str(entry, "context", sw, l, own);
  // The skill is the policy its stage learns in the context its `skill` field names: another
  // context's policy is refused when the trials that use it load it, after all the training.
  if (s.context != own)
    rd.fail(rd.line_of_key("context", l), sw + ": '" + s.skill + "' is the policy stage '" + producer->name +
                                              "' learns in context '" + own + "' (its field skill, " + producer->file +
                                              ":" + std::to_string(producer->line) + "), not one of context '" +
                                              s.context + "': give context = \"" + own + "\" or leave it out");
  if (std::find(from->contexts.begin(), from->contexts.end(), s.context) == from->contexts.end())
    rd.fail(l, sw + ": run '" + s.run + "' " + has_no("context", s.context, from->contexts));
  if (from->trials < trials)
    rd.fail(l, sw + ": run '" + s.run + "' has " + std::to_string(from->trials) + " trials, fewer than the " +
                   std::to_string(trials) + " of " + user + " (trial i uses trial i's policy)");
  return s;
}

void read_run_skills(const json& rj, const Reader& rd, const std::string& what, const Curriculum& cur,
                     const CurriculumStage* stage, const BatchScript& b, BatchRun& r) {
  // The learned skills its contexts use, and where each comes from.
  std::set<std::string> needed;
  for (const auto& c : r.contexts)
    for (const auto& l : stage->context(c).learned) needed.insert(l);
  if (rj.contains("skills")) {
    const json& sj = rj["skills"];
    const int sl = rd.line_of_key("skills", r.line);
    if (!sj.is_object()) rd.fail(sl, what + ": 'skills' must be a table {Skill = {run = ..., context = ...}}");
    for (auto it = sj.begin(); it != sj.end(); ++it) {
      const std::string sw = what + ", skill '" + it.key() + "'";
      const int l = rd.line_of_key(it.key(), sl);
      const BatchSkill s = read_skill_source(it.key(), *it, rd, sw, l, cur, b, r.trials, "run '" + r.name + "'");
      if (!needed.count(s.skill))
        rd.fail(l, sw + ": no context of run '" + r.name + "' uses the learned skill '" + s.skill + "'");
      r.skills.push_back(s);
    }
  }
  for (const auto& n : needed)
    if (std::none_of(r.skills.begin(), r.skills.end(), [&](const BatchSkill& s) { return s.skill == n; }))
      rd.fail(r.line, what + ": its contexts use the learned skill '" + n +
                          "': say which run trains it, e.g. skills = { " + n + " = { run = \"...\", context = \"...\" } }");
}

// Reads one run of 'runs' (written from line `runs_line` on).
// The scenario parameters a run or an evaluation sets (--set among them), and each shape it
// evaluates, tried on its scenario now: a name the scenario does not declare or a value it
// refuses is the script's error at `line`, or the command line's when --set (`sets`) gave it,
// not a failure of every trial after the training.
void check_scenario_params(const std::string& scenario, const Params& params, const std::vector<std::string>& shapes,
                           const Params& sets, const SandboxLimits& limits, const Reader& rd, int line,
                           const std::string& what) {
  Scenario s = Scenario::load(scenario, limits);
  for (const auto& param : params) {
    try {
      const bool from_lua = std::find(sets.begin(), sets.end(), param) == sets.end();
      if (const auto problems = s.param_problems({param}, from_lua); !problems.empty()) throw Error(problems.front());
      s.set_param(param.first, param.second);
    } catch (const Error& e) {
      // A --set goes to every run, those --only leaves out too (a folder's trials all share it):
      // say how to set it on some runs only (found by a probe: a sorting parameter could not be
      // varied by --set with the paper's stages in the script).
      if (std::find(sets.begin(), sets.end(), param) != sets.end())
        throw Error("--set " + param.first + "=" + param.second + ": " + what + ": " + e.what() +
                    "\n  a --set goes to every run of the script, whatever --only selects; to set it on some runs "
                    "only, give it in their `params` (runs = {{name = ..., params = {" + param.first + " = ...}}}, "
                    "docs/batch.md) in a script of your own");
      rd.fail(line, what + ": " + e.what());
    }
  }
  try {
    for (const auto& shape : shapes) s.set_param("shape", shape);
  } catch (const Error& e) {
    rd.fail(line, what + ": " + e.what());
  }
  // Parameters that go out of range only together (a noise level times noise_scale) are refused by
  // the generator: one world built now names them at this line, not at the curriculum's stage
  // (found by a probe). A layout that seed cannot hold is no fault of the parameters.
  try {
    s.generate(0);
  } catch (const PlacementError&) {
  } catch (const ScriptError& e) {
    rd.fail(line, what + ": " + e.what());
  }
}

// How reading goes on after an entry's problem: roger run stops at the first (thrown); roger check
// reads every entry of runs, evaluations, tables and figures, collecting each one's first problem.
// Once one has a problem, an entry naming a run or an evaluation not read (that one, or a misspelt
// name, which the list of names would then give wrong) is left for the check after the fix (found
// by a probe: a script's mistakes came one roger check at a time).
struct EntryProblems {
  BatchProblems* out = nullptr;  // null: the first problem is thrown
  const BatchScript& b;
  bool failed = false;  // a run or an evaluation was not read

  // Whether `j` names, as a 'run' or an 'evaluation' at any depth, one not read: also a sorting
  // row's 'learned' and 'hand' runs and a comparison's "run/context" rows (found by a probe: a
  // misspelt stage was followed by "table 'Compare': no run 'Fetch'; the runs are (none)").
  bool names_unread(const json& j) const {
    if (j.is_array()) return std::any_of(j.begin(), j.end(), [&](const json& e) { return names_unread(e); });
    if (!j.is_object()) return false;
    const auto unread_run = [&](const std::string& name) { return !b.run(name); };
    for (auto it = j.begin(); it != j.end(); ++it) {
      const std::string& key = it.key();
      if (it->is_string() && (key == "run" || key == "learned" || key == "hand") && unread_run(*it)) return true;
      if (key == "compare" && it->is_array())
        for (const json& row : *it)
          if (row.is_string() && unread_run(row.get<std::string>().substr(0, row.get<std::string>().find('/'))))
            return true;
      if (it->is_string() && it.key() == "evaluation" &&
          std::none_of(b.evaluations.begin(), b.evaluations.end(), [&](const BatchEvaluation& e) { return e.name == *it; }))
        return true;
      if (names_unread(*it)) return true;
    }
    return false;
  }

  // Reads the entry `j`, a `kind` ("run", "table"), with `read`.
  template <class Read>
  void entry(const json& j, const std::string& kind, Read&& read) {
    if (out && failed && names_unread(j)) {
      std::string label = kind;
      for (const char* key : {"name", "title", "file"})
        if (j.is_object() && j.contains(key) && j[key].is_string()) {
          label += " '" + j[key].get<std::string>() + "'";
          break;
        }
      out->unchecked.push_back(label);
      return;
    }
    try {
      read();
    } catch (const ScriptError& e) {
      if (!out) throw;
      out->errors.push_back(e);
      failed = failed || kind == "run" || kind == "evaluation";  // what later entries may name
    }
  }
};

// The line of the table named `name` (a run's or an evaluation's): where the name is written, or
// where a table with `marker` gets a computed name (built in a loop), else `list_line`.
int table_line(const Reader& rd, const std::string& name, const std::string& marker, int list_line) {
  if (const int l = rd.line_of_name(name, list_line)) return l;
  if (const int l = rd.line_of_built_name(marker, list_line)) return l;
  return list_line;
}

BatchRun read_run(const json& rj, const Reader& rd, int runs_line, const Curriculum& cur,
                  const std::vector<std::string>& stage_names, const BatchOverrides& overrides, const BatchScript& b) {
  BatchRun r;
  const std::string nm = rj.is_object() && rj.contains("name") && rj["name"].is_string() ? rj["name"].get<std::string>() : "";
  r.line = nm.empty() ? runs_line : table_line(rd, nm, "stage", runs_line);
  const std::string what = nm.empty() ? "a run" : "run '" + nm + "'";
  rd.check_object(rj, what, {"name", "stage", "contexts", "trials", "params", "skills", "final_worlds"}, r.line);
  r.name = rd.str(rj, "name", what, r.line, "", true);
  if (!results_name(r.name) || r.name == "eval")
    rd.fail(r.line, what + ": a run name uses letters, digits, '.', '_' and '-', at most 200 of them (and is not 'eval', "
                         "'.' or '..')");
  // At the second's line, not the first's (found by a probe: both looked for the first `name =`).
  if (const BatchRun* first = b.run(r.name)) {
    const int second = rd.line_of_name(r.name, first->line + 1);
    rd.fail(second ? second : r.line, "a second run named '" + r.name + "' (the first is at line " +
                                          std::to_string(first->line) + ")");
  }
  r.stage = rd.str(rj, "stage", what, r.line, "", true);
  const CurriculumStage* stage = nullptr;
  for (const auto& st : cur.stages())
    if (st.name == r.stage) stage = &st;
  if (!stage)
    rd.fail(rd.line_of_key("stage", r.line), what + ": the curriculum " + cur.path() + " " +
                                                 has_no("stage", r.stage, stage_names));
  std::vector<std::string> ctx_names;
  for (const auto& c : stage->contexts) ctx_names.push_back(c.name);
  r.contexts = rd.strings(rj, "contexts", what, r.line, false);
  // Left out, every context; written empty is more likely a list that came out empty by mistake.
  if (r.contexts.empty() && rj.contains("contexts"))
    rd.fail(rd.line_of_key("contexts", r.line), what + ": 'contexts' is empty: name some of the contexts of stage '" +
                                                    r.stage + "' (" + quoted_list(ctx_names) +
                                                    "), or leave the field out for all of them");
  if (r.contexts.empty()) r.contexts = ctx_names;
  for (const auto& c : r.contexts)
    if (std::find(ctx_names.begin(), ctx_names.end(), c) == ctx_names.end())
      rd.fail(rd.line_of_key("contexts", r.line), what + ": stage '" + r.stage + "' " + has_no("context", c, ctx_names));
  // A context names its trials' folders (trials/<run>/<context>/000). Found by a probe: one named
  // "C<img ...>" passed roger check, and roger run refused it after writing the results folder.
  for (const auto& c : r.contexts)
    if (!results_name(c))
      rd.fail(rj.contains("contexts") ? rd.line_of_key("contexts", r.line) : r.line,
              what + ": the context '" + c + "' of stage '" + r.stage + "' cannot name its trials' folders (trials/" +
                  r.name + "/<context>/000): a context a batch runs uses letters, digits, '.', '_' and '-', at most "
                  "200 of them (rename it in the curriculum)");
  r.trials = int(rd.integer(rj, "trials", what, r.line, b.trials, 1, 100000));
  if (overrides.trials > 0) r.trials = overrides.trials;
  refuse_seeds_past_largest(rd, b.seed, uint64_t(r.trials),
                            rj.contains("trials") ? rd.line_of_key("trials", r.line) : rd.line_of_key("seed", 1),
                            what + ": trial i trains with seed 'seed' + i", "seed + trials - 1",
                            "'seed'", overrides.trials > 0 ? ", or fewer --trials" : "");
  r.params = b.params;
  merge_params(r.params, rd.params(rj, "params", what, r.line));
  merge_params(r.params, overrides.sets);
  check_scenario_params(stage->scenario, r.params, {}, overrides.sets, b.limits, rd, r.line, what);
  read_run_skills(rj, rd, what, cur, stage, b, r);
  const std::string worlds = rd.str(rj, "final_worlds", what, r.line, "shared");
  if (worlds != "own" && worlds != "shared")
    rd.fail(rd.line_of_key("final_worlds", r.line),
            what + ": final_worlds is 'own' (each trial's final evaluation in worlds of its own) or 'shared' (every "
                   "trial's on the stage's held-out seeds), not '" + worlds + "'");
  r.own_final_worlds = worlds == "own";
  // Found by a probe: a stage that teaches took final_worlds = "own" and ran every trial's final
  // evaluation on its test set all the same, saying nothing.
  if (r.own_final_worlds && stage->teaches())
    rd.fail(rd.line_of_key("final_worlds", r.line),
            what + ": final_worlds = 'own' cannot apply to stage '" + r.stage + "', which teaches: every trial's "
                   "final evaluation runs the stage's test set (test task i in world seed " +
                   std::to_string(stage->checkpoints.seeds) + " + i), the same for every trial so that the trials "
                   "and the teachers are measured alike; for worlds of each policy's own, evaluate the run "
                   "(evaluations = {{run = '" + r.name + "', context = ..., worlds = 'own'}}), and leave "
                   "final_worlds out");
  return r;
}

// A note for each parameter of a run's context's own `params` that the run's params (the script's,
// the run's, --set, merged in that order) set to another value, at the line of the params whose
// value wins. Found by a probe: a batch setting obstacles = 0 and a run eye_pixels = 64 trained
// context Coarse (eye_pixels = 32, obstacles = 2) exactly as context Full, without a word. The
// override may be meant, as a --set of roger train is, which says so: a note, not an error.
void note_context_overrides(const json& rj, const Reader& rd, int top_line, const Curriculum& cur,
                            const BatchOverrides& overrides, BatchScript& b) {
  const BatchRun& r = b.runs.back();
  const Params own = rd.params(rj, "params", "run '" + r.name + "'", r.line);
  const auto named = [](const Params& ps, const std::string& name) {
    return std::find_if(ps.begin(), ps.end(), [&](const auto& p) { return p.first == name; });
  };
  for (const std::string& c : r.contexts)
    for (const auto& [name, value] : cur.stage(r.stage).context(c).params) {
      const auto wins = named(r.params, name);
      if (wins == r.params.end() || wins->second == value) continue;
      std::string by = "--set " + name + "=" + wins->second;
      int line = r.line;  // a --set is the command line's: the run it reaches
      if (std::find(overrides.sets.begin(), overrides.sets.end(), *wins) == overrides.sets.end()) {
        const bool run_own = named(own, name) != own.end();
        by = (run_own ? "the run's params " : "the batch script's params ") + name + " = " + wins->second;
        line = rd.line_of_key("params", run_own ? r.line : top_line);  // as an error in those params names it
      }
      b.notes.push_back(b.path + ":" + std::to_string(line) + ": run '" + r.name + "': context '" + c +
                        "' of stage '" + r.stage + "' sets " + name + " = " + value + ", overridden by " + by +
                        " (a batch's params and --set win over a context's own, as --set does in roger train)");
    }
}

// Reads 'runs', in order (a run takes skills only from the runs before it).
void read_runs(const json& top, const Reader& rd, int top_line, const Curriculum& cur,
               const BatchOverrides& overrides, BatchScript& b, EntryProblems& problems) {
  std::vector<std::string> stage_names;
  for (const auto& st : cur.stages()) stage_names.push_back(st.name);

  if (!top.contains("runs")) rd.fail(top_line, "the batch script: missing required field 'runs' (a list of runs)");
  const int runs_line = rd.line_of_key("runs", 1);
  if (!top["runs"].is_array() || top["runs"].empty())
    rd.fail(runs_line, "the batch script: 'runs' must be a non-empty list of {name = ..., stage = ..., contexts = {...}}");
  for (const json& rj : top["runs"])
    problems.entry(rj, "run", [&] {
      b.runs.push_back(read_run(rj, rd, runs_line, cur, stage_names, overrides, b));
      // A stage's bare scenario name with a scenario of that name beside the curriculum, once.
      const std::string n = cur.stage(b.runs.back().stage).scenario_note();
      if (!n.empty() && std::find(b.notes.begin(), b.notes.end(), n) == b.notes.end()) b.notes.push_back(n);
      note_context_overrides(rj, rd, top_line, cur, overrides, b);
    });
}

// Reads one evaluation of 'evaluations' (written from line `el` on).
// Reads an evaluation's optional 'skills': learned skills of the evaluated context taken from
// another run than the ones its policies embed (a Phi_SG retrained on another body, say).
void read_evaluation_skills(const json& ej, const Reader& rd, const std::string& what, const Curriculum& cur,
                            const BatchScript& b, BatchEvaluation& e) {
  if (!ej.contains("skills")) return;
  const BatchRun* from = b.run(e.run);
  const CurriculumStage& stage = cur.stage(from->stage);
  const std::vector<std::string>& uses = stage.context(e.context).learned;
  const json& sj = ej["skills"];
  const int sl = rd.line_of_key("skills", e.line);
  if (!sj.is_object()) rd.fail(sl, what + ": 'skills' must be a table {Skill = {run = ..., context = ...}}");
  for (auto it = sj.begin(); it != sj.end(); ++it) {
    const std::string sw = what + ", skill '" + it.key() + "'";
    const int l = rd.line_of_key(it.key(), sl);
    const BatchSkill s = read_skill_source(it.key(), *it, rd, sw, l, cur, b, e.trials, "evaluation '" + e.name + "'");
    if (std::find(uses.begin(), uses.end(), s.skill) == uses.end())
      rd.fail(l, sw + ": context '" + e.context + "' of run '" + e.run + "' uses no learned skill '" + s.skill +
                     "'; it uses " + (uses.empty() ? std::string("none") : quoted_list(uses)));
    e.skills.push_back(s);
  }
}

BatchEvaluation read_evaluation(const json& ej, const Reader& rd, int el, const BatchOverrides& overrides,
                                const Curriculum& cur, const BatchScript& b) {
  BatchEvaluation e;
  const std::string nm = ej.is_object() && ej.contains("name") && ej["name"].is_string() ? ej["name"].get<std::string>() : "";
  e.line = nm.empty() ? el : table_line(rd, nm, "run", el);
  const std::string what = nm.empty() ? "an evaluation" : "evaluation '" + nm + "'";
  rd.check_object(ej, what,
                  {"name", "run", "context", "scenario", "params", "shapes", "episodes", "first_seed", "worlds",
                   "trials", "skills"},
                  e.line);
  e.name = rd.str(ej, "name", what, e.line, "", true);
  if (!results_name(e.name))
    rd.fail(e.line, what + ": a name uses letters, digits, '.', '_' and '-', at most 200 of them (and is not '.' or '..')");
  for (const auto& o : b.evaluations)
    if (o.name == e.name) {
      const int second = rd.line_of_name(e.name, o.line + 1);
      rd.fail(second ? second : e.line, "a second evaluation named '" + e.name + "' (the first is at line " +
                                            std::to_string(o.line) + ")");
    }
  e.run = rd.str(ej, "run", what, e.line, "", true);
  const BatchRun* from = b.run(e.run);
  if (!from) {
    std::vector<std::string> names;
    for (const auto& r : b.runs) names.push_back(r.name);
    rd.fail(rd.line_of_key("run", e.line), what + ": no run '" + e.run + "'; the runs are " + quoted_list(names));
  }
  e.context = rd.str(ej, "context", what, e.line, from->contexts.back());
  if (std::find(from->contexts.begin(), from->contexts.end(), e.context) == from->contexts.end())
    rd.fail(rd.line_of_key("context", e.line),
            what + ": run '" + e.run + "' " + has_no("context", e.context, from->contexts));
  e.scenario = rd.str(ej, "scenario", what, e.line, "");
  if (!e.scenario.empty()) {
    try {
      const std::string written = e.scenario;
      e.scenario = resolve_scenario_near(e.scenario, b.path);  // beside the batch script first, as require
      // A curriculum or a batch script named here failed inside it, at no line of this script
      // (found by a probe: "skills.lua:45: attempt to call a nil value").
      require_script_kind(written, e.scenario, {"scenario"}, "");
    } catch (const Error& ex) {
      rd.fail(rd.line_of_key("scenario", e.line), what + ": " + ex.what());
    }
  }
  e.params = rd.params(ej, "params", what, e.line);
  e.shapes = rd.strings(ej, "shapes", what, e.line, false);
  // As a run's empty 'contexts' (found by a probe: shapes = {} was one group 'all' without a word).
  if (e.shapes.empty() && ej.contains("shapes"))
    rd.fail(rd.line_of_key("shapes", e.line), what + ": 'shapes' is empty: name the shapes to evaluate one group "
                                                 "each, or leave the field out for one group 'all' in the scenario's own");
  for (const auto& s : e.shapes)
    if (!results_name(s))
      rd.fail(rd.line_of_key("shapes", e.line), what + ": shape '" + s + "' is not a plain name (letters, digits, '.', "
                                                 "'_' and '-', at most 200 of them)");
  if (std::any_of(e.params.begin(), e.params.end(), [](const auto& p) { return p.first == "shape"; }) &&
      !e.shapes.empty())
    rd.fail(rd.line_of_key("shapes", e.line), what + ": give the shape either in 'params' or in 'shapes', not both");
  e.episodes = int(rd.integer(ej, "episodes", what, e.line, 50, 1, 1000000));
  e.first_seed = rd.integer(ej, "first_seed", what, e.line, -1, -1, int64_t(1) << 53);
  const std::string worlds = rd.str(ej, "worlds", what, e.line, "own");
  if (worlds != "own" && worlds != "shared")
    rd.fail(rd.line_of_key("worlds", e.line), what + ": worlds is 'own' (each policy its own) or 'shared' (the same "
                                                     "worlds for every policy), not '" + worlds + "'");
  e.shared_worlds = worlds == "shared";
  // --trials N replaces the evaluation's trials as it replaces the run's: the script's own is checked
  // against no run's count it overrides (found by a probe: `--trials 1` refused an evaluation of
  // trials = 3 as "must be between 1 and 1", blaming the script).
  const int most = overrides.trials > 0 ? 100000 : from->trials;
  e.trials = int(rd.integer(ej, "trials", what, e.line, from->trials, 1, most));
  if (overrides.trials > 0) e.trials = from->trials;
  if (e.first_seed >= 0) {  // shape k's worlds follow shape k-1's (run.cpp's evaluation_seed_offset)
    const uint64_t shapes = std::max<uint64_t>(1, e.shapes.size());
    const uint64_t worlds = shapes * (e.shared_worlds ? 1 : uint64_t(e.trials)) * uint64_t(e.episodes);
    refuse_seeds_past_largest(rd, uint64_t(e.first_seed), worlds, rd.line_of_key("first_seed", e.line),
                              what + ": its " + std::to_string(worlds) + " worlds take seeds from 'first_seed' on",
                              "first_seed + " + std::to_string(worlds - 1), "'first_seed'");
  }
  read_evaluation_skills(ej, rd, what, cur, b, e);
  std::string scenario = e.scenario;
  for (const auto& st : cur.stages())
    if (scenario.empty() && st.name == from->stage) scenario = st.scenario;
  check_scenario_params(scenario, e.params, e.shapes, {}, b.limits, rd, e.line, what);  // --set is training's
  return e;
}

// What a run trained a context with: the stage's and the context's own params, and the batch's
// (the script's, the run's, --set) over them, each with who set it ("" for the context's own).
struct TrainedParam {
  std::string name, value, by;
};
std::vector<TrainedParam> trained_params(const CurriculumStage& stage, const std::string& context, const BatchRun& run,
                                         const BatchOverrides& overrides) {
  std::vector<TrainedParam> out;
  for (const auto& [name, value] : stage.scenario_params(stage.context(context))) out.push_back({name, value, ""});
  for (const auto& [name, value] : run.params) {
    const bool by_set = std::find(overrides.sets.begin(), overrides.sets.end(), std::make_pair(name, value)) !=
                        overrides.sets.end();
    const std::string by = by_set ? "--set" : "the batch's params";
    const std::string& key = name;  // a lambda may not capture a structured binding (C++17)
    const auto it = std::find_if(out.begin(), out.end(), [&](const TrainedParam& t) { return t.name == key; });
    if (it == out.end()) out.push_back({name, value, by});
    else if (it->value != value) *it = {name, value, by};
  }
  return out;
}

// A note for each parameter the evaluated run trained with that the evaluation runs otherwise: in
// the stage's scenario, one its params set to another value, or one the batch's params or --set
// gave training, which an evaluation does not take; in another scenario, one that scenario
// declares and the evaluation leaves at its default. Found by probes: a context's frozen eyes
// (eye_pixels = 32) evaluated in cluttered with its default 128 eyes, and nothing said it; then a
// run's eye_pixels = 64 noted with the context's 32 "to evaluate as trained", and the run's own
// eyes, evaluated in the stage's scenario at 128, not noted at all.
void note_evaluation_params(const Reader& rd, const Curriculum& cur, const BatchOverrides& overrides, BatchScript& b) {
  const BatchEvaluation& e = b.evaluations.back();
  const BatchRun& run = *b.run(e.run);
  const CurriculumStage& stage = cur.stage(run.stage);
  const std::vector<TrainedParam> trained = trained_params(stage, e.context, run, overrides);
  if (trained.empty()) return;
  const bool same = e.scenario.empty() || e.scenario == stage.scenario;
  const Scenario scenario = Scenario::load(same ? stage.scenario : e.scenario, b.limits);
  const std::vector<ScenarioParam> declared = scenario.params();
  const Params own = stage.scenario_params(stage.context(e.context));
  const auto at = [&](int line, const TrainedParam& t) {
    return b.path + ":" + std::to_string(line) + ": evaluation '" + e.name + "': " +
           (t.by.empty() ? "stage '" + stage.name + "', context '" + e.context + "' sets "
                         : "run '" + run.name + "' trained stage '" + stage.name + "', context '" + e.context +
                               "' with ") +
           t.name + " = " + t.value + (t.by.empty() ? "" : " (" + t.by + ")");
  };
  for (const TrainedParam& t : trained) {
    const auto given = std::find_if(e.params.begin(), e.params.end(), [&](const auto& p) { return p.first == t.name; });
    const auto p = std::find_if(declared.begin(), declared.end(), [&](const auto& d) { return d.name == t.name; });
    const std::string as_trained = "(give params = {" + t.name + " = " + t.value + "} to evaluate as trained)";
    if (given != e.params.end()) {
      if (same && given->second != t.value)
        b.notes.push_back(at(rd.line_of_key("params", e.line), t) + ", overridden by the evaluation's params " +
                          t.name + " = " + given->second + " (an evaluation's params win over a context's own)");
    } else if (!same && p != declared.end()) {
      b.notes.push_back(at(e.line, t) + ", which this evaluation leaves at scenario '" + scenario.name() +
                        "''s default " + p->default_value +
                        ": in another scenario than its stage's an evaluation runs with its own params only " +
                        as_trained);
    } else if (same && !t.by.empty()) {
      const auto ctx = std::find_if(own.begin(), own.end(), [&](const auto& o) { return o.first == t.name; });
      b.notes.push_back(at(e.line, t) + ", which this evaluation leaves at " +
                        (ctx != own.end() ? "the context's own " + ctx->second
                                          : "the scenario's default " + (p != declared.end() ? p->default_value : "")) +
                        ": an evaluation runs with the stage's and context's params and its own, not the batch's "
                        "or --set " + as_trained);
    }
  }
}

// Reads the optional 'evaluations'.
void read_evaluations(const json& top, const Reader& rd, const BatchOverrides& overrides, const Curriculum& cur,
                      BatchScript& b, EntryProblems& problems) {
  if (top.contains("evaluations")) {
    const int el = rd.line_of_key("evaluations", 1);
    if (!top["evaluations"].is_array()) rd.fail(el, "the batch script: 'evaluations' must be a list");
    for (const json& ej : top["evaluations"])
      problems.entry(ej, "evaluation", [&] {
        b.evaluations.push_back(read_evaluation(ej, rd, el, overrides, cur, b));
        note_evaluation_params(rd, cur, overrides, b);
      });
  }
}

// The names of the runs read so far.
std::vector<std::string> run_names(const BatchScript& b) {
  std::vector<std::string> n;
  for (const auto& r : b.runs) n.push_back(r.name);
  return n;
}

// Reads a run's table's 'usage' rows (written at line `ul`): which action of a context a skill
// subsumes.
void read_usage(const json& tj, const Reader& rd, const std::string& what, int ul, const BatchRun* r,
                const Curriculum& cur, BatchTable& t) {
  if (!tj["usage"].is_array()) rd.fail(ul, what + ": 'usage' must be a list of {context = ..., skill = ..., subsumes = {...}}");
  for (const json& uj : tj["usage"]) {
    rd.check_object(uj, what + ", usage", {"context", "skill", "subsumes"}, ul);
    BatchUsage u;
    u.context = rd.str(uj, "context", what + ", usage", ul, "", true);
    if (std::find(r->contexts.begin(), r->contexts.end(), u.context) == r->contexts.end())
      rd.fail(ul, what + ", usage: run '" + t.run + "' " + has_no("context", u.context, r->contexts));
    u.skill = rd.str(uj, "skill", what + ", usage", ul, "", true);
    u.subsumes = rd.strings(uj, "subsumes", what + ", usage", ul, true);
    // Found by a probe: a skill that subsumes itself read as "50% of the decisions among itself and
    // the actions it subsumes (itself)", a share of nothing.
    if (std::find(u.subsumes.begin(), u.subsumes.end(), u.skill) != u.subsumes.end())
      rd.fail(ul, what + ", usage: '" + u.skill + "' subsumes itself: list the actions it stands for, not the skill");
    std::vector<std::string> psi;
    for (const auto& a : cur.stage(r->stage).context(u.context).actions) psi.push_back(a->name());
    std::vector<std::string> all = u.subsumes;
    all.push_back(u.skill);
    for (const auto& a : all)
      if (std::find(psi.begin(), psi.end(), a) == psi.end())
        rd.fail(ul, what + ", usage: context '" + u.context + "' has no action '" + a + "'; its actions are " +
                        quoted_list(psi));
    t.usage.push_back(std::move(u));
  }
}

// The number of objects in the worlds of run `r` in its context `context`, as its trials train
// it: the run's params, else the stage's and the context's, else its scenario's default; "" when
// the scenario has no parameter 'objects' (not a sorting stage).
std::string objects_of(const BatchRun& r, const std::string& context, const Curriculum& cur) {
  for (const auto& [key, value] : r.params)
    if (key == "objects") return value;
  const CurriculumStage& stage = cur.stage(r.stage);
  for (const auto& [key, value] : stage.scenario_params(stage.context(context)))
    if (key == "objects") return value;
  for (const ScenarioParam& p : Scenario::load(stage.scenario).params())
    if (p.name == "objects") return p.default_value;
  return "";
}

// A sorting row's run plays worlds of the row's number of objects (found by a probe: a row of 8
// objects over a run of 2 printed "8 objects, 2 sorted per episode", and a row over a stage of no
// sorting at all a count made up from its reward).
void check_sorting_run(const BatchRun& r, int objects, const Curriculum& cur, const Reader& rd, const std::string& what,
                       int l) {
  for (const std::string& context : r.contexts) {
    const std::string held = objects_of(r, context, cur);
    if (held.empty())
      rd.fail(l, what + ": run '" + r.name + "' trains stage '" + r.stage + "' in scenario '" +
                     cur.stage(r.stage).scenario + "', which has no parameter 'objects': a sorting row's runs sort");
    if (held != std::to_string(objects))
      rd.fail(l, what + ": the row is of " + std::to_string(objects) + " objects, but run '" + r.name + "' (context '" +
                     context + "') plays worlds of " + held);
  }
}

// A sorting row's `hand` run learns nothing (each of its contexts has one action, the hand-written
// policy), and its `learned` run chooses among actions (found by a probe: the two swapped were
// taken, the learned run's trials then pooled as one policy's, its interval too narrow).
void check_sorting_roles(const BatchSortingRow& row, const BatchScript& b, const Curriculum& cur, const Reader& rd,
                         const std::string& what, int l) {
  const auto chooser = [&](const std::string& run) -> std::string {  // a context that learns, or ""
    const BatchRun& r = *b.run(run);
    for (const std::string& c : r.contexts)
      if (cur.stage(r.stage).context(c).actions.size() > 1) return c;
    return "";
  };
  if (!row.hand.empty()) {
    if (const std::string c = chooser(row.hand); !c.empty())
      rd.fail(l, what + ": 'hand' names run '" + row.hand + "', whose context '" + c + "' learns to choose among " +
                     std::to_string(cur.stage(b.run(row.hand)->stage).context(c).actions.size()) +
                     " actions; a hand-written run's contexts have one action, the policy" +
                     (row.learned.empty() || chooser(row.learned).empty() ? " (did you mean learned = '" + row.hand + "'?)"
                                                                          : ""));
  }
  if (!row.learned.empty() && chooser(row.learned).empty())
    rd.fail(l, what + ": 'learned' names run '" + row.learned + "', which learns nothing: each of its contexts has "
                   "one action" + (row.hand.empty() || !chooser(row.hand).empty() ? " (did you mean hand = '" +
                                                                                      row.learned + "'?)" : ""));
}

// Reads a sorting table's rows: {objects = n, learned = run, hand = run}, each run one of the script's.
void read_sorting_rows(const json& rows, const Reader& rd, const std::string& what, int l, const BatchScript& b,
                       const Curriculum& cur, BatchTable& t) {
  if (!rows.is_array() || rows.empty())
    rd.fail(l, what + ": 'sorting' must be a list of {objects = n, learned = run, hand = run}");
  for (const json& rj : rows) {
    rd.check_object(rj, what + ", a sorting row", {"objects", "learned", "hand"}, l);
    BatchSortingRow row;
    if (!rj.contains("objects") || !rj["objects"].is_number_integer() || rj["objects"].get<int64_t>() < 1 ||
        rj["objects"].get<int64_t>() > 1000)
      rd.fail(l, what + ": a sorting row's 'objects' must be a whole number of objects, 1 to 1000");
    row.objects = int(rj["objects"].get<int64_t>());
    row.learned = rd.str(rj, "learned", what, l, "");
    row.hand = rd.str(rj, "hand", what, l, "");
    if (row.learned.empty() && row.hand.empty()) rd.fail(l, what + ": a sorting row needs 'learned', 'hand' or both");
    for (const std::string* name : {&row.learned, &row.hand})
      if (!name->empty() && !b.run(*name))
        rd.fail(l, what + ": no run '" + *name + "'; the runs are " + quoted_list(run_names(b)));
    for (const std::string* name : {&row.learned, &row.hand})
      if (!name->empty()) check_sorting_run(*b.run(*name), row.objects, cur, rd, what, l);
    check_sorting_roles(row, b, cur, rd, what, l);
    for (const BatchSortingRow& before : t.sorting)
      if (before.objects == row.objects)
        rd.fail(l, what + ": two sorting rows of " + std::to_string(row.objects) + " objects; a row holds a learned "
                       "run and a hand-written one of that count");
    t.sorting.push_back(std::move(row));
  }
}

// Reads a list of "run/context" rows (a comparison across runs), each of a run and context the
// script trains.
std::vector<BatchRow> read_rows(const json& j, const Reader& rd, const std::string& what, int l, const BatchScript& b) {
  if (!j.is_array() || j.empty()) rd.fail(l, what + ": 'compare' must be a list of \"run/context\" rows");
  std::vector<BatchRow> rows;
  for (const json& rj : j) {
    const std::string text = rj.is_string() ? rj.get<std::string>() : "";
    const size_t slash = text.find('/');
    if (slash == std::string::npos)
      rd.fail(l, what + ": a row of 'compare' is \"run/context\", got " + rj.dump());
    BatchRow row{text.substr(0, slash), text.substr(slash + 1)};
    const BatchRun* r = b.run(row.run);
    if (!r) rd.fail(l, what + ": no run '" + row.run + "'; the runs are " + quoted_list(run_names(b)));
    if (std::find(r->contexts.begin(), r->contexts.end(), row.context) == r->contexts.end())
      rd.fail(l, what + ": run '" + row.run + "' " + has_no("context", row.context, r->contexts));
    // Found by a probe: a row twice drew two identical rows (a run's contexts twice are refused).
    for (const BatchRow& before : rows)
      if (before.label() == row.label()) rd.fail(l, what + ": 'compare' names '" + text + "' twice");
    rows.push_back(std::move(row));
  }
  return rows;
}

// Reads a comparison table {compare = {"run/context", ...}, baseline = "run/context"}.
void read_compare_table(const json& tj, const Reader& rd, const std::string& what, int l, const BatchScript& b,
                        BatchTable& t) {
  if (tj.contains("run") || tj.contains("evaluation") || tj.contains("usage"))
    rd.fail(l, what + ": a comparison's rows are its 'compare' list: no 'run', 'evaluation' or 'usage'");
  t.compare = read_rows(tj["compare"], rd, what, rd.line_of_key("compare", l), b);
  t.baseline = rd.str(tj, "baseline", what, l, t.compare.front().label());
  const auto it = std::find_if(t.compare.begin(), t.compare.end(), [&](const BatchRow& r) { return r.label() == t.baseline; });
  if (it == t.compare.end())
    rd.fail(rd.line_of_key("baseline", l), what + ": the baseline '" + t.baseline + "' is not one of its rows");
  std::rotate(t.compare.begin(), it, it + 1);  // the baseline first
}

// The task parameters the records of a run's trials name: its stage's task space's axes, and with
// `lifted`, the parameter its LCAS teacher lifts outside the space (episodes.jsonl records it;
// the final evaluations run its last level, and final.jsonl does not).
std::vector<std::string> task_params(const Curriculum& cur, const BatchRun& r, bool lifted) {
  const CurriculumStage& st = cur.stage(r.stage);
  std::vector<std::string> names;
  for (const TaskDim& d : st.tasks.dims()) names.push_back(d.name);
  if (lifted && st.teacher && st.teacher->kind == TeacherSpec::Kind::kLcas && st.tasks.index(st.teacher->lift) < 0)
    names.push_back(st.teacher->lift);
  return names;
}

// Refuses a table's 'by' that no final evaluation of its runs records: what each world held, or a
// task parameter of a run's stage (report_teachers.cpp, feature_of). A misspelt one wrote an empty
// table with a note, found only once the run was over.
void check_by(const BatchTable& t, const Reader& rd, const std::string& what, int l, const Curriculum& cur,
              const BatchScript& b) {
  std::vector<std::string> features = {"obstacles", "objects", "shape"}, tasks;
  std::vector<std::string> runs;
  if (t.compare.empty()) runs.push_back(t.run);
  for (const BatchRow& row : t.compare) runs.push_back(row.run);
  for (const std::string& run : runs)
    for (const std::string& p : task_params(cur, *b.run(run), false))
      if (std::find(tasks.begin(), tasks.end(), p) == tasks.end()) tasks.push_back(p);
  features.insert(features.end(), tasks.begin(), tasks.end());
  if (std::find(features.begin(), features.end(), t.by) != features.end()) return;
  rd.fail(rd.line_of_key("by", l), what + ": 'by' is '" + t.by + "', which no final evaluation of its runs records" +
                                       suggestion(t.by, features) + "; they record what each world held (obstacles, "
                                       "objects, shape)" +
                                       (tasks.empty() ? std::string(" and no task") : " and the task's " + quoted_list(tasks)));
}

// Reads one table of 'tables' as written; `at` is the line to search from, moved past this table.
BatchTable read_table_fields(const json& tj, const Reader& rd, int& at, const Curriculum& cur, const BatchScript& b) {
  BatchTable t;
  const std::string title = tj.is_object() && tj.contains("title") && tj["title"].is_string() ? tj["title"].get<std::string>() : "";
  const int l = title.empty() ? at : std::max(at, rd.line_of_key("title", at));
  at = l + 1;
  const std::string what = title.empty() ? "a table" : "table '" + title + "'";
  rd.check_object(tj, what, {"title", "run", "baseline", "evaluation", "usage", "sorting", "compare", "by"}, l);
  t.title = title;
  refuse_line_break(rd, t.title, what + ": 'title'", l);
  t.by = rd.str(tj, "by", what, l, "");
  if (!t.by.empty() && (tj.contains("evaluation") || tj.contains("sorting") || tj.contains("usage")))
    rd.fail(l, what + ": 'by' splits the final evaluations of a run's contexts or of 'compare''s rows");
  if (tj.contains("compare")) {
    read_compare_table(tj, rd, what, l, b, t);
    if (!t.by.empty()) check_by(t, rd, what, l, cur, b);
    return t;
  }
  if (tj.contains("sorting")) {
    if (tj.contains("run") || tj.contains("evaluation") || tj.contains("baseline") || tj.contains("usage"))
      rd.fail(l, what + ": a sorting table has rows of its own: no 'run', 'evaluation', 'baseline' or 'usage'");
    read_sorting_rows(tj["sorting"], rd, what, rd.line_of_key("sorting", l), b, cur, t);
    return t;
  }
  t.run = rd.str(tj, "run", what, l, "");
  t.evaluation = rd.str(tj, "evaluation", what, l, "");
  if (t.run.empty() == t.evaluation.empty())
    rd.fail(l, what + ": give one of 'run', 'evaluation', 'sorting' or 'compare'" +
                   (t.run.empty() ? "" : std::string(", not both 'run' and 'evaluation'")));
  if (!t.evaluation.empty()) {
    if (std::none_of(b.evaluations.begin(), b.evaluations.end(), [&](const auto& e) { return e.name == t.evaluation; })) {
      std::vector<std::string> names;
      for (const auto& e : b.evaluations) names.push_back(e.name);
      rd.fail(l, what + ": no evaluation '" + t.evaluation + "'; the evaluations are " + quoted_list(names));
    }
    if (tj.contains("baseline") || tj.contains("usage"))
      rd.fail(l, what + ": 'baseline' and 'usage' belong to a run's table");
  } else {
    const BatchRun* r = b.run(t.run);
    if (!r) rd.fail(l, what + ": no run '" + t.run + "'; the runs are " + quoted_list(run_names(b)));
    t.baseline = rd.str(tj, "baseline", what, l, r->contexts.front());
    if (std::find(r->contexts.begin(), r->contexts.end(), t.baseline) == r->contexts.end())
      rd.fail(rd.line_of_key("baseline", l), what + ": run '" + t.run + "' " + has_no("context", t.baseline, r->contexts));
    if (tj.contains("usage")) read_usage(tj, rd, what, rd.line_of_key("usage", l), r, cur, t);
    if (!t.by.empty()) check_by(t, rd, what, l, cur, b);
  }
  return t;
}

// Reads one table of 'tables', with its title; `at` is the line to search from, moved past it.
// Everything a table shows, as one text: two tables with the same are one table written twice.
std::string table_identity(const BatchTable& t) {
  std::string id = t.title + '\n' + t.run + '\n' + t.baseline + '\n' + t.evaluation + '\n' + t.by + '\n';
  for (const auto& u : t.usage) id += "u " + u.context + ' ' + u.skill + ' ' + join(u.subsumes) + '\n';
  for (const auto& r : t.sorting) id += "s " + std::to_string(r.objects) + ' ' + r.learned + ' ' + r.hand + '\n';
  for (const auto& r : t.compare) id += "c " + r.label() + '\n';
  return id;
}

BatchTable read_table(const json& tj, const Reader& rd, int& at, const Curriculum& cur, const BatchScript& b) {
  BatchTable t = read_table_fields(tj, rd, at, cur, b);
  if (t.title.empty()) t.title = default_title(t, b);
  // Found by a probe: `tables = {{run = "Y"}, {run = "Y"}}` wrote one table twice without a word.
  for (const auto& o : b.tables)
    if (table_identity(o) == table_identity(t))
      rd.fail(at - 1, "a second table the same as an earlier one ('" + t.title + "'): the report would show it "
                      "twice; remove one, or give them what differs (a 'title', a 'by', 'usage' rows)");
  return t;
}

// Reads 'tables' (default: one per run against its first context, one per evaluation).
void read_tables(const json& top, const Reader& rd, const Curriculum& cur, BatchScript& b, EntryProblems& problems) {
  if (top.contains("tables")) {
    const int tl = rd.line_of_key("tables", 1);
    if (!top["tables"].is_array()) rd.fail(tl, "the batch script: 'tables' must be a list");
    int at = tl;
    for (const json& tj : top["tables"])
      problems.entry(tj, "table", [&] { b.tables.push_back(read_table(tj, rd, at, cur, b)); });
  } else {
    for (const auto& r : b.runs) {
      BatchTable t;
      t.run = r.name;
      t.baseline = r.contexts.front();
      t.title = default_title(t, b);
      b.tables.push_back(t);
    }
    for (const auto& e : b.evaluations) {
      BatchTable t;
      t.evaluation = e.name;
      t.title = default_title(t, b);
      b.tables.push_back(t);
    }
  }
}

// Reads a figure's 'file': a plain name, not the one the report gives a run's IQM curves.
std::string read_figure_file(const json& fj, const Reader& rd, int l, const std::string& what, const BatchScript& b) {
  const std::string file = rd.str(fj, "file", what, l, "", true);
  if (!results_name(file))
    rd.fail(l, what + ": 'file' is a plain name (letters, digits, '.', '_' and '-', at most 200 of them; no folder, no "
                      "extension): <file>.png and <file>.svg are written");
  // Found by a probe: file = "curves.png" passed check, and the report wrote curves.png.png.
  for (const char* ext : {".png", ".svg", ".PNG", ".SVG"})
    if (file.size() > 4 && file.compare(file.size() - 4, 4, ext) == 0) {
      const std::string stem = file.substr(0, file.size() - 4);
      rd.fail(l, what + ": 'file' is named without its extension: '" + stem + "' (the report writes " + stem +
                     ".png and " + stem + ".svg)");
    }
  for (const auto& r : b.runs)
    if (file == "iqm_" + r.name)
      rd.fail(l, what + ": the report draws the IQM learning curves of run '" + r.name + "' into iqm_" + r.name +
                     ".png and .svg itself: give this figure another file name");
  return file;
}

// Reads what a figure of kind "tasks" adds: the context of run `r` and the parameter its teacher chooses.
void read_tasks_figure(const json& fj, const Reader& rd, int l, const std::string& what, const Curriculum& cur,
                       const BatchRun& r, BatchFigure& f) {
  f.context = rd.str(fj, "context", what, l, r.contexts.front());
  if (std::find(r.contexts.begin(), r.contexts.end(), f.context) == r.contexts.end())
    rd.fail(rd.line_of_key("context", l), what + ": run '" + f.run + "' " + has_no("context", f.context, r.contexts));
  f.param = rd.str(fj, "param", what, l, "", true);
  // Where the teacher of the run's stage sampled: a parameter it chooses, or the one LCAS lifts.
  const std::vector<std::string> chosen = task_params(cur, r, true);
  if (chosen.empty())
    rd.fail(l, what + ": run '" + f.run + "''s stage '" + r.stage + "' has no task space or teacher: a figure of "
                   "kind \"tasks\" draws where a teacher sampled");
  if (std::find(chosen.begin(), chosen.end(), f.param) == chosen.end())
    rd.fail(rd.line_of_key("param", l), what + ": 'param' is '" + f.param + "', which the teacher of run '" + f.run +
                                            "' does not choose" + suggestion(f.param, chosen) + "; it chooses " +
                                            quoted_list(chosen));
  // Found by a probe: the figure then read "not drawn: no finished trial" after the run.
  const auto fixed = std::find_if(r.params.begin(), r.params.end(), [&](const auto& p) { return p.first == f.param; });
  if (fixed != r.params.end())
    rd.fail(rd.line_of_key("param", l), what + ": 'param' is '" + f.param + "', which the params of run '" + f.run +
                                            "' fix (" + f.param + " = " + fixed->second +
                                            "): its teacher does not choose it in that run");
}

// Reads the run of a figure drawn from one run (not 'compare'), and what its kind needs of it.
void read_figure_run(const json& fj, const Reader& rd, int l, const std::string& what, const Curriculum& cur,
                     const BatchScript& b, BatchFigure& f) {
  f.run = rd.str(fj, "run", what, l, "", true);
  const BatchRun* r = b.run(f.run);
  if (!r) rd.fail(rd.line_of_key("run", l), what + ": no run '" + f.run + "'; the runs are " + quoted_list(run_names(b)));
  if (f.kind == "cumulative" && r->skills.empty())
    rd.fail(l, what + ": a cumulative figure needs a run that takes skills from an earlier run; '" + f.run +
                   "' takes none");
  if (f.kind == "tasks") {
    read_tasks_figure(fj, rd, l, what, cur, *r, f);
  } else if (fj.contains("param") || fj.contains("context")) {
    // Naming what was given (found by a probe: 'param' alone was said as "'param' and 'context'").
    const std::string given = fj.contains("param") && fj.contains("context") ? "'param' and 'context' belong"
                              : fj.contains("param")                        ? "'param' belongs"
                                                                            : "'context' belongs";
    rd.fail(l, what + ": " + given + " to a figure of kind \"tasks\" (this one is of kind \"" + f.kind + "\")");
  }
}

// Reads one figure of 'figures'; `at` is the line to search from, moved past this figure.
BatchFigure read_figure(const json& fj, const Reader& rd, int& at, const Curriculum& cur, const BatchScript& b) {
  BatchFigure f;
  const std::string file = fj.is_object() && fj.contains("file") && fj["file"].is_string() ? fj["file"].get<std::string>() : "";
  const int l = file.empty() ? at : std::max(at, rd.line_of_key("file", at));
  at = l + 1;
  const std::string what = file.empty() ? "a figure" : "figure '" + file + "'";
  rd.check_object(fj, what, {"file", "title", "kind", "run", "log_x", "compare", "y", "context", "param"}, l);
  f.file = read_figure_file(fj, rd, l, what, b);
  f.title = rd.str(fj, "title", what, l, "");
  refuse_line_break(rd, f.title, what + ": 'title'", l);
  f.kind = rd.str(fj, "kind", what, l, "curves");
  if (f.kind != "curves" && f.kind != "cumulative" && f.kind != "tasks")
    rd.fail(rd.line_of_key("kind", l), what + ": 'kind' is \"curves\", \"cumulative\" or \"tasks\", got '" + f.kind + "'");
  // Found by a probe: log_x and y on a cumulative or tasks figure were taken, and drew nothing of them.
  for (const char* key : {"log_x", "y"})
    if (f.kind != "curves" && fj.contains(key))
      rd.fail(rd.line_of_key(key, l), what + ": '" + key + "' belongs to a figure of kind \"curves\" (this one is of "
                                          "kind \"" + f.kind + "\", whose axes it does not set)");
  f.y = rd.str(fj, "y", what, l, "reward");
  if (f.y != "reward" && f.y != "success")
    rd.fail(rd.line_of_key("y", l), what + ": 'y' is \"reward\" (the greedy episodic reward) or \"success\" (the share "
                                        "of test tasks mastered), got '" + f.y + "'");
  if (fj.contains("compare")) {
    if (f.kind != "curves") rd.fail(l, what + ": 'compare' draws the curves of several runs' contexts (kind \"curves\")");
    if (fj.contains("run")) rd.fail(l, what + ": give 'run' or 'compare', not both");
    f.compare = read_rows(fj["compare"], rd, what, rd.line_of_key("compare", l), b);
    f.run = f.compare.front().run;
  } else {
    read_figure_run(fj, rd, l, what, cur, b, f);
  }
  f.log_x = rd.boolean(fj, "log_x", what, l, false);
  for (const auto& o : b.figures)
    if (o.file == f.file) rd.fail(l, "a second figure written to '" + f.file + "'");
  return f;
}

// Reads 'figures' (default: learning curves of every run, cumulative times of every run with
// skills).
void read_figures(const json& top, const Reader& rd, const Curriculum& cur, BatchScript& b, EntryProblems& problems) {
  if (top.contains("figures")) {
    const int fl = rd.line_of_key("figures", 1);
    if (!top["figures"].is_array()) rd.fail(fl, "the batch script: 'figures' must be a list");
    int at = fl;
    for (const json& fj : top["figures"])
      problems.entry(fj, "figure", [&] { b.figures.push_back(read_figure(fj, rd, at, cur, b)); });
  } else {
    for (const auto& r : b.runs) {
      // Named by the run too when it is not the stage's name (found by a probe: the figures of runs
      // SG and SG_M, noise-free and noisy, had the same title).
      const std::string of = "stage " + r.stage + (r.name == r.stage ? std::string() : " (run " + r.name + ")");
      BatchFigure f;
      f.file = "curves_" + r.name;
      f.title = "Learning curves: " + of;
      f.run = r.name;
      b.figures.push_back(f);
      if (!r.skills.empty()) {
        f.file = "cumulative_" + r.name;
        f.title = "Cumulative training time: " + of;
        f.kind = "cumulative";
        b.figures.push_back(f);
      }
    }
  }
}

}  // namespace

// Found by a probe: a comparison's or a split's table written without a title had an empty heading.
std::string batch_detail::default_title(const BatchTable& t, const BatchScript& b) {
  if (!t.compare.empty()) return (t.by.empty() ? "Comparison of " : "Final success by " + t.by + ": ") + row_labels(t.compare);
  if (!t.sorting.empty()) return "Sorting";
  if (!t.evaluation.empty()) return "Evaluation " + t.evaluation;
  const std::string stage = "Stage " + b.run(t.run)->stage + " (run " + t.run + ")";
  return t.by.empty() ? stage : stage + ": final success by " + t.by;
}

std::string row_labels(const std::vector<BatchRow>& rows) {
  std::string text;
  for (const BatchRow& r : rows) text += (text.empty() ? "" : ", ") + r.label();
  return text;
}

const BatchRun* BatchScript::run(const std::string& n) const {
  for (const auto& r : runs)
    if (r.name == n) return &r;
  return nullptr;
}

std::vector<const BatchRun*> BatchScript::ordered_runs() const {
  std::vector<const BatchRun*> out;
  std::set<std::string> placed;
  while (out.size() < runs.size()) {
    bool progress = false;
    for (const auto& r : runs) {
      if (placed.count(r.name)) continue;
      bool ready = true;
      for (const auto& s : r.skills) ready = ready && placed.count(s.run) > 0;
      if (!ready) continue;
      out.push_back(&r);
      placed.insert(r.name);
      progress = true;
    }
    if (!progress) throw Error("batch script: runs take skills from each other in a cycle");
  }
  return out;
}

bool results_name(const std::string& s) {
  const bool plain = !s.empty() && s.size() <= 200 && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-';
  });
  return plain && s != "." && s != "..";
}

std::string batch_trial_id(const std::string& run, const std::string& context, int trial) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%03d", trial);
  return run + "/" + context + "/" + buf;
}

std::string batch_eval_id(const std::string& evaluation, const std::string& shape, int trial) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%03d", trial);
  return "eval/" + evaluation + "/" + shape + "/" + buf;
}

std::vector<std::string> batch_eval_groups(const BatchEvaluation& e) {
  return e.shapes.empty() ? std::vector<std::string>{"all"} : e.shapes;
}

namespace {

// load_batch_script, or with `collected` check_batch_script.
BatchScript read_batch_script(const std::string& path_in, const BatchOverrides& overrides,
                              const SandboxLimits& limits_in, BatchProblems* collected) {
  const std::string path = resolve_script(path_in);
  // Run as a batch script, a curriculum fails inside its first roger.primitive (no such API here),
  // a scenario inside its first require of a scenario library.
  require_script_kind(path_in, path, {"batch script"});
  SandboxLimits limits = limits_in;
  apply_limit_overrides(overrides, limits);
  LuaSandbox sandbox(limits);
  BatchScript b;
  b.file = path;
  b.path = sandbox.display_name(path);
  sandbox.set_main_script(path);
  sandbox.run_file(path, 1);
  lua_State* L = sandbox.state();
  const std::string text = read_file_text(path);
  const Reader rd(b.path, text);
  const int top_line = rd.return_line();
  const json top = returned_table(L, rd, top_line);

  read_header(top, rd, top_line, path, overrides, b);
  const std::unique_ptr<Curriculum> cur = load_curriculum(rd, path, b.limits, b);
  EntryProblems problems{collected, b};
  read_runs(top, rd, top_line, *cur, overrides, b, problems);
  read_evaluations(top, rd, overrides, *cur, b, problems);
  read_tables(top, rd, *cur, b, problems);
  read_figures(top, rd, *cur, b, problems);
  b.ordered_runs();  // rejects cycles (impossible with earlier-run skills, kept as a guard)
  return b;
}

}  // namespace

BatchScript load_batch_script(const std::string& path, const BatchOverrides& overrides, const SandboxLimits& limits) {
  return read_batch_script(path, overrides, limits, nullptr);
}

BatchScript check_batch_script(const std::string& path, const BatchOverrides& overrides, BatchProblems& problems) {
  return read_batch_script(path, overrides, {}, &problems);
}

std::string resolve_batch_script_path(const std::string& name_or_path) {
  return resolve_script_path(name_or_path, "scripts", "batch script", "batch scripts in scripts/", is_batch_script);
}

bool is_batch_script(const std::string& path) {
  return script_has_key(path, "runs") || script_has_key(path, "curriculum") ||
         script_has_key(path, "evaluations");
}

std::string script_kind(const std::string& path) {
  if (is_curriculum_script(path)) return "curriculum";
  if (is_skill_script(path)) return "skill script";
  if (is_batch_script(path)) return "batch script";
  if (script_has_key(path, "generate")) return "scenario";
  return "";
}

namespace {

// What runs a script of `kind`, for the error that names it given as another kind; the commands
// quoted for a shell (found by a probe: a path with a space, pasted, was two words).
std::string what_runs(const std::string& kind, const std::string& name) {
  const std::string given = shell_word(name);
  if (kind == "curriculum")
    return "train one of its stages with roger train " + given + " --stage S --context C --out DIR, or name it as "
           "the curriculum of a batch script (docs/batch.md)";
  if (kind == "batch script") return "run it with roger run " + given;
  if (kind == "skill script") return "evaluate one of its policies with roger eval " + given + " --policy NAME";
  return "a curriculum's stages name it as their scenario (docs/curricula.md); draw it with roger render " + given +
         " --out FILE.png";
}

}  // namespace

void require_script_kind(const std::string& given, const std::string& path, const std::vector<std::string>& wanted,
                         const std::string& option) {
  const std::string kind = script_kind(path);
  if (kind.empty() || std::find(wanted.begin(), wanted.end(), kind) != wanted.end()) return;
  std::string expected;
  for (size_t i = 0; i < wanted.size(); ++i)
    expected += (i == 0 ? "" : i + 1 == wanted.size() ? " or " : ", ") + wanted[i];
  throw Error((option.empty() ? "" : option + " ") + given + " is a " + kind + ", not a " + expected + ": " +
              what_runs(kind, given));
}

}  // namespace roger
