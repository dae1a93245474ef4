// lua_sandbox.cpp: the LuaSandbox class (the state, the main script, loading and protected calls),
// ScriptError and where scripts are found.
#include "script/sandbox/lua_sandbox.h"

#include <algorithm>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <lua.hpp>

#include "core/fileio.h"
#include "core/install.h"
#include "core/text.h"
#include "script/sandbox/lua_sandbox_internal.h"

namespace roger {
namespace fs = std::filesystem;
using namespace sandbox_detail;

namespace {
// warn(...) as the stand-alone lua has it (found by a probe: it did nothing): off until "@on",
// "@off" turns it off again; a message, its pieces gathered, is one line "Lua warning: ..." to the
// sandbox's print sink (stderr, unless a caller quiets prints).
void sandbox_warn(void* ud, const char* message, int continues) {
  auto& s = *static_cast<LuaSandbox::Impl*>(ud);
  if (!s.warning_continues && !continues && message[0] == '@') {  // a control message
    if (std::strcmp(message, "@on") == 0) s.warnings_on = true;
    if (std::strcmp(message, "@off") == 0) s.warnings_on = false;
    return;
  }
  if (s.warnings_on) s.warning += message;
  s.warning_continues = continues != 0;
  if (continues) return;
  if (s.warnings_on && s.print) s.print("Lua warning: " + s.warning);
  s.warning.clear();
}

// Whether a traceback names a line of Lua other than `file`:`line`, the message's own, outside the
// message's frame: one whose Lua frames are all that line (an error of roger.stage{...} at the top
// of a script: "[C]: in field 'stage'", "s.lua:16: in main chunk") says nothing the message does
// not. The frames inside the message's frame are those of the library that raised the error at its
// caller's line (error(text, 2) and above), so they say nothing to its caller either (found by a
// probe: a scenario's noise out of range showed lib/body.lua's and lib/place.lua's lines).
bool traceback_adds(const std::string& traceback, const std::string& file, int line) {
  const std::string own = "\t" + file + ":" + std::to_string(line) + ":";
  const size_t own_frame = traceback.find("\n" + own);
  size_t at = own_frame == std::string::npos ? traceback.find('\n') : own_frame;
  while (at != std::string::npos) {
    const size_t end = traceback.find('\n', at + 1);
    const std::string frame = traceback.substr(at + 1, end == std::string::npos ? std::string::npos : end - at - 1);
    if (frame.rfind("\t[C]:", 0) != 0 && frame.rfind(own, 0) != 0) return true;
    at = end;
  }
  return false;
}

// "file:line: message\ntraceback", leaving out the parts that are unknown, and a traceback that
// names no other line (docs/cli.md: every error is one message; the record keeps the traceback).
std::string compose(const std::string& message, const std::string& file, int line,
                    const std::string& traceback) {
  std::string text;
  if (!file.empty()) text = file + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": ";
  text += message;
  if (!traceback.empty() && (file.empty() || line <= 0 || traceback_adds(traceback, file, line)))
    text += "\n" + traceback;
  return text;
}
}  // namespace

ScriptError::ScriptError(std::string message_in, std::string file_in, int line_in,
                         std::string traceback_in)
    : Error(compose(message_in, file_in, line_in, traceback_in)),
      message(std::move(message_in)),
      file(std::move(file_in)),
      line(line_in),
      traceback(std::move(traceback_in)) {}

fs::path project_root() {
  if (const char* home = std::getenv("ROGER_HOME"); home && *home) return fs::path(home);
  if (std::optional<fs::path> installed = installed_data_dir()) return *installed;
  return fs::path(ROGER_SOURCE_DIR);
}

std::string project_in_use() {
  std::error_code ec;
  const char* home = std::getenv("ROGER_HOME");
  if (home && *home)
    return "ROGER_HOME=" + std::string(home) +
           (fs::is_directory(home, ec) ? std::string()
                                       : ", which is not a folder: set it to a project holding scenarios/, "
                                         "curricula/ and scripts/, or unset it");
  const fs::path root = project_root();
  if (installed_data_dir()) return root.string() + ", installed beside the program";
  // Found by a probe: a copied program named a source tree that was no longer there.
  if (!fs::is_directory(root / "scenarios", ec))
    return root.string() + ", the source tree this roger was built from, which is no longer there: set ROGER_HOME "
                           "to a project folder, or install roger (cmake --install) and run the installed one";
  return root.string() + ", the source tree this roger was built from";
}

std::string lua_file_here(const std::string& name) {
  std::error_code ec;
  const std::string file = name + ".lua";
  const bool bare = name.find('/') == std::string::npos && fs::path(name).extension() != ".lua";
  return bare && fs::is_regular_file(file, ec) ? file : std::string();
}

// The shipped tree (installed, or the source tree this roger was built from) when ROGER_HOME names
// a project of one's own: its libraries and scripts are found after the project's.
std::optional<fs::path> shipped_tree_apart() {
  std::error_code ec;
  const fs::path project = fs::weakly_canonical(project_root(), ec);
  if (ec || !fs::is_directory(project, ec)) return std::nullopt;  // a ROGER_HOME naming nothing is said as such
  const std::optional<fs::path> installed = installed_data_dir();
  const fs::path shipped = fs::weakly_canonical(installed ? *installed : fs::path(ROGER_SOURCE_DIR), ec);
  if (ec || shipped == project || !fs::is_directory(shipped / "scenarios", ec)) return std::nullopt;
  return shipped;
}

std::vector<fs::path> module_search_roots(const fs::path& main_folder, bool batch_script) {
  std::vector<fs::path> roots;
  if (!main_folder.empty()) roots.push_back(main_folder);
  const fs::path project = project_root();
  // A batch script's libraries are other batch scripts (scripts/paper.lua), a curriculum's and a
  // scenario's are in curricula/ and scenarios/ (docs/batch.md, docs/scenarios.md).
  const std::vector<const char*> order = batch_script ? std::vector<const char*>{"scripts", "curricula", "scenarios"}
                                                      : std::vector<const char*>{"scenarios", "curricula", "scripts"};
  for (const char* name : order) {
    std::error_code ec;
    const fs::path p = fs::weakly_canonical(project / name, ec);
    if (!ec && std::find(roots.begin(), roots.end(), p) == roots.end()) roots.push_back(p);
  }
  // Then the project itself, for "curricula.sorting" (module_root_takes): found by a probe, a
  // curriculum's require("sorting") met scenarios/sorting.lua first and could not reach the
  // curriculum of that name.
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(project, ec);
  if (!ec && std::find(roots.begin(), roots.end(), p) == roots.end()) roots.push_back(p);
  // Last, with ROGER_HOME naming a project of one's own, the shipped tree's folders (installed, or
  // the source tree), so that its libraries (lib.shapes, lib.skills) are found without copying
  // them (found by a probe: a lab's project folder could use none of them).
  if (const std::optional<fs::path> shipped = shipped_tree_apart())
    for (const char* name : order) {
      const fs::path q = fs::weakly_canonical(*shipped / name, ec);
      if (!ec && std::find(roots.begin(), roots.end(), q) == roots.end()) roots.push_back(q);
    }
  return roots;
}

bool looks_like_batch_script(const fs::path& path) {
  std::string text;
  try {
    text = read_file_text(path.string());
  } catch (const std::exception&) {
    return false;  // unreadable: loading it says why
  }
  // A cheap look first: most scripts (every scenario) name none of a batch script's fields.
  if (text.find("runs") == std::string::npos && text.find("evaluations") == std::string::npos &&
      text.find("curriculum") == std::string::npos)
    return false;
  const std::string p = path.string();
  if (script_has_key(p, "stages")) return false;  // a curriculum (script_kind_of looks at it first)
  return script_has_key(p, "runs") || script_has_key(p, "curriculum") || script_has_key(p, "evaluations");
}

LuaSandbox::LuaSandbox(const SandboxLimits& limits) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.limits = limits;
  s.hook_interval = int(std::clamp<uint64_t>(limits.instructions, 1, 1000));
  constexpr double kSlower = kSanitizedAllowance;  // a sanitizer build's instrumented C++ (lua_sandbox.h)
  s.time_floor_ns = int64_t(std::clamp(limits.seconds, 0.0, 1e6) * 1e9 * kSlower);
  s.ns_per_instruction = std::clamp(limits.seconds_per_instruction, 0.0, 1.0) * 1e9 * kSlower;
  s.print = [](const std::string& line) { std::cerr << line << '\n'; };
  s.L = lua_newstate(sandbox_alloc, &s);
  if (!s.L)
    throw Error("cannot create a Lua state within the script memory limit of " +
                std::to_string(limits.memory_bytes) + " bytes");
  *static_cast<Impl**>(lua_getextraspace(s.L)) = &s;
  s.running = s.L;
  lua_atpanic(s.L, sandbox_panic);
  lua_setwarnf(s.L, sandbox_warn, &s);
  lua_sethook(s.L, count_hook, LUA_MASKCOUNT, s.hook_interval);
  lua_pushcfunction(s.L, open_sandbox);
  if (lua_pcall(s.L, 0, 0, 0) != LUA_OK) {
    const std::string msg = lua_isstring(s.L, -1) ? lua_tostring(s.L, -1) : "unknown error";
    lua_close(s.L);
    s.L = nullptr;
    throw Error("cannot open the Lua libraries: " + msg);
  }
  s.roots = module_search_roots();
}

