// Module script: everything Lua. Owns the sandbox and every binding: scenarios, skill scripts,
// curricula, batch scripts. Lua lives only here. Depends on learn and below; must not depend on
// batch, report, view or cli. Its sub-folders, lowest first: sandbox < scenario, control < skills,
// curriculum < batch < authoring (docs/architecture.md); this one, sandbox, includes no other.
//
// lua_sandbox.h: a Lua 5.4 state that is safe to hand to a researcher's script.
//
// Scenario, curriculum and batch scripts are user input, so the state they run in:
//   - opens only the base, math, string, table, utf8 and coroutine libraries (no io, os, debug,
//     package: touching them raises an error saying the script is sandboxed); everything else a
//     script meets is Lua 5.4's (docs/scenarios.md, The sandbox, lists what differs);
//   - loads source text only (no bytecode: a binary chunk can crash the VM), with a `require` that
//     resolves dotted module names inside a fixed list of folders;
//   - stops runaway scripts with an instruction budget per call and a memory cap for the state;
//     the budget also counts the work of C library functions (pattern matching steps, elements
//     of table functions, bytes allocated: what Lua does, no more) and of coroutines (charged to
//     the call that resumes them), and setmetatable refuses __gc (finalizers run with the
//     budget's hook off); a processor-time limit per call stops what one instruction can do
//     in C and no count sees (long __index chains, long strings compared, huge `...` lists);
//   - turns every Lua error into a roger::ScriptError naming file:line with a traceback.
// Nothing here aborts the process: all calls into Lua are protected.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/spec.h"
#include "core/text.h"  // format_number, join, suggestion (messages)

struct lua_State;

namespace roger {

// How many times larger the processor-time allowance below is in a sanitizer build, whose
// instrumented C++ (the pattern matcher, the charged functions) runs several times slower while
// Debian's Lua does not. ROGER_SANITIZED decides it: CMake defines it for every target of every
// ROGER_SANITIZE build (address, undefined or both, with gcc or clang), and nothing else does.
#ifdef ROGER_SANITIZED
inline constexpr double kSanitizedAllowance = 8.0;
#else
inline constexpr double kSanitizedAllowance = 1.0;
#endif

// Resource limits of one sandbox.
struct SandboxLimits {
  uint64_t instructions = 50'000'000;   // Lua VM instructions per top-level protected call
  size_t memory_bytes = 256u << 20;     // bytes the whole Lua state may hold
  // The processor-time backstop, for single instructions that do long work in C where no count
  // sees it: a top-level call may spend `seconds` plus `seconds_per_instruction` for every VM
  // instruction it has run (a quarter of that per unit charged for C work or allocation) of
  // processor time in Lua; the engine's own functions it calls do not count. A plain loop spends
  // 5 ns per instruction, code that allocates and collects much 40-70 ns, so only instructions
  // doing long C work, for longer than `seconds`, ever meet it. Both are kSanitizedAllowance times
  // larger in a sanitizer build.
  double seconds = 0.2;
  double seconds_per_instruction = 200e-9;
};

// A Lua error with its location. what() is "file:line: message" followed by the traceback.
struct ScriptError : Error {
  // Builds the error; file may be empty and line 0 when unknown.
  ScriptError(std::string message, std::string file, int line, std::string traceback);
  std::string message;    // the error text without its location
  std::string file;       // the script as shown to the user ("scenarios/cluttered.lua")
  int line = 0;           // 0 when unknown
  std::string traceback;  // Lua's "stack traceback:" text, empty when none
};

// Whether `require` looks for the dotted module `name` in roots[index] (LuaSandbox::module_roots):
// the project folder itself, searched last, takes only a name that says its script folder
// ("curricula.sorting", which the bare "sorting" cannot reach past scenarios/sorting.lua).
bool module_root_takes(const std::vector<std::filesystem::path>& roots, size_t index, const std::string& name);

// The file `require(name)` loads from `roots` (LuaSandbox::module_roots), found as the sandbox's
// require finds it: a valid dotted name, a regular file, inside its root once links are followed;
// empty when require would load none (or refuse the one it finds). For readers of scripts that
// must not reach further than the scripts can (roger check's static pass).
std::filesystem::path find_module_file(const std::vector<std::filesystem::path>& roots, const std::string& name);

// The project folder holding scenarios/, curricula/ and scripts/: $ROGER_HOME if set, else the
// installed data beside the program (<prefix>/share/roger, core/install.h), else the source tree
// the engine was built from (a program run from its build tree).
std::filesystem::path project_root();

// The project folder in use and why it is that one, for messages: "ROGER_HOME=DIR" (", which is
// not a folder: ..." when it is none), "DIR, installed beside the program", or "DIR, the source
// tree this roger was built from" (a copy of bin/roger alone silently used that tree).
std::string project_in_use();

// For a path of the docs (docs/examples/x.lua, as the docs' commands name them) that is not a file
// here, where an installed tree keeps it (P/share/doc/roger/examples/x.lua, beside the project
// P/share/roger), as "; the documentation's files are installed apart from the project: PATH";
// else "".
std::string installed_docs_hint(const std::string& path);

// For a bare name given without ".lua" that is a file here with it (`roger check pen` beside
// pen.lua): "pen.lua"; else "".
std::string lua_file_here(const std::string& name);

// Where `require` looks for a module: `main_folder` first when given (the main script's folder),
// then the project's scenarios/, curricula/ and scripts/ -- for a batch script scripts/,
// curricula/ and scenarios/, so that its `require("paper")` is scripts/paper.lua wherever the
// script lies -- each resolved once and listed once.
std::vector<std::filesystem::path> module_search_roots(const std::filesystem::path& main_folder = {},
                                                       bool batch_script = false);

// Whether the script's own text (or the module it returns) sets a batch script's field (`runs`,
// `curriculum`, `evaluations`) and no curriculum's `stages`: the kind whose `require` searches
// scripts/ first (set_main_script).
bool looks_like_batch_script(const std::filesystem::path& path);

class LuaSandbox {
 public:
  // Opens a fresh sandboxed state. Throws roger::Error if the limits leave no room for Lua itself.
  explicit LuaSandbox(const SandboxLimits& limits = {});
  ~LuaSandbox();
  LuaSandbox(LuaSandbox&&) noexcept;
  LuaSandbox& operator=(LuaSandbox&&) noexcept;
  LuaSandbox(const LuaSandbox&) = delete;
  LuaSandbox& operator=(const LuaSandbox&) = delete;

