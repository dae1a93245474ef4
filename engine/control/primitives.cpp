#include "control/primitives.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Cholesky>

#include "core/error.h"
#include "control/planner.h"
#include "core/rng.h"
#include "core/shape.h"

namespace roger {
namespace {

Vec2 perp(const Vec2& v) { return {-v.y(), v.x()}; }
Vec2 unit(double angle) { return {std::cos(angle), std::sin(angle)}; }
double clamp_abs(double v, double limit) { return std::clamp(v, -limit, limit); }

// Where the object is believed to be: this tick's estimate, or the last one if it is recent. With
// `vision_only`, touch-based estimates are ignored: controllers that work at a distance (approach,
// preshape) keep one consistent frame instead of flipping between what vision and a grazing
// contact say about a polygon.
bool object_estimate(const ControlInput& in, double memory, VisualObject& out,
                     bool vision_only = false) {
  const Percepts& p = *in.percepts;
  if (vision_only) {
    if (!p.vision.seen || in.time - p.vision_time > memory) return false;
    out = p.vision;
    return true;
  }
  if (p.object.seen) {
    out = p.object;
    return true;
  }
  if (p.remembered.seen && in.time - p.remembered_time <= memory) {
    out = p.remembered;
    return true;
  }
  return false;
}

// Jacobian columns of a world point carried by one arm's hand or by the base, over the 8 DOFs.
// Moving the base forward carries every point along the heading; turning the base swings it about
// the base centre; each arm joint swings the hand about that joint.
void hand_jacobian(const ControlInput& in, int side, Eigen::Matrix<double, 2, kDofCount>& J) {
  const Senses& s = *in.senses;
  const ArmPoints& a = in.percepts->arms[side];
  const Vec2 base(s.base.x, s.base.y);
  J.setZero();
  J.col(kBaseForward) = unit(s.base.theta);
  J.col(kBaseHeading) = perp(a.hand - base);
  J.col(kLeftShoulder + 2 * side) = perp(a.hand - a.shoulder);
  J.col(kLeftElbow + 2 * side) = perp(a.hand - a.elbow);
}

// Damped least squares: dq = J^T (J J^T + lambda^2 I)^-1 e, restricted to the columns in `use`.
// Damping keeps the step bounded when a target is out of reach or the arm is stretched straight.
template <int Rows>
DofVector damped_solve(const Eigen::Matrix<double, Rows, kDofCount>& J_full,
                       const Eigen::Matrix<double, Rows, 1>& e, const DofVector& use,
                       double lambda) {
  Eigen::Matrix<double, Rows, kDofCount> J = J_full;
  for (int c = 0; c < kDofCount; ++c)
    if (use[c] == 0.0) J.col(c).setZero();
  // Coefficient-wise products: at these sizes Eigen would otherwise route J J^T through its
  // general matrix kernel, whose set-up costs more than the arithmetic.
  Eigen::Matrix<double, Rows, Rows> A = J.lazyProduct(J.transpose());
  A.diagonal().array() += lambda * lambda;
  const Eigen::Matrix<double, Rows, 1> y = A.ldlt().solve(e);
  return J.transpose().lazyProduct(y);
}

// Caps each joint's step so one tick's command never asks for a leap the linearization cannot
// justify.
void cap_steps(DofVector& dq, double linear, double angular) {
  dq[kBaseForward] = clamp_abs(dq[kBaseForward], linear);
  for (int i = 1; i < kDofCount; ++i) dq[i] = clamp_abs(dq[i], angular);
}

// The three contact locations and the unit normals from the object centre towards each, from
// kinematics (body centre, hand centres).
struct ContactGeometry {
  Vec2 point[kTactileCount];
  Vec2 normal[kTactileCount];
};

ContactGeometry kinematic_contacts(const ControlInput& in, const Vec2& center) {
  ContactGeometry g;
  const Senses& s = *in.senses;
  g.point[kBody] = Vec2(s.base.x, s.base.y);
  g.point[kLeftHand] = in.percepts->arms[kLeft].hand;
  g.point[kRightHand] = in.percepts->arms[kRight].hand;
  for (int t = 0; t < kTactileCount; ++t) {
    const Vec2 d = g.point[t] - center;
    g.normal[t] = d.norm() > 1e-9 ? Vec2(d.normalized()) : Vec2(1.0, 0.0);
  }
  return g;
}

}  // namespace

GraspResidual grasp_residual(const Vec2 normal[kTactileCount], const Vec2 point[kTactileCount],
                             const Vec2& center, double size, double moment_weight,
                             double friction) {
  // Rows: force x, force y, scaled moment. Column i: what contact i's tangential share adds.
  const double w = std::sqrt(std::max(moment_weight, 0.0)) / std::max(size, 0.05);
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  Eigen::Matrix3d A;
  for (int i = 0; i < kTactileCount; ++i) {
    const Vec2 r = point[i] - center;
    const Vec2 tangent(-normal[i].y(), normal[i].x());
    b += Eigen::Vector3d(normal[i].x(), normal[i].y(),
                         w * (r.x() * normal[i].y() - r.y() * normal[i].x()));
    A.col(i) = Eigen::Vector3d(tangent.x(), tangent.y(), w * (r.x() * tangent.y() - r.y() * tangent.x()));
  }
  GraspResidual best;
  best.phi = b.squaredNorm();
  best.force = b.head<2>();
  if (!(friction > 0.0)) return best;
  // A box-constrained least squares in three unknowns: the optimum has each share free or at one
  // of its bounds, so try all 27 such patterns, solving for the free shares, and keep the best
  // pattern whose free shares fall within their bounds (the problem is convex). Pattern 0 (all
  // free) is the unconstrained optimum: when it is feasible it is the answer, which is the common
  // case of a settled grasp.
  for (int pattern = 0; pattern < 27; ++pattern) {
    int code[kTactileCount];
    for (int i = 0, c = pattern; i < kTactileCount; ++i, c /= 3) code[i] = c % 3;  // 0 free, 1 -, 2 +
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    Eigen::Vector3d rhs = b;
    int free_index[kTactileCount], free_count = 0;
    for (int i = 0; i < kTactileCount; ++i) {
      if (code[i] == 0) {
        free_index[free_count++] = i;
      } else {
        t[i] = code[i] == 1 ? -friction : friction;
        rhs += A.col(i) * t[i];
      }
    }
    if (free_count > 0) {
      // Normal equations with a whisker of ridge for parallel tangents; fixed-size storage, so
      // no allocation in the control loop.
      using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3>;
      Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 3> Af(3, free_count);
      for (int k = 0; k < free_count; ++k) Af.col(k) = A.col(free_index[k]);
      // (Coefficient-wise products: dynamic sizes would go through the general matrix kernel.)
      Small M = Af.transpose().lazyProduct(Af);
      M.diagonal().array() += 1e-12;
      const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1> g = -Af.transpose().lazyProduct(rhs);
      const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1> tf = M.ldlt().solve(g);
      bool inside = true;
      for (int k = 0; k < free_count; ++k) {
        inside = inside && std::abs(tf[k]) <= friction + 1e-12;
        t[free_index[k]] = tf[k];
      }
      if (!inside) continue;
    }
    const Eigen::Vector3d residual = b + A * t;
    if (residual.squaredNorm() < best.phi) {
      best.phi = residual.squaredNorm();
      best.force = residual.head<2>();
      for (int i = 0; i < kTactileCount; ++i) best.friction_used[i] = t[i];
    }
    if (pattern == 0) return best;  // reached only when the unconstrained optimum is feasible
  }
  return best;
}

namespace {

// Targets of a three-contact configuration around an object centre: the body on the line to the
// object at body_distance, the hands at +-spread from the body's side on a circle of hand_radius.
struct Targets {
  double body_distance;
  double body_press = 0.0;  // how far (m) the body may still push once it touches the object
  // body_distance only as a least distance: nearer is pushed back out, farther is left free (no
  // row in the task), so a subordinate may choose the body's distance.
  bool body_keep_out = false;
  Vec2 hand[2];
};

// A hand still far round the object from its target swings wide (up to `swing` metres further
// out), so it travels around the object instead of through it; the detour fades as it arrives.
Targets grasp_targets(const ControlInput& in, const Vec2& center, double body_distance,
                      double hand_radius, double spread, double swing) {
  const Senses& s = *in.senses;
  const Vec2 base(s.base.x, s.base.y);
  // The body's side of the object: where the body touches it, the touch normal says which way the
  // surface there faces (a polygon's face need not face the base centre); else the base's bearing.
  Vec2 to_base = base - center;
  const Percepts& p = *in.percepts;
  if (p.contact_on_object[kBody] && s.touch[kBody].index == p.touched_object)
    to_base = s.touch[kBody].normal;
  const double side_angle = std::atan2(to_base.y(), to_base.x());
  Targets t;
  t.body_distance = body_distance;
  // Facing the object, Roger's left lies clockwise from its side of the object (seen from above).
  const double target_angle[2] = {side_angle - spread, side_angle + spread};
  for (int side = 0; side < 2; ++side) {
    const Vec2 h = in.percepts->arms[side].hand - center;
    const double gap = std::abs(wrap_angle(target_angle[side] - std::atan2(h.y(), h.x())));
    const double radius = hand_radius + swing * std::min(1.0, gap / 0.6);
    t.hand[side] = center + radius * unit(target_angle[side]);
  }
  return t;
}

// Builds the task of placing the hands and the body's distance to the object (and, with `facing`,
// the heading facing it) and its damped least-squares command towards the targets. The Jacobian
// covers every DOF that moves the task, so a subordinate's projection respects it; the command
// uses only the DOFs in `use`.
void reach_targets(const ControlInput& in, const Vec2& center, const Targets& t, bool facing,
                   const DofVector& use, double lambda, ControlOutput& out, double& worst_error) {
  const Senses& s = *in.senses;
  Eigen::Matrix<double, 6, kDofCount> J = Eigen::Matrix<double, 6, kDofCount>::Zero();
  Eigen::Matrix<double, 6, 1> e = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 2, kDofCount> Jh;
  worst_error = 0.0;
  for (int side = 0; side < 2; ++side) {
    hand_jacobian(in, side, Jh);
    J.middleRows<2>(2 * side) = Jh;
    const Vec2 err = t.hand[side] - in.percepts->arms[side].hand;
    e.segment<2>(2 * side) = err;
    worst_error = std::max(worst_error, err.norm());
  }
  // The distance to the object centre, which driving forward shortens by cos(bearing), and the
  // bearing itself, which turning removes.
  const Vec2 base(s.base.x, s.base.y);
  const Vec2 to_obj = center - base;
  const double d = to_obj.norm();
  J(4, kBaseForward) = -unit(s.base.theta).dot(to_obj) / std::max(d, 1e-6);
  e(4) = t.body_distance - d;
  // Touch overrides vision: once the body feels the object it is there, whatever the estimate of
  // the object's size says (a polygon's corner may be nearer than its estimated radius); pushing
  // on would only shove the object away.
  if (in.percepts->contact_on_object[kBody]) e(4) = std::max(e(4), -t.body_press);
  if (t.body_keep_out) {
    // A zero row leaves the command alone and is skipped by the nullspace projection. Once pushing
    // back, aim 1 cm beyond the bound: approaching it only asymptotically would keep the row
    // active, and with it the body's distance locked, for ever.
    if (e(4) <= 0.0) J.row(4).setZero(), e(4) = 0.0;
    else e(4) += 0.01;
  }
  worst_error = std::max(worst_error, std::abs(e(4)));
  // When closing a grasp (`facing`: phi3), a hand folded towards its own shoulder (elbow beyond
  // 2.5 rad) is near a singularity: the shoulder barely moves it, and the least-squares step can
  // stall it against the body instead of swinging it round to a target on the far side of the
  // object. While such a hand is far from its target, open the elbow first. (Preshaping starts
  // from the folded rest posture, where this would only get in the way.)
  DofVector unfold = DofVector::Zero();
  for (int side = 0; side < 2; ++side) {
    const int elbow = kLeftElbow + 2 * side;
    const double q = s.q[elbow];
    if (facing && std::abs(q) > 2.5 && e.segment<2>(2 * side).norm() > 0.08 &&
        !in.percepts->contact_on_object[kLeftHand + side])
      unfold[elbow] = 0.5 * (std::copysign(2.0, q) - q);
  }
  if (facing) {
    J(5, kBaseHeading) = 1.0;
    e(5) = wrap_angle(std::atan2(to_obj.y(), to_obj.x()) - s.base.theta);
    out.command = damped_solve<6>(J, e, use, lambda);
    out.jacobian = J;
  } else {
    const Eigen::Matrix<double, 5, kDofCount> J5 = J.topRows<5>();
    const Eigen::Matrix<double, 5, 1> e5 = e.head<5>();
    out.command = damped_solve<5>(J5, e5, use, lambda);
    out.jacobian = J5;
  }
  for (int side = 0; side < 2; ++side) {
    const int elbow = kLeftElbow + 2 * side;
    if (unfold[elbow] != 0.0 && use[elbow] != 0.0) out.command[elbow] = unfold[elbow];
  }
}

DofVector mask(std::initializer_list<int> dofs) {
  DofVector m = DofVector::Zero();
  for (int d : dofs) m[d] = 1.0;
  return m;
}

const DofVector kArmsAndForward =
    mask({kBaseForward, kLeftShoulder, kLeftElbow, kRightShoulder, kRightElbow});
const DofVector kArmsOnly = mask({kLeftShoulder, kLeftElbow, kRightShoulder, kRightElbow});
const DofVector kArmsAndBase =
    mask({kBaseForward, kBaseHeading, kLeftShoulder, kLeftElbow, kRightShoulder, kRightElbow});

// Rows of the identity for a set of DOFs: a task that owns those DOFs outright.
void own_dofs(std::initializer_list<int> dofs, TaskJacobian& J) {
  J.resize(int(dofs.size()), kDofCount);
  J.setZero();
  int r = 0;
  for (int d : dofs) J(r++, d) = 1.0;
}

// ---------------------------------------------------------------------------------------------

// phi0: centre the stimulus in both eyes (eye pans) and turn the base towards it (heading).
class Track final : public Primitive {
 public:
  Track() : Primitive("phi0", 0.1) {}
  PrimitivePtr clone() const override { return std::make_shared<Track>(*this); }

