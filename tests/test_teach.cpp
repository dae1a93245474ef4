// Tests of the teachers (engine/teach, docs/curricula.md "Teachers"): task spaces, each teacher
// against a simulated learner whose answer is known, the Gaussian mixtures ALP-GMM fits; then the
// teachers in real stages through the trainer (tests/scripts/teach_*.lua): where each samples,
// what is recorded, determinism across --jobs, and bad input refused at file:line.
#include <catch2/catch.hpp>

#include <unistd.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "batch/trainer.h"
#include "core/error.h"
#include "script/curriculum/curriculum.h"
#include "temp_dir.h"
#include "core/rng.h"
#include "teach/teach.h"
#include "teach/teach_internal.h"

using namespace roger;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

namespace {

TaskDim int_dim(const std::string& name, int lo, int hi) {
  TaskDim d;
  d.name = name, d.kind = TaskDim::Kind::kInt, d.lo = lo, d.hi = hi;
  return d;
}
TaskDim real_dim(const std::string& name, double lo, double hi) {
  TaskDim d;
  d.name = name, d.kind = TaskDim::Kind::kReal, d.lo = lo, d.hi = hi;
  return d;
}
TaskDim choice_dim(const std::string& name, std::vector<std::string> choices) {
  TaskDim d;
  d.name = name, d.kind = TaskDim::Kind::kChoice, d.choices = std::move(choices);
  return d;
}

// The paper's two worlds as one space: obstacles 0-6, the four shapes, near and far starts.
TaskSpace paper_space() {
  return TaskSpace({int_dim("obstacles", 0, 6), choice_dim("shape", {"circle", "triangle", "pentagon", "spade"}),
                    real_dim("robot_distance", 0.8, 2.0)});
}

TaskOutcome outcome(const TaskPick& p, bool success, double td = 0.0, uint64_t seed = 0) {
  TaskOutcome o;
  o.task = p.task;
  o.world_seed = p.world_seed.value_or(seed);
  o.success = success;
  o.reward = success ? 100 : -100;
  o.td_error = td;
  return o;
}

// Outcomes whose success rate follows p exactly (error diffusion): every window's rate is the
// mean of p over it, so a test can say when the curve rose and when it stopped.
struct ExactLearner {
  double carry = 0.0;
  bool operator()(double p) {
    carry += p;
    if (carry >= 1.0 - 1e-12) {
      carry -= 1.0;
      return true;
    }
    return false;
  }
};

}  // namespace

TEST_CASE("a task space samples every task alike and maps onto the unit cube", "[teach]") {
  const TaskSpace s = paper_space();
  REQUIRE(s.size() == 3);
  CHECK(s.dims()[0].name == "obstacles");  // sorted by name
  CHECK(s.dims()[1].name == "robot_distance");
  CHECK(s.describe() == "obstacles = roger.int(0, 6), robot_distance = roger.real(0.8, 2), "
                        "shape = roger.choice{circle, triangle, pentagon, spade}");
  Rng rng(7);
  std::map<int, int> obstacles;
  std::map<int, int> shapes;
  double lo = 10, hi = -10;
  for (int i = 0; i < 28000; ++i) {
    const TaskPoint t = s.sample(rng);
    ++obstacles[int(t[0])];
    ++shapes[int(t[2])];
    lo = std::min(lo, t[1]), hi = std::max(hi, t[1]);
    // The unit cube and back give the same task; a discrete value sits at its slice's centre.
    CHECK(s.from_unit(s.to_unit(t)) == t);
  }
  REQUIRE(obstacles.size() == 7);
  for (const auto& [k, n] : obstacles) CHECK(std::abs(n - 4000) < 300);  // 7 values alike (sd 59)
  for (const auto& [k, n] : shapes) CHECK(std::abs(n - 7000) < 400);     // 4 shapes alike (sd 72)
  CHECK(lo >= 0.8);
  CHECK(hi < 2.0);
  CHECK(lo < 0.81);
  CHECK(hi > 1.99);
  CHECK(s.to_unit({0, 0.8, 0})[0] == Approx(0.5 / 7));
  CHECK(s.from_unit({1.0, 1.0, 1.0}) == TaskPoint{6, 2.0, 3});  // the cube's far corner is the last value

  const TaskPoint t{3, 1.25, 3};
  CHECK(s.params(t) == ParamList{{"obstacles", "3"}, {"robot_distance", "1.25"}, {"shape", "spade"}});
  CHECK(s.to_json(t).dump() == R"({"obstacles":3,"robot_distance":1.25,"shape":"spade"})");
  CHECK(s.task_of(s.params(t)) == t);

  // A choice's values recorded as the Lua values they are (found by a probe: roger.choice{0, 200}
  // was recorded as "0" and "200", where an int axis records numbers).
  TaskDim gap{"gap", TaskDim::Kind::kChoice, 0, 0, {"0", "200", "0.25"}}, lit{"lit", TaskDim::Kind::kChoice, 0, 0, {"true", "false"}};
  const TaskSpace typed({gap, lit, TaskDim{"shape", TaskDim::Kind::kChoice, 0, 0, {"circle", "2x", "007", "1e3"}}});
  CHECK(typed.to_json({1, 0, 0}).dump() == R"({"gap":200,"lit":"true","shape":"circle"})");
  CHECK(typed.to_json({2, 1, 1}).dump() == R"({"gap":0.25,"lit":"false","shape":"2x"})");
  CHECK(typed.to_json({0, 0, 2}).dump() == R"({"gap":0,"lit":"true","shape":"007"})");  // names, not numbers
  CHECK(typed.to_json({0, 0, 3}).dump() == R"({"gap":0,"lit":"true","shape":"1e3"})");
  CHECK(typed.task_of(typed.params({2, 1, 1})) == TaskPoint{2, 1, 1});
}

TEST_CASE("a task space names what it allows when a value lies outside it", "[teach]") {
  const TaskSpace s = paper_space();
  std::string why;
  CHECK_FALSE(s.value_of(0, "7", &why));
  CHECK(why == "an integer in roger.int(0, 6)");
  CHECK_FALSE(s.value_of(0, "2.5", &why));
  CHECK(s.value_of(0, "2") == 2.0);
  CHECK_FALSE(s.value_of(2, "square", &why));
  CHECK(why == "a value of roger.choice{circle, triangle, pentagon, spade}");
  CHECK_FALSE(s.task_of({{"obstacles", "9"}, {"robot_distance", "1"}, {"shape", "spade"}}, &why));
  CHECK(why == "obstacles = 9 is outside the task space: obstacles takes an integer in roger.int(0, 6)");
  // Found by a probe: a choice in another case had no suggestion.
  CHECK_FALSE(s.task_of({{"obstacles", "1"}, {"robot_distance", "1"}, {"shape", "Spade"}}, &why));
  CHECK(why == "shape = Spade is outside the task space (did you mean 'spade'?): shape takes a value of "
               "roger.choice{circle, triangle, pentagon, spade}");
  CHECK_FALSE(s.task_of({{"obstacles", "1"}, {"shape", "spade"}}, &why));
  CHECK(why == "no value for 'robot_distance' (roger.real(0.8, 2))");
  CHECK_FALSE(s.task_of({{"mass", "1"}}, &why));
  CHECK_THAT(why, Contains("'mass' is not a parameter of the task space"));

  CHECK_THROWS_WITH(TaskSpace({int_dim("obstacles", 4, 2)}), Contains("reversed"));
  CHECK_THROWS_WITH(TaskSpace({real_dim("d", 1, 1)}), Contains("a single value"));
  CHECK_THROWS_WITH(TaskSpace({choice_dim("shape", {})}), Contains("at least one value"));
  CHECK_THROWS_WITH(TaskSpace({int_dim("a", 0, 1), int_dim("a", 0, 2)}), Contains("two axes"));

  // Restrictions (the steps of a sequence) must lie inside the space.
  const TaskSpace easy = restrict_space(s, {int_dim("obstacles", 0, 0), choice_dim("shape", {"circle"})});
  Rng rng(1);
  for (int i = 0; i < 50; ++i) {
    const TaskPoint t = *s.task_of(easy.params(easy.sample(rng)));
    CHECK(t[0] == 0);
    CHECK(t[2] == 0);
  }
  CHECK_THROWS_WITH(restrict_space(s, {int_dim("obstacles", 0, 9)}),
                    Contains("obstacles = roger.int(0, 9) is outside the task space's roger.int(0, 6)"));
  CHECK_THROWS_WITH(restrict_space(s, {choice_dim("shape", {"square"})}),
                    Contains("shape = square is outside the task space: shape takes a value of"));
  // A single value over an int axis that is no integer says so, not "outside".
  CHECK_THROWS_WITH(restrict_space(s, {choice_dim("obstacles", {"2.5"})}),
                    Contains("obstacles = 2.5 is outside the task space: obstacles takes an integer in roger.int(0, 6)"));
  CHECK_THROWS_WITH(restrict_space(s, {real_dim("obstacles", 1, 2)}),
                    Contains("obstacles = roger.real(1, 2) is a real range, but obstacles takes an integer in roger.int(0, 6)"));
  CHECK_THROWS_WITH(restrict_space(s, {int_dim("mass", 0, 1)}), Contains("nor a parameter of the task space"));
}

TEST_CASE("every teacher draws the same tasks from the same seed and outcomes, others from another", "[teach]") {
  const TaskSpace s = paper_space();
  std::vector<TeacherSpec> specs(5);
  specs[0].kind = TeacherSpec::Kind::kRandom;
  specs[1].kind = TeacherSpec::Kind::kSequence;
  specs[1].steps = {{{int_dim("obstacles", 0, 0)}, 0.5, -1, 10}, {{}, 0.9, 0.2, 10}};
  specs[2].kind = TeacherSpec::Kind::kLcas;
  specs[2].lift = "obstacles", specs[2].levels = {"0", "3", "6"}, specs[2].window = 10;
  specs[3].kind = TeacherSpec::Kind::kAlpGmm;
  specs[3].fit_every = 20;
  specs[4].kind = TeacherSpec::Kind::kPlr;
  for (const TeacherSpec& spec : specs) {
    auto run = [&](uint64_t seed) {
      auto t = make_teacher(spec, s, seed);
      std::vector<double> trace;
      for (int e = 0; e < 200; ++e) {
        const TaskPick p = t->next();
        trace.insert(trace.end(), p.task.begin(), p.task.end());
        trace.push_back(double(p.world_seed.value_or(0)));
        // A learner better on fewer obstacles and nearer starts.
        const bool ok = (e * 7919 % 100) < 90 - 12 * p.task[0] - 20 * (p.task[1] - 0.8);
        t->record(outcome(p, ok, 1.0 + p.task[0], 1000 + uint64_t(e)));
      }
      return std::make_pair(trace, t->state().dump());
    };
    INFO(spec.name());
    CHECK(run(5) == run(5));
    CHECK(run(5).first != run(6).first);
  }
}

TEST_CASE("sequence promotes at its threshold over a full window, and demotes below its own", "[teach]") {
  const TaskSpace s = paper_space();
  TeacherSpec spec;
  spec.kind = TeacherSpec::Kind::kSequence;
  // Unobstructed first, then up to 3 obstacles, then the whole space.
  spec.steps = {{{int_dim("obstacles", 0, 0)}, 0.8, -1, 10},
                {{int_dim("obstacles", 0, 3)}, 0.8, 0.3, 10},
                {{}, 0.9, 0.3, 10}};
  auto t = make_teacher(spec, s, 3);
  auto step = [&] { return t->state()["step"].get<int>(); };
  auto play = [&](bool ok) {
    const TaskPick p = t->next();
    t->record(outcome(p, ok));
    return p;
  };
  // 7 of 10 is below 0.8: no promotion however long it goes on.
  for (int e = 0; e < 50; ++e) {
    const TaskPick p = play(e % 10 < 7);
    CHECK(p.task[0] == 0);
  }
  CHECK(step() == 1);
  // A window of 8 of 10: promoted at that very episode, not before the window is full.
  for (int e = 0; e < 10; ++e) play(true);  // the last 10 are all successes: promoted
  CHECK(step() == 2);
  CHECK(t->state()["moves"].size() == 1);
  CHECK(t->state()["moves"][0]["episode"] == 58);  // the last 10 hold 8 successes from the 58th episode
  // Step 2 draws 0-3 obstacles; a window at 2 of 10 (< 0.3) sends it back, not a fuller one.
  std::set<int> seen;
  for (int e = 0; e < 9; ++e) seen.insert(int(play(e < 3).task[0]));
  CHECK(step() == 2);  // 9 episodes: the window is not full yet
  for (int v : seen) CHECK(v <= 3);
  play(false);  // 3 of 10: not below 0.3
  CHECK(step() == 2);
  play(false);  // 2 of 10
  CHECK(step() == 1);
  CHECK(t->state()["moves"][1]["to"] == 1);
}

TEST_CASE("LCAS lifts only once the success curve has saturated, never while it rises", "[teach]") {
  const TaskSpace s = paper_space();
  TeacherSpec spec;
  spec.kind = TeacherSpec::Kind::kLcas;
  spec.lift = "eye_pixels";  // outside the space: set beside each task
  spec.levels = {"32", "64", "128"};
  spec.window = 50;
  spec.slope = 0.05;
  auto t = make_teacher(spec, s, 11);
  CHECK(t->test_params() == ParamList{{"eye_pixels", "128"}});
  ExactLearner learner;
  // Level 1: the rate rises 0 -> 0.9 over 400 episodes (0.1125 per window), then stays.
  int lifted_at = -1;
  for (int e = 0; e < 800 && lifted_at < 0; ++e) {
    const TaskPick p = t->next();
    REQUIRE(p.extra == ParamList{{"eye_pixels", "32"}});
    t->record(outcome(p, learner(std::min(0.9, 0.9 * e / 400.0))));
    if (t->state()["level"] == 2) lifted_at = e;
  }
  // Not while it rose (gain 0.1125 per window >= 0.05); within two windows of its plateau.
  CHECK(lifted_at >= 400);
  CHECK(lifted_at < 500);
  // Level 2: a slower rise, 0.1 per window (0.06 at least, with the rounding to whole successes),
  // for 450 episodes: never lifted.
  for (int e = 0; e < 450; ++e) {
    const TaskPick p = t->next();
    REQUIRE(p.extra == ParamList{{"eye_pixels", "64"}});
    t->record(outcome(p, learner(0.002 * e)));
  }
  CHECK(t->state()["level"] == 2);
  // A lifted axis of the space is held at its level while the others vary.
  TeacherSpec in_space = spec;
  in_space.lift = "obstacles";
  in_space.levels = {"0", "3", "6"};
  auto u = make_teacher(in_space, s, 11);
  CHECK(u->test_params().empty());
  std::set<int> shapes;
  for (int e = 0; e < 60; ++e) {
    const TaskPick p = u->next();
    CHECK(p.task[0] == 0);
    CHECK(p.extra.empty());
    shapes.insert(int(p.task[2]));
    u->record(outcome(p, true));
  }
  CHECK(shapes.size() == 4);
  in_space.levels = {"0", "9"};
  CHECK_THROWS_WITH(make_teacher(in_space, s, 1), Contains("obstacles = 9 is outside the task space"));
}

// Found by a probe: with window 10 and slope 0.1, a gain of one success in ten (0.5 after 0.4) read
// as 0.09999999999999998, below the slope, and lifted; the rule says a gain less than the slope.
// The gain is counted in successes, so one in ten is 0.1 exactly, and only a flat curve lifts.
TEST_CASE("LCAS compares a gain of whole successes with its slope exactly", "[teach]") {
  const TaskSpace s = paper_space();
  TeacherSpec spec;
  spec.kind = TeacherSpec::Kind::kLcas;
  spec.lift = "eye_pixels";
  spec.levels = {"32", "64"};
  spec.window = 10;
  spec.slope = 0.1;
  auto play_windows = [&](const std::vector<int>& successes) {
    auto t = make_teacher(spec, s, 2);
    for (int wins : successes)
      for (int e = 0; e < 10; ++e) t->record(outcome(t->next(), e < wins));
    return t->state();
  };
  // 4 then 5 of 10, 9 then 10 of 10, 0 then 1: each a gain of exactly the slope, not less.
  for (const auto& pair : std::vector<std::vector<int>>{{4, 5}, {9, 10}, {0, 1}, {2, 3}, {6, 7}}) {
    INFO(pair[0] << " then " << pair[1]);
    CHECK(play_windows(pair)["level"] == 1);
  }
  // No gain: lifted, and the gain it records is the exact 0.
  const nlohmann::json flat = play_windows({5, 5});
  CHECK(flat["level"] == 2);
  CHECK(flat["lifts"][0]["gain"].get<double>() == 0.0);
  CHECK(flat["lifts"][0]["rate"].get<double>() == 0.5);
}

TEST_CASE("LCAS with a floor waits out a curve flat at zero; without one it lifts at the first chance", "[teach]") {
  const TaskSpace s = paper_space();
  TeacherSpec spec;
  spec.kind = TeacherSpec::Kind::kLcas;
  spec.lift = "eye_pixels";
  spec.levels = {"32", "64"};
  spec.window = 20;
  spec.slope = 0.05;
  // Nothing succeeds for 200 episodes, then the rate climbs 0.025 per episode to 0.8 and stays.
  auto rate_at = [](int e) { return e < 200 ? 0.0 : std::min(0.8, 0.025 * (e - 200)); };
  auto lift_episode = [&](double floor) {
    spec.floor = floor;
    auto t = make_teacher(spec, s, 5);
    ExactLearner learner;
    for (int e = 0; e < 600; ++e) {
      const TaskPick p = t->next();
      t->record(outcome(p, learner(rate_at(e))));
      if (t->state()["level"] == 2) return e;
    }
    return -1;
  };
  // The slope rule alone: two flat windows of zeros are "saturated".
  CHECK(lift_episode(0.0) == 2 * spec.window - 1);
  // A floor of 0.5: not while flat at zero, not while rising (the rise reaches 0.5 at episode 220
  // and 0.8 at 232), but within two windows of the plateau.
  const int lifted = lift_episode(0.5);
  CHECK(lifted >= 232);
  CHECK(lifted < 232 + 2 * spec.window);
}

