// report_internal.h: what the files of report/ share, private to the folder. The report is one
// concept told in several parts, a file each, around one reading of the results folder:
//   report_folder.cpp       Folder (the folder read once, its results checked by batch first), numbers
//                           pooled over evaluations, formatting
//   report_runs.cpp         Tables I and II: a run's contexts against its baseline, usage, misses
//   report_evaluations.cpp  Table III: evaluations per shape, their distinct layouts, 95% intervals
//   report_sorting.cpp      sorting tables: hand-written and learned policies per number of objects
//   report_figures.cpp      learning curves, IQM curves, cumulative training time
//   report.cpp              write_report: tables.md, report.json, the figures' list, the dashboard
// Each table appends its Markdown to `md` and its numbers to `rep` (report.json's "tables").
#pragma once

#include <cstdint>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/batch.h"
#include "report/stats.h"
#include "script/batch/batch_script.h"

namespace roger::report_detail {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr uint64_t kBootstrapSeed = 20240601;  // fixed: the same folder gives the same intervals
constexpr int kCurvePoints = 200;              // the learning curves' common grid
// A run table's field for the dashboard alone, dropped from report.json: each context's actions in
// the order tables.md lists them (its usage object's keys come sorted by name).
constexpr const char* kUsageOrder = "usage_order";

// One number formatted by printf's format f.
std::string fmt(const char* f, double v);

// Bin b of `bins` equal bins over [lo, hi], as "0.92 to 1.04": each edge to two decimal places
// finer than the bins' width, so that neighbouring bins read apart and each edge within half a
// percent of a bin of where it lies (two significant digits wrote 1.16 to 1.28 as "1.2 to 1.3").
std::string bin_label(double lo, double hi, int b, int bins);

// A fraction as a percentage with one decimal: 0.975 -> "97.5%".
std::string pct(double fraction);

// A success rate as a percentage: pct's, with more digits where one decimal would round a rate
// that is not 1 to "100.0%" (0.9996 -> "99.96%") or a rate above 0 to "0.0%".
std::string rate_pct(double rate);

// " with k=v k=v" for a table head's scenario parameters ("" for none), so that a run or an
// evaluation on another body never reads as one on the stage's.
std::string with_params(const std::vector<std::pair<std::string, std::string>>& params);

// One context's (or group's) finished trials.
struct Results {
  std::vector<json> ok;  // result.json of every finished trial, in trial order
  int failed = 0, pending = 0, expected = 0;
};

// Where a trial of the folder `dir` stands: with its result, failed (its error.json), or pending.
enum class TrialState { kResult, kFailed, kPending };
TrialState trial_state(const std::string& dir, const std::string& id);

// How many of a plan's trials have a result in its folder, and how many do not yet.
struct Completeness {
  int trials = 0, with_results = 0, pending = 0, failed = 0;
  bool partial() const { return with_results < trials; }
};
Completeness completeness(const BatchPlan& plan);

// tables.md's line saying a report is partial: how many trials have results, how many do not.
std::string partial_line(const Completeness& c);
// report.json's "partial": {"trials", "with_results", "pending", "failed"}.
json partial_json(const Completeness& c);

// The results folder, read once.
class Folder {
 public:
  // Reads the records in `dir`; figures go to `out` (a staging folder that write_report moves
  // into `dir` once the whole report is written).
  Folder(const std::string& dir, const std::string& out) : dir_(dir), out_(out) {}
  // The trials of these ids: each finished one's checked result.json, and how many failed or wait.
  Results trials(const std::vector<std::string>& ids) const;
  // Every trial of one context of a run.
  Results run(const BatchRun& run, const std::string& context) const;
  const std::string& dir() const { return dir_; }
  // Where figures are written.
  const std::string& out() const { return out_; }

