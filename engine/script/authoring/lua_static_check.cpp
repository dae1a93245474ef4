// lua_static_check.cpp: the static pass of `roger check` (lua_static_check.h): a scan of the
// tokens that follows Lua's scoping closely enough to tell locals from globals, and lists the
// globals read and written, the roger.* members used and the modules required.
#include "script/authoring/lua_static_check.h"

#include <algorithm>
#include <cctype>
#include <deque>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <set>

#include <lua.hpp>

#include "core/fileio.h"
#include "core/text.h"
#include "script/control/lua_control.h"  // makes_predicate
#include "script/sandbox/lua_sandbox.h"  // edit_distance
#include "script/sandbox/lua_tokens.h"

namespace roger {
namespace fs = std::filesystem;
namespace {

struct Access {
  // kDynamic: globals made where this pass cannot name them (load, _G[name] = v, rawset(_G, name, v)).
  enum Kind { kRead, kWrite, kMember, kMemberWrite, kRequire, kFinding, kDynamic } kind;
  std::string name;  // a global, a dotted member path ("roger.robot.base_radius"), a module, or
                     // a finding's whole message
  int line;
  std::vector<std::string> locals = {};  // of a read: the locals in scope, for suggestions
  std::string literal = {};              // of a finding: the string literal compared
  // The functions it lies in, outermost first, after 0 for the chunk ({0}: at the top; a write
  // through the globals' table counts as one there, meant as a global wherever it is written).
  std::vector<int> functions = {};
  bool in_function() const { return functions.size() > 1; }
};

// A local (or a parameter) as declared: a global read of its name elsewhere is a local out of scope.
struct LocalDeclaration {
  std::string name;
  int line;
  bool parameter = false;  // a function's
  int function = 0;        // the function it belongs to (0: the chunk)
  int function_line = 0;   // where that function is written
};

// A scope (block, function, loop, branch) or a bracket; locals live in scopes only. Aliases are
// the locals that hold `roger` itself (local R = roger), whose members are roger's.
struct Frame {
  enum Kind { kBlock, kFunction, kLoopHeader, kIf, kRepeat, kBrace, kParen, kBracket } kind;
  std::set<std::string> locals;
  std::set<std::string> aliases = {};
  std::string third = {};  // a function's third parameter: a reward function's event
  int function = 0;        // a function's number in the file (from 1), its line beside it
  int function_line = 0;
  bool bracket() const { return kind == kBrace || kind == kParen || kind == kBracket; }
};

// Locals of a `local` statement, declared once its expression list has been read: Lua evaluates
// `local x = x` before x is in scope, so that x is the global.
struct PendingLocals {
  size_t end;                      // the last token of the expression list
  std::vector<std::string> names;
  bool alias;                      // local R = roger
};

// Binary operators: after an operand, one of these continues the expression.
bool binary_operator(const LuaToken& t) {
  static const std::set<std::string> ops = {"+", "-", "*", "/", "//", "%", "^", "..", "==", "~=", "<",
                                            "<=", ">", ">=", "&", "|", "~", "<<", ">>"};
  if (t.type == LuaToken::kName) return t.text == "and" || t.text == "or";
  return t.type == LuaToken::kOp && ops.count(t.text);
}

// Binary operators that bind tighter than a comparison: after one, or before one, a token is not
// a comparison's whole operand (`a .. state.x == "CONV"` compares the concatenation).
bool tighter_than_comparison(const LuaToken& t) {
  static const std::set<std::string> cmp = {"==", "~=", "<", "<=", ">", ">="};
  return binary_operator(t) && t.type == LuaToken::kOp && !cmp.count(t.text);
}

// ---- closed vocabularies: a string compared with a word of one must be one ----
// A stage's callbacks get each action's state as one of these, and a reward function's third
// argument is one of these events; a near miss ("conv", "timout") compares false for good, and the
// stage learns nothing without a word.

const std::vector<std::string> kStates = {"NOREF", "!CONV", "CONV"};
const std::vector<std::string> kEvents = {"decision", "absorbing", "timeout"};

bool among(const std::vector<std::string>& words, const std::string& w) {
  return std::find(words.begin(), words.end(), w) != words.end();
}
bool starts(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

// `s` upper- or lower-cased, without its spaces, '_' and '-': "Not conv" -> "NOTCONV".
std::string squeezed(const std::string& s, bool upper) {
  std::string out;
  for (const unsigned char c : s)
    if (c != ' ' && c != '_' && c != '-') out += static_cast<char>(upper ? std::toupper(c) : std::tolower(c));
  return out;
}

// The state a literal that is none meant: the same word in another case or spacing, or spelt out
// ("converged", "not CONV", "no_ref"); else the nearest by edits to the literal as written (its
// case kept, so that a "cone" is not read as CONV). Empty when it is a state or near none.
std::string meant_state(const std::string& s) {
  if (among(kStates, s)) return "";
  std::string u = squeezed(s, true);
  if (starts(u, "NOT") || starts(u, "NON")) u = "!" + u.substr(3);
  if (starts(u, "UNCONV")) u = "!" + u.substr(2);
  const size_t converg = u.find("CONVERG");
  if (converg <= 1) u = u.substr(0, converg + 4);  // CONVERGED, !CONVERGED
  if (starts(u, "NOREFERENCE")) u = "NOREF";
  if (among(kStates, u)) return u;
  const auto near = nearest_names(s, kStates);
  return near.empty() ? "" : near[0];
}

// The event a literal that is none meant: another case or spacing ("Timeout", "time out"), another
// form of the word ("absorbed", "decisions", "timed_out"), or the nearest by edits ("timout").
std::string meant_event(const std::string& s) {
  if (among(kEvents, s)) return "";
  const std::string l = squeezed(s, false);
  if (among(kEvents, l)) return l;
  if (starts(l, "absorb")) return "absorbing";
  if (starts(l, "decid") || starts(l, "decis")) return "decision";
  if (starts(l, "timeout") || starts(l, "timedout")) return "timeout";
  const auto near = nearest_names(l, kEvents);
  return near.empty() ? "" : near[0];
}

// The finding: `"conv" is compared with state.phi3, but a controller's state is "NOREF", "!CONV" or
// "CONV" (did you mean "CONV"?)`; `what` says what the other operand is ("a controller's state").
std::string never_equal(const std::string& literal, const std::string& with, const std::string& what,
                        const std::vector<std::string>& words, const std::string& meant) {
  std::string m = "\"" + literal + "\" is compared with " + with + ", but " + what + " is ";
  for (size_t i = 0; i < words.size(); ++i)
    m += (i == 0 ? "" : i + 1 == words.size() ? " or " : ", ") + ("\"" + words[i] + "\"");
  return m + " (did you mean \"" + meant + "\"?)";
}

// One pass over a file's tokens, in order, keeping the stack of scopes and brackets.
class Scanner {
 public:
  explicit Scanner(const std::string& text) : t_(lua_tokenize(text)) {
    frames_.push_back({Frame::kBlock, {}});  // the chunk
    for (i_ = 0; t_[i_].type != LuaToken::kEnd; ++i_) {
      step();
      while (!pending_.empty() && i_ >= pending_.back().end) {
        for (const auto& n : pending_.back().names) declare(n, pending_.back().alias);
        pending_.pop_back();
      }
    }
    count_values_written();
  }
  std::vector<Access> accesses;
  std::vector<LocalDeclaration> local_declarations;  // in file order
  std::set<std::string> values_written;              // string literals written outside comparisons

 private:
  const LuaToken& at(size_t k) const { return t_[std::min(k, t_.size() - 1)]; }
  bool op(size_t k, const char* s) const { return at(k).type == LuaToken::kOp && at(k).text == s; }
  bool word(size_t k, const char* w) const { return at(k).type == LuaToken::kName && at(k).text == w; }
  bool name(size_t k) const { return at(k).type == LuaToken::kName && !lua_keyword(at(k).text); }
  bool after(const char* s) const { return i_ > 0 && op(i_ - 1, s); }
  Frame& top() { return frames_.back(); }
  void note(Access::Kind kind, const std::string& n, int line) {
    accesses.push_back({kind, n, line});
    Access& a = accesses.back();
    a.functions.push_back(0);
    for (const Frame& f : frames_)
      if (f.kind == Frame::kFunction) a.functions.push_back(f.function);
  }
  const Frame* innermost_function() const {
    for (auto it = frames_.rbegin(); it != frames_.rend(); ++it)
      if (it->kind == Frame::kFunction) return &*it;
    return nullptr;
  }
  // A local declared at t, of the innermost function (or of `of`, a function being opened).
  void declared_at(const LuaToken& t, bool parameter = false, const Frame* of = nullptr) {
    const Frame* f = of ? of : innermost_function();
    local_declarations.push_back({t.text, t.line, parameter, f ? f->function : 0, f ? f->function_line : 0});
  }
  // A global written through the globals' table (_G.x = v) is meant as one, wherever it is written.
  void meant_global(const std::string& n, int line) {
    note(Access::kWrite, n, line);
    accesses.back().functions = {0};
  }

  // Declares a local in the innermost scope (brackets hold none), an alias of roger or not.
  void declare(const std::string& n, bool alias = false) {
    for (auto it = frames_.rbegin(); it != frames_.rend(); ++it)
      if (!it->bracket()) {
        it->locals.insert(n);
        if (it->third == n) it->third.clear();  // `local event = ...` is no longer the argument
        if (alias) it->aliases.insert(n);
        else it->aliases.erase(n);
        return;
      }
  }
  bool is_local(const std::string& n) const {
    for (const Frame& f : frames_)
      if (f.locals.count(n)) return true;
    return n == "_ENV";
  }
  // The scope whose local n is (the innermost), or null for a global.
  Frame* owner(const std::string& n) {
    for (auto it = frames_.rbegin(); it != frames_.rend(); ++it)
      if (it->locals.count(n)) return &*it;
    return nullptr;
  }
  bool is_alias(const std::string& n) {
    const Frame* f = owner(n);
    return f && f->aliases.count(n);
  }

  // Whether the expression list starting at k is the global `roger` alone.
  bool bare_roger(size_t k) const { return word(k, "roger") && !is_local("roger") && expression_list_end(k) == k; }

  // Whether token k ends an operand: a name, number, string, vararg or closing bracket.
  bool operand_end(size_t k) const {
    const LuaToken& t = at(k);
    if (t.type == LuaToken::kString || t.type == LuaToken::kNumber) return true;
    if (t.type == LuaToken::kName) return !lua_keyword(t.text) || t.text == "true" || t.text == "false" || t.text == "nil";
    return op(k, ")") || op(k, "}") || op(k, "]") || op(k, "...");
  }

  // The bracket closing the one opened at k (or the end).
  size_t matching(size_t k) const {
    int depth = 0;
    for (;; ++k) {
      if (at(k).type == LuaToken::kEnd) return k;
      if (op(k, "(") || op(k, "{") || op(k, "[")) ++depth;
      if ((op(k, ")") || op(k, "}") || op(k, "]")) && --depth == 0) return k;
    }
  }

  // The `end` of the function whose keyword is at k (or the end).
  size_t function_end(size_t k) const {
    int depth = 0;
    for (;; ++k) {
      if (at(k).type == LuaToken::kEnd) return k;
      if (word(k, "function") || word(k, "if") || word(k, "do") || word(k, "repeat")) ++depth;
      if ((word(k, "end") || word(k, "until")) && --depth == 0) return k;
    }
  }

  // The last token of the expression list starting at k: brackets and function bodies whole; it
  // ends at an operand that no suffix, call, comma or binary operator follows.
  size_t expression_list_end(size_t k) const {
    for (;; ++k) {
      if (at(k).type == LuaToken::kEnd) return k;
      if (op(k, "(") || op(k, "{") || op(k, "[")) k = matching(k);
      else if (word(k, "function")) k = function_end(k);
      else if (!operand_end(k)) continue;
      const size_t n = k + 1;
      if (at(n).type == LuaToken::kString || op(n, "(") || op(n, "{") || op(n, "[") || op(n, ".") || op(n, ":") ||
          op(n, ",") || binary_operator(at(n)))
        continue;
      return k;
    }
  }
  // Whether the current token starts a statement rather than sits inside an expression's brackets.
  bool statement_level() const { return !frames_.back().bracket(); }

  void step() {
    const LuaToken& tok = t_[i_];
    if (tok.type == LuaToken::kOp) return punctuation(tok.text);
    if (tok.type != LuaToken::kName) return;
    if (lua_keyword(tok.text)) return keyword(tok.text);
    if (after(".") || after(":") || after("::") || (i_ > 0 && word(i_ - 1, "goto"))) return;
    const bool key = top().kind == Frame::kBrace && op(i_ + 1, "=") && (after("{") || after(",") || after(";"));
    if (!key) variable();
  }

  void punctuation(const std::string& p) {
    if (p == "==" || p == "~=") comparison();
    if (p == "{") frames_.push_back({Frame::kBrace, {}});
    if (p == "(") frames_.push_back({Frame::kParen, {}});
    if (p == "[") frames_.push_back({Frame::kBracket, {}});
    const Frame::Kind closes = p == "}" ? Frame::kBrace : p == ")" ? Frame::kParen : Frame::kBracket;
    if ((p == "}" || p == ")" || p == "]") && frames_.size() > 1 && top().kind == closes) frames_.pop_back();
  }

  void keyword(const std::string& w) {
    if (w == "local") return local();
    if (w == "function") return function();
    if (w == "for") {
      frames_.push_back({Frame::kLoopHeader, {}});
      size_t k = i_ + 1;
      while (name(k)) {
        declare(at(k).text);
        declared_at(at(k));
        if (!op(k + 1, ",")) break;
        k += 2;
      }
      i_ = k;
    } else if (w == "while") {
      frames_.push_back({Frame::kLoopHeader, {}});
    } else if (w == "do") {
      if (top().kind == Frame::kLoopHeader) top().kind = Frame::kBlock;
      else frames_.push_back({Frame::kBlock, {}});
    } else if (w == "if") {
      frames_.push_back({Frame::kIf, {}});
    } else if (w == "elseif" || w == "else") {
      if (top().kind == Frame::kIf) top().locals.clear();  // each branch is its own block
    } else if (w == "repeat") {
      frames_.push_back({Frame::kRepeat, {}});
    } else if (w == "until") {
      close_repeat();
    } else if (w == "end") {
      close_block();
    }
  }

  // `until cond` still sees the loop body's locals: they move to the enclosing scope (so a name
  // the body declared is never reported; the price is not reporting its later misuse).
  void close_repeat() {
    while (frames_.size() > 1 && top().bracket()) frames_.pop_back();
    if (frames_.size() < 2 || top().kind != Frame::kRepeat) return;
    std::set<std::string> body = std::move(top().locals);
    frames_.pop_back();
    for (const auto& n : body) declare(n);
  }

  void close_block() {
    while (frames_.size() > 1 && top().bracket()) frames_.pop_back();
    if (frames_.size() > 1) frames_.pop_back();
  }

  // local function f ... | local a <const>, b = ...
  void local() {
    if (word(i_ + 1, "function")) {
      if (name(i_ + 2)) declare(at(i_ + 2).text), declared_at(at(i_ + 2));  // visible in its own body (recursion)
      i_ += 2;
      return open_function(false);
    }
    size_t k = i_ + 1;
    std::vector<std::string> names;
    while (name(k)) {
      names.push_back(at(k).text);
      declared_at(at(k));
      ++k;
      if (op(k, "<") && name(k + 1) && op(k + 2, ">")) k += 3;  // <const>, <close>
      if (!op(k, ",")) break;
      ++k;
    }
    if (op(k, "=")) {
      pending_.push_back({expression_list_end(k + 1), names, names.size() == 1 && bare_roger(k + 1)});
    } else {
      for (const auto& n : names) declare(n);
    }
    i_ = k - 1;
  }

  // function name.field:method(params) ... end, or an anonymous function(params).
  void function() {
    bool method = false;
    if (name(i_ + 1)) {
      size_t k = i_ + 1;
      const std::string first = at(k).text;
      const int line = at(k).line;
      std::string path = first;
      while (op(k + 1, ".") && at(k + 2).type == LuaToken::kName) path += "." + at(k + 2).text, k += 2;
      if (op(k + 1, ":") && at(k + 2).type == LuaToken::kName) method = true, k += 2;
      const bool globals_table = first == "_G" || (first == "_ENV" && !owner("_ENV"));
      if (globals_table && !method && k == i_ + 3) {
        meant_global(at(k).text, line);  // function _G.f(): as _G.f = function (found by a probe)
      } else if (owner("_ENV") && path == first) {
        // under `local _ENV = t`, `function f` makes a field of t (found by a probe: warned of)
      } else if (!is_local(first)) {
        const bool plain = path == first && !method;
        note(plain ? Access::kWrite : Access::kRead, first, line);
        if (first == "roger" && path != first) note(method ? Access::kMember : Access::kMemberWrite, path, line);
      } else if (is_alias(first) && path != first) {
        note(method ? Access::kMember : Access::kMemberWrite, "roger" + path.substr(first.size()), line);
      }
      i_ = k;
    }
    open_function(method);
  }

  // Opens a function scope holding its parameters; i_ is on the token before "(".
  void open_function(bool method) {
    Frame f{Frame::kFunction, {}};
    f.function = ++functions_;
    f.function_line = at(i_).line;
    if (method) f.locals.insert("self");
    size_t k = i_ + 1;
    if (op(k, "(")) {
      int params = 0;
      for (++k; !op(k, ")") && at(k).type != LuaToken::kEnd; ++k)
        if (name(k)) {
          f.locals.insert(at(k).text);
          declared_at(at(k), true, &f);
          if (++params == 3 && !method) f.third = at(k).text;  // a callback is never a method
        }
    }
    frames_.push_back(std::move(f));
    i_ = k;
  }

  // The end of a variable starting at k (a name, then .field or [index] suffixes).
  size_t skip_suffixes(size_t k) const {
    for (;;) {
      if (op(k + 1, ".") && at(k + 2).type == LuaToken::kName) {
        k += 2;
      } else if (op(k + 1, "[")) {
        int depth = 0;
        size_t j = k + 1;
        for (; at(j).type != LuaToken::kEnd; ++j) {
          if (op(j, "[")) ++depth;
          if (op(j, "]") && --depth == 0) break;
        }
        k = j;
      } else {
        return k;
      }
    }
  }

  // Whether the name at k is a target of an assignment: `a = ...`, `a, b.c, d[1] = ...`.
  bool assigned(size_t k) const {
    if (!statement_level()) return false;
    while (op(k + 1, ",") && name(k + 2)) k = skip_suffixes(k + 2);
    return op(k + 1, "=");
  }

  void variable() {
    const std::string n = at(i_).text;
    const int line = at(i_).line;
    // The chunk's own _ENV (no local of that name) is the globals' table: `_ENV.x = v` defines x
    // (found by a probe: it did not).
    if (n == "_ENV" && !owner("_ENV")) return global_table_write(line);
    if (is_local(n)) return local_variable(n, line);
    // Under `local _ENV = t` a free name is a field of t, which this pass cannot see.
    if (owner("_ENV")) return;
    if (n == "_G" || n == "_ENV" || n == "rawset") global_table_write(line);
    if (n == "load" || (n == "setmetatable" && op(i_ + 1, "(") && word(i_ + 2, "_G"))) note(Access::kDynamic, n, line);
    if (n == "roger") return member_chain(line);
    if (n == "require") {
      if (at(i_ + 1).type == LuaToken::kString) note(Access::kRequire, at(i_ + 1).text, line);
      if (op(i_ + 1, "(") && at(i_ + 2).type == LuaToken::kString && op(i_ + 3, ")"))
        note(Access::kRequire, at(i_ + 2).text, line);
    }
    note(assigned(i_) ? Access::kWrite : Access::kRead, n, line);
    if (accesses.back().kind == Access::kRead)
      for (const Frame& f : frames_) accesses.back().locals.insert(accesses.back().locals.end(), f.locals.begin(), f.locals.end());
  }

  // A global defined through the globals' table: `_G.x = v`, `_G["x"] = v` (or `_ENV`'s), and
  // `rawset(_G, "x", v)` define x as `x = v` does.
  void global_table_write(int line) {
    const size_t k = i_;
    if (at(k).text == "rawset") {
      if (op(k + 1, "(") && (word(k + 2, "_G") || word(k + 2, "_ENV")) && op(k + 3, ",")) {
        if (at(k + 4).type == LuaToken::kString && op(k + 5, ",")) meant_global(at(k + 4).text, line);
        else note(Access::kDynamic, "rawset", line);
      }
      return;
    }
    // One target of several too: `_G.a, _G.b = 1, 2` (found by a probe: only the last was defined).
    if (op(k + 1, ".") && name(k + 2) && assigned(k + 2)) meant_global(at(k + 2).text, line);
    if (op(k + 1, "[") && at(k + 2).type == LuaToken::kString && op(k + 3, "]") && assigned(k + 3))
      meant_global(at(k + 2).text, line);
    else if (op(k + 1, "[") && !(at(k + 2).type == LuaToken::kString && op(k + 3, "]")))
      note(Access::kDynamic, at(k).text + "[...]", line);  // _G[name]: a global named at run time
  }

  // A local or upvalue: an alias of roger reaches roger's members. `R = roger` makes R one; any
  // other assignment to R alone unmakes it.
  void local_variable(const std::string& n, int line) {
    if (statement_level() && op(i_ + 1, "=")) {
      Frame* f = owner(n);
      if (!f) return;  // _ENV
      if (bare_roger(i_ + 2)) f->aliases.insert(n);
      else f->aliases.erase(n);
      return;
    }
    if (is_alias(n)) member_chain(line, true);
  }

  // roger.a.b or roger["a"] (or through an alias of roger): the member path as far as it is
  // written with constant names.
  void member_chain(int line, bool alias = false) {
    size_t k = i_;
    std::string path = "roger";
    for (;;) {
      if (op(k + 1, ".") && at(k + 2).type == LuaToken::kName) {
        path += "." + at(k + 2).text, k += 2;
      } else if (op(k + 1, "[") && at(k + 2).type == LuaToken::kString && op(k + 3, "]")) {
        path += "." + at(k + 2).text, k += 3;
      } else {
        break;
      }
    }
    const bool write = statement_level() && op(k + 1, "=");
    if (!alias) note(write && path == "roger" ? Access::kWrite : Access::kRead, "roger", line);
    if (path != "roger") note(write ? Access::kMemberWrite : Access::kMember, path, line);
    if (!write && makes_predicate(path)) predicate_call(i_, k);
    i_ = k;
  }

  // ---- a predicate taken for a truth value: and, or, not ----
  // A predicate is a userdata, which Lua's and, or and not take for true whatever its condition:
  // `roger.converged(a) and roger.converged(b)` is the second alone (found by a probe: a stage's
  // absorbing waited for one of its two conditions, and roger check said ok). Lua cannot overload
  // them, so only a call written in place is seen; one held in a variable is not followed.

  // The call of a predicate maker whose name runs from token `first` to `last`: reported when it is
  // the whole left operand of and / or, or the operand of not.
  void predicate_call(size_t first, size_t last) {
    size_t end = last + 1;
    if (op(end, "(") || op(end, "{")) end = matching(end);
    else if (at(end).type != LuaToken::kString) return;  // the function itself, not a predicate
    const size_t n = end + 1;
    if (at(n).type == LuaToken::kString || op(n, "(") || op(n, "{") || op(n, "[") || op(n, ".") || op(n, ":"))
      return;  // something of the predicate, not the predicate
    if (in_reported_chain_.count(first)) return;
    const int line = at(first).line;
    const std::string p = written(first, end);
    if (first > 0 && word(first - 1, "not")) {
      note(Access::kFinding,
           "not " + p + " is false: Lua takes a predicate for true; for the condition that holds when " + p +
               " does not, write roger.negate(" + p + ")",
           line);
      return;
    }
    if (!starts_operand(first)) return;
    // `flag and P or Q` is the choice idiom: or's left operand is the whole `flag and P`.
    const bool is_and = word(n, "and"), is_or = word(n, "or") && !(first > 0 && word(first - 1, "and"));
    if (!is_and && !is_or) return;
    std::vector<std::string> parts = {p};
    size_t k = n;
    while (word(k, is_and ? "and" : "or")) {
      const size_t part_end = logical_operand_end(k + 1, is_and);
      parts.push_back(written(k + 1, part_end));
      in_reported_chain_.insert(k + 1);
      k = part_end + 1;
    }
    note(Access::kFinding, dropped_operands(parts, is_and), line);
  }

  // "P and Q is Q alone: ...; for both to hold, write roger.all{P, Q}", or the same of or.
  static std::string dropped_operands(const std::vector<std::string>& parts, bool is_and) {
    const std::string w = is_and ? "and" : "or";
    std::string m = join(parts, (" " + w + " ").c_str()) + " is " + (is_and ? parts.back() : parts.front()) +
                    " alone: Lua takes a predicate for true, so '" + w + "' gives ";
    m += is_and ? "its right operand" : "the predicate and never looks further";
    const std::string how = parts.size() == 2 ? (is_and ? "both" : "either") : is_and ? "every one" : "any one";
    return m + "; for " + how + " to hold, write roger." + (is_and ? "all" : "any") + "{" + join(parts) + "}";
  }

  // The last token of an operand of and (of or) starting at k: up to the next and or or (the next
  // or; and binds tighter), a comma or the expression's end, brackets and function bodies whole.
  size_t logical_operand_end(size_t k, bool in_and) const {
    for (;; ++k) {
      if (at(k).type == LuaToken::kEnd) return k - 1;
      if (op(k, "(") || op(k, "{") || op(k, "[")) k = matching(k);
      else if (word(k, "function")) k = function_end(k);
      else if (!operand_end(k)) continue;
      const LuaToken& next = at(k + 1);
      const bool stop = word(k + 1, "or") || (in_and && word(k + 1, "and"));
      if (!stop && (next.type == LuaToken::kString || op(k + 1, "(") || op(k + 1, "{") || op(k + 1, "[") ||
                    op(k + 1, ".") || op(k + 1, ":") || binary_operator(next)))
        continue;
      return k;
    }
  }

  // Tokens first to last as they would be written: spaces between words and around operators,
  // none inside calls, indexes and fields; long ones cut.
  std::string written(size_t first, size_t last) const {
    std::string out;
    for (size_t k = first; k <= last; ++k) {
      const LuaToken& t = at(k);
      const bool tight_before = op(k, ")") || op(k, "}") || op(k, "]") || op(k, ",") || op(k, ".") || op(k, ":") ||
                                ((op(k, "(") || op(k, "{") || op(k, "[") || t.type == LuaToken::kString) &&
                                 k > first && operand_end(k - 1));
      const bool tight_after = k > first && (op(k - 1, "(") || op(k - 1, "{") || op(k - 1, "[") || op(k - 1, ".") ||
                                             op(k - 1, ":") || op(k - 1, "#") || word(k - 1, "function"));
      if (k > first && !tight_before && !tight_after) out += " ";
      out += t.type == LuaToken::kString ? "\"" + t.text + "\"" : t.text;
    }
    return shortened_text(out, 80);
  }

  // ---- a string literal compared with a controller's state or a reward function's event ----

  static constexpr size_t kNone = static_cast<size_t>(-1);
  struct Operand {
    size_t first, last;  // tokens
  };

  // The bracket opening the one closing at k, or kNone.
  size_t opening(size_t k) const {
    for (int depth = 0;; --k) {
      if (op(k, ")") || op(k, "}") || op(k, "]")) ++depth;
      if ((op(k, "(") || op(k, "{") || op(k, "[")) && --depth == 0) return k;
      if (k == 0) return kNone;
    }
  }

  // The first token of the prefix expression (a name or a parenthesised expression, then fields,
  // indexes and calls) whose last token is k, or kNone.
  size_t prefix_start(size_t k) const {
    for (;;) {
      if (name(k)) {
        if (k < 2 || !(op(k - 1, ".") || op(k - 1, ":"))) return k;
        k -= 2;
      } else if (op(k, ")") || op(k, "]")) {
        const size_t open = opening(k);
        if (open == kNone) return kNone;
        if (open > 0 && operand_end(open - 1)) k = open - 1;  // a call or an index
        else return op(k, ")") ? open : kNone;
      } else {
        return kNone;
      }
    }
  }

  // The last token of the prefix expression starting at k, or kNone.
  size_t prefix_end(size_t k) const {
    if (op(k, "(")) k = matching(k);
    else if (!name(k)) return kNone;
    for (;;) {
      if ((op(k + 1, ".") || op(k + 1, ":")) && at(k + 2).type == LuaToken::kName) k += 2;
      else if (op(k + 1, "[") || op(k + 1, "(") || op(k + 1, "{")) k = matching(k + 1);
      else if (at(k + 1).type == LuaToken::kString) k += 1;
      else return k;
    }
  }

  // Whether an operand starting at k is a comparison's whole left operand: what precedes it binds
  // looser (and, or) or starts an expression.
  bool starts_operand(size_t k) const {
    if (k == 0) return true;
    for (const char* o : {"(", "[", "{", ",", "=", ";"})
      if (op(k - 1, o)) return true;
    for (const char* w : {"and", "or", "return", "if", "elseif", "while", "until"})
      if (word(k - 1, w)) return true;
    return false;
  }

  // The operands of the comparison at i_, when each is a string or a prefix expression whole.
  std::optional<Operand> left_operand() const {
    const size_t last = i_ - 1;
    const size_t first = at(last).type == LuaToken::kString ? last : prefix_start(last);
    if (first == kNone || !starts_operand(first)) return std::nullopt;
    return Operand{first, last};
  }
  std::optional<Operand> right_operand() const {
    const size_t first = i_ + 1;
    const size_t last = at(first).type == LuaToken::kString ? first : prefix_end(first);
    if (last == kNone || tighter_than_comparison(at(last + 1))) return std::nullopt;
    return Operand{first, last};
  }

  void comparison() {
    if (i_ == 0) return;
    const auto l = left_operand(), r = right_operand();
    if (!l || !r) return;
    const bool l_string = l->first == l->last && at(l->first).type == LuaToken::kString;
    const bool r_string = r->first == r->last && at(r->first).type == LuaToken::kString;
    if (l_string != r_string) compared(at(l_string ? l->first : r->first), r_string ? *l : *r);
  }

  // A literal compared with an index expression (state.phi3, s[name]) should be a state, but for
  // the string fields of the world's entries (o.name, o.shape, o.region, o.colour: an object may
  // be called "conv"); with `event` or a function's third parameter, an event.
  void compared(const LuaToken& literal, const Operand& other) {
    const std::string with = text_of(other);
    const bool entry_field = other.last > other.first && op(other.last - 1, ".") &&
                             among({"name", "shape", "region", "colour"}, at(other.last).text);
    const bool index = !entry_field && (op(other.last, "]") || (other.last > other.first && op(other.last - 1, ".")));
    std::string message;
    if (index) {
      const std::string meant = meant_state(literal.text);
      if (!meant.empty()) message = never_equal(literal.text, with, "a controller's state", kStates, meant);
    } else if (other.first == other.last && event_argument(with)) {
      const std::string meant = meant_event(literal.text);
      const std::string shown = with == "event" ? with : with + ", a function's third parameter";
      if (!meant.empty()) message = never_equal(literal.text, shown, "a reward function's event", kEvents, meant);
    }
    ++compared_[literal.text];
    if (!message.empty()) accesses.push_back({Access::kFinding, message, literal.line, {}, literal.text});
  }

  // The literals the file writes outside such comparisons (a parameter's choice or default, a task
  // axis's value, an argument): values its tables hold, so what is compared with one can equal it,
  // and the judge drops its finding. Found by a probe: a scenario's p.hull == "conv", over the
  // choices {"conv", "box"}, was taken for a misspelt controller state.
  void count_values_written() {
    std::map<std::string, int> written;
    for (const LuaToken& t : t_)
      if (t.type == LuaToken::kString) ++written[t.text];
    for (const auto& [text, n] : written)
      if (n > compared_[text]) values_written.insert(text);
  }

  // Whether a plain name is a reward function's event: named so, or a function's third parameter.
  bool event_argument(const std::string& n) {
    const Frame* f = owner(n);
    return n == "event" || (f && f->kind == Frame::kFunction && f->third == n);
  }

  // An operand as written, near enough: its tokens, strings quoted.
  std::string text_of(const Operand& o) const {
    std::string out;
    for (size_t k = o.first; k <= o.last; ++k) {
      const LuaToken& t = at(k);
      out += t.type == LuaToken::kString ? "\"" + t.text + "\"" : t.text;
      if (op(k, ",")) out += " ";
    }
    return out;
  }

  std::vector<LuaToken> t_;
  std::vector<Frame> frames_;
  std::vector<PendingLocals> pending_;  // innermost last
  int functions_ = 0;                   // the functions opened so far
  std::map<std::string, int> compared_;  // string literals compared with an index or an event, by text
  size_t i_ = 0;
  std::set<size_t> in_reported_chain_;  // where the later operands of a reported and / or start
};

struct ScannedFile {
  std::string shown;
  std::vector<Access> accesses;
  std::vector<LocalDeclaration> local_declarations;
  std::set<std::string> values_written;  // Scanner::values_written
  std::vector<StaticProblem> duplicate_keys;  // found in the text, apart from the names
};

// A key written twice in one table constructor (`{ Skilled = {...}, Skilled = {...} }`): Lua keeps
// the last value, so the first is lost without a word (found by a probe: a context of a map
// vanished and roger check said ok). Reported at the second, naming the first.
std::vector<StaticProblem> duplicate_keys(const std::string& text, const std::string& shown) {
  std::vector<StaticProblem> out;
  const LuaTableMap map(text);
  for (const auto& node : map.nodes()) {
    std::map<std::string, int> first_line;
    for (const auto& e : node.entries)
      if (const auto [first, added] = first_line.emplace(e.key, e.line); !added)
        out.push_back({shown, e.line,
                       "the table written at line " + std::to_string(node.line) + " gives '" + e.key +
                           "' twice (first at line " + std::to_string(first->second) +
                           "): Lua keeps the last value, and the first is lost"});
  }
  return out;
}

ScannedFile scanned_file(const std::string& text, const std::string& shown) {
  Scanner scanned(text);
  return {shown, std::move(scanned.accesses), std::move(scanned.local_declarations), std::move(scanned.values_written),
          duplicate_keys(text, shown)};
}

// The problems judged from a file's names and those of its text, in line order.
void append_in_line_order(std::vector<StaticProblem> found, const std::vector<StaticProblem>& more,
                          std::vector<StaticProblem>& out) {
  found.insert(found.end(), more.begin(), more.end());
  std::stable_sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.line < b.line; });
  out.insert(out.end(), found.begin(), found.end());
}

// What the files define and what the kind's sandbox has; judges each access.
class AccessJudge {
 public:
  AccessJudge(std::optional<ScriptKind> kind, const std::vector<ScannedFile>& files) : kind_(kind), api_(script_api_names(kind)) {
    for (const auto& f : files)
      for (const auto& a : f.accesses) {
        if (a.kind == Access::kWrite) written_.insert(a.name);
        if (a.kind == Access::kMemberWrite) written_.insert(a.name);
        dynamic_ = dynamic_ || a.kind == Access::kDynamic;
      }
    // A value any of the files writes (found by a probe: a module's `mode == "per_decision"`, its
    // third parameter, was given "per_decision" by the curriculum that requires it).
    for (const auto& f : files)
      values_.insert(f.values_written.begin(), f.values_written.end());
  }

