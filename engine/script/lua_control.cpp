#include "script/lua_control.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <map>
#include <set>

#include <lua.hpp>

#include "core/error.h"
#include "control/primitives.h"

namespace roger {
namespace {

constexpr const char* kControllerType = "roger.Controller";
constexpr const char* kPredicateType = "roger.Predicate";
constexpr const char* kBookType = "roger.ControlBook";
constexpr size_t kMaxObjects = 20000;             // controllers and predicates one script may make
constexpr size_t kMaxTableEntries = 4'000'000;    // policy table entries over the whole script
constexpr int kMaxPolicyActions = 12;             // 3^12 states, as Policy allows

// Registry keys: the addresses of these are unique and need no allocation to look up.
char book_key;  // mutable, so never merged with another constant
char cache_key;

// Joins items with a separator.
// Raises a Lua error with the text as is, located at the Lua caller's file:line.
[[noreturn]] void raise(lua_State* L, const std::string& message) {
  luaL_error(L, "%s", message.c_str());
  std::abort();  // unreachable: luaL_error does not return
}

// A place in a script: its file as shown in messages, and the line.
struct Location {
  std::string file;
  int line = 0;
};

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

// Levenshtein distance, for "did you mean" hints.
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// " (did you mean 'x'?)" when one known word is within two edits of the given one.
std::string suggestion(const std::string& given, const std::vector<std::string>& known) {
  std::string best;
  size_t best_distance = 3;
  for (const auto& k : known) {
    const size_t d = edit_distance(given, k);
    if (d < best_distance && d < std::max(given.size(), k.size())) best = k, best_distance = d;
  }
  return best.empty() ? "" : " (did you mean '" + best + "'?)";
}

// The stand-in for a controller named before it was defined. It behaves as the controller it is
// bound to when the script finishes loading; until then (or if never bound) it has no reference.
class NameReference final : public StandIn {
 public:
  explicit NameReference(std::string name) : StandIn(std::move(name)) {}
  const char* kind() const override { return target() ? target()->kind() : "reference"; }
};

// A predicate used as a policy's `done`: a controller with no command whose gamma is CONV while
// the predicate holds, !CONV otherwise.
class PredicateGoal final : public Controller {
 public:
  explicit PredicateGoal(PredicatePtr p) : p_(std::move(p)) { set_name(p_->describe()); }
  std::vector<const Controller*> children() const override {
    std::vector<const Controller*> out;
    p_->controllers(out);
    return out;
  }
  const char* kind() const override { return "predicate"; }
  void reset(uint64_t seed) override {
    Controller::reset(seed);
    p_->reset();
  }

 protected:
  void compute(const ControlInput& in, ControlOutput&, Gamma& gamma_raw) override {
    gamma_raw = p_->holds(in) ? Gamma::kConv : Gamma::kNotConv;
  }
  // It has no command: the state is all there is to compute.
  bool compute_state(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) override {
    compute(in, out, gamma_raw);
    return true;
  }

