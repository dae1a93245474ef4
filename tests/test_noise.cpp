// test_noise.cpp: the sensor and actuator noise (senses/noise.cpp, world:robot{ noise = ... }):
// refused when out of range, seeded by the world's seed alone, nothing when its sigmas are 0, never
// read by a judge, and the scripted task still done under the moderate level M.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <filesystem>
#include <fstream>
#include <string>

#include "batch/batch.h"
#include "control/agent.h"
#include "learn/episode.h"
#include "script/curriculum/curriculum.h"
#include "script/scenario/scenario.h"
#include "script/skills/skill_script.h"
#include "senses/noise.h"
#include "sim/world.h"
#include "scenario_text.h"
#include "world_fixtures.h"

using namespace roger;
using Catch::Matchers::Contains;
using roger::test::robot_error;

namespace {

// The moderate level M (docs/results.md, Noise), scaled.
NoiseParams moderate(double scale) {
  return NoiseParams{10.0 * scale, 0.01 * scale, 0.01 * scale, 0.1 * scale, 0.1 * scale};
}

// The scenario parameters of M, scaled, on a loaded scenario.
void set_moderate(Scenario& s, double scale) {
  const std::pair<const char*, const char*> m[] = {{"noise_image", "10"},  {"noise_joints", "0.01"},
                                                   {"noise_base", "0.01"}, {"noise_touch", "0.1"},
                                                   {"noise_effort", "0.1"}};
  for (const auto& [k, v] : m) s.set_param(k, v);
  s.set_param("noise_scale", std::to_string(scale));
}

// Whether two sets of senses agree to the bit in what the controllers read.
bool same_senses(const Senses& a, const Senses& b) {
  bool same = std::memcmp(a.q.data(), b.q.data(), sizeof(double) * kDofCount) == 0 &&
              std::memcmp(&a.base, &b.base, sizeof a.base) == 0 && a.stereo_valid == b.stereo_valid &&
              std::memcmp(a.stimulus_world.data(), b.stimulus_world.data(), 2 * sizeof(double)) == 0;
  for (int e = 0; e < 2; ++e) {
    same = same && a.stimulus[e].seen == b.stimulus[e].seen && a.stimulus[e].bearing == b.stimulus[e].bearing;
    same = same && std::memcmp(a.image[e].stimulus.data(), b.image[e].stimulus.data(), sizeof(float) * 128) == 0;
    for (int u = 0; u < 128; ++u) same = same && a.image[e].colour[u] == b.image[e].colour[u];
  }
  for (int t = 0; t < kTactileCount; ++t) same = same && a.touch[t].force == b.touch[t].force;
  return same;
}

// Drives a world with a fixed command for `ticks` ticks and returns its state hash.
uint64_t drive(World& w, const WorldSpec& spec, int ticks) {
  w.reset(spec);
  DofVector cmd = DofVector::Zero();
  cmd[kBaseForward] = 0.05, cmd[kBaseHeading] = 0.05, cmd[kLeftEye] = 0.1, cmd[kLeftShoulder] = 0.1;
  for (int i = 0; i < ticks; ++i) {
    w.command(cmd);
    w.tick();
  }
  return w.state_hash();
}

// Replays recorded errors, one per tick: a trajectory that owes nothing to what the senses say.
class Replay final : public Controller {
 public:
  explicit Replay(std::vector<DofVector> errors) : errors_(std::move(errors)) { set_name("replay"); }
  const char* kind() const override { return "replay"; }

 protected:
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    out.command = errors_[std::min<size_t>(in.tick, errors_.size() - 1)];
    gamma = Gamma::kNotConv;
  }

 private:
  std::vector<DofVector> errors_;
};

}  // namespace