  void judge(const ScannedFile& f, std::vector<StaticProblem>& out) const {
    std::set<std::pair<int, std::string>> seen;  // one report per name and line
    for (const auto& a : f.accesses) {
      std::string message;
      if (a.kind == Access::kRead) message = global(a.name, a.locals);
      if (a.kind == Access::kRead && !message.empty()) message = out_of_scope(f, a, message);
      if (a.kind == Access::kMember) message = member(a.name);
      // A compared literal (a misspelt state or event) only where callbacks can be; a predicate taken
      // for a truth value (no literal) wherever predicates are made.
      if (a.kind == Access::kFinding && (a.literal.empty() || (callbacks_possible() && !values_.count(a.literal))))
        message = a.name;
      if (!message.empty() && seen.insert({a.line, message}).second) out.push_back({f.shown, a.line, message});
    }
  }

 private:
  bool known(const std::string& n) const { return api_.count(n) || written_.count(n); }

  std::string global(const std::string& n, std::vector<std::string> names) const {
    // Found by a probe: a global made by load("x = 5")() or _G[name] = v was refused, where the
    // script ran: what this pass cannot see, it does not report.
    if (known(n) || dynamic_) return "";
    for (const auto& [k, table] : api_)
      if (k.find('.') == std::string::npos) names.push_back(k);
    for (const auto& k : written_)
      if (k.find('.') == std::string::npos) names.push_back(k);
    std::string m = "undefined global '" + n + "'";
    if (n == "roger") return m + ": " + what() + " reaches no roger.* API";
    if (n == "self")  // found by a probe: a method written with `.` read self as a global
      return m + ": self is the table a function written with `:` receives (function T:name(...)); one written "
                 "with `.` has no self unless it names it as a parameter";
    // Lua 5.1's globals, which 5.4 has elsewhere (found by a probe: `table.unpack or unpack`, a
    // common idiom, said only "not in the sandbox").
    static const std::pair<const char*, const char*> kLua51[] = {
        {"unpack", "table.unpack"}, {"loadstring", "load"}, {"setfenv", "_ENV"}, {"getfenv", "_ENV"},
        {"module", "a table the module returns"}};
    for (const auto& [old_name, now] : kLua51)
      if (n == old_name)
        return m + ": a global of Lua 5.1, for which roger's Lua 5.4 has " + now +
               (n == "unpack" || n == "loadstring"
                    ? " (this pass reports every read of it, a fallback's `" + std::string(now) + " or " + n +
                          "` too: write " + now + " alone)"
                    : std::string());
    const auto near = nearest_names(n, names);
    if (!near.empty()) return m + "; did you mean " + join(near, " or ") + "?";
    // A shipped library of that name (`shapes` used without its require): say how to get it.
    std::error_code ec;
    for (const char* folder : {"scenarios", "curricula"})
      if (std::filesystem::is_regular_file(project_root() / folder / "lib" / (n + ".lua"), ec))
        return m + "; " + folder + "/lib/" + n + ".lua is a library: local " + n + " = require(\"lib." + n +
               "\") before its first use";
    return m + " (not a local in scope, not assigned in the script, not in the sandbox)";
  }

