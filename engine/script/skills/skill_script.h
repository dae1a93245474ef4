// skill_script.h: skill scripts, Lua files (curricula/*.lua) that build controllers with the
// control-basis API (lua_control.h) and return named policies to run:
//
//   return {
//     name = "scripted", description = "...",
//     policies = {
//       task = { action = controller, goal = predicate, time_limit = 10,
//                scenario = "unobstructed", params = { obstacles = 2 }, description = "..." },
//       ...
//     },
//   }
//
// Loading runs the script once, binds the names it used before defining them, rejects skills that
// contain themselves and validates every policy, with errors at the script's file:line. The Lua
// state is closed when load() returns: the policies are plain C++ controllers and predicates, so
// running an episode never calls Lua. docs/control.md is the reference.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "control/control.h"
#include "script/sandbox/lua_sandbox.h"
#include "script/scenario/scenario.h"
#include "control/predicate.h"
#include "learn/episode.h"

namespace roger {

class SkillScript {
 public:
  // One runnable policy: an action, the goal that ends an episode in success, and its limits.
  struct NamedPolicy {
    std::string name;
    ControllerPtr action;
    PredicatePtr goal;
    double time_limit = 0.0;    // simulated seconds
    double time_per_object = 0.0;  // simulated seconds per object of the world, added to time_limit
    // The options an episode of this policy runs with (its time limit).
    EpisodeOptions episode_options() const {
      EpisodeOptions o;
      o.time_limit = time_limit;
      o.time_per_object = time_per_object;
      return o;
    }
    std::string scenario;       // the scenario evaluations use by default ("unobstructed")
    // Scenario parameters its episodes run with, over the scenario's defaults ({objects = 4}: a
    // policy for a known number of objects); --set overrides them. As text, sorted by name.
    std::vector<std::pair<std::string, std::string>> params;
    std::string description;
    int goal_line = 0;          // where its goal is written in the script (for errors of the goal)
    int params_line = 0;        // where its params are written
  };

  // Runs the script at `path` (or curricula/<path>.lua for a bare name such as "scripted") and
  // validates what it returns. Throws ScriptError (file:line) or roger::Error.
  static SkillScript load(const std::string& path, const SandboxLimits& limits = {});

  SkillScript(SkillScript&&) noexcept;
  SkillScript& operator=(SkillScript&&) noexcept;
  ~SkillScript();

  // The script's name (its `name` field, or the file name without .lua).
  const std::string& name() const;
  // Its description ("" when none).
  const std::string& description() const;
  // The script as shown in messages.
  const std::string& path() const;

  // The policies' names, sorted.
  std::vector<std::string> policy_names() const;

  // A policy by name. Throws roger::Error listing the known names for an unknown one.
  const NamedPolicy& policy(const std::string& name) const;

  // The scenario a policy's episodes run in: `chosen` (a --scenario) or the policy's own, with the
  // policy's params set. A param the scenario refuses is a ScriptError at the policy's params line.
  Scenario scenario_of(const NamedPolicy& policy, const std::string& chosen = "",
                       const SandboxLimits& limits = {}) const;

  // Every controller the script defines or its policies use, each once: the named ones in the
  // order they were defined, then the others as the policies reach them (policies by name, each
  // depth first). For watching gammas in pictures. Name stand-ins are looked through.
  std::vector<ControllerPtr> controllers() const;

 private:
  SkillScript();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The file a skill-script argument names: the path itself if it is a file, else
// <project>/curricula/<name>.lua for a bare name. Throws roger::Error listing the scripts in
// curricula/ when neither exists.
std::string resolve_skill_script_path(const std::string& name_or_path);

// Whether the file looks like a skill script rather than a scenario: the table it returns is
// written with a `policies` field. Reads the source text only (runs nothing); false when the file
// cannot be read. For `roger check`, to pick the loader.
bool is_skill_script(const std::string& path);

// For `roger check`: loads a skill script and checks that each policy's scenario loads and
// generates the worlds of seeds 0..19, and that each policy runs its first ticks (0.1 s) in the
// world of seed 0, its goal evaluated there. Returns the problems found (empty when sound), each a complete message with
// file:line where known. `loaded` (may be null) receives the script when it loaded, so that a
// caller need not run it again (its prints would show twice). `sets` (roger check's --set) are set
// on each policy's scenario that declares them, as `roger eval` takes them; one that no policy's
// scenario declares is a problem.
std::vector<std::string> check_skill_script(const std::string& path, const SandboxLimits& limits = {},
                                            std::optional<SkillScript>* loaded = nullptr,
                                            const std::vector<std::pair<std::string, std::string>>& sets = {});

}  // namespace roger
