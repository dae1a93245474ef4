// Tests of scenario scripts: the shipped scenarios keep their constraints over many seeds, worlds
// are a pure function of (scenario, parameters, seed), and mistakes in a script are reported at
// the script's file:line. Run from the repository root (CTest does).
#include <catch2/catch.hpp>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <regex>
#include <string>
#include <vector>

#include "script/sandbox/lua_sandbox.h"
#include "core/rng.h"
#include "core/robot.h"
#include "script/scenario/scenario.h"
#include "senses/senses.h"
#include "core/shape.h"
#include "sim/world.h"
#include "scenario_text.h"

using namespace roger;
using Catch::Matchers::Contains;
using Catch::Matchers::EndsWith;
using Catch::Matchers::StartsWith;

namespace {

// Every field of a world, bit-exact (hex floats), for equality checks.
std::string dump(const WorldSpec& w) {
  std::ostringstream os;
  char buf[64];
  auto num = [&](double v) {
    std::snprintf(buf, sizeof buf, "%a ", v);
    os << buf;
  };
  auto colour = [&](const Colour& c) { os << int(c.r) << ',' << int(c.g) << ',' << int(c.b) << ' '; };
  auto shape = [&](const Shape& s) {
    os << s.name << " [";
    for (const auto& p : s.polygons)
      for (const auto& v : p.vertices) num(v.x()), num(v.y());
    for (const auto& d : s.disks) num(d.center.x()), num(d.center.y()), num(d.radius);
    os << "] ";
  };
  auto pose = [&](const Pose& p) { num(p.x), num(p.y), num(p.theta); };
  os << w.scenario << ' ' << w.seed << '\n';
  for (const auto& [k, v] : w.params) os << k << '=' << v << ' ';
  os << "\narena ";
  num(w.arena.xmin), num(w.arena.xmax), num(w.arena.ymin), num(w.arena.ymax), num(w.arena.cell);
  colour(w.arena.wall_colour);
  os << "\nrobot ";
  pose(w.robot.pose);
  for (double q : {w.robot.left_shoulder, w.robot.left_elbow, w.robot.right_shoulder,
                   w.robot.right_elbow, w.robot.left_eye, w.robot.right_eye})
    num(q);
  for (const auto& o : w.objects) {
    os << "\nobject " << o.name << ' ';
    shape(o.shape), colour(o.colour), pose(o.pose);
    for (double v : {o.mass, o.friction_force, o.friction_torque, o.viscosity, o.angular_viscosity,
                     o.surface_friction})
      num(v);
  }
  for (const auto& o : w.obstacles) {
    os << "\nobstacle " << o.name << ' ';
    shape(o.shape), colour(o.colour), pose(o.pose);
  }
  for (const auto& g : w.goals) {
    os << "\ngoal " << g.name << ' ';
    num(g.center.x()), num(g.center.y()), num(g.radius), colour(g.colour);
  }
  os << "\nstimulus ";
  colour(w.stimulus_colour);
  return os.str();
}

double wall_distance(const ArenaSpec& a, double x, double y) {
  return std::min({x - a.xmin, a.xmax - x, y - a.ymin, a.ymax - y});
}

Shape disk(const Vec2& c, double r) {
  Shape s;
  s.name = "disk";
  s.disks.push_back(Disk{c, r});
  return s;
}


// Whether an eye somewhere on a coarse grid of free floor, looking at the object, sees part of it
// past the obstacles.
bool object_visible_somewhere(const WorldSpec& w) {
  const ObjectSpec& object = w.objects.at(0);
  std::vector<SeenSurface> surfaces;
  append_seen_surfaces(surfaces, object.shape, object.pose, SurfaceKind::kObject, 0, object.colour);
  for (size_t i = 0; i < w.obstacles.size(); ++i)
    append_seen_surfaces(surfaces, w.obstacles[i].shape, w.obstacles[i].pose, SurfaceKind::kObstacle, int(i),
                 w.obstacles[i].colour);
  const ArenaSpec& a = w.arena;
  const double step = 0.25, margin = 0.2;
  EyeImage image;
  for (double x = a.xmin + margin; x <= a.xmax - margin + 1e-9; x += step) {
    for (double y = a.ymin + margin; y <= a.ymax - margin + 1e-9; y += step) {
      const Vec2 eye(x, y);
      // Free floor: room for Roger's base, and not on top of the object.
      bool free = shape_signed_distance(object.shape, object.pose, eye) > 0.3;
      for (const auto& o : w.obstacles) free = free && shape_signed_distance(o.shape, o.pose, eye) > 0.16;
      if (!free) continue;
      const double heading = std::atan2(object.pose.y - y, object.pose.x - x);
      paint_eye(Camera{}, eye, heading, surfaces, a.wall_colour, w.stimulus_colour, image);
      for (int u = 0; u < Camera{}.pixels; ++u)
        if (image.kind[u] == SurfaceKind::kObject) return true;
    }
  }
  return false;
}

ScriptError generate_error(Scenario& s, uint64_t seed = 0) {
  try {
    s.generate(seed);
  } catch (const ScriptError& e) {
    return e;
  }
  FAIL("generate did not fail");
  throw;
}

ScriptError load_error(const std::string& path) {
  try {
    Scenario::load(path);
  } catch (const ScriptError& e) {
    return e;
  }
  FAIL("load did not fail: " << path);
  throw;
}

}  // namespace

TEST_CASE("the shape library", "[scenario]") {
  Scenario s = Scenario::load("cluttered");
  for (const char* name : {"circle", "triangle", "pentagon", "spade"}) {
    s.set_param("shape", name);
    const WorldSpec w = s.generate(1);
    REQUIRE(w.objects.size() == 1);
    const Shape& shape = w.objects[0].shape;
    CHECK(shape.name == name);
    CHECK(w.objects[0].name == name);
    // All about the ball's size.
    CHECK(shape_bounding_radius(shape) == Approx(0.2).margin(0.021));
  }
  s.set_param("shape", "circle");
  const Shape circle = s.generate(1).objects[0].shape;
  REQUIRE(circle.disks.size() == 1);
  CHECK(circle.polygons.empty());
  CHECK(circle.disks[0].radius == 0.2);
  s.set_param("shape", "spade");
  const Shape spade = s.generate(1).objects[0].shape;
  CHECK(spade.polygons.size() + spade.disks.size() >= 3);  // non-convex: several parts
  s.set_param("shape", "pentagon");
  CHECK(s.generate(1).objects[0].shape.polygons.at(0).vertices.size() == 5);
  s.set_param("shape", "triangle");
  CHECK(s.generate(1).objects[0].shape.polygons.at(0).vertices.size() == 3);
}

TEST_CASE("unobstructed: constraints hold over 1000 seeds", "[scenario]") {
  Scenario s = Scenario::load("scenarios/unobstructed.lua");
  CHECK(s.name() == "unobstructed");
  CHECK(s.path() == "scenarios/unobstructed.lua");
  // Base and hands in the start posture: more than the base, less than a stretched arm.
  const double footprint = robot_footprint_radius();
  CHECK(footprint > 0.16);
  CHECK(footprint <= 0.18 + 1.0 + 0.08);
  double headings = 0.0;
  for (uint64_t seed = 0; seed < 1000; ++seed) {
    const WorldSpec w = s.generate(seed);
    INFO("seed " << seed);
    REQUIRE(w.objects.size() == 1);
    REQUIRE(w.goals.size() == 1);
    CHECK(w.obstacles.empty());
    const ObjectSpec& ball = w.objects[0];
    const Pose& r = w.robot.pose;
    CHECK(ball.name == "circle");
    CHECK(ball.mass == 0.5);
    CHECK(ball.colour == Colour{220, 30, 30});
    CHECK(w.stimulus_colour == ball.colour);
    CHECK(w.arena.xmin == -2.0);
    CHECK(w.arena.xmax == 2.0);
    CHECK(wall_distance(w.arena, ball.pose.x, ball.pose.y) >= 0.95);
    CHECK(std::hypot(ball.pose.x - r.x, ball.pose.y - r.y) >= 1.4);
    CHECK(wall_distance(w.arena, r.x, r.y) >= 0.5);
    // Hands and base inside the arena and clear of the ball; nothing starts on the goal.
    for (const auto& d : robot_footprint(w.robot)) {
      CHECK(wall_distance(w.arena, d.center.x(), d.center.y()) >= d.radius);
      CHECK(shape_gap(disk(d.center, d.radius), Pose{}, ball.shape, ball.pose) > 0.0);
      CHECK((d.center - w.goals[0].center).norm() > d.radius + w.goals[0].radius);
    }
    CHECK(w.goals[0].center == Vec2(0.0, 0.0));
    CHECK(w.goals[0].radius == 0.25);
    CHECK(std::hypot(ball.pose.x, ball.pose.y) > 0.2 + 0.25);
    headings += r.theta;
  }
  CHECK(std::abs(headings / 1000.0) < 0.2);  // random headings, centred on zero
}

TEST_CASE("cluttered: no overlaps and the object is never hidden, for every shape, over 1000 seeds",
          "[scenario]") {
  Scenario s = Scenario::load("cluttered");
  for (const char* name : {"circle", "triangle", "pentagon", "spade"}) {
    s.set_param("shape", name);
    int boxes = 0, disks = 0;
    for (uint64_t seed = 0; seed < 1000; ++seed) {
      const WorldSpec w = s.generate(seed);
      INFO(name << " seed " << seed);
      REQUIRE(w.objects.size() == 1);
      REQUIRE(w.obstacles.size() == 3);
      const ObjectSpec& object = w.objects[0];
      CHECK(wall_distance(w.arena, object.pose.x, object.pose.y) >= 0.95);
      CHECK(std::hypot(object.pose.x - w.robot.pose.x, object.pose.y - w.robot.pose.y) >= 1.4);
      const auto robot = robot_footprint(w.robot);
      for (size_t i = 0; i < w.obstacles.size(); ++i) {
        const ObstacleSpec& o = w.obstacles[i];
        CHECK(o.colour == Colour{90, 90, 110});
        const double size = 2.0 * shape_bounding_radius(o.shape);
        if (o.shape.polygons.empty()) {
          ++disks;
          CHECK(size >= 0.15 - 1e-12);
          CHECK(size <= 0.3 + 1e-12);
        } else {
          ++boxes;
          CHECK(size <= 0.3 * std::sqrt(2.0) + 1e-12);
        }
        CHECK(shape_gap(o.shape, o.pose, object.shape, object.pose) >= 0.4 - 1e-9);
        for (const auto& d : robot) CHECK(shape_gap(o.shape, o.pose, disk(d.center, d.radius), Pose{}) >= 0.4 - 1e-9);
        CHECK(shape_gap(o.shape, o.pose, disk(w.goals[0].center, w.goals[0].radius), Pose{}) >= 0.4 - 1e-9);
        for (size_t j = 0; j < i; ++j)
          CHECK(shape_gap(o.shape, o.pose, w.obstacles[j].shape, w.obstacles[j].pose) >= 0.4 - 1e-9);
      }
      CHECK(object_visible_somewhere(w));
    }
    CHECK(boxes > 1000);  // both kinds of obstacle occur
    CHECK(disks > 1000);
  }
}

