// run.cpp: a run of a batch script: its trials on a pool of worker threads, resumably, phase by
// phase; each trial trains a stage (trainer.h) or evaluates a trained policy.
#include "batch/batch.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <filesystem>
#include <map>
#include <mutex>
#include <numeric>
#include <optional>
#include <ostream>
#include <set>
#include <sstream>
#include <thread>

#include "batch/batch_internal.h"
#include "engine_fingerprint.h"
#include "batch/trainer.h"
#include "core/json_input.h"
#include "core/error.h"
#include "core/fileio.h"
#include "core/text.h"
#include "core/interrupt.h"
#include "script/batch/batch_script.h"

namespace roger {

namespace fs = std::filesystem;
using namespace batch_detail;
using Clock = std::chrono::steady_clock;

namespace {

void check_id(const std::string& id) {
  if (id.empty()) throw Error("batch: a trial id is empty");
  std::stringstream ss(id);
  std::string part;
  while (std::getline(ss, part, '/')) {
    if (part.empty() || part == "." || part == "..")
      throw Error("batch: trial id '" + id + "' has an empty, '.' or '..' segment");
    for (size_t k = 0; k < part.size(); ++k) {
      const auto c = static_cast<unsigned char>(part[k]);
      if (std::isalnum(c) || c == '.' || c == '_' || c == '-') continue;
      size_t end = k + 1;  // the whole character, not one byte of its UTF-8
      while (c >= 0xC0 && end < part.size() && (static_cast<unsigned char>(part[end]) & 0xC0) == 0x80) ++end;
      throw Error("batch: trial id '" + id + "' has the character '" + part.substr(k, end - k) +
                  "'; use letters, digits, '.', '_', '-' and '/'");
    }
  }
}

// Reads a finished trial's result, or returns false when the trial has not finished.
bool read_finished(const std::string& dir, TrialOutcome& out) {
  for (const char* name : {"result.json", "error.json"}) {
    const fs::path p = fs::path(dir) / name;
    if (!fs::exists(p)) continue;
    try {
      out.result = read_json_file(p.string());
    } catch (const std::exception&) {
      return false;  // truncated or edited by hand: treat as unfinished and run again
    }
    if (!out.result.is_object()) return false;
    out.ok = std::string(name) == "result.json";
    out.resumed = true;
    return true;
  }
  return false;
}

// The state of one run_trials call, shared by its workers and its progress reporter.
class TrialPool {
 public:
  TrialPool(const std::vector<std::string>& ids, const TrialFunction& run, const BatchOptions& options)
      : run_(run), options_(options), outcomes_(ids.size()), start_(Clock::now()) {
    for (size_t i = 0; i < ids.size(); ++i) {
      outcomes_[i].id = ids[i];
      if (!read_finished(trial_dir(options.out_dir, ids[i]), outcomes_[i])) pending_.push_back(i);
    }
    resumed_ = ids.size() - pending_.size();
    for (const TrialOutcome& o : outcomes_) failed_ += o.resumed && !o.ok;
  }

  // Runs the pending trials on `jobs` threads while reporting progress; returns every outcome.
  std::vector<TrialOutcome> run(int jobs) {
    const int threads = std::min<int>(jobs, int(std::max<size_t>(1, pending_.size())));
    workers_ = threads;  // before the reporter, which reads it
    std::thread reporter;
    if (options_.progress && options_.live) reporter = std::thread([this] { report_live(); });
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t) pool.emplace_back([this] { work(); });
    if (options_.progress && !options_.live) report_plain();
    for (auto& t : pool) t.join();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      finished_ = true;
    }
    wake_.notify_all();
    if (reporter.joinable()) reporter.join();
    if (options_.progress) {
      std::lock_guard<std::mutex> lock(mutex_);
      *options_.progress << (options_.live ? "\r\033[K" : "") << progress_line(true) << "\n" << std::flush;
    }
    if (stop_) std::rethrow_exception(stop_);
    return std::move(outcomes_);
  }

 private:
  // One progress line; called with the mutex held.
  std::string progress_line(bool final) const {
    const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
    const size_t left = pending_.size() - done_ - running_;
    std::ostringstream os;
    os << "trials: " << resumed_ + done_ << "/" << outcomes_.size() << " done";
    // The failed among them (found by a probe: "2/2 done" above "0 of 2 trials done, 2 failed").
    if (failed_ || resumed_)
      os << " (" << (failed_ ? std::to_string(failed_) + " failed" : "") << (failed_ && resumed_ ? ", " : "")
         << (resumed_ ? std::to_string(resumed_) + " from an earlier run" : "") << ")";
    os << ", " << running_ << " running, " << left << " left, " << format_duration(elapsed) << " elapsed";
    if (!final)
      if (const double to_go = time_to_go(); to_go >= 0) os << ", about " << format_duration(to_go) << " to go";
    return os.str();
  }

