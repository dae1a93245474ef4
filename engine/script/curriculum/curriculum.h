// curriculum.h: developmental curricula written in Lua (curricula/paper.lua). A curriculum script
// builds controllers with the control-basis API (lua_control.h) and returns its stages:
//
//   return {
//     name = "paper", description = "...",
//     stages = {
//       roger.stage{ name = "SG", scenario = "unobstructed", params = {}, time_limit = 5,
//                    absorbing = roger.converged(p.phi3),         -- or function(state) ... end
//                    reward = {absorbing = 100, timeout = -100, step = 0},  -- or a function
//                    learner = {alpha = 0.2, discount = 0.95, epsilon_start = 1, epsilon_end = 0.05},
//                    budget = {episodes = 300},
//                    checkpoints = {every = 20, episodes = 20, threshold = 0.9, seeds = 1000000,
//                                   stop_after = 0, settle = true, final = 50},
//                    contexts = { {name = "B1", actions = {...}}, ... },  -- or {B1 = {...}, ...}
//                    skill = {name = "Phi_SG", context = "DC2"} },
//       ...
//     },
//   }
//
// roger.stage{...} validates a stage where it is written (errors at that file:line) and returns
// the table; plain tables are accepted too and validated when the script returns. Contexts
// written as a list keep the script's order; written as a map they are ordered by name.
// roger.learned("Phi_SG") is a stand-in for the skill an earlier stage yields; it is bound
// to that stage's greedy policy at train time (Curriculum::bind_learned). docs/curricula.md is
// the reference.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "control/control.h"
#include "sim/world.h"
#include "learn/learning.h"
#include "script/sandbox/lua_sandbox.h"
#include "control/predicate.h"
#include "teach/teach.h"

