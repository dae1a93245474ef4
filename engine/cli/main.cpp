// roger: the command-line program. Each subcommand is a thin layer over the engine library; every
// user error ends in one clear message on standard error and a non-zero exit, never a crash.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "view/animation.h"
#include "cli/bench.h"
#include "cli/commands.h"
#include "script/curriculum.h"
#include "learn/episode.h"
#include "core/error.h"
#include "script/lua_sandbox.h"
#include "view/render.h"
#include "script/scenario.h"
#include "script/skill_script.h"
#include "batch/trainer.h"
#include "sim/world.h"

namespace {

using namespace roger;

// Applies `--set key=value` options to a scenario.
void apply_sets(Scenario& scenario, const std::vector<std::string>& sets) {
  for (const std::string& kv : sets) {
    const size_t eq = kv.find('=');
    if (eq == std::string::npos || eq == 0)
      throw Error("--set expects key=value, got '" + kv + "'");
    scenario.set_param(kv.substr(0, eq), kv.substr(eq + 1));
  }
}

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
  double every = 0.1;         // seconds between recorded frames
};

// The scenario a policy runs in: --scenario if given, else the policy's own, else unobstructed.
std::string policy_scenario(const SkillScript::NamedPolicy& p, const std::string& chosen) {
  if (!chosen.empty()) return chosen;
  return p.scenario.empty() ? "unobstructed" : p.scenario;
}

// Renders one episode of a skill script's policy: a folder with frames and a replay page, or
// (for a .png path) one summary strip.
int run_render_episode(const RenderArgs& a) {
  SkillScript script = SkillScript::load(a.scenario);
  const SkillScript::NamedPolicy& policy = script.policy(a.policy);
  Scenario scenario = Scenario::load(policy_scenario(policy, a.world));
  apply_sets(scenario, a.sets);
  const WorldSpec spec = scenario.generate(a.seed);
  EpisodeOptions options;
  options.time_limit = policy.time_limit;
  options.record_every = a.every;
  // Watch the named controllers (primitives, skills), at most a dozen, so the timeline stays legible.
  std::vector<ControllerPtr> watch = script.controllers();
  if (watch.size() > 12) watch.resize(12);
  Agent agent;
  const EpisodeResult episode = run_episode(agent, spec, a.seed, *policy.action, *policy.goal, options, watch);
  AnimationOptions anim;
  anim.frame.width_px = a.width;
  anim.frame.robot = agent.world().params().robot;
  anim.title = script.name() + ": " + policy.name + " in " + scenario.name() + ", seed " + std::to_string(a.seed);
  const bool summary = a.out.size() > 4 && a.out.compare(a.out.size() - 4, 4, ".png") == 0;
  if (summary) {
    render_episode_summary(spec, episode, a.out, anim);
  } else {
    render_episode(spec, episode, a.out, anim);
  }
  std::printf("wrote %s (%s after %.2f s, reward %.0f; %zu frames)\n", a.out.c_str(),
              episode.success ? "success" : "timeout", episode.sim_seconds, episode.reward,
              episode.frames.size());
  return 0;
}

int run_render(const RenderArgs& a) {
  if (!a.policy.empty()) return run_render_episode(a);
  Scenario scenario = Scenario::load(a.scenario);
  apply_sets(scenario, a.sets);
  const WorldSpec spec = scenario.generate(a.seed);
  World world;
  world.reset(spec);
  // Optionally let the world settle (Roger holds still) before the picture is taken.
  const int ticks = int(a.seconds / world.tick_seconds() + 0.5);
  for (int i = 0; i < ticks; ++i) world.tick();
  RenderOptions options;
  options.width_px = a.width;
  options.show_grid = a.grid;
  options.robot = world.params().robot;
  render_frame(spec, world.frame(), a.out, options);
  std::printf("wrote %s (%s, seed %llu)\n", a.out.c_str(), a.scenario.c_str(),
              static_cast<unsigned long long>(a.seed));
  return 0;
}

