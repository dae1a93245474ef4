// lua_static_check.h: `roger check`'s static pass, run before anything of a script runs. Reads the
// source (and the modules it requires by a literal name) without compiling it, and reports at
// file:line
//   - a `roger.` member the script's kind does not have (roger.sequnce), with the nearest names,
//     also through a local or upvalue holding roger itself (local R = roger; R.sequnce);
//   - a read of a global that neither the sandbox nor any of those files defines (a misspelt
//     local, print written pirnt, `local pirnt = pirnt`: a local is in scope only after its
//     statement's expression list);
//   - a string literal compared (== or ~=) with a value of a closed vocabulary, near one of its
//     words but none of them, so never equal: with an index expression (state.phi3, s[name]), a
//     controller's state ("conv" for "CONV"); with `event` or a function's third parameter, a
//     reward function's event ("timout" for "timeout"). Only where a curriculum's callbacks may
//     be (a curriculum, or a file of no known kind), and not for a literal the file also writes
//     as a value (a parameter's choice), which what is compared may hold;
//   - a predicate made in place (roger.converged(c), roger.all{...}, ...) that and, or or not takes
//     for a truth value: Lua takes any predicate for true, so `roger.converged(a) and
//     roger.converged(b)` is the second alone (roger.all{...} is meant), an `or` the first alone
//     and a `not` false.
// Names come from a live sandbox of the script's kind (script_api.h). Scoping is followed as Lua
// does (locals of blocks, functions, loops, parameters, `local function`), so a sound script
// yields nothing; what the pass cannot see (a name built at run time) it does not report.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "script/authoring/script_api.h"

namespace roger {

// One finding: what() is "file:line: message", or "file: message" for one of no line (Lua's "C
// stack overflow" of a file nested past its compiler's limit names none).
struct StaticProblem {
  std::string file;  // as shown to the user
  int line = 0;
  std::string message;
  std::string what() const { return file + (line > 0 ? ":" + std::to_string(line) : "") + ": " + message; }
};

// Checks a script file as a script of `kind` (without one, against every kind's names), and every
// module it requires by a literal name that the sandbox would find. Problems are in file order,
// then line order.
// With `warnings`, also a warning for each module of the script's own folder that a shipped library
// (a file of the project's folders) requires in place of the shipped module of that name, and
// ("file:line: ...") for each global assigned inside a function that nothing assigns outside one
// (a `local` forgotten: its value outlives the call).
std::vector<StaticProblem> static_check(const std::string& path, std::optional<ScriptKind> kind,
                                        std::vector<std::string>* warnings = nullptr);

// The same over source text (shown as `shown`), without following requires.
std::vector<StaticProblem> static_check_text(const std::string& text, const std::string& shown,
                                             std::optional<ScriptKind> kind);

// The script at `path` and every module it requires by a literal name that the sandbox would load,
// and theirs in turn, each once, in the order found (the files static_check reads).
std::vector<std::filesystem::path> required_files(const std::string& path);

// A script that requires a module by a literal name: the script, the name, the line of the first
// such require.
struct ModuleUse {
  std::filesystem::path script;
  std::string name;
  int line = 0;
};

// The scripts among `scripts` that require `module` by a literal name that the sandbox's require
// would resolve to it were each the main script (its folder first, then the project's), in the
// order given. A module that requires it counts too.
std::vector<ModuleUse> module_users(const std::filesystem::path& module, const std::vector<std::filesystem::path>& scripts);

// The names nearest to `name` among `known` (edits, a swap of two neighbours counting as one, at
// most a third of its length and at least 1), nearest first, at most three.
std::vector<std::string> nearest_names(const std::string& name, const std::vector<std::string>& known);

}  // namespace roger
