// plan.cpp: the plan of a batch script (its trials, phase by phase), the selectors of --only, and
// the results folder's manifest and summary.csv.
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>

#include "batch/batch.h"
#include "batch/batch_internal.h"
#include "batch/trainer.h"
#include "core/error.h"
#include "core/fileio.h"
#include "core/json_input.h"
#include "core/text.h"
#include "engine_fingerprint.h"
#include "script/curriculum/curriculum.h"
#include "script/scenario/scenario.h"
#include "script/sandbox/lua_sandbox.h"

namespace roger {

namespace fs = std::filesystem;
using namespace batch_detail;
using json = nlohmann::json;

// FNV-1a, 64 bits, as 16 hex digits: a stable fingerprint of a file's text.
std::string batch_detail::fingerprint(const std::string& text) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char buf[20];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

namespace {

// The first five of `items`, joined, and how many more there are.
std::string join_some(const std::vector<std::string>& items) {
  std::string s;
  for (size_t k = 0; k < items.size() && k < 5; ++k) s += (k ? ", " : "") + items[k];
  return items.size() > 5 ? s + " and " + std::to_string(items.size() - 5) + " more" : s;
}

// A value of a configuration for a message: whole when short, else 70 characters from a little
// before `at`, where it first differs from the other side's, so that the change shows.
std::string excerpt(const std::string& s, size_t at) {
  if (s.size() <= 80) return s;
  const size_t from = at > 30 ? at - 30 : 0;
  return (from ? "..." : "") + s.substr(from, 70) + (from + 70 < s.size() ? "..." : "");
}

// The path of member `key` under `at`: "runs[1].trials", or "sources['lib/skills.lua']" for a key
// that is not a plain name.
std::string member_path(const std::string& at, const std::string& key) {
  const bool plain = !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
  if (!plain) return at + "['" + key + "']";
  return at.empty() ? key : at + "." + key;
}

void differences(const json* a, const json* b, const std::string& at, std::vector<std::string>& out);

// The names of a list of [name, value] pairs (a parameter list), or nothing when `list` is not
// one or names a key twice.
std::optional<std::map<std::string, const json*>> pairs_by_name(const json& list) {
  std::map<std::string, const json*> named;
  for (const json& item : list) {
    if (!item.is_array() || item.size() != 2 || !item[0].is_string()) return std::nullopt;
    if (!named.emplace(item[0].get<std::string>(), &item[1]).second) return std::nullopt;
  }
  return named;
}

// Two parameter lists compared by name ("params.mass: absent in the folder, \"0.7\" now") rather
// than by place, where one more --set would shift every later pair; false when either is not such
// a list.
bool differences_by_name(const json& a, const json& b, const std::string& at, std::vector<std::string>& out) {
  const auto named_a = pairs_by_name(a), named_b = pairs_by_name(b);
  if (!named_a || !named_b || (a.empty() && b.empty())) return false;
  std::set<std::string> names;
  for (const auto& [name, value] : *named_a) names.insert(name);
  for (const auto& [name, value] : *named_b) names.insert(name);
  for (const auto& name : names) {
    const auto ia = named_a->find(name), ib = named_b->find(name);
    differences(ia == named_a->end() ? nullptr : ia->second, ib == named_b->end() ? nullptr : ib->second,
                member_path(at, name), out);
  }
  return true;
}

// The differences between two configurations (nullptr: absent), one "path: old in the folder, new
// now" line per value that differs. Objects and arrays are compared member by member, so a line
// names what changed rather than two dumps of a whole list cut at the same place.
void differences(const json* a, const json* b, const std::string& at, std::vector<std::string>& out) {
  if (a && b && *a == *b) return;
  if (a && b && a->is_object() && b->is_object()) {
    std::set<std::string> keys;
    for (auto it = a->begin(); it != a->end(); ++it) keys.insert(it.key());
    for (auto it = b->begin(); it != b->end(); ++it) keys.insert(it.key());
    for (const auto& k : keys)
      differences(a->contains(k) ? &(*a)[k] : nullptr, b->contains(k) ? &(*b)[k] : nullptr, member_path(at, k), out);
    return;
  }
  if (a && b && a->is_array() && b->is_array()) {
    if (differences_by_name(*a, *b, at, out)) return;
    for (size_t k = 0; k < std::max(a->size(), b->size()); ++k)
      differences(k < a->size() ? &(*a)[k] : nullptr, k < b->size() ? &(*b)[k] : nullptr,
                  at + "[" + std::to_string(k + 1) + "]", out);  // counted from 1, as in the Lua script
    return;
  }
  const std::string sa = a ? a->dump() : "", sb = b ? b->dump() : "";
  size_t first = 0;
  while (first < sa.size() && first < sb.size() && sa[first] == sb[first]) ++first;
  out.push_back(at + ": " + (a ? excerpt(sa, first) : "absent") + " in the folder, " + (b ? excerpt(sb, first) : "absent") +
                " now");
}

// Why the manifest's trial ids or training seeds are not the ones its configuration plans ("" when
// they are; when absent, "" unless `required`): a list edited by hand would make the report and a
// resumed run disagree with what the folder says it holds. Their types were checked on reading.
std::string planned_trials_problem(const json& m, const BatchPlan& plan, bool required) {
  if (!m.contains("trials") || !m.contains("seeds")) {
    if (!required) return "";  // a folder of the fuzz fixtures, made by hand without them
    return std::string("field \"") + (m.contains("trials") ? "seeds" : "trials") + "\" is missing";
  }
  std::vector<std::string> planned;
  for (const auto& p : plan.phases)
    for (const auto& t : p) planned.push_back(t.id);
  const json& listed = m["trials"];
  if (listed != json(planned)) {
    const std::set<std::string> in_plan(planned.begin(), planned.end());
    std::set<std::string> in_list;
    for (const auto& id : listed) in_list.insert(id.get<std::string>());
    std::vector<std::string> missing, extra;
    for (const auto& id : planned)
      if (!in_list.count(id)) missing.push_back(id);
    for (const auto& id : listed)
      if (!in_plan.count(id.get<std::string>())) extra.push_back(id.get<std::string>());
    std::string why = "field \"trials\" lists " + std::to_string(listed.size()) + " trial ids where the configuration plans " +
                      std::to_string(planned.size());
    if (!missing.empty()) why += "; missing: " + join_some(missing);
    if (!extra.empty()) why += "; not in the plan: " + join_some(extra);
    return missing.empty() && extra.empty() ? why + ", in another order or repeated" : why;
  }
  const json& seeds = m["seeds"];
  size_t training = 0;
  for (const auto& p : plan.phases)
    for (const auto& t : p) {
      if (!t.run) continue;
      ++training;
      const std::string plan_seed = std::to_string(t.seed) + " (the script's seed " + std::to_string(plan.script->seed) +
                                    " + trial " + std::to_string(t.index) + ")";
      if (!seeds.contains(t.id)) return "field \"seeds\" has no seed for trial " + t.id + "; the plan gives it " + plan_seed;
      if (seeds[t.id].get<uint64_t>() != t.seed)
        return "field \"seeds\" gives trial " + t.id + " seed " + seeds[t.id].dump() + ", but the plan gives it " + plan_seed;
    }
  if (seeds.size() != training)
    return "field \"seeds\" holds " + std::to_string(seeds.size()) + " seeds, and the plan has " + std::to_string(training) +
           " training trials";
  return "";
}

// The training trials of one run, every context.
std::vector<PlannedTrial> plan_run(const BatchScript& b, const BatchRun* r) {
  std::vector<PlannedTrial> phase;
  for (const auto& c : r->contexts)
    for (int i = 0; i < r->trials; ++i) {
      PlannedTrial t;
      t.id = batch_trial_id(r->name, c, i);
      t.run = r;
      t.context = c;
      t.index = i;
      t.seed = b.seed + uint64_t(i);
      phase.push_back(t);
    }
  return phase;
}

// The evaluation trials of every evaluation, one group per shape.
std::vector<PlannedTrial> plan_evaluations(const BatchScript& b) {
  std::vector<PlannedTrial> phase;
  for (const auto& e : b.evaluations)
    for (const auto& g : batch_eval_groups(e))
      for (int i = 0; i < e.trials; ++i) {
        PlannedTrial t;
        t.id = batch_eval_id(e.name, g, i);
        t.evaluation = &e;
        t.context = e.context;
        t.shape = g;
        t.index = i;
        t.seed = b.seed + uint64_t(i);
        phase.push_back(t);
      }
  return phase;
}

// Whether a selector chooses a trial.
bool matches(const PlannedTrial& t, const std::string& o) {
  if (t.run) return o == t.run->name || o == t.run->name + "/" + t.context;
  return o == "eval" || o == "eval/" + t.evaluation->name;
}

// The fields of a configuration that only the report reads: changing them trains nothing again.
constexpr const char* kReportFields[] = {"name", "description", "tables", "figures"};

// Whether an evaluation's trials keep their worlds whatever their number: with worlds of their
// own, shape k's trial i starts at (k * trials + i) * episodes (evaluation_seed_offset), so more
// trials would move the worlds of every shape after the first.
bool evaluation_worlds_keep(const json& e) {
  return e.value("worlds", std::string()) == "shared" || e.value("shapes", json::array()).size() <= 1;
}

// Whether configuration `now` plans every trial `old` planned, each the same: the two are equal
// but for the report's fields and for numbers of trials that grew (trial i of a run is a function
// of its id and the rest of the configuration, whatever the count: batch_trial_id, plan_run; an
// evaluation's only where evaluation_worlds_keep, unless `any_evaluation` pretends it always is).
bool extends(json old, json now, bool any_evaluation = false) {
  for (const char* field : kReportFields) old.erase(field), now.erase(field);
  const auto grow = [](json& o, const json& n) {
    if (o.is_object() && n.is_object() && o.contains("trials") && n.contains("trials") &&
        n["trials"].is_number_integer() && o["trials"].is_number_integer() && n["trials"] >= o["trials"])
      o["trials"] = n["trials"];
  };
  grow(old, now);
  for (const char* list : {"runs", "evaluations"})
    if (old.contains(list) && now.contains(list) && old[list].is_array() && now[list].is_array() &&
        old[list].size() == now[list].size())
      for (size_t k = 0; k < old[list].size(); ++k)
        if (std::string(list) == "runs" || any_evaluation || evaluation_worlds_keep(now[list][k]))
          grow(old[list][k], now[list][k]);
  return old == now;
}

// Where a configuration's files are, named so that a results folder survives a move: an absolute
// path under the project root is named relative to it ("curricula/paper.lua", as sources already
// are), one under the batch script's folder "<script folder>/pen.lua"; a relative path (an
// evaluation's scenario as written: "pen.lua") is first taken beside the script, as the loader
// takes it. What the files hold is compared by config["sources"], so a moved copy resumes and an
// edited one does not (docs/batch.md, Resuming).
// How a place under the batch script's folder begins (relocated_path).
const std::string kScriptFolder = "<script folder>/";

struct Places {
  fs::path root;           // the project root the configuration was made under
  fs::path script_dir;     // the batch script's folder (absolute)
  fs::path relative_base;  // where a relative path is looked for: this run's script folder
  // A file outside the project and the script's folder is named by its absolute path (a file shared
  // by labs, that stayed where it was), unless it is named here by its place from the script's
  // folder ("<script folder>/../worlds/room.lua"): both configurations have a file there, as when a
  // lab whose batch/, curricula and worlds sit side by side was moved or copied whole.
  std::set<std::string> moved_with_script;
  // When not null, receives each such file's place from the script's folder.
  std::set<std::string>* outside = nullptr;
};

std::string relocated_path(const std::string& value, const Places& at) {
  if (value.empty()) return value;
  fs::path p(value);
  std::error_code ec;
  if (p.is_relative()) {
    // A bare name ("cluttered") is a name, not a path; a relative path is the file beside the
    // script when there is one (resolve_scenario_near), else as spelt.
    if (value.find('/') == std::string::npos && p.extension() != ".lua") return value;
    if (at.relative_base.empty() || !fs::exists(at.relative_base / p, ec)) return value;
    return kScriptFolder + p.lexically_normal().generic_string();
  }
  p = p.lexically_normal();
  const auto under = [&](const fs::path& folder) -> std::optional<std::string> {
    if (folder.empty()) return std::nullopt;
    const fs::path rel = p.lexically_relative(folder);
    if (rel.empty() || *rel.begin() == "..") return std::nullopt;
    return rel.generic_string();
  };
  if (auto r = under(at.root)) return *r;
  if (auto r = under(at.script_dir)) return kScriptFolder + *r;
  // Sources are recorded by their real paths: the script folder through a link is the same.
  if (auto r = under(fs::weakly_canonical(at.script_dir, ec))) return kScriptFolder + *r;
  if (at.script_dir.empty()) return value;
  const std::string place = kScriptFolder + p.lexically_relative(at.script_dir).generic_string();
  if (at.outside) at.outside->insert(place);
  return at.moved_with_script.count(place) ? place : value;
}

// The project root a manifest's configuration was made under: the folder of which its curriculum
// file is the recorded source of the same relative name ("curricula/paper.lua" of the curriculum
// .../share/roger/curricula/paper.lua); else `fallback` (this project's).
fs::path recorded_root(const json& config, const fs::path& fallback) {
  if (!config.is_object() || !config.contains("sources") || !config["sources"].is_object()) return fallback;
  const std::string file = config.value("curriculum_file", std::string());
  for (auto it = config["sources"].begin(); it != config["sources"].end(); ++it) {
    const std::string& key = it.key();
    if (key[0] != '/' && source_names_path(key, file))
      return fs::path(file.substr(0, file.size() - key.size() - 1));
  }
  return fallback;
}

// `config` with its files named relative to the places it was made at (relocated_path): two
// configurations equal so are the same files' at the same places of their project and script
// folder, however they were spelt and wherever the two were.
json relocated(json config, const Places& at) {
  if (!config.is_object()) return config;
  if (config.contains("curriculum_file") && config["curriculum_file"].is_string()) {
    config["curriculum_file"] = relocated_path(config["curriculum_file"].get<std::string>(), at);
    config.erase("curriculum");  // as spelt ("paper", "curricula/paper.lua"): the file decides
  }
  for (const char* field : {"sources", "evaluation_sources"})
    if (config.contains(field) && config[field].is_object()) {
      json sources = json::object();
      for (auto it = config[field].begin(); it != config[field].end(); ++it)
        sources[it.key().empty() || it.key()[0] != '/' ? it.key() : relocated_path(it.key(), at)] = it.value();
      config[field] = sources;
    }
  for (const char* list : {"runs", "evaluations"})
    if (config.contains(list) && config[list].is_array())
      for (json& item : config[list])
        if (item.is_object() && item.contains("scenario") && item["scenario"].is_string())
          item["scenario"] = relocated_path(item["scenario"].get<std::string>(), at);
  return config;
}

// What changed when a folder is reopened with a configuration that extends its own: the report's
// fields, the numbers of trials, or both; for the note roger run prints, or, not `written`, roger
// run --dry-run (found by a probe: "The manifest now holds this script" of a dry run, which wrote
// nothing).
std::string extension_note(const json& old, const json& now, const std::string& out, bool written) {
  std::vector<std::string> changed;  // the report's fields that changed, as the docs name them
  for (const char* field : kReportFields)
    if (old.value(field, json()) != now.value(field, json()))
      changed.push_back(std::string(field) == "name" ? "its name" : "its " + std::string(field));
  const bool more = !extends(now, old);  // trials grew where the reverse does not extend
  std::string report;
  for (size_t k = 0; k < changed.size(); ++k)
    report += (k == 0 ? "" : k + 1 == changed.size() ? " and " : ", ") + changed[k];
  if (!report.empty()) report += " changed";
  const std::string what = !report.empty() && more ? report + " and it plans more trials"
                           : !report.empty()       ? report
                                                   : "it plans more trials";
  return "the script differs from the one " + out + " was made with, but only in what trains nothing again: " +
         what + (written ? ". The manifest now holds this script; the trials there are kept" +
                               std::string(more ? ", and the new ones run" : "")
                         : ". The run would write this script into the manifest and keep the trials there" +
                               std::string(more ? ", and run the new ones" : "")) + ".";
}

// For a folder whose configuration extends `config` (it holds more trials than `config` plans,
// as after a run with a larger --trials): how to resume it; "" otherwise.
std::string fewer_trials_hint(const json& old_config, const json& config) {
  // Any evaluation counts here: the folder holds more of its trials, whatever their worlds.
  if (!old_config.is_object() || !config.is_object() || !extends(config, old_config, true)) return "";
  std::set<int64_t> counts;  // the folder's trials of every run and evaluation (what --trials sets)
  for (const char* list : {"runs", "evaluations"})
    if (old_config.contains(list) && old_config[list].is_array())
      for (const json& item : old_config[list])
        if (item.is_object() && item.contains("trials") && item["trials"].is_number_integer())
          counts.insert(item["trials"].get<int64_t>());
  const std::string how = counts.size() == 1 ? "run the command with --trials " + std::to_string(*counts.begin()) +
                                                   ", the folder's number of trials"
                                             : "give the script's runs and evaluations the folder's numbers of trials";
  // Not "a larger --trials wrote it": the script's own trials may have been cut by --trials now
  // (found by a probe: `--trials 1` on a folder of the script's 2 blamed a --trials never given).
  return "\nThe folder's manifest plans more trials than this command does (it was made, or grown, with more "
         "trials than this command gives, whether or not those trials ran; a plan never shrinks): to resume it, " +
         how + ".";
}

// For a refusal where only the files' places differ: every Lua file holds what it held, but the
// curriculum was found elsewhere (a batch script's `curriculum` is looked for from the current
// folder first, so the same command from another folder can find another file of that name;
// found by a probe, told only "absent now" of files whose fingerprints were the same); "" else.
std::string same_contents_hint(const json& old_config, const json& config) {
  const auto fingerprints = [](const json& c) {
    std::multiset<std::string> out;
    if (c.is_object() && c.contains("sources") && c["sources"].is_object())
      for (const auto& [file, print] : c["sources"].items()) out.insert(print.dump());
    return out;
  };
  const std::string then = old_config.is_object() ? old_config.value("curriculum_file", std::string()) : "";
  const std::string now = config.value("curriculum_file", std::string());
  if (then == now || fingerprints(old_config).empty() || fingerprints(old_config) != fingerprints(config)) return "";
  return "\nEvery Lua file its trials read holds what it held (the same fingerprints), but other files: the "
         "curriculum was " + then + " then and is " + now + " now. A batch script's curriculum is looked for from "
         "the current folder first, then beside the script, then in the project, so another current folder or a "
         "copy of the script elsewhere (beside a copy of its curriculum) finds another file: run the folder's own "
         "script (manifest.json's script_file) from the folder the run was started in, or name the curriculum in "
         "the script by a path that depends on neither.";
}

// Whether two configurations differ in the fingerprints of the Lua files their trials read alone.
bool only_sources_differ(json a, json b) {
  for (const char* field : {"sources", "evaluation_sources"}) {
    if (a.is_object()) a.erase(field);
    if (b.is_object()) b.erase(field);
  }
  return a == b;
}

// The refusal of a folder made with configuration `old_config`, with the differences from
// `config` and what they mean.
Error refusal(const json& old, const json& old_config, const json& config, const BatchPlan& plan) {
  std::vector<std::string> lines;
  differences(&old_config, &config, "", lines);
  // What changes trials first, then the report's fields, which alone would have been taken.
  std::stable_partition(lines.begin(), lines.end(), [](const std::string& line) {
    for (const char* field : kReportFields)
      if (line.rfind(std::string(field) + ":", 0) == 0 || line.rfind(std::string(field) + "[", 0) == 0 ||
          line.rfind(std::string(field) + ".", 0) == 0)
        return false;
    return true;
  });
  std::string why;
  for (size_t k = 0; k < lines.size() && k < 12; ++k) why += "\n  " + lines[k];
  if (lines.size() > 12) why += "\n  ... and " + std::to_string(lines.size() - 12) + " more";
  // More trials of an evaluation whose worlds depend on their number: say why that one is refused.
  if (old_config.is_object() && extends(old_config, config, true))
    why += "\nMore trials of an evaluation with worlds of its own and several shapes move the worlds of the "
           "trials it has (shape k's trial i starts at (k x trials + i) x episodes), so they are a new folder's. "
           "More training trials alone resume: raise the trials of the runs in the script and give each such "
           "evaluation its own `trials`, the folder's number (one without takes the script's, and --trials "
           "sets both).";
  why += fewer_trials_hint(old_config, config);
  why += same_contents_hint(old_config, config);
  // Only a Lua file training reads changed: say that, not "another script" (a probe added a
  // comment to its curriculum and read the refusal as about another script).
  const bool sources_alone = only_sources_differ(old_config, config);
  // The same script file (the same path, or the same name in the same place after a move) with
  // other contents is not "another batch script".
  std::error_code ec;
  const std::string old_file = old.value("script_file", std::string());
  const bool same_script =
      !old_file.empty() && (fs::equivalent(old_file, plan.script->file, ec) ||
                            fs::path(old_file).filename() == fs::path(plan.script->file).filename());
  const std::string made = sources_alone
                               ? "before a Lua file its trials read changed (its trials and new ones would mix two "
                                 "versions of it)"
                           : same_script ? "by this batch script as it was then, with other contents or other "
                                           "parameters (a command's --set, --trials, --lua-instructions and --lua-memory are parameters too)"
                                         : "by another batch script or other parameters";
  // Where only a Lua file changed, the script and parameters are the same: what resumes is the file
  // as it was (found by a probe: "run it with the script it was made with", which it was).
  const std::string advice =
      sources_alone
          ? "\nTo resume the folder, put the files listed back as they were (its trials were made with them); for "
            "the files as they are now, give another --out."
          : "\nTo resume the folder, run it with the script and parameters it was made with (its manifest.json "
            "records them); for this configuration, give another --out.";
  return Error("the results folder " + plan.out + " (of " + old.value("script", std::string("?")) + ") was made " +
               made + "; it cannot be resumed with " + plan.script->path + " as it is now. Differences:" + why + advice);
}

// Takes a configuration that extends the folder's own (extends()): checks that the folder's
// trials are the ones its configuration planned, as when resuming, and rewrites the manifest.
// Returns the note saying what changed.
std::string extend_manifest(const json& old, const json& old_config, const json& old_places, const json& now_places,
                            const BatchPlan& plan, const fs::path& manifest_path, const json& fresh_manifest,
                            bool write) {
  BatchPlan old_plan;
  try {
    old_plan = plan_batch(std::make_shared<BatchScript>(batch_config_from_json(old_config)), plan.out);
  } catch (const std::exception& e) {
    throw Error(manifest_path.string() + ": field \"config\": " + e.what() +
                "; this folder cannot be resumed: use another --out");
  }
  if (const std::string p = planned_trials_problem(old, old_plan, true); !p.empty())
    throw Error(manifest_path.string() + ": " + p + "; this folder cannot be resumed: use another --out");
  if (write) write_file_atomic(manifest_path.string(), fresh_manifest.dump(1) + "\n", "cannot write the manifest");
  return extension_note(old_places, now_places, plan.out, write);  // a dry run's says what the run would do
}

// A plan that changes (more trials, another report) rewrites the manifest: not while other parts
// of the folder run the old one, whose shards would end "done" by it and leave the new trials to
// no one (the report then fails, and its advice is refused).
void refuse_while_others_run(const BatchPlan& plan, const RunningClaim* claim) {
  const std::vector<std::string> others = claim ? claim->others_running() : std::vector<std::string>();
  if (others.empty()) return;
  std::string list;
  for (size_t k = 0; k < others.size() && k < 5; ++k) list += (k ? ", " : "") + others[k];
  if (others.size() > 5) list += " and " + std::to_string(others.size() - 5) + " more";
  throw Error("the script differs from the one " + plan.out + " was made with (it plans more trials or another "
              "report), and other parts of the folder are running the folder's plan: " + list +
              ". Wait for them to end, then run this command again; or run it with the folder's script and "
              "parameters now");
}

// Why the folder's finished trials cannot be resumed with: a Lua file a trial read that the
// configuration's sources do not list (a module a callback required while episodes ran, after the
// curriculum was loaded) and that has changed or gone since; "" when none has. `then` places the
// files as the folder's configuration named them.
std::string late_source_problem(const BatchPlan& plan, const json& old_config, const Places& then) {
  std::set<std::string> listed;  // compared with the configuration already
  for (const char* field : {"sources", "evaluation_sources"})
    if (old_config.is_object() && old_config.contains(field) && old_config[field].is_object())
      for (const auto& [name, print] : old_config[field].items()) listed.insert(name);
  std::set<std::string> seen;
  for (const auto& phase : plan.phases)
    for (const auto& t : phase) {
      const fs::path file = fs::path(plan.out) / "trials" / t.id / "result.json";
      std::error_code ec;
      if (!fs::is_regular_file(file, ec)) continue;
      json r;
      try {
        r = read_json_file(file.string());
      } catch (const std::exception&) {
        continue;  // the trial is corrupt and runs again (trial_status)
      }
      if (!r.is_object() || !r.contains("sources") || !r["sources"].is_object()) continue;
      for (const auto& [name, print] : r["sources"].items()) {
        if (listed.count(name) || !seen.insert(name).second || !print.is_string()) continue;
        std::string place = name.empty() || name[0] != '/' ? name : relocated_path(name, then);
        if (place.rfind(kScriptFolder, 0) == 0) place = (then.relative_base / place.substr(kScriptFolder.size())).string();
        const fs::path path = source_file_path(place);
        const bool gone = !fs::is_regular_file(path, ec);
        if (!gone && fingerprint(read_file_text(path.string())) == print.get<std::string>()) continue;
        const std::string it = path.string() == name ? "it" : path.string();
        return "trial " + t.id + " required " + name + " while it ran (a require inside a function the episodes "
               "call, which the list of sources made when the run started could not hold), and " + it +
               (gone ? " is gone" : " has changed since") + ": resuming would mix two versions of it in one folder. "
               "Put the file back as it was, or use another --out.";
      }
    }
  return "";
}

// Whether no trial of the plan has a result in its folder, each failed or not run: a Lua file
// changed since then made nothing there (found by a probe: after a reward that looped failed every
// trial, the fixed reward was refused the folder, "its trials and new ones would mix two versions").
bool holds_no_result(const BatchPlan& plan) {
  for (const auto& phase : plan.phases)
    for (const auto& t : phase) {
      json result;
      std::string problem;
      if (trial_status(plan.out, t, result, problem) == "ok") return false;
    }
  return true;
}

// Checks that an existing manifest was made by this engine and configuration, or by one that this
// configuration extends (extends(): then the manifest is rewritten with it, unless `write` is false,
// and the returned note says what changed; "" otherwise), or whose Lua files alone changed while no
// trial there has a result (rewritten the same way, and said so).
std::string check_manifest(const BatchPlan& plan, const fs::path& manifest_path, json config,
                           const json& fresh_manifest, const RunningClaim* claim, bool write = true) {
  json old;
  try {
    old = read_manifest_file(manifest_path.string());
  } catch (const std::exception& e) {
    throw Error(std::string(e.what()) + "; this folder cannot be resumed: use another --out");
  }
  const std::string& out = plan.out;
  const std::string old_engine = old.value("engine", std::string());
  if (old_engine != ROGER_ENGINE_FINGERPRINT)
    throw Error("the results folder " + out + " was made by " +
                (old_engine.empty() ? std::string("a roger that did not record its engine")
                                    : "another build of the engine (engine " + old_engine + ")") +
                ", and this roger's engine is " + ROGER_ENGINE_FINGERPRINT +
                ": its trials would mix with this build's. Use another --out, or remove the folder "
                "to start over; `roger report " + out + "` still reports what it holds.");
  const json old_config = old.value("config", json());
  // A folder made before evaluations' files were recorded is compared by what it recorded.
  if (old_config.is_object() && !old_config.contains("evaluation_sources")) config.erase("evaluation_sources");
  // Compared by where the files are in their project and script folder, not by how their paths
  // were spelt: the folder resumes from another working folder, or after the project, the
  // install or both were moved or copied (relocated()).
  std::error_code ec;
  const fs::path here = fs::weakly_canonical(project_root(), ec);
  const std::string old_file = old.value("script_file", std::string());
  const fs::path script_dir = fs::absolute(plan.script->file).lexically_normal().parent_path();
  Places then{recorded_root(old_config, here),
               old_file.empty() ? fs::path() : fs::path(old_file).lexically_normal().parent_path(), script_dir,
               {}, nullptr};
  Places now{recorded_root(config, here), script_dir, script_dir, {}, nullptr};
  // The files outside the project and the script's folder at the same place from it in both.
  std::set<std::string> outside_then, outside_now;
  then.outside = &outside_then, now.outside = &outside_now;
  relocated(old_config, then), relocated(config, now);
  std::set_intersection(outside_then.begin(), outside_then.end(), outside_now.begin(), outside_now.end(),
                        std::inserter(now.moved_with_script, now.moved_with_script.end()));
  then.moved_with_script = now.moved_with_script;
  then.outside = now.outside = nullptr;
  const json old_places = relocated(old_config, then), now_places = relocated(config, now);
  if (old_places == now_places || (old_config.is_object() && extends(old_places, now_places)))
    if (const std::string p = late_source_problem(plan, old_config, then); !p.empty())
      throw Error("the results folder " + out + " cannot be resumed: " + p);
  if (old_places != now_places && old_config.is_object() && extends(old_places, now_places)) {
    refuse_while_others_run(plan, claim);
    return extend_manifest(old, old_config, old_places, now_places, plan, manifest_path, fresh_manifest, write);
  }
  if (old_places != now_places && only_sources_differ(old_places, now_places) && holds_no_result(plan)) {
    refuse_while_others_run(plan, claim);
    if (write) write_file_atomic(manifest_path.string(), fresh_manifest.dump(1) + "\n", "cannot write the manifest");
    return "a Lua file its trials read changed since " + out + " was made, but no trial there has a result (each "
           "failed or never ran), so nothing mixes two versions: " +
           (write ? "the manifest now records the files as they are, and every trial runs"
                  : "the run would record the files as they are in the manifest, and run every trial");
  }
  if (old_places != now_places) throw refusal(old, old_places, now_places, plan);
  if (const std::string p = planned_trials_problem(old, plan, true); !p.empty())
    throw Error(manifest_path.string() + ": " + p + "; this folder cannot be resumed: use another --out");
  return "";
}


// Why the results folder `out` could not be made. ENOENT from a folder whose parent exists (/proc,
// /sys) is not "a folder on that path does not exist" (file_error_line's advice): that file
// system makes no folder there, so the advice is another place.
FileError folder_creation_error(const std::string& out, const std::error_code& ec) {
  std::error_code ignored;
  fs::path parent = fs::absolute(out, ignored).lexically_normal().parent_path();
  while (!parent.empty() && parent != parent.root_path() && !fs::exists(parent, ignored)) parent = parent.parent_path();
  if (ec.value() != ENOENT || !fs::is_directory(parent, ignored) || parent == parent.root_path())
    return FileError("cannot create the results folder '" + out + "': " + ec.message(), out, ec.value());
  return FileError("cannot create the results folder '" + out + "': '" + parent.string() + "' exists, but its file "
                   "system makes no folder there (" + ec.message() + "); give --out a folder on a disk", out, EINVAL);
}

// A lock file of the results folder `out` (made if need be), opened.
int open_lock_file(const std::string& out, const std::string& name) {
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw folder_creation_error(out, ec);
  const std::string path = (fs::path(out) / name).string();
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
  if (fd < 0) {
    const int err = errno;
    throw FileError("cannot open '" + path + "': " + std::strerror(err), path, err);
  }
  return fd;
}

// An exclusive lock on a results folder (flock on <out>/.lock), held while it lives: shards that
// start together open the folder one at a time.
class FolderLock {
 public:
  explicit FolderLock(const std::string& out) {
    fd_ = open_lock_file(out, ".lock");
    const std::string path = (fs::path(out) / ".lock").string();
    while (::flock(fd_, LOCK_EX) != 0)
      if (errno != EINTR) {
        const int err = errno;
        ::close(fd_);
        throw Error("cannot lock '" + path + "': " + std::strerror(err));
      }
  }
  ~FolderLock() { ::close(fd_); }  // closing releases the lock
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  int fd_ = -1;
};

// flock(fd, op) without waiting: false when another holds the file.
bool try_flock(int fd, int op, const std::string& path) {
  while (::flock(fd, op | LOCK_NB) != 0) {
    if (errno == EWOULDBLOCK) return false;
    if (errno != EINTR) throw Error("cannot lock '" + path + "': " + std::strerror(errno));
  }
  return true;
}

// This process's id and host, in the claim file `fd` (for the message of a run refused: shards of
// a cluster run on other machines), then `part` (a part's line for the other parts, part_line()).
void write_holder(int fd, const std::string& part = "") {
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  const std::string text = "pid " + std::to_string(::getpid()) + " " + host + "\n" + part;
  if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, text.data(), text.size(), 0) != ssize_t(text.size())) {
    // Only a message reads it: a claim without it still holds.
  }
}

