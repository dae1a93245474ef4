// batch_internal.h: what the batch module's files share and nobody else needs.
#pragma once

#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/batch.h"
#include "batch/trainer.h"
#include "learn/learning.h"
#include "script/curriculum/curriculum.h"
#include "script/scenario/scenario.h"

namespace roger::batch_detail {

// The first line of a message.
std::string first_line(const std::string& s);

// ---- plan.cpp ----

// What a shard's record says of it: running (from the moment it opened the folder), ended (every
// trial it owns has a result), or interrupted (a signal stopped it with trials not run). A shard
// killed outright (SIGKILL, a lost node) stays "running"; the page then says it has no news.
enum class ShardState { running, ended, interrupted };
const char* shard_state_name(ShardState state);

// A shard's own outcome, in <out>/shards/K-of-N.json (no other shard writes that file): the trials
// it owns, which failed, how many it has not run yet, and its state. Written as the shard opens the
// folder (a shard of another N starting meanwhile is refused then) and again as it ends.
BatchSummary record_shard(const BatchPlan& plan, const Shard& shard, ShardState state);

// Every shard's state, as a sharded run's status.json gives it to the page (docs/browser.md): for
// K = 0 .. N-1, {"state", "trials", "pending"}: the trials it owns (from the plan), its state and
// trials not run from shards/K-of-N.json, the state "not started" when it has no record (queued,
// or cancelled before it started) and "unknown" when its record cannot be read. A record unchanged
// since the last read (its time of change and its size: a shared filesystem may keep whole seconds,
// and a change of state all but always changes the size) is not read again: every shard reads the others'
// each second.
class ShardBoard {
 public:
  nlohmann::json read(const BatchPlan& plan, int count);

 private:
  struct Seen {
    std::filesystem::file_time_type changed;
    std::uintmax_t size = 0;
    nlohmann::json entry;
  };
  std::map<int, Seen> seen_;
};

// The scenarios the batch script's evaluations name (those that take their stage's name none).
std::vector<std::string> evaluation_scenarios(const BatchScript& b);

// The Lua files the scenarios `scenarios` read (each loaded once) that are not among `training`'s.
std::vector<std::filesystem::path> evaluation_source_files(const std::vector<std::string>& scenarios,
                                                           const std::vector<std::filesystem::path>& training,
                                                           const SandboxLimits& limits);

// The Lua files a run's trials read (the curriculum, what it requires, its scenarios and the
// evaluations' scenarios) as they were when the run started. Every trial loads them again, so one
// removed or edited meanwhile would fail every later trial, or train or evaluate them on other
// files than the manifest records.
class SourceWatch {
 public:
  // Loads the curriculum and each scenario once to list their files and fingerprints them.
  explicit SourceWatch(const std::string& curriculum_file, const SandboxLimits& limits = {},
                       const std::vector<std::string>& evaluation_scenarios = {});
  // Watches too the files a finished trial read beyond those (its result.json "sources": modules a
  // callback required while episodes ran), at the fingerprints the trial recorded.
  void learn(const nlohmann::json& sources);
  // Throws roger::FileError naming the first file that is gone (ENOENT) or changed (0).
  void check() const;

