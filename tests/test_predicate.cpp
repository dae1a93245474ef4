// Tests of engine/predicate: converged / gamma_is, all / any / not, held for t seconds, which
// controllers a predicate evaluates at a tick, and the world's sorting judgement.
#include <cmath>
#include <catch2/catch.hpp>

#include "control/predicate.h"

using namespace roger;

namespace {

// A controller whose gamma the test sets, counting its evaluations.
class Scripted final : public Controller {
 public:
  explicit Scripted(std::string name) { set_name(std::move(name)); }
  const char* kind() const override { return "scripted"; }
  ControllerPtr copy() const override { return std::make_shared<Scripted>(*this); }
  Gamma next = Gamma::kNotConv;
  int evaluations = 0;

 protected:
  void compute(const ControlInput&, ControlOutput&, Gamma& gamma) override {
    ++evaluations;
    gamma = next;
  }
};

// A world of the default control tick (20 ms), for controllers that read it.
const WorldModel kDefaultModel;

ControlInput at_tick(uint64_t tick, double time) {
  ControlInput in;
  in.model = &kDefaultModel;
  in.tick = tick;
  in.time = time;
  return in;
}

}  // namespace

TEST_CASE("converged, gamma_is, all, any and not read the tick's states", "[predicate]") {
  auto a = std::make_shared<Scripted>("a"), b = std::make_shared<Scripted>("b");
  auto both = all_of({converged(a), converged(b)});
  auto either = any_of({converged(a), converged(b)});
  auto neither = negate(either);
  auto a_noref = gamma_is(a, Gamma::kNoRef);
  uint64_t tick = 0;
  const Gamma gammas[] = {Gamma::kNoRef, Gamma::kNotConv, Gamma::kConv};
  for (Gamma ga : gammas)
    for (Gamma gb : gammas) {
      a->next = ga, b->next = gb;
      ++tick;  // before the call: its arguments are evaluated in no set order
      const ControlInput in = at_tick(tick, 0.02 * double(tick));
      const bool ca = ga == Gamma::kConv, cb = gb == Gamma::kConv;
      INFO(gamma_name(ga) << " " << gamma_name(gb));
      CHECK(both->holds(in) == (ca && cb));
      CHECK(either->holds(in) == (ca || cb));
      CHECK(neither->holds(in) == !(ca || cb));
      CHECK(a_noref->holds(in) == (ga == Gamma::kNoRef));
    }
  CHECK(all_of({})->holds(at_tick(++tick, 1.0)));
  CHECK_FALSE(any_of({})->holds(at_tick(++tick, 1.0)));
  CHECK(both->describe() == "all(converged(a), converged(b))");
}

TEST_CASE("all and any evaluate no controller beyond the part that decides them", "[predicate]") {
  // The transport goal all(converged(phi1), converged(phi4 <| phi5)) must not compute the grasp
  // keeper on every tick of the search, where phi1 is not even at the goal.
  auto cheap = std::make_shared<Scripted>("cheap"), costly = std::make_shared<Scripted>("costly");
  auto both = all_of({converged(cheap), converged(costly)});
  auto either = any_of({converged(cheap), converged(costly)});
  cheap->next = Gamma::kNotConv;
  for (uint64_t t = 1; t <= 10; ++t) CHECK_FALSE(both->holds(at_tick(t, 0.02 * double(t))));
  CHECK(costly->evaluations == 0);
  cheap->next = Gamma::kConv;
  for (uint64_t t = 11; t <= 20; ++t) CHECK(either->holds(at_tick(t, 0.02 * double(t))));
  CHECK(costly->evaluations == 0);
  // Once the first part holds, all() needs the second.
  costly->next = Gamma::kConv;
  CHECK(both->holds(at_tick(21, 0.42)));
  CHECK(costly->evaluations == 1);
}

TEST_CASE("with held() inside, every part sees every tick, and held times without a gap", "[predicate]") {
  auto a = std::make_shared<Scripted>("a"), b = std::make_shared<Scripted>("b");
  auto timed = all_of({converged(a), held(converged(b), 0.1)});
  REQUIRE(timed->timed());
  CHECK_FALSE(all_of({converged(a), converged(b)})->timed());
  CHECK(negate(held(converged(b), 0.1))->timed());
  a->next = Gamma::kNotConv, b->next = Gamma::kConv;
  uint64_t tick = 0;
  double time = 0.0;
  // a is not converged, yet b's timer runs: it must have watched b all along.
  for (; tick < 10; ++tick, time += 0.02) CHECK_FALSE(timed->holds(at_tick(tick + 1, time)));
  CHECK(b->evaluations == 10);
  a->next = Gamma::kConv;
  CHECK(timed->holds(at_tick(++tick, time)));  // b converged for 0.2 s already
  // An interruption restarts held().
  b->next = Gamma::kNotConv;
  time += 0.02;
  CHECK_FALSE(timed->holds(at_tick(++tick, time)));
  b->next = Gamma::kConv;
  for (int k = 0; k < 5; ++k) {
    time += 0.02;
    CHECK_FALSE(timed->holds(at_tick(++tick, time)));  // 0.0 .. 0.08 s held
  }
  time += 0.02;
  CHECK(timed->holds(at_tick(++tick, time)));          // 0.1 s
  timed->reset();
  CHECK_FALSE(timed->holds(at_tick(++tick, time + 0.02)));
}

