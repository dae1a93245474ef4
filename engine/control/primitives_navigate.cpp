// primitives_navigate.cpp: phi1, the harmonic-function path planner as a primitive: its planner
// query (the goal and grid for this tick), its convergence test, and its reference (the base
// command down the potential).
#include <algorithm>
#include <cmath>

#include "control/planner.h"
#include "control/primitives_internal.h"
#include "core/rng.h"
#include "core/shape.h"

namespace roger {
namespace primitives_internal {
namespace {

// phi1: the harmonic-function path planner. A control point (the base centre, or a point carried
// ahead of it such as a grasped object) descends the harmonic potential to the goal: an approach
// ring around the perceived object, a goal region of the scenario, or a vantage point elsewhere.
class Navigate final : public Primitive {
  // Where the constructor declared each parameter: reading one is an index, not a name search.
  struct {
    ParamSlot goal = 0, region = 0, speed = 0, carry_turn = 0, memory = 0, margin = 0, replan = 0,
        tolerance = 0, depth = 0, away = 0;
    BodySlot approach, carry, objects, squeeze;
  } p_;
  enum class GoalKind { kObject, kRegion, kElsewhere };
 public:
  Navigate() : Primitive("phi1", 0.05) {
    p_.goal = declare_text("goal", {"object", "region", "elsewhere"},
                           "approach the perceived object, reach a goal region, or go and look from elsewhere");
    p_.region = declare_whole("region", 0, 0, 63, "which goal region (index into the scenario's goals) for goal='region'");
    // 0.58, not 0.62: from a ring 4 cm nearer, phi2 has less to travel to its standoff, and the
    // hand-written task in cluttered worlds loses fewer triangles to a preshape that pushes the
    // object ahead of it (docs/results.md, "The triangle at 95%").
    p_.approach = declare_body("approach", &BodyMetrics::approach, 0.3, 2.0, "approach distance (m) from the object centre to the base");
    p_.carry = follow_body(declare("carry", 0.0, 0.0, 1.0,
                                   "control point ahead of the base (m): 0 = base centre; \"body\": the grasped object's centre"),
                           &BodyMetrics::carry, false);
    p_.speed = declare("speed", 0.9, 0.05, 2.0, "cruise speed (m/s)");
    p_.carry_turn = declare("carry_turn", 0.6, 0.01, 3.0, "largest heading step (rad) per command while carrying");
    p_.memory = declare("memory", 2.0, 0.0, 60.0, "seconds a lost object's last position stays a goal");
    p_.margin = declare("margin", 0.05, 0.0, 1.0, "how far (m) inside a goal region's edge the goal cells end");
    p_.depth = declare("depth", 0.0, 0.0, 1.0, "how far (m) inside a goal region's edge the control point must be to converge");
    p_.replan = declare("replan", 0.15, 0.0, 1.0, "how far (m) the object estimate must move to plan again");
    // Steering needs the direction of the gradient, not the potential to 4 digits: a looser
    // solve than the planner's default halves the sweeps of every plan.
    p_.tolerance = declare("tolerance", 2e-3, 1e-8, 0.1, "relative change per sweep at which a plan has converged");
    // Other objects are obstacles grown by this much: the base's radius and the preshaped hands'
    // reach to its sides, so the hands do not land on a neighbour (docs/control.md measures 0.3,
    // 0.4 and 0.5 on 8-object sorting).
    p_.objects = declare_body("objects", &BodyMetrics::objects_growth, 0.0, 2.0,
                         "how far (m) other objects are grown as obstacles (0: objects are not obstacles)");
    // More than the base's radius (0.16 m): the base itself still keeps off the neighbours. 0.25 as
    // the sorting curricula's carry, which steers between the same neighbours.
    p_.squeeze = declare_body("squeeze", &BodyMetrics::squeeze, 0.0, 2.0,
                         "how far (m) other objects are grown instead when the `objects` growth leaves an "
                         "approach no goal cell or no way to it (0: never)");
    p_.away = declare("away", 2.0, 0.2, 50.0,
                      "how far (m) from where it set out a goal='elsewhere' run's vantage point lies, at least");
    on_params_changed();
  }
  Navigate(const Navigate& o)
      : Primitive(o), p_(o.p_), planner_(planner_params()), goal_kind_(o.goal_kind_) {}
  PrimitivePtr clone() const override { return std::make_shared<Navigate>(*this); }
  // The distance to the goal, not the potential: far from the goal the harmonic potential lies
  // within a hair of 1 and changes by less than `stall` over `plateau` even at full speed, so a
  // carry under the grasp keeper (phi1 <| phi4 <| phi5) counted as settled, CONV, every 16 ticks.
  double progress(const ControlOutput& out) const override { return out.residual; }
  void reset(uint64_t seed) override {
    Primitive::reset(seed);
    grid_ = nullptr;
    planned_ = false;
    stamps_.clear();
    left_out_ = -1;
    bare_region_ = -1;
    squeezed_for_ = -1;
    // The grid often outlives the episode (the same arena), and with it the last solution, which
    // the next solve would start from: an episode would then depend on the one before it.
    planner_.forget_solution();
    turn_sign_ = 0;
    blocked_time_ = 0.0;
    rng_.reseed(Rng::mix(seed, 0xe15e4e7e));
    trip_ = Trip::kNone;
    looked_from_valid_ = seen_since_run_ = false;
    drawn_tick_ = UINT64_MAX;
  }

