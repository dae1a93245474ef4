// environment.cpp: a stage as an environment (StageEnvironment) and many of them on threads
// (VecEnvironment), over the episode loop and the semi-MDP driver that training uses.
#include "batch/environment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#if defined(__SSE__) || defined(__x86_64__)
#include <xmmintrin.h>
#endif

#include "batch/batch_internal.h"
#include "core/error.h"
#include "learn/episode.h"
#include "script/authoring/lua_static_check.h"
#include "script/batch/batch_script.h"
#include "script/curriculum/curriculum.h"
#include "script/scenario/scenario.h"

namespace roger {

using batch_detail::StageHooks;

namespace {

// "with the parameters given (robot_distance=99, shape=spade)" of a world's message: make's params
// and a task's over them; "with the stage's own parameters" when none.
std::string params_given(const ParamList& sets, const ParamList& task) {
  std::string text;
  auto add = [&](const std::string& key, const std::string& value) {
    text += (text.empty() ? "" : ", ") + key + "=" + value;
  };
  for (const auto& set : sets)  // a pair, not a structured binding: a lambda cannot capture those (C++17)
    if (std::none_of(task.begin(), task.end(), [&](const auto& p) { return p.first == set.first; }))
      add(set.first, set.second);
  for (const auto& [key, value] : task) add(key, value);
  return text.empty() ? "with the stage's own parameters" : "with the parameters given (" + text + ")";
}

// "file:line: " of a script's error, "" when it has no file.
std::string located(const ScriptError& e) {
  return e.file.empty() ? "" : e.file + (e.line > 0 ? ":" + std::to_string(e.line) : "") + ": ";
}

// The world of `seed`, an error building it given `prefix` in front (which seed, stage and
// parameters): one that cannot be placed as PlacementError (a teacher's reset skips its task), any
// other as ScriptError, its traceback kept (found by a probe: make's params={'goal_x': -1e9} said
// only place.lua's line and the arena, not which call or parameter).
WorldSpec built_world(Scenario& scenario, uint64_t seed, const std::string& prefix) {
  try {
    return scenario.generate(seed);
  } catch (const PlacementError& e) {
    throw placement_error(e, prefix);
  } catch (const ScriptError& e) {
    ScriptError out(prefix + located(e) + e.message, "", 0, e.traceback);
    out.message = e.message;
    out.file = e.file;
    out.line = e.line;
    throw out;
  }
}

}  // namespace

#if defined(__SSE__) || defined(__x86_64__)
EngineFloatMode::EngineFloatMode() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | 0x8040u); }  // FTZ | DAZ
EngineFloatMode::~EngineFloatMode() { _mm_setcsr(saved_); }
#else
EngineFloatMode::EngineFloatMode() = default;
EngineFloatMode::~EngineFloatMode() = default;
#endif

// The loaded stage and the running episode. The driver is the training driver with learning off
// and its decisions given from outside; its table is never read.
struct StageEnvironment::Impl {
  Curriculum cur;
  const CurriculumStage& stage;
  const CurriculumContext& ctx;
  Scenario scenario;
  Agent agent;
  QTable table;
  Rng unused{0};
  StageHooks hooks;
  SemiMdpDriver driver;
  std::optional<EpisodeRun> run;
  bool ended = false;  // the episode ended (or failed): step() needs a reset first
  bool faulted = false;  // it was ended by an error (a Lua fault), not by its stage
  std::map<std::string, std::string> base;  // the stage's value of each parameter a task has set

  // Sets a task's parameters on the scenario, and the stage's back on those it leaves out.
  void set_task(const ParamList& task) {
    for (const auto& stage_value : base) {
      const std::string& key = stage_value.first;  // named: clang 14 cannot capture a binding
      if (std::none_of(task.begin(), task.end(), [&](const auto& p) { return p.first == key; }))
        scenario.set_param(key, stage_value.second);
    }
    for (const auto& [key, value] : task) {
      if (!base.count(key))
        for (const ScenarioParam& p : scenario.params())
          if (p.name == key) base[key] = p.value;
      scenario.set_param(key, value);
    }
  }

