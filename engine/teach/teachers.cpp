// teachers.cpp: the teachers that need no model of the learner's progress beyond its success
// rate (random, sequence, LCAS), and make_teacher.
#include <algorithm>
#include <cstdio>
#include <deque>
#include <numeric>

#include "core/error.h"
#include "core/text.h"
#include "teach/teach_internal.h"

namespace roger {
namespace {

using json = nlohmann::json;

// "<spec> (file:line): message", for settings the space cannot take.
[[noreturn]] void fail(const TeacherSpec& spec, const std::string& message) {
  const std::string at = spec.file.empty() ? "" : " (" + spec.file + ":" + std::to_string(spec.line) + ")";
  throw Error(spec.name() + at + ": " + message);
}

// The successes among xs[from, to).
int count_of(const std::deque<bool>& xs, size_t from, size_t to) {
  return int(std::count(xs.begin() + std::ptrdiff_t(from), xs.begin() + std::ptrdiff_t(to), true));
}

double mean_of(const std::deque<bool>& xs, size_t from, size_t to) {
  double s = 0.0;
  for (size_t i = from; i < to; ++i) s += xs[i];
  return to > from ? s / double(to - from) : 0.0;
}

// Domain randomization: every task equally likely.
class RandomTeacher final : public Teacher {
 public:
  RandomTeacher(const TaskSpace& space, uint64_t seed) : space_(space), rng_(seed) {}
  std::string kind() const override { return "random"; }
  TaskPick next() override { return {space_.sample(rng_), {}, std::nullopt}; }
  void record(const TaskOutcome&) override { ++episodes_; }
  json state() const override { return {{"kind", kind()}, {"episodes", episodes_}}; }

 private:
  TaskSpace space_;
  Rng rng_;
  int episodes_ = 0;
};

// Fixed steps, each a restriction of the space; the next step begins when the success rate over
// the last `window` episodes of this step reaches `promote`, the previous one comes back when it
// falls below `demote`. Each move starts the window afresh.
class SequenceTeacher final : public Teacher {
 public:
  SequenceTeacher(const TeacherSpec& spec, const TaskSpace& space, uint64_t seed) : space_(space), rng_(seed) {
    if (spec.steps.empty()) fail(spec, "needs at least one step");
    for (size_t k = 0; k < spec.steps.size(); ++k) {
      const TeacherSpec::Step& s = spec.steps[k];
      try {
        steps_.push_back({restrict_space(space, s.restrict), s.promote, s.demote, s.window});
      } catch (const Error& e) {
        fail(spec, "step " + std::to_string(k + 1) + ": " + e.what());
      }
    }
  }
  std::string kind() const override { return "sequence"; }
  TaskPick next() override {
    const Step& s = steps_[size_t(step_)];
    return {*space_.task_of(s.space.params(s.space.sample(rng_))), {}, std::nullopt};
  }
  void record(const TaskOutcome& o) override {
    ++episodes_;
    const Step& s = steps_[size_t(step_)];
    window_.push_back(o.success);
    if (int(window_.size()) > s.window) window_.pop_front();
    if (int(window_.size()) < s.window) return;
    const double rate = mean_of(window_, 0, window_.size());
    if (step_ + 1 < int(steps_.size()) && rate >= s.promote) move(step_ + 1, rate);
    else if (s.demote >= 0.0 && step_ > 0 && rate < s.demote) move(step_ - 1, rate);
  }
  json state() const override {
    json j = {{"kind", kind()}, {"episodes", episodes_}, {"step", step_ + 1}, {"steps", steps_.size()},
              {"moves", moves_}};
    j["rate"] = window_.empty() ? json(nullptr) : json(mean_of(window_, 0, window_.size()));
    return j;
  }

