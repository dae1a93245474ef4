// Module report: what a results folder says. Owns statistics, tables.md, report.json and the
// figures. Depends on batch and below (it reads results folders); must not depend on view or cli.
//
// report.h: the report of a results folder written by `roger run` (commands.h): tables.md (the
// paper's Tables I-III with medians, interquartile means and their bootstrap intervals, the
// fraction of trials that reached the threshold, Mann-Whitney U p-values and probabilities of
// improvement against the baseline, and the usage analysis; evaluation and sorting tables with
// their distinct layouts and the success rate's 95% interval, resampled as the episodes were drawn)
// and the figures (learning curves and
// cumulative training times, PNG and SVG). Everything is read back from the folder: manifest.json
// and trials/<id>/result.json. Every file is written atomically. The dashboard (index.html) shows
// the same numbers in a browser. Each kind of table and figure is a file of its own
// (report_internal.h lists them).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "report/stats.h"  // CurveGrid, curve_grid

namespace roger {

// Writes tables.md, report.json (the tables' numbers), every figure of the results folder `dir`
// and its dashboard: index.html with dashboard.js, the same numbers for a browser (docs/browser.md).
// Returns the files written. Throws roger::Error when the folder holds no sound manifest.json, or
// when a trial's record is corrupt (naming the trial, the file and what is wrong), before writing.
// `by`: features (a world's "obstacles", "objects", "shape", or a task parameter) to split each run
// table's final success by, a table after it per feature (as a batch script's `by` tables do).
std::vector<std::string> write_report(const std::string& dir, const std::vector<std::string>& by = {});

// Writes the dashboard's page alone (index.html) into the results folder `dir`, atomically, so a
// run can be watched from its start: the page shows the run's progress from status.js and the
// report from dashboard.js once there is one. Returns its path; throws roger::Error when it cannot.
std::string write_dashboard_page(const std::string& dir);

}  // namespace roger
