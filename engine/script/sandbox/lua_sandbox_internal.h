// lua_sandbox_internal.h: the sandbox's state and the helpers its files share (private to script/sandbox/).
//
// lua_sandbox.cpp holds the LuaSandbox class, lua_sandbox_hooks.cpp the memory and instruction
// budgets and the error reporting, lua_sandbox_libs.cpp the library set a script sees,
// lua_sandbox_costs.cpp the library functions charged for their work, lua_table_library.cpp the
// table functions charged as they go, lua_patterns.cpp the pattern functions counting their
// steps, lua_sandbox_coroutines.cpp the coroutine library under the budgets and
// lua_sandbox_modules.cpp source loading and `require`.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "script/sandbox/lua_sandbox.h"

struct lua_Debug;

namespace roger {

struct LuaSandbox::Impl {
  SandboxLimits limits;
  lua_State* L = nullptr;
  size_t memory_used = 0;
  uint64_t instructions_used = 0;
  size_t bytes_uncharged = 0;  // allocated but not yet charged (kBytesPerInstruction at a time)
  int hook_interval = 1000;
  int call_depth = 0;
  // The thread running now: the state's main thread, or the coroutine a resume entered
  // (lua_sandbox_coroutines.cpp). The allocator, which is told no thread, arms its hook there.
  lua_State* running = nullptr;
  // The processor-time backstop (lua_sandbox_hooks.cpp, check_time).
  int64_t time_floor_ns = 0;        // SandboxLimits::seconds
  double ns_per_instruction = 0.0;   // SandboxLimits::seconds_per_instruction
  int64_t call_start_ns = 0;      // monotonic clock at the top-level call's start
  int64_t call_start_cpu_ns = 0;  // the thread's processor time then
  int64_t excluded_ns = 0;        // monotonic time in the engine's own functions since (lua_protect)
  bool out_of_time = false;       // the limit was passed in this call
  double spent_seconds = 0.0;     // the processor time it had spent then
  int64_t spent_allowed_ns = 0;   // and what it was allowed then (allowed_ns)
  uint64_t charged_units = 0;     // of instructions_used, those charged for C work and allocation
  int big_blocks = 0;             // live blocks of kBigBlock bytes or more
  // What spent the budget when C code did (charge_budget), for the count hook to say it again.
  const char* spent_what = nullptr;
  const char* spent_why = nullptr;
  // The first budget error of the call, "file:line: text", raised again as it was each time a
  // script that caught it with pcall goes on: where and why the budget ran out, not the line
  // after the pcall nor the allocation of the error's own message.
  std::array<char, 640> spent_report{};

  bool main_set = false;
  std::filesystem::path main_dir;  // absolute folder of the main script
  std::string main_dir_display;    // the same folder as the user wrote it ("" for the cwd)
  std::vector<std::filesystem::path> roots;  // require's search folders, absolute and canonical
  std::vector<std::string> chunk_names;  // display names of loaded files (to undo Lua's truncation)
  std::vector<std::string> loading;      // modules being required, outermost first
  std::vector<std::filesystem::path> source_files;  // every file compiled, each once, in load order
  std::function<void(const std::string&)> print;
  // What a print wrote before an argument's __tostring failed: the stand-alone lua has written
  // those arguments and no newline, so the next print's line continues it. A top-level call ends
  // it as a line of its own (end_unended_print), as a terminal would show it.
  std::string print_unended;
  // warn(): off until "@on", as the stand-alone lua has it; a message in pieces is gathered here.
  bool warnings_on = false;
  bool warning_continues = false;
  std::string warning;

  // Filled by the message handler at the moment of an error.
  std::string err_traceback, err_file;
  int err_line = 0;
  bool err_handled = false;

  // Where the script was when the allocator first refused memory in the current top-level call
  // (a memory error runs no message handler, so this is the only record of its line).
  std::array<char, 256> oom_file{};
  int oom_line = 0;

