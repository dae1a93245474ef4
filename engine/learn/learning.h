// Module learn: learning over controller states. Owns the Q-table and policy files, the semi-MDP
// driver, learned skills and the one episode loop (episode.h). Depends on control and below;
// must not depend on Lua (script), batch or report: scripts reach it through DecisionHooks.
//
// learning.h: learning a stage of a developmental curriculum (the paper's Sections II.B and III).
// A stage is an MDP whose state is the vector of gamma values of its actions Psi (3^|Psi| states);
// Q-learning with epsilon-greedy exploration (falling linearly from 100% to 5% over the training
// budget) learns it as a semi-MDP: a decision is made when the state changes (or the running
// action gives up, see SemiMdpDriver), and the chosen action runs until then. An episode ends in an absorbing state (+100) or at the time-out (-100,
// also terminal). The greedy policy of a learned stage becomes a skill, one action of later stages.
//
// Policy files (QTable::save/load) are JSON:
//   { "format": "roger-policy", "version": 1,
//     "actions": ["search", "phi0"],            // the names of Psi, in state-vector order
//     "params": { "alpha": 0.1, "discount": 0.95, "epsilon_start": 1.0, "epsilon_end": 0.05,
//                 "initial_q": 0.0, "referenced_only": false },  // false when absent
//     "q":      [[Q(s,0), Q(s,1), ...], ...],   // 3^|Psi| rows of |Psi| numbers
//     "visits": [[n(s,0), n(s,1), ...], ...],   // how many backups each (s, a) received
//     "stage": "search_grasp", "context": "DC1", "seed": 7,   // the caller's metadata
//     "extra": { ... } }                        // optional: anything else the caller keeps
// Numbers are written with the shortest text that reads back to the same double, so a table
// round-trips bit for bit.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "control/agent.h"
#include "control/control.h"
#include "control/predicate.h"
#include "core/rng.h"
#include "core/spec.h"
#include "learn/episode.h"

namespace roger {

// The Q-learning parameters of a stage.
struct QParams {
  double alpha = 0.1;          // learning rate, in (0, 1]
  double discount = 0.95;      // gamma of the backup, in [0, 1]
  double epsilon_start = 1.0;  // exploration at the start of training (the paper: 100%)
  double epsilon_end = 0.05;   // exploration at the end of the budget and after it (the paper: 5%)
  double initial_q = 0.0;      // every value before its first backup
  // Choose only actions with a reference: an action whose gamma is NOREF in the state is not
  // chosen, explored or backed up from (unless every action is NOREF), as a controller's gradient
  // is engaged only inside its region of attraction (the paper's Eq. 1). Off, as the paper's
  // learner: every action may be chosen in every state, and learning which ones run is part of
  // the stage (scripts/ablation.lua measures the difference).
  bool referenced_only = false;
  // Choose only actions still on their way: while some action's gamma is !CONV in the state, an
  // action whose gamma is CONV (nothing left to do) or NOREF (no reference) is not chosen, explored
  // or backed up from; in a state with no !CONV action the rule above decides. Off, as the paper.
  bool unconverged_first = false;
  // What is wrong, naming the offending field ("alpha must be in (0, 1], got -1"), or "" when
  // every value is in range and finite.
  std::string problem() const;
  // Throws roger::Error with problem() after `where` when there is one.
  void validate(const std::string& where = "q-learning") const;
};

// The caller's description of a saved policy, written beside the table.
struct PolicyMetadata {
  std::string stage;                          // e.g. "search_grasp"
  std::string context;                        // e.g. "DC1"
  uint64_t seed = 0;                          // the training trial's seed
  nlohmann::json extra = nlohmann::json();    // anything else (null = not written)
};

// The action-value table of a stage: one row per state (gamma vector), one column per action.
class QTable {
 public:
  // A table for actions with these names (1 to 12 of them, non-empty and distinct), every value
  // params.initial_q. Throws roger::Error for bad names or parameters.
  explicit QTable(std::vector<std::string> action_names, const QParams& params = {});

  // The number of states, 3^actions.
  int states() const { return states_; }
  // The number of actions.
  int actions() const { return actions_; }
  // The actions' names, in state-vector order.
  const std::vector<std::string>& action_names() const { return names_; }
  // The learning parameters.
  const QParams& params() const { return params_; }

  // Q(s, a).
  double value(int s, int a) const;
  // Sets Q(s, a) (for tests and hand-made tables; visits are unchanged).
  void set(int s, int a, double v);
  // How many backups Q(s, a) has received.
  uint64_t visits(int s, int a) const;
  // Whether any action of state s has received a backup: a state never visited still holds
  // initial_q everywhere, so its greedy action says nothing.
  bool visited(int s) const;
  // The number of states visited.
  int visited_states() const;

