// records.cpp: reading back what a run left in its results folder. A trial's result.json,
// error.json and policy.json and the folder's manifest.json are checked before anything uses them:
// a truncated, empty, hand-edited or foreign file is named with what is wrong with it, never read
// as zeros (docs/reliability.md).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "batch/batch_internal.h"
#include "core/json_input.h"
#include "core/error.h"
#include "core/fileio.h"
#include "core/text.h"
#include "learn/learning.h"
#include "teach/teach.h"

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

// Why a result's "teacher" (what its stage's teacher did, which the report tells) cannot be told
// ("" when it can, or when there is none): found by a fuzzer, a hand-edited kind or state reached
// the report as "[json.exception.type_error.302] type must be string, but is number".
std::string teacher_problem(const json& r) {
  if (!r.contains("teacher")) return "";
  const json& t = r["teacher"];
  if (!t.is_object()) return "field \"teacher\" must be an object, got " + std::string(t.type_name());
  if (t.contains("kind") && !t["kind"].is_string())
    return "field \"teacher\": \"kind\" must name the teacher, got " +
           (t["kind"].is_structured() ? std::string(t["kind"].type_name()) : t["kind"].dump());
  try {
    describe_teacher_state(t.value("state", json()));
  } catch (const json::exception& e) {
    return "field \"teacher\": its \"state\" is not as roger train records it (" + json_error_text(e.what()) + ")";
  }
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
  if (r.contains("sources") && !(r["sources"].is_object() && std::all_of(r["sources"].begin(), r["sources"].end(),
                                                                         [](const json& f) { return f.is_string(); })))
    return "field \"sources\" must map the Lua files the trial read to their fingerprints";
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
  return teacher_problem(r);
}

// A reached trial's time to threshold is its checkpoints' own: the simulated seconds of the first
// of the passing checkpoints that last to the end. A time edited by hand (a probe turned Table
// I's B1 into 0:50) is refused, as a success rate that disagrees with its outcomes is.
std::string threshold_problem(const json& r) {
  if (!r["reached"].is_boolean() || !r.contains("threshold") || !r["threshold"].is_number()) return "";
  const json& cps = r["checkpoints"];
  const double threshold = r["threshold"].get<double>();
  // A trial reaches its threshold when its last checkpoint passes it (found by a probe: "reached":
  // false written by hand over a trial that reached it moved Table I's row unseen).
  if (!r["reached"].get<bool>()) {
    if (!cps.empty() && cps.back()["success_rate"].get<double>() >= threshold)
      return "field \"reached\" is false, but its last checkpoint's success rate " +
             format_number(cps.back()["success_rate"].get<double>()) + " is at or above the threshold " +
             format_number(threshold);
    return "";
  }
  size_t first = cps.size();
  while (first > 0 && cps[first - 1]["success_rate"].get<double>() >= threshold) --first;
  if (cps.empty()) return "field \"reached\" is true, but it has no checkpoint that could have reached the threshold";
  if (first == cps.size())
    return "field \"reached\" is true, but its last checkpoint's success rate is below the threshold " +
           format_number(threshold);
  const double at = cps[first]["sim_s"].get<double>(), said = r["time_to_threshold_s"].get<double>();
  if (said != at)
    return "field \"time_to_threshold_s\" is " + format_number(said) + ", but its checkpoints reached the threshold at " +
           format_number(at) + " simulated seconds (checkpoint " + std::to_string(first) + ")";
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
  return threshold_problem(r);
}

