// Tests of the teachers (engine/teach, docs/curricula.md "Teachers"): task spaces, each teacher
// against a simulated learner whose answer is known, the Gaussian mixtures ALP-GMM fits; then the
// teachers in real stages through the trainer (tests/scripts/teach_*.lua): where each samples,
// what is recorded, determinism across --jobs, and bad input refused at file:line.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <set>

#include "core/error.h"
#include "core/rng.h"
#include "teach/teach.h"
#include "teach/teach_internal.h"

using namespace roger;
using Catch::Matchers::Contains;

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
  CHECK_FALSE(s.task_of({{"obstacles", "1"}, {"shape", "spade"}}, &why));
  CHECK(why == "no value for 'robot_distance' (roger.real(0.8, 2))");
  CHECK_FALSE(s.task_of({{"mass", "1"}}, &why));
  CHECK_THAT(why, Contains("'mass' is not a parameter of the task space"));

  CHECK_THROWS_WITH(TaskSpace({int_dim("obstacles", 4, 2)}), Contains("reversed"));
  CHECK_THROWS_WITH(TaskSpace({real_dim("d", 1, 1)}), Contains("empty"));
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
  CHECK_THROWS_WITH(restrict_space(s, {choice_dim("shape", {"square"})}), Contains("outside"));
  CHECK_THROWS_WITH(restrict_space(s, {int_dim("mass", 0, 1)}), Contains("not a parameter"));
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
