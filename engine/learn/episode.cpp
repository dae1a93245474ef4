#include "learn/episode.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include "control/primitives.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/text.h"

namespace roger {

EpisodeRun::EpisodeRun(Agent& agent, const WorldSpec& spec, uint64_t seed, EpisodeDriver& driver,
                       double time_limit, EpisodeObserver* observer)
    : agent_(agent), driver_(driver), observer_(observer) {
  if (!(time_limit > 0.0)) throw Error("episode: time limit must be positive");
  agent.reset(spec);
  driver.begin(seed);
  agent.set_judge(driver.judge());
  if (observer) observer->on_begin(agent, seed);
  max_ticks_ = int(std::ceil(time_limit / agent.world().tick_seconds() - 1e-9));
  over_ = max_ticks_ <= 0;
}

bool EpisodeRun::tick() {
  paused_ = false;
  if (over_) return false;
  Controller* action = driver_.choose(agent_.input());
  if (!action) {
    paused_ = driver_.paused();
    over_ = out_.success = !paused_;
    return false;
  }
  agent_.step(*action);
  out_.ticks += 1;
  if (observer_) observer_->on_tick(agent_, out_.ticks, *action);
  if (driver_.absorbed(agent_.input())) {
    over_ = out_.success = true;
    return false;
  }
  over_ = out_.ticks >= max_ticks_;
  return !over_;
}

EpisodeRun::~EpisodeRun() { agent_.set_judge(nullptr); }

EpisodeOutcome EpisodeRun::finish() {
  if (finished_) throw Error("episode: finished twice");
  finished_ = true;
  out_.sim_seconds = agent_.world().time();
  out_.success = driver_.end(agent_.input(), out_.success, out_.ticks, out_.sim_seconds);
  if (observer_) observer_->on_end(agent_, out_.success, out_.ticks);
  return out_;
}

EpisodeOutcome run_episode(Agent& agent, const WorldSpec& spec, uint64_t seed, EpisodeDriver& driver,
                           double time_limit, EpisodeObserver* observer) {
  throw_if_interrupted();  // a batch run asked to stop (Ctrl-C): no new episode
  EpisodeRun run(agent, spec, seed, driver, time_limit, observer);
  while (run.tick()) {
  }
  if (run.paused()) throw Error("episode: the driver paused a loop that cannot be resumed");
  return run.finish();
}

namespace {

// One action, run every tick until its goal predicate holds.
// Which controllers of an action and its goal ever ran with a reference, over the episodes it is
// told of: a navigator to a goal region past the world's, or a binding to a colour no object has,
// is NOREF at every tick it runs, and the evaluation fails at every seed with no other sign. It
// only reads what the controllers kept of their last evaluation, so the episodes are unchanged.
class ReferenceWatch {
 public:
  ReferenceWatch(const Controller& action, const Predicate& goal) : roots_{&action} {
    goal.controllers(roots_);
    std::vector<const Controller*> to_visit = roots_;
    while (!to_visit.empty()) {
      const Controller* c = to_visit.back();
      to_visit.pop_back();
      if (std::any_of(watched_.begin(), watched_.end(), [&](const Watched& w) { return w.controller == c; }))
        continue;
      watched_.push_back(Watched{c});
      for (const Controller* part : c->children()) to_visit.push_back(part);
    }
  }
  // An episode begins: its controllers were reset, and their ticks count from the start again.
  void begin() {
    for (Watched& w : watched_) w.evaluated = w.observed = UINT64_MAX;
  }
  // Between ticks (at least once after each; twice does no harm): what ran since the last look.
  void look() {
    for (Watched& w : watched_) {
      const uint64_t evaluated = w.controller->evaluated_tick(), observed = w.controller->observed_tick();
      if (evaluated == w.evaluated && observed == w.observed) continue;
      w.evaluated = evaluated, w.observed = observed;
      w.ran = true;
      w.referenced = w.referenced || w.controller->output().gamma != Gamma::kNoRef;
    }
  }
  // The controllers that ran and never had a reference, a line each for the outermost of them,
  // with the innermost inside it when they are others (the step of a sequence that names a region
  // past the world's) and the binding they ran under (its colour may be no object's), in the order
  // of a walk from the action, then from the goal's controllers.
  std::vector<std::string> never_referenced() const {
    auto unreferenced = [&](const Controller* c) {
      for (const Watched& w : watched_)
        if (w.controller == c) return w.ran && !w.referenced;
      return false;
    };
    auto described = [](const Controller* c) {
      const std::string settings = c->settings();
      return c->name() + (settings.empty() ? "" : " {" + settings + "}");
    };
    std::vector<const Controller*> seen;
    // The innermost unreferenced controllers at or below `c` (itself when no part is one).
    std::function<void(const Controller*, std::vector<std::string>&)> innermost = [&](const Controller* c,
                                                                                      std::vector<std::string>& out) {
      bool inner = false;
      for (const Controller* part : c->children())
        if (unreferenced(part)) inner = true, innermost(part, out);
      const std::string d = described(c);
      if (!inner && std::find(out.begin(), out.end(), d) == out.end()) out.push_back(d);
    };
    std::vector<std::string> lines;
    // `binding`: the nearest binding above c, which chose the colour or region c did not find.
    std::function<void(const Controller*, const Controller*)> walk = [&](const Controller* c,
                                                                          const Controller* binding) {
      if (std::find(seen.begin(), seen.end(), c) != seen.end()) return;
      seen.push_back(c);
      if (!unreferenced(c)) {
        if (std::string(c->kind()) == "binding") binding = c;
        for (const Controller* part : c->children()) walk(part, binding);
        return;
      }
      std::vector<std::string> inside;
      innermost(c, inside);
      std::string line = described(c);
      if (!(inside.size() == 1 && inside[0] == line)) line += " (inside: " + join(inside) + ")";
      if (binding) line += " under " + described(binding);
      lines.push_back(line);
    };
    for (const Controller* root : roots_) walk(root, nullptr);
    return lines;
  }

