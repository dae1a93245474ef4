// learn_commands.cpp: `roger eval` (a policy over seeded episodes) and `roger train` (one trial).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/explain.h"
#include "batch/trainer.h"
#include "cli/cli_internal.h"
#include "cli/commands.h"
#include "core/error.h"
#include "core/fileio.h"
#include "core/interrupt.h"
#include "core/text.h"
#include "learn/episode.h"
#include "script/curriculum/curriculum.h"
#include "script/scenario/scenario.h"
#include "script/skills/skill_script.h"
#include "sim/world_model.h"
#include "teach/teach.h"

namespace roger {

int64_t saved_policy_first_seed(const char* command, uint64_t seed) {
  if (seed > uint64_t(INT64_MAX))
    throw Error(std::string(command) + ": --seed " + std::to_string(seed) + ": a saved policy's episodes take a first "
                "seed of at most " + std::to_string(INT64_MAX));
  return int64_t(seed);
}

std::vector<std::pair<std::string, std::string>> split_sets(const std::vector<std::string>& sets, const char* option) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const std::string& kv : sets) {
    const size_t eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) throw Error(std::string(option) + " expects key=value, got '" + kv + "'");
    std::pair<std::string, std::string> set{kv.substr(0, eq), kv.substr(eq + 1)};
    // A blank beside '=' (--set "obstacles = 2", quoted as one word) was read as the key
    // 'obstacles ' that no scenario has, or the value ' 2': say how to write it.
    const auto blank = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
    const bool key_blank = std::any_of(set.first.begin(), set.first.end(), blank);
    if (key_blank || (!set.second.empty() && (blank(set.second.front()) || blank(set.second.back())))) {
      std::string key = set.first, value = set.second;
      key.erase(std::remove_if(key.begin(), key.end(), blank), key.end());
      value.erase(0, value.find_first_not_of(" \t"));
      value.erase(value.find_last_not_of(" \t") + 1);
      throw Error(std::string(option) + " '" + kv + "': a key=value takes no blanks around '=' or at its ends; write " +
                  option + " " + key + "=" + value);
    }
    // A key given twice with two values is a mistake in the command (which one the run used would
    // show only in its manifest), not an override: refused, naming both.
    const auto same_key = std::find_if(out.begin(), out.end(), [&](const auto& o) { return o.first == set.first; });
    if (same_key == out.end()) {
      out.push_back(std::move(set));
    } else if (same_key->second != set.second) {
      throw Error(std::string(option) + " " + set.first + " is given twice, as '" + same_key->second + "' and as '" +
                  set.second + "': give it once");
    }
  }
  return out;
}

SandboxLimits sandbox_limits(const LuaLimitArgs& lua) {
  SandboxLimits limits;
  if (lua.instructions > 0) limits.instructions = lua.instructions;
  if (lua.memory_mib > 0) limits.memory_bytes = size_t(lua.memory_mib) << 20;
  return limits;
}

// See cli_internal.h. Found by a probe: a colour typo in a scenario showed only as every episode
// failing, blamed on the stage's absorbing function.
std::string stimulus_unseen_in(const std::string& scenario, const ParamList& params, const SandboxLimits& limits,
                               uint64_t first_seed, int worlds, const ParamList& where_declared) {
  try {
    Scenario s = Scenario::load(scenario, limits);
    for (const auto& [k, v] : params) s.set_param(k, v);
    const std::vector<ScenarioParam> declared = s.params();
    for (const auto& [k, v] : where_declared)
      if (std::any_of(declared.begin(), declared.end(), [&k = k](const ScenarioParam& p) { return p.name == k; }))
        s.set_param(k, v);
    QuietPrints prints(s.sandbox(), "roger looked for the stimulus colour in the worlds");
    prints.quiet();
    return stimulus_unseen_note(s, first_seed, worlds);
  } catch (const std::exception&) {
    return "";
  }
}

// "eye_pixels = 32, overridden by --set eye_pixels=128": parameters, each one a --set of `sets`
// replaced with another value marked so (found by a probe: the line read as if the coarse eyes were
// in force), and each one a saved policy's trial set otherwise (`trial`, set here too) marked as
// that (found by a newcomer: eval said obstacles = 0 of a policy trained, and evaluated, with 2).
std::string params_marking_sets(const std::vector<std::pair<std::string, std::string>>& params,
                                const std::vector<std::string>& sets,
                                const std::vector<std::pair<std::string, std::string>>& trial) {
  std::string text;
  for (const auto& [name, value] : params) {
    text += (text.empty() ? "" : ", ") + name + " = " + value;
    bool by_set = false;
    for (const std::string& set : sets)
      if (set.rfind(name + "=", 0) == 0) {
        by_set = true;
        if (set.substr(name.size() + 1) != value) text += ", overridden by --set " + set;
      }
    if (by_set) continue;
    for (const auto& [trial_name, trial_value] : trial)
      if (trial_name == name && trial_value != value)
        text += ", overridden by the trial's own " + name + " = " + trial_value;
  }
  return text;
}

