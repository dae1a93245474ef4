#include "learn/learning.h"

#include "core/fileio.h"

#include <unistd.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace roger {
namespace {

constexpr const char* kFormat = "roger-policy";
constexpr int kVersion = 1;
constexpr int kMaxActions = 12;  // 3^12 = 531441 states: the same bound as Policy

bool finite(double v) { return std::isfinite(v); }

// "[a, b, c]" for messages.
std::string list_names(const std::vector<std::string>& names) {
  std::string s = "[";
  for (size_t i = 0; i < names.size(); ++i) s += (i ? ", \"" : "\"") + names[i] + "\"";
  return s + "]";
}

// The state (gamma vector) nearest to s among the visited ones: the least sum over actions of
// |gamma_i - gamma'_i| (NOREF = 0 < !CONV = 1 < CONV = 2), ties to the lowest index; -1 if none.
// gamma_state_index puts the first action in the most significant base-3 digit; the distance
// does not depend on the order, so digits are compared from the least significant one.
template <typename Visited>
int nearest_visited_state(int s, int states, int actions, const Visited& visited) {
  int best = -1, best_distance = INT_MAX;
  for (int t = 0; t < states; ++t) {
    if (!visited(t)) continue;
    int distance = 0, a = s, b = t;
    for (int i = 0; i < actions; ++i, a /= 3, b /= 3) distance += std::abs(a % 3 - b % 3);
    if (distance < best_distance) best_distance = distance, best = t;
  }
  return best;
}

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

// The greedy policy of a learned stage as a controller (see make_policy_skill).
class LearnedSkill final : public Controller {
 public:
  LearnedSkill(const std::string& name, std::vector<ControllerPtr> psi, const QTable& q,
               PredicatePtr absorbing)
      : actions_(std::move(psi)), absorbing_(std::move(absorbing)) {
    set_name(name);
    states_ = q.states();
    // A snapshot of what policy_action() needs: later training must not change a skill that a
    // later stage already learned to use.
    greedy_.resize(size_t(states_));
    visited_.resize(size_t(states_));
    for (int s = 0; s < states_; ++s) {
      greedy_[size_t(s)] = q.greedy(s);
      visited_[size_t(s)] = q.visited(s) ? 1 : 0;
    }
    resolved_.assign(size_t(states_), -1);
    scratch_.resize(actions_.size());
  }

  std::vector<const Controller*> children() const override {
    std::vector<const Controller*> c;
    for (const auto& a : actions_) c.push_back(a.get());
    std::vector<const Controller*> read;
    absorbing_->controllers(read);
    for (const Controller* r : read)
      if (std::find(c.begin(), c.end(), r) == c.end()) c.push_back(r);
    return c;
  }

  const char* kind() const override { return "learned"; }

  void reset(uint64_t seed) override {
    Controller::reset(seed);
    for (auto& a : actions_) a->reset(seed);
    reset_predicate(*absorbing_, seed);
    absorbing_tick_ = UINT64_MAX;
    last_action_ = -1;
  }

 protected:
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) override {
    const int s = read_state(in, gamma_raw);
    last_action_ = action_for(s);
    const ControlOutput& run = actions_[size_t(last_action_)]->evaluate(in);
    out.command = run.command;
    out.jacobian = run.jacobian;
    out.phi = run.phi;
    out.residual = run.residual;
  }

  bool compute_state(const ControlInput& in, ControlOutput&, Gamma& gamma_raw) override {
    read_state(in, gamma_raw);
    return true;
  }

 public:
  // The action whose command this tick used was executed.
  void executed(const ControlInput& in) override {
    if (last_action_ >= 0) actions_[size_t(last_action_)]->executed(in);
  }

 protected:

 private:
  // The state index and the skill's own gamma at this tick.
  int read_state(const ControlInput& in, Gamma& gamma_raw) {
    bool any_reference = false;
    for (size_t i = 0; i < actions_.size(); ++i) {
      scratch_[i] = actions_[i]->state(in);
      any_reference |= scratch_[i] != Gamma::kNoRef;
    }
    // The predicate is asked once per tick, even when state() and evaluate() both run.
    if (absorbing_tick_ != in.tick) {
      absorbing_tick_ = in.tick;
      absorbing_now_ = absorbing_->holds(in);
    }
    gamma_raw = absorbing_now_ ? Gamma::kConv : any_reference ? Gamma::kNotConv : Gamma::kNoRef;
    return gamma_state_index(scratch_);
  }

