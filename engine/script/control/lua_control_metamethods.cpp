// The metamethods of controller and predicate values: their fields, tostring, and the errors for
// changing a controller in place or reading a predicate's fields.
#include "script/control/lua_control_internal.h"

namespace roger {
namespace lua_control_detail {
namespace {

// Pushes a part of a composite: a name stand-in shows as the controller it is bound to.
void push_part(lua_State* L, const ControllerPtr& part) {
  const auto* ref = dynamic_cast<const NameReference*>(part.get());
  lua_push_controller(L, ref && ref->target() ? ref->target() : part);
}

// Pushes a list of controllers as a Lua list.
void push_parts(lua_State* L, const std::vector<ControllerPtr>& parts) {
  lua_createtable(L, int(parts.size()), 0);
  for (size_t i = 0; i < parts.size(); ++i) {
    push_part(L, parts[i]);
    lua_rawseti(L, -2, lua_Integer(i + 1));
  }
}

}  // namespace

// c.name, c.kind, the parts of composites (subordinate, superior, steps, actions) and the methods.
int l_controller_index(lua_State* L) {
  return lua_protect(L, [L]() {
    const ControllerPtr c = *static_cast<ControllerPtr*>(luaL_checkudata(L, 1, kControllerType));
    const std::string key = lua_type(L, 2) == LUA_TSTRING ? lua_tostring(L, 2) : "";
    const auto* sub = dynamic_cast<const SubjectTo*>(c.get());
    const auto* seq = dynamic_cast<const Sequence*>(c.get());
    const auto* pol = dynamic_cast<const Policy*>(c.get());
    if (key == "name") {
      lua_pushstring(L, c->name().c_str());
    } else if (key == "kind") {
      lua_pushstring(L, c->kind());
    } else if (key == "subordinate" && sub) {
      push_part(L, sub->subordinate());
    } else if (key == "superior" && sub) {
      push_part(L, sub->superior());
    } else if (key == "steps" && seq) {
      push_parts(L, seq->steps());
    } else if (key == "actions" && pol) {
      push_parts(L, pol->actions());
    } else if (key == "with" || key == "subject_to" || key == "param" || key == "params") {
      lua_getmetatable(L, 1);
      lua_getfield(L, -1, key.c_str());
    } else {
      // The parameter methods are a primitive's alone (found by a probe: a sequence's error
      // listed them, and calling one only said "only primitives have parameters").
      const bool primitive = std::dynamic_pointer_cast<const Primitive>(c) != nullptr;
      const std::string parts = sub ? "subordinate, superior, " : seq ? "steps, " : pol ? "actions, " : "";
      std::vector<std::string> known = {"name", "kind", "subject_to"};
      if (primitive) known.insert(known.end(), {"with", "param", "params"});
      if (sub) known.insert(known.end(), {"subordinate", "superior"});
      if (seq) known.push_back("steps");
      if (pol) known.push_back("actions");
      raise(L, controller_text(*c) + " has no field '" + key + "'" + suggestion(key, known) + "; it has name, kind, " +
                   parts +
                   (primitive ? "and the methods with{...}, subject_to(sup), param(name), params()"
                              : "and the method subject_to(sup) (the parameter methods with, param and params are "
                                "a primitive's)"));
    }
    return 1;
  });
}

// Controllers are values: changing one in place would change every composition holding it.
int l_controller_newindex(lua_State* L) {
  return luaL_error(L, "controllers cannot be changed in place; make a changed copy with c:with{...}");
}

// tostring(c): "controller 'phi4 <| phi2' (subject_to)".
int l_controller_tostring(lua_State* L) {
  const ControllerPtr& c = *static_cast<ControllerPtr*>(luaL_checkudata(L, 1, kControllerType));
  return lua_protect(L, [L, &c]() {
    lua_pushstring(L, controller_text(*c).c_str());
    return 1;
  });
}

// tostring(p): "predicate converged(phi3)".
int l_predicate_tostring(lua_State* L) {
  const PredicatePtr& p = *static_cast<PredicatePtr*>(luaL_checkudata(L, 1, kPredicateType));
  return lua_protect(L, [L, &p]() {
    const std::string text = "predicate " + p->describe();
    lua_pushstring(L, text.c_str());
    return 1;
  });
}

// Predicates have no fields: say what to do with them instead.
int l_predicate_index(lua_State* L) {
  return luaL_error(L, "a predicate has no fields; combine predicates with roger.all, roger.any, "
                    "roger.negate and roger.held");
}

}  // namespace lua_control_detail
}  // namespace roger
