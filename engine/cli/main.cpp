// roger: the command-line program. main() declares each subcommand's arguments and calls its
// command (commands.h); every user error ends in one clear message on standard error and a
// non-zero exit, never a crash.
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "batch/batch.h"
#include "cli/cli_internal.h"
#include "cli/commands.h"
#include "core/error.h"
#include "core/text.h"
#include "script/batch/batch_script.h"
#include "script/curriculum/curriculum.h"
#include "script/sandbox/lua_sandbox.h"
#include "script/scenario/scenario.h"

namespace {

using namespace roger;

// Checks of number options that say what was expected. CLI11's Range lets NaN through, calls "abc"
// out of range and prints a bound of 1e308 in 309 digits; its unsigned integers read -1 as 2^64 - 1.
CLI::Validator number_in(double lo, double hi, bool lo_open = false) {
  const std::string range = (lo_open ? "above " + format_number(lo) : "from " + format_number(lo)) +
                            (std::isinf(hi) ? std::string() : " to " + format_number(hi));
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        const bool number = !text.empty() && *end == '\0' && std::isfinite(v);
        if (number && (lo_open ? v > lo : v >= lo) && v <= hi) return "";
        return "expected a number " + range + ", got '" + text + "'";
      },
      "NUMBER " + range);
}

CLI::Validator integer_in(uint64_t lo, uint64_t hi) {
  const std::string range = "from " + std::to_string(lo) + " to " + std::to_string(hi);
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        errno = 0;
        char* end = nullptr;
        const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
        const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
        if (digits && *end == '\0' && errno == 0 && v >= lo && v <= hi) return "";
        return "expected a whole number " + range + ", got '" + text + "'";
      },
      "INTEGER " + range);
}

// A path: not empty (`--out ""` wrote to the default folder).
CLI::Validator path_value() {
  return CLI::Validator([](std::string& text) { return text.empty() ? std::string("expected a path, got ''") : std::string(); },
                        "PATH");
}

// A name given: not empty (found by a probe: `roger propose --context ''` searched from the stage's
// first context, as if the option were left out, where --stage '' was refused).
CLI::Validator name_value(const char* what) {
  return CLI::Validator([what](std::string& text) {
    return text.empty() ? "expected " + std::string(what) + ", got ''" : std::string();
  }, "NAME");
}

// --shard: K/N with 0 <= K < N, or slurm (read from the job's environment when the run starts).
CLI::Validator shard_value() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if (text == "slurm") return "";
        try {
          parse_shard(text);
          return "";
        } catch (const Error&) {
          return "expected K/N with 0 <= K < N (e.g. 0/4), or slurm, got '" + text + "'";
        }
      },
      "K/N|slurm");
}

// A seed: any whole number a 64-bit unsigned integer holds.
CLI::Validator seed_value() { return integer_in(0, UINT64_MAX); }

