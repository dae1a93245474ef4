// Tests of engine/curriculum: the paper's curriculum holds exactly the paper's Psi sets, bad
// curricula are clear errors at file:line, Lua callbacks that misbehave stop training with the
// stage, context and line named, and the documented example loads and trains.
#include <catch2/catch.hpp>

#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "script/curriculum/curriculum.h"
#include "script/scenario/scenario.h"
#include "core/error.h"
#include "learn/learning.h"
#include "batch/trainer.h"
#include "temp_dir.h"
#include "test_files.h"

using namespace roger;

namespace {

std::vector<std::string> names_of(const CurriculumContext& c) { return controller_names(c.actions); }

// The message of the error `f` throws ("" when none).
std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("the paper's curriculum holds the paper's Psi sets", "[curriculum]") {
  Curriculum cur = Curriculum::load("paper");
  REQUIRE(cur.stages().size() == 2);
  const CurriculumStage& sg = cur.stage("SG");
  const CurriculumStage& t = cur.stage("T");
  CHECK(sg.time_limit == 5.0);
  CHECK(t.time_limit == 10.0);
  CHECK(sg.absorbing->describe().find("phi3") != std::string::npos);
  using V = std::vector<std::string>;
  CHECK(names_of(sg.context("B1")) == V{"phi1", "phi3", "phi4 <| phi2", "Phi6"});
  CHECK(names_of(sg.context("DC1")) == V{"phi1", "phi3", "phi4 <| phi2", "Phi6", "Phi7"});
  CHECK(names_of(sg.context("DC2")) == V{"phi3", "Phi6", "Phi7"});
  const std::string T = "phi1 <| phi4 <| phi5";
  CHECK(names_of(t.context("B2")) == V{"phi3", "phi4 <| phi5", "Phi6", "Phi7", T});
  CHECK(names_of(t.context("DC3")) == V{"phi3", "phi4 <| phi5", "Phi6", "Phi7", "Phi_SG", T});
  CHECK(names_of(t.context("DC4")) == V{"Phi7", "phi4 <| phi5", "Phi_SG", T});
  CHECK(names_of(t.context("DC5")) == V{"phi4 <| phi5", "Phi_SG", "Phi_STG", T});
  CHECK(names_of(t.context("DC6")) == V{"Phi_STG", T});
  // The order the script writes them in, and the learned skill each T context reaches.
  V order;
  for (const auto& c : t.contexts) order.push_back(c.name);
  CHECK(order == V{"B2", "DC3", "DC4", "DC5", "DC6"});
  CHECK(t.context("B2").learned.empty());
  CHECK(t.context("DC6").learned == V{"Phi_SG"});  // through Phi_STG
  REQUIRE(sg.skill);
  CHECK(sg.skill->first == "Phi_SG");
  CHECK(sg.skill->second == "DC2");
  CHECK(cur.producer("Phi_SG") == &sg);
  CHECK(check_curriculum("curricula/paper.lua").empty());
  CHECK(is_curriculum_script("curricula/paper.lua"));
  // `local paper = require("paper") ... return paper`: of the kind of the module it returns.
  CHECK(is_curriculum_script("tests/scripts/kill_curriculum.lua"));
  CHECK(check_curriculum("tests/scripts/kill_curriculum.lua").empty());
  CHECK_FALSE(is_curriculum_script("curricula/scripted.lua"));
  CHECK(error_of([] { (void)Curriculum::load("paper").stage("X"); }).find("its stages: SG, T") != std::string::npos);
  // A stage or context named in the wrong case, as a probe's --stage carry for Carry.
  CHECK(error_of([] { (void)Curriculum::load("paper").stage("sg"); })
            .find("has no stage 'sg' (did you mean 'SG'?); its stages: SG, T") != std::string::npos);
  CHECK(error_of([] { (void)Curriculum::load("paper").stage("SG").context("dc2"); })
            .find("stage 'SG' has no context 'dc2' (did you mean 'DC2'?); its contexts: B1, DC1, DC2") != std::string::npos);
  // The stage and context swapped (found by a probe: "has no stage 'DC6'" alone).
  CHECK(error_of([] { (void)Curriculum::load("paper").stage("DC6"); })
            .find("has no stage 'DC6' ('DC6' is a context of stage 'T': a stage comes first, then its context); "
                  "its stages: SG, T") != std::string::npos);
}

// Found by a probe: a curriculum that returns what a module of its own makes (`local make =
// require("stages") ... return make{...}`) trained with roger train, and roger check ran it as a
// skill script ("attempt to call a nil value (field 'primitive')"). A return inside a function
// is not the script's.
TEST_CASE("a script returning what a required module makes is of that module's kind", "[curriculum]") {
  const test::TempDir tmp("roger_curriculum_made");
  std::ofstream(tmp.path / "stages_of_mine.lua") << "return function(t) return { stages = t } end\n";
  std::ofstream(tmp.path / "made.lua") << "local make = require('stages_of_mine')\nreturn make{}\n";
  std::ofstream(tmp.path / "made_dot.lua") << "local m = require('stages_of_mine')\nreturn m.build('x')\n";
  std::ofstream(tmp.path / "inner.lua") << "local m = require('stages_of_mine')\n"
                                           "local function f() return m(1) end\nreturn { generate = f }\n";
  CHECK(is_curriculum_script((tmp.path / "made.lua").string()));
  CHECK(is_curriculum_script((tmp.path / "made_dot.lua").string()));
  CHECK_FALSE(is_curriculum_script((tmp.path / "inner.lua").string()));
}

// Found by a probe: a controller named "search\xffgrasp" passed roger check, trained its whole
// budget, then failed as the records were written ("[json.exception.type_error.316] invalid UTF-8
// byte"), leaving nothing. Every name records show is refused at load, at its line.
TEST_CASE("a name that is not UTF-8 text is refused at its line, before any training", "[curriculum]") {
  const test::TempDir tmp("roger_curriculum_utf8");
  const auto error_of_stage = [&](const std::string& stage) {
    std::ofstream(tmp.path / "bad.lua") << "local p = require('lib.skills').primitives()\n"
                                         << "return { stages = { " << stage << " } }\n";
    try {
      (void)Curriculum::load((tmp.path / "bad.lua").string());
    } catch (const ScriptError& e) {
      return e.file.substr(e.file.rfind('/') + 1) + ":" + std::to_string(e.line) + ": " + e.message;
    }
    return std::string("loaded");
  };
  const std::string rest = "scenario = 'cluttered', time_limit = 4, absorbing = roger.converged(p.phi0), "
                           "budget = { episodes = 4 }, checkpoints = { every = 4 }, ";
  CHECK_THAT(error_of_stage("roger.stage{ name = 'S\xff', " + rest + "contexts = { { name = 'A', actions = { p.phi0 } } } }"),
             Catch::Contains("bad.lua:2: stage 'S\\xFF': field 'name' must be UTF-8 text (records and pages show it): "
                             "in 'S\\xFF', byte 0xff at byte 2 is not part of a UTF-8 character"));
  CHECK_THAT(error_of_stage("roger.stage{ name = 'S', " + rest + "contexts = { { name = 'A\xff', actions = { p.phi0 } } } }"),
             Catch::Contains("field 'name' must be UTF-8 text (records and pages show it): in 'A\\xFF'"));
  CHECK_THAT(error_of_stage("roger.stage{ name = 'S', " + rest + "contexts = { ['A\xff'] = { p.phi0 } } }"),
             Catch::Contains("stage 'S': a context's name must be UTF-8 text"));
  CHECK_THAT(error_of_stage("roger.stage{ name = 'S', " + rest + "contexts = { { name = 'A', actions = { "
                            "roger.sequence('s\xffg', { p.phi0, p.phi1 }) } } } }"),
             Catch::Contains("bad.lua:2: roger.sequence('s\\xFFg'): the name must be UTF-8 text"));
  CHECK_THAT(error_of_stage("roger.stage{ name = 'S', " + rest + "contexts = { { name = 'A', actions = { "
                            "roger.learned('k\xff') } } } }"),
             Catch::Contains("roger.learned: the name must be UTF-8 text"));
}

// Found by a probe: a --set the scenario lacks was said twice on a stage with a task space (the
// second time without its line), and "scenario 'cluttered': scenario 'cluttered' (...)" named it twice.
// Found by another: placed at the stage's line first, it read as the curriculum's error (a shipped
// library's line, for the paper's stages); the --set comes first, the stage's line after.
TEST_CASE("a --set the stage's scenario lacks is said once, with the stage", "[curriculum]") {
  const std::vector<std::string> problems =
      check_curriculum("docs/examples/teachers_example.lua", {}, {{"obstacle", "2"}}, {"Look"});
  REQUIRE(problems.size() == 1);
  CHECK_THAT(problems[0], Catch::StartsWith("--set obstacle=2: stage 'Look' (docs/examples/teachers_example.lua:31): "
                                            "scenario 'cluttered' (scenarios/cluttered.lua) has no parameter 'obstacle' "
                                            "(did you mean 'obstacles'?)"));
}

TEST_CASE("bad curricula are clear errors at file:line", "[curriculum]") {
  struct Case {
    const char* file;
    std::vector<std::string> parts;
  };
  const std::vector<Case> cases = {
      {"bad_curriculum_skill_context.lua", {"bad_curriculum_skill_context.lua:5:", "stage 'S'", "unknown context 'DC9'", "contexts: A"}},
      {"bad_curriculum_empty_psi.lua", {"bad_curriculum_empty_psi.lua:5:", "stage 'S', context 'Empty'", "Psi is empty"}},
      {"bad_curriculum_field.lua", {"bad_curriculum_field.lua:4:", "unknown field 'time_limt'", "time_limit"}},
      {"bad_curriculum_learned_same.lua", {"bad_curriculum_learned_same.lua:6:", "context 'B'", "this very stage yields"}},
      {"bad_curriculum_too_many.lua", {"bad_curriculum_too_many.lua:8:", "context 'Wide'", "13 actions", "at most 12"}},
      {"bad_curriculum_plain_field.lua", {"bad_curriculum_plain_field.lua:5:", "stage 'Plain'", "episodes", "-3"}},
      {"bad_curriculum_discount_clock.lua",
       {"bad_curriculum_discount_clock.lua:6:", "stage 'Clock'", "learner", "discount_seconds", "got -2"}},
      {"bad_curriculum_unconverged.lua",
       {"bad_curriculum_unconverged.lua:6:", "stage 'Eager'", "learner", "unconverged_first", "a boolean"}},
      {"bad_curriculum_alpha.lua",
       {"bad_curriculum_alpha.lua:6:", "stage 'Alpha'", "stage 'Alpha': learner: alpha must be in (0, 1], got -1"}},
      {"bad_curriculum_time_per_object.lua",
       {"bad_curriculum_time_per_object.lua:5:", "stage 'Slow'", "field 'time_limit'", "per_object", "got 0"}},
      {"bad_curriculum_misspelt_action.lua",
       {"bad_curriculum_misspelt_action.lua:7:", "no controller \"phi33\"", "carry, phi0, phi1, phi2, phi3, phi4, phi5, search"}},
      {"bad_curriculum_time_field.lua",
       {"bad_curriculum_time_field.lua:5:", "stage 'Typo'", "field 'time_limit'", "per_objects", "per_object"}},
      {"bad_curriculum_held_ticks.lua",
       {"bad_curriculum_held_ticks.lua:6:", "stage 'Patient'", "field 'absorbing'",
        "held(converged(phi3), 250.0 s) can hold only after 250.02 simulated seconds (the goal is first judged after "
        "the first tick, at 0.02 s), past the time_limit of 5 s"}},
  };
  // Each at the line its field is written on (the first part), with no traceback: it would name
  // only the roger.stage{ line.
  for (const auto& c : cases) {
    INFO(c.file);
    const std::string m = error_of([&] { Curriculum::load(std::string("tests/scripts/") + c.file); });
    INFO("message: " << m);
    for (const auto& p : c.parts) CHECK(m.find(p) != std::string::npos);
    CHECK(m.find(c.parts[1]) == m.rfind(c.parts[1]));  // the stage is named once
  }
}

// Before, these loaded and checked "ok", and training failed at its first episode.
TEST_CASE("roger check calls the Lua callbacks as at an episode's first decision", "[curriculum]") {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"bad_curriculum_world_field.lua", "bad_curriculum_world_field.lua:5: stage 'S', context 'A': absorbing function: "},
      {"bad_curriculum_reward_nan.lua", "bad_curriculum_reward_nan.lua:5: stage 'S', context 'A': the reward function "
                                        "must return a finite number, got number nan (event 'decision')"},
      {"bad_curriculum_predicate_raises.lua", "bad_curriculum_predicate_raises.lua:5: stage 'S', context 'A'"},
      {"bad_curriculum_state_name.lua", "bad_curriculum_state_name.lua:5: stage 'S', context 'A': absorbing function: "
                                        "state has no action 'Phi3' (did you mean 'phi3'?); its actions: phi3 (a "
                                        "function shared by contexts of other actions reads one they may lack with "
                                        "rawget(state, name), nil there)"},
      // Found by a probe: the state's metatable's __index called by hand on a number crashed roger.
      {"bad_curriculum_state_metatable.lua", "bad_curriculum_state_metatable.lua:5: stage 'S', context 'A': absorbing "
                                             "function: bad argument #1 to '__index' (table expected, got number)"},
      // Found by probes: a misspelt field of a world entry read nil, and check said ok. The error
      // is at the helper's line that reads it, not at the line that called the helper.
      {"bad_curriculum_world_entry.lua",
       "bad_curriculum_world_entry.lua:5: stage 'S', context 'A': absorbing function: an object of world.objects "
       "has no field 'regoin' (did you mean 'region'?); its fields: name, shape, colour, x, y, held, region"},
      {"bad_curriculum_world_goals.lua",
       "bad_curriculum_world_goals.lua:5: stage 'S', context 'A': absorbing function: world has no field 'goalz' "
       "(did you mean 'goals'?); its fields: objects, goals, obstacles"},
      // Found by a probe: `return r, done`, as a Gymnasium step gives it, was taken as r and the
      // flag dropped without a word.
      {"bad_curriculum_reward_done.lua",
       "bad_curriculum_reward_done.lua:5: stage 'S', context 'A': the reward function must return one finite number, "
       "got 2 values (number 1, boolean false); an episode ends when the stage's absorbing holds or at its time_limit"},
      {"bad_curriculum_absorbing_two.lua",
       "bad_curriculum_absorbing_two.lua:4: stage 'S', context 'A': the absorbing function must return true or "
       "false, got 2 values (boolean false, string 'converged')"},
  };
  for (const auto& [file, says] : cases) {
    INFO(file);
    const std::vector<std::string> problems = check_curriculum("tests/scripts/" + file);
    REQUIRE(problems.size() == 1);
    INFO(problems[0]);
    CHECK(problems[0].find(says) != std::string::npos);
    CHECK(problems[0].find("(called as at an episode's first decision, world seed 0, every action NOREF)") !=
          std::string::npos);
  }
  CHECK(check_curriculum("curricula/sorting.lua").empty());  // Lua callbacks that read the world
}

