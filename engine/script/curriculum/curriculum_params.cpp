// curriculum_params.cpp: a stage's and its contexts' scenario parameters checked against the
// stage's scenario where the curriculum is loaded, each bad one reported at the line of the
// `params` table that gives it (rather than later, by the trial or roger check, with no line).
#include <filesystem>

#include "core/fileio.h"
#include "script/curriculum/curriculum_internal.h"
#include "script/sandbox/lua_tokens.h"
#include "script/scenario/scenario.h"

namespace roger {
namespace curriculum_detail {
namespace {

namespace fs = std::filesystem;

// The text of a script shown as `shown` (as given, or relative to the project), "" if unreadable.
std::string source_text(const std::string& shown) {
  if (shown.empty()) return "";
  std::error_code ec;
  const fs::path path = fs::is_regular_file(shown, ec) ? fs::path(shown) : project_root() / shown;
  if (!fs::is_regular_file(path, ec)) return "";
  try {
    return read_file_text(path.string());
  } catch (const std::exception&) {
    return "";
  }
}

// The stage's constructor: the one whose `name` is written on the stage's line (a plain table,
// whose line is its name's), else the first opened on that line (roger.stage{...}); -1 if none.
int stage_node(const LuaTableMap& map, int line) {
  for (size_t n = 0; n < map.nodes().size(); ++n) {
    const auto* name = map.entry(int(n), "name");
    if (name && name->line == line) return int(n);
  }
  return map.opened_on(line);
}

// The constructor of the context `name` in the stage's `contexts` (a list of {name = ..., ...} or
// a map name = {...}) and the line it is written on; {-1, fallback} when not written there.
std::pair<int, int> context_node(const LuaTableMap& map, int stage, const std::string& name, int fallback) {
  const auto* contexts = map.entry(stage, "contexts");
  if (!contexts) return {-1, fallback};
  const int list = map.value_node(*contexts);
  if (list < 0) return {-1, contexts->line};
  if (const auto* keyed = map.entry(list, name)) return {map.value_node(*keyed), keyed->line};
  for (int item : map.nodes()[size_t(list)].items) {
    const auto* n = map.entry(item, "name");
    if (n && n->value_text == name) return {item, map.nodes()[size_t(item)].line};
  }
  return {-1, contexts->line};
}

}  // namespace

int params_line(const CurriculumStage& st, const std::string& context) {
  const std::string text = source_text(st.file);
  if (text.empty() || st.line <= 0) return st.line;
  const LuaTableMap map(text);
  const int stage = stage_node(map, st.line);
  if (stage < 0) return st.line;
  int node = stage, line = st.line;
  if (!context.empty()) std::tie(node, line) = context_node(map, stage, context, st.line);
  const auto* params = map.entry(node, "params");
  return params ? params->line : line;
}

void check_stage_params(const CurriculumStage& st) {
  bool any = !st.params.empty();
  for (const auto& c : st.contexts) any = any || !c.params.empty();
  if (!any) return;  // nothing to check: no scenario to load
  const Scenario scenario = Scenario::load(st.scenario);
  auto refuse = [&](const std::vector<std::string>& problems, const std::string& context) {
    if (problems.empty()) return;
    throw ScriptError(st.where(context) + ": params: " + join(problems, "; "), st.file, params_line(st, context), "");
  };
  refuse(scenario.param_problems(st.params), "");
  for (const auto& c : st.contexts) refuse(scenario.param_problems(c.params), c.name);
}

}  // namespace curriculum_detail
}  // namespace roger
