// Tests of the sorting task (Figure 1: scenarios/sorting.lua, curricula/sorting.lua): the scenario
// makes worlds with every object placed and reachable, the curriculum's Lua reward and absorbing
// function see the world and their errors name file:line, the hand-written policy sorts two
// objects, an episode of many objects owes nothing to the ones before it, and the learned
// transport skill is loaded from its file, not trained again.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

#include "batch/trainer.h"
#include "control/agent.h"
#include "control/primitives.h"
#include "control/planner.h"
#include "core/error.h"
#include "script/curriculum/curriculum.h"
#include "script/scenario/scenario.h"
#include "learn/episode.h"
#include "script/skills/skill_script.h"
#include "sim/occupancy.h"

using namespace roger;
namespace fs = std::filesystem;

namespace {

// The message of the error `f` throws ("" when none).
std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// Whether a free path joins `from` to the disk (center, radius) on the planner's grid (obstacles
// inflated as the agent inflates them).
bool joined(const OccupancyGrid& grid, const Vec2& from, const Vec2& center, double radius) {
  HarmonicPlanner planner;
  planner.set_grid(grid);
  planner.set_goal(center, radius);
  return planner.update_reachability() && planner.reachable(from);
}

Shape disk(const Vec2& c, double r) {
  Shape s;
  s.name = "disk";
  s.disks.push_back(Disk{c, r});
  return s;
}

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

}  // namespace

TEST_CASE("sorting: 50 seeds of eight objects and four obstacles, no overlaps, every object reachable",
          "[sorting]") {
  Scenario s = Scenario::load("scenarios/sorting.lua");
  s.set_param("objects", "8");
  s.set_param("obstacles", "4");
  const double approach = 0.58;  // phi1's approach ring around an object
  for (const char* mix : {"cycle", "random"}) {
    s.set_param("mix", mix);
    for (uint64_t seed = 0; seed < 50; ++seed) {
      INFO(mix << " seed " << seed);
      const WorldSpec w = s.generate(seed);
      REQUIRE(w.objects.size() == 8);
      REQUIRE(w.obstacles.size() == 4);
      REQUIRE(w.goals.size() == 4);
      const OccupancyGrid grid = build_occupancy(w, body_metrics(w.body, w.eyes).grid_inflate);
      const Vec2 start(w.robot.pose.x, w.robot.pose.y);
      for (size_t i = 0; i < w.objects.size(); ++i) {
        const ObjectSpec& o = w.objects[i];
        INFO(o.name);
        // Its type's region is named after it and drawn in its colour.
        const std::string type = o.name.substr(0, o.name.find(' '));
        const auto region = std::find_if(w.goals.begin(), w.goals.end(), [&](const GoalRegion& g) { return g.name == type; });
        REQUIRE(region != w.goals.end());
        for (size_t j = 0; j < i; ++j) CHECK(shape_gap(o.shape, o.pose, w.objects[j].shape, w.objects[j].pose) > 0.0);
        for (const auto& ob : w.obstacles) CHECK(shape_gap(o.shape, o.pose, ob.shape, ob.pose) > 0.0);
        for (const auto& g : w.goals) CHECK(shape_gap(o.shape, o.pose, disk(g.center, g.radius), Pose{}) > 0.0);
        for (const auto& d : robot_footprint(w.robot)) CHECK(shape_gap(o.shape, o.pose, disk(d.center, d.radius), Pose{}) > 0.0);
        // Roger can reach the object, and carry it from there to its region.
        const Vec2 at(o.pose.x, o.pose.y);
        CHECK(joined(grid, start, at, approach));
        CHECK(joined(grid, at, region->center, region->radius));
      }
    }
  }
}

