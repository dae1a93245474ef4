// curriculum_world.cpp: the world as a curriculum's Lua callbacks see it (their `world` argument).
#include <cstdio>
#include <string>
#include <vector>

#include "core/text.h"
#include "script/curriculum/curriculum_internal.h"
#include "script/sandbox/lua_sandbox.h"

namespace roger {
namespace curriculum_detail {

namespace {

// A name a world table does not hold, read by a callback: an error at the callback's line naming
// the fields, where a nil would quietly change what it decides (`o.regoin == "goal"` false for
// good). `optional` is a field that may be absent (an object's region outside every region): nil.
int unknown_field(lua_State* L, const char* what, const std::vector<std::string>& fields,
                  const char* optional = nullptr) {
  const std::string key = lua_type(L, 2) == LUA_TSTRING ? lua_tostring(L, 2) : luaL_tolstring(L, 2, nullptr);
  if (optional && key == optional) return 0;
  return raise_at_reader(L, std::string(what) + " has no field '" + key + "'" + suggestion(key, fields) +
                                "; its fields: " + join(fields));
}
int unknown_world_field(lua_State* L) { return unknown_field(L, "world", {"objects", "goals", "obstacles"}); }
int unknown_object_field(lua_State* L) {
  return unknown_field(L, "an object of world.objects", {"name", "shape", "colour", "x", "y", "held", "region"},
                       "region");
}
int unknown_goal_field(lua_State* L) {
  return unknown_field(L, "a goal region of world.goals", {"name", "x", "y", "radius"});
}
int unknown_obstacle_field(lua_State* L) {
  return unknown_field(L, "an obstacle of world.obstacles", {"name", "x", "y", "shape"});
}

// The static obstacles as the callbacks see them: {name, x, y, shape} each, in the scenario's order.
void push_obstacles(lua_State* L, const WorldSpec& spec) {
  lua_createtable(L, int(spec.obstacles.size()), 0);
  for (size_t i = 0; i < spec.obstacles.size(); ++i) {
    const ObstacleSpec& o = spec.obstacles[i];
    lua_createtable(L, 0, 4);
    lua_pushstring(L, o.name.c_str());
    lua_setfield(L, -2, "name");
    lua_pushnumber(L, o.pose.x);
    lua_setfield(L, -2, "x");
    lua_pushnumber(L, o.pose.y);
    lua_setfield(L, -2, "y");
    lua_pushstring(L, o.shape.name.c_str());
    lua_setfield(L, -2, "shape");
    set_strict_index(L, "roger.WorldObstacle", unknown_obstacle_field);
    lua_rawseti(L, -2, lua_Integer(i + 1));
  }
  lua_setfield(L, -2, "obstacles");
}

}  // namespace

// The world as the Lua callbacks see it (the task's judge, not Roger's senses): every object with
// its pose, shape, colour, whether Roger touches it and the goal region its centre lies in; the
// regions; the obstacles. Each table is strict: reading a field it does not have is an error.
void push_world(lua_State* L, const World& world) {
  const WorldSpec& spec = world.spec();
  lua_createtable(L, 0, 3);
  lua_createtable(L, int(spec.objects.size()), 0);
  for (size_t i = 0; i < spec.objects.size(); ++i) {
    const Pose pose = world.object_pose(int(i));
    lua_createtable(L, 0, 8);
    lua_pushstring(L, spec.objects[i].name.c_str());
    lua_setfield(L, -2, "name");
    lua_pushstring(L, spec.objects[i].shape.name.c_str());
    lua_setfield(L, -2, "shape");
    lua_pushstring(L, spec.objects[i].colour.hex().c_str());
    lua_setfield(L, -2, "colour");
    lua_pushnumber(L, pose.x);
    lua_setfield(L, -2, "x");
    lua_pushnumber(L, pose.y);
    lua_setfield(L, -2, "y");
    lua_pushboolean(L, world.held(int(i)));
    lua_setfield(L, -2, "held");
    if (const int g = world.region_of(int(i)); g >= 0) {
      lua_pushstring(L, spec.goals[size_t(g)].name.c_str());
      lua_setfield(L, -2, "region");
    }
    set_strict_index(L, "roger.WorldObject", unknown_object_field);
    lua_rawseti(L, -2, lua_Integer(i + 1));
  }
  lua_setfield(L, -2, "objects");
  lua_createtable(L, int(spec.goals.size()), 0);
  for (size_t g = 0; g < spec.goals.size(); ++g) {
    lua_createtable(L, 0, 4);
    lua_pushstring(L, spec.goals[g].name.c_str());
    lua_setfield(L, -2, "name");
    lua_pushnumber(L, spec.goals[g].center.x());
    lua_setfield(L, -2, "x");
    lua_pushnumber(L, spec.goals[g].center.y());
    lua_setfield(L, -2, "y");
    lua_pushnumber(L, spec.goals[g].radius);
    lua_setfield(L, -2, "radius");
    set_strict_index(L, "roger.WorldGoal", unknown_goal_field);
    lua_rawseti(L, -2, lua_Integer(g + 1));
  }
  lua_setfield(L, -2, "goals");
  push_obstacles(L, spec);
  set_strict_index(L, "roger.World", unknown_world_field);
}

}  // namespace curriculum_detail
}  // namespace roger
