// primitives_internal.h: what the primitives' source files share and the public header does not
// show: the kinematic helpers, the contact geometry of the grasp family, and each primitive's
// factory for the registry in primitives.cpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <initializer_list>

#include <Eigen/Cholesky>

#include "control/primitives.h"
#include "core/shape.h"

namespace roger {
namespace primitives_internal {

// The vector v turned a quarter turn anticlockwise.
inline Vec2 perp(const Vec2& v) { return {-v.y(), v.x()}; }
// The unit vector at `angle` (remembered per thread for the last angle: see heading_vector).
inline Vec2 unit(double angle) { return heading_vector(angle); }
// v clamped to [-limit, limit].
inline double clamp_abs(double v, double limit) { return std::clamp(v, -limit, limit); }

// Where the object is believed to be: this tick's estimate, or the last one if it is recent. With
// `vision_only`, touch-based estimates are ignored: controllers that work at a distance (approach,
// preshape) keep one consistent frame instead of flipping between what vision and a grazing
// contact say about a polygon.
bool object_estimate(const ControlInput& in, double memory, VisualObject& out,
                     bool vision_only = false);

// Jacobian columns of a world point carried by one arm's hand or by the base, over the 8 DOFs.
// Moving the base forward carries every point along the heading; turning the base swings it about
// the base centre; each arm joint swings the hand about that joint.
inline void hand_jacobian(const ControlInput& in, int side,
                          Eigen::Matrix<double, 2, kDofCount>& J) {
  const SenseReadings& s = *in.senses;
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
inline void cap_steps(DofVector& dq, double linear, double angular) {
  dq[kBaseForward] = clamp_abs(dq[kBaseForward], linear);
  for (int i = 1; i < kDofCount; ++i) dq[i] = clamp_abs(dq[i], angular);
}

// A mask over the DOFs: 1 for those listed, 0 for the others.
DofVector mask(std::initializer_list<int> dofs);

// Rows of the identity for a set of DOFs: a task that owns those DOFs outright.
void own_dofs(std::initializer_list<int> dofs, TaskJacobian& J);

// ---- The grasp family's contact geometry (primitives_contact.cpp) ----

// The three contact locations and the unit normals from the object centre towards each, from
// kinematics (body centre, hand centres).
struct ContactGeometry {
  Vec2 point[kTactileCount];
  Vec2 normal[kTactileCount];
};

// The contacts of body and hands by kinematics, with normals from `center` towards each.
ContactGeometry kinematic_contacts(const ControlInput& in, const Vec2& center);

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
                      double hand_radius, double spread, double swing);

// Builds the task of placing the hands and the body's distance to the object (and, with `facing`,
// the heading facing it) and its damped least-squares command towards the targets. The Jacobian
// covers every DOF that moves the task, so a subordinate's projection respects it; the command
// uses only the DOFs in `use`.
void reach_targets(const ControlInput& in, const Vec2& center, const Targets& t, bool facing,
                   const DofVector& use, double lambda, ControlOutput& out, double& worst_error);

// The errors of that task without its Jacobian or command: the hands' (rows 0-3) and the body's
// distance (row 4, zero when t.body_keep_out leaves it free). Returns the largest, which is what
// reach_targets reports as worst_error; `body_row` says whether row 4 is in the task.
double reach_errors(const ControlInput& in, const Vec2& center, const Targets& t,
                    Eigen::Matrix<double, 6, 1>& e, bool& body_row);

// ---- Each primitive's factory, for make_primitive ----

PrimitivePtr make_track();      // phi0 (primitives_simple.cpp)
PrimitivePtr make_search();     // search (primitives_simple.cpp)
PrimitivePtr make_navigate();   // phi1 (primitives_navigate.cpp)
PrimitivePtr make_preshape();   // phi2 (primitives_grasp.cpp)
PrimitivePtr make_grasp();      // phi3 (primitives_grasp.cpp)
PrimitivePtr make_condition();  // phi4 (primitives_simple.cpp)
PrimitivePtr make_hold();       // phi5 (primitives_grasp.cpp)
PrimitivePtr make_release();    // release (primitives_release.cpp)

}  // namespace primitives_internal
}  // namespace roger