TEST_CASE("the visibility check itself sees occlusion", "[scenario]") {
  // A ball walled in on all four sides is hidden from everywhere; open one side and it is seen.
  WorldSpec w;
  ObjectSpec ball;
  ball.shape = disk(Vec2::Zero(), 0.2);
  w.objects.push_back(ball);
  auto wall = [](double x, double y, double hw, double hh) {
    ObstacleSpec o;
    o.shape.name = "wall";
    o.shape.polygons.push_back(Polygon{{Vec2(-hw, -hh), Vec2(hw, -hh), Vec2(hw, hh), Vec2(-hw, hh)}});
    o.pose = Pose{x, y, 0.0};
    return o;
  };
  w.obstacles = {wall(0, 0.4, 0.5, 0.1), wall(0, -0.4, 0.5, 0.1), wall(0.4, 0, 0.1, 0.5)};
  CHECK(object_visible_somewhere(w));
  w.obstacles.push_back(wall(-0.4, 0, 0.1, 0.5));
  CHECK_FALSE(object_visible_somewhere(w));
}

TEST_CASE("a world is a pure function of scenario, parameters and seed", "[scenario]") {
  Scenario a = Scenario::load("cluttered");
  Scenario b = Scenario::load("scenarios/cluttered.lua");
  a.set_param("shape", "spade");
  b.set_param("shape", "spade");
  const std::string first = dump(a.generate(42));
  CHECK(dump(a.generate(7)) != first);
  CHECK(dump(a.generate(42)) == first);  // no state carried between calls
  CHECK(dump(b.generate(42)) == first);  // nor between instances
  CHECK(dump(a.generate(43)) != first);
  const WorldSpec w = a.generate(42);
  CHECK(w.seed == 42);
  CHECK(w.scenario == "scenarios/cluttered.lua");
  CHECK(w.params.at("shape") == "spade");
  CHECK(w.params.at("obstacles") == "3");
  CHECK(w.params.at("obstacle_clearance") == "0.4");

  // Cluttered puts Roger and the object where unobstructed does, then adds obstacles.
  Scenario open = Scenario::load("unobstructed");
  open.set_param("shape", "spade");
  for (uint64_t seed : {0, 1, 99}) {
    const WorldSpec u = open.generate(seed), c = a.generate(seed);
    CHECK(u.robot.pose.x == c.robot.pose.x);
    CHECK(u.robot.pose.theta == c.robot.pose.theta);
    CHECK(u.objects[0].pose.x == c.objects[0].pose.x);
    CHECK(u.objects[0].pose.theta == c.objects[0].pose.theta);
  }
}

// Found by a probe: an rng kept from one world's generate (or a fork of it) drew on in the next
// one, so a world depended on the worlds built before it in that Lua state, in an order --jobs
// changes. It is finished when its generate returns, as the world is.
TEST_CASE("a world's rng and its forks draw only while its generate runs", "[scenario]") {
  for (const std::string keep : {"rng", "rng:fork()"}) {
    INFO(keep);
    Scenario s = test::scenario_from("kept_rng",
                                     "local kept\n"
                                     "return { generate = function(world, rng, p)\n"
                                     "  local x = kept and kept:uniform(-1, 1) or 0\n"
                                     "  kept = kept or " + keep + "\n"
                                     "  world:robot{ x = x, y = 0, heading = rng:angle() }\n"
                                     "end }\n");
    CHECK_NOTHROW(s.generate(1));
    const ScriptError e = generate_error(s);
    CHECK(e.line == 3);
    CHECK_THAT(e.message, StartsWith("rng:uniform: this rng is finished: a world's rng and its forks draw only "
                                     "while its generate runs"));
  }
}

TEST_CASE("scenario parameters", "[scenario]") {
  Scenario s = Scenario::load("cluttered");
  const auto params = s.params();
  auto find = [&](const std::string& name) {
    for (const auto& p : params)
      if (p.name == name) return p;
    FAIL("no parameter " << name);
    throw;
  };
  const ScenarioParam shape = find("shape");
  CHECK(shape.type == ParamType::kString);
  CHECK(shape.default_value == "circle");
  CHECK(shape.choices == std::vector<std::string>{"circle", "pentagon", "spade", "triangle"});
  CHECK(find("obstacles").type == ParamType::kInteger);
  CHECK(find("obstacles").default_value == "3");
  CHECK(find("mass").type == ParamType::kNumber);
  CHECK_FALSE(find("mass").description.empty());

  SECTION("set_param converts by type and takes effect") {
    s.set_param("obstacles", "5");
    s.set_param("mass", "0.75");
    s.set_param("shape", "pentagon");
    const WorldSpec w = s.generate(3);
    CHECK(w.obstacles.size() == 5);
    CHECK(w.objects[0].mass == 0.75);
    CHECK(w.objects[0].shape.name == "pentagon");
    CHECK(w.params.at("mass") == "0.75");
    s.set_param("obstacles", "0");
    CHECK(s.generate(3).obstacles.empty());
  }
  SECTION("an unknown key lists the known parameters, the nearest named first") {
    CHECK_THROWS_WITH(s.set_param("obstcles", "2"),
                      StartsWith("scenario 'cluttered' (scenarios/cluttered.lua) has no parameter "
                                 "'obstcles' (did you mean 'obstacles'?); known parameters: base_radius "
                                 "(number, default 0.16; min 0.09; max 1)") &&
                          Contains("goal_radius (number, default 0.25; min 0.01)") &&
                          Contains("obstacles (integer, default 3; min 0; max 8)") &&
                          Contains("shape (string, default circle; one of circle, pentagon, spade, triangle)"));
    // A body field through --set gets its hint too (lib/body.lua's parameters are the scenario's).
    CHECK_THROWS_WITH(s.set_param("uper_arm", "0.6"), Contains("has no parameter 'uper_arm' (did you mean 'upper_arm'?)"));
    // Found by a probe: lib/body's 36 noise levels, each listed, buried the scenario's own. They
    // are one entry, and a misspelt one is still named by the suggestion.
    CHECK_THROWS_WITH(s.set_param("obstcles", "2"),
                      Contains("; noise_* (36 parameters, noise_base to noise_touch_tau); ") &&
                          !Contains("noise_base_bias (number"));
    CHECK_THROWS_WITH(s.set_param("noise_joint_bias", "0.01"),
                      Contains("has no parameter 'noise_joint_bias' (did you mean 'noise_joints_bias'?)"));
    // Found by a probe: a kind or channel by another common name (the docs call quantum the
    // resolution) got no hint; any other noise name is told how they are spelt.
    CHECK_THROWS_WITH(s.set_param("noise_joints_resolution", "0.01"),
                      Contains("has no parameter 'noise_joints_resolution' (did you mean 'noise_joints_quantum'?)"));
    CHECK_THROWS_WITH(s.set_param("noise_camera", "5"), Contains("(did you mean 'noise_image'?)"));
    CHECK_THROWS_WITH(s.set_param("noise_encoders_latency", "2"), Contains("(did you mean 'noise_joints_delay'?)"));
    CHECK_THROWS_WITH(s.set_param("noise", "0.1"),
                      Contains("has no parameter 'noise' (noise parameters are noise_CHANNEL, its sigma, and "
                               "noise_CHANNEL_KIND; channels: base, effort, image, joints, touch; kinds: bias, delay, "
                               "drift, dropout, quantum, tau; and noise_scale); known parameters: "));
  }
  // Before, "expects at most 12" or "expects an integer": a user learnt the range one bound at a time.
  SECTION("a value that does not fit says the whole range, the description and the default") {
    CHECK_THROWS_WITH(s.set_param("obstacles", "2.5"),
                      "parameter 'obstacles' of scenario 'cluttered' expects an integer in [0, 8], got '2.5' "
                      "(number of obstacles; default 3)");
    CHECK_THROWS_WITH(s.set_param("mass", "heavy"),
                      "parameter 'mass' of scenario 'cluttered' expects a number in [0.01, 10000], got 'heavy' "
                      "(object mass (kg); default 0.5)");
    CHECK_THROWS_WITH(s.set_param("goal_radius", "wide"),
                      "parameter 'goal_radius' of scenario 'cluttered' expects a number of at least 0.01, got 'wide' "
                      "(goal radius (m); default 0.25)");
    CHECK_THROWS_WITH(s.set_param("shape", "hexagon"),
                      "parameter 'shape' of scenario 'cluttered' expects one of circle, pentagon, "
                      "spade, triangle, got 'hexagon' (the object: circle, triangle, pentagon or spade; default circle)");
    CHECK_THROWS_WITH(s.set_param("obstacles", "40"),
                      "parameter 'obstacles' of scenario 'cluttered' expects an integer in [0, 8], got '40' "
                      "(number of obstacles; default 3)");
    // lib/body.lua's locked joints: a list, checked when set (before, at the first world built).
    CHECK_THROWS_WITH(s.set_param("locked", "left_elbow,left_knee"),
                      "parameter 'locked' of scenario 'cluttered' expects a comma-separated list of any of left_eye, "
                      "right_eye, left_shoulder, left_elbow, right_shoulder, right_elbow (or none), got "
                      "'left_elbow,left_knee' (joints held at their start angle, comma-separated (e.g. "
                      "left_elbow,right_elbow); default )");
    // Found by a probe: a joint named twice was taken here, and refused by world:robot at a line of
    // scenarios/lib/place.lua.
    CHECK_THROWS_WITH(s.set_param("locked", "left_elbow, left_elbow"),
                      Contains("parameter 'locked' of scenario 'cluttered' expects a comma-separated list of any of "
                               "left_eye, right_eye, left_shoulder, left_elbow, right_shoulder, right_elbow (or none), "
                               "each once, got 'left_elbow, left_elbow'"));
    CHECK_THROWS_WITH(s.set_param("eye_pixels", "3"),
                      "parameter 'eye_pixels' of scenario 'cluttered' expects an integer in [16, 512], got '3' "
                      "(pixels of each eye; default 128)");
    // Several at once (--set, a stage's params): each refused, none set.
    CHECK_THROWS_WITH(s.set_params({{"obstacles", "2"}, {"eye_pixels", "3"}, {"shap", "circle"}}),
                      StartsWith("parameter 'eye_pixels' of scenario 'cluttered' expects an integer in [16, 512], "
                                 "got '3' (pixels of each eye; default 128); scenario 'cluttered' "
                                 "(scenarios/cluttered.lua) has no parameter 'shap' (did you mean 'shape'?)"));
    CHECK(s.generate(0).obstacles.size() == 3);
    CHECK_THROWS_AS(s.set_param("mass", ""), Error);
    // Found by a probe: " 3" was taken where "3 " was refused (strtoll skips leading blanks).
    CHECK_THROWS_WITH(s.set_param("obstacles", " 2"), StartsWith("parameter 'obstacles' of scenario 'cluttered' "
                                                                 "expects an integer in [0, 8], got ' 2'"));
    CHECK_THROWS_WITH(s.set_param("mass", "\t1"), Contains("expects a number in [0.01, 10000], got '\t1'"));
    // Found by a probe: hexadecimal, which strtod reads, was taken (eye_pixels=0x20 ran 32 pixels).
    CHECK_THROWS_WITH(s.set_param("eye_pixels", "0x20"), Contains("expects an integer in [16, 512], got '0x20'"));
    CHECK_THROWS_WITH(s.set_param("mass", "0X1p-1"), Contains("expects a number in [0.01, 10000], got '0X1p-1'"));
    // Found by a probe: `--set noise_joints_delay=2.0` was refused where a table's `delay = 2.0` is
    // taken. A whole number written as a float is that integer; a fraction is still refused.
    CHECK_NOTHROW(s.set_param("obstacles", "2.0"));
    CHECK(s.generate(0).obstacles.size() == 2);
    CHECK_NOTHROW(s.set_param("obstacles", "1e0"));
    CHECK(s.generate(0).obstacles.size() == 1);
    CHECK_THROWS_WITH(s.set_param("obstacles", "2.000001"), Contains("expects an integer in [0, 8], got '2.000001'"));
    CHECK_THROWS_WITH(s.set_param("obstacles", "2.0x"), Contains("got '2.0x'"));
    CHECK_THROWS_WITH(s.set_param("obstacles", "nan"), Contains("got 'nan'"));
    CHECK_THROWS_WITH(s.set_param("obstacles", "9.0"), Contains("expects an integer in [0, 8], got '9.0'"));
    s.set_param("obstacles", "3");
    // Found by a probe: a number below the smallest double was refused as out of range; it is 0.
    CHECK_NOTHROW(s.set_param("noise_joints_bias", "1e-400"));
    CHECK_THROWS_WITH(s.set_param("noise_joints_bias", "1e400"), Contains("got '1e400'"));
    s.set_param("noise_joints_bias", "0");
    // A failed set_param leaves the old value.
    CHECK(s.generate(0).obstacles.size() == 3);
  }
}

