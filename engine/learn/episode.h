// episode.h: the one episode loop. Training, greedy checkpoints, `roger eval` and replay recording
// all run an episode through run_episode(agent, spec, seed, driver, time_limit, observer); what
// differs between them is the driver (what runs each tick) and the observer (what is recorded).
// Owns: the loop, the fixed-action driver, frame and gamma recording. Must not depend on Lua,
// batch or report code: scripts reach the loop only through the driver's virtual functions.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "control/agent.h"
#include "control/control.h"
#include "control/predicate.h"
#include "sim/world.h"

namespace roger {

// What runs at each control tick of an episode and when the episode is over.
class EpisodeDriver {
 public:
  virtual ~EpisodeDriver() = default;
  // Starts an episode: resets every controller and predicate it uses with the episode's seed.
  virtual void begin(uint64_t seed) = 0;
  // The controller to run for the coming tick, or nullptr when the episode has just reached its
  // absorbing state (a driver may find that at a decision point, before acting).
  virtual Controller* choose(const ControlInput& in) = 0;
  // After the tick: whether the absorbing state holds (the episode then ends in success).
  virtual bool absorbed(const ControlInput& in) = 0;
  // The episode ended after `ticks` ticks at simulated time `time`, in success or at the time
  // limit; returns the final success (a driver may still find the absorbing state here).
  virtual bool end(const ControlInput& in, bool success, int ticks, double time) = 0;
  // Whether the last choose() returned nullptr because the driver waits for a choice from outside
  // (an environment's step), not because the episode is absorbed: the loop then pauses before the
  // tick and asks choose() again once the choice is given.
  virtual bool paused() const { return false; }
  // The judge of its absorbing predicate (the episode loop lets it follow each tick), or none.
  virtual Judge* judge() { return nullptr; }
};

// What an episode loop reports to whoever records it (pictures, timelines). Default: nothing.
class EpisodeObserver {
 public:
  virtual ~EpisodeObserver() = default;
  // The world is reset and the driver has begun.
  virtual void on_begin(const Agent&, uint64_t /*seed*/) {}
  // A tick has run `ran` (what the driver chose), before the absorbing state is checked; `tick`
  // counts from 1.
  virtual void on_tick(const Agent&, int /*tick*/, const Controller& /*ran*/) {}
  // The episode is over.
  virtual void on_end(const Agent&, bool /*success*/, int /*ticks*/) {}
};

// How an episode ended.
struct EpisodeOutcome {
  bool success = false;     // the absorbing state was reached before the time limit
  int ticks = 0;            // control ticks run
  double sim_seconds = 0.0; // simulated time at the end
};

// The one episode loop, one control tick at a time, for a caller that must return between ticks
// (an environment stepped from Python): run_episode below is begin, tick() until it returns false,
// then finish(), so a stepped episode is the same episode bit for bit. Each tick asks the driver
// for a controller, runs it for one tick, tells the observer and asks the driver whether the
// episode is absorbed, until it is or `time_limit` simulated seconds pass. A driver may pause the
// loop before a tick (EpisodeDriver::paused): tick() then returns without running anything and
// runs that tick when called again.
class EpisodeRun {
 public:
  // Resets the agent into `spec` and begins the driver with `seed`. Throws roger::Error for a bad
  // limit. The agent, driver and observer must outlive the run.
  EpisodeRun(Agent& agent, const WorldSpec& spec, uint64_t seed, EpisodeDriver& driver, double time_limit,
             EpisodeObserver* observer = nullptr);
  // Runs one control tick. False when the episode is over (then call finish()), or when the driver
  // paused before the tick (paused() says which).
  bool tick();
  // Whether the last tick() stopped because the driver waits for a choice from outside.
  bool paused() const { return paused_; }
  // Whether the episode has ended (absorbed or out of time); finish() is still to be called.
  bool over() const { return over_; }
  // Control ticks run so far.
  int ticks() const { return out_.ticks; }
  // Ends the episode: tells the driver and the observer; returns how it ended. Call once, when over.
  EpisodeOutcome finish();
  ~EpisodeRun();