 protected:
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    own_dofs({kLeftEye, kRightEye, kBaseHeading}, out.jacobian);
    const Senses& s = *in.senses;
    if (!s.stimulus[kLeft].seen || !s.stimulus[kRight].seen) {
      gamma = Gamma::kNoRef;
      return;
    }
    const double el = s.stimulus[kLeft].bearing, er = s.stimulus[kRight].bearing;
    // The gaze direction relative to the base: the mean of both eyes' lines of sight.
    const double eb = wrap_angle(0.5 * (s.q[kLeftEye] + el + s.q[kRightEye] + er));
    out.command[kLeftEye] = el;
    out.command[kRightEye] = er;
    out.command[kBaseHeading] = eb;
    out.phi = 0.5 * (el * el + er * er + eb * eb);
    out.residual = std::max({std::abs(el), std::abs(er), std::abs(eb)});
    gamma = out.residual <= epsilon() ? Gamma::kConv : Gamma::kNotConv;
  }
};

// search: turn to randomly sampled headings, eyes spread to widen the view, until both eyes see
// the stimulus; as soon as one eye glimpses it, turn that way.
class Search final : public Primitive {
  // Where the constructor declared each parameter: reading one is an index, not a name search.
  struct { ParamSlot spread = 0, reached = 0, min_turn = 0, max_turn = 0; } p_;
 public:
  Search() : Primitive("search", 0.0) {
    p_.spread = declare("spread", 0.6, 0.0, 1.5, "eye pan (rad) each side while looking around");
    p_.reached = declare("reached", 0.3, 0.01, 3.0, "heading error (rad) at which a new heading is sampled");
    p_.min_turn = declare("min_turn", 1.2, 0.0, 6.3, "smallest sampled turn (rad)");
    p_.max_turn = declare("max_turn", 3.2, 0.0, 6.3, "largest sampled turn (rad)");
  }
  PrimitivePtr clone() const override { return std::make_shared<Search>(*this); }
  void reset(uint64_t seed) override {
    Primitive::reset(seed);
    rng_.reseed(Rng::mix(seed, 0x5ea4c4));
    has_target_ = false;
  }

