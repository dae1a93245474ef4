// episode.h: running one action (a primitive, composition or skill) through an episode: until a
// goal predicate holds or a time limit passes, with the paper's rewards, optionally recording
// frames and the controllers' states for pictures and animations.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "control/agent.h"
#include "control/control.h"
#include "control/predicate.h"
#include "sim/world.h"

namespace roger {

// How an episode runs and pays.
struct EpisodeOptions {
  double time_limit = 10.0;        // simulated seconds
  double success_reward = 100.0;   // reward when the goal predicate holds
  double timeout_reward = -100.0;  // reward at the time limit without it
  double record_every = 0.0;       // seconds between recorded frames; 0 = no frames
};

// The states of watched controllers over an episode, one entry per control tick.
struct GammaTrace {
  std::string name;
  std::vector<Gamma> states;
};

// What happened in one episode.
struct EpisodeResult {
  uint64_t seed = 0;
  bool success = false;
  double reward = 0.0;
  double sim_seconds = 0.0;
  int ticks = 0;
  std::vector<Frame> frames;      // when recording
  std::vector<double> frame_ticks;// tick index of each frame
  std::vector<GammaTrace> gammas; // one per watched controller, every tick
};

// Runs `action` from a fresh world until `goal` holds or the time limit. Every controller it uses
// is reset with the episode seed, so the episode is a pure function of (spec, seed, action).
EpisodeResult run_episode(Agent& agent, const WorldSpec& spec, uint64_t seed, Controller& action,
                          Predicate& goal, const EpisodeOptions& options = {},
                          const std::vector<ControllerPtr>& watch = {});

// Success rate and reward statistics over several episodes.
struct EvalSummary {
  int episodes = 0;
  int successes = 0;
  double success_rate = 0.0;
  double reward_mean = 0.0, reward_std = 0.0;
  double time_mean = 0.0;  // simulated seconds per episode
  std::vector<EpisodeResult> results;
};

// Evaluates an action over `episodes` seeds (seed, seed + 1, ...), making each world with `make`.
EvalSummary evaluate_action(const std::function<WorldSpec(uint64_t)>& make, Controller& action,
                            Predicate& goal, int episodes, uint64_t first_seed,
                            const EpisodeOptions& options = {}, const WorldParams& world = {});

}  // namespace roger