 private:
  PredicatePtr p_;
};

// A name used before its controller was defined, with where it was first used.
struct Reference {
  std::shared_ptr<NameReference> ref;
  std::string context;  // "roger.sequence('A'): step 2"
  Location where;
};

// What a script has defined: named controllers, default primitives, pending references. Lives in
// a userdata in the Lua registry, so it goes away with the state (the C++ objects it shares live
// on wherever the engine keeps them).
struct ControlBook {
  std::vector<NamedController> named;  // definition order
  std::map<std::string, size_t> by_name;
  std::map<std::string, PrimitivePtr> defaults;  // kind -> the shared default instance
  std::map<std::string, Reference> references;   // name -> its stand-in
  std::vector<std::string> reference_order;      // names in the order first referenced
  std::vector<ControllerPtr> made;               // every controller made, in order
  bool finished = false;
  size_t objects = 0;
  size_t table_entries = 0;
};

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
  if (++book.objects > kMaxObjects)
    raise(L, "too many controllers and predicates (a script may make at most " +
                 std::to_string(kMaxObjects) + ")");
  lua_charge(L, 50);
}

// Records a controller the script made (the book shares its ownership until the state closes).
template <class T>
std::shared_ptr<T> made(ControlBook& book, std::shared_ptr<T> c) {
  book.made.push_back(c);
  return c;
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
  return (names.empty() ? std::string("the script has named no controllers")
                        : "named controllers: " + join(names)) +
         "; primitive kinds: " + kinds_text();
}

// "controller 'Phi7' (sequence)", or "controller 'phi1'" when the name is the kind.
std::string controller_text(const Controller& c) {
  const std::string kind = c.kind();
  return "controller '" + c.name() + "'" + (kind == c.name() ? "" : " (" + kind + ")");
}

// The primitive behind a controller value, if it is one.
PrimitivePtr as_primitive(const ControllerPtr& c) { return std::dynamic_pointer_cast<Primitive>(c); }

// Resolves a name among the script's named controllers, then as a primitive kind (that kind's
// shared default instance, made on first use). Null when it is neither.
ControllerPtr resolve_now(lua_State* L, ControlBook& book, const std::string& name) {
  if (auto it = book.by_name.find(name); it != book.by_name.end()) return book.named[it->second].controller;
  if (!is_kind(name)) return nullptr;
  auto& slot = book.defaults[name];
  if (!slot) {
    count_object(L, book);
    slot = made(book, make_primitive(name));
  }
  return slot;
}

// Checks a new controller name and records the controller under it, with the caller's location.
void register_name(lua_State* L, ControlBook& book, const std::string& context, const std::string& name,
                   const ControllerPtr& c) {
  if (name.empty()) raise(L, context + ": a name must not be empty");
  if (name.find("<|") != std::string::npos)
    raise(L, context + ": the name '" + name + "' contains '<|', which roger.compose reads as subject-to");
  if (is_kind(name))
    raise(L, context + ": the name '" + name + "' is a primitive kind, which always means that kind's "
             "default primitive; choose another name (e.g. '" + name + "_tuned')");
  if (auto it = book.by_name.find(name); it != book.by_name.end()) {
    const auto& other = book.named[it->second];
    raise(L, context + ": there is already a controller named '" + name + "'" +
                 (other.file.empty() ? "" : " (defined at " + other.file + ":" + std::to_string(other.line) + ")"));
  }
  c->set_name(name);
  const Location where = caller_location(L);
  book.by_name[name] = book.named.size();
  book.named.push_back(NamedController{name, c, where.file, where.line});
}

// ---- userdata ----

// __gc of userdata holding a C++ object.
template <class T>
int destroy(lua_State* L) {
  static_cast<T*>(lua_touserdata(L, 1))->~T();
  return 0;
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

// The primitive a parameter method is called on, or an error saying what the controller is.
PrimitivePtr self_primitive(lua_State* L, const char* method) {
  const ControllerPtr c = self_controller(L, method);
  PrimitivePtr p = as_primitive(c);
  if (!p)
    raise(L, std::string("c:") + method + ": '" + c->name() + "' is a " + c->kind() +
                 "; only primitives have parameters");
  return p;
}

// The names of a primitive's parameters.
std::vector<std::string> param_names(const Primitive& p) {
  std::vector<std::string> names;
  for (const auto& d : p.param_defs()) names.push_back(d.name);
  return names;
}

// "[0, 1000000]" for messages.
std::string range_text(const ParamDef& d) {
  return "[" + format_number(d.min) + ", " + format_number(d.max) + "]";
}

// Sets the parameters in the table at `index` (nil: none) on a primitive; a `name` field is
// returned through `name` rather than set. Keys are applied in sorted order so that the first
// error reported does not depend on Lua's table order.
void apply_params(lua_State* L, Primitive& p, int index, const std::string& context, std::string& name,
                  bool& has_name) {
  index = lua_absindex(L, index);
  if (lua_isnoneornil(L, index)) return;
  const std::string known = join(param_names(p)) + " (and name)";
  if (!lua_istable(L, index))
    raise(L, context + ": the parameters must be a table {name = value, ...}, got " +
                 lua_describe_value(L, index) + "; " + p.kind() + "'s parameters: " + known);
  std::vector<std::string> keys;
  lua_pushnil(L);
  while (lua_next(L, index)) {
    lua_pop(L, 1);
    if (lua_type(L, -1) != LUA_TSTRING) {
      const std::string what = lua_isinteger(L, -1)
                                   ? "a value at position " + std::to_string(lua_tointeger(L, -1))
                                   : std::string("a key of type ") + luaL_typename(L, -1);
      raise(L, context + ": parameters are named (name = value), got " + what + "; " + p.kind() +
                   "'s parameters: " + known);
    }
    keys.push_back(lua_tostring(L, -1));
  }
  std::sort(keys.begin(), keys.end());
  for (const auto& key : keys) {
    lua_pushstring(L, key.c_str());
    lua_rawget(L, index);
    if (key == "name") {
      if (lua_type(L, -1) != LUA_TSTRING)
        raise(L, context + ": 'name' must be a string, got " + lua_describe_value(L, -1));
      name = lua_tostring(L, -1);
      has_name = true;
      lua_pop(L, 1);
      continue;
    }
    const ParamDef* def = nullptr;
    for (const auto& d : p.param_defs())
      if (d.name == key) def = &d;
    if (!def) {
      auto names = param_names(p);
      names.push_back("name");
      raise(L, context + ": unknown parameter '" + key + "'" + suggestion(key, names) + "; " + p.kind() +
                   "'s parameters: " + known);
    }
    const std::string param = context + ": parameter '" + key + "'";
    if (def->choices.empty()) {
      const std::string expected = "a number in " + range_text(*def);
      if (lua_type(L, -1) != LUA_TNUMBER)
        raise(L, param + " must be " + expected + ", got " + lua_describe_value(L, -1));
      const double v = lua_tonumber(L, -1);
      if (!std::isfinite(v)) raise(L, param + " must be a finite number in " + range_text(*def) + ", got " + format_number(v));
      if (v < def->min || v > def->max)
        raise(L, param + " must be within " + range_text(*def) + ", got " + format_number(v));
      p.set_number(key, v);
    } else {
      const std::string expected = "one of " + join(def->choices);
      if (lua_type(L, -1) != LUA_TSTRING) raise(L, param + " must be " + expected + ", got " + lua_describe_value(L, -1));
      const std::string v = lua_tostring(L, -1);
      if (std::find(def->choices.begin(), def->choices.end(), v) == def->choices.end())
        raise(L, param + " must be " + expected + ", got '" + v + "'");
      p.set_text(key, v);
    }
    lua_pop(L, 1);
  }
}

// roger.primitive(kind [, {param = value, ..., name = "..."}])
int l_primitive(lua_State* L) {
  return lua_protect(L, [L]() {
    ControlBook& book = book_of(L);
    if (lua_type(L, 1) != LUA_TSTRING)
      raise(L, "roger.primitive: argument 1 must be a primitive kind (one of " + kinds_text() + "), got " +
                   lua_describe_value(L, 1));
    const std::string kind = lua_tostring(L, 1);
    if (!is_kind(kind))
      raise(L, "roger.primitive: unknown primitive '" + kind + "'" + suggestion(kind, primitive_names()) +
                   "; known primitives: " + kinds_text());
    count_object(L, book);
    PrimitivePtr p = made(book, make_primitive(kind));
    std::string name;
    bool has_name = false;
    const std::string context = "roger.primitive('" + kind + "')";
    apply_params(L, *p, 2, context, name, has_name);
    if (has_name) register_name(L, book, context, name, p);
    lua_push_controller(L, p);
    return 1;
  });
}

// c:with{param = value, ..., name = "..."}: a copy of a primitive with some parameters changed.
// Names are not inherited: the copy shows its kind unless given a name.
int l_with(lua_State* L) {
  return lua_protect(L, [L]() {
    ControlBook& book = book_of(L);
    const PrimitivePtr original = self_primitive(L, "with");
    const std::string context = "c:with (on '" + original->name() + "')";
    count_object(L, book);
    PrimitivePtr p = made(book, original->clone());
    p->set_name(p->kind());
    std::string name;
    bool has_name = false;
    apply_params(L, *p, 2, context, name, has_name);
    if (has_name) register_name(L, book, context, name, p);
    lua_push_controller(L, p);
    return 1;
  });
}

// c:param(name): a primitive's parameter value (number or string).
int l_param(lua_State* L) {
  return lua_protect(L, [L]() {
    const PrimitivePtr p = self_primitive(L, "param");
    if (lua_type(L, 2) != LUA_TSTRING)
      raise(L, "c:param: argument 1 must be a parameter name, got " + lua_describe_value(L, 2));
    const std::string key = lua_tostring(L, 2);
    for (const auto& d : p->param_defs()) {
      if (d.name != key) continue;
      if (d.choices.empty()) lua_pushnumber(L, d.value);
      else lua_pushstring(L, d.text.c_str());
      return 1;
    }
    raise(L, "c:param: " + std::string(p->kind()) + " has no parameter '" + key + "'" +
                 suggestion(key, param_names(*p)) + "; its parameters: " + join(param_names(*p)));
  });
}

// c:params(): a table of a primitive's parameters and their values.
int l_params(lua_State* L) {
  const PrimitivePtr p = self_primitive(L, "params");
  lua_createtable(L, 0, int(p->param_defs().size()));
  for (const auto& d : p->param_defs()) {
    if (d.choices.empty()) lua_pushnumber(L, d.value);
    else lua_pushstring(L, d.text.c_str());
    lua_setfield(L, -2, d.name.c_str());
  }
  return 1;
}

// Makes sub <| sup and pushes it.
void push_subject_to(lua_State* L, ControlBook& book, ControllerPtr sub, ControllerPtr sup) {
  count_object(L, book);
  lua_push_controller(L, made(book, std::make_shared<SubjectTo>(std::move(sub), std::move(sup))));
}

// sub:subject_to(sup)
int l_subject_to_method(lua_State* L) {
  return lua_protect(L, [L]() {
    ControlBook& book = book_of(L);
    ControllerPtr sub = self_controller(L, "subject_to");
    ControllerPtr sup = lua_check_controller(L, 2, "c:subject_to", "argument 1 (the superior)");
    push_subject_to(L, book, std::move(sub), std::move(sup));
    return 1;
  });
}

// roger.subject_to(sub, sup)
int l_subject_to(lua_State* L) {
  return lua_protect(L, [L]() {
    ControlBook& book = book_of(L);
    ControllerPtr sub = lua_check_controller(L, 1, "roger.subject_to", "argument 1 (the subordinate)");
    ControllerPtr sup = lua_check_controller(L, 2, "roger.subject_to", "argument 2 (the superior)");
    push_subject_to(L, book, std::move(sub), std::move(sup));
    return 1;
  });
}

// The parser of roger.compose's notation: names, "<|" (right-associative) and parentheses.
class ComposeParser {
 public:
  ComposeParser(lua_State* L, ControlBook& book, std::string text, int table)
      : L_(L), book_(book), text_(std::move(text)), table_(table) {}

  ControllerPtr parse() {
    skip_space();
    if (pos_ >= text_.size()) fail("the expression is empty; write e.g. \"phi1 <| phi4 <| phi5\"");
    ControllerPtr c = expression();
    skip_space();
    if (pos_ < text_.size()) fail("expected '<|' or the end at column " + std::to_string(pos_ + 1) + ", got '" + text_.substr(pos_) + "'");
    return c;
  }

 private:
  [[noreturn]] void fail(const std::string& message) {
    raise(L_, "roger.compose(\"" + text_ + "\"): " + message);
  }

  void skip_space() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }

  bool at_operator() const { return text_.compare(pos_, 2, "<|") == 0; }

  // expression := term [ "<|" expression ]
  ControllerPtr expression() {
    ControllerPtr left = term();
    skip_space();
    if (!at_operator()) return left;
    pos_ += 2;
    ControllerPtr right = expression();
    count_object(L_, book_);
    return made(book_, std::make_shared<SubjectTo>(std::move(left), std::move(right)));
  }

  // term := name | "(" expression ")"
  ControllerPtr term() {
    skip_space();
    if (pos_ >= text_.size()) fail("expected a controller name or '(' at the end");
    if (text_[pos_] == '(') {
      ++pos_;
      ControllerPtr inner = expression();
      skip_space();
      if (pos_ >= text_.size() || text_[pos_] != ')') fail("missing ')' at column " + std::to_string(pos_ + 1));
      ++pos_;
      return inner;
    }
    const size_t start = pos_;
    while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_])) && text_[pos_] != '(' &&
           text_[pos_] != ')' && !at_operator())
      ++pos_;
    if (pos_ == start) fail("expected a controller name at column " + std::to_string(start + 1) + ", got '" + text_.substr(start) + "'");
    return lookup(text_.substr(start, pos_ - start));
  }

  // The table entry, else a named controller, else a primitive kind's default instance.
  ControllerPtr lookup(const std::string& name) {
    if (table_) {
      lua_pushstring(L_, name.c_str());
      if (lua_rawget(L_, table_) != LUA_TNIL) {
        ControllerPtr* c = test_controller(L_, -1);
        if (!c) fail("the table's entry '" + name + "' must be a controller, got " + lua_describe_value(L_, -1));
        ControllerPtr out = *c;
        lua_pop(L_, 1);
        return out;
      }
      lua_pop(L_, 1);
    }
    if (ControllerPtr c = resolve_now(L_, book_, name)) return c;
    std::vector<std::string> candidates = primitive_names();
    for (const auto& n : book_.named) candidates.push_back(n.name);
    std::string table_keys;
    if (table_) {
      std::vector<std::string> keys;
      lua_pushnil(L_);
      while (lua_next(L_, table_)) {
        lua_pop(L_, 1);
        if (lua_type(L_, -1) == LUA_TSTRING) keys.push_back(lua_tostring(L_, -1));
      }
      std::sort(keys.begin(), keys.end());
      candidates.insert(candidates.end(), keys.begin(), keys.end());
      table_keys = keys.empty() ? "the table is empty; " : "the table has " + join(keys) + "; ";
    }
    fail("unknown controller '" + name + "'" + suggestion(name, candidates) + "; " + table_keys +
         known_names(book_));
  }

  lua_State* L_;
  ControlBook& book_;
  std::string text_;
  int table_;
  size_t pos_ = 0;
};

