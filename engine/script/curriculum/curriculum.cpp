#include "script/curriculum/curriculum.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include <lua.hpp>

#include "core/error.h"
#include "core/fileio.h"
#include "core/text.h"
#include "control/primitives.h"
#include "script/curriculum/curriculum_internal.h"
#include "script/sandbox/lua_tokens.h"
#include "script/control/lua_control.h"
#include "script/scenario/scenario.h"

namespace roger {
namespace fs = std::filesystem;

using curriculum_detail::LearnedRef;
using curriculum_detail::LuaCallback;
using curriculum_detail::parse_stage;
using curriculum_detail::push_world;

namespace {

char book_key;  // registry key of the loader's book (a light userdata)

// What the script's roger.stage / roger.learned calls have made so far.
struct Book {
  // Where each roger.stage table was written. The tables themselves are kept in the registry
  // (kStageTablesKey), so that no other table can take the address of one collected.
  std::map<const void*, std::pair<std::string, int>> tables;
  std::map<std::string, std::shared_ptr<LearnedRef>> learned;
  bool loaded = false;  // the script has returned: its stages are read (roger.stage refuses then)
};

constexpr const char* kStageTablesKey = "roger.stage_tables";

Book& book_of(lua_State* L) {
  lua_rawgetp(L, LUA_REGISTRYINDEX, &book_key);
  auto* b = static_cast<Book*>(lua_touserdata(L, -1));
  lua_pop(L, 1);
  if (!b) luaL_error(L, "the curriculum API is not installed in this Lua state");
  return *b;
}

// Where the caller of the running C function is, "" when it is C++.
std::pair<std::string, int> caller(lua_State* L) {
  lua_Debug ar;
  if (lua_getstack(L, 1, &ar) && lua_getinfo(L, "Sl", &ar) && ar.currentline > 0)
    return {ar.source && ar.source[0] == '@' ? ar.source + 1 : ar.short_src, ar.currentline};
  return {"", 0};
}

// Whether a Lua function of a file other than `file` is on the stack above roger.stage's caller:
// the stage is written by a library for that file.
bool called_through_another_file(lua_State* L, const std::string& file) {
  lua_Debug ar;
  for (int level = 2; lua_getstack(L, level, &ar); ++level)
    if (lua_getinfo(L, "Sl", &ar) && ar.currentline > 0 &&
        (ar.source && ar.source[0] == '@' ? ar.source + 1 : ar.short_src) != file)
      return true;
  return false;
}

// roger.stage{...}: validates a stage where it is written (errors point at this line) and returns
// the same table. The curriculum reads the table again when the script returns, with any changes
// made to it since, and places that reading's errors here too.
int l_stage(lua_State* L) {
  return lua_protect(L, [&]() {
    lua_check_arity(L, "roger.stage", 1, "1 argument (a table of fields)");
    Book& book = book_of(L);
    if (book.loaded) lua_refuse_after_load(L, "stages");
    CurriculumStage st;
    LuaCallback a, r, t;
    const auto where = caller(L);
    parse_stage(L, 1, st, a, r, t, where.first);
    st.file = where.first, st.line = where.second;
    try {
      curriculum_detail::check_stage_params(st);
    } catch (const ScriptError& e) {
      // Placed at the stage's params table, which a library may write for its caller (found by a
      // probe: paper.stages{ sg_params = { forarm = 0.6 } } named curricula/lib/paper_stages.lua
      // alone): the traceback names the caller's line, as for the library's own errors.
      if (!e.traceback.empty() || !called_through_another_file(L, where.first)) throw;
      luaL_traceback(L, L, nullptr, 1);
      const std::string traceback = lua_tostring(L, -1);
      lua_pop(L, 1);
      throw ScriptError(e.message, e.file, e.line, traceback);
    }
    lua_settop(L, 1);
    book.tables[lua_topointer(L, 1)] = where;
    luaL_getsubtable(L, LUA_REGISTRYINDEX, kStageTablesKey);
    lua_pushvalue(L, 1);
    lua_rawseti(L, -2, lua_Integer(lua_rawlen(L, -2)) + 1);
    lua_settop(L, 1);
    return 1;
  });
}

// roger.learned("Phi_SG"): the stand-in for a skill an earlier stage yields.
int l_learned(lua_State* L) {
  return lua_protect(L, [&]() {
    lua_check_arity(L, "roger.learned", 1, "1 argument (the name of a skill)");
    Book& book = book_of(L);
    if (book.loaded) lua_refuse_after_load(L, "the stand-ins of learned skills");
    if (lua_type(L, 1) != LUA_TSTRING)
      luaL_error(L, "roger.learned: expects the name of a skill an earlier stage yields (a string), got %s",
                 lua_describe_value(L, 1).c_str());
    const std::string name = lua_tostring(L, 1);
    if (name.empty()) luaL_error(L, "roger.learned: the name must not be empty");
    if (const std::string problem = name_text_problem(name); !problem.empty())
      luaL_error(L, "roger.learned: the name %s", problem.c_str());
    if (const std::string problem = curriculum_detail::skill_name_problem(name); !problem.empty())
      luaL_error(L, "roger.learned: %s", problem.c_str());
    auto it = book.learned.find(name);
    if (it == book.learned.end()) it = book.learned.emplace(name, std::make_shared<LearnedRef>(name)).first;
    lua_push_controller(L, it->second);
    return 1;
  });
}

}  // namespace

std::string CurriculumStage::time_limit_text() const {
  if (time_per_object > 0.0 && time_limit > 0.0)
    return format_number(time_limit) + " s + " + format_number(time_per_object) + " s per object limit";
  if (time_per_object > 0.0) return format_number(time_per_object) + " s per object limit";
  return format_number(time_limit) + " s limit";
}

double CurriculumStage::episode_time_limit(const WorldSpec& world) const {
  const double limit = time_limit + time_per_object * double(world.objects.size());
  if (!(limit > 0.0))
    throw ScriptError(where() + ": time_limit = {per_object = " + format_number(time_per_object) + "} gives no time "
                      "in a world without objects (scenario '" + scenario + "' placed none): give the stage a number "
                      "of seconds, or place an object", file, line, "");
  return limit;
}

std::string CurriculumStage::scenario_warning() const {
  const std::string w = scenario_found_from_here(scenario, file);
  if (w.empty()) return "";
  const int at = curriculum_detail::field_line(*this, "", "scenario");
  return (at > 0 ? file + ":" + std::to_string(at) + ": " : std::string()) + where() + ": " + w;
}

std::string CurriculumStage::scenario_note() const {
  if (scenario_beside.empty()) return "";
  const int field = curriculum_detail::field_line(*this, "", "scenario"), at = field > 0 ? field : line;
  return (at > 0 ? file + ":" + std::to_string(at) + ": " : std::string()) + where() + ": scenario '" + scenario +
         "' is the project's " + resolve_scenario_path(scenario) + " (a bare name is one of scenarios/), not " +
         scenario_beside + " of the same name: to train in that one, name it with its \".lua\" (scenario = \"" +
         fs::path(scenario_beside).filename().string() + "\")";
}

std::string CurriculumStage::learner_warning() const {
  if (!(learner.epsilon_start < learner.epsilon_end)) return "";
  const int at = curriculum_detail::field_line(*this, "", "learner");
  return (at > 0 ? file + ":" + std::to_string(at) + ": " : std::string()) + where() + ": learner: epsilon_start " +
         format_number(learner.epsilon_start) + " is below epsilon_end " + format_number(learner.epsilon_end) +
         ": exploration rises over the budget instead of falling (the two swapped?)";
}

std::string CurriculumStage::where(const std::string& context) const {
  return "stage '" + name + "'" + (context.empty() ? "" : ", context '" + context + "'");
}

std::string CurriculumStage::written_at() const {
  return !file.empty() && line > 0 ? file + ":" + std::to_string(line) + ": " : "";
}

const CurriculumContext& CurriculumStage::context(const std::string& n) const {
  std::vector<std::string> names;
  for (const auto& c : contexts) {
    if (c.name == n) return c;
    names.push_back(c.name);
  }
  throw Error(where() + " has no context '" + n + "'" + suggestion(n, names) + "; its contexts: " + join(names));
}

std::vector<std::pair<std::string, std::string>> CurriculumStage::scenario_params(
    const CurriculumContext& context) const {
  std::map<std::string, std::string> merged(params.begin(), params.end());
  for (const auto& [key, value] : context.params) merged[key] = value;
  return {merged.begin(), merged.end()};
}

struct Curriculum::Impl {
  std::unique_ptr<LuaSandbox> sandbox;
  std::string path, file, name, description;
  Book book;
  std::vector<CurriculumStage> stages;
  std::map<std::string, LuaCallback> absorbing_fns, reward_fns, teacher_fns;  // by stage name
  const World* world = nullptr;  // shown to the callbacks (set_world)
  int episode_ref = LUA_NOREF;    // the callbacks' per-episode table (begin_episode)
};

Curriculum::Curriculum() = default;
Curriculum::Curriculum(Curriculum&&) noexcept = default;
Curriculum& Curriculum::operator=(Curriculum&&) noexcept = default;
Curriculum::~Curriculum() = default;

const std::string& Curriculum::name() const { return impl_->name; }
const std::string& Curriculum::description() const { return impl_->description; }
const std::string& Curriculum::path() const { return impl_->path; }
const std::vector<std::filesystem::path>& Curriculum::source_files() const { return impl_->sandbox->source_files(); }
const std::string& Curriculum::file() const { return impl_->file; }
const std::vector<CurriculumStage>& Curriculum::stages() const { return impl_->stages; }

const CurriculumStage& Curriculum::stage(const std::string& n) const {
  std::vector<std::string> names;
  for (const auto& s : impl_->stages) {
    if (s.name == n) return s;
    names.push_back(s.name);
  }
  // A context's name given as the stage (found by a probe: the stage and context swapped said only
  // that the stage is missing).
  std::vector<std::string> having;
  for (const auto& s : impl_->stages)
    if (std::any_of(s.contexts.begin(), s.contexts.end(), [&](const auto& c) { return c.name == n; }))
      having.push_back("'" + s.name + "'");
  const std::string context_hint =
      having.empty() ? "" : " ('" + n + "' is a context of stage " + join(having, " and ") + ": a stage comes first, then its context)";
  throw Error("curriculum '" + impl_->name + "' (" + impl_->path + ") has no stage '" + n + "'" + suggestion(n, names) +
              context_hint + "; its stages: " + join(names));
}

const CurriculumStage* Curriculum::producer(const std::string& skill) const {
  for (const auto& s : impl_->stages)
    if (s.skill && s.skill->first == skill) return &s;
  return nullptr;
}

std::vector<std::string> Curriculum::skills_used(const CurriculumContext& context) const {
  std::set<std::string> used;
  std::function<void(const CurriculumContext&)> walk = [&](const CurriculumContext& ctx) {
    for (const auto& name : ctx.learned) {
      if (!used.insert(name).second) continue;
      if (const CurriculumStage* from = producer(name)) walk(from->context(from->skill->second));
    }
  };
  walk(context);
  return std::vector<std::string>(used.begin(), used.end());
}

std::string Curriculum::unused_skill_problem(const CurriculumStage& stage, const std::string& context,
                                             const std::string& name) const {
  const std::vector<std::string> used = skills_used(stage.context(context));
  if (std::find(used.begin(), used.end(), name) != used.end()) return "";
  return stage.where(context) + " uses no learned skill '" + name + "'" +
         (used.empty() ? " (it uses none)" : "; it uses " + join(used));
}

bool Curriculum::has_learned(const std::string& n) const { return impl_->book.learned.count(n) > 0; }

void Curriculum::bind_learned(const std::string& n, ControllerPtr skill) {
  auto it = impl_->book.learned.find(n);
  if (it == impl_->book.learned.end()) throw Error("curriculum '" + impl_->name + "' never uses roger.learned('" + n + "')");
  it->second->bind(std::move(skill));
}

namespace {

// The line where a plain-table stage's name is written (a table carries no lines), 0 if none.
int line_of_stage(const std::string& text, const std::string& name) {
  return lua_line_of_string_field(lua_tokenize(text), "name", name);
}

// The stage on top of the stack, read as the script left it when it returned, so that changes
// made to a roger.stage table after the call count (a wrapper that shortens a required
// curriculum's budgets, say). `file` and `line` become where the stage is written: roger.stage's
// line, or for a plain table the line where its name is written in `display`.
// `booked` is true while a roger.stage table is read: an error then comes of a change made to it
// after roger.stage accepted it.
CurriculumStage take_stage(lua_State* L, const Book& book, const std::string& display, const std::string& text,
                           std::string& file, int& line, bool& booked, LuaCallback& a, LuaCallback& r,
                           LuaCallback& teacher) {
  auto it = book.tables.find(lua_topointer(L, -1));
  booked = it != book.tables.end();
  if (booked) {
    file = it->second.first;
    line = it->second.second;
  } else {
    lua_getfield(L, -1, "name");
    file = display;
    line = lua_type(L, -1) == LUA_TSTRING ? line_of_stage(text, lua_tostring(L, -1)) : 0;
    lua_pop(L, 1);
  }
  CurriculumStage st;
  parse_stage(L, -1, st, a, r, teacher, file, display);
  st.file = file, st.line = line;
  curriculum_detail::check_stage_params(st);
  booked = false;
  return st;
}

// What an init that names no context written before its own names instead: a context written
// later (of its stage or a later one), or nothing at all, with the nearest stage or context (found
// by a probe: each was "names no context written before this one", whatever the slip).
std::string init_target_problem(const std::vector<CurriculumStage>& stages, const CurriculumContext& ctx) {
  std::vector<std::string> stage_names;
  for (const auto& st : stages) {
    stage_names.push_back(st.name);
    if (st.name != ctx.init_stage) continue;
    std::vector<std::string> contexts;
    for (const auto& c : st.contexts) {
      contexts.push_back(c.name);
      if (c.name != ctx.init_context) continue;
      if (&c == &ctx) return "this context itself, whose table it would start from: name one written before";
      return "a context written after this one: move stage '" + st.name + "', context '" + c.name +
             "' before it, or name one written before";
    }
    return "no context: stage '" + st.name + "' has no context '" + ctx.init_context + "'" +
           suggestion(ctx.init_context, contexts);
  }
  return "no context: there is no stage '" + ctx.init_stage + "'" + suggestion(ctx.init_stage, stage_names);
}

// Across stages: a skill is yielded by one stage only, and a learned skill must come from an
// earlier stage.
// A context's init names a context written before it (an earlier stage's, or an earlier one of its
// own stage), so that training it first never loops, and one that shares an action with it, so
// that something of its table carries over (found by a probe: a table sharing none passed check
// and was refused in training, after the init context had trained).
void check_init_order(const std::vector<CurriculumStage>& stages) {
  std::map<std::string, const CurriculumContext*> before;  // the contexts written so far, by "stage/context"
  std::vector<std::string> order;
  const auto names = [](const CurriculumContext& c) {
    std::vector<std::string> out;
    for (const auto& a : c.actions) out.push_back(a->name());
    return out;
  };
  for (const auto& st : stages)
    for (const auto& ctx : st.contexts) {
      if (!ctx.init_context.empty()) {
        const std::string target = ctx.init_stage + "/" + ctx.init_context;
        const auto init = "init = {stage = '" + ctx.init_stage + "', context = '" + ctx.init_context + "'}";
        const int line = curriculum_detail::field_line(st, ctx.name, "init");
        const auto found = before.find(target);
        if (found == before.end())
          throw ScriptError(st.where(ctx.name) + ": " + init + " names " + init_target_problem(stages, ctx) +
                                "; the contexts written before this one: " +
                                (order.empty() ? std::string("none") : join(order)),
                            st.file, line, "");
        const std::vector<std::string> mine = names(ctx), theirs = names(*found->second);
        if (std::none_of(mine.begin(), mine.end(), [&](const std::string& a) {
              return std::find(theirs.begin(), theirs.end(), a) != theirs.end();
            }))
          throw ScriptError(st.where(ctx.name) + ": " + init + " shares no action with this context, so nothing of its "
                                "table could be carried over (its actions: " + join(theirs) + "; this context's: " +
                                join(mine) + ")",
                            st.file, line, "");
      }
      before[st.name + "/" + ctx.name] = &ctx;
      order.push_back(st.name + "/" + ctx.name);
    }
}

// A skill a stage yields is named apart from the controllers the script names (found by a probe: a
// skill 'Phi6' beside lib.skills' Phi6 passed, and read as one in Psi's errors and in usage).
void check_skill_names(const std::vector<CurriculumStage>& stages, LuaSandbox& sandbox) {
  const std::vector<NamedController> named = named_controllers(sandbox);
  for (const CurriculumStage& st : stages) {
    if (!st.skill) continue;
    for (const NamedController& c : named)
      if (c.name == st.skill->first)
        throw ScriptError(st.where() + ": skill: '" + c.name + "' is the name of a controller the script defines" +
                              (c.file.empty() ? "" : " (at " + c.file + ":" + std::to_string(c.line) + ")") +
                              "; a learned skill and a controller of one name would read as one in Psi and in usage: "
                              "give the skill another name",
                          st.file, curriculum_detail::field_line(st, "", "skill"), "");
  }
}

void check_learned_order(const std::vector<CurriculumStage>& stages) {
  std::map<std::string, size_t> produced;
  for (size_t i = 0; i < stages.size(); ++i) {
    const CurriculumStage& st = stages[i];
    if (st.skill) {
      if (produced.count(st.skill->first))
        throw ScriptError(st.where() + ": a second stage yields the skill '" + st.skill->first + "'", st.file, st.line, "");
      produced[st.skill->first] = i;
    }
  }
  for (size_t i = 0; i < stages.size(); ++i) {
    const CurriculumStage& st = stages[i];
    for (const auto& ctx : st.contexts)
      for (const auto& name : ctx.learned) {
        auto it = produced.find(name);
        std::vector<std::string> known;
        for (const auto& [k, v] : produced) known.push_back(k);
        if (it == produced.end())
          throw ScriptError(st.where(ctx.name) + ": roger.learned('" + name + "') names no skill of this curriculum; " +
                                (known.empty() ? "no stage yields one (give a stage skill = {name = ..., context = ...})"
                                               : "skills: " + join(known)),
                            st.file, st.line, "");
        if (it->second == i)
          throw ScriptError(st.where(ctx.name) + ": uses the learned skill '" + name +
                                "', which this very stage yields; a learned skill can only be used by later stages",
                            st.file, st.line, "");
        if (it->second > i)
          throw ScriptError(st.where(ctx.name) + ": uses the learned skill '" + name + "', which the later stage '" +
                                stages[it->second].name + "' yields; move that stage before this one",
                            st.file, st.line, "");
      }
  }
}

}  // namespace

void install_curriculum_api(LuaSandbox& sandbox) {
  install_control_api(sandbox);
  lua_State* L = sandbox.state();
  lua_getglobal(L, "roger");
  lua_pushcfunction(L, l_stage);
  lua_setfield(L, -2, "stage");
  lua_pushcfunction(L, l_learned);
  lua_setfield(L, -2, "learned");
  lua_pop(L, 1);
  sandbox.call_protected(0, [](lua_State* L) { curriculum_detail::install_teaching_api(L); });
}

Curriculum Curriculum::load(const std::string& path_in, const SandboxLimits& limits) {
  const std::string path = resolve_curriculum_path(path_in);
  Curriculum cur;
  cur.impl_ = std::make_unique<Impl>();
  Impl& impl = *cur.impl_;
  impl.sandbox = std::make_unique<LuaSandbox>(limits);
  LuaSandbox& sandbox = *impl.sandbox;
  impl.file = path;
  impl.path = sandbox.display_name(path);
  install_curriculum_api(sandbox);
  lua_State* L = sandbox.state();
  lua_pushlightuserdata(L, &impl.book);
  lua_rawsetp(L, LUA_REGISTRYINDEX, &book_key);
  sandbox.set_main_script(path);
  try {
    read_stages(impl, path);
    check_learned_order(impl.stages);
    check_skill_names(impl.stages, sandbox);
    check_init_order(impl.stages);
  } catch (const ScriptError& e) {
    if (std::optional<ScriptError> moved = curriculum_detail::at_stage_field(e)) throw *moved;  // its line
    throw;
  }
  return cur;
}

// Runs the curriculum script and reads the stages of the table it returns into `impl`.
void Curriculum::read_stages(Impl& impl, const std::string& path) {
  LuaSandbox& sandbox = *impl.sandbox;
  sandbox.run_file(path, 1);
  finish_control_definitions(sandbox);

  // The text, for the lines of plain-table stages (a table carries no lines).
  const std::string text = read_file_text(path);
  std::string file = impl.path;  // for errors raised while C++ reads the returned table
  int line = 0;
  bool booked = false;  // reading a table roger.stage accepted (take_stage)
  const auto read = [&](lua_State* L) {
    const int t = lua_gettop(L);
    if (!lua_istable(L, t))
      luaL_error(L, "a curriculum must return a table {name = ..., description = ..., stages = {...}}, got %s",
                 lua_describe_value(L, t).c_str());
    // A misspelt top-level key (stagez) is placed where it is written, else at the returned table.
    const std::vector<std::string> known{"name", "description", "stages"};
    const LuaTableMap map(text);
    line = map.returned() >= 0 ? map.nodes()[size_t(map.returned())].line : map.return_line();
    if (map.returned() >= 0)
      for (const auto& e : map.nodes()[size_t(map.returned())].entries)
        if (std::find(known.begin(), known.end(), e.key) == known.end()) {
          line = e.line;
          break;
        }
    LuaFields top(L, t, "the curriculum", known);
    impl.name = top.string("name", fs::path(path).stem().string());
    if (const std::string problem = name_text_problem(impl.name); !problem.empty()) top.fail("field 'name' " + problem);
    impl.description = top.string("description", "");
    if (top.push("stages") == LUA_TNIL) top.fail("missing required field 'stages' (a list of roger.stage{...})");
    const int ss = lua_gettop(L);
    if (!lua_istable(L, ss)) top.wrong_type("stages", "a list of stages");
    const lua_Integer n = lua_Integer(lua_rawlen(L, ss));
    const std::string beside = lua_key_beside_list(L, ss);
    // A map of stages, as contexts may be written (found by a probe: "is empty" of a map that is not).
    if (n == 0 && !beside.empty())
      top.fail("'stages' is a map (it has the entry " + beside + "), and stages are a list in the curriculum's "
               "order: write {roger.stage{name = ...}, ...}");
    if (n == 0) top.fail("'stages' is empty: define at least one stage");
    // A stage written `Extra = roger.stage{...}` beside the list would be dropped without a word.
    if (!beside.empty())
      top.fail("'stages' must be a list {roger.stage{...}, ...}; it also has the named entry " + beside +
               ", which would be left out: write it in the list");
    for (lua_Integer i = 1; i <= n; ++i) {
      lua_rawgeti(L, ss, i);
      LuaCallback a, r, teacher;
      CurriculumStage st = take_stage(L, impl.book, impl.path, text, file, line, booked, a, r, teacher);
      for (const auto& other : impl.stages)
        if (other.name == st.name) luaL_error(L, "a second stage named '%s'", st.name.c_str());
      impl.absorbing_fns[st.name] = a;
      impl.reward_fns[st.name] = r;
      impl.teacher_fns[st.name] = teacher;
      impl.stages.push_back(std::move(st));
      lua_pop(L, 1);
    }
  };
  try {
    sandbox.read_returned_table(file, [&]() { return line; }, read);
    impl.book.loaded = true;
  } catch (const ScriptError& e) {
    // Found by a probe: a wrapper's `stage.learner.alpah = 0.3` after roger.stage returned was
    // placed at the roger.stage line alone, which had accepted the table.
    if (!booked) throw;
    throw ScriptError(e.message + " (roger.stage accepted this stage's table here; it was changed after roger.stage "
                                  "returned it, and the curriculum reads it again, with the change, when the script "
                                  "returns)",
                      e.file, e.line, e.traceback);
  }
}

namespace {

// The state table's __index, reached only by a name that is not one of its actions: an error at
// the callback's line naming the actions, where a nil would make `state.Phi3 == "CONV"` false for
// good and the stage fail to learn without a word.
int state_unknown_action(lua_State* L) {
  luaL_checktype(L, 1, LUA_TTABLE);  // getmetatable(state).__index(5, "x") reached lua_next on a number
  std::vector<std::string> names;
  lua_pushnil(L);
  while (lua_next(L, 1)) {
    lua_pop(L, 1);
    if (lua_type(L, -1) == LUA_TSTRING) names.push_back(lua_tostring(L, -1));
  }
  std::sort(names.begin(), names.end());
  const std::string key = lua_type(L, 2) == LUA_TSTRING ? lua_tostring(L, 2) : luaL_tolstring(L, 2, nullptr);
  return raise_at_reader(
      L, "state has no action '" + key + "'" + suggestion(key, names) + "; its actions: " + join(names) +
             " (a function shared by contexts of other actions reads one they may lack with rawget(state, name), "
             "nil there)");
}

// Pushes a state as a Lua table {[action name] = "CONV" | "!CONV" | "NOREF"}; reading another name
// is an error (state_unknown_action).
void push_state(lua_State* L, const CurriculumContext& ctx, const std::vector<Gamma>& state) {
  lua_createtable(L, 0, int(state.size()));
  for (size_t i = 0; i < state.size() && i < ctx.actions.size(); ++i) {
    lua_pushstring(L, gamma_name(state[i]));
    lua_setfield(L, -2, ctx.actions[i]->name().c_str());
  }
  curriculum_detail::set_strict_index(L, "roger.State", state_unknown_action);
}

}  // namespace

namespace curriculum_detail {

// A callback returns one value (the results from `base` + 1 on): the extra values of
// `return r, done`, as a Gymnasium step gives them, would otherwise be dropped without a word, and
// the episode would not end. None reads as nil, which the caller refuses with the type expected.
void refuse_more_results(lua_State* L, int base, const std::string& what, const std::string& expected,
                         const std::string& hint, const LuaCallback& fn) {
  const int n = lua_gettop(L) - base;
  if (n == 0) lua_pushnil(L);
  if (n <= 1) return;
  std::string values;
  for (int i = base + 1; i <= base + n && i <= base + 4; ++i)
    values += (values.empty() ? "" : ", ") + lua_describe_value(L, i);
  if (n > 4) values += ", ...";
  throw ScriptError(what + " must return " + expected + ", got " + std::to_string(n) + " values (" + values + ")" +
                        hint,
                    fn.file, fn.line, "");
}

void set_strict_index(lua_State* L, const char* type_name, lua_CFunction unknown) {
  if (luaL_newmetatable(L, type_name)) {
    lua_pushcfunction(L, unknown);
    lua_setfield(L, -2, "__index");
  }
  lua_setmetatable(L, -2);
}

}  // namespace curriculum_detail

LuaSandbox& Curriculum::sandbox() { return *impl_->sandbox; }

void Curriculum::set_world(const World* world) { impl_->world = world; }

namespace {

// How a teacher function's file is named in the trial's results: from the project's folder, else
// from the curriculum's, else whole; so that results do not depend on where a lab or the project sits
// (found by a probe: tables.md said "the function at /tmp/lab/cur/mine.lua:29" of curriculum mine.lua).
std::string named_in_results(const std::string& file, const std::string& curriculum_file) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(file, ec);
  if (ec || !p.is_absolute()) return file;
  for (const fs::path& folder : {fs::weakly_canonical(project_root(), ec),
                                 fs::weakly_canonical(fs::path(curriculum_file).parent_path(), ec)}) {
    const fs::path rel = p.lexically_relative(folder);
    if (!folder.empty() && !rel.empty() && *rel.begin() != "..") return rel.generic_string();
  }
  return file;
}

}  // namespace

