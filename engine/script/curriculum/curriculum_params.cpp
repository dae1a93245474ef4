// curriculum_params.cpp: a stage's and its contexts' scenario parameters checked against the
// stage's scenario where the curriculum is loaded, each bad one reported at the line of the
// `params` table that gives it (rather than later, by the trial or roger check, with no line).
#include <filesystem>
#include <optional>
#include <regex>
#include <tuple>

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
// whose line is its name's), else the last opened on that line with a `name` or `contexts` (in
// `return { stages = { roger.stage{` the stage's is the third), else the first; -1 if none. The
// curriculum's own table is no stage, though its name be on that line (found by a probe: in
// `return { name = "t", stages = { roger.stage{` every field's error stayed at the call's line).
int stage_node(const LuaTableMap& map, int line) {
  int opened = -1;
  for (size_t n = 0; n < map.nodes().size(); ++n) {
    if (map.entry(int(n), "stages")) continue;
    const auto* name = map.entry(int(n), "name");
    if (name && name->line == line) return int(n);
    if (map.nodes()[n].line == line && (name || map.entry(int(n), "contexts"))) opened = int(n);
  }
  return opened >= 0 ? opened : map.opened_on(line);
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

int params_line(const CurriculumStage& st, const std::string& context) { return field_line(st, context, "params"); }

int field_line(const CurriculumStage& st, const std::string& context, const std::string& field) {
  const std::string text = source_text(st.file);
  if (text.empty() || st.line <= 0) return st.line;
  const LuaTableMap map(text);
  const int stage = stage_node(map, st.line);
  if (stage < 0) return st.line;
  int node = stage, line = st.line;
  if (!context.empty()) std::tie(node, line) = context_node(map, stage, context, st.line);
  const auto* entry = map.entry(node, field);
  return entry ? entry->line : line;
}

namespace {

// Descends from `node` along a message's path of sub-tables ("learner: ", "context 2: ") to the
// constructor its field is written in; `line` follows to the deepest one found. The rest of the
// message is left in `rest`.
int descend(const LuaTableMap& map, int node, int& line, std::string& rest) {
  static const std::regex sub(R"(^(context (\d+)|[a-z_]+): (.*)$)");
  std::smatch m;
  while (node >= 0 && std::regex_match(rest, m, sub)) {
    int child = -1;
    if (m[2].matched) {  // "context 2": the second item of the contexts' list
      const auto* contexts = map.entry(node, "contexts");
      const int list = contexts ? map.value_node(*contexts) : -1;
      const size_t k = size_t(std::stoul(m[2].str()));
      if (list >= 0 && k >= 1 && k <= map.nodes()[size_t(list)].items.size())
        child = map.nodes()[size_t(list)].items[k - 1];
      if (child >= 0) line = map.nodes()[size_t(child)].line;
    } else if (const auto* e = map.entry(node, m[1].str())) {
      line = e->line;
      child = map.value_node(*e);
    } else {
      return node;  // a sentence, not a field's name: the field is in `node`
    }
    rest = m[3].str();
    if (child < 0) return -1;
    node = child;
  }
  return node;
}

}  // namespace

std::optional<ScriptError> at_stage_field(const ScriptError& e) {
  // Found by a probe: a stage's misspelt or ill-typed field was reported at its roger.stage{
  // line, however far below it was written. A table carries no lines; the text does.
  static const std::regex stage(R"(^stage '([^']*)'(?:, context '([^']*)')?: (.*)$)");
  std::smatch m;
  // A field's line only for an error of the roger.stage{...} call itself (raised in Lua, with a
  // traceback): one found when the returned table is read again may be of a field changed after
  // the call (a wrapper's paper.stages[2].budget = {...}), which the text does not show. A
  // context's line also for an error found later (an action's name, a learned skill no stage
  // yields), when the context is written in the stage's text.
  const bool in_call = !e.traceback.empty();
  if (e.file.empty() || e.line <= 0 || !std::regex_match(e.message, m, stage)) return std::nullopt;
  if (!in_call && !m[2].matched) return std::nullopt;
  const std::string text = source_text(e.file);
  if (text.empty()) return std::nullopt;
  const LuaTableMap map(text);
  int node = stage_node(map, e.line), line = e.line;
  if (node < 0 || map.nodes()[size_t(node)].line != e.line) return std::nullopt;  // raised elsewhere (a callback)
  if (m[2].matched) std::tie(node, line) = context_node(map, node, m[2].str(), line);
  if (!in_call) return node >= 0 ? std::optional<ScriptError>(ScriptError(e.message, e.file, line, "")) : std::nullopt;
  std::string rest = m[3].str();
  node = descend(map, node, line, rest);
  static const std::regex field(R"(^(?:unknown fields? |field )'([A-Za-z_][A-Za-z0-9_]*)')");
  // "tasks.goal_radius must be ...": the key's line in the field's table (found by a probe).
  static const std::regex dotted(R"(^([a-z_]+)\.([A-Za-z_][A-Za-z0-9_]*) )");
  std::smatch f;
  if (node >= 0 && std::regex_search(rest, f, field)) {
    if (const auto* entry = map.entry(node, f[1].str())) line = entry->line;
  } else if (node >= 0 && std::regex_search(rest, f, dotted)) {
    if (const auto* entry = map.entry(node, f[1].str())) {
      line = entry->line;
      const int table = map.value_node(*entry);
      if (const auto* key = table >= 0 ? map.entry(table, f[2].str()) : nullptr) line = key->line;
    }
  }
  if (line == e.line) return std::nullopt;
  // Without the traceback: it names the roger.stage{ call's line, which the text's line replaces
  // (found by a probe: a message at the context's line 39 above a traceback saying line 30).
  return ScriptError(e.message, e.file, line, "");
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
  refuse(scenario.param_problems(st.params, true), "");
  for (const auto& c : st.contexts) refuse(scenario.param_problems(c.params, true), c.name);
}

}  // namespace curriculum_detail
}  // namespace roger