// A goal held longer than its episode can never hold: a load refuses it (test_lua_control,
// test_curriculum) by this bound, which must never refuse a goal that can hold.
TEST_CASE("earliest_seconds bounds when a predicate can first hold", "[predicate]") {
  auto a = std::make_shared<Scripted>("a"), b = std::make_shared<Scripted>("b");
  CHECK(converged(a)->earliest_seconds() == 0.0);
  CHECK(held(converged(a), 2.0)->earliest_seconds() == 2.0);
  CHECK(held(held(converged(a), 2.0), 3.0)->earliest_seconds() == 5.0);
  CHECK(all_of({held(converged(a), 2.0), held(converged(b), 3.0)})->earliest_seconds() == 3.0);
  CHECK(any_of({held(converged(a), 2.0), held(converged(b), 3.0)})->earliest_seconds() == 2.0);
  CHECK(negate(held(converged(a), 9.0))->earliest_seconds() == 0.0);  // holds at once
  CHECK(std::isinf(any_of({})->earliest_seconds()));
  CHECK(all_of({})->earliest_seconds() == 0.0);
  // An episode of 5 s has its last tick at 5 s; one of 5.01 s at 5.02 s (ticks of 20 ms). The goal
  // is first judged after the first tick, at 0.02 s (EpisodeRun), so a hold of 5 s ends at 5.02 s at
  // the earliest (found by a probe: held(p, 5) in a 5 s policy passed, and never held).
  CHECK(can_hold_within(*held(converged(a), 4.98), 5.0, 0.02));
  CHECK_FALSE(can_hold_within(*held(converged(a), 4.99), 5.0, 0.02));
  CHECK_FALSE(can_hold_within(*held(converged(a), 5.0), 5.0, 0.02));
  CHECK(can_hold_within(*held(converged(a), 5.0), 5.01, 0.02));
  CHECK_FALSE(can_hold_within(*any_of({}), 5.0, 0.02));
  // The bound is reached: b converged from the first judged state (0.02 s) holds held(b, 4.98) at
  // the last tick of a 5 s episode, 5 s, and not before.
  auto hold = held(converged(b), 4.98);
  b->next = Gamma::kConv;
  std::vector<int> holding;
  for (int tick = 1; tick <= 250; ++tick)
    if (hold->holds(at_tick(uint64_t(tick), tick * 0.02))) holding.push_back(tick);
  CHECK(holding == std::vector<int>{250});
}

// Found by a probe: roger.all{} as a stage's absorbing state passed roger check (every episode would
// have succeeded at its first tick), where roger.any{}, which never holds, was refused.
TEST_CASE("always_holds tells an all of no parts, and an all or any that rests on one alone", "[predicate]") {
  auto a = std::make_shared<Scripted>("a");
  CHECK(all_of({})->always_holds());
  CHECK(all_of({all_of({}), all_of({})})->always_holds());
  CHECK(any_of({converged(a), all_of({})})->always_holds());
  CHECK_FALSE(any_of({})->always_holds());
  CHECK_FALSE(all_of({all_of({}), converged(a)})->always_holds());
  CHECK_FALSE(converged(a)->always_holds());
  CHECK_FALSE(held(all_of({}), 1.0)->always_holds());  // holds only after its second
  CHECK_FALSE(negate(all_of({}))->always_holds());
}

TEST_CASE("sorted() judges every colour with a region, sorted(colour) one of them", "[predicate]") {
  const Colour red{220, 30, 30}, blue{40, 80, 220}, grey{128, 128, 128};
  WorldModel model;
  WorldSpec& spec = model.spec;
  spec.goals.resize(2);
  spec.goals[0].colour = red;
  spec.goals[1].colour = blue;
  std::vector<MapObject> objects(4);
  objects[0].colour = red, objects[0].region = 0;   // red, in the red region
  objects[1].colour = blue, objects[1].region = 0;  // blue, in the red region: not sorted
  objects[2].colour = blue, objects[2].region = 1;  // blue, in the blue region
  objects[3].colour = grey;                         // no region has its colour: not counted
  ControlInput in = at_tick(1, 0.02);
  in.model = &model;
  in.objects = &objects;
  const SortCount all = sorted_objects(in), reds = sorted_objects(in, &red), blues = sorted_objects(in, &blue);
  CHECK(all.sortable == 3);
  CHECK(all.sorted == 2);
  CHECK(reds.sortable == 1);
  CHECK(reds.sorted == 1);
  CHECK(blues.sortable == 2);
  CHECK(blues.sorted == 1);
  CHECK_FALSE(sorted()->holds(in));
  CHECK(sorted(red)->holds(in));
  CHECK_FALSE(sorted(blue)->holds(in));
  CHECK_THROWS_WITH(sorted(grey)->holds(in), Catch::Contains("no goal region has the colour #808080"));
  CHECK(sorted(blue)->describe() == "sorted(\"#2850dc\")");
  // Held in the hand, an object in its region is not yet sorted.
  objects[0].held = true;
  ControlInput later = at_tick(2, 0.04);
  later.model = &model;
  later.objects = &objects;
  CHECK_FALSE(sorted(red)->holds(later));
  objects[1].region = 1;
  objects[0].held = false;
  CHECK(sorted()->holds(later));
}

