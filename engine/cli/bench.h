// bench.h: throughput of the simulation layers, measured in one run so ratios are comparable.
#pragma once

#include <memory>
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
  double physics_rtf = 0.0;      // physics alone: servos + Box2D (fastest measurement)
  double world_rtf = 0.0;        // physics + senses every control tick (fastest measurement)
  double senses_overhead = 0.0;  // (world cost / physics cost) - 1, the median over pairs
  uint64_t final_hash = 0;       // state hash at the end, so the work cannot be optimized away
};

// The full pipeline (physics + senses + controllers + the control loop) running an action
// through episodes, against physics alone replaying exactly the same commands.
struct PipelineResult {
  double sim_seconds = 0.0;    // simulated seconds per measurement
  int episodes = 0;            // episodes per measurement
  int successes = 0;           // of the first measurement
  double pipeline_rtf = 0.0;   // simulated seconds per wall second, whole pipeline (fastest)
  double replay_rtf = 0.0;     // physics alone, replaying the pipeline's errors vectors (fastest)
  double cost_ratio = 0.0;     // pipeline cost / physics cost on the same trajectories: the
                               // median over measurements of each one's own ratio
  uint64_t hash = 0;           // FNV-1a of every errors vector issued and each episode's final
                               // state (first measurement): any change to a result changes it
};

class Agent;

// One pipeline line: `action` on each world until `goal` or the time limit, then physics alone
// replaying the recorded commands. Each measure() times both once, back to back. result() holds
// the speeds of the fastest (least disturbed) measurements so far, the cost ratio as the median of
// each measurement's own pipeline time over its replay's (the two share the machine's state of
// the moment, where two separate best times need not: docs/cli.md gives the spread this removed on
// a shared machine), and the successes, simulated time and hash of the first. `roger bench`
// measures its lines in rounds, each line once per round, so lines compared with each other were
// timed in the same seconds. Controllers are reset per episode.
class PipelineBench {
 public:
  PipelineBench(std::vector<WorldSpec> worlds, Controller& action, Predicate& goal, double time_limit,
                const WorldParams& params = {});
  ~PipelineBench();
  void measure();
  const PipelineResult& result() const { return result_; }

 private:
  double run_episodes();  // the timed pipeline; returns wall seconds
  double replay();        // the timed physics alone on the same commands; returns wall seconds
  std::vector<WorldSpec> worlds_;
  Controller& action_;
  Predicate& goal_;
  double time_limit_;
  WorldParams params_;
  std::unique_ptr<Agent> agent_;
  std::vector<std::vector<DofVector>> commands_;  // per world, the errors vector of every tick
  int measured_ = 0;
  double best_pipeline_ = 0.0, best_replay_ = 0.0;
  std::vector<double> ratios_;
  PipelineResult result_;
};

// The fixed scripted motion of base, eyes and arms used by the benchmark (a pure function of time).
DofVector bench_motion(double t);

// Measures physics alone and physics + senses on one world under the scripted motion, single-threaded.
BenchResult bench_world(const WorldSpec& spec, const BenchOptions& options = {},
                        const WorldParams& params = {});

}  // namespace roger
