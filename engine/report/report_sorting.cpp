// report_sorting.cpp: sorting tables (report_internal.h): per number of objects, the hand-written
// and the learned policy's final evaluations side by side.
#include "report/report_internal.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "core/text.h"

namespace roger::report_detail {
namespace {

// One stage's sorting figures over its trials' final greedy evaluations. The objects sorted per
// episode are the world's count at the end of each episode (final_sorted_mean). Results written
// before the trainer counted them have only the reward, from which they follow as
// curricula/sorting.lua paid it then (100 when every object is sorted; 100 k / n - 100 at the
// time-out with k of n sorted): a trial with success rate s and mean reward R sorted
// n s + n (R + 100 - 200 s) / 100 per episode.
// The success rate pools every trial's final evaluation, with its interval (stats.h,
// pooled_rate_interval): a learned run's trials are policies of their own; a hand-written run's
// trials are one policy evaluated again (`one_policy`), whose layouts alone are resampled.
struct SortingFigures {
  bool any = false;
  std::vector<double> rates;
  Pooled pooled;
  RateInterval ci;
  double sorted = 0.0, seconds_per_object = 0.0;
  int reached = 0, trials = 0;
  int failed = 0, pending = 0, expected = 0;  // the run's trials without a result (trials_note)
  std::string note;                           // " (1 failed of 3 trials)" when some have none, else ""
};
SortingFigures sorting_figures(const Results& r, int n, bool one_policy, uint64_t salt) {
  SortingFigures f;
  f.trials = int(r.ok.size());
  f.failed = r.failed, f.pending = r.pending, f.expected = r.expected;
  if (r.failed || r.pending) {
    std::string parts = r.failed ? std::to_string(r.failed) + " failed" : "";
    if (r.pending) parts += (parts.empty() ? "" : ", ") + std::to_string(r.pending) + " pending";
    f.note = " (" + parts + " of " + counted(r.expected, "trial") + ")";
  }
  if (r.ok.empty()) return f;
  f.any = true;
  f.pooled = pool(r.ok, "final_episodes");
  std::vector<RateCell> cells;
  double sorted = 0.0, seconds = 0.0;
  for (const auto& j : r.ok) {
    const double s = num(j, "success_rate"), reward = num(j, "reward_mean");
    append_rate_cells(j, one_policy ? 0 : int64_t(num(j, "trial")), "final_first_seed", "final_episodes",
                      "final_outcomes", cells);
    f.rates.push_back(s);
    sorted += j.contains("final_sorted_mean") ? num(j, "final_sorted_mean")
                                              : n * s + n * (reward + 100.0 - 200.0 * s) / 100.0;
    seconds += j.contains("final_time_mean") ? num(j, "final_time_mean") : 0.0;
    f.reached += j.value("reached", false) ? 1 : 0;
  }
  if (!cells.empty()) f.ci = pooled_rate_interval(cells, kBootstrapSeed + salt, kRateResamples);
  f.sorted = sorted / double(r.ok.size());
  f.seconds_per_object = f.sorted > 0.0 ? seconds / double(r.ok.size()) / f.sorted : 0.0;
  return f;
}

// "99.3% [98.0%, 100.0%]": a pooled success rate and its interval.
std::string rate_with_interval(const SortingFigures& f) {
  return rate_pct(f.pooled.success) + " [" + rate_pct(f.ci.ci.low) + ", " + rate_pct(f.ci.ci.high) + "]";
}

// The figures for report.json; the trials that failed or have no result yet always (a script that
// reads the rates sees what they pool), the figures when some trial has a result.
json figures_json(const SortingFigures& f) {
  json j = {{"failed", f.failed}, {"pending", f.pending}};
  if (!f.any) return j;
  j.update({{"success_rate", f.pooled.success}, {"success_low", f.ci.ci.low}, {"success_high", f.ci.ci.high},
            {"interval", resampled_name(f.ci.by)}, {"layouts", f.ci.layouts}, {"sorted", f.sorted},
            {"seconds_per_object", f.seconds_per_object}});
  return j;
}

}  // namespace

// A sorting table: one row per number of objects, the hand-written and the learned policy side by side.
void sorting_table(const BatchScript& b, const BatchTable& t, const Folder& folder, std::ostringstream& md, json& rep) {
  md << "## " << t.title << "\n\n";
  md << "| Objects | Hand-written: success [95% CI] | layouts | sorted per episode | sim. s per object | Learned: "
        "success [95% CI] | per trial (min-max) | layouts | sorted per episode | sim. s per object | reached threshold |\n";
  md << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  json rows = json::array();
  std::set<Resampled> methods;
  uint64_t salt = 0;
  auto figures = [&](const std::string& name, int n, bool one_policy) {
    ++salt;
    if (name.empty()) return SortingFigures{};
    const BatchRun& run = *b.run(name);
    SortingFigures f = sorting_figures(folder.run(run, run.contexts.front()), n, one_policy, salt);
    if (f.any) methods.insert(f.ci.by);
    return f;
  };
  for (const auto& row : t.sorting) {
    const SortingFigures hand = figures(row.hand, row.objects, true), learned = figures(row.learned, row.objects, false);
    // A run's trials that failed or have no result are said in its success cell (found by a probe:
    // a row of "-" read as a run never asked for, and its rates as pooling every trial).
    md << "| " << row.objects << " | ";
    if (hand.any)
      md << rate_with_interval(hand) << hand.note << " | " << hand.ci.layouts << " | " << fmt("%.2f", hand.sorted)
         << " | " << fmt("%.1f", hand.seconds_per_object) << " | ";
    else
      md << (hand.note.empty() ? "-" : "-" + hand.note) << " | - | - | - | ";
    if (learned.any)
      md << rate_with_interval(learned) << learned.note << " | "
         << rate_pct(*std::min_element(learned.rates.begin(), learned.rates.end())) << "-"
         << rate_pct(*std::max_element(learned.rates.begin(), learned.rates.end())) << " | " << learned.ci.layouts
         << " | " << fmt("%.2f", learned.sorted) << " | " << fmt("%.1f", learned.seconds_per_object) << " | "
         << learned.reached << "/" << learned.trials << " |\n";
    else
      md << (learned.note.empty() ? "-" : "-" + learned.note) << " | - | - | - | - | - |\n";
    json j = {{"objects", row.objects}};
    if (!row.hand.empty()) j["hand"] = figures_json(hand);
    if (!row.learned.empty()) {
      j["learned"] = figures_json(learned);
      j["learned"]["reached"] = learned.reached;
      j["learned"]["trials"] = learned.trials;
    }
    rows.push_back(j);
  }
  md << "\nEach stage's final greedy policy per trial, evaluated on the stage's held-out seeds or, with the run's "
        "final_worlds = \"own\", on worlds of its own (trial i's from the held-out seeds + i * episodes); success "
        "pools every trial's episodes. Success: every object in the region of its type and let go. Layouts: the distinct world seeds of those episodes. Objects "
        "sorted per episode: the world's count at the end of each episode; simulated seconds per object are the "
        "evaluation's mean episode time (time-outs in full) over the objects sorted per episode. A hand-written "
        "policy learns nothing: its trials are the same policy evaluated again, so its episodes count as one "
        "policy's. "
     << interval_note(methods) << "\n\n";
  rep.push_back({{"title", t.title}, {"sorting", rows}});
}

}  // namespace roger::report_detail