std::unique_ptr<Teacher> Curriculum::make_teacher(const CurriculumStage& stage, const TaskSpace& space, uint64_t seed) {
  if (stage.teacher_lua)
    return curriculum_detail::make_lua_teacher(*impl_->sandbox, stage, impl_->teacher_fns.at(stage.name), space, seed,
                                               named_in_results(impl_->teacher_fns.at(stage.name).file, file()));
  if (stage.teacher) return roger::make_teacher(*stage.teacher, space, seed);
  return nullptr;
}

namespace {

// Pushes the value a source gives: an expression ("roger.teacher.alp_gmm{}"), a chunk that returns
// one, or a file that does. Nothing returned is an error: nil would read as the field left out.
void push_source_value(LuaSandbox& sandbox, const LuaSource& source, const char* field) {
  if (source.file) {
    sandbox.load_file(source.name);
  } else {
    try {
      sandbox.load_string("return " + source.text, "=" + source.name);  // an expression
    } catch (const ScriptError& as_expression) {
      try {
        sandbox.load_string(source.text, "=" + source.name);  // statements (that end in a return)
      } catch (const ScriptError& as_chunk) {
        if (as_chunk.line > as_expression.line) throw;  // the reading that got further says more
        throw as_expression;
      }
    }
  }
  sandbox.call(0, 1);
  if (lua_isnil(sandbox.state(), -1))
    throw ScriptError(std::string("gives no value for '") + field + "': " +
                          (source.file ? "the file must end in a return" : "write a value, or a chunk that returns one"),
                      source.file ? sandbox.display_name(source.name) : source.name, 1, "");
}

}  // namespace

