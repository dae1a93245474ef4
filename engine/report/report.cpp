#include "report/report.h"

#include <algorithm>
#include <cmath>
#include <climits>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "batch/batch.h"
#include "script/batch/batch_script.h"
#include "core/error.h"
#include "core/fileio.h"
#include "report/dashboard_internal.h"
#include "report/plot.h"
#include "report/stats.h"

namespace roger {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

constexpr uint64_t kBootstrapSeed = 20240601;  // fixed: the same folder gives the same intervals
constexpr int kCurvePoints = 200;

std::string read_text(const fs::path& path) { return read_file_text(path.string()); }

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::string pct(double fraction) { return fmt("%.1f%%", 100.0 * fraction); }

// One context's (or group's) finished trials.
struct Results {
  std::vector<json> ok;  // result.json of every finished trial, in trial order
  int failed = 0, pending = 0, expected = 0;
};

// Checks the JSON types of what the report reads from a trial's result.json with value(), get()
// or [] (num() checks its own numbers): a hand-edited or damaged result is a roger::Error naming
// the file, not a json type_error, nor an abort on a missing "usage".
void check_result_shape(const json& j, const fs::path& file) {
  auto bad = [&](const std::string& what) { throw Error(file.string() + ": " + what); };
  if (!j.is_object()) bad(std::string("a trial result must be a JSON object, got ") + j.type_name());
  if (j.contains("reached") && !j["reached"].is_boolean()) bad("field \"reached\" must be true or false");
  if (j.contains("psi")) {
    const json& psi = j["psi"];
    if (!psi.is_array() || !std::all_of(psi.begin(), psi.end(), [](const json& a) { return a.is_string(); }))
      bad("field \"psi\" must be a list of action names");
  }
  if (j.contains("usage")) {
    const json& usage = j["usage"];
    if (!usage.is_object() || !std::all_of(usage.begin(), usage.end(), [](const json& f) { return f.is_number(); }))
      bad("field \"usage\" must map action names to numbers");
  }
  if (j.contains("checkpoints") && !j["checkpoints"].is_array()) bad("field \"checkpoints\" must be a list");
  if (j.contains("diagnosis")) {
    const json& d = j["diagnosis"];
    const json* causes = d.is_object() && d.contains("causes") ? &d["causes"] : nullptr;
    if (!causes || !causes->is_array() ||
        !std::all_of(causes->begin(), causes->end(), [](const json& c) { return c.is_string(); }))
      bad("field \"diagnosis\" must be an object whose \"causes\" is a list of sentences");
  }
  if (j.contains("trial") &&
      !(j["trial"].is_number_integer() && j["trial"].get<int64_t>() >= 0 && j["trial"].get<int64_t>() < 100000))
    bad("field \"trial\" must be a trial index (an integer in [0, 100000))");
}

// A result's "usage" (checked by check_result_shape), or an empty one when it has none.
const json& usage_of(const json& j) {
  static const json none = json::object();
  const auto it = j.find("usage");
  return it == j.end() ? none : *it;
}

// The results folder, read once.
class Folder {
 public:
  explicit Folder(const std::string& dir) : dir_(dir) {}
  Results trials(const std::vector<std::string>& ids) const {
    Results r;
    r.expected = int(ids.size());
    for (const auto& id : ids) {
      const fs::path d = trial_dir(dir_, id);
      std::error_code ec;
      if (fs::exists(d / "result.json", ec)) {
        try {
          r.ok.push_back(json::parse(read_text(d / "result.json")));
        } catch (const std::exception& e) {
          throw Error((d / "result.json").string() + ": not JSON: " + e.what());
        }
        check_result_shape(r.ok.back(), d / "result.json");
      } else if (fs::exists(d / "error.json", ec)) {
        ++r.failed;
      } else {
        ++r.pending;
      }
    }
    return r;
  }
  Results run(const BatchRun& run, const std::string& context) const {
    std::vector<std::string> ids;
    for (int i = 0; i < run.trials; ++i) ids.push_back(batch_trial_id(run.name, context, i));
    return trials(ids);
  }
  const std::string& dir() const { return dir_; }