  // The raw state, for bindings. Call into Lua only through call()/run_file()/load_*().
  lua_State* state() const;

  // The limits this sandbox enforces.
  const SandboxLimits& limits() const;

  // Declares the main script: `require` then searches its folder first, then
  // <project>/scenarios, <project>/curricula and <project>/scripts (for a batch script,
  // looks_like_batch_script: scripts, curricula, scenarios). run_file() does this for its first
  // file when no main script was declared.
  void set_main_script(const std::string& path);

  // The folders `require` searches, in order (absolute paths): the script's, the project's
  // script folders, and last the project folder itself, for names that begin with one of those
  // folders (module_root_takes).
  std::vector<std::filesystem::path> module_roots() const;

  // Compiles a source file (text only) and pushes the chunk. `path` is shown in messages as given.
  void load_file(const std::string& path);

  // Compiles source text and pushes the chunk; chunkname is shown in messages ("@file" or "=name").
  void load_string(const std::string& code, const std::string& chunkname);

  // Calls the function below nargs arguments on the stack, like lua_pcall, with a fresh
  // instruction budget (unless already inside a call) and a traceback on error. Throws ScriptError.
  void call(int nargs, int nresults);

  // Runs `body`, C++ that reads the nargs values on top of the stack with the Lua API and may
  // throw, inside a protected call as call() runs Lua (budget, ScriptError out); pops the values.
  void call_protected(int nargs, const std::function<void(lua_State*)>& body);

  // call_protected on the table a script returned (on the stack top), for the loaders that read
  // it: a Lua error without a location (raised by C++ reading the table) is placed at
  // `file`:`line()`, the line where what was being read is written, without a traceback (it
  // would show only C).
  void read_returned_table(const std::string& file, const std::function<int()>& line,
                           const std::function<void(lua_State*)>& body);

  // load_file() then call() with no arguments; leaves nresults values on the stack.
  void run_file(const std::string& path, int nresults = 1);

  // Where print() output goes (default: standard error, so standard output stays machine-readable).
  void set_print(std::function<void(const std::string&)> sink);
  // The sink in force (to put it back after a while elsewhere).
  const std::function<void(const std::string&)>& print_sink() const;

  // The name a file is shown under: relative to the project root when inside it, else as given.
  std::string display_name(const std::filesystem::path& path) const;