  // The time left, as the dashboard estimates it (TimeLeft below): the trials not started take
  // the mean time of those that finished well, the running ones that mean less what they have
  // run, all of it shared by the workers, and never less than the longest running one still
  // needs. -1 before a trial finished well. (It divided the time elapsed by the trials done and
  // counted each running trial whole: a run's first minutes read several times too long.)
  // Called with the mutex held.
  double time_to_go() const {
    if (durations_.empty()) return -1.0;
    const double mean = std::accumulate(durations_.begin(), durations_.end(), 0.0) / double(durations_.size());
    const auto now = Clock::now();
    double work = mean * double(pending_.size() - done_ - stopped_ - running_), longest = 0.0;
    for (const auto& [index, began] : began_) {
      const double rest = std::max(0.0, mean - std::chrono::duration<double>(now - began).count());
      work += rest, longest = std::max(longest, rest);
    }
    return std::max(work / double(std::max(1, workers_)), longest);
  }

  // A worker: takes pending trials one by one until none is left or the run stops.
  void work() {
    for (;;) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!stop_ && interrupt_requested()) stop_ = std::make_exception_ptr(Interrupted());
        if (stop_) return;
      }
      const size_t k = next_.fetch_add(1);
      if (k >= pending_.size()) return;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        ++running_;
        began_.emplace(k, Clock::now());
      }
      TrialOutcome& outcome = outcomes_[pending_[k]];
      const bool finished = run_one(outcome);
      {
        std::lock_guard<std::mutex> lock(mutex_);
        --running_;
        began_.erase(k);
        finished ? ++done_ : ++stopped_;
        failed_ += finished && !outcome.ok;
        // A failed trial may have stopped at once: only those that finished well are timed.
        if (finished && outcome.ok) durations_.push_back(outcome.wall_seconds);
      }
      wake_.notify_all();
    }
  }

  // Runs one trial in a fresh folder and commits its result.json, or its error.json; returns false
  // when a FileError (a full disk, a folder not writable, a script removed) stopped it: the trial is
  // not at fault, so it records nothing and the run stops (run() rethrows the first such error).
  bool run_one(TrialOutcome& out) {
    const std::string dir = trial_dir(options_.out_dir, out.id);
    std::error_code ec;
    fs::remove_all(dir, ec);  // a trial cut short: start it afresh
    fs::create_directories(dir, ec);
    const auto t0 = Clock::now();
    try {
      if (ec) throw FileError("cannot create the trial folder '" + dir + "': " + ec.message(), dir, ec.value());
      out.result = run_(out.id, dir);
      out.ok = true;
      write_file_atomic((fs::path(dir) / "result.json").string(), out.result.dump(1) + "\n",
                        "cannot write the trial result");
    } catch (const FileError&) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!stop_) stop_ = std::current_exception();
      fs::remove_all(dir, ec);  // its partial files: the resumed run starts it afresh anyway
      return false;
    } catch (const std::exception& e) {
      if (interrupt_requested()) {
        // Stopped part-way by Ctrl-C (its episode ended with Interrupted, or whatever that caused):
        // not the trial's fault, so nothing is recorded and the resumed run starts it afresh.
        std::lock_guard<std::mutex> lock(mutex_);
        if (!stop_) stop_ = std::make_exception_ptr(Interrupted());
        fs::remove_all(dir, ec);
        return false;
      }
      out.ok = false;
      const auto* detailed = dynamic_cast<const TrialError*>(&e);
      out.result = detailed && detailed->details.is_object() ? detailed->details : nlohmann::json::object();
      out.result["error"] = printable_text(e.what());
      out.result["trial"] = out.id;
      try {
        // Text in the details a script gave (a stage's name) is written with U+FFFD for a byte
        // that is no UTF-8, not refused: a trial that failed is never lost for its message.
        write_file_atomic((fs::path(dir) / "error.json").string(),
                          out.result.dump(1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n",
                          "cannot write the trial error");
      } catch (const std::exception&) {
        // The outcome still carries the error; the trial will simply run again on resume.
      }
    }
    out.wall_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    return true;
  }

  // Live mode: one line redrawn in place every quarter second.
  void report_live() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!finished_) {
      wake_.wait_for(lock, std::chrono::duration<double>(0.25));
      if (finished_) break;
      *options_.progress << "\r\033[K" << progress_line(false) << std::flush;
    }
  }

  // Plain mode: the calling thread prints one line every `every` seconds until all are done.
  void report_plain() {
    std::unique_lock<std::mutex> lock(mutex_);
    auto next_line = Clock::now();
    while (done_ + stopped_ < pending_.size() && !(stop_ && running_ == 0)) {
      if (Clock::now() >= next_line) {
        *options_.progress << progress_line(false) << "\n" << std::flush;
        next_line = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                       std::chrono::duration<double>(options_.every));
      }
      wake_.wait_until(lock, next_line);
    }
  }

  const TrialFunction& run_;
  const BatchOptions& options_;
  std::vector<TrialOutcome> outcomes_;
  std::vector<size_t> pending_;
  size_t resumed_ = 0;
  const Clock::time_point start_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::atomic<size_t> next_{0};
  size_t done_ = 0, running_ = 0, stopped_ = 0;
  size_t failed_ = 0;  // of those done, and of those from an earlier run: an error.json
  int workers_ = 1;
  std::map<size_t, Clock::time_point> began_;  // when each running trial began, by its place in pending_
  std::vector<double> durations_;              // wall seconds of the trials that finished well
  std::exception_ptr stop_;  // the first FileError, or Interrupted: no worker starts another trial after it
  bool finished_ = false;
};

}  // namespace