 private:
  struct Watched {
    const Controller* controller;
    uint64_t evaluated = UINT64_MAX, observed = UINT64_MAX;  // at the last look
    bool ran = false, referenced = false;
  };
  std::vector<const Controller*> roots_;  // the action, then the controllers the goal reads
  std::vector<Watched> watched_;
};

class FixedActionDriver final : public EpisodeDriver {
 public:
  FixedActionDriver(Controller& action, Predicate& goal, ReferenceWatch* watch = nullptr)
      : action_(action), goal_(goal), judge_(&goal), watch_(watch) {}
  void begin(uint64_t seed) override {
    action_.reset(seed);
    goal_.reset();
    judge_.reset(seed);
    if (watch_) watch_->begin();
  }
  Controller* choose(const ControlInput&) override { return &action_; }
  // Success is the true world's: under noise the goal is judged on the true senses.
  bool absorbed(const ControlInput& in) override {
    if (!watch_) return judge_.holds(in);
    watch_->look();  // the tick's own evaluations, before the goal's of the next tick replace them
    const bool holds = judge_.holds(in);
    watch_->look();
    return holds;
  }
  bool end(const ControlInput&, bool success, int, double) override { return success; }
  Judge* judge() override { return &judge_; }

 private:
  Controller& action_;
  Predicate& goal_;
  Judge judge_;
  ReferenceWatch* watch_;
};

// Records frames every `every` ticks (and the last one) and the watched controllers' states.
class Recorder final : public EpisodeObserver {
 public:
  Recorder(EpisodeResult& result, const std::vector<ControllerPtr>& watch, int every)
      : result_(result), watch_(watch), every_(every) {}

  void on_begin(const Agent& agent, uint64_t seed) override {
    for (const auto& w : watch_) w->reset(seed);
    for (const auto& w : watch_) result_.gammas.push_back(GammaTrace{w->name(), {}});
    if (every_) record(agent, 0);
  }
  void on_tick(const Agent& agent, int tick, const Controller& ran) override {
    for (size_t i = 0; i < watch_.size(); ++i) result_.gammas[i].states.push_back(watch_[i]->state(agent.input()));
    if (every_ && tick % every_ == 0) record(agent, tick);
    if (every_ || !watch_.empty()) note_decision(tick, ran);
  }
  void on_end(const Agent& agent, bool /*success*/, int ticks) override {
    // The episode's last moment is always shown, whatever the frame period: the goal reached, or the
    // world at the time-out (found by a probe: a failed episode's viewer showed, at its end, the
    // world of its last frame seconds before, the very moment one renders a failure to see).
    if (every_ && (result_.frame_ticks.empty() || result_.frame_ticks.back() != ticks)) record(agent, ticks);
  }