namespace {

// Which worlds failed, the first few of them (all in --json), and the roger render command that
// replays one: the same script, policy, scenario, parameters and skills, at that world seed, and
// the parameters of its test task (`task`, with --test-set).
void print_failed_seeds(const EvalArgs& a, const std::vector<uint64_t>& failed,
                        const std::vector<std::pair<std::string, std::string>>& task = {}) {
  if (failed.empty()) return;
  const size_t shown = std::min<size_t>(failed.size(), 10);
  std::string seeds;
  for (size_t i = 0; i < shown; ++i) seeds += (i ? ", " : "") + std::to_string(failed[i]);
  if (failed.size() > shown) seeds += ", ... (" + std::to_string(failed.size() - shown) + " more; all in --json)";
  std::printf("  failed seeds   %s\n", seeds.c_str());
  std::string command = "roger render " + shell_word(a.script) + " --policy " + shell_word(a.policy);
  if (!a.scenario.empty()) command += " --scenario " + shell_word(a.scenario);
  for (const auto& s : a.sets) command += " --set " + shell_word(s);
  for (const auto& [k, v] : task) command += " --set " + shell_word(k + "=" + v);
  for (const auto& s : a.skills) command += " --skill " + shell_word(s);
  const std::string seed = std::to_string(failed.front());
  command += " --seed " + seed + " --out episode-" + seed;
  std::printf("  replay one     %s\n", command.c_str());
}

// The command line's changes to the evaluated worlds and skills, on a line of their own: a run on
// another body or over a retrained skill must not read as the default run.
void print_changes(const EvalArgs& a) {
  std::string changes;
  // Each once, as split_sets takes a repeated one (found by a probe: the line showed it twice).
  for (const auto& [k, v] : split_sets(a.sets, "--set")) changes += (changes.empty() ? "" : ", ") + ("--set " + k + "=" + v);
  for (const auto& [k, v] : split_sets(a.skills, "--skill"))
    changes += (changes.empty() ? "" : ", ") + ("--skill " + k + "=" + v);
  if (!changes.empty()) std::printf("  with           %s\n", changes.c_str());
}

using Params = std::vector<std::pair<std::string, std::string>>;


// The stage's and context's own scenario parameters, when they have any (found by a probe: a
// maturation's frozen eyes were said nowhere in train's or eval's output).
void print_stage_params(const Params& params, const std::string& stage, const std::string& context,
                        const std::vector<std::string>& sets, const Params& trial = {}) {
  if (!params.empty())
    std::printf("  stage params   %s (stage %s, context %s)\n", params_marking_sets(params, sets, trial).c_str(),
                stage.c_str(), context.c_str());
}

// What eval says of a saved policy beside the header: the stage's own parameters, another
// curriculum than the policy's, and the parameters its trial trained with beyond its stage's (its
// --set), set here too so that the held-out seeds are the trial's worlds, or, in another scenario,
// left out.
void print_trial_params(const PolicyEvalResult& r, const std::string& scenario, const std::vector<std::string>& sets) {
  print_stage_params(r.stage_params, r.stage, r.context, sets, r.trial_sets);
  if (!r.scenario_note.empty()) std::printf("  note           %s\n", r.scenario_note.c_str());
  if (!r.curriculum_note.empty()) std::printf("  note           %s\n", r.curriculum_note.c_str());
  if (!r.trial_sets.empty())
    std::printf("  trained with   %s (the trial's own parameters, set here too; a --set of one overrides it)\n",
                params_text(r.trial_sets).c_str());
  // Found by a probe: a policy run on another body by --set lost the body it trained on from the output.
  if (!r.trial_sets_overridden.empty())
    std::printf("  trained with   %s (the trial's own parameters, not in force here)\n",
                params_marking_sets(r.trial_sets_overridden, sets).c_str());
  if (!r.trial_sets_left.empty())
    std::printf("  note           %s\n", trial_params_left_note(r.trial_sets_left, r.trial_sets_left_declared, scenario).c_str());
}

// eval --policy FILE.json: what to evaluate, from the command line.
PolicyEvalOptions policy_eval_options(const EvalArgs& a) {
  PolicyEvalOptions o;
  o.curriculum = a.script;
  o.policy_file = a.policy;
  o.scenario = a.scenario;
  o.sets = split_sets(a.sets, "--set");
  // Not given: the stage's final evaluation's count (found by a probe: a stage of 20 final episodes
  // was evaluated on 50, which did not reproduce the trial's figures as the docs say).
  o.episodes = a.episodes_given ? a.episodes : 0;
  o.first_seed = a.seed_given ? saved_policy_first_seed("roger eval", a.seed) : -1;
  for (const auto& [name, file] : split_sets(a.skills, "--skill")) o.skill_files[name] = file;
  o.limits = sandbox_limits(a.lua);
  if (a.test_set && (a.seed_given || a.episodes_given))
    throw Error(std::string("roger eval: --test-set runs the test set's own tasks on its own world seeds; ") +
                (a.seed_given ? "--seed" : "--episodes") + " cannot be given with it");
  o.test_set = a.test_set;
  o.trial_params = true;
  return o;
}

// When no episode succeeded under a stage's Lua absorbing function: that it never returned true,
// with the names the worlds have (found by a probe: a judge looking for "blue ball" in a world
// without one gave 0% in another scenario and said nothing, where training's why lines say it).
// "" otherwise, or when the world cannot be made here.
std::string lua_judge_never_note(const EvalArgs& a, const PolicyEvalResult& r) {
  if (r.eval.successes > 0 || r.eval.episodes == 0) return "";
  try {
    const SandboxLimits limits = sandbox_limits(a.lua);
    if (!Curriculum::load(a.script, limits).stage(r.stage).absorbing_lua) return "";
    Scenario s = Scenario::load(r.scenario_file, limits);
    for (const auto& [k, v] : r.params) s.set_param(k, v);
    QuietPrints prints(s.sandbox(), "roger looked at the worlds' names");
    prints.quiet();
    const WorldSpec w = s.generate(r.eval.first_seed);
    std::vector<std::string> objects, regions;
    for (const auto& o : w.objects) objects.push_back("'" + o.name + "'");
    for (const auto& g : w.goals) regions.push_back("'" + g.name + "'");
    return "the stage's Lua absorbing function returned true in none of the " + counted(r.eval.episodes, "episode") +
           ": what it compares (a name, a region) may be written otherwise than these worlds' (the first's objects: " +
           (objects.empty() ? "none" : join(objects)) + "; its regions: " + (regions.empty() ? "none" : join(regions)) +
           ")";
  } catch (const std::exception&) {
    return "";
  }
}

// "from FILE", and the curriculum it was learned in when that is another (or this one before an
// edit: found by a probe, a skill from another curriculum was used without a word).
static std::string skill_file_origin(const SkillSource& s) {
  if (s.trained_curriculum.empty()) return "from " + s.file;
  return "from " + s.file + ", learned in " +
         (s.trained_curriculum_edited ? "an earlier version of " + s.trained_curriculum
                                      : "the curriculum " + s.trained_curriculum) +
         " (its actions run here as this curriculum defines them)";
}

// The body parameters (body_param_values) of the first world of `scenario_file` with `params`, as
// text, for a skill's note when the scenario does not declare them; none when it cannot be built.
static ParamList first_world_body(const std::string& scenario_file, const ParamList& params, const SandboxLimits& limits,
                                  uint64_t seed) {
  ParamList out;
  try {
    Scenario s = Scenario::load(scenario_file, limits);
    for (const auto& [k, v] : params) s.set_param(k, v);
    QuietPrints prints(s.sandbox(), "roger looked at the world's body");
    prints.quiet();
    for (const auto& [name, value] : body_param_values(s.generate(seed))) out.push_back({name, format_number(value)});
  } catch (const std::exception&) {
    out.clear();
  }
  return out;
}

// "; trained with upper_arm = 0.7 (here 0.5)": the scenario parameters a skill's policy records
// (its trial's, policy.json's extra.params) that differ from this run's, "" when none does (found
// by a probe: a skill learned on another body was used without a word). A body parameter this
// run's scenario does not declare is compared with its world's body (`body_here`), "here 0.16, the
// scenario's own body" (found by a probe: a scenario building its own body said nothing).
static std::string skill_params_note(const SkillSource& s, const ParamList& run, const ParamList& body_here = {}) {
  if (!s.policy.is_object() || !s.policy.contains("extra") || !s.policy["extra"].is_object()) return "";
  const nlohmann::json params = s.policy["extra"].value("params", nlohmann::json::object());
  if (!params.is_object()) return "";
  std::string theirs, here, own_theirs, own_here;
  for (const auto& [name, value] : run) {
    const auto it = params.find(name);
    if (it == params.end() || !it->is_string() || it->get<std::string>() == value) continue;
    theirs += (theirs.empty() ? "" : ", ") + name + " = " + it->get<std::string>();
    here += (here.empty() ? "" : ", ") + value;
  }
  for (const auto& [name, value] : body_here) {
    const auto it = params.find(name);
    const bool declared = std::any_of(run.begin(), run.end(), [&n = name](const auto& p) { return p.first == n; });
    if (declared || it == params.end() || !it->is_string()) continue;
    char* end = nullptr;
    const std::string trained = it->get<std::string>();
    const double v = std::strtod(trained.c_str(), &end);
    if (*end != '\0' || format_number(v) == value) continue;
    own_theirs += (own_theirs.empty() ? "" : ", ") + name + " = " + trained;
    own_here += (own_here.empty() ? "" : ", ") + value;
  }
  std::string note;
  if (!theirs.empty()) note += "; trained with " + theirs + " (here " + here + ")";
  if (!own_theirs.empty())
    note += "; trained with " + own_theirs + " (here " + own_here + ", the scenario's own body, which no parameter sets)";
  return note;
}

// The episodes that succeeded at the first tick, when the goal is first judged: it held from the
// start (found by a probe: such a goal read as 100% success, where roger train warns of it).
void print_first_tick_warning(int at_first_tick, int episodes) {
  if (at_first_tick > 0)
    std::printf("  warning        %d of %s succeeded at the first tick, when the goal is first judged: it held "
                "in their worlds from the start, so they show nothing of the policy (check the goal against its "
                "worlds)\n", at_first_tick, counted(episodes, "episode").c_str());
}

// eval --policy FILE.json: what the evaluation found, as text.
void print_policy_eval(const EvalArgs& a, const PolicyEvalResult& r, const std::string& stimulus_unseen) {
  std::printf("roger eval: %s stage %s context %s (%s) in %s, %s from seed %llu, %s\n", a.script.c_str(),
              r.stage.c_str(), r.context.c_str(), a.policy.c_str(), r.scenario.c_str(),
              counted(r.eval.episodes, a.test_set ? "test task" : "episode").c_str(),
              static_cast<unsigned long long>(r.eval.first_seed),
              r.time_limit.c_str());
  print_changes(a);
  print_trial_params(r, a.scenario, a.sets);
  // A skill given by --skill that learned on another body says so, as roger train does (found by a
  // probe: eval said nothing).
  const bool given = std::any_of(r.skills.begin(), r.skills.end(), [](const SkillSource& s) { return !s.embedded; });
  const ParamList body_here =
      given ? first_world_body(r.scenario_file, r.params, sandbox_limits(a.lua), r.eval.first_seed) : ParamList();
  for (const SkillSource& s : r.skills)
    if (!s.embedded)
      if (const std::string note = skill_params_note(s, r.params, body_here);
          !note.empty() || !s.trained_curriculum.empty())
        std::printf("  skill %-9s %s%s\n", s.name.c_str(), skill_file_origin(s).c_str(), note.c_str());
  if (r.stage_test_tasks > 0 && !a.test_set)
    std::printf("  note           stage %s teaches: its trials ended on %d test tasks of its task space, not run here "
                "(--test-set runs them; these episodes have the stage's own parameters%s)\n",
                r.stage.c_str(), r.stage_test_tasks, a.sets.empty() ? "" : " and the --set ones");
  if (a.test_set && r.test_set_changed)
    std::printf("  note           the curriculum's test set for stage %s is no longer the one this policy's trial "
                "ended on; these are that trial's %zu tasks, as %s keeps them\n",
                r.stage.c_str(), r.test_tasks.size(), r.test_set_source.c_str());
  else if (a.test_set)
    std::printf("  test set       from %s\n", r.test_set_source.c_str());
  std::printf("  success rate   %.1f%% (%d of %d)\n", 100.0 * r.eval.success_rate, r.eval.successes, r.eval.episodes);
  const size_t first_failed = r.eval.failed_seeds.empty() ? 0 : size_t(r.eval.failed_seeds.front() - r.eval.first_seed);
  print_failed_seeds(a, r.eval.failed_seeds, a.test_set && first_failed < r.test_tasks.size()
                                                 ? r.test_tasks[first_failed]
                                                 : std::vector<std::pair<std::string, std::string>>{});
  std::printf("  reward         %.1f +- %.1f\n", r.eval.reward_mean, r.eval.reward_std);
  std::printf("  episode time   %.2f s (mean, simulated)\n", r.eval.time_mean);
  std::string usage;
  for (const auto& [name, f] : r.eval.usage) usage += (usage.empty() ? "" : ", ") + name + " " + std::to_string(int(std::lround(100 * f))) + "%";
  std::printf("  usage          %s\n", usage.c_str());
  print_first_tick_warning(r.eval.succeeded_at_first_tick, r.eval.episodes);
  if (r.eval.successes == 0 && !stimulus_unseen.empty()) std::printf("  note           %s\n", stimulus_unseen.c_str());
  if (const std::string judge = lua_judge_never_note(a, r); !judge.empty())
    std::printf("  note           %s\n", judge.c_str());
  print_unread_sets(r.unread_sets, r.scenario_file, r.params, a.sets);
}

// eval --policy FILE.json --json: the figures, the trial's parameters and with --test-set its tasks.
nlohmann::json policy_eval_json(const EvalArgs& a, const PolicyEvalResult& r, const std::string& stimulus_unseen) {
  nlohmann::json j = eval_summary_json(r.eval);
  j["succeeded_at_first_tick"] = r.eval.succeeded_at_first_tick;
  j.update({{"script", a.script}, {"policy", a.policy}, {"stage", r.stage}, {"context", r.context},
            {"scenario", r.scenario}, {"scenario_file", r.scenario_file}, {"failed_seeds", r.eval.failed_seeds}, {"test_set", a.test_set},
            {"stimulus_unseen", stimulus_unseen}});
  j["trial_params"] = nlohmann::json::object();  // the trial's own parameters set here (print_trial_params)
  for (const auto& [k, v] : r.trial_sets) j["trial_params"][k] = v;
  j["trial_params_overridden"] = nlohmann::json::object();  // the trial's own, replaced by --set here
  for (const auto& [k, v] : r.trial_sets_overridden) j["trial_params_overridden"][k] = v;
  // With --test-set, whence the tasks came, and each episode's task in order (world seed
  // first_seed + i).
  if (a.test_set) {
    j.update({{"test_set_from", r.test_set_source}, {"test_set_changed", r.test_set_changed}});
    j["test_tasks"] = nlohmann::json::array();
    for (const auto& task : r.test_tasks) {
      nlohmann::json t = nlohmann::json::object();
      for (const auto& [k, v] : task) t[k] = v;
      j["test_tasks"].push_back(t);
    }
  }
  for (const auto& [k, v] : r.params) j["params"][k] = v;
  return j;
}

// eval --policy FILE.json: a policy saved by roger train, its Psi rebuilt from the curriculum.
int run_eval_policy_file(const EvalArgs& a) {
  const PolicyEvalResult r = evaluate_policy_file(policy_eval_options(a));
  // The eyes' colour in these worlds, when it may be why every episode failed (and in --json).
  const std::string unseen = !a.test_set && (r.eval.successes == 0 || a.json)
                                 ? stimulus_unseen_in(r.scenario_file, r.params, sandbox_limits(a.lua), r.eval.first_seed,
                                                      std::min(5, r.eval.episodes))
                                 : "";
  print_policy_eval(a, r, unseen);
  if (a.json) std::printf("%s\n", policy_eval_json(a, r, unseen).dump().c_str());
  return 0;
}

}  // namespace

