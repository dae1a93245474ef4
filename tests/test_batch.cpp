// Tests of engine/batch: parallel, resumable trials with atomic results.
#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <regex>
#include <set>
#include <sstream>
#include <thread>

#include "batch/batch.h"
#include "batch/batch_internal.h"
#include "core/error.h"
#include "core/rng.h"
#include "core/text.h"
#include "report/report.h"
#include "script/scenario/scenario.h"
#include "test_files.h"

using namespace roger;
namespace fs = std::filesystem;
using roger::test::slurp;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("roger_batch_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  return p;
}

// A deterministic "trial": some work that depends only on the id.
nlohmann::json work(const std::string& id, const std::string& dir) {
  uint64_t h = 1469598103934665603ull;
  for (char c : id) h = (h ^ uint8_t(c)) * 1099511628211ull;
  Rng rng(h);
  double sum = 0.0;
  for (int i = 0; i < 20000; ++i) sum += rng.uniform();
  std::ofstream(fs::path(dir) / "notes.txt") << id << "\n";
  return {{"id", id}, {"sum", sum}};
}

std::vector<std::string> ids(int n) {
  std::vector<std::string> v;
  for (int i = 0; i < n; ++i) v.push_back("SG/B1/seed-" + std::to_string(i));
  return v;
}

}  // namespace

// Found by a probe: the refusal of a trial id named one byte of a UTF-8 character ('\xc3').
TEST_CASE("a trial id that cannot name a folder is refused naming its whole character", "[batch]") {
  const fs::path d = fresh_dir("bad_ids");
  CHECK_THROWS_WITH(run_trials({"R/\xc3\x9cni/000"}, work, BatchOptions{1, d.string()}),
                    "batch: trial id 'R/\xc3\x9cni/000' has the character '\xc3\x9c'; use letters, digits, '.', '_', '-' "
                    "and '/'");
  CHECK_THROWS_WITH(run_trials({"R/a<b/000"}, work, BatchOptions{1, d.string()}),
                    Catch::Matchers::Contains("has the character '<'"));
  CHECK_THROWS_WITH(run_trials({"R/../000"}, work, BatchOptions{1, d.string()}),
                    Catch::Matchers::Contains("has an empty, '.' or '..' segment"));
}

TEST_CASE("trials run in parallel and results do not depend on the number of jobs", "[batch]") {
  const fs::path a = fresh_dir("jobs1"), b = fresh_dir("jobs2");
  const auto one = run_trials(ids(12), work, BatchOptions{1, a.string()});
  const auto two = run_trials(ids(12), work, BatchOptions{2, b.string()});
  REQUIRE(one.size() == 12);
  for (size_t i = 0; i < one.size(); ++i) {
    CHECK(one[i].id == ids(12)[i]);
    CHECK(one[i].ok);
    CHECK_FALSE(one[i].resumed);
    CHECK(one[i].result == two[i].result);
    // The committed files are identical too.
    std::ifstream fa(fs::path(trial_dir(a.string(), one[i].id)) / "result.json");
    std::ifstream fb(fs::path(trial_dir(b.string(), two[i].id)) / "result.json");
    std::stringstream sa, sb;
    sa << fa.rdbuf();
    sb << fb.rdbuf();
    CHECK(sa.str() == sb.str());
    CHECK(fs::exists(fs::path(trial_dir(a.string(), one[i].id)) / "notes.txt"));
  }
  fs::remove_all(a);
  fs::remove_all(b);
}

TEST_CASE("an interrupted batch resumes without losing or repeating a trial", "[batch]") {
  const fs::path dir = fresh_dir("resume");
  const auto all = ids(10);
  // A first run that finishes only some trials...
  std::vector<std::string> first(all.begin(), all.begin() + 6);
  run_trials(first, work, BatchOptions{2, dir.string()});
  // ...and one cut short: its folder has files but no result.
  const std::string cut = trial_dir(dir.string(), all[7]);
  fs::create_directories(cut);
  std::ofstream(fs::path(cut) / "half-written.tmp") << "partial";
  std::atomic<int> calls{0};
  std::set<std::string> ran;
  std::mutex m;
  const auto out = run_trials(all, [&](const std::string& id, const std::string& d) {
    ++calls;
    std::lock_guard<std::mutex> lock(m);
    ran.insert(id);
    return work(id, d);
  }, BatchOptions{2, dir.string()});
  CHECK(calls == 4);  // exactly the four unfinished trials
  for (int i = 0; i < 6; ++i) CHECK(ran.count(all[size_t(i)]) == 0);
  CHECK_FALSE(fs::exists(fs::path(cut) / "half-written.tmp"));  // started afresh
  // And the results equal an uninterrupted run's.
  const fs::path clean = fresh_dir("clean");
  const auto reference = run_trials(all, work, BatchOptions{1, clean.string()});
  for (size_t i = 0; i < all.size(); ++i) {
    CHECK(out[i].result == reference[i].result);
    CHECK(out[i].resumed == (i < 6));
  }
  fs::remove_all(dir);
  fs::remove_all(clean);
}

TEST_CASE("a file error of the machine stops the trials and fails none of them", "[batch][faults]") {
  // The sixth trial meets a full disk: no trial is recorded as failed (no error.json, not even the
  // sixth's), none starts after it, and run_trials rethrows it; the same call resumes the rest.
  const fs::path dir = fresh_dir("disk_full");
  const auto all = ids(10);
  std::atomic<int> calls{0};
  const auto full_at_sixth = [&](const std::string& id, const std::string& d) {
    if (++calls == 6) throw FileError("cannot write the policy file '" + d + "/policy.json': No space left on device",
                                      d + "/policy.json", ENOSPC);
    return work(id, d);
  };
  try {
    run_trials(all, full_at_sixth, BatchOptions{1, dir.string()});
    FAIL("no FileError");
  } catch (const FileError& e) {
    CHECK(e.error_number == ENOSPC);
    CHECK(std::string(e.what()).find("policy.json") != std::string::npos);
  }
  CHECK(calls == 6);
  int finished = 0;
  for (const auto& id : all) {
    CHECK_FALSE(fs::exists(fs::path(trial_dir(dir.string(), id)) / "error.json"));
    finished += fs::exists(fs::path(trial_dir(dir.string(), id)) / "result.json");
  }
  CHECK(finished == 5);
  CHECK_FALSE(fs::exists(trial_dir(dir.string(), all[5])));  // its partial files removed
  const auto out = run_trials(all, full_at_sixth, BatchOptions{2, dir.string()});
  CHECK(calls == 11);  // the five left, once each
  for (size_t i = 0; i < all.size(); ++i) {
    CHECK(out[i].ok);
    CHECK(out[i].resumed == (i < 5));
  }
  fs::remove_all(dir);
}

TEST_CASE("a run notices a script of its curriculum removed or edited under it", "[batch][faults]") {
  const fs::path dir = fresh_dir("source_watch");
  fs::create_directories(dir);
  const fs::path curriculum = dir / "kill_curriculum.lua";
  fs::copy_file("tests/scripts/kill_curriculum.lua", curriculum);
  const batch_detail::SourceWatch watch(curriculum.string());
  CHECK_NOTHROW(watch.check());
  std::ofstream(curriculum, std::ios::app) << "-- edited\n";
  try {
    watch.check();
    FAIL("an edited curriculum went unnoticed");
  } catch (const FileError& e) {
    CHECK(e.error_number == 0);
    CHECK(std::string(e.what()) == "'" + curriculum.string() + "' changed while the run was using it");
  }
  fs::remove(curriculum);
  try {
    watch.check();
    FAIL("a removed curriculum went unnoticed");
  } catch (const FileError& e) {
    CHECK(e.error_number == ENOENT);
    CHECK(std::string(e.what()) == "cannot read '" + curriculum.string() + "': it was removed while the run was using it");
  }
  fs::remove_all(dir);
}

// Found by a probe: a module required inside a reward function (not when the curriculum loads) was
// in no list of the run's sources, so a resumed run mixed the trials of two versions of it.
TEST_CASE("a module a callback requires while trials run is recorded, watched and compared on resuming",
          "[batch][faults]") {
  const fs::path dir = fresh_dir("lazy_require");
  fs::create_directories(dir);
  std::ofstream(dir / "lazy_reward.lua") << "return { reward = function(state, action, event) "
                                            "return event == 'absorbing' and 100 or -1 end }\n";
  std::ofstream(dir / "lazy.lua")
      << "local p = require('lib.skills').primitives()\n"
         "return { name = 'lazy', stages = { roger.stage{ name = 'S', scenario = 'unobstructed', time_limit = 4,\n"
         "  absorbing = roger.converged(p.phi0),\n"
         "  reward = function(...) return require('lazy_reward').reward(...) end,\n"
         "  budget = { episodes = 4 }, checkpoints = { every = 4, episodes = 2, final = 2, threshold = 0.9 },\n"
         "  contexts = { { name = 'A', actions = { p.search, p.phi0 } } } } } }\n";
  std::ofstream(dir / "lazy_batch.lua") << "return { name = 'lazy', curriculum = 'lazy.lua', trials = 1, "
                                           "runs = { { name = 'S', stage = 'S' } } }\n";
  const fs::path out = dir / "out";
  const auto open = [&] {
    const auto b = std::make_shared<const BatchScript>(load_batch_script((dir / "lazy_batch.lua").string()));
    const BatchPlan plan = plan_batch(b, out.string());
    open_results_folder(plan);
    return plan;
  };
  RunControl control;
  control.jobs = 1;
  REQUIRE(run_batch(open(), control).failed.empty());
  const std::string module = fs::weakly_canonical(dir / "lazy_reward.lua").string();
  const nlohmann::json result = nlohmann::json::parse(slurp(out / "trials" / "S" / "A" / "000" / "result.json"));
  REQUIRE(result["sources"].contains(module));
  CHECK_FALSE(nlohmann::json::parse(slurp(out / "manifest.json"))["config"]["sources"].contains(module));
  // The run watches it from the trial that required it on.
  batch_detail::SourceWatch watch((dir / "lazy.lua").string());
  watch.learn(result["sources"]);
  CHECK_NOTHROW(watch.check());
  const std::string text = slurp(dir / "lazy_reward.lua");
  std::ofstream(dir / "lazy_reward.lua") << text << "-- edited\n";
  CHECK_THROWS_WITH(watch.check(), "'" + module + "' changed while the run was using it");
  // A resumed run is refused, naming the trial and the file; with the file as it was, it resumes.
  CHECK_THROWS_WITH(open(), "the results folder " + out.string() + " cannot be resumed: trial S/A/000 required " +
                                module + " while it ran (a require inside a function the episodes call, which the "
                                "list of sources made when the run started could not hold), and it has changed since: "
                                "resuming would mix two versions of it in one folder. Put the file back as it was, "
                                "or use another --out.");
  std::ofstream(dir / "lazy_reward.lua") << text;
  CHECK_NOTHROW(open());
  fs::remove(dir / "lazy_reward.lua");
  CHECK_THROWS_WITH(open(), Catch::Matchers::Contains("required " + module) && Catch::Matchers::Contains("and it is gone"));
  fs::remove_all(dir);
}

