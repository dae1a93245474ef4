// decision_cycle.h: a cycle of decisions, found in a recorded episode: the same states and actions
// over and over up to the episode's end, never reaching the absorbing state. A greedy policy in
// such a cycle is livelocked; `roger train` names it (batch/explain.h) and the episode viewer
// marks it on its timeline.
#pragma once

#include <vector>

namespace roger {

// One turn of a cycle and how often it repeated.
struct DecisionCycle {
  std::vector<int> states;   // one turn: the decision states, in order (any ids the caller uses)
  std::vector<int> actions;  // the action chosen at each
  int turns = 0;             // whole turns in a row up to the last decision; 0: no cycle
  int first = 0;             // the index of the first decision of the first of those turns
};

// The cycle that ends a sequence of decisions (states[k], actions[k]): the shortest turn that
// repeats at least twice in a row up to the last decision, rotated to start at its least
// (state, action), so the same cycle entered at another point of its turn compares equal.
DecisionCycle find_decision_cycle(const std::vector<int>& states, const std::vector<int>& actions);

}  // namespace roger
