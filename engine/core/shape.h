// shape.h: validation and geometry of shapes (unions of convex polygons and disks).
// Box2D 2.4 asserts on degenerate polygons, so every shape from a script passes validate_shape()
// before any fixture is made from it.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

#include "core/spec.h"

namespace roger {

// Box2D's limit on polygon vertices (b2_maxPolygonVertices).
constexpr int kMaxPolygonVertices = 8;

// Checks a shape and puts each polygon in counter-clockwise order. Throws roger::Error naming the
// part and the problem (too few or many vertices, non-finite numbers, collinear or repeated points,
// a non-convex polygon, a tiny area, a non-positive radius, an empty shape).
void validate_shape(Shape& shape);

// Area of the union's parts, counted separately (overlaps count twice; used to spread mass).
double shape_area(const Shape& shape);

// Radius of the smallest origin-centred circle holding the shape.
double shape_bounding_radius(const Shape& shape);

// (cos theta, sin theta), the same bits as computing them afresh, remembered for the last angle
// asked on this thread: one control tick asks for the base's heading a dozen times (the eyes, the
// arms' kinematics, the percepts, every primitive), and a sine and cosine cost about a hundred
// instructions. Keyed by the angle's bits, so -0 and +0 (whose sines differ in sign) stay apart.
inline Vec2 heading_vector(double theta) {
  struct Memo {
    bool valid;
    uint64_t bits;
    double c, s;
  };
  thread_local Memo memo{false, 0, 0.0, 0.0};
  uint64_t bits;
  std::memcpy(&bits, &theta, sizeof bits);
  if (!memo.valid || memo.bits != bits) memo = {true, bits, std::cos(theta), std::sin(theta)};
  return {memo.c, memo.s};
}

// Transforms a point from a body frame (pose) to the world frame.
inline Vec2 to_world(const Pose& pose, const Vec2& p) {
  const Vec2 cs = heading_vector(pose.theta);
  const double c = cs.x(), s = cs.y();
  return {pose.x + c * p.x() - s * p.y(), pose.y + s * p.x() + c * p.y()};
}

// Transforms a world point into a body frame (pose).
inline Vec2 to_local(const Pose& pose, const Vec2& p) {
  const Vec2 cs = heading_vector(pose.theta);
  const double c = cs.x(), s = cs.y();
  const double dx = p.x() - pose.x, dy = p.y() - pose.y;
  return {c * dx + s * dy, -s * dx + c * dy};
}

// Distance from a world point to the shape placed at pose (negative inside).
double shape_signed_distance(const Shape& shape, const Pose& pose, const Vec2& point);

// Wraps an angle to (-pi, pi].
double wrap_angle(double a);

}  // namespace roger