 protected:
  // A new tolerance needs a new planner.
  void on_params_changed() override {
    const std::string& goal = choice(p_.goal);
    goal_kind_ = goal == "region" ? GoalKind::kRegion : goal == "elsewhere" ? GoalKind::kElsewhere : GoalKind::kObject;
    PlannerParams p = planner_params();
    if (p.tolerance != planner_.params().tolerance) {
      planner_ = HarmonicPlanner(p);
      grid_ = nullptr;
      planned_ = false;
    }
  }

  PlannerParams planner_params() const {
    PlannerParams p;
    p.tolerance = value(p_.tolerance);
    return p;
  }

  // The state needs reachability and the distance to the goal, not the solved potential.
  bool compute_state(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    classify(in, false, out, gamma);
    return true;
  }
  // Observed while another action has the robot (a sequence's summary reads every step each
  // tick), phi1 answers from the state path and solves nothing: a solve is paid for when a command
  // needs it, its own or a subject-to's whose state needs the projected command. What a skipped
  // solve would have changed is only where the next solve starts, which converges to the same
  // tolerance from either; the turn a carry commits to belongs to a run and starts with it
  // (compute). The 8-object bench's three episodes solved 183 times before, 64 after.
  // goal='elsewhere' is not exact: its state between runs is NOREF, and only a run (a command)
  // draws where to go.
  bool state_is_exact() const override { return goal_kind_ != GoalKind::kElsewhere; }

  // The reference: once the planner query and the convergence test leave the control point on
  // its way, the base command down the potential.
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    own_dofs({kBaseForward, kBaseHeading}, out.jacobian);
    // A run's first command (the tick before gave none) commits to no turn from before it.
    if (!acted_last_tick(in)) turn_sign_ = 0, blocked_time_ = 0.0;
    const Vec2 point = classify(in, true, out, gamma);
    if (gamma != Gamma::kNotConv) return;
    const SenseReadings& s = *in.senses;
    const double carry = value(in, p_.carry);
    out.phi = planner_.potential(point);
    Vec2 dir = planner_.descent(point);
    if (dir.squaredNorm() < 1e-12) dir = (goal_center_ - point).normalized();
    const double slow = std::clamp(out.residual / 0.3, 0.25, 1.0);  // ease into the goal
    const double lookahead = 0.3;                                     // s of motion per command
    const double speed = value(p_.speed) * slow;
    if (carry > 0.05) steer_carried(s, in.dt(), dir, speed, lookahead, carry, out);
    else steer_base(s, dir, speed, lookahead, out);
  }