TrialError::TrialError(const std::string& message, nlohmann::json details_in)
    : Error(message), details(std::move(details_in)) {}

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
  const int jobs = std::max(1, options.jobs > 0 ? options.jobs
                                                : int(std::max(1u, std::thread::hardware_concurrency())));
  return TrialPool(ids, run, options).run(jobs);
}

namespace {

// The policy file a trial reuses, or roger::Error saying why it is not there.
std::string policy_of(const std::string& out, const std::string& id) {
  const fs::path p = fs::path(trial_dir(out, id)) / "policy.json";
  if (fs::exists(p)) return p.string();
  const fs::path err = fs::path(trial_dir(out, id)) / "error.json";
  if (fs::exists(err)) {
    std::string msg;
    try {
      const nlohmann::json e = read_json_file(err.string());
      msg = e.is_object() ? e.value("error", std::string()) : std::string();
    } catch (const std::exception& e) {
      msg = e.what();
    }
    throw Error("needs the policy of trial " + id + ", which failed: " + first_line(msg));
  }
  throw Error("needs the policy of trial " + id + ", which has not run yet (run it first, e.g. --only " +
              id.substr(0, id.rfind('/')) + ")");
}

// A training trial: trains the run's stage and context with the trial's seed, reusing the
// policies of the same trial index of the runs its skills come from.
nlohmann::json training_trial(const BatchPlan& plan, const PlannedTrial& t, const std::string& dir,
                              const RunControl& control) {
  TrainOptions o;
  o.limits = plan.script->limits;
  o.eval_cache = control.eval_cache;
  o.explain = control.explain;
  o.curriculum = plan.script->curriculum_file;
  o.stage = t.run->stage;
  o.context = t.context;
  o.seed = t.seed;
  o.sets = t.run->params;
  o.sets_from = "the params of run '" + t.run->name + "'";
  if (t.run->own_final_worlds) o.final_worlds_block = uint64_t(t.index);  // final_worlds = "own"
  std::map<std::string, std::string> skill_ids;
  for (const auto& s : t.run->skills) {
    const std::string from = batch_trial_id(s.run, s.context, t.index);
    o.skill_files[s.skill] = policy_of(plan.out, from);
    // Named by its place in the results folder in the trial's files (found by a probe: a relative
    // --out was recorded as typed, so two runs into two folders were never the same files).
    o.skill_file_names[s.skill] = "trials/" + from + "/policy.json";
    skill_ids[s.skill] = from;
  }
  // A trial that faults keeps what it had trained beside its error.json (which run_one then
  // writes over with the trial's details): its episodes and checkpoints, for finding the cause.
  TrainResult progress;
  o.progress_on_fault = &progress;
  TrainResult r;
  try {
    r = train_stage(o);
  } catch (const FileError&) {
    throw;
  } catch (const std::exception& e) {
    try {
      write_faulted_train_outputs(progress, e.what(), dir);
    } catch (const std::exception&) {
      // The fault is what the trial records; its episodes are a help, not a result.
    }
    throw;
  }
  write_train_outputs(r, dir);
  nlohmann::json j = train_summary_json(r);
  j["id"] = t.id;
  j["final_outcomes"] = r.final_eval.outcomes;  // for the sorting tables' intervals
  j["run"] = t.run->name;
  j["trial"] = t.index;
  j["set_params"] = planned_params_json(t);
  // Paths inside the results folder, so results do not depend on where the folder is.
  std::vector<std::string> policies;
  for (const auto& [skill, from] : skill_ids)
    if (j.contains("skills") && j["skills"].contains(skill)) {
      j["skills"][skill]["file"] = "trials/" + from + "/policy.json";
      j["skills"][skill]["trial"] = from;
      policies.push_back("trials/" + from + "/policy.json");
    }
  j["policies"] = policy_fingerprints(plan.out, policies);  // a retrained skill's users run again
  j["engine"] = ROGER_ENGINE_FINGERPRINT;
  nlohmann::json cps = nlohmann::json::array();
  for (const auto& c : r.checkpoints) cps.push_back(checkpoint_json(c));
  j["checkpoints"] = cps;
  j["sources"] = source_fingerprints(r.source_files);  // a resumed run compares them (check_manifest)
  return j;
}

// Where an evaluation trial's worlds start, past the first seed. Each shape has layouts of its own:
// a seed places Roger, the goal, the object and the obstacles the same whatever the shape, so
// shapes on common seeds would count each layout once per shape. With worlds of their own
// (the default) shape k's trial i starts at (k * trials + i) * episodes, so no two episodes of
// the evaluation share a layout; shared worlds give every policy shape k's episodes from
// k * episodes (common random numbers between policies, not between shapes).
uint64_t evaluation_seed_offset(const BatchEvaluation& e, const PlannedTrial& t) {
  const std::vector<std::string> groups = batch_eval_groups(e);
  const uint64_t k = uint64_t(std::find(groups.begin(), groups.end(), t.shape) - groups.begin());
  const uint64_t n = uint64_t(e.episodes);
  return e.shared_worlds ? k * n : (k * uint64_t(e.trials) + uint64_t(t.index)) * n;
}

// An evaluation trial: the policy of a trained trial, without retraining, in the evaluation's
// worlds (evaluation_seed_offset). Its episodes go to eval.jsonl in `dir`, before result.json,
// so that every number the report reads from result.json can be checked against them.
nlohmann::json evaluation_trial(const BatchPlan& plan, const PlannedTrial& t, const std::string& dir,
                                Clock::time_point t0) {
  const BatchEvaluation& e = *t.evaluation;
  const std::string from = batch_trial_id(e.run, e.context, t.index);
  PolicyEvalOptions o;
  o.limits = plan.script->limits;
  o.curriculum = plan.script->curriculum_file;
  o.policy_file = policy_of(plan.out, from);
  o.scenario = e.scenario;
  o.sets = e.params;
  if (!e.shapes.empty()) o.sets.emplace_back("shape", t.shape);
  o.episodes = e.episodes;
  o.first_seed = e.first_seed;
  o.seed_offset = evaluation_seed_offset(e, t);
  o.keep_episodes = true;
  nlohmann::json skills = nlohmann::json::object();
  for (const BatchSkill& s : e.skills) {
    const std::string source = batch_trial_id(s.run, s.context, t.index);
    o.skill_files[s.skill] = policy_of(plan.out, source);
    skills[s.skill] = "trials/" + source + "/policy.json";
  }
  const PolicyEvalResult r = evaluate_policy_file(o);
  nlohmann::json params = nlohmann::json::object();
  for (const auto& [k, v] : r.params) params[k] = v;
  nlohmann::json j = eval_summary_json(r.eval);
  j.update({{"id", t.id},
            {"evaluation", e.name},
            {"run", e.run},
            {"context", e.context},
            {"trial", t.index},
            {"shape", t.shape},
            {"policy", "trials/" + from + "/policy.json"},
            {"stage", r.stage},
            {"scenario", r.scenario},
            {"params", params},
            {"set_params", planned_params_json(t)},
            {"skills", skills},
            {"wall_s", std::chrono::duration<double>(Clock::now() - t0).count()}});
  j["outcomes"] = r.eval.outcomes;  // each episode's, for the report's intervals (report_evaluations.cpp)
  write_file_atomic((fs::path(dir) / kEvalEpisodesFile).string(), eval_episode_lines(r.eval),
                    "cannot write the evaluation's episodes");
  j["episodes_file"] = kEvalEpisodesFile;  // checked by trial_status (records.cpp)
  j["sources"] = source_fingerprints(r.source_files);
  std::vector<std::string> policies{"trials/" + from + "/policy.json"};
  for (const auto& [skill, file] : skills.items()) policies.push_back(file.get<std::string>());
  j["policies"] = policy_fingerprints(plan.out, policies);  // a retrained policy's evaluations run again
  j["engine"] = ROGER_ENGINE_FINGERPRINT;
  return j;
}

// What error.json records about a trial's fault beside its message: the trial's kind and seed, and
// where it happened (the script's file and line, the episode and its world seed) when known.
nlohmann::json fault_details(const PlannedTrial& t, const std::exception& e) {
  nlohmann::json d = {{"kind", t.run ? "train" : "eval"}, {"index", t.index}};
  if (t.run) d["seed"] = t.seed;
  if (const auto* f = dynamic_cast<const EpisodeFault*>(&e)) {
    d["phase"] = f->phase;
    d["episode"] = f->episode;
    d["world_seed"] = f->world_seed;
    if (!f->file.empty()) d["file"] = f->file;
    if (f->line > 0) d["line"] = f->line;
  } else if (const auto* s = dynamic_cast<const ScriptError*>(&e)) {
    if (!s->file.empty()) d["file"] = s->file;
    if (s->line > 0) d["line"] = s->line;
  }
  return d;
}

// The trials of one phase this invocation runs: selected, and within the budget of new trials.
// A trial that failed in an earlier invocation is tried again, and so is one whose files are
// corrupt (said on the log): a trial is finished only when its records are sound.
// Counts in `undiagnosed` the finished training trials without a diagnosis under --explain (a run
// runs no finished trial again, so they keep their result as it is).
std::vector<std::string> phase_ids(const BatchPlan& plan, const std::vector<PlannedTrial>& phase,
                                   const RunControl& control, int& budget, std::set<std::string>& names,
                                   int& undiagnosed) {
  std::vector<std::string> ids;
  std::error_code ec;
  for (const auto& t : phase) {
    if (!control.shard.owns(t) || !trial_selected(t, control.only)) continue;
    const fs::path dir = trial_dir(plan.out, t.id);
    nlohmann::json result;
    std::string problem;
    const std::string status = trial_status(plan.out, t, result, problem);
    if (status == "corrupt" && control.log)
      *control.log << "roger run: " << first_line(problem) << "; running trial " << t.id << " again\n";
    if (status == "failed" || status == "corrupt") {  // run again from an empty folder
      fs::remove(dir / "result.json", ec);
      fs::remove(dir / "error.json", ec);
    }
    const bool finished = status == "ok";
    if (finished && control.explain && t.run && !result.contains("diagnosis")) ++undiagnosed;
    if (!finished) {
      if (budget == 0) continue;
      if (budget > 0) --budget;
    }
    ids.push_back(t.id);
    names.insert(t.run ? t.run->name : "eval/" + t.evaluation->name);
  }
  return ids;
}

// Writes a run's progress into `out`: status.json, and status.js, the same object for a page
// opened from the file system.
void write_status_files(const std::string& out, const nlohmann::json& status) {
  write_file_atomic((fs::path(out) / "status.json").string(), status.dump(1) + "\n", "cannot write status.json");
  write_file_atomic((fs::path(out) / "status.js").string(),
                    "// Generated by roger run: its progress for index.html (a copy of status.json).\n"
                    "window.ROGER_STATUS = " + status.dump() + ";\n",
                    "cannot write status.js");
}

// The time a run has left, from the trials it times itself: a trial starts about when its folder
// is first seen and ends about when its result is (each the middle of the second between two
// scans, which StatusWriter makes once a second). Each trial not finished costs the mean time of
// the trials of its run that finished in this invocation (a run's curriculum has a cost of its
// own), else of those of its kind (training or evaluation: an evaluation is far cheaper), less
// what a started one already ran; the sum is shared among as many workers as were seen busy at
// once, and is never less than the longest running trial still needs. A kind none of whose trials
// finished yet is not costed: its trials are counted apart (eta_uncounted), not guessed at.
class TimeLeft {
 public:
  // A trial found finished, or started, when the run began (a folder left by a run killed or
  // stopped): neither is timed, nor is the latter counted as busy.
  void earlier(const std::string& id, const std::string& state) {
    if (state == "done" || state == "failed") finished_.insert(id);
    if (state == "started") earlier_.insert(id);
  }
  void begin_scan(double elapsed) {
    elapsed_ = elapsed;
    seen_at_ = 0.5 * (last_scan_s_ + elapsed);
    open_.clear();
    busy_now_ = 0;
  }
  // One trial's state at this scan.
  void trial(const PlannedTrial& t, const std::string& state) {
    const int kind = t.run ? 0 : 1;
    const std::string run = t.run ? t.run->name : "";
    if (state == "pending" || (state == "started" && earlier_.count(t.id))) {
      open_.push_back({kind, -1, run});
    } else if (state == "started") {
      ++busy_now_;
      open_.push_back({kind, elapsed_ - began_.emplace(t.id, seen_at_).first->second, run});
    } else if (finished_.insert(t.id).second && state == "done" && !earlier_.count(t.id)) {
      // A failed trial may have stopped at once, and one an earlier run had begun was never seen
      // to begin: either would make the mean too short.
      // One never seen started began and ended between two scans: half the interval, as likely
      // as any (zero made a run of sub-second trials, quick.lua on idle cores, read "0 s left").
      const auto b = began_.find(t.id);
      const double d = b == began_.end() ? 0.5 * (elapsed_ - last_scan_s_) : std::max(0.0, seen_at_ - b->second);
      durations_[kind].push_back(d);
      if (t.run) by_run_[run].push_back(d);
    }
  }
  void end_scan() {
    last_scan_s_ = elapsed_;
    busy_ = std::max(busy_, busy_now_);
  }
  // eta_s (null until a trial of some kind was timed) and eta_uncounted of this scan.
  std::pair<nlohmann::json, nlohmann::json> estimate() const {
    double work = 0, longest = 0;
    size_t uncounted[2] = {0, 0};
    bool costed = false;
    for (const auto& o : open_) {
      const std::vector<double>* timed = &durations_[o.kind];
      const auto r = by_run_.find(o.run);
      if (r != by_run_.end() && !r->second.empty()) timed = &r->second;
      if (timed->empty()) {
        ++uncounted[o.kind];
        continue;
      }
      const double mean = std::accumulate(timed->begin(), timed->end(), 0.0) / double(timed->size());
      const double rest = o.ran < 0 ? mean : std::max(0.0, mean - o.ran);
      work += rest;
      if (o.ran >= 0) longest = std::max(longest, rest);
      costed = true;
    }
    nlohmann::json eta = nullptr, left_out = nlohmann::json::object();
    if (!costed) return {eta, left_out};
    if (uncounted[0]) left_out["training"] = uncounted[0];
    if (uncounted[1]) left_out["evaluation"] = uncounted[1];
    return {std::max(work / double(std::max<size_t>(1, busy_)), longest), left_out};
  }

