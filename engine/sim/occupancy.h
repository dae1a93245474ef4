// occupancy.h: the arena as a grid of free and occupied cells (walls and static obstacles),
// 64 x 64 cells of 6.25 cm on the default arena. The harmonic-function planner solves on it.
#pragma once

#include <cstdint>
#include <vector>

#include "core/spec.h"

namespace roger {

// A row-major grid over the arena; cell (i, j) spans x0 + i*cell .. x0 + (i+1)*cell.
struct OccupancyGrid {
  int nx = 0, ny = 0;
  double x0 = 0.0, y0 = 0.0, cell = 0.0;
  std::vector<uint8_t> occupied;  // 1 where a wall or obstacle is, 0 where free

  // Whether cell (i, j) is occupied; cells outside the grid count as occupied.
  bool at(int i, int j) const {
    return i < 0 || j < 0 || i >= nx || j >= ny || occupied[size_t(j) * nx + i] != 0;
  }
  // Centre of cell (i, j), world frame.
  Vec2 center(int i, int j) const { return {x0 + (i + 0.5) * cell, y0 + (j + 0.5) * cell}; }
  // The cell holding a world point; false when the point is outside the grid.
  bool cell_of(const Vec2& p, int& i, int& j) const;
  // Number of occupied cells.
  int count() const;
};

// Rasterizes walls (the outer ring of cells) and obstacles grown by `inflate` metres: a cell is
// occupied when its centre lies within inflate + half a cell of a wall or an obstacle.
OccupancyGrid build_occupancy(const WorldSpec& spec, double inflate = 0.0);

}  // namespace roger