  // An undefined global that is the name of a local declared elsewhere in the file: said so, with
  // its line, in place of a guess at another name (found by a probe: a local declared below its
  // use was "undefined global 'target'; did you mean rawget?"). A local of this code's own
  // functions (or of the chunk) declared below it is declared too late; one of them declared above
  // it, in a block that has ended; one of another function is that function's alone (found by a
  // later probe: "declare it above" of another function's local would not help). One declared on
  // the read's own line is `local x = x`, whose x is the global: no note.
  static std::string out_of_scope(const ScannedFile& f, const Access& a, const std::string& message) {
    const auto enclosing = [&](const LocalDeclaration& l) {
      return std::find(a.functions.begin(), a.functions.end(), l.function) != a.functions.end();
    };
    const LocalDeclaration *below = nullptr, *ended = nullptr, *other = nullptr;
    for (const LocalDeclaration& l : f.local_declarations) {
      if (l.name != a.name || l.line == a.line) continue;
      if (!enclosing(l)) {
        if (!other) other = &l;
      } else if (l.line > a.line) {
        if (!below) below = &l;
      } else if (!ended) {
        ended = &l;
      }
    }
    const std::string head = "undefined global '" + a.name + "'";
    const bool in_function = a.in_function();
    if (below)
      return head + ": the local '" + a.name + "' is declared below, at line " + std::to_string(below->line) +
             ", and a local is seen only after its statement: declare it above its first use";
    if (ended)
      return head + ": the local '" + a.name + "' of line " + std::to_string(ended->line) +
             " is out of scope here (a local is seen to the end of the block or function that declares it)";
    if (!other) return message;
    const std::string where = "the function at line " + std::to_string(other->function_line);
    if (other->parameter)
      return head + ": '" + a.name + "' is a parameter of " + where + ", seen only inside that function" +
             (in_function ? ": pass it to this one" : "");
    return head + ": the local '" + a.name + "' of line " + std::to_string(other->line) + " belongs to " + where +
           ", which this code does not see: " +
           (in_function ? "pass it as an argument, or declare it where both see it" : "declare it at the top");
  }

