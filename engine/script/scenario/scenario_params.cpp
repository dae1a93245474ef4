// scenario_params.cpp: scenario parameters: their types, reading the script's `params` table,
// and parsing values given as text.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "core/text.h"
#include "script/scenario/scenario_internal.h"

namespace roger {

// A finite number; one too small for a double (1e-400) is its nearest, not an error: only
// overflow is.
bool parse_number_text(const std::string& text, double& value) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  const bool underflow = errno == ERANGE && std::fabs(v) <= std::numeric_limits<double>::min();
  if (text.empty() || *end || (errno && !underflow) || !std::isfinite(v)) return false;
  value = v;
  return true;
}

std::vector<std::string> list_param_items(const std::string& text) {
  std::vector<std::string> items;
  for (size_t from = 0; from <= text.size();) {
    const size_t comma = std::min(text.find(',', from), text.size());
    std::string item = text.substr(from, comma - from);
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    items.push_back(std::move(item));
    from = comma + 1;
  }
  return items;
}

const char* param_type_name(ParamType type) {
  switch (type) {
    case ParamType::kNumber: return "number";
    case ParamType::kInteger: return "integer";
    case ParamType::kString: return "string";
    case ParamType::kBoolean: return "boolean";
  }
  return "?";
}

namespace scenario_detail {

// The canonical text of a parameter value (what WorldSpec::params records).
std::string slot_text(const ParamSlot& s) {
  switch (s.info.type) {
    case ParamType::kNumber: return format_number(s.number);
    case ParamType::kInteger: return std::to_string(s.integer);
    case ParamType::kString: return s.text;
    case ParamType::kBoolean: return s.flag ? "true" : "false";
  }
  return "";
}

// Pushes a parameter value with its Lua type.
void push_slot(lua_State* L, const ParamSlot& s) {
  switch (s.info.type) {
    case ParamType::kNumber: lua_pushnumber(L, s.number); break;
    case ParamType::kInteger: lua_pushinteger(L, s.integer); break;
    case ParamType::kString: lua_pushstring(L, s.text.c_str()); break;
    case ParamType::kBoolean: lua_pushboolean(L, s.flag); break;
  }
}

// What a parameter takes, whole: "an integer in [0, 12]", "a number of at least 0.01", "one of
// circle, spade", "a boolean (true or false)", "a string".
std::string expected_text(const ScenarioParam& p) {
  if (p.list) return "a comma-separated list of any of " + join(p.choices) + " (or none)";
  if (!p.choices.empty()) return "one of " + join(p.choices);
  switch (p.type) {
    case ParamType::kBoolean: return "a boolean (true or false)";
    case ParamType::kString: return "a string";
    case ParamType::kInteger:
    case ParamType::kNumber: break;
  }
  const std::string kind = p.type == ParamType::kInteger ? "an integer" : "a number";
  if (p.min && p.max) return kind + " in [" + format_number(*p.min) + ", " + format_number(*p.max) + "]";
  if (p.min) return kind + " of at least " + format_number(*p.min);
  if (p.max) return kind + " of at most " + format_number(*p.max);
  return kind;
}

namespace {

// An integer, or a whole number written as a float ("2.0", "1e3"), as a Lua table takes
// `delay = 2.0` (lua_param_text): the same value, so the same parameter.
bool parse_integer_text(const std::string& text, int64_t& value) {
  const char* begin = text.c_str();
  char* end = nullptr;
  errno = 0;
  long long v = std::strtoll(begin, &end, 10);
  if (!text.empty() && *end && !errno) {
    errno = 0;
    const double d = std::strtod(begin, &end);
    if (*end || errno || !(std::fabs(d) < 0x1p62) || d != std::floor(d)) return false;
    v = static_cast<long long>(d);
  }
  if (text.empty() || *end || errno) return false;
  value = v;
  return true;
}

bool parse_boolean_text(const std::string& text, bool& value) {
  const std::string t = lower_ascii(text);
  if (t == "true" || t == "1" || t == "yes" || t == "on") return value = true, true;
  if (t == "false" || t == "0" || t == "no" || t == "off") return value = false, true;
  return false;
}

// Each item of a list parameter's text, spaces around it dropped, is one of the choices, and is
// there once (a name twice is most likely another mistyped as it: world:robot refuses it, at a
// library's line).
bool check_list_items(const ParamSlot& s, const std::string& canonical, std::string& why) {
  std::vector<std::string> seen;
  for (const std::string& item : list_param_items(canonical)) {
    // An empty item beside others ("left_eye,", ",") is most likely one left out: "" alone is none
    // (found by a probe: --set locked=, locked nothing, unsaid).
    if (item.empty() && canonical.find_first_not_of(" \t") != std::string::npos)
      return why = expected_text(s.info) + ", with no empty item between commas", false;
    if (!item.empty() && std::find(s.info.choices.begin(), s.info.choices.end(), item) == s.info.choices.end())
      return why = expected_text(s.info), false;
    if (!item.empty() && std::find(seen.begin(), seen.end(), item) != seen.end())
      return why = expected_text(s.info) + ", each once", false;
    seen.push_back(item);
  }
  return true;
}

}  // namespace

// Parses text into a slot of the slot's type; false (and `why`: what the parameter takes, whole)
// when it does not fit.
bool parse_slot(ParamSlot& s, const std::string& text, std::string& why) {
  const auto refuse = [&]() { return why = expected_text(s.info), false; };
  const bool numeric = s.info.type == ParamType::kInteger || s.info.type == ParamType::kNumber;
  // strtoll and strtod skip leading blanks, which would take " 3" where "3 " is refused.
  if (numeric && !text.empty() && std::isspace(static_cast<unsigned char>(text[0]))) return refuse();
  // Nor hexadecimal, which strtod takes (found by a probe: --set eye_pixels=0x20 ran 32 pixels and
  // was recorded as 0x20; robot_distance = "0x10" from Python was 16 m).
  if (numeric && text.find_first_of("xX") != std::string::npos) return refuse();
  bool parsed = true;
  switch (s.info.type) {
    case ParamType::kInteger: parsed = parse_integer_text(text, s.integer); break;
    case ParamType::kNumber: parsed = parse_number_text(text, s.number); break;
    case ParamType::kBoolean: parsed = parse_boolean_text(text, s.flag); break;
    case ParamType::kString: s.text = text; break;
  }
  if (!parsed) return refuse();
  const std::string canonical = slot_text(s);
  if (s.info.list) return check_list_items(s, canonical, why);
  if (!s.info.choices.empty() &&
      std::find(s.info.choices.begin(), s.info.choices.end(), canonical) == s.info.choices.end())
    return refuse();
  const double value = s.info.type == ParamType::kInteger ? double(s.integer) : s.number;
  if (numeric && ((s.info.min && value < *s.info.min) || (s.info.max && value > *s.info.max))) return refuse();
  return true;
}

// "name (type, default d; one of ...)", for the unknown-parameter message.
std::string describe_param(const ScenarioParam& p) {
  std::string text = p.name + " (" + param_type_name(p.type) + ", default " + p.default_value;
  if (!p.choices.empty()) text += (p.list ? "; a list of any of " : "; one of ") + join(p.choices);
  if (p.min) text += "; min " + format_number(*p.min);
  if (p.max) text += "; max " + format_number(*p.max);
  return text + ")";
}

}  // namespace scenario_detail

