// batch_script.h: batch scripts (scripts/paper.lua), the Lua description of a whole experiment:
// which curriculum, how many trials of which stage and contexts, which learned skills each run
// takes from which earlier run, which saved policies are evaluated where, and which tables and
// figures the report draws. docs/batch.md is the reference of every field.
//
//   return {
//     name = "paper", curriculum = "curricula/paper.lua", trials = 50, seed = 1,
//     runs = {
//       { name = "SG", stage = "SG", contexts = {"B1", "DC1", "DC2"} },
//       { name = "T", stage = "T", contexts = {"B2", "DC3", "DC4", "DC5", "DC6"},
//         skills = { Phi_SG = { run = "SG", context = "DC2" } } },
//     },
//     evaluations = { { name = "generalization", run = "T", context = "DC6", scenario = "cluttered",
//                       params = {obstacles = 3}, shapes = {"circle", "spade"}, episodes = 50 } },
//     tables = { ... }, figures = { ... },   -- optional: defaults follow the runs
//   }
//
// The script runs in the sandbox (lua_sandbox.h). Every mistake (an unknown field, curriculum,
// stage, context, run or skill) is a ScriptError naming the batch script's file:line and listing
// what exists.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "script/sandbox/lua_sandbox.h"

namespace roger {

using Params = std::vector<std::pair<std::string, std::string>>;

// Where a run takes a learned skill from: trial i uses the policy of trial i of run/context.
struct BatchSkill {
  std::string skill;    // "Phi_SG"
  std::string run;      // the earlier run that trains it ("SG")
  std::string context;  // the context of that run whose policy is used ("DC2")
};

// Trials of one curriculum stage in several contexts.
struct BatchRun {
  std::string name;                   // unique; the first segment of its trial ids
  std::string stage;                  // a stage of the curriculum
  std::vector<std::string> contexts;  // contexts of that stage, in table order
  int trials = 0;                     // trials per context
  Params params;                      // scenario parameters (batch params, then these)
  std::vector<BatchSkill> skills;     // learned skills taken from earlier runs
  // final_worlds = "own": trial i's final greedy evaluation starts i * its episodes past the
  // stage's held-out seeds, so the trials' final policies meet distinct worlds; false ("shared",
  // the default, as the paper's Tables I and II): every trial's on the held-out seeds.
  bool own_final_worlds = false;
  int line = 0;                       // where it is written
};

// Greedy runs of one run/context's final policies in another scenario, per object shape.
struct BatchEvaluation {
  std::string name;                 // unique; ids are eval/<name>/<shape>/<trial>
  std::string run, context;         // whose policies (every trial's, up to `trials`)
  std::string scenario;             // "" = the stage's
  Params params;                    // scenario parameters
  std::vector<std::string> shapes;  // one group per shape (sets shape=...); empty = one group "all"
  int episodes = 50;                // episodes per policy and shape
  int64_t first_seed = -1;          // -1 = the stage's held-out seeds
  bool shared_worlds = false;       // every policy on the same worlds (common random numbers);
                                    // false: trial i's worlds start at first_seed + i * episodes
  int trials = 0;                   // how many of the run's trials are evaluated
  // Learned skills taken from these runs instead of those the policies embed: trial i's policy runs
  // over trial i's skill (a Phi_SG retrained on another body under the same transport policy).
  std::vector<BatchSkill> skills;
  int line = 0;
};

// A usage comparison: a skill's share of the decisions against the actions it subsumes.
struct BatchUsage {
  std::string context, skill;
  std::vector<std::string> subsumes;
};

// One row of a sorting table: a number of objects, and the runs (their first context) of the
// learned and the hand-written sorting stage for it (either may be empty).
struct BatchSortingRow {
  int objects = 0;
  std::string learned, hand;
};

// A row of a comparison across runs: one context of one run ("T_alp/B2").
struct BatchRow {
  std::string run, context;
  std::string label() const { return run + "/" + context; }
};

// "T_seq/DC3, T_lcas/DC3": rows' labels, for titles and figure lines.
std::string row_labels(const std::vector<BatchRow>& rows);

// One table of the report: a run against its baseline context, an evaluation, a sorting table
// (one row per number of objects), or a comparison of contexts of several runs (teachers on one
// context) against the first. With `by`, a run's or a comparison's table is instead the final
// evaluations' success rate split by a recorded feature of each episode's world or task.
struct BatchTable {
  std::string title;
  std::string run, baseline;  // a run's table (baseline: one of its contexts)
  std::string evaluation;     // or an evaluation's table
  std::vector<BatchUsage> usage;
  std::vector<BatchSortingRow> sorting;  // or a sorting table
  std::vector<BatchRow> compare;         // or rows of several runs, the first the baseline
  std::string by;                        // "obstacles", "shape", a task parameter: the split
};

// One figure of the report (written as <file>.png and <file>.svg).
struct BatchFigure {
  std::string file, title;
  // "curves": learning curves of a run's contexts (or of `compare`'s rows); "cumulative": stacked
  // times; "tasks": where a run's teacher sampled `param` against training episodes.
  std::string kind = "curves";
  std::string run;
  bool log_x = false;
  std::vector<BatchRow> compare;  // curves of these rows instead of a run's contexts
  std::string y = "reward";       // curves of the greedy "reward" or "success" (% of test tasks mastered)
  std::string context, param;     // a tasks figure: the context and the parameter drawn
};

// A loaded and validated batch script.
struct BatchScript {
  std::string file;             // the script as given
  std::string path;             // as shown in messages
  std::string name, description;
  std::string curriculum;       // as written (resolved by the trainer)
  std::string curriculum_file;  // the resolved file
  // "" or, when `curriculum` was found from the current folder only (not beside the script, not in
  // the project), why another folder will not find it (roger check warns: scenario_found_from_here).
  std::string curriculum_warning;
  int trials = 0;
  uint64_t seed = 1;
  Params params;                // scenario parameters of every training run (script, then --set)
  // The sandbox's budgets for the curriculum, its scenarios and every trial: the script's
  // `limits = { instructions = N, memory = MiB }`, then --lua-instructions and --lua-memory.
  SandboxLimits limits;
  std::vector<BatchRun> runs;
  std::vector<BatchEvaluation> evaluations;
  std::vector<BatchTable> tables;
  std::vector<BatchFigure> figures;
  // What roger check and roger run say before any trial, each "file:line: ...": a run's stage
  // whose bare scenario name is not the scenario of that name beside the curriculum
  // (CurriculumStage::scenario_note), and a context's own scenario parameter that the script's, a
  // run's or --set's params override (as roger train marks one a --set overrides).
  std::vector<std::string> notes;

