// Tests of engine/planner: the harmonic-function path planner behind phi1.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "core/error.h"
#include "sim/occupancy.h"
#include "control/planner.h"
#include "control/planner_internal.h"
#include "core/rng.h"
#include "world_fixtures.h"

using namespace roger;
using namespace roger::test;

namespace {

constexpr double kInflate = 0.2;  // the robot's clearance, as phi1 grows the grid
constexpr double kStep = 0.02;    // trace step: a third of a 6.25 cm cell

ObstacleSpec obstacle(const Shape& shape, double x, double y, double theta = 0.0) {
  ObstacleSpec o;
  o.shape = shape;
  o.pose = {x, y, theta};
  return o;
}

// The default arena with 3 to 8 boxes and disks at random.
WorldSpec random_world(Rng& rng) {
  WorldSpec w = open_world(false);
  const int count = int(rng.integer(3, 8));
  for (int n = 0; n < count; ++n) {
    const Shape shape = rng.uniform() < 0.5 ? box_shape(rng.uniform(0.1, 0.4), rng.uniform(0.1, 0.4))
                                            : ball_shape(rng.uniform(0.1, 0.3));
    w.obstacles.push_back(obstacle(shape, rng.uniform(-1.6, 1.6), rng.uniform(-1.6, 1.6), rng.uniform(0.0, 3.0)));
  }
  return w;
}

// A random point whose cell is free in the grid.
Vec2 free_point(Rng& rng, const OccupancyGrid& g) {
  for (;;) {
    const Vec2 p(rng.uniform(g.x0, g.x0 + g.nx * g.cell), rng.uniform(g.y0, g.y0 + g.ny * g.cell));
    int i, j;
    if (g.cell_of(p, i, j) && !g.at(i, j)) return p;
  }
}

bool occupied_at(const OccupancyGrid& g, const Vec2& p) {
  int i, j;
  return !g.cell_of(p, i, j) || g.at(i, j);
}

// The planner's Laplace problem solved the plain way, cell by cell, on the padded grid: goal cells
// held at q = 1, cells the flood from the goal misses at 0, red-black SOR on the rest until no
// cell changes by `tol` of its value; the first `smoothing` sweeps with omega 1. Starts from q
// (cold: empty), and returns the sweeps made.
struct ReferencePlan {
  const OccupancyGrid& g;
  int stride = g.nx + 2;
  std::vector<double> q = std::vector<double>(size_t(stride) * (g.ny + 2), 0.0);

  int solve(const Vec2& center, double radius, double omega, double tol, int smoothing) {
    const size_t n = q.size();
    std::vector<int> dist(n, -1), queue;
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i)
        if (!g.at(i, j) && (g.center(i, j) - center).norm() <= radius) queue.push_back(index(i, j));
    int ci, cj;
    if (g.cell_of(center, ci, cj) && !g.at(ci, cj) && dist[size_t(index(ci, cj))] < 0)
      queue.push_back(index(ci, cj));
    for (int k : queue) dist[size_t(k)] = 0;
    for (size_t head = 0; head < queue.size(); ++head)
      for (int m : {queue[head] - 1, queue[head] + 1, queue[head] - stride, queue[head] + stride}) {
        const int i = m % stride - 1, j = m / stride - 1;
        if (i < 0 || j < 0 || i >= g.nx || j >= g.ny || g.at(i, j) || dist[size_t(m)] >= 0) continue;
        dist[size_t(m)] = dist[size_t(queue[head])] + 1, queue.push_back(m);
      }
    for (size_t k = 0; k < n; ++k)
      if (dist[k] <= 0) q[k] = dist[k] == 0 ? 1.0 : 0.0;
    for (int sweeps = 1; sweeps <= 2000; ++sweeps) {
      const double w = sweeps <= smoothing ? 1.0 : omega;
      int unconverged = 0;
      for (int c = 0; c < 2; ++c)
        for (int j = 1; j <= g.ny; ++j)
          for (int i = 1; i <= g.nx; ++i) {
            const int k = j * stride + i;
            if ((i + j) % 2 != c || dist[size_t(k)] <= 0) continue;
            const double sum = q[size_t(k - 1)] + q[size_t(k + 1)] + q[size_t(k - stride)] + q[size_t(k + stride)];
            const double mean = 0.25 * sum, change = w * (mean - q[size_t(k)]);
            q[size_t(k)] += change;
            unconverged += !(std::fabs(change) < tol * q[size_t(k)]);
          }
      if (unconverged == 0) return sweeps;
    }
    return -1;
  }
  int index(int i, int j) const { return (j + 1) * stride + (i + 1); }
  // q at p between cell centres, as the planner interpolates it.
  double complement(const Vec2& p) const {
    const double fx = (p.x() - g.x0) / g.cell - 0.5, fy = (p.y() - g.y0) / g.cell - 0.5;
    const int i = int(std::floor(fx)), j = int(std::floor(fy));
    const double tx = fx - i, ty = fy - j;
    const size_t k = size_t(index(i, j));
    const double w00 = (1.0 - tx) * (1.0 - ty), w10 = tx * (1.0 - ty), w01 = (1.0 - tx) * ty, w11 = tx * ty;
    return w00 * q[k] + w10 * q[k + 1] + w01 * q[k + size_t(stride)] + w11 * q[k + size_t(stride) + 1];
  }
};

}  // namespace

