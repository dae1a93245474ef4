// learning.cpp: the exploration schedule, the options of a learning episode, and a stage's
// semi-MDP as the driver of the one episode loop (episode.h).
#include "learn/learning.h"

#include <cmath>

#include "core/error.h"
#include "core/text.h"
#include "learn/episode.h"
#include "learn/learning_internal.h"

namespace roger {

using namespace learning_detail;

namespace learning_detail {

// Checks that psi is the table's action set, in order.
void check_psi(const std::vector<ControllerPtr>& psi, const QTable& q, const std::string& where) {
  if (int(psi.size()) != q.actions())
    throw Error(where + ": the table has " + std::to_string(q.actions()) + " actions " +
                list_names(q.action_names()) + " but psi has " + std::to_string(psi.size()));
  for (size_t i = 0; i < psi.size(); ++i) {
    if (!psi[i]) throw Error(where + ": psi[" + std::to_string(i) + "] is not a controller");
    if (psi[i]->name() != q.action_names()[i])
      throw Error(where + ": action " + std::to_string(i) + " of the table is \"" +
                  q.action_names()[i] + "\" but psi has \"" + psi[i]->name() + "\" there");
  }
}

}  // namespace learning_detail

ExplorationSchedule::ExplorationSchedule(double start, double end, double budget, BudgetUnit unit)
    : start_(start), end_(end), budget_(budget), unit_(unit) {
  if (!(start >= 0.0 && start <= 1.0)) throw Error("exploration: epsilon_start must be in [0, 1]");
  if (!(end >= 0.0 && end <= 1.0)) throw Error("exploration: epsilon_end must be in [0, 1]");
  if (!(budget > 0.0) || !finite(budget)) throw Error("exploration: the budget must be positive and finite");
}

ExplorationSchedule ExplorationSchedule::episodes(const QParams& params, int budget) {
  params.validate("exploration");
  return ExplorationSchedule(params.epsilon_start, params.epsilon_end, double(budget), BudgetUnit::kEpisodes);
}

ExplorationSchedule ExplorationSchedule::sim_seconds(const QParams& params, double budget) {
  params.validate("exploration");
  return ExplorationSchedule(params.epsilon_start, params.epsilon_end, budget, BudgetUnit::kSimSeconds);
}

double ExplorationSchedule::epsilon(double spent) const {
  // The ends are returned as given rather than computed: start + (end - start) * 1 need not
  // equal end in floating point.
  if (!(spent > 0.0)) return start_;
  if (spent >= budget_) return end_;
  const double f = spent / budget_;
  return start_ + (end_ - start_) * f;
}

std::string reward_magnitude_problem(double reward) {
  if (!(std::fabs(reward) > kMaxRewardMagnitude)) return "";
  return "at most 1e12 in magnitude (an episode's sum of rewards and the Q values must stay finite), got " +
         format_number(reward);
}

void LearningEpisodeOptions::validate() const {
  if (!(time_limit > 0.0) || !finite(time_limit))
    throw Error("learning episode: time_limit must be positive and finite");
  for (const auto& [name, r] : {std::pair<const char*, double>{"success_reward", success_reward},
                                {"timeout_reward", timeout_reward}, {"step_reward", step_reward}}) {
    if (!finite(r)) throw Error(std::string("learning episode: ") + name + " must be finite");
    if (const std::string p = reward_magnitude_problem(r); !p.empty())
      throw Error(std::string("learning episode: ") + name + " must be " + p);
  }
  if (!(discount_seconds >= 0.0) || !finite(discount_seconds))
    throw Error("learning episode: discount_seconds must be >= 0 and finite");
}


SemiMdpDriver::SemiMdpDriver(const std::vector<ControllerPtr>& psi, Predicate* absorbing, QTable& q,
                             double epsilon, Rng& rng, const LearningEpisodeOptions& options, bool learn,
                             DecisionHooks* hooks, Judge* judge)
    : psi_(psi), absorbing_(absorbing), own_judge_(absorbing), judge_(judge ? judge : &own_judge_), q_(q), epsilon_(epsilon), rng_(rng), options_(options), learn_(learn),
      hooks_(hooks), hooked_reward_(hooks && hooks->has_reward()), hooked_absorbing_(hooks && hooks->has_absorbing()) {
  options.validate();
  check_psi(psi, q, "learning episode");
  if (!(epsilon >= 0.0 && epsilon <= 1.0)) throw Error("learning episode: epsilon must be in [0, 1]");
  if (!absorbing && !hooked_absorbing_)
    throw Error("learning episode: needs an absorbing predicate or an absorbing callback");
  if (judge_->predicate() != absorbing) throw Error("learning episode: the judge given judges another predicate");
  gammas_.resize(psi.size());
}

void SemiMdpDriver::begin(uint64_t seed) {
  for (const auto& c : psi_) c->reset(seed);
  if (absorbing_) reset_predicate(*absorbing_, seed);
  judge_->reset(seed);
  ep_ = TrainingEpisode();
  ep_.seed = seed;
  ep_.action_ticks.assign(psi_.size(), 0);
  state_ = action_ = pending_state_ = -1;
  accumulated_ = decided_at_ = tick_start_ = running_reward_ = transition_reward_ = 0.0;
  awaiting_ = resumed_ = false;
  if (hooks_) hooks_->begin();
}

// The discount of a reward `elapsed` seconds into a decision, and of the bootstrap at the next
// decision: with the per-decision clock (discount_seconds = 0), rewards within one decision are
// not discounted and the next decision is one step away.
double SemiMdpDriver::discount_within(double elapsed) const {
  return options_.discount_seconds > 0.0 ? std::pow(q_.params().discount, elapsed / options_.discount_seconds) : 1.0;
}

double SemiMdpDriver::discount_bootstrap(double elapsed) const {
  return options_.discount_seconds > 0.0 ? std::pow(q_.params().discount, elapsed / options_.discount_seconds)
                                         : q_.params().discount;
}

int SemiMdpDriver::read_state(const ControlInput& in) {
  for (size_t i = 0; i < psi_.size(); ++i) gammas_[i] = psi_[i]->state(in);
  return gamma_state_index(gammas_);
}

// A decision in state s at time `now`: backs up the previous one and chooses the next action.
void SemiMdpDriver::decide(int s, double now) {
  close_transition(s, now);
  int a;
  if (learn_) {
    a = q_.choose(s, epsilon_, rng_);
  } else if (epsilon_ > 0.0 && rng_.uniform() < epsilon_) {
    a = q_.explore(s, rng_);
  } else {
    a = q_.policy_action(s);
  }
  open_decision(s, now, a);
}

// Semi-MDP: the previous action ran until this change of state; its transition ends here.
void SemiMdpDriver::close_transition(int s, double now) {
  if (action_ < 0) return;
  const double r = hooked_reward_ ? hooks_->reward(gammas_, action_, "decision", now) : accumulated_;
  if (hooked_reward_) {
    ep_.reward += r;
    running_reward_ += r;
  }
  if (learn_) backed_up(q_.update(state_, action_, r, s, false, discount_bootstrap(now - decided_at_)));
  transition_reward_ = running_reward_;
  running_reward_ = 0.0;
}

void SemiMdpDriver::backed_up(double td_error) {
  ++ep_.backups;
  ep_.td_abs_sum += std::abs(td_error);
}

void SemiMdpDriver::open_decision(int s, double now, int a) {
  action_ = a;
  state_ = s;
  accumulated_ = 0.0;
  decided_at_ = now;
  ++ep_.decisions;
  ep_.actions_taken.push_back(action_);
  ep_.decision_states.push_back(s);
}

void SemiMdpDriver::act(int a) {
  if (!awaiting_) throw Error("learning episode: no decision is pending (the episode is over or not begun)");
  if (a < 0 || a >= int(psi_.size()))
    throw Error("learning episode: action index " + std::to_string(a) + " is not in [0, " +
                std::to_string(psi_.size()) + ")");
  open_decision(pending_state_, tick_start_, a);
  awaiting_ = false;
  resumed_ = true;
}

Controller* SemiMdpDriver::choose(const ControlInput& in) {
  if (resumed_) {  // the tick paused for act(): its state was read and its transition closed
    resumed_ = false;
    return psi_[size_t(action_)].get();
  }
  tick_start_ = in.time;  // `in` changes under us when the agent steps
  const int s = read_state(in);
  // A decision at every change of state, and when the running action gave up without one.
  if (s != state_ || every_tick_ || (action_ >= 0 && psi_[size_t(action_)]->gave_up_on(in.tick))) {
    if (hooked_absorbing_ && hooks_->absorbing(gammas_, tick_start_)) return nullptr;
    if (!external_) {
      decide(s, tick_start_);
    } else {
      close_transition(s, tick_start_);
      pending_state_ = s;
      awaiting_ = true;
      return nullptr;
    }
  }
  return psi_[size_t(action_)].get();
}

bool SemiMdpDriver::absorbed(const ControlInput& in) {
  ++ep_.action_ticks[size_t(action_)];
  if (!hooked_reward_) {
    accumulated_ += discount_within(tick_start_ - decided_at_) * options_.step_reward;
    ep_.reward += options_.step_reward;
    running_reward_ += options_.step_reward;
  }
  return judge_->holds(in);
}

bool SemiMdpDriver::end(const ControlInput& in, bool success, int ticks, double time) {
  ep_.ticks = ticks;
  ep_.sim_seconds = time;
  const SortCount sort = sorted_objects(in);
  ep_.objects_sortable = sort.sortable;
  ep_.objects_sorted = sort.sorted;
  // The last tick may have reached the absorbing state without a decision point after it.
  if (!success && hooked_absorbing_ && ticks > 0) {
    read_state(in);
    success = hooks_->absorbing(gammas_, time);
  }
  ep_.success = success;
  if (action_ < 0) return success;
  double final_reward;
  if (hooked_reward_) {
    read_state(in);
    final_reward = hooks_->reward(gammas_, action_, success ? "absorbing" : "timeout", time);
  } else {
    final_reward = success ? options_.success_reward : options_.timeout_reward;
  }
  ep_.reward += final_reward;
  running_reward_ += final_reward;
  transition_reward_ = running_reward_;
  // Both ends are terminal: the absorbing state by definition, and the time-out because the
  // paper's episode simply stops there as a failure (no value beyond it to bootstrap from).
  if (learn_)
    backed_up(q_.update(state_, action_, accumulated_ + discount_within(time - decided_at_) * final_reward, state_,
                        true, q_.params().discount));
  return success;
}

TrainingEpisode run_learning_episode(Agent& agent, const WorldSpec& spec, uint64_t seed,
                                     const std::vector<ControllerPtr>& psi, Predicate& absorbing,
                                     QTable& q, double epsilon, Rng& rng,
                                     const LearningEpisodeOptions& options, bool learn) {
  SemiMdpDriver driver(psi, &absorbing, q, epsilon, rng, options, learn);
  run_episode(agent, spec, seed, driver, options.time_limit);
  return driver.episode();
}
}  // namespace roger
