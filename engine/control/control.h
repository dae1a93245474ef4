// Module control: the control basis. Owns controllers and their states, subject-to composition,
// primitives phi0-phi5, predicates, the harmonic planner and the agent's tick. Depends on sim and
// below; knows nothing of learning, Lua or files.
//
// control.h: the control basis. A controller phi|sigma,tau descends a potential phi over sensory
// features sigma through effectors tau (a subset of the 8 degrees of freedom) and reports its state
// gamma by the paper's Equation 1. Controllers compose by nullspace projection ("subject-to"), and
// skills (sequences, state-to-action policies) are controllers too, so any of them can be an action.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/body.h"
#include "core/robot.h"
#include "core/spec.h"
#include "perception/percepts.h"
#include "senses/senses.h"
#include "sim/occupancy.h"
#include "sim/world.h"
#include "sim/world_model.h"

namespace roger {

// A controller's state (Equation 1), ordered so that min() of two states is the weaker one.
enum class Gamma : uint8_t { kNoRef = 0, kNotConv = 1, kConv = 2 };

// "NOREF", "!CONV" or "CONV".
const char* gamma_name(Gamma g);

// Rows of a task Jacobian over the 8 degrees of freedom. The row count is bounded, so Eigen keeps
// the storage inline: evaluating a controller never allocates.
constexpr int kMaxTaskRows = 16;
using TaskJacobian =
    Eigen::Matrix<double, Eigen::Dynamic, kDofCount, Eigen::RowMajor, kMaxTaskRows, kDofCount>;
using DofMatrix = Eigen::Matrix<double, kDofCount, kDofCount>;


// What a controller may read: the world's immutable model (its body and what follows from it, the
// eyes' camera, the static map: arena, obstacles as an occupancy grid, goal regions) and what this
// tick gives: Roger's senses, the percepts made of them, and the map of movable objects
// (MapObject). Never the simulator's object poses as senses.
struct ControlInput {
  const WorldModel* model = nullptr;    // the world of this episode (sim/world_model.h)
  // Roger's senses as control reads them: the sightings, never the pixels (SenseReadings).
  const SenseReadings* senses = nullptr;
  // The same tick as the true world gives it (true senses and what they make of them, all else
  // alike), for judges (Judge in predicate.h); null when the senses are the true ones (no noise).
  const ControlInput* truth = nullptr;
  const Percepts* percepts = nullptr;
  const std::vector<MapObject>* objects = nullptr;  // the map of movable objects (may be null)
  double time = 0.0;                    // simulated seconds since the episode began
  uint64_t tick = 0;                    // tick counter, for caching within a tick
  // Bindings (see Binding): what this tick's senses attended to, where a controller may ask the
  // agent to attend from the next tick on, and the goal region that goal='region' navigators
  // deliver to instead of their own `region` parameter (-1: their own; the attention's region).
  const Attention* attention = nullptr;
  Attention* next_attention = nullptr;
  int region = -1;

  // Parts of the model, by name.
  const WorldSpec& spec() const { return model->spec; }
  const RobotParams& robot() const { return model->spec.body; }
  const BodyMetrics& body() const { return model->body; }
  const Camera& camera() const { return model->camera; }
  const OccupancyGrid& grid() const { return model->grid; }  // static obstacles, grown
  double dt() const { return model->tick_seconds(); }       // the control tick (s)
};

// What a controller gives back each tick.
struct ControlOutput {
  Gamma gamma = Gamma::kNoRef;          // after the hold time
  double phi = 0.0;                     // the potential
  double residual = 0.0;                // the quantity compared with epsilon (see each primitive)
  DofVector command = DofVector::Zero();// the errors vector to apply
  TaskJacobian jacobian;                // rows of the task it protects when superior (may be empty)
};

// Parameters every controller has.
struct ControllerParams {
  double epsilon = 0.0;  // convergence threshold on the residual; 0 = the primitive's default
  double gain = 1.0;     // scales the command
  double hold = 0.0;     // seconds the condition must hold before gamma is CONV
  double stall = 0.01;   // as a subordinate: converged once its projected command is this small,
                         // or its progress (Controller::progress) has changed by less than this
                         // over `plateau` seconds
  double plateau = 0.3;  // seconds over which a subordinate's progress must have settled
};

// A closed-loop action. Evaluation is cached per tick: a controller shared by several compositions
// is computed once.
class Controller;
class Predicate;

// Copies already made while duplicating controllers and predicates (Controller::duplicate): a
// part shared by several owners is copied once and stays shared among the copies.
struct Duplicates {
  std::vector<std::pair<const Controller*, std::shared_ptr<Controller>>> controllers;
  std::vector<std::pair<const Predicate*, std::shared_ptr<Predicate>>> predicates;
};

class Controller {
 public:
  virtual ~Controller() = default;

