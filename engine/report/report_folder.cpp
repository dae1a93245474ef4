// report_folder.cpp: a results folder read once for the report (report_internal.h): every trial's
// result.json parsed (write_report has checked each one first, engine/batch/records.cpp), pooled
// evaluations, formatting.
#include "report/report_internal.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>

#include "core/json_input.h"
#include "core/error.h"
#include "core/fileio.h"
#include "core/text.h"

namespace roger::report_detail {
namespace {

std::string read_text(const fs::path& path) { return read_file_text(path.string()); }

// "trial <id>'s result.json: ", naming the record a message is about (its id was checked when the
// folder was read).
std::string record_of(const json& j) {
  const auto it = j.find("id");
  return it != j.end() && it->is_string() ? "trial " + it->get<std::string>() + "'s result.json: " : "";
}

}  // namespace

std::string fmt(const char* f, double v) {
  // Sized by the text: "%.2f" of -1e308 is 313 characters, and a buffer of 64 cut it (found by a
  // probe, on a hand-edited episode's obstacles).
  const int n = std::snprintf(nullptr, 0, f, v);
  std::string text(size_t(std::max(n, 0)), '\0');
  std::snprintf(text.data(), text.size() + 1, f, v);
  return text;
}

std::string bin_label(double lo, double hi, int b, int bins) {
  const double width = (hi - lo) / bins;
  const int decimals = width > 0 ? std::clamp(2 - int(std::floor(std::log10(width))), 0, 17) : 2;
  const auto edge = [&](int k) {
    char buf[400];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, lo + (hi - lo) * k / bins);
    std::string t = buf;
    if (t.find('.') != std::string::npos) {
      t.erase(t.find_last_not_of('0') + 1);
      if (t.back() == '.') t.pop_back();
    }
    return t == "-0" ? std::string("0") : t;
  };
  return edge(b) + " to " + edge(b + 1);
}

std::string pct(double fraction) { return fmt("%.1f%%", 100.0 * fraction); }

std::string rate_pct(double rate) {
  // One more digit at a time until the text no longer claims all or none where the rate is
  // neither: a single failure in 2500 episodes must not read as 100.0%. What the text claims is
  // the number it shows (10.0% starts with a 1 and zeros too).
  std::string text = pct(rate);
  const auto shown = [&] { return std::strtod(text.c_str(), nullptr); };
  for (int digits = 2; digits <= 9 && ((rate < 1 && shown() >= 100.0) || (rate > 0 && shown() == 0.0)); ++digits)
    text = fmt(("%." + std::to_string(digits) + "f%%").c_str(), 100.0 * rate);
  return text;
}

std::string with_params(const std::vector<std::pair<std::string, std::string>>& params) {
  std::string out = params.empty() ? "" : " with";
  for (const auto& [k, v] : params) out += " " + k + "=" + v;
  return out;
}

TrialState trial_state(const std::string& dir, const std::string& id) {
  const fs::path d = trial_dir(dir, id);
  std::error_code ec;
  if (fs::exists(d / "result.json", ec)) return TrialState::kResult;
  return fs::exists(d / "error.json", ec) ? TrialState::kFailed : TrialState::kPending;
}

Results Folder::trials(const std::vector<std::string>& ids) const {
  Results r;
  r.expected = int(ids.size());
  for (const auto& id : ids) {
    const TrialState state = trial_state(dir_, id);
    if (state == TrialState::kFailed) ++r.failed;
    if (state == TrialState::kPending) ++r.pending;
    if (state != TrialState::kResult) continue;
    const fs::path file = fs::path(trial_dir(dir_, id)) / "result.json";
    try {
      r.ok.push_back(parse_json(read_text(file)));
    } catch (const std::exception& e) {
      throw Error(file.string() + ": not JSON: " + json_error_text(e.what()));
    }
  }
  return r;
}

Completeness completeness(const BatchPlan& plan) {
  Completeness c;
  for (const auto& phase : plan.phases)
    for (const PlannedTrial& t : phase) {
      const TrialState state = trial_state(plan.out, t.id);
      ++c.trials;
      c.with_results += state == TrialState::kResult;
      c.failed += state == TrialState::kFailed;
      c.pending += state == TrialState::kPending;
    }
  return c;
}

std::string partial_line(const Completeness& c) {
  std::vector<std::string> without;
  if (c.pending) without.push_back(std::to_string(c.pending) + " pending");
  if (c.failed) without.push_back(std::to_string(c.failed) + " failed");
  return "**Partial report:** " + std::to_string(c.with_results) + " of " + counted(c.trials, "trial") +
         (c.with_results == 1 ? " has a result" : " have results") + " (" + join(without) +
         "); the tables and figures draw only on the trials with results.";
}

json partial_json(const Completeness& c) {
  return {{"trials", c.trials}, {"with_results", c.with_results}, {"pending", c.pending}, {"failed", c.failed}};
}

Results Folder::run(const BatchRun& run, const std::string& context) const {
  std::vector<std::string> ids;
  for (int i = 0; i < run.trials; ++i) ids.push_back(batch_trial_id(run.name, context, i));
  return trials(ids);
}

const json& usage_of(const json& j) {
  static const json none = json::object();
  const auto it = j.find("usage");
  return it == j.end() ? none : *it;
}