namespace roger {

// When greedy evaluations happen during training and what counts as reaching the threshold.
struct CheckpointSpec {
  int every = 0;             // training episodes between greedy evaluations (0 = budget / 20)
  int episodes = 20;         // held-out episodes per evaluation
  double threshold = 0.9;    // success rate that counts as learned
  uint64_t seeds = 1000000;  // the first held-out seed (then seeds + 1, ...)
  int stop_after = 0;        // stop after this many consecutive passing checkpoints (0 = never)...
  bool settle = true;        // ...of one greedy policy (false: policies that changed count too)
  int final_episodes = 50;   // episodes of the final greedy evaluation (same held-out seeds)
};

// One developmental context: a named action set Psi.
struct CurriculumContext {
  std::string name;
  std::vector<ControllerPtr> actions;  // in the script's order (the state-vector order)
  std::vector<std::string> learned;    // the learned skills (roger.learned names) it reaches
  // Scenario parameters of this context, over the stage's (a developmental context that restricts
  // the body or the senses: eyes of 32 pixels, locked elbows), sorted by key.
  std::vector<std::pair<std::string, std::string>> params;
  // init = {stage = ..., context = ...}: the Q-table starts from that context's, trained first
  // with the same seed (a warm start, learn/warm_start.h); empty: from initial_q.
  std::string init_stage, init_context;
};

// A stage's test set (field `test`): the tasks every greedy evaluation runs, one episode each in
// world seed checkpoints.seeds + i, so the learning curve is the share of them mastered.
struct TestSetSpec {
  bool given = false;              // written by the stage; else drawn from the space
  int tasks = 0;                   // {tasks = N, seed = S}: N tasks drawn uniformly with Rng(S)...
  uint64_t seed = 0;
  std::vector<ParamList> list;     // ...or {list = {...}}: the tasks themselves
};

// One stage of a curriculum: an MDP per context, with shared task definition.
struct CurriculumStage {
  std::string name;
  std::string description;
  std::string scenario = "unobstructed";
  std::vector<std::pair<std::string, std::string>> params;  // scenario parameters, as text
  // An episode's time-out: time_limit seconds, plus time_per_object for each object of its world
  // (a stage written with time_limit = {per_object = s} has only the second).
  double time_limit = 0.0;
  double time_per_object = 0.0;
  PredicatePtr absorbing;            // null when absorbing is a Lua function
  bool absorbing_lua = false;        // called at decision points only
  LearningEpisodeOptions rewards;    // the fixed rewards and the discount's clock (not its time_limit)
  bool reward_lua = false;           // a Lua function(state, action, event) at decision points
  QParams learner;
  int budget_episodes = 0;
  CheckpointSpec checkpoints;
  std::vector<CurriculumContext> contexts;
  std::optional<std::pair<std::string, std::string>> skill;  // {skill name, context}
  // Teachers (docs/curricula.md, Teachers): each training episode's scenario parameters drawn
  // from a task space by a teacher, greedy evaluations on a test set of tasks.
  TaskSpace tasks;                     // empty: every episode has the stage's own parameters
  std::optional<TeacherSpec> teacher;  // a built-in teacher (random when only tasks are given)
  bool teacher_lua = false;            // a Lua function(history, rng): Curriculum::make_teacher
  TestSetSpec test;
  std::string file;  // where the stage is written
  int line = 0;
  // A scenario file of the bare name `scenario` beside the stage's file or its curriculum, which
  // the name does not take (scenario_beside): "" when none. scenario_note() says it.
  std::string scenario_beside;
  // Whether training episodes have tasks chosen by a teacher (then evaluations run a test set).
  bool teaches() const { return !tasks.empty() || teacher.has_value() || teacher_lua; }
  // The test set's tasks for a trial whose task space is `space` (the stage's, less what --set
  // fixes): the list written, or `count` tasks drawn (the first `count` of one sequence, so a
  // shorter evaluation runs a prefix of a longer one). Throws roger::Error for a listed task
  // outside the space.
  std::vector<TaskPoint> test_tasks(const TaskSpace& space, int count) const;
  // Throws ScriptError at the axis's (or the teacher's) file:line when scenario `scenario` cannot
  // play `space` (the stage's tasks, or what is left of them) as the stage field is checked against
  // the stage's own: an axis it has no parameter of, a real axis over an integer, an end or a choice
  // it refuses, an LCAS teacher's level it cannot set.
  void check_played_in(const std::string& scenario, const TaskSpace& space) const;
  // Throws ScriptError at the teacher's file:line when the parameters a run fixes (`fixed`, named
  // `fixed_by`: "--set", "the params of run 'R'") leave its teacher nothing to do: an LCAS
  // teacher's lifted parameter (in the task space or not: lifting it is all it does), or every
  // axis of an ALP-GMM teacher's space. train, check, batch runs and make() ask it alike.
  void check_fixed(const std::vector<std::string>& fixed, const std::string& fixed_by) const;
  // "" or, at the teacher's file:line, why it will never move within the budget: an LCAS window
  // that needs more than the budget's episodes at a level, a sequence step's window past the
  // budget (found by a probe: "at step 1 of 2, never moved" after the trial). A warning, not an
  // error: a stage that shows a teacher's mechanics may train a few episodes.
  std::string teacher_window_warning() const;
  // "" or, at the `scenario` field's file:line, why the scenario's path will not be found from
  // another folder than this one (scenario_found_from_here). A warning for roger check.
  std::string scenario_warning() const;
  // "" or, at the `scenario` field's file:line (the stage's when the default), that the bare name
  // is the project's scenario and not scenario_beside, and how to name that one. A note for
  // roger check, train and run: the shipped one is what the name documentedly means.
  std::string scenario_note() const;
  // "" or, at the `learner` field's file:line, that exploration rises over the budget
  // (epsilon_start below epsilon_end: the two swapped, most likely). A warning for roger check.
  std::string learner_warning() const;
  // How many test tasks each checkpoint's and the final evaluation run: the test set's, else the
  // checkpoints' episode counts.
  int checkpoint_test_tasks() const { return test.given ? test.tasks : checkpoints.episodes; }
  int final_test_tasks() const { return test.given ? test.tasks : checkpoints.final_episodes; }
  // The time-out of an episode in `world`: time_limit + time_per_object x its objects. Throws
  // ScriptError at the stage's line when that is no time (a per-object limit, no object).
  double episode_time_limit(const WorldSpec& world) const;
  // "12 s limit" or "30 s per object limit", for messages.
  std::string time_limit_text() const;
  // "stage 'SG'" or "stage 'SG', context 'B1'", for messages.
  std::string where(const std::string& context = "") const;
  // "file.lua:12: ", where the stage is written, in front of a message; "" when not known.
  std::string written_at() const;
  // The context by name. Throws roger::Error listing the stage's contexts.
  const CurriculumContext& context(const std::string& name) const;
  // The scenario parameters of an episode in `context`: the stage's, with the context's over them.
  std::vector<std::pair<std::string, std::string>> scenario_params(const CurriculumContext& context) const;
};

// Lua source given to a loaded curriculum from outside its script (the Python module's
// make(tasks=..., teacher=...)): the text of a value or of a chunk that returns one, or a file.
struct LuaSource {
  std::string text;   // "" when a file
  std::string name;   // as messages show it: the chunk's name ("make(teacher=...)") or the file
  bool file = false;  // `name` is a Lua file that returns the value
  bool empty() const { return text.empty() && !file; }
};

class Curriculum {
 public:
  // Runs the script at `path` (or curricula/<path>.lua for a bare name) and validates its stages.
  // Every call builds fresh controllers, so each training trial loads its own copy. Throws
  // ScriptError (file:line) or roger::Error.
  static Curriculum load(const std::string& path, const SandboxLimits& limits = {});