TEST_CASE("sorting: the Lua reward and absorbing function see the world; their errors name file:line",
          "[sorting]") {
  const fs::path dir = temp_dir("roger_sorting_lua");
  // A stage whose absorbing function reads the world and whose reward raises once an object has
  // been seen: both must be called (the reward is asked at the time-out at the latest).
  const std::string script = R"(local p = roger.primitive("search")
local seen = 0
local function absorbing(state, time, world)
  seen = #world.objects + #world.goals
  return false
end
local function reward(state, action, event, time, world)
  if world.objects[1].name ~= "circle 1" then error("the world is not the sorting world") end
  error("reward saw " .. seen .. " things")
end
return { name = "probe", stages = { roger.stage{
  name = "S", scenario = "sorting", time_limit = 0.5, absorbing = absorbing, reward = reward,
  learner = { alpha = 0.1, discount = 0.9 }, budget = { episodes = 1 },
  checkpoints = { every = 1, episodes = 1, final = 1 },
  contexts = { { name = "A", actions = { p } } } } } }
)";
  std::ofstream(dir / "probe.lua") << script;
  TrainOptions o;
  o.curriculum = (dir / "probe.lua").string();
  o.stage = "S";
  o.context = "A";
  const std::string m = error_of([&] { train_stage(o); });
  INFO(m);
  CHECK(m.find("probe.lua:9:") != std::string::npos);  // the reward's error(...)
  CHECK(m.find("stage 'S', context 'A'") != std::string::npos);
  CHECK(m.find("reward saw 6 things") != std::string::npos);  // 2 objects + 4 regions: absorbing was called with the world

  // An absorbing function that raises: its line, and the stage and context.
  std::string bad = script;
  bad.replace(bad.find("  seen = #world.objects"), 0, "  if world.goals[1].name == \"circle\" then error(\"absorbing raised\") end\n");
  std::ofstream(dir / "probe.lua") << bad;
  const std::string a = error_of([&] { train_stage(o); });
  INFO(a);
  CHECK(a.find("probe.lua:4:") != std::string::npos);
  CHECK(a.find("absorbing function") != std::string::npos);
  CHECK(a.find("absorbing raised") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("sorting: the hand-written policy sorts both of two objects in at least 48 of 50 episodes",
          "[sorting]") {
  TrainOptions o;
  o.curriculum = "curricula/sorting.lua";
  o.stage = "Hand2";
  o.context = "Scripted";
  o.seed = 1;
  o.keep_episodes = false;
  const TrainResult r = train_stage(o);
  INFO("success " << r.final_eval.success_rate << ", mean time " << r.final_eval.time_mean);
  CHECK(r.final_eval.episodes == 50);  // the sorting stages' final evaluation
  // All 50 today: a change of numerics may lose one or two worlds, a regression more.
  CHECK(r.final_eval.success_rate >= 0.96);
  // An episode ends at the decision point at which both lie sorted (26.3 s on average today), not
  // at the 60 s limit: the chooser is NOREF once its moves have nothing left to do, which is that
  // point. Under 28 s: episodes 7% slower, or three that wait for the limit, cross it.
  CHECK(r.final_eval.time_mean < 28.0);
}

namespace {

// Episodes of curricula/sort_by_hand.lua's `sort` fully sorted (judged by the world) among `n`
// seeds from `first` of the sorting world with `objects` objects.
int sorted_by_hand(int objects, int obstacles, uint64_t first, int n) {
  const SkillScript script = SkillScript::load("curricula/sort_by_hand.lua");
  const SkillScript::NamedPolicy& sort = script.policy("sort");
  Scenario scenario = Scenario::load("sorting");
  scenario.set_param("objects", std::to_string(objects));
  scenario.set_param("obstacles", std::to_string(obstacles));
  return evaluate_action([&](uint64_t s) { return scenario.generate(s); }, *sort.action, *sort.goal, n, first,
                         sort.episode_options())
      .successes;
}

}  // namespace

// One hand-written policy for any number of objects, judged by the world (roger.sorted), within
// 30 simulated seconds per object: all 10 of seeds 60000-60009 with four objects and all 20 of
// seeds 60000-60019 with eight, every time (the engine is deterministic). With eight, one world
// may be lost to a change of numerics; a second is a regression (the first bar, 17 of 20, let
// three go). docs/results.md, Sorting, gives the held-out rates and what still fails.
TEST_CASE("sorting: one hand-written policy sorts 4 and 8 objects, its time limit per object", "[sorting]") {
  const int four = sorted_by_hand(4, 0, 60000, 10);
  const int eight = sorted_by_hand(8, 0, 60000, 20);
  INFO("4 objects: " << four << " of 10; 8 objects: " << eight << " of 20");
  CHECK(four == 10);
  CHECK(eight >= 19);
}

// What `--jobs` relies on: a worker's agent and policy run whichever episodes come to it, in any
// order, so an episode must owe nothing to the ones before it. The many-objects path keeps more
// between episodes than any other: each navigator's planner (its grid, its last cold solve), the
// world's seen surfaces of objects at rest, the bindings' invocations and patience, the eyes'
// memory of the object they saw last. Worlds of 8 objects (with and without obstacles, cycle and
// random mix) and of 4, run forwards and backwards through one agent and one policy, must give
// every episode the same ticks, the same final physical state and the same success.
TEST_CASE("sorting: an episode of many objects is the same whatever ran before it", "[sorting][determinism]") {
  const SkillScript script = SkillScript::load("curricula/sort_by_hand.lua");
  const SkillScript::NamedPolicy& sort = script.policy("sort");
  struct Case {
    const char* objects;
    const char* obstacles;
    const char* mix;
    uint64_t seed;
  };
  const std::vector<Case> worlds = {
      {"8", "0", "cycle", 61000}, {"4", "1", "cycle", 61001}, {"8", "2", "random", 61002}, {"8", "0", "random", 61003}};
  std::vector<WorldSpec> specs;
  for (const Case& w : worlds) {
    Scenario scenario = Scenario::load("sorting");
    scenario.set_param("objects", w.objects);
    scenario.set_param("obstacles", w.obstacles);
    scenario.set_param("mix", w.mix);
    specs.push_back(scenario.generate(w.seed));
  }
  struct Outcome {
    int ticks = 0;
    bool success = false;
    uint64_t state = 0;
  };
  Agent agent;
  const auto run_in = [&](const std::vector<size_t>& order) {
    std::vector<Outcome> out(worlds.size());
    for (size_t k : order) {
      const EpisodeResult r = run_episode(agent, specs[k], worlds[k].seed, *sort.action, *sort.goal, sort.episode_options());
      out[k] = {r.ticks, r.success, agent.world().state_hash()};
    }
    return out;
  };
  const std::vector<Outcome> forwards = run_in({0, 1, 2, 3}), backwards = run_in({3, 2, 1, 0});
  int sorted = 0;
  for (size_t k = 0; k < worlds.size(); ++k) {
    INFO("world " << k << ": " << worlds[k].objects << " objects, seed " << worlds[k].seed);
    CHECK(forwards[k].ticks == backwards[k].ticks);
    CHECK(forwards[k].success == backwards[k].success);
    CHECK(forwards[k].state == backwards[k].state);
    sorted += forwards[k].success;
    // Long episodes, not ones that ended before anything could differ.
    CHECK(forwards[k].ticks > 1000);
  }
  CHECK(sorted >= 3);
  // And the same bits on every machine (CI runs this on another): the episodes' final states as
  // they were when the test was written. A change that moves sorting's trajectories changes them;
  // set them anew then, as tests/golden/quick is regenerated, and say so in the commit.
  const uint64_t golden[] = {11376191091082392145ull, 13210054656833250368ull, 14806041470359023509ull,
                             2856145545837203033ull};
  for (size_t k = 0; k < worlds.size(); ++k) {
    INFO("world " << k << ": final state hash " << forwards[k].state);
    CHECK(forwards[k].state == golden[k]);
  }
}

// A bystander is not the object: in 4-object seed 300050 the eyes lost the triangle behind the
// pentagon while phi3 closed in, the body bumped the pentagon, and touch took it for the triangle;
// the grasp closed on it and the creeping body shoved it 3 m across the arena into the wall, where
// no grasp could take it again (a time-out at 120 s). Touch now locates only an object of the
// stimulus colour (Percepts::update).
TEST_CASE("sorting: a grasp does not close on a bystander of another colour and shove it away", "[sorting]") {
  CHECK(sorted_by_hand(4, 0, 300050, 1) == 1);
}

// What is left hidden from where Roger looked: in 8-object seed 182003 (random mix) the last
// triangle lay behind a pentagon put away, every move was NOREF after its scan, and the chooser's
// rounds searched again from the same spot for 158 s, to the time-out. The round now ends with
// phi1 going elsewhere, which leaves a spot from which a whole round saw nothing.
TEST_CASE("sorting: the hand-written sort looks from elsewhere for what is hidden from where it looked",
          "[sorting]") {
  const SkillScript script = SkillScript::load("curricula/sort_by_hand.lua");
  const SkillScript::NamedPolicy& sort = script.policy("sort");
  auto* policy = dynamic_cast<const Policy*>(sort.action.get());
  REQUIRE(policy != nullptr);
  CHECK(policy->actions().back()->name() == "phi1");
  Scenario scenario = Scenario::load("sorting");
  scenario.set_param("objects", "8");
  scenario.set_param("mix", "random");
  const EvalSummary r = evaluate_action([&](uint64_t s) { return scenario.generate(s); }, *sort.action,
                                        *sort.goal, 1, 182003, sort.episode_options());
  INFO("time " << r.time_mean << " s");
  CHECK(r.successes == 1);
}

namespace {

// An 8-object sorting world (seed 3, the cycle mix) with both its circles (1 and 5) lying in the
// circle region (region 0), let go.
WorldSpec circles_put_away() {
  Scenario scenario = Scenario::load("sorting");
  scenario.set_param("objects", "8");
  WorldSpec spec = scenario.generate(3);
  const GoalRegion& region = spec.goals[0];
  int moved = 0;
  for (auto& o : spec.objects)
    if (o.name.rfind("circle", 0) == 0) {
      o.pose.x = region.center.x() + (moved == 0 ? -0.25 : 0.25);
      o.pose.y = region.center.y();
      ++moved;
    }
  REQUIRE(moved == 2);
  return spec;
}

}  // namespace

TEST_CASE("sorting: a bound move whose objects are all put away ends NOREF within a scan", "[sorting]") {
  // Two circles already in the circle region (region 0), let go: the circle move backs off, its
  // search sweeps round without a glimpse (the eyes ignore what is put away), and the move is NOREF.
  const SkillScript script = SkillScript::load("curricula/sort_by_hand.lua");
  const SkillScript::NamedPolicy& sort = script.policy("sort");
  auto* policy = dynamic_cast<const Policy*>(sort.action.get());
  REQUIRE(policy != nullptr);
  REQUIRE(policy->actions().size() == 5);  // the four moves, then looking from elsewhere
  const ControllerPtr circle = policy->actions().front();
  WorldSpec spec = circles_put_away();
  Agent agent;
  agent.reset(spec);
  circle->reset(3);
  double noref_at = -1.0;
  for (int t = 0; t < 500 && noref_at < 0.0; ++t) {
    agent.step(*circle);
    if (circle->state(agent.input()) == Gamma::kNoRef) noref_at = agent.world().time();
  }
  INFO("NOREF at " << noref_at << " s");
  // Backing off (about 1 s) and one sweep (1.4 s, test_primitives): 2.22 s. A second sweep or a
  // back-off twice as long crosses 2.6 s; under 1.8 s the move gave up without sweeping round.
  CHECK(noref_at > 1.8);
  CHECK(noref_at < 2.6);
}

TEST_CASE("sorting: a type's task is CONV and rests once its objects are put away, !CONV while one is left",
          "[sorting]") {
  // The actions of the learned sorting stages (sorting.task in curricula/lib/sorting.lua). Resting
  // runs none of the move, so the learned Phi_T inside need not even be bound here.
  Curriculum cur = Curriculum::load("curricula/sorting.lua");
  const std::vector<ControllerPtr>& tasks = cur.stage("Sort8").context("Learned").actions;
  REQUIRE(tasks.size() == 4);
  const ControllerPtr circle = tasks[0], triangle = tasks[1];
  CHECK(circle->name() == "put away circle");
  WorldSpec spec = circles_put_away();
  Agent agent;
  agent.reset(spec);
  for (const auto& t : tasks) t->reset(3);
  // Put away once the circles have lain sorted for sorting.SETTLE (1 s): a touch that comes and
  // goes does not make the task flicker. Meanwhile the eyes turn (phi0) and nothing else moves.
  const PrimitivePtr look = make_primitive("phi0");
  look->reset(3);
  double conv_at = -1.0;
  for (int t = 0; t < 100 && conv_at < 0.0; ++t) {
    agent.step(*look);
    CHECK(triangle->state(agent.input()) == Gamma::kNotConv);  // triangles are left, its move not yet run
    if (circle->state(agent.input()) == Gamma::kConv) conv_at = agent.world().time();
  }
  INFO("CONV at " << conv_at << " s");
  CHECK(conv_at >= 0.98);
  CHECK(conv_at <= 1.04);
  for (int t = 0; t < 50; ++t) {
    agent.step(*circle);
    CHECK(agent.last_errors().isZero());  // at rest: no command, Roger holds still
    CHECK(circle->output().gamma == Gamma::kConv);
    CHECK(circle->inner() == nullptr);
  }
  // One circle back out of its region: the task has something to do again.
  spec.objects[0].pose.x = 0.0, spec.objects[0].pose.y = 0.0;
  REQUIRE(spec.objects[0].name.rfind("circle", 0) == 0);
  agent.reset(spec);
  for (const auto& t : tasks) t->reset(3);
  CHECK(circle->state(agent.input()) == Gamma::kNotConv);
}

TEST_CASE("sorting: the learned transport skill is loaded from its policy file, not trained again",
          "[sorting]") {
  const fs::path dir = temp_dir("roger_sorting_skill");
  // Phi_T as a learned policy: stage T (which trains its Phi_SG first, with the same seed).
  TrainOptions t;
  t.curriculum = "curricula/sorting.lua";
  t.stage = "T";
  t.context = "DC6";
  t.seed = 2;
  t.keep_episodes = false;
  const TrainResult tr = train_stage(t);
  write_train_outputs(tr, (dir / "T").string());
  const fs::path file = dir / "T" / "policy.json";
  const nlohmann::json written = nlohmann::json::parse(std::ifstream(file));

  TrainOptions s;
  s.curriculum = "curricula/sorting.lua";
  s.stage = "Sort2";
  s.context = "Learned";
  s.seed = 3;  // not T's seed: a Phi_SG trained again would differ from the one T learned on
  s.keep_episodes = false;
  s.skill_files["Phi_T"] = file.string();
  const TrainResult sr = train_stage(s);
  // Phi_T from the file, and the Phi_SG it uses from the copy embedded in that file.
  REQUIRE(sr.skills.size() == 2);
  const auto find = [&](const std::string& name) {
    const auto it = std::find_if(sr.skills.begin(), sr.skills.end(), [&](const SkillSource& k) { return k.name == name; });
    REQUIRE(it != sr.skills.end());
    return *it;
  };
  const SkillSource phi_t = find("Phi_T");
  CHECK(phi_t.file == file.string());
  CHECK(find("Phi_SG").policy == written["extra"]["skills"]["Phi_SG"]["policy"]);
  // Its training is the embedding file's to tell: the summary claims no figures for it.
  CHECK(find("Phi_SG").embedded);
  CHECK_FALSE(phi_t.embedded);
  const nlohmann::json summary = train_summary_json(sr);
  CHECK(summary["skills"]["Phi_SG"]["embedded"] == true);
  CHECK_FALSE(summary["skills"]["Phi_SG"].contains("reached"));
  CHECK_FALSE(phi_t.trained);
  CHECK(phi_t.policy == written);  // the very table T learned, embedded in the Sort2 policy as read
  CHECK(train_policy_json(sr)["extra"]["skills"]["Phi_T"]["trained"] == false);
  // Psi of the sorting stage: per type, Phi_T bound to it, run as that type's task.
  CHECK(sr.psi == std::vector<std::string>{"put away circle", "put away triangle", "put away pentagon", "put away spade"});
  fs::remove_all(dir);
}

TEST_CASE("sorting: the documented two-move example runs and is shown verbatim", "[sorting]") {
  const SkillScript script = SkillScript::load("docs/examples/sorting_moves.lua");
  const SkillScript::NamedPolicy& policy = script.policy("two_moves");
  Scenario scenario = Scenario::load("sorting");
  EpisodeOptions options;
  options.time_limit = policy.time_limit;
  const EvalSummary s = evaluate_action([&](uint64_t seed) { return scenario.generate(seed); }, *policy.action,
                                        *policy.goal, 10, 1000, options, WorldParams{});
  CHECK(s.successes >= 8);
  std::ifstream doc_in("docs/control.md"), file_in("docs/examples/sorting_moves.lua");
  std::stringstream doc, file;
  doc << doc_in.rdbuf();
  file << file_in.rdbuf();
  CHECK(doc.str().find(file.str().substr(file.str().find("local skills"))) != std::string::npos);
}

TEST_CASE("sorting: a binding redirects the world's attention, and gives up after its patience", "[sorting]") {
  Scenario scenario = Scenario::load("sorting");
  const WorldSpec spec = scenario.generate(5);
  Agent agent;
  agent.reset(spec);
  Binding::Bindings b;
  b.stimulus = true;
  b.colour = Colour{0, 200, 0};  // no object has it: search never converges
  b.region = 3;
  b.ignore_region = 3;
  b.patience = 1.0;
  auto binding = std::make_shared<Binding>(make_primitive("search"), b);
  binding->reset(5);
  CHECK(binding->state(agent.input()) == Gamma::kNotConv);  // never invoked: nothing says done or impossible
  agent.step(*binding);
  // From the next tick the world attends as the binding asked; the first tick commanded nothing.
  CHECK(agent.world().attention().colour == Colour{0, 200, 0});
  CHECK(agent.world().attention().region == 3);
  CHECK(agent.input().region == 3);
  CHECK(binding->output().gamma == Gamma::kNotConv);
  CHECK(binding->output().command.isZero());
  CHECK(binding->invocations() == 1);
  // Run it: not converged after 1 s, the invocation is given up (NOREF, no command), and the next
  // evaluation starts the second.
  double gave_up_at = -1.0;
  while (agent.input().time < 3.0 && binding->invocations() == 1) {
    if (binding->state(agent.input()) == Gamma::kNoRef && gave_up_at < 0.0) gave_up_at = agent.input().time;
    agent.step(*binding);
  }
  CHECK(gave_up_at == Approx(1.0).margin(0.05));
  CHECK(binding->invocations() == 2);
  agent.step(*binding);
  CHECK(binding->output().gamma == Gamma::kNotConv);  // running again
}

TEST_CASE("sorting: bad roger.bind arguments are errors at file:line naming the field", "[sorting]") {
  const fs::path dir = temp_dir("roger_sorting_bind");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{}", "binds nothing: give 'stimulus', 'region' or both"},
      {"{region = 99}", "field 'region' must be a goal region's index 0 to 63"},
      {"{stimulus = \"red\"}", "field 'stimulus' must be a colour"},
      {"{stimulus = \"#ff0000\", patience = -1}", "field 'patience' must be seconds from 0 (no limit) to 1e6, got -1"},
      {"{stimulus = \"#ff0000\", ignore_delivered = true}", "field 'ignore_delivered' needs 'region'"},
      {"{stimulus = \"#ff0000\", sticky_noref = 1}", "field 'sticky_noref' must be a boolean, got number"},
      {"{stimulus = \"#ff0000\", retry_after = -5}", "field 'retry_after' must be seconds from 0 (never forget a NOREF) to 1e6, got -5"},
      {"{stimulus = \"#ff0000\", colour = 1}", "unknown field 'colour'; known fields: ignore_delivered, patience, region, retry_after, sticky_noref, stimulus"},
  };
  for (const auto& [fields, message] : cases) {
    INFO(fields);
    std::ofstream(dir / "bad.lua") << "local s = roger.primitive(\"search\")\nlocal b = roger.bind(\"b\", s, " << fields
                                   << ")\nreturn { name = \"x\", policies = { p = { action = b, goal = roger.converged(b), time_limit = 1 } } }\n";
    const std::string m = error_of([&] { SkillScript::load((dir / "bad.lua").string()); });
    INFO(m);
    CHECK(m.find("bad.lua:2:") != std::string::npos);
    CHECK(m.find("roger.bind('b')") != std::string::npos);
    CHECK(m.find(message) != std::string::npos);
  }
  fs::remove_all(dir);
}