void Curriculum::set_teaching(const std::string& name, const LuaSource& tasks, const LuaSource& teacher,
                              const std::string& scenario) {
  if (tasks.empty() && teacher.empty()) return;
  auto it = std::find_if(impl_->stages.begin(), impl_->stages.end(), [&](const auto& s) { return s.name == name; });
  if (it == impl_->stages.end()) stage(name);  // throws, listing the stages
  CurriculumStage st = *it;
  if (!scenario.empty()) st.scenario = scenario;  // checked against what the environment plays
  if (!tasks.empty()) st.tasks = TaskSpace();
  st.teacher.reset();
  st.teacher_lua = false;
  LuaSandbox& sandbox = *impl_->sandbox;
  lua_State* L = sandbox.state();
  LuaStackGuard guard(L);
  std::vector<const char*> fields;
  for (const auto& [source, field] : {std::make_pair(&tasks, "tasks"), std::make_pair(&teacher, "teacher")})
    if (!source->empty()) {
      push_source_value(sandbox, *source, field);
      fields.push_back(field);
    }
  LuaCallback fn;
  try {
    sandbox.call_protected(int(fields.size()), [&](lua_State* L) {
      const int first = lua_gettop(L) - int(fields.size()) + 1;
      lua_newtable(L);  // the fields as a stage writes them
      for (size_t i = 0; i < fields.size(); ++i) {
        lua_pushvalue(L, first + int(i));
        lua_setfield(L, -2, fields[i]);
      }
      const LuaFields f(L, lua_gettop(L), st.where(), {"tasks", "teacher"});
      curriculum_detail::parse_teaching(L, f, st, fn, false, false);
    });
  } catch (const ScriptError& e) {
    if (!e.file.empty()) throw;
    // Read from C++, without a line: at the source of the field the message names.
    const bool of_teacher = tasks.empty() || (!teacher.empty() && e.message.find("teacher") != std::string::npos);
    const LuaSource& at = of_teacher ? teacher : tasks;
    throw ScriptError(e.message, at.file ? sandbox.display_name(at.name) : at.name, 1, "");
  }
  st.test = it->test;  // an environment runs no test set
  st.scenario = it->scenario;  // the stage's own, as recorded; the environment plays `scenario`
  *it = std::move(st);
  impl_->teacher_fns[name] = fn;
}

