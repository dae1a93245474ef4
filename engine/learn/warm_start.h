// warm_start.h: a Q-table that starts from one learned earlier (roger train --init), over the
// states and actions the two share by name, so that training can go on from where an earlier run
// (of this context or of another one with some of its actions) left off.
#pragma once

#include <string>
#include <vector>

#include "learn/learning.h"

namespace roger {

// What a warm start took from the earlier table.
struct WarmStart {
  std::string source;                  // the file (or trial) it came from, as given
  std::vector<std::string> shared;     // the actions both tables have, in the new table's order
  std::vector<std::string> fresh;      // the new table's actions the earlier one lacks: initial_q
  std::vector<std::string> dropped;    // the earlier table's actions the new one lacks
  int states_with_values = 0;          // new states whose shared entries came from visited states
};

// A table over `actions` (with `params`) whose entries for the actions it shares with `earlier`
// (by name) come from `earlier`: Q(s, a) is the visit-weighted mean of earlier's Q(s', a) over
// the earlier states s' whose shared actions' gammas are those of s (exactly one state when every
// earlier action is shared; the plain mean when none was visited), and the visits their sum; an
// action earlier lacks starts at params.initial_q, unvisited. Throws roger::Error naming `source`
// when no action is shared (nothing could be carried over).
QTable warm_start_table(const std::vector<std::string>& actions, const QParams& params, const QTable& earlier,
                        const std::string& source, WarmStart* info = nullptr);

}  // namespace roger