TEST_CASE("a failing trial is recorded and does not lose the others", "[batch]") {
  const fs::path dir = fresh_dir("fail");
  const auto out = run_trials(ids(5), [](const std::string& id, const std::string& d) -> nlohmann::json {
    if (id == "SG/B1/seed-2") throw Error("curricula/x.lua:7: the reward is not a number");
    return work(id, d);
  }, BatchOptions{2, dir.string()});
  int ok = 0;
  for (const auto& o : out) ok += o.ok;
  CHECK(ok == 4);
  CHECK_FALSE(out[2].ok);
  CHECK(out[2].result["error"].get<std::string>().find("x.lua:7") != std::string::npos);
  CHECK(fs::exists(fs::path(trial_dir(dir.string(), "SG/B1/seed-2")) / "error.json"));
  // Resuming does not run it again: the error is the trial's result.
  int calls = 0;
  run_trials(ids(5), [&](const std::string& id, const std::string& d) { ++calls; return work(id, d); },
             BatchOptions{1, dir.string()});
  CHECK(calls == 0);
  fs::remove_all(dir);
}

TEST_CASE("bad trial ids are refused", "[batch]") {
  const fs::path dir = fresh_dir("bad");
  CHECK_THROWS_WITH(run_trials({"a", "a"}, work, BatchOptions{1, dir.string()}), Catch::Contains("twice"));
  CHECK_THROWS_WITH(run_trials({"../x"}, work, BatchOptions{1, dir.string()}), Catch::Contains(".."));
  CHECK_THROWS_WITH(run_trials({"a b"}, work, BatchOptions{1, dir.string()}), Catch::Contains("character"));
  CHECK_THROWS_WITH(run_trials({"a"}, work, BatchOptions{1, ""}), Catch::Contains("folder"));
  fs::remove_all(dir);
}

TEST_CASE("progress lines count trials done, running and left", "[batch]") {
  const fs::path dir = fresh_dir("progress");
  std::ostringstream progress;
  BatchOptions options{2, dir.string()};
  options.progress = &progress;
  options.every = 0.01;
  run_trials(ids(6), work, options);
  const std::string text = progress.str();
  CHECK(text.find("trials: 6/6 done") != std::string::npos);
  CHECK(text.find("left") != std::string::npos);
  CHECK(format_duration(42) == "42 s");
  CHECK(format_duration(185) == "3 min 05 s");
  CHECK(format_duration(3720) == "1 h 02 min");
  fs::remove_all(dir);
}

// The time left counts what the running trial has done: one worker, three trials of a second
// each; while the second runs, the estimate falls from 2 s towards 1 s. (It divided the time
// elapsed by the trials done and counted the running trial whole: 2 s and more all along.)
TEST_CASE("the time left counts the part of a running trial already run", "[batch]") {
  const fs::path dir = fresh_dir("time_left");
  std::ostringstream progress;
  BatchOptions options{1, dir.string()};
  options.progress = &progress;
  options.every = 0.05;
  const auto second = [](const std::string& id, const std::string&) {
    std::this_thread::sleep_for(std::chrono::seconds(1));
    return nlohmann::json{{"id", id}};
  };
  run_trials(ids(3), second, options);
  std::set<std::string> estimates;  // while one of three was done
  std::istringstream lines(progress.str());
  for (std::string line; std::getline(lines, line);) {
    static const std::regex one_done("trials: 1/3 done.*about (\\d+ s) to go");
    std::smatch m;
    if (std::regex_search(line, m, one_done)) estimates.insert(m[1]);
  }
  INFO(progress.str());
  CHECK(estimates.count("1 s") == 1);
  CHECK(estimates.size() <= 2);  // 1 s and 2 s at most
  CHECK(!estimates.count("3 s"));
  fs::remove_all(dir);
}

