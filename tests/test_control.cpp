// Tests of engine/control: Equation 1 states, nullspace projection, subject-to, sequences, policies.
#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include "control/agent.h"
#include "control/control.h"
#include "core/rng.h"
#include "sim/occupancy.h"
#include "world_fixtures.h"

using namespace roger;
using namespace roger::test;

namespace {

// A controller whose output the test scripts directly.
class Scripted final : public Controller {
 public:
  explicit Scripted(std::string name) { set_name(std::move(name)); }
  const char* kind() const override { return "scripted"; }
  ControllerPtr copy() const override { return std::make_shared<Scripted>(*this); }
  Gamma next = Gamma::kNotConv;
  DofVector command = DofVector::Zero();
  TaskJacobian jacobian;
  int evaluations = 0;

 protected:
  void compute(const ControlInput&, ControlOutput& out, Gamma& gamma) override {
    ++evaluations;
    out.command = command;
    out.jacobian = jacobian;
    gamma = next;
  }
};

TaskJacobian random_jacobian(Rng& rng, int rows) {
  TaskJacobian J(rows, kDofCount);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < kDofCount; ++c) J(r, c) = rng.uniform(-1.0, 1.0);
  return J;
}

DofVector random_vector(Rng& rng) {
  DofVector v;
  for (int i = 0; i < kDofCount; ++i) v[i] = rng.uniform(-1.0, 1.0);
  return v;
}

// A world of the default control tick (20 ms), for controllers that read it.
const WorldModel kDefaultModel;

ControlInput at_tick(uint64_t tick, double time = 0.0) {
  ControlInput in;
  in.model = &kDefaultModel;
  in.tick = tick;
  in.time = time;
  return in;
}

}  // namespace

TEST_CASE("the nullspace projector annihilates the task: J N = 0", "[control]") {
  Rng rng(3);
  for (int rows = 1; rows <= 7; ++rows) {
    const TaskJacobian J = random_jacobian(rng, rows);
    const DofMatrix N = nullspace_projector(J);
    CHECK((J * N).norm() < 1e-9);
    CHECK((N * N - N).norm() < 1e-9);            // a projector
    CHECK((N - N.transpose()).norm() < 1e-9);    // orthogonal
    CHECK(std::abs(N.trace() - (kDofCount - rows)) < 1e-9);  // rank of the nullspace
  }
  // A rank-deficient task (a repeated row) loses only one dimension, and stays exact.
  TaskJacobian J = random_jacobian(rng, 3);
  J.row(2) = 2.0 * J.row(0);
  const DofMatrix N = nullspace_projector(J);
  CHECK((J * N).norm() < 1e-9);
  CHECK(std::abs(N.trace() - (kDofCount - 2)) < 1e-9);
  // N v without forming N is the same vector.
  for (int rows = 0; rows <= 9; ++rows) {
    const TaskJacobian Jr = random_jacobian(rng, rows);
    const DofVector v = random_vector(rng);
    CHECK((nullspace_project(Jr, v) - nullspace_projector(Jr) * v).norm() < 1e-12);
  }
  // No task: everything is free.
  CHECK((nullspace_projector(TaskJacobian(0, kDofCount)) - DofMatrix::Identity()).norm() == 0.0);
}

TEST_CASE("an agent's occupancy grid follows the arena and obstacles of each episode", "[control]") {
  // The grid is kept from one episode to the next while the arena and obstacles stay the same; a
  // moved, reshaped, added or removed obstacle, or another arena, must give that world's grid.
  auto with_box = [](double x, double half) {
    WorldSpec w = open_world();
    ObstacleSpec o;
    o.shape = box_shape(half, 0.2);
    o.pose = {x, 0.8, 0.0};
    w.obstacles.push_back(o);
    return w;
  };
  WorldSpec wide = open_world();
  wide.arena.xmax = 3.0;
  const std::vector<WorldSpec> worlds = {with_box(0.5, 0.3), with_box(0.5, 0.3), with_box(-0.7, 0.3),
                                         with_box(-0.7, 0.5), open_world(), with_box(0.5, 0.3),
                                         wide, open_world(false), with_box(0.5, 0.3)};
  Agent agent;
  for (size_t k = 0; k < worlds.size(); ++k) {
    agent.reset(worlds[k]);
    const OccupancyGrid expected = build_occupancy(worlds[k], body_metrics(worlds[k].body, worlds[k].eyes).grid_inflate);
    INFO("world " << k);
    CHECK(agent.grid().nx == expected.nx);
    CHECK(agent.grid().x0 == expected.x0);
    CHECK(agent.grid().occupied == expected.occupied);
  }
}

