// lua_sandbox_hooks.cpp: the sandbox's budgets (memory, instructions) and how Lua errors are
// located and described.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>

#include <lua.hpp>

#include "script/sandbox/lua_sandbox_internal.h"

namespace roger {
namespace sandbox_detail {

// The sandbox a state belongs to (its address lives in the state's extra space, which threads share).
LuaSandbox::Impl& impl_of(lua_State* L) {
  return **static_cast<LuaSandbox::Impl**>(lua_getextraspace(L));
}

namespace {

// Counts units of C work or allocation as instructions, and apart (the time budget allows them less).
void add_charged_units(LuaSandbox::Impl& s, uint64_t units) {
  s.instructions_used += units;
  s.charged_units += units;
}

// Records the innermost Lua line running when the memory cap is first hit in a call. Only reads
// the call stack (lua_getstack and lua_getinfo "Sl" allocate nothing).
void note_refusal(LuaSandbox::Impl& s) {
  if (!s.running || s.oom_line > 0) return;
  lua_Debug ar;
  for (int level = 0; lua_getstack(s.running, level, &ar); ++level) {
    if (lua_getinfo(s.running, "Sl", &ar) && ar.currentline > 0) {
      std::snprintf(s.oom_file.data(), s.oom_file.size(), "%s", ar.short_src);
      s.oom_line = ar.currentline;
      return;
    }
  }
}

// Charges allocated bytes to the call's budget. The allocator cannot raise an error, so once the
// budget is spent it arms the count hook to raise it at the next VM instruction.
void charge_allocation(LuaSandbox::Impl& s, size_t bytes) {
  s.bytes_uncharged += bytes;
  if (s.bytes_uncharged < kBytesPerInstruction) return;
  add_charged_units(s, s.bytes_uncharged / kBytesPerInstruction);
  s.bytes_uncharged %= kBytesPerInstruction;
  // Only the allocation that spends the budget names allocation: once the VM's instructions (or a
  // C function's work) spent it, allocating says nothing new (raising its error allocates).
  if (s.instructions_used <= s.limits.instructions || s.call_depth == 0 || !s.running || s.spent_what ||
      s.spent_report[0] != '\0')
    return;
  s.spent_what = "copying and allocating";
  s.spent_why = "the script built more strings or tables than the budget allows (16 bytes count as one instruction)";
  lua_sethook(s.running, count_hook, LUA_MASKCOUNT, 1);
}

// Counts the live blocks of kBigBlock bytes or more as one grows past the size or shrinks below
// it. The first one shortens the count hook's interval at once, so the time limit is checked
// between the slow instructions it allows (the instructions run since the last hook are then not
// counted: at most an interval's, where the block itself was charged kBigBlock / 16).
void note_block(LuaSandbox::Impl& s, size_t before, size_t after) {
  const bool was = before >= kBigBlock, is = after >= kBigBlock;
  if (was == is) return;
  s.big_blocks += is ? 1 : -1;
  if (is && s.running && s.call_depth > 0 && lua_gethookcount(s.running) > kBigInterval)
    lua_sethook(s.running, count_hook, LUA_MASKCOUNT, kBigInterval);
}

}  // namespace

// The allocator: the usual realloc/free pair, refusing to grow the state beyond the cap. Lua then
// runs an emergency collection and retries before raising "not enough memory".
void* sandbox_alloc(void* ud, void* ptr, size_t osize, size_t nsize) {
  auto* s = static_cast<LuaSandbox::Impl*>(ud);
  const size_t old = ptr ? osize : 0;  // for new blocks osize encodes the object type
  if (nsize == 0) {
    std::free(ptr);
    s->memory_used -= old;
    note_block(*s, old, 0);
    return nullptr;
  }
  if (nsize > old && nsize - old > s->limits.memory_bytes - std::min(s->memory_used, s->limits.memory_bytes)) {
    note_refusal(*s);
    return nullptr;
  }
  void* p = std::realloc(ptr, nsize);
  if (p) s->memory_used = s->memory_used - old + nsize;
  if (p) note_block(*s, old, nsize);
  if (p && nsize > old) charge_allocation(*s, nsize - old);
  return p;
}

// Last resort: an error outside any protected call. Throwing unwinds out of the Lua API (the
// library is compiled as C++) instead of letting Lua call abort().
int sandbox_panic(lua_State* L) {
  const char* msg = lua_tostring(L, -1);
  throw Error(std::string("Lua panic (error outside a protected call): ") + (msg ? msg : "?"));
}

namespace {

// What Lua shows for a "@name" chunk: names over LUA_IDSIZE - 1 bytes keep only their end.
std::string lua_short_src(const std::string& name) {
  constexpr size_t kKeep = LUA_IDSIZE - 4;
  if (name.size() + 1 <= size_t(LUA_IDSIZE)) return name;
  return "..." + name.substr(name.size() - kKeep);
}

// Replaces every occurrence of `from` in text.
void replace_all(std::string& text, const std::string& from, const std::string& to) {
  if (from.empty()) return;
  for (size_t pos = text.find(from); pos != std::string::npos; pos = text.find(from, pos + to.size()))
    text.replace(pos, from.size(), to);
}

}  // namespace

// Puts back the full names of files whose names Lua truncated in a message or traceback.
std::string restore_names(const LuaSandbox::Impl& s, std::string text) {
  for (const auto& name : s.chunk_names) {
    const std::string short_name = lua_short_src(name);
    if (short_name != name) replace_all(text, short_name, name);
  }
  return text;
}

// Splits "file:line: message" into its parts; false when the text has no such prefix.
bool split_location(const std::string& text, std::string& file, int& line, std::string& rest) {
  const size_t eol = text.find('\n');
  for (size_t colon = text.find(':'); colon != std::string::npos && colon < eol;
       colon = text.find(':', colon + 1)) {
    size_t i = colon + 1;
    while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]))) ++i;
    if (i == colon + 1 || i + 1 >= text.size() || text[i] != ':' || text[i + 1] != ' ') continue;
    file = text.substr(0, colon);
    line = std::atoi(text.substr(colon + 1, i - colon - 1).c_str());
    rest = text.substr(i + 2);
    return true;
  }
  return false;
}