  // Every source file compiled so far: the scripts run or loaded, then the modules `require`
  // found, each once, in load order (absolute, canonical paths). What a result depends on.
  const std::vector<std::filesystem::path>& source_files() const;

  // Bytes the Lua state holds now.
  size_t memory_used() const;

  // Instructions counted in the current or last top-level call (to the nearest hook interval).
  uint64_t instructions_used() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

// Runs a C function's body, turning any std::exception (roger::Error included) into a Lua error at
// the Lua caller's file:line. Every lua_CFunction that runs C++ code which may throw goes through
// it: a C++ exception must never cross the Lua VM. A ScriptError keeps its own file:line. For states
// owned by a LuaSandbox only.
int lua_protect(lua_State* L, const std::function<int()>& body);

// Counts `units` of work done in C++ on behalf of a script (for example one per placement candidate
// tested) against the instruction budget, so loops inside engine functions cannot outrun it.
// Raises the budget error at the Lua caller's file:line when the budget is spent. For states owned
// by a LuaSandbox only.
void lua_charge(lua_State* L, uint64_t units);
// The same, the error naming the call and why it spent the budget ("world:sample_position: instruction
// budget of N exceeded: <why>") in place of "runaway loop?"; `what` and `why` are static strings.
void lua_charge(lua_State* L, uint64_t units, const char* what, const char* why);

// Whether the running call's budget is spent: a script's pcall caught its error and returned (a
// generator's `return pcall(loop)`). The call then ends with the budget's error; what the script
// returned is not worth judging. For states owned by a LuaSandbox only.
bool lua_budget_spent(lua_State* L);

// Refuses a call of a fixed-arity API function given more than `most` arguments: Lua drops extra
// arguments silently, and some mislead (roger.converged(c, 0.5) read as a hold time). Raises
// "call: takes <takes>, got N[; hint]" at the Lua caller's file:line. A method (a `call` with a
// colon, "rng:int") does not count its object.
void lua_check_arity(lua_State* L, const char* call, int most, const char* takes, const char* hint = nullptr);

// The first key (in sorted order) of the table at `index` that is not a position 1..#t of its list
// part, as messages show it ("'x'", "[7]"); "" when the table is a plain list. A list field's
// reader reads 1..#t, so such a key (`away_from = {x = 1, y = 1, distance = 3}` for a list of one
// point, `{a, [3] = c}`) would be dropped without a word: every list reader refuses it.
std::string lua_key_beside_list(lua_State* L, int index);

// Reads the named fields of a table argument such as world:object{...}. The constructor rejects
// keys that are not in `known` (listing the known ones) and positional values; the accessors check
// types. Every message starts with the context ("world:object") and is raised with luaL_error, so
// it carries the calling script's file:line.
class LuaFields {
 public:
  // Checks that the value at `index` is a table with only known string keys.
  LuaFields(lua_State* L, int index, std::string context, std::vector<std::string> known);

  // Whether the field is present (not nil).
  bool has(const char* key) const;
  // A required finite number.
  double number(const char* key) const;
  // An optional finite number.
  double number(const char* key, double fallback) const;
  // A required integer (a float with an integral value is accepted).
  int64_t integer(const char* key) const;
  // An optional integer.
  int64_t integer(const char* key, int64_t fallback) const;
  // A required string.
  std::string string(const char* key) const;
  // An optional string.
  std::string string(const char* key, const std::string& fallback) const;
  // An optional boolean.
  bool boolean(const char* key, bool fallback) const;
  // An optional colour: {r, g, b}, {r=, g=, b=} (integers 0-255) or "#rrggbb".
  Colour colour(const char* key, const Colour& fallback) const;
  // Pushes the raw value of a field (nil when absent) and returns its Lua type.
  int push(const char* key) const;
  // Raises a Lua error "context: message" at the caller's file:line.
  [[noreturn]] void fail(const std::string& message) const;
  // Raises "context: field 'key' must be <expected>, got <type>".
  [[noreturn]] void wrong_type(const char* key, const char* expected) const;

  const std::string& context() const { return context_; }
  lua_State* state() const { return L_; }

