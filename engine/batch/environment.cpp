// environment.cpp: a stage as an environment (StageEnvironment) and many of them on threads
// (VecEnvironment), over the episode loop and the semi-MDP driver that training uses.
#include "batch/environment.h"

#include <optional>

#include "batch/batch_internal.h"
#include "core/error.h"
#include "learn/episode.h"
#include "script/curriculum/curriculum.h"
#include "script/scenario/scenario.h"

namespace roger {

using batch_detail::StageHooks;

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
      ended = true;
      throw;
    }
  }
};

namespace {

// Every learned skill the context uses must come from a file: an environment trains nothing.
void check_skills_given(const CurriculumContext& ctx, const CurriculumStage& stage, const EnvironmentOptions& o) {
  for (const auto& name : ctx.learned)
    if (!o.skill_files.count(name))
      throw Error(stage.where(ctx.name) + " uses the learned skill '" + name +
                  "': give its policy file, skills={'" + name + "': '.../policy.json'} (roger train writes one)");
}

Curriculum load_checked(const EnvironmentOptions& o) {
  Curriculum cur = Curriculum::load(o.curriculum, o.limits);
  const CurriculumStage& stage = cur.stage(o.stage);
  check_skills_given(stage.context(o.context), stage, o);
  return cur;
}

}  // namespace

StageEnvironment::StageEnvironment(const EnvironmentOptions& o) {
  impl_ = std::make_unique<Impl>(load_checked(o), o.stage, o.context, o, info_);
  const CurriculumStage& st = impl_->stage;
  TrainOptions topt;
  topt.skill_files = o.skill_files;
  topt.limits = o.limits;
  std::vector<SkillSource> sources;
  batch_detail::bind_skills(impl_->cur, impl_->ctx, topt, nullptr, sources);
  info_.curriculum = impl_->cur.path();
  info_.stage = st.name;
  info_.context = impl_->ctx.name;
  info_.scenario = impl_->scenario.name();
  info_.actions = controller_names(impl_->ctx.actions);
  info_.time_limit = st.time_limit;
  info_.time_per_object = st.time_per_object;
  info_.tick_seconds = impl_->agent.world().tick_seconds();
  info_.budget_episodes = st.budget_episodes;
  info_.learner = st.learner;
  info_.discount_seconds = st.rewards.discount_seconds;
  info_.checkpoint_every = st.checkpoints.every;
  info_.checkpoint_episodes = st.checkpoints.episodes;
  info_.threshold = st.checkpoints.threshold;
  info_.checkpoint_seeds = st.checkpoints.seeds;
  info_.stop_after = st.checkpoints.stop_after;
  info_.settle = st.checkpoints.settle;
  info_.final_episodes = st.checkpoints.final_episodes;
}

StageEnvironment::~StageEnvironment() = default;

const std::vector<Gamma>& StageEnvironment::reset(uint64_t seed) {
  Impl& m = *impl_;
  m.ended = true;  // until the new episode is running
  m.run.reset();
  seed_ = seed;
  const WorldSpec spec = m.scenario.generate(seed);
  m.run.emplace(m.agent, spec, seed, m.driver, m.stage.episode_time_limit(spec));
  m.ended = false;
  m.advance();
  return m.driver.gammas();
}

EnvironmentStep StageEnvironment::step(int action) {
  Impl& m = *impl_;
  if (!m.run || m.ended)
    throw Error("step: no episode is running in " + info_.stage + "/" + info_.context + " (call reset first)");
  m.driver.act(action);  // checks the index
  m.advance();
  EnvironmentStep r;
  r.reward = m.driver.transition_reward();
  if (m.ended) {
    r.terminated = m.driver.episode().success;
    r.truncated = !r.terminated;
  }
  return r;
}

const std::vector<Gamma>& StageEnvironment::state() const { return impl_->driver.gammas(); }
bool StageEnvironment::running() const { return impl_->run && !impl_->ended; }
double StageEnvironment::sim_seconds() const { return impl_->agent.world().time(); }
int StageEnvironment::ticks() const { return impl_->run ? impl_->run->ticks() : 0; }
const TrainingEpisode& StageEnvironment::episode() const { return impl_->driver.episode(); }
const Agent& StageEnvironment::agent() const { return impl_->agent; }