 private:
  mutable std::mutex mutex_;  // trials learn and check from several threads
  std::vector<std::pair<std::string, std::string>> files_;  // path, fingerprint
};

// The Lua files `files` with their fingerprints, named relative to the project when inside it, as
// the manifest's config "sources" and a trial's result.json "sources" record them.
nlohmann::json source_fingerprints(const std::vector<std::filesystem::path>& files);
// FNV-1a of a text, as 16 hex digits: what the fingerprints of sources and policies are.
std::string fingerprint(const std::string& text);
// The fingerprints of the policy files a trial reads (an evaluation's own, every skill's), by their
// names inside the results folder `out` ("trials/SG/DC2/000/policy.json"), as its result.json
// records them in "policies": a trial that read a policy retrained since is run again.
nlohmann::json policy_fingerprints(const std::string& out, const std::vector<std::string>& names);
// Whether `key`, a source named relative to a project root as source_fingerprints names it
// ("curricula/paper.lua"), is the file at `path` (".../curricula/paper.lua"): path ends with "/" + key.
bool source_names_path(const std::string& key, const std::string& path);
// The file a name of source_fingerprints stands for.
std::filesystem::path source_file_path(const std::string& name);

// ---- records.cpp: reading a results folder back, every file checked ----

// An evaluation trial's episodes, one JSON line each (eval_episode_lines), named by its result's
// "episodes_file".
inline constexpr const char* kEvalEpisodesFile = "eval.jsonl";

// A trial's state on disk: "ok" (filling `result`), "failed" (filling `error` with its message),
// "corrupt" (filling `error` with the file at fault and what is wrong: a result.json, error.json or
// a training trial's policy.json that is truncated, empty, edited or another trial's, or the
// episodes of its final evaluation (final.jsonl) or of an evaluation trial (eval.jsonl) missing,
// cut short, or disagreeing with the result's outcomes, reward mean and std, time mean or objects
// sorted) or "pending".
std::string trial_status(const std::string& out, const PlannedTrial& t, nlohmann::json& result, std::string& error);

// The scenario parameters the plan runs trial t with (the batch's, its run's or evaluation's, and
// --set; an evaluation's shape), as its result.json records them in "set_params".
nlohmann::json planned_params_json(const PlannedTrial& t);

// Why a parsed result.json cannot be trial t's result (not an object, another trial's id, seed or
// scenario parameters, a
// field missing, of the wrong type or not finite, a success rate or count that disagrees with its
// own episode outcomes), or "" when it can. Every field the report reads is
// checked here, the optional ones (outcomes, skipped tasks, a diagnosis) where present: the report
// reads only results that passed (write_report checks the folder first).
std::string result_problem(const nlohmann::json& result, const PlannedTrial& t);

// A JSON file, or roger::Error "<path>: ..." saying it is missing, empty or not JSON.
nlohmann::json read_json_file(const std::string& path);

// A results folder's manifest.json, checked to be one (an object of format roger-results/1 with
// its config, engine and script; every field of the config that batch_config_from_json reads, and
// the trial ids and seeds where present, of the right type), or roger::Error naming the file, the
// field and what is wrong. plan.cpp compares the trial ids and seeds with the plan.
nlohmann::json read_manifest_file(const std::string& path);

// ---- trainer.cpp: what a trial and an environment (environment.cpp) both build a stage from ----

// A stage's Lua reward and absorbing functions as the decision hooks of its semi-MDP.
class StageHooks final : public DecisionHooks {
 public:
  StageHooks(Curriculum& cur, const CurriculumStage& stage, const CurriculumContext& ctx)
      : cur_(cur), stage_(stage), ctx_(ctx) {}
  bool has_absorbing() const override { return stage_.absorbing_lua; }
  bool has_reward() const override { return stage_.reward_lua; }
  void begin() override {
    if (stage_.reward_lua || stage_.absorbing_lua) cur_.begin_episode();
  }
  bool absorbing(const std::vector<Gamma>& state, double time) override {
    return cur_.call_absorbing(stage_, ctx_, state, time);
  }
  double reward(const std::vector<Gamma>& state, int action, const char* event, double time) override {
    return cur_.call_reward(stage_, ctx_, state, action, event, time);
  }

 private:
  Curriculum& cur_;
  const CurriculumStage& stage_;
  const CurriculumContext& ctx_;
};

// The scenario of a stage with its parameters and the context's over them, then the caller's
// `sets`; `name` another scenario ("" = the stage's, whose parameters then do not apply). Appends
// the parameters used to `used`.
Scenario make_scenario(const CurriculumStage& stage, const CurriculumContext& context, const std::string& name,
                       const std::vector<std::pair<std::string, std::string>>& sets,
                       const SandboxLimits& limits, std::vector<std::pair<std::string, std::string>>* used);

// Binds every learned skill `ctx` uses: from embedded policies (`embedded`: name -> policy JSON),
// from options.skill_files, or by training the producing stage with options.seed. Appends where
// each came from.
void bind_skills(Curriculum& cur, const CurriculumContext& ctx, const TrainOptions& options,
                 const nlohmann::json* embedded, std::vector<SkillSource>& sources);

}  // namespace roger::batch_detail
