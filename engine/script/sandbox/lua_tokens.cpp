// lua_tokens.cpp: Lua source split into tokens with their lines (lua_tokens.h).
#include "script/sandbox/lua_tokens.h"

#include <cctype>
#include <cstring>
#include <set>
#include <utility>

namespace roger {
namespace {

// The length of a long bracket "[==[" at s[i] (its level + 2), or 0 when there is none.
size_t long_bracket(const std::string& s, size_t i) {
  if (i >= s.size() || s[i] != '[') return 0;
  size_t j = i + 1;
  while (j < s.size() && s[j] == '=') ++j;
  return j < s.size() && s[j] == '[' ? j - i + 1 : 0;
}

bool name_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool name_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }
bool digit(char c) { return std::isdigit(static_cast<unsigned char>(c)); }

// One pass over Lua source: s[i] is the next character, line its line.
struct Lexer {
  explicit Lexer(const std::string& source) : s(source) {}
  const std::string& s;
  size_t i = 0;
  int line = 1;
  std::vector<LuaToken> out;

  // Skips a long bracket body whose opening bracket (of `open` characters) starts at i.
  void skip_long(size_t open, std::string* text) {
    const std::string close = "]" + std::string(open - 2, '=') + "]";
    const size_t start = i + open;
    const size_t end = s.find(close, start);
    const size_t stop = end == std::string::npos ? s.size() : end;
    for (size_t k = i; k < stop; ++k) line += s[k] == '\n';
    if (text) *text = s.substr(start, stop - start);
    i = end == std::string::npos ? s.size() : end + close.size();
  }

  // A comment, "--" at i: to the line's end, or a long bracket's.
  void comment() {
    i += 2;
    if (const size_t open = long_bracket(s, i)) {
      skip_long(open, nullptr);
    } else {
      while (i < s.size() && s[i] != '\n') ++i;
    }
  }

  // A string in the quote at i; its text keeps escapes as written.
  void quoted_string() {
    const char quote = s[i];
    const int at = line;
    std::string text;
    for (++i; i < s.size() && s[i] != quote; ++i) {
      if (s[i] == '\\' && i + 1 < s.size()) text += s[i++];
      line += s[i] == '\n';
      text += s[i];
    }
    ++i;
    out.push_back({LuaToken::kString, text, at});
  }

  void long_string(size_t open) {
    const int at = line;
    std::string text;
    skip_long(open, &text);
    out.push_back({LuaToken::kString, text, at});
  }

  void name() {
    const size_t start = i;
    while (i < s.size() && name_char(s[i])) ++i;
    out.push_back({LuaToken::kName, s.substr(start, i - start), line});
  }

  // A numeral: digits, letters, dots, and a sign after an exponent's letter (1e-3, 0x1p+4).
  void number() {
    const size_t start = i;
    while (i < s.size() && (std::isalnum(static_cast<unsigned char>(s[i])) || s[i] == '.' ||
                            ((s[i] == '+' || s[i] == '-') && std::strchr("eEpP", s[i - 1]))))
      ++i;
    out.push_back({LuaToken::kNumber, s.substr(start, i - start), line});
  }

  void op() {
    size_t len = 1;
    if (s.compare(i, 3, "...") == 0) len = 3;
    else
      for (const char* two : {"==", "~=", "<=", ">=", "..", "::", "//", "<<", ">>"})
        if (s.compare(i, 2, two) == 0) len = 2;
    out.push_back({LuaToken::kOp, s.substr(i, len), line});
    i += len;
  }

