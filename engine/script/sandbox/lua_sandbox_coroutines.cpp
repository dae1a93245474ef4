// lua_sandbox_coroutines.cpp: Lua 5.4's coroutine library under the call's budgets. The count
// hook is a thread's own: a coroutine takes its creator's when it is made and keeps its own count
// between resumes, so every instruction it runs is counted, to the call running when it runs
// (wherever the coroutine was made), and what it runs after its last hook is paid for when it
// starts (charge_first_run). What the library's resume, wrap and close add here:
//   - a spent budget resumes (or closes) nothing: they raise its error at the caller's line;
//   - a coroutine is entered with the hook interval the budgets want now (a coroutine made
//     before a big block appeared checks the time between its slow instructions too);
//   - while it runs, the allocator arms the hook of the coroutine, not of the thread that
//     resumed it (Impl::running);
//   - a budget spent inside it is not handed back as resume's `false, message`, which the caller
//     could catch and go on: its error goes on up, naming the coroutine's line, and the caller's
//     hook fires at its next instruction whatever happens;
//   - a coroutine the budget's error killed keeps its hooks off for good (Lua leaves them so for
//     an error raised in a hook), so its pending __close handlers are never run: neither by
//     wrap's error path nor by a later coroutine.close;
//   - a budget spent by the __close handlers wrap's error path runs is the budget's error too.
// Everything else (create, yield, status, running, isyieldable, the messages) is Lua's own.
#include <lua.hpp>

#include "script/sandbox/lua_sandbox_internal.h"

namespace roger {
namespace sandbox_detail {
namespace {

// Makes `co` the running thread of the sandbox until the end of the scope, errors included (Lua's
// errors unwind C++ frames: the library is C++-compiled).
class Entered {
 public:
  Entered(LuaSandbox::Impl& s, lua_State* co) : s_(s), before_(s.running) { s.running = co; }
  ~Entered() { s_.running = before_; }
  Entered(const Entered&) = delete;
  Entered& operator=(const Entered&) = delete;