TEST_CASE("Gaussian mixtures recover separated clusters and AIC picks their number", "[teach]") {
  Rng rng(3);
  Eigen::MatrixXd x(300, 2);
  for (int i = 0; i < 300; ++i) {
    const bool a = i % 3 != 0;  // 200 around (0.2, 0.3), 100 around (0.8, 0.7)
    x(i, 0) = (a ? 0.2 : 0.8) + 0.03 * rng.normal();
    x(i, 1) = (a ? 0.3 : 0.7) + 0.03 * rng.normal();
  }
  Rng fit_rng(9);
  const teach_detail::Mixture m = teach_detail::best_mixture(x, 2, 6, fit_rng);
  REQUIRE(m.parts.size() == 2);
  std::vector<teach_detail::Gaussian> g = m.parts;
  std::sort(g.begin(), g.end(), [](const auto& a, const auto& b) { return a.mean[0] < b.mean[0]; });
  CHECK(g[0].mean[0] == Approx(0.2).margin(0.01));
  CHECK(g[0].mean[1] == Approx(0.3).margin(0.01));
  CHECK(g[1].mean[0] == Approx(0.8).margin(0.01));
  CHECK(g[0].weight == Approx(2.0 / 3).margin(0.01));
  // The covariance is the cluster's (0.03^2) plus the regularisation (1e-3).
  CHECK(g[0].cov(0, 0) == Approx(0.0009 + 0.001).margin(0.0003));
  // A draw from a component lies around its mean.
  double mean0 = 0.0;
  for (int i = 0; i < 2000; ++i) mean0 += teach_detail::sample_marginal(g[1], 1, fit_rng)[0] / 2000;
  CHECK(mean0 == Approx(0.8).margin(0.01));
}

// Found by a probe (fit_every = 2, history = 20): a component left with no point once its one point
// left the history stayed, weight 0 at the origin, fit after fit, since EM from a warm start never
// revives an empty component. Such a start is not taken: the fit starts afresh.
TEST_CASE("a warm start with an empty component fits afresh; one whose components all hold points is kept",
          "[teach]") {
  Rng rng(5);
  Eigen::MatrixXd x(40, 2);
  for (int i = 0; i < 40; ++i) {
    x(i, 0) = (i % 2 ? 0.2 : 0.8) + 0.02 * rng.normal();
    x(i, 1) = (i % 2 ? 0.3 : 0.7) + 0.02 * rng.normal();
  }
  Rng fit_rng(9);
  const teach_detail::Mixture good = teach_detail::fit_mixture(x, 2, fit_rng);
  teach_detail::Mixture dead = good;
  dead.parts[1].weight = 0.0;  // what a component whose points all left looks like
  dead.parts[1].mean.setZero();
  for (const teach_detail::Mixture* start : std::vector<const teach_detail::Mixture*>{&good, &dead}) {
    const teach_detail::Mixture m = teach_detail::fit_mixture(x, 2, fit_rng, start);
    for (const auto& g : m.parts) CHECK(g.weight == Approx(0.5).margin(0.01));
  }
  // Kept from a good start: EM has little left to do.
  CHECK(teach_detail::fit_mixture(x, 2, fit_rng, &good).iterations <= 2);
}

TEST_CASE("ALP-GMM samples the learnable band at least twice as often as random does", "[teach]") {
  // One axis, x in [0, 1]: below 0.4 the task is trivial (always succeeds), above 0.6 unlearnable
  // (never), between them a band where competence grows with practice there, up to 0.9. Random
  // samples the band 20% of the time; ALP-GMM, whose progress lives only in the band, samples it
  // at least twice as often over episodes 200 to 1000 (after its first four fits).
  const TaskSpace s({real_dim("x", 0, 1)});
  auto band_share = [&](TeacherSpec spec, uint64_t seed) {
    auto t = make_teacher(spec, s, seed);
    Rng world(seed + 100);
    double practice = 0.0;
    int in_band = 0;
    for (int e = 0; e < 1000; ++e) {
      const TaskPick p = t->next();
      const double x = p.task[0];
      const bool band = x >= 0.4 && x <= 0.6;
      const double competence = std::min(0.9, practice / 150.0);
      const bool ok = x < 0.4 || (band && world.uniform() < competence);
      if (band) practice += 1.0;
      if (e >= 200) in_band += band;
      t->record(outcome(p, ok));
    }
    return in_band / 800.0;
  };
  TeacherSpec random;
  TeacherSpec alp;
  alp.kind = TeacherSpec::Kind::kAlpGmm;
  alp.fit_every = 50;
  for (uint64_t seed : {1, 2, 3}) {
    const double r = band_share(random, seed), a = band_share(alp, seed);
    INFO("seed " << seed << ": random " << r << ", alp_gmm " << a);
    CHECK(r == Approx(0.2).margin(0.05));
    CHECK(a >= 2 * r);
  }
}

// Found by a probe: on int and choice axes an episode's progress was measured against the task's
// first try, so a task that failed once and succeeded ever since showed a progress of 1 for good.
TEST_CASE("ALP-GMM measures progress against the same task's last try", "[teach]") {
  const TaskSpace s({int_dim("obstacles", 0, 1)});
  TeacherSpec spec;
  spec.kind = TeacherSpec::Kind::kAlpGmm;
  spec.fit_every = 1000;  // no fit: the pairs alone
  auto t = make_teacher(spec, s, 1);
  TaskPick p;
  p.task = {0.0};
  t->record(outcome(p, false));  // its first try fails: progress 0 (none before it)
  t->record(outcome(p, true));   // then succeeds: progress 1
  for (int e = 0; e < 8; ++e) t->record(outcome(p, true));  // and goes on succeeding: 0 each
  CHECK(t->state()["mean_alp"] == Approx(0.1));  // 1 of the 10 pairs; against the first try, 0.9
}

TEST_CASE("PLR replays the levels with the highest scores", "[teach]") {
  // Each level's score is known: its task's x (a TD error that grows with x). PLR's replays, at
  // temperature 0.1, go to the top-ranked levels, but for the staleness share.
  const TaskSpace s({real_dim("x", 0, 1)});
  TeacherSpec spec;
  spec.kind = TeacherSpec::Kind::kPlr;
  auto t = make_teacher(spec, s, 4);
  std::vector<std::pair<double, uint64_t>> seen;  // (score, world seed) of every level played
  int replays = 0, top_replays = 0, new_levels = 0;
  for (int e = 0; e < 600; ++e) {
    const TaskPick p = t->next();
    const uint64_t world = p.world_seed.value_or(50000 + uint64_t(e));
    if (p.world_seed) {
      ++replays;
      // The replayed level is among the 3 highest scores of those seen.
      std::vector<double> scores;
      for (const auto& l : seen) scores.push_back(l.first);
      std::sort(scores.rbegin(), scores.rend());
      if (p.task[0] >= scores[std::min<size_t>(2, scores.size() - 1)]) ++top_replays;
      // A replay is the level's own task in its own world.
      const auto it = std::find_if(seen.begin(), seen.end(), [&](const auto& l) { return l.second == world; });
      REQUIRE(it != seen.end());
      CHECK(it->first == p.task[0]);
    } else {
      ++new_levels;
      seen.push_back({p.task[0], world});
    }
    t->record(outcome(p, false, p.task[0], world));
  }
  CHECK(replays == Approx(300).margin(40));  // replay = 0.5
  CHECK(double(top_replays) / replays >= 0.85);
  CHECK(t->state()["levels"] == new_levels);
  CHECK(t->state()["top"][0]["score"].get<double>() == Approx(std::max_element(seen.begin(), seen.end())->first));

  // With score = 1 - success, failed levels come back.
  spec.score_td = false;
  auto f = make_teacher(spec, s, 4);
  int replayed_failures = 0, replayed = 0;
  for (int e = 0; e < 400; ++e) {
    const TaskPick p = f->next();
    const bool ok = p.task[0] < 0.5;  // the upper half fails
    if (p.world_seed) ++replayed, replayed_failures += !ok;
    f->record(outcome(p, ok, 0.0, 90000 + uint64_t(e)));
  }
  CHECK(double(replayed_failures) / replayed >= 0.85);
}

TEST_CASE("ALP-GMM's fits cost milliseconds over a stage's budget", "[teach]") {
  // The teacher's work for 1500 episodes of the paper's 3-axis space, fits every 50 included:
  // the trainer records it per trial (teacher_wall_s); docs/curricula.md quotes both figures.
  const TaskSpace s = paper_space();
  TeacherSpec spec;
  spec.kind = TeacherSpec::Kind::kAlpGmm;
  auto t = make_teacher(spec, s, 2);
  const auto t0 = std::chrono::steady_clock::now();
  for (int e = 0; e < 1500; ++e) {
    const TaskPick p = t->next();
    t->record(outcome(p, (e * 31 % 100) < 100 - 14 * p.task[0]));
  }
  const double s_used = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CHECK(t->state()["fits"] == 30);
  WARN("ALP-GMM, 1500 episodes with 30 fits: " << s_used * 1000 << " ms");
}

// ---- the teachers in real stages: tests/scripts/teach_curriculum.lua over teach_reach.lua, whose
// `level` axis has a trivial part (< 0.4), a learnable band [0.4, 0.6] and an unreachable part.

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

std::vector<json> read_jsonl(const fs::path& p) {
  std::ifstream in(p);
  REQUIRE(in.good());
  std::vector<json> out;
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(json::parse(line));
  return out;
}

json read_json(const fs::path& p) {
  std::ifstream in(p);
  REQUIRE(in.good());
  return json::parse(in);
}

