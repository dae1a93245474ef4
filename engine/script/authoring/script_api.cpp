// script_api.cpp: the API of each kind of script, from a live sandbox (script_api.h).
#include "script/authoring/script_api.h"

#include <algorithm>

#include <lua.hpp>

#include "script/batch/batch_script.h"
#include "script/curriculum/curriculum.h"
#include "script/control/lua_control.h"
#include "script/scenario/scenario.h"
#include "script/skills/skill_script.h"

namespace roger {
namespace {

// Adds the string keys of the table at the top of the stack under `prefix`, descending into
// sub-tables of `roger` (the global table itself is listed one level deep).
void list_table(lua_State* L, const std::string& prefix, bool descend, std::map<std::string, bool>& out) {
  lua_pushnil(L);
  while (lua_next(L, -2) != 0) {
    if (lua_type(L, -2) == LUA_TSTRING) {
      const std::string name = prefix + lua_tostring(L, -2);
      const bool table = lua_istable(L, -1);
      out[name] = table;
      if (table && (descend || name == "roger")) {
        const bool view = lua_push_view_data(L, -1);  // a read-only table's fields are its data's
        list_table(L, name + ".", true, out);
        if (view) lua_pop(L, 1);
      }
    }
    lua_pop(L, 1);
  }
}

}  // namespace

const std::vector<ScriptKind>& script_kinds() {
  static const std::vector<ScriptKind> kinds{ScriptKind::kScenario, ScriptKind::kSkillScript,
                                             ScriptKind::kCurriculum, ScriptKind::kBatchScript};
  return kinds;
}

const char* script_kind_name(ScriptKind kind) {
  switch (kind) {
    case ScriptKind::kScenario: return "scenario";
    case ScriptKind::kSkillScript: return "skill script";
    case ScriptKind::kCurriculum: return "curriculum";
    case ScriptKind::kBatchScript: return "batch script";
  }
  return "script";
}

std::optional<ScriptKind> script_kind_of(const std::string& path) {
  const std::string kind = script_kind(path);  // the one decision (script/batch/batch_script.h)
  for (ScriptKind k : script_kinds())
    if (kind == script_kind_name(k)) return k;
  return std::nullopt;
}

void install_script_api(LuaSandbox& sandbox, ScriptKind kind) {
  switch (kind) {
    case ScriptKind::kScenario: install_scenario_api(sandbox); break;
    case ScriptKind::kSkillScript: install_control_api(sandbox); break;
    case ScriptKind::kCurriculum: install_curriculum_api(sandbox); break;
    case ScriptKind::kBatchScript: break;  // the plain sandbox
  }
}

std::map<std::string, bool> script_api_names(std::optional<ScriptKind> kind) {
  std::map<std::string, bool> out;
  for (ScriptKind k : script_kinds()) {
    if (kind && k != *kind) continue;
    LuaSandbox sandbox;
    install_script_api(sandbox, k);
    lua_State* L = sandbox.state();
    LuaStackGuard guard(L);
    lua_pushglobaltable(L);
    list_table(L, "", false, out);
  }
  return out;
}

ModuleValue run_module(const std::string& path, ScriptKind kind, const std::string& main_script,
                       const std::string& name, const SandboxLimits& limits) {
  LuaSandbox sandbox(limits);
  install_script_api(sandbox, kind);
  lua_State* L = sandbox.state();
  LuaStackGuard guard(L);
  if (name.empty()) {
    sandbox.run_file(path, 1);
  } else {
    sandbox.set_main_script(main_script);
    lua_getglobal(L, "require");
    lua_pushstring(L, name.c_str());
    sandbox.call(1, 1);
  }
  ModuleValue out{luaL_typename(L, -1), {}};
  if (!lua_istable(L, -1)) return out;
  lua_pushnil(L);
  while (lua_next(L, -2)) {
    lua_pop(L, 1);
    out.keys.push_back(lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1)
                                                       : "[" + std::string(luaL_typename(L, -1)) + "]");
  }
  std::sort(out.keys.begin(), out.keys.end());
  return out;
}

}  // namespace roger