 private:
  // ---- The planner query ----

  // The control point: the base centre, or a point carried ahead of it. When carrying, vision
  // says where the carried object really is, if the eyes have it.
  Vec2 control_point(const ControlInput& in) const {
    const SenseReadings& s = *in.senses;
    const double carry = value(in, p_.carry);
    const Vec2 point = Vec2(s.base.x, s.base.y) + carry * unit(s.base.theta);
    if (carry > 0.05 && in.percepts->object.seen &&
        (in.percepts->object.center - point).norm() < 0.5 * carry)
      return in.percepts->object.center;
    return point;
  }

  // Sets the planner's grid and goal for this tick; false when there is no goal.
  bool prepare(const ControlInput& in, bool solve, const Vec2& point) {
    if (goal_kind_ == GoalKind::kRegion) return prepare_region(in, solve);
    return prepare_object(in, solve, point);
  }

  // The goal region of the scenario (goal='region'); false when the scenario has no such region.
  bool prepare_region(const ControlInput& in, bool solve) {
    // A binding may name the region (ControlInput::region) instead of the parameter.
    const size_t k = in.region >= 0 ? size_t(in.region) : size_t(value(p_.region));
    if (k >= in.spec().goals.size()) return false;
    if (bare_region_ >= 0 && size_t(bare_region_) != k) {
      bare_region_ = -1;  // another region: the objects put away in the last are grown again
      if (grid_ == &in.grid()) build_map(in);
    }
    const bool map_changed = update_map(in, nullptr);
    // The region is fixed while the region is: set it once (the planner would notice that
    // nothing changed, but finding the goal cells each tick is not free).
    if (map_changed || !planned_ || k != planned_region_) {
      planned_ = true;
      planned_region_ = k;
      goal_center_ = in.spec().goals[k].center;
      goal_radius_ = in.spec().goals[k].radius;
      planner_.set_goal(goal_center_, std::max(0.5 * in.grid().cell, goal_radius_ - value(p_.margin)));
    }
    // A region whose every goal cell lies under the growth of objects already put away in it is
    // full only for the grid, not for the floor: the next of the type goes in beside them. From
    // then on, for this navigator, the objects in that region are stamped at their own size.
    if (planner_.goal_cells() == 0 && bare_region_ < 0 && grown_in_region(in, int(k))) {
      bare_region_ = int(k);
      build_map(in);  // set_grid finds the goal cells again on the new grid
    }
    // A region holding every free cell of its components leaves the planner nothing to solve
    // (update is false), yet its goal is there: a point in it is at its goal (found by a probe: a
    // goal of radius 10 m in a 4 m arena left phi1 NOREF everywhere, as if it had no region).
    const bool to_solve = solve ? planner_.update() : planner_.update_reachability();
    return to_solve || planner_.goal_cells() > 0;
  }

  // Whether an obstacle object lying in region k is stamped with a growth.
  bool grown_in_region(const ControlInput& in, int k) const {
    if (!(value(in, p_.objects) > 0.0)) return false;
    for (const Stamp& st : stamps_)
      if (st.on && st.region == k) return true;
    return false;
  }

  // The approach ring around the perceived object (goal='object'); false when the object is not
  // seen or lies off the grid.
  bool prepare_object(const ControlInput& in, bool solve, const Vec2& point) {
    VisualObject obj;
    if (!object_estimate(in, value(p_.memory), obj, true)) return false;
    int i, j;
    if (!in.grid().cell_of(obj.center, i, j)) return false;
    // The object approached is no obstacle: the base stops on entering the approach disk.
    if (update_map(in, &obj.center)) planned_ = false;
    // Re-plan only when the estimate has moved by `replan` metres (or more, far away): stereo
    // jitter must not cost a solve per tick; keeping the goal fixed lets every re-plan start warm
    // from the last solution.
    // Far from the object a shift of the estimate barely turns the path: the tolerance grows
    // with the distance (a quarter of it), so the long approach re-plans rarely.
    const double distance = (obj.center - Vec2(in.senses->base.x, in.senses->base.y)).norm();
    if (!planned_ ||
        (obj.center - goal_center_).norm() > std::max(value(p_.replan), 0.25 * distance)) {
      planned_ = true;
      goal_center_ = obj.center;
      goal_radius_ = value(in, p_.approach);
      planner_.set_goal(goal_center_, goal_radius_);
    }
    squeeze_if_shut_out(in, point);
    return solve ? planner_.update() : planner_.update_reachability();
  }