namespace {

// Runs a shell command line (from the repository root, as CTest does); returns its exit status
// and, in `err`, what it printed on standard error.
int shell(const std::string& line, std::string* err = nullptr) {
  const fs::path log = fresh_dir("shell_log");
  const int raw = std::system((line + " 2>" + log.string()).c_str());
  if (err) {
    std::ifstream in(log);
    std::stringstream ss;
    ss << in.rdbuf();
    *err = ss.str();
  }
  fs::remove(log);
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

}  // namespace

TEST_CASE("parse_shard reads K/N and a Slurm array's task, and refuses anything else", "[batch][shard]") {
  const Shard s = parse_shard("2/5");
  CHECK(s.index == 2);
  CHECK(s.count == 5);
  for (const char* bad : {"5/5", "-1/3", "1/0", "1", "a/b", "1/3x", "", " 1/3", "1/+3", "+1/3", "1/ 3"})
    CHECK_THROWS_WITH(parse_shard(bad), Catch::Contains("K/N"));
  unsetenv("ROGER_SHARDS");
  unsetenv("SLURM_ARRAY_TASK_ID");
  unsetenv("SLURM_ARRAY_TASK_COUNT");
  CHECK_THROWS_WITH(parse_shard("slurm"), Catch::Contains("SLURM_ARRAY_TASK_ID"));
  setenv("SLURM_ARRAY_TASK_ID", "1", 1);
  setenv("SLURM_ARRAY_TASK_COUNT", "3", 1);
  CHECK(parse_shard("slurm").index == 1);
  CHECK(parse_shard("slurm").count == 3);
  // A single task resubmitted (--array=2) is an array of one: ROGER_SHARDS keeps the run's N.
  setenv("SLURM_ARRAY_TASK_ID", "2", 1);
  setenv("SLURM_ARRAY_TASK_COUNT", "1", 1);
  CHECK_THROWS_WITH(parse_shard("slurm"), Catch::Contains("ROGER_SHARDS"));
  setenv("ROGER_SHARDS", "3", 1);
  CHECK(parse_shard("slurm").index == 2);
  CHECK(parse_shard("slurm").count == 3);
  unsetenv("ROGER_SHARDS");
  unsetenv("SLURM_ARRAY_TASK_ID");
  unsetenv("SLURM_ARRAY_TASK_COUNT");
}

TEST_CASE("shards of one script run at once into one folder and report what one run reports", "[batch][shard]") {
  const fs::path out = fresh_dir("shards");
  const std::string run = std::string(ROGER_BINARY) + " run scripts/quick.lua --jobs 1 --out " + out.string();
  // Three shards at once; shard 1 stops after its search-grasp trials, as if its node had died.
  const std::string all = "(" + run + " --shard 0/3 >/dev/null 2>&1 & " + run + " --shard 1/3 --only SG >/dev/null 2>&1 & " +
                          run + " --shard 2/3 >/dev/null 2>&1 & wait)";
  REQUIRE(shell(all) == 0);
  CHECK(fs::exists(out / "shards" / "0-of-3.json"));
  CHECK_FALSE(fs::exists(out / "summary.csv"));  // shards write no shared file but the manifest
  CHECK_FALSE(fs::exists(out / "tables.md"));
  // The dashboard's status: shard 1's T trials are still to come, so the run waits for a shard,
  // not for its report, and is not over.
  const auto status = [&] { return nlohmann::json::parse(slurp(out / "status.json")); };
  CHECK(status()["running"] == false);
  CHECK(status()["finishing"] == false);
  CHECK(status()["waiting"] == "shards");
  // Each shard's state, from its record: shard 1 ended with its T trials not run (--only), shard 2
  // owns no trial of quick.lua (trials 0 and 1 only).
  const auto shard_entry = [&](int k) { return status()["shards"][size_t(k)]; };
  REQUIRE(status()["shards"].size() == 3);
  CHECK(shard_entry(0) == nlohmann::json{{"state", "ended"}, {"pending", 0}, {"trials", 12}});
  CHECK(shard_entry(1)["state"] == "ended");
  CHECK(shard_entry(1)["pending"].get<int>() > 0);
  CHECK(shard_entry(2) == nlohmann::json{{"state", "ended"}, {"pending", 0}, {"trials", 0}});
  CHECK(status()["slurm"] == false);

  // The report names what is missing and who owns it, and writes nothing.
  std::string err;
  CHECK(shell(std::string(ROGER_BINARY) + " report " + out.string() + " >/dev/null", &err) == 1);
  INFO(err);
  CHECK(err.find("T/B2/001 (run T, context B2, trial 1; shard 1 of 3)") != std::string::npos);
  CHECK(err.find("eval/generalization/spade/001") != std::string::npos);
  CHECK(err.find("T/B2/000") == std::string::npos);
  CHECK_FALSE(fs::exists(out / "tables.md"));
  CHECK_FALSE(fs::exists(out / "summary.csv"));
  // A partial report leaves the status to the trials still to come: the page keeps waiting.
  REQUIRE(shell(std::string(ROGER_BINARY) + " report --partial " + out.string() + " >/dev/null 2>&1") == 0);
  CHECK(status()["waiting"] == "shards");
  CHECK_FALSE(status().contains("report"));

  // The shard resumes with its command; then the report equals an unsharded run's (kept in
  // tests/golden/quick, made by one roger run of the same script).
  REQUIRE(shell(run + " --shard 1/3 >/dev/null") == 0);
  CHECK(status()["waiting"] == "report");  // every trial is over: the run waits for roger report
  CHECK(shard_entry(1) == nlohmann::json{{"state", "ended"}, {"pending", 0}, {"trials", 12}});
  REQUIRE(shell(std::string(ROGER_BINARY) + " report " + out.string() + " >/dev/null", &err) == 0);
  // roger report closes the run's status, as roger run does after its report: the page shows it.
  CHECK(status()["report"] == "written");
  CHECK_FALSE(status().contains("waiting"));
  const int same = shell("bash tests/tools/compare_results.sh --golden tests/golden/quick " + out.string() + " 1>&2", &err);
  INFO(err);
  CHECK(same == 0);
  fs::remove_all(out);
}

// Found by a probe: a second `roger run` of a folder in use said "resuming" and emptied the first's
// trials in flight to run them again; the first then failed writing into them ("A folder on that
// path does not exist") or recorded trials as failed for a policy "not run yet".
TEST_CASE("a results folder in use by a run is refused to a second run, parts of it sharing it", "[batch][shard]") {
  const fs::path out = fresh_dir("claim");
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  const std::string pid = " (pid " + std::to_string(::getpid()) + " on " + host + ")";
  {
    const RunningClaim whole(out.string(), Shard());
    CHECK_THROWS_WITH(RunningClaim(out.string(), Shard()),
                      Catch::StartsWith("the results folder '" + out.string() + "' is in use by another roger run" + pid +
                                        ": two runs of one folder would each run again the other's trials in flight") &&
                          Catch::Contains("give each its own --shard K/N"));
    CHECK_THROWS_WITH(RunningClaim(out.string(), Shard{0, 2}), Catch::Contains("in use by another roger run" + pid));
    // roger run --dry-run says so without claiming (found by a probe: it said "resumes", exit 0).
    CHECK(results_folder_unavailable(out.string(), Shard()) ==
          "the results folder '" + out.string() + "' is in use by another roger run" + pid);
    CHECK_THAT(results_folder_unavailable(out.string(), Shard{0, 2}), Catch::Contains("in use by another roger run"));
  }
  CHECK(results_folder_unavailable(out.string(), Shard()).empty());
  CHECK(results_folder_unavailable((out / "new" / "deeper").string(), Shard()).empty());
  std::ofstream(out / "file") << "x";
  CHECK(results_folder_unavailable((out / "file" / "r").string(), Shard()) ==
        "'" + (out / "file").string() + "' is a file: the results folder cannot be made there");
  {
    const RunningClaim first(out.string(), Shard{0, 2}), second(out.string(), Shard{1, 2});
    CHECK_THROWS_WITH(RunningClaim(out.string(), Shard{0, 2}),
                      Catch::Contains("in use by another roger run of the same part (--shard 0/2)" + pid));
    CHECK_THROWS_WITH(RunningClaim(out.string(), Shard()),
                      Catch::Contains("in use by runs of parts of it (--shard or --only): --shard 0/2" + pid +
                                      ", --shard 1/2" + pid + ": two runs of one folder"));
    // Found by a probe: a part that shares trials with a part running (its own shard, narrowed by
    // --only) ran them at the same time.
    CHECK_THROWS_WITH(RunningClaim(out.string(), Shard{1, 2}, {"SG"}),
                      Catch::Contains("is in use by a roger run of --shard 1/2" + pid +
                                      ", whose trials include some of this part's (--shard 1/2 --only SG): the two "
                                      "would each run again the other's trials in flight"));
    CHECK_THROWS_WITH(RunningClaim(out.string(), Shard(), {"SG/B1"}), Catch::Contains("a roger run of --shard "));
    CHECK(first.others_running() == std::vector<std::string>{"--shard 1/2" + pid});
    CHECK(results_folder_unavailable(out.string(), Shard()) == "the results folder '" + out.string() +
                                                                  "' is in use by runs of parts of it (--shard or "
                                                                  "--only): --shard 0/2" + pid + ", --shard 1/2" + pid);
    // --only SG shares trials with both shards: the run would be refused, and the dry run says so.
    CHECK_THAT(results_folder_unavailable(out.string(), Shard(), {"SG"}),
               Catch::Contains("is in use by a roger run of --shard ") &&
                   Catch::EndsWith(", whose trials include some of this part's"));
    // A part that shares trials with a part running (the same shard among them) is in use for it
    // (found by a probe: --dry-run of a shard said "resumes" while that shard ran).
    CHECK(results_folder_unavailable(out.string(), Shard{0, 2}) ==
          "the results folder '" + out.string() + "' is in use by a roger run of --shard 0/2" + pid +
              ", whose trials include some of this part's");
    CHECK_THAT(results_folder_unavailable(out.string(), Shard{1, 2}, {"SG"}), Catch::Contains("--shard 1/2" + pid));
    CHECK(results_folder_unavailable(out.string(), Shard{0, 3}).size() > 0);  // another N overlaps both
    // A part refused for its overlap leaves no claim naming it (found by a probe: the claim file
    // of --shard 1/3 named the pid of a command refused and gone).
    CHECK_THROWS(RunningClaim(out.string(), Shard{1, 3}));
    CHECK(fs::file_size(out / ".running-shard-1-of-3") == 0);
  }
  {
    // Disjoint --only names run together (docs/batch.md); the same names twice, or a name within
    // another's, do not.
    const RunningClaim sg(out.string(), Shard(), {"SG"}), t(out.string(), Shard(), {"T", "eval"});
    CHECK_THROWS_WITH(RunningClaim(out.string(), Shard(), {"eval", "T", "T"}),
                      Catch::Contains("in use by another roger run of the same part (--only T --only eval)" + pid));
    CHECK_THROWS_WITH(RunningClaim(out.string(), Shard(), {"eval/gen"}),
                      Catch::Contains("a roger run of --only T --only eval" + pid));
    CHECK_THROWS_WITH(RunningClaim(out.string(), Shard{0, 2}, {"SG/B1"}), Catch::Contains("a roger run of --only SG" + pid));
    const RunningClaim u(out.string(), Shard{0, 2}, {"U"});
    CHECK(u.others_running().size() == 2);
  }
  // A run that holds the folder alone removes the temporaries a killed writer left (found by a
  // probe: a second Ctrl-C left a staging folder that no later run removed), and nothing else.
  fs::create_directories(out / ".staged4242-0-17.tmp");
  std::ofstream(out / ".staged4242-0-17.tmp" / ".roger-plot-4242-1-2.tmp") << "x";
  std::ofstream(out / ".tables.md.tmp4242-3-99") << "x";
  std::ofstream(out / ".roger-plot-4242-5-6.tmp") << "x";
  std::ofstream(out / ".notes.tmp") << "mine";
  const RunningClaim again(out.string(), Shard());  // each claim ended with its holder
  CHECK_FALSE(fs::exists(out / ".staged4242-0-17.tmp"));
  CHECK_FALSE(fs::exists(out / ".tables.md.tmp4242-3-99"));
  CHECK_FALSE(fs::exists(out / ".roger-plot-4242-5-6.tmp"));
  CHECK(fs::exists(out / ".notes.tmp"));
  CHECK(fs::exists(out / ".running"));
  // A claim ended leaves its file (unlinking a flock file races with a run opening it) but empties
  // it: no file names a process that holds nothing.
  CHECK(slurp(out / ".running-shard-0-of-2").empty());
  CHECK(slurp(out / ".running-only-T-only-eval").empty());
  CHECK(again.others_running().empty());

  // End to end: the second run is refused before it touches anything, and the first is undisturbed.
  const fs::path results = fresh_dir("claim_run");
  const std::string run = std::string(ROGER_BINARY) + " run scripts/quick.lua --jobs 1 --out " + results.string();
  std::string err;
  REQUIRE(shell("(" + run + " >/dev/null 2>&1 & sleep 2; " + run + " >/dev/null 2>&2; echo $? > " +
                    (out / "second_status").string() + "; wait)", &err) == 0);
  std::ifstream status_file(out / "second_status");
  int second = -1;
  status_file >> second;
  INFO(err);
  CHECK(second == 1);
  CHECK_THAT(err, Catch::Contains("roger run: error: the results folder '" + results.string() + "' is in use by another roger run (pid "));
  CHECK(shell("bash tests/tools/compare_results.sh --golden tests/golden/quick " + results.string() + " 1>&2", &err) == 0);
  fs::remove_all(results);
  fs::remove_all(out);
}

// Found by a probe: a batch script whose curriculum = "paper" was refused a folder made with
// curriculum = "curricula/paper.lua", the same file, though files are compared by place.
TEST_CASE("a folder resumes with its curriculum named another way", "[batch]") {
  const fs::path dir = fresh_dir("spelt");
  fs::create_directories(dir);
  const fs::path script = dir / "spelt.lua", out = dir / "out";
  auto write = [&](const std::string& curriculum) {
    std::ofstream(script) << "return { name = 'spelt', curriculum = '" << curriculum
                          << "', trials = 1, runs = { { name = 'SG', stage = 'SG', contexts = { 'DC2' } } } }\n";
  };
  write("curricula/paper.lua");
  const std::string run = std::string(ROGER_BINARY) + " run " + script.string() + " --jobs 1 --no-report --out " + out.string();
  REQUIRE(shell(run + " >/dev/null") == 0);
  write("paper");
  std::string err;
  CHECK(shell(run + " >/dev/null", &err) == 0);
  INFO(err);
  CHECK(err.find("resuming") != std::string::npos);
  CHECK(err.find("in the folder") == std::string::npos);
  write("curricula/ablation.lua");  // another file is still another configuration
  CHECK(shell(run + " >/dev/null", &err) == 1);
  CHECK(err.find("curriculum_file") != std::string::npos);
  fs::remove_all(dir);
}

// Found by an outsider following docs/cluster.md: ROGER_SHARDS=0 was refused as "array task 0 is
// not below the shard count 0", and a task id without a count as "SLURM_ARRAY_TASK_ID and
// SLURM_ARRAY_TASK_COUNT are not set" though the id was.
TEST_CASE("parse_shard names the Slurm variable that is missing or zero", "[batch][shard]") {
  unsetenv("ROGER_SHARDS");
  unsetenv("SLURM_ARRAY_TASK_ID");
  unsetenv("SLURM_ARRAY_TASK_COUNT");
  setenv("SLURM_ARRAY_TASK_ID", "0", 1);
  setenv("ROGER_SHARDS", "0", 1);
  CHECK_THROWS_WITH(parse_shard("slurm"), Catch::Contains("ROGER_SHARDS must be at least 1") &&
                                              !Catch::Contains("not below the shard count"));
  unsetenv("ROGER_SHARDS");
  CHECK_THROWS_WITH(parse_shard("slurm"), Catch::Contains("SLURM_ARRAY_TASK_ID is set (0)") &&
                                              Catch::Contains("neither ROGER_SHARDS nor SLURM_ARRAY_TASK_COUNT"));
  unsetenv("SLURM_ARRAY_TASK_ID");
  setenv("SLURM_ARRAY_TASK_COUNT", "3", 1);
  CHECK_THROWS_WITH(parse_shard("slurm"), Catch::Contains("SLURM_ARRAY_TASK_ID is not set (SLURM_ARRAY_TASK_COUNT=3 is)"));
  unsetenv("SLURM_ARRAY_TASK_COUNT");
}

// Found by an outsider: shards 0/3 and then 1/2 both ran into one folder. Shards of two counts split
// the trials differently (trial 3 is shard 0's of 3 and shard 1's of 2), so they can run one trial
// at once.
TEST_CASE("a shard of another N is refused in a folder that shards of N filled", "[batch][shard]") {
  const fs::path out = fresh_dir("shard_count");
  const std::string run = std::string(ROGER_BINARY) + " run scripts/quick.lua --jobs 1 --out " + out.string();
  std::string err;
  REQUIRE(shell(run + " --shard 2/3 >/dev/null", &err) == 0);  // quick.lua has trials 0 and 1: quick
  CHECK(shell(run + " --shard 1/2 >/dev/null", &err) == 1);
  INFO(err);
  CHECK(err.find("shards of N = 3 (shards/2-of-3.json)") != std::string::npos);
  CHECK(err.find("this is shard 1 of 2") != std::string::npos);
  CHECK(err.find("Keep N = 3") != std::string::npos);
  CHECK_FALSE(fs::exists(out / "shards" / "1-of-2.json"));
  fs::remove_all(out);
}

// A shard records its N as it starts, not only when it ends: a shard of another N that starts while
// it runs is refused too. A run without --shard finishes such a folder by itself.
TEST_CASE("a started shard records its N and a run without shards still opens the folder", "[batch][shard]") {
  const fs::path out = fresh_dir("shard_started");
  BatchOverrides two;
  two.trials = 2;
  const auto script = std::make_shared<const BatchScript>(load_batch_script("quick", two));
  CHECK_FALSE(open_results_folder(plan_batch(script, out.string()), nullptr, Shard{0, 3}));
  const nlohmann::json record = nlohmann::json::parse(slurp(out / "shards" / "0-of-3.json"));
  CHECK(record["shards"] == 3);
  CHECK(record["pending"] == record["trials"]);
  CHECK_THROWS_WITH(open_results_folder(plan_batch(script, out.string()), nullptr, Shard{1, 2}),
                    Catch::Contains("shards of N = 3 (shards/0-of-3.json)"));
  CHECK_FALSE(fs::exists(out / "shards" / "1-of-2.json"));
  CHECK(open_results_folder(plan_batch(script, out.string()), nullptr, Shard{1, 3}));  // the same N
  CHECK(open_results_folder(plan_batch(script, out.string())));                        // no shard
  fs::remove_all(out);
}

// The kill curriculum's batch of 2 trials of SG/B1 in `dir`, as written, and with --trials 4: a
// plan and the plan that grows from it.
static std::pair<std::shared_ptr<const BatchScript>, std::shared_ptr<const BatchScript>> two_plans_of_kill_batch(
    const fs::path& dir) {
  fs::create_directories(dir);
  std::ofstream(dir / "batch.lua") << "return {\n"
                                      "  name = \"kill\", curriculum = \"kill_curriculum.lua\", trials = 2, seed = 7,\n"
                                      "  runs = { { name = \"SG\", stage = \"SG\", contexts = { \"B1\" } } },\n"
                                      "}\n";
  fs::copy_file("tests/scripts/kill_curriculum.lua", dir / "kill_curriculum.lua");
  BatchOverrides four;
  four.trials = 4;
  const auto script = std::make_shared<const BatchScript>(load_batch_script((dir / "batch.lua").string()));
  const auto more = std::make_shared<const BatchScript>(load_batch_script((dir / "batch.lua").string(), four));
  return {script, more};
}

// Found by a probe: shard 1 with --trials 4 rewrote the manifest while shard 0 ran the folder's
// plan of 2; shard 0 ended "done", and no one ran the new trials it owned.
TEST_CASE("a plan that changes is refused while other parts run the folder's", "[batch][shard]") {
  const fs::path dir = fresh_dir("shard_replan"), out = dir / "out";
  const auto [script, more] = two_plans_of_kill_batch(dir);
  {
    const RunningClaim zero(out.string(), Shard{0, 2});
    CHECK_FALSE(open_results_folder(plan_batch(script, out.string()), nullptr, Shard{0, 2}, &zero));
    const RunningClaim one(out.string(), Shard{1, 2});
    CHECK_THROWS_WITH(open_results_folder(plan_batch(more, out.string()), nullptr, Shard{1, 2}, &one),
                      Catch::Contains("other parts of the folder are running the folder's plan: --shard 0/2 (pid ") &&
                          Catch::Contains("Wait for them to end, then run this command again"));
    CHECK(open_results_folder(plan_batch(script, out.string()), nullptr, Shard{1, 2}, &one));  // the same plan
  }
  const RunningClaim one(out.string(), Shard{1, 2});  // alone now: the plan grows
  std::string note;
  CHECK(open_results_folder(plan_batch(more, out.string()), &note, Shard{1, 2}, &one));
  CHECK_THAT(note, Catch::Contains("it plans more trials"));
  fs::remove_all(dir);
}

// Found by a probe: scripts/slurm/submit.sh queued shards into a folder each of them refused once it
// started (shards of another N). inspect_results_folder says what roger run would find, and
// refuses what it would refuse, writing nothing: not even a plan that grows.
TEST_CASE("inspect_results_folder says what a run would do in a folder and writes nothing", "[batch][shard]") {
  const fs::path dir = fresh_dir("inspected"), out = dir / "out";
  const auto [script, more] = two_plans_of_kill_batch(dir);
  CHECK(inspect_results_folder(plan_batch(script, out.string()), Shard{0, 2}) ==
        "a new results folder (roger run makes " + out.string() + ")");
  CHECK_FALSE(fs::exists(out));
  CHECK_FALSE(open_results_folder(plan_batch(script, out.string()), nullptr, Shard{0, 2}));
  const std::string manifest = slurp(out / "manifest.json");
  CHECK(inspect_results_folder(plan_batch(script, out.string()), Shard{1, 2}) ==
        "resumes " + out.string() + " (0 of 2 trials have a result)");
  CHECK_THAT(inspect_results_folder(plan_batch(more, out.string())),
             Catch::StartsWith("resumes " + out.string() + " (0 of 4 trials have a result); ") &&
                 Catch::Contains("it plans more trials"));
  CHECK(slurp(out / "manifest.json") == manifest);  // the grown plan is not written
  CHECK_THROWS_WITH(inspect_results_folder(plan_batch(script, out.string()), Shard{0, 3}),
                    Catch::Contains("holds shards of N = 2"));
  CHECK_FALSE(fs::exists(out / "shards" / "0-of-3.json"));
  std::ofstream(out / "manifest.json") << std::regex_replace(manifest, std::regex("\"engine\": \"[0-9a-f]+\""),
                                                             "\"engine\": \"0000000000000000\"");
  CHECK_THROWS_WITH(inspect_results_folder(plan_batch(script, out.string())),
                    Catch::Contains("was made by another build of the engine (engine 0000000000000000)"));
  std::ofstream(dir / "a_file") << "x";
  CHECK_THROWS_WITH(inspect_results_folder(plan_batch(script, (dir / "a_file").string())),
                    Catch::Contains("is a file: give another --out"));
  fs::remove_all(dir);
}

// Found by an outsider: quick.lua (trials 0 and 1) in 3 shards printed "shard 2 of 3: trials 2, 5,
// ... of every run", then "0 of 0 trials done".
TEST_CASE("a shard with no trial to run says so and succeeds", "[batch][shard]") {
  const fs::path out = fresh_dir("shard_idle");
  std::string err;
  const int status = shell(std::string(ROGER_BINARY) + " run scripts/quick.lua --shard 2/3 --out " + out.string() +
                           " >/dev/null", &err);
  INFO(err);
  CHECK(status == 0);  // the extra tasks of a Slurm array succeed (docs/cluster.md)
  CHECK(err.find("shard 2 of 3 has no trial to run") != std::string::npos);
  CHECK(err.find("have at most 2 trials (indices 0 and 1), so only shards 0 and 1 have trials") != std::string::npos);
  CHECK(err.find("trials 2, 5") == std::string::npos);
  fs::remove_all(out);
}

// ---- [faults]: what a misbehaving script or a corrupt file costs (docs/reliability.md) ----

namespace {

void spit(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary | std::ios::trunc) << text;
}

}  // namespace

