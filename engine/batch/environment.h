// environment.h: a stage of a curriculum as an environment stepped from outside, for learners
// written elsewhere (the Python module, engine/python/). reset(seed) builds the world of a seed
// as `roger eval` does; step(action) gives the action of one decision of the stage's semi-MDP and
// runs it until the state of Psi changes, through the one episode loop (EpisodeRun) and the same
// SemiMdpDriver that training and evaluation use, so a loop that chooses QTable::policy_action
// at every decision replays `roger eval` of that table bit for bit. In per-tick mode every control
// tick is a decision, for learners of raw senses. VecEnvironment steps many of them on threads.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "control/agent.h"
#include "learn/learning.h"
#include "script/sandbox/lua_sandbox.h"

namespace roger {

// What an environment runs.
struct EnvironmentOptions {
  std::string curriculum;                                 // script path or bare name ("paper")
  std::string stage, context;
  std::string scenario;                                   // "" = the stage's
  std::vector<std::pair<std::string, std::string>> sets;  // scenario parameters over the stage's
  std::map<std::string, std::string> skill_files;         // learned skill name -> its policy.json
  bool per_tick = false;                                  // a decision every control tick
  SandboxLimits limits;
};

// The stage as the environment runs it: what a learner needs to follow `roger train`'s protocol.
struct EnvironmentInfo {
  std::string curriculum, stage, context, scenario;
  std::vector<std::string> actions;                        // Psi, in state-vector order
  std::vector<std::pair<std::string, std::string>> params; // scenario parameters used
  // An episode's time-out: time_limit + time_per_object x the objects of its world.
  double time_limit = 0.0, time_per_object = 0.0, tick_seconds = 0.0;
  int budget_episodes = 0;
  QParams learner;
  double discount_seconds = 0.0;  // the discount's clock: 0 once per decision, else per these seconds
  int checkpoint_every = 0, checkpoint_episodes = 0, stop_after = 0, final_episodes = 0;
  double threshold = 0.0;
  uint64_t checkpoint_seeds = 0;
  bool settle = true;
};

// What one step gave.
struct EnvironmentStep {
  double reward = 0.0;      // undiscounted, of the transition this step ran
  bool terminated = false;  // the absorbing state was reached
  bool truncated = false;   // the time limit passed without it
};

class StageEnvironment {
 public:
  // Loads the curriculum, its stage and context, binds the learned skills from options.skill_files
  // (every skill the context uses must be given) and loads the scenario. Throws roger::Error or
  // ScriptError naming the file and the field.
  explicit StageEnvironment(const EnvironmentOptions& options);
  ~StageEnvironment();
  StageEnvironment(const StageEnvironment&) = delete;
  StageEnvironment& operator=(const StageEnvironment&) = delete;

  const EnvironmentInfo& info() const { return info_; }
  // Starts an episode in the world of `seed` and runs to its first decision. Returns the state.
  const std::vector<Gamma>& reset(uint64_t seed);
  // Runs `action` (an index of Psi) until the next decision or the end of the episode. Throws
  // roger::Error for a bad index or when no episode is running (before reset, after the end, or
  // after an error), ScriptError for a fault of the stage's Lua functions.
  EnvironmentStep step(int action);

  // The state of Psi at the last decision (or at the end).
  const std::vector<Gamma>& state() const;
  // Whether an episode runs and waits for step().
  bool running() const;
  uint64_t seed() const { return seed_; }
  // Simulated seconds and control ticks of the running (or last) episode.
  double sim_seconds() const;
  int ticks() const;
  // The episode so far: decisions, actions taken, its reward (complete once it ended).
  const TrainingEpisode& episode() const;
  // The robot, its senses and percepts now.
  const Agent& agent() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  EnvironmentInfo info_;
  uint64_t seed_ = 0;
};

// N environments of one stage stepped together on worker threads. Environment i's k-th episode
// (k from 0) runs in the world of seed first_seed + i + k * N, and an environment whose episode
// ended is reset at once (its next episode's state is what step() returns for it), so what every
// environment does is a function of the seeds and the actions alone, whatever the thread count.
class VecEnvironment {
 public:
  // Builds `n` environments (each with its own Lua state) and `threads` - 1 workers (the caller's
  // thread is the other). Throws like StageEnvironment, or roger::Error for n or threads < 1.
  VecEnvironment(const EnvironmentOptions& options, int n, int threads);
  ~VecEnvironment();
  VecEnvironment(const VecEnvironment&) = delete;
  VecEnvironment& operator=(const VecEnvironment&) = delete;

  int size() const { return int(envs_.size()); }
  int threads() const { return threads_; }
  const EnvironmentInfo& info() const { return envs_.front()->info(); }
  // Resets every environment (i with first_seed + i). Writes each state into states (n x |Psi|
  // bytes, the gamma values 0, 1, 2) and each world seed into seeds.
  void reset(uint64_t first_seed, uint8_t* states, uint64_t* seeds);
  // Where step() writes, one entry per environment (states: n x |Psi| bytes).
  struct StepOutput {
    uint8_t* states;         // the state after the step; after the reset when the episode ended
    double* rewards;         // the reward of the step
    uint8_t* terminated;     // the episode reached the absorbing state
    uint8_t* truncated;      // the episode reached the time limit
    uint8_t* final_states;   // for an episode that ended: its last state (else zeros)
    uint64_t* seeds;         // the world seed of the running episode
    uint64_t* episode_seeds; // for an episode that ended: its world seed, simulated seconds,
    double* episode_sim_s;   // control ticks and return (the engine's sum of its rewards);
    int32_t* episode_ticks;  // zeros otherwise
    double* episode_rewards;
  };
  // Steps environment i with actions[i] and writes the outcomes. Throws roger::Error for an action
  // out of range (before anything runs); rethrows the error of the lowest environment that failed
  // (the others have stepped; the failed one needs reset()).
  void step(const int64_t* actions, const StepOutput& out);

 private:
  void run_all();     // every environment's job, shared among the threads
  void worker();      // a worker's loop
  void run_jobs();    // takes jobs until none is left
  void job(int i);    // one environment's step (or reset)
  std::vector<std::unique_ptr<StageEnvironment>> envs_;
  std::vector<uint64_t> episodes_started_;
  uint64_t first_seed_ = 0;
  int threads_ = 1;
  // The work of one call, read by job().
  bool resetting_ = false;
  const int64_t* actions_ = nullptr;
  std::vector<EnvironmentStep> results_;
  std::vector<uint8_t> ended_;
  std::vector<std::vector<Gamma>> final_;
  std::vector<double> final_sim_s_, final_reward_;
  std::vector<uint64_t> final_seed_;
  std::vector<int> final_ticks_;
  std::vector<std::exception_ptr> errors_;
  // The pool: a generation number wakes the workers; next_ hands out environments.
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  uint64_t generation_ = 0;
  int busy_ = 0;
  std::atomic<int> next_{0};
  bool quit_ = false;
};

}  // namespace roger