int run_shell(const std::string& line) {
  const int raw = std::system(line.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

// One trial of a stage of the teachers' curriculum, its episodes kept.
TrainResult train_reach(const std::string& stage, uint64_t seed) {
  TrainOptions o;
  o.curriculum = "tests/scripts/teach_curriculum.lua";
  o.stage = stage;
  o.context = "A";
  o.seed = seed;
  return train_stage(o);
}

bool in_band(const json& task) { return task["level"] >= 0.4 && task["level"] <= 0.6; }

// A file's text without its wall-clock figures (the machine's, not the engine's): every JSON field
// whose name holds "wall", and a CSV's wall_s column.
std::string without_wall(const std::string& text, bool csv) {
  if (!csv) return std::regex_replace(text, std::regex("\"[a-z_]*wall[a-z_]*\": ?[-0-9.e+]+"), "");
  std::istringstream in(text);
  std::string out, line;
  int wall = -1;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string c; std::getline(row, c, ',');) cells.push_back(c);
    if (wall < 0) wall = int(std::find(cells.begin(), cells.end(), "wall_s") - cells.begin());
    for (size_t i = 0; i < cells.size(); ++i)
      if (int(i) != wall) out += cells[i] + ",";
    out += "\n";
  }
  return out;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The teachers' batch (teach_batch.lua: one trial per teacher) run once for every test below.
struct TeachBatch {
  fs::path dir = fs::temp_directory_path() / ("roger_teach_batch_" + std::to_string(::getpid()));
  TeachBatch() {
    fs::remove_all(dir);
    REQUIRE(run_shell(std::string(ROGER_BINARY) + " run tests/scripts/teach_batch.lua --jobs 2 --out " + dir.string() +
                      " > /dev/null 2>&1") == 0);
  }
  ~TeachBatch() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

const fs::path& teach_batch() {
  static const TeachBatch batch;
  return batch.dir;
}

fs::path trial_of(const std::string& run) { return teach_batch() / "trials" / run / "A" / "000"; }

}  // namespace

TEST_CASE("in a real stage, ALP-GMM samples the learnable band at least twice as often as random", "[teach][stage]") {
  // Over episodes 100 to 300 of three trials each (the band is 20% of the space, what random
  // samples; ALP-GMM fits every 25 episodes, so by episode 100 it has fitted four times). Measured:
  // random 24%, 23.5%, 20%; ALP-GMM 45.5%, 71%, 53%.
  int random_band = 0, alp_band = 0, n = 0;
  for (uint64_t seed : {1, 2, 3}) {
    const TrainResult r = train_reach("Random", seed), a = train_reach("Alp", seed);
    for (size_t e = 100; e < 300; ++e, ++n) {
      random_band += in_band(r.episodes[e].task);
      alp_band += in_band(a.episodes[e].task);
    }
    // The mixture it ended with puts most of its progress on the band.
    const json& parts = a.teacher["state"]["components"];
    double alp_total = 0, alp_band_mass = 0;
    for (const auto& c : parts) {
      alp_total += c["alp"].get<double>();
      if (in_band(c["task"])) alp_band_mass += c["alp"].get<double>();
    }
    INFO("seed " << seed << ": " << parts.dump());
    CHECK(alp_band_mass > 0.5 * alp_total);
  }
  INFO("random " << random_band << ", alp_gmm " << alp_band << " band tasks of " << n);
  CHECK(double(random_band) / n == Approx(0.2).margin(0.05));
  CHECK(alp_band >= 2 * random_band);
}

TEST_CASE("in a real stage, PLR replays the levels with the highest scores", "[teach][stage]") {
  for (const std::string run : {"Plr", "PlrFail"}) {
    // Levels are (task, world seed); each episode's score is in its record (td_error), or 1 -
    // success for PlrFail. A replay is an episode in another episode's world.
    const std::vector<json> eps = read_jsonl(trial_of(run) / "episodes.jsonl");
    std::map<uint64_t, double> score;  // level (by world seed) -> its last score
    int replays = 0, top = 0;
    for (const json& e : eps) {
      const uint64_t seed = e["seed"];
      const double s = run == "Plr" ? e["td_error"].get<double>() : (e["success"] ? 0.0 : 1.0);
      if (score.count(seed)) {
        ++replays;
        std::vector<double> all;
        for (const auto& [k, v] : score) all.push_back(v);
        std::sort(all.rbegin(), all.rend());
        // Among the top 3 scores (ties count as the top), or a staleness draw (10%).
        top += score[seed] >= all[std::min<size_t>(2, all.size() - 1)];
      }
      score[seed] = s;
    }
    INFO(run << ": " << top << " of " << replays << " replays among the top 3 scores");
    CHECK(replays == Approx(150).margin(30));  // replay = 0.5
    CHECK(double(top) / replays >= 0.85);
  }
}

TEST_CASE("in a real stage, sequence promotes and demotes exactly at its thresholds", "[teach][stage]") {
  // Steps: level 0.1 (promote at 0.9 over 10), the band (promote at 0.8, demote below 0.2 over
  // 20), the whole space. Replaying the rule over the recorded outcomes gives the teacher's moves,
  // and every episode's task lies in its step.
  const std::vector<json> eps = read_jsonl(trial_of("Sequence") / "episodes.jsonl");
  const json moves = read_json(trial_of("Sequence") / "result.json")["teacher"]["state"]["moves"];
  const double promote[] = {0.9, 0.8, 1.0}, demote[] = {-1, 0.2, -1};
  const size_t window[] = {10, 20, 20};
  int step = 0;
  std::vector<bool> outcomes;
  json expected = json::array();
  for (size_t e = 0; e < eps.size(); ++e) {
    const double level = eps[e]["task"]["level"];
    if (step == 0) CHECK(level == 0.1);
    if (step == 1) CHECK((level >= 0.4 && level <= 0.6));
    outcomes.push_back(eps[e]["success"]);
    if (outcomes.size() < window[step]) continue;
    const double rate =
        std::count(outcomes.end() - long(window[step]), outcomes.end(), true) / double(window[step]);
    const int to = step < 2 && rate >= promote[step] ? step + 1 : demote[step] >= 0 && rate < demote[step] ? step - 1 : step;
    if (to == step) continue;
    expected.push_back({{"episode", e + 1}, {"from", step + 1}, {"to", to + 1}});
    step = to;
    outcomes.clear();
  }
  REQUIRE(moves.size() == expected.size());
  REQUIRE(moves.size() >= 2);  // it reached the whole space
  for (size_t k = 0; k < moves.size(); ++k) {
    CHECK(moves[k]["episode"] == expected[k]["episode"]);
    CHECK(moves[k]["to"] == expected[k]["to"]);
  }
}

TEST_CASE("in a real stage, LCAS lifts only after saturation and never before", "[teach][stage]") {
  // lift = {level = {0.1, 0.5, 0.9}}, window 20, slope 0.05: at each level, the teacher lifts at
  // the first episode where the last 20 succeeded less than 5 points more often than the 20
  // before, and at no episode before it.
  for (const std::string run : {"Lcas", "LiftOnly"}) {
    const std::vector<json> eps = read_jsonl(trial_of(run) / "episodes.jsonl");
    const json lifts = read_json(trial_of(run) / "result.json")["teacher"]["state"]["lifts"];
    REQUIRE(lifts.size() == 2);
    const std::string param = run == "Lcas" ? "level" : "distance";
    size_t start = 0;
    for (size_t k = 0; k <= lifts.size(); ++k) {
      const size_t end = k < lifts.size() ? lifts[k]["episode"].get<size_t>() : eps.size();
      for (size_t e = start; e < end; ++e) {
        const json& v = eps[e]["task"][param];
        CHECK((v.is_string() ? std::stod(v.get<std::string>()) : v.get<double>()) ==
              Approx(run == "Lcas" ? std::vector<double>{0.1, 0.5, 0.9}[k] : double(k)));
        if (k == lifts.size() || e + 1 < start + 40) continue;  // the last level, or fewer than two windows
        int last = 0, before = 0;
        for (size_t i = e + 1 - 20; i <= e; ++i) last += eps[i]["success"].get<bool>();
        for (size_t i = e + 1 - 40; i < e + 1 - 20; ++i) before += eps[i]["success"].get<bool>();
        const bool saturated = (last - before) / 20.0 < 0.05;
        INFO(run << " level " << k << ", episode " << e + 1);
        CHECK(saturated == (e + 1 == end));  // lifted at the first saturated episode, never before
      }
      start = end;
    }
  }
}

TEST_CASE("every teacher gives the same trial to the bit with --jobs 1 and --jobs 2", "[teach][stage]") {
  const fs::path one = fs::temp_directory_path() / ("roger_teach_jobs1_" + std::to_string(::getpid()));
  fs::remove_all(one);
  REQUIRE(run_shell(std::string(ROGER_BINARY) + " run tests/scripts/teach_batch.lua --jobs 1 --out " + one.string() +
                    " > /dev/null 2>&1") == 0);
  int compared = 0;
  for (const auto& entry : fs::recursive_directory_iterator(teach_batch() / "trials")) {
    if (!entry.is_regular_file()) continue;
    const fs::path rel = fs::relative(entry.path(), teach_batch());
    INFO(rel);
    REQUIRE(fs::exists(one / rel));
    const bool csv = rel.extension() == ".csv";
    CHECK(without_wall(slurp(entry.path()), csv) == without_wall(slurp(one / rel), csv));
    ++compared;
  }
  CHECK(compared == 8 * 7);  // 8 teachers, 7 files each
  fs::remove_all(one);
}

// ---- bad input: refused where it is written, naming the field and what is allowed

namespace {

// A curriculum whose one stage (over scenarios/cluttered.lua) gets `fields`, written on line 8.
fs::path write_stage(const fs::path& dir, const std::string& name, const std::string& fields) {
  const fs::path file = dir / (name + ".lua");
  std::ofstream(file) << "local p = { phi0 = roger.primitive(\"phi0\") }\n"
                         "local function stage(fields)\n"
                         "  local s = { name = \"S\", scenario = \"cluttered\", time_limit = 1, absorbing = roger.converged(p.phi0),\n"
                         "              budget = { episodes = 4 }, checkpoints = { every = 4 }, contexts = { { name = \"A\", actions = { p.phi0 } } } }\n"
                         "  for k, v in pairs(fields) do s[k] = v end\n"
                         "  return roger.stage(s)\n"
                         "end\n"
                         "return { stages = { stage(" << fields << ") } }\n";
  return file;
}

// A trial of write_stage's stage S in its context A.
TrainOptions stage_options(const fs::path& file) {
  TrainOptions o;
  o.curriculum = file.string();
  o.stage = "S";
  o.context = "A";
  return o;
}

// The message of loading a curriculum that must fail.
std::string load_error(const fs::path& file) {
  try {
    Curriculum::load(file.string());
  } catch (const std::exception& e) {
    return e.what();
  }
  FAIL("loaded " << file << " without an error");
  return "";
}

}  // namespace

// Found by a probe: a context fixing the parameter an LCAS teacher lifts was said at the teacher's
// line, where a context's mistakes are said at the context's.
TEST_CASE("a context fixing what the teacher varies is refused at the context's line", "[teach][errors]") {
  test::TempDir dir("roger_teach_context_line");
  const fs::path file = dir.path / "ctx.lua";
  std::ofstream(file) << "local p = require('lib.skills').primitives()\n"
                         "return { name = 't', stages = { roger.stage{ name = 'S', scenario = 'cluttered', time_limit = 4,\n"
                         "  absorbing = roger.converged(p.phi0), budget = { episodes = 30 }, checkpoints = { every = 10 },\n"
                         "  teacher = roger.teacher.lcas{ lift = { eye_pixels = { 16, 32 } }, window = 5 },\n"
                         "  contexts = {\n"
                         "    { name = 'A', actions = { p.search, p.phi0 } },\n"
                         "    { name = 'B', actions = { p.search, p.phi0 }, params = { eye_pixels = 32 } },\n"
                         "  } } } }\n";
  CHECK_THAT(load_error(file), StartsWith(file.string() + ":7: stage 'S', context 'B': the context's params fix "
                                          "'eye_pixels', which roger.teacher.lcas (" + file.string() + ":4) varies"));
}

// Found by a probe: roger.int(1, 5) over a parameter of choices 1, 3, 5 passed (its ends are
// choices) and training failed at a 2 with no file or stage; a boolean took roger.choice{0, 1} and
// {"yes", "no"} as --set's text, and a teacher returning false was then outside the space; a
// number's choice "two" was told to lose its quotes.
TEST_CASE("a task axis takes the values its parameter takes, said at the axis's line", "[teach][errors]") {
  test::TempDir dir("roger_teach_axis_values");
  std::ofstream(dir.path / "odd.lua") << "return { params = { level = { default = 3, choices = { 1, 3, 5 } },\n"
                                         "    flag = { default = false }, count = { default = 1 },\n"
                                         "    eyes = { default = '', choices = { 'left', 'right' }, list = true } },\n"
                                         "  generate = function(world, rng, p)\n"
                                         "    world:robot{ x = 0, y = 0, heading = p.level + p.count + (p.flag and 1 or 0) +\n"
                                         "      #p.eyes }\n"
                                         "  end }\n";
  const auto error_of = [&](const std::string& tasks) {
    const fs::path file = dir.path / "axis.lua";
    std::ofstream(file) << "local p = require('lib.skills').primitives()\n"
                           "return { name = 't', stages = { roger.stage{ name = 'S', scenario = 'odd.lua', time_limit = 4,\n"
                           "  absorbing = roger.converged(p.phi0), budget = { episodes = 30 },\n"
                           "  tasks = " << tasks << ",\n"
                           "  contexts = { { name = 'A', actions = { p.search, p.phi0 } } } } } }\n";
    try {
      Curriculum::load(file.string());
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("loaded");
  };
  CHECK_THAT(error_of("{ level = roger.int(1, 5) }"),
             Contains("axis.lua:4: stage 'S': tasks.level = roger.int(1, 5): 'level' of scenario 'odd' takes only 1, 3, "
                      "5: vary it with roger.choice{1, 3, 5} (or some of them)"));
  CHECK_THAT(error_of("{ flag = roger.choice{ 0, 1 } }"),
             Contains("axis.lua:4: stage 'S': tasks.flag: roger.choice's value 1 is 0: parameter 'flag' of scenario "
                      "'odd' is a boolean: write roger.choice{true, false}"));
  CHECK_THAT(error_of("{ flag = roger.choice{ 'true', 'false' } }"),
             Contains("tasks.flag: roger.choice's value 1 is the string \"true\": parameter 'flag' of scenario 'odd' "
                      "is a boolean: write roger.choice{true, false}"));
  CHECK_THAT(error_of("{ count = roger.choice{ 1, 'two' } }"),
             Catch::Matchers::EndsWith("roger.choice's value 2 is the string \"two\": parameter 'count' of scenario 'odd' takes a "
                      "number"));
  // A list's choices are sets: the same items in another order are the same worlds.
  CHECK_THAT(error_of("{ eyes = roger.choice{ 'left,right', '', 'right, left' } }"),
             Contains("tasks.eyes: roger.choice's values 1 and 3 (\"left,right\" and \"right, left\") list the same items "
                      "of 'eyes', which build the same worlds: give each set once"));
  CHECK(error_of("{ level = roger.choice{ 1, 5 }, flag = roger.choice{ true, false }, count = roger.int(1, 3),\n"
                 "  eyes = roger.choice{ '', 'left', 'left,right' } }") == "loaded");
}

TEST_CASE("a bad task space or teacher is refused at load with file:line, the field and what is allowed",
          "[teach][errors]") {
  test::TempDir dir("roger_teach_bad");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{ tasks = { obstacle = roger.int(0, 6) } }",
       ":8: stage 'S': tasks.obstacle = roger.int(0, 6): scenario 'cluttered' (scenarios/cluttered.lua) has no "
       "parameter 'obstacle' (did you mean 'obstacles'?); known parameters: "},
      {"{ tasks = { obstacles = roger.int(5, 2) } }", ":8: roger.int(5, 2): the range is reversed (lo must be below hi"},
      {"{ tasks = { mass = roger.real(1, 1) } }", ":8: roger.real(1, 1): the range is a single value"},
      {"{ tasks = { shape = roger.choice{} } }", ":8: roger.choice{...}: the list is empty"},
      // Found by a probe: one value was refused of roger.real alone.
      {"{ tasks = { obstacles = roger.int(2, 2) } }",
       ":8: roger.int(2, 2): the range is a single value (lo must be below hi; a single value needs no axis: give the value itself, in params or in a teacher's step)"},
      // Found by a probe: math.maxinteger became 2^63 as a double, drawn out of range.
      {"{ tasks = { obstacles = roger.int(0, math.maxinteger) } }",
       ":8: roger.int(lo, hi): hi must lie within -2^53..2^53 (-9007199254740992..9007199254740992), got "
       "9223372036854775807"},
      // Found by a probe: 2^53 + 1 became 2^53 as a double, and passed.
      {"{ tasks = { obstacles = roger.int(0, 9007199254740993) } }",
       ":8: roger.int(lo, hi): hi must lie within -2^53..2^53 (-9007199254740992..9007199254740992), got "
       "9007199254740993"},
      {"{ tasks = { shape = roger.choice{ 'circle' } } }",
       ":8: roger.choice{circle}: one value (a single value needs no axis: give the value itself, in params or in a teacher's step); give at least two"},
      // Found by a probe: a key beside the levels was dropped without a word, and a negative test
      // seed became 2^64 - 1.
      {"{ teacher = roger.teacher.lcas{ lift = { eye_pixels = { 32, 64, x = 1 } } } }",
       ":8: roger.teacher.lcas: lift.eye_pixels must be a plain list of levels, the most constrained first, got the "
       "key 'x'"},
      // Found by a probe: "[20, 100000]" did not say that its lower end is k_max.
      {"{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.alp_gmm{ k_max = 8, history = 5 } }",
       "roger.teacher.alp_gmm: field 'history' must be an integer in [8, 100000] (at least k_max = 8: one episode per "
       "component), got 5"},
      // Found by a probe: a task axis given as the teacher read "got a userdata".
      {"{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.int(0, 3) }",
       "field 'teacher' is the task axis roger.int(0, 3), not a teacher: an axis goes in 'tasks'"},
      // Found by a probe: {"1", "01", "1e0"} over a number parameter were three slices of one world.
      {"{ tasks = { obstacles = roger.choice{ 1, '01' } } }",
       "stage 'S': tasks.obstacles: roger.choice's value 2 is the string \"01\": parameter 'obstacles' of scenario "
       "'cluttered' takes a number: write 01 without quotes"},
      // Found by a probe: a test list's task after a hole, or under a name, was left out unsaid.
      {"{ tasks = { obstacles = roger.int(0, 3) }, test = { list = { { obstacles = 1 }, [3] = { obstacles = 2 } } } }",
       "stage 'S': test: field 'list' must be a list of tasks {{param = value, ...}, ...}, got the key [3]"},
      {"{ tasks = { obstacles = roger.int(0, 3) }, test = { list = { { obstacles = 1 }, x = { obstacles = 2 } } } }",
       "stage 'S': test: field 'list' must be a list of tasks {{param = value, ...}, ...}, got the key 'x'"},
      {"{ tasks = { obstacles = roger.int(0, 3) }, test = { tasks = 5, seed = -1 } }",
       ":6: stage 'S': test: field 'seed' must be a non-negative integer, got -1"},
      {"{ tasks = { obstacles = roger.int(0, 20) } }",
       ":8: stage 'S': tasks.obstacles = roger.int(0, 20): parameter 'obstacles' of scenario 'cluttered' expects an "
       "integer in [0, 8], got '20'"},
      {"{ tasks = { shape = roger.choice{\"circle\", \"square\"} } }",
       ":8: stage 'S': tasks.shape = roger.choice{circle, square}: parameter 'shape' of scenario 'cluttered' expects "
       "one of circle, pentagon, spade, triangle, got 'square'"},
      {"{ tasks = { obstacles = roger.real(0, 3) } }", "'obstacles' is an integer parameter of scenario 'cluttered': use roger.int"},
      {"{ tasks = { obstacles = 3 } }",
       ":6: stage 'S': tasks.obstacles must be roger.int(lo, hi), roger.real(lo, hi) or roger.choice{...}, got number 3"},
      {"{ tasks = { obstacles = roger.int(0, 3) }, params = { obstacles = 2 } }",
       ":8: stage 'S': tasks.obstacles = roger.int(0, 3) varies 'obstacles', which the stage's params fix"},
      {"{ tasks = { obstacles = roger.int(0, 3) }, contexts = { { name = 'A', actions = { 'phi0' }, params = { obstacles = 1 } } } }",
       "stage 'S', context 'A': the context's params fix 'obstacles', which tasks.obstacles = roger.int(0, 3) varies"},
      {"{ tasks = { obstacles = roger.int(0, 3) }, teacher = 3 }",
       ":6: stage 'S': field 'teacher' must be a teacher (roger.teacher.random{}, .sequence{...}, .lcas{...}, "
       ".alp_gmm{...}, .plr{...}) or a function(history, rng), got number 3"},
      {"{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.sequence{ { obstacles = 9 } } }",
       ":8: stage 'S': roger.teacher.sequence ("},
      // Found by a probe: 2.5 over an int axis was "outside the task space's roger.int(0, 3)", not why.
      {"{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.sequence{ { obstacles = 2.5 } } }",
       "step 1: obstacles = 2.5 is outside the task space: obstacles takes an integer in roger.int(0, 3)"},
      // Found by a probe: thresholds that can never act were accepted.
      {"{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.sequence{ { obstacles = 0, demote = 0.5 }, {} } }",
       ":8: roger.teacher.sequence: step 1: field 'demote' needs a step before it to go back to (the first step has none)"},
      {"{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.sequence{ { obstacles = 0 }, { promote = 0.5 } } }",
       ":8: roger.teacher.sequence: step 2: field 'promote' needs a step after it to go on to (the last step has none)"},
      // Found by a probe: a last step's demote was held below the default promote it never uses.
      {"{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.sequence{ { obstacles = 0 }, { obstacles = 1, demote = 0.95 }, {} } }",
       "step 2: field 'demote' (0.95) must be below 'promote' (0.9)"},
      {"{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.lcas{ lift = { obstacles = { 0, 20 } } } }",
       "the level obstacles = 20 is outside the task space: obstacles takes an integer in roger.int(0, 3)"},
      {"{ teacher = roger.teacher.lcas{ lift = { eye_pixels = { 32, 3 } } } }",
       ":8: stage 'S': roger.teacher.lcas: lift.eye_pixels: parameter 'eye_pixels' of scenario 'cluttered' expects an integer in [16, 512], got '3'"},
      // Found by a probe: a string level was taken, where a teacher function's string is refused.
      {"{ teacher = roger.teacher.lcas{ lift = { eye_pixels = { \"32\", 64 } } } }",
       ":8: stage 'S': roger.teacher.lcas: lift.eye_pixels[1] is the string \"32\": parameter 'eye_pixels' of "
       "scenario 'cluttered' takes a number: write 32 without quotes"},
      // Found by a probe: a sequence's step and a test list took obstacles = "1" as 1.
      {"{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.sequence{ { obstacles = \"1\" }, {} } }",
       ":8: stage 'S': roger.teacher.sequence: step 1: obstacles = \"1\" is a string, but obstacles takes a number "
       "(roger.int(0, 3)): write 1 without quotes"},
      {"{ tasks = { obstacles = roger.int(0, 3) }, test = { list = { { obstacles = 1 }, { obstacles = \"2\" } } } }",
       ":6: stage 'S': test: list[2]: obstacles = \"2\" is a string, but obstacles takes a number (roger.int(0, 3)): "
       "write 2 without quotes"},
      {"{ teacher = roger.teacher.lcas{ lift = { eye_pixels = { 32, 64 } }, floor = 1.5 } }",
       ":8: roger.teacher.lcas: field 'floor' must be in [0, 1], got 1.5"},
      // Found by a probe: lifts that never change the level trained as a stage with it fixed.
      {"{ teacher = roger.teacher.lcas{ lift = { eye_pixels = { 32 } } } }",
       ":8: roger.teacher.lcas: lift.eye_pixels = {32} has one level, so nothing is ever lifted: give two or more, "
       "the most constrained first (to hold eye_pixels at 32, set it in the stage's params instead)"},
      {"{ teacher = roger.teacher.lcas{ lift = { eye_pixels = { 32, 64, 32 } } } }",
       ":8: roger.teacher.lcas: lift.eye_pixels: the level 32 is listed twice (levels 1 and 3)"},
      // Found by a probe: a misspelt test task had no "did you mean", where a teacher's result has one;
      // and a context fixing the lifted parameter was told to use the --set that is refused in turn.
      {"{ tasks = { obstacles = roger.int(0, 3) }, test = { list = { { obstacls = 2 } } } }",
       ":6: stage 'S': test: list[1]: 'obstacls' is not a parameter of the task space (did you mean 'obstacles'?) "
       "(obstacles = roger.int(0, 3))"},
      {"{ teacher = roger.teacher.lcas{ lift = { eye_pixels = { 32, 64 } } }, contexts = { { name = 'A', actions = { "
       "'phi0' }, params = { eye_pixels = 32 } } } }",
       "the context's params fix 'eye_pixels', which roger.teacher.lcas (" },
      {"{ teacher = roger.teacher.lcas{ lift = { eye_pixels = { 32, 64 } } }, contexts = { { name = 'A', actions = { "
       "'phi0' }, params = { eye_pixels = 32 } } } }",
       "varies; the parameter lifted is the teacher's at every level, in every context, and --set cannot fix it either: "
       "remove it from the context's params, or give the context a stage without the lift"},
      {"{ tasks = { obstacles = roger.int(0, 3) }, test = { list = { { obstacles = 7 } } } }",
       ":6: stage 'S': test: list[1]: obstacles = 7 is outside the task space: obstacles takes an integer in roger.int(0, 3)"},
      {"{ tasks = { obstacles = roger.int(0, 3) }, test = { tasks = 10 }, checkpoints = { episodes = 5 } }",
       "checkpoints.episodes does not apply with a test set"},
      {"{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.alp_gmm{ k = 3 } }",
       ":8: roger.teacher.alp_gmm: unknown field 'k'; known fields: fit_every, history, k_max, random_share"},
      {"{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.plr{ score = 'loss' } }",
       "field 'score' must be \"td\" (the episode's mean |TD error|) or \"success\" (1 - success), got 'loss'"},
      {"{ teacher = roger.teacher.random{} }", "roger.teacher.random needs a task space"},
      // Found by a probe: "unknown field 'foo'; known fields: " with nothing after it.
      {"{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.random{ foo = 1 } }",
       ":8: roger.teacher.random{}: takes no fields (every task alike), got the field string 'foo'"},
      // Found by a probe: "must be a list of levels ..., got a table".
      {"{ teacher = roger.teacher.lcas{ lift = { eye_pixels = {} } } }",
       ":8: roger.teacher.lcas: lift.eye_pixels must be a list of levels, the most constrained first, got a table "
       "with no levels 1, 2, ... (an empty list)"},
      // Found by a probe: a table of named levels was "an empty list" too.
      {"{ teacher = roger.teacher.lcas{ lift = { eye_pixels = { a = 32, b = 64 } } } }",
       ":8: roger.teacher.lcas: lift.eye_pixels must be a list of levels, the most constrained first, got a table "
       "of named levels with no levels 1, 2, ... (write {32, 64}, not {a = 32})"},
      // Found by a probe: each said what was expected, not what it got.
      {"{ teacher = roger.teacher.lcas{ lift = { obstacles = { 0, 3 }, eye_pixels = { 32, 64 } } } }",
       ":8: roger.teacher.lcas: field 'lift' must name one parameter {param = {level 1, level 2, ...}}, got 2: "
       "eye_pixels, obstacles"},
      {"{ tasks = { obstacles = roger.int(0, 3) }, test = { list = {} } }",
       ":6: stage 'S': test: field 'list' must be a non-empty list of tasks {{param = value, ...}, ...}, got table (empty)"},
      {"{ tasks = { obstacles = roger.int(0, 3) }, test = { tasks = 'ten' } }",
       ":6: stage 'S': test: field 'tasks' must be an integer, got string 'ten'"},
  };
  for (size_t k = 0; k < cases.size(); ++k) {
    const fs::path file = write_stage(dir.path, "c" + std::to_string(k), cases[k].first);
    const std::string message = load_error(file);
    INFO(cases[k].first << "\n" << message);
    CHECK_THAT(message, Contains(cases[k].second));
    CHECK_THAT(message, Contains(file.filename().string() + ":"));  // every one names the file and line
  }
  // roger check also builds the worlds at the ends of a task space: Roger 6 m from the object does
  // not fit in the arena.
  const fs::path crowded = write_stage(dir.path, "crowded", "{ tasks = { robot_distance = roger.real(1, 6) } }");
  const std::vector<std::string> problems = check_curriculum(crowded.string());
  REQUIRE(problems.size() == 1);
  CHECK_THAT(problems[0], Contains("crowded.lua:8: stage 'S': scenario 'cluttered' with robot_distance = 6 (an end of the "
                                   "stage's task space): ") && Contains("no placement for"));
  // Found by a probe: parameters that combine go out of range only together, at the highest
  // corner (a noise delay times its scale), which check never built, and training failed there.
  for (const std::string teacher : {"", ", teacher = roger.teacher.lcas{ lift = { noise_scale = { 0.5, 1, 2 } } }"}) {
    const fs::path corner = write_stage(
        dir.path, "corner", "{ tasks = { noise_joints_delay = roger.int(0, 30)" +
                                std::string(teacher.empty() ? ", noise_scale = roger.real(0.5, 2) }" : " }") + teacher + " }");
    const std::vector<std::string> found = check_curriculum(corner.string());
    REQUIRE(found.size() == 1);
    CHECK_THAT(found[0], Contains("corner.lua:8: stage 'S': scenario 'cluttered' with noise_joints_delay = 30, "
                                  "noise_scale = 2 (the highest corner of the stage's task space): ") &&
                             Contains("field 'delay' must be within [0, 50] ticks, got 60") &&
                             !Contains("stack traceback"));
  }
  // A last step's demote stands alone: it promotes to nothing, so no default promote bounds it.
  const fs::path last_demote = write_stage(dir.path, "last_demote",
                                           "{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.sequence{ "
                                           "{ obstacles = 0 }, { obstacles = 1, demote = 0.95, window = 5 } } }");
  CHECK_NOTHROW(Curriculum::load(last_demote.string()));
  // An end that some layouts hold is not an error: training skips the others. Seed 0 cannot place
  // the object 2.6 m from Roger, seed 1 can (before, roger check refused what training ran).
  const fs::path some = write_stage(dir.path, "some", "{ tasks = { robot_distance = roger.real(0.8, 2.6) }, "
                                                      "test = { list = { { robot_distance = 1.0 } } } }");
  CHECK(check_curriculum(some.string()).empty());
  // But the test set is not skipped: drawn from that space, its 23rd task (2.57 m) cannot be
  // placed in its world seed, and every trial would fail at its final evaluation.
  const fs::path drawn = write_stage(dir.path, "drawn", "{ tasks = { robot_distance = roger.real(0.8, 2.6) } }");
  const std::vector<std::string> test_problems = check_curriculum(drawn.string());
  REQUIRE(test_problems.size() == 1);
  // Past the checkpoints' 20 tasks it is the final evaluation's alone, and said so (found by a
  // probe: "every trial's evaluations run it", though training ran through every checkpoint).
  CHECK_THAT(test_problems[0], Contains("drawn.lua:") && Contains("stage 'S': test task 23 of 50 ") &&
                                   Contains("cannot be placed in world seed 1000022, where every trial's final "
                                            "evaluation runs it (its checkpoints run the first 20) (the test set is "
                                            "not skipped)"));
  const fs::path every = write_stage(dir.path, "every", "{ tasks = { robot_distance = roger.real(0.8, 2.6) }, "
                                                        "checkpoints = { episodes = 30, final = 30 } }");
  const std::vector<std::string> every_problems = check_curriculum(every.string());
  REQUIRE(every_problems.size() == 1);
  CHECK_THAT(every_problems[0], Contains("stage 'S': test task 23 of 30 ") &&
                                    Contains("where every trial's checkpoints and final evaluation run it (the test "
                                             "set is not skipped)"));
}

