#include "control/planner.h"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <cstring>
#include <cmath>
#include <limits>

#include "control/planner_internal.h"
#include "core/error.h"

namespace roger {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The four neighbours of a padded index: the Laplacian's stencil and the flood fill's steps.
inline void neighbours(int k, int stride, int out[4]) {
  out[0] = k - 1, out[1] = k + 1, out[2] = k - stride, out[3] = k + stride;
}

// Young's optimal over-relaxation for a region whose largest inscribed disk has radius r cells.
// The slowest error mode of Jacobi on a region is about that of its largest open room, and a disk
// of radius r has Laplacian eigenvalue (2.405 / r)^2, so the Jacobi spectral radius is
// mu = 1 - lambda / 4 and omega = 2 / (1 + sqrt(1 - mu^2)). In the open 4 x 4 m arena (56 free
// cells across) this gives 1.89; among obstacles 1.7 to 1.8, where 1.9 would over-relax and take
// two to three times as many sweeps.
double young_omega(double r) {
  if (r <= 0.0) return 1.0;
  const double lambda = (2.405 / r) * (2.405 / r);
  const double mu = std::clamp(1.0 - lambda / 4.0, 0.0, 1.0);
  return 2.0 / (1.0 + std::sqrt(std::max(0.0, 1.0 - mu * mu)));
}

}  // namespace

HarmonicPlanner::HarmonicPlanner(const PlannerParams& params) : params_(params) {
  if (!(params_.omega > 0.0 && params_.omega < 2.0))
    throw Error("planner: omega must lie in (0, 2) for successive over-relaxation to converge");
  if (params_.max_sweeps < 1) throw Error("planner: max_sweeps must be at least 1");
  if (!(params_.tolerance > 0.0) || !std::isfinite(params_.tolerance))
    throw Error("planner: tolerance must be a positive number");
  if (params_.warm_smoothing < 0) throw Error("planner: warm_smoothing must not be negative");
}

void HarmonicPlanner::set_grid(const OccupancyGrid& grid) {
  if (grid.nx < 1 || grid.ny < 1 || grid.occupied.size() != size_t(grid.nx) * grid.ny ||
      !(grid.cell > 0.0) || !std::isfinite(grid.x0) || !std::isfinite(grid.y0))
    throw Error("planner: the occupancy grid is malformed (empty, cells missing, or no cell size)");
  if (has_grid_ && grid.nx == grid_.nx && grid.ny == grid_.ny && grid.x0 == grid_.x0 &&
      grid.y0 == grid_.y0 && grid.cell == grid_.cell && grid.occupied == grid_.occupied)
    return;
  // The same arena with some cells changed (an object moved, in or out of the grid): the last
  // solution, on the cells free in both, is a closer start than zeros for the next solve.
  const bool keep = params_.warm_start && have_values_ && has_grid_ && grid.nx == grid_.nx &&
                    grid.ny == grid_.ny && grid.x0 == grid_.x0 && grid.y0 == grid_.y0 && grid.cell == grid_.cell;
  if (keep) kept_.swap(q_);
  grid_ = grid;
  has_grid_ = true;
  // The arrays are rebuilt below: no reachability, no solution.
  flooded_ = solved_ = have_values_ = cold_.valid = false;
  backoffs_ = 0;
  rebuild_structure();
  find_goal_cells(pending_goal_);
  if (keep) {
    for (size_t k = 0; k < q_.size(); ++k) q_[k] = free_[k] ? kept_[k] : 0.0;
    have_values_ = true;
  }
}

void HarmonicPlanner::forget_solution() {
  solved_ = have_values_ = false;
  backoffs_ = 0;
}

void HarmonicPlanner::set_goal(const Vec2& center, double radius) {
  if (!center.allFinite() || !(radius >= 0.0) || !std::isfinite(radius))
    throw Error("planner: the goal needs a finite centre and a finite, non-negative radius");
  goal_center_ = center;
  goal_radius_ = radius;
  has_goal_ = true;
  find_goal_cells(pending_goal_);
  // Comparing cell sets, not centres, lets a goal that jitters within a cell cost nothing.
  if (pending_goal_ != goal_) flooded_ = solved_ = false;
}

