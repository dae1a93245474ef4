// Tests of engine/trainer: a trial is repeatable bit for bit, `roger train --json` writes every
// file and a parseable last line, `roger eval --policy` reproduces the final evaluation from the
// saved file, every context of the paper's curriculum reaches 90% greedy success, with the figures
// printed for quoting, and the evaluation cache changes no result ("[cache]").
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdio>
#include <map>
#include <tuple>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "batch/explain.h"
#include "batch/trainer.h"
#include "core/fileio.h"
#include "control/agent.h"
#include "script/curriculum/curriculum.h"
#include "script/scenario/scenario.h"
#include "temp_dir.h"
#include "test_files.h"

using namespace roger;
namespace fs = std::filesystem;
using roger::test::slurp;
using Catch::Matchers::Contains;

namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// One trial's options: curriculum, stage, context and seed, without keeping its episodes.
TrainOptions trial_options(const std::string& curriculum, const std::string& stage, const std::string& context,
                           uint64_t seed) {
  TrainOptions o;
  o.curriculum = curriculum;
  o.stage = stage;
  o.context = context;
  o.seed = seed;
  o.keep_episodes = false;
  return o;
}

// Runs the roger program; returns its exit status and standard output.
std::pair<int, std::string> run_roger(const std::string& args) {
  const fs::path out = fs::temp_directory_path() / ("roger_trainer_out_" + std::to_string(::getpid()));
  const int raw = std::system((std::string(ROGER_BINARY) + " " + args + " >" + out.string() + " 2>&1").c_str());
  std::string text = slurp(out);
  fs::remove(out);
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, text};
}

std::string last_line(const std::string& text) {
  std::string t = text;
  while (!t.empty() && t.back() == '\n') t.pop_back();
  const size_t nl = t.rfind('\n');
  return nl == std::string::npos ? t : t.substr(nl + 1);
}

}  // namespace

TEST_CASE("the same seed gives the same learning curve and policy", "[trainer]") {
  TrainOptions o;
  o.curriculum = "paper";
  o.stage = "SG";
  o.context = "DC1";
  o.seed = 11;
  const TrainResult a = train_stage(o);
  const TrainResult b = train_stage(o);
  REQUIRE(a.episodes.size() == b.episodes.size());
  for (size_t i = 0; i < a.episodes.size(); ++i) {
    INFO("episode " << i);
    CHECK(a.episodes[i].episode.seed == b.episodes[i].episode.seed);
    CHECK(same_bits(a.episodes[i].epsilon, b.episodes[i].epsilon));
    CHECK(same_bits(a.episodes[i].episode.reward, b.episodes[i].episode.reward));
    CHECK(same_bits(a.episodes[i].episode.sim_seconds, b.episodes[i].episode.sim_seconds));
    CHECK(a.episodes[i].episode.actions_taken == b.episodes[i].episode.actions_taken);
  }
  REQUIRE(a.checkpoints.size() == b.checkpoints.size());
  for (size_t i = 0; i < a.checkpoints.size(); ++i) {
    CHECK(a.checkpoints[i].at.episodes == b.checkpoints[i].at.episodes);
    CHECK(same_bits(a.checkpoints[i].at.sim_s, b.checkpoints[i].at.sim_s));
    CHECK(a.checkpoints[i].at.decisions == b.checkpoints[i].at.decisions);
    CHECK(same_bits(a.checkpoints[i].success_rate, b.checkpoints[i].success_rate));
    CHECK(same_bits(a.checkpoints[i].reward_mean, b.checkpoints[i].reward_mean));
  }
  int differing = 0;
  for (int s = 0; s < a.q->states(); ++s)
    for (int k = 0; k < a.q->actions(); ++k)
      differing += !same_bits(a.q->value(s, k), b.q->value(s, k)) || a.q->visits(s, k) != b.q->visits(s, k);
  CHECK(differing == 0);
  CHECK(same_bits(a.to_threshold.sim_s, b.to_threshold.sim_s));
  CHECK(same_bits(a.final_eval.success_rate, b.final_eval.success_rate));
  // Another seed trains on other worlds.
  o.seed = 12;
  const TrainResult c = train_stage(o);
  CHECK(c.episodes[0].episode.seed != a.episodes[0].episode.seed);
}

// Before, a stage always began from initial_q: a run could not go on from a table learned earlier.
TEST_CASE("roger train --init starts the table from a policy learned earlier", "[trainer]") {
  const test::TempDir tmp("roger_trainer_init");
  TrainOptions o;
  o.curriculum = "paper";
  o.stage = "SG";
  o.context = "DC1";
  o.seed = 1;
  const TrainResult dc1 = train_stage(o);
  const std::string file = (tmp.path / "dc1.json").string();
  write_file_atomic(file, train_policy_json(dc1).dump(), "test");
  o.context = "DC2";
  const TrainResult cold = train_stage(o);
  o.init_file = file;
  const TrainResult warm = train_stage(o);
  REQUIRE(warm.init);
  CHECK(warm.init->shared == std::vector<std::string>{"phi3", "Phi6", "Phi7"});
  CHECK(warm.init->dropped == std::vector<std::string>{"phi1", "phi4 <| phi2"});
  // DC1's values over DC2's actions: the deterministic engine reaches the threshold in 10 episodes
  // instead of 20 (a warm start that carried nothing would take the cold run's 20).
  CHECK(cold.to_threshold.episodes == 20);
  CHECK(warm.to_threshold.episodes == 10);
  const nlohmann::json summary = train_summary_json(warm);
  CHECK(summary["init"]["file"] == file);
  CHECK(summary["init"]["shared"].size() == 3);
  CHECK(train_policy_json(warm)["extra"]["init"] == summary["init"]);
  CHECK_FALSE(train_summary_json(cold).contains("init"));
  // A table sharing no action with the context is refused, naming both sets.
  o.stage = "T";
  o.context = "DC6";
  CHECK_THROWS_WITH(train_stage(o), Catch::Matchers::Contains("dc1.json: its table shares no action with this "
                                                              "context's (its actions: phi1, phi3, phi4 <| phi2, Phi6, Phi7;"));
  // Found by a probe: --init warm-started the skill trained first (Phi_SG) too, changing it without
  // a word, and a T context's start from another T context's table was refused naming SG/DC2's
  // actions. The skill is trained as without --init; the table starts from the shared actions.
  o.init_file.clear();
  const TrainResult t6 = train_stage(o);
  const std::string t6_file = (tmp.path / "t6.json").string();
  write_file_atomic(t6_file, train_policy_json(t6).dump(), "test");
  o.context = "DC4";
  const TrainResult t4_cold = train_stage(o);
  o.init_file = t6_file;
  const TrainResult t4_warm = train_stage(o);
  REQUIRE(t4_warm.init);
  CHECK_FALSE(t4_warm.init->shared.empty());
  REQUIRE(t4_warm.skills.size() == 1);
  REQUIRE(t4_cold.skills.size() == 1);
  CHECK(t4_warm.skills[0].trained);
  CHECK(t4_warm.skills[0].to_threshold.episodes == t4_cold.skills[0].to_threshold.episodes);
  CHECK(t4_warm.skills[0].policy == t4_cold.skills[0].policy);
}