double num(const json& j, const char* key) {
  if (!j.contains(key) || !j[key].is_number()) throw Error(record_of(j) + "a trial result has no number '" + key + "'");
  return j[key].get<double>();
}

std::vector<CensoredTime> times_of(const Results& r) {
  std::vector<CensoredTime> t;
  for (const auto& j : r.ok) t.push_back({num(j, "time_to_threshold_s"), j.value("reached", false)});
  return t;
}

Pooled pool(const std::vector<json>& evals, const char* episodes_key) {
  Pooled p;
  double sum = 0, sum_sq = 0, succ = 0;
  for (const auto& j : evals) {
    const double n = num(j, episodes_key), m = num(j, "reward_mean"), s = num(j, "reward_std");
    if (!(n >= 0 && n <= 1e9 && n == std::floor(n)))  // int64_t(1e300) would be undefined
      throw Error(record_of(j) + "a trial result's '" + episodes_key + "' is not a count of episodes: " + fmt("%g", n));
    sum += n * m;
    sum_sq += n * (s * s + m * m);
    succ += n * num(j, "success_rate");
    p.episodes += int64_t(n);
  }
  if (p.episodes == 0) return p;
  p.mean = sum / p.episodes;
  p.std = std::sqrt(std::max(0.0, sum_sq / p.episodes - p.mean * p.mean));
  p.success = succ / p.episodes;
  return p;
}

void append_rate_cells(const json& j, int64_t policy, const char* first_seed_key, const char* episodes_key,
                       const char* outcomes_key, std::vector<RateCell>& cells) {
  // The seed as the integer it is: read as a double, seeds past 2^53 were refused (found by a probe:
  // an evaluation's first_seed of 2^53 left a folder no report could read) and two seeds just below
  // it rounded to one layout (4 worlds counted as 3, and the interval resampled as if shared).
  const double n = num(j, episodes_key);
  const json* seed = j.contains(first_seed_key) ? &j[first_seed_key] : nullptr;
  if (!seed || !(seed->is_number_unsigned() || (seed->is_number_integer() && seed->get<int64_t>() >= 0)))
    throw Error(record_of(j) + "a trial result's '" + first_seed_key + "' is not a seed (an integer from 0 to "
                "2^64 - 1): " + (seed ? seed->dump() : std::string("none")));
  const uint64_t first = seed->get<uint64_t>();
  if (!(n >= 0 && n <= 1e6 && n == std::floor(n)))  // a batch evaluation runs at most a million
    throw Error(record_of(j) + "a trial result's '" + episodes_key + "' is not a count of episodes up to a million: " +
                fmt("%g", n));
  // Its characters were checked before the report began (batch_detail::result_problem).
  const bool known = j.contains(outcomes_key);
  const std::string outcomes = known ? j[outcomes_key].get<std::string>() : std::string();
  if (known && outcomes.size() != size_t(n))
    throw Error(record_of(j) + "a trial result's '" + outcomes_key + "' holds " + std::to_string(outcomes.size()) +
                " outcomes for " + fmt("%g", n) + " episodes");
  const double rate = known ? 0.0 : num(j, "success_rate");
  for (int64_t k = 0; k < int64_t(n); ++k)
    // A layout is the world's seed, which wraps past 2^64 as the engine's does; kept in int64_t,
    // one to one.
    cells.push_back({policy, int64_t(first + uint64_t(k)), known ? double(outcomes[size_t(k)] == '1') : rate, 1.0});
}

std::string resampled_name(Resampled by) {
  switch (by) {
    case Resampled::kPolicies: return "policies";
    case Resampled::kLayouts: return "layouts";
    case Resampled::kPoliciesAndLayouts: return "policies and layouts";
  }
  return "?";
}

std::string interval_note(const std::set<Resampled>& methods) {
  std::string s = "Success rate [95% CI]: a percentile bootstrap of the pooled rate (" + std::to_string(kRateResamples) +
                  " resamples, docs/batch.md) that draws again what the episodes were drawn from: ";
  std::vector<std::string> parts;
  if (methods.count(Resampled::kPolicies))
    parts.push_back("whole policies, where no layout is met by two policies (a policy's episodes share its "
                    "learned choices)");
  if (methods.count(Resampled::kPoliciesAndLayouts))
    parts.push_back("whole policies and whole layouts, independently, where policies share layouts (a hard "
                    "layout costs every policy that meets it)");
  if (methods.count(Resampled::kLayouts)) parts.push_back("the layouts, where there is one policy");
  // With no result yet there is nothing drawn from to name (a partial report of pending trials).
  if (parts.empty()) s = s.substr(0, s.size() - 2) + " (none yet: no trial of the table has a result)";
  for (size_t k = 0; k < parts.size(); ++k) s += (k ? "; " : "") + parts[k];
  return s + ". It is never narrower than Wilson's interval over the distinct layouts, which keeps it open at 0% "
             "and 100%.";
}

std::string trials_note(const Results& r) {
  std::string s = std::to_string(r.ok.size()) + "/" + std::to_string(r.expected);
  if (r.failed) s += " (" + std::to_string(r.failed) + " failed)";
  if (r.pending) s += " (" + std::to_string(r.pending) + " pending)";
  return s;
}

}  // namespace roger::report_detail