// Found by a newcomer (in a skill script): a navigator sent to a goal region the worlds lack passed
// check and was NOREF at every decision; a curriculum's actions were not looked at. One inside a
// binding that names the region goes where the binding says.
TEST_CASE("roger check refuses an action sent to a goal region the stage's worlds lack", "[curriculum]") {
  const std::vector<std::string> problems = check_curriculum("tests/scripts/bad_curriculum_region.lua");
  REQUIRE(problems.size() == 1);
  CHECK(problems[0] == "tests/scripts/bad_curriculum_region.lua:7: stage 'S', context 'A': action 'phi1': the "
                       "navigator phi1 {goal = \"region\", region = 7} goes to goal region 7, but the worlds of "
                       "scenario 'unobstructed' have 1 goal region (0 to 0)");
}

// Found by a probe: a slip on the time-out's branch of a reward passed check, and training stopped
// at its first episode's end.
TEST_CASE("roger check calls a Lua reward also as at an episode's end", "[curriculum]") {
  const std::vector<std::string> problems = check_curriculum("tests/scripts/bad_curriculum_reward_timeout.lua");
  REQUIRE(problems.size() == 1);
  INFO(problems[0]);
  CHECK_THAT(problems[0], Catch::StartsWith("tests/scripts/bad_curriculum_reward_timeout.lua:6: stage 'S', context 'A': "
                                            "reward function: an object of world.objects has no field 'massa'"));
  CHECK_THAT(problems[0], Catch::Contains("(called as at an episode's end by time-out, world seed 0, every action NOREF)"));
}

TEST_CASE("misbehaving Lua callbacks stop training naming stage, context and line", "[curriculum]") {
  struct Case {
    const char* file;
    std::vector<std::string> parts;
  };
  const std::vector<Case> cases = {
      {"bad_curriculum_reward_nan.lua", {"bad_curriculum_reward_nan.lua:5:", "stage 'S', context 'A'", "finite number", "nan"}},
      {"bad_curriculum_reward_string.lua", {"bad_curriculum_reward_string.lua:4:", "stage 'S', context 'A'", "finite number", "string 'lots'"}},
      {"bad_curriculum_predicate_raises.lua", {"bad_curriculum_predicate_raises.lua:5:", "stage 'S', context 'A'", "no such sensor"}},
      {"bad_curriculum_reward_done.lua", {"bad_curriculum_reward_done.lua:5:", "stage 'S', context 'A'", "got 2 values"}},
  };
  for (const auto& c : cases) {
    INFO(c.file);
    TrainOptions o;
    o.curriculum = std::string("tests/scripts/") + c.file;
    o.stage = "S";
    o.context = "A";
    const std::string m = error_of([&] { train_stage(o); });
    INFO("message: " << m);
    for (const auto& p : c.parts) CHECK(m.find(p) != std::string::npos);
  }
}

// Found by a probe: paper.stages{ sg_params = { forarm = 0.6 } } was refused at a line of
// curricula/lib/paper_stages.lua alone; the traceback names the caller's line. A stage of the
// file's own has none (its line is the whole story).
TEST_CASE("a stage's params refused through a library name the caller's line", "[curriculum]") {
  const test::TempDir tmp("roger_curriculum_through");
  std::ofstream(tmp.path / "mine.lua") << "local paper = require('lib.paper_stages')\n"
                                          "local sg, t = paper.stages{ suffix = '_long', sg_params = { forarm = 0.6 } }\n"
                                          "return { stages = { sg, t } }\n";
  try {
    (void)Curriculum::load((tmp.path / "mine.lua").string());
    FAIL("loaded");
  } catch (const ScriptError& e) {
    CHECK_THAT(e.message, Catch::Matchers::Contains("stage 'SG_long', context 'B1': params: scenario 'unobstructed'") &&
                              Catch::Matchers::Contains("no parameter 'forarm' (did you mean 'forearm'?)"));
    CHECK_THAT(e.file, Catch::Matchers::EndsWith("lib/paper_stages.lua"));
    CHECK_THAT(e.traceback, Catch::Matchers::Contains("mine.lua:2: in main chunk"));
  }
  std::ofstream(tmp.path / "own.lua")
      << "local p = require('lib.skills').primitives()\n"
         "return { stages = { roger.stage{ name = 'S', scenario = 'unobstructed', time_limit = 4,\n"
         "  absorbing = roger.converged(p.phi0), budget = { episodes = 6 },\n"
         "  contexts = { { name = 'C', actions = { p.search, p.phi0 }, params = { forarm = 0.6 } } } } } }\n";
  try {
    (void)Curriculum::load((tmp.path / "own.lua").string());
    FAIL("loaded");
  } catch (const ScriptError& e) {
    CHECK(e.line == 4);
    CHECK(e.traceback.empty());
  }
}