  void token() {
    const char c = s[i];
    if (c == '\n') {
      ++line, ++i;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else if (s.compare(i, 2, "--") == 0) {
      comment();
    } else if (c == '"' || c == '\'') {
      quoted_string();
    } else if (const size_t open = long_bracket(s, i)) {
      long_string(open);
    } else if (name_start(c)) {
      name();
    } else if (digit(c) || (c == '.' && i + 1 < s.size() && digit(s[i + 1]))) {
      number();
    } else {
      op();
    }
  }
};

}  // namespace

namespace {

// Line ends as Lua's lexer counts them: "\n", "\r", "\r\n" and "\n\r" each end one line (found
// by a probe: a file with old-Mac endings, a lone "\r", which Lua reads fine, was one line here,
// so its first comment hid the whole file from the static check).
std::string with_newlines(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (c != '\n' && c != '\r') {
      out += c;
      continue;
    }
    out += '\n';
    if (i + 1 < s.size() && (s[i + 1] == '\n' || s[i + 1] == '\r') && s[i + 1] != c) ++i;  // a pair is one end
  }
  return out;
}

}  // namespace

std::vector<LuaToken> lua_tokenize(const std::string& text) {
  const bool returns = text.find('\r') != std::string::npos;
  const std::string normalised = returns ? with_newlines(text) : std::string();
  const std::string& s = returns ? normalised : text;
  Lexer lexer(s);
  // A UTF-8 byte-order mark and a first line starting with '#' (a shebang) are skipped, as Lua's
  // file loader does (lua_file_text).
  if (s.rfind("\xEF\xBB\xBF", 0) == 0) lexer.i = 3;
  if (s.compare(lexer.i, 1, "#") == 0) lexer.i = std::min(s.find('\n', lexer.i), s.size());
  while (lexer.i < s.size()) lexer.token();
  lexer.out.push_back({LuaToken::kEnd, "", lexer.line});
  return std::move(lexer.out);
}

bool lua_keyword(const std::string& name) {
  static const std::set<std::string> words = {"and", "break", "do", "else", "elseif", "end", "false",
                                              "for", "function", "goto", "if", "in", "local", "nil",
                                              "not", "or", "repeat", "return", "then", "true", "until",
                                              "while"};
  return words.count(name) > 0;
}

bool lua_string_written_as(const std::string& written, const std::string& value) {
  if (written.size() != value.size()) return false;
  for (size_t k = 0; k < value.size(); ++k) {
    const char c = value[k];
    const bool plain = std::isalnum(static_cast<unsigned char>(c)) || c == '_';
    if (plain && written[k] != c) return false;
  }
  return true;
}

int lua_line_of_string_field(const std::vector<LuaToken>& t, const std::string& key, const std::string& value, int from) {
  for (size_t i = 0; i + 2 < t.size(); ++i)
    if (t[i].line >= from && t[i].type == LuaToken::kName && t[i].text == key && t[i + 1].type == LuaToken::kOp &&
        t[i + 1].text == "=" && t[i + 2].type == LuaToken::kString && lua_string_written_as(t[i + 2].text, value))
      return t[i].line;
  return 0;
}

// One pass over a script's tokens, tracking the open braces, parentheses, brackets and blocks.
struct LuaTableMap::Reader {
  enum Frame { kBrace, kParen, kBracket, kBlock };
  LuaTableMap& map;
  const std::vector<LuaToken> t;
  std::vector<std::pair<Frame, int>> stack;  // frame and, for braces, its node
  // The entry whose value starts at token `value_at` (after its '='), so that a '{' there is its child.
  int pending_node = -1, pending_entry = -1;
  size_t value_at = 0;

  Reader(LuaTableMap& m, const std::string& text) : map(m), t(lua_tokenize(text)) {}

  bool is_op(size_t i, const char* op) const { return t[i].type == LuaToken::kOp && t[i].text == op; }
  bool in_brace() const { return !stack.empty() && stack.back().first == kBrace; }
  int here() const { return in_brace() ? stack.back().second : -1; }

  void read() {
    for (size_t i = 0; i + 1 < t.size(); ++i) {
      if (entry(i)) continue;  // i is now its '='
      if (is_op(i, "{")) {
        open_brace(i);
        continue;
      }
      track_nesting(t[i]);
    }
  }

