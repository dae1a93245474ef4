// The primitives of the control API: roger.primitive, c:with{...}, c:param(name), c:params(), and
// how a parameter table is applied to a primitive.
#include <algorithm>
#include <cmath>

#include "script/control/lua_control_internal.h"

namespace roger {
namespace lua_control_detail {
namespace {

// The primitive behind a controller value, if it is one.
PrimitivePtr as_primitive(const ControllerPtr& c) { return std::dynamic_pointer_cast<Primitive>(c); }

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
      const std::string expected =
          "a number in " + range_text(*def) + (def->body ? " or \"body\" (the episode's body decides)" : "");
      if (def->body && lua_type(L, -1) == LUA_TSTRING && std::string(lua_tostring(L, -1)) == "body") {
        p.set_text(key, "body");
        lua_pop(L, 1);
        continue;
      }
      if (lua_type(L, -1) != LUA_TNUMBER)
        raise(L, param + " must be " + expected + ", got " + lua_describe_value(L, -1));
      const double v = lua_tonumber(L, -1);
      if (!std::isfinite(v)) raise(L, param + " must be a finite number in " + range_text(*def) + ", got " + format_number(v));
      if (v < def->min || v > def->max)
        raise(L, param + " must be within " + range_text(*def) + ", got " + format_number(v));
      if (def->whole && v != std::floor(v))
        raise(L, param + " must be a whole number in " + range_text(*def) + " (an index), got " + format_number(v));
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

}  // namespace

// roger.primitive(kind [, {param = value, ..., name = "..."}])
int l_primitive(lua_State* L) {
  return lua_protect(L, [L]() {
    ControlBook& book = book_of(L);
    lua_check_arity(L, "roger.primitive", 2, "1 or 2 arguments (a kind and a table of parameters)");
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
    lua_check_arity(L, "c:with", 1, "1 argument (a table of parameters)");
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
    lua_check_arity(L, "c:param", 1, "1 argument (a parameter name)");
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
  lua_check_arity(L, "c:params", 0, "no arguments");
  lua_createtable(L, 0, int(p->param_defs().size()));
  for (const auto& d : p->param_defs()) {
    if (d.choices.empty()) lua_pushnumber(L, d.value);
    else lua_pushstring(L, d.text.c_str());
    lua_setfield(L, -2, d.name.c_str());
  }
  return 1;
}

}  // namespace lua_control_detail
}  // namespace roger