namespace {

// Parameter names must be usable as params.name in Lua.
bool is_identifier(const std::string& s) {
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
  return std::all_of(s.begin(), s.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

}  // namespace

using namespace scenario_detail;

// Reads the `params` table: short (name = default) and long ({default=, ...}) forms.
void Scenario::Impl::read_params(lua_State* L, int index, const LuaTableMap& map, int node) {
  index = lua_absindex(L, index);
  const int params_line = reading_line;
  if (!lua_istable(L, index))
    throw error(std::string("the scenario's 'params' must be a table of name = default, got ") +
                    luaL_typename(L, index), params_line);
  lua_pushnil(L);
  while (lua_next(L, index)) {
    const int key_slot = lua_gettop(L) - 1;
    // Where this parameter is written (a table built by code, body.with_params{...}, has no
    // entries in the text: then the `params` line).
    const LuaTableMap::Entry* e =
        lua_type(L, -2) == LUA_TSTRING ? map.entry(node, lua_tostring(L, -2)) : nullptr;
    reading_line = e ? e->line : params_line;
    ParamSlot slot = read_param(L);
    params[slot.info.name] = std::move(slot);
    lua_settop(L, key_slot);  // keep the key for lua_next
  }
}

// Reads one parameter: its name (the key at -2) and its short or long form (the value at -1).
ParamSlot Scenario::Impl::read_param(lua_State* L) const {
  if (lua_type(L, -2) != LUA_TSTRING || !is_identifier(lua_tostring(L, -2)))
    throw error("parameter names must be identifiers (name = default), got " +
                std::string(lua_type(L, -2) == LUA_TSTRING ? "'" + std::string(lua_tostring(L, -2)) + "'"
                                                           : luaL_typename(L, -2)));
  ParamSlot slot;
  slot.info.name = lua_tostring(L, -2);
  const std::string ctx = "parameter '" + slot.info.name + "'";
  int value = lua_gettop(L);
  std::vector<std::string> choices;
  if (lua_istable(L, value)) value = read_param_table(L, value, ctx, slot, choices);
  read_default(L, value, ctx, slot);
  // Found by a probe: default = "0.35" with min = 0.2 made a string parameter, and the first
  // world:goal{radius = p.goal_radius} was blamed for a string, not this line.
  const bool numeric = slot.info.type == ParamType::kNumber || slot.info.type == ParamType::kInteger;
  if (!numeric && (slot.info.min || slot.info.max))
    throw error(ctx + ": " + (slot.info.min ? "min" : "max") + " bounds a number, and the default is " +
                param_type_name(slot.info.type) + " " +
                (slot.info.type == ParamType::kString ? "'" + slot.text + "'" : slot_text(slot)) +
                " (its type is the default's: write it as a number for a numeric parameter)");
  if (slot.info.list && slot.info.type != ParamType::kString)
    throw error(ctx + ": a list's default is a string of comma-separated choices (\"\" for none), got " +
                param_type_name(slot.info.type) + " " + slot_text(slot));
  // An integer parameter's bounds are whole numbers (found by a probe: min = 0.5 on an integer
  // default passed, reading as a real-valued bound the parameter can never take).
  for (const auto& [bound, name] : {std::pair{slot.info.min, "min"}, std::pair{slot.info.max, "max"}})
    if (slot.info.type == ParamType::kInteger && bound && *bound != std::floor(*bound))
      throw error(ctx + ": " + name + " = " + format_number(*bound) + " bounds an integer parameter (its default " +
                  slot_text(slot) + " is an integer): give a whole number, or write the default as " + slot_text(slot) +
                  ".0 for a real-valued parameter");
  slot.info.choices = choices;
  slot.info.default_value = slot.info.value = slot_text(slot);
  if (numeric) check_choices_in_bounds(slot.info, ctx);
  std::string why;
  ParamSlot check = slot;
  if (!parse_slot(check, slot.info.default_value, why))
    throw error(ctx + ": the default " + slot.info.default_value + " is not " + why);
  return slot;
}

// A numeric choice outside the parameter's own min or max could never be set: the value would be
// refused for the bounds while the refusal named it among the choices (found by a probe: "expects
// one of 1, 2, 4, got '4'", at no line). Refused at the declaration instead.
void Scenario::Impl::check_choices_in_bounds(const ScenarioParam& p, const std::string& ctx) const {
  for (const std::string& c : p.choices) {
    double value = 0.0;
    if (!parse_number_text(c, value)) continue;  // not a number: the default's check names it
    const std::string choice = ctx + ": the choice " + c + " is ", never = ", so it could never be set";
    // Found by a probe: choices {2.5, 2} on an integer default loaded, and 2.5 was then refused as
    // not one of "2.5, 2", at no line.
    if (p.type == ParamType::kInteger && value != std::floor(value))
      throw error(choice + "not whole, and the parameter is an integer (its default " + p.default_value +
                  "): give whole numbers, or write the default as " + p.default_value + ".0 for a real-valued parameter");
    if (p.min && value < *p.min) throw error(choice + "below its min = " + format_number(*p.min) + never);
    if (p.max && value > *p.max) throw error(choice + "above its max = " + format_number(*p.max) + never);
  }
}

// The long form {default=, description=, choices=, list=, min=, max=}: fills the slot's
// description, bounds, `choices` and whether it is a list of them, pushes the default and returns
// its stack index.
int Scenario::Impl::read_param_table(lua_State* L, int value, const std::string& ctx, ParamSlot& slot,
                                     std::vector<std::string>& choices) const {
  LuaFields f(L, value, ctx, {"default", "description", "choices", "list", "min", "max"});
  slot.info.description = f.string("description", "");
  if (f.has("min")) slot.info.min = f.number("min");
  if (f.has("max")) slot.info.max = f.number("max");
  // Found by a probe: min = 1, max = 0.2 was said as "the default 0.5 is not a number in [1, 0.2]".
  if (slot.info.min && slot.info.max && *slot.info.min > *slot.info.max)
    throw error(ctx + ": min = " + format_number(*slot.info.min) + " is above max = " + format_number(*slot.info.max) +
                ", so no value could be set");
  if (f.push("choices") != LUA_TNIL) read_choices(L, f, ctx, choices);
  slot.info.list = f.boolean("list", false);
  if (slot.info.list && choices.empty())
    throw error(ctx + ": list = true takes the items from choices = {...}, and there are none");
  // A list's value is its items joined by commas: an item holding one could never be given
  // (found by a probe: choices {"a,b", "c"} loaded, and its default failed at the first world).
  for (const std::string& c : choices)
    if (slot.info.list && (c.find(',') != std::string::npos || c.empty()))
      throw error(ctx + ": list = true joins its items with commas, so an item cannot " +
                  (c.empty() ? std::string("be empty") : "hold one, got '" + c + "'"));
  f.push("default");
  value = lua_gettop(L);
  if (lua_isnil(L, value)) throw error(ctx + ": missing its 'default'");
  return value;
}

// The list of allowed values (on the stack top) as their canonical texts.
void Scenario::Impl::read_choices(lua_State* L, const LuaFields& f, const std::string& ctx,
                                  std::vector<std::string>& choices) const {
  if (!lua_istable(L, -1)) f.wrong_type("choices", "a list of allowed values");
  // Found by a probe: {"a", "b", extra = "c"} dropped the "c" without a word.
  if (const std::string key = lua_key_beside_list(L, -1); !key.empty())
    throw error(ctx + ": choices must be a list {\"a\", \"b\", ...}, got the key " + key);
  int numbers = 0, strings = 0;
  for (lua_Integer i = 1; i <= lua_Integer(lua_rawlen(L, -1)); ++i) {
    lua_rawgeti(L, -1, i);
    numbers += lua_type(L, -1) == LUA_TNUMBER;
    strings += lua_type(L, -1) == LUA_TSTRING;
    // Found by a probe: {"circle", 3} loaded, a choice of another type than the others.
    if (numbers > 0 && strings > 0)
      throw error(ctx + ": choices mixes numbers and strings; give all of one kind, the default's");
    if (lua_type(L, -1) == LUA_TNUMBER || lua_type(L, -1) == LUA_TSTRING)
      choices.push_back(lua_isinteger(L, -1) ? std::to_string(lua_tointeger(L, -1))
                        : lua_type(L, -1) == LUA_TNUMBER ? format_number(lua_tonumber(L, -1))
                                                          : lua_tostring(L, -1));
    else
      throw error(ctx + ": choices must be numbers or strings");
    // Found by a probe: {1, 1} loaded; a choice given twice is a slip (another value was meant).
    if (std::find(choices.begin(), choices.end() - 1, choices.back()) != choices.end() - 1)
      throw error(ctx + ": the choice " + choices.back() + " is given twice");
    lua_pop(L, 1);
  }
  if (choices.empty()) throw error(ctx + ": choices is empty");
}

// The parameter's type and value, taken from its default (at `value`).
void Scenario::Impl::read_default(lua_State* L, int value, const std::string& ctx,
                                  ParamSlot& slot) const {
  switch (lua_type(L, value)) {
    case LUA_TNUMBER:
      if (lua_isinteger(L, value)) {
        slot.info.type = ParamType::kInteger;
        slot.integer = lua_tointeger(L, value);
      } else {
        slot.info.type = ParamType::kNumber;
        slot.number = lua_tonumber(L, value);
      }
      break;
    case LUA_TSTRING:
      slot.info.type = ParamType::kString;
      slot.text = lua_tostring(L, value);
      break;
    case LUA_TBOOLEAN:
      slot.info.type = ParamType::kBoolean;
      slot.flag = lua_toboolean(L, value);
      break;
    default:
      throw error(ctx + ": the default must be a number, integer, string or boolean, got " +
                  luaL_typename(L, value));
  }
}

}  // namespace roger
