// lua_fields.cpp: converting Lua values for the bindings (named-field tables, colours) and the
// text helpers their messages use.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <lua.hpp>

#include "core/text.h"
#include "script/sandbox/lua_sandbox.h"

namespace roger {

LuaFields::LuaFields(lua_State* L, int index, std::string context, std::vector<std::string> known)
    : L_(L), index_(lua_absindex(L, index)), context_(std::move(context)) {
  if (!lua_istable(L_, index_))
    fail(std::string("expects a table of named fields, got ") + luaL_typename(L_, index_));
  std::sort(known.begin(), known.end());
  std::vector<std::string> unknown;
  lua_pushnil(L_);
  while (lua_next(L_, index_)) {
    lua_pop(L_, 1);
    if (lua_type(L_, -1) != LUA_TSTRING) {
      const std::string what = lua_isinteger(L_, -1)
                                   ? "a value at position " + std::to_string(lua_tointeger(L_, -1))
                                   : std::string("a key of type ") + luaL_typename(L_, -1);
      lua_pop(L_, 1);
      fail("expects named fields (name = value), got " + what + "; known fields: " + join(known));
    }
    const std::string key = lua_tostring(L_, -1);
    if (!std::binary_search(known.begin(), known.end(), key)) unknown.push_back(key);
  }
  if (!unknown.empty()) {
    // Each unknown field with the known one it is nearest to, if any (a misspelt 'forarm').
    std::sort(unknown.begin(), unknown.end());
    std::string named;
    for (const auto& key : unknown) named += (named.empty() ? "'" : ", '") + key + "'" + suggestion(key, known);
    fail(std::string(unknown.size() == 1 ? "unknown field " : "unknown fields ") + named +
         "; known fields: " + join(known));
  }
}

std::string lua_key_beside_list(lua_State* L, int index) {
  index = lua_absindex(L, index);
  const lua_Integer n = lua_Integer(lua_rawlen(L, index));
  std::vector<std::string> keys;
  lua_pushnil(L);
  while (lua_next(L, index)) {
    lua_pop(L, 1);
    if (lua_isinteger(L, -1) && lua_tointeger(L, -1) >= 1 && lua_tointeger(L, -1) <= n) continue;
    // Read without conversions: lua_tostring on a number key would change the key lua_next walks.
    if (lua_type(L, -1) == LUA_TSTRING) {
      size_t length = 0;
      const char* text = lua_tolstring(L, -1, &length);
      keys.push_back("'" + shortened_text(std::string(text, length), 40) + "'");
    } else if (lua_type(L, -1) == LUA_TNUMBER) {
      keys.push_back("[" + (lua_isinteger(L, -1) ? std::to_string(lua_tointeger(L, -1)) : format_number(lua_tonumber(L, -1))) + "]");
    } else {
      keys.push_back(std::string("[a ") + luaL_typename(L, -1) + "]");
    }
  }
  std::sort(keys.begin(), keys.end());
  return keys.empty() ? "" : keys.front();
}

void lua_check_arity(lua_State* L, const char* call, int most, const char* takes, const char* hint) {
  // A method's object is its first value on the stack, but not an argument the user counts.
  const int got = lua_gettop(L) - (std::strchr(call, ':') ? 1 : 0);
  if (got <= most) return;
  luaL_error(L, "%s: takes %s, got %d%s%s", call, takes, got, hint ? "; " : "", hint ? hint : "");
}

int raise_at_reader(lua_State* L, const std::string& text) {
  luaL_where(L, 1);
  lua_pushstring(L, text.c_str());
  lua_concat(L, 2);
  return lua_error(L);
}

void LuaFields::fail(const std::string& message) const {
  luaL_error(L_, "%s: %s", context_.c_str(), message.c_str());
  std::abort();  // unreachable: luaL_error does not return
}

void LuaFields::wrong_type(const char* key, const char* expected) const {
  push(key);
  // The type, and what it holds where that is short: "string 'ten'", "table (empty)".
  std::string got = luaL_typename(L_, -1);
  if (lua_type(L_, -1) == LUA_TSTRING) {
    std::string text = lua_tostring(L_, -1);
    if (text.size() > 40) text = text.substr(0, 37) + "...";
    got += " '" + text + "'";
  } else if (lua_type(L_, -1) == LUA_TNUMBER || lua_type(L_, -1) == LUA_TBOOLEAN) {
    got += " " + std::string(luaL_tolstring(L_, -1, nullptr));
    lua_pop(L_, 1);
  } else if (lua_type(L_, -1) == LUA_TTABLE) {
    lua_pushnil(L_);
    if (lua_next(L_, -2)) lua_pop(L_, 2);
    else got += " (empty)";
  }
  lua_pop(L_, 1);
  fail(std::string("field '") + key + "' must be " + expected + ", got " + got);
}

int LuaFields::push(const char* key) const {
  lua_pushstring(L_, key);
  return lua_rawget(L_, index_);
}

bool LuaFields::has(const char* key) const {
  const bool present = push(key) != LUA_TNIL;
  lua_pop(L_, 1);
  return present;
}

double LuaFields::number(const char* key) const {
  if (!has(key)) fail(std::string("missing required field '") + key + "' (a number)");
  return number(key, 0.0);
}

double LuaFields::number(const char* key, double fallback) const {
  const int type = push(key);
  if (type == LUA_TNIL) {
    lua_pop(L_, 1);
    return fallback;
  }
  if (type != LUA_TNUMBER) {
    lua_pop(L_, 1);
    wrong_type(key, "a number");
  }
  const double v = lua_tonumber(L_, -1);
  lua_pop(L_, 1);
  if (!std::isfinite(v)) fail(std::string("field '") + key + "' must be a finite number, got " + format_number(v));
  return v;
}

int64_t LuaFields::integer(const char* key) const {
  if (!has(key)) fail(std::string("missing required field '") + key + "' (an integer)");
  return integer(key, 0);
}

int64_t LuaFields::integer(const char* key, int64_t fallback) const {
  const int type = push(key);
  if (type == LUA_TNIL) {
    lua_pop(L_, 1);
    return fallback;
  }
  int ok = 0;
  const lua_Integer v = type == LUA_TNUMBER ? lua_tointegerx(L_, -1, &ok) : 0;
  const std::string shown = type == LUA_TNUMBER ? format_number(lua_tonumber(L_, -1)) : "";
  lua_pop(L_, 1);
  if (type != LUA_TNUMBER) wrong_type(key, "an integer");
  if (!ok) fail(std::string("field '") + key + "' must be an integer, got " + shown);
  return v;
}

std::string LuaFields::string(const char* key) const {
  if (!has(key)) fail(std::string("missing required field '") + key + "' (a string)");
  return string(key, "");
}

std::string LuaFields::string(const char* key, const std::string& fallback) const {
  const int type = push(key);
  if (type == LUA_TNIL) {
    lua_pop(L_, 1);
    return fallback;
  }
  if (type != LUA_TSTRING) {
    lua_pop(L_, 1);
    wrong_type(key, "a string");
  }
  std::string v = lua_tostring(L_, -1);
  lua_pop(L_, 1);
  return v;
}

bool LuaFields::boolean(const char* key, bool fallback) const {
  const int type = push(key);
  if (type == LUA_TNIL) {
    lua_pop(L_, 1);
    return fallback;
  }
  if (type != LUA_TBOOLEAN) {
    lua_pop(L_, 1);
    wrong_type(key, "a boolean");
  }
  const bool v = lua_toboolean(L_, -1);
  lua_pop(L_, 1);
  return v;
}

Colour LuaFields::colour(const char* key, const Colour& fallback) const {
  if (push(key) == LUA_TNIL) {
    lua_pop(L_, 1);
    return fallback;
  }
  const Colour c = lua_to_colour(L_, -1, context_ + ": field '" + key + "'");
  lua_pop(L_, 1);
  return c;
}

Colour lua_to_colour(lua_State* L, int index, const std::string& context) {
  index = lua_absindex(L, index);
  const char* expected = "a colour: {r, g, b} or {r=, g=, b=} with integers 0-255, or \"#rrggbb\"";
  if (lua_type(L, index) == LUA_TSTRING) {
    const std::string text = lua_tostring(L, index);
    // Six hex digits after the '#': sscanf's %x alone took a sign, spaces and a 0x (found by a probe:
    // "#-1-1-1" was white, and "# 1 2 3" #010203, each without a word).
    const bool hex = text.size() == 7 && text[0] == '#' &&
                     std::all_of(text.begin() + 1, text.end(), [](char c) { return std::isxdigit(uint8_t(c)) != 0; });
    unsigned r, g, b;
    if (hex && std::sscanf(text.c_str(), "#%2x%2x%2x", &r, &g, &b) == 3) return Colour{uint8_t(r), uint8_t(g), uint8_t(b)};
    luaL_error(L, "%s must be %s, got \"%s\"", context.c_str(), expected, text.c_str());
  }
  if (!lua_istable(L, index))
    luaL_error(L, "%s must be %s, got %s", context.c_str(), expected, luaL_typename(L, index));
  const bool named = lua_getfield(L, index, "r") != LUA_TNIL;
  lua_pop(L, 1);
  // Keys beside the three components (found by a probe: {200, 0, 0, 0} passed with its fourth
  // entry dropped, and {1, 2, 3, r = 4} was said to miss its g).
  int positional = 0, keyed = 0;
  std::string other;
  lua_pushnil(L);
  while (lua_next(L, index) != 0) {
    lua_pop(L, 1);
    int is_int = 0;
    const lua_Integer k = lua_type(L, -1) == LUA_TNUMBER ? lua_tointegerx(L, -1, &is_int) : 0;
    const char* name = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : nullptr;
    if (is_int && k >= 1 && k <= 3) ++positional;
    else if (name && (!std::strcmp(name, "r") || !std::strcmp(name, "g") || !std::strcmp(name, "b"))) ++keyed;
    else if (other.empty())
      other = name     ? "'" + std::string(name) + "'"
              : is_int ? "[" + std::to_string(k) + "]"
                       : "a " + std::string(luaL_typename(L, -1)) + " key";
  }
  if (!other.empty())
    luaL_error(L, "%s must be %s: it has %s beside the three components (a colour has no alpha)", context.c_str(),
               expected, other.c_str());
  if (positional > 0 && keyed > 0)
    luaL_error(L, "%s must be %s: it mixes {r, g, b} and {r=, g=, b=}", context.c_str(), expected);
  const char* names[3] = {"r", "g", "b"};
  uint8_t out[3];
  for (int i = 0; i < 3; ++i) {
    const int type = named ? lua_getfield(L, index, names[i]) : lua_rawgeti(L, index, i + 1);
    int ok = 0;
    const lua_Integer v = type == LUA_TNUMBER ? lua_tointegerx(L, -1, &ok) : 0;
    lua_pop(L, 1);
    if (!ok || v < 0 || v > 255) {
      // What was given, read again: the component is popped (a number shows as Lua prints it).
      named ? lua_getfield(L, index, names[i]) : lua_rawgeti(L, index, i + 1);
      const std::string got = lua_type(L, -1) == LUA_TNUMBER ? format_number(lua_tonumber(L, -1))
                              : lua_isnil(L, -1)            ? std::string("nothing")
                                                            : std::string("a ") + luaL_typename(L, -1);
      luaL_error(L, "%s must be %s (component %s is missing or not an integer 0-255, got %s)", context.c_str(), expected,
                 names[i], got.c_str());
    }
    out[i] = uint8_t(v);
  }
  return Colour{out[0], out[1], out[2]};
}

LuaStackGuard::LuaStackGuard(lua_State* L) : L_(L), top_(lua_gettop(L)) {}
LuaStackGuard::~LuaStackGuard() { lua_settop(L_, top_); }

}  // namespace roger
