// learning_internal.h: what the learn module's files share and nobody else needs.
#pragma once

#include <climits>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "learn/learning.h"

namespace roger::learning_detail {

constexpr const char* kFormat = "roger-policy";
constexpr int kVersion = 1;
// The most states a policy file writes every row of (3^6: six actions); a larger table writes only
// the rows that hold something, keyed by state (QTable::to_json).
constexpr int kDenseStates = 729;
constexpr int kMaxActions = 12;  // 3^12 = 531441 states: the same bound as Policy

inline bool finite(double v) { return std::isfinite(v); }

// "[a, b, c]" for messages.
std::string list_names(const std::vector<std::string>& names);

// The state (gamma vector) nearest to s among the visited ones: the least sum over actions of
// |gamma_i - gamma'_i| (NOREF = 0 < !CONV = 1 < CONV = 2), ties to the lowest index; -1 if none.
// gamma_state_index puts the first action in the most significant base-3 digit; the distance
// does not depend on the order, so digits are compared from the least significant one.
template <typename Visited>
inline int nearest_visited_state(int s, int states, int actions, const Visited& visited) {
  int best = -1, best_distance = INT_MAX;
  for (int t = 0; t < states; ++t) {
    if (!visited(t)) continue;
    int distance = 0, a = s, b = t;
    for (int i = 0; i < actions; ++i, a /= 3, b /= 3) distance += std::abs(a % 3 - b % 3);
    if (distance < best_distance) best_distance = distance, best = t;
  }
  return best;
}

// Checks that psi is the table's action set, in order; throws roger::Error naming `where`.
void check_psi(const std::vector<ControllerPtr>& psi, const QTable& q, const std::string& where);

}  // namespace roger::learning_detail
