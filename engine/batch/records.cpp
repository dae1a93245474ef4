// records.cpp: reading back what a run left in its results folder. A trial's result.json,
// error.json and policy.json and the folder's manifest.json are checked before anything uses them:
// a truncated, empty, hand-edited or foreign file is named with what is wrong with it, never read
// as zeros (docs/reliability.md).
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "batch/batch_internal.h"
#include "core/error.h"
#include "core/fileio.h"
#include "core/text.h"
#include "learn/learning.h"

namespace roger {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

constexpr double kInf = HUGE_VAL;

// Why field `key` of object j is not a finite number within [lo, hi] ("" when it is): a share
// of 7.5 or a negative time is no trial's, and the tables would print it (a success of 750%).
std::string number_problem(const json& j, const char* key, double lo = -kInf, double hi = kInf) {
  if (!j.contains(key)) return "it has no field \"" + std::string(key) + "\"";
  const json& v = j[key];
  if (!v.is_number() || !std::isfinite(v.get<double>()))
    return "field \"" + std::string(key) + "\" must be a finite number, got " + v.dump();
  if (v.get<double>() < lo || v.get<double>() > hi)
    return "field \"" + std::string(key) + "\" must be " +
           (hi == kInf ? "at least " + format_number(lo) : "within [" + format_number(lo) + ", " + format_number(hi) + "]") +
           ", got " + v.dump();
  return "";
}

// Why a field that some results hold and others lack has the wrong type ("" when each present
// one is sound): what the report reads of them is then safe to read.
std::string optional_field_problem(const json& r) {
  if (r.contains("reached") && !r["reached"].is_boolean()) return "field \"reached\" must be true or false";
  if (r.contains("psi")) {
    if (!r["psi"].is_array()) return "field \"psi\" must be the list of the context's actions";
    for (const auto& a : r["psi"])
      if (!a.is_string()) return "field \"psi\" must hold action names, got " + a.dump();
  }
  if (r.contains("checkpoints") && !r["checkpoints"].is_array()) return "field \"checkpoints\" must be a list";
  if (r.contains("skipped_tasks") && !r["skipped_tasks"].is_array())
    return "field \"skipped_tasks\" must be a list of the training tasks skipped";
  for (const char* key : {"outcomes", "final_outcomes"})
    if (r.contains(key) && !(r[key].is_string() && r[key].get<std::string>().find_first_not_of("01") == std::string::npos))
      return "field \"" + std::string(key) + "\" must be a string of episode outcomes, 1 a success and 0 a failure";
  if (r.contains("diagnosis")) {
    const json& d = r["diagnosis"];
    const json* causes = d.is_object() && d.contains("causes") ? &d["causes"] : nullptr;
    if (!causes || !causes->is_array() ||
        !std::all_of(causes->begin(), causes->end(), [](const json& c) { return c.is_string(); }))
      return "field \"diagnosis\" must be an object whose \"causes\" is a list of sentences";
  }
  return "";
}

// Why the training-only fields of a result are unsound ("" when sound); their types were checked
// by optional_field_problem.
std::string training_problem(const json& r) {
  for (const char* key : {"time_to_threshold_s", "train_episodes", "final_episodes"})
    if (auto p = number_problem(r, key, 0.0); !p.empty()) return p;
  if (!r.contains("reached")) return "field \"reached\" must be true or false";
  if (!r.contains("psi") || r["psi"].empty()) return "field \"psi\" must be the list of the context's actions";
  if (!r.contains("checkpoints")) return "field \"checkpoints\" must be a list";
  for (size_t k = 0; k < r["checkpoints"].size(); ++k) {
    const json& c = r["checkpoints"][k];
    for (const char* key : {"sim_s", "reward_mean", "success_rate"}) {
      const double lo = std::string(key) == "reward_mean" ? -kInf : 0.0, hi = std::string(key) == "success_rate" ? 1.0 : kInf;
      const std::string p = c.is_object() ? number_problem(c, key, lo, hi) : "it is not an object";
      if (!p.empty()) return "checkpoint " + std::to_string(k) + ": " + p;
    }
  }
  return "";
}

}  // namespace

