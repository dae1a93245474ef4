// environment.h: a stage of a curriculum as an environment stepped from outside, for learners
// written elsewhere (the Python module, engine/python/). reset(seed) builds the world of a seed
// as `roger eval` does; step(action) gives the action of one decision of the stage's semi-MDP and
// runs it until the state of Psi changes, through the one episode loop (EpisodeRun) and the same
// SemiMdpDriver that training and evaluation use, so a loop that chooses QTable::policy_action
// at every decision replays `roger eval` of that table bit for bit. In per-tick mode every control
// tick is a decision, for learners of raw senses. VecEnvironment steps many of them on threads.
#pragma once

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "control/agent.h"
#include "core/robot.h"
#include "learn/learning.h"
#include "script/curriculum/curriculum.h"
#include "script/sandbox/lua_sandbox.h"
#include "script/scenario/scenario.h"
#include "teach/teach.h"

namespace roger {

// The floating-point mode of the calling thread for one call into the engine from outside: within
// it, subnormals are flushed to zero, as on the engine's own threads (World::reset: Box2D's
// resting joints would otherwise decay into subnormals at a hundred times the cost); at its end
// the thread gets its own mode back. So an episode stepped from a caller's thread runs as `roger
// eval` runs it, whatever the caller does to the mode between calls, and a Python interpreter's
// numpy and torch keep IEEE subnormals on that thread.
class EngineFloatMode {
 public:
  EngineFloatMode();
  ~EngineFloatMode();
  EngineFloatMode(const EngineFloatMode&) = delete;
  EngineFloatMode& operator=(const EngineFloatMode&) = delete;

 private:
  unsigned saved_ = 0;
};

// What an environment runs.
struct EnvironmentOptions {
  std::string curriculum;                                 // script path or bare name ("paper")
  std::string stage, context;
  std::string scenario;                                   // "" = the stage's
  std::vector<std::pair<std::string, std::string>> sets;  // scenario parameters over the stage's
  std::map<std::string, std::string> skill_files;         // learned skill name -> its policy.json
  // Learned skills embedded in a policy file (its extra.skills: name -> policy JSON), bound for
  // those skill_files does not give, as `roger eval --policy` binds them.
  nlohmann::json embedded_skills = nlohmann::json::object();
  bool per_tick = false;                                  // a decision every control tick
  SandboxLimits limits;
  // Another task space or teacher than the stage's (Curriculum::set_teaching); empty: the stage's.
  LuaSource tasks, teacher;
  // Whether a teacher will run (false: make(..., teacher=False), make_vec): a stage's LCAS teacher
  // whose lifted parameter the params fix is refused only when it runs.
  bool teaching = true;
};

// The stage as the environment runs it: what a learner needs to follow `roger train`'s protocol.
struct EnvironmentInfo {
  std::string curriculum, stage, context, scenario;
  std::vector<std::string> actions;                        // Psi, in state-vector order
  std::vector<std::pair<std::string, std::string>> params; // scenario parameters used
  std::map<std::string, ParamType> param_types;            // each one's declared type
  // An episode's time-out: time_limit + time_per_object x the objects of its world.
  double time_limit = 0.0, time_per_object = 0.0, tick_seconds = 0.0;
  int budget_episodes = 0;
  QParams learner;
  double discount_seconds = 0.0;  // the discount's clock: 0 once per decision, else per these seconds
  int checkpoint_every = 0, checkpoint_episodes = 0, stop_after = 0, final_episodes = 0;
  double threshold = 0.0;
  uint64_t checkpoint_seeds = 0;
  bool settle = true;
  int eye_pixels = 128;  // each eye's pixels in the stage's worlds (its first held-out world's)
  // The range of each joint reading (Dof order) in per-tick observations, of the same world's
  // body (observed_joint_ranges).
  std::array<double, kDofCount> joint_low{}, joint_high{};
};

// What a joint reading of `body` is reported within, per Dof: the heading's wrap (-pi, pi], the
// eyes' pan limits and the arms' setpoint ranges (the right arm's mirrored); -+infinity for the
// odometer, which no body bounds. Arm joints can be pushed past their range and noise moves any
// reading, so a per-tick observation clamps its readings to these ranges.
void observed_joint_ranges(const RobotParams& body, std::array<double, kDofCount>& low,
                           std::array<double, kDofCount>& high);

// A world that could not be placed (PlacementError), its message given `prefix` in front ("make:
// could not build the world of seed ..."): the same class, file and line, and the placement's
// own message after the prefix; its Lua traceback is kept in .traceback, not in the message (the
// parameters, which the prefix names, are what to change).
PlacementError placement_error(const PlacementError& e, const std::string& prefix);
// A copy of `e` whose text (what()) is `text`: the same class, message, file, line and traceback.
PlacementError with_text(const PlacementError& e, const std::string& text);

// A teacher whose worlds have another body than the stage's (what the tick mode's observation
// space is made for): an LCAS teacher lifting a body parameter (eye_pixels) beside the task space.
struct TeacherBodyChange {
  std::string teacher;              // "roger.teacher.lcas (curricula/teachers.lua:87)"
  std::string lift;                 // the parameter it lifts
  std::vector<std::string> levels;  // its values
  std::string level;                // the first whose worlds' body differs
  std::string misfit;               // how: "eyes of 32 pixels, where ..."
};

// What one step gave. The stage's time-out ends the episode as its absorbing state does: the
// engine's learner pays its reward and does not bootstrap beyond it (learn/learning.cpp).
struct EnvironmentStep {
  double reward = 0.0;      // undiscounted, of the transition this step ran
  bool terminated = false;  // the episode ended: the absorbing state, or the time-out
  bool time_out = false;    // it ended because the stage's time limit passed
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
  // Starts the episode of `seed` in the world generated with a task's parameters set over the
  // stage's (those of task_space(), and beside them those a teacher lifts); a parameter an earlier
  // task set and this one does not is back at the stage's value. Throws roger::Error for a
  // parameter the scenario refuses.
  const std::vector<Gamma>& reset(uint64_t seed, const ParamList& task);
  // The stage's task space (or options.tasks) less the parameters options.sets fix, as `roger
  // train` has it; empty when the stage has none.
  const TaskSpace& task_space() const { return task_space_; }
  // Throws ScriptError at the axis's file:line when `scenario` cannot play task_space() (make's
  // scenario= with the stage's own tasks: make's own tasks were checked against it at load).
  void check_played_in(const std::string& scenario) const;
  // Whether the stage (or options) gives a teacher; the teacher over task_space(), drawing from
  // Rng(seed), as Curriculum::make_teacher makes it. A Lua teacher runs in this environment's
  // sandbox: the teacher must not outlive the environment.
  bool teaches() const;
  std::unique_ptr<Teacher> make_teacher(uint64_t seed);
  // Whether the stage's teacher sets a parameter beside the task space whose worlds have another
  // body than info()'s (eye_pixels, joint ranges), read from the first held-out world generated
  // at each of its values: what the tick mode refuses at make. Call it before the first reset.
  std::optional<TeacherBodyChange> teacher_body_change();
  // Runs `action` (an index of Psi) until the next decision or the end of the episode. Throws
  // roger::Error for a bad index or when no episode is running (before reset, after the end, or
  // after an error), ScriptError for a fault of the stage's Lua functions.
  EnvironmentStep step(int action);
  // Starts the episode of `seed` and takes `actions` at its decisions: the episode is a function
  // of its seed and actions, so this is the same episode at the same point (what a copy of the
  // environment continues). Throws as reset and step do.
  void replay(uint64_t seed, const std::vector<int>& actions, const ParamList& task = {});

