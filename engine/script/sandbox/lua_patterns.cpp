// lua_patterns.cpp: string.find, match, gmatch and gsub for sandboxed scripts. Lua's own are C
// loops that can backtrack for hours on one call (".-.-.-b" over a long subject), out of reach of
// the instruction budget's count hook, which fires only between VM instructions. These are a port
// of Lua 5.4's matcher (lstrlib.c: the same pattern language, results and messages) that counts
// its steps against the call's budget, and a plain find that runs in linear time.
#include <cctype>
#include <cstddef>
#include <cstring>

#include <lua.hpp>

#include "script/sandbox/lua_sandbox_internal.h"

namespace roger {
namespace sandbox_detail {
namespace {

constexpr int kMaxCaptures = 32;     // LUA_MAXCAPTURES
constexpr int kMaxDepth = 200;       // MAXCCALLS: recursion depth of one match
constexpr ptrdiff_t kUnfinished = -1;
constexpr ptrdiff_t kPosition = -2;
constexpr char kEsc = '%';
constexpr const char* kSpecials = "^$*+?.([%-";
constexpr uint64_t kChargeEvery = 1024;  // steps counted before they are charged to the budget
constexpr uint64_t kStepCost = 2;        // instructions a step costs (it takes about 9 ns)

struct MatchState {
  const char* src_init;  // the subject
  const char* src_end;
  const char* p_end;     // end of the pattern
  lua_State* L;
  const char* what;      // "string.find", for the budget message
  int matchdepth;
  int level;             // captures, finished or not
  uint64_t steps;        // not yet charged
  struct {
    const char* init;
    ptrdiff_t len;
  } capture[kMaxCaptures];
};

unsigned char uchar(char c) { return static_cast<unsigned char>(c); }

// Counts n steps of matching; every kChargeEvery of them are charged to the call's budget.
void tick(MatchState* ms, uint64_t n) {
  ms->steps += n;
  if (ms->steps < kChargeEvery) return;
  const uint64_t steps = ms->steps;
  ms->steps = 0;
  charge_budget(ms->L, steps * kStepCost, ms->what,
                "the pattern backtracks too much over its subject: simplify or anchor it");
}

// The capture index a back reference %1-%9 names, checked.
int check_capture(MatchState* ms, int l) {
  l -= '1';
  if (l < 0 || l >= ms->level || ms->capture[l].len == kUnfinished)
    return luaL_error(ms->L, "invalid capture index %%%d", l + 1);
  return l;
}

// The innermost capture still open, for a ')'.
int capture_to_close(MatchState* ms) {
  for (int level = ms->level - 1; level >= 0; level--)
    if (ms->capture[level].len == kUnfinished) return level;
  return luaL_error(ms->L, "invalid pattern capture");
}

// Where the single-character class at p ends.
const char* class_end(MatchState* ms, const char* p) {
  switch (*p++) {
    case kEsc:
      if (p == ms->p_end) luaL_error(ms->L, "malformed pattern (ends with '%%')");
      return p + 1;
    case '[':
      if (*p == '^') p++;
      do {  // look for a ']'
        if (p == ms->p_end) luaL_error(ms->L, "malformed pattern (missing ']')");
        if (*(p++) == kEsc && p < ms->p_end) p++;  // skip escapes (e.g. '%]')
      } while (*p != ']');
      return p + 1;
    default:
      return p;
  }
}

// Whether c is in the class %cl (upper case: its complement; any other character: itself).
bool match_class(int c, int cl) {
  int res;
  switch (std::tolower(cl)) {
    case 'a': res = std::isalpha(c); break;
    case 'c': res = std::iscntrl(c); break;
    case 'd': res = std::isdigit(c); break;
    case 'g': res = std::isgraph(c); break;
    case 'l': res = std::islower(c); break;
    case 'p': res = std::ispunct(c); break;
    case 's': res = std::isspace(c); break;
    case 'u': res = std::isupper(c); break;
    case 'w': res = std::isalnum(c); break;
    case 'x': res = std::isxdigit(c); break;
    case 'z': res = c == 0; break;  // deprecated in Lua 5.2, still Lua 5.4's
    default: return cl == c;
  }
  return std::islower(cl) ? res != 0 : res == 0;
}

// Whether c is in the set [...] from p to its closing bracket ec.
bool match_bracket_class(int c, const char* p, const char* ec) {
  bool sig = true;
  if (*(p + 1) == '^') {
    sig = false;
    p++;
  }
  while (++p < ec) {
    if (*p == kEsc) {
      p++;
      if (match_class(c, uchar(*p))) return sig;
    } else if (*(p + 1) == '-' && p + 2 < ec) {
      p += 2;
      if (uchar(*(p - 2)) <= c && c <= uchar(*p)) return sig;
    } else if (uchar(*p) == c) {
      return sig;
    }
  }
  return !sig;
}

// Whether the subject character at s matches the single-character class p..ep.
bool single_match(MatchState* ms, const char* s, const char* p, const char* ep) {
  if (s >= ms->src_end) return false;
  const int c = uchar(*s);
  switch (*p) {
    case '.': return true;
    case kEsc: return match_class(c, uchar(*(p + 1)));
    case '[': return match_bracket_class(c, p, ep - 1);
    default: return uchar(*p) == c;
  }
}

const char* do_match(MatchState* ms, const char* s, const char* p);

// %bxy: a balanced run from x to its matching y at s; the end of it, or nullptr.
const char* match_balance(MatchState* ms, const char* s, const char* p) {
  if (p >= ms->p_end - 1) luaL_error(ms->L, "malformed pattern (missing arguments to '%%b')");
  if (*s != *p) return nullptr;
  const int b = *p, e = *(p + 1);
  int cont = 1;
  const char* from = s;
  while (++s < ms->src_end) {
    if (*s == e) {
      if (--cont == 0) {
        tick(ms, uint64_t(s - from));
        return s + 1;
      }
    } else if (*s == b) {
      cont++;
    }
  }
  tick(ms, uint64_t(s - from));
  return nullptr;  // the subject ends out of balance
}

// item* and item+: the longest run that lets the rest match.
const char* max_expand(MatchState* ms, const char* s, const char* p, const char* ep) {
  ptrdiff_t i = 0;  // the longest run of the item
  while (single_match(ms, s + i, p, ep)) i++;
  tick(ms, uint64_t(i));
  for (; i >= 0; i--)  // try the longest first, then one shorter each time
    if (const char* res = do_match(ms, s + i, ep + 1)) return res;
  return nullptr;
}

// item-: the shortest run that lets the rest match.
const char* min_expand(MatchState* ms, const char* s, const char* p, const char* ep) {
  for (;;) {
    if (const char* res = do_match(ms, s, ep + 1)) return res;
    if (!single_match(ms, s, p, ep)) return nullptr;
    s++;  // one more repetition
  }
}

// Opens a capture (or records a position) and matches the rest.
const char* start_capture(MatchState* ms, const char* s, const char* p, ptrdiff_t what) {
  const int level = ms->level;
  if (level >= kMaxCaptures) luaL_error(ms->L, "too many captures");
  ms->capture[level].init = s;
  ms->capture[level].len = what;
  ms->level = level + 1;
  const char* res = do_match(ms, s, p);
  if (!res) ms->level--;  // undo the capture
  return res;
}

// Closes the innermost open capture and matches the rest.
const char* end_capture(MatchState* ms, const char* s, const char* p) {
  const int l = capture_to_close(ms);
  ms->capture[l].len = s - ms->capture[l].init;
  const char* res = do_match(ms, s, p);
  if (!res) ms->capture[l].len = kUnfinished;  // undo the capture
  return res;
}

// A back reference: the text of capture l again at s.
const char* match_capture(MatchState* ms, const char* s, int l) {
  l = check_capture(ms, l);
  const size_t len = size_t(ms->capture[l].len);  // a position capture's is huge: no match
  if (size_t(ms->src_end - s) < len) return nullptr;
  tick(ms, len / 16);
  return std::memcmp(ms->capture[l].init, s, len) == 0 ? s + len : nullptr;
}

// An escape other than a class (%b, %f, %0-%9) at p; sets p to where matching goes on.
const char* match_escape(MatchState* ms, const char* s, const char*& p) {
  switch (*(p + 1)) {
    case 'b':
      s = match_balance(ms, s, p + 2);
      p += 4;
      return s;
    case 'f': {
      p += 2;
      if (*p != '[') luaL_error(ms->L, "missing '[' after '%%f' in pattern");
      const char* ep = class_end(ms, p);
      const char previous = (s == ms->src_init) ? '\0' : *(s - 1);
      if (!match_bracket_class(uchar(previous), p, ep - 1) && match_bracket_class(uchar(*s), p, ep - 1)) {
        p = ep;
        return s;
      }
      return nullptr;
    }
    default:  // a back reference %0-%9
      s = match_capture(ms, s, uchar(*(p + 1)));
      p += 2;
      return s;
  }
}

// A single-character class at p with its optional suffix (?, *, +, -).
const char* match_item(MatchState* ms, const char* s, const char*& p, bool& more) {
  const char* ep = class_end(ms, p);
  more = false;
  if (!single_match(ms, s, p, ep)) {
    if (*ep == '*' || *ep == '?' || *ep == '-') {  // accepts empty
      p = ep + 1;
      more = true;
      return s;
    }
    return nullptr;  // '+' or no suffix
  }
  switch (*ep) {
    case '?':
      if (const char* res = do_match(ms, s + 1, ep + 1)) return res;
      p = ep + 1;
      more = true;
      return s;
    case '+': return max_expand(ms, s + 1, p, ep);
    case '*': return max_expand(ms, s, p, ep);
    case '-': return min_expand(ms, s, p, ep);
    default:
      p = ep;
      more = true;
      return s + 1;
  }
}

// Matches pattern p at s; the end of the match, or nullptr. Tail calls are loops, as in Lua's.
const char* do_match(MatchState* ms, const char* s, const char* p) {
  if (ms->matchdepth-- == 0) luaL_error(ms->L, "pattern too complex");
  bool more = true;
  while (more && s && p != ms->p_end) {
    tick(ms, 1);
    more = false;
    if (*p == '(') {
      s = *(p + 1) == ')' ? start_capture(ms, s, p + 2, kPosition)
                          : start_capture(ms, s, p + 1, kUnfinished);
    } else if (*p == ')') {
      s = end_capture(ms, s, p + 1);
    } else if (*p == '$' && p + 1 == ms->p_end) {
      s = (s == ms->src_end) ? s : nullptr;
    } else if (*p == kEsc && (*(p + 1) == 'b' || *(p + 1) == 'f' || std::isdigit(uchar(*(p + 1))))) {
      s = match_escape(ms, s, p);
      more = s != nullptr;
    } else {
      s = match_item(ms, s, p, more);
    }
  }
  ms->matchdepth++;
  return s;
}

// ---- the library functions ----

// A 1-based position from Lua's relative one (negative counts from the end), clipped to >= 1.
size_t posrelat(lua_Integer pos, size_t len) {
  if (pos > 0) return size_t(pos);
  if (pos == 0) return 1;
  if (pos < -lua_Integer(len)) return 1;
  return len + size_t(pos) + 1;
}

// Returns capture i (its length, or kPosition once the position is pushed).
ptrdiff_t get_capture(MatchState* ms, int i, const char* s, const char* e, const char** cap) {
  if (i >= ms->level) {
    if (i != 0) luaL_error(ms->L, "invalid capture index %%%d", i + 1);
    *cap = s;
    return e - s;
  }
  const ptrdiff_t capl = ms->capture[i].len;
  *cap = ms->capture[i].init;
  if (capl == kUnfinished) luaL_error(ms->L, "unfinished capture");
  else if (capl == kPosition) lua_pushinteger(ms->L, (ms->capture[i].init - ms->src_init) + 1);
  return capl;
}

// Pushes capture i (the whole match s..e when there are none).
void push_capture(MatchState* ms, int i, const char* s, const char* e) {
  const char* cap;
  const ptrdiff_t l = get_capture(ms, i, s, e, &cap);
  if (l != kPosition) lua_pushlstring(ms->L, cap, size_t(l));
}

// Pushes every capture (the whole match when there is none and s is given); returns how many.
int push_captures(MatchState* ms, const char* s, const char* e) {
  const int n = (ms->level == 0 && s) ? 1 : ms->level;
  luaL_checkstack(ms->L, n, "too many captures");
  for (int i = 0; i < n; i++) push_capture(ms, i, s, e);
  return n;
}

// Whether the pattern has none of the magic characters (find then searches plainly).
bool no_specials(const char* p, size_t l) {
  size_t upto = 0;
  do {
    if (std::strpbrk(p + upto, kSpecials)) return false;
    upto += std::strlen(p + upto) + 1;  // may have more after a \0
  } while (upto <= l);
  return true;
}

// Sets up a match of pattern p over subject s for the function `what`.
void prepare(MatchState* ms, lua_State* L, const char* what, const char* s, size_t ls, const char* p,
             size_t lp) {
  ms->L = L;
  ms->what = what;
  ms->src_init = s;
  ms->src_end = s + ls;
  ms->p_end = p + lp;
  ms->steps = 0;
}

// Before each attempt: no captures, full depth (also after an error left a gmatch midway).
void reprepare(MatchState* ms) {
  ms->level = 0;
  ms->matchdepth = kMaxDepth;
}

// A plain search, linear in the subject and the pattern (memmem); nullptr when absent.
const char* plain_find(lua_State* L, const char* s, size_t ls, const char* p, size_t lp) {
  charge_budget(L, (ls + lp) / 16, "string.find", "the subject is too long to search");
  if (lp == 0) return s;
  return static_cast<const char*>(memmem(s, ls, p, lp));
}

// string.find (find) and string.match (!find).
int find_aux(lua_State* L, bool find) {
  size_t ls, lp;
  const char* s = luaL_checklstring(L, 1, &ls);
  const char* p = luaL_checklstring(L, 2, &lp);
  const size_t init = posrelat(luaL_optinteger(L, 3, 1), ls) - 1;
  if (init > ls) {
    luaL_pushfail(L);  // starts after the subject's end
    return 1;
  }
  if (find && (lua_toboolean(L, 4) || no_specials(p, lp))) {
    if (const char* s2 = plain_find(L, s + init, ls - init, p, lp)) {
      lua_pushinteger(L, (s2 - s) + 1);
      lua_pushinteger(L, lua_Integer((s2 - s) + lp));
      return 2;
    }
    luaL_pushfail(L);
    return 1;
  }
  MatchState ms;
  const bool anchor = *p == '^';
  if (anchor) p++, lp--;
  prepare(&ms, L, find ? "string.find" : "string.match", s, ls, p, lp);
  const char* s1 = s + init;
  do {
    reprepare(&ms);
    if (const char* res = do_match(&ms, s1, p)) {
      if (!find) return push_captures(&ms, s1, res);
      lua_pushinteger(L, (s1 - s) + 1);
      lua_pushinteger(L, res - s);
      return push_captures(&ms, nullptr, nullptr) + 2;
    }
  } while (s1++ < ms.src_end && !anchor);
  luaL_pushfail(L);
  return 1;
}

// string.find(s, pattern [, init [, plain]]).
int str_find(lua_State* L) { return find_aux(L, true); }
// string.match(s, pattern [, init]).
int str_match(lua_State* L) { return find_aux(L, false); }

// What the iterator of one gmatch keeps between calls.
struct GMatchState {
  const char* src;        // where the next search starts
  const char* p;          // the pattern
  const char* lastmatch;  // end of the last match
  MatchState ms;
};

// The iterator gmatch returns: the next match's captures, or nothing.
int gmatch_aux(lua_State* L) {
  auto* gm = static_cast<GMatchState*>(lua_touserdata(L, lua_upvalueindex(3)));
  gm->ms.L = L;
  for (const char* src = gm->src; src <= gm->ms.src_end; src++) {
    reprepare(&gm->ms);
    const char* e = do_match(&gm->ms, src, gm->p);
    if (e && e != gm->lastmatch) {
      gm->src = gm->lastmatch = e;
      return push_captures(&gm->ms, src, e);
    }
  }
  return 0;
}

// string.gmatch(s, pattern [, init]).
int str_gmatch(lua_State* L) {
  size_t ls, lp;
  const char* s = luaL_checklstring(L, 1, &ls);
  const char* p = luaL_checklstring(L, 2, &lp);
  size_t init = posrelat(luaL_optinteger(L, 3, 1), ls) - 1;
  lua_settop(L, 2);  // the closure keeps the strings alive
  auto* gm = static_cast<GMatchState*>(lua_newuserdatauv(L, sizeof(GMatchState), 0));
  if (init > ls) init = ls + 1;  // avoids overflow in s + init
  prepare(&gm->ms, L, "string.gmatch", s, ls, p, lp);
  gm->src = s + init;
  gm->p = p;
  gm->lastmatch = nullptr;
  lua_pushcclosure(L, gmatch_aux, 3);
  return 1;
}

// Adds the replacement string (argument 3) with its %0-%9 and %% to the buffer.
void add_string(MatchState* ms, luaL_Buffer* b, const char* s, const char* e) {
  size_t l;
  lua_State* L = ms->L;
  const char* news = lua_tolstring(L, 3, &l);
  const char* p;
  while ((p = static_cast<const char*>(std::memchr(news, kEsc, l))) != nullptr) {
    luaL_addlstring(b, news, size_t(p - news));
    p++;  // skip the escape
    if (*p == kEsc) {
      luaL_addchar(b, *p);
    } else if (*p == '0') {
      luaL_addlstring(b, s, size_t(e - s));
    } else if (std::isdigit(uchar(*p))) {
      const char* cap;
      const ptrdiff_t resl = get_capture(ms, *p - '1', s, e, &cap);
      if (resl == kPosition) luaL_addvalue(b);
      else luaL_addlstring(b, cap, size_t(resl));
    } else {
      luaL_error(L, "invalid use of '%c' in replacement string", kEsc);
    }
    l -= size_t(p + 1 - news);
    news = p + 1;
  }
  luaL_addlstring(b, news, l);
}

// Adds the replacement of the match s..e (of type tr); whether it changed the text.
bool add_value(MatchState* ms, luaL_Buffer* b, const char* s, const char* e, int tr) {
  lua_State* L = ms->L;
  if (tr == LUA_TFUNCTION) {
    lua_pushvalue(L, 3);
    const int n = push_captures(ms, s, e);
    lua_call(L, n, 1);
  } else if (tr == LUA_TTABLE) {
    push_capture(ms, 0, s, e);
    lua_gettable(L, 3);
  } else {
    add_string(ms, b, s, e);
    return true;
  }
  if (!lua_toboolean(L, -1)) {  // nil or false: keep the original text
    lua_pop(L, 1);
    luaL_addlstring(b, s, size_t(e - s));
    return false;
  }
  if (!lua_isstring(L, -1)) luaL_error(L, "invalid replacement value (a %s)", luaL_typename(L, -1));
  luaL_addvalue(b);
  return true;
}

// string.gsub(s, pattern, repl [, n]).
int str_gsub(lua_State* L) {
  size_t srcl, lp;
  const char* src = luaL_checklstring(L, 1, &srcl);
  const char* p = luaL_checklstring(L, 2, &lp);
  const char* lastmatch = nullptr;
  const int tr = lua_type(L, 3);
  const lua_Integer max_s = luaL_optinteger(L, 4, lua_Integer(srcl) + 1);
  const bool anchor = *p == '^';
  luaL_argexpected(L, tr == LUA_TNUMBER || tr == LUA_TSTRING || tr == LUA_TFUNCTION || tr == LUA_TTABLE, 3,
                   "string/function/table");
  luaL_Buffer b;
  luaL_buffinit(L, &b);
  if (anchor) p++, lp--;
  MatchState ms;
  prepare(&ms, L, "string.gsub", src, srcl, p, lp);
  lua_Integer n = 0;
  bool changed = false;
  while (n < max_s) {
    reprepare(&ms);
    const char* e = do_match(&ms, src, p);
    if (e && e != lastmatch) {
      n++;
      changed = add_value(&ms, &b, src, e, tr) || changed;
      src = lastmatch = e;
    } else if (src < ms.src_end) {
      luaL_addchar(&b, *src++);
    } else {
      break;
    }
    if (anchor) break;
  }
  if (!changed) {
    lua_pushvalue(L, 1);  // the original string
  } else {
    luaL_addlstring(&b, src, size_t(ms.src_end - src));
    luaL_pushresult(&b);
  }
  lua_pushinteger(L, n);
  return 2;
}

}  // namespace

// Replaces string.find, match, gmatch and gsub by the budgeted ones. The string table is also the
// strings' metatable's __index, so ("x"):find reaches them too; Lua's own are left unreachable.
void install_patterns(lua_State* L, int string_table) {
  const luaL_Reg functions[] = {
      {"find", str_find}, {"match", str_match}, {"gmatch", str_gmatch}, {"gsub", str_gsub}};
  for (const auto& f : functions) {
    lua_pushcfunction(L, f.func);
    lua_setfield(L, string_table, f.name);
  }
}

}  // namespace sandbox_detail
}  // namespace roger