  // Whether action a may be chosen in state s: always, or with params().referenced_only when its
  // gamma in s is not NOREF or no action of s has a reference.
  bool engageable(int s, int a) const;
  // argmax_a Q(s, a) over the engageable actions, ties to the lowest index so that the policy is
  // deterministic.
  int greedy(int s) const;
  // max_a Q(s, a) over the engageable actions.
  double max_value(int s) const;

  // The action the learned policy takes in s: greedy(s) in a visited state; in a state never
  // visited, greedy() of the nearest visited state (the least sum over actions of |gamma - gamma'|
  // with NOREF < !CONV < CONV, ties to the lowest state index), since a state seen in training
  // that differs in one controller's convergence is a better guide than the initial values;
  // greedy(s) when nothing was visited at all. Only actions engageable in s are chosen.
  int policy_action(int s) const;

  // Epsilon-greedy: with probability epsilon a uniformly random engageable action, else greedy(s). Draws
  // from rng only when epsilon > 0, so a greedy run consumes no random numbers.
  int choose(int s, double epsilon, Rng& rng);
  // A uniformly random engageable action of s (one draw from rng).
  int explore(int s, Rng& rng) const;

  // The Q-learning backup Q(s,a) += alpha (reward + discount_power max_a' Q(s_next,a') - Q(s,a)),
  // without the bootstrap term when `terminal`. discount_power is the discount of this transition:
  // params().discount for one decision, params().discount^k for a transition lasting k units.
  // Counts a visit of (s, a) and returns the TD error (the bracket).
  double update(int s, int a, double reward, int s_next, bool terminal, double discount_power);

  // The table and metadata as JSON in the policy-file format (see the top of this file).
  nlohmann::json to_json(const PolicyMetadata& meta = {}) const;
  // Reads the policy-file format. `expected_actions` are the names the caller's Psi has, in order
  // (empty: accept whatever the file says). `source` names the file in messages. Fills `meta` when
  // given. Throws roger::Error naming the source and the field for a missing field, wrong sizes,
  // non-numbers, bad parameters or action names that differ from the expected ones.
  static QTable from_json(const nlohmann::json& j, const std::vector<std::string>& expected_actions,
                          const std::string& source, PolicyMetadata* meta = nullptr);

  // Writes the policy file atomically (a temporary file beside it, then rename), so a reader
  // never sees half a table. Throws roger::Error naming the file when it cannot be written.
  void save(const std::string& path, const PolicyMetadata& meta = {}) const;
  // Reads a policy file (see from_json). Throws roger::Error naming the file.
  static QTable load(const std::string& path, const std::vector<std::string>& expected_actions,
                     PolicyMetadata* meta = nullptr);

 private:
  void check(int s, int a, const char* what) const;
  uint32_t engageable_mask(int s) const;               // bit a: engageable(s, a)
  int best_in(int row_state, uint32_t mask) const;     // argmax over mask of row_state's values
  std::vector<std::string> names_;
  QParams params_;
  int actions_ = 0, states_ = 0;
  std::vector<double> q_;            // states x actions, row-major
  std::vector<uint64_t> visits_;     // states x actions
  std::vector<uint8_t> state_seen_;  // per state: any visit
};

// The names of a list of controllers, for a QTable over them.
std::vector<std::string> controller_names(const std::vector<ControllerPtr>& psi);

// What a training budget is counted in.
enum class BudgetUnit { kEpisodes, kSimSeconds };

// Exploration falling linearly from epsilon_start to epsilon_end over a budget, then constant at
// epsilon_end (the paper: "decreased linearly from 100% to 5%"). Exact at both ends.
class ExplorationSchedule {
 public:
  // From start to end over `budget` units (> 0). Throws roger::Error for bad values.
  ExplorationSchedule(double start, double end, double budget, BudgetUnit unit = BudgetUnit::kEpisodes);
  // Over a budget of episodes, with the stage's epsilons.
  static ExplorationSchedule episodes(const QParams& params, int budget);
  // Over a budget of simulated seconds, with the stage's epsilons.
  static ExplorationSchedule sim_seconds(const QParams& params, double budget);

  // Epsilon after `spent` units (episodes completed, or simulated seconds trained): exactly
  // `start` at 0 (and before), exactly `end` at the budget and after, linear between.
  double epsilon(double spent) const;