TEST_CASE("descending the potential reaches the goal around random obstacles", "[planner]") {
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    Rng rng(seed);
    const WorldSpec world = random_world(rng);
    const OccupancyGrid plain = build_occupancy(world), grown = build_occupancy(world, kInflate);
    HarmonicPlanner planner;
    planner.set_grid(grown);
    Vec2 goal;
    do {
      goal = free_point(rng, grown);
      planner.set_goal(goal, 0.1);
    } while (!planner.update());
    REQUIRE(planner.converged());
    Vec2 start;
    do start = free_point(rng, grown);
    while (!planner.reachable(start) || (start - goal).norm() < 0.5);

    const std::vector<Vec2> path = planner.trace(start, kStep, 5000);
    INFO("seed " << seed << ": from (" << start.x() << ", " << start.y() << ") to (" << goal.x() << ", "
                 << goal.y() << "), " << path.size() << " points, omega " << planner.omega() << ", "
                 << planner.sweeps_last_solve() << " sweeps");
    CHECK(planner.at_goal(path.back()));
    int collisions = 0, rises = 0;
    for (size_t k = 0; k < path.size(); ++k) {
      collisions += occupied_at(plain, path[k]);
      // complement() is 1 - potential() without the rounding, so it must rise where u falls.
      if (k > 0 && !(planner.complement(path[k]) > planner.complement(path[k - 1]))) ++rises;
      if (k > 0 && planner.potential(path[k]) > planner.potential(path[k - 1])) ++rises;
    }
    CHECK(collisions == 0);
    CHECK(rises == 0);
  }
}

TEST_CASE("a goal walled in by a ring of obstacles is unreachable from outside", "[planner]") {
  // A closed square enclosure of four boxes around (0.8, 0.8): inner half-width 0.45 m.
  WorldSpec world = open_world(false);
  world.obstacles.push_back(obstacle(box_shape(0.55, 0.05), 0.8, 0.8 + 0.5));
  world.obstacles.push_back(obstacle(box_shape(0.55, 0.05), 0.8, 0.8 - 0.5));
  world.obstacles.push_back(obstacle(box_shape(0.05, 0.55), 0.8 + 0.5, 0.8));
  world.obstacles.push_back(obstacle(box_shape(0.05, 0.55), 0.8 - 0.5, 0.8));
  const OccupancyGrid grown = build_occupancy(world, kInflate);
  const Vec2 centre(0.8, 0.8), outside(-1.0, -1.0), margin(0.8, 0.8 - 0.55 - 0.12);
  REQUIRE(occupied_at(grown, margin));  // in the inflated rim, outside the ring

  HarmonicPlanner planner;
  planner.set_grid(grown);
  SECTION("the goal fills the enclosure: no cell outside the goal is joined to it") {
    planner.set_goal(centre, 0.5);
    CHECK(planner.goal_cells() > 0);
    CHECK_FALSE(planner.update());
  }
  SECTION("a small goal: reachable from inside only") {
    planner.set_goal(centre, 0.1);
    CHECK(planner.update());
    CHECK(planner.reachable(centre + Vec2(0.15, 0.1)));
    CHECK(planner.descent(centre + Vec2(0.15, 0.1)).norm() == Approx(1.0));
  }
  CHECK_FALSE(planner.reachable(outside));
  CHECK(planner.descent(outside) == Vec2::Zero());
  CHECK_FALSE(planner.reachable(margin));
  CHECK(planner.descent(margin) == Vec2::Zero());
  CHECK(planner.potential(outside) == 1.0);
  CHECK(planner.trace(outside, kStep, 100).size() == 1);
}

