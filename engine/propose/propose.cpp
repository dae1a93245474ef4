// propose.cpp: the search of roger propose: the probe, the candidates, successive halving over
// short seeded training runs, and the proposal written as a curriculum.
#include "propose/propose.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numeric>
#include <ostream>
#include <regex>
#include <set>

#include "batch/trainer.h"
#include "core/json_input.h"
#include "core/error.h"
#include "core/fileio.h"
#include "core/rng.h"
#include "core/text.h"
#include "propose/propose_internal.h"
#include "script/batch/batch_script.h"
#include "script/curriculum/curriculum.h"
#include "script/scenario/scenario.h"

#include <unistd.h>  // access: whether the project's curricula/ is the user's to write

namespace roger {
namespace fs = std::filesystem;
using namespace propose_detail;

namespace {

// Letters, digits, underscores and dots: the names require takes.
bool require_spells(const std::string& text) {
  return std::all_of(text.begin(), text.end(), [](char ch) {
    return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '.';
  });
}

// The error of a curriculum `file` (`real` its canonical path) outside the project's script
// folders, with its name too when it is not one require takes: both said at once, so one copy
// mends both. An installed project's folder is not the user's to write (found by a probe: the
// advice was to copy into /usr/local/share/roger/curricula): a project folder of one's own comes first.
Error outside_project(const std::string& file, const fs::path& real) {
  const std::string curricula = (project_root() / "curricula").string();
  const std::string stem = real.stem().string();
  const bool named = real.extension() == ".lua" && require_spells(stem) && stem.find('.') == std::string::npos;
  const std::string what = " (with the files it names by relative paths: scenarios beside it, modules it requires)" +
                           (named ? std::string()
                                  : ", under a name require takes (letters, digits and underscores, a .lua file: "
                                    "not '" + real.filename().string() + "')");
  return Error("roger propose: " + file + ": the curriculum lies outside the project's curricula/ (" + curricula +
               "), scenarios/ and scripts/; the proposal written into --out builds on it by require, and require "
               "in a roger script finds modules only in the script's own folder and in those three, so it could "
               "not load. Make a project folder of your own: copy the curriculum into DIR/curricula/" + what +
               " and run roger with ROGER_HOME=DIR (ROGER_HOME=DIR roger propose " +
               (named ? stem : std::string("NAME")) + " ...; the proposal then loads with the same ROGER_HOME, "
               "and finds the shipped libraries after your own)" +
               (access(curricula.c_str(), W_OK) == 0 ? ", or copy it into " + curricula + "/" : std::string()) +
               "; nothing was run");
}

// The require name of a curriculum file, checked before anything runs. A proposal is a file in
// --out that builds on the curriculum by require(name), and require in a roger script finds
// modules only in the script's own folder and in the project's scenarios/, curricula/ and scripts/
// (the sandbox reads no other file). So the curriculum must lie in one of those folders, under a
// name require can spell, and be the file that name finds first from the proposal's folder and
// the candidates'; otherwise the probe's training would be spent on a proposal that cannot load.
std::string module_name(const std::string& file, const std::string& out) {
  std::error_code ec;
  const fs::path real = fs::weakly_canonical(fs::absolute(file), ec);
  std::string name;
  fs::path rel;
  for (const auto& root : module_search_roots()) {
    rel = real.lexically_relative(root);
    if (rel.empty() || *rel.begin() == "..") continue;
    name = fs::path(rel).replace_extension().generic_string();
    std::replace(name.begin(), name.end(), '/', '.');
    break;
  }
  if (name.empty()) throw outside_project(file, real);
  const bool spellable = rel.extension() == ".lua" && name.find("..") == std::string::npos && require_spells(name);
  if (!spellable)
    throw Error("roger propose: " + file + ": the proposal builds on the curriculum by require(\"" + name +
                "\"), not a module name require takes (letters, digits and underscores, its folders joined by "
                "dots, a .lua file): rename the file to such a name; nothing was run");
  const fs::path out_dir = fs::weakly_canonical(fs::absolute(out), ec);
  for (const fs::path& folder : {out_dir, out_dir / "candidates"})
    for (const auto& root : module_search_roots(folder)) {
      const fs::path found = root / rel;
      if (!fs::is_regular_file(found, ec)) continue;
      if (fs::equivalent(found, real, ec)) break;
      throw Error("roger propose: " + file + ": the proposal builds on the curriculum by require(\"" + name +
                  "\"), and from " + folder.string() + " that finds " + found.string() +
                  " first (require searches the script's folder, then scenarios/, curricula/, scripts/): "
                  "propose from a copy of the curriculum under a name of its own; nothing was run");
    }
  return name;
}

// The task's scenario as the proposal must name it: lib.propose calls roger.stage from its own
// file, so a path the curriculum names relative to the file that writes the stage (its
// resolve_scenario_near) would be looked for beside curricula/lib/ instead. The file the
// curriculum loads, named from the project when inside it (a proposal of a curriculum inside the
// project stays portable), else absolute; "" for a shipped scenario's bare name, the same
// from anywhere.
std::string scenario_from_project(const std::string& scenario) {
  const fs::path written(scenario);
  if (written.extension() != ".lua" && scenario.find('/') == std::string::npos) return "";
  std::error_code ec;
  const fs::path real = fs::weakly_canonical(fs::absolute(resolve_scenario_path(scenario)), ec);
  const fs::path rel = real.lexically_relative(fs::weakly_canonical(project_root(), ec));
  if (rel.empty() || *rel.begin() == "..") return real.generic_string();
  const std::string r = rel.generic_string();
  return r.find('/') == std::string::npos ? "./" + r : r;  // a bare "x.lua" would mean scenarios/x.lua
}

// A stage's time-out in a world of its own scenario (the held-out seeds' first): a limit per
// object depends on the world.
double stage_time_limit(const CurriculumStage& stage, const SandboxLimits& limits) {
  if (!(stage.time_per_object > 0.0)) return stage.time_limit;
  Scenario scenario = Scenario::load(stage.scenario, limits);
  for (const auto& [key, value] : stage.params) scenario.set_param(key, value);
  return stage.episode_time_limit(scenario.generate(stage.checkpoints.seeds));
}

void check_options(const ProposeOptions& o, double time_limit) {
  if (o.out.empty()) throw Error("roger propose: --out must name a folder");
  // At most 1e9 s (30 years): a budget of 1e308 ran, printed as 309 digits (found by a probe).
  if (!(o.budget_s > 0) || !(o.budget_s <= 1e9))
    throw Error("roger propose: --budget must be a positive number of simulated seconds, at most 1e9, got " +
                format_number(o.budget_s));
  if (o.budget_s < 30 * time_limit)
    throw Error("roger propose: --budget " + format_number(o.budget_s) + " is under 30 episodes of the stage's time " +
                "limit of " + format_number(time_limit) + " simulated s, " + format_number(30 * time_limit) +
                " simulated s: too little to learn anything, and one episode past the budget could exceed it by more " +
                "than 10%; give a --budget of at least " + format_number(30 * time_limit));
  if (!(o.probe_share > 0 && o.probe_share < 1)) throw Error("roger propose: the probe share must be in (0, 1)");
  if (o.probe_trials < 1 || o.trials < 1 || o.max_candidates < 1)
    throw Error("roger propose: probe trials, trials and max candidates must be at least 1");
  // Each probe trial runs at least one episode whatever its cap (found by a probe: --probe-trials
  // 100 spent 1000 of a budget of 300 simulated s, and said nothing).
  const double probe_cap = o.budget_s * o.probe_share / o.probe_trials;
  if (probe_cap < time_limit)
    throw Error("roger propose: each of the " + std::to_string(o.probe_trials) + " probe trials would get " +
                format_number(probe_cap) + " simulated s (--budget x --probe-share / --probe-trials), under one "
                "episode of the stage's time limit of " + format_number(time_limit) + " simulated s, and each runs at "
                "least one: give fewer --probe-trials, or a larger --probe-share or --budget");
}

// The starting context must be one the probe can train and a proposal can compare with.
void check_context(const CurriculumStage& stage, const CurriculumContext& ctx) {
  if (!ctx.learned.empty())
    throw Error("roger propose: " + stage.where(ctx.name) + " uses learned skills; start from a context of the stage's " +
                "own controllers (the proposal's subgoal stages are what learns skills)");
  // The proposal names its own context P beside the stage's (found by a probe: a stage with a
  // context P, a proposal's own, trained the probe and then failed inside the first candidate).
  for (const CurriculumContext& c : stage.contexts)
    if (c.name == "P")
      throw Error("roger propose: " + stage.where(c.name) + " is named 'P', the name the proposal gives its own context "
                  "beside the stage's; rename it (a proposal proposed from again: name its P otherwise first)");
  // The probe would train the warm start too, and no proposal context has one to compare with.
  if (!ctx.init_context.empty())
    throw Error("roger propose: " + stage.where(ctx.name) + " starts from the Q-table of context '" + ctx.init_context +
                "' of stage '" + ctx.init_stage + "' (init); the proposal's contexts learn from scratch, so start "
                "from a context without init");
}

// Runs one check of the command, keeping its refusal rather than throwing it, so that a command
// with several problems hears of all of them at once instead of one per attempt.
template <class Check>
void collect_refusal(std::vector<std::string>& refusals, Check check) {
  try {
    check();
  } catch (const FileError&) {
    throw;  // the machine's fault, not the command's: it stops everything, as elsewhere
  } catch (const Error& e) {
    refusals.push_back(e.what());
  }
}

// Throws the refusals collected: one as it is, several as one message listing each.
void refuse(const std::vector<std::string>& refusals) {
  if (refusals.empty()) return;
  if (refusals.size() == 1) throw Error(refusals.front());
  const std::string prefix = "roger propose: ";
  std::string text = prefix + std::to_string(refusals.size()) + " problems, each to mend before anything runs:";
  for (const auto& r : refusals) text += "\n  - " + (r.rfind(prefix, 0) == 0 ? r.substr(prefix.size()) : r);
  throw Error(text);
}

// A folder of other files is no search's: settings.json, written before anything else, makes a
// folder a search's. A roger run results folder (manifest.json) has a trials/ folder of its own,
// whose records a search would mix with its own; any other files are someone's work.
// Returns whether the folder holds a search's files alone without its settings.json (lost, or
// removed): read as a search whose settings cannot be read, whose records are reused where they
// are this search's (found by a probe: the search's own folder was "other files").
bool refuse_foreign_folder(const std::string& out, bool has_settings) {
  if (fs::exists(fs::path(out) / "manifest.json"))
    throw Error("roger propose: " + out + " is a roger run results folder (it holds manifest.json), whose trials/ "
                "the search's records would mix with; give another --out (a new or empty folder, or an earlier "
                "search's to resume it)");
  if (has_settings) return false;
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(out)) names.push_back(entry.path().filename().string());
  if (names.empty()) return false;
  static const std::set<std::string> written = {"candidates", "probe", "trials", "proposal.lua", "propose.md"};
  if (std::all_of(names.begin(), names.end(), [](const std::string& n) { return written.count(n) > 0; })) return true;
  std::sort(names.begin(), names.end());
  const size_t shown = std::min<size_t>(names.size(), 3);
  std::string list = join(std::vector<std::string>(names.begin(), names.begin() + long(shown)));
  if (names.size() > shown) list += " and " + std::to_string(names.size() - shown) + " more";
  throw Error("roger propose: " + out + " holds other files (" + list + ") and no search's settings.json; give "
              "another --out (a new or empty folder, or an earlier search's to resume it)");
}

// The search a folder holds, one per folder as a results folder holds one batch: settings.json
// records what this search asks, and a folder holding another (another seed, budget, stage...)
// is refused before anything is written, rather than mixed with it and its proposal replaced.
// The folder is made first, so that an --out nothing can be written to fails now, not after the
// probe's training.
void claim_search_folder(const ProposeOptions& o, const std::string& module, const std::string& stage,
                         const std::string& context) {
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (ec) throw FileError("roger propose: cannot create the folder '" + o.out + "': " + ec.message(), o.out, ec.value());
  if (!fs::is_directory(o.out)) throw Error("roger propose: cannot create the folder '" + o.out + "': it is a file");
  const nlohmann::json search = {{"curriculum", module},         {"stage", stage},
                                 {"context", context},           {"budget_s", o.budget_s},
                                 {"seed", o.seed},               {"trials", o.trials},
                                 {"probe_trials", o.probe_trials}, {"probe_share", o.probe_share},
                                 {"max_candidates", o.max_candidates}, {"prune_below", o.prune_below}};
  const std::string file = (fs::path(o.out) / "settings.json").string();
  const bool settings_lost = refuse_foreign_folder(o.out, fs::exists(file));
  // A settings.json that cannot be read (not JSON, or missing what a search writes: a disk fault or
  // an edit) is written again with this search's settings, as an unreadable record is run again:
  // the trials' records say themselves which candidate, seed and cap they are of, so only matching
  // ones are reused (found by a probe: "remove it to search here again" led to "holds other files").
  std::string unreadable;
  nlohmann::json before;
  if (fs::exists(file)) {
    try {
      before = parse_json(read_file_text(file));
      if (!before.is_object()) unreadable = "not a JSON object";
      for (const auto& [key, value] : search.items()) {
        if (!unreadable.empty()) break;
        if (!before.contains(key)) unreadable = "no field \"" + key + "\"";
        // Found by a probe: "seed": "one" read as another search's, which no command could resume.
        else if (before[key].is_number() != value.is_number() || (!value.is_number() && before[key].type() != value.type()))
          unreadable = "field \"" + key + "\" is " + std::string(before[key].type_name()) + ", where a search writes " +
                       value.type_name();
      }
    } catch (const nlohmann::json::exception& e) {
      unreadable = "not valid JSON: " + json_error_text(e.what());
    }
  }
  if (settings_lost && o.progress)
    *o.progress << "roger propose: " << o.out << " holds a search's files and no settings.json: it is written with "
                << "this search's settings; the folder's records are reused where they are this search's\n";
  if (!unreadable.empty() && o.progress)
    *o.progress << "roger propose: " << file << " cannot be read (" << unreadable << "): written again with this "
                << "search's settings; the folder's records are reused where they are this search's\n";
  if (fs::exists(file) && unreadable.empty()) {
    // Each difference by the option that sets it (found by a probe: "budget_s 3000.0 there").
    const auto option = [](std::string key) {
      if (key == "curriculum") return key;
      if (key == "budget_s") key = "budget";
      std::replace(key.begin(), key.end(), '_', '-');
      return "--" + key;
    };
    // Whole numbers as written (found by a probe: seeds past 2^53 both read 1.8446744073709552e+19).
    const auto shown = [](const nlohmann::json& v) {
      return v.is_number_integer() ? v.dump() : v.is_number() ? format_number(v.get<double>())
                                              : v.is_string() ? v.get<std::string>() : v.dump();
    };
    std::string differ;
    for (const auto& [key, value] : search.items())
      if (before[key] != value)
        differ += (differ.empty() ? "" : ", ") + option(key) + " " + shown(before[key]) + " there, " + shown(value) +
                  " here";
    if (!differ.empty())
      throw Error("roger propose: " + o.out + " holds another search (" + differ +
                  "); give another --out, or the same settings to resume it");
  }
  write_file_atomic(file, search.dump(1) + "\n", "cannot write the search's settings");
}

// One training run of a candidate, from its record when an earlier run wrote it: the trial of `spec` with this seed, run for at most cap_s simulated s (or read from its record at
// `file`). A trial that did not reach the threshold scores on score_cap_s, its round's cap, which
// the budget may have cut cap_s below: the record keeps the loss the ranking uses.
CandidateTrial run_trial(const ProposeOptions& o, const CandidateSpec& spec, const std::string& sources, uint64_t seed,
                         double cap_s, double score_cap_s, const std::string& file,
                         std::vector<std::string>* unreadable, int* stale) {
  const std::string hash = text_hash(spec.lua + sources);
  if (fs::exists(file)) {
    // A record of another candidate text or cap (a curriculum edited since) is run again, and
    // counted; an unreadable one (records are written atomically, so a disk fault or an edit) is said.
    std::string why;
    try {
      const nlohmann::json j = parse_json(read_file_text(file));
      if (j.at("hash") == hash && j.at("seed") == seed && j.at("cap_s") == cap_s) {
        CandidateTrial tr;
        tr.seed = seed;
        tr.cap_s = cap_s;
        tr.score_cap_s = score_cap_s;
        tr.spent_s = j.at("spent_s").get<double>();
        tr.skills_s = j.at("skills_s").get<double>();
        tr.reached = j.at("reached").get<bool>();
        tr.time_s = j.at("time_s").get<double>();
        tr.last_success = j.at("last_success").get<double>();
        tr.loss = j.at("loss").get<double>();
        // The loss is what the record's other numbers give (found by a probe: a loss edited beside
        // reached = true and its time was ranked as written).
        const double recorded_cap = j.value("score_cap_s", score_cap_s);
        const bool loss_agrees = tr.loss == (tr.reached ? tr.time_s : recorded_cap * (2.0 - tr.last_success));
        // A record of a round cap since changed (a longer --budget) scores on this one.
        if (!tr.reached) tr.loss = score_cap_s * (2.0 - tr.last_success);
        tr.checkpoints = j.value("checkpoints", -1);
        tr.cut = j.value("cut", "");
        tr.cut_reached = j.value("cut_reached", false);
        tr.reused = true;
        // Numbers no trial gives (damaged, or edited by hand) make the record unreadable: run again.
        const bool sound = std::isfinite(tr.spent_s) && tr.spent_s >= 0 && std::isfinite(tr.skills_s) &&
                           tr.skills_s >= 0 && tr.skills_s <= tr.spent_s && std::isfinite(tr.time_s) && tr.time_s >= 0 &&
                           (!tr.reached || tr.time_s <= tr.spent_s) && std::isfinite(tr.last_success) &&
                           tr.last_success >= 0 && tr.last_success <= 1 && std::isfinite(tr.loss) && loss_agrees;
        if (sound) return tr;
        why = "numbers no trial gives";
      } else {
        ++*stale;
      }
    } catch (const nlohmann::json::exception& e) {
      why = json_error_text(e.what());
    } catch (const std::exception& e) {
      why = e.what();
    }
    if (!why.empty()) note_unreadable(o, file, why, unreadable);
  }
  TrainOptions t;
  t.curriculum = spec.c.file;
  t.stage = o.stage;
  t.context = "P";
  t.seed = seed;
  t.limits = o.limits;
  t.keep_episodes = false;
  t.max_sim_s = cap_s;
  t.final_evaluation = false;
  const TrainResult r = train_stage(t);
  CandidateTrial tr;
  tr.seed = seed;
  tr.cap_s = cap_s;
  tr.score_cap_s = score_cap_s;
  for (const auto& s : r.skills)
    if (s.trained) tr.skills_s += s.totals.sim_s;
  // The cap ends one stage at most: with no task episode, the last skill trained (r.skills is in
  // training order, a skill's own skills first) was still training when it ran out.
  if (r.totals.episodes == 0 && !r.skills.empty() && r.skills.back().trained) {
    tr.cut = r.skills.back().name;
    tr.cut_reached = r.skills.back().reached;
  }
  tr.spent_s = tr.skills_s + r.totals.sim_s;
  tr.reached = r.reached;
  tr.time_s = tr.skills_s + r.to_threshold.sim_s;
  tr.last_success = r.checkpoints.empty() ? 0.0 : r.checkpoints.back().success_rate;
  tr.checkpoints = int(r.checkpoints.size());
  // A subgoal stage is trained as roger train trains it, so that the trial stays a prefix of the
  // candidate's own training; one that has not learned its subgoal (met its stop rule) within the
  // cap leaves the task none of it. The candidate then did not reach the threshold within the cap,
  // and scores 2 x cap as a task that never passed: cutting the subgoal stage short to test the
  // task would test a skill the proposal never hands over. What must not be silent is why: tr.cut.
  // A trial the budget cut short scores on its round's cap all the same (found by a probe: the last
  // candidate's trial, cut to 3.6 of 20.3 s, scored 7.3 against the others' 40.6 for the same 0% and
  // won the search); its record said the cut cap's loss while the ranking used the other.
  tr.loss = tr.reached ? tr.time_s : score_cap_s * (2.0 - tr.last_success);
  const nlohmann::json j = {{"format", "roger-propose-trial"}, {"candidate", spec.c.id}, {"hash", hash},
                            {"seed", seed}, {"cap_s", cap_s}, {"score_cap_s", score_cap_s}, {"spent_s", tr.spent_s},
                            {"skills_s", tr.skills_s}, {"reached", tr.reached}, {"time_s", tr.time_s}, {"last_success", tr.last_success},
                            {"checkpoints", tr.checkpoints}, {"cut", tr.cut}, {"cut_reached", tr.cut_reached},
                            {"loss", tr.loss}};
  write_file_atomic(file, j.dump(1) + "\n", "cannot write the trial record");
  return tr;
}

// A trial's outcome on the console: when the cap ended a subgoal stage, which one and where (the
// task never trained, so "not reached" alone would hide that it was never tested).
std::string outcome_text(const CandidateTrial& tr) {
  if (tr.reached) return "reached after " + std::to_string(int(std::lround(tr.time_s))) + " s";
  if (!tr.cut.empty()) return "not reached (" + cut_text(tr) + ")";
  return "not reached";
}

// Cautions on the trials of round `round` whose subgoal stage the cap ended, so that the task never
// trained: their loss of 2 x cap says the candidate's subgoal stages need more than the cap, not
// how its task learns, and a reader of the ranking should know which losses those are.
void note_cut(const std::vector<CandidateSpec>& specs, const std::vector<size_t>& alive, int round,
              ProposeResult& res) {
  for (size_t i : alive) {
    int trials = 0;
    std::vector<std::string> cuts;
    for (const auto& t : specs[i].c.trials) {
      if (t.round != round) continue;
      ++trials;
      if (!t.cut.empty()) cuts.push_back(cut_text(t));
    }
    if (cuts.empty()) continue;
    // Each reason once, with how many trials it ended (found by a probe: with --trials 100 one
    // reason came 100 times in a line of 5896 characters).
    // Found by a later probe: a reason of two trials was said twice, since the reasons kept had
    // their counts appended: the distinct ones are looked up apart.
    std::vector<std::string> distinct, reasons;
    for (const std::string& c : cuts) {
      if (std::find(distinct.begin(), distinct.end(), c) != distinct.end()) continue;
      distinct.push_back(c);
      const auto n = std::count(cuts.begin(), cuts.end(), c);
      reasons.push_back(n > 1 ? c + ", in " + std::to_string(n) + " of them" : c);
    }
    res.cautions.push_back("round " + std::to_string(round) + ": " + specs[i].c.id + "'s task never trained in " +
                           std::to_string(cuts.size()) + " of its " + counted(trials, "trial") + " (" + join(reasons, "; ") +
                           "), which scored 2 x cap untested");
  }
}

// Cautions on round `round` (alive sorted by score, the first `keep` going on): a round none of
// whose trials ran a checkpoint ranked on equal losses, and a cut inside a tie was decided by the
// candidates' order (stable_sort). A probe found both only by reading every trial's record.
void note_round(const ProposeOptions& o, const TaskRef& task, const std::vector<CandidateSpec>& specs,
                const std::vector<size_t>& alive, size_t keep, int round, double cap, ProposeResult& res) {
  bool any_checkpoint = false;
  for (size_t i : alive)
    for (const auto& t : specs[i].c.trials)
      if (t.round == round && (t.checkpoints != 0 || t.reached)) any_checkpoint = true;
  if (!any_checkpoint) {
    const double interval_s = task.checkpoint_every * task.time_limit;
    res.cautions.push_back(
        "round " + std::to_string(round) + ": no trial ran a checkpoint: its cap of " + format_number(std::round(cap)) +
        " simulated s is under the " + format_number(std::round(interval_s)) + " s a checkpoint can take (every " +
        counted(task.checkpoint_every, "training episode") + ", each up to " + format_number(task.time_limit) +
        " s), so every loss was the same and the candidates' order decided which went on; a --budget of about " +
        format_number(std::ceil(o.budget_s * interval_s / cap)) + " gives this round's trials one checkpoint each");
    return;
  }
  if (keep >= alive.size() || specs[alive[keep - 1]].c.score != specs[alive[keep]].c.score) return;
  // Every tied candidate on each side of the cut (found by a probe: the caution named the two beside
  // it, "C2 did, C3 did not", where C1 went on too and C4, C6 and C8 were dropped too).
  std::vector<std::string> tied, went_on, dropped;
  for (size_t k = 0; k < alive.size(); ++k) {
    if (specs[alive[k]].c.score != specs[alive[keep]].c.score) continue;
    tied.push_back(specs[alive[k]].c.id);
    (k < keep ? went_on : dropped).push_back(specs[alive[k]].c.id);
  }
  char loss[32];
  std::snprintf(loss, sizeof loss, "%.1f", specs[alive[keep]].c.score);
  res.cautions.push_back("round " + std::to_string(round) + ": " + join(tied) + " tied at a mean loss of " + loss +
                         " where the round cut, and the candidates' order decided which went on (" + join(went_on) +
                         (went_on.size() == 1 ? " did, " : " did; ") + join(dropped) + " did not)");
}

// The folder as a fresh run of this search leaves it: a record or candidate of an earlier run of it
// that this one did not write or reuse (its scenario edited since, other candidates) is removed
// (found by a probe: candidates/C5.lua and C6.lua stayed, valid curricula of candidates
// propose.md no longer names).
void remove_stale_records(const ProposeOptions& o, const ProposeResult& res) {
  std::set<std::string> kept;  // "folder/name"
  for (const Candidate& c : res.candidates) {
    kept.insert("candidates/" + fs::path(c.file).filename().string());
    for (const CandidateTrial& t : c.trials) kept.insert("trials/" + trial_file_name(c.id, t.round, t.index));
  }
  for (int k = 0; k < o.probe_trials; ++k) kept.insert("probe/" + probe_file_name(k));
  // Only names a search writes: a file of the user's own there (notes, an edited candidate) stays
  // (found by a probe: trials/my_analysis.txt and candidates/my_edit.lua vanished on a resume).
  static const std::map<std::string, std::regex> own = {{"candidates", std::regex(R"(C[0-9]+\.lua)")},
                                                        {"trials", std::regex(R"(C[0-9]+-r[0-9]+-t[0-9]+\.json)")},
                                                        {"probe", std::regex(R"(probe-[0-9]+\.json)")}};
  for (const auto& [folder, names] : own) {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(fs::path(o.out) / folder, ec)) {
      const std::string name = entry.path().filename().string();
      if (entry.is_regular_file(ec) && std::regex_match(name, names) && !kept.count(folder + "/" + name))
        fs::remove(entry.path(), ec);
    }
  }
}

