// batch.h: a run of a batch script. Its trials are planned in phases (a run's trials come after
// those of the runs whose skills they reuse) and run on a local thread pool, resumably, into one
// results folder. Owns: the plan, the pool, the manifest, the trial folders and summary.csv.
// Must not depend on report, view or cli (the report is written by whoever calls run_batch).
//
// Each trial is a pure function of its id (the id names its curriculum, stage, context and seed),
// so results do not depend on the number of threads; each finished trial commits one result file
// atomically, so a run that is interrupted (Ctrl-C, kill -9) resumes without losing or repeating
// a trial.
#pragma once

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "script/batch/batch_script.h"

namespace roger {

// How a batch runs.
struct BatchOptions {
  int jobs = 0;                    // worker threads; 0 = all cores
  std::string out_dir;             // results folder; trials go in <out_dir>/trials/<id>/
  std::ostream* progress = nullptr;// where progress goes (nullptr: none)
  bool live = false;               // a live bar redrawn in place (a terminal), else plain lines
  double every = 5.0;              // seconds between plain progress lines
};

// What happened to one trial.
struct TrialOutcome {
  std::string id;
  bool ok = false;            // it produced a result
  bool resumed = false;       // the result was already on disk from an earlier run
  nlohmann::json result;      // the trial's result (ok), or {"error": message}
  double wall_seconds = 0.0;  // this run's wall time for it (0 when resumed)
};

// An error of a trial with facts for its error.json beside the message (where a script failed,
// which episode, which seeds): error.json is `details` plus "error" (the message).
struct TrialError : Error {
  // The message and the facts (a JSON object).
  TrialError(const std::string& message, nlohmann::json details);
  nlohmann::json details;
};

// A trial: given its id and its own folder (created, empty), returns its result. It may write
// files into the folder (atomically); throwing records the error as the trial's result: error.json
// holds {"error": message, "trial": id} and, for a TrialError, its details. A roger::FileError (a
// full disk, a folder not writable, a script removed: the machine's fault, not the trial's) records
// nothing and stops the run (run_trials).
using TrialFunction = std::function<nlohmann::json(const std::string& id, const std::string& dir)>;

// Runs the trials not already finished in out_dir, `jobs` at a time, and returns every trial's
// outcome in the order of `ids`. A trial is finished when <dir>/result.json (or error.json)
// exists; a folder without either (a trial cut short) is emptied and run again. Ids are paths
// of safe characters ([A-Za-z0-9._-] segments separated by '/'), unique: otherwise roger::Error.
// After a trial throws a FileError no other trial starts; the running ones end, and the first
// FileError is rethrown (the trials finished so far are kept, so the same call resumes).
std::vector<TrialOutcome> run_trials(const std::vector<std::string>& ids, const TrialFunction& run,
                                     const BatchOptions& options);

// The folder of a trial within a results folder.
std::string trial_dir(const std::string& out_dir, const std::string& id);

// Formats seconds as a short duration for progress lines ("42 s", "3 min 05 s", "1 h 02 min").
std::string format_duration(double seconds);

// One trial of a batch script: a training trial of a run's context, or an evaluation trial.
struct PlannedTrial {
  std::string id;
  const BatchRun* run = nullptr;               // a training trial
  const BatchEvaluation* evaluation = nullptr; // or an evaluation trial
  std::string context, shape;
  int index = 0;
  uint64_t seed = 0;
};

// Every trial of a batch script, phase by phase, and the folder they go to.
struct BatchPlan {
  std::shared_ptr<const BatchScript> script;
  std::string out;                                 // the results folder
  std::vector<std::vector<PlannedTrial>> phases;   // a phase waits for the phases before it
};

// Plans the trials of `script` into `out`.
BatchPlan plan_batch(std::shared_ptr<const BatchScript> script, const std::string& out);

// The manifest.json of the results folder `dir`, checked: a JSON object of format
// "roger-results/1" whose "config" is an object, whose "engine" and "script" are strings, and whose
// "version" is a string where present. Throws roger::Error naming the file and what is wrong.
nlohmann::json read_manifest(const std::string& dir);

// The plan of the run that made the results folder `dir`, rebuilt from its manifest. Throws
// roger::Error when `dir` holds no readable manifest.
BatchPlan read_results_plan(const std::string& dir);

// One slice of a plan's trials for one process of many (a machine of a cluster): trial i of every
// run and context, and the evaluations of trial i's policies, belong to shard i mod count, so a
// shard never needs a trial that another shard owns.
struct Shard {
  int index = 0;  // K, 0-based
  int count = 0;  // N; 0 = not sharded (every trial)
  bool slurm = false;  // from --shard slurm: a task of a Slurm array (submit.sh runs it again)
  bool active() const { return count > 0; }
  bool owns(const PlannedTrial& t) const { return !active() || t.index % count == index; }
  // Where a shard that ran in a results folder records its outcome: <out>/shards/K-of-N.json.
  std::string record_path(const std::string& out) const {
    return out + "/shards/" + std::to_string(index) + "-of-" + std::to_string(count) + ".json";
  }
};

// Reads --shard: "K/N" with 0 <= K < N, or "slurm": K from SLURM_ARRAY_TASK_ID and N from
// ROGER_SHARDS or else SLURM_ARRAY_TASK_COUNT. Throws roger::Error saying what is expected.
Shard parse_shard(const std::string& text);

// A planned trial that has no result yet (neither result.json nor error.json), and, when shards
// ran in the folder, which shard owns it ("shard 2 of 3"; "" otherwise).
struct MissingTrial {
  const PlannedTrial* trial = nullptr;
  std::string owner;
  std::string problem;  // for a corrupt record: the file and what is wrong with it; "" when none
};

// The trials of the plan without a sound result or error in its folder, in plan order: those not
// run yet and those whose files are corrupt (truncated, empty, edited, another trial's).
std::vector<MissingTrial> missing_trials(const BatchPlan& plan);

// Whether a trial is chosen by `only` ("RUN", "RUN/CONTEXT", "eval" or "eval/NAME"; empty: all).
bool trial_selected(const PlannedTrial& trial, const std::vector<std::string>& only);

// Throws roger::Error, naming what exists, for a selector of `only` that chooses no trial.
void check_selectors(const BatchPlan& plan, const std::vector<std::string>& only);

// Refuses (roger::Error) a results folder `out` that exists, holds files and has no manifest.json:
// the results of a run whose manifest was removed (nothing tells which script made them, and new
// trials would mix with them), or another program's files that a run would write over. An empty
// folder, or one holding only the lock files of a run starting beside this one, is taken.
void check_out_folder(const std::string& out);

// Refuses (roger::Error), before any trial runs, an --only selection (of shard `shard`'s trials)
// whose trials still to run need the policies of trials outside it that have no result: each of
// them would fail, recorded as such. Names those trials and the --only that runs them.
void check_only_needs(const BatchPlan& plan, const std::vector<std::string>& only, const Shard& shard);

// Opens the results folder: writes its manifest (format, script, engine, configuration, trial
// ids and seeds), or, when one exists, checks that it was made by this engine build and the same
// configuration (else roger::Error saying what differs). A configuration that differs only in
// what trains nothing again (the report's name, description, tables and figures; more trials of
// a run, or of an evaluation whose worlds do not depend on their number: shared, or one shape)
// is taken: the manifest is rewritten with it and `note` (if given) says so.
// Returns true when resuming. Shards that open one folder at once take turns (a lock file), so
// the manifest is written by one at a time. A shard (`shard` active) is refused (roger::Error) in a
// folder whose shards/ records shards of another N, and records itself there as it starts.
// `claim` (may be null) is the run's: a plan that changes is refused while other parts run the old.
class RunningClaim;
bool open_results_folder(const BatchPlan& plan, std::string* note = nullptr, const Shard& shard = Shard(),
                         const RunningClaim* claim = nullptr);

// What roger run of the plan (as shard `shard`, when active) would find in its folder, said without
// writing or claiming anything (roger check --out; scripts/slurm/submit.sh asks before it queues
// the shards): throws the roger::Error open_results_folder would (a folder of another engine build
// or configuration, of shards of another N, holding other files, a file); otherwise returns what
// the run would do there ("a new results folder ...", "resumes DIR (12 of 50 trials have a result)").
std::string inspect_results_folder(const BatchPlan& plan, const Shard& shard = Shard());

// Why roger run (as shard `shard`, of the trials `only` selects) could not run in the results
// folder `out` now, said without making or claiming anything (roger run --dry-run): it, or the
// nearest folder above it, cannot be written, or another run holds it; "" when it could.
std::string results_folder_unavailable(const std::string& out, const Shard& shard,
                                       const std::vector<std::string>& only = {});

// A results folder claimed by one roger run for as long as this lives. A run of the whole folder
// holds it alone; runs of parts of it (a --shard, --only names) hold it together, each part once.
// A second run of a folder or part in use would empty the first's trials in flight (a resume runs
// a trial without a result afresh) and the first would fail writing into them, so it is refused:
// roger::Error naming who holds it and what to do. So is a part that shares a trial with a part
// running ("--shard 1/2 --only SG" beside "--shard 1/2"); parts that share none run together.
// Released when destroyed, or however the process ends (flock on <out>/.running, and on
// <out>/.running-<part> for a part, which names its part for the others).
class RunningClaim {
 public:
  RunningClaim(const std::string& out, const Shard& shard, const std::vector<std::string>& only = {});
  ~RunningClaim();
  RunningClaim(const RunningClaim&) = delete;
  RunningClaim& operator=(const RunningClaim&) = delete;
  // The other parts of the folder running now ("--shard 0/2 (pid 12 on node3)"); none for a run of
  // the whole folder, which holds it alone.
  std::vector<std::string> others_running() const;