TEST_CASE("subject-to keeps the superior's objective and projects the subordinate", "[control]") {
  Rng rng(11);
  auto sup = std::make_shared<Scripted>("sup");
  auto sub = std::make_shared<Scripted>("sub");
  SubjectTo both(sub, sup);
  CHECK(both.name() == "sub <| sup");
  for (int trial = 0; trial < 20; ++trial) {
    sup->jacobian = random_jacobian(rng, 1 + trial % 5);
    sup->command = random_vector(rng);
    sub->command = random_vector(rng);
    const ControlOutput& out = both.evaluate(at_tick(uint64_t(trial)));
    // Whatever the subordinate adds is invisible to the superior's task...
    CHECK((sup->jacobian * (out.command - sup->command)).norm() < 1e-9);
    // ...and is exactly its command's component in the nullspace.
    const DofMatrix N = nullspace_projector(sup->jacobian);
    CHECK((out.command - sup->command - N * sub->command).norm() < 1e-12);
    CHECK(out.jacobian.rows() == sup->jacobian.rows() + sub->jacobian.rows());
  }
}

TEST_CASE("a composite's gamma is the weaker of its parts, with the stall rule", "[control]") {
  auto sup = std::make_shared<Scripted>("sup");
  auto sub = std::make_shared<Scripted>("sub");
  SubjectTo both(sub, sup);
  uint64_t tick = 0;
  sup->next = Gamma::kConv, sub->next = Gamma::kConv;
  CHECK(both.evaluate(at_tick(++tick)).gamma == Gamma::kConv);
  sup->next = Gamma::kNoRef;
  CHECK(both.evaluate(at_tick(++tick)).gamma == Gamma::kNoRef);
  sup->next = Gamma::kConv, sub->next = Gamma::kNotConv;
  sub->command = DofVector::Unit(kBaseForward);
  CHECK(both.evaluate(at_tick(++tick)).gamma == Gamma::kNotConv);
  // The superior owns the DOF the subordinate pushes on: nothing survives the projection, so the
  // subordinate sits at its constrained equilibrium and counts as converged.
  sup->jacobian = TaskJacobian::Zero(1, kDofCount);
  sup->jacobian(0, kBaseForward) = 1.0;
  CHECK(both.evaluate(at_tick(++tick)).gamma == Gamma::kConv);
  // A subordinate asking for nothing does not converge by that alone.
  sub->command.setZero();
  CHECK(both.evaluate(at_tick(++tick)).gamma == Gamma::kNotConv);
}

namespace {

// A subordinate whose potential stays at 1 while the distance it reports as its residual falls by
// `step` a tick (a navigator far from its goal); it measures its progress by that distance when
// `by_distance`.
class Travelling final : public Controller {
 public:
  explicit Travelling(bool by_distance) : by_distance_(by_distance) { set_name("travelling"); }
  const char* kind() const override { return "scripted"; }
  double progress(const ControlOutput& out) const override { return by_distance_ ? out.residual : out.phi; }
  double distance = 5.0, step = 0.02;

 protected:
  void compute(const ControlInput&, ControlOutput& out, Gamma& gamma) override {
    out.command = DofVector::Unit(kBaseForward);
    out.phi = 1.0;
    out.residual = distance;
    distance = std::max(0.0, distance - step);
    gamma = Gamma::kNotConv;
  }

 private:
  bool by_distance_;
};

// Runs `both` (executed each tick, 20 ms apart) for `ticks` ticks from `first`; returns the ticks
// on which it read CONV.
int conv_ticks(SubjectTo& both, uint64_t first, int ticks) {
  int conv = 0;
  for (uint64_t t = first; t < first + uint64_t(ticks); ++t) {
    ControlInput in = at_tick(t, 0.02 * double(t));
    conv += both.evaluate(in).gamma == Gamma::kConv;
    both.executed(in);
  }
  return conv;
}

}  // namespace

