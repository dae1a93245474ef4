// propose_report.cpp: propose.md, what a proposal search tried and why its winner won.
#include <algorithm>
#include <cstdio>
#include <sstream>

#include "core/fileio.h"
#include "core/text.h"
#include "propose/propose_internal.h"

namespace roger::propose_detail {

namespace {

std::string fmt(const char* f, double x) {
  char b[64];
  std::snprintf(b, sizeof b, f, x);
  return b;
}

// A markdown table cell: "phi4 <| phi2" keeps its bar.
std::string cell(const std::string& s) {
  std::string r;
  for (char ch : s) r += ch == '|' ? std::string("\\|") : std::string(1, ch);
  return r;
}

double spent(const Candidate& c) {
  double s = 0.0;
  for (const auto& t : c.trials) s += t.spent_s;
  return s;
}

// A trial's last checkpoint: "none ran" when the task ran none, and why: the cap ended a subgoal
// stage (its loss of 2 x cap then measured no task training), or came before the task's first
// checkpoint (found by a probe: "none ran" said no reason).
std::string last_checkpoint(const CandidateTrial& t) {
  if (t.checkpoints != 0) return fmt("%.0f%%", 100 * t.last_success);
  if (t.checkpoints < 0) return "none ran";  // a record from before checkpoints were counted
  return "none ran: " + (t.cut.empty() ? std::string("the cap came before the task's first checkpoint") : cut_text(t));
}

}  // namespace

std::string cut_text(const CandidateTrial& t) {
  if (t.cut.empty()) return "";
  return "the cap ended " + t.cut + "'s stage " +
         (t.cut_reached ? "at its threshold, before its stop rule" : "short of its threshold");
}

namespace {

void probe_section(std::ostream& md, const ProposeOptions& o, const ProbeStats& probe, const ProbeSummary& s) {
  md << "## The probe\n\n" << counted(o.probe_trials, "trial") << " of context " << o.context << " capped at "
     << fmt("%.0f", o.budget_s * o.probe_share / o.probe_trials) << " simulated s each: "
     << counted(probe.episodes, "training episode") << ", " << fmt("%.0f", probe.sim_s) << " simulated s, "
     << counted(static_cast<long long>(probe.successes.size()), "successful episode") << ".\n\n";
  if (probe.successes.empty()) {
    // Nothing to read subgoals or pruning from: say so rather than print a table of zeros.
    md << "**No probe episode succeeded**, so there is no subgoal and no pruning to propose from: the only "
       << "candidate is the base (the starting context as given). A larger `--budget` or `--probe-share` "
       << "lets the probe see successes.\n\n";
    return;
  }
  md << "| action | share of successful time | subgoal: CONV reached in | median decision | most often while running |\n"
     << "|---|---|---|---|---|\n";
  for (size_t a = 0; a < probe.psi.size(); ++a) {
    md << "| " << cell(probe.psi[a]) << " | " << fmt("%.1f%%", 100 * s.tick_share[a]) << " | ";
    const auto it = std::find_if(s.subgoals.begin(), s.subgoals.end(), [&](const Subgoal& g) { return g.action == int(a); });
    if (it == s.subgoals.end()) md << "- | - | - |\n";
    else md << fmt("%.0f%%", 100 * it->share) << " | " << fmt("%.1f", it->order) << " | "
            << (it->achiever >= 0 ? cell(probe.psi[size_t(it->achiever)]) : "-") << " |\n";
  }
  md << "\nThe goal was reached most often while "
     << (s.final_achiever >= 0 ? "'" + probe.psi[size_t(s.final_achiever)] + "'" : "no recorded action") << " ran. "
     << "Pruning drops an action that ran under " << fmt("%.0f%%", 100 * o.prune_below)
     << " of the successful episodes' control ticks, never one the goal or a subgoal was reached under.\n\n";
}

void candidates_section(std::ostream& md, const ProposeResult& r) {
  md << "## The candidates\n\n| id | kind | final Psi (and learned subgoal stages) | trials | reached | score (mean loss, last round) | simulated s spent | result |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  for (size_t i = 0; i < r.candidates.size(); ++i) {
    const Candidate& c = r.candidates[i];
    int reached = 0;
    for (const auto& t : c.trials) reached += t.reached;
    md << "| " << c.id << " | " << c.kind << " | " << cell(c.summary) << " | " << c.trials.size() << " | " << reached << " | "
       << (c.trials.empty() ? "-" : fmt("%.1f", c.score)) << " | " << fmt("%.0f", spent(c)) << " | "
       << (!c.evaluated ? "not evaluated (over --max-candidates)"
           : int(i) == r.winner ? "**winner**"
           : c.eliminated_round > 0 ? "dropped in round " + std::to_string(c.eliminated_round) : "-")
       << " |\n";
  }
  md << "\nWhere each comes from:\n\n";
  for (const auto& c : r.candidates) md << "- " << c.id << ": " << c.why << ".\n";
  md << "\nEvery trial (seed, cap, what it spent; time = learned subgoal stages + the task's time-to-threshold):\n\n"
     << "| candidate | round | seed | cap s | spent s | of which subgoal stages | reached | time s | last checkpoint | loss |\n"
     << "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& c : r.candidates)
    for (const auto& t : c.trials)
      md << "| " << c.id << " | " << t.round << " | " << t.seed << " | " << fmt("%.1f", t.cap_s) << " | "
         << fmt("%.1f", t.spent_s) << " | " << fmt("%.1f", t.skills_s) << " | " << (t.reached ? "yes" : "no") << " | "
         << (t.reached ? fmt("%.1f", t.time_s) : "-") << " | "
         << last_checkpoint(t) << " | "
         << fmt("%.1f", t.loss) << " |\n";
}

void winner_section(std::ostream& md, const ProposeResult& r) {
  const Candidate& w = r.candidates[size_t(r.winner)];
  md << "## Why " << w.id << " won\n\n";
  const auto evaluated = std::count_if(r.candidates.begin(), r.candidates.end(), [](const Candidate& c) { return c.evaluated; });
  if (evaluated <= 1) {
    md << w.id << " is the only candidate evaluated (" << w.summary << "): with one candidate there is nothing to "
       << "halve, so no trial ran.\n\n";
    return;
  }
  if (r.rounds == 0) {
    md << w.id << " (" << w.summary << ") wins by default: no round of successive halving ranked the candidates, "
       << "as the budget ran out first (the cautions say how).\n\n";
    return;
  }
  const Candidate* runner = nullptr;
  for (const auto& c : r.candidates)
    if (&c != &w && c.eliminated_round == r.rounds && (!runner || c.score < runner->score)) runner = &c;
  md << w.id << " (" << w.kind << ": " << w.summary << ") had the lowest mean loss in the last round of successive "
     << "halving, " << fmt("%.1f", w.score);
  if (runner) md << ", against " << fmt("%.1f", runner->score) << " for " << runner->id << " (" << runner->summary << ")";
  md << ". A trial's loss is its simulated time to the threshold, learned subgoal stages included, when it "
     << "reached it within its cap, else cap x (2 - its last checkpoint's success rate), so any trial that reached "
     << "the threshold ranks before any that did not. It comes from: " << w.why << ".\n\n";
}

}  // namespace