// A round the budget ran out in, before each of its candidates had its trials (the probe took more
// than its share: its trials end an episode past their caps): it ranks nothing, the scores stay the
// last complete round's, and the search ends there, saying so (found by a probe: caps of -0 s,
// "a --budget of about -849056", candidates scored inf, one dropped after no trial at all).
void note_budget_out(const std::vector<CandidateSpec>& specs, const std::vector<size_t>& alive, int r, int rounds,
                     double cap, int trials, double time_limit, ProposeResult& res) {
  const std::string spent = "(" + format_number(std::round(res.spent_s)) + " of the budget's " +
                            format_number(std::round(res.budget_s)) + " simulated s spent, " +
                            format_number(std::round(res.probe_s)) + " by the probe)";
  // Where a round's trials (not the probe) spent the budget: what they were allowed, and what won.
  const std::string allowed = "round " + std::to_string(r + 1) + "'s trials were each allowed " +
                              format_number(std::round(cap * 100) / 100) + " simulated s (what the rounds had left " +
                              "over " + counted(long(alive.size()), "candidate") + " x --trials " +
                              std::to_string(trials) + ")";
  const std::string outcome = (r == 0 ? "no round ranked the candidates, and " + specs[alive.front()].c.id +
                                            " (the base) wins by default"
                                      : "the winner is the best of round " + std::to_string(r)) +
                              "; fewer --trials, or a larger --budget, ranks them";
  // A cap under one episode that fewer trials would have raised past it: the trials, each running
  // one at least, overran it (found by a probe: --trials 100 was blamed on the probe, which took its
  // 20%). Under an episode even for one trial, what the probe left is to blame.
  if (cap < time_limit && cap * trials >= time_limit) {
    res.cautions.push_back(allowed + ", under one episode of the stage's time limit of " + format_number(time_limit) +
                           " s, and each runs one at least, so the budget ran out within the round " + spent + ": " +
                           outcome);
    return;
  }
  // Each trial runs on to the end of the episode that passes its cap, so with many trials the
  // round's overruns add up past its share (found by a probe: --trials 100 with caps of 48 s ran
  // 191 of 200 trials, and the caution blamed the probe, which the caps had already left out).
  double overrun = 0.0;
  int ran = 0;
  for (size_t i : alive)
    for (const CandidateTrial& t : specs[i].c.trials)
      if (t.round == r + 1) overrun += std::max(0.0, t.spent_s - t.cap_s), ++ran;
  if (cap >= time_limit && overrun > 0.0) {
    res.cautions.push_back(allowed + ", and each runs on to the end of the episode that passes its cap (the stage's "
                           "time limit is " + format_number(time_limit) + " s): the " + std::to_string(ran) +
                           " trials run overran their caps by " + format_number(std::round(overrun)) +
                           " s together, so the budget ran out within the round " + spent + ": " + outcome);
    return;
  }
  if (r == 0) {
    res.cautions.push_back("the probe left the " + counted(rounds, "round") + " of successive halving no budget for " +
                           "each candidate's trials " + spent + ": no round ranked the candidates, and " +
                           specs[alive.front()].c.id + " (the base) wins by default; a larger --budget, or a smaller "
                           "--probe-share or --probe-trials, ranks them");
    return;
  }
  res.cautions.push_back("round " + std::to_string(r + 1) + " of " + std::to_string(rounds) + " ran out of budget " +
                         "before each of its candidates had its trials " + spent + ": it ranked nothing, and the " +
                         "winner is the best of round " + std::to_string(r));
}

