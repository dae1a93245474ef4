// The script's book of definitions, the shared helpers of the control API's files, the value
// bridge (pushing and checking controllers and predicates) and the installation of it all.
#include "script/control/lua_control.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <set>

#include <lua.hpp>

#include "core/error.h"
#include "control/primitives.h"
#include "core/text.h"
#include "script/control/lua_control_internal.h"
#include "script/sandbox/lua_sandbox.h"

namespace roger {
namespace lua_control_detail {
namespace {

constexpr const char* kBookType = "roger.ControlBook";
constexpr size_t kMaxObjects = 20000;             // controllers and predicates one script may make

// Registry keys: the addresses of these are unique and need no allocation to look up.
char book_key;  // mutable, so never merged with another constant
char cache_key;

// Where the Lua function that called the running C function is; empty when the caller is C++.
Location caller_location(lua_State* L) {
  lua_Debug ar;
  Location where;
  if (lua_getstack(L, 1, &ar) && lua_getinfo(L, "Sl", &ar) && ar.currentline > 0) {
    // `source` holds the full chunk name; `short_src` may be truncated for long paths.
    where.file = ar.source && ar.source[0] == '@' ? ar.source + 1 : ar.short_src;
    where.line = ar.currentline;
  }
  return where;
}

// Lua's traceback from the running C function when a Lua function of a file other than `file` (its
// caller's) is on the stack above that caller: a library called from another file, whose line alone
// would not tell the author where the mistake is (found by a probe: an action name never defined, in
// a list the author wrote, was placed at the line of the helper module's roger.stage). "" otherwise.
std::string traceback_through_another_file(lua_State* L, const std::string& file) {
  lua_Debug ar;
  bool other = false;
  for (int level = 2; !other && lua_getstack(L, level, &ar); ++level)
    other = lua_getinfo(L, "Sl", &ar) && ar.currentline > 0 &&
            (ar.source && ar.source[0] == '@' ? ar.source + 1 : ar.short_src) != file;
  if (!other) return "";
  luaL_traceback(L, L, nullptr, 1);
  std::string traceback = lua_tostring(L, -1);
  lua_pop(L, 1);
  return traceback;
}

// Whether a chunk's file is one of the project's shipped libraries (curricula/lib/*.lua,
// scenarios/lib/*.lua): code the script's author calls but did not write.
// A chunk's name is relative to the project root for a file inside it (the sandbox names modules
// so), whatever the working folder: it is resolved against that root, not the working folder.
bool shipped_library(const std::string& file) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path root = fs::weakly_canonical(project_root(), ec);
  if (ec) return false;
  const fs::path path = fs::path(file).is_relative() ? root / file : fs::path(file);
  if (!fs::is_regular_file(path, ec)) return false;
  const fs::path folder = fs::weakly_canonical(path, ec).parent_path();
  if (ec || folder.filename() != "lib") return false;
  return folder == root / "curricula" / "lib" || folder == root / "scenarios" / "lib";
}

// The location of the innermost Lua frame outside the shipped libraries: the line of the
// author's script that called the library which made a controller (its own line when it made it
// itself). `library` is the last library file passed over, "" when none.
Location author_location(lua_State* L, std::string& library) {
  library.clear();
  lua_Debug ar;
  for (int level = 1; lua_getstack(L, level, &ar); ++level) {
    if (!lua_getinfo(L, "Sl", &ar) || ar.currentline <= 0) continue;
    const std::string file = ar.source && ar.source[0] == '@' ? ar.source + 1 : ar.short_src;
    if (shipped_library(file)) {
      library = file;
      continue;
    }
    return Location{file, ar.currentline};
  }
  library.clear();
  return caller_location(L);
}

// How to build a second copy of what a shipped library builds: lib.skills' builders take a name as
// their last argument, lib.sorting's the option tag (found by a probe: sorting.moves twice was told
// to pass a name, which it does not take).
std::string another_copy_hint(const std::string& library) {
  if (library.size() >= 11 && library.compare(library.size() - 11, 11, "sorting.lua") == 0)
    return "; to build another copy, give lib.sorting's builder the option tag, text added to its names "
           "(e.g. sorting.moves(Phi_T, { tag = \" 2\" })); sorting.tasks takes the tag as its second argument "
           "(sorting.tasks(moves, \" 2\")), and sorting.by_hand a name (sorting.by_hand(moves, \"sort 2\"))";
  return "; to build another copy, pass the library's builder a name as its last argument (e.g. "
         "skills.Phi6(p, \"Phi6_b\"))";
}

}  // namespace

// Raises a Lua error with the text as is, located at the Lua caller's file:line.
[[noreturn]] void raise(lua_State* L, const std::string& message) {
  luaL_error(L, "%s", message.c_str());
  std::abort();  // unreachable: luaL_error does not return
}

}  // namespace lua_control_detail