// What every grid needs at once: the free cells and their components (reachability is a lookup in
// them). What only some queries need waits for its first use: the way out of occupied cells
// (ensure_exits) and what a solve starts from (ensure_solve_structure). A navigator that only
// reports its state, as most do while another moves, then pays for none of it when objects move.
void HarmonicPlanner::rebuild_structure() {
  const int nx = grid_.nx, ny = grid_.ny;
  stride_ = nx + 2;
  const size_t n = size_t(stride_) * (ny + 2);
  q_.assign(n, 0.0);
  dist_.assign(n, -1);
  free_.assign(n, 0);
  for (int j = 0; j < ny; ++j) {
    const uint8_t* occupied = grid_.occupied.data() + size_t(j) * nx;
    uint8_t* row = free_.data() + index(0, j);
    for (int i = 0; i < nx; ++i) row[i] = occupied[i] ? 0 : 1;
  }
  exits_ready_ = solve_structure_ready_ = false;

  // Connected components of the free cells (4-neighbourhood, as the Laplacian): reachability of
  // any goal is then a lookup, with no flood per goal change.
  label_components();
}

// Labels the components in two passes over the cells in index order: the first gives each free
// cell the provisional label of its left or lower neighbour (a new one when neither is free) and
// joins the two labels where both are (union-find on queue_); the second numbers each component
// where its first cell is, which is the numbering a breadth-first search from each unlabelled
// cell in index order gives. A search's neighbour tests branched unpredictably, in a third of
// the time a grid change costs.
void HarmonicPlanner::label_components() {
  const size_t n = free_.size();
  component_.assign(n, -1);
  component_size_.clear();
  queue_.resize(n);
  int* parent = queue_.data();
  auto root = [parent](int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];  // halving the path
    return a;
  };
  int* label = component_.data();
  int labels = 0;
  // The padding ring holds no free cell: the first and last rows are passed over.
  for (size_t k = size_t(stride_); k + size_t(stride_) < n; ++k) {
    if (!free_[k]) continue;
    const int left = label[k - 1], below = label[k - size_t(stride_)];
    if (left < 0 && below < 0) {
      parent[labels] = labels;
      label[k] = labels++;
    } else if (below < 0 || left == below) {
      label[k] = left;
    } else if (left < 0) {
      label[k] = below;
    } else {
      const int a = root(left), b = root(below);
      parent[std::max(a, b)] = std::min(a, b);
      label[k] = std::min(a, b);
    }
  }
  number_.assign(size_t(labels), -1);
  for (size_t k = 0; k < n; ++k) {
    if (label[k] < 0) continue;
    int& id = number_[size_t(root(label[k]))];
    if (id < 0) id = int(component_size_.size()), component_size_.push_back(0);
    label[k] = id;
    ++component_size_[size_t(id)];
  }
}

// Every occupied cell of the grid learns its nearest free cell (breadth first from all free cells
// at once) and the neighbour that leads there, so a robot standing in an inflated margin still gets
// a direction out of it. The padding ring stays unreachable. Built on first use after a grid
// change; the queries that read it are const, hence the mutable arrays.
void HarmonicPlanner::ensure_exits() const {
  if (exits_ready_) return;
  const int nx = grid_.nx, ny = grid_.ny;
  const size_t n = free_.size();
  nearest_.assign(n, -1);
  exit_.assign(n, -1);
  // The ring is marked -2 while the search runs, so one test (-1) tells a grid cell not yet found.
  for (int i = 0; i < stride_; ++i) nearest_[size_t(i)] = nearest_[n - 1 - size_t(i)] = -2;
  for (int j = 0; j < ny; ++j) nearest_[size_t(index(-1, j))] = nearest_[size_t(index(nx, j))] = -2;
  std::vector<int>& queue = queue_;  // scratch, shared with the components and the flood
  queue.resize(n);
  size_t tail = 0;
  for (int k = 0; k < int(n); ++k)
    if (free_[size_t(k)]) nearest_[size_t(k)] = exit_[size_t(k)] = k, queue[tail++] = k;
  for (size_t head = 0; head < tail; ++head) {
    const int k = queue[head];
    int nb[4];
    neighbours(k, stride_, nb);
    for (int m : nb) {
      if (nearest_[size_t(m)] != -1) continue;
      nearest_[size_t(m)] = nearest_[size_t(k)];
      exit_[size_t(m)] = k;
      queue[tail++] = m;
    }
  }
  for (int& v : nearest_)
    if (v == -2) v = -1;
  exits_ready_ = true;
}

