// explain.cpp: see explain.h.
#include "batch/explain.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "control/control.h"

namespace roger {

namespace {

// The gamma of action a in state s of n actions (the first action is the most significant base-3
// digit, as gamma_state_index makes it).
Gamma gamma_in(int s, int a, int n) {
  for (int k = n - 1; k > a; --k) s /= 3;
  return Gamma(s % 3);
}

// A share as a whole percentage: "40%".
std::string percent(double fraction) { return std::to_string(int(std::lround(100.0 * fraction))) + "%"; }
std::string percent(int part, int whole) { return percent(whole ? double(part) / whole : 0.0); }

// The names of some actions, comma-separated.
std::string names(const std::vector<int>& actions, const std::vector<std::string>& psi) {
  std::string out;
  for (int a : actions) out += (out.empty() ? "" : ", ") + psi[size_t(a)];
  return out;
}

}  // namespace

std::string TrainingDiagnosis::state_text(int state) const {
  std::string out;
  for (size_t a = 0; a < psi.size(); ++a)
    out += (a ? " " : "") + psi[a] + "=" + gamma_name(gamma_in(state, int(a), int(psi.size())));
  return out;
}

namespace {

// "greedy cycle: (...) -> a -> back, repeating ... in k of n final greedy episodes (up to t turns)".
// A cycle of more than six decisions is shown by its first four and its last, with how many lie
// between (a line of sixty states could not be read; the diagnosis's "cycles" keeps them all).
std::string cycle_text(const TrainingDiagnosis& d, const std::string& lead, const DecisionCycle& c, int episodes) {
  constexpr size_t kInFull = 6, kHead = 4;
  const size_t n = c.states.size();
  std::string text = lead + (n > kInFull ? " of " + std::to_string(n) + " decisions:" : ":");
  for (size_t k = 0; k < n; ++k) {
    if (n > kInFull && k == kHead) {
      text += " ... " + std::to_string(n - kHead - 1) + " more decisions ... ->";
      k = n - 1;
    }
    text += " (" + d.state_text(c.states[k]) + ") -> " + d.psi[size_t(c.actions[k])] + " ->";
  }
  return text + " back, repeating without reaching the absorbing state in " + std::to_string(episodes) + " of " +
         std::to_string(d.final_episodes) + " final greedy episodes (up to " + std::to_string(c.turns) + " turns)";
}

}  // namespace

std::string TrainingDiagnosis::cycle_cause() const { return cycle_text(*this, "greedy cycle", cycle, cycle_episodes); }

std::vector<std::string> TrainingDiagnosis::other_cycle_causes() const {
  constexpr size_t kInFull = 2;  // other cycles told in full; the rest are counted
  std::vector<std::string> out;
  int rest_episodes = 0, rest_cycles = 0;
  for (size_t k = 1; k < cycles.size(); ++k) {
    if (k <= kInFull) {
      out.push_back(cycle_text(*this, "another greedy cycle", cycles[k].cycle, cycles[k].episodes));
    } else {
      rest_episodes += cycles[k].episodes;
      ++rest_cycles;
    }
  }
  if (rest_cycles > 0)
    out.push_back(std::to_string(rest_episodes) + " more of the final greedy episodes ended in " +
                  std::to_string(rest_cycles) + " other greedy cycle" + (rest_cycles > 1 ? "s" : ""));
  return out;
}

std::vector<std::string> TrainingDiagnosis::action_causes() const {
  std::vector<std::string> out;
  if (!never_referenced.empty())
    out.push_back("never able to run: " + names(never_referenced, psi) + " (NOREF at every decision)");
  if (!never_tried.empty()) out.push_back("never chosen in training: " + names(never_tried, psi));
  // Those never tried are said above; the greedy policy's own omissions are the others.
  std::vector<int> unused_greedy;
  for (int a : never_chosen)
    if (std::find(never_tried.begin(), never_tried.end(), a) == never_tried.end()) unused_greedy.push_back(a);
  if (!unused_greedy.empty()) out.push_back("never chosen by the final greedy policy: " + names(unused_greedy, psi));
  return out;
}

// Found by a probe: a Lua absorbing function comparing a region name written otherwise than the
// world's never held; the causes named cycles and time-outs, and the learner was blamed.
std::string TrainingDiagnosis::never_reached_cause() const {
  if (train_episodes == 0 || train_timeouts < train_episodes || final_timeouts < final_episodes) return "";
  const std::string episodes = "the " + std::to_string(train_episodes) + " training episodes" +
                               (final_episodes ? " and the " + std::to_string(final_episodes) + " final ones"
                                               : std::string());
  return "absorbing state never reached: " +
         (absorbing_lua ? "the stage's Lua absorbing function returned true in none of " + episodes +
                              " (what it compares, such as a name or a region written otherwise than the world's, "
                              "may never match)"
                        : "every one of " + episodes + " timed out, so no reward from it was ever learned");
}

std::string TrainingDiagnosis::goal_at_start_cause() const {
  if (ended_before_deciding == 0) return "";
  return std::to_string(ended_before_deciding) + " of " + std::to_string(episodes_seen) +
         " episodes (training and final) ended in the absorbing state at their start (before their first "
         "decision, or at the first tick, when the goal is first judged): the goal held in their worlds from the "
         "start, so they teach nothing and count as successes (check the stage's absorbing state, or the goal, "
         "against its worlds)";
}

std::vector<std::string> TrainingDiagnosis::causes() const {
  std::vector<std::string> out;
  if (const std::string at_start = goal_at_start_cause(); !at_start.empty()) out.push_back(at_start);
  if (cycle.turns > 0) out.push_back(cycle_cause());
  for (std::string& c : other_cycle_causes()) out.push_back(std::move(c));
  for (const Stuck& st : stuck)
    out.push_back("state never left: (" + state_text(st.state) + "), where " + psi[size_t(st.action)] +
                  " ran until the time-out in " + std::to_string(st.episodes) + " of " +
                  std::to_string(final_episodes) + " final greedy episodes");
  for (std::string& c : action_causes()) out.push_back(std::move(c));
  // Every episode timed out: said as the absorbing state never reached, which is what it means.
  if (const std::string never = never_reached_cause(); !never.empty()) out.push_back(never);
  else if (train_timeouts > 0 || final_timeouts > 0)
    out.push_back("time-outs: " + percent(train_timeouts, train_episodes) + " of the training episodes (" +
                  percent(last_quarter_timeouts, last_quarter_episodes) + " of the last quarter), " +
                  percent(final_timeouts, final_episodes) + " of the final evaluation");
  for (const Drop& d : drops)
    out.push_back("checkpoint " + std::to_string(d.passed) + " passed (" + percent(d.passed_rate) +
                  ") and checkpoint " + std::to_string(d.failed) + " failed (" + percent(d.failed_rate) + ", after " +
                  std::to_string(d.failed_at_episodes) + " episodes" +
                  (d.policy_changed ? ": the greedy policy changed" : "") + ")");
  return out;
}

nlohmann::json TrainingDiagnosis::to_json() const {
  using json = nlohmann::json;
  const auto action_names = [&](const std::vector<int>& v) {
    json out = json::array();
    for (int a : v) out.push_back(psi[size_t(a)]);
    return out;
  };
  json j = {{"causes", causes()},
            {"never_chosen", action_names(never_chosen)},
            {"never_tried", action_names(never_tried)},
            {"never_referenced", action_names(never_referenced)},
            {"ended_before_deciding", ended_before_deciding},
            {"timeouts", {{"training", train_episodes ? double(train_timeouts) / train_episodes : 0.0},
                          {"training_last_quarter",
                           last_quarter_episodes ? double(last_quarter_timeouts) / last_quarter_episodes : 0.0},
                          {"final", final_episodes ? double(final_timeouts) / final_episodes : 0.0}}}};
  const auto cycle_json = [&](const DecisionCycle& c, int episodes) {
    json states = json::array();
    for (int s : c.states) states.push_back(state_text(s));
    return json{{"states", states}, {"actions", action_names(c.actions)}, {"episodes", episodes}, {"turns", c.turns}};
  };
  if (cycle.turns > 0) j["cycle"] = cycle_json(cycle, cycle_episodes);
  json cycle_list = json::array();
  for (const CycleCount& c : cycles) cycle_list.push_back(cycle_json(c.cycle, c.episodes));
  j["cycles"] = cycle_list;
  json stuck_list = json::array();
  for (const Stuck& st : stuck)
    stuck_list.push_back({{"state", state_text(st.state)}, {"action", psi[size_t(st.action)]}, {"episodes", st.episodes}});
  j["stuck"] = stuck_list;
  json drop_list = json::array();
  for (const Drop& d : drops)
    drop_list.push_back({{"passed", d.passed}, {"failed", d.failed}, {"passed_rate", d.passed_rate},
                         {"failed_rate", d.failed_rate}, {"failed_at_episodes", d.failed_at_episodes},
                         {"policy_changed", d.policy_changed}});
  j["checkpoint_drops"] = drop_list;
  return j;
}

namespace {

// The final greedy episodes that timed out: the cycle most of them end in, and the states the
// others never left.
void read_final_episodes(const std::vector<TrainingEpisode>& episodes, TrainingDiagnosis& d) {
  std::map<std::pair<std::vector<int>, std::vector<int>>, std::pair<int, int>> cycles;  // -> episodes, turns
  std::map<std::pair<int, int>, int> stuck;
  for (const TrainingEpisode& ep : episodes) {
    ++d.final_episodes;
    if (ep.success) continue;
    ++d.final_timeouts;
    const DecisionCycle c = find_decision_cycle(ep.decision_states, ep.actions_taken);
    if (c.turns > 0) {
      auto& [count, turns] = cycles[{c.states, c.actions}];
      ++count;
      turns = std::max(turns, c.turns);
    } else if (!ep.decision_states.empty()) {
      ++stuck[{ep.decision_states.back(), ep.actions_taken.back()}];
    }
  }
  for (const auto& [key, value] : cycles)
    d.cycles.push_back({DecisionCycle{key.first, key.second, value.second, 0}, value.first});
  // The most frequent first; among as frequent, the map's order (the first found before).
  std::stable_sort(d.cycles.begin(), d.cycles.end(),
                   [](const auto& x, const auto& y) { return x.episodes > y.episodes; });
  if (!d.cycles.empty()) {
    d.cycle = d.cycles.front().cycle;
    d.cycle_episodes = d.cycles.front().episodes;
  }
  for (const auto& [key, count] : stuck) d.stuck.push_back({key.first, key.second, count});
  std::stable_sort(d.stuck.begin(), d.stuck.end(),
                   [](const auto& x, const auto& y) { return x.episodes > y.episodes; });
}

// Which actions training chose, and which ever had a reference at a decision.
void read_decisions(const TrainResult& r, TrainingDiagnosis& d) {
  const int n = int(r.psi.size());
  std::vector<bool> tried(size_t(n), false), chosen(size_t(n), false), referenced(size_t(n), false);
  bool any_decision = false;
  const auto note_states = [&](const TrainingEpisode& ep) {
    ++d.episodes_seen;
    // Before the first decision (a Lua absorbing function asked at the start), or at the first tick,
    // when a predicate is first judged (found by a probe: not(converged(phi3)), phi3 never run,
    // trained to 100% in one tick an episode without a word, where roger eval warned).
    d.ended_before_deciding += ep.success && (ep.decision_states.empty() || ep.ticks == 1);
    any_decision = any_decision || !ep.decision_states.empty();
    for (int s : ep.decision_states)
      for (int a = 0; a < n; ++a) referenced[size_t(a)] = referenced[size_t(a)] || gamma_in(s, a, n) != Gamma::kNoRef;
  };
  const int quarter_from = int(r.episodes.size()) - int(r.episodes.size()) / 4;
  for (const EpisodeRecord& e : r.episodes) {
    for (int a : e.episode.actions_taken) tried[size_t(a)] = true;
    note_states(e.episode);
    ++d.train_episodes;
    d.train_timeouts += !e.episode.success;
    if (int(&e - r.episodes.data()) >= quarter_from) {
      ++d.last_quarter_episodes;
      d.last_quarter_timeouts += !e.episode.success;
    }
  }
  for (const TrainingEpisode& ep : r.final_eval.runs) {
    for (int a : ep.actions_taken) chosen[size_t(a)] = true;
    note_states(ep);
  }
  // Without a decision, no action was ever seen NOREF (found by a probe: "never able to run" of a
  // stage whose every episode ended before its first).
  for (int a = 0; a < n; ++a) {
    if (!r.episodes.empty() && !tried[size_t(a)]) d.never_tried.push_back(a);
    if (!r.final_eval.runs.empty() && !chosen[size_t(a)]) d.never_chosen.push_back(a);
    if (any_decision && !referenced[size_t(a)]) d.never_referenced.push_back(a);
  }
}

}  // namespace

TrainingDiagnosis diagnose_training(const TrainResult& r) {
  TrainingDiagnosis d;
  d.psi = r.psi;
  d.absorbing_lua = r.absorbing_lua;
  read_final_episodes(r.final_eval.runs, d);
  read_decisions(r, d);
  for (size_t k = 1; k < r.checkpoints.size(); ++k) {
    const CheckpointRecord &before = r.checkpoints[k - 1], &now = r.checkpoints[k];
    if (before.success_rate >= r.threshold && now.success_rate < r.threshold)
      d.drops.push_back({int(k), int(k) + 1, now.at.episodes, before.success_rate, now.success_rate, now.policy_changed});
  }
  return d;
}

}  // namespace roger