namespace {

// evaluate_action over a skill script's policy, an error naming the world's seed (a world that
// cannot be built, a goal that cannot work in it) and, for the goal's, the policy's line (found
// by a probe: "roger.sorted(): none of the world's 1 objects has the colour of a goal region"
// named no file, policy or seed).
EvalSummary evaluate_policy(const SkillScript& script, const SkillScript::NamedPolicy& policy, Scenario& scenario,
                            int episodes, uint64_t first_seed, const EpisodeOptions& options) {
  uint64_t seed = first_seed;
  auto seed_note = [&] { return " (world seed " + std::to_string(seed) + ")"; };
  auto generate = [&](uint64_t s) {
    seed = s;
    try {
      return scenario.generate(s);
    } catch (const PlacementError& e) {
      throw PlacementError(ScriptError(e.message + seed_note(), e.file, e.line, e.traceback));
    } catch (const ScriptError& e) {
      throw ScriptError(e.message + seed_note(), e.file, e.line, e.traceback);
    }
  };
  try {
    return evaluate_action(generate, *policy.action, *policy.goal, episodes, first_seed, options);
  } catch (const ScriptError&) {
    throw;
  } catch (const Error& e) {
    // The world's own failure (the physics of a body too light) names the scenario that made it
    // (found by a probe: only the policy's line was named, not the body's scenario).
    throw ScriptError("policy '" + policy.name + "': " + e.what() + " (world seed " + std::to_string(seed) +
                          " of scenario '" + scenario.name() + "', " + scenario.path() + ")",
                      script.path(), policy.goal_line, "");
  }
}

// goal_out_of_reach of the world of `seed`, said with its seed; "" when every goal region is within
// reach, or the world cannot be made here (its own error is said elsewhere).
std::string goal_out_of_reach_at(Scenario& scenario, uint64_t seed) {
  try {
    WorldModel model;
    derive_world_model(scenario.generate(seed), WorldParams{}, -1.0, model);
    const std::string why = goal_out_of_reach(model);
    return why.empty() ? "" : "in world seed " + std::to_string(seed) + ", " + why;
  } catch (const std::exception&) {
    return "";
  }
}

// The parts that never had a reference (EvalSummary::never_referenced), a line each: a policy
// failing at every seed because its navigator names a goal region past the world's, or its
// binding a colour no object has, said nothing but its success rate (found by a probe).
// Printed when every episode failed: a part that is not needed where the policy succeeds (the
// sort's look from elsewhere, in worlds where every object is seen) is no sign of anything.
void print_never_referenced(const EvalSummary& r) {
  if (r.successes > 0) return;
  // The kinds of noise these worlds had, not every kind (found by a probe: white noise alone was
  // said to have lost readings or made them late).
  std::vector<std::string> effects;
  if (r.noise_offsets) effects.push_back("perturbed");
  if (r.noise_lost) effects.push_back("lost");
  if (r.noise_late) effects.push_back("late");
  if (r.noise_coarse) effects.push_back("too coarse");
  std::string readings;
  for (size_t i = 0; i < effects.size(); ++i)
    readings += (i == 0 ? "" : i + 1 == effects.size() ? " or " : ", ") + effects[i];
  for (const std::string& name : r.never_referenced) std::printf("  no reference   %s\n", name.c_str());
  if (!r.never_referenced.empty())
    std::printf("  note           %s NOREF at every tick %s ran, in %s: what %s on was never there "
                "(a goal region past the world's, or too near a wall or obstacle for Roger's base to enter, a colour "
                "no object has, an object never reached)%s\n",
                r.never_referenced.size() == 1 ? "this part was" : "these parts were",
                r.never_referenced.size() == 1 ? "it" : "they",
                r.episodes == 1 ? "the episode" : ("all " + std::to_string(r.episodes) + " episodes").c_str(),
                r.never_referenced.size() == 1 ? "it acts" : "they act",
                // Found by a probe: readings all lost (dropout 1) were blamed on the world alone.
                r.noisy() ? (", or these worlds' noise kept it from the senses (readings " + readings + ")").c_str()
                        : "");
}

// --policy left out, refused naming what it could be, as --stage and --context of train are (found
// by a probe: "--policy is required" alone, where a misspelt one lists the script's policies).
void require_policy(const EvalArgs& a) {
  if (!a.policy.empty()) return;
  const std::string path = [&] {
    try {
      return resolve_curriculum_path(a.script);
    } catch (const Error&) {
      (void)policy_is_saved_file(a.script, "");  // says it as eval does: "no curriculum or skill script"
      throw;
    }
  }();
  if (is_curriculum_script(path))
    throw CommandLineError("--policy is required: with a curriculum, a policy file roger train wrote "
                           "(--policy out/policy.json)");
  const SkillScript script = SkillScript::load(a.script, sandbox_limits(a.lua));
  throw CommandLineError("--policy is required: the policy of skill script '" + script.name() + "' to evaluate, one "
                         "of: " + join(script.policy_names()));
}

// roger eval itself; command_eval stops it on request.
int evaluate_command(const EvalArgs& a) {
  require_policy(a);
  // Seeds S to S + N - 1 must not wrap past 2^64 - 1 to 0, 1, ... (found by a probe: they did, without
  // a word, and reran the worlds of an evaluation from seed 0).
  // A saved policy's first seed is below 2^63 (saved_policy_first_seed): checked there first, since
  // this bound would suggest a seed that one refuses (found by a probe).
  if (policy_is_saved_file(a.script, a.policy)) return run_eval_policy_file(a);
  if (a.seed_given && a.episodes > 0 && a.seed > UINT64_MAX - uint64_t(a.episodes - 1))
    throw Error("roger eval: --seed " + std::to_string(a.seed) + " with --episodes " + std::to_string(a.episodes) +
                " runs seeds past " + std::to_string(UINT64_MAX) + ": give a --seed of at most " +
                std::to_string(UINT64_MAX - uint64_t(a.episodes - 1)));
  if (a.test_set)
    throw Error("roger eval: --test-set runs a saved policy (--policy FILE.json) of a stage that teaches on its "
                "test set; policy '" + a.policy + "' of " + a.script + " is a skill script's, which has none");
  if (!a.skills.empty())
    throw Error("roger eval: --skill replaces a learned skill of a saved policy (--policy FILE.json); policy '" +
                a.policy + "' of " + a.script + " is a skill script's, which learns nothing");
  const SandboxLimits limits = sandbox_limits(a.lua);
  SkillScript script = SkillScript::load(a.script, limits);
  const SkillScript::NamedPolicy& policy = script.policy(a.policy);
  Scenario scenario = script.scenario_of(policy, a.scenario, limits);
  apply_sets(scenario, a.sets);
  const EpisodeOptions options = policy.episode_options();
  const EvalSummary r = evaluate_policy(script, policy, scenario, a.episodes, a.seed, options);
  const std::string limit = policy.time_per_object > 0.0
                                ? format_number(policy.time_per_object) + " s per object limit"
                                : format_number(policy.time_limit) + " s limit";
  std::printf("roger eval: %s policy '%s' in %s, %s from seed %llu, %s\n",
              script.path().c_str(), policy.name.c_str(), scenario.name().c_str(), counted(a.episodes, "episode").c_str(),
              static_cast<unsigned long long>(a.seed), limit.c_str());
  if (!policy.params.empty())
    std::printf("  policy params  %s\n", params_marking_sets(policy.params, a.sets).c_str());
  print_changes(a);
  std::vector<uint64_t> failed;
  for (size_t i = 0; i < r.results.size(); ++i)
    if (!r.results[i].success) failed.push_back(a.seed + i);
  std::printf("  success rate   %.1f%% (%d of %d)\n", 100.0 * r.success_rate, r.successes, r.episodes);
  print_failed_seeds(a, failed);
  std::printf("  reward         %.1f +- %.1f\n", r.reward_mean, r.reward_std);
  std::printf("  episode time   %.2f s (mean, simulated)\n", r.time_mean);
  print_never_referenced(r);
  if (r.successes == 0 && !r.never_referenced.empty())
    if (const std::string why = goal_out_of_reach_at(scenario, a.seed); !why.empty())
      std::printf("  note           %s\n", why.c_str());
  // As for a saved policy (found by a probe: a skill script's policy in a world whose stimulus no
  // object had said only that its parts had no reference).
  std::string unseen;
  if (r.successes == 0 || a.json) {
    QuietPrints prints(scenario.sandbox(), "roger looked for the stimulus colour in the worlds");
    prints.quiet();
    unseen = stimulus_unseen_note(scenario, a.seed, std::min(5, a.episodes));
  }
  if (r.successes == 0 && !unseen.empty()) std::printf("  note           %s\n", unseen.c_str());
  print_first_tick_warning(r.succeeded_at_first_tick, r.episodes);
  print_unread_sets(scenario.unread_params(split_sets(a.sets, "--set")), scenario.path(),
                    scenario_param_values(scenario), a.sets);
  if (a.json) {
    nlohmann::json j = {{"script", script.path()},      {"policy", policy.name},
                        {"scenario", scenario.name()},  {"scenario_file", scenario.path()},
                        {"episodes", r.episodes},
                        {"first_seed", a.seed},          {"successes", r.successes},
                        {"success_rate", r.success_rate}, {"reward_mean", r.reward_mean},
                        {"reward_std", r.reward_std},    {"time_mean", r.time_mean},
                        {"failed_seeds", failed},       {"never_referenced", r.never_referenced},
                        {"succeeded_at_first_tick", r.succeeded_at_first_tick},
                        {"stimulus_unseen", unseen}};
    for (const auto& p : scenario.params()) j["params"][p.name] = p.value;
    std::printf("%s\n", j.dump().c_str());
  }
  return 0;
}

}  // namespace