TEST_CASE("a task whose world cannot be placed is skipped and shown; a space of such tasks fails its trial",
          "[teach][errors]") {
  test::TempDir dir("roger_teach_skip");
  // Beyond about 2 m from Roger the object finds no place in the 4 x 4 m arena.
  const fs::path holes = write_stage(dir.path, "holes", "{ tasks = { robot_distance = roger.real(1, 3.4) }, budget = { episodes = 6 }, "
                                                         "checkpoints = { every = 6 }, test = { list = { { robot_distance = 1 } } } }");
  TrainOptions o = stage_options(holes);
  const TrainResult r = train_stage(o);
  REQUIRE(r.episodes.size() == 6);  // every episode trained, on a task that could be placed
  for (const auto& e : r.episodes) CHECK(e.task["robot_distance"].get<double>() < 2.2);
  REQUIRE(r.skipped_tasks.size() == 6);  // of 12 draws, about the share of [1, 3.4] beyond 2 m
  for (const auto& k : r.skipped_tasks) {
    INFO(k.dump());
    CHECK(k["task"]["robot_distance"].get<double>() > 1.9);
    CHECK_THAT(k["error"].get<std::string>(), Contains("no placement for 'circle'"));
    CHECK(k["episode"].get<int>() < 6);
  }
  CHECK(train_summary_json(r)["skipped_tasks"] == r.skipped_tasks);
  // The same trial again: the same skips (the teacher's draws are the trial's).
  CHECK(train_stage(o).skipped_tasks == r.skipped_tasks);
  // roger train says so (found by a probe: only summary.json did), and that its figures are the
  // test tasks', not held-out episodes.
  const fs::path said = dir.path / "said.txt";
  REQUIRE(run_shell(std::string(ROGER_BINARY) + " train " + holes.string() + " --stage S --context A --seed " +
                    std::to_string(o.seed) + " --out " + (dir.path / "out").string() + " > " + said.string()) == 0);
  CHECK_THAT(slurp(said), Contains("  final policy   ") && Contains(" success over 1 test task, reward ") &&
                              Contains("  teacher        random over robot_distance = roger.real(1, 3.4)\n") &&
                              Contains("  skipped        6 tasks the scenario could not place (the first: "
                                       "{\"robot_distance\":" + r.skipped_tasks[0]["task"]["robot_distance"].dump() +
                                       "}; all in summary.json)\n"));
  // A space that is all holes: the trial fails, saying so, rather than drawing forever.
  const fs::path all = write_stage(dir.path, "all", "{ tasks = { robot_distance = roger.real(3.3, 3.4) }, "
                                                     "test = { list = { { robot_distance = 3.3 } } } }");
  o.curriculum = all.string();
  // Said first, at the stage's line, with the last task; the placement's own message kept after it
  // (before, the placement's message came first and the skips only after its traceback).
  std::string message, where;
  try {
    train_stage(o);
  } catch (const ScriptError& e) {
    message = e.message;
    where = e.file + ":" + std::to_string(e.line);
  }
  INFO(message);
  CHECK(where == all.string() + ":6");
  CHECK_THAT(message, StartsWith("stage 'S': 100 tasks in a row from its teacher (random) could not be placed in 10 "
                                 "world seeds, each skipped (the last: robot_distance = 3.") &&
                          Contains(", for training episode 0, world seed ") &&
                          Contains("the task space (robot_distance = roger.real(3.3, 3.4)) asks for worlds the scenario "
                                   "cannot build. The placement failed with: ") &&
                          Contains("lib/place.lua:91: world:sample_position: no placement for 'circle' after 1000 tries"));
  // Found by a probe: a narrow space far from Roger, which some layouts hold and the first
  // episode's does not, failed every trial drawing 100 tasks in that one layout. After 10 skips the
  // draws move to another world seed: the trial trains.
  const fs::path narrow = write_stage(dir.path, "narrow", "{ tasks = { robot_distance = roger.real(2.1, 2.4) }, "
                                                           "test = { list = { { robot_distance = 2.1 } } } }");
  o.curriculum = narrow.string();
  o.seed = 6;  // its training episode 3's layout holds no task of the space (100 skips failed it)
  const TrainResult moved = train_stage(o);
  CHECK(moved.episodes.size() == 4);
  CHECK(moved.skipped_tasks.size() == 10);
  o.seed = 1;
  // Found by a probe: with every axis fixed by --set, a world that could not be placed was drawn
  // again 100 times, the same each time, and the message blamed a task space of no parameters.
  o.curriculum = holes.string();
  o.sets = {{"robot_distance", "3.4"}};
  CHECK_THROWS_WITH(train_stage(o), Contains("no placement for 'circle'") && !Contains("100 tasks in a row") &&
                                        !Contains("no parameters"));
}

TEST_CASE("a Lua teacher's history, and its faults: each fails its trial alone at file:line", "[teach][errors]") {
  test::TempDir dir("roger_teach_fn");
  // The function sees every earlier episode in order: it returns its history's length as the task.
  const fs::path counting = write_stage(
      dir.path, "counting",
      "{ tasks = { obstacles = roger.int(0, 3), shape = roger.choice{'circle', 'spade'} },\n"
      "  test = { tasks = 2 },\n"
      "  teacher = function(history, rng)\n"
      "    for i, e in ipairs(history) do\n"
      "      assert(e.task.obstacles == (i - 1) % 4 and type(e.success) == 'boolean' and e.time > 0 and e.reward ~= nil)\n"
      "    end\n"
      "    return { obstacles = #history % 4 }\n"
      "  end }");
  TrainOptions o = stage_options(counting);
  const TrainResult r = train_stage(o);
  REQUIRE(r.episodes.size() == 4);
  std::set<std::string> shapes;
  for (size_t e = 0; e < 4; ++e) {
    CHECK(r.episodes[e].task["obstacles"] == int(e));
    CHECK(r.episodes[e].world.obstacles == int(e));  // what the world placed
    shapes.insert(r.episodes[e].task["shape"].get<std::string>());  // left out: drawn uniformly
  }
  CHECK(r.teacher["kind"] == "function");
  // A curriculum outside the project names its function from the curriculum's folder (found by a
  // probe: tables.md gave the function's absolute path, so the results depended on where they ran).
  CHECK(r.teacher["state"]["function"] == "counting.lua:10");

  const std::vector<std::pair<std::string, std::string>> faults = {
      {"function() return { obstacles = 9 } end",
       "stage 'S': teacher function returned obstacles = 9, outside the task space: obstacles takes an integer in "
       "roger.int(0, 3)"},
      {"function() return { mass = 1 } end",
       "stage 'S': teacher function returned 'mass', which is not a parameter of the task space (obstacles = roger.int(0, 3))"},
      {"function() return 3 end", "stage 'S': teacher function must return a table of task parameters"},
      // Found by a probe: the second value was dropped without a word.
      {"function() return { obstacles = 1 }, 12345 end",
       "stage 'S': teacher function must return one table of task parameters, got 2 values (a table, number 12345)"},
      // Found by a probe: neither said what it got or what was meant.
      {"function() return { obstacls = 1 } end",
       "stage 'S': teacher function returned 'obstacls', which is not a parameter of the task space (did you mean "
       "'obstacles'?) (obstacles = roger.int(0, 3))"},
      {"function() return { 1, 2 } end",
       "must have string keys {param = value}, got the key number 1 (a list? name each value)"},
      {"function() error('no idea') end", "stage 'S': teacher function: "},
      {"function() while true do end end", "stage 'S': teacher function: instruction budget of 50000000 exceeded"},
  };
  for (size_t k = 0; k < faults.size(); ++k) {
    const fs::path file = write_stage(dir.path, "fault" + std::to_string(k),
                                      "{ tasks = { obstacles = roger.int(0, 3) }, teacher = " + faults[k].first + " }");
    o.curriculum = file.string();
    std::string message;
    std::string where;
    try {
      train_stage(o);
    } catch (const ScriptError& e) {
      message = e.what();
      where = e.file + ":" + std::to_string(e.line);
    }
    INFO(message);
    CHECK_THAT(message, Contains(faults[k].second));
    CHECK(where == file.string() + ":8");
  }
}

// Found by a probe: a teacher's rng kept in a variable and drawn by the absorbing function made
// every verdict depend on the teacher's draws, and roger eval of the policy could not give the
// trial's final figure. The rng (and its forks) draw only while the teacher function runs.
TEST_CASE("a teacher's rng draws only while its function runs", "[teach][errors]") {
  test::TempDir dir("roger_teach_rng_kept");
  const fs::path file = write_stage(dir.path, "kept",
      "{ tasks = { obstacles = roger.int(0, 3) },\n"
      "  teacher = function(history, rng) kept = rng:fork(); rng:uniform(); return {} end,\n"
      "  absorbing = function(state) if kept then return kept:uniform() < 0.5 end return false end }");
  std::string message;
  try {
    train_stage(stage_options(file));
  } catch (const std::exception& e) {
    message = e.what();
  }
  CHECK_THAT(message, Contains("kept.lua:10: stage 'S', context 'A': absorbing function: rng:uniform: this rng is a "
                               "teacher function's, and draws only while that function runs"));
}

