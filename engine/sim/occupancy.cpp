#include "sim/occupancy.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/shape.h"

namespace roger {

bool OccupancyGrid::cell_of(const Vec2& p, int& i, int& j) const {
  i = int(std::floor((p.x() - x0) / cell));
  j = int(std::floor((p.y() - y0) / cell));
  return i >= 0 && j >= 0 && i < nx && j < ny;
}

int OccupancyGrid::count() const {
  return int(std::count(occupied.begin(), occupied.end(), uint8_t(1)));
}

OccupancyGrid build_occupancy(const WorldSpec& spec, double inflate) {
  const ArenaSpec& a = spec.arena;
  if (!(a.cell > 0.0) || !std::isfinite(a.cell))
    throw Error("arena: cell size must be a positive number of metres");
  OccupancyGrid g;
  g.cell = a.cell;
  g.x0 = a.xmin, g.y0 = a.ymin;
  g.nx = std::max(1, int(std::lround((a.xmax - a.xmin) / a.cell)));
  g.ny = std::max(1, int(std::lround((a.ymax - a.ymin) / a.cell)));
  if (double(g.nx) * g.ny > 16.0e6)
    throw Error("arena: the occupancy grid would have more than 16 million cells; use a larger cell");
  g.occupied.assign(size_t(g.nx) * g.ny, 0);
  const double reach = inflate + 0.5 * a.cell;
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const Vec2 c = g.center(i, j);
      const double wall = std::min({c.x() - a.xmin, a.xmax - c.x(), c.y() - a.ymin, a.ymax - c.y()});
      bool occ = i == 0 || j == 0 || i == g.nx - 1 || j == g.ny - 1 || wall <= reach;
      for (size_t k = 0; !occ && k < spec.obstacles.size(); ++k) {
        const ObstacleSpec& o = spec.obstacles[k];
        // Cheap rejection by bounding circle before the exact distance.
        const double far = std::hypot(c.x() - o.pose.x, c.y() - o.pose.y) - shape_bounding_radius(o.shape);
        if (far > reach) continue;
        occ = shape_signed_distance(o.shape, o.pose, c) <= reach;
      }
      g.occupied[size_t(j) * g.nx + i] = occ ? 1 : 0;
    }
  return g;
}

}  // namespace roger