TEST_CASE("sorting: bad options of lib/sorting's moves are errors at the caller's file:line", "[sorting]") {
  const fs::path dir = temp_dir("roger_sorting_moves");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{ stiky_noref = true }", "unknown option 'stiky_noref' (known: retry_after, sticky_noref, tag)"},
      {"{ retry_after = \"30\" }", "option 'retry_after' must be a number, got string"},
      {"\" (tag)\"", "options must be a table {tag, sticky_noref, retry_after}, got string"},
  };
  for (const auto& [options, message] : cases) {
    INFO(options);
    std::ofstream(dir / "bad.lua") << "local sorting = require(\"lib.sorting\")\n"
                                   << "local moves = sorting.moves(roger.primitive(\"search\"), " << options << ")\n"
                                   << "return { name = \"x\", policies = { p = { action = moves[1], "
                                      "goal = roger.converged(moves[1]), time_limit = 1 } } }\n";
    const std::string m = error_of([&] { SkillScript::load((dir / "bad.lua").string()); });
    INFO(m);
    CHECK(m.find("bad.lua:2:") != std::string::npos);
    CHECK(m.find(message) != std::string::npos);
  }
  // Good options reach the bindings (docs/control.md's snippet).
  std::ofstream(dir / "good.lua") << "local sorting = require(\"lib.sorting\")\n"
                                  << "local moves = sorting.moves(roger.primitive(\"search\"), "
                                     "{ sticky_noref = true, retry_after = 30 })\n"
                                  << "return { name = \"x\", policies = { p = { action = moves[1], "
                                     "goal = roger.converged(moves[1]), time_limit = 1 } } }\n";
  const SkillScript script = SkillScript::load((dir / "good.lua").string());
  const auto* move = dynamic_cast<const Binding*>(script.policy("p").action.get());
  REQUIRE(move);
  CHECK(move->bindings().sticky_noref);
  CHECK(move->bindings().retry_after == 30.0);
  CHECK(move->bindings().patience == 15.0);
  fs::remove_all(dir);
}

