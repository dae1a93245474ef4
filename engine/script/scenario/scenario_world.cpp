// scenario_world.cpp: the world builder's methods (arena, robot, objects, obstacles, goals,
// stimulus) with their checks, and the installation of the scenario's Lua API.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <string>
#include <tuple>
#include <vector>

#include "core/robot.h"
#include "core/text.h"
#include "script/scenario/scenario_internal.h"

namespace roger {
namespace scenario_detail {

// The world a method is called on, refusing a world whose generate call is over.
WorldBuilder& world_self(lua_State* L, const char* call) {
  WorldBuilder& w = self<WorldBuilder>(L, kWorldType, call);
  if (w.finished)
    luaL_error(L, "%s: this world is finished (world methods work only while generate runs)", call);
  return w;
}

// "4 x 4 m arena", for messages.
std::string arena_text(const ArenaSpec& a) {
  return fmt(a.xmax - a.xmin) + " x " + fmt(a.ymax - a.ymin) + " m arena";
}

// Roger's footprint (when placed), then the objects, then the obstacles, as requested.
Occupants occupants(const WorldBuilder& w, bool objects, bool obstacles) {
  Occupants out;
  if (w.robot_set) {
    const char* names[3] = {"Roger's base", "Roger's left hand", "Roger's right hand"};
    const auto disks = robot_footprint(w.spec.robot, w.spec.body);
    for (size_t i = 0; i < disks.size(); ++i)
      out.robot_shapes.push_back(disk_shape(names[i], disks[i].center, disks[i].radius));
    for (const auto& s : out.robot_shapes) out.list.push_back(Occupant{s.name, &s, Pose{}});
  }
  if (objects)
    for (const auto& o : w.spec.objects) out.list.push_back(Occupant{"object '" + o.name + "'", &o.shape, o.pose});
  if (obstacles)
    for (const auto& o : w.spec.obstacles)
      out.list.push_back(Occupant{"obstacle '" + o.name + "'", &o.shape, o.pose});
  return out;
}

namespace {

// Raises an error if the shape sticks out of the arena or overlaps an occupant.
void check_free(const LuaFields& f, const WorldBuilder& w, const std::string& what, const Shape& shape,
                const Pose& pose, bool against_obstacles) {
  const double inset = arena_inset(w.spec.arena, shape, pose);
  // Written only for a message: every placement passes here, most of them in every world drawn.
  const auto at = [&] { return what + " at " + point_text(pose.x, pose.y); };
  if (inset < -1e-9) {
    const auto& a = w.spec.arena;
    f.fail(at() + " sticks out of the arena [" + fmt(a.xmin) + ", " + fmt(a.xmax) + "] x [" +
           fmt(a.ymin) + ", " + fmt(a.ymax) + "] by " + measured(-inset) + " m");
  }
  const Occupants occ = occupants(w, true, against_obstacles);
  lua_charge(f.state(), occ.list.size() * (shape.polygons.size() + shape.disks.size()));
  for (const auto& o : occ.list) {
    const double gap = shape_gap(shape, pose, *o.shape, o.pose);
    if (gap < -1e-9) f.fail(at() + " overlaps " + o.what + " by " + measured(-gap) + " m");
  }
}

// Refuses a goal region whose centre an obstacle covers, whichever of the two is placed last: the
// navigator (phi1) goes to a region's centre, so such a region is never reached, however much of it
// is free floor (found by a probe: every episode failed with "no reference", naming other causes).
void check_goal_centre_free(const LuaFields& f, const GoalRegion& g, const ObstacleSpec& o) {
  const Shape centre = disk_shape(g.name, g.center, 1e-6);
  if (shape_gap(centre, Pose{}, o.shape, o.pose) < 0.0)
    f.fail("goal '" + g.name + "' has its centre " + point_text(g.center.x(), g.center.y()) + " under obstacle '" +
           o.name + "' (at " + point_text(o.pose.x, o.pose.y) + "): the navigator goes to a goal region's centre, "
           "which no one reaches there; move the goal or the obstacle");
}

}  // namespace

// Once something depends on the arena, world:arena may no longer change it.
void fix_arena(WorldBuilder& w) { w.arena_fixed = true; }

namespace {

// The given name, or "<kind> N"; refuses a name already used by a thing of the same kind.
std::string unique_name(const LuaFields& f, const std::string& given, const char* kind, size_t count,
                        const std::vector<std::string>& taken) {
  const std::string name = given.empty() ? std::string(kind) + " " + std::to_string(count + 1) : given;
  // Pictures, pages and results show the name (found by a probe: roger check took "bad\255" and
  // every picture then failed with "input string not valid UTF-8", naming neither file nor object).
  if (const std::string problem = name_text_problem(name); !problem.empty()) f.fail("field 'name' " + problem);
  const std::string a_kind = std::string(std::strchr("aeiou", kind[0]) ? "an " : "a ") + kind;
  // Found by a probe: an unnamed object's default name taken by a named one was said at a line
  // that names nothing.
  if (std::find(taken.begin(), taken.end(), name) != taken.end())
    f.fail("there is already " + a_kind + " named '" + name + "'" +
           (given.empty() ? std::string(": this one is given no name, and its default name ('") + kind +
                                " N' for the Nth " + kind + " made) is taken; give it a 'name'"
                          : std::string()));
  return name;
}

// world:arena{xmin=, xmax=, ymin=, ymax=, cell=, wall_colour=}
int l_world_arena(lua_State* L) {
  return lua_protect(L, [L]() {
    WorldBuilder& w = world_self(L, "world:arena");
    lua_check_arity(L, "world:arena", 1, "1 argument (a table of fields)");
    LuaFields f(L, 2, "world:arena", {"xmin", "xmax", "ymin", "ymax", "cell", "wall_colour"});
    if (w.arena_set) f.fail("the arena is already set (call world:arena once)");
    if (w.arena_fixed)
      f.fail("call world:arena first, before anything is placed, sampled or measured by world:bounds() (the "
             "default arena is already in use)");
    ArenaSpec a;
    a.xmin = f.number("xmin", a.xmin);
    a.xmax = f.number("xmax", a.xmax);
    a.ymin = f.number("ymin", a.ymin);
    a.ymax = f.number("ymax", a.ymax);
    a.cell = f.number("cell", a.cell);
    a.wall_colour = f.colour("wall_colour", a.wall_colour);
    for (auto [lo, hi, axis] : {std::tuple{a.xmin, a.xmax, "x"}, std::tuple{a.ymin, a.ymax, "y"}}) {
      if (!(hi - lo >= 0.5) || hi - lo > 1000.0)
        f.fail(std::string("the ") + axis + " extent must be 0.5 to 1000 m, got [" + fmt(lo) + ", " + fmt(hi) + "]");
      // The physics holds positions in single precision: 100 km out a step is 8 mm, and Roger's base
      // could not move there (found by a probe: roger check said ok, and every episode failed).
      // Within 1000 m of the origin a step is under 0.1 mm.
      if (lo < -1000.0 || hi > 1000.0)
        f.fail(std::string("the arena must lie within 1000 m of the origin along ") + axis + ", got [" + fmt(lo) +
               ", " + fmt(hi) + "] (the physics holds positions in single precision, which far out loses the "
               "millimetres Roger moves by: move the arena's coordinates nearer 0)");
      if (!(a.cell > 0.0)) f.fail("cell must be a positive size in metres, got " + fmt(a.cell));
      const double cells = (hi - lo) / a.cell;
      if (std::abs(cells - std::round(cells)) > 1e-6 * std::max(1.0, cells))
        f.fail(std::string("the ") + axis + " extent " + fmt(hi - lo) + " m is not a whole number of " +
               fmt(a.cell) + " m cells");
      if (cells < 4 || cells > 1024)
        f.fail("the occupancy grid needs 4 to 1024 cells per side, got " + fmt(std::round(cells)) +
               " along " + axis);
    }
    w.spec.arena = a;
    w.arena_set = true;
    return 0;
  });
}

// world:bounds() -> xmin, xmax, ymin, ymax (fixes the arena).
int l_world_bounds(lua_State* L) {
  WorldBuilder& w = world_self(L, "world:bounds");
  lua_check_arity(L, "world:bounds", 0, "no arguments");
  fix_arena(w);
  const auto& a = w.spec.arena;
  for (double v : {a.xmin, a.xmax, a.ymin, a.ymax}) lua_pushnumber(L, v);
  return 4;
}

// world:robot{x=, y=, heading=, left_shoulder=, left_elbow=, right_shoulder=, right_elbow=,
//             left_eye=, right_eye=, body=, eyes=, noise=}
int l_world_robot(lua_State* L) {
  return lua_protect(L, [L]() {
    WorldBuilder& w = world_self(L, "world:robot");
    lua_check_arity(L, "world:robot", 1, "1 argument (a table of fields)");
    LuaFields f(L, 2, "world:robot",
                {"x", "y", "heading", "left_shoulder", "left_elbow", "right_shoulder", "right_elbow",
                 "left_eye", "right_eye", "body", "eyes", "noise"});
    if (w.robot_set) f.fail("Roger is already placed (call world:robot once)");
    fix_arena(w);
    const RobotParams p = read_body(f);
    const EyeParams eyes = read_eyes(f);
    check_body(f, p, eyes);
    const NoiseParams noise = read_noise(f);
    // The arms start folded as this body folds them, unless the script says otherwise.
    RobotStart r = folded_start(p);
    r.pose = Pose{f.number("x"), f.number("y"), f.number("heading", 0.0)};
    auto joint = [&](const char* key, double fallback, double lo, double hi) {
      const double v = f.number(key, fallback);
      if (v < lo || v > hi)
        f.fail(std::string("field '") + key + "' must be within [" + fmt(lo) + ", " + fmt(hi) +
               "] rad, got " + fmt(v));
      return v;
    };
    r.left_shoulder = joint("left_shoulder", r.left_shoulder, p.shoulder_min, p.shoulder_max);
    r.left_elbow = joint("left_elbow", r.left_elbow, p.elbow_min, p.elbow_max);
    r.right_shoulder = joint("right_shoulder", r.right_shoulder, -p.shoulder_max, -p.shoulder_min);
    r.right_elbow = joint("right_elbow", r.right_elbow, -p.elbow_max, -p.elbow_min);
    r.left_eye = joint("left_eye", r.left_eye, -p.eye_pan_limit, p.eye_pan_limit);
    r.right_eye = joint("right_eye", r.right_eye, -p.eye_pan_limit, p.eye_pan_limit);
    const char* names[3] = {"Roger's base", "Roger's left hand", "Roger's right hand"};
    const auto disks = robot_footprint(r, p);
    for (size_t i = 0; i < disks.size(); ++i)
      check_free(f, w, names[i], disk_shape(names[i], Vec2::Zero(), disks[i].radius),
                 Pose{disks[i].center.x(), disks[i].center.y(), 0.0}, true);
    w.spec.robot = r;
    w.spec.body = p;
    w.spec.eyes = eyes;
    w.spec.noise = noise;
    w.robot_set = true;
    return 0;
  });
}

// The shape field of world:object and world:obstacle.
const Shape& shape_field(lua_State* L, const LuaFields& f) {
  f.push("shape");
  ShapeBox* box = test_shape(L, -1);
  if (!box) {
    const bool missing = lua_isnil(L, -1);
    lua_pop(L, 1);
    if (missing) f.fail("missing required field 'shape' (a shape made by roger.shape{...})");
    f.wrong_type("shape", "a shape made by roger.shape{...}");
  }
  lua_pop(L, 1);  // the userdata stays alive: the argument table holds it
  return box->shape;
}

// The fields world:object and world:obstacle share: a name unique among the things of its kind
// (made from `kind` and a number when none is given), the shape, the colour and the pose.
template <class Thing>
void read_thing(lua_State* L, const LuaFields& f, const char* kind, const std::vector<Thing>& others, Thing& t) {
  std::vector<std::string> taken;
  for (const auto& other : others) taken.push_back(other.name);
  t.name = unique_name(f, f.string("name", ""), kind, others.size(), taken);
  t.shape = shape_field(L, f);
  t.colour = f.colour("colour", t.colour);
  t.pose = Pose{f.number("x"), f.number("y"), f.number("theta", 0.0)};
}

// world:object{name=, shape=, colour=, x=, y=, theta=, mass=, friction_force=, friction_torque=,
//              viscosity=, angular_viscosity=, surface_friction=}
int l_world_object(lua_State* L) {
  return lua_protect(L, [L]() {
    WorldBuilder& w = world_self(L, "world:object");
    lua_check_arity(L, "world:object", 1, "1 argument (a table of fields)");
    LuaFields f(L, 2, "world:object",
                {"name", "shape", "colour", "x", "y", "theta", "mass", "friction_force",
                 "friction_torque", "viscosity", "angular_viscosity", "surface_friction"});
    if (w.spec.objects.size() >= kMaxThings) f.fail("too many objects (the limit is 1000)");
    fix_arena(w);
    ObjectSpec o;
    read_thing(L, f, "object", w.spec.objects, o);
    // Each within a range Box2D can hold in single precision (a mass of 1e39 kg is infinite
    // there and aborts it; one of 1e-46 kg is 0 there, which fixes the object in place: found by a
    // probe) and wider than any object Roger could move or stop. The least mass is a link's.
    o.mass = ranged(f, "mass", o.mass, 0.001, 1e4, "kg");
    o.friction_force = ranged(f, "friction_force", o.friction_force, 0.0, 1e6, "N");
    o.friction_torque = ranged(f, "friction_torque", o.friction_torque, 0.0, 1e6, "N m");
    o.viscosity = ranged(f, "viscosity", o.viscosity, 0.0, 1e4, "1/s");
    o.angular_viscosity = ranged(f, "angular_viscosity", o.angular_viscosity, 0.0, 1e4, "1/s");
    o.surface_friction = ranged(f, "surface_friction", o.surface_friction, 0.0, 10.0, "(a Coulomb coefficient)");
    check_free(f, w, "object '" + o.name + "'", o.shape, o.pose, true);
    w.spec.objects.push_back(std::move(o));
    return 0;
  });
}

// world:obstacle{name=, shape=, colour=, x=, y=, theta=}. Obstacles may overlap each other (to
// build compound walls) but not Roger or the objects.
int l_world_obstacle(lua_State* L) {
  return lua_protect(L, [L]() {
    WorldBuilder& w = world_self(L, "world:obstacle");
    lua_check_arity(L, "world:obstacle", 1, "1 argument (a table of fields)");
    LuaFields f(L, 2, "world:obstacle", {"name", "shape", "colour", "x", "y", "theta"});
    if (w.spec.obstacles.size() >= kMaxThings) f.fail("too many obstacles (the limit is 1000)");
    fix_arena(w);
    ObstacleSpec o;
    read_thing(L, f, "obstacle", w.spec.obstacles, o);
    check_free(f, w, "obstacle '" + o.name + "'", o.shape, o.pose, false);
    for (const GoalRegion& g : w.spec.goals) check_goal_centre_free(f, g, o);
    w.spec.obstacles.push_back(std::move(o));
    return 0;
  });
}

// world:goal{name=, x=, y=, radius=, colour=}: a floor region, seen by the planner only.
int l_world_goal(lua_State* L) {
  return lua_protect(L, [L]() {
    WorldBuilder& w = world_self(L, "world:goal");
    lua_check_arity(L, "world:goal", 1, "1 argument (a table of fields)");
    LuaFields f(L, 2, "world:goal", {"name", "x", "y", "radius", "colour"});
    if (w.spec.goals.size() >= kMaxThings) f.fail("too many goals (the limit is 1000)");
    fix_arena(w);
    GoalRegion g;
    std::vector<std::string> taken;
    for (const auto& other : w.spec.goals) taken.push_back(other.name);
    g.name = unique_name(f, f.string("name", ""), "goal", w.spec.goals.size(), taken);
    const double x = f.number("x");  // read in order: a missing x is named before a missing y
    g.center = Vec2(x, f.number("y"));
    g.radius = f.number("radius", g.radius);
    g.colour = f.colour("colour", g.colour);
    const auto& a = w.spec.arena;
    if (!(g.radius > 0.0)) f.fail("field 'radius' must be positive, got " + fmt(g.radius));
    if (g.center.x() <= a.xmin || g.center.x() >= a.xmax || g.center.y() <= a.ymin || g.center.y() >= a.ymax)
      f.fail("goal '" + g.name + "' centre " + point_text(g.center.x(), g.center.y()) +
             " is outside the " + arena_text(a));
    lua_charge(L, w.spec.obstacles.size());
    for (const ObstacleSpec& o : w.spec.obstacles) check_goal_centre_free(f, g, o);
    w.spec.goals.push_back(std::move(g));
    return 0;
  });
}

// world:stimulus{colour=}: the colour the eyes track (default: the first object's colour).
int l_world_stimulus(lua_State* L) {
  WorldBuilder& w = world_self(L, "world:stimulus");
  lua_check_arity(L, "world:stimulus", 1, "1 argument (a table of fields)");
  LuaFields f(L, 2, "world:stimulus", {"colour"});
  if (!f.has("colour")) f.fail("missing required field 'colour'");
  // The eyes track one colour: a second call would replace the first without a word (found by a probe).
  if (w.stimulus_set)
    f.fail("the stimulus is already set, to " + w.spec.stimulus_colour.hex() + ": the eyes track one colour (call "
           "world:stimulus once)");
  w.spec.stimulus_colour = f.colour("colour", w.spec.stimulus_colour);
  w.stimulus_set = true;
  return 0;
}

// tostring(world), for print-debugging.
int l_world_tostring(lua_State* L) {
  const auto& w = *static_cast<WorldBuilder*>(luaL_checkudata(L, 1, kWorldType));
  lua_pushfstring(L, "world (%s, %d objects, %d obstacles, %d goals)", arena_text(w.spec.arena).c_str(),
                  int(w.spec.objects.size()), int(w.spec.obstacles.size()), int(w.spec.goals.size()));
  return 1;
}

// The string keys of the table at `index`, sorted (for the messages naming what a table has).
std::vector<std::string> sorted_names(lua_State* L, int index) {
  std::vector<std::string> names;
  lua_pushnil(L);
  while (lua_next(L, index)) {
    if (lua_type(L, -2) == LUA_TSTRING) names.push_back(lua_tostring(L, -2));
    lua_pop(L, 1);
  }
  std::sort(names.begin(), names.end());
  return names;
}

// The __index of a class's methods table (upvalue 1: what the object is called, "rng"): a name
// it lacks is an error at the reader's line naming the methods, with the nearest. Before, a
// misspelt method read nil and the call failed with "attempt to call a nil value (method ...)".
int l_no_method(lua_State* L) {
  const std::string what = lua_tostring(L, lua_upvalueindex(1));
  const std::string name = luaL_tolstring(L, 2, nullptr);
  const std::vector<std::string> methods = sorted_names(L, 1);
  return raise_at_reader(L, what + " has no method '" + name + "'" + suggestion(name, methods) + "; its methods: " +
                                join(methods));
}

// Registers a userdata metatable with its methods, finalizer and tostring.
void new_class(lua_State* L, const char* type, const luaL_Reg* methods, lua_CFunction gc,
               lua_CFunction tostring) {
  luaL_newmetatable(L, type);
  if (methods) {
    lua_newtable(L);
    luaL_setfuncs(L, methods, 0);
    lua_newtable(L);  // the methods table's own metatable: an unknown name is an error
    std::string what = type;
    what = what.substr(what.find('.') + 1);
    std::transform(what.begin(), what.end(), what.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    lua_pushstring(L, what.c_str());
    lua_pushcclosure(L, l_no_method, 1);
    lua_setfield(L, -2, "__index");
    lua_pushboolean(L, 0);
    lua_setfield(L, -2, "__metatable");
    lua_setmetatable(L, -2);
    lua_setfield(L, -2, "__index");
  }
  if (gc) {
    lua_pushcfunction(L, gc);
    lua_setfield(L, -2, "__gc");
  }
  if (tostring) {
    lua_pushcfunction(L, tostring);
    lua_setfield(L, -2, "__tostring");
  }
  lua_pushboolean(L, 0);
  lua_setfield(L, -2, "__metatable");
  lua_pop(L, 1);
}

// generate's params is a view (lua_new_view): an empty table whose metatable reads and writes
// its data, so that every name read is noted (roger check warns of a declared parameter generate
// never reads, which no --set or teacher could change). To a script it is the table of the values
// in force: reading, writing, pairs, next, #, rawget and rawlen give what they would on that table.
// __index: the value, noted as read. A name the scenario does not declare is an error at the
// reader's line, with the nearest. Before, `p.goal_raduis` read nil, and world:goal{radius = nil}
// quietly took its default, so `--set goal_radius=...` changed nothing. Only names are
// parameters: another key (ipairs reading p[1]) reads nil, as in any table.
int l_param_read(lua_State* L) {
  lua_check_view_data(L, "generate's params");
  const int data = lua_gettop(L);
  lua_pushvalue(L, 2);
  if (lua_rawget(L, data) != LUA_TNIL) {
    lua_view_note_read(L, 1, 2);
    return 1;
  }
  if (lua_type(L, 2) != LUA_TSTRING) return 1;  // nil, as an absent field of a table
  const std::string name = lua_tostring(L, 2);
  const std::vector<std::string> params = sorted_names(L, data);
  return raise_at_reader(L, "the scenario has no parameter '" + name + "'" + suggestion(name, params) +
                                (params.empty() ? std::string("; it declares none") : "; its parameters: " + join(params)));
}

// __newindex: a write goes to the data, where later reads find it.
int l_param_write(lua_State* L) {
  lua_check_view_data(L, "generate's params");
  lua_insert(L, 2);
  lua_rawset(L, 2);
  return 0;
}

// __pairs: the data in the sandbox's order; a loop over them all reads them all.
int l_params_pairs(lua_State* L) {
  lua_check_view_data(L, "generate's params");
  const int data = lua_gettop(L);
  lua_pushnil(L);
  while (lua_next(L, data)) {
    lua_pop(L, 1);
    lua_view_note_read(L, 1, -1);
  }
  return lua_pairs_in_order(L, data);
}

// The __index of roger.body_metrics's result: a misspelt number is an error at the reader's line.
// Found by a probe: `m.footprnt_radius` read nil, world:sample_position took radius 0, and the
// mistake surfaced seeds later as a base sticking out of the arena.
int l_no_metric(lua_State* L) {
  luaL_checktype(L, 1, LUA_TTABLE);  // getmetatable(m).__index(5, "x") reached lua_next on a number
  if (lua_type(L, 2) != LUA_TSTRING) return 0;
  const std::string name = lua_tostring(L, 2);
  const std::vector<std::string> fields = sorted_names(L, 1);
  return raise_at_reader(L, "roger.body_metrics(...) has no number '" + name + "'" + suggestion(name, fields) +
                                "; its numbers: " + join(fields));
}

// The __newindex of a shape: a shape does not change (found by a probe: `sq.name = "x"` said
// "attempt to index a roger.Shape value", as if it could not be read).
int l_shape_newindex(lua_State* L) {
  const std::string key = luaL_tolstring(L, 2, nullptr);
  return raise_at_reader(L, "a shape cannot be changed (its '" + key + "' was set): a shape is fixed once made; make "
                            "another with roger.shape{...}, or a scaled copy with shape:scaled(k)");
}

// The rng object's class.
void new_rng_class(lua_State* L) {
  const luaL_Reg rng_methods[] = {{"uniform", l_rng_uniform}, {"int", l_rng_int},
                                  {"normal", l_rng_normal},   {"angle", l_rng_angle},
                                  {"choice", l_rng_choice},   {"shuffle", l_rng_shuffle},
                                  {"fork", l_rng_fork},       {nullptr, nullptr}};
  new_class(L, kRngType, rng_methods, nullptr, nullptr);
}

}  // namespace

// Installs the metatables and the `roger` table (run protected).
int install_api(lua_State* L) {
  const luaL_Reg world_methods[] = {{"arena", l_world_arena},       {"bounds", l_world_bounds},
                                    {"robot", l_world_robot},       {"object", l_world_object},
                                    {"obstacle", l_world_obstacle}, {"goal", l_world_goal},
                                    {"stimulus", l_world_stimulus}, {"sample_position", l_world_sample},
                                    {nullptr, nullptr}};
  new_class(L, kWorldType, world_methods, destroy<WorldBuilder>, l_world_tostring);
  new_rng_class(L);
  new_class(L, kShapeType, nullptr, destroy<ShapeBox>, l_shape_tostring);
  luaL_newmetatable(L, kParamsType);
  const luaL_Reg params_methods[] = {{"__index", l_param_read}, {"__newindex", l_param_write},
                                     {"__pairs", l_params_pairs}, {"__len", lua_view_len}, {nullptr, nullptr}};
  luaL_setfuncs(L, params_methods, 0);
  // Hidden, as a teacher's history's is: its metamethods are the view (setmetatable(p, nil) would
  // leave an empty table), and called on another table they found no data (found by a probe:
  // getmetatable(p).__index({}, "x") crashed roger).
  lua_pushstring(L, "generate's params");
  lua_setfield(L, -2, "__metatable");
  lua_pop(L, 1);
  luaL_newmetatable(L, kBodyMetricsType);
  lua_pushcfunction(L, l_no_metric);
  lua_setfield(L, -2, "__index");
  lua_pop(L, 1);
  luaL_getmetatable(L, kShapeType);
  lua_pushcfunction(L, l_shape_index);
  lua_setfield(L, -2, "__index");
  lua_pushcfunction(L, l_shape_newindex);
  lua_setfield(L, -2, "__newindex");
  lua_pushcfunction(L, l_shape_scaled);
  lua_setfield(L, -2, "scaled");
  lua_pop(L, 1);

  lua_newtable(L);  // roger
  lua_pushcfunction(L, l_shape);
  lua_setfield(L, -2, "shape");
  lua_pushstring(L, ROGER_VERSION);
  lua_setfield(L, -2, "version");
  const RobotParams p;
  lua_newtable(L);  // roger.robot: Roger's dimensions, for placement arithmetic
  const std::pair<const char*, double> numbers[] = {
      {"base_radius", p.base_radius},   {"hand_radius", p.hand_radius},
      {"upper_arm", p.link_length[0]},  {"forearm", p.link_length[1]},
      {"shoulder_y", p.shoulder_y},     {"eye_y", p.eye_y},
      {"footprint_radius", robot_footprint_radius()}};
  for (const auto& [key, value] : numbers) {
    lua_pushnumber(L, value);
    lua_setfield(L, -2, key);
  }
  lua_make_read_only(L, "roger.robot");
  lua_setfield(L, -2, "robot");
  lua_pushcfunction(L, l_body_metrics);
  lua_setfield(L, -2, "body_metrics");
  lua_setglobal(L, "roger");
  return 0;
}

}  // namespace scenario_detail

bool lua_is_rng_method(lua_State* L, const std::string& name) {
  LuaStackGuard guard(L);
  if (luaL_getmetatable(L, scenario_detail::kRngType) != LUA_TTABLE) return false;
  if (lua_getfield(L, -1, "__index") != LUA_TTABLE) return false;
  lua_pushstring(L, name.c_str());
  return lua_rawget(L, -2) != LUA_TNIL;
}

int64_t lua_push_rng(lua_State* L, uint64_t seed) {
  if (luaL_getmetatable(L, scenario_detail::kRngType) == LUA_TNIL) scenario_detail::new_rng_class(L);
  lua_pop(L, 1);
  // A teacher function's: an epoch of its own, negative (live_rng's message tells them apart),
  // live during each of its calls (found by a probe: a teacher's rng kept in a global and drawn by
  // the absorbing function changed every verdict, and roger eval could not give the trial's).
  const lua_Integer epoch = -scenario_detail::open_rng_epoch(L);
  scenario_detail::close_rng_epoch(L);
  scenario_detail::push_rng(L, seed, epoch);
  return epoch;
}

void lua_rng_calls_begin(lua_State* L, int64_t key) { scenario_detail::set_live_rng_epoch(L, key); }

void lua_rng_calls_end(lua_State* L) { scenario_detail::close_rng_epoch(L); }

}  // namespace roger