 private:
  struct Open {
    int kind;           // 0 training, 1 evaluation
    double ran;         // seconds it has run, -1 when not started
    std::string run;    // its run's name ("" for an evaluation)
  };
  double elapsed_ = 0, seen_at_ = 0, last_scan_s_ = 0;
  std::vector<Open> open_;
  size_t busy_now_ = 0, busy_ = 0;
  std::map<std::string, double> began_;  // when each trial of this invocation was first seen started
  std::set<std::string> finished_, earlier_;
  std::vector<double> durations_[2];     // of the trials that finished well: training, evaluation
  std::map<std::string, std::vector<double>> by_run_;  // the training durations, by run
};

// The progress of a run for the results folder's dashboard (index.html): status.json, and the same
// object as status.js for a page opened from the file system, where it cannot fetch() a file but
// can (re)load a script. Rewritten atomically at most once a second by its own thread from what is
// on disk (result.json, error.json, a trial's folder), so it never slows or changes a trial.
// A trial's state from its folder: "done", "failed", "started" (files, no record) or "pending".
std::string trial_state(const std::string& dir) {
  std::error_code ec;
  if (fs::exists(fs::path(dir) / "result.json", ec)) return "done";
  if (fs::exists(fs::path(dir) / "error.json", ec)) return "failed";
  if (fs::exists(dir, ec)) return "started";
  return "pending";
}

// A status's counts of the plan's trials as their folders have them: per run/context and
// evaluation (in plan order), with totals and the trials started and not finished. `each` (when
// given) sees every trial and its state.
nlohmann::json trial_counts(const BatchPlan& plan,
                            const std::function<void(const PlannedTrial&, const std::string&)>& each = {}) {
  std::vector<std::string> order;
  std::map<std::string, nlohmann::json> groups;
  size_t total = 0, done = 0, failed = 0, started = 0;
  nlohmann::json started_ids = nlohmann::json::array();
  for (const auto& p : plan.phases)
    for (const auto& t : p) {
      const std::string group = t.run ? t.run->name + "/" + t.context : "eval/" + t.evaluation->name;
      if (!groups.count(group)) {
        order.push_back(group);
        groups[group] = {{"group", group}, {"trials", 0}, {"done", 0}, {"failed", 0}, {"started", 0}};
      }
      const std::string state = trial_state(trial_dir(plan.out, t.id));
      if (each) each(t, state);
      nlohmann::json& g = groups[group];
      g["trials"] = g["trials"].get<int>() + 1;
      ++total;
      if (state == "pending") continue;
      g[state] = g[state].get<int>() + 1;
      (state == "done" ? done : state == "failed" ? failed : started) += 1;
      if (state == "started") started_ids.push_back(t.id);
    }
  nlohmann::json list = nlohmann::json::array();
  for (const auto& k : order) list.push_back(groups[k]);
  return {{"trials", total}, {"done", done}, {"failed", failed}, {"started", started}, {"started_ids", started_ids},
          {"groups", list}};
}

class StatusWriter {
 public:
  StatusWriter(const BatchPlan& plan, const Shard& shard)
      : plan_(plan), shard_(shard), start_(Clock::now()), wall_start_(std::chrono::system_clock::now()) {
    remember_earlier();
    write(true);
    thread_ = std::thread([this] { loop(); });
  }
  // Whether Ctrl-C (or SIGTERM) stopped the run: the final status says so, for the page.
  void set_interrupted(bool interrupted) { interrupted_ = interrupted; }
  // Writes the final status of the trials (running: false, finishing: true: the command still
  // writes its report, then its closing status: write_closing_status
  // in engine/cli/run.cpp) and stops the thread.
  ~StatusWriter() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
    write(false);
  }