TEST_CASE("a goal inside an obstacle has no cells and is unreachable", "[planner]") {
  WorldSpec world = open_world(false);
  world.obstacles.push_back(obstacle(box_shape(0.4, 0.4), 0.0, 0.0));
  HarmonicPlanner planner;
  planner.set_grid(build_occupancy(world, kInflate));
  planner.set_goal(Vec2(0.0, 0.0), 0.1);
  CHECK(planner.goal_cells() == 0);
  CHECK_FALSE(planner.update());
  CHECK_FALSE(planner.reachable(Vec2(1.5, 1.5)));
  CHECK(planner.descent(Vec2(1.5, 1.5)) == Vec2::Zero());
}

TEST_CASE("reachability is the flood from the goal on grids of many components", "[planner]") {
  // The components are labelled row by row, joining labels where a cell's left and lower
  // neighbours both hold one. Random grids, half occupied (many components, and combs whose teeth
  // join only rows later), and a goal of one cell: every free cell must be reachable exactly
  // when a breadth-first flood from the goal finds it. Labels joined wrongly would join walled-off
  // parts or split one.
  Rng rng(23);
  for (int trial = 0; trial < 200; ++trial) {
    OccupancyGrid g;
    g.nx = 5 + int(rng.integer(0, 40)), g.ny = 5 + int(rng.integer(0, 40)), g.cell = 0.1;
    g.occupied.assign(size_t(g.nx) * g.ny, 0);
    const double density = rng.uniform(0.2, 0.6);
    for (auto& c : g.occupied) c = rng.uniform(0.0, 1.0) < density;
    if (trial % 4 == 0)  // a comb: teeth downwards from a full top row, joined at the top only
      for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) g.occupied[size_t(j) * g.nx + i] = j < g.ny - 1 && i % 2 == 1;
    int gi, gj;
    do gi = int(rng.integer(0, g.nx - 1)), gj = int(rng.integer(0, g.ny - 1));
    while (g.at(gi, gj));
    HarmonicPlanner planner;
    planner.set_grid(g);
    planner.set_goal(g.center(gi, gj), 0.0);
    std::vector<int> seen(g.occupied.size(), 0), queue{gj * g.nx + gi};
    seen[size_t(queue[0])] = 1;
    for (size_t head = 0; head < queue.size(); ++head) {
      const int i = queue[head] % g.nx, j = queue[head] / g.nx;
      const int next[4][2] = {{i - 1, j}, {i + 1, j}, {i, j - 1}, {i, j + 1}};
      for (const auto& n : next)
        if (!g.at(n[0], n[1]) && !seen[size_t(n[1] * g.nx + n[0])])
          seen[size_t(n[1] * g.nx + n[0])] = 1, queue.push_back(n[1] * g.nx + n[0]);
    }
    CHECK(planner.update_reachability() == (queue.size() > 1));
    int wrong = 0;
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i)
        if (!g.at(i, j)) wrong += planner.reachable(g.center(i, j)) != (seen[size_t(j * g.nx + i)] != 0);
    INFO("trial " << trial << ": " << g.nx << " x " << g.ny);
    CHECK(wrong == 0);
  }
}

TEST_CASE("a U-shaped trap between start and goal is routed around", "[planner]") {
  // The U opens towards -x; the start sits in its cavity, the goal straight behind its bottom, so
  // an attractive-repulsive field would hold the robot in the cavity.
  WorldSpec world = open_world(false);
  world.obstacles.push_back(obstacle(box_shape(0.1, 0.9), 0.3, 0.0));     // bottom of the U
  world.obstacles.push_back(obstacle(box_shape(0.55, 0.1), -0.25, 0.8));  // upper arm
  world.obstacles.push_back(obstacle(box_shape(0.55, 0.1), -0.25, -0.8)); // lower arm
  const OccupancyGrid plain = build_occupancy(world), grown = build_occupancy(world, kInflate);
  const Vec2 start(-0.2, 0.05), goal(1.3, 0.0);
  REQUIRE_FALSE(occupied_at(grown, start));

  HarmonicPlanner planner;
  planner.set_grid(grown);
  planner.set_goal(goal, 0.1);
  REQUIRE(planner.update());
  // At the start the way out is backwards, away from the goal.
  CHECK(planner.descent(start).x() < 0.0);
  const std::vector<Vec2> path = planner.trace(start, kStep, 5000);
  CHECK(planner.at_goal(path.back()));
  double leftmost = start.x();
  int collisions = 0;
  for (const Vec2& p : path) {
    leftmost = std::min(leftmost, p.x());
    collisions += occupied_at(plain, p);
  }
  CHECK(leftmost < -0.8);  // it left the cavity through the opening
  CHECK(collisions == 0);
}