// roger.compose("phi1 <| phi4 <| phi5" [, {phi1 = carry, ...}])
int l_compose(lua_State* L) {
  return lua_protect(L, [L]() {
    ControlBook& book = book_of(L);
    if (lua_type(L, 1) != LUA_TSTRING)
      raise(L, "roger.compose: argument 1 must be an expression such as \"phi1 <| phi4 <| phi5\", got " +
                   lua_describe_value(L, 1));
    int table = 0;
    if (!lua_isnoneornil(L, 2)) {
      if (!lua_istable(L, 2))
        raise(L, "roger.compose: argument 2 must be a table {name = controller, ...}, got " + lua_describe_value(L, 2));
      table = 2;
    }
    ComposeParser parser(L, book, lua_tostring(L, 1), table);
    lua_push_controller(L, parser.parse());
    return 1;
  });
}

// A skill's name argument: a string, checked when it is registered.
std::string skill_name(lua_State* L, const char* function) {
  if (lua_type(L, 1) != LUA_TSTRING)
    raise(L, std::string(function) + ": argument 1 must be the skill's name (a string), got " +
                 lua_describe_value(L, 1));
  return lua_tostring(L, 1);
}

// Reads a list of controllers (steps or actions) at `index`.
std::vector<ControllerPtr> controller_list(lua_State* L, int index, const std::string& context,
                                           const char* field, const char* item) {
  index = lua_absindex(L, index);
  if (!lua_istable(L, index))
    raise(L, context + ": " + field + " must be a list of controllers (or their names), got " +
                 lua_describe_value(L, index));
  const lua_Integer n = lua_Integer(lua_rawlen(L, index));
  lua_pushnil(L);
  while (lua_next(L, index)) {
    lua_pop(L, 1);
    if (!lua_isinteger(L, -1) || lua_tointeger(L, -1) < 1 || lua_tointeger(L, -1) > n)
      raise(L, context + ": " + field + " must be a list {c1, c2, ...}, but it has the key " +
                   lua_describe_value(L, -1));
  }
  if (n == 0) raise(L, context + ": " + field + " is empty");
  std::vector<ControllerPtr> out;
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, index, i);
    out.push_back(lua_check_controller(L, -1, context, std::string(item) + " " + std::to_string(i)));
    lua_pop(L, 1);
  }
  return out;
}