 protected:
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    own_dofs({kBaseHeading, kLeftEye, kRightEye}, out.jacobian);
    const Senses& s = *in.senses;
    const bool left = s.stimulus[kLeft].seen, right = s.stimulus[kRight].seen;
    if (left && right) {
      gamma = Gamma::kConv;  // found: both eyes have it
      has_target_ = false;
      return;
    }
    gamma = Gamma::kNotConv;
    const double heading = s.q[kBaseHeading];
    if (left || right) {
      // One eye sees it: turn towards it, bring both eyes to bear.
      const int e = left ? kLeft : kRight;
      const double rel = wrap_angle(s.q[kLeftEye + e] + s.stimulus[e].bearing);
      target_ = heading + rel;
      has_target_ = true;
      out.command[kLeftEye] = rel - s.q[kLeftEye];
      out.command[kRightEye] = rel - s.q[kRightEye];
    } else {
      if (!has_target_ || std::abs(target_ - heading) < value(p_.reached)) {
        const double turn = rng_.uniform(value(p_.min_turn), value(p_.max_turn));
        target_ = heading + (rng_.uniform() < 0.5 ? -turn : turn);
        has_target_ = true;
      }
      out.command[kLeftEye] = value(p_.spread) - s.q[kLeftEye];
      out.command[kRightEye] = -value(p_.spread) - s.q[kRightEye];
    }
    out.command[kBaseHeading] = clamp_abs(target_ - heading, 1.0);
    out.residual = std::abs(target_ - heading);
  }

 private:
  Rng rng_{0};
  double target_ = 0.0;
  bool has_target_ = false;
};