 private:
  std::string dir_, out_;
};

// A trial result's number `key`; a roger::Error when it has none.
double num(const json& j, const char* key);

// A result's "usage" (checked when read), or an empty one when it has none.
const json& usage_of(const json& j);

// The trials' times-to-threshold, censored where the threshold was never reached.
std::vector<CensoredTime> times_of(const Results& r);

// Pooled figures of several greedy evaluations of `episodes` episodes each (rewards and successes).
struct Pooled {
  double mean = 0, std = 0, success = 0;
  int64_t episodes = 0;  // summed over trials: may pass 2^31
};

// Pools evaluations whose episode counts are under `episodes_key`.
Pooled pool(const std::vector<json>& evals, const char* episodes_key);

// "48/50", with how many failed or are pending.
std::string trials_note(const Results& r);

// A row of a run table (label: the context, or "run/context" in a comparison) against the baseline's
// times; appends its numbers to rows; returns whether some trials never reached the threshold.
bool run_table_row(const std::string& label, const Results& r, const BatchTable& t,
                   const std::vector<CensoredTime>& base_times, double base_mean, std::ostringstream& md, json& rows);
// The paragraph under a run table saying what its columns mean.
void run_table_notes(bool any_censored, std::ostringstream& md);

constexpr int kRateResamples = 10000;  // the pooled success rates' bootstrap (pooled_rate_interval)

// Appends one trial's cells of a pooled success rate (stats.h, RateCell) under `policy`: one per
// episode, its layout the episode's world seed (the first seed + k), its outcome from the trial's
// per-episode outcomes ("1101..."). A result written before they were recorded gives each episode
// the trial's rate, so a resample of layouts sees no layout harder than another there.
void append_rate_cells(const json& j, int64_t policy, const char* first_seed_key, const char* episodes_key,
                       const char* outcomes_key, std::vector<RateCell>& cells);

// How an interval was resampled, for report.json: "policies", "layouts", "policies and layouts".
std::string resampled_name(Resampled by);

// The sentence under a table that says how its success rates' intervals were made.
std::string interval_note(const std::set<Resampled>& methods);

// Table I / II: a run's contexts against its baseline (report_runs.cpp).
void run_table(const BatchScript& b, const BatchTable& t, const Folder& folder, std::ostringstream& md, json& rep);

// Table III: an evaluation per shape, and a Total row (report_evaluations.cpp).
void eval_table(const BatchScript& b, const BatchTable& t, const Folder& folder, std::ostringstream& md, json& rep);

// A comparison of contexts of several runs (teachers on one context) against the first, with the
// run table's columns (report_teachers.cpp).
void compare_table(const BatchScript& b, const BatchTable& t, const Folder& folder, std::ostringstream& md, json& rep);

// Under a table of rows whose stages teach: what success means with a test set, the training tasks
// skipped and what each trial's teacher did (into table's "skipped_tasks" and "teachers").
void teaching_notes(const BatchScript& b, const std::vector<BatchRow>& rows, const Folder& folder,
                    std::ostringstream& md, json& table);

// The final evaluations' success rate split by a recorded feature of each episode (its task's
// parameter or its world's obstacles, objects or shape), a row per context (report_teachers.cpp).
// What a by-table found in the final-evaluation records it read.
struct ByFound {
  int64_t records = 0;             // read, with or without the feature
  bool feature = false;            // whether any of them has the table's feature
  std::set<std::string> features;  // the features they have
};
ByFound by_table(const BatchScript& b, const BatchTable& t, const Folder& folder, std::ostringstream& md, json& rep);

// A sorting table, one row per number of objects (report_sorting.cpp).
void sorting_table(const BatchScript& b, const BatchTable& t, const Folder& folder, std::ostringstream& md, json& rep);

// A run's learning curves (Figures 3 and 4); whether drawn (report_figures.cpp).
bool curves_figure(const BatchScript& b, const BatchFigure& f, const Folder& folder, std::vector<std::string>& written,
                   json& page);

// The IQM figure's file name without extension: "iqm_<run>".
std::string iqm_file(const BatchRun& run);

// The IQM learning curves of a run's stage; its line for tables.md (report_figures.cpp).
std::string iqm_figure(const BatchScript& b, const BatchRun& run, const Folder& folder,
                       std::vector<std::string>& written);

// Where a run's teacher sampled one parameter against training episodes, pooled over its trials
// (a heat map); whether drawn (report_teachers.cpp).
bool tasks_figure(const BatchScript& b, const BatchFigure& f, const Folder& folder, std::vector<std::string>& written,
                  json& page);

// " (B2, DC3 pending)": which of a figure's curves or contexts lack some or all of their trials'
// results; "" when none does (report_figures.cpp).
std::string figure_pending_note(const BatchScript& b, const BatchFigure& f, const Folder& folder);

// Cumulative training time per context; whether drawn (report_figures.cpp).
bool cumulative_figure(const BatchScript& b, const BatchFigure& f, const Folder& folder, std::vector<std::string>& written,
                       json& page);

}  // namespace roger::report_detail
