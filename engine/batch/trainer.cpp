#include "batch/trainer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <filesystem>
#include <map>
#include <optional>
#include <set>

#include "batch/batch_internal.h"
#include "control/agent.h"
#include "core/error.h"
#include "core/fileio.h"
#include "core/rng.h"
#include "core/text.h"
#include "script/curriculum/curriculum.h"
#include "script/scenario/scenario.h"

namespace roger {
namespace fs = std::filesystem;
using batch_detail::StageHooks;
using batch_detail::bind_skills;
using batch_detail::make_scenario;

namespace {

// A digest of the curriculum file's text: the same text is the same curriculum, wherever it is and
// however its path is written.
std::string curriculum_digest(const Curriculum& cur) { return text_hash(read_file_text(cur.file())); }

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// "<first line> (<phase> episode <k>, world seed <s>)<the other lines>".
std::string episode_fault_text(const std::string& cause, const std::string& phase, int episode, uint64_t seed) {
  return with_note_on_first_line(cause, " (" + phase + " episode " + std::to_string(episode) + ", world seed " +
                                            std::to_string(seed) + ")");
}

// One stage/context of a loaded curriculum, ready to run episodes in a scenario.
struct StageRun {
  Curriculum& cur;
  const CurriculumStage& stage;
  const CurriculumContext& ctx;
  Scenario scenario;
  Agent agent;
  // One judge of the absorbing predicate for every episode of the trial: under noise its copies of
  // the predicate's controllers are made once and reset each episode, as the originals are, and
  // keep what those keep (a navigator's cold solve of the same region). Controllers cannot change
  // after they are made (c:with makes another), so a copy made earlier is the copy made now.
  Judge judge{stage.absorbing.get()};

  // Every Lua file the run has compiled so far: the curriculum's and the scenario's, and the modules
  // they required, including those a callback required while episodes ran (which no load lists).
  std::vector<std::filesystem::path> files_read() {
    std::vector<std::filesystem::path> files = cur.source_files();
    for (const auto& f : scenario.sandbox().source_files())
      if (std::find(files.begin(), files.end(), f) == files.end()) files.push_back(f);
    return files;
  }

  // One episode of the stage's semi-MDP through the episode loop; the stage's Lua functions, if
  // any, are called at decision points only.
  // An error is rethrown as an EpisodeFault naming `phase`, `index` and the world seed.
  // `observer`, if any, records it (roger render).
  TrainingEpisode run(QTable& q, uint64_t seed, double epsilon, Rng& rng, bool learn, const std::string& phase,
                      int index, EpisodeObserver* observer = nullptr, EpisodeWorld* world = nullptr) {
    try {
      const WorldSpec spec = scenario.generate(seed);
      if (world) {
        world->obstacles = int(spec.obstacles.size());
        world->shapes.clear();
        for (const auto& o : spec.objects) world->shapes.push_back(o.shape.name);
      }
      StageHooks hooks(cur, stage, ctx);
      SemiMdpDriver driver(ctx.actions, stage.absorbing.get(), q, epsilon, rng, stage.rewards, learn, &hooks, &judge);
      run_episode(agent, spec, seed, driver, stage.episode_time_limit(spec), observer);
      return driver.episode();
    } catch (const EpisodeFault&) {
      throw;  // from a learned skill's own training: already placed
    } catch (const std::exception& e) {
      throw EpisodeFault(e, phase, index, seed);
    }
  }
};

// The curriculum the policy file records, when it is another than `cur`; "" when the same or none.
// The same text is the same curriculum, whatever the path said from another folder (found by a
// probe: a policy trained as c/ok.lua, judged as ./ok.lua from c/, was said to be another's).
std::string other_curriculum(const PolicyMetadata& meta, const Curriculum& cur) {
  if (!meta.extra.is_object() || !meta.extra.contains("curriculum") || !meta.extra["curriculum"].is_string()) return "";
  const std::string recorded = meta.extra["curriculum"].get<std::string>();
  if (meta.extra.contains("curriculum_digest") && meta.extra["curriculum_digest"].is_string())
    return meta.extra["curriculum_digest"].get<std::string>() == curriculum_digest(cur) ? "" : recorded;
  std::error_code ec;
  if (recorded == cur.path() || fs::equivalent(recorded, cur.file(), ec)) return "";
  // Trained in another checkout of the project (tests/policies/ were): the same file of it.
  const std::string own = "/" + cur.path();
  if (recorded.size() > own.size() && recorded.compare(recorded.size() - own.size(), own.size(), own) == 0) return "";
  return recorded;
}

// Whether the curriculum a policy file records is the file `cur` was read from (then edited since,
// when other_curriculum names it).
bool same_curriculum_file(const std::string& recorded, const Curriculum& cur) {
  std::error_code ec;
  return recorded == cur.path() || fs::equivalent(recorded, cur.file(), ec);
}

}  // namespace

// The scenario of a stage with its parameters, then the caller's.
Scenario batch_detail::make_scenario(const CurriculumStage& stage, const CurriculumContext& context,
                                     const std::string& name,
                       const std::vector<std::pair<std::string, std::string>>& sets,
                       const SandboxLimits& limits, std::vector<std::pair<std::string, std::string>>* used) {
  const bool own = name.empty() || name == stage.scenario;
  Scenario s = Scenario::load(own ? stage.scenario : name, limits);
  if (own) s.set_params(stage.scenario_params(context));
  s.set_params(sets);
  if (used)
    for (const auto& p : s.params()) used->push_back({p.name, p.value});
  return s;
}

namespace {

// The greedy evaluation episodes of one trial, by world seed, as they last ran. A greedy episode
// is a function of its world seed and of the actions chosen at its decisions: every episode
// starts afresh (a world rebuilt from the spec, every controller of Psi and the absorbing
// predicate reset, phi1's planner without its last solution), epsilon 0 draws no random numbers,
// and the learned skills inside Psi cannot change, since each is a snapshot of its table taken
// when it was bound (make_policy_skill). Its decisions are q.policy_action(s) at the states it
// meets. So when policy_action(s) is still the action recorded at each of its decision states, the
// episode would run again exactly as recorded: the first decision meets the same state and takes
// the same action, hence the same run to the second decision, and so on. Lua reward or absorbing
// functions could keep state between calls, so a stage with them gets no cache.
struct EvalCache {
  struct Kept {
    TrainingEpisode episode;
    EpisodeWorld world;
  };
  std::map<uint64_t, Kept> by_seed;
  int reused = 0;  // episodes taken from the cache