LuaSandbox::~LuaSandbox() {
  if (impl_ && impl_->L) {
    // No finalizer written in Lua exists (setmetatable refuses __gc); to-be-closed variables
    // still pending run their __close at close, under a fresh budget.
    impl_->instructions_used = 0;
    impl_->out_of_time = false;
    lua_sethook(impl_->L, count_hook, LUA_MASKCOUNT, impl_->hook_interval);
    lua_close(impl_->L);
    try {
      end_unended_print(*impl_);  // a __close's print
    } catch (...) {  // a sink that throws loses the line, not the program
    }
  }
}

LuaSandbox::LuaSandbox(LuaSandbox&&) noexcept = default;
LuaSandbox& LuaSandbox::operator=(LuaSandbox&& other) noexcept {
  if (this != &other) {
    LuaSandbox doomed(std::move(*this));
    impl_ = std::move(other.impl_);
  }
  return *this;
}

lua_State* LuaSandbox::state() const { return impl_->L; }
const SandboxLimits& LuaSandbox::limits() const { return impl_->limits; }
size_t LuaSandbox::memory_used() const { return impl_->memory_used; }
uint64_t LuaSandbox::instructions_used() const { return impl_->instructions_used; }

QuietPrints::QuietPrints(LuaSandbox& sandbox, std::string what)
    : sandbox_(sandbox), shown_(sandbox.print_sink()), what_(std::move(what)) {}

