// scenario_body.cpp: Roger's body and eyes as fields of world:robot (body = {...}, eyes = {...}),
// and roger.body_metrics, which tells a generator what follows from a body before it places Roger.
#include <cmath>
#include <string>
#include <vector>

#include "core/body.h"
#include "script/sandbox/lua_sandbox.h"
#include "script/scenario/scenario_internal.h"

namespace roger {
namespace scenario_detail {

double ranged(const LuaFields& f, const char* key, double fallback, double lo, double hi, const char* unit,
              bool low_open) {
  const double v = f.number(key, fallback);
  if (!(v >= lo && v <= hi) || (low_open && v == lo))
    f.fail(std::string("field '") + key + "' must be within " + (low_open ? "(" : "[") + fmt(lo) + ", " +
           fmt(hi) + "]" + (*unit ? " " : "") + unit + ", got " +
           format_number(v));  // a number without unit: "[0, 10], got"; a tiny value as written, not as 0
  return v;
}

namespace {

// Reads the optional sub-table `key` of f with `read(index)`: nil reads nothing; anything but a
// table is refused, saying it must be `expected`.
template <class Read>
void read_subtable(const LuaFields& f, const char* key, const char* expected, Read read) {
  lua_State* L = f.state();
  if (f.push(key) == LUA_TNIL) return lua_pop(L, 1);
  const int t = lua_gettop(L);
  if (!lua_istable(L, t)) f.wrong_type(key, expected);
  read(t);
  lua_pop(L, 1);
}

// The same for a sub-table of named fields, read by name under "context<separator>key": a field
// it does not know is refused with the known names (LuaFields).
template <class Read>
void read_fields(const LuaFields& f, const char* key, const char* separator, const char* expected,
                 std::vector<std::string> known, Read read) {
  read_subtable(f, key, expected, [&](int t) {
    read(LuaFields(f.state(), t, f.context() + separator + key, std::move(known)));
  });
}

// A {min, max} field of joint limits within [-lim, lim].
void joint_range(const LuaFields& f, const char* key, double& lo, double& hi, double lim) {
  read_fields(f, key, ": ", "a table {min = ..., max = ...}", {"min", "max"}, [&](const LuaFields& r) {
    lo = ranged(r, "min", lo, -lim, lim, "rad");
    hi = ranged(r, "max", hi, -lim, lim, "rad");
    if (!(lo < hi)) r.fail("min must be below max, got " + fmt(lo) + " and " + fmt(hi));
  });
}

// The fields a servo reads: the base's force and torque servos all four; the arms' Box2D motors
// (implicit velocity servos) no rate gain kv; the eyes, kinematic rate servos, no force either.
enum class ServoKind { kBase, kArm, kEye };

// One servo's gains and limits: servos.<key> = {kp, max_rate, kv, max_effort}, of them what it
// reads (found by a probe: an arm's or an eye's kv was accepted and did nothing).
void servo(const LuaFields& f, const char* key, ServoParams& s, ServoKind kind) {
  const bool reads_kv = kind == ServoKind::kBase, reads_effort = kind != ServoKind::kEye;
  const char* why_not = kind == ServoKind::kArm ? "an arm's joint is a Box2D motor, which takes kp, max_rate and "
                                                  "max_effort, but no rate gain kv"
                                                : "the eyes are kinematic rate servos, which take kp and max_rate";
  read_fields(f, key, ".", "a table {kp = ..., max_rate = ..., kv = ..., max_effort = ...}",
              {"kp", "max_rate", "kv", "max_effort"}, [&](const LuaFields& v) {
                for (const auto& [name, read] : {std::pair{"kv", reads_kv}, std::pair{"max_effort", reads_effort}})
                  if (!read && v.has(name)) v.fail(std::string("field '") + name + "' would do nothing: " + why_not);
                s.kp = ranged(v, "kp", s.kp, 0.01, 1000.0, "1/s");
                s.max_rate = ranged(v, "max_rate", s.max_rate, 0.01, 100.0, "m/s or rad/s");
                if (reads_kv) s.kv = ranged(v, "kv", s.kv, 0.0, 1000.0, "N/(m/s) or N m/(rad/s)");
                if (reads_effort) s.max_effort = ranged(v, "max_effort", s.max_effort, 0.0, 1000.0, "N or N m");
              });
}

// body.servos = {base_forward = ..., base_heading = ..., eye = ..., shoulder = ..., elbow = ...}.
void servos(const LuaFields& f, RobotParams& b) {
  read_fields(f, "servos", ": ", "a table of servos {shoulder = {kp = ...}, ...}",
                {"base_forward", "base_heading", "eye", "shoulder", "elbow"}, [&](const LuaFields& s) {
                  servo(s, "base_forward", b.base_forward, ServoKind::kBase);
                  servo(s, "base_heading", b.base_heading, ServoKind::kBase);
                  servo(s, "eye", b.eye, ServoKind::kEye);
                  servo(s, "shoulder", b.shoulder, ServoKind::kArm);
                  servo(s, "elbow", b.elbow, ServoKind::kArm);
                });
}

// body.locked = {"left_elbow", ...}: joints held at their start angle.
unsigned locked_joints(const LuaFields& f) {
  std::vector<std::string> names;
  for (const auto& [name, dof] : lockable_joints()) names.push_back(name);
  unsigned mask = 0;
  read_subtable(f, "locked", "a list of joint names {\"left_elbow\", ...}", [&](int t) {
    lua_State* L = f.state();
    // Found by a probe: {"left_eye", right = "right_eye"} locked the left eye alone, unsaid.
    if (const std::string key = lua_key_beside_list(L, t); !key.empty())
      f.fail("field 'locked' must be a list of joint names {\"left_elbow\", ...}, got the key " + key);
    const lua_Integer n = lua_Integer(lua_rawlen(L, t));
    for (lua_Integer i = 1; i <= n; ++i) {
      lua_rawgeti(L, t, i);
      const std::string name = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : "";
      lua_pop(L, 1);
      int dof = -1;
      for (const auto& [known, d] : lockable_joints())
        if (known == name) dof = d;
      if (dof < 0)
        f.fail("field 'locked' entry " + std::to_string(i) + " must be a joint name, one of " + join(names) +
               (name.empty() ? std::string() : ", got '" + name + "'"));
      // A name twice is most likely another joint mistyped as it (found by a probe).
      if (mask & (1u << unsigned(dof)))
        f.fail("field 'locked' entry " + std::to_string(i) + " names '" + name + "' a second time (another joint "
               "meant? the joints: " + join(names) + ")");
      mask |= 1u << unsigned(dof);
    }
  });
  return mask;
}

}  // namespace

RobotParams read_body(const LuaFields& parent) {
  RobotParams b;
  read_fields(parent, "body", ": ", "a table of body fields {upper_arm = ..., ...}",
                {"upper_arm", "forearm", "base_radius", "axle_half_width", "base_mass", "link_mass",
                 "hand_radius", "hand_mass", "shoulder_y", "eye_y", "shoulder", "elbow", "eye_pan",
                 "friction", "servos", "locked"},
                [&](const LuaFields& f) {
                  b.link_length[0] = ranged(f, "upper_arm", b.link_length[0], 0.1, 2.0, "m");
                  b.link_length[1] = ranged(f, "forearm", b.link_length[1], 0.1, 2.0, "m");
                  b.base_radius = ranged(f, "base_radius", b.base_radius, 0.05, 1.0, "m");
                  b.axle_half_width = ranged(f, "axle_half_width", b.axle_half_width, 0.02, 1.0, "m");
                  b.base_mass = ranged(f, "base_mass", b.base_mass, 0.01, 100.0, "kg");
                  b.link_mass = ranged(f, "link_mass", b.link_mass, 0.001, 100.0, "kg");
                  b.hand_radius = ranged(f, "hand_radius", b.hand_radius, 0.01, 0.3, "m");
                  b.hand_mass = ranged(f, "hand_mass", b.hand_mass, 0.001, 100.0, "kg");
                  b.shoulder_y = ranged(f, "shoulder_y", b.shoulder_y, 0.0, 1.0, "m");
                  b.eye_y = ranged(f, "eye_y", b.eye_y, 0.005, 1.0, "m");
                  joint_range(f, "shoulder", b.shoulder_min, b.shoulder_max, M_PI);
                  joint_range(f, "elbow", b.elbow_min, b.elbow_max, M_PI);
                  b.eye_pan_limit = ranged(f, "eye_pan", b.eye_pan_limit, 0.05, M_PI / 2, "rad");
                  b.surface_friction = ranged(f, "friction", b.surface_friction, 0.0, 10.0, "");
                  servos(f, b);
                  b.locked = locked_joints(f);
                });
  return b;
}

EyeParams read_eyes(const LuaFields& parent) {
  EyeParams e;
  read_fields(parent, "eyes", ": ", "a table {pixels = ..., fov = ...}", {"pixels", "fov"}, [&](const LuaFields& f) {
    const int64_t pixels = f.integer("pixels", e.pixels);
    if (pixels < kMinPixels || pixels > kMaxPixels)
      f.fail("field 'pixels' must be within [" + std::to_string(kMinPixels) + ", " + std::to_string(kMaxPixels) +
             "], got " + std::to_string(pixels));
    e.pixels = int(pixels);
    e.fov = ranged(f, "fov", e.fov, kMinFov, kMaxFov, "rad (the full field of view)");
  });
  return e;
}

namespace {

// The ranges of one channel's noise: its magnitudes (sigma, bias, drift) and resolution, in its
// unit.
struct ChannelRange {
  const char* key;
  double max;             // sigma, bias and drift
  const char* unit;
  double quantum_max;     // the resolution
  const char* quantum_unit;
};

constexpr int kMaxNoiseDelay = 50;  // ticks (1 s)
constexpr double kMaxDriftTau = 3600.0;  // s

// noise.<channel> = sigma, or { sigma, bias, drift = { sigma, tau }, delay, dropout, quantum }.
ChannelNoise read_channel(const LuaFields& f, const ChannelRange& r) {
  ChannelNoise c;
  lua_State* L = f.state();
  const int type = f.push(r.key);
  lua_pop(L, 1);
  if (type == LUA_TNIL) return c;
  if (type == LUA_TNUMBER) {
    c.sigma = ranged(f, r.key, 0.0, 0.0, r.max, r.unit);
    return c;
  }
  read_fields(f, r.key, ".", "a number (sigma) or a table {sigma = ..., bias = ..., drift = {sigma = ..., tau = ...}, "
              "delay = ..., dropout = ..., quantum = ...}",
              {"sigma", "bias", "drift", "delay", "dropout", "quantum"}, [&](const LuaFields& k) {
                c.sigma = ranged(k, "sigma", 0.0, 0.0, r.max, r.unit);
                c.bias = ranged(k, "bias", 0.0, 0.0, r.max, r.unit);
                read_fields(k, "drift", ".", "a table {sigma = ..., tau = ...}", {"sigma", "tau"}, [&](const LuaFields& d) {
                  c.drift = ranged(d, "sigma", 0.0, 0.0, r.max, r.unit);
                  // tau = 0 is a drift that never correlates: refused while there is a drift, so
                  // the range says (0, ...] then; without one (sigma 0) tau is not used.
                  c.drift_tau = ranged(d, "tau", 0.0, 0.0, kMaxDriftTau, "s", c.drift > 0.0 && d.has("tau"));
                  if (c.drift > 0.0 && !d.has("tau"))
                    d.fail("field 'tau' is missing: a drift with a sigma needs its correlation time, in s "
                           "(the noise_<channel>_tau parameters default to 10)");
                  // Found by a probe: { tau = 10 } alone passed as no drift, where { sigma } alone
                  // was refused: a drift written is asked for, so its sigma is said.
                  if (!d.has("sigma"))
                    d.fail("field 'sigma' is missing: a drift is its stationary sigma, in " + std::string(r.unit) +
                           ", and its correlation time tau (sigma = 0 for none)");
                });
                const int64_t delay = k.integer("delay", 0);
                if (delay < 0 || delay > kMaxNoiseDelay)
                  k.fail("field 'delay' must be within [0, " + std::to_string(kMaxNoiseDelay) + "] ticks, got " +
                         std::to_string(delay));
                c.delay = int(delay);
                c.dropout = ranged(k, "dropout", 0.0, 0.0, 1.0, "(a probability per tick)");
                c.quantum = ranged(k, "quantum", 0.0, 0.0, r.quantum_max, r.quantum_unit);
              });
  return c;
}

}  // namespace

NoiseParams read_noise(const LuaFields& parent) {
  NoiseParams n;
  static const ChannelRange image{"image", 255.0, "colour levels", 255.0, "colour levels"},
      joints{"joints", 1.0, "rad", 1.0, "rad"}, base{"base", 1.0, "m and rad", 1.0, "m and rad"},
      touch{"touch", 5.0, "(a fraction of the force)", 1000.0, "N"},
      effort{"effort", 5.0, "(a fraction of the command)", 1.0, "m or rad (of the commanded error)"};
  read_fields(parent, "noise", ": ", "a table {image = ..., joints = ..., base = ..., touch = ..., effort = ...}",
              {"image", "joints", "base", "touch", "effort"}, [&](const LuaFields& f) {
                n.image = read_channel(f, image);
                n.joints = read_channel(f, joints);
                n.base = read_channel(f, base);
                n.touch = read_channel(f, touch);
                n.effort = read_channel(f, effort);
              });
  // Found by a probe: a quantum of 0.1 or 1 level turned the noisy image's processing on and changed
  // every trajectory, though it rounds no colour.
  n.image.quantum = image_quantum_levels(n.image.quantum);
  return n;
}

double image_quantum_levels(double quantum) {
  const double levels = std::round(quantum);
  return levels > 1.0 ? levels : 0.0;
}

void check_body(const LuaFields& f, const RobotParams& body, const EyeParams& eyes) {
  const auto problems = body_problems(body, eyes);
  if (!problems.empty()) f.fail("Roger's body cannot be built: " + join(problems, "; "));
}

// roger.body_metrics{ body = {...}, eyes = {...} } -> the numbers that follow from that body.
int l_body_metrics(lua_State* L) {
  return lua_protect(L, [L]() {
    lua_check_arity(L, "roger.body_metrics", 1, "at most 1 argument (a table of fields)");
    if (lua_isnoneornil(L, 1)) {
      lua_settop(L, 0);
      lua_newtable(L);
    }
    LuaFields f(L, 1, "roger.body_metrics", {"body", "eyes"});
    const RobotParams body = read_body(f);
    const EyeParams eyes = read_eyes(f);
    check_body(f, body, eyes);
    const BodyMetrics m = body_metrics(body, eyes);
    lua_newtable(L);
    const std::pair<const char*, double> numbers[] = {
        {"footprint_radius", m.footprint_radius}, {"approach", m.approach},
        {"preshape_reach", m.preshape_reach},     {"grasp_reach", m.grasp_reach},
        {"grid_inflate", m.grid_inflate},         {"objects_growth", m.objects_growth},
        {"squeeze", m.squeeze},                   {"release_distance", m.release_distance},
        {"half_view", m.half_view},               {"sidestep", m.sidestep},
        {"carry", m.carry},                       {"fold_shoulder", m.fold_shoulder},
        {"fold_elbow", m.fold_elbow}};
    for (const auto& [key, value] : numbers) {
      lua_pushnumber(L, value);
      lua_setfield(L, -2, key);
    }
    luaL_setmetatable(L, kBodyMetricsType);  // a misspelt number is an error, not nil
    return 1;
  });
}

}  // namespace scenario_detail
}  // namespace roger