TEST_CASE("deep in a long corridor the potential is 1 to the last bit, yet the way is found", "[planner]") {
  // A serpentine corridor two cells wide, carved by hand: the potential falls by about e^-pi/3
  // per cell along it, so 5 legs of 56 cells leave 1 - u near 1e-130 at the far end.
  OccupancyGrid g;
  g.nx = g.ny = 64;
  g.x0 = g.y0 = -2.0;
  g.cell = 0.0625;
  g.occupied.assign(64 * 64, 1);
  auto carve = [&](int i0, int i1, int j0, int j1) {
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) g.occupied[size_t(j) * 64 + i] = 0;
  };
  for (int leg = 0; leg < 5; ++leg) {
    const int j = 4 + 6 * leg;
    carve(4, 59, j, j + 1);
    if (leg < 4) {
      const int i = leg % 2 == 0 ? 58 : 4;  // the bend to the next leg, alternating ends
      carve(i, i + 1, j, j + 7);
    }
  }
  const Vec2 goal = g.center(4, 4), far_end = g.center(59, 28);

  HarmonicPlanner planner;
  planner.set_grid(g);
  planner.set_goal(goal, 0.0);
  REQUIRE(planner.update());
  CHECK(planner.converged());
  CHECK(planner.reachable(far_end));
  CHECK(planner.potential(far_end) == 1.0);  // the flat far field: u has no digits left
  CHECK(planner.complement(far_end) > 0.0);
  CHECK(planner.complement(far_end) < 1e-100);
  const std::vector<Vec2> path = planner.trace(far_end, kStep, 20000);
  CHECK(planner.at_goal(path.back()));
  int collisions = 0;
  for (const Vec2& p : path) collisions += occupied_at(g, p);
  CHECK(collisions == 0);
}

TEST_CASE("a robot in an inflated margin is led out of it", "[planner]") {
  WorldSpec world = open_world(false);
  world.obstacles.push_back(obstacle(ball_shape(0.3), 0.0, 0.0));
  const OccupancyGrid grown = build_occupancy(world, kInflate);
  HarmonicPlanner planner;
  planner.set_grid(grown);
  planner.set_goal(Vec2(1.5, 0.0), 0.1);
  REQUIRE(planner.update());
  // 0.42 m from the centre: clear of the disk, inside its 0.2 m margin, on the far side.
  const Vec2 p(-0.42, 0.0);
  REQUIRE(occupied_at(grown, p));
  CHECK(planner.reachable(p));
  const Vec2 d = planner.descent(p);
  CHECK(d.norm() == Approx(1.0));
  CHECK(d.x() < 0.0);  // out of the margin first, not through the disk
  CHECK(planner.at_goal(planner.trace(p, kStep, 5000).back()));
}

TEST_CASE("after grids come and go, the planner answers as a new one on the last grid", "[planner]") {
  // The ways out of occupied cells and what a solve starts from are built on first use after a
  // grid change: one left from an earlier grid would lead a robot in a margin the wrong way.
  Rng rng(31);
  WorldSpec world = open_world(false);
  world.obstacles.push_back(obstacle(ball_shape(0.3), 0.0, 0.0));
  const OccupancyGrid first = build_occupancy(world, kInflate);
  world.obstacles[0].pose = {0.9, -0.4, 0.0};
  world.obstacles.push_back(obstacle(box_shape(0.2, 0.6), -0.8, 0.7));
  const OccupancyGrid last = build_occupancy(world, kInflate);
  PlannerParams params;
  params.warm_start = false;  // a new planner starts cold: so must the used one, for equal bits
  HarmonicPlanner used(params), fresh(params);
  const Vec2 goal(1.6, 1.6);
  used.set_goal(goal, 0.2);
  fresh.set_goal(goal, 0.2);
  used.set_grid(first);
  REQUIRE(used.update());
  // Queries on the first grid build its exits (a point in the first disk's margin)...
  CHECK(used.reachable(Vec2(-0.42, 0.0)));
  CHECK(used.descent(Vec2(-0.42, 0.0)).x() < 0.0);
  // ...then the grid changes twice, the second time with nothing but reachability asked.
  used.set_grid(last);
  used.update_reachability();
  CHECK(used.reachable(Vec2(0.9 - 0.42, -0.4)));
  used.set_grid(first);
  used.set_grid(last);
  fresh.set_grid(last);
  REQUIRE(used.update());
  REQUIRE(fresh.update());
  for (int n = 0; n < 400; ++n) {
    // Half the points in occupied cells, where the exits decide.
    Vec2 p;
    do p = Vec2(rng.uniform(-1.95, 1.95), rng.uniform(-1.95, 1.95));
    while (n % 2 == 0 && !occupied_at(last, p));
    INFO("point (" << p.x() << ", " << p.y() << ")");
    CHECK(used.reachable(p) == fresh.reachable(p));
    const Vec2 a = used.descent(p), b = fresh.descent(p);
    CHECK(std::memcmp(a.data(), b.data(), sizeof(double) * 2) == 0);
    const double qa = used.complement(p), qb = fresh.complement(p);
    CHECK(std::memcmp(&qa, &qb, sizeof qa) == 0);
  }
  CHECK(used.sweeps_last_solve() == fresh.sweeps_last_solve());
}

