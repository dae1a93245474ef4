// Tests of engine/occupancy: rasterizing walls and obstacles for the planner.
#include <catch2/catch.hpp>

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
