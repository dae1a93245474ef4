// The skills of the control API: roger.sequence(name, {step, ...}) and roger.policy(name, {...}),
// a state-to-action table over its actions' states.
#include <algorithm>
#include <cctype>
#include <cmath>

#include "script/control/lua_control_internal.h"

namespace roger {
namespace lua_control_detail {
namespace {

constexpr size_t kMaxTableEntries = 4'000'000;    // policy table entries over the whole script
constexpr int kMaxPolicyActions = 12;             // 3^12 states, as Policy allows

// A predicate used as a policy's `done`: a controller with no command whose gamma is CONV while
// the predicate holds, !CONV otherwise.
class PredicateGoal final : public Controller {
 public:
  explicit PredicateGoal(PredicatePtr p) : p_(std::move(p)) { set_name(p_->describe()); }
  std::vector<const Controller*> children() const override {
    std::vector<const Controller*> out;
    p_->controllers(out);
    return out;
  }
  const char* kind() const override { return "predicate"; }
  bool can_converge() const override { return std::isfinite(p_->earliest_seconds()); }
  ControllerPtr copy() const override { return std::make_shared<PredicateGoal>(*this); }
  void relink(Duplicates& done) override { p_ = duplicate(p_, done); }
  void reset(uint64_t seed) override {
    Controller::reset(seed);
    p_->reset();
  }

 protected:
  void compute(const ControlInput& in, ControlOutput&, Gamma& gamma_raw) override {
    gamma_raw = p_->holds(in) ? Gamma::kConv : Gamma::kNotConv;
  }
  // It has no command: the state is all there is to compute.
  bool compute_state(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) override {
    compute(in, out, gamma_raw);
    return true;
  }

 private:
  PredicatePtr p_;
};

// A skill's name argument: a string, checked when it is registered.
std::string skill_name(lua_State* L, const char* function) {
  if (lua_type(L, 1) != LUA_TSTRING)
    raise(L, std::string(function) + ": argument 1 must be the skill's name (a string), got " +
                 lua_describe_value(L, 1));
  return lua_tostring(L, 1);
}

// Reads a list of controllers (steps or actions) at `index`.
std::vector<ControllerPtr> controller_list(lua_State* L, int index, const std::string& context,
                                           const char* field, const char* item) {
  index = lua_absindex(L, index);
  if (!lua_istable(L, index))
    raise(L, context + ": " + field + " must be a list of controllers (or their names), got " +
                 lua_describe_value(L, index));
  const lua_Integer n = lua_Integer(lua_rawlen(L, index));
  lua_pushnil(L);
  while (lua_next(L, index)) {
    lua_pop(L, 1);
    if (!lua_isinteger(L, -1) || lua_tointeger(L, -1) < 1 || lua_tointeger(L, -1) > n)
      raise(L, context + ": " + field + " must be a list {c1, c2, ...}, but it has the key " +
                   lua_describe_value(L, -1));
  }
  if (n == 0) raise(L, context + ": " + field + " must hold at least one " + item + ", got an empty list");
  std::vector<ControllerPtr> out;
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, index, i);
    out.push_back(lua_check_controller(L, -1, context, std::string(item) + " " + std::to_string(i)));
    lua_pop(L, 1);
  }
  return out;
}

}  // namespace

// roger.sequence(name, {step, step, ...} [, {fall_back = false}])
int l_sequence(lua_State* L) {
  return lua_protect(L, [L]() {
    ControlBook& book = book_of(L);
    const std::string name = skill_name(L, "roger.sequence");
    const std::string context = "roger.sequence('" + name + "')";
    if (lua_gettop(L) > 3)
      raise(L, context + ": expects (name, {step, ...} [, {fall_back = false}]), got " +
                   std::to_string(lua_gettop(L)) + " arguments");
    auto steps = controller_list(L, 2, context, "the steps", "step");
    bool fall_back = true;
    if (lua_gettop(L) == 3 && !lua_isnil(L, 3)) fall_back = LuaFields(L, 3, context, {"fall_back"}).boolean("fall_back", true);
    count_object(L, book);
    auto seq = made(book, std::make_shared<Sequence>(std::move(steps), fall_back));
    register_name(L, book, context, name, seq);
    lua_push_controller(L, seq);
    return 1;
  });
}