  Impl(Curriculum c, const std::string& stage_name, const std::string& context, const EnvironmentOptions& o,
       EnvironmentInfo& info)
      : cur(std::move(c)),
        stage(cur.stage(stage_name)),
        ctx(stage.context(context)),
        scenario(batch_detail::make_scenario(stage, ctx, o.scenario, o.sets, o.limits, &info.params)),
        table(controller_names(ctx.actions), stage.learner),
        hooks(cur, stage, ctx),
        driver(ctx.actions, stage.absorbing.get(), table, 0.0, unused, stage.rewards, false, &hooks) {
    driver.choose_externally(true);
    driver.decide_every_tick(o.per_tick);
    cur.set_world(&agent.world());  // the Lua callbacks' `world`
  }

  // Binds the skills the context uses: a skill given by a file from it, the others from the
  // embedded ones.
  void bind_context_skills(const EnvironmentOptions& o) {
    TrainOptions topt;
    topt.skill_files = o.skill_files;
    topt.limits = o.limits;
    std::vector<SkillSource> sources;
    nlohmann::json embedded = o.embedded_skills.is_object() ? o.embedded_skills : nlohmann::json::object();
    for (const auto& given : o.skill_files) embedded.erase(given.first);
    batch_detail::bind_skills(cur, ctx, topt, embedded.empty() ? nullptr : &embedded, sources);
  }

  // The stage's first held-out world, which gives the body.
  WorldSpec held_out_world(const EnvironmentOptions& o) {
    return built_world(scenario, stage.checkpoints.seeds,
                       "could not build the world of seed " + std::to_string(stage.checkpoints.seeds) + " of " +
                           stage.where(ctx.name) + " (its first held-out world, which gives the body) " +
                           params_given(o.sets, {}) + ": ");
  }

  // Ticks until the driver waits for a decision or the episode ends. An error ends the episode.
  void advance() {
    try {
      while (run->tick()) {
      }
      if (!run->paused()) {
        ended = true;
        run->finish();
      }
    } catch (...) {
      ended = faulted = true;
      throw;
    }
  }
};

