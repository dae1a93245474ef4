// inspect.cpp: `roger render` (a picture of a world, or an episode of a skill script's policy).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "batch/trainer.h"
#include "cli/cli_internal.h"
#include "cli/commands.h"
#include "core/fileio.h"
#include "core/interrupt.h"
#include "core/text.h"
#include "learn/episode.h"
#include "script/curriculum/curriculum.h"
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

std::string unread_sets_note(const std::vector<std::string>& unread, const std::string& scenario) {
  if (unread.empty()) return "";
  std::vector<std::string> options;
  for (const std::string& name : unread) options.push_back("--set " + name);
  return listed_with_and(options) + " changed no world here: the scenario's generate never read " +
         (unread.size() == 1 ? "it" : "them") + " (roger check " + scenario + " lists each parameter it never reads)";
}

std::vector<std::pair<std::string, std::string>> scenario_param_values(const Scenario& scenario) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const ScenarioParam& p : scenario.params()) out.emplace_back(p.name, p.value);
  return out;
}

std::string noise_sets_note(const std::vector<std::pair<std::string, std::string>>& params,
                             const std::vector<std::string>& sets) {
  std::map<std::string, std::string> value(params.begin(), params.end());
  const auto zero = [&](const std::string& name) { return value.count(name) && std::strtod(value[name].c_str(), nullptr) == 0.0; };
  const auto ends_with = [](const std::string& s, const std::string& tail) {
    return s.size() > tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
  };
  std::vector<std::string> notes;
  for (const auto& [key, set] : split_sets(sets, "--set")) {
    if (key.rfind("noise_", 0) == 0 && ends_with(key, "_tau")) {
      const std::string drift = key.substr(0, key.size() - 4) + "_drift";
      if (zero(drift)) notes.push_back("--set " + key + " changed no world here: " + drift + " is 0, and tau is the "
                                       "drift's correlation time");
    } else if (key == "noise_scale" && value.count(key)) {
      bool all_zero = true;
      for (const auto& [name, v] : params)
        if (name.rfind("noise_", 0) == 0 && name != key && !ends_with(name, "_tau")) all_zero = all_zero && zero(name);
      if (all_zero) notes.push_back("--set noise_scale changed no world here: every noise level it multiplies is 0");
    } else if (key.rfind("noise_", 0) == 0 && value.count(key) && !zero(key)) {
      // Found by a probe: a level under noise_scale 0, a delay scaled under half a tick and an image
      // quantum of a level or less ran as no noise at all, unsaid.
      const double scale = value.count("noise_scale") ? std::strtod(value["noise_scale"].c_str(), nullptr) : 1.0;
      const double asked = std::strtod(value[key].c_str(), nullptr) * scale;
      if (scale == 0.0)
        notes.push_back("--set " + key + " changed no world here: noise_scale is 0, and it multiplies every level");
      else if (ends_with(key, "_delay") && std::floor(asked + 0.5) == 0.0)
        notes.push_back("--set " + key + " changed no world here: times noise_scale = " + value["noise_scale"] +
                        " it is " + format_number(asked) + " ticks, which rounds to none");
      else if (key == "noise_image_quantum" && std::round(asked) <= 1.0)
        notes.push_back("--set " + key + " changed no world here: an image quantum of one colour level or less "
                        "rounds no colour (colours are whole levels)");
    }
  }
  // A dropout that noise_scale carries past 1 is held at 1, where every other kind past its range
  // is refused: said, since every reading of that channel is then lost (found by a probe).
  const bool scaling_set = std::any_of(sets.begin(), sets.end(), [&](const std::string& s) {
    return s.rfind("noise_scale=", 0) == 0 || (s.rfind("noise_", 0) == 0 && s.find("_dropout=") != std::string::npos);
  });
  const bool scaled = scaling_set && value.count("noise_scale");
  const double scale = scaled ? std::strtod(value["noise_scale"].c_str(), nullptr) : 1.0;
  for (const auto& [name, v] : params) {
    const double dropout = std::strtod(v.c_str(), nullptr);
    if (scaled && name.rfind("noise_", 0) == 0 && ends_with(name, "_dropout") && dropout * scale > 1.0)
      notes.push_back(name + " = " + v + " times noise_scale = " + value["noise_scale"] + " is held at a dropout of 1: "
                      "every reading of the " + name.substr(6, name.size() - 6 - 8) + " channel is lost");
  }
  return join(notes, "; ");
}