// What flood_from_goal starts from, and the clearance that sizes omega: built before the first
// solve on a grid.
void HarmonicPlanner::ensure_solve_structure() {
  if (solve_structure_ready_) return;
  const int nx = grid_.nx, ny = grid_.ny;
  const size_t n = free_.size();
  // -1 on free cells, -2 elsewhere.
  unreached_.assign(n, -2);
  for (size_t k = 0; k < n; ++k)
    if (free_[k]) unreached_[k] = -1;

  // Distance from each cell centre to the nearest occupied centre, in cells (two-pass chamfer,
  // steps 1 and sqrt 2, within 8 %): its maximum over the relaxed cells sizes omega.
  clearance_.assign(n, 0.0f);
  const float diag = float(std::sqrt(2.0));
  for (size_t k = 0; k < n; ++k) clearance_[k] = free_[k] ? std::numeric_limits<float>::max() : 0.0f;
  // Each pass takes the row before it whole (a loop the compiler vectorizes), then the cell before
  // it along the row (the one serial chain); min is exact, so the order changes no bit.
  float* c = clearance_.data();
  for (int j = 1; j <= ny; ++j) {
    float* row = c + j * stride_;
    const float* before = row - stride_;
    for (int i = 1; i <= nx; ++i)
      row[i] = std::min(std::min(row[i], before[i] + 1.0f), std::min(before[i - 1] + diag, before[i + 1] + diag));
    for (int i = 1; i <= nx; ++i) row[i] = std::min(row[i], row[i - 1] + 1.0f);
  }
  for (int j = ny; j >= 1; --j) {
    float* row = c + j * stride_;
    const float* after = row + stride_;
    for (int i = nx; i >= 1; --i)
      row[i] = std::min(std::min(row[i], after[i] + 1.0f), std::min(after[i + 1] + diag, after[i - 1] + diag));
    for (int i = nx; i >= 1; --i) row[i] = std::min(row[i], row[i + 1] + 1.0f);
  }
  solve_structure_ready_ = true;
}

void HarmonicPlanner::find_goal_cells(std::vector<int>& out) const {
  out.clear();
  if (!has_grid_ || !has_goal_) return;
  const OccupancyGrid& g = grid_;
  const double r = goal_radius_;
  // Clamp in floating point first: a goal far outside the arena must not overflow an int.
  auto cell_index = [&](double v, double origin, int count) {
    return int(std::clamp(std::floor((v - origin) / g.cell), -1.0, double(count)));
  };
  const int i0 = std::max(0, cell_index(goal_center_.x() - r, g.x0, g.nx));
  const int i1 = std::min(g.nx - 1, cell_index(goal_center_.x() + r, g.x0, g.nx));
  const int j0 = std::max(0, cell_index(goal_center_.y() - r, g.y0, g.ny));
  const int j1 = std::min(g.ny - 1, cell_index(goal_center_.y() + r, g.y0, g.ny));
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i)
      if (!g.at(i, j) && (g.center(i, j) - goal_center_).norm() <= r) out.push_back(index(i, j));
  // Listed row by row, so already in index order; the centre's own cell joins in its place.
  int i, j;
  if (g.cell_of(goal_center_, i, j) && !g.at(i, j)) {
    const auto at = std::lower_bound(out.begin(), out.end(), index(i, j));
    if (at == out.end() || *at != index(i, j)) out.insert(at, index(i, j));
  }
}

bool HarmonicPlanner::update_reachability() {
  if (!has_grid_) return false;
  if (!flooded_) {
    goal_ = pending_goal_;
    // The goal's components, and whether any of them has a free cell outside the goal.
    goal_components_.clear();
    for (int k : goal_)
      if (std::find(goal_components_.begin(), goal_components_.end(), component_[k]) == goal_components_.end())
        goal_components_.push_back(component_[k]);
    int inside = 0;
    for (int c : goal_components_) inside += component_size_[size_t(c)];
    any_reachable_ = inside > int(goal_.size());
    flooded_ = true;
  }
  return any_reachable_;
}