  // The name shown in policies, tables and pictures ("phi1", "phi4 <| phi2", "Phi7").
  const std::string& name() const { return name_; }
  void set_name(std::string name) { name_ = std::move(name); }

  // Parameters common to all controllers.
  ControllerParams& params() { return params_; }
  const ControllerParams& params() const { return params_; }

  // Starts an episode: clears hold timers and any internal state; seed makes choices repeatable.
  virtual void reset(uint64_t seed);

  // Evaluates for this tick (cached: the second call in the same tick returns the first result).
  const ControlOutput& evaluate(const ControlInput& in);

  // This tick's state alone (cached). Cheaper than evaluate() where a controller can tell its
  // state without computing its command (phi1 needs no potential solve for it); evaluate() still
  // gives the full output afterwards.
  Gamma state(const ControlInput& in);

  // The last output.
  const ControlOutput& output() const { return out_; }

  // How far it still has to go, for a composite's plateau test (SubjectTo): its potential by
  // default. A controller whose potential is flat over most of its range (phi1's harmonic
  // potential far from the goal) gives a measure that falls while it makes headway.
  virtual double progress(const ControlOutput& out) const { return out.phi; }

  // Whether state() alone serves where only the state is needed: it gives the state evaluate()
  // would, and skipping the command changes nothing the controller's later commands follow from,
  // but for rounding (phi1's next solve starts from an older solution and converges to the same
  // tolerance). A composite that needs only the state of such a part skips the part's command;
  // any other part (search, whose turn is its memory) it evaluates as before.
  virtual bool state_is_exact() const { return false; }

  // This tick's state where only the state is needed: state() where that is exact, evaluate()
  // otherwise.
  Gamma observe(const ControlInput& in) { return state_is_exact() ? state(in) : evaluate(in).gamma; }

  // The controllers this one is made of, for pictures, usage counts and cycle checks.
  virtual std::vector<const Controller*> children() const { return {}; }

  // Whether its state can ever be CONV, as far as its make tells (true where nothing rules it
  // out): a policy without a goal (`done`) never converges, nor a sequence whose last step, a
  // subject-to whose superior or a binding whose skill is one. A goal of converged() on such a
  // controller would fail every episode, and a load refuses it.
  virtual bool can_converge() const { return true; }

  // The part whose command it passed on at its last evaluation (a sequence's step, a policy's
  // choice, a stand-in's or binding's target), for episode timelines; nullptr when it has none or
  // runs several at once.
  virtual const Controller* inner() const { return nullptr; }

  // Whether this controller, or the part it runs now (down the inner() chain), gave up an
  // invocation on `tick` (a binding out of patience). A stage takes it as the end of the running
  // action, a decision point, even when the state did not change (a sticky binding's NOREF).
  virtual bool gave_up_on(uint64_t tick) const {
    const Controller* part = inner();
    return part && part->gave_up_on(tick);
  }

  // Told by the control loop that this tick's command (from evaluate()) was written to the robot;
  // composites pass it on to the children whose commands they used. Evaluations made only to
  // observe a state are never executed, which is what lets a subordinate's settled potential
  // mean "stuck while acting" rather than "not running".
  void executed(const ControlInput& in) {
    executed_tick_ = in.tick;
    note_executed(in);
    pass_executed(in);
  }
  // What a judge's copy of this controller is told when the original was executed (Judge,
  // predicate.h): the same bookkeeping of its own, passed on to no part (each part's copy hears
  // of its own original).
  void mirror_executed(const ControlInput& in) {
    executed_tick_ = in.tick;
    note_executed(in);
  }
  // The ticks of its last execution, full evaluation and state-only evaluation in this episode
  // (UINT64_MAX: none).
  uint64_t executed_tick() const { return executed_tick_; }
  uint64_t evaluated_tick() const { return last_tick_; }
  uint64_t observed_tick() const { return state_tick_; }

  // A short word for what it is: a primitive's own name, "subject_to", "sequence" or "policy".
  virtual const char* kind() const = 0;
  // What was set on it as a script writes it (a primitive's parameters away from their defaults,
  // a binding's colour and region), to tell controllers of one name apart in messages; "" for none.
  virtual std::string settings() const { return ""; }