namespace {

// Every learned skill the context uses must come from a file: an environment trains nothing.
void check_skills_given(const CurriculumContext& ctx, const CurriculumStage& stage, const EnvironmentOptions& o) {
  for (const auto& name : ctx.learned)
    if (!o.skill_files.count(name) && !(o.embedded_skills.is_object() && o.embedded_skills.contains(name)))
      throw Error(stage.where(ctx.name) + " uses the learned skill '" + name +
                  "': give its policy file, skills={'" + name + "': '.../policy.json'} (roger train writes one)");
}

// Refuses a script of another kind given as the curriculum, as roger train does (found by a probe:
// make("docs/examples/corridor.lua", ...) failed inside scenarios/lib/shapes.lua, a skill script
// with "unknown field 'policies'"), and a member of roger.* that no curriculum has in make's
// tasks or teacher text, as roger check's static pass names it (teacher='roger.teacher.nosuch{}'
// read "attempt to call a nil value (field 'nosuch')", not which teachers there are).
// `given`, if `resolve` finds it, must be a script of kind `kind`; one found nowhere is left to the
// loader, which says where it looked.
void require_kind_if_found(const std::string& given, std::string (*resolve)(const std::string&), const char* kind,
                           const std::string& option) {
  std::string path;
  try {
    path = resolve(given);
  } catch (const Error&) {
    return;
  }
  require_script_kind(given, path, {kind}, option);
}

void check_sources(const EnvironmentOptions& o) {
  require_kind_if_found(o.curriculum, resolve_curriculum_path, "curriculum", "");
  // A curriculum given as the scenario failed inside it (found by a probe: make(scenario=
  // "curricula/paper.lua") raised "skills.lua:45: attempt to call a nil value").
  if (!o.scenario.empty()) require_kind_if_found(o.scenario, resolve_scenario_path, "scenario", "scenario=");
  for (const LuaSource* source : {&o.tasks, &o.teacher})
    if (!source->text.empty())
      for (const StaticProblem& p : static_check_text("return " + source->text, source->name, ScriptKind::kCurriculum))
        if (p.message.find("is not in the API") != std::string::npos) throw ScriptError(p.message, source->name, p.line, "");
}

// A teacher or tasks text that failed on a name nothing defines (found by a probe: teacher="alp_gmm"
// said "gives no value for 'teacher': write a value", and "alp_gmm{}" "attempt to call a nil value"):
// said as a stage's script is told it, with the way to write a teacher or an axis.
void explain_undefined_name(const EnvironmentOptions& o, const ScriptError& e) {
  // Only a failure a nil explains: a name the curriculum defines is one this pass cannot see.
  const std::string& m = e.message;
  if (m.rfind("gives no value", 0) != 0 && m.find("a nil value (global '") == std::string::npos) return;
  for (const LuaSource* source : {&o.tasks, &o.teacher}) {
    if (source->text.empty() || e.file != source->name) continue;
    for (const StaticProblem& p : static_check_text("return " + source->text, source->name, ScriptKind::kCurriculum)) {
      const std::string head = "undefined global '";
      if (p.message.rfind(head, 0) != 0) continue;
      const std::string name = p.message.substr(head.size(), p.message.find('\'', head.size()) - head.size());
      const auto among = [&](const std::vector<std::string>& names) {
        return std::find(names.begin(), names.end(), name) != names.end();
      };
      const std::string how = among(teaching_names(true))    ? "; a teacher is written roger.teacher." + name + "{...}"
                              : among(teaching_names(false)) ? "; an axis is written roger." + name + "(...)"
                                                             : "";
      throw ScriptError(p.message + how, source->name, p.line, "");
    }
  }
}

Curriculum load_checked(const EnvironmentOptions& o) {
  check_sources(o);
  Curriculum cur = Curriculum::load(o.curriculum, o.limits);
  try {
    cur.set_teaching(o.stage, o.tasks, o.teacher, o.scenario);
  } catch (const ScriptError& e) {
    explain_undefined_name(o, e);
    throw;
  }
  const CurriculumStage& stage = cur.stage(o.stage);
  check_skills_given(stage.context(o.context), stage, o);
  return cur;
}

// What the stage says of its episodes, its learner and its checkpoints, in the environment's info.
void describe_stage(const CurriculumStage& st, EnvironmentInfo& info) {
  info.stage = st.name;
  info.time_limit = st.time_limit;
  info.time_per_object = st.time_per_object;
  info.budget_episodes = st.budget_episodes;
  info.learner = st.learner;
  info.discount_seconds = st.rewards.discount_seconds;
  info.checkpoint_every = st.checkpoints.every;
  info.checkpoint_episodes = st.checkpoints.episodes;
  info.threshold = st.checkpoints.threshold;
  info.checkpoint_seeds = st.checkpoints.seeds;
  info.stop_after = st.checkpoints.stop_after;
  info.settle = st.checkpoints.settle;
  info.final_episodes = st.checkpoints.final_episodes;
}

// The parameters make's params fix (as a trial of `roger train` has them: they do not vary). A
// task space given with them (make(tasks=...)) that varies one of them is refused, as the
// curriculum refuses a stage's tasks over its own params: one of the two would be dropped silently.
std::vector<std::string> fixed_params(const EnvironmentOptions& o, const CurriculumStage& st) {
  std::vector<std::string> fixed;
  for (const auto& [key, value] : o.sets) fixed.push_back(key);
  if (!o.tasks.empty())
    for (const std::string& key : fixed)
      if (st.tasks.index(key) >= 0)
        throw Error(st.where() + ": " + o.tasks.name + " varies '" + key + "', which make's params fix (" + key +
                    "=" + std::find_if(o.sets.begin(), o.sets.end(), [&](const auto& p) { return p.first == key; })
                              ->second + "); remove one of them");
  return fixed;
}

}  // namespace

StageEnvironment::StageEnvironment(const EnvironmentOptions& o) {
  const EngineFloatMode mode;
  impl_ = std::make_unique<Impl>(load_checked(o), o.stage, o.context, o, info_);
  const CurriculumStage& st = impl_->stage;
  impl_->bind_context_skills(o);
  info_.curriculum = impl_->cur.path();
  describe_stage(st, info_);
  info_.context = impl_->ctx.name;
  info_.scenario = impl_->scenario.name();
  for (const ScenarioParam& p : impl_->scenario.params()) info_.param_types[p.name] = p.type;
  info_.actions = controller_names(impl_->ctx.actions);
  info_.tick_seconds = impl_->agent.world().tick_seconds();
  sets_ = o.sets;
  const std::vector<std::string> fixed = fixed_params(o, st);
  // The body is the world's (a scenario parameter, the same in every world of the stage's
  // scenarios): the tick mode's image shapes and joint ranges follow the held-out worlds' body.
  const WorldSpec held_out = impl_->held_out_world(o);
  info_.eye_pixels = held_out.eyes.pixels;
  observed_joint_ranges(held_out.body, info_.joint_low, info_.joint_high);
  // (An ALP-GMM teacher left no axis is refused where it is made, with make's own way out.)
  // Without a teacher the parameter it would lift is the params' to fix (found by a probe: a policy
  // trained under LCAS records its last level, and policy.make() gave it back with teacher=False).
  if (o.teaching && st.teacher && st.teacher->kind == TeacherSpec::Kind::kLcas) try {
      st.check_fixed(fixed, "make's params");
    } catch (const ScriptError& e) {
      throw ScriptError(e.message + ", or give teacher=False for none", e.file, e.line, e.traceback);
    }
  task_space_ = st.tasks.without(fixed);
  if (o.teaching && !(o.tasks.empty() && o.teacher.empty())) check_task_space_ends(o);
}

