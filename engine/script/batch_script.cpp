#include "script/batch_script.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include <lua.hpp>

#include "script/curriculum.h"
#include "core/error.h"

namespace roger {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

std::string quoted_list(const std::vector<std::string>& items) {
  std::vector<std::string> q;
  for (const auto& s : items) q.push_back("'" + s + "'");
  return q.empty() ? "(none)" : join(q);
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The Lua value at `index` as JSON: tables with keys 1..n are arrays, tables with string keys
// objects; numbers, strings and booleans as they are. `where` names the value for messages.
json lua_to_json(lua_State* L, int index, const std::string& where, int depth = 0) {
  index = lua_absindex(L, index);
  if (depth > 32) throw Error(where + ": nested too deeply");
  switch (lua_type(L, index)) {
    case LUA_TNIL: return nullptr;
    case LUA_TBOOLEAN: return bool(lua_toboolean(L, index));
    case LUA_TNUMBER:
      if (lua_isinteger(L, index)) return int64_t(lua_tointeger(L, index));
      {
        const double v = lua_tonumber(L, index);
        if (!std::isfinite(v)) throw Error(where + " must be a finite number");
        return v;
      }
    case LUA_TSTRING: return std::string(lua_tostring(L, index));
    case LUA_TTABLE: {
      json obj = json::object();
      std::map<lua_Integer, json> items;
      lua_pushnil(L);
      while (lua_next(L, index) != 0) {
        if (lua_type(L, -2) == LUA_TSTRING) {
          const std::string key = lua_tostring(L, -2);
          obj[key] = lua_to_json(L, -1, where + "." + key, depth + 1);
        } else if (lua_isinteger(L, -2)) {
          const lua_Integer k = lua_tointeger(L, -2);
          items[k] = lua_to_json(L, -1, where + "[" + std::to_string(k) + "]", depth + 1);
        } else {
          lua_pop(L, 2);
          throw Error(where + ": keys must be names or list positions");
        }
        lua_pop(L, 1);
      }
      if (!items.empty() && !obj.empty())
        throw Error(where + ": mixes named fields (" + obj.begin().key() + ") with list items");
      if (items.empty()) return obj.empty() ? json::array() : obj;
      json arr = json::array();
      lua_Integer expect = 1;
      for (auto& [k, v] : items) {
        if (k != expect) throw Error(where + ": a list with a hole at position " + std::to_string(expect));
        arr.push_back(std::move(v));
        ++expect;
      }
      return arr;
    }
    default:
      throw Error(where + " cannot be a " + std::string(lua_typename(L, lua_type(L, index))) +
                  " (batch scripts hold names, numbers, strings and tables)");
  }
}

// Reads a validated script out of the JSON the Lua script returned, with lines for messages.
class Reader {
 public:
  Reader(std::string display, std::string text) : display_(std::move(display)), text_(std::move(text)) {}

  [[noreturn]] void fail(int line, const std::string& message) const {
    throw ScriptError(message, display_, line, "");
  }

  // The line where `name = "value"` is first written at or after line `from` (0 when not found).
  int line_of_name(const std::string& value, int from = 1) const {
    return line_of("name\\s*=\\s*[\"']" + escape(value) + "[\"']", from);
  }
  // The line where `key =` is first written at or after line `from`, else `from`.
  int line_of_key(const std::string& key, int from = 1) const {
    const int l = line_of("(^|[^A-Za-z0-9_])" + escape(key) + "\\s*=[^=]", from);
    return l ? l : from;
  }

  // Checks that a value is an object with only known keys.
  void check_object(const json& j, const std::string& what, const std::vector<std::string>& known, int line) const {
    if (!j.is_object()) fail(line, what + " must be a table of named fields");
    for (auto it = j.begin(); it != j.end(); ++it)
      if (std::find(known.begin(), known.end(), it.key()) == known.end())
        fail(line_of_key(it.key(), line), what + ": unknown field '" + it.key() + "'; the fields are " + join(known));
  }

  std::string str(const json& o, const char* key, const std::string& what, int line, const std::string& fallback,
                  bool required = false) const {
    if (!o.contains(key)) {
      if (required) fail(line, what + ": missing required field '" + key + "'");
      return fallback;
    }
    if (!o[key].is_string()) fail(line_of_key(key, line), what + ": field '" + key + "' must be a string");
    const std::string s = o[key];
    if (required && s.empty()) fail(line_of_key(key, line), what + ": field '" + key + "' is empty");
    return s;
  }

  int64_t integer(const json& o, const char* key, const std::string& what, int line, int64_t fallback, int64_t lo,
                  int64_t hi) const {
    if (!o.contains(key)) return fallback;
    const json& v = o[key];
    int64_t x = 0;
    if (v.is_number_integer()) x = v.get<int64_t>();
    else if (v.is_number_float() && std::floor(v.get<double>()) == v.get<double>() && std::fabs(v.get<double>()) < 9e15)
      x = int64_t(v.get<double>());
    else fail(line_of_key(key, line), what + ": field '" + key + "' must be an integer");
    if (x < lo || x > hi)
      fail(line_of_key(key, line), what + ": field '" + key + "' must be between " + std::to_string(lo) + " and " +
                                       std::to_string(hi) + ", got " + std::to_string(x));
    return x;
  }

  bool boolean(const json& o, const char* key, const std::string& what, int line, bool fallback) const {
    if (!o.contains(key)) return fallback;
    if (!o[key].is_boolean()) fail(line_of_key(key, line), what + ": field '" + key + "' must be true or false");
    return o[key].get<bool>();
  }

  std::vector<std::string> strings(const json& o, const char* key, const std::string& what, int line,
                                   bool required) const {
    std::vector<std::string> out;
    if (!o.contains(key)) {
      if (required) fail(line, what + ": missing required field '" + key + "' (a list of names)");
      return out;
    }
    const json& v = o[key];
    if (!v.is_array()) fail(line_of_key(key, line), what + ": field '" + key + "' must be a list of names");
    for (const auto& s : v) {
      if (!s.is_string()) fail(line_of_key(key, line), what + ": field '" + key + "' must be a list of names");
      const std::string n = s;
      if (std::find(out.begin(), out.end(), n) != out.end())
        fail(line_of_key(key, line), what + ": field '" + key + "' names '" + n + "' twice");
      out.push_back(n);
    }
    if (required && out.empty()) fail(line_of_key(key, line), what + ": field '" + key + "' is empty");
    return out;
  }

  // Scenario parameters: a table of name = number, string or boolean.
  Params params(const json& o, const char* key, const std::string& what, int line) const {
    Params out;
    if (!o.contains(key)) return out;
    const json& v = o[key];
    if (v.is_array() && v.empty()) return out;
    if (!v.is_object()) fail(line_of_key(key, line), what + ": field '" + key + "' must be a table of name = value");
    for (auto it = v.begin(); it != v.end(); ++it) {
      std::string text;
      if (it->is_string()) text = it->get<std::string>();
      else if (it->is_number_integer()) text = std::to_string(it->get<int64_t>());
      else if (it->is_number_float()) text = format_number(it->get<double>());
      else if (it->is_boolean()) text = it->get<bool>() ? "true" : "false";
      else fail(line_of_key(key, line), what + ": parameter '" + it.key() + "' must be a number, string or boolean");
      out.emplace_back(it.key(), text);
    }
    return out;
  }

 private:
  static std::string escape(const std::string& s) { return std::regex_replace(s, std::regex("[^A-Za-z0-9_]"), "."); }
  int line_of(const std::string& pattern, int from) const {
    size_t pos = 0;
    for (int l = 1; l < from && pos != std::string::npos; ++l) {
      pos = text_.find('\n', pos);
      if (pos != std::string::npos) ++pos;
    }
    if (pos == std::string::npos) return 0;
    std::smatch m;
    const std::regex re(pattern);
    auto begin = text_.cbegin() + long(pos);
    if (std::regex_search(begin, text_.cend(), m, re))
      return int(std::count(text_.cbegin(), begin + m.position(0), '\n')) + 1 +
             (m.length(1) > 0 && m.str(1) == "\n" ? 1 : 0);
    return 0;
  }
  std::string display_, text_;
};

void merge_params(Params& into, const Params& more) {
  for (const auto& [k, v] : more) {
    auto it = std::find_if(into.begin(), into.end(), [&](const auto& p) { return p.first == k; });
    if (it != into.end()) it->second = v;
    else into.emplace_back(k, v);
  }
}

// Finds the script: the path itself, or <project>/scripts/<name>.lua for a bare name.
std::string resolve_script(const std::string& arg) {
  return resolve_script_path(arg, "scripts", "batch script", "batch scripts in scripts/");
}

json params_json(const Params& p) {
  json j = json::array();
  for (const auto& [k, v] : p) j.push_back({k, v});
  return j;
}

Params params_from(const json& j) {
  Params p;
  for (const auto& e : j) p.emplace_back(e.at(0).get<std::string>(), e.at(1).get<std::string>());
  return p;
}

}  // namespace

const BatchRun* BatchScript::run(const std::string& n) const {
  for (const auto& r : runs)
    if (r.name == n) return &r;
  return nullptr;
}

std::vector<const BatchRun*> BatchScript::ordered_runs() const {
  std::vector<const BatchRun*> out;
  std::set<std::string> placed;
  while (out.size() < runs.size()) {
    bool progress = false;
    for (const auto& r : runs) {
      if (placed.count(r.name)) continue;
      bool ready = true;
      for (const auto& s : r.skills) ready = ready && placed.count(s.run) > 0;
      if (!ready) continue;
      out.push_back(&r);
      placed.insert(r.name);
      progress = true;
    }
    if (!progress) throw Error("batch script: runs take skills from each other in a cycle");
  }
  return out;
}

std::string batch_trial_id(const std::string& run, const std::string& context, int trial) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%03d", trial);
  return run + "/" + context + "/" + buf;
}