 private:
  std::string out_;
  std::string own_file_;  // this part's claim file's name; "" for the whole folder
  int whole_ = -1;        // <out>/.running: exclusive for a run of the whole folder, shared by parts
  int own_ = -1;          // a part's <out>/.running-<part>, exclusive
};

// The line roger run prints for a shard: the trial indices it runs and how many trials, or that it
// has none (more shards than the plan's runs and evaluations have trials).
std::string describe_shard(const BatchPlan& plan, const Shard& shard);

// How run_batch runs the plan.
struct RunControl {
  int jobs = 0;                     // worker threads; 0 = all cores
  bool live = false;                // redraw one progress line in place (a terminal)
  int max_trials = 0;               // > 0: stop after starting this many new trials
  std::vector<std::string> only;    // selectors (see trial_selected)
  std::ostream* log = nullptr;      // progress and messages (nullptr: none)
  Shard shard;                      // only this shard's trials; a shard writes no summary.csv
  bool eval_cache = true;           // reuse greedy evaluation episodes (TrainOptions::eval_cache)
  bool explain = false;             // a diagnosis in every training result (TrainOptions::explain)
};

// What a run of the plan left in its folder. For a run with --only (RunControl::only), `failed`,
// `corrupt` and `pending` are its selection's, and the trials outside it are counted apart: they
// are not this command's (another run's, maybe running beside it). A shard's counts are its own.
struct BatchSummary {
  size_t trials = 0;                // in the plan (a shard: its own trials)
  std::vector<std::string> failed;  // "id: first line of the error"
  std::vector<std::string> corrupt; // "id: <file>: what is wrong" (a record that cannot be read)
  int pending = 0;                  // not run yet
  std::vector<std::string> pending_ids;  // their ids
  int outside_pending = 0;          // outside --only: not run yet
  int outside_failed = 0;           // outside --only: failed (in an earlier or another run)
  int outside_corrupt = 0;          // outside --only: with a record that cannot be read
  int undiagnosed = 0;              // under --explain: training trials finished earlier, without a diagnosis
  size_t finished_now = 0;          // trials this invocation finished (the other done ones, earlier runs)
  double wall_s = 0.0;              // this invocation's wall time
  bool interrupted = false;         // Ctrl-C (core/interrupt.h) stopped it before its selection was done
  std::string summary_csv;          // summary.csv's text (empty for a shard's): write_summary_csv writes it
};

// Runs the selected trials of the plan that are not finished, phase by phase (trials that failed
// before are tried again), then reads what is on disk into the summary (summary.csv's text, which
// the caller writes after the report, so that the two never disagree); a shard instead records
// its own outcome in <out>/shards/K-of-N.json, since other shards may still be running. A stop
// requested by Ctrl-C (core/interrupt.h) ends it early the same way: the trials in flight are left
// for the resumed run, the finished ones are kept.
BatchSummary run_batch(const BatchPlan& plan, const RunControl& control);

// The run's closing status, after its report (or the decision to write none): the folder's
// status.json and status.js as run_batch's final status left them, no longer "finishing", with
// what became of the report ("written", "failed" or "none"). The dashboard reloads dashboard.js
// only once it reads this, so it never takes a previous run's report for this one's, however long
// the report takes. `roger report` writes it too, for a sharded run (whose shards write no
// report). Does nothing in a folder without a status.json. Never throws: progress for a page is a
// convenience.
void write_closing_status(const std::string& out, const std::string& report);

// The folder's status.json (and status.js) with its place as it is now and whether it holds a
// report (`folder`, `dashboard`), and the trials' counts as their folders have them, the rest as
// it was: a folder moved or copied since its run named the old place, and its page's commands
// continued or reported that one (found by a probe). write_closing_status does the place too.
// Does nothing without a status.json; never throws.
void refresh_status_place(const BatchPlan& plan);

// What the plan's trials' records say: failed, corrupt and pending trials, and summary.csv's
// text, one row per planned trial (pending ones included).
BatchSummary summarize_trials(const BatchPlan& plan);
// Writes <out>/summary.csv from summary.summary_csv: after the report (tables.md, report.json,
// the figures), since a kill between the two must not leave a summary that says more than the
// report does (found by a probe: all 24 trials ok beside a report of 8).
void write_summary_csv(const BatchPlan& plan, const BatchSummary& summary);

}  // namespace roger
