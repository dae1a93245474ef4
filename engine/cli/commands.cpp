#include "cli/commands.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "batch/batch.h"
#include "script/batch_script.h"
#include "script/curriculum.h"
#include "engine_fingerprint.h"
#include "core/error.h"
#include "core/fileio.h"
#include "report/report.h"
#include "batch/trainer.h"

namespace roger {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// FNV-1a, 64 bits, as 16 hex digits: a stable fingerprint of the curriculum's text.
std::string fingerprint(const std::string& text) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char buf[20];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

// The Lua files training with a curriculum reads (docs/batch.md), each with its fingerprint, named
// relative to the project when inside it: a results folder is resumed only while none changed.
json source_fingerprints(const std::string& curriculum_file) {
  const Curriculum cur = Curriculum::load(curriculum_file);
  const fs::path root = fs::weakly_canonical(project_root());
  json out = json::object();
  for (const fs::path& f : curriculum_source_files(cur)) {
    const fs::path rel = f.lexically_relative(root);
    const bool inside = !rel.empty() && *rel.begin() != "..";
    out[inside ? rel.generic_string() : f.generic_string()] = fingerprint(read_text(f.string()));
  }
  return out;
}

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

std::string first_line(const std::string& s) {
  const size_t nl = s.find('\n');
  return nl == std::string::npos ? s : s.substr(0, nl);
}

// What a trial id stands for.
struct TrialSpec {
  std::string id;
  const BatchRun* run = nullptr;               // a training trial
  const BatchEvaluation* evaluation = nullptr; // or an evaluation trial
  std::string context, shape;
  int index = 0;
  uint64_t seed = 0;
};

bool finished(const std::string& out, const std::string& id) {
  const fs::path d = trial_dir(out, id);
  std::error_code ec;
  return fs::exists(d / "result.json", ec) || fs::exists(d / "error.json", ec);
}

// The differences between two configurations, as "field: old -> new" lines.
std::vector<std::string> differences(const json& a, const json& b, const std::string& at = "") {
  std::vector<std::string> out;
  if (a.is_object() && b.is_object()) {
    std::set<std::string> keys;
    for (auto it = a.begin(); it != a.end(); ++it) keys.insert(it.key());
    for (auto it = b.begin(); it != b.end(); ++it) keys.insert(it.key());
    for (const auto& k : keys) {
      const json na = a.contains(k) ? a[k] : json(), nb = b.contains(k) ? b[k] : json();
      for (auto& d : differences(na, nb, at.empty() ? k : at + "." + k)) out.push_back(d);
    }
    return out;
  }
  if (a != b) {
    std::string sa = a.dump(), sb = b.dump();
    if (sa.size() > 80) sa = sa.substr(0, 77) + "...";
    if (sb.size() > 80) sb = sb.substr(0, 77) + "...";
    out.push_back(at + ": " + sa + " in the folder, " + sb + " now");
  }
  return out;
}

}  // namespace