TEST_CASE("world:robot refuses bad noise with the file, line, field and range", "[noise]") {
  CHECK_THAT(robot_error("noise_image", "{ x = 0, y = 0, noise = { image = 300 } }"),
             Contains("roger_test_noise_image.lua:2:") &&
                 Contains("world:robot: noise: field 'image' must be within [0, 255] colour levels, got 300"));
  CHECK_THAT(robot_error("noise_negative", "{ x = 0, y = 0, noise = { joints = -0.1 } }"),
             Contains(":2:") && Contains("field 'joints' must be within [0, 1] rad, got -0.1"));
  CHECK_THAT(robot_error("noise_unknown", "{ x = 0, y = 0, noise = { odometry = 1 } }"),
             Contains(":2:") && Contains("unknown field 'odometry'; known fields: base, effort, image, joints, touch"));
  CHECK_THAT(robot_error("noise_type", "{ x = 0, y = 0, noise = 3 }"), Contains(":2:") && Contains("noise"));
  Scenario s = Scenario::load("unobstructed");
  set_moderate(s, 2.0);
  const WorldSpec w = s.generate(5);
  CHECK(w.noise.image == 20.0);
  CHECK(w.noise.joints == 0.02);
  CHECK(w.noise.effort == 0.2);
  CHECK(w.noise.any());
  CHECK(!Scenario::load("unobstructed").generate(5).noise.any());
}

TEST_CASE("sigma 0 is no noise, to the bit", "[noise]") {
  WorldSpec plain = test::open_world();
  plain.seed = 42;
  WorldSpec zero = plain;
  zero.noise = NoiseParams{0.0, 0.0, 0.0, 0.0, 0.0};
  World a, b;
  CHECK(drive(a, plain, 150) == drive(b, zero, 150));
  CHECK(same_senses(a.senses(), b.senses()));
  CHECK(&a.senses() == &a.true_senses());
  // Each kind alone moves something (so the comparison above could fail).
  for (int k = 0; k < 5; ++k) {
    WorldSpec one = plain;
    double* sigma[5] = {&one.noise.image, &one.noise.joints, &one.noise.base, &one.noise.touch, &one.noise.effort};
    *sigma[k] = k == 0 ? 10.0 : 0.1;
    World c;
    const uint64_t h = drive(c, one, 150);
    INFO("noise kind " << k);
    if (k == 4) CHECK(h != drive(a, plain, 150));  // effort moves the world
    else if (k != 3) CHECK(!same_senses(c.senses(), c.true_senses()));
  }
}

TEST_CASE("the noise is a function of the world's seed alone", "[noise]") {
  WorldSpec spec = test::open_world();
  spec.seed = 7;
  spec.noise = moderate(2.0);
  World a, b, c;
  const uint64_t h = drive(a, spec, 200);
  drive(b, test::open_world(), 37);  // another world first: nothing of it carries over
  CHECK(drive(b, spec, 200) == h);
  CHECK(same_senses(a.senses(), b.senses()));
  spec.seed = 8;
  CHECK(drive(c, spec, 200) != h);
}

TEST_CASE("image noise moves colours and coverage but keeps the stimulus found", "[noise]") {
  World w;
  w.reset(test::open_world());
  EyeImage image = w.true_senses().image[kLeft];
  const Sighting truth = detect_stimulus(image);
  REQUIRE(truth.seen);
  Rng rng(3);
  add_image_noise(image, 10.0, rng);
  int moved = 0, stray = 0;
  for (int u = 0; u < image.pixels(); ++u) {
    moved += image.colour[u] != w.true_senses().image[kLeft].colour[u];
    stray += image.stimulus[u] > 0.0f && w.true_senses().image[kLeft].stimulus[u] == 0.0f &&
             std::abs(u - truth.u) > 0.5 * (truth.u_hi - truth.u_lo) + 1.5;
  }
  CHECK(moved > image.pixels() / 2);
  CHECK(stray == 0);  // no pixel of wall reads as the red ball at 10 levels
  const Sighting noisy = detect_stimulus(image);
  REQUIRE(noisy.seen);
  CHECK(std::abs(noisy.u - truth.u) < 0.3);
  CHECK(image.noisy);
}