TEST_CASE("a subordinate settles when its progress stops, not while its potential is flat", "[control]") {
  // The plateau rule: executed for `plateau` seconds with its progress changed by less than
  // `stall`, a subordinate counts as converged where its superior lets it be.
  for (const bool by_distance : {true, false}) {
    auto sub = std::make_shared<Travelling>(by_distance);
    auto sup = std::make_shared<Scripted>("sup");
    sup->next = Gamma::kConv;
    SubjectTo both(sub, sup);
    both.reset(0);
    // Making headway (1 m/s) with a flat potential: measured by its distance it never settles;
    // measured by its potential it "settles" once `plateau` has passed.
    const int moving = conv_ticks(both, 1, 50);
    // Stopped: settled after `plateau` (0.3 s) either way.
    sub->step = 0.0;
    const int stopped = conv_ticks(both, 51, 50);
    INFO((by_distance ? "by distance" : "by potential") << ": " << moving << " CONV moving, " << stopped << " stopped");
    CHECK((by_distance ? moving == 0 : moving > 0));
    CHECK(stopped >= 30);
  }
}

TEST_CASE("evaluation is cached per tick, and hold delays convergence", "[control]") {
  auto c = std::make_shared<Scripted>("c");
  c->params().hold = 0.1;
  c->next = Gamma::kConv;
  CHECK(c->evaluate(at_tick(1, 0.00)).gamma == Gamma::kNotConv);
  CHECK(c->evaluate(at_tick(1, 0.00)).gamma == Gamma::kNotConv);
  CHECK(c->evaluations == 1);
  CHECK(c->evaluate(at_tick(2, 0.06)).gamma == Gamma::kNotConv);
  CHECK(c->evaluate(at_tick(3, 0.10)).gamma == Gamma::kConv);
  c->next = Gamma::kNotConv;
  CHECK(c->evaluate(at_tick(4, 0.12)).gamma == Gamma::kNotConv);
  c->next = Gamma::kConv;
  CHECK(c->evaluate(at_tick(5, 0.14)).gamma == Gamma::kNotConv);  // the hold starts again
}

TEST_CASE("a hold must be watched without a gap: ticks nobody evaluated restart it", "[control]") {
  auto c = std::make_shared<Scripted>("c");
  c->params().hold = 0.1;
  c->next = Gamma::kConv;
  CHECK(c->evaluate(at_tick(1, 0.00)).gamma == Gamma::kNotConv);
  CHECK(c->evaluate(at_tick(2, 0.02)).gamma == Gamma::kNotConv);
  // Ticks 3 to 9 unseen (an idle sequence step, a predicate part not needed): CONV at tick 10 is
  // the start of a new hold, not the end of one begun at tick 1.
  CHECK(c->evaluate(at_tick(10, 0.18)).gamma == Gamma::kNotConv);
  for (uint64_t t = 11; t <= 14; ++t) CHECK(c->evaluate(at_tick(t, 0.18 + 0.02 * double(t - 10))).gamma == Gamma::kNotConv);
  CHECK(c->evaluate(at_tick(15, 0.28)).gamma == Gamma::kConv);
  // The state-only path keeps the same watch.
  CHECK(c->state(at_tick(16, 0.30)) == Gamma::kConv);
  CHECK(c->state(at_tick(20, 0.38)) == Gamma::kNotConv);
}

TEST_CASE("a sequence advances on CONV and falls back on NOREF", "[control]") {
  auto a = std::make_shared<Scripted>("a"), b = std::make_shared<Scripted>("b"),
       c = std::make_shared<Scripted>("c");
  a->command = DofVector::Unit(0), b->command = DofVector::Unit(1), c->command = DofVector::Unit(2);
  Sequence seq({a, b, c});
  seq.reset(0);
  uint64_t tick = 0;
  a->next = Gamma::kNotConv, b->next = Gamma::kNoRef, c->next = Gamma::kNoRef;
  CHECK(seq.evaluate(at_tick(++tick)).command == a->command);
  CHECK(seq.output().gamma == Gamma::kNotConv);
  a->next = Gamma::kConv, b->next = Gamma::kNotConv;
  CHECK(seq.evaluate(at_tick(++tick)).command == b->command);
  CHECK(seq.current() == 1);
  b->next = Gamma::kConv, c->next = Gamma::kNotConv;
  seq.evaluate(at_tick(++tick));
  CHECK(seq.current() == 2);
  c->next = Gamma::kConv;
  CHECK(seq.evaluate(at_tick(++tick)).gamma == Gamma::kConv);  // the last step converged
  // c loses its reference: back to b, which still has one.
  c->next = Gamma::kNoRef;
  CHECK(seq.evaluate(at_tick(++tick)).command == b->command);
  CHECK(seq.current() == 1);
  a->next = b->next = c->next = Gamma::kNoRef;
  seq.evaluate(at_tick(++tick));
  CHECK(seq.output().gamma == Gamma::kNoRef);
  CHECK(seq.current() == 0);
}