// roger.sequence(name, {step, step, ...})
int l_sequence(lua_State* L) {
  return lua_protect(L, [L]() {
    ControlBook& book = book_of(L);
    const std::string name = skill_name(L, "roger.sequence");
    const std::string context = "roger.sequence('" + name + "')";
    if (lua_gettop(L) > 2)
      raise(L, context + ": expects (name, {step, ...}), got " + std::to_string(lua_gettop(L)) + " arguments");
    auto steps = controller_list(L, 2, context, "the steps", "step");
    count_object(L, book);
    auto seq = made(book, std::make_shared<Sequence>(std::move(steps)));
    register_name(L, book, context, name, seq);
    lua_push_controller(L, seq);
    return 1;
  });
}

// The index (0-based) of the action a policy table value means: a controller among the actions,
// an action's name, or a 1-based index.
int action_index(lua_State* L, ControlBook& book, int index, const std::vector<ControllerPtr>& actions,
                 const std::string& where) {
  std::vector<std::string> names;
  for (const auto& a : actions) names.push_back(a->name());
  const std::string listing = "; the actions are " + join(names) + " (or their indices 1 to " +
                              std::to_string(actions.size()) + ")";
  if (lua_type(L, index) == LUA_TNUMBER) {
    if (!lua_isinteger(L, index) || lua_tointeger(L, index) < 1 || lua_tointeger(L, index) > lua_Integer(actions.size()))
      raise(L, where + " must be an action or its index 1 to " + std::to_string(actions.size()) + ", got " +
                   lua_describe_value(L, index));
    return int(lua_tointeger(L, index)) - 1;
  }
  ControllerPtr c;
  if (ControllerPtr* box = test_controller(L, index)) {
    c = *box;
  } else if (lua_type(L, index) == LUA_TSTRING) {
    const std::string name = lua_tostring(L, index);
    int found = -1;
    for (size_t i = 0; i < actions.size(); ++i) {
      if (actions[i]->name() != name) continue;
      if (found >= 0) raise(L, where + ": the name '" + name + "' is ambiguous: actions " + std::to_string(found + 1) +
                                   " and " + std::to_string(i + 1) + " both have it; use the index or the controller");
      found = int(i);
    }
    if (found >= 0) return found;
    c = resolve_now(L, book, name);
    if (!c) raise(L, where + " names '" + name + "', which is not an action" + listing);
  } else {
    raise(L, where + " must be an action (a controller, its name or its index), got " + lua_describe_value(L, index) + listing);
  }
  for (size_t i = 0; i < actions.size(); ++i)
    if (actions[i] == c) return int(i);
  raise(L, where + " is '" + c->name() + "', which is not one of the policy's actions" + listing);
}

