// curriculum_params.cpp: a stage's and its contexts' scenario parameters checked against the
// stage's scenario where the curriculum is loaded, each bad one reported at the line of the
// `params` table that gives it (rather than later, by the trial or roger check, with no line).
#include <filesystem>
#include <optional>
#include <sstream>
#include <algorithm>
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

// The messages below are read by hand, not by std::regex: its matcher recurses once per character,
// and a message quoting a 100 KB string of a stage's overflowed the stack (found by a probe:
// `params = { shape = string.rep("x", 100000) }` crashed roger check).
struct MessageScan {
  const std::string& text;
  size_t at = 0;

  // Consumes `literal` if it comes next.
  bool take(const std::string& literal) {
    if (text.compare(at, literal.size(), literal) != 0) return false;
    at += literal.size();
    return true;
  }
  // Consumes the longest run of characters `in` accepts, if it has `first` at its head; "" if none.
  template <class First, class In>
  std::string take_run(First first, In in) {
    const size_t from = at;
    if (at < text.size() && first(text[at]))
      for (++at; at < text.size() && in(text[at]);) ++at;
    return text.substr(from, at - from);
  }
  // Consumes the text up to (not including) the next `c`; nullopt, consuming nothing, if none.
  std::optional<std::string> take_until(char c) {
    const size_t end = text.find(c, at);
    if (end == std::string::npos) return std::nullopt;
    std::string run = text.substr(at, end - at);
    at = end;
    return run;
  }
  // The rest of the text, if it is one line (as a regex's `.*$` took it).
  std::optional<std::string> rest_of_line() const {
    if (text.find_first_of("\r\n", at) != std::string::npos) return std::nullopt;
    return text.substr(at);
  }
};

bool is_lower_name_char(char c) { return (c >= 'a' && c <= 'z') || c == '_'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_identifier_head(char c) { return (c >= 'A' && c <= 'Z') || is_lower_name_char(c); }
bool is_identifier_char(char c) { return is_identifier_head(c) || is_digit(c); }

// A message's head naming a sub-table: "learner: rest" (name), or "context 2: rest" (context 2).
struct SubTableHead {
  std::string name;
  std::optional<size_t> context;  // 1-based, as written; none for a named sub-table
  std::string rest;
};

std::optional<SubTableHead> sub_table_head(const std::string& message) {
  MessageScan scan{message};
  SubTableHead head;
  if (scan.take("context ")) {
    const std::string digits = scan.take_run(is_digit, is_digit);
    if (!digits.empty() && scan.take(": ")) {
      const std::optional<std::string> rest = scan.rest_of_line();
      if (!rest) return std::nullopt;
      size_t k = 0;
      for (char d : digits) k = std::min<size_t>(k * 10 + size_t(d - '0'), 1u << 30);
      head.context = k;
      head.rest = *rest;
      return head;
    }
    scan.at = 0;
  }
  head.name = scan.take_run(is_lower_name_char, is_lower_name_char);
  if (head.name.empty() || !scan.take(": ")) return std::nullopt;
  const std::optional<std::string> rest = scan.rest_of_line();
  if (!rest) return std::nullopt;
  head.rest = *rest;
  return head;
}

// Descends from `node` along a message's path of sub-tables ("learner: ", "context 2: ") to the
// constructor its field is written in; `line` follows to the deepest one found. The rest of the
// message is left in `rest`.
int descend(const LuaTableMap& map, int node, int& line, std::string& rest) {
  while (node >= 0) {
    const std::optional<SubTableHead> head = sub_table_head(rest);
    if (!head) break;
    int child = -1;
    if (head->context) {  // "context 2": the second item of the contexts' list
      const size_t k = *head->context;
      const auto* contexts = map.entry(node, "contexts");
      const int list = contexts ? map.value_node(*contexts) : -1;
      if (list >= 0 && k >= 1 && k <= map.nodes()[size_t(list)].items.size())
        child = map.nodes()[size_t(list)].items[k - 1];
      if (child >= 0) line = map.nodes()[size_t(child)].line;
    } else if (const auto* e = map.entry(node, head->name)) {
      line = e->line;
      child = map.value_node(*e);
    } else {
      return node;  // a sentence, not a field's name: the field is in `node`
    }
    rest = head->rest;
    if (child < 0) return -1;
    node = child;
  }
  return node;
}

// "stage 'S': rest" or "stage 'S', context 'C': rest".
struct StageMessage {
  std::optional<std::string> context;
  std::string rest;
};

std::optional<StageMessage> stage_message(const std::string& message) {
  MessageScan scan{message};
  StageMessage m;
  if (!scan.take("stage '") || !scan.take_until('\'') || !scan.take("'")) return std::nullopt;
  const size_t after_stage = scan.at;
  if (scan.take(", context '")) {
    m.context = scan.take_until('\'');
    if (!m.context || !scan.take("'")) m.context.reset(), scan.at = after_stage;
  }
  if (!scan.take(": ")) return std::nullopt;
  const std::optional<std::string> rest = scan.rest_of_line();
  if (!rest) return std::nullopt;
  m.rest = *rest;
  return m;
}

// The field a message's rest names at its head: "unknown field 'x'", "unknown fields 'x', ...",
// "field 'x' ..." (key ""), or "tasks.goal_radius ..." (field "tasks", key "goal_radius").
struct NamedField {
  std::string field, key;
};

std::optional<NamedField> named_field(const std::string& rest) {
  MessageScan scan{rest};
  if (scan.take("unknown fields ") || scan.take("unknown field ") || scan.take("field ")) {
    std::string name;
    if (scan.take("'") && !(name = scan.take_run(is_identifier_head, is_identifier_char)).empty() && scan.take("'"))
      return NamedField{name, ""};
    scan.at = 0;
  }
  NamedField dotted;
  dotted.field = scan.take_run(is_lower_name_char, is_lower_name_char);
  if (dotted.field.empty() || !scan.take(".")) return std::nullopt;
  dotted.key = scan.take_run(is_identifier_head, is_identifier_char);
  if (dotted.key.empty() || !scan.take(" ")) return std::nullopt;
  return dotted;
}

}  // namespace

