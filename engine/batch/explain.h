// explain.h: why a training trial did not reach its threshold, told from its own data: the final
// greedy episodes (a cycle of states and actions that repeats until the time-out, a state the
// chosen action never leaves), the decisions of training (actions never tried, never able to run),
// how often episodes time out, and checkpoints that passed and then failed. `roger train` prints
// it, result.json holds it ("diagnosis"), the report lists it (docs/curricula.md, Why a training
// failed).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/trainer.h"
#include "learn/decision_cycle.h"

namespace roger {

// What the data of a trial says.
struct TrainingDiagnosis {
  std::vector<std::string> psi;       // the actions' names, in state-vector order
  // The final greedy evaluation: its episodes, those that timed out, the cycle most of them ended
  // in (turns: the most in one episode) and in how many.
  int final_episodes = 0, final_timeouts = 0;
  DecisionCycle cycle;
  int cycle_episodes = 0;
  // Every cycle a timed-out episode ended in, the most frequent first (cycles[0] is `cycle`): with
  // many actions (sorting), the episodes a policy fails end in several.
  struct CycleCount {
    DecisionCycle cycle;
    int episodes = 0;
  };
  std::vector<CycleCount> cycles;
  // A state whose chosen action ran until the time-out (no cycle), and in how many episodes.
  struct Stuck {
    int state = 0, action = 0, episodes = 0;
  };
  std::vector<Stuck> stuck;           // most frequent first
  std::vector<int> never_chosen;      // actions the final greedy policy never chose
  std::vector<int> never_tried;       // actions never chosen in training, exploration included
  std::vector<int> never_referenced;  // NOREF at every decision state met (training and final)
  // Episodes (training and final) that ended in the absorbing state before their first decision:
  // the goal held in their worlds from the start.
  int ended_before_deciding = 0, episodes_seen = 0;
  int train_episodes = 0, train_timeouts = 0;
  bool absorbing_lua = false;  // the absorbing state is a Lua function's
  int last_quarter_episodes = 0, last_quarter_timeouts = 0;
  // A checkpoint that passed followed by one that failed (1-based, as in checkpoints.jsonl).
  struct Drop {
    int passed = 0, failed = 0, failed_at_episodes = 0;
    double passed_rate = 0, failed_rate = 0;
    bool policy_changed = false;
  };
  std::vector<Drop> drops;

  // "go0=CONV go1=!CONV nowhere=NOREF": the gammas of a state, by action name.
  std::string state_text(int state) const;
  // One sentence per cause found, the most telling first (empty when nothing stands out).
  std::vector<std::string> causes() const;
  // The sentence said for the time-outs when no episode, training or final, reached the absorbing
  // state ("" when one did).
  std::string never_reached_cause() const;
  // The sentence said when some episodes ended in the absorbing state before deciding ("" when
  // none did): they teach nothing and count as successes (found by a probe: a stage whose goal
  // held at the first tick "reached 90% after 3 episodes, 0 decisions").
  std::string goal_at_start_cause() const;
  // The sentence of the greedy cycle (when cycle.turns > 0), and those of the actions.
  std::string cycle_cause() const;
  // The sentences of the other cycles: the next two in full, then how many episodes the rest hold.
  std::vector<std::string> other_cycle_causes() const;
  std::vector<std::string> action_causes() const;
  // The diagnosis for result.json and summary.json (its "causes" are causes()).
  nlohmann::json to_json() const;
};

// Reads the diagnosis out of a trial's result: its final evaluation's episodes (kept by
// train_stage), its training episodes (when kept) and its checkpoints.
TrainingDiagnosis diagnose_training(const TrainResult& result);

}  // namespace roger
