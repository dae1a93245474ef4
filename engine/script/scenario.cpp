#include "script/scenario.h"

#include <algorithm>
#include <cerrno>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <tuple>

#include <lua.hpp>

#include "core/error.h"
#include "core/rng.h"
#include "core/robot.h"
#include "core/shape.h"
#include "sim/world.h"

namespace roger {
namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Geometry of placed shapes.

namespace {

// One convex part of a shape in the world frame (polygons counter-clockwise, as validated).
struct Part {
  bool disk = true;
  Vec2 c = Vec2::Zero();
  double r = 0.0;
  std::vector<Vec2> v;
};

// The shape's parts moved to its pose.
std::vector<Part> placed_parts(const Shape& shape, const Pose& pose) {
  std::vector<Part> parts;
  for (const auto& d : shape.disks) parts.push_back(Part{true, to_world(pose, d.center), d.radius, {}});
  for (const auto& poly : shape.polygons) {
    Part p;
    p.disk = false;
    for (const auto& v : poly.vertices) p.v.push_back(to_world(pose, v));
    parts.push_back(std::move(p));
  }
  return parts;
}

// Distance from p to the segment ab.
double segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 e = b - a;
  const double t = std::clamp((p - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
  return (a + t * e - p).norm();
}

// Signed distance from a point to a convex counter-clockwise polygon (negative inside).
double polygon_signed_distance(const std::vector<Vec2>& v, const Vec2& p) {
  double outside = -std::numeric_limits<double>::infinity();
  double edge = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < v.size(); ++i) {
    const Vec2& a = v[i];
    const Vec2& b = v[(i + 1) % v.size()];
    const Vec2 e = b - a;
    outside = std::max(outside, Vec2(e.y(), -e.x()).dot(p - a) / e.norm());
    edge = std::min(edge, segment_distance(p, a, b));
  }
  return outside <= 0.0 ? outside : edge;
}

// Separating-axis gap of two convex polygons: positive distance when apart (vertex-edge minimum,
// exact for convex polygons), minus the penetration depth when they overlap.
double polygon_gap(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  double best = -std::numeric_limits<double>::infinity();
  for (const auto* poly : {&a, &b}) {
    for (size_t i = 0; i < poly->size(); ++i) {
      const Vec2 e = (*poly)[(i + 1) % poly->size()] - (*poly)[i];
      const Vec2 n = Vec2(e.y(), -e.x()).normalized();
      double amin = INFINITY, amax = -INFINITY, bmin = INFINITY, bmax = -INFINITY;
      for (const auto& p : a) amin = std::min(amin, n.dot(p)), amax = std::max(amax, n.dot(p));
      for (const auto& p : b) bmin = std::min(bmin, n.dot(p)), bmax = std::max(bmax, n.dot(p));
      best = std::max(best, std::max(bmin - amax, amin - bmax));
    }
  }
  if (best <= 0.0) return best;
  double d = INFINITY;
  for (size_t i = 0; i < b.size(); ++i)
    for (const auto& p : a) d = std::min(d, segment_distance(p, b[i], b[(i + 1) % b.size()]));
  for (size_t i = 0; i < a.size(); ++i)
    for (const auto& p : b) d = std::min(d, segment_distance(p, a[i], a[(i + 1) % a.size()]));
  return d;
}

// Gap between two convex parts (negative: penetration depth).
double part_gap(const Part& a, const Part& b) {
  if (a.disk && b.disk) return (a.c - b.c).norm() - a.r - b.r;
  if (a.disk) return polygon_signed_distance(b.v, a.c) - a.r;
  if (b.disk) return polygon_signed_distance(a.v, b.c) - b.r;
  return polygon_gap(a.v, b.v);
}

// How far inside the arena walls the shape stays (negative: by how much it sticks out).
double arena_inset(const ArenaSpec& arena, const Shape& shape, const Pose& pose) {
  double inset = INFINITY;
  auto within = [&](const Vec2& p, double r) {
    inset = std::min({inset, p.x() - r - arena.xmin, arena.xmax - p.x() - r, p.y() - r - arena.ymin,
                      arena.ymax - p.y() - r});
  };
  for (const auto& part : placed_parts(shape, pose)) {
    if (part.disk) within(part.c, part.r);
    for (const auto& v : part.v) within(v, 0.0);
  }
  return inset;
}

// A one-disk shape, for Roger's base and hands and goal regions.
Shape disk_shape(const std::string& name, const Vec2& c, double r) {
  Shape s;
  s.name = name;
  s.disks.push_back(Disk{c, r});
  return s;
}

}  // namespace

double shape_gap(const Shape& a, const Pose& pa, const Shape& b, const Pose& pb) {
  double gap = INFINITY;
  const auto pb_parts = placed_parts(b, pb);
  for (const auto& p : placed_parts(a, pa))
    for (const auto& q : pb_parts) gap = std::min(gap, part_gap(p, q));
  return gap;
}

std::vector<Disk> robot_footprint(const RobotStart& start) {
  const RobotParams robot;
  std::vector<Disk> disks{Disk{Vec2(start.pose.x, start.pose.y), robot.base_radius}};
  disks.push_back(Disk{arm_forward_kinematics(robot, start.pose, kLeft, start.left_shoulder,
                                              start.left_elbow).hand,
                       robot.hand_radius});
  disks.push_back(Disk{arm_forward_kinematics(robot, start.pose, kRight, start.right_shoulder,
                                              start.right_elbow).hand,
                       robot.hand_radius});
  return disks;
}

double robot_footprint_radius() {
  double r = 0.0;
  for (const auto& d : robot_footprint(RobotStart{})) r = std::max(r, d.center.norm() + d.radius);
  return r;
}

// ---------------------------------------------------------------------------------------------
// The Lua API: shapes, the rng and the world builder.

namespace {

constexpr const char* kShapeType = "roger.Shape";
constexpr const char* kRngType = "roger.Rng";
constexpr const char* kWorldType = "roger.World";
constexpr size_t kMaxThings = 1000;   // objects, obstacles or goals in one world
constexpr size_t kMaxParts = 64;      // polygons plus disks in one shape

// Joins items with a separator.
// A number for messages, with rounding noise near zero shown as 0.
std::string fmt(double v) { return format_number(std::abs(v) < 5e-13 ? 0.0 : v); }

// "(x, y)" for messages.
std::string point_text(double x, double y) { return "(" + fmt(x) + ", " + fmt(y) + ")"; }

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
};

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
    luaL_error(L, "%s: call it with a colon, as %s(...) (the first argument is a %s, not the %s)",
               call, call, luaL_typename(L, 1), object.c_str());
  }
  return *static_cast<T*>(p);
}