void print_unread_sets(const std::vector<std::string>& unread, const std::string& scenario,
                       const std::vector<std::pair<std::string, std::string>>& params,
                       const std::vector<std::string>& sets) {
  if (!unread.empty()) std::printf("  note           %s\n", unread_sets_note(unread, scenario).c_str());
  if (const std::string noise = noise_sets_note(params, sets); !noise.empty())
    std::printf("  note           %s\n", noise.c_str());
}

namespace {

// roger render's line for the --set its one world never read: the picture would not show why.
void print_unread_note(Scenario& scenario, const std::vector<std::string>& sets) {
  const std::vector<std::string> unread = scenario.unread_params(split_sets(sets, "--set"));
  if (!unread.empty()) std::printf("note: %s\n", unread_sets_note(unread, scenario.path()).c_str());
  if (const std::string noise = noise_sets_note(scenario_param_values(scenario), sets); !noise.empty())
    std::printf("note: %s\n", noise.c_str());
}

}  // namespace

void refuse_foreign_files(const std::string& out, const std::string& command,
                          const std::function<bool(const std::string&)>& own) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(out, ec)) return;
  std::vector<std::string> foreign;
  for (const auto& entry : fs::directory_iterator(out, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || name[0] == '.' || entry.is_directory(ec) || own(name)) continue;
    foreign.push_back(name);
  }
  if (foreign.empty()) return;
  std::sort(foreign.begin(), foreign.end());
  if (foreign.size() > 5) foreign.resize(5), foreign.push_back("...");
  throw Error("--out " + out + " holds files " + command + " does not write (" + join(foreign) + "): its output "
              "would go among them. Give a new or empty folder (or one " + command + " wrote before)");
}

std::string trial_params_left_note(const std::vector<std::pair<std::string, std::string>>& left, size_t declared,
                                   const std::string& scenario) {
  std::vector<std::string> played, undeclared;
  std::string sets;
  for (size_t i = 0; i < left.size(); ++i) {
    if (i >= declared) {
      undeclared.push_back(left[i].first);
      continue;
    }
    played.push_back(left[i].first);
    sets += (sets.empty() ? "--set " : " --set ") + left[i].first + "=" + left[i].second;
  }
  std::string note = "the trial trained with " + params_text(left) + "; scenario " + scenario;
  if (!played.empty())
    note += " plays its own value" + std::string(played.size() == 1 ? " of " : "s of ") +
            (undeclared.empty() ? std::string(played.size() == 1 ? "it" : "them") : join(played)) + " here (" + sets +
            " plays the trial's)";
  if (!played.empty() && !undeclared.empty()) note += ", and";
  if (!undeclared.empty())
    note += " has no parameter " + join(undeclared) + " (its worlds are as the scenario makes them, whatever " +
            (undeclared.size() == 1 ? "it" : "they") + " were in training)";
  return note;
}

bool policy_is_saved_file(const std::string& script, const std::string& policy) {
  const bool json_file = policy.size() >= 5 && policy.compare(policy.size() - 5, 5, ".json") == 0;
  std::string path;
  try {
    path = resolve_curriculum_path(script);
  } catch (const Error& e) {
    // eval and render take a skill script too: a name that is neither is not only "no curriculum".
    const std::string message = e.what(), missing = "no curriculum '";
    if (message.rfind(missing, 0) != 0) throw;
    throw Error("no curriculum or skill script '" + message.substr(missing.size()));
  }
  if (!is_curriculum_script(path)) {
    if (json_file)
      throw Error("--policy " + policy + " is a saved policy, which runs with the curriculum it was trained on "
                  "(CURRICULUM.lua --policy FILE.json); " + script + " is not a curriculum, so --policy names one of "
                  "its policies");
    return false;
  }
  if (!json_file) {
    // Found by a probe: a mistyped out/policy.jsn was said to be no policy file, not to be missing.
    std::error_code ec;
    const bool exists = std::filesystem::exists(policy, ec);
    throw Error("with a curriculum, --policy names a policy file written by roger train (policy.json), got '" +
                policy + "'" + (exists ? std::string() : ": no such file"));
  }
  return true;
}