QuietPrints::~QuietPrints() { finish(); }

void QuietPrints::quiet() {
  quieted_ = true;
  sandbox_.set_print([this](const std::string&) { ++hidden_; });
}

void QuietPrints::finish() {
  if (!quieted_) return;
  quieted_ = false;
  sandbox_.set_print(shown_);
  if (hidden_ && shown_)
    shown_("(" + counted(static_cast<long long>(hidden_), "more line") + " printed while " + what_ + ", not shown)");
  hidden_ = 0;
}

void sandbox_detail::keep_unended_print(LuaSandbox::Impl& s, const char* text, size_t length) {
  constexpr size_t kMostKept = 64u << 10;
  s.print_unended.append(text, length);
  if (s.print_unended.size() > kMostKept) end_unended_print(s);
}

void sandbox_detail::end_unended_print(LuaSandbox::Impl& s) {
  if (s.print_unended.empty()) return;
  std::string line;
  line.swap(s.print_unended);
  if (s.print) s.print(line);
}

void LuaSandbox::set_print(std::function<void(const std::string&)> sink) {
  impl_->print = std::move(sink);
}

const std::function<void(const std::string&)>& LuaSandbox::print_sink() const { return impl_->print; }

void LuaSandbox::set_main_script(const std::string& path) {
  Impl& s = *impl_;
  std::error_code ec;
  const fs::path folder = fs::weakly_canonical(fs::absolute(fs::path(path), ec).parent_path(), ec);
  s.main_dir = folder;
  s.main_dir_display = fs::path(path).parent_path().string();
  s.roots = module_search_roots(folder, looks_like_batch_script(fs::absolute(fs::path(path), ec)));
  s.main_set = true;
}

std::vector<fs::path> LuaSandbox::module_roots() const { return impl_->roots; }

bool module_root_takes(const std::vector<fs::path>& roots, size_t index, const std::string& name) {
  std::error_code ec;
  if (index == 0 || index >= roots.size() || roots[index] != fs::weakly_canonical(project_root(), ec)) return true;
  const std::string folder = name.substr(0, name.find('.'));
  return name.find('.') != std::string::npos && (folder == "scenarios" || folder == "curricula" || folder == "scripts");
}

std::string LuaSandbox::display_name(const fs::path& path) const {
  std::error_code ec;
  const fs::path real = fs::weakly_canonical(fs::absolute(path, ec), ec);
  const fs::path root = fs::weakly_canonical(project_root(), ec);
  if (!ec && path.is_absolute() && inside(root, real)) return real.lexically_relative(root).string();
  return path.string();
}

