// Tests of engine/batch_script: the shipped batch scripts load with the paper's protocol, and bad
// batch scripts are clear errors naming file:line and what exists.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "script/batch/batch_script.h"
#include "core/error.h"
#include "test_files.h"
#include "temp_dir.h"

using namespace roger;
namespace fs = std::filesystem;

namespace {

// The message of the error loading a script raises ("" when it loads).
std::string load_error(const std::string& path) {
  try {
    load_batch_script(path);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

std::string load_error_with(const std::string& path, const BatchOverrides& overrides) {
  try {
    load_batch_script(path, overrides);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// As a stage's: an evaluation's scenario path is found beside the batch script that names it
// (before, from the current folder only), and a missing one says where it was looked for.
TEST_CASE("an evaluation's scenario path is found beside the batch script", "[batch_script]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_batch_near_" + std::to_string(::getpid()));
  fs::create_directories(dir / "worlds");
  std::ofstream(dir / "worlds" / "mine.lua") << "return { generate = function(world, rng, p) world:robot{ x = 0, y = 0 } end }\n";
  auto script = [&](const std::string& scenario) {
    const fs::path path = dir / "batch.lua";
    std::ofstream(path) << "return {\n  name = 'near', curriculum = '" << fs::absolute("tests/scripts/kill_curriculum.lua").string()
                        << "', trials = 1,\n  runs = { { name = 'SG', stage = 'SG', contexts = { 'DC2' } } },\n"
                           "  evaluations = { { name = 'e', run = 'SG', context = 'DC2',\n"
                           "    scenario = '" << scenario << "', episodes = 2 } },\n}\n";
    return path.string();
  };
  CHECK(load_batch_script(script("worlds/mine.lua")).evaluations.at(0).scenario == (dir / "worlds" / "mine.lua").string());
  CHECK(load_batch_script(script("cluttered")).evaluations.at(0).scenario == "cluttered");
  CHECK_THAT(load_error(script("worlds/theirs.lua")),
             Catch::Matchers::Contains("batch.lua:5: evaluation 'e': no scenario 'worlds/theirs.lua' (named in ") &&
                 Catch::Matchers::Contains("): looked at " + (dir / "worlds" / "theirs.lua").string() + ", then"));
  fs::remove_all(dir);
}

// Found by a probe: the default figures of runs SG and SG_M (the same stage, noise-free and
// noisy) had the same title.
TEST_CASE("a run's default figures are named by its stage, and by the run when it is named otherwise",
          "[batch_script]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_batch_titles_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path path = dir / "batch.lua";
  std::ofstream(path) << "return {\n  name = 'titles', curriculum = '"
                      << fs::absolute("tests/scripts/kill_curriculum.lua").string()
                      << "', trials = 1,\n  runs = { { name = 'SG', stage = 'SG', contexts = { 'DC2' } },\n"
                         "    { name = 'SG_M', stage = 'SG', contexts = { 'DC2' }, params = { noise_image = 10 } },\n"
                         "    { name = 'T_M', stage = 'T', contexts = { 'DC6' },\n"
                         "      skills = { Phi_SG = { run = 'SG_M', context = 'DC2' } } } },\n}\n";
  const BatchScript b = load_batch_script(path.string());
  std::vector<std::string> titles;
  for (const auto& f : b.figures) titles.push_back(f.file + ": " + f.title);
  CHECK(titles == std::vector<std::string>{"curves_SG: Learning curves: stage SG",
                                           "curves_SG_M: Learning curves: stage SG (run SG_M)",
                                           "curves_T_M: Learning curves: stage T (run T_M)",
                                           "cumulative_T_M: Cumulative training time: stage T (run T_M)"});
  fs::remove_all(dir);
}

// Found by a probe: a list parameter's values written as a list ({"left_eye", "right_eye"}) were
// "must be a number, string or boolean", where a stage's params and Python's make() take them.
TEST_CASE("a run's list parameter may be written as a list", "[batch_script]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_batch_list_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path path = dir / "batch.lua";
  const auto write = [&](const std::string& locked) {
    std::ofstream(path) << "return {\n  name = 'listed', curriculum = '"
                        << fs::absolute("tests/scripts/kill_curriculum.lua").string()
                        << "', trials = 1,\n  runs = { { name = 'SG', stage = 'SG', contexts = { 'DC2' },\n"
                           "    params = { locked = " << locked << " } } },\n}\n";
  };
  write("{ 'left_eye', 'right_eye' }");
  const BatchScript b = load_batch_script(path.string());
  CHECK(b.runs.at(0).params == Params{{"locked", "left_eye,right_eye"}});
  write("{ 'left_eye,right_eye' }");
  CHECK_THROWS_WITH(load_batch_script(path.string()),
                    Catch::Matchers::Contains("batch.lua:4: run 'SG': parameter 'locked' as a list takes names or "
                                              "numbers without commas, got \"left_eye,right_eye\""));
  write("{ x = 1 }");
  CHECK_THROWS_WITH(load_batch_script(path.string()),
                    Catch::Matchers::Contains("parameter 'locked' must be a number, string or boolean, or a list of "
                                              "names {\"a\", \"b\"} (a list parameter's values)"));
  fs::remove_all(dir);
}

TEST_CASE("an evaluation may take a learned skill from another run", "[batch_script]") {
  const BatchScript b = load_batch_script("tests/scripts/batch_eval_skill.lua");
  REQUIRE(b.evaluations.size() == 2);
  CHECK(b.evaluations[0].skills.empty());
  REQUIRE(b.evaluations[1].skills.size() == 1);
  CHECK(b.evaluations[1].skills[0].skill == "Phi_SG");
  CHECK(b.evaluations[1].skills[0].run == "SG_wide");
  CHECK(b.evaluations[1].skills[0].context == "DC2");
  // The manifest keeps them, and an evaluation without them writes what it wrote before.
  const nlohmann::json config = batch_config_json(b);
  CHECK(batch_config_json(batch_config_from_json(config)) == config);
  CHECK_FALSE(config["evaluations"][0].contains("skills"));
  CHECK(config["evaluations"][1]["skills"][0]["run"] == "SG_wide");
}

TEST_CASE("scripts/paper.lua describes the paper's protocol", "[batch_script]") {
  const BatchScript b = load_batch_script("scripts/paper.lua");
  CHECK(b.name == "paper");
  REQUIRE(b.runs.size() == 2);
  CHECK(b.runs[0].contexts == std::vector<std::string>{"B1", "DC1", "DC2"});
  CHECK(b.runs[1].contexts == std::vector<std::string>{"B2", "DC3", "DC4", "DC5", "DC6"});
  CHECK(b.runs[0].trials == 50);
  CHECK(b.runs[1].trials == 50);
  REQUIRE(b.runs[1].skills.size() == 1);
  CHECK(b.runs[1].skills[0].skill == "Phi_SG");
  CHECK(b.runs[1].skills[0].run == "SG");
  CHECK(b.runs[1].skills[0].context == "DC2");
  REQUIRE(b.evaluations.size() == 1);
  CHECK(b.evaluations[0].context == "DC6");
  CHECK(b.evaluations[0].shapes == std::vector<std::string>{"circle", "triangle", "pentagon", "spade"});
  CHECK(b.evaluations[0].episodes == 50);
  CHECK(!b.evaluations[0].shared_worlds);  // each policy its own worlds (docs/batch.md)
  CHECK(b.tables.size() == 3);
  CHECK(b.figures.size() == 3);
  // The configuration survives the manifest's JSON.
  CHECK(batch_config_json(batch_config_from_json(batch_config_json(b))) == batch_config_json(b));
  BatchScript shared = b;
  shared.evaluations[0].shared_worlds = true;
  CHECK(batch_config_from_json(batch_config_json(shared)).evaluations[0].shared_worlds);
  // A folder written before evaluations had worlds of their own: its policies shared them.
  nlohmann::json old = batch_config_json(b);
  old["evaluations"][0].erase("worlds");
  CHECK(batch_config_from_json(old).evaluations[0].shared_worlds);
  // A run's final evaluations share the held-out seeds unless it asks for worlds of their own
  // (the sorting script's runs); the manifest keeps the choice.
  CHECK(!b.runs[0].own_final_worlds);
  BatchScript own = b;
  own.runs[1].own_final_worlds = true;
  CHECK(batch_config_json(own)["runs"][1]["final_worlds"] == "own");
  CHECK(!batch_config_json(b)["runs"][1].contains("final_worlds"));  // configurations without it read as before
  CHECK(batch_config_from_json(batch_config_json(own)).runs[1].own_final_worlds);
  // Overrides: trials and scenario parameters.
  BatchOverrides o;
  o.trials = 3;
  o.sets = {{"mass", "0.7"}};
  const BatchScript q = load_batch_script("paper", o);
  CHECK(q.runs[1].trials == 3);
  CHECK(q.evaluations[0].trials == 3);
  CHECK(q.runs[0].params == Params{{"mass", "0.7"}});
  CHECK(load_batch_script("scripts/quick.lua").trials == 2);
  // Found by a probe: an evaluation's own trials were checked against its run's count after --trials
  // replaced it: `--trials 1` refused trials = 3 ("must be between 1 and 1"), blaming the script.
  const test::TempDir dir("roger_trials_override");
  const fs::path file = dir.path / "three.lua";
  std::ofstream(file) << "return { name = 'three', curriculum = 'paper', trials = 2,\n"
                         "  runs = { { name = 'SG', stage = 'SG', contexts = { 'DC2' }, trials = 3 } },\n"
                         "  evaluations = { { name = 'e', run = 'SG', episodes = 2, trials = 3 } } }\n";
  BatchOverrides one;
  one.trials = 1;
  const BatchScript smoke = load_batch_script(file.string(), one);
  CHECK(smoke.runs[0].trials == 1);
  CHECK(smoke.evaluations[0].trials == 1);
  BatchOverrides five;
  five.trials = 5;
  CHECK(load_batch_script(file.string(), five).evaluations[0].trials == 5);
  CHECK(load_batch_script(file.string()).evaluations[0].trials == 3);
}

// Found by a probe: a script returning another it requires was read by its own text alone, so
// roger check took this one for a scenario ("unknown field 'trials'"), and roger run on a
// curriculum failed inside its first roger.primitive ("attempt to index a nil value").
// Found by a probe: these passed roger check and roger run's start, and failed every trial they
// reached, after the training (an evaluation) or at once (a run), tying the folder to them.
TEST_CASE("scenario parameters and shapes are tried on their scenario when the script loads", "[batch_script]") {
  BatchOverrides sets;
  sets.sets = {{"foo", "1"}};
  try {
    load_batch_script("tests/scripts/kill_batch.lua", sets);
    FAIL("a --set of no parameter was taken");
  } catch (const ScriptError& e) {
    FAIL("a --set of no parameter was blamed on the script's line: " << e.what());
  } catch (const Error& e) {  // the command line's mistake, said as such
    CHECK_THAT(e.what(), Catch::StartsWith("--set foo=1: run 'SG': scenario 'unobstructed'") &&
                             Catch::Contains("has no parameter 'foo'") &&
                             Catch::Contains("a --set goes to every run of the script, whatever --only selects; to "
                                             "set it on some runs only, give it in their `params`"));
  }
  sets.sets = {{"obstacles", "99"}};  // cluttered's, not the training world's
  CHECK_THAT(load_error_with("tests/scripts/kill_batch.lua", sets), Catch::Contains("has no parameter 'obstacles'"));
  const std::string m = load_error("tests/scripts/bad_batch_eval_shape.lua");
  CHECK_THAT(m, Catch::Contains("bad_batch_eval_shape.lua:7:") && Catch::Contains("evaluation 'gen'") &&
                    Catch::Contains("'hexagon'"));
}

// Found by a probe: a run's noise level that its noise_scale carries past the channel's range was
// refused at the curriculum library's stage line (curricula/lib/paper_stages.lua), not the run's.
TEST_CASE("a run's parameters that go out of range only together are refused at the run's line", "[batch_script]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_run_params_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "batch.lua") << "return { name = 'scaled', curriculum = 'paper', trials = 1,\n"
                                      "  runs = { { name = 'SG', stage = 'SG', contexts = { 'DC2' },\n"
                                      "             params = { noise_joints_delay = 30, noise_scale = 2 } } } }\n";
  CHECK_THAT(load_error((dir / "batch.lua").string()),
             Catch::StartsWith((dir / "batch.lua").string() + ":2: run 'SG': ") &&
                 Catch::Contains("field 'delay' must be within [0, 50] ticks, got 60 (the scenario parameters "
                                 "noise_joints_delay = 30 times noise_scale = 2: lower either)"));
  fs::remove_all(dir);
}

// Found by a probe: a batch's `capsule = 0` for a boolean parameter was taken as false, where Lua
// reads 0 as true; a --set capsule=0 on the command line is taken.
TEST_CASE("a boolean parameter in a batch script takes true or false, a --set also 0 or 1", "[batch_script]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_batch_boolean_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "corridor.lua") << test::slurp("docs/examples/corridor.lua");
  std::ofstream(dir / "cur.lua") << "local p = require('lib.skills').primitives()\n"
                                    "return { stages = { roger.stage{ name = 'S', scenario = 'corridor.lua', time_limit = 4,\n"
                                    "  absorbing = roger.converged(p.phi0), budget = { episodes = 1 },\n"
                                    "  contexts = { { name = 'A', actions = { p.phi0 } } } } } }\n";
  auto with = [&](const std::string& value) {
    std::ofstream(dir / "batch.lua") << "return { name = 'b', curriculum = 'cur.lua', trials = 1,\n"
                                        "  runs = { { name = 'S', stage = 'S', contexts = { 'A' },\n"
                                        "             params = { capsule = " << value << " } } } }\n";
    return load_error((dir / "batch.lua").string());
  };
  CHECK_THAT(with("0"), Catch::StartsWith((dir / "batch.lua").string() + ":2: run 'S': ") &&
                            Catch::Contains("parameter 'capsule' of scenario 'corridor' is a boolean: write capsule = "
                                            "true or capsule = false, got '0'"));
  CHECK(with("false").empty());
  std::ofstream(dir / "batch.lua") << "return { name = 'b', curriculum = 'cur.lua', trials = 1,\n"
                                      "  runs = { { name = 'S', stage = 'S', contexts = { 'A' } } } }\n";
  BatchOverrides sets;
  sets.sets = {{"capsule", "0"}};
  CHECK(load_error_with((dir / "batch.lua").string(), sets).empty());
  fs::remove_all(dir);
}

// Found by a probe: a batch's params (obstacles = 0) and a run's (eye_pixels = 64) replaced the
// own params of context Coarse (eye_pixels = 32, obstacles = 2) without a word, so it trained
// exactly as context Full. Each overridden one is a note at the line of the params that win (the
// run's line for a --set), as roger train marks a --set's; a run that gives the context's own
// values back, and a context without params, have none.
TEST_CASE("a context's own params that a batch's params override are noted where those are written", "[batch_script]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_batch_ctx_params_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "cur.lua") << "local p = require('lib.skills').primitives()\n"
                                    "return { stages = { roger.stage{ name = 'S', scenario = 'cluttered', time_limit = 4,\n"
                                    "  params = { obstacles = 1 }, absorbing = roger.converged(p.phi0), budget = { episodes = 20 },\n"
                                    "  contexts = { { name = 'Coarse', actions = { p.search, p.phi0 }, "
                                    "params = { eye_pixels = 32, obstacles = 2 } },\n"
                                    "               { name = 'Full', actions = { p.search, p.phi0 } } } } } }\n";
  const std::string path = (dir / "b.lua").string();
  std::ofstream(path) << "return {\n  curriculum = 'cur.lua',\n  params = { obstacles = 0 },\n  runs = {\n"
                         "    { name = 'S', stage = 'S',\n      params = { eye_pixels = 64 } },\n"
                         "    { name = 'Back', stage = 'S', contexts = { 'Coarse' },\n"
                         "      params = { eye_pixels = 32, obstacles = 2 } },\n  },\n}\n";
  const std::string why = " (a batch's params and --set win over a context's own, as --set does in roger train)";
  CHECK(load_batch_script(path).notes ==
        std::vector<std::string>{
            path + ":6: run 'S': context 'Coarse' of stage 'S' sets eye_pixels = 32, overridden by the run's params "
                   "eye_pixels = 64" + why,
            path + ":3: run 'S': context 'Coarse' of stage 'S' sets obstacles = 2, overridden by the batch script's "
                   "params obstacles = 0" + why});
  BatchOverrides sets;
  sets.sets = {{"eye_pixels", "128"}};
  const std::vector<std::string> notes = load_batch_script(path, sets).notes;
  REQUIRE(notes.size() == 3);
  CHECK(notes[0] == path + ":5: run 'S': context 'Coarse' of stage 'S' sets eye_pixels = 32, overridden by --set "
                           "eye_pixels=128" + why);
  CHECK(notes[2] == path + ":7: run 'Back': context 'Coarse' of stage 'S' sets eye_pixels = 32, overridden by --set "
                           "eye_pixels=128" + why);
  fs::remove_all(dir);
}

// Found by a probe: an evaluation's params were compared with nothing: a context's eye_pixels = 32
// overridden by them, or left at another scenario's default 128, without a word.
TEST_CASE("a context's own params an evaluation does not run with are noted", "[batch_script]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_batch_eval_params_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "cur.lua") << "local p = require('lib.skills').primitives()\n"
                                    "return { stages = { roger.stage{ name = 'S', scenario = 'cluttered', time_limit = 4,\n"
                                    "  absorbing = roger.converged(p.phi0), budget = { episodes = 1 },\n"
                                    "  contexts = { { name = 'Coarse', actions = { p.phi0 }, params = { eye_pixels = 32 } },\n"
                                    "               { name = 'Full', actions = { p.phi0 } } } } } }\n";
  const std::string path = (dir / "b.lua").string();
  std::ofstream(path) << "return { name = 'b', curriculum = 'cur.lua', trials = 1,\n"
                         "  runs = { { name = 'S', stage = 'S', contexts = { 'Coarse', 'Full' } } },\n"
                         "  evaluations = {\n"
                         "    { name = 'same', run = 'S', context = 'Coarse', params = { eye_pixels = 64 } },\n"
                         "    { name = 'kept', run = 'S', context = 'Coarse', params = { eye_pixels = 32 } },\n"
                         "    { name = 'other', run = 'S', context = 'Coarse', scenario = 'unobstructed' },\n"
                         "    { name = 'given', run = 'S', context = 'Coarse', scenario = 'unobstructed',\n"
                         "      params = { eye_pixels = 32 } },\n"
                         "    { name = 'full', run = 'S', context = 'Full', scenario = 'unobstructed' } } }\n";
  CHECK(load_batch_script(path).notes ==
        std::vector<std::string>{
            path + ":4: evaluation 'same': stage 'S', context 'Coarse' sets eye_pixels = 32, overridden by the "
                   "evaluation's params eye_pixels = 64 (an evaluation's params win over a context's own)",
            path + ":6: evaluation 'other': stage 'S', context 'Coarse' sets eye_pixels = 32, which this evaluation "
                   "leaves at scenario 'unobstructed''s default 128: in another scenario than its stage's an "
                   "evaluation runs with its own params only (give params = {eye_pixels = 32} to evaluate as trained)"});
  fs::remove_all(dir);
}

// Found by a probe: a run that trained with eye_pixels = 64 (its params) over a context's 32 was
// told "give params = {eye_pixels = 32} to evaluate as trained", and evaluated in the stage's own
// scenario at the context's 32, or a --set's value at the default, without a word.
TEST_CASE("the params a run trained with and an evaluation does not run with are noted", "[batch_script]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_batch_trained_params_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "cur.lua") << "local p = require('lib.skills').primitives()\n"
                                    "return { stages = { roger.stage{ name = 'S', scenario = 'cluttered', time_limit = 4,\n"
                                    "  absorbing = roger.converged(p.phi0), budget = { episodes = 1 },\n"
                                    "  contexts = { { name = 'Coarse', actions = { p.phi0 }, params = { eye_pixels = 32 } } } } } }\n";
  const std::string path = (dir / "b.lua").string();
  std::ofstream(path) << "return { name = 'b', curriculum = 'cur.lua', trials = 1,\n"
                         "  runs = { { name = 'S', stage = 'S', contexts = { 'Coarse' }, params = { eye_pixels = 64 } } },\n"
                         "  evaluations = {\n"
                         "    { name = 'same', run = 'S', context = 'Coarse' },\n"
                         "    { name = 'other', run = 'S', context = 'Coarse', scenario = 'unobstructed' },\n"
                         "    { name = 'given', run = 'S', context = 'Coarse', params = { eye_pixels = 64, mass = 0.7 } } } }\n";
  BatchOverrides sets;
  sets.sets = {{"mass", "0.6"}};
  std::vector<std::string> notes;
  for (const std::string& n : load_batch_script(path, sets).notes)
    if (n.find("evaluation '") != std::string::npos) notes.push_back(n);
  const std::string trained = "run 'S' trained stage 'S', context 'Coarse' with ";
  const std::string not_taken = ": an evaluation runs with the stage's and context's params and its own, not the "
                                "batch's or --set ";
  CHECK(notes == std::vector<std::string>{
      path + ":4: evaluation 'same': " + trained + "eye_pixels = 64 (the batch's params), which this evaluation leaves "
             "at the context's own 32" + not_taken + "(give params = {eye_pixels = 64} to evaluate as trained)",
      path + ":4: evaluation 'same': " + trained + "mass = 0.6 (--set), which this evaluation leaves at the scenario's "
             "default 0.5" + not_taken + "(give params = {mass = 0.6} to evaluate as trained)",
      path + ":5: evaluation 'other': " + trained + "eye_pixels = 64 (the batch's params), which this evaluation leaves "
             "at scenario 'unobstructed''s default 128: in another scenario than its stage's an evaluation runs with "
             "its own params only (give params = {eye_pixels = 64} to evaluate as trained)",
      path + ":5: evaluation 'other': " + trained + "mass = 0.6 (--set), which this evaluation leaves at scenario "
             "'unobstructed''s default 0.5: in another scenario than its stage's an evaluation runs with its own params "
             "only (give params = {mass = 0.6} to evaluate as trained)",
      path + ":6: evaluation 'given': " + trained + "mass = 0.6 (--set), overridden by the evaluation's params mass = "
             "0.7 (an evaluation's params win over a context's own)"});
  fs::remove_all(dir);
}

TEST_CASE("a script is of the kind of the module it returns", "[batch_script]") {
  CHECK(is_batch_script("tests/scripts/wrapped_batch.lua"));
  const BatchScript b = load_batch_script("tests/scripts/wrapped_batch.lua");
  CHECK(b.name == "kill");
  for (const auto& r : b.runs) CHECK(r.trials == 1);
  CHECK_FALSE(is_batch_script("tests/scripts/kill_curriculum.lua"));
  // Found by a probe: a scenario named as the curriculum failed inside it, in a traceback.
  const fs::path dir = fs::temp_directory_path() / ("roger_kind_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "b.lua") << "return { name = 'b',\n  curriculum = 'scenarios/cluttered.lua',\n"
                                  "  runs = { { name = 'SG', stage = 'SG' } } }\n";
  CHECK_THAT(load_error((dir / "b.lua").string()),
             Catch::Contains("b.lua:2: the curriculum scenarios/cluttered.lua is a scenario, not a curriculum: a "
                             "curriculum's stages name it as their scenario"));
  fs::remove_all(dir);
  CHECK(load_error("curricula/paper.lua") ==
        "curricula/paper.lua is a curriculum, not a batch script: train one of its stages with roger train "
        "curricula/paper.lua --stage S --context C --out DIR, or name it as the curriculum of a batch script "
        "(docs/batch.md)");
}

TEST_CASE("bad batch scripts are clear errors at file:line", "[batch_script]") {
  std::string m = load_error("tests/scripts/bad_batch_unknown_curriculum.lua");
  INFO(m);
  CHECK(m.find("bad_batch_unknown_curriculum.lua:4:") != std::string::npos);
  CHECK(m.find("no_such_curriculum") != std::string::npos);
  // Found by a probe: "no such file here or in the project" named none of the places looked at.
  const std::string cwd = fs::current_path().string();
  CHECK_THAT(m, Catch::Contains("no curriculum 'curricula/no_such_curriculum.lua': looked at " + cwd +
                                "/curricula/no_such_curriculum.lua (from the current folder), then " + cwd +
                                "/tests/scripts/curricula/no_such_curriculum.lua (beside the batch script)"));
  // Run from the project, the project's path is the current folder's: named once (found by a newcomer).
  CHECK(m.find("(in the project)") == std::string::npos);

  m = load_error("tests/scripts/bad_batch_unknown_context.lua");
  INFO(m);
  CHECK(m.find("bad_batch_unknown_context.lua:7:") != std::string::npos);
  CHECK(m.find("no context 'DC9'") != std::string::npos);
  CHECK(m.find("'B1', 'DC1', 'DC2'") != std::string::npos);

  m = load_error("tests/scripts/bad_batch_unknown_field.lua");
  INFO(m);
  CHECK(m.find("bad_batch_unknown_field.lua:7:") != std::string::npos);
  CHECK(m.find("unknown field 'contxts'") != std::string::npos);
  CHECK(m.find("contexts") != std::string::npos);

  m = load_error("tests/scripts/bad_batch_unknown_run.lua");
  INFO(m);
  CHECK(m.find("bad_batch_unknown_run.lua:8:") != std::string::npos);
  CHECK(m.find("no earlier run 'SGX'") != std::string::npos);
  CHECK(m.find("'SG'") != std::string::npos);

  m = load_error("tests/scripts/bad_batch_missing_skill.lua");
  INFO(m);
  CHECK(m.find("bad_batch_missing_skill.lua:7:") != std::string::npos);
  CHECK(m.find("Phi_SG") != std::string::npos);

  m = load_error("tests/scripts/bad_batch_unknown_stage.lua");
  INFO(m);
  CHECK(m.find("bad_batch_unknown_stage.lua:5:") != std::string::npos);
  CHECK(m.find("no stage 'Transport'") != std::string::npos);
  CHECK(m.find("'SG', 'T'") != std::string::npos);

  m = load_error("tests/scripts/bad_batch_worlds.lua");
  INFO(m);
  CHECK(m.find("bad_batch_worlds.lua:8:") != std::string::npos);
  CHECK(m.find("'own'") != std::string::npos);
  CHECK(m.find("not 'same'") != std::string::npos);

  m = load_error("tests/scripts/bad_batch_final_worlds.lua");
  INFO(m);
  CHECK(m.find("bad_batch_final_worlds.lua:7:") != std::string::npos);
  CHECK(m.find("run 'SG': final_worlds is 'own'") != std::string::npos);
  CHECK(m.find("not 'mine'") != std::string::npos);

  m = load_error("tests/scripts/bad_batch_runtime.lua");
  INFO(m);
  CHECK(m.find("bad_batch_runtime.lua:3:") != std::string::npos);

  m = load_error("tests/scripts/bad_batch_eval_skill.lua");
  INFO(m);
  CHECK(m.find("bad_batch_eval_skill.lua:9:") != std::string::npos);
  CHECK(m.find("evaluation 'e', skill 'Phi_SG': context 'B2' of run 'T' uses no learned skill 'Phi_SG'; it uses none") !=
        std::string::npos);

  m = load_error("tests/scripts/bad_batch_escape.lua");  // once a hang in Lua's matcher
  INFO(m);
  CHECK(m.find("bad_batch_escape.lua:3: string.gsub: instruction budget of 50000000 exceeded") != std::string::npos);

  m = load_error("tests/scripts/bad_batch_chain.lua");  // once minutes of C work within the instruction budget
  INFO(m);
  CHECK(m.find("bad_batch_chain.lua:4: processor time budget exceeded: ") != std::string::npos);

  m = load_error("tests/scripts/no_such_batch.lua");
  INFO(m);
  CHECK(m.find("no batch script") != std::string::npos);
}

TEST_CASE("a damaged manifest configuration is a roger::Error, never undefined behaviour or a crash",
          "[batch_script]") {
  // Found by tests/fuzz/fuzz_manifest: the report follows the configuration's references without
  // looking (a table naming a missing run was a null dereference), and a count of 1e300 was
  // converted to int (undefined behaviour).
  const nlohmann::json good = batch_config_json(load_batch_script("scripts/quick.lua"));
  CHECK_NOTHROW(batch_config_from_json(good));
  const std::vector<std::pair<std::string, std::function<void(nlohmann::json&)>>> cases = {
      {"\"trials\"", [](nlohmann::json& j) { j["trials"] = 1e300; }},
      {"\"trials\"", [](nlohmann::json& j) { j["runs"][0]["trials"] = -2; }},
      {"\"episodes\"", [](nlohmann::json& j) { j["evaluations"][0]["episodes"] = 0; }},
      {"\"seed\"", [](nlohmann::json& j) { j["seed"] = 18446744073709551615u; }},
      {"run 'nope'", [](nlohmann::json& j) { j["tables"][0]["run"] = "nope"; }},
      {"evaluation 'nope'", [](nlohmann::json& j) { j["tables"][2]["evaluation"] = "nope"; }},
      {"run 'nope'", [](nlohmann::json& j) { j["figures"][1]["run"] = "nope"; }},
      {"kind 'pie'", [](nlohmann::json& j) { j["figures"][0]["kind"] = "pie"; }},
      {"run 'nope'", [](nlohmann::json& j) { j["evaluations"][0]["run"] = "nope"; }},
      {"run 'nope'", [](nlohmann::json& j) { j["runs"][1]["skills"][0]["run"] = "nope"; }},
      {"incomplete", [](nlohmann::json& j) { j.erase("runs"); }},
      // Found by a probe: a figure's file "../../pwn" made the report write outside the folder.
      {"figure file '../../pwn' is not a name", [](nlohmann::json& j) { j["figures"][0]["file"] = "../../pwn"; }},
      {"run '../../zz' is not a name", [](nlohmann::json& j) { j["runs"][0]["name"] = "../../zz"; }},
      {"context '..' is not a name", [](nlohmann::json& j) { j["runs"][0]["contexts"][0] = ".."; }},
      {"evaluation 'a/b' is not a name", [](nlohmann::json& j) { j["evaluations"][0]["name"] = "a/b"; }},
      {"shape '/etc' is not a name", [](nlohmann::json& j) { j["evaluations"][0]["shapes"][0] = "/etc"; }},
  };
  for (const auto& [what, spoil] : cases) {
    nlohmann::json j = good;
    spoil(j);
    INFO(j.dump());
    try {
      batch_config_from_json(j);
      FAIL("accepted a configuration with " << what);
    } catch (const Error& e) {
      CHECK_THAT(e.what(), Catch::Contains(what));
    }
  }
}

TEST_CASE("a batch script's limits set the sandbox's budgets; the command line's override them", "[batch_script]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_limits_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  auto script = [&](const std::string& limits) {
    const fs::path file = dir / "limits.lua";
    std::ofstream(file) << "return { name = 'limits', curriculum = 'curricula/paper.lua',\n"
                        << "  limits = " << limits << ",\n"
                        << "  runs = { { name = 'SG', stage = 'SG', contexts = { 'DC2' } } } }\n";
    return file.string();
  };
  const BatchScript b = load_batch_script(script("{ instructions = 200000000, memory = 1024 }"));
  CHECK(b.limits.instructions == 200'000'000);
  CHECK(b.limits.memory_bytes == size_t(1024) << 20);
  // The manifest's configuration records them (a folder made under other limits is not resumed).
  const nlohmann::json config = batch_config_json(b);
  CHECK(config["limits"] == nlohmann::json({{"instructions", 200'000'000}, {"memory_mib", 1024}}));
  CHECK(batch_config_json(batch_config_from_json(config)) == config);
  // A script without them has the defaults, recorded too.
  const BatchScript plain = load_batch_script("paper");
  CHECK(plain.limits.instructions == SandboxLimits().instructions);
  CHECK(batch_config_json(plain)["limits"]["memory_mib"] == 256);
  // --lua-instructions and --lua-memory over the script's.
  BatchOverrides o;
  o.instructions = 70'000'000;
  o.memory_mib = 64;
  const BatchScript over = load_batch_script(script("{ instructions = 200000000 }"), o);
  CHECK(over.limits.instructions == 70'000'000);
  CHECK(over.limits.memory_bytes == size_t(64) << 20);
  // Mistakes name the line and the field.
  CHECK_THAT(load_error(script("{ instructions = 1e8, memry = 5 }")),
             Catch::Matchers::Contains("limits.lua:2: the batch script's limits: unknown field 'memry'"));
  CHECK_THAT(load_error(script("{ memory = 4 }")),
             Catch::Matchers::Contains("field 'memory' must be between 16 and 1048576, got 4"));
  CHECK_THAT(load_error(script("{ instructions = 'many' }")), Catch::Matchers::Contains("field 'instructions' must be an integer"));
  // Found by a probe: 2^53, the documented largest budget written as Lua writes it, was refused as
  // "must be an integer"; a whole float is the integer it holds, and the range says what is too big.
  CHECK(load_batch_script(script("{ instructions = 2^53 }")).limits.instructions == uint64_t(1) << 53);
  CHECK_THAT(load_error(script("{ instructions = 2^60 }")),
             Catch::Matchers::Contains("field 'instructions' must be between 1000 and 9007199254740992, got "
                                       "1152921504606846976"));
  // And 0/0 said "the batch script.limits.instructions must be a finite number".
  CHECK_THAT(load_error(script("{ instructions = 0/0 }")),
             Catch::Matchers::Contains("field 'limits.instructions' must be a finite number, got nan"));
  fs::remove_all(dir);
}

TEST_CASE("every seed a batch derives lies within 2^53, and a whole number past int64 is out of range",
          "[batch_script]") {
  // Found by a probe: seed = 2^53 with 3 trials passed (its trials' seeds past the bound results keep
  // exact), and seed = 2^63 was refused as "must be an integer".
  const fs::path dir = fs::temp_directory_path() / ("roger_seeds_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  auto script = [&](const std::string& seed, const std::string& first_seed) {
    const fs::path file = dir / "seeds.lua";
    std::ofstream(file) << "return { name = 'seeds', curriculum = 'curricula/paper.lua', trials = 3, seed = " << seed
                        << ",\n  runs = { { name = 'SG', stage = 'SG', contexts = { 'DC2' } } },\n"
                        << "  evaluations = { { name = 'g', run = 'SG', context = 'DC2', shapes = { 'circle', "
                        << "'spade' },\n    episodes = 10, first_seed = " << first_seed << " } } }\n";
    return file.string();
  };
  // The last trial's seed and the last world's seed may be 2^53 itself.
  const BatchScript b = load_batch_script(script("2^53 - 2", "2^53 - 59"));
  CHECK(b.seed == (uint64_t(1) << 53) - 2);
  CHECK(b.evaluations.at(0).first_seed == (int64_t(1) << 53) - 59);
  CHECK_THAT(load_error(script("2^53 - 1", "0")),
             Catch::Matchers::Contains("seeds.lua:1: run 'SG': trial i trains with seed 'seed' + i, so the last seed, "
                                       "seed + trials - 1 = 9007199254740993, is past 2^53 (9007199254740992), the "
                                       "largest seed a batch takes: give 'seed' at most 9007199254740990"));
  BatchOverrides more;
  more.trials = 5;
  CHECK_THAT(load_error_with(script("2^53 - 2", "0"), more),
             Catch::Matchers::Contains("give 'seed' at most 9007199254740988, or fewer --trials"));
  // Two shapes of 3 trials' 10 episodes each, in worlds of their own: 60 seeds.
  CHECK_THAT(load_error(script("1", "2^53 - 58")),
             Catch::Matchers::Contains("seeds.lua:4: evaluation 'g': its 60 worlds take seeds from 'first_seed' on, "
                                       "so the last seed, first_seed + 59 = 9007199254740993, is past 2^53"));
  CHECK_THAT(load_error(script("2^63", "0")),
             Catch::Matchers::Contains("seeds.lua:1: the batch script: field 'seed' must be between 0 and "
                                       "9007199254740992, got number 9.223372036854776e+18"));
  CHECK_THAT(load_error(script("1.5", "0")),
             Catch::Matchers::Contains("field 'seed' must be an integer, got number 1.5"));
  fs::remove_all(dir);
}

TEST_CASE("names that would clash or climb out and a skill from another context are refused at load",
          "[batch_script]") {
  // Each once passed the load and failed after the training (a figure over the report's own
  // iqm_<run>, a skill policy of the wrong context) or wrote outside results/ (a name '../..').
  const fs::path dir = fs::temp_directory_path() / ("roger_clash_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  auto script = [&](const std::string& name, const std::string& skill_context, const std::string& figure) {
    const fs::path file = dir / "clash.lua";
    std::ofstream(file) << "return { name = '" << name << "', curriculum = 'curricula/paper.lua',\n"
                        << "  runs = { { name = 'SG', stage = 'SG', contexts = { 'B1', 'DC2' } },\n"
                        << "    { name = 'T', stage = 'T', contexts = { 'DC6' },\n"
                        << "      skills = { Phi_SG = { run = 'SG'" << skill_context << " } } } },\n"
                        << "  figures = { { file = '" << figure << "', run = 'SG' } } }\n";
    return file.string();
  };
  CHECK_NOTHROW(load_batch_script(script("clash", ", context = 'DC2'", "curves")));
  CHECK_THAT(load_error(script("clash", ", context = 'B1'", "curves")),
             Catch::Matchers::Contains("clash.lua:4: run 'T', skill 'Phi_SG': 'Phi_SG' is the policy stage 'SG' learns "
                                       "in context 'DC2' (its field skill, curricula/lib/paper_stages.lua:") &&
                 Catch::Matchers::Contains("not one of context 'B1': give context = \"DC2\" or leave it out"));
  CHECK_THAT(load_error(script("clash", "", "iqm_SG")),
             Catch::Matchers::Contains("clash.lua:5: figure 'iqm_SG': the report draws the IQM learning curves of "
                                       "run 'SG' into iqm_SG.png and .svg itself"));
  CHECK_NOTHROW(load_batch_script(script("clash", "", "iqm_X")));
  for (const char* name : {"../../escaped", "", "..", "a/b"})
    CHECK_THAT(load_error(script(name, "", "curves")),
               Catch::Matchers::Contains("clash.lua:1: the batch script: 'name' names the results folder"));
  CHECK_THAT(load_error(script("clash", "", "..")), Catch::Matchers::Contains("'file' is a plain name"));
  // Found by a probe: a figure named with 300 letters passed roger check, and the run stopped at its
  // report, "File name too long" (a file system's name takes 255 bytes).
  CHECK_THAT(load_error(script("clash", "", std::string(201, 'f'))),
             Catch::Matchers::Contains("'file' is a plain name (letters, digits, '.', '_' and '-', at most 200 of them"));
  CHECK_NOTHROW(load_batch_script(script("clash", "", std::string(200, 'f'))));
  // Found by a probe: "curves.png" was taken, and the report wrote curves.png.png.
  CHECK_THAT(load_error(script("clash", "", "curves.png")),
             Catch::Matchers::Contains("clash.lua:5: figure 'curves.png': 'file' is named without its extension: "
                                       "'curves' (the report writes curves.png and curves.svg)"));
  CHECK_THAT(load_error(script("clash", "", "curves.svg")), Catch::Matchers::Contains("'curves' (the report writes"));
  CHECK_NOTHROW(load_batch_script(script("clash", "", "curves.v2")));
  // contexts = {} is a list that came out empty, not "every context".
  const fs::path empty = dir / "empty.lua";
  std::ofstream(empty) << "return { name = 'e', curriculum = 'curricula/paper.lua',\n"
                       << "  runs = { { name = 'SG', stage = 'SG',\n    contexts = {} } } }\n";
  CHECK_THAT(load_error(empty.string()),
             Catch::Matchers::Contains("empty.lua:3: run 'SG': 'contexts' is empty: name some of the contexts of "
                                       "stage 'SG' ('B1', 'DC1', 'DC2'), or leave the field out"));
  // So is shapes = {} (found by a probe: one group 'all' without a word).
  std::ofstream(empty) << "return { name = 'e', curriculum = 'curricula/paper.lua',\n"
                       << "  runs = { { name = 'SG', stage = 'SG' } },\n"
                       << "  evaluations = { { name = 'g', run = 'SG', context = 'DC2',\n    shapes = {} } } }\n";
  CHECK_THAT(load_error(empty.string()),
             Catch::Matchers::Contains("empty.lua:4: evaluation 'g': 'shapes' is empty: name the shapes to evaluate one "
                                       "group each, or leave the field out"));
  fs::remove_all(dir);
}

// Found by a probe: a context named "C<img ...>" or "Ünïcødé" passed roger check of the batch script,
// and roger run refused its trial ids after it had written the results folder (whose page then
// waited for a report that never came), cutting the character 'Ü' in half in its message.
TEST_CASE("a context a batch runs must be able to name its trials' folders", "[batch_script]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_context_names_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  for (const std::string& name : std::vector<std::string>{"C<img>", "\xc3\x9cni", "a b", "..", std::string(201, 'c'), "ok.name-1_2"}) {
    INFO(name);
    std::ofstream(dir / "cur.lua") << "local p = require('lib.skills').primitives()\n"
                                      "return { stages = { roger.stage{ name = 'S', scenario = 'unobstructed',\n"
                                      "  time_limit = 4, absorbing = roger.converged(p.phi0), budget = { episodes = 4 },\n"
                                      "  contexts = { { name = '" << name << "', actions = { p.search, p.phi0 } } } } } }\n";
    std::ofstream(dir / "batch.lua") << "return { name = 'names', curriculum = 'cur.lua', trials = 1,\n"
                                        "  runs = { { name = 'R', stage = 'S' } } }\n";
    const std::string m = load_error((dir / "batch.lua").string());
    if (name == "ok.name-1_2") {
      CHECK(m.empty());
      continue;
    }
    CHECK_THAT(m, Catch::Matchers::Contains("batch.lua:2: run 'R': the context '" + name + "' of stage 'S' cannot name "
                                            "its trials' folders (trials/R/<context>/000): a context a batch runs "
                                            "uses letters, digits, '.', '_' and '-', at most 200 of them"));
  }
  fs::remove_all(dir);
}

// Found by a probe: a description's line break let the rest of it open a Markdown heading of
// tables.md ("# injected heading"); a description or a title is one line of the report.
TEST_CASE("a batch script's description and titles are one line each", "[batch_script]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_one_line_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const auto script = [&](const std::string& description, const std::string& title) {
    std::ofstream(dir / "lines.lua") << "return { name = 'lines', curriculum = 'curricula/paper.lua',\n"
                                        "  description = " << description << ",\n"
                                        "  runs = { { name = 'SG', stage = 'SG', contexts = { 'B1' } } },\n"
                                        "  tables = { { title = " << title << ", run = 'SG', baseline = 'B1' } } }\n";
    return load_error((dir / "lines.lua").string());
  };
  CHECK(script("'one line'", "'Table'").empty());
  CHECK_THAT(script("'one\\n# injected heading'", "'Table'"),
             Catch::Matchers::Contains("lines.lua:2: the batch script's 'description' is one line of the report, and "
                                       "has a line break: join its lines"));
  CHECK_THAT(script("'one'", "'Table\\nII'"), Catch::Matchers::Contains("'title' is one line of the report"));
  fs::remove_all(dir);
}

// Found by a probe: a misspelt 'by' of a table or 'param' of a figure of where a teacher sampled
// passed the load, and the report wrote an empty table, or no figure "for want of a finished
// trial", once the training was over.
TEST_CASE("a table's by and a tasks figure's param are checked against the runs' stages at load", "[batch_script]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_by_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  auto with_param = [&](const std::string& table, const std::string& run, const std::string& param) {
    const fs::path file = dir / "by.lua";
    std::ofstream(file) << "return { name = 'by', curriculum = 'tests/scripts/teach_curriculum.lua',\n"
                        << "  runs = { { name = 'Alp', stage = 'Alp' }, { name = 'Lift', stage = 'LiftOnly' } },\n"
                        << "  tables = { { title = 't', compare = { 'Alp/A', 'Lift/A' },\n"
                        << "               by = '" << table << "' } },\n"
                        << "  figures = { { file = 'f', kind = 'tasks', run = '" << run << "', param = '" << param
                        << "' } } }\n";
    return file.string();
  };
  // A task parameter, or what a world held; the parameter a teacher chooses, or the one LCAS lifts.
  for (const char* by : {"level", "obstacles", "shape", "objects"}) CHECK_NOTHROW(load_batch_script(with_param(by, "Alp", "level")));
  CHECK_NOTHROW(load_batch_script(with_param("level", "Lift", "distance")));
  CHECK_THAT(load_error(with_param("levle", "Alp", "level")),
             Catch::Matchers::Contains("by.lua:4: table 't': 'by' is 'levle', which no final evaluation of its runs "
                                       "records (did you mean 'level'?); they record what each world held (obstacles, "
                                       "objects, shape) and the task's 'level'"));
  CHECK_THAT(load_error(with_param("level", "Alp", "levl")),
             Catch::Matchers::Contains("by.lua:5: figure 'f': 'param' is 'levl', which the teacher of run 'Alp' does not "
                                       "choose (did you mean 'level'?); it chooses 'level'"));
  CHECK_THAT(load_error(with_param("level", "Lift", "level")),
             Catch::Matchers::Contains("the teacher of run 'Lift' does not choose; it chooses 'distance'"));
  // Found by a probe: a parameter the run's params fix drew "not drawn: no finished trial".
  std::ofstream(dir / "fixed.lua") << "return { name = 'fixed', curriculum = 'tests/scripts/teach_curriculum.lua',\n"
                                      "  runs = { { name = 'Fn', stage = 'Function', params = { level = 0.5 } } },\n"
                                      "  figures = { { file = 'f', kind = 'tasks', run = 'Fn',\n"
                                      "                param = 'level' } } }\n";
  CHECK_THAT(load_error((dir / "fixed.lua").string()),
             Catch::Matchers::Contains("fixed.lua:4: figure 'f': 'param' is 'level', which the params of run 'Fn' fix "
                                       "(level = 0.5): its teacher does not choose it in that run"));
  // Found by a probe: 'param' alone on a figure of another kind was said as "'param' and 'context'".
  std::ofstream(dir / "kindless.lua") << "return { name = 'kindless', curriculum = 'tests/scripts/teach_curriculum.lua',\n"
                                         "  runs = { { name = 'Alp', stage = 'Alp' } },\n"
                                         "  figures = { { file = 'f', run = 'Alp', param = 'level' } } }\n";
  CHECK_THAT(load_error((dir / "kindless.lua").string()),
             Catch::Matchers::Contains("figure 'f': 'param' belongs to a figure of kind \"tasks\" (this one is of "
                                       "kind \"curves\")"));
  // Found by a probe: log_x and y on a figure of another kind were taken, and set nothing.
  std::ofstream(dir / "axes.lua") << "return { name = 'axes', curriculum = 'tests/scripts/teach_curriculum.lua',\n"
                                     "  runs = { { name = 'Alp', stage = 'Alp' } },\n"
                                     "  figures = { { file = 't', kind = 'tasks', run = 'Alp',\n"
                                     "                log_x = true } } }\n";
  CHECK_THAT(load_error((dir / "axes.lua").string()),
             Catch::Matchers::Contains("axes.lua:4: figure 't': 'log_x' belongs to a figure of kind \"curves\" (this "
                                       "one is of kind \"tasks\", whose axes it does not set)"));
  fs::remove_all(dir);
}

// Found by a probe: a run built in a loop, with a computed name, was blamed at the line of another
// run (the first after `runs =`); and final_worlds = "own" on a stage that teaches was taken and
// had no effect (its final evaluation runs the test set, the same for every trial).
TEST_CASE("a run with a computed name is blamed at its own line; own final worlds are refused where a stage teaches",
          "[batch_script]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_built_runs_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path file = dir / "built.lua";
  std::ofstream(file) << "local runs = {}\n"
                         "runs[1] = { name = 'SG', stage = 'SG', contexts = { 'DC2' } }\n"
                         "for _, s in ipairs({ 'T' }) do\n"
                         "  runs[#runs + 1] = { name = s,\n"
                         "                      stage = s, contexts = { 'DC6', 'DC7' } }\n"
                         "end\n"
                         "return { name = 'built', curriculum = 'paper', trials = 1, runs = runs }\n";
  CHECK_THAT(load_error(file.string()), Catch::Contains("built.lua:5: run 'T': stage 'T' has no context 'DC7'"));
  std::ofstream(file) << "return { name = 'own', curriculum = 'tests/scripts/teach_curriculum.lua',\n"
                         "  runs = { { name = 'Alp', stage = 'Alp',\n"
                         "             final_worlds = 'own' } } }\n";
  CHECK_THAT(load_error(file.string()),
             Catch::Contains("built.lua:3: run 'Alp': final_worlds = 'own' cannot apply to stage 'Alp', which teaches: "
                             "every trial's final evaluation runs the stage's test set"));
  fs::remove_all(dir);
}

// Found by a probe: a table nested 33 deep in a batch script crashed roger check as the sandbox
// closed (the reader held a key and a value per level on Lua's stack, which guarantees 20 slots),
// and a line of 100,000 characters crashed it as the reader looked for a line (std::regex's
// matcher recursed once per character).
TEST_CASE("a batch script nested too deeply or with a very long line is refused at its line and never crashes",
          "[batch_script]") {
  const test::TempDir dir("roger_deep_batch");
  const fs::path file = dir.path / "deep.lua";
  std::ofstream(file) << "local deep = {}\nlocal at = deep\nfor i = 1, 1000 do at[1] = {} at = at[1] end\n"
                         "return { name = 'deep', curriculum = 'paper', trials = 1, notes = deep,\n"
                         "  runs = { { name = 'SG', stage = 'SG', contexts = { 'B1' } } } }\n";
  CHECK_THAT(load_error(file.string()), Catch::Contains("deep.lua:4: field 'notes[1][1]") &&
                                            Catch::Contains("[1]': nested too deeply"));
  const std::string padding(100000, ' ');
  std::ofstream(file) << "local runs = {}\n"
                         "for _, s in ipairs({ 'SG' }) do runs[#runs + 1] = { name = s, stage = s," << padding
                      << "contexts = { 'DC9' } } end\n"
                         "return { name = 'long', curriculum = 'paper', trials = 1, runs = runs }\n";
  CHECK_THAT(load_error(file.string()), Catch::Contains("deep.lua:2: run 'SG': stage 'SG' has no context 'DC9'"));
  std::ofstream(file) << "return { name = 'long', curriculum = 'paper', trials = 1,\n"
                         "  runs = { { name = 'SG', stage = 'SG', contexts = { 'B1' } },\n"
                         "           { name = '" << std::string(100000, 'x') << "', stage = 'SG', contexts = { 'DC9' } } } }\n";
  CHECK_THAT(load_error(file.string()), Catch::Contains("deep.lua:3: run '" + std::string(10, 'x')) &&
                                            Catch::Contains("': a run name uses letters, digits, '.', '_' and '-', at "
                                                            "most 200 of them"));
}

// Found by a probe: description = "caf\233 au lait" (Latin-1) passed roger check, and roger run
// stopped with "[json.exception.type_error.316] invalid UTF-8 byte at index 4" naming nothing.
TEST_CASE("a batch script's text that is no UTF-8 is refused at load, naming the field", "[batch_script]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_batch_latin1_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path file = dir / "latin1.lua";
  std::ofstream(file) << "return { name = 'l', curriculum = 'paper', trials = 1, description = 'caf\\233 au lait',\n"
                         "  runs = { { name = 'SG', stage = 'SG', contexts = { 'B1' } } } }\n";
  CHECK_THAT(load_error(file.string()),
             Catch::Contains("latin1.lua:1: field 'description' must be UTF-8 text, got \"caf\\xE9 au lait\" "
                             "(byte 0xe9 at byte 4 is not part of a UTF-8 character; save the script as UTF-8)"));
  std::ofstream(file) << "return { name = 'l', curriculum = 'paper', trials = 1, description = 'caf\\195\\169 au lait',\n"
                         "  runs = { { name = 'SG', stage = 'SG', contexts = { 'B1' } } } }\n";
  CHECK(load_error(file.string()).empty());
  fs::remove_all(dir);
}

// Found by a probe: `trials = "2"` said "must be an integer" without what it got, and a misspelt
// context of a batch script had no "did you mean", where the stage's and train's errors have one.
TEST_CASE("a batch script's wrong type says what it got, a misspelt context its nearest", "[batch_script]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_batch_said_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const auto error_with = [&](const std::string& trials, const std::string& context) {
    std::ofstream(dir / "said.lua") << "return {\n  name = \"said\", curriculum = \"paper\", trials = " << trials
                                    << ",\n  runs = { { name = \"SG\", stage = \"SG\", contexts = { \"" << context
                                    << "\" } } },\n}\n";
    return load_error((dir / "said.lua").string());
  };
  CHECK_THAT(error_with("\"2\"", "DC2"),
             Catch::Contains("said.lua:2: the batch script: field 'trials' must be an integer, got string '2'"));
  CHECK_THAT(error_with("2", "DC22"), Catch::Contains("said.lua:3: run 'SG': stage 'SG' has no context 'DC22' (did you "
                                                      "mean 'DC2'?); its contexts are 'B1', 'DC1', 'DC2'"));
  fs::remove_all(dir);
}

// Found by a probe: a batch script's mistakes came one roger check at a time. Each entry's first
// problem is said; entries naming a run that was not read wait for the fix, and say so.
TEST_CASE("roger check says every entry's problem, and which entries wait for a fix", "[batch_script]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_batch_all_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path file = dir / "all.lua";
  std::ofstream(file) << "return {\n"
                         "  name = 'all', curriculum = 'paper', trials = 2,\n"
                         "  runs = {\n"
                         "    { name = 'SG', stage = 'SG', contexts = { 'B1', 'DC9' } },\n"
                         "    { name = 'SG2', stage = 'SGG' },\n"
                         "    { name = 'T', stage = 'T', contexts = { 'B2' }, skills = { Phi_SG = { run = 'SG', context = 'DC2' } } },\n"
                         "  },\n"
                         "  tables = {\n"
                         "    { title = 'x', run = 'SG' },\n"
                         "    { title = 'y', evaluation = 'none' },\n"
                         "    { title = 'z', compare = { 'SG/B1', 'SG2/B1' } },\n"
                         "    { title = 's', sorting = { { objects = 2, hand = 'SG2' } } },\n"
                         "  },\n"
                         "  figures = { { file = 'f', run = 'SG', kind = 'pie' } },\n"
                         "}\n";
  BatchProblems problems;
  check_batch_script(file.string(), {}, problems);
  REQUIRE(problems.errors.size() == 2);
  CHECK_THAT(problems.errors[0].what(), Catch::Contains("all.lua:4: run 'SG': stage 'SG' has no context 'DC9'"));
  CHECK_THAT(problems.errors[1].what(), Catch::Contains("all.lua:5: run 'SG2': the curriculum"));
  CHECK_THAT(problems.errors[1].what(), Catch::Contains("'SGG'"));
  // A comparison's "run/context" rows and a sorting row's runs are names too (found by a probe).
  CHECK(problems.unchecked ==
        std::vector<std::string>{"run 'T'", "table 'x'", "table 'y'", "table 'z'", "table 's'", "figure 'f'"});
  // roger run stops at the first, as before.
  CHECK_THAT(load_error(file.string()), Catch::Contains("all.lua:4:") && !Catch::Contains("all.lua:5:"));

  // Without a problem in the runs, every table and figure is read.
  std::ofstream(file) << "return {\n"
                         "  name = 'all', curriculum = 'paper', trials = 2,\n"
                         "  runs = { { name = 'SG', stage = 'SG', contexts = { 'B1', 'DC1' } } },\n"
                         "  tables = {\n"
                         "    { title = 'x', run = 'SG', baseline = 'DC2' },\n"
                         "    { title = 'y', evaluation = 'none' },\n"
                         "  },\n"
                         "  figures = { { file = 'f', run = 'SG', kind = 'pie' } },\n"
                         "}\n";
  problems = {};
  check_batch_script(file.string(), {}, problems);
  REQUIRE(problems.errors.size() == 3);
  CHECK_THAT(problems.errors[0].what(), Catch::Contains("all.lua:5: table 'x': run 'SG' has no context 'DC2'"));
  CHECK_THAT(problems.errors[1].what(), Catch::Contains("all.lua:6: table 'y': no evaluation 'none'"));
  CHECK_THAT(problems.errors[2].what(), Catch::Contains("all.lua:8: figure 'f': 'kind' is"));
  CHECK(problems.unchecked.empty());
  fs::remove_all(dir);
}

// Found by a probe: a second run (or evaluation) of the same name was refused at the first's line.
TEST_CASE("a second run or evaluation of a name is refused at its own line", "[batch_script]") {
  const test::TempDir dir("roger_second_name");
  const fs::path file = dir.path / "twice.lua";
  std::ofstream(file) << "return { name = 'twice', curriculum = 'paper', trials = 1,\n"
                         "  runs = {\n"
                         "    { name = 'SG', stage = 'SG', contexts = { 'DC2' } },\n"
                         "    { name = 'SG', stage = 'SG', contexts = { 'B1' } } } }\n";
  CHECK_THAT(load_error(file.string()), Catch::Contains("twice.lua:4: a second run named 'SG' (the first is at line 3)"));
  std::ofstream(file) << "return { name = 'twice', curriculum = 'paper', trials = 1,\n"
                         "  runs = { { name = 'SG', stage = 'SG', contexts = { 'DC2' } } },\n"
                         "  evaluations = {\n"
                         "    { name = 'e', run = 'SG', episodes = 2 },\n"
                         "    { name = 'e', run = 'SG', episodes = 3 } } }\n";
  CHECK_THAT(load_error(file.string()),
             Catch::Contains("twice.lua:5: a second evaluation named 'e' (the first is at line 4)"));
  // Found by a probe: a comparison's row twice drew two identical rows.
  std::ofstream(file) << "return { name = 'twice', curriculum = 'paper', trials = 1,\n"
                         "  runs = { { name = 'SG', stage = 'SG', contexts = { 'B1', 'DC2' } } },\n"
                         "  tables = { { compare = { 'SG/B1', 'SG/DC2', 'SG/B1' } } } }\n";
  CHECK_THAT(load_error(file.string()), Catch::Contains("'compare' names 'SG/B1' twice"));
  // Found by a probe: the same table twice was written twice without a word.
  std::ofstream(file) << "return { name = 'twice', curriculum = 'paper', trials = 1,\n"
                         "  runs = { { name = 'SG', stage = 'SG', contexts = { 'B1', 'DC2' } } },\n"
                         "  tables = { { run = 'SG' }, { run = 'SG' } } }\n";
  CHECK_THAT(load_error(file.string()),
             Catch::Contains("twice.lua:3: a second table the same as an earlier one ('Stage SG (run SG)'): the "
                             "report would show it twice"));
  std::ofstream(file) << "return { name = 'twice', curriculum = 'paper', trials = 1,\n"
                         "  runs = { { name = 'SG', stage = 'SG', contexts = { 'B1', 'DC2' } } },\n"
                         "  tables = { { run = 'SG' }, { run = 'SG', baseline = 'DC2' } } }\n";
  CHECK(load_batch_script(file.string()).tables.size() == 2);
  // And a one-line script's second figure of a file was said to be at line 2 (it has one).
  std::ofstream(file) << "return { name = 'twice', curriculum = 'paper', runs = { { name = 'SG', stage = 'SG' } }, "
                         "figures = { { file = 'f', run = 'SG' }, { file = 'f', run = 'SG' } } }";
  CHECK_THAT(load_error(file.string()), Catch::Contains("twice.lua:1: a second figure written to 'f'"));
  // A name past 200 bytes would fail at the results folder (found by a probe: "File name too long").
  std::ofstream(file) << "return { name = '" << std::string(300, 'n') << "', curriculum = 'paper', trials = 1,\n"
                         "  runs = { { name = 'SG', stage = 'SG', contexts = { 'B1' } } } }\n";
  CHECK_THAT(load_error(file.string()), Catch::Contains("at most 200 bytes, got 'nnnn") &&
                                            Catch::Contains("...' (300 bytes)"));
}

// Found by a probe: a usage row whose skill subsumed itself printed a share of nothing.
TEST_CASE("a usage row's skill does not subsume itself", "[batch_script]") {
  const test::TempDir dir("roger_usage_self");
  const fs::path file = dir.path / "usage.lua";
  std::ofstream(file) << "return { name = 'usage', curriculum = 'paper', trials = 1,\n"
                         "  runs = { { name = 'SG', stage = 'SG', contexts = { 'B1', 'DC1' } } },\n"
                         "  tables = { { run = 'SG', usage = {\n"
                         "    { context = 'DC1', skill = 'Phi7', subsumes = { 'phi1', 'Phi7' } } } } } }\n";
  CHECK_THAT(load_error(file.string()),
             Catch::Contains("'Phi7' subsumes itself: list the actions it stands for, not the skill"));
}

// Found by a probe: an evaluation whose scenario named a curriculum failed inside the curriculum
// ("skills.lua:45: attempt to call a nil value"), at no line of the batch script.
TEST_CASE("an evaluation's scenario of another kind of script is refused at its line, saying the kind", "[batch_script]") {
  const test::TempDir dir("roger_eval_kind");
  const fs::path file = dir.path / "kind.lua";
  std::ofstream(file) << "return { name = 'kind', curriculum = 'paper', trials = 1,\n"
                         "  runs = { { name = 'SG', stage = 'SG', contexts = { 'DC2' } } },\n"
                         "  evaluations = { { name = 'e', run = 'SG', episodes = 2,\n"
                         "    scenario = 'curricula/paper.lua' } } }\n";
  CHECK_THAT(load_error(file.string()),
             Catch::Contains("kind.lua:4: evaluation 'e': curricula/paper.lua is a curriculum, not a scenario"));
}

// Found by a probe: a sorting row of 8 objects over a run of 2 printed "8 objects, 2 sorted per
// episode", and a row over a stage of no sorting a count made up from its reward.
TEST_CASE("a sorting row's runs sort worlds of the row's number of objects", "[batch_script]") {
  const test::TempDir dir("roger_sorting_rows");
  const fs::path file = dir.path / "rows.lua";
  auto script = [&](const std::string& runs, const std::string& row) {
    std::ofstream(file) << "return { name = 'rows', curriculum = 'curricula/sorting.lua', trials = 1,\n"
                        << "  runs = { " << runs << " },\n"
                        << "  tables = { { title = 'sorting', sorting = { " << row << " } } } }\n";
    return file.string();
  };
  const std::string hand2 = "{ name = 'Hand2', stage = 'Hand2', contexts = { 'Scripted' } }";
  CHECK_NOTHROW(load_batch_script(script(hand2, "{ objects = 2, hand = 'Hand2' }")));
  CHECK_THAT(load_error(script(hand2, "{ objects = 8, hand = 'Hand2' }")),
             Catch::Contains("rows.lua:3: table 'sorting': the row is of 8 objects, but run 'Hand2' (context 'Scripted') "
                             "plays worlds of 2"));
  CHECK_THAT(load_error(script("{ name = 'SG', stage = 'SG', contexts = { 'DC2' } }", "{ objects = 2, hand = 'SG' }")),
             Catch::Contains("run 'SG' trains stage 'SG' in scenario") &&
                 Catch::Contains("which has no parameter 'objects': a sorting row's runs sort"));
  // Found by a probe: 'learned' and 'hand' swapped were taken, and the learned run's trials pooled
  // as one policy's; two rows of one count were taken too.
  const std::string both = hand2 + ", { name = 'SG', stage = 'SG', contexts = { 'DC2' } }, { name = 'T', stage = 'T', "
                           "contexts = { 'DC6' }, skills = { Phi_SG = { run = 'SG', context = 'DC2' } } }, { name = "
                           "'Sort2', stage = 'Sort2', contexts = { 'Learned' }, skills = { Phi_T = { run = 'T', "
                           "context = 'DC6' } } }";
  CHECK_NOTHROW(load_batch_script(script(both, "{ objects = 2, learned = 'Sort2', hand = 'Hand2' }")));
  CHECK_THAT(load_error(script(both, "{ objects = 2, learned = 'Hand2', hand = 'Sort2' }")),
             Catch::Contains("rows.lua:3: table 'sorting': 'hand' names run 'Sort2', whose context 'Learned' learns to "
                             "choose among 4 actions; a hand-written run's contexts have one action, the policy (did you "
                             "mean learned = 'Sort2'?)"));
  CHECK_THAT(load_error(script(both, "{ objects = 2, learned = 'Hand2' }")),
             Catch::Contains("'learned' names run 'Hand2', which learns nothing: each of its contexts has one action "
                             "(did you mean hand = 'Hand2'?)"));
  CHECK_THAT(load_error(script(both, "{ objects = 2, learned = 'Sort2' }, { objects = 2, hand = 'Hand2' }")),
             Catch::Contains("two sorting rows of 2 objects"));
}