// phi1: the harmonic-function path planner. A control point (the base centre, or a point carried
// ahead of it such as a grasped object) descends the harmonic potential to the goal: an approach
// ring around the perceived object, or a goal region of the scenario.
class Navigate final : public Primitive {
  // Where the constructor declared each parameter: reading one is an index, not a name search.
  struct {
    ParamSlot goal = 0, region = 0, approach = 0, carry = 0, speed = 0,
        carry_turn = 0, memory = 0, margin = 0, replan = 0, tolerance = 0;
  } p_;
 public:
  Navigate() : Primitive("phi1", 0.05) {
    p_.goal = declare_text("goal", {"object", "region"}, "approach the perceived object, or reach a goal region");
    p_.region = declare("region", 0, 0, 63, "which goal region (index into the scenario's goals) for goal='region'");
    p_.approach = declare("approach", 0.62, 0.3, 2.0, "approach distance (m) from the object centre to the base");
    p_.carry = declare("carry", 0.0, 0.0, 1.0, "control point ahead of the base (m): 0 = base centre");
    p_.speed = declare("speed", 0.9, 0.05, 2.0, "cruise speed (m/s)");
    p_.carry_turn = declare("carry_turn", 0.6, 0.01, 3.0, "largest heading step (rad) per command while carrying");
    p_.memory = declare("memory", 2.0, 0.0, 60.0, "seconds a lost object's last position stays a goal");
    p_.margin = declare("margin", 0.05, 0.0, 1.0, "how far (m) inside a goal region's edge the goal cells end");
    p_.replan = declare("replan", 0.15, 0.0, 1.0, "how far (m) the object estimate must move to plan again");
    // Steering needs the direction of the gradient, not the potential to 4 digits: a looser
    // solve than the planner's default halves the sweeps of every plan.
    p_.tolerance = declare("tolerance", 2e-3, 1e-8, 0.1, "relative change per sweep at which a plan has converged");
    on_params_changed();
  }
  Navigate(const Navigate& o) : Primitive(o), p_(o.p_), planner_(planner_params()) {}
  PrimitivePtr clone() const override { return std::make_shared<Navigate>(*this); }
  void reset(uint64_t seed) override {
    Primitive::reset(seed);
    grid_ = nullptr;
    planned_ = false;
  }

 protected:
  // A new tolerance needs a new planner.
  void on_params_changed() override {
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

  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    own_dofs({kBaseForward, kBaseHeading}, out.jacobian);
    const Vec2 point = classify(in, true, out, gamma);
    if (gamma != Gamma::kNotConv) return;
    const Senses& s = *in.senses;
    const double carry = value(p_.carry);
    out.phi = planner_.potential(point);
    Vec2 dir = planner_.descent(point);
    if (dir.squaredNorm() < 1e-12) dir = (goal_center_ - point).normalized();
    const double slow = std::clamp(out.residual / 0.3, 0.25, 1.0);  // ease into the goal
    const double lookahead = 0.3;                                     // s of motion per command
    const double speed = value(p_.speed) * slow;
    const Vec2 fwd = unit(s.base.theta);
    if (carry > 0.05) {
      // A point ahead of a differential drive moves holonomically: v = u.f, w = u.left / carry.
      // Never back away from what is carried: the body would leave it; turn on the spot instead.
      const Vec2 u = speed * dir;
      out.command[kBaseForward] = std::max(0.0, u.dot(fwd)) * lookahead;
      const double turn = value(p_.carry_turn);
      out.command[kBaseHeading] = clamp_abs(u.dot(perp(fwd)) / carry * lookahead, turn);
      // With the way ahead more than a right angle off, rotate towards it at full rate (the
      // formula above vanishes when the goal lies straight behind).
      if (u.dot(fwd) < 0.0) out.command[kBaseHeading] = u.dot(perp(fwd)) >= 0.0 ? turn : -turn;
    } else {
      const double turn = wrap_angle(std::atan2(dir.y(), dir.x()) - s.base.theta);
      const double along = std::max(0.0, std::cos(turn));
      out.command[kBaseHeading] = clamp_abs(turn, 0.8);
      out.command[kBaseForward] = speed * lookahead * along * along;
    }
  }

 private:
  // The control point: the base centre, or a point carried ahead of it. When carrying, vision
  // says where the carried object really is, if the eyes have it.
  Vec2 control_point(const ControlInput& in) const {
    const Senses& s = *in.senses;
    const double carry = value(p_.carry);
    const Vec2 point = Vec2(s.base.x, s.base.y) + carry * unit(s.base.theta);
    if (carry > 0.05 && in.percepts->object.seen &&
        (in.percepts->object.center - point).norm() < 0.5 * carry)
      return in.percepts->object.center;
    return point;
  }

  // Equation 1 for the planner: NOREF without a goal or when the goal cannot be reached, CONV in
  // the goal, !CONV on the way. With `solve`, the potential is brought up to date for the command.
  Vec2 classify(const ControlInput& in, bool solve, ControlOutput& out, Gamma& gamma) {
    const Vec2 point = control_point(in);
    if (!prepare(in, solve) || !planner_.reachable(point)) {
      gamma = Gamma::kNoRef;
      return point;
    }
    out.residual = goal_distance(point);
    gamma = converged(point) ? Gamma::kConv : Gamma::kNotConv;
    return point;
  }

  // Sets the planner's grid and goal for this tick; false when there is no goal.
  bool prepare(const ControlInput& in, bool solve) {
    if (choice(p_.goal) == "region") {
      const size_t k = size_t(value(p_.region));
      if (k >= in.spec->goals.size()) return false;
      // The region and the grid are fixed for the episode: set them once (the planner would
      // notice that nothing changed, but finding the goal cells each tick is not free).
      if (grid_ != in.grid || !planned_) {
        grid_ = in.grid;
        planned_ = true;
        planner_.set_grid(*in.grid);
        goal_center_ = in.spec->goals[k].center;
        goal_radius_ = in.spec->goals[k].radius;
        planner_.set_goal(goal_center_, std::max(0.5 * in.grid->cell, goal_radius_ - value(p_.margin)));
      }
      return solve ? planner_.update() : planner_.update_reachability();
    }
    VisualObject obj;
    if (!object_estimate(in, value(p_.memory), obj, true)) return false;
    int i, j;
    if (!in.grid->cell_of(obj.center, i, j)) return false;
    // Re-plan only when the estimate has moved by `replan` metres (or more, far away): stereo
    // jitter must not cost a solve per tick. The goal is the disk of radius `approach` around the object; the object
    // itself need not be an obstacle, since the base stops on entering the disk, and keeping the
    // grid fixed lets every re-plan start warm from the last solution.
    if (grid_ != in.grid) {
      grid_ = in.grid;
      planner_.set_grid(*in.grid);
      planned_ = false;
    }
    // Far from the object a shift of the estimate barely turns the path: the tolerance grows
    // with the distance (a quarter of it), so the long approach re-plans rarely.
    const double distance = (obj.center - Vec2(in.senses->base.x, in.senses->base.y)).norm();
    if (!planned_ ||
        (obj.center - goal_center_).norm() > std::max(value(p_.replan), 0.25 * distance)) {
      planned_ = true;
      goal_center_ = obj.center;
      goal_radius_ = value(p_.approach);
      planner_.set_goal(goal_center_, goal_radius_);
    }
    return solve ? planner_.update() : planner_.update_reachability();
  }