// Candidate `spec`'s trials of round `round` (from 1; of `rounds`), each capped at `cap` and at what
// the budget has left, until the budget is spent; added to the candidate and returned. A trial that
// did not reach the threshold scores on `cap`.
std::vector<CandidateTrial> round_trials(const ProposeOptions& o, const TaskRef& task, CandidateSpec& spec, int round,
                                         int rounds, double cap, ProposeResult& res) {
  std::vector<CandidateTrial> now;
  for (int j = 1; j <= o.trials; ++j) {
    const double allowed = std::min(cap, res.budget_s - res.spent_s);
    if (allowed <= 0.0) break;  // the budget is spent
    const uint64_t seed = Rng::mix(o.seed, 0x747269616cull + uint64_t((round - 1) * o.trials + j - 1));
    const std::string file = (fs::path(o.out) / "trials" / trial_file_name(spec.c.id, round, j)).string();
    CandidateTrial tr = run_trial(o, spec, task.sources, seed, allowed, cap, file, &res.unreadable, &res.stale_records);
    tr.round = round;
    tr.index = j;
    res.spent_s += tr.spent_s;
    (tr.reused ? res.trials_reused : res.trials_run) += 1;
    if (o.progress) {
      char line[512];
      std::snprintf(line, sizeof line, "round %d/%d %s trial %d: %s, loss %.0f, spent %.0f of %.0f simulated s%s\n",
                    round, rounds, spec.c.id.c_str(), j, outcome_text(tr).c_str(), tr.loss, res.spent_s, res.budget_s,
                    tr.reused ? " (reused)" : "");
      *o.progress << line << std::flush;
    }
    spec.c.trials.push_back(tr);
    now.push_back(tr);
  }
  return now;
}

