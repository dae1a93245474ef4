// report_evaluations.cpp: Table III and every evaluation table (report_internal.h): per shape, the
// pooled rewards and successes, the distinct worlds the episodes ran in and the success rate's
// 95% Wilson interval over them.
#include "report/report_internal.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>
#include <climits>

#include "core/error.h"

namespace roger::report_detail {
namespace {

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

}  // namespace

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

}  // namespace roger::report_detail