TEST_CASE("a sequence stuck on its first step without a reference is NOREF, whatever later steps have",
          "[control]") {
  // A sorting move's search that has looked everywhere (the first step, NOREF) while an object
  // pressed against the body gives the grasp step a reference: the sequence cannot get to that
  // step, so it has nothing to do.
  auto search = std::make_shared<Scripted>("search"), grasp = std::make_shared<Scripted>("grasp");
  Sequence seq({search, grasp});
  seq.reset(0);
  search->next = Gamma::kNoRef, grasp->next = Gamma::kNotConv;
  CHECK(seq.evaluate(at_tick(1)).gamma == Gamma::kNoRef);
  CHECK(seq.current() == 0);
  // Further on, a step without a reference falls back and the sequence is !CONV, as before.
  search->next = Gamma::kConv;
  seq.evaluate(at_tick(2));
  REQUIRE(seq.current() == 1);
  grasp->next = Gamma::kNoRef, search->next = Gamma::kNotConv;
  CHECK(seq.evaluate(at_tick(3)).gamma == Gamma::kNotConv);
  CHECK(seq.current() == 0);
}

TEST_CASE("a policy maps the gamma vector of its actions to an action", "[control]") {
  auto a = std::make_shared<Scripted>("a"), b = std::make_shared<Scripted>("b");
  a->command = DofVector::Unit(3), b->command = DofVector::Unit(4);
  std::vector<int> table(9, -1);
  table[gamma_state_index({Gamma::kNotConv, Gamma::kNoRef})] = 0;
  table[gamma_state_index({Gamma::kConv, Gamma::kNotConv})] = 1;
  Policy p({a, b}, table, b);
  p.reset(0);
  a->next = Gamma::kNotConv, b->next = Gamma::kNoRef;
  CHECK(p.evaluate(at_tick(1)).command == a->command);
  CHECK(p.chosen() == 0);
  CHECK(p.output().gamma == Gamma::kNotConv);
  a->next = Gamma::kConv, b->next = Gamma::kNotConv;
  CHECK(p.evaluate(at_tick(2)).command == b->command);
  b->next = Gamma::kConv;
  CHECK(p.evaluate(at_tick(3)).gamma == Gamma::kConv);  // its goal controller converged
  CHECK(p.chosen() == -1);                               // and the table has no entry there
  a->next = b->next = Gamma::kNoRef;
  CHECK(p.evaluate(at_tick(4)).gamma == Gamma::kNoRef);
  CHECK(gamma_state_index({Gamma::kConv, Gamma::kConv}) == 8);
  CHECK_THROWS_WITH(Policy({a, b}, std::vector<int>(8, 0), nullptr), Catch::Contains("3^2 = 9"));
}

TEST_CASE("a policy asked only for its state runs none of its actions", "[control]") {
  // A stage reads the state of every action each tick; a policy not chosen must not run (and so
  // restart or advance) the action its table would pick.
  auto a = std::make_shared<Scripted>("a"), goal = std::make_shared<Scripted>("goal");
  Policy p({a}, std::vector<int>(3, 0), goal);
  p.reset(0);
  a->next = Gamma::kNotConv, goal->next = Gamma::kNotConv;
  CHECK(p.state(at_tick(1)) == Gamma::kNotConv);
  CHECK(p.chosen() == -1);
  CHECK(a->evaluations == 1);  // its state was read: one evaluation of the scripted controller
  a->next = Gamma::kNoRef;
  CHECK(p.state(at_tick(2)) == Gamma::kNoRef);
  goal->next = Gamma::kConv;
  CHECK(p.state(at_tick(3)) == Gamma::kConv);
  CHECK(p.chosen() == -1);
  // Evaluated after its state in the same tick, it runs its action with the same state.
  a->next = Gamma::kNotConv, goal->next = Gamma::kNotConv;
  a->command = DofVector::Unit(2);
  CHECK(p.state(at_tick(4)) == Gamma::kNotConv);
  CHECK(p.evaluate(at_tick(4)).command == a->command);
  CHECK(p.output().gamma == Gamma::kNotConv);
  CHECK(p.chosen() == 0);
}