int command_eval(const EvalArgs& a) {
  // Stopped part-way, an evaluation is no result: it says so and prints no figures (found by a
  // probe: Ctrl-C ended it without a word, where train, render and run say what they kept).
  catch_interrupts("the evaluation ends at its next episode, with no figures");
  try {
    return evaluate_command(a);
  } catch (const std::exception&) {  // Interrupted, or an episode's error that carries it
    if (!interrupt_requested()) throw;
    std::fflush(stdout);
    std::fprintf(stderr, "roger eval: stopped; no figures (an evaluation stopped part-way is no result)\n");
    return interrupt_exit_status();
  }
}

// Where a skill of the trial came from, as roger train says it.
// A skill trained first learns its own stage's task, without the trial's --set (found by a probe:
// with --set locked=left_eye, nothing said that the skill had trained with both eyes).
static std::string skill_origin(const SkillSource& s, bool sets_given) {
  if (s.embedded)
    return "embedded in the policy file of the skill learned with it (stage " + s.stage + " context " +
           s.context + ")";
  if (!s.trained) return skill_file_origin(s);
  return "trained first: stage " + s.stage + " context " + s.context + ", " +
         (s.reached ? "reached" : "did NOT reach") + " its threshold after " +
         counted(s.to_threshold.episodes, "episode") +
         (sets_given ? " (its stage's own task, without --set: to learn it with them, train stage " + s.stage +
                           " with them and give its policy by --skill " + s.name + "=FILE.json)"
                     : std::string());
}