namespace {

// The index (0-based) of the action a policy table value means: a controller among the actions,
// an action's name, or a 1-based index.
int action_index(lua_State* L, ControlBook& book, int index, const std::vector<ControllerPtr>& actions,
                 const std::string& where) {
  std::vector<std::string> names;
  for (const auto& a : actions) names.push_back(a->name());
  const std::string listing = "; the actions are " + join(names) + " (or their indices 1 to " +
                              std::to_string(actions.size()) + ")";
  if (lua_type(L, index) == LUA_TNUMBER) {
    if (!lua_isinteger(L, index) || lua_tointeger(L, index) < 1 || lua_tointeger(L, index) > lua_Integer(actions.size()))
      raise(L, where + " must be an action or its index 1 to " + std::to_string(actions.size()) + ", got " +
                   lua_describe_value(L, index));
    return int(lua_tointeger(L, index)) - 1;
  }
  ControllerPtr c;
  if (ControllerPtr* box = test_controller(L, index)) {
    c = *box;
  } else if (lua_type(L, index) == LUA_TSTRING) {
    const std::string name = lua_tostring(L, index);
    int found = -1;
    for (size_t i = 0; i < actions.size(); ++i) {
      if (actions[i]->name() != name) continue;
      if (found >= 0) raise(L, where + ": the name '" + name + "' is ambiguous: actions " + std::to_string(found + 1) +
                                   " and " + std::to_string(i + 1) + " both have it; use the index or the controller");
      found = int(i);
    }
    if (found >= 0) return found;
    c = resolve_now(L, book, name);
    if (!c) raise(L, where + " names '" + name + "', which is not an action" + listing);
  } else {
    raise(L, where + " must be an action (a controller, its name or its index), got " + lua_describe_value(L, index) + listing);
  }
  for (size_t i = 0; i < actions.size(); ++i)
    if (actions[i] == c) return int(i);
  raise(L, where + " is '" + c->name() + "', which is not one of the policy's actions" + listing);
}

// Parses a state key "CONV !CONV NOREF" (or with "*" wildcards) into one gamma per action; -1
// marks a wildcard.
std::vector<int> parse_state_key(lua_State* L, const std::string& key, size_t n, const std::string& where,
                                 const std::vector<ControllerPtr>& actions) {
  std::vector<int> out;
  std::string token;
  auto flush = [&]() {
    if (token.empty()) return;
    std::string upper = token;
    std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char ch) { return char(std::toupper(ch)); });
    if (upper == "*") out.push_back(-1);
    else if (upper == "NOREF") out.push_back(int(Gamma::kNoRef));
    else if (upper == "!CONV") out.push_back(int(Gamma::kNotConv));
    else if (upper == "CONV") out.push_back(int(Gamma::kConv));
    else raise(L, where + ": '" + token + "' is not a state; write NOREF, !CONV, CONV or * for each action");
    token.clear();
  };
  for (char ch : key) {
    if (std::isspace(static_cast<unsigned char>(ch)) || ch == ',') flush();
    else token += ch;
  }
  flush();
  if (out.size() != n) {
    std::vector<std::string> names;
    for (const auto& a : actions) names.push_back(a->name());
    raise(L, where + ": the key has " + std::to_string(out.size()) + " states but the policy has " +
                 std::to_string(n) + " actions (" + join(names) + "); write NOREF, !CONV, CONV or * for each, in that order");
  }
  return out;
}