struct CheckArgs {
  std::string script;
  std::vector<std::string> sets;
  int seeds = 20;
};

int run_check(const CheckArgs& a) {
  if (is_curriculum_script(a.script)) {
    const std::vector<std::string> problems = check_curriculum(a.script);
    for (const auto& p : problems) std::fprintf(stderr, "roger: error: %s\n", p.c_str());
    if (!problems.empty()) return 1;
    const Curriculum cur = Curriculum::load(a.script);
    std::string stages;
    for (const auto& st : cur.stages()) {
      std::string contexts;
      for (const auto& c : st.contexts) contexts += (contexts.empty() ? "" : " ") + c.name;
      stages += (stages.empty() ? "" : "; ") + st.name + ": " + contexts;
    }
    std::printf("%s: ok (curriculum '%s'; stages %s)\n", a.script.c_str(), cur.name().c_str(), stages.c_str());
    return 0;
  }
  if (is_skill_script(a.script)) {
    const std::vector<std::string> problems = check_skill_script(a.script);
    for (const auto& p : problems) std::fprintf(stderr, "roger: error: %s\n", p.c_str());
    if (!problems.empty()) return 1;
    const SkillScript script = SkillScript::load(a.script);
    std::string names;
    for (const auto& n : script.policy_names()) names += (names.empty() ? "" : ", ") + n;
    std::printf("%s: ok (skill script '%s'; policies: %s)\n", a.script.c_str(), script.name().c_str(),
                names.c_str());
    return 0;
  }
  Scenario scenario = Scenario::load(a.script);
  apply_sets(scenario, a.sets);
  // A scenario is a function of its seed: try several, and build each world as an episode would.
  World world;
  for (int seed = 0; seed < a.seeds; ++seed) world.reset(scenario.generate(uint64_t(seed)));
  // Without --set, also every declared choice of every parameter (each shape, say).
  if (a.sets.empty()) {
    const std::vector<std::string> problems = check_scenario(a.script, 2);
    if (!problems.empty()) {
      for (const auto& p : problems) std::fprintf(stderr, "roger: error: %s\n", p.c_str());
      return 1;
    }
  }
  std::printf("%s: ok (scenario '%s', %d seeds generated and built%s)\n", a.script.c_str(),
              scenario.name().c_str(), a.seeds, a.sets.empty() ? ", every parameter choice tried" : "");
  return 0;
}

struct EvalArgs {
  std::string script;
  std::string policy;
  std::string scenario;
  std::vector<std::string> sets;
  int episodes = 50;
  uint64_t seed = 1000;
  bool seed_given = false;
  bool json = false;
};

// Splits key=value options into pairs.
std::vector<std::pair<std::string, std::string>> split_sets(const std::vector<std::string>& sets, const char* option) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const std::string& kv : sets) {
    const size_t eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) throw Error(std::string(option) + " expects key=value, got '" + kv + "'");
    out.push_back({kv.substr(0, eq), kv.substr(eq + 1)});
  }
  return out;
}