// Parses a state key "CONV !CONV NOREF" (or with "*" wildcards) into one gamma per action; -1
// marks a wildcard.
std::vector<int> parse_state_key(lua_State* L, const std::string& key, size_t n, const std::string& where,
                                 const std::vector<ControllerPtr>& actions) {
  std::vector<int> out;
  std::string token;
  auto flush = [&]() {
    if (token.empty()) return;
    std::string upper = token;
    std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char ch) { return char(std::toupper(ch)); });
    if (upper == "*") out.push_back(-1);
    else if (upper == "NOREF") out.push_back(int(Gamma::kNoRef));
    else if (upper == "!CONV") out.push_back(int(Gamma::kNotConv));
    else if (upper == "CONV") out.push_back(int(Gamma::kConv));
    else raise(L, where + ": '" + token + "' is not a state; write NOREF, !CONV, CONV or * for each action");
    token.clear();
  };
  for (char ch : key) {
    if (std::isspace(static_cast<unsigned char>(ch)) || ch == ',') flush();
    else token += ch;
  }
  flush();
  if (out.size() != n) {
    std::vector<std::string> names;
    for (const auto& a : actions) names.push_back(a->name());
    raise(L, where + ": the key has " + std::to_string(out.size()) + " states but the policy has " +
                 std::to_string(n) + " actions (" + join(names) + "); write NOREF, !CONV, CONV or * for each, in that order");
  }
  return out;
}