void lua_refuse_after_load(lua_State* L, const std::string& what) {
  std::string called = "this function";
  lua_Debug ar;
  if (lua_getstack(L, 0, &ar) && lua_getinfo(L, "n", &ar) && ar.name)
    called = (ar.namewhat && std::string(ar.namewhat) == "method" ? "c:" : "roger.") + std::string(ar.name);
  luaL_error(L, "%s: %s are made while the script loads, and this call comes once it has loaded, from a function "
                "the engine calls as it runs (an absorbing, reward or teacher function), where each call would make "
                "another: make it at the script's top level and use that one here",
             called.c_str(), what.c_str());
  std::abort();  // unreachable: luaL_error does not return
}

namespace lua_control_detail {

// The book of the state, or a Lua error when the control API is not installed.
ControlBook& book_of(lua_State* L) {
  lua_rawgetp(L, LUA_REGISTRYINDEX, &book_key);
  auto* book = static_cast<ControlBook*>(luaL_testudata(L, -1, kBookType));
  lua_pop(L, 1);
  if (!book) raise(L, "the control API (roger.primitive, ...) is not installed in this Lua state");
  return *book;
}

// Counts one more object made by the script against the cap, and a little work against the
// instruction budget (constructing a controller costs far more than one VM instruction).
void count_object(lua_State* L, ControlBook& book) {
  if (book.finished) lua_refuse_after_load(L, "controllers and predicates");
  if (++book.objects > kMaxObjects)
    raise(L, "too many controllers and predicates (a script may make at most " +
                 std::to_string(kMaxObjects) + ")");
  lua_charge(L, 50);
}

// "phi0, search, phi1, ..." in make_primitive's order.
std::string kinds_text() { return join(primitive_names()); }

// Whether a name is one of the primitive kinds.
bool is_kind(const std::string& name) {
  const auto& kinds = primitive_names();
  return std::find(kinds.begin(), kinds.end(), name) != kinds.end();
}

// "named controllers: A, B; primitive kinds: phi0, ..." for unknown-name messages.
std::string known_names(const ControlBook& book) {
  std::vector<std::string> names;
  for (const auto& n : book.named) names.push_back(n.name);
  // Named so far: a name is known from the line that makes its controller on (a probe's compose
  // named a sequence made two lines further down).
  return (names.empty() ? std::string("the script has named no controllers yet")
                        : "controllers named so far: " + join(names)) +
         "; primitive kinds: " + kinds_text();
}

// "controller 'Phi7' (sequence)", or "controller 'phi1'" when the name is the kind.
std::string controller_text(const Controller& c) {
  const std::string kind = c.kind();
  return "controller '" + c.name() + "'" + (kind == c.name() ? "" : " (" + kind + ")");
}

// Resolves a name among the script's named controllers, then as a primitive kind (that kind's
// shared default instance, made on first use). Null when it is neither.
ControllerPtr resolve_now(lua_State* L, ControlBook& book, const std::string& name) {
  if (auto it = book.by_name.find(name); it != book.by_name.end()) return book.named[it->second].controller;
  if (!is_kind(name)) return nullptr;
  auto& slot = book.defaults[name];
  if (!slot) {
    // Once loaded, the engine reads the returned table: a kind's default named only there (action
    // = "phi0") is made then, not refused as a callback's new object (found by a probe: such a
    // script was told of absorbing, reward and teacher functions). One per kind: no cap to count.
    if (!book.finished) count_object(L, book);
    slot = made(book, make_primitive(name));
  }
  return slot;
}

// Checks a new controller name and records the controller under it, with the caller's location.
void register_name(lua_State* L, ControlBook& book, const std::string& context, const std::string& name,
                   const ControllerPtr& c) {
  if (name.empty()) raise(L, context + ": a name must not be empty");
  if (const std::string problem = name_text_problem(name); !problem.empty()) raise(L, context + ": the name " + problem);
  if (name.find("<|") != std::string::npos)
    raise(L, context + ": the name '" + name + "' contains '<|', which roger.compose reads as subject-to");
  if (is_kind(name))
    raise(L, context + ": the name '" + name + "' is a primitive kind, which always means that kind's "
             "default primitive; choose another name (e.g. '" + name + "_tuned')");
  // A controller a shipped library builds (lib.skills' Phi6) is placed at the author's line that
  // called the builder: the second copy's error, and where the first was defined.
  std::string library;
  const Location where = author_location(L, library);
  const bool through_library = !library.empty();
  if (auto it = book.by_name.find(name); it != book.by_name.end()) {
    const auto& other = book.named[it->second];
    const std::string text = context + ": there is already a controller named '" + name + "'" +
                             (other.file.empty() ? "" : " (defined at " + other.file + ":" + std::to_string(other.line) + ")") +
                             (through_library ? another_copy_hint(library) : "");
    if (!through_library || where.file.empty()) raise(L, text);
    lua_pushfstring(L, "%s:%d: %s", where.file.c_str(), where.line, text.c_str());
    lua_error(L);
  }
  c->set_name(name);
  book.by_name[name] = book.named.size();
  book.named.push_back(NamedController{name, c, where.file, where.line});
}

// The controller held by the value at index, or null.
ControllerPtr* test_controller(lua_State* L, int index) {
  return static_cast<ControllerPtr*>(luaL_testudata(L, index, kControllerType));
}

// The predicate held by the value at index, or null.
PredicatePtr* test_predicate(lua_State* L, int index) {
  return static_cast<PredicatePtr*>(luaL_testudata(L, index, kPredicateType));
}

// The controller a method is called on, with a hint for the `c.with{...}` slip.
ControllerPtr self_controller(lua_State* L, const char* method) {
  ControllerPtr* c = test_controller(L, 1);
  if (!c)
    raise(L, std::string("c:") + method + ": call it with a colon, as c:" + method +
                 "(...) (the first argument is " + lua_describe_value(L, 1) + ", not a controller)");
  return *c;
}

namespace {

// ---- installation ----

// __gc of userdata holding a C++ object.
template <class T>
int destroy(lua_State* L) {
  static_cast<T*>(lua_touserdata(L, 1))->~T();
  return 0;
}

// Registers a metatable with the given metamethods; __metatable hides it from scripts.
void new_class(lua_State* L, const char* type, const luaL_Reg* entries) {
  luaL_newmetatable(L, type);
  luaL_setfuncs(L, entries, 0);
  lua_pushboolean(L, 0);
  lua_setfield(L, -2, "__metatable");
  lua_pop(L, 1);
}

// The three types' metatables: controllers (with their methods), predicates and the book.
void install_classes(lua_State* L) {
  const luaL_Reg controller_entries[] = {{"__index", l_controller_index},
                                         {"__newindex", l_controller_newindex},
                                         {"__tostring", l_controller_tostring},
                                         {"__gc", destroy<ControllerPtr>},
                                         {"with", l_with},
                                         {"subject_to", l_subject_to_method},
                                         {"param", l_param},
                                         {"params", l_params},
                                         {nullptr, nullptr}};
  const luaL_Reg predicate_entries[] = {{"__index", l_predicate_index},
                                        {"__tostring", l_predicate_tostring},
                                        {"__gc", destroy<PredicatePtr>},
                                        {nullptr, nullptr}};
  const luaL_Reg book_entries[] = {{"__gc", destroy<ControlBook>}, {nullptr, nullptr}};
  new_class(L, kControllerType, controller_entries);
  new_class(L, kPredicateType, predicate_entries);
  new_class(L, kBookType, book_entries);
}

// The book (what the script made) and one userdata per controller (weak values: the same
// controller is the same Lua value), each under its key in the registry.
void install_book_and_cache(lua_State* L) {
  new (lua_newuserdatauv(L, sizeof(ControlBook), 0)) ControlBook();
  luaL_setmetatable(L, kBookType);
  lua_rawsetp(L, LUA_REGISTRYINDEX, &book_key);
  lua_newtable(L);
  lua_newtable(L);
  lua_pushliteral(L, "v");
  lua_setfield(L, -2, "__mode");
  lua_setmetatable(L, -2);
  lua_rawsetp(L, LUA_REGISTRYINDEX, &cache_key);
}

// The functions of the global `roger` table, each that makes a predicate with a call of it as a
// script writes one: a message about the function given itself, its call forgotten, shows it.
struct ApiEntry {
  const char* name;
  lua_CFunction function;
  const char* predicate_call;  // null: it makes no predicate
};
const ApiEntry kFunctions[] = {{"primitive", l_primitive, nullptr},
                               {"subject_to", l_subject_to, nullptr},
                               {"compose", l_compose, nullptr},
                               {"sequence", l_sequence, nullptr},
                               {"policy", l_policy, nullptr},
                               {"converged", l_converged, "roger.converged(c)"},
                               {"sorted", l_sorted, "roger.sorted()"},
                               {"gamma", l_gamma, "roger.gamma(c, \"CONV\")"},
                               {"all", l_all, "roger.all{p1, p2}"},
                               {"any", l_any, "roger.any{p1, p2}"},
                               {"negate", l_negate, "roger.negate(p)"},
                               {"not", l_negate, "roger.negate(p)"},
                               {"held", l_held, "roger.held(p, seconds)"},
                               {"bind", l_bind, nullptr}};

// The functions in the global `roger` table (made if the script has none yet), and
// roger.primitive_kinds.
void install_functions(lua_State* L) {
  if (lua_getglobal(L, "roger") != LUA_TTABLE) {
    lua_pop(L, 1);
    lua_newtable(L);
    lua_pushvalue(L, -1);
    lua_setglobal(L, "roger");
  }
  for (const ApiEntry& e : kFunctions) {
    lua_pushcfunction(L, e.function);
    lua_setfield(L, -2, e.name);
  }
  const auto& kinds = primitive_names();
  lua_createtable(L, int(kinds.size()), 0);
  for (size_t i = 0; i < kinds.size(); ++i) {
    lua_pushstring(L, kinds[i].c_str());
    lua_rawseti(L, -2, lua_Integer(i + 1));
  }
  lua_make_read_only(L, "roger.primitive_kinds");
  lua_setfield(L, -2, "primitive_kinds");
  lua_pop(L, 1);
}

// Installs the metatables, the book, the userdata cache and the functions, once per state (run
// protected).
int install(lua_State* L) {
  lua_rawgetp(L, LUA_REGISTRYINDEX, &book_key);
  const bool installed = !lua_isnil(L, -1);
  lua_pop(L, 1);
  if (installed) return 0;
  install_classes(L);
  install_book_and_cache(L);
  install_functions(L);
  return 0;
}

// Runs `body` on the sandbox's state inside a protected call.
void with_state(LuaSandbox& sandbox, const std::function<void(lua_State*)>& body) {
  lua_State* L = sandbox.state();
  lua_pushcfunction(L, [](lua_State* L) -> int {
    auto* fn = static_cast<const std::function<void(lua_State*)>*>(lua_touserdata(L, 1));
    return lua_protect(L, [&]() {
      (*fn)(L);
      return 0;
    });
  });
  lua_pushlightuserdata(L, const_cast<std::function<void(lua_State*)>*>(&body));
  sandbox.call(1, 0);
}

// Finds a path from `from` back to `target` through children(), appending the nodes passed.
bool path_back(const Controller* from, const Controller* target, std::set<const Controller*>& seen,
               std::vector<const Controller*>& path) {
  for (const Controller* child : from->children()) {
    if (child == target) return true;
    if (!seen.insert(child).second) continue;
    path.push_back(child);
    if (path_back(child, target, seen, path)) return true;
    path.pop_back();
  }
  return false;
}

}  // namespace
}  // namespace lua_control_detail

