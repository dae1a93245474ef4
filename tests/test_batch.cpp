// Tests of engine/batch: parallel, resumable trials with atomic results.
#include <catch2/catch.hpp>

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
