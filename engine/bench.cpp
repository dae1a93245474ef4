#include "bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace roger {

DofVector bench_motion(double t) {
  DofVector e;
  e << 0.3 * std::sin(0.7 * t), 0.6 * std::sin(0.3 * t), 0.3 * std::sin(2.0 * t),
      0.3 * std::cos(2.0 * t), 0.4 * std::sin(1.1 * t), 0.4 * std::cos(0.9 * t),
      0.4 * std::sin(1.3 * t), 0.4 * std::cos(0.8 * t);
  return e;
}

namespace {

// Runs one measurement; with_senses chooses between the two layers. Returns wall seconds.
double measure(World& world, const WorldSpec& spec, double sim_seconds, bool with_senses,
               uint64_t& hash) {
  world.reset(spec);
  const int ticks = int(sim_seconds / world.tick_seconds());
  const int substeps = world.params().substeps;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < ticks; ++i) {
    world.command(bench_motion(world.time()));
    if (with_senses) {
      world.tick();
    } else {
      for (int s = 0; s < substeps; ++s) world.step_physics();
    }
  }
  const auto stop = std::chrono::steady_clock::now();
  hash ^= world.state_hash();
  return std::chrono::duration<double>(stop - start).count();
}

}  // namespace

BenchResult bench_world(const WorldSpec& spec, const BenchOptions& options,
                        const WorldParams& params) {
  World world(params);
  BenchResult r;
  r.sim_seconds = options.sim_seconds;
  double best_physics = INFINITY, best_world = INFINITY;
  // Interleaved, best of N: the machine is shared, and the minimum is the least disturbed run.
  for (int rep = 0; rep < std::max(1, options.repeats); ++rep) {
    best_physics = std::min(best_physics, measure(world, spec, options.sim_seconds, false, r.final_hash));
    best_world = std::min(best_world, measure(world, spec, options.sim_seconds, true, r.final_hash));
  }
  r.physics_rtf = options.sim_seconds / best_physics;
  r.world_rtf = options.sim_seconds / best_world;
  r.senses_overhead = best_world / best_physics - 1.0;
  return r;
}

}  // namespace roger