// Before, a stage's scenario = "rand_clutter.lua" was looked for from the current folder: the
// same curriculum run from another folder failed with "no scenario".
TEST_CASE("a stage's scenario path is found beside the curriculum that names it, as require", "[curriculum]") {
  const test::TempDir tmp("roger_curriculum_near");
  std::filesystem::create_directories(tmp.path / "worlds");
  std::ofstream(tmp.path / "worlds" / "mine.lua")
      << "return { name = 'mine', params = { far = 1.0 },\n"
         "  generate = function(world, rng, p) world:robot{ x = p.far, y = 0 } end }\n";
  const std::string stage = "local p = require('lib.skills').primitives()\n"
                            "return { stages = { roger.stage{ name = 'S', time_limit = 2, scenario = '";
  const std::string rest = "',\n  absorbing = roger.converged(p.phi0), budget = { episodes = 1 },\n"
                           "  contexts = { { name = 'A', actions = { p.phi0 }, params = { far = 0.5 } } } } } }\n";
  std::ofstream(tmp.path / "near.lua") << stage << "worlds/mine.lua" << rest;
  const Curriculum cur = Curriculum::load((tmp.path / "near.lua").string());  // from the repository's folder
  CHECK(cur.stage("S").scenario == (tmp.path / "worlds" / "mine.lua").string());
  // A bare name stays the project's scenario, and a path from the project is recorded as written.
  std::ofstream(tmp.path / "bare.lua") << stage << "cluttered" << rest;
  CHECK_THAT(error_of([&] { Curriculum::load((tmp.path / "bare.lua").string()); }),
             Catch::Matchers::Contains("scenario 'cluttered' (scenarios/cluttered.lua) has no parameter 'far'"));
  std::ofstream(tmp.path / "missing.lua") << stage << "worlds/theirs.lua" << rest;
  CHECK_THAT(error_of([&] { Curriculum::load((tmp.path / "missing.lua").string()); }),
             Catch::Matchers::Contains("missing.lua:2: stage 'S': field 'scenario': no scenario 'worlds/theirs.lua' "
                                       "(named in " + (tmp.path / "missing.lua").string() + "): looked at " +
                                       (tmp.path / "worlds" / "theirs.lua").string() +
                                       ", then worlds/theirs.lua from the current folder, then in the project"));
}

// Found by a probe: a curriculum that set the scenario of a stage lib.paper_stages made
// (`sg.scenario = "bigbot.lua"`) had it looked for beside curricula/lib/, not beside itself.
TEST_CASE("a stage a library made takes a scenario path beside the curriculum that sets it", "[curriculum]") {
  const test::TempDir tmp("roger_curriculum_lib_stage");
  std::ofstream(tmp.path / "bigbot.lua")
      << std::regex_replace(test::slurp("scenarios/unobstructed.lua"), std::regex("name = \"unobstructed\""),
                            "name = \"bigbot\"");
  std::ofstream(tmp.path / "big.lua") << "local SG, T = require('lib.paper_stages').stages{ suffix = '_big' }\n"
                                         "SG.scenario = 'bigbot.lua'\n"
                                         "return { name = 'big', stages = { SG, T } }\n";
  const Curriculum cur = Curriculum::load((tmp.path / "big.lua").string());
  CHECK(cur.stage("SG_big").scenario == (tmp.path / "bigbot.lua").string());
  CHECK(cur.stage("T_big").scenario == "unobstructed");
  // Not there either: each place looked at is named, beside the library first.
  std::ofstream(tmp.path / "none.lua") << "local SG, T = require('lib.paper_stages').stages{ suffix = '_none' }\n"
                                          "SG.scenario = 'nobot.lua'\n"
                                          "return { name = 'none', stages = { SG, T } }\n";
  CHECK_THAT(error_of([&] { Curriculum::load((tmp.path / "none.lua").string()); }),
             Catch::Matchers::Contains("curricula/lib/nobot.lua, then " + (tmp.path / "nobot.lua").string() +
                                       ", then nobot.lua from the current folder, then in the project"));
}

// Found by a probe: a step reward of 1e308 was taken, and training stopped at its first backup with
// "q-table: update() needs a finite reward", naming no file.
TEST_CASE("a reward too large for an episode's sum is refused at the curriculum's line", "[curriculum]") {
  const test::TempDir tmp("roger_curriculum_huge_reward");
  auto write = [&](const std::string& name, const std::string& reward) {
    std::ofstream(tmp.path / name)
        << "local p = require('lib.skills').primitives()\n"
           "return { stages = { roger.stage{ name = 'S', time_limit = 5, absorbing = roger.converged(p.phi3),\n"
           "  reward = " << reward << ",\n"
           "  budget = { episodes = 3 }, contexts = { { name = 'A', actions = { p.phi3, p.phi0 } } } } } }\n";
    return (tmp.path / name).string();
  };
  CHECK_THAT(error_of([&] { Curriculum::load(write("step.lua", "{ step = 1e308 }")); }),
             Catch::Matchers::Contains("step.lua:3: stage 'S': reward: field 'step' must be at most 1e12 in magnitude "
                                       "(an episode's sum of rewards and the Q values must stay finite), got 1e+308"));
  CHECK_THAT(error_of([&] { Curriculum::load(write("timeout.lua", "{ timeout = -2e12 }")); }),
             Catch::Matchers::Contains("field 'timeout' must be at most 1e12 in magnitude"));
  CHECK_NOTHROW(Curriculum::load(write("edge.lua", "{ absorbing = 1e12, timeout = -1e12, step = -1 }")));
  const std::vector<std::string> problems =
      check_curriculum(write("fn.lua", "function(state, action, event) return 1e300 end"));
  REQUIRE(problems.size() == 1);
  CHECK_THAT(problems[0], Catch::Matchers::Contains("fn.lua:3: stage 'S', context 'A': the reward function must "
                                                    "return at most 1e12 in magnitude (an episode's sum of rewards "
                                                    "and the Q values must stay finite), got 1e+300 (event "
                                                    "'decision')"));
}

// Found by a probe: a stage's scenario = "cluttered" trained in the shipped scenarios/cluttered.lua
// while an edited cluttered.lua lay beside the curriculum, without a word. A bare name is one of
// scenarios/ (docs/curricula.md), so shipped curricula and results stay as they were; the stage
// says which file it takes and how to take the other (roger check, train and run print it).
TEST_CASE("a bare scenario name with a scenario of that name beside the curriculum is noted", "[curriculum]") {
  const test::TempDir tmp("roger_curriculum_bare_beside");
  std::ofstream(tmp.path / "cluttered.lua") << test::slurp("scenarios/cluttered.lua");
  const auto write = [&](const std::string& name, const std::string& scenario) {
    std::ofstream(tmp.path / name) << "local p = require('lib.skills').primitives()\n"
                                      "return { stages = { roger.stage{ name = 'S', time_limit = 2,\n" << scenario <<
                                      "  absorbing = roger.converged(p.phi0), budget = { episodes = 1 },\n"
                                      "  contexts = { { name = 'A', actions = { p.phi0 } } } } } }\n";
    return Curriculum::load((tmp.path / name).string());
  };
  const std::string path = (tmp.path / "cur.lua").string(), copy = (tmp.path / "cluttered.lua").string();
  const Curriculum cur = write("cur.lua", "  scenario = 'cluttered',\n");
  CHECK(cur.stage("S").scenario == "cluttered");  // still the shipped one
  CHECK(cur.stage("S").scenario_note() ==
        path + ":3: stage 'S': scenario 'cluttered' is the project's " + resolve_scenario_path("cluttered") +
            " (a bare name is one of scenarios/), not " + copy + " of the same name: to train in that one, name it "
            "with its \".lua\" (scenario = \"cluttered.lua\")");
  // Named with its .lua, the copy is taken, and nothing is said.
  const Curriculum local = write("local.lua", "  scenario = 'cluttered.lua',\n");
  CHECK(local.stage("S").scenario == copy);
  CHECK(local.stage("S").scenario_note().empty());
  // The default scenario too, at the stage's line; a file of the name that is no scenario is not one.
  std::ofstream(tmp.path / "unobstructed.lua") << test::slurp("scenarios/unobstructed.lua");
  CHECK_THAT(write("default.lua", "").stage("S").scenario_note(),
             Catch::Matchers::StartsWith((tmp.path / "default.lua").string() + ":2: stage 'S': scenario 'unobstructed' "));
  std::ofstream(tmp.path / "unobstructed.lua") << "return { shift = 1 }\n";
  CHECK(write("module.lua", "").stage("S").scenario_note().empty());
  // Shipped curricula beside their own libraries (curricula/lib/sorting.lua, of stages of scenario
  // "sorting") have none.
  for (const char* shipped : {"paper", "sorting", "maturation", "teachers", "ablation"}) {
    const Curriculum curriculum = Curriculum::load(shipped);  // named: a range-for over a temporary's member dangles
    for (const auto& st : curriculum.stages()) CHECK(st.scenario_note().empty());
  }
}