 private:
  void loop() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!wake_.wait_for(lock, std::chrono::seconds(1), [this] { return stop_; })) write(true);
  }
  // Remembers the trials finished or started before this invocation, for the time left.
  void remember_earlier() {
    for (const auto& p : plan_.phases)
      for (const auto& t : p) time_left_.earlier(t.id, trial_state(trial_dir(plan_.out, t.id)));
  }
  // The trials' counts (trial_counts) and an estimate of the time left (TimeLeft, which this
  // once-a-second scan feeds).
  nlohmann::json scan(bool running) {
    const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
    time_left_.begin_scan(elapsed);
    const nlohmann::json counts =
        trial_counts(plan_, [this](const PlannedTrial& t, const std::string& state) { time_left_.trial(t, state); });
    time_left_.end_scan();
    const size_t left = counts["trials"].get<size_t>() - counts["done"].get<size_t>() - counts["failed"].get<size_t>();
    auto [eta, uncounted] = running ? time_left_.estimate() : std::make_pair(nlohmann::json(), nlohmann::json::object());
    const auto epoch_ms = [](std::chrono::system_clock::time_point t) {
      return std::chrono::duration_cast<std::chrono::milliseconds>(t.time_since_epoch()).count();
    };
    std::error_code ec;
    nlohmann::json j = {{"format", "roger-status"}, {"running", running}, {"finishing", !running},
                        {"interrupted", interrupted_},
                        {"updated_ms", epoch_ms(std::chrono::system_clock::now())},
                        {"started_ms", epoch_ms(wall_start_)}, {"elapsed_s", elapsed},
                        {"eta_s", eta}, {"eta_uncounted", uncounted},
                        // What the page names before a report exists, and the command that
                        // continues the run (a killed run's page says it): the batch script as
                        // given, and the folder.
                        {"name", plan_.script->name}, {"script", plan_.script->path},
                        {"folder", fs::absolute(plan_.out, ec).lexically_normal().string()},
                        // Whether the folder holds a report (an earlier one while the run runs):
                        // the page asks for dashboard.js only then, or once the closing status
                        // says the report is written.
                        {"dashboard", fs::exists(fs::path(plan_.out) / "dashboard.js", ec)}};
    j.update(counts);
    if (shard_.active()) {
      j["shard"] = std::to_string(shard_.index) + "/" + std::to_string(shard_.count);
      // Every shard's state, from their records: the page tells an interrupted shard from one that
      // has not started (found by a probe: a cancelled shard read as queued, "No news").
      j["shards"] = shards_.read(plan_, shard_.count);
      j["slurm"] = shard_.slurm;
      // A shard writes no report, and its final status is the closing one (roger run writes none
      // after a shard): the run then waits for the other shards (their trials are not over, an
      // interrupted shard's own among them), or, once every trial is, for `roger report` (the
      // report job).
      if (!running) {
        j["finishing"] = false;
        j["waiting"] = left > 0 ? "shards" : "report";
      }
    }
    return j;
  }
  // Called by the thread under the mutex, and by the destructor once the thread is gone.
  void write(bool running) {
    try {
      write_status_files(plan_.out, scan(running));
    } catch (const std::exception&) {
      // Progress for a page is a convenience: a full disk must not stop the trials.
    }
  }

  const BatchPlan& plan_;
  const Shard shard_;
  const Clock::time_point start_;
  const std::chrono::system_clock::time_point wall_start_;
  bool interrupted_ = false;
  TimeLeft time_left_;
  ShardBoard shards_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
};

