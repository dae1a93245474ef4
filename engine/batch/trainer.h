// trainer.h: one training trial of one stage and context of a curriculum (curriculum.h), with the
// paper's measurements: learning curves at greedy checkpoints on held-out seeds, time-to-threshold
// in simulated seconds, episodes, decisions and wall seconds, and the final policy's success rate,
// reward and action usage. A trial is a pure function of (curriculum, stage, context, seed,
// parameters): the same inputs give the same curve and policy bit for bit (wall times aside).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "learn/episode.h"
#include "learn/learning.h"
#include "learn/warm_start.h"
#include "script/sandbox/lua_sandbox.h"

namespace roger {

// An error in one episode of a trial (a fault of a reward or absorbing function or of a scenario
// generator, or any engine error): it names the episode and its world seed, so a fault that only
// some seeds trigger can be found again. what() is "<the cause's first line> (<phase> episode <k>,
// world seed <s>)" followed by the cause's other lines (a Lua traceback).
struct EpisodeFault : Error {
  // Wraps `cause`, keeping its file:line when it is a ScriptError.
  EpisodeFault(const std::exception& cause, std::string phase, int episode, uint64_t world_seed);
  // A fault of a stage and context trained first for this trial (a learned skill or the context's
  // init), its phase preceded by `trained_first` ("in training its skill 'Phi_SG' first: stage
  // 'SG', context 'DC2'"): the episode and world seed are that training's, not this trial's.
  EpisodeFault(const EpisodeFault& inner, const std::string& trained_first);
  // The message with `where` (the stage and context, for a command that names them) in its note:
  // "<first line> (<where>, <phase> episode <k>, world seed <s>)<the other lines>".
  std::string text_in(const std::string& where) const;
  std::string cause;           // the cause's what()
  std::string phase;           // "training", "checkpoint 3 evaluation", "final evaluation", "evaluation"
  int episode = 0;             // 0-based index within the phase (as in episodes.jsonl)
  uint64_t world_seed = 0;     // the seed the scenario generated the episode's world from
  std::string file;            // the script at fault when the cause is a ScriptError, else ""
  int line = 0;                // its line, 0 when unknown
  bool no_placement = false;   // the cause is a PlacementError: the world could not be placed
};

struct TrainResult;

// What a trial trains and how.
struct TrainOptions {
  std::string curriculum;   // script path or bare name ("paper")
  std::string stage, context;
  uint64_t seed = 1;
  std::vector<std::pair<std::string, std::string>> sets;  // scenario parameters over the stage's
  std::string sets_from = "--set";                        // who gave `sets`, for messages
  std::map<std::string, std::string> skill_files;         // learned skill name -> its policy.json
  // How a skill file is named in the trial's own files (a batch trial's: its place in the results
  // folder, so that the files do not depend on where the folder is); else as skill_files has it.
  std::map<std::string, std::string> skill_file_names;
  // Skills the caller has bound already ({name: {policy, file, trained, seed}}), taken as they are
  // rather than trained again: a chain's stage trained first, over the skills trained before it.
  const nlohmann::json* given_skills = nullptr;
  SandboxLimits limits;
  bool keep_episodes = true;  // keep the per-episode records (episodes.jsonl)
  // Reuse a greedy evaluation episode (checkpoints and the final evaluation) instead of running it
  // again when the table still chooses, at every decision state the episode met on its last run,
  // the action it chose then: the episode would run again exactly as before. The results are the
  // same bit for bit either way (only eval_wall_s and wall_s change); false runs every episode.
  bool eval_cache = true;
  // > 0: stop training once this many simulated seconds of training episodes have been spent, the
  // learned skills trained first for this trial included (each gets what the earlier ones left).
  // The trial is then a prefix of the uncapped one (the exploration schedule still runs over the
  // stage's budget in episodes), and censored when the threshold was not reached by then. For
  // short search runs (roger propose); 0 trains to the stage's budget.
  double max_sim_s = 0.0;
  bool final_evaluation = true;  // false skips the final greedy evaluation (final_eval stays empty)
  // The final evaluation starts final_worlds_block times its episodes past the stage's held-out
  // seeds: trial i of a batch run with final_worlds = "own" passes i, so that each trial's final
  // policy meets worlds of its own. The checkpoints keep the held-out seeds.
  uint64_t final_worlds_block = 0;
  // Say why in the summary (train_summary_json's "diagnosis", batch/explain.h) even when the
  // threshold was reached; a trial that did not reach it always says why.
  bool explain = false;
  // A policy.json learned earlier (roger train --init): the Q-table starts from its values and
  // visits over the actions the two share by name (learn/warm_start.h) instead of initial_q.
  std::string init_file;
  // When set, a fault once training has begun (a training episode, the teacher, a checkpoint or
  // the final evaluation) leaves here what the trial had done before it: its training episodes,
  // checkpoints and teacher state, for the caller to keep (roger train writes them beside
  // error.json: write_faulted_train_outputs). The exception itself propagates unchanged.
  TrainResult* progress_on_fault = nullptr;
  // Called once the trial's skills, table and scenario are set, before its first training episode,
  // with the result so far (what it trains: roger train says so then, not only when it is done).
  std::function<void(const TrainResult&)> on_start;
};

// A point of training: what had been spent when it was reached.
struct TrainPoint {
  int episodes = 0;
  double sim_s = 0.0;
  int64_t decisions = 0;
  double wall_s = 0.0;  // training wall time, checkpoint evaluations excluded
};

// What an episode's world held, as its generator placed it: the obstacles and each object's shape
// (episodes.jsonl's "world": a success rate can be split by them, roger report --by).
struct EpisodeWorld {
  int obstacles = 0;
  std::vector<std::string> shapes;  // per object, in the scenario's order
  nlohmann::json to_json() const { return {{"obstacles", obstacles}, {"objects", shapes.size()}, {"shapes", shapes}}; }
};

// One greedy evaluation during training.
struct CheckpointRecord {
  TrainPoint at;
  double success_rate = 0.0, reward_mean = 0.0, reward_std = 0.0;
  double eval_wall_s = 0.0;
  // Whether the greedy policy (visited states and their greedy actions) differs from the previous
  // checkpoint's; true at the first. stop_after counts passing checkpoints of one policy.
  bool policy_changed = true;
  nlohmann::json teacher;  // the teacher's state then (teach.h); null without a teacher
};

// One training episode.
struct EpisodeRecord {
  int index = 0;
  double epsilon = 0.0;
  TrainingEpisode episode;
  EpisodeWorld world;
  nlohmann::json task;  // the task the teacher chose ({"obstacles": 3, ...}); null without a teacher
};

// A greedy evaluation's figures.
struct GreedyEval {
  int episodes = 0;
  uint64_t first_seed = 0;
  int successes = 0;
  double success_rate = 0.0, reward_mean = 0.0, reward_std = 0.0, time_mean = 0.0;
  // Objects a sorting task counts (the most in any episode; 0 when the worlds have none) and the
  // mean number sorted at the end of an episode (TrainingEpisode::objects_sorted).
  int sortable = 0;
  double sorted_mean = 0.0;
  std::vector<std::pair<std::string, double>> usage;  // per action: share of the decisions
  int64_t decisions = 0;
  // Each episode's outcome in seed order, '1' a success and '0' a failure: what a report needs to
  // resample the worlds (report_evaluations.cpp) without the episodes themselves.
  std::string outcomes;
  int succeeded_at_first_tick = 0;  // successes at the first tick: the goal held from the start
  std::vector<TrainingEpisode> runs;  // the final evaluation's episodes (for batch/explain.h)
  std::vector<EpisodeWorld> worlds;   // and their worlds
  std::vector<nlohmann::json> tasks;  // and their test tasks (null entries without a test set)
  std::vector<uint64_t> failed_seeds; // the world seeds of the episodes that did not succeed
};

// Where a learned skill used by the trial came from.
struct SkillSource {
  std::string name;           // "Phi_SG"
  std::string stage, context; // the stage and context that yield it
  std::string file;           // the policy file it was read from ("" when trained here)
  std::string file_name;      // how the trial's files name it (TrainOptions::skill_file_names; "": file)
  uint64_t trained_seed = 0;  // when trained here: the seed it was trained with
  bool trained = false;
  bool embedded = false;      // read from the policy file of a skill learned with it (no figures)
  bool reached = false;       // when trained here: whether it reached its threshold
  TrainPoint to_threshold;    // when trained here: its time-to-threshold (or totals if censored)
  TrainPoint totals;
  nlohmann::json policy;      // the policy file's JSON (embedded in the trial's own policy)
  // A file's skill trained with another curriculum than the trial's (its path; "" when the same or
  // unrecorded), or with this curriculum's file before an edit: its actions run on this one's now.
  std::string trained_curriculum;
  bool trained_curriculum_edited = false;
};

// Everything a trial produced.
struct TrainResult {
  std::string curriculum_path, curriculum_name, stage, context, scenario;
  std::string scenario_file;      // the scenario script's path, as resolved (scenario is its name)
  std::string curriculum_digest;  // of the curriculum file's text (curriculum_digest in trainer.cpp)
  std::string teacher_warning;    // CurriculumStage::teacher_window_warning: why it could not move
  std::string scenario_note;      // CurriculumStage::scenario_note: a same-named scenario beside, not taken
  uint64_t seed = 0;
  std::vector<std::string> psi;
  std::shared_ptr<QTable> q;
  std::vector<EpisodeRecord> episodes;
  std::vector<CheckpointRecord> checkpoints;
  bool reached = false;       // the threshold was reached and held
  bool stopped_early = false; // stop_after ended training before the budget
  bool explain = false;       // TrainOptions::explain
  TrainPoint to_threshold;    // when reached; else the totals (censored)
  TrainPoint totals;
  double threshold = 0.0;
  bool absorbing_lua = false;  // the stage's absorbing state is a Lua function's (for the diagnosis)
  bool reward_lua = false;     // its reward is (with absorbing_lua: no evaluation is reused, docs/curricula.md)
  double wall_s = 0.0;        // the whole trial, evaluations and skill training included
  GreedyEval final_eval;
  std::vector<SkillSource> skills;
  std::optional<WarmStart> init;  // where the table started from (TrainOptions::init_file, a context's init)
  std::optional<TrainPoint> init_trained;  // a context's init trained first: what it spent
  bool init_reached = false;               // and whether it reached its threshold
  std::pair<std::string, std::string> init_from;  // its stage and context (a file's, as the file says them)
  // The stage's and its context's own scenario parameters (a maturation's locked joints, a
  // sorting stage's objects), said beside the command's --set so a restricted trial reads as one.
  std::vector<std::pair<std::string, std::string>> stage_params;
  std::vector<std::pair<std::string, std::string>> params;  // scenario parameters used
  // A stage that teaches (curriculum.h, CurriculumStage::teaches): its task space as the trial
  // had it (less what --set fixed), the teacher's kind and final state, the processor time its
  // choices and fits took (inside the training wall time), and the test set.
  bool teaches = false;
  std::string task_space;
  nlohmann::json teacher;     // {"kind", "state", "wall_s"}
  double teacher_wall_s = 0.0;
  // Tasks the teacher chose whose world the scenario could not place (PlacementError): each was
  // skipped and another drawn for the same episode. {"episode", "task", "error"}, in order.
  nlohmann::json skipped_tasks = nlohmann::json::array();
  int test_tasks = 0;         // tasks of the checkpoints' test set
  uint64_t test_seed = 0;     // ...drawn with this seed, or else the stage's own list of them
  std::vector<std::vector<std::pair<std::string, std::string>>> test_list;  // (test = {list = {...}})
  // The final evaluation's tasks, each as the parameters set before its episode (the teacher's
  // own beside them), in order from world seed final_eval.first_seed: policy.json keeps them, so
  // `roger eval --test-set` runs them again whatever the curriculum says later.
  std::vector<std::vector<std::pair<std::string, std::string>>> final_tasks;
  // The evaluation cache's work (TrainOptions::eval_cache), in this stage's evaluations only (not
  // those of skills trained first). Not written to any result file: the files do not depend on
  // whether the cache was on.
  int evals = 0;                  // greedy evaluations: the checkpoints and the final one
  int evals_reused = 0;           // those whose every episode was reused
  int eval_episodes = 0;          // their episodes
  int eval_episodes_reused = 0;   // those reused
  // Every Lua file the trial compiled, in load order: the curriculum's and scenario's, and modules
  // a callback required while episodes ran (a batch records their fingerprints in result.json).
  std::vector<std::filesystem::path> source_files;
  // The names of options.sets that the scenario's generate read in none of the trial's worlds:
  // setting them changed no world (roger train says so). Not written to any result file.
  std::vector<std::string> unread_sets;
};

// Trains one stage/context for one seed. Learned skills the context uses come from
// options.skill_files or, when absent, from training their stage and context first with the same
// seed. Throws roger::Error / ScriptError for bad input (naming the stage, context and file:line).
TrainResult train_stage(const TrainOptions& options);

// The summary as JSON (the fields of `roger train --json`), with "diagnosis" (batch/explain.h)
// when the threshold was not reached or result.explain.
nlohmann::json train_summary_json(const TrainResult& result);

// The figures of a greedy evaluation as results files and `--json` lines write them: episodes,
// first_seed, successes, success_rate, reward_mean, reward_std, time_mean and usage (each
// action's share of the decisions).
nlohmann::json eval_summary_json(const GreedyEval& eval);

// A greedy evaluation's episodes (kept: GreedyEval::runs), one JSON line each, as final.jsonl and
// an evaluation trial's eval.jsonl hold them: index, seed, reward, success, sim_s, world, the task
// with a test set, and the objects sorted when the worlds have some to sort.
std::string eval_episode_lines(const GreedyEval& eval);

// One checkpoint as checkpoints.jsonl and a trial's result.json write it: where training stood
// (episodes, sim_s, decisions, wall_s), the greedy evaluation's success rate and reward, its wall
// time, whether the policy had changed since the last checkpoint, and the teacher's state then
// (a stage that teaches).
nlohmann::json checkpoint_json(const CheckpointRecord& checkpoint);

// The policy file's JSON (QTable format with metadata: curriculum, stage, context, seed, psi,
// the learned skills used, embedded).
nlohmann::json train_policy_json(const TrainResult& result);

// Writes policy.json, curve.csv, episodes.jsonl, checkpoints.jsonl and summary.json into `dir`
// (created if needed), each atomically (temporary file, then rename). Throws roger::Error.
void write_train_outputs(const TrainResult& result, const std::string& dir);

// What a trial that faulted had done (TrainOptions::progress_on_fault): curve.csv,
// checkpoints.jsonl and episodes.jsonl as write_train_outputs writes them, and error.json with the
// fault's message and how far training got. An earlier trial's policy.json, final.jsonl and
// summary.json in `dir` are removed, so the folder never holds two trials' files. Writes nothing and
// returns false when there is nothing to keep: no training episode ran, or a stop was requested (a
// trial stopped part-way is no result, and no fault). Throws roger::Error.
bool write_faulted_train_outputs(const TrainResult& partial, const std::string& fault, const std::string& dir);

// The scenario parameters a saved policy's trial set beyond what its stage and context in
// `curriculum` give now (the file's extra.params that differ from them): what `roger eval
// --policy` sets as the trial's own, less those `sets` gives (a --set wins). None when `scenario`
// names another scenario than the stage's, where roger eval leaves them. Throws roger::Error for a
// file that names no stage and context.
std::vector<std::pair<std::string, std::string>> policy_trial_params(
    const PolicyMetadata& meta, const std::string& policy_file, const std::string& curriculum,
    const std::string& scenario, const std::vector<std::pair<std::string, std::string>>& sets,
    const SandboxLimits& limits);

// What is said when a saved policy is played in a curriculum other than the one it trained with
// (whose stage and context of the same names then judge it), or in the same file changed since;
// "" when it is the one it trained with. `roger eval --policy` and the Python module say it.
std::string policy_curriculum_note(const PolicyMetadata& meta, const std::string& curriculum,
                                   const SandboxLimits& limits);

// What evaluating a saved policy needs.
struct PolicyEvalOptions {
  std::string curriculum;                                 // the script that defines its stage
  std::string policy_file;                                // a policy.json written by roger train
  std::string scenario;                                   // "" = the stage's
  std::vector<std::pair<std::string, std::string>> sets;  // scenario parameters
  int episodes = 50;                                      // 0 = the stage's final evaluation's count
  int64_t first_seed = -1;                                // -1 = the stage's held-out seeds
  uint64_t seed_offset = 0;                               // added to the first seed (a policy's own worlds)
  // Learned skills from these policy files instead of the ones the policy embeds (skill -> file).
  std::map<std::string, std::string> skill_files;
  SandboxLimits limits;
  AgentParams agent;  // how the agent perceives and is judged (tests judge through copies with it)
  // A teaching stage's policy on the test set its trials ended on (its final evaluation's tasks,
  // world seeds and the teacher's own parameters), instead of `episodes` from `first_seed`.
  bool test_set = false;
  // roger render: test task k (from 1) of that test set, in its world seed, instead of first_seed.
  int test_task = 0;
  // In the stage's own scenario, the parameters the trial trained with beyond its stage's and
  // context's (its --set: the policy file's extra.params where they differ) are set too, before
  // `sets`, so that the policy runs in the trial's worlds (roger eval and render; a batch
  // evaluation gives its own parameters).
  bool trial_params = false;
  bool keep_episodes = false;  // keep the episodes in the result's GreedyEval::runs (eval.jsonl)
  // The command a hint shows ("roger eval", "roger render"): a policy given with another
  // curriculum than its own is told the command with that one.
  std::string command = "roger eval";
};

// The outcome of evaluating a saved policy.
struct PolicyEvalResult {
  std::string stage, context, scenario;
  std::string scenario_file;  // the scenario script's path, as resolved (scenario is its name)
  // With options.trial_params: the trial's own parameters set (in the stage's scenario), or those
  // left out (in another scenario, which may not declare them), each as the policy file has it.
  std::vector<std::pair<std::string, std::string>> trial_sets, trial_sets_left;
  // How many of trial_sets_left (the first ones) the other scenario declares; the rest it does not.
  size_t trial_sets_left_declared = 0;
  // The trial's own parameters that the command's --set overrode here, at their trained values.
  std::vector<std::pair<std::string, std::string>> trial_sets_overridden;
  // The learned skills the policy ran with: embedded in its file, or given by --skill.
  std::vector<SkillSource> skills;
  // The curriculum the policy file says it was trained with, when it is not the one given (whose
  // stage and context of the same names then judge it: their goal, reward and time limit); "".
  std::string trained_curriculum;
  bool trained_curriculum_edited = false;  // that curriculum is the one given, changed since
  std::string curriculum_note;             // what is said of either (policy_curriculum_note), or ""
  // The stage's and its context's own scenario parameters, in the stage's scenario (as TrainResult's).
  std::vector<std::pair<std::string, std::string>> stage_params;
  std::string time_limit;  // the stage's time-out, as text: "12 s limit", "30 s per object limit"
  // In the stage's own scenario: CurriculumStage::scenario_note (a bare name taken for the shipped
  // scenario beside a same-named one), as roger train says it; "" otherwise.
  std::string scenario_note;
  // A teaching stage's trials end on this many test tasks (its task space or teacher), which this
  // evaluation, on the stage's own parameters and held-out seeds, does not run; 0 for other stages.
  int stage_test_tasks = 0;
  // With options.test_set: each episode's task, its parameters as text (the teacher's own beside
  // them), in the order of the episodes.
  std::vector<std::vector<std::pair<std::string, std::string>>> test_tasks;
  std::string test_set_source;     // whence they came: the policy file, or the curriculum
  bool test_set_changed = false;   // the curriculum's test set is no longer the one the file keeps
  GreedyEval eval;
  std::vector<std::pair<std::string, std::string>> params;
  std::vector<std::filesystem::path> source_files;  // as TrainResult's
  std::vector<std::string> unread_sets;  // as TrainResult's: the --set names no world read
};

// Rebuilds a saved policy's Psi from the curriculum (and its embedded learned skills) and runs it
// greedily with the stage's absorbing state and time limit in any scenario.
PolicyEvalResult evaluate_policy_file(const PolicyEvalOptions& options);

// One greedy episode of a saved policy, recorded for replay (roger render).
struct RecordedPolicyEpisode {
  PolicyEvalResult about;   // stage, context, scenario and its parameters (`eval` is left empty)
  WorldSpec spec;           // the episode's world
  EpisodeResult episode;    // frames, the watched controllers' states, the decisions
};

// Runs the greedy episode of a saved policy on world seed options.first_seed (-1: the stage's first
// held-out seed) through the same episode loop as training and evaluation, recording a frame
// every `record_every` seconds and the states of Psi and the controllers inside it (at most
// `watch_limit` rows, outermost first, none repeating another: distinct_traces).
RecordedPolicyEpisode record_policy_episode(const PolicyEvalOptions& options, double record_every,
                                            size_t watch_limit = 12);

}  // namespace roger