// init = {stage = ..., context = ...} in a context: that context is trained first with the same
// seed, and its table is where this one starts.
TEST_CASE("a context's init trains that context first and starts from its table", "[trainer]") {
  const test::TempDir tmp("roger_trainer_ctx_init");
  std::ofstream(tmp.path / "init.lua")
      << "local SG = require('lib.paper_stages').stages{}\n"
         "local p = require('lib.skills').primitives()\n"
         "return { stages = { roger.stage{ name = 'S', time_limit = SG.time_limit, absorbing = SG.absorbing,\n"
         "  budget = SG.budget, checkpoints = SG.checkpoints, contexts = {\n"
         "    { name = 'Small', actions = SG.contexts[3].actions },\n"
         "    { name = 'Big', actions = SG.contexts[2].actions, init = { context = 'Small' } } } } } }\n";
  TrainOptions o;
  o.curriculum = (tmp.path / "init.lua").string();
  o.stage = "S";
  o.context = "Big";
  o.seed = 1;
  const TrainResult r = train_stage(o);
  REQUIRE(r.init);
  REQUIRE(r.init_trained);
  const nlohmann::json j = train_summary_json(r)["init"];
  CHECK(j["stage"] == "S");
  CHECK(j["context"] == "Small");
  CHECK(j["seed"] == 1);
  CHECK_FALSE(j.contains("file"));
  CHECK(j["totals"]["episodes"].get<int>() > 0);
  // The same as --init with the policy that context learns with that seed.
  o.context = "Small";
  const std::string file = (tmp.path / "small.json").string();
  write_file_atomic(file, train_policy_json(train_stage(o)).dump(), "test");
  o.context = "Big";
  o.init_file = file;
  const TrainResult same = train_stage(o);
  CHECK(same.to_threshold.episodes == r.to_threshold.episodes);
  CHECK(same.final_eval.success_rate == r.final_eval.success_rate);
  for (int s = 0; s < r.q->states(); ++s)
    for (int a = 0; a < r.q->actions(); ++a) CHECK(r.q->value(s, a) == same.q->value(s, a));
}

TEST_CASE("roger train writes every file and eval --policy reproduces its final evaluation", "[trainer][cli]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_train_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const auto [status, out] =
      run_roger("train curricula/paper.lua --stage SG --context DC2 --seed 4 --out " + dir.string() + " --json");
  INFO(out);
  REQUIRE(status == 0);
  for (const char* f : {"policy.json", "curve.csv", "episodes.jsonl", "checkpoints.jsonl", "summary.json"})
    CHECK(fs::is_regular_file(dir / f));
  const nlohmann::json j = nlohmann::json::parse(last_line(out));
  for (const char* k : {"time_to_threshold_s", "episodes_to_threshold", "decisions_to_threshold", "wall_to_threshold_s",
                        "wall_s", "reached", "success_rate", "reward_mean", "reward_std", "usage"})
    CHECK(j.contains(k));
  CHECK(j["usage"].contains("Phi7"));
  CHECK(nlohmann::json::parse(slurp(dir / "summary.json"))["success_rate"] == j["success_rate"]);
  CHECK(slurp(dir / "curve.csv").rfind("episodes,sim_s,decisions,wall_s,success_rate,reward_mean\n", 0) == 0);
  const nlohmann::json first_episode = nlohmann::json::parse(slurp(dir / "episodes.jsonl").substr(0, slurp(dir / "episodes.jsonl").find('\n')));
  for (const char* k : {"index", "seed", "epsilon", "reward", "success", "sim_s", "ticks", "decisions", "actions"})
    CHECK(first_episode.contains(k));
  const nlohmann::json policy = nlohmann::json::parse(slurp(dir / "policy.json"));
  CHECK(policy["stage"] == "SG");
  CHECK(policy["context"] == "DC2");
  CHECK(policy["extra"]["psi"] == nlohmann::json({"phi3", "Phi6", "Phi7"}));

  // The saved policy alone plus the curriculum: the same held-out seeds give the same rate.
  const auto [estatus, eout] = run_roger("eval curricula/paper.lua --policy " + (dir / "policy.json").string() + " --json");
  INFO(eout);
  REQUIRE(estatus == 0);
  const nlohmann::json e = nlohmann::json::parse(last_line(eout));
  CHECK(e["success_rate"] == j["success_rate"]);
  CHECK(e["reward_mean"] == j["reward_mean"]);
  // In another scenario too (a figure, not a comparison).
  const auto [cstatus, cout] = run_roger("eval curricula/paper.lua --policy " + (dir / "policy.json").string() +
                                     " --scenario cluttered --set shape=spade --episodes 5 --json");
  INFO(cout);
  CHECK(cstatus == 0);
  // A T policy trained with --skill embeds the skill, so eval needs only the file.
  const fs::path tdir = dir / "T";
  const auto [tstatus, tout] = run_roger("train curricula/paper.lua --stage T --context DC6 --seed 4 --out " + tdir.string() +
                                     " --skill Phi_SG=" + (dir / "policy.json").string() + " --json");
  INFO(tout);
  REQUIRE(tstatus == 0);
  const nlohmann::json t = nlohmann::json::parse(last_line(tout));
  CHECK(t["skills"]["Phi_SG"]["trained"] == false);
  // Found by a probe: training that stop_after ended said nothing of it.
  CHECK((tout.find("  stopped        after " + std::to_string(t["train_episodes"].get<int>()) +
                   " training episodes, before the budget's end") != std::string::npos) == t["stopped_early"].get<bool>());
  const auto [t2status, t2out] = run_roger("eval curricula/paper.lua --policy " + (tdir / "policy.json").string() + " --json");
  INFO(t2out);
  REQUIRE(t2status == 0);
  CHECK(nlohmann::json::parse(last_line(t2out))["success_rate"] == t["success_rate"]);

  // roger render replays one of those greedy episodes through the same loop: the same outcome as
  // its evaluation, with the frames, the states of Psi and what ran inside it.
  PolicyEvalOptions po;
  po.curriculum = "curricula/paper.lua";
  po.policy_file = (tdir / "policy.json").string();
  po.scenario = "cluttered";
  po.sets = {{"shape", "spade"}};
  for (int64_t seed : {4009, 4010, 4011}) {
    po.first_seed = seed;
    po.episodes = 1;
    const PolicyEvalResult evaluated = evaluate_policy_file(po);
    const RecordedPolicyEpisode recorded = record_policy_episode(po, 0.5);
    CHECK(recorded.episode.success == (evaluated.eval.successes == 1));
    CHECK(recorded.episode.reward == evaluated.eval.reward_mean);
    CHECK(recorded.episode.sim_seconds == evaluated.eval.time_mean);
    CHECK(recorded.episode.frames.size() >= size_t(recorded.episode.sim_seconds / 0.5));
    REQUIRE(recorded.episode.gammas.size() >= 2);
    CHECK(recorded.episode.gammas[0].name == "Phi_STG");  // Psi first, then what is inside it
    CHECK(recorded.episode.gammas[0].states.size() == size_t(recorded.episode.ticks));
    // No row repeats another: Phi_STG and the transport each hold a "phi4 <| phi5" of their own,
    // and the learned Phi_SG runs inside a binding of the same name; each pair runs alike, so each
    // is one row, not two rows or a numbered second one.
    for (size_t i = 0; i < recorded.episode.gammas.size(); ++i) {
      CHECK(recorded.episode.gammas[i].name.find(" (") == std::string::npos);
      for (size_t j = 0; j < i; ++j) CHECK(recorded.episode.gammas[i].name != recorded.episode.gammas[j].name);
    }
    REQUIRE(!recorded.episode.decisions.empty());
    CHECK(recorded.episode.decisions.front().path.front() == "Phi_STG");
  }
  const fs::path movie = dir / "replay";
  const auto [rstatus, rout] = run_roger("render curricula/paper.lua --policy " + (tdir / "policy.json").string() +
                                         " --seed 2000000 --out " + movie.string());
  INFO(rout);
  CHECK(rstatus == 0);
  CHECK(fs::is_regular_file(movie / "episode.json"));
  fs::remove_all(dir);
}

