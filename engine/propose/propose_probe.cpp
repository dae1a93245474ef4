// propose_probe.cpp: the probe of the starting context and what its successful episodes say.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <ostream>

#include "batch/trainer.h"
#include "core/json_input.h"
#include "core/error.h"
#include "core/fileio.h"
#include "core/rng.h"
#include "core/text.h"
#include "propose/propose_internal.h"

namespace roger::propose_detail {
namespace fs = std::filesystem;

void note_unreadable(const ProposeOptions& o, const std::string& file, const std::string& why,
                     std::vector<std::string>* unreadable) {
  if (o.progress) *o.progress << "roger propose: " << file << " cannot be read (" << why << "): its trial runs again\n";
  unreadable->push_back(file);
}

namespace {

// The gamma digit of action i in state s over n actions (gamma_state_index puts the first action
// in the most significant base-3 digit).
int gamma_digit(int s, int i, int n) {
  for (int k = n - 1; k > i; --k) s /= 3;
  return s % 3;
}

ProbeEpisode probe_episode(const TrainingEpisode& ep, int n) {
  ProbeEpisode p;
  p.ticks = ep.action_ticks;
  p.path = ep.actions_taken;
  p.first_conv.assign(size_t(n), -1);
  for (size_t d = 0; d < ep.decision_states.size(); ++d)
    for (int i = 0; i < n; ++i)
      if (p.first_conv[size_t(i)] < 0 && gamma_digit(ep.decision_states[d], i, n) == 2) p.first_conv[size_t(i)] = int(d);
  return p;
}

nlohmann::json probe_json(const TrainResult& r, const std::vector<ProbeEpisode>& successes, double cap_s,
                          const std::string& key) {
  nlohmann::json eps = nlohmann::json::array();
  for (const auto& e : successes) eps.push_back({{"ticks", e.ticks}, {"first_conv", e.first_conv}, {"path", e.path}});
  return {{"format", "roger-propose-probe"}, {"key", key}, {"cap_s", cap_s}, {"psi", r.psi},
          {"episodes", r.totals.episodes}, {"sim_s", r.totals.sim_s}, {"successes", eps}};
}

// Whether a probe record holds what run_probe reads, each of the right type and range: one that
// does not (damaged, or edited by hand) is run again, as an unreadable one is, rather than read
// as whatever its damage says.
bool sound_probe_record(const nlohmann::json& j) {
  auto count = [](const nlohmann::json& v) { return v.is_number_integer() && v.get<int64_t>() >= 0 && v.get<int64_t>() <= (int64_t(1) << 31) - 1; };
  auto seconds = [](const nlohmann::json& v) { return v.is_number() && std::isfinite(v.get<double>()) && v.get<double>() >= 0; };
  auto ints = [](const nlohmann::json& v, size_t n, int lo, int hi) {
    if (!v.is_array() || (n && v.size() != n)) return false;
    for (const auto& x : v)
      if (!x.is_number_integer() || x.get<int64_t>() < lo || x.get<int64_t>() > hi) return false;
    return true;
  };
  if (!j.is_object() || !j.contains("psi") || !j["psi"].is_array() || j["psi"].empty()) return false;
  for (const auto& a : j["psi"])
    if (!a.is_string()) return false;
  const size_t n = j["psi"].size();
  if (!count(j.value("episodes", nlohmann::json())) || !seconds(j.value("sim_s", nlohmann::json()))) return false;
  if (!j.contains("successes") || !j["successes"].is_array()) return false;
  for (const auto& e : j["successes"])
    if (!e.is_object() || !ints(e.value("ticks", nlohmann::json()), n, 0, INT32_MAX) ||
        !ints(e.value("first_conv", nlohmann::json()), n, -1, INT32_MAX) ||
        !ints(e.value("path", nlohmann::json()), 0, 0, int(n) - 1))
      return false;
  return true;
}

// One probe trial, from its record when an earlier run wrote it.
nlohmann::json probe_trial(const ProposeOptions& o, const std::string& context, const std::string& sources,
                           uint64_t seed, double cap_s, const std::string& file, bool* reused,
                           std::vector<std::string>* unreadable, int* stale) {
  const std::string key = o.stage + "/" + context + "/" + std::to_string(seed) + "/" + sources;
  if (fs::exists(file)) {
    // An unreadable record (a disk fault: records are written atomically) is run again, and said;
    // one of other sources or another cap (a curriculum edited since) is run again, and counted.
    std::string why;
    try {
      nlohmann::json j = parse_json(read_file_text(file));
      const bool same = j.value("key", "") == key && j.value("cap_s", -1.0) == cap_s;
      if (same && sound_probe_record(j)) {
        *reused = true;
        return j;
      }
      if (same || !j.contains("key")) why = "fields missing or out of range";
      else ++*stale;
    } catch (const nlohmann::json::exception& e) {
      why = json_error_text(e.what());
    } catch (const std::exception& e) {
      why = e.what();
    }
    if (!why.empty()) note_unreadable(o, file, why, unreadable);
  }
  TrainOptions t;
  t.curriculum = o.curriculum;
  t.stage = o.stage;
  t.context = context;
  t.seed = seed;
  t.limits = o.limits;
  t.max_sim_s = cap_s;
  t.final_evaluation = false;
  const TrainResult r = train_stage(t);
  std::vector<ProbeEpisode> successes;
  for (const auto& rec : r.episodes)
    if (rec.episode.success) successes.push_back(probe_episode(rec.episode, int(r.psi.size())));
  nlohmann::json j = probe_json(r, successes, cap_s, key);
  write_file_atomic(file, j.dump(1) + "\n", "cannot write the probe record");
  *reused = false;
  return j;
}

}  // namespace

ProbeStats run_probe(const ProposeOptions& o, const std::string& context, const std::string& sources, double cap_s,
                     int* reused, std::vector<std::string>* unreadable, int* stale) {
  ProbeStats stats;
  for (int k = 0; k < o.probe_trials; ++k) {
    const uint64_t seed = Rng::mix(o.seed, 0x70726f6265ull + uint64_t(k));  // apart from the trials' seeds
    const std::string file = (fs::path(o.out) / "probe" / probe_file_name(k)).string();
    bool was_reused = false;
    const nlohmann::json j = probe_trial(o, context, sources, seed, cap_s, file, &was_reused, unreadable, stale);
    *reused += was_reused;
    stats.psi = j.at("psi").get<std::vector<std::string>>();
    stats.episodes += j.at("episodes").get<int>();
    stats.sim_s += j.at("sim_s").get<double>();
    for (const auto& e : j.at("successes"))
      stats.successes.push_back({e.at("ticks").get<std::vector<int>>(), e.at("first_conv").get<std::vector<int>>(),
                                 e.at("path").get<std::vector<int>>()});
    if (o.progress) {
      char line[200];
      std::snprintf(line, sizeof line, "probe %d/%d: %s %.0f simulated s, %zu successful episode%s so far\n", k + 1,
                    o.probe_trials, was_reused ? "reused" : "trained", j.at("sim_s").get<double>(), stats.successes.size(),
                    stats.successes.size() == 1 ? "" : "s");
      *o.progress << line << std::flush;
    }
  }
  return stats;
}

namespace {

// The most frequent value (ties to the lowest), -1 when there is none.
int mode(const std::vector<int>& values) {
  std::map<int, int> count;
  for (int v : values) ++count[v];
  int best = -1, n = 0;
  for (const auto& [v, c] : count)
    if (c > n) best = v, n = c;
  return best;
}

double median(std::vector<int> v) {
  std::sort(v.begin(), v.end());
  const size_t m = v.size() / 2;
  return v.empty() ? 0.0 : v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

}  // namespace

ProbeSummary summarize_probe(const ProbeStats& probe) {
  ProbeSummary s;
  const int n = int(probe.psi.size());
  s.tick_share.assign(size_t(n), 0.0);
  double total = 0.0;
  for (const auto& e : probe.successes)
    for (int i = 0; i < n; ++i) s.tick_share[size_t(i)] += e.ticks[size_t(i)], total += e.ticks[size_t(i)];
  for (double& t : s.tick_share) t = total > 0 ? t / total : 0.0;
  const double episodes = double(probe.successes.size());
  std::vector<int> finals;
  for (const auto& e : probe.successes)
    if (!e.path.empty()) finals.push_back(e.path.back());
  s.final_achiever = mode(finals);
  for (int i = 0; i < n; ++i) {
    // Reached CONV after the first decision: converged on the way, not given at the start.
    std::vector<int> at, achievers;
    for (const auto& e : probe.successes) {
      const int d = e.first_conv[size_t(i)];
      if (d >= 1) at.push_back(d), achievers.push_back(e.path[size_t(d - 1)]);
    }
    if (episodes == 0 || double(at.size()) < 0.5 * episodes) continue;
    s.subgoals.push_back({i, double(at.size()) / episodes, median(at), mode(achievers)});
  }
  std::stable_sort(s.subgoals.begin(), s.subgoals.end(),
                   [](const Subgoal& a, const Subgoal& b) { return a.order < b.order; });
  return s;
}

}  // namespace roger::propose_detail
