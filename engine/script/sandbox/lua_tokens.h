// lua_tokens.h: Lua source text split into tokens with their lines, for the passes that read a
// script without running it: where the fields of a returned table are written (skill scripts)
// and the static check of names (lua_static_check.h). Strings, comments and long brackets are
// handled; the text is never compiled.
#pragma once

#include <string>
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

}  // namespace roger