  // The first segment of a member path that does not exist, with what exists beside it.
  std::string member(const std::string& path) const {
    if (!api_.count("roger")) return "";  // reported as an undefined global
    size_t dot = path.find('.');
    while (dot != std::string::npos) {
      const size_t next = path.find('.', dot + 1);
      const std::string prefix = path.substr(0, dot), full = path.substr(0, next);
      if (!known(full)) return unknown_member(prefix, full);
      const auto it = api_.find(full);
      if (it == api_.end() || !it->second) return "";  // not a table (or the script's own): stop
      dot = next;
    }
    return "";
  }

  std::string unknown_member(const std::string& prefix, const std::string& full) const {
    std::vector<std::string> siblings;
    for (const auto& [k, table] : api_)
      if (k.rfind(prefix + ".", 0) == 0 && k.find('.', prefix.size() + 1) == std::string::npos)
        siblings.push_back(k.substr(prefix.size() + 1));
    std::string m = full + " is not in the API of " + what();
    std::vector<std::string> elsewhere;
    for (ScriptKind other : script_kinds())
      if (kind_ && other != *kind_ && script_api_names(other).count(full)) elsewhere.push_back(script_kind_name(other));
    if (!elsewhere.empty()) m += " (a " + join(elsewhere, " or a ") + " has it)";
    auto near = nearest_names(full.substr(prefix.size() + 1), siblings);
    if (!near.empty()) {
      for (auto& n : near) n = prefix + "." + n;
      m += "; did you mean " + join(near, " or ") + "?";
      // A short list is worth seeing whole (roger.teacher's five kinds): the nearest may not be meant.
      return siblings.size() <= 8 ? m + " (" + prefix + " has: " + join(siblings) + ")" : m;
    }
    return m + "; " + prefix + " has: " + join(siblings);
  }

