// dashboard_internal.h: the results folder's dashboard (private to report/): index.html, the page
// of engine/report/web/dashboard.html compiled in, and dashboard.js, the numbers report_*.cpp computed
// for tables.md and the figures, as data the page draws (a page opened from the file system cannot
// fetch() JSON, but it can load a script). dashboard.cpp writes both.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "report/stats.h"
#include "script/batch/batch_script.h"

namespace roger::dashboard {

using json = nlohmann::json;

// The bootstrap of the learning curves' IQM bands (report_figures.cpp computes them once for the IQM
// figures and the page): a fixed seed, so the same folder gives the same bands, and 1000
// resamples per grid time, since a band is drawn, not tabulated.
constexpr uint64_t kCurveBootstrapSeed = 20240602;
constexpr int kCurveResamples = 1000;

// One context's learning curve for the page: the grid times (minutes), the mean and population std
// over `trials` trials, and the interquartile mean with its 95% bootstrap interval at each time.
json curve_series(const std::string& context, const std::vector<double>& minutes,
                  const CurveBands& bands, size_t trials);

// tables.md as blocks the page renders: headings, paragraphs, list items and tables (header and
// rows of cells, the cells' text as in tables.md).
json markdown_blocks(const std::string& md);

// Every trial of the script in the folder, per run and context (and per evaluation and shape): its
// folder, its state ("ok", "failed", "pending") and, when finished, the few numbers a list needs.
json trial_index(const BatchScript& b, const std::string& dir);

// Writes dashboard.js (window.ROGER_REPORT = data) and index.html into dir, atomically; returns
// their paths.
std::vector<std::string> write_dashboard(const std::string& dir, const json& data);

}  // namespace roger::dashboard