 private:
  struct Step {
    TaskSpace space;
    double promote, demote;
    int window;
  };
  void move(int to, double rate) {
    moves_.push_back({{"episode", episodes_}, {"from", step_ + 1}, {"to", to + 1}, {"rate", rate}});
    step_ = to;
    window_.clear();
  }
  TaskSpace space_;
  std::vector<Step> steps_;
  Rng rng_;
  int step_ = 0, episodes_ = 0;
  std::deque<bool> window_;  // this step's last outcomes
  json moves_ = json::array();
};

// Lift-Constraint-Act-Saturate: one parameter held at a level while the learner acts, lifted to the
// next once the success curve saturates: the last `window` episodes at this level succeeded at a
// rate higher than the `window` before them by less than `slope`, and at a rate of at least
// `floor` (0 by default: then a curve still flat at zero counts as saturated). A parameter of the task space
// is held at its level while the other axes vary; any other scenario parameter is set beside the
// task.
class LcasTeacher final : public Teacher {
 public:
  LcasTeacher(const TeacherSpec& spec, const TaskSpace& space, uint64_t seed)
      : space_(space), lift_(spec.lift), window_(spec.window), slope_(spec.slope), floor_(spec.floor), rng_(seed) {
    if (spec.levels.empty()) fail(spec, "lift needs at least one level");
    axis_ = space.index(spec.lift);
    for (const auto& level : spec.levels) {
      if (axis_ < 0) {
        levels_.push_back(0.0);
        continue;
      }
      std::string allowed;
      const auto v = space.value_of(size_t(axis_), level, &allowed);
      if (!v) fail(spec, "the level " + spec.lift + " = " + level + " is outside the task space: " + spec.lift +
                             " takes " + allowed);
      levels_.push_back(*v);
    }
    texts_ = spec.levels;
  }
  std::string kind() const override { return "lcas"; }
  TaskPick next() override {
    TaskPick p{space_.sample(rng_), {}, std::nullopt};
    if (axis_ >= 0) p.task[size_t(axis_)] = levels_[size_t(level_)];
    else p.extra.emplace_back(lift_, texts_[size_t(level_)]);
    return p;
  }
  void record(const TaskOutcome& o) override {
    ++episodes_;
    outcomes_.push_back(o.success);
    const size_t w = size_t(window_);
    if (outcomes_.size() > 2 * w) outcomes_.pop_front();
    if (level_ + 1 >= int(levels_.size()) || outcomes_.size() < 2 * w) return;
    const double rate = mean_of(outcomes_, w, 2 * w);
    // The gain as the difference of the windows' successes over w, rounded once: the difference of
    // the two rounded rates is not exact (0.5 - 0.4 is 0.09999999999999998), and a gain of one
    // episode in ten read below a slope of 0.1 (found by a probe: lifted where the rule says not).
    const double gain = (count_of(outcomes_, w, 2 * w) - count_of(outcomes_, 0, w)) / double(w);
    if (gain >= slope_) return;  // still learning at this level
    if (rate < floor_) return;   // flat below the floor: not yet begun
    lifts_.push_back({{"episode", episodes_}, {"from", param_value_json(texts_[size_t(level_)])},
                      {"to", param_value_json(texts_[size_t(level_ + 1)])}, {"rate", rate}, {"gain", gain}});
    ++level_;
    outcomes_.clear();
  }
  json state() const override {
    json j = {{"kind", kind()}, {"episodes", episodes_}, {"param", lift_}, {"level", level_ + 1},
              {"levels", texts_.size()}, {"value", param_value_json(texts_[size_t(level_)])}, {"lifts", lifts_}};
    const size_t w = size_t(window_);
    j["rate"] = outcomes_.size() >= w ? json(mean_of(outcomes_, outcomes_.size() - w, outcomes_.size())) : json(nullptr);
    return j;
  }
  ParamList test_params() const override {
    return axis_ >= 0 ? ParamList{} : ParamList{{lift_, texts_.back()}};
  }