// Found by a probe: `--set locked=left_knee` passed --set and failed at the first world, in
// library code and without naming the parameter. A list parameter is checked where it is set.
TEST_CASE("a list parameter takes any of its choices, comma-separated, and refuses others when set", "[scenario]") {
  Scenario s = test::scenario_from("list_param", R"(return {
  params = { held = { default = "", choices = { "left_elbow", "right_elbow", "left_eye" }, list = true,
                      description = "joints held" } },
  generate = function(world, rng, p)
    local locked = {}
    for name in string.gmatch(p.held, "[^,%s]+") do locked[#locked + 1] = name end
    world:robot{ x = 0, y = 0, body = { locked = locked } }
  end,
})");
  CHECK(s.generate(0).body.locked == 0u);
  s.set_param("held", "left_elbow, right_elbow");
  CHECK(s.generate(0).body.locked != 0u);
  s.set_param("held", "");
  CHECK(s.generate(0).body.locked == 0u);
  CHECK_THROWS_WITH(s.set_param("held", "left_elbow,left_knee"),
                    "parameter 'held' of scenario 'roger_test_list_param' expects a comma-separated list of any of "
                    "left_elbow, right_elbow, left_eye (or none), got 'left_elbow,left_knee' (joints held; default )");
  CHECK_THROWS_WITH(test::scenario_from("list_no_choices", "return { params = { held = { default = '', list = true } }, "
                                                           "generate = function() end }"),
                    Contains("parameter 'held': list = true takes the items from choices = {...}, and there are none"));
  CHECK_THROWS_WITH(test::scenario_from("list_number", "return { params = { n = { default = 1, choices = { 1, 2 }, "
                                                       "list = true } }, generate = function() end }"),
                    Contains("parameter 'n': a list's default is a string of comma-separated choices (\"\" for "
                             "none), got integer 1"));
  // Found by a probe: `--set held=,` (or a trailing comma) held nothing, unsaid; "" alone is none.
  CHECK_THROWS_WITH(s.set_param("held", "left_elbow,"), Contains("(or none), with no empty item between commas"));
  CHECK_THROWS_WITH(s.set_param("held", ","), Contains("with no empty item between commas"));
  CHECK_NOTHROW(s.set_param("held", ""));
  // Found by a probe: an item holding a comma loaded, and no value could ever name it.
  CHECK_THROWS_WITH(test::scenario_from("list_comma", "return { params = { k = { default = '', choices = { 'a,b', 'c' }, "
                                                      "list = true } }, generate = function() end }"),
                    Contains("parameter 'k': list = true joins its items with commas, so an item cannot hold one, got "
                             "'a,b'"));
}

