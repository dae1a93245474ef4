// bench.h: throughput of the simulation layers, measured in one run so ratios are comparable.
#pragma once

#include <string>
#include <vector>

#include "control/control.h"
#include "control/predicate.h"

#include "core/spec.h"
#include "sim/world.h"

namespace roger {

// How long and how often to measure.
struct BenchOptions {
  double sim_seconds = 300.0;  // simulated seconds per measurement
  int repeats = 5;             // measurements per layer, interleaved; the best is kept
};

// Simulated seconds per wall second of each layer (higher is faster).
struct BenchResult {
  double sim_seconds = 0.0;
  double physics_rtf = 0.0;      // physics alone: servos + Box2D
  double world_rtf = 0.0;        // physics + senses every control tick
  double senses_overhead = 0.0;  // (world cost / physics cost) - 1
  uint64_t final_hash = 0;       // state hash at the end, so the work cannot be optimized away
};

// The full pipeline (physics + senses + controllers + the control loop) running an action
// through episodes, against physics alone replaying exactly the same commands.
struct PipelineResult {
  double sim_seconds = 0.0;    // simulated seconds per measurement
  int episodes = 0;            // episodes per measurement
  int successes = 0;           // of the first measurement
  double pipeline_rtf = 0.0;   // simulated seconds per wall second, whole pipeline
  double replay_rtf = 0.0;     // physics alone, replaying the pipeline's errors vectors
  double cost_ratio = 0.0;     // pipeline cost / physics cost on the same trajectories
  uint64_t hash = 0;           // FNV-1a of every errors vector issued and each episode's final
                               // state (first measurement): any change to a result changes it
};

// Runs `action` on each world until `goal` or the time limit (best of `repeats`), then replays
// the recorded commands through physics alone. Controllers are reset per episode.
PipelineResult bench_pipeline(const std::vector<WorldSpec>& worlds, Controller& action,
                              Predicate& goal, double time_limit, int repeats,
                              const WorldParams& params = {});

// The fixed scripted motion of base, eyes and arms used by the benchmark (a pure function of time).
DofVector bench_motion(double t);

// Measures physics alone and physics + senses on one world under the scripted motion, single-threaded.
BenchResult bench_world(const WorldSpec& spec, const BenchOptions& options = {},
                        const WorldParams& params = {});

}  // namespace roger