 private:
  Agent& agent_;
  EpisodeDriver& driver_;
  EpisodeObserver* observer_;
  int max_ticks_ = 0;
  bool over_ = false, paused_ = false, finished_ = false;
  EpisodeOutcome out_;
};

// The one episode loop (EpisodeRun) from start to end. The episode is a pure function of (spec,
// seed, driver). Throws roger::Error for a bad limit.
EpisodeOutcome run_episode(Agent& agent, const WorldSpec& spec, uint64_t seed, EpisodeDriver& driver,
                           double time_limit, EpisodeObserver* observer = nullptr);

// How an episode of one action runs and pays.
struct EpisodeOptions {
  double time_limit = 10.0;        // simulated seconds
  double time_per_object = 0.0;    // simulated seconds more per object of the world
  double success_reward = 100.0;   // reward when the goal predicate holds
  double timeout_reward = -100.0;  // reward at the time limit without it
  double record_every = 0.0;       // seconds between recorded frames; 0 = no frames
};

// The states of watched controllers over an episode, one entry per control tick.
struct GammaTrace {
  std::string name;
  std::vector<Gamma> states;
};

// A decision of the action's skills: from `tick` on, the action runs through `path`, the chain of
// controllers from the action down to the step a sequence runs or the action a policy chose.
struct Decision {
  int tick = 0;                    // the control tick (from 1) at which this path first ran
  std::vector<std::string> path;   // names, outermost first (the action itself alone when flat)
};

// What happened in one episode of one action.
struct EpisodeResult {
  uint64_t seed = 0;
  bool success = false;
  double reward = 0.0;
  double sim_seconds = 0.0;
  int ticks = 0;
  std::vector<Frame> frames;      // when recording
  std::vector<double> frame_ticks;// tick index of each frame
  std::vector<GammaTrace> gammas; // one per watched controller, every tick
  std::vector<Decision> decisions;// when recording: each change of the running path of the action
};

// An observer that records into `result` what run_episode(action) records: a frame every
// `record_every` seconds (0: none) and the episode's last moment (its success or time-out), the states of the `watch`
// controllers every tick, and (when recording either) each change of the path that runs, from the
// controller the driver chose down to the step or choice running inside it. With any driver
// (a learned stage's too), so that every kind of episode can be replayed.
std::unique_ptr<EpisodeObserver> make_recorder(EpisodeResult& result, const std::vector<ControllerPtr>& watch,
                                               double record_every, double tick_seconds);

// The traces worth a row each on a timeline, at most `limit`, in order: a trace with the name and
// the states of an earlier one is dropped (two copies of one composite, each inside another
// skill, or a learned skill and the binding that runs it, show the same row twice), and a name
// still shared by traces whose states differ is numbered from its second on ("phi4 <| phi5 (2)").
std::vector<GammaTrace> distinct_traces(std::vector<GammaTrace> traces, size_t limit);

// Runs `action` (a primitive, composition or skill) through the loop from a fresh world until
// `goal` holds or the time limit, recording frames every options.record_every seconds and the
// states of the `watch` controllers every tick (and, when recording either, the decisions). Every controller it uses is reset with the
// episode seed, so the episode is a pure function of (spec, seed, action).
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
  // The controllers of the action and its goal that ran and were NOREF at every tick of every
  // episode: the outermost of them, by name and settings, with the innermost inside each
  // ("purple {stimulus = \"#7800c8\"} (inside: phi3, phi0)"). What they act on was never there.
  std::vector<std::string> never_referenced;
  // What sensor or actuator noise did to readings in some world: offset them (white, bias, drift),
  // lose some (dropout), delay them, round them (quantum). It may hide what a part acts on: for the
  // note on parts never referenced.
  bool noise_offsets = false, noise_lost = false, noise_late = false, noise_coarse = false;
  bool noisy() const { return noise_offsets || noise_lost || noise_late || noise_coarse; }
  int succeeded_at_first_tick = 0;  // successes at the first tick: the goal held from the start
};

// Evaluates an action over `episodes` seeds (seed, seed + 1, ...), making each world with `make`.
EvalSummary evaluate_action(const std::function<WorldSpec(uint64_t)>& make, Controller& action,
                            Predicate& goal, int episodes, uint64_t first_seed,
                            const EpisodeOptions& options = {}, const WorldParams& world = {});

}  // namespace roger
