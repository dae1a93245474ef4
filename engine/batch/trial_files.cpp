// trial_files.cpp: what a training trial writes (trainer.h): policy.json, summary.json, curve.csv,
// checkpoints.jsonl, episodes.jsonl and final.jsonl, all together or none, and what a trial that
// faulted leaves beside error.json.
#include "batch/trainer.h"

#include <filesystem>
#include <sstream>

#include "batch/explain.h"
#include "core/error.h"
#include "core/fileio.h"
#include "core/interrupt.h"
#include "core/text.h"
#include "teach/teach.h"

namespace roger {
namespace fs = std::filesystem;

namespace {

// A point of training as every file gives it.
nlohmann::json point_json(const TrainPoint& p) {
  return {{"episodes", p.episodes}, {"sim_s", p.sim_s}, {"decisions", p.decisions}, {"wall_s", p.wall_s}};
}

}  // namespace

nlohmann::json eval_summary_json(const GreedyEval& e) {
  nlohmann::json usage = nlohmann::json::object();
  for (const auto& [name, f] : e.usage) usage[name] = f;
  return {{"episodes", e.episodes},       {"first_seed", e.first_seed},   {"successes", e.successes},
          {"success_rate", e.success_rate}, {"reward_mean", e.reward_mean}, {"reward_std", e.reward_std},
          {"time_mean", e.time_mean},     {"usage", usage}};
}

std::string eval_episode_lines(const GreedyEval& g) {
  std::ostringstream out;
  for (size_t i = 0; i < g.runs.size(); ++i) {
    nlohmann::json line = {{"index", i}, {"seed", g.runs[i].seed}, {"reward", g.runs[i].reward},
                           {"success", g.runs[i].success}, {"sim_s", g.runs[i].sim_seconds},
                           {"world", g.worlds[i].to_json()}};
    if (!g.tasks[i].is_null()) line["task"] = g.tasks[i];
    if (g.sortable > 0) line["sorted"] = g.runs[i].objects_sorted;
    out << line.dump() << "\n";
  }
  return out.str();
}

nlohmann::json checkpoint_json(const CheckpointRecord& c) {
  nlohmann::json j = point_json(c.at);
  j["success_rate"] = c.success_rate;
  j["reward_mean"] = c.reward_mean;
  j["reward_std"] = c.reward_std;
  j["eval_wall_s"] = c.eval_wall_s;
  j["policy_changed"] = c.policy_changed;
  if (!c.teacher.is_null()) j["teacher"] = c.teacher;  // the teacher's state then
  return j;
}

// Where a warm-started table came from, as the summary and the policy file record it.
namespace {

nlohmann::json warm_start_json(const TrainResult& r) {
  const WarmStart& w = *r.init;
  nlohmann::json j = {{"shared", w.shared}, {"fresh", w.fresh}, {"dropped", w.dropped},
                      {"states_with_values", w.states_with_values}};
  if (r.init_trained) {  // the context's init, trained first with this seed
    j.update({{"stage", r.init_from.first}, {"context", r.init_from.second}, {"seed", r.seed},
              {"reached", r.init_reached}, {"totals", point_json(*r.init_trained)}});
  } else {
    j["file"] = w.source;
  }
  return j;
}

}  // namespace

nlohmann::json train_policy_json(const TrainResult& r) {
  PolicyMetadata meta;
  meta.stage = r.stage;
  meta.context = r.context;
  meta.seed = r.seed;
  nlohmann::json extra = {{"curriculum", r.curriculum_path}, {"curriculum_name", r.curriculum_name},
                          {"curriculum_digest", r.curriculum_digest}, {"psi", r.psi}, {"scenario", r.scenario}};
  for (const auto& [k, v] : r.params) extra["params"][k] = v;
  for (const auto& s : r.skills)
    extra["skills"][s.name] = {{"stage", s.stage}, {"context", s.context},
                               {"file", s.file_name.empty() ? s.file : s.file_name},
                               {"trained", s.trained}, {"seed", s.trained_seed}, {"policy", s.policy}};
  if (r.init) extra["init"] = warm_start_json(r);
  if (r.teaches && r.final_eval.episodes > 0) {
    // Each task as [name, value] pairs in the order they are set, values as the text they were set as.
    nlohmann::json tasks = nlohmann::json::array();
    for (const ParamList& task : r.final_tasks) tasks.push_back(task);
    extra["test_set"] = {{"first_seed", r.final_eval.first_seed}, {"tasks", tasks}};
  }
  meta.extra = extra;
  return r.q->to_json(meta);
}

namespace {

// What the summary says of a skill the stage's actions use: trained here, embedded or read from a file.
nlohmann::json skill_json(const SkillSource& s) {
  nlohmann::json k = {{"stage", s.stage}, {"context", s.context}, {"trained", s.trained}};
  if (s.embedded) {
    // Read with the skill that embeds it: how its training went is that file's to say.
    k["embedded"] = true;
    if (s.trained) k["seed"] = s.trained_seed;
  } else if (s.trained) {
    k["seed"] = s.trained_seed;
    k["reached"] = s.reached;
    k["time_to_threshold"] = point_json(s.to_threshold);
    k["totals"] = point_json(s.totals);
  } else {
    k["file"] = s.file_name.empty() ? s.file : s.file_name;
  }
  return k;
}

// What a stage that teaches adds to its summary: the task space, the teacher and the test set.
void teaching_json(const TrainResult& r, nlohmann::json& j) {
  j["tasks"] = r.task_space;
  j["teacher"] = r.teacher;
  j["teacher_wall_s"] = r.teacher_wall_s;
  j["skipped_tasks"] = r.skipped_tasks;
  j["test"] = {{"tasks", r.test_tasks}};
  // The final evaluation runs more of the same draw than the checkpoints (found by a probe: the
  // summary said 10 test tasks of a final evaluation of 50).
  if (!r.final_tasks.empty() && int(r.final_tasks.size()) != r.test_tasks)
    j["test"]["final_tasks"] = r.final_tasks.size();
  if (r.test_list.empty()) {
    j["test"]["seed"] = r.test_seed;
  } else {  // the tasks themselves: a seed would say they were drawn
    for (const ParamList& task : r.test_list) {
      nlohmann::json t = nlohmann::json::object();
      for (const auto& p : task) t[p.first] = param_value_json(p.second);
      j["test"]["list"].push_back(t);
    }
  }
}

}  // namespace

nlohmann::json train_summary_json(const TrainResult& r) {
  nlohmann::json usage = nlohmann::json::object();
  for (const auto& [name, f] : r.final_eval.usage) usage[name] = f;
  nlohmann::json j = {
      {"curriculum", r.curriculum_path},
      {"stage", r.stage},
      {"context", r.context},
      {"seed", r.seed},
      {"scenario", r.scenario},
      {"psi", r.psi},
      {"states", r.q->states()},
      {"visited_states", r.q->visited_states()},
      {"threshold", r.threshold},
      {"reached", r.reached},
      {"stopped_early", r.stopped_early},
      {"time_to_threshold_s", r.to_threshold.sim_s},
      {"episodes_to_threshold", r.to_threshold.episodes},
      {"decisions_to_threshold", r.to_threshold.decisions},
      {"wall_to_threshold_s", r.to_threshold.wall_s},
      {"train_episodes", r.totals.episodes},
      {"train_sim_s", r.totals.sim_s},
      {"train_decisions", r.totals.decisions},
      {"train_wall_s", r.totals.wall_s},
      {"wall_s", r.wall_s},
      {"success_rate", r.final_eval.success_rate},
      {"reward_mean", r.final_eval.reward_mean},
      {"reward_std", r.final_eval.reward_std},
      {"final_episodes", r.final_eval.episodes},
      {"final_first_seed", r.final_eval.first_seed},
      {"final_time_mean", r.final_eval.time_mean},
      {"usage", usage},
  };
  if (r.final_eval.sortable > 0) {
    j["final_sortable"] = r.final_eval.sortable;
    j["final_sorted_mean"] = r.final_eval.sorted_mean;
  }
  for (const auto& s : r.skills) j["skills"][s.name] = skill_json(s);
  if (r.init) j["init"] = warm_start_json(r);
  for (const auto& [k, v] : r.params) j["params"][k] = v;
  if (r.teaches) teaching_json(r, j);
  if (!r.reached || r.explain) j["diagnosis"] = diagnose_training(r).to_json();
  return j;
}

namespace {

// The output folder `dir_in`, made if need be.
void make_output_folder(const std::string& dir_in) {
  const fs::path dir(dir_in);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw FileError("cannot create the output folder '" + dir_in + "': " + ec.message(), dir_in, ec.value());
  if (!fs::is_directory(dir)) throw Error("cannot create the output folder '" + dir_in + "': it is a file");
}

// curve.csv and checkpoints.jsonl: one line per checkpoint.
void stage_checkpoint_files(const TrainResult& r, const StagedFiles& staged) {
  std::ostringstream curve, cps;
  curve << "episodes,sim_s,decisions,wall_s,success_rate,reward_mean\n";
  for (const auto& c : r.checkpoints) {
    curve << c.at.episodes << "," << format_number(c.at.sim_s) << "," << c.at.decisions << ","
          << format_number(c.at.wall_s) << "," << format_number(c.success_rate) << "," << format_number(c.reward_mean) << "\n";
    cps << checkpoint_json(c).dump() << "\n";
  }
  write_file_atomic(staged.stage("curve.csv"), curve.str());
  write_file_atomic(staged.stage("checkpoints.jsonl"), cps.str());
}

// episodes.jsonl: one line per training episode.
void stage_episodes_file(const TrainResult& r, const StagedFiles& staged) {
  std::ostringstream eps;
  for (const auto& e : r.episodes) {
    nlohmann::json counts = nlohmann::json::object();
    std::vector<int> n(r.psi.size(), 0);
    for (int a : e.episode.actions_taken) ++n[size_t(a)];
    for (size_t a = 0; a < r.psi.size(); ++a) counts[r.psi[a]] = n[a];
    nlohmann::json line = {{"index", e.index},       {"seed", e.episode.seed},       {"epsilon", e.epsilon},
                           {"reward", e.episode.reward}, {"success", e.episode.success}, {"sim_s", e.episode.sim_seconds},
                           {"ticks", e.episode.ticks}, {"decisions", e.episode.decisions}, {"actions", counts},
                           {"world", e.world.to_json()}};
    if (!e.task.is_null()) {
      line["task"] = e.task;
      line["td_error"] = e.episode.backups > 0 ? e.episode.td_abs_sum / e.episode.backups : 0.0;  // PLR's score
    }
    eps << line.dump() << "\n";
  }
  write_file_atomic(staged.stage("episodes.jsonl"), eps.str());
}

// final.jsonl: the final evaluation's episodes, one line each (a success rate split by task or world).
void stage_final_file(const TrainResult& r, const StagedFiles& staged) {
  write_file_atomic(staged.stage("final.jsonl"), eval_episode_lines(r.final_eval));
}

// Removes `names` from `dir` where they exist: another trial's files.
void remove_stale(const std::string& dir, const std::vector<std::string>& names) {
  for (const auto& name : names) {
    std::error_code ec;
    if (fs::remove(fs::path(dir) / name, ec); ec)
      throw FileError("cannot remove the earlier trial's '" + (fs::path(dir) / name).string() + "': " + ec.message(),
                      (fs::path(dir) / name).string(), ec.value());
  }
}

}  // namespace

void write_train_outputs(const TrainResult& r, const std::string& dir) {
  make_output_folder(dir);
  // All six or none: a failed write leaves a folder trained before with its own files, not a
  // policy of one trial beside the summary of another.
  StagedFiles staged(dir);
  write_file_atomic(staged.stage("policy.json"), train_policy_json(r).dump(1) + "\n");
  stage_checkpoint_files(r, staged);
  stage_episodes_file(r, staged);
  stage_final_file(r, staged);
  write_file_atomic(staged.stage("summary.json"), train_summary_json(r).dump(1) + "\n");
  // summary.json says the folder is whole: the earlier one goes first and the new one comes last,
  // so a kill among the moves (found by a probe: policy.json of one trial beside summary.json of
  // the one before) leaves a folder without it, which is no finished training.
  staged.commit({"policy.json", "curve.csv", "checkpoints.jsonl", "episodes.jsonl", "final.jsonl", "summary.json"},
                {"summary.json"});
  remove_stale(dir, {"error.json"});  // of a trial that faulted here before
}

bool write_faulted_train_outputs(const TrainResult& r, const std::string& fault, const std::string& dir) {
  if (r.totals.episodes == 0 || interrupt_requested()) return false;
  make_output_folder(dir);
  StagedFiles staged(dir);
  stage_checkpoint_files(r, staged);
  stage_episodes_file(r, staged);
  nlohmann::json error = {{"error", printable_text(fault)},
                          {"curriculum", r.curriculum_path},
                          {"stage", r.stage},
                          {"context", r.context},
                          {"seed", r.seed},
                          {"trained", point_json(r.totals)},
                          {"checkpoints", r.checkpoints.size()}};
  if (!r.teacher.is_null()) error["teacher"] = r.teacher;
  if (!r.skipped_tasks.empty()) error["skipped_tasks"] = r.skipped_tasks;
  write_file_atomic(staged.stage("error.json"), error.dump(1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  // The earlier trial's results go first: a crash between the two steps leaves none of its files
  // beside this trial's.
  remove_stale(dir, {"policy.json", "final.jsonl", "summary.json"});
  staged.commit({"curve.csv", "checkpoints.jsonl", "episodes.jsonl", "error.json"});
  return true;
}

}  // namespace roger