// make's own task space, or teacher, refused at make when the parameters at one of its ends give
// no world, as roger check refuses a stage's (found by a probe: tasks={'goal_x': real(-10, 10)} was
// taken, and every reset then failed with the arena's error). A task no layout holds is not
// refused: its reset skips it.
void StageEnvironment::check_task_space_ends(const EnvironmentOptions& o) const {
  CurriculumStage st = impl_->stage;
  if (!o.scenario.empty()) st.scenario = o.scenario;
  const std::vector<std::string> problems = task_space_end_problems(st, impl_->ctx.name, o.limits, o.sets);
  if (!problems.empty()) throw ScriptError(join(problems, "\n"), "", 0, "");  // each names its file:line
}

PlacementError placement_error(const PlacementError& e, const std::string& prefix) {
  return with_text(e, prefix + located(e) + e.message);
}

PlacementError with_text(const PlacementError& e, const std::string& text) {
  PlacementError out(ScriptError(text, "", 0, ""));
  out.message = e.message;
  out.file = e.file;
  out.line = e.line;
  out.traceback = e.traceback;
  return out;
}

bool StageEnvironment::teaches() const { return impl_->stage.teaches(); }

void StageEnvironment::check_played_in(const std::string& scenario) const {
  impl_->stage.check_played_in(scenario, task_space_);
}

std::optional<TeacherBodyChange> StageEnvironment::teacher_body_change() {
  const CurriculumStage& st = impl_->stage;
  // Only an LCAS teacher sets a parameter beside the task space (a task space's own body axes are
  // the package's to refuse at make, from its dims).
  if (!st.teacher || st.teacher->kind != TeacherSpec::Kind::kLcas || task_space_.index(st.teacher->lift) >= 0)
    return std::nullopt;
  const TeacherSpec& t = *st.teacher;
  const EngineFloatMode mode;
  std::optional<TeacherBodyChange> change;
  for (const std::string& level : t.levels) {
    impl_->set_task({{t.lift, level}});
    WorldSpec w;
    try {
      w = impl_->scenario.generate(st.checkpoints.seeds);
    } catch (const PlacementError&) {
      continue;  // a level the scenario cannot place here: the teacher's resets skip such tasks
    }
    std::array<double, kDofCount> low, high;
    observed_joint_ranges(w.body, low, high);
    std::string misfit;
    if (w.eyes.pixels != info_.eye_pixels)
      misfit = "eyes of " + std::to_string(w.eyes.pixels) + " pixels, where observation_space's images have " +
               std::to_string(info_.eye_pixels) + " (stage_info['eye_pixels'])";
    else if (low != info_.joint_low || high != info_.joint_high)
      misfit = "other joint ranges than observation_space's (stage_info['joint_low'], ['joint_high'])";
    if (misfit.empty()) continue;
    change = TeacherBodyChange{t.name() + (t.file.empty() ? "" : " (" + t.file + ":" + std::to_string(t.line) + ")"),
                               t.lift, t.levels, level, misfit};
    break;
  }
  impl_->set_task({});
  return change;
}