  // Whether the files can hold a curriculum's callbacks (absorbing, reward), the only functions
  // given a controller's state or an event: a scenario's, a skill script's or a batch script's
  // index expressions are parameters and tables of their own (found by a probe: a scenario's
  // p.hull == "conv" was taken for a misspelt state). A module checked alone may be a curriculum's.
  bool callbacks_possible() const { return !kind_ || *kind_ == ScriptKind::kCurriculum; }

  // "a scenario", or "any script" when the kind is not known.
  std::string what() const { return kind_ ? std::string("a ") + script_kind_name(*kind_) : "any script"; }

  std::optional<ScriptKind> kind_;
  std::map<std::string, bool> api_;
  std::set<std::string> written_;
  std::set<std::string> values_;  // string literals some file writes outside comparisons
  bool dynamic_ = false;  // some file makes globals this pass cannot name
};

// "require('sorting') takes scenarios/sorting.lua; curricula/sorting.lua has the same name:
// require('curricula.sorting') loads it" when a bare name is found in the project's scenarios/,
// which every script but a batch script searches first, and curricula/ or scripts/ hold a file of
// that name too; "" otherwise (found by a probe: a curriculum's require("sorting") got the
// scenario and failed at "attempt to index a nil value"). A batch script's require("paper") of
// scripts/paper.lua is what it means, and is left alone.
std::string other_of_name(const LuaSandbox& sandbox, const std::string& name, const fs::path& module) {
  if (name.find('.') != std::string::npos || module.empty()) return "";
  const fs::path project = fs::weakly_canonical(project_root());
  std::error_code ec;
  if (module.parent_path() != fs::weakly_canonical(project / "scenarios", ec)) return "";
  std::vector<std::string> others;
  for (const char* folder : {"curricula", "scripts"}) {
    const fs::path other = project / folder / (name + ".lua");
    if (fs::is_regular_file(other, ec) && fs::weakly_canonical(other, ec) != module)
      others.push_back(std::string(folder) + "/" + name + ".lua");
  }
  if (others.empty()) return "";
  std::string text = "require('" + name + "') takes " + sandbox.display_name(module) + "; ";
  for (size_t i = 0; i < others.size(); ++i) {
    const std::string folder = others[i].substr(0, others[i].find('/'));
    text += (i ? "; " : "") + others[i] + " has the same name: require('" + folder + "." + name + "') loads it";
  }
  return text;
}

}  // namespace