 private:
  void record(const Agent& agent, int tick) {
    result_.frames.push_back(agent.world().frame());
    result_.frame_ticks.push_back(tick);
  }
  // Follows what ran down to what runs inside it now (Controller::inner) and records a decision
  // when that path differs from the last tick's. The path is compared as pointers in a reused
  // buffer, so names are copied only at decisions.
  void note_decision(int tick, const Controller& ran) {
    path_.clear();
    for (const Controller* c = &ran; c && path_.size() < 32; c = c->inner()) path_.push_back(c);
    if (path_ == last_path_) return;
    last_path_ = path_;
    Decision d;
    d.tick = tick;
    for (const Controller* c : path_)  // a stand-in and its target usually share a name: once
      if (d.path.empty() || d.path.back() != c->name()) d.path.push_back(c->name());
    result_.decisions.push_back(std::move(d));
  }
  EpisodeResult& result_;
  const std::vector<ControllerPtr>& watch_;
  const int every_;
  std::vector<const Controller*> path_, last_path_;
};

}  // namespace

std::unique_ptr<EpisodeObserver> make_recorder(EpisodeResult& result, const std::vector<ControllerPtr>& watch,
                                               double record_every, double tick_seconds) {
  const int every = record_every > 0.0 ? std::max(1, int(std::lround(record_every / tick_seconds))) : 0;
  return std::make_unique<Recorder>(result, watch, every);
}

std::vector<GammaTrace> distinct_traces(std::vector<GammaTrace> traces, size_t limit) {
  std::vector<GammaTrace> kept;
  std::map<std::string, int> uses;  // traces kept per name
  for (GammaTrace& t : traces) {
    if (kept.size() == limit) break;
    const auto same = [&](const GammaTrace& k) { return k.states == t.states && k.name == t.name; };
    if (std::any_of(kept.begin(), kept.end(), same)) continue;
    kept.push_back(std::move(t));
  }
  for (GammaTrace& k : kept)
    if (const int n = ++uses[k.name]; n > 1) k.name += " (" + std::to_string(n) + ")";
  return kept;
}

namespace {

// One episode of `driver`'s action (run_episode below; evaluate_action keeps one driver for all).
EpisodeResult fixed_action_episode(Agent& agent, const WorldSpec& spec, uint64_t seed, FixedActionDriver& driver,
                                   const EpisodeOptions& options, const std::vector<ControllerPtr>& watch) {
  EpisodeResult r;
  r.seed = seed;
  const auto recorder = make_recorder(r, watch, options.record_every, agent.world().tick_seconds());
  const double limit = options.time_limit + options.time_per_object * double(spec.objects.size());
  const EpisodeOutcome out = run_episode(agent, spec, seed, driver, limit, recorder.get());
  r.success = out.success;
  r.ticks = out.ticks;
  r.sim_seconds = out.sim_seconds;
  r.reward = r.success ? options.success_reward : options.timeout_reward;
  return r;
}

}  // namespace

EpisodeResult run_episode(Agent& agent, const WorldSpec& spec, uint64_t seed, Controller& action,
                          Predicate& goal, const EpisodeOptions& options,
                          const std::vector<ControllerPtr>& watch) {
  FixedActionDriver driver(action, goal);
  return fixed_action_episode(agent, spec, seed, driver, options, watch);
}

EvalSummary evaluate_action(const std::function<WorldSpec(uint64_t)>& make, Controller& action,
                            Predicate& goal, int episodes, uint64_t first_seed,
                            const EpisodeOptions& options, const WorldParams& world) {
  if (episodes < 1) throw Error("evaluation: needs at least one episode");
  Agent agent(world);
  // One driver for every episode, as one action and goal serve them all: under noise its judge's
  // copies of the goal's controllers are then made once and reset each episode, as the goal's own
  // are, and keep what those keep (a navigator's cold solve of the same region, copied rather than
  // solved again); a driver per episode made the copies and solved the region anew each time.
  ReferenceWatch watch(action, goal);
  FixedActionDriver driver(action, goal, &watch);
  EvalSummary s;
  double sum = 0.0, sum2 = 0.0, time = 0.0;
  for (int e = 0; e < episodes; ++e) {
    const uint64_t seed = first_seed + uint64_t(e);
    const WorldSpec spec = make(seed);
    for (const ChannelNoise* c : {&spec.noise.image, &spec.noise.joints, &spec.noise.base, &spec.noise.touch,
                                  &spec.noise.effort}) {
      s.noise_offsets = s.noise_offsets || c->offsets();
      s.noise_lost = s.noise_lost || c->dropout > 0.0;
      s.noise_late = s.noise_late || c->delay > 0;
      s.noise_coarse = s.noise_coarse || c->quantum > 0.0;
    }
    EpisodeResult r = fixed_action_episode(agent, spec, seed, driver, options, {});
    s.successes += r.success;
    s.succeeded_at_first_tick += r.success && r.ticks <= 1;
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
  s.never_referenced = watch.never_referenced();
  return s;
}

}  // namespace roger