// The world a method is called on, refusing a world whose generate call is over.
WorldBuilder& world_self(lua_State* L, const char* call) {
  WorldBuilder& w = self<WorldBuilder>(L, kWorldType, call);
  if (w.finished)
    luaL_error(L, "%s: this world is finished (world methods work only while generate runs)", call);
  return w;
}

// Validates a shape and pushes it as an immutable shape value.
ShapeBox& push_shape(lua_State* L, Shape shape, const char* context) {
  try {
    validate_shape(shape);  // names the shape, the part and the problem
  } catch (const Error& e) {
    throw Error(std::string(context) + ": " + e.what());
  }
  auto* box = static_cast<ShapeBox*>(lua_newuserdatauv(L, sizeof(ShapeBox), 0));
  new (box) ShapeBox{std::move(shape), 0.0, 0.0};
  luaL_setmetatable(L, kShapeType);
  box->radius = shape_bounding_radius(box->shape);
  box->area = shape_area(box->shape);
  return *box;
}

// Reads a vertex {x, y} or {x=, y=}.
Vec2 read_vertex(lua_State* L, int index, const std::string& where) {
  if (!lua_istable(L, index)) luaL_error(L, "%s must be {x, y}, got %s", where.c_str(), luaL_typename(L, index));
  const bool named = lua_getfield(L, index, "x") != LUA_TNIL;
  lua_pop(L, 1);
  double xy[2];
  for (int k = 0; k < 2; ++k) {
    const int type = named ? lua_getfield(L, index, k ? "y" : "x") : lua_rawgeti(L, index, k + 1);
    if (type != LUA_TNUMBER) luaL_error(L, "%s must be {x, y} with two numbers", where.c_str());
    xy[k] = lua_tonumber(L, -1);
    lua_pop(L, 1);
  }
  return Vec2(xy[0], xy[1]);
}

// roger.shape{name=, polygons={{{x,y},...},...}, disks={{x=,y=,r=},...}}
int l_shape(lua_State* L) {
  return lua_protect(L, [L]() {
    LuaFields f(L, 1, "roger.shape", {"name", "polygons", "disks"});
    Shape shape;
    shape.name = f.string("name", "unnamed");
    const std::string ctx = "roger.shape: shape '" + shape.name + "'";
    if (f.push("polygons") != LUA_TNIL) {
      if (!lua_istable(L, -1)) f.wrong_type("polygons", "a list of polygons, each a list of {x, y}");
      const lua_Integer n = lua_Integer(lua_rawlen(L, -1));
      if (size_t(n) > kMaxParts) f.fail("more than " + std::to_string(kMaxParts) + " polygons");
      for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L, -1, i);
        const std::string where = ctx + " polygon " + std::to_string(i);
        if (!lua_istable(L, -1)) luaL_error(L, "%s must be a list of {x, y} vertices, got %s", where.c_str(), luaL_typename(L, -1));
        Polygon poly;
        const lua_Integer m = lua_Integer(lua_rawlen(L, -1));
        if (m > kMaxPolygonVertices)
          luaL_error(L, "%s: expected 3 to %d vertices, got %d", where.c_str(), kMaxPolygonVertices, int(m));
        for (lua_Integer j = 1; j <= m; ++j) {
          lua_rawgeti(L, -1, j);
          poly.vertices.push_back(read_vertex(L, -1, where + " vertex " + std::to_string(j)));
          lua_pop(L, 1);
        }
        shape.polygons.push_back(std::move(poly));
        lua_pop(L, 1);
      }
    }
    lua_pop(L, 1);
    if (f.push("disks") != LUA_TNIL) {
      if (!lua_istable(L, -1)) f.wrong_type("disks", "a list of disks {x=, y=, r=}");
      const lua_Integer n = lua_Integer(lua_rawlen(L, -1));
      if (size_t(n) + shape.polygons.size() > kMaxParts) f.fail("more than " + std::to_string(kMaxParts) + " parts");
      for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L, -1, i);
        LuaFields d(L, -1, ctx + " disk " + std::to_string(i), {"x", "y", "r"});
        shape.disks.push_back(Disk{Vec2(d.number("x", 0.0), d.number("y", 0.0)), d.number("r")});
        lua_pop(L, 1);
      }
    }
    lua_pop(L, 1);
    push_shape(L, std::move(shape), "roger.shape");
    return 1;
  });
}

// shape.name, .radius, .area, .polygons, .disks and :scaled.
int l_shape_index(lua_State* L) {
  const auto& box = *static_cast<ShapeBox*>(luaL_checkudata(L, 1, kShapeType));
  const std::string key = lua_type(L, 2) == LUA_TSTRING ? lua_tostring(L, 2) : "";
  if (key == "name") {
    lua_pushstring(L, box.shape.name.c_str());
  } else if (key == "radius") {
    lua_pushnumber(L, box.radius);
  } else if (key == "area") {
    lua_pushnumber(L, box.area);
  } else if (key == "polygons") {
    lua_createtable(L, int(box.shape.polygons.size()), 0);
    for (size_t i = 0; i < box.shape.polygons.size(); ++i) {
      const auto& vs = box.shape.polygons[i].vertices;
      lua_createtable(L, int(vs.size()), 0);
      for (size_t j = 0; j < vs.size(); ++j) {
        lua_createtable(L, 2, 0);
        lua_pushnumber(L, vs[j].x());
        lua_rawseti(L, -2, 1);
        lua_pushnumber(L, vs[j].y());
        lua_rawseti(L, -2, 2);
        lua_rawseti(L, -2, lua_Integer(j + 1));
      }
      lua_rawseti(L, -2, lua_Integer(i + 1));
    }
  } else if (key == "disks") {
    lua_createtable(L, int(box.shape.disks.size()), 0);
    for (size_t i = 0; i < box.shape.disks.size(); ++i) {
      const auto& d = box.shape.disks[i];
      lua_createtable(L, 0, 3);
      lua_pushnumber(L, d.center.x());
      lua_setfield(L, -2, "x");
      lua_pushnumber(L, d.center.y());
      lua_setfield(L, -2, "y");
      lua_pushnumber(L, d.radius);
      lua_setfield(L, -2, "r");
      lua_rawseti(L, -2, lua_Integer(i + 1));
    }
  } else if (key == "scaled") {
    lua_getmetatable(L, 1);
    lua_getfield(L, -1, "scaled");
  } else {
    return luaL_error(L, "a shape has no field '%s'; it has name, radius, area, polygons, disks "
                      "and the method scaled(factor [, name])", key.c_str());
  }
  return 1;
}

