#include "core/body.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/shape.h"
#include "core/text.h"

namespace roger {

Camera camera_of(const EyeParams& eyes) {
  Camera c;
  c.pixels = eyes.pixels;
  c.half_fov = 0.5 * eyes.fov;
  c.principal = 0.5 * (eyes.pixels - 1);
  const double focal = 0.5 * eyes.pixels / std::tan(c.half_fov);
  const double whole = std::round(focal);
  c.focal = std::abs(focal - whole) <= 1e-9 ? whole : focal;
  return c;
}

Vec2 hand_in_base(const RobotParams& body, int side, double shoulder, double elbow) {
  const double sy = side == kLeft ? body.shoulder_y : -body.shoulder_y;
  const double a1 = shoulder, a2 = a1 + elbow;
  const Vec2 elbow_point = Vec2(0.0, sy) + body.link_length[0] * Vec2(std::cos(a1), std::sin(a1));
  return elbow_point + body.link_length[1] * Vec2(std::cos(a2), std::sin(a2));
}

namespace {

struct Angles {
  double shoulder, elbow;
};

// The left arm's joint angles that put its hand nearest `target` (base frame), the elbow bent
// inwards as the default fold's, within the elbow's range.
Angles left_arm_towards(const RobotParams& b, const Vec2& target) {
  const double l1 = b.link_length[0], l2 = b.link_length[1];
  const Vec2 d = target - Vec2(0.0, b.shoulder_y);
  const double c = std::clamp((d.squaredNorm() - l1 * l1 - l2 * l2) / (2.0 * l1 * l2), -1.0, 1.0);
  const double elbow = std::clamp(-std::acos(c), b.elbow_min, b.elbow_max);
  const double shoulder =
      std::atan2(d.y(), d.x()) - std::atan2(l2 * std::sin(elbow), l1 + l2 * std::cos(elbow));
  return {wrap_angle(shoulder), elbow};
}

// Where the folded left hand should be: the default fold's hand, moved out by as much as the base
// and the hand have grown, so it keeps the same gap beside the body.
Vec2 fold_target(const RobotParams& b) {
  const RobotParams ref;
  const RobotStart fold;
  const Vec2 h = hand_in_base(ref, kLeft, fold.left_shoulder, fold.left_elbow);
  return h + Vec2(0.0, (b.base_radius - ref.base_radius) + (b.hand_radius - ref.hand_radius));
}

// The fold posture: the default's angles plus the difference between the inverse kinematics of
// this body and of the default one (exactly the default's for the default body).
Angles fold_posture(const RobotParams& b) {
  const RobotParams ref;
  const RobotStart fold;
  const Angles mine = left_arm_towards(b, fold_target(b));
  const Angles theirs = left_arm_towards(ref, fold_target(ref));
  // An elbow the inverse kinematics clamped to its range's end lands there give or take a rounding
  // step, which must not put it outside (found by a probe: elbow {min = -0.1} refused for
  // "-0.1000000000000001"); a fold really outside a range stays outside, and is refused.
  const auto onto = [](double angle, double lo, double hi) {
    constexpr double rounding = 1e-12;
    return angle < lo && angle > lo - rounding ? lo : angle > hi && angle < hi + rounding ? hi : angle;
  };
  return {onto(fold.left_shoulder + (mine.shoulder - theirs.shoulder), b.shoulder_min, b.shoulder_max),
          onto(fold.left_elbow + (mine.elbow - theirs.elbow), b.elbow_min, b.elbow_max)};
}

// The folded footprint's half width: the base's radius or the folded hands' outer edge.
double folded_half_width(const RobotParams& b, const Angles& fold) {
  const Vec2 hand = hand_in_base(b, kLeft, fold.shoulder, fold.elbow);
  return std::max(b.base_radius, std::abs(hand.y()) + b.hand_radius);
}

}  // namespace

RobotStart folded_start(const RobotParams& body, const Pose& pose) {
  const Angles fold = fold_posture(body);
  RobotStart s;
  s.pose = pose;
  s.left_shoulder = fold.shoulder, s.left_elbow = fold.elbow;
  s.right_shoulder = -fold.shoulder, s.right_elbow = -fold.elbow;
  return s;
}

BodyMetrics body_metrics(const RobotParams& b, const EyeParams& eyes) {
  const RobotParams r0;
  const EyeParams e0;
  const BodyMetrics tuned;
  const Angles fold = fold_posture(b);
  const double grown_base = b.base_radius - r0.base_radius;
  const double grown_span = (b.link_length[0] + b.link_length[1]) - (r0.link_length[0] + r0.link_length[1]);
  const double grown_width = folded_half_width(b, fold) - folded_half_width(r0, fold_posture(r0));
  BodyMetrics m;
  m.fold_shoulder = fold.shoulder, m.fold_elbow = fold.elbow;
  // The approach ring keeps its gap between the base's front and the object.
  m.approach = tuned.approach + grown_base;
  // Out of reach: the arms' span and a quarter metre more.
  m.preshape_reach = tuned.preshape_reach + grown_span;
  // Just beyond the approach ring.
  m.grasp_reach = tuned.grasp_reach + (m.approach - tuned.approach);
  // The folded footprint's half width (a centimetre more), for the planner's grid; other objects
  // grown by it and the preshaped hands' swing; a squeeze keeps the base itself off them.
  m.grid_inflate = tuned.grid_inflate + grown_width;
  m.objects_growth = tuned.objects_growth + grown_width;
  m.squeeze = tuned.squeeze + grown_base;
  // Backing off from a released object: the base's front clears it by the same gap.
  m.release_distance = tuned.release_distance + grown_base;
  // The search's half view is a share of the eyes' half field of view.
  m.half_view = tuned.half_view * (eyes.fov / e0.fov);
  // A sideways step of the base's diameter less 2 cm (0.3 m for the 0.32 m base).
  m.sidestep = tuned.sidestep + 2.0 * grown_base;
  // The grasped object sits against the base's front.
  m.carry = tuned.carry + grown_base;
  const Vec2 hand = hand_in_base(b, kLeft, fold.shoulder, fold.elbow);
  m.footprint_radius = std::max(b.base_radius, hand.norm() + b.hand_radius);
  return m;
}

const std::vector<std::pair<std::string, int>>& lockable_joints() {
  static const std::vector<std::pair<std::string, int>> joints = {
      {"left_eye", kLeftEye},           {"right_eye", kRightEye},
      {"left_shoulder", kLeftShoulder}, {"left_elbow", kLeftElbow},
      {"right_shoulder", kRightShoulder}, {"right_elbow", kRightElbow}};
  return joints;
}

namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// Problems of the folded posture: joint limits, a hand on the base, the hands on each other.
void fold_problems(const RobotParams& b, std::vector<std::string>& out) {
  const Angles fold = fold_posture(b);
  // Each joint whose range misses its folded angle, with the range: what to widen.
  // The angle with as many digits as set it apart from the bound it passes (found by a probe:
  // "elbow -0.1 outside its range [-0.1, 0.1]").
  const auto apart = [](double v, double bound) {
    char text[40], other[40];
    for (int digits = 6;; ++digits) {
      std::snprintf(text, sizeof text, "%.*g", digits, v);
      std::snprintf(other, sizeof other, "%.*g", digits, bound);
      if (std::string(text) != other || digits >= 17) return std::string(text);
    }
  };
  const auto outside = [&](const char* joint, double angle, double lo, double hi) {
    return angle < lo || angle > hi ? std::string(joint) + " " + apart(angle, angle < lo ? lo : hi) +
                                          " outside its range [" + num(lo) + ", " + num(hi) + "]"
                                    : std::string();
  };
  std::vector<std::string> joints;
  for (std::string j : {outside("shoulder", fold.shoulder, b.shoulder_min, b.shoulder_max),
                        outside("elbow", fold.elbow, b.elbow_min, b.elbow_max)})
    if (!j.empty()) joints.push_back(j);
  if (!joints.empty())
    out.push_back("the folded posture (shoulder " + num(fold.shoulder) + ", elbow " + num(fold.elbow) +
                  " rad, where the arms start and carry) lies outside the joints' ranges: " + join(joints, "; ") +
                  " rad (body.shoulder and body.elbow set them)");
  const Vec2 hand = hand_in_base(b, kLeft, fold.shoulder, fold.elbow);
  const double gap = hand.norm() - b.base_radius - b.hand_radius;
  if (gap < 0.01)
    out.push_back("the hands cannot fold clear of the base: a folded hand's edge is " + num(gap) +
                  " m from the base's (at least 0.01 m needed; longer upper arm, shorter forearm or a "
                  "smaller hand)");
  if (std::abs(hand.y()) < b.hand_radius + 0.005)
    out.push_back("the folded hands touch each other");
}

}  // namespace