std::vector<std::string> nearest_names(const std::string& name, const std::vector<std::string>& known) {
  const size_t limit = std::max<size_t>(1, name.size() / 3);
  // The same name but for case is nearest of all (found by a probe: roger.teacher.ALP_GMM had no
  // suggestion, each capital counting as an edit).
  const auto lower = [](std::string t) {
    for (char& c : t) c = char(std::tolower(static_cast<unsigned char>(c)));
    return t;
  };
  std::vector<std::pair<size_t, std::string>> scored;
  for (const auto& k : known) {
    const size_t d = lower(name) == lower(k) ? 0 : edit_distance(name, k);
    if (d <= limit && k != name) scored.push_back({d, k});
  }
  std::sort(scored.begin(), scored.end());
  scored.erase(std::unique(scored.begin(), scored.end()), scored.end());
  std::vector<std::string> out;
  for (size_t i = 0; i < scored.size() && i < 3; ++i) out.push_back(scored[i].second);
  return out;
}

namespace {

// Lua's own verdict on the text's syntax (compiled, never run), as "shown:LINE: message": a file
// that does not compile is reported so, not by what the scanner makes of it (a missing comma
// before a name read as an undefined global, found by a probe).
std::optional<StaticProblem> syntax_problem(const std::string& text, const std::string& shown) {
  lua_State* L = luaL_newstate();
  if (!L) return std::nullopt;
  std::optional<StaticProblem> out;
  const std::string source = lua_file_text(text);  // a byte-order mark, a shebang: as Lua's loader
  if (luaL_loadbufferx(L, source.data(), source.size(), ("=" + shown).c_str(), "t") != LUA_OK) {
    const std::string message = lua_isstring(L, -1) ? lua_tostring(L, -1) : "does not compile";
    StaticProblem p{shown, 0, message};
    const std::string head = shown + ":";
    if (message.rfind(head, 0) == 0) {  // "shown:3: '}' expected near 'cell'"
      const size_t colon = message.find(':', head.size());
      const std::string line = message.substr(head.size(), colon == std::string::npos ? 0 : colon - head.size());
      if (!line.empty() && std::all_of(line.begin(), line.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); })) {
        p.line = std::stoi(line);
        p.message = message.substr(colon + 1 + (colon + 1 < message.size() && message[colon + 1] == ' '));
      }
    }
    out = p;
  }
  lua_close(L);
  return out;
}