std::unique_ptr<Teacher> StageEnvironment::make_teacher(uint64_t seed) {
  const CurriculumStage& st = impl_->stage;
  if (st.teacher && st.teacher->kind == TeacherSpec::Kind::kPlr && st.teacher->score_td)
    throw Error(st.where() + ": " + st.teacher->name() + " scores levels by the engine learner's TD errors " +
                "(score = \"td\", plr's default), which an environment stepped from outside does not have: give it "
                "score = \"success\" from Python, roger.make(..., teacher='roger.teacher.plr{score = \"success\"}') "
                "(with the stage's other plr settings inside the braces), or teacher=False for none");
  try {
    return impl_->cur.make_teacher(impl_->stage, task_space_, seed);
  } catch (const ScriptError&) {
    throw;
  } catch (const Error& e) {
    // A teacher that needs a task space, whose every axis make's params fixed: say so, by name.
    if (!task_space_.empty() || st.tasks.empty()) throw;
    std::string axes;
    for (const TaskDim& d : st.tasks.dims()) axes += (axes.empty() ? "'" : ", '") + d.name + "'";
    throw Error(std::string(e.what()) + ": make's params fix every axis of the stage's task space (" + axes +
                "); leave one of them out of params, or give teacher=False");
  }
}

void observed_joint_ranges(const RobotParams& body, std::array<double, kDofCount>& low,
                           std::array<double, kDofCount>& high) {
  const double inf = std::numeric_limits<double>::infinity();
  low = {-inf, -M_PI, -body.eye_pan_limit, -body.eye_pan_limit,
         body.shoulder_min, body.elbow_min, -body.shoulder_max, -body.elbow_max};
  high = {inf, M_PI, body.eye_pan_limit, body.eye_pan_limit,
          body.shoulder_max, body.elbow_max, -body.shoulder_min, -body.elbow_min};
}

StageEnvironment::~StageEnvironment() = default;

const std::vector<Gamma>& StageEnvironment::reset(uint64_t seed) { return reset(seed, ParamList()); }

const std::vector<Gamma>& StageEnvironment::reset(uint64_t seed, const ParamList& task) {
  const EngineFloatMode mode;
  Impl& m = *impl_;
  m.ended = true;  // until the new episode is running
  m.faulted = false;
  m.run.reset();
  seed_ = seed;
  m.set_task(task);
  const WorldSpec spec = built_world(m.scenario, seed,
                                     "could not build the world of seed " + std::to_string(seed) + " of " +
                                         m.stage.where(m.ctx.name) + " " + params_given(sets_, task) + ": ");
  m.run.emplace(m.agent, spec, seed, m.driver, m.stage.episode_time_limit(spec));
  m.ended = false;
  m.advance();
  return m.driver.gammas();
}

EnvironmentStep StageEnvironment::step(int action) {
  const EngineFloatMode mode;
  Impl& m = *impl_;
  if (!m.run)
    throw Error("step: no episode is running in " + info_.stage + "/" + info_.context + " (call reset first)");
  if (m.ended && m.faulted)
    throw Error("step: the episode in " + info_.stage + "/" + info_.context +
                " is over: an error ended it (the ScriptError or RogerError an earlier step or reset raised, "
                "not terminated or truncated); call reset for the next");
  if (m.ended)
    throw Error("step: the episode in " + info_.stage + "/" + info_.context +
                " is over (it ended with terminated or truncated; call reset for the next)");
  m.driver.act(action);  // checks the index
  m.advance();
  EnvironmentStep r;
  r.reward = m.driver.transition_reward();
  if (m.ended) {
    r.terminated = true;
    r.time_out = !m.driver.episode().success;
  }
  return r;
}

void StageEnvironment::replay(uint64_t seed, const std::vector<int>& actions, const ParamList& task) {
  reset(seed, task);
  for (int a : actions) step(a);
}

const std::vector<Gamma>& StageEnvironment::state() const { return impl_->driver.gammas(); }
bool StageEnvironment::running() const { return impl_->run && !impl_->ended; }
bool StageEnvironment::begun() const { return impl_->run.has_value(); }
double StageEnvironment::sim_seconds() const { return impl_->agent.world().time(); }
int StageEnvironment::ticks() const { return impl_->run ? impl_->run->ticks() : 0; }
const TrainingEpisode& StageEnvironment::episode() const { return impl_->driver.episode(); }
const Agent& StageEnvironment::agent() const { return impl_->agent; }

// ---- VecEnvironment ----

VecEnvironment::VecEnvironment(const EnvironmentOptions& options, int n, int threads, Autoreset autoreset)
    : autoreset_(autoreset) {
  if (n < 1) throw Error("make_vec: num_envs must be at least 1, got " + std::to_string(n));
  if (threads < 1) throw Error("make_vec: threads must be at least 1, got " + std::to_string(threads));
  threads_ = std::min(threads, n);
  for (int i = 0; i < n; ++i) envs_.push_back(std::make_unique<StageEnvironment>(options));
  slots_.resize(size_t(n));
  for (int i = 0; i < n; ++i) slots_[size_t(i)].base_seed = uint64_t(i);
  errors_.resize(size_t(n));
  for (int t = 1; t < threads_; ++t) workers_.emplace_back([this] { worker(); });
}

