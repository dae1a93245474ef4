// warm_start.cpp: see warm_start.h. The mapping goes through the policy-file format, the one way
// in that sets visits as well as values.
#include "learn/warm_start.h"

#include <algorithm>

#include <nlohmann/json.hpp>

#include "core/error.h"

namespace roger {
namespace {

// The base-3 digits of a state, the first action the most significant (gamma_state_index).
std::vector<int> digits(int s, int n) {
  std::vector<int> d(static_cast<size_t>(n));
  for (int i = n - 1; i >= 0; --i, s /= 3) d[size_t(i)] = s % 3;
  return d;
}

std::string join_names(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

}  // namespace

QTable warm_start_table(const std::vector<std::string>& actions, const QParams& params, const QTable& earlier,
                        const std::string& source, WarmStart* info) {
  const QTable fresh(actions, params);  // checks the names and the parameters
  WarmStart w;
  w.source = source;
  std::vector<int> from(actions.size(), -1);  // new action -> earlier action, -1 when new
  const auto& old_names = earlier.action_names();
  for (size_t a = 0; a < actions.size(); ++a) {
    const auto it = std::find(old_names.begin(), old_names.end(), actions[a]);
    if (it == old_names.end()) w.fresh.push_back(actions[a]);
    else from[a] = int(it - old_names.begin()), w.shared.push_back(actions[a]);
  }
  for (const auto& n : old_names)
    if (std::find(actions.begin(), actions.end(), n) == actions.end()) w.dropped.push_back(n);
  if (w.shared.empty())
    throw Error(source + ": its table shares no action with this context's (its actions: " + join_names(old_names) +
                "; this context's: " + join_names(actions) + "), so nothing of it could be carried over");

  // Sums over the earlier states, keyed by the new state's shared digits: earlier state s' adds to
  // every new state that agrees with it on the shared actions.
  const int n_new = fresh.actions(), n_old = earlier.actions();
  std::vector<int> place(size_t(n_old), -1);  // earlier action -> its digit position in the new state
  for (int a = 0; a < n_new; ++a)
    if (from[size_t(a)] >= 0) place[size_t(from[size_t(a)])] = a;
  // The shared part of a new state as an index over the shared actions alone (base 3).
  auto shared_key = [&](const std::vector<int>& d_new) {
    int k = 0;
    for (int a = 0; a < n_new; ++a)
      if (from[size_t(a)] >= 0) k = k * 3 + d_new[size_t(a)];
    return k;
  };
  int keys = 1;
  for (size_t i = 0; i < w.shared.size(); ++i) keys *= 3;
  // Per key and shared action (in new order): sum of Q * visits, of visits, of Q, and the count.
  struct Sum { double qv = 0, v = 0, q = 0; int n = 0; };
  std::vector<Sum> sums(size_t(keys) * w.shared.size());
  for (int s = 0; s < earlier.states(); ++s) {
    const std::vector<int> d_old = digits(s, n_old);
    std::vector<int> d_new(size_t(n_new), 0);
    for (int o = 0; o < n_old; ++o)
      if (place[size_t(o)] >= 0) d_new[size_t(place[size_t(o)])] = d_old[size_t(o)];
    const int k = shared_key(d_new);
    int j = 0;
    for (int a = 0; a < n_new; ++a) {
      if (from[size_t(a)] < 0) continue;
      Sum& sum = sums[size_t(k) * w.shared.size() + size_t(j++)];
      const double q = earlier.value(s, from[size_t(a)]);
      const double v = double(earlier.visits(s, from[size_t(a)]));
      sum.qv += q * v, sum.v += v, sum.q += q, ++sum.n;
    }
  }

  nlohmann::json j = fresh.to_json();
  for (int s = 0; s < fresh.states(); ++s) {
    const int k = shared_key(digits(s, n_new));
    bool any = false;
    int i = 0;
    for (int a = 0; a < n_new; ++a) {
      if (from[size_t(a)] < 0) continue;
      const Sum& sum = sums[size_t(k) * w.shared.size() + size_t(i++)];
      j["q"][size_t(s)][size_t(a)] = sum.v > 0 ? sum.qv / sum.v : sum.q / sum.n;
      j["visits"][size_t(s)][size_t(a)] = uint64_t(sum.v);
      any = any || sum.v > 0;
    }
    w.states_with_values += any;
  }
  if (info) *info = w;
  return QTable::from_json(j, actions, source);
}

}  // namespace roger