// roger.policy(name, {actions = {...}, table = {[state] = action, ...}, done = c_or_p, fallback = a})
int l_policy(lua_State* L) {
  return lua_protect(L, [L]() {
    ControlBook& book = book_of(L);
    const std::string name = skill_name(L, "roger.policy");
    const std::string context = "roger.policy('" + name + "')";
    LuaFields f(L, 2, context, {"actions", "table", "done", "fallback"});
    if (!f.has("actions")) f.fail("missing required field 'actions' (a list of controllers)");
    f.push("actions");
    std::vector<ControllerPtr> actions = controller_list(L, -1, context, "'actions'", "action");
    lua_pop(L, 1);
    if (int(actions.size()) > kMaxPolicyActions)
      f.fail("at most " + std::to_string(kMaxPolicyActions) + " actions (3^" + std::to_string(kMaxPolicyActions) +
             " states), got " + std::to_string(actions.size()));
    const size_t n = actions.size();
    size_t states = 1;
    for (size_t i = 0; i < n; ++i) states *= 3;
    if (book.table_entries + states > kMaxTableEntries)
      f.fail("the script's policy tables exceed " + std::to_string(kMaxTableEntries) + " entries in all");
    book.table_entries += states;

    std::vector<int> table(states, -1), specificity(states, -1);
    std::vector<std::string> source(states);
    if (f.push("table") == LUA_TNIL) f.fail("missing required field 'table' ({[\"CONV !CONV\"] = action, ...})");
    if (!lua_istable(L, -1)) f.wrong_type("table", "a table {[\"CONV !CONV ...\"] = action, ...}");
    const int t = lua_gettop(L);
    std::vector<std::string> keys;
    lua_pushnil(L);
    while (lua_next(L, t)) {
      lua_pop(L, 1);
      if (lua_type(L, -1) != LUA_TSTRING)
        f.fail("the table's keys must be states such as \"CONV !CONV NOREF\", got " + lua_describe_value(L, -1));
      keys.push_back(lua_tostring(L, -1));
    }
    std::sort(keys.begin(), keys.end());
    for (const auto& key : keys) {
      const std::string where = context + ": table[\"" + key + "\"]";
      const std::vector<int> pattern = parse_state_key(L, key, n, where, actions);
      lua_pushstring(L, key.c_str());
      lua_rawget(L, t);
      const int action = action_index(L, book, -1, actions, where);
      lua_pop(L, 1);
      int wild = 0;
      for (int g : pattern) wild += g < 0;
      const int spec = int(n) - wild;
      // Every state the key matches: count through the wildcard positions in base 3.
      std::vector<size_t> wild_at;
      for (size_t i = 0; i < n; ++i)
        if (pattern[i] < 0) wild_at.push_back(i);
      size_t combinations = 1;
      for (size_t i = 0; i < wild_at.size(); ++i) combinations *= 3;
      lua_charge(L, combinations);
      std::vector<int> gammas(pattern);
      for (size_t k = 0; k < combinations; ++k) {
        size_t digits = k;
        for (size_t w = wild_at.size(); w-- > 0;) {
          gammas[wild_at[w]] = int(digits % 3);
          digits /= 3;
        }
        int index = 0;
        for (int g : gammas) index = index * 3 + g;
        const size_t at = size_t(index);
        if (specificity[at] == spec && table[at] != action) {
          std::string state;
          for (size_t i = 0; i < n; ++i) state += (i ? " " : "") + std::string(gamma_name(Gamma(gammas[i])));
          f.fail("the keys \"" + source[at] + "\" and \"" + key + "\" both match the state " + state +
                 " with different actions; make one of them more specific");
        }
        if (spec > specificity[at]) {
          specificity[at] = spec;
          table[at] = action;
          source[at] = key;
        }
      }
    }
    lua_settop(L, t - 1);

    int fallback = -1;
    if (f.push("fallback") != LUA_TNIL) fallback = action_index(L, book, -1, actions, context + ": fallback");
    lua_pop(L, 1);
    ControllerPtr done;
    if (f.push("done") != LUA_TNIL) {
      if (PredicatePtr* p = test_predicate(L, -1)) {
        count_object(L, book);
        done = made(book, std::make_shared<PredicateGoal>(*p));
      } else {
        done = lua_check_controller(L, -1, context, "field 'done' (a controller or a predicate)");
      }
    }
    lua_pop(L, 1);
    count_object(L, book);
    auto policy = made(book, std::make_shared<Policy>(std::move(actions), std::move(table), std::move(done), fallback));
    register_name(L, book, context, name, policy);
    lua_push_controller(L, policy);
    return 1;
  });
}

// ---- predicates ----

// Makes a predicate (may throw roger::Error) and pushes it.
void push_new_predicate(lua_State* L, PredicatePtr p) {
  count_object(L, book_of(L));
  lua_push_predicate(L, p);
}

// roger.converged(c)
int l_converged(lua_State* L) {
  return lua_protect(L, [L]() {
    push_new_predicate(L, converged(lua_check_controller(L, 1, "roger.converged", "argument 1")));
    return 1;
  });
}

