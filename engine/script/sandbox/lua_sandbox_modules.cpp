// lua_sandbox_modules.cpp: reading and compiling script files, and `require` resolving dotted
// module names inside the sandbox's folders.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include <lua.hpp>

#include "core/fileio.h"
#include "core/text.h"
#include "script/sandbox/lua_sandbox_internal.h"
#include "script/sandbox/lua_tokens.h"

namespace roger {
namespace sandbox_detail {
namespace fs = std::filesystem;

namespace {

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

}  // namespace

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

namespace {

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

}  // namespace

// Compiles a file's text as a "@shown" chunk and pushes it, or returns the error as a ScriptError.
// Like luaL_loadfilex: skips what lua_file_text skips; refuses bytecode.
std::optional<ScriptError> compile(lua_State* L, LuaSandbox::Impl& s, std::string text,
                                   const std::string& shown) {
  text = lua_file_text(std::move(text));
  if (text.rfind(LUA_SIGNATURE, 0) == 0)
    return ScriptError("attempt to load a binary chunk: roger loads Lua source text only "
                       "(precompiled bytecode is refused)", shown, 0, "");
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

namespace {

// The search for the valid dotted module `name` in `roots`, as require makes it: the first root
// (module_root_takes) holding a regular file of that name, or none (`root` = roots.size()), and
// the roots looked in before it. Shared by require and find_module_file, so that no reader of
// scripts looks further than require does.
struct ModuleSearch {
  std::string rel;            // "lib/shapes.lua"
  size_t root = 0;            // the root the file is in; roots.size() when none holds it
  fs::path real;              // the file, links followed
  std::vector<size_t> missed; // the roots looked in without the file
};

ModuleSearch search_module(const std::vector<fs::path>& roots, const std::string& name) {
  ModuleSearch out;
  out.rel = name;
  std::replace(out.rel.begin(), out.rel.end(), '.', '/');
  out.rel += ".lua";
  std::error_code ec;
  for (out.root = 0; out.root < roots.size(); ++out.root) {
    if (!module_root_takes(roots, out.root, name)) continue;
    const fs::path candidate = roots[out.root] / out.rel;
    if (fs::is_regular_file(candidate, ec)) {
      out.real = fs::weakly_canonical(candidate, ec);
      if (ec) out.real.clear();
      return out;
    }
    out.missed.push_back(out.root);
  }
  return out;
}

// The modules require could load from `roots` (dotted names, "lib.skills"), for a misspelt name's
// nearest (found by a probe: require("lib.skill") listed the places searched, and no "did you mean").
std::vector<std::string> module_names(const std::vector<fs::path>& roots) {
  std::vector<std::string> names;
  for (const fs::path& root : roots) {
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(root, ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec)) {
      const std::string base = it->path().filename().string();
      if (it.depth() >= 3 || base.front() == '.') it.disable_recursion_pending();  // not .git's
      if (it->path().extension() != ".lua") continue;
      fs::path rel = it->path().lexically_relative(root);
      rel.replace_extension();
      std::string dotted;
      for (const auto& part : rel) dotted += (dotted.empty() ? "" : ".") + part.string();
      names.push_back(dotted);
    }
  }
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  return names;
}

// Finds module `name` in the sandbox's roots: sets `found` and `shown`, or `error` (an invalid
// name, a require cycle, a file outside the roots or no file at all).
void locate_module(const LuaSandbox::Impl& s, const std::string& name, fs::path& found,
                   std::string& shown, std::string& error) {
  if (!valid_module_name(name)) {
    error = "require: invalid module name '" + name +
            "': use dotted names of letters, digits and underscores (\"lib.shapes\" loads "
            "lib/shapes.lua inside the script folders)";
    return;
  }
  if (std::find(s.loading.begin(), s.loading.end(), name) != s.loading.end()) {
    error = "require cycle: ";
    for (auto it = std::find(s.loading.begin(), s.loading.end(), name); it != s.loading.end(); ++it)
      error += *it + " -> ";
    error += name;
    return;
  }
  const ModuleSearch search = search_module(s.roots, name);
  const std::string& rel = search.rel;
  if (search.root < s.roots.size()) {
    const fs::path& root = s.roots[search.root];
    if (search.real.empty() || !inside(root, search.real)) {
      error = "require: module '" + name + "' resolves to " + search.real.string() +
              ", outside the allowed script folders";
      return;
    }
    found = search.real;
    shown = module_display(s, root, rel);
    return;
  }
  std::vector<std::string> tried;
  for (size_t i : search.missed) {
    // Where each place is, unmistakably: a script in <cwd>/scenarios and the project's
    // scenarios/ would otherwise both show as scenarios/lib/x.lua.
    const fs::path& root = s.roots[i];
    const std::string candidate = (root / rel).lexically_normal().string();
    std::error_code ec;
    const bool project = i > 0 && root == fs::weakly_canonical(project_root(), ec);
    tried.push_back(s.main_set && root == s.main_dir ? module_display(s, root, rel) + " (beside the script)"
                    : project ? candidate + " (in the project)"
                              : candidate + " (in the project " + root.parent_path().string() + ")");
  }
  error = "module '" + name + "' not found" + suggestion(name, module_names(s.roots)) + "; searched:";
  for (const auto& t : tried) error += "\n\t" + t;
  if (name.size() > 4 && name.compare(name.size() - 4, 4, ".lua") == 0)
    error += "\nA module name has no \".lua\": write require(\"" + name.substr(0, name.size() - 4) +
             "\"), which loads " + rel.substr(0, rel.size() - 8) + ".lua";
}

// Compiles the module file and runs it with (name, shown), leaving its one result on the stack.
// Lua errors propagate to the caller's protected call as they are.
void run_module(lua_State* L, LuaSandbox::Impl& s, const std::string& name, const fs::path& found,
                const std::string& shown) {
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
}

}  // namespace

// require(name): a standard library by its name, else dotted names ("lib.shapes" ->
// lib/shapes.lua) searched in the sandbox's roots only, text chunks only, cached, with cycles
// reported. As Lua's: a number is taken as its text, and a module's first load also returns
// where it was found (its file, as messages show it).
int sandbox_require(lua_State* L) {
  if (lua_type(L, 1) != LUA_TSTRING && lua_type(L, 1) != LUA_TNUMBER)
    return luaL_error(L, "require expects a module name (a string such as \"lib.shapes\"), got %s",
                      luaL_typename(L, 1));
  size_t length = 0;
  const char* text = lua_tolstring(L, 1, &length);
  const std::string name(text, length);  // whole: a NUL inside is refused, not cut at (found by a probe)
  lua_settop(L, 1);
  lua_getfield(L, LUA_REGISTRYINDEX, kModulesKey);  // index 2: the cache
  lua_getfield(L, 2, name.c_str());
  if (lua_toboolean(L, -1)) return 1;  // as Lua's: a module that returned false is run again
  lua_pop(L, 1);
  // A standard library's name ("string", "utf8", "coroutine", "_G", ...) gives the library, as
  // Lua's require finds it in package.loaded before any file (the missing ones give their guard).
  lua_getfield(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
  if (lua_getfield(L, -1, name.c_str()) != LUA_TNIL) return 1;
  lua_pop(L, 2);
  auto& s = impl_of(L);

  std::string error;  // raised after the C++ objects of the search are gone
  fs::path found;
  std::string shown;
  lua_protect(L, [&]() {
    locate_module(s, name, found, shown, error);
    return 0;
  });
  if (!error.empty()) return luaL_error(L, "%s", error.c_str());

  // Load and run the module; Lua errors propagate to the caller's protected call as they are.
  run_module(L, s, name, found, shown);
  if (lua_isnil(L, -1)) {
    lua_pop(L, 1);
    lua_pushboolean(L, 1);
  }
  lua_pushvalue(L, -1);
  lua_setfield(L, 2, name.c_str());
  lua_pushstring(L, shown.c_str());
  return 2;
}

}  // namespace sandbox_detail

namespace {

namespace fs = std::filesystem;

// The file of module `name` as a script in `folder` would require it (the roots its sandbox
// would search, in order), or an empty path.
fs::path module_file(const fs::path& folder, const std::string& name) {
  std::string rel = name;
  std::replace(rel.begin(), rel.end(), '.', '/');
  rel += ".lua";
  std::error_code ec;
  for (const fs::path& root : module_search_roots(folder))
    if (fs::is_regular_file(root / rel, ec)) return root / rel;
  return {};
}

// Whether token i is `require "m"` or `require("m")` with a module name m; i moves past it.
bool required_module(const std::vector<LuaToken>& t, size_t& i, std::string& module) {
  if (t[i].type != LuaToken::kName || t[i].text != "require") return false;
  size_t j = i + 1;
  const bool paren = t[j].type == LuaToken::kOp && t[j].text == "(";
  if (paren) ++j;
  if (t[j].type != LuaToken::kString || t[j].text.empty()) return false;
  for (char c : t[j].text)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.')) return false;
  module = t[j].text;
  i = j + (paren && t[j + 1].type == LuaToken::kOp && t[j + 1].text == ")" ? 2 : 1);
  return true;
}

// Read from the script's tokens, not by std::regex, whose matcher recurses once per character: a
// line of 100,000 characters overflowed the stack (found by a probe: roger check crashed on a
// script whose one line returned a long name). Strings and comments no longer count either.
bool has_key(const std::string& path, const std::string& key, int depth) {
  const std::vector<LuaToken> t = lua_tokenize(read_file_text(path));
  auto is_op = [&](size_t i, const char* op) { return t[i].type == LuaToken::kOp && t[i].text == op; };
  // A script that returns a module it requires (`local p = require("paper") ... return p`, or
  // `return require("paper")`) is of that module's kind; so is one that returns what a required
  // module makes (`local make = require("stages") ... return make{...}`, `return p.build(...)`:
  // found by a probe, roger check ran such a curriculum as a skill script, roger train took it).
  std::map<std::string, std::string> modules;  // local name -> module
  std::string result_module;
  int block = 0;  // the blocks open at token i: only the main chunk's return gives the script's value
  std::vector<char> brackets;  // the brackets open at token i, innermost last
  for (size_t i = 0; t[i].type != LuaToken::kEnd; ++i) {
    if (t[i].type == LuaToken::kOp) {
      const std::string& op = t[i].text;
      if (op == "{" || op == "(" || op == "[") brackets.push_back(op[0]);
      if ((op == "}" || op == ")" || op == "]") && !brackets.empty()) brackets.pop_back();
    }
    if (t[i].type != LuaToken::kName) continue;
    // A table's field, `{ key = ...}` or `t.key = ...`: not a variable of that name (found by a
    // probe: a skill script's `local stages = {...}` made it a curriculum, a scenario's
    // `local runs = ...` a batch script).
    if (t[i].text == key && is_op(i + 1, "=") && i > 0) {
      const bool field = is_op(i - 1, ".") || is_op(i - 1, "{") ||
                         ((is_op(i - 1, ",") || is_op(i - 1, ";")) && !brackets.empty() && brackets.back() == '{');
      if (field) return true;
    }
    const std::string& word = t[i].text;
    if (word == "function" || word == "do" || word == "if" || word == "repeat") ++block;
    if (word == "end" || word == "until") --block;
    std::string module;
    if (t[i].text == "local" && t[i + 1].type == LuaToken::kName && is_op(i + 2, "=")) {
      size_t j = i + 3;
      if (required_module(t, j, module)) modules[t[i + 1].text] = module;
    } else if (t[i].text == "return" && block == 0) {
      // `return require("m")` or `return p`, ending its line (a `;` may follow)
      size_t j = i + 1;
      if (!required_module(t, j, module)) {
        if (t[j].type != LuaToken::kName) continue;  // `return nil` too: it leaves no module
        const auto it = modules.find(t[j].text);
        module = it != modules.end() ? it->second : std::string();
        ++j;
      }
      const bool made = t[j].type == LuaToken::kString || is_op(j, "(") || is_op(j, "{") || is_op(j, ".") ||
                        is_op(j, ":");
      if (made && !module.empty()) {
        result_module = module;
        continue;
      }
      if (is_op(j, ";")) ++j;
      if (t[j].type == LuaToken::kEnd || t[j].line > t[i].line) result_module = module;
    }
  }
  if (result_module.empty() || depth >= 8) return false;
  const fs::path file = module_file(fs::absolute(fs::path(path)).parent_path(), result_module);
  return !file.empty() && has_key(file.string(), key, depth + 1);
}

}  // namespace

bool script_has_key(const std::string& path, const std::string& key) { return has_key(path, key, 0); }

fs::path find_module_file(const std::vector<fs::path>& roots, const std::string& name) {
  if (!sandbox_detail::valid_module_name(name)) return {};
  const sandbox_detail::ModuleSearch search = sandbox_detail::search_module(roots, name);
  const bool kept = search.root < roots.size() && !search.real.empty() && sandbox_detail::inside(roots[search.root], search.real);
  return kept ? search.real : fs::path();  // require refuses one outside its root
}

std::string lua_file_text(std::string text) {
  if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);
  if (!text.empty() && text[0] == '#') text.erase(0, std::min(text.find('\n'), text.size()));
  return text;
}

}  // namespace roger