std::string batch_eval_id(const std::string& evaluation, const std::string& shape, int trial) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%03d", trial);
  return "eval/" + evaluation + "/" + shape + "/" + buf;
}

std::vector<std::string> batch_eval_groups(const BatchEvaluation& e) {
  return e.shapes.empty() ? std::vector<std::string>{"all"} : e.shapes;
}

BatchScript load_batch_script(const std::string& path_in, const BatchOverrides& overrides,
                              const SandboxLimits& limits) {
  const std::string path = resolve_script(path_in);
  LuaSandbox sandbox(limits);
  BatchScript b;
  b.file = path;
  b.path = sandbox.display_name(path);
  sandbox.set_main_script(path);
  sandbox.run_file(path, 1);
  lua_State* L = sandbox.state();
  const std::string text = read_text(path);
  const Reader rd(b.path, text);
  // The line of the final `return` (for errors about the whole table).
  int top_line = 1;
  {
    std::istringstream in(text);
    std::string l;
    for (int n = 1; std::getline(in, l); ++n)
      if (std::regex_search(l, std::regex("^\\s*return\\b"))) top_line = n;
  }
  if (!lua_istable(L, -1))
    rd.fail(top_line, "a batch script must return a table {name = ..., curriculum = ..., runs = {...}}, got " +
                          std::string(luaL_typename(L, -1)));
  json top;
  try {
    top = lua_to_json(L, -1, "the batch script");
  } catch (const ScriptError&) {
    throw;
  } catch (const Error& e) {
    rd.fail(top_line, e.what());
  }
  lua_pop(L, 1);

  rd.check_object(top, "the batch script",
                  {"name", "description", "curriculum", "trials", "seed", "params", "runs", "evaluations", "tables",
                   "figures"},
                  top_line);
  b.name = rd.str(top, "name", "the batch script", top_line, fs::path(path).stem().string());
  b.description = rd.str(top, "description", "the batch script", top_line, "");
  b.curriculum = rd.str(top, "curriculum", "the batch script", top_line, "", true);
  b.trials = int(rd.integer(top, "trials", "the batch script", top_line, 1, 1, 100000));
  b.seed = uint64_t(rd.integer(top, "seed", "the batch script", top_line, 1, 0, int64_t(1) << 53));
  b.params = rd.params(top, "params", "the batch script", top_line);
  merge_params(b.params, overrides.sets);
  if (overrides.trials > 0) b.trials = overrides.trials;

  // The curriculum: relative to the current folder, else the script's folder, else a shipped name.
  std::string cur_arg = b.curriculum;
  {
    std::error_code ec;
    const fs::path beside = fs::path(path).parent_path() / b.curriculum;
    const fs::path in_project = project_root() / b.curriculum;
    if (!fs::is_regular_file(cur_arg, ec)) {
      if (fs::is_regular_file(beside, ec)) cur_arg = beside.string();
      else if (fs::is_regular_file(in_project, ec)) cur_arg = in_project.string();
    }
  }
  std::unique_ptr<Curriculum> cur;
  try {
    cur = std::make_unique<Curriculum>(Curriculum::load(cur_arg, limits));
  } catch (const ScriptError& e) {
    rd.fail(rd.line_of_key("curriculum", 1), "the curriculum '" + b.curriculum + "' does not load: " + e.what());
  } catch (const Error& e) {
    rd.fail(rd.line_of_key("curriculum", 1), e.what());
  }
  b.curriculum_file = fs::absolute(cur->file()).lexically_normal().string();
  std::vector<std::string> stage_names;
  for (const auto& st : cur->stages()) stage_names.push_back(st.name);

  // Runs.
  if (!top.contains("runs")) rd.fail(top_line, "the batch script: missing required field 'runs' (a list of runs)");
  const int runs_line = rd.line_of_key("runs", 1);
  if (!top["runs"].is_array() || top["runs"].empty())
    rd.fail(runs_line, "the batch script: 'runs' must be a non-empty list of {name = ..., stage = ..., contexts = {...}}");
  for (const json& rj : top["runs"]) {
    BatchRun r;
    const std::string nm = rj.is_object() && rj.contains("name") && rj["name"].is_string() ? rj["name"].get<std::string>() : "";
    r.line = nm.empty() ? runs_line : std::max(rd.line_of_name(nm, runs_line), runs_line);
    const std::string what = nm.empty() ? "a run" : "run '" + nm + "'";
    rd.check_object(rj, what, {"name", "stage", "contexts", "trials", "params", "skills"}, r.line);
    r.name = rd.str(rj, "name", what, r.line, "", true);
    if (!std::regex_match(r.name, std::regex("[A-Za-z0-9_.-]+")) || r.name == "eval")
      rd.fail(r.line, what + ": a run name uses letters, digits, '.', '_' and '-' (and is not 'eval')");
    if (b.run(r.name)) rd.fail(r.line, "a second run named '" + r.name + "'");
    r.stage = rd.str(rj, "stage", what, r.line, "", true);
    const CurriculumStage* stage = nullptr;
    for (const auto& st : cur->stages())
      if (st.name == r.stage) stage = &st;
    if (!stage)
      rd.fail(rd.line_of_key("stage", r.line), what + ": the curriculum " + cur->path() + " has no stage '" + r.stage +
                                                   "'; its stages are " + quoted_list(stage_names));
    std::vector<std::string> ctx_names;
    for (const auto& c : stage->contexts) ctx_names.push_back(c.name);
    r.contexts = rd.strings(rj, "contexts", what, r.line, false);
    if (r.contexts.empty()) r.contexts = ctx_names;
    for (const auto& c : r.contexts)
      if (std::find(ctx_names.begin(), ctx_names.end(), c) == ctx_names.end())
        rd.fail(rd.line_of_key("contexts", r.line), what + ": stage '" + r.stage + "' has no context '" + c +
                                                        "'; its contexts are " + quoted_list(ctx_names));
    r.trials = int(rd.integer(rj, "trials", what, r.line, b.trials, 1, 100000));
    if (overrides.trials > 0) r.trials = overrides.trials;
    r.params = b.params;
    merge_params(r.params, rd.params(rj, "params", what, r.line));
    merge_params(r.params, overrides.sets);
    // The learned skills its contexts use, and where each comes from.
    std::set<std::string> needed;
    for (const auto& c : r.contexts)
      for (const auto& l : stage->context(c).learned) needed.insert(l);
    if (rj.contains("skills")) {
      const json& sj = rj["skills"];
      const int sl = rd.line_of_key("skills", r.line);
      if (!sj.is_object()) rd.fail(sl, what + ": 'skills' must be a table {Skill = {run = ..., context = ...}}");
      for (auto it = sj.begin(); it != sj.end(); ++it) {
        const std::string sw = what + ", skill '" + it.key() + "'";
        const int l = rd.line_of_key(it.key(), sl);
        rd.check_object(*it, sw, {"run", "context"}, l);
        BatchSkill s;
        s.skill = it.key();
        s.run = rd.str(*it, "run", sw, l, "", true);
        const BatchRun* from = b.run(s.run);
        if (!from) {
          std::vector<std::string> earlier;
          for (const auto& e : b.runs) earlier.push_back(e.name);
          rd.fail(l, sw + ": no earlier run '" + s.run + "'; the runs before it are " + quoted_list(earlier));
        }
        const CurriculumStage* producer = cur->producer(s.skill);
        if (!producer)
          rd.fail(l, sw + ": the curriculum yields no skill '" + s.skill + "'");
        if (producer->name != from->stage)
          rd.fail(l, sw + ": run '" + s.run + "' trains stage '" + from->stage + "', but '" + s.skill +
                         "' is yielded by stage '" + producer->name + "'");
        s.context = rd.str(*it, "context", sw, l, producer->skill ? producer->skill->second : "");
        if (std::find(from->contexts.begin(), from->contexts.end(), s.context) == from->contexts.end())
          rd.fail(l, sw + ": run '" + s.run + "' has no context '" + s.context + "'; its contexts are " +
                         quoted_list(from->contexts));
        if (from->trials < r.trials)
          rd.fail(l, sw + ": run '" + s.run + "' has " + std::to_string(from->trials) + " trials, fewer than the " +
                         std::to_string(r.trials) + " of run '" + r.name + "' (trial i uses trial i's policy)");
        if (!needed.count(s.skill))
          rd.fail(l, sw + ": no context of run '" + r.name + "' uses the learned skill '" + s.skill + "'");
        r.skills.push_back(s);
      }
    }
    for (const auto& n : needed)
      if (std::none_of(r.skills.begin(), r.skills.end(), [&](const BatchSkill& s) { return s.skill == n; }))
        rd.fail(r.line, what + ": its contexts use the learned skill '" + n +
                            "': say which run trains it, e.g. skills = { " + n + " = { run = \"...\", context = \"...\" } }");
    b.runs.push_back(std::move(r));
  }

  // Evaluations.
  if (top.contains("evaluations")) {
    const int el = rd.line_of_key("evaluations", 1);
    if (!top["evaluations"].is_array()) rd.fail(el, "the batch script: 'evaluations' must be a list");
    for (const json& ej : top["evaluations"]) {
      BatchEvaluation e;
      const std::string nm = ej.is_object() && ej.contains("name") && ej["name"].is_string() ? ej["name"].get<std::string>() : "";
      e.line = nm.empty() ? el : std::max(rd.line_of_name(nm, el), el);
      const std::string what = nm.empty() ? "an evaluation" : "evaluation '" + nm + "'";
      rd.check_object(ej, what,
                      {"name", "run", "context", "scenario", "params", "shapes", "episodes", "first_seed", "trials"},
                      e.line);
      e.name = rd.str(ej, "name", what, e.line, "", true);
      if (!std::regex_match(e.name, std::regex("[A-Za-z0-9_.-]+")))
        rd.fail(e.line, what + ": a name uses letters, digits, '.', '_' and '-'");
      for (const auto& o : b.evaluations)
        if (o.name == e.name) rd.fail(e.line, "a second evaluation named '" + e.name + "'");
      e.run = rd.str(ej, "run", what, e.line, "", true);
      const BatchRun* from = b.run(e.run);
      if (!from) {
        std::vector<std::string> names;
        for (const auto& r : b.runs) names.push_back(r.name);
        rd.fail(rd.line_of_key("run", e.line), what + ": no run '" + e.run + "'; the runs are " + quoted_list(names));
      }
      e.context = rd.str(ej, "context", what, e.line, from->contexts.back());
      if (std::find(from->contexts.begin(), from->contexts.end(), e.context) == from->contexts.end())
        rd.fail(rd.line_of_key("context", e.line), what + ": run '" + e.run + "' has no context '" + e.context +
                                                       "'; its contexts are " + quoted_list(from->contexts));
      e.scenario = rd.str(ej, "scenario", what, e.line, "");
      e.params = rd.params(ej, "params", what, e.line);
      e.shapes = rd.strings(ej, "shapes", what, e.line, false);
      for (const auto& s : e.shapes)
        if (!std::regex_match(s, std::regex("[A-Za-z0-9_.-]+")))
          rd.fail(rd.line_of_key("shapes", e.line), what + ": shape '" + s + "' is not a plain name");
      if (std::any_of(e.params.begin(), e.params.end(), [](const auto& p) { return p.first == "shape"; }) &&
          !e.shapes.empty())
        rd.fail(rd.line_of_key("shapes", e.line), what + ": give the shape either in 'params' or in 'shapes', not both");
      e.episodes = int(rd.integer(ej, "episodes", what, e.line, 50, 1, 1000000));
      e.first_seed = rd.integer(ej, "first_seed", what, e.line, -1, -1, int64_t(1) << 53);
      e.trials = int(rd.integer(ej, "trials", what, e.line, from->trials, 1, from->trials));
      if (overrides.trials > 0) e.trials = std::min(overrides.trials, from->trials);
      b.evaluations.push_back(std::move(e));
    }
  }

  auto run_names = [&]() {
    std::vector<std::string> n;
    for (const auto& r : b.runs) n.push_back(r.name);
    return n;
  };
  // Tables (default: one per run against its first context, one per evaluation).
  if (top.contains("tables")) {
    const int tl = rd.line_of_key("tables", 1);
    if (!top["tables"].is_array()) rd.fail(tl, "the batch script: 'tables' must be a list");
    int at = tl;
    for (const json& tj : top["tables"]) {
      BatchTable t;
      const std::string title = tj.is_object() && tj.contains("title") && tj["title"].is_string() ? tj["title"].get<std::string>() : "";
      const int l = title.empty() ? at : std::max(at, rd.line_of_key("title", at));
      at = l + 1;
      const std::string what = title.empty() ? "a table" : "table '" + title + "'";
      rd.check_object(tj, what, {"title", "run", "baseline", "evaluation", "usage"}, l);
      t.title = title;
      t.run = rd.str(tj, "run", what, l, "");
      t.evaluation = rd.str(tj, "evaluation", what, l, "");
      if (t.run.empty() == t.evaluation.empty()) rd.fail(l, what + ": give either 'run' or 'evaluation'");
      if (!t.evaluation.empty()) {
        if (std::none_of(b.evaluations.begin(), b.evaluations.end(), [&](const auto& e) { return e.name == t.evaluation; })) {
          std::vector<std::string> names;
          for (const auto& e : b.evaluations) names.push_back(e.name);
          rd.fail(l, what + ": no evaluation '" + t.evaluation + "'; the evaluations are " + quoted_list(names));
        }
        if (tj.contains("baseline") || tj.contains("usage"))
          rd.fail(l, what + ": 'baseline' and 'usage' belong to a run's table");
      } else {
        const BatchRun* r = b.run(t.run);
        if (!r) rd.fail(l, what + ": no run '" + t.run + "'; the runs are " + quoted_list(run_names()));
        t.baseline = rd.str(tj, "baseline", what, l, r->contexts.front());
        if (std::find(r->contexts.begin(), r->contexts.end(), t.baseline) == r->contexts.end())
          rd.fail(rd.line_of_key("baseline", l), what + ": run '" + t.run + "' has no context '" + t.baseline +
                                                     "'; its contexts are " + quoted_list(r->contexts));
        if (tj.contains("usage")) {
          const int ul = rd.line_of_key("usage", l);
          if (!tj["usage"].is_array()) rd.fail(ul, what + ": 'usage' must be a list of {context = ..., skill = ..., subsumes = {...}}");
          for (const json& uj : tj["usage"]) {
            rd.check_object(uj, what + ", usage", {"context", "skill", "subsumes"}, ul);
            BatchUsage u;
            u.context = rd.str(uj, "context", what + ", usage", ul, "", true);
            if (std::find(r->contexts.begin(), r->contexts.end(), u.context) == r->contexts.end())
              rd.fail(ul, what + ", usage: run '" + t.run + "' has no context '" + u.context + "'; its contexts are " +
                              quoted_list(r->contexts));
            u.skill = rd.str(uj, "skill", what + ", usage", ul, "", true);
            u.subsumes = rd.strings(uj, "subsumes", what + ", usage", ul, true);
            std::vector<std::string> psi;
            for (const auto& a : cur->stage(r->stage).context(u.context).actions) psi.push_back(a->name());
            std::vector<std::string> all = u.subsumes;
            all.push_back(u.skill);
            for (const auto& a : all)
              if (std::find(psi.begin(), psi.end(), a) == psi.end())
                rd.fail(ul, what + ", usage: context '" + u.context + "' has no action '" + a + "'; its actions are " +
                                quoted_list(psi));
            t.usage.push_back(std::move(u));
          }
        }
      }
      b.tables.push_back(std::move(t));
    }
  } else {
    for (const auto& r : b.runs) {
      BatchTable t;
      t.title = "Stage " + r.stage + " (run " + r.name + ")";
      t.run = r.name;
      t.baseline = r.contexts.front();
      b.tables.push_back(t);
    }
    for (const auto& e : b.evaluations) {
      BatchTable t;
      t.title = "Evaluation " + e.name;
      t.evaluation = e.name;
      b.tables.push_back(t);
    }
  }

  // Figures (default: learning curves of every run, cumulative times of every run with skills).
  if (top.contains("figures")) {
    const int fl = rd.line_of_key("figures", 1);
    if (!top["figures"].is_array()) rd.fail(fl, "the batch script: 'figures' must be a list");
    int at = fl;
    for (const json& fj : top["figures"]) {
      BatchFigure f;
      const std::string file = fj.is_object() && fj.contains("file") && fj["file"].is_string() ? fj["file"].get<std::string>() : "";
      const int l = file.empty() ? at : std::max(at, rd.line_of_key("file", at));
      at = l + 1;
      const std::string what = file.empty() ? "a figure" : "figure '" + file + "'";
      rd.check_object(fj, what, {"file", "title", "kind", "run", "log_x"}, l);
      f.file = rd.str(fj, "file", what, l, "", true);
      if (!std::regex_match(f.file, std::regex("[A-Za-z0-9_.-]+")))
        rd.fail(l, what + ": 'file' is a plain name (no folder, no extension): <file>.png and <file>.svg are written");
      f.title = rd.str(fj, "title", what, l, "");
      f.kind = rd.str(fj, "kind", what, l, "curves");
      if (f.kind != "curves" && f.kind != "cumulative")
        rd.fail(rd.line_of_key("kind", l), what + ": 'kind' is \"curves\" or \"cumulative\", got '" + f.kind + "'");
      f.run = rd.str(fj, "run", what, l, "", true);
      const BatchRun* r = b.run(f.run);
      if (!r) rd.fail(rd.line_of_key("run", l), what + ": no run '" + f.run + "'; the runs are " + quoted_list(run_names()));
      if (f.kind == "cumulative" && r->skills.empty())
        rd.fail(l, what + ": a cumulative figure needs a run that takes skills from an earlier run; '" + f.run +
                       "' takes none");
      f.log_x = rd.boolean(fj, "log_x", what, l, false);
      for (const auto& o : b.figures)
        if (o.file == f.file) rd.fail(l, "a second figure written to '" + f.file + "'");
      b.figures.push_back(std::move(f));
    }
  } else {
    for (const auto& r : b.runs) {
      BatchFigure f;
      f.file = "curves_" + r.name;
      f.title = "Learning curves: stage " + r.stage;
      f.run = r.name;
      b.figures.push_back(f);
      if (!r.skills.empty()) {
        f.file = "cumulative_" + r.name;
        f.title = "Cumulative training time: stage " + r.stage;
        f.kind = "cumulative";
        b.figures.push_back(f);
      }
    }
  }
  b.ordered_runs();  // rejects cycles (impossible with earlier-run skills, kept as a guard)
  return b;
}