// A global assigned inside a function that no statement outside a function assigns: most often a
// `local` forgotten, whose value then outlives the call (found by a probe: a reward function's
// `calls = (calls or 0) + 1` passed check, and counted on across episodes into the evaluations).
// Once per name and file, at its first such line. A global meant as one is assigned at the top.
std::vector<StaticProblem> globals_set_in_functions(const std::vector<ScannedFile>& files) {
  std::set<std::string> at_top;
  for (const auto& f : files)
    for (const auto& a : f.accesses)
      if (a.kind == Access::kWrite && !a.in_function()) at_top.insert(a.name);
  std::vector<StaticProblem> out;
  for (const auto& f : files) {
    std::set<std::string> said;
    for (const auto& a : f.accesses)
      if (a.kind == Access::kWrite && a.in_function() && !at_top.count(a.name) && said.insert(a.name).second)
        out.push_back({f.shown, a.line,
                       "'" + a.name + "' is assigned inside a function without `local`: it is a global, which keeps "
                       "its value from one call to the next (a callback's, across episodes and into evaluations); "
                       "write `local " + a.name + "` for a value of one call (a curriculum's callbacks keep an "
                       "episode's values in their `episode` argument), or assign it once outside the functions "
                       "if it is meant to last"});
  }
  return out;
}

}  // namespace