void LuaSandbox::load_file(const std::string& path) {
  Impl& s = *impl_;
  const std::string shown = display_name(path);
  std::string text;
  try {
    text = read_file(path, shown, s.limits.memory_bytes);
  } catch (const Error& e) {
    throw ScriptError(e.what(), "", 0, "");
  }
  if (auto failure = compile(s.L, s, std::move(text), shown)) throw *failure;
  std::error_code ec;
  const fs::path real = fs::weakly_canonical(path, ec);  // absolute: the file was just read
  note_source_file(s, ec ? fs::path(path).lexically_normal() : real);
}

const std::vector<fs::path>& LuaSandbox::source_files() const { return impl_->source_files; }

void LuaSandbox::load_string(const std::string& code, const std::string& chunkname) {
  Impl& s = *impl_;
  if (!chunkname.empty() && chunkname[0] == '@') {
    if (auto failure = compile(s.L, s, code, chunkname.substr(1))) throw *failure;
    return;
  }
  if (code.rfind(LUA_SIGNATURE, 0) == 0)
    throw ScriptError("attempt to load a binary chunk: roger loads Lua source text only", chunkname,
                      0, "");
  const int status = luaL_loadbufferx(s.L, code.data(), code.size(), chunkname.c_str(), "t");
  if (status == LUA_OK) return;
  std::string msg = lua_isstring(s.L, -1) ? lua_tostring(s.L, -1) : "cannot compile";
  lua_pop(s.L, 1);
  std::string file, rest;
  int line = 0;
  if (split_location(msg, file, line, rest)) throw ScriptError(rest, file, line, "");
  throw ScriptError(msg, "", 0, "");
}

void LuaSandbox::call_protected(int nargs, const std::function<void(lua_State*)>& body) {
  lua_State* L = impl_->L;
  lua_pushcfunction(L, [](lua_State* L) -> int {
    auto* fn = static_cast<const std::function<void(lua_State*)>*>(lua_touserdata(L, -1));
    lua_pop(L, 1);
    return lua_protect(L, [&]() {
      (*fn)(L);
      return 0;
    });
  });
  lua_insert(L, -(nargs + 1));  // below the values the body reads
  lua_pushlightuserdata(L, const_cast<std::function<void(lua_State*)>*>(&body));
  call(nargs + 1, 0);
}

void LuaSandbox::read_returned_table(const std::string& file, const std::function<int()>& line,
                                     const std::function<void(lua_State*)>& body) {
  try {
    call_protected(1, body);
  } catch (const ScriptError& e) {
    if (!e.file.empty()) throw;
    throw ScriptError(e.message, file, line(), "");
  }
}

namespace {

// The file of the function in slot `at`, for errors that carry no location (memory).
std::string file_of_function(lua_State* L, int at) {
  lua_Debug ar;
  lua_pushvalue(L, at);
  if (lua_getinfo(L, ">S", &ar) && ar.source && ar.source[0] == '@') return ar.source + 1;
  return "";
}

// A call from C++ (not one the script makes) starts afresh: nothing spent, nothing pending, the
// budgets full.
void begin_top_level_call(LuaSandbox::Impl& s) {
  s.spent_what = s.spent_why = nullptr;
  s.spent_report[0] = '\0';
  s.oom_line = 0;
  s.pending.reset();
  s.pending_text.clear();
  sandbox_detail::start_budgets(s);
}

// The error a failed lua_pcall left on the stack (popped), as the ScriptError it stands for: the
// sandbox's own pending error, the memory limit (at the allocation's line when known), or the
// script's message, split into file, line and message, with the handler's traceback.
[[noreturn]] void throw_call_error(LuaSandbox::Impl& s, int status, const std::string& entry_file) {
  lua_State* L = s.L;
  std::string msg = "unknown error";
  if (lua_isstring(L, -1)) {
    size_t length = 0;
    const char* text = lua_tolstring(L, -1, &length);
    msg.assign(text, length);  // all of it: a message may hold a NUL
  }
  lua_pop(L, 1);
  if (s.pending && msg == s.pending_text) {
    ScriptError error = *s.pending;
    s.pending.reset();
    throw error;
  }
  if (status == LUA_ERRMEM) {
    const bool located = s.oom_line > 0;
    // How to raise it said too (found by a probe: neither budget's message said where it is set).
    throw ScriptError("not enough memory (script memory limit of " +
                          std::to_string(s.limits.memory_bytes >> 20) + " MiB; if the data is meant, raise it: "
                          "--lua-memory MIB, or a batch script's limits = { memory = MIB })",
                      located ? restore_names(s, s.oom_file.data()) : entry_file, located ? s.oom_line : 0, "");
  }
  // The script's own bytes, made printable: a record and a terminal take every message.
  msg = printable_text(msg);
  if (status == LUA_ERRERR) msg = "error while handling an error (" + msg + ")";
  msg = restore_names(s, msg);
  const std::string traceback = s.err_handled ? printable_text(restore_names(s, s.err_traceback)) : "";
  std::string file, rest;
  int line = 0;
  if (split_location(msg, file, line, rest)) throw ScriptError(rest, file, line, traceback);
  throw ScriptError(msg, s.err_handled ? restore_names(s, s.err_file) : entry_file,
                    s.err_handled ? s.err_line : 0, traceback);
}

}  // namespace

