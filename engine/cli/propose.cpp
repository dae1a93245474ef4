// propose.cpp: `roger propose`, a thin layer over engine/propose (docs/propose.md).
#include <cstdio>
#include <iostream>

#include "cli/cli_internal.h"
#include "cli/commands.h"
#include "core/interrupt.h"
#include "core/text.h"
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
  o.limits = sandbox_limits(a.lua);
  o.progress = &std::cerr;
  // Every finished trial's record stays in --out, and the same command reuses it (propose.h).
  catch_interrupts("the trial running ends at its next episode; every finished trial's record is kept");
  ProposeResult r;
  try {
    r = propose_curriculum(o);
  } catch (const std::exception&) {
    if (!interrupt_requested()) throw;
    std::fflush(stdout);
    std::fprintf(stderr, "roger propose: interrupted; run the same command again: it reuses the records of the "
                 "finished trials in %s, and the trial that was running starts afresh\n", a.out.c_str());
    return interrupt_exit_status();
  }
  const Candidate& w = r.candidates[size_t(r.winner)];
  size_t evaluated = 0;
  for (const Candidate& c : r.candidates) evaluated += c.evaluated ? 1 : 0;
  // Those generated past --max-candidates are listed in propose.md, not run: say how many ran.
  const std::string not_run = evaluated == r.candidates.size()
                                  ? ""
                                  : " (" + std::to_string(evaluated) + " evaluated, the rest over --max-candidates)";
  std::printf("roger propose: stage %s, %s%s, %s, %s run, %d reused\n", a.stage.c_str(),
              counted(long(r.candidates.size()), "candidate").c_str(), not_run.c_str(),
              rounds_said(r).c_str(), counted(r.trials_run, "trial").c_str(), r.trials_reused);
  for (const auto& file : r.unreadable)
    std::printf("  unreadable     %s could not be read: its trial was run again\n", file.c_str());
  // Found by a probe: after an edit everything ran again, "0 reused", without a word of why.
  if (r.stale_records > 0)
    std::printf("  run again      %s of an earlier search here %s made from other sources (the curriculum, "
                "its scenario or roger changed since) or with another cap: %s trial%s ran again\n",
                counted(r.stale_records, "record").c_str(), r.stale_records == 1 ? "was" : "were",
                r.stale_records == 1 ? "its" : "their", r.stale_records == 1 ? "" : "s");
  // Without a success the "winner" is the starting context unchanged: say why, not only its name.
  if (r.successful_episodes == 0)
    std::printf("  probe          no successful episode in %d training episodes: no subgoal or pruning to build on, "
                "so the only candidate is the base (the starting context as given); a larger --budget or "
                "--probe-share lets the probe see successes\n", r.probe_episodes);
  else
    std::printf("  probe          %d successful episode%s of %d training episodes\n", r.successful_episodes,
                r.successful_episodes == 1 ? "" : "s", r.probe_episodes);
  // Successes, and still the base alone: say why (found by a probe: it said only "1 candidate").
  if (r.successful_episodes > 0 && r.candidates.size() == 1)
    std::printf("  candidates     the base alone: in the successful probe episodes no action of Psi converged at a "
                "decision after the first in at least half of them (no subgoal), and every action ran %.0f%% of "
                "their control ticks or more, or reached the goal (nothing to prune); docs/propose.md, The method\n",
                100 * a.prune_below);
  // The budget as given (found by a probe: --budget 150.5 read "of 150").
  std::printf("  spent          %.1f of %s simulated s (%.1f%%), of which the probe %.1f\n", r.spent_s,
              format_number(r.budget_s).c_str(), 100 * r.spent_s / r.budget_s, r.probe_s);
  for (const auto& caution : r.cautions) std::printf("  caution        %s\n", caution.c_str());
  std::printf("  winner         %s (%s): %s\n", w.id.c_str(), w.kind.c_str(), w.summary.c_str());
  std::printf("  wrote          %s (context P), %s\n", r.proposal_file.c_str(), r.report_file.c_str());
  if (const char* home = std::getenv("ROGER_HOME"); home && *home)
    std::printf("  note           the proposal loads with ROGER_HOME=%s, as it was proposed (roger check and roger "
                "train of it need it set)\n", shell_word(home).c_str());
  return 0;
}

}  // namespace roger