namespace {

// The --set options an episode ran with, for its title: a replay under noise says so.
std::string sets_note(const std::vector<std::string>& sets) {
  return sets.empty() ? "" : " with --set " + join(sets, " --set ");
}

// Writes a recorded episode: a folder with frames and a replay page, or (for a .png path) one
// summary strip; then says what it wrote.
// Whether --out names one summary strip (a .png) rather than a folder of frames.
// In any case of letters (found by a probe: x.PNG wrote a folder named x.PNG).
bool is_summary_strip(const std::string& out) { return lower_ascii(std::filesystem::path(out).extension().string()) == ".png"; }

void write_rendered_episode(const RenderArgs& a, const WorldSpec& spec, const EpisodeResult& episode,
                            const std::string& title) {
  constexpr int kPanels = 4;  // of a summary strip
  AnimationOptions anim;
  anim.frame.width_px = a.width;
  anim.title = title;
  anim.fps = 1.0 / a.every;  // frames per simulated second, as recorded (found by a probe: always 10)
  const bool summary = is_summary_strip(a.out);
  if (summary) {
    throw_if_interrupted();
    make_parent_folder(a.out, "roger render");  // as the folder of frames is made
    render_episode_summary(spec, episode, a.out, anim, kPanels);
  } else {
    render_episode(spec, episode, a.out, anim);
  }
  // A strip shows some of the frames recorded: say how many of how many.
  const size_t shown = summary ? std::min(size_t(kPanels), episode.frames.size()) : episode.frames.size();
  const std::string frames = summary ? std::to_string(shown) + " of " + std::to_string(episode.frames.size()) +
                                           " frames recorded"
                                     : counted(long(shown), "frame");
  std::printf("wrote %s (%s after %.2f s, reward %.0f; %s)\n", a.out.c_str(), episode.success ? "success" : "timeout",
              episode.sim_seconds, episode.reward, frames.c_str());
}

// Renders the greedy episode of a policy saved by roger train (its curriculum is a.scenario).
int run_render_policy_file(const RenderArgs& a) {
  PolicyEvalOptions o;
  o.curriculum = a.scenario;
  o.policy_file = a.policy;
  o.scenario = a.world;
  o.sets = split_sets(a.sets, "--set");
  // Found by a probe: a seed of 2^63 or more read as none given and recorded the first held-out
  // world (seed 1000000) under a title that named it.
  o.first_seed = saved_policy_first_seed("roger render", a.seed);
  for (const auto& [name, file] : split_sets(a.skills, "--skill")) o.skill_files[name] = file;
  if (a.test_task > 0 && a.seed_given)
    throw Error("roger render: --test-task runs the task in its own world seed; --seed cannot be given with it");
  o.test_task = a.test_task;
  o.trial_params = true;  // the trial's own parameters, as roger eval sets them
  o.command = "roger render";
  o.limits = sandbox_limits(a.lua);
  const RecordedPolicyEpisode r = record_policy_episode(o, a.every);
  std::string task;
  if (a.test_task > 0) {
    task = params_text(r.about.test_tasks[size_t(a.test_task - 1)]);
    task = ", test task " + std::to_string(a.test_task) + " (" + (task.empty() ? "the stage's own parameters" : task) + ")";
  }
  const std::string trained = r.about.trial_sets.empty() ? "" : " with " + params_text(r.about.trial_sets);
  // As roger eval says them (found by a probe: docs/cli.md promised the line, and render gave it
  // only in the page's title).
  if (!r.about.trial_sets.empty())
    std::printf("trained with: %s (the trial's own parameters, set here too; a --set of one overrides it)\n",
                params_text(r.about.trial_sets).c_str());
  if (!r.about.trial_sets_overridden.empty())
    std::printf("trained with: %s (the trial's own parameters, not in force here)\n",
                params_marking_sets(r.about.trial_sets_overridden, a.sets).c_str());
  // Found by a probe: eval said so, render did not, and its title gave no body.
  if (!r.about.trial_sets_left.empty())
    std::printf("note: %s\n", trial_params_left_note(r.about.trial_sets_left, r.about.trial_sets_left_declared, r.about.scenario).c_str());
  if (!r.about.unread_sets.empty())
    std::printf("note: %s\n", unread_sets_note(r.about.unread_sets, r.about.scenario_file).c_str());
  write_rendered_episode(a, r.spec, r.episode,
                         r.about.stage + "/" + r.about.context + " (" + a.policy + ") in " + r.about.scenario +
                             trained + sets_note(a.sets) + ", seed " + std::to_string(r.episode.seed) + task);
  return 0;
}

// The controllers a skill script's policy shows on its timeline: those its action runs and its
// goal reads, in the order a walk from the action, then from the goal's controllers, meets them,
// then the script's others; at most a dozen, so that it stays legible, and a note naming the
// policy's own left out (found by a probe: the script's first twelve were shown, in the order
// they were defined, and the carrying steps the scripted task's goal reads were never among them).
std::vector<ControllerPtr> timeline_controllers(const SkillScript& script, const SkillScript::NamedPolicy& policy) {
  constexpr size_t kMost = 12;
  const std::vector<ControllerPtr> all = script.controllers();
  std::vector<const Controller*> walk{policy.action.get()};
  for (size_t i = 0; i < walk.size(); ++i)  // breadth first: the action's own steps before their insides
    for (const Controller* part : walk[i]->children())
      if (std::find(walk.begin(), walk.end(), part) == walk.end()) walk.push_back(part);  // a shared part once
  policy.goal->controllers(walk);
  std::vector<ControllerPtr> used, others;
  for (const Controller* c : walk)
    for (const ControllerPtr& named : all)
      if (named.get() == c && std::find(used.begin(), used.end(), named) == used.end()) used.push_back(named);
  for (const ControllerPtr& named : all)
    if (std::find(used.begin(), used.end(), named) == used.end()) others.push_back(named);
  if (used.size() > kMost) {
    std::vector<std::string> left;
    for (size_t i = kMost; i < used.size(); ++i) left.push_back(used[i]->name());
    std::fprintf(stderr, "roger: note: the timeline shows %zu of the %zu controllers policy '%s' runs or its goal "
                 "reads; not shown: %s\n", kMost, used.size(), policy.name.c_str(), join(left).c_str());
  }
  used.insert(used.end(), others.begin(), others.end());
  if (used.size() > kMost) used.resize(kMost);
  return used;
}

// Renders one episode of a skill script's policy: a folder with frames and a replay page, or
// (for a .png path) one summary strip.
int run_render_episode(const RenderArgs& a) {
  // Before the episode is run: a folder of other files was written into (found by a probe), and
  // a results folder's index.html, its dashboard, would have been replaced by the replay page.
  // One writer at a time into a folder, and a folder made here goes again when nothing is
  // written (found by a probe: a stopped rendering left an empty folder it said was as it was).
  std::optional<OutputClaim> claim;
  if (!is_summary_strip(a.out)) {
    refuse_foreign_files(a.out, "roger render", render_episode_writes);
    claim.emplace(a.out, "roger render");
  }
  if (policy_is_saved_file(a.scenario, a.policy)) return run_render_policy_file(a);
  if (a.test_task > 0)
    throw Error("roger render: --test-task renders a task of a saved policy's test set (CURRICULUM.lua --policy "
                "FILE.json); policy '" + a.policy + "' of " + a.scenario + " is a skill script's, which has none");
  if (!a.skills.empty())
    throw Error("roger render: --skill replaces a learned skill of a saved policy (--policy FILE.json); policy '" +
                a.policy + "' of " + a.scenario + " is a skill script's, which learns nothing");
  const SandboxLimits limits = sandbox_limits(a.lua);
  SkillScript script = SkillScript::load(a.scenario, limits);
  const SkillScript::NamedPolicy& policy = script.policy(a.policy);
  Scenario scenario = script.scenario_of(policy, a.world, limits);
  apply_sets(scenario, a.sets);
  const WorldSpec spec = scenario.generate(a.seed);
  EpisodeOptions options = policy.episode_options();
  options.record_every = a.every;
  const std::vector<ControllerPtr> watch = timeline_controllers(script, policy);
  Agent agent;
  const EpisodeResult episode = run_episode(agent, spec, a.seed, *policy.action, *policy.goal, options, watch);
  print_unread_note(scenario, a.sets);
  write_rendered_episode(a, spec, episode,
                         script.name() + ": " + policy.name + " in " + scenario.name() +
                             (policy.params.empty() ? "" : " (" + params_text(policy.params) + ")") + sets_note(a.sets) +
                             ", seed " +
                             std::to_string(a.seed));
  return 0;
}

}  // namespace