TEST_CASE("a context's init names a context written before it", "[curriculum]") {
  const test::TempDir tmp("roger_curriculum_init");
  auto write = [&](const std::string& name, const std::string& b_init, const std::string& b_actions = "p.phi3, p.phi1") {
    std::ofstream(tmp.path / name)
        << "local p = require('lib.skills').primitives()\n"
           "return { stages = { roger.stage{ name = 'S', time_limit = 5, absorbing = roger.converged(p.phi3),\n"
           "  budget = { episodes = 3 }, contexts = {\n"
           "    { name = 'A', actions = { p.phi3 } },\n"
           "    { name = 'B', actions = { " << b_actions << " },\n"
           "      init = " << b_init << " } } } } }\n";
    return (tmp.path / name).string();
  };
  const Curriculum cur = Curriculum::load(write("ok.lua", "{ context = 'A' }"));
  CHECK(cur.stage("S").context("B").init_stage == "S");  // the same stage unless named
  CHECK(cur.stage("S").context("B").init_context == "A");
  CHECK(cur.stage("S").context("A").init_context.empty());
  CHECK_THAT(error_of([&] { Curriculum::load(write("self.lua", "{ context = 'B' }")); }),
             Catch::Matchers::Contains("self.lua:6: stage 'S', context 'B': init = {stage = 'S', context = 'B'} names "
                                       "this context itself, whose table it would start from: name one written before; "
                                       "the contexts written before this one: S/A"));
  // Found by a probe: a table that shares no action passed check, and training refused it after
  // the init context had trained.
  CHECK_THAT(error_of([&] { Curriculum::load(write("disjoint.lua", "{ context = 'A' }", "p.phi1, p.phi0")); }),
             Catch::Matchers::Contains("disjoint.lua:6: stage 'S', context 'B': init = {stage = 'S', context = 'A'} "
                                       "shares no action with this context, so nothing of its table could be carried "
                                       "over (its actions: phi3; this context's: phi1, phi0)"));
  CHECK_THAT(error_of([&] { Curriculum::load(write("typo.lua", "{ contxt = 'A' }")); }),
             Catch::Matchers::Contains("typo.lua:6: stage 'S': context 2:") &&
                 Catch::Matchers::Contains("init: unknown field 'contxt' (did you mean 'context'?)"));
}

TEST_CASE("a stage's learner may discount by the seconds a decision ran", "[curriculum]") {
  // The semi-MDP's clock (SemiMdpDriver, tested in tests/test_learning.cpp): once per
  // decision by default, as the paper; by elapsed time when a stage asks ("a semi-MDP transition pays
  // the rewards since its decision and discounts the bootstrap").
  const test::TempDir tmp("roger_curriculum_clock");
  std::ofstream(tmp.path / "clock.lua")
      << "local p3 = roger.primitive(\"phi3\")\n"
         "local function stage(name, learner)\n"
         "  return roger.stage{ name = name, time_limit = 5, absorbing = roger.converged(p3),\n"
         "    budget = { episodes = 3 }, learner = learner, contexts = { { name = \"A\", actions = { p3 } } } }\n"
         "end\n"
         "return { stages = { stage(\"PerDecision\", { alpha = 0.2 }),\n"
         "                    stage(\"PerSecond\", { discount = 0.9, discount_seconds = 2.5 }) } }\n";
  Curriculum cur = Curriculum::load((tmp.path / "clock.lua").string());
  CHECK(cur.stage("PerDecision").rewards.discount_seconds == 0.0);
  CHECK(cur.stage("PerSecond").rewards.discount_seconds == 2.5);
  CHECK(cur.stage("PerSecond").learner.discount == 0.9);
}

TEST_CASE("a stage's learner may choose among the actions still on their way first", "[curriculum]") {
  const test::TempDir tmp("roger_curriculum_unconverged");
  std::ofstream(tmp.path / "eager.lua") << R"(local p3 = roger.primitive("phi3")
local function stage(name, learner)
  return roger.stage{ name = name, time_limit = 5, absorbing = roger.converged(p3), budget = { episodes = 3 },
                      learner = learner, contexts = { { name = "A", actions = { p3 } } } }
end
return { stages = { stage("Paper", nil), stage("Eager", { unconverged_first = true, referenced_only = true }) } }
)";
  const Curriculum cur = Curriculum::load((tmp.path / "eager.lua").string());
  CHECK_FALSE(cur.stage("Paper").learner.unconverged_first);  // the paper's learner, by default
  CHECK(cur.stage("Eager").learner.unconverged_first);
  CHECK(cur.stage("Eager").learner.referenced_only);
}

TEST_CASE("a stage's time limit may be given per object of its world", "[curriculum]") {
  const test::TempDir tmp("roger_curriculum_per_object");
  std::ofstream(tmp.path / "limits.lua") << R"(local p3 = roger.primitive("phi3")
local function stage(name, limit)
  return roger.stage{ name = name, scenario = "sorting", time_limit = limit, absorbing = roger.converged(p3),
                      budget = { episodes = 3 }, contexts = { { name = "A", actions = { p3 } } } }
end
return { stages = { stage("Fixed", 12), stage("PerObject", { per_object = 30 }) } }
)";
  Curriculum cur = Curriculum::load((tmp.path / "limits.lua").string());
  WorldSpec two, eight;
  two.objects.resize(2);
  eight.objects.resize(8);
  const CurriculumStage &fixed = cur.stage("Fixed"), &per_object = cur.stage("PerObject");
  CHECK(fixed.episode_time_limit(two) == 12.0);
  CHECK(fixed.episode_time_limit(eight) == 12.0);
  CHECK(fixed.time_limit_text() == "12 s limit");
  CHECK(per_object.episode_time_limit(two) == 60.0);
  CHECK(per_object.episode_time_limit(eight) == 240.0);
  CHECK(per_object.time_limit_text() == "30 s per object limit");
}

TEST_CASE("the documented example curriculum loads and trains without rebuilding", "[curriculum]") {
  Curriculum cur = Curriculum::load("docs/examples/curriculum_example.lua");
  REQUIRE(cur.stages().size() == 1);
  const CurriculumStage& st = cur.stages()[0];
  CHECK(st.name == "Look");
  CHECK(st.reward_lua);
  TrainOptions o;
  o.curriculum = "docs/examples/curriculum_example.lua";
  o.stage = "Look";
  o.context = "Gaze";
  o.seed = 3;
  const TrainResult r = train_stage(o);
  INFO("final success " << r.final_eval.success_rate);
  CHECK(r.final_eval.success_rate >= 0.9);
  CHECK(r.reached);
}

TEST_CASE("the callbacks' episode table starts empty every episode", "[curriculum]") {
  Curriculum cur = Curriculum::load("tests/scripts/curriculum_episode_notes.lua");
  const CurriculumStage& st = cur.stage("S");
  const CurriculumContext& ctx = st.context("A");
  const std::vector<Gamma> state = {Gamma::kNotConv, Gamma::kNotConv};
  cur.begin_episode();
  CHECK(cur.call_reward(st, ctx, state, 0, "decision", 0.1) == 1.0);
  CHECK(cur.call_reward(st, ctx, state, 1, "decision", 0.2) == 2.0);
  CHECK_FALSE(cur.call_absorbing(st, ctx, state, 0.2));
  CHECK(cur.call_reward(st, ctx, state, 1, "decision", 0.3) == 3.0);
  CHECK(cur.call_absorbing(st, ctx, state, 0.3));  // both callbacks see the same table
  cur.begin_episode();
  CHECK_FALSE(cur.call_absorbing(st, ctx, state, 0.0));
  CHECK(cur.call_reward(st, ctx, state, 0, "timeout", 0.5) == 1.0);
}

// Found by a probe: roger.sequence in an absorbing function passed roger check and failed in
// training at its second call ("already a controller named"); roger.primitive, roger.learned and
// roger.stage there were taken without a word, each call making another.
TEST_CASE("the functions that make controllers, predicates and stages refuse to once the script has loaded",
          "[curriculum]") {
  test::TempDir dir("roger_make_in_callback");
  const std::string path = (dir.path / "late.lua").string();
  const std::vector<Gamma> state = {Gamma::kNoRef, Gamma::kNoRef};
  for (const auto& [call, what] : std::vector<std::pair<std::string, std::string>>{
           {"roger.sequence('Dup', {'phi0'})", "roger.sequence: controllers and predicates"},
           {"roger.primitive('phi0')", "roger.primitive: controllers and predicates"},
           {"roger.converged('phi0')", "roger.converged: controllers and predicates"},
           {"roger.learned('Phi_X')", "roger.learned: the stand-ins of learned skills"},
           {"roger.stage{ name = 'X' }", "roger.stage: stages"}}) {
    std::ofstream(path) << "local function absorbing(state)\n  local made = " << call << "\n  return false\nend\n"
                        << "return { stages = { roger.stage{ name = 'S', time_limit = 3, absorbing = absorbing, budget = { episodes = 2 },\n"
                        << "  contexts = { { name = 'A', actions = { 'search', 'phi0' } } } } } }\n";
    Curriculum cur = Curriculum::load(path);
    const CurriculumStage& st = cur.stage("S");
    cur.begin_episode();
    CHECK_THAT(error_of([&] { cur.call_absorbing(st, st.context("A"), state, 0.0); }),
               Catch::Matchers::Contains("late.lua:2: stage 'S', context 'A': absorbing function: " + what + " are made while the script loads, and this call "
                                         "comes once it has loaded, from a function the engine calls as it runs (an "
                                         "absorbing, reward or teacher function), where each call would make "
                                         "another: make it at the script's top level and use that one here"));
  }
}

// Found by a probe: a teacher's rng kept and drawn in absorbing passed roger check, whose
// callbacks ran before any teacher, and training refused it at its first episode.
TEST_CASE("roger check calls the callbacks again once a Lua teacher has run", "[curriculum]") {
  test::TempDir dir("roger_teacher_rng_kept");
  const std::string path = (dir.path / "kept.lua").string();
  std::ofstream(path) << "local kept\n"
                         "local function teacher(history, rng) kept = rng return {} end\n"
                         "local function absorbing(state) if kept then kept:uniform() end return false end\n"
                         "return { stages = { roger.stage{ name = 'S', time_limit = 3, budget = { episodes = 2 },\n"
                         "  contexts = { { name = 'A', actions = { 'search', 'phi0' } } }, absorbing = absorbing,\n"
                         "  tasks = { shape = roger.choice{ 'circle', 'spade' } }, teacher = teacher } } }\n";
  const std::vector<std::string> problems = check_curriculum(path);
  REQUIRE(problems.size() == 1);
  CHECK_THAT(problems[0], Catch::Matchers::Contains("kept.lua:3: stage 'S', context 'A': absorbing function: "
                                                    "rng:uniform: this rng is a teacher function's, and draws only "
                                                    "while that function runs"));
}