  Curriculum(Curriculum&&) noexcept;
  Curriculum& operator=(Curriculum&&) noexcept;
  ~Curriculum();

  const std::string& name() const;         // its `name` (or the file name)
  const std::string& description() const;  // "" when none
  const std::string& path() const;         // as shown in messages
  const std::string& file() const;         // the file that was run (for reloading)

  // The Lua files the script read: itself, then the modules it required (absolute paths).
  const std::vector<std::filesystem::path>& source_files() const;

  // The stages in order.
  const std::vector<CurriculumStage>& stages() const;
  // A stage by name. Throws roger::Error listing the stages.
  const CurriculumStage& stage(const std::string& name) const;
  // The stage whose `skill` yields a learned skill of this name, or null.
  const CurriculumStage* producer(const std::string& skill) const;
  // The learned skills a context uses, itself or through the skills it uses (what a --skill or a
  // Python `skills` entry may name).
  std::vector<std::string> skills_used(const CurriculumContext& context) const;
  // Why the context of `stage` cannot take a policy file for the learned skill `name` ("stage 'T',
  // context 'B2' uses no learned skill 'Phi_XX'; it uses ..."), or "" when it uses that skill.
  std::string unused_skill_problem(const CurriculumStage& stage, const std::string& context,
                                   const std::string& name) const;

  // Binds the stand-in roger.learned(name) to a skill (a learned policy made with
  // make_policy_skill). Throws roger::Error when the script has no such stand-in.
  void bind_learned(const std::string& name, ControllerPtr skill);
  // Whether the script made a stand-in for this learned skill.
  bool has_learned(const std::string& name) const;

  // The sandbox the script and its callbacks run in (roger check quiets its prints).
  LuaSandbox& sandbox();

  // The world the Lua callbacks are shown (their argument `world`), or null for none (nil): the
  // episode's world, set by whoever runs the episodes (the trainer).
  void set_world(const World* world);
  // The teacher of a stage that teaches, over `space` (the stage's task space less what --set
  // fixes), drawing from Rng(seed): a built-in one, or one that calls the stage's Lua function
  // between episodes (under the sandbox's budgets; a fault or a task outside the space is a
  // ScriptError at the function's file:line). Null for a stage without teacher or tasks.
  std::unique_ptr<Teacher> make_teacher(const CurriculumStage& stage, const TaskSpace& space, uint64_t seed);
  // Gives a stage another task space or teacher (the Python module's make(tasks=, teacher=)): each
  // source that is not empty is run in this curriculum's sandbox and its value read as the stage's
  // field of that name is, and checked as there: against the stage's params, and against
  // `scenario` when one is given (make(scenario=...): the one the environment plays), else the
  // stage's. New tasks without a teacher get the random one, as a stage written so does. Throws
  // ScriptError at the source's name:line, or roger::Error for an unknown stage.
  void set_teaching(const std::string& stage, const LuaSource& tasks, const LuaSource& teacher,
                    const std::string& scenario = "");
  // An episode begins: the callbacks' last argument, `episode`, is a new empty table from now on
  // (what they keep there, e.g. a count at the last decision, lasts one episode).
  void begin_episode();