// shape:scaled(factor [, name]): a uniformly scaled copy.
int l_shape_scaled(lua_State* L) {
  return lua_protect(L, [L]() {
    const ShapeBox& box = self<ShapeBox>(L, kShapeType, "shape:scaled");
    const double k = lua_tonumber(L, 2);
    if (lua_type(L, 2) != LUA_TNUMBER || !(k > 0.0) || !std::isfinite(k))
      luaL_error(L, "shape:scaled: the factor must be a positive number");
    Shape s = box.shape;
    if (lua_type(L, 3) == LUA_TSTRING) s.name = lua_tostring(L, 3);
    for (auto& p : s.polygons)
      for (auto& v : p.vertices) v *= k;
    for (auto& d : s.disks) d.center *= k, d.radius *= k;
    push_shape(L, std::move(s), "shape:scaled");
    return 1;
  });
}

// tostring(shape), for print-debugging.
int l_shape_tostring(lua_State* L) {
  const auto& box = *static_cast<ShapeBox*>(luaL_checkudata(L, 1, kShapeType));
  lua_pushfstring(L, "shape '%s' (%d polygons, %d disks, radius %s m)", box.shape.name.c_str(),
                  int(box.shape.polygons.size()), int(box.shape.disks.size()),
                  fmt(box.radius).c_str());
  return 1;
}

// ---- rng ----

// Pushes a new rng value seeded with `seed`.
Rng& push_rng(lua_State* L, uint64_t seed) {
  auto* rng = static_cast<Rng*>(lua_newuserdatauv(L, sizeof(Rng), 0));
  new (rng) Rng(seed);
  luaL_setmetatable(L, kRngType);
  return *rng;
}

// A finite number argument, or an error naming the call and the argument.
double arg_number(lua_State* L, int index, const char* call, const char* name) {
  if (lua_type(L, index) != LUA_TNUMBER)
    luaL_error(L, "%s: argument '%s' must be a number, got %s", call, name, luaL_typename(L, index));
  const double v = lua_tonumber(L, index);
  if (!std::isfinite(v)) luaL_error(L, "%s: argument '%s' must be finite", call, name);
  return v;
}

// An integer argument, or an error naming the call and the argument.
lua_Integer arg_integer(lua_State* L, int index, const char* call, const char* name) {
  int ok = 0;
  const lua_Integer v = lua_tointegerx(L, index, &ok);
  if (!ok || lua_type(L, index) != LUA_TNUMBER)
    luaL_error(L, "%s: argument '%s' must be an integer, got %s", call, name,
               lua_type(L, index) == LUA_TNUMBER ? fmt(lua_tonumber(L, index)).c_str()
                                                 : luaL_typename(L, index));
  return v;
}

// rng:uniform() in [0, 1), rng:uniform(a, b) in [a, b).
int l_rng_uniform(lua_State* L) {
  Rng& rng = self<Rng>(L, kRngType, "rng:uniform");
  if (lua_gettop(L) == 1) {
    lua_pushnumber(L, rng.uniform());
    return 1;
  }
  const double a = arg_number(L, 2, "rng:uniform", "a"), b = arg_number(L, 3, "rng:uniform", "b");
  if (a > b) return luaL_error(L, "rng:uniform: a (%s) must not exceed b (%s)", fmt(a).c_str(), fmt(b).c_str());
  lua_pushnumber(L, rng.uniform(a, b));
  return 1;
}

// rng:int(n) in 1..n, rng:int(a, b) in a..b (inclusive).
int l_rng_int(lua_State* L) {
  Rng& rng = self<Rng>(L, kRngType, "rng:int");
  lua_Integer a = 1, b;
  if (lua_gettop(L) <= 2) {
    b = arg_integer(L, 2, "rng:int", "n");
  } else {
    a = arg_integer(L, 2, "rng:int", "a");
    b = arg_integer(L, 3, "rng:int", "b");
  }
  if (a > b) return luaL_error(L, "rng:int: the range %I..%I is empty", a, b);
  lua_pushinteger(L, rng.integer(a, b));
  return 1;
}

// rng:normal([mu [, sigma]]).
int l_rng_normal(lua_State* L) {
  Rng& rng = self<Rng>(L, kRngType, "rng:normal");
  const double mu = lua_isnoneornil(L, 2) ? 0.0 : arg_number(L, 2, "rng:normal", "mu");
  const double sigma = lua_isnoneornil(L, 3) ? 1.0 : arg_number(L, 3, "rng:normal", "sigma");
  if (sigma < 0.0) return luaL_error(L, "rng:normal: sigma must not be negative");
  lua_pushnumber(L, rng.normal(mu, sigma));
  return 1;
}

// rng:angle(): uniform in [-pi, pi).
int l_rng_angle(lua_State* L) {
  Rng& rng = self<Rng>(L, kRngType, "rng:angle");
  lua_pushnumber(L, rng.uniform(-M_PI, M_PI));
  return 1;
}

// rng:choice(list): one element, uniformly.
int l_rng_choice(lua_State* L) {
  Rng& rng = self<Rng>(L, kRngType, "rng:choice");
  if (!lua_istable(L, 2)) return luaL_error(L, "rng:choice: expects a list, got %s", luaL_typename(L, 2));
  const lua_Integer n = lua_Integer(lua_rawlen(L, 2));
  if (n == 0) return luaL_error(L, "rng:choice: the list is empty");
  lua_rawgeti(L, 2, rng.integer(1, n));
  return 1;
}

// rng:shuffle(list): shuffles in place (Fisher-Yates) and returns the list.
int l_rng_shuffle(lua_State* L) {
  Rng& rng = self<Rng>(L, kRngType, "rng:shuffle");
  if (!lua_istable(L, 2)) return luaL_error(L, "rng:shuffle: expects a list, got %s", luaL_typename(L, 2));
  for (lua_Integer i = lua_Integer(lua_rawlen(L, 2)); i > 1; --i) {
    const lua_Integer j = rng.integer(1, i);
    lua_rawgeti(L, 2, i);
    lua_rawgeti(L, 2, j);
    lua_rawseti(L, 2, i);
    lua_rawseti(L, 2, j);
  }
  lua_settop(L, 2);
  return 1;
}

// rng:fork(): an independent generator seeded from this one (for streams that must not shift
// when another part of the script draws more or fewer numbers).
int l_rng_fork(lua_State* L) {
  Rng& rng = self<Rng>(L, kRngType, "rng:fork");
  push_rng(L, rng.next());
  return 1;
}

// ---- world ----