  // A copy of this controller alone (its parts still the originals'): same parameters, name and
  // state. Through roger::duplicate only, which then relinks the parts. The default refuses: a
  // controller that cannot be copied cannot be judged on the true world under noise.
  virtual std::shared_ptr<Controller> copy() const;
  // Replaces the parts of a fresh copy by their duplicates (nothing for a leaf).
  virtual void relink(Duplicates&) {}

 protected:
  // Computes the output for this tick; gamma_raw before the hold time.
  virtual void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) = 0;

  // Optional fast path of state(): sets gamma_raw (and residual) without the command. Returns
  // false to fall back on compute(). It must agree with compute() on the state. compute() may
  // follow it in the same tick (the state is then not settled twice: see evaluate()).
  virtual bool compute_state(const ControlInput&, ControlOutput&, Gamma&) { return false; }

  // Its own bookkeeping when its command was executed (after executed_tick() is set).
  virtual void note_executed(const ControlInput&) {}
  // Passes the execution on to the parts whose commands it used.
  virtual void pass_executed(const ControlInput&) {}

 private:
  // Applies the hold time to a raw state (idempotent within a tick).
  Gamma settle(Gamma raw, const ControlInput& in);
  std::string name_;
  ControllerParams params_;
  ControlOutput out_;
  uint64_t last_tick_ = UINT64_MAX;   // tick of the last full evaluation
  uint64_t state_tick_ = UINT64_MAX;  // tick of the last state-only evaluation
  Gamma state_raw_ = Gamma::kNoRef;   // the raw state it found
  uint64_t settle_tick_ = UINT64_MAX; // tick of the last settle(), to see gaps in the hold
  uint64_t executed_tick_ = UINT64_MAX;  // tick of the last execution
  double conv_since_ = -1.0;
};

using ControllerPtr = std::shared_ptr<Controller>;

namespace control_detail {
// What duplicate() does for controllers and predicates alike: the copy `made` already holds, or a
// fresh copy, recorded before its parts are relinked (a cycle then finds it).
template <class T>
std::shared_ptr<T> duplicate_in(const std::shared_ptr<T>& p, Duplicates& done,
                                std::vector<std::pair<const T*, std::shared_ptr<T>>>& made) {
  if (!p) return nullptr;
  for (const auto& [original, copy] : made)
    if (original == p.get()) return copy;
  std::shared_ptr<T> copy = p->copy();
  made.emplace_back(p.get(), copy);
  copy->relink(done);
  return copy;
}
}  // namespace control_detail

// A deep copy with its own state: the controller and every part it is made of, each copied once
// (`done` records the copies, so shared parts stay shared). A judge reads the true world through
// such copies while the originals act on the noisy senses (Judge in predicate.h).
ControllerPtr duplicate(const ControllerPtr& c, Duplicates& done);

// The nullspace projector N = I - J^+ J of a task Jacobian (Moore-Penrose), from an orthonormal
// basis of J's row space: rows that depend on the others to within `tolerance` times the largest
// row add nothing (the pseudoinverse is truncated there rather than blowing up near singularities).
DofMatrix nullspace_projector(const TaskJacobian& jacobian, double tolerance = 1e-6);
// N v for the same N, without forming N (what composition needs each tick).
DofVector nullspace_project(const TaskJacobian& jacobian, const DofVector& v, double tolerance = 1e-6);

// c2 <| c1: the subordinate's command projected into the nullspace of the superior's Jacobian.
// Its Jacobian stacks both (so chains nest: phi1 <| (phi4 <| phi5)). Its gamma is the weakest of
// the two: NOREF if either lacks a reference, CONV only when both have converged, where the
// subordinate has converged when its own gamma is CONV or when it can make no more progress in the
// superior's nullspace (its projected command is at most its `stall`, or, while the composite is
// being executed, its potential has settled: changed by less than `stall` over the last `plateau`
// seconds of execution, the paper's phi-dot near zero): the constrained equilibrium.
class SubjectTo final : public Controller {
 public:
  // subordinate <| superior.
  SubjectTo(ControllerPtr subordinate, ControllerPtr superior);
  std::vector<const Controller*> children() const override;
  const char* kind() const override { return "subject_to"; }
  const ControllerPtr& subordinate() const { return sub_; }
  const ControllerPtr& superior() const { return sup_; }
  void reset(uint64_t seed) override;
  ControllerPtr copy() const override { return std::make_shared<SubjectTo>(*this); }
  void relink(Duplicates& done) override;
  bool state_is_exact() const override { return sub_->state_is_exact() && sup_->state_is_exact(); }
  // Its state is never above its superior's (a settled subordinate counts as converged, a
  // superior never does by the subordinate).
  bool can_converge() const override { return sup_->can_converge(); }

