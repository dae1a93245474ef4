// roger: the command-line program. Each subcommand is a thin layer over the engine library; every
// user error ends in one clear message on standard error and a non-zero exit, never a crash.
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench.h"
#include "error.h"
#include "lua_sandbox.h"
#include "render.h"
#include "scenario.h"
#include "world.h"

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
};

int run_render(const RenderArgs& a) {
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

struct BenchArgs {
  std::string scenario = "scenarios/unobstructed.lua";
  uint64_t seed = 1;
  double seconds = 300.0;
  int repeats = 5;
  bool json = false;
};

int run_bench(const BenchArgs& a) {
  Scenario scenario = Scenario::load(a.scenario);
  const WorldSpec spec = scenario.generate(a.seed);
  const WorldParams params;
  const BenchResult r = bench_world(spec, BenchOptions{a.seconds, a.repeats}, params);
  std::printf("roger bench: %s seed %llu, %.0f simulated s per run, best of %d, one core\n",
              a.scenario.c_str(), static_cast<unsigned long long>(a.seed), a.seconds, a.repeats);
  std::printf("  physics alone        %9.0fx real time\n", r.physics_rtf);
  std::printf("  physics + senses     %9.0fx real time  (senses add %.0f%%)\n", r.world_rtf,
              100.0 * r.senses_overhead);
  if (a.json) {
    nlohmann::json j = {{"scenario", a.scenario},
                        {"seed", a.seed},
                        {"sim_seconds", a.seconds},
                        {"repeats", a.repeats},
                        {"physics_dt", params.dt},
                        {"control_dt", params.dt * params.substeps},
                        {"physics_rtf", r.physics_rtf},
                        {"world_rtf", r.world_rtf},
                        {"senses_overhead", r.senses_overhead}};
    std::printf("%s\n", j.dump().c_str());
  }
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

  CheckArgs check_args;
  auto* check = app.add_subcommand("check", "Load and validate a script without running an episode");
  check->add_option("script", check_args.script, "Script (.lua)")->required();
  check->add_option("--set", check_args.sets, "Scenario parameter key=value (repeatable)");
  check->add_option("--seeds", check_args.seeds, "Seeds to generate")->capture_default_str()
      ->check(CLI::Range(1, 100000));

  BenchArgs bench_args;
  auto* bench = app.add_subcommand("bench", "Measure simulated seconds per wall second, per layer");
  bench->add_option("--scenario", bench_args.scenario, "Scenario script")->capture_default_str();
  bench->add_option("--seed", bench_args.seed, "World seed")->capture_default_str();
  bench->add_option("--seconds", bench_args.seconds, "Simulated seconds per measurement")
      ->capture_default_str()->check(CLI::Range(1.0, 1e6));
  bench->add_option("--repeats", bench_args.repeats, "Measurements per layer (best kept)")
      ->capture_default_str()->check(CLI::Range(1, 1000));
  bench->add_flag("--json", bench_args.json, "End with one JSON line of the figures");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (*render) return run_render(render_args);
    if (*check) return run_check(check_args);
    if (*bench) return run_bench(bench_args);
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::cerr << "roger: error: " << e.what() << "\n";
    return 1;
  }
  return 2;
}