// eval --policy FILE.json: a policy saved by roger train, its Psi rebuilt from the curriculum.
int run_eval_policy_file(const EvalArgs& a) {
  PolicyEvalOptions o;
  o.curriculum = a.script;
  o.policy_file = a.policy;
  o.scenario = a.scenario;
  o.sets = split_sets(a.sets, "--set");
  o.episodes = a.episodes;
  o.first_seed = a.seed_given ? int64_t(a.seed) : -1;
  const PolicyEvalResult r = evaluate_policy_file(o);
  std::printf("roger eval: %s stage %s context %s (%s) in %s, %d episodes from seed %llu, %.0f s limit\n",
              a.script.c_str(), r.stage.c_str(), r.context.c_str(), a.policy.c_str(), r.scenario.c_str(),
              r.eval.episodes, static_cast<unsigned long long>(r.eval.first_seed), r.time_limit);
  std::printf("  success rate   %.1f%% (%d of %d)\n", 100.0 * r.eval.success_rate, r.eval.successes, r.eval.episodes);
  std::printf("  reward         %.1f +- %.1f\n", r.eval.reward_mean, r.eval.reward_std);
  std::printf("  episode time   %.2f s (mean, simulated)\n", r.eval.time_mean);
  std::string usage;
  for (const auto& [name, f] : r.eval.usage) usage += (usage.empty() ? "" : ", ") + name + " " + std::to_string(int(std::lround(100 * f))) + "%";
  std::printf("  usage          %s\n", usage.c_str());
  if (a.json) {
    nlohmann::json j = {{"script", a.script},          {"policy", a.policy},          {"stage", r.stage},
                        {"context", r.context},        {"scenario", r.scenario},      {"episodes", r.eval.episodes},
                        {"first_seed", r.eval.first_seed}, {"successes", r.eval.successes},
                        {"success_rate", r.eval.success_rate}, {"reward_mean", r.eval.reward_mean},
                        {"reward_std", r.eval.reward_std}, {"time_mean", r.eval.time_mean}};
    for (const auto& [name, f] : r.eval.usage) j["usage"][name] = f;
    for (const auto& [k, v] : r.params) j["params"][k] = v;
    std::printf("%s\n", j.dump().c_str());
  }
  return 0;
}

int run_eval(const EvalArgs& a) {
  if (is_curriculum_script(resolve_curriculum_path(a.script))) {
    if (a.policy.size() < 5 || a.policy.compare(a.policy.size() - 5, 5, ".json") != 0)
      throw Error("with a curriculum, --policy names a policy file written by roger train (policy.json), got '" +
                  a.policy + "'");
    return run_eval_policy_file(a);
  }
  SkillScript script = SkillScript::load(a.script);
  const SkillScript::NamedPolicy& policy = script.policy(a.policy);
  Scenario scenario = Scenario::load(policy_scenario(policy, a.scenario));
  apply_sets(scenario, a.sets);
  EpisodeOptions options;
  options.time_limit = policy.time_limit;
  const EvalSummary r = evaluate_action([&](uint64_t seed) { return scenario.generate(seed); },
                                        *policy.action, *policy.goal, a.episodes, a.seed, options);
  std::printf("roger eval: %s policy '%s' in %s, %d episodes from seed %llu, %.0f s limit\n",
              script.path().c_str(), policy.name.c_str(), scenario.name().c_str(), a.episodes,
              static_cast<unsigned long long>(a.seed), policy.time_limit);
  std::printf("  success rate   %.1f%% (%d of %d)\n", 100.0 * r.success_rate, r.successes, r.episodes);
  std::printf("  reward         %.1f +- %.1f\n", r.reward_mean, r.reward_std);
  std::printf("  episode time   %.2f s (mean, simulated)\n", r.time_mean);
  if (a.json) {
    nlohmann::json j = {{"script", script.path()},      {"policy", policy.name},
                        {"scenario", scenario.name()},  {"episodes", r.episodes},
                        {"first_seed", a.seed},          {"successes", r.successes},
                        {"success_rate", r.success_rate}, {"reward_mean", r.reward_mean},
                        {"reward_std", r.reward_std},    {"time_mean", r.time_mean}};
    for (const auto& p : scenario.params()) j["params"][p.name] = p.value;
    std::printf("%s\n", j.dump().c_str());
  }
  return 0;
}

struct BenchArgs {
  std::string scenario = "scenarios/unobstructed.lua";
  uint64_t seed = 1;
  double seconds = 300.0;
  int repeats = 5;
  bool json = false;
  std::string script = "curricula/scripted.lua";
  std::string policy = "task";
  int episodes = 20;
};