VecEnvironment::~VecEnvironment() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    quit_ = true;
  }
  wake_.notify_all();
  for (auto& w : workers_) w.join();
}

// An episode that ends before its first decision (a Lua absorbing function that holds at once) is
// skipped: a learner has nothing to decide in it.
void VecEnvironment::begin(int i) {
  Slot& s = slots_[size_t(i)];
  s.needs_reset = false;
  s.restarted = true;
  for (int tries = 0; tries < 1000; ++tries) {
    envs_[size_t(i)]->reset(s.base_seed + s.started++ * envs_.size());
    if (envs_[size_t(i)]->running()) return;
  }
  s.needs_reset = true;
  throw Error("1000 episodes in a row ended before their first decision (its absorbing function holds at once)");
}

void VecEnvironment::keep_last(int i) {
  const StageEnvironment& env = *envs_[size_t(i)];
  Slot& s = slots_[size_t(i)];
  s.ended = true;
  s.last_state = env.state();
  s.last_seed = env.seed();
  s.last_sim_s = env.sim_seconds();
  s.last_ticks = env.ticks();
  s.last_decisions = env.episode().decisions;
  s.last_reward = env.episode().reward;
  s.last_success = env.episode().success;
}

void VecEnvironment::step_one(int i) {
  Slot& s = slots_[size_t(i)];
  if (s.needs_reset) return begin(i);  // next-step autoreset (or a fault's successor): the action is ignored
  const StageEnvironment& env = *envs_[size_t(i)];
  s.result = envs_[size_t(i)]->step(int(actions_[i]));
  // At the cap the episode is truncated, whether its stage ended it in the same decision or not
  // (Gymnasium's TimeLimit: both flags then).
  s.truncated = most_decisions_ > 0 && env.episode().decisions >= most_decisions_;
  if (env.running() && !s.truncated) return;
  keep_last(i);
  if (autoreset_ == Autoreset::kSameStep) return begin(i);
  s.needs_reset = true;
}

void VecEnvironment::job(int i) {
  Slot& s = slots_[size_t(i)];
  s.result = {};
  s.restarted = s.ended = s.failed = s.truncated = false;
  try {
    if (!resetting_) return step_one(i);
    if (s.reset_requested) begin(i);
  } catch (...) {
    errors_[size_t(i)] = std::current_exception();
    if (!s.ended && !resetting_) keep_last(i);
    s.failed = true;
    s.needs_reset = true;
  }
}
void VecEnvironment::run_jobs() {
  for (int i = next_++; i < size(); i = next_++) job(i);
}

void VecEnvironment::worker() {
  uint64_t seen = 0;
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return quit_ || generation_ != seen; });
      if (quit_) return;
      seen = generation_;
    }
    run_jobs();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      --busy_;
    }
    done_.notify_one();
  }
}

// Hands the environments out one at a time (a long decision in one does not hold up the others'
// share), the caller's thread working too, and waits for every worker.
void VecEnvironment::run_all() {
  for (auto& e : errors_) e = nullptr;
  next_ = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    busy_ = int(workers_.size());
    ++generation_;
  }
  wake_.notify_all();
  run_jobs();
  {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [&] { return busy_ == 0; });
  }
}

// The error of the lowest environment that failed in the last call, if any.
void VecEnvironment::rethrow_first() const {
  for (auto& e : errors_)
    if (e) std::rethrow_exception(e);
}

namespace {

void write_state(const std::vector<Gamma>& g, uint8_t* out) {
  for (size_t a = 0; a < g.size(); ++a) out[a] = uint8_t(g[a]);
}

}  // namespace

void VecEnvironment::write_now(const Episodes& out) const {
  const size_t k = info().actions.size();
  for (size_t i = 0; i < envs_.size(); ++i) {
    const StageEnvironment& env = *envs_[i];
    write_state(env.state(), out.states + i * k);
    out.seeds[i] = env.seed();
    out.sim_seconds[i] = env.sim_seconds();
    out.ticks[i] = env.ticks();
    out.decisions[i] = env.episode().decisions;
  }
}