  double start() const { return start_; }    // epsilon at the beginning
  double end() const { return end_; }        // epsilon at and after the budget
  double budget() const { return budget_; }  // the units over which it falls
  BudgetUnit unit() const { return unit_; }  // what the budget counts

 private:
  double start_, end_, budget_;
  BudgetUnit unit_;
};

// The largest magnitude of one reward: an episode's sum of them (thousands of ticks) and the Q
// values built from them stay finite and far from overflow (found by a probe: a step reward of 1e308
// was taken, and training stopped at "q-table: update() needs a finite reward").
constexpr double kMaxRewardMagnitude = 1e12;

// "" or, for a reward beyond kMaxRewardMagnitude, what its refusal says after "must be" or "must
// return": "at most 1e12 in magnitude (...), got 1e+308". One wording for every place a reward is read.
std::string reward_magnitude_problem(double reward);

// How a learning episode runs and pays (the paper: +100 absorbing, -100 time-out, 0 otherwise).
struct LearningEpisodeOptions {
  double time_limit = 5.0;         // simulated seconds (the paper: 5 for search-grasp, 10 transport)
  double success_reward = 100.0;   // reward when the absorbing predicate holds
  double timeout_reward = -100.0;  // reward at the time limit (a failure, and terminal)
  double step_reward = 0.0;        // reward every control tick
  // The clock of the discount: 0 discounts once per decision (the transition from one decision to
  // the next is one step of the semi-MDP); > 0 discounts by discount^(elapsed / discount_seconds),
  // for a discount that depends on how long an action ran.
  double discount_seconds = 0.0;
  // Throws roger::Error naming the field for a value out of range or not finite.
  void validate() const;
};

// What happened in one learning (or greedy evaluation) episode.
struct TrainingEpisode {
  uint64_t seed = 0;
  double reward = 0.0;              // the undiscounted return (step rewards plus the final reward)
  bool success = false;             // the absorbing predicate held before the time limit
  double sim_seconds = 0.0;         // simulated time the episode lasted
  int ticks = 0;                    // control ticks run
  int decisions = 0;                // choices made (first tick, every state change, every give-up)
  // At the end, the objects a sorting task counts and how many of them are sorted
  // (sorted_objects, the world's judgement; both 0 in a world without goal regions' colours).
  int objects_sortable = 0, objects_sorted = 0;
  std::vector<int> actions_taken;   // the action chosen at each decision
  std::vector<int> decision_states; // the state index at each decision
  std::vector<int> action_ticks;    // per action of Psi: the ticks it ran (usage frequencies)
  // The backups of a learning episode: how many, and the sum of their |TD error| (a teacher's
  // measure of how much the episode still had to teach, PLR's score). 0 when not learning.
  int backups = 0;
  double td_abs_sum = 0.0;
};

// Callbacks a stage may define beside its declarative rewards and absorbing predicate (a
// curriculum's Lua functions). They are called at decision points only, never every tick.
class DecisionHooks {
 public:
  virtual ~DecisionHooks() = default;
  // Whether absorbing() is defined: then it is asked at every decision point and at the end.
  virtual bool has_absorbing() const = 0;
  // Whether reward() is defined: then it replaces the declarative rewards.
  virtual bool has_reward() const = 0;
  // An episode begins (before its first decision): what the callbacks keep per episode starts
  // afresh.
  virtual void begin() {}
  // Whether `state` (the gammas of Psi) at simulated time `time` is absorbing.
  virtual bool absorbing(const std::vector<Gamma>& state, double time) = 0;
  // The reward of `action`, which ran until `state`; event is "decision", "absorbing" or "timeout".
  virtual double reward(const std::vector<Gamma>& state, int action, const char* event, double time) = 0;
};

// A stage's semi-MDP as the driver of the episode loop (episode.h). Every control tick it reads
// the state (the gamma of each controller of psi); on the first tick, whenever the state changed,
// and when the running action gave up (Controller::gave_up_on) it backs up the previous decision
// with the reward accumulated since it (when `learn`) and chooses the next action
// epsilon-greedily; the chosen action runs until the next decision.
// The episode ends when `absorbing` holds (success_reward, terminal backup) or at the time limit
// (timeout_reward, terminal backup). With learn = false the table is only read: exploitation uses
// policy_action() (the rule the learned skill follows), so an evaluation measures the skill a
// stage yields. `hooks` (may be null) add Lua rewards and absorbing states at decision points;
// `absorbing` may be null only when the hooks define absorbing(). `judge` (may be null: the
// driver's own) is a judge of `absorbing` that outlives the driver: a trial's episodes share one,
// so its copies of the absorbing predicate's controllers are made once and reset each episode, as
// the originals are. psi must be the table's actions (same count and names). Throws roger::Error
// for a mismatch, a judge of another predicate or bad options.
class SemiMdpDriver final : public EpisodeDriver {
 public:
  SemiMdpDriver(const std::vector<ControllerPtr>& psi, Predicate* absorbing, QTable& q, double epsilon,
                Rng& rng, const LearningEpisodeOptions& options, bool learn, DecisionHooks* hooks = nullptr,
                Judge* judge = nullptr);
  SemiMdpDriver(const SemiMdpDriver&) = delete;  // judge_ may point at its own judge
  SemiMdpDriver& operator=(const SemiMdpDriver&) = delete;
  void begin(uint64_t seed) override;
  Controller* choose(const ControlInput& in) override;
  bool absorbed(const ControlInput& in) override;
  bool end(const ControlInput& in, bool success, int ticks, double time) override;
  bool paused() const override { return awaiting_; }
  Judge* judge() override { return judge_; }
  // What happened in the episode (complete after end()).
  const TrainingEpisode& episode() const { return ep_; }