// " (pid N on HOST)" from a claim file, or "" when it names none.
std::string holder_of(const std::string& path) {
  std::ifstream in(path);
  std::string word, pid, host;
  if (!(in >> word >> pid) || word != "pid") return "";
  return " (pid " + pid + (in >> host ? " on " + host : "") + ")";
}

// A non-negative integer from an environment variable, or -1 when unset; throws when malformed.
long env_count(const char* name) {
  const char* v = std::getenv(name);
  if (!v) return -1;
  char* end = nullptr;
  errno = 0;
  const long n = std::strtol(v, &end, 10);
  if (errno || end == v || *end || n < 0)
    throw Error(std::string("--shard slurm: ") + name + "='" + v + "' is not " +
                (std::string(name) == "SLURM_ARRAY_TASK_ID" ? "an index (a whole number from 0)" : "a count (a whole number)"));
  return n;
}

// The variable --shard slurm takes N from: ROGER_SHARDS, set by submit.sh to the run's N (an
// array resubmitted in part has fewer tasks), else the array's size; nullptr when neither is set.
const char* shard_count_variable() {
  if (std::getenv("ROGER_SHARDS")) return "ROGER_SHARDS";
  return std::getenv("SLURM_ARRAY_TASK_COUNT") ? "SLURM_ARRAY_TASK_COUNT" : nullptr;
}

