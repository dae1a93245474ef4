// report.cpp: write_report (report.h): the tables in the batch script's order, the figures and their
// list, tables.md, report.json and the dashboard; each part comes from its own file (report_internal.h).
#include "report/report.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "batch/batch.h"
#include "core/json_input.h"
#include "core/error.h"
#include "core/fileio.h"
#include "core/text.h"
#include "report/dashboard_internal.h"
#include "report/report_internal.h"
#include "script/batch/batch_script.h"

namespace roger {

namespace fs = std::filesystem;
using json = nlohmann::json;
using namespace report_detail;

namespace {

// Each --by feature once, in the order given: a feature named twice is still one split per table.
std::vector<std::string> distinct(const std::vector<std::string>& features) {
  std::vector<std::string> out;
  for (const auto& f : features)
    if (std::find(out.begin(), out.end(), f) == out.end()) out.push_back(f);
  return out;
}

// What a figure shows, for its line of tables.md: its title, else its kind and rows (found by a
// probe: a comparison of several runs' contexts was listed as "curves of run" its first row's).
std::string figure_description(const BatchFigure& f) {
  if (!f.title.empty()) return f.title;
  return f.compare.empty() ? f.kind + " of run " + f.run : f.kind + " of " + row_labels(f.compare);
}

// Draws the script's figures; their lines for tables.md, each saying what it lacks.
std::vector<std::string> draw_figures(const BatchScript& b, const Folder& folder, std::vector<std::string>& written,
                                      json& page_figures) {
  std::vector<std::string> figures_md;
  for (const auto& f : b.figures) {
    const bool drawn = f.kind == "cumulative" ? cumulative_figure(b, f, folder, written, page_figures)
                       : f.kind == "tasks"    ? tasks_figure(b, f, folder, written, page_figures)
                                              : curves_figure(b, f, folder, written, page_figures);
    // A heat map of where a teacher sampled names the finished trials it lacks (their
    // episodes.jsonl lost), rather than silently drawing fewer.
    const json& fig = page_figures.back();
    std::string lacking;
    if (f.kind == "tasks" && !fig["missing"].empty())
      lacking = fig["missing"].get<std::vector<std::string>>().front() +
                (fig["missing"].size() > 1 ? " and " + std::to_string(fig["missing"].size() - 1) + " more" : "") +
                " finished without episodes.jsonl";
    std::string line = "- `" + f.file + ".png` / `" + f.file + ".svg`: " + figure_description(f);
    if (!drawn) line += " (not drawn: " + (lacking.empty() ? "no finished trial" : lacking) + ")";
    else if (!lacking.empty()) line += " (not in it: " + lacking + ")";
    figures_md.push_back(line + figure_pending_note(b, f, folder));
  }
  for (const BatchRun& run : b.runs) {
    figures_md.push_back(iqm_figure(b, run, folder, written));
    // The page draws its own IQM curves from the curves figures' data; it links these files
    // (found by a probe: it listed figure3 to figure5 and not the IQM figures beside them).
    page_figures.push_back({{"kind", "iqm"}, {"file", iqm_file(run)}, {"run", run.name}});
  }
  return figures_md;
}

// The figure files the folder's previous report drew, as its dashboard.js lists them, read before
// this report replaces it: one the script no longer asks for goes with it (found by a probe:
// figure5.png stayed beside a report that no longer named it). Only files a report listed are
// touched, never one of the user's; a missing or unreadable dashboard.js lists none.
std::set<std::string> previous_figure_files(const std::string& dir) {
  std::set<std::string> files;
  std::error_code ec;
  const fs::path page = fs::path(dir) / "dashboard.js";
  if (!fs::is_regular_file(page, ec)) return files;
  std::string text;
  try {
    text = read_file_text(page.string());
  } catch (const std::exception&) {
    return files;
  }
  const size_t open = text.find('{'), close = text.rfind('}');
  if (open == std::string::npos || close == std::string::npos || close < open) return files;
  const json data = parse_json(text.cbegin() + long(open), text.cbegin() + long(close) + 1, false);
  if (!data.is_object() || !data.contains("figures") || !data["figures"].is_array()) return files;
  for (const json& f : data["figures"])
    if (f.is_object() && f.contains("file") && f["file"].is_string() && results_name(f["file"].get<std::string>()))
      for (const char* ext : {".png", ".svg"}) files.insert(f["file"].get<std::string>() + ext);
  return files;
}

// Removes the figure files this report did not write: those of a figure it could not draw, which
// tables.md says "(not drawn: ...)" and which would read as this report's beside it, and those
// of a figure of the previous report (`files`, as previous_figure_files reads them) the script no
// longer asks for.
void remove_unwritten_figures(const std::string& dir, const json& page_figures, std::set<std::string> files,
                              const std::vector<std::string>& out) {
  for (const json& f : page_figures)
    if (const std::string file = f.value("file", std::string()); !file.empty())
      for (const char* ext : {".png", ".svg"}) files.insert(file + ext);
  for (const std::string& o : out) files.erase(fs::path(o).filename().string());
  for (const std::string& f : files) {
    std::error_code ec;
    fs::remove(fs::path(dir) / f, ec);  // usually none
  }
}

// An evaluation's scenario as the tables name it. The configuration records a scenario found
// beside the batch script by its absolute path (what the trials loaded); the tables name it from
// the script as the command named that (`lab/pen.lua` for `roger run lab/batch.lua`), as they name
// the script, so that a published table does not carry one machine's folders.
std::string scenario_as_named(const std::string& scenario, const json& manifest) {
  const fs::path recorded(scenario);
  const std::string script = manifest.value("script", std::string()),
                    script_file = manifest.value("script_file", std::string());
  if (!recorded.is_absolute() || script.empty() || script_file.empty()) return scenario;
  std::error_code ec;
  const fs::path folder = fs::weakly_canonical(fs::path(script_file).parent_path(), ec);
  const fs::path rel = recorded.lexically_normal().lexically_relative(folder);
  if (ec || rel.empty() || *rel.begin() == "..") return scenario;
  return (fs::path(script).parent_path() / rel).lexically_normal().generic_string();
}

// The script's tables, and with roger report --by each run's and evaluation's rows split again
// by each feature. A feature of the command line that no record has is a slip (a typo, a feature
// of other scripts): refused before anything is written, rather than a report of empty tables.
json write_tables(const BatchScript& b, const std::vector<std::string>& by, const Folder& folder, std::ostringstream& md) {
  json rep = json::array();
  std::map<std::string, int64_t> by_records;  // per --by feature: the records its tables read
  std::map<std::string, bool> by_found;       // and whether any had it
  std::set<std::string> features;             // what the records have
  for (const auto& t : b.tables) {
    if (!t.sorting.empty()) sorting_table(b, t, folder, md, rep);
    else if (!t.compare.empty()) compare_table(b, t, folder, md, rep);
    else if (!t.by.empty()) by_table(b, t, folder, md, rep);
    else if (!t.run.empty()) run_table(b, t, folder, md, rep);
    else eval_table(b, t, folder, md, rep);
    if (!t.by.empty() || (t.run.empty() && t.compare.empty())) continue;
    for (const auto& feature : by) {
      BatchTable split = t;
      split.by = feature;
      split.title = t.title + ": final success by " + feature;
      const ByFound found = by_table(b, split, folder, md, rep);
      by_records[feature] += found.records;
      by_found[feature] = by_found[feature] || found.feature;
      features.insert(found.features.begin(), found.features.end());
    }
  }
  for (const auto& feature : by)
    if (by_records[feature] > 0 && !by_found[feature])
      // Records, not episodes: a trial shown by two tables is read by each (found by a probe: "none
      // of the 512 episodes" of 336).
      throw Error("--by " + feature + ": no final-evaluation episode the tables read has a feature '" + feature +
                  "' (" + counted(by_records[feature], "record") + " read, a trial's once for each table that shows "
                  "it); they have: " +
                  join(std::vector<std::string>(features.begin(), features.end())));
  return rep;
}

// The figures, drawn (their files appended to `written`, the page's entries to `page_figures`),
// and their section of tables.md: each figure's line, then how the curves were made.
void write_figures(const BatchScript& b, const Folder& folder, std::vector<std::string>& written,
                   json& page_figures, std::ostringstream& md) {
  const std::vector<std::string> figures_md = draw_figures(b, folder, written, page_figures);
  md << "## Figures\n\n";
  for (const auto& l : figures_md) md << l << "\n";
  md << "\nLearning curves: each trial's greedy checkpoint rewards (the mean episodic reward of held-out "
        "episodes) against its simulated training time, interpolated linearly between checkpoints onto a "
        "common grid of "
     << kCurvePoints << " times (log-spaced on a log axis) from the latest first checkpoint to the latest last "
        "one; a trial that stopped early keeps its last value. Lines are the mean over trials, bands ± one "
        "(population) std. IQM learning curves (one per stage): on the same grid, the interquartile mean over "
        "trials with its 95% percentile-bootstrap interval at each time (" << dashboard::kCurveResamples
     << " resamples of whole trials, one set for the whole curve). Cumulative training time: mean simulated time-to-threshold of the skill's source "
        "trials (each trial uses the policy of the same-numbered source trial) stacked under the run's own, "
        "in the contexts that use the skill (directly or inside another skill); a context that does not "
        "shows its own time alone.\n";
  if (std::any_of(b.figures.begin(), b.figures.end(), [](const BatchFigure& f) { return f.y == "success"; }))
    md << "\nCurves of success (`y = \"success\"`): the checkpoints' success rates in place of their rewards "
          "(with a test set, the share of its tasks mastered; without one, the share of the checkpoint's "
          "held-out episodes that succeeded, and the axis says so), and the band (mean ± one std) cut to the "
          "possible range, 0 to 100%.\n";
}

}  // namespace

std::vector<std::string> write_report(const std::string& dir, const std::vector<std::string>& by_given) {
  // Every record is checked first (engine/batch/records.cpp): a corrupt trial stops the report
  // before anything is written, rather than being read as whatever its damage says.
  const BatchPlan plan = read_results_plan(dir);  // outlives the trials missing_trials points to
  for (const auto& m : missing_trials(plan))
    if (!m.problem.empty()) throw Error("trial " + m.trial->id + ": " + m.problem);
  const json manifest = read_manifest(dir);
  BatchScript b = batch_config_from_json(manifest.value("config", json::object()));
  for (BatchEvaluation& e : b.evaluations) e.scenario = scenario_as_named(e.scenario, manifest);
  // Written whole or not at all: a table that refuses a record's numbers, or a figure that cannot
  // be drawn, leaves the previous report as it was rather than half replaced.
  const std::vector<std::string> by = distinct(by_given);
  const std::set<std::string> previous = previous_figure_files(dir);
  StagedFiles staged(dir);
  const Folder folder(dir, staged.path());
  std::ostringstream md;
  md << "# Results: " << b.name << "\n\n";
  // Said first, so that no table or figure of a partial report reads as the whole run's.
  const Completeness done = completeness(plan);
  if (done.partial()) md << partial_line(done) << "\n\n";
  if (!b.description.empty()) md << b.description << "\n\n";
  md << "Batch script `" << manifest.value("script", std::string("?")) << "`, curriculum `" << b.curriculum
     << "`, roger " << manifest.value("version", std::string("?")) << "; trial i of every run has seed "
     << b.seed << " + i.\n\n";
  const json rep = write_tables(b, by, folder, md);
  std::vector<std::string> written;
  json page_figures = json::array();
  write_figures(b, folder, written, page_figures, md);
  const std::string tables = staged.stage("tables.md");
  write_file_atomic(tables, md.str(), "cannot write tables.md");
  const std::string report_json = staged.stage("report.json");
  json report = {{"tables", rep}};
  for (json& t : report["tables"]) t.erase(kUsageOrder);  // the page's alone
  if (done.partial()) report["partial"] = partial_json(done);  // absent when every trial has a result
  write_file_atomic(report_json, report.dump(1) + "\n", "cannot write report.json");
  written.insert(written.begin(), {tables, report_json});
  const json page = {{"name", b.name}, {"description", b.description},
                     {"script", manifest.value("script", std::string("?"))}, {"curriculum", b.curriculum},
                     {"version", manifest.value("version", std::string("?"))}, {"seed", b.seed},
                     {"blocks", dashboard::markdown_blocks(md.str())}, {"tables", rep},
                     {"figures", page_figures}, {"trials", dashboard::trial_index(b, dir)}};
  for (const auto& f : dashboard::write_dashboard(staged.path(), page)) written.push_back(f);
  const std::vector<std::string> out = staged.commit(written);
  remove_unwritten_figures(dir, page_figures, previous, out);
  return out;
}

}  // namespace roger
