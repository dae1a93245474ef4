// scenario_shapes.cpp: roger.shape and the immutable shape values it makes.
#include <cmath>

#include "core/error.h"
#include "core/shape.h"
#include "script/scenario/scenario_internal.h"

namespace roger {
namespace scenario_detail {
namespace {

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
  // Nothing beside the two (found by a probe: {0, 0, 0} and {x = 0, y = 0, z = 1} were taken).
  int entries = 0;
  index = lua_absindex(L, index);
  lua_pushnil(L);
  while (lua_next(L, index)) lua_pop(L, 1), ++entries;
  if (entries != 2)
    luaL_error(L, "%s must be {x, y} (or {x = ..., y = ...}) and nothing else, got a table of %d entries", where.c_str(),
               entries);
  return Vec2(xy[0], xy[1]);
}

}  // namespace

// roger.shape{name=, polygons={{{x,y},...},...}, disks={{x=,y=,r=},...}}
int l_shape(lua_State* L) {
  return lua_protect(L, [L]() {
    lua_check_arity(L, "roger.shape", 1, "1 argument (a table of fields)");
    LuaFields f(L, 1, "roger.shape", {"name", "polygons", "disks"});
    Shape shape;
    shape.name = f.string("name", "unnamed");
    const std::string ctx = "roger.shape: shape '" + shape.name + "'";
    if (f.push("polygons") != LUA_TNIL) {
      if (!lua_istable(L, -1)) f.wrong_type("polygons", "a list of polygons, each a list of {x, y}");
      if (const std::string key = lua_key_beside_list(L, -1); !key.empty())
        f.fail("field 'polygons' must be a list of polygons {p1, p2, ...}, got the key " + key);
      const lua_Integer n = lua_Integer(lua_rawlen(L, -1));
      if (size_t(n) > kMaxParts) f.fail("more than " + std::to_string(kMaxParts) + " polygons");
      for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L, -1, i);
        const std::string where = ctx + " polygon " + std::to_string(i);
        if (!lua_istable(L, -1)) luaL_error(L, "%s must be a list of {x, y} vertices, got %s", where.c_str(), luaL_typename(L, -1));
        Polygon poly;
        if (const std::string key = lua_key_beside_list(L, -1); !key.empty())
          luaL_error(L, "%s must be a list of {x, y} vertices, got the key %s", where.c_str(), key.c_str());
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
      // A lone disk written without its list ({x = 0, r = 0.1}) said "has no parts".
      if (const std::string key = lua_key_beside_list(L, -1); !key.empty())
        f.fail("field 'disks' must be a list of disks {{x=, y=, r=}, ...}, got the key " + key +
               (lua_type(L, -1) == LUA_TTABLE && lua_getfield(L, -1, "r") != LUA_TNIL ? " (one disk? write disks = {{...}})" : ""));
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
    lua_check_arity(L, "shape:scaled", 2, "1 or 2 arguments (factor [, name])");
    const double k = lua_tonumber(L, 2);
    if (lua_type(L, 2) != LUA_TNUMBER || !(k > 0.0) || !std::isfinite(k))
      luaL_error(L, "shape:scaled: the factor must be a positive number, got %s",
                 lua_type(L, 2) == LUA_TNUMBER ? luaL_tolstring(L, 2, nullptr) : luaL_typename(L, 2));
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

// The shape value at index, or null.
ShapeBox* test_shape(lua_State* L, int index) {
  return static_cast<ShapeBox*>(luaL_testudata(L, index, kShapeType));
}

}  // namespace scenario_detail
}  // namespace roger