  // The state of Psi at the last decision (or at the end).
  const std::vector<Gamma>& state() const;
  // Whether an episode runs and waits for step(); whether one was begun since construction.
  bool running() const;
  bool begun() const;
  uint64_t seed() const { return seed_; }
  // Simulated seconds and control ticks of the running (or last) episode.
  double sim_seconds() const;
  int ticks() const;
  // The episode so far: decisions, actions taken, its reward (complete once it ended).
  const TrainingEpisode& episode() const;
  // The robot, its senses and percepts now.
  const Agent& agent() const;

 private:
  void check_task_space_ends(const EnvironmentOptions& o) const;

  struct Impl;
  std::unique_ptr<Impl> impl_;
  EnvironmentInfo info_;
  uint64_t seed_ = 0;
  TaskSpace task_space_;
  std::vector<std::pair<std::string, std::string>> sets_;  // options.sets, for messages
};

// How a VecEnvironment begins an ended episode's successor: Gymnasium's autoreset modes.
enum class Autoreset {
  kNextStep,  // at the environment's next step, whose action is then ignored (Gymnasium's default)
  kSameStep,  // at once, within the step in which the episode ended
  kDisabled,  // never: the caller resets it (reset with a mask); stepping it is an error
};

// N environments of one stage stepped together on worker threads. Environment i's episodes run in
// the worlds of its base seed b_i, b_i + N, b_i + 2N, ... (reset(first_seed) sets b_i = first_seed
// + i; a reset without a seed goes on along the schedule), so what every environment does is a
// function of the seeds and the actions alone, whatever the thread count.
class VecEnvironment {
 public:
  // Builds `n` environments (each with its own Lua state) and `threads` - 1 workers (the caller's
  // thread is the other). Throws like StageEnvironment, or roger::Error for n or threads < 1.
  VecEnvironment(const EnvironmentOptions& options, int n, int threads, Autoreset autoreset = Autoreset::kNextStep);
  ~VecEnvironment();
  VecEnvironment(const VecEnvironment&) = delete;
  VecEnvironment& operator=(const VecEnvironment&) = delete;

