// report_evaluations.cpp: Table III and every evaluation table (report_internal.h): per shape, the
// pooled rewards and successes, the distinct layouts the episodes ran in and the success rate's
// 95% interval, resampled as the episodes were drawn (stats.h, pooled_rate_interval).
#include "report/report_internal.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "core/error.h"

namespace roger::report_detail {
namespace {

// One row of an evaluation table: pooled episodes, the per-policy rates and the success rate's
// interval (with the layouts and policies it resampled).
struct EvalRow {
  Pooled p;
  std::vector<double> rates;  // one per evaluation: a policy on the row's object (each object's, in the Total)
  std::set<int64_t> policies;  // the trial indices the evaluations are of
  RateInterval ci;
};

// The row of some evaluation trials (one shape's, or every shape's for the Total). The trial index
// names the policy (trial i of every shape runs the same policy). `salt` varies the bootstrap's
// seed from row to row.
EvalRow eval_row(const std::vector<json>& evals, uint64_t salt) {
  EvalRow r;
  r.p = pool(evals, "episodes");
  std::vector<RateCell> cells;
  for (const auto& j : evals) {
    r.rates.push_back(num(j, "success_rate"));
    r.policies.insert(int64_t(num(j, "trial")));
    append_rate_cells(j, int64_t(num(j, "trial")), "first_seed", "episodes", "outcomes", cells);
  }
  if (!cells.empty()) r.ci = pooled_rate_interval(cells, kBootstrapSeed + salt, kRateResamples);
  return r;
}

// Writes an evaluation table's row (name, policies column) and returns its numbers for report.json,
// with the trials of `counted` that failed or have no result yet, as a training row has them: a
// script that reads the rates sees that they pool fewer policies than the evaluation asked for.
json eval_row_out(const std::string& name, const std::string& object, const EvalRow& r, const Results& counted,
                  const std::string& policies, std::ostringstream& md) {
  md << "| " << name << " | " << fmt("%.1f", r.p.mean) << " ± " << fmt("%.1f", r.p.std) << " | " << rate_pct(r.p.success)
     << " [" << rate_pct(r.ci.ci.low) << ", " << rate_pct(r.ci.ci.high) << "] | " << rate_pct(mean(r.rates)) << " ± "
     << pct(population_std(r.rates)) << " | " << policies << " | " << r.p.episodes << " | " << r.ci.layouts << " |\n";
  return {{"object", object}, {"reward_mean", r.p.mean}, {"reward_std", r.p.std}, {"success_rate", r.p.success},
          {"success_low", r.ci.ci.low}, {"success_high", r.ci.ci.high}, {"interval", resampled_name(r.ci.by)},
          {"per_policy_success_mean", mean(r.rates)}, {"per_policy_success_std", population_std(r.rates)},
          {"policies", r.policies.size()}, {"evaluations", r.rates.size()}, {"episodes", r.p.episodes},
          {"layouts", r.ci.layouts}, {"failed", counted.failed}, {"pending", counted.pending}};
}

// The head of an evaluation table: its title, whose policies, where, and how they met their worlds.
void eval_table_head(const BatchTable& t, const BatchEvaluation& ev, std::ostringstream& md) {
  md << "## " << t.title << "\n\n";
  md << "The final " << ev.run << "/" << ev.context << " policy of "
     << (ev.trials == 1 ? std::string("1 trial") : "each of " + std::to_string(ev.trials) + " trials") << ", without "
     << "retraining, in " << (ev.scenario.empty() ? "its stage's own scenario" : "scenario `" + ev.scenario + "`")
     << with_params(ev.params);
  // A learned skill replaced: the same policies over another skill are another measure.
  for (const auto& s : ev.skills)
    md << ", with " << s.skill << " from run `" << s.run << "` context " << s.context << " (trial i's for trial i)";
  md << ", " << ev.episodes << " episodes per policy and object, "
     << (ev.shared_worlds ? "every policy in the same worlds (shared: common random numbers, for paired comparisons)"
                          : "each policy in worlds of its own")
     << ".\n\n";
  md << "| Object | Avg. reward ± std | Success rate [95% CI] | Success rate per policy (mean ± std) | Policies | "
        "Episodes | Layouts |\n";
  md << "|---|---|---|---|---|---|---|\n";
}

// Every trial of a shape must have run the episodes the evaluation asks for: what the rows
// resample is what it asked for (one that is no count at all is pool()'s to name).
void check_episode_counts(const BatchEvaluation& ev, const std::string& shape, const std::vector<json>& ok) {
  for (const auto& j : ok) {
    const double n = num(j, "episodes");
    if (n >= 0 && n <= 1e9 && n == std::floor(n) && n != double(ev.episodes))
      throw Error("a trial of evaluation '" + ev.name + "', shape " + shape + ", ran " + fmt("%g", n) +
                  " episodes; the evaluation asks for " + std::to_string(ev.episodes));
  }
}

// The Total row's count: its cells are policies' evaluations on one object each, said so that
// 200/200 is not read as 200 policies.
std::string total_count(const BatchEvaluation& ev, size_t evaluations, size_t shapes, const Results& every) {
  std::string count = std::to_string(evaluations) + "/" + std::to_string(every.expected);
  if (shapes > 1)
    count += " of " + (ev.trials == 1 ? std::string("1 policy") : std::to_string(ev.trials) + " policies") + " × " +
             std::to_string(shapes) + " objects";
  if (every.failed) count += " (" + std::to_string(every.failed) + " failed)";
  if (every.pending) count += " (" + std::to_string(every.pending) + " pending)";
  return count;
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
  std::set<Resampled> methods;
  Results every;  // the Total row's count: every policy on every object, failed and pending ones too
  uint64_t salt = 0;
  const std::vector<std::string> groups = batch_eval_groups(*ev);
  for (const auto& g : groups) {
    std::vector<std::string> ids;
    for (int i = 0; i < ev->trials; ++i) ids.push_back(batch_eval_id(ev->name, g, i));
    const Results r = folder.trials(ids);
    every.expected += r.expected;
    every.failed += r.failed;
    every.pending += r.pending;
    ++salt;
    std::string name = g;
    if (!name.empty()) name[0] = char(std::toupper(static_cast<unsigned char>(name[0])));
    if (r.ok.empty()) {
      md << "| " << name << " | - | - | - | " << trials_note(r) << " | 0 | 0 |\n";
      rows.push_back({{"object", g}, {"policies", 0}, {"evaluations", 0}, {"failed", r.failed}, {"pending", r.pending}});
      continue;
    }
    check_episode_counts(*ev, g, r.ok);
    const EvalRow row = eval_row(r.ok, salt);
    methods.insert(row.ci.by);
    all.insert(all.end(), r.ok.begin(), r.ok.end());
    rows.push_back(eval_row_out(name, g, row, r, trials_note(r), md));
  }
  if (!all.empty()) {
    const EvalRow total = eval_row(all, 0);
    methods.insert(total.ci.by);
    rows.push_back(eval_row_out("**Total**", "Total", total, every, total_count(*ev, all.size(), groups.size(), every), md));
  } else {  // counted as the shape rows are, with nothing to pool (found by a probe: it was left out)
    md << "| **Total** | - | - | - | " << total_count(*ev, 0, groups.size(), every) << " | 0 | 0 |\n";
    rows.push_back({{"object", "Total"}, {"policies", 0}, {"evaluations", 0}, {"failed", every.failed},
                    {"pending", every.pending}});
  }
  // A Total row without a result pools nothing: the note names none (found by a probe: it named one).
  md << "\nAvg. reward ± std (population std) and success rate pool every episode of every policy; the per-policy "
        "column shows how much the policies of different trials differ"
     << (all.empty() ? "" : " (in the Total row, each policy on each object)")
     << ". Layouts: the distinct world seeds the "
        "episodes ran in (a seed places Roger, the goal, the object and the obstacles; the shape is the row's). "
     << interval_note(methods) << "\n\n";
  rep.push_back({{"title", t.title}, {"evaluation", ev->name}, {"rows", rows}});
}

}  // namespace roger::report_detail