TEST_CASE("a trial whose teacher faults late keeps the episodes it trained, in roger train and in a batch",
          "[teach][errors]") {
  test::TempDir dir("roger_teach_kept");
  // Passes roger check (which calls it on 30 episodes of history) and faults before episode 33.
  const std::string late = "{ tasks = { obstacles = roger.int(0, 3) }, budget = { episodes = 40 },\n"
                           "  teacher = function(history, rng) if #history == 32 then error('late') end return {} end }";
  const fs::path file = write_stage(dir.path, "late", late);
  TrainOptions o = stage_options(file);
  TrainResult progress;
  o.progress_on_fault = &progress;
  CHECK_THROWS_WITH(train_stage(o), Contains("stage 'S': teacher function: ") && Contains("late"));
  CHECK(progress.episodes.size() == 32);
  CHECK(progress.totals.episodes == 32);
  CHECK(progress.checkpoints.size() == 8);  // every 4 episodes
  CHECK(progress.teacher["kind"] == "function");

  // roger train writes them beside error.json, in place of an earlier trial's results there.
  const fs::path out = dir.path / "out";
  fs::create_directories(out);
  for (const char* stale : {"policy.json", "summary.json", "final.jsonl"}) std::ofstream(out / stale) << "{}\n";
  const std::string roger = std::string(ROGER_BINARY);
  const fs::path said = dir.path / "said.txt";
  CHECK(run_shell(roger + " train " + file.string() + " --stage S --context A --out " + out.string() + " 2> " +
                  said.string()) == 1);
  const std::string message = slurp(said);
  CHECK_THAT(message, Contains("late.lua:9: stage 'S': teacher function: "));
  CHECK_THAT(message, Contains("kept           " + out.string() +
                               "/{episodes.jsonl,checkpoints.jsonl,curve.csv,error.json}: the 32 training episodes "
                               "and 8 checkpoints before the fault"));
  const std::string episodes = slurp(out / "episodes.jsonl");
  CHECK(std::count(episodes.begin(), episodes.end(), '\n') == 32);
  const json error = read_json(out / "error.json");
  CHECK_THAT(error["error"].get<std::string>(), Contains("late"));
  CHECK(error["trained"]["episodes"] == 32);
  CHECK(error["checkpoints"] == 8);
  for (const char* stale : {"policy.json", "summary.json", "final.jsonl"}) CHECK_FALSE(fs::exists(out / stale));
  // Fixed, the trial's results replace the fault's record.
  write_stage(dir.path, "late", "{ tasks = { obstacles = roger.int(0, 3) }, budget = { episodes = 40 } }");
  CHECK(run_shell(roger + " train " + file.string() + " --stage S --context A --out " + out.string() + " > /dev/null") == 0);
  CHECK(fs::exists(out / "policy.json"));
  CHECK_FALSE(fs::exists(out / "error.json"));

  // A batch trial keeps them beside the error.json the run writes.
  write_stage(dir.path, "late", late);
  const fs::path batch = dir.path / "batch.lua";
  std::ofstream(batch) << "return { name = 'late', curriculum = '" << file.string()
                       << "', trials = 1, runs = { { name = 'S', stage = 'S', contexts = { 'A' } } } }\n";
  const fs::path results = dir.path / "results";
  CHECK(run_shell(roger + " run " + batch.string() + " --out " + results.string() + " > /dev/null 2>&1") != 0);
  const fs::path trial = results / "trials" / "S" / "A" / "000";
  const std::string kept = slurp(trial / "episodes.jsonl");
  CHECK(std::count(kept.begin(), kept.end(), '\n') == 32);
  CHECK_THAT(read_json(trial / "error.json")["error"].get<std::string>(), Contains("late"));
  CHECK_FALSE(fs::exists(trial / "result.json"));
}

TEST_CASE("the report compares the teachers, splits their success by level and maps where they sampled",
          "[teach][stage]") {
  const fs::path dir = teach_batch();
  const std::string md = slurp(dir / "tables.md");
  // The comparison: a row per teacher against the first, Mann-Whitney and all.
  CHECK_THAT(md, Contains("## Teachers: time to 90% mastered\n\nRows: a context of a run each, against `Random/A`."));
  for (const char* row : {"| Random/A |", "| Alp/A |", "| Plr/A |", "| PlrFail/A |", "| Sequence/A |", "| Lcas/A |",
                          "| Function/A |", "| LiftOnly/A |"})
    CHECK_THAT(md, Contains(row));
  // What each trial's teacher did, as roger train says it (found by a probe: the report said
  // nothing of it), from the trials' own records.
  CHECK_THAT(md, Contains("What each trial's teacher did (its result.json, \"teacher\"):\n\n"));
  const json comparison = read_json(dir / "report.json")["tables"][0];
  REQUIRE(comparison["teachers"].size() >= 4);
  for (const json& t : comparison["teachers"]) {
    const json result = read_json(trial_of(t["row"].get<std::string>().substr(0, t["row"].get<std::string>().find('/'))) /
                                  "result.json");
    CHECK(t["did"] == describe_teacher_state(result["teacher"]["state"]));
    // Named by its kind (found by a probe: the line said not which teacher).
    CHECK(t["kind"] == result["teacher"]["kind"]);
    CHECK_THAT(md, Contains("- " + t["row"].get<std::string>() + " trial 0 (" + t["kind"].get<std::string>() +
                            "): " + t["did"].get<std::string>() + "\n"));
  }
  // Every teacher has its line, random and function too (found by a probe: they had none).
  CHECK(comparison["teachers"].size() == 8);
  // Found by a probe: an untitled comparison had an empty heading, a run's own table of a stage
  // that teaches said nothing of its teacher, and an untitled comparison figure was listed as its
  // first row's run's.
  CHECK_THAT(md, Contains("\n## Comparison of Random/A, Alp/A\n"));
  const std::string sequence_table = md.substr(md.find("\n## Stage Sequence (run Sequence)\n"));
  CHECK_THAT(sequence_table.substr(0, sequence_table.find("\n## ", 1)),
             Contains("With a test set (a stage that teaches), the success rate is the share of its tasks") &&
                 Contains("\n- Sequence/A trial 0 (sequence): at step "));
  CHECK_THAT(md, Contains("\n- `two_teachers.png` / `two_teachers.svg`: curves of Random/A, Alp/A\n"));
  CHECK(md.find("\n## \n") == std::string::npos);
  // The split by level: five bins of the real axis, each cell the final episodes of that bin.
  const json report = read_json(dir / "report.json");
  const json& by = report["tables"][1];
  REQUIRE(by["by"] == "level");
  REQUIRE(by["rows"].size() == 2);
  int episodes = 0;
  for (const auto& [bin, cell] : by["rows"][0]["cells"].items()) episodes += cell["episodes"].get<int>();
  CHECK(by["rows"][0]["cells"].size() == 5);
  CHECK(episodes == 20);  // the whole test set
  // Where ALP-GMM sampled: the heat map the dashboard draws, every column's shares adding to 1.
  const std::string js = slurp(dir / "dashboard.js");
  const json page = json::parse(js.substr(js.find('=') + 1, js.rfind(';') - js.find('=') - 1));
  int maps = 0;
  for (const auto& f : page["figures"]) {
    if (f["kind"] != "tasks") continue;
    ++maps;
    CHECK(fs::exists(dir / (f["file"].get<std::string>() + ".png")));
    REQUIRE(f["rows"].size() == 10);
    // The bins span the axis (roger.real(0, 1)), not the range the draws covered: a teacher that
    // kept to the band shows the rest of the axis empty.
    CHECK(f["rows"][0] == "0 to 0.1");
    CHECK(f["rows"][9] == "0.9 to 1");
    for (size_t c = 0; c + 1 < f["x_edges"].size(); ++c) {
      double total = 0;
      for (const auto& row : f["share"]) total += row[c].get<double>();
      CHECK(total == Approx(1.0).margin(1e-3));
    }
  }
  CHECK(maps == 2);
}

// Found by a probe: a "tasks drawn" map had a row per value drawn, so the values a teacher never
// drew were not there to see. The trials of the Sequence run are rewritten here to a space of
// roger.int(0, 3) of which only 0 and 1 were drawn: the map has the four rows.
TEST_CASE("a tasks-drawn map shows the whole axis of the recorded space", "[teach][stage]") {
  test::TempDir copy("roger_teach_axis");
  fs::copy(teach_batch(), copy.path, fs::copy_options::recursive);
  for (const auto& trial : fs::directory_iterator(copy.path / "trials" / "Sequence" / "A")) {
    json result = read_json(trial.path() / "result.json");
    result["tasks"] = "level = roger.int(0, 3)";
    std::ofstream(trial.path() / "result.json") << result.dump();
    std::stringstream original(slurp(trial.path() / "episodes.jsonl")), rewritten;
    for (std::string line; std::getline(original, line);) {
      if (line.empty()) continue;
      json e = json::parse(line);
      if (e.contains("task") && e["task"].contains("level")) e["task"]["level"] = e["task"]["level"].get<double>() < 0.5 ? 0 : 1;
      rewritten << e.dump() << "\n";
    }
    std::ofstream(trial.path() / "episodes.jsonl") << rewritten.str();
  }
  REQUIRE(run_shell(std::string(ROGER_BINARY) + " report " + copy.path.string() + " > /dev/null 2>&1") == 0);
  const std::string js = slurp(copy.path / "dashboard.js");
  const json page = json::parse(js.substr(js.find('=') + 1, js.rfind(';') - js.find('=') - 1));
  int maps = 0;
  for (const auto& f : page["figures"])
    if (f["kind"] == "tasks" && f["run"] == "Sequence") {
      ++maps;
      CHECK(f["rows"] == json::array({"0", "1", "2", "3"}));
      for (size_t c = 0; c + 1 < f["x_edges"].size(); ++c) CHECK(f["share"][2][c] == 0.0);  // never drawn
    }
  CHECK(maps == 1);
}

// A choice of fractions is a row per value, not bins of a range, now that its values are recorded
// as numbers.
TEST_CASE("a tasks-drawn map of a choice of numbers has a row per value", "[teach][stage]") {
  test::TempDir copy("roger_teach_choice_axis");
  fs::copy(teach_batch(), copy.path, fs::copy_options::recursive);
  for (const auto& trial : fs::directory_iterator(copy.path / "trials" / "Sequence" / "A")) {
    json result = read_json(trial.path() / "result.json");
    result["tasks"] = "level = roger.choice{0.25, 0.5, 0.75}";
    std::ofstream(trial.path() / "result.json") << result.dump();
    std::stringstream original(slurp(trial.path() / "episodes.jsonl")), rewritten;
    for (std::string line; std::getline(original, line);) {
      if (line.empty()) continue;
      json e = json::parse(line);
      if (e.contains("task") && e["task"].contains("level")) e["task"]["level"] = e["task"]["level"].get<double>() < 0.5 ? 0.25 : 0.5;
      rewritten << e.dump() << "\n";
    }
    std::ofstream(trial.path() / "episodes.jsonl") << rewritten.str();
  }
  REQUIRE(run_shell(std::string(ROGER_BINARY) + " report " + copy.path.string() + " > /dev/null 2>&1") == 0);
  const std::string js = slurp(copy.path / "dashboard.js");
  const json page = json::parse(js.substr(js.find('=') + 1, js.rfind(';') - js.find('=') - 1));
  int maps = 0;
  for (const auto& f : page["figures"])
    if (f["kind"] == "tasks" && f["run"] == "Sequence") {
      ++maps;
      CHECK(f["rows"] == json::array({"0.25", "0.5", "0.75"}));
      double drawn = 0.0;
      for (size_t c = 0; c + 1 < f["x_edges"].size(); ++c) {
        CHECK(f["share"][2][c] == 0.0);  // never drawn
        drawn += f["share"][0][c].get<double>() + f["share"][1][c].get<double>();
      }
      CHECK(drawn > 0.0);
    }
  CHECK(maps == 1);
}

// Found by a probe: `roger report --by bogus` said no trial had recorded its episodes, and a
// final.jsonl record whose "success" is a string stopped the report with a bare JSON type error.
TEST_CASE("report --by names what the records have, and a damaged record's file and line", "[teach][stage]") {
  test::TempDir copy("roger_teach_by");
  fs::copy(teach_batch(), copy.path, fs::copy_options::recursive);
  const std::string report = std::string(ROGER_BINARY) + " report " + copy.path.string();
  // A feature no record has is refused, with those they have, and the report is left as it was.
  const std::string tables_before = fs::exists(copy.path / "tables.md") ? slurp(copy.path / "tables.md") : "";
  const fs::path err = copy.path / "err.txt";
  REQUIRE(run_shell(report + " --by bogus > /dev/null 2>" + err.string()) == 1);
  // The records of every table it would split: the comparisons of 8 rows and of 2, and Sequence's,
  // said to be records (a trial shown by two tables is read twice), not episodes.
  CHECK_THAT(slurp(err), Contains("roger report: error: --by bogus: no final-evaluation episode the tables read has a feature "
                                  "'bogus' (210 records read, a trial's once for each table that shows it); they have: "
                                  "level, objects, obstacles, shape"));
  CHECK((fs::exists(copy.path / "tables.md") ? slurp(copy.path / "tables.md") : "") == tables_before);
  const fs::path final_records = copy.path / "trials" / "Random" / "A" / "000" / "final.jsonl";
  std::string text = slurp(final_records);
  // Line 2 replaced, not added: a file of another count of lines is refused before any line is read.
  const size_t second = text.find('\n') + 1;
  text = text.substr(0, second) + "{\"index\":1,\"success\":\"maybe\"}\n" + text.substr(text.find('\n', second) + 1);
  std::ofstream(final_records) << text;
  CHECK(run_shell(report + " --by level > /dev/null 2>" + err.string()) == 1);
  CHECK_THAT(slurp(err), Contains(final_records.string() + ":2: field \"success\" must be true or false, got \"maybe\""));
}

// Found by a probe: a finished trial whose episodes.jsonl was lost dropped out of the heat map of
// where its teacher sampled without a word (the title counted the trials left).
TEST_CASE("a heat map of where a teacher sampled names the finished trials it lacks", "[teach][stage]") {
  test::TempDir copy("roger_teach_missing");
  fs::copy(teach_batch(), copy.path, fs::copy_options::recursive);
  fs::remove(copy.path / "trials" / "Alp" / "A" / "000" / "episodes.jsonl");
  REQUIRE(run_shell(std::string(ROGER_BINARY) + " report " + copy.path.string() + " > /dev/null") == 0);
  CHECK_THAT(slurp(copy.path / "tables.md"),
             Contains("- `tasks_Alp.png` / `tasks_Alp.svg`: Where ALP-GMM sampled (not drawn: Alp/A/000 finished "
                      "without episodes.jsonl)"));
  const std::string js = slurp(copy.path / "dashboard.js");
  const json page = json::parse(js.substr(js.find('=') + 1, js.rfind(';') - js.find('=') - 1));
  for (const auto& f : page["figures"])
    if (f["kind"] == "tasks") CHECK(f.value("missing", json()) == (f["run"] == "Alp" ? json{"Alp/A/000"} : json::array()));
}

// Found by a probe: `roger eval` of a teaching stage's policy printed its figures as if they were
// the trial's final evaluation, which ran the stage's test tasks instead.
TEST_CASE("roger eval of a teaching stage's policy says its test tasks are not what it runs", "[teach][stage]") {
  const fs::path dir = teach_batch();
  const fs::path out = dir.parent_path() / "roger_teach_eval_note.txt";
  REQUIRE(run_shell(std::string(ROGER_BINARY) + " eval tests/scripts/teach_curriculum.lua --policy " +
                    (dir / "trials" / "Alp" / "A" / "000" / "policy.json").string() + " --episodes 2 > " + out.string()) == 0);
  CHECK_THAT(slurp(out), Contains("  note           stage Alp teaches: its trials ended on 20 test tasks of its task "
                                  "space, not run here (--test-set runs them; these episodes have the stage's own "
                                  "parameters)\n"));
  fs::remove(out);
}