// The policy's actions (its 'actions' field) within the cap on actions; charges the states of its
// table (3^actions) against the script's budget of table entries and returns their number.
std::vector<ControllerPtr> policy_actions(lua_State* L, ControlBook& book, const LuaFields& f,
                                          const std::string& context, size_t& states) {
  if (!f.has("actions")) f.fail("missing required field 'actions' (a list of controllers)");
  f.push("actions");
  std::vector<ControllerPtr> actions = controller_list(L, -1, context, "'actions'", "action");
  lua_pop(L, 1);
  // As a context's Psi (found by a probe: {"phi0", "phi0"} was taken, its states' two columns one).
  for (size_t i = 0; i < actions.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (actions[i]->name() == actions[j]->name())
        f.fail("'actions': two actions are named '" + actions[i]->name() + "' (actions " + std::to_string(j + 1) +
               " and " + std::to_string(i + 1) + "); a policy's actions must differ, as its states name them");
  if (int(actions.size()) > kMaxPolicyActions)
    f.fail("at most " + std::to_string(kMaxPolicyActions) + " actions (3^" + std::to_string(kMaxPolicyActions) +
           " states), got " + std::to_string(actions.size()));
  const size_t n = actions.size();
  states = 1;
  for (size_t i = 0; i < n; ++i) states *= 3;
  if (book.table_entries + states > kMaxTableEntries)
    f.fail("the script's policy tables exceed " + std::to_string(kMaxTableEntries) + " entries in all");
  book.table_entries += states;
  return actions;
}

// A policy table being filled: per state, its action (-1: none), the specificity of the key that
// set it (-1: none) and that key.
struct PolicyTable {
  std::vector<int> table, specificity;
  std::vector<std::string> source;
};

// Sets every state one key (parsed into `pattern`) matches to its action, where no more specific
// key has set it; two equally specific keys giving one state different actions are an error.
void fill_key(lua_State* L, const LuaFields& f, const std::string& key, const std::vector<int>& pattern,
              int action, size_t n, PolicyTable& t) {
  std::vector<int>& table = t.table;
  std::vector<int>& specificity = t.specificity;
  std::vector<std::string>& source = t.source;
  int wild = 0;
  for (int g : pattern) wild += g < 0;
  const int spec = int(n) - wild;
  // Every state the key matches: count through the wildcard positions in base 3.
  std::vector<size_t> wild_at;
  for (size_t i = 0; i < n; ++i)
    if (pattern[i] < 0) wild_at.push_back(i);
  size_t combinations = 1;
  for (size_t i = 0; i < wild_at.size(); ++i) combinations *= 3;
  lua_charge(L, combinations);
  std::vector<int> gammas(pattern);
  for (size_t k = 0; k < combinations; ++k) {
    size_t digits = k;
    for (size_t w = wild_at.size(); w-- > 0;) {
      gammas[wild_at[w]] = int(digits % 3);
      digits /= 3;
    }
    int index = 0;
    for (int g : gammas) index = index * 3 + g;
    const size_t at = size_t(index);
    if (specificity[at] == spec && table[at] != action) {
      std::string state;
      for (size_t i = 0; i < n; ++i) state += (i ? " " : "") + std::string(gamma_name(Gamma(gammas[i])));
      f.fail("the keys \"" + source[at] + "\" and \"" + key + "\" both match the state " + state +
             " with different actions; make one of them more specific");
    }
    if (spec > specificity[at]) {
      specificity[at] = spec;
      table[at] = action;
      source[at] = key;
    }
  }
}

// Reads the policy's 'table' field {[state] = action, ...} into one action per state (-1: none).
// Keys are read in sorted order so that the first error reported does not depend on Lua's order.
std::vector<int> policy_table(lua_State* L, ControlBook& book, const LuaFields& f, const std::string& context,
                              const std::vector<ControllerPtr>& actions, size_t states) {
  const size_t n = actions.size();
  PolicyTable pt{std::vector<int>(states, -1), std::vector<int>(states, -1), std::vector<std::string>(states)};
  if (f.push("table") == LUA_TNIL) f.fail("missing required field 'table' ({[\"CONV !CONV\"] = action, ...})");
  if (!lua_istable(L, -1)) f.wrong_type("table", "a table {[\"CONV !CONV ...\"] = action, ...}");
  const int t = lua_gettop(L);
  std::vector<std::string> keys;
  lua_pushnil(L);
  while (lua_next(L, t)) {
    lua_pop(L, 1);
    if (lua_type(L, -1) != LUA_TSTRING)
      f.fail("the table's keys must be states such as \"CONV !CONV NOREF\", got " + lua_describe_value(L, -1));
    keys.push_back(lua_tostring(L, -1));
  }
  std::sort(keys.begin(), keys.end());
  for (const auto& key : keys) {
    const std::string where = context + ": table[\"" + key + "\"]";
    const std::vector<int> pattern = parse_state_key(L, key, n, where, actions);
    lua_pushstring(L, key.c_str());
    lua_rawget(L, t);
    const int action = action_index(L, book, -1, actions, where);
    lua_pop(L, 1);
    fill_key(L, f, key, pattern, action, n, pt);
  }
  lua_settop(L, t - 1);
  return std::move(pt.table);
}

// The policy's 'done' field: a controller, or a predicate made into one; null when absent.
ControllerPtr policy_done(lua_State* L, ControlBook& book, const LuaFields& f, const std::string& context) {
  ControllerPtr done;
  if (f.push("done") != LUA_TNIL) {
    if (PredicatePtr* p = test_predicate(L, -1)) {
      count_object(L, book);
      done = made(book, std::make_shared<PredicateGoal>(*p));
    } else if (lua_type(L, -1) == LUA_TSTRING || test_controller(L, -1)) {
      done = lua_check_controller(L, -1, context, "field 'done'");
    } else {
      // Neither: said as a predicate's slip, which gives the hint for roger.converged without its
      // call (found by a probe: "field 'done' (a controller or a predicate) must be a controller").
      lua_check_predicate(L, -1, context, "field 'done' (a predicate, or a controller whose CONV it takes)");
    }
  }
  lua_pop(L, 1);
  return done;
}

}  // namespace

