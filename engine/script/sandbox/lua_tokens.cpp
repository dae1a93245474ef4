// lua_tokens.cpp: Lua source split into tokens with their lines (lua_tokens.h).
#include "script/sandbox/lua_tokens.h"

#include <cctype>
#include <cstring>
#include <set>

namespace roger {
namespace {

// The length of a long bracket "[==[" at s[i] (its level + 2), or 0 when there is none.
size_t long_bracket(const std::string& s, size_t i) {
  if (i >= s.size() || s[i] != '[') return 0;
  size_t j = i + 1;
  while (j < s.size() && s[j] == '=') ++j;
  return j < s.size() && s[j] == '[' ? j - i + 1 : 0;
}

}  // namespace

std::vector<LuaToken> lua_tokenize(const std::string& s) {
  std::vector<LuaToken> out;
  int line = 1;
  size_t i = 0;
  // Skips a long bracket body whose opening bracket (of `open` characters) starts at i.
  auto skip_long = [&](size_t open, std::string* text) {
    const std::string close = "]" + std::string(open - 2, '=') + "]";
    const size_t start = i + open;
    const size_t end = s.find(close, start);
    const size_t stop = end == std::string::npos ? s.size() : end;
    for (size_t k = i; k < stop; ++k) line += s[k] == '\n';
    if (text) *text = s.substr(start, stop - start);
    i = end == std::string::npos ? s.size() : end + close.size();
  };
  if (s.rfind("#", 0) == 0) i = s.find('\n') == std::string::npos ? s.size() : s.find('\n');
  while (i < s.size()) {
    const char c = s[i];
    if (c == '\n') {
      ++line, ++i;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else if (s.compare(i, 2, "--") == 0) {
      i += 2;
      if (const size_t open = long_bracket(s, i)) {
        skip_long(open, nullptr);
      } else {
        while (i < s.size() && s[i] != '\n') ++i;
      }
    } else if (c == '"' || c == '\'') {
      const int at = line;
      std::string text;
      for (++i; i < s.size() && s[i] != c; ++i) {
        if (s[i] == '\\' && i + 1 < s.size()) text += s[i++];
        line += s[i] == '\n';
        text += s[i];
      }
      ++i;
      out.push_back({LuaToken::kString, text, at});
    } else if (const size_t open = long_bracket(s, i)) {
      const int at = line;
      std::string text;
      skip_long(open, &text);
      out.push_back({LuaToken::kString, text, at});
    } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      const size_t start = i;
      while (i < s.size() && (std::isalnum(static_cast<unsigned char>(s[i])) || s[i] == '_')) ++i;
      out.push_back({LuaToken::kName, s.substr(start, i - start), line});
    } else if (std::isdigit(static_cast<unsigned char>(c)) ||
               (c == '.' && i + 1 < s.size() && std::isdigit(static_cast<unsigned char>(s[i + 1])))) {
      const size_t start = i;
      while (i < s.size() && (std::isalnum(static_cast<unsigned char>(s[i])) || s[i] == '.' ||
                              ((s[i] == '+' || s[i] == '-') && std::strchr("eEpP", s[i - 1]))))
        ++i;
      out.push_back({LuaToken::kNumber, s.substr(start, i - start), line});
    } else {
      size_t len = 1;
      if (s.compare(i, 3, "...") == 0) len = 3;
      else
        for (const char* op : {"==", "~=", "<=", ">=", "..", "::", "//", "<<", ">>"})
          if (s.compare(i, 2, op) == 0) len = 2;
      out.push_back({LuaToken::kOp, s.substr(i, len), line});
      i += len;
    }
  }
  out.push_back({LuaToken::kEnd, "", line});
  return out;
}

bool lua_keyword(const std::string& name) {
  static const std::set<std::string> words = {"and", "break", "do", "else", "elseif", "end", "false",
                                              "for", "function", "goto", "if", "in", "local", "nil",
                                              "not", "or", "repeat", "return", "then", "true", "until",
                                              "while"};
  return words.count(name) > 0;
}

}  // namespace roger