 private:
  std::string dir_;
};

double num(const json& j, const char* key) {
  if (!j.contains(key) || !j[key].is_number()) throw Error(std::string("a trial result has no number '") + key + "'");
  return j[key].get<double>();
}

std::vector<CensoredTime> times_of(const Results& r) {
  std::vector<CensoredTime> t;
  for (const auto& j : r.ok) t.push_back({num(j, "time_to_threshold_s"), j.value("reached", false)});
  return t;
}

// Pooled figures of several greedy evaluations of `episodes` episodes each (rewards and successes).
struct Pooled {
  double mean = 0, std = 0, success = 0;
  int64_t episodes = 0;  // summed over trials: may pass 2^31
};

Pooled pool(const std::vector<json>& evals, const char* episodes_key) {
  Pooled p;
  double sum = 0, sum_sq = 0, succ = 0;
  for (const auto& j : evals) {
    const double n = num(j, episodes_key), m = num(j, "reward_mean"), s = num(j, "reward_std");
    if (!(n >= 0 && n <= 1e9 && n == std::floor(n)))  // int64_t(1e300) would be undefined
      throw Error(std::string("a trial result's '") + episodes_key + "' is not a count of episodes: " + fmt("%g", n));
    sum += n * m;
    sum_sq += n * (s * s + m * m);
    succ += n * num(j, "success_rate");
    p.episodes += int64_t(n);
  }
  if (p.episodes == 0) return p;
  p.mean = sum / p.episodes;
  p.std = std::sqrt(std::max(0.0, sum_sq / p.episodes - p.mean * p.mean));
  p.success = succ / p.episodes;
  return p;
}

std::string trials_note(const Results& r) {
  std::string s = std::to_string(r.ok.size()) + "/" + std::to_string(r.expected);
  if (r.failed) s += " (" + std::to_string(r.failed) + " failed)";
  if (r.pending) s += " (" + std::to_string(r.pending) + " pending)";
  return s;
}

// The head of a run table: its title, the run and baseline it compares, and the column names.
void run_table_head(const BatchRun& run, const BatchTable& t, std::ostringstream& md) {
  md << "## " << (t.title.empty() ? "Stage " + run.stage : t.title) << "\n\n";
  md << "Run `" << run.name << "`: stage " << run.stage << ", baseline " << t.baseline << ".\n\n";
  md << "| Approach | Train time (min:sec) | % Improvement | Avg. reward ± std | Success rate | Median time | "
        "IQM time [95% CI] | Reached | p (Mann-Whitney vs "
     << t.baseline << ") | P(faster than " << t.baseline << ") | Trials |\n";
  md << "|---|---|---|---|---|---|---|---|---|---|---|\n";
}

// The columns comparing a context's times with the baseline's ("-" when there is nothing to compare).
struct BaselineColumns {
  std::string improvement = "-", p_value = "-", p_faster = "-";
};

// Compares a context's times (mean m) with the baseline's: % improvement, Mann-Whitney p-value and
// P(faster), each also recorded in row.
BaselineColumns compare_with_baseline(const std::vector<CensoredTime>& times, const std::vector<CensoredTime>& base_times,
                                      double base_mean, double m, json& row) {
  BaselineColumns col;
  if (base_mean > 0) {
    const double imp = percent_improvement(base_mean, m);
    col.improvement = fmt("%.2f%%", imp);
    row["improvement_percent"] = imp;
  }
  try {
    const MannWhitneyResult mw = mann_whitney_u_censored(times, base_times);
    col.p_value = mw.p_value < 1e-4 ? fmt("%.1e", mw.p_value) : fmt("%.4f", mw.p_value);
    row["mann_whitney_p"] = mw.p_value;
  } catch (const std::exception&) {
    col.p_value = "n/a";
  }
  const double pf = probability_of_improvement_censored(times, base_times);
  col.p_faster = fmt("%.2f", pf);
  row["probability_faster"] = pf;
  return col;
}

// Writes context c's row of a run table (and appends its numbers to rows); returns whether some of
// its trials never reached the threshold.
bool run_table_row(const std::string& c, const Results& r, const BatchTable& t,
                   const std::vector<CensoredTime>& base_times, double base_mean, std::ostringstream& md, json& rows) {
  json row = {{"context", c}, {"trials", r.ok.size()}, {"failed", r.failed}, {"pending", r.pending}};
  if (r.ok.empty()) {
    md << "| " << c << " | - | - | - | - | - | - | - | - | - | " << trials_note(r) << " |\n";
    rows.push_back(row);
    return false;
  }
  const std::vector<CensoredTime> times = times_of(r);
  const std::vector<double> tv = censored_values(times);
  const double reached = fraction_reached(times);
  const bool censored = reached < 1.0;
  const double m = mean(tv), med = median(tv);
  const ConfidenceInterval iqm = bootstrap_ci(tv, interquartile_mean, kBootstrapSeed);
  const Pooled fin = pool(r.ok, "final_episodes");
  const std::string lb = censored ? "≥ " : "";
  row["time_mean_s"] = m;
  row["time_median_s"] = med;
  row["time_iqm_s"] = iqm.estimate;
  row["time_iqm_ci_s"] = {iqm.low, iqm.high};
  row["fraction_reached"] = reached;
  row["reward_mean"] = fin.mean;
  row["reward_std"] = fin.std;
  row["success_rate"] = fin.success;
  row["final_episodes"] = fin.episodes;
  BaselineColumns col;
  if (c != t.baseline && !base_times.empty()) col = compare_with_baseline(times, base_times, base_mean, m, row);
  md << "| " << c << " | " << lb << format_min_sec(m) << " | " << col.improvement << " | " << fmt("%.1f", fin.mean)
     << " ± " << fmt("%.1f", fin.std) << " | " << pct(fin.success) << " | " << lb << format_min_sec(med) << " | "
     << lb << format_min_sec(iqm.estimate) << " [" << format_min_sec(iqm.low) << ", " << format_min_sec(iqm.high)
     << "] | " << pct(reached) << " | " << col.p_value << " | " << col.p_faster << " | " << trials_note(r) << " |\n";
  rows.push_back(row);
  return censored;
}

// The paragraph under a run table saying what its columns mean.
void run_table_notes(bool any_censored, std::ostringstream& md) {
  md << "\nTrain time is **simulated** time (not wall time) until the greedy policy first reached the "
        "threshold success rate at a checkpoint, in min:sec; the mean over trials (then median, interquartile "
        "mean with its 95% percentile-bootstrap interval). % Improvement compares the means with the "
        "baseline's. Avg. reward ± std (population std) and success rate pool every trial's final greedy "
        "evaluation. Reached: the fraction of trials that reached the threshold within the budget.";
  if (any_censored)
    md << " Trials that never reached it count at their whole training time (right-censored), so the values "
          "marked ≥ are lower bounds; the Mann-Whitney U test and P(faster) rank them as slower than every trial "
          "that reached it.";
  md << " P(faster): the probability that a trial of the row is faster than one of the baseline.\n\n";
}

// Usage: share of the final greedy policies' decisions per action, mean over trials, listed per
// context; returns the shares by context and action.
json usage_shares(const BatchRun& run, const Folder& folder, std::ostringstream& md) {
  md << "### Usage of the final policies\n\nShare of the decisions of each action in the final greedy "
        "evaluation, mean over trials.\n\n";
  json usage_rows = json::object();
  for (const auto& c : run.contexts) {
    const Results r = folder.run(run, c);
    if (r.ok.empty()) continue;
    std::vector<std::string> order;
    for (const auto& a : r.ok.front().value("psi", json::array())) order.push_back(a.get<std::string>());
    std::map<std::string, double> share;
    for (const auto& j : r.ok)
      for (auto it = usage_of(j).begin(); it != usage_of(j).end(); ++it) share[it.key()] += it->get<double>() / double(r.ok.size());
    md << "- " << c << ":";
    for (const auto& a : order) {
      md << " " << a << " " << pct(share[a]) << (a == order.back() ? "" : ",");
      usage_rows[c][a] = share[a];
    }
    md << "\n";
  }
  return usage_rows;
}

// The table's usage comparisons: the share of a skill's decisions among itself and the actions it
// subsumes, mean +- std over trials; returns them.
json usage_comparisons(const BatchRun& run, const BatchTable& t, const Folder& folder, std::ostringstream& md) {
  json comparisons = json::array();
  for (const auto& u : t.usage) {
    const Results r = folder.run(run, u.context);
    std::vector<double> ratios;
    for (const auto& j : r.ok) {
      const json& us = usage_of(j);
      const double s = us.value(u.skill, 0.0);
      double total = s;
      for (const auto& a : u.subsumes) total += us.value(a, 0.0);
      if (total > 0) ratios.push_back(s / total);
    }
    std::string subs;
    for (const auto& a : u.subsumes) subs += (subs.empty() ? "" : ", ") + a;
    if (ratios.empty()) {
      md << "\n" << u.context << ": no trial used " << u.skill << " or " << subs << ".\n";
      continue;
    }
    md << "\n" << u.context << ": " << u.skill << " makes " << pct(mean(ratios)) << " ± " << pct(population_std(ratios))
       << " of the decisions among itself and the actions it subsumes (" << subs << "), mean ± std over "
       << ratios.size() << " trials.\n";
    comparisons.push_back({{"context", u.context}, {"skill", u.skill}, {"subsumes", u.subsumes},
                           {"share_mean", mean(ratios)}, {"share_std", population_std(ratios)},
                           {"trials", ratios.size()}});
  }
  return comparisons;
}

// Why the trials of a run that missed the threshold missed it: the causes their result.json names
// (batch/explain.h), one line per trial; returns them ([] when every trial reached it).
json why_not_reached(const BatchRun& run, const Folder& folder, std::ostringstream& md) {
  json out = json::array();
  for (const auto& c : run.contexts) {
    const Results r = folder.run(run, c);
    for (const auto& j : r.ok) {
      if (!j.contains("diagnosis") || j.value("reached", true)) continue;  // --explain explains them all
      const int trial = j.value("trial", 0);
      std::vector<std::string> causes = j["diagnosis"]["causes"].get<std::vector<std::string>>();
      if (causes.empty()) causes.push_back("nothing stands out in the data");
      if (out.empty()) md << "\n### Why trials did not reach the threshold\n\nWhat each trial's own data shows "
                             "(its result.json, \"diagnosis\"; docs/curricula.md, Why a training failed).\n\n";
      md << "- " << c << ", trial " << trial << " (`trials/" << batch_trial_id(run.name, c, trial) << "`): ";
      for (size_t k = 0; k < causes.size(); ++k) md << (k ? "; " : "") << causes[k];
      md << ".\n";
      out.push_back({{"context", c}, {"trial", trial}, {"causes", causes}});
    }
  }
  return out;
}

// Table I / II: a run's contexts against its baseline.
void run_table(const BatchScript& b, const BatchTable& t, const Folder& folder, std::ostringstream& md, json& rep) {
  const BatchRun& run = *b.run(t.run);
  const Results base = folder.run(run, t.baseline);
  const std::vector<CensoredTime> base_times = times_of(base);
  const double base_mean = base_times.empty() ? 0.0 : mean(censored_values(base_times));
  run_table_head(run, t, md);
  json rows = json::array();
  bool any_censored = false;
  for (const auto& c : run.contexts)
    if (run_table_row(c, folder.run(run, c), t, base_times, base_mean, md, rows)) any_censored = true;
  run_table_notes(any_censored, md);

  const json usage_rows = usage_shares(run, folder, md);
  const json comparisons = usage_comparisons(run, t, folder, md);
  const json why = why_not_reached(run, folder, md);
  md << "\n";
  rep.push_back({{"title", t.title}, {"run", run.name}, {"baseline", t.baseline}, {"rows", rows},
                 {"usage", usage_rows}, {"usage_comparisons", comparisons}});
  if (!why.empty()) rep.back()["why_not_reached"] = why;  // absent when all reached: reports stay as they were
}

// The distinct worlds of some evaluation trials: the union of their seeds [first_seed, first_seed
// + episodes). Policies that share worlds (common random numbers) count each world once.
int64_t distinct_worlds(const std::vector<json>& evals) {
  std::vector<std::pair<int64_t, int64_t>> spans;  // [first, last + 1)
  for (const auto& j : evals) {
    const double first = num(j, "first_seed"), n = num(j, "episodes");
    if (!(first >= 0 && first <= 9007199254740992.0 && first == std::floor(first)))
      throw Error("a trial result's 'first_seed' is not a seed: " + fmt("%g", first));
    spans.push_back({int64_t(first), int64_t(first) + int64_t(n)});
  }
  std::sort(spans.begin(), spans.end());
  int64_t count = 0, covered = INT64_MIN;
  for (const auto& [a, b] : spans) {
    if (b > std::max(a, covered)) count += b - std::max(a, covered);
    covered = std::max(covered, b);
  }
  return count;
}

// One row of an evaluation table: pooled episodes, the per-policy rates, the distinct worlds and
// the success rate's 95% Wilson interval with the worlds as its draws (the episodes when no world
// repeats; when policies share worlds only the worlds are independent draws, so the interval
// does not claim the precision of episodes that replay them).
struct EvalRow {
  Pooled p;
  std::vector<double> rates;
  int64_t worlds = 0;
  ConfidenceInterval ci;
};

// The row of some evaluation trials; worlds < 0: their distinct worlds, counted.
EvalRow eval_row(const std::vector<json>& evals, int64_t worlds = -1) {
  EvalRow r;
  r.p = pool(evals, "episodes");
  for (const auto& j : evals) r.rates.push_back(num(j, "success_rate"));
  r.worlds = worlds >= 0 ? worlds : distinct_worlds(evals);
  if (r.worlds > 0) r.ci = wilson_interval(r.p.success * double(r.worlds), double(r.worlds));
  return r;
}

// Writes an evaluation table's row (name, policies column) and returns its numbers for report.json.
json eval_row_out(const std::string& name, const std::string& object, const EvalRow& r, const std::string& policies,
                  std::ostringstream& md) {
  md << "| " << name << " | " << fmt("%.1f", r.p.mean) << " ± " << fmt("%.3f", r.p.std) << " | " << pct(r.p.success)
     << " [" << pct(r.ci.low) << ", " << pct(r.ci.high) << "] | " << pct(mean(r.rates)) << " ± "
     << pct(population_std(r.rates)) << " | " << policies << " | " << r.p.episodes << " | " << r.worlds << " |\n";
  return {{"object", object}, {"reward_mean", r.p.mean}, {"reward_std", r.p.std}, {"success_rate", r.p.success},
          {"success_low", r.ci.low}, {"success_high", r.ci.high}, {"policies", r.rates.size()},
          {"episodes", r.p.episodes}, {"worlds", r.worlds}};
}

// The head of an evaluation table: its title, whose policies, where, and how they met their worlds.
void eval_table_head(const BatchTable& t, const BatchEvaluation& ev, std::ostringstream& md) {
  md << "## " << (t.title.empty() ? "Evaluation " + ev.name : t.title) << "\n\n";
  md << "The final " << ev.run << "/" << ev.context << " policy of each of " << ev.trials << " trials, without "
     << "retraining, in scenario " << (ev.scenario.empty() ? "(the stage's)" : "`" + ev.scenario + "`");
  if (!ev.params.empty()) {
    md << " with";
    for (const auto& [k, v] : ev.params) md << " " << k << "=" << v;
  }
  md << ", " << ev.episodes << " episodes per policy and object, "
     << (ev.shared_worlds ? "every policy in the same worlds (shared: common random numbers, for paired comparisons)"
                          : "each policy in worlds of its own")
     << ".\n\n";
  md << "| Object | Avg. reward ± std | Success rate [95% CI] | Success rate per policy (mean ± std) | Policies | "
        "Episodes | Worlds |\n";
  md << "|---|---|---|---|---|---|---|\n";
}

// Table III: an evaluation per shape, and a Total row.
void eval_table(const BatchScript& b, const BatchTable& t, const Folder& folder, std::ostringstream& md, json& rep) {
  const BatchEvaluation* ev = nullptr;
  for (const auto& e : b.evaluations)
    if (e.name == t.evaluation) ev = &e;
  eval_table_head(t, *ev, md);
  json rows = json::array();
  std::vector<json> all;
  int expected = 0;
  int64_t all_worlds = 0;  // shapes differ, so their worlds add up
  for (const auto& g : batch_eval_groups(*ev)) {
    std::vector<std::string> ids;
    for (int i = 0; i < ev->trials; ++i) ids.push_back(batch_eval_id(ev->name, g, i));
    const Results r = folder.trials(ids);
    expected += r.expected;
    std::string name = g;
    if (!name.empty()) name[0] = char(std::toupper(static_cast<unsigned char>(name[0])));
    if (r.ok.empty()) {
      md << "| " << name << " | - | - | - | " << trials_note(r) << " | 0 | 0 |\n";
      continue;
    }
    const EvalRow row = eval_row(r.ok);
    all.insert(all.end(), r.ok.begin(), r.ok.end());
    all_worlds += row.worlds;
    rows.push_back(eval_row_out(name, g, row, trials_note(r), md));
  }
  if (!all.empty())
    rows.push_back(eval_row_out("**Total**", "Total", eval_row(all, all_worlds),
                                std::to_string(all.size()) + "/" + std::to_string(expected), md));
  md << "\nAvg. reward ± std (population std) and success rate pool every episode of every policy; the per-policy "
        "column shows how much the policies of different trials differ. Worlds: the distinct worlds (seeds) "
        "the episodes ran in. The 95% interval of the success rate is Wilson's score interval with the worlds "
        "as its draws: when policies share worlds, their episodes replay the same draws and add no precision.\n\n";
  rep.push_back({{"title", t.title}, {"evaluation", ev->name}, {"rows", rows}});
}

std::vector<std::string> figure_paths(const std::string& dir, const std::string& file) {
  return {(fs::path(dir) / (file + ".png")).string(), (fs::path(dir) / (file + ".svg")).string()};
}

// One context's learning curves on their common grid: the grid in minutes, each trial's values
// there, and their mean, std and IQM bands.
struct ContextCurves {
  std::string context;
  std::vector<double> minutes;
  std::vector<std::vector<double>> values;
  CurveBands bands;
};

// A run's learning curves per context: greedy reward at the checkpoints against simulated
// training minutes (contexts without a finished trial are left out).
std::vector<ContextCurves> run_curves(const BatchRun& run, const Folder& folder, bool log_x) {
  std::vector<ContextCurves> out;
  for (const auto& c : run.contexts) {
    const Results r = folder.run(run, c);
    std::vector<std::vector<std::pair<double, double>>> trials;
    for (const auto& j : r.ok) {
      std::vector<std::pair<double, double>> pts;
      for (const auto& cp : j.value("checkpoints", json::array())) pts.emplace_back(num(cp, "sim_s"), num(cp, "reward_mean"));
      trials.push_back(std::move(pts));
    }
    CurveGrid g = curve_grid(trials, kCurvePoints, log_x);
    if (g.t.empty()) continue;
    ContextCurves cc{c, {}, std::move(g.values), {}};
    for (double t : g.t) cc.minutes.push_back(t / 60.0);
    cc.bands = curve_bands(cc.values, dashboard::kCurveBootstrapSeed, dashboard::kCurveResamples);
    out.push_back(std::move(cc));
  }
  return out;
}

// The axes of every learning-curve figure.
CurveOptions curve_options(bool log_x) {
  CurveOptions o;
  o.x_label = "Simulated training time (min)";
  o.y_label = "Average episodic reward (greedy)";
  o.log_x = log_x;
  return o;
}

// A run's learning curves (Figures 3 and 4): mean +- std per context.
bool curves_figure(const BatchScript& b, const BatchFigure& f, const Folder& folder, std::vector<std::string>& written,
                   json& page) {
  const BatchRun& run = *b.run(f.run);
  std::vector<CurveSeries> series;
  json page_series = json::array();
  for (const ContextCurves& cc : run_curves(run, folder, f.log_x)) {
    page_series.push_back(dashboard::curve_series(cc.context, cc.minutes, cc.bands, cc.values.size()));
    series.push_back({cc.context, cc.minutes, cc.bands.mean, cc.bands.std, {}, {}});
  }
  page.push_back({{"kind", "curves"}, {"file", f.file}, {"run", run.name}, {"log_x", f.log_x},
                  {"title", f.title.empty() ? "Learning curves: stage " + run.stage : f.title},
                  {"series", page_series}});
  if (series.empty()) return false;
  const auto paths = figure_paths(folder.dir(), f.file);
  plot_learning_curves(paths, f.title.empty() ? "Learning curves: stage " + run.stage : f.title, series,
                       curve_options(f.log_x));
  written.insert(written.end(), paths.begin(), paths.end());
  return true;
}

// The IQM learning curves of a run's stage: per context the interquartile mean over trials inside
// its 95% bootstrap band, on the time axis of the run's own curves figure (log when it is). Its
// line for tables.md, whether drawn or not.
std::string iqm_figure(const BatchScript& b, const BatchRun& run, const Folder& folder,
                       std::vector<std::string>& written) {
  bool log_x = false;
  for (const auto& f : b.figures)
    if (f.kind != "cumulative" && f.run == run.name) log_x = log_x || f.log_x;
  std::vector<CurveSeries> series;
  for (const ContextCurves& cc : run_curves(run, folder, log_x))
    series.push_back({cc.context, cc.minutes, cc.bands.iqm, {}, cc.bands.iqm_low, cc.bands.iqm_high});
  const std::string file = "iqm_" + run.name;
  const std::string title = "IQM learning curves: stage " + run.stage +
                            (run.name == run.stage ? std::string() : " (run " + run.name + ")");
  std::string line = "- `" + file + ".png` / `" + file + ".svg`: " + title;
  if (series.empty()) return line + " (not drawn: no finished trial)";
  CurveOptions o = curve_options(log_x);
  o.y_label = "IQM of the greedy episodic reward";
  const auto paths = figure_paths(folder.dir(), file);
  plot_learning_curves(paths, title, series, o);
  written.insert(written.end(), paths.begin(), paths.end());
  return line;
}

// Cumulative training time per context: the skills' runs (the trial's own skill source) then the run.
bool cumulative_figure(const BatchScript& b, const BatchFigure& f, const Folder& folder, std::vector<std::string>& written,
                       json& page) {
  const BatchRun& run = *b.run(f.run);
  std::vector<std::string> categories;
  std::vector<BarStack> stacks;
  for (const auto& s : run.skills) stacks.push_back({s.run + " (" + s.skill + ", " + s.context + ")", {}});
  stacks.push_back({run.name, {}});
  for (const auto& c : run.contexts) {
    const Results r = folder.run(run, c);
    if (r.ok.empty()) continue;
    categories.push_back(c);
    for (size_t k = 0; k < run.skills.size(); ++k) {
      const BatchSkill& s = run.skills[k];
      std::vector<double> v;
      for (const auto& j : r.ok) {
        const int i = j.value("trial", 0);
        const Results src = folder.trials({batch_trial_id(s.run, s.context, i)});
        if (!src.ok.empty()) v.push_back(num(src.ok.front(), "time_to_threshold_s") / 60.0);
      }
      stacks[k].values.push_back(v.empty() ? 0.0 : mean(v));
    }
    std::vector<double> v;
    for (const auto& j : r.ok) v.push_back(num(j, "time_to_threshold_s") / 60.0);
    stacks.back().values.push_back(mean(v));
  }
  json page_stacks = json::array();
  for (const auto& st : stacks) page_stacks.push_back({{"name", st.name}, {"minutes", st.values}});
  page.push_back({{"kind", "cumulative"}, {"file", f.file}, {"run", run.name}, {"categories", categories},
                  {"title", f.title.empty() ? "Cumulative training time" : f.title}, {"stacks", page_stacks}});
  if (categories.empty()) return false;
  BarOptions o;
  o.y_label = "Cumulative simulated training time (min)";
  o.value_label = [](double m) { return format_min_sec(60.0 * m); };
  const auto paths = figure_paths(folder.dir(), f.file);
  plot_stacked_bars(paths, f.title.empty() ? "Cumulative training time" : f.title, categories, stacks, o);
  written.insert(written.end(), paths.begin(), paths.end());
  return true;
}

}  // namespace

