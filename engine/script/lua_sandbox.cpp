#include "script/lua_sandbox.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

#include <lua.hpp>

namespace roger {
namespace fs = std::filesystem;

struct LuaSandbox::Impl {
  SandboxLimits limits;
  lua_State* L = nullptr;
  size_t memory_used = 0;
  uint64_t instructions_used = 0;
  int hook_interval = 1000;
  int call_depth = 0;

  bool main_set = false;
  fs::path main_dir;               // absolute folder of the main script
  std::string main_dir_display;    // the same folder as the user wrote it ("" for the cwd)
  std::vector<fs::path> roots;     // require's search folders, absolute and canonical
  std::vector<std::string> chunk_names;  // display names of loaded files (to undo Lua's truncation)
  std::vector<std::string> loading;      // modules being required, outermost first
  std::vector<fs::path> source_files;    // every file compiled, each once, in load order
  std::function<void(const std::string&)> print;

  // Filled by the message handler at the moment of an error.
  std::string err_traceback, err_file;
  int err_line = 0;
  bool err_handled = false;

  // A ScriptError thrown by C++ inside a protected C function, re-thrown as is by call().
  std::optional<ScriptError> pending;
  std::string pending_text;
};

namespace {

constexpr const char* kModulesKey = "roger.modules";
constexpr const char* kSandboxNote = "roger scripts are sandboxed (no os, io, debug, package)";

// The sandbox a state belongs to (its address lives in the state's extra space, which threads share).
LuaSandbox::Impl& impl_of(lua_State* L) {
  return **static_cast<LuaSandbox::Impl**>(lua_getextraspace(L));
}

// The allocator: the usual realloc/free pair, refusing to grow the state beyond the cap. Lua then
// runs an emergency collection and retries before raising "not enough memory".
void* sandbox_alloc(void* ud, void* ptr, size_t osize, size_t nsize) {
  auto* s = static_cast<LuaSandbox::Impl*>(ud);
  const size_t old = ptr ? osize : 0;  // for new blocks osize encodes the object type
  if (nsize == 0) {
    std::free(ptr);
    s->memory_used -= old;
    return nullptr;
  }
  if (nsize > old && nsize - old > s->limits.memory_bytes - std::min(s->memory_used, s->limits.memory_bytes))
    return nullptr;
  void* p = std::realloc(ptr, nsize);
  if (p) s->memory_used = s->memory_used - old + nsize;
  return p;
}

// Last resort: an error outside any protected call. Throwing unwinds out of the Lua API (the
// library is compiled as C++) instead of letting Lua call abort().
int sandbox_panic(lua_State* L) {
  const char* msg = lua_tostring(L, -1);
  throw Error(std::string("Lua panic (error outside a protected call): ") + (msg ? msg : "?"));
}

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

// The instruction budget: a count hook every hook_interval instructions. Once the budget is spent
// it fires on every instruction, so a script that catches the error with pcall is stopped again
// at its next instruction until the error reaches the engine.
void count_hook(lua_State* L, lua_Debug* ar) {
  auto& s = impl_of(L);
  s.instructions_used += uint64_t(lua_gethookcount(L));
  if (s.instructions_used <= s.limits.instructions) return;
  lua_sethook(L, count_hook, LUA_MASKCOUNT, 1);
  const auto budget = static_cast<unsigned long long>(s.limits.instructions);
  char text[96];
  std::snprintf(text, sizeof text, "instruction budget of %llu exceeded (runaway loop?)", budget);
  if (lua_getinfo(L, "Sl", ar) && ar->currentline > 0)
    lua_pushfstring(L, "%s:%d: %s", ar->short_src, ar->currentline, text);
  else
    lua_pushstring(L, text);
  lua_error(L);
}

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

// load(chunk [, chunkname [, mode [, env]]]) with the mode forced to text: the original load is
// the upvalue; the argument count is kept because an explicit nil env means "no environment".
int sandbox_load(lua_State* L) {
  const int n = lua_gettop(L);
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_pushvalue(L, 1);
  if (n >= 2) lua_pushvalue(L, 2); else lua_pushnil(L);
  lua_pushliteral(L, "t");
  if (n >= 4) lua_pushvalue(L, 4);
  lua_call(L, n >= 4 ? 4 : 3, LUA_MULTRET);
  return lua_gettop(L) - n;
}

// print(...): tab-separated tostring() of the arguments, one line to the sandbox's sink.
int sandbox_print(lua_State* L) {
  const int n = lua_gettop(L);
  luaL_Buffer b;
  luaL_buffinit(L, &b);
  for (int i = 1; i <= n; ++i) {
    if (i > 1) luaL_addchar(&b, '\t');
    luaL_tolstring(L, i, nullptr);
    luaL_addvalue(&b);
  }
  luaL_pushresult(&b);
  std::string line = lua_tostring(L, -1);
  return lua_protect(L, [&]() {
    auto& s = impl_of(L);
    if (s.print) s.print(line);
    return 0;
  });
}

// Dotted identifiers only, so a module name can never climb out of a folder ("..", "/").
bool valid_module_name(const std::string& name) {
  if (name.empty() || name.front() == '.' || name.back() == '.') return false;
  char prev = 0;
  for (char c : name) {
    const bool ok = std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.';
    if (!ok || (c == '.' && prev == '.')) return false;
    prev = c;
  }
  return true;
}

// Whether `file` lies under `folder` (both normalized, absolute).
bool inside(const fs::path& folder, const fs::path& file) {
  const fs::path rel = file.lexically_relative(folder);
  return !rel.empty() && *rel.begin() != "..";
}

// The contents of a script file; refuses files larger than the memory cap before reading them.
std::string read_file(const fs::path& path, const std::string& shown, size_t limit) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw Error("cannot open '" + shown + "': " +
                (fs::exists(path, ec) ? "not a regular file" : "no such file"));
  const auto size = fs::file_size(path, ec);
  if (!ec && size > limit)
    throw Error("cannot load '" + shown + "': the file is larger than the script memory limit");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open '" + shown + "': " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// How a module file is shown in messages: relative to the project root when inside it, else
// under the main script's folder as the user wrote it, else absolute.
std::string module_display(const LuaSandbox::Impl& s, const fs::path& root, const std::string& rel) {
  std::error_code ec;
  const fs::path proot = fs::weakly_canonical(project_root(), ec);
  const fs::path file = root / rel;
  if (inside(proot, file)) return file.lexically_relative(proot).string();
  if (s.main_set && root == s.main_dir)
    return (fs::path(s.main_dir_display) / rel).lexically_normal().string();
  return file.string();
}

// Compiles source text as a "@shown" chunk and pushes it, or returns the error as a ScriptError.
// Like luaL_loadfilex: skips a UTF-8 byte-order mark and a first line starting with '#' (keeping
// the line count); refuses bytecode.
std::optional<ScriptError> compile(lua_State* L, LuaSandbox::Impl& s, std::string text,
                                   const std::string& shown) {
  if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);
  if (text.rfind(LUA_SIGNATURE, 0) == 0)
    return ScriptError("attempt to load a binary chunk: roger loads Lua source text only "
                       "(precompiled bytecode is refused)", shown, 0, "");
  if (!text.empty() && text[0] == '#') text.erase(0, std::min(text.find('\n'), text.size()));
  if (std::find(s.chunk_names.begin(), s.chunk_names.end(), shown) == s.chunk_names.end())
    s.chunk_names.push_back(shown);
  const std::string chunkname = "@" + shown;
  const int status = luaL_loadbufferx(L, text.data(), text.size(), chunkname.c_str(), "t");
  if (status == LUA_OK) return std::nullopt;
  std::string msg = lua_isstring(L, -1) ? lua_tostring(L, -1) : "cannot compile";
  lua_pop(L, 1);
  if (status == LUA_ERRMEM)
    return ScriptError("not enough memory to compile (script memory limit of " +
                       std::to_string(s.limits.memory_bytes >> 20) + " MiB)", shown, 0, "");
  msg = restore_names(s, msg);
  std::string file, rest;
  int line = 0;
  if (split_location(msg, file, line, rest)) return ScriptError(rest, file, line, "");
  return ScriptError(msg, shown, 0, "");
}

// Records a compiled file once.
void note_source_file(LuaSandbox::Impl& s, const fs::path& file) {
  if (std::find(s.source_files.begin(), s.source_files.end(), file) == s.source_files.end())
    s.source_files.push_back(file);
}

// require(name): dotted names ("lib.shapes" -> lib/shapes.lua) searched in the sandbox's roots
// only, text chunks only, cached, with cycles reported.
int sandbox_require(lua_State* L) {
  if (lua_type(L, 1) != LUA_TSTRING)
    return luaL_error(L, "require expects a module name (a string such as \"lib.shapes\"), got %s",
                      luaL_typename(L, 1));
  const std::string name = lua_tostring(L, 1);
  lua_settop(L, 1);
  lua_getfield(L, LUA_REGISTRYINDEX, kModulesKey);  // index 2: the cache
  lua_getfield(L, 2, name.c_str());
  if (!lua_isnil(L, -1)) return 1;
  lua_pop(L, 1);
  auto& s = impl_of(L);

  std::string error;  // raised after the C++ objects of the search are gone
  fs::path found;
  std::string shown;
  lua_protect(L, [&]() {
    if (!valid_module_name(name)) {
      error = "require: invalid module name '" + name +
              "': use dotted names of letters, digits and underscores (\"lib.shapes\" loads "
              "lib/shapes.lua inside the script folders)";
      return 0;
    }
    if (std::find(s.loading.begin(), s.loading.end(), name) != s.loading.end()) {
      error = "require cycle: ";
      for (auto it = std::find(s.loading.begin(), s.loading.end(), name); it != s.loading.end(); ++it)
        error += *it + " -> ";
      error += name;
      return 0;
    }
    std::string rel = name;
    std::replace(rel.begin(), rel.end(), '.', '/');
    rel += ".lua";
    std::vector<std::string> tried;
    std::error_code ec;
    for (const auto& root : s.roots) {
      const fs::path candidate = root / rel;
      if (!fs::is_regular_file(candidate, ec)) {
        tried.push_back(module_display(s, root, rel));
        continue;
      }
      const fs::path real = fs::weakly_canonical(candidate, ec);
      if (ec || !inside(root, real)) {
        error = "require: module '" + name + "' resolves to " + real.string() +
                ", outside the allowed script folders";
        return 0;
      }
      found = real;
      shown = module_display(s, root, rel);
      return 0;
    }
    error = "module '" + name + "' not found; searched:";
    for (const auto& t : tried) error += "\n\t" + t;
    return 0;
  });
  if (!error.empty()) return luaL_error(L, "%s", error.c_str());

  // Load and run the module; Lua errors propagate to the caller's protected call as they are.
  struct LoadingGuard {
    std::vector<std::string>& stack;
    ~LoadingGuard() { stack.pop_back(); }
  };
  std::optional<ScriptError> failure;
  lua_protect(L, [&]() {
    failure = compile(L, s, read_file(found, shown, s.limits.memory_bytes), shown);
    note_source_file(s, found);
    return 0;
  });
  if (failure) {
    lua_protect(L, [&]() -> int { throw *failure; });
  }
  s.loading.push_back(name);
  {
    LoadingGuard guard{s.loading};
    lua_pushstring(L, name.c_str());
    lua_pushstring(L, shown.c_str());
    lua_call(L, 2, 1);
  }
  if (lua_isnil(L, -1)) {
    lua_pop(L, 1);
    lua_pushboolean(L, 1);
  }
  lua_pushvalue(L, -1);
  lua_setfield(L, 2, name.c_str());
  return 1;
}

// Opens the permitted libraries and installs the replacements (run protected: it allocates).
int open_sandbox(lua_State* L) {
  const luaL_Reg libs[] = {{LUA_GNAME, luaopen_base},      {LUA_MATHLIBNAME, luaopen_math},
                           {LUA_STRLIBNAME, luaopen_string}, {LUA_TABLIBNAME, luaopen_table},
                           {LUA_UTF8LIBNAME, luaopen_utf8}};
  for (const auto& lib : libs) {
    luaL_requiref(L, lib.name, lib.func, 1);
    lua_pop(L, 1);
  }
  lua_pushglobaltable(L);
  const int g = lua_gettop(L);
  lua_pushnil(L);
  lua_setfield(L, g, "dofile");  // reads arbitrary files
  lua_pushnil(L);
  lua_setfield(L, g, "loadfile");
  lua_getfield(L, g, "load");
  lua_pushcclosure(L, sandbox_load, 1);
  lua_setfield(L, g, "load");
  lua_pushcfunction(L, sandbox_require);
  lua_setfield(L, g, "require");
  lua_pushcfunction(L, sandbox_print);
  lua_setfield(L, g, "print");
  for (const char* lib : {"os", "io", "debug", "package"}) {
    push_guard(L, lib);
    lua_setfield(L, g, lib);
  }
  lua_getfield(L, g, "string");
  lua_pushnil(L);
  lua_setfield(L, -2, "dump");  // bytecode out is as unwelcome as bytecode in
  lua_pop(L, 1);
  // math.random is seeded from the clock: a script using it would not be reproducible.
  lua_getfield(L, g, "math");
  const char* no_random =
      "math.random is not available in roger scripts: draw from the rng object your function "
      "receives (rng:uniform, rng:int, rng:normal, ...) so every run is reproducible from its seed";
  set_refusal(L, lua_gettop(L), "random", no_random);
  set_refusal(L, lua_gettop(L), "randomseed", no_random);
  lua_pop(L, 1);
  lua_newtable(L);
  lua_setfield(L, LUA_REGISTRYINDEX, kModulesKey);
  return 0;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

namespace {
// "file:line: message\ntraceback", leaving out the parts that are unknown.
std::string compose(const std::string& message, const std::string& file, int line,
                    const std::string& traceback) {
  std::string text;
  if (!file.empty()) text = file + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": ";
  text += message;
  if (!traceback.empty()) text += "\n" + traceback;
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
  return fs::path(ROGER_SOURCE_DIR);
}

LuaSandbox::LuaSandbox(const SandboxLimits& limits) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.limits = limits;
  s.hook_interval = int(std::clamp<uint64_t>(limits.instructions, 1, 1000));
  s.print = [](const std::string& line) { std::cerr << line << '\n'; };
  s.L = lua_newstate(sandbox_alloc, &s);
  if (!s.L)
    throw Error("cannot create a Lua state within the script memory limit of " +
                std::to_string(limits.memory_bytes) + " bytes");
  *static_cast<Impl**>(lua_getextraspace(s.L)) = &s;
  lua_atpanic(s.L, sandbox_panic);
  lua_sethook(s.L, count_hook, LUA_MASKCOUNT, s.hook_interval);
  lua_pushcfunction(s.L, open_sandbox);
  if (lua_pcall(s.L, 0, 0, 0) != LUA_OK) {
    const std::string msg = lua_isstring(s.L, -1) ? lua_tostring(s.L, -1) : "unknown error";
    lua_close(s.L);
    s.L = nullptr;
    throw Error("cannot open the Lua libraries: " + msg);
  }
  const fs::path root = project_root();
  for (const char* folder : {"scenarios", "curricula", "scripts"}) {
    std::error_code ec;
    const fs::path p = fs::weakly_canonical(root / folder, ec);
    if (!ec) s.roots.push_back(p);
  }
}

LuaSandbox::~LuaSandbox() {
  if (impl_ && impl_->L) {
    // Finalizers written in Lua run at close: give them a fresh budget so they cannot hang us.
    impl_->instructions_used = 0;
    lua_sethook(impl_->L, count_hook, LUA_MASKCOUNT, impl_->hook_interval);
    lua_close(impl_->L);
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

void LuaSandbox::set_print(std::function<void(const std::string&)> sink) {
  impl_->print = std::move(sink);
}

void LuaSandbox::set_main_script(const std::string& path) {
  Impl& s = *impl_;
  std::error_code ec;
  const fs::path folder = fs::weakly_canonical(fs::absolute(fs::path(path), ec).parent_path(), ec);
  s.main_dir = folder;
  s.main_dir_display = fs::path(path).parent_path().string();
  std::vector<fs::path> roots{folder};
  const fs::path root = project_root();
  for (const char* name : {"scenarios", "curricula", "scripts"}) {
    const fs::path p = fs::weakly_canonical(root / name, ec);
    if (!ec && std::find(roots.begin(), roots.end(), p) == roots.end()) roots.push_back(p);
  }
  s.roots = std::move(roots);
  s.main_set = true;
}

std::vector<fs::path> LuaSandbox::module_roots() const { return impl_->roots; }

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

void LuaSandbox::call(int nargs, int nresults) {
  Impl& s = *impl_;
  lua_State* L = s.L;
  const int base = lua_gettop(L) - nargs;  // the function's slot
  if (!lua_checkstack(L, 2)) throw Error("Lua stack exhausted");
  // Where the called function lives, for errors that carry no location (memory).
  lua_Debug ar;
  lua_pushvalue(L, base);
  std::string entry_file;
  if (lua_getinfo(L, ">S", &ar) && ar.source && ar.source[0] == '@') entry_file = ar.source + 1;
  lua_pushcfunction(L, message_handler);
  lua_insert(L, base);
  const bool top_level = s.call_depth == 0;
  if (top_level) {
    s.instructions_used = 0;
    s.pending.reset();
    s.pending_text.clear();
    lua_sethook(L, count_hook, LUA_MASKCOUNT, s.hook_interval);
  }
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
  if (status == LUA_OK) return;

  std::string msg = lua_isstring(L, -1) ? lua_tostring(L, -1) : "unknown error";
  lua_pop(L, 1);
  if (s.pending && msg == s.pending_text) {
    ScriptError error = *s.pending;
    s.pending.reset();
    throw error;
  }
  if (status == LUA_ERRMEM)
    throw ScriptError("not enough memory (script memory limit of " +
                          std::to_string(s.limits.memory_bytes >> 20) + " MiB)",
                      entry_file, 0, "");
  if (status == LUA_ERRERR) msg = "error while handling an error (" + msg + ")";
  msg = restore_names(s, msg);
  const std::string traceback = s.err_handled ? restore_names(s, s.err_traceback) : "";
  std::string file, rest;
  int line = 0;
  if (split_location(msg, file, line, rest)) throw ScriptError(rest, file, line, traceback);
  throw ScriptError(msg, s.err_handled ? restore_names(s, s.err_file) : entry_file,
                    s.err_handled ? s.err_line : 0, traceback);
}

void LuaSandbox::run_file(const std::string& path, int nresults) {
  if (!impl_->main_set) set_main_script(path);
  load_file(path);
  call(0, nresults);
}

// ---------------------------------------------------------------------------------------------

int lua_protect(lua_State* L, const std::function<int()>& body) {
  std::string message;
  bool located = false;
  try {
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
  // Raised outside the catch blocks, once the C++ exception is destroyed.
  if (located) {
    lua_pushstring(L, message.c_str());
    return lua_error(L);
  }
  return luaL_error(L, "%s", message.c_str());
}

void lua_charge(lua_State* L, uint64_t units) {
  auto& s = impl_of(L);
  s.instructions_used += units;
  if (s.instructions_used <= s.limits.instructions) return;
  lua_sethook(L, count_hook, LUA_MASKCOUNT, 1);  // as in count_hook: no escaping through pcall
  luaL_error(L, "instruction budget of %I exceeded (runaway loop?)", lua_Integer(s.limits.instructions));
}

// ---------------------------------------------------------------------------------------------

namespace {
// Joins items with a separator.
}  // namespace

LuaFields::LuaFields(lua_State* L, int index, std::string context, std::vector<std::string> known)
    : L_(L), index_(lua_absindex(L, index)), context_(std::move(context)) {
  if (!lua_istable(L_, index_))
    fail(std::string("expects a table of named fields, got ") + luaL_typename(L_, index_));
  std::sort(known.begin(), known.end());
  std::vector<std::string> unknown;
  lua_pushnil(L_);
  while (lua_next(L_, index_)) {
    lua_pop(L_, 1);
    if (lua_type(L_, -1) != LUA_TSTRING) {
      const std::string what = lua_isinteger(L_, -1)
                                   ? "a value at position " + std::to_string(lua_tointeger(L_, -1))
                                   : std::string("a key of type ") + luaL_typename(L_, -1);
      lua_pop(L_, 1);
      fail("expects named fields (name = value), got " + what + "; known fields: " + join(known));
    }
    const std::string key = lua_tostring(L_, -1);
    if (!std::binary_search(known.begin(), known.end(), key)) unknown.push_back(key);
  }
  if (!unknown.empty()) {
    std::sort(unknown.begin(), unknown.end());
    fail(std::string(unknown.size() == 1 ? "unknown field '" : "unknown fields '") +
         join(unknown, "', '") + "'; known fields: " + join(known));
  }
}

void LuaFields::fail(const std::string& message) const {
  luaL_error(L_, "%s: %s", context_.c_str(), message.c_str());
  std::abort();  // unreachable: luaL_error does not return
}

void LuaFields::wrong_type(const char* key, const char* expected) const {
  push(key);
  const std::string got = luaL_typename(L_, -1);
  lua_pop(L_, 1);
  fail(std::string("field '") + key + "' must be " + expected + ", got " + got);
}

int LuaFields::push(const char* key) const {
  lua_pushstring(L_, key);
  return lua_rawget(L_, index_);
}

bool LuaFields::has(const char* key) const {
  const bool present = push(key) != LUA_TNIL;
  lua_pop(L_, 1);
  return present;
}

double LuaFields::number(const char* key) const {
  if (!has(key)) fail(std::string("missing required field '") + key + "' (a number)");
  return number(key, 0.0);
}

double LuaFields::number(const char* key, double fallback) const {
  const int type = push(key);
  if (type == LUA_TNIL) {
    lua_pop(L_, 1);
    return fallback;
  }
  if (type != LUA_TNUMBER) {
    lua_pop(L_, 1);
    wrong_type(key, "a number");
  }
  const double v = lua_tonumber(L_, -1);
  lua_pop(L_, 1);
  if (!std::isfinite(v)) fail(std::string("field '") + key + "' must be a finite number, got " + format_number(v));
  return v;
}

int64_t LuaFields::integer(const char* key) const {
  if (!has(key)) fail(std::string("missing required field '") + key + "' (an integer)");
  return integer(key, 0);
}

int64_t LuaFields::integer(const char* key, int64_t fallback) const {
  const int type = push(key);
  if (type == LUA_TNIL) {
    lua_pop(L_, 1);
    return fallback;
  }
  int ok = 0;
  const lua_Integer v = type == LUA_TNUMBER ? lua_tointegerx(L_, -1, &ok) : 0;
  const std::string shown = type == LUA_TNUMBER ? format_number(lua_tonumber(L_, -1)) : "";
  lua_pop(L_, 1);
  if (type != LUA_TNUMBER) wrong_type(key, "an integer");
  if (!ok) fail(std::string("field '") + key + "' must be an integer, got " + shown);
  return v;
}

std::string LuaFields::string(const char* key) const {
  if (!has(key)) fail(std::string("missing required field '") + key + "' (a string)");
  return string(key, "");
}

std::string LuaFields::string(const char* key, const std::string& fallback) const {
  const int type = push(key);
  if (type == LUA_TNIL) {
    lua_pop(L_, 1);
    return fallback;
  }
  if (type != LUA_TSTRING) {
    lua_pop(L_, 1);
    wrong_type(key, "a string");
  }
  std::string v = lua_tostring(L_, -1);
  lua_pop(L_, 1);
  return v;
}

bool LuaFields::boolean(const char* key, bool fallback) const {
  const int type = push(key);
  if (type == LUA_TNIL) {
    lua_pop(L_, 1);
    return fallback;
  }
  if (type != LUA_TBOOLEAN) {
    lua_pop(L_, 1);
    wrong_type(key, "a boolean");
  }
  const bool v = lua_toboolean(L_, -1);
  lua_pop(L_, 1);
  return v;
}

Colour LuaFields::colour(const char* key, const Colour& fallback) const {
  if (push(key) == LUA_TNIL) {
    lua_pop(L_, 1);
    return fallback;
  }
  const Colour c = lua_to_colour(L_, -1, context_ + ": field '" + key + "'");
  lua_pop(L_, 1);
  return c;
}

Colour lua_to_colour(lua_State* L, int index, const std::string& context) {
  index = lua_absindex(L, index);
  const char* expected = "a colour: {r, g, b} or {r=, g=, b=} with integers 0-255, or \"#rrggbb\"";
  if (lua_type(L, index) == LUA_TSTRING) {
    const std::string text = lua_tostring(L, index);
    unsigned r, g, b;
    char tail;
    if (text.size() == 7 && std::sscanf(text.c_str(), "#%2x%2x%2x%c", &r, &g, &b, &tail) == 3)
      return Colour{uint8_t(r), uint8_t(g), uint8_t(b)};
    luaL_error(L, "%s must be %s, got \"%s\"", context.c_str(), expected, text.c_str());
  }
  if (!lua_istable(L, index))
    luaL_error(L, "%s must be %s, got %s", context.c_str(), expected, luaL_typename(L, index));
  const bool named = lua_getfield(L, index, "r") != LUA_TNIL;
  lua_pop(L, 1);
  const char* names[3] = {"r", "g", "b"};
  uint8_t out[3];
  for (int i = 0; i < 3; ++i) {
    const int type = named ? lua_getfield(L, index, names[i]) : lua_rawgeti(L, index, i + 1);
    int ok = 0;
    const lua_Integer v = type == LUA_TNUMBER ? lua_tointegerx(L, -1, &ok) : 0;
    lua_pop(L, 1);
    if (!ok || v < 0 || v > 255)
      luaL_error(L, "%s must be %s (component %s is missing or not an integer 0-255)",
                 context.c_str(), expected, names[i]);
    out[i] = uint8_t(v);
  }
  return Colour{out[0], out[1], out[2]};
}

LuaStackGuard::LuaStackGuard(lua_State* L) : L_(L), top_(lua_gettop(L)) {}
LuaStackGuard::~LuaStackGuard() { lua_settop(L_, top_); }

std::string format_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  // Exponent notation only for very large or small magnitudes ("10", not "1e+01").
  const bool plain = value == 0.0 || (std::abs(value) >= 1e-4 && std::abs(value) < 1e15);
  char buf[40];
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, value);
    if (std::strtod(buf, nullptr) == value && (!plain || !std::strchr(buf, 'e'))) break;
  }
  return buf;
}

std::string join(const std::vector<std::string>& items, const char* sep) {
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) out += (i ? sep : "") + items[i];
  return out;
}

std::string resolve_script_path(const std::string& arg, const std::string& folder_name,
                                const std::string& kind, const std::string& list_label,
                                const std::function<bool(const std::string&)>& accept) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_regular_file(arg, ec)) return arg;
  const fs::path folder = project_root() / folder_name;
  const bool bare = arg.find('/') == std::string::npos;
  const std::string file = fs::path(arg).extension() == ".lua" ? arg : arg + ".lua";
  if (bare && fs::is_regular_file(folder / file, ec)) return (folder / file).string();
  std::vector<std::string> shipped;
  for (const auto& entry : fs::directory_iterator(folder, ec))
    if (entry.path().extension() == ".lua" && (!accept || accept(entry.path().string())))
      shipped.push_back(entry.path().stem().string());
  std::sort(shipped.begin(), shipped.end());
  throw Error("no " + kind + " '" + arg + "': " +
              (bare ? "not a file, and " + folder_name + "/" + file + " does not exist"
                    : std::string(fs::exists(arg, ec) ? "not a regular file" : "no such file")) +
              (shipped.empty() ? "" : "; " + list_label + ": " + join(shipped)));
}

}  // namespace roger