  // An approach whose ring lies wholly under the growth of other objects, or that they wall off
  // from the base (an object in a corner beside another, or between two neighbours and an
  // obstacle), would be NOREF for as long as they lie there: the move that wants the object gives
  // up after its patience and is chosen again, to the end of the episode (8-object sorting seed
  // 540034). The other objects are then grown only by `squeeze`, enough to keep the base itself
  // off them, until the approach turns to another object or starts over.
  void squeeze_if_shut_out(const ControlInput& in, const Vec2& point) {
    const double squeeze = value(in, p_.squeeze);
    if (squeezed_for_ >= 0 || left_out_ < 0 || !(squeeze > 0.0) || squeeze >= value(in, p_.objects)) return;
    if (planner_.update_reachability() && planner_.reachable(point)) return;
    squeezed_for_ = left_out_;
    build_map(in);
  }

  // goal='elsewhere': away from a place where looking shows nothing. A run (a tick on which it runs
  // after one on which it did not) that begins within kSameSpot of where the last run ended, the
  // eyes having had no stimulus since (as its state was asked between runs), draws a vantage point
  // at random (from the seed) among the free cells the base can reach at least `away` metres off
  // (the farthest it can reach, if none is that far) and drives there. Any other run notes the
  // place and is CONV at once: Roger has not looked from there yet, or saw something from there.
  // Between runs it is NOREF: it has no goal until a run draws one.
  // A chooser that runs it after each round of searches then leaves only a place from which a
  // whole round saw nothing, where the round before ended. A drive that makes no headway for
  // kStuckSeconds gives up (NOREF).
  void classify_elsewhere(const ControlInput& in, bool solve, const Vec2& point, ControlOutput& out,
                          Gamma& gamma) {
    out.residual = 0.0;
    if (!acted_last_tick(in) && !solve) {
      // Between runs: no goal until a run draws one (NOREF, as phi1 with no object in view), and
      // no planning; only what the eyes see. A chooser whose other actions have nothing to do is
      // then NOREF too, which is a decision point of a stage.
      seen_since_run_ |= in.percepts->object.seen;
      gamma = Gamma::kNoRef;
      return;
    }
    if (solve && !acted_last_tick(in) && drawn_tick_ != in.tick) begin_elsewhere(in, point);
    if (trip_ == Trip::kStay || trip_ == Trip::kArrived) {
      gamma = Gamma::kConv;
      return;
    }
    if (trip_ == Trip::kNone || !prepare_elsewhere(in, solve) || !planner_.reachable(point)) {
      gamma = Gamma::kNoRef;
      return;
    }
    out.residual = goal_distance(point);
    gamma = converged(point) ? Gamma::kConv : Gamma::kNotConv;
    watch_trip(in, solve, point, out.residual, gamma);
  }

  // The first tick of a run: stay and note the place, or draw a vantage point away from it.
  void begin_elsewhere(const ControlInput& in, const Vec2& base) {
    drawn_tick_ = in.tick;
    const bool saw = seen_since_run_;
    seen_since_run_ = false;
    if (saw || !looked_from_valid_ || (base - looked_from_).norm() > kSameSpot) {
      looked_from_valid_ = true;
      looked_from_ = base;
      trip_ = Trip::kStay;
      return;
    }
    update_map(in, nullptr);
    trip_ = draw_vantage(base) ? Trip::kDriving : Trip::kNone;
    if (trip_ == Trip::kNone) looked_from_ = base;
    planned_ = false;
    best_residual_ = INFINITY;
    no_headway_ = 0.0;
  }