  int last_action_ = -1;  // the action run at the last full evaluation

  // QTable::policy_action on the snapshot, resolved once per state.
  int action_for(int s) {
    int& a = resolved_[size_t(s)];
    if (a >= 0) return a;
    if (visited_[size_t(s)]) return a = greedy_[size_t(s)];
    const int t = nearest_visited_state(s, states_, int(actions_.size()),
                                        [this](int k) { return visited_[size_t(k)] != 0; });
    return a = greedy_[size_t(t >= 0 ? t : s)];
  }

  std::vector<ControllerPtr> actions_;
  PredicatePtr absorbing_;
  int states_ = 0;
  std::vector<int> greedy_;       // per state: the table's greedy action
  std::vector<uint8_t> visited_;  // per state: visited in training
  std::vector<int> resolved_;     // per state: the action taken, -1 until first needed
  std::vector<Gamma> scratch_;
  uint64_t absorbing_tick_ = UINT64_MAX;
  bool absorbing_now_ = false;
};

// Field access with messages naming the source and the field.
const nlohmann::json& field(const nlohmann::json& j, const char* name, const std::string& source) {
  auto it = j.find(name);
  if (it == j.end()) throw Error(source + ": missing field \"" + name + "\"");
  return *it;
}

double number(const nlohmann::json& j, const std::string& what, const std::string& source) {
  if (!j.is_number()) throw Error(source + ": " + what + " must be a number, got " + j.dump());
  const double v = j.get<double>();
  if (!finite(v)) throw Error(source + ": " + what + " must be finite");
  return v;
}

}  // namespace

void QParams::validate(const std::string& where) const {
  auto in = [&](const char* name, double v, bool open_below, const char* range) {
    if (!finite(v) || v > 1.0 || v < 0.0 || (open_below && v == 0.0))
      throw Error(where + ": " + name + " must be in " + range + ", got " + std::to_string(v));
  };
  in("alpha", alpha, true, "(0, 1]");
  in("discount", discount, false, "[0, 1]");
  in("epsilon_start", epsilon_start, false, "[0, 1]");
  in("epsilon_end", epsilon_end, false, "[0, 1]");
  if (!finite(initial_q)) throw Error(where + ": initial_q must be finite, got " + std::to_string(initial_q));
}

QTable::QTable(std::vector<std::string> action_names, const QParams& params)
    : names_(std::move(action_names)), params_(params) {
  params_.validate();
  if (names_.empty() || int(names_.size()) > kMaxActions)
    throw Error("q-table: needs 1 to " + std::to_string(kMaxActions) + " actions (3^n states), got " +
                std::to_string(names_.size()));
  for (size_t i = 0; i < names_.size(); ++i) {
    if (names_[i].empty()) throw Error("q-table: action " + std::to_string(i) + " has no name");
    for (size_t k = 0; k < i; ++k)
      if (names_[k] == names_[i])
        throw Error("q-table: two actions are named \"" + names_[i] +
                    "\"; names identify actions in policy files");
  }
  actions_ = int(names_.size());
  states_ = 1;
  for (int i = 0; i < actions_; ++i) states_ *= 3;
  q_.assign(size_t(states_) * size_t(actions_), params_.initial_q);
  visits_.assign(q_.size(), 0);
  state_seen_.assign(size_t(states_), 0);
}

void QTable::check(int s, int a, const char* what) const {
  if (s < 0 || s >= states_ || a < 0 || a >= actions_)
    throw Error(std::string("q-table: ") + what + "(" + std::to_string(s) + ", " + std::to_string(a) +
                ") outside " + std::to_string(states_) + " states x " + std::to_string(actions_) +
                " actions");
}

double QTable::value(int s, int a) const {
  check(s, a, "value");
  return q_[size_t(s) * size_t(actions_) + size_t(a)];
}

void QTable::set(int s, int a, double v) {
  check(s, a, "set");
  if (!finite(v)) throw Error("q-table: set() needs a finite value");
  q_[size_t(s) * size_t(actions_) + size_t(a)] = v;
}

uint64_t QTable::visits(int s, int a) const {
  check(s, a, "visits");
  return visits_[size_t(s) * size_t(actions_) + size_t(a)];
}

