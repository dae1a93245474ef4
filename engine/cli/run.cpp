// run.cpp: `roger run` (a batch script: plan, run every trial resumably, then the report) and
// `roger report` (tables and figures from a results folder). docs/batch.md describes both.
#include <iostream>
#include <string>

#include "batch/batch.h"
#include "cli/commands.h"
#include "core/error.h"
#include "report/report.h"
#include "script/batch_script.h"

namespace roger {

namespace {

// The --trials and --set overrides of a batch script.
BatchOverrides overrides_of(const RunArgs& a) {
  BatchOverrides ov;
  ov.trials = a.trials;
  for (const auto& s : a.sets) {
    const size_t eq = s.find('=');
    if (eq == std::string::npos || eq == 0) throw Error("--set '" + s + "': expected key=value");
    ov.sets.emplace_back(s.substr(0, eq), s.substr(eq + 1));
  }
  if (a.trials < 0) throw Error("--trials must be positive");
  return ov;
}

// The closing lines of a run; returns 1 when some trial failed.
int print_outcome(const BatchSummary& s, std::ostream& log) {
  log << "roger run: " << (s.trials - s.failed.size() - size_t(s.pending)) << " of " << s.trials
      << " trials done in " << format_duration(s.wall_s);
  if (s.pending) log << ", " << s.pending << " not run yet (run the same command again to continue)";
  log << "\n";
  if (s.failed.empty()) return 0;
  log << "roger run: " << s.failed.size() << " trial" << (s.failed.size() == 1 ? "" : "s")
      << " failed (their error.json holds the whole message; the same command tries them again):\n";
  for (const auto& f : s.failed) log << "  " << f << "\n";
  return 1;
}

}  // namespace

int command_run(const RunArgs& a) {
  std::ostream& log = a.progress ? *a.progress : std::cerr;
  try {
    const BatchScript b = load_batch_script(a.script, overrides_of(a));
    const BatchPlan plan = plan_batch(b, a.out.empty() ? "results/" + b.name : a.out);
    check_selectors(plan, a.only);
    if (open_results_folder(plan)) log << "roger run: resuming " << plan.out << "\n";
    size_t trials = 0;
    for (const auto& p : plan.phases) trials += p.size();
    log << "roger run: " << b.path << " -> " << plan.out << " (" << trials << " trials, curriculum "
        << b.curriculum << ")\n";
    const BatchSummary summary = run_batch(plan, RunControl{a.jobs, a.live, a.max_trials, a.only, &log});
    int status = 0;
    if (!a.no_report) {
      try {
        for (const auto& f : write_report(plan.out)) log << "roger run: wrote " << f << "\n";
      } catch (const std::exception& e) {
        log << "roger run: the report failed: " << e.what() << "\n";
        status = 1;
      }
    }
    return print_outcome(summary, log) ? 1 : status;
  } catch (const std::exception& e) {
    log << "roger run: " << e.what() << "\n";
    return 1;
  }
}

int command_report(const ReportArgs& a) {
  std::ostream& log = a.progress ? *a.progress : std::cerr;
  try {
    for (const auto& f : write_report(a.dir)) log << "roger report: wrote " << f << "\n";
    return 0;
  } catch (const std::exception& e) {
    log << "roger report: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace roger