namespace {

// A --skill the context does not use would be ignored: refused, naming what it uses.
void check_skill_flags(const TrainOptions& o) {
  if (o.skill_files.empty()) return;
  const Curriculum cur = Curriculum::load(o.curriculum, o.limits);
  const CurriculumStage& stage = cur.stage(o.stage);
  for (const auto& [name, file] : o.skill_files)
    if (const std::string problem = cur.unused_skill_problem(stage, o.context, name); !problem.empty())
      throw Error("--skill " + name + "=" + file + ": " + problem);
}

// A --out folder holding files roger train does not write (a folder of scenarios, of notes) is
// refused before training: its results would go among them, and a policy.json of another tool
// would be replaced (found by a probe). Subfolders (an episode rendered there) and hidden files
// are left alone; a folder of an earlier roger train is its to write again.
void check_train_out_folder(const std::string& out) {
  static const std::set<std::string> own = {"policy.json",    "curve.csv",   "checkpoints.jsonl", "episodes.jsonl",
                                            "final.jsonl",    "summary.json", "error.json"};
  refuse_foreign_files(out, "roger train", [](const std::string& name) { return own.count(name) > 0; });
}

}  // namespace

namespace {

// train_stage, with a fault in an episode naming the stage and context it trained, as roger
// check names them: the cause's own file:line is often a library's (scenarios/lib/place.lua).
TrainResult train_for_command_line(const TrainOptions& o) {
  try {
    return train_stage(o);
  } catch (const EpisodeFault& f) {
    throw Error(f.text_in("stage '" + o.stage + "'" + (o.context.empty() ? "" : ", context '" + o.context + "'")));
  }
}

// train_for_command_line, keeping what a trial that faulted once training had begun had done:
// its episodes, checkpoints and the fault go into `out`, and the message says where.
TrainResult train_keeping_progress(TrainOptions& o, const std::string& out) {
  TrainResult progress;
  o.progress_on_fault = &progress;
  try {
    return train_for_command_line(o);
  } catch (const FileError&) {
    throw;
  } catch (const std::exception& e) {
    // The note goes under the message's first line, before any traceback.
    const std::string message = e.what(), first = message.substr(0, message.find('\n'));
    const std::string rest = message.substr(first.size());
    if (!write_faulted_train_outputs(progress, e.what(), out)) {
      // Found by a probe: a fault in the first episode left an earlier training's policy.json and
      // summary.json in the folder, unsaid, as if they were this one's.
      std::error_code ec;
      if (interrupt_requested() || !std::filesystem::exists(std::filesystem::path(out) / "policy.json", ec)) throw;
      throw Error(first + "\n  nothing kept   " + out + " is as it was: its files are an earlier training's" + rest);
    }
    throw Error(first + "\n  kept           " + out + "/{episodes.jsonl,checkpoints.jsonl,curve.csv,error.json}: the " +
                counted(progress.totals.episodes, "training episode") + " and " +
                counted(int(progress.checkpoints.size()), "checkpoint") + " before the fault" + rest);
  }
}

// The trial a command line asks for.
TrainOptions train_options(const TrainArgs& a) {
  TrainOptions o;
  o.curriculum = a.curriculum;
  o.stage = a.stage;
  o.context = a.context;
  o.seed = a.seed;
  o.sets = split_sets(a.sets, "--set");
  for (const auto& [name, file] : split_sets(a.skills, "--skill")) o.skill_files[name] = file;
  o.eval_cache = !a.no_eval_cache;
  o.explain = a.explain;
  o.init_file = a.init;
  o.limits = sandbox_limits(a.lua);
  return o;
}

// What the trial trains on: its stage's parameters, the --set, its skills and its warm start.
// Said before its first training episode (found by a probe: a trial of minutes said nothing until
// it ended, and nothing at all when stopped), so a mistaken --set or skill can be stopped early.
void print_trained_on(const TrainArgs& a, const TrainResult& r) {
  std::printf("roger train: %s stage %s context %s seed %llu (%zu action%s) in %s\n",
              r.curriculum_path.c_str(), r.stage.c_str(), r.context.c_str(), static_cast<unsigned long long>(r.seed),
              r.psi.size(), r.psi.size() == 1 ? "" : "s", r.scenario.c_str());
  // Before anything trains: the trial is in the project's scenario, and may not be the one meant.
  if (!r.scenario_note.empty()) std::printf("  note           %s\n", r.scenario_note.c_str());
  print_stage_params(r.stage_params, r.stage, r.context, a.sets);
  // As roger eval says it, so that a trial on another body never reads as one on the default body.
  // Each key once, as it was taken (found by a probe: a --set given twice was listed twice).
  std::string sets;
  for (const auto& [k, v] : split_sets(a.sets, "--set")) sets += (sets.empty() ? "" : ", ") + ("--set " + k + "=" + v);
  if (!sets.empty()) std::printf("  with           %s\n", sets.c_str());
  const ParamList body_here =
      r.skills.empty() ? ParamList() : first_world_body(r.scenario_file, r.params, sandbox_limits(a.lua), 0);
  for (const auto& s : r.skills)
    std::printf("  skill %s        %s%s\n", s.name.c_str(), skill_origin(s, !a.sets.empty()).c_str(),
                // A skill trained first without the --set has said so already.
                s.trained && !s.embedded && !a.sets.empty() ? "" : skill_params_note(s, r.params, body_here).c_str());
  if (r.init) {
    const WarmStart& w = *r.init;
    std::printf("  init           %s: %zu of %zu actions shared, %d states with values%s%s\n", w.source.c_str(),
                w.shared.size(), r.psi.size(), w.states_with_values,
                w.fresh.empty() ? "" : ("; at initial_q: " + join(w.fresh)).c_str(),
                w.dropped.empty() ? "" : ("; left out: " + join(w.dropped)).c_str());
    // Found by a probe: a warm start from another stage's policy, learned for another goal and
    // rewards, was said as one from this stage's.
    const auto& [stage, context] = r.init_from;
    if (!a.init.empty() && !stage.empty() && stage != r.stage)
      std::printf("  note           --init's policy was learned in stage %s%s, not %s: its values are of that "
                  "stage's goal and rewards, a start that helps only where the two agree\n",
                  stage.c_str(), context.empty() ? "" : (", context " + context).c_str(), r.stage.c_str());
  }
}

// What came of it: the threshold, the final policy and how it used its actions.
void print_outcome(const TrainResult& r) {
  if (r.reached) {
    std::printf("  threshold      %.0f%% reached after %s, %.1f simulated s, %s, %.2f wall s\n",
                100 * r.threshold, counted(r.to_threshold.episodes, "episode").c_str(), r.to_threshold.sim_s,
                counted(static_cast<long long>(r.to_threshold.decisions), "decision").c_str(), r.to_threshold.wall_s);
  } else {
    std::printf("  threshold      %.0f%% NOT reached in %s (%.1f simulated s)\n", 100 * r.threshold,
                counted(r.totals.episodes, "episode").c_str(), r.totals.sim_s);
  }
  // Found by a probe: training that stop_after ended said nothing of it (summary.json's stopped_early).
  if (r.stopped_early)
    std::printf("  stopped        after %s, before the budget's end: stop_after's consecutive passing checkpoints "
                "of one greedy policy\n", counted(r.totals.episodes, "training episode").c_str());
  std::string usage;
  for (const auto& [name, f] : r.final_eval.usage)
    usage += (usage.empty() ? "" : ", ") + name + " " + std::to_string(int(std::lround(100 * f))) + "%";
  std::printf("  final policy   %.0f%% success over %s, reward %.1f +- %.1f\n", 100 * r.final_eval.success_rate,
              counted(r.final_eval.episodes, r.teaches ? "test task" : "held-out episode").c_str(), r.final_eval.reward_mean,
              r.final_eval.reward_std);
  std::printf("  usage          %s (%s in the table)\n", usage.c_str(), counted(r.q->states(), "state").c_str());
}

// A stage that teaches: its teacher, what it did, and the tasks the scenario could not place.
void print_teacher(const TrainResult& r) {
  std::printf("  teacher        %s over %s\n", r.teacher.value("kind", std::string("?")).c_str(), r.task_space.c_str());
  const std::string did = describe_teacher_state(r.teacher.value("state", nlohmann::json()));
  if (!did.empty()) std::printf("                 %s\n", did.c_str());
  if (!r.teacher_warning.empty()) std::printf("  note           %s\n", r.teacher_warning.c_str());
  // A task whose world could not be placed is skipped and another drawn (docs/curricula.md): a
  // space that is partly holes shows here, not only in summary.json.
  if (!r.skipped_tasks.empty())
    std::printf("  skipped        %s the scenario could not place (the first: %s; all in summary.json)\n",
                counted(int(r.skipped_tasks.size()), "task").c_str(),
                r.skipped_tasks[0].value("task", nlohmann::json()).dump().c_str());
}

}  // namespace

