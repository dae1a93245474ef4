// roger: the command-line program. main() declares each subcommand's arguments and calls its
// command (commands.h); every user error ends in one clear message on standard error and a
// non-zero exit, never a crash.
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "cli/cli_internal.h"
#include "cli/commands.h"
#include "core/error.h"

namespace {

using namespace roger;

// --lua-instructions and --lua-memory, for commands that run scripts.
void add_lua_limits(CLI::App* c, LuaLimitArgs& a, const char* whose) {
  c->add_option("--lua-instructions", a.instructions,
                std::string("Lua instruction budget per call into a script (default 50000000") + whose + ")")
      ->check(CLI::Range(uint64_t(1000), uint64_t(1) << 53));
  c->add_option("--lua-memory", a.memory_mib,
                std::string("Memory cap of each script's Lua state, in MiB (default 256") + whose + ")")
      ->check(CLI::Range(uint64_t(16), uint64_t(1) << 20));
}

// The flags of the commands that train (train, run): one declaration, one help text each.
void add_training_flags(CLI::App* c, bool& no_eval_cache, bool& explain) {
  c->add_flag("--no-eval-cache", no_eval_cache,
              "Run every greedy evaluation episode instead of reusing those the unchanged policy would "
              "repeat (identical results, slower: a check of the cache)");
  c->add_flag("--explain", explain,
              "Say what each training trial's data shows (greedy cycles, actions never run, time-outs) even "
              "when it reached its threshold; a trial that missed it always says why");
}

CLI::App* add_render(CLI::App& app, RenderArgs& a) {
  auto* c = app.add_subcommand("render", "Draw a scenario's world for one seed (PNG or SVG)");
  c->add_option("scenario", a.scenario, "Scenario script (.lua)")->required();
  c->add_option("--seed", a.seed, "World seed")->capture_default_str();
  c->add_option("--out", a.out, "Output picture (.png or .svg)")->required();
  c->add_option("--set", a.sets, "Scenario parameter key=value (repeatable)");
  c->add_option("--width", a.width, "Picture width in pixels")->capture_default_str()->check(CLI::Range(200, 8000));
  c->add_option("--seconds", a.seconds, "Simulate this long (Roger idle) first")->check(CLI::Range(0.0, 3600.0));
  c->add_flag("--grid", a.grid, "Draw the metric grid across the floor");
  c->add_option("--policy", a.policy,
                "With a skill script: render an episode of this policy; with a curriculum: the greedy "
                "episode of a policy.json written by roger train (a folder with frames and a replay "
                "page, or a .png summary)");
  c->add_option("--scenario", a.world, "The episode's scenario (default: the policy's)");
  c->add_option("--every", a.every, "Seconds between recorded frames")
      ->capture_default_str()->check(CLI::Range(0.02, 10.0));
  return c;
}

CLI::App* add_check(CLI::App& app, CheckArgs& a) {
  auto* c = app.add_subcommand("check", "Load and validate a script without running an episode");
  c->add_option("script", a.script, "Script (.lua)")->required();
  c->add_option("--set", a.sets, "Scenario parameter key=value (repeatable)");
  c->add_option("--seeds", a.seeds, "Seeds to generate")->capture_default_str()->check(CLI::Range(1, 100000));
  add_lua_limits(c, a.lua, "; a batch script's own limits otherwise");
  return c;
}

CLI::App* add_eval(CLI::App& app, EvalArgs& a, CLI::Option*& seed) {
  auto* c = app.add_subcommand("eval", "Evaluate a policy of a skill script over seeded episodes");
  c->add_option("script", a.script, "Skill script (.lua)")->required();
  c->add_option("--policy", a.policy,
                "Policy name in the skill script, or with a curriculum a policy.json written by roger train")
      ->required();
  c->add_option("--scenario", a.scenario, "Scenario (default: the policy's)");
  c->add_option("--set", a.sets, "Scenario parameter key=value (repeatable)");
  c->add_option("--skill", a.skills,
                "With a saved policy: a learned skill's policy NAME=FILE.json instead of the one it embeds "
                "(repeatable), e.g. a Phi_SG retrained on another body");
  c->add_option("--episodes", a.episodes, "Episodes")->capture_default_str()->check(CLI::Range(1, 1000000));
  seed = c->add_option("--seed", a.seed, "First seed (then seed+1, ...); with a saved "
                       "policy the default is its stage's held-out seeds")->capture_default_str();
  c->add_flag("--json", a.json, "End with one JSON line of the figures");
  add_lua_limits(c, a.lua, "");
  return c;
}

CLI::App* add_train(CLI::App& app, TrainArgs& a) {
  auto* c = app.add_subcommand("train", "Train one stage and context of a curriculum for one seed");
  c->add_option("curriculum", a.curriculum, "Curriculum script (.lua)")->required();
  c->add_option("--stage", a.stage, "Stage name (e.g. SG)")->required();
  c->add_option("--context", a.context, "Developmental context (e.g. DC2)")->required();
  c->add_option("--seed", a.seed, "Trial seed")->capture_default_str();
  c->add_option("--out", a.out, "Output folder")->required();
  c->add_flag("--json", a.json, "End with one JSON line of the figures");
  c->add_option("--skill", a.skills,
                "A learned skill's policy NAME=FILE.json (repeatable; default: train its stage first)");
  c->add_option("--set", a.sets, "Scenario parameter key=value (repeatable)");
  add_training_flags(c, a.no_eval_cache, a.explain);
  add_lua_limits(c, a.lua, "");
  return c;
}

CLI::App* add_propose(CLI::App& app, ProposeArgs& a) {
  auto* c = app.add_subcommand("propose", "Propose a developmental curriculum for a stage by a budgeted search");
  c->add_option("curriculum", a.curriculum, "Curriculum script (.lua)")->required();
  c->add_option("--stage", a.stage, "The task stage (e.g. T)")->required();
  c->add_option("--context", a.context, "The starting Psi: a context of the stage (default: its first)");
  c->add_option("--budget", a.budget, "Simulated seconds of training the whole search may spend")
      ->required()->check(CLI::PositiveNumber);
  c->add_option("--out", a.out, "Folder of the proposal, its report and the search's records (re-run resumes)")->required();
  c->add_option("--seed", a.seed, "Search seed")->capture_default_str();
  c->add_option("--trials", a.trials, "Seeded trials per candidate and round")->capture_default_str()->check(CLI::Range(1, 100));
  c->add_option("--probe-trials", a.probe_trials, "Trials of the probe")->capture_default_str()->check(CLI::Range(1, 100));
  c->add_option("--probe-share", a.probe_share, "Share of the budget for the probe")->capture_default_str()->check(CLI::Range(0.01, 0.9));
  c->add_option("--max-candidates", a.max_candidates, "Candidates evaluated")->capture_default_str()->check(CLI::Range(1, 64));
  c->add_option("--prune-below", a.prune_below, "Prune actions running under this share of successful time")
      ->capture_default_str()->check(CLI::Range(0.0, 1.0));
  return c;
}

CLI::App* add_run(CLI::App& app, RunArgs& a) {
  auto* c = app.add_subcommand("run", "Run a batch script: many seeded trials in parallel, then the report");
  c->add_option("script", a.script, "Batch script (.lua), or a name in scripts/")->required();
  c->add_option("--trials", a.trials, "Trials per run (overrides the script)")->check(CLI::Range(1, 100000));
  c->add_option("--jobs", a.jobs, "Worker threads (default: all cores)")->check(CLI::Range(1, 1024));
  c->add_option("--out", a.out, "Results folder (default: results/<script name>)");
  c->add_option("--set", a.sets, "Scenario parameter key=value for every run (repeatable)");
  c->add_option("--only", a.only, "Only this run, RUN/CONTEXT, or eval/NAME (repeatable)");
  c->add_flag("--live", a.live, "A live progress bar (default on a terminal)");
  c->add_flag("--no-report", a.no_report, "Skip the report at the end");
  add_training_flags(c, a.no_eval_cache, a.explain);
  c->add_option("--shard", a.shard,
                "Run only shard K/N (0-based) of the trials, or 'slurm' inside a Slurm job array; "
                "shards share one results folder, and roger report writes the report when all are done");
  add_lua_limits(c, a.lua, ", or the batch script's limits; recorded in the results folder");
  return c;
}

CLI::App* add_report(CLI::App& app, ReportArgs& a) {
  auto* c = app.add_subcommand("report", "Write tables and figures from a results folder");
  c->add_option("dir", a.dir, "Results folder")->required();
  c->add_flag("--partial", a.partial, "Report even when some trials have no result yet (marked pending)");
  return c;
}

CLI::App* add_bench(CLI::App& app, BenchArgs& a) {
  auto* c = app.add_subcommand("bench", "Measure simulated seconds per wall second, per layer");
  c->add_option("--scenario", a.scenario, "Scenario script")->capture_default_str();
  c->add_option("--seed", a.seed, "World seed")->capture_default_str();
  c->add_option("--seconds", a.seconds, "Simulated seconds per measurement")
      ->capture_default_str()->check(CLI::Range(1.0, 1e6));
  c->add_option("--repeats", a.repeats, "Measurements per layer (best kept)")
      ->capture_default_str()->check(CLI::Range(1, 1000));
  c->add_flag("--json", a.json, "End with one JSON line of the figures");
  c->add_option("--script", a.script, "Skill script for the pipeline measurement")->capture_default_str();
  c->add_option("--policy", a.policy, "Its policy")->capture_default_str();
  c->add_option("--episodes", a.episodes, "Pipeline episodes (seeds from --seed)")
      ->capture_default_str()->check(CLI::Range(1, 10000));
  return c;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"roger: a simulated mobile manipulator that learns hierarchical skills through "
               "developmental curricula"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("roger ") + ROGER_VERSION);
  RenderArgs render_args;
  CheckArgs check_args;
  EvalArgs eval_args;
  TrainArgs train_args;
  RunArgs run_args;
  ReportArgs report_args;
  BenchArgs bench_args;
  ProposeArgs propose_args;
  CLI::Option* eval_seed = nullptr;
  auto* render = add_render(app, render_args);
  auto* check = add_check(app, check_args);
  auto* eval = add_eval(app, eval_args, eval_seed);
  auto* train = add_train(app, train_args);
  auto* run = add_run(app, run_args);
  auto* report = add_report(app, report_args);
  auto* bench = add_bench(app, bench_args);
  auto* propose = add_propose(app, propose_args);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (*render) return command_render(render_args);
    if (*check) return command_check(check_args);
    if (*bench) return command_bench(bench_args);
    if (*eval) {
      eval_args.seed_given = eval_seed->count() > 0;
      return command_eval(eval_args);
    }
    if (*train) return command_train(train_args);
    if (*run) {
      if (!run->count("--live")) run_args.live = isatty(fileno(stderr)) != 0;
      return command_run(run_args);
    }
    if (*report) return command_report(report_args);
    if (*propose) return command_propose(propose_args);
  } catch (const FileError& e) {
    std::fflush(stdout);
    std::cerr << "roger: error: " << file_error_line(e, false) << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::cerr << "roger: error: " << e.what() << "\n";
    return 1;
  }
  return 2;
}
