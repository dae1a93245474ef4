// scenario_geometry.cpp: gaps between placed shapes, how far a shape stays inside the arena, and
// Roger's footprint.
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/robot.h"
#include "core/shape.h"
#include "script/scenario/scenario_internal.h"
#include "sim/world.h"

namespace roger {
namespace scenario_detail {
namespace {

// One convex part of a shape in the world frame (polygons counter-clockwise, as validated).
struct Part {
  bool disk = true;
  Vec2 c = Vec2::Zero();
  double r = 0.0;
  std::vector<Vec2> v;
};

// The shape's parts moved to its pose.
std::vector<Part> placed_parts(const Shape& shape, const Pose& pose) {
  std::vector<Part> parts;
  for (const auto& d : shape.disks) parts.push_back(Part{true, to_world(pose, d.center), d.radius, {}});
  for (const auto& poly : shape.polygons) {
    Part p;
    p.disk = false;
    for (const auto& v : poly.vertices) p.v.push_back(to_world(pose, v));
    parts.push_back(std::move(p));
  }
  return parts;
}

// Distance from p to the segment ab.
double segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 e = b - a;
  const double t = std::clamp((p - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
  return (a + t * e - p).norm();
}

// Signed distance from a point to a convex counter-clockwise polygon (negative inside).
double polygon_signed_distance(const std::vector<Vec2>& v, const Vec2& p) {
  double outside = -std::numeric_limits<double>::infinity();
  double edge = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < v.size(); ++i) {
    const Vec2& a = v[i];
    const Vec2& b = v[(i + 1) % v.size()];
    const Vec2 e = b - a;
    outside = std::max(outside, Vec2(e.y(), -e.x()).dot(p - a) / e.norm());
    edge = std::min(edge, segment_distance(p, a, b));
  }
  return outside <= 0.0 ? outside : edge;
}

// Separating-axis gap of two convex polygons: positive distance when apart (vertex-edge minimum,
// exact for convex polygons), minus the penetration depth when they overlap.
double polygon_gap(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  double best = -std::numeric_limits<double>::infinity();
  for (const auto* poly : {&a, &b}) {
    for (size_t i = 0; i < poly->size(); ++i) {
      const Vec2 e = (*poly)[(i + 1) % poly->size()] - (*poly)[i];
      const Vec2 n = Vec2(e.y(), -e.x()).normalized();
      double amin = INFINITY, amax = -INFINITY, bmin = INFINITY, bmax = -INFINITY;
      for (const auto& p : a) amin = std::min(amin, n.dot(p)), amax = std::max(amax, n.dot(p));
      for (const auto& p : b) bmin = std::min(bmin, n.dot(p)), bmax = std::max(bmax, n.dot(p));
      best = std::max(best, std::max(bmin - amax, amin - bmax));
    }
  }
  if (best <= 0.0) return best;
  double d = INFINITY;
  for (size_t i = 0; i < b.size(); ++i)
    for (const auto& p : a) d = std::min(d, segment_distance(p, b[i], b[(i + 1) % b.size()]));
  for (size_t i = 0; i < a.size(); ++i)
    for (const auto& p : b) d = std::min(d, segment_distance(p, a[i], a[(i + 1) % a.size()]));
  return d;
}

// Gap between two convex parts (negative: penetration depth).
double part_gap(const Part& a, const Part& b) {
  if (a.disk && b.disk) return (a.c - b.c).norm() - a.r - b.r;
  if (a.disk) return polygon_signed_distance(b.v, a.c) - a.r;
  if (b.disk) return polygon_signed_distance(a.v, b.c) - b.r;
  return polygon_gap(a.v, b.v);
}

}  // namespace

// How far inside the arena walls the shape stays (negative: by how much it sticks out).
double arena_inset(const ArenaSpec& arena, const Shape& shape, const Pose& pose) {
  double inset = INFINITY;
  auto within = [&](const Vec2& p, double r) {
    inset = std::min({inset, p.x() - r - arena.xmin, arena.xmax - p.x() - r, p.y() - r - arena.ymin,
                      arena.ymax - p.y() - r});
  };
  for (const auto& part : placed_parts(shape, pose)) {
    if (part.disk) within(part.c, part.r);
    for (const auto& v : part.v) within(v, 0.0);
  }
  return inset;
}

// A one-disk shape, for Roger's base and hands and goal regions.
Shape disk_shape(const std::string& name, const Vec2& c, double r) {
  Shape s;
  s.name = name;
  s.disks.push_back(Disk{c, r});
  return s;
}

}  // namespace scenario_detail

using scenario_detail::disk_shape;
using scenario_detail::placed_parts;

double shape_gap(const Shape& a, const Pose& pa, const Shape& b, const Pose& pb) {
  double gap = INFINITY;
  const auto pb_parts = placed_parts(b, pb);
  for (const auto& p : placed_parts(a, pa))
    for (const auto& q : pb_parts) gap = std::min(gap, part_gap(p, q));
  return gap;
}

std::vector<Disk> robot_footprint(const RobotStart& start, const RobotParams& robot) {
  std::vector<Disk> disks{Disk{Vec2(start.pose.x, start.pose.y), robot.base_radius}};
  disks.push_back(Disk{arm_forward_kinematics(robot, start.pose, kLeft, start.left_shoulder,
                                              start.left_elbow).hand,
                       robot.hand_radius});
  disks.push_back(Disk{arm_forward_kinematics(robot, start.pose, kRight, start.right_shoulder,
                                              start.right_elbow).hand,
                       robot.hand_radius});
  return disks;
}

double robot_footprint_radius(const RobotParams& body) {
  double r = 0.0;
  for (const auto& d : robot_footprint(folded_start(body), body)) r = std::max(r, d.center.norm() + d.radius);
  return r;
}

}  // namespace roger