using namespace lua_control_detail;


void install_control_api(LuaSandbox& sandbox) {
  lua_State* L = sandbox.state();
  lua_pushcfunction(L, install);
  sandbox.call(0, 0);
}

void finish_control_definitions(LuaSandbox& sandbox) {
  ControlBook* book = nullptr;
  with_state(sandbox, [&](lua_State* L) { book = &book_of(L); });
  auto unbind_all = [&]() {
    for (auto& [name, r] : book->references) r.ref->unbind();
  };
  for (const auto& name : book->reference_order) {
    const Reference& r = book->references.at(name);
    auto it = book->by_name.find(name);
    if (it == book->by_name.end()) {
      unbind_all();
      std::vector<std::string> candidates = primitive_names();
      for (const auto& n : book->named) candidates.push_back(n.name);
      // A name written in quotes that is the script's variable (found by a probe: `{ search_grasp,
      // "transport" }` for the local transport): a string names a controller by the name it was made
      // with, and a variable is written bare.
      const std::string near = suggestion(name, candidates);
      const bool identifier = !name.empty() && !std::isdigit(static_cast<unsigned char>(name[0])) &&
                              std::all_of(name.begin(), name.end(), [](char c) {
                                return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
                              });
      const std::string bare = near.empty() && identifier
                                   ? " (a string names a controller by the name it was made with; a controller held "
                                     "in a variable " + name + " is given without quotes, as " + name + ")"
                                   : "";
      throw ScriptError(r.context + " names '" + name + "', which is not defined anywhere in the script" + near + bare +
                            "; " + known_names(*book),
                        r.where.file, r.where.line, r.traceback);
    }
    r.ref->bind(book->named[it->second].controller);
  }
  // A cycle must pass through a reference, and every reference is bound to a named controller:
  // checking whether each named controller can reach itself finds them all.
  for (const auto& n : book->named) {
    std::set<const Controller*> seen;
    std::vector<const Controller*> path;
    if (!path_back(n.controller.get(), n.controller.get(), seen, path)) continue;
    std::string chain = n.name;
    for (const Controller* c : path)
      if (!is_name_reference(*c)) chain += " -> " + c->name();
    chain += " -> " + n.name;
    unbind_all();
    throw ScriptError("skill '" + n.name + "' contains itself: " + chain, n.file, n.line, "");
  }
  book->finished = true;
}