  // A run by name, or null.
  const BatchRun* run(const std::string& name) const;
  // Runs in an order where every run comes after the runs it takes skills from.
  std::vector<const BatchRun*> ordered_runs() const;
};

// What the command line changes in a script.
struct BatchOverrides {
  int trials = 0;  // > 0: every run's and evaluation's trial count
  Params sets;     // scenario parameters added to every training run
  uint64_t instructions = 0;  // > 0: the instruction budget per call (--lua-instructions)
  uint64_t memory_mib = 0;    // > 0: the Lua state's memory cap in MiB (--lua-memory)
};

// Loads a batch script, applies the overrides and validates it against its curriculum. The script
// itself runs under `limits` (or the overrides' budgets, when given); its curriculum under the
// limits it sets (BatchScript::limits). Throws ScriptError (file:line) or roger::Error.
BatchScript load_batch_script(const std::string& path, const BatchOverrides& overrides = {},
                              const SandboxLimits& limits = {});

// What roger check finds in a batch script's entries (runs, evaluations, tables, figures): each
// entry's first problem, in the script's order, and the entries left unread for naming a run or an
// evaluation not read ("run 'T'", "table 'Table I'"): their check follows once the problems are fixed.
struct BatchProblems {
  std::vector<ScriptError> errors;
  std::vector<std::string> unchecked;
};

// load_batch_script reading every entry: their problems go into `problems` (the script is whole
// only when there are none); a problem before the entries (the header, the curriculum) is thrown.
BatchScript check_batch_script(const std::string& path, const BatchOverrides& overrides, BatchProblems& problems);

// Whether the file reads as a batch script: it sets `runs`, `curriculum` or `evaluations`
// (script_has_key), as scripts/paper.lua and scripts/quick.lua (`quick.evaluations = ...`) do.
bool is_batch_script(const std::string& path);

// The kind a script reads as by the fields it sets, without running it: "curriculum" (stages),
// "skill script" (policies), "batch script" (runs, curriculum or evaluations), "scenario"
// (generate), or "" when it sets none of them; script_kind_of (script_api.h) reads it. A
// curriculum may set a field of the others' and is one first.
std::string script_kind(const std::string& path);

// The file a batch script argument names: the path itself, or <project>/scripts/<name>.lua for a
// bare name (resolve_script_path's rules and errors).
std::string resolve_batch_script_path(const std::string& name_or_path);

// Throws roger::Error when the script at `path` (resolved; `given` as the user typed it) reads as
// a kind not in `wanted` (script_kind's names), naming both and what runs it instead: a script of
// the wrong kind otherwise fails inside, in a Lua traceback or a list of fields that do not
// belong. A script of no known kind passes: loading it says what is wrong. `option`, when given,
// is the option or field that named it ("--scenario"), said before it.
void require_script_kind(const std::string& given, const std::string& path, const std::vector<std::string>& wanted,
                         const std::string& option = "");

// The script's resolved configuration as JSON (the manifest's "config"; read back by the report).
nlohmann::json batch_config_json(const BatchScript& script);

// Rebuilds a script from batch_config_json (no validation against the curriculum).
BatchScript batch_config_from_json(const nlohmann::json& config);

// A training trial's id: "SG/B1/003".
std::string batch_trial_id(const std::string& run, const std::string& context, int trial);

// Whether a name can name a folder or a file of the results (a trial id's segment, a figure's
// file): letters, digits, '.', '_' and '-', at most 200 of them (a file system takes 255 bytes a
// name, and the atomic writers add a suffix to their temporaries: found by a probe, a figure named
// with 300 letters passed roger check and stopped the run at its report), and not '.' or '..'.
bool results_name(const std::string& name);
// An evaluation trial's id: "eval/generalization/circle/003".
std::string batch_eval_id(const std::string& evaluation, const std::string& shape, int trial);
// The group name of an evaluation's shape ("all" when it names no shapes).
std::vector<std::string> batch_eval_groups(const BatchEvaluation& evaluation);

}  // namespace roger