TEST_CASE("script mistakes are reported at the script's file:line", "[scenario]") {
  SECTION("syntax error") {
    const ScriptError e = load_error("tests/scripts/bad_syntax.lua");
    CHECK(e.file == "tests/scripts/bad_syntax.lua");
    CHECK(e.line == 5);
  }
  SECTION("a misspelt field of the returned table, at the line where it is written") {
    // Found by a probe: these named the file alone, with a traceback of "[C]: in ?".
    const ScriptError field = load_error("tests/scripts/bad_scenario_fields.lua");
    CHECK(field.line == 6);
    CHECK_THAT(field.message, StartsWith("parameter 'n': unknown field 'defualt' (did you mean 'default'?)"));
    CHECK(field.traceback.empty());
    const ScriptError top = load_error("tests/scripts/bad_scenario_top.lua");
    CHECK(top.line == 5);
    CHECK_THAT(top.message, StartsWith("the scenario table has an unknown field 'parms' (did you mean 'params'?)"));
  }
  SECTION("runtime error inside a generator, with a traceback") {
    Scenario s = Scenario::load("tests/scripts/bad_runtime.lua");
    const ScriptError e = generate_error(s);
    CHECK(e.file == "tests/scripts/bad_runtime.lua");
    CHECK(e.line == 5);
    CHECK_THAT(e.message, Contains("attempt to index a nil value (field 'dimensions')"));
    CHECK_THAT(e.traceback, Contains("tests/scripts/bad_runtime.lua:5: in "));
    CHECK_THAT(e.traceback, Contains("tests/scripts/bad_runtime.lua:12: in "));
  }
  SECTION("a degenerate polygon never reaches Box2D") {
    Scenario s = Scenario::load("tests/scripts/bad_polygon.lua");
    const ScriptError e = generate_error(s);
    CHECK(e.file == "tests/scripts/bad_polygon.lua");
    CHECK(e.line == 4);
    CHECK_THAT(e.message, StartsWith("roger.shape: shape 'flat' polygon 1: degenerate"));
  }
  SECTION("a misspelt method of the world or of rng names the methods, at its line") {
    // Found by a probe: rng:integer(...) read nil and failed with "attempt to call a nil value".
    Scenario s = Scenario::load("tests/scripts/bad_method_name.lua");
    const ScriptError world = generate_error(s);
    CHECK(world.line == 9);
    CHECK(world.message == "world has no method 'obstcle' (did you mean 'obstacle'?); its methods: arena, bounds, "
                           "goal, object, obstacle, robot, sample_position, stimulus");
    s.set_param("which", "rng");
    const ScriptError rng = generate_error(s);
    CHECK(rng.line == 7);
    CHECK(rng.message == "rng has no method 'integre'; its methods: angle, choice, fork, int, normal, shuffle, uniform");
    // Found by a probe: in a helper the generator calls, the error named the generator's line.
    Scenario helper = Scenario::load("tests/scripts/bad_method_in_helper.lua");
    const ScriptError in_helper = generate_error(helper);
    CHECK(in_helper.file == "tests/scripts/bad_method_in_helper.lua");
    CHECK(in_helper.line == 5);
    CHECK_THAT(in_helper.message, StartsWith("world has no method 'sample_positon' (did you mean 'sample_position'?)"));
  }
  SECTION("a misspelt parameter read by the generator, at its line") {
    // Found by a probe: p.goal_raduis read nil, world:goal took its default radius, roger check
    // passed, and --set goal_radius=... changed nothing.
    Scenario s = test::scenario_from("param_typo", R"(return {
  params = { goal_radius = { default = 0.35, min = 0.2, max = 1 } },
  generate = function(world, rng, p)
    world:robot{ x = 0, y = 0, heading = 0 }
    for _ in ipairs(p) do end -- a key that is no name reads nil, as in any table
    world:goal{ x = 2, y = 0, radius = p.goal_raduis }
  end,
})");
    const ScriptError e = generate_error(s);
    CHECK(e.line == 6);
    CHECK(e.message == "the scenario has no parameter 'goal_raduis' (did you mean 'goal_radius'?); its parameters: "
                       "goal_radius");
  }
  SECTION("bounds on a parameter whose default is no number, at its line") {
    // Found by a probe: the first world:goal that read it was blamed for a string.
    const auto path = std::filesystem::temp_directory_path() / "roger_test_string_bounds.lua";
    std::ofstream(path) << "return {\n  params = {\n    goal_radius = { default = '0.35', min = 0.2 },\n  },\n"
                           "  generate = function(world) world:robot{ x = 0, y = 0 } end,\n}\n";
    const ScriptError e = load_error(path.string());
    CHECK(e.line == 3);
    CHECK(e.message == "parameter 'goal_radius': min bounds a number, and the default is string '0.35' (its type "
                       "is the default's: write it as a number for a numeric parameter)");
  }
  SECTION("a choice outside the parameter's own bounds, at its line") {
    // Found by a probe: choices = {1, 2, 4} with max = 3 loaded, and roger check then refused k=4
    // with "expects one of 1, 2, 4, got '4'", at no line.
    const auto path = std::filesystem::temp_directory_path() / "roger_test_choice_bounds.lua";
    const auto write_with = [&](const std::string& param) {
      std::ofstream(path) << "return {\n  params = {\n    " << param << ",\n  },\n"
                             "  generate = function(world) world:robot{ x = 0, y = 0 } end,\n}\n";
      return path.string();
    };
    const ScriptError above = load_error(write_with("k = { default = 2, choices = { 1, 2, 4 }, min = 0, max = 3 }"));
    CHECK(above.line == 3);
    CHECK(above.message == "parameter 'k': the choice 4 is above its max = 3, so it could never be set");
    CHECK(load_error(write_with("r = { default = 0.5, choices = { 0.05, 0.5 }, min = 0.1 }")).message ==
          "parameter 'r': the choice 0.05 is below its min = 0.1, so it could never be set");
    // Choices within the bounds load as before.
    CHECK_NOTHROW(Scenario::load(write_with("k = { default = 2, choices = { 1, 2, 3 }, min = 1, max = 3 }")));
    // Found by a probe: bounds the wrong way round were told as the default outside them, an
    // integer parameter took a fractional bound, and choices mixed numbers and strings.
    CHECK(load_error(write_with("a = { default = 0.5, min = 1, max = 0.2 }")).message ==
          "parameter 'a': min = 1 is above max = 0.2, so no value could be set");
    CHECK(load_error(write_with("n = { default = 2, min = 0.5, max = 3 }")).message ==
          "parameter 'n': min = 0.5 bounds an integer parameter (its default 2 is an integer): give a whole number, "
          "or write the default as 2.0 for a real-valued parameter");
    CHECK(load_error(write_with("s = { default = 'circle', choices = { 'circle', 3 } }")).message ==
          "parameter 's': choices mixes numbers and strings; give all of one kind, the default's");
    CHECK_NOTHROW(Scenario::load(write_with("n = { default = 2.0, min = 0.5, max = 3.5 }")));
    // Found by a probe: a fractional choice of an integer parameter loaded, and was then refused
    // as not one of the choices it listed; a choice given twice loaded.
    CHECK(load_error(write_with("k = { default = 2, choices = { 2.5, 2 } }")).message ==
          "parameter 'k': the choice 2.5 is not whole, and the parameter is an integer (its default 2): give whole "
          "numbers, or write the default as 2.0 for a real-valued parameter");
    CHECK(load_error(write_with("s = { default = 'a', choices = { 'a', 'b', 'a' } }")).message ==
          "parameter 's': the choice a is given twice");
    CHECK(load_error(write_with("k = { default = 2, choices = { 2, 2.0 } }")).message ==
          "parameter 'k': the choice 2 is given twice");
    CHECK_NOTHROW(Scenario::load(write_with("k = { default = 2.0, choices = { 2.5, 2 } }")));
    std::filesystem::remove(path);
  }
  SECTION("an unknown shape lists the known ones") {
    Scenario s = Scenario::load("tests/scripts/bad_shape_name.lua");
    const ScriptError e = generate_error(s);
    CHECK(e.file == "tests/scripts/bad_shape_name.lua");
    CHECK(e.line == 6);
    CHECK(e.message == "unknown shape 'hexagon'; known shapes: circle, pentagon, spade, triangle");
  }
  // Found by a probe: a negative width made a box all the same, a size written as a string passed,
  // and a forgotten name ended in "arithmetic on a nil value" at the library's line.
  SECTION("the shape helpers check their arguments at the caller's line") {
    const std::pair<std::string, std::string> cases[] = {
        {"shapes.box('z', -0.3, 0.5)", "shapes.box('z', ...): w must be a number above 0 (metres), got -0.3"},
        {"shapes.box('b', 0.3, '0.3')", "shapes.box('b', ...): h must be a number above 0 (metres), got \"0.3\""},
        {"shapes.box(0.3, 0.3)", "shapes.box: the first argument is the shape's name (a string), got 0.3"},
        {"shapes.disk('d', 0)", "shapes.disk('d', ...): r must be a number above 0 (metres), got 0"},
        {"shapes.regular('h', 9, 0.2)",
         "shapes.regular('h', n, r): n is the number of vertices, an integer from 3 to 8, got 9"},
        {"shapes.regular('h', 5, -0.2)", "shapes.regular('h', ...): r must be a number above 0 (metres), got -0.2"}};
    for (const auto& [call, says] : cases) {
      INFO(call);
      try {
        test::scenario_from("shape_args", "local shapes = require('lib.shapes')\n"
                                          "return { generate = function(world, rng, p)\n"
                                          "  world:robot{ x = 0, y = 0, heading = 0 }\n"
                                          "  world:object{ shape = " + call + ", x = 1, y = 0 }\n"
                                          "end }\n")
            .generate(0);
        FAIL("accepted");
      } catch (const ScriptError& e) {
        CHECK(e.line == 4);
        CHECK(e.file.find("shape_args") != std::string::npos);
        CHECK(e.message == says);
      }
    }
    CHECK_NOTHROW(test::scenario_from("shape_ok", "local shapes = require('lib.shapes')\n"
                                                  "return { generate = function(world, rng, p)\n"
                                                  "  world:robot{ x = 0, y = 0, heading = 0 }\n"
                                                  "  world:object{ shape = shapes.regular('h', 6.0, 0.2), x = 1, y = 0 }\n"
                                                  "end }\n")
                      .generate(0));
  }
  SECTION("impossible placements end in a clear error after bounded retries") {
    Scenario s = Scenario::load("tests/scripts/bad_placement.lua");
    const ScriptError walls = generate_error(s);
    CHECK(walls.line == 8);
    CHECK(walls.message ==
          "world:sample_position: no placement for 'ball': it needs 2.5 m from the walls, which "
          "leaves no room in a 4 x 4 m arena");
    s.set_param("mode", "robot");
    const ScriptError robot = generate_error(s);
    CHECK(robot.line == 11);
    CHECK_THAT(robot.message,
               StartsWith("world:sample_position: no placement for 'ball' after 500 tries: it "
                          "needs 0.25 m from the walls, ") &&
                   Contains("10 m from Roger (failed every try)") &&
                   EndsWith("in a 4 x 4 m arena"));
    // Found by a probe: a candidate too near two of sorting's goal regions counted twice, so the
    // message said "after 1000 tries" and "(failed in 3401 tries)".
    Scenario sorting = Scenario::load("sorting");
    sorting.set_param("forearm", "2");
    const ScriptError crowded = generate_error(sorting);
    INFO(crowded.message);
    const std::regex failed("failed in ([0-9]+) tries");
    for (auto it = std::sregex_iterator(crowded.message.begin(), crowded.message.end(), failed);
         it != std::sregex_iterator(); ++it)
      CHECK(std::stoi((*it)[1].str()) < 1000);
    CHECK_THAT(crowded.message, Contains("after 1000 tries"));
    // Found by a probe: "(failed in 1000 tries)" after "after 1000 tries" said the count twice.
    CHECK_THAT(crowded.message, Contains("clearance from the goal regions (failed every try)"));
  }
  SECTION("field names and types") {
    Scenario s = Scenario::load("tests/scripts/bad_field.lua");
    const ScriptError unknown = generate_error(s);
    CHECK(unknown.line == 8);
    CHECK(unknown.message ==
          "world:object: unknown field 'mas' (did you mean 'mass'?); known fields: angular_viscosity, colour, "
          "friction_force, friction_torque, mass, name, shape, surface_friction, theta, "
          "viscosity, x, y");
    s.set_param("mode", "type");
    CHECK(generate_error(s).message == "world:object: field 'x' must be a number, got string 'one'");
    s.set_param("mode", "missing");
    CHECK(generate_error(s).message == "world:object: missing required field 'x' (a number)");
    s.set_param("mode", "overlap");
    CHECK(generate_error(s).message ==
          "world:object: object 'object 1' at (0.2, 0) overlaps Roger's base by 0.16 m");
    // Beyond what Box2D holds in single precision, refused here rather than aborting the physics.
    s.set_param("mode", "huge_mass");
    CHECK(generate_error(s).message == "world:object: field 'mass' must be within [0.001, 10000] kg, got 1e+39");
    s.set_param("mode", "huge_viscosity");
    CHECK(generate_error(s).message ==
          "world:object: field 'angular_viscosity' must be within [0, 10000] 1/s, got 1e+300");
  }
  SECTION("a generator that forgets Roger") {
    Scenario s = Scenario::load("tests/scripts/bad_no_robot.lua");
    const ScriptError e = generate_error(s);
    CHECK(e.file == "tests/scripts/bad_no_robot.lua");
    CHECK(e.line == 4);
    CHECK_THAT(e.message, StartsWith("the generator did not place Roger"));
  }
  // Found by a probe: a table returned beside world:robot was dropped without a word.
  SECTION("a generator that returns a value") {
    const std::string head = "return { generate = function(world, rng, p)\n"
                             "  world:robot{ x = 0, y = 0, heading = 0 }\n";
    try {
      test::scenario_from("returns_table", head + "  return { objects = {} }\nend }\n").generate(0);
      FAIL("a generator's returned table was accepted");
    } catch (const ScriptError& e) {
      CHECK(e.line == 1);
      CHECK_THAT(e.message, StartsWith("the generator returned a table, which is not read"));
    }
    // Returning the world itself, or nothing, is what a generator may do.
    CHECK_NOTHROW(test::scenario_from("returns_world", head + "  return world\nend }\n").generate(0));
    CHECK_NOTHROW(test::scenario_from("returns_nil", head + "  return nil\nend }\n").generate(0));
    // Found by a probe: a second value passed, as Lua keeps the first.
    try {
      test::scenario_from("returns_two", head + "  return nil, 5\nend }\n").generate(0);
      FAIL("a generator's second value was accepted");
    } catch (const ScriptError& e) {
      CHECK(e.line == 1);
      CHECK_THAT(e.message, StartsWith("the generator returned a second value (a number), which is not read"));
    }
    // Found by a probe: a budget a generator's pcall caught, returned with pcall's values, was said
    // to be a second value returned, and the budget went unnamed.
    try {
      test::scenario_from("returns_pcall", "local function loop() while true do end end\n" + head +
                                               "  return pcall(loop)\nend }\n")
          .generate(0);
      FAIL("a generator that spent its budget was accepted");
    } catch (const ScriptError& e) {
      CHECK(e.line == 1);
      CHECK_THAT(e.message, Contains("instruction budget of 50000000 exceeded"));
    }
  }
  SECTION("a runaway generator") {
    Scenario s = Scenario::load("tests/scripts/bad_runtime.lua", SandboxLimits{200000, 64u << 20});
    s.sandbox().load_string("while true do end", "@tests/scripts/inline.lua");
    CHECK_THROWS_WITH(s.sandbox().call(0, 0), Contains("instruction budget of 200000 exceeded"));
  }
  SECTION("a missing scenario names the nearest and lists the shipped ones") {
    CHECK_THROWS_WITH(Scenario::load("clutered"),
                      "no scenario 'clutered' (did you mean 'cluttered'?): not a file, and scenarios/clutered.lua does not "
                      "exist; scenarios in scenarios/: cluttered, sorting, unobstructed");
  }
}

