#include "core/shape.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/error.h"

namespace roger {
namespace {

double cross(const Vec2& o, const Vec2& a, const Vec2& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

std::string where(const Shape& shape, const char* kind, size_t index) {
  std::ostringstream os;
  os << "shape '" << (shape.name.empty() ? "?" : shape.name) << "' " << kind << " " << index + 1;
  return os.str();
}

// Minimum edge length and area, a little above Box2D's own limits (b2_linearSlop = 5 mm) so a
// shape that passes here never trips b2PolygonShape::Set's asserts.
constexpr double kMinEdge = 0.01;
constexpr double kMinArea = 1e-4;

void validate_polygon(const Shape& shape, size_t index, Polygon& poly) {
  const auto& v = poly.vertices;
  const size_t n = v.size();
  if (n < 3 || n > size_t(kMaxPolygonVertices)) {
    std::ostringstream os;
    os << where(shape, "polygon", index) << ": expected 3 to " << kMaxPolygonVertices
       << " vertices, got " << n;
    throw Error(os.str());
  }
  for (size_t i = 0; i < n; ++i)
    if (!std::isfinite(v[i].x()) || !std::isfinite(v[i].y()))
      throw Error(where(shape, "polygon", index) + ": vertex " + std::to_string(i + 1) +
                  " is not a finite number");
  double area2 = 0.0;
  for (size_t i = 0; i < n; ++i) area2 += cross(Vec2::Zero(), v[i], v[(i + 1) % n]);
  if (std::abs(area2) * 0.5 < kMinArea) {
    // A bow tie's two halves cancel: its triangles have area, their signed sum none (found by a
    // probe: {0,0},{1,1},{1,0},{0,1} was blamed on collinear or repeated vertices).
    double unsigned2 = 0.0;
    for (size_t i = 1; i + 1 < n; ++i) unsigned2 += std::abs(cross(v[0], v[i], v[i + 1]));
    std::ostringstream os;
    os << where(shape, "polygon", index) << ": degenerate (area " << std::abs(area2) * 0.5 << " m^2; "
       << (unsigned2 * 0.5 >= kMinArea ? "its edges cross: list the vertices in order around the outline"
                                        : "collinear or repeated vertices?")
       << ")";
    throw Error(os.str());
  }
  if (area2 < 0) std::reverse(poly.vertices.begin(), poly.vertices.end());
  for (size_t i = 0; i < n; ++i) {
    const Vec2& a = v[i];
    const Vec2& b = v[(i + 1) % n];
    const Vec2& c = v[(i + 2) % n];
    if ((b - a).norm() < kMinEdge) {
      std::ostringstream os;
      os << where(shape, "polygon", index) << ": vertices " << i + 1 << " and " << (i + 1) % n + 1
         << " are closer than " << kMinEdge << " m";
      throw Error(os.str());
    }
    // Strict convexity with a tolerance relative to the edge lengths: collinear triples are
    // rejected because Box2D's hull would silently drop the middle point.
    const double turn = cross(a, b, c) / ((b - a).norm() * (c - b).norm());
    if (turn <= 1e-3) {
      std::ostringstream os;
      os << where(shape, "polygon", index) << ": vertices " << i + 1 << ", " << (i + 1) % n + 1
         << ", " << (i + 2) % n + 1
         << (std::abs(turn) <= 1e-3 ? " are collinear" : " make it non-convex")
         << " (a polygon must be convex; split a concave outline into convex parts)";
      throw Error(os.str());
    }
  }
}

}  // namespace

void validate_shape(Shape& shape) {
  if (shape.polygons.empty() && shape.disks.empty())
    throw Error("shape '" + shape.name + "' has no parts (give polygons or disks)");
  for (size_t i = 0; i < shape.polygons.size(); ++i) validate_polygon(shape, i, shape.polygons[i]);
  for (size_t i = 0; i < shape.disks.size(); ++i) {
    const Disk& d = shape.disks[i];
    if (!std::isfinite(d.center.x()) || !std::isfinite(d.center.y()) || !std::isfinite(d.radius))
      throw Error(where(shape, "disk", i) + ": not a finite number");
    if (d.radius < kMinEdge) {
      std::ostringstream os;
      os << where(shape, "disk", i) << ": radius must be at least " << kMinEdge << " m, got "
         << d.radius;
      throw Error(os.str());
    }
  }
}

double shape_area(const Shape& shape) {
  double area = 0.0;
  for (const auto& p : shape.polygons) {
    const size_t n = p.vertices.size();
    double a2 = 0.0;
    for (size_t i = 0; i < n; ++i) a2 += cross(Vec2::Zero(), p.vertices[i], p.vertices[(i + 1) % n]);
    area += std::abs(a2) * 0.5;
  }
  for (const auto& d : shape.disks) area += M_PI * d.radius * d.radius;
  return area;
}

double shape_bounding_radius(const Shape& shape) {
  double r = 0.0;
  for (const auto& p : shape.polygons)
    for (const auto& v : p.vertices) r = std::max(r, v.norm());
  for (const auto& d : shape.disks) r = std::max(r, d.center.norm() + d.radius);
  return r;
}

double shape_signed_distance(const Shape& shape, const Pose& pose, const Vec2& point) {
  const Vec2 p = to_local(pose, point);
  double best = std::numeric_limits<double>::infinity();
  for (const auto& d : shape.disks) best = std::min(best, (p - d.center).norm() - d.radius);
  for (const auto& poly : shape.polygons) {
    const auto& v = poly.vertices;
    const size_t n = v.size();
    double outside = -std::numeric_limits<double>::infinity();  // max signed edge distance
    double edge_dist = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < n; ++i) {
      const Vec2 a = v[i], b = v[(i + 1) % n];
      const Vec2 e = b - a;
      const Vec2 normal(e.y(), -e.x());  // outward for counter-clockwise order
      outside = std::max(outside, normal.dot(p - a) / e.norm());
      const double t = std::clamp((p - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
      edge_dist = std::min(edge_dist, (a + t * e - p).norm());
    }
    best = std::min(best, outside <= 0 ? outside : edge_dist);
  }
  return best;
}

double wrap_angle(double a) {
  if (a > -M_PI && a <= M_PI) return a;  // already principal: exactly itself, no rounding
  a = std::fmod(a + M_PI, 2.0 * M_PI);
  if (a <= 0) a += 2.0 * M_PI;
  return a - M_PI;
}

}  // namespace roger