// Moves the failed, corrupt and pending trials outside the --only of `control` from `s`'s lists to
// its counts of trials outside it: this command neither ran them nor answers for them.
void split_outside_only(const BatchPlan& plan, const RunControl& control, BatchSummary& s) {
  if (control.only.empty()) return;
  std::map<std::string, const PlannedTrial*> by_id;
  for (const auto& p : plan.phases)
    for (const auto& t : p) by_id[t.id] = &t;
  const auto inside = [&](const std::string& line) {  // "id" or "id: message"; an id has no ':'
    const auto it = by_id.find(line.substr(0, line.find(':')));
    return it == by_id.end() || trial_selected(*it->second, control.only);
  };
  const auto split = [&](std::vector<std::string>& list, int& outside) {
    const auto mid = std::stable_partition(list.begin(), list.end(), inside);
    outside = int(list.end() - mid);
    list.erase(mid, list.end());
  };
  // From the lists read once: a part running beside this one changes the folder meanwhile.
  split(s.failed, s.outside_failed);
  split(s.corrupt, s.outside_corrupt);
  split(s.pending_ids, s.outside_pending);
  s.pending = int(s.pending_ids.size());
}

}  // namespace

namespace {

// What running the phases left: whether a signal stopped them, and the trials passed over
// undiagnosed (phase_ids).
struct PhasesRun {
  bool interrupted = false;
  int undiagnosed = 0;
};

// Each phase's trials that this run (or shard) takes, in turn, `trial` running each; a signal
// stops the phases where they are (what finished is on disk; the report and summary.csv say the
// rest is pending).
PhasesRun run_phases(const BatchPlan& plan, const RunControl& control, const TrialFunction& trial) {
  BatchOptions bo;
  bo.jobs = control.jobs;
  bo.out_dir = plan.out;
  bo.progress = control.log;
  bo.live = control.live;
  int budget = control.max_trials > 0 ? control.max_trials : -1;
  PhasesRun run;
  for (size_t k = 0; k < plan.phases.size() && !run.interrupted; ++k) {
    std::set<std::string> names;
    const std::vector<std::string> ids = phase_ids(plan, plan.phases[k], control, budget, names, run.undiagnosed);
    if (ids.empty()) continue;
    std::string label;
    for (const auto& n : names) label += (label.empty() ? "" : ", ") + n;
    if (control.log)
      *control.log << "roger run: phase " << (k + 1) << "/" << plan.phases.size() << ": " << label << " ("
                   << ids.size() << (ids.size() == 1 ? " trial)\n" : " trials)\n");
    try {
      run_trials(ids, trial, bo);
    } catch (const Interrupted&) {
      run.interrupted = true;
    }
  }
  return run;
}

}  // namespace

