// Module teach: teachers that choose each training episode's task from a space of tasks by the
// learner's progress (adaptive curricula). Owns task spaces over scenario parameters, the
// teachers (random, sequence, LCAS, ALP-GMM with its Gaussian mixtures, PLR) and their states.
// Plain C++ with Eigen on core alone: it knows nothing of worlds, controllers, learning or Lua.
// A stage's Lua function as a teacher implements Teacher in script/curriculum; the trainer
// (batch/trainer.cpp) asks the stage's teacher for every training episode's task and tells it
// the outcome. docs/curricula.md, "Teachers", is the reference.
//
// Every teacher draws from its own Rng, seeded by its trial, and from nothing else: the tasks of
// a trial are a pure function of the trial's seed and the outcomes of its episodes, so a trial
// stays bit-identical whatever the number of worker threads or the machine.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/rng.h"

namespace roger {

using ParamList = std::vector<std::pair<std::string, std::string>>;  // scenario parameters as text

// A parameter's text as the records write it: an integer or a number when it is one as the engine
// writes numbers ("64" is 64, not 64.0 or "64"; "1.25" is 1.25), else the text ("007", "1e3").
nlohmann::json param_value_json(const std::string& text);

// "obstacles = 2, shape = spade", for messages.
std::string params_text(const ParamList& params);

// One axis of a task space: a scenario parameter and the values a task may give it.
struct TaskDim {
  enum class Kind { kInt, kReal, kChoice };
  std::string name;                  // the scenario parameter
  Kind kind = Kind::kReal;
  double lo = 0.0, hi = 1.0;         // int: lo..hi inclusive; real: [lo, hi]
  std::vector<std::string> choices;  // choice: the values as text (as a scenario parameter takes them)
  std::vector<size_t> string_choices;  // choice: those written as Lua strings (refused for a number parameter)
  std::string file;                  // where it was written (roger.int(...)), "" when unknown
  int line = 0;
  // "roger.int(0, 6)", "roger.real(0.5, 2)", "roger.choice{circle, spade}".
  std::string text() const;
  // The number of distinct values (int, choice), 0 for a real range.
  size_t cells() const;
};

// A task: one number per dimension of its space, in the space's order: the integer of an int
// axis, the value of a real one, the index of a choice.
using TaskPoint = std::vector<double>;

// The product of its axes, sorted by parameter name. Every task of the space is equally likely
// under sample(), and the unit cube maps onto it so that each value of a discrete axis owns an
// equal slice (the coordinates teachers that fit densities work in).
class TaskSpace {
 public:
  TaskSpace() = default;
  // Axes in any order (kept sorted by name). Throws roger::Error for a repeated name, an empty
  // choice, a reversed or empty range or a non-integral bound of an int axis.
  explicit TaskSpace(std::vector<TaskDim> dims);

  const std::vector<TaskDim>& dims() const { return dims_; }
  bool empty() const { return dims_.empty(); }
  size_t size() const { return dims_.size(); }
  // The axis of a parameter, or -1.
  int index(const std::string& name) const;

  // A task drawn uniformly.
  TaskPoint sample(Rng& rng) const;
  // A task's coordinates in the unit cube (the centre of a discrete value's slice) and back
  // (clamped into the cube first).
  std::vector<double> to_unit(const TaskPoint& task) const;
  TaskPoint from_unit(const std::vector<double>& unit) const;

  // The task as scenario parameters (text), in the space's order.
  ParamList params(const TaskPoint& task) const;
  // The task as a JSON object {"obstacles": 3, "shape": "spade", "distance": 1.25}: a choice's
  // value as param_value_json gives it (roger.choice{0, 200} records numbers, as an int axis does).
  nlohmann::json to_json(const TaskPoint& task) const;
  // One axis's value from a parameter's text ("3", "spade"); nullopt and `why` (what the axis
  // allows) when the text is not one of its values.
  std::optional<double> value_of(size_t dim, const std::string& text, std::string* why = nullptr) const;
  // The task a parameter list gives (every axis named once, nothing else); nullopt and `why`.
  std::optional<TaskPoint> task_of(const ParamList& params, std::string* why = nullptr) const;
  // Whether `sub` (an axis of the same parameter) lies inside this space's axis of its name.
  bool covers(const TaskDim& sub) const;

  // This space without the axes of these parameters (fixed by --set or a batch run's params).
  // The space remembers the axes it lost (fixed()): a teacher written for the whole space may
  // still name them, and the run's value stands (docs/curricula.md, Task spaces).
  TaskSpace without(const std::vector<std::string>& names) const;
  // The parameters whose axes without() removed, sorted.
  const std::vector<std::string>& fixed() const { return fixed_; }
  bool is_fixed(const std::string& name) const;
  // The axes without() removed, as a space of their own: what a teacher naming them is checked
  // against, though the run's value stands.
  TaskSpace fixed_space() const { return TaskSpace(fixed_dims_); }
  // "distance = roger.real(0.5, 2), obstacles = roger.int(0, 6)".
  std::string describe() const;

