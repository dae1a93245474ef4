// report_runs.cpp: Tables I and II (report_internal.h): a run's contexts against its baseline,
// with the usage of the final policies and why trials missed the threshold.
#include "report/report_internal.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include "core/error.h"
#include "core/text.h"

namespace roger::report_detail {
namespace {

// The head of a run table: its title, the run and baseline it compares, and the column names.
void run_table_head(const BatchRun& run, const BatchTable& t, std::ostringstream& md) {
  md << "## " << t.title << "\n\n";
  md << "Run `" << run.name << "`: stage " << run.stage << with_params(run.params) << ", baseline " << t.baseline
     << ".\n\n";
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
    // A censored mean is a lower bound: over a censored baseline the improvement is at least this,
    // of a censored row at most this, and with both no bound follows.
    const bool row_low = fraction_reached(times) < 1.0, base_low = fraction_reached(base_times) < 1.0;
    col.improvement = std::string(row_low && base_low ? "~ " : base_low ? "≥ " : row_low ? "≤ " : "") +
                      fmt("%.2f%%", imp);
    row["improvement_percent"] = imp;
    row["improvement_bound"] = row_low && base_low ? "none" : base_low ? "lower" : row_low ? "upper" : "exact";
  }
  // One trial against another gives a p-value of 1 and a P(faster) of 0, 0.5 or 1 whatever the
  // approaches: a test needs a sample on each side.
  if (times.size() < 2 || base_times.size() < 2) return col;
  try {
    const MannWhitneyResult mw = mann_whitney_u_censored(times, base_times);
    col.p_value = mw.p_value < 1e-4 ? fmt("%.1e", mw.p_value) : fmt("%.4f", mw.p_value);
    row["mann_whitney_p"] = mw.p_value;
    row["mann_whitney_exact"] = mw.exact;  // else the normal approximation
  } catch (const std::exception&) {
    col.p_value = "n/a";
  }
  const double pf = probability_of_improvement_censored(times, base_times);
  col.p_faster = fmt("%.2f", pf);
  row["probability_faster"] = pf;
  return col;
}

// Which of a row's times are lower bounds: those a censored trial enters (censored_far_values),
// the mean whenever a trial is censored; the median and the interquartile mean only when a
// censored trial falls inside their window (found by a probe: one of 24 trials censored marked
// an exact median with ≥).
struct TimeBounds {
  bool mean = false, median = false, iqm = false, iqm_low = false, iqm_high = false;
};

TimeBounds time_bounds(const std::vector<CensoredTime>& times, double med, const ConfidenceInterval& iqm) {
  TimeBounds b;
  if (fraction_reached(times) == 1.0) return b;
  const std::vector<double> far = censored_far_values(times);
  const ConfidenceInterval far_iqm = bootstrap_ci(far, interquartile_mean, kBootstrapSeed);
  b.mean = true;
  b.median = median(far) != med;
  b.iqm = far_iqm.estimate != iqm.estimate;
  b.iqm_low = far_iqm.low != iqm.low;
  b.iqm_high = far_iqm.high != iqm.high;
  return b;
}

}  // namespace

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
  const TimeBounds bound = time_bounds(times, med, iqm);
  const auto lb = [](bool b) { return b ? "≥ " : ""; };
  row["time_mean_s"] = m;
  row["time_median_s"] = med;
  row["time_iqm_s"] = iqm.estimate;
  // One trial has no interval (a bootstrap of one value is that value twice).
  row["time_iqm_ci_s"] = tv.size() < 2 ? json() : json{iqm.low, iqm.high};
  row["time_lower_bound"] = censored;  // the mean's: some trial is censored
  row["time_median_lower_bound"] = bound.median;
  row["time_iqm_lower_bound"] = bound.iqm;
  row["time_iqm_ci_lower_bound"] = tv.size() < 2 ? json() : json{bound.iqm_low, bound.iqm_high};
  row["fraction_reached"] = reached;
  row["reward_mean"] = fin.mean;
  row["reward_std"] = fin.std;
  row["success_rate"] = fin.success;
  row["final_episodes"] = fin.episodes;
  BaselineColumns col;
  if (c != t.baseline && !base_times.empty()) col = compare_with_baseline(times, base_times, base_mean, m, row);
  md << "| " << c << " | " << lb(bound.mean) << format_min_sec(m) << " | " << col.improvement << " | "
     << fmt("%.1f", fin.mean) << " ± " << fmt("%.1f", fin.std) << " | " << rate_pct(fin.success) << " | "
     << lb(bound.median) << format_min_sec(med) << " | " << lb(bound.iqm) << format_min_sec(iqm.estimate)
     << (tv.size() < 2 ? std::string()
                       : " [" + std::string(lb(bound.iqm_low)) + format_min_sec(iqm.low) + ", " + lb(bound.iqm_high) +
                             format_min_sec(iqm.high) + "]")
     << " | " << rate_pct(reached) << " | " << col.p_value << " | " << col.p_faster << " | " << trials_note(r) << " |\n";
  rows.push_back(row);
  return censored;
}