// One stage's sorting figures over its trials' final greedy evaluations. The objects sorted per
// episode are the world's count at the end of each episode (final_sorted_mean). Results written
// before the trainer counted them have only the reward, from which they follow as
// curricula/sorting.lua paid it then (100 when every object is sorted; 100 k / n - 100 at the
// time-out with k of n sorted): a trial with success rate s and mean reward R sorted
// n s + n (R + 100 - 200 s) / 100 per episode.
struct SortingFigures {
  bool any = false;
  std::vector<double> rates;
  double sorted = 0.0, seconds_per_object = 0.0;
  int reached = 0, trials = 0;
};
SortingFigures sorting_figures(const Results& r, int n) {
  SortingFigures f;
  f.trials = int(r.ok.size());
  if (r.ok.empty()) return f;
  f.any = true;
  double sorted = 0.0, seconds = 0.0;
  for (const auto& j : r.ok) {
    const double s = num(j, "success_rate"), reward = num(j, "reward_mean");
    f.rates.push_back(s);
    sorted += j.contains("final_sorted_mean") ? num(j, "final_sorted_mean")
                                              : n * s + n * (reward + 100.0 - 200.0 * s) / 100.0;
    seconds += j.contains("final_time_mean") ? num(j, "final_time_mean") : 0.0;
    f.reached += j.value("reached", false) ? 1 : 0;
  }
  f.sorted = sorted / double(r.ok.size());
  f.seconds_per_object = f.sorted > 0.0 ? seconds / double(r.ok.size()) / f.sorted : 0.0;
  return f;
}