TEST_CASE("roger eval --test-set repeats a teaching trial's final evaluation episode for episode", "[teach][stage]") {
  const fs::path dir = teach_batch();
  const fs::path out = dir.parent_path() / "roger_teach_eval_test_set.txt";
  // Alp draws its test tasks from the space; LiftOnly has none, and runs LCAS's last level of a
  // parameter beside it.
  for (const std::string stage : {"Alp", "LiftOnly"}) {
    INFO(stage);
    const fs::path trial = dir / "trials" / stage / "A" / "000";
    REQUIRE(run_shell(std::string(ROGER_BINARY) + " eval tests/scripts/teach_curriculum.lua --policy " +
                      (trial / "policy.json").string() + " --test-set --json > " + out.string()) == 0);
    const std::string text = slurp(out);
    const json got = json::parse(text.substr(text.rfind("\n{") + 1));
    std::istringstream lines(slurp(trial / "final.jsonl"));
    std::vector<json> final;
    for (std::string line; std::getline(lines, line);) final.push_back(json::parse(line));
    REQUIRE(got["test_set"] == true);
    // LiftOnly's trial records its lift's last level among its own parameters (distance 2), which
    // the test tasks set themselves: neither a --set they refuse nor a change of the test set.
    CHECK(got["test_set_changed"] == false);
    REQUIRE(got["episodes"] == int(final.size()));
    REQUIRE(got["test_tasks"].size() == final.size());
    std::vector<uint64_t> failed;
    int successes = 0;
    for (size_t i = 0; i < final.size(); ++i) {
      CHECK(final[i]["seed"] == got["first_seed"].get<uint64_t>() + i);
      const json task = final[i].value("task", json::object());
      for (const auto& [k, v] : task.items())
        CHECK(got["test_tasks"][i][k] == (v.is_string() ? v.get<std::string>() : v.dump()));
      if (stage == "LiftOnly") CHECK(got["test_tasks"][i] == json{{"distance", "2"}});
      successes += final[i]["success"].get<bool>();
      if (!final[i]["success"].get<bool>()) failed.push_back(final[i]["seed"].get<uint64_t>());
    }
    CHECK(got["successes"] == successes);
    CHECK(got["failed_seeds"] == failed);
    if (stage == "Alp") {
      REQUIRE(!failed.empty());  // the replay line sets the failed world's task
      const json first = final[size_t(failed.front() - got["first_seed"].get<uint64_t>())]["task"];
      CHECK_THAT(text, Contains("--set level=" + first["level"].dump() + " --seed " + std::to_string(failed.front())));
    }
  }
  // The policy file keeps the tasks: a curriculum whose test set was edited since (another seed)
  // runs the same episodes, and says the curriculum's set has changed.
  const std::string alp = (dir / "trials" / "Alp" / "A" / "000" / "policy.json").string();
  const auto eval_json = [&](const std::string& curriculum, const std::string& policy) {
    REQUIRE(run_shell(std::string(ROGER_BINARY) + " eval " + curriculum + " --policy " + policy + " --test-set --json > " +
                      out.string()) == 0);
    const std::string text = slurp(out);
    return std::make_pair(text, json::parse(text.substr(text.rfind("\n{") + 1)));
  };
  const auto [kept_text, kept] = eval_json("tests/scripts/teach_curriculum.lua", alp);
  CHECK(kept["test_set_from"] == alp);
  CHECK(kept["test_set_changed"] == false);
  std::string source = slurp("tests/scripts/teach_curriculum.lua");
  const size_t at = source.find("test = { tasks = 20, seed = 7 }");
  REQUIRE(at != std::string::npos);
  source.replace(at, 31, "test = { tasks = 20, seed = 8 }");
  const fs::path edited = dir.parent_path() / "roger_teach_edited_curriculum.lua";
  std::ofstream(edited) << source;
  const auto [edited_text, after_edit] = eval_json(edited.string(), alp);
  CHECK(after_edit["test_set_changed"] == true);
  CHECK_THAT(edited_text, Contains("note           the curriculum's test set for stage Alp is no longer the one this "
                                   "policy's trial ended on; these are that trial's 20 tasks, as " + alp + " keeps them"));
  for (const char* same : {"test_tasks", "failed_seeds", "successes", "first_seed", "reward_mean"})
    CHECK(after_edit[same] == kept[same]);
  fs::remove(edited);
  // A policy file from before it kept them: the curriculum's test set, said so.
  json file = json::parse(slurp(alp));
  REQUIRE(file["extra"].contains("test_set"));
  file["extra"].erase("test_set");
  const fs::path older = dir.parent_path() / "roger_teach_older_policy.json";
  std::ofstream(older) << file.dump();
  const auto [older_text, from_curriculum] = eval_json("tests/scripts/teach_curriculum.lua", older.string());
  CHECK_THAT(from_curriculum["test_set_from"].get<std::string>(), Contains("records none: written by an earlier roger"));
  CHECK(from_curriculum["test_tasks"] == kept["test_tasks"]);
  CHECK(from_curriculum["failed_seeds"] == kept["failed_seeds"]);
  fs::remove(older);
  // roger render --test-task k replays task k as the final evaluation ran it: its outcome is final.jsonl's.
  std::istringstream alp_lines(slurp(dir / "trials" / "Alp" / "A" / "000" / "final.jsonl"));
  int k = 0;
  for (std::string line; std::getline(alp_lines, line) && k < 3;) {
    const json record = json::parse(line);
    ++k;
    const fs::path movie = dir.parent_path() / ("roger_teach_task_" + std::to_string(k));
    REQUIRE(run_shell(std::string(ROGER_BINARY) + " render tests/scripts/teach_curriculum.lua --policy " + alp +
                      " --test-task " + std::to_string(k) + " --out " + movie.string() + " > /dev/null") == 0);
    const json episode = json::parse(slurp(movie / "episode.json"));
    CHECK(episode["success"] == record["success"]);
    CHECK(episode["seed"] == record["seed"]);
    CHECK_THAT(episode["title"].get<std::string>(),
               Contains(", test task " + std::to_string(k) + " (level = " + kept["test_tasks"][k - 1]["level"].get<std::string>() + ")"));
    fs::remove_all(movie);
  }
  // A --set of a parameter the tasks set would be overwritten by them: refused.
  CHECK(run_shell(std::string(ROGER_BINARY) + " eval tests/scripts/teach_curriculum.lua --policy " + alp +
                  " --test-set --set level=0.5 2> " + out.string()) == 1);
  CHECK_THAT(slurp(out), Contains("--set level=0.5: the test set's tasks (" + alp + ") set level themselves"));
  // Its seeds and number are the test set's own; a stage without a test set has none to run.
  CHECK(run_shell(std::string(ROGER_BINARY) + " eval tests/scripts/teach_curriculum.lua --policy " + alp +
                  " --test-set --seed 5 2> " + out.string()) == 1);
  CHECK_THAT(slurp(out), Contains("--test-set runs the test set's own tasks on its own world seeds; --seed cannot be "
                                  "given with it"));
  CHECK(run_shell(std::string(ROGER_BINARY) + " eval curricula/scripted.lua --policy task --test-set 2> " +
                  out.string()) == 1);
  CHECK_THAT(slurp(out), Contains("policy 'task' of curricula/scripted.lua is a skill script's, which has none"));
  fs::remove(out);
}

TEST_CASE("docs/examples/teachers_example.lua: every block of the docs' Teachers section is in it, each stage trains",
          "[teach][stage]") {
  // Each ```lua block of docs/curricula.md's "Teachers" is in the example file (leading spaces
  // aside), so the documented calls are the ones that run below.
  const auto trimmed_lines = [](const std::string& text) {
    std::string out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out += line.substr(std::min(line.find_first_not_of(' '), line.size())) + "\n";
    return out;
  };
  const std::string example = trimmed_lines(slurp("docs/examples/teachers_example.lua"));
  const std::string doc = slurp("docs/curricula.md");
  const size_t begin = doc.find("\n## Teachers\n"), end = doc.find("\n## ", begin + 1);
  REQUIRE(begin != std::string::npos);
  const std::string section = doc.substr(begin, end - begin);
  int blocks = 0;
  for (size_t at = section.find("```lua\n"); at != std::string::npos; at = section.find("```lua\n", at + 1)) {
    const size_t from = at + 7, to = section.find("```\n", from);
    const std::string block = trimmed_lines(section.substr(from, to - from));
    INFO(block);
    CHECK(example.find(block) != std::string::npos);
    ++blocks;
  }
  CHECK(blocks == 6);
  // Each stage trains to its threshold on its test set (measured: all at 20 episodes, 100%), and
  // its teacher did what the stage shows: sequence and LCAS moved, PLR replayed, the function ran.
  for (const std::string stage : {"Look", "LookRandom", "LookSequence", "LookLcas", "LookPlr", "LookFunction"}) {
    TrainOptions o;
    o.curriculum = "docs/examples/teachers_example.lua";
    o.stage = stage;
    o.context = "Gaze";
    o.seed = 1;
    const TrainResult r = train_stage(o);
    INFO(stage << ": " << r.teacher.dump());
    CHECK(r.reached);
    CHECK(r.final_eval.success_rate >= 0.9);
    const json& state = r.teacher["state"];
    if (stage == "LookSequence") CHECK(state["step"] == 3);
    if (stage == "LookLcas") CHECK(state["value"] == 128);  // a number, as episodes.jsonl writes it
    if (stage == "LookPlr") CHECK(state["replays"].get<int>() > 10);
    // The summary says what the test set was: LookRandom's is the list written in the stage (a
    // probe found it written as a seed, as if drawn), the others' drawn with a seed.
    const json test = train_summary_json(r)["test"];
    // Found by a probe: the summary's params showed a task axis's scenario default, which no
    // episode used; a parameter LCAS lifts outside the space keeps its last level.
    const json params = train_summary_json(r)["params"];
    CHECK_FALSE(params.contains("obstacles"));
    CHECK(params.contains("robot_distance") == (stage != "LookRandom"));
    if (stage == "LookLcas") CHECK(params["eye_pixels"] == "128");
    if (stage == "LookRandom") {
      CHECK(test == json::parse(R"({"tasks": 3, "list": [{"obstacles": 0, "robot_distance": 1},
                                  {"obstacles": 2, "robot_distance": 1.5}, {"obstacles": 4, "robot_distance": 2}]})"));
    } else if (stage != "Look") {
      CHECK(test.contains("seed"));
      CHECK_FALSE(test.contains("list"));
    }
    if (stage == "LookFunction") {  // named by where it is written
      const std::string text = slurp("docs/examples/teachers_example.lua");
      const auto line = 1 + std::count(text.begin(), text.begin() + text.find("teacher = function(history"), '\n');
      CHECK(state["function"] == "docs/examples/teachers_example.lua:" + std::to_string(line));
    }
  }
}

// Found by a probe: a stage without a test set whose final evaluation runs more tasks than its
// checkpoints recorded the checkpoints' count alone ("tasks": 10 of a final evaluation of 50).
TEST_CASE("the summary says how many test tasks the final evaluation ran", "[teach][stage]") {
  test::TempDir dir("roger_teach_final_tasks");
  TrainOptions o = stage_options(write_stage(dir.path, "final", "{ tasks = { obstacles = roger.int(0, 2) }, "
                                                               "checkpoints = { every = 4, episodes = 3, final = 5 } }"));
  const TrainResult r = train_stage(o);
  const json summary = train_summary_json(r);
  CHECK(summary["test"]["tasks"] == 3);
  CHECK(summary["test"]["final_tasks"] == 5);
  CHECK(r.final_eval.episodes == 5);
}

// Found by a probe: roger train said only "teacher lcas over ..."; the lifts and a sequence's
// moves were in summary.json alone.
TEST_CASE("roger train says what its teacher did", "[teach][stage]") {
  test::TempDir dir("roger_teach_said");
  const std::string roger = ROGER_BINARY, said = (dir.path / "said.txt").string();
  const auto train = [&](const std::string& stage) {
    REQUIRE(run_shell(roger + " train docs/examples/teachers_example.lua --stage " + stage + " --context Gaze --out " +
                      (dir.path / stage).string() + " > " + said) == 0);
    return slurp(said);
  };
  const std::string lcas = train("LookLcas");
  const json state = json::parse(slurp(dir.path / "LookLcas" / "summary.json"))["teacher"]["state"];
  REQUIRE(state["lifts"].size() == 2);
  CHECK_THAT(lcas, Contains("  teacher        lcas over ") &&
                       Contains("\n                 eye_pixels = 128 (level 3 of 3); lifted at episodes " +
                                state["lifts"][0]["episode"].dump() + " (to 64), " + state["lifts"][1]["episode"].dump() +
                                " (to 128)\n"));
  CHECK_THAT(train("LookSequence"), Contains("                 at step 3 of 3; moved at episodes ") &&
                                        Contains(" (step 1 to 2, rate "));
  CHECK_THAT(train("LookPlr"), Contains(" of 60 episodes replayed a level; ") && Contains(" levels kept\n"));
  const std::string alp = train("Look");
  CHECK_THAT(alp, Contains(" fits, mean ALP ") && Contains("; most progress around {"));
  // The mixture is recorded to six decimals (a fit's 0.9999999999999374 read as 1).
  const json look = json::parse(slurp(dir.path / "Look" / "summary.json"));  // kept: a range-for over a
  for (const json& c : look["teacher"]["state"]["components"]) {              // temporary's member dangles
    const double alp_value = c["alp"].get<double>();
    CHECK(alp_value == std::round(alp_value * 1e6) / 1e6);
  }
  CHECK(describe_teacher_state(json{{"kind", "lcas"}, {"param", "obstacles"}, {"value", 0}, {"level", 1},
                                    {"levels", 4}, {"lifts", json::array()}}) ==
        "obstacles = 0 (level 1 of 4), never lifted");
  // Found by a probe: an empty level read "locked =  (level 2 of 2); lifted at episodes 4 (to )".
  CHECK(describe_teacher_state(json{{"kind", "lcas"}, {"param", "locked"}, {"value", ""}, {"level", 2},
                                    {"levels", 2}, {"lifts", json::array({json{{"episode", 4}, {"to", ""}}})}}) ==
        "locked = \"\" (level 2 of 2); lifted at episodes 4 (to \"\")");
  // Found by a probe: random and function teachers said nothing, in roger train or the report.
  CHECK(describe_teacher_state(json{{"kind", "random"}, {"episodes", 3}}) == "3 tasks drawn uniformly from the task space");
  CHECK(describe_teacher_state(json{{"kind", "function"}, {"episodes", 1}, {"function", "c.lua:9"}}) ==
        "1 task chosen by the function at c.lua:9");
  // Found by a probe: a move decided on the last episode's outcome read as a step reached.
  CHECK(describe_teacher_state(json{{"kind", "sequence"}, {"episodes", 20}, {"step", 3}, {"steps", 3},
                                    {"moves", json::array({json{{"episode", 10}, {"from", 1}, {"to", 2}, {"rate", 0.3}},
                                                           json{{"episode", 20}, {"from", 2}, {"to", 3}, {"rate", 0.9}}})}}) ==
        "at step 2 of 3 when training ended; moved at episodes 10 (step 1 to 2, rate 0.3); after the last episode, "
        "to step 3 (rate 0.9), never trained");
  CHECK(describe_teacher_state(json{{"kind", "lcas"}, {"episodes", 60}, {"param", "noise_scale"}, {"value", 2},
                                    {"level", 3}, {"levels", 3},
                                    {"lifts", json::array({json{{"episode", 44}, {"from", 0}, {"to", 1}},
                                                           json{{"episode", 60}, {"from", 1}, {"to", 2}}})}}) ==
        "noise_scale = 1 (level 2 of 3) when training ended; lifted at episodes 44 (to 1); after the last episode, "
        "to 2, never trained");
  // A record written before lifts had a "from": the lift before the last gives it.
  CHECK(describe_teacher_state(json{{"kind", "lcas"}, {"episodes", 60}, {"param", "noise_scale"}, {"value", 2},
                                    {"level", 3}, {"levels", 3},
                                    {"lifts", json::array({json{{"episode", 44}, {"to", 1}},
                                                           json{{"episode", 60}, {"to", 2}}})}}) ==
        "noise_scale = 1 (level 2 of 3) when training ended; lifted at episodes 44 (to 1); after the last episode, "
        "to 2, never trained");
  // Found by a probe: fractions at full precision, a task as JSON, "1 levels kept".
  CHECK(describe_teacher_state(json{{"kind", "plr"}, {"replays", 1}, {"episodes", 1}, {"levels", 1}}) ==
        "1 of 1 episode replayed a level; 1 level kept");
  CHECK(describe_teacher_state(json{{"kind", "alp_gmm"}, {"fits", 2}, {"mean_alp", 1.0 / 3.0},
                                    {"components", json::array({json{{"alp", 0.5}, {"task", json{{"robot_distance",
                                                                                                 1.5340091575147519},
                                                                                                {"shape", "spade"}}}}})}}) ==
        "2 fits, mean ALP 0.333; most progress around {robot_distance = 1.53, shape = spade} (ALP 0.5)");
  CHECK(describe_teacher_state(json{{"kind", "sequence"}, {"step", 2}, {"steps", 3},
                                    {"moves", json::array({json{{"episode", 19}, {"from", 1}, {"to", 2},
                                                                {"rate", 2.0 / 3.0}}})}}) ==
        "at step 2 of 3; moved at episodes 19 (step 1 to 2, rate 0.667)");
}

TEST_CASE("a task parameter given by --set is fixed: the axis leaves the trial's space", "[teach][stage]") {
  // LookRandom varies obstacles (0-4) and robot_distance; --set obstacles=2 holds every training
  // and test world at 2 obstacles while the distance still varies, and the summary's space says so.
  TrainOptions o;
  o.curriculum = "docs/examples/teachers_example.lua";
  o.stage = "LookRandom";
  o.context = "Gaze";
  o.seed = 1;
  o.sets = {{"obstacles", "2"}};
  const TrainResult r = train_stage(o);
  std::set<double> distances;
  for (const auto& e : r.episodes) {
    CHECK(e.world.obstacles == 2);
    CHECK_FALSE(e.task.contains("obstacles"));
    distances.insert(e.task["robot_distance"].get<double>());
  }
  CHECK(distances.size() == r.episodes.size());  // a real axis: every draw its own
  o.sets = {{"obstacles", "22"}};
  CHECK_THROWS_WITH(train_stage(o), Contains("parameter 'obstacles' of scenario 'cluttered' expects an integer in [0, 8], got '22'"));

  // Found by a probe: eval --test-set of such a trial's policy said the curriculum's test set was no
  // longer the one the trial ended on, though nothing was edited: it rebuilt the test set without
  // the trial's own --set, over the whole space.
  test::TempDir dir("roger_teach_fixed_axis");
  const std::string roger = ROGER_BINARY, out = (dir.path / "out").string(), said = (dir.path / "said.txt").string();
  REQUIRE(run_shell(roger + " train docs/examples/teachers_example.lua --stage Look --context Gaze --set obstacles=2 --out " +
                    out + " > /dev/null") == 0);
  REQUIRE(run_shell(roger + " eval docs/examples/teachers_example.lua --policy " + out + "/policy.json --test-set --json > " +
                    said) == 0);
  const std::string text = slurp(said);
  CHECK(json::parse(text.substr(text.rfind("\n{") + 1))["test_set_changed"] == false);
  CHECK_THAT(text, !Contains("no longer"));

  // Found by a probe: with every axis fixed, ALP-GMM said only that it "needs a task space with at
  // least one parameter", not that the --set had emptied it.
  o.stage = "Look";
  o.sets = {{"obstacles", "2"}, {"shape", "circle"}};
  CHECK_THROWS_WITH(train_stage(o), "docs/examples/teachers_example.lua:42: stage 'Look': every parameter of its "
                                    "task space (obstacles, shape) is fixed by --set, leaving its teacher "
                                    "(roger.teacher.alp_gmm) nothing to choose; leave one to the teacher, or fix fewer");
  o.stage = "LookLcas";
  o.sets = {{"eye_pixels", "64"}};
  CHECK_THROWS_WITH(train_stage(o), "docs/examples/teachers_example.lua:68: stage 'LookLcas': 'eye_pixels' is fixed "
                                    "by --set, and it is the parameter its teacher (roger.teacher.lcas) lifts: lifting "
                                    "it is all that teacher does; leave it to the teacher, or use a stage with another "
                                    "teacher");
  // Found by a probe: a batch run's params were called "--set" in the message.
  o.sets_from = "the params of run 'R'";
  CHECK_THROWS_WITH(train_stage(o), Contains("stage 'LookLcas': 'eye_pixels' is fixed by the params of run 'R', and"));
  // Found by a probe: a lifted parameter inside the task space, fixed by --set, was lifted anyway
  // (the trial trained and was judged at the teacher's levels, the --set value ignored).
  o = TrainOptions{};
  o.curriculum = "tests/scripts/teach_curriculum.lua";
  o.stage = "Lcas";
  o.context = "A";
  o.sets = {{"level", "0.5"}};
  CHECK_THROWS_WITH(train_stage(o), Contains("teach_curriculum.lua:39: stage 'Lcas': 'level' is fixed by --set, and "
                                             "it is the parameter its teacher (roger.teacher.lcas) lifts"));
  // roger check with the same --set says so too, as training would.
  const std::string checked = (dir.path / "checked.txt").string();
  CHECK(run_shell(roger + " check tests/scripts/teach_curriculum.lua --set level=0.5 > " + checked + " 2>&1") == 1);
  CHECK_THAT(slurp(checked), Contains("teach_curriculum.lua:39: stage 'Lcas': 'level' is fixed by --set"));
}