// The successive halving of Karnin et al. (2013) as Jamieson and Talwalkar (2016) use it: ceil(log2 n)
// rounds, each given an equal share of what budget remains; in a round every survivor runs
// options.trials seeded trials capped at an equal share of it, and the better half (by mean loss)
// goes on. Every trial's simulated seconds are counted; a trial is capped at what remains.
void successive_halving(const ProposeOptions& o, const TaskRef& task, std::vector<CandidateSpec>& specs,
                        ProposeResult& res) {
  std::vector<size_t> alive;
  for (size_t i = 0; i < specs.size(); ++i)
    if (specs[i].c.evaluated) alive.push_back(i);
  const int rounds = alive.size() > 1 ? int(std::ceil(std::log2(double(alive.size())))) : 0;
  res.rounds = res.planned_rounds = rounds;
  for (int r = 0; r < rounds && alive.size() > 1; ++r) {
    const double cap = (res.budget_s - res.spent_s) / double(rounds - r) / double(alive.size() * size_t(o.trials));
    std::vector<double> before;  // the scores the last complete round gave
    for (size_t i : alive) before.push_back(specs[i].c.score);
    bool complete = cap > 0.0;
    for (size_t k = 0; complete && k < alive.size(); ++k) {
      CandidateSpec& spec = specs[alive[k]];
      const std::vector<CandidateTrial> now = round_trials(o, task, spec, r + 1, rounds, cap, res);
      complete = now.size() == size_t(o.trials);
      if (complete)
        spec.c.score = std::accumulate(now.begin(), now.end(), 0.0,
                                       [](double a, const CandidateTrial& t) { return a + t.loss; }) / double(now.size());
    }
    if (!complete) {
      for (size_t k = 0; k < alive.size(); ++k) specs[alive[k]].c.score = before[k];
      note_budget_out(specs, alive, r, rounds, cap, o.trials, task.time_limit, res);
      res.rounds = r;
      break;
    }
    note_cut(specs, alive, r + 1, res);
    std::stable_sort(alive.begin(), alive.end(), [&](size_t a, size_t b) { return specs[a].c.score < specs[b].c.score; });
    const size_t keep = (alive.size() + 1) / 2;
    note_round(o, task, specs, alive, keep, r + 1, cap, res);
    for (size_t k = keep; k < alive.size(); ++k) specs[alive[k]].c.eliminated_round = r + 1;
    alive.resize(keep);
  }
  res.winner = alive.empty() ? 0 : int(alive.front());
}