bool HarmonicPlanner::update() {
  if (!update_reachability()) {
    solved_ = false;
    return false;
  }
  if (solved_) return true;
  // After a grid change the old values belong to other obstacles; start from zero then.
  const bool warm = params_.warm_start && have_values_;
  if (warm) {
    ensure_solve_structure();
    flood_from_goal();  // distances to the goal: which cells the solve relaxes
    solve(true);
  } else if (!reuse_cold_solve()) {
    ensure_solve_structure();
    flood_from_goal();
    const int backoffs_before = backoffs_;
    solve(false);
    remember_cold_solve(backoffs_before);
  }
  solved_ = have_values_ = true;
  return true;
}

// A cold solve is a function of the grid, the goal cells and what stalls taught about omega, and of
// nothing else: the same three give the same solution to the last bit. An episode forgets the
// solution of the one before (forget_solution), but a fixed goal region in a fixed arena asks
// for the same cold solve every episode; it is copied, not solved again.
bool HarmonicPlanner::reuse_cold_solve() {
  if (!cold_.valid || cold_.backoffs_before != backoffs_ || cold_.goal != goal_) return false;
  // What flood_from_goal would find again...
  dist_ = cold_.dist;
  relaxed_cells_ = cold_.relaxed_cells;
  any_reachable_ = cold_.any_reachable;
  // ...and what the solve would.
  q_ = cold_.q;
  sweeps_last_ = cold_.sweeps;
  converged_ = cold_.converged;
  omega_ = cold_.omega;
  backoffs_ = cold_.backoffs_after;
  ++solves_;
  ++reused_solves_;
  return true;
}

// Keeps the cold solve just made, for reuse_cold_solve.
void HarmonicPlanner::remember_cold_solve(int backoffs_before) {
  cold_.valid = true;
  cold_.goal = goal_;
  cold_.backoffs_before = backoffs_before;
  cold_.dist = dist_;
  cold_.relaxed_cells = relaxed_cells_;
  cold_.any_reachable = any_reachable_;
  cold_.q = q_;
  cold_.sweeps = sweeps_last_;
  cold_.converged = converged_;
  cold_.omega = omega_;
  cold_.backoffs_after = backoffs_;
}

void HarmonicPlanner::flood_from_goal() {
  // Breadth first from the goal over free cells, with the same 4-neighbourhood as the Laplacian:
  // a free cell the flood misses is walled off, its exact potential is 1 (q = 0), and it is held
  // there. Unreached free cells start at -1 and all others at -2, so one test tells a cell to
  // visit; the queue holds at most every free cell once (rebuild_structure sized it).
  dist_ = unreached_;
  int* queue = queue_.data();
  size_t tail = 0;
  for (int k : goal_) dist_[k] = 0, queue[tail++] = k;
  for (size_t head = 0; head < tail; ++head) {
    const int k = queue[head], next = dist_[k] + 1;
    int nb[4];
    neighbours(k, stride_, nb);
    for (int m : nb)
      if (dist_[m] == -1) dist_[m] = next, queue[tail++] = m;
  }
  any_reachable_ = tail > goal_.size();
}

void HarmonicPlanner::solve(bool warm) {
  const float widest = split_by_colour(warm);
  const double base = params_.auto_omega ? young_omega(widest) : params_.omega;
  omega_ = 1.0 + (base - 1.0) * std::pow(0.75, backoffs_);
  // If the count of unconverged cells stops falling for this long, over-relaxation is amplifying
  // rounding errors down a long corridor where q falls by decades (a red-black update there can
  // multiply a relative error by up to 2 omega - 1): relax less, here and for later solves.
  const int stall_window = 2 * (grid_.nx + grid_.ny);
  int sweeps = 0, fewest = INT_MAX, since_fewest = 0;
  converged_ = !any_reachable_;
  while (!converged_ && sweeps < params_.max_sweeps) {
    // A moved goal leaves a sharp local error; over-relaxed at once, it would ring across the
    // whole grid. A few plain Gauss-Seidel sweeps smooth it where it is first.
    const int unconverged =
        sweep(warm && sweeps < params_.warm_smoothing ? 1.0 : omega_, warm ? -1 : sweeps);
    ++sweeps;
    converged_ = unconverged == 0;
    if (unconverged < fewest) {
      fewest = unconverged, since_fewest = 0;
    } else if (++since_fewest >= stall_window && omega_ > 1.0) {
      ++backoffs_;
      omega_ = 1.0 + (omega_ - 1.0) * 0.75;
      fewest = INT_MAX, since_fewest = 0;
    }
  }
  join_colours();
  sweeps_last_ = sweeps;
  sweeps_total_ += sweeps;
  ++solves_;
}