// A sorting table: one row per number of objects, the hand-written and the learned policy side by side.
void sorting_table(const BatchScript& b, const BatchTable& t, const Folder& folder, std::ostringstream& md, json& rep) {
  md << "## " << (t.title.empty() ? std::string("Sorting") : t.title) << "\n\n";
  md << "| Objects | Hand-written: success | sorted per episode | sim. s per object | Learned: success, mean (min-max) "
        "| sorted per episode | sim. s per object | reached threshold |\n";
  md << "|---|---|---|---|---|---|---|---|\n";
  json rows = json::array();
  auto figures = [&](const std::string& name, int n) {
    if (name.empty()) return SortingFigures{};
    const BatchRun& run = *b.run(name);
    return sorting_figures(folder.run(run, run.contexts.front()), n);
  };
  for (const auto& row : t.sorting) {
    const SortingFigures hand = figures(row.hand, row.objects), learned = figures(row.learned, row.objects);
    md << "| " << row.objects << " | ";
    if (hand.any)
      md << pct(mean(hand.rates)) << " | " << fmt("%.2f", hand.sorted) << " | " << fmt("%.1f", hand.seconds_per_object) << " | ";
    else
      md << "- | - | - | ";
    if (learned.any)
      md << pct(mean(learned.rates)) << " (" << pct(*std::min_element(learned.rates.begin(), learned.rates.end())) << "-"
         << pct(*std::max_element(learned.rates.begin(), learned.rates.end())) << ") | " << fmt("%.2f", learned.sorted)
         << " | " << fmt("%.1f", learned.seconds_per_object) << " | " << learned.reached << "/" << learned.trials << " |\n";
    else
      md << "- | - | - | - |\n";
    json j = {{"objects", row.objects}};
    if (hand.any) j["hand"] = {{"success_rate", mean(hand.rates)}, {"sorted", hand.sorted}, {"seconds_per_object", hand.seconds_per_object}};
    if (learned.any)
      j["learned"] = {{"success_rate", mean(learned.rates)}, {"sorted", learned.sorted},
                      {"seconds_per_object", learned.seconds_per_object}, {"reached", learned.reached}, {"trials", learned.trials}};
    rows.push_back(j);
  }
  md << "\nEach stage's final greedy policy per trial, evaluated on its held-out seeds. Success: every object "
        "in the region of its type and let go. Objects sorted per episode: the world's count at the end of "
        "each episode; simulated seconds per object are the "
        "evaluation's mean episode time (time-outs in full) over the objects sorted per episode. A hand-written "
        "policy learns nothing: its trials are the same policy evaluated again.\n\n";
  rep.push_back({{"title", t.title}, {"sorting", rows}});
}