TEST_CASE("touch and effort noise scale forces by about their sigma", "[noise]") {
  Senses s;
  s.touch[kLeftHand].contact = true;
  s.touch[kLeftHand].force = 10.0;
  Rng rng(11);
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < 2000; ++i) {
    Senses z = s;
    add_touch_noise(z, 0.1, rng);
    sum += z.touch[kLeftHand].force, sum2 += z.touch[kLeftHand].force * z.touch[kLeftHand].force;
    CHECK(z.touch[kBody].force == 0.0);
  }
  const double mean = sum / 2000, sd = std::sqrt(sum2 / 2000 - mean * mean);
  CHECK(mean == Approx(10.0).epsilon(0.02));
  CHECK(sd == Approx(1.0).epsilon(0.1));
  DofVector f = DofVector::Ones();
  draw_effort_noise(f, 0.0, rng);
  CHECK(f == DofVector::Ones());
  draw_effort_noise(f, 0.1, rng);
  CHECK(f != DofVector::Ones());
}

// The judges read the true world: the object map's `held` follows the true touch, whatever the
// noisy touch says.
TEST_CASE("no noise reaches the object map's held", "[noise]") {
  const SkillScript script = SkillScript::load("curricula/scripted.lua");
  const SkillScript::NamedPolicy& task = script.policy("search_grasp");
  Scenario scenario = Scenario::load("unobstructed");
  set_moderate(scenario, 2.0);
  scenario.set_param("noise_touch", "1");  // forces that swing by their own size
  Agent agent;
  agent.reset(scenario.generate(7390001));
  reset_predicate(*task.goal, 7390001);
  task.action->reset(7390001);
  int differ = 0, ticks = 0;
  for (; ticks < 250; ++ticks) {
    agent.step(*task.action);
    const Senses& truth = agent.world().true_senses();
    for (size_t i = 0; i < agent.objects().size(); ++i) {
      bool held = false;
      for (const Touch& t : truth.touch) held |= t.contact && t.kind == SurfaceKind::kObject && t.index == int(i);
      CHECK(agent.objects()[i].held == held);
    }
    for (int t = 0; t < kTactileCount; ++t)
      differ += agent.world().senses().touch[t].force != truth.touch[t].force;
  }
  CHECK(differ > 0);  // the controllers did read other forces
}

// The scripted task exercises every primitive: phi6 search and phi0, search_grasp phi1, phi2, phi4
// and phi3, the task the carrying phi1 and phi5 too. Each part is done under M in (nearly) every
// world of both scenarios, and the task under 4M in most.
TEST_CASE("the scripted task and its parts are done under the moderate noise M", "[noise]") {
  const SkillScript script = SkillScript::load("curricula/scripted.lua");
  const std::pair<const char*, double> runs[] = {{"phi6", 1.0}, {"search_grasp", 1.0}, {"task", 1.0}, {"task", 4.0}};
  for (const auto& [policy, scale] : runs) {
    const SkillScript::NamedPolicy& task = script.policy(policy);
    EpisodeOptions options;
    options.time_limit = task.time_limit;
    for (const char* world : {"unobstructed", "cluttered"}) {
      Scenario scenario = Scenario::load(world);
      set_moderate(scenario, scale);
      const EvalSummary r = evaluate_action([&](uint64_t s) { return scenario.generate(s); }, *task.action,
                                            *task.goal, 20, 7380000, options);
      INFO(policy << " in " << world << " at " << scale << " M");
      CHECK(r.successes >= (scale == 1.0 ? 19 : 16));
    }
  }
}