TEST_CASE("a moved goal is solved from the previous solution", "[planner]") {
  // Warm and cold planners track the same goal as it steps one cell at a time.
  long warm_sweeps = 0, cold_sweeps = 0;
  for (uint64_t seed = 100; seed < 110; ++seed) {
    Rng rng(seed);
    const OccupancyGrid grown = build_occupancy(random_world(rng), kInflate);
    PlannerParams cold_params;
    cold_params.warm_start = false;
    HarmonicPlanner warm, cold(cold_params);
    warm.set_grid(grown);
    cold.set_grid(grown);
    Vec2 goal;
    do {
      goal = free_point(rng, grown);
      warm.set_goal(goal, 0.1);
    } while (!warm.update() || occupied_at(grown, goal + Vec2(grown.cell, 0.0)));
    goal.x() += grown.cell;
    warm.set_goal(goal, 0.1);
    cold.set_goal(goal, 0.1);
    warm.update();
    cold.update();
    INFO("seed " << seed);
    CHECK(warm.converged());
    warm_sweeps += warm.sweeps_last_solve();
    cold_sweeps += cold.sweeps_last_solve();
    // Both reach the same field, to within the tolerance's reach.
    double worst = 0.0;
    for (int j = 0; j < grown.ny; ++j)
      for (int i = 0; i < grown.nx; ++i) {
        const double a = warm.complement(grown.center(i, j)), b = cold.complement(grown.center(i, j));
        if (b > 0.0) worst = std::max(worst, std::abs(a - b) / b);
      }
    CHECK(worst < 1e-2);
  }
  INFO("sweeps after a one-cell move: warm " << warm_sweeps << ", cold " << cold_sweeps);
  CHECK(warm_sweeps < 0.9 * cold_sweeps);
}

TEST_CASE("nothing changed means no work", "[planner]") {
  Rng rng(7);
  const OccupancyGrid grown = build_occupancy(random_world(rng), kInflate);
  HarmonicPlanner planner;
  CHECK_FALSE(planner.update());  // no grid yet
  planner.set_grid(grown);
  planner.set_goal(Vec2(-1.5, -1.5), 0.1);
  planner.update();
  REQUIRE(planner.solves() == 1);
  const long sweeps = planner.total_sweeps();
  CHECK(sweeps > 0);
  const bool reachable = planner.update();
  CHECK(planner.update() == reachable);
  CHECK(planner.total_sweeps() == sweeps);

  // The same goal again, or one that moves within the same cells: no solve.
  planner.set_goal(Vec2(-1.5, -1.5), 0.1);
  planner.set_goal(Vec2(-1.5 + 0.001, -1.5), 0.1 + 0.001);
  planner.update();
  CHECK(planner.solves() == 1);

  // An identical grid is not a new grid.
  const OccupancyGrid copy = grown;
  planner.set_grid(copy);
  planner.update();
  CHECK(planner.solves() == 1);
  CHECK(planner.total_sweeps() == sweeps);

  // A different grid is, and starts from zero.
  OccupancyGrid changed = grown;
  *std::find(changed.occupied.begin(), changed.occupied.end(), uint8_t(0)) = 1;
  planner.set_grid(changed);
  planner.update();
  CHECK(planner.solves() == 2);
}