// The sweep works on q split by colour (a checkerboard layout): row j of colour c holds, in order,
// the padded cells (i, j) with (i + j) % 2 == c, so that a half-sweep reads its four neighbours
// from contiguous rows of the other colour, and the kernel (planner_sweep.cpp) relaxes 2 to 8
// cells per instruction.
// Each row has a guard slot at both ends, so the shifted reads of its edge cells stay in bounds,
// and is a whole number of 64-byte lines wide, starting on a line (colour_base); guards and fixed
// cells are never relaxed. The sweep relaxes the cells the flood reached outside the goal; every
// other cell is fixed: goal cells at q = 1, obstacles, padding and walled-off cells at q = 0. A
// relaxed cell starts at 0 in a cold solve and at its value in q_ in a warm one.
// In the same pass: the relaxed cells' count, their widest clearance (returned, for omega) and
// the groups of slots that hold them (groups_).
float HarmonicPlanner::split_by_colour(bool warm) {
  const int rows = grid_.ny + 2;
  // A guard slot at each end, and the row a whole number of the widest kernel's lanes (a line).
  constexpr int pad = planner_internal::kRelaxLanes;
  split_width_ = ((stride_ + 1) / 2 + 2 + pad - 1) / pad * pad;
  // RelaxGroup::at is 32 bits, and its nearest 23: a flood distance is less than the free cells.
  if (int64_t(rows) * split_width_ > int64_t(INT32_MAX) - pad ||
      int64_t(grid_.nx) * grid_.ny > planner_internal::RelaxGroup::kMaxNearest)
    throw Error("planner: a grid of " + std::to_string(grid_.nx) + " x " + std::to_string(grid_.ny) +
                " cells is too large to solve");
  // The groups come in whole lanes of the kernel this processor runs.
  const int lanes = planner_internal::widest_relax_kernel().lanes;
  float widest = 0.0f;
  relaxed_cells_ = 0;
  for (int c = 0; c < 2; ++c) {
    colour_[c].assign(size_t(rows) * split_width_ + kAlignSlots, 0.0);
    groups_[c].clear();
  }
  slot_dist_.resize(size_t(split_width_));
  for (int j = 0; j < rows; ++j)
    for (int c = 0; c < 2; ++c) {
      // The cells of colour c in row j are every other one, from column (j + c) % 2.
      double* values = colour_base(c) + size_t(j) * split_width_ + 1;
      int first = 0, last = -1;
      std::fill(slot_dist_.begin(), slot_dist_.end(), INT_MAX);
      for (int i = (j + c) & 1, k = j * stride_ + i; i < stride_; i += 2, k += 2) {
        const int d = dist_[k];
        if (d <= 0) {
          values[i / 2] = d == 0 ? 1.0 : 0.0;
          continue;
        }
        values[i / 2] = warm ? q_[k] : 0.0;
        widest = std::max(widest, clearance_[k]);
        const int slot = 1 + i / 2;
        if (last < 0) first = slot;
        last = slot;
        slot_dist_[size_t(slot)] = d;
        ++relaxed_cells_;
      }
      if (last >= 0) add_relaxed_groups(j, c, first, last, lanes);
    }
  return widest;
}