// Mixed noise levels on one agent give each episode what a fresh agent gives it.
TEST_CASE("an episode's noise owes nothing to the previous episode's", "[noise]") {
  const SkillScript script = SkillScript::load("curricula/scripted.lua");
  const SkillScript::NamedPolicy& task = script.policy("task");
  EpisodeOptions options;
  options.time_limit = task.time_limit;
  std::vector<Scenario> scenarios;
  for (double scale : {0.0, 1.0, 4.0}) {
    scenarios.push_back(Scenario::load("cluttered"));
    set_moderate(scenarios.back(), scale);
  }
  auto make = [&](uint64_t seed) { return scenarios[seed % scenarios.size()].generate(seed); };
  const EvalSummary mixed = evaluate_action(make, *task.action, *task.goal, 6, 7370000, options);
  for (const EpisodeResult& r : mixed.results) {
    const EvalSummary alone = evaluate_action(make, *task.action, *task.goal, 1, r.seed, options);
    INFO("seed " << r.seed);
    CHECK(alone.results[0].ticks == r.ticks);
    CHECK(alone.results[0].reward == r.reward);
    CHECK(alone.results[0].success == r.success);
  }
}

// Episodes under noise run as a batch's trials, one or three at a time: the same results, as the
// noise is a function of the world's seed alone, not of the thread or the order.
TEST_CASE("noisy episodes do not depend on the number of jobs", "[noise]") {
  auto episode = [](const std::string& id, const std::string&) {
    const SkillScript script = SkillScript::load("curricula/scripted.lua");
    const SkillScript::NamedPolicy& task = script.policy("task");
    Scenario scenario = Scenario::load("cluttered");
    set_moderate(scenario, 2.0);
    EpisodeOptions options;
    options.time_limit = task.time_limit;
    const uint64_t seed = 7360000 + std::stoull(id.substr(id.find('-') + 1));
    const EvalSummary r = evaluate_action([&](uint64_t s) { return scenario.generate(s); }, *task.action,
                                          *task.goal, 1, seed, options);
    return nlohmann::json{{"ticks", r.results[0].ticks}, {"reward", r.results[0].reward},
                          {"success", r.results[0].success}};
  };
  std::vector<std::string> ids;
  for (int i = 0; i < 6; ++i) ids.push_back("noise/seed-" + std::to_string(i));
  const auto dir = std::filesystem::temp_directory_path() / "roger_test_noise_jobs";
  std::filesystem::remove_all(dir);
  const auto one = run_trials(ids, episode, BatchOptions{1, (dir / "one").string()});
  const auto three = run_trials(ids, episode, BatchOptions{3, (dir / "three").string()});
  REQUIRE(one.size() == ids.size());
  for (size_t i = 0; i < ids.size(); ++i) {
    INFO(ids[i]);
    CHECK(one[i].ok);
    CHECK(one[i].result == three[i].result);
  }
  std::filesystem::remove_all(dir);
}

// The task's absorbing predicate reads controllers, and the actions' controllers read the noisy
// senses; the judge (Judge) asks copies of them reading the true senses. Its phi1 converges on the
// carried object's centre as Roger's body places it (0.36 m ahead of the base), so even without
// noise the true centre ends up to 0.30 m from the region's (radius 0.25 m). Each episode the judge
// calls done under M and 2M must be done in the true world: the object's centre within 0.1 m of
// the region's edge, and the object touched by Roger as the true touch has it. (At 4M the grasp
// slips in the hands, so the object may lie up to 0.15 m beyond the edge when Roger's body is at
// the goal: the judge reads the true world, but phi1 places the carried object by the body.)
TEST_CASE("the task done under noise is done in the true world", "[noise]") {
  const SkillScript script = SkillScript::load("curricula/scripted.lua");
  const SkillScript::NamedPolicy& task = script.policy("task");
  for (double scale : {0.0, 1.0, 2.0}) {
    Scenario scenario = Scenario::load("unobstructed");
    set_moderate(scenario, scale);
    int done = 0;
    for (uint64_t seed = 7350000; seed < 7350040; ++seed) {
      Agent agent;
      agent.reset(scenario.generate(seed));
      task.action->reset(seed);
      reset_predicate(*task.goal, seed);
      Judge judge(task.goal.get());
      judge.reset(seed);
      bool holds = false;
      for (int t = 0; t < 500 && !holds; ++t) {
        agent.step(*task.action);
        holds = judge.holds(agent.input());
      }
      if (!holds) continue;
      ++done;
      const GoalRegion& g = agent.world().spec().goals.at(0);
      const double d = (agent.objects()[0].center - g.center).norm();
      INFO("seed " << seed << " at " << scale << " M: the object's centre " << d << " m from the region's");
      CHECK(d < g.radius + 0.1);
      CHECK(agent.objects()[0].held);
    }
    INFO("at " << scale << " M");
    CHECK(done >= 39);
  }
}