  double goal_distance(const Vec2& p) const {
    return std::max(0.0, (p - goal_center_).norm() - goal_radius_);
  }

  bool converged(const Vec2& p) const {
    return (p - goal_center_).norm() <= goal_radius_ + epsilon();
  }

  HarmonicPlanner planner_;
  const OccupancyGrid* grid_ = nullptr;
  bool planned_ = false;
  Vec2 goal_center_ = Vec2::Zero();
  double goal_radius_ = 0.0;
};

// phi2: visual preshape. From the stereo estimate of the object, the body goes to a standoff on
// the line to the object and the hands to a standoff circle at +-spread around it; phi is
// |sum of unit contact normals|^2 over body and hands. Effectors: base forward and arms; the task
// (5 rows) leaves the heading, with the arms compensating, free for a subordinate such as phi4.
// With body = "clear" the body's distance is only bounded below by the standoff (4 rows while
// clear of it), so a subordinate may also move the base along the line, arms compensating. That
// is the freedom phi4 needs: with only the heading free, as in "standoff", a preshape symmetric
// about the line leaves phi4 nothing to gain (turning opens one elbow and closes the other).
class Preshape final : public Primitive {
  // Where the constructor declared each parameter: reading one is an index, not a name search.
  struct {
    ParamSlot standoff = 0, spread = 0, swing = 0, phi_max = 0, reach = 0,
        memory = 0, damping = 0, body = 0;
  } p_;
 public:
  Preshape() : Primitive("phi2", 0.04) {
    p_.standoff = declare("standoff", 0.05, 0.0, 0.5, "gap (m) between the object's surface and the hands and body");
    p_.spread = declare("spread", 1.85, 1.0, 3.0, "angle (rad) of each hand from the body around the object");
    p_.swing = declare("swing", 0.15, 0.0, 1.0, "how far (m) a hand swings out while going round the object");
    p_.phi_max = declare("phi_max", 1.0, 0.0, 9.0, "largest |sum of normals|^2 counted as preshaped");
    p_.reach = declare("reach", 1.25, 0.3, 3.0, "objects farther (m) than this from the base are out of reach");
    p_.memory = declare("memory", 2.0, 0.0, 60.0, "seconds a lost object's last position stays usable");
    p_.damping = declare("damping", 0.05, 0.0, 1.0, "least-squares damping near singular postures");
    p_.body = declare_text("body", {"standoff", "clear"},
                           "body to the standoff, or only kept clear of it (its distance left to a subordinate)");
  }
  PrimitivePtr clone() const override { return std::make_shared<Preshape>(*this); }

 protected:
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    VisualObject obj;
    const Senses& s = *in.senses;
    if (!object_estimate(in, value(p_.memory), obj, true) ||
        (obj.center - Vec2(s.base.x, s.base.y)).norm() > value(p_.reach)) {
      gamma = Gamma::kNoRef;
      return;
    }
    const double r = std::clamp(obj.radius, 0.05, 0.5);
    const double standoff = value(p_.standoff);
    Targets t = grasp_targets(in, obj.center, r + in.robot->base_radius + standoff,
                              r + in.robot->hand_radius + standoff, value(p_.spread),
                              value(p_.swing));
    t.body_keep_out = choice(p_.body) == "clear";
    double worst = 0.0;
    // Hands and body distance, not the heading: it stays free for a subordinate such as phi4.
    reach_targets(in, obj.center, t, false, kArmsAndForward, value(p_.damping), out, worst);
    cap_steps(out.command, 0.3, 0.6);
    const ContactGeometry g = kinematic_contacts(in, obj.center);
    out.phi = grasp_residual(g.normal, g.point, obj.center, r, 0.0, 0.0).phi;  // |sum n|^2
    out.residual = worst;
    gamma = worst <= epsilon() && out.phi <= value(p_.phi_max) ? Gamma::kConv : Gamma::kNotConv;
  }
};

// phi3: contact configuration. Closes body and hands on the object (squeezing slightly inside its
// surface) at +-spread around it, and reports phi = the grasp residual of the touch contacts:
// |sum of unit contact normals|^2 plus the moment residual, less what `friction` lets each contact
// carry along the surface (grasp_residual). CONV needs all three contacts on one object and phi
// at most epsilon for `hold` seconds. Without friction a pentagon's best three faces leave 0.38,
// above any useful epsilon although the grasp holds; with the default 0.25 they leave 0.10.
class Grasp final : public Primitive {
  // Where the constructor declared each parameter: reading one is an index, not a name search.
  struct {
    ParamSlot squeeze = 0, body_squeeze = 0, creep = 0, slide = 0, light = 0,
        spread = 0, swing = 0, moment = 0, friction = 0, reach = 0,
        memory = 0, damping = 0;
  } p_;
 public:
  Grasp() : Primitive("phi3", 0.2) {
    p_.squeeze = declare("squeeze", 0.03, 0.0, 0.2, "how far (m) inside the surface the hands aim");
    p_.body_squeeze = declare("body_squeeze", 0.02, 0.0, 0.2, "how far (m) inside the surface the body aims");
    p_.creep = declare("creep", 0.04, 0.0, 0.3, "step (m) per command of a body or hand closing until it touches");
    p_.slide = declare("slide", 0.5, 0.0, 5.0, "rate at which touching hands slide around to balance the normals");
    p_.light = declare("light", 0.0, 0.0, 0.2, "press depth (m) of a hand while it slides");
    p_.spread = declare("spread", 2.0944, 1.0, 3.0, "angle (rad) of each hand from the body around the object");
    p_.swing = declare("swing", 0.05, 0.0, 1.0, "how far (m) a hand swings out while going round the object");
    p_.moment = declare("moment", 0.25, 0.0, 10.0, "weight of the moment residual in phi");
    p_.friction = declare("friction", 0.25, 0.0, 2.0, "share of each contact's push that friction may carry in phi");
    p_.reach = declare("reach", 1.25, 0.3, 3.0, "objects farther (m) than this from the base are out of reach");
    p_.memory = declare("memory", 2.0, 0.0, 60.0, "seconds a lost object's last position stays usable");
    p_.damping = declare("damping", 0.05, 0.0, 1.0, "least-squares damping near singular postures");
    // A grasp counts once it has held for a few ticks: a hand that closes with a bounce touches
    // for a tick and is off again.
    set_number("hold", 0.1);
  }
  PrimitivePtr clone() const override { return std::make_shared<Grasp>(*this); }