std::vector<StaticProblem> static_check_text(const std::string& text, const std::string& shown,
                                             std::optional<ScriptKind> kind) {
  if (auto syntax = syntax_problem(text, shown)) return {*syntax};
  const std::vector<ScannedFile> files{scanned_file(text, shown)};
  std::vector<StaticProblem> judged, out;
  AccessJudge(kind, files).judge(files[0], judged);
  append_in_line_order(judged, files[0].duplicate_keys, out);
  return out;
}

namespace {

// "lib/shapes.lua beside the script takes the place of the shipped scenarios/lib/shapes.lua inside
// scenarios/lib/place.lua" when `module`, which `file` requires as `name`, is the script folder's
// and `file` and a module of that name are the project's; "" otherwise. A copy made to replace the
// shipped one there is what the user meant; a helper that happens to share its name is not (found
// by a probe: the shipped lib.place then failed at its own line).
std::string shadow_of(const LuaSandbox& sandbox, const fs::path& file, const std::string& name, const fs::path& module) {
  const std::vector<fs::path> roots = sandbox.module_roots();
  if (roots.size() < 2) return "";
  const auto under = [](const fs::path& root, const fs::path& p) {
    const fs::path rel = p.lexically_relative(root);
    return !rel.empty() && *rel.begin() != "..";
  };
  const std::vector<fs::path> project(roots.begin() + 1, roots.end());
  const auto shipped = [&](const fs::path& p) {
    return std::any_of(project.begin(), project.end(), [&](const fs::path& r) { return under(r, p); });
  };
  if (!under(roots.front(), module) || shipped(module) || !shipped(file)) return "";
  const fs::path replaced = find_module_file(project, name);
  if (replaced.empty()) return "";
  return sandbox.display_name(module) + " beside the script takes the place of the shipped " +
         sandbox.display_name(replaced) + " inside " + sandbox.display_name(file) + " (its require(\"" + name +
         "\")): rename yours unless you mean to replace it there";
}

}  // namespace

namespace {

// The script at `path`, then each module it requires by a literal name that the sandbox's require
// would load, and theirs in turn, each once, breadth first. `scan(file)` reads one and returns its
// accesses (null for one that does not compile or cannot be read: it requires nothing this pass can
// see); `required(file, name, module)` hears of each require that loads a file.
void walk_requires(const LuaSandbox& sandbox, const std::string& path,
                   const std::function<const std::vector<Access>*(const fs::path&)>& scan,
                   const std::function<void(const fs::path&, const std::string&, const fs::path&)>& required) {
  std::error_code ec;
  std::deque<fs::path> queue{fs::weakly_canonical(path, ec)};
  std::set<fs::path> seen{queue.front()};
  while (!queue.empty()) {
    const fs::path file = queue.front();
    queue.pop_front();
    const std::vector<Access>* accesses = scan(file);
    if (!accesses) continue;
    for (const auto& a : *accesses) {
      if (a.kind != Access::kRequire) continue;
      // What require would load, never more (found by a probe: a name climbing out, "..tmp.x",
      // or a module linked out of the project made roger check read and quote a file outside it).
      const fs::path module = find_module_file(sandbox.module_roots(), a.name);
      if (module.empty()) continue;
      required(file, a.name, module);
      if (seen.insert(module).second) queue.push_back(module);
    }
  }
}

}  // namespace

std::vector<StaticProblem> static_check(const std::string& path, std::optional<ScriptKind> kind,
                                        std::vector<std::string>* warnings) {
  LuaSandbox sandbox;  // for its module folders and how it shows file names
  sandbox.set_main_script(path);
  std::vector<ScannedFile> files;
  std::vector<StaticProblem> syntax_errors;
  const auto scan = [&](const fs::path& file) -> const std::vector<Access>* {
    // The script itself as the user named it, as the loader's messages show it; modules as the
    // sandbox shows them.
    const bool script = files.empty() && syntax_errors.empty();
    const std::string shown = script && fs::path(path).is_relative() ? path : sandbox.display_name(file);
    const std::string text = read_file_text(file.string());
    if (auto syntax = syntax_problem(text, shown)) {  // its names mean nothing until it compiles
      syntax_errors.push_back(*syntax);
      return nullptr;
    }
    files.push_back(scanned_file(text, shown));
    return &files.back().accesses;
  };
  const auto required = [&](const fs::path& file, const std::string& name, const fs::path& module) {
    if (!warnings) return;
    for (const std::string& warning : {shadow_of(sandbox, file, name, module), other_of_name(sandbox, name, module)})
      if (!warning.empty() && std::find(warnings->begin(), warnings->end(), warning) == warnings->end())
        warnings->push_back(warning);
  };
  walk_requires(sandbox, path, scan, required);
  const AccessJudge judge(kind, files);
  std::vector<StaticProblem> out = syntax_errors;
  for (const auto& f : files) {
    std::vector<StaticProblem> judged;
    judge.judge(f, judged);
    append_in_line_order(judged, f.duplicate_keys, out);
  }
  if (warnings)
    for (const StaticProblem& w : globals_set_in_functions(files)) warnings->push_back(w.what());
  return out;
}

std::vector<fs::path> required_files(const std::string& path) {
  LuaSandbox sandbox;  // for its module folders
  sandbox.set_main_script(path);
  std::vector<fs::path> out;
  std::vector<Access> accesses;
  const auto scan = [&](const fs::path& file) -> const std::vector<Access>* {
    out.push_back(file);
    try {
      const std::string text = read_file_text(file.string());
      if (syntax_problem(text, file.string())) return nullptr;
      accesses = Scanner(text).accesses;
    } catch (const Error&) {
      return nullptr;  // unreadable: the loader says so
    }
    return &accesses;
  };
  walk_requires(sandbox, path, scan, [](const fs::path&, const std::string&, const fs::path&) {});
  return out;
}

std::vector<ModuleUse> module_users(const fs::path& module, const std::vector<fs::path>& scripts) {
  std::error_code ec;
  const fs::path target = fs::weakly_canonical(module, ec);
  std::vector<ModuleUse> out;
  for (const auto& script : scripts) {
    std::string text;
    try {
      text = read_file_text(script.string());
    } catch (const Error&) {
      continue;  // unreadable: it requires nothing we can see
    }
    // Where the sandbox's require would look were this script the main one.
    const fs::path real = fs::weakly_canonical(script, ec);
    const std::vector<fs::path> roots = module_search_roots(real.parent_path(), looks_like_batch_script(real));
    for (const auto& a : Scanner(text).accesses)
      if (a.kind == Access::kRequire && find_module_file(roots, a.name) == target) {
        out.push_back({script, a.name, a.line});
        break;
      }
  }
  return out;
}

}  // namespace roger