TEST_CASE("a fault of a Lua callback fails its trial only, and error.json says where", "[batch][faults]") {
  const fs::path out = fresh_dir("faults");
  std::string err;
  // tests/scripts/faults_curriculum.lua: a reward that loops forever after 1,000 calls, an absorbing
  // function that asks for 1 GiB after 50 calls, a reward that turns NaN after 20, an absorbing
  // function that returns a string, a scenario that refuses some seeds' worlds, a reward setting a
  // finalizer, an absorbing function with a backtracking pattern, a scenario whose generator asks
  // string.rep for 2^62 empty strings (each once an endless hang), a reward reading an __index
  // chain that loops and a generator comparing two 4 MB strings for ever (each one instruction of
  // long C work, stopped by the processor-time budget); then a sound run.
  const int status = shell(std::string(ROGER_BINARY) + " run tests/scripts/faults_batch.lua --jobs 2 --out " + out.string(), &err);
  INFO(err);
  CHECK(status == 1);
  CHECK(err.find("roger run: 2 of 22 trials done") != std::string::npos);
  CHECK(err.find("roger run: 20 trials failed") != std::string::npos);
  for (const char* id : {"sound/A/000", "sound/A/001"}) CHECK(fs::is_regular_file(fs::path(trial_dir(out.string(), id)) / "result.json"));

  struct Fault {
    const char* run;
    const char* file;
    int line;
    const char* says;
  };
  const std::vector<Fault> faults = {
      {"loop", "tests/scripts/faults_curriculum.lua", 18, "instruction budget of 50000000 exceeded"},
      {"bomb", "tests/scripts/faults_curriculum.lua", 26, "not enough memory (script memory limit of 256 MiB; if the data is meant, raise it: --lua-memory"},
      {"nan", "tests/scripts/faults_curriculum.lua", 31, "must return a finite number, got number nan"},
      {"type", "tests/scripts/faults_curriculum.lua", 37, "must return true or false, got string 'yes'"},
      {"unlucky", "tests/scripts/faults_scenario.lua", 9, "an unlucky world"},
      {"finalizer", "tests/scripts/faults_curriculum.lua", 44, "a metatable with __gc is refused"},
      {"pattern", "tests/scripts/faults_curriculum.lua", 52, "string.find: instruction budget of 50000000 exceeded"},
      {"escape", "tests/scripts/faults_escape_scenario.lua", 10, "string.rep: instruction budget of 50000000 exceeded"},
      {"chain", "tests/scripts/faults_curriculum.lua", 61, "processor time budget exceeded: "},
      {"compare", "tests/scripts/faults_compare_scenario.lua", 11, "processor time budget exceeded: "},
  };
  for (const auto& f : faults)
    for (int i = 0; i < 2; ++i) {
      const std::string id = std::string(f.run) + "/A/00" + std::to_string(i);
      INFO(id);
      const fs::path dir = trial_dir(out.string(), id);
      CHECK_FALSE(fs::exists(dir / "result.json"));
      REQUIRE(fs::is_regular_file(dir / "error.json"));
      nlohmann::json e = nlohmann::json::parse(slurp(dir / "error.json"));  // [] of a missing key gives null
      INFO(e.dump(1));
      CHECK(e["trial"] == id);
      CHECK(e["kind"] == "train");
      CHECK(e["seed"] == 3 + i);
      CHECK(e["file"] == f.file);
      CHECK(e["line"] == f.line);
      REQUIRE(e["episode"].is_number_integer());
      REQUIRE(e["world_seed"].is_number_unsigned());
      REQUIRE(e["phase"].is_string());
      const std::string message = e["error"];
      const std::string first = message.substr(0, message.find('\n'));
      CHECK(first.rfind(std::string(f.file) + ":" + std::to_string(f.line) + ": ", 0) == 0);
      CHECK(first.find(f.says) != std::string::npos);
      CHECK(first.find("(" + e["phase"].get<std::string>() + " episode " + std::to_string(e["episode"].get<int>()) +
                       ", world seed " + std::to_string(e["world_seed"].get<uint64_t>()) + ")") != std::string::npos);
      // The whole first line is the trial's row in summary.csv and in the closing list.
      CHECK(err.find("  " + id + ": " + first) != std::string::npos);
      if (std::string(f.run) == "loop")  // the first 1,000 calls were fine: far beyond the first episodes
        CHECK_FALSE((e["phase"] == "training" && e["episode"].get<int>() < 100));
      if (std::string(f.run) == "unlucky") {
        // The world seed named is the one that fails: the fault can be replayed alone.
        Scenario s = Scenario::load(f.file);
        CHECK_THROWS_WITH(s.generate(e["world_seed"].get<uint64_t>()), Catch::Contains("an unlucky world"));
      }
    }
  const std::string csv = slurp(out / "summary.csv");
  size_t failed_rows = 0;
  for (size_t at = csv.find(",failed,"); at != std::string::npos; at = csv.find(",failed,", at + 1)) ++failed_rows;
  CHECK(failed_rows == 20);
  fs::remove_all(out);
}

