// scenario_purity.cpp: whether a scenario's generator is a function of its parameters and seed
// alone (Scenario::impurity, for roger check). A world is built from (scenario, parameters, seed)
// everywhere: training, evaluation, rendering and replay build the same seed at different times,
// after different worlds, so a generator that keeps state between calls (a counter in a global or
// an upvalue) makes a trial depend on which worlds came before it.
#include <cstdio>
#include <sstream>
#include <string>

#include "script/scenario/scenario.h"

namespace roger {
namespace {

// The numbers of a world a generator decides, as text at full precision: what differs between two
// builds of one seed shows here.
class Fingerprint {
 public:
  Fingerprint& operator<<(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g ", v);
    text_ += buf;
    return *this;
  }
  Fingerprint& operator<<(const std::string& s) {
    text_ += s + " ";
    return *this;
  }
  Fingerprint& operator<<(const Colour& c) { return *this << double(c.r) << double(c.g) << double(c.b); }
  Fingerprint& operator<<(const Pose& p) { return *this << p.x << p.y << p.theta; }
  Fingerprint& operator<<(const Shape& s) {
    *this << s.name;
    for (const Polygon& poly : s.polygons)
      for (const Vec2& v : poly.vertices) *this << v.x() << v.y();
    for (const Disk& d : s.disks) *this << d.center.x() << d.center.y() << d.radius;
    return *this;
  }
  const std::string& text() const { return text_; }

 private:
  std::string text_;
};

// Where the two builds of one seed part: the first field whose text differs.
std::string first_difference(const WorldSpec& a, const WorldSpec& b) {
  const auto part = [](const WorldSpec& w, int k) {
    Fingerprint f;
    switch (k) {
      case 0:
        f << w.arena.xmin << w.arena.xmax << w.arena.ymin << w.arena.ymax << w.arena.cell << w.arena.wall_colour;
        break;
      case 1:
        f << w.robot.pose << w.robot.left_shoulder << w.robot.left_elbow << w.robot.right_shoulder
          << w.robot.right_elbow << w.robot.left_eye << w.robot.right_eye << w.body.base_radius
          << w.body.link_length[0] << w.body.link_length[1] << w.body.hand_radius << double(w.body.locked)
          << double(w.eyes.pixels) << w.eyes.fov;
        break;
      case 2:
        for (const ObjectSpec& o : w.objects) f << o.name << o.shape << o.colour << o.pose << o.mass;
        break;
      case 3:
        for (const ObstacleSpec& o : w.obstacles) f << o.name << o.shape << o.colour << o.pose;
        break;
      case 4:
        for (const GoalRegion& g : w.goals) f << g.name << g.center.x() << g.center.y() << g.radius << g.colour;
        f << w.stimulus_colour;
        break;
    }
    return f.text();
  };
  static const char* const names[] = {"the arena", "Roger's start or body", "the objects", "the obstacles",
                                      "the goals or the stimulus colour"};
  for (int k = 0; k < 5; ++k)
    if (part(a, k) != part(b, k)) return names[k];
  return "";
}

}  // namespace

std::string Scenario::impurity(uint64_t seed) {
  const WorldSpec first = generate(seed);
  for (int again = 1; again <= 2; ++again) {
    const std::string differs = first_difference(first, generate(seed));
    if (!differs.empty())
      return "generate is not a function of its parameters and seed alone: world seed " + std::to_string(seed) +
             " built " + (again == 1 ? "again" : "a third time") + " right after differs in " + differs +
             ": a trial's worlds would depend on the worlds built before them (a global or an upvalue that "
             "generate changes is kept between calls); keep every value a world needs inside generate, drawn "
             "from its rng";
  }
  return "";
}

}  // namespace roger
