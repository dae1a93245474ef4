// scenario_internal.h: what the scenario's files share (private to script/scenario/).
//
// scenario_geometry.cpp measures placed shapes, scenario_shapes.cpp holds roger.shape and the shape
// values, scenario_rng.cpp the rng object, scenario_world.cpp the world builder's methods and the
// installation of the Lua API, scenario_placement.cpp world:sample_position, scenario_params.cpp
// the parameters, and scenario.cpp the Scenario class.
#pragma once

#include <cstdio>

#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <lua.hpp>

#include "core/body.h"
#include "core/rng.h"
#include "script/sandbox/lua_sandbox.h"
#include "script/sandbox/lua_tokens.h"
#include "script/scenario/scenario.h"

namespace roger {
namespace scenario_detail {

constexpr const char* kShapeType = "roger.Shape";
constexpr const char* kRngType = "roger.Rng";
constexpr const char* kWorldType = "roger.World";
constexpr const char* kParamsType = "roger.Params";  // generate's third argument
constexpr const char* kBodyMetricsType = "roger.BodyMetrics";  // roger.body_metrics's result
constexpr size_t kMaxThings = 1000;   // objects, obstacles or goals in one world
constexpr size_t kMaxParts = 64;      // polygons plus disks in one shape

// A number for messages, with rounding noise near zero shown as 0.
inline std::string fmt(double v) { return format_number(std::abs(v) < 5e-13 ? 0.0 : v); }
// A length the engine computed (an overlap, a margin), to four significant digits: "0.41", not
// the 0.41000000000000003 its arithmetic gave.
inline std::string measured(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", std::abs(v) < 5e-13 ? 0.0 : v);
  return text;
}

// "(x, y)" for messages.
inline std::string point_text(double x, double y) { return "(" + fmt(x) + ", " + fmt(y) + ")"; }

// A shape value: validated when made, immutable afterwards.
struct ShapeBox {
  Shape shape;
  double radius = 0.0;
  double area = 0.0;
};

// The world being built by one generate() call.
struct WorldBuilder {
  WorldSpec spec;
  bool arena_set = false;    // world:arena was called
  bool arena_fixed = false;  // something depends on the arena: it can no longer change
  bool robot_set = false;
  bool stimulus_set = false;
  bool finished = false;     // generate returned: the world is read-only
  Rng* rng = nullptr;        // the generator's rng, kept alive as the world's user value
  bool* no_placement = nullptr;  // set when world:sample_position finds no place (PlacementError)
};

// The optional number field `key` of f (`fallback` when absent) within [lo, hi], or (lo, hi] when
// `low_open`; else raises naming the field, the range, the unit and the value.
double ranged(const LuaFields& f, const char* key, double fallback, double lo, double hi, const char* unit,
              bool low_open = false);

// world:robot's body = {...} and eyes = {...} fields (the defaults when absent); each bad value
// raises "context: body: field ..." with the range and the known fields.
RobotParams read_body(const LuaFields& parent);
EyeParams read_eyes(const LuaFields& parent);
// world:robot's noise = {image, joints, base, touch, effort} (sigmas, each range-checked); none if absent.
NoiseParams read_noise(const LuaFields& parent);
// The image's quantum as the senses apply it: colours are whole levels, so it is rounded to the
// nearest (half away from 0, as the senses round), and a grid of one level or none changes no
// colour, so it is none (0): such an image runs to the bit as without the field.
double image_quantum_levels(double quantum);
// Raises when the body cannot be built (core/body.h, body_problems), naming every problem.
void check_body(const LuaFields& f, const RobotParams& body, const EyeParams& eyes);
// roger.body_metrics{ body = ..., eyes = ... }.
int l_body_metrics(lua_State* L);

// __gc of userdata holding a C++ object.
template <class T>
int destroy(lua_State* L) {
  static_cast<T*>(lua_touserdata(L, 1))->~T();
  return 0;
}

// The object a method is called on, with a hint for the common `world.object{...}` slip.
template <class T>
T& self(lua_State* L, const char* type, const char* call) {
  void* p = luaL_testudata(L, 1, type);
  if (!p) {
    const std::string c = call;
    const std::string object = c.substr(0, c.find(':'));
    // Called with no argument at all, the first is none (found by a probe: "is a no value").
    const std::string first = lua_isnone(L, 1) ? std::string("it was given no argument")
                                               : std::string("the first argument is a ") + luaL_typename(L, 1);
    luaL_error(L, "%s: call it with a colon, as %s(...) (%s, not the %s)", call, call, first.c_str(), object.c_str());
  }
  return *static_cast<T*>(p);
}

// ---- scenario_geometry.cpp ----

// How far inside the arena walls the shape stays (negative: by how much it sticks out).
double arena_inset(const ArenaSpec& arena, const Shape& shape, const Pose& pose);

// A one-disk shape, for Roger's base and hands and goal regions.
Shape disk_shape(const std::string& name, const Vec2& c, double r);

// ---- scenario_shapes.cpp ----

// roger.shape{...}.
int l_shape(lua_State* L);
// shape.name, .radius, .area, .polygons, .disks and :scaled.
int l_shape_index(lua_State* L);
// shape:scaled(factor [, name]).
int l_shape_scaled(lua_State* L);
// tostring(shape).
int l_shape_tostring(lua_State* L);
// The shape value at index, or null.
ShapeBox* test_shape(lua_State* L, int index);

// ---- scenario_rng.cpp ----
// A script's rng. One of a generate call (and its forks) has that call's epoch and draws only while
// the call runs: kept in an upvalue, it would make a world depend on the worlds generated before it
// in that Lua state, which --jobs orders differently. Epoch 0 (a teacher function's) draws as long
// as it is held.
struct ScriptRng {
  Rng rng;
  lua_Integer epoch = 0;
};

// Pushes a new rng value seeded with `seed`, of `epoch`.
ScriptRng& push_rng(lua_State* L, uint64_t seed, lua_Integer epoch);
// A generate call's epoch, new in this Lua state, whose rngs draw until close_rng_epoch (or the next
// open_rng_epoch).
lua_Integer open_rng_epoch(lua_State* L);
void close_rng_epoch(lua_State* L);
void set_live_rng_epoch(lua_State* L, lua_Integer epoch);  // the rngs of `epoch` draw again
// rng:uniform, rng:int, rng:normal, rng:angle, rng:choice, rng:shuffle and rng:fork.
int l_rng_uniform(lua_State* L);
int l_rng_int(lua_State* L);
int l_rng_normal(lua_State* L);
int l_rng_angle(lua_State* L);
int l_rng_choice(lua_State* L);
int l_rng_shuffle(lua_State* L);
int l_rng_fork(lua_State* L);

// ---- scenario_world.cpp ----

// "4 x 4 m arena", for messages.
std::string arena_text(const ArenaSpec& a);

// A named thing already in the world that new things must not overlap.
struct Occupant {
  std::string what;  // "obstacle 'box'", "Roger's left hand"
  const Shape* shape;
  Pose pose;
};

// Everything placed so far that blocks space (the robot's footprint disks own their shapes).
struct Occupants {
  std::vector<Shape> robot_shapes;
  std::vector<Occupant> list;
};

// Roger's footprint (when placed), then the objects, then the obstacles, as requested.
Occupants occupants(const WorldBuilder& w, bool objects, bool obstacles);

// The world a method is called on, refusing a world whose generate call is over.
WorldBuilder& world_self(lua_State* L, const char* call);

// Once something depends on the arena, world:arena may no longer change it.
void fix_arena(WorldBuilder& w);

// Installs the metatables and the `roger` table (run protected).
int install_api(lua_State* L);

// ---- scenario_placement.cpp ----

// world:sample_position{...}.
int l_world_sample(lua_State* L);

// ---- scenario_params.cpp ----

// A parameter's current value in its own type.
struct ParamSlot {
  ScenarioParam info;
  double number = 0.0;
  int64_t integer = 0;
  std::string text;
  bool flag = false;
};

// The canonical text of a parameter value (what WorldSpec::params records).
std::string slot_text(const ParamSlot& s);

// Pushes a parameter value with its Lua type.
void push_slot(lua_State* L, const ParamSlot& s);

// Parses text into a slot of the slot's type; false (and `why`) when it does not fit.
bool parse_slot(ParamSlot& s, const std::string& text, std::string& why);
// What a parameter takes, whole: "an integer in [0, 12]", "one of circle, spade", ...
std::string expected_text(const ScenarioParam& p);

// "name (type, default d; one of ...)", for the unknown-parameter message.
std::string describe_param(const ScenarioParam& p);

}  // namespace scenario_detail

struct Scenario::Impl {
  LuaSandbox sandbox;
  std::string path;  // as shown
  std::string name, description;
  int generate_ref = LUA_NOREF;
  int generate_line = 0;
  int reads_ref = LUA_NOREF;  // the names generate's params were read by (push_params_view), once one ran
  bool no_placement = false;  // the last generate's world:sample_position found no place
  std::map<std::string, scenario_detail::ParamSlot> params;