std::vector<NamedController> named_controllers(LuaSandbox& sandbox) {
  std::vector<NamedController> out;
  with_state(sandbox, [&](lua_State* L) { out = book_of(L).named; });
  return out;
}

std::vector<ControllerPtr> script_controllers(LuaSandbox& sandbox) {
  std::vector<ControllerPtr> out;
  with_state(sandbox, [&](lua_State* L) { out = book_of(L).made; });
  return out;
}

void lua_push_controller(lua_State* L, const ControllerPtr& controller) {
  if (!controller) {
    lua_pushnil(L);
    return;
  }
  lua_rawgetp(L, LUA_REGISTRYINDEX, &cache_key);
  if (!lua_istable(L, -1)) raise(L, "the control API (roger.primitive, ...) is not installed in this Lua state");
  if (lua_rawgetp(L, -1, controller.get()) != LUA_TNIL) {
    lua_remove(L, -2);
    return;
  }
  lua_pop(L, 1);
  new (lua_newuserdatauv(L, sizeof(ControllerPtr), 0)) ControllerPtr(controller);
  luaL_setmetatable(L, kControllerType);
  lua_pushvalue(L, -1);
  lua_rawsetp(L, -3, controller.get());
  lua_remove(L, -2);
}

void lua_push_predicate(lua_State* L, const PredicatePtr& predicate) {
  if (!predicate) {
    lua_pushnil(L);
    return;
  }
  new (lua_newuserdatauv(L, sizeof(PredicatePtr), 0)) PredicatePtr(predicate);
  luaL_setmetatable(L, kPredicateType);
}