BatchSummary run_batch(const BatchPlan& plan, const RunControl& control) {
  std::map<std::string, const PlannedTrial*> by_id;
  for (const auto& p : plan.phases)
    for (const auto& t : p) by_id[t.id] = &t;
  SourceWatch sources(plan.script->curriculum_file, plan.script->limits, evaluation_scenarios(*plan.script));
  std::atomic<size_t> finished_now{0};  // trials this run finished (the others done were finished before)
  const TrialFunction trial = [&](const std::string& id, const std::string& dir) -> nlohmann::json {
    const PlannedTrial& t = *by_id.at(id);
    const auto t0 = Clock::now();
    try {
      sources.check();
      nlohmann::json result = t.run ? training_trial(plan, t, dir, control) : evaluation_trial(plan, t, dir, t0);
      // And after: a file edited while the trial loaded it would otherwise be in a result kept as
      // finished (found by the fault test once policies were compared: the trial before the stop
      // recorded the edited curriculum's digest). The trial is then not kept; the resumed run redoes it.
      sources.check();
      sources.learn(result["sources"]);  // a module a callback required: watched from now on
      ++finished_now;
      return result;
    } catch (const FileError&) {
      throw;  // not the trial's fault: the run stops (run_trials)
    } catch (const std::exception& e) {
      sources.check();  // a script removed or edited under the trial is the cause, not the trial
      throw TrialError(e.what(), fault_details(t, e));
    }
  };
  const auto start = Clock::now();
  std::optional<StatusWriter> status;
  status.emplace(plan, control.shard);
  const PhasesRun run = run_phases(plan, control, trial);
  // The trials' final status. The page waits for the closing one (write_closing_status), written
  // after the report, before it reloads dashboard.js: this one comes before the report exists.
  status->set_interrupted(run.interrupted);
  // A shard's record first, so that its final status reads its own state from it.
  BatchSummary summary =
      control.shard.active()
          ? record_shard(plan, control.shard, run.interrupted ? ShardState::interrupted : ShardState::ended)
          : summarize_trials(plan);
  status.reset();
  const double wall = std::chrono::duration<double>(Clock::now() - start).count();
  split_outside_only(plan, control, summary);
  summary.wall_s = wall;
  summary.interrupted = run.interrupted;
  summary.undiagnosed = run.undiagnosed;
  summary.finished_now = finished_now;
  return summary;
}