int command_run(const RunArgs& a) {
  std::ostream& log = a.progress ? *a.progress : std::cerr;
  try {
    BatchOverrides ov;
    ov.trials = a.trials;
    for (const auto& s : a.sets) {
      const size_t eq = s.find('=');
      if (eq == std::string::npos || eq == 0) throw Error("--set '" + s + "': expected key=value");
      ov.sets.emplace_back(s.substr(0, eq), s.substr(eq + 1));
    }
    if (a.trials < 0) throw Error("--trials must be positive");
    const BatchScript b = load_batch_script(a.script, ov);
    const std::string out = a.out.empty() ? (fs::path("results") / b.name).string() : a.out;

    // Every trial, phase by phase: a run's trials come after those of the runs it takes skills from.
    std::vector<std::vector<TrialSpec>> phases;
    for (const BatchRun* r : b.ordered_runs()) {
      std::vector<TrialSpec> phase;
      for (const auto& c : r->contexts)
        for (int i = 0; i < r->trials; ++i) {
          TrialSpec t;
          t.id = batch_trial_id(r->name, c, i);
          t.run = r;
          t.context = c;
          t.index = i;
          t.seed = b.seed + uint64_t(i);
          phase.push_back(t);
        }
      // A phase waits for the phases of the runs it depends on (ordered_runs puts them first).
      phases.push_back(std::move(phase));
    }
    {
      std::vector<TrialSpec> phase;
      for (const auto& e : b.evaluations)
        for (const auto& g : batch_eval_groups(e))
          for (int i = 0; i < e.trials; ++i) {
            TrialSpec t;
            t.id = batch_eval_id(e.name, g, i);
            t.evaluation = &e;
            t.context = e.context;
            t.shape = g;
            t.index = i;
            t.seed = b.seed + uint64_t(i);
            phase.push_back(t);
          }
      if (!phase.empty()) phases.push_back(std::move(phase));
    }

    // --only: which trials this invocation runs.
    auto matches = [](const TrialSpec& t, const std::string& o) {
      if (t.run) return o == t.run->name || o == t.run->name + "/" + t.context;
      return o == "eval" || o == "eval/" + t.evaluation->name;
    };
    auto selected = [&](const TrialSpec& t) {
      if (a.only.empty()) return true;
      for (const auto& o : a.only)
        if (matches(t, o)) return true;
      return false;
    };
    for (const auto& o : a.only) {
      bool any = false;
      for (const auto& p : phases)
        for (const auto& t : p) any = any || matches(t, o);
      if (!any) {
        std::string names;
        for (const auto& r : b.runs) names += (names.empty() ? "" : ", ") + r.name;
        for (const auto& e : b.evaluations) names += ", eval/" + e.name;
        throw Error("--only '" + o + "' names no run, run/context or eval/evaluation of " + b.path + " (they are: " +
                    names + ")");
      }
    }

    // The manifest: what the folder holds. A folder made by another script or parameters is refused.
    json config = batch_config_json(b);
    config["sources"] = source_fingerprints(b.curriculum_file);
    json ids = json::array(), seeds = json::object();
    for (const auto& p : phases)
      for (const auto& t : p) {
        ids.push_back(t.id);
        if (t.run) seeds[t.id] = t.seed;
      }
    const fs::path manifest_path = fs::path(out) / "manifest.json";
    std::error_code ec;
    if (fs::exists(manifest_path, ec)) {
      json old;
      try {
        old = json::parse(read_text(manifest_path.string()));
      } catch (const std::exception& e) {
        throw Error(manifest_path.string() + ": not JSON (" + e.what() + "); use another --out");
      }
      const std::string old_engine = old.value("engine", std::string());
      if (old_engine != ROGER_ENGINE_FINGERPRINT)
        throw Error("the results folder " + out + " was made by " +
                    (old_engine.empty() ? std::string("a roger that did not record its engine")
                                        : "another build of the engine (engine " + old_engine + ")") +
                    ", and this roger's engine is " + ROGER_ENGINE_FINGERPRINT +
                    ": its trials would mix with this build's. Use another --out, or remove the folder "
                    "to start over; `roger report " + out + "` still reports what it holds.");
      const json old_config = old.value("config", json());
      if (old_config != config) {
        std::string why;
        for (const auto& d : differences(old_config, config)) why += "\n  " + d;
        throw Error("the results folder " + out + " was made by another batch script or other parameters (" +
                    old.value("script", std::string("?")) + "); it cannot be resumed with " + b.path +
                    ". Differences:" + why + "\nUse another --out, or remove the folder to start over.");
      }
      log << "roger run: resuming " << out << "\n";
    } else {
      const json manifest = {{"format", "roger-results/1"},
                             {"script", b.path},
                             {"script_file", fs::absolute(b.file).lexically_normal().string()},
                             {"version", ROGER_VERSION},
                             {"engine", ROGER_ENGINE_FINGERPRINT},
                             {"config", config},
                             {"trials", ids},
                             {"seeds", seeds}};
      write_file_atomic(manifest_path.string(), manifest.dump(1) + "\n", "roger run: cannot write the manifest");
    }

    // The trials themselves.
    std::map<std::string, const TrialSpec*> by_id;
    for (const auto& p : phases)
      for (const auto& t : p) by_id[t.id] = &t;
    auto policy_of = [&](const std::string& id) {
      const fs::path p = fs::path(trial_dir(out, id)) / "policy.json";
      if (fs::exists(p)) return p.string();
      const fs::path err = fs::path(trial_dir(out, id)) / "error.json";
      if (fs::exists(err)) {
        std::string msg;
        try {
          msg = json::parse(read_text(err.string())).value("error", std::string());
        } catch (const std::exception&) {
        }
        throw Error("needs the policy of trial " + id + ", which failed: " + first_line(msg));
      }
      throw Error("needs the policy of trial " + id + ", which has not run yet (run it first, e.g. --only " +
                  id.substr(0, id.rfind('/')) + ")");
    };
    const TrialFunction fn = [&](const std::string& id, const std::string& dir) -> json {
      const TrialSpec& t = *by_id.at(id);
      const auto t0 = std::chrono::steady_clock::now();
      if (t.run) {
        TrainOptions o;
        o.curriculum = b.curriculum_file;
        o.stage = t.run->stage;
        o.context = t.context;
        o.seed = t.seed;
        o.sets = t.run->params;
        std::map<std::string, std::string> skill_ids;
        for (const auto& s : t.run->skills) {
          const std::string from = batch_trial_id(s.run, s.context, t.index);
          o.skill_files[s.skill] = policy_of(from);
          skill_ids[s.skill] = from;
        }
        const TrainResult r = train_stage(o);
        write_train_outputs(r, dir);
        json j = train_summary_json(r);
        j["id"] = id;
        j["run"] = t.run->name;
        j["trial"] = t.index;
        // Paths inside the results folder, so results do not depend on where the folder is.
        for (const auto& [skill, from] : skill_ids)
          if (j.contains("skills") && j["skills"].contains(skill)) {
            j["skills"][skill]["file"] = "trials/" + from + "/policy.json";
            j["skills"][skill]["trial"] = from;
          }
        json cps = json::array();
        for (const auto& c : r.checkpoints)
          cps.push_back({{"episodes", c.at.episodes}, {"sim_s", c.at.sim_s}, {"decisions", c.at.decisions},
                         {"wall_s", c.at.wall_s}, {"success_rate", c.success_rate}, {"reward_mean", c.reward_mean},
                         {"reward_std", c.reward_std}});
        j["checkpoints"] = cps;
        return j;
      }
      const BatchEvaluation& e = *t.evaluation;
      const std::string from = batch_trial_id(e.run, e.context, t.index);
      PolicyEvalOptions o;
      o.curriculum = b.curriculum_file;
      o.policy_file = policy_of(from);
      o.scenario = e.scenario;
      o.sets = e.params;
      if (!e.shapes.empty()) o.sets.emplace_back("shape", t.shape);
      o.episodes = e.episodes;
      o.first_seed = e.first_seed;
      const PolicyEvalResult r = evaluate_policy_file(o);
      json usage = json::object();
      for (const auto& [name, f] : r.eval.usage) usage[name] = f;
      json params = json::object();
      for (const auto& [k, v] : r.params) params[k] = v;
      return {{"id", id},
              {"evaluation", e.name},
              {"run", e.run},
              {"context", e.context},
              {"trial", t.index},
              {"shape", t.shape},
              {"policy", "trials/" + from + "/policy.json"},
              {"stage", r.stage},
              {"scenario", r.scenario},
              {"episodes", r.eval.episodes},
              {"first_seed", r.eval.first_seed},
              {"successes", r.eval.successes},
              {"success_rate", r.eval.success_rate},
              {"reward_mean", r.eval.reward_mean},
              {"reward_std", r.eval.reward_std},
              {"time_mean", r.eval.time_mean},
              {"usage", usage},
              {"params", params},
              {"wall_s", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()}};
    };

    BatchOptions bo;
    bo.jobs = a.jobs;
    bo.out_dir = out;
    bo.progress = &log;
    bo.live = a.live;
    std::map<std::string, TrialOutcome> outcomes;
    int budget = a.max_trials > 0 ? a.max_trials : -1;
    const auto start = std::chrono::steady_clock::now();
    log << "roger run: " << b.path << " -> " << out << " (" << ids.size() << " trials, curriculum "
        << b.curriculum << ")\n";
    for (size_t k = 0; k < phases.size(); ++k) {
      std::vector<std::string> run_ids;
      std::set<std::string> names;
      for (const auto& t : phases[k]) {
        if (!selected(t)) continue;
        // A trial that failed in an earlier invocation is tried again.
        const fs::path err = fs::path(trial_dir(out, t.id)) / "error.json";
        if (fs::exists(err, ec) && !fs::exists(fs::path(trial_dir(out, t.id)) / "result.json", ec)) fs::remove(err, ec);
        if (!finished(out, t.id)) {
          if (budget == 0) continue;
          if (budget > 0) --budget;
        }
        run_ids.push_back(t.id);
        names.insert(t.run ? t.run->name : "eval/" + t.evaluation->name);
      }
      if (run_ids.empty()) continue;
      std::string label;
      for (const auto& n : names) label += (label.empty() ? "" : ", ") + n;
      log << "roger run: phase " << (k + 1) << "/" << phases.size() << ": " << label << " (" << run_ids.size()
          << " trials)\n";
      for (auto& o : run_trials(run_ids, fn, bo)) outcomes[o.id] = std::move(o);
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    // summary.csv: one row per trial of the manifest (pending ones included), from the results on disk.
    std::ostringstream csv;
    csv << "id,kind,run,stage,context,evaluation,shape,trial,seed,status,reached,time_to_threshold_s,"
           "episodes_to_threshold,decisions_to_threshold,train_episodes,train_sim_s,success_rate,reward_mean,"
           "reward_std,wall_s,error\n";
    std::vector<std::string> failed;
    int pending = 0;
    for (const auto& p : phases)
      for (const auto& t : p) {
        json r;
        std::string status = "pending", error;
        const fs::path d = trial_dir(out, t.id);
        try {
          if (fs::exists(d / "result.json")) {
            r = json::parse(read_text((d / "result.json").string()));
            status = "ok";
          } else if (fs::exists(d / "error.json")) {
            error = json::parse(read_text((d / "error.json").string())).value("error", std::string());
            status = "failed";
          }
        } catch (const std::exception& e) {
          status = "failed";
          error = std::string("unreadable result: ") + e.what();
        }
        if (status == "failed") failed.push_back(t.id + ": " + first_line(error));
        if (status == "pending") ++pending;
        csv << t.id << "," << (t.run ? "train" : "eval") << "," << (t.run ? t.run->name : t.evaluation->run) << ","
            << (t.run ? t.run->stage : csv_number(r, "stage")) << "," << t.context << ","
            << (t.evaluation ? t.evaluation->name : "") << "," << t.shape << "," << t.index << ","
            << (t.run ? std::to_string(t.seed) : "") << "," << status << "," << csv_number(r, "reached") << ","
            << csv_number(r, "time_to_threshold_s") << "," << csv_number(r, "episodes_to_threshold") << ","
            << csv_number(r, "decisions_to_threshold") << "," << csv_number(r, "train_episodes") << ","
            << csv_number(r, "train_sim_s") << "," << csv_number(r, "success_rate") << ","
            << csv_number(r, "reward_mean") << "," << csv_number(r, "reward_std") << "," << csv_number(r, "wall_s")
            << "," << csv_field(first_line(error)) << "\n";
      }
    write_file_atomic((fs::path(out) / "summary.csv").string(), csv.str(), "roger run: cannot write summary.csv");

    int status = 0;
    if (!a.no_report) {
      try {
        for (const auto& f : write_report(out)) log << "roger run: wrote " << f << "\n";
      } catch (const std::exception& e) {
        log << "roger run: the report failed: " << e.what() << "\n";
        status = 1;
      }
    }
    log << "roger run: " << (ids.size() - failed.size() - size_t(pending)) << " of " << ids.size()
        << " trials done in " << format_duration(wall);
    if (pending) log << ", " << pending << " not run yet (run the same command again to continue)";
    log << "\n";
    if (!failed.empty()) {
      log << "roger run: " << failed.size() << " trial" << (failed.size() == 1 ? "" : "s")
          << " failed (their error.json holds the whole message; the same command tries them again):\n";
      for (const auto& f : failed) log << "  " << f << "\n";
      status = 1;
    }
    return status;
  } catch (const std::exception& e) {
    log << "roger run: " << e.what() << "\n";
    return 1;
  }
}

int command_report(const ReportArgs& a) {
  std::ostream& log = a.progress ? *a.progress : std::cerr;
  try {
    for (const auto& f : write_report(a.dir)) log << "roger report: wrote " << f << "\n";
    return 0;
  } catch (const std::exception& e) {
    log << "roger report: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace roger