void VecEnvironment::reset(const ResetRequest& request, const Episodes& out) {
  for (size_t i = 0; i < envs_.size(); ++i) {
    Slot& s = slots_[i];
    s.reset_requested = !request.mask || request.mask[i];
    if (s.reset_requested && request.seeded && request.seeded[i]) {
      s.base_seed = request.seeds[i];
      s.started = 0;
    }
  }
  resetting_ = true;
  run_all();
  write_now(out);
  rethrow_first();
}

void VecEnvironment::step(const int64_t* actions, const StepOutput& out) {
  const size_t k = info().actions.size();
  for (size_t i = 0; i < envs_.size(); ++i) {
    if (slots_[i].needs_reset && autoreset_ == Autoreset::kDisabled)
      throw Error("step: the episode of environment " + std::to_string(i) +
                  " is over and autoreset is disabled: reset it first (options={'reset_mask': ...})");
    if (!slots_[i].needs_reset && (actions[i] < 0 || actions[i] >= int64_t(k)))
      throw Error("step: action " + std::to_string(actions[i]) + " of environment " + std::to_string(i) +
                  " is not in [0, " + std::to_string(k) + ")");
  }
  resetting_ = false;
  actions_ = actions;
  run_all();
  write_now(out.now);
  for (size_t i = 0; i < envs_.size(); ++i) {
    const Slot& s = slots_[i];
    out.rewards[i] = s.result.reward;
    out.terminated[i] = s.result.terminated;
    out.time_out[i] = s.result.time_out;
    out.restarted[i] = s.restarted;
    out.ended[i] = s.ended;
    out.failed[i] = s.failed;
    out.truncated[i] = s.truncated;
    for (size_t a = 0; a < k; ++a) out.last.states[i * k + a] = s.ended ? uint8_t(s.last_state[a]) : 0;
    out.last.seeds[i] = s.ended ? s.last_seed : 0;
    out.last.sim_seconds[i] = s.ended ? s.last_sim_s : 0.0;
    out.last.ticks[i] = s.ended ? s.last_ticks : 0;
    out.last.decisions[i] = s.ended ? s.last_decisions : 0;
    out.episode_rewards[i] = s.ended ? s.last_reward : 0.0;
    out.success[i] = s.ended && s.last_success;
  }
  rethrow_first();
}

std::vector<VecEnvironment::Snapshot> VecEnvironment::snapshot() const {
  std::vector<Snapshot> out(envs_.size());
  for (size_t i = 0; i < envs_.size(); ++i) {
    const StageEnvironment& env = *envs_[i];
    Snapshot& s = out[i];
    s.base_seed = slots_[i].base_seed;
    s.started = slots_[i].started;
    s.needs_reset = slots_[i].needs_reset;
    s.begun = env.begun();
    s.seed = env.seed();
    if (s.begun) s.actions = env.episode().actions_taken;
  }
  return out;
}

void VecEnvironment::continue_at(int i, uint64_t next) {
  if (i < 0 || i >= size()) throw Error("continue_at: no environment " + std::to_string(i));
  Slot& s = slots_[size_t(i)];
  s.base_seed = next - s.started * envs_.size();  // modulo 2^64, as begin() reads it back
}

void VecEnvironment::cap_decisions(int most) {
  if (most < 0) throw Error("max_episode_steps: a number of decisions, at least 1 (or none), got " + std::to_string(most));
  most_decisions_ = most;
}

void VecEnvironment::restore(const std::vector<Snapshot>& snapshots) {
  if (snapshots.size() != envs_.size())
    throw Error("restore: expected " + std::to_string(envs_.size()) + " environments' states, got " +
                std::to_string(snapshots.size()));
  for (size_t i = 0; i < envs_.size(); ++i) {
    const Snapshot& s = snapshots[i];
    Slot& slot = slots_[i];
    slot = Slot{};
    slot.base_seed = s.base_seed;
    slot.started = s.started;
    slot.needs_reset = s.needs_reset;
    if (!s.begun) continue;
    try {
      envs_[i]->replay(s.seed, s.actions);
    } catch (const Error& e) {
      if (!s.needs_reset)  // it ran on in the original: the same seed and actions should have too
        throw Error("restore: environment " + std::to_string(i) + "'s episode (seed " + std::to_string(s.seed) +
                    ") did not replay: " + e.what());
      // It faulted there before, and its episode is over: so it is in the copy.
    }
  }
}

}  // namespace roger
