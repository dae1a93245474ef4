// Tests of engine/batch: parallel, resumable trials with atomic results.
#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>

#include "batch/batch.h"
#include "core/error.h"
#include "core/rng.h"

using namespace roger;
namespace fs = std::filesystem;

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
  for (const char* bad : {"5/5", "-1/3", "1/0", "1", "a/b", "1/3x", ""})
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

  // The report names what is missing and who owns it, and writes nothing.
  std::string err;
  CHECK(shell(std::string(ROGER_BINARY) + " report " + out.string() + " >/dev/null", &err) == 1);
  INFO(err);
  CHECK(err.find("T/B2/001 (run T, context B2, trial 1; shard 1 of 3)") != std::string::npos);
  CHECK(err.find("eval/generalization/spade/001") != std::string::npos);
  CHECK(err.find("T/B2/000") == std::string::npos);
  CHECK_FALSE(fs::exists(out / "tables.md"));
  CHECK_FALSE(fs::exists(out / "summary.csv"));

  // The shard resumes with its command; then the report equals an unsharded run's (kept in
  // tests/golden/quick, made by one roger run of the same script).
  REQUIRE(shell(run + " --shard 1/3 >/dev/null") == 0);
  REQUIRE(shell(std::string(ROGER_BINARY) + " report " + out.string() + " >/dev/null", &err) == 0);
  const int same = shell("bash tests/tools/compare_results.sh --golden tests/golden/quick " + out.string() + " 1>&2", &err);
  INFO(err);
  CHECK(same == 0);
  fs::remove_all(out);
}

TEST_CASE("a manifest that is JSON but not an object of the right shape is a roger::Error naming it", "[batch]") {
  // Found by tests/fuzz/fuzz_manifest: `roger report` called value() on whatever the manifest held,
  // and a manifest reading "file", or one whose "script" was a number, escaped as a json type_error.
  const fs::path dir = fresh_dir("manifest_shape");
  fs::create_directories(dir);
  const std::string path = (dir / "manifest.json").string();
  for (const auto& [text, what] : std::vector<std::pair<std::string, std::string>>{
           {"\"file\"", "expected a JSON object, got string"},
           {"[1, 2]", "expected a JSON object, got array"},
           {"{\"config\": 3}", "field \"config\" must be an object"},
           {"{\"script\": 5, \"config\": {}}", "field \"script\" must be a string"},
           {"{\"version\": null, \"config\": {}}", "field \"version\" must be a string"}}) {
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