namespace {

// Writes a policy script to dir/name whose line 2 is `line2` (lib.sorting required on line 1) and
// whose policy `p` runs `action`; returns its path.
std::string sorting_script(const fs::path& dir, const std::string& name, const std::string& line2,
                           const std::string& action) {
  std::ofstream(dir / name) << "local sorting = require(\"lib.sorting\")\n"
                            << line2 << "\n"
                            << "return { name = \"x\", policies = { p = { action = " << action
                            // Not converged(action): a chooser of sorting.by_hand has no done, and never
                            // converges (a load refuses such a goal); these scripts are only loaded.
                            << ", goal = roger.gamma(" << action << ", \"!CONV\"), time_limit = 1 } } }\n";
  return (dir / name).string();
}

}  // namespace

TEST_CASE("sorting: sorting.move names an unknown type at the caller's line and takes a colour and region of one's own",
          "[sorting]") {
  const fs::path dir = temp_dir("roger_sorting_type");
  const std::string bad = sorting_script(dir, "bad.lua", "local m = sorting.move(roger.primitive(\"search\"), \"red\")", "m");
  const std::string m = error_of([&] { SkillScript::load(bad); });
  INFO(m);
  CHECK(m.find("bad.lua:2: sorting.move: unknown type 'red' (known: circle, triangle, pentagon, spade)") != std::string::npos);
  CHECK(m.find("give both options colour and region") != std::string::npos);
  const std::string half = sorting_script(
      dir, "half.lua", "local m = sorting.move(roger.primitive(\"search\"), \"red\", { region = 1 })", "m");
  CHECK(error_of([&] { SkillScript::load(half); }).find("half.lua:2: sorting.move: unknown type 'red'") != std::string::npos);
  const std::string wrong = sorting_script(
      dir, "wrong.lua", "local m = sorting.move(roger.primitive(\"search\"), \"red\", { region = \"1\" })", "m");
  CHECK(error_of([&] { SkillScript::load(wrong); }).find("wrong.lua:2: sorting.move: option 'region' must be a number, got string") !=
        std::string::npos);
  // A task judges by its type's colour: an unknown type would have judged every colour.
  const std::string task = sorting_script(
      dir, "task.lua", "local m = sorting.task(sorting.move(roger.primitive(\"search\"), \"circle\"), \"red\")", "m");
  CHECK(error_of([&] { SkillScript::load(task); }).find("task.lua:2: sorting.task: unknown type 'red' (known: circle") !=
        std::string::npos);

  // A task of one's own type takes its colour, as the move does (found by a probe: sorting.move
  // took "red" with a colour and region, and sorting.task refused it).
  const std::string own_task = sorting_script(
      dir, "own_task.lua",
      "local m = sorting.task(sorting.move(roger.primitive(\"search\"), \"red\", { colour = \"#ff0000\", region = 2 }), "
      "\"red\", { tag = \" 1\", colour = \"#ff0000\" })",
      "m");
  CHECK(SkillScript::load(own_task).policy("p").action->name() == "put away red 1");
  const std::string task_option = sorting_script(
      dir, "task_option.lua", "local m = sorting.task(sorting.move(roger.primitive(\"search\"), \"circle\"), \"circle\", { region = 1 })",
      "m");
  CHECK(error_of([&] { SkillScript::load(task_option); })
            .find("task_option.lua:2: sorting.task: unknown option 'region' (known: colour, tag)") != std::string::npos);

  const SkillScript own = SkillScript::load(sorting_script(
      dir, "own.lua", "local m = sorting.move(roger.primitive(\"search\"), \"red\", { colour = \"#ff0000\", region = 2 })",
      "m"));
  const auto* move = dynamic_cast<const Binding*>(own.policy("p").action.get());
  REQUIRE(move);
  CHECK(move->name() == "sort red");
  CHECK(move->bindings().colour == Colour{255, 0, 0});
  CHECK(move->bindings().region == 2);
  fs::remove_all(dir);
}

