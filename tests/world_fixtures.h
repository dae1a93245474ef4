// world_fixtures.h: small hand-made worlds for the engine's tests (no Lua involved).
#pragma once

#include <cmath>

#include "core/shape.h"
#include "core/spec.h"
#include "sim/world.h"

namespace roger::test {

// The paper's ball: a red disk of radius 0.2 m.
inline Shape ball_shape(double radius = 0.2) {
  Shape s;
  s.name = "circle";
  s.disks.push_back(Disk{Vec2::Zero(), radius});
  return s;
}

// An axis-aligned box centred on its origin.
inline Shape box_shape(double half_x, double half_y) {
  Shape s;
  s.name = "box";
  s.polygons.push_back(Polygon{{{-half_x, -half_y}, {half_x, -half_y}, {half_x, half_y}, {-half_x, half_y}}});
  return s;
}

// The default 4 x 4 m arena with Roger at the origin facing +x and optionally one ball.
inline WorldSpec open_world(bool with_ball = true, Vec2 ball = Vec2(1.5, 0.0)) {
  WorldSpec w;
  w.scenario = "test";
  if (with_ball) {
    ObjectSpec o;
    o.name = "ball";
    o.shape = ball_shape();
    o.pose = {ball.x(), ball.y(), 0.0};
    w.objects.push_back(o);
  }
  return w;
}

// Runs control ticks for `seconds` of simulated time.
inline void run_for(World& world, double seconds) {
  const int ticks = int(std::lround(seconds / world.tick_seconds()));
  for (int i = 0; i < ticks; ++i) world.tick();
}

// Angle between two vectors, in degrees.
inline double angle_between_deg(const Vec2& a, const Vec2& b) {
  const double c = a.normalized().dot(b.normalized());
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / M_PI;
}

}  // namespace roger::test