void Curriculum::begin_episode() {
  // Protected: a script at its memory budget makes even an empty table an error, not an abort.
  int& ref = impl_->episode_ref;
  impl_->sandbox->call_protected(0, [&ref](lua_State* L) {
    luaL_unref(L, LUA_REGISTRYINDEX, ref);
    ref = LUA_NOREF;
    lua_newtable(L);
    ref = luaL_ref(L, LUA_REGISTRYINDEX);
  });
}

namespace {

// The callbacks' last two arguments: the world (nil without one) and the episode's table (a fresh
// one when no episode was begun, so a callback may always write to it).
void push_world_and_episode(lua_State* L, const World* world, int& episode_ref) {
  if (world) push_world(L, *world);
  else lua_pushnil(L);
  if (episode_ref == LUA_NOREF) {
    lua_newtable(L);
    episode_ref = luaL_ref(L, LUA_REGISTRYINDEX);
  }
  lua_rawgeti(L, LUA_REGISTRYINDEX, episode_ref);
}

}  // namespace

bool Curriculum::call_absorbing(const CurriculumStage& stage, const CurriculumContext& context,
                                const std::vector<Gamma>& state, double time) {
  const LuaCallback& fn = impl_->absorbing_fns.at(stage.name);
  lua_State* L = impl_->sandbox->state();
  LuaStackGuard guard(L);
  lua_rawgeti(L, LUA_REGISTRYINDEX, fn.ref);
  push_state(L, context, state);
  lua_pushnumber(L, time);
  push_world_and_episode(L, impl_->world, impl_->episode_ref);
  const int base = lua_gettop(L) - 5;  // below the function
  try {
    impl_->sandbox->call(4, LUA_MULTRET);
  } catch (const ScriptError& e) {
    throw ScriptError(stage.where(context.name) + ": absorbing function: " + e.message,
                      e.file.empty() ? fn.file : e.file, e.file.empty() ? fn.line : e.line, e.traceback);
  }
  refuse_more_results(L, base, stage.where(context.name) + ": the absorbing function", "true or false", "", fn);
  if (!lua_isboolean(L, -1))
    throw ScriptError(stage.where(context.name) + ": the absorbing function must return true or false, got " +
                          lua_describe_value(L, -1),
                      fn.file, fn.line, "");
  return lua_toboolean(L, -1);
}