// e's traceback when it goes on to a file other than e's own (a stage a helper module writes for
// its caller, whose line tells where the mistake is), else "": within one file it names the
// roger.stage{ call's line, which the field's line replaces.
static std::string traceback_of_caller(const ScriptError& e) {
  std::istringstream lines(e.traceback);
  std::string line;
  std::getline(lines, line);  // "stack traceback:"
  while (std::getline(lines, line)) {
    const size_t start = line.find_first_not_of(" \t");
    if (start == std::string::npos || line.compare(start, 3, "[C]") == 0) continue;
    const size_t colon = line.find(':', start);
    if (colon != std::string::npos && line.substr(start, colon - start) != e.file) return e.traceback;
  }
  return "";
}

std::optional<ScriptError> at_stage_field(const ScriptError& e) {
  // Found by a probe: a stage's misspelt or ill-typed field was reported at its roger.stage{
  // line, however far below it was written. A table carries no lines; the text does.
  //
  // A field's line only for an error of the roger.stage{...} call itself (raised in Lua, with a
  // traceback): one found when the returned table is read again may be of a field changed after
  // the call (a wrapper's paper.stages[2].budget = {...}), which the text does not show. A
  // context's line also for an error found later (an action's name, a learned skill no stage
  // yields), when the context is written in the stage's text.
  const bool in_call = !e.traceback.empty();
  if (e.file.empty() || e.line <= 0) return std::nullopt;
  const std::optional<StageMessage> m = stage_message(e.message);
  if (!m || (!in_call && !m->context)) return std::nullopt;
  const std::string text = source_text(e.file);
  if (text.empty()) return std::nullopt;
  const LuaTableMap map(text);
  int node = stage_node(map, e.line), line = e.line;
  if (node < 0 || map.nodes()[size_t(node)].line != e.line) return std::nullopt;  // raised elsewhere (a callback)
  if (m->context) std::tie(node, line) = context_node(map, node, *m->context, line);
  const std::string traceback = traceback_of_caller(e);
  if (!in_call) return node >= 0 ? std::optional<ScriptError>(ScriptError(e.message, e.file, line, traceback)) : std::nullopt;
  std::string rest = m->rest;
  node = descend(map, node, line, rest);
  // "tasks.goal_radius must be ...": the key's line in the field's table (found by a probe).
  const std::optional<NamedField> f = node >= 0 ? named_field(rest) : std::nullopt;
  if (f) {
    if (const auto* entry = map.entry(node, f->field)) {
      line = entry->line;
      const int table = f->key.empty() ? -1 : map.value_node(*entry);
      if (const auto* key = table >= 0 ? map.entry(table, f->key) : nullptr) line = key->line;
    }
  }
  if (line == e.line) return std::nullopt;
  // Without the traceback: it names the roger.stage{ call's line, which the text's line replaces
  // (found by a probe: a message at the context's line 39 above a traceback saying line 30).
  return ScriptError(e.message, e.file, line, traceback);
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