bool QTable::visited(int s) const {
  check(s, 0, "visited");
  return state_seen_[size_t(s)] != 0;
}

int QTable::visited_states() const {
  return int(std::count(state_seen_.begin(), state_seen_.end(), uint8_t(1)));
}

int QTable::greedy(int s) const {
  check(s, 0, "greedy");
  const double* row = &q_[size_t(s) * size_t(actions_)];
  int best = 0;
  for (int a = 1; a < actions_; ++a)
    if (row[a] > row[best]) best = a;  // strict: ties keep the lowest index
  return best;
}

double QTable::max_value(int s) const {
  return q_[size_t(s) * size_t(actions_) + size_t(greedy(s))];
}

int QTable::policy_action(int s) const {
  if (visited(s)) return greedy(s);
  const int t = nearest_visited_state(s, states_, actions_,
                                      [this](int k) { return state_seen_[size_t(k)] != 0; });
  return greedy(t >= 0 ? t : s);
}

int QTable::choose(int s, double epsilon, Rng& rng) {
  check(s, 0, "choose");
  if (!(epsilon >= 0.0 && epsilon <= 1.0)) throw Error("q-table: epsilon must be in [0, 1]");
  if (epsilon > 0.0 && rng.uniform() < epsilon) return int(rng.integer(0, actions_ - 1));
  return greedy(s);
}

double QTable::update(int s, int a, double reward, int s_next, bool terminal, double discount_power) {
  check(s, a, "update");
  check(s_next, 0, "update");
  if (!finite(reward)) throw Error("q-table: update() needs a finite reward");
  if (!(discount_power >= 0.0 && discount_power <= 1.0))
    throw Error("q-table: update() needs a discount in [0, 1]");
  double& v = q_[size_t(s) * size_t(actions_) + size_t(a)];
  const double target = reward + (terminal ? 0.0 : discount_power * max_value(s_next));
  const double td = target - v;
  v += params_.alpha * td;
  ++visits_[size_t(s) * size_t(actions_) + size_t(a)];
  state_seen_[size_t(s)] = 1;
  return td;
}

nlohmann::json QTable::to_json(const PolicyMetadata& meta) const {
  nlohmann::json j;
  j["format"] = kFormat;
  j["version"] = kVersion;
  j["stage"] = meta.stage;
  j["context"] = meta.context;
  j["seed"] = meta.seed;
  j["actions"] = names_;
  j["params"] = {{"alpha", params_.alpha},
                 {"discount", params_.discount},
                 {"epsilon_start", params_.epsilon_start},
                 {"epsilon_end", params_.epsilon_end},
                 {"initial_q", params_.initial_q}};
  nlohmann::json q = nlohmann::json::array(), visits = nlohmann::json::array();
  for (int s = 0; s < states_; ++s) {
    nlohmann::json qrow = nlohmann::json::array(), vrow = nlohmann::json::array();
    for (int a = 0; a < actions_; ++a) {
      qrow.push_back(q_[size_t(s) * size_t(actions_) + size_t(a)]);
      vrow.push_back(visits_[size_t(s) * size_t(actions_) + size_t(a)]);
    }
    q.push_back(std::move(qrow));
    visits.push_back(std::move(vrow));
  }
  j["q"] = std::move(q);
  j["visits"] = std::move(visits);
  if (!meta.extra.is_null()) j["extra"] = meta.extra;
  return j;
}