namespace {

void set_status_place(nlohmann::json& j, const std::string& out) {
  std::error_code ec;
  j["folder"] = fs::absolute(out, ec).lexically_normal().string();
  j["dashboard"] = fs::exists(fs::path(out) / "dashboard.js", ec);
}

}  // namespace

void refresh_status_place(const BatchPlan& plan) {
  const std::string& out = plan.out;
  try {
    std::error_code ec;
    if (!fs::is_regular_file(fs::path(out) / "status.json", ec)) return;
    nlohmann::json j = parse_json(read_file_text((fs::path(out) / "status.json").string()));
    set_status_place(j, out);
    // The counts as the trials' folders have them now (found by a probe: a killed run's last
    // status said 8 done and one started above a partial report of 9), and the shards' states;
    // a run still going writes its own again within a second.
    j.update(trial_counts(plan));
    if (j.contains("shards") && j["shards"].is_array())
      j["shards"] = ShardBoard().read(plan, int(j["shards"].size()));
    write_status_files(out, j);
  } catch (const std::exception&) {
    // As write_closing_status.
  }
}

void write_closing_status(const std::string& out, const std::string& report) {
  try {
    nlohmann::json j = parse_json(read_file_text((fs::path(out) / "status.json").string()));
    set_status_place(j, out);
    j["running"] = false;
    j["finishing"] = false;
    j.erase("waiting");  // a sharded run's last status, before roger report
    j["report"] = report;
    j["updated_ms"] = std::chrono::duration_cast<std::chrono::milliseconds>(
                          std::chrono::system_clock::now().time_since_epoch()).count();
    write_status_files(out, j);
  } catch (const std::exception&) {
    // The page says "no news" after 30 s without it.
  }
}

}  // namespace roger
