// inspect.cpp: `roger render` (a picture of a world, or an episode of a skill script's policy)
// and `roger check` (a script validated without running an episode).
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "batch/trainer.h"
#include "cli/cli_internal.h"
#include "cli/commands.h"
#include "core/fileio.h"
#include "core/text.h"
#include "learn/episode.h"
#include "script/batch/batch_script.h"
#include "script/curriculum/curriculum.h"
#include "script/authoring/lua_static_check.h"
#include "script/authoring/script_api.h"
#include "script/scenario/scenario.h"
#include "script/skills/skill_script.h"
#include "sim/world.h"
#include "teach/teach.h"
#include "view/animation.h"
#include "view/render.h"

namespace roger {

void apply_sets(Scenario& scenario, const std::vector<std::string>& sets) {
  scenario.set_params(split_sets(sets, "--set"));
}

std::string policy_scenario(const SkillScript::NamedPolicy& p, const std::string& chosen) {
  if (!chosen.empty()) return chosen;
  return p.scenario.empty() ? "unobstructed" : p.scenario;
}

bool policy_is_saved_file(const std::string& script, const std::string& policy) {
  const bool json_file = policy.size() >= 5 && policy.compare(policy.size() - 5, 5, ".json") == 0;
  if (!is_curriculum_script(resolve_curriculum_path(script))) {
    if (json_file)
      throw Error("--policy " + policy + " is a saved policy, which runs with the curriculum it was trained on "
                  "(CURRICULUM.lua --policy FILE.json); " + script + " is not a curriculum, so --policy names one of "
                  "its policies");
    return false;
  }
  if (!json_file)
    throw Error("with a curriculum, --policy names a policy file written by roger train (policy.json), got '" +
                policy + "'");
  return true;
}

namespace {

// Writes a recorded episode: a folder with frames and a replay page, or (for a .png path) one
// summary strip; then says what it wrote.
void write_rendered_episode(const RenderArgs& a, const WorldSpec& spec, const EpisodeResult& episode,
                            const std::string& title) {
  AnimationOptions anim;
  anim.frame.width_px = a.width;
  anim.title = title;
  const bool summary = a.out.size() > 4 && a.out.compare(a.out.size() - 4, 4, ".png") == 0;
  if (summary) {
    render_episode_summary(spec, episode, a.out, anim);
  } else {
    render_episode(spec, episode, a.out, anim);
  }
  std::printf("wrote %s (%s after %.2f s, reward %.0f; %zu frames)\n", a.out.c_str(),
              episode.success ? "success" : "timeout", episode.sim_seconds, episode.reward,
              episode.frames.size());
}

// Renders the greedy episode of a policy saved by roger train (its curriculum is a.scenario).
int run_render_policy_file(const RenderArgs& a) {
  PolicyEvalOptions o;
  o.curriculum = a.scenario;
  o.policy_file = a.policy;
  o.scenario = a.world;
  o.sets = split_sets(a.sets, "--set");
  o.first_seed = int64_t(a.seed);
  for (const auto& [name, file] : split_sets(a.skills, "--skill")) o.skill_files[name] = file;
  if (a.test_task > 0 && a.seed_given)
    throw Error("roger render: --test-task runs the task in its own world seed; --seed cannot be given with it");
  o.test_task = a.test_task;
  o.trial_params = true;  // the trial's own parameters, as roger eval sets them
  const RecordedPolicyEpisode r = record_policy_episode(o, a.every);
  std::string task;
  if (a.test_task > 0) {
    task = params_text(r.about.test_tasks[size_t(a.test_task - 1)]);
    task = ", test task " + std::to_string(a.test_task) + " (" + (task.empty() ? "the stage's own parameters" : task) + ")";
  }
  const std::string trained = r.about.trial_sets.empty() ? "" : " with " + params_text(r.about.trial_sets);
  write_rendered_episode(a, r.spec, r.episode,
                         r.about.stage + "/" + r.about.context + " (" + a.policy + ") in " + r.about.scenario +
                             trained + ", seed " + std::to_string(r.episode.seed) + task);
  return 0;
}

// Renders one episode of a skill script's policy: a folder with frames and a replay page, or
// (for a .png path) one summary strip.
int run_render_episode(const RenderArgs& a) {
  if (policy_is_saved_file(a.scenario, a.policy)) return run_render_policy_file(a);
  if (a.test_task > 0)
    throw Error("roger render: --test-task renders a task of a saved policy's test set (CURRICULUM.lua --policy "
                "FILE.json); policy '" + a.policy + "' of " + a.scenario + " is a skill script's, which has none");
  if (!a.skills.empty())
    throw Error("roger render: --skill replaces a learned skill of a saved policy (--policy FILE.json); policy '" +
                a.policy + "' of " + a.scenario + " is a skill script's, which learns nothing");
  SkillScript script = SkillScript::load(a.scenario);
  const SkillScript::NamedPolicy& policy = script.policy(a.policy);
  Scenario scenario = Scenario::load(policy_scenario(policy, a.world));
  apply_sets(scenario, a.sets);
  const WorldSpec spec = scenario.generate(a.seed);
  EpisodeOptions options = policy.episode_options();
  options.record_every = a.every;
  // Watch the named controllers (primitives, skills), at most a dozen, so the timeline stays legible.
  std::vector<ControllerPtr> watch = script.controllers();
  if (watch.size() > 12) watch.resize(12);
  Agent agent;
  const EpisodeResult episode = run_episode(agent, spec, a.seed, *policy.action, *policy.goal, options, watch);
  write_rendered_episode(a, spec, episode,
                         script.name() + ": " + policy.name + " in " + scenario.name() + ", seed " + std::to_string(a.seed));
  return 0;
}

}  // namespace

int command_render(const RenderArgs& a) {
  if (!a.policy.empty()) return run_render_episode(a);
  if (!a.skills.empty()) throw Error("roger render: --skill needs --policy FILE.json (a policy saved by roger train)");
  Scenario scenario = Scenario::load(a.scenario);
  apply_sets(scenario, a.sets);
  const WorldSpec spec = scenario.generate(a.seed);
  World world;
  world.reset(spec);
  // Optionally let the world settle (Roger holds still) before the picture is taken.
  const int ticks = int(a.seconds / world.tick_seconds() + 0.5);
  for (int i = 0; i < ticks; ++i) world.tick();
  RenderOptions options;
  options.width_px = a.width;
  options.show_grid = a.grid;
  render_frame(spec, world.frame(), a.out, options);
  std::printf("wrote %s (%s, seed %llu)\n", a.out.c_str(), a.scenario.c_str(),
              static_cast<unsigned long long>(a.seed));
  return 0;
}

namespace {

// roger check on a batch script: loads it and validates it against its curriculum. `shown`: the
// script as the command line named it.
int check_batch(const std::string& path, const std::string& shown, const LuaLimitArgs& lua) {
  BatchOverrides overrides;
  overrides.instructions = lua.instructions;
  overrides.memory_mib = lua.memory_mib;
  const BatchScript b = load_batch_script(path, overrides);
  std::string runs;
  for (const auto& r : b.runs) {
    const size_t n = r.contexts.size();
    runs += (runs.empty() ? "" : ", ") + r.name + " (" + std::to_string(n) + (n == 1 ? " context)" : " contexts)");
  }
  const SandboxLimits defaults;
  std::string limits;
  if (b.limits.instructions != defaults.instructions || b.limits.memory_bytes != defaults.memory_bytes)
    limits = "; Lua limits " + std::to_string(b.limits.instructions) + " instructions, " +
             std::to_string(b.limits.memory_bytes >> 20) + " MiB";
  std::printf("%s: ok (batch script '%s' on %s; %d trial%s; runs %s%s)\n", shown.c_str(), b.name.c_str(),
              b.curriculum.c_str(), b.trials, b.trials == 1 ? "" : "s", runs.c_str(), limits.c_str());
  return 0;
}

}  // namespace

namespace {

// The static pass (a misspelt roger.* member, an undefined global), before anything runs: prints
// each problem as file:line and returns their number. A bare name is the scenario it names, as
// for the loader below (scenarios/<name>.lua of the project or the installed tree); a name that
// is neither is left to the loader, which says what exists.
size_t report_static_problems(const std::string& script) {
  std::string path;
  try {
    path = resolve_scenario_path(script);
  } catch (const Error&) {
    return 0;
  }
  const std::vector<StaticProblem> problems = static_check(path, script_kind_of(path));
  for (const auto& p : problems) std::fprintf(stderr, "roger: error: %s\n", p.what().c_str());
  return problems.size();
}

}  // namespace

namespace {

// The file `roger check` checks: the path as given, else a path relative to the project (as the
// other commands take `curricula/paper.lua` from any folder), else a bare name of the project's
// scenarios/ (first, as check has always read a bare name), curricula/ or scripts/. A name that is
// none of them is refused as a script of any kind, not as a missing scenario.
std::string check_target(const std::string& arg) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(arg, ec)) return arg;
  if (arg.find('/') != std::string::npos) {
    if (fs::path(arg).is_relative() && fs::is_regular_file(project_root() / arg, ec))
      return (project_root() / arg).string();
    return arg;  // a path (read_file_text and the loaders say what is wrong with it)
  }
  const std::string file = fs::path(arg).extension() == ".lua" ? arg : arg + ".lua";
  for (const char* folder : {"scenarios", "curricula", "scripts"})
    if (fs::is_regular_file(project_root() / folder / file, ec)) return (project_root() / folder / file).string();
  throw Error("no script '" + arg + "': not a file here, and the project has no scenarios/" + file + ", curricula/" +
              file + " or scripts/" + file);
}