// The paragraph under a run table saying what its columns mean.
void run_table_notes(bool any_censored, std::ostringstream& md) {
  md << "\nTrain time is **simulated** time (not wall time) until the first checkpoint from which the greedy "
        "policy's success rate stayed at or above the threshold, in min:sec; the mean over trials (then median, "
        "interquartile mean with its 95% percentile-bootstrap interval, none for one trial). % Improvement compares the means with the "
        "baseline's. Avg. reward ± std (population std) and success rate pool every trial's final greedy "
        "evaluation. Reached: the fraction of trials that reached the threshold within the budget.";
  if (any_censored)
    md << " Trials that never reached it count at their whole training time (right-censored), so the values "
          "marked ≥ are lower bounds (a median or interquartile mean is exact, and unmarked, when the censored "
          "trials, the slowest, lie outside its window); the Mann-Whitney U test and P(faster) rank them as "
          "slower than every trial that reached it. A % Improvement marked ≥ or ≤ is a bound for the same reason (the baseline's mean, "
          "or the row's, is a lower bound), and one marked ~ compares two lower bounds, so no bound follows.";
  md << " P(faster): the probability that a trial of the row is faster than one of the baseline; it and the "
        "p-value (exact with at most 20 trials a side, or 8 when times tie, then over the midranks; else the "
        "normal approximation) need two trials a side.\n\n";
}

namespace {

// Usage: share of the final greedy policies' decisions per action, mean over trials, listed per
// context; returns the shares by context and action, and in `order` each context's actions in
// the order of its Psi, as listed (a JSON object's keys come sorted by name).
json usage_shares(const BatchRun& run, const Folder& folder, std::ostringstream& md, json& order_of) {
  md << "### Usage of the final policies\n\nShare of the decisions of each action in the final greedy "
        "evaluation, mean over trials.\n\n";
  json usage_rows = json::object();
  for (const auto& c : run.contexts) {
    const Results r = folder.run(run, c);
    if (r.ok.empty()) {  // said, so that a heading over no context does not read as an empty result
      md << "- " << c << ": no finished trial\n";
      continue;
    }
    std::vector<std::string> order;
    for (const auto& a : r.ok.front().value("psi", json::array())) order.push_back(a.get<std::string>());
    std::map<std::string, double> share;
    for (const auto& j : r.ok)
      for (auto it = usage_of(j).begin(); it != usage_of(j).end(); ++it) share[it.key()] += it->get<double>() / double(r.ok.size());
    md << "- " << c << ":";
    order_of[c] = order;
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
    if (r.ok.empty()) {  // a partial report: nothing to say of its usage yet, and no claim of none
      md << "\n" << u.context << ": no finished trial yet.\n";
      continue;
    }
    if (ratios.empty()) {
      md << "\n" << u.context << ": no trial used " << u.skill << " or " << subs << ".\n";
      continue;
    }
    md << "\n" << u.context << ": " << u.skill << " makes " << pct(mean(ratios)) << " ± " << pct(population_std(ratios))
       << " of the decisions among itself and the actions it subsumes (" << subs << "), mean ± std over "
       << counted(ratios.size(), "trial") << ".\n";
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

}  // namespace

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
  json table = {{"title", t.title}, {"run", run.name}, {"baseline", t.baseline}, {"rows", rows}};
  std::vector<BatchRow> run_rows;
  for (const auto& c : run.contexts) run_rows.push_back({run.name, c});
  teaching_notes(b, run_rows, folder, md, table);

  json usage_order = json::object();
  table["usage"] = usage_shares(run, folder, md, usage_order);
  table[kUsageOrder] = usage_order;
  table["usage_comparisons"] = usage_comparisons(run, t, folder, md);
  const json why = why_not_reached(run, folder, md);
  md << "\n";
  if (!why.empty()) table["why_not_reached"] = why;  // absent when all reached: reports stay as they were
  rep.push_back(table);
}

}  // namespace roger::report_detail