ControllerPtr lua_to_controller(lua_State* L, int index) {
  ControllerPtr* c = test_controller(L, index);
  return c ? *c : nullptr;
}

PredicatePtr lua_to_predicate(lua_State* L, int index) {
  PredicatePtr* p = test_predicate(L, index);
  return p ? *p : nullptr;
}

ControllerPtr lua_check_controller(lua_State* L, int index, const std::string& context,
                                   const std::string& what) {
  index = lua_absindex(L, index);
  if (ControllerPtr* c = test_controller(L, index)) return *c;
  const std::string prefix = context + ": " + what;
  if (lua_type(L, index) != LUA_TSTRING) {
    const std::string hint = test_predicate(L, index)
                                 ? " (a predicate is a condition, not an action)"
                                 : "";
    raise(L, prefix + " must be a controller (made by roger.primitive, roger.subject_to, roger.compose, "
                      "roger.sequence, roger.policy or roger.bind) or the name of one, got " +
                 lua_describe_value(L, index) + hint);
  }
  ControlBook& book = book_of(L);
  const std::string name = lua_tostring(L, index);
  if (name.empty()) raise(L, prefix + " is an empty name");
  if (ControllerPtr c = resolve_now(L, book, name)) return c;
  if (book.finished) {
    std::vector<std::string> candidates = primitive_names();
    for (const auto& n : book.named) candidates.push_back(n.name);
    raise(L, prefix + " names '" + name + "', which is not a controller" + suggestion(name, candidates) +
                 "; " + known_names(book));
  }
  // Defined later (or never): a stand-in, bound when the script finishes loading.
  auto it = book.references.find(name);
  if (it == book.references.end()) {
    count_object(L, book);
    const Location where = caller_location(L);
    it = book.references.emplace(name, Reference{std::make_shared<NameReference>(name), prefix, where,
                                                 traceback_through_another_file(L, where.file)}).first;
    book.reference_order.push_back(name);
  }
  return it->second.ref;
}