int run_bench(const BenchArgs& a) {
  Scenario scenario = Scenario::load(a.scenario);
  const WorldSpec spec = scenario.generate(a.seed);
  const WorldParams params;
  const BenchResult r = bench_world(spec, BenchOptions{a.seconds, a.repeats}, params);
  // The whole pipeline: the hand-written task policy through episodes on 20 seeds of the same
  // scenario, against physics alone replaying exactly the same commands.
  SkillScript script = SkillScript::load(a.script);
  const SkillScript::NamedPolicy& task = script.policy(a.policy);
  std::vector<WorldSpec> worlds;
  for (int i = 0; i < a.episodes; ++i) worlds.push_back(scenario.generate(a.seed + uint64_t(i)));
  const PipelineResult p = bench_pipeline(worlds, *task.action, *task.goal, task.time_limit, a.repeats, params);
  std::printf("roger bench: %s seed %llu, %.0f simulated s per run, best of %d, one core\n",
              a.scenario.c_str(), static_cast<unsigned long long>(a.seed), a.seconds, a.repeats);
  std::printf("  physics alone        %9.0fx real time\n", r.physics_rtf);
  std::printf("  physics + senses     %9.0fx real time  (senses add %.0f%%)\n", r.world_rtf,
              100.0 * r.senses_overhead);
  std::printf("  full pipeline        %9.0fx real time  (%s policy '%s', %d episodes, %.0f simulated s,\n"
              "                                           %d successes; %.2fx the cost of physics alone\n"
              "                                           replaying the same commands at %.0fx)\n",
              p.pipeline_rtf, a.script.c_str(), a.policy.c_str(), p.episodes, p.sim_seconds,
              p.successes, p.cost_ratio, p.replay_rtf);
  if (a.json) {
    nlohmann::json j = {{"scenario", a.scenario},
                        {"seed", a.seed},
                        {"sim_seconds", a.seconds},
                        {"repeats", a.repeats},
                        {"physics_dt", params.dt},
                        {"control_dt", params.dt * params.substeps},
                        {"physics_rtf", r.physics_rtf},
                        {"world_rtf", r.world_rtf},
                        {"senses_overhead", r.senses_overhead},
                        {"pipeline_rtf", p.pipeline_rtf},
                        {"pipeline_replay_physics_rtf", p.replay_rtf},
                        {"pipeline_cost_ratio", p.cost_ratio},
                        {"pipeline_episodes", p.episodes},
                        {"pipeline_successes", p.successes},
                        {"pipeline_sim_seconds", p.sim_seconds}};
    std::printf("%s\n", j.dump().c_str());
  }
  return 0;
}

struct TrainArgs {
  std::string curriculum;
  std::string stage, context;
  uint64_t seed = 1;
  std::string out;
  bool json = false;
  std::vector<std::string> skills;
  std::vector<std::string> sets;
};