// Found by a probe: a scenario of one's own calling place.robot without robot_wall_margin failed
// at lib/place.lua's line that read it; the user's own line was only in the traceback.
TEST_CASE("a placement step of lib/place.lua names what the scenario lacks, at the scenario's line", "[scenario]") {
  const std::string head = "local body = require('lib.body')\nlocal place = require('lib.place')\n"
                           "return { params = body.with_params{ goal_x = { default = 0 } },\n"
                           "  generate = function(world, rng, p)\n";
  auto error_of = [&](const std::string& name, const std::string& call) {
    return test::generate_error(name, head + "    " + call + "\n  end }\n");
  };
  CHECK_THAT(error_of("place_robot", "place.robot(world, rng, p)"),
             Contains("roger_test_place_robot.lua:5: place.robot reads the scenario parameter "
                        "'robot_wall_margin', which the scenario does not declare: add it to its params"));
  // Found by a probe: the rng given to place.goal, which takes none, failed inside lib/place.lua.
  CHECK_THAT(error_of("place_goal_rng", "place.goal(world, rng, p)"),
             Contains("roger_test_place_goal_rng.lua:5: place.goal(world, p): p must be the generator's parameters "
                      "(its third argument), got roger.Rng"));
  CHECK_THAT(error_of("place_object_nil", "place.object(world, p)"),
             Contains("roger_test_place_object_nil.lua:5: place.object(world, rng, p): p must be the generator's "
                      "parameters (its third argument), got nil"));
  CHECK_THAT(error_of("place_goal", "place.goal(world, p)"),
             Contains("roger_test_place_goal.lua:5: place.goal reads the scenario parameters 'goal_y', "
                      "'goal_radius', which the scenario does not declare: add them"));
  // Found by a probe: obstacles declared as a real (2.0) took --set obstacles=2.5 and built 2.
  Scenario counted = test::scenario_from(
      "place_count", "local body = require('lib.body')\nlocal place = require('lib.place')\n"
                     "return { params = body.with_params{ obstacles = { default = 2.0, min = 0 },\n"
                     "    obstacle_min_size = { default = 0.1 }, obstacle_max_size = { default = 0.3 },\n"
                     "    obstacle_clearance = { default = 0.2 } },\n"
                     "  generate = function(world, rng, p)\n    world:robot{ x = -1, y = 0 }\n"
                     "    place.obstacles(world, rng, p)\n  end }\n");
  CHECK(counted.generate(0).obstacles.size() == 2);
  counted.set_param("obstacles", "2.5");
  CHECK_THROWS_WITH(counted.generate(0),
                    Contains("roger_test_place_count.lua:8: place.obstacles: the parameter obstacles is a count, got "
                             "2.5 (declare it with a whole default, { default = 3, min = 0 }, and it takes whole numbers "
                             "only)"));
  // Found by a probe: a shape default no library shape has failed at lib/place.lua's line.
  CHECK_THAT(test::generate_error("place_shape",
                                  "local body = require('lib.body')\nlocal place = require('lib.place')\n"
                                  "return { params = body.with_params{ shape = 'hexagon', mass = { default = 0.5 },\n"
                                  "    object_wall_margin = { default = 0.9 }, robot_distance = { default = 1.0 } },\n"
                                  "  generate = function(world, rng, p)\n    world:robot{ x = -1, y = 0 }\n"
                                  "    place.object(world, rng, p)\n  end }\n"),
             Contains("roger_test_place_shape.lua:7: place.object: the parameter shape is 'hexagon', which is no shape "
                      "of lib.shapes; known shapes: circle, pentagon, spade, triangle (declare it with choices = "
                      "shapes.names() to have it checked where it is set)"));
}