// An episode is written to a folder or a .png strip: a picture's other extension (x.svg) would
// be a folder named like a file, so it is refused before the episode runs.
void check_episode_out(const std::string& out, int width) {
  namespace fs = std::filesystem;
  const std::string ext = lower_ascii(fs::path(out).extension().string());
  const std::string name = lower_ascii(fs::path(out).filename().string());
  // ".png" alone is a hidden name, no strip's (found by a probe: refused after the episode, as "not
  // named .png").
  if (name == ".png")
    throw Error("roger render --policy: --out '" + out + "' names no strip: give it a name, such as episode.png");
  // A strip is four frames side by side: one that no PNG can hold is refused before the episode
  // (found by a probe: --width 16000 ran the episode, then failed).
  constexpr int kStripFrames = 4, kMostPixels = 32767;
  if (ext == ".png" && long(width) * kStripFrames > kMostPixels)
    throw Error("roger render --policy: --width " + std::to_string(width) + ": a summary strip is " +
                std::to_string(kStripFrames) + " frames wide, " + std::to_string(long(width) * kStripFrames) +
                " pixels, past the " + std::to_string(kMostPixels) + " a picture's side can have: give --width " +
                "of at most " + std::to_string(kMostPixels / kStripFrames) + ", or a folder (frames of any --width)");
  std::error_code ec;
  if (ext.empty() || ext == ".png" || fs::is_directory(out, ec)) return;
  for (const char* picture : {".svg", ".jpg", ".jpeg", ".gif", ".pdf", ".html", ".json", ".webp"})
    if (ext == picture)
      throw Error("roger render --policy: --out takes a folder (frames, episode.json and a replay page) or a FILE.png "
                  "(one summary strip), got '" + out + "'" + (ext == ".svg" ? "; an episode has no SVG form (a "
                  "world's picture has: roger render SCENARIO --out x.svg)" : ""));
}

int command_render(const RenderArgs& a) {
  if (!a.policy.empty()) {
    check_episode_out(a.out, a.width);
    // Stopped part-way, an episode's rendering writes nothing: its folder (or strip) keeps what it
    // had (render_episode stages its files).
    catch_interrupts("the rendering stops and writes nothing");
    try {
      return run_render_episode(a);
    } catch (const Interrupted&) {
      std::fflush(stdout);
      std::fprintf(stderr, "roger render: stopped; nothing written (%s is as it was)\n", a.out.c_str());
      return interrupt_exit_status();
    }
  }
  if (!a.skills.empty()) throw Error("roger render: --skill needs --policy FILE.json (a policy saved by roger train)");
  Scenario scenario = Scenario::load(a.scenario, sandbox_limits(a.lua));
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
  print_unread_note(scenario, a.sets);
  std::printf("wrote %s (%s, seed %llu)\n", a.out.c_str(), a.scenario.c_str(),
              static_cast<unsigned long long>(a.seed));
  return 0;
}

}  // namespace roger
