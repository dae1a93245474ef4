// scenario_placement.cpp: world:sample_position, rejection sampling of a free position that keeps
// its distances from the walls, Roger, the objects, the obstacles, the goals and given points.
#include <algorithm>
#include <cmath>
#include <optional>

#include "core/shape.h"
#include "script/scenario/scenario_internal.h"

namespace roger {
namespace scenario_detail {
namespace {

// A point the sampled position must stay `distance` away from.
struct Away {
  Vec2 p;
  double distance;
  std::string name;
};

// What world:sample_position was asked for.
struct SampleRequest {
  std::string name;
  double radius = 0.0;
  double clearance = 0.0;
  double margin = 0.0;
  double robot_distance = 0.0;
  bool avoid_goals = true;
  int64_t tries = 0;
  std::vector<Away> away;
};

// The rectangle the centre may be in: the arena shrunk by the margin, within the region.
struct SampleArea {
  double x0, x1, y0, y1;
  std::string region_text;
};

// A constraint with the number of candidates it rejected.
struct Constraint {
  std::string text;
  int64_t rejected = 0;
  int64_t last_try = -1;  // the candidate it last rejected: one it rejects twice (two goals) counts once
};

// The constraints, with where each kind starts in the list.
struct SampleConstraints {
  std::vector<Constraint> list;
  size_t c_robot = 0, c_robot_distance = 0, c_objects = 0, c_obstacles = 0, c_goals = 0, c_away = 0;
};

// The radius of the disk to place: the field 'radius', or the bounding radius of 'shape'.
double read_radius(lua_State* L, const LuaFields& f) {
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
  return radius;
}

// The field 'away_from': a list of {x=, y=, distance=, name=}.
std::vector<Away> read_away_from(lua_State* L, const LuaFields& f) {
  std::vector<Away> away;
  if (f.push("away_from") != LUA_TNIL) {
    if (!lua_istable(L, -1)) f.wrong_type("away_from", "a list of {x=, y=, distance=, name=}");
    // Found by a probe: away_from = {x = 1, y = 1, distance = 3}, one point without its list, was a
    // list of none: the 3 m were never kept, and roger check said ok.
    if (const std::string key = lua_key_beside_list(L, -1); !key.empty())
      f.fail("field 'away_from' must be a list {{x=, y=, distance=}, ...}, got the key " + key +
             " (one point? write away_from = {{x = ..., y = ..., distance = ...}})");
    const lua_Integer n = lua_Integer(lua_rawlen(L, -1));
    for (lua_Integer i = 1; i <= n; ++i) {
      lua_rawgeti(L, -1, i);
      LuaFields a(L, -1, "world:sample_position: away_from[" + std::to_string(i) + "]",
                  {"x", "y", "distance", "name"});
      Away item{Vec2(a.number("x"), a.number("y")), a.number("distance"), ""};
      // A negative distance keeps nothing away, and said nothing (found by a probe).
      if (item.distance < 0.0) a.fail("field 'distance' must not be negative, got " + fmt(item.distance));
      item.name = a.string("name", point_text(item.p.x(), item.p.y()));
      away.push_back(std::move(item));
      lua_pop(L, 1);
    }
  }
  lua_pop(L, 1);
  return away;
}

// Reads the fields of world:sample_position (all but 'region'), checking each.
SampleRequest read_request(lua_State* L, const LuaFields& f) {
  SampleRequest r;
  r.name = f.string("name", "position");
  const double radius = read_radius(L, f);
  if (radius < 0.0) f.fail("field 'radius' must not be negative");
  const double clearance = f.number("clearance", 0.05);
  if (clearance < 0.0) f.fail("field 'clearance' must not be negative");
  const double margin = std::max(f.number("wall_margin", radius + clearance), radius);
  const double robot_distance = f.number("robot_distance", 0.0);
  if (robot_distance < 0.0) f.fail("field 'robot_distance' must not be negative");
  const bool avoid_goals = f.boolean("avoid_goals", true);
  const int64_t tries = f.integer("tries", 1000);
  if (tries < 1 || tries > 1'000'000) f.fail("field 'tries' must be 1 to 1000000");
  r.radius = radius;
  r.clearance = clearance;
  r.margin = margin;
  r.robot_distance = robot_distance;
  r.avoid_goals = avoid_goals;
  r.tries = tries;
  r.away = read_away_from(L, f);
  return r;
}

// The rectangle the centre may be in, from the arena, the margin and the field 'region'.
SampleArea read_area(lua_State* L, const LuaFields& f, const ArenaSpec& a, double margin) {
  // The rectangle the centre may be in: the arena shrunk by the margin, within the region.
  double x0 = a.xmin + margin, x1 = a.xmax - margin, y0 = a.ymin + margin, y1 = a.ymax - margin;
  std::string region_text;
  if (f.push("region") != LUA_TNIL) {
    LuaFields r(L, -1, "world:sample_position: region", {"xmin", "xmax", "ymin", "ymax"});
    const double rx0 = r.number("xmin", a.xmin), rx1 = r.number("xmax", a.xmax);
    const double ry0 = r.number("ymin", a.ymin), ry1 = r.number("ymax", a.ymax);
    // A reversed region is the script's slip, not the arena's lack of room (found by a probe).
    if (rx0 > rx1) r.fail("xmin " + fmt(rx0) + " is past xmax " + fmt(rx1) + ": the region holds no point");
    if (ry0 > ry1) r.fail("ymin " + fmt(ry0) + " is past ymax " + fmt(ry1) + ": the region holds no point");
    x0 = std::max(x0, rx0), x1 = std::min(x1, rx1), y0 = std::max(y0, ry0), y1 = std::min(y1, ry1);
    region_text = " within the region [" + fmt(rx0) + ", " + fmt(rx1) + "] x [" + fmt(ry0) + ", " +
                  fmt(ry1) + "]";
  }
  lua_pop(L, 1);
  return SampleArea{x0, x1, y0, y1, region_text};
}

// The constraints a candidate must meet, in the order the failure message lists them.
SampleConstraints constraints_of(const WorldBuilder& w, const SampleRequest& r,
                                 const std::string& region_text) {
  SampleConstraints c;
  auto& constraints = c.list;
  constraints.push_back({measured(r.margin) + " m from the walls" + region_text});
  c.c_robot = constraints.size();
  if (w.robot_set)
    constraints.push_back({fmt(r.clearance) + " m clearance from Roger's base and hands"});
  c.c_robot_distance = constraints.size();
  if (w.robot_set && r.robot_distance > 0.0)
    constraints.push_back({fmt(r.robot_distance) + " m from Roger"});
  c.c_objects = constraints.size();
  constraints.push_back({fmt(r.clearance) + " m clearance from the objects"});
  c.c_obstacles = constraints.size();
  constraints.push_back({fmt(r.clearance) + " m clearance from the obstacles"});
  c.c_goals = constraints.size();
  constraints.push_back({fmt(r.clearance) + " m clearance from the goal regions"});
  c.c_away = constraints.size();
  for (const auto& item : r.away) constraints.push_back({fmt(item.distance) + " m from " + item.name});
  return c;
}

// Draws up to r.tries candidates from the world's rng; the first that meets every constraint, or
// none (each constraint then counts the candidates it rejected).
std::optional<Vec2> draw_position(lua_State* L, const WorldBuilder& w, const SampleRequest& r,
                                  const SampleArea& area, SampleConstraints& c) {
  const Occupants occ = occupants(w, true, true);
  const size_t robot_parts = w.robot_set ? 3 : 0;
  const double radius = r.radius, clearance = r.clearance;
  const double x0 = area.x0, x1 = area.x1, y0 = area.y0, y1 = area.y1;
  const auto& away = r.away;
  const Vec2 base(w.spec.robot.pose.x, w.spec.robot.pose.y);
  for (int64_t t = 0; t < r.tries; ++t) {
    // Found by a probe: a million tries where no place fits ran out of the budget as a "runaway loop?".
    lua_charge(L, 1 + occ.list.size() + w.spec.goals.size() + away.size(), "world:sample_position",
               "its tries ran past the budget left before a place was found (no place may meet its constraints: "
               "with fewer tries it says which failed)");
    // One draw per statement: the order in which a call's arguments are evaluated is unspecified
    // (gcc drew y first, clang x), so the worlds, and every result, depended on the compiler.
    // y first keeps the worlds of the gcc builds that made tests/golden.
    const double y = w.rng->uniform(y0, y1);
    const double x = w.rng->uniform(x0, x1);
    const Vec2 p(x, y);
    bool ok = true;
    auto reject = [&](size_t k) {
      if (c.list[k].last_try != t) ++c.list[k].rejected, c.list[k].last_try = t;
      ok = false;
    };
    for (size_t i = 0; i < occ.list.size(); ++i) {
      const auto& o = occ.list[i];
      if (shape_signed_distance(*o.shape, o.pose, p) - radius < clearance) {
        const bool is_robot = i < robot_parts;
        const bool is_object = !is_robot && i < robot_parts + w.spec.objects.size();
        reject(is_robot ? c.c_robot : is_object ? c.c_objects : c.c_obstacles);
      }
    }
    if (w.robot_set && r.robot_distance > 0.0 && (p - base).norm() < r.robot_distance)
      reject(c.c_robot_distance);
    if (r.avoid_goals)
      for (const auto& g : w.spec.goals)
        if ((p - g.center).norm() - g.radius - radius < clearance) reject(c.c_goals);
    for (size_t i = 0; i < away.size(); ++i)
      if ((p - away[i].p).norm() < away[i].distance) reject(c.c_away + i);
    if (ok) return p;
  }
  return std::nullopt;
}

// What the failure message says the position needs: every constraint that rejected candidates
// (with its count of the `tries`, or "every try", which the message has just counted), and those
// that always apply.
std::string needs_text(const SampleConstraints& c, int tries) {
  const auto& constraints = c.list;
  std::vector<std::string> parts;
  for (const auto& k : constraints) {
    if (k.rejected > 0)
      parts.push_back(k.text + (k.rejected >= tries ? std::string(" (failed every try)")
                                                    : " (failed in " + std::to_string(k.rejected) + " tries)"));
    else if (&k == &constraints.front() || k.text.find("clearance") == std::string::npos)
      parts.push_back(k.text);
  }
  return join(parts);
}

}  // namespace

// world:sample_position{name=, radius= | shape=, wall_margin=, clearance=, robot_distance=,
//                       away_from={{x=, y=, distance=, name=}, ...}, avoid_goals=,
//                       region={xmin=, xmax=, ymin=, ymax=}, tries=}
// Rejection sampling of a free disk centre, drawing from the generator's rng. Returns x, y.
int l_world_sample(lua_State* L) {
  return lua_protect(L, [L]() {
    WorldBuilder& w = world_self(L, "world:sample_position");
    lua_check_arity(L, "world:sample_position", 1, "1 argument (a table of fields)");
    LuaFields f(L, 2, "world:sample_position",
                {"name", "radius", "shape", "wall_margin", "clearance", "robot_distance",
                 "away_from", "avoid_goals", "region", "tries"});
    fix_arena(w);
    const SampleRequest request = read_request(L, f);
    const ArenaSpec& a = w.spec.arena;
    const SampleArea area = read_area(L, f, a, request.margin);
    const std::string label = "no placement for '" + request.name + "'";
    if (area.x0 > area.x1 || area.y0 > area.y1)
      f.fail(label + ": it needs " + measured(request.margin) + " m from the walls" + area.region_text +
             ", which leaves no room in a " + arena_text(a));
    SampleConstraints constraints = constraints_of(w, request, area.region_text);
    if (const auto p = draw_position(L, w, request, area, constraints)) {
      lua_pushnumber(L, p->x());
      lua_pushnumber(L, p->y());
      return 2;
    }
    if (w.no_placement) *w.no_placement = true;
    f.fail(label + " after " + std::to_string(request.tries) + " tries: it needs " +
           needs_text(constraints, request.tries) + " in a " + arena_text(a));
  });
}

}  // namespace scenario_detail
}  // namespace roger