// A repeatable option: one value per occurrence, all occurrences kept. CLI11 lets an option bound
// to a vector take every word up to the next option, so `--set a=1 SCRIPT` swallowed the script.
CLI::Option* repeatable(CLI::Option* o) {
  return o->expected(1)->allow_extra_args(false)->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

// --set key=value, repeatable; a word without its '=' (or without a key) is the parser's refusal,
// status 2 as every malformed option's (found by a probe: `--set mass` exited 1, as a script's
// mistake does).
// A key=value word (`shown` in the help, `expected` in the refusal); with needs_value, a value too.
CLI::Validator key_value(const char* shown, const char* expected, bool needs_value = false) {
  return CLI::Validator(
      [expected, needs_value](std::string& kv) -> std::string {
        const size_t eq = kv.find('=');
        if (eq == std::string::npos || eq == 0) return std::string("expected ") + expected + ", got '" + kv + "'";
        return needs_value && eq + 1 == kv.size() ? std::string("expected ") + expected + ", got '" + kv + "' (no file)"
                                                  : "";
      },
      shown);
}

void add_sets(CLI::App* c, std::vector<std::string>& sets, const char* help) {
  repeatable(c->add_option("--set", sets, help))->check(key_value("KEY=VALUE", "key=value"));
}

// --skill NAME=FILE.json, repeatable, checked as --set is (found by a probe: `--skill Phi_SG` exited 1).
void add_skills(CLI::App* c, std::vector<std::string>& skills, const char* help) {
  repeatable(c->add_option("--skill", skills, help))->check(key_value("NAME=FILE.json", "NAME=FILE.json", true));
}

// --lua-instructions and --lua-memory, for commands that run scripts.
void add_lua_limits(CLI::App* c, LuaLimitArgs& a, const char* whose) {
  c->add_option("--lua-instructions", a.instructions,
                std::string("Lua instruction budget per call into a script (default 50000000") + whose + ")")
      ->check(integer_in(1000, uint64_t(1) << 53));
  c->add_option("--lua-memory", a.memory_mib,
                std::string("Memory cap of each script's Lua state, in MiB (default 256") + whose + ")")
      ->check(integer_in(16, uint64_t(1) << 20));
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
  auto* c = app.add_subcommand("render", "Draw a scenario's world for one seed (PNG or SVG), or record a policy's episode");
  c->add_option("scenario", a.scenario,
                "Scenario script (.lua); with --policy, a skill script or a curriculum (for a policy.json)")
      ->required();
  c->add_option("--seed", a.seed, "World seed")->capture_default_str()->check(seed_value());
  c->add_option("--out", a.out, "Output picture (.png or .svg); with --policy, a folder or a .png summary")
      ->check(path_value())->required();
  add_sets(c, a.sets, "Scenario parameter key=value (repeatable)");
  // render.cpp's range, as Python's render_width has it.
  c->add_option("--width", a.width, "Picture width in pixels (of each frame of an episode's strip)")
      ->capture_default_str()
      ->check(integer_in(100, 16000));
  c->add_option("--seconds", a.seconds, "Simulate this long (Roger idle) first")->check(number_in(0.0, 3600.0));
  c->add_flag("--grid", a.grid, "Draw the metric grid across the floor");
  c->add_option("--policy", a.policy,
                "With a skill script: render an episode of this policy; with a curriculum: the greedy "
                "episode of a policy.json written by roger train (a folder with frames and a replay "
                "page, or a .png summary)");
  c->add_option("--scenario", a.world, "The episode's scenario (default: the policy's)");
  add_skills(c, a.skills,
                           "With a saved policy: a learned skill's policy NAME=FILE.json instead of the one it embeds "
                           "(repeatable), as roger eval takes it");
  c->add_option("--test-task", a.test_task,
                "With a saved policy of a stage that teaches: task K (from 1) of the test set its trial ended on, "
                "in that task's world seed")
      ->check(integer_in(1, 1000000));
  c->add_option("--every", a.every, "Seconds between recorded frames")
      ->capture_default_str()->check(number_in(0.02, 10.0));
  add_lua_limits(c, a.lua, "");
  return c;
}

CLI::App* add_check(CLI::App& app, CheckArgs& a) {
  auto* c = app.add_subcommand("check", "Load and validate a script without running an episode");
  c->add_option("scripts", a.scripts, "Scripts (.lua): each is checked")->required();
  add_sets(c, a.sets, "Scenario parameter key=value (repeatable)");
  c->add_option("--seeds", a.seeds, "Seeds to generate")->capture_default_str()->check(integer_in(1, 100000));
  add_lua_limits(c, a.lua, "; a batch script's own limits otherwise");
  return c;
}

CLI::App* add_eval(CLI::App& app, EvalArgs& a, CLI::Option*& seed) {
  auto* c = app.add_subcommand("eval", "Evaluate a policy of a skill script, or one saved by roger train, over seeded episodes");
  c->add_option("script", a.script, "Skill script (.lua), or the curriculum of a policy.json")->required();
  // Required, and refused without naming what it could be by the command (require_policy).
  c->add_option("--policy", a.policy,
                "Policy name in the skill script, or with a curriculum a policy.json written by roger train "
                "(required)");
  c->add_option("--scenario", a.scenario, "Scenario (default: the policy's)");
  add_sets(c, a.sets, "Scenario parameter key=value (repeatable)");
  add_skills(c, a.skills,
                           "With a saved policy: a learned skill's policy NAME=FILE.json instead of the one it embeds "
                           "(repeatable), e.g. a Phi_SG retrained on another body");
  c->add_option("--episodes", a.episodes,
                "Episodes (default 50; of a saved policy, its stage's final evaluation's, 50 unless the stage sets "
                "checkpoints.final)")
      ->check(integer_in(1, 1000000));
  seed = c->add_option("--seed", a.seed, "First seed (then seed+1, ...); with a saved "
                       "policy the default is its stage's held-out seeds")->capture_default_str()->check(seed_value());
  c->add_flag("--test-set", a.test_set,
              "With a saved policy of a stage that teaches: the test set its trials ended on (its tasks and "
              "world seeds) instead of --episodes from --seed");
  c->add_flag("--json", a.json, "End with one JSON line of the figures");
  add_lua_limits(c, a.lua, "");
  return c;
}

CLI::App* add_train(CLI::App& app, TrainArgs& a) {
  auto* c = app.add_subcommand("train", "Train one stage and context of a curriculum for one seed");
  c->add_option("curriculum", a.curriculum, "Curriculum script (.lua)")->required();
  // Not CLI11's required(): left out, each is refused with the curriculum's choices (command_train).
  c->add_option("--stage", a.stage, "Stage name (e.g. SG); required");
  c->add_option("--context", a.context, "Developmental context (e.g. DC2); required");
  c->add_option("--seed", a.seed, "Trial seed")->capture_default_str()->check(seed_value());
  c->add_option("--out", a.out, "Output folder")->check(path_value())->required();
  c->add_flag("--json", a.json, "End with one JSON line of the figures");
  add_skills(c, a.skills,
                           "A learned skill's policy NAME=FILE.json (repeatable; default: train its stage first)");
  add_sets(c, a.sets, "Scenario parameter key=value (repeatable)");
  c->add_option("--init", a.init,
                "A policy.json learned earlier: the Q-table starts from its values over the actions the two "
                "share by name (a warm start), the others at initial_q");
  add_training_flags(c, a.no_eval_cache, a.explain);
  add_lua_limits(c, a.lua, "");
  return c;
}

CLI::App* add_propose(CLI::App& app, ProposeArgs& a) {
  auto* c = app.add_subcommand("propose", "Propose a developmental curriculum for a stage by a budgeted search");
  c->add_option("curriculum", a.curriculum, "Curriculum script (.lua)")->required();
  c->add_option("--stage", a.stage, "The task stage (e.g. T)")->required();
  c->add_option("--context", a.context, "The starting Psi: a context of the stage (default: its first)")
      ->check(name_value("a context's name (leave --context out for the stage's first)"));
  c->add_option("--budget", a.budget, "Simulated seconds of training the whole search may spend")
      ->required()->check(number_in(0.0, 1e9, true));  // propose_curriculum's bound, the parser's refusal (status 2)
  c->add_option("--out", a.out, "Folder of the proposal, its report and the search's records (re-run resumes)")->check(path_value())->required();
  add_lua_limits(c, a.lua, "");
  c->add_option("--seed", a.seed, "Search seed")->capture_default_str()->check(seed_value());
  c->add_option("--trials", a.trials, "Seeded trials per candidate and round")->capture_default_str()->check(integer_in(1, 100));
  c->add_option("--probe-trials", a.probe_trials, "Trials of the probe")->capture_default_str()->check(integer_in(1, 100));
  c->add_option("--probe-share", a.probe_share, "Share of the budget for the probe")->capture_default_str()->check(number_in(0.01, 0.9));
  c->add_option("--max-candidates", a.max_candidates, "Candidates evaluated")->capture_default_str()->check(integer_in(1, 64));
  c->add_option("--prune-below", a.prune_below, "Prune actions running under this share of successful time")
      ->capture_default_str()->check(number_in(0.0, 1.0));
  return c;
}

CLI::App* add_run(CLI::App& app, RunArgs& a) {
  auto* c = app.add_subcommand("run", "Run a batch script: many seeded trials in parallel, then the report");
  c->add_option("script", a.script, "Batch script (.lua), or a name in scripts/")->required();
  c->add_option("--trials", a.trials, "Trials per run (overrides the script)")->check(integer_in(1, 100000));
  c->add_option("--jobs", a.jobs, "Worker threads (default: all cores)")->check(integer_in(1, 1024));
  c->add_option("--out", a.out,
                "Results folder (default: results/<name>, the batch script's name field, which roger check shows)")
      ->check(path_value());
  add_sets(c, a.sets, "Scenario parameter key=value for every run (repeatable)");
  repeatable(c->add_option("--only", a.only, "Only this run, RUN/CONTEXT, or eval/NAME (repeatable)"));
  c->add_flag("--live", a.live, "A live progress bar (default on a terminal)");
  c->add_flag("--no-report", a.no_report, "Skip the report at the end");
  add_training_flags(c, a.no_eval_cache, a.explain);
  c->add_option("--shard", a.shard,
                "Run only shard K/N (0-based) of the trials, or 'slurm' inside a Slurm job array; "
                "shards share one results folder, and roger report writes the report when all are done")
      ->check(shard_value());
  c->add_flag("--dry-run", a.dry_run,
              "Check what the run checks before its trials (the script, --only, the results folder as this "
              "command would open it) and say what it would do there, writing nothing and running no trial");
  add_lua_limits(c, a.lua, ", or the batch script's limits; recorded in the results folder");
  return c;
}

CLI::App* add_report(CLI::App& app, ReportArgs& a) {
  auto* c = app.add_subcommand("report", "Write tables and figures from a results folder");
  c->add_option("dir", a.dir, "Results folder")->required();
  c->add_flag("--partial", a.partial, "Report even when some trials have no result yet (marked pending)");
  repeatable(c->add_option("--by", a.by,
                           "After each run's table, its final success split by this feature of the episodes' "
                           "worlds or tasks (obstacles, objects, shape, or a task parameter); repeatable"));
  return c;
}

CLI::App* add_bench(CLI::App& app, BenchArgs& a) {
  auto* c = app.add_subcommand("bench", "Measure simulated seconds per wall second, per layer");
  c->add_option("--scenario", a.scenario, "Scenario script")->capture_default_str();
  c->add_option("--seed", a.seed, "World seed")->capture_default_str()->check(seed_value());
  c->add_option("--seconds", a.seconds, "Simulated seconds per measurement")
      ->capture_default_str()->check(number_in(1.0, 1e6));
  c->add_option("--repeats", a.repeats, "Measurements per layer (best kept)")
      ->capture_default_str()->check(integer_in(1, 1000));
  c->add_flag("--json", a.json, "End with one JSON line of the figures");
  c->add_option("--script", a.script, "Skill script for the pipeline measurement")->capture_default_str();
  c->add_option("--policy", a.policy, "Its policy")->capture_default_str();
  c->add_option("--episodes", a.episodes, "Pipeline episodes (seeds from --seed)")
      ->capture_default_str()->check(integer_in(1, 10000));
  add_lua_limits(c, a.lua, "");
  return c;
}

// train and eval take a curriculum (eval a skill script too), and a scenario or a batch script
// given instead fails inside it: named as what it is (require_script_kind). A name that finds no
// file is left to the command, which says where it looked.
void require_curriculum(const std::string& given, const std::vector<std::string>& wanted) {
  std::string path;
  try {
    path = resolve_curriculum_path(given);
  } catch (const Error&) {
    return;
  }
  require_script_kind(given, path, wanted);
}

// A --scenario option given a script of another kind failed inside it (found by a probe: eval
// --scenario curricula/paper.lua said "curricula/lib/skills.lua:45: attempt to call a nil value"),
// so it is named as what it is. Empty (the policy's own) or a name that finds no file is left to
// the command.
void require_scenario_option(const std::string& given) {
  if (given.empty()) return;
  std::string path;
  try {
    path = resolve_scenario_path(given);
  } catch (const Error&) {
    return;
  }
  require_script_kind(given, path, {"scenario"}, "--scenario");
}

// Options of roger render that the other form does not read, refused rather than ignored (found by
// a probe: `roger render cluttered --scenario unobstructed` drew cluttered, and `--grid` or
// `--seconds` with --policy changed nothing).
void refuse_render_options_unused(const CLI::App& render, const RenderArgs& a) {
  const bool episode = !a.policy.empty();
  for (const char* option : {"--scenario", "--test-task", "--every"})
    if (!episode && render.count(option) > 0)
      throw Error(std::string("roger render: ") + option + " is an option of an episode's recording (--policy); "
                  "without it roger render draws one world of " + a.scenario);
  for (const char* option : {"--seconds", "--grid"})
    if (episode && render.count(option) > 0)
      throw Error(std::string("roger render: ") + option + " is an option of a world's picture (without --policy); " +
                  (std::string(option) == "--grid" ? "an episode's frames are drawn without the grid"
                                                   : "an episode is recorded from its start to its end"));
}

// render draws a scenario's world, or with --policy an episode of a skill script's or curriculum's
// policy: a script of the other kind fails inside (found by a probe: a skill script without
// --policy failed in curricula/lib/skills.lua, "attempt to call a nil value (field 'primitive')").
void require_render_kind(const RenderArgs& a) {
  if (!a.policy.empty()) return require_curriculum(a.scenario, {"curriculum", "skill script"});
  std::string path;
  try {
    path = resolve_scenario_path(a.scenario);
  } catch (const Error&) {
    return;
  }
  const std::string kind = script_kind(path);
  if (kind == "skill script" || kind == "curriculum")
    throw Error(a.scenario + " is a " + kind + ", and without --policy roger render draws a scenario's world: give "
                "--policy " + (kind == "curriculum" ? "FILE.json (a policy roger train wrote)" : "NAME (one of its "
                "policies)") + " to record an episode, or name a scenario");
  if (kind == "batch script") require_script_kind(a.scenario, path, {"scenario"});
}

// The first word CLI11 would misname: an unknown command (it says "A subcommand is required") or
// an unknown option of the command (it names a missing required option instead). Empty when every
// option word is one the command declares.
std::string unknown_word(const std::vector<CLI::App*>& commands, int argc, char** argv) {
  if (argc < 2) return "";
  const std::string first = argv[1];
  if (first == "-h" || first == "--help" || first == "--version") return "";
  std::string names;
  std::vector<std::string> command_names;
  const CLI::App* command = nullptr;
  for (const auto* c : commands) {
    names += (names.empty() ? "" : ", ") + c->get_name();
    command_names.push_back(c->get_name());
    if (c->get_name() == first) command = c;
  }
  if (!command)
    return std::string(first[0] == '-' ? "unknown option '" : "unknown command '") + first + "'" +
           suggestion(first, command_names) + "; the commands are " + names + " (see roger --help)";
  std::vector<std::string> options;
  for (const CLI::Option* o : command->get_options())
    for (const std::string& n : o->get_lnames()) options.push_back("--" + n);
  for (int i = 2; i < argc; ++i) {
    const std::string word = argv[i];
    if (word == "--") break;
    if (word.size() < 3 || word.compare(0, 2, "--") != 0) continue;
    const std::string name = word.substr(0, word.find('='));
    const CLI::Option* option = command->get_option_no_throw(name);
    if (!option)
      return "unknown option '" + name + "' of roger " + first + suggestion(name, options) + " (see roger " + first +
             " --help)";
    // Found by a probe: CLI11 takes the next word as the value whatever it is, so `--out
    // --no-report` wrote a results folder named --no-report.
    const std::string next = i + 1 < argc ? argv[i + 1] : "";
    if (word.find('=') == std::string::npos && option->get_items_expected_min() > 0 && next.size() > 2 &&
        next.compare(0, 2, "--") == 0)
      return "option '" + name + "' of roger " + first + " expects a value, and the next word is the option '" + next +
             "': give " + name + " its value";
  }
  return "";
}

// Every command's arguments, and the command as CLI11 has it (set when it was given).
struct Commands {
  RenderArgs render_args;
  CheckArgs check_args;
  EvalArgs eval_args;
  TrainArgs train_args;
  RunArgs run_args;
  ReportArgs report_args;
  BenchArgs bench_args;
  ProposeArgs propose_args;
  CLI::Option* eval_seed = nullptr;
  CLI::App *render = nullptr, *check = nullptr, *eval = nullptr, *train = nullptr, *run = nullptr, *report = nullptr,
           *bench = nullptr, *propose = nullptr;

  explicit Commands(CLI::App& app)
      : render(add_render(app, render_args)),
        check(add_check(app, check_args)),
        eval(add_eval(app, eval_args, eval_seed)),
        train(add_train(app, train_args)),
        run(add_run(app, run_args)),
        report(add_report(app, report_args)),
        bench(add_bench(app, bench_args)),
        propose(add_propose(app, propose_args)) {}
  Commands(const Commands&) = delete;  // CLI11 writes into the members above, where they are
  std::vector<CLI::App*> all() const { return {render, check, eval, train, run, report, bench, propose}; }
};

// Parses the command line: -1 when a command is to run, else the exit status (bad usage exits 2,
// as docs/cli.md says, where CLI11's own codes are 100 and more; help exits 0).
int parse_command_line(CLI::App& app, const Commands& commands, int argc, char** argv) {
  const std::string unknown = unknown_word(commands.all(), argc, argv);
  if (!unknown.empty()) {
    std::cerr << "roger: error: " << unknown << "\n";
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ArgumentMismatch& e) {
    // "--context: At Most 1 required but received 2" in words (found by a probe).
    const std::string text = e.what(), said = ": At Most 1 required but received ";
    const size_t at = text.find(said);
    if (at == std::string::npos) return app.exit(e) == 0 ? 0 : 2;
    std::cerr << "roger: error: " << text.substr(0, at) << " is given " << text.substr(at + said.size())
              << " times, and takes one value: give it once (a batch script runs several contexts, seeds or "
                 "policies: docs/batch.md)\n";
    return 2;
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  return -1;
}

// Runs the command given, after the checks of its options that need to know which were given.
int run_command(Commands& c) {
  if (*c.render) {
    c.render_args.seed_given = c.render->count("--seed") > 0;
    refuse_render_options_unused(*c.render, c.render_args);
    require_render_kind(c.render_args);
    require_scenario_option(c.render_args.world);
    return command_render(c.render_args);
  }
  if (*c.check) return command_check(c.check_args);
  if (*c.bench) {
    require_scenario_option(c.bench_args.scenario);
    // Its --script is a skill script: a curriculum or a scenario failed inside it (found by a probe).
    require_curriculum(c.bench_args.script, {"skill script"});
    return command_bench(c.bench_args);
  }
  if (*c.eval) {
    c.eval_args.seed_given = c.eval_seed->count() > 0;
    c.eval_args.episodes_given = c.eval->count("--episodes") > 0;
    require_curriculum(c.eval_args.script, {"curriculum", "skill script"});
    require_scenario_option(c.eval_args.scenario);
    return command_eval(c.eval_args);
  }
  if (*c.train) {
    require_curriculum(c.train_args.curriculum, {"curriculum"});
    return command_train(c.train_args);
  }
  if (*c.run) {
    if (!c.run->count("--live")) c.run_args.live = isatty(fileno(stderr)) != 0;
    return command_run(c.run_args);
  }
  if (*c.report) return command_report(c.report_args);
  if (*c.propose) return command_propose(c.propose_args);
  return 2;
}

// What a command printed must have reached its standard output: `roger eval --json > r.json` on a
// full disk would otherwise leave a cut JSON and exit 0 (found by a probe with /dev/full).
int with_output_written(int status) {
  errno = 0;
  std::cout.flush();
  if (std::fflush(stdout) == 0 && !std::ferror(stdout) && std::cout.good()) return status;
  const int cause = errno;
  std::cerr << "roger: error: could not write the standard output"
            << (cause != 0 ? std::string(" (") + std::strerror(cause) + ")" : std::string())
            << ": what the command printed there is incomplete\n";
  return status == 0 ? 1 : status;
}

int run_checked(Commands& commands) {
  try {
    return run_command(commands);
  } catch (const CommandLineError& e) {
    std::fflush(stdout);
    std::cerr << error_line(printable_text(e.what())) << "\nRun with --help for more information.\n";
    return 2;
  } catch (const FileError& e) {
    std::fflush(stdout);
    std::cerr << error_line(file_error_line(e, false)) << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::cerr << error_line(printable_text(e.what())) << "\n";
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"roger: a simulated mobile manipulator that learns hierarchical skills through "
               "developmental curricula"};
  app.require_subcommand(1);
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return std::string("roger: error: ") + e.what() + "\nRun with --help for more information.\n";
  });
  // With the project folder in use: a copy of bin/roger alone silently used the source tree.
  app.set_version_flag("--version", [] { return std::string("roger ") + ROGER_VERSION + " (project folder: " +
                                                project_in_use() + ")"; });
  Commands commands(app);
  if (const int status = parse_command_line(app, commands, argc, argv); status >= 0)
    return with_output_written(status);
  return with_output_written(run_checked(commands));
}
