// scenario.h: world generators written in Lua (scenarios/*.lua), run in a LuaSandbox.
//
// A scenario script returns a table
//   { name = "...", description = "...", params = { shape = "circle", obstacles = 3, ... },
//     generate = function(world, rng, params) ... end }
// and generate() turns (script, parameters, seed) into a WorldSpec: a world is a pure function of
// the three. The Lua API (world:arena/robot/object/obstacle/goal/stimulus/sample_position,
// roger.shape, the rng object) validates every call where it is made, so a mistake names the
// script's file:line. docs/scenarios.md is the reference.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "script/sandbox/lua_sandbox.h"
#include "core/spec.h"

namespace roger {

// A world the generator could not place: world:sample_position found no position that keeps every
// constraint (the parameters asked for more than the arena holds, or a rare layout left no room).
// Not a mistake in the script: a teacher's trainer skips such a task and draws another.
struct PlacementError : ScriptError {
  explicit PlacementError(const ScriptError& e) : ScriptError(e) {}
};

// The type of a scenario parameter, taken from its default value.
enum class ParamType { kNumber, kInteger, kString, kBoolean };

// "number", "integer", "string" or "boolean".
const char* param_type_name(ParamType type);

// Whether `text` is a finite number as a number parameter reads it (--set's rules), and its value.
bool parse_number_text(const std::string& text, double& value);

// The items of a list parameter's text, split at its commas, the spaces and tabs around each
// dropped; empty ones kept ("" is one empty item).
std::vector<std::string> list_param_items(const std::string& text);

// One scenario parameter: its default, current value (both as text) and constraints.
struct ScenarioParam {
  std::string name;
  ParamType type = ParamType::kNumber;
  std::string default_value;
  std::string value;
  std::string description;
  std::vector<std::string> choices;  // allowed values; empty when any value of the type goes
  std::optional<double> min, max;    // bounds of numbers and integers
  bool list = false;                 // a comma-separated list of choices (any of them, or none)
};

class Scenario {
 public:
  // Runs the script at `path` (or scenarios/<path>.lua for a bare name such as "cluttered") and
  // checks the table it returns. Throws ScriptError (file:line) or roger::Error.
  static Scenario load(const std::string& path, const SandboxLimits& limits = {});

  Scenario(Scenario&&) noexcept;
  Scenario& operator=(Scenario&&) noexcept;
  ~Scenario();

  // The scenario's name (its `name` field, or the file name without .lua).
  const std::string& name() const;
  // Its one-paragraph description ("" when none).
  const std::string& description() const;
  // The script as shown in messages.
  const std::string& path() const;

  // The parameters, sorted by name, with their defaults and current values.
  std::vector<ScenarioParam> params() const;

  // The declared parameters no generate of this scenario has read (by name, by rawget, by pairs or
  // next), sorted: after roger check's worlds, those no --set or teacher could change a world with.
  std::vector<std::string> unread_params();
  // Of the names `sets` gives (a command's --set), those unread_params holds, in their order, once
  // each: a --set that changed no world (roger train, eval and run say so).
  std::vector<std::string> unread_params(const std::vector<std::pair<std::string, std::string>>& sets);

  // Sets a parameter from text (the CLI's --set key=value), converting by the default's type.
  // Throws roger::Error for an unknown key (listing the known ones), a value of the wrong type or
  // one outside the declared choices or bounds.
  void set_param(const std::string& key, const std::string& value);
  // Sets several at once (--set, a stage's params), or sets none and throws roger::Error naming
  // every one that set_param would refuse, joined by "; ".
  void set_params(const std::vector<std::pair<std::string, std::string>>& values);
  // What set_param would say of each of `values`, in order (empty when all would be taken);
  // changes nothing. `from_lua`: the values were written in a Lua table (a stage's, a context's or
  // a batch script's params), where a boolean parameter takes true or false only: Lua reads 0 as
  // true, so `capsule = 0` is refused rather than taken as the command line's --set capsule=0.
  std::vector<std::string> param_problems(const std::vector<std::pair<std::string, std::string>>& values,
                                          bool from_lua = false) const;

  // Runs the generator for a seed with a fresh Rng(seed) and the current parameters, and returns
  // the validated world. Throws ScriptError (file:line) on any problem, PlacementError when the
  // error was world:sample_position finding no place. Not thread-safe: use one Scenario per thread.
  WorldSpec generate(uint64_t seed);

  // Whether the generator keeps state between calls: builds world `seed` three times in a row and
  // returns what differs between the builds ("generate is not a function of ..."), or "" when
  // they agree. For roger check (a counter in a global made each world depend on those built
  // before it). Throws as generate does.
  std::string impurity(uint64_t seed);

  // The sandbox the script runs in.
  LuaSandbox& sandbox();