// curricula/maturation.lua (docs/curricula.md, Contexts that change the body): a context's scenario
// parameters lie over its stage's, so SG is learned with coarse eyes and T with the full body.
TEST_CASE("a context's scenario params restrict the body of its worlds alone", "[curriculum]") {
  Curriculum cur = Curriculum::load("curricula/maturation.lua");
  const CurriculumStage& sg = cur.stage("SG_coarse");
  const CurriculumStage& t = cur.stage("T_coarse");
  const auto restricted = sg.scenario_params(sg.context("DC2"));
  CHECK(restricted == std::vector<std::pair<std::string, std::string>>{{"eye_fov", "1.0472"}, {"eye_pixels", "32"}});
  CHECK(t.scenario_params(t.context("DC6")).empty());
  TrainOptions o;
  o.curriculum = "curricula/maturation.lua";
  o.stage = "SG_coarse";
  o.context = "DC2";
  o.seed = 1;
  const TrainResult r = train_stage(o);
  auto param = [](const TrainResult& res, const std::string& key) {
    for (const auto& [k, v] : res.params)
      if (k == key) return v;
    return std::string("absent");
  };
  CHECK(param(r, "eye_pixels") == "32");
  CHECK(r.reached);  // Phi_SG is learned with 32-pixel eyes too
  o.stage = "T_coarse";
  o.context = "DC6";
  const TrainResult tr = train_stage(o);
  CHECK(param(tr, "eye_pixels") == "128");
  CHECK(tr.reached);
}

TEST_CASE("a map context with fields, and bad context params, are read where they are written", "[curriculum]") {
  roger::test::TempDir dir;
  const std::string path = (dir.path / "ctx.lua").string();
  std::ofstream(path) << "local p = require('lib.skills').primitives()\n"
                         "return { stages = { roger.stage{ name = 'S', time_limit = 2,\n"
                         "  absorbing = roger.converged(p.phi0), budget = { episodes = 1 },\n"
                         "  params = { eye_pixels = 64, shape = 'spade' },\n"
                         "  contexts = { A = { actions = { p.phi0 }, params = { eye_pixels = 16 } }, B = { p.phi0 } } } } }\n";
  Curriculum cur = Curriculum::load(path);
  const CurriculumStage& s = cur.stage("S");
  CHECK(s.scenario_params(s.context("A")) ==
        std::vector<std::pair<std::string, std::string>>{{"eye_pixels", "16"}, {"shape", "spade"}});
  CHECK(s.scenario_params(s.context("B")) ==
        std::vector<std::pair<std::string, std::string>>{{"eye_pixels", "64"}, {"shape", "spade"}});
  const std::string bad = (dir.path / "bad.lua").string();
  std::ofstream(bad) << "local p = require('lib.skills').primitives()\n"
                        "return { stages = { roger.stage{ name = 'S', time_limit = 2,\n"
                        "  absorbing = roger.converged(p.phi0), budget = { episodes = 1 },\n"
                        "  contexts = { { name = 'A', actions = { p.phi0 }, params = { eye_pixels = {} } } } } } }\n";
  CHECK_THROWS_WITH(Curriculum::load(bad), Catch::Matchers::Contains("bad.lua:4:") &&  // the context's line
                                               Catch::Matchers::Contains("params.eye_pixels must be a number, string or boolean"));
  // Found by a probe: a map context with a misspelt 'actions' was told "the actions must be a plain
  // list {a, b, ...}, got the key string 'action'".
  const std::string typo = (dir.path / "typo.lua").string();
  std::ofstream(typo) << "local p = require('lib.skills').primitives()\n"
                         "return { stages = { roger.stage{ name = 'S', time_limit = 2,\n"
                         "  absorbing = roger.converged(p.phi0), budget = { episodes = 1 },\n"
                         "  contexts = { A = { p.phi0 }, B = { actoins = { p.phi0 }, params = { eye_pixels = 16 } } } } } }\n";
  CHECK_THAT(error_of([&] { Curriculum::load(typo); }),
             Catch::Matchers::Contains("typo.lua:4: stage 'S', context 'B': a context of the map form is a list of "
                                       "actions {a, b, ...} or a table {actions = {...}, params = {...}, init = "
                                       "{...}}; this one has the field 'actoins' (did you mean 'actions'?) and no "
                                       "field 'actions'"));
  const std::string unbuildable = (dir.path / "unbuildable.lua").string();
  std::ofstream(unbuildable) << "local p = require('lib.skills').primitives()\n"
                                "return { stages = { roger.stage{ name = 'S', time_limit = 2,\n"
                                "  absorbing = roger.converged(p.phi0), budget = { episodes = 1 },\n"
                                "  contexts = { { name = 'A', actions = { p.phi0 } },\n"
                                "               { name = 'Tiny', actions = { p.phi0 }, params = { eye_pixels = 4 } } } } } }\n";
  // A bad parameter is refused where the curriculum loads, at the line of the params table that
  // gives it, with each bad one named. Before: "stage 'S': scenario 'unobstructed': parameter
  // 'eye_pixels' ... expects at least 16, got '3'", with no file:line, from roger check or the trial.
  const std::string lines = (dir.path / "lines.lua").string();
  std::ofstream(lines) << "local p = require('lib.skills').primitives()\n"
                          "return { stages = { roger.stage{ name = 'S', time_limit = 2,\n"
                          "  absorbing = roger.converged(p.phi0), budget = { episodes = 1 },\n"
                          "  contexts = {\n"
                          "    { name = 'A', actions = { p.phi0 } },\n"
                          "    { name = 'Tiny', actions = { p.phi0 },\n"
                          "      params = { eye_pixels = 3, shap = 'spade' } } } } } }\n";
  CHECK_THAT(error_of([&] { Curriculum::load(lines); }),
             Catch::Matchers::Contains("lines.lua:7: stage 'S', context 'Tiny': params: parameter 'eye_pixels' of "
                                       "scenario 'unobstructed' expects an integer in [16, 512], got '3' "
                                       "(pixels of each eye; default 128); scenario 'unobstructed'") &&
                 Catch::Matchers::Contains("has no parameter 'shap' (did you mean 'shape'?)"));
  const std::string plain = (dir.path / "plain.lua").string();  // a stage as a plain table
  std::ofstream(plain) << "local p = require('lib.skills').primitives()\n"
                          "return { stages = { {\n"
                          "  name = 'S', time_limit = 2, scenario = 'cluttered',\n"
                          "  absorbing = roger.converged(p.phi0), budget = { episodes = 1 },\n"
                          "  params = {\n"
                          "    obstacles = 40 },\n"
                          "  contexts = { { name = 'A', actions = { p.phi0 } } } } } }\n";
  CHECK_THAT(error_of([&] { Curriculum::load(plain); }),
             Catch::Matchers::Contains("plain.lua:5: stage 'S': params: parameter 'obstacles' of scenario 'cluttered' "
                                       "expects an integer in [0, 8], got '40'"));
  // Found by a probe: `capsule = 0` for a boolean parameter was taken as false (the command
  // line's --set capsule=0), where Lua reads 0 as true. In Lua a boolean takes true or false.
  const std::string corridor = (dir.path / "corridor.lua").string();
  std::ofstream(corridor) << test::slurp("docs/examples/corridor.lua");
  auto with_capsule = [&](const std::string& value) {
    std::ofstream(dir.path / "boolean.lua") << "local p = require('lib.skills').primitives()\n"
                                                "return { stages = { roger.stage{ name = 'S', time_limit = 2,\n"
                                                "  absorbing = roger.converged(p.phi0), budget = { episodes = 1 },\n"
                                                "  scenario = 'corridor.lua',\n"
                                                "  params = { capsule = " << value << " },\n"
                                                "  contexts = { { name = 'A', actions = { p.phi0 } } } } } }\n";
    return error_of([&] { Curriculum::load((dir.path / "boolean.lua").string()); });
  };
  CHECK_THAT(with_capsule("0"), Catch::Matchers::Contains("boolean.lua:5: stage 'S': params: parameter 'capsule' of "
                                                          "scenario 'corridor' is a boolean: write capsule = true or "
                                                          "capsule = false, got '0' (Lua reads 0 as true"));
  CHECK_THAT(with_capsule("'no'"), Catch::Matchers::Contains("is a boolean: write capsule = true"));
  CHECK(with_capsule("false").empty());
  CHECK(with_capsule("true").empty());
  const auto problems = check_curriculum(unbuildable);
  REQUIRE(problems.size() == 1);
  CHECK_THAT(problems[0], Catch::Matchers::Contains("context 'Tiny'") && Catch::Matchers::Contains("eye_pixels"));
}

