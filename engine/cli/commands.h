// commands.h: `roger run` (a batch script: every trial, resumably, then the report) and
// `roger report` (tables and figures from a results folder). docs/batch.md describes both.
#pragma once

#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

namespace roger {

// The arguments of `roger run SCRIPT.lua [--trials N] [--jobs J] [--out DIR] [--set k=v]... [--only NAME]... [--live]`.
struct RunArgs {
  std::string script;               // batch script path, or a bare name in scripts/ ("paper", "quick")
  int trials = 0;                   // > 0: overrides every run's trial count
  int jobs = 0;                     // worker threads; 0 = all cores
  std::string out;                  // results folder; "" = results/<script name>
  std::vector<std::string> sets;    // "key=value" scenario parameters for every training run
  std::vector<std::string> only;    // run only these: "RUN", "RUN/CONTEXT" or "eval/NAME" (empty = all)
  bool live = false;                // redraw one live progress line (a terminal) instead of plain lines
  bool no_report = false;           // skip the report at the end
  int max_trials = 0;               // > 0: stop after starting this many new trials (tests, partial runs)
  std::ostream* progress = nullptr; // where progress and messages go (nullptr = standard error)
};

// The arguments of `roger report DIR`.
struct ReportArgs {
  std::string dir;                  // a results folder written by roger run
  std::ostream* progress = nullptr; // where messages go (nullptr = standard error)
};

// Runs a batch script into its results folder and then writes the report. Returns the exit status:
// 0 when every trial succeeded, 1 when some failed (listed) or the input is bad (message printed).
int command_run(const RunArgs& args);

// Writes tables.md and the figures of a results folder. Returns 0, or 1 with a message.
int command_report(const ReportArgs& args);

}  // namespace roger