// Records that row j of colour c relaxes cells in slots first..last (slot_dist_ holds their flood
// steps from the goal, INT_MAX elsewhere), as groups of `lanes` slots from the start of the
// 64-byte line that holds the first: a vector's loads of its own row and of the rows above and
// below then never straddle two cache lines (4 to 6% of the 8-object pipeline in roger bench).
// A group without a relaxed cell (inside an object's grown disk) is left out: relaxing it would
// change nothing. Each group's own nearest cell lets a cold solve's front pass over the groups it
// has not reached yet.
void HarmonicPlanner::add_relaxed_groups(int j, int c, int first, int last, int lanes) {
  const int shift = (j + c) & 1;
  for (int slot = first - first % planner_internal::kRelaxLanes; slot <= last; slot += lanes) {
    unsigned mask = 0;
    int nearest = INT_MAX;
    for (int m = 0; m < lanes; ++m) {
      const int d = slot_dist_[size_t(slot + m)];
      if (d == INT_MAX) continue;
      mask |= 1u << m;
      nearest = std::min(nearest, d);
    }
    if (mask == 0) continue;
    groups_[c].emplace_back(int32_t(j) * split_width_ + slot, nearest, shift, mask);
  }
}

// Writes the split values back into q_.
void HarmonicPlanner::join_colours() {
  const int rows = grid_.ny + 2;
  for (int j = 0; j < rows; ++j)
    for (int c = 0; c < 2; ++c) {
      const double* values = colour_base(c) + size_t(j) * split_width_ + 1;
      for (int i = (j + c) & 1, k = j * stride_ + i; i < stride_; i += 2, k += 2) q_[k] = values[i / 2];
    }
}

int HarmonicPlanner::sweep(double omega, int front) {
  // Red-black Gauss-Seidel: the cells of one colour depend only on the other colour, so a
  // half-sweep has no dependency from one cell to the next and its order does not matter.
  //
  // Convergence is judged relative to each cell's value, not absolutely: far from the goal q is
  // tiny and an absolute test would stop long before the direction there is right. A cell the
  // solve has not reached yet (q = 0, no change) fails the strict test, and so does a NaN.
  //
  // A cold solve (front: the sweeps made so far; -1 when warm) starts from zero everywhere but
  // the goal, and half-sweep h can carry a value only one step further from it: before it, every
  // cell more than h flood steps from the goal is still exactly 0, and a cell more than h + 1
  // steps away, all of whose neighbours are, would relax to exactly 0 again and stay unconverged.
  // Groups made only of such cells are passed over (they count as unconverged all the same).
  const planner_internal::RelaxHalfSweep half_sweep = planner_internal::widest_relax_kernel().half_sweep;
  int converged = 0;
  for (int c = 0; c < 2; ++c) {
    const int64_t reached = front < 0 ? int64_t(INT_MAX) : 2 * int64_t(front) + c + 1;
    converged += half_sweep(colour_base(c), colour_base(1 - c), split_width_, groups_[c].data(),
                            int(groups_[c].size()), reached, omega, params_.tolerance);
  }
  return relaxed_cells_ - converged;
}

double HarmonicPlanner::measure_residual() const {
  // Over the relaxed cells in memory order; the largest of a set does not depend on the order.
  double worst = 0.0;
  for (int k = 0; k < int(dist_.size()); ++k)
    if (dist_[k] > 0) {
      const double avg = 0.25 * (q_[k - 1] + q_[k + 1] + q_[k - stride_] + q_[k + stride_]);
      worst = std::max(worst, q_[k] > 0.0 ? std::fabs(q_[k] - avg) / q_[k] : kInf);
    }
  return worst;
}

bool HarmonicPlanner::locate(const Vec2& p, int& k) const {
  int i, j;
  if (!has_grid_ || !p.allFinite() || !grid_.cell_of(p, i, j)) return false;
  k = index(i, j);
  return true;
}

bool HarmonicPlanner::cell_reachable(int k) const {
  if (!flooded_) return false;
  if (!free_[k]) ensure_exits();
  const int cell = free_[k] ? k : nearest_[k];
  if (cell < 0) return false;
  return std::find(goal_components_.begin(), goal_components_.end(), component_[cell]) !=
         goal_components_.end();
}

bool HarmonicPlanner::reachable(const Vec2& p) const {
  int k;
  return locate(p, k) && cell_reachable(k);
}

bool HarmonicPlanner::at_goal(const Vec2& p) const {
  int k;
  return flooded_ && locate(p, k) && free_[k] && std::binary_search(goal_.begin(), goal_.end(), k);
}