double Curriculum::call_reward(const CurriculumStage& stage, const CurriculumContext& context,
                               const std::vector<Gamma>& state, int action, const std::string& event, double time) {
  const LuaCallback& fn = impl_->reward_fns.at(stage.name);
  lua_State* L = impl_->sandbox->state();
  LuaStackGuard guard(L);
  lua_rawgeti(L, LUA_REGISTRYINDEX, fn.ref);
  push_state(L, context, state);
  if (action >= 0 && size_t(action) < context.actions.size()) {
    lua_pushstring(L, context.actions[size_t(action)]->name().c_str());
  } else {
    lua_pushnil(L);
  }
  lua_pushstring(L, event.c_str());
  lua_pushnumber(L, time);
  push_world_and_episode(L, impl_->world, impl_->episode_ref);
  const int base = lua_gettop(L) - 7;  // below the function
  try {
    impl_->sandbox->call(6, LUA_MULTRET);
  } catch (const ScriptError& e) {
    throw ScriptError(stage.where(context.name) + ": reward function: " + e.message,
                      e.file.empty() ? fn.file : e.file, e.file.empty() ? fn.line : e.line, e.traceback);
  }
  refuse_more_results(L, base, stage.where(context.name) + ": the reward function", "one finite number",
                      "; an episode ends when the stage's absorbing holds or at its time_limit", fn);
  if (lua_type(L, -1) != LUA_TNUMBER || !std::isfinite(lua_tonumber(L, -1)))
    throw ScriptError(stage.where(context.name) + ": the reward function must return a finite number, got " +
                          lua_describe_value(L, -1) + " (event '" + event + "')",
                      fn.file, fn.line, "");
  if (const std::string p = reward_magnitude_problem(lua_tonumber(L, -1)); !p.empty())
    throw ScriptError(stage.where(context.name) + ": the reward function must return " + p + " (event '" + event + "')",
                      fn.file, fn.line, "");
  return lua_tonumber(L, -1);
}

