// learned_skill.cpp: the greedy policy of a learned stage as a skill, one action of later stages.
#include <algorithm>
#include <cstdint>

#include "core/error.h"
#include "learn/learning.h"
#include "learn/learning_internal.h"

namespace roger {

using namespace learning_detail;

namespace {

// The greedy policy of a learned stage as a controller (see make_policy_skill).
class LearnedSkill final : public Controller {
 public:
  LearnedSkill(const std::string& name, std::vector<ControllerPtr> psi, const QTable& q,
               PredicatePtr absorbing)
      // A copy of the table: later training must not change a skill that a later stage already
      // learned to use.
      : actions_(std::move(psi)), absorbing_(std::move(absorbing)), q_(q) {
    set_name(name);
    resolved_.assign(size_t(q_.states()), -1);
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
  ControllerPtr copy() const override { return std::make_shared<LearnedSkill>(*this); }
  void relink(Duplicates& done) override {
    for (auto& a : actions_) a = duplicate(a, done);
    absorbing_ = duplicate(absorbing_, done);
  }
  const Controller* inner() const override { return last_action_ >= 0 ? actions_[size_t(last_action_)].get() : nullptr; }

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

  // The action whose command this tick used was executed.
  void pass_executed(const ControlInput& in) override {
    if (last_action_ >= 0) actions_[size_t(last_action_)]->executed(in);
  }

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

  // QTable::policy_action on the snapshot, resolved once per state (a state never visited
  // searches the table for its nearest visited one).
  int action_for(int s) {
    int& a = resolved_[size_t(s)];
    if (a < 0) a = q_.policy_action(s);
    return a;
  }

  std::vector<ControllerPtr> actions_;
  PredicatePtr absorbing_;
  const QTable q_;
  std::vector<int> resolved_;     // per state: the action taken, -1 until first needed
  std::vector<Gamma> scratch_;
  uint64_t absorbing_tick_ = UINT64_MAX;
  bool absorbing_now_ = false;
};

}  // namespace

ControllerPtr make_policy_skill(const std::string& name, const std::vector<ControllerPtr>& psi,
                                const QTable& q, PredicatePtr absorbing) {
  if (name.empty()) throw Error("learned skill: needs a name");
  if (!absorbing) throw Error("learned skill \"" + name + "\": needs an absorbing predicate");
  check_psi(psi, q, "learned skill \"" + name + "\"");
  return std::make_shared<LearnedSkill>(name, psi, q, std::move(absorbing));
}

}  // namespace roger