TEST_CASE("a time limit per object follows the objects of each world in training and in eval", "[trainer][cli]") {
  // time_limit = {per_object = s}: an episode in a world of n objects times out after n s, so a
  // saved policy evaluated with another number of objects gets the time that number needs.
  const test::TempDir tmp("roger_trainer_per_object");
  std::ofstream(tmp.path / "per_object.lua") << R"(local p3 = roger.primitive("phi3")
return { stages = { roger.stage{
  name = "Never", scenario = "sorting", params = { objects = 3 }, time_limit = { per_object = 0.4 },
  absorbing = function() return false end, budget = { episodes = 2 },
  checkpoints = { every = 2, episodes = 1, final = 2 },
  contexts = { { name = "A", actions = { p3 } } },
} } }
)";
  const std::string curriculum = (tmp.path / "per_object.lua").string();
  const auto [status, out] = run_roger("train " + curriculum + " --stage Never --context A --seed 1 --out " +
                                       (tmp.path / "out").string());
  INFO(out);
  REQUIRE(status == 0);
  std::istringstream episodes(slurp(tmp.path / "out" / "episodes.jsonl"));
  int count = 0;
  for (std::string line; std::getline(episodes, line); ++count)
    CHECK(nlohmann::json::parse(line)["sim_s"].get<double>() == Approx(1.2).margin(1e-9));  // 3 objects
  CHECK(count == 2);
  PolicyEvalOptions po;
  po.curriculum = curriculum;
  po.policy_file = (tmp.path / "out" / "policy.json").string();
  po.episodes = 2;
  for (int objects : {1, 5}) {
    po.sets = {{"objects", std::to_string(objects)}};
    const PolicyEvalResult r = evaluate_policy_file(po);
    CHECK(r.eval.successes == 0);
    CHECK(r.eval.time_mean == Approx(0.4 * objects).margin(1e-9));
    CHECK(r.time_limit == "0.4 s per object limit");
  }
  const auto [estatus, eout] = run_roger("eval " + curriculum + " --policy " + po.policy_file + " --set objects=5 --episodes 1");
  INFO(eout);
  CHECK(estatus == 0);
  CHECK(eout.find("0.4 s per object limit") != std::string::npos);
  CHECK(eout.find("2.00 s (mean, simulated)") != std::string::npos);
}

// Each context of the paper, one seeded trial: the figures to quote, and the final success.
TEST_CASE("every context of the paper's curriculum reaches 90% greedy success", "[trainer][paper]") {
  const std::vector<std::pair<std::string, std::string>> contexts = {
      {"SG", "B1"}, {"SG", "DC1"}, {"SG", "DC2"}, {"T", "B2"}, {"T", "DC3"}, {"T", "DC4"}, {"T", "DC5"}, {"T", "DC6"}};
  for (const auto& [stage, context] : contexts) {
    TrainOptions o = trial_options("paper", stage, context, 1);
    const TrainResult r = train_stage(o);
    std::printf("%-3s %-4s reached %-5s time-to-threshold %8.1f sim s, %5d episodes, %6.2f wall s; final success %.2f "
                "(trial %.1f wall s)\n",
                stage.c_str(), context.c_str(), r.reached ? "yes" : "no", r.to_threshold.sim_s, r.to_threshold.episodes,
                r.to_threshold.wall_s, r.final_eval.success_rate, r.wall_s);
    INFO(stage << "/" << context);
    CHECK(r.final_eval.success_rate >= 0.9);
  }
}

namespace {
// Median time-to-threshold over seeds 1 to `seeds` of one context, in simulated seconds and in episodes;
// a trial that never reached the threshold counts at its whole training time (censored).
std::pair<double, double> median_time_to_threshold(const std::string& stage, const std::string& context,
                                                   int seeds = 10, const std::string& curriculum = "paper") {
  std::vector<double> times, episodes;
  for (uint64_t seed = 1; seed <= uint64_t(seeds); ++seed) {
    TrainOptions o = trial_options(curriculum, stage, context, seed);
    const TrainResult r = train_stage(o);
    times.push_back(r.reached ? r.to_threshold.sim_s : r.totals.sim_s);
    episodes.push_back(r.reached ? r.to_threshold.episodes : r.totals.episodes);
  }
  std::sort(times.begin(), times.end());
  std::sort(episodes.begin(), episodes.end());
  const size_t h = size_t(seeds) / 2;  // seeds is even
  const std::pair<double, double> m{0.5 * (times[h - 1] + times[h]), 0.5 * (episodes[h - 1] + episodes[h])};
  std::printf("%s/%-4s median time-to-threshold over %d seeds: %.1f simulated s, %.1f episodes\n", stage.c_str(),
              context.c_str(), seeds, m.first, m.second);
  return m;
}
}  // namespace

TEST_CASE("the baselines reach the threshold, and valuing untried actions as failures slows B2", "[trainer][fidelity]") {
  // B1, seeds 2 and 9, and B2, seed 6: short runs that reach the threshold and keep it (every B1
  // and B2 trial of the paper run does).
  for (uint64_t seed : {2, 9}) {
    TrainOptions o = trial_options("paper", "SG", "B1", seed);
    const TrainResult paper = train_stage(o);
    INFO("B1 seed " << seed);
    CHECK(paper.reached);
    CHECK(paper.final_eval.success_rate >= 0.9);
  }
  const TrainResult b2 = train_stage(trial_options("paper", "T", "B2", 6));
  CHECK(b2.reached);
  CHECK(b2.final_eval.success_rate >= 0.9);
  // With initial_q = -100 (curricula/ablation.lua's T_q100, the setting the paper's curriculum
  // replaced) untried actions stop being tried once exploration falls: over seeds 1-10 B2 needs
  // 295 episodes to the threshold by the median, against 120 with the paper's settings. (It used
  // to stall some trials for good, seed 6 among them; since phi1 read for its state neither solves
  // nor commits to a turn, none of seeds 1-60 stalls.)
  const auto paper = median_time_to_threshold("T", "B2");
  const auto q100 = median_time_to_threshold("T_q100", "B2", 10, "curricula/ablation.lua");
  CHECK(q100.second > 1.5 * paper.second);
}