TEST_CASE("sorting: by_hand runs the first move not NOREF for up to 11 moves and refuses 12 naming the limit",
          "[sorting]") {
  const fs::path dir = temp_dir("roger_sorting_by_hand");
  auto moves = [](int n) {
    return "local t = roger.primitive(\"search\") local moves = {} for i = 1, " + std::to_string(n) +
           " do moves[i] = sorting.move(t, sorting.TYPES[(i - 1) % 4 + 1], { tag = \" \" .. i }) end "
           "local sort = sorting.by_hand(moves)";
  };
  // Eleven moves took 3^11 table keys, beyond the script's instruction budget.
  const SkillScript script = SkillScript::load(sorting_script(dir, "eleven.lua", moves(11), "sort"));
  const auto* sort = dynamic_cast<const Policy*>(script.policy("p").action.get());
  REQUIRE(sort);
  REQUIRE(sort->actions().size() == 12);
  const std::vector<int>& table = sort->table();
  REQUIRE(table.size() == 531441);
  int wrong = 0;
  for (size_t state = 0; state < table.size(); ++state) {
    // The first move (most significant digit first) whose gamma is not NOREF; none: the fallback.
    int first = -1;
    size_t rest = state / 3;  // the last digit is phi1's
    for (int i = 10; i >= 0; --i, rest /= 3)
      if (rest % 3 != size_t(Gamma::kNoRef)) first = i;
    wrong += table[state] != first;
  }
  CHECK(wrong == 0);

  const std::string m = error_of([&] { SkillScript::load(sorting_script(dir, "twelve.lua", moves(12), "sort")); });
  INFO(m);
  CHECK(m.find("twelve.lua:2: sorting.by_hand: takes a list of 1 to 11 moves") != std::string::npos);
  CHECK(m.find("got 12 moves") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("sorting: roger.sorted is an error in a world whose objects no region's colour matches", "[sorting]") {
  const SkillScript script = SkillScript::load("curricula/sort_by_hand.lua");
  const SkillScript::NamedPolicy& sort = script.policy("sort");
  Scenario scenario = Scenario::load("sorting");
  // One digit off in every region's colour: nothing left for the goal to count.
  auto typo = [&](uint64_t seed) {
    WorldSpec spec = scenario.generate(seed);
    for (GoalRegion& g : spec.goals) g.colour.b = uint8_t(g.colour.b + 1);
    return spec;
  };
  const std::string m = error_of([&] { evaluate_action(typo, *sort.action, *sort.goal, 1, 1, sort.episode_options()); });
  INFO(m);
  CHECK(m.find("roger.sorted(): none of the world's 2 objects has the colour of a goal region") != std::string::npos);
  CHECK(m.find("objects: #dc1e1e, #9628aa") != std::string::npos);
  CHECK(m.find("goal regions: circle #dc1e1f, triangle #2850dd, pentagon #e6aa15, spade #9628ab") != std::string::npos);
  CHECK(m.find("roger.sorted matches an object to the region of its exact colour") != std::string::npos);
}