// Found by a probe: each of these was reported at the roger.stage{ line (2), however far below it
// the field was written.
TEST_CASE("a stage's bad field is reported at the line it is written on", "[curriculum]") {
  const test::TempDir tmp("roger_stage_field_lines");
  auto error_with = [&](const std::string& name, const std::string& field, const std::string& context_a) {
    const auto path = tmp.path / name;
    std::ofstream(path) << "local p = require('lib.skills').primitives()\n"
                           "return { stages = { roger.stage{\n"
                           "  name = 'S',\n"
                           "  time_limit = 5,\n"
                           "  absorbing = roger.converged(p.phi3), budget = { episodes = 3 },\n"
                        << "  " << field << "\n"
                        << "  contexts = {\n"
                           "    { name = 'B', actions = { p.phi3 } },\n"
                        << "    " << context_a << "\n"
                        << "  },\n"
                           "} } }\n";
    return error_of([&] { Curriculum::load(path.string()); });
  };
  const std::string good = "{ name = 'A', actions = { p.phi3, p.phi1 } },";
  using Catch::Matchers::Contains;
  CHECK_THAT(error_with("typo.lua", "time_limt = 12,", good),
             Contains("typo.lua:6: stage 'S': unknown field 'time_limt' (did you mean 'time_limit'?)"));
  // Found by a probe: with the curriculum's name on the call's line, every field's error stayed at
  // that line (the curriculum's table was taken for the stage's).
  {
    const auto named = tmp.path / "named_curriculum.lua";
    std::ofstream(named) << "local p = require('lib.skills').primitives()\n"
                            "return { name = 't', stages = { roger.stage{\n"
                            "  name = 'S', time_limit = 5,\n"
                            "  absorbing = roger.converged(p.phi3), budget = { episodes = 3 },\n"
                            "  contexts = { { name = 'B', actions = { p.phi3 } } },\n"
                            "  tasks = {},\n"
                            "} } }\n";
    CHECK_THAT(error_of([&] { Curriculum::load(named.string()); }),
               Contains("named_curriculum.lua:6: stage 'S': field 'tasks' is empty"));
  }
  CHECK_THAT(error_with("learner.lua", "learner = { alpah = 0.2 },", good),
             Contains("learner.lua:6: stage 'S': learner: unknown field 'alpah' (did you mean 'alpha'?)"));
  CHECK_THAT(error_with("checkpoints.lua", "checkpoints = {\n    every = -5 },", good),
             Contains("checkpoints.lua:7: stage 'S': checkpoints: field 'every' must be"));
  // Found by a probe: every past the budget gave one checkpoint, after the last episode.
  CHECK_THAT(error_with("every.lua", "checkpoints = {\n    every = 4 },", good),
             Contains("every.lua:7: stage 'S': checkpoints: field 'every' is 4, more than the budget's 3 episodes: "
                      "the only checkpoint would follow the last episode"));
  // Found by a probe: these two were still at the roger.stage{ line.
  CHECK_THAT(error_with("tasks.lua", "tasks = {\n    mass = 0.3 },", good),
             Contains("tasks.lua:7: stage 'S': tasks.mass must be roger.int(lo, hi), roger.real(lo, hi) or "
                      "roger.choice{...}, got number 0.3 (a fixed value belongs in params)"));
  CHECK_THAT(error_with("teacher.lua", "teacher = roger.teacher.random{},", good),
             Contains("teacher.lua:6: stage 'S': field 'teacher': roger.teacher.random needs a task space"));
  CHECK_THAT(error_with("type.lua", "description = 3,", good),
             Contains("type.lua:6: stage 'S': field 'description' must be"));
  CHECK_THAT(error_with("empty.lua", "", "{ name = 'A', actions = {} },"),
             Contains("empty.lua:9: stage 'S', context 'A': Psi is empty"));
  CHECK_THAT(error_with("nme.lua", "", "{ nme = 'A', actions = { p.phi3 } },"),
             Contains("nme.lua:9: stage 'S': context 2: unknown field 'nme' (did you mean 'name'?)"));
  // A second context of a name, at its own line (found by a probe: at the stage's, not saying
  // where the first was).
  CHECK_THAT(error_with("twice.lua", "", "{ name = 'B', actions = { p.phi1 } },"),
             Contains("twice.lua:9: stage 'S': context 2: a second context named 'B' (context 1 is named so)"));
  // Found by a probe: what is found after the call, a learned skill no stage yields or an action's
  // name nothing defines, was reported at the stage's line; it is at its context's.
  CHECK_THAT(error_with("learned.lua", "", "{ name = 'A', actions = { p.phi3, roger.learned('Nope') } },"),
             Contains("learned.lua:9: stage 'S', context 'A': roger.learned('Nope') names no skill"));
  // Found by a probe: a learned skill named as a primitive kind, or as a controller the script
  // defines, passed, and read as that controller in Psi's errors and in usage.
  CHECK_THAT(error_with("kind.lua", "", "{ name = 'A', actions = { p.phi3, roger.learned('phi0') } },"),
             Contains("kind.lua:9: roger.learned: the name 'phi0' is a primitive kind, which always means that kind's "
                      "default primitive; a learned skill needs another name (e.g. 'phi0_learned')"));
  CHECK_THAT(error_with("yields_kind.lua", "skill = { name = 'phi1', context = 'B' },", good),
             Contains("yields_kind.lua:6: stage 'S': skill: field 'name': the name 'phi1' is a primitive kind"));
  CHECK_THAT(error_with("yields_named.lua", "skill = { name = 'Phi6' }, x = require('lib.skills').Phi6(p),", good),
             Contains("unknown field 'x'"));
  CHECK_THAT(error_with("yields_named.lua", "skill = { name = 'Phi6', context = 'B' },",
                        "{ name = 'A', actions = { p.phi3, require('lib.skills').Phi6(p) } },"),
             Contains("yields_named.lua:6: stage 'S': skill: 'Phi6' is the name of a controller the script defines (at ") &&
                 Contains("yields_named.lua:9); a learned skill and a controller of one name would read as one"));
  // Found by a probe: written through a helper module's roger.stage, the name's error named the
  // module's line alone; its traceback now names the author's line that called it.
  {
    std::ofstream(tmp.path / "helper_stages.lua") << "local M = {}\n"
                                                     "function M.look(p, actions)\n"
                                                     "  return roger.stage{ name = 'Look', time_limit = 3,\n"
                                                     "    absorbing = roger.converged(p.phi0), budget = { episodes = 4 },\n"
                                                     "    contexts = { { name = 'A', actions = actions } } }\n"
                                                     "end\n"
                                                     "return M\n";
    const auto path = tmp.path / "uses_helper.lua";
    std::ofstream(path) << "local p = require('lib.skills').primitives()\n"
                           "local M = require('helper_stages')\n"
                           "return { stages = { M.look(p, { p.search, 'phi00' }) } }\n";
    const std::string error = error_of([&] { Curriculum::load(path.string()); });
    CHECK_THAT(error, Contains("helper_stages.lua:5: stage 'Look', context 'A': action 2 names 'phi00', which is not "
                               "defined anywhere in the script (did you mean 'phi0'?)") &&
                          Contains("uses_helper.lua:3: in main chunk"));
  }
  CHECK_THAT(error_with("named.lua", "", "{ name = 'A', actions = { p.phi3, 'transprot' } },"),
             Contains("named.lua:9: stage 'S', context 'A': action 2 names 'transprot', which is not defined"));
  // A named context beside the list was dropped without a word (found by a probe): refused.
  CHECK_THAT(error_with("mixed.lua", "", "A = { p.phi3, p.phi1 },"),
             Contains("mixed.lua:7: stage 'S': field 'contexts' mixes a list with the named entry 'A': write it in "
                      "the list as {name = ..., actions = {...}}, or every context as a map"));
  // So was a named stage beside the list of stages.
  const auto path = tmp.path / "stages.lua";
  std::ofstream(path) << "local p = require('lib.skills').primitives()\n"
                         "local function st(name)\n"
                         "  return roger.stage{ name = name, time_limit = 5, absorbing = roger.converged(p.phi3),\n"
                         "    budget = { episodes = 3 }, contexts = { { name = 'A', actions = { p.phi3 } } } }\n"
                         "end\n"
                         "return { stages = { st('S1'), Extra = st('S2') } }\n";
  CHECK_THAT(error_of([&] { Curriculum::load(path.string()); }),
             Contains("stages.lua:6: the curriculum: 'stages' must be a list {roger.stage{...}, ...}; it also has the "
                      "named entry 'Extra', which would be left out: write it in the list"));
  // Found by a probe: a message quoting 100,000 characters crashed roger check: std::regex's
  // matcher, reading the message for its field's line, recursed once per character and
  // overflowed the stack. So did finding a plain-table stage's line by a name that long.
  CHECK_THAT(error_with("long.lua", "learner = {\n    [string.rep('x', 100000)] = 1 },", good),
             Contains("long.lua:6: stage 'S': learner: unknown field '" + std::string(10, 'x')));
  const std::string long_name(100000, 'x');
  const auto plain = tmp.path / "plain.lua";
  std::ofstream(plain) << "local p = require('lib.skills').primitives()\n"
                          "return { stages = {\n"
                          "  { name = '" << long_name << "', time_limit = 5, absorbing = roger.converged(p.phi3),\n"
                          "    budget = { episodes = 3 }, contexts = { { name = 'A', actions = { p.phi3 } } }, bogus = 1 } } }\n";
  CHECK_THAT(error_of([&] { Curriculum::load(plain.string()); }),
             Contains("plain.lua:3: stage '" + long_name + "': unknown field 'bogus'"));
  // Found by a probe: a name of the wrong type was "missing required field 'name'".
  const auto numbered = tmp.path / "numbered.lua";
  std::ofstream(numbered) << "local p = require('lib.skills').primitives()\n"
                             "return { stages = { roger.stage{ name = 5, time_limit = 5,\n"
                             "  absorbing = roger.converged(p.phi3), budget = { episodes = 3 },\n"
                             "  contexts = { { name = 'A', actions = { p.phi3 } } } } } }\n";
  CHECK_THAT(error_of([&] { Curriculum::load(numbered.string()); }),
             Contains("numbered.lua:2: a stage: field 'name' must be a string such as \"SG\", got number 5"));
}

namespace {

// Loads a one-stage curriculum whose stage has `fields` (absorbing, reward, time_limit) on its
// third line; the error's message, "" when it loads.
std::string stage_error(const std::filesystem::path& dir, const std::string& fields) {
  const auto path = dir / "stage.lua";
  std::ofstream(path) << "local p = require('lib.skills').primitives()\n"
                         "return { stages = { roger.stage{ name = 'S', budget = { episodes = 3 },\n"
                      << "  " << fields << "\n"
                      << "  contexts = { { name = 'A', actions = { p.search, p.phi0 } } } } } }\n";
  return error_of([&] { Curriculum::load(path.string()); });
}

}  // namespace