  // Ends a drive that arrived (whether its command or a look at its state finds it there) or,
  // counted on its commands, makes no headway; where it ends is the place looked from next.
  void watch_trip(const ControlInput& in, bool commanding, const Vec2& base, double residual, Gamma& gamma) {
    if (commanding) {
      if (residual < best_residual_ - kHeadway) best_residual_ = residual, no_headway_ = 0.0;
      else no_headway_ += in.dt();
    }
    if (gamma == Gamma::kConv || no_headway_ > kStuckSeconds) {
      trip_ = gamma == Gamma::kConv ? Trip::kArrived : Trip::kNone;
      looked_from_ = base;
      if (trip_ == Trip::kNone) gamma = Gamma::kNoRef;
    }
  }

  // The drive's planner query: the vantage point on the grid with the objects as they lie.
  bool prepare_elsewhere(const ControlInput& in, bool solve) {
    if (update_map(in, nullptr) || !planned_) {
      planned_ = true;
      goal_center_ = vantage_;
      goal_radius_ = kVantageRadius;
      planner_.set_goal(goal_center_, goal_radius_);
    }
    return solve ? planner_.update() : planner_.update_reachability();
  }

  // Draws vantage_ from the cells of the planner's grid joined to the base's; false if none is.
  bool draw_vantage(const Vec2& base) {
    planner_.set_goal(base, kVantageRadius);
    if (!planner_.update_reachability()) return false;
    const OccupancyGrid& grid = planner_.grid();
    const double away = value(p_.away);
    int far = 0;
    double farthest = -1.0;
    vantages_.clear();
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i) {
        const Vec2 c = grid.center(i, j);
        if (grid.occupied[size_t(j) * grid.nx + i] || !planner_.reachable(c)) continue;
        const double d = (c - base).norm();
        if (d >= away) vantages_.push_back(c);
        if (d > farthest) farthest = d, far = j * grid.nx + i;
      }
    if (farthest <= kVantageRadius) return false;  // nowhere to go but where it stands
    vantage_ = vantages_.empty() ? grid.center(far % grid.nx, far / grid.nx)
                                 : vantages_[size_t(rng_.integer(0, int64_t(vantages_.size()) - 1))];
    return true;
  }

  // ---- The map: the static grid and the other objects ----