// --shard slurm: K from the array task's id, N from shard_count_variable(); each refusal names the
// variable that is missing or wrong, since the job's environment is all the user can change.
Shard slurm_shard() {
  const long id = env_count("SLURM_ARRAY_TASK_ID");
  const char* count_name = shard_count_variable();
  const long count = count_name ? env_count(count_name) : -1;
  if (id < 0 && count < 0)
    throw Error("--shard slurm: SLURM_ARRAY_TASK_ID and SLURM_ARRAY_TASK_COUNT are not set: run it inside a "
                "Slurm job array (sbatch --array=0-(N-1)), or give --shard K/N");
  if (id < 0)
    throw Error(std::string("--shard slurm: SLURM_ARRAY_TASK_ID is not set (") + count_name + "=" +
                std::to_string(count) + " is): run it inside a Slurm job array (sbatch --array=0-(N-1)), or give "
                "--shard K/N");
  if (count < 0)
    throw Error("--shard slurm: SLURM_ARRAY_TASK_ID is set (" + std::to_string(id) +
                ") but neither ROGER_SHARDS nor SLURM_ARRAY_TASK_COUNT is: set ROGER_SHARDS to the run's number "
                "of shards N, or give --shard " + std::to_string(id) + "/N");
  if (count < 1)
    throw Error(std::string("--shard slurm: ") + count_name + " must be at least 1 (the run's number of shards N), and "
                "it is 0: set ROGER_SHARDS to the N the array was submitted with (submit.sh sets it)");
  if (id >= count)
    throw Error("--shard slurm: array task " + std::to_string(id) + " is not below the shard count " +
                std::to_string(count) + " (" + count_name + "); submit the array as --array=0-" +
                std::to_string(count - 1) + ", or set ROGER_SHARDS=N when resubmitting single tasks of an N-shard run");
  Shard s;
  s.index = int(id);
  s.count = int(count);
  s.slurm = true;
  return s;
}