// --stage and --context name the trial; one left out is refused with what the curriculum offers
// (found by a probe: "--context is required" named none, and the way to learn them was to guess).
void check_stage_and_context(const TrainArgs& a) {
  if (!a.stage.empty() && !a.context.empty()) return;
  const Curriculum curriculum = Curriculum::load(a.curriculum, sandbox_limits(a.lua));
  if (a.stage.empty()) {
    std::vector<std::string> stages;
    for (const CurriculumStage& s : curriculum.stages()) stages.push_back(s.name);
    throw CommandLineError("--stage is required: curriculum '" + curriculum.name() + "' (" + curriculum.path() +
                ") has the stages " + join(stages));
  }
  const CurriculumStage& stage = curriculum.stage(a.stage);
  std::vector<std::string> contexts;
  for (const CurriculumContext& c : stage.contexts) contexts.push_back(c.name);
  throw CommandLineError("--context is required: " + stage.where() + " has the contexts " + join(contexts));
}

int command_train(const TrainArgs& a) {
  check_stage_and_context(a);
  TrainOptions o = train_options(a);
  o.on_start = [&a](const TrainResult& started) {
    print_trained_on(a, started);
    std::fflush(stdout);  // seen at once through a pipe or in a log
  };
  check_skill_flags(o);
  check_train_out_folder(a.out);
  // One writer at a time (found by a probe: two trainings into one folder both committed, one's
  // policy beside the other's summary).
  const OutputClaim claim(a.out, "roger train");
  // A trial stopped part-way is no result: nothing is written, and the folder keeps what it had.
  catch_interrupts("the trial ends at its next episode and writes nothing");
  TrainResult r;
  try {
    r = train_keeping_progress(o, a.out);
  } catch (const std::exception&) {
    if (!interrupt_requested()) throw;
    std::fflush(stdout);
    std::fprintf(stderr, "roger train: stopped; nothing written (%s is as it was)\n", a.out.c_str());
    return interrupt_exit_status();
  }
  write_train_outputs(r, a.out);
  print_outcome(r);
  if (r.teaches) print_teacher(r);
  print_unread_sets(r.unread_sets, r.scenario_file, r.params, a.sets);
  const TrainingDiagnosis diagnosis = diagnose_training(r);
  if (const std::string at_start = diagnosis.goal_at_start_cause(); !at_start.empty() && r.reached && !r.explain)
    std::printf("  warning        %s\n", at_start.c_str());
  if (!r.reached || r.explain) {
    std::vector<std::string> causes = diagnosis.causes();
    if (!r.reached) {  // the eyes' colour first: what it leaves undone the other causes only describe
      const std::string scenario = Curriculum::load(o.curriculum, o.limits).stage(o.stage).scenario;
      if (const std::string note = stimulus_unseen_in(scenario, r.params, o.limits, 0, 5); !note.empty())
        causes.insert(causes.begin(), note);
    }
    for (size_t k = 0; k < causes.size(); ++k) std::printf("  %-15s%s\n", k ? "" : "why", causes[k].c_str());
    if (causes.empty()) std::printf("  why            nothing stands out in the data\n");
  }
  // Found by a probe: "0 of 13 reused" with a Lua reward said nothing of why.
  const char* uncached = !o.eval_cache ? " (--no-eval-cache)"
                         : r.absorbing_lua || r.reward_lua
                             ? " (none: the stage's Lua reward or absorbing function may keep state between calls)"
                             : "";
  std::printf("  evaluations    %d of %d reused whole, %d of %d episodes reused%s\n", r.evals_reused, r.evals,
              r.eval_episodes_reused, r.eval_episodes, uncached);
  std::printf("  wrote          %s/{policy.json,curve.csv,episodes.jsonl,checkpoints.jsonl,final.jsonl,summary.json} (%.2f wall s)\n",
              a.out.c_str(), r.wall_s);
  if (a.json) std::printf("%s\n", train_summary_json(r).dump().c_str());
  return 0;
}

}  // namespace roger