namespace {

// A damaged manifest is refused by roger report and by a resumed roger run, naming it and what is
// wrong, and nothing is written; the manifest is put back afterwards.
void manifest_refused(const fs::path& out, const std::string& run, const std::string& report,
                      const std::vector<std::string>& outputs) {
  std::string err;
  const std::string manifest = slurp(out / "manifest.json");
  const std::vector<std::pair<std::string, std::string>> manifests = {
      {manifest.substr(0, manifest.size() / 3), "not JSON"},
      {"", "empty (0 bytes)"},
      {"{}", "not the manifest of a roger run results folder"},
      {slurp(out / "trials/SG/B1/000/result.json"), "not the manifest"},
  };
  for (const auto& [text, says] : manifests) {
    INFO(says);
    spit(out / "manifest.json", text);
    CHECK(shell(report + " >/dev/null", &err) == 1);
    CHECK(err.find((out / "manifest.json").string() + ": ") != std::string::npos);
    CHECK(err.find(says) != std::string::npos);
    CHECK(shell(run + out.string() + " >/dev/null", &err) == 1);
    CHECK(err.find((out / "manifest.json").string() + ": ") != std::string::npos);
    for (const auto& o : outputs) CHECK_FALSE(fs::exists(out / o));
  }
  spit(out / "manifest.json", manifest);
}

}  // namespace

TEST_CASE("a corrupt record of a results folder is named, never read as zeros, and run again", "[batch][faults]") {
  const fs::path out = fresh_dir("corrupt"), clean = fresh_dir("corrupt_clean");
  const std::string run = std::string(ROGER_BINARY) + " run tests/scripts/kill_batch.lua --jobs 2 --out ";
  const std::string report = std::string(ROGER_BINARY) + " report " + out.string();
  std::string err;
  REQUIRE(shell(run + out.string(), &err) == 0);
  fs::copy(out, clean, fs::copy_options::recursive);
  const std::vector<std::string> outputs = {"summary.csv", "tables.md", "report.json", "figure3.png"};

  struct Damage {
    const char* file;  // inside the results folder
    std::function<std::string(const std::string&)> spoil;
    const char* says;
  };
  const std::string b1 = "trials/SG/B1/001/", e0 = "trials/eval/gen/spade/000/";
  const std::vector<Damage> damages = {
      {"trials/SG/B1/001/result.json", [](const std::string& t) { return t.substr(0, t.size() / 2); }, "not JSON"},
      {"trials/SG/B1/001/result.json", [](const std::string&) { return std::string(); }, "empty (0 bytes)"},
      {"trials/SG/B1/001/result.json", [](const std::string& t) {
         return std::regex_replace(t, std::regex("\"success_rate\": [0-9.e+-]+"), "\"success_rate\": \"high\""); },
       "field \"success_rate\" must be a finite number, got \"high\""},
      {"trials/SG/B1/001/result.json", [](const std::string& t) {
         return std::regex_replace(t, std::regex("\"reward_mean\": [0-9.e+-]+"), "\"reward_mean\": 1e999"); },
       "number overflow"},
      {"trials/SG/B1/001/result.json", [&](const std::string&) { return slurp(out / "trials/SG/B1/000/result.json"); },
       "it is the result of trial SG/B1/000, not of SG/B1/001"},
      {"trials/SG/B1/001/result.json", [&](const std::string&) { return slurp(out / "manifest.json"); }, "no trial \"id\""},
      {"trials/SG/B1/001/result.json", [](const std::string&) { return std::string("[1, 2, 3]\n"); }, "must be a JSON object"},
      {"trials/SG/B1/001/policy.json", [](const std::string& t) { return t.substr(0, t.size() - 9); }, "policy.json: not JSON"},
      {"trials/SG/B1/001/policy.json", [](const std::string& t) {
         return std::regex_replace(t, std::regex("\"format\": \"[^\"]*\""), "\"format\": \"other\""); }, "\"format\""},
      {"trials/eval/gen/spade/000/result.json", [](const std::string& t) {
         return std::regex_replace(t, std::regex("\"episodes\": [0-9]+,"), ""); }, "no field \"episodes\""},
      // Found by a probe: each of these was read as the folder's own and moved the tables.
      {"trials/SG/B1/001/result.json", [](const std::string& t) {
         return std::regex_replace(t, std::regex("\"reached\": true"), "\"reached\": false"); },
       "field \"reached\" is false, but its last checkpoint's success rate 1 is at or above the threshold 0.9"},
      {"trials/SG/B1/001/result.json", [](const std::string& t) {
         return std::regex_replace(t, std::regex("\"engine\": \"[0-9a-f]+\""), "\"engine\": \"0123\""); },
       "it was made by another build of the engine (engine 0123), and the folder by engine"},
      {"trials/SG/B1/001/result.json", [](const std::string& t) {  // a trial of an edited copy of the curriculum
         return std::regex_replace(t, std::regex("\"tests/scripts/kill_curriculum.lua\": \"[0-9a-f]+\""),
                                   "\"/elsewhere/kill_curriculum.lua\": \"00000000000000aa\""); },
       "none of the Lua files it read is the folder's curriculum (fingerprint "},
      {"trials/SG/B1/001/result.json", [](const std::string& t) {  // another version of a scenario, same name
         return std::regex_replace(t, std::regex("\"scenarios/unobstructed.lua\": \"[0-9a-f]+\""),
                                   "\"scenarios/unobstructed.lua\": \"00000000000000bb\""); },
       "it read scenarios/unobstructed.lua with the fingerprint 00000000000000bb, but the folder's"},
      {"trials/SG/B1/001/result.json", [](const std::string& t) {  // a checkpoint's rate edited (dashboard)
         return std::regex_replace(t, std::regex("(\"checkpoints\": \\[\\s*\\{[^}]*\"success_rate\":) [0-9.e+-]+"),
                                   "$1 0.123"); },
       "checkpoints.jsonl:1: checkpoint 1 is not the one the trial's result.json records: edited?"},
      {"trials/SG/B1/001/checkpoints.jsonl", [](const std::string& t) { return t.substr(0, t.find('\n') + 1); },
       "checkpoints.jsonl: holds 1 checkpoints, but the trial's result.json records "},
      {"trials/eval/gen/spade/000/result.json", [](const std::string& t) {  // its policy trained again since
         return std::regex_replace(t, std::regex("(\"trials/T/DC6/000/policy.json\": )\"[0-9a-f]+\""),
                                   "$1\"00000000000000cc\""); },
       "it read trials/T/DC6/000/policy.json with the fingerprint 00000000000000cc, and the file now has "},
  };
  for (const auto& d : damages) {
    const fs::path file = out / d.file;
    const std::string good = slurp(file);
    spit(file, d.spoil(good));
    for (const auto& o : outputs) fs::remove(out / o);
    INFO(d.file << ": " << d.says);
    for (const char* partial : {"", " --partial"}) {
      CHECK(shell(report + partial + " >/dev/null", &err) == 1);
      INFO(err);
      const std::string id = std::string(d.file).substr(7, std::string(d.file).rfind('/') - 7);
      CHECK(err.find("  " + id + " (") != std::string::npos);
      CHECK(err.find("CORRUPT: " + file.parent_path().string()) != std::string::npos);
      CHECK(err.find(d.says) != std::string::npos);
      for (const auto& o : outputs) CHECK_FALSE(fs::exists(out / o));  // nothing written, nothing misleading
    }
    // The report itself refuses to read it, whoever calls it.
    CHECK_THROWS_WITH(write_report(out.string()), Catch::Contains(d.says));
    for (const auto& o : outputs) CHECK_FALSE(fs::exists(out / o));
    spit(file, good);
  }

  manifest_refused(out, run, report, outputs);
  // A damaged error.json is named too: a failed trial is a record like any other.
  fs::rename(out / e0 / "result.json", out / e0 / "result.kept");
  spit(out / e0 / "error.json", "{\"error\": ");
  CHECK(shell(report + " >/dev/null", &err) == 1);
  CHECK(err.find("CORRUPT: " + (out / e0 / "error.json").string() + ": not JSON") != std::string::npos);
  fs::remove(out / e0 / "error.json");
  fs::rename(out / e0 / "result.kept", out / e0 / "result.json");

  // roger run names corrupt trials and runs them again: the folder ends as an untouched run's.
  spit(out / b1 / "result.json", "{\"id\": \"SG/B1/001\", \"success_rate\": 0");
  spit(out / e0 / "result.json", "");
  REQUIRE(shell(run + out.string() + " >/dev/null", &err) == 0);
  INFO(err);
  CHECK(err.find(b1 + "result.json: not JSON") != std::string::npos);
  CHECK(err.find("running trial SG/B1/001 again") != std::string::npos);
  CHECK(err.find("running trial eval/gen/spade/000 again") != std::string::npos);
  CHECK(shell("bash tests/tools/compare_results.sh " + clean.string() + " " + out.string() + " 1>&2", &err) == 0);
  fs::remove_all(out);
  fs::remove_all(clean);
}