std::string resolve_curriculum_path(const std::string& arg) {
  return resolve_script_path(arg, "curricula", "curriculum", "curricula in curricula/",
                             is_curriculum_script);
}

bool is_curriculum_script(const std::string& path) { return script_has_key(path, "stages"); }

namespace {

// Generates a world of seed 0, or of the first of seeds 1 to 19 that can be placed when seed 0
// cannot: training skips a task whose layout fails (docs/curricula.md, Teachers), so an end is
// wrong only when no layout holds it. Throws the first seed's error when none can, and any other
// error at once.
void generate_some_seed(Scenario& s) {
  std::optional<PlacementError> first;
  for (uint64_t seed = 0; seed < 20; ++seed) {
    try {
      s.generate(seed);
      return;
    } catch (const PlacementError& e) {
      if (!first) first = e;
    }
  }
  throw *first;
}

// The task space a trial of the stage draws from: the stage's, less the parameters the command's
// --set fixes (as TrialTeacher takes it).
TaskSpace trial_task_space(const CurriculumStage& st, const ParamList& sets) {
  std::vector<std::string> fixed;
  for (const auto& [k, v] : sets) fixed.push_back(k);
  return st.tasks.without(fixed);
}

// An error's text without Lua's traceback: for a world at a task space's end, the traceback runs
// through the scenario's library, and the message already names the axis's line and the value.
std::string untraced(const std::exception& e) {
  const std::string text = e.what();
  return text.substr(0, text.find("\nstack traceback:"));
}

// Every axis at its highest at once (the last choice, the last level an LCAS teacher lifts), in
// `s`: parameters that combine go out of range only together (found by a probe: a noise delay of
// roger.int(0, 30) ticks times a noise_scale of roger.real(0.5, 2) passed check, and training
// failed at 54 ticks). Only an error of the parameters counts: a corner no layout holds is a task
// training skips.
void check_high_corner(const CurriculumStage& st, const TaskSpace& space, Scenario& s, bool lifts,
                       const std::string& with_sets, std::vector<std::string>& problems) {
  if (space.empty() || space.size() + (lifts ? 1 : 0) < 2) return;  // one axis: its ends were tried
  ParamList corner = space.params(space.from_unit(std::vector<double>(space.size(), 1.0)));
  for (size_t i = 0; i < space.size(); ++i)
    if (space.dims()[i].kind == TaskDim::Kind::kChoice) corner[i].second = space.dims()[i].choices.back();
  if (lifts) corner.push_back({st.teacher->lift, st.teacher->levels.back()});
  for (const auto& [k, v] : corner) s.set_param(k, v);
  try {
    generate_some_seed(s);
  } catch (const PlacementError&) {
  } catch (const std::exception& e) {
    const TaskDim& first = space.dims().front();
    const std::string at = first.file.empty() ? "" : first.file + ":" + std::to_string(first.line) + ": ";
    problems.push_back(at + st.where() + ": scenario '" + st.scenario + "' with " + params_text(corner) +
                       " (the highest corner of the stage's task space" + with_sets + "): " + untraced(e));
  }
}

// A scenario's error, said of the stage's scenario once: an error that names the scenario itself
// ("scenario 'cluttered' (scenarios/cluttered.lua) has no parameter ...") is not prefixed again.
std::string of_scenario(const CurriculumStage& st, const std::string& what) {
  const std::string named = "scenario '" + st.scenario + "'";
  return what.compare(0, named.size(), named) == 0 ? what : named + ": " + what;
}

// The worlds at the ends of a stage's task space: each axis at its lowest and highest value (each
// value of a choice, each level an LCAS teacher lifts), the other axes at their first value, in
// the parameters of `context` (the first when null) and the command's --set: where placements fail
// first. Without `layouts`, an end no layout of seeds 0 to 19 holds is no problem, only an error of
// the parameters (a reset skips a task it cannot place, and says so).
void check_task_space_ends(const CurriculumStage& st, const SandboxLimits& limits, const ParamList& sets,
                           std::vector<std::string>& problems, const CurriculumContext* context = nullptr,
                           bool layouts = true) {
  const TaskSpace space = trial_task_space(st, sets);
  const bool lifts = st.teacher && st.teacher->kind == TeacherSpec::Kind::kLcas && space.index(st.teacher->lift) < 0 &&
                     std::none_of(sets.begin(), sets.end(), [&](const auto& s) { return s.first == st.teacher->lift; });
  if (space.empty() && !lifts) return;
  const TaskPoint low = space.from_unit(std::vector<double>(space.size(), 0.0));
  const TaskPoint high = space.from_unit(std::vector<double>(space.size(), 1.0));
  struct Try {
    std::string name, value, at;  // at: "file:line: " of the axis or teacher, "" when unknown
  };
  auto at = [](const std::string& file, int line) { return file.empty() ? "" : file + ":" + std::to_string(line) + ": "; };
  std::vector<Try> tries;  // over the low corner
  for (size_t i = 0; i < space.size(); ++i) {
    const TaskDim& d = space.dims()[i];
    if (d.kind == TaskDim::Kind::kChoice) {
      for (const auto& c : d.choices) tries.push_back({d.name, c, at(d.file, d.line)});
    } else {
      tries.push_back({d.name, space.params(low)[i].second, at(d.file, d.line)});
      tries.push_back({d.name, space.params(high)[i].second, at(d.file, d.line)});
    }
  }
  if (lifts)
    for (const auto& level : st.teacher->levels)
      tries.push_back({st.teacher->lift, level, at(st.teacher->file, st.teacher->line)});
  const std::string with_sets = sets.empty() ? "" : ", " + params_text(sets) + " by --set";
  const size_t before = problems.size();
  try {
    Scenario s = Scenario::load(st.scenario, limits);
    for (const auto& [k, v] : st.scenario_params(context ? *context : st.contexts.front())) s.set_param(k, v);
    for (const auto& [k, v] : sets) s.set_param(k, v);
    for (const auto& [k, v] : space.params(low)) s.set_param(k, v);
    for (const Try& t : tries) {
      const int i = space.index(t.name);
      const auto problem = [&](const std::exception& e) {
        problems.push_back(t.at + st.where() + ": scenario '" + st.scenario + "' with " + t.name + " = " + t.value +
                           " (an end of the stage's task space" + with_sets + "): " + untraced(e));
      };
      try {
        s.set_param(t.name, t.value);
        generate_some_seed(s);
      } catch (const PlacementError& e) {
        if (layouts) problem(e);
      } catch (const std::exception& e) {
        problem(e);
      }
      if (i >= 0) s.set_param(t.name, space.params(low)[size_t(i)].second);
    }
    if (problems.size() == before) check_high_corner(st, space, s, lifts, with_sets, problems);
  } catch (const std::exception& e) {
    problems.push_back(st.where() + ": " + of_scenario(st, e.what()));
  }
}

// The test set as the stage's trials meet it: task i in world seed checkpoints.seeds + i, in the
// parameters of each context (each distinct set once). It is not skipped as a training task is,
// so a task no layout of its seed holds fails every trial at the first evaluation that runs it (a
// checkpoint's, or only the final one's for a task past the checkpoints' count): refused here,
// naming the task and which evaluations run it.
void check_test_set(Curriculum& cur, const CurriculumStage& st, const SandboxLimits& limits, const ParamList& sets,
                    std::vector<std::string>& problems) {
  if (!st.teaches()) return;
  const TaskSpace space = trial_task_space(st, sets);
  std::vector<TaskPoint> tasks;
  ParamList extra;  // what the teacher sets beside the test tasks (an LCAS lift's last level)
  try {
    tasks = st.test_tasks(space, std::max(st.checkpoint_test_tasks(), st.final_test_tasks()));
    extra = cur.make_teacher(st, space, 0)->test_params();
  } catch (const std::exception& e) {
    return problems.push_back(st.where() + ": test: " + e.what());
  }
  std::set<ParamList> seen;
  for (const auto& ctx : st.contexts) {
    const ParamList params = st.scenario_params(ctx);
    if (!seen.insert(params).second) continue;
    size_t i = 0;
    try {
      Scenario s = Scenario::load(st.scenario, limits);
      s.set_params(params);
      s.set_params(sets);
      for (; i < tasks.size(); ++i) {
        s.set_params(space.params(tasks[i]));
        s.set_params(extra);
        s.generate(st.checkpoints.seeds + i);
      }
    } catch (const PlacementError& e) {
      ParamList task = space.params(tasks[i]);
      task.insert(task.end(), extra.begin(), extra.end());
      // At the stage's `test` field, without the scenario's traceback: the task and seed say it
      // (found by a probe: it was said at the roger.stage{ line, a traceback after it).
      const std::string at = st.file.empty() ? "" : st.file + ":" + std::to_string(curriculum_detail::field_line(st, "", "test")) + ": ";
      const std::string why = e.what();
      problems.push_back(at + (ctx.params.empty() ? st.where() : st.where(ctx.name)) + ": test task " +
                         std::to_string(i + 1) + " of " +
                         std::to_string(tasks.size()) + " (" + params_text(task) + ") cannot be placed in world seed " +
                         std::to_string(st.checkpoints.seeds + i) + ", where every trial's " +
                         (int(i) < st.checkpoint_test_tasks()
                              ? std::string("checkpoints and final evaluation run it")
                              : "final evaluation runs it (its checkpoints run the first " +
                                    std::to_string(st.checkpoint_test_tasks()) + ")") +
                         " (the test set is not skipped): " + why.substr(0, why.find("\nstack traceback:")));
    } catch (const std::exception& e) {
      problems.push_back(st.where(ctx.name) + ": " + of_scenario(st, e.what()));
    }
  }
}

}  // namespace