// The records of the shards that ran in a folder (<out>/shards/K-of-N.json): their file names, by N.
std::map<int, std::vector<std::string>> shard_records(const std::string& out) {
  std::error_code ec;
  std::map<int, std::vector<std::string>> records;
  for (const auto& e : fs::directory_iterator(fs::path(out) / "shards", ec)) {
    const std::string name = e.path().filename().string();
    int k = 0, n = 0;
    if (std::sscanf(name.c_str(), "%d-of-%d.json", &k, &n) == 2) records[n].push_back(name);
  }
  for (auto& [n, names] : records) std::sort(names.begin(), names.end());
  return records;
}

// The shard count recorded by the shards that ran in a folder, or 0.
int recorded_shard_count(const std::string& out) {
  const auto records = shard_records(out);
  return records.empty() ? 0 : records.rbegin()->first;
}

// Refuses a shard whose N is not the N of the shards recorded in the folder: two counts split the
// trials differently (i mod 3, i mod 2), so shards of both can run one trial at once, each writing
// its files. A run without --shard is not refused: it runs what is left by itself.
void check_shard_count(const std::string& out, const Shard& shard) {
  for (const auto& [n, names] : shard_records(out)) {
    if (n == shard.count) continue;
    const std::string recorded = std::to_string(n);
    throw Error("the results folder " + out + " holds shards of N = " + recorded + " (shards/" +
                join_some(names) + "), and this is shard " + std::to_string(shard.index) + " of " +
                std::to_string(shard.count) + ": shards of two counts split the trials differently and can run one "
                "trial at once. Keep N = " + recorded + " (--shard K/" + recorded + "; ROGER_SHARDS=" + recorded +
                " or submit.sh SCRIPT " + recorded + " for --shard slurm), or give another --out for a run of N = " +
                std::to_string(shard.count) + "; roger run without --shard finishes this folder by itself.");
  }
}

