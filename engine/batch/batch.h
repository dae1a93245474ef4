// batch.h: running many independent trials on a local thread pool, resumably. Each trial is a
// pure function of its id (the id names its curriculum, stage, context and seed), so results do
// not depend on the number of threads; each finished trial commits one result file atomically,
// so a run that is interrupted (Ctrl-C, kill -9) resumes without losing or repeating a trial.
#pragma once

#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

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

// A trial: given its id and its own folder (created, empty), returns its result. It may write
// files into the folder (atomically); throwing records the error as the trial's result.
using TrialFunction = std::function<nlohmann::json(const std::string& id, const std::string& dir)>;

// Runs the trials not already finished in out_dir, `jobs` at a time, and returns every trial's
// outcome in the order of `ids`. A trial is finished when <dir>/result.json (or error.json)
// exists; a folder without either (a trial cut short) is emptied and run again. Ids are paths
// of safe characters ([A-Za-z0-9._-] segments separated by '/'), unique: otherwise roger::Error.
std::vector<TrialOutcome> run_trials(const std::vector<std::string>& ids, const TrialFunction& run,
                                     const BatchOptions& options);

// The folder of a trial within a results folder.
std::string trial_dir(const std::string& out_dir, const std::string& id);

// Formats seconds as a short duration for progress lines ("42 s", "3 min 05 s", "1 h 02 min").
std::string format_duration(double seconds);

}  // namespace roger
