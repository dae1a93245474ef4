// propose_internal.h: what the files of engine/propose share (the probe's statistics, candidate
// generation, the Lua text of a candidate, the report). Private to engine/propose/.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "propose/propose.h"

namespace roger::propose_detail {

// One successful probe episode, as much of it as the proposal reads.
struct ProbeEpisode {
  std::vector<int> ticks;       // per action of Psi: control ticks it ran
  std::vector<int> first_conv;  // per action: first decision whose state has it CONV (-1: never)
  std::vector<int> path;        // the action chosen at each decision
};

// What the probe of the starting context saw.
struct ProbeStats {
  std::vector<std::string> psi;           // the starting context's actions
  int episodes = 0;                       // training episodes of the probe
  double sim_s = 0.0;                     // simulated seconds they lasted
  std::vector<ProbeEpisode> successes;    // the successful ones
};

// A controller of Psi that the successful episodes pass through converged.
struct Subgoal {
  int action = -1;        // index into Psi
  double share = 0.0;     // share of successful episodes reaching its CONV after the first decision
  double order = 0.0;     // median decision index of that first CONV (the subgoals' order)
  int achiever = -1;      // the action most often running just before that first CONV
};

// The successful episodes' statistics.
struct ProbeSummary {
  std::vector<double> tick_share;  // per action: share of the successful episodes' ticks it ran
  std::vector<Subgoal> subgoals;   // in the order the episodes reach them
  int final_achiever = -1;         // the action most often running when the task's goal is reached
};

// The probe: trains the starting context for options.probe_trials seeds, each capped at cap_s
// simulated seconds, reusing the probe records already in out/probe/.
// `sources` fingerprints the Lua the task is read from: a record of other sources is run again.
ProbeStats run_probe(const ProposeOptions& options, const std::string& context, const std::string& sources,
                     double cap_s, int* reused, std::vector<std::string>* unreadable, int* stale);

// A record that exists but cannot be read (`why`): said on options.progress and added to
// `unreadable`, so that a trial run again over it is not mistaken for one never run.
void note_unreadable(const ProposeOptions& options, const std::string& file, const std::string& why,
                     std::vector<std::string>* unreadable);

// The statistics of the successful episodes (a subgoal is reached in at least half of them).
ProbeSummary summarize_probe(const ProbeStats& probe);

// How a candidate's Lua file finds the task: the module to require and the stage and context.
struct TaskRef {
  std::string module;        // require name of the original curriculum ("paper")
  std::string stage, context;
  std::string scenario;      // the task's scenario from the project when a path ("" for a bare name)
  bool context_params = false;  // the starting context sets scenario parameters (its body, senses)
  std::string command;       // the roger propose command line, for the file's header
  std::string sources;       // text_hash of every Lua file the task and the proposals read
  int checkpoint_every = 0;  // training episodes between the stage's checkpoints
  int stop_after = 0;        // the stage's stop_after (0: it trains to the end of its budget)
  double time_limit = 0.0;   // the stage's time-out (s) in a world of its scenario
};

// A candidate and the text of its curriculum file.
struct CandidateSpec {
  Candidate c;
  std::string lua;
};

// Every candidate the probe suggests, in priority order (the base first).
std::vector<CandidateSpec> generate_candidates(const TaskRef& task, const ProbeStats& probe,
                                               const ProbeSummary& summary, double prune_below);

// What a trial's CandidateTrial::cut means, "the cap ended Phi_to_phi1's stage short of its
// threshold" ("" when nothing was cut): for the console, the trial table and the cautions.
std::string cut_text(const CandidateTrial& t);

// The names of a search's records: trials/C2-r1-t2.json (candidate, round and trial from 1),
// probe/probe-1.json (k from 0).
inline std::string trial_file_name(const std::string& candidate, int round, int trial) {
  return candidate + "-r" + std::to_string(round) + "-t" + std::to_string(trial) + ".json";
}
inline std::string probe_file_name(int k) { return "probe-" + std::to_string(k + 1) + ".json"; }

// Writes propose.md.
void write_propose_report(const ProposeOptions& options, const TaskRef& task, const ProbeStats& probe,
                          const ProbeSummary& summary, const ProposeResult& result);

}  // namespace roger::propose_detail
