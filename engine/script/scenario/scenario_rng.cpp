// scenario_rng.cpp: the rng object a generator draws from.
#include <cmath>

#include "script/scenario/scenario_internal.h"

namespace roger {
namespace scenario_detail {

namespace {
// Registry fields: the epoch whose rngs draw now (0: none), and the last epoch handed out.
constexpr const char* kLiveEpoch = "roger.rng_live_epoch";
constexpr const char* kLastEpoch = "roger.rng_last_epoch";

lua_Integer registry_integer(lua_State* L, const char* key) {
  lua_getfield(L, LUA_REGISTRYINDEX, key);
  const lua_Integer v = lua_tointeger(L, -1);
  lua_pop(L, 1);
  return v;
}

void set_registry_integer(lua_State* L, const char* key, lua_Integer v) {
  lua_pushinteger(L, v);
  lua_setfield(L, LUA_REGISTRYINDEX, key);
}
}  // namespace

ScriptRng& push_rng(lua_State* L, uint64_t seed, lua_Integer epoch) {
  auto* rng = static_cast<ScriptRng*>(lua_newuserdatauv(L, sizeof(ScriptRng), 0));
  new (rng) ScriptRng{Rng(seed), epoch};
  luaL_setmetatable(L, kRngType);
  return *rng;
}

lua_Integer open_rng_epoch(lua_State* L) {
  const lua_Integer epoch = registry_integer(L, kLastEpoch) + 1;
  set_registry_integer(L, kLastEpoch, epoch);
  set_registry_integer(L, kLiveEpoch, epoch);
  return epoch;
}

void close_rng_epoch(lua_State* L) { set_registry_integer(L, kLiveEpoch, 0); }

void set_live_rng_epoch(lua_State* L, lua_Integer epoch) { set_registry_integer(L, kLiveEpoch, epoch); }

namespace {

// The rng a method is called on, or an error when its generate call has returned.
ScriptRng& live_rng(lua_State* L, const char* call) {
  ScriptRng& r = self<ScriptRng>(L, kRngType, call);
  if (r.epoch < 0 && registry_integer(L, kLiveEpoch) != r.epoch)
    luaL_error(L, "%s: this rng is a teacher function's, and draws only while that function runs, so that "
               "every other callback depends on the episode alone (draw inside the teacher what it needs)", call);
  if (r.epoch != 0 && registry_integer(L, kLiveEpoch) != r.epoch)
    luaL_error(L, "%s: this rng is finished: a world's rng and its forks draw only while its generate runs, so "
               "that a world depends on its parameters and seed alone (draw inside generate what later calls "
               "need, and keep the numbers)", call);
  return r;
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

}  // namespace

// rng:uniform() in [0, 1), rng:uniform(a, b) in [a, b).
int l_rng_uniform(lua_State* L) {
  Rng& rng = live_rng(L, "rng:uniform").rng;
  lua_check_arity(L, "rng:uniform", 2, "no arguments or 2 (a, b)");
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
  Rng& rng = live_rng(L, "rng:int").rng;
  lua_check_arity(L, "rng:int", 2, "1 or 2 arguments (n, or a and b)");
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
  Rng& rng = live_rng(L, "rng:normal").rng;
  lua_check_arity(L, "rng:normal", 2, "at most 2 arguments (mu, sigma)");
  const double mu = lua_isnoneornil(L, 2) ? 0.0 : arg_number(L, 2, "rng:normal", "mu");
  const double sigma = lua_isnoneornil(L, 3) ? 1.0 : arg_number(L, 3, "rng:normal", "sigma");
  if (sigma < 0.0) return luaL_error(L, "rng:normal: sigma must not be negative");
  lua_pushnumber(L, rng.normal(mu, sigma));
  return 1;
}

// rng:angle(): uniform in [-pi, pi).
int l_rng_angle(lua_State* L) {
  Rng& rng = live_rng(L, "rng:angle").rng;
  lua_check_arity(L, "rng:angle", 0, "no arguments");
  lua_pushnumber(L, rng.uniform(-M_PI, M_PI));
  return 1;
}

namespace {

// An empty list that is a table of named entries (rng:choice{a = 1}): said as such, with the name
// of the function; nothing otherwise.
void refuse_named_entries(lua_State* L, const char* what, const char* instead) {
  if (lua_rawlen(L, 2) > 0) return;
  lua_pushnil(L);
  if (!lua_next(L, 2)) return;
  const std::string key = luaL_tolstring(L, -2, nullptr);
  luaL_error(L, "%s: expects a list {v1, v2, ...}, got a table whose entries are named (as '%s'): %s", what,
             key.c_str(), instead);
}

}  // namespace

// rng:choice(list): one element, uniformly. A view (a teacher's history) is read through to its
// data: read raw, it was empty (found by a probe: rng:choice(history) said "the list is empty"
// with an episode in it).
int l_rng_choice(lua_State* L) {
  Rng& rng = live_rng(L, "rng:choice").rng;
  lua_check_arity(L, "rng:choice", 1, "1 argument (a list)");
  if (!lua_istable(L, 2)) return luaL_error(L, "rng:choice: expects a list, got %s", luaL_typename(L, 2));
  if (lua_push_view_data(L, 2)) lua_replace(L, 2);
  const lua_Integer n = lua_Integer(lua_rawlen(L, 2));
  // A table of named entries only is no list (found by a probe: rng:choice{a = 1} said "empty").
  refuse_named_entries(L, "rng:choice", "draw from a list of its keys or values");
  if (n == 0) return luaL_error(L, "rng:choice: the list is empty");
  lua_rawgeti(L, 2, rng.integer(1, n));
  return 1;
}

// rng:shuffle(list): shuffles in place (Fisher-Yates) and returns the list.
int l_rng_shuffle(lua_State* L) {
  Rng& rng = live_rng(L, "rng:shuffle").rng;
  lua_check_arity(L, "rng:shuffle", 1, "1 argument (a list)");
  if (!lua_istable(L, 2)) return luaL_error(L, "rng:shuffle: expects a list, got %s", luaL_typename(L, 2));
  // A view cannot change (found by a probe: rng:shuffle(history) returned it as it was, unsaid).
  if (lua_push_view_data(L, 2))
    return luaL_error(L, "rng:shuffle: shuffles its list in place, and %s cannot change: shuffle a copy (local t = "
                      "{} for i, v in ipairs(list) do t[i] = v end)",
                      luaL_getmetafield(L, 2, "__metatable") == LUA_TSTRING ? lua_tostring(L, -1) : "a view");
  // Found by a probe: rng:shuffle{a = 1} returned it unchanged, where rng:choice refuses it.
  refuse_named_entries(L, "rng:shuffle", "a table's entries have no order to shuffle; shuffle a list of its keys");
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
  ScriptRng& parent = live_rng(L, "rng:fork");
  lua_check_arity(L, "rng:fork", 0, "no arguments");
  push_rng(L, parent.rng.next(), parent.epoch);
  return 1;
}

}  // namespace scenario_detail
}  // namespace roger