  // Which objects are obstacles this tick: every object but the one approached (the object of the
  // stimulus colour nearest to `target`, the perceived object) or carried (the one Roger touches,
  // or else the one at the control point: a contact that lapses for a tick must not turn the
  // carried object into an obstacle and back). With neither to go by (a region's navigator asked
  // for its state before anything is held; a target no object of the stimulus colour is near),
  // every object of the stimulus colour not yet put away is left out: those are what Roger is
  // after. An object stays an obstacle wherever it lies, in a goal region too.
  // The object the one left out stays, while the perception still lies near it: two objects of the
  // stimulus colour side by side (stereo may pair one eye's view of one with the other eye's view
  // of the other) must not swap in and out of the grid every tick, each swap a solve.
  void choose_obstacles(const ControlInput& in, const Vec2* target, std::vector<uint8_t>& on) {
    const std::vector<MapObject>& objects = *in.objects;
    on.assign(objects.size(), 1);
    if (left_out_ >= int(objects.size())) left_out_ = -1;
    auto near = [&](int i, const Vec2& p, double slack) {
      return (objects[size_t(i)].center - p).norm() <= objects[size_t(i)].radius + slack;
    };
    // Approaching, only an object of the stimulus colour is what Roger is after: a neighbour of
    // another colour nearer the perception (one half hiding the other biases stereo towards the
    // nearer) stays an obstacle. Carrying, the object is whichever is held, as touch says.
    auto nearest_to = [&](const Vec2& p, bool stimulus_only) {
      auto sought = [&](int i) {
        return !stimulus_only || !in.attention || objects[size_t(i)].colour == in.attention->colour;
      };
      if (left_out_ >= 0 && sought(left_out_) && near(left_out_, p, 2.0 * kTargetSlack)) return left_out_;
      double best = 1e300;
      int found = -1;
      for (size_t i = 0; i < objects.size(); ++i) {
        const double d = (objects[i].center - p).norm();
        if (sought(int(i)) && near(int(i), p, kTargetSlack) && d < best) best = d, found = int(i);
      }
      return found;
    };
    int chosen = -1;
    if (target) {
      chosen = nearest_to(*target, true);
    } else if (in.percepts->touched_object >= 0 && size_t(in.percepts->touched_object) < objects.size()) {
      chosen = in.percepts->touched_object;
    } else if (value(in, p_.carry) > 0.05) {
      chosen = nearest_to(control_point(in), false);
    }
    left_out_ = chosen;
    if (chosen >= 0) {
      on[size_t(chosen)] = 0;
      return;
    }
    // Going elsewhere, nothing is sought: every object untouched is an obstacle.
    if (!in.attention || goal_kind_ == GoalKind::kElsewhere) return;
    for (size_t i = 0; i < objects.size(); ++i) {
      const MapObject& o = objects[i];
      const bool put_away = o.region >= 0 && o.region == in.attention->ignore_region && !o.held;
      if (o.colour == in.attention->colour && !put_away) on[i] = 0;
    }
  }

  // Brings the planner's grid up to date with the objects: the static grid plus a disk for each
  // obstacle object, re-stamped only when one is added, dropped or has moved a cell (the growth
  // leaves room for that), so a still scene costs one comparison per object and tick, and never a
  // solve. Returns whether the grid changed.
  bool update_map(const ControlInput& in, const Vec2* target) {
    const bool new_grid = grid_ != &in.grid();
    if (new_grid) {
      grid_ = &in.grid();
      stamps_.clear();
    }
    const double grow = value(in, p_.objects);
    if (!in.objects || grow <= 0.0) {
      if (new_grid) planner_.set_grid(in.grid());
      return new_grid;
    }
    choose_obstacles(in, target, wanted_);
    const std::vector<MapObject>& objects = *in.objects;
    bool changed = new_grid || stamps_.size() != objects.size();
    if (squeezed_for_ >= 0 && squeezed_for_ != left_out_) squeezed_for_ = -1, changed = true;
    stamps_.resize(objects.size());
    for (size_t i = 0; i < objects.size(); ++i) {
      Stamp& st = stamps_[i];
      const bool on = wanted_[i] != 0;
      // Which region an object lies in matters only to a region stamped at the objects' own size.
      const bool region_same = bare_region_ < 0 || st.region == objects[i].region;
      if (st.on == on && region_same && (!on || (st.center - objects[i].center).norm() <= in.grid().cell))
        continue;
      st.on = on;
      st.center = objects[i].center;
      st.radius = objects[i].radius;
      st.region = objects[i].region;
      changed = true;
    }
    if (!changed) return false;
    build_map(in);
    return true;
  }

  // The planner's grid from the static grid and the stamps: each obstacle object a disk of its
  // radius grown by `objects` (by `squeeze` while squeezed), or of its own radius in the region
  // bare_region_.
  void build_map(const ControlInput& in) {
    map_ = *grid_;
    const double grow = squeezed_for_ >= 0 ? value(in, p_.squeeze) : value(in, p_.objects);
    for (const Stamp& st : stamps_)
      if (st.on) stamp_disk(st.center, st.region >= 0 && st.region == bare_region_ ? st.radius : st.radius + grow);
    planner_.set_grid(map_);
  }

