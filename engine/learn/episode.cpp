#include "learn/episode.h"

#include <cmath>

#include "core/error.h"

namespace roger {

EpisodeResult run_episode(Agent& agent, const WorldSpec& spec, uint64_t seed, Controller& action,
                          Predicate& goal, const EpisodeOptions& options,
                          const std::vector<ControllerPtr>& watch) {
  if (!(options.time_limit > 0.0)) throw Error("episode: time limit must be positive");
  agent.reset(spec);
  action.reset(seed);
  goal.reset();
  for (const auto& w : watch) w->reset(seed);
  EpisodeResult r;
  r.seed = seed;
  for (const auto& w : watch) r.gammas.push_back(GammaTrace{w->name(), {}});
  const double dt = agent.world().tick_seconds();
  const int max_ticks = int(std::ceil(options.time_limit / dt - 1e-9));
  const int frame_every = options.record_every > 0.0 ? std::max(1, int(std::lround(options.record_every / dt))) : 0;
  if (frame_every) {
    r.frames.push_back(agent.world().frame());
    r.frame_ticks.push_back(0);
  }
  for (int t = 0; t < max_ticks; ++t) {
    agent.step(action);
    const ControlInput& in = agent.input();
    for (size_t i = 0; i < watch.size(); ++i) r.gammas[i].states.push_back(watch[i]->state(in));
    r.ticks = t + 1;
    const bool done = goal.holds(in);
    if (frame_every && (r.ticks % frame_every == 0 || done)) {
      r.frames.push_back(agent.world().frame());
      r.frame_ticks.push_back(r.ticks);
    }
    if (done) {
      r.success = true;
      break;
    }
  }
  r.sim_seconds = agent.world().time();
  r.reward = r.success ? options.success_reward : options.timeout_reward;
  return r;
}

EvalSummary evaluate_action(const std::function<WorldSpec(uint64_t)>& make, Controller& action,
                            Predicate& goal, int episodes, uint64_t first_seed,
                            const EpisodeOptions& options, const WorldParams& world) {
  if (episodes < 1) throw Error("evaluation: needs at least one episode");
  Agent agent(world);
  EvalSummary s;
  double sum = 0.0, sum2 = 0.0, time = 0.0;
  for (int e = 0; e < episodes; ++e) {
    const uint64_t seed = first_seed + uint64_t(e);
    EpisodeResult r = run_episode(agent, make(seed), seed, action, goal, options);
    s.successes += r.success;
    sum += r.reward;
    sum2 += r.reward * r.reward;
    time += r.sim_seconds;
    s.results.push_back(std::move(r));
  }
  s.episodes = episodes;
  s.success_rate = double(s.successes) / episodes;
  s.reward_mean = sum / episodes;
  // Population standard deviation, as the paper's tables report it (e.g. 96.0 +- 28.0).
  s.reward_std = std::sqrt(std::max(0.0, sum2 / episodes - s.reward_mean * s.reward_mean));
  s.time_mean = time / episodes;
  return s;
}

}  // namespace roger