// The line of a shard that owns no trial: N is larger than the number of trials of every run and
// evaluation (`most`), which a Slurm array of too many tasks makes. It still runs, and succeeds.
std::string idle_shard(const BatchPlan& plan, const Shard& shard, int most) {
  const std::string n = std::to_string(shard.count), last = std::to_string(most - 1);
  const std::string which = most == 1   ? " (index 0), so only shard 0 has trials"
                            : most == 2 ? "s (indices 0 and 1), so only shards 0 and 1 have trials"
                                        : "s (indices 0 to " + last + "), so only shards 0 to " + last + " have trials";
  return "shard " + std::to_string(shard.index) + " of " + n + " has no trial to run: shard K runs the trials of "
         "index i with i mod " + n + " = K, and the runs and evaluations of " + plan.script->path + " have at most " +
         std::to_string(most) + " trial" + which + ". It ends at once; with " + std::to_string(most) + " shard" +
         (most == 1 ? "" : "s") + " or fewer, none is idle.";
}

}  // namespace

namespace batch_detail {

// The Lua files training with a curriculum reads (docs/batch.md), each with its fingerprint, named
// relative to the project when inside it: a results folder is resumed only while none changed.
json source_fingerprints(const std::vector<fs::path>& files) {
  const fs::path root = fs::weakly_canonical(project_root());
  json out = json::object();
  for (const fs::path& f : files) {
    const fs::path rel = f.lexically_relative(root);
    const bool inside = !rel.empty() && *rel.begin() != "..";
    out[inside ? rel.generic_string() : f.generic_string()] = fingerprint(read_file_text(f.string()));
  }
  return out;
}

bool source_names_path(const std::string& key, const std::string& path) {
  return !key.empty() && path.size() > key.size() + 1 && path.compare(path.size() - key.size(), key.size(), key) == 0 &&
         path[path.size() - key.size() - 1] == '/';
}

json policy_fingerprints(const std::string& out, const std::vector<std::string>& names) {
  json prints = json::object();
  for (const std::string& name : names) prints[name] = fingerprint(read_file_text((fs::path(out) / name).string()));
  return prints;
}

fs::path source_file_path(const std::string& name) {
  const fs::path p(name);
  return p.is_absolute() ? p : fs::weakly_canonical(project_root()) / p;
}

std::vector<std::string> evaluation_scenarios(const BatchScript& b) {
  std::vector<std::string> names;
  for (const BatchEvaluation& e : b.evaluations)
    if (!e.scenario.empty()) names.push_back(e.scenario);
  return names;
}

std::vector<fs::path> evaluation_source_files(const std::vector<std::string>& scenarios,
                                              const std::vector<fs::path>& training, const SandboxLimits& limits) {
  std::vector<fs::path> files;
  for (const std::string& name : std::set<std::string>(scenarios.begin(), scenarios.end())) {
    Scenario scenario = Scenario::load(name, limits);  // alive while its list is read
    for (const fs::path& f : scenario.sandbox().source_files())
      if (std::find(training.begin(), training.end(), f) == training.end() &&
          std::find(files.begin(), files.end(), f) == files.end())
        files.push_back(f);
  }
  return files;
}

SourceWatch::SourceWatch(const std::string& curriculum_file, const SandboxLimits& limits,
                         const std::vector<std::string>& evaluation_scenarios) {
  std::vector<fs::path> files = curriculum_source_files(Curriculum::load(curriculum_file, limits), limits);
  for (const fs::path& f : evaluation_source_files(evaluation_scenarios, files, limits)) files.push_back(f);
  for (const fs::path& f : files) files_.emplace_back(f.string(), fingerprint(read_file_text(f.string())));
}

void SourceWatch::learn(const json& sources) {
  if (!sources.is_object()) return;
  const std::lock_guard<std::mutex> hold(mutex_);
  for (const auto& [name, print] : sources.items()) {
    const std::string path = source_file_path(name).string();
    if (!print.is_string() || std::any_of(files_.begin(), files_.end(), [&](const auto& f) { return f.first == path; }))
      continue;
    files_.emplace_back(path, print.get<std::string>());
  }
}

void SourceWatch::check() const {
  std::vector<std::pair<std::string, std::string>> files;
  {
    const std::lock_guard<std::mutex> hold(mutex_);
    files = files_;
  }
  for (const auto& [path, print] : files) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec))
      throw FileError("cannot read '" + path + "': it was removed while the run was using it", path, ENOENT);
    if (fingerprint(read_file_text(path)) != print)
      throw FileError("'" + path + "' changed while the run was using it", path, 0);
  }
}

std::string first_line(const std::string& s) {
  const size_t nl = s.find('\n');
  return nl == std::string::npos ? s : s.substr(0, nl);
}

const char* shard_state_name(ShardState state) {
  switch (state) {
    case ShardState::running: return "running";
    case ShardState::ended: return "ended";
    case ShardState::interrupted: return "interrupted";
  }
  return "unknown";
}

json ShardBoard::read(const BatchPlan& plan, int count) {
  json board = json::array();
  if (count < 1) return board;
  std::vector<int> owned(size_t(count), 0);
  for (const auto& p : plan.phases)
    for (const auto& t : p) ++owned[size_t(t.index % count)];
  for (int k = 0; k < count; ++k) {
    Shard shard;
    shard.index = k;
    shard.count = count;
    const fs::path path = shard.record_path(plan.out);
    std::error_code ec;
    const auto changed = fs::last_write_time(path, ec);
    const auto size = ec ? std::uintmax_t(0) : fs::file_size(path, ec);
    if (ec) {
      seen_.erase(k);
      board.push_back({{"state", "not started"}, {"trials", owned[size_t(k)]}});
      continue;
    }
    const auto it = seen_.find(k);
    if (it == seen_.end() || it->second.changed != changed || it->second.size != size) {
      json entry = {{"state", "unknown"}};
      try {
        const json record = parse_json(read_file_text(path.string()));
        if (record.is_object() && record.value("state", json()).is_string())
          entry = {{"state", record["state"]}, {"pending", record.value("pending", json())}};
      } catch (const std::exception&) {
        // written whole (write_file_atomic), so only another program's file: "unknown"
      }
      entry["trials"] = owned[size_t(k)];
      seen_[k] = Seen{changed, size, entry};
    }
    board.push_back(seen_[k].entry);
  }
  return board;
}

// A shard's own outcome, in <out>/shards/K-of-N.json (no other shard writes that file): the
// trials it owns, which failed, how many it has not run yet, and its state.
BatchSummary record_shard(const BatchPlan& plan, const Shard& shard, ShardState state) {
  BatchSummary s;
  json failed = json::array();
  for (const auto& p : plan.phases)
    for (const auto& t : p) {
      if (!shard.owns(t)) continue;
      ++s.trials;
      json result;
      std::string error;
      const std::string status = trial_status(plan.out, t, result, error);
      if (status == "pending") ++s.pending, s.pending_ids.push_back(t.id);
      if (status == "corrupt") s.corrupt.push_back(t.id + ": " + first_line(error));
      if (status != "failed") continue;
      s.failed.push_back(t.id + ": " + first_line(error));
      failed.push_back(t.id);
    }
  const json record = {{"shard", shard.index}, {"shards", shard.count}, {"trials", s.trials},
                       {"failed", failed},     {"pending", s.pending},   {"state", shard_state_name(state)},
                       {"slurm", shard.slurm}};
  write_file_atomic(shard.record_path(plan.out), record.dump(1) + "\n", "cannot write the shard's record");
  return s;
}

}  // namespace batch_detail