// Why a result's episode outcomes ("1101...", under `outcomes_key`) disagree with its summary of
// them ("" when they agree): a count of `episodes_key` episodes, the success rate, and the
// successes where recorded. A rate edited by hand would print outside its own interval, which the
// report computes from the outcomes.
std::string outcomes_problem(const json& r, const char* outcomes_key, const char* episodes_key) {
  if (!r.contains(outcomes_key)) return "";
  const std::string& outcomes = r[outcomes_key].get_ref<const std::string&>();
  const std::string field = "field \"" + std::string(outcomes_key) + "\"";
  if (double(outcomes.size()) != r[episodes_key].get<double>())
    return field + " holds " + std::to_string(outcomes.size()) + (outcomes.size() == 1 ? " outcome" : " outcomes") +
           " for " + r[episodes_key].dump() +
           " episodes (field \"" + episodes_key + "\")";
  const auto wins = std::count(outcomes.begin(), outcomes.end(), '1');
  if (r.contains("successes") && !(r["successes"].is_number() && r["successes"].get<double>() == double(wins)))
    return "field \"successes\" must be " + std::to_string(wins) + ", the successes in " + field + ", got " +
           r["successes"].dump();
  const double rate = outcomes.empty() ? 0.0 : double(wins) / double(outcomes.size());
  if (std::abs(r["success_rate"].get<double>() - rate) > 1e-9)
    return "field \"success_rate\" must be " + format_number(rate) + " (" + std::to_string(wins) + " of " +
           std::to_string(outcomes.size()) + " in " + field + "), got " + r["success_rate"].dump();
  return "";
}

// Why an evaluation result's counts disagree with its evaluation or with each other ("" when they
// agree); its fields' types were checked before.
std::string evaluation_problem(const json& r, const PlannedTrial& t) {
  const double episodes = r["episodes"].get<double>();
  if (!(episodes == std::floor(episodes) && episodes <= 1e6))  // a batch evaluation runs at most a million
    return "field \"episodes\" is not a count of episodes up to a million, got " + r["episodes"].dump();
  if (t.evaluation && episodes != double(t.evaluation->episodes))
    return "field \"episodes\": it ran " + r["episodes"].dump() + " episodes; the evaluation asks for " +
           std::to_string(t.evaluation->episodes);
  if (r.contains("outcomes")) return outcomes_problem(r, "outcomes", "episodes");
  if (r.contains("successes")) {  // a result written before the outcomes were recorded
    const json& s = r["successes"];
    if (!s.is_number_integer() || s.get<double>() < 0 || s.get<double>() > episodes)
      return "field \"successes\" must be a count of the " + r["episodes"].dump() + " episodes, got " + s.dump();
    if (episodes > 0 && std::abs(r["success_rate"].get<double>() - s.get<double>() / episodes) > 1e-9)
      return "field \"success_rate\" must be " + format_number(s.get<double>() / episodes) + " (" + s.dump() +
             " of " + r["episodes"].dump() + " episodes), got " + r["success_rate"].dump();
  }
  return "";
}

// A JSON value's type and, when short, the value: what a message says was found.
std::string found(const json& v) {
  if (v.is_structured()) return v.type_name();
  const std::string text = v.dump();
  return std::string(v.type_name()) + " " + (text.size() > 40 ? text.substr(0, 37) + "..." : text);
}

// The shape of a manifest's "config" as batch_config_json writes it and batch_config_from_json
// reads it: a type name ("string", "integer", "boolean", "pair": two strings), [shape] a list of
// that shape, {...} an object with those fields ("name?" optional, "*" any field name).
const json& config_shape() {
  static const json shape = json::parse(R"({
    "name": "string", "description?": "string", "curriculum": "string", "curriculum_file?": "string",
    "trials": "integer", "seed": "integer", "params": ["pair"],
    "limits?": {"instructions": "integer", "memory_mib": "integer"}, "sources?": {"*": "string"},
    "evaluation_sources?": {"*": "string"}, "runs": [{"name": "string", "stage": "string", "contexts": ["string"], "trials": "integer",
              "params": ["pair"], "skills": [{"skill": "string", "run": "string", "context": "string"}],
              "final_worlds?": "string"}],
    "evaluations": [{"name": "string", "run": "string", "context": "string", "scenario": "string",
                     "params": ["pair"], "shapes": ["string"], "episodes": "integer", "first_seed": "integer",
                     "worlds?": "string", "trials": "integer",
                     "skills?": [{"skill": "string", "run": "string", "context": "string"}]}],
    "tables": [{"title": "string", "run": "string", "baseline": "string", "evaluation": "string",
                "usage": [{"context": "string", "skill": "string", "subsumes": ["string"]}],
                "sorting?": [{"objects": "integer", "learned": "string", "hand": "string"}],
                "compare?": ["string"], "by?": "string"}],
    "figures": [{"file": "string", "title": "string", "kind": "string", "run": "string", "log_x": "boolean",
                 "compare?": ["string"], "y?": "string", "context?": "string", "param?": "string"}]
  })");
  return shape;
}