TEST_CASE("a manifest that is JSON but not an object of the right shape is a roger::Error naming it", "[batch]") {
  // Found by tests/fuzz/fuzz_manifest: `roger report` called value() on whatever the manifest held,
  // and a manifest reading "file", or one whose "script" was a number, escaped as a json type_error.
  const fs::path dir = fresh_dir("manifest_shape");
  fs::create_directories(dir);
  const std::string path = (dir / "manifest.json").string();
  for (const auto& [text, what] : std::vector<std::pair<std::string, std::string>>{
           {"\"file\"", "must be a JSON object, got string"},
           {"[1, 2]", "must be a JSON object, got array"},
           {"{\"config\": {}}", "not the manifest of a roger run results folder"},
           {"{\"format\": \"roger-results/1\", \"config\": 3}", "field \"config\" must be an object"},
           {"{\"format\": \"roger-results/1\", \"config\": {}, \"engine\": \"e\", \"script\": 5}",
            "field \"script\" must be a string"},
           {"{\"format\": \"roger-results/1\", \"config\": {}, \"engine\": \"e\", \"script\": \"s\", \"version\": null}",
            "field \"version\" must be a string"}}) {
    std::ofstream(path) << text;
    INFO(text);
    try {
      read_results_plan(dir.string());
      FAIL("read the manifest " << text);
    } catch (const Error& e) {
      CHECK_THAT(e.what(), Catch::Contains(path) && Catch::Contains(what));
    }
  }
  fs::remove_all(dir);
}