void LuaSandbox::call(int nargs, int nresults) {
  Impl& s = *impl_;
  lua_State* L = s.L;
  const int base = lua_gettop(L) - nargs;  // the function's slot
  if (!lua_checkstack(L, 2)) throw Error("Lua stack exhausted");
  const std::string entry_file = file_of_function(L, base);
  lua_pushcfunction(L, message_handler);
  lua_insert(L, base);
  if (s.call_depth == 0) begin_top_level_call(s);
  s.err_handled = false;
  int status;
  {
    struct Depth {  // restored even if a panic unwinds through lua_pcall
      int& depth;
      ~Depth() { --depth; }
    } depth{++s.call_depth};
    status = lua_pcall(L, nargs, nresults, base);
  }
  lua_remove(L, base);
  if (s.call_depth == 0) end_unended_print(s);
  if (status != LUA_OK) throw_call_error(s, status, entry_file);
  // A budget's error that a script's pcall or xpcall caught, its function then ending at once
  // (`return pcall(loop)`): no instruction came after the catch to raise it again, and the call
  // returned as if the budget held (found by a probe). It is the budget's error all the same.
  if (sandbox_detail::budget_spent(s) && s.spent_report[0] != '\0') {
    lua_settop(L, base - 1);
    lua_pushstring(L, s.spent_report.data());
    throw_call_error(s, LUA_ERRRUN, entry_file);
  }
}

void LuaSandbox::run_file(const std::string& path, int nresults) {
  if (!impl_->main_set) set_main_script(path);
  load_file(path);
  call(0, nresults);
}

namespace {

// `path`, refused when it is no text: a program or another binary file given for a script would
// otherwise be read as Lua, giving a page of "undefined global 'ELF'" or a guess at its kind. A
// Lua binary chunk passes, for the loader to refuse by name.
const std::string& text_script(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[4096];
  in.read(head, sizeof head);
  const std::string bytes(head, size_t(in.gcount()));
  const size_t nul = bytes.find('\0');
  if (nul != std::string::npos && bytes.rfind(LUA_SIGNATURE, 0) != 0)
    throw Error("'" + path + "' is no Lua script: it is not text (a NUL byte at offset " + std::to_string(nul) +
                "; a program or another binary file?)");
  // A file roger wrote, given where a script goes (found by a probe: the policy and the curriculum
  // swapped read "policy.json:1: unexpected symbol near '{'").
  const std::string ext = std::filesystem::path(path).extension().string();
  const size_t first = bytes.find_first_not_of(" \t\r\n");
  if (ext == ".json" && first != std::string::npos && (bytes[first] == '{' || bytes[first] == '['))
    throw Error("'" + path + "' is no Lua script: it is JSON (a policy roger train wrote, or a result?); give the "
                "script (a curriculum, a scenario, ...) here, and a policy with --policy, --init or --skill");
  static const std::pair<const char*, const char*> written[] = {
      {".md", "Markdown"}, {".csv", "CSV"}, {".png", "PNG image"}, {".svg", "SVG image"}, {".html", "HTML page"}};
  for (const auto& [suffix, what] : written)
    if (ext == suffix)
      throw Error("'" + path + "' is no Lua script: it is a " + what + " (a report roger wrote?); give a Lua script "
                  "(.lua) here");
  return path;
}

}  // namespace