 private:
  TaskSpace space_;
  std::string lift_;
  int axis_ = -1, window_, level_ = 0, episodes_ = 0;
  double slope_, floor_;
  std::vector<double> levels_;       // on the space's axis
  std::vector<std::string> texts_;   // as written
  Rng rng_;
  std::deque<bool> outcomes_;        // the last 2 windows at this level
  json lifts_ = json::array();
};

}  // namespace

std::string TeacherSpec::name() const {
  switch (kind) {
    case Kind::kRandom: return "roger.teacher.random";
    case Kind::kSequence: return "roger.teacher.sequence";
    case Kind::kLcas: return "roger.teacher.lcas";
    case Kind::kAlpGmm: return "roger.teacher.alp_gmm";
    case Kind::kPlr: return "roger.teacher.plr";
  }
  return "roger.teacher";
}

namespace {

// A value as a sentence shows it: a fraction to three figures (found by a probe: "rate
// 0.3333333333333333", a task at 1.5340091575147519), a string without its quotes.
std::string shown(const json& v) {
  if (v.is_number_float()) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", v.get<double>());
    return text;
  }
  // An empty text shown as one (found by a probe: a level "" of `locked` read "locked =  (level 2").
  if (v.is_string()) return v.get<std::string>().empty() ? "\"\"" : v.get<std::string>();
  return v.dump();
}

// "{obstacles = 4, shape = triangle}": a task.
std::string task_shown(const json& task) {
  std::vector<std::string> parts;
  if (task.is_object())
    for (const auto& [k, v] : task.items()) parts.push_back(k + " = " + shown(v));
  return "{" + join(parts) + "}";
}

// Whether a move or lift of a teacher that recorded `state` came after its last episode: decided on
// that episode's outcome, it set the level of an episode that never ran (found by a probe: "moved at
// episodes 10, 20" of a 20-episode budget, read as a curriculum that reached its last step).
bool after_last_episode(const json& move, const json& state) {
  const json episode = move.value("episode", json()), episodes = state.value("episodes", json());
  return episode.is_number() && episodes.is_number() && episode.get<double>() >= episodes.get<double>();
}

// The last of `moves` (a sequence's moves, an LCAS teacher's lifts), taken out of them, when it came
// after the last episode; else null. Only the last can: one move follows each episode at most.
json take_after_last_episode(json& moves, const json& state) {
  if (moves.empty() || !after_last_episode(moves.back(), state)) return json();
  json last = moves.back();
  moves.erase(moves.size() - 1);
  return last;
}

// "19 (step 1 to 2, rate 0.5), 29 (step 2 to 3, rate 0.6)": a sequence's moves.
std::string sequence_moves(const json& moves) {
  std::vector<std::string> parts;
  for (const json& m : moves)
    parts.push_back(shown(m.value("episode", json())) + " (step " + shown(m.value("from", json())) + " to " +
                    shown(m.value("to", json())) + ", rate " + shown(m.value("rate", json())) + ")");
  return join(parts);
}

// "31 (to 64), 59 (to 128)": an LCAS teacher's lifts.
std::string lcas_lifts(const json& lifts) {
  std::vector<std::string> parts;
  for (const json& l : lifts) parts.push_back(shown(l.value("episode", json())) + " (to " + shown(l.value("to", json())) + ")");
  return join(parts);
}

// A sequence's line: where it stood and its moves; a move after the last episode said apart.
std::string describe_sequence(const json& state, const std::string& steps) {
  json moves = state.value("moves", json::array());
  const json last = take_after_last_episode(moves, state);
  std::string text = last.is_null() ? "at step " + shown(state.value("step", json("?"))) + " of " + steps
                                    : "at step " + shown(last.value("from", json("?"))) + " of " + steps +
                                          " when training ended";
  text += moves.empty() ? ", never moved" : "; moved at episodes " + sequence_moves(moves);
  if (!last.is_null())
    text += "; after the last episode, to step " + shown(last.value("to", json("?"))) + " (rate " +
            shown(last.value("rate", json())) + "), never trained";
  return text;
}

// An LCAS teacher's line: its level and lifts; a lift after the last episode said apart.
std::string describe_lcas(const json& state, const std::string& levels) {
  json lifts = state.value("lifts", json::array());
  const json last = take_after_last_episode(lifts, state);
  const std::string param = state.value("param", std::string("?"));
  std::string text;
  if (last.is_null()) {
    text = param + " = " + shown(state.value("value", json("?"))) + " (level " + shown(state.value("level", json("?"))) +
           " of " + levels + ")";
  } else {  // the level before the last lift: the lift's own "from", or (recorded before lifts had
            // one) the lift before it's "to"
    json from = last.value("from", json());
    if (from.is_null() && !lifts.empty()) from = lifts.back().value("to", json());
    const json level = state.value("level", json());  // an integer from roger train; any other is "?"
    const bool counted = level.is_number_integer() && level.get<int64_t>() > 0;
    text = param + " = " + shown(from.is_null() ? json("?") : from) + " (level " +
           (counted ? shown(json(level.get<int64_t>() - 1)) : std::string("?")) + " of " + levels + ") when training ended";
  }
  text += lifts.empty() ? ", never lifted" : "; lifted at episodes " + lcas_lifts(lifts);
  if (!last.is_null()) text += "; after the last episode, to " + shown(last.value("to", json("?"))) + ", never trained";
  return text;
}

}  // namespace