// "4 x 4 m arena", for messages.
std::string arena_text(const ArenaSpec& a) {
  return fmt(a.xmax - a.xmin) + " x " + fmt(a.ymax - a.ymin) + " m arena";
}

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
Occupants occupants(const WorldBuilder& w, bool objects, bool obstacles) {
  Occupants out;
  if (w.robot_set) {
    const char* names[3] = {"Roger's base", "Roger's left hand", "Roger's right hand"};
    const auto disks = robot_footprint(w.spec.robot);
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

// Raises an error if the shape sticks out of the arena or overlaps an occupant.
void check_free(const LuaFields& f, const WorldBuilder& w, const std::string& what, const Shape& shape,
                const Pose& pose, bool against_obstacles) {
  const double inset = arena_inset(w.spec.arena, shape, pose);
  const std::string at = what + " at " + point_text(pose.x, pose.y);
  if (inset < -1e-9) {
    const auto& a = w.spec.arena;
    f.fail(at + " sticks out of the arena [" + fmt(a.xmin) + ", " + fmt(a.xmax) + "] x [" +
           fmt(a.ymin) + ", " + fmt(a.ymax) + "] by " + fmt(-inset) + " m");
  }
  const Occupants occ = occupants(w, true, against_obstacles);
  lua_charge(f.state(), occ.list.size() * (shape.polygons.size() + shape.disks.size()));
  for (const auto& o : occ.list) {
    const double gap = shape_gap(shape, pose, *o.shape, o.pose);
    if (gap < -1e-9) f.fail(at + " overlaps " + o.what + " by " + fmt(-gap) + " m");
  }
}

// Once something depends on the arena, world:arena may no longer change it.
void fix_arena(WorldBuilder& w) { w.arena_fixed = true; }

// The shape value at index, or null.
ShapeBox* test_shape(lua_State* L, int index) {
  return static_cast<ShapeBox*>(luaL_testudata(L, index, kShapeType));
}

// The given name, or "<kind> N"; refuses a name already used by a thing of the same kind.
std::string unique_name(const LuaFields& f, const std::string& given, const char* kind, size_t count,
                        const std::vector<std::string>& taken) {
  const std::string name = given.empty() ? std::string(kind) + " " + std::to_string(count + 1) : given;
  if (std::find(taken.begin(), taken.end(), name) != taken.end())
    f.fail("there is already a " + std::string(kind) + " named '" + name + "'");
  return name;
}

// world:arena{xmin=, xmax=, ymin=, ymax=, cell=, wall_colour=}
int l_world_arena(lua_State* L) {
  return lua_protect(L, [L]() {
    WorldBuilder& w = world_self(L, "world:arena");
    LuaFields f(L, 2, "world:arena", {"xmin", "xmax", "ymin", "ymax", "cell", "wall_colour"});
    if (w.arena_set) f.fail("the arena is already set (call world:arena once)");
    if (w.arena_fixed)
      f.fail("call world:arena first, before anything is placed or sampled (the default arena is "
             "already in use)");
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
  fix_arena(w);
  const auto& a = w.spec.arena;
  for (double v : {a.xmin, a.xmax, a.ymin, a.ymax}) lua_pushnumber(L, v);
  return 4;
}

// world:robot{x=, y=, heading=, left_shoulder=, left_elbow=, right_shoulder=, right_elbow=,
//             left_eye=, right_eye=}
int l_world_robot(lua_State* L) {
  return lua_protect(L, [L]() {
    WorldBuilder& w = world_self(L, "world:robot");
    LuaFields f(L, 2, "world:robot",
                {"x", "y", "heading", "left_shoulder", "left_elbow", "right_shoulder", "right_elbow",
                 "left_eye", "right_eye"});
    if (w.robot_set) f.fail("Roger is already placed (call world:robot once)");
    fix_arena(w);
    RobotStart r;
    r.pose = Pose{f.number("x"), f.number("y"), f.number("heading", 0.0)};
    const RobotParams p;
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
    const auto disks = robot_footprint(r);
    for (size_t i = 0; i < disks.size(); ++i)
      check_free(f, w, names[i], disk_shape(names[i], Vec2::Zero(), disks[i].radius),
                 Pose{disks[i].center.x(), disks[i].center.y(), 0.0}, true);
    w.spec.robot = r;
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

// world:object{name=, shape=, colour=, x=, y=, theta=, mass=, friction_force=, friction_torque=,
//              viscosity=, angular_viscosity=, surface_friction=}
int l_world_object(lua_State* L) {
  return lua_protect(L, [L]() {
    WorldBuilder& w = world_self(L, "world:object");
    LuaFields f(L, 2, "world:object",
                {"name", "shape", "colour", "x", "y", "theta", "mass", "friction_force",
                 "friction_torque", "viscosity", "angular_viscosity", "surface_friction"});
    if (w.spec.objects.size() >= kMaxThings) f.fail("too many objects (the limit is 1000)");
    fix_arena(w);
    ObjectSpec o;
    std::vector<std::string> taken;
    for (const auto& other : w.spec.objects) taken.push_back(other.name);
    o.name = unique_name(f, f.string("name", ""), "object", w.spec.objects.size(), taken);
    o.shape = shape_field(L, f);
    o.colour = f.colour("colour", o.colour);
    o.pose = Pose{f.number("x"), f.number("y"), f.number("theta", 0.0)};
    auto positive = [&](const char* key, double fallback, bool allow_zero) {
      const double v = f.number(key, fallback);
      if (v < 0.0 || (!allow_zero && v == 0.0))
        f.fail(std::string("field '") + key + "' must be " + (allow_zero ? "zero or more" : "positive") +
               ", got " + fmt(v));
      return v;
    };
    o.mass = positive("mass", o.mass, false);
    o.friction_force = positive("friction_force", o.friction_force, true);
    o.friction_torque = positive("friction_torque", o.friction_torque, true);
    o.viscosity = positive("viscosity", o.viscosity, true);
    o.angular_viscosity = positive("angular_viscosity", o.angular_viscosity, true);
    o.surface_friction = positive("surface_friction", o.surface_friction, true);
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
    LuaFields f(L, 2, "world:obstacle", {"name", "shape", "colour", "x", "y", "theta"});
    if (w.spec.obstacles.size() >= kMaxThings) f.fail("too many obstacles (the limit is 1000)");
    fix_arena(w);
    ObstacleSpec o;
    std::vector<std::string> taken;
    for (const auto& other : w.spec.obstacles) taken.push_back(other.name);
    o.name = unique_name(f, f.string("name", ""), "obstacle", w.spec.obstacles.size(), taken);
    o.shape = shape_field(L, f);
    o.colour = f.colour("colour", o.colour);
    o.pose = Pose{f.number("x"), f.number("y"), f.number("theta", 0.0)};
    check_free(f, w, "obstacle '" + o.name + "'", o.shape, o.pose, false);
    w.spec.obstacles.push_back(std::move(o));
    return 0;
  });
}

// world:goal{name=, x=, y=, radius=, colour=}: a floor region, seen by the planner only.
int l_world_goal(lua_State* L) {
  return lua_protect(L, [L]() {
    WorldBuilder& w = world_self(L, "world:goal");
    LuaFields f(L, 2, "world:goal", {"name", "x", "y", "radius", "colour"});
    if (w.spec.goals.size() >= kMaxThings) f.fail("too many goals (the limit is 1000)");
    fix_arena(w);
    GoalRegion g;
    std::vector<std::string> taken;
    for (const auto& other : w.spec.goals) taken.push_back(other.name);
    g.name = unique_name(f, f.string("name", ""), "goal", w.spec.goals.size(), taken);
    g.center = Vec2(f.number("x"), f.number("y"));
    g.radius = f.number("radius", g.radius);
    g.colour = f.colour("colour", g.colour);
    const auto& a = w.spec.arena;
    if (!(g.radius > 0.0)) f.fail("field 'radius' must be positive, got " + fmt(g.radius));
    if (g.center.x() <= a.xmin || g.center.x() >= a.xmax || g.center.y() <= a.ymin || g.center.y() >= a.ymax)
      f.fail("goal '" + g.name + "' centre " + point_text(g.center.x(), g.center.y()) +
             " is outside the " + arena_text(a));
    w.spec.goals.push_back(std::move(g));
    return 0;
  });
}

// world:stimulus{colour=}: the colour the eyes track (default: the first object's colour).
int l_world_stimulus(lua_State* L) {
  WorldBuilder& w = world_self(L, "world:stimulus");
  LuaFields f(L, 2, "world:stimulus", {"colour"});
  if (!f.has("colour")) f.fail("missing required field 'colour'");
  w.spec.stimulus_colour = f.colour("colour", w.spec.stimulus_colour);
  w.stimulus_set = true;
  return 0;
}

// world:sample_position{name=, radius= | shape=, wall_margin=, clearance=, robot_distance=,
//                       away_from={{x=, y=, distance=, name=}, ...}, avoid_goals=,
//                       region={xmin=, xmax=, ymin=, ymax=}, tries=}
// Rejection sampling of a free disk centre, drawing from the generator's rng. Returns x, y.
int l_world_sample(lua_State* L) {
  return lua_protect(L, [L]() {
    WorldBuilder& w = world_self(L, "world:sample_position");
    LuaFields f(L, 2, "world:sample_position",
                {"name", "radius", "shape", "wall_margin", "clearance", "robot_distance",
                 "away_from", "avoid_goals", "region", "tries"});
    fix_arena(w);
    const std::string name = f.string("name", "position");
    double radius = 0.0;
    if (f.has("shape")) {
      if (f.has("radius")) f.fail("give either 'radius' or 'shape', not both");
      f.push("shape");
      const ShapeBox* box = test_shape(L, -1);
      lua_pop(L, 1);
      if (!box) f.wrong_type("shape", "a shape made by roger.shape{...}");
      radius = box->radius;
    } else {
      radius = f.number("radius", 0.0);
    }
    if (radius < 0.0) f.fail("field 'radius' must not be negative");
    const double clearance = f.number("clearance", 0.05);
    if (clearance < 0.0) f.fail("field 'clearance' must not be negative");
    const double margin = std::max(f.number("wall_margin", radius + clearance), radius);
    const double robot_distance = f.number("robot_distance", 0.0);
    const bool avoid_goals = f.boolean("avoid_goals", true);
    const int64_t tries = f.integer("tries", 1000);
    if (tries < 1 || tries > 1'000'000) f.fail("field 'tries' must be 1 to 1000000");

    struct Away {
      Vec2 p;
      double distance;
      std::string name;
    };
    std::vector<Away> away;
    if (f.push("away_from") != LUA_TNIL) {
      if (!lua_istable(L, -1)) f.wrong_type("away_from", "a list of {x=, y=, distance=, name=}");
      const lua_Integer n = lua_Integer(lua_rawlen(L, -1));
      for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L, -1, i);
        LuaFields a(L, -1, "world:sample_position: away_from[" + std::to_string(i) + "]",
                    {"x", "y", "distance", "name"});
        Away item{Vec2(a.number("x"), a.number("y")), a.number("distance"), ""};
        item.name = a.string("name", point_text(item.p.x(), item.p.y()));
        away.push_back(std::move(item));
        lua_pop(L, 1);
      }
    }
    lua_pop(L, 1);

    const ArenaSpec& a = w.spec.arena;
    // The rectangle the centre may be in: the arena shrunk by the margin, within the region.
    double x0 = a.xmin + margin, x1 = a.xmax - margin, y0 = a.ymin + margin, y1 = a.ymax - margin;
    std::string region_text;
    if (f.push("region") != LUA_TNIL) {
      LuaFields r(L, -1, "world:sample_position: region", {"xmin", "xmax", "ymin", "ymax"});
      const double rx0 = r.number("xmin", a.xmin), rx1 = r.number("xmax", a.xmax);
      const double ry0 = r.number("ymin", a.ymin), ry1 = r.number("ymax", a.ymax);
      x0 = std::max(x0, rx0), x1 = std::min(x1, rx1), y0 = std::max(y0, ry0), y1 = std::min(y1, ry1);
      region_text = " within the region [" + fmt(rx0) + ", " + fmt(rx1) + "] x [" + fmt(ry0) + ", " +
                    fmt(ry1) + "]";
    }
    lua_pop(L, 1);
    const std::string label = "no placement for '" + name + "'";
    if (x0 > x1 || y0 > y1)
      f.fail(label + ": it needs " + fmt(margin) + " m from the walls" + region_text +
             ", which leaves no room in a " + arena_text(a));

    // The constraints, each with the number of candidates it rejected.
    struct Constraint {
      std::string text;
      int64_t rejected = 0;
    };
    std::vector<Constraint> constraints;
    constraints.push_back({fmt(margin) + " m from the walls" + region_text});
    const Occupants occ = occupants(w, true, true);
    const size_t robot_parts = w.robot_set ? 3 : 0;
    const size_t c_robot = constraints.size();
    if (w.robot_set)
      constraints.push_back({fmt(clearance) + " m clearance from Roger's base and hands"});
    const size_t c_robot_distance = constraints.size();
    if (w.robot_set && robot_distance > 0.0)
      constraints.push_back({fmt(robot_distance) + " m from Roger"});
    const size_t c_objects = constraints.size();
    constraints.push_back({fmt(clearance) + " m clearance from the objects"});
    const size_t c_obstacles = constraints.size();
    constraints.push_back({fmt(clearance) + " m clearance from the obstacles"});
    const size_t c_goals = constraints.size();
    constraints.push_back({fmt(clearance) + " m clearance from the goal regions"});
    const size_t c_away = constraints.size();
    for (const auto& item : away) constraints.push_back({fmt(item.distance) + " m from " + item.name});

    const Vec2 base(w.spec.robot.pose.x, w.spec.robot.pose.y);
    for (int64_t t = 0; t < tries; ++t) {
      lua_charge(L, 1 + occ.list.size() + w.spec.goals.size() + away.size());
      const Vec2 p(w.rng->uniform(x0, x1), w.rng->uniform(y0, y1));
      bool ok = true;
      auto reject = [&](size_t c) { ++constraints[c].rejected, ok = false; };
      for (size_t i = 0; i < occ.list.size(); ++i) {
        const auto& o = occ.list[i];
        if (shape_signed_distance(*o.shape, o.pose, p) - radius < clearance) {
          const bool is_robot = i < robot_parts;
          const bool is_object = !is_robot && i < robot_parts + w.spec.objects.size();
          reject(is_robot ? c_robot : is_object ? c_objects : c_obstacles);
        }
      }
      if (w.robot_set && robot_distance > 0.0 && (p - base).norm() < robot_distance) reject(c_robot_distance);
      if (avoid_goals)
        for (const auto& g : w.spec.goals)
          if ((p - g.center).norm() - g.radius - radius < clearance) reject(c_goals);
      for (size_t i = 0; i < away.size(); ++i)
        if ((p - away[i].p).norm() < away[i].distance) reject(c_away + i);
      if (ok) {
        lua_pushnumber(L, p.x());
        lua_pushnumber(L, p.y());
        return 2;
      }
    }
    std::vector<std::string> parts;
    for (const auto& c : constraints) {
      if (c.rejected > 0)
        parts.push_back(c.text + " (failed in " + std::to_string(c.rejected) + " tries)");
      else if (&c == &constraints.front() || c.text.find("clearance") == std::string::npos)
        parts.push_back(c.text);
    }
    f.fail(label + " after " + std::to_string(tries) + " tries: it needs " + join(parts) + " in a " +
           arena_text(a));
  });
}

// tostring(world), for print-debugging.
int l_world_tostring(lua_State* L) {
  const auto& w = *static_cast<WorldBuilder*>(luaL_checkudata(L, 1, kWorldType));
  lua_pushfstring(L, "world (%s, %d objects, %d obstacles, %d goals)", arena_text(w.spec.arena).c_str(),
                  int(w.spec.objects.size()), int(w.spec.obstacles.size()), int(w.spec.goals.size()));
  return 1;
}

// Registers a userdata metatable with its methods, finalizer and tostring.
void new_class(lua_State* L, const char* type, const luaL_Reg* methods, lua_CFunction gc,
               lua_CFunction tostring) {
  luaL_newmetatable(L, type);
  if (methods) {
    lua_newtable(L);
    luaL_setfuncs(L, methods, 0);
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

// Installs the metatables and the `roger` table (run protected).
int install_api(lua_State* L) {
  const luaL_Reg world_methods[] = {{"arena", l_world_arena},       {"bounds", l_world_bounds},
                                    {"robot", l_world_robot},       {"object", l_world_object},
                                    {"obstacle", l_world_obstacle}, {"goal", l_world_goal},
                                    {"stimulus", l_world_stimulus}, {"sample_position", l_world_sample},
                                    {nullptr, nullptr}};
  const luaL_Reg rng_methods[] = {{"uniform", l_rng_uniform}, {"int", l_rng_int},
                                  {"normal", l_rng_normal},   {"angle", l_rng_angle},
                                  {"choice", l_rng_choice},   {"shuffle", l_rng_shuffle},
                                  {"fork", l_rng_fork},       {nullptr, nullptr}};
  new_class(L, kWorldType, world_methods, destroy<WorldBuilder>, l_world_tostring);
  new_class(L, kRngType, rng_methods, nullptr, nullptr);
  new_class(L, kShapeType, nullptr, destroy<ShapeBox>, l_shape_tostring);
  luaL_getmetatable(L, kShapeType);
  lua_pushcfunction(L, l_shape_index);
  lua_setfield(L, -2, "__index");
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
  lua_setfield(L, -2, "robot");
  lua_setglobal(L, "roger");
  return 0;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Scenario.

const char* param_type_name(ParamType type) {
  switch (type) {
    case ParamType::kNumber: return "number";
    case ParamType::kInteger: return "integer";
    case ParamType::kString: return "string";
    case ParamType::kBoolean: return "boolean";
  }
  return "?";
}

namespace {

// A parameter's current value in its own type.
struct ParamSlot {
  ScenarioParam info;
  double number = 0.0;
  int64_t integer = 0;
  std::string text;
  bool flag = false;
};

// The canonical text of a parameter value (what WorldSpec::params records).
std::string slot_text(const ParamSlot& s) {
  switch (s.info.type) {
    case ParamType::kNumber: return format_number(s.number);
    case ParamType::kInteger: return std::to_string(s.integer);
    case ParamType::kString: return s.text;
    case ParamType::kBoolean: return s.flag ? "true" : "false";
  }
  return "";
}

// Pushes a parameter value with its Lua type.
void push_slot(lua_State* L, const ParamSlot& s) {
  switch (s.info.type) {
    case ParamType::kNumber: lua_pushnumber(L, s.number); break;
    case ParamType::kInteger: lua_pushinteger(L, s.integer); break;
    case ParamType::kString: lua_pushstring(L, s.text.c_str()); break;
    case ParamType::kBoolean: lua_pushboolean(L, s.flag); break;
  }
}

// Parses text into a slot of the slot's type; false (and `why`) when it does not fit.
bool parse_slot(ParamSlot& s, const std::string& text, std::string& why) {
  const char* begin = text.c_str();
  char* end = nullptr;
  errno = 0;
  switch (s.info.type) {
    case ParamType::kInteger: {
      const long long v = std::strtoll(begin, &end, 10);
      if (text.empty() || *end || errno) return why = "an integer", false;
      s.integer = v;
      break;
    }
    case ParamType::kNumber: {
      const double v = std::strtod(begin, &end);
      if (text.empty() || *end || errno || !std::isfinite(v)) return why = "a number", false;
      s.number = v;
      break;
    }
    case ParamType::kBoolean: {
      std::string t = text;
      std::transform(t.begin(), t.end(), t.begin(), ::tolower);
      if (t == "true" || t == "1" || t == "yes" || t == "on") s.flag = true;
      else if (t == "false" || t == "0" || t == "no" || t == "off") s.flag = false;
      else return why = "a boolean (true or false)", false;
      break;
    }
    case ParamType::kString: s.text = text; break;
  }
  const std::string canonical = slot_text(s);
  if (!s.info.choices.empty() &&
      std::find(s.info.choices.begin(), s.info.choices.end(), canonical) == s.info.choices.end())
    return why = "one of " + join(s.info.choices), false;
  const double value = s.info.type == ParamType::kInteger ? double(s.integer) : s.number;
  if (s.info.type == ParamType::kNumber || s.info.type == ParamType::kInteger) {
    if (s.info.min && value < *s.info.min) return why = "at least " + format_number(*s.info.min), false;
    if (s.info.max && value > *s.info.max) return why = "at most " + format_number(*s.info.max), false;
  }
  return true;
}

// "name (type, default d; one of ...)", for the unknown-parameter message.
std::string describe_param(const ScenarioParam& p) {
  std::string text = p.name + " (" + param_type_name(p.type) + ", default " + p.default_value;
  if (!p.choices.empty()) text += "; one of " + join(p.choices);
  if (p.min) text += "; min " + format_number(*p.min);
  if (p.max) text += "; max " + format_number(*p.max);
  return text + ")";
}

// Parameter names must be usable as params.name in Lua.
bool is_identifier(const std::string& s) {
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
  return std::all_of(s.begin(), s.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

}  // namespace

struct Scenario::Impl {
  LuaSandbox sandbox;
  std::string path;  // as shown
  std::string name, description;
  int generate_ref = LUA_NOREF;
  int generate_line = 0;
  std::map<std::string, ParamSlot> params;

  explicit Impl(const SandboxLimits& limits) : sandbox(limits) {}

  // Runs `body` inside a protected call (body may use the Lua API and throw). Errors without a
  // location are attributed to the scenario file.
  void protect(const std::function<void(lua_State*)>& body, int nargs = 0) {
    lua_State* L = sandbox.state();
    lua_pushcfunction(L, [](lua_State* L) -> int {
      auto* fn = static_cast<const std::function<void(lua_State*)>*>(lua_touserdata(L, -1));
      lua_pop(L, 1);
      return lua_protect(L, [&]() {
        (*fn)(L);
        return 0;
      });
    });
    lua_insert(L, -(nargs + 1));
    lua_pushlightuserdata(L, const_cast<std::function<void(lua_State*)>*>(&body));
    try {
      sandbox.call(nargs + 1, 0);
    } catch (const ScriptError& e) {
      if (!e.file.empty()) throw;
      throw ScriptError(e.message, path, 0, e.traceback);
    }
  }

  ScriptError error(const std::string& message, int line = 0) const {
    return ScriptError(message, path, line, "");
  }

  void read_params(lua_State* L, int index);
  void read_table(lua_State* L);
};

// Reads the `params` table: short (name = default) and long ({default=, ...}) forms.
void Scenario::Impl::read_params(lua_State* L, int index) {
  index = lua_absindex(L, index);
  if (!lua_istable(L, index))
    throw error(std::string("the scenario's 'params' must be a table of name = default, got ") +
                luaL_typename(L, index));
  lua_pushnil(L);
  while (lua_next(L, index)) {
    const int key_slot = lua_gettop(L) - 1;
    if (lua_type(L, -2) != LUA_TSTRING || !is_identifier(lua_tostring(L, -2)))
      throw error("parameter names must be identifiers (name = default), got " +
                  std::string(lua_type(L, -2) == LUA_TSTRING ? "'" + std::string(lua_tostring(L, -2)) + "'"
                                                             : luaL_typename(L, -2)));
    ParamSlot slot;
    slot.info.name = lua_tostring(L, -2);
    const std::string ctx = "parameter '" + slot.info.name + "'";
    int value = lua_gettop(L);
    std::vector<std::string> choices;
    if (lua_istable(L, value)) {
      LuaFields f(L, value, ctx, {"default", "description", "choices", "min", "max"});
      slot.info.description = f.string("description", "");
      if (f.has("min")) slot.info.min = f.number("min");
      if (f.has("max")) slot.info.max = f.number("max");
      if (f.push("choices") != LUA_TNIL) {
        if (!lua_istable(L, -1)) f.wrong_type("choices", "a list of allowed values");
        for (lua_Integer i = 1; i <= lua_Integer(lua_rawlen(L, -1)); ++i) {
          lua_rawgeti(L, -1, i);
          if (lua_type(L, -1) == LUA_TNUMBER || lua_type(L, -1) == LUA_TSTRING)
            choices.push_back(lua_isinteger(L, -1) ? std::to_string(lua_tointeger(L, -1))
                              : lua_type(L, -1) == LUA_TNUMBER ? format_number(lua_tonumber(L, -1))
                                                                : lua_tostring(L, -1));
          else
            throw error(ctx + ": choices must be numbers or strings");
          lua_pop(L, 1);
        }
        if (choices.empty()) throw error(ctx + ": choices is empty");
      }
      f.push("default");
      value = lua_gettop(L);
      if (lua_isnil(L, value)) throw error(ctx + ": missing its 'default'");
    }
    switch (lua_type(L, value)) {
      case LUA_TNUMBER:
        if (lua_isinteger(L, value)) {
          slot.info.type = ParamType::kInteger;
          slot.integer = lua_tointeger(L, value);
        } else {
          slot.info.type = ParamType::kNumber;
          slot.number = lua_tonumber(L, value);
        }
        break;
      case LUA_TSTRING:
        slot.info.type = ParamType::kString;
        slot.text = lua_tostring(L, value);
        break;
      case LUA_TBOOLEAN:
        slot.info.type = ParamType::kBoolean;
        slot.flag = lua_toboolean(L, value);
        break;
      default:
        throw error(ctx + ": the default must be a number, integer, string or boolean, got " +
                    luaL_typename(L, value));
    }
    slot.info.choices = choices;
    slot.info.default_value = slot.info.value = slot_text(slot);
    std::string why;
    ParamSlot check = slot;
    if (!parse_slot(check, slot.info.default_value, why))
      throw error(ctx + ": the default " + slot.info.default_value + " is not " + why);
    params[slot.info.name] = std::move(slot);
    lua_settop(L, key_slot);  // keep the key for lua_next
  }
}

// Checks the table the script returned (on the stack top) and keeps its generator.
void Scenario::Impl::read_table(lua_State* L) {
  const int t = lua_gettop(L);
  if (!lua_istable(L, t))
    throw error(std::string("a scenario script must return a table {name=..., params={...}, "
                            "generate=function(world, rng, params) ... end}, got ") +
                luaL_typename(L, t));
  const std::vector<std::string> known{"description", "generate", "name", "params"};
  lua_pushnil(L);
  while (lua_next(L, t)) {
    lua_pop(L, 1);
    const std::string key = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : "";
    if (std::find(known.begin(), known.end(), key) == known.end())
      throw error("the scenario table has an unknown field " +
                  (key.empty() ? std::string("(a non-string key)") : "'" + key + "'") +
                  "; known fields: " + join(known));
  }
  auto text_field = [&](const char* key, const std::string& fallback) {
    const int type = lua_getfield(L, t, key);
    std::string v = fallback;
    if (type == LUA_TSTRING) v = lua_tostring(L, -1);
    else if (type != LUA_TNIL)
      throw error(std::string("the scenario's '") + key + "' must be a string, got " + luaL_typename(L, -1));
    lua_pop(L, 1);
    return v;
  };
  name = text_field("name", fs::path(path).stem().string());
  description = text_field("description", "");
  if (lua_getfield(L, t, "params") != LUA_TNIL) read_params(L, -1);
  lua_settop(L, t);
  if (lua_getfield(L, t, "generate") != LUA_TFUNCTION)
    throw error(std::string("the scenario table needs generate = function(world, rng, params) ... "
                            "end, got ") + luaL_typename(L, -1));
  lua_Debug ar;
  lua_pushvalue(L, -1);
  lua_getinfo(L, ">S", &ar);
  generate_line = ar.linedefined;
  generate_ref = luaL_ref(L, LUA_REGISTRYINDEX);
}

Scenario::Scenario() = default;
Scenario::Scenario(Scenario&&) noexcept = default;
Scenario& Scenario::operator=(Scenario&&) noexcept = default;
Scenario::~Scenario() = default;

Scenario Scenario::load(const std::string& path_in, const SandboxLimits& limits) {
  const std::string path = resolve_scenario_path(path_in);
  Scenario s;
  s.impl_ = std::make_unique<Impl>(limits);
  Impl& impl = *s.impl_;
  lua_State* L = impl.sandbox.state();
  impl.path = impl.sandbox.display_name(path);
  lua_pushcfunction(L, install_api);
  impl.sandbox.call(0, 0);
  impl.sandbox.set_main_script(path);
  impl.sandbox.run_file(path, 1);
  impl.protect([&](lua_State* L) { impl.read_table(L); }, 1);
  return s;
}

const std::string& Scenario::name() const { return impl_->name; }
const std::string& Scenario::description() const { return impl_->description; }
const std::string& Scenario::path() const { return impl_->path; }
LuaSandbox& Scenario::sandbox() { return impl_->sandbox; }

std::vector<ScenarioParam> Scenario::params() const {
  std::vector<ScenarioParam> out;
  for (const auto& [key, slot] : impl_->params) out.push_back(slot.info);
  return out;
}

void Scenario::set_param(const std::string& key, const std::string& value) {
  auto it = impl_->params.find(key);
  if (it == impl_->params.end()) {
    std::vector<std::string> known;
    for (const auto& [k, slot] : impl_->params) known.push_back(describe_param(slot.info));
    throw Error("scenario '" + impl_->name + "' (" + impl_->path + ") has no parameter '" + key +
                "'; " + (known.empty() ? "it has no parameters" : "known parameters: " + join(known, "; ")));
  }
  ParamSlot updated = it->second;
  std::string why;
  if (!parse_slot(updated, value, why))
    throw Error("parameter '" + key + "' of scenario '" + impl_->name + "' expects " + why +
                ", got '" + value + "'");
  updated.info.value = slot_text(updated);
  it->second = std::move(updated);
}

WorldSpec Scenario::generate(uint64_t seed) {
  Impl& impl = *impl_;
  WorldSpec out;
  impl.protect([&](lua_State* L) {
    lua_rawgeti(L, LUA_REGISTRYINDEX, impl.generate_ref);
    auto* w = static_cast<WorldBuilder*>(lua_newuserdatauv(L, sizeof(WorldBuilder), 1));
    new (w) WorldBuilder();
    luaL_setmetatable(L, kWorldType);
    const int world = lua_gettop(L);
    w->rng = &push_rng(L, seed);
    lua_pushvalue(L, -1);
    lua_setiuservalue(L, world, 1);  // the world keeps the rng alive
    lua_createtable(L, 0, int(impl.params.size()));
    for (const auto& [key, slot] : impl.params) {
      push_slot(L, slot);
      lua_setfield(L, -2, key.c_str());
    }
    lua_pushvalue(L, world);  // keep the world on this frame after the call
    lua_insert(L, world - 1);
    {
      // The world is read-only once generate returns or fails (a script may have kept it).
      struct Finish {
        WorldBuilder* w;
        ~Finish() { w->finished = true; }
      } finish{w};
      lua_call(L, 3, 0);
    }
    if (!w->robot_set)
      throw impl.error("the generator did not place Roger: call world:robot{x=..., y=..., heading=...}",
                       impl.generate_line);
    WorldSpec spec = w->spec;
    if (!w->stimulus_set && !spec.objects.empty()) spec.stimulus_colour = spec.objects.front().colour;
    try {
      for (auto& o : spec.objects) validate_shape(o.shape);
      for (auto& o : spec.obstacles) validate_shape(o.shape);
    } catch (const Error& e) {
      throw impl.error(e.what(), impl.generate_line);
    }
    spec.scenario = impl.path;
    spec.seed = seed;
    for (const auto& [key, slot] : impl.params) spec.params[key] = slot_text(slot);
    out = std::move(spec);
  });
  return out;
}

std::string resolve_scenario_path(const std::string& arg) {
  return resolve_script_path(arg, "scenarios", "scenario", "shipped scenarios");
}

std::vector<std::string> check_scenario(const std::string& path, int seeds, const SandboxLimits& limits) {
  std::vector<std::string> problems;
  std::set<std::string> seen;  // a mistake that every seed hits is reported once
  auto attempt = [&](const std::string& what, const std::function<void()>& body) {
    try {
      body();
    } catch (const std::exception& e) {
      if (seen.insert(e.what()).second) problems.push_back(what.empty() ? e.what() : what + ": " + e.what());
    }
  };
  std::optional<Scenario> scenario;
  attempt("", [&]() { scenario = Scenario::load(path, limits); });
  if (!scenario) return problems;
  for (int seed = 0; seed < seeds; ++seed)
    attempt("seed " + std::to_string(seed), [&]() { scenario->generate(uint64_t(seed)); });
  for (const auto& p : scenario->params()) {
    for (const auto& choice : p.choices) {
      attempt(p.name + "=" + choice + ", seed 0", [&]() {
        scenario->set_param(p.name, choice);
        scenario->generate(0);
      });
    }
    if (!p.choices.empty()) scenario->set_param(p.name, p.value);
  }
  return problems;
}

}  // namespace roger