std::vector<std::string> body_problems(const RobotParams& b, const EyeParams& eyes) {
  std::vector<std::string> out;
  const std::pair<const char*, double> positive[] = {
      {"upper_arm", b.link_length[0]}, {"forearm", b.link_length[1]}, {"base_radius", b.base_radius},
      {"axle_half_width", b.axle_half_width}, {"base_mass", b.base_mass}, {"link_mass", b.link_mass},
      {"hand_radius", b.hand_radius}, {"hand_mass", b.hand_mass}, {"eye_y", b.eye_y},
      {"eye_pan", b.eye_pan_limit}};
  for (const auto& [name, v] : positive)
    if (!(v > 0.0) || !std::isfinite(v)) out.push_back(std::string(name) + " must be positive, got " + num(v));
  if (!(b.shoulder_min < b.shoulder_max)) out.push_back("shoulder's min must be below its max");
  if (!(b.elbow_min < b.elbow_max)) out.push_back("elbow's min must be below its max");
  if (b.eye_y >= b.base_radius)
    out.push_back("eye_y (" + num(b.eye_y) + " m) must lie inside the base (below base_radius " + num(b.base_radius) +
                  "): a smaller eye_y or a larger base_radius");
  if (eyes.pixels < kMinPixels || eyes.pixels > kMaxPixels)
    out.push_back("eyes.pixels must be within [" + std::to_string(kMinPixels) + ", " +
                  std::to_string(kMaxPixels) + "], got " + std::to_string(eyes.pixels));
  if (!(eyes.fov >= kMinFov && eyes.fov <= kMaxFov))
    out.push_back("eyes.fov must be within [" + num(kMinFov) + ", " + num(kMaxFov) + "] rad, got " + num(eyes.fov));
  if (out.empty()) fold_problems(b, out);
  return out;
}

}  // namespace roger