  explicit Impl(const SandboxLimits& limits) : sandbox(limits) {}

  // Runs `body` inside a protected call (body may use the Lua API and throw). Errors without a
  // location are attributed to the scenario file.
  void protect(const std::function<void(lua_State*)>& body, int nargs = 0);

  // A ScriptError at the scenario file (and line, when known).
  // An error of the scenario file, at `line`; without one, at the line being read (0 once the
  // returned table is read).
  ScriptError error(const std::string& message, int line = -1) const {
    return ScriptError(message, path, line < 0 ? reading_line : line, "");
  }

  // Pushes generate's third argument: a view of the values in force (scenario_world.cpp), whose
  // reads go to the table of names read (reads_ref, made by the first generate).
  void push_params_view(lua_State* L);
  // Reads the `params` table (scenario_params.cpp); `map`: where the script's tables are written,
  // `node` the constructor of this one in it (-1: not written in the text).
  void read_params(lua_State* L, int index, const LuaTableMap& map, int node);
  // Checks the table the script returned and keeps its generator (scenario.cpp).
  void read_table(lua_State* L, const LuaTableMap& map);
  // While the returned table is read: the line of what is being read.
  int reading_line = 0;
  // The slot `key` would hold with `value` (into `out`), or why not: Scenario::set_param's message.
  std::optional<std::string> parse_param(const std::string& key, const std::string& value,
                                         scenario_detail::ParamSlot& out) const;
  // The known parameters, for the message of an unknown one (scenario.cpp).
  std::string known_params_text() const;

 private:
  // The parts of read_params (scenario_params.cpp).
  scenario_detail::ParamSlot read_param(lua_State* L) const;
  int read_param_table(lua_State* L, int value, const std::string& ctx,
                       scenario_detail::ParamSlot& slot, std::vector<std::string>& choices) const;
  void read_choices(lua_State* L, const LuaFields& f, const std::string& ctx,
                    std::vector<std::string>& choices) const;
  void read_default(lua_State* L, int value, const std::string& ctx,
                    scenario_detail::ParamSlot& slot) const;
  void check_choices_in_bounds(const ScenarioParam& p, const std::string& ctx) const;
};

}  // namespace roger