 private:
  lua_State* L_;
  int index_;
  std::string context_;
};

// A view (a teacher's history, generate's params): an empty table holding its data under a key no
// script can write (a light userdata), with a metatable of its maker's that reads through (__index,
// __len, __pairs). The sandbox's next, rawget and rawlen read a view's data, so they see what
// pairs, an index and # see, not the key.
// Pushes a new view of the table at `data`, with no metatable yet.
void lua_new_view(lua_State* L, int data);
// Pushes the data of the view at `index` and returns true; for any other value pushes nothing and
// returns false.
bool lua_push_view_data(lua_State* L, int index);
// For a view's metamethods: pushes the data of the view that is argument 1, or raises "bad
// argument #1 (<what> expected)" for any other value (a metamethod a script calls itself).
void lua_check_view_data(lua_State* L, const char* what);
// A view's __len: its data's length, as # on the data gives it.
int lua_view_len(lua_State* L);
// Replaces the table on the stack top with a read-only view of it (an API's constants: roger.robot,
// roger.primitive_kinds): an index, #, pairs, ipairs, next and rawget read the data; a write is an
// error at the writer's line naming `name` and the field (found by a probe: roger.robot.base_radius
// = 1 was taken, and every later read saw it).
void lua_make_read_only(lua_State* L, const char* name);

// A view may keep a table of the names read through it (a scenario's params: roger check's warning
// about a parameter generate never reads), under this key: its __index notes each name it reads
// (lua_view_note_read), and so do the sandbox's rawget and next.
void* lua_view_reads_key();
// Notes the string key at index `key` as read in the view at index `view`, if it keeps reads.
void lua_view_note_read(lua_State* L, int view, int key);

// Pushes what the sandbox's pairs returns for the table at `index` (the iterator over its keys in
// the order that is the same in every run, the table, nil) and returns 3: for a view's __pairs,
// which would otherwise visit its data in the order of Lua's string hashes, seeded per run.
int lua_pairs_in_order(lua_State* L, int index);

// For an __index metamethod refusing a name: raises `text` at the line of the Lua function that
// read the name (level 1: the function that called the metamethod; level 2, used before, named
// that function's caller, so a misspelt name inside a helper was reported at the helper's call).
int raise_at_reader(lua_State* L, const std::string& text);

// Converts the value at `index` into a colour, or raises "context: ..." at the caller's line.
Colour lua_to_colour(lua_State* L, int index, const std::string& context);

// For a check that calls a script's function many times (roger check building twenty worlds,
// calling a teacher function thirty times): after quiet(), print() lines are counted, not shown;
// finish() (or the destructor) puts the sink back and says how many were kept back, "(N more lines
// printed while <what>, not shown)" (found by a probe: 22 and 30 copies of one debugging print).
class QuietPrints {
 public:
  QuietPrints(LuaSandbox& sandbox, std::string what);
  ~QuietPrints();
  QuietPrints(const QuietPrints&) = delete;
  QuietPrints& operator=(const QuietPrints&) = delete;
  void quiet();
  void finish();

 private:
  LuaSandbox& sandbox_;
  std::function<void(const std::string&)> shown_;
  std::string what_;
  size_t hidden_ = 0;
  bool quieted_ = false;
};

// Restores the Lua stack top when it goes out of scope (for C++ code that pushes temporaries).
class LuaStackGuard {
 public:
  explicit LuaStackGuard(lua_State* L);
  ~LuaStackGuard();
  LuaStackGuard(const LuaStackGuard&) = delete;
  LuaStackGuard& operator=(const LuaStackGuard&) = delete;

 private:
  lua_State* L_;
  int top_;
};

// The file a script argument names: the path itself if it is a file, else
// <project>/<folder>/<name>.lua for a bare name, or <project>/<path> for a relative path. Otherwise a roger::Error: "no <kind> '<arg>': ..."
// ending with "; <list_label>: " and the scripts of that folder that `accept` takes (every .lua
// file when it is empty).
std::string resolve_script_path(const std::string& arg, const std::string& folder,
                                const std::string& kind, const std::string& list_label,
                                const std::function<bool(const std::string&)>& accept = {});

// Whether a script's text sets a table field `key` (`key = ...` or `t.key = ...`) outside
// comments, or that of the module it returns (`local p = require("paper") ... return p`): a
// quick look at what kind of script a file is (a curriculum has `stages`, a batch script `runs`)
// without running it.
bool script_has_key(const std::string& path, const std::string& key);

// A Lua file's text as Lua's file loader (luaL_loadfilex: `lua script.lua`, dofile, require)
// compiles it: without a UTF-8 byte-order mark, which editors on Windows write, and with a first
// line starting with '#' (a shebang) emptied, its line break kept so that line numbers hold.
std::string lua_file_text(std::string text);

}  // namespace roger
