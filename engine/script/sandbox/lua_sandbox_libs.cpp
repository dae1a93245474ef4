// lua_sandbox_libs.cpp: the libraries a sandboxed script sees, with guards standing in for the
// missing ones and safe replacements of load, print and require.
#include <algorithm>
#include <cstring>
#include <string>

#include <lua.hpp>

#include "script/sandbox/lua_sandbox_internal.h"

namespace roger {
namespace sandbox_detail {
namespace {

constexpr const char* kSandboxNote = "roger scripts are sandboxed (no os, io, debug, package)";

// Guard tables stand in for the missing libraries so that `os.execute` explains itself.
int guard_access(lua_State* L) {
  const char* lib = lua_tostring(L, lua_upvalueindex(1));
  if (lua_type(L, 2) == LUA_TSTRING)
    return luaL_error(L, "%s.%s is not available: %s", lib, lua_tostring(L, 2), kSandboxNote);
  return luaL_error(L, "%s is not available: %s", lib, kSandboxNote);
}

// Calling a guard table (`os()`) explains the sandbox too.
int guard_call(lua_State* L) {
  return luaL_error(L, "%s is not available: %s", lua_tostring(L, lua_upvalueindex(1)), kSandboxNote);
}

// Pushes the guard table standing in for library `lib`; its metatable is hidden from scripts.
void push_guard(lua_State* L, const char* lib) {
  lua_newtable(L);
  lua_newtable(L);
  lua_pushstring(L, lib);
  lua_pushcclosure(L, guard_access, 1);
  lua_setfield(L, -2, "__index");
  lua_pushstring(L, lib);
  lua_pushcclosure(L, guard_access, 1);
  lua_setfield(L, -2, "__newindex");
  lua_pushstring(L, lib);
  lua_pushcclosure(L, guard_call, 1);
  lua_setfield(L, -2, "__call");
  lua_pushboolean(L, 0);
  lua_setfield(L, -2, "__metatable");  // getmetatable(os) cannot reach the guard
  lua_setmetatable(L, -2);
}

// A function that only raises the message in its upvalue.
int refuse_function(lua_State* L) {
  return luaL_error(L, "%s", lua_tostring(L, lua_upvalueindex(1)));
}

// Replaces table[field] by a function raising `message`.
void set_refusal(lua_State* L, int table, const char* field, const char* message) {
  lua_pushstring(L, message);
  lua_pushcclosure(L, refuse_function, 1);
  lua_setfield(L, table, field);
}

// Charges compiling `bytes` of source text, one instruction a byte (the lexer may skip them all,
// allocating nothing). Raised inside lua_load, the budget's error becomes load's `nil, message`,
// and the count hook raises it again at the script's next instruction.
void charge_source(lua_State* L, size_t bytes) {
  charge_budget(L, bytes, "load", "the chunk is too long to compile within the budget left");  // 5 ns a byte
}

// Refuses a binary chunk by its first byte, whatever mode load was given: the compiler never sees
// bytecode. (Text is accepted or refused by the mode, as Lua does.)
void refuse_bytecode(lua_State* L, const char* piece, size_t size) {
  if (size > 0 && piece[0] == LUA_SIGNATURE[0]) {
    lua_pushliteral(L, "attempt to load a binary chunk: roger loads Lua source text only");
    lua_error(L);
  }
}

// What load reads: a string a slice at a time, each charged as it is read (the compiler stops
// reading at the first syntax error, and so does the charge), or the pieces of the script's reader
// (argument 1), each charged.
struct Source {
  const char* text = nullptr;
  size_t left = 0;
  bool first = true;
};

constexpr size_t kSlice = 4096;
// A piece from a reader function costs its call and the compiler's taking it on, about as long as
// 64 instructions, besides its bytes (a reader giving a byte at a time is stopped as a loop is).
constexpr size_t kPieceCost = 64;

const char* read_slice(lua_State* L, void* data, size_t* size) {
  auto* source = static_cast<Source*>(data);
  *size = std::min(kSlice, source->left);
  if (*size == 0) return nullptr;
  if (source->first) refuse_bytecode(L, source->text, *size);
  source->first = false;
  charge_source(L, *size);
  const char* piece = source->text;
  source->text += *size;
  source->left -= *size;
  return piece;
}

// lbaselib's generic_reader: the piece is kept in the reserved slot 5 while the compiler reads it.
const char* read_function(lua_State* L, void* data, size_t* size) {
  luaL_checkstack(L, 2, "too many nested functions");
  lua_pushvalue(L, 1);
  lua_call(L, 0, 1);
  if (lua_isnil(L, -1)) {
    lua_pop(L, 1);
    *size = 0;
    return nullptr;
  }
  if (!lua_isstring(L, -1)) luaL_error(L, "reader function must return a string");
  lua_replace(L, 5);
  const char* piece = lua_tolstring(L, 5, size);
  auto* source = static_cast<Source*>(data);
  if (source->first && *size > 0) refuse_bytecode(L, piece, *size);
  if (*size > 0) source->first = false;
  charge_source(L, kPieceCost + *size);
  return piece;
}

// load(chunk [, chunkname [, mode [, env]]]): lbaselib's luaB_load, refusing binary chunks
// whatever the mode and charging the source as the compiler reads it.
int sandbox_load(lua_State* L) {
  size_t len;
  const char* s = lua_tolstring(L, 1, &len);
  const char* mode = luaL_optstring(L, 3, "bt");
  const int env = !lua_isnone(L, 4) ? 4 : 0;
  Source source;
  int status;
  if (s) {
    const char* chunkname = luaL_optstring(L, 2, s);
    source.text = s;
    source.left = len;
    status = lua_load(L, read_slice, &source, chunkname, mode);
  } else {
    const char* chunkname = luaL_optstring(L, 2, "=(load)");
    luaL_checktype(L, 1, LUA_TFUNCTION);
    lua_settop(L, 5);  // the reserved slot
    status = lua_load(L, read_function, &source, chunkname, mode);
  }
  if (status != LUA_OK) {  // fail and the message
    luaL_pushfail(L);
    lua_insert(L, -2);
    return 2;
  }
  if (env != 0) {  // the environment as the chunk's first upvalue
    lua_pushvalue(L, env);
    if (!lua_setupvalue(L, -2, 1)) lua_pop(L, 1);
  }
  return 1;
}

// print(...): tab-separated tostring() of the arguments, one line to the sandbox's sink. When an
// argument's __tostring fails, Lua has written the arguments before it (no tab after the last, no
// newline): that much is kept, and the next print's line continues it.
int sandbox_print(lua_State* L) {
  const int n = lua_gettop(L);
  luaL_Buffer b;
  luaL_buffinit(L, &b);
  for (int i = 1; i <= n; ++i) {
    if (i > 1) luaL_addchar(&b, '\t');
    try {
      luaL_tolstring(L, i, nullptr);
    } catch (...) {  // a Lua error (this Lua is compiled as C++), raised on once the text is kept
      keep_unended_print(impl_of(L), luaL_buffaddr(&b), luaL_bufflen(&b) - (i > 1 ? 1 : 0));
      throw;
    }
    luaL_addvalue(&b);
  }
  luaL_pushresult(&b);
  size_t length = 0;
  const char* text = lua_tolstring(L, -1, &length);
  return lua_protect(L, [&]() {
    auto& s = impl_of(L);
    std::string line = std::move(s.print_unended);  // all of the text, as Lua's print writes a NUL and what follows
    s.print_unended.clear();
    line.append(text, length);
    if (s.print) s.print(line);
    return 0;
  });
}

// setmetatable(t, mt) as Lua's, refusing a metatable with a __gc field: Lua runs finalizers with
// debug hooks off, so no budget could stop one that loops. Lua marks an object for finalization
// only if its metatable has __gc when it is set (a raw look-up, as here), so a field added later
// is never called; debug.setmetatable is out of reach (no debug library).
int sandbox_setmetatable(lua_State* L) {
  const int t = lua_type(L, 2);
  luaL_checktype(L, 1, LUA_TTABLE);
  luaL_argexpected(L, t == LUA_TNIL || t == LUA_TTABLE, 2, "nil or table");
  if (luaL_getmetafield(L, 1, "__metatable") != LUA_TNIL)
    return luaL_error(L, "cannot change a protected metatable");
  if (t == LUA_TTABLE) {
    lua_pushliteral(L, "__gc");
    if (lua_rawget(L, 2) != LUA_TNIL)
      return luaL_error(L, "setmetatable: a metatable with __gc is refused: roger scripts cannot "
                           "have finalizers (Lua runs them outside the instruction budget, so one "
                           "that never returned would hang the run)");
  }
  lua_settop(L, 2);
  lua_setmetatable(L, 1);
  return 1;
}

// xpcall and the budgets. An error raised in the count hook (the budget's own) reaches the
// message handler with hooks still off: a handler that looped would never be stopped. So the
// budget's errors never reach a script's handler: before one is raised, the handler of every
// xpcall running on the thread is replaced by keep_message (disarm_handlers); every other error
// reaches the script's handler as in Lua. The handler is the one Lua calls, from where Lua calls
// it: a wrapper calling it (the sandbox had one) was a frame of its own, seen in tracebacks
// ("[C]: in ?"), by error levels, and by the C stack (a handler that kept raising ran half as
// often before "error in error handling").
//
// The running xpcalls of a thread are found by their activation records (lua_getstack at level
// 0 when xpcall starts; lua_setlocal reaches a frame's slots through one while the frame lives),
// kept in a registry table keyed weakly by thread: a walk of the stack to find them costs a
// lua_getstack per level, each as long as the level is deep, and a recursion 100,000 deep would
// take minutes to say its budget is spent.
constexpr const char* kXpcallsKey = "roger.xpcall_frames";

// The activation records of the xpcalls running on one thread, innermost last (a userdata).
struct XpcallFrames {
  int count;
  int capacity;
  lua_Debug frames[1];  // `capacity` of them
};

size_t frames_size(int capacity) { return sizeof(XpcallFrames) + sizeof(lua_Debug) * size_t(capacity - 1); }

// Pushes the registry's table of running xpcalls, weak-keyed: a coroutine left suspended inside an
// xpcall takes its records with it when it is collected.
void push_xpcalls(lua_State* L) { push_weak_keyed(L, kXpcallsKey); }

// The running thread's records, or null; allocates nothing (a budget's error may be on its way).
XpcallFrames* thread_frames(lua_State* L) {
  if (lua_getfield(L, LUA_REGISTRYINDEX, kXpcallsKey) != LUA_TTABLE) {
    lua_pop(L, 1);
    return nullptr;
  }
  lua_pushthread(L);
  lua_rawget(L, -2);
  auto* frames = static_cast<XpcallFrames*>(lua_touserdata(L, -1));
  lua_pop(L, 2);  // the table keeps the userdata
  return frames;
}

// Notes the running xpcall (level 0) among the thread's records, growing them as needed.
void note_xpcall(lua_State* L) {
  lua_Debug here;
  lua_getstack(L, 0, &here);
  XpcallFrames* frames = thread_frames(L);
  if (!frames || frames->count == frames->capacity) {
    const int capacity = frames ? frames->capacity * 2 : 4;
    push_xpcalls(L);
    auto* grown = static_cast<XpcallFrames*>(lua_newuserdatauv(L, frames_size(capacity), 0));
    grown->count = frames ? frames->count : 0;
    grown->capacity = capacity;
    if (frames) std::memcpy(grown->frames, frames->frames, sizeof(lua_Debug) * size_t(frames->count));
    lua_pushthread(L);
    lua_insert(L, -2);
    lua_rawset(L, -3);
    lua_pop(L, 1);
    frames = grown;
  }
  frames->frames[frames->count++] = here;
}

// Forgets the running xpcall (level 0), and any record above it.
void forget_xpcall(lua_State* L) {
  lua_Debug here;
  XpcallFrames* frames = thread_frames(L);
  if (!frames || !lua_getstack(L, 0, &here)) return;
  for (int i = frames->count - 1; i >= 0; --i) {
    if (frames->frames[i].i_ci == here.i_ci) {
      frames->count = i;
      return;
    }
  }
}

// The handler standing for a script's while a budget's error goes by: the message as it is.
int keep_message(lua_State* L) {
  lua_settop(L, 1);
  return 1;
}

// lbaselib's finishpcall, as xpcall's continuation too (after a yield in its function, or an
// error a coroutine's resume recovered): the xpcall is over, so its record goes.
int finish_xpcall(lua_State* L, int status, lua_KContext extra) {
  forget_xpcall(L);
  if (status != LUA_OK && status != LUA_YIELD) {
    lua_pushboolean(L, 0);
    lua_pushvalue(L, -2);
    return 2;
  }
  return lua_gettop(L) - int(extra);
}

// xpcall(f, handler, ...): lbaselib's luaB_xpcall, noting itself while it runs.
int sandbox_xpcall(lua_State* L) {
  const int n = lua_gettop(L);
  luaL_checktype(L, 2, LUA_TFUNCTION);
  note_xpcall(L);
  lua_pushboolean(L, 1);
  lua_pushvalue(L, 1);
  lua_rotate(L, 3, 2);
  const int status = lua_pcallk(L, n - 2, LUA_MULTRET, 2, 2, finish_xpcall);
  return finish_xpcall(L, status, 2);
}

}  // namespace

// Replaces the handler of every xpcall running on L by keep_message (slot 2 of xpcall's frame,
// where Lua looks for it when an error comes). Without room for two values it does nothing: the
// stack is then at Lua's limit, where calling a handler fails anyway ("error in error handling").
void disarm_handlers(lua_State* L) {
  if (!lua_checkstack(L, 2)) return;
  XpcallFrames* frames = thread_frames(L);
  for (int i = 0; frames && i < frames->count; ++i) {
    lua_pushcfunction(L, keep_message);
    if (!lua_setlocal(L, &frames->frames[i], 2)) lua_pop(L, 1);
  }
}

namespace {

// Lua's own libraries that read no file, reach no process and are seeded from nothing outside.
void open_permitted_libraries(lua_State* L) {
  const luaL_Reg libs[] = {{LUA_GNAME, luaopen_base},        {LUA_MATHLIBNAME, luaopen_math},
                           {LUA_STRLIBNAME, luaopen_string},   {LUA_TABLIBNAME, luaopen_table},
                           {LUA_UTF8LIBNAME, luaopen_utf8},    {LUA_COLIBNAME, luaopen_coroutine}};
  for (const auto& lib : libs) {
    luaL_requiref(L, lib.name, lib.func, 1);
    lua_pop(L, 1);
  }
}

// The base library's functions that load code or print, in the globals at index g.
void install_base_replacements(lua_State* L, int g) {
  // They read any file: refused with a word on what to use, not a nil whose call says only
  // "attempt to call a nil value".
  const char* no_file_loading =
      "is not available in roger scripts: it reads any file; require(\"dotted.name\") loads a module from the "
      "script's folder or the project's scenarios/, curricula/ and scripts/";
  set_refusal(L, g, "dofile", (std::string("dofile ") + no_file_loading).c_str());
  set_refusal(L, g, "loadfile", (std::string("loadfile ") + no_file_loading).c_str());
  lua_pushcfunction(L, sandbox_load);
  lua_setfield(L, g, "load");
  lua_pushcfunction(L, sandbox_require);
  lua_setfield(L, g, "require");
  lua_pushcfunction(L, sandbox_print);
  lua_setfield(L, g, "print");
  lua_pushcfunction(L, sandbox_xpcall);
  lua_setfield(L, g, "xpcall");
  lua_pushcfunction(L, sandbox_setmetatable);
  lua_setfield(L, g, "setmetatable");
}

// os, io, debug and package as guards that name what to use instead, in the globals at index g and
// in package.loaded: the guards are also what require("os") returns, as Lua's require returns the
// library.
void install_library_guards(lua_State* L, int g) {
  luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
  for (const char* lib : {"os", "io", "debug", "package"}) {
    push_guard(L, lib);
    if (std::string(lib) == "debug") {
      // Of debug, traceback alone: it only reads the stack into a string, and
      // xpcall(f, debug.traceback) is how Lua code keeps where an error came from (found by a
      // probe: such a handler failed, and xpcall said only "error in error handling").
      lua_pushstring(L, "traceback");
      luaopen_debug(L);  // a table of the library's functions; nothing else is installed
      lua_getfield(L, -1, "traceback");
      lua_remove(L, -2);
      lua_rawset(L, -3);
    }
    lua_pushvalue(L, -1);
    lua_setfield(L, -3, lib);
    lua_setfield(L, g, lib);
  }
  lua_pop(L, 1);
}

// string.dump refused and the patterns budgeted; math.random and math.randomseed refused.
void install_string_and_math(lua_State* L, int g) {
  lua_getfield(L, g, "string");
  // Bytecode out is as unwelcome as bytecode in.
  set_refusal(L, lua_gettop(L), "dump",
              "string.dump is not available in roger scripts: bytecode is refused, in and out (load takes source "
              "text only)");
  install_patterns(L, lua_gettop(L));
  lua_pop(L, 1);
  // math.random is seeded from the clock: a script using it would not be reproducible.
  lua_getfield(L, g, "math");
  // Each named as called (found by a probe: math.randomseed was refused as math.random).
  for (const char* name : {"random", "randomseed"})
    set_refusal(L, lua_gettop(L), name,
                (std::string("math.") + name + " is not available in roger scripts: draw from the rng object a "
                 "scenario's generate or a teacher function receives (rng:uniform, rng:int, rng:normal, ...) so "
                 "every run is reproducible from its seed; a reward or absorbing function draws nothing (it gets "
                 "no rng: make it a function of its arguments)").c_str());
  lua_pop(L, 1);
}

}  // namespace

// Opens the permitted libraries and installs the replacements (run protected: it allocates).
int open_sandbox(lua_State* L) {
  open_permitted_libraries(L);
  lua_pushglobaltable(L);
  const int g = lua_gettop(L);
  install_base_replacements(L, g);
  install_library_guards(L, g);
  install_string_and_math(L, g);
  install_charges(L);
  install_pairs(L);
  install_table_library(L);
  install_coroutines(L);
  lua_newtable(L);
  lua_setfield(L, LUA_REGISTRYINDEX, kModulesKey);
  return 0;
}

}  // namespace sandbox_detail
}  // namespace roger