  // Whether the recorded episode would run again the same with table q.
  static bool still_valid(const TrainingEpisode& ep, const QTable& q) {
    for (size_t k = 0; k < ep.decision_states.size(); ++k)
      if (q.policy_action(ep.decision_states[k]) != ep.actions_taken[k]) return false;
    return true;
  }
  // The episode of `seed` as it last ran, if it would run again the same with table q; else null.
  const Kept* reusable(uint64_t seed, const QTable& q) const {
    const auto it = by_seed.find(seed);
    return it != by_seed.end() && still_valid(it->second.episode, q) ? &it->second : nullptr;
  }
};

// The worlds of a greedy evaluation: seeds first_seed, first_seed + 1, ...; with a test set, the
// task of each (its parameters set before its episode, with `extra` beside them), drawn from a
// space or, for a saved policy, as its file lists them.
struct EvalWorlds {
  uint64_t first_seed = 0;
  int episodes = 0;
  const TaskSpace* space = nullptr;          // null: the stage's own parameters
  const std::vector<TaskPoint>* tasks = nullptr;
  ParamList extra = {};
  const std::vector<ParamList>* listed = nullptr;  // instead of space and tasks: each task's parameters

  bool has_tasks() const { return tasks || listed; }
  // Episode i's task: its parameters, then those beside them.
  ParamList task(size_t i) const {
    if (listed) return (*listed)[i];
    ParamList all = space->params((*tasks)[i]);
    all.insert(all.end(), extra.begin(), extra.end());
    return all;
  }
  // Episode i's task as records keep it (null without a test set).
  nlohmann::json task_json(size_t i) const {
    if (tasks) return space->to_json((*tasks)[i]);
    if (!listed) return nullptr;
    nlohmann::json t = nlohmann::json::object();
    for (const auto& [k, v] : (*listed)[i]) t[k] = param_value_json(v);
    return t;
  }
};

// Sets a task's parameters (and those beside it) on the scenario, for the next episodes.
void set_params(Scenario& scenario, const ParamList& task, const ParamList& extra) {
  for (const auto& [k, v] : task) scenario.set_param(k, v);
  for (const auto& [k, v] : extra) scenario.set_param(k, v);
}

// A placement failure `f` rethrown with `what` (what could not be placed, and what follows) before
// its own text, at the stage's file:line: the trial stops for the stage's reason, the placement's
// detail and traceback kept.
[[noreturn]] void fail_placement(const CurriculumStage& stage, const std::string& what, const EpisodeFault& f,
                                 bool as_fault) {
  const size_t nl = f.cause.find('\n');
  const std::string first = f.cause.substr(0, nl);
  const std::string rest = nl == std::string::npos ? "" : f.cause.substr(nl + 1);
  const ScriptError e(stage.where() + ": " + what + " The placement failed with: " + first, stage.file, stage.line, rest);
  if (as_fault) throw EpisodeFault(PlacementError(e), f.phase, f.episode, f.world_seed);
  throw e;
}

// A greedy evaluation on held-out seeds first_seed, first_seed + 1, ...; with a cache, reusing the
// episodes that would run again exactly as they last did.
// `phase` names the evaluation in errors ("final evaluation").
// `keep`: keep the episodes in GreedyEval::runs (the final evaluation, for the diagnosis).
GreedyEval greedy_eval(StageRun& run, QTable& q, const EvalWorlds& worlds, const std::string& phase,
                       EvalCache* cache = nullptr, bool keep = false) {
  const uint64_t first_seed = worlds.first_seed;
  const int episodes = worlds.episodes;
  GreedyEval g;
  g.episodes = episodes;
  g.first_seed = first_seed;
  Rng unused(0);
  std::vector<double> rewards;
  std::vector<int64_t> counts(size_t(q.actions()), 0);
  double time = 0.0;
  for (int i = 0; i < episodes; ++i) {
    const uint64_t seed = first_seed + uint64_t(i);
    const EvalCache::Kept* kept = cache ? cache->reusable(seed, q) : nullptr;
    EvalCache::Kept fresh;
    if (kept) {
      ++cache->reused;
    } else {
      if (worlds.has_tasks()) set_params(run.scenario, worlds.task(size_t(i)), {});
      try {
        fresh.episode = run.run(q, seed, 0.0, unused, false, phase, i, nullptr, &fresh.world);
      } catch (const EpisodeFault& f) {
        if (!worlds.has_tasks() || !f.no_placement) throw;
        const ParamList task = worlds.task(size_t(i));
        fail_placement(run.stage,
                       "test task " + std::to_string(i + 1) + " of " + std::to_string(episodes) + " (" +
                           (task.empty() ? "the stage's own parameters" : params_text(task)) +
                           ") cannot be placed in world seed " + std::to_string(seed) +
                           "; the test set is not skipped, since the measure would change with it: give the stage "
                           "another test (test.seed, a test.list or a narrower space).",
                       f, true);
      }
    }
    const EvalCache::Kept& done = kept ? *kept : cache ? cache->by_seed[seed] = std::move(fresh) : fresh;
    const TrainingEpisode& ep = done.episode;
    g.successes += ep.success;
    g.succeeded_at_first_tick += ep.success && ep.ticks <= 1;
    if (!ep.success) g.failed_seeds.push_back(seed);
    g.outcomes += ep.success ? '1' : '0';
    rewards.push_back(ep.reward);
    time += ep.sim_seconds;
    g.sortable = std::max(g.sortable, ep.objects_sortable);
    g.sorted_mean += ep.objects_sorted;
    for (int a : ep.actions_taken) ++counts[size_t(a)];
    g.decisions += ep.decisions;
    if (keep) {
      g.runs.push_back(ep);
      g.worlds.push_back(done.world);
      g.tasks.push_back(worlds.task_json(size_t(i)));
    }
  }
  double mean = 0.0, var = 0.0;
  for (double r : rewards) mean += r;
  mean /= std::max(1, episodes);
  for (double r : rewards) var += (r - mean) * (r - mean);
  g.success_rate = double(g.successes) / std::max(1, episodes);
  g.reward_mean = mean;
  g.reward_std = std::sqrt(var / std::max(1, episodes));
  g.time_mean = time / std::max(1, episodes);
  g.sorted_mean /= std::max(1, episodes);
  for (int a = 0; a < q.actions(); ++a)
    g.usage.push_back({q.action_names()[size_t(a)], g.decisions ? double(counts[size_t(a)]) / double(g.decisions) : 0.0});
  return g;
}

// A learned skill's policy file given as --skill NAME=FILE.
nlohmann::json read_skill_file(const std::string& name, const std::string& path) {
  try {
    return batch_detail::read_json_file(path);  // checked: truncated, empty or not JSON is named
  } catch (const std::exception& e) {
    throw Error("the policy of the learned skill '" + name + "': " + e.what());
  }
}

// The options of a stage and context trained first, for this trial (a learned skill its actions
// use, or its context's init): that context's own task, no records of its episodes, and no --init
// (found by a probe: the caller's warm start was applied to the skill trained first too, changing
// it without a word, or refused naming that skill's actions).
TrainOptions first_training(const TrainOptions& options, const std::string& stage, const std::string& context) {
  TrainOptions sub = options;
  sub.stage = stage;
  sub.context = context;
  sub.sets.clear();
  sub.keep_episodes = false;
  sub.init_file.clear();
  // Its episodes are not this trial's: a fault in it keeps nothing as this trial's progress.
  sub.progress_on_fault = nullptr;
  sub.on_start = nullptr;
  return sub;
}

// train_stage of a stage and context trained first for this trial (`why`: "its skill 'Phi_SG'"),
// a fault in it naming that stage and context (found by a probe: a fault in the skill's checkpoint
// read "stage 'T', context 'DC6', checkpoint 8 evaluation", and T's folder kept SG's curve as T's).
TrainResult train_first(const TrainOptions& sub, const std::string& why) {
  try {
    return train_stage(sub);
  } catch (const EpisodeFault& f) {
    throw EpisodeFault(f, "in training " + why + " first: stage '" + sub.stage + "', context '" + sub.context + "'");
  }
}

// The simulated training seconds of the skills trained for this trial so far.
double skills_sim_s(const std::vector<SkillSource>& sources) {
  double s = 0.0;
  for (const auto& src : sources)
    if (src.trained) s += src.totals.sim_s;
  return s;
}

}  // namespace

void batch_detail::bind_skills(Curriculum& cur, const CurriculumContext& ctx, const TrainOptions& options,
                 const nlohmann::json* embedded, std::vector<SkillSource>& sources) {
  for (const auto& name : ctx.learned) {
    if (std::any_of(sources.begin(), sources.end(), [&](const SkillSource& s) { return s.name == name; })) continue;
    const CurriculumStage* producer = cur.producer(name);
    if (!producer) throw Error("curriculum '" + cur.name() + "': no stage yields the learned skill '" + name + "'");
    const CurriculumContext& pctx = producer->context(producer->skill->second);
    // A skill built on other learned skills needs them bound first; a skill read from a file, with
    // the ones that file embeds (those it was learned with), not with new ones.
    nlohmann::json from_file;
    const nlohmann::json* deps = embedded;
    const auto file = options.skill_files.find(name);
    if ((!embedded || !embedded->contains(name)) && file != options.skill_files.end()) {
      from_file = read_skill_file(name, file->second);
      if (from_file.contains("extra") && from_file["extra"].contains("skills")) deps = &from_file["extra"]["skills"];
    }
    bind_skills(cur, pctx, options, deps, sources);
    SkillSource src;
    src.name = name;
    src.stage = producer->name;
    src.context = pctx.name;
    if (embedded && embedded->contains(name)) {
      const nlohmann::json& e = (*embedded)[name];
      src.policy = e.at("policy");
      src.file = e.value("file", "");
      src.trained = e.value("trained", false);
      src.trained_seed = e.value("seed", uint64_t(0));
      src.embedded = true;
    } else if (file != options.skill_files.end()) {
      src.policy = std::move(from_file);
      src.file = file->second;
      const auto named = options.skill_file_names.find(name);
      if (named != options.skill_file_names.end()) src.file_name = named->second;
    } else if (embedded) {
      throw Error("the policy file does not embed the learned skill '" + name + "' its context uses");
    } else {
      // No policy given: train the producing stage and context first, with the same seed.
      TrainOptions sub = first_training(options, producer->name, pctx.name);
      sub.max_sim_s = options.max_sim_s > 0 ? std::max(1e-9, options.max_sim_s - skills_sim_s(sources)) : 0.0;
      // Over the skills just bound, not trained again inside (found by a probe: a chain's second
      // stage trained its first skill again, under what was left of a cap, and that time went
      // uncounted: the cap that ended the second stage was recorded as task time).
      nlohmann::json given = nlohmann::json::object();
      for (const auto& s : sources)
        given[s.name] = {{"policy", s.policy}, {"file", s.file}, {"trained", s.trained}, {"seed", s.trained_seed}};
      sub.given_skills = &given;
      const TrainResult r = train_first(sub, "its skill '" + name + "'");
      src.trained = true;
      src.trained_seed = options.seed;
      src.reached = r.reached;
      src.to_threshold = r.to_threshold;
      src.totals = r.totals;
      src.policy = train_policy_json(r);
    }
    // A file given for the skill is checked for its stage and context first: "a policy of stage T"
    // says more than the action lists of two stages.
    const std::string source = src.file.empty() ? "the policy of skill '" + name + "'"
                                                : src.file + " (given for the learned skill '" + name + "')";
    PolicyMetadata meta;
    if (!src.file.empty()) {
      QTable::from_json(src.policy, {}, source, &meta);
      if (meta.stage != producer->name || meta.context != pctx.name)
        throw Error(src.file + ": a policy of stage '" + meta.stage + "', context '" + meta.context + "', but the skill '" +
                    name + "' comes from stage '" + producer->name + "', context '" + pctx.name + "'");
      src.trained_curriculum = other_curriculum(meta, cur);  // found by a probe: another's skill, unsaid
      src.trained_curriculum_edited = !src.trained_curriculum.empty() && same_curriculum_file(src.trained_curriculum, cur);
    }
    const QTable q = QTable::from_json(src.policy, controller_names(pctx.actions), source, &meta);
    cur.bind_learned(name, make_policy_skill(name, pctx.actions, q, producer->absorbing));
    sources.push_back(std::move(src));
  }
}

EpisodeFault::EpisodeFault(const std::exception& e, std::string phase_in, int episode_in, uint64_t seed_in)
    : Error(episode_fault_text(e.what(), phase_in, episode_in, seed_in)),
      cause(e.what()),
      phase(std::move(phase_in)),
      episode(episode_in),
      world_seed(seed_in) {
  if (const auto* script = dynamic_cast<const ScriptError*>(&e)) {
    file = script->file;
    line = script->line;
  }
  no_placement = dynamic_cast<const PlacementError*>(&e) != nullptr;
}

EpisodeFault::EpisodeFault(const EpisodeFault& inner, const std::string& trained_first)
    : Error(episode_fault_text(inner.cause, trained_first + ", " + inner.phase, inner.episode, inner.world_seed)),
      cause(inner.cause),
      phase(trained_first + ", " + inner.phase),
      episode(inner.episode),
      world_seed(inner.world_seed),
      file(inner.file),
      line(inner.line),
      no_placement(inner.no_placement) {}

std::string EpisodeFault::text_in(const std::string& where) const {
  return episode_fault_text(cause, where + ", " + phase, episode, world_seed);
}

namespace {

// A checkpoint's record: where training stood and what its greedy evaluation gave.
CheckpointRecord checkpoint_record(const TrainPoint& at, const GreedyEval& g, double eval_wall_s) {
  CheckpointRecord c;
  c.at = at;
  c.success_rate = g.success_rate;
  c.reward_mean = g.reward_mean;
  c.reward_std = g.reward_std;
  c.eval_wall_s = eval_wall_s;
  return c;
}

// The greedy policy as the learned policy plays it: which states were visited, and the greedy
// action in each (QTable::policy_action is a function of these alone). -1 for a state not visited.
void greedy_signature(const QTable& q, std::vector<int>& out) {
  out.resize(size_t(q.states()));
  for (int s = 0; s < q.states(); ++s) out[size_t(s)] = q.visited(s) ? q.greedy(s) : -1;
}

}  // namespace

namespace {

// The teacher of one trial of a stage that teaches: the trial's task space (the stage's, less the
// parameters --set fixes), the teacher drawing from its own stream of the trial's seed, and the
// test sets of the checkpoints and of the final evaluation. Times its own work.
class TrialTeacher {
 public:
  TrialTeacher(Curriculum& cur, const CurriculumStage& stage, const TrainOptions& options) {
    std::vector<std::string> fixed;
    for (const auto& [k, v] : options.sets) fixed.push_back(k);
    stage.check_fixed(fixed, options.sets_from);
    space_ = stage.tasks.without(fixed);
    teacher_ = cur.make_teacher(stage, space_, Rng::mix(options.seed, 0x7465616368ull));  // "teach"
    const int cp_n = stage.checkpoint_test_tasks(), final_n = stage.final_test_tasks();
    final_tasks_ = stage.test_tasks(space_, std::max(cp_n, final_n));
    checkpoint_tasks_.assign(final_tasks_.begin(), final_tasks_.begin() + std::min<size_t>(size_t(cp_n), final_tasks_.size()));
    final_tasks_.resize(std::min<size_t>(size_t(final_n), final_tasks_.size()));
    extra_ = teacher_->test_params();
  }