TEST_CASE("training stops after stop_after passing checkpoints of one greedy policy", "[trainer]") {
  // SG/DC2 stopped after 5 passing checkpoints (curricula/ablation.lua's SG_stop5 and
  // SG_anypass), seed 14: its first four checkpoints pass, and the policy changed in the 10
  // episodes before the fifth, which passes too. Counting any passes (settle = false) it stopped
  // there, yielding a Phi_SG that had passed once and succeeds in 88.5% of fresh worlds; with
  // settle (the default) it trains on until one policy has passed five times.
  TrainOptions o = trial_options("curricula/ablation.lua", "SG_stop5", "DC2", 14);
  const TrainResult settled = train_stage(o);
  o.stage = "SG_anypass";
  const TrainResult anypass = train_stage(o);
  REQUIRE(anypass.stopped_early);
  REQUIRE(anypass.checkpoints.size() == 5);
  CHECK(anypass.checkpoints.back().policy_changed);
  REQUIRE(settled.stopped_early);
  CHECK(settled.checkpoints.size() > 5);
  // The rule itself: the last five pass, and the last four are the first one's policy.
  const auto& cps = settled.checkpoints;
  for (size_t k = cps.size() - 5; k < cps.size(); ++k) {
    INFO("checkpoint " << k);
    CHECK(cps[k].success_rate >= settled.threshold);
    if (k > cps.size() - 5) CHECK_FALSE(cps[k].policy_changed);
  }
  CHECK(cps.front().policy_changed);
  // Up to the fifth checkpoint both trained the same episodes with the same seeds.
  for (size_t k = 0; k < 5; ++k) CHECK(same_bits(cps[k].success_rate, anypass.checkpoints[k].success_rate));
}

TEST_CASE("over 30 seeds, the search-grasp contexts' medians order as the paper found", "[trainer][medians]") {
  // The paper's Table I: DC2 fastest, then DC1, then the baseline B1. Handing over Phi7 (approach
  // while preshaping) shortens the chain to learn, and DC2, which also drops the primitives Phi7
  // subsumes, has 27 states against B1's 81. Over 50 trials DC1 leads B1 by 31% (p = 0.013,
  // docs/results.md); seeds 1-10 alone cannot resolve it (B1's median there is 125 s against
  // DC1's 148 s; over seeds 1-30, 248 s against 149 s).
  std::map<std::string, double> median;
  for (const char* c : {"B1", "DC1", "DC2"}) median[c] = median_time_to_threshold("SG", c, 30).first;
  INFO("medians: B1 " << median["B1"] << ", DC1 " << median["DC1"] << ", DC2 " << median["DC2"] << " simulated s");
  CHECK(median["DC2"] < median["DC1"]);
  CHECK(median["DC1"] < median["B1"]);
  CHECK(median["DC2"] < 0.5 * median["B1"]);
}

TEST_CASE("over 10 seeds, the transport contexts' medians order as the paper found", "[trainer][medians]") {
  // The paper: the contexts that hand over learned skills and drop the subsumed actions far below
  // the baseline, each faster than the one before, B2 > DC4 > DC5 > DC6. Here DC5 and DC6 are
  // over 75% faster than B2 and DC4 over half (the paper: all three over 90%). DC3 (B2 plus the
  // learned Phi_SG) is not asserted: the paper finds it 16.67% faster than B2, and here it is 33%
  // faster over 50 trials with p = 0.011 (docs/results.md), but over seeds 1-10 its median is
  // above B2's (1543 s against 1345 s): a difference 10 seeds cannot resolve.
  std::map<std::string, double> median, median_episodes;
  for (const char* c : {"B2", "DC3", "DC4", "DC5", "DC6"}) std::tie(median[c], median_episodes[c]) = median_time_to_threshold("T", c);
  INFO("medians: B2 " << median["B2"] << ", DC3 " << median["DC3"] << ", DC4 " << median["DC4"] << ", DC5 " << median["DC5"]
                      << ", DC6 " << median["DC6"] << " simulated s; B2 " << median_episodes["B2"]
                      << ", DC4 " << median_episodes["DC4"] << ", DC5 " << median_episodes["DC5"]
                      << ", DC6 " << median_episodes["DC6"] << " episodes");
  for (const char* c : {"DC5", "DC6"}) CHECK(median[c] < 0.25 * median["B2"]);
  CHECK(median["DC4"] < 0.5 * median["B2"]);
  CHECK(median["DC4"] < median["DC3"]);
  CHECK(median["DC5"] < median["DC4"]);
  // DC6 the lowest, in episodes: DC5 and DC6 both reach the threshold at the first checkpoint
  // (10 episodes), where their simulated seconds differ only by the episodes' lengths, so in this
  // engine the two tie at the measurement's resolution rather than DC6 being clearly faster.
  CHECK(median_episodes["DC6"] <= median_episodes["DC5"]);
  CHECK(median_episodes["DC6"] <= median_episodes["DC4"]);
  CHECK(median_episodes["DC6"] < median_episodes["B2"]);
}

