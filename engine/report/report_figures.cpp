// report_figures.cpp: the report's figures (report_internal.h): learning curves per context (Figures
// 3 and 4), the IQM curves per stage with their bootstrap bands, cumulative training time (Figure 5).
#include "report/report_internal.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include "core/text.h"
#include "report/dashboard_internal.h"
#include "report/plot.h"

namespace roger::report_detail {
namespace {

std::vector<std::string> figure_paths(const std::string& dir, const std::string& file) {
  return {(fs::path(dir) / (file + ".png")).string(), (fs::path(dir) / (file + ".svg")).string()};
}

// One context's learning curves on their common grid: the grid in minutes, each trial's values
// there, and their mean, std and IQM bands.
struct ContextCurves {
  std::string context;
  size_t place = 0;  // its row's place among the figure's rows, drawn or not: its colour
  std::vector<double> minutes;
  std::vector<std::vector<double>> values;
  CurveBands bands;
  bool test_set = true;  // every trial's checkpoints ran a test set (so a success rate is a share mastered)
};

// Learning curves per row (a run's context): the greedy reward (or, with `success`, the success
// rate: the share of a test set mastered, in %) at the checkpoints against simulated training
// minutes (rows without a finished trial are left out). Each is named by its context, or by
// "run/context" when the rows come from several runs.
std::vector<ContextCurves> row_curves(const BatchScript& b, const std::vector<BatchRow>& rows, const Folder& folder,
                                      bool log_x, bool success = false) {
  std::vector<ContextCurves> out;
  const bool runs = std::any_of(rows.begin(), rows.end(), [&](const BatchRow& r) { return r.run != rows.front().run; });
  for (size_t place = 0; place < rows.size(); ++place) {
    const BatchRow& row = rows[place];
    const Results r = folder.run(*b.run(row.run), row.context);
    std::vector<std::vector<std::pair<double, double>>> trials;
    bool test_set = true;
    for (const auto& j : r.ok) {
      const json& test = j.value("test", json::object());
      test_set = test_set && test.is_object() && test.value("tasks", 0) > 0;
      std::vector<std::pair<double, double>> pts;
      for (const auto& cp : j.value("checkpoints", json::array()))
        pts.emplace_back(num(cp, "sim_s"), success ? 100.0 * num(cp, "success_rate") : num(cp, "reward_mean"));
      trials.push_back(std::move(pts));
    }
    CurveGrid g = curve_grid(trials, kCurvePoints, log_x);
    if (g.t.empty()) continue;
    ContextCurves cc{runs ? row.label() : row.context, place, {}, std::move(g.values), {}, test_set};
    for (double t : g.t) cc.minutes.push_back(t / 60.0);
    cc.bands = curve_bands(cc.values, dashboard::kCurveBootstrapSeed, dashboard::kCurveResamples);
    out.push_back(std::move(cc));
  }
  return out;
}

// A run's contexts as rows.
std::vector<BatchRow> rows_of_run(const BatchRun& run) {
  std::vector<BatchRow> rows;
  for (const auto& c : run.contexts) rows.push_back({run.name, c});
  return rows;
}

// The y axis of a success-rate curve: with a test set, the share of its tasks mastered; without
// one, the share of each checkpoint's held-out episodes that succeeded (the stage's own worlds).
std::string success_label(bool test_set) {
  return test_set ? "Test tasks mastered (%, greedy)" : "Checkpoint episodes succeeded (%, greedy)";
}

// The axes of every learning-curve figure (the greedy reward, or a success rate in %).
CurveOptions curve_options(bool log_x, bool success = false, bool test_set = true) {
  CurveOptions o;
  o.x_label = "Simulated training time (min)";
  o.y_label = success ? success_label(test_set) : "Average episodic reward (greedy)";
  if (success) o.y_min = 0.0, o.y_max = 100.0;
  o.log_x = log_x;
  return o;
}

// " (B2, DC3 pending; DC6 from 1 of 2 trials)": the rows of a figure that lack some of their
// trials' results, so that a partial figure never reads as the whole run's; "" when none does.
std::string rows_pending_note(const BatchScript& b, const std::vector<BatchRow>& rows, const Folder& folder) {
  const bool runs = std::any_of(rows.begin(), rows.end(), [&](const BatchRow& r) { return r.run != rows.front().run; });
  std::vector<std::string> pending, failed, some;
  for (const auto& row : rows) {
    const BatchRun& run = *b.run(row.run);
    int with_results = 0, waiting = 0;  // counted from the folder, without reading the results again
    for (int i = 0; i < run.trials; ++i) {
      const TrialState state = trial_state(folder.dir(), batch_trial_id(run.name, row.context, i));
      with_results += state == TrialState::kResult;
      waiting += state == TrialState::kPending;
    }
    const std::string name = runs ? row.label() : row.context;
    if (with_results > 0 && with_results < run.trials)
      some.push_back(name + " from " + std::to_string(with_results) + " of " + counted(run.trials, "trial"));
    else if (with_results == 0 && run.trials > 0) (waiting ? pending : failed).push_back(name);
  }
  std::vector<std::string> parts;
  if (!pending.empty()) parts.push_back(join(pending) + " pending");
  if (!failed.empty()) parts.push_back(join(failed) + " failed");
  if (!some.empty()) parts.push_back(join(some));
  return parts.empty() ? "" : " (" + join(parts, "; ") + ")";
}

}  // namespace

std::string figure_pending_note(const BatchScript& b, const BatchFigure& f, const Folder& folder) {
  if (f.kind == "tasks") return rows_pending_note(b, {{f.run, f.context}}, folder);
  if (f.kind == "curves" && !f.compare.empty()) return rows_pending_note(b, f.compare, folder);
  const BatchRun& run = *b.run(f.run);
  std::vector<BatchRow> rows = rows_of_run(run);
  // A cumulative figure stacks its skills' trials too (found by a probe: with SG/DC2's results
  // missing, every bar's SG part fell to the trials left, or to 0, and the figure said nothing).
  if (f.kind == "cumulative")
    for (const auto& s : run.skills) rows.push_back({s.run, s.context});
  return rows_pending_note(b, rows, folder);
}

// A run's learning curves (Figures 3 and 4): mean +- std per context (cut to [0, 100] for a
// share of test tasks mastered).
bool curves_figure(const BatchScript& b, const BatchFigure& f, const Folder& folder, std::vector<std::string>& written,
                   json& page) {
  const BatchRun& run = *b.run(f.run);
  const bool success = f.y == "success";
  std::vector<CurveSeries> series;
  json page_series = json::array();
  bool test_set = true;  // the label says "mastered" only when every curve drawn had a test set
  for (const ContextCurves& cc : row_curves(b, f.compare.empty() ? rows_of_run(run) : f.compare, folder, f.log_x, success)) {
    test_set = test_set && cc.test_set;
    page_series.push_back(dashboard::curve_series(cc.context, cc.minutes, cc.bands, cc.values.size()));
    page_series.back()["colour"] = cc.place;  // the page's curve keeps the picture's colour
    if (!success) {
      series.push_back({cc.context, cc.minutes, cc.bands.mean, cc.bands.std, {}, {}, int(cc.place)});
      continue;
    }
    // A share of tasks lies in [0, 100]: its band is mean +- std cut to that range.
    CurveSeries c{cc.context, cc.minutes, cc.bands.mean, {}, {}, {}, int(cc.place)};
    for (size_t i = 0; i < c.mean.size(); ++i) {
      c.low.push_back(std::max(0.0, c.mean[i] - cc.bands.std[i]));
      c.high.push_back(std::min(100.0, c.mean[i] + cc.bands.std[i]));
    }
    series.push_back(std::move(c));
  }
  const std::string title = !f.title.empty() ? f.title
                            : f.compare.empty() ? "Learning curves: stage " + run.stage +
                                                      (run.name == run.stage ? std::string() : " (run " + run.name + ")")
                                                : "Learning curves";
  page.push_back({{"kind", "curves"}, {"file", f.file}, {"run", f.compare.empty() ? run.name : std::string()},
                  {"log_x", f.log_x}, {"y", f.y}, {"title", title}, {"series", page_series},
                  {"y_label", !success ? "Greedy episodic reward"
                              : test_set ? "Test tasks mastered (%)" : "Checkpoint episodes succeeded (%)"}});
  if (series.empty()) return false;
  const auto paths = figure_paths(folder.out(), f.file);
  plot_learning_curves(paths, title, series, curve_options(f.log_x, success, test_set));
  written.insert(written.end(), paths.begin(), paths.end());
  return true;
}

std::string iqm_file(const BatchRun& run) { return "iqm_" + run.name; }

// The IQM learning curves of a run's stage: per context the interquartile mean over trials inside
// its 95% bootstrap band, on the time axis of the run's own curves figure (log when it is). Its
// line for tables.md, whether drawn or not.
std::string iqm_figure(const BatchScript& b, const BatchRun& run, const Folder& folder,
                       std::vector<std::string>& written) {
  bool log_x = false;
  for (const auto& f : b.figures)
    if (f.kind == "curves" && f.compare.empty() && f.run == run.name) log_x = log_x || f.log_x;
  std::vector<CurveSeries> series;
  for (const ContextCurves& cc : row_curves(b, rows_of_run(run), folder, log_x))
    series.push_back({cc.context, cc.minutes, cc.bands.iqm, {}, cc.bands.iqm_low, cc.bands.iqm_high, int(cc.place)});
  const std::string file = iqm_file(run);
  const std::string title = "IQM learning curves: stage " + run.stage +
                            (run.name == run.stage ? std::string() : " (run " + run.name + ")");
  std::string line = "- `" + file + ".png` / `" + file + ".svg`: " + title;
  if (series.empty()) return line + " (not drawn: no finished trial)" + rows_pending_note(b, rows_of_run(run), folder);
  line += rows_pending_note(b, rows_of_run(run), folder);
  CurveOptions o = curve_options(log_x);
  o.y_label = "IQM of the greedy episodic reward";
  const auto paths = figure_paths(folder.out(), file);
  plot_learning_curves(paths, title, series, o);
  written.insert(written.end(), paths.begin(), paths.end());
  return line;
}

// Whether a trial used the learned skill: its record's "skills" are the learned skills its context
// binds, directly or inside another skill (DC6's Phi_STG holds Phi_SG); none when it has none.
bool used_skill(const json& result, const std::string& skill) {
  return result.contains("skills") && result["skills"].is_object() && result["skills"].contains(skill);
}

// Cumulative training time per context: the skills' runs (the trial's own skill source) then the
// run. A skill's time is stacked only under the contexts that use it, as the paper's "as
// appropriate" has it (found in a review: B2, whose actions hold no Phi_SG, carried SG's time).
bool cumulative_figure(const BatchScript& b, const BatchFigure& f, const Folder& folder, std::vector<std::string>& written,
                       json& page) {
  const BatchRun& run = *b.run(f.run);
  std::vector<std::string> categories;
  std::vector<BarStack> stacks;
  for (const auto& s : run.skills) stacks.push_back({s.run + " (" + s.skill + ", " + s.context + ")", {}, {}});
  stacks.push_back({run.name, {}, {}});
  std::vector<bool> drawn(run.skills.size(), false);  // a skill's part has a bar somewhere
  for (const auto& c : run.contexts) {
    const Results r = folder.run(run, c);
    if (r.ok.empty()) continue;
    categories.push_back(c);
    // A trial that never reached the threshold counts its whole training time (as the run
    // tables do), so a mean over it is a lower bound.
    for (size_t k = 0; k < run.skills.size(); ++k) {
      const BatchSkill& s = run.skills[k];
      std::vector<double> v;
      bool censored = false;
      for (const auto& j : r.ok) {
        if (!used_skill(j, s.skill)) continue;
        const int i = j.value("trial", 0);
        const Results src = folder.trials({batch_trial_id(s.run, s.context, i)});
        if (src.ok.empty()) continue;
        v.push_back(num(src.ok.front(), "time_to_threshold_s") / 60.0);
        censored = censored || !src.ok.front().value("reached", false);
      }
      stacks[k].values.push_back(v.empty() ? 0.0 : mean(v));
      stacks[k].lower_bound.push_back(censored);
      drawn[k] = drawn[k] || !v.empty();
    }
    std::vector<double> v;
    bool censored = false;
    for (const auto& j : r.ok) {
      v.push_back(num(j, "time_to_threshold_s") / 60.0);
      censored = censored || !j.value("reached", false);
    }
    stacks.back().values.push_back(mean(v));
    stacks.back().lower_bound.push_back(censored);
  }
  // A skill whose source trials have no result (pending or failed) under every context drawn has
  // no bar: its legend entry says so rather than name a colour the figure lacks (found by a probe
  // on an interrupted run). It keeps its place, and so every colour its place in the full figure.
  for (size_t k = 0; k < run.skills.size(); ++k)
    if (!drawn[k] && !categories.empty()) stacks[k].name += " (not drawn)";
  json page_stacks = json::array();
  for (const auto& st : stacks)
    page_stacks.push_back({{"name", st.name}, {"minutes", st.values}, {"lower_bound", st.lower_bound}});
  page.push_back({{"kind", "cumulative"}, {"file", f.file}, {"run", run.name}, {"categories", categories},
                  {"title", f.title.empty() ? "Cumulative training time" : f.title}, {"stacks", page_stacks}});
  if (categories.empty()) return false;
  BarOptions o;
  o.y_label = "Cumulative simulated training time (min)";
  o.value_label = [](double m) { return format_min_sec(60.0 * m); };
  const auto paths = figure_paths(folder.out(), f.file);
  plot_stacked_bars(paths, f.title.empty() ? "Cumulative training time" : f.title, categories, stacks, o);
  written.insert(written.end(), paths.begin(), paths.end());
  return true;
}

}  // namespace roger::report_detail