  // The next training episode's task, set on the scenario; its world seed (the episode's own,
  // unless the teacher replays a level).
  uint64_t pick(Scenario& scenario, uint64_t own_seed) {
    const auto t0 = std::chrono::steady_clock::now();
    pick_ = teacher_->next();
    wall_s_ += seconds_since(t0);
    set_params(scenario, space_.params(pick_.task), pick_.extra);
    return pick_.world_seed.value_or(own_seed);
  }
  // The task of the last pick as text, for messages.
  std::string task_text() const {
    ParamList all = space_.params(pick_.task);
    all.insert(all.end(), pick_.extra.begin(), pick_.extra.end());
    return all.empty() ? "the stage's own parameters" : params_text(all);
  }
  // The task of the last pick, as records keep it.
  nlohmann::json task() const {
    nlohmann::json task = space_.to_json(pick_.task);
    for (const auto& [k, v] : pick_.extra) task[k] = param_value_json(v);
    return task;
  }
  // What came of it, told to the teacher; the task as the episode's record keeps it.
  nlohmann::json tell(const TrainingEpisode& ep) {
    const auto t0 = std::chrono::steady_clock::now();
    TaskOutcome o;
    o.task = pick_.task;
    o.world_seed = ep.seed;
    o.success = ep.success;
    o.reward = ep.reward;
    o.sim_s = ep.sim_seconds;
    o.td_error = ep.backups > 0 ? ep.td_abs_sum / ep.backups : 0.0;
    teacher_->record(o);
    wall_s_ += seconds_since(t0);
    return task();
  }
  EvalWorlds worlds(uint64_t first_seed, bool final) const {
    const std::vector<TaskPoint>& tasks = final ? final_tasks_ : checkpoint_tasks_;
    return {first_seed, int(tasks.size()), &space_, &tasks, extra_};
  }
  nlohmann::json state() const { return teacher_->state(); }
  // What the teacher sets beside every test task (an LCAS lift's last level).
  const ParamList& test_params() const { return extra_; }
  std::string kind() const { return teacher_->kind(); }
  double wall_s() const { return wall_s_; }
  const TaskSpace& space() const { return space_; }
  int test_tasks() const { return int(checkpoint_tasks_.size()); }