ApiFunction lua_control_function(lua_State* L, int index) {
  const lua_CFunction f = lua_tocfunction(L, index);
  if (!f) return {};
  for (const auto& e : lua_control_detail::kFunctions)
    if (e.function == f) return {std::string("roger.") + e.name, e.predicate_call ? e.predicate_call : ""};
  return {};
}

bool makes_predicate(const std::string& path) {
  for (const auto& e : lua_control_detail::kFunctions)
    if (e.predicate_call && path == std::string("roger.") + e.name) return true;
  return false;
}

PredicatePtr lua_check_predicate(lua_State* L, int index, const std::string& context, const std::string& what) {
  if (PredicatePtr* p = test_predicate(L, index)) return *p;
  const ApiFunction maker = lua_control_function(L, index);
  const std::string hint = test_controller(L, index)
                               ? " (a controller is an action, not a condition: write roger.converged(c) "
                                 "or roger.gamma(c, \"CONV\"))"
                           : !maker.predicate_call.empty()
                               ? " (the function " + maker.name + " itself: did you mean " + maker.predicate_call + "?)"
                           : lua_type(L, index) == LUA_TSTRING
                               ? std::string(" (a predicate is not named: write roger.converged(\"") + lua_tostring(L, index) +
                                     "\") for a controller of that name to be at equilibrium)"
                               : "";
  raise(L, context + ": " + what + " must be a predicate (roger.converged, roger.gamma, roger.all, "
                                   "roger.any, roger.negate, roger.held, roger.sorted), got " +
               lua_describe_value(L, index) + hint);
}