// The message handler of every protected call: records the innermost Lua frame and a traceback
// (the stack is gone once lua_pcall returns) and leaves the message as a string.
int message_handler(lua_State* L) {
  auto& s = impl_of(L);
  if (!lua_isstring(L, 1)) {
    if (!(luaL_callmeta(L, 1, "__tostring") && lua_type(L, -1) == LUA_TSTRING))
      lua_pushfstring(L, "(error object is a %s value)", luaL_typename(L, 1));
    lua_replace(L, 1);
  }
  lua_settop(L, 1);
  try {
    s.err_file.clear();
    s.err_line = 0;
    lua_Debug ar;
    for (int level = 1; lua_getstack(L, level, &ar); ++level) {
      if (lua_getinfo(L, "Sl", &ar) && ar.currentline > 0) {
        s.err_file = ar.short_src;
        s.err_line = ar.currentline;
        break;
      }
    }
    luaL_traceback(L, L, nullptr, 1);
    s.err_traceback = lua_tostring(L, -1);
    lua_pop(L, 1);
    s.err_handled = true;
  } catch (const std::exception&) {
    // Out of C++ memory while describing an error: report the message without a traceback.
  }
  return 1;
}

int64_t monotonic_ns() {
  timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return int64_t(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

int64_t thread_cpu_ns() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return int64_t(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

void start_budgets(LuaSandbox::Impl& s) {
  s.instructions_used = 0;
  s.charged_units = 0;
  s.out_of_time = false;
  s.excluded_ns = 0;
  s.call_start_ns = monotonic_ns();
  s.call_start_cpu_ns = thread_cpu_ns();
  s.running = s.L;
  lua_sethook(s.L, count_hook, LUA_MASKCOUNT, wanted_interval(s));
}

int wanted_interval(const LuaSandbox::Impl& s) { return s.big_blocks > 0 ? kBigInterval : s.hook_interval; }

void push_weak_keyed(lua_State* L, const char* key) {
  if (luaL_getsubtable(L, LUA_REGISTRYINDEX, key)) return;
  lua_createtable(L, 0, 1);
  lua_pushliteral(L, "k");
  lua_setfield(L, -2, "__mode");
  lua_setmetatable(L, -2);
}

bool budget_spent(const LuaSandbox::Impl& s) { return s.instructions_used > s.limits.instructions || s.out_of_time; }

namespace {

// Raises the call's budget error: the first one as it was first raised (a script that caught it
// with pcall is stopped again with the same file:line and cause), else `text` at `where` (a
// "file:line" or "") and remembered as the first.
[[noreturn]] void raise_budget_error(lua_State* L, const char* where, const char* text) {
  auto& s = impl_of(L);
  if (s.spent_report[0] == '\0')
    std::snprintf(s.spent_report.data(), s.spent_report.size(), "%s%s%s", where, *where ? ": " : "", text);
  disarm_handlers(L);  // no script's xpcall handler runs for it (lua_sandbox_libs.cpp)
  lua_pushstring(L, s.spent_report.data());
  lua_error(L);
  std::abort();  // lua_error does not return
}

// Raises a budget error at the running Lua line: "<file>:<line>: <text>".
[[noreturn]] void raise_at_line(lua_State* L, lua_Debug* ar, const char* text) {
  char where[LUA_IDSIZE + 24] = "";
  if (lua_getinfo(L, "Sl", ar) && ar->currentline > 0)
    std::snprintf(where, sizeof where, "%s:%d", ar->short_src, ar->currentline);
  raise_budget_error(L, where, text);
}

// What a spent budget says: the processor time's, or the instruction budget's (naming the C
// function that spent it, for the count hook to say again after a script caught the error).
void spent_message(const LuaSandbox::Impl& s, char* text, size_t size) {
  const auto budget = static_cast<unsigned long long>(s.limits.instructions);
  // The allowance as allowed_ns counts it: units of allocation and C work at a quarter of an
  // instruction (found by a probe: "2.20 s for 13127809 instructions (0.20 s plus 200 ns per
  // instruction)" read as 2.83 s allowed, most of those being units of a table grown under pcall).
  const uint64_t units = std::min(s.charged_units, s.instructions_used);
  if (s.out_of_time)
    std::snprintf(text, size,
                  "processor time budget exceeded: %.3f s for %llu instructions and %llu units of allocation and C "
                  "work (a call may spend %.2f s plus %.0f ns per instruction and %.0f ns per unit: %.3f s here): "
                  "single instructions did long work in C (a long __index or __newindex chain, comparing or "
                  "converting very long strings, calls with very many ... values, or allocating: a table or "
                  "string grown to the memory cap again and again under pcall)",
                  s.spent_seconds, static_cast<unsigned long long>(s.instructions_used - units),
                  static_cast<unsigned long long>(units), double(s.time_floor_ns) * 1e-9, s.ns_per_instruction,
                  0.25 * s.ns_per_instruction, double(s.spent_allowed_ns) * 1e-9);
  else if (s.spent_what)
    std::snprintf(text, size, "%s: instruction budget of %llu exceeded: %s", s.spent_what, budget, s.spent_why);
  else
    std::snprintf(text, size, "instruction budget of %llu exceeded (runaway loop? if the work is meant, raise the "
                  "budget: --lua-instructions N, or a batch script's limits = { instructions = N })", budget);
}

// The processor time a call has been allowed so far (SandboxLimits::seconds and
// seconds_per_instruction). Units charged for C work and allocation are allowed a quarter of a VM
// instruction's time (50 ns): they stand for 16 bytes allocated and written or a step matched (a
// memory bomb filling 256 MiB spends about 17 ns per unit), and a script that built long strings
// must not earn seconds to spend on comparing them.
int64_t allowed_ns(const LuaSandbox::Impl& s) {
  const uint64_t charged = std::min(s.charged_units, s.instructions_used);
  const double units = double(s.instructions_used - charged) + 0.25 * double(charged);
  return s.time_floor_ns + int64_t(units * s.ns_per_instruction);
}

// The processor-time backstop. The monotonic clock (cheap) says when the allowance may have run
// out; the thread's own processor time decides, so a thread kept waiting on a busy machine is not
// stopped. Time in the engine's functions (lua_protect) counts for neither.
void check_time(lua_State* L, LuaSandbox::Impl& s, lua_Debug* ar) {
  if (s.call_depth == 0) return;
  if (!s.out_of_time) {
    const int64_t allowed = allowed_ns(s);
    if (monotonic_ns() - s.call_start_ns - s.excluded_ns <= allowed) return;
    const int64_t spent = thread_cpu_ns() - s.call_start_cpu_ns - s.excluded_ns;
    if (spent <= allowed) return;
    s.out_of_time = true;
    s.spent_seconds = double(spent) * 1e-9;
    s.spent_allowed_ns = allowed;
  }
  lua_sethook(L, count_hook, LUA_MASKCOUNT, 1);  // as for the instruction budget: no escaping through pcall
  char text[560];
  spent_message(s, text, sizeof text);
  raise_at_line(L, ar, text);
}

}  // namespace

// The instruction budget: a count hook every `interval` instructions (hook_interval, or
// kBigInterval while big blocks live). Once the budget is spent it fires on every instruction, so
// a script that catches the error with pcall is stopped again at its next instruction until the
// error reaches the engine. Each time it also checks the processor-time limit.
void count_hook(lua_State* L, lua_Debug* ar) {
  auto& s = impl_of(L);
  s.instructions_used += uint64_t(lua_gethookcount(L));
  if (s.instructions_used <= s.limits.instructions) {
    check_time(L, s, ar);
    const int wanted = wanted_interval(s);
    if (wanted != lua_gethookcount(L)) lua_sethook(L, count_hook, LUA_MASKCOUNT, wanted);
    return;
  }
  lua_sethook(L, count_hook, LUA_MASKCOUNT, 1);
  char text[560];
  spent_message(s, text, sizeof text);
  raise_at_line(L, ar, text);
}

void raise_spent_budget(lua_State* L) {
  const auto& s = impl_of(L);
  lua_sethook(L, count_hook, LUA_MASKCOUNT, 1);
  char text[560];
  spent_message(s, text, sizeof text);
  raise_at_lua_line(L, text);
}

// Raises `text` at the line of the innermost Lua function calling: a charge made in a C function
// that a C function called (table.sort's comparisons) names the line that called table.sort, also
// when the error leaves a coroutine, where no message handler looks for it.
void raise_at_lua_line(lua_State* L, const char* text) {
  char where[LUA_IDSIZE + 24] = "";
  lua_Debug ar;
  for (int level = 1; lua_getstack(L, level, &ar); ++level) {
    if (lua_getinfo(L, "Sl", &ar) && ar.currentline > 0) {
      std::snprintf(where, sizeof where, "%s:%d", ar.short_src, ar.currentline);
      break;
    }
  }
  raise_budget_error(L, where, text);
}

}  // namespace sandbox_detail

using sandbox_detail::count_hook;
using sandbox_detail::impl_of;

namespace {

// Counts the time of an engine function called from Lua out of the processor-time limit: what
// the engine does (building a world, training) is not the script's single instructions.
struct EngineTime {
  explicit EngineTime(LuaSandbox::Impl& s) : s(s), start(sandbox_detail::monotonic_ns()) {}
  ~EngineTime() { s.excluded_ns += sandbox_detail::monotonic_ns() - start; }
  LuaSandbox::Impl& s;
  int64_t start;
};

}  // namespace

int lua_protect(lua_State* L, const std::function<int()>& body) {
  std::string message;
  bool located = false;
  try {
    EngineTime engine_time(impl_of(L));
    return body();
  } catch (const ScriptError& e) {
    // Keep the original location; call() re-throws the very same error.
    message = e.file.empty() ? e.message
                             : e.file + (e.line > 0 ? ":" + std::to_string(e.line) : "") + ": " +
                                   e.message;
    located = !e.file.empty();
    auto& s = impl_of(L);
    s.pending = e;
    s.pending_text = message;
  } catch (const std::exception& e) {
    message = e.what();
  }
  // Raised outside the catch blocks, once the C++ exception is destroyed. A budget spent in a
  // call the engine made (its error comes back here) is the budget's error still: no script's
  // xpcall handler runs for it.
  if (sandbox_detail::budget_spent(impl_of(L))) sandbox_detail::disarm_handlers(L);
  if (located) {
    lua_pushstring(L, message.c_str());
    return lua_error(L);
  }
  return luaL_error(L, "%s", message.c_str());
}

void lua_charge(lua_State* L, uint64_t units) {
  sandbox_detail::charge_budget(L, units, nullptr, nullptr);
}

void lua_charge(lua_State* L, uint64_t units, const char* what, const char* why) {
  sandbox_detail::charge_budget(L, units, what, why);
}

bool lua_budget_spent(lua_State* L) { return sandbox_detail::budget_spent(sandbox_detail::impl_of(L)); }

namespace sandbox_detail {

// Counts work done in C against the budget; once it is spent, raises the budget error naming
// `what` and `why` (or the plain runaway-loop message) at the Lua caller's file:line.
void charge_budget(lua_State* L, uint64_t units, const char* what, const char* why) {
  auto& s = impl_of(L);
  add_charged_units(s, std::min<uint64_t>(units, s.limits.instructions + 1));
  if (s.instructions_used <= s.limits.instructions) return;
  lua_sethook(L, count_hook, LUA_MASKCOUNT, 1);  // as in count_hook: no escaping through pcall
  s.spent_what = what;
  s.spent_why = why;
  char text[560];
  spent_message(s, text, sizeof text);
  raise_at_lua_line(L, text);
}

void charge_unwinding(lua_State* L, const char* what) {
  charge_budget(L, kUnwindCost, what, "too many coroutine switches for the budget left");
  auto& s = impl_of(L);
  s.charged_units -= std::min(s.charged_units, kUnwindCost);  // an instruction's time, not C work's
}

}  // namespace sandbox_detail

}  // namespace roger