// The task of the search: the stage and context, checked as roger check checks them (every
// refusal at once), and what its records must match. Sets o.context when it was left to the first.
TaskRef read_task(ProposeOptions& o) {
  TaskRef task;
  // A scenario or a batch script fails inside Curriculum::load: say what it is instead.
  require_script_kind(o.curriculum, resolve_curriculum_path(o.curriculum), {"curriculum"});
  const Curriculum cur = Curriculum::load(o.curriculum, o.limits);
  const CurriculumStage& stage = cur.stage(o.stage);
  if (o.context.empty()) o.context = stage.contexts.front().name;
  const CurriculumContext& ctx = stage.context(o.context);
  const double time_limit = stage_time_limit(stage, o.limits);
  // Every refusal at once, the command's own mistakes first: one run says all there is to mend.
  std::vector<std::string> refusals;
  collect_refusal(refusals, [&] { check_options(o, time_limit); });
  collect_refusal(refusals, [&] { check_context(stage, ctx); });
  // The stage as roger check checks it, its worlds built: a context whose world cannot be built
  // failed inside the probe, after settings.json was written, at the scenario library's line
  // (found by a probe); roger check names the curriculum's.
  collect_refusal(refusals, [&] {
    const std::vector<std::string> problems = check_curriculum(o.curriculum, o.limits, {}, {stage.name});
    if (!problems.empty()) throw Error(join(problems, "\n"));
  });
  collect_refusal(refusals, [&] { task.module = module_name(cur.file(), o.out); });
  refuse(refusals);
  task.stop_after = stage.checkpoints.stop_after;
  task.checkpoint_every = stage.checkpoints.every > 0 ? stage.checkpoints.every : std::max(1, stage.budget_episodes / 20);
  task.time_limit = time_limit;
  task.scenario = scenario_from_project(stage.scenario);
  task.context_params = !ctx.params.empty();
  // Every Lua file the task reads, and the library the proposals are written with: records
  // made with other versions of any of them are not reused.
  std::string text;
  for (const auto& f : curriculum_source_files(cur, o.limits)) text += read_file_text(f.string());
  text += read_file_text((project_root() / "curricula" / "lib" / "propose.lua").string());
  task.sources = text_hash(text);
  task.stage = stage.name;
  task.context = ctx.name;
  return task;
}