TEST_CASE("a rotate fallback runs its actions in turn, passing at once over one that ends as its turn begins",
          "[control]") {
  // No table entry: the actions take turns, each until it has ended. An action that ends on the tick
  // its turn begins (sorting.by_hand's phi1 going elsewhere, with no need to) costs no tick.
  auto a = std::make_shared<Scripted>("a"), b = std::make_shared<Scripted>("b"),
       c = std::make_shared<Scripted>("c");
  a->command = DofVector::Unit(1), b->command = DofVector::Unit(2), c->command = DofVector::Unit(3);
  Policy p({a, b, c}, std::vector<int>(27, -1), nullptr, Policy::kRotate);
  p.reset(0);
  CHECK(p.evaluate(at_tick(1)).command == a->command);  // a's turn
  CHECK(p.evaluate(at_tick(2)).command == a->command);  // still !CONV: still a's
  a->next = Gamma::kNoRef;                              // a has ended,
  b->next = Gamma::kConv;                               // and b is done as soon as it is asked:
  CHECK(p.evaluate(at_tick(3)).command == c->command);  // c runs on the very tick
  CHECK(p.chosen() == 2);
  CHECK(p.evaluate(at_tick(4)).command == c->command);
  // c ends, and a and b would end at once: a (the next) runs for a tick, as the old rule had it.
  c->next = Gamma::kNoRef;
  CHECK(p.evaluate(at_tick(5)).command == a->command);
  // A gap (another skill ran on tick 6): the turn begins again with the action in turn.
  a->next = Gamma::kNotConv;
  CHECK(p.evaluate(at_tick(7)).command == a->command);
}

TEST_CASE("a policy that rests when done runs nothing while its goal holds", "[control]") {
  auto a = std::make_shared<Scripted>("a"), goal = std::make_shared<Scripted>("goal");
  a->command = DofVector::Unit(1);
  Policy runs_on({a}, std::vector<int>(3, 0), goal), rests({a}, std::vector<int>(3, 0), goal);
  rests.set_rest_when_done(true);
  CHECK_FALSE(runs_on.rest_when_done());
  runs_on.reset(0), rests.reset(0);
  a->next = Gamma::kNotConv, goal->next = Gamma::kNotConv;
  CHECK(rests.evaluate(at_tick(1)).command == a->command);  // not there yet: runs its action
  goal->next = Gamma::kConv;
  const ControlOutput& at_rest = rests.evaluate(at_tick(2));
  CHECK(at_rest.gamma == Gamma::kConv);
  CHECK(at_rest.command.isZero());
  CHECK(rests.chosen() == -1);
  CHECK(rests.inner() == nullptr);
  CHECK(runs_on.evaluate(at_tick(2)).command == a->command);  // the default: its table runs on
  goal->next = Gamma::kNotConv;  // the goal lost again (an object knocked out of its region)
  CHECK(rests.evaluate(at_tick(3)).command == a->command);
}

