// Tests of engine/occupancy: rasterizing walls and obstacles for the planner.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "core/rng.h"
#include "core/shape.h"
#include "sim/occupancy.h"
#include "world_fixtures.h"

using namespace roger;
using namespace roger::test;

TEST_CASE("the default arena is a 64 x 64 grid walled on its border", "[occupancy]") {
  const OccupancyGrid g = build_occupancy(open_world(false));
  CHECK(g.nx == 64);
  CHECK(g.ny == 64);
  CHECK(g.cell == Approx(0.0625));
  CHECK(g.count() == 4 * 64 - 4);
  CHECK(g.at(0, 10));
  CHECK(g.at(63, 10));
  CHECK_FALSE(g.at(32, 32));
  CHECK(g.at(-1, 5));  // outside counts as occupied
  int i, j;
  REQUIRE(g.cell_of(Vec2(0.01, 0.01), i, j));
  CHECK(i == 32);
  CHECK(j == 32);
  CHECK_FALSE(g.cell_of(Vec2(2.5, 0.0), i, j));
}

TEST_CASE("obstacles occupy the cells they cover, grown by the inflation", "[occupancy]") {
  WorldSpec w = open_world(false);
  ObstacleSpec box;
  box.shape = box_shape(0.25, 0.25);
  box.pose = {1.0, -0.5, 0.0};
  w.obstacles.push_back(box);
  ObstacleSpec post;
  post.shape = ball_shape(0.15);
  post.pose = {-1.0, 1.0, 0.0};
  w.obstacles.push_back(post);
  const OccupancyGrid plain = build_occupancy(w);
  const OccupancyGrid grown = build_occupancy(w, 0.2);
  int i, j;
  REQUIRE(plain.cell_of(Vec2(1.0, -0.5), i, j));
  CHECK(plain.at(i, j));
  REQUIRE(plain.cell_of(Vec2(-1.0, 1.0), i, j));
  CHECK(plain.at(i, j));
  // Just outside the box: free in the plain grid, occupied once grown.
  REQUIRE(plain.cell_of(Vec2(1.4, -0.5), i, j));
  CHECK_FALSE(plain.at(i, j));
  CHECK(grown.at(i, j));
  // The box's area in cells is about right: 0.5 x 0.5 m is 64 cells of 6.25 cm, plus a rim.
  const int box_cells = plain.count() - (4 * 64 - 4);
  CHECK(box_cells > 64);
  CHECK(box_cells < 64 + 60 + 40);
  CHECK(grown.count() > plain.count());
}

TEST_CASE("arena size and cell size set the grid", "[occupancy]") {
  WorldSpec w = open_world(false);
  w.arena = ArenaSpec{-3.0, 3.0, -1.0, 1.0, 0.1, {}};
  const OccupancyGrid g = build_occupancy(w);
  CHECK(g.nx == 60);
  CHECK(g.ny == 20);
  w.arena.cell = 0.0;
  CHECK_THROWS_WITH(build_occupancy(w), Catch::Contains("cell size"));
}

namespace {

// The grid as build_occupancy made it before obstacles were culled by their bounding boxes: every
// cell against every obstacle, the bounding radius recomputed each time. Kept as the reference the
// fast build must match bit for bit.
OccupancyGrid reference_occupancy(const WorldSpec& spec, double inflate = 0.0) {
  const ArenaSpec& a = spec.arena;
  OccupancyGrid g;
  g.cell = a.cell;
  g.x0 = a.xmin, g.y0 = a.ymin;
  g.nx = std::max(1, int(std::lround((a.xmax - a.xmin) / a.cell)));
  g.ny = std::max(1, int(std::lround((a.ymax - a.ymin) / a.cell)));
  g.occupied.assign(size_t(g.nx) * g.ny, 0);
  const double reach = inflate + 0.5 * a.cell;
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const Vec2 c = g.center(i, j);
      const double wall = std::min({c.x() - a.xmin, a.xmax - c.x(), c.y() - a.ymin, a.ymax - c.y()});
      bool occ = i == 0 || j == 0 || i == g.nx - 1 || j == g.ny - 1 || wall <= reach;
      for (size_t k = 0; !occ && k < spec.obstacles.size(); ++k) {
        const ObstacleSpec& o = spec.obstacles[k];
        const double far = std::hypot(c.x() - o.pose.x, c.y() - o.pose.y) - shape_bounding_radius(o.shape);
        if (far > reach) continue;
        occ = shape_signed_distance(o.shape, o.pose, c) <= reach;
      }
      g.occupied[size_t(j) * g.nx + i] = occ ? 1 : 0;
    }
  return g;
}