 private:
  Scenario();
  WorldSpec generate_world(uint64_t seed);  // generate, without telling a PlacementError apart
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Installs what a scenario script reaches (roger.shape, roger.robot, roger.version and the world,
// rng and shape objects) into a fresh sandbox, as Scenario::load does. Throws ScriptError if the
// state is out of memory.
void install_scenario_api(LuaSandbox& sandbox);

// Pushes an rng object (a generator's `rng`: uniform, int, normal, angle, choice, shuffle, fork)
// seeded with `seed`, registering its class in this Lua state on first use: a curriculum's teacher
// function gets one. It and its forks draw only between lua_rng_calls_begin(L, key) and
// lua_rng_calls_end(L), `key` being what this returns: kept past its function's call and drawn
// from by another callback, it would make that callback's results depend on the teacher's calls.
// Raises Lua errors: call it inside a protected call.
int64_t lua_push_rng(lua_State* L, uint64_t seed);
void lua_rng_calls_begin(lua_State* L, int64_t key);
void lua_rng_calls_end(lua_State* L);
// Whether `name` is a method of the rng objects of state L (false before the first is pushed).
bool lua_is_rng_method(lua_State* L, const std::string& name);

// The file a scenario argument names: the path itself if it is a file, else
// <project>/scenarios/<name>.lua for a bare name. Throws roger::Error listing the shipped
// scenarios when neither exists.
std::string resolve_scenario_path(const std::string& name_or_path);

// The scenario a script names (a stage's `scenario`, a batch script's evaluation's), as the
// loader should record it: a path (x.lua, worlds/x.lua) is looked for first beside the file that
// names it (`naming_file`, as messages show it), as `require` looks beside the script, then beside
// `also_beside` when given (a curriculum that set the field of a stage a library made), then as
// resolve_scenario_path finds it (from the current folder, then in the project); a bare name is
// one of the project's scenarios. Returns `name` itself unless the file beside differs from what
// `name` gives from here; then its path relative to the project (absolute outside it). Throws
// roger::Error listing where it looked.
std::string resolve_scenario_near(const std::string& name, const std::string& naming_file,
                                  const std::string& also_beside = "");

// "" or, when `name` is a bare name (one of the project's scenarios/, as resolve_scenario_near
// records it) and a scenario `<name>.lua` lies beside `naming_file` or else beside `also_beside`,
// that file as those are shown ("cluttered.lua" beside "cur.lua"): a copy made to be edited, which
// the bare name does not take. For the note roger check, train and run give of it.
std::string scenario_beside(const std::string& name, const std::string& naming_file,
                            const std::string& also_beside = "");

// For `roger check`: "" or, when `recorded` (what resolve_scenario_near returned for a name of
// `naming_file`) is a path found only from the current folder (not beside the file, not in the
// project), why it will not be found from another folder and how to write it beside the file.
std::string scenario_found_from_here(const std::string& recorded, const std::string& naming_file,
                                     const std::string& kind = "scenario");

// For `roger check`: loads a scenario and generates worlds for seeds 0..seeds-1, and one world of
// seed 0 for every choice of every parameter that declares choices, and both values of a boolean,
// one parameter at a time (the others at their defaults). Returns the problems found (empty when the scenario is sound); each
// is a complete message with file:line where known, after the value that failed.
// With `range_ends`, also one world at each end (min, max) of every numeric parameter that
// declares them; those that fail go there ("obstacles=12 (its max), seed 0: ..."), apart from the
// problems: a range's end often holds only with other parameters changed too (a longer arm in a
// larger arena), so it is a warning for the author, not a fault of the scenario as declared.
std::vector<std::string> check_scenario(const std::string& path, int seeds = 5,
                                        const SandboxLimits& limits = {},
                                        std::vector<std::string>* range_ends = nullptr);
// The same on a scenario already loaded (its parameters are back at their values after).
std::vector<std::string> check_scenario(Scenario& scenario, int seeds, std::vector<std::string>* range_ends = nullptr);

// What is wrong with a world whose objects none has the colour its eyes look for (world:stimulus),
// or "" (a world without objects looks for nothing in particular).
std::string stimulus_unseen(const WorldSpec& w);

// "in 5 of 5 worlds (the first: seed 0) no object has the stimulus colour ...": stimulus_unseen
// over the worlds of seeds first_seed .. first_seed + worlds - 1 (one that cannot be generated is
// passed over: its error is said where it is built), or "" when every world has it. A colour typo
// otherwise shows only as every episode failing.
std::string stimulus_unseen_note(Scenario& scenario, uint64_t first_seed, int worlds);

// The ends of a numeric parameter's declared range as the text --set takes, with "min" or "max"
// (an integer's rounded inwards); none for other parameters.
std::vector<std::pair<std::string, std::string>> numeric_ends(const ScenarioParam& p);

// The numeric body parameters of scenarios/lib/body.lua (upper_arm, forearm, base_radius,
// hand_radius, eye_pixels, eye_fov) as the world's Roger has them.
std::vector<std::pair<std::string, double>> body_param_values(const WorldSpec& world);

// Gap between two placed shapes: the distance between them when apart, minus the penetration
// depth when they overlap (exact for unions of convex polygons and disks).
double shape_gap(const Shape& a, const Pose& pa, const Shape& b, const Pose& pb);

// Roger's footprint in a start posture: the base disk and the two hand disks, world frame.
std::vector<Disk> robot_footprint(const RobotStart& start, const RobotParams& body = RobotParams{});

// The largest distance from Roger's base centre to the edge of its footprint in the body's folded
// start posture (0.383 m for the default Roger): a disk of this radius holds Roger at any heading.
double robot_footprint_radius(const RobotParams& body = RobotParams{});

}  // namespace roger