 private:
  std::vector<TaskDim> dims_;
  std::vector<std::string> fixed_;
  std::vector<TaskDim> fixed_dims_;
};

// The task space restricted on some axes (a step of a sequence): each axis of `restrict` replaces
// the space's axis of its name and must lie inside it; an axis of a parameter the run fixes
// (space.fixed()) is left out, the run's value standing. Throws roger::Error naming the axis.
TaskSpace restrict_space(const TaskSpace& space, const std::vector<TaskDim>& restrict);

// What a teacher chose for one training episode.
struct TaskPick {
  TaskPoint task;                      // in the teacher's space
  ParamList extra;                     // parameters outside the space (LCAS lifting one)
  std::optional<uint64_t> world_seed;  // a level replayed (PLR); else the episode's own world
};

// What came of it.
struct TaskOutcome {
  TaskPoint task;
  uint64_t world_seed = 0;
  bool success = false;
  double reward = 0.0;
  double sim_s = 0.0;
  double td_error = 0.0;  // the mean |TD error| of the episode's backups (PLR's score)
};

// A teacher: asked for the next training episode's task, told what came of it.
class Teacher {
 public:
  virtual ~Teacher() = default;
  // "random", "sequence", "lcas", "alp_gmm", "plr", "function".
  virtual std::string kind() const = 0;
  // The task of the next training episode.
  virtual TaskPick next() = 0;
  // The outcome of the episode of the last next().
  virtual void record(const TaskOutcome& outcome) = 0;
  // The teacher's own state, for the checkpoints' records (its step, level, mixture, levels).
  virtual nlohmann::json state() const = 0;
  // Parameters the test set's episodes run with beside their tasks: a parameter LCAS lifts from
  // outside the space is tested at its last level, the whole task.
  virtual ParamList test_params() const { return {}; }
};

// A built-in teacher's settings, as roger.teacher.<kind>{...} reads them.
struct TeacherSpec {
  enum class Kind { kRandom, kSequence, kLcas, kAlpGmm, kPlr };
  Kind kind = Kind::kRandom;
  std::string file;  // where it was written
  int line = 0;

  // sequence: steps in order, each a restriction of the space (restrict_space).
  struct Step {
    std::vector<TaskDim> restrict;
    double promote = 0.9;   // success rate over the window at or above which the next step begins
    double demote = -1.0;   // below which the previous step comes back (< 0: never)
    int window = 20;        // episodes of this step the rate is taken over
    std::vector<std::string> string_values;  // parameters whose one value was written as a Lua string ("1")
  };
  std::vector<Step> steps;

  // lcas: one parameter lifted through its levels.
  std::string lift;                 // the parameter
  std::vector<std::string> levels;  // its values, most constrained first
  std::vector<size_t> string_levels;  // 0-based indices of levels written as Lua strings ("32")
  int window = 50;                  // the saturation test compares the last two windows...
  double slope = 0.05;              // ...and lifts when the rate rose by less than this,
  double floor = 0.0;               // and the last window's rate is at least this: a curve flat at
                                    // zero (no success yet) has not saturated, it has not begun

  // alp_gmm (Portelas et al., 2019)
  int fit_every = 50;          // episodes between fits (uniform tasks until the first)
  int k_max = 6;               // mixtures of 2..k_max components, chosen by AIC
  double random_share = 0.2;   // share of uniform draws after the first fit
  int history = 250;           // the most recent (task, ALP) pairs a fit sees

  // plr (Jiang et al., 2021)
  double replay = 0.5;         // probability of replaying a seen level (once there is one)
  double temperature = 0.1;    // of the rank-based priorities
  double staleness = 0.1;      // share of the staleness priorities in the mix
  bool score_td = true;        // score: mean |TD error| (true) or 1 - success
  int buffer = 500;            // levels kept (the lowest scores make room)

  // "roger.teacher.alp_gmm", for messages.
  std::string name() const;
};

// A built-in teacher over `space` whose draws come from Rng(seed). Throws roger::Error for
// settings the space cannot take (a sequence step outside it, an LCAS level the lifted axis of
// the space does not have), naming spec.file:line.
std::unique_ptr<Teacher> make_teacher(const TeacherSpec& spec, const TaskSpace& space, uint64_t seed);

// What a teacher's recorded state (Teacher::state()) says it did, in one line for the console:
// "eye_pixels = 128 (level 3 of 3); lifted at episodes 31 (to 64), 59 (to 128)", "60 tasks drawn
// uniformly from the task space"; a move decided on the last episode's outcome is said as such
// ("; after the last episode, to 128, never trained"). "" for a state it does not know.
std::string describe_teacher_state(const nlohmann::json& state);

// A fixed test set: tasks drawn uniformly with Rng(seed), or given.
std::vector<TaskPoint> draw_test_tasks(const TaskSpace& space, int count, uint64_t seed);

}  // namespace roger