// A convex polygon: n vertices on a circle of radius r about `centre`, at random angles in order
// (so some are long and thin), counter-clockwise.
Polygon random_polygon(Rng& rng, const Vec2& centre, double r) {
  const int n = int(rng.integer(3, kMaxPolygonVertices));
  std::vector<double> angles;
  for (int k = 0; k < n; ++k) angles.push_back(rng.uniform(0.0, 2.0 * M_PI));
  std::sort(angles.begin(), angles.end());
  Polygon p;
  for (double t : angles) p.vertices.push_back(centre + r * Vec2(std::cos(t), std::sin(t)));
  return p;
}

// A disk, a box, a random polygon, a compound of several parts (some off the shape's origin, so
// the bounding radius is well away from the parts), or a long thin wall.
Shape random_shape(Rng& rng, double size) {
  Shape s;
  s.name = "random";
  switch (rng.integer(0, 4)) {
    case 0: s.disks.push_back(Disk{Vec2::Zero(), rng.uniform(0.02, size)}); break;
    case 1: s = box_shape(rng.uniform(0.02, size), rng.uniform(0.02, size)); break;
    case 2: s.polygons.push_back(random_polygon(rng, Vec2::Zero(), rng.uniform(0.05, size))); break;
    case 3: {
      const int parts = int(rng.integer(2, 6));
      for (int k = 0; k < parts; ++k) {
        const Vec2 at(rng.uniform(-size, size), rng.uniform(-size, size));
        if (rng.uniform() < 0.5)
          s.disks.push_back(Disk{at, rng.uniform(0.02, 0.5 * size)});
        else
          s.polygons.push_back(random_polygon(rng, at, rng.uniform(0.05, 0.5 * size)));
      }
      break;
    }
    default: s = box_shape(rng.uniform(0.5, 4.0 * size), rng.uniform(0.01, 0.05)); break;
  }
  return s;
}

// An arena of random size, offset and cell (not always a power of two, nor dividing the arena),
// with many obstacles inside, straddling the walls, just outside and far outside.
WorldSpec random_cluttered_world(Rng& rng) {
  WorldSpec w = open_world(false);
  const double cell = rng.uniform() < 0.5 ? 0.0625 : rng.uniform(0.03, 0.2);
  const double xmin = rng.uniform(-6.0, 2.0), ymin = rng.uniform(-6.0, 2.0);
  w.arena.xmin = xmin, w.arena.xmax = xmin + rng.uniform(1.0, 8.0);
  w.arena.ymin = ymin, w.arena.ymax = ymin + rng.uniform(1.0, 8.0);
  w.arena.cell = cell;
  const ArenaSpec& a = w.arena;
  const int count = int(rng.integer(20, 120));
  for (int n = 0; n < count; ++n) {
    ObstacleSpec o;
    o.shape = random_shape(rng, rng.uniform(0.05, 0.6));
    double x = rng.uniform(a.xmin - 1.0, a.xmax + 1.0), y = rng.uniform(a.ymin - 1.0, a.ymax + 1.0);
    if (rng.uniform() < 0.2) x = rng.uniform() < 0.5 ? a.xmin + rng.uniform(-0.3, 0.3) : a.xmax + rng.uniform(-0.3, 0.3);
    if (rng.uniform() < 0.2) y = rng.uniform() < 0.5 ? a.ymin + rng.uniform(-0.3, 0.3) : a.ymax + rng.uniform(-0.3, 0.3);
    if (rng.uniform() < 0.03) x = rng.uniform(-1e6, 1e6);  // far away: touches nothing
    o.pose = {x, y, rng.uniform(-M_PI, M_PI)};
    w.obstacles.push_back(o);
  }
  return w;
}