// Found by a probe: a folder made from mylab (`scenario = "pen.lua"`) was refused from another
// working folder ("pen.lua" in the folder, "/.../mylab/pen.lua" now) and after copying the project
// (the sources were keyed by their absolute paths), "made by another batch script" of the same one.
TEST_CASE("a results folder resumes from another folder and after a copy, not with a changed source", "[batch]") {
  const fs::path top = fresh_dir("relocate");
  const fs::path lab = top / "mylab";
  fs::create_directories(lab);
  std::string text = slurp("tests/scripts/kill_batch.lua");
  const std::string from = "scenario = \"cluttered\"";
  REQUIRE(text.find(from) != std::string::npos);
  text.replace(text.find(from), from.size(), "scenario = \"pen.lua\"");
  std::ofstream(lab / "my_batch.lua") << text;
  fs::copy_file("tests/scripts/kill_curriculum.lua", lab / "kill_curriculum.lua");
  fs::copy_file("scenarios/cluttered.lua", lab / "pen.lua");
  const fs::path project = fs::current_path();
  const auto open_in = [&](const fs::path& cwd, const std::string& script, const fs::path& out) {
    fs::current_path(cwd);
    struct Back {
      fs::path to;
      ~Back() { fs::current_path(to); }
    } back{project};
    const auto b = std::make_shared<const BatchScript>(load_batch_script(script));
    return open_results_folder(plan_batch(b, out.string()));
  };
  CHECK_FALSE(open_in(lab, "my_batch.lua", lab / "results" / "k"));
  {
    // One trial's result: a folder none of whose trials has one resumes whatever changed (test
    // "a folder without a result resumes after a Lua file its trials read changed").
    fs::current_path(lab);
    RunControl one;
    one.jobs = 1, one.max_trials = 1;
    const BatchSummary done =
        run_batch(plan_batch(std::make_shared<const BatchScript>(load_batch_script("my_batch.lua")),
                             (lab / "results" / "k").string()),
                  one);
    fs::current_path(project);
    REQUIRE(done.failed.empty());
  }
  // The same script from another working folder: the same files, spelt otherwise.
  CHECK(open_in(top, (lab / "my_batch.lua").string(), lab / "results" / "k"));
  // The whole folder copied elsewhere: the same sources at the same places of the copy.
  const fs::path copy = top / "copy";
  fs::copy(lab, copy, fs::copy_options::recursive);
  CHECK(open_in(top, (copy / "my_batch.lua").string(), copy / "results" / "k"));
  // Why the folder of `dir` is refused to its script ("" when it is opened).
  const auto refusal = [&](const fs::path& dir) -> std::string {
    try {
      open_in(dir, "my_batch.lua", dir / "results" / "k");
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  // Found by a probe: from a folder holding a copy of the curriculum, the script's curriculum is
  // that copy (looked for from the current folder first): other files, refused, but the refusal
  // says their contents are the same and why another file was taken.
  const fs::path twin = top / "twin";
  fs::create_directories(twin);
  fs::copy_file(lab / "kill_curriculum.lua", twin / "kill_curriculum.lua");
  std::string from_twin;
  try {
    open_in(twin, (lab / "my_batch.lua").string(), lab / "results" / "k");
  } catch (const Error& e) {
    from_twin = e.what();
  }
  CHECK_THAT(from_twin, Catch::Matchers::Contains("Every Lua file its trials read holds what it held (the same "
                                                  "fingerprints), but other files: the curriculum was "
                                                  "<script folder>/kill_curriculum.lua then and is " +
                                                  (twin / "kill_curriculum.lua").string() + " now"));
  // A source that changed is refused, as before.
  std::ofstream(copy / "kill_curriculum.lua", std::ios::app) << "-- edited\n";
  CHECK_THAT(refusal(copy), Catch::Matchers::Contains("before a Lua file its trials read changed") &&
                                Catch::Matchers::Contains("sources['<script folder>/kill_curriculum.lua']"));
  // Found by a probe: an evaluation's scenario edited between runs was taken, and its trials
  // would have mixed two versions of it. It is a source too, and a run watches it.
  const std::string pen = slurp(lab / "pen.lua");
  std::ofstream(lab / "pen.lua", std::ios::app) << "-- edited\n";
  CHECK_THAT(refusal(lab), Catch::Matchers::Contains("before a Lua file its trials read changed") &&
                               Catch::Matchers::Contains("evaluation_sources['<script folder>/pen.lua']"));
  const batch_detail::SourceWatch watch((lab / "kill_curriculum.lua").string(), {}, {(lab / "pen.lua").string()});
  std::ofstream(lab / "pen.lua") << pen;
  CHECK_THROWS_WITH(watch.check(), "'" + (lab / "pen.lua").string() + "' changed while the run was using it");
  // A folder made before evaluations' scenarios were recorded resumes as it did.
  const fs::path manifest = lab / "results" / "k" / "manifest.json";
  nlohmann::json m = nlohmann::json::parse(slurp(manifest));
  REQUIRE(m["config"].contains("evaluation_sources"));
  m["config"].erase("evaluation_sources");
  std::ofstream(manifest) << m.dump(1);
  CHECK(open_in(lab, "my_batch.lua", lab / "results" / "k"));
  // The same script with another seed: not "another batch script".
  text.replace(text.find("seed = 7"), 8, "seed = 8");
  std::ofstream(lab / "my_batch.lua") << text;
  CHECK_THAT(refusal(lab), Catch::Matchers::Contains("(of my_batch.lua) was made by this batch script as it was then, "
                                                     "with other contents or other parameters (a command's --set, "
                                                     "--trials, --lua-instructions and --lua-memory are parameters "
                                                     "too); it cannot be resumed") &&
                               Catch::Matchers::Contains("seed: 7 in the folder, 8 now"));
  fs::remove_all(top);
}

// Found by a probe: a lab whose batch script, curriculum and worlds sit side by side (batch/,
// curr/, worlds/) could not resume its folder after a copy: the files outside the batch script's
// folder were named by their absolute paths, and the refusal said a file had changed.
TEST_CASE("a lab's folders side by side resume after a copy; a shared file that stayed, after a move", "[batch]") {
  const fs::path top = fresh_dir("relocate_siblings");
  const fs::path lab = top / "lab", shared = top / "shared";
  for (const char* sub : {"batch", "curr", "worlds"}) fs::create_directories(lab / sub);
  fs::create_directories(shared);
  std::string curriculum = slurp("tests/scripts/kill_curriculum.lua");
  const std::string stop = "stage.checkpoints.stop_after = 0\n";
  REQUIRE(curriculum.find(stop) != std::string::npos);
  curriculum.insert(curriculum.find(stop) + stop.size(), "  stage.scenario = \"../worlds/room.lua\"\n");
  std::ofstream(lab / "curr" / "kill_curriculum.lua") << curriculum;
  fs::copy_file("scenarios/unobstructed.lua", lab / "worlds" / "room.lua");
  fs::copy_file("scenarios/unobstructed.lua", shared / "hall.lua");
  const auto batch = [](const std::string& curriculum_path, const std::string& scenario_path) {
    std::string text = slurp("tests/scripts/kill_batch.lua");
    text.replace(text.find("\"kill_curriculum.lua\""), 21, "\"" + curriculum_path + "\"");
    text.replace(text.find("\"cluttered\", params = { obstacles = 2 }"), 39, "\"" + scenario_path + "\"");
    return text;
  };
  // The evaluation's world from the lab's worlds/ folder, then from a folder shared by labs.
  std::ofstream(lab / "batch" / "b.lua") << batch("../curr/kill_curriculum.lua", "../worlds/room.lua");
  std::ofstream(lab / "batch" / "s.lua") << batch("../curr/kill_curriculum.lua", (shared / "hall.lua").string());
  const auto open = [](const fs::path& script, const fs::path& out) {
    const auto b = std::make_shared<const BatchScript>(load_batch_script(script.string()));
    return open_results_folder(plan_batch(b, out.string()));
  };
  CHECK_FALSE(open(lab / "batch" / "b.lua", lab / "out" / "b"));
  CHECK_FALSE(open(lab / "batch" / "s.lua", lab / "out" / "s"));
  {
    // One trial's result in b: a folder without one resumes whatever changed.
    RunControl one;
    one.jobs = 1, one.max_trials = 1;
    REQUIRE(run_batch(plan_batch(std::make_shared<const BatchScript>(load_batch_script((lab / "batch" / "b.lua").string())),
                                 (lab / "out" / "b").string()),
                      one).failed.empty());
  }
  // The whole lab copied: its own files are at the same places of the copy.
  const fs::path copy = top / "copy";
  fs::copy(lab, copy, fs::copy_options::recursive);
  CHECK(open(copy / "batch" / "b.lua", copy / "out" / "b"));
  // Moved: the shared world stayed where it was, and is still the same file.
  const fs::path moved = top / "elsewhere" / "lab";
  fs::create_directories(moved.parent_path());
  fs::rename(lab, moved);
  CHECK(open(moved / "batch" / "s.lua", moved / "out" / "s"));
  // A world of the lab edited in the copy is still refused, named from the script's folder.
  std::ofstream(copy / "worlds" / "room.lua", std::ios::app) << "-- edited\n";
  try {
    open(copy / "batch" / "b.lua", copy / "out" / "b");
    FAIL("a folder was resumed with an edited world");
  } catch (const Error& e) {
    CHECK_THAT(e.what(), Catch::Matchers::Contains("before a Lua file its trials read changed"));
    CHECK_THAT(e.what(), Catch::Matchers::Contains("sources['<script folder>/../worlds/room.lua']"));
  }
  fs::remove_all(top);
}

TEST_CASE("a results folder made under other Lua limits is not resumed", "[batch]") {
  const fs::path out = fresh_dir("limits");
  BatchOverrides small;
  small.trials = 1;
  const auto script = std::make_shared<const BatchScript>(load_batch_script("quick", small));
  CHECK_FALSE(open_results_folder(plan_batch(script, out.string())));
  CHECK(open_results_folder(plan_batch(script, out.string())));  // the same limits: resumed
  BatchOverrides larger = small;
  larger.instructions = 200'000'000;
  const auto other = std::make_shared<const BatchScript>(load_batch_script("quick", larger));
  try {
    open_results_folder(plan_batch(other, out.string()));
    FAIL("a folder made under other limits was resumed");
  } catch (const Error& e) {
    CHECK_THAT(e.what(), Catch::Matchers::Contains("limits.instructions: 50000000 in the folder, 200000000 now"));
  }
  fs::remove_all(out);
}

// Found by a probe: three runs that took no skills ran in three phases, one after the other, so
// with --jobs 2 and a trial each one core sat idle at every phase.
TEST_CASE("runs that take no skills share a phase; a run waits only for the runs it takes skills from", "[batch]") {
  const fs::path dir = fresh_dir("phases");
  fs::create_directories(dir);
  const fs::path path = dir / "phases.lua";
  std::ofstream(path) << R"(return {
  curriculum = "paper", trials = 2,
  runs = {
    { name = "SG_a", stage = "SG", contexts = { "DC2" } },
    { name = "T", stage = "T", contexts = { "DC6" }, skills = { Phi_SG = { run = "SG_a", context = "DC2" } } },
    { name = "SG_b", stage = "SG", contexts = { "B1", "DC2" } },
    { name = "T2", stage = "T", contexts = { "DC5" }, skills = { Phi_SG = { run = "SG_b", context = "DC2" } } },
  },
  evaluations = { { name = "g", run = "T", context = "DC6", episodes = 2 } },
})";
  const auto script = std::make_shared<const BatchScript>(load_batch_script(path.string(), {}));
  const BatchPlan plan = plan_batch(script, (dir / "out").string());
  std::vector<std::vector<std::string>> phases;
  for (const auto& p : plan.phases) {
    phases.emplace_back();
    for (const PlannedTrial& t : p) phases.back().push_back(t.id);
  }
  CHECK(phases == std::vector<std::vector<std::string>>{
                      {"SG_a/DC2/000", "SG_a/DC2/001", "SG_b/B1/000", "SG_b/B1/001", "SG_b/DC2/000", "SG_b/DC2/001"},
                      {"T/DC6/000", "T/DC6/001", "T2/DC5/000", "T2/DC5/001"},
                      {"eval/g/all/000", "eval/g/all/001"}});
  fs::remove_all(dir);
}

// Found by a probe: a folder whose manifest.json was deleted was taken with its trials, whatever made
// them; a folder of notes, one of roger propose, the folder of one's scripts were written into.
TEST_CASE("check_out_folder takes a new, empty or results folder and refuses one with other files", "[batch]") {
  const fs::path dir = fresh_dir("out_folder");
  check_out_folder(dir.string());  // not there yet: made by the run
  fs::create_directories(dir);
  check_out_folder(dir.string());  // empty
  // The lock files of a run starting beside this one (it writes its manifest under .lock next).
  for (const char* name : {".lock", ".running", ".running-shard-0-of-2", ".manifest.json.tmp42-0-7"})
    std::ofstream(dir / name) << "";
  // And the logs' folder scripts/slurm/submit.sh makes before its shards start (a file of that name is no such).
  fs::create_directories(dir / "slurm");
  std::ofstream(dir / "slurm" / "shard-0-1.out") << "";
  check_out_folder(dir.string());
  fs::create_directories(dir / "trials" / "SG");
  std::ofstream(dir / "summary.csv") << "id\n";
  CHECK_THROWS_WITH(check_out_folder(dir.string()),
                    "the folder '" + dir.string() + "' holds results of roger run (summary.csv, trials/) but no "
                    "manifest.json, so nothing tells which script and parameters made them, and the trials of this "
                    "run would mix with them. Move them aside (or put back the folder's manifest.json), or give "
                    "another --out");
  std::ofstream(dir / "manifest.json") << "{}";
  check_out_folder(dir.string());  // a results folder: open_results_folder checks its manifest
  fs::remove(dir / "manifest.json");
  std::ofstream(dir / "settings.json") << "{}";  // roger propose's: its trials/ are its own records
  CHECK_THROWS_WITH(check_out_folder(dir.string()),
                    Catch::Contains("is not a results folder of roger run (it has no manifest.json), it is one of "
                                    "roger propose, and is not empty: it holds settings.json, summary.csv, trials/"));
  fs::remove_all(dir);
  // open_results_folder checks again under its lock: a folder filled between the check and the claim.
  fs::create_directories(dir);
  std::ofstream(dir / "notes.md") << "mine";
  const auto b = std::make_shared<const BatchScript>(load_batch_script("tests/scripts/kill_batch.lua"));
  CHECK_THROWS_WITH(open_results_folder(plan_batch(b, dir.string())), Catch::Contains("it holds notes.md."));
  CHECK_FALSE(fs::exists(dir / "manifest.json"));
  fs::remove_all(dir);
}

namespace {

// Opens <dir>/out for <dir>/batch.lua run with --trials `trials` (0: none): whether it resumed.
bool open_with_trials(const fs::path& dir, int trials) {
  BatchOverrides ov;
  ov.trials = trials;
  const auto b = std::make_shared<const BatchScript>(load_batch_script((dir / "batch.lua").string(), ov));
  return open_results_folder(plan_batch(b, (dir / "out").string()));
}

}  // namespace

