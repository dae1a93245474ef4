// The predicates of the control API: roger.converged, roger.gamma, roger.all, roger.any,
// roger.negate, roger.held and roger.sorted.
#include <algorithm>
#include <cmath>

#include "core/text.h"
#include "script/control/lua_control_internal.h"
#include "sim/world_model.h"

namespace roger {
namespace lua_control_detail {
namespace {

// Makes a predicate (may throw roger::Error) and pushes it.
void push_new_predicate(lua_State* L, PredicatePtr p) {
  count_object(L, book_of(L));
  lua_push_predicate(L, p);
}

}  // namespace

// roger.converged(c)
int l_converged(lua_State* L) {
  return lua_protect(L, [L]() {
    // A second argument reads as a hold time, which converged has not: say where that lives.
    lua_check_arity(L, "roger.converged", 1, "1 argument (a controller)",
                    "to require it to hold for a time, use roger.held(roger.converged(c), seconds)");
    push_new_predicate(L, converged(lua_check_controller(L, 1, "roger.converged", "argument 1")));
    return 1;
  });
}

// roger.sorted() / roger.sorted(colour): the world's judgement of a sorting task, or of one type
int l_sorted(lua_State* L) {
  return lua_protect(L, [L]() {
    const int n = lua_gettop(L);
    if (n > 1) raise(L, "roger.sorted: takes no argument or a colour, got " + std::to_string(n) + " arguments");
    if (n == 0 || lua_isnil(L, 1)) {
      push_new_predicate(L, sorted());
    } else {
      push_new_predicate(L, sorted(lua_to_colour(L, 1, "roger.sorted: argument 1")));
    }
    return 1;
  });
}

// roger.gamma(c, "NOREF" | "!CONV" | "CONV")
int l_gamma(lua_State* L) {
  return lua_protect(L, [L]() {
    lua_check_arity(L, "roger.gamma", 2, "2 arguments (a controller and a state)",
                    "to require it to hold for a time, use roger.held(roger.gamma(c, state), seconds)");
    ControllerPtr c = lua_check_controller(L, 1, "roger.gamma", "argument 1");
    const std::string given = lua_type(L, 2) == LUA_TSTRING ? lua_tostring(L, 2) : "";
    for (Gamma g : {Gamma::kNoRef, Gamma::kNotConv, Gamma::kConv}) {
      if (given == gamma_name(g)) {
        push_new_predicate(L, gamma_is(c, g));
        return 1;
      }
    }
    raise(L, "roger.gamma: argument 2 must be \"NOREF\", \"!CONV\" or \"CONV\", got " + lua_describe_value(L, 2));
  });
}

namespace {

// roger.all{p, ...} / roger.any{p, ...} (or the predicates as separate arguments).
int combine(lua_State* L, bool all) {
  return lua_protect(L, [L, all]() {
    const std::string context = all ? "roger.all" : "roger.any";
    std::vector<PredicatePtr> parts;
    if (lua_gettop(L) == 1 && lua_istable(L, 1)) {
      const lua_Integer n = lua_Integer(lua_rawlen(L, 1));
      lua_pushnil(L);
      while (lua_next(L, 1)) {
        lua_pop(L, 1);
        if (!lua_isinteger(L, -1) || lua_tointeger(L, -1) < 1 || lua_tointeger(L, -1) > n)
          raise(L, context + ": expects a list of predicates {p1, p2, ...}, but it has the key " +
                       lua_describe_value(L, -1));
      }
      for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L, 1, i);
        parts.push_back(lua_check_predicate(L, -1, context, "element " + std::to_string(i)));
        lua_pop(L, 1);
      }
    } else {
      for (int i = 1; i <= lua_gettop(L); ++i)
        parts.push_back(lua_check_predicate(L, i, context, "argument " + std::to_string(i)));
    }
    push_new_predicate(L, all ? all_of(std::move(parts)) : any_of(std::move(parts)));
    return 1;
  });
}
}  // namespace

int l_all(lua_State* L) { return combine(L, true); }
int l_any(lua_State* L) { return combine(L, false); }

// roger.negate(p), also roger["not"](p)
int l_negate(lua_State* L) {
  return lua_protect(L, [L]() {
    lua_check_arity(L, "roger.negate", 1, "1 argument (a predicate)");
    push_new_predicate(L, negate(lua_check_predicate(L, 1, "roger.negate", "argument 1")));
    return 1;
  });
}

// roger.held(p, seconds)
int l_held(lua_State* L) {
  return lua_protect(L, [L]() {
    lua_check_arity(L, "roger.held", 2, "2 arguments (a predicate and a duration in seconds)");
    PredicatePtr p = lua_check_predicate(L, 1, "roger.held", "argument 1");
    const double seconds = lua_tonumber(L, 2);
    if (lua_type(L, 2) != LUA_TNUMBER || !std::isfinite(seconds) || seconds < 0.0)
      raise(L, "roger.held: argument 2 must be a duration in seconds (a finite number >= 0), got " +
                   lua_describe_value(L, 2));
    push_new_predicate(L, held(p, seconds));
    return 1;
  });
}

}  // namespace lua_control_detail

namespace {

// The controllers `p` reads that can never converge, said for a message ("" when there are none):
// a converged() of one never holds, its negation always.
std::string never_converging(const Predicate& p) {
  std::vector<const Controller*> read;
  p.controllers(read);
  std::vector<std::string> names;
  for (const Controller* c : read)
    if (!c->can_converge() && std::find(names.begin(), names.end(), c->name()) == names.end())
      names.push_back(c->name());
  if (names.empty()) return "";
  return "; " + join(names, ", ") + (names.size() == 1 ? " never converges" : " never converge") +
         " (a roger.policy without done is never CONV, nor is a sequence whose last step, a subject-to whose " +
         "superior or a binding whose skill is one: give the policy a done, or judge another controller)";
}

}  // namespace

std::string never_holds_within(const Predicate& goal, double time_limit) {
  const WorldParams params;  // every world's control tick
  const double tick = params.dt * params.substeps;
  if (can_hold_within(goal, time_limit, tick)) return "";
  const double earliest = goal.earliest_seconds();
  const std::string what = shortened_text(goal.describe(), 120);
  if (!std::isfinite(earliest))
    return what + " can never hold: it rests on a roger.any() of no parts, which is false, on the roger.negate of "
           "a predicate that always holds, or on converged() of a controller that never converges" +
           never_converging(goal);
  return what + " can hold only after " + format_number(tick + earliest) + " simulated seconds (the goal is first " +
         "judged after the first tick, at " + format_number(tick) + " s), past the time_limit of " +
         format_number(time_limit) + " s: no episode could reach it (roger.held counts seconds, not ticks)";
}

std::string holds_at_once(const Predicate& goal) {
  if (goal.always_holds())
    return shortened_text(goal.describe(), 120) + " always holds: it rests on a roger.all() of no parts, which is true, "
           "or on the roger.negate of a predicate that never holds, so every episode would end in success at its first tick" +
           never_converging(goal);
  const double from = goal.certain_from();
  if (!std::isfinite(from)) return "";
  return shortened_text(goal.describe(), 120) + " holds after " + format_number(from) +
         " simulated seconds whatever happens: it rests on a roger.held of a predicate that always holds (a roger.all() "
         "of no parts, or the roger.negate of one that never holds), so every episode would end in success then";
}

}  // namespace roger
