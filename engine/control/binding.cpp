// binding.cpp: a controller run under per-invocation bindings (the stimulus it attends to and the
// goal region it delivers to); see Binding in control.h.
#include "control/control.h"
#include "core/error.h"
#include "core/rng.h"

namespace roger {

std::string Binding::settings() const {
  std::string out;
  if (bindings_.stimulus) out = "stimulus = \"" + bindings_.colour.hex() + "\"";
  if (bindings_.region >= 0) out += (out.empty() ? "" : ", ") + std::string("region = ") + std::to_string(bindings_.region);
  return out;
}

Binding::Binding(ControllerPtr target, const Bindings& bindings) : target_(std::move(target)), bindings_(bindings) {
  if (!target_) throw Error("binding: needs a controller to bind");
  set_name(target_->name());
}

void Binding::reset(uint64_t seed) {
  Controller::reset(seed);
  target_->reset(seed);
  seed_ = seed;
  invocations_ = 0;
  begun_tick_ = UINT64_MAX;
  begun_time_ = 0.0;
  gave_up_ = false;
  gave_up_tick_ = UINT64_MAX;
  failed_ = noref_ = target_noref_ = false;
  noref_since_ = 0.0;
  // Not yet invoked: nothing says its work is done (CONV) or cannot be done (NOREF).
  last_ = Gamma::kNotConv;
}

bool Binding::running(const ControlInput& in) const {
  if (begun_tick_ == in.tick) return true;
  return !gave_up_ && executed_tick() != UINT64_MAX && executed_tick() + 1 == in.tick;
}

bool Binding::ended(const ControlInput& in) const {
  return begun_tick_ != in.tick && last_ == Gamma::kConv;
}

bool Binding::out_of_patience(const ControlInput& in) const {
  return bindings_.patience > 0.0 && last_ != Gamma::kConv && in.time - begun_time_ >= bindings_.patience;
}

Attention Binding::wanted(const Attention& now) const {
  Attention a = now;
  if (bindings_.stimulus) a.colour = bindings_.colour;
  if (bindings_.stimulus || bindings_.ignore_region >= 0) a.ignore_region = bindings_.ignore_region;
  if (bindings_.region >= 0) a.region = bindings_.region;
  return a;
}

bool Binding::attending(const ControlInput& in) const {
  // Without an agent (a controller run on its own) nobody redirects the senses: bindings are moot.
  return !in.attention || *in.attention == wanted(*in.attention);
}

void Binding::compute(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) {
  // Run again after its work was done (CONV), it starts that work over: a sorting move chosen
  // again after it delivered carries the next object instead of holding its last CONV for ever.
  if (!running(in) || ended(in)) {
    // A new invocation: the target starts afresh, as an action chosen anew would.
    ++invocations_;
    begun_tick_ = in.tick;
    begun_time_ = in.time;
    gave_up_ = false;
    target_->reset(Rng::mix(seed_, uint64_t(invocations_)));
  }
  if (!attending(in)) {
    // The world still attends to another stimulus or region: wait the one tick until it attends
    // to ours.
    out.command.setZero();
    out.jacobian.resize(0, kDofCount);
    out.phi = out.residual = 0.0;
    last_ = Gamma::kNotConv;
    gamma_raw = sticky(Gamma::kNotConv, in);
    return;
  }
  if (out_of_patience(in)) {
    give_up(in);
    gamma_raw = last_ = Gamma::kNoRef;
    return;
  }
  const ControlOutput& t = target_->evaluate(in);
  out.command = t.command;
  out.jacobian = t.jacobian;
  out.phi = t.phi;
  out.residual = t.residual;
  last_ = t.gamma;
  gamma_raw = sticky(t.gamma, in);
}

void Binding::give_up(const ControlInput& in) {
  gave_up_ = true;
  gave_up_tick_ = in.tick;
  failed_ = bindings_.sticky_noref;
  mark_noref(in, true);
}

void Binding::mark_noref(const ControlInput& in, bool fresh) {
  if (fresh || !noref_) noref_since_ = in.time;
  noref_ = true;
}

bool Binding::noref_forgotten(const ControlInput& in) const {
  return bindings_.retry_after > 0.0 && noref_ && in.time - noref_since_ >= bindings_.retry_after;
}

Gamma Binding::sticky(Gamma g, const ControlInput& in) {
  const bool target_was_noref = target_noref_;
  target_noref_ = g == Gamma::kNoRef;
  if (g == Gamma::kNoRef) {
    // The target itself says NOREF: shown whatever the memory, and remembered from when it began.
    failed_ = bindings_.sticky_noref;
    mark_noref(in, !target_was_noref);
    return g;
  }
  if (g == Gamma::kConv) failed_ = false;
  if (failed_ && noref_forgotten(in)) failed_ = false;
  noref_ = failed_;
  return failed_ ? Gamma::kNoRef : g;
}

Gamma Binding::resting_state(const ControlInput& in) {
  if (failed_ || last_ == Gamma::kNoRef) {
    if (!noref_forgotten(in)) return mark_noref(in, false), Gamma::kNoRef;
    // Forgotten: as a binding not yet invoked, with nothing to say its work is done or cannot be.
    failed_ = noref_ = false;
    last_ = Gamma::kNotConv;
  }
  noref_ = false;
  return last_;
}

bool Binding::compute_state(const ControlInput& in, ControlOutput&, Gamma& gamma_raw) {
  if (!running(in)) {
    gamma_raw = resting_state(in);
  } else if (!attending(in)) {
    gamma_raw = sticky(Gamma::kNotConv, in);
  } else if (out_of_patience(in)) {
    give_up(in);
    gamma_raw = last_ = Gamma::kNoRef;
  } else {
    last_ = target_->state(in);
    gamma_raw = sticky(last_, in);
  }
  return true;
}

void Binding::note_executed(const ControlInput& in) {
  if (!gave_up_ && in.next_attention && in.attention) *in.next_attention = wanted(*in.attention);
}

void Binding::pass_executed(const ControlInput& in) {
  if (!gave_up_ && attending(in)) target_->executed(in);
}

}  // namespace roger
