// planner.h: the harmonic-function path planner behind phi1 (Connolly & Grupen). Laplace's equation
// is solved on the occupancy grid with obstacle and border cells held at 1 and goal cells at 0; the
// base descends the solution's gradient. A harmonic function has no local minima, so every descent
// from a cell joined to the goal ends in the goal, around obstacles and out of dead ends.
//
// Numerics, and why:
// - The potential is stored as its complement q = 1 - u (obstacles 0, goal 1). Far from the goal u
//   is 1 - 1e-12 or closer, where a double keeps no digits of the difference; q keeps full relative
//   precision down to 1e-308, so its differences, hence the direction, stay meaningful everywhere.
// - Red-black successive over-relaxation, converged when no cell changes by more than `tolerance`
//   of its own value in a sweep. An absolute test would stop long before the far field is right.
// - omega comes from the size of the free space (Young's formula): 1.89 in the open arena, 1.7 to
//   1.8 among obstacles, where a fixed 1.9 takes two to three times the sweeps. A solve that stalls
//   (over-relaxation amplifying rounding down a long corridor) lowers omega and carries on.
// - When only the goal moved, the solve starts from the previous solution. That saves only 15 to
//   25 % of the sweeps: a move of one cell changes q near the goal by tens of percent, and the
//   far field must converge to the same relative tolerance either way.
// - Reachability is an exact flood fill from the goal, so a walled-off goal is reported, not guessed.
//
// Cost, without changing a bit: the sweep relaxes 2, 4 or 8 cells per instruction (SSE2, AVX,
// AVX-512, chosen at run time; planner_sweep.cpp) over a flat list per colour of groups of lanes
// that hold relaxed cells, each group with its own mask and nearest cell (so no lane is read for a
// row's cells it does not hold, and a group's loads do not straddle a 64-byte line), and in a cold
// solve only the groups of rows its front from the goal can have reached. A cold solve of the
// goal solved last is copied. A grid change builds only what reachability needs; the ways out of
// occupied cells and what a solve starts from wait for the first query or solve that reads them
// (a navigator that only reports its state, as most do while objects move, never pays for them).
#pragma once

#include <cstdint>
#include <vector>

#include "control/planner_internal.h"
#include "sim/occupancy.h"
#include "core/spec.h"

namespace roger {

struct PlannerParams {
  double omega = 1.9;        // SOR over-relaxation factor in (0, 2), used when auto_omega is off
  bool auto_omega = true;    // pick omega from the size of the free space instead (Young's formula)
  int max_sweeps = 2000;     // a solve stops here even if not converged
  double tolerance = 1e-4;   // converged when no cell changes by this fraction of its value in a sweep
  bool warm_start = true;    // start from the previous solution when only the goal moved
  int warm_smoothing = 8;    // plain Gauss-Seidel sweeps (omega 1) that begin a warm-started solve
};

class HarmonicPlanner {
 public:
  // Checks the parameters; throws roger::Error on an omega outside (0, 2) or a non-positive limit.
  // The planner answers "unreachable" everywhere until set_grid, set_goal and update.
  explicit HarmonicPlanner(const PlannerParams& params = {});

  // Sets the obstacles; an identical grid changes nothing. Another grid of the same arena (objects
  // moved) keeps the solution on the cells free in both as the next solve's warm start; any other
  // discards it.
  void set_grid(const OccupancyGrid& grid);
  // Forgets the solution and what stalled solves taught about omega, keeping the grid's structure:
  // the next update() solves from scratch, exactly as a new planner on this grid would. For a new
  // episode, which must not depend on the episodes before it.
  void forget_solution();
  // Sets the goal: the free cells whose centre lies within radius of center, plus the free cell
  // holding center; a goal covering the same cells as before changes nothing.
  void set_goal(const Vec2& center, double radius);
  // Brings reachability up to date (component lookups, no flood, no solve): enough for reachable()
  // and at_goal(), so a controller can report its state without paying for a solve. Returns
  // whether some free cell outside the goal is joined to it.
  bool update_reachability();
  // Solves if the grid or the goal changed (from the previous solution when only the goal moved);
  // true when some free cell outside the goal is joined to it. Costs nothing when nothing changed.
  // The queries below answer for the most recent update().
  bool update();

  // Whether a free path of cells joins p's cell to a goal cell. A point inside an occupied cell
  // (the robot grazing an inflated margin) counts as being in the free cell nearest to it.
  bool reachable(const Vec2& p) const;
  // The harmonic potential u at p, bilinear between cell centres: 0 on the goal, 1 on obstacles.
  double potential(const Vec2& p) const;
  // 1 - potential(p) without the cancellation: keeps its precision far from the goal.
  double complement(const Vec2& p) const;
  // Unit direction of steepest descent of the potential at p (its gradient, interpolated between
  // cell centres); zero at the goal or when unreachable.
  Vec2 descent(const Vec2& p) const;
  // Whether p lies in a goal cell.
  bool at_goal(const Vec2& p) const;
  // Follows descent() from start in steps of `step` metres until the goal, a dead stop or
  // max_steps; returns the points visited, start first (for tests, pictures and debugging).
  std::vector<Vec2> trace(const Vec2& start, double step, int max_steps) const;