json read_manifest(const std::string& dir) {
  const fs::path manifest_path = fs::path(dir) / "manifest.json";
  std::error_code ec;
  if (!fs::is_regular_file(manifest_path, ec))
    throw Error(!fs::exists(dir, ec)        ? "no results folder '" + dir + "': nothing is there"
                : !fs::is_directory(dir, ec) ? "'" + dir + "' is a file, not a results folder of roger run"
                                             : "'" + dir + "' is not a results folder of roger run: it has no manifest.json");
  // The checked reader (records.cpp): an object with its format, engine, script, version, the
  // types of its config's fields and of its trials' ids and seeds.
  return read_manifest_file(manifest_path.string());
}

BatchPlan read_results_plan(const std::string& dir) {
  const json manifest = read_manifest(dir);
  std::shared_ptr<BatchScript> script;
  try {
    script = std::make_shared<BatchScript>(batch_config_from_json(manifest["config"]));
  } catch (const std::exception& e) {
    throw Error((fs::path(dir) / "manifest.json").string() + ": field \"config\": " + json_error_text(e.what()));
  }
  script->path = manifest["script"].get<std::string>();
  if (manifest.contains("script_file") && manifest["script_file"].is_string())
    script->file = manifest["script_file"].get<std::string>();  // where it was: `path` is as it was typed
  BatchPlan plan = plan_batch(std::move(script), dir);
  if (const std::string p = planned_trials_problem(manifest, plan, false); !p.empty())
    throw Error((fs::path(dir) / "manifest.json").string() + ": " + p);
  return plan;
}

Shard parse_shard(const std::string& text) {
  if (text == "slurm") return slurm_shard();
  Shard s;
  int k = -1, n = -1;
  char rest = 0;
  // Digits only: sscanf took " 1/3" and "1/+3" (found by a probe).
  if (!std::regex_match(text, std::regex("[0-9]{1,9}/[0-9]{1,9}")) ||
      std::sscanf(text.c_str(), "%d/%d%c", &k, &n, &rest) != 2 || n < 1 || k < 0 || k >= n)
    throw Error("--shard '" + text + "': expected K/N with 0 <= K < N (e.g. 0/4), or slurm");
  s.index = k;
  s.count = n;
  return s;
}

std::vector<MissingTrial> missing_trials(const BatchPlan& plan) {
  const int shards = recorded_shard_count(plan.out);
  std::vector<MissingTrial> out;
  for (const auto& p : plan.phases)
    for (const auto& t : p) {
      json result;
      std::string problem;
      const std::string status = trial_status(plan.out, t, result, problem);
      if (status == "ok" || status == "failed") continue;
      MissingTrial m;
      m.trial = &t;
      if (status == "corrupt") m.problem = problem;
      if (shards > 0) m.owner = "shard " + std::to_string(t.index % shards) + " of " + std::to_string(shards);
      out.push_back(m);
    }
  return out;
}

BatchPlan plan_batch(std::shared_ptr<const BatchScript> script, const std::string& out) {
  const BatchScript& b = *script;
  BatchPlan plan;
  plan.script = std::move(script);
  plan.out = out;
  // Runs that take no skills share the first phase; a run that takes skills joins the phase after
  // the last of the runs it takes them from (ordered_runs puts those first). A phase per run
  // instead left cores idle at the end of each, though the runs did not wait for each other.
  std::map<std::string, size_t> phase_of;
  for (const BatchRun* r : b.ordered_runs()) {
    size_t k = 0;
    for (const auto& s : r->skills) k = std::max(k, phase_of.at(s.run) + 1);
    phase_of[r->name] = k;
    if (plan.phases.size() <= k) plan.phases.resize(k + 1);
    const std::vector<PlannedTrial> trials = plan_run(b, r);
    plan.phases[k].insert(plan.phases[k].end(), trials.begin(), trials.end());
  }
  std::vector<PlannedTrial> evaluations = plan_evaluations(b);
  if (!evaluations.empty()) plan.phases.push_back(std::move(evaluations));
  return plan;
}

bool trial_selected(const PlannedTrial& t, const std::vector<std::string>& only) {
  if (only.empty()) return true;
  for (const auto& o : only)
    if (matches(t, o)) return true;
  return false;
}

void check_selectors(const BatchPlan& plan, const std::vector<std::string>& only) {
  const BatchScript& b = *plan.script;
  for (const auto& o : only) {
    bool any = false;
    for (const auto& p : plan.phases)
      for (const auto& t : p) any = any || matches(t, o);
    if (!any) {
      // Each run with its contexts (SG/DC1, SG/DC2), so a misspelt context is seen at once.
      std::vector<std::string> names;
      for (const auto& r : b.runs) {
        std::vector<std::string> contexts;
        for (const auto& p : plan.phases)
          for (const auto& t : p)
            if (t.run == &r && std::find(contexts.begin(), contexts.end(), t.context) == contexts.end())
              contexts.push_back(t.context);
        names.push_back(r.name + (contexts.empty() ? "" : " (" + join(contexts, ", ") + ")"));
      }
      for (const auto& e : b.evaluations) names.push_back("eval/" + e.name);
      throw Error("--only '" + o + "' names no run, run/context or eval/evaluation of " + b.path + " (they are: " +
                  join(names, "; ") + ")");
    }
  }
}

namespace {

// The trials whose policies trial t loads: the runs its skills come from (a training trial), or the
// policy it evaluates and its skills' (an evaluation), each of t's index.
std::vector<std::string> policy_sources(const PlannedTrial& t) {
  std::vector<std::string> ids;
  const auto& skills = t.run ? t.run->skills : t.evaluation->skills;
  if (t.evaluation) ids.push_back(batch_trial_id(t.evaluation->run, t.evaluation->context, t.index));
  for (const BatchSkill& s : skills) ids.push_back(batch_trial_id(s.run, s.context, t.index));
  return ids;
}

}  // namespace

void check_only_needs(const BatchPlan& plan, const std::vector<std::string>& only, const Shard& shard) {
  if (only.empty()) return;
  std::map<std::string, const PlannedTrial*> by_id;
  for (const auto& p : plan.phases)
    for (const auto& t : p) by_id[t.id] = &t;
  std::map<std::string, bool> known;  // each trial's records read once: many evaluations share a source
  const auto finished = [&](const PlannedTrial& t) {
    const auto [at, added] = known.emplace(t.id, false);
    if (added) {
      json result;
      std::string error;
      at->second = trial_status(plan.out, t, result, error) == "ok";
    }
    return at->second;
  };
  std::vector<std::string> needed, needing, runs;
  // Adds the sources of trial t that neither --only selects nor have a result; true if any.
  const auto need_sources_of = [&](const PlannedTrial& t) {
    bool any = false;
    for (const std::string& id : policy_sources(t)) {
      const auto it = by_id.find(id);
      if (it == by_id.end() || trial_selected(*it->second, only) || finished(*it->second)) continue;
      any = true;
      if (std::find(needed.begin(), needed.end(), id) == needed.end()) needed.push_back(id);
      const std::string run = id.substr(0, id.rfind('/'));
      if (std::find(runs.begin(), runs.end(), run) == runs.end()) runs.push_back(run);
    }
    return any;
  };
  for (const auto& p : plan.phases)
    for (const auto& t : p)
      if (shard.owns(t) && trial_selected(t, only) && !finished(t) && need_sources_of(t)) needing.push_back(t.id);
  // And what those need in turn (found by a probe: the advice to add --only T/DC6 was refused
  // again for T/DC6's own skill, SG/DC2).
  const size_t direct = needed.size();
  for (size_t k = 0; k < needed.size(); ++k) need_sources_of(*by_id.at(needed[k]));
  if (needed.empty()) return;
  const std::vector<std::string> first(needed.begin(), needed.begin() + long(direct)),
      then(needed.begin() + long(direct), needed.end());
  throw Error("--only " + join(only, " --only ") + ": its trials need the policies of trials outside it that have " +
              "no result yet (not run, or failed): " + join_some(first) + ", for " + join_some(needing) +
              (then.empty() ? std::string() : "; and those need " + join_some(then)) +
              ". Nothing was run: add --only " + join(runs, " --only ") + " to this command, or run " +
              (runs.size() == 1 ? "it" : "those") + " first");
}

namespace {

// Removes the hidden temporaries a killed writer left at the top of results folder `out`
// (write_file_atomic's .NAME.tmpPID-N-R, StagedFiles' .stagedPID-N-R.tmp, PLplot's
// .roger-plot-PID-N-R.tmp): called only by a run that holds the folder alone, when no writer can
// be at work. Best effort: one that cannot be removed is left, as before.
void remove_stale_temporaries(const std::string& out) {
  static const std::regex plot_temporary(R"(\.roger-plot-[0-9]+-[0-9]+-[0-9]+\.tmp)");
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(out, ec)) {
    const std::string name = entry.path().filename().string();
    if (is_writer_leftover(name) || std::regex_match(name, plot_temporary)) fs::remove_all(entry.path(), ec);
  }
}

// Whether a file at the top of a folder without a manifest can be a run's that is starting beside
// this one (its lock files: .lock, .running, .running-<part>), a temporary a killed one left, or
// the Slurm logs' folder scripts/slurm/submit.sh makes there before its shards start.
bool starting_run_file(const std::string& name, bool folder) {
  static const std::regex temporary(R"(\..+\.tmp[0-9]+-[0-9]+-[0-9]+)");
  return name == ".lock" || name == ".running" || name.rfind(".running-", 0) == 0 || std::regex_match(name, temporary) ||
         (folder && name == "slurm");
}