// roger.gamma(c, "NOREF" | "!CONV" | "CONV")
int l_gamma(lua_State* L) {
  return lua_protect(L, [L]() {
    ControllerPtr c = lua_check_controller(L, 1, "roger.gamma", "argument 1");
    const std::string given = lua_type(L, 2) == LUA_TSTRING ? lua_tostring(L, 2) : "";
    for (Gamma g : {Gamma::kNoRef, Gamma::kNotConv, Gamma::kConv}) {
      if (given == gamma_name(g)) {
        push_new_predicate(L, gamma_is(c, g));
        return 1;
      }
    }
    raise(L, "roger.gamma: argument 2 must be \"NOREF\", \"!CONV\" or \"CONV\", got " + lua_describe_value(L, 2));
  });
}

// roger.all{p, ...} / roger.any{p, ...} (or the predicates as separate arguments).
int combine(lua_State* L, bool all) {
  return lua_protect(L, [L, all]() {
    const std::string context = all ? "roger.all" : "roger.any";
    std::vector<PredicatePtr> parts;
    if (lua_gettop(L) == 1 && lua_istable(L, 1)) {
      const lua_Integer n = lua_Integer(lua_rawlen(L, 1));
      lua_pushnil(L);
      while (lua_next(L, 1)) {
        lua_pop(L, 1);
        if (!lua_isinteger(L, -1) || lua_tointeger(L, -1) < 1 || lua_tointeger(L, -1) > n)
          raise(L, context + ": expects a list of predicates {p1, p2, ...}, but it has the key " +
                       lua_describe_value(L, -1));
      }
      for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L, 1, i);
        parts.push_back(lua_check_predicate(L, -1, context, "element " + std::to_string(i)));
        lua_pop(L, 1);
      }
    } else {
      for (int i = 1; i <= lua_gettop(L); ++i)
        parts.push_back(lua_check_predicate(L, i, context, "argument " + std::to_string(i)));
    }
    push_new_predicate(L, all ? all_of(std::move(parts)) : any_of(std::move(parts)));
    return 1;
  });
}
int l_all(lua_State* L) { return combine(L, true); }
int l_any(lua_State* L) { return combine(L, false); }

// roger.negate(p), also roger["not"](p)
int l_negate(lua_State* L) {
  return lua_protect(L, [L]() {
    push_new_predicate(L, negate(lua_check_predicate(L, 1, "roger.negate", "argument 1")));
    return 1;
  });
}

// roger.held(p, seconds)
int l_held(lua_State* L) {
  return lua_protect(L, [L]() {
    PredicatePtr p = lua_check_predicate(L, 1, "roger.held", "argument 1");
    const double seconds = lua_tonumber(L, 2);
    if (lua_type(L, 2) != LUA_TNUMBER || !std::isfinite(seconds) || seconds < 0.0)
      raise(L, "roger.held: argument 2 must be a duration in seconds (a finite number >= 0), got " +
                   lua_describe_value(L, 2));
    push_new_predicate(L, held(p, seconds));
    return 1;
  });
}

// ---- metamethods ----

// Pushes a part of a composite: a name stand-in shows as the controller it is bound to.
void push_part(lua_State* L, const ControllerPtr& part) {
  const auto* ref = dynamic_cast<const NameReference*>(part.get());
  lua_push_controller(L, ref && ref->target() ? ref->target() : part);
}

// Pushes a list of controllers as a Lua list.
void push_parts(lua_State* L, const std::vector<ControllerPtr>& parts) {
  lua_createtable(L, int(parts.size()), 0);
  for (size_t i = 0; i < parts.size(); ++i) {
    push_part(L, parts[i]);
    lua_rawseti(L, -2, lua_Integer(i + 1));
  }
}

// c.name, c.kind, the parts of composites (subordinate, superior, steps, actions) and the methods.
int l_controller_index(lua_State* L) {
  return lua_protect(L, [L]() {
    const ControllerPtr c = *static_cast<ControllerPtr*>(luaL_checkudata(L, 1, kControllerType));
    const std::string key = lua_type(L, 2) == LUA_TSTRING ? lua_tostring(L, 2) : "";
    const auto* sub = dynamic_cast<const SubjectTo*>(c.get());
    const auto* seq = dynamic_cast<const Sequence*>(c.get());
    const auto* pol = dynamic_cast<const Policy*>(c.get());
    if (key == "name") {
      lua_pushstring(L, c->name().c_str());
    } else if (key == "kind") {
      lua_pushstring(L, c->kind());
    } else if (key == "subordinate" && sub) {
      push_part(L, sub->subordinate());
    } else if (key == "superior" && sub) {
      push_part(L, sub->superior());
    } else if (key == "steps" && seq) {
      push_parts(L, seq->steps());
    } else if (key == "actions" && pol) {
      push_parts(L, pol->actions());
    } else if (key == "with" || key == "subject_to" || key == "param" || key == "params") {
      lua_getmetatable(L, 1);
      lua_getfield(L, -1, key.c_str());
    } else {
      const std::string parts = sub ? "subordinate, superior, " : seq ? "steps, " : pol ? "actions, " : "";
      raise(L, controller_text(*c) + " has no field '" + key + "'; it has name, kind, " +
                   parts + "and the methods with{...}, subject_to(sup), param(name), params()");
    }
    return 1;
  });
}