TEST_CASE("the Lua API checks its arguments where they are given", "[scenario]") {
  // Scenarios written to temporary files exercise the API through generate().
  auto run = [](const std::string& body, const std::string& name) -> std::string {
    const std::string path = "/tmp/roger_api_" + name + ".lua";
    FILE* f = std::fopen(path.c_str(), "w");
    std::fputs(("local shapes = require('lib.shapes')\nreturn { generate = function(world, rng)\n" +
                body + "\nend }\n")
                   .c_str(),
               f);
    std::fclose(f);
    Scenario s = Scenario::load(path);
    try {
      s.generate(0);
    } catch (const ScriptError& e) {
      std::remove(path.c_str());
      CHECK(e.line == 3);
      return e.message;
    }
    std::remove(path.c_str());
    return "no error";
  };
  CHECK(run("world.robot{x = 0, y = 0}", "dot") ==
        "world:robot: call it with a colon, as world:robot(...) (the first argument is a table, "
        "not the world)");
  CHECK(run("world:robot{x = 3, y = 0}", "outside") ==
        "world:robot: Roger's base at (3, 0) sticks out of the arena [-2, 2] x [-2, 2] by 1.16 m");
  CHECK(run("world:robot{x = 0, y = 0, left_eye = 2}", "eye") ==
        "world:robot: field 'left_eye' must be within [-1.5707963267948966, 1.5707963267948966] rad, got 2");
  CHECK(run("world:robot{x = 0, y = 0} world:arena{xmin = -3}", "late_arena") ==
        "world:arena: call world:arena first, before anything is placed, sampled or measured by world:bounds() "
        "(the default arena is already in use)");
  // Found by a probe: after world:bounds() alone the message named placing and sampling only.
  CHECK(run("local x0 = world:bounds() world:arena{xmin = -3}", "bounds_then_arena") ==
        "world:arena: call world:arena first, before anything is placed, sampled or measured by world:bounds() "
        "(the default arena is already in use)");
  CHECK(run("world:arena{xmin = 99998, xmax = 100002}", "far") ==
        "world:arena: the arena must lie within 1000 m of the origin along x, got [99998, 100002] (the physics holds "
        "positions in single precision, which far out loses the millimetres Roger moves by: move the arena's "
        "coordinates nearer 0)");
  CHECK(run("world:arena{xmin = -2, xmax = 2.1}", "cells") ==
        "world:arena: the x extent 4.1 m is not a whole number of 0.0625 m cells");
  CHECK(run("world:object{shape = {}, x = 0, y = 0}", "shape_type") ==
        "world:object: field 'shape' must be a shape made by roger.shape{...}, got table (empty)");
  CHECK(run("world:goal{x = 5, y = 0}", "goal") ==
        "world:goal: goal 'goal 1' centre (5, 0) is outside the 4 x 4 m arena");
  // Found by a newcomer's walk through the docs: the centre's fields were read in the compiler's
  // order of arguments, so an empty goal named y missing first, and x only on the next run.
  // Found by a probe: a goal whose centre lay under an obstacle passed check, and every episode
  // failed with "no reference", its note naming other causes. Refused in either order.
  CHECK(run("world:obstacle{shape = shapes.box('block', 0.8, 0.8), x = 1, y = 1} world:goal{x = 1, y = 1.3, radius = 0.7}",
            "goal_under") ==
        "world:goal: goal 'goal 1' has its centre (1, 1.3) under obstacle 'obstacle 1' (at (1, 1)): the navigator goes "
        "to a goal region's centre, which no one reaches there; move the goal or the obstacle");
  CHECK(run("world:goal{name = 'home', x = 1, y = 1} world:obstacle{name = 'post', shape = shapes.disk('post', 0.2), "
            "x = 1.15, y = 1}", "under_goal") ==
        "world:obstacle: goal 'home' has its centre (1, 1) under obstacle 'post' (at (1.15, 1)): the navigator goes "
        "to a goal region's centre, which no one reaches there; move the goal or the obstacle");
  CHECK(run("world:robot{x = -1, y = -1} world:goal{x = 1, y = 1} world:obstacle{shape = shapes.disk('post', 0.2), x = 1.25, y = 1}",
            "beside_goal") == "no error");
  // Found by a probe: a million tries where no place fits spent the budget as a "runaway loop?".
  CHECK(run("world:arena{xmin = -20, xmax = 20, ymin = -20, ymax = 20, cell = 0.25} world:robot{x = 0, y = 0} "
            "for i = 1, 60 do world:obstacle{shape = shapes.box('b', 0.2, 0.2), x = -19 + 0.5 * i, y = 10} end "
            "local x, y = world:sample_position{radius = 0.2, robot_distance = 30, tries = 1000000}", "tries_budget") ==
        "world:sample_position: instruction budget of 50000000 exceeded: its tries ran past the budget left before a "
        "place was found (no place may meet its constraints: with fewer tries it says which failed)");
  // Found by a probe: a second call replaced the first colour without a word.
  CHECK(run("world:stimulus{colour = {40, 80, 221}} world:stimulus{colour = '#00ff00'}", "stimulus_twice") ==
        "world:stimulus: the stimulus is already set, to #2850dd: the eyes track one colour (call world:stimulus once)");
  CHECK(run("world:goal{}", "goal_empty") == "world:goal: missing required field 'x' (a number)");
  CHECK(run("world:goal{x = 1}", "goal_no_y") == "world:goal: missing required field 'y' (a number)");
  CHECK(run("world:obstacle{shape = shapes.get('circle'), x = 0, y = 0, colour = {1, 2}}", "colour") ==
        "world:obstacle: field 'colour' must be a colour: {r, g, b} or {r=, g=, b=} with integers "
        "0-255, or \"#rrggbb\" (component b is missing or not an integer 0-255, got nothing)");
  CHECK(run("world:obstacle{shape = shapes.get('circle'), x = 0, y = 0, colour = {300, 0, 0}}", "colour_range") ==
        "world:obstacle: field 'colour' must be a colour: {r, g, b} or {r=, g=, b=} with integers "
        "0-255, or \"#rrggbb\" (component r is missing or not an integer 0-255, got 300)");
  // Found by a probe: a fourth entry (an alpha) was dropped without a word, and a colour mixing the
  // two forms was said to miss its g.
  CHECK(run("world:obstacle{shape = shapes.get('circle'), x = 0, y = 0, colour = {200, 0, 0, 0}}", "colour_alpha") ==
        "world:obstacle: field 'colour' must be a colour: {r, g, b} or {r=, g=, b=} with integers "
        "0-255, or \"#rrggbb\": it has [4] beside the three components (a colour has no alpha)");
  CHECK(run("world:obstacle{shape = shapes.get('circle'), x = 0, y = 0, colour = {1, 2, 3, r = 4}}", "colour_mixed") ==
        "world:obstacle: field 'colour' must be a colour: {r, g, b} or {r=, g=, b=} with integers "
        "0-255, or \"#rrggbb\": it mixes {r, g, b} and {r=, g=, b=}");
  // Found by a probe: "#-1-1-1" read as white and "# 1 2 3" as #010203 (sscanf's %x takes a sign,
  // spaces and a 0x), without a word; "#rrggbb" is six hex digits.
  for (const char* text : {"#-1-1-1", "# 1 2 3", "#0x1e1e", "#+f+f+f", "#dc1e1g"})
    CHECK(run(std::string("world:obstacle{shape = shapes.get('circle'), x = 0, y = 0, colour = '") + text + "'}",
              "colour_text") == std::string("world:obstacle: field 'colour' must be a colour: {r, g, b} or {r=, g=, b=} "
                                            "with integers 0-255, or \"#rrggbb\", got \"") + text + "\"");
  CHECK(run("world:robot{x = -1, y = 0} world:obstacle{shape = shapes.get('circle'), x = 1, y = 1, colour = '#DC1e1E'}",
            "colour_hex") == "no error");
  CHECK(run("roger.shape{name = 'big', polygons = {{{0,0},{1,0},{1,1},{0.5,1.5},{0,1},{-1,1},{-1,0.5},{-1,-1},{0,-1}}}}", "verts") ==
        "roger.shape: shape 'big' polygon 1: expected 3 to 8 vertices, got 9");
  CHECK(run("roger.shape{name = 'v', polygons = {{{0,0},{1,0},{0.2,0.2},{0,1}}}}", "concave")
            .find("non-convex") != std::string::npos);
  CHECK(run("roger.shape{name = 'd', disks = {{x = 0, y = 0, r = -1}}}", "radius") ==
        "roger.shape: shape 'd' disk 1: radius must be at least 0.01 m, got -1");
  // Found by a probe: a list field took its positions 1..#t and dropped any other key unsaid (a
  // point without its list kept nothing 3 m away; a joint under a name was not locked).
  CHECK(run("world:robot{x = -1, y = 0} world:sample_position{radius = 0.2, away_from = {x = 1, y = 1, distance = 3}}",
            "away_one") == "world:sample_position: field 'away_from' must be a list {{x=, y=, distance=}, ...}, got the "
                           "key 'distance' (one point? write away_from = {{x = ..., y = ..., distance = ...}})");
  CHECK(run("world:robot{x = 0, y = 0, body = {locked = {'left_eye', right = 'right_eye'}}}", "locked_key") ==
        "world:robot: body: field 'locked' must be a list of joint names {\"left_elbow\", ...}, got the key 'right'");
  CHECK(run("roger.shape{name = 'd', disks = {x = 0.3, r = 0.1}}", "lone_disk") ==
        "roger.shape: field 'disks' must be a list of disks {{x=, y=, r=}, ...}, got the key 'r' (one disk? write "
        "disks = {{...}})");
  CHECK(run("roger.shape{name = 'd', disks = {{r = 0.1}, second = {r = 0.2}}}", "disk_key") ==
        "roger.shape: field 'disks' must be a list of disks {{x=, y=, r=}, ...}, got the key 'second'");
  CHECK(run("local tri = {{0, 0}, {0.2, 0}, {0, 0.2}} roger.shape{name = 'p', polygons = {tri, [3] = tri}}", "poly_hole") ==
        "roger.shape: field 'polygons' must be a list of polygons {p1, p2, ...}, got the key [3]");
  CHECK(run("roger.shape{name = 'p', polygons = {{{0, 0}, {0.2, 0}, {0, 0.2}, x = 1}}}", "vertex_key") ==
        "roger.shape: shape 'p' polygon 1 must be a list of {x, y} vertices, got the key 'x'");
  CHECK(run("roger.shape{name = 'p', polygons = {{{0, 0, 0}, {0.2, 0}, {0, 0.2}}}}", "vertex_z") ==
        "roger.shape: shape 'p' polygon 1 vertex 1 must be {x, y} (or {x = ..., y = ...}) and nothing else, got a "
        "table of 3 entries");
  CHECK(run("world:robot{x = 0, y = 0} world:sample_position{radius = 0.2, away_from = {{x = 1, y = 1, distance = -1}}}",
            "away_negative") == "world:sample_position: away_from[1]: field 'distance' must not be negative, got -1");
  CHECK(run("rng:int(5, 1)", "range") == "rng:int: the range 5..1 is empty");
  // Found by a probe: a reversed region blamed the arena ("leaves no room in a 4 x 4 m arena").
  CHECK(run("world:robot{x = 0, y = 0} world:sample_position{radius = 0.1, region = {xmin = 1, xmax = -1}}",
            "region_reversed") == "world:sample_position: region: xmin 1 is past xmax -1: the region holds no point");
  CHECK(run("rng:choice({})", "choice") == "rng:choice: the list is empty");
  // Found by a probe: rng:shuffle took a table of named entries unchanged, robot_distance a
  // negative distance, and an unnamed object whose default name was taken was said at a line
  // that names nothing; a mass of 1e-46 kg is 0 in the physics' single precision (fixed in place).
  CHECK(run("rng:shuffle({a = 1})", "shuffle_named") ==
        "rng:shuffle: expects a list {v1, v2, ...}, got a table whose entries are named (as 'a'): a table's entries "
        "have no order to shuffle; shuffle a list of its keys");
  CHECK(run("world:robot{x = 0, y = 0} world:sample_position{radius = 0.1, robot_distance = -1}", "robot_distance") ==
        "world:sample_position: field 'robot_distance' must not be negative");
  CHECK(run("world:robot{x = 0, y = 0} world:object{name = 'object 2', shape = shapes.get('circle'), x = 1, y = 1} "
            "world:object{shape = shapes.get('circle'), x = 1, y = -1}", "default_name") ==
        "world:object: there is already an object named 'object 2': this one is given no name, and its default name "
        "('object N' for the Nth object made) is taken; give it a 'name'");
  CHECK(run("world:robot{x = 0, y = 0} world:object{shape = shapes.get('circle'), x = 1, y = 1, mass = 1e-46}",
            "tiny_mass") == "world:object: field 'mass' must be within [0.001, 10000] kg, got 1e-46");
  // Found by a probe: setting a shape's field said "attempt to index a roger.Shape value".
  CHECK(run("local s = shapes.get('circle') s.name = 'ball'", "shape_set") ==
        "a shape cannot be changed (its 'name' was set): a shape is fixed once made; make another with "
        "roger.shape{...}, or a scaled copy with shape:scaled(k)");
  // Found by a probe: a table of named entries was "empty", and rng.uniform() "a no value".
  CHECK(run("rng:choice({a = 1})", "choice_named") ==
        "rng:choice: expects a list {v1, v2, ...}, got a table whose entries are named (as 'a'): draw from a list "
        "of its keys or values");
  CHECK(run("rng.uniform(0, 1)", "rng_dot") ==
        "rng:uniform: call it with a colon, as rng:uniform(...) (the first argument is a number, "
        "not the rng)");
  CHECK(run("rng.uniform()", "rng_dot_none") ==
        "rng:uniform: call it with a colon, as rng:uniform(...) (it was given no argument, not the rng)");
  CHECK(run("world:robot{x = 0, y = 0} world:robot{x = 1, y = 1}", "twice") ==
        "world:robot: Roger is already placed (call world:robot once)");
  CHECK(run("world:robot{x = 0, y = 0} world:object{name = 'a', shape = shapes.get('circle'), x = 1, y = 1} "
            "world:object{name = 'a', shape = shapes.get('circle'), x = -1, y = -1}", "dup") ==
        "world:object: there is already an object named 'a'");
  // Found by a probe: a name no picture could show passed roger check, and every render failed.
  CHECK(run("world:robot{x = 0, y = 0} world:object{name = 'bad\\255utf', shape = shapes.get('circle'), x = 1, y = 1}",
            "utf8") == "world:object: field 'name' must be UTF-8 text (records and pages show it): in 'bad\\xFFutf', "
                       "byte 0xff at byte 4 is not part of a UTF-8 character");
  const Vec2 hand = robot_footprint(RobotStart{}).at(1).center;  // left hand, robot at the origin
  CHECK_THAT(run("world:robot{x = 0, y = 0} world:obstacle{shape = shapes.box('b', 0.1, 0.1), x = " +
                     format_number(hand.x()) + ", y = " + format_number(hand.y()) + "}",
                 "hand"),
             StartsWith("world:obstacle: obstacle 'obstacle 1' at (") && Contains("overlaps Roger's left hand"));
  // Found by a probe: the only argument error that did not say what it got.
  CHECK(run("shapes.get('circle'):scaled(-1)", "negative") == "shape:scaled: the factor must be a positive number, got -1");
  CHECK(run("shapes.get('circle'):scaled('x')", "string") == "shape:scaled: the factor must be a positive number, got string");
  CHECK(run("world:robot{x = 0, y = 0} local s = shapes.get('circle') local t = s:scaled(2) "
            "assert(t.radius == 0.4 and s.radius == 0.2 and t.name == 'circle') "
            "local x, y = world:sample_position{shape = t} "
            "assert(rng:int(3) >= 1 and rng:uniform(2, 3) >= 2 and #rng:shuffle({1, 2, 3}) == 3) "
            // Found by a probe: the full range divided by zero (SIGFPE) through an overflow.
            "assert(math.type(rng:int(math.mininteger, math.maxinteger)) == 'integer') "
            "assert(rng:int(math.maxinteger - 1, math.maxinteger) >= math.maxinteger - 1) "
            "assert(rng:int(math.mininteger, math.mininteger + 1) <= math.mininteger + 1) "
            "assert(rng:int(-1, 0) <= 0) "
            // Found by a probe: a finite range wider than the largest double gave inf.
            "for i = 1, 100 do local u = rng:uniform(-1e308, 1e308) assert(u >= -1e308 and u < 1e308, u) end "
            "for i = 1, 100 do local u = rng:uniform(-1.7e308, 1.7e308) assert(u >= -1.7e308 and u < 1.7e308, u) end "
            "assert(rng:fork():uniform() < 1 and rng:angle() < math.pi and rng:normal(1, 0) == 1) "
            "local xmin, xmax = world:bounds() assert(xmin == -2 and xmax == 2) "
            "world:stimulus{colour = '#00ff00'} error('reached the end')", "ok") == "reached the end");
}

TEST_CASE("the stimulus colour defaults to the first object's colour", "[scenario]") {
  const std::string path = "/tmp/roger_api_stimulus.lua";
  FILE* f = std::fopen(path.c_str(), "w");
  std::fputs("local shapes = require('lib.shapes')\n"
             "return { params = { explicit = false }, generate = function(world, rng, p)\n"
             "  world:robot{x = -1, y = -1}\n"
             "  world:object{shape = shapes.get('triangle'), colour = {r = 10, g = 20, b = 30}, x = 1, y = 1}\n"
             "  if p.explicit then world:stimulus{colour = {1, 2, 3}} end\n"
             "end }\n", f);
  std::fclose(f);
  Scenario s = Scenario::load(path);
  std::remove(path.c_str());
  CHECK(s.name() == "roger_api_stimulus");
  CHECK(s.generate(0).stimulus_colour == Colour{10, 20, 30});
  s.set_param("explicit", "true");
  CHECK(s.generate(0).stimulus_colour == Colour{1, 2, 3});
  CHECK_THROWS_WITH(s.set_param("explicit", "maybe"), Contains("expects a boolean (true or false)"));
}

TEST_CASE("check_scenario accepts the shipped scenarios and the documented example",
          "[scenario]") {
  CHECK(check_scenario("unobstructed").empty());
  CHECK(check_scenario("cluttered").empty());
  CHECK(check_scenario("docs/examples/corridor.lua").empty());
  const auto problems = check_scenario("tests/scripts/bad_placement.lua", 2);
  REQUIRE(problems.size() == 2);  // one per distinct message: the seeds share the first
  CHECK_THAT(problems[0], StartsWith("seed 0: tests/scripts/bad_placement.lua:8: "));
  CHECK_THAT(problems[1], StartsWith("mode=robot, seed 0: tests/scripts/bad_placement.lua:11: "));
  const auto broken = check_scenario("tests/scripts/bad_syntax.lua");
  REQUIRE(broken.size() == 1);
  CHECK_THAT(broken[0], StartsWith("tests/scripts/bad_syntax.lua:5:"));
}