// Why value v at `at` (a path such as "config.runs[1].trials") does not have `shape` ("" when it has).
std::string shape_problem(const json& v, const json& shape, const std::string& at) {
  const std::string field = "field \"" + at + "\" must be ";
  if (shape.is_string()) {
    const std::string& type = shape.get_ref<const std::string&>();
    const bool ok = type == "string"    ? v.is_string()
                    : type == "integer" ? v.is_number_integer()
                    : type == "boolean" ? v.is_boolean()
                                        : v.is_array() && v.size() == 2 && v[0].is_string() && v[1].is_string();
    if (ok) return "";
    return field + (type == "integer" ? "an integer" : type == "pair" ? "a [name, value] pair of strings" : "a " + type) +
           ", got " + found(v);
  }
  if (shape.is_array()) {
    if (!v.is_array()) return field + "an array, got " + found(v);
    for (size_t k = 0; k < v.size(); ++k)
      if (auto p = shape_problem(v[k], shape[0], at + "[" + std::to_string(k) + "]"); !p.empty()) return p;
    return "";
  }
  if (!v.is_object()) return field + "an object, got " + found(v);
  for (auto it = shape.begin(); it != shape.end(); ++it) {
    std::string key = it.key();
    const bool optional = key.back() == '?';
    if (optional) key.pop_back();
    if (key == "*") {
      for (auto m = v.begin(); m != v.end(); ++m)
        if (auto p = shape_problem(*m, *it, at + "['" + m.key() + "']"); !p.empty()) return p;
    } else if (!v.contains(key)) {
      if (!optional) return "field \"" + at + "." + key + "\" is missing";
    } else if (auto p = shape_problem(v[key], *it, at + "." + key); !p.empty()) {
      return p;
    }
  }
  return "";
}

// Why the manifest's list of trials or its training seeds have the wrong type ("" when sound);
// plan.cpp compares them with the plan of its configuration.
std::string trial_ids_problem(const json& m) {
  if (m.contains("trials")) {
    const json& ids = m["trials"];
    if (!ids.is_array() || !std::all_of(ids.begin(), ids.end(), [](const json& id) { return id.is_string(); }))
      return "field \"trials\" must be the list of the folder's trial ids, got " + found(ids);
  }
  if (m.contains("seeds")) {
    const json& seeds = m["seeds"];
    if (!seeds.is_object()) return "field \"seeds\" must map the training trials to their seeds, got " + found(seeds);
    for (auto it = seeds.begin(); it != seeds.end(); ++it)
      if (!it->is_number_unsigned())
        return "field \"seeds\" must map each training trial to its seed, got " + found(*it) + " for " + it.key();
  }
  return "";
}

}  // namespace