// Under noise the judge reads the true world through copies of the goal's controllers (Judge).
// Without noise the copies must judge exactly as the goal itself: every episode of the task and
// its parts ends on the same tick with the same outcome whether the judge asks the goal or its
// copies, so what judging through copies adds under noise is the true senses and nothing else.
TEST_CASE("judging the goal through copies of its controllers changes nothing without noise", "[noise]") {
  const SkillScript script = SkillScript::load("curricula/scripted.lua");
  AgentParams copies;
  copies.always_judge_truth = true;
  for (const char* policy : {"phi6", "search_grasp", "task"}) {
    const SkillScript::NamedPolicy& task = script.policy(policy);
    EpisodeOptions options;
    options.time_limit = task.time_limit;
    for (const char* world : {"unobstructed", "cluttered"}) {
      Scenario scenario = Scenario::load(world);
      Agent plain, judged(WorldParams{}, copies);
      int successes = 0;
      for (uint64_t seed = 7340000; seed < 7340015; ++seed) {
        const WorldSpec spec = scenario.generate(seed);
        const EpisodeResult a = run_episode(plain, spec, seed, *task.action, *task.goal, options);
        const EpisodeResult b = run_episode(judged, spec, seed, *task.action, *task.goal, options);
        INFO(policy << " in " << world << ", seed " << seed);
        CHECK(a.success == b.success);
        CHECK(a.ticks == b.ticks);
        CHECK(plain.world().state_hash() == judged.world().state_hash());
        successes += a.success;
      }
      INFO(policy << " in " << world);
      CHECK(successes >= 13);  // the comparison is between episodes that end in success (13-15 of 15)
    }
  }
}

// No noise reaches a judge: the same true trajectory, sensed without noise and with 8M on every
// sense, gets the same verdict from the task's judge at every tick. The trajectory is a successful
// noise-free episode's errors replayed without the gaze reflex (the motors' effort noise is off, so
// the senses' noise cannot move the robot). The goal asked directly on the noisy senses does
// disagree on some tick, so the noise would have reached it.
TEST_CASE("no noise reaches the task's judge", "[noise]") {
  const SkillScript script = SkillScript::load("curricula/scripted.lua");
  const SkillScript::NamedPolicy& task = script.policy("task");
  AgentParams replaying;
  replaying.gaze_reflex = false;
  int disagreements = 0, verdicts = 0;
  for (uint64_t seed = 7330000; seed < 7330006; ++seed) {
    Scenario clean = Scenario::load("unobstructed"), noisy = Scenario::load("unobstructed");
    set_moderate(noisy, 8.0);
    noisy.set_param("noise_effort", "0");
    Agent recorder;
    recorder.reset(clean.generate(seed));
    task.action->reset(seed);
    reset_predicate(*task.goal, seed);
    std::vector<DofVector> errors;
    for (bool done = false; !done && errors.size() < 500;) {
      recorder.step(*task.action);
      errors.push_back(recorder.last_errors());
      done = task.goal->holds(recorder.input());
    }
    Replay replay(errors);
    Agent a(WorldParams{}, replaying), b(WorldParams{}, replaying);
    a.reset(clean.generate(seed));
    b.reset(noisy.generate(seed));
    Judge judge_a(task.goal.get());
    std::shared_ptr<Predicate> goal_b = duplicate(task.goal, *std::make_unique<Duplicates>());
    Judge judge_b(goal_b.get());
    reset_predicate(*task.goal, seed), reset_predicate(*goal_b, seed);
    judge_a.reset(seed), judge_b.reset(seed);
    for (size_t t = 0; t < errors.size() + 50; ++t) {
      a.step(replay), b.step(replay);
      REQUIRE(a.world().state_hash() == b.world().state_hash());
      const bool verdict = judge_a.holds(a.input());
      INFO("seed " << seed << ", tick " << t);
      CHECK(judge_b.holds(b.input()) == verdict);
      verdicts += verdict;
      disagreements += goal_b->holds(b.input()) != verdict;
    }
  }
  INFO(verdicts << " ticks judged done, " << disagreements << " where the noisy goal disagreed");
  CHECK(verdicts > 0);
  CHECK(disagreements > 0);
}