// The error for a folder that holds `names` (sorted) and no manifest.json (check_out_folder).
Error foreign_folder_error(const std::string& out, const std::vector<std::string>& names) {
  const auto has = [&](const char* n) { return std::binary_search(names.begin(), names.end(), std::string(n)); };
  const bool propose = has("settings.json") || has("proposal.lua");
  if (!propose && (has("trials/") || has("summary.csv") || has("shards/") || has("status.json")))
    return Error("the folder '" + out + "' holds results of roger run (" + join_some(names) +
                 ") but no manifest.json, so nothing tells which script and parameters made them, and the trials "
                 "of this run would mix with them. Move them aside (or put back the folder's manifest.json), or "
                 "give another --out");
  return Error("the folder '" + out + "' is not a results folder of roger run (it has no manifest.json)" +
               (propose ? ", it is one of roger propose," : "") + " and is not empty: it holds " + join_some(names) +
               ". roger run would write its trials, report and dashboard (index.html, tables.md) over or among "
               "them: give --out a new or empty folder");
}

// A part's --only names as its claim knows them: sorted, each once.
std::vector<std::string> part_names(std::vector<std::string> only) {
  std::sort(only.begin(), only.end());
  only.erase(std::unique(only.begin(), only.end()), only.end());
  return only;
}

// The part of a results folder a run claims: its shard and its --only names ("--shard 0/2 --only
// SG"), and the claim file's name for it (".running-shard-0-of-2-only-SG"); "" for the whole.
std::pair<std::string, std::string> run_part(const Shard& shard, const std::vector<std::string>& given) {
  const std::vector<std::string> only = part_names(given);
  std::string said, file;
  if (shard.active()) {
    said = "--shard " + std::to_string(shard.index) + "/" + std::to_string(shard.count);
    file = "-shard-" + std::to_string(shard.index) + "-of-" + std::to_string(shard.count);
  }
  for (const auto& o : only) {
    said += (said.empty() ? "--only " : " --only ") + o;
    file += "-only-";
    for (char c : o) file += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  }
  return {said, file.empty() ? "" : ".running" + file};
}

// A part's line in its claim file: "part K N [names]" (N = 0: not sharded; names: its --only).
std::string part_line(const Shard& shard, const std::vector<std::string>& only) {
  std::string line = "part " + std::to_string(shard.index) + " " + std::to_string(shard.count);
  for (const auto& o : only) line += " " + o;
  return line + "\n";
}

// Another part running in the folder, as its claim file says.
struct LivePart {
  Shard shard;
  std::vector<std::string> only;
  std::string said;  // "--shard 0/2 --only SG (pid 12 on node3)"
};

// Whether two --only selections can name one trial: either is everything, or a name is the other
// or contains it ("SG" and "SG/B1", "eval" and "eval/gen").
bool selections_overlap(const std::vector<std::string>& a, const std::vector<std::string>& b) {
  if (a.empty() || b.empty()) return true;
  const auto within = [](const std::string& x, const std::string& y) { return x == y || y.rfind(x + "/", 0) == 0; };
  for (const auto& x : a)
    for (const auto& y : b)
      if (within(x, y) || within(y, x)) return true;
  return false;
}

// Whether two parts can hold one trial: shards of one N with other indices never do.
bool parts_overlap(const Shard& s1, const std::vector<std::string>& o1, const Shard& s2, const std::vector<std::string>& o2) {
  const bool shards_apart = s1.active() && s2.active() && s1.count == s2.count && s1.index != s2.index;
  return !shards_apart && selections_overlap(o1, o2);
}

// The parts of `out` running now (their claim file locked), but the one of file `own`. A shared
// lock taken for a moment tells: it fails only while a part holds its file.
std::vector<LivePart> live_parts(const std::string& out, const std::string& own) {
  std::vector<LivePart> parts;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(out, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(".running-", 0) != 0 || name == own) continue;
    const int fd = ::open(entry.path().c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) continue;
    const bool free = try_flock(fd, LOCK_SH, entry.path().string());
    ::close(fd);  // releases the shared lock, if taken
    if (free) continue;
    LivePart part;
    std::ifstream in(entry.path());
    std::string first, word;
    std::getline(in, first);
    if (in >> word >> part.shard.index >> part.shard.count && word == "part")
      while (in >> word) part.only.push_back(word);
    part.said = run_part(part.shard, part.only).first + holder_of(entry.path().string());
    parts.push_back(std::move(part));
  }
  return parts;
}

}  // namespace

void check_out_folder(const std::string& out) {
  std::error_code ec;
  if (fs::exists(fs::path(out) / "manifest.json", ec) || !fs::is_directory(out, ec)) return;
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(out, ec)) {
    const std::string name = entry.path().filename().string();
    const bool folder = entry.is_directory(ec);
    if (!starting_run_file(name, folder)) names.push_back(name + (folder ? "/" : ""));
  }
  std::sort(names.begin(), names.end());
  if (!names.empty()) throw foreign_folder_error(out, names);
}

RunningClaim::RunningClaim(const std::string& out, const Shard& shard, const std::vector<std::string>& only) {
  const auto [part, part_file] = run_part(shard, only);
  const std::string whole = (fs::path(out) / ".running").string();
  const std::string what = "the results folder '" + out + "' is in use by ";
  const std::string then = ": two runs of one folder would each run again the other's trials in flight. Wait "
                           "for it to end (or stop it), or give another --out; to run one folder in several "
                           "processes at once, give each its own --shard K/N (docs/cluster.md)";
  whole_ = open_lock_file(out, ".running");
  if (!try_flock(whole_, part.empty() ? LOCK_EX : LOCK_SH, whole)) {
    // Parts share the folder's claim: if a shared lock is free, parts hold it; else a whole run.
    const bool parts = try_flock(whole_, LOCK_SH, whole);
    ::close(whole_);
    // Each part named with its process (found by a probe: "runs of parts of it" named none).
    std::vector<std::string> said;
    if (parts)
      for (const LivePart& p : live_parts(out, "")) said.push_back(p.said);
    std::sort(said.begin(), said.end());
    const std::string running = said.empty() ? "" : ": " + join(said);
    throw Error(what + (parts ? "runs of parts of it (--shard or --only)" + running
                              : "another roger run" + holder_of(whole)) + then);
  }
  if (part.empty()) {
    write_holder(whole_);
    remove_stale_temporaries(out);
    return;
  }
  own_ = open_lock_file(out, part_file);
  if (!try_flock(own_, LOCK_EX, (fs::path(out) / part_file).string())) {
    const std::string holder = holder_of((fs::path(out) / part_file).string());
    ::close(own_);
    ::close(whole_);
    throw Error(what + "another roger run of the same part (" + part + ")" + holder + then);
  }
  const std::vector<std::string> names = part_names(only);
  write_holder(own_, part_line(shard, names));
  out_ = out, own_file_ = part_file;
  for (const LivePart& other : live_parts(out, part_file))
    if (parts_overlap(shard, names, other.shard, other.only)) {
      // Emptied as the destructor empties it: a refused run leaves no claim naming it (found by a
      // probe: .running-shard-1-of-3 named the pid of a command refused and gone).
      if (::ftruncate(own_, 0) != 0) {}
      ::close(own_);
      ::close(whole_);
      throw Error(what + "a roger run of " + other.said + ", whose trials include some of this part's (" + part +
                  "): the two would each run again the other's trials in flight. Wait for it to end, or give "
                  "parts that share no trial: shards of one N (--shard K/N), or --only names apart");
    }
}