TEST_CASE("a sticky binding stays NOREF through retries until an invocation converges", "[control]") {
  // A chooser that runs again a move it was told is stuck must see a retry, not the fresh !CONV
  // of an episode's start; the move acts as it always did (its command passes through).
  auto plain_target = std::make_shared<Scripted>("move"), sticky_target = std::make_shared<Scripted>("move");
  Binding::Bindings b;
  b.region = 1;
  b.patience = 1.0;
  Binding plain(plain_target, b);
  b.sticky_noref = true;
  Binding sticky(sticky_target, b);
  plain.reset(0), sticky.reset(0);
  uint64_t tick = 0;
  // One control tick of both (1/8 s apart, exact in binary), the target reporting g; returns the two states.
  auto step = [&](Gamma g) {
    plain_target->next = sticky_target->next = g;
    plain_target->command = sticky_target->command = DofVector::Unit(0);
    const ControlInput in = at_tick(tick, 0.125 * double(tick));
    ++tick;
    const std::pair<Gamma, Gamma> gammas{plain.evaluate(in).gamma, sticky.evaluate(in).gamma};
    plain.executed(in), sticky.executed(in);
    return gammas;
  };
  using G = std::pair<Gamma, Gamma>;
  CHECK(step(Gamma::kNotConv) == G{Gamma::kNotConv, Gamma::kNotConv});
  CHECK(step(Gamma::kNoRef) == G{Gamma::kNoRef, Gamma::kNoRef});
  // The target finds a reference again: the plain binding shows it, the sticky one does not, and
  // still passes the target's command on.
  CHECK(step(Gamma::kNotConv) == G{Gamma::kNotConv, Gamma::kNoRef});
  CHECK(sticky.output().command == DofVector::Unit(0));
  // Not run for a tick, then read for its state alone: what the invocation ended with, or NOREF.
  ++tick;
  CHECK(plain.state(at_tick(tick)) == Gamma::kNotConv);
  CHECK(sticky.state(at_tick(tick)) == Gamma::kNoRef);
  // Run again: a new invocation, still NOREF for the sticky binding, until one converges.
  CHECK(step(Gamma::kNotConv) == G{Gamma::kNotConv, Gamma::kNoRef});
  CHECK(sticky.invocations() == 2);
  CHECK(step(Gamma::kConv) == G{Gamma::kConv, Gamma::kConv});
  CHECK(step(Gamma::kNotConv) == G{Gamma::kNotConv, Gamma::kNotConv});  // the next object: cleared
  CHECK(sticky.invocations() == 3);
  // Given up after its patience (1 s, 8 ticks, without converging): NOREF for both; evaluated again, both
  // start over, and the sticky one says it is a retry while it acts.
  const uint64_t begun = tick - 1;
  G gave_up{Gamma::kNotConv, Gamma::kNotConv};
  while (tick < begun + 8) gave_up = step(Gamma::kNotConv);
  CHECK(gave_up == G{Gamma::kNotConv, Gamma::kNotConv});
  CHECK(step(Gamma::kNotConv) == G{Gamma::kNoRef, Gamma::kNoRef});
  CHECK(sticky.output().command.isZero());
  CHECK(step(Gamma::kNotConv) == G{Gamma::kNotConv, Gamma::kNoRef});
  CHECK(sticky.invocations() == 4);
  CHECK(sticky.output().command == DofVector::Unit(0));
  // A new episode forgets it.
  sticky.reset(0);
  CHECK(sticky.state(at_tick(tick)) == Gamma::kNotConv);
}