  // Marks the cells of map_ whose centres lie within `radius` (plus half a cell, as the static
  // obstacles are grown) of `center`.
  void stamp_disk(const Vec2& center, double radius) {
    const double reach = radius + 0.5 * map_.cell;
    const int i0 = std::max(0, int(std::floor((center.x() - reach - map_.x0) / map_.cell)));
    const int j0 = std::max(0, int(std::floor((center.y() - reach - map_.y0) / map_.cell)));
    const int i1 = std::min(map_.nx - 1, int(std::floor((center.x() + reach - map_.x0) / map_.cell)));
    const int j1 = std::min(map_.ny - 1, int(std::floor((center.y() + reach - map_.y0) / map_.cell)));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i)
        if ((map_.center(i, j) - center).squaredNorm() <= reach * reach)
          map_.occupied[size_t(j) * map_.nx + i] = 1;
  }

  // ---- The convergence test ----

  // Equation 1 for the planner: NOREF without a goal or when the goal cannot be reached, CONV in
  // the goal, !CONV on the way. With `solve`, the potential is brought up to date for the command.
  Vec2 classify(const ControlInput& in, bool solve, ControlOutput& out, Gamma& gamma) {
    const Vec2 point = control_point(in);
    if (goal_kind_ == GoalKind::kElsewhere) {
      classify_elsewhere(in, solve, point, out, gamma);
      return point;
    }
    if (!prepare(in, solve, point) || !planner_.reachable(point)) {
      gamma = Gamma::kNoRef;
      return point;
    }
    out.residual = goal_distance(point);
    gamma = converged(point) ? Gamma::kConv : Gamma::kNotConv;
    return point;
  }

  // How far (m) the control point is from the goal's edge (0 inside).
  double goal_distance(const Vec2& p) const {
    return std::max(0.0, (p - goal_center_).norm() - goal_radius_);
  }

  // Whether the control point is within epsilon of the goal (`depth` inside a region's edge: a
  // carried object's centre is then inside the region, not merely at its edge).
  bool converged(const Vec2& p) const {
    const double depth = goal_kind_ == GoalKind::kRegion ? std::min(value(p_.depth), 0.9 * goal_radius_) : 0.0;
    return (p - goal_center_).norm() <= goal_radius_ - depth + epsilon();
  }

  // ---- The reference ----

  // The base command that moves a point `carry` metres ahead of the base along `dir` at `speed`.
  void steer_carried(const SenseReadings& s, double dt, const Vec2& dir, double speed, double lookahead,
                     double carry, ControlOutput& out) {
    const Vec2 fwd = unit(s.base.theta);
    // A point ahead of a differential drive moves holonomically: v = u.f, w = u.left / carry.
    // Never back away from what is carried: the body would leave it; turn on the spot instead.
    const Vec2 u = speed * dir;
    out.command[kBaseForward] = std::max(0.0, u.dot(fwd)) * lookahead;
    const double turn = value(p_.carry_turn);
    out.command[kBaseHeading] = clamp_abs(u.dot(perp(fwd)) / carry * lookahead, turn);
    // With the way ahead more than a right angle off, rotate towards it at full rate (the
    // formula above vanishes when the goal lies straight behind), and keep turning the same way
    // until it is ahead again. Turning swings the carried point sideways, and behind the base the
    // descent often splits round an obstacle: the side it points to flips as the point crosses
    // the split, and a turn that followed it would rock the base on the spot until the time-out.
    if (u.dot(fwd) < 0.0) {
      if (turn_sign_ == 0) turn_sign_ = u.dot(perp(fwd)) >= 0.0 ? 1 : -1, blocked_time_ = 0.0;
      // A turn that makes no headway is blocked (the carried object or an arm against an
      // obstacle, which the planner's grid, grown for the base alone, does not see): the other
      // way round may be free.
      blocked_time_ = std::abs(s.qdot[kBaseHeading]) < kTurnStalled ? blocked_time_ + dt : 0.0;
      if (blocked_time_ > kTurnPatience) turn_sign_ = -turn_sign_, blocked_time_ = 0.0;
      out.command[kBaseHeading] = turn_sign_ * turn;
    } else if (u.dot(fwd) > 0.5 * u.norm()) {
      turn_sign_ = 0;  // within 60 degrees of ahead: steer by the formula again
    } else if (turn_sign_ != 0) {
      out.command[kBaseHeading] = turn_sign_ * turn;  // still finishing the committed turn
    }
  }