 protected:
  // Records the subordinate's progress for the plateau test (it settles while being executed).
  void note_executed(const ControlInput& in) override;
  void pass_executed(const ControlInput& in) override;
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) override;
  // The state from the parts' states, where it needs no command: a superior without a reference,
  // or a subordinate that is not !CONV.
  bool compute_state(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) override;

 private:
  // The composite's gamma from its parts' outputs and the subordinate's command projected into
  // the superior's nullspace.
  Gamma combine(const ControlInput& in, const ControlOutput& a, const ControlOutput& b,
                const DofVector& projected) const;
  ControllerPtr sub_, sup_;
  // The subordinate's recent potentials (time, phi), oldest first, for the plateau test.
  static constexpr int kHistory = 64;
  std::array<std::pair<double, double>, kHistory> history_{};
  int history_count_ = 0, history_head_ = 0;
};

// A skill that runs its steps in order: the current step runs until it reports CONV, then the next
// one starts; if the current step loses its reference (NOREF), the previous step runs again (its
// precondition was lost, e.g. tracking lost the stimulus, so search again). Its gamma: CONV when the
// last step is CONV, NOREF when every step is NOREF or the first step runs without a reference
// (nothing before it to fall back to; the later steps' references are moot), !CONV otherwise.
// Without `fall_back`, a step that loses its reference does not hand back to the step before: the
// sequence stays on it and is NOREF while it is (it cannot go on; nothing before it can help). For
// steps that are no precondition of the next: "let go, carry one object, let go" ends NOREF when
// there is no object to carry, instead of letting go for ever.
class Sequence final : public Controller {
 public:
  explicit Sequence(std::vector<ControllerPtr> steps, bool fall_back = true);
  bool falls_back() const { return fall_back_; }
  std::vector<const Controller*> children() const override;
  const char* kind() const override { return "sequence"; }
  void reset(uint64_t seed) override;
  ControllerPtr copy() const override { return std::make_shared<Sequence>(*this); }
  void relink(Duplicates& done) override;
  // The step running now.
  int current() const { return current_; }
  const Controller* inner() const override { return steps_[size_t(current_)].get(); }
  const std::vector<ControllerPtr>& steps() const { return steps_; }
  // CONV when its last step is.
  bool can_converge() const override { return steps_.back()->can_converge(); }
  bool state_is_exact() const override;

 protected:
  void pass_executed(const ControlInput& in) override;
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) override;
  // The state without the running step's command where that step's state is exact; otherwise
  // the step is evaluated, as compute() would.
  bool compute_state(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) override;

 private:
  // Moves the current step past converged steps and back past steps without a reference, once
  // per tick (the state path and compute() may both run in one tick).
  void advance(const ControlInput& in);
  // The sequence's raw gamma from its steps' states.
  Gamma summary(const ControlInput& in);
  std::vector<ControllerPtr> steps_;
  bool fall_back_ = true;
  int current_ = 0;
  uint64_t advanced_tick_ = UINT64_MAX;
};

// A controller that stands in for another: a name used before its definition, a learned skill
// bound at train time. Once bound it behaves exactly as its target (outputs, state, execution);
// unbound it has no reference. Subclasses say what kind of stand-in they are.
class StandIn : public Controller {
 public:
  explicit StandIn(std::string name) { set_name(std::move(name)); }
  // Binds the target. SubjectTo reads a subordinate's parameters (stall, plateau) from the
  // controller it holds, so the stand-in takes the target's; hold and gain stay neutral, since
  // the target already applied its own to what the stand-in passes on.
  void bind(ControllerPtr target);
  // Drops the target (breaks reference cycles before an error is reported).
  void unbind() { target_.reset(); }
  const ControllerPtr& target() const { return target_; }
  const Controller* inner() const override { return target_.get(); }
  bool bound() const { return target_ != nullptr; }
  bool state_is_exact() const override { return !target_ || target_->state_is_exact(); }
  // Unbound (a learned skill before training), nothing tells.
  bool can_converge() const override { return !target_ || target_->can_converge(); }
  std::vector<const Controller*> children() const override;
  void reset(uint64_t seed) override;
  void relink(Duplicates& done) override;