namespace {
// Trains one context of the paper with the evaluation cache on and off and checks that the two
// trials agree bit for bit in everything but wall time, and that the cache did work.
void check_cache_changes_nothing(const std::string& stage, const std::string& context, uint64_t seed) {
  TrainOptions o;
  o.curriculum = "paper";
  o.stage = stage;
  o.context = context;
  o.seed = seed;
  const TrainResult on = train_stage(o);
  o.eval_cache = false;
  const TrainResult off = train_stage(o);
  INFO(stage << "/" << context << " seed " << seed);
  REQUIRE(on.checkpoints.size() == off.checkpoints.size());
  for (size_t i = 0; i < on.checkpoints.size(); ++i) {
    INFO("checkpoint " << i);
    const CheckpointRecord &a = on.checkpoints[i], &b = off.checkpoints[i];
    CHECK(same_bits(a.success_rate, b.success_rate));
    CHECK(same_bits(a.reward_mean, b.reward_mean));
    CHECK(same_bits(a.reward_std, b.reward_std));
    CHECK(a.at.episodes == b.at.episodes);
    CHECK(same_bits(a.at.sim_s, b.at.sim_s));
    CHECK(a.at.decisions == b.at.decisions);
  }
  const GreedyEval &fa = on.final_eval, &fb = off.final_eval;
  CHECK(fa.episodes == fb.episodes);
  CHECK(fa.first_seed == fb.first_seed);
  CHECK(fa.successes == fb.successes);
  CHECK(same_bits(fa.success_rate, fb.success_rate));
  CHECK(same_bits(fa.reward_mean, fb.reward_mean));
  CHECK(same_bits(fa.reward_std, fb.reward_std));
  CHECK(same_bits(fa.time_mean, fb.time_mean));
  CHECK(fa.decisions == fb.decisions);
  REQUIRE(fa.usage.size() == fb.usage.size());
  for (size_t k = 0; k < fa.usage.size(); ++k) CHECK(same_bits(fa.usage[k].second, fb.usage[k].second));
  // Training itself saw the same worlds and made the same choices: skipping an evaluation episode
  // leaves nothing behind that a later training episode could notice.
  CHECK(on.q->to_json().dump() == off.q->to_json().dump());
  CHECK(on.reached == off.reached);
  CHECK(on.to_threshold.episodes == off.to_threshold.episodes);
  CHECK(same_bits(on.totals.sim_s, off.totals.sim_s));
  CHECK(on.evals == off.evals);
  CHECK(on.evals == int(on.checkpoints.size()) + 1);
  CHECK(on.evals_reused > 0);
  CHECK(on.eval_episodes_reused > 0);
  CHECK(off.evals_reused == 0);
  CHECK(off.eval_episodes_reused == 0);
  std::printf("%s/%s seed %llu: %d of %d evaluations reused whole, %d of %d evaluation episodes reused\n",
              stage.c_str(), context.c_str(), static_cast<unsigned long long>(seed), on.evals_reused, on.evals,
              on.eval_episodes_reused, on.eval_episodes);
}
}  // namespace

// The cache's premise: a greedy episode is a function of its world seed and its decisions, so the
// same controllers give the same episode whatever ran before it.
TEST_CASE("a greedy episode does not depend on the episodes before it", "[trainer][cache]") {
  TrainOptions o;
  o.curriculum = "paper";
  o.stage = "SG";
  o.context = "B1";  // phi1 approaches the object: its planner outlives the episodes
  o.seed = 1;
  o.keep_episodes = false;
  const TrainResult trained = train_stage(o);
  QTable q = *trained.q;
  Curriculum cur = Curriculum::load("paper");
  const CurriculumStage& stage = cur.stage("SG");
  const CurriculumContext& ctx = stage.context("B1");
  Scenario scenario = Scenario::load(stage.scenario);
  for (const auto& [k, v] : stage.params) scenario.set_param(k, v);
  Agent agent;
  Rng unused(0);
  // Each seed's episode and the world's final hash, running the seeds in the order given.
  const auto run_all = [&](const std::vector<uint64_t>& seeds) {
    std::map<uint64_t, std::pair<TrainingEpisode, uint64_t>> out;
    for (uint64_t seed : seeds) {
      const TrainingEpisode ep = run_learning_episode(agent, scenario.generate(seed), seed, ctx.actions, *stage.absorbing,
                                                      q, 0.0, unused, stage.rewards, false);
      out[seed] = {ep, agent.world().state_hash()};
    }
    return out;
  };
  std::vector<uint64_t> seeds;
  for (uint64_t s = 0; s < 30; ++s) seeds.push_back(stage.checkpoints.seeds + s);
  const auto forwards = run_all(seeds);
  std::reverse(seeds.begin(), seeds.end());
  const auto backwards = run_all(seeds);
  for (uint64_t seed : seeds) {
    INFO("seed " << seed);
    const TrainingEpisode &a = forwards.at(seed).first, &b = backwards.at(seed).first;
    CHECK(forwards.at(seed).second == backwards.at(seed).second);
    CHECK(a.ticks == b.ticks);
    CHECK(same_bits(a.reward, b.reward));
    CHECK(a.decision_states == b.decision_states);
    CHECK(a.actions_taken == b.actions_taken);
  }
}

TEST_CASE("the evaluation cache changes no result", "[trainer][cache]") {
  check_cache_changes_nothing("SG", "DC2", 5);
  // B1 steers with phi1, whose planner once carried its solution from one episode to the next.
  check_cache_changes_nothing("SG", "B1", 1);
}

TEST_CASE("roger train writes the same files with and without the evaluation cache", "[trainer][cli][cache]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_train_cache_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  for (const char* flag : {"", " --no-eval-cache"}) {
    const auto [status, out] = run_roger("train curricula/paper.lua --stage SG --context DC2 --seed 4 --out " +
                                         (dir / (*flag ? "off" : "on")).string() + flag);
    INFO(out);
    REQUIRE(status == 0);
  }
  // Byte for byte, but for the wall-clock figures.
  const auto without_wall = [](nlohmann::json j) {
    for (const char* k : {"wall_s", "eval_wall_s", "train_wall_s", "wall_to_threshold_s"}) j.erase(k);
    return j.dump();
  };
  const auto lines = [](const std::string& text) {
    std::vector<std::string> v;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) v.push_back(l);
    return v;
  };
  for (const char* f : {"policy.json", "episodes.jsonl"}) CHECK(slurp(dir / "on" / f) == slurp(dir / "off" / f));
  CHECK(without_wall(nlohmann::json::parse(slurp(dir / "on" / "summary.json"))) ==
        without_wall(nlohmann::json::parse(slurp(dir / "off" / "summary.json"))));
  const auto cp_on = lines(slurp(dir / "on" / "checkpoints.jsonl")), cp_off = lines(slurp(dir / "off" / "checkpoints.jsonl"));
  REQUIRE(cp_on.size() == cp_off.size());
  for (size_t i = 0; i < cp_on.size(); ++i)
    CHECK(without_wall(nlohmann::json::parse(cp_on[i])) == without_wall(nlohmann::json::parse(cp_off[i])));
  // curve.csv: episodes,sim_s,decisions,wall_s,success_rate,reward_mean; all but wall_s.
  const auto curve_on = lines(slurp(dir / "on" / "curve.csv")), curve_off = lines(slurp(dir / "off" / "curve.csv"));
  REQUIRE(curve_on.size() == curve_off.size());
  const auto drop_wall = [](const std::string& row) {
    std::vector<std::string> cells;
    std::istringstream in(row);
    for (std::string c; std::getline(in, c, ',');) cells.push_back(c);
    cells.erase(cells.begin() + 3);
    return cells;
  };
  for (size_t i = 0; i < curve_on.size(); ++i) CHECK(drop_wall(curve_on[i]) == drop_wall(curve_off[i]));
  fs::remove_all(dir);
}