// ---- VecEnvironment ----

VecEnvironment::VecEnvironment(const EnvironmentOptions& options, int n, int threads) {
  if (n < 1) throw Error("make_vec: num_envs must be at least 1, got " + std::to_string(n));
  if (threads < 1) throw Error("make_vec: threads must be at least 1, got " + std::to_string(threads));
  threads_ = std::min(threads, n);
  for (int i = 0; i < n; ++i) envs_.push_back(std::make_unique<StageEnvironment>(options));
  episodes_started_.assign(size_t(n), 0);
  results_.resize(size_t(n));
  ended_.resize(size_t(n));
  final_.resize(size_t(n));
  final_sim_s_.resize(size_t(n));
  final_reward_.resize(size_t(n));
  final_seed_.resize(size_t(n));
  final_ticks_.resize(size_t(n));
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

// Environment i's next episode: its world seed follows from i and how many it has begun.
void VecEnvironment::job(int i) {
  StageEnvironment& env = *envs_[size_t(i)];
  const uint64_t n = envs_.size();
  try {
    ended_[size_t(i)] = 0;
    if (!resetting_) {
      results_[size_t(i)] = env.step(int(actions_[i]));
      if (env.running()) return;
      ended_[size_t(i)] = 1;
      final_[size_t(i)] = env.state();
      final_sim_s_[size_t(i)] = env.sim_seconds();
      final_ticks_[size_t(i)] = env.ticks();
      final_seed_[size_t(i)] = env.seed();
      final_reward_[size_t(i)] = env.episode().reward;
    }
    // An episode that ends before its first decision (a Lua absorbing function that holds at
    // once) is skipped: a learner has nothing to decide in it.
    for (int tries = 0; tries < 1000; ++tries) {
      env.reset(first_seed_ + uint64_t(i) + episodes_started_[size_t(i)]++ * n);
      if (env.running()) return;
    }
    throw Error("make_vec: 1000 episodes in a row ended before their first decision");
  } catch (...) {
    errors_[size_t(i)] = std::current_exception();
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
  for (auto& e : errors_)
    if (e) std::rethrow_exception(e);
}

namespace {

void write_state(const std::vector<Gamma>& g, uint8_t* out) {
  for (size_t a = 0; a < g.size(); ++a) out[a] = uint8_t(g[a]);
}

}  // namespace

void VecEnvironment::reset(uint64_t first_seed, uint8_t* states, uint64_t* seeds) {
  first_seed_ = first_seed;
  episodes_started_.assign(envs_.size(), 0);
  resetting_ = true;
  run_all();
  const size_t k = info().actions.size();
  for (size_t i = 0; i < envs_.size(); ++i) {
    write_state(envs_[i]->state(), states + i * k);
    seeds[i] = envs_[i]->seed();
  }
}

void VecEnvironment::step(const int64_t* actions, const StepOutput& out) {
  const size_t k = info().actions.size();
  for (size_t i = 0; i < envs_.size(); ++i)
    if (actions[i] < 0 || actions[i] >= int64_t(k))
      throw Error("step: action " + std::to_string(actions[i]) + " of environment " + std::to_string(i) +
                  " is not in [0, " + std::to_string(k) + ")");
  resetting_ = false;
  actions_ = actions;
  run_all();
  for (size_t i = 0; i < envs_.size(); ++i) {
    write_state(envs_[i]->state(), out.states + i * k);
    out.rewards[i] = results_[i].reward;
    out.terminated[i] = results_[i].terminated;
    out.truncated[i] = results_[i].truncated;
    out.seeds[i] = envs_[i]->seed();
    const bool ended = ended_[i];
    for (size_t a = 0; a < k; ++a) out.final_states[i * k + a] = ended ? uint8_t(final_[i][a]) : 0;
    out.episode_seeds[i] = ended ? final_seed_[i] : 0;
    out.episode_sim_s[i] = ended ? final_sim_s_[i] : 0.0;
    out.episode_ticks[i] = ended ? final_ticks_[i] : 0;
    out.episode_rewards[i] = ended ? final_reward_[i] : 0.0;
  }
}

}  // namespace roger