QTable QTable::from_json(const nlohmann::json& j, const std::vector<std::string>& expected,
                         const std::string& source, PolicyMetadata* meta) {
  if (!j.is_object()) throw Error(source + ": a policy file must hold a JSON object");
  const auto& format = field(j, "format", source);
  if (!format.is_string() || format.get<std::string>() != kFormat)
    throw Error(source + ": field \"format\" must be \"" + kFormat + "\", got " + format.dump());
  const auto& version = field(j, "version", source);
  if (!version.is_number_integer() || version.get<int64_t>() != kVersion)
    throw Error(source + ": field \"version\" must be " + std::to_string(kVersion) + ", got " +
                version.dump());

  const auto& jactions = field(j, "actions", source);
  if (!jactions.is_array()) throw Error(source + ": field \"actions\" must be a list of names");
  std::vector<std::string> names;
  for (const auto& n : jactions) {
    if (!n.is_string()) throw Error(source + ": field \"actions\" must be a list of names, got " + n.dump());
    names.push_back(n.get<std::string>());
  }
  if (!expected.empty() && names != expected)
    throw Error(source + ": field \"actions\" is " + list_names(names) +
                " but this stage's actions are " + list_names(expected) +
                " (a policy is tied to its action set and order)");

  const auto& jp = field(j, "params", source);
  if (!jp.is_object()) throw Error(source + ": field \"params\" must be an object");
  QParams p;
  auto param = [&](const char* name) {
    return number(field(jp, name, source + ": params"), std::string("params.") + name, source);
  };
  p.alpha = param("alpha");
  p.discount = param("discount");
  p.epsilon_start = param("epsilon_start");
  p.epsilon_end = param("epsilon_end");
  p.initial_q = param("initial_q");
  p.validate(source + ": params");

  QTable t = [&] {
    try {
      return QTable(names, p);
    } catch (const Error& e) {
      throw Error(source + ": field \"actions\": " + e.what());
    }
  }();

  auto rows = [&](const char* name) -> const nlohmann::json& {
    const auto& r = field(j, name, source);
    if (!r.is_array() || int(r.size()) != t.states_)
      throw Error(source + ": field \"" + name + "\" must have " + std::to_string(t.states_) +
                  " rows (3^" + std::to_string(t.actions_) + " states), got " +
                  (r.is_array() ? std::to_string(r.size()) : r.type_name()));
    for (size_t s = 0; s < r.size(); ++s)
      if (!r[s].is_array() || int(r[s].size()) != t.actions_)
        throw Error(source + ": field \"" + name + "\" row " + std::to_string(s) + " must have " +
                    std::to_string(t.actions_) + " entries (one per action)");
    return r;
  };
  const auto& jq = rows("q");
  const auto& jv = rows("visits");
  for (int s = 0; s < t.states_; ++s)
    for (int a = 0; a < t.actions_; ++a) {
      const size_t k = size_t(s) * size_t(t.actions_) + size_t(a);
      t.q_[k] = number(jq[size_t(s)][size_t(a)],
                       "field \"q\" [" + std::to_string(s) + "][" + std::to_string(a) + "]", source);
      const auto& v = jv[size_t(s)][size_t(a)];
      if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<int64_t>() >= 0))
        throw Error(source + ": field \"visits\" [" + std::to_string(s) + "][" + std::to_string(a) +
                    "] must be a count (an integer >= 0), got " + v.dump());
      t.visits_[k] = v.get<uint64_t>();
      if (t.visits_[k] > 0) t.state_seen_[size_t(s)] = 1;
    }

  PolicyMetadata m;
  const auto& stage = field(j, "stage", source);
  const auto& context = field(j, "context", source);
  const auto& seed = field(j, "seed", source);
  if (!stage.is_string()) throw Error(source + ": field \"stage\" must be a string");
  if (!context.is_string()) throw Error(source + ": field \"context\" must be a string");
  if (!seed.is_number_unsigned() && !(seed.is_number_integer() && seed.get<int64_t>() >= 0))
    throw Error(source + ": field \"seed\" must be an integer >= 0");
  m.stage = stage.get<std::string>();
  m.context = context.get<std::string>();
  m.seed = seed.get<uint64_t>();
  if (auto it = j.find("extra"); it != j.end()) m.extra = *it;
  if (meta) *meta = std::move(m);
  return t;
}

void QTable::save(const std::string& path, const PolicyMetadata& meta) const {
  write_file_atomic(path, to_json(meta).dump(1) + "\n", "cannot write the policy file");
}

QTable QTable::load(const std::string& path, const std::vector<std::string>& expected,
                    PolicyMetadata* meta) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot read the policy file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(buffer.str());
  } catch (const nlohmann::json::parse_error& e) {
    throw Error(path + ": not valid JSON: " + e.what());
  }
  return from_json(j, expected, path, meta);
}

std::vector<std::string> controller_names(const std::vector<ControllerPtr>& psi) {
  std::vector<std::string> names;
  for (size_t i = 0; i < psi.size(); ++i) {
    if (!psi[i]) throw Error("psi[" + std::to_string(i) + "] is not a controller");
    names.push_back(psi[i]->name());
  }
  return names;
}

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

