// lua_sandbox_costs.cpp: the library functions whose work grows with their arguments, charged to
// the call's instruction budget. A C function runs between two VM instructions, out of the count
// hook's reach: string.rep("", 2^62) loops for ever allocating nothing, and string.byte, utf8.len
// or tonumber over a long string cost millions of steps for one instruction, again and again.
// Each one here first charges the work Lua's function will do with its arguments (rates below):
// nothing for a call Lua refuses or answers before its loop, else the loop up to where Lua ends it
// (the first invalid UTF-8 sequence or digit, say). Then Lua's own function runs in the same
// frame, so results, messages and their file:line are Lua's. The table functions that loop over
// elements, table.sort among them, are charged as they go instead (lua_table_library.cpp).
#include <cctype>
#include <climits>
#include <cstdint>
#include <cstring>

#include <lua.hpp>

#include "script/sandbox/lua_sandbox_internal.h"

namespace roger {
namespace sandbox_detail {
namespace {

constexpr const char* kTooMuch = "the call asks for more work than the budget has left";
// What C work costs in instructions, measured against a plain Lua loop (4-5 ns an instruction
// here) and rounded up so that each stops no later than the loop: a byte scanned takes 2-6 ns, a
// value pushed or a format item 20-30 ns.
constexpr uint64_t kBytesPerUnit = 1;      // bytes scanned per instruction charged
constexpr uint64_t kElementCost = 8;       // instructions charged per argument or format item

// The instructions charged for n elements, saturating.
uint64_t elements(uint64_t n) { return n > UINT64_MAX / kElementCost ? UINT64_MAX : n * kElementCost; }

// Each cost function below reads the arguments as Lua's function will (raising its messages for
// bad ones, in the same frame) and returns the work that function will do: 0 when Lua refuses the
// call or answers it before its loop, else the length of the loop, up to where Lua stops it.

// lstrlib's posrelatI: a 1-based start position, clipped to 1.
size_t string_start(lua_Integer pos, size_t len) {
  if (pos > 0) return size_t(pos);
  if (pos == 0 || pos < -lua_Integer(len)) return 1;
  return len + size_t(pos) + 1;
}

// lstrlib's getendpos: an end position, clipped to [0, len].
size_t string_end(lua_Integer pos, size_t len) {
  if (pos > lua_Integer(len)) return len;
  if (pos >= 0) return size_t(pos);
  if (pos < -lua_Integer(len)) return 0;
  return len + size_t(pos) + 1;
}

// Whether `n` values fit on the stack (Lua refuses more before pushing any; growing it here is
// what Lua's own check would do next).
bool stack_takes(lua_State* L, size_t n) { return n < size_t(INT_MAX) && lua_checkstack(L, int(n)); }

// string.byte(s [, i [, j]]): one value pushed per byte, unless Lua refuses the slice.
uint64_t cost_byte(lua_State* L) {
  size_t len;
  luaL_checklstring(L, 1, &len);
  const lua_Integer pi = luaL_optinteger(L, 2, 1);
  const size_t posi = string_start(pi, len), pose = string_end(luaL_optinteger(L, 3, pi), len);
  if (posi > pose || !stack_takes(L, pose - posi + 1)) return 0;
  return pose - posi + 1;
}

// The arguments string.char (max 255) or utf8.char (max 0x7FFFFFFF) converts before the first it
// refuses, that one included.
template <lua_Unsigned kMax>
uint64_t cost_codes(lua_State* L) {
  const int n = lua_gettop(L);
  for (int i = 1; i <= n; ++i) {
    int ok = 0;
    const lua_Unsigned code = lua_Unsigned(lua_tointegerx(L, i, &ok));
    if (!ok || code > kMax) return elements(uint64_t(i));
  }
  return elements(uint64_t(n));
}

// string.pack, packsize, unpack: one step per format item, and an item takes at least a byte of
// the format (read up to its first zero, as Lua reads it).
uint64_t cost_format(lua_State* L) { return elements(std::strlen(luaL_checkstring(L, 1))); }

// string.upper, lower and reverse: a loop over the string's bytes, a byte at a time (about 1 ns a
// byte here; the allocator alone charged them a sixteenth of that, and a loop of upper over a
// long string ran up to 7 times as long as a plain loop before its budget was spent).
uint64_t cost_string_bytes(lua_State* L) {
  size_t len;
  luaL_checklstring(L, 1, &len);
  return len / kBytesPerUnit;
}

// What %q costs for a string: a byte scanned per byte, and an element more for each control
// character, which Lua's addquoted writes with snprintf ("\\0", "\\031") where the rest are copied
// a byte at a time.
uint64_t quoted_cost(lua_State* L, int arg) {
  size_t len;
  const char* s = lua_tolstring(L, arg, &len);  // a string already: nothing is converted
  uint64_t controls = 0;
  for (size_t k = 0; k < len; ++k) {
    const unsigned char c = static_cast<unsigned char>(s[k]);
    controls += c != '\n' && std::iscntrl(c);
  }
  return len / kBytesPerUnit + controls * (kElementCost - 1);
}

// string.format(f, ...): the format's bytes, an element per item, and for each %q of a string
// what quoting it costs (1.4 ns a byte here, 50 a control character, where %s copies with memcpy
// and is charged by the allocator). Only reads: an argument is never converted in place, and what
// Lua refuses (a bad conversion, a missing value) it refuses after this, as before.
uint64_t cost_string_format(lua_State* L) {
  size_t length;
  const char* p = luaL_checklstring(L, 1, &length);
  const char* const end = p + length;
  uint64_t items = 0, quoted = 0;
  int arg = 1;
  while (p < end) {
    if (*p++ != '%') continue;
    if (p < end && *p == '%') {
      ++p;
      continue;
    }
    ++arg, ++items;
    const char* const spec = p;
    while (p < end && *p != '\0' && std::strchr("-+ #0123456789.", *p)) ++p;  // flags, width, precision
    // Lua refuses %q with modifiers before quoting anything.
    if (p == spec && p < end && *p == 'q' && lua_type(L, arg) == LUA_TSTRING) quoted += quoted_cost(L, arg);
  }
  const uint64_t bytes = uint64_t(length) / kBytesPerUnit + quoted;
  return elements(items) > UINT64_MAX - bytes ? UINT64_MAX : elements(items) + bytes;
}

// string.unpack refuses a start position past the data before reading its format.
uint64_t cost_unpack(lua_State* L) {
  const uint64_t items = cost_format(L);
  size_t ld;
  luaL_checklstring(L, 2, &ld);
  return string_start(luaL_optinteger(L, 3, 1), ld) - 1 <= ld ? items : 0;
}

// lutf8lib's u_posrelat.
lua_Integer utf8_position(lua_Integer pos, size_t len) {
  if (pos >= 0) return pos;
  if (0u - size_t(pos) > len) return 0;
  return lua_Integer(len) + pos + 1;
}

// lutf8lib's utf8_decode: where the sequence at s ends, or null when it is not valid UTF-8.
const char* utf8_next(const char* s, bool strict) {
  static const uint32_t limits[] = {~uint32_t(0), 0x80, 0x800, 0x10000u, 0x200000u, 0x4000000u};
  unsigned c = static_cast<unsigned char>(s[0]);
  uint32_t res = 0;
  if (c < 0x80) return s + 1;
  int count = 0;
  for (; c & 0x40; c <<= 1) {
    const unsigned cc = static_cast<unsigned char>(s[++count]);
    if ((cc & 0xC0) != 0x80) return nullptr;
    res = (res << 6) | (cc & 0x3F);
  }
  res |= uint32_t(c & 0x7F) << (count * 5);
  if (count > 5 || res > 0x7FFFFFFFu || res < limits[count]) return nullptr;
  if (strict && (res > 0x10FFFFu || (0xD800u <= res && res <= 0xDFFFu))) return nullptr;
  return s + count + 1;
}

// The bytes Lua's utf8 decoding reads from position `from` (0-based) while sequences start
// before `to`, up to and including the first invalid one.
uint64_t utf8_scan(const char* s, lua_Integer from, lua_Integer to, bool strict) {
  lua_Integer at = from;
  while (at < to) {
    const char* next = utf8_next(s + at, strict);
    if (!next) return uint64_t(at - from) + 1;
    at = next - s;
  }
  return uint64_t(at - from);
}

// utf8.len(s [, i [, j [, lax]]]): decodes until j or the first invalid sequence.
uint64_t cost_utf8_len(lua_State* L) {
  size_t len;
  const char* s = luaL_checklstring(L, 1, &len);
  lua_Integer posi = utf8_position(luaL_optinteger(L, 2, 1), len);
  lua_Integer posj = utf8_position(luaL_optinteger(L, 3, -1), len);
  const bool strict = !lua_toboolean(L, 4);
  if (!(1 <= posi && --posi <= lua_Integer(len)) || !(--posj < lua_Integer(len))) return 0;  // Lua refuses
  return utf8_scan(s, posi, posj + 1, strict) / kBytesPerUnit;
}

// utf8.codepoint(s [, i [, j [, lax]]]): one value per sequence, until the first invalid one.
uint64_t cost_utf8_codepoint(lua_State* L) {
  size_t len;
  const char* s = luaL_checklstring(L, 1, &len);
  const lua_Integer posi = utf8_position(luaL_optinteger(L, 2, 1), len);
  const lua_Integer pose = utf8_position(luaL_optinteger(L, 3, posi), len);
  const bool strict = !lua_toboolean(L, 4);
  if (posi < 1 || pose > lua_Integer(len) || posi > pose || !stack_takes(L, size_t(pose - posi) + 1)) return 0;
  return utf8_scan(s, posi - 1, pose, strict) / kBytesPerUnit;
}

// utf8.offset(s, n [, i]): the bytes Lua steps over to find character n from i.
uint64_t cost_utf8_offset(lua_State* L) {
  size_t len;
  const char* s = luaL_checklstring(L, 1, &len);
  lua_Integer n = luaL_checkinteger(L, 2);
  lua_Integer posi = utf8_position(luaL_optinteger(L, 3, n >= 0 ? 1 : lua_Integer(len) + 1), len);
  if (!(1 <= posi && --posi <= lua_Integer(len))) return 0;  // Lua refuses the position
  auto cont = [&](lua_Integer p) { return (static_cast<unsigned char>(s[p]) & 0xC0) == 0x80; };
  const lua_Integer start = posi;
  if (n == 0) {
    while (posi > 0 && cont(posi)) posi--;
  } else if (cont(posi)) {
    return 0;  // Lua refuses a start inside a sequence
  } else if (n < 0) {
    for (; n < 0 && posi > 0; n++) do posi--; while (posi > 0 && cont(posi));
  } else {
    for (n--; n > 0 && posi < lua_Integer(len); n--) do posi++; while (cont(posi));
  }
  return uint64_t(posi > start ? posi - start : start - posi) / kBytesPerUnit + 1;
}

// tonumber(v [, base]). With a base, Lua reads the numeral up to its first invalid digit; without,
// the string up to its first zero byte, unless a 'n' (of "inf" or "nan") refuses it first.
uint64_t cost_tonumber(lua_State* L) {
  if (lua_isnoneornil(L, 2)) {
    if (lua_type(L, 1) != LUA_TSTRING) return 0;
    const char* s = lua_tostring(L, 1);
    const size_t special = std::strcspn(s, ".xXnN");
    return (s[special] == 'n' || s[special] == 'N' ? special : std::strlen(s)) / kBytesPerUnit;
  }
  const lua_Integer base = luaL_checkinteger(L, 2);  // checked here, as Lua's would, so its messages stay Lua's
  luaL_checktype(L, 1, LUA_TSTRING);
  luaL_argcheck(L, 2 <= base && base <= 36, 2, "base out of range");
  const char* s = lua_tostring(L, 1);
  constexpr const char* kSpaces = " \f\n\r\t\v";
  const char* p = s + std::strspn(s, kSpaces);
  if (*p == '-' || *p == '+') p++;
  for (; std::isalnum(static_cast<unsigned char>(*p)); p++) {
    const int c = static_cast<unsigned char>(*p);
    if ((std::isdigit(c) ? c - '0' : std::toupper(c) - 'A' + 10) >= base) return uint64_t(p - s) + 1;
  }
  return uint64_t(p + std::strspn(p, kSpaces) - s) / kBytesPerUnit;
}

// A collection (or a step, or a switch of mode, which may finish one) walks the heap: 0.2 ns a
// byte of small tables, 0.07 of long strings (plain lua5.4 here). Charged an instruction per 32
// bytes, a walk's units are allowed (50 ns each) eight times the time it takes; charged one per
// byte, five collections of a 20 MiB heap spent the whole budget (found by a probe: a script could
// not collect once it held 48 MiB, where plain Lua takes microseconds).
constexpr uint64_t kHeapBytesPerUnit = 32;

uint64_t cost_collectgarbage(lua_State* L) {
  static const char* const options[] = {"stop", "restart", "collect", "count", "step", "setpause",
                                        "setstepmul", "isrunning", "generational", "incremental", nullptr};
  const int o = luaL_checkoption(L, 1, "collect", options);
  const bool walks = o == 2 || o == 4 || o == 8 || o == 9;
  return walks ? impl_of(L).memory_used / kHeapBytesPerUnit : 0;
}

using Cost = uint64_t (*)(lua_State*);

// The charged function: upvalue 1 is Lua's (a light C function, run in this very frame so that
// its argument errors and file:line are as before), upvalue 2 its name for the budget message.
template <Cost cost>
int charged(lua_State* L) {
  charge_budget(L, cost(L), static_cast<const char*>(lua_touserdata(L, lua_upvalueindex(2))), kTooMuch);
  return lua_tocfunction(L, lua_upvalueindex(1))(L);
}

// string.rep(s, n [, sep]): Lua's loop runs n times, copying nothing when s and sep are empty;
// otherwise its result is allocated first (and charged by the allocator) unless Lua refuses it as
// too large or the memory cap does, so the copies are charged once it has returned.
int charged_rep(lua_State* L) {
  size_t l, lsep;
  luaL_checklstring(L, 1, &l);
  const lua_Integer n = luaL_checkinteger(L, 2);
  luaL_optlstring(L, 3, "", &lsep);
  const char* what = static_cast<const char*>(lua_touserdata(L, lua_upvalueindex(2)));
  if (n > 0 && l + lsep == 0) charge_budget(L, uint64_t(n), what, kTooMuch);
  const int results = lua_tocfunction(L, lua_upvalueindex(1))(L);
  if (n > 0 && l + lsep > 0) charge_budget(L, uint64_t(n) / kBytesPerInstruction, what, kTooMuch);
  return results;
}

// The iterator utf8.codes returns: Lua's (upvalue 1), charged for the continuation bytes it skips
// from the position it is given (none from a position past the string) and the sequence it reads.
int charged_codes_step(lua_State* L) {
  uint64_t cost = 1;
  if (lua_isstring(L, 1)) {
    size_t len;
    const char* s = lua_tolstring(L, 1, &len);
    for (lua_Unsigned n = lua_Unsigned(lua_tointeger(L, 2)); n < len && (static_cast<unsigned char>(s[n]) & 0xC0) == 0x80; ++n)
      ++cost;
  }
  charge_budget(L, cost / kBytesPerUnit, "utf8.codes", kTooMuch);
  return lua_tocfunction(L, lua_upvalueindex(1))(L);
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
    {"string", "rep", "string.rep", charged_rep},
    {"string", "byte", "string.byte", charged<cost_byte>},
    {"string", "char", "string.char", charged<cost_codes<0xFF>>},
    {"string", "pack", "string.pack", charged<cost_format>},
    {"string", "packsize", "string.packsize", charged<cost_format>},
    {"string", "unpack", "string.unpack", charged<cost_unpack>},
    {"string", "upper", "string.upper", charged<cost_string_bytes>},
    {"string", "lower", "string.lower", charged<cost_string_bytes>},
    {"string", "reverse", "string.reverse", charged<cost_string_bytes>},
    {"string", "format", "string.format", charged<cost_string_format>},
    {"utf8", "char", "utf8.char", charged<cost_codes<0x7FFFFFFF>>},
    {"utf8", "len", "utf8.len", charged<cost_utf8_len>},
    {"utf8", "codepoint", "utf8.codepoint", charged<cost_utf8_codepoint>},
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