// Found by a probe: with --set obstacles=2 (or a batch run's params = {obstacles = 2}) every trial
// of a sequence or function teacher that names obstacles failed ("'obstacles' is not a parameter of
// the task space (no parameters)"), though the docs say the axis simply leaves the trial's space.
TEST_CASE("a parameter fixed by --set is ignored where a sequence or function teacher names it", "[teach][stage]") {
  for (const std::string stage : {"LookSequence", "LookFunction"}) {
    TrainOptions o;
    o.curriculum = "docs/examples/teachers_example.lua";
    o.stage = stage;
    o.context = "Gaze";
    o.seed = 1;
    o.sets = {{"obstacles", "2"}};
    const TrainResult r = train_stage(o);
    INFO(stage << ": " << r.teacher.dump());
    REQUIRE(r.episodes.size() == 60);
    for (const auto& e : r.episodes) CHECK(e.world.obstacles == 2);  // the run's value, never the teacher's
    CHECK(r.task_space == "no parameters");
    if (stage == "LookSequence") CHECK(r.teacher["state"]["moves"].size() >= 1);  // its steps still move
  }
  // The same teachers still name only parameters of the whole space: a misspelt one is refused at
  // load, --set or not.
  test::TempDir dir("roger_teach_fixed");
  const fs::path typo = write_stage(dir.path, "typo", "{ tasks = { obstacles = roger.int(0, 3) }, "
                                                       "teacher = roger.teacher.sequence{ { obstacle = 0 }, {} } }");
  CHECK_THAT(load_error(typo), Contains("step 1: 'obstacle' is neither a step's setting (promote, demote, window) "
                                        "nor a parameter of the task space"));
  // A function's value for a fixed parameter is ignored; its other values still count.
  const fs::path fn = write_stage(dir.path, "fn", "{ tasks = { obstacles = roger.int(0, 3), shape = roger.choice{'circle', 'spade'} }, "
                                                   "teacher = function() return { obstacles = 3, shape = 'spade' } end }");
  TrainOptions o = stage_options(fn);
  o.sets = {{"obstacles", "1"}};
  const TrainResult r = train_stage(o);
  for (const auto& e : r.episodes) {
    CHECK(e.world.obstacles == 1);
    CHECK(e.task == json{{"shape", "spade"}});
  }
  // Found by a probe: but a value outside the whole space passed under --set, and the same trial
  // without it failed; it is the function's fault either way.
  const fs::path outside = write_stage(dir.path, "outside", "{ tasks = { obstacles = roger.int(0, 3) }, "
                                                             "teacher = function() return { obstacles = 99 } end }");
  o = stage_options(outside);
  o.sets = {{"obstacles", "1"}};
  CHECK_THROWS_WITH(train_stage(o), Contains("stage 'S': teacher function returned obstacles = 99, outside the task "
                                             "space: obstacles takes an integer in roger.int(0, 3)"));
  const fs::path text = write_stage(dir.path, "text", "{ tasks = { obstacles = roger.int(0, 3) }, "
                                                       "teacher = function() return { obstacles = '2' } end }");
  o = stage_options(text);
  o.sets = {{"obstacles", "1"}};
  CHECK_THROWS_WITH(train_stage(o), Contains("returned obstacles = \"2\" (a string), but obstacles takes a number"));
}

// Found by a probe: `teacher = roger.teacher.lcas` (the maker, braces forgotten) passed roger check
// and failed every trial ("teacher function must return a table ..., got userdata").
TEST_CASE("a built-in teacher without its braces is refused at load with a hint", "[teach][errors]") {
  test::TempDir dir("roger_teach_braces");
  for (const std::string kind : {"random", "sequence", "lcas", "alp_gmm", "plr"}) {
    const fs::path file = write_stage(dir.path, kind, "{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher." + kind + " }");
    const std::string message = load_error(file);
    INFO(message);
    CHECK_THAT(message, Contains(file.filename().string() + ":6: stage 'S': field 'teacher' is the function roger.teacher." +
                                 kind + " itself, not a teacher: did you mean roger.teacher." + kind +
                                 (kind == "random" ? "{}?" : "{...}?")));
  }
  // Another built-in function is no teacher either, and says so rather than failing in training.
  const fs::path print = write_stage(dir.path, "print", "{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.int }");
  CHECK_THAT(load_error(print), Contains(":6: stage 'S': field 'teacher' must be a teacher") &&
                                    Contains("or a Lua function(history, rng), got a built-in function"));
}

// Found by a probe: a teacher function's {obstacles = "2"} was read as 2 while `true` was refused.
TEST_CASE("a teacher function's string for a number axis is refused at its line", "[teach][errors]") {
  test::TempDir dir("roger_teach_string");
  const fs::path file = write_stage(dir.path, "s", "{ tasks = { obstacles = roger.int(0, 3), robot_distance = roger.real(0.8, 1.2) },\n"
                                                   "  teacher = function() return { obstacles = '2' } end }");
  std::string message, where;
  try {
    train_stage(stage_options(file));
  } catch (const ScriptError& e) {
    message = e.message;
    where = e.file + ":" + std::to_string(e.line);
  }
  CHECK(message == "stage 'S': teacher function returned obstacles = \"2\" (a string), but obstacles takes a number: "
                   "roger.int(0, 3); return the number itself (before training episode 0)");
  CHECK(where == file.string() + ":9");
}

// Found by a probe: roger check said ok of a teacher function that failed in every trial once its
// learner began to succeed (its error, or a value outside the task space, came after the trial's
// first episodes). Now check calls it as training does, on a history of failures then successes.
TEST_CASE("roger check calls a teacher function on a history and finds its errors at their lines", "[teach][errors]") {
  test::TempDir dir("roger_teach_check_fn");
  // Fine until ten episodes have succeeded, then a misspelt field of a history entry (an entry
  // holds its four fields alone: reading another is an error, not a nil).
  const fs::path late = write_stage(dir.path, "late", "{ tasks = { obstacles = roger.int(0, 3) }, budget = { episodes = 30 },\n"
                                                      "  teacher = function(history, rng)\n"
                                                      "    local wins = 0\n"
                                                      "    for _, h in ipairs(history) do if h.success then wins = wins + 1 end end\n"
                                                      "    if wins < 10 then return { obstacles = rng:int(0, 3) } end\n"
                                                      "    return { obstacles = history[#history].tsak.obstacles }\n"
                                                      "  end }");
  std::vector<std::string> problems = check_curriculum(late.string());
  REQUIRE(problems.size() == 1);
  INFO(problems[0]);
  CHECK_THAT(problems[0], Contains(late.string() + ":13: stage 'S': teacher function: a history entry has no field 'tsak' "
                                    "(did you mean 'task'?); its fields: reward, success, task, time") &&
                              Contains("(before training episode 20) (roger check's history: 10 episodes failed, then "
                                       "10 succeeded)"));
  // A value outside the task space once the learner succeeds: at the function's line.
  const fs::path out = write_stage(dir.path, "out", "{ tasks = { obstacles = roger.int(0, 3) }, budget = { episodes = 30 },\n"
                                                     "  teacher = function(history, rng)\n"
                                                     "    if #history > 0 and history[#history].success then return { obstacles = 4 } end\n"
                                                     "    return {}\n"
                                                     "  end }");
  problems = check_curriculum(out.string());
  REQUIRE(problems.size() == 1);
  INFO(problems[0]);
  CHECK_THAT(problems[0], Contains(out.string() + ":9: stage 'S': teacher function returned obstacles = 4, outside the task "
                                   "space") && Contains("before training episode 11"));
  // The documented example's functions pass.
  CHECK(check_curriculum("docs/examples/teachers_example.lua").empty());
  // No more calls than the budget's episodes (found by a probe: a function failing after ten
  // episodes of a five-episode budget was refused, and trained).
  const fs::path short_budget = write_stage(dir.path, "short", "{ tasks = { obstacles = roger.int(0, 3) }, budget = { episodes = 5 },\n"
                                                               "  checkpoints = { every = 5 },\n"
                                                               "  teacher = function(history, rng)\n"
                                                               "    if #history >= 5 then error('only after five') end\n"
                                                               "    return {}\n"
                                                               "  end }");
  CHECK(check_curriculum(short_budget.string()) == std::vector<std::string>{});
  CHECK_NOTHROW(train_stage(stage_options(short_budget)));
  // A history entry returned whole is told as such (found by a probe: "result.task must be a
  // number, string or boolean, got a table").
  const fs::path entry = write_stage(dir.path, "entry", "{ tasks = { obstacles = roger.int(0, 3) },\n"
                                                        "  teacher = function(history, rng)\n"
                                                        "    if #history > 0 then return history[#history] end\n"
                                                        "    return {}\n"
                                                        "  end }");
  problems = check_curriculum(entry.string());
  REQUIRE(problems.size() == 1);
  CHECK_THAT(problems[0], Contains(entry.string() + ":9: stage 'S': teacher function returned a history entry (its "
                                   "fields task, success, reward, time), not a task: return the entry's task, as "
                                   "`return history[#history].task`"));
  // Found by a probe: check's history had rewards 0 and 1 and a time of 5 s past a 1 s limit, so a
  // function that read them passed here and failed in training. Now as training records them.
  const fs::path reads = write_stage(dir.path, "reads", "{ tasks = { obstacles = roger.int(0, 3) },\n"
                                                        "  teacher = function(history, rng)\n"
                                                        "    for _, h in ipairs(history) do\n"
                                                        "      assert(h.reward == (h.success and 100 or -100), h.reward)\n"
                                                        "      assert(h.time <= 1 and h.time > 0, h.time)\n"
                                                        "    end\n"
                                                        "    return {}\n"
                                                        "  end }");
  CHECK(check_curriculum(reads.string()) == std::vector<std::string>{});
}

// Found by a probe: a teacher function's writes to its history stayed (`history[1].success = 7` was
// seen by every later call, and so was a rawset on it), a misspelt field of an entry's task read as nil, and `roger check
// --set obstacles=2` called the function on tasks holding obstacles, which training (where the
// run fixes it) does not give: check said ok of a function that failed in training.
// Found by a probe: with no episode failed, check said "0 episodes failed, then 1 succeeded".
TEST_CASE("roger check says the history it fed a teacher function plainly", "[teach][errors]") {
  const test::TempDir dir("roger_teach_history_said");
  const fs::path file = write_stage(dir.path, "said", "{ tasks = { obstacles = roger.int(0, 3) }, budget = { episodes = 2 }, "
                                                      "checkpoints = { every = 2 }, teacher = function(history, rng) if #history == 1 then "
                                                      "error('look') end return {} end }");
  const std::vector<std::string> problems = check_curriculum(file.string());
  REQUIRE(problems.size() == 1);
  CHECK_THAT(problems[0], Contains(": look (before training episode 1) (roger check's history: 1 episode succeeded)"));
}

TEST_CASE("a teacher function reads its history read-only and strictly as training gives it", "[teach][errors]") {
  test::TempDir dir("roger_teach_history_view");
  auto problems_of = [&](const std::string& name, const std::string& body, const ParamList& sets = {}) {
    const fs::path path = write_stage(dir.path, name, "{ tasks = { obstacles = roger.int(0, 3), shape = roger.choice{'circle', 'spade'} },\n"
                                                      "  teacher = function(history, rng)\n" + body + "\n"
                                                      "    return {}\n"
                                                      "  end }");
    return std::make_pair(path.string(), check_curriculum(path.string(), {}, sets));
  };
  for (const char* write : {"if #history > 0 then history[1].success = 7 end", "if #history > 0 then history[#history].task.shape = 'x' end",
                            "if #history > 0 then table.remove(history) end", "history[#history + 1] = {}",
                            // Found by a probe: rawset passed the read-only history, and later calls read the value.
                            "rawset(history, 1, 3)", "if #history > 0 then rawset(history[1], 'success', 7) end",
                            "if #history > 0 then rawset(history[1].task, 'shape', 'x') end"}) {
    const auto [path, problems] = problems_of("write", write);
    INFO(write);
    REQUIRE(problems.size() == 1);
    CHECK_THAT(problems[0], Contains(path + ":10: stage 'S': teacher function: the history is read-only"));
  }
  {
    const auto [path, problems] = problems_of("misspelt", "if #history > 0 then local n = history[1].task.obstacls end");
    REQUIRE(problems.size() == 1);
    CHECK_THAT(problems[0], Contains(path + ":10: stage 'S': teacher function: a history entry's task has no field "
                                            "'obstacls' (did you mean 'obstacles'?); its fields: obstacles, shape "
                                            "(before training episode 1) (roger check's history: 1 episode failed)"));
  }
  // Found by a probe: a name read on the list itself (`history.success`) was nil, and the teacher
  // never lifted; the rng's methods there mean the arguments came in the wrong order.
  {
    const auto [path, problems] = problems_of("list_field", "if history.success then return {obstacles = 3} end");
    REQUIRE(problems.size() == 1);
    CHECK_THAT(problems[0], Contains(path + ":10: stage 'S': teacher function: the history is a list of the trial's "
                                            "training episodes, in order, and has no field 'success': read an entry's, "
                                            "history[i].success (the last: history[#history].success, after checking "
                                            "#history > 0)"));
  }
  {
    const auto [path, problems] = problems_of("swapped", "local r = history:int(0, 3)");
    REQUIRE(problems.size() == 1);
    CHECK_THAT(problems[0], Contains(path + ":10: stage 'S': teacher function: the history has no method 'int': a "
                                            "teacher function takes the history first and the rng second, "
                                            "function(history, rng) ... rng:int(...) ... end"));
  }
  // Reading as a teacher reads: #, ipairs, pairs, an index past the end.
  const std::string reads = "local n = 0\n for _, h in ipairs(history) do for k in pairs(h.task) do n = n + 1 end end\n"
                            "    assert(n == 2 * #history and history[#history + 1] == nil)\n"
                            "    assert(rawlen(history) == #history and rawget(history, #history) == history[#history])\n"
                            "    assert(#history == 0 or rawget(history[1], 'task') == history[1].task)";
  CHECK(problems_of("reads", reads).second.empty());
  // Found by a probe: pairs over an entry, or over its task, visited the fields in the order of
  // Lua's string hashes, seeded per state, so a teacher that chose by that order picked other tasks
  // from one seed. Each check is a new state: four of them with the fields in order.
  const std::string in_order = "for _, h in ipairs(history) do\n"
                               "      local keys, axes = {}, {}\n"
                               "      for k in pairs(h) do keys[#keys + 1] = k end\n"
                               "      for k in pairs(h.task) do axes[#axes + 1] = k end\n"
                               "      assert(table.concat(keys, ',') == 'reward,success,task,time', table.concat(keys, ','))\n"
                               "      assert(table.concat(axes, ',') == 'obstacles,shape', table.concat(axes, ','))\n"
                               "    end";
  for (int state = 0; state < 4; ++state) CHECK(problems_of("ordered", in_order).second.empty());
  // Found by a probe: next(history) gave the view's private key, so `next(history) == nil` (the usual
  // test of an empty table) was false for an empty history; and an entry's task given back as it is
  // was refused as "the key a userdata".
  const std::string nexts = "local first = next(history)\n"
                            "    assert((first == nil) == (#history == 0), 'next(history) on ' .. #history)\n"
                            "    if #history > 0 then\n"
                            "      local k, v = next(history[1].task) local n = 0\n"
                            "      while k do assert(history[1].task[k] == v) n = n + 1 k, v = next(history[1].task, k) end\n"
                            "      assert(n == 2 and next(history, #history) == nil)\n"
                            "      assert(select(2, next(history)).task.shape)\n"
                            "    end";
  CHECK(problems_of("nexts", nexts).second.empty());
  const auto [replay_path, replay] = problems_of("replay", "if #history > 0 then return history[#history].task end");
  CHECK(replay.empty());
  // Found by a probe: rng:choice(history) read the view raw and said "the list is empty" with an
  // episode in it; rng:shuffle(history) returned it unshuffled without a word.
  const std::string choose = "if #history > 0 then\n"
                             "      local h = rng:choice(history)\n"
                             "      assert(h.task.shape and h.task == history[1].task or #history > 1)\n"
                             "    end";
  CHECK(problems_of("choose", choose).second.empty());
  const auto [shuffle_path, shuffled] = problems_of("shuffle", "if #history > 0 then rng:shuffle(history) end");
  REQUIRE(shuffled.size() == 1);
  CHECK_THAT(shuffled[0], Contains(shuffle_path + ":10: stage 'S': teacher function: rng:shuffle: shuffles its list in place, "
                                   "and the teacher's history (read-only) cannot change: shuffle a copy"));
  // With --set obstacles=2 a task holds no obstacles, in check as in training, and says why.
  const std::string reader = "if #history > 0 then local n = history[#history].task.obstacles + 1 end";
  CHECK(problems_of("fixed", reader).second.empty());
  const auto [path, problems] = problems_of("fixed", reader, {{"obstacles", "2"}});
  REQUIRE(problems.size() == 1);
  CHECK_THAT(problems[0], Contains("a history entry's task has no field 'obstacles'; its fields: shape (obstacles is "
                                   "fixed for this run, by --set or the batch run's params, and in no task)"));
  // Found by a probe: with every axis fixed, "its fields:  (obstacles is fixed ...)".
  const auto [path2, none] = problems_of("fixed2", reader, {{"obstacles", "2"}, {"shape", "circle"}});
  REQUIRE(none.size() == 1);
  CHECK_THAT(none[0], Contains("a history entry's task has no field 'obstacles'; it has none (obstacles, shape are fixed"));
}