std::string describe_teacher_state(const json& state) {
  if (!state.is_object()) return "";
  const std::string kind = state.value("kind", std::string());
  const auto count = [&](const char* key) { return state.contains(key) ? shown(state[key]) : std::string("?"); };
  const auto counted_as = [&](const char* key, const std::string& noun) {
    return count(key) + " " + noun + (state.value(key, json()) == json(1) ? "" : "s");
  };
  if (kind == "random") return counted_as("episodes", "task") + " drawn uniformly from the task space";
  if (kind == "function")  // what it chose is the trial's episodes.jsonl (and a figure of kind "tasks")
    return counted_as("episodes", "task") + " chosen by the function at " + state.value("function", std::string("?"));
  if (kind == "sequence") return describe_sequence(state, count("steps"));
  if (kind == "lcas") return describe_lcas(state, count("levels"));
  if (kind == "alp_gmm") {
    std::string most;  // the component of the most learning progress: where the teacher drew most
    double best = -1.0;
    for (const json& c : state.value("components", json::array()))
      if (c.value("alp", -1.0) > best) {
        best = c.value("alp", -1.0);
        most = task_shown(c.value("task", json()));
      }
    return counted_as("fits", "fit") + ", mean ALP " + count("mean_alp") +
           (most.empty() ? "" : "; most progress around " + most + " (ALP " + shown(json(best)) + ")");
  }
  if (kind == "plr")
    return count("replays") + " of " + counted_as("episodes", "episode") + " replayed a level; " +
           counted_as("levels", "level") + " kept";
  return "";
}

std::unique_ptr<Teacher> make_teacher(const TeacherSpec& spec, const TaskSpace& space, uint64_t seed) {
  switch (spec.kind) {
    case TeacherSpec::Kind::kRandom: return std::make_unique<RandomTeacher>(space, seed);
    case TeacherSpec::Kind::kSequence: return std::make_unique<SequenceTeacher>(spec, space, seed);
    case TeacherSpec::Kind::kLcas: return std::make_unique<LcasTeacher>(spec, space, seed);
    case TeacherSpec::Kind::kAlpGmm:
      if (space.empty()) fail(spec, "needs a task space with at least one parameter");
      return teach_detail::make_alp_gmm(spec, space, seed);
    case TeacherSpec::Kind::kPlr: return teach_detail::make_plr(spec, space, seed);
  }
  fail(spec, "unknown teacher");
}

}  // namespace roger
