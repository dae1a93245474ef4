// Module propose: proposing a developmental curriculum for a task automatically (roger propose).
// From one stage of a curriculum (its actions, reward and absorbing predicate) it runs a short
// probe of the task, reads from the probe's successful episodes which controllers they pass
// through converged (candidate subgoals), in which order and by which action, and how long each
// action ran (the pruning statistic); it writes candidate curricula as Lua files, evaluates them by
// short seeded training runs under successive halving, counting every simulated second the search
// trains, and writes the winner as a curriculum (proposal.lua) with a report (propose.md).
// Depends on batch (train_stage) and below; must not depend on report, view or cli.
// docs/propose.md is the reference.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "script/sandbox/lua_sandbox.h"

namespace roger {

// What to propose for and how hard to search.
struct ProposeOptions {
  std::string curriculum;      // script path or bare name ("paper")
  std::string stage;           // the task stage ("T")
  std::string context;         // the starting Psi: a context of the stage ("" = its first)
  double budget_s = 0.0;       // simulated seconds of training the whole search may spend (> 0)
  std::string out;             // the folder of candidates, trial records, proposal.lua, propose.md
  uint64_t seed = 1;
  double probe_share = 0.2;    // share of the budget for the probe of the starting context
  int probe_trials = 2;        // probe trials (seeds)
  int trials = 2;              // trials (seeds) per candidate and round of successive halving
  int max_candidates = 8;      // candidates evaluated (the rest are listed, not run)
  double prune_below = 0.05;   // prune an action running under this share of successful time
  SandboxLimits limits;
  std::ostream* progress = nullptr;  // one line per trial (nullptr = none)
};

// One evaluated (or reused) training run of a candidate.
struct CandidateTrial {
  uint64_t seed = 0;
  double cap_s = 0.0;        // the simulated seconds it was allowed (its round's cap, or less: the budget's rest)
  double score_cap_s = 0.0;  // its round's cap, which a trial that did not reach the threshold scores on
  double spent_s = 0.0;      // what it spent: its skills' training, then its final stage
  double skills_s = 0.0;     // of which the learned subgoal stages
  bool reached = false;      // the final stage reached its threshold within the cap
  double time_s = 0.0;       // skills_s + the final stage's time-to-threshold (when reached)
  double last_success = 0.0; // the final stage's last checkpoint's success rate
  double loss = 0.0;         // time_s when reached, else score_cap_s * (2 - last_success)
  bool reused = false;       // read back from the trial record of an earlier run
  int round = 0;             // the round of successive halving it belongs to (1-based)
  int index = 0;             // its place among the candidate's trials of that round (1-based)
  int checkpoints = -1;      // greedy checkpoints the final stage ran (-1: a record from before they were kept)
  // The learned skill whose subgoal stage the cap ended before its stop rule did, leaving the task
  // no training: the trial then scored 2 x cap with its task untested, which must be said ("" = none).
  std::string cut;
  bool cut_reached = false;  // ...that stage had reached its threshold (not yet its stop rule)
};

// A candidate curriculum.
struct Candidate {
  std::string id;            // "C1"
  std::string kind;          // "base", "pruned", "macro", "subgoal", "chain"
  std::string summary;       // one line: what its Psi is
  std::string why;           // where it comes from in the probe
  std::string file;          // its curriculum file in out/candidates/
  std::vector<std::string> psi;  // the final stage's actions, by name
  bool evaluated = false;    // false: generated but over max_candidates
  int eliminated_round = -1; // the round successive halving dropped it in (-1 = survived)
  std::vector<CandidateTrial> trials;  // every round's
  double score = 0.0;        // mean loss of its trials in its last round (lower is better)
};

// What one proposal search did.
struct ProposeResult;
// "2 rounds", or, when the budget ran out before the planned ones, "0 of 1 rounds" (found by a probe:
// "in 0 rounds" beside a caution naming "the 1 round").
std::string rounds_said(const ProposeResult& r);

struct ProposeResult {
  std::vector<Candidate> candidates;
  int winner = -1;               // index into candidates
  double budget_s = 0.0;
  double probe_s = 0.0;          // simulated seconds the probe trained
  double spent_s = 0.0;          // the whole search, the probe included
  int successful_episodes = 0;   // in the probe
  int probe_episodes = 0;        // training episodes of the probe
  int rounds = 0;
  int planned_rounds = 0;  // the rounds successive halving planned (more than `rounds` when the budget ran out)
  int trials_run = 0, trials_reused = 0;
  // Records in out/probe/ and out/trials/ that could not be read (a disk fault or an edit): their
  // trials ran again, as roger run runs a trial with unreadable files again. Counted in trials_run.
  std::vector<std::string> unreadable;
  // Records of other sources (the curriculum, its scenario or the engine changed since) or of
  // another cap: their trials ran again. Counted in trials_run.
  int stale_records = 0;
  // What makes the ranking less than it seems: a round whose trials ran no checkpoint (every loss
  // the same), a cut that fell in a tie (the candidates' order decided). One sentence each.
  std::vector<std::string> cautions;
  std::string proposal_file;     // out/proposal.lua
  std::string report_file;       // out/propose.md
};

// Runs the search (resuming from the trial records already in options.out) and writes
// candidates/*.lua, trials/*.json, proposal.lua and propose.md into options.out. Throws
// roger::Error for bad options (naming the option) and ScriptError for a bad curriculum.
ProposeResult propose_curriculum(const ProposeOptions& options);

}  // namespace roger