// A stereo fix that jumps: with M's 0.01 rad on the eye pans, a fix at 2 m is off by about half a
// metre (the eyes are 0.16 m apart). Fused over the ticks (StereoFilter) the estimate the
// controllers read is off by about half as much, measured against the fix the true senses make
// (the mean of fixes whose range is the baseline over a noisy vergence keeps some of their bias).
TEST_CASE("under noise the stereo fixes are fused into a steady estimate", "[noise]") {
  const SkillScript script = SkillScript::load("curricula/scripted.lua");
  const SkillScript::NamedPolicy& task = script.policy("search_grasp");
  Scenario scenario = Scenario::load("unobstructed");
  set_moderate(scenario, 1.0);
  double raw2 = 0.0, fused2 = 0.0;
  int n = 0;
  for (uint64_t seed = 7320000; seed < 7320010; ++seed) {
    Agent agent;
    agent.reset(scenario.generate(seed));
    task.action->reset(seed);
    for (int t = 0; t < 250; ++t) {
      agent.step(*task.action);
      const VisualObject& o = agent.percepts().object;
      const Senses& true_senses = agent.world().true_senses();
      if (!o.seen || o.by_touch || !agent.world().senses().stereo_valid || !true_senses.stereo_valid) continue;
      const Vec2 truth = true_senses.stimulus_world;  // the fix without noise
      raw2 += (agent.world().senses().stimulus_world - truth).squaredNorm();
      fused2 += (o.center - truth).squaredNorm();
      ++n;
    }
  }
  REQUIRE(n > 500);
  const double raw = std::sqrt(raw2 / n), fused = std::sqrt(fused2 / n);
  INFO("RMS error of the fixes " << raw << " m, of the fused estimate " << fused << " m, over " << n << " ticks");
  CHECK(raw > 0.2);
  CHECK(fused < 0.6 * raw);  // 0.15 m against 0.29 m
}

// A CONV that flickers: every change of an action's state is a decision of the learner, so a
// state that flips with the noise multiplies the decisions and slows learning (SG under M took
// 240-390 episodes to its threshold instead of 20-30 before the fixes were fused). The states of
// SG's actions in B1 over search-grasp episodes under M change about as often as without noise.
TEST_CASE("under M the actions' states change about as often as without noise", "[noise]") {
  Curriculum cur = Curriculum::load("paper");
  const CurriculumContext& b1 = cur.stage("SG").context("B1");
  const SkillScript script = SkillScript::load("curricula/scripted.lua");
  const SkillScript::NamedPolicy& task = script.policy("search_grasp");
  int changes[2] = {0, 0};
  for (int noisy = 0; noisy < 2; ++noisy) {
    Scenario scenario = Scenario::load("unobstructed");
    set_moderate(scenario, noisy);
    for (uint64_t seed = 7310000; seed < 7310020; ++seed) {
      Agent agent;
      EpisodeOptions options;
      options.time_limit = task.time_limit;
      const EpisodeResult r = run_episode(agent, scenario.generate(seed), seed, *task.action, *task.goal, options, b1.actions);
      for (const GammaTrace& g : r.gammas)
        for (size_t t = 1; t < g.states.size(); ++t) changes[noisy] += g.states[t] != g.states[t - 1];
    }
  }
  INFO(changes[0] << " changes of state without noise, " << changes[1] << " under M");
  CHECK(changes[0] > 100);
  CHECK(changes[1] < 1.5 * changes[0]);
}