// Found by a probe: `absorbing = roger.all{}` passed roger check, and every episode would have
// succeeded at its first tick, where roger.any{} (which never holds) was refused.
TEST_CASE("a stage whose absorbing state holds at once is refused, as one that never holds", "[curriculum]") {
  const test::TempDir tmp("roger_stage_all_empty");
  using Catch::Matchers::Contains;
  CHECK_THAT(stage_error(tmp.path, "time_limit = 4, absorbing = roger.all{},"),
             Contains("stage.lua:3: stage 'S': field 'absorbing': all() always holds: it rests on a roger.all() of no "
                      "parts, which is true, or on the roger.negate of a predicate that never holds, so every episode "
                      "would end in success at its first tick"));
  CHECK_THAT(stage_error(tmp.path, "time_limit = 4, absorbing = roger.any{},"),
             Contains("stage.lua:3: stage 'S': field 'absorbing': any() can never hold: it rests on a roger.any() of no "
                      "parts, which is false"));
  CHECK_THAT(stage_error(tmp.path, "time_limit = 4, absorbing = roger.negate(roger.any{}),"),
             Contains("stage.lua:3: stage 'S': field 'absorbing': not(any()) always holds"));
  // Whatever the time limit, and through an any it decides.
  CHECK_THAT(stage_error(tmp.path, "time_limit = { per_object = 4 }, absorbing = roger.all{},"),
             Contains("stage.lua:3: stage 'S': field 'absorbing': all() always holds"));
  CHECK_THAT(stage_error(tmp.path, "time_limit = 4, absorbing = roger.any{roger.converged(p.phi0), roger.all()},"),
             Contains("field 'absorbing': any(converged(phi0), all()) always holds"));
  CHECK(stage_error(tmp.path, "time_limit = 4, absorbing = roger.all{roger.converged(p.phi0)},").empty());
  // Found by a probe: held() of a truth passed, and trained to 100% success in two episodes.
  CHECK_THAT(stage_error(tmp.path, "time_limit = 4, absorbing = roger.held(roger.all{}, 0.5),"),
             Contains("stage.lua:3: stage 'S': field 'absorbing': held(all(), 0.500 s) holds after 0.5 simulated "
                      "seconds whatever happens"));
}

// Found by a probe: `absorbing = roger.converged` (the function, its call forgotten) loaded, and
// roger check blamed "[C]:", no line of the curriculum, for the arguments of the call it then made
// as a callback's; `reward = roger.converged` too.
TEST_CASE("a control function given itself as absorbing or reward is refused at its field", "[curriculum]") {
  const test::TempDir tmp("roger_stage_function_itself");
  using Catch::Matchers::Contains;
  CHECK_THAT(stage_error(tmp.path, "time_limit = 4, absorbing = roger.converged,"),
             Contains("stage.lua:3: stage 'S': field 'absorbing' is the function roger.converged itself, not a "
                      "predicate: did you mean roger.converged(c)?"));
  const std::vector<std::pair<std::string, std::string>> makers = {
      {"gamma", "roger.gamma(c, \"CONV\")"}, {"all", "roger.all{p1, p2}"},     {"any", "roger.any{p1, p2}"},
      {"negate", "roger.negate(p)"},        {"held", "roger.held(p, seconds)"}, {"sorted", "roger.sorted()"}};
  for (const auto& [name, call] : makers)
    CHECK_THAT(stage_error(tmp.path, "time_limit = 4, absorbing = roger." + name + ","),
               Contains("stage.lua:3: stage 'S': field 'absorbing' is the function roger." + name +
                        " itself, not a predicate: did you mean " + call + "?"));
  CHECK_THAT(stage_error(tmp.path, "time_limit = 4, absorbing = roger.primitive,"),
             Contains("stage.lua:3: stage 'S': field 'absorbing' is the function roger.primitive itself, not a "
                      "predicate: write a predicate such as roger.converged(c), or a function(state)"));
  CHECK_THAT(stage_error(tmp.path, "time_limit = 4, absorbing = roger.converged(p.phi0), reward = roger.converged,"),
             Contains("stage.lua:3: stage 'S': field 'reward' is the function roger.converged itself, not a reward: "
                      "give a table {absorbing = 100, timeout = -100, step = 0} or a function(state, action, "
                      "event); a condition such as roger.converged(c) belongs in 'absorbing'"));
  // A Lua function is a callback, as before.
  CHECK(stage_error(tmp.path, "time_limit = 4, absorbing = function(state) return state.phi0 == 'CONV' end,\n"
                              "  reward = function() return 0 end,")
            .empty());
}

TEST_CASE("changes made to a roger.stage table after the call count and are checked", "[curriculum]") {
  // A wrapper that shortens a required curriculum's budgets once trained the original's 400
  // episodes silently (tests/scripts/kill_curriculum.lua among them).
  Curriculum kill = Curriculum::load("tests/scripts/kill_curriculum.lua");
  for (const auto& stage : kill.stages()) {
    CHECK(stage.budget_episodes == 20);
    CHECK(stage.checkpoints.final_episodes == 6);
  }
  test::TempDir dir("roger_stage_edits");
  const std::string wrapper = (dir.path / "wrapper.lua").string();
  std::ofstream(wrapper) << "local paper = require('paper')\npaper.stages[2].budget = { episodes = -5 }\nreturn paper\n";
  CHECK_THAT(error_of([&] { Curriculum::load(wrapper); }),
             Catch::Matchers::Contains("curricula/lib/paper_stages.lua:124: stage 'T': budget: field 'episodes' must be a "
                                       "positive integer, got -5"));
  // Its upper bound is named when crossed (found by a probe).
  std::ofstream(wrapper) << "local paper = require('paper')\npaper.stages[2].budget = { episodes = 2147483647 }\nreturn paper\n";
  CHECK_THAT(error_of([&] { Curriculum::load(wrapper); }),
             Catch::Matchers::Contains("stage 'T': budget: field 'episodes' must be a positive integer of at most "
                                       "100000000, got 2147483647"));
  std::ofstream(wrapper) << "local paper = require('paper')\npaper.stages[1].bogus = 3\nreturn paper\n";
  CHECK_THAT(error_of([&] { Curriculum::load(wrapper); }),
             Catch::Matchers::Contains("curricula/lib/paper_stages.lua:106: stage 'SG': unknown field 'bogus'"));
  // That line had accepted the table: the error says the change came after (found by a probe: a
  // wrapper's misspelt learner field read as the library's mistake).
  std::ofstream(wrapper) << "local paper = require('paper')\npaper.stages[1].learner.alpah = 0.3\nreturn paper\n";
  CHECK_THAT(error_of([&] { Curriculum::load(wrapper); }),
             Catch::Matchers::Contains("curricula/lib/paper_stages.lua:106: stage 'SG': learner: unknown field 'alpah' "
                                       "(did you mean 'alpha'?)"));
  CHECK_THAT(error_of([&] { Curriculum::load(wrapper); }),
             Catch::Matchers::Contains("(roger.stage accepted this stage's table here; it was changed after roger.stage "
                                       "returned it, and the curriculum reads it again, with the change, when the "
                                       "script returns)"));
  // A mistake roger.stage saw itself is said without it.
  std::ofstream(wrapper) << "return { stages = { roger.stage{ name = 'S', bogus = 1 } } }\n";
  CHECK_THAT(error_of([&] { Curriculum::load(wrapper); }), !Catch::Matchers::Contains("roger.stage accepted"));
}

// Found by a probe: these two took (and dropped) extra arguments, where every other function of
// the API refuses them at the call's line.
TEST_CASE("roger.stage and roger.learned refuse an extra argument at its line", "[curriculum]") {
  test::TempDir dir("roger_stage_arity");
  const std::string path = (dir.path / "extra.lua").string();
  std::ofstream(path) << "local x = roger.learned('Phi_SG', 2)\nreturn { stages = {} }\n";
  CHECK_THAT(error_of([&] { Curriculum::load(path); }),
             Catch::Matchers::Contains("extra.lua:1: roger.learned: takes 1 argument (the name of a skill), got 2"));
  std::ofstream(path) << "return { stages = {\n  roger.stage({ name = 'S' }, 2) } }\n";
  CHECK_THAT(error_of([&] { Curriculum::load(path); }),
             Catch::Matchers::Contains("extra.lua:2: roger.stage: takes 1 argument (a table of fields), got 2"));
}

// Found by a probe: a test task that cannot be placed passed roger check and failed every trial at
// its first checkpoint, after the training.
TEST_CASE("check builds every test task in its world seed and names one that cannot be placed", "[curriculum]") {
  test::TempDir dir("roger_test_set_check");
  const std::string file = (dir.path / "ts.lua").string();
  auto write = [&](const std::string& far) {
    std::ofstream(file) << "local p = require('lib.skills').primitives()\n"
                           "return { name = 'ts', stages = {\n"
                           "  roger.stage{ name = 'S', scenario = 'cluttered', time_limit = 4,\n"
                           "    absorbing = roger.converged(p.phi0), budget = { episodes = 20 },\n"
                           "    tasks = { robot_distance = roger.real(0.8, " << far << ") }, test = { tasks = 30 },\n"
                           "    contexts = { { name = 'Gaze', actions = { p.search, p.phi0 } } } } } }\n";
  };
  write("2.6");
  const auto problems = check_curriculum(file);
  REQUIRE(problems.size() == 1);
  // At the stage's `test` field (line 5), without the scenario's traceback (found by a probe).
  CHECK_THAT(problems[0], Catch::Matchers::StartsWith(file + ":5: stage 'S': test task 23 of 30 (robot_distance = 2.57") &&
                              Catch::Matchers::Contains("cannot be placed in world seed 1000022") &&
                              Catch::Matchers::Contains("no placement for 'circle'") &&
                              !Catch::Matchers::Contains("stack traceback"));
  write("2.0");
  CHECK(check_curriculum(file).empty());
}