void LearningEpisodeOptions::validate() const {
  if (!(time_limit > 0.0) || !finite(time_limit))
    throw Error("learning episode: time_limit must be positive and finite");
  if (!finite(success_reward)) throw Error("learning episode: success_reward must be finite");
  if (!finite(timeout_reward)) throw Error("learning episode: timeout_reward must be finite");
  if (!finite(step_reward)) throw Error("learning episode: step_reward must be finite");
  if (!(discount_seconds >= 0.0) || !finite(discount_seconds))
    throw Error("learning episode: discount_seconds must be >= 0 and finite");
}

TrainingEpisode run_learning_episode(Agent& agent, const WorldSpec& spec, uint64_t seed,
                                     const std::vector<ControllerPtr>& psi, Predicate& absorbing,
                                     QTable& q, double epsilon, Rng& rng,
                                     const LearningEpisodeOptions& options, bool learn) {
  options.validate();
  check_psi(psi, q, "learning episode");
  if (!(epsilon >= 0.0 && epsilon <= 1.0)) throw Error("learning episode: epsilon must be in [0, 1]");
  agent.reset(spec);
  for (const auto& c : psi) c->reset(seed);
  reset_predicate(absorbing, seed);

  const int n = q.actions();
  TrainingEpisode ep;
  ep.seed = seed;
  ep.action_ticks.assign(size_t(n), 0);
  const double dt = agent.world().tick_seconds();
  const int max_ticks = int(std::ceil(options.time_limit / dt - 1e-9));
  const double gamma = q.params().discount;
  // Discount of a reward `elapsed` seconds into a decision, and of the bootstrap at the next
  // decision: with the per-decision clock, rewards within one decision are not discounted and the
  // next decision is one step away.
  const bool timed = options.discount_seconds > 0.0;
  auto within = [&](double elapsed) { return timed ? std::pow(gamma, elapsed / options.discount_seconds) : 1.0; };
  auto bootstrap = [&](double elapsed) { return timed ? std::pow(gamma, elapsed / options.discount_seconds) : gamma; };

  std::vector<Gamma> gammas(static_cast<size_t>(n));
  int state = -1, action = -1;
  double accumulated = 0.0;  // reward since the last decision, discounted to it
  double decided_at = 0.0;   // simulated time of the last decision
  for (int t = 0; t < max_ticks; ++t) {
    const ControlInput& in = agent.input();
    const double now = in.time;  // `in` changes under us when the agent steps
    for (int i = 0; i < n; ++i) gammas[size_t(i)] = psi[size_t(i)]->state(in);
    const int s = gamma_state_index(gammas);
    if (s != state) {
      // Semi-MDP: the previous action ran until this change of state; its transition ends here.
      if (learn && action >= 0) q.update(state, action, accumulated, s, false, bootstrap(now - decided_at));
      if (learn) {
        action = q.choose(s, epsilon, rng);
      } else if (epsilon > 0.0 && rng.uniform() < epsilon) {
        action = int(rng.integer(0, n - 1));
      } else {
        action = q.policy_action(s);
      }
      state = s;
      accumulated = 0.0;
      decided_at = now;
      ++ep.decisions;
      ep.actions_taken.push_back(action);
      ep.decision_states.push_back(s);
    }
    agent.step(*psi[size_t(action)]);
    ++ep.action_ticks[size_t(action)];
    ep.ticks = t + 1;
    accumulated += within(now - decided_at) * options.step_reward;
    ep.reward += options.step_reward;
    if (absorbing.holds(agent.input())) {
      ep.success = true;
      break;
    }
  }
  ep.sim_seconds = agent.world().time();
  const double final_reward = ep.success ? options.success_reward : options.timeout_reward;
  ep.reward += final_reward;
  // Both ends are terminal: the absorbing state by definition, and the time-out because the
  // paper's episode simply stops there as a failure (no value beyond it to bootstrap from).
  if (learn && action >= 0)
    q.update(state, action, accumulated + within(ep.sim_seconds - decided_at) * final_reward, state,
             true, gamma);
  return ep;
}

ControllerPtr make_policy_skill(const std::string& name, const std::vector<ControllerPtr>& psi,
                                const QTable& q, PredicatePtr absorbing) {
  if (name.empty()) throw Error("learned skill: needs a name");
  if (!absorbing) throw Error("learned skill \"" + name + "\": needs an absorbing predicate");
  check_psi(psi, q, "learned skill \"" + name + "\"");
  return std::make_shared<LearnedSkill>(name, psi, q, std::move(absorbing));
}

}  // namespace roger