 private:
  TaskSpace space_;
  std::unique_ptr<Teacher> teacher_;
  std::vector<TaskPoint> checkpoint_tasks_, final_tasks_;
  ParamList extra_;
  TaskPick pick_;
  double wall_s_ = 0.0;
};

// Training episode e in the world of `own_seed`, or with a teacher in the world of its task. A task
// whose world cannot be placed is the space's hole, not the learner's failure: it goes into
// `skipped` and the teacher draws again (nothing has run yet: the world comes first). After
// kSkipsPerWorld skips the draws move to another world seed, as one layout may hold no task of a
// narrow space that others hold (found by a probe: robot_distance in [2.1, 2.4] failed every
// trial in the one layout of its episode). A space that is mostly holes fails its trial rather
// than drawing forever.
TrainingEpisode train_episode(StageRun& run, TrialTeacher* teacher, QTable& q, uint64_t own_seed, double eps, Rng& rng,
                              int e, EpisodeWorld& world, nlohmann::json& skipped) {
  constexpr int kMaxSkippedInARow = 100, kSkipsPerWorld = 10;
  for (int skips = 0;;) {
    const uint64_t layout = skips < kSkipsPerWorld ? own_seed : Rng::mix(own_seed, uint64_t(skips / kSkipsPerWorld));
    const uint64_t seed = teacher ? teacher->pick(run.scenario, layout) : layout;
    try {
      return run.run(q, seed, eps, rng, true, "training", e, nullptr, &world);
    } catch (const EpisodeFault& f) {
      // A space --set or the run's params left without axes draws the same task every time: a
      // redraw cannot place what this one could not, so the placement's own error stands.
      if (!teacher || !f.no_placement || teacher->space().empty()) throw;
      skipped.push_back({{"episode", e}, {"task", teacher->task()}, {"error", f.cause}});
      if (++skips >= kMaxSkippedInARow)
        fail_placement(run.stage,
                       std::to_string(kMaxSkippedInARow) + " tasks in a row from its teacher (" + teacher->kind() +
                           ") could not be placed in " + std::to_string(kMaxSkippedInARow / kSkipsPerWorld) +
                           " world seeds, each skipped (the last: " + teacher->task_text() +
                           ", for training episode " + std::to_string(e) + ", world seed " +
                           std::to_string(f.world_seed) + "): the task space (" + teacher->space().describe() +
                           ") asks for worlds the scenario cannot build.",
                       f, false);
    }
  }
}

}  // namespace

namespace {

// What the trial trains, as its summary and policy file name it.
TrainResult trial_header(const Curriculum& cur, const CurriculumStage& stage, const CurriculumContext& ctx,
                         const TrainOptions& options) {
  TrainResult res;
  res.curriculum_path = cur.path();
  res.curriculum_digest = curriculum_digest(cur);
  res.teacher_warning = stage.teacher_window_warning();
  res.scenario_note = stage.scenario_note();
  res.curriculum_name = cur.name();
  res.stage = stage.name;
  res.context = ctx.name;
  res.stage_params = stage.scenario_params(ctx);
  res.seed = options.seed;
  res.threshold = stage.checkpoints.threshold;
  res.absorbing_lua = stage.absorbing_lua;
  res.reward_lua = stage.reward_lua;
  res.psi = controller_names(ctx.actions);
  return res;
}

// The table training starts from: the learner's initial values, or a warm start from the table
// learned earlier (--init, else the context's init trained first with the same seed), over the
// actions the two share.
void start_table(TrainResult& res, const CurriculumStage& stage, const CurriculumContext& ctx,
                 const TrainOptions& options) {
  if (!options.init_file.empty()) {
    res.init.emplace();
    PolicyMetadata meta;
    const QTable earlier = QTable::load(options.init_file, {}, &meta);
    res.init_from = {meta.stage, meta.context};
    res.q = std::make_shared<QTable>(warm_start_table(res.psi, stage.learner, earlier, options.init_file, &*res.init));
  } else if (!ctx.init_context.empty()) {
    const TrainOptions sub = first_training(options, ctx.init_stage, ctx.init_context);
    const TrainResult first = train_first(sub, "its init");
    res.init.emplace();
    res.init_trained = first.totals;
    res.init_reached = first.reached;
    res.init_from = {ctx.init_stage, ctx.init_context};
    res.q = std::make_shared<QTable>(warm_start_table(
        res.psi, stage.learner, *first.q,
        "stage '" + ctx.init_stage + "', context '" + ctx.init_context + "' (init, trained first)", &*res.init));
  } else {
    res.q = std::make_shared<QTable>(res.psi, stage.learner);
  }
}

// The parameters recorded are those the checkpoints' and the final evaluation's worlds have: a
// parameter an LCAS teacher lifts outside the task space is evaluated at its last level, which
// `roger eval --policy` then sets as the trial's own (trial_only_params). Training episodes record
// the level they had in their task. A parameter a task axis draws has no one value (summary.json's
// tasks and test say what it took): its scenario default, which no episode used, is left out.
void record_test_params(TrainResult& res, const TrialTeacher& teacher) {
  for (const auto& [name, level] : teacher.test_params())
    for (auto& param : res.params)
      if (param.first == name) param.second = level;
  res.params.erase(std::remove_if(res.params.begin(), res.params.end(),
                                  [&](const auto& p) { return teacher.space().index(p.first) >= 0; }),
                   res.params.end());
}

// What a stage that teaches records at the end: its task space, the teacher's kind, state and
// time, and the test sets.
void record_teacher(TrainResult& res, const TrialTeacher& teacher, const CurriculumStage& stage) {
  res.teaches = true;
  res.task_space = teacher.space().describe();
  res.teacher_wall_s = teacher.wall_s();
  res.teacher = {{"kind", teacher.kind()}, {"wall_s", teacher.wall_s()}, {"state", teacher.state()}};
  res.test_tasks = teacher.test_tasks();
  res.test_seed = stage.test.seed;
  res.test_list = stage.test.list;
  const EvalWorlds final_worlds = teacher.worlds(stage.checkpoints.seeds, true);
  for (size_t i = 0; i < size_t(final_worlds.episodes); ++i) res.final_tasks.push_back(final_worlds.task(i));
}

// The trial's greedy evaluations, each counted in the result (its episodes, and those reused from
// the cache): with a teacher on its test set, otherwise on the held-out seeds from `offset` on.
class TrialEvaluations {
 public:
  TrialEvaluations(StageRun& run, const TrialTeacher* teacher, const TrainOptions& options, TrainResult& res)
      : run_(run), teacher_(teacher), res_(res),
        cache_(options.eval_cache && !run.stage.absorbing_lua && !run.stage.reward_lua ? &eval_cache_ : nullptr) {}