// Found by a probe: a test task the scenario cannot place failed the trial at its first checkpoint
// with the placement's message alone, nothing saying it was a test-set task or which stage.
TEST_CASE("a test-set task that cannot be placed fails its trial naming the test task and the stage", "[teach][errors]") {
  test::TempDir dir("roger_teach_test_hole");
  const fs::path file = write_stage(dir.path, "hole", "{ tasks = { robot_distance = roger.real(0.8, 3.4) }, "
                                                      "test = { list = { { robot_distance = 1 }, { robot_distance = 3.3 } } } }");
  std::string message, where;
  bool placement = false;
  try {
    train_stage(stage_options(file));
  } catch (const EpisodeFault& e) {
    message = e.what();
    where = e.file + ":" + std::to_string(e.line);
    placement = e.no_placement;
    CHECK(e.phase == "checkpoint 1 evaluation");
    CHECK(e.episode == 1);
  }
  INFO(message);
  CHECK(where == file.string() + ":6");
  CHECK(placement);
  CHECK_THAT(message, StartsWith(file.string() + ":6: stage 'S': test task 2 of 2 (robot_distance = 3.3) cannot be "
                                                 "placed in world seed 1000001; the test set is not skipped") &&
                          Contains("The placement failed with: scenarios/lib/place.lua:91: world:sample_position: no "
                                   "placement for 'circle'") &&
                          Contains("(checkpoint 1 evaluation episode 1, world seed 1000001)"));
}

// Found by a probe: LCAS's lifted integer levels were written as 32.0 in episodes.jsonl and as
// strings ("64") in the teacher's state.
TEST_CASE("LCAS writes integer levels as integers in the records and its state", "[teach][stage]") {
  test::TempDir dir("roger_teach_lcas_int");
  const fs::path file = write_stage(dir.path, "lcas", "{ tasks = { obstacles = roger.int(0, 1) }, budget = { episodes = 8 }, "
                                                      "checkpoints = { every = 8 }, "
                                                      "teacher = roger.teacher.lcas{ lift = { eye_pixels = { 32, 64 } }, window = 1, slope = 1 } }");
  const TrainResult r = train_stage(stage_options(file));
  std::set<int64_t> seen;
  for (const auto& e : r.episodes) {
    INFO(e.task.dump());
    REQUIRE(e.task["eye_pixels"].is_number_integer());
    seen.insert(e.task["eye_pixels"].get<int64_t>());
  }
  CHECK(seen == std::set<int64_t>{32, 64});  // slope 1: lifted after the first two windows
  const json& state = r.teacher["state"];
  CHECK(state["value"] == 64);
  CHECK(state["value"].is_number_integer());
  CHECK(state["lifts"][0]["to"] == 64);
  const std::string line = r.episodes.back().task.dump();
  CHECK_THAT(line, Contains("\"eye_pixels\":64") && !Contains("64.0"));
}

// Noticed in a review: a trial whose LCAS teacher lifts a parameter outside its task space
// recorded the scenario's default (eye_pixels 128) as its parameters, though its checkpoints and
// final evaluation ran at the last level; `roger eval --policy` then evaluated the policy with
// eyes its trial's figures never saw.
TEST_CASE("LCAS records the level its evaluations ran at and eval of its policy sets it", "[teach][stage]") {
  test::TempDir dir("roger_teach_lcas_params");
  const fs::path file = write_stage(dir.path, "lcas", "{ budget = { episodes = 4 }, checkpoints = { every = 4, final = 2 }, "
                                                      "teacher = roger.teacher.lcas{ lift = { eye_pixels = { 32, 64 } } } }");
  const TrainResult r = train_stage(stage_options(file));
  auto param = [](const ParamList& params, const std::string& name) {
    for (const auto& [k, v] : params)
      if (k == name) return v;
    return std::string("(absent)");
  };
  CHECK(param(r.params, "eye_pixels") == "64");  // not the scenario's 128
  for (const auto& e : r.episodes) CHECK(e.task["eye_pixels"] == 32);  // window 25: never lifted
  const fs::path out = dir.path / "out";
  write_train_outputs(r, out.string());
  PolicyEvalOptions po;
  po.curriculum = file.string();
  po.policy_file = (out / "policy.json").string();
  po.episodes = 1;
  po.trial_params = true;
  const PolicyEvalResult evaluated = evaluate_policy_file(po);
  CHECK(evaluated.trial_sets == ParamList{{"eye_pixels", "64"}});
  CHECK(param(evaluated.params, "eye_pixels") == "64");
  po.sets = {{"eye_pixels", "128"}};  // a --set of the command wins
  const PolicyEvalResult given = evaluate_policy_file(po);
  CHECK(given.trial_sets.empty());
  CHECK(param(given.params, "eye_pixels") == "128");
}

// Found by a probe: Lua drops extra arguments, so roger.int(0, 3, 1) or roger.converged(c, 0.5)
// ran as if the extra meant something. Each now is refused at its line.
TEST_CASE("the teaching API refuses extra arguments at load with file:line", "[teach][errors]") {
  test::TempDir dir("roger_teach_arity");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{ tasks = { obstacles = roger.int(0, 3, 1) } }", ":8: roger.int: takes 2 arguments (lo, hi), got 3"},
      {"{ tasks = { robot_distance = roger.real(0.8, 1, 2) } }", ":8: roger.real: takes 2 arguments (lo, hi), got 3"},
      {"{ tasks = { shape = roger.choice({ 'circle' }, 2) } }",
       ":8: roger.choice: takes 1 argument (a list of values), got 2"},
      {"{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.random({}, 1) }",
       ":8: roger.teacher.random: takes 1 argument (a table of options), got 2"},
      {"{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.sequence({ { obstacles = 0 } }, 1) }",
       ":8: roger.teacher.sequence: takes 1 argument (a list of steps), got 2"},
      {"{ teacher = roger.teacher.lcas({ lift = { obstacles = { 0, 3 } } }, 1) }",
       ":8: roger.teacher.lcas: takes 1 argument (a table of options), got 2"},
      {"{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.alp_gmm({}, 1) }",
       ":8: roger.teacher.alp_gmm: takes 1 argument (a table of options), got 2"},
      {"{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.plr({}, 1) }",
       ":8: roger.teacher.plr: takes 1 argument (a table of options), got 2"},
      {"{ absorbing = roger.converged(p.phi0, 0.5) }",
       ":8: roger.converged: takes 1 argument (a controller), got 2; to require it to hold for a time, use "
       "roger.held(roger.converged(c), seconds)"},
  };
  for (size_t k = 0; k < cases.size(); ++k) {
    const fs::path file = write_stage(dir.path, "c" + std::to_string(k), cases[k].first);
    const std::string message = load_error(file);
    INFO(cases[k].first << "\n" << message);
    CHECK_THAT(message, Contains(file.filename().string() + cases[k].second));
  }
  // The same calls with the arguments they take.
  for (const std::string fields :
       {"{ tasks = { obstacles = roger.int(0, 3), robot_distance = roger.real(0.8, 1), shape = roger.choice({ 'circle', 'spade' }) }, "
        "teacher = roger.teacher.random({}) }",
        "{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.sequence({ { obstacles = 0 } }) }",
        "{ teacher = roger.teacher.lcas({ lift = { obstacles = { 0, 3 } } }) }",
        "{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.alp_gmm({}) }",
        "{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.plr() }",
        "{ absorbing = roger.held(roger.converged(p.phi0), 0.5) }"}) {
    INFO(fields);
    CHECK_NOTHROW(Curriculum::load(write_stage(dir.path, "ok", fields).string()));
  }
}

// Found by a probe: a window that cannot fill within the budget trained "at step 1 of 2, never
// moved", and roger check said nothing. A warning at the teacher's line (check, and train's note).
TEST_CASE("a teacher whose window cannot fill within the budget is warned of", "[teach][errors]") {
  test::TempDir dir("roger_teach_window");
  auto warning = [&](const std::string& name, const std::string& fields) {
    return Curriculum::load(write_stage(dir.path, name, fields).string()).stage("S").teacher_window_warning();
  };
  // A window that fills only at the last episode counts as none: what it decides sets no episode
  // (found by a probe: "moved at episodes 10, 20" of a 20-episode budget).
  CHECK_THAT(warning("seq", "{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.sequence{ "
                            "{ obstacles = 0, window = 4 }, {} } }"),
             Contains("seq.lua:8: stage 'S': roger.teacher.sequence: step 1's window = 4 is not below the budget's 4 "
                      "episodes: the sequence will never move past it"));
  CHECK_THAT(warning("lcas", "{ teacher = roger.teacher.lcas{ lift = { eye_pixels = { 32, 64 } }, window = 2 } }"),
             Contains("lcas.lua:8: stage 'S': roger.teacher.lcas: window = 2 needs 4 episodes at a level (two windows) "
                      "before it can lift eye_pixels, not fewer than the budget's 4 episodes"));
  // Found by a probe: ALP-GMM's first fit after the budget trained a uniform teacher without a word.
  CHECK_THAT(warning("alp", "{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.alp_gmm{ fit_every = 4 } }"),
             Contains("alp.lua:8: stage 'S': roger.teacher.alp_gmm: fit_every = 4 is not below the budget's 4 episodes: "
                      "it will never fit its mixture before the last episode, and draws every task uniformly"));
  // Found by a probe: windows each within the budget that together are not, and two teachers that
  // are random{} under another name, were said nothing of.
  CHECK_THAT(warning("seq_sum", "{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.sequence{ "
                                "{ obstacles = 0, window = 2 }, { obstacles = 1, window = 2 }, {} } }"),
             Contains("seq_sum.lua:8: stage 'S': roger.teacher.sequence: steps 1 to 2 need 4 episodes (a full window "
                      "each) before step 3, not fewer than the budget's 4 episodes: no episode will train at step 3"));
  CHECK_THAT(warning("alp_random", "{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.alp_gmm{ "
                                   "fit_every = 2, random_share = 1 } }"),
             Contains("random_share = 1 draws every task uniformly: it never uses its mixture"));
  CHECK_THAT(warning("plr_never", "{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.plr{ replay = 0 } }"),
             Contains("replay = 0 never replays a level: it draws every task afresh"));
  // Windows that fit, and a last step's (it never moves on), say nothing.
  CHECK(warning("fits", "{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.sequence{ "
                        "{ obstacles = 0, window = 3 }, { window = 100 } } }").empty());
  CHECK(warning("lcas_fits", "{ teacher = roger.teacher.lcas{ lift = { eye_pixels = { 32, 64 } }, window = 1 } }").empty());
  CHECK(warning("alp_fits", "{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.alp_gmm{ fit_every = 3 } }").empty());
  // Found by a probe: 7 levels of window 10 in 60 episodes reached level 2, and the test set ran
  // at level 7, which no episode had trained at. Each lift needs two windows.
  CHECK_THAT(warning("levels", "{ teacher = roger.teacher.lcas{ lift = { eye_pixels = { 32, 64, 128 } }, window = 1 } }"),
             Contains("levels.lua:8: stage 'S': roger.teacher.lcas: its 3 levels of eye_pixels need 4 episodes (two "
                      "windows of 1 per lift) before the last, not fewer than the budget's 4 episodes: no episode will "
                      "train at eye_pixels = 128, the level the test set runs at"));
  // Found by a probe: a lifted parameter that is an axis of the task space is drawn over the whole
  // axis by the test set; the warning said the test set ran at the last level.
  CHECK_THAT(warning("in_space", "{ tasks = { obstacles = roger.int(0, 4) }, "
                                 "teacher = roger.teacher.lcas{ lift = { obstacles = { 0, 2, 4 } }, window = 2 } }"),
             Contains("it will never lift it, and the test set draws it over its whole axis, where no episode "
                      "trained past the first level"));
  CHECK_THAT(warning("in_space_levels", "{ tasks = { obstacles = roger.int(0, 4) }, "
                                        "teacher = roger.teacher.lcas{ lift = { obstacles = { 0, 2, 4 } }, window = 1 } }"),
             Contains("no episode will train at obstacles = 4, a level the test set draws tasks at"));
  // Found by a probe: replay = 1 replayed the first level for the whole budget.
  CHECK_THAT(warning("plr", "{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.plr{ replay = 1 } }"),
             Contains("plr.lua:8: stage 'S': roger.teacher.plr: replay = 1 replays a seen level at every episode: "
                      "after the first it never draws a new one, and trains on that one task for the whole budget"));
  CHECK(warning("plr_fits", "{ tasks = { obstacles = roger.int(0, 3) }, teacher = roger.teacher.plr{ replay = 0.9 } }").empty());
  const std::string roger = ROGER_BINARY, said = (dir.path / "said.txt").string();
  CHECK(run_shell(roger + " check " + (dir.path / "seq.lua").string() + " > " + said + " 2>&1") == 0);
  CHECK_THAT(slurp(said), Contains("roger: warning: ") && Contains("seq.lua:8: stage 'S': roger.teacher.sequence: step 1's window"));
}

// Found by a probe: a by table over a real parameter put its bins in the order of their text
// ("13.39 to 18.35" before "3.47 to 8.43"), a false trend read left to right.
TEST_CASE("a by table's bins of a real parameter run from its least value to its greatest", "[teach][stage]") {
  test::TempDir copy("roger_teach_bins");
  fs::copy(teach_batch(), copy.path, fs::copy_options::recursive);
  // Every final episode of one trial given a level of its own, from 0.5 to 25: bins whose edges
  // pass from one digit to two, which the order of their text put out of order.
  const fs::path records = copy.path / "trials" / "Random" / "A" / "000" / "final.jsonl";
  std::istringstream in(slurp(records));
  std::vector<json> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(json::parse(line));
  REQUIRE(lines.size() > 8);
  std::ostringstream out;
  for (size_t k = 0; k < lines.size(); ++k) {
    lines[k]["task"]["level"] = 0.5 + 24.5 * double(k) / double(lines.size() - 1);
    out << lines[k].dump() << "\n";
  }
  std::ofstream(records) << out.str();
  REQUIRE(run_shell(std::string(ROGER_BINARY) + " report " + copy.path.string() + " --by level > /dev/null") == 0);
  const std::string tables = slurp(copy.path / "tables.md");
  std::vector<double> edges;
  for (size_t at = tables.find("| level = "); at != std::string::npos && edges.size() < 5;
       at = tables.find("| level = ", at + 1))
    edges.push_back(std::strtod(tables.c_str() + at + 10, nullptr));
  INFO(tables);
  REQUIRE(edges.size() == 5);
  CHECK(edges.back() > 10.0);  // edges of one digit and of two
  CHECK(std::is_sorted(edges.begin(), edges.end()));
}

// Found by a probe: a test list's entry that is not a task was reported at the roger.stage{ line,
// where every other mistake of `test` is at its own line.
TEST_CASE("a test list's bad entry is reported at the line of test", "[teach][errors]") {
  test::TempDir dir("roger_teach_test_line");
  const fs::path file = dir.path / "listed.lua";
  std::ofstream(file) << "local p = { phi0 = roger.primitive('phi0') }\n"
                         "return { stages = { roger.stage{ name = 'S', scenario = 'cluttered', time_limit = 1,\n"
                         "  absorbing = roger.converged(p.phi0), budget = { episodes = 4 }, checkpoints = { every = 4 },\n"
                         "  contexts = { { name = 'A', actions = { p.phi0 } } },\n"
                         "  tasks = { obstacles = roger.int(0, 3) },\n"
                         "  test = { list = { { obstacles = 1 }, 5 } },\n"
                         "} } }\n";
  CHECK_THAT(load_error(file), Contains("listed.lua:6: stage 'S': test: list[2]"));
}
