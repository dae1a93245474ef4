// dashboard.cpp: the results folder's dashboard: index.html (web/dashboard.html of this
// folder, compiled in) and dashboard.js (the report's numbers). The page draws what the report
// computed; it computes no statistic itself.
#include "report/dashboard_internal.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "batch/batch.h"
#include "core/json_input.h"
#include "core/error.h"
#include "core/fileio.h"
#include "report/report.h"
#include "report/stats.h"

#include "dashboard_page_html.h"  // generated from engine/report/web/dashboard.html

namespace roger {
namespace dashboard {
namespace {

namespace fs = std::filesystem;

// Five significant digits: a curve is drawn, and the paper's folder must stay a light page.
double rounded(double v) {
  if (!std::isfinite(v) || v == 0.0) return v;
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.5g", v);
  return std::strtod(buf, nullptr);
}

json rounded_array(const std::vector<double>& xs) {
  json a = json::array();
  for (double x : xs) a.push_back(rounded(x));
  return a;
}

// The cells of a markdown table row "| a | b |".
std::vector<std::string> table_cells(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  for (size_t i = 1; i < line.size(); ++i) {
    if (line[i] == '|') {
      const size_t b = cell.find_first_not_of(' '), e = cell.find_last_not_of(' ');
      cells.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
      cell.clear();
    } else {
      cell += line[i];
    }
  }
  return cells;
}

std::string read_text(const fs::path& path) { return read_file_text(path.string()); }

// One trial's entry: its folder, its state, and from result.json the numbers a list shows.
json trial_entry(const std::string& dir, const std::string& id, int index) {
  const std::string folder = "trials/" + id + "/";
  json t = {{"index", index}, {"id", id}, {"folder", folder}, {"state", "pending"}};
  const fs::path d = fs::path(trial_dir(dir, id));
  std::error_code ec;
  if (fs::exists(d / "result.json", ec)) {
    t["state"] = "ok";
    try {
      const json r = parse_json(read_text(d / "result.json"));
      for (const char* key : {"time_to_threshold_s", "reached", "success_rate", "reward_mean"})
        if (r.contains(key)) t[key] = r[key].is_number() ? json(rounded(r[key].get<double>())) : r[key];
    } catch (const std::exception&) {
      t["state"] = "failed";
    }
  } else if (fs::exists(d / "error.json", ec)) {
    t["state"] = "failed";
    // Why it failed, for the chip's tooltip: the first line of the message (error.json, linked
    // below, holds the whole of it and the traceback).
    try {
      const json e = parse_json(read_text(d / "error.json"));
      const std::string message = e.value("error", std::string());
      t["error"] = message.substr(0, message.find('\n'));
    } catch (const std::exception&) {
      t["error"] = "error.json cannot be read";
    }
  }
  // The files worth opening: the episodes of training, any error, and any episode page rendered there.
  json files = json::array();
  for (const char* f : {"episodes.jsonl", "checkpoints.jsonl", "curve.csv", "final.jsonl", "eval.jsonl", "policy.json",
                        "summary.json", "result.json", "error.json"})
    if (fs::exists(d / f, ec)) files.push_back(f);
  t["files"] = files;
  json pages = json::array();
  for (fs::directory_iterator it(d, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_directory(ec) && fs::exists(it->path() / "index.html", ec))
      pages.push_back(it->path().filename().string() + "/index.html");
  std::sort(pages.begin(), pages.end());
  t["pages"] = pages;
  return t;
}

}  // namespace

json curve_series(const std::string& context, const std::vector<double>& minutes,
                  const CurveBands& bands, size_t trials) {
  return {{"context", context}, {"trials", trials}, {"minutes", rounded_array(minutes)},
          {"mean", rounded_array(bands.mean)}, {"std", rounded_array(bands.std)},
          {"iqm", rounded_array(bands.iqm)}, {"iqm_low", rounded_array(bands.iqm_low)},
          {"iqm_high", rounded_array(bands.iqm_high)}};
}

json markdown_blocks(const std::string& md) {
  json blocks = json::array();
  std::istringstream in(md);
  std::string line;
  json* table = nullptr;
  while (std::getline(in, line)) {
    if (line.empty()) {
      table = nullptr;
      continue;
    }
    if (line[0] == '|') {
      const std::vector<std::string> cells = table_cells(line);
      if (!table) {
        blocks.push_back({{"kind", "table"}, {"header", cells}, {"rows", json::array()}});
        table = &blocks.back();
      } else if (line.compare(0, 4, "|---") != 0) {
        (*table)["rows"].push_back(cells);
      }
      continue;
    }
    table = nullptr;
    if (line.compare(0, 4, "### ") == 0) blocks.push_back({{"kind", "h3"}, {"text", line.substr(4)}});
    else if (line.compare(0, 3, "## ") == 0) blocks.push_back({{"kind", "h2"}, {"text", line.substr(3)}});
    else if (line.compare(0, 2, "# ") == 0) blocks.push_back({{"kind", "h1"}, {"text", line.substr(2)}});
    else if (line.compare(0, 2, "- ") == 0) blocks.push_back({{"kind", "li"}, {"text", line.substr(2)}});
    else blocks.push_back({{"kind", "p"}, {"text", line}});
  }
  return blocks;
}

json trial_index(const BatchScript& b, const std::string& dir) {
  json runs = json::array();
  for (const BatchRun& run : b.runs) {
    json contexts = json::array();
    for (const std::string& c : run.contexts) {
      json trials = json::array();
      for (int i = 0; i < run.trials; ++i) trials.push_back(trial_entry(dir, batch_trial_id(run.name, c, i), i));
      contexts.push_back({{"context", c}, {"trials", trials}});
    }
    runs.push_back({{"run", run.name}, {"stage", run.stage}, {"contexts", contexts}});
  }
  json evaluations = json::array();
  for (const BatchEvaluation& ev : b.evaluations) {
    json groups = json::array();
    for (const std::string& g : batch_eval_groups(ev)) {
      json trials = json::array();
      for (int i = 0; i < ev.trials; ++i) trials.push_back(trial_entry(dir, batch_eval_id(ev.name, g, i), i));
      groups.push_back({{"group", g}, {"trials", trials}});
    }
    evaluations.push_back({{"evaluation", ev.name}, {"run", ev.run}, {"context", ev.context}, {"groups", groups}});
  }
  return {{"runs", runs}, {"evaluations", evaluations}};
}

std::vector<std::string> write_dashboard(const std::string& dir, const json& report) {
  json data = report;
  // A figure the report could not draw (no finished trial) has no PNG or SVG in this report's
  // folder: the page links only the files that were written.
  for (json& f : data["figures"]) {
    std::error_code ec;
    const std::string file = f.value("file", std::string());
    f["files"] = json::array();
    for (const char* ext : {".png", ".svg"})
      if (!file.empty() && fs::exists(fs::path(dir) / (file + ext), ec)) f["files"].push_back(file + ext);
  }
  // When this report was written: a page that saw a run end waits for a report written since the
  // run started (status.js's started_ms), never showing an older one as the run's.
  data["written_ms"] = std::chrono::duration_cast<std::chrono::milliseconds>(
                           std::chrono::system_clock::now().time_since_epoch()).count();
  // '<' only occurs inside JSON strings, where \u003c means the same: no name closes a script.
  std::string text = data.dump(-1, ' ', false, json::error_handler_t::replace);
  std::string safe;
  safe.reserve(text.size());
  for (char c : text) safe += c == '<' ? std::string("\\u003c") : std::string(1, c);
  const std::string script = (fs::path(dir) / "dashboard.js").string();
  write_file_atomic(script,
                    "// Generated by roger report: the numbers of the report for index.html.\n"
                    "window.ROGER_REPORT = " + safe + ";\n",
                    "cannot write dashboard.js");
  return {script, write_dashboard_page(dir)};
}

}  // namespace dashboard

std::string write_dashboard_page(const std::string& dir) {
  const std::string page = (std::filesystem::path(dir) / "index.html").string();
  write_file_atomic(page, kDashboardPageHtml, "cannot write the dashboard");
  return page;
}

}  // namespace roger