 private:
  LuaSandbox::Impl& s_;
  lua_State* before_;
};

// Before the coroutine `co` runs on behalf of L: refuses when the budget is spent, and brings the
// coroutine's hook interval down to the one wanted now. Only down: setting a hook restarts its
// count, and the instructions run since the coroutine's last hook would go uncounted if it were
// done at every resume.
void before_running(lua_State* L, lua_State* co) {
  auto& s = impl_of(L);
  if (budget_spent(s)) raise_spent_budget(L);
  if (co == L) return;  // Lua refuses to resume the running coroutine itself
  const int wanted = wanted_interval(s);
  if (lua_gethook(co) != count_hook || lua_gethookcount(co) > wanted) lua_sethook(co, count_hook, LUA_MASKCOUNT, wanted);
}

// A coroutine about to run for the first time is charged its hook interval at once: what it runs
// after its last hook fires (less than one interval) is never counted, since it dies or is dropped
// before the next, and many short coroutines ran several times the budget uncounted (found by a
// probe: 7 times, in coroutines of 490 instructions). Charged first, a coroutine's count is an
// upper bound of what it runs.
void charge_first_run(lua_State* L, lua_State* co, const char* what) {
  lua_Debug frame;
  if (co == L || lua_status(co) != LUA_OK || lua_getstack(co, 0, &frame) || lua_gettop(co) == 0) return;
  charge_budget(L, uint64_t(lua_gethookcount(co)), what,
                "each coroutine is charged its first hook interval of instructions when it starts");
}

// The registry table (weak keys) of the coroutines a spent budget stopped, each with its error.
constexpr const char* kStoppedKey = "roger.stopped_coroutines";

// That table, pushed; weak-keyed (found by a probe: it held every stopped coroutine for the
// state's life).
void push_stopped(lua_State* L) { push_weak_keyed(L, kStoppedKey); }

// After the coroutine at stack index `co` ran on behalf of L: when it spent the budget, the
// caller's hook fires at its next instruction; and a coroutine that died of it (the budget's error
// comes from the count hook, which leaves the dead coroutine's hooks off for good) is noted as
// stopped, and its error (at stack index `error`, 0 when none) raised again here, at the
// coroutine's line, instead of being returned as a value.
void after_running(lua_State* L, int co, int error) {
  if (!budget_spent(impl_of(L))) return;
  lua_sethook(L, count_hook, LUA_MASKCOUNT, 1);
  const int status = lua_status(lua_tothread(L, co));
  if (status == LUA_OK || status == LUA_YIELD) return;
  push_stopped(L);
  lua_pushvalue(L, co);
  if (error != 0) lua_pushvalue(L, error); else lua_pushliteral(L, "stopped by the budget");
  lua_rawset(L, -3);
  lua_pop(L, 1);
  if (error == 0) return;
  disarm_handlers(L);  // the budget's error: no script's xpcall handler runs for it
  lua_pushvalue(L, error);
  lua_error(L);
}

// Whether the coroutine at stack index `co` was stopped by a budget (pushes its error if so).
bool stopped_coroutine(lua_State* L, int co) {
  push_stopped(L);
  lua_pushvalue(L, co);
  if (lua_rawget(L, -2) != LUA_TNIL) {
    lua_remove(L, -2);
    return true;
  }
  lua_pop(L, 2);
  return false;
}

// coroutine.resume(co, ...): Lua's (upvalue 1, run in this frame so its messages are Lua's).
int sandbox_resume(lua_State* L) {
  lua_State* co = lua_tothread(L, 1);
  if (co) {
    before_running(L, co);
    charge_first_run(L, co, "coroutine.resume");
  }
  int n;
  {
    Entered entered(impl_of(L), co ? co : L);
    n = lua_tocfunction(L, lua_upvalueindex(1))(L);
  }
  if (co) after_running(L, 1, lua_toboolean(L, -n) ? 0 : lua_gettop(L));
  if (co && co != L && lua_toboolean(L, -n)) charge_unwinding(L, "coroutine.resume");
  return n;
}

// The function coroutine.wrap returns: Lua's auxwrap, written over Lua's coroutine.resume
// (upvalue 2) so that the budget's error is raised as the coroutine raised it. Upvalue 1 is the
// coroutine.
int sandbox_wrapped(lua_State* L) {
  lua_State* co = lua_tothread(L, lua_upvalueindex(1));
  before_running(L, co);
  charge_first_run(L, co, "a coroutine.wrap function");
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  int n;
  {
    Entered entered(impl_of(L), co);
    n = lua_tocfunction(L, lua_upvalueindex(2))(L);  // true, results or false, message
  }
  if (lua_toboolean(L, -n)) {
    after_running(L, 1, 0);
    charge_unwinding(L, "a coroutine.wrap function");
    return n - 1;
  }
  after_running(L, 1, lua_gettop(L));
  // As Lua's auxwrap: close the failed coroutine's pending variables, then raise its error with
  // the caller's position in front when it is a string.
  int status = lua_status(co);
  if (status != LUA_OK && status != LUA_YIELD) {
    {
      Entered entered(impl_of(L), co);
      status = lua_resetthread(co);
      lua_xmove(co, L, 1);
    }
    // Its __close handlers spent the budget (found by a probe: pcall caught that error, and the
    // caller ran on): raised as the budget's error is, the caller's hook firing next.
    if (budget_spent(impl_of(L))) {
      lua_sethook(L, count_hook, LUA_MASKCOUNT, 1);
      disarm_handlers(L);
      return lua_error(L);
    }
  }
  if (status != LUA_ERRMEM && lua_type(L, -1) == LUA_TSTRING) {
    luaL_where(L, 1);
    lua_insert(L, -2);
    lua_concat(L, 2);
  }
  return lua_error(L);
}

// coroutine.wrap(f): a coroutine made by Lua's coroutine.create (upvalue 1), called through
// sandbox_wrapped (upvalue 2 is Lua's coroutine.resume).
int sandbox_wrap(lua_State* L) {
  lua_tocfunction(L, lua_upvalueindex(1))(L);  // checks f as Lua's wrap does; pushes the coroutine
  lua_pushvalue(L, lua_upvalueindex(2));
  lua_pushcclosure(L, sandbox_wrapped, 2);
  return 1;
}

// How deep coroutine.close calls nest on this thread's C stack: a __close that closes another
// coroutine, whose __close closes another, ... Lua 5.4.4 counts no C call for them, and 15000 of
// them overflowed the C stack (a segmentation fault, found by a probe; Lua's own bug list has
// it, fixed in 5.4.6 by counting them as C calls). Past Lua's limit of C calls the close raises
// Lua's "C stack overflow", as 5.4.6 does.
thread_local int close_depth = 0;
constexpr int kMaxCloseDepth = 200;  // LUAI_MAXCCALLS

class NestedClose {
 public:
  NestedClose() { ++close_depth; }
  ~NestedClose() { --close_depth; }
  NestedClose(const NestedClose&) = delete;
  NestedClose& operator=(const NestedClose&) = delete;
};

// coroutine.close(co): Lua's (upvalue 1). A suspended coroutine's pending to-be-closed variables
// run their __close in it, under the budget. Those of a coroutine a budget stopped never run (its
// hooks stay off): closing it gives false and the budget's error.
int sandbox_close(lua_State* L) {
  if (close_depth >= kMaxCloseDepth) return luaL_error(L, "C stack overflow");
  const NestedClose nested;
  lua_State* co = lua_tothread(L, 1);
  if (co) {
    before_running(L, co);
    if (stopped_coroutine(L, 1)) {
      lua_pushboolean(L, 0);
      lua_insert(L, -2);
      return 2;
    }
  }
  int n;
  {
    Entered entered(impl_of(L), co ? co : L);
    n = lua_tocfunction(L, lua_upvalueindex(1))(L);
  }
  if (co) after_running(L, 1, n == 2 ? lua_gettop(L) : 0);
  return n;
}

}  // namespace

void install_coroutines(lua_State* L) {
  lua_getglobal(L, LUA_COLIBNAME);
  const int co = lua_gettop(L);
  lua_getfield(L, co, "resume");  // Lua's, a light C function
  const int resume = lua_gettop(L);
  lua_pushvalue(L, resume);
  lua_pushcclosure(L, sandbox_resume, 1);
  lua_setfield(L, co, "resume");
  lua_getfield(L, co, "create");
  lua_pushvalue(L, resume);
  lua_pushcclosure(L, sandbox_wrap, 2);
  lua_setfield(L, co, "wrap");
  lua_getfield(L, co, "close");
  lua_pushcclosure(L, sandbox_close, 1);
  lua_setfield(L, co, "close");
  lua_pop(L, 2);
}

}  // namespace sandbox_detail
}  // namespace roger