// Before, roger check tried every choice but no range's end: a world of 12 obstacles that had no
// room for the ninth passed the check and failed in training.
TEST_CASE("check_scenario tries each numeric range's ends and says which value failed", "[scenario]") {
  const std::string path = "/tmp/roger_check_ends.lua";
  std::ofstream(path) << "return {\n"
                         "  params = { boxes = { default = 2, min = 0, max = 9 }, gap = { default = 0.5, min = 0.25, max = 1.5 } },\n"
                         "  generate = function(world, rng, p)\n"
                         "    world:arena{ xmin = -1, xmax = 1, ymin = -1, ymax = 1 }\n"
                         "    world:robot{ x = 0, y = 0 }\n"
                         "    if p.boxes > 8 then error('no room for box ' .. p.boxes) end\n"
                         "  end,\n}\n";
  std::vector<std::string> ends;
  const auto problems = check_scenario(path, 2, {}, &ends);
  std::remove(path.c_str());
  CHECK(problems.empty());  // the defaults and the choices are sound
  REQUIRE(ends.size() == 1);  // boxes=0, gap=0.25 and gap=1.5 build
  CHECK_THAT(ends[0], StartsWith("boxes=9 (its max), seed 0: /tmp/roger_check_ends.lua:6: no room for box 9"));
  // Without the out-vector, the ends are not tried (as the curriculum's checks call it).
  CHECK(check_scenario("cluttered").empty());
  CHECK(numeric_ends(ScenarioParam{"n", ParamType::kInteger, "3", "3", "", {}, 0.5, 12.5}) ==
        std::vector<std::pair<std::string, std::string>>{{"1", "min"}, {"12", "max"}});
  // Found by a probe: two ends that fail in the same words were one warning (upper_arm=2 said
  // nothing and went uncounted beside forearm=2).
  Scenario alike = test::scenario_from("ends_alike", "return { params = { a = { default = 0.5, min = 0.1, max = 2 },\n"
                                                     "  b = { default = 0.5, min = 0.1, max = 2 } },\n"
                                                     "  generate = function(world, rng, p)\n"
                                                     "    if p.a > 1 or p.b > 1 then error('too big') end\n"
                                                     "    world:robot{ x = 0, y = 0 }\n  end }\n");
  std::vector<std::string> both;
  CHECK(check_scenario(alike, 1, &both).empty());
  REQUIRE(both.size() == 2);
  CHECK_THAT(both[0], StartsWith("a=2 (its max), seed 0: ") && Contains("too big"));
  CHECK_THAT(both[1], StartsWith("b=2 (its max), seed 0: ") && Contains("too big"));
}

// Found by a probe: roger check said "every parameter choice ... tried" and never built the false
// branch of a boolean switch, which then failed in a batch run.
TEST_CASE("check_scenario tries both values of a boolean parameter", "[scenario]") {
  for (const bool by_default : {true, false}) {
    const std::string value = by_default ? "true" : "false", other = by_default ? "false" : "true";
    Scenario s = test::scenario_from("switch", "return { params = { flag = " + value + ", n = 3 },\n"
                                               "  generate = function(world, rng, p)\n"
                                               "    if p.flag == " + other + " then error('this branch breaks') end\n"
                                               "    world:robot{ x = 0, y = 0 }\n  end }\n");
    const auto problems = check_scenario(s, 1);
    INFO(value);
    REQUIRE(problems.size() == 1);
    CHECK_THAT(problems[0], StartsWith("flag=" + other + ", seed 0: ") && Contains("this branch breaks"));
    CHECK(s.params().front().value == value);  // back at its value after
  }
}

