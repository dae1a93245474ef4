#include "batch/batch.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <ostream>
#include <set>
#include <sstream>
#include <thread>

#include "core/error.h"
#include "core/fileio.h"

namespace roger {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

void check_id(const std::string& id) {
  if (id.empty()) throw Error("batch: a trial id is empty");
  std::stringstream ss(id);
  std::string part;
  while (std::getline(ss, part, '/')) {
    if (part.empty() || part == "." || part == "..")
      throw Error("batch: trial id '" + id + "' has an empty, '.' or '..' segment");
    for (char c : part)
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-'))
        throw Error("batch: trial id '" + id + "' has the character '" + std::string(1, c) +
                    "'; use letters, digits, '.', '_', '-' and '/'");
  }
}

// Reads a finished trial's result, or returns false when the trial has not finished.
bool read_finished(const std::string& dir, TrialOutcome& out) {
  for (const char* name : {"result.json", "error.json"}) {
    const fs::path p = fs::path(dir) / name;
    if (!fs::exists(p)) continue;
    std::ifstream in(p);
    try {
      out.result = nlohmann::json::parse(in);
    } catch (const std::exception&) {
      return false;  // cannot happen with atomic writes; treat as unfinished and run again
    }
    out.ok = std::string(name) == "result.json";
    out.resumed = true;
    return true;
  }
  return false;
}

}  // namespace

std::string trial_dir(const std::string& out_dir, const std::string& id) {
  return (fs::path(out_dir) / "trials" / id).string();
}

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  const long s = std::lround(seconds);
  char buf[64];
  if (s < 60) std::snprintf(buf, sizeof buf, "%ld s", s);
  else if (s < 3600) std::snprintf(buf, sizeof buf, "%ld min %02ld s", s / 60, s % 60);
  else std::snprintf(buf, sizeof buf, "%ld h %02ld min", s / 3600, (s % 3600) / 60);
  return buf;
}

std::vector<TrialOutcome> run_trials(const std::vector<std::string>& ids, const TrialFunction& run,
                                     const BatchOptions& options) {
  if (options.out_dir.empty()) throw Error("batch: no results folder given");
  std::set<std::string> seen;
  for (const auto& id : ids) {
    check_id(id);
    if (!seen.insert(id).second) throw Error("batch: trial id '" + id + "' appears twice");
  }
  std::vector<TrialOutcome> outcomes(ids.size());
  std::vector<size_t> pending;
  for (size_t i = 0; i < ids.size(); ++i) {
    outcomes[i].id = ids[i];
    if (!read_finished(trial_dir(options.out_dir, ids[i]), outcomes[i])) pending.push_back(i);
  }
  const int jobs = std::max(1, options.jobs > 0 ? options.jobs
                                                : int(std::max(1u, std::thread::hardware_concurrency())));
  const size_t total = ids.size(), resumed = total - pending.size();

  std::mutex mutex;
  std::condition_variable wake;
  std::atomic<size_t> next{0};
  size_t done = 0, running = 0;
  bool finished = false;
  const auto start = Clock::now();

  auto progress_line = [&](bool final) {
    // Called with the mutex held.
    const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
    const size_t left = pending.size() - done - running;
    std::ostringstream os;
    os << "trials: " << resumed + done << "/" << total << " done";
    if (resumed) os << " (" << resumed << " from an earlier run)";
    os << ", " << running << " running, " << left << " left, " << format_duration(elapsed) << " elapsed";
    if (done > 0 && !final) {
      // Each worker finishes a trial every elapsed/done*jobs seconds on average.
      const double per_trial = elapsed / double(done);
      os << ", about " << format_duration(per_trial * double(left + running)) << " to go";
    }
    return os.str();
  };

  auto worker = [&]() {
    for (;;) {
      const size_t k = next.fetch_add(1);
      if (k >= pending.size()) return;
      const size_t i = pending[k];
      {
        std::lock_guard<std::mutex> lock(mutex);
        ++running;
      }
      TrialOutcome& out = outcomes[i];
      const std::string dir = trial_dir(options.out_dir, out.id);
      std::error_code ec;
      fs::remove_all(dir, ec);  // a trial cut short: start it afresh
      fs::create_directories(dir, ec);
      const auto t0 = Clock::now();
      try {
        if (ec) throw Error("batch: cannot create '" + dir + "': " + ec.message());
        out.result = run(out.id, dir);
        out.ok = true;
        write_file_atomic((fs::path(dir) / "result.json").string(), out.result.dump(1) + "\n",
                          "batch: cannot write the trial result");
      } catch (const std::exception& e) {
        out.ok = false;
        out.result = nlohmann::json{{"error", e.what()}};
        try {
          write_file_atomic((fs::path(dir) / "error.json").string(), out.result.dump(1) + "\n",
                            "batch: cannot write the trial error");
        } catch (const std::exception&) {
          // The outcome still carries the error; the trial will simply run again on resume.
        }
      }
      out.wall_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
      {
        std::lock_guard<std::mutex> lock(mutex);
        --running;
        ++done;
      }
      wake.notify_all();
    }
  };

  std::thread reporter;
  if (options.progress) {
    reporter = std::thread([&]() {
      std::unique_lock<std::mutex> lock(mutex);
      const auto period = std::chrono::duration<double>(options.live ? 0.25 : options.every);
      while (!finished) {
        wake.wait_for(lock, period);
        if (finished) break;
        if (options.live) *options.progress << "\r\033[K" << progress_line(false) << std::flush;
      }
    });
  }
  // Plain lines are printed on a timer by the reporter only in live mode; in plain mode the
  // main thread prints one every `every` seconds while waiting.
  std::vector<std::thread> pool;
  const int threads = std::min<int>(jobs, int(std::max<size_t>(1, pending.size())));
  for (int t = 0; t < threads; ++t) pool.emplace_back(worker);
  if (options.progress && !options.live) {
    std::unique_lock<std::mutex> lock(mutex);
    auto next_line = Clock::now();
    while (done < pending.size()) {
      if (Clock::now() >= next_line) {
        *options.progress << progress_line(false) << "\n" << std::flush;
        next_line = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                       std::chrono::duration<double>(options.every));
      }
      wake.wait_until(lock, next_line);
    }
  }
  for (auto& t : pool) t.join();
  {
    std::lock_guard<std::mutex> lock(mutex);
    finished = true;
  }
  wake.notify_all();
  if (reporter.joinable()) reporter.join();
  if (options.progress) {
    std::lock_guard<std::mutex> lock(mutex);
    *options.progress << (options.live ? "\r\033[K" : "") << progress_line(true) << "\n" << std::flush;
  }
  return outcomes;
}

}  // namespace roger