TEST_CASE("a binding with retry_after forgets a NOREF that long after it began", "[control]") {
  // A greedy chooser shown a type stuck for good never tries it again; a view blocked by another
  // object, or an object pinned for a while, may have cleared meanwhile.
  constexpr uint64_t kPatience = 64, kRetryAfter = 16;  // ticks of 1/8 s: 8 s and 2 s
  auto target = std::make_shared<Scripted>("move"), other_target = std::make_shared<Scripted>("move");
  Binding::Bindings b;
  b.region = 1;
  b.patience = 0.125 * kPatience;
  b.sticky_noref = true;
  b.retry_after = 0.125 * kRetryAfter;
  Binding forgetful(target, b);
  b.retry_after = 0.0;
  Binding remembers(other_target, b);
  forgetful.reset(0), remembers.reset(0);
  uint64_t tick = 0;
  // One tick (1/8 s, exact in binary): `run` evaluates both bindings, else only their states are read.
  auto step = [&](Gamma g, bool run) {
    target->next = other_target->next = g;
    const ControlInput in = at_tick(tick, 0.125 * double(tick));
    ++tick;
    if (!run) return std::pair<Gamma, Gamma>{forgetful.state(in), remembers.state(in)};
    const std::pair<Gamma, Gamma> gammas{forgetful.evaluate(in).gamma, remembers.evaluate(in).gamma};
    forgetful.executed(in), remembers.executed(in);
    return gammas;
  };
  using G = std::pair<Gamma, Gamma>;
  CHECK(step(Gamma::kNotConv, true) == G{Gamma::kNotConv, Gamma::kNotConv});
  while (tick < kPatience) step(Gamma::kNotConv, true);
  CHECK(step(Gamma::kNotConv, true) == G{Gamma::kNoRef, Gamma::kNoRef});  // given up
  // Not run: NOREF until retry_after has passed since the give-up, then !CONV for the forgetful one.
  G resting{};
  while (tick < kPatience + kRetryAfter) resting = step(Gamma::kNotConv, false);
  CHECK(resting == G{Gamma::kNoRef, Gamma::kNoRef});
  CHECK(step(Gamma::kNotConv, false) == G{Gamma::kNotConv, Gamma::kNoRef});
  // Run again, it is a fresh try; given up again, the memory starts over from that give-up.
  CHECK(step(Gamma::kNotConv, true) == G{Gamma::kNotConv, Gamma::kNoRef});
  const uint64_t begun = tick - 1;
  while (tick < begun + kPatience) step(Gamma::kNotConv, true);
  CHECK(step(Gamma::kNotConv, true) == G{Gamma::kNoRef, Gamma::kNoRef});
  const uint64_t gave_up = tick - 1;
  while (tick < gave_up + kRetryAfter) resting = step(Gamma::kNotConv, false);
  CHECK(resting == G{Gamma::kNoRef, Gamma::kNoRef});
  CHECK(step(Gamma::kNotConv, false).first == Gamma::kNotConv);
  // A target that itself says NOREF is shown NOREF however long it lasts; once it has a reference
  // again, the sticky NOREF lasts until retry_after after the target's NOREF began.
  CHECK(step(Gamma::kNoRef, true).first == Gamma::kNoRef);
  const uint64_t noref_began = tick - 1;
  while (tick < noref_began + kRetryAfter - 4) CHECK(step(Gamma::kNoRef, true).first == Gamma::kNoRef);
  CHECK(step(Gamma::kNotConv, true).first == Gamma::kNoRef);  // sticky: not yet forgotten
  while (tick < noref_began + kRetryAfter) step(Gamma::kNotConv, true);
  CHECK(step(Gamma::kNotConv, true).first == Gamma::kNotConv);  // forgotten
  CHECK(step(Gamma::kNoRef, true).first == Gamma::kNoRef);  // a fresh NOREF: remembered from now
  const uint64_t fresh = tick - 1;
  CHECK(step(Gamma::kNotConv, true).first == Gamma::kNoRef);
  // Another fresh NOREF while that one is remembered starts the memory over.
  while (tick < fresh + 10) step(Gamma::kNotConv, true);
  CHECK(step(Gamma::kNoRef, true).first == Gamma::kNoRef);
  while (tick < fresh + 10 + kRetryAfter) CHECK(step(Gamma::kNotConv, true).first == Gamma::kNoRef);
  CHECK(step(Gamma::kNotConv, true).first == Gamma::kNotConv);
  // A new episode forgets it all.
  forgetful.reset(0);
  CHECK(forgetful.state(at_tick(tick)) == Gamma::kNotConv);
}