void write_propose_report(const ProposeOptions& o, const TaskRef& task, const ProbeStats& probe,
                          const ProbeSummary& summary, const ProposeResult& r) {
  std::ostringstream md;
  md << "# roger propose: stage " << task.stage << " of " << task.module << "\n\n`" << task.command << "`\n\n"
     << "Budget " << fmt("%.0f", r.budget_s) << " simulated s of training; spent " << fmt("%.1f", r.spent_s)
     << " (" << fmt("%.1f", 100 * r.spent_s / r.budget_s) << "%): the probe " << fmt("%.1f", r.probe_s)
     << ", the candidates' trials " << fmt("%.1f", r.spent_s - r.probe_s) << ". Greedy checkpoint episodes are not "
     << "counted, as in the time-to-threshold of the paper. Successive halving over "
     << counted(std::count_if(r.candidates.begin(), r.candidates.end(), [](const Candidate& c) { return c.evaluated; }),
                "candidate")
     << " in " << rounds_said(r) << ", " << counted(o.trials, "seeded trial") << " per candidate and round "
     << "(Karnin et al. 2013; Jamieson and Talwalkar 2016; docs/propose.md). The proposal: `proposal.lua` ("
     << r.candidates[size_t(r.winner)].id << "), context P.\n\n";
  probe_section(md, o, probe, summary);
  candidates_section(md, r);
  md << "\n";
  if (!r.cautions.empty()) {
    md << "## Cautions\n\n";
    for (const auto& c : r.cautions) md << "- " << c << ".\n";
    md << "\n";
  }
  winner_section(md, r);
  write_file_atomic(r.report_file, md.str(), "cannot write propose.md");
}

}  // namespace roger::propose_detail
