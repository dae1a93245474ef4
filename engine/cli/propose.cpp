// propose.cpp: `roger propose`, a thin layer over engine/propose (docs/propose.md).
#include <cstdio>
#include <iostream>

#include "cli/commands.h"
#include "propose/propose.h"

namespace roger {

int command_propose(const ProposeArgs& a) {
  ProposeOptions o;
  o.curriculum = a.curriculum;
  o.stage = a.stage;
  o.context = a.context;
  o.budget_s = a.budget;
  o.out = a.out;
  o.seed = a.seed;
  o.trials = a.trials;
  o.probe_trials = a.probe_trials;
  o.probe_share = a.probe_share;
  o.max_candidates = a.max_candidates;
  o.prune_below = a.prune_below;
  o.progress = &std::cerr;
  const ProposeResult r = propose_curriculum(o);
  const Candidate& w = r.candidates[size_t(r.winner)];
  size_t evaluated = 0;
  for (const Candidate& c : r.candidates) evaluated += c.evaluated ? 1 : 0;
  // Those generated past --max-candidates are listed in propose.md, not run: say how many ran.
  const std::string not_run = evaluated == r.candidates.size()
                                  ? ""
                                  : " (" + std::to_string(evaluated) + " evaluated, the rest over --max-candidates)";
  std::printf("roger propose: stage %s, %zu candidate%s%s, %d round(s), %d trials run, %d reused\n", a.stage.c_str(),
              r.candidates.size(), r.candidates.size() == 1 ? "" : "s", not_run.c_str(), r.rounds, r.trials_run,
              r.trials_reused);
  // Without a success the "winner" is the starting context unchanged: say why, not only its name.
  if (r.successful_episodes == 0)
    std::printf("  probe          no successful episode in %d training episodes: no subgoal or pruning to build on, "
                "so the only candidate is the base (the starting context as given); a larger --budget or "
                "--probe-share lets the probe see successes\n", r.probe_episodes);
  else
    std::printf("  probe          %d successful episode%s of %d training episodes\n", r.successful_episodes,
                r.successful_episodes == 1 ? "" : "s", r.probe_episodes);
  std::printf("  spent          %.1f of %.0f simulated s (%.1f%%), the probe %.1f\n", r.spent_s, r.budget_s,
              100 * r.spent_s / r.budget_s, r.probe_s);
  for (const auto& caution : r.cautions) std::printf("  caution        %s\n", caution.c_str());
  std::printf("  winner         %s (%s): %s\n", w.id.c_str(), w.kind.c_str(), w.summary.c_str());
  std::printf("  wrote          %s (context P), %s\n", r.proposal_file.c_str(), r.report_file.c_str());
  return 0;
}

}  // namespace roger