// Touch locates the object perceived only on an object of the stimulus colour: a bystander of
// another colour bumped on the way is not taken for it (it was what the grasp then closed on and
// shoved into a wall), and a neighbour of the same colour brushed against while one is held does
// not take the held one's place.
TEST_CASE("touch locates the object only on an object of the stimulus colour", "[control][percepts]") {
  const Colour blue{40, 80, 220}, yellow{230, 170, 20};
  std::vector<MapObject> objects(3);
  objects[0].colour = blue, objects[1].colour = yellow, objects[2].colour = blue;
  const RobotParams robot;
  Senses s;
  // Tick 1: stereo fixes the blue object 1 m ahead, 0.1 m in radius.
  s.stereo_valid = true;
  for (auto& st : s.stimulus) st.seen = true, st.half_width = std::asin(0.1);
  s.stimulus_world = s.stimulus_base = Vec2(1.0, 0.0);
  Percepts with_map, without_map;
  with_map.update(s, robot, &objects, &blue);
  without_map.update(s, robot);
  REQUIRE(with_map.object.seen);
  REQUIRE_FALSE(with_map.object.by_touch);
  REQUIRE(with_map.remembered.radius == Approx(0.1));

  // Tick 2: the eyes lose it, and the body bumps the yellow object at (0.3, 0.3).
  s.time = 0.02;
  s.stereo_valid = false;
  auto touch = [&](int sensor, int index, const Vec2& point, const Vec2& normal) {
    Touch& t = s.touch[size_t(sensor)];
    t.contact = true, t.kind = SurfaceKind::kObject, t.index = index, t.point = point, t.normal = normal;
  };
  touch(kBody, 1, Vec2(0.3, 0.3), Vec2(-1.0, 0.0));
  with_map.update(s, robot, &objects, &blue);
  without_map.update(s, robot);
  CHECK(with_map.touched_object == 1);
  CHECK_FALSE(with_map.object.seen);  // nothing perceived this tick: vision lost it, touch is not it
  CHECK(with_map.felt_object == -1);
  CHECK(with_map.remembered.center.isApprox(Vec2(1.0, 0.0)));
  // Without the map and the colour, whatever is touched most is taken for the object.
  CHECK(without_map.object.by_touch);
  CHECK(without_map.object.center.isApprox(Vec2(0.4, 0.3)));

  // Tick 3: the body and the left hand touch the blue object: touch locates it.
  s.time = 0.04;
  s.touch = {};
  touch(kBody, 0, Vec2(0.9, 0.0), Vec2(-1.0, 0.0));
  touch(kLeftHand, 0, Vec2(1.0, 0.1), Vec2(0.0, 1.0));
  with_map.update(s, robot, &objects, &blue);
  REQUIRE(with_map.object.by_touch);
  CHECK(with_map.felt_object == 0);
  CHECK(with_map.object.center.isApprox(Vec2(1.0, 0.0)));

  // Tick 4: the other blue object is touched by two sensors, the held one by the body alone: the
  // held one stays the object.
  s.time = 0.06;
  s.touch = {};
  touch(kBody, 0, Vec2(0.9, 0.0), Vec2(-1.0, 0.0));
  touch(kLeftHand, 2, Vec2(1.2, 0.5), Vec2(0.0, -1.0));
  touch(kRightHand, 2, Vec2(1.3, 0.4), Vec2(-1.0, 0.0));
  with_map.update(s, robot, &objects, &blue);
  CHECK(with_map.touched_object == 2);
  CHECK(with_map.felt_object == 0);
  CHECK(with_map.object.center.isApprox(Vec2(1.0, 0.0)));

  // Tick 5: the held one is let go: the blue object touched is now the one located.
  s.time = 0.08;
  s.touch[size_t(kBody)] = Touch{};
  with_map.update(s, robot, &objects, &blue);
  CHECK(with_map.felt_object == 2);
}

TEST_CASE("duplicate copies a skill and its parts once each, keeping what they share", "[control]") {
  auto x = std::make_shared<Scripted>("x"), y = std::make_shared<Scripted>("y");
  auto both = std::make_shared<SubjectTo>(x, y);
  auto policy = std::make_shared<Policy>(std::vector<ControllerPtr>{x, both}, std::vector<int>(9, 1), both);
  auto steps = std::make_shared<Sequence>(std::vector<ControllerPtr>{policy, both});
  steps->set_name("steps");
  Duplicates done;
  const ControllerPtr copy = duplicate(steps, done);
  REQUIRE(copy != steps);
  CHECK(copy->name() == "steps");
  CHECK(done.controllers.size() == 5);  // steps, policy, both, x, y: each once
  const auto& s = static_cast<const Sequence&>(*copy);
  const auto& p = static_cast<const Policy&>(*s.steps()[0]);
  const auto& b = static_cast<const SubjectTo&>(*s.steps()[1]);
  CHECK(p.actions()[1].get() == &b);  // `both` is one controller in the copy, as in the original
  CHECK(p.actions()[0] == b.subordinate());
  CHECK(b.subordinate() != x);
  CHECK(b.superior() != y);
  CHECK(p.table() == policy->table());
  // The copies evaluate on their own: the originals are not asked.
  x->next = y->next = Gamma::kConv;
  ControlInput in;
  in.tick = 1;
  copy->evaluate(in);
  CHECK(x->evaluations == 0);
  CHECK(y->evaluations == 0);
}
