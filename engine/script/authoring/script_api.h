// script_api.h: what each kind of script can reach, read from a live sandbox set up as that
// kind's loader sets it up. The API is described for editors and the linter in docs/api/*.lua;
// tests/test_lua_sandbox.cpp compares the two, and `roger check`'s static pass
// (lua_static_check.h) knows names from here.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "script/sandbox/lua_sandbox.h"

namespace roger {

enum class ScriptKind { kScenario, kSkillScript, kCurriculum, kBatchScript };

// Every kind, in the order above.
const std::vector<ScriptKind>& script_kinds();

// "scenario", "skill script", "curriculum", "batch script".
const char* script_kind_name(ScriptKind kind);

// The kind of a script file, told apart from its text alone as `roger check` does: a curriculum
// writes `stages`, a skill script returns `policies`, a batch script writes `runs`, `curriculum`
// or `evaluations`, a scenario `generate`. Nothing when none of them (a module, or a script that
// takes its table from another, such as `return require("paper")` with changes).
std::optional<ScriptKind> script_kind_of(const std::string& path);

// Installs into a fresh sandbox what the loader of `kind` installs before running the script.
void install_script_api(LuaSandbox& sandbox, ScriptKind kind);

// The names a script of `kind` reaches, from a live sandbox: every global, and every member of
// `roger` and of its sub-tables as a dotted path ("roger.shape", "roger.robot.base_radius").
// Values are true for tables (whose members are listed too). Without a kind: every kind's names.
std::map<std::string, bool> script_api_names(std::optional<ScriptKind> kind);

// What a module gave when run: its Lua type ("table", "function", ...) and, for a table, its keys
// (string keys as written, others as "[type]"), sorted.
struct ModuleValue {
  std::string type;
  std::vector<std::string> keys;
};

// Runs a module once in a fresh sandbox of `kind` with `limits`: through `require(name)` with
// `main_script` declared, as that script's sandbox runs it, or, without a name, as a main script.
// Throws ScriptError with the module's file:line.
ModuleValue run_module(const std::string& path, ScriptKind kind, const std::string& main_script,
                       const std::string& name, const SandboxLimits& limits);

}  // namespace roger