TEST_CASE("a cold solve of the same goal on the same grid is reused, to the last bit", "[planner]") {
  Rng rng(11);
  const OccupancyGrid grown = build_occupancy(random_world(rng), kInflate);
  // What a new planner computes for each of two goals.
  auto fresh = [&](const Vec2& goal) {
    HarmonicPlanner p;
    p.set_grid(grown);
    p.set_goal(goal, 0.3);
    p.update();
    return p;
  };
  const Vec2 goal_a(-1.5, -1.5), goal_b(1.4, 1.2);
  const HarmonicPlanner ref_a = fresh(goal_a), ref_b = fresh(goal_b);
  auto same_as = [&](const HarmonicPlanner& p, const HarmonicPlanner& ref) {
    Rng probe(3);
    for (int t = 0; t < 200; ++t) {
      const Vec2 x(probe.uniform(-1.9, 1.9), probe.uniform(-1.9, 1.9));
      if (p.complement(x) != ref.complement(x) || p.descent(x) != ref.descent(x) ||
          p.reachable(x) != ref.reachable(x))
        return false;
    }
    return p.omega() == ref.omega() && p.sweeps_last_solve() == ref.sweeps_last_solve();
  };

  HarmonicPlanner planner;
  planner.set_grid(grown);
  planner.set_goal(goal_a, 0.3);
  planner.update();
  const long sweeps = planner.total_sweeps();
  // A new episode: the solution is forgotten, and the same cold solve is copied, not redone.
  planner.forget_solution();
  planner.update();
  CHECK(planner.reused_solves() == 1);
  CHECK(planner.total_sweeps() == sweeps);
  CHECK(same_as(planner, ref_a));
  // Another goal after forgetting is solved, not copied.
  planner.forget_solution();
  planner.set_goal(goal_b, 0.3);
  planner.update();
  CHECK(planner.reused_solves() == 1);
  CHECK(planner.total_sweeps() > sweeps);
  CHECK(same_as(planner, ref_b));
  // A warm solve (goal moved without forgetting) is never a copy of a cold one.
  planner.set_goal(goal_a, 0.3);
  planner.update();
  CHECK(planner.reused_solves() == 1);
  // A changed grid forgets the remembered solve.
  OccupancyGrid changed = grown;
  *std::find(changed.occupied.begin(), changed.occupied.end(), uint8_t(0)) = 1;
  planner.set_grid(changed);
  planner.set_goal(goal_b, 0.3);
  planner.update();
  CHECK(planner.reused_solves() == 1);
}

TEST_CASE("the planner's solves are the plain red-black relaxation to the last bit", "[planner]") {
  // The sweep passes over fixed slots, and a cold solve over rows its front cannot have reached:
  // neither may change a bit of the potential or the count of sweeps, cold or warm.
  Rng rng(21);
  for (int world = 0; world < 4; ++world) {
    const WorldSpec w = world == 0 ? open_world(false) : random_world(rng);
    const OccupancyGrid g = build_occupancy(w, kInflate);
    PlannerParams params;
    params.tolerance = 2e-3;  // as phi1 plans
    HarmonicPlanner planner(params);
    planner.set_grid(g);
    ReferencePlan reference{g};
    for (int goal = 0; goal < 3; ++goal) {
      const Vec2 center = free_point(rng, g);
      const double radius = rng.uniform(0.1, 0.6);
      planner.set_goal(center, radius);
      if (!planner.update()) continue;
      INFO("world " << world << ", goal " << goal << (goal ? " (warm)" : " (cold)"));
      REQUIRE(planner.converged());
      const int sweeps = reference.solve(center, radius, planner.omega(), params.tolerance,
                                         goal ? params.warm_smoothing : 0);
      CHECK(planner.sweeps_last_solve() == sweeps);
      for (int k = 0; k < 200; ++k) {
        const Vec2 p = free_point(rng, g);
        const double expected = reference.complement(p), got = planner.complement(p);
        if (std::memcmp(&expected, &got, sizeof got) != 0) FAIL("q differs at (" << p.x() << ", " << p.y() << ")");
      }
    }
  }
  SUCCEED();
}

namespace {

// The groups of `lanes` slots that cover `count` slots of one split row from slot `at`, as the
// planner makes them: each with its mask of relaxed slots (kept even when empty, which relaxes
// nothing) and `nearest`.
std::vector<planner_internal::RelaxGroup> groups_of(int lanes, int at, int count, int shift, int nearest,
                                                    const std::vector<bool>& relaxed) {
  std::vector<planner_internal::RelaxGroup> groups;
  for (int m = 0; m < count; m += lanes) {
    unsigned mask = 0;
    for (int k = 0; k < lanes; ++k)
      if (relaxed[size_t(at + m + k)]) mask |= 1u << k;
    groups.emplace_back(at + m, nearest, shift, mask);
  }
  return groups;
}

}  // namespace