  int size() const { return int(envs_.size()); }
  int threads() const { return threads_; }
  Autoreset autoreset() const { return autoreset_; }
  const EnvironmentInfo& info() const { return envs_.front()->info(); }
  const StageEnvironment& env(int i) const { return *envs_[size_t(i)]; }
  // A running (or the last) episode of every environment, one entry each (states: n x |Psi| bytes,
  // the gamma values 0, 1, 2).
  struct Episodes {
    uint8_t* states;
    uint64_t* seeds;
    double* sim_seconds;
    int32_t* ticks;
    int32_t* decisions;
  };
  // Which environments reset() begins anew: all when mask is null, else those with mask[i] != 0;
  // each in the world of seeds[i] when seeded[i] != 0 (its base seed from then on), else of the
  // next seed of its schedule. seeded and seeds may be null (no seeds given).
  struct ResetRequest {
    const uint8_t* mask = nullptr;
    const uint8_t* seeded = nullptr;
    const uint64_t* seeds = nullptr;
  };
  // Resets the requested environments and writes every environment's running episode.
  void reset(const ResetRequest& request, const Episodes& out);
  // Where step() writes, one entry per environment.
  struct StepOutput {
    Episodes now;            // the episode running after the step (the new one after a reset)
    double* rewards;         // the reward of the step (0 for a step that only reset)
    uint8_t* terminated;     // the episode ended: its absorbing state or the stage's time-out
    uint8_t* time_out;       // it ended by the stage's time-out
    uint8_t* restarted;      // the environment began a new episode in this step
    uint8_t* ended;          // its episode ended in this step (by its stage, or by a fault)
    uint8_t* failed;         // its step raised an error (a Lua fault): the episode is over
    uint8_t* truncated;      // its episode was cut short at the decision cap (cap_decisions)
    Episodes last;           // for an ended episode: its last state, seed, time, ticks, decisions
    double* episode_rewards; // for an ended episode: its return (the engine's sum of its rewards)
    uint8_t* success;        // for an ended episode: it reached the absorbing state
  };
  // Steps environment i with actions[i] (or, for one whose episode ended at the last step under
  // kNextStep, or failed, begins its next episode) and writes the outcomes of all. Throws
  // roger::Error before anything runs for an action out of range, or under kDisabled for an
  // environment whose episode is over. After a fault it writes every environment's outcome, then
  // rethrows the error of the lowest environment that failed (failed[] marks them all; their next
  // step begins a new episode, or under kDisabled their reset).
  void step(const int64_t* actions, const StepOutput& out);

  // What a copy of the batch needs (Python's pickle and deepcopy): each environment's schedule
  // and the episode it runs (or ran last), as the seed and actions that replay it.
  struct Snapshot {
    uint64_t base_seed = 0, started = 0;
    bool needs_reset = false;  // its next step begins its next episode (or, kDisabled, needs a reset)
    bool begun = false;        // an episode was begun: `seed` and `actions` replay it
    uint64_t seed = 0;
    std::vector<int> actions;
  };
  std::vector<Snapshot> snapshot() const;
  // Takes each environment's schedule from `s` (one per environment) and replays its episode. An
  // episode that faulted faults again in its replay and is over, as it was; one that ran on and
  // does not replay throws roger::Error.
  void restore(const std::vector<Snapshot>& s);
  // Moves environment i's schedule on without touching its running episode: its next episode runs
  // in the world of `next`, then next + N, ... (Python's make_vec gives an environment whose given
  // seed's schedule would meet another's a schedule of its own after its first world).
  void continue_at(int i, uint64_t next);
  // Ends an episode at its `most`-th decision, as cut short (StepOutput's truncated; terminated
  // and success only if its stage ended it in that decision): Gymnasium's max_episode_steps, which
  // gymnasium.make_vec hands to a vector entry point. 0 (the default) caps nothing.
  void cap_decisions(int most);
  int decision_cap() const { return most_decisions_; }

 private:
  // One environment's part of the current call and what follows its episode.
  struct Slot {
    uint64_t base_seed = 0, started = 0;  // its schedule: the next episode's seed is base + started * N
    bool reset_requested = false, needs_reset = false;
    EnvironmentStep result;
    bool restarted = false, ended = false, failed = false, truncated = false;
    std::vector<Gamma> last_state;
    uint64_t last_seed = 0;
    double last_sim_s = 0.0, last_reward = 0.0;
    int last_ticks = 0, last_decisions = 0;
    bool last_success = false;
  };
  void run_all();        // every environment's job, shared among the threads
  void worker();         // a worker's loop
  void run_jobs();       // takes jobs until none is left
  void job(int i);       // one environment's step (or reset)
  void step_one(int i);  // job(i) of a step
  void begin(int i);     // environment i's next episode along its schedule
  void keep_last(int i); // records the episode that just ended in its slot
  void write_now(const Episodes& out) const;
  void rethrow_first() const;
  std::vector<std::unique_ptr<StageEnvironment>> envs_;
  std::vector<Slot> slots_;
  Autoreset autoreset_ = Autoreset::kNextStep;
  int threads_ = 1;
  int most_decisions_ = 0;  // cap_decisions
  // The work of one call, read by job().
  bool resetting_ = false;
  const int64_t* actions_ = nullptr;
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