 protected:
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    const Senses& s = *in.senses;
    const Percepts& p = *in.percepts;
    VisualObject obj;
    const bool seen = object_estimate(in, value(p_.memory), obj);
    if (!seen || (obj.center - Vec2(s.base.x, s.base.y)).norm() > value(p_.reach)) {
      gamma = Gamma::kNoRef;
      return;
    }
    const double r = std::clamp(obj.radius, 0.05, 0.5);
    // Guarded moves: vision's size estimate bounds the object, but a polygon's face may lie well
    // inside it, so the body creeps forward until it feels the object, and only then do the hands
    // close in, each creeping until it touches and then pressing `squeeze` into the surface.
    // Squeezing before the body touches would pin the object and keep the body from reaching it.
    const bool body_on = p.contact_on_object[kBody];
    const Vec2 base(s.base.x, s.base.y);
    const double creep = value(p_.creep);
    GraspResidual grasp;  // with all three contacts on the object, computed once per tick
    const double body_distance = body_on ? r + in.robot->base_radius - value(p_.body_squeeze)
                                         : (obj.center - base).norm() - creep;
    Targets t = grasp_targets(in, obj.center, std::min(body_distance, r + in.robot->base_radius),
                              r + in.robot->hand_radius + 0.01, value(p_.spread), value(p_.swing));
    t.body_press = value(p_.body_squeeze);
    if (body_on) {
      // What the contacts leave unbalanced: with all three on the object, the grasp residual
      // (friction included); before that, the sum of the unit normals measured by touch (each
      // from the surface towards its sensor).
      Vec2 sum = Vec2::Zero();
      int touching_count = 0;
      for (int k = 0; k < kTactileCount; ++k)
        if (p.contact_on_object[k] && s.touch[k].index == p.touched_object)
          sum += s.touch[k].normal, ++touching_count;
      double unbalanced = sum.squaredNorm();
      if (touching_count == kTactileCount) {
        Vec2 normal[kTactileCount], point[kTactileCount];
        for (int k = 0; k < kTactileCount; ++k) normal[k] = s.touch[k].normal, point[k] = s.touch[k].point;
        grasp = grasp_residual(normal, point, obj.center, r, value(p_.moment), value(p_.friction));
        sum = grasp.force;
        unbalanced = grasp.phi;
      }
      // Press lightly while the grasp is unbalanced, so the hands can slide, and firmly once it
      // balances.
      const double press = unbalanced > epsilon() ? value(p_.light) : value(p_.squeeze);
      for (int side = 0; side < 2; ++side) {
        const Vec2 hand = in.percepts->arms[side].hand;
        const double now = (hand - obj.center).norm();
        const bool touching = p.contact_on_object[kLeftHand + side];
        if (touching) {
          // Slide the contact along the surface down the gradient of the residual |S|^2 (S the
          // unbalanced force): moving a contact by d(angle) around the object turns its normal by
          // about d(angle), so d|S|^2/d(angle) is about 2 S . perp(n). The step follows the touched surface (its tangent,
          // pressing along its normal), not a circle about the centre, which would cut into a
          // polygon's corner and drag the object round instead of sliding over it.
          const Vec2 n = s.touch[kLeftHand + side].normal;
          const Vec2 tangent(-n.y(), n.x());
          const double slide = std::clamp(-value(p_.slide) * sum.dot(tangent), -0.3, 0.3);
          t.hand[side] = hand + slide * now * tangent - press * n;
        } else {
          const Vec2 out_dir = (t.hand[side] - obj.center).normalized();
          t.hand[side] = obj.center + (now - creep) * out_dir;
        }
      }
    }
    double worst = 0.0;
    // Once the body and a hand touch, the arms alone place the hands: moving the base for them
    // would shove the object with the body or turn it off the object. The base only keeps the
    // body pressed on (its own row: the distance to the object along the heading).
    const bool hand_on = p.contact_on_object[kLeftHand] || p.contact_on_object[kRightHand];
    reach_targets(in, obj.center, t, true, !body_on ? kArmsAndBase : hand_on ? kArmsOnly : kArmsAndForward,
                  value(p_.damping), out, worst);
    if (body_on && hand_on) {
      const Vec2 to_obj = obj.center - base;
      const double d = to_obj.norm();
      const double along = unit(s.base.theta).dot(to_obj) / std::max(d, 1e-6);  // -d(d)/d(forward)
      const double e = std::max(t.body_distance - d, -t.body_press);
      if (along > 0.3) out.command[kBaseForward] = -e / along;
    }
    cap_steps(out.command, 0.15, 0.5);
    // phi from touch when all three contacts are on one object, else from kinematics plus a
    // penalty per missing contact (so phi falls as contacts are made).
    int on = 0;
    for (int k = 0; k < kTactileCount; ++k)
      on += p.contact_on_object[k] && s.touch[k].index == p.touched_object;
    if (on == kTactileCount) {
      out.phi = grasp.phi;  // all three on means the body touches: computed above
    } else {
      const ContactGeometry g = kinematic_contacts(in, obj.center);
      out.phi = grasp_residual(g.normal, g.point, obj.center, r, 0.0, 0.0).phi + (kTactileCount - on);
    }
    out.residual = out.phi;
    gamma = on == kTactileCount && out.phi <= epsilon() ? Gamma::kConv : Gamma::kNotConv;
  }
};

