// lua_table_library.cpp: table.insert, remove, move, concat and unpack for sandboxed scripts. Each
// is a C loop over a range of elements between two VM instructions, out of the count hook's reach
// (table.move over 2^63 elements loops for ever), and each element can end the loop early: an
// __index or __newindex that raises, a value concat refuses. So they are ports of Lua 5.4's
// (ltablib.c: the same checks, results and messages) that charge the elements as they go, a block
// at a time ahead of the work: a call Lua refuses or answers before its loop costs nothing but its
// checks, one stopped after k elements about k elements' worth, a whole loop its whole length.
// table.sort and table.pack stay Lua's (sort's comparisons are counted in lua_sandbox_costs.cpp;
// pack's work is its arguments, already on the stack).
#include <climits>
#include <cstdint>
#include <algorithm>

#include <lua.hpp>

#include "script/sandbox/lua_sandbox_internal.h"

namespace roger {
namespace sandbox_detail {
namespace {

constexpr uint64_t kElementCost = 8;  // instructions per element read or moved (20-30 ns of C)
constexpr uint64_t kBlock = 256;      // elements charged at a time

// Charges the `total` elements of one loop as it goes: before each block of kBlock elements (or
// what is left of the loop, if less) the block's cost.
class ElementCharge {
 public:
  ElementCharge(lua_State* L, const char* what, uint64_t total) : L_(L), what_(what), left_(total) {}
  // Before each element.
  void step() {
    if (ahead_ == 0) {
      ahead_ = std::min(kBlock, left_);
      left_ -= ahead_;
      charge_budget(L_, ahead_ * kElementCost, what_, "the call asks for more work than the budget has left");
    }
    --ahead_;
  }