TEST_CASE("sorted() is an error in a world with objects none of which has a region of its colour", "[predicate]") {
  const Colour red{220, 30, 30}, typo{220, 30, 31}, blue{40, 80, 220};
  WorldModel model;
  model.spec.goals.resize(2);
  model.spec.goals[0].name = "circle", model.spec.goals[0].colour = typo;
  model.spec.goals[1].name = "triangle", model.spec.goals[1].colour = blue;
  std::vector<MapObject> objects;
  ControlInput in = at_tick(1, 0.02);
  in.model = &model;
  in.objects = &objects;
  // No objects at all: nothing to sort, and no error.
  CHECK(sorted()->holds(in));
  CHECK(sorted(red)->holds(in));
  objects.resize(2);
  objects[0].colour = red, objects[1].colour = red;
  const std::string listing =
      "(objects: #dc1e1e x 2; goal regions: circle #dc1e1f, triangle #2850dc); roger.sorted matches an object to "
      "the region of its exact colour";
  CHECK_THROWS_WITH(sorted()->holds(in), Catch::Contains("roger.sorted(): none of the world's 2 objects has the colour "
                                                         "of a goal region, so it would hold for ever " + listing));
  CHECK_THROWS_WITH(sorted(blue)->holds(in), Catch::Contains("none of the world's 2 objects") && Catch::Contains(listing));
  CHECK_THROWS_WITH(sorted(red)->holds(in), Catch::Contains("roger.sorted(\"#dc1e1e\"): no goal region has the colour #dc1e1e"));
  // One object counted: a type absent from the world (blue) is sorted, as before.
  objects[1].colour = typo;
  CHECK_FALSE(sorted()->holds(in));
  CHECK(sorted(blue)->holds(in));
}

TEST_CASE("duplicate copies a predicate and its controllers once each, with their own state", "[predicate]") {
  auto a = std::make_shared<Scripted>("a");
  auto p = all_of({converged(a), held(gamma_is(a, Gamma::kConv), 0.04)});
  Duplicates done;
  const PredicatePtr q = duplicate(p, done);
  REQUIRE(q != p);
  CHECK(q->describe() == p->describe());
  std::vector<const Controller*> read;
  q->controllers(read);
  REQUIRE(read.size() == 2);
  CHECK(read[0] == read[1]);  // `a` read twice: one copy, shared as the original is
  CHECK(read[0] != a.get());
  CHECK(done.controllers.size() == 1);
  // The copy keeps its own hold timer and its own controller.
  a->next = Gamma::kConv;
  for (uint64_t t = 0; t < 3; ++t) CHECK(p->holds(at_tick(t, 0.02 * double(t))) == (t == 2));
  CHECK(a->evaluations == 3);
  CHECK_FALSE(q->holds(at_tick(3, 0.06)));  // its copy of `a` still says !CONV, as `a` did when copied
  CHECK(a->evaluations == 3);
}

TEST_CASE("a judge asks the predicate itself without truth and copies of it on the truth", "[predicate]") {
  auto a = std::make_shared<Scripted>("a");
  auto p = converged(a);
  Judge judge(p.get());
  judge.reset(1);
  ControlInput in = at_tick(0, 0.0);
  a->next = Gamma::kConv;
  CHECK(judge.holds(in));  // no truth: the predicate itself
  CHECK(a->evaluations == 1);
  // With the true tick given, the judge evaluates copies: the original is not asked again, and
  // what the actions' controller says next does not reach the copy.
  ControlInput truth = at_tick(1, 0.02);
  in = at_tick(1, 0.02);
  in.truth = &truth;
  CHECK(judge.holds(in));
  a->next = Gamma::kNoRef;
  in.tick = truth.tick = 2;
  CHECK(judge.holds(in));
  CHECK(a->evaluations == 1);
  CHECK_FALSE(p->holds(in));
  CHECK_FALSE(Judge().holds(in));  // no predicate: never done
}