 protected:
  void pass_executed(const ControlInput& in) override;
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) override;
  // The state alone, through the target's own fast path (a policy's state vector reads this).
  bool compute_state(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) override;

 private:
  ControllerPtr target_;
};

// A controller run under bindings set per invocation: the stimulus its eyes attend to (colour,
// and the goal region whose let-go objects they ignore) and the goal region its goal='region'
// navigators deliver to. One learned skill serves every binding without retraining: the
// bindings change what it perceives and where it delivers, not what it learned.
// The bindings are the world's attention (Attention): an invocation begins when the binding is
// evaluated on a tick after one on which it was not executed; the target is reset (seed mixed
// with the invocation count) and the agent is asked to attend as the binding says. Until the
// world attends so (the next tick) the binding commands nothing and is !CONV. The attention stays
// as the last binding left it. While it is not running, its state is the one it ended its last
// invocation with (!CONV before the first: nothing says yet that its work is done or cannot be
// done): a bound skill that delivered stays CONV, and one whose skill found nothing to do (a
// search that looked everywhere) stays NOREF, so the state vector of a stage remembers which
// bindings have done their work and which have none left. An invocation that reached CONV is
// over: executed again, the binding starts a new one (the next object of its kind).
// With `patience` > 0, an invocation that has not converged after that many seconds is given up:
// the binding reports NOREF (the state changes, so whoever chose it decides again) and commands
// nothing; evaluated again, it starts a new invocation. Multi-object scenes have dead ends a
// single object never showed (a stimulus hidden from one eye by another object, a grasp lost on
// the way): giving up and starting over is how a chooser gets out of them.
// With `sticky_noref`, NOREF outlasts the invocation that ended with it (given up, or its target
// NOREF): the binding reports NOREF, through later invocations too, until one converges. Its
// command is the target's as ever; only the state it shows differs. A chooser that runs a type
// it was told is stuck then sees a retry, not the fresh !CONV every episode starts with.
// With `retry_after` > 0, a NOREF is forgotten that many seconds after it began (its last give-up,
// or its target turning NOREF): the binding shows !CONV again, as one worth another try, unless
// its target still says NOREF. A greedy chooser whose state showed a type stuck for good would
// otherwise never try it again, though a blocked view or a pinned object may clear meanwhile.
class Binding final : public Controller {
 public:
  // What a binding sets; a field it does not set stays as the world's attention has it.
  struct Bindings {
    bool stimulus = false;   // sets the colour and the ignored region
    Colour colour;           // the stimulus colour (when `stimulus`)
    int ignore_region = -1;  // the region whose let-go objects are ignored (when `stimulus` or >= 0)
    int region = -1;         // the delivery region (-1: not bound)
    double patience = 0.0;   // seconds an invocation may run without converging (0: no limit)
    bool sticky_noref = false;  // after an invocation ends NOREF, NOREF until one converges
    double retry_after = 0.0;   // seconds after which a NOREF is forgotten (0: never)
  };
  Binding(ControllerPtr target, const Bindings& bindings);
  std::vector<const Controller*> children() const override { return {target_.get()}; }
  bool can_converge() const override { return target_->can_converge(); }
  const char* kind() const override { return "binding"; }
  std::string settings() const override;
  void reset(uint64_t seed) override;
  ControllerPtr copy() const override { return std::make_shared<Binding>(*this); }
  void relink(Duplicates& done) override;
  const ControllerPtr& target() const { return target_; }
  const Controller* inner() const override { return target_.get(); }
  bool gave_up_on(uint64_t tick) const override { return gave_up_tick_ == tick || Controller::gave_up_on(tick); }
  const Bindings& bindings() const { return bindings_; }
  int invocations() const { return invocations_; }