TEST_CASE("a half-sweep's groups give the same bits in any order, and those past the front none", "[planner]") {
  // The cells of a half-sweep depend only on the other colour, so the planner may list its groups
  // in any order; a group whose nearest cell lies past `reached` is passed over: its cells keep
  // their values and do not count as converged. Through every width this processor runs.
  using namespace planner_internal;
  Rng rng(11);
  for (int lanes : {2, 4, 8}) {
    const RelaxHalfSweep kernel = relax_kernel(lanes);
    if (!kernel) continue;
    const int count = 5 * lanes, width = count + 2 * kRelaxLanes, rows = 4;
    std::vector<double> q(size_t(width * rows)), other(q.size());
    for (size_t k = 0; k < q.size(); ++k) q[k] = rng.uniform(0.5, 1.0), other[k] = rng.uniform(0.5, 1.0);
    const std::vector<bool> all(q.size(), true);
    std::vector<RelaxGroup> near = groups_of(lanes, width + kRelaxLanes, count, 1, 2, all);
    const std::vector<RelaxGroup> far = groups_of(lanes, 2 * width + kRelaxLanes, count, 0, 7, all);
    std::vector<RelaxGroup> both = near;
    both.insert(both.end(), far.begin(), far.end());
    std::vector<double> q_near = q, q_both = q, q_reversed = q;
    const int c_near = kernel(q_near.data(), other.data(), width, near.data(), int(near.size()), 5, 1.9, 0.5);
    const int c_both = kernel(q_both.data(), other.data(), width, both.data(), int(both.size()), 5, 1.9, 0.5);
    std::reverse(both.begin(), both.end());
    const int c_reversed = kernel(q_reversed.data(), other.data(), width, both.data(), int(both.size()), 5, 1.9, 0.5);
    CHECK(c_near > 0);  // the tolerance is wide: some cells converge
    CHECK(c_both == c_near);
    CHECK(c_reversed == c_near);
    CHECK(std::memcmp(q_both.data(), q_near.data(), sizeof(double) * q.size()) == 0);
    CHECK(std::memcmp(q_reversed.data(), q_near.data(), sizeof(double) * q.size()) == 0);
    CHECK(std::memcmp(q_near.data(), q.data(), sizeof(double) * q.size()) != 0);  // it did relax
    // With the front past both rows, the far row relaxes too.
    std::vector<double> q_all = q;
    kernel(q_all.data(), other.data(), width, both.data(), int(both.size()), 7, 1.9, 0.5);
    CHECK(std::memcmp(q_all.data() + 2 * width, q.data() + 2 * width, sizeof(double) * width) != 0);
  }
}

TEST_CASE("every width of the relaxation kernel gives the same bits", "[planner]") {
  // Rows of a half-sweep with values over many decades, down to subnormal ones (as q is far from
  // the goal; only there is a quarter of a sum inexact), fixed and relaxed cells mixed, against
  // the 2-lane kernel every processor runs and the scalar relaxation: a wider kernel that fused
  // the multiply into the subtraction, or lost a lane, would differ in some bit or some count.
  using namespace planner_internal;
  Rng rng(7);
  const int count = 8 * kRelaxLanes, width = count + 2, rows = 4;
  int widths_run = 0;
  for (int lanes : {4, 8}) {
    const RelaxHalfSweep wide = relax_kernel(lanes);
    if (!wide) continue;  // this processor lacks the instruction set
    ++widths_run;
    for (int trial = 0; trial < 200; ++trial) {
      // One row in three lies wholly in the subnormal range, where a quarter of a sum rounds.
      const double deepest = trial % 3 ? 300.0 : 322.0, shallowest = trial % 3 ? 0.0 : 308.0;
      auto value = [&] { return std::pow(10.0, -rng.uniform(shallowest, deepest)) * rng.uniform(0.5, 1.0); };
      std::vector<double> q(size_t(width * rows)), other(q.size());
      std::vector<bool> is_relaxed(q.size());
      for (size_t k = 0; k < q.size(); ++k) {
        q[k] = value(), other[k] = value();
        is_relaxed[k] = rng.uniform(0.0, 1.0) < 0.8;
      }
      // Rows 1 and 2, with both shifts; row 2 is passed over when its nearest cell is too far.
      struct Row {
        int at, shift, count, nearest;
      };
      const Row row_list[2] = {{width + 1, trial % 2, count, 3},
                               {2 * width + 1, 1 - trial % 2, count - lanes, trial % 4 < 2 ? 4 : 9}};
      auto groups = [&](int group_lanes) {
        std::vector<RelaxGroup> out;
        for (const Row& r : row_list) {
          const std::vector<RelaxGroup> g = groups_of(group_lanes, r.at, r.count, r.shift, r.nearest, is_relaxed);
          out.insert(out.end(), g.begin(), g.end());
        }
        return out;
      };
      const std::vector<RelaxGroup> groups2 = groups(2), groups_wide = groups(lanes);
      const double omega = rng.uniform(1.0, 1.95), tol = trial % 2 ? 2e-3 : 1e-300;
      std::vector<double> q2 = q, qw = q;
      const int c2 = relax_kernel(2)(q2.data(), other.data(), width, groups2.data(), int(groups2.size()), 5, omega, tol);
      const int cw = wide(qw.data(), other.data(), width, groups_wide.data(), int(groups_wide.size()), 5, omega, tol);
      CHECK(cw == c2);
      CHECK(std::memcmp(q2.data(), qw.data(), sizeof(double) * q2.size()) == 0);
      // And the 2-lane kernel is the scalar relaxation, operation for operation.
      std::vector<double> expected = q;
      int converged = 0;
      for (const Row& r : row_list) {
        if (r.nearest > 5) continue;
        for (int m = 0; m < r.count; ++m) {
          const int64_t k = r.at + m;
          if (!is_relaxed[size_t(k)]) continue;
          const int64_t l = k + r.shift - 1;
          const double sum = other[size_t(l)] + other[size_t(l + 1)] + other[size_t(k - width)] + other[size_t(k + width)];
          const double v = q[size_t(k)], mean = 0.25 * sum, change = omega * (mean - v);
          expected[size_t(k)] = v + change;
          converged += std::fabs(change) < tol * expected[size_t(k)];
        }
      }
      CHECK(c2 == converged);
      CHECK(std::memcmp(q2.data(), expected.data(), sizeof(double) * q2.size()) == 0);
    }
  }
  INFO("wider kernels this processor runs: " << widths_run);
  SUCCEED();
}

