// lua_pairs.cpp: pairs() in an order that is the same in every run. Lua's own pairs visits a
// table's keys in the order of their hash slots, and a string's hash is seeded per Lua state from
// the clock and from addresses that change with each process: a teacher that picked "the shape
// learned least" by a loop of pairs over shape names gave three different runs out of four from
// one seed (found by a probe). Lua leaves the order unspecified, so a fixed one keeps its
// semantics: every key with a value is visited once, a field cleared during the loop is not
// visited after, and assigning to an existing field is allowed; a table with a __pairs
// metamethod, and any value that is not a table, get Lua's own pairs.
//
// The order: numbers by value, then strings byte by byte (not strcoll's, which depends on the
// locale), then false and true, then the keys that have no order of their own (tables, functions,
// userdata, threads) in Lua's order, which is the one part that can change between runs.
// `next`, `rawget`, `rawlen` and `rawset` stay Lua's own, but for a view (lua_new_view), whose data
// they read (rawset: write as the view's own rule for writes says).
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include <lua.hpp>

#include "script/sandbox/lua_sandbox_internal.h"

namespace roger {
namespace sandbox_detail {
namespace {

// Instructions charged per key, and per key and level of the sort: a pairs over n keys costs about
// what a Lua loop collecting and sorting them would.
constexpr uint64_t kKeyCost = 4;

// A key as the sort sees it: its class and value, and its place in the collected list.
struct SortKey {
  int rank = 0;  // 0 number, 1 string, 2 boolean, 3 other (Lua's order kept)
  bool integer = false;
  lua_Integer i = 0;
  double d = 0.0;
  const char* s = nullptr;
  size_t length = 0;
  int slot = 0;  // index in the collected list (1-based), which keeps the key alive
};

// Whether integer i is less than float f, exactly. Float keys never hold an integral value in
// the integers' range (Lua stores those as integers), and never NaN.
bool integer_below(lua_Integer i, double f) {
  if (f >= 9223372036854775808.0) return true;
  if (f < -9223372036854775808.0) return false;
  return i <= lua_Integer(std::floor(f));
}

bool number_below(const SortKey& a, const SortKey& b) {
  if (a.integer && b.integer) return a.i < b.i;
  if (!a.integer && !b.integer) return a.d < b.d;
  return a.integer ? integer_below(a.i, b.d) : !integer_below(b.i, a.d);
}

bool key_below(const SortKey& a, const SortKey& b) {
  if (a.rank != b.rank) return a.rank < b.rank;
  switch (a.rank) {
    case 0:
      return number_below(a, b);
    case 1: {
      const int c = std::memcmp(a.s, b.s, std::min(a.length, b.length));
      return c != 0 ? c < 0 : a.length < b.length;
    }
    case 2:
      return a.i < b.i;
    default:
      return a.slot < b.slot;
  }
}

// The key at the top of the stack, collected as `slot`.
SortKey describe_key(lua_State* L, int slot) {
  SortKey k;
  k.slot = slot;
  switch (lua_type(L, -1)) {
    case LUA_TNUMBER:
      k.integer = lua_isinteger(L, -1);
      if (k.integer) k.i = lua_tointeger(L, -1); else k.d = lua_tonumber(L, -1);
      break;
    case LUA_TSTRING:
      k.rank = 1;
      k.s = lua_tolstring(L, -1, &k.length);
      break;
    case LUA_TBOOLEAN:
      k.rank = 2;
      k.i = lua_toboolean(L, -1);
      break;
    default:
      k.rank = 3;
  }
  return k;
}

// Raises what Lua's next raises for the key at index 2 of pairs' table (upvalue 1), if anything:
// "invalid key to 'next'" with no position, as Lua's next raises it from C. Whether Lua takes a
// key is its table's business: a float key of integral value is never an array index to it
// (lua 5.4.4's findindex), and in the hash part it is found only when its slot's chain holds the
// integer key; an integer key with no value is taken in the array part; a key whose value was
// cleared stays until the table is rebuilt.
void check_key_as_lua(lua_State* L) {
  lua_pushvalue(L, 2);
  if (lua_next(L, lua_upvalueindex(1))) lua_pop(L, 2);
}

// For a key Lua's next takes that pairs did not collect: how many collected keys (upvalue 2)
// sort at or before it (a key with no order of its own goes after them all).
lua_Integer sorted_place(lua_State* L) {
  lua_pushvalue(L, 2);
  const SortKey key = describe_key(L, INT_MAX);
  lua_Integer lo = 0, hi = lua_Integer(lua_rawlen(L, lua_upvalueindex(2)));
  while (lo < hi) {
    const lua_Integer mid = lo + (hi - lo) / 2;
    lua_rawgeti(L, lua_upvalueindex(2), mid + 1);
    const bool after = key_below(key, describe_key(L, int(mid + 1)));
    lua_pop(L, 1);
    if (after) hi = mid; else lo = mid + 1;
  }
  lua_pop(L, 1);
  return lo;
}

// The position to look from after the key at index 2 (not nil). The key returned last is known
// at once; any other is looked up among the collected keys. A float key, and a key pairs did not
// collect, are first put to Lua's next, which refuses them or not as it would (found by a probe:
// the iterator took 1.0 for 1 and refused keys with luaL_error, which puts file:line in front).
lua_Integer position_after(lua_State* L) {
  const bool is_float = lua_type(L, 2) == LUA_TNUMBER && !lua_isinteger(L, 2);
  const lua_Integer last = lua_tointeger(L, lua_upvalueindex(3));
  if (!is_float && last > 0) {
    lua_rawgeti(L, lua_upvalueindex(2), last);
    const bool same = lua_rawequal(L, -1, 2);
    lua_pop(L, 1);
    if (same) return last + 1;
  }
  lua_pushvalue(L, 2);
  const bool known = lua_rawget(L, lua_upvalueindex(4)) == LUA_TNUMBER;
  const lua_Integer place = known ? lua_tointeger(L, -1) : 0;
  lua_pop(L, 1);
  if (known && !is_float) return place + 1;
  check_key_as_lua(L);
  return (known ? place : sorted_place(L)) + 1;
}

// Refuses a first argument that is no table as Lua's next does. Called under a name (a local,
// a field), luaL_typeerror says that name; called under none (pcall(f)), Lua names a function by
// the global holding it, and this iterator is held by none: Lua's would be 'next' (found by a
// probe: the sandbox's said '?').
int refuse_as_next(lua_State* L) {
  lua_Debug ar;
  if (!lua_getstack(L, 0, &ar) || !lua_getinfo(L, "n", &ar) || ar.name != nullptr)
    return luaL_typeerror(L, 1, "table");
  const char* type = luaL_getmetafield(L, 1, "__name") == LUA_TSTRING ? lua_tostring(L, -1)
                     : lua_type(L, 1) == LUA_TLIGHTUSERDATA          ? "light userdata"
                                                                       : luaL_typename(L, 1);
  return luaL_error(L, "bad argument #1 to 'next' (table expected, got %s)", type);
}

// The iterator, called as Lua calls next: (t, k) gives the key after k and its value, whatever it
// returned before (found by a probe: it kept a cursor of its own, so a peek at the first key, or
// the iterator used twice, skipped keys). Upvalue 1 is the table, 2 its keys in order, 3 the
// position of the key it returned last (where the next call usually starts), 4 each key's
// position. A key whose value was cleared during the loop is passed over. Another table than
// pairs' is walked by Lua's next; anything else is refused as Lua's next refuses it, before the
// arguments are padded (found by a probe: a call with none said "got nil", not "got no value").
int sorted_next(lua_State* L) {
  if (!lua_rawequal(L, 1, lua_upvalueindex(1))) {
    if (lua_type(L, 1) != LUA_TTABLE) return refuse_as_next(L);
    lua_settop(L, 2);
    if (lua_next(L, 1)) return 2;
    lua_pushnil(L);
    return 1;
  }
  lua_settop(L, 2);
  lua_Integer at = lua_isnil(L, 2) ? 1 : position_after(L);
  for (;; ++at) {
    if (lua_rawgeti(L, lua_upvalueindex(2), at) == LUA_TNIL) return 1;  // the end: nil
    lua_pushvalue(L, -1);
    if (lua_rawget(L, lua_upvalueindex(1)) != LUA_TNIL) break;
    lua_pop(L, 2);
  }
  lua_pushinteger(L, at);
  lua_replace(L, lua_upvalueindex(3));
  return 2;
}

// Pushes the iterator over the keys of the table at `index` in order, with that table and nil, as
// Lua's pairs returns next, t, nil; charges the sort to the budget.
void push_sorted_iteration(lua_State* L, int index) {
  index = lua_absindex(L, index);
  lua_newtable(L);  // the keys as collected, which keeps them alive while they are sorted
  const int collected = lua_gettop(L);
  std::vector<SortKey> keys;
  lua_pushnil(L);
  while (lua_next(L, index)) {
    lua_pop(L, 1);
    const int slot = int(keys.size()) + 1;
    keys.push_back(describe_key(L, slot));
    lua_pushvalue(L, -1);
    lua_rawseti(L, collected, slot);
  }
  const double levels = keys.size() > 1 ? std::log2(double(keys.size())) : 1.0;
  charge_budget(L, uint64_t(double(keys.size()) * (1.0 + levels)) * kKeyCost, "pairs",
                "the table is too large to visit within the budget left");
  std::stable_sort(keys.begin(), keys.end(), key_below);
  lua_pushvalue(L, index);
  lua_createtable(L, int(keys.size()), 0);
  const int ordered = lua_gettop(L);
  lua_createtable(L, 0, int(keys.size()));
  const int positions = lua_gettop(L);
  for (size_t i = 0; i < keys.size(); ++i) {
    lua_rawgeti(L, collected, keys[i].slot);
    lua_pushvalue(L, -1);
    lua_rawseti(L, ordered, lua_Integer(i) + 1);
    lua_pushinteger(L, lua_Integer(i) + 1);
    lua_rawset(L, positions);
  }
  lua_pushinteger(L, 0);
  lua_insert(L, positions);  // upvalues: the table, the keys in order, 0, the positions
  lua_pushcclosure(L, sorted_next, 4);
  lua_replace(L, collected);
  lua_pushvalue(L, index);
  lua_pushnil(L);
}

// pairs(t): Lua's own (upvalue 1) for a value with __pairs or that is no table (or none); else
// the iterator above over t's keys in order, with t and nil, as Lua's returns next, t, nil.
int sorted_pairs(lua_State* L) {
  // Lua's own sees the arguments as given: `pairs()` is refused ("value expected"), not taken
  // for `pairs(nil)`.
  if (lua_type(L, 1) != LUA_TTABLE) return lua_tocfunction(L, lua_upvalueindex(1))(L);
  if (luaL_getmetafield(L, 1, "__pairs") != LUA_TNIL) {
    lua_settop(L, 1);
    return lua_tocfunction(L, lua_upvalueindex(1))(L);
  }
  lua_settop(L, 1);
  push_sorted_iteration(L, 1);
  return 3;
}

char view_data_key, view_reads_key;

// next(t, k): Lua's own (upvalue 1), except on a view, where the keys are its data's (found by a
// probe: next(history) gave the view's private key, so `next(history) == nil`, the usual test of
// an empty table, was false for an empty history); a key it gives counts as read.
int view_aware_next(lua_State* L) {
  const int args = lua_gettop(L);
  if (args < 1 || !lua_push_view_data(L, 1)) return lua_tocfunction(L, lua_upvalueindex(1))(L);
  const int data = lua_gettop(L);
  if (args >= 2) lua_pushvalue(L, 2); else lua_pushnil(L);
  if (!lua_next(L, data)) {
    lua_pushnil(L);
    return 1;
  }
  lua_view_note_read(L, 1, -2);
  return 2;
}

// rawget(t, k): Lua's own (upvalue 1), except on a view, whose fields are its data's: a library
// testing whether a scenario declares a parameter with rawget(params, name) sees what params.name
// would read. The key counts as read.
int view_aware_rawget(lua_State* L) {
  if (lua_gettop(L) < 2 || !lua_push_view_data(L, 1)) return lua_tocfunction(L, lua_upvalueindex(1))(L);
  lua_copy(L, lua_gettop(L), 3);  // the data at 3; what came after the key is dropped, as Lua's rawget drops it
  lua_settop(L, 3);
  lua_view_note_read(L, 1, 2);
  lua_pushvalue(L, 2);
  lua_rawget(L, 3);
  return 1;
}

// rawlen(t): Lua's own (upvalue 1), except on a view: its data's length, as # gives it.
int view_aware_rawlen(lua_State* L) {
  if (lua_gettop(L) < 1 || !lua_push_view_data(L, 1)) return lua_tocfunction(L, lua_upvalueindex(1))(L);
  lua_pushinteger(L, lua_Integer(lua_rawlen(L, -1)));
  return 1;
}

// rawset(t, k, v): Lua's own (upvalue 1), except on a view, where it does what `t[k] = v` does: the
// view's __newindex, its maker's rule for a write. A raw write is one that no metamethod of the
// table sees, and a view's metamethods are its table's raw access: generate's params take the
// value in their data (where pairs, next and # find it), a teacher's history refuses it. Before,
// the value landed on the view itself (found by a probe: rawset(history, 1, 3) passed the
// read-only history, and every later call of the teacher read 3 for its first entry).
int view_aware_rawset(lua_State* L) {
  if (lua_gettop(L) < 3 || !lua_push_view_data(L, 1)) return lua_tocfunction(L, lua_upvalueindex(1))(L);
  lua_settop(L, 3);
  if (luaL_getmetafield(L, 1, "__newindex") != LUA_TFUNCTION)
    return luaL_error(L, "a view without a rule for writes");  // every view's maker gives one
  lua_insert(L, 1);
  lua_pushvalue(L, 2);  // rawset returns its table
  lua_insert(L, 1);
  // Called from here, the rule's error would name no line (its caller is this C function): it is
  // raised again at the line that called rawset, as `t[k] = v` there would raise it.
  const int status = lua_pcall(L, 3, 0, 0);
  if (status == LUA_OK) return 1;
  if (status == LUA_ERRRUN && lua_type(L, -1) == LUA_TSTRING) {
    luaL_where(L, 1);
    lua_insert(L, -2);
    lua_concat(L, 2);
  }
  return lua_error(L);
}

// Replaces the global `name` by `wrapper`, which holds the original as its upvalue 1.
void wrap_global(lua_State* L, const char* name, lua_CFunction wrapper) {
  lua_getglobal(L, name);
  lua_pushcclosure(L, wrapper, 1);
  lua_setglobal(L, name);
}

}  // namespace

void install_pairs(lua_State* L) {
  wrap_global(L, "pairs", sorted_pairs);
  wrap_global(L, "next", view_aware_next);
  wrap_global(L, "rawget", view_aware_rawget);
  wrap_global(L, "rawlen", view_aware_rawlen);
  wrap_global(L, "rawset", view_aware_rawset);
}

}  // namespace sandbox_detail

void lua_new_view(lua_State* L, int data) {
  data = lua_absindex(L, data);
  lua_createtable(L, 0, 2);
  lua_pushlightuserdata(L, &sandbox_detail::view_data_key);
  lua_pushvalue(L, data);
  lua_rawset(L, -3);
}

bool lua_push_view_data(lua_State* L, int index) {
  if (lua_type(L, index) != LUA_TTABLE) return false;
  index = lua_absindex(L, index);
  lua_pushlightuserdata(L, &sandbox_detail::view_data_key);
  if (lua_rawget(L, index) == LUA_TTABLE) return true;
  lua_pop(L, 1);
  return false;
}

void lua_check_view_data(lua_State* L, const char* what) {
  if (!lua_push_view_data(L, 1)) luaL_argerror(L, 1, lua_pushfstring(L, "%s expected", what));  // a Lua string: the error jumps
}

int lua_view_len(lua_State* L) {
  lua_check_view_data(L, "a view");
  lua_pushinteger(L, lua_Integer(lua_rawlen(L, -1)));
  return 1;
}

namespace {

int read_only_index(lua_State* L) {
  lua_check_view_data(L, "a read-only table");
  lua_pushvalue(L, 2);
  lua_rawget(L, -2);
  return 1;
}

int read_only_newindex(lua_State* L) {
  const std::string name = lua_tostring(L, lua_upvalueindex(1));
  const std::string key = lua_type(L, 2) == LUA_TSTRING ? "'" + std::string(lua_tostring(L, 2)) + "'"
                                                        : luaL_tolstring(L, 2, nullptr);
  return raise_at_reader(L, name + " is read-only (its field " + key + " was set): copy what you need into a table "
                                "of your own");
}

int read_only_pairs(lua_State* L) {
  lua_check_view_data(L, "a read-only table");
  return lua_pairs_in_order(L, -1);
}

}  // namespace

void lua_make_read_only(lua_State* L, const char* name) {
  const int data = lua_gettop(L);
  lua_new_view(L, data);
  lua_createtable(L, 0, 5);
  lua_pushcfunction(L, read_only_index);
  lua_setfield(L, -2, "__index");
  lua_pushstring(L, name);
  lua_pushcclosure(L, read_only_newindex, 1);
  lua_setfield(L, -2, "__newindex");
  lua_pushcfunction(L, lua_view_len);
  lua_setfield(L, -2, "__len");
  lua_pushcfunction(L, read_only_pairs);
  lua_setfield(L, -2, "__pairs");
  lua_pushfstring(L, "%s (read-only)", name);
  lua_setfield(L, -2, "__metatable");  // getmetatable shows this; setmetatable is refused
  lua_setmetatable(L, -2);
  lua_replace(L, data);
}

void* lua_view_reads_key() { return &sandbox_detail::view_reads_key; }

void lua_view_note_read(lua_State* L, int view, int key) {
  if (lua_type(L, key) != LUA_TSTRING) return;  // a view's reads are of its named fields
  view = lua_absindex(L, view), key = lua_absindex(L, key);
  lua_pushlightuserdata(L, &sandbox_detail::view_reads_key);
  if (lua_rawget(L, view) == LUA_TTABLE) {
    lua_pushvalue(L, key);
    lua_pushboolean(L, 1);
    lua_rawset(L, -3);
  }
  lua_pop(L, 1);
}

int lua_pairs_in_order(lua_State* L, int index) {
  sandbox_detail::push_sorted_iteration(L, index);
  return 3;
}

}  // namespace roger