// roger.policy(name, {actions = {...}, table = {[state] = action, ...}, done = c_or_p, fallback = a,
//                     rest_when_done = false})
int l_policy(lua_State* L) {
  return lua_protect(L, [L]() {
    ControlBook& book = book_of(L);
    const std::string name = skill_name(L, "roger.policy");
    const std::string context = "roger.policy('" + name + "')";
    lua_check_arity(L, "roger.policy", 2, "2 arguments (a name and a table of fields)");
    LuaFields f(L, 2, context, {"actions", "table", "done", "fallback", "rest_when_done"});
    size_t states = 0;
    std::vector<ControllerPtr> actions = policy_actions(L, book, f, context, states);
    std::vector<int> table = policy_table(L, book, f, context, actions, states);

    int fallback = -1;
    if (f.push("fallback") == LUA_TSTRING && std::string(lua_tostring(L, -1)) == "rotate") fallback = Policy::kRotate;
    else if (!lua_isnil(L, -1)) fallback = action_index(L, book, -1, actions, context + ": fallback (an action, or \"rotate\")");
    lua_pop(L, 1);
    ControllerPtr done = policy_done(L, book, f, context);
    const bool rest = f.boolean("rest_when_done", false);
    if (rest && !done) f.fail("field 'rest_when_done' needs 'done': the goal at which the policy rests");
    count_object(L, book);
    auto policy = made(book, std::make_shared<Policy>(std::move(actions), std::move(table), std::move(done), fallback));
    policy->set_rest_when_done(rest);
    register_name(L, book, context, name, policy);
    lua_push_controller(L, policy);
    return 1;
  });
}

// roger.bind(name, controller, {stimulus = colour, region = k, ignore_delivered = true, patience = s})
int l_bind(lua_State* L) {
  return lua_protect(L, [L]() {
    ControlBook& book = book_of(L);
    const std::string name = skill_name(L, "roger.bind");
    const std::string context = "roger.bind('" + name + "')";
    if (lua_gettop(L) != 3)
      raise(L, context + ": expects (name, controller, {stimulus = colour, region = k}), got " +
                   std::to_string(lua_gettop(L)) + " arguments");
    ControllerPtr target = lua_check_controller(L, 2, context, "argument 2 (the controller to bind)");
    LuaFields f(L, 3, context, {"stimulus", "region", "ignore_delivered", "patience", "sticky_noref", "retry_after"});
    if (!f.has("stimulus") && !f.has("region")) f.fail("binds nothing: give 'stimulus', 'region' or both");
    const int64_t region = f.integer("region", -1);
    if (f.has("region") && (region < 0 || region > 63))
      f.fail("field 'region' must be a goal region's index 0 to 63 (as phi1's 'region'), got " + std::to_string(region));
    Binding::Bindings b;
    b.stimulus = f.has("stimulus");
    b.colour = f.colour("stimulus", Colour{});
    b.region = int(region);
    if (f.boolean("ignore_delivered", f.has("region"))) {
      if (!f.has("region")) f.fail("field 'ignore_delivered' needs 'region': the region whose delivered objects to ignore");
      b.ignore_region = int(region);
    }
    b.patience = f.number("patience", 0.0);
    b.sticky_noref = f.boolean("sticky_noref", false);
    b.retry_after = f.number("retry_after", 0.0);
    if (!(b.retry_after >= 0.0 && b.retry_after <= 1e6))
      f.fail("field 'retry_after' must be seconds from 0 (never forget a NOREF) to 1e6, got " + format_number(b.retry_after));
    if (!(b.patience >= 0.0 && b.patience <= 1e6))
      f.fail("field 'patience' must be seconds from 0 (no limit) to 1e6, got " + format_number(b.patience));
    count_object(L, book);
    auto binding = made(book, std::make_shared<Binding>(target, b));
    binding->set_name(name);
    register_name(L, book, context, name, binding);
    lua_push_controller(L, binding);
    return 1;
  });
}

}  // namespace lua_control_detail
}  // namespace roger