// phi4: kinematic conditioning. phi = sum over arms of cos^2(elbow): zero at the most manipulable
// posture (elbows at +-90 degrees, where L1 L2 |sin(elbow)| peaks). Its command descends phi on the
// elbows; as a subordinate, the projection turns it into base and shoulder motions that keep the
// superior's contacts where they are. It is an optimization, not a constraint: as a superior it
// protects only its gradient direction (a one-row Jacobian).
class Condition final : public Primitive {
  // Where the constructor declared each parameter: reading one is an index, not a name search.
  struct { ParamSlot rate = 0; } p_;
 public:
  Condition() : Primitive("phi4", 0.05) {
    p_.rate = declare("rate", 0.15, 0.0, 5.0, "step per tick per unit gradient (rad)");
  }
  PrimitivePtr clone() const override { return std::make_shared<Condition>(*this); }

 protected:
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    const Senses& s = *in.senses;
    double grad2 = 0.0;
    out.phi = 0.0;
    for (int dof : {int(kLeftElbow), int(kRightElbow)}) {
      const double q = s.q[dof];
      out.phi += std::cos(q) * std::cos(q);
      const double g = -std::sin(2.0 * q);  // d/dq cos^2(q)
      grad2 += g * g;
      out.command[dof] = -value(p_.rate) * g;
    }
    out.jacobian.resize(grad2 > 0.0 ? 1 : 0, kDofCount);
    if (grad2 > 0.0) out.jacobian.row(0) = -out.command.transpose();
    out.residual = std::sqrt(grad2);
    gamma = out.residual <= epsilon() ? Gamma::kConv : Gamma::kNotConv;
  }
};

// phi5: dynamic contact adjustment. With all three contacts on the object, each hand presses
// `squeeze` into the surface along its touch normal, and leads by `lead` seconds of the base's
// acceleration so the grasp carries the object's inertia; its task is the hands' position in the
// base frame (the arm joints). Each hand's press fades as its contact force nears `press`, so the
// grasp regulates force rather than position. NOREF as soon as a contact is lost.
class Hold final : public Primitive {
  // Where the constructor declared each parameter: reading one is an index, not a name search.
  struct { ParamSlot squeeze = 0, pull = 0, press = 0, lead = 0, moment = 0, friction = 0, damping = 0; } p_;
 public:
  Hold() : Primitive("phi5", 0.3) {
    p_.squeeze = declare("squeeze", 0.03, 0.0, 0.2, "press depth (m) of each hand along its contact normal");
    p_.pull = declare("pull", 0.03, 0.0, 0.2, "how far (m) the hands draw the object onto the body");
    p_.press = declare("press", 50.0, 0.0, 1000.0,
                       "contact force (N) each hand presses towards: its squeeze, and its pull while the "
                       "body touches the object, fade as its force nears this (0: never)");
    p_.lead = declare("lead", 0.04, 0.0, 1.0, "hand lead per unit of base acceleration (m per m/s^2)");
    p_.moment = declare("moment", 0.25, 0.0, 10.0, "weight of the moment residual in phi");
    p_.friction = declare("friction", 0.5, 0.0, 2.0, "share of each contact's push that friction may carry in phi");
    p_.damping = declare("damping", 0.05, 0.0, 1.0, "least-squares damping near singular postures");
  }
  PrimitivePtr clone() const override { return std::make_shared<Hold>(*this); }
  void reset(uint64_t seed) override {
    Primitive::reset(seed);
    has_velocity_ = false;
  }

 protected:
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    own_dofs({kLeftShoulder, kLeftElbow, kRightShoulder, kRightElbow}, out.jacobian);
    const Senses& s = *in.senses;
    const Percepts& p = *in.percepts;
    // The base's acceleration from its velocity senses (world frame).
    const Vec2 v = s.qdot[kBaseForward] * unit(s.base.theta);
    const Vec2 accel = has_velocity_ ? Vec2((v - last_velocity_) / in.dt) : Vec2::Zero();
    last_velocity_ = v;
    has_velocity_ = true;
    bool on[kTactileCount];
    for (int k = 0; k < kTactileCount; ++k)
      on[k] = p.contact_on_object[k] && s.touch[k].index == p.touched_object;
    // NOREF as soon as a contact is lost; but while both hands still hold the object the hands
    // keep pressing and draw it back onto the body, so a grasp that slipped can recover.
    if (!on[kLeftHand] || !on[kRightHand]) {
      gamma = Gamma::kNoRef;
      return;
    }
    Eigen::Matrix<double, 4, kDofCount> J;
    Eigen::Matrix<double, 4, 1> e;
    Eigen::Matrix<double, 2, kDofCount> Jh;
    // From the object towards the body: the body's touch normal, or, with the body off the
    // object, the direction from the hands' midpoint to the base.
    const Vec2 base(s.base.x, s.base.y);
    const Vec2 mid = 0.5 * (in.percepts->arms[kLeft].hand + in.percepts->arms[kRight].hand);
    const Vec2 to_body = on[kBody] ? s.touch[kBody].normal : Vec2((base - mid).normalized());
    const double pull = on[kBody] ? value(p_.pull) : 2.0 * value(p_.pull);
    for (int side = 0; side < 2; ++side) {
      hand_jacobian(in, side, Jh);
      J.middleRows<2>(2 * side) = Jh;
      const Touch& touch = s.touch[kLeftHand + side];
      // Press into the surface, draw the object onto the body (so its contact is kept while the
      // base pulls and turns), and lead with the base's acceleration where that pushes inward.
      // The press and the pull fade as the hand's contact force nears `press`. The arms are rate
      // servos with torque limits: a step that never fades drives both hands to their limits,
      // which differ with the arms' postures, and in every turn the difference walks the object
      // round the body until a shoulder reaches its stop. Fading, a hand the object pushes into
      // stands and resists (up to its limit), and a hand the object leaves presses after it.
      // With the body off the object the pull does not fade: what the hands feel then is their
      // own squeeze, not the object resting on the body, and only the pull brings it back.
      const double press = value(p_.press);
      const double fade = press > 0.0 ? std::clamp(1.0 - touch.force / press, 0.0, 1.0) : 1.0;
      Vec2 err = -fade * value(p_.squeeze) * touch.normal + (on[kBody] ? fade : 1.0) * pull * to_body;
      const double inward = -accel.dot(touch.normal);
      if (inward > 0) err += -value(p_.lead) * inward * touch.normal;
      e.segment<2>(2 * side) = err;
    }
    static const DofVector arms = mask({kLeftShoulder, kLeftElbow, kRightShoulder, kRightElbow});
    out.command = damped_solve<4>(J, e, arms, value(p_.damping));
    cap_steps(out.command, 0.1, 0.3);
    Vec2 normal[kTactileCount], point[kTactileCount];
    for (int k = 0; k < kTactileCount; ++k) normal[k] = s.touch[k].normal, point[k] = s.touch[k].point;
    VisualObject obj;
    const Vec2 center = object_estimate(in, 1e9, obj)
                            ? obj.center
                            : Vec2((point[0] + point[1] + point[2]) / 3.0);
    out.phi = grasp_residual(normal, point, center, std::max(obj.radius, 0.1), value(p_.moment),
                             value(p_.friction)).phi;
    out.residual = out.phi;
    if (!on[kBody]) {
      gamma = Gamma::kNoRef;
      return;
    }
    gamma = out.phi <= epsilon() ? Gamma::kConv : Gamma::kNotConv;
  }

 private:
  Vec2 last_velocity_ = Vec2::Zero();
  bool has_velocity_ = false;
};

}  // namespace