int run_train(const TrainArgs& a) {
  TrainOptions o;
  o.curriculum = a.curriculum;
  o.stage = a.stage;
  o.context = a.context;
  o.seed = a.seed;
  o.sets = split_sets(a.sets, "--set");
  for (const auto& [name, file] : split_sets(a.skills, "--skill")) o.skill_files[name] = file;
  const TrainResult r = train_stage(o);
  write_train_outputs(r, a.out);
  std::printf("roger train: %s stage %s context %s seed %llu (%zu actions, %d states) in %s\n",
              r.curriculum_path.c_str(), r.stage.c_str(), r.context.c_str(), static_cast<unsigned long long>(r.seed),
              r.psi.size(), r.q->states(), r.scenario.c_str());
  for (const auto& s : r.skills)
    std::printf("  skill %s        %s\n", s.name.c_str(),
                s.trained ? ("trained first: stage " + s.stage + " context " + s.context + ", " +
                             (s.reached ? "reached" : "NOT reached") + " its threshold after " +
                             std::to_string(s.to_threshold.episodes) + " episodes").c_str()
                          : ("from " + s.file).c_str());
  if (r.reached) {
    std::printf("  threshold      %.0f%% reached after %d episodes, %.1f simulated s, %lld decisions, %.2f wall s\n",
                100 * r.threshold, r.to_threshold.episodes, r.to_threshold.sim_s,
                static_cast<long long>(r.to_threshold.decisions), r.to_threshold.wall_s);
  } else {
    std::printf("  threshold      %.0f%% NOT reached in %d episodes (%.1f simulated s)\n", 100 * r.threshold,
                r.totals.episodes, r.totals.sim_s);
  }
  std::string usage;
  for (const auto& [name, f] : r.final_eval.usage)
    usage += (usage.empty() ? "" : ", ") + name + " " + std::to_string(int(std::lround(100 * f))) + "%";
  std::printf("  final policy   %.0f%% success over %d held-out episodes, reward %.1f +- %.1f\n",
              100 * r.final_eval.success_rate, r.final_eval.episodes, r.final_eval.reward_mean, r.final_eval.reward_std);
  std::printf("  usage          %s\n", usage.c_str());
  std::printf("  wrote          %s/{policy.json,curve.csv,episodes.jsonl,checkpoints.jsonl,summary.json} (%.2f wall s)\n",
              a.out.c_str(), r.wall_s);
  if (a.json) std::printf("%s\n", train_summary_json(r).dump().c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"roger: a simulated mobile manipulator that learns hierarchical skills through "
               "developmental curricula"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("roger ") + ROGER_VERSION);

  RenderArgs render_args;
  auto* render = app.add_subcommand("render", "Draw a scenario's world for one seed (PNG or SVG)");
  render->add_option("scenario", render_args.scenario, "Scenario script (.lua)")->required();
  render->add_option("--seed", render_args.seed, "World seed")->capture_default_str();
  render->add_option("--out", render_args.out, "Output picture (.png or .svg)")->required();
  render->add_option("--set", render_args.sets, "Scenario parameter key=value (repeatable)");
  render->add_option("--width", render_args.width, "Picture width in pixels")
      ->capture_default_str()->check(CLI::Range(200, 8000));
  render->add_option("--seconds", render_args.seconds, "Simulate this long (Roger idle) first")
      ->check(CLI::Range(0.0, 3600.0));
  render->add_flag("--grid", render_args.grid, "Draw the metric grid across the floor");
  render->add_option("--policy", render_args.policy,
                     "With a skill script: render an episode of this policy (a folder with frames "
                     "and a replay page, or a .png summary)");
  render->add_option("--scenario", render_args.world, "The episode's scenario (default: the policy's)");
  render->add_option("--every", render_args.every, "Seconds between recorded frames")
      ->capture_default_str()->check(CLI::Range(0.02, 10.0));

  CheckArgs check_args;
  auto* check = app.add_subcommand("check", "Load and validate a script without running an episode");
  check->add_option("script", check_args.script, "Script (.lua)")->required();
  check->add_option("--set", check_args.sets, "Scenario parameter key=value (repeatable)");
  check->add_option("--seeds", check_args.seeds, "Seeds to generate")->capture_default_str()
      ->check(CLI::Range(1, 100000));

  EvalArgs eval_args;
  auto* eval = app.add_subcommand("eval", "Evaluate a policy of a skill script over seeded episodes");
  eval->add_option("script", eval_args.script, "Skill script (.lua)")->required();
  eval->add_option("--policy", eval_args.policy,
                   "Policy name in the skill script, or with a curriculum a policy.json written by roger train")
      ->required();
  eval->add_option("--scenario", eval_args.scenario, "Scenario (default: the policy's)");
  eval->add_option("--set", eval_args.sets, "Scenario parameter key=value (repeatable)");
  eval->add_option("--episodes", eval_args.episodes, "Episodes")->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  auto* eval_seed = eval->add_option("--seed", eval_args.seed, "First seed (then seed+1, ...); with a saved "
                                     "policy the default is its stage's held-out seeds")->capture_default_str();
  eval->add_flag("--json", eval_args.json, "End with one JSON line of the figures");

  TrainArgs train_args;
  auto* train = app.add_subcommand("train", "Train one stage and context of a curriculum for one seed");
  train->add_option("curriculum", train_args.curriculum, "Curriculum script (.lua)")->required();
  train->add_option("--stage", train_args.stage, "Stage name (e.g. SG)")->required();
  train->add_option("--context", train_args.context, "Developmental context (e.g. DC2)")->required();
  train->add_option("--seed", train_args.seed, "Trial seed")->capture_default_str();
  train->add_option("--out", train_args.out, "Output folder")->required();
  train->add_flag("--json", train_args.json, "End with one JSON line of the figures");
  train->add_option("--skill", train_args.skills,
                    "A learned skill's policy NAME=FILE.json (repeatable; default: train its stage first)");
  train->add_option("--set", train_args.sets, "Scenario parameter key=value (repeatable)");

  RunArgs run_args;
  auto* run = app.add_subcommand("run", "Run a batch script: many seeded trials in parallel, then the report");
  run->add_option("script", run_args.script, "Batch script (.lua), or a name in scripts/")->required();
  run->add_option("--trials", run_args.trials, "Trials per run (overrides the script)")
      ->check(CLI::Range(1, 100000));
  run->add_option("--jobs", run_args.jobs, "Worker threads (default: all cores)")->check(CLI::Range(1, 1024));
  run->add_option("--out", run_args.out, "Results folder (default: results/<script name>)");
  run->add_option("--set", run_args.sets, "Scenario parameter key=value for every run (repeatable)");
  run->add_option("--only", run_args.only, "Only this run, RUN/CONTEXT, or eval/NAME (repeatable)");
  run->add_flag("--live", run_args.live, "A live progress bar (default on a terminal)");
  run->add_flag("--no-report", run_args.no_report, "Skip the report at the end");

  ReportArgs report_args;
  auto* report = app.add_subcommand("report", "Write tables and figures from a results folder");
  report->add_option("dir", report_args.dir, "Results folder")->required();

  BenchArgs bench_args;
  auto* bench = app.add_subcommand("bench", "Measure simulated seconds per wall second, per layer");
  bench->add_option("--scenario", bench_args.scenario, "Scenario script")->capture_default_str();
  bench->add_option("--seed", bench_args.seed, "World seed")->capture_default_str();
  bench->add_option("--seconds", bench_args.seconds, "Simulated seconds per measurement")
      ->capture_default_str()->check(CLI::Range(1.0, 1e6));
  bench->add_option("--repeats", bench_args.repeats, "Measurements per layer (best kept)")
      ->capture_default_str()->check(CLI::Range(1, 1000));
  bench->add_flag("--json", bench_args.json, "End with one JSON line of the figures");
  bench->add_option("--script", bench_args.script, "Skill script for the pipeline measurement")
      ->capture_default_str();
  bench->add_option("--policy", bench_args.policy, "Its policy")->capture_default_str();
  bench->add_option("--episodes", bench_args.episodes, "Pipeline episodes (seeds from --seed)")
      ->capture_default_str()->check(CLI::Range(1, 10000));

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (*render) return run_render(render_args);
    if (*check) return run_check(check_args);
    if (*bench) return run_bench(bench_args);
    if (*eval) {
      eval_args.seed_given = eval_seed->count() > 0;
      return run_eval(eval_args);
    }
    if (*train) return run_train(train_args);
    if (*run) {
      if (!run->count("--live")) run_args.live = isatty(fileno(stderr)) != 0;
      return command_run(run_args);
    }
    if (*report) return command_report(report_args);
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::cerr << "roger: error: " << e.what() << "\n";
    return 1;
  }
  return 2;
}
