// bench.h: throughput of the simulation layers, measured in one run so ratios are comparable.
#pragma once

#include <string>

#include "spec.h"
#include "world.h"

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

// The fixed scripted motion of base, eyes and arms used by the benchmark (a pure function of time).
DofVector bench_motion(double t);

// Measures physics alone and physics + senses on one world under the scripted motion, single-threaded.
BenchResult bench_world(const WorldSpec& spec, const BenchOptions& options = {},
                        const WorldParams& params = {});

}  // namespace roger