// ---------------------------------------------------------------------------------------------

Primitive::Primitive(std::string kind, double default_epsilon) : kind_(std::move(kind)) {
  set_name(kind_);
  declare("epsilon", default_epsilon, 0.0, 1e6, "convergence threshold on the residual");
  declare("gain", 1.0, 0.0, 100.0, "scales the command");
  declare("hold", 0.0, 0.0, 60.0, "seconds the condition must hold before gamma is CONV");
  declare("stall", 0.01, 0.0, 1e6,
          "as a subordinate, converged once its projected command, or the change of its potential "
          "over `plateau` seconds, is this small");
  declare("plateau", 0.3, 0.0, 60.0, "seconds over which a subordinate's potential must settle");
}

Primitive::ParamSlot Primitive::declare(const std::string& name, double value, double min, double max,
                                        const std::string& help) {
  ParamDef d;
  d.name = name, d.value = value, d.min = min, d.max = max, d.help = help;
  defs_.push_back(d);
  on_param(name, value);
  return defs_.size() - 1;
}

Primitive::ParamSlot Primitive::declare_text(const std::string& name, std::vector<std::string> choices,
                                             const std::string& help) {
  ParamDef d;
  d.name = name, d.choices = std::move(choices), d.help = help;
  d.text = d.choices.front();
  defs_.push_back(d);
  return defs_.size() - 1;
}

void Primitive::on_param(const std::string& name, double value) {
  if (name == "epsilon") params().epsilon = value;
  if (name == "gain") params().gain = value;
  if (name == "hold") params().hold = value;
  if (name == "stall") params().stall = value;
  if (name == "plateau") params().plateau = value;
}

ParamDef& Primitive::find(const std::string& name) {
  for (auto& d : defs_)
    if (d.name == name) return d;
  std::ostringstream os;
  os << kind_ << ": unknown parameter '" << name << "'; known parameters:";
  for (size_t i = 0; i < defs_.size(); ++i) os << (i ? ", " : " ") << defs_[i].name;
  throw Error(os.str());
}

const ParamDef& Primitive::find(const std::string& name) const {
  return const_cast<Primitive*>(this)->find(name);
}

void Primitive::set_number(const std::string& name, double value) {
  ParamDef& d = find(name);
  if (!d.choices.empty())
    throw Error(kind_ + ": parameter '" + name + "' takes a string, one of: " + [&] {
      std::string s;
      for (const auto& c : d.choices) s += (s.empty() ? "" : ", ") + c;
      return s;
    }());
  if (!std::isfinite(value) || value < d.min || value > d.max) {
    std::ostringstream os;
    os << kind_ << ": parameter '" << name << "' must be a number in [" << d.min << ", " << d.max
       << "], got " << value;
    throw Error(os.str());
  }
  d.value = value;
  on_param(name, value);
  on_params_changed();
}

void Primitive::set_text(const std::string& name, const std::string& value) {
  ParamDef& d = find(name);
  if (d.choices.empty())
    throw Error(kind_ + ": parameter '" + name + "' takes a number, not '" + value + "'");
  if (std::find(d.choices.begin(), d.choices.end(), value) == d.choices.end()) {
    std::string s;
    for (const auto& c : d.choices) s += (s.empty() ? "" : ", ") + c;
    throw Error(kind_ + ": parameter '" + name + "' must be one of " + s + ", got '" + value + "'");
  }
  d.text = value;
  on_params_changed();
}

double Primitive::number(const std::string& name) const {
  const ParamDef& d = find(name);
  return d.value;
}

const std::string& Primitive::text(const std::string& name) const { return find(name).text; }

PrimitivePtr make_primitive(const std::string& name) {
  if (name == "phi0") return std::make_shared<Track>();
  if (name == "search") return std::make_shared<Search>();
  if (name == "phi1") return std::make_shared<Navigate>();
  if (name == "phi2") return std::make_shared<Preshape>();
  if (name == "phi3") return std::make_shared<Grasp>();
  if (name == "phi4") return std::make_shared<Condition>();
  if (name == "phi5") return std::make_shared<Hold>();
  std::string known;
  for (const auto& n : primitive_names()) known += (known.empty() ? "" : ", ") + n;
  throw Error("unknown primitive '" + name + "'; known primitives: " + known);
}

const std::vector<std::string>& primitive_names() {
  static const std::vector<std::string> names = {"phi0", "search", "phi1", "phi2",
                                                 "phi3", "phi4",   "phi5"};
  return names;
}

const std::map<std::string, std::string>& primitive_descriptions() {
  static const std::map<std::string, std::string> d = {
      {"phi0", "track: centre the stimulus in both eyes and turn the base to it"},
      {"search", "turn to sampled headings until both eyes see the stimulus"},
      {"phi1", "harmonic-function path planner to the object's approach ring or a goal region"},
      {"phi2", "visual preshape: body and hands to a standoff around the object"},
      {"phi3", "contact configuration: close on the object, balance the touch normals"},
      {"phi4", "kinematic conditioning: most manipulable arm posture (subordinate)"},
      {"phi5", "dynamic contact adjustment: hold the grasp while the base accelerates"}};
  return d;
}

}  // namespace roger