  // Calls a stage's Lua absorbing function on a state (the gammas of a context's actions).
  // Throws ScriptError naming the stage, the context and file:line.
  bool call_absorbing(const CurriculumStage& stage, const CurriculumContext& context,
                      const std::vector<Gamma>& state, double time);
  // Calls a stage's Lua reward function for the action that ran until this state; event is
  // "decision", "absorbing" or "timeout". The result must be a finite number: otherwise a
  // ScriptError naming the stage, the context and the function's file:line.
  double call_reward(const CurriculumStage& stage, const CurriculumContext& context,
                     const std::vector<Gamma>& state, int action, const std::string& event, double time);

 private:
  Curriculum();
  struct Impl;
  static void read_stages(Impl& impl, const std::string& path);  // runs the script, reads its stages
  std::unique_ptr<Impl> impl_;
};

// Installs what a curriculum reaches (the control API of lua_control.h, roger.stage and
// roger.learned) into a fresh sandbox, as Curriculum::load does. Throws ScriptError if the state
// is out of memory.
void install_curriculum_api(LuaSandbox& sandbox);

// The file a curriculum argument names: the path itself if it is a file, else
// <project>/curricula/<name>.lua. Throws roger::Error when neither exists.
std::string resolve_curriculum_path(const std::string& name_or_path);

// Whether the file looks like a curriculum: its source writes a `stages` field (reads the text
// only). For `roger check` and `roger eval`, to pick the loader.
bool is_curriculum_script(const std::string& path);

// For `roger check`: loads a curriculum and generates one world of every stage's scenario with
// its parameters, `sets` over them as `roger train --set` sets them (a teacher function is then
// called on the space without their axes, as training calls it). `stages` names the stages
// checked (all when empty); `sets_from` names who gave `sets` in messages. Returns the problems
// (empty when sound), each a complete message.
std::vector<std::string> check_curriculum(const std::string& path, const SandboxLimits& limits = {},
                                          const ParamList& sets = {}, const std::vector<std::string>& stages = {},
                                          const std::string& sets_from = "--set");
// The same of a curriculum loaded already (its top level is not run again: `roger check` of a
// curriculum that prints printed it twice).
std::vector<std::string> check_curriculum(Curriculum& cur, const SandboxLimits& limits = {}, const ParamList& sets = {},
                                          const std::vector<std::string>& stages = {},
                                          const std::string& sets_from = "--set");

// What check_curriculum says of a stage's task space, for one given from outside (Python's
// make(tasks=..., teacher=...)): the worlds at its ends (each axis's lowest and highest value, each
// choice, each level an LCAS teacher lifts) that cannot be built, in `context`'s parameters and
// `sets`. Only errors of the parameters count: a task no layout holds is skipped where it is drawn,
// and said (a space of nothing else is refused at its first reset).
std::vector<std::string> task_space_end_problems(const CurriculumStage& stage, const std::string& context,
                                                const SandboxLimits& limits, const ParamList& sets);

// The test sets of `stages` (all when empty) as their trials will meet them, `sets` over the
// stages' parameters: each test task no layout of its world seed holds, which would fail every
// trial at its first evaluation (check_curriculum's words). roger run asks before any trial runs.
std::vector<std::string> check_test_sets(const std::string& path, const SandboxLimits& limits, const ParamList& sets,
                                         const std::vector<std::string>& stages);

// Every Lua file training with this curriculum reads: its own source files, then each stage's
// scenario and the modules that requires, each once (absolute paths). A batch fingerprints them,
// so that results are never resumed after any of them changed. Throws like Scenario::load.
std::vector<std::filesystem::path> curriculum_source_files(const Curriculum& cur, const SandboxLimits& limits = {});

// The names of roger.teacher's teachers (`teachers`), else of the task axes roger.int, .real and
// .choice, as the curriculum API installs them: for messages naming what exists.
std::vector<std::string> teaching_names(bool teachers);

}  // namespace roger
