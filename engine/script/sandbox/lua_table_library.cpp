// lua_table_library.cpp: table.insert, remove, move, concat, unpack and sort for sandboxed scripts. Each
// is a C loop over a range of elements between two VM instructions, out of the count hook's reach
// (table.move over 2^63 elements loops for ever), and each element can end the loop early: an
// __index or __newindex that raises, a value concat refuses. So they are ports of Lua 5.4's
// (ltablib.c: the same checks, results and messages) that charge the elements as they go, a block
// at a time ahead of the work: a call Lua refuses or answers before its loop costs nothing but its
// checks, one stopped after k elements about k elements' worth, a whole loop its whole length.
// table.sort is charged per comparison instead. table.pack stays Lua's (its work is its
// arguments, already on the stack).
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

// ---- table.sort: ltablib's quicksort, each comparison charged before it is made ----
//
// A comparison can make no VM instruction of its own (a comparator in C such as rawequal, an
// __lt in C, two numbers), so each is charged here. It is charged inside this port, in the frame
// of table.sort itself, and the comparator is called straight from that frame as Lua's sort
// calls it: a wrapper function between them (the sandbox had one) is a frame of its own, seen by
// error(msg, 2) in the comparator (it blamed the wrapper, not table.sort), by tracebacks ("[C]:
// in ?") and by the C stack's depth.

// Instructions per comparison through a comparator or an __lt (a call from C and a C __lt take
// about 80 ns, some 32 instructions' time).
constexpr uint64_t kComparisonCost = 32;
constexpr const char* kTooManyComparisons = "too many comparisons for the budget left";

using Index = unsigned int;  // ltablib's IdxT
constexpr Index kRandomLimit = 100u;  // ltablib's RANLIMIT: larger ranges may take a random pivot

// ltablib's l_randomizePivot takes the clock and the time: the order it gives equal elements (or
// an order function that is not one) would change from run to run, and a script's results with
// it. The sandbox is deterministic, so the "random" pivot is a hash of the range: as good against
// the unbalanced partitions it is there for, the same in every run.
unsigned int randomize_pivot(Index lo, Index up) {
  uint64_t h = (uint64_t(lo) << 32 | up) * 0x9E3779B97F4A7C15ull;
  h ^= h >> 29;
  return unsigned(h) | 1u;  // never 0, which means "the middle" to auxsort
}

// What a comparison by < of the values at a and b costs: two numbers one instruction, as Lua's <
// does; two strings one more per kBytesPerInstruction bytes they may share; anything else goes
// through an __lt metamethod, which may be a C function no hook counts: kComparisonCost.
uint64_t plain_comparison_cost(lua_State* L, int a, int b) {
  const int ta = lua_type(L, a), tb = lua_type(L, b);
  if (ta == LUA_TNUMBER && tb == LUA_TNUMBER) return 1;
  if (ta != LUA_TSTRING || tb != LUA_TSTRING) return kComparisonCost;
  size_t la = 0, lb = 0;
  lua_tolstring(L, a, &la), lua_tolstring(L, b, &lb);
  return 1 + std::min(la, lb) / kBytesPerInstruction;
}

// ltablib's sort_comp: whether the value at a sorts before the one at b (the order, argument 2,
// or <), charged first.
bool sort_less(lua_State* L, int a, int b) {
  if (lua_isnil(L, 2)) {
    charge_budget(L, plain_comparison_cost(L, a, b), "table.sort", kTooManyComparisons);
    return lua_compare(L, a, b, LUA_OPLT);
  }
  charge_budget(L, kComparisonCost, "table.sort", kTooManyComparisons);
  lua_pushvalue(L, 2);
  lua_pushvalue(L, a - 1);  // -1 for the function
  lua_pushvalue(L, b - 2);  // -2 for the function and a
  lua_call(L, 2, 1);
  const bool less = lua_toboolean(L, -1);
  lua_pop(L, 1);
  return less;
}

// ltablib's set2: t[i] = top, t[j] = the value below it.
void set2(lua_State* L, Index i, Index j) {
  lua_seti(L, 1, i);
  lua_seti(L, 1, j);
}