Vec2 HarmonicPlanner::cell_gradient(int k) const {
  // Zero on the padding ring (no neighbours outside) and on goal cells: a goal cell's central
  // difference points away from its lower neighbours, which would set a false stop just outside a
  // goal in a corner. Obstacle cells keep theirs: it points out into the free space.
  const int i = k % stride_, j = k / stride_;
  if (i == 0 || j == 0 || i == stride_ - 1 || j == grid_.ny + 1 || dist_[k] == 0) return Vec2::Zero();
  return Vec2(q_[k + 1] - q_[k - 1], q_[k + stride_] - q_[k - stride_]) / (2.0 * grid_.cell);
}

double HarmonicPlanner::bilinear(const Vec2& p, Vec2* gradient) const {
  // Between the centres of the 2 x 2 cells around p; the padding ring covers the grid's edge.
  const double fx = (p.x() - grid_.x0) / grid_.cell - 0.5, fy = (p.y() - grid_.y0) / grid_.cell - 0.5;
  const int i = int(std::floor(fx)), j = int(std::floor(fy));
  const double tx = fx - i, ty = fy - j;
  const int k = index(i, j);
  const double w00 = (1.0 - tx) * (1.0 - ty), w10 = tx * (1.0 - ty), w01 = (1.0 - tx) * ty, w11 = tx * ty;
  if (gradient)
    *gradient = w00 * cell_gradient(k) + w10 * cell_gradient(k + 1) + w01 * cell_gradient(k + stride_) +
                w11 * cell_gradient(k + stride_ + 1);
  return w00 * q_[k] + w10 * q_[k + 1] + w01 * q_[k + stride_] + w11 * q_[k + stride_ + 1];
}

double HarmonicPlanner::complement(const Vec2& p) const {
  int k;
  if (!solved_ || !locate(p, k)) return 0.0;
  return bilinear(p, nullptr);
}

double HarmonicPlanner::potential(const Vec2& p) const { return 1.0 - complement(p); }

Vec2 HarmonicPlanner::descent(const Vec2& p) const {
  int k;
  if (!solved_ || !locate(p, k) || !cell_reachable(k) || (free_[k] && dist_[k] == 0)) return Vec2::Zero();
  // Descending u is ascending q = 1 - u. The gradient is taken by central differences at the four
  // cell centres around p and interpolated between them, so the direction turns smoothly as the
  // base drives on; the gradient of the bilinear potential itself would jump wherever p crosses
  // a row or column of centres, making the heading chatter along a wall. Differences of q keep
  // their relative precision however small q gets, so this only fails where q has no usable
  // digits left: all cells at zero (deep in an obstacle margin, or values that underflowed on a
  // huge grid) or an exact saddle.
  Vec2 gradient;
  const double value = bilinear(p, &gradient);
  const double norm = gradient.norm();
  if (norm * grid_.cell > 1e-9 * value) return gradient / norm;
  // There, head for a neighbouring cell one step nearer the goal by the flood fill (from a free
  // cell) or one step nearer the free space (from an occupied one); both always exist.
  int target = -1;
  if (free_[k]) {
    int nb[4];
    neighbours(k, stride_, nb);
    for (int m : nb)
      if (free_[m] && dist_[m] >= 0 && dist_[m] < dist_[k] && (target < 0 || q_[m] > q_[target]))
        target = m;
  } else {
    ensure_exits();
    target = exit_[k];
  }
  if (target < 0) return Vec2::Zero();
  const Vec2 to = grid_.center(target % stride_ - 1, target / stride_ - 1) - p;
  const double d = to.norm();
  return d > 0.0 ? Vec2(to / d) : Vec2::Zero();
}

std::vector<Vec2> HarmonicPlanner::trace(const Vec2& start, double step, int max_steps) const {
  std::vector<Vec2> path{start};
  if (!(step > 0.0)) return path;
  Vec2 p = start;
  for (int s = 0; s < max_steps && !at_goal(p); ++s) {
    const Vec2 d = descent(p);
    if (d.isZero()) break;
    p += step * d;
    path.push_back(p);
  }
  return path;
}

}  // namespace roger