// Found by a probe: after a reward that looped failed every trial, the command with the reward fixed
// was refused ("its trials and new ones would mix two versions"), though no trial had a result.
TEST_CASE("a folder without a result resumes after a Lua file its trials read changed", "[batch]") {
  const fs::path dir = fresh_dir("no_result_yet");
  fs::create_directories(dir);
  fs::copy_file("tests/scripts/kill_batch.lua", dir / "batch.lua");
  fs::copy_file("tests/scripts/kill_curriculum.lua", dir / "kill_curriculum.lua");
  const auto script = std::make_shared<const BatchScript>(load_batch_script((dir / "batch.lua").string()));
  CHECK_FALSE(open_results_folder(plan_batch(script, (dir / "out").string())));  // a new folder, no trial run
  const std::string before = slurp(dir / "out" / "manifest.json");
  std::ofstream(dir / "kill_curriculum.lua", std::ios::app) << "-- the reward fixed\n";
  const auto edited = std::make_shared<const BatchScript>(load_batch_script((dir / "batch.lua").string()));
  const BatchPlan plan = plan_batch(edited, (dir / "out").string());
  CHECK_THAT(inspect_results_folder(plan), Catch::Contains("but no trial there has a result (each failed or never "
                                                           "ran), so nothing mixes two versions: the run would record "
                                                           "the files as they are in the manifest, and run every trial"));
  CHECK(slurp(dir / "out" / "manifest.json") == before);  // the dry run's look writes nothing
  std::string note;
  CHECK(open_results_folder(plan, &note));
  CHECK_THAT(note, Catch::EndsWith("the manifest now records the files as they are, and every trial runs"));
  CHECK(slurp(dir / "out" / "manifest.json") != before);
  CHECK(open_results_folder(plan, &note));  // and resumes as it is
  fs::remove_all(dir);
}

// Found by a probe: after --trials 3 extended a folder, the command without it was refused with
// "runs[1].trials: 3 in the folder, 2 now" and no word of how to resume it.
TEST_CASE("a folder refused for holding more trials says which --trials resumes it", "[batch]") {
  const fs::path dir = fresh_dir("fewer");
  fs::create_directories(dir);
  const std::string text = "return {\n"
                           "  name = \"kill\", curriculum = \"kill_curriculum.lua\", trials = 2, seed = 7,\n"
                           "  runs = { { name = \"SG\", stage = \"SG\", contexts = { \"B1\", \"DC2\" } } },\n"
                           "}\n";
  std::ofstream(dir / "batch.lua") << text;
  fs::copy_file("tests/scripts/kill_curriculum.lua", dir / "kill_curriculum.lua");
  const auto open = [&](int trials) { return open_with_trials(dir, trials); };
  INFO(text);
  CHECK_FALSE(open(3));
  CHECK_THROWS_WITH(open(0), Catch::Contains("runs[1].trials: 3 in the folder, 2 now") &&
                                 Catch::Contains("The folder's manifest plans more trials than this command does (it "
                                                 "was made, or grown, with more trials than this command gives, "
                                                 "whether or not those trials ran; a plan never shrinks): to resume "
                                                 "it, run the command with --trials 3, the folder's number of trials."));
  CHECK(open(3));
  fs::remove_all(dir);
}

// Found by a probe: a folder made without --trials, then a command with --trials 1, was refused
// with no word of how to resume it when an evaluation had several shapes; and every refusal ended
// by inviting the user to remove the folder.
TEST_CASE("a folder with an evaluation of several shapes says which --trials resumes it", "[batch]") {
  const fs::path dir = fresh_dir("fewer_shapes");
  fs::create_directories(dir);
  fs::copy_file("tests/scripts/kill_batch.lua", dir / "batch.lua");
  fs::copy_file("tests/scripts/kill_curriculum.lua", dir / "kill_curriculum.lua");
  const auto open = [&](int trials) { return open_with_trials(dir, trials); };
  CHECK_FALSE(open(0));  // the script's 2
  CHECK_THROWS_WITH(open(1), Catch::Contains("to resume it, run the command with --trials 2, the folder's number of "
                                             "trials.") &&
                                 Catch::Contains("To resume the folder, run it with the script and parameters it was "
                                                 "made with (its manifest.json records them); for this configuration, "
                                                 "give another --out.") &&
                                 !Catch::Contains("remove the folder"));
  CHECK_THROWS_WITH(open(3), Catch::Contains("give each such evaluation its own `trials`, the folder's number"));
  CHECK(open(2));
  fs::remove_all(dir);
}

// Found by a probe: a change to the description alone was said to be of "its report's titles,
// tables or figures"; the refusal of another script listed the report's fields among the rest.
TEST_CASE("a folder's notes and refusals name what changed, what changes trials first", "[batch]") {
  const fs::path dir = fresh_dir("described");
  fs::create_directories(dir);
  const std::string text = slurp("tests/scripts/kill_batch.lua");
  fs::copy_file("tests/scripts/kill_curriculum.lua", dir / "kill_curriculum.lua");
  const auto open = [&](const std::string& script, std::string* note) {
    std::ofstream(dir / "batch.lua") << script;
    const auto b = std::make_shared<const BatchScript>(load_batch_script((dir / "batch.lua").string()));
    return open_results_folder(plan_batch(b, (dir / "out").string()), note);
  };
  std::string note;
  CHECK_FALSE(open(text, &note));
  const std::string described =
      std::regex_replace(text, std::regex("name = \"kill\","), "name = \"kill\", description = \"Small.\",");
  CHECK(open(described, &note));
  CHECK_THAT(note, Catch::Contains("only in what trains nothing again: its description changed. The manifest"));
  const std::string renamed = std::regex_replace(described, std::regex("seed = 7"), "seed = 8");
  try {
    open(std::regex_replace(renamed, std::regex("name = \"kill\""), "name = \"kill2\""), nullptr);
    FAIL("another seed was taken");
  } catch (const Error& e) {
    const std::string what = e.what();
    INFO(what);
    REQUIRE(what.find("name: ") != std::string::npos);
    CHECK(what.find("seed: 7 in the folder, 8 now") < what.find("name: "));
  }
  fs::remove_all(dir);
}

// Found by a probe: SLURM_ARRAY_TASK_ID='x' was "not a count" (it is an index); --out /proc/foo
// said "A folder on that path does not exist: make it", which nobody can there.
TEST_CASE("an array task id that is no index, and a folder no file system makes, are said so", "[batch][shard]") {
  setenv("SLURM_ARRAY_TASK_ID", "x", 1);
  setenv("SLURM_ARRAY_TASK_COUNT", "3", 1);
  CHECK_THROWS_WITH(parse_shard("slurm"), "--shard slurm: SLURM_ARRAY_TASK_ID='x' is not an index (a whole number from 0)");
  setenv("SLURM_ARRAY_TASK_ID", "1", 1);
  setenv("SLURM_ARRAY_TASK_COUNT", "y", 1);
  CHECK_THROWS_WITH(parse_shard("slurm"), "--shard slurm: SLURM_ARRAY_TASK_COUNT='y' is not a count (a whole number)");
  unsetenv("SLURM_ARRAY_TASK_ID");
  unsetenv("SLURM_ARRAY_TASK_COUNT");
  if (!fs::is_directory("/proc/self")) return;
  try {
    const RunningClaim claim("/proc/roger_no_folder_here", Shard());
    FAIL("a folder was made in /proc");
  } catch (const FileError& e) {
    CHECK(std::string(e.what()) == "cannot create the results folder '/proc/roger_no_folder_here': '/proc' exists, but "
                                   "its file system makes no folder there (No such file or directory); give --out a "
                                   "folder on a disk");
    CHECK(e.error_number != ENOENT);  // not "a folder on that path does not exist: make it"
  }
}

// Found by a probe: a reward returning "résumé: éé..." was quoted in the error cut inside an "é",
// and a scenario's error("bad \255 byte"): error.json could not be written (its JSON writer refuses
// bytes that are not UTF-8), the exception was swallowed, and the trial was lost: "0 of 1 trials
// done, 1 not run yet", exit 0, at every resume. It now fails as any fault does, message whole.
TEST_CASE("a trial whose error is no UTF-8 text fails with error.json, not lost", "[batch][faults]") {
  const fs::path dir = fresh_dir("utf8_error");
  fs::create_directories(dir);
  std::ofstream(dir / "cur.lua") << "local p = require('lib.skills').primitives()\n"
                                    "return { name = 'u', stages = {\n"
                                    "  roger.stage{ name = 'S', scenario = 'unobstructed', time_limit = 4,\n"
                                    "    absorbing = roger.converged(p.phi0), budget = { episodes = 5 },\n"
                                    "    reward = function() return 'r\\195\\169sum\\195\\169: ' .. string.rep('\\195\\169', 40) end,\n"
                                    "    contexts = { { name = 'Gaze', actions = { p.search, p.phi0 } } } } } }\n";
  std::ofstream(dir / "b.lua") << "return { name = 'u', curriculum = 'cur.lua', trials = 1,\n"
                                  "  runs = { { name = 'S', stage = 'S', contexts = { 'Gaze' } } } }\n";
  std::string err;
  const std::string run = std::string(ROGER_BINARY) + " run " + (dir / "b.lua").string() + " --jobs 1 --out " +
                          (dir / "out").string();
  CHECK(shell(run + " >/dev/null", &err) == 1);
  INFO(err);
  CHECK_THAT(err, Catch::Contains("S/Gaze/000") && Catch::Contains("1 failed"));
  const fs::path error_file = dir / "out" / "trials" / "S" / "Gaze" / "000" / "error.json";
  REQUIRE(fs::is_regular_file(error_file));
  const std::string message = nlohmann::json::parse(slurp(error_file))["error"];
  CHECK_THAT(message, Catch::Contains("the reward function must return a finite number, got string 'r\xC3\xA9sum\xC3\xA9: "));
  CHECK(utf8_problem(message).empty());
  fs::remove_all(dir);
}