TEST_CASE("points off the grid and bad parameters", "[planner]") {
  HarmonicPlanner planner;
  planner.set_grid(build_occupancy(open_world(false), kInflate));
  planner.set_goal(Vec2(1.0, 1.0), 0.2);
  REQUIRE(planner.update());
  CHECK_FALSE(planner.reachable(Vec2(5.0, 0.0)));
  CHECK(planner.descent(Vec2(5.0, 0.0)) == Vec2::Zero());
  CHECK(planner.at_goal(Vec2(1.0, 1.0)));
  CHECK(planner.descent(Vec2(1.0, 1.0)) == Vec2::Zero());
  CHECK(planner.potential(Vec2(1.0, 1.0)) == Approx(0.0));
  CHECK(planner.residual() < 1e-3);
  CHECK_THROWS_AS(planner.set_goal(Vec2(NAN, 0.0), 0.1), Error);
  CHECK_THROWS_AS(planner.set_goal(Vec2(0.0, 0.0), -1.0), Error);
  CHECK_THROWS_AS(planner.set_grid(OccupancyGrid{}), Error);
  PlannerParams bad;
  bad.omega = 2.0;
  bad.auto_omega = false;
  CHECK_THROWS_AS(HarmonicPlanner(bad), Error);
  bad = PlannerParams{};
  bad.tolerance = 0.0;
  CHECK_THROWS_AS(HarmonicPlanner(bad), Error);
}

TEST_CASE("solve timings on the 64 x 64 arena", "[planner][.bench]") {
  using Clock = std::chrono::steady_clock;
  for (const bool cluttered : {false, true}) {
    Rng rng(3);
    const WorldSpec world = cluttered ? random_world(rng) : open_world(false);
    const OccupancyGrid grown = build_occupancy(world, kInflate);
    PlannerParams cold_params;
    cold_params.warm_start = false;
    HarmonicPlanner warm, cold(cold_params);
    warm.set_grid(grown);
    cold.set_grid(grown);
    // The goal steps back and forth between two neighbouring cells.
    Vec2 a(-1.0, -0.9);
    warm.set_goal(a, 0.1);
    while (!warm.update() || occupied_at(grown, a + Vec2(grown.cell, 0.0))) {
      a = free_point(rng, grown);
      warm.set_goal(a, 0.1);
    }
    const Vec2 b = a + Vec2(grown.cell, 0.0);
    const int rounds = 200;
    double warm_us = 0.0, cold_us = 0.0;
    long warm_sweeps = 0, cold_sweeps = 0;
    for (int r = 0; r < rounds; ++r) {
      const Vec2& goal = r % 2 == 0 ? b : a;
      auto t0 = Clock::now();
      warm.set_goal(goal, 0.1);
      warm.update();
      auto t1 = Clock::now();
      cold.set_goal(goal, 0.1);
      cold.update();
      auto t2 = Clock::now();
      warm_us += std::chrono::duration<double, std::micro>(t1 - t0).count();
      cold_us += std::chrono::duration<double, std::micro>(t2 - t1).count();
      warm_sweeps += warm.sweeps_last_solve();
      cold_sweeps += cold.sweeps_last_solve();
    }
    std::printf("%s arena (%d free cells, omega %.3f): warm solve %.0f sweeps %.0f us, cold solve %.0f sweeps %.0f us\n",
                cluttered ? "cluttered" : "open", grown.nx * grown.ny - grown.count(), warm.omega(),
                double(warm_sweeps) / rounds, warm_us / rounds, double(cold_sweeps) / rounds, cold_us / rounds);
    CHECK(warm.converged());
  }
}