namespace batch_detail {

json read_json_file(const std::string& path) {
  std::error_code ec;
  // "No such file" for a path that names nothing (found by a probe: a mistyped policy path read
  // "not a file", as if something else were there).
  if (!fs::exists(path, ec)) throw Error(path + ": no such file");
  if (!fs::is_regular_file(path, ec))
    throw Error(path + ": not a file (" + (fs::is_directory(path, ec) ? "a folder" : "a device, pipe or socket") + ")");
  const std::string text = read_file_text(path);
  if (text.empty()) throw Error(path + ": empty (0 bytes)");
  try {
    return parse_json(text);
  } catch (const std::exception& e) {
    // A Lua script given where a file roger wrote goes (found by a probe: --skill NAME=a skill
    // script read "not JSON ... truncated or edited?"): said as what it is.
    if (fs::path(path).extension() == ".lua")
      throw Error(path + ": a Lua script, not a JSON file roger wrote (a policy.json of roger train, say); a "
                  "hand-written skill is used by a context that lists it among its actions");
    throw Error(path + ": not JSON (" + std::to_string(text.size()) + " bytes: truncated or edited?): " + json_error_text(e.what()));
  }
}

json planned_params_json(const PlannedTrial& t) {
  json j = json::object();
  for (const auto& [k, v] : t.run ? t.run->params : t.evaluation->params) j[k] = v;
  if (t.evaluation && !t.evaluation->shapes.empty()) j["shape"] = t.shape;
  return j;
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
  // Found by a probe: a trial copied in from a sweep's other folder changed the tables unseen.
  // (A result written before set_params was recorded has none to compare.)
  if (r.contains("set_params"))
    if (const json planned = planned_params_json(t); r["set_params"] != planned)
      return "it was run with the scenario parameters " + r["set_params"].dump() + ", but the plan gives trial " +
             t.id + " " + planned.dump() + " (copied from another results folder?)";
  if (!t.run) return evaluation_problem(r, t);
  if (auto p = training_problem(r); !p.empty()) return p;
  if (r.contains("seed") && !(r["seed"].is_number_unsigned() && r["seed"].get<uint64_t>() == t.seed))
    return "field \"seed\" must be " + std::to_string(t.seed) + ", the seed the plan gives trial " + t.id + ", got " +
           r["seed"].dump();
  return outcomes_problem(r, "final_outcomes", "final_episodes");
}

namespace {

// What a results folder's manifest says every trial there was made with: the engine, the Lua files
// by name, and the curriculum's fingerprint. Read once per manifest as it is on disk (a report reads
// hundreds of trials against it).
struct FolderProvenance {
  bool known = false;
  std::string engine;
  std::map<std::string, std::string> sources;  // name -> fingerprint (training's and evaluations')
  std::string curriculum;                      // the curriculum file's fingerprint, "" if not found
};

FolderProvenance read_provenance(const fs::path& manifest) {
  FolderProvenance p;
  json m;
  try {
    m = read_manifest_file(manifest.string());
  } catch (const std::exception&) {
    return p;  // said by whoever reads the manifest for the plan
  }
  p.known = true;
  p.engine = m["engine"].get<std::string>();
  const json& config = m["config"];
  const std::string file = config.value("curriculum_file", std::string());
  for (const char* field : {"sources", "evaluation_sources"}) {
    if (!config.contains(field) || !config[field].is_object()) continue;
    for (const auto& [name, print] : config[field].items()) {
      if (!print.is_string()) continue;
      p.sources[name] = print.get<std::string>();
      // The curriculum is the source its recorded path ends with ("tests/x.lua" of ".../tests/x.lua").
      if (std::string(field) == "sources" && (name == file || source_names_path(name, file)))
        p.curriculum = print.get<std::string>();
    }
  }
  return p;
}

// A copy: runs read it from several threads, and a rewritten manifest replaces the cached entry.
FolderProvenance folder_provenance(const std::string& out) {
  static std::mutex mutex;
  static std::map<std::string, std::pair<std::string, FolderProvenance>> cache;  // folder -> (stamp, what)
  const fs::path manifest = fs::path(out) / "manifest.json";
  std::error_code ec;
  const auto size = fs::file_size(manifest, ec);
  const auto time = fs::last_write_time(manifest, ec).time_since_epoch().count();
  const std::string stamp = ec ? "" : std::to_string(size) + "@" + std::to_string(time);
  std::lock_guard<std::mutex> lock(mutex);
  auto& entry = cache[fs::absolute(manifest).lexically_normal().string()];
  if (stamp.empty() || entry.first != stamp) entry = {stamp, stamp.empty() ? FolderProvenance{} : read_provenance(manifest)};
  return entry.second;
}

// Why a trial's result was not made for this folder ("" when it was, or when the folder or the
// result records too little to tell): found by a probe, trials copied in from another folder (a
// shard run elsewhere, of a curriculum edited there, or by another build of the engine) were read
// as this folder's and changed its tables; and an evaluation of a policy retrained since was kept.
std::string provenance_problem(const std::string& out, const json& r) {
  const FolderProvenance f = folder_provenance(out);
  if (!f.known) return "";
  if (r.contains("engine") && r["engine"].is_string() && r["engine"] != f.engine)
    return "it was made by another build of the engine (engine " + r["engine"].get<std::string>() +
           "), and the folder by engine " + f.engine + " (copied from another results folder?)";
  if (r.contains("sources") && r["sources"].is_object()) {
    bool read_curriculum = f.curriculum.empty();
    for (const auto& [name, print] : r["sources"].items()) {
      read_curriculum = read_curriculum || print == f.curriculum;
      const auto it = f.sources.find(name);
      if (it != f.sources.end() && print != it->second)
        return "it read " + name + " with the fingerprint " + print.get<std::string>() + ", but the folder's " +
               name + " has " + it->second + " (a trial of another version of it, copied from another results folder?)";
    }
    if (!read_curriculum)
      return "none of the Lua files it read is the folder's curriculum (fingerprint " + f.curriculum +
             "): a trial of another curriculum, copied from another results folder?";
  }
  // A policy gone since (its trial removed, or failed, to run again) changes nothing here: its trial
  // runs again first, as it ran, and is compared then.
  if (r.contains("policies") && r["policies"].is_object())
    for (const auto& [name, print] : r["policies"].items()) {
      const fs::path file = fs::path(out) / name;
      std::error_code ec;
      if (!fs::is_regular_file(file, ec)) continue;
      const std::string now = fingerprint(read_file_text(file.string()));
      if (!print.is_string() || print != now)
        return "it read " + name + " with the fingerprint " + (print.is_string() ? print.get<std::string>() : print.dump()) +
               ", and the file now has " + now + " (trained again, or edited, since): its figures are of another policy";
    }
  return "";
}

// Where a trial's per-episode records are, and which of its result's fields summarize them.
struct EpisodeRecords {
  const char* file;         // "final.jsonl", "eval.jsonl"
  const char* outcomes;     // its outcomes' field: "final_outcomes", "outcomes"
  const char* what;         // "final-evaluation episodes"
  // The result's means and std over the lines' fields: {result field, line field, std?}.
  std::vector<std::tuple<const char*, const char*, bool>> summaries;
};

// Whether `said` (a result's number) is what the records give (`from`, computed as the trainer
// does: the same sums in the same order, so equal but for the last bits of a JSON round trip).
bool agrees(double said, double from) { return std::abs(said - from) <= 1e-9 * std::max(1.0, std::abs(from)); }

// Why the lines' summaries disagree with the result's ("" when they agree): a reward mean edited
// by hand beside outcomes left alone (found by a probe) would print in the tables.
std::string summary_problem(const std::string& path, const json& result, const EpisodeRecords& records,
                            const std::map<std::string, std::vector<double>>& columns) {
  for (const auto& [field, column, is_std] : records.summaries) {
    if (!result.contains(field) || !result[field].is_number()) continue;  // the result's check names it
    const auto c = columns.find(column);
    if (c == columns.end()) continue;  // lines without it (objects sorted in worlds with none to sort)
    const std::vector<double>& xs = c->second;
    double mean = 0.0, var = 0.0;
    for (double x : xs) mean += x;
    mean /= double(std::max<size_t>(1, xs.size()));
    for (double x : xs) var += (x - mean) * (x - mean);
    const double from = is_std ? std::sqrt(var / double(std::max<size_t>(1, xs.size()))) : mean;
    if (!agrees(result[field].get<double>(), from))
      return path + ": its episodes' \"" + column + "\" give a " + (is_std ? "std" : "mean") + " of " +
             format_number(from) + ", but the trial's result.json records " + result[field].dump() + " (\"" + field +
             "\"): edited?";
  }
  return "";
}

// Throws roger::Error when a trial's per-episode records (a training trial's final.jsonl, an
// evaluation trial's eval.jsonl), which the report's tables split by feature read and which
// back its result's numbers, are missing, cut short, or disagree with the result: another count
// of episodes, another outcome, another mean or std.
void check_episode_records(const fs::path& dir, const json& result, const EpisodeRecords& records) {
  const std::string path = (dir / records.file).string();
  const std::string& outcomes = result[records.outcomes].get_ref<const std::string&>();
  const size_t episodes = outcomes.size();
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw Error(path + ": missing: the trial's result.json records " + std::to_string(episodes) + " " + records.what +
                " (\"" + records.outcomes + "\"), and this file holds them, one line each");
  // A file cut at a line's end parses line by line: only the count shows episodes lost. One cut
  // within a line has a last line without its end (found by a probe: it passed, and only a report
  // --by, which parses the lines, failed on it, every time, since the trial was kept).
  const std::string text = read_file_text(path);
  if (!text.empty() && text.back() != '\n')
    throw Error(path + ": its last line has no end, as a file cut short has: truncated or edited?");
  // Each episode's outcome is the one result.json records (found by a probe: 25 successes flipped
  // to failures passed, and one report gave the trials 100% in Table II and 75% split by obstacles).
  std::map<std::string, std::vector<double>> columns;  // each summarized field, over the lines
  size_t lines = 0;
  for (size_t at = 0; at < text.size();) {
    const size_t end = std::min(text.find('\n', at), text.size());
    if (end > at && (text[at] != '{' || text[end - 1] != '}'))
      throw Error(path + ":" + std::to_string(lines + 1) + ": not a JSON object on one line: truncated or edited?");
    // (A line that is no record, or whose success is no boolean, is the reader's to refuse, with
    // its own words: final_record.)
    if (end > at && lines < episodes) {
      const json record = parse_json(text.cbegin() + long(at), text.cbegin() + long(end), false);
      const bool success = outcomes[lines] == '1';
      if (record.is_object() && record.contains("success") && record["success"].is_boolean() &&
          record["success"] != success)
        throw Error(path + ":" + std::to_string(lines + 1) + ": \"success\": " + record["success"].dump() +
                    ", but the trial's result.json records episode " + std::to_string(lines + 1) + " " +
                    (success ? "a success" : "a failure") + " (\"" + records.outcomes + "\"): edited?");
      // The summarized fields of a record (an object with its boolean success; another line is
      // the reader's to refuse, with its own words).
      std::set<std::string> read;  // a column two summaries share (a mean and a std) is read once
      const bool sound = record.is_object() && record.contains("success") && record["success"].is_boolean();
      for (const auto& summary : records.summaries) {
        const char* column = std::get<1>(summary);
        if (!sound || !record.contains(column) || !read.insert(column).second) continue;
        if (!record[column].is_number())
          throw Error(path + ":" + std::to_string(lines + 1) + ": field \"" + column + "\" must be a number, got " +
                      record[column].dump());
        columns[column].push_back(record[column].get<double>());
      }
    }
    lines += end > at;
    at = end + 1;
  }
  if (lines != episodes)
    throw Error(path + ": holds " + std::to_string(lines) + " " + records.what + ", but the trial's result.json "
                "records " + std::to_string(episodes) + " (\"" + records.outcomes + "\"): truncated or edited?");
  // A summary is checked where every line gives its field (objects sorted only where the worlds
  // have some; a damaged line is the reader's to name).
  for (auto it = columns.begin(); it != columns.end();)
    it = it->second.size() == episodes ? std::next(it) : columns.erase(it);
  if (auto p = summary_problem(path, result, records, columns); !p.empty()) throw Error(p);
}

// A training trial's final evaluation (final.jsonl); nothing for a result from before it was written.
void check_final_records(const fs::path& dir, const json& result) {
  if (!result.contains("final_outcomes")) return;
  check_episode_records(dir, result,
                        {"final.jsonl", "final_outcomes", "final-evaluation episodes",
                         {{"reward_mean", "reward", false}, {"reward_std", "reward", true},
                          {"final_time_mean", "sim_s", false}, {"final_sorted_mean", "sorted", false}}});
}

// A training trial's checkpoints.jsonl, where there is one, holds its result's checkpoints line for
// line (found by a probe: a checkpoint's rate edited in result.json reached the dashboard unseen,
// and a damaged line of checkpoints.jsonl was never noticed).
void check_checkpoint_records(const fs::path& dir, const json& result) {
  const fs::path file = dir / "checkpoints.jsonl";
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return;
  const std::string text = read_file_text(file.string());
  const json& cps = result["checkpoints"];
  size_t k = 0, at = 0;
  for (; at < text.size(); ++k) {
    const size_t end = std::min(text.find('\n', at), text.size());
    const std::string where = file.string() + ":" + std::to_string(k + 1);
    json line;
    try {
      line = json::parse(text.substr(at, end - at));
    } catch (const json::exception& e) {
      throw Error(where + ": not JSON (" + json_error_text(e.what()) + ")");
    }
    if (k >= cps.size() || line != cps[k])
      throw Error(where + ": checkpoint " + std::to_string(k + 1) + " is not the one the trial's result.json records" +
                  (k >= cps.size() ? " (it records " + std::to_string(cps.size()) + ")" : "") + ": edited?");
    at = end + 1;
  }
  if (k != cps.size())
    throw Error(file.string() + ": holds " + std::to_string(k) + " checkpoints, but the trial's result.json records " +
                std::to_string(cps.size()) + ": truncated or edited?");
}

// An evaluation trial's episodes (eval.jsonl, named by its result since they were written).
void check_evaluation_records(const fs::path& dir, const json& result) {
  if (!result.contains("episodes_file")) return;  // a result from before eval.jsonl was written
  if (result["episodes_file"] != kEvalEpisodesFile || !result.contains("outcomes"))
    throw Error((dir / "result.json").string() + ": field \"episodes_file\" must be \"" + kEvalEpisodesFile +
                "\" beside the episodes' \"outcomes\", got " + result["episodes_file"].dump());
  check_episode_records(dir, result,
                        {kEvalEpisodesFile, "outcomes", "evaluation episodes",
                         {{"reward_mean", "reward", false}, {"reward_std", "reward", true}, {"time_mean", "sim_s", false}}});
}

// Throws roger::Error when a training trial's policy.json is another trial's: its stage, context
// or seed are not the plan's for this one (found by a probe: trial 001's policy copied into 000
// was taken, and the later runs were built on it). A policy that names no stage (written without
// them) passes.
void check_policy_owner(const std::string& path, const json& policy, const PlannedTrial& t) {
  if (!policy.contains("stage") || policy["stage"] == "") return;
  const std::pair<const char*, json> own[] = {{"stage", t.run->stage}, {"context", t.context}, {"seed", t.seed}};
  for (const auto& [key, planned] : own)
    if (policy.contains(key) && policy[key] != planned)
      throw Error(path + ": field \"" + key + "\" is " + policy[key].dump() + ", but the plan gives trial " + t.id +
                  " " + planned.dump() + ": the policy of another trial (copied in?)");
}

}  // namespace

std::string trial_status(const std::string& out, const PlannedTrial& t, json& result, std::string& message) {
  const fs::path d = trial_dir(out, t.id);
  const std::string result_path = (d / "result.json").string(), error_path = (d / "error.json").string();
  std::error_code ec;
  try {
    if (fs::exists(result_path, ec)) {
      result = read_json_file(result_path);
      if (const std::string p = result_problem(result, t); !p.empty()) throw Error(result_path + ": " + p);
      if (const std::string p = provenance_problem(out, result); !p.empty()) throw Error(result_path + ": " + p);
      if (t.run) {  // a training trial's policy is what later trials and `roger eval` read
        const std::string policy = (d / "policy.json").string();
        std::vector<std::string> psi;
        for (const auto& a : result["psi"]) psi.push_back(a.get<std::string>());
        const json saved = read_json_file(policy);
        QTable::from_json(saved, psi, policy);
        check_policy_owner(policy, saved, t);
        check_final_records(d, result);
        check_checkpoint_records(d, result);
      } else {
        check_evaluation_records(d, result);
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
  // The report reads "version" with value(), which throws a json type_error on any other shape.
  if (m.contains("version") && !m["version"].is_string())
    throw Error(path + ": field \"version\" must be a string, got " + m["version"].type_name());
  // Every field batch_config_from_json reads, by its path: its own messages would be nlohmann's.
  if (auto p = shape_problem(m["config"], config_shape(), "config"); !p.empty()) throw Error(path + ": " + p);
  if (auto p = trial_ids_problem(m); !p.empty()) throw Error(path + ": " + p);
  return m;
}

}  // namespace batch_detail
}  // namespace roger
