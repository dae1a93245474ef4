// batch_script_internal.h: what the batch script loader (batch_script.cpp) shares with
// batch_script_reader.cpp (the returned table as JSON, and reading its fields with their lines).
// Private to engine/script/batch.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "script/batch/batch_script.h"
#include "script/sandbox/lua_tokens.h"

struct lua_State;

namespace roger {
namespace batch_detail {

using json = nlohmann::json;

// The title of a table written without one, made from what it shows: "Comparison of SG/B1,
// SG/DC2", "Stage SG (run SG)", "Evaluation generalization", with ": final success by shape"
// for a table split by a feature (docs/api/batch.lua).
std::string default_title(const BatchTable& t, const BatchScript& b);

// "'a', 'b'" (or "(none)") for messages.
std::string quoted_list(const std::vector<std::string>& items);

// "has no context 'DC22' (did you mean 'DC2'?); its contexts are 'B1', 'DC2'": `kind` is what
// `name` should have been ("context", "stage"), `names` what there is.
std::string has_no(const std::string& kind, const std::string& name, const std::vector<std::string>& names);

// The Lua value at `index` as JSON: tables with keys 1..n are arrays, tables with string keys
// objects; numbers, strings and booleans as they are. `path` is where the value lies within the
// returned table ("limits.instructions"; "" for the table), for messages.
json lua_to_json(lua_State* L, int index, const std::string& path, int depth = 0);

// Reads a validated script out of the JSON the Lua script returned, with lines for messages.
class Reader {
 public:
  // The lines of what a message names are found in the text's tokens, not by std::regex: its matcher
  // recursed once per character of a long line and overflowed the stack (found by a probe).
  Reader(std::string display, const std::string& text) : display_(std::move(display)), tokens_(lua_tokenize(text)) {}

  // Throws a ScriptError at the script's line.
  [[noreturn]] void fail(int line, const std::string& message) const;

  // The line where `name = "value"` is first written at or after line `from` (0 when not found).
  int line_of_name(const std::string& value, int from = 1) const;
  // The line of a table with a computed name (`name = stage`) and `marker =` within three lines,
  // at or after line `from`, else anywhere (0 when there is none).
  int line_of_built_name(const std::string& marker, int from = 1) const;
  // The line where `key =` is first written at or after line `from`, else `from`.
  int line_of_key(const std::string& key, int from = 1) const;
  // The line of the last `return` that begins its line (1 when none): the returned table's.
  int return_line() const;

  // Checks that a value is an object with only known keys.
  void check_object(const json& j, const std::string& what, const std::vector<std::string>& known, int line) const;

  // A string field (the fallback when absent; a required one must be present and not empty).
  std::string str(const json& o, const char* key, const std::string& what, int line, const std::string& fallback,
                  bool required = false) const;

  // An integer field within [lo, hi] (the fallback when absent).
  int64_t integer(const json& o, const char* key, const std::string& what, int line, int64_t fallback, int64_t lo,
                  int64_t hi) const;

  // A boolean field (the fallback when absent).
  bool boolean(const json& o, const char* key, const std::string& what, int line, bool fallback) const;

  // A list of distinct names (a required one must be present and not empty).
  std::vector<std::string> strings(const json& o, const char* key, const std::string& what, int line,
                                   bool required) const;

  // Scenario parameters: a table of name = number, string or boolean.
  Params params(const json& o, const char* key, const std::string& what, int line) const;

 private:
  // Whether token i is the name `key` followed by `=` (not `==`).
  bool is_assignment(size_t i, const std::string& key) const;
  std::string display_;
  std::vector<LuaToken> tokens_;
};

}  // namespace batch_detail
}  // namespace roger
