#include "control/control.h"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>

#include "core/error.h"
#include "core/shape.h"

namespace roger {

const char* gamma_name(Gamma g) {
  switch (g) {
    case Gamma::kNoRef: return "NOREF";
    case Gamma::kNotConv: return "!CONV";
    case Gamma::kConv: return "CONV";
  }
  return "?";
}

void Controller::reset(uint64_t) {
  out_ = ControlOutput{};
  last_tick_ = state_tick_ = settle_tick_ = UINT64_MAX;
  conv_since_ = -1.0;
  executed_tick_ = UINT64_MAX;
}

ControllerPtr Controller::copy() const {
  throw Error("controller '" + name_ + "' (" + kind() +
              ") cannot be copied, so it cannot be judged on the true world under noise");
}

ControllerPtr duplicate(const ControllerPtr& c, Duplicates& done) {
  return control_detail::duplicate_in(c, done, done.controllers);
}

void SubjectTo::relink(Duplicates& done) {
  sub_ = duplicate(sub_, done);
  sup_ = duplicate(sup_, done);
}

void Sequence::relink(Duplicates& done) {
  for (auto& s : steps_) s = duplicate(s, done);
}

void StandIn::relink(Duplicates& done) { target_ = duplicate(target_, done); }

void Binding::relink(Duplicates& done) { target_ = duplicate(target_, done); }

void Policy::relink(Duplicates& done) {
  for (auto& a : actions_) a = duplicate(a, done);
  done_ = duplicate(done_, done);
}

Gamma Controller::settle(Gamma raw, const ControlInput& in) {
  // Convergence may have to hold for a while before it counts, and without interruption: a
  // controller nobody looked at for some ticks (a sequence's idle step, the part of a predicate
  // that was not needed) starts its hold again.
  if (in.tick != settle_tick_ + 1) conv_since_ = -1.0;
  settle_tick_ = in.tick;
  const double time = in.time;
  if (raw != Gamma::kConv) {
    conv_since_ = -1.0;
    return raw;
  }
  if (conv_since_ < 0.0) conv_since_ = time;
  return time - conv_since_ + 1e-9 >= params_.hold ? Gamma::kConv : Gamma::kNotConv;
}

const ControlOutput& Controller::evaluate(const ControlInput& in) {
  if (in.tick == last_tick_) return out_;
  last_tick_ = in.tick;
  out_.command.setZero();
  out_.jacobian.resize(0, kDofCount);
  out_.phi = out_.residual = 0.0;
  Gamma raw = Gamma::kNoRef;
  compute(in, out_, raw);
  if (params_.gain != 1.0) out_.command *= params_.gain;
  // After the state path found the same raw state this tick, that state is settled already:
  // settling it again would count the tick twice and restart the hold time. (A binding's state
  // path may find another: its invocation begins in compute().)
  if (state_tick_ != in.tick || raw != state_raw_) out_.gamma = settle(raw, in);
  return out_;
}

Gamma Controller::state(const ControlInput& in) {
  if (in.tick == last_tick_ || in.tick == state_tick_) return out_.gamma;
  Gamma raw = Gamma::kNoRef;
  if (!compute_state(in, out_, raw)) return evaluate(in).gamma;
  state_tick_ = in.tick;
  state_raw_ = raw;
  out_.gamma = settle(raw, in);
  return out_.gamma;
}

namespace {

// An orthonormal basis of J's row space by modified Gram-Schmidt; a row whose orthogonalization
// cancelled much of it (its norm fell below 1/sqrt 2 of what it was) is orthogonalized once more,
// which is enough for double precision (Daniel, Gragg, Kaufman and Stewart), while the common
// rows, unit rows of the dofs a primitive owns, take one pass. A row whose remainder is below
// `tolerance` times the largest row norm depends on the others and is dropped, which truncates
// the pseudoinverse there instead of letting it blow up. Returns the rank; the basis is its first
// columns. Far cheaper than an SVD.
int row_space_basis(const TaskJacobian& J, double tolerance, DofMatrix& basis) {
  double largest = 0.0;
  for (int r = 0; r < J.rows(); ++r) largest = std::max(largest, J.row(r).norm());
  if (largest <= 0.0) return 0;
  int rank = 0;
  for (int r = 0; r < J.rows() && rank < kDofCount; ++r) {
    DofVector v = J.row(r).transpose();
    for (int pass = 0; pass < 2; ++pass) {
      const double before = v.squaredNorm();
      for (int k = 0; k < rank; ++k) v -= basis.col(k).dot(v) * basis.col(k);
      if (v.squaredNorm() >= 0.5 * before) break;
    }
    const double norm = v.norm();
    if (norm <= tolerance * largest) continue;
    basis.col(rank++) = v / norm;
  }
  return rank;
}

}  // namespace

DofMatrix nullspace_projector(const TaskJacobian& J, double tolerance) {
  // N = I - sum of q q^T over the basis, by rank-one updates of fixed size (the product of dynamic
  // blocks went through Eigen's general matrix kernel, which cost more than the basis itself).
  DofMatrix N = DofMatrix::Identity();
  DofMatrix basis;
  const int rank = row_space_basis(J, tolerance, basis);
  for (int k = 0; k < rank; ++k) N.noalias() -= basis.col(k) * basis.col(k).transpose();
  return N;
}

DofVector nullspace_project(const TaskJacobian& J, const DofVector& v, double tolerance) {
  DofMatrix basis;
  const int rank = row_space_basis(J, tolerance, basis);
  DofVector out = v;
  for (int k = 0; k < rank; ++k) out -= basis.col(k).dot(v) * basis.col(k);
  return out;
}

SubjectTo::SubjectTo(ControllerPtr subordinate, ControllerPtr superior)
    : sub_(std::move(subordinate)), sup_(std::move(superior)) {
  if (!sub_ || !sup_) throw Error("subject_to: both sides must be controllers");
  // "<|" reads right to left (a <| b <| c is a <| (b <| c)): a subordinate that is itself an
  // unnamed composite is parenthesized, so that (a <| b) <| c, another controller, reads apart
  // (found by a probe: both were "a <| b <| c").
  const bool grouped = std::string(sub_->kind()) == "subject_to" && sub_->name().find(" <| ") != std::string::npos;
  set_name((grouped ? "(" + sub_->name() + ")" : sub_->name()) + " <| " + sup_->name());
}

std::vector<const Controller*> SubjectTo::children() const { return {sub_.get(), sup_.get()}; }

void SubjectTo::note_executed(const ControlInput& in) {
  if (history_count_ > 0) {
    const auto& newest = history_[size_t((history_head_ - 1 + kHistory) % kHistory)];
    if (in.time - newest.first > 1.5 * in.dt() + 1e-9) history_count_ = history_head_ = 0;
  }
  history_[size_t(history_head_)] = {in.time, sub_->progress(sub_->output())};
  history_head_ = (history_head_ + 1) % kHistory;
  history_count_ = std::min(history_count_ + 1, kHistory);
}

void SubjectTo::pass_executed(const ControlInput& in) {
  sub_->executed(in);
  sup_->executed(in);
}

void SubjectTo::reset(uint64_t seed) {
  Controller::reset(seed);
  history_count_ = history_head_ = 0;
  sub_->reset(seed);
  sup_->reset(seed);
}

void SubjectTo::compute(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) {
  const ControlOutput& a = sup_->evaluate(in);
  const ControlOutput& b = sub_->evaluate(in);
  const DofVector projected = nullspace_project(a.jacobian, b.command);
  out.command = a.command + projected;
  const int rows = std::min<int>(kMaxTaskRows, int(a.jacobian.rows() + b.jacobian.rows()));
  out.jacobian.resize(rows, kDofCount);
  const int top = std::min<int>(rows, int(a.jacobian.rows()));
  out.jacobian.topRows(top) = a.jacobian.topRows(top);
  if (rows > top) out.jacobian.bottomRows(rows - top) = b.jacobian.topRows(rows - top);
  out.phi = a.phi;
  out.residual = a.residual;
  gamma_raw = combine(in, a, b, projected);
}

bool SubjectTo::compute_state(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) {
  const Gamma a = sup_->observe(in);
  const Gamma b = sub_->observe(in);
  // combine() needs the commands only for a !CONV subordinate under a superior with a reference.
  if (b == Gamma::kNotConv && a != Gamma::kNoRef) return false;
  out.residual = sup_->output().residual;
  gamma_raw = std::min(a, b);
  return true;
}

Gamma SubjectTo::combine(const ControlInput& in, const ControlOutput& a, const ControlOutput& b,
                         const DofVector& projected) const {
  Gamma sub = b.gamma;
  // Blocked by the superior (it asks for motion, none of which survives the projection), or
  // settled where the superior lets it be (its potential no longer falls while it is being
  // executed): the constrained equilibrium counts as converged. A subordinate asking for nothing
  // keeps its gamma.
  const ControllerParams& sp = sub_->params();
  const double stall = sp.stall;
  if (sub != Gamma::kNotConv || a.gamma == Gamma::kNoRef || b.command.norm() <= stall)
    return std::min(a.gamma, sub);
  // The history holds the subordinate's potential at the ticks this composite was executed, and
  // only an unbroken run of them up to the last tick (executed() clears it after a gap).
  bool settled = false;
  if (history_count_ > 0) {
    const auto& newest = history_[size_t((history_head_ - 1 + kHistory) % kHistory)];
    if (in.time - newest.first <= 1.5 * in.dt() + 1e-9) {
      for (int k = 0; k < history_count_; ++k) {
        const auto& past = history_[size_t((history_head_ - 1 - k + 2 * kHistory) % kHistory)];
        if (in.time - past.first + 1e-9 < sp.plateau) continue;
        settled = std::abs(sub_->progress(b) - past.second) <= stall;
        break;
      }
    }
  }
  if (!settled) settled = projected.norm() <= stall;
  if (settled) sub = Gamma::kConv;
  return std::min(a.gamma, sub);
}

Sequence::Sequence(std::vector<ControllerPtr> steps, bool fall_back)
    : steps_(std::move(steps)), fall_back_(fall_back) {
  if (steps_.empty()) throw Error("sequence: needs at least one step");
  for (const auto& s : steps_)
    if (!s) throw Error("sequence: every step must be a controller");
}

std::vector<const Controller*> Sequence::children() const {
  std::vector<const Controller*> c;
  for (const auto& s : steps_) c.push_back(s.get());
  return c;
}

void Sequence::pass_executed(const ControlInput& in) { steps_[size_t(current_)]->executed(in); }

void Sequence::reset(uint64_t seed) {
  Controller::reset(seed);
  for (auto& s : steps_) s->reset(seed);
  current_ = 0;
  advanced_tick_ = UINT64_MAX;
}

bool Sequence::state_is_exact() const {
  for (const auto& s : steps_)
    if (!s->state_is_exact()) return false;
  return true;
}

void Sequence::advance(const ControlInput& in) {
  if (advanced_tick_ == in.tick) return;
  advanced_tick_ = in.tick;
  const int n = int(steps_.size());
  // Advance past converged steps, fall back past steps without a reference; at most n moves.
  for (int moves = 0; moves < n; ++moves) {
    const Gamma g = steps_[current_]->state(in);
    if (g == Gamma::kConv && current_ + 1 < n) {
      ++current_;
    } else if (g == Gamma::kNoRef && current_ > 0 && fall_back_) {
      --current_;
    } else {
      break;
    }
  }
}

Gamma Sequence::summary(const ControlInput& in) {
  // Without falling back, a step that lost its reference is the end of the road; so is the first
  // step without one, with nothing before it to fall back to: the later steps' references (a touch
  // on some object, an object seen) are moot while the sequence cannot get to them.
  if ((!fall_back_ || current_ == 0) && steps_[size_t(current_)]->state(in) == Gamma::kNoRef) return Gamma::kNoRef;
  const Gamma last = steps_.back()->state(in);
  bool any_reference = false;
  for (const auto& s : steps_) any_reference |= s->state(in) != Gamma::kNoRef;
  return last == Gamma::kConv ? Gamma::kConv : any_reference ? Gamma::kNotConv : Gamma::kNoRef;
}

void Sequence::compute(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) {
  advance(in);
  const ControlOutput& run = steps_[current_]->evaluate(in);
  out.command = run.command;
  out.jacobian = run.jacobian;
  out.phi = run.phi;
  out.residual = run.residual;
  gamma_raw = summary(in);
}

bool Sequence::compute_state(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) {
  advance(in);
  Controller& run = *steps_[current_];
  run.observe(in);
  out.residual = run.output().residual;
  gamma_raw = summary(in);
  return true;
}

void StandIn::bind(ControllerPtr target) {
  target_ = std::move(target);
  params() = target_->params();
  params().hold = 0.0;
  params().gain = 1.0;
}

std::vector<const Controller*> StandIn::children() const {
  if (target_) return {target_.get()};
  return {};
}

void StandIn::reset(uint64_t seed) {
  Controller::reset(seed);
  if (target_) target_->reset(seed);
}

void StandIn::pass_executed(const ControlInput& in) {
  if (target_) target_->executed(in);
}

void StandIn::compute(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) {
  if (!target_) {
    gamma_raw = Gamma::kNoRef;
    return;
  }
  const ControlOutput& o = target_->evaluate(in);
  out.command = o.command;
  out.jacobian = o.jacobian;
  out.phi = o.phi;
  out.residual = o.residual;
  gamma_raw = o.gamma;  // already after the target's hold time; the stand-in holds for 0 s
}

bool StandIn::compute_state(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) {
  if (!target_) {
    gamma_raw = Gamma::kNoRef;
    return true;
  }
  gamma_raw = target_->state(in);
  out.residual = target_->output().residual;
  return true;
}

int gamma_state_index(const std::vector<Gamma>& gammas) {
  int index = 0;
  for (Gamma g : gammas) index = index * 3 + int(g);
  return index;
}

Policy::Policy(std::vector<ControllerPtr> actions, std::vector<int> table, ControllerPtr done,
               int fallback)
    : actions_(std::move(actions)), table_(std::move(table)), done_(std::move(done)), fallback_(fallback) {
  if (actions_.empty()) throw Error("policy: needs at least one action");
  if (actions_.size() > 12) throw Error("policy: at most 12 actions (3^12 states)");
  int states = 1;
  for (size_t i = 0; i < actions_.size(); ++i) states *= 3;
  if (int(table_.size()) != states)
    throw Error("policy: the table must have 3^" + std::to_string(actions_.size()) + " = " +
                std::to_string(states) + " entries, got " + std::to_string(table_.size()));
  for (int a : table_)
    if (a < -1 || a >= int(actions_.size())) throw Error("policy: table entry out of range");
  if (fallback_ < kRotate || fallback_ >= int(actions_.size())) throw Error("policy: fallback out of range");
  scratch_.resize(actions_.size());
}

std::vector<const Controller*> Policy::children() const {
  std::vector<const Controller*> c;
  for (const auto& a : actions_) c.push_back(a.get());
  if (done_) c.push_back(done_.get());
  return c;
}

void Policy::pass_executed(const ControlInput& in) {
  if (chosen_ >= 0) actions_[size_t(chosen_)]->executed(in);
}

void Policy::reset(uint64_t seed) {
  Controller::reset(seed);
  for (auto& a : actions_) a->reset(seed);
  if (done_) done_->reset(seed);
  chosen_ = -1;
  rotation_ = 0;
  chosen_tick_ = UINT64_MAX;
}

int Policy::next_in_turn(const ControlInput& in) {
  const int n = int(actions_.size());
  const bool ran = chosen_ == rotation_ && chosen_tick_ + 1 == in.tick;
  if (ran && scratch_[size_t(rotation_)] == Gamma::kNotConv) return rotation_;  // still its turn
  // The one in turn ran on the last tick and has ended: the next one's turn. A turn that begins
  // with an action that ends as soon as it is evaluated (a phi1 going elsewhere with no need to)
  // passes on at once, so that action costs the round no tick; each at most once a tick.
  if (ran) rotation_ = (rotation_ + 1) % n;
  const int first = rotation_;
  for (int passed = 0; passed + 1 < n; ++passed) {
    if (actions_[size_t(rotation_)]->evaluate(in).gamma == Gamma::kNotConv) return rotation_;
    rotation_ = (rotation_ + 1) % n;
  }
  rotation_ = first;  // every other one ends at once too: the first of them runs, for a tick
  return rotation_;
}

Gamma Policy::read_state(const ControlInput& in) {
  bool any_reference = false;
  for (size_t i = 0; i < actions_.size(); ++i) {
    scratch_[i] = actions_[i]->state(in);
    any_reference |= scratch_[i] != Gamma::kNoRef;
  }
  const bool done = done_ && done_->state(in) == Gamma::kConv;
  return done ? Gamma::kConv : any_reference ? Gamma::kNotConv : Gamma::kNoRef;
}

bool Policy::compute_state(const ControlInput& in, ControlOutput&, Gamma& gamma_raw) {
  // Its state from its actions' states and its goal alone: asking a policy that is not running
  // what state it is in must not run (and so restart) the action its table would choose.
  gamma_raw = read_state(in);
  return true;
}

void Policy::compute(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) {
  gamma_raw = read_state(in);
  if (rest_when_done_ && gamma_raw == Gamma::kConv) {
    chosen_ = -1;  // at its goal: no command
    return;
  }
  const int entry = table_[size_t(gamma_state_index(scratch_))];
  if (entry < 0 && fallback_ == kRotate) {
    chosen_ = next_in_turn(in);
  } else {
    chosen_ = entry >= 0 ? entry : fallback_;
  }
  chosen_tick_ = in.tick;
  if (chosen_ >= 0) {
    const ControlOutput& run = actions_[size_t(chosen_)]->evaluate(in);
    out.command = run.command;
    out.jacobian = run.jacobian;
    out.phi = run.phi;
    out.residual = run.residual;
  }
}

}  // namespace roger