std::vector<std::string> write_report(const std::string& dir) {
  // Every record is checked first (engine/batch/records.cpp): a corrupt trial stops the report
  // before anything is written, rather than being read as whatever its damage says.
  const BatchPlan plan = read_results_plan(dir);  // outlives the trials missing_trials points to
  for (const auto& m : missing_trials(plan))
    if (!m.problem.empty()) throw Error("trial " + m.trial->id + ": " + m.problem);
  const json manifest = read_manifest(dir);
  const BatchScript b = batch_config_from_json(manifest.value("config", json::object()));
  const Folder folder(dir);
  std::ostringstream md;
  md << "# Results: " << b.name << "\n\n";
  if (!b.description.empty()) md << b.description << "\n\n";
  md << "Batch script `" << manifest.value("script", std::string("?")) << "`, curriculum `" << b.curriculum
     << "`, roger " << manifest.value("version", std::string("?")) << "; trial i of every run has seed "
     << b.seed << " + i.\n\n";
  json rep = json::array();
  for (const auto& t : b.tables) {
    if (!t.sorting.empty()) sorting_table(b, t, folder, md, rep);
    else if (!t.run.empty()) run_table(b, t, folder, md, rep);
    else eval_table(b, t, folder, md, rep);
  }
  std::vector<std::string> written;
  std::vector<std::string> figures_md;
  json page_figures = json::array();
  for (const auto& f : b.figures) {
    const bool drawn = f.kind == "cumulative" ? cumulative_figure(b, f, folder, written, page_figures)
                                              : curves_figure(b, f, folder, written, page_figures);
    figures_md.push_back("- `" + f.file + ".png` / `" + f.file + ".svg`: " +
                         (f.title.empty() ? f.kind + " of run " + f.run : f.title) + (drawn ? "" : " (not drawn: no finished trial)"));
  }
  for (const BatchRun& run : b.runs) figures_md.push_back(iqm_figure(b, run, folder, written));
  md << "## Figures\n\n";
  for (const auto& l : figures_md) md << l << "\n";
  md << "\nLearning curves: each trial's greedy checkpoint rewards (the mean episodic reward of held-out "
        "episodes) against its simulated training time, interpolated linearly between checkpoints onto a "
        "common grid of "
     << kCurvePoints << " times (log-spaced on a log axis) from the latest first checkpoint to the latest last "
        "one; a trial that stopped early keeps its last value. Lines are the mean over trials, bands ± one "
        "(population) std. IQM learning curves (one per stage): on the same grid, the interquartile mean over "
        "trials with its 95% percentile-bootstrap interval at each time (" << dashboard::kCurveResamples
     << " resamples). Cumulative training time: mean simulated time-to-threshold of the skill's source "
        "trials (each trial uses the policy of the same-numbered source trial) stacked under the run's own.\n";
  const std::string tables = (fs::path(dir) / "tables.md").string();
  write_file_atomic(tables, md.str(), "cannot write tables.md");
  const std::string report_json = (fs::path(dir) / "report.json").string();
  write_file_atomic(report_json, json{{"tables", rep}}.dump(1) + "\n", "cannot write report.json");
  written.insert(written.begin(), {tables, report_json});
  const json page = {{"name", b.name}, {"description", b.description},
                     {"script", manifest.value("script", std::string("?"))}, {"curriculum", b.curriculum},
                     {"version", manifest.value("version", std::string("?"))}, {"seed", b.seed},
                     {"blocks", dashboard::markdown_blocks(md.str())}, {"tables", rep},
                     {"figures", page_figures}, {"trials", dashboard::trial_index(b, dir)}};
  for (const auto& f : dashboard::write_dashboard(dir, page)) written.push_back(f);
  return written;
}

}  // namespace roger