namespace {

// A list parameter's values written as a Lua list ({"left_eye", "right_eye"}): the comma-separated
// text --set takes, as Python's make() joins a list (found by a probe: "must be a number, string or
// boolean, got a table", where world:robot{ body = { locked = {...} } } takes a table).
std::string lua_param_list_text(lua_State* L, int index, const std::string& where) {
  index = lua_absindex(L, index);
  const lua_Integer n = lua_Integer(lua_rawlen(L, index));
  lua_pushnil(L);
  const bool empty = lua_next(L, index) == 0;
  if (!empty) lua_pop(L, 2);
  if (empty)
    luaL_error(L, "%s must be a number, string or boolean, or a list of names {\"a\", \"b\"} (a list parameter's "
                  "values), got an empty table (a list parameter with no values is \"\")", where.c_str());
  std::string text;
  lua_pushnil(L);
  while (lua_next(L, index)) {
    const bool item = lua_isinteger(L, -2) && lua_tointeger(L, -2) >= 1 && lua_tointeger(L, -2) <= n;
    const int type = lua_type(L, -1);
    if (!item || (type != LUA_TSTRING && type != LUA_TNUMBER))
      luaL_error(L, "%s must be a number, string or boolean, or a list of names {\"a\", \"b\"} (a list parameter's "
                    "values; or their text \"a,b\"), got a table with the %s %s", where.c_str(),
                 item ? "item" : "key", lua_describe_value(L, item ? -1 : -2).c_str());
    lua_pop(L, 1);
  }
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, index, i);
    const std::string value = lua_param_text(L, -1, where);  // a string or a number: checked above
    lua_pop(L, 1);
    if (value.find(',') != std::string::npos)
      luaL_error(L, "%s: item %d ('%s') holds a comma, which separates a list parameter's values", where.c_str(),
                 int(i), value.c_str());
    text += (i > 1 ? "," : "") + value;
  }
  return text;
}

}  // namespace

std::string lua_param_text(lua_State* L, int index, const std::string& where) {
  switch (lua_type(L, index)) {
    case LUA_TNUMBER:
      return lua_isinteger(L, index) ? std::to_string(lua_tointeger(L, index)) : format_number(lua_tonumber(L, index));
    case LUA_TBOOLEAN: return lua_toboolean(L, index) ? "true" : "false";
    case LUA_TSTRING: return lua_tostring(L, index);
    default:
      luaL_error(L, "%s must be a number, string or boolean, got %s", where.c_str(), lua_describe_value(L, index).c_str());
  }
  return "";
}

void lua_read_params(lua_State* L, int index, const std::string& where,
                     std::vector<std::pair<std::string, std::string>>& out, const std::string& key_where) {
  index = lua_absindex(L, index);
  if (!lua_istable(L, index))
    luaL_error(L, "%s must be a table of scenario parameters {key = value}, got %s", where.c_str(),
               lua_describe_value(L, index).c_str());
  lua_pushnil(L);
  while (lua_next(L, index)) {
    if (lua_type(L, -2) != LUA_TSTRING)
      luaL_error(L, "%s must have string keys {param = value}, got the key %s (a list? name each value)", where.c_str(),
                 lua_describe_value(L, -2).c_str());
    const std::string key = lua_tostring(L, -2);
    const std::string at = (key_where.empty() ? where + "." : key_where) + key;
    out.push_back({key, lua_istable(L, -1) ? lua_param_list_text(L, -1, at) : lua_param_text(L, -1, at)});
    lua_pop(L, 1);
  }
  std::sort(out.begin(), out.end());
}

std::string lua_describe_value(lua_State* L, int index) {
  index = lua_absindex(L, index);
  switch (lua_type(L, index)) {
    case LUA_TNONE:
    case LUA_TNIL: return "nil";
    case LUA_TBOOLEAN: return lua_toboolean(L, index) ? "boolean true" : "boolean false";
    case LUA_TNUMBER:
      return "number " + (lua_isinteger(L, index) ? std::to_string(lua_tointeger(L, index))
                                                  : format_number(lua_tonumber(L, index)));
    case LUA_TSTRING: {
      size_t length = 0;
      const char* text = lua_tolstring(L, index, &length);
      return "string '" + shortened_text(std::string(text, length), 40) + "'";  // cut between characters
    }
    case LUA_TTABLE: return "a table";
    case LUA_TFUNCTION: return "a function";
    default: break;
  }
  if (ControllerPtr* c = test_controller(L, index)) return controller_text(**c);
  if (PredicatePtr* p = test_predicate(L, index)) return "predicate " + (*p)->describe();
  return std::string("a ") + luaL_typename(L, index);
}

bool is_name_reference(const Controller& controller) {
  return dynamic_cast<const NameReference*>(&controller) != nullptr;
}

}  // namespace roger