TEST_CASE("a trial capped in simulated seconds is the uncapped trial's prefix, skills' training included",
          "[trainer][cap]") {
  TrainOptions o;
  o.curriculum = "paper";
  o.stage = "SG";
  o.context = "B1";
  o.seed = 3;
  const TrainResult whole = train_stage(o);
  o.max_sim_s = 100.0;
  o.final_evaluation = false;
  const TrainResult capped = train_stage(o);
  CHECK(capped.totals.sim_s >= 100.0);
  CHECK(capped.totals.sim_s < 100.0 + 5.0);  // stops at the first episode past the cap
  REQUIRE(capped.episodes.size() < whole.episodes.size());
  for (size_t i = 0; i < capped.episodes.size(); ++i) {
    CHECK(capped.episodes[i].episode.seed == whole.episodes[i].episode.seed);
    CHECK(same_bits(capped.episodes[i].episode.reward, whole.episodes[i].episode.reward));
    CHECK(capped.episodes[i].episode.actions_taken == whole.episodes[i].episode.actions_taken);
  }
  REQUIRE(capped.checkpoints.size() <= whole.checkpoints.size());
  for (size_t i = 0; i < capped.checkpoints.size(); ++i)
    CHECK(same_bits(capped.checkpoints[i].success_rate, whole.checkpoints[i].success_rate));
  CHECK(capped.final_eval.episodes == 0);  // no final evaluation asked

  // T/DC6 trains Phi_SG (SG/DC2) first: the cap covers both.
  TrainOptions t;
  t.curriculum = "paper";
  t.stage = "T";
  t.context = "DC6";
  t.seed = 3;
  t.max_sim_s = 150.0;
  t.final_evaluation = false;
  const TrainResult r = train_stage(t);
  REQUIRE(r.skills.size() == 1);
  const double skill_s = r.skills[0].totals.sim_s;
  INFO("skill " << skill_s << " s, T " << r.totals.sim_s << " s");
  CHECK(skill_s > 0.0);
  CHECK(skill_s + r.totals.sim_s >= 150.0);
  CHECK(skill_s + r.totals.sim_s < 150.0 + 5.0 + 10.0);  // one episode past the cap in each stage
}

// Found by a probe: in a chain (C over Phi_B over Phi_A, trained first), B's stage trained Phi_A
// again inside, under what was left of the cap, uncounted; the cap that ended B was recorded as
// task time, and the task trained on a B that had none. B now trains over the Phi_A just trained.
TEST_CASE("a capped chain of skills trains each once and the cap ends the stage it reaches", "[trainer][cap]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_chain_cap_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "chain.lua")
      << "local p = require('lib.skills').primitives()\n"
         "local function stage(name, actions, skill)\n"
         "  return roger.stage{ name = name, scenario = 'unobstructed', time_limit = 4,\n"
         "    absorbing = roger.converged(p.phi0), budget = { episodes = 30 },\n"
         "    checkpoints = { every = 10, episodes = 5, threshold = 0.9, final = 5 },\n"
         "    contexts = { { name = 'X', actions = actions } }, skill = skill and { name = skill, context = 'X' } }\n"
         "end\n"
         "return { stages = {\n"
         "  stage('A', { p.search, p.phi0 }, 'Phi_A'),\n"
         "  stage('B', { roger.learned('Phi_A'), p.phi0 }, 'Phi_B'),\n"
         "  stage('C', { roger.learned('Phi_B'), p.phi0 }),\n"
         "} }\n";
  TrainOptions o;
  o.curriculum = (dir / "chain.lua").string();
  o.context = "X";
  o.seed = 2;
  o.final_evaluation = false;
  o.stage = "A";
  const double a_s = train_stage(o).totals.sim_s;
  o.stage = "C";
  o.max_sim_s = a_s + 10.0;  // A whole, then 10 s of B's stage
  const TrainResult r = train_stage(o);
  REQUIRE(r.skills.size() == 2);
  CHECK(r.skills[0].name == "Phi_A");
  CHECK(same_bits(r.skills[0].totals.sim_s, a_s));
  CHECK(r.skills[1].name == "Phi_B");
  INFO("Phi_B's stage " << r.skills[1].totals.sim_s << " s, C's " << r.totals.sim_s << " s");
  CHECK(r.skills[1].totals.sim_s >= 10.0);     // the rest of the cap went to B's stage...
  CHECK(r.skills[1].totals.sim_s < 10.0 + 4.0);  // ...stopping at the first episode past it
  CHECK(r.totals.episodes == 0);                 // and C's task never trained
  fs::remove_all(dir);
}

// Found by a probe: a fault in a skill trained first named the trial's own stage and phase, and
// roger train kept the skill's curve in the trial's folder as the trial's own progress.
TEST_CASE("a fault in a skill trained first names that skill's stage and keeps nothing as the trial's",
          "[trainer][errors]") {
  test::TempDir dir("roger_first_fault");
  std::ofstream(dir.path / "chain.lua")
      << "local p = require('lib.skills').primitives()\n"
         "local calls = 0\n"
         "local function reward(state, action, event)\n"
         "  calls = calls + 1\n"
         "  if calls == 40 then error('boom') end\n"
         "  return 0\n"
         "end\n"
         "return { stages = {\n"
         "  roger.stage{ name = 'A', scenario = 'unobstructed', time_limit = 4, reward = reward,\n"
         "    absorbing = roger.converged(p.phi0), budget = { episodes = 30 },\n"
         "    checkpoints = { every = 10, episodes = 5, threshold = 0.9, final = 5 },\n"
         "    contexts = { { name = 'X', actions = { p.search, p.phi0 } } }, skill = { name = 'Phi_A', context = 'X' } },\n"
         "  roger.stage{ name = 'B', scenario = 'unobstructed', time_limit = 4,\n"
         "    absorbing = roger.converged(p.phi0), budget = { episodes = 30 },\n"
         "    checkpoints = { every = 10, episodes = 5, threshold = 0.9, final = 5 },\n"
         "    contexts = { { name = 'Y', actions = { roger.learned('Phi_A'), p.phi0 } } } },\n"
         "} }\n";
  const fs::path out = dir.path / "out";
  const auto [status, said] = run_roger("train " + (dir.path / "chain.lua").string() +
                                        " --stage B --context Y --out " + out.string());
  CHECK(status == 1);
  CHECK_THAT(said, Contains("chain.lua:5: stage 'A', context 'X': reward function: ") && Contains("boom") &&
                       Contains("(stage 'B', context 'Y', in training its skill 'Phi_A' first: stage 'A', context 'X', "));
  CHECK_THAT(said, !Contains("kept"));
  CHECK(!fs::exists(out));
}

namespace {

// A stage of tests/scripts/explain_curriculum.lua (built to fail), trained for seed 1.
TrainResult train_fixture(const std::string& stage) {
  TrainOptions o;
  o.curriculum = "tests/scripts/explain_curriculum.lua";
  o.stage = stage;
  o.context = "A";
  o.seed = 1;
  return train_stage(o);
}

}  // namespace

