// lua_sandbox_costs.cpp: the library functions whose work grows with their arguments, charged to
// the call's instruction budget. A C function runs between two VM instructions, out of the count
// hook's reach: string.rep("", 2^62) loops for ever allocating nothing, table.move over a huge
// range too, and table.concat, unpack, insert or sort over a big table cost thousands of steps for
// one instruction, again and again. Each one here first charges the work its arguments ask for
// (rates below), then runs Lua's own function in the same frame, so results, messages and their
// file:line are Lua's. A table's __len, when it has one, is called twice (here and by Lua's).
#include <algorithm>
#include <cstdint>

#include <lua.hpp>

#include "script/sandbox/lua_sandbox_internal.h"

namespace roger {
namespace sandbox_detail {
namespace {

constexpr const char* kTooMuch = "the call asks for more work than the budget has left";
// What C work costs in instructions, measured against a plain Lua loop (4-5 ns an instruction
// here) and rounded up so that each stops no later than the loop: a byte scanned takes 2-6 ns, a
// table element read or moved 20-30 ns, a comparison through a closure and a C __lt 80 ns.
constexpr uint64_t kBytesPerUnit = 1;      // bytes scanned per instruction charged
constexpr uint64_t kElementCost = 8;       // instructions charged per table element or format item
constexpr uint64_t kComparisonCost = 32;   // instructions charged per comparison of table.sort

// The count of integers from `from` to `to` (0 when empty), saturating: the whole range of
// integers holds 2^64 of them, one more than a uint64_t can say.
uint64_t span(lua_Integer from, lua_Integer to) {
  if (from > to) return 0;
  const uint64_t gaps = uint64_t(lua_Unsigned(to) - lua_Unsigned(from));
  return gaps == UINT64_MAX ? UINT64_MAX : gaps + 1;
}

// The instructions charged for n elements, saturating (a range can hold 2^64 of them).
uint64_t elements(uint64_t n) { return n > UINT64_MAX / kElementCost ? UINT64_MAX : n * kElementCost; }

// A 1-based string position from a relative one, as lstrlib's posrelatI.
lua_Integer string_start(lua_Integer pos, size_t len) {
  if (pos > 0) return pos;
  if (pos == 0 || pos < -lua_Integer(len)) return 1;
  return lua_Integer(len) + pos + 1;
}

// An end position from a relative one, as lstrlib's getendpos.
lua_Integer string_end(lua_Integer pos, size_t len) {
  if (pos > lua_Integer(len)) return lua_Integer(len);
  if (pos >= 0) return pos;
  if (pos < -lua_Integer(len)) return 0;
  return lua_Integer(len) + pos + 1;
}

// Argument 1 of a table function: a table, or a value with a metatable (Lua's checks the rest).
void check_table(lua_State* L) {
  if (lua_type(L, 1) == LUA_TTABLE) return;
  if (!lua_getmetatable(L, 1)) luaL_checktype(L, 1, LUA_TTABLE);
  lua_pop(L, 1);
}

// The length ltablib uses for the table at `arg` (its __len when it has one).
lua_Integer table_length(lua_State* L, int arg) {
  if (lua_type(L, arg) == LUA_TTABLE && !luaL_getmetafield(L, arg, "__len")) return lua_Integer(lua_rawlen(L, arg));
  if (lua_type(L, arg) == LUA_TTABLE) lua_pop(L, 1);
  return luaL_len(L, arg);
}

// The range [from, to] a table function reads: arguments at `first` and first + 1, defaulting
// to 1 and the table's length.
uint64_t table_range(lua_State* L, int first) {
  const lua_Integer from = luaL_optinteger(L, first, 1);
  const lua_Integer to = lua_isnoneornil(L, first + 1) ? table_length(L, 1) : luaL_checkinteger(L, first + 1);
  return span(from, to);
}

// Bytes from position i (argument at `first`, default 1) to j (next, default -1) of string 1.
uint64_t string_range(lua_State* L, int first, lua_Integer default_end) {
  size_t len;
  luaL_checklstring(L, 1, &len);
  const lua_Integer i = string_start(luaL_optinteger(L, first, 1), len);
  return span(i, string_end(luaL_optinteger(L, first + 1, default_end), len));
}

// What each function's arguments ask for, in instructions.
uint64_t cost_rep(lua_State* L) {
  size_t l, lsep;
  luaL_checklstring(L, 1, &l);
  const lua_Integer n = luaL_checkinteger(L, 2);
  luaL_optlstring(L, 3, "", &lsep);
  if (n <= 0) return 0;
  if (l + lsep == 0) return uint64_t(n);  // Lua's loop runs n times even for empty strings
  // A result over the memory cap is refused before the loop (Lua allocates it first).
  const double bytes = double(n) * double(l + lsep);
  return bytes > double(impl_of(L).limits.memory_bytes) ? 0 : uint64_t(n) / kBytesPerInstruction;
}
uint64_t cost_byte(lua_State* L) {
  size_t len;
  luaL_checklstring(L, 1, &len);
  const lua_Integer i = string_start(luaL_optinteger(L, 2, 1), len);
  return span(i, string_end(luaL_optinteger(L, 3, i), len));
}
uint64_t cost_arguments(lua_State* L) { return elements(uint64_t(lua_gettop(L))); }
uint64_t cost_format_string(lua_State* L) {  // pack, packsize, unpack: one step per format item
  size_t len;
  luaL_checklstring(L, 1, &len);
  return elements(len);
}
uint64_t cost_concat(lua_State* L) {
  check_table(L);
  luaL_optstring(L, 2, "");
  return elements(table_range(L, 3));
}
uint64_t cost_unpack(lua_State* L) { return elements(table_range(L, 2)); }
uint64_t cost_move(lua_State* L) {
  check_table(L);
  const lua_Integer from = luaL_checkinteger(L, 2), to = luaL_checkinteger(L, 3);
  luaL_checkinteger(L, 4);
  return elements(span(from, to));
}
uint64_t cost_shift(lua_State* L) {  // table.insert and table.remove move up to #t elements
  check_table(L);
  return elements(uint64_t(std::max<lua_Integer>(0, table_length(L, 1))));
}
uint64_t cost_utf8_len(lua_State* L) { return string_range(L, 2, -1) / kBytesPerUnit; }
uint64_t cost_utf8_offset(lua_State* L) {
  size_t len;
  luaL_checklstring(L, 1, &len);
  const lua_Integer n = luaL_checkinteger(L, 2);
  return std::min<uint64_t>(len, n < 0 ? uint64_t(-(n + 1)) + 1 : uint64_t(n)) + 1;
}
uint64_t cost_tonumber(lua_State* L) {
  if (!lua_isnoneornil(L, 2)) {  // checked here, as Lua's would, so its messages stay Lua's
    const lua_Integer base = luaL_checkinteger(L, 2);
    luaL_checktype(L, 1, LUA_TSTRING);
    luaL_argcheck(L, 2 <= base && base <= 36, 2, "base out of range");
  }
  return lua_type(L, 1) == LUA_TSTRING ? uint64_t(lua_rawlen(L, 1)) / kBytesPerUnit : 0;
}
// A collection, a step, or a switch of mode (which collects or marks everything) walks the heap.
uint64_t cost_collectgarbage(lua_State* L) {
  static const char* const options[] = {"stop", "restart", "collect", "count", "step", "setpause",
                                        "setstepmul", "isrunning", "generational", "incremental", nullptr};
  const int o = luaL_checkoption(L, 1, "collect", options);
  const bool walks = o == 2 || o == 4 || o == 8 || o == 9;
  return walks ? impl_of(L).memory_used / kBytesPerUnit : 0;
}

using Cost = uint64_t (*)(lua_State*);

// The charged function: upvalue 1 is Lua's (a light C function, run in this very frame so that
// its argument errors and file:line are as before), upvalue 2 its name for the budget message.
template <Cost cost>
int charged(lua_State* L) {
  charge_budget(L, cost(L), static_cast<const char*>(lua_touserdata(L, lua_upvalueindex(2))), kTooMuch);
  return lua_tocfunction(L, lua_upvalueindex(1))(L);
}

// table.sort's comparisons, kComparisonCost instructions each (a comparison through this closure
// and a metamethod takes as long): calls the script's comparator (upvalue 1) or <.
int counted_less(lua_State* L) {
  charge_budget(L, kComparisonCost, "table.sort", "too many comparisons for the budget left");
  if (lua_isnil(L, lua_upvalueindex(1))) {
    lua_pushboolean(L, lua_compare(L, 1, 2, LUA_OPLT));
    return 1;
  }
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  lua_call(L, 2, 1);
  return 1;
}

// table.sort(t [, comp]): Lua's, with every comparison counted (a bad comparator, or __lt given
// as a C function, makes no VM instruction of its own).
int charged_sort(lua_State* L) {
  check_table(L);
  if (!lua_isnoneornil(L, 2)) luaL_checktype(L, 2, LUA_TFUNCTION);
  lua_settop(L, 2);
  lua_pushvalue(L, 2);
  lua_pushcclosure(L, counted_less, 1);
  lua_replace(L, 2);
  return lua_tocfunction(L, lua_upvalueindex(1))(L);
}

// The iterator utf8.codes returns: Lua's (upvalue 1), charged for the bytes it skipped.
int charged_codes_step(lua_State* L) {
  const lua_Integer from = lua_tointeger(L, 2);
  const int n = lua_tocfunction(L, lua_upvalueindex(1))(L);
  const lua_Integer to = n > 0 ? lua_tointeger(L, -n) : lua_Integer(luaL_len(L, 1));
  charge_budget(L, 1 + span(from, to) / kBytesPerUnit, "utf8.codes", kTooMuch);
  return n;
}

// utf8.codes(s): Lua's, with its iterator charged.
int charged_codes(lua_State* L) {
  const int n = lua_tocfunction(L, lua_upvalueindex(1))(L);  // iterator, s, 0
  lua_pushvalue(L, -n);
  lua_pushcclosure(L, charged_codes_step, 1);
  lua_replace(L, -n - 1);
  return n;
}

struct Charged {
  const char* library;
  const char* name;
  const char* shown;
  lua_CFunction function;
};

const Charged kCharged[] = {
    {"string", "rep", "string.rep", charged<cost_rep>},
    {"string", "byte", "string.byte", charged<cost_byte>},
    {"string", "char", "string.char", charged<cost_arguments>},
    {"string", "pack", "string.pack", charged<cost_format_string>},
    {"string", "packsize", "string.packsize", charged<cost_format_string>},
    {"string", "unpack", "string.unpack", charged<cost_format_string>},
    {"table", "concat", "table.concat", charged<cost_concat>},
    {"table", "unpack", "table.unpack", charged<cost_unpack>},
    {"table", "move", "table.move", charged<cost_move>},
    {"table", "insert", "table.insert", charged<cost_shift>},
    {"table", "remove", "table.remove", charged<cost_shift>},
    {"table", "sort", "table.sort", charged_sort},
    {"utf8", "char", "utf8.char", charged<cost_arguments>},
    {"utf8", "len", "utf8.len", charged<cost_utf8_len>},
    {"utf8", "codepoint", "utf8.codepoint", charged<cost_byte>},
    {"utf8", "offset", "utf8.offset", charged<cost_utf8_offset>},
    {"utf8", "codes", "utf8.codes", charged_codes},
    {nullptr, "tonumber", "tonumber", charged<cost_tonumber>},
    {nullptr, "collectgarbage", "collectgarbage", charged<cost_collectgarbage>},
};

}  // namespace

// Replaces each library function whose work grows with its arguments by its charged version
// (Lua's is kept only as the replacement's upvalue, out of scripts' reach).
void install_charges(lua_State* L) {
  for (const Charged& c : kCharged) {
    if (c.library) lua_getglobal(L, c.library); else lua_pushglobaltable(L);
    lua_getfield(L, -1, c.name);
    lua_pushlightuserdata(L, const_cast<char*>(c.shown));
    lua_pushcclosure(L, c.function, 2);
    lua_setfield(L, -2, c.name);
    lua_pop(L, 1);
  }
}

}  // namespace sandbox_detail
}  // namespace roger