// The docs' examples are installed with the documentation (found by a probe: the docs' commands
// failed on an installed copy, and nothing said where the examples were).
std::string installed_docs_hint(const std::string& path) {
  namespace fs = std::filesystem;
  const std::string docs = "docs/";
  std::error_code ec;
  if (path.rfind(docs, 0) != 0 || fs::exists(path, ec)) return "";
  const fs::path installed = project_root().parent_path() / "doc" / "roger" / path.substr(docs.size());
  if (!fs::is_regular_file(installed, ec)) return "";
  return "; the documentation's files are installed apart from the project: " + installed.string();
}

namespace {

// "; scenarios/unobstructed.lua is a scenario" for a bare name that is a script of another
// folder (found by a probe: roger.make("unobstructed", ...) said only that no curriculum has the
// name), "; it is a folder" for a folder; "" otherwise.
std::string misnamed_hint(const std::string& arg, const std::string& folder_name) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(arg, ec)) return "; '" + arg + "' is a folder: give one script in it";
  if (arg.find('/') != std::string::npos) return "";
  static const std::pair<const char*, const char*> kinds[] = {
      {"curricula", "a curriculum or a skill script"}, {"scenarios", "a scenario"}, {"scripts", "a batch script"}};
  const std::string file = fs::path(arg).extension() == ".lua" ? arg : arg + ".lua";
  for (const auto& [folder, what] : kinds)
    if (folder != folder_name && fs::is_regular_file(project_root() / folder / file, ec))
      return std::string("; ") + folder + "/" + file + " is " + what + ", another kind of script";
  return "";
}

}  // namespace

std::string resolve_script_path(const std::string& arg, const std::string& folder_name,
                                const std::string& kind, const std::string& list_label,
                                const std::function<bool(const std::string&)>& accept) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_regular_file(arg, ec)) return text_script(arg);
  if (arg.empty()) throw Error("no " + kind + " given: the name is empty");  // not "curricula/.lua does not exist"
  const fs::path folder = project_root() / folder_name;
  const bool bare = arg.find('/') == std::string::npos;
  const std::string file = fs::path(arg).extension() == ".lua" ? arg : arg + ".lua";
  if (bare && fs::is_regular_file(folder / file, ec)) return text_script((folder / file).string());
  // Then the shipped tree's, as require finds its libraries (found by a probe: with ROGER_HOME a
  // project of one's own, a copy of paper.lua could not find the scenario 'unobstructed').
  const std::optional<fs::path> shipped = shipped_tree_apart();
  if (bare && shipped && fs::is_regular_file(*shipped / folder_name / file, ec))
    return text_script((*shipped / folder_name / file).string());
  // A path relative to the project (tests/scripts/x.lua, or one a script named and the loader
  // recorded so) is the same file from any folder.
  if (!bare && fs::path(arg).is_relative() && fs::is_regular_file(project_root() / arg, ec))
    return text_script((project_root() / arg).string());
  // The project's and the shipped tree's, said so when they are two (found by a probe: a project
  // of its own without scenarios/ was said to hold the shipped ones there).
  std::vector<std::string> known;
  for (const fs::path& in : {folder, shipped ? *shipped / folder_name : folder})
    for (const auto& entry : fs::directory_iterator(in, ec))
      if (entry.path().extension() == ".lua" && (!accept || accept(entry.path().string())))
        known.push_back(entry.path().stem().string());
  std::sort(known.begin(), known.end());
  known.erase(std::unique(known.begin(), known.end()), known.end());
  // Which project was looked in, when it is not the source tree this roger was built from (the
  // tests' and a developer's): an installed tree's, or $ROGER_HOME's, which may point nowhere.
  const char* home = std::getenv("ROGER_HOME");
  const bool elsewhere = (home && *home) || fs::weakly_canonical(project_root(), ec) !=
                                                fs::weakly_canonical(fs::path(ROGER_SOURCE_DIR), ec);
  const std::string where = elsewhere ? " (the project is " + project_in_use() + ")" : "";
  const std::string here = lua_file_here(arg);
  const std::string hint = (here.empty() ? "" : "; " + here + " is a file here: name it with its \".lua\"") +
                           installed_docs_hint(arg) + misnamed_hint(arg, folder_name);
  const std::string nearest = bare ? suggestion(fs::path(arg).stem().string(), known) : "";
  throw Error("no " + kind + " '" + arg + "'" + nearest + ": " +
              (bare ? "not a file, and " + folder_name + "/" + file + " does not exist" + where
                    : std::string(fs::exists(arg, ec) ? "not a regular file" : "no such file here or in the project" + where)) +
              hint + (known.empty() ? "" : "; " + list_label + (shipped ? " and roger's own" : "") + ": " + join(known)));
}

}  // namespace roger