json batch_config_json(const BatchScript& b) {
  json runs = json::array(), evals = json::array(), tables = json::array(), figures = json::array();
  for (const auto& r : b.runs) {
    json skills = json::array();
    for (const auto& s : r.skills) skills.push_back({{"skill", s.skill}, {"run", s.run}, {"context", s.context}});
    runs.push_back({{"name", r.name}, {"stage", r.stage}, {"contexts", r.contexts}, {"trials", r.trials},
                    {"params", params_json(r.params)}, {"skills", skills}});
  }
  for (const auto& e : b.evaluations)
    evals.push_back({{"name", e.name}, {"run", e.run}, {"context", e.context}, {"scenario", e.scenario},
                     {"params", params_json(e.params)}, {"shapes", e.shapes}, {"episodes", e.episodes},
                     {"first_seed", e.first_seed}, {"trials", e.trials}});
  for (const auto& t : b.tables) {
    json usage = json::array();
    for (const auto& u : t.usage) usage.push_back({{"context", u.context}, {"skill", u.skill}, {"subsumes", u.subsumes}});
    tables.push_back({{"title", t.title}, {"run", t.run}, {"baseline", t.baseline}, {"evaluation", t.evaluation},
                      {"usage", usage}});
  }
  for (const auto& f : b.figures)
    figures.push_back({{"file", f.file}, {"title", f.title}, {"kind", f.kind}, {"run", f.run}, {"log_x", f.log_x}});
  return {{"name", b.name}, {"description", b.description}, {"curriculum", b.curriculum},
          {"curriculum_file", b.curriculum_file}, {"trials", b.trials}, {"seed", b.seed},
          {"params", params_json(b.params)}, {"runs", runs}, {"evaluations", evals}, {"tables", tables},
          {"figures", figures}};
}