  // Decisions from outside (an environment stepped from Python): at a decision point the driver
  // closes the previous transition (its reward, and its backup when learning) and pauses the loop
  // until act() gives the action, instead of choosing from the table. Set before begin().
  void choose_externally(bool on) { external_ = on; }
  // Makes every control tick a decision point, not only a change of state (raw-senses learners).
  void decide_every_tick(bool on) { every_tick_ = on; }
  // Whether the driver waits for act().
  bool awaiting() const { return awaiting_; }
  // Gives the action of the pending decision. Throws roger::Error when none is pending or `a` is
  // not an action of psi.
  void act(int a);
  // The gammas of psi at the last decision point (or at the end of the episode).
  const std::vector<Gamma>& gammas() const { return gammas_; }
  // The undiscounted reward of the transition that ended at the last decision point or at the
  // end of the episode: its step rewards and the Lua reward or the final reward that closed it.
  double transition_reward() const { return transition_reward_; }

 private:
  int read_state(const ControlInput& in);
  void decide(int s, double now);
  void close_transition(int s, double now);
  void open_decision(int s, double now, int a);
  void backed_up(double td_error);  // counts a backup's |TD error| into the episode
  double discount_within(double elapsed) const;
  double discount_bootstrap(double elapsed) const;
  const std::vector<ControllerPtr>& psi_;
  Predicate* absorbing_;
  Judge own_judge_;  // the absorbing predicate judged on the true world (noise never decides success)
  Judge* judge_;     // own_judge_ or the caller's
  QTable& q_;
  const double epsilon_;
  Rng& rng_;
  const LearningEpisodeOptions& options_;
  const bool learn_;
  DecisionHooks* hooks_;
  const bool hooked_reward_, hooked_absorbing_;  // what the hooks define, asked once
  TrainingEpisode ep_;
  std::vector<Gamma> gammas_;
  int state_ = -1, action_ = -1;
  double accumulated_ = 0.0;  // reward since the last decision, discounted to it
  double decided_at_ = 0.0;   // simulated time of the last decision
  double tick_start_ = 0.0;   // simulated time at the start of the running tick
  bool external_ = false, every_tick_ = false;
  bool awaiting_ = false;     // paused at a decision point until act()
  bool resumed_ = false;      // act() gave the action of this tick's decision
  int pending_state_ = -1;    // the state of the decision act() completes
  double running_reward_ = 0.0, transition_reward_ = 0.0;  // undiscounted, see transition_reward()
};

// One episode of a stage through the episode loop with a SemiMdpDriver (no hooks), in a fresh
// world: resets the agent, every controller of psi (with `seed`) and the absorbing predicate.
TrainingEpisode run_learning_episode(Agent& agent, const WorldSpec& spec, uint64_t seed,
                                     const std::vector<ControllerPtr>& psi, Predicate& absorbing,
                                     QTable& q, double epsilon, Rng& rng,
                                     const LearningEpisodeOptions& options, bool learn);

// The greedy policy of a learned stage as a skill, usable as one action of a later stage. Every
// tick it runs policy_action() of the current state (a snapshot of q taken now: later training
// does not change the skill). Its gamma: CONV exactly when `absorbing` holds, NOREF when none of
// its actions has a reference, !CONV otherwise. Its kind is "learned"; resetting it resets psi and
// the predicate. Throws roger::Error when psi does not match q or absorbing is null.
ControllerPtr make_policy_skill(const std::string& name, const std::vector<ControllerPtr>& psi,
                                const QTable& q, PredicatePtr absorbing);

}  // namespace roger