 private:
  lua_State* L_;
  const char* what_;
  uint64_t left_;
  uint64_t ahead_ = 0;  // elements charged and not yet done
};

// The elements from `from` to `to` (0 when empty); the whole range of integers saturates.
uint64_t span(lua_Integer from, lua_Integer to) {
  if (from > to) return 0;
  const uint64_t gaps = uint64_t(lua_Unsigned(to) - lua_Unsigned(from));
  return gaps == UINT64_MAX ? UINT64_MAX : gaps + 1;
}

// What a value must offer to stand for a table (ltablib's TAB_R, TAB_W, TAB_L).
constexpr int kRead = 1, kWrite = 2, kLength = 4;

// Whether the metatable below `n` - 1 pushed values has field `key` (pushes the field).
bool has_field(lua_State* L, const char* key, int n) {
  lua_pushstring(L, key);
  return lua_rawget(L, -n) != LUA_TNIL;
}

// ltablib's checktab: argument `arg` is a table, or has a metatable with the metamethods `what` needs.
void check_table(lua_State* L, int arg, int what) {
  if (lua_type(L, arg) == LUA_TTABLE) return;
  int n = 1;  // values to pop
  if (lua_getmetatable(L, arg) && (!(what & kRead) || has_field(L, "__index", ++n)) &&
      (!(what & kWrite) || has_field(L, "__newindex", ++n)) && (!(what & kLength) || has_field(L, "__len", ++n)))
    lua_pop(L, n);
  else
    luaL_checktype(L, arg, LUA_TTABLE);  // raises Lua's message
}

// ltablib's aux_getn: checks argument 1 and returns its length (its __len when it has one).
lua_Integer length_of(lua_State* L, int what) {
  check_table(L, 1, what | kLength);
  return luaL_len(L, 1);
}

// table.insert(t, [pos,] value).
int table_insert(lua_State* L) {
  const lua_Integer e = lua_Integer(lua_Unsigned(length_of(L, kRead | kWrite)) + 1u);  // first empty element
  lua_Integer pos;
  switch (lua_gettop(L)) {
    case 2:
      pos = e;
      break;
    case 3: {
      pos = luaL_checkinteger(L, 2);
      luaL_argcheck(L, lua_Unsigned(pos) - 1u < lua_Unsigned(e), 2, "position out of bounds");
      ElementCharge charge(L, "table.insert", e > pos ? lua_Unsigned(e) - lua_Unsigned(pos) : 0);
      for (lua_Integer i = e; i > pos; i--) {  // move up elements
        charge.step();
        lua_geti(L, 1, i - 1);
        lua_seti(L, 1, i);
      }
      break;
    }
    default:
      return luaL_error(L, "wrong number of arguments to 'insert'");
  }
  lua_seti(L, 1, pos);
  return 0;
}

// table.remove(t [, pos]).
int table_remove(lua_State* L) {
  const lua_Integer size = length_of(L, kRead | kWrite);
  lua_Integer pos = luaL_optinteger(L, 2, size);
  if (pos != size)  // a position given: in [1, size + 1]
    luaL_argcheck(L, lua_Unsigned(pos) - 1u <= lua_Unsigned(size), 1, "position out of bounds");
  lua_geti(L, 1, pos);  // the result
  ElementCharge charge(L, "table.remove", pos < size ? lua_Unsigned(size) - lua_Unsigned(pos) : 0);
  for (; pos < size; pos++) {
    charge.step();
    lua_geti(L, 1, pos + 1);
    lua_seti(L, 1, pos);
  }
  lua_pushnil(L);
  lua_seti(L, 1, pos);
  return 1;
}

// table.move(a1, f, e, t [, a2]): increasing order when the ranges allow it, as Lua's.
int table_move(lua_State* L) {
  const lua_Integer f = luaL_checkinteger(L, 2);
  const lua_Integer e = luaL_checkinteger(L, 3);
  const lua_Integer t = luaL_checkinteger(L, 4);
  const int tt = !lua_isnoneornil(L, 5) ? 5 : 1;  // the destination
  check_table(L, 1, kRead);
  check_table(L, tt, kWrite);
  if (e >= f) {
    luaL_argcheck(L, f > 0 || e < LUA_MAXINTEGER + f, 3, "too many elements to move");
    const lua_Integer n = e - f + 1;
    luaL_argcheck(L, t <= LUA_MAXINTEGER - n + 1, 4, "destination wrap around");
    ElementCharge charge(L, "table.move", uint64_t(n));
    if (t > e || t <= f || (tt != 1 && !lua_compare(L, 1, tt, LUA_OPEQ))) {
      for (lua_Integer i = 0; i < n; i++) {
        charge.step();
        lua_geti(L, 1, f + i);
        lua_seti(L, tt, t + i);
      }
    } else {
      for (lua_Integer i = n - 1; i >= 0; i--) {
        charge.step();
        lua_geti(L, 1, f + i);
        lua_seti(L, tt, t + i);
      }
    }
  }
  lua_pushvalue(L, tt);
  return 1;
}

// Adds t[i] to the buffer of table.concat, refusing what is not a string or a number.
void add_field(lua_State* L, luaL_Buffer* b, lua_Integer i) {
  lua_geti(L, 1, i);
  if (!lua_isstring(L, -1))
    luaL_error(L, "invalid value (%s) at index %I in table for 'concat'", luaL_typename(L, -1), static_cast<LUAI_UACINT>(i));
  luaL_addvalue(b);
}

// table.concat(t [, sep [, i [, j]]]).
int table_concat(lua_State* L) {
  lua_Integer last = length_of(L, kRead);
  size_t lsep;
  const char* sep = luaL_optlstring(L, 2, "", &lsep);
  lua_Integer i = luaL_optinteger(L, 3, 1);
  last = luaL_optinteger(L, 4, last);
  ElementCharge charge(L, "table.concat", span(i, last));
  luaL_Buffer b;
  luaL_buffinit(L, &b);
  for (; i < last; i++) {
    charge.step();
    add_field(L, &b, i);
    luaL_addlstring(&b, sep, lsep);
  }
  if (i == last) {  // the last value, when the range was not empty
    charge.step();
    add_field(L, &b, i);
  }
  luaL_pushresult(&b);
  return 1;
}

// table.unpack(t [, i [, j]]): refuses more results than the stack can take before any work.
int table_unpack(lua_State* L) {
  lua_Integer i = luaL_optinteger(L, 2, 1);
  const lua_Integer e = lua_isnoneornil(L, 3) ? luaL_len(L, 1) : luaL_checkinteger(L, 3);
  if (i > e) return 0;  // an empty range
  lua_Unsigned n = lua_Unsigned(e) - lua_Unsigned(i);  // elements minus 1 (no overflow)
  if (n >= lua_Unsigned(INT_MAX) || !lua_checkstack(L, int(++n))) return luaL_error(L, "too many results to unpack");
  ElementCharge charge(L, "table.unpack", n);
  for (; i < e; i++) {  // t[i .. e - 1] (e itself could overflow i)
    charge.step();
    lua_geti(L, 1, i);
  }
  charge.step();
  lua_geti(L, 1, e);
  return int(n);
}

}  // namespace

void install_table_library(lua_State* L) {
  const luaL_Reg functions[] = {{"insert", table_insert},
                                {"remove", table_remove},
                                {"move", table_move},
                                {"concat", table_concat},
                                {"unpack", table_unpack}};
  lua_getglobal(L, LUA_TABLIBNAME);
  for (const auto& f : functions) {
    lua_pushcfunction(L, f.func);
    lua_setfield(L, -2, f.name);
  }
  lua_pop(L, 1);
}

}  // namespace sandbox_detail
}  // namespace roger