// Found by a probe: a world its parameters cannot build (a noise level noise_scale carries past its
// range) was told without the line of the params table that asked for it.
TEST_CASE("a context's world its parameters cannot build is placed at its params line", "[curriculum]") {
  test::TempDir dir("roger_params_world");
  const std::string file = (dir.path / "nc.lua").string();
  std::ofstream(file) << "local p = require('lib.skills').primitives()\n"
                         "return { name = 'nc', stages = {\n"
                         "  roger.stage{ name = 'Look', scenario = 'cluttered', time_limit = 4,\n"
                         "    absorbing = roger.converged(p.phi0), budget = { episodes = 20 },\n"
                         "    params = { noise_joints_delay = 30 },\n"
                         "    contexts = { { name = 'Clean', actions = { p.search, p.phi0 } },\n"
                         "      { name = 'Double', actions = { p.search, p.phi0 },\n"
                         "        params = { noise_scale = 2 } } } } } }\n";
  const auto problems = check_curriculum(file);
  REQUIRE(problems.size() == 1);
  CHECK_THAT(problems[0], Catch::Matchers::StartsWith(file + ":8: stage 'Look', context 'Double': scenario 'cluttered': ") &&
                              Catch::Matchers::Contains("noise_joints_delay = 30 times noise_scale = 2"));
}

// Found by a probe: `roger check --set noise_scale=2` passed a stage over noise_joints_delay =
// roger.int(0, 30), whose training then failed at its first episode of delay 58; and a --set that
// fixes an axis left the check trying that axis's ends, which training never meets.
TEST_CASE("check builds the task space's ends and test tasks under the command's --set", "[curriculum]") {
  test::TempDir dir("roger_check_sets");
  const std::string file = (dir.path / "k5.lua").string();
  std::ofstream(file) << "local p = require('lib.skills').primitives()\n"
                         "return { name = 'k5', stages = {\n"
                         "  roger.stage{ name = 'S', scenario = 'cluttered', time_limit = 4,\n"
                         "    absorbing = roger.converged(p.phi0), budget = { episodes = 20 },\n"
                         "    tasks = { noise_joints_delay = roger.int(0, 30),\n"
                         "              robot_distance = roger.real(0.8, 2.6) },\n"
                         "    teacher = roger.teacher.random{},\n"
                         "    contexts = { { name = 'Gaze', actions = { p.search, p.phi0 } } } } } }\n";
  CHECK_FALSE(check_curriculum(file).empty());  // robot_distance 2.6 cannot be placed
  // Fixing the distance by --set removes its axis: what remains is buildable.
  CHECK(check_curriculum(file, {}, {{"robot_distance", "1.5"}}).empty());
  const auto problems = check_curriculum(file, {}, {{"robot_distance", "1.5"}, {"noise_scale", "2"}});
  REQUIRE(problems.size() == 1);
  CHECK_THAT(problems[0], Catch::Matchers::StartsWith(file + ":5: stage 'S': scenario 'cluttered' with "
                                                             "noise_joints_delay = 30 (an end of the stage's task space, "
                                                             "robot_distance = 1.5, noise_scale = 2 by --set): ") &&
                              Catch::Matchers::Contains("noise_joints_delay = 30 times noise_scale = 2"));
}

// Found by a probe: skills.transported(p.carry) (a primitive for the composite) failed at
// curricula/lib/skills.lua:87 ("controller 'phi1' has no field 'subordinate'"), skills.transport()
// at "attempt to index a nil value (local 'p')" in the library: the newcomer's line came after.
TEST_CASE("lib.skills' builders refuse what they do not take at the caller's line", "[curriculum]") {
  test::TempDir dir("roger_skills_args");
  const std::string file = (dir.path / "wrong.lua").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"skills.transported(p.carry)",
       "wrong.lua:3: skills.transported takes the transport composite (skills.transport(p)), got controller 'phi1'"},
      {"skills.transport()", "wrong.lua:3: skills.transport takes the controllers of skills.primitives() "
                             "(local p = skills.primitives()), got nil"},
      {"skills.Phi7({ phi1 = p.phi1 })",
       "wrong.lua:3: skills.Phi7 takes the controllers of skills.primitives(): its table has no 'phi2'"},
      {"skills.Phi_STG(skills.Phi6(p), p.phi4)",
       "wrong.lua:3: skills.Phi_STG (its second argument) takes the controllers of skills.primitives() "
       "(local p = skills.primitives()), got controller 'phi4'"},
  };
  for (const auto& [call, says] : cases) {
    std::ofstream(file) << "local skills = require('lib.skills')\nlocal p = skills.primitives()\nlocal x = " << call
                        << "\nreturn { name = 'w', stages = {} }\n";
    INFO(call);
    CHECK_THAT(error_of([&] { Curriculum::load(file); }), Catch::Matchers::Contains(says));
  }
}

// Found by a probe: a learned skill listed twice in a context was told of "a controller the script
// defines", and p.phi1 beside p.carry (both named phi1) of no positions.
TEST_CASE("two actions of one name are said with their positions and why they clash", "[curriculum]") {
  const test::TempDir tmp("roger_two_names");
  using Catch::Matchers::Contains;
  const auto psi = [&](const std::string& actions) {
    const auto path = tmp.path / "psi.lua";
    std::ofstream(path) << "local p = require('lib.skills').primitives()\n"
                           "return { stages = {\n"
                           "  roger.stage{ name = 'A', time_limit = 4, absorbing = roger.converged(p.phi0),\n"
                           "    budget = { episodes = 3 }, skill = { name = 'Phi_A', context = 'C' },\n"
                           "    contexts = { { name = 'C', actions = { p.search, p.phi0 } } } },\n"
                           "  roger.stage{ name = 'B', time_limit = 4, absorbing = roger.converged(p.phi3), budget = { episodes = 3 },\n"
                           "    contexts = { { name = 'L', actions = { " << actions << " } } } } } }\n";
    return error_of([&] { Curriculum::load(path.string()); });
  };
  CHECK_THAT(psi("roger.learned('Phi_A'), roger.learned('Phi_A'), p.phi3"),
             Contains("two actions are named 'Phi_A' (actions 1 and 2 are the same action: list it once)"));
  CHECK_THAT(psi("p.phi1, p.phi3, p.carry"),
             Contains("two actions are named 'phi1' (actions 1 and 3: a controller is named by its kind unless it is "
                      "given name = \"...\""));
  CHECK_THAT(psi("p.phi3, p.phi3"), Contains("(actions 1 and 2 are the same action: list it once)"));
  CHECK(psi("roger.learned('Phi_A'), p.phi3").empty());
}

// Found by a probe: an init naming a context written later, a later stage's, or a misspelt stage
// was each "names no context written before this one; those are: none".
TEST_CASE("an init that names no earlier context says what it names instead", "[curriculum]") {
  const test::TempDir tmp("roger_init_target");
  using Catch::Matchers::Contains;
  const auto with_init = [&](const std::string& init) {
    const auto path = tmp.path / "init.lua";
    std::ofstream(path) << "local p = require('lib.skills').primitives()\n"
                           "return { stages = {\n"
                           "  roger.stage{ name = 'Look', time_limit = 4, absorbing = roger.converged(p.phi0), budget = { episodes = 3 },\n"
                           "    contexts = { { name = 'Gaze', actions = { p.search, p.phi0 }, init = " << init << " },\n"
                           "                 { name = 'Gaze2', actions = { p.search, p.phi0 } } } },\n"
                           "  roger.stage{ name = 'Grab', time_limit = 4, absorbing = roger.converged(p.phi3), budget = { episodes = 3 },\n"
                           "    contexts = { { name = 'L', actions = { p.search, p.phi3 } } } } } }\n";
    return error_of([&] { Curriculum::load(path.string()); });
  };
  CHECK_THAT(with_init("{ context = 'Gaze2' }"),
             Contains("names a context written after this one: move stage 'Look', context 'Gaze2' before it, or name "
                      "one written before; the contexts written before this one: none"));
  CHECK_THAT(with_init("{ stage = 'Grab', context = 'L' }"), Contains("names a context written after this one"));
  CHECK_THAT(with_init("{ stage = 'Lok', context = 'Gaze2' }"),
             Contains("names no context: there is no stage 'Lok' (did you mean 'Look'?)"));
  CHECK_THAT(with_init("{ stage = 'Grab', context = 'X' }"), Contains("names no context: stage 'Grab' has no context 'X'"));
}

// Found by a probe: stages written as a map, as contexts may be, were "empty (or not a list)".
TEST_CASE("stages written as a map are said to be one", "[curriculum]") {
  const test::TempDir tmp("roger_stages_map");
  const auto path = tmp.path / "map.lua";
  std::ofstream(path) << "local p = require('lib.skills').primitives()\n"
                         "return { name = 'm', stages = {\n"
                         "  Look = roger.stage{ name = 'Look', time_limit = 4, absorbing = roger.converged(p.phi0),\n"
                         "    budget = { episodes = 3 }, contexts = { { name = 'C', actions = { p.search, p.phi0 } } } } } }\n";
  CHECK_THAT(error_of([&] { Curriculum::load(path.string()); }),
             Catch::Matchers::Contains("map.lua:2: the curriculum: 'stages' is a map (it has the entry 'Look'), and "
                                       "stages are a list in the curriculum's order"));
  std::ofstream(path) << "return { name = 'm', stages = {} }\n";
  CHECK_THAT(error_of([&] { Curriculum::load(path.string()); }),
             Catch::Matchers::Contains("'stages' is empty: define at least one stage"));
}
