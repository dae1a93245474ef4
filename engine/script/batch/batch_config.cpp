// batch_config.cpp: a batch script's resolved configuration as the JSON a results folder's
// manifest keeps, and read back from it for `roger report` (checked: the manifest is a file anyone
// can edit or damage, and the report follows its references).
#include <algorithm>
#include <string>

#include "core/error.h"
#include "core/text.h"
#include "script/batch/batch_script.h"
#include "script/batch/batch_script_internal.h"

namespace roger {

using json = nlohmann::json;

namespace {

json params_json(const Params& p) {
  json j = json::array();
  for (const auto& [k, v] : p) j.push_back({k, v});
  return j;
}

// A "run/context" row of a comparison.
BatchRow row_from(const json& j) {
  const std::string text = j.get<std::string>();
  const size_t slash = text.find('/');
  if (slash == std::string::npos) throw Error("the manifest's configuration: a comparison row is \"run/context\", got " + j.dump());
  return {text.substr(0, slash), text.substr(slash + 1)};
}

Params params_from(const json& j) {
  Params p;
  for (const auto& e : j) p.emplace_back(e.at(0).get<std::string>(), e.at(1).get<std::string>());
  return p;
}

}  // namespace

json batch_config_json(const BatchScript& b) {
  json runs = json::array(), evals = json::array(), tables = json::array(), figures = json::array();
  for (const auto& r : b.runs) {
    json skills = json::array();
    for (const auto& s : r.skills) skills.push_back({{"skill", s.skill}, {"run", s.run}, {"context", s.context}});
    json rj = {{"name", r.name}, {"stage", r.stage}, {"contexts", r.contexts}, {"trials", r.trials},
               {"params", params_json(r.params)}, {"skills", skills}};
    // Written only when "own", so the configuration of a run without it reads as before.
    if (r.own_final_worlds) rj["final_worlds"] = "own";
    runs.push_back(std::move(rj));
  }
  for (const auto& e : b.evaluations) {
    json ej = {{"name", e.name}, {"run", e.run}, {"context", e.context}, {"scenario", e.scenario},
               {"params", params_json(e.params)}, {"shapes", e.shapes}, {"episodes", e.episodes},
               {"first_seed", e.first_seed}, {"worlds", e.shared_worlds ? "shared" : "own"},
               {"trials", e.trials}};
    // Written only when given, so the configuration of an evaluation without them reads as before.
    for (const auto& s : e.skills) ej["skills"].push_back({{"skill", s.skill}, {"run", s.run}, {"context", s.context}});
    evals.push_back(std::move(ej));
  }
  for (const auto& t : b.tables) {
    json usage = json::array();
    for (const auto& u : t.usage) usage.push_back({{"context", u.context}, {"skill", u.skill}, {"subsumes", u.subsumes}});
    json table = {{"title", t.title}, {"run", t.run}, {"baseline", t.baseline}, {"evaluation", t.evaluation},
                  {"usage", usage}};
    for (const auto& r : t.sorting)
      table["sorting"].push_back({{"objects", r.objects}, {"learned", r.learned}, {"hand", r.hand}});
    // Written only when given, so the configuration of a script without them reads as before.
    for (const auto& r : t.compare) table["compare"].push_back(r.label());
    if (!t.by.empty()) table["by"] = t.by;
    tables.push_back(std::move(table));
  }
  for (const auto& f : b.figures) {
    json fig = {{"file", f.file}, {"title", f.title}, {"kind", f.kind}, {"run", f.run}, {"log_x", f.log_x}};
    for (const auto& r : f.compare) fig["compare"].push_back(r.label());
    if (f.y != "reward") fig["y"] = f.y;
    if (f.kind == "tasks") fig["context"] = f.context, fig["param"] = f.param;
    figures.push_back(std::move(fig));
  }
  // The budgets every script of the run had: a result made under other limits may differ (a trial
  // that failed for its budget, or one that passed only with a larger one), so they are part of
  // the folder's configuration and a run under other limits does not resume into it.
  const json limits = {{"instructions", b.limits.instructions}, {"memory_mib", b.limits.memory_bytes >> 20}};
  return {{"name", b.name}, {"description", b.description}, {"curriculum", b.curriculum},
          {"curriculum_file", b.curriculum_file}, {"trials", b.trials}, {"seed", b.seed},
          {"params", params_json(b.params)}, {"limits", limits}, {"runs", runs}, {"evaluations", evals},
          {"tables", tables}, {"figures", figures}};
}

namespace {

// An integer field of the manifest's configuration in [lo, hi]. Not get<int>(): converting 1e300
// to int is undefined behaviour, and a negative or huge count would plan absurd trials.
int64_t config_integer(const json& j, const char* key, int64_t lo, int64_t hi) {
  const json& v = j.at(key);
  if (!v.is_number_integer() || (v.is_number_unsigned() && v.get<uint64_t>() > uint64_t(hi)) ||
      v.get<int64_t>() < lo || v.get<int64_t>() > hi)
    throw Error(std::string("the manifest's configuration: field \"") + key + "\" must be an integer in [" +
                std::to_string(lo) + ", " + std::to_string(hi) + "], got " + v.dump());
  return v.get<int64_t>();
}

// The references between runs, evaluations, tables and figures that load_batch_script checked when
// the manifest was written: the report follows them without looking, so a hand-edited or damaged
// manifest is refused here instead of crashing it.
void check_config_references(const BatchScript& b) {
  auto fail = [](const std::string& what) {
    throw Error("the manifest's configuration is inconsistent: " + what);
  };
  auto evaluation = [&](const std::string& name) {
    return std::any_of(b.evaluations.begin(), b.evaluations.end(), [&](const auto& e) { return e.name == name; });
  };
  // A comparison's row names a run and one of its contexts.
  auto context_of = [&](const BatchRow& row, const std::string& who) {
    const BatchRun* r = b.run(row.run);
    if (!r || std::find(r->contexts.begin(), r->contexts.end(), row.context) == r->contexts.end())
      fail(who + " names '" + row.label() + "', which it lacks");
  };
  // A name that names a folder or a file of the results passed results_name when the script was
  // read; an edited manifest's may not (found by a probe: a figure's file "../../pwn" made the report
  // write outside the folder, a run "../../zz" sent it to read trials elsewhere).
  auto folder_name = [&](const std::string& name, const std::string& what) {
    if (!results_name(name))
      fail(what + " '" + name + "' is not a name for the results' folders and files (letters, digits, '_', '.' "
           "and '-', at most 200 characters)");
  };
  for (const auto& r : b.runs) {
    folder_name(r.name, "run");
    for (const auto& c : r.contexts) folder_name(c, "run '" + r.name + "': context");
  }
  for (const auto& e : b.evaluations) {
    folder_name(e.name, "evaluation");
    for (const auto& s : e.shapes) folder_name(s, "evaluation '" + e.name + "': shape");
  }
  for (const auto& f : b.figures) folder_name(f.file, "figure file");
  for (const auto& r : b.runs)
    for (const auto& s : r.skills)
      if (!b.run(s.run)) fail("run '" + r.name + "' takes a skill from run '" + s.run + "', which it lacks");
  for (const auto& e : b.evaluations) {
    if (!b.run(e.run)) fail("evaluation '" + e.name + "' names run '" + e.run + "', which it lacks");
    for (const auto& s : e.skills)
      if (!b.run(s.run)) fail("evaluation '" + e.name + "' takes a skill from run '" + s.run + "', which it lacks");
  }
  for (const auto& t : b.tables) {
    for (const auto& r : t.sorting)
      for (const std::string* name : {&r.learned, &r.hand})
        if (!name->empty() && !b.run(*name)) fail("table '" + t.title + "' names run '" + *name + "', which it lacks");
    if (!t.sorting.empty()) continue;
    if (!t.compare.empty()) {
      for (const auto& r : t.compare) context_of(r, "table '" + t.title + "'");
      continue;
    }
    if (t.run.empty() ? !evaluation(t.evaluation) : !b.run(t.run))
      fail("table '" + t.title + "' names " + (t.run.empty() ? "evaluation '" + t.evaluation : "run '" + t.run) +
           "', which it lacks");
  }
  for (const auto& f : b.figures) {
    if (!b.run(f.run)) fail("figure '" + f.file + "' names run '" + f.run + "', which it lacks");
    if (f.kind != "curves" && f.kind != "cumulative" && f.kind != "tasks")
      fail("figure '" + f.file + "' is of kind '" + f.kind + "', not curves, cumulative or tasks");
    for (const auto& r : f.compare) context_of(r, "figure '" + f.file + "'");
    if (f.kind == "tasks") context_of({f.run, f.context}, "figure '" + f.file + "'");
  }
}

// The learned skills a run or an evaluation takes from earlier runs.
std::vector<BatchSkill> skills_from(const json& list) {
  std::vector<BatchSkill> skills;
  for (const auto& s : list) skills.push_back({s.at("skill"), s.at("run"), s.at("context")});
  return skills;
}

// A run of the manifest's configuration.
BatchRun run_from(const json& rj) {
  BatchRun r;
  r.name = rj.at("name");
  r.stage = rj.at("stage");
  r.contexts = rj.at("contexts").get<std::vector<std::string>>();
  r.trials = int(config_integer(rj, "trials", 1, 100000));
  r.params = params_from(rj.at("params"));
  r.skills = skills_from(rj.at("skills"));
  r.own_final_worlds = rj.value("final_worlds", std::string("shared")) == "own";
  return r;
}

// An evaluation of the manifest's configuration.
BatchEvaluation evaluation_from(const json& ej) {
  BatchEvaluation e;
  e.name = ej.at("name");
  e.run = ej.at("run");
  e.context = ej.at("context");
  e.scenario = ej.at("scenario");
  e.params = params_from(ej.at("params"));
  e.shapes = ej.at("shapes").get<std::vector<std::string>>();
  e.episodes = int(config_integer(ej, "episodes", 1, 1000000));
  e.first_seed = config_integer(ej, "first_seed", -1, int64_t(1) << 53);
  // Folders written before evaluations had worlds of their own shared them.
  e.shared_worlds = ej.value("worlds", std::string("shared")) != "own";
  e.trials = int(config_integer(ej, "trials", 1, 100000));
  if (ej.contains("skills")) e.skills = skills_from(ej.at("skills"));
  return e;
}

// A table of the manifest's configuration (`b`: the script read so far, for a default title).
BatchTable table_from(const json& tj, const BatchScript& b) {
  BatchTable t;
  t.title = tj.at("title");
  t.run = tj.at("run");
  t.baseline = tj.at("baseline");
  t.evaluation = tj.at("evaluation");
  for (const auto& u : tj.at("usage"))
    t.usage.push_back({u.at("context"), u.at("skill"), u.at("subsumes").get<std::vector<std::string>>()});
  for (const auto& r : tj.value("sorting", json::array()))
    t.sorting.push_back({int(config_integer(r, "objects", 1, 1000)), r.at("learned"), r.at("hand")});
  for (const auto& r : tj.value("compare", json::array())) t.compare.push_back(row_from(r));
  t.by = tj.value("by", std::string());
  // A folder written before tables had a title made when the script was read.
  if (t.title.empty()) t.title = batch_detail::default_title(t, b);
  return t;
}

// A figure of the manifest's configuration.
BatchFigure figure_from(const json& fj) {
  BatchFigure f;
  f.file = fj.at("file");
  f.title = fj.at("title");
  f.kind = fj.at("kind");
  f.run = fj.at("run");
  f.log_x = fj.at("log_x");
  for (const auto& r : fj.value("compare", json::array())) f.compare.push_back(row_from(r));
  f.y = fj.value("y", std::string("reward"));
  f.context = fj.value("context", std::string());
  f.param = fj.value("param", std::string());
  return f;
}

}  // namespace

BatchScript batch_config_from_json(const json& j) {
  BatchScript b;
  try {
    b.name = j.at("name");
    b.description = j.value("description", "");
    b.curriculum = j.at("curriculum");
    b.curriculum_file = j.value("curriculum_file", "");
    b.trials = int(config_integer(j, "trials", 1, 100000));
    b.seed = uint64_t(config_integer(j, "seed", 0, int64_t(1) << 53));
    b.params = params_from(j.at("params"));
    if (j.contains("limits")) {  // folders written before the limits were settable had the defaults
      b.limits.instructions = uint64_t(config_integer(j.at("limits"), "instructions", 1, int64_t(1) << 53));
      b.limits.memory_bytes = size_t(config_integer(j.at("limits"), "memory_mib", 1, int64_t(1) << 20)) << 20;
    }
    for (const auto& rj : j.at("runs")) b.runs.push_back(run_from(rj));
    for (const auto& ej : j.at("evaluations")) b.evaluations.push_back(evaluation_from(ej));
    for (const auto& tj : j.at("tables")) b.tables.push_back(table_from(tj, b));
    for (const auto& fj : j.at("figures")) b.figures.push_back(figure_from(fj));
  } catch (const json::exception& e) {
    throw Error(std::string("the manifest's configuration is incomplete or not from this version: ") + json_error_text(e.what()));
  }
  check_config_references(b);
  return b;
}

}  // namespace roger
