// report_sorting.cpp: sorting tables (report_internal.h): per number of objects, the hand-written
// and the learned policy's final evaluations side by side.
#include "report/report_internal.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

namespace roger::report_detail {
namespace {

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

}  // namespace

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

}  // namespace roger::report_detail