BatchScript batch_config_from_json(const json& j) {
  BatchScript b;
  try {
    b.name = j.at("name");
    b.description = j.value("description", "");
    b.curriculum = j.at("curriculum");
    b.curriculum_file = j.value("curriculum_file", "");
    b.trials = j.at("trials");
    b.seed = j.at("seed");
    b.params = params_from(j.at("params"));
    for (const auto& rj : j.at("runs")) {
      BatchRun r;
      r.name = rj.at("name");
      r.stage = rj.at("stage");
      r.contexts = rj.at("contexts").get<std::vector<std::string>>();
      r.trials = rj.at("trials");
      r.params = params_from(rj.at("params"));
      for (const auto& s : rj.at("skills")) r.skills.push_back({s.at("skill"), s.at("run"), s.at("context")});
      b.runs.push_back(std::move(r));
    }
    for (const auto& ej : j.at("evaluations")) {
      BatchEvaluation e;
      e.name = ej.at("name");
      e.run = ej.at("run");
      e.context = ej.at("context");
      e.scenario = ej.at("scenario");
      e.params = params_from(ej.at("params"));
      e.shapes = ej.at("shapes").get<std::vector<std::string>>();
      e.episodes = ej.at("episodes");
      e.first_seed = ej.at("first_seed");
      e.trials = ej.at("trials");
      b.evaluations.push_back(std::move(e));
    }
    for (const auto& tj : j.at("tables")) {
      BatchTable t;
      t.title = tj.at("title");
      t.run = tj.at("run");
      t.baseline = tj.at("baseline");
      t.evaluation = tj.at("evaluation");
      for (const auto& u : tj.at("usage"))
        t.usage.push_back({u.at("context"), u.at("skill"), u.at("subsumes").get<std::vector<std::string>>()});
      b.tables.push_back(std::move(t));
    }
    for (const auto& fj : j.at("figures")) {
      BatchFigure f;
      f.file = fj.at("file");
      f.title = fj.at("title");
      f.kind = fj.at("kind");
      f.run = fj.at("run");
      f.log_x = fj.at("log_x");
      b.figures.push_back(std::move(f));
    }
  } catch (const json::exception& e) {
    throw Error(std::string("the manifest's configuration is incomplete or not from this version: ") + e.what());
  }
  return b;
}

}  // namespace roger