// The command that runs this search again.
std::string search_command(const ProposeOptions& o, const TaskRef& task) {
  const auto number = [](double v) {
    char text[64];
    std::snprintf(text, sizeof text, "%g", v);
    return std::string(text);
  };
  // The curriculum by its module name, as settings.json keeps it: the same search however the
  // command spelt it (found by a probe: paper, curricula/paper.lua and an absolute path wrote three
  // candidate headers, whose hashes matched no record, and a resume ran every trial again).
  std::string command = "roger propose " + task.module + " --stage " + o.stage + " --context " + task.context +
                        " --budget " + number(o.budget_s) + " --seed " + std::to_string(o.seed);
  // The options that differ from their defaults, so that the command given runs this search again.
  const ProposeOptions defaults;
  if (o.trials != defaults.trials) command += " --trials " + std::to_string(o.trials);
  if (o.probe_trials != defaults.probe_trials) command += " --probe-trials " + std::to_string(o.probe_trials);
  if (o.probe_share != defaults.probe_share) command += " --probe-share " + number(o.probe_share);
  if (o.max_candidates != defaults.max_candidates)
    command += " --max-candidates " + std::to_string(o.max_candidates);
  if (o.prune_below != defaults.prune_below) command += " --prune-below " + number(o.prune_below);
  return command;
}