  // The base command that turns the base to `dir` and drives along it, slower the more it is off.
  static void steer_base(const SenseReadings& s, const Vec2& dir, double speed, double lookahead,
                         ControlOutput& out) {
    const double turn = wrap_angle(std::atan2(dir.y(), dir.x()) - s.base.theta);
    const double along = std::max(0.0, std::cos(turn));
    out.command[kBaseHeading] = clamp_abs(turn, 0.8);
    out.command[kBaseForward] = speed * lookahead * along * along;
  }

  // One object's disk in the planner's grid, as last stamped.
  struct Stamp {
    bool on = false;
    Vec2 center = Vec2::Zero();
    double radius = 0.0;  // the object's own (build_map grows it)
    int region = -1;      // the goal region holding its centre, or -1
  };
  static constexpr double kTargetSlack = 0.3;  // m beyond its radius a perceived target may lie

  HarmonicPlanner planner_;
  const OccupancyGrid* grid_ = nullptr;  // the static grid the map was built on
  OccupancyGrid map_;                    // the static grid and the obstacle objects
  std::vector<Stamp> stamps_;            // per object, what map_ holds of it
  std::vector<uint8_t> wanted_;          // scratch: which objects are obstacles this tick
  int left_out_ = -1;                    // the object approached or carried, last tick
  int bare_region_ = -1;                 // a goal region whose objects are stamped ungrown, or -1
  int squeezed_for_ = -1;                // the object whose approach grows the others by `squeeze`, or -1
  bool planned_ = false;
  size_t planned_region_ = 0;  // the goal region planned for (goal='region')
  Vec2 goal_center_ = Vec2::Zero();
  double goal_radius_ = 0.0;
  GoalKind goal_kind_ = GoalKind::kObject;  // the `goal` parameter (kept here, not compared as text)
  // goal='elsewhere': what this run does, decided on its first tick (begin_elsewhere).
  enum class Trip { kNone, kStay, kDriving, kArrived };  // kNone: nowhere to go, or gave up
  Trip trip_ = Trip::kNone;
  Rng rng_{0};                             // draws the vantage points
  Vec2 vantage_ = Vec2::Zero();            // where this run drives
  bool looked_from_valid_ = false;
  Vec2 looked_from_ = Vec2::Zero();        // where the last run ended: the place looked from
  bool seen_since_run_ = false;            // the eyes had a stimulus between runs
  double best_residual_ = INFINITY;        // the drive's nearest approach so far (m)
  double no_headway_ = 0.0;                // s since it last came kHeadway nearer
  std::vector<Vec2> vantages_;             // scratch: the cells a vantage point is drawn from
  uint64_t drawn_tick_ = UINT64_MAX;       // the first tick of the current run
  static constexpr double kVantageRadius = 0.3;  // m: the goal disk around a vantage point
  static constexpr double kSameSpot = 0.5;       // m: a run beginning this near leaves the place
  static constexpr double kHeadway = 0.1;        // m nearer that counts as headway
  static constexpr double kStuckSeconds = 3.0;   // s without headway that end a drive
  int turn_sign_ = 0;  // a committed turn on the spot while carrying: +1 left, -1 right, 0 none
  double blocked_time_ = 0.0;  // seconds the committed turn has made no headway
  static constexpr double kTurnStalled = 0.1;   // rad/s: a turn slower than this makes no headway
  static constexpr double kTurnPatience = 0.5;  // s of no headway before turning the other way
};

}  // namespace

PrimitivePtr make_navigate() { return std::make_shared<Navigate>(); }

}  // namespace primitives_internal
}  // namespace roger
