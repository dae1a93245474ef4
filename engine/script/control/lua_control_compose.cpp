// Subject-to compositions in the control API: roger.subject_to(sub, sup), sub:subject_to(sup) and
// roger.compose's "phi1 <| phi4 <| phi5" notation.
#include <algorithm>
#include <cctype>

#include "script/control/lua_control_internal.h"

namespace roger {
namespace lua_control_detail {
namespace {

// Refuses a controller subject to itself (found by a probe: a:subject_to(a) and "A <| A" were
// taken, the one controller then run twice each tick, once in its own nullspace).
void refuse_self(lua_State* L, const ControllerPtr& sub, const ControllerPtr& sup, const std::string& call) {
  if (sub.get() == sup.get())
    raise(L, call + ": the subordinate and the superior are the same controller ('" + sub->name() +
                 "'): a controller cannot be subject to itself; make a second one for the other role");
}

// Makes sub <| sup and pushes it.
void push_subject_to(lua_State* L, ControlBook& book, ControllerPtr sub, ControllerPtr sup) {
  count_object(L, book);
  lua_push_controller(L, made(book, std::make_shared<SubjectTo>(std::move(sub), std::move(sup))));
}

}  // namespace

// sub:subject_to(sup)
int l_subject_to_method(lua_State* L) {
  return lua_protect(L, [L]() {
    ControlBook& book = book_of(L);
    ControllerPtr sub = self_controller(L, "subject_to");
    // sub.subject_to(sup): the superior came as the subordinate, and no superior (found by a probe:
    // "argument 1 (the superior) ... got nil", of a call given one).
    if (lua_gettop(L) == 1)
      raise(L, "c:subject_to: call it with a colon, as sub:subject_to(sup) (called with one controller, '" +
                   sub->name() + "', and no superior: sub.subject_to(sup) passes sup as the subordinate)");
    lua_check_arity(L, "c:subject_to", 1, "1 argument (the superior)");
    ControllerPtr sup = lua_check_controller(L, 2, "c:subject_to", "argument 1 (the superior)");
    refuse_self(L, sub, sup, "c:subject_to");
    push_subject_to(L, book, std::move(sub), std::move(sup));
    return 1;
  });
}

// roger.subject_to(sub, sup)
int l_subject_to(lua_State* L) {
  return lua_protect(L, [L]() {
    ControlBook& book = book_of(L);
    lua_check_arity(L, "roger.subject_to", 2, "2 arguments (the subordinate and the superior)");
    ControllerPtr sub = lua_check_controller(L, 1, "roger.subject_to", "argument 1 (the subordinate)");
    ControllerPtr sup = lua_check_controller(L, 2, "roger.subject_to", "argument 2 (the superior)");
    refuse_self(L, sub, sup, "roger.subject_to");
    push_subject_to(L, book, std::move(sub), std::move(sup));
    return 1;
  });
}

namespace {

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
    refuse_unused_entries();
    return c;
  }

 private:
  [[noreturn]] void fail(const std::string& message) {
    raise(L_, "roger.compose(\"" + text_ + "\"): " + message);
  }

  // A table entry the expression never names would be dropped (found by a probe: {phi44 = tuned}
  // for "phi4 <| phi2" ran the default phi4, the tuned one thrown away without a word).
  void refuse_unused_entries() {
    if (!table_) return;
    lua_pushnil(L_);
    while (lua_next(L_, table_)) {
      lua_pop(L_, 1);
      const std::string key = lua_type(L_, -1) == LUA_TSTRING ? lua_tostring(L_, -1) : "";
      if (!key.empty() && std::find(used_.begin(), used_.end(), key) != used_.end()) continue;
      const std::string what = key.empty() ? "the table's key " + lua_describe_value(L_, -1) : "the table's entry '" + key + "'";
      fail(what + " is named nowhere in the expression, which names " + join(named_) + suggestion(key, named_) +
           ": an entry replaces the name it is given under");
    }
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
    if (left.get() == right.get())
      fail("'" + left->name() + "' is subject to itself: a controller cannot be; make a second one for the other role");
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
    const std::string name = text_.substr(start, pos_ - start);
    // "phi4 <|| phi2", "phi4 < phi2": said as the operator mistyped, not as a controller '|'.
    if (name.find_first_of("<|>") != std::string::npos)
      fail("'" + name + "' at column " + std::to_string(start + 1) + " is no controller name: the subject-to "
           "operator is written '<|' (\"phi4 <| phi2\": phi4 subject to phi2)");
    named_.push_back(name);
    return lookup(name);
  }

  // The table entry, else a named controller, else a primitive kind's default instance.
  ControllerPtr lookup(const std::string& name) {
    if (table_) {
      lua_pushstring(L_, name.c_str());
      if (lua_rawget(L_, table_) != LUA_TNIL) {
        used_.push_back(name);
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
    // Its names are read when it is called (found by a probe: a controller defined on the next line
    // was "unknown" with no word of when names are known).
    const std::string later = book_.finished ? "" : " (roger.compose looks its names up when it is called: one "
                                                    "defined further down the script is not known yet)";
    fail("unknown controller '" + name + "'" + suggestion(name, candidates) + later + "; " + table_keys +
         known_names(book_));
  }

  lua_State* L_;
  ControlBook& book_;
  std::string text_;
  int table_;
  size_t pos_ = 0;
  std::vector<std::string> named_;  // the names the expression gives, in order
  std::vector<std::string> used_;   // those the table gives
};

}  // namespace

// roger.compose("phi1 <| phi4 <| phi5" [, {phi1 = carry, ...}])
int l_compose(lua_State* L) {
  return lua_protect(L, [L]() {
    ControlBook& book = book_of(L);
    lua_check_arity(L, "roger.compose", 2, "1 or 2 arguments (an expression and a table of controllers)");
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

}  // namespace lua_control_detail
}  // namespace roger
