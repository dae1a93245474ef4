// Reading a batch script's returned table: the Lua value as JSON, and its fields checked one by
// one with the lines where they are written.
#include <algorithm>
#include <cmath>
#include <map>

#include <lua.hpp>

#include "core/error.h"
#include "core/text.h"
#include "script/batch/batch_script_internal.h"
#include "script/sandbox/lua_sandbox.h"  // suggestion

namespace roger {
namespace batch_detail {

// "'a', 'b'" (or "(none)") for messages.
std::string quoted_list(const std::vector<std::string>& items) {
  std::vector<std::string> q;
  for (const auto& s : items) q.push_back("'" + s + "'");
  return q.empty() ? "(none)" : join(q);
}

std::string has_no(const std::string& kind, const std::string& name, const std::vector<std::string>& names) {
  return "has no " + kind + " '" + name + "'" + suggestion(name, names) + "; its " + kind + "s are " + quoted_list(names);
}

namespace {
// The string at `index`, refused unless it is UTF-8 text: the manifest and the records are JSON,
// and a Latin-1 description would stop the run at its first write instead of here, at its line.
std::string utf8_text(lua_State* L, int index, const std::string& where) {
  size_t length = 0;
  const char* bytes = lua_tolstring(L, index, &length);
  std::string text(bytes, length);
  if (const std::string problem = utf8_problem(text); !problem.empty())
    throw Error(where + " must be UTF-8 text, got \"" + shortened_text(text, 40) + "\" (" + problem +
                "; save the script as UTF-8)");
  return text;
}

// The value at `path` within the returned table ("limits.instructions", "runs[2].params"), as
// messages name it: "field 'limits.instructions'", or the whole table when the path is empty.
std::string value_named(const std::string& path) {
  return path.empty() ? "the batch script's table" : "field '" + path + "'";
}
}  // namespace

// The Lua value at `index` as JSON: tables with keys 1..n are arrays, tables with string keys
// objects; numbers, strings and booleans as they are. `path` is where the value is within the
// returned table ("" for the table itself), for messages.
json lua_to_json(lua_State* L, int index, const std::string& path, int depth) {
  const std::string where = value_named(path);
  index = lua_absindex(L, index);
  if (depth > 32) throw Error(where + ": nested too deeply");
  switch (lua_type(L, index)) {
    case LUA_TNIL: return nullptr;
    case LUA_TBOOLEAN: return bool(lua_toboolean(L, index));
    case LUA_TNUMBER:
      if (lua_isinteger(L, index)) return int64_t(lua_tointeger(L, index));
      {
        const double v = lua_tonumber(L, index);
        if (!std::isfinite(v)) throw Error(where + " must be a finite number, got " + format_number(v));
        return v;
      }
    case LUA_TSTRING: return utf8_text(L, index, where);
    case LUA_TTABLE: {
      // Each level holds a key and a value on Lua's stack while the next reads its own: room for
      // them, which Lua guarantees for 20 slots only (found by a probe: a table nested 33 deep
      // wrote past the stack, and the sandbox crashed when it closed).
      if (!lua_checkstack(L, 3)) throw Error(where + ": nested too deeply");
      json obj = json::object();
      std::map<lua_Integer, json> items;
      lua_pushnil(L);
      while (lua_next(L, index) != 0) {
        if (lua_type(L, -2) == LUA_TSTRING) {
          const std::string key = utf8_text(L, -2, where + ": a key");
          obj[key] = lua_to_json(L, -1, path.empty() ? key : path + "." + key, depth + 1);
        } else if (lua_isinteger(L, -2)) {
          const lua_Integer k = lua_tointeger(L, -2);
          items[k] = lua_to_json(L, -1, path + "[" + std::to_string(k) + "]", depth + 1);
        } else {
          lua_pop(L, 2);
          throw Error(where + ": keys must be names or list positions");
        }
        lua_pop(L, 1);
      }
      if (!items.empty() && !obj.empty())
        throw Error(where + ": mixes named fields (" + obj.begin().key() + ") with list items");
      if (items.empty()) return obj.empty() ? json::array() : obj;
      json arr = json::array();
      lua_Integer expect = 1;
      for (auto& [k, v] : items) {
        if (k != expect) throw Error(where + ": a list with a hole at position " + std::to_string(expect));
        arr.push_back(std::move(v));
        ++expect;
      }
      return arr;
    }
    default:
      throw Error(where + " cannot be a " + std::string(lua_typename(L, lua_type(L, index))) +
                  " (batch scripts hold names, numbers, strings and tables)");
  }
}

// Throws a ScriptError at the script's line.
void Reader::fail(int line, const std::string& message) const {
  // Never past the file's last line: entries are looked for from the line after the one before
  // (found by a probe: a one-line script's second figure was said to be at line 2).
  int last = 1;
  for (size_t i = 0; tokens_[i].type != LuaToken::kEnd; ++i) last = std::max(last, tokens_[i].line);
  throw ScriptError(message, display_, std::min(line, last), "");
}

// The line where `name = "value"` is first written at or after line `from` (0 when not found).
int Reader::line_of_name(const std::string& value, int from) const {
  return lua_line_of_string_field(tokens_, "name", value, from);
}

bool Reader::is_assignment(size_t i, const std::string& key) const {
  return tokens_[i].type == LuaToken::kName && tokens_[i].text == key && tokens_[i + 1].type == LuaToken::kOp &&
         tokens_[i + 1].text == "=";
}

// The line of a table the script builds with a computed name (`name = stage`, in a loop): the
// first `name = <not a string>` at or after line `from`, then from the top, with `marker =` on
// its line or one of the next three (`stage` for a run); 0 when there is none. Found by a probe:
// such a run was reported at the line of another run, the first after `runs =`.
int Reader::line_of_built_name(const std::string& marker, int from) const {
  for (int start : {from, 1}) {
    for (size_t i = 0; tokens_[i].type != LuaToken::kEnd; ++i) {
      if (tokens_[i].line < start || !is_assignment(i, "name")) continue;
      const LuaToken& value = tokens_[i + 2];
      if (value.type == LuaToken::kString || value.type == LuaToken::kEnd || value.text == "[") continue;
      for (size_t j = i + 3; tokens_[j].type != LuaToken::kEnd && tokens_[j].line <= value.line + 3; ++j)
        if (is_assignment(j, marker)) return tokens_[i].line;
    }
  }
  return 0;
}

// The line where `key =` is first written at or after line `from`, else `from`.
int Reader::line_of_key(const std::string& key, int from) const {
  for (size_t i = 0; tokens_[i].type != LuaToken::kEnd; ++i)
    if (tokens_[i].line >= from && is_assignment(i, key)) return tokens_[i].line;
  return from;
}

int Reader::return_line() const {
  int line = 1;
  for (size_t i = 0; tokens_[i].type != LuaToken::kEnd; ++i)
    if (tokens_[i].type == LuaToken::kName && tokens_[i].text == "return" &&
        (i == 0 || tokens_[i - 1].line < tokens_[i].line))
      line = tokens_[i].line;
  return line;
}

// Checks that a value is an object with only known keys.
void Reader::check_object(const json& j, const std::string& what, const std::vector<std::string>& known,
                          int line) const {
  if (!j.is_object()) fail(line, what + " must be a table of named fields");
  for (auto it = j.begin(); it != j.end(); ++it)
    if (std::find(known.begin(), known.end(), it.key()) == known.end())
      fail(line_of_key(it.key(), line), what + ": unknown field '" + it.key() + "'" + suggestion(it.key(), known) +
                                               "; the fields are " + join(known));
}

namespace {

// A value of the script as a message names it: "string '2'", "number 2.5", "a table".
std::string json_value_said(const json& v) {
  if (v.is_string()) return "string '" + shortened_text(v.get<std::string>(), 40) + "'";
  if (v.is_number()) return "number " + v.dump();
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  return v.is_null() ? "nil" : "a table";
}

}  // namespace

// A string field (the fallback when absent; a required one must be present and not empty).
std::string Reader::str(const json& o, const char* key, const std::string& what, int line,
                        const std::string& fallback, bool required) const {
  if (!o.contains(key)) {
    if (required) fail(line, what + ": missing required field '" + key + "'");
    return fallback;
  }
  if (!o[key].is_string())
    fail(line_of_key(key, line), what + ": field '" + key + "' must be a string, got " + json_value_said(o[key]));
  const std::string s = o[key];
  if (required && s.empty()) fail(line_of_key(key, line), what + ": field '" + key + "' is empty");
  return s;
}

// An integer field within [lo, hi] (the fallback when absent).
int64_t Reader::integer(const json& o, const char* key, const std::string& what, int line, int64_t fallback,
                        int64_t lo, int64_t hi) const {
  if (!o.contains(key)) return fallback;
  const json& v = o[key];
  int64_t x = 0;
  if (v.is_number_integer()) x = v.get<int64_t>();
  else if (v.is_number_float() && std::floor(v.get<double>()) == v.get<double>() && std::fabs(v.get<double>()) < 9.2e18)
    x = int64_t(v.get<double>());  // a whole float (2^53, 2e8) is the integer it holds; the range says the rest
  else if (v.is_number_float() && std::floor(v.get<double>()) == v.get<double>())
    // A whole number past int64 (2^63, 1e300) is an integer out of range, not "not an integer".
    fail(line_of_key(key, line), what + ": field '" + key + "' must be between " + std::to_string(lo) + " and " +
                                     std::to_string(hi) + ", got " + json_value_said(v));
  else fail(line_of_key(key, line), what + ": field '" + key + "' must be an integer, got " + json_value_said(v));
  if (x < lo || x > hi)
    fail(line_of_key(key, line), what + ": field '" + key + "' must be between " + std::to_string(lo) + " and " +
                                     std::to_string(hi) + ", got " + std::to_string(x));
  return x;
}

// A boolean field (the fallback when absent).
bool Reader::boolean(const json& o, const char* key, const std::string& what, int line, bool fallback) const {
  if (!o.contains(key)) return fallback;
  if (!o[key].is_boolean())
    fail(line_of_key(key, line), what + ": field '" + key + "' must be true or false, got " + json_value_said(o[key]));
  return o[key].get<bool>();
}

// A list of distinct names (a required one must be present and not empty).
std::vector<std::string> Reader::strings(const json& o, const char* key, const std::string& what, int line,
                                         bool required) const {
  std::vector<std::string> out;
  if (!o.contains(key)) {
    if (required) fail(line, what + ": missing required field '" + key + "' (a list of names)");
    return out;
  }
  const json& v = o[key];
  if (!v.is_array()) fail(line_of_key(key, line), what + ": field '" + key + "' must be a list of names");
  for (const auto& s : v) {
    if (!s.is_string()) fail(line_of_key(key, line), what + ": field '" + key + "' must be a list of names");
    const std::string n = s;
    if (std::find(out.begin(), out.end(), n) != out.end())
      fail(line_of_key(key, line), what + ": field '" + key + "' names '" + n + "' twice");
    out.push_back(n);
  }
  if (required && out.empty()) fail(line_of_key(key, line), what + ": field '" + key + "' is empty");
  return out;
}

// Scenario parameters: a table of name = number, string or boolean, or a list parameter's values as
// a list ({"left_eye", "right_eye"}: the text "left_eye,right_eye", as a stage's params take it).
Params Reader::params(const json& o, const char* key, const std::string& what, int line) const {
  Params out;
  if (!o.contains(key)) return out;
  const json& v = o[key];
  if (v.is_array() && v.empty()) return out;
  if (!v.is_object()) fail(line_of_key(key, line), what + ": field '" + key + "' must be a table of name = value");
  for (auto it = v.begin(); it != v.end(); ++it) {
    std::string text;
    if (it->is_string()) text = it->get<std::string>();
    else if (it->is_number_integer()) text = std::to_string(it->get<int64_t>());
    else if (it->is_number_float()) text = format_number(it->get<double>());
    else if (it->is_boolean()) text = it->get<bool>() ? "true" : "false";
    else if (it->is_array() && !it->empty()) {
      bool first = true;
      for (const json& item : *it) {
        const std::string value = item.is_string() ? item.get<std::string>()
                                  : item.is_number_integer() ? std::to_string(item.get<int64_t>())
                                  : item.is_number() ? format_number(item.get<double>()) : ",";
        if (value.find(',') != std::string::npos)
          fail(line_of_key(key, line), what + ": parameter '" + it.key() + "' as a list takes names or numbers "
               "without commas, got " + item.dump());
        text += (first ? "" : ",") + value;
        first = false;
      }
    } else
      fail(line_of_key(key, line), what + ": parameter '" + it.key() + "' must be a number, string or boolean, or a "
           "list of names {\"a\", \"b\"} (a list parameter's values)");
    out.emplace_back(it.key(), text);
  }
  return out;
}

}  // namespace batch_detail
}  // namespace roger