// ltablib's partition of [lo, up] around the pivot P at the top of the stack (a[up - 1] == P):
// returns P's place.
Index partition(lua_State* L, Index lo, Index up) {
  Index i = lo, j = up - 1;
  for (;;) {
    while ((void)lua_geti(L, 1, ++i), sort_less(L, -1, -2)) {  // a[i] < P
      if (i == up - 1) luaL_error(L, "invalid order function for sorting");
      lua_pop(L, 1);
    }
    while ((void)lua_geti(L, 1, --j), sort_less(L, -3, -1)) {  // P < a[j]
      if (j < i) luaL_error(L, "invalid order function for sorting");
      lua_pop(L, 1);
    }
    if (j < i) {
      lua_pop(L, 1);
      set2(L, up - 1, i);
      return i;
    }
    set2(L, i, j);
  }
}

// ltablib's choosePivot: an element in the middle half of [lo, up], chosen by rnd.
Index choose_pivot(Index lo, Index up, unsigned int rnd) {
  const Index r4 = (up - lo) / 4;
  return rnd % (r4 * 2) + (lo + r4);
}

// auxsort's first steps: orders a[lo] and a[up], then a[p] between them.
void order_three(lua_State* L, Index lo, Index p, Index up) {
  lua_geti(L, 1, p);
  lua_geti(L, 1, lo);
  if (sort_less(L, -2, -1)) {  // a[p] < a[lo]
    set2(L, p, lo);
    return;
  }
  lua_pop(L, 1);
  lua_geti(L, 1, up);
  if (sort_less(L, -1, -2)) set2(L, p, up); else lua_pop(L, 2);  // a[up] < a[p]
}

// ltablib's auxsort: sorts [lo, up], recursing into the smaller part and looping on the larger.
void auxsort(lua_State* L, Index lo, Index up, unsigned int rnd) {
  while (lo < up) {
    lua_geti(L, 1, lo);
    lua_geti(L, 1, up);
    if (sort_less(L, -1, -2)) set2(L, lo, up); else lua_pop(L, 2);  // a[up] < a[lo]
    if (up - lo == 1) return;
    Index p = (up - lo < kRandomLimit || rnd == 0) ? (lo + up) / 2 : choose_pivot(lo, up, rnd);
    order_three(L, lo, p, up);
    if (up - lo == 2) return;
    lua_geti(L, 1, p);  // the pivot P, kept on the stack and swapped with a[up - 1]
    lua_pushvalue(L, -1);
    lua_geti(L, 1, up - 1);
    set2(L, p, up - 1);
    p = partition(L, lo, up);
    Index n;
    if (p - lo < up - p) {
      auxsort(L, lo, p - 1, rnd);
      n = p - lo;
      lo = p + 1;
    } else {
      auxsort(L, p + 1, up, rnd);
      n = up - p;
      up = p - 1;
    }
    if ((up - lo) / 128 > n) rnd = randomize_pivot(lo, up);  // too unbalanced: a new pivot
  }
}

// table.sort(t [, comp]).
int table_sort(lua_State* L) {
  const lua_Integer n = length_of(L, kRead | kWrite);
  if (n > 1) {
    luaL_argcheck(L, n < INT_MAX, 1, "array too big");
    if (!lua_isnoneornil(L, 2)) luaL_checktype(L, 2, LUA_TFUNCTION);
    lua_settop(L, 2);
    auxsort(L, 1, Index(n), 0);
  }
  return 0;
}

}  // namespace

void install_table_library(lua_State* L) {
  const luaL_Reg functions[] = {{"insert", table_insert},
                                {"remove", table_remove},
                                {"move", table_move},
                                {"concat", table_concat},
                                {"unpack", table_unpack},
                                {"sort", table_sort}};
  lua_getglobal(L, LUA_TABLIBNAME);
  for (const auto& f : functions) {
    lua_pushcfunction(L, f.func);
    lua_setfield(L, -2, f.name);
  }
  lua_pop(L, 1);
}

}  // namespace sandbox_detail
}  // namespace roger