// Found by a new user: a report's cause held a cycle of about sixty transitions on one line.
TEST_CASE("a long greedy cycle is told by its first decisions, its last and how many lie between",
          "[trainer][explain]") {
  TrainingDiagnosis d;
  d.psi = {"a", "b"};
  d.final_episodes = 10;
  d.cycle_episodes = 1;
  for (int k = 0; k < 60; ++k) d.cycle.states.push_back(k % 9), d.cycle.actions.push_back(k % 2);
  d.cycle.turns = 2;
  const std::string text = d.cycle_cause();
  CHECK(text.rfind("greedy cycle of 60 decisions: (a=NOREF b=NOREF) -> a -> (a=NOREF b=!CONV) -> b -> ", 0) == 0);
  CHECK_THAT(text, Catch::Contains(" -> b -> ... 55 more decisions ... -> (a=!CONV b=CONV) -> b -> back, repeating "
                                   "without reaching the absorbing state in 1 of 10 final greedy episodes (up to 2 turns)"));
  CHECK(std::count(text.begin(), text.end(), '(') == 6);  // five states and the turns
  d.cycle.states.resize(6), d.cycle.actions.resize(6);  // six are told in full
  CHECK(d.cycle_cause().rfind("greedy cycle: (", 0) == 0);
  CHECK(d.cycle_cause().find("more decisions") == std::string::npos);
}

TEST_CASE("a livelocked stage is explained by its greedy cycle", "[trainer][explain]") {
  // Arrivals pay and nothing absorbs: the greedy policy shuttles between the two regions.
  const TrainResult r = train_fixture("livelock");
  REQUIRE_FALSE(r.reached);
  const TrainingDiagnosis d = diagnose_training(r);
  REQUIRE(d.cycle.turns >= 3);
  CHECK(d.cycle_episodes == d.final_episodes);
  CHECK(d.final_timeouts == d.final_episodes);
  std::vector<std::string> actions;
  for (int a : d.cycle.actions) actions.push_back(r.psi[size_t(a)]);
  std::sort(actions.begin(), actions.end());
  CHECK(actions == std::vector<std::string>{"go0", "go1"});
  for (int s : d.cycle.states) CHECK(d.state_text(s).find("nowhere=NOREF") != std::string::npos);
  CHECK(d.never_referenced == std::vector<int>{2});  // nowhere: its region does not exist
  CHECK(d.stuck.empty());
  CHECK(d.train_timeouts == d.train_episodes);
  const std::vector<std::string> causes = d.causes();
  REQUIRE_FALSE(causes.empty());
  CHECK(causes.front().rfind("greedy cycle: (", 0) == 0);
  // result.json and summary.json carry the same, because the threshold was not reached.
  const nlohmann::json j = train_summary_json(r);
  REQUIRE(j.contains("diagnosis"));
  CHECK(j["diagnosis"]["cycle"]["actions"].size() == 2);
  CHECK(j["diagnosis"]["never_referenced"] == nlohmann::json::array({"nowhere"}));
  CHECK(j["diagnosis"]["timeouts"]["final"] == 1.0);
}

TEST_CASE("every greedy cycle the failed final episodes ended in is counted", "[trainer][explain]") {
  // A final evaluation of 7 episodes, built by hand: 2 end in one cycle, 3 in three others, one in
  // a state never left, and one succeeds. With many actions (sorting) a policy's failures end in
  // several cycles, and naming only the most frequent left most of them unexplained.
  TrainResult r;
  r.psi = {"a", "b", "c"};
  const auto episode = [](std::vector<int> states, std::vector<int> actions, bool success) {
    TrainingEpisode ep;
    ep.decision_states = std::move(states);
    ep.actions_taken = std::move(actions);
    ep.success = success;
    return ep;
  };
  r.final_eval.runs = {episode({1, 2, 1, 2, 1, 2}, {0, 1, 0, 1, 0, 1}, false),
                       episode({5, 1, 2, 1, 2}, {2, 0, 1, 0, 1}, false),
                       episode({3, 3, 3}, {2, 2, 2}, false),
                       episode({4, 4}, {1, 1}, false),
                       episode({5, 6, 6, 6}, {0, 2, 2, 2}, false),
                       episode({7}, {0}, false),
                       episode({1, 8}, {0, 2}, true)};
  const TrainingDiagnosis d = diagnose_training(r);
  CHECK(d.final_episodes == 7);
  CHECK(d.final_timeouts == 6);
  REQUIRE(d.cycles.size() == 4);
  CHECK(d.cycle_episodes == 2);
  CHECK(d.cycles[0].episodes == 2);
  CHECK(d.cycles[0].cycle.actions == d.cycle.actions);
  int accounted = 0;
  for (const auto& c : d.cycles) accounted += c.episodes;
  for (const auto& s : d.stuck) accounted += s.episodes;
  CHECK(accounted == d.final_timeouts);  // every time-out has its cause
  const std::vector<std::string> causes = d.causes();
  REQUIRE(causes.size() >= 5);
  CHECK(causes[0].rfind("greedy cycle: (", 0) == 0);
  CHECK(causes[0].find("in 2 of 7 final greedy episodes") != std::string::npos);
  CHECK(causes[1].rfind("another greedy cycle: (", 0) == 0);
  CHECK(causes[2].rfind("another greedy cycle: (", 0) == 0);
  CHECK(causes[3] == "1 more of the final greedy episodes ended in 1 other greedy cycle");
  CHECK(causes[4].rfind("state never left: (", 0) == 0);
  const nlohmann::json j = d.to_json();
  REQUIRE(j["cycles"].size() == 4);
  CHECK(j["cycles"][0] == j["cycle"]);
  CHECK(j["cycles"][3]["episodes"] == 1);
}

TEST_CASE("a stage that never runs the action it needs is explained", "[trainer][explain]") {
  // Only referenced actions are chosen, and the one the absorbing state needs is NOREF throughout.
  const TrainResult r = train_fixture("unused");
  REQUIRE_FALSE(r.reached);
  const TrainingDiagnosis d = diagnose_training(r);
  CHECK(d.cycle.turns == 0);
  CHECK(d.never_tried == std::vector<int>{1});
  CHECK(d.never_chosen == std::vector<int>{1});
  CHECK(d.never_referenced == std::vector<int>{1});
  REQUIRE(d.stuck.size() == 1);
  CHECK(d.state_text(d.stuck[0].state) == "go0=CONV nowhere=NOREF");
  CHECK(r.psi[size_t(d.stuck[0].action)] == "go0");
  CHECK(d.stuck[0].episodes == d.final_episodes);
  const std::vector<std::string> causes = d.causes();
  REQUIRE(causes.size() >= 3);
  CHECK(causes[0] == "state never left: (go0=CONV nowhere=NOREF), where go0 ran until the time-out in 2 of 2 final "
                     "greedy episodes");
  CHECK(causes[1] == "never able to run: nowhere (NOREF at every decision)");
  CHECK(causes[2] == "never chosen in training: nowhere");
  // Every episode timed out: the time-outs are said as the absorbing state never reached.
  CHECK(causes.back() == "absorbing state never reached: every one of the " + std::to_string(d.train_episodes) +
                             " training episodes and the 2 final ones timed out, so no reward from it was ever learned");
}