// The kind a script whose table names none of the keys that tell kinds apart (a misspelt
// `stagez`, `policy`) is checked as, so that the loader says which field is unknown, with the
// nearest one: a curriculum when it builds stages, a skill script when it builds controllers, else
// a scenario, as before.
std::optional<ScriptKind> guessed_kind(const std::string& path) {
  const std::string text = read_file_text(path);
  if (text.find("roger.stage") != std::string::npos) return ScriptKind::kCurriculum;
  for (const char* builder : {"lib.skills", "roger.primitive", "roger.sequence", "roger.compose", "roger.subject_to"})
    if (text.find(builder) != std::string::npos) return ScriptKind::kSkillScript;
  return std::nullopt;
}

}  // namespace

int command_check(const CheckArgs& args) {
  CheckArgs a = args;
  a.script = check_target(args.script);
  if (report_static_problems(a.script) > 0) return 1;
  const SandboxLimits limits = sandbox_limits(a.lua);
  if (!script_kind_of(a.script)) {  // its loader throws what is unknown, with the nearest field
    const std::optional<ScriptKind> guess = guessed_kind(a.script);
    if (guess == ScriptKind::kCurriculum) Curriculum::load(a.script, limits);
    if (guess == ScriptKind::kSkillScript) SkillScript::load(a.script, limits);
  }
  if (is_curriculum_script(a.script)) {
    const std::vector<std::string> problems = check_curriculum(a.script, limits);
    for (const auto& p : problems) std::fprintf(stderr, "roger: error: %s\n", p.c_str());
    if (!problems.empty()) return 1;
    const Curriculum cur = Curriculum::load(a.script, limits);
    std::string stages;
    for (const auto& st : cur.stages()) {
      std::string contexts;
      for (const auto& c : st.contexts) contexts += (contexts.empty() ? "" : " ") + c.name;
      stages += (stages.empty() ? "" : "; ") + st.name + ": " + contexts;
    }
    std::printf("%s: ok (curriculum '%s'; stages %s)\n", args.script.c_str(), cur.name().c_str(), stages.c_str());
    return 0;
  }
  if (is_skill_script(a.script)) {
    const std::vector<std::string> problems = check_skill_script(a.script, limits);
    for (const auto& p : problems) std::fprintf(stderr, "roger: error: %s\n", p.c_str());
    if (!problems.empty()) return 1;
    const SkillScript script = SkillScript::load(a.script, limits);
    std::string names;
    for (const auto& n : script.policy_names()) names += (names.empty() ? "" : ", ") + n;
    std::printf("%s: ok (skill script '%s'; policies: %s)\n", args.script.c_str(), script.name().c_str(),
                names.c_str());
    return 0;
  }
  if (is_batch_script(a.script)) return check_batch(a.script, args.script, a.lua);
  Scenario scenario = Scenario::load(a.script, limits);
  apply_sets(scenario, a.sets);
  // A scenario is a function of its seed: try several, and build each world as an episode would.
  World world;
  // A failure names its seed after the first line, as training does: it may hold for some seeds only.
  for (int seed = 0; seed < a.seeds; ++seed) {
    try {
      world.reset(scenario.generate(uint64_t(seed)));
    } catch (const std::exception& e) {
      throw Error(with_note_on_first_line(e.what(), " (world seed " + std::to_string(seed) + ")"));
    }
  }
  // Without --set, also every declared choice of every parameter (each shape, say), and each end
  // of every declared range (the most obstacles, the longest arm): those are warnings, since an
  // end may hold only with other parameters changed too.
  std::vector<std::string> range_ends;
  if (a.sets.empty()) {
    const std::vector<std::string> problems = check_scenario(a.script, 2, limits, &range_ends);
    if (!problems.empty()) {
      for (const auto& p : problems) std::fprintf(stderr, "roger: error: %s\n", p.c_str());
      return 1;
    }
    for (const auto& w : range_ends)  // the message without Lua's traceback: the value and the line say it
      std::fprintf(stderr, "roger: warning: at a range's end: %s\n", w.substr(0, w.find("\nstack traceback:")).c_str());
  }
  std::string tried;
  if (a.sets.empty())
    tried = ", every parameter choice and range end tried" +
            (range_ends.empty() ? std::string() : "; " + std::to_string(range_ends.size()) +
                                                      " range end(s) could not be built (warnings above)");
  std::printf("%s: ok (scenario '%s', %d seeds generated and built%s)\n", args.script.c_str(),
              scenario.name().c_str(), a.seeds, tried.c_str());
  return 0;
}

}  // namespace roger