  GreedyEval operator()(int episodes, const std::string& phase, bool keep = false, uint64_t offset = 0) {
    const int reused_before = eval_cache_.reused;
    const uint64_t seeds = run_.stage.checkpoints.seeds;
    const EvalWorlds worlds = teacher_ ? teacher_->worlds(seeds, keep) : EvalWorlds{seeds + offset, episodes};
    episodes = worlds.episodes;
    GreedyEval g = greedy_eval(run_, *res_.q, worlds, phase, cache_, keep);
    const int reused = eval_cache_.reused - reused_before;
    ++res_.evals;
    res_.eval_episodes += episodes;
    res_.eval_episodes_reused += reused;
    res_.evals_reused += cache_ && episodes > 0 && reused == episodes;
    return g;
  }

 private:
  StageRun& run_;
  const TrialTeacher* teacher_;
  TrainResult& res_;
  EvalCache eval_cache_;
  EvalCache* cache_;
};

// The checkpoints' verdicts: how many passed in a row, and how many of them in a row one greedy
// policy passed (for stop_after, with settle: a policy that changed since the last checkpoint has
// passed once, on one set of seeds).
class CheckpointVerdicts {
 public:
  // Judges checkpoint c of the table q (marking whether its greedy policy changed); true when
  // stop_after ends training there.
  bool judge(CheckpointRecord& c, const QTable& q, const CheckpointSpec& cp) {
    const bool passed = c.success_rate >= cp.threshold;
    passing_ = passed ? passing_ + 1 : 0;
    greedy_signature(q, greedy_now_);
    c.policy_changed = first_ || greedy_now_ != greedy_before_;
    first_ = false;
    settled_ = !passed ? 0 : c.policy_changed && cp.settle ? 1 : settled_ + 1;
    greedy_before_.swap(greedy_now_);
    return cp.stop_after > 0 && settled_ >= cp.stop_after;
  }
  int passing() const { return passing_; }