 protected:
  // Asks the world to attend as the binding says (unless it gave up); the target runs only while
  // the world attends so.
  void note_executed(const ControlInput& in) override;
  void pass_executed(const ControlInput& in) override;
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) override;
  bool compute_state(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) override;

 private:
  // Whether the invocation under way reached CONV on an earlier tick (its work is done).
  bool ended(const ControlInput& in) const;
  // Whether this tick continues an invocation (executed on the previous tick, or begun on this).
  bool running(const ControlInput& in) const;
  // The attention this binding asks for, given the world's attention now.
  Attention wanted(const Attention& now) const;
  // Whether this tick's attention is the one the binding asks for.
  bool attending(const ControlInput& in) const;
  // Whether the running invocation has used up its patience without converging.
  bool out_of_patience(const ControlInput& in) const;
  // Ends the running invocation as given up.
  void give_up(const ControlInput& in);
  // The state shown for the target's g: with sticky_noref, NOREF from a NOREF until a CONV.
  Gamma sticky(Gamma g, const ControlInput& in);
  // Notes that the binding shows NOREF now (for retry_after): a fresh one (a give-up, the target
  // turning NOREF) starts the memory over; one that lasts keeps its start.
  void mark_noref(const ControlInput& in, bool fresh);
  // Whether retry_after has passed since the NOREF began: the binding may be tried again.
  bool noref_forgotten(const ControlInput& in) const;
  // The state of a binding that is not running: what its last invocation ended with.
  Gamma resting_state(const ControlInput& in);
  ControllerPtr target_;
  Bindings bindings_;
  uint64_t seed_ = 0;
  int invocations_ = 0;
  uint64_t begun_tick_ = UINT64_MAX;
  double begun_time_ = 0.0;     // when the running invocation began (s)
  bool gave_up_ = false;        // the last invocation ran out of patience
  uint64_t gave_up_tick_ = UINT64_MAX;  // the tick it did
  bool failed_ = false;         // sticky_noref: a NOREF since the last CONV
  bool noref_ = false;          // the state shown was NOREF on the last tick it was asked
  bool target_noref_ = false;   // the target's own state was NOREF when last read
  double noref_since_ = 0.0;    // when that NOREF began (s)
  Gamma last_ = Gamma::kNoRef;  // the state the last invocation ended with
};

// Packs the gammas of a list of controllers into a state index in [0, 3^n).
int gamma_state_index(const std::vector<Gamma>& gammas);

// A skill that maps the state (the gamma vector of its actions) to one of its actions, by a table;
// states missing from the table run `fallback` (or nothing), or, with kRotate, the actions in turn:
// each runs until it has ended (its state is no longer !CONV after it ran), then the next; a way out
// of a state where every action said it has nothing to do, which running the same one again would
// not leave. An action that ends on the tick its turn begins (its state no longer !CONV once
// evaluated) hands the tick to the next at once. Learned stages yield these. Its gamma:
// CONV when `done` is CONV (its goal), NOREF when no action has a reference, !CONV otherwise.
class Policy final : public Controller {
 public:
  // actions: the state vector's controllers and the choices; table: state index -> action index
  // (-1 = no entry); done: the controller whose convergence is the skill's goal (may be null).
  Policy(std::vector<ControllerPtr> actions, std::vector<int> table, ControllerPtr done,
         int fallback = -1);
  static constexpr int kRotate = -2;  // `fallback`: the actions in turn
  std::vector<const Controller*> children() const override;
  // CONV only when `done` is: never without one.
  bool can_converge() const override { return done_ && done_->can_converge(); }
  const char* kind() const override { return "policy"; }
  void reset(uint64_t seed) override;
  ControllerPtr copy() const override { return std::make_shared<Policy>(*this); }
  void relink(Duplicates& done) override;
  // The action chosen at the last evaluation, or -1.
  int chosen() const { return chosen_; }
  const Controller* inner() const override { return chosen_ >= 0 ? actions_[size_t(chosen_)].get() : nullptr; }
  const std::vector<ControllerPtr>& actions() const { return actions_; }
  const std::vector<int>& table() const { return table_; }
  // Whether it runs nothing while `done` holds (off: its table's action runs on). On, a policy
  // chosen again once its goal holds does not disturb what it achieved: a task whose objects are
  // put away does not go looking for them.
  void set_rest_when_done(bool rest) { rest_when_done_ = rest; }
  bool rest_when_done() const { return rest_when_done_; }

 protected:
  void pass_executed(const ControlInput& in) override;
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) override;
  bool compute_state(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) override;

 private:
  // Reads the actions' states into scratch_ and returns the policy's own: CONV when `done` has
  // converged, else !CONV while some action has a reference, else NOREF.
  Gamma read_state(const ControlInput& in);
  // The kRotate fallback's action for this tick (see the class comment); evaluates the actions it
  // passes over.
  int next_in_turn(const ControlInput& in);
  std::vector<ControllerPtr> actions_;
  std::vector<int> table_;
  ControllerPtr done_;
  int fallback_ = -1;
  bool rest_when_done_ = false;
  int chosen_ = -1;
  int rotation_ = 0;                   // the action a kRotate fallback runs
  uint64_t chosen_tick_ = UINT64_MAX;  // the tick of the last choice
  std::vector<Gamma> scratch_;
};

}  // namespace roger
