// scenario.cpp: the Scenario class: loading a script, checking the table it returns, and
// running its generator; and `roger check` for scenarios.
#include "script/scenario/scenario.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iterator>
#include <map>
#include <optional>
#include <set>

#include <lua.hpp>

#include "core/body.h"
#include "core/error.h"
#include "core/fileio.h"
#include "core/shape.h"
#include "core/text.h"
#include "script/scenario/scenario_internal.h"
#include "script/sandbox/lua_tokens.h"

namespace roger {
namespace fs = std::filesystem;
using namespace scenario_detail;

namespace {

// A script is read as a scenario unless it returns another kind's field (docs/authoring.md): a
// misspelt one of those ('stage', 'policy') lands here, so the error names the kind it belongs to
// (found by a probe: `return { policy = {} }` listed the scenario's fields alone).
std::string other_kind_hint(const std::string& key, const std::vector<std::string>& known) {
  if (key.empty() || !suggestion(key, known).empty()) return "";
  for (const auto& [field, kind] : std::vector<std::pair<std::string, std::string>>{
           {"stages", "a curriculum"}, {"policies", "a skill script"}, {"runs", "a batch script"}})
    if (!suggestion(key, {field}).empty() ||  // or its singular: 'policy' for 'policies'
        (key.size() >= 4 && field.rfind(key.substr(0, key.size() - 1), 0) == 0))
      return " (did you mean '" + field + "'? " + kind + " returns it; a script is read as a scenario when it "
             "returns no 'stages', 'policies' or 'runs')";
  return "";
}

}  // namespace

// Runs `body` inside a protected call (body may use the Lua API and throw). Errors without a
// location are attributed to the scenario file.
void Scenario::Impl::protect(const std::function<void(lua_State*)>& body, int nargs) {
  try {
    sandbox.call_protected(nargs, body);
  } catch (const ScriptError& e) {
    if (!e.file.empty()) throw;
    throw ScriptError(e.message, path, 0, e.traceback);
  }
}

// Checks the table the script returned (on the stack top) and keeps its generator.
void Scenario::Impl::read_table(lua_State* L, const LuaTableMap& map) {
  const int t = lua_gettop(L);
  const int returned = map.returned();
  const int table_line = returned >= 0 ? map.nodes()[size_t(returned)].line : map.return_line();
  // The line where the returned table's `key` is written, else the table's.
  auto key_line = [&](const std::string& key) {
    const LuaTableMap::Entry* e = map.entry(returned, key);
    return e ? e->line : table_line;
  };
  reading_line = table_line;
  if (!lua_istable(L, t))
    throw error(std::string("a scenario script must return a table {name=..., params={...}, "
                            "generate=function(world, rng, params) ... end}, got ") +
                    luaL_typename(L, t), reading_line);
  const std::vector<std::string> known{"description", "generate", "name", "params"};
  lua_pushnil(L);
  while (lua_next(L, t)) {
    lua_pop(L, 1);
    const std::string key = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : "";
    if (std::find(known.begin(), known.end(), key) == known.end())
      throw error("the scenario table has an unknown field " +
                      (key.empty() ? std::string("(a non-string key)") : "'" + key + "'" + suggestion(key, known)) +
                      "; known fields: " + join(known) + other_kind_hint(key, known),
                  key.empty() ? table_line : key_line(key));
  }
  auto text_field = [&](const char* key, const std::string& fallback) {
    const int type = lua_getfield(L, t, key);
    std::string v = fallback;
    if (type == LUA_TSTRING) v = lua_tostring(L, -1);
    else if (type != LUA_TNIL)
      throw error(std::string("the scenario's '") + key + "' must be a string, got " + luaL_typename(L, -1),
                  key_line(key));
    if (const std::string problem = utf8_problem(v); !problem.empty())  // shown in pictures, pages and results
      throw error(std::string("the scenario's '") + key + "' must be UTF-8 text, and " + problem, key_line(key));
    lua_pop(L, 1);
    return v;
  };
  name = text_field("name", fs::path(path).stem().string());
  description = text_field("description", "");
  reading_line = key_line("params");
  const LuaTableMap::Entry* params_entry = map.entry(returned, "params");
  if (lua_getfield(L, t, "params") != LUA_TNIL)
    read_params(L, -1, map, params_entry ? map.value_node(*params_entry) : -1);
  lua_settop(L, t);
  reading_line = key_line("generate");
  if (lua_getfield(L, t, "generate") != LUA_TFUNCTION)
    throw error(std::string("the scenario table needs generate = function(world, rng, params) ... "
                            "end, got ") + luaL_typename(L, -1), reading_line);
  lua_Debug ar;
  lua_pushvalue(L, -1);
  lua_getinfo(L, ">S", &ar);
  generate_line = ar.linedefined;
  generate_ref = luaL_ref(L, LUA_REGISTRYINDEX);
  reading_line = 0;
}

void install_scenario_api(LuaSandbox& sandbox) {
  lua_pushcfunction(sandbox.state(), install_api);
  sandbox.call(0, 0);
}

Scenario::Scenario() = default;
Scenario::Scenario(Scenario&&) noexcept = default;
Scenario& Scenario::operator=(Scenario&&) noexcept = default;
Scenario::~Scenario() = default;

Scenario Scenario::load(const std::string& path_in, const SandboxLimits& limits) {
  const std::string path = resolve_scenario_path(path_in);
  Scenario s;
  s.impl_ = std::make_unique<Impl>(limits);
  Impl& impl = *s.impl_;
  impl.path = impl.sandbox.display_name(path);
  install_scenario_api(impl.sandbox);
  impl.sandbox.set_main_script(path);
  impl.sandbox.run_file(path, 1);
  // A table carries no lines: where its fields are written, from the text, for the messages.
  const LuaTableMap map(read_file_text(path));
  impl.sandbox.read_returned_table(impl.path, [&]() { return impl.reading_line; },
                                   [&](lua_State* L) { impl.read_table(L, map); });
  return s;
}

const std::string& Scenario::name() const { return impl_->name; }
const std::string& Scenario::description() const { return impl_->description; }
const std::string& Scenario::path() const { return impl_->path; }
LuaSandbox& Scenario::sandbox() { return impl_->sandbox; }

std::vector<ScenarioParam> Scenario::params() const {
  std::vector<ScenarioParam> out;
  for (const auto& [key, slot] : impl_->params) out.push_back(slot.info);
  return out;
}

// The known parameters, each with its type, default and range; a family of more than eight that
// share the word before their first '_' (lib/body's 36 noise_* levels) as one entry, which a
// misspelt name's suggestion still reaches: a list of them all buried the others.
std::string Scenario::Impl::known_params_text() const {
  std::map<std::string, int> family;
  for (const auto& [k, slot] : params)
    if (const size_t cut = k.find('_'); cut != std::string::npos) ++family[k.substr(0, cut)];
  std::vector<std::string> known;
  std::set<std::string> folded;
  for (const auto& [k, slot] : params) {
    const size_t cut = k.find('_');
    const std::string word = cut == std::string::npos ? "" : k.substr(0, cut);
    if (word.empty() || family[word] <= 8) {
      known.push_back(describe_param(slot.info));
    } else if (folded.insert(word).second) {
      known.push_back(word + "_* (" + std::to_string(family[word]) + " parameters, " + k + " to " +
                      std::prev(params.lower_bound(word + "`"))->first + ")");
    }
  }
  return join(known, "; ");
}

// The hint for an unknown noise_* name among a scenario's noise parameters (lib/body's): a kind or a
// channel called by another common name (resolution for quantum, latency for delay, camera for
// image...) is pointed to ours, any other noise_ name is told how they are spelt (found by a probe:
// noise_joints_resolution got the 36 names folded to one entry). "" when `key` is not noise_*.
static std::string noise_param_hint(const std::string& key, const std::map<std::string, ParamSlot>& params) {
  static const std::map<std::string, std::string> same = {
      {"resolution", "quantum"}, {"precision", "quantum"}, {"step", "quantum"}, {"latency", "delay"},
      {"lag", "delay"},          {"loss", "dropout"},      {"drop", "dropout"}, {"offset", "bias"},
      {"std", "sigma"},          {"stddev", "sigma"},      {"sd", "sigma"},     {"camera", "image"},
      {"cameras", "image"},      {"eye", "image"},         {"eyes", "image"},   {"images", "image"},
      {"joint", "joints"},       {"encoder", "joints"},    {"encoders", "joints"}, {"arms", "joints"},
      {"pose", "base"},          {"odometry", "base"},     {"contact", "touch"}, {"contacts", "touch"},
      {"motor", "effort"},       {"motors", "effort"},     {"command", "effort"}, {"commands", "effort"}};
  if (key != "noise" && key.rfind("noise_", 0) != 0) return "";
  std::set<std::string> channels, kinds;
  for (const auto& [k, slot] : params) {
    if (k.rfind("noise_", 0) != 0 || k == "noise_scale") continue;
    const size_t cut = k.find('_', 6);
    channels.insert(k.substr(6, cut == std::string::npos ? std::string::npos : cut - 6));
    if (cut != std::string::npos) kinds.insert(k.substr(cut + 1));
  }
  if (channels.empty()) return "";
  const auto ours = [&](const std::string& word) { return same.count(word) ? same.at(word) : word; };
  const std::string rest = key.size() > 6 ? key.substr(6) : "";
  const size_t cut = rest.find('_');
  const std::string channel = ours(rest.substr(0, cut)), kind = cut == std::string::npos ? "" : ours(rest.substr(cut + 1));
  const std::string guess = "noise_" + channel + (kind.empty() || kind == "sigma" ? "" : "_" + kind);
  if (guess != key && params.count(guess)) return " (did you mean '" + guess + "'?)";
  return " (noise parameters are noise_CHANNEL, its sigma, and noise_CHANNEL_KIND; channels: " +
         join(std::vector<std::string>(channels.begin(), channels.end())) +
         "; kinds: " + join(std::vector<std::string>(kinds.begin(), kinds.end())) + "; and noise_scale)";
}

// The slot `key` would hold with `value` (in `out`), or why it cannot: an unknown key lists the
// known parameters (the nearest first); a value that does not fit says what the parameter takes,
// whole, and what it is for.
std::optional<std::string> Scenario::Impl::parse_param(const std::string& key, const std::string& value,
                                                       ParamSlot& out) const {
  auto it = params.find(key);
  if (it == params.end()) {
    std::vector<std::string> names;
    for (const auto& [k, slot] : params) names.push_back(k);
    std::string hint = suggestion(key, names);
    // noise_joints_sigma for noise_joints: a noise channel's sigma is its bare name (world:robot's
    // noise table writes it `sigma`).
    const std::string stem = key.size() > 6 && key.compare(key.size() - 6, 6, "_sigma") == 0 ? key.substr(0, key.size() - 6) : "";
    if (hint.empty() && !stem.empty() && params.count(stem)) hint = " (did you mean '" + stem + "', the channel's sigma?)";
    if (hint.empty()) hint = noise_param_hint(key, params);
    return "scenario '" + name + "' (" + path + ") has no parameter '" + key + "'" + hint + "; " +
           (names.empty() ? "it has no parameters" : "known parameters: " + known_params_text());
  }
  out = it->second;
  std::string why;
  if (!parse_slot(out, value, why)) {
    const ScenarioParam& p = it->second.info;
    return "parameter '" + key + "' of scenario '" + name + "' expects " + why + ", got '" + value + "' (" +
           (p.description.empty() ? "" : p.description + "; ") + "default " + p.default_value + ")";
  }
  out.info.value = slot_text(out);
  return std::nullopt;
}

void Scenario::set_param(const std::string& key, const std::string& value) {
  ParamSlot updated;
  if (const auto why = impl_->parse_param(key, value, updated)) throw Error(*why);
  impl_->params[key] = std::move(updated);
}

std::vector<std::string> Scenario::param_problems(const std::vector<std::pair<std::string, std::string>>& values,
                                                  bool from_lua) const {
  std::vector<std::string> problems;
  ParamSlot unused;
  for (const auto& [key, value] : values) {
    if (const auto why = impl_->parse_param(key, value, unused)) {
      problems.push_back(*why);
    } else if (from_lua && unused.info.type == ParamType::kBoolean && !unused.info.list && value != "true" &&
               value != "false") {
      problems.push_back("parameter '" + key + "' of scenario '" + impl_->name + "' is a boolean: write " + key +
                         " = true or " + key + " = false, got '" + value + "' (Lua reads 0 as true, so a number " +
                         "or a word would say one thing in Lua and another to roger; --set " + key + "=" + value +
                         " on the command line is taken)");
    }
  }
  return problems;
}

void Scenario::set_params(const std::vector<std::pair<std::string, std::string>>& values) {
  const std::vector<std::string> problems = param_problems(values);
  if (!problems.empty()) throw Error(join(problems, "; "));
  for (const auto& [key, value] : values) set_param(key, value);
}

WorldSpec Scenario::generate(uint64_t seed) {
  Impl& impl = *impl_;
  impl.no_placement = false;
  try {
    return generate_world(seed);
  } catch (const ScriptError& e) {
    if (impl.no_placement) throw PlacementError(e);
    throw;
  }
}

std::vector<std::pair<std::string, double>> body_param_values(const WorldSpec& world) {
  return {{"upper_arm", world.body.link_length[0]}, {"forearm", world.body.link_length[1]},
          {"base_radius", world.body.base_radius},  {"hand_radius", world.body.hand_radius},
          {"eye_pixels", double(world.eyes.pixels)}, {"eye_fov", world.eyes.fov}};
}

namespace {

// A parameter's value as a number (0 for one that is not a number or is not declared).
double param_number(const std::map<std::string, ParamSlot>& params, const std::string& name, double absent) {
  const auto it = params.find(name);
  if (it == params.end()) return absent;
  const ParamSlot& s = it->second;
  return s.info.type == ParamType::kNumber ? s.number : s.info.type == ParamType::kInteger ? double(s.integer) : 0.0;
}

// Why a declared parameter of one of lib/body.lua's names (`what` it is there) cannot be read as
// that, or "": those names are read as the body's and the noise's numbers whoever declared them,
// so one of another type is refused (found by a probe: a scenario's own noise_joints = "low" was
// read as 0, and the refusal spoke of a joints sigma of 0; upper_arm = "long" likewise).
std::string not_body_number(const std::string& name, const ParamSlot& p, const std::string& what) {
  if (p.info.type == ParamType::kNumber || p.info.type == ParamType::kInteger) return "";
  return "the parameter " + name + " is a " + param_type_name(p.info.type) + " (" + slot_text(p) +
         "), but " + name + " is a parameter of scenarios/lib/body.lua, a number (" + what +
         "), and roger reads a scenario's " + name + " as that: give yours another name";
}

// A noise parameter of body.PARAMS (docs/scenarios.md, Noise) that asks for noise the world does
// not have: the generator did not pass body.noise_of(p) to world:robot (or passed noise of its
// own). A noise study would record a level no episode had, so it is refused, naming the first such
// parameter. Found by a probe: --set noise_image=200 was echoed and ignored. Every declared
// parameter, times noise_scale, must give the world's very level, as body.noise_of makes it, at its
// default too; found by a later probe: in a world with noise of its own, --set noise_image=200 and
// noise_scale=8 were recorded while its fixed levels ran. A scenario with noise of its own gives its
// levels as the parameters' defaults (body.with_params's second table), or declares none of them.
void check_noise_params_used(const std::map<std::string, ParamSlot>& params, const NoiseParams& noise,
                             const std::function<void(const std::string&)>& fail) {
  const auto set = [&](const std::string& name) {
    const auto it = params.find(name);
    return it != params.end() && slot_text(it->second) != it->second.info.default_value;
  };
  if (const auto it = params.find("noise_scale"); it != params.end())
    if (const std::string why = not_body_number("noise_scale", it->second, "the factor of every noise level");
        !why.empty())
      return fail(why);
  const double scale = param_number(params, "noise_scale", 1.0);
  const bool scale_set = set("noise_scale");
  const std::pair<const char*, const ChannelNoise*> channels[] = {
      {"image", &noise.image}, {"joints", &noise.joints}, {"base", &noise.base}, {"touch", &noise.touch},
      {"effort", &noise.effort}};
  for (const auto& [name, c] : channels) {
    const std::string n = std::string("noise_") + name;
    struct Kind {
      std::string param;
      const char* what;
      double in_world;
    };
    const Kind kinds[] = {{n, "sigma", c->sigma},           {n + "_bias", "bias", c->bias},
                          {n + "_drift", "drift sigma", c->drift}, {n + "_tau", "drift tau", c->drift_tau},
                          {n + "_delay", "delay", double(c->delay)}, {n + "_dropout", "dropout", c->dropout},
                          {n + "_quantum", "quantum", c->quantum}};
    for (const auto& [param, what, in_world] : kinds) {
      if (const auto it = params.find(param); it != params.end())
        if (const std::string why = not_body_number(param, it->second, std::string(name) + " " + what); !why.empty()) {
          fail(why);
          continue;
        }
      const bool tau = param == n + "_tau";  // a time, not scaled
      if (!params.count(param) || (tau && c->drift == 0.0 && !set(param))) continue;  // no drift: tau unused
      double asked = (tau ? 1.0 : scale) * param_number(params, param, 0.0);
      if (param == n + "_delay") asked = std::floor(asked + 0.5);  // whole ticks, as body.noise_of rounds
      if (param == n + "_dropout") asked = std::min(1.0, asked);   // a probability, as body.noise_of caps it
      if (param == "noise_image_quantum") asked = image_quantum_levels(asked);  // whole levels, as read_noise keeps
      if (asked == in_world) continue;
      const std::string times_scale = scale == 1.0 || tau ? "" : " (times noise_scale = " + slot_text(params.at("noise_scale")) + ")";
      const std::string asking = set(param) || !scale_set
                                     ? "the parameter " + param + " = " + slot_text(params.at(param)) + times_scale
                                            : "noise_scale = " + slot_text(params.at("noise_scale")) + " (times " + param +
                                                  " = " + slot_text(params.at(param)) + ")";
      if (asked > 0.0 && in_world == 0.0 && !tau)
        fail(asking + " asks for " + name + " noise, but the world has none: pass body.noise_of(params) to world:robot{ "
             "noise = ... } (scenarios/lib/body.lua), or leave the parameter at 0");
      const bool defaults = !set(param) && !scale_set;
      // A tau of a world without drift is none, not 0 (found by a probe: "has 0", a tau no world has).
      const std::string has = tau && c->drift == 0.0 ? "no drift" : format_number(in_world);
      fail(asking + (defaults ? " (its default)" : "") + " asks for " + name + " " + what + " = " + format_number(asked) +
           ", but the world's Roger has " + has + ": its generator sets the noise itself rather "
           "than passing body.noise_of(params) to world:robot{ noise = ... } (scenarios/lib/body.lua); " +
           (defaults ? "pass it, or give the world's levels as the parameters' defaults (body.with_params(params, { " +
                           param + " = ... }))"
                     : std::string("leave ") + (set(param) ? "the parameter at its default" : "noise_scale at 1") +
                           ", or give the level in the scenario"));
    }
  }
}

// The locked-joint mask a `locked` parameter's text names ("left_elbow,right_elbow").
unsigned locked_mask(const std::string& names) {
  unsigned mask = 0;
  for (const auto& [name, dof] : lockable_joints())
    for (size_t at = names.find(name); at != std::string::npos; at = names.find(name, at + 1)) {
      const size_t end = at + name.size();
      const bool whole = (at == 0 || names[at - 1] == ',' || names[at - 1] == ' ') &&
                         (end == names.size() || names[end] == ',' || names[end] == ' ');
      if (whole) mask |= 1u << unsigned(dof);
    }
  return mask;
}

// A body parameter of body.PARAMS (docs/scenarios.md, Bodies) set away from its default whose
// value the world's Roger does not have: the generator did not pass body.of(p) to world:robot (or
// built a body of its own). A transfer study would record a body no episode had, so it is refused,
// as an unused noise parameter is. Found by a probe: --set upper_arm=0.3 was recorded and Roger
// kept the scenario's 0.9 m arms. A parameter at its default is asked about too (found by a later
// probe: the results recorded upper_arm = 0.5 of a 0.9 m arm); a scenario of another body gives
// it as the parameters' defaults (body.with_params's second table).
void check_body_params_used(const std::map<std::string, ParamSlot>& params, const WorldSpec& world,
                            const std::function<void(const std::string&)>& fail) {
  auto declared = [&](const std::string& name) -> const ParamSlot* {
    const auto it = params.find(name);
    return it != params.end() ? &it->second : nullptr;
  };
  auto refuse = [&](const std::string& name, const std::string& in_world) {
    const ParamSlot& p = *declared(name);
    const bool set = slot_text(p) != p.info.default_value;
    fail("the parameter " + name + " = " + slot_text(p) + (set ? "" : " (its default)") +
         " asks for a body the world's Roger does not have (its " + name + " is " + in_world + "): pass " +
         "body.of(params) to world:robot{ body = ..., eyes = ... } (scenarios/lib/body.lua), or " +
         (set ? "leave the parameter at its default"
              : "give the world's body as the parameters' defaults (body.with_params(params, { " + name + " = ... }))"));
  };
  for (const auto& [name, in_world] : body_param_values(world)) {
    if (!declared(name)) continue;
    if (const std::string why = not_body_number(name, *declared(name), "the body's " + name); !why.empty()) fail(why);
    else if (param_number(params, name, 0.0) != in_world) refuse(name, format_number(in_world));
  }
  if (const ParamSlot* p = declared("locked"); p && locked_mask(p->text) != world.body.locked) {
    std::string names;
    for (const auto& [name, dof] : lockable_joints())
      if (is_locked(world.body, dof)) names += (names.empty() ? "" : ",") + name;
    refuse("locked", names.empty() ? "none" : names);
  }
}

// The world a generator built, checked as a whole: Roger placed, shapes sound, every body and
// noise parameter the scenario declares (`params`) in force; with its seed and parameters. `fail`
// raises a problem at the generator's line.
WorldSpec checked_world(const WorldBuilder& w, uint64_t seed, const std::map<std::string, ParamSlot>& params,
                        const std::string& path, const std::function<void(const std::string&)>& fail) {
  if (!w.robot_set) fail("the generator did not place Roger: call world:robot{x=..., y=..., heading=...}");
  WorldSpec spec = w.spec;
  if (!w.stimulus_set && !spec.objects.empty()) spec.stimulus_colour = spec.objects.front().colour;
  try {
    for (auto& o : spec.objects) validate_shape(o.shape);
    for (auto& o : spec.obstacles) validate_shape(o.shape);
  } catch (const Error& e) {
    fail(e.what());
  }
  check_noise_params_used(params, spec.noise, fail);
  check_body_params_used(params, spec, fail);
  spec.scenario = path;
  spec.seed = seed;
  for (const auto& [key, slot] : params) spec.params[key] = slot_text(slot);
  return spec;
}

}  // namespace

// generate's third argument: a view of the values in force (scenario_world.cpp), whose reads go to
// the scenario's table of names read (made on the first generate).
void Scenario::Impl::push_params_view(lua_State* L) {
  lua_createtable(L, 0, int(params.size()));
  for (const auto& [key, slot] : params) {
    push_slot(L, slot);
    lua_setfield(L, -2, key.c_str());
  }
  const int data = lua_gettop(L);
  lua_new_view(L, data);
  lua_pushlightuserdata(L, lua_view_reads_key());
  if (reads_ref == LUA_NOREF) {
    lua_newtable(L);
    lua_pushvalue(L, -1);
    reads_ref = luaL_ref(L, LUA_REGISTRYINDEX);
  } else {
    lua_rawgeti(L, LUA_REGISTRYINDEX, reads_ref);
  }
  lua_rawset(L, -3);
  luaL_setmetatable(L, kParamsType);  // reading an undeclared parameter is an error
  lua_replace(L, data);
}

std::vector<std::string> Scenario::unread_params() {
  std::vector<std::string> unread;
  impl_->protect([&](lua_State* L) {
    if (impl_->reads_ref == LUA_NOREF) lua_newtable(L); else lua_rawgeti(L, LUA_REGISTRYINDEX, impl_->reads_ref);
    for (const auto& [key, slot] : impl_->params) {
      if (lua_getfield(L, -1, key.c_str()) == LUA_TNIL) unread.push_back(key);
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
  });
  return unread;
}

std::vector<std::string> Scenario::unread_params(const std::vector<std::pair<std::string, std::string>>& sets) {
  const std::vector<std::string> never = unread_params();
  std::vector<std::string> out;
  for (const auto& set : sets)
    if (std::binary_search(never.begin(), never.end(), set.first) &&
        std::find(out.begin(), out.end(), set.first) == out.end())
      out.push_back(set.first);
  return out;
}

WorldSpec Scenario::generate_world(uint64_t seed) {
  Impl& impl = *impl_;
  WorldSpec out;
  impl.protect([&](lua_State* L) {
    lua_rawgeti(L, LUA_REGISTRYINDEX, impl.generate_ref);
    auto* w = static_cast<WorldBuilder*>(lua_newuserdatauv(L, sizeof(WorldBuilder), 1));
    new (w) WorldBuilder();
    luaL_setmetatable(L, kWorldType);
    const int world = lua_gettop(L);
    w->rng = &push_rng(L, seed, open_rng_epoch(L)).rng;
    w->no_placement = &impl.no_placement;
    lua_pushvalue(L, -1);
    lua_setiuservalue(L, world, 1);  // the world keeps the rng alive
    impl.push_params_view(L);
    lua_pushvalue(L, world);  // keep the world on this frame after the call
    lua_insert(L, world - 1);
    {
      // The world is read-only once generate returns or fails (a script may have kept it).
      struct Finish {
        WorldBuilder* w;
        ~Finish() { w->finished = true; }
      } finish{w};
      const int base = lua_gettop(L) - 4;  // below generate and its three arguments
      lua_call(L, 3, LUA_MULTRET);
      // A budget its pcall caught ends the call with the budget's error (found by a probe: `return
      // pcall(loop)` was said to return a second value).
      if (lua_budget_spent(L)) return;
      // One result at most (found by a probe: `return nil, 5` passed, as Lua keeps the first).
      if (lua_gettop(L) - base > 1) {
        lua_settop(L, base + 2);  // the second result: the one that goes unread
        throw impl.error(std::string("the generator returned a second value (a ") + luaL_typename(L, -1) +
                             "), which is not read: it builds the world through world:robot{...}, world:object{...} "
                             "and the other methods of world, and returns nothing",
                         impl.generate_line);
      }
      if (lua_gettop(L) == base) lua_pushnil(L);
    }
    // Its rng (and its forks) draw no more: a failed generate's are past by the next one's epoch,
    // and nothing else runs in a scenario's Lua state.
    close_rng_epoch(L);
    // A generator builds the world through its methods; a value it returns would go unread (found
    // by a probe: a table of objects returned beside world:robot was dropped without a word).
    if (!lua_isnil(L, -1) && !lua_rawequal(L, -1, world - 1))
      throw impl.error(std::string("the generator returned a ") + luaL_typename(L, -1) +
                           ", which is not read: it builds the world through world:robot{...}, world:object{...} "
                           "and the other methods of world, and returns nothing",
                       impl.generate_line);
    out = checked_world(*w, seed, impl.params, impl.path,
                        [&](const std::string& why) { throw impl.error(why, impl.generate_line); });
  });
  return out;
}

std::string resolve_scenario_path(const std::string& arg) {
  return resolve_script_path(arg, "scenarios", "scenario", "scenarios in scenarios/");
}

namespace {

// A file named as messages show it: relative to the current folder, or to the project.
fs::path as_found(const std::string& shown) {
  std::error_code ec;
  const fs::path file(shown);
  return fs::is_regular_file(file, ec) ? file : project_root() / shown;
}

// Whether a scenario's name is a path (x.lua, worlds/x) rather than a bare name of scenarios/.
bool path_like(const std::string& name) {
  return fs::path(name).extension() == ".lua" || name.find('/') != std::string::npos;
}

}  // namespace

std::string resolve_scenario_near(const std::string& name, const std::string& naming_file,
                                  const std::string& also_beside) {
  std::error_code ec;
  const fs::path written(name);
  if (!path_like(name) || written.is_absolute() || naming_file.empty()) {
    try {
      resolve_scenario_path(name);
    } catch (const Error& e) {
      // Found by a probe: scenario = "walled" with walled.lua beside the curriculum said only that
      // scenarios/walled.lua does not exist.
      const fs::path file = naming_file.empty() ? fs::path() : as_found(naming_file);
      const fs::path with_lua = file.parent_path() / (name + ".lua");
      if (path_like(name) || naming_file.empty() || !fs::is_regular_file(with_lua, ec)) throw;
      if (fs::equivalent(with_lua, name + ".lua", ec)) throw;  // the message's "is a file here" says it
      throw Error(std::string(e.what()) + "; " + name + ".lua is beside " + naming_file + ": name it with its \".lua\" (\"" +
                  name + ".lua\")");
    }
    return name;
  }
  // Beside the naming file, then beside `also_beside` (the curriculum that changed a stage a
  // library made), as require looks beside the script.
  std::vector<fs::path> looked;
  fs::path near;
  for (const std::string& shown : {naming_file, also_beside}) {
    if (shown.empty()) continue;
    const fs::path file = as_found(shown);
    if (!fs::is_regular_file(file, ec)) continue;
    const fs::path candidate = (file.parent_path() / written).lexically_normal();
    if (std::find(looked.begin(), looked.end(), candidate) != looked.end()) continue;
    looked.push_back(candidate);
    if (fs::is_regular_file(candidate, ec)) {
      near = candidate;
      break;
    }
  }
  if (near.empty()) {
    try {
      resolve_scenario_path(name);
    } catch (const Error& e) {
      std::string beside;
      // Absolute: beside a file named from its own folder, the path would read as the name itself.
      for (const fs::path& l : looked) beside += fs::absolute(l, ec).lexically_normal().string() + ", then ";
      throw Error("no scenario '" + name + "' (named in " + naming_file + "): looked at " + beside + name +
                  " from the current folder, then in the project; " + e.what());
    }
    return name;
  }
  if (fs::is_regular_file(written, ec) && fs::equivalent(written, near, ec)) return name;  // the same file
  // Recorded so that it is found again from any folder: relative to the project when inside it.
  const fs::path real = fs::weakly_canonical(near, ec), root = fs::weakly_canonical(project_root(), ec);
  const fs::path rel = real.lexically_relative(root);
  const bool in_project = !rel.empty() && *rel.begin() != "..";
  return in_project ? rel.generic_string() : real.string();
}

std::string scenario_beside(const std::string& name, const std::string& naming_file, const std::string& also_beside) {
  if (path_like(name)) return "";
  std::string shipped;
  try {
    shipped = resolve_scenario_path(name);
  } catch (const Error&) {
    return "";
  }
  std::error_code ec;
  for (const std::string& shown : {naming_file, also_beside}) {
    if (shown.empty()) continue;
    const fs::path file = as_found(shown), copy = file.parent_path() / (name + ".lua");
    if (!fs::is_regular_file(copy, ec) || fs::equivalent(copy, shipped, ec) || fs::equivalent(copy, file, ec)) continue;
    // Only a scenario: curricula/lib/sorting.lua beside a stage of scenario "sorting" is a library.
    if (!script_has_key(copy.string(), "generate") || script_has_key(copy.string(), "stages")) continue;
    return (fs::path(shown).parent_path() / (name + ".lua")).string();
  }
  return "";
}

std::string scenario_found_from_here(const std::string& recorded, const std::string& naming_file,
                                     const std::string& kind) {
  std::error_code ec;
  const fs::path written(recorded);
  if (!path_like(recorded) || written.is_absolute() || naming_file.empty() || !fs::is_regular_file(written, ec)) return "";
  if (fs::is_regular_file(project_root() / written, ec)) return "";  // found from any folder
  const fs::path file = as_found(naming_file), here = fs::absolute(written, ec).lexically_normal();
  // Beside the naming file (from its own folder, the two read alike: found by a probe).
  if (fs::is_regular_file(file.parent_path() / written, ec)) return "";
  const fs::path beside = here.lexically_relative(fs::absolute(file, ec).parent_path().lexically_normal());
  return kind + " '" + recorded + "' was found from the current folder, not beside " + naming_file +
         ": from another folder it will not be found (written relative to " + file.filename().string() + ", it is '" +
         beside.generic_string() + "', found from any folder)";
}

namespace {

// Runs `body`; an error goes into `into` (prefixed by `what`) unless the same message came before
// under the same `key`: a mistake that every seed hits is reported once.
void attempt(std::set<std::string>& seen, std::vector<std::string>& into, const std::string& what,
             const std::function<void()>& body, const std::string& key = "") {
  try {
    body();
  } catch (const std::exception& e) {
    if (seen.insert(key + "\n" + e.what()).second) into.push_back(what.empty() ? e.what() : what + ": " + e.what());
  }
}

}  // namespace

std::vector<std::string> check_scenario(const std::string& path, int seeds, const SandboxLimits& limits,
                                        std::vector<std::string>* range_ends) {
  std::vector<std::string> problems;
  std::set<std::string> seen;
  std::optional<Scenario> scenario;
  attempt(seen, problems, "", [&]() { scenario = Scenario::load(path, limits); });
  if (!scenario) return problems;
  return check_scenario(*scenario, seeds, range_ends);
}

std::vector<std::string> check_scenario(Scenario& scenario, int seeds, std::vector<std::string>* range_ends) {
  std::vector<std::string> problems;
  std::set<std::string> seen;
  for (int seed = 0; seed < seeds; ++seed)
    attempt(seen, problems, "seed " + std::to_string(seed), [&]() { scenario.generate(uint64_t(seed)); });
  // One parameter at a time, the others at their defaults: each choice, and (when asked) each end
  // of a numeric range, where placements and bodies fail first.
  for (const auto& p : scenario.params()) {
    // A boolean is a choice of two (found by a probe: the false branch of a switch went untried).
    const std::vector<std::string> choices =
        p.choices.empty() && p.type == ParamType::kBoolean ? std::vector<std::string>{"true", "false"} : p.choices;
    for (const auto& choice : choices) {
      attempt(seen, problems, p.name + "=" + choice + ", seed 0", [&]() {
        scenario.set_param(p.name, choice);
        scenario.generate(0);
      });
    }
    if (range_ends) {
      for (const auto& end : numeric_ends(p)) {
        // A named copy: clang 14 cannot capture a structured binding in the lambda.
        const std::string& bound = end.first;
        // Each end its own warning, though two may fail alike (found by a probe: upper_arm=2 fails
        // with forearm=2's words, and was neither said nor counted).
        attempt(seen, *range_ends, p.name + "=" + bound + " (its " + end.second + "), seed 0", [&]() {
          scenario.set_param(p.name, bound);
          scenario.generate(0);
        }, p.name + "=" + bound);
      }
    }
    scenario.set_param(p.name, p.value);
  }
  return problems;
}

std::string stimulus_unseen(const WorldSpec& w) {
  if (w.objects.empty()) return "";
  std::vector<std::string> colours;
  for (const auto& o : w.objects) {
    if (o.colour == w.stimulus_colour) return "";
    if (std::find(colours.begin(), colours.end(), o.colour.hex()) == colours.end()) colours.push_back(o.colour.hex());
  }
  return "no object has the stimulus colour " + w.stimulus_colour.hex() + " (world:stimulus): the eyes look for what "
         "is not there; the objects' colours: " + join(colours);
}

std::string stimulus_unseen_note(Scenario& scenario, uint64_t first_seed, int worlds) {
  int unseen = 0, built = 0;
  uint64_t first = 0;
  std::string text;
  for (int k = 0; k < worlds; ++k) {
    std::string why;
    try {
      why = stimulus_unseen(scenario.generate(first_seed + uint64_t(k)));
    } catch (const std::exception&) {
      continue;
    }
    ++built;
    if (why.empty()) continue;
    if (unseen++ == 0) first = first_seed + uint64_t(k), text = why;
  }
  if (unseen == 0) return "";
  return "in " + std::to_string(unseen) + " of " + std::to_string(built) + " worlds (the first: seed " +
         std::to_string(first) + ") " + text;
}

std::vector<std::pair<std::string, std::string>> numeric_ends(const ScenarioParam& p) {
  std::vector<std::pair<std::string, std::string>> ends;
  if (!p.choices.empty() || (p.type != ParamType::kNumber && p.type != ParamType::kInteger)) return ends;
  const bool integer = p.type == ParamType::kInteger;
  auto text = [&](double v) { return integer ? std::to_string(int64_t(v)) : format_number(v); };
  if (p.min) ends.push_back({text(integer ? std::ceil(*p.min) : *p.min), "min"});
  if (p.max) ends.push_back({text(integer ? std::floor(*p.max) : *p.max), "max"});
  return ends;
}

}  // namespace roger