 private:
  int passing_ = 0, settled_ = 0;
  bool first_ = true;
  std::vector<int> greedy_before_, greedy_now_;
};

// Trains to the stage's budget, or to the trial's cap (TrainOptions::max_sim_s, after what its
// skills spent), or until stop_after, with a greedy checkpoint every cp.every episodes and at the
// end. res.totals follows what has been spent, so a fault leaves it true.
void train_episodes(StageRun& run, TrialTeacher* teacher, const TrainOptions& options, TrialEvaluations& evaluate,
                    TrainResult& res) {
  QTable& q = *res.q;
  const int budget = run.stage.budget_episodes;
  const CheckpointSpec& cp = run.stage.checkpoints;
  const ExplorationSchedule schedule = ExplorationSchedule::episodes(run.stage.learner, budget);
  Rng rng(Rng::mix(options.seed, 0x65787031ull));  // exploration stream, apart from world seeds
  const double cap = options.max_sim_s > 0 ? options.max_sim_s - skills_sim_s(res.skills) : 0.0;
  TrainPoint& spent = res.totals;
  CheckpointVerdicts verdicts;
  for (int e = 0; e < budget; ++e) {
    if (options.max_sim_s > 0 && spent.sim_s >= cap) break;  // judged at its last checkpoint
    const auto te = std::chrono::steady_clock::now();
    const double eps = schedule.epsilon(e);
    EpisodeWorld world;
    TrainingEpisode ep = train_episode(run, teacher, q, Rng::mix(options.seed, uint64_t(e) + 1), eps, rng, e, world,
                                       res.skipped_tasks);
    nlohmann::json task = teacher ? teacher->tell(ep) : nlohmann::json();
    spent.wall_s += seconds_since(te);
    spent.episodes = e + 1;
    spent.sim_s += ep.sim_seconds;
    spent.decisions += ep.decisions;
    if (options.keep_episodes) res.episodes.push_back(EpisodeRecord{e, eps, std::move(ep), std::move(world), std::move(task)});
    if ((e + 1) % cp.every != 0 && e + 1 != budget) continue;
    const auto tc = std::chrono::steady_clock::now();
    const GreedyEval g = evaluate(cp.episodes, "checkpoint " + std::to_string(res.checkpoints.size() + 1) + " evaluation");
    res.checkpoints.push_back(checkpoint_record(spent, g, seconds_since(tc)));
    if (teacher) res.checkpoints.back().teacher = teacher->state();
    if (verdicts.judge(res.checkpoints.back(), q, cp) && e + 1 < budget) {
      res.stopped_early = true;
      break;
    }
  }
  // The first checkpoint from which the rate stays at or above the threshold to the end.
  res.reached = verdicts.passing() > 0;
  res.to_threshold = res.reached ? res.checkpoints[res.checkpoints.size() - size_t(verdicts.passing())].at : spent;
}

}  // namespace

TrainResult train_stage(const TrainOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  // A fresh load per trial: every trial gets its own controllers.
  Curriculum cur = Curriculum::load(options.curriculum, options.limits);
  const CurriculumStage& stage = cur.stage(options.stage);
  const CurriculumContext& ctx = stage.context(options.context);
  TrainResult res = trial_header(cur, stage, ctx, options);
  bind_skills(cur, ctx, options, options.given_skills, res.skills);

  StageRun run{cur, stage, ctx, make_scenario(stage, ctx, "", options.sets, options.limits, &res.params), Agent()};
  cur.set_world(&run.agent.world());  // the Lua callbacks' `world`
  res.scenario = run.scenario.name();
  res.scenario_file = run.scenario.path();
  start_table(res, stage, ctx, options);
  std::optional<TrialTeacher> teacher;
  if (stage.teaches()) {
    teacher.emplace(cur, stage, options);
    record_test_params(res, *teacher);
  }
  TrialEvaluations evaluate(run, teacher ? &*teacher : nullptr, options, res);
  if (options.on_start) options.on_start(res);
  try {
    train_episodes(run, teacher ? &*teacher : nullptr, options, evaluate, res);
    if (options.final_evaluation)
      res.final_eval = evaluate(stage.checkpoints.final_episodes, "final evaluation", true,
                                options.final_worlds_block * uint64_t(stage.checkpoints.final_episodes));
  } catch (...) {
    // What training had done when the fault stopped it, for a caller that keeps it.
    if (options.progress_on_fault) {
      if (teacher) res.teacher = {{"kind", teacher->kind()}, {"wall_s", teacher->wall_s()}, {"state", teacher->state()}};
      res.wall_s = seconds_since(t0);
      *options.progress_on_fault = std::move(res);
    }
    throw;
  }
  if (teacher) record_teacher(res, *teacher, stage);
  res.source_files = run.files_read();
  // Found by a probe: roger check warned of a parameter generate never reads, but a --set of it in
  // roger train or eval said nothing, and the trial ran in the worlds it would have run in anyway.
  res.unread_sets = run.scenario.unread_params(options.sets);
  res.explain = options.explain;
  res.wall_s = seconds_since(t0);
  return res;
}

namespace {

// The scenario parameters a policy's trial trained with beyond its stage's and context's: those
// of the file's extra.params that differ from what the stage and context give now, less those
// `sets` gives (a --set of the command wins). Parameters the scenario no longer declares are left
// out.
ParamList trial_only_params(const PolicyMetadata& meta, const CurriculumStage& stage, const CurriculumContext& ctx,
                            const ParamList& sets, const SandboxLimits& limits, const std::string& policy_file,
                            ParamList* overridden = nullptr) {
  ParamList out;
  if (!meta.extra.is_object() || !meta.extra.contains("params") || !meta.extra["params"].is_object()) return out;
  ParamList now;
  make_scenario(stage, ctx, "", {}, limits, &now);
  for (const auto& param : now) {  // not a structured binding: clang 14 refuses one in a lambda
    const auto it = meta.extra["params"].find(param.first);
    if (it == meta.extra["params"].end() || !it->is_string() || it->get<std::string>() == param.second) continue;
    const auto set = std::find_if(sets.begin(), sets.end(), [&](const auto& s) { return s.first == param.first; });
    if (set == sets.end()) out.push_back({param.first, it->get<std::string>()});
    else if (overridden && set->second != it->get<std::string>()) overridden->push_back({param.first, it->get<std::string>()});
  }
  // A value the scenario refuses is the file's (found by a probe: an edited "abc" was refused
  // naming the scenario's parameter, not the file it came from).
  try {
    if (!out.empty()) make_scenario(stage, ctx, "", out, limits, nullptr);
  } catch (const Error& e) {
    throw Error(policy_file + ": field \"extra.params\": " + e.what());
  }
  return out;
}

}  // namespace

ParamList policy_trial_params(const PolicyMetadata& meta, const std::string& policy_file, const std::string& curriculum,
                              const std::string& scenario, const ParamList& sets, const SandboxLimits& limits) {
  if (meta.stage.empty() || meta.context.empty())
    throw Error(policy_file + ": the policy names no curriculum stage and context (not written by roger train?)");
  Curriculum cur = Curriculum::load(curriculum, limits);
  const CurriculumStage& stage = cur.stage(meta.stage);
  if (!scenario.empty() && scenario != stage.scenario) return {};
  return trial_only_params(meta, stage, stage.context(meta.context), sets, limits, policy_file);
}

namespace {

// "; the policy was trained with ..." when the policy file records another curriculum than
// `cur` (a policy of curricula/paper.lua given with another curriculum reads "has no stage 'T'").
std::string trained_with(const PolicyMetadata& meta, const Curriculum& cur, const std::string& policy_file,
                         const std::string& command) {
  const std::string recorded = other_curriculum(meta, cur);
  if (recorded.empty()) return "";
  if (same_curriculum_file(recorded, cur))
    return ". " + policy_file + " was trained with " + recorded + " as it was before it changed";
  return ". " + policy_file + " was trained with the curriculum " + recorded + ": give that one (" + command + " " +
         shell_word(recorded) + " --policy " + shell_word(policy_file) + (command == "roger eval" ? ")" : " ...)");
}

// The note policy_curriculum_note gives, of the curriculum `cur`.
std::string curriculum_note_of(const PolicyMetadata& meta, const Curriculum& cur) {
  const std::string recorded = other_curriculum(meta, cur);
  if (recorded.empty()) return "";
  const std::string judged = "; stage " + meta.stage + ", context " + meta.context;
  const std::string what = " judge it here (their goal, reward and time limit, and its actions' definitions)";
  if (same_curriculum_file(recorded, cur))
    return "the curriculum " + recorded + " changed since the policy was trained" + judged + " of it as it is now" +
           what;
  return "the policy was trained with the curriculum " + recorded + judged + " of this one" + what;
}

// Loads a saved policy with its stage, context and learned skills, and hands its stage run, its
// table, the first world seed, what the file says of itself and the options in force (the trial's
// own parameters among their sets: PolicyEvalOptions::trial_params) to `use`; fills `out`'s stage,
// context, scenario and parameters.
void with_policy_file(const PolicyEvalOptions& given, PolicyEvalResult& out,
                      const std::function<void(StageRun&, QTable&, uint64_t, const PolicyMetadata&,
                                               const PolicyEvalOptions&)>& use) {
  PolicyEvalOptions options = given;
  const nlohmann::json j = batch_detail::read_json_file(options.policy_file);
  PolicyMetadata meta;
  QTable::from_json(j, {}, options.policy_file, &meta);  // the metadata first, to find the stage
  if (meta.stage.empty() || meta.context.empty())
    throw Error(options.policy_file + ": the policy names no curriculum stage and context (not written by roger train?)");
  Curriculum cur = Curriculum::load(options.curriculum, options.limits);
  const CurriculumStage* found_stage = nullptr;
  const CurriculumContext* found_ctx = nullptr;
  // Named by the file and its field (found by a probe: an edited stage said "stage 'SG' has no
  // context 'DC6'" alone).
  const char* field = "field \"stage\"";
  try {
    found_stage = &cur.stage(meta.stage);
    field = "fields \"stage\" and \"context\"";
    found_ctx = &found_stage->context(meta.context);
  } catch (const Error& e) {
    throw Error(options.policy_file + ": " + field + ": " + e.what() +
                trained_with(meta, cur, options.policy_file, options.command));
  }
  const CurriculumStage& stage = *found_stage;
  const CurriculumContext& ctx = *found_ctx;
  QTable q = QTable::from_json(j, controller_names(ctx.actions), options.policy_file);
  nlohmann::json embedded =
      meta.extra.is_object() && meta.extra.contains("skills") ? meta.extra["skills"] : nlohmann::json::object();
  for (const auto& [name, file] : options.skill_files) {
    if (!embedded.contains(name)) {
      std::vector<std::string> used;
      for (auto it = embedded.begin(); it != embedded.end(); ++it) used.push_back(it.key());
      throw Error(options.policy_file + ": the policy uses no learned skill '" + name + "' to replace" +
                  (used.empty() ? std::string(" (it uses none)") : " (it uses " + join(used) + ")"));
    }
    embedded.erase(name);  // bound from the file instead (bind_skills)
  }
  for (const std::string& skill : ctx.learned)
    if (!embedded.contains(skill) && !options.skill_files.count(skill))
      throw Error(options.policy_file + ": field \"extra.skills\" does not hold the learned skill '" + skill +
                  "' its context " + ctx.name + " uses (a policy roger train wrote embeds it; give one with --skill " +
                  skill + "=FILE.json)");
  std::vector<SkillSource> sources;
  TrainOptions topt;
  topt.limits = options.limits;
  topt.skill_files = options.skill_files;
  bind_skills(cur, ctx, topt, &embedded, sources);
  out.skills = sources;
  out.stage = stage.name;
  out.context = ctx.name;
  out.trained_curriculum = other_curriculum(meta, cur);  // found by a probe: judged by another's goal, unsaid
  // Found by a probe: a curriculum edited in place was said to be "another", naming itself.
  out.trained_curriculum_edited = !out.trained_curriculum.empty() && same_curriculum_file(out.trained_curriculum, cur);
  out.curriculum_note = curriculum_note_of(meta, cur);
  if (options.scenario.empty() || options.scenario == stage.scenario) {
    out.stage_params = stage.scenario_params(ctx);
    out.scenario_note = stage.scenario_note();  // found by a probe: train said it, eval did not
  }
  out.time_limit = stage.time_limit_text();
  out.stage_test_tasks = stage.teaches() ? stage.final_test_tasks() : 0;
  if (options.trial_params) {
    ParamList overridden;
    const ParamList trial = trial_only_params(meta, stage, ctx, options.sets, options.limits, options.policy_file,
                                              &overridden);
    if (options.scenario.empty() || options.scenario == stage.scenario) {
      out.trial_sets = trial;
      out.trial_sets_overridden = overridden;
      options.sets.insert(options.sets.begin(), trial.begin(), trial.end());
    } else {
      out.trial_sets_left = trial;
    }
  }
  StageRun run{cur, stage, ctx, make_scenario(stage, ctx, options.scenario, options.sets, options.limits, &out.params),
               Agent(WorldParams{}, options.agent)};
  cur.set_world(&run.agent.world());
  out.scenario = run.scenario.name();
  out.scenario_file = run.scenario.path();
  // The trial's parameters another scenario declares first: a --set can play those (found by a
  // probe: the note advised --set for parameters the scenario then refused as unknown).
  std::set<std::string> declared;
  for (const ScenarioParam& p : run.scenario.params()) declared.insert(p.name);
  const auto left_declared = std::stable_partition(out.trial_sets_left.begin(), out.trial_sets_left.end(),
                                                   [&](const auto& kv) { return declared.count(kv.first) > 0; });
  out.trial_sets_left_declared = size_t(left_declared - out.trial_sets_left.begin());
  use(run, q, (options.first_seed >= 0 ? uint64_t(options.first_seed) : stage.checkpoints.seeds) + options.seed_offset,
      meta, options);
  out.source_files = run.files_read();
  out.unread_sets = run.scenario.unread_params(given.sets);  // the command's own, not the trial's added above
}

// Psi and the controllers inside it, breadth first, each once, at most `limit`. A part is held
// through its action (an aliasing pointer: the action owns it).
std::vector<ControllerPtr> watched_controllers(const std::vector<ControllerPtr>& psi, size_t limit) {
  std::vector<ControllerPtr> out;
  std::vector<ControllerPtr> layer = psi;
  while (!layer.empty() && out.size() < limit) {
    std::vector<ControllerPtr> next;
    for (const ControllerPtr& c : layer) {
      const bool seen = std::any_of(out.begin(), out.end(), [&](const ControllerPtr& o) { return o.get() == c.get(); });
      if (out.size() >= limit || seen) continue;
      out.push_back(c);
      for (const Controller* child : c->children()) next.push_back(ControllerPtr(c, const_cast<Controller*>(child)));
    }
    layer = std::move(next);
  }
  return out;
}

// The test set a policy file records (train_policy_json): where its worlds start and each task's
// parameters in the order they were set.
struct TestSet {
  bool recorded = false;
  uint64_t first_seed = 0;
  std::vector<ParamList> tasks;
};

TestSet saved_test_set(const PolicyMetadata& meta, const std::string& file) {
  TestSet t;
  if (!meta.extra.is_object() || !meta.extra.contains("test_set")) return t;
  try {
    const nlohmann::json& j = meta.extra.at("test_set");
    t.first_seed = j.at("first_seed").get<uint64_t>();
    t.tasks = j.at("tasks").get<std::vector<ParamList>>();
  } catch (const nlohmann::json::exception& e) {
    throw Error(file + ": field \"test_set\" must hold first_seed and tasks, lists of [name, value] pairs "
                "(train_policy_json): " + json_error_text(e.what()));
  }
  t.recorded = true;
  return t;
}

// A --set of a parameter the saved test tasks set would be overwritten by each task: refused.
void check_sets_leave_tasks(const ParamList& sets, const std::vector<ParamList>& tasks, const std::string& file) {
  for (const auto& [k, v] : sets)
    for (const ParamList& task : tasks)
      for (const auto& p : task)
        if (p.first == k)
          throw Error("--set " + k + "=" + v + ": the test set's tasks (" + file + ") set " + k +
                      " themselves, and run as they were: give another parameter, or run without the test set");
}

// The test set a saved policy's trial ended on, for --test-set: the tasks its file keeps, else
// (a file from before roger kept them) the curriculum's, as a trial of the stage makes them now.
// Fills `out`'s test_tasks, test_set_source and test_set_changed; returns the first world seed.
uint64_t resolve_test_set(StageRun& run, const PolicyMetadata& meta, const PolicyEvalOptions& options,
                          PolicyEvalResult& out) {
  const TestSet saved = saved_test_set(meta, options.policy_file);
  // The command's --set, less the trial's own parameters set beside them (out.trial_sets): those
  // the test tasks set themselves (an LCAS lift's last level) are the tasks', not the command's.
  ParamList command_sets;
  for (const auto& set : options.sets)
    if (std::find(out.trial_sets.begin(), out.trial_sets.end(), set) == out.trial_sets.end()) command_sets.push_back(set);
  if (saved.recorded) check_sets_leave_tasks(command_sets, saved.tasks, options.policy_file);
  // The test set as a trial of the stage makes it now (TrialTeacher: the space less the --set
  // parameters, the teacher's own parameters beside it), on the same world seeds. The trial's own
  // parameters count as its --set did (a task axis it fixed left its space), but for those its
  // test tasks set themselves.
  ParamList trial_sets = command_sets;
  for (const auto& set : out.trial_sets) {
    const bool tasks_set_it = std::any_of(saved.tasks.begin(), saved.tasks.end(), [&](const ParamList& task) {
      return std::any_of(task.begin(), task.end(), [&](const auto& p) { return p.first == set.first; });
    });
    if (!tasks_set_it) trial_sets.push_back(set);
  }
  std::vector<ParamList> now;
  bool made_now = run.stage.teaches();
  if (made_now) {
    try {
      TrainOptions topt;
      topt.sets = trial_sets;
      const TrialTeacher teacher(run.cur, run.stage, topt);
      const EvalWorlds worlds = teacher.worlds(run.stage.checkpoints.seeds, true);
      for (size_t i = 0; i < size_t(worlds.episodes); ++i) now.push_back(worlds.task(i));
    } catch (const Error&) {
      if (!saved.recorded) throw;
      made_now = false;  // the file's tasks are run all the same; the curriculum's could not be made
    }
  }
  if (!saved.recorded) {
    if (!run.stage.teaches())
      throw Error(run.stage.where() + " has no test set: it has no task space or teacher, so its trials end on "
                  "its held-out seeds (so --test-set, and roger render's --test-task, have no tasks to run)");
    out.test_set_source = "the curriculum (" + options.policy_file + " records none: written by an earlier roger)";
    out.test_tasks = std::move(now);
    return run.stage.checkpoints.seeds;
  }
  // The tasks the trial's final evaluation ran, as its policy file keeps them: the curriculum's
  // test set may have been edited since, and the measure is of the policy on those.
  out.test_tasks = saved.tasks;
  out.test_set_source = options.policy_file;
  out.test_set_changed = !made_now || now != saved.tasks || saved.first_seed != run.stage.checkpoints.seeds;
  return saved.first_seed;
}

}  // namespace

std::string policy_curriculum_note(const PolicyMetadata& meta, const std::string& curriculum,
                                   const SandboxLimits& limits) {
  return curriculum_note_of(meta, Curriculum::load(curriculum, limits));
}

PolicyEvalResult evaluate_policy_file(const PolicyEvalOptions& given) {
  PolicyEvalResult out;
  with_policy_file(given, out, [&](StageRun& run, QTable& q, uint64_t first, const PolicyMetadata& meta,
                                   const PolicyEvalOptions& options) {
    if (!options.test_set) {
      const int episodes = options.episodes > 0 ? options.episodes : run.stage.checkpoints.final_episodes;
      out.eval = greedy_eval(run, q, EvalWorlds{first, episodes}, "evaluation", nullptr, options.keep_episodes);
      return;
    }
    const uint64_t first_seed = resolve_test_set(run, meta, options, out);
    out.eval = greedy_eval(run, q, EvalWorlds{first_seed, int(out.test_tasks.size()), nullptr, nullptr, {}, &out.test_tasks},
                           "evaluation", nullptr, options.keep_episodes);
  });
  return out;
}

RecordedPolicyEpisode record_policy_episode(const PolicyEvalOptions& given, double record_every,
                                            size_t watch_limit) {
  RecordedPolicyEpisode r;
  with_policy_file(given, r.about, [&](StageRun& run, QTable& q, uint64_t seed, const PolicyMetadata& meta,
                                       const PolicyEvalOptions& options) {
    if (options.test_task > 0) {
      // Test task k of the trial's test set, in its own world seed, as its final evaluation ran it.
      const uint64_t first = resolve_test_set(run, meta, options, r.about);
      if (size_t(options.test_task) > r.about.test_tasks.size())
        throw Error("--test-task " + std::to_string(options.test_task) + ": the test set has " +
                    std::to_string(r.about.test_tasks.size()) + " tasks (from " + r.about.test_set_source + ")");
      set_params(run.scenario, r.about.test_tasks[size_t(options.test_task - 1)], {});
      seed = first + uint64_t(options.test_task - 1);
    }
    // Twice the rows shown are watched, so that rows repeating others (distinct_traces) leave
    // their places to the next ones.
    const std::vector<ControllerPtr> watch = watched_controllers(run.ctx.actions, 2 * watch_limit);
    const auto recorder = make_recorder(r.episode, watch, record_every, run.agent.world().tick_seconds());
    Rng unused(0);
    const TrainingEpisode ep = run.run(q, seed, 0.0, unused, false, "render", 0, recorder.get());
    r.spec = run.scenario.generate(seed);
    r.episode.seed = seed;
    r.episode.success = ep.success;
    r.episode.reward = ep.reward;
    r.episode.sim_seconds = ep.sim_seconds;
    r.episode.ticks = ep.ticks;
    r.episode.gammas = distinct_traces(std::move(r.episode.gammas), watch_limit);
  });
  return r;
}

}  // namespace roger