// The probe's maze: up to 1000 posts 2 * `half` m across on a 1.8 m pitch from 3 m inside the
// corner of a `size` m square arena (64 m: 1024^2 cells of 6.25 cm).
WorldSpec post_maze(double size = 64.0, double half = 0.2) {
  WorldSpec w = open_world(false);
  w.arena.xmin = w.arena.ymin = -0.5 * size;
  w.arena.xmax = w.arena.ymax = 0.5 * size;
  const Shape post = box_shape(half, half);
  for (int i = 0; i < 32; ++i)
    for (int j = 0; j < 32 && w.obstacles.size() < 1000; ++j) {
      ObstacleSpec o;
      o.shape = post;
      o.pose = {w.arena.xmin + 3.0 + i * 1.8, w.arena.ymin + 3.0 + j * 1.8, 0.0};
      if (o.pose.x < w.arena.xmax && o.pose.y < w.arena.ymax) w.obstacles.push_back(o);
    }
  return w;
}

}  // namespace

TEST_CASE("the culled build is the per-cell reference to the bit on random cluttered worlds", "[occupancy]") {
  Rng rng(20240611);
  for (int trial = 0; trial < 60; ++trial) {
    const WorldSpec w = random_cluttered_world(rng);
    const double inflate = trial % 3 == 0 ? 0.0 : rng.uniform(0.0, 0.5);
    INFO("trial " << trial << ", " << w.obstacles.size() << " obstacles, cell " << w.arena.cell
                  << ", inflate " << inflate);
    const OccupancyGrid fast = build_occupancy(w, inflate), slow = reference_occupancy(w, inflate);
    REQUIRE(fast.nx == slow.nx);
    REQUIRE(fast.ny == slow.ny);
    CHECK(fast.occupied == slow.occupied);
    // Not a vacuous comparison: the obstacles do occupy cells beyond the walls.
    CHECK(slow.count() > 2 * (slow.nx + slow.ny));
  }
}

TEST_CASE("the culled build matches the reference at odd inflations and poses", "[occupancy]") {
  WorldSpec w = open_world(false);
  Rng rng(7);
  for (int n = 0; n < 40; ++n) {
    ObstacleSpec o;
    o.shape = random_shape(rng, 0.4);
    o.pose = {rng.uniform(-2.5, 2.5), rng.uniform(-2.5, 2.5), rng.uniform(-M_PI, M_PI)};
    w.obstacles.push_back(o);
  }
  // A negative inflation shrinks the reach below half a cell; a large one covers the arena.
  for (const double inflate : {-0.2, -0.03125, 0.0, 1e-12, 0.03125, 0.7, 3.0})
    CHECK(build_occupancy(w, inflate).occupied == reference_occupancy(w, inflate).occupied);
  // Unvalidated numbers: a NaN pose makes a polygon's signed distance -inf everywhere (the whole
  // grid occupied), and an infinite one nothing; neither may be culled differently.
  for (const double bad : {std::nan(""), HUGE_VAL, -HUGE_VAL}) {
    WorldSpec v = w;
    v.obstacles[3].pose.x = bad;
    v.obstacles[7].pose.y = bad;
    CHECK(build_occupancy(v).occupied == reference_occupancy(v).occupied);
    CHECK(build_occupancy(v, bad).occupied == reference_occupancy(v, bad).occupied);
  }
}

TEST_CASE("the culled build matches the reference on a maze of posts on grid lines", "[occupancy]") {
  // A 16 m corner of the probe's maze (the reference is too slow for all 64 m): posts whose edges
  // fall on cell boundaries and centres, where a cell centre is exactly at the reach.
  WorldSpec w = post_maze(16.0, 0.25);
  for (const double inflate : {0.0, 0.2, 0.25 - 0.5 * w.arena.cell})
    CHECK(build_occupancy(w, inflate).occupied == reference_occupancy(w, inflate).occupied);
}

TEST_CASE("a 1000-post 64 m arena builds well within a second", "[occupancy]") {
  // Was ~14 s when every cell visited every obstacle; now tens of milliseconds in Release. The
  // bound is loose so Debug and sanitizer builds pass too.
  const WorldSpec w = post_maze();
  const auto start = std::chrono::steady_clock::now();
  const OccupancyGrid g = build_occupancy(w, 0.2);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  CHECK(g.count() > 1000 * 36);
  CHECK(seconds < 1.0);
}