// generate's params is a view that notes the names read (for roger check's warning about a
// parameter generate never reads): to the script it is still the table of the values in force.
TEST_CASE("generate's params reads, writes and walks as a table of the values in force", "[scenario]") {
  Scenario s = test::scenario_from("params_view", R"(return { params = { b = 2, a = "x", c = true },
  generate = function(world, rng, p)
    local keys = {}
    for k, v in pairs(p) do keys[#keys + 1] = k .. "=" .. tostring(v) end
    assert(table.concat(keys, " ") == "a=x b=2 c=true", table.concat(keys, " "))
    assert(rawget(p, "b") == 2 and rawget(p, "nope") == nil and #p == 0 and rawlen(p) == 0)
    assert(rawget(p, "b", "extra", 4) == 2 and select("#", rawget(p, "b", 1)) == 1)
    assert(type(p) == "table" and next(p) ~= nil)
    p.b = p.b + 1
    p.extra = 5
    assert(p.b == 3 and rawget(p, "b") == 3 and p.extra == 5)
    assert(rawset(p, "a", "y") == p)
    assert(p.a == "y" and rawget(p, "a") == "y")
    -- a raw write is a write of the table's: pairs and next see it too
    keys = {}
    for k, v in pairs(p) do keys[#keys + 1] = k .. "=" .. tostring(v) end
    assert(table.concat(keys, " ") == "a=y b=3 c=true extra=5", table.concat(keys, " "))
    p[1] = "first"
    assert(#p == 1 and rawlen(p) == 1)
    world:robot{ x = 0, y = 0 }
    local misspelt = p.bb
  end }
)");
  try {
    s.generate(0);
    FAIL("generate read an undeclared parameter without an error");
  } catch (const ScriptError& e) {
    CHECK(e.line == 21);
    CHECK_THAT(e.what(), Contains("the scenario has no parameter 'bb' (did you mean 'b'?); its parameters: a, b, c"));
  }
}

// Found by a probe: getmetatable(p).__index({}, "x") crashed roger (the metamethod took a table
// without the view's data for one), and so did the body metrics' __index called on a number.
// generate's params hide their metatable, as a teacher's history does; the metrics' refuses a
// number; and neither is followed on a value it was not made for.
TEST_CASE("a metamethod a script reaches and calls by hand is refused on another value", "[scenario]") {
  Scenario s = test::scenario_from("metamethods", R"(return { params = { b = 2 },
  generate = function(world, rng, p)
    assert(getmetatable(p) == "generate's params", tostring(getmetatable(p)))
    assert(not pcall(setmetatable, p, nil) and p.b == 2)
    local m = roger.body_metrics({})
    local ok, err = pcall(getmetatable(m).__index, 5, "x")
    assert(not ok and err:find("table expected, got number"), tostring(err))
    world:robot{ x = 0, y = 0 }
  end }
)");
  CHECK_NOTHROW(s.generate(0));
}

// Found by a probe: a scenario declared `clutter` and placed its obstacles from `obstacles`, and a
// sweep over clutter trained on the same worlds at every level. A name counts as read by an index,
// rawget (lib/place.lua tests declarations so), a pairs loop or next; one read only under another
// parameter's choice counts once check_scenario has tried that choice.
TEST_CASE("a scenario knows which of its parameters no generate has read", "[scenario]") {
  const std::string head = "return { params = { kind = { default = 'plain', choices = { 'plain', 'walled' } },\n"
                           "    size = 1, wall = 0.5, declared = 2, never = 3, also_never = 'x' },\n"
                           "  generate = function(world, rng, p)\n";
  Scenario s = test::scenario_from("unread", head +
                                                 "    local n = p.size + (rawget(p, 'declared') or 0)\n"
                                                 "    if p.kind == 'walled' then n = n + p.wall end\n"
                                                 "    world:robot{ x = 0, y = 0 }\n  end }\n");
  s.generate(0);
  CHECK(s.unread_params() == std::vector<std::string>{"also_never", "never", "wall"});
  CHECK(check_scenario(s, 2).empty());  // each choice of kind: walled reads wall
  CHECK(s.unread_params() == std::vector<std::string>{"also_never", "never"});
  // A loop over them all reads them all; next reads the key it gives.
  Scenario all = test::scenario_from("unread_pairs", head + "    for k, v in pairs(p) do end\n"
                                                            "    world:robot{ x = 0, y = 0 }\n  end }\n");
  all.generate(0);
  CHECK(all.unread_params().empty());
  Scenario first = test::scenario_from("unread_next", head + "    local k = next(p)\n"
                                                              "    world:robot{ x = 0, y = 0 }\n  end }\n");
  CHECK(first.unread_params().size() == 6);  // no generate yet: none read
  first.generate(0);
  CHECK(first.unread_params().size() == 5);
  // The shipped scenarios read every parameter they declare.
  for (const char* name : {"unobstructed", "cluttered", "sorting"}) {
    INFO(name);
    Scenario shipped = Scenario::load(name);
    for (int seed = 0; seed < 3; ++seed) shipped.generate(uint64_t(seed));
    check_scenario(shipped, 1);
    CHECK(shipped.unread_params().empty());
  }
}

TEST_CASE("generated worlds go through the physics without tripping Box2D", "[scenario]") {
  Scenario s = Scenario::load("cluttered");
  World world;
  for (const char* name : {"circle", "triangle", "pentagon", "spade"}) {
    s.set_param("shape", name);
    world.reset(s.generate(5));
    for (int i = 0; i < 10; ++i) world.tick();
    const Pose p = world.object_pose(0);
    CHECK(std::isfinite(p.x));
    CHECK(std::abs(p.x - world.spec().objects[0].pose.x) < 0.01);  // nothing pushed it
  }
}

TEST_CASE("an object with every field at its upper bound goes through the physics", "[scenario]") {
  Scenario s = Scenario::load("tests/scripts/bad_field.lua");
  s.set_param("mode", "heaviest");
  World world;
  world.reset(s.generate(0));
  for (int i = 0; i < 50; ++i) world.tick();
  const Pose p = world.object_pose(0);
  CHECK(std::abs(p.x - 1.0) < 1e-6);
  CHECK(std::abs(p.y - 1.0) < 1e-6);
}

TEST_CASE("every complete scenario in docs/scenarios.md loads and generates", "[scenario]") {
  std::ifstream in("docs/scenarios.md");
  REQUIRE(in);
  std::stringstream text;
  text << in.rdbuf();
  const std::string doc = text.str();
  int examples = 0;
  for (size_t start = doc.find("```lua\n"); start != std::string::npos;
       start = doc.find("```lua\n", start + 1)) {
    const size_t body = start + 7, end = doc.find("```", body);
    REQUIRE(end != std::string::npos);
    const std::string code = doc.substr(body, end - body);
    if (code.find("generate = function") == std::string::npos) continue;  // a fragment
    const std::string path = "/tmp/roger_doc_example_" + std::to_string(examples++) + ".lua";
    std::ofstream(path) << code;
    const auto problems = check_scenario(path, 20);
    std::remove(path.c_str());
    CHECK(problems == std::vector<std::string>{});
  }
  CHECK(examples == 4);  // the ball, a body of lib.body with its noise, the noise's kinds, the corridor
  // The long example is docs/examples/corridor.lua verbatim, after the file's header comment.
  std::ifstream file_in("docs/examples/corridor.lua");
  std::stringstream file;
  file << file_in.rdbuf();
  const std::string source = file.str();
  const std::string from_require = source.substr(source.find("local shapes"));
  CHECK(doc.find(from_require) != std::string::npos);
}

TEST_CASE("work done in C++ counts against the instruction budget", "[scenario]") {
  // Each call tests 1000 candidates in C++ for a handful of Lua instructions; without charging that
  // work the loop would run for minutes before the VM count caught up.
  const std::string path = "/tmp/roger_api_charge.lua";
  std::ofstream(path) << "return { generate = function(world, rng)\n"
                         "  world:robot{x = 0, y = 0}\n"
                         "  while true do\n"
                         "    pcall(world.sample_position, world, {radius = 0.2, robot_distance = 10})\n"
                         "  end\n"
                         "end }\n";
  Scenario s = Scenario::load(path, SandboxLimits{5'000'000, 64u << 20});
  std::remove(path.c_str());
  const auto start = std::chrono::steady_clock::now();
  const ScriptError e = generate_error(s);
  CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < 5.0);  // ~0.05 s in Release
  CHECK_THAT(e.message, Contains("instruction budget of 5000000 exceeded"));
  CHECK(e.file == "/tmp/roger_api_charge.lua");
  CHECK((e.line == 3 || e.line == 4));
}

TEST_CASE("world:sample_position draws a candidate's y, then its x, whatever the compiler", "[scenario]") {
  // Both used to be arguments of one call, whose evaluation order C++ leaves unspecified: gcc drew
  // y first and clang x, so every world (and result) depended on the compiler that built roger.
  const std::string path = "/tmp/roger_sample_order_" + std::to_string(::getpid()) + ".lua";
  std::ofstream(path) << "return { generate = function(world, rng, p)\n"
                         "  local x, y = world:sample_position{radius = 0.1, region = {xmin = -1, xmax = 1, ymin = 0.5, ymax = 1.5}}\n"
                         "  error(string.format('drawn %.17g %.17g', x, y))\n"
                         "end }\n";
  Scenario s = Scenario::load(path);
  std::remove(path.c_str());
  for (uint64_t seed : {1, 7, 12345}) {
    std::string message;
    try {
      s.generate(seed);
    } catch (const ScriptError& e) {
      message = e.message;
    }
    INFO(message);
    double x = 0, y = 0;
    REQUIRE(std::sscanf(message.substr(message.find("drawn")).c_str(), "drawn %lf %lf", &x, &y) == 2);
    Rng rng(seed);  // the generator's rng: its first two draws are the first candidate's
    const double first = rng.uniform(), second = rng.uniform();
    CHECK(y == Approx(0.5 + 1.0 * first).margin(1e-12));
    CHECK(x == Approx(-1.0 + 2.0 * second).margin(1e-12));
  }
}

TEST_CASE("a world with no place for a thing is a PlacementError; a script's own error is not", "[scenario]") {
  Scenario s = Scenario::load("cluttered");
  s.set_param("robot_distance", "3.5");  // farther than the 4 x 4 m arena holds
  std::string message;
  try {
    s.generate(1);
  } catch (const PlacementError& e) {
    message = e.what();
    CHECK_THAT(e.file, Catch::Matchers::EndsWith("lib/place.lua"));  // still a ScriptError at its line
    CHECK(e.line > 0);
  }
  CHECK_THAT(message, Catch::Matchers::Contains("no placement for 'circle' after 1000 tries"));
  // The next world that can be placed is built as before: the flag does not stick.
  s.set_param("robot_distance", "1.4");
  CHECK_NOTHROW(s.generate(1));
  // An error() of the script is a plain ScriptError.
  s.set_param("obstacle_min_size", "0.5");
  bool placement = false, script = false;
  try {
    s.generate(1);
  } catch (const PlacementError&) {
    placement = true;
  } catch (const ScriptError& e) {
    script = std::string(e.what()).find("exceeds obstacle_max_size") != std::string::npos;
  }
  CHECK_FALSE(placement);
  CHECK(script);
}

// Found by a probe: --set noise_joints_delay=30 --set noise_scale=2 was refused as "field 'delay'
// must be within [0, 50] ticks, got 60", naming neither parameter the user had set.
TEST_CASE("a noise level scaled past its range names the two scenario parameters that made it", "[scenario]") {
  Scenario s = Scenario::load("cluttered");
  s.set_param("noise_joints_delay", "30");
  s.set_param("noise_scale", "2");
  const ScriptError delay = generate_error(s);
  // At the scenario's line that placed Roger, not at lib/place.lua's that asked lib/body.lua, and
  // without the libraries' frames (found by a probe).
  CHECK_THAT(delay.file, Catch::Matchers::EndsWith("scenarios/cluttered.lua"));
  CHECK(delay.line == 41);
  CHECK_THAT(std::string(delay.what()), !Contains("stack traceback"));
  CHECK_THAT(delay.message, Contains("noise.joints: field 'delay' must be within [0, 50] ticks, got 60 (the scenario "
                                     "parameters noise_joints_delay = 30 times noise_scale = 2: lower either)"));
  s.set_param("noise_joints_delay", "0");
  s.set_param("noise_image_quantum", "200");
  const ScriptError quantum = generate_error(s);
  CHECK_THAT(quantum.message, Contains("noise.image: field 'quantum' must be within [0, 255] colour levels, got 400 "
                                       "(the scenario parameters noise_image_quantum = 200 times noise_scale = 2"));
  s.set_param("noise_image_quantum", "0");
  s.set_param("noise_base_drift", "0.75");
  CHECK_THAT(generate_error(s).message, Contains("noise.base: field 'drift.sigma' must be within [0, 1] m and rad, got 1.5 "
                                                 "(the scenario parameters noise_base_drift = 0.75 times noise_scale = 2"));
  // Within range once scaled: the world builds as before.
  s.set_param("noise_base_drift", "0.5");
  CHECK_NOTHROW(s.generate(0));
}

TEST_CASE("a level written out of range names no parameter and the drift's tau says its open range", "[scenario]") {
  const std::string dir = "/tmp/roger_test_scenario_tau_" + std::to_string(getpid());
  std::filesystem::create_directories(dir);
  auto robot_error = [&](const std::string& name, const std::string& robot) {
    const std::string path = dir + "/" + name + ".lua";
    std::ofstream(path) << "return { name = 't', generate = function(world, rng, params)\n"
                           "  world:robot" << robot << "\nend }\n";
    Scenario s = Scenario::load(path);
    return generate_error(s).message;
  };
  // Written in the script, no product of parameters: the message is ranged's own.
  const std::string written = robot_error("delay", "{ x = 0, y = 0, noise = { joints = { delay = 60 } } }");
  CHECK_THAT(written, EndsWith("field 'delay' must be within [0, 50] ticks, got 60"));
  // tau = 0 is refused with a drift ("must be positive"), so its range is (0, 3600], not [0, 3600].
  CHECK_THAT(robot_error("tau_high", "{ x = 0, y = 0, noise = { joints = { drift = { sigma = 0.01, tau = 4000 } } } }"),
             EndsWith("noise.joints.drift: field 'tau' must be within (0, 3600] s, got 4000"));
  CHECK_THAT(robot_error("tau_zero", "{ x = 0, y = 0, noise = { joints = { drift = { sigma = 0.01, tau = 0 } } } }"),
             EndsWith("field 'tau' must be within (0, 3600] s, got 0"));
  std::filesystem::remove_all(dir);
}

// Found by a probe: Lua drops extra arguments, so world:goal({x = 1, y = 0}, 5) read as a radius
// of 5 and made the default one. Every fixed-arity function now refuses more, at the caller's line.
TEST_CASE("the scenario API refuses extra arguments at the caller's line", "[scenario]") {
  auto run = [](const std::string& body) -> std::string {
    const std::string path = "/tmp/roger_arity_" + std::to_string(getpid()) + ".lua";
    std::ofstream(path) << "local shapes = require('lib.shapes')\nreturn { generate = function(world, rng)\n"
                        << body << "\nend }\n";
    Scenario s = Scenario::load(path);
    std::filesystem::remove(path);
    try {
      s.generate(0);
    } catch (const ScriptError& e) {
      CHECK(e.line == 3);
      return e.message;
    }
    return "no error";
  };
  const std::string circle = "shape = shapes.get('circle'), ";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"world:goal({x = 1, y = 0}, 5)", "world:goal: takes 1 argument (a table of fields), got 2"},
      {"roger.shape({disks = {{x = 0, y = 0, r = 1}}}, 2)", "roger.shape: takes 1 argument (a table of fields), got 2"},
      {"rng:int(1, 2, 3)", "rng:int: takes 1 or 2 arguments (n, or a and b), got 3"},
      {"rng:uniform(0, 1, 2)", "rng:uniform: takes no arguments or 2 (a, b), got 3"},
      {"rng:normal(0, 1, 2)", "rng:normal: takes at most 2 arguments (mu, sigma), got 3"},
      {"rng:angle(1)", "rng:angle: takes no arguments, got 1"},
      {"rng:choice({1}, 2)", "rng:choice: takes 1 argument (a list), got 2"},
      {"rng:shuffle({1}, 2)", "rng:shuffle: takes 1 argument (a list), got 2"},
      {"rng:fork(1)", "rng:fork: takes no arguments, got 1"},
      {"shapes.get('circle'):scaled(2, 'big', 3)", "shape:scaled: takes 1 or 2 arguments (factor [, name]), got 3"},
      {"world:arena({}, 1)", "world:arena: takes 1 argument (a table of fields), got 2"},
      {"world:bounds(1)", "world:bounds: takes no arguments, got 1"},
      {"world:robot({x = 0, y = 0}, 1)", "world:robot: takes 1 argument (a table of fields), got 2"},
      {"world:object({" + circle + "x = 1, y = 1}, 1)", "world:object: takes 1 argument (a table of fields), got 2"},
      {"world:obstacle({" + circle + "x = 1, y = 1}, 1)", "world:obstacle: takes 1 argument (a table of fields), got 2"},
      {"world:stimulus({colour = '#00ff00'}, 1)", "world:stimulus: takes 1 argument (a table of fields), got 2"},
      {"world:sample_position({radius = 0.1}, 1)",
       "world:sample_position: takes 1 argument (a table of fields), got 2"},
      {"roger.body_metrics({}, 1)", "roger.body_metrics: takes at most 1 argument (a table of fields), got 2"},
  };
  for (const auto& [call, says] : cases) {
    INFO(call);
    CHECK(run(call) == says);
  }
  // The same calls with the arguments they take.
  CHECK(run("world:arena({}) world:goal({x = 1, y = 0}) roger.shape({disks = {{x = 0, y = 0, r = 1}}}) rng:int(1, 2) rng:int(2) "
            "rng:uniform(0, 1) rng:uniform() rng:normal(0, 1) rng:normal() rng:angle() rng:choice({1}) "
            "rng:shuffle({1}) rng:fork() shapes.get('circle'):scaled(2, 'big') shapes.get('circle'):scaled(2) "
            "world:bounds() world:robot({x = 0, y = 0}) world:object({" + circle + "x = 1, y = 1}) "
            "world:obstacle({" + circle + "x = -1, y = -1}) world:stimulus({colour = '#00ff00'}) "
            "world:sample_position({radius = 0.1}) roger.body_metrics({}) roger.body_metrics() error('reached the end')") ==
        "reached the end");
}