// Controllers are values: changing one in place would change every composition holding it.
int l_controller_newindex(lua_State* L) {
  return luaL_error(L, "controllers cannot be changed in place; make a changed copy with c:with{...}");
}

// tostring(c): "controller 'phi4 <| phi2' (subject_to)".
int l_controller_tostring(lua_State* L) {
  const ControllerPtr& c = *static_cast<ControllerPtr*>(luaL_checkudata(L, 1, kControllerType));
  return lua_protect(L, [L, &c]() {
    lua_pushstring(L, controller_text(*c).c_str());
    return 1;
  });
}

// tostring(p): "predicate converged(phi3)".
int l_predicate_tostring(lua_State* L) {
  const PredicatePtr& p = *static_cast<PredicatePtr*>(luaL_checkudata(L, 1, kPredicateType));
  return lua_protect(L, [L, &p]() {
    const std::string text = "predicate " + p->describe();
    lua_pushstring(L, text.c_str());
    return 1;
  });
}

// Predicates have no fields: say what to do with them instead.
int l_predicate_index(lua_State* L) {
  return luaL_error(L, "a predicate has no fields; combine predicates with roger.all, roger.any, "
                    "roger.negate and roger.held");
}

// Registers a metatable with the given metamethods; __metatable hides it from scripts.
void new_class(lua_State* L, const char* type, const luaL_Reg* entries) {
  luaL_newmetatable(L, type);
  luaL_setfuncs(L, entries, 0);
  lua_pushboolean(L, 0);
  lua_setfield(L, -2, "__metatable");
  lua_pop(L, 1);
}

// Installs the metatables, the book, the userdata cache and the functions (run protected).
int install(lua_State* L) {
  lua_rawgetp(L, LUA_REGISTRYINDEX, &book_key);
  const bool installed = !lua_isnil(L, -1);
  lua_pop(L, 1);
  if (installed) return 0;

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

  new (lua_newuserdatauv(L, sizeof(ControlBook), 0)) ControlBook();
  luaL_setmetatable(L, kBookType);
  lua_rawsetp(L, LUA_REGISTRYINDEX, &book_key);

  // One userdata per controller (weak values): the same controller is the same Lua value.
  lua_newtable(L);
  lua_newtable(L);
  lua_pushliteral(L, "v");
  lua_setfield(L, -2, "__mode");
  lua_setmetatable(L, -2);
  lua_rawsetp(L, LUA_REGISTRYINDEX, &cache_key);

  if (lua_getglobal(L, "roger") != LUA_TTABLE) {
    lua_pop(L, 1);
    lua_newtable(L);
    lua_pushvalue(L, -1);
    lua_setglobal(L, "roger");
  }
  const luaL_Reg functions[] = {{"primitive", l_primitive}, {"subject_to", l_subject_to},
                                {"compose", l_compose},     {"sequence", l_sequence},
                                {"policy", l_policy},       {"converged", l_converged},
                                {"gamma", l_gamma},         {"all", l_all},
                                {"any", l_any},             {"negate", l_negate},
                                {"not", l_negate},          {"held", l_held},
                                {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
  const auto& kinds = primitive_names();
  lua_createtable(L, int(kinds.size()), 0);
  for (size_t i = 0; i < kinds.size(); ++i) {
    lua_pushstring(L, kinds[i].c_str());
    lua_rawseti(L, -2, lua_Integer(i + 1));
  }
  lua_setfield(L, -2, "primitive_kinds");
  lua_pop(L, 1);
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
      throw ScriptError(r.context + " names '" + name + "', which is not defined anywhere in the script" +
                            suggestion(name, candidates) + "; " + known_names(*book),
                        r.where.file, r.where.line, "");
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
                      "roger.sequence or roger.policy) or the name of one, got " +
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
    it = book.references.emplace(name, Reference{std::make_shared<NameReference>(name), prefix, caller_location(L)}).first;
    book.reference_order.push_back(name);
  }
  return it->second.ref;
}

PredicatePtr lua_check_predicate(lua_State* L, int index, const std::string& context, const std::string& what) {
  if (PredicatePtr* p = test_predicate(L, index)) return *p;
  const std::string hint = test_controller(L, index)
                               ? " (a controller is an action, not a condition: write roger.converged(c) "
                                 "or roger.gamma(c, \"CONV\"))"
                               : "";
  raise(L, context + ": " + what + " must be a predicate (roger.converged, roger.gamma, roger.all, "
                                   "roger.any, roger.negate, roger.held), got " +
               lua_describe_value(L, index) + hint);
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
      std::string s = lua_tostring(L, index);
      if (s.size() > 40) s = s.substr(0, 37) + "...";
      return "string '" + s + "'";
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
