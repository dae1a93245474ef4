// commands.h: the commands of the `roger` program, one function each, with their arguments.
// Owns: what a command prints and its exit status. Everything else is the engine's: a command is
// a thin layer over batch, report, view and script. docs/cli.md describes every command.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

namespace roger {

// --lua-instructions N and --lua-memory MIB: the sandbox's budgets for every script a command runs
// (0: the default, or for roger run the batch script's own `limits`).
struct LuaLimitArgs {
  uint64_t instructions = 0;  // VM instructions per call from the engine
  uint64_t memory_mib = 0;    // the Lua state's memory cap, MiB
};

// The arguments of `roger run SCRIPT.lua [--trials N] [--jobs J] [--out DIR] [--set k=v]... [--only NAME]... [--live]`.
struct RunArgs {
  std::string script;               // batch script path, or a bare name in scripts/ ("paper", "quick")
  int trials = 0;                   // > 0: overrides every run's trial count
  int jobs = 0;                     // worker threads; 0 = all cores
  std::string out;                  // results folder; "" = results/<the batch script's name>
  std::vector<std::string> sets;    // "key=value" scenario parameters for every training run
  std::vector<std::string> only;    // run only these: "RUN", "RUN/CONTEXT" or "eval/NAME" (empty = all)
  bool live = false;                // redraw one live progress line (a terminal) instead of plain lines
  bool no_report = false;           // skip the report at the end
  int max_trials = 0;               // > 0: stop after starting this many new trials (tests, partial runs)
  std::string shard;                // "K/N" or "slurm": only that shard's trials, and no report ("" = all)
  bool no_eval_cache = false;       // run every greedy evaluation episode (same results, slower)
  bool explain = false;             // every training trial's result.json says why, reached or not
  bool dry_run = false;             // check everything a run checks before its trials, folder too; run none
  LuaLimitArgs lua;                 // over the script's limits
  std::ostream* progress = nullptr; // where progress and messages go (nullptr = standard error)
};

// The arguments of `roger report DIR`.
struct ReportArgs {
  std::string dir;                  // a results folder written by roger run
  bool partial = false;             // report what is there even when trials have no result yet
  std::vector<std::string> by;      // also split each run's final success by these recorded features
  std::ostream* progress = nullptr; // where messages go (nullptr = standard error)
};

// Runs a batch script into its results folder and then writes the report. Returns the exit status:
// 0 when every trial succeeded, 1 when some failed (listed) or the input is bad (message printed).
int command_run(const RunArgs& args);

// Writes summary.csv, tables.md and the figures of a results folder. Returns 0; or 1 with a message,
// writing nothing, when the folder is unreadable or (without `partial`) some trials have no
// result yet: those are listed, each with the shard that owns it.
int command_report(const ReportArgs& args);

// The arguments of `roger render SCENARIO.lua --seed N --out FILE` (or a skill script's --policy episode).
struct RenderArgs {
  std::string scenario;
  uint64_t seed = 1;
  std::string out;
  std::vector<std::string> sets;
  int width = 1000;
  double seconds = 0.0;
  bool grid = false;
  std::string policy;         // with a skill script: render an episode of this policy
  std::string world;          // the scenario of that episode (default: the policy's)
  std::vector<std::string> skills;  // with a saved policy: NAME=FILE.json, a learned skill instead of the embedded one
  double every = 0.1;         // seconds between recorded frames
  int test_task = 0;          // with a saved policy of a teaching stage: its test set's task k (from 1)
  bool seed_given = false;
  LuaLimitArgs lua;
};

// Draws a scenario's world, or records an episode of a skill script's policy. Returns 0.
int command_render(const RenderArgs& args);

// The arguments of `roger check SCRIPT.lua`.
struct CheckArgs {
  std::vector<std::string> scripts;  // as given: each is checked
  std::string script;                // the one being checked
  std::vector<std::string> sets;
  int seeds = 20;
  LuaLimitArgs lua;
};

// Loads and validates a scenario, skill script or curriculum; returns 0, or 1 listing the problems.
int command_check(const CheckArgs& args);

// The arguments of `roger eval SCRIPT.lua --policy NAME|FILE.json`.
struct EvalArgs {
  std::string script;
  std::string policy;
  std::string scenario;
  std::vector<std::string> sets;
  std::vector<std::string> skills;  // NAME=FILE.json: a learned skill instead of the embedded one
  int episodes = 50;
  uint64_t seed = 1000;
  bool seed_given = false, episodes_given = false;
  bool test_set = false;  // a teaching stage's saved policy on its trials' final test set
  bool json = false;
  LuaLimitArgs lua;
};

// Evaluates a skill script's policy or a saved policy over seeded episodes. Returns 0.
int command_eval(const EvalArgs& args);

// The arguments of `roger train CURRICULUM.lua --stage S --context C --seed N --out DIR`.
struct TrainArgs {
  std::string curriculum;
  std::string stage, context;
  uint64_t seed = 1;
  std::string out;
  bool json = false;
  std::vector<std::string> skills;
  std::vector<std::string> sets;
  std::string init;            // a policy.json to start the Q-table from (TrainOptions::init_file)
  bool no_eval_cache = false;  // run every greedy evaluation episode (TrainOptions::eval_cache)
  bool explain = false;        // say why even when the threshold was reached (TrainOptions::explain)
  LuaLimitArgs lua;
};

// Trains one stage and context for one seed and writes its outputs. Returns 0.
int command_train(const TrainArgs& args);

// The arguments of `roger bench`.
struct BenchArgs {
  std::string scenario = "scenarios/unobstructed.lua";
  uint64_t seed = 1;
  double seconds = 300.0;
  int repeats = 5;
  bool json = false;
  std::string script = "curricula/scripted.lua";
  std::string policy = "task";
  int episodes = 20;
  LuaLimitArgs lua;           // for the scenario and the skill script given
};

// Measures simulated seconds per wall second of physics, senses and the whole pipeline. Returns 0.
int command_bench(const BenchArgs& args);

// The arguments of `roger propose CURRICULUM.lua --stage T --budget SECONDS --out DIR`.
struct ProposeArgs {
  std::string curriculum;
  std::string stage;
  std::string context;          // the starting Psi ("" = the stage's first context)
  double budget = 0.0;          // simulated seconds of training the search may spend
  std::string out;
  uint64_t seed = 1;
  int trials = 2;               // seeded trials per candidate and round
  int probe_trials = 2;
  double probe_share = 0.2;
  int max_candidates = 8;
  double prune_below = 0.05;
  LuaLimitArgs lua;
};

// Proposes a curriculum for a stage (engine/propose) and writes it with its report. Returns 0.
int command_propose(const ProposeArgs& args);

}  // namespace roger