std::string results_folder_unavailable(const std::string& out, const Shard& shard, const std::vector<std::string>& only) {
  std::error_code ec;
  // The folder, or the nearest folder above it that exists, where the run would make it.
  fs::path place = fs::absolute(out, ec);
  while (!place.empty() && !fs::exists(place, ec) && place != place.parent_path()) place = place.parent_path();
  if (fs::exists(place, ec) && !fs::is_directory(place, ec))
    return "'" + place.string() + "' is a file: the results folder cannot be made there";
  if (::access(place.c_str(), W_OK | X_OK) != 0) {
    const int err = errno;
    return "'" + place.string() + "' cannot be written (" + std::strerror(err) + "): the run could not " +
           (place == fs::absolute(out, ec) ? "write its results there" : "make the results folder '" + out + "'");
  }
  const std::string whole = (fs::path(out) / ".running").string();
  const int fd = ::open(whole.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return "";  // no run has claimed it yet
  const bool shared = try_flock(fd, LOCK_SH, whole);  // a whole run holds it alone; parts share it
  ::close(fd);
  if (!shared) return "the results folder '" + out + "' is in use by another roger run" + holder_of(whole);
  if (!run_part(shard, only).first.empty()) {
    // Parts run beside parts that share no trial: one that does (the same part among them) holds
    // the folder for this one (found by a probe: --dry-run of a shard said "resumes" while it ran).
    const std::vector<std::string> names = part_names(only);
    for (const LivePart& other : live_parts(out, ""))
      if (parts_overlap(shard, names, other.shard, other.only))
        return "the results folder '" + out + "' is in use by a roger run of " + other.said +
               ", whose trials include some of this part's";
    return "";
  }
  std::vector<std::string> said;
  for (const LivePart& part : live_parts(out, "")) said.push_back(part.said);
  std::sort(said.begin(), said.end());
  return said.empty() ? "" : "the results folder '" + out + "' is in use by runs of parts of it (--shard or --only): " +
                                 join(said);
}

std::vector<std::string> RunningClaim::others_running() const {
  std::vector<std::string> said;
  if (own_file_.empty()) return said;  // a run of the whole folder holds it alone
  for (const LivePart& p : live_parts(out_, own_file_)) said.push_back(p.said);
  return said;
}

// The claim files stay (unlinking a flock file races with a run that has just opened it): emptied,
// so that none names a process that no longer holds it; the lock, not the text, is the claim.
RunningClaim::~RunningClaim() {
  // A part shares .running and wrote nothing there; best effort (the lock is released either way).
  if (::ftruncate(own_ >= 0 ? own_ : whole_, 0) != 0) {}
  if (own_ >= 0) ::close(own_);  // closing releases the lock
  ::close(whole_);
}

namespace {

// The manifest a run of the plan writes in a new folder (its "config" what a resumed one must match).
json planned_manifest(const BatchPlan& plan) {
  const BatchScript& b = *plan.script;
  json config = batch_config_json(b);
  const std::vector<fs::path> training = curriculum_source_files(Curriculum::load(b.curriculum_file, b.limits), b.limits);
  config["sources"] = source_fingerprints(training);
  // Apart from sources, so that a folder made before evaluations' files were recorded still resumes.
  config["evaluation_sources"] = source_fingerprints(evaluation_source_files(evaluation_scenarios(b), training, b.limits));
  json ids = json::array(), seeds = json::object();
  for (const auto& p : plan.phases)
    for (const auto& t : p) {
      ids.push_back(t.id);
      if (t.run) seeds[t.id] = t.seed;
    }
  json manifest = {{"format", "roger-results/1"},
                   {"script", b.path},
                   {"script_file", fs::absolute(b.file).lexically_normal().string()},
                   {"version", ROGER_VERSION},
                   {"engine", ROGER_ENGINE_FINGERPRINT},
                   {"config", config},
                   {"trials", ids},
                   {"seeds", seeds}};
  return manifest;
}

}  // namespace

bool open_results_folder(const BatchPlan& plan, std::string* note, const Shard& shard, const RunningClaim* claim) {
  const FolderLock lock(plan.out);
  if (shard.active()) check_shard_count(plan.out, shard);  // before the manifest is rewritten
  const json manifest = planned_manifest(plan);
  const fs::path manifest_path = fs::path(plan.out) / "manifest.json";
  std::error_code ec;
  const bool resuming = fs::exists(manifest_path, ec);
  if (!resuming) check_out_folder(plan.out);  // again under the lock: the caller checked before claiming it
  if (resuming) {
    const std::string said = check_manifest(plan, manifest_path, manifest["config"], manifest, claim);
    if (note) *note = said;
  } else {
    write_file_atomic(manifest_path.string(), manifest.dump(1) + "\n", "cannot write the manifest");
  }
  // Recorded under the lock, so that of two shards of different N starting together the second
  // sees the first's N.
  if (shard.active()) record_shard(plan, shard, ShardState::running);
  return resuming;
}

std::string inspect_results_folder(const BatchPlan& plan, const Shard& shard) {
  std::error_code ec;
  if (fs::exists(plan.out, ec) && !fs::is_directory(plan.out, ec))
    throw Error("the results folder " + plan.out + " is a file: give another --out");
  if (shard.active()) check_shard_count(plan.out, shard);
  const fs::path manifest_path = fs::path(plan.out) / "manifest.json";
  if (!fs::exists(manifest_path, ec)) {
    check_out_folder(plan.out);
    return "a new results folder (roger run makes " + plan.out + ")";
  }
  const json manifest = planned_manifest(plan);
  const std::string note = check_manifest(plan, manifest_path, manifest["config"], manifest, nullptr, false);
  size_t all = 0;
  for (const auto& p : plan.phases) all += p.size();
  const std::vector<MissingTrial> missing = missing_trials(plan);
  // Corrupt records named (found by a probe: a dry run over a folder with damaged files counted them
  // among those without a result, and said nothing of them).
  std::vector<std::string> corrupt;
  for (const MissingTrial& m : missing)
    if (!m.problem.empty()) corrupt.push_back(m.trial->id);
  const std::string damaged =
      corrupt.empty() ? "" : "; " + std::to_string(corrupt.size()) + (corrupt.size() == 1 ? " has a corrupt record" :
                                                                                            " have corrupt records") +
                                 " and would run again (roger report " + shell_word(plan.out) + " says what is wrong): " +
                                 join_some(corrupt);
  return "resumes " + plan.out + " (" + std::to_string(all - missing.size()) + " of " + std::to_string(all) +
         " trials have a result" + damaged + ")" + (note.empty() ? "" : "; " + note);
}

std::string describe_shard(const BatchPlan& plan, const Shard& shard) {
  int most = 0;  // the largest number of trials of a run or evaluation
  size_t owned = 0, all = 0;
  for (const auto& p : plan.phases)
    for (const auto& t : p) {
      most = std::max(most, t.index + 1);
      ++all;
      if (shard.owns(t)) ++owned;
    }
  const std::string k = std::to_string(shard.index), n = std::to_string(shard.count);
  if (owned == 0) return idle_shard(plan, shard, most);
  std::vector<std::string> indices;
  for (int i = shard.index; i < most; i += shard.count) indices.push_back(std::to_string(i));
  return "shard " + k + " of " + n + ": trial" + (indices.size() == 1 ? " " : "s ") + join_some(indices) +
         " of every run and evaluation (i mod " + n + " = " + k + "), " + std::to_string(owned) + " of " +
         std::to_string(all) + " trials; no report (run roger report " + shell_word(plan.out) + " when every shard is done)";
}

namespace {

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string csv_number(const json& j, const char* key) {
  if (!j.contains(key)) return "";
  const json& v = j[key];
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_number_integer()) return std::to_string(v.get<int64_t>());
  if (v.is_number()) return format_number(v.get<double>());
  if (v.is_string()) return csv_field(v.get<std::string>());
  return "";
}


// One row of summary.csv. An evaluation's stage is its result's, else (a failed or pending trial:
// found by a probe, whose failed rows had none and fell out of a filter by stage) its run's.
void summary_row(std::ostream& csv, const BatchScript& script, const PlannedTrial& t, const std::string& status,
                 const json& r, const std::string& error) {
  std::string stage = t.run ? t.run->stage : csv_number(r, "stage");
  if (stage.empty() && t.evaluation)
    if (const BatchRun* run = script.run(t.evaluation->run)) stage = csv_field(run->stage);
  // Not reached: result.json's figures are the whole training (right-censored), not times to a
  // threshold, and a column averaged as such would mix them in; the reached column says why empty.
  const bool unreached = r.is_object() && r.contains("reached") && r["reached"] == false;
  const auto to_threshold = [&](const char* key) { return unreached ? std::string() : csv_number(r, key); };
  csv << t.id << "," << (t.run ? "train" : "eval") << "," << (t.run ? t.run->name : t.evaluation->run) << ","
      << stage << "," << t.context << ","
      << (t.evaluation ? t.evaluation->name : "") << "," << t.shape << "," << t.index << ","
      << (t.run ? std::to_string(t.seed) : "") << "," << status << "," << csv_number(r, "reached") << ","
      << to_threshold("time_to_threshold_s") << "," << to_threshold("episodes_to_threshold") << ","
      << to_threshold("decisions_to_threshold") << "," << csv_number(r, "train_episodes") << ","
      << csv_number(r, "train_sim_s") << "," << csv_number(r, "success_rate") << ","
      << csv_number(r, "reward_mean") << "," << csv_number(r, "reward_std") << "," << csv_number(r, "wall_s")
      << "," << csv_field(first_line(error)) << "\n";
}

}  // namespace

BatchSummary summarize_trials(const BatchPlan& plan) {
  std::ostringstream csv;
  csv << "id,kind,run,stage,context,evaluation,shape,trial,seed,status,reached,time_to_threshold_s,"
         "episodes_to_threshold,decisions_to_threshold,train_episodes,train_sim_s,success_rate,reward_mean,"
         "reward_std,wall_s,error\n";
  BatchSummary s;
  for (const auto& p : plan.phases)
    for (const auto& t : p) {
      json r;
      std::string error;
      const std::string status = trial_status(plan.out, t, r, error);
      if (status == "failed") s.failed.push_back(t.id + ": " + first_line(error));
      if (status == "corrupt") s.corrupt.push_back(t.id + ": " + first_line(error));
      if (status == "pending") ++s.pending, s.pending_ids.push_back(t.id);
      ++s.trials;
      summary_row(csv, *plan.script, t, status, r, error);
    }
  s.summary_csv = csv.str();
  return s;
}

void write_summary_csv(const BatchPlan& plan, const BatchSummary& summary) {
  write_file_atomic((fs::path(plan.out) / "summary.csv").string(), summary.summary_csv, "cannot write summary.csv");
}

}  // namespace roger