// Found by a probe: a Lua absorbing function comparing a region name written otherwise than the
// world's ("Goal" for "goal") never held, and the causes named only cycles and time-outs.
TEST_CASE("a stage whose Lua absorbing function never held says so", "[trainer][explain]") {
  TrainingDiagnosis d;
  d.psi = {"a"};
  d.train_episodes = d.train_timeouts = 40;
  d.final_episodes = d.final_timeouts = 5;
  d.absorbing_lua = true;
  CHECK(d.causes() == std::vector<std::string>{
                          "absorbing state never reached: the stage's Lua absorbing function returned true in none "
                          "of the 40 training episodes and the 5 final ones (what it compares, such as a name or a "
                          "region written otherwise than the world's, may never match)"});
  d.train_timeouts = 39;  // one reached it: the time-outs are told as such
  CHECK(d.causes() == std::vector<std::string>{
                          "time-outs: 98% of the training episodes (0% of the last quarter), 100% of the final evaluation"});
}

TEST_CASE("roger train says why it missed the threshold, and --explain why it reached it", "[trainer][explain][cli]") {
  const fs::path out = fs::temp_directory_path() / ("roger_explain_" + std::to_string(::getpid()));
  const auto [status, text] = run_roger("train tests/scripts/explain_curriculum.lua --stage livelock --context A --out " +
                                        out.string());
  CHECK(status == 0);
  CHECK(text.find("  why            greedy cycle: (go0=") != std::string::npos);
  CHECK(text.find("never able to run: nowhere") != std::string::npos);
  CHECK(nlohmann::json::parse(slurp(out / "summary.json")).contains("diagnosis"));
  // A stage that reaches its threshold says why only when asked.
  const auto [quiet_status, quiet] = run_roger("train curricula/paper.lua --stage SG --context DC2 --seed 1 --out " +
                                               out.string());
  CHECK(quiet_status == 0);
  CHECK(quiet.find("why ") == std::string::npos);
  CHECK_FALSE(nlohmann::json::parse(slurp(out / "summary.json")).contains("diagnosis"));
  const auto [asked_status, asked] = run_roger("train curricula/paper.lua --stage SG --context DC2 --seed 1 --explain --out " +
                                               out.string());
  CHECK(asked_status == 0);
  CHECK(asked.find("  why ") != std::string::npos);
  CHECK(nlohmann::json::parse(slurp(out / "summary.json")).contains("diagnosis"));
  fs::remove_all(out);
}

// Found by a probe: a stage whose absorbing state held at the first tick "reached 90% after 3
// episodes, 0 decisions" with 100% success, and --explain said its actions were never able to run.
TEST_CASE("roger train warns of episodes that ended before their first decision", "[trainer][explain][cli]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_at_start_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "always.lua") << "local p = require('lib.skills').primitives()\n"
                                       "return { stages = { roger.stage{ name = 'S', scenario = 'unobstructed',\n"
                                       "  time_limit = 4, absorbing = function(s) return true end, budget = { episodes = 6 },\n"
                                       "  checkpoints = { every = 3, episodes = 3, final = 3 },\n"
                                       "  contexts = { { name = 'C', actions = { p.search, p.phi0 } } } } } }\n";
  const auto [status, text] = run_roger("train " + (dir / "always.lua").string() + " --stage S --context C --json --out " +
                                        (dir / "out").string());
  INFO(text);
  CHECK(status == 0);
  CHECK(text.find("  warning        9 of 9 episodes (training and final) ended in the absorbing state at their "
                  "start (before their first decision, or at the first tick, when the goal is first judged): the goal "
                  "held in their worlds from the start") != std::string::npos);
  // So does a predicate that holds at the first tick (found by a probe: 100% without a word).
  std::ofstream(dir / "negated.lua") << "local p = require('lib.skills').primitives()\n"
                                        "return { stages = { roger.stage{ name = 'S', scenario = 'unobstructed',\n"
                                        "  time_limit = 4, absorbing = roger.negate(roger.converged(p.phi3)),\n"
                                        "  budget = { episodes = 6 }, checkpoints = { every = 3, episodes = 3, final = 3 },\n"
                                        "  contexts = { { name = 'C', actions = { p.search, p.phi0 } } } } } }\n";
  const auto [negated_status, negated] = run_roger("train " + (dir / "negated.lua").string() +
                                                   " --stage S --context C --out " + (dir / "negated").string());
  INFO(negated);
  CHECK(negated_status == 0);
  CHECK(negated.find("  warning        ") != std::string::npos);
  CHECK(negated.find("ended in the absorbing state at their start") != std::string::npos);
  // Its Lua absorbing function keeps the evaluation cache off, and the cache's line says why (found
  // by a probe: "0 of 3 reused" and no word).
  CHECK(text.find(" reused (none: the stage's Lua reward or absorbing function may keep state between calls)\n") !=
        std::string::npos);
  const auto [explained_status, explained] = run_roger("train " + (dir / "always.lua").string() +
                                                       " --stage S --context C --explain --out " + (dir / "out").string());
  CHECK(explained_status == 0);
  CHECK(explained.find("  why            9 of 9 episodes") != std::string::npos);
  CHECK(explained.find("never able to run") == std::string::npos);
  CHECK(nlohmann::json::parse(slurp(dir / "out" / "summary.json"))["diagnosis"]["ended_before_deciding"] == 9);
  // And roger eval of the policy says so too (found by a probe: 100%, 0.00 s, no word).
  const auto [eval_status, evaluated] = run_roger("eval " + (dir / "always.lua").string() + " --policy " +
                                                  (dir / "out" / "policy.json").string() + " --episodes 3 --json");
  CHECK(eval_status == 0);
  CHECK(evaluated.find("  warning        3 of 3 episodes succeeded at the first tick, when the goal is first judged") !=
        std::string::npos);
  CHECK(nlohmann::json::parse(evaluated.substr(evaluated.rfind("\n{") + 1))["succeeded_at_first_tick"] == 3);
  fs::remove_all(dir);
}

TEST_CASE("checkpoints that passed and then failed are named", "[trainer][explain]") {
  TrainResult r;
  r.psi = {"a", "b"};
  r.threshold = 0.9;
  const double rates[] = {0.5, 0.95, 0.6, 0.95, 1.0};
  for (int k = 0; k < 5; ++k) {
    CheckpointRecord c;
    c.at.episodes = 20 * (k + 1);
    c.success_rate = rates[k];
    c.policy_changed = true;
    r.checkpoints.push_back(c);
  }
  const TrainingDiagnosis d = diagnose_training(r);
  REQUIRE(d.drops.size() == 1);
  CHECK(d.drops[0].passed == 2);
  CHECK(d.drops[0].failed == 3);
  CHECK(d.causes() == std::vector<std::string>{
                          "checkpoint 2 passed (95%) and checkpoint 3 failed (60%, after 60 episodes: the greedy "
                          "policy changed)"});
  // Without episodes (none kept), nothing is claimed about actions or time-outs.
  CHECK(d.never_tried.empty());
  CHECK(d.never_referenced.empty());
  CHECK(d.train_episodes == 0);
}
