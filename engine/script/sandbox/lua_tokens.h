// lua_tokens.h: Lua source text split into tokens with their lines, for the passes that read a
// script without running it: where the fields of a returned table are written (skill scripts)
// and the static check of names (lua_static_check.h). Strings, comments and long brackets are
// handled; the text is never compiled.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace roger {

struct LuaToken {
  enum Type { kName, kString, kNumber, kOp, kEnd } type;
  std::string text;  // names and operators as written; strings without their quotes
  int line;
};

// Splits Lua source into tokens, ending with one kEnd. Never fails: anything odd (an unfinished
// string, say) simply yields fewer tokens; the compiler reports it when the script runs.
std::vector<LuaToken> lua_tokenize(const std::string& text);

// Whether a name is one of Lua 5.4's reserved words.
bool lua_keyword(const std::string& name);

// Whether a string token's text (escapes as written) may be `value`: the same length, and the
// same letters, digits and '_' (each other character of `value` may be written otherwise).
bool lua_string_written_as(const std::string& written, const std::string& value);

// The line of the first `key = "value"` written at or after line `from` (0 when none), the string
// told by lua_string_written_as. Passes over text without a regex: std::regex's matcher recursed
// once per character of a long line and overflowed the stack (found by a probe).
int lua_line_of_string_field(const std::vector<LuaToken>& tokens, const std::string& key, const std::string& value,
                             int from = 1);

// The table constructors written in a Lua source text, with their lines. A Lua table carries no
// line numbers, so a message about a field of a table a script returned or passed (a skill
// script's policy, a stage's params) finds where it is written here. Read from the tokens only:
// fields set by code (t.x = 1, a table built in a loop) are not seen, and callers fall back to a
// line they know.
class LuaTableMap {
 public:
  struct Entry {
    std::string key;         // key = value, or ["key"] = value
    int line = 0;            // of the key
    int child = -1;          // the constructor written as its value, if one is
    std::string value_name;  // the variable named as its value (key = x,), if one is
    std::string value_text;  // the string written as its value (key = "x",), if one is
  };
  struct Node {
    int line = 0;             // of its '{'
    int parent = -1;          // the constructor it is written in, directly (-1: none)
    std::vector<Entry> entries;
    std::vector<int> items;   // the constructors written as its positional values, in order
  };

  explicit LuaTableMap(const std::string& text);

  const std::vector<Node>& nodes() const { return nodes_; }
  // The entry `key` written directly in `node`, or null (also for node -1).
  const Entry* entry(int node, const std::string& key) const;
  // The constructor an entry's value was written with: inline, or `local X = { ... }` named as
  // its value (the first such assignment of X); -1 when neither.
  int value_node(const Entry& e) const;
  // The constructor written after a top-level `return` (-1: none), and the line of the last
  // top-level `return` (0: none).
  int returned() const { return returned_; }
  int return_line() const { return return_line_; }
  // The first constructor opened on `line`, or -1.
  int opened_on(int line) const;

 private:
  struct Reader;  // the pass over the tokens that builds the map (lua_tokens.cpp)
  std::vector<Node> nodes_;
  std::vector<std::pair<std::string, int>> variables_;  // local X = { ... }, in order
  int returned_ = -1;
  int return_line_ = 0;
};

}  // namespace roger