namespace {

// A stage's Lua absorbing and reward functions called as at the first decision of an episode of
// the context, in world seed 0 with every action NOREF, and the reward also as at the episode's
// end (event "timeout", then "absorbing", at the time limit, after the first action): a misspelt
// field of `world` or a reward that is not a number is found here rather than in training, on
// the branch of an event as on the decisions' (found by a probe: a slip under `event ==
// "timeout"` passed check and stopped training at its first episode's end).
void check_callbacks(Curriculum& cur, const CurriculumStage& st, const CurriculumContext& ctx, const WorldSpec& spec,
                     std::vector<std::string>& problems) {
  if (!st.absorbing_lua && !st.reward_lua) return;
  World world;
  const char* called_as = "an episode's first decision";
  try {
    world.reset(spec);
    cur.set_world(&world);
    cur.begin_episode();
    const std::vector<Gamma> state(ctx.actions.size(), Gamma::kNoRef);
    if (st.absorbing_lua) cur.call_absorbing(st, ctx, state, 0.0);
    if (st.reward_lua) {
      cur.call_reward(st, ctx, state, 0, "decision", 0.0);
      QuietPrints prints(cur.sandbox(), "roger check called the reward function again, at an episode's end");
      prints.quiet();
      const double end = st.episode_time_limit(spec);
      const std::pair<const char*, const char*> ends[] = {{"timeout", "an episode's end by time-out"},
                                                          {"absorbing", "an episode's end in the absorbing state"}};
      for (const auto& [event, as] : ends) {
        called_as = as;
        cur.call_reward(st, ctx, state, 0, event, end);
      }
    }
  } catch (const std::exception& e) {
    problems.push_back(with_note_on_first_line(
        e.what(), std::string(" (called as at ") + called_as + ", world seed 0, every action NOREF)"));
  }
  cur.set_world(nullptr);
}

// An action of the context that sends Roger to a goal region (a binding's, or a navigator's own)
// none of the stage's first worlds (seeds 0 to 4 of `s`) has: it would be NOREF at every
// decision (found by a newcomer in a skill script, which roger check already refused for a
// binding; a curriculum's actions were not looked at).
void check_regions(const CurriculumStage& st, const CurriculumContext& ctx, Scenario& s, const WorldSpec& seed0,
                   std::vector<std::string>& problems) {
  for (const ControllerPtr& action : ctx.actions) {
    if (!first_region_beyond(action.get(), int(seed0.goals.size())).controller) continue;
    // Beyond seed 0's regions: the most of the first worlds decides (the count may vary by seed).
    int regions = 0;
    try {
      for (uint64_t seed = 0; seed < 5; ++seed) regions = std::max(regions, int(s.generate(seed).goals.size()));
    } catch (const std::exception&) {
      return;  // the worlds' own problem, said where they are built
    }
    const RegionUse use = first_region_beyond(action.get(), regions);
    if (!use.controller) continue;
    problems.push_back(st.written_at() + st.where(ctx.name) + ": action '" + action->name() + "': " +
                       region_use_problem(use, st.scenario, regions));
    return;
  }
}

// The history roger check fed a teacher function before its error: "2 episodes failed, then 1
// succeeded", "1 episode failed", or, when none failed, "1 episode succeeded" (it said "0 episodes
// failed, then 1 succeeded": found by a probe).
std::string history_said(int failed, int succeeded) {
  if (failed == 0) return counted(succeeded, "episode") + " succeeded";
  return counted(failed, "episode") + " failed" + (succeeded ? ", then " + std::to_string(succeeded) + " succeeded" : "");
}

// A stage's Lua teacher function called as between training episodes, on a history it builds:
// the first ten episodes failed, the next twenty succeeded (a learner that learns; under a budget
// of fewer than 30 episodes, a third of them failed and the rest succeeded), so a function that
// reads `history` or changes its mind after a run of successes meets both cases. An error
// in it, or a result outside the task space, is found here rather than after a trial's first
// episodes.
void check_teacher_function(Curriculum& cur, const CurriculumStage& st, const ParamList& sets,
                            std::vector<std::string>& problems) {
  if (!st.teacher_lua) return;
  // No more calls than training makes (found by a probe: a function that fails after episode 10 of
  // a 5-episode budget was refused, and trained).
  const int episodes = st.budget_episodes > 0 ? std::min(30, st.budget_episodes) : 30, failed_first = episodes / 3;
  const double limit = st.time_limit > 0.0 ? st.time_limit : st.time_per_object;  // a world of one object
  int episode = 0;
  QuietPrints prints(cur.sandbox(), "roger check called the teacher function again");  // shown for the first call
  try {
    const std::unique_ptr<Teacher> teacher = cur.make_teacher(st, trial_task_space(st, sets), 0);
    for (; episode < episodes; ++episode) {
      if (episode == 1) prints.quiet();
      TaskOutcome o;
      o.task = teacher->next().task;
      o.world_seed = uint64_t(episode);
      o.success = episode >= failed_first;
      // As training records them with the stage's fixed rewards: a failure times out at the limit, a
      // success ends halfway (found by a probe: rewards 0 and 1 and a time of 5 s past a 4 s limit,
      // so a function that read them passed here and failed at training's first episode).
      o.reward = o.success ? st.rewards.success_reward : st.rewards.timeout_reward;
      o.sim_s = o.success ? 0.5 * limit : limit;
      teacher->record(o);
    }
  } catch (const std::exception& e) {
    // The teacher's message names the episode; the history it read is roger check's own.
    const int failed = std::min(episode, failed_first), succeeded = episode - failed;
    problems.push_back(episode == 0 ? std::string(e.what())
                                    : with_note_on_first_line(e.what(), " (roger check's history: " + history_said(failed, succeeded) + ")"));
  }
}

}  // namespace

