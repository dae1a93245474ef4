// percepts.cpp: the percepts of one tick (the object's estimate from stereo or touch, the stereo
// filter under noise, the arms' kinematics) and the map of movable objects.
#include "perception/percepts.h"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>

#include "core/shape.h"

namespace roger {

namespace {

// How many touch sensors are on object i (`on`: which sensors touch an object at all).
int contacts_on(const SenseReadings& s, const bool (&on)[kTactileCount], int i) {
  int n = 0;
  for (int t = 0; t < kTactileCount; ++t) n += on[t] && s.touch[t].index == i;
  return n;
}

// The object most sensors touch among those `eligible` accepts (the lowest index on a tie), or -1.
template <class Eligible>
int most_touched(const SenseReadings& s, const bool (&on)[kTactileCount], Eligible eligible) {
  int best = -1, most = 0;
  for (int t = 0; t < kTactileCount; ++t) {
    const int i = s.touch[t].index;
    if (!on[t] || i < 0 || !eligible(i)) continue;
    const int n = contacts_on(s, on, i);
    if (n > most || (n == most && i < best)) most = n, best = i;
  }
  return best;
}

}  // namespace

void PoseFilter::reset(bool joints, bool base) {
  joints_ = joints, base_ = base, valid_ = false;
}

void PoseFilter::apply(SenseReadings& s, double dt) {
  if (!valid_) {
    q_ = s.q, qdot_ = s.qdot, pose_ = s.base, valid_ = true;
    return;
  }
  constexpr double g = kPoseGain;
  // The motion since the last tick, from the mean of its rates and this tick's (trapezoidal).
  const DofVector moved = 0.5 * dt * (qdot_ + s.qdot);
  qdot_ = s.qdot;
  if (joints_) {
    for (int k = kLeftEye; k < kDofCount; ++k) {
      q_[k] += moved[k];
      q_[k] += g * (s.q[k] - q_[k]);
      s.q[k] = q_[k];
    }
  }
  if (base_) {
    const double heading = pose_.theta + 0.5 * moved[kBaseHeading];  // mid-tick heading
    pose_.x += moved[kBaseForward] * std::cos(heading);
    pose_.y += moved[kBaseForward] * std::sin(heading);
    pose_.theta = wrap_angle(pose_.theta + moved[kBaseHeading]);
    q_[kBaseForward] += moved[kBaseForward];
    pose_.x += g * (s.base.x - pose_.x);
    pose_.y += g * (s.base.y - pose_.y);
    pose_.theta = wrap_angle(pose_.theta + g * wrap_angle(s.base.theta - pose_.theta));
    q_[kBaseForward] += g * (s.q[kBaseForward] - q_[kBaseForward]);
    s.base = pose_;
    s.q[kBaseForward] = q_[kBaseForward];
    s.q[kBaseHeading] = pose_.theta;
  }
}

Vec2 StereoFilter::fuse(const Vec2& z, const Vec2& eyes_mid, double baseline, const StereoNoise& noise, double t) {
  // The fix's covariance: along the line of sight the range error d^2 / b times the vergence's
  // (two bearings' worth); across it d times one bearing's, and the base's own error in both.
  // The range is the estimate's where there is one: weighing each fix by its own range would
  // favour the fixes that happen to fall short (their variance is smaller) and pull it closer.
  const Vec2 ray = (valid ? center : z) - eyes_mid;
  const double d = std::max(ray.norm(), 1e-6);
  const Vec2 along = ray / d, across(-along.y(), along.x());
  const double vergence = std::sqrt(2.0) * noise.bearing;
  const double sr = d * d / std::max(baseline, 1e-6) * vergence, sl = d * std::hypot(noise.bearing, noise.base);
  const Eigen::Matrix2d R = sr * sr * along * along.transpose() + sl * sl * across * across.transpose() +
                            noise.base * noise.base * Eigen::Matrix2d::Identity();
  // An object lost from view for a while, or pushed, may be elsewhere: it moves at up to about
  // kDrift m/s; an estimate older than kForget seconds starts over. A fix more than four standard
  // deviations off is an outlier and left out, unless it is the third in a row: the object may
  // not be where it was, so that one is fused (starting over from it did worse under 4M).
  constexpr double kDrift = 0.3, kForget = 1.0, kGate = 16.0;
  if (valid && t - time <= kForget) {
    const Eigen::Matrix2d P = covariance + kDrift * kDrift * (t - time) * Eigen::Matrix2d::Identity();
    const Eigen::Matrix2d S_inv = (P + R).inverse();
    const Vec2 innovation = z - center;
    if (innovation.dot(S_inv * innovation) > kGate && ++rejected < 3) return center;
    const Eigen::Matrix2d K = P * S_inv;
    center += K * innovation;
    covariance = (Eigen::Matrix2d::Identity() - K) * P;
  } else {
    center = z, covariance = R;
  }
  valid = true, time = t, rejected = 0;
  return center;
}

void Percepts::update(const SenseReadings& s, const RobotParams& robot, const std::vector<MapObject>* objects,
                      const Colour* stimulus, const StereoNoise& noise) {
  object = VisualObject{};
  // A stimulus that runs off either image has no trustworthy centre there: no stereo fix then.
  if (s.stereo_valid && !s.stimulus[0].clipped && !s.stimulus[1].clipped) {
    object.seen = true;
    object.center = s.stimulus_world;
    object.center_base = s.stimulus_base;
    if (noise.any()) {
      object.center = stereo.fuse(s.stimulus_world, to_world(s.base, Vec2::Zero()), 2.0 * robot.eye_y, noise, s.time);
      object.center_base = to_local(s.base, object.center);
    }
    // Size from the angular width in the eye with the wider view of it: r = d sin(half width).
    double half = 0.0;
    for (int e = 0; e < 2; ++e)
      if (s.stimulus[e].seen) half = std::max(half, s.stimulus[e].half_width);
    const double range = object.center_base.norm();
    object.radius = range * std::sin(half);
    remembered = vision = object;
    remembered_time = vision_time = s.time;
  }
  for (int side = 0; side < 2; ++side)
    arms[side] = arm_forward_kinematics(robot, s.base, side, s.q[kLeftShoulder + 2 * side],
                                        s.q[kLeftElbow + 2 * side]);
  for (int t = 0; t < kTactileCount; ++t) {
    const Touch& touch = s.touch[t];
    contact_on_object[t] = touch.contact && touch.kind == SurfaceKind::kObject;
  }
  // The object most sensors touch (the lowest index on a tie), whatever the number of objects.
  touched_object = most_touched(s, contact_on_object, [](int) { return true; });
  // Close up, vision is poor (the object fills the eyes' view, and a polygon shows each eye other
  // corners) but touch knows where the surface is: each contact on the object puts its centre one
  // (visually estimated) radius behind the contact point, against the contact normal.
  const int felt = felt_object_of(s, objects, stimulus);
  felt_object = -1;
  if (felt >= 0 && remembered.radius > 0.0) {
    felt_object = felt;
    Vec2 sum = Vec2::Zero();
    int n = 0;
    for (int t = 0; t < kTactileCount; ++t)
      if (contact_on_object[t] && s.touch[t].index == felt)
        sum += s.touch[t].point - remembered.radius * s.touch[t].normal, ++n;
    object.seen = object.by_touch = true;
    object.center = sum / n;
    object.center_base = to_local(s.base, object.center);
    if (noise.any()) stereo.valid = false;  // touch says where it is now: a later fix starts over
    object.radius = remembered.radius;
    remembered.center = object.center;
    remembered.center_base = object.center_base;
    remembered_time = s.time;
  }
}

// Which touched object is the object perceived (contact_on_object and touched_object must be this
// tick's). Without the map and the stimulus colour: the one touched most. With them: the object
// touch located last tick while it is still touched (a neighbour of the same colour brushed
// against must not take its place), else the one touched most among those of the stimulus colour.
// A bystander of another colour bumped on the way is not the object: taken for it, it was what
// phi3 closed on, and the creeping body shoved it across the arena into a wall (sorting, seed
// 300050).
int Percepts::felt_object_of(const SenseReadings& s, const std::vector<MapObject>* objects,
                             const Colour* stimulus) const {
  if (!objects || !stimulus) return touched_object;
  if (felt_object >= 0 && contacts_on(s, contact_on_object, felt_object) > 0) return felt_object;
  return most_touched(s, contact_on_object, [&](int i) {
    return size_t(i) < objects->size() && (*objects)[size_t(i)].colour == *stimulus;
  });
}

void start_object_map(const WorldSpec& spec, std::vector<MapObject>& map) {
  map.assign(spec.objects.size(), MapObject{});
  for (size_t i = 0; i < spec.objects.size(); ++i) {
    map[i].radius = shape_bounding_radius(spec.objects[i].shape);
    map[i].colour = spec.objects[i].colour;
  }
}

void update_object_map(const World& world, std::vector<MapObject>& map) {
  for (size_t i = 0; i < map.size(); ++i) {
    MapObject& o = map[i];
    const Pose pose = world.object_pose(int(i));
    o.center = Vec2(pose.x, pose.y);
    o.held = world.held(int(i));
    o.region = world.region_of(int(i));
  }
}

}  // namespace roger