namespace batch_detail {

json read_json_file(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw Error(path + ": not a file");
  const std::string text = read_file_text(path);
  if (text.empty()) throw Error(path + ": empty (0 bytes)");
  try {
    return json::parse(text);
  } catch (const std::exception& e) {
    throw Error(path + ": not JSON (" + std::to_string(text.size()) + " bytes: truncated or edited?): " + e.what());
  }
}

std::string result_problem(const json& r, const PlannedTrial& t) {
  if (!r.is_object()) return "a trial result must be a JSON object, got " + std::string(r.type_name());
  if (!r.contains("id") || !r["id"].is_string()) return "it has no trial \"id\" (not a result of roger run?)";
  if (r["id"] != t.id) return "it is the result of trial " + r["id"].get<std::string>() + ", not of " + t.id;
  if (!r.contains("trial") || !r["trial"].is_number_integer() || r["trial"] != t.index)
    return "field \"trial\" must be " + std::to_string(t.index) + ", got " + (r.contains("trial") ? r["trial"].dump() : "nothing");
  if (auto p = number_problem(r, "success_rate", 0.0, 1.0); !p.empty()) return p;
  if (auto p = number_problem(r, "reward_mean"); !p.empty()) return p;
  if (auto p = number_problem(r, "reward_std", 0.0); !p.empty()) return p;
  if (!t.run)
    if (auto p = number_problem(r, "episodes", 0.0); !p.empty()) return p;
  if (!r.contains("usage") || !r["usage"].is_object()) return "field \"usage\" must be an object";
  for (auto it = r["usage"].begin(); it != r["usage"].end(); ++it)
    if (!it->is_number() || !(it->get<double>() >= 0.0 && it->get<double>() <= 1.0 + 1e-9))
      return "field \"usage\" must map actions to shares, got " + it->dump() + " for " + it.key();
  if (auto p = optional_field_problem(r); !p.empty()) return p;
  return t.run ? training_problem(r) : "";
}

std::string trial_status(const std::string& out, const PlannedTrial& t, json& result, std::string& message) {
  const fs::path d = trial_dir(out, t.id);
  const std::string result_path = (d / "result.json").string(), error_path = (d / "error.json").string();
  std::error_code ec;
  try {
    if (fs::exists(result_path, ec)) {
      result = read_json_file(result_path);
      if (const std::string p = result_problem(result, t); !p.empty()) throw Error(result_path + ": " + p);
      if (t.run) {  // a training trial's policy is what later trials and `roger eval` read
        const std::string policy = (d / "policy.json").string();
        std::vector<std::string> psi;
        for (const auto& a : result["psi"]) psi.push_back(a.get<std::string>());
        QTable::from_json(read_json_file(policy), psi, policy);
      }
      return "ok";
    }
    if (fs::exists(error_path, ec)) {
      const json e = read_json_file(error_path);
      if (!e.is_object() || !e.contains("error") || !e["error"].is_string())
        throw Error(error_path + ": a trial error must be an object with a string \"error\"");
      message = e["error"].get<std::string>();
      return "failed";
    }
  } catch (const std::exception& e) {
    result = json();
    message = e.what();
    return "corrupt";
  }
  return "pending";
}

json read_manifest_file(const std::string& path) {
  const json m = read_json_file(path);
  if (!m.is_object()) throw Error(path + ": a manifest must be a JSON object, got " + std::string(m.type_name()));
  if (!m.contains("format") || m["format"] != "roger-results/1")
    throw Error(path + ": not the manifest of a roger run results folder (\"format\" must be \"roger-results/1\", got " +
                (m.contains("format") ? m["format"].dump() : std::string("nothing")) + ")");
  if (!m.contains("config") || !m["config"].is_object()) throw Error(path + ": field \"config\" must be an object");
  for (const char* key : {"engine", "script"})
    if (!m.contains(key) || !m[key].is_string()) throw Error(path + ": field \"" + std::string(key) + "\" must be a string");
  return m;
}

}  // namespace batch_detail
}  // namespace roger
