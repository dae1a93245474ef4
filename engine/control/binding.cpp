// binding.cpp: a controller run under per-invocation bindings (the stimulus it attends to and the
// goal region it delivers to); see Binding in control.h.
#include "control/control.h"
#include "core/error.h"
#include "core/rng.h"

namespace roger {

Binding::Binding(ControllerPtr target, bool has_stimulus, Attention attention, int region)
    : target_(std::move(target)), has_stimulus_(has_stimulus), attention_(attention), region_(region) {
  if (!target_) throw Error("binding: needs a controller to bind");
  set_name(target_->name());
}

void Binding::reset(uint64_t seed) {
  Controller::reset(seed);
  target_->reset(seed);
  seed_ = seed;
  invocations_ = 0;
  executed_tick_ = begun_tick_ = UINT64_MAX;
  last_ = Gamma::kNoRef;
}

bool Binding::running(const ControlInput& in) const {
  return begun_tick_ == in.tick || (executed_tick_ != UINT64_MAX && executed_tick_ + 1 == in.tick);
}

bool Binding::attending(const ControlInput& in) const {
  return !has_stimulus_ || (in.attention && *in.attention == attention_);
}

ControlInput Binding::bound(const ControlInput& in) const {
  ControlInput b = in;
  if (region_ >= 0) b.region = region_;
  return b;
}

void Binding::compute(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) {
  if (!running(in)) {
    // A new invocation: the target starts afresh, as an action chosen anew would.
    ++invocations_;
    begun_tick_ = in.tick;
    target_->reset(Rng::mix(seed_, uint64_t(invocations_)));
  }
  if (!attending(in)) {
    // The eyes still look for another stimulus: wait the one tick until they attend to ours.
    out.command.setZero();
    out.jacobian.resize(0, kDofCount);
    out.phi = out.residual = 0.0;
    gamma_raw = last_ = Gamma::kNotConv;
    return;
  }
  const ControlOutput& t = target_->evaluate(bound(in));
  out.command = t.command;
  out.jacobian = t.jacobian;
  out.phi = t.phi;
  out.residual = t.residual;
  gamma_raw = last_ = t.gamma;
}

bool Binding::compute_state(const ControlInput& in, ControlOutput&, Gamma& gamma_raw) {
  if (!running(in)) {
    gamma_raw = last_;  // what its last invocation ended with
  } else if (!attending(in)) {
    gamma_raw = Gamma::kNotConv;
  } else {
    gamma_raw = last_ = target_->state(bound(in));
  }
  return true;
}

void Binding::executed(const ControlInput& in) {
  executed_tick_ = in.tick;
  if (has_stimulus_ && in.next_attention) *in.next_attention = attention_;
  if (attending(in)) target_->executed(bound(in));
}

}  // namespace roger
