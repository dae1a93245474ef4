// curriculum_world.cpp: the world as a curriculum's Lua callbacks see it (their `world` argument).
#include <cstdio>

#include "script/curriculum/curriculum_internal.h"

namespace roger {
namespace curriculum_detail {

namespace {

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
    lua_rawseti(L, -2, lua_Integer(i + 1));
  }
  lua_setfield(L, -2, "obstacles");
}

}  // namespace

// The world as the Lua callbacks see it (the task's judge, not Roger's senses): every object with
// its pose, shape, colour, whether Roger touches it and the goal region its centre lies in; the
// regions; the obstacles.
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
    lua_rawseti(L, -2, lua_Integer(g + 1));
  }
  lua_setfield(L, -2, "goals");
  push_obstacles(L, spec);
}

}  // namespace curriculum_detail
}  // namespace roger
