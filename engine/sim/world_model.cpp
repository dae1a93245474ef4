// world_model.cpp: deriving a world's immutable model from its spec, once per world.
#include "sim/world_model.h"

#include <cstring>

#include "core/error.h"
#include "core/shape.h"

namespace roger {

namespace {

// Whether two numbers have the same bits (a grid built from either would be the same).
bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same(const Vec2& a, const Vec2& b) { return same(a.x(), b.x()) && same(a.y(), b.y()); }

// Whether two shapes are the same to the bit.
bool same(const Shape& a, const Shape& b) {
  if (a.polygons.size() != b.polygons.size() || a.disks.size() != b.disks.size()) return false;
  for (size_t i = 0; i < a.polygons.size(); ++i) {
    const auto &u = a.polygons[i].vertices, &v = b.polygons[i].vertices;
    if (u.size() != v.size()) return false;
    for (size_t k = 0; k < u.size(); ++k)
      if (!same(u[k], v[k])) return false;
  }
  for (size_t i = 0; i < a.disks.size(); ++i)
    if (!same(a.disks[i].center, b.disks[i].center) || !same(a.disks[i].radius, b.disks[i].radius))
      return false;
  return true;
}

// Whether the occupancy grid of one world is that of the other: the same arena bounds and cell,
// and the same obstacles in the same places (all build_occupancy reads).
bool same_obstacles(const WorldSpec& a, const WorldSpec& b) {
  const ArenaSpec &p = a.arena, &q = b.arena;
  if (!same(p.xmin, q.xmin) || !same(p.xmax, q.xmax) || !same(p.ymin, q.ymin) ||
      !same(p.ymax, q.ymax) || !same(p.cell, q.cell) || a.obstacles.size() != b.obstacles.size())
    return false;
  for (size_t k = 0; k < a.obstacles.size(); ++k) {
    const Pose &u = a.obstacles[k].pose, &v = b.obstacles[k].pose;
    if (!same(u.x, v.x) || !same(u.y, v.y) || !same(u.theta, v.theta) ||
        !same(a.obstacles[k].shape, b.obstacles[k].shape))
      return false;
  }
  return true;
}

}  // namespace

void check_world_spec(WorldSpec& spec) {
  spec.robot.pose.theta = wrap_angle(spec.robot.pose.theta);
  for (auto& o : spec.objects) o.pose.theta = wrap_angle(o.pose.theta);
  for (auto& o : spec.obstacles) o.pose.theta = wrap_angle(o.pose.theta);
  for (auto& o : spec.objects) validate_shape(o.shape);
  for (auto& o : spec.obstacles) validate_shape(o.shape);
  const auto& a = spec.arena;
  if (!(a.xmax > a.xmin && a.ymax > a.ymin))
    throw Error("arena: xmax must exceed xmin and ymax exceed ymin");
  if (const auto problems = body_problems(spec.body, spec.eyes); !problems.empty())
    throw Error("Roger's body: " + problems.front());
}

void derive_world_model(const WorldSpec& spec_in, const WorldParams& params, double grid_inflate,
                        WorldModel& model) {
  WorldSpec spec = spec_in;
  check_world_spec(spec);
  const BodyMetrics body = body_metrics(spec.body, spec.eyes);
  const double inflate = grid_inflate >= 0.0 ? grid_inflate : body.grid_inflate;
  const bool keep_grid = model.grid.nx > 0 && same(inflate, model.grid_inflate) && same_obstacles(spec, model.spec);
  if (!keep_grid) {
    OccupancyGrid grid = build_occupancy(spec, inflate);
    model.grid = std::move(grid);
    model.grid_inflate = inflate;
  }
  model.spec = std::move(spec);
  model.params = params;
  model.body = body;
  model.camera = camera_of(model.spec.eyes);
  model.noise = noise_model(model.spec.noise, model.camera);
}

}  // namespace roger