std::vector<std::string> check_curriculum(const std::string& path, const SandboxLimits& limits, const ParamList& sets,
                                          const std::vector<std::string>& stages, const std::string& sets_from) {
  std::optional<Curriculum> cur;
  try {
    cur.emplace(Curriculum::load(path, limits));
  } catch (const std::exception& e) {
    return {e.what()};
  }
  return check_curriculum(*cur, limits, sets, stages, sets_from);
}

std::vector<std::string> check_curriculum(Curriculum& cur, const SandboxLimits& limits, const ParamList& sets,
                                          const std::vector<std::string>& stages, const std::string& sets_from) {
  struct SetRefused {};  // a value of `sets` the stage's scenario refused, said already
  std::vector<std::string> problems;
  // Each context's world: its parameters may change the body or the senses (contexts of the same
  // parameters are one check).
  for (const auto& st : cur.stages()) {
    if (!stages.empty() && std::find(stages.begin(), stages.end(), st.name) == stages.end()) continue;
    std::set<std::vector<std::pair<std::string, std::string>>> checked;
    bool worlds_failed = false;  // a context's world could not be built (said above)
    const CurriculumContext* called = nullptr;  // the last context whose callbacks were called, in `called_world`
    WorldSpec called_world;
    for (const auto& ctx : st.contexts) {
      // Every context is built (its actions are its own: check_regions); the errors of its world
      // are said once per set of parameters.
      const bool first = checked.insert(st.scenario_params(ctx)).second;
      const std::string where = ctx.params.empty() ? st.where() : st.where(ctx.name);
      WorldSpec spec;
      try {
        Scenario s = Scenario::load(st.scenario, limits);
        for (const auto& [k, v] : st.scenario_params(ctx)) s.set_param(k, v);
        // A value the command gave is its own error, not the stage's (found by a probe: a misspelt
        // --set was placed at a line of the shipped library that writes the paper's stages).
        for (const auto& [k, v] : sets) {
          try {
            s.set_param(k, v);
          } catch (const std::exception& e) {
            const std::string written = st.file.empty() || st.line <= 0 ? ""
                                        : " (" + st.file + ":" + std::to_string(st.line) + ")";
            if (first)
              problems.push_back(sets_from + " " + k + "=" + v + ": " + where + written + ": " + of_scenario(st, e.what()));
            throw SetRefused();
          }
        }
        spec = s.generate(0);
        check_regions(st, ctx, s, spec, problems);
      } catch (const SetRefused&) {
        worlds_failed = true;
        continue;
      } catch (const std::exception& e) {
        // Placed at the params table that asked for this world (the context's, else the stage's),
        // as a bad parameter is: a level noise_scale carries past its range, say; else at the stage.
        const bool asked = !ctx.params.empty() || !st.params.empty();
        const int line = asked ? curriculum_detail::params_line(st, ctx.params.empty() ? "" : ctx.name) : st.line;
        const std::string at = !st.file.empty() && line > 0 ? st.file + ":" + std::to_string(line) + ": " : "";
        if (first) problems.push_back(at + where + ": " + of_scenario(st, e.what()));
        worlds_failed = true;
        continue;
      }
      try {
        st.episode_time_limit(spec);
      } catch (const std::exception& e) {
        if (first) problems.push_back(e.what());
        continue;
      }
      check_callbacks(cur, st, ctx, spec, problems);
      if (st.teacher_lua) called = &ctx, called_world = spec;  // kept only to call them again below
    }
    // What training refuses first: a teacher the run's parameters leave nothing to do (found by a
    // probe: check passed with the --set or the run's params that failed every trial).
    try {
      std::vector<std::string> fixed;
      for (const auto& [k, v] : sets) fixed.push_back(k);
      st.check_fixed(fixed, sets_from);
    } catch (const std::exception& e) {
      problems.push_back(e.what());
      continue;
    }
    const size_t before_teacher = problems.size();
    check_teacher_function(cur, st, sets, problems);
    // The callbacks again once the teacher has run, as in training, where the teacher draws before
    // each episode (found by a probe: a teacher's rng kept and drawn in absorbing passed check, the
    // callbacks having run before any teacher, and training refused it).
    if (st.teacher_lua && called && problems.size() == before_teacher)
      check_callbacks(cur, st, *called, called_world, problems);
    // The task space's worlds and the test set's are the same worlds in other parameters: those
    // that could not be built would only be said again (found by a probe: a --set the scenario
    // lacks was said twice, the second time without its line).
    if (worlds_failed) continue;
    const size_t before = problems.size();
    check_task_space_ends(st, limits, sets, problems);
    if (problems.size() == before) check_test_set(cur, st, limits, sets, problems);  // else the same holes again
  }
  return problems;
}

std::vector<std::string> task_space_end_problems(const CurriculumStage& stage, const std::string& context,
                                                const SandboxLimits& limits, const ParamList& sets) {
  std::vector<std::string> problems;
  check_task_space_ends(stage, limits, sets, problems, &stage.context(context), false);
  return problems;
}

std::vector<std::string> check_test_sets(const std::string& path, const SandboxLimits& limits, const ParamList& sets,
                                         const std::vector<std::string>& stages) {
  std::vector<std::string> problems;
  Curriculum cur = Curriculum::load(path, limits);
  for (const auto& st : cur.stages())
    if (stages.empty() || std::find(stages.begin(), stages.end(), st.name) != stages.end())
      check_test_set(cur, st, limits, sets, problems);
  return problems;
}

std::vector<std::filesystem::path> curriculum_source_files(const Curriculum& cur, const SandboxLimits& limits) {
  std::vector<std::filesystem::path> files = cur.source_files();
  std::set<std::string> scenarios;
  for (const auto& st : cur.stages()) {
    if (!scenarios.insert(st.scenario).second) continue;
    Scenario s = Scenario::load(st.scenario, limits);
    for (const auto& f : s.sandbox().source_files())
      if (std::find(files.begin(), files.end(), f) == files.end()) files.push_back(f);
  }
  return files;
}

}  // namespace roger