  // Sweeps made by the most recent solve (update() calls that had nothing to do are not solves;
  // a reused solve reports those of the solve it copied).
  int sweeps_last_solve() const { return sweeps_last_; }
  // Sweeps made since construction, over all solves (a reused solve makes none).
  long total_sweeps() const { return sweeps_total_; }
  // Number of solves since construction (reused ones included).
  int solves() const { return solves_; }
  // Cold solves answered by copying the last cold solve of the same goal on the same grid, which
  // it would have repeated to the last bit (each episode of a fixed goal region starts cold).
  int reused_solves() const { return reused_solves_; }
  // The over-relaxation factor of the most recent solve.
  double omega() const { return omega_; }
  // Whether the most recent solve met the tolerance within max_sweeps.
  bool converged() const { return converged_; }
  // Largest relative residual |q - mean of its 4 neighbours| / q over the cells of the last solve,
  // measured when asked (a solve does not pay for it; valid until the grid changes).
  double residual() const { return measure_residual(); }
  // Number of cells in the goal last set (0 before set_grid and set_goal, or when all are occupied).
  int goal_cells() const { return int(pending_goal_.size()); }
  // The grid in use.
  const OccupancyGrid& grid() const { return grid_; }
  // The parameters it was built with.
  const PlannerParams& params() const { return params_; }

 private:
  int index(int i, int j) const { return (j + 1) * stride_ + (i + 1); }  // padded index of cell (i, j)
  bool locate(const Vec2& p, int& k) const;  // padded index of p's cell; false outside the grid
  void rebuild_structure();                  // padding, free cells, components; after a grid change
  void label_components();                   // component_ and component_size_ from free_
  void ensure_exits() const;                 // nearest_ and exit_, on first use after a grid change
  void ensure_solve_structure();             // unreached_ and clearance_, before a solve
  void find_goal_cells(std::vector<int>& out) const;
  void flood_from_goal();                    // distances to the goal (dist_)
  void solve(bool warm);
  bool reuse_cold_solve();                   // the remembered cold solve, if it is this one
  void remember_cold_solve(int backoffs_before);
  // colour_, groups_ and relaxed_cells_; returns the widest relaxed cell's clearance
  float split_by_colour(bool warm);
  void add_relaxed_groups(int j, int c, int first, int last, int lanes);  // one row's groups
  void join_colours();                       // colour_ back into q_
  int sweep(double omega, int front);        // one red-black SOR sweep; returns unconverged cells
  double measure_residual() const;
  Vec2 cell_gradient(int k) const;           // gradient of q at a cell centre, central differences
  double bilinear(const Vec2& p, Vec2* gradient) const;  // q at p, and its interpolated gradient
  bool cell_reachable(int k) const;

  PlannerParams params_;
  OccupancyGrid grid_;
  bool has_grid_ = false, has_goal_ = false;
  Vec2 goal_center_ = Vec2::Zero();
  double goal_radius_ = 0.0;

  // Padded (nx + 2) x (ny + 2) arrays: a ring of occupied cells spares the sweep any bounds checks.
  int stride_ = 0;
  std::vector<double> q_;        // the complement potential, 1 - u
  std::vector<double> kept_;     // scratch: the solution across a change of grid
  std::vector<uint8_t> free_;    // 1 on free cells of the grid
  std::vector<int> dist_;        // steps to the goal through free cells; < 0 when not joined
  std::vector<int> unreached_;   // dist_ before a flood: -1 on free cells, -2 on the others
  // For occupied cells: the nearest free cell (-1: none), and the neighbour one step nearer to it.
  // Built lazily by const queries (ensure_exits), hence mutable.
  mutable std::vector<int> nearest_;
  mutable std::vector<int> exit_;
  mutable bool exits_ready_ = false;
  bool solve_structure_ready_ = false;   // unreached_ and clearance_ match the grid
  std::vector<float> clearance_; // distance in cells from each cell centre to the nearest occupied one
  int relaxed_cells_ = 0;        // cells the sweep relaxes (free, joined to the goal, not goal)
  std::vector<double> colour_[2];   // q_ split by colour during a solve (see split_by_colour)
  static constexpr int kAlignSlots = 8;  // spare slots, so the rows can start on a 64-byte line
  // Where colour c's slots begin: the first 64-byte boundary in colour_[c].
  double* colour_base(int c) {
    const auto at = reinterpret_cast<uintptr_t>(colour_[c].data());
    return colour_[c].data() + ((64 - at % 64) % 64) / sizeof(double);
  }
  int split_width_ = 0;             // slots per row of colour_
  // Per colour, the groups of slots the sweep relaxes, row by row (planner_sweep.cpp).
  std::vector<planner_internal::RelaxGroup> groups_[2];
  std::vector<int> slot_dist_;      // scratch: flood steps of the relaxed slots of one split row
  std::vector<int> goal_;        // sorted padded indices of the goal cells in force
  std::vector<int> pending_goal_;
  // Breadth-first scratch, kept to avoid allocating per change; ensure_exits (const) uses it too.
  mutable std::vector<int> queue_;
  std::vector<int> component_;   // connected component of each free cell (-1 elsewhere)
  std::vector<int> component_size_;   // cells per component
  std::vector<int> number_;           // scratch: each provisional label's component (label_components)
  std::vector<int> goal_components_;  // the components holding goal cells

  bool flooded_ = false;      // reachability (the flood from the goal) is up to date
  bool solved_ = false;       // the potential is solved for the current grid and goal
  bool have_values_ = false;  // q_ holds a solution for the current grid: warm starts may use it
  bool any_reachable_ = false;
  int sweeps_last_ = 0, solves_ = 0;
  long sweeps_total_ = 0;
  bool converged_ = false;
  double omega_ = 1.0;
  int backoffs_ = 0;             // times a stalled solve on this grid lowered omega
  int reused_solves_ = 0;

  // The last cold solve on this grid: its inputs beyond the grid, and everything it and the flood
  // before it produced.
  struct ColdSolve {
    bool valid = false;
    std::vector<int> goal;
    std::vector<int> dist;
    int relaxed_cells = 0;
    bool any_reachable = false;
    int backoffs_before = 0, backoffs_after = 0, sweeps = 0;
    std::vector<double> q;
    bool converged = false;
    double omega = 1.0;
  } cold_;
};

}  // namespace roger