// The winning candidate, written as proposal.lua with a header that says where it came from.
void write_proposal(const ProposeOptions& o, const std::vector<CandidateSpec>& specs, ProposeResult& res) {
  const CandidateSpec& win = specs[size_t(res.winner)];
  std::string text = win.lua;
  text = "-- proposal.lua: the curriculum roger propose proposes (its candidate " + win.c.id +
         "; propose.md beside it says why it won)\n" + text.substr(text.find('\n') + 1);
  res.proposal_file = (fs::path(o.out) / "proposal.lua").string();
  write_file_atomic(res.proposal_file, text, "cannot write the proposal");
}

}  // namespace

std::string rounds_said(const ProposeResult& r) {
  if (r.rounds >= r.planned_rounds) return counted(r.rounds, "round");
  return std::to_string(r.rounds) + " of " + counted(r.planned_rounds, "round");
}

ProposeResult propose_curriculum(const ProposeOptions& options) {
  ProposeOptions o = options;
  TaskRef task = read_task(o);
  claim_search_folder(o, task.module, task.stage, task.context);
  task.command = search_command(o, task);

  ProposeResult res;
  res.budget_s = o.budget_s;
  int probes_reused = 0;
  const ProbeStats probe = run_probe(o, task.context, task.sources, o.budget_s * o.probe_share / o.probe_trials, &probes_reused,
                                    &res.unreadable, &res.stale_records);
  res.probe_s = probe.sim_s;
  res.spent_s = probe.sim_s;
  res.successful_episodes = int(probe.successes.size());
  res.probe_episodes = probe.episodes;
  const ProbeSummary summary = summarize_probe(probe);

  std::vector<CandidateSpec> specs = generate_candidates(task, probe, summary, o.prune_below);
  for (size_t i = 0; i < specs.size(); ++i) {
    Candidate& c = specs[i].c;
    c.file = (fs::path(o.out) / "candidates" / (c.id + ".lua")).string();
    c.evaluated = int(i) < o.max_candidates;
    write_file_atomic(c.file, specs[i].lua, "cannot write the candidate curriculum");
  }
  successive_halving(o, task, specs, res);

  write_proposal(o, specs, res);
  for (auto& s : specs) res.candidates.push_back(std::move(s.c));
  res.report_file = (fs::path(o.out) / "propose.md").string();
  o.context = task.context;
  write_propose_report(o, task, probe, summary, res);
  remove_stale_records(o, res);
  return res;
}

}  // namespace roger