  // key = value, or ["key"] = value, directly inside a constructor: recorded with its value when
  // that is a plain name or string, and i moved to its '='.
  bool entry(size_t& i) {
    if (!in_brace()) return false;
    const LuaToken& tok = t[i];
    size_t key_end = 0;
    std::string key;
    if (tok.type == LuaToken::kName && !lua_keyword(tok.text) && is_op(i + 1, "=")) {
      key = tok.text, key_end = i + 1;
    } else if (is_op(i, "[") && i + 3 < t.size() && t[i + 1].type == LuaToken::kString && is_op(i + 2, "]") &&
               is_op(i + 3, "=")) {
      key = t[i + 1].text, key_end = i + 3;
    }
    if (!key_end) return false;
    Entry e;
    e.key = key, e.line = tok.line;
    const size_t v = key_end + 1;
    const bool alone = v + 1 < t.size() && (is_op(v + 1, ",") || is_op(v + 1, ";") || is_op(v + 1, "}"));
    if (alone && t[v].type == LuaToken::kName && !lua_keyword(t[v].text)) e.value_name = t[v].text;
    if (alone && t[v].type == LuaToken::kString) e.value_text = t[v].text;
    std::vector<Entry>& entries = map.nodes_[size_t(here())].entries;
    entries.push_back(std::move(e));
    pending_node = here(), pending_entry = int(entries.size()) - 1, value_at = v;
    i = key_end;
    return true;
  }

  // A table constructor: a node, the child of the entry whose value it is, an item of the
  // constructor around it, a local's table, or the table the script returns.
  void open_brace(size_t i) {
    const int node = int(map.nodes_.size()), parent = here();
    map.nodes_.push_back(Node{t[i].line, parent, {}, {}});
    if (pending_node >= 0 && value_at == i) {
      map.nodes_[size_t(pending_node)].entries[size_t(pending_entry)].child = node;
    } else if (in_brace() && i > 0 && (is_op(i - 1, "{") || is_op(i - 1, ",") || is_op(i - 1, ";"))) {
      map.nodes_[size_t(parent)].items.push_back(node);
    } else if (i >= 2 && is_op(i - 1, "=") && t[i - 2].type == LuaToken::kName && !in_brace()) {
      map.variables_.emplace_back(t[i - 2].text, node);  // local X = { ... }
    }
    if (i >= 1 && t[i - 1].type == LuaToken::kName && t[i - 1].text == "return" && stack.empty())
      map.returned_ = node;
    stack.push_back({kBrace, node});
  }

  // Every other token: what opens and closes the frames, and the top level's `return`.
  void track_nesting(const LuaToken& tok) {
    if (tok.type == LuaToken::kName && tok.text == "return" && stack.empty()) map.return_line_ = tok.line;
    if (tok.type == LuaToken::kOp) {
      if (tok.text == "(") stack.push_back({kParen, -1});
      if (tok.text == "[") stack.push_back({kBracket, -1});
      if ((tok.text == "}" || tok.text == ")" || tok.text == "]") && !stack.empty()) stack.pop_back();
    } else if (tok.type == LuaToken::kName) {
      if (tok.text == "function" || tok.text == "do" || tok.text == "if" || tok.text == "repeat")
        stack.push_back({kBlock, -1});
      if ((tok.text == "end" || tok.text == "until") && !stack.empty()) stack.pop_back();
    }
  }
};

LuaTableMap::LuaTableMap(const std::string& text) { Reader(*this, text).read(); }

const LuaTableMap::Entry* LuaTableMap::entry(int node, const std::string& key) const {
  if (node < 0) return nullptr;
  for (const auto& e : nodes_[size_t(node)].entries)
    if (e.key == key) return &e;
  return nullptr;
}

int LuaTableMap::value_node(const Entry& e) const {
  if (e.child >= 0) return e.child;
  if (e.value_name.empty()) return -1;
  for (const auto& [name, node] : variables_)
    if (name == e.value_name) return node;
  return -1;
}

int LuaTableMap::opened_on(int line) const {
  for (size_t n = 0; n < nodes_.size(); ++n)
    if (nodes_[n].line == line) return int(n);
  return -1;
}

}  // namespace roger