  // A ScriptError thrown by C++ inside a protected C function, re-thrown as is by call().
  std::optional<ScriptError> pending;
  std::string pending_text;
};

namespace sandbox_detail {

// ---- lua_sandbox_hooks.cpp: budgets and error reporting ----

// The sandbox a state belongs to (its address lives in the state's extra space, which threads share).
LuaSandbox::Impl& impl_of(lua_State* L);

// Bytes allocated that count as one instruction: copying and building strings and tables is
// charged to the budget too (a = a .. b copies all of a in one instruction).
constexpr size_t kBytesPerInstruction = 16;

// The allocator: realloc/free refusing to grow the state beyond the memory cap.
void* sandbox_alloc(void* ud, void* ptr, size_t osize, size_t nsize);

// Last resort for an error outside any protected call: throws roger::Error.
int sandbox_panic(lua_State* L);

// Pushes the registry's table at `key`, made with weak keys when first made: what the sandbox
// notes per coroutine (the stopped ones, the xpcalls running on each) goes with the coroutine
// when it is collected.
void push_weak_keyed(lua_State* L, const char* key);

// Puts back the full names of files whose names Lua truncated in a message or traceback.
std::string restore_names(const LuaSandbox::Impl& s, std::string text);

// Splits "file:line: message" into its parts; false when the text has no such prefix.
bool split_location(const std::string& text, std::string& file, int& line, std::string& rest);

// The message handler of every protected call: records the error's location and traceback.
int message_handler(lua_State* L);

// print's text before an argument whose __tostring failed, kept for the next print to continue
// (LuaSandbox::Impl::print_unended); past 64 KiB it is written as a line, so that a loop of such
// prints cannot grow it without bound outside the script's memory limit.
void keep_unended_print(LuaSandbox::Impl& s, const char* text, size_t length);

// Writes what prints left unended as a line of its own (at the end of a top-level call).
void end_unended_print(LuaSandbox::Impl& s);

// The instruction budget's count hook; also checks the processor-time limit.
void count_hook(lua_State* L, lua_Debug* ar);

// A block this large or larger (a long string, a big table, a stack grown for a huge `...`) makes
// single instructions slow: while one lives, the count hook runs every kBigInterval instructions,
// so the time limit is checked between them. Smaller blocks bound an instruction's work to tens
// of microseconds, a thousand of them to tens of milliseconds.
constexpr size_t kBigBlock = 256u << 10;
constexpr int kBigInterval = 8;

// The monotonic clock and the thread's processor time, in nanoseconds.
int64_t monotonic_ns();
int64_t thread_cpu_ns();

// Starts a top-level call's budgets: its instruction count, its clock and the hook's interval.
void start_budgets(LuaSandbox::Impl& s);

// The count hook's interval the budgets want now: kBigInterval while big blocks live, else the
// sandbox's own.
int wanted_interval(const LuaSandbox::Impl& s);

// Whether the current call has spent its instruction budget or its processor time.
bool budget_spent(const LuaSandbox::Impl& s);

// Raises the spent budget's error (as the count hook words it) at the Lua caller's file:line, and
// arms L's hook to say it again at its every instruction.
[[noreturn]] void raise_spent_budget(lua_State* L);

// Raises `text` at the innermost calling Lua function's file:line.
[[noreturn]] void raise_at_lua_line(lua_State* L, const char* text);

// Counts `units` of work done in C against the call's budget; once it is spent, raises
// "<what>: instruction budget of N exceeded: <why>" at the Lua caller's file:line (lua_charge's
// message when what is null). Saturates: a huge count cannot wrap the total around.
void charge_budget(lua_State* L, uint64_t units, const char* what, const char* why);

// A coroutine's switch that succeeded (a resume that returned true), counted as kUnwindCost VM
// instructions, their processor time allowed as theirs: Debian's Lua, built as C++, unwinds a
// yield with a C++ exception, microseconds where an instruction takes nanoseconds, so a generator
// would otherwise be stopped by the time budget as if it did long work in C; the instruction
// budget still bounds how many switches a call makes. A resume that fails (an error) earns none,
// nor does an error caught by pcall: a loop of errors that each did long C work (an __index chain
// too long) must still meet the time budget.
constexpr uint64_t kUnwindCost = 64;
void charge_unwinding(lua_State* L, const char* what);

// ---- lua_sandbox_costs.cpp: library functions charged for the work their arguments ask ----

// Replaces string.rep, table.concat, table.sort, utf8.len, ... by versions charging their work.
void install_charges(lua_State* L);

// ---- lua_table_library.cpp: table.insert, remove, move, concat, unpack charged as they go ----

// Replaces those table functions by ports of Lua 5.4's charging each element they touch.
void install_table_library(lua_State* L);

// ---- lua_patterns.cpp: string.find, match, gmatch, gsub counting their steps ----

// Replaces the pattern functions of the string table at `string_table` by the budgeted ones.
void install_patterns(lua_State* L, int string_table);

// ---- lua_pairs.cpp: pairs in an order that is the same in every run ----

// Replaces pairs by one visiting a plain table's keys in a fixed order (numbers, strings, booleans),
// and next, rawget, rawlen and rawset by ones that read a view's data (lua_new_view) and write
// it by the view's rule.
void install_pairs(lua_State* L);

// ---- lua_sandbox_libs.cpp: what a script sees ----

// Opens the permitted libraries and installs the replacements (run protected: it allocates).
int open_sandbox(lua_State* L);

// Before a budget's error is raised on L: the handler of every xpcall running on L is replaced by
// one keeping the message, so no script's handler runs for it (Lua would run one with hooks off
// for an error raised in the count hook). Allocates nothing.
void disarm_handlers(lua_State* L);

// ---- lua_sandbox_coroutines.cpp: the coroutine library under the call's budgets ----

// Replaces coroutine.resume, wrap and close by versions that keep the budgets (run protected).
void install_coroutines(lua_State* L);

// ---- lua_sandbox_modules.cpp: source files and require ----

// The registry key of require's module cache.
constexpr const char* kModulesKey = "roger.modules";

// Whether `file` lies under `folder` (both normalized, absolute).
bool inside(const std::filesystem::path& folder, const std::filesystem::path& file);

// The contents of a script file; refuses files larger than the memory cap before reading them.
std::string read_file(const std::filesystem::path& path, const std::string& shown, size_t limit);

// Compiles source text as a "@shown" chunk and pushes it, or returns the error as a ScriptError.
std::optional<ScriptError> compile(lua_State* L, LuaSandbox::Impl& s, std::string text,
                                   const std::string& shown);

// Records a compiled file once.
void note_source_file(LuaSandbox::Impl& s, const std::filesystem::path& file);

// require(name), the sandbox's replacement for the package library's.
int sandbox_require(lua_State* L);

}  // namespace sandbox_detail
}  // namespace roger
