// decision_cycle.cpp: see decision_cycle.h.
#include "learn/decision_cycle.h"

#include <algorithm>
#include <utility>

namespace roger {

namespace {

// Whether the last `turns` turns of `period` decisions are all the same.
bool repeats(const std::vector<int>& s, const std::vector<int>& a, size_t n, size_t period, size_t turns) {
  if (period * turns > n) return false;
  for (size_t i = 0; i < period * (turns - 1); ++i) {
    const size_t k = n - 1 - i;
    if (s[k] != s[k - period] || a[k] != a[k - period]) return false;
  }
  return true;
}

}  // namespace

DecisionCycle find_decision_cycle(const std::vector<int>& states, const std::vector<int>& actions) {
  DecisionCycle c;
  const size_t n = std::min(states.size(), actions.size());
  for (size_t period = 1; 2 * period <= n; ++period) {
    if (!repeats(states, actions, n, period, 2)) continue;
    size_t turns = 2;
    while (repeats(states, actions, n, period, turns + 1)) ++turns;
    std::vector<std::pair<int, int>> turn;
    for (size_t k = n - period; k < n; ++k) turn.emplace_back(states[k], actions[k]);
    std::rotate(turn.begin(), std::min_element(turn.begin(), turn.end()), turn.end());
    for (const auto& [state, action] : turn) {
      c.states.push_back(state);
      c.actions.push_back(action);
    }
    c.turns = int(turns);
    c.first = int(n - period * turns);
    return c;
  }
  return c;
}

}  // namespace roger
