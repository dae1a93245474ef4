// primitives_contact.cpp: the contact geometry the grasp family (phi2, phi3, phi5) shares: the
// grasp residual of three contacts, the contacts by kinematics, and the targets of a three-contact
// configuration with the least-squares command that reaches them.
#include <algorithm>
#include <cmath>

#include "control/primitives_internal.h"
#include "core/shape.h"

namespace roger {

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

namespace primitives_internal {

ContactGeometry kinematic_contacts(const ControlInput& in, const Vec2& center) {
  ContactGeometry g;
  const SenseReadings& s = *in.senses;
  g.point[kBody] = Vec2(s.base.x, s.base.y);
  g.point[kLeftHand] = in.percepts->arms[kLeft].hand;
  g.point[kRightHand] = in.percepts->arms[kRight].hand;
  for (int t = 0; t < kTactileCount; ++t) {
    const Vec2 d = g.point[t] - center;
    g.normal[t] = d.norm() > 1e-9 ? Vec2(d.normalized()) : Vec2(1.0, 0.0);
  }
  return g;
}

Targets grasp_targets(const ControlInput& in, const Vec2& center, double body_distance,
                      double hand_radius, double spread, double swing) {
  const SenseReadings& s = *in.senses;
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

double reach_errors(const ControlInput& in, const Vec2& center, const Targets& t,
                    Eigen::Matrix<double, 6, 1>& e, bool& body_row) {
  const SenseReadings& s = *in.senses;
  double worst = 0.0;
  for (int side = 0; side < 2; ++side) {
    const Vec2 err = t.hand[side] - in.percepts->arms[side].hand;
    e.segment<2>(2 * side) = err;
    worst = std::max(worst, err.norm());
  }
  const Vec2 base(s.base.x, s.base.y);
  e(4) = t.body_distance - (center - base).norm();
  // Touch overrides vision: once the body feels the object it is there, whatever the estimate of
  // the object's size says (a polygon's corner may be nearer than its estimated radius); pushing
  // on would only shove the object away.
  if (in.percepts->contact_on_object[kBody]) e(4) = std::max(e(4), -t.body_press);
  body_row = true;
  if (t.body_keep_out) {
    // A zero row leaves the command alone and is skipped by the nullspace projection. Once pushing
    // back, aim 1 cm beyond the bound: approaching it only asymptotically would keep the row
    // active, and with it the body's distance locked, for ever.
    if (e(4) <= 0.0) body_row = false, e(4) = 0.0;
    else e(4) += 0.01;
  }
  return std::max(worst, std::abs(e(4)));
}

void reach_targets(const ControlInput& in, const Vec2& center, const Targets& t, bool facing,
                   const DofVector& use, double lambda, ControlOutput& out, double& worst_error) {
  const SenseReadings& s = *in.senses;
  Eigen::Matrix<double, 6, kDofCount> J = Eigen::Matrix<double, 6, kDofCount>::Zero();
  Eigen::Matrix<double, 6, 1> e = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 2, kDofCount> Jh;
  bool body_row = true;
  worst_error = reach_errors(in, center, t, e, body_row);
  for (int side = 0; side < 2; ++side) {
    hand_jacobian(in, side, Jh);
    J.middleRows<2>(2 * side) = Jh;
  }
  // The distance to the object centre, which driving forward shortens by cos(bearing), and the
  // bearing itself, which turning removes.
  const Vec2 base(s.base.x, s.base.y);
  const Vec2 to_obj = center - base;
  const double d = to_obj.norm();
  if (body_row) J(4, kBaseForward) = -unit(s.base.theta).dot(to_obj) / std::max(d, 1e-6);
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

}  // namespace primitives_internal
}  // namespace roger
