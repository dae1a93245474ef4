// Module perception: what Roger makes of its senses, once per tick, for every controller to read:
// the object's estimate (stereo, fused over the ticks under noise, or touch close up), the arms'
// kinematics from the joint senses, which object touch located; and the map of movable objects
// Roger is given. Depends on sim and below; knows nothing of controllers, learning or Lua.
//
// percepts.h: the percepts of one tick and the object map.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/spec.h"
#include "senses/noise.h"
#include "senses/senses.h"
#include "sim/world.h"

namespace roger {

// The object as Roger estimates it: from vision (stereo centre, size from the angular width), or,
// when vision cannot tell (the object fills an eye's view) but touch can, from the contacts.
struct VisualObject {
  bool seen = false;             // an estimate this tick (stereo, or touch when vision is clipped)
  bool by_touch = false;         // this tick's estimate comes from the contacts
  Vec2 center = Vec2::Zero();    // world frame
  Vec2 center_base = Vec2::Zero();
  double radius = 0.0;           // half the angular width times the range
};

// An object as the map of movable objects has it: Roger is given this map as it is given the
// static one (it does not build it from its eyes). The planner treats these objects as obstacles
// (all but the one it approaches or carries), and a task's judge (roger.sorted) reads where they
// lie. No controller perceives its stimulus through it: what a controller is after, it sees.
struct MapObject {
  Vec2 center = Vec2::Zero();  // the object's pose, world frame
  double radius = 0.0;         // the smallest circle about that centre holding its shape
  Colour colour;
  bool held = false;           // touched by the body or a hand at the last sensing (World::held)
  int region = -1;             // the goal region holding its centre (World::region_of), or -1
};

// The map of movable objects of a world at its current tick: each object's radius and colour
// from the spec, its pose, whether Roger holds it and the region it lies in from the world.
void start_object_map(const WorldSpec& spec, std::vector<MapObject>& map);
void update_object_map(const World& world, std::vector<MapObject>& map);

// The object's centre as fused over the ticks: a Kalman filter in the world frame whose
// measurements are the stereo fixes, each with the covariance its geometry gives (the range error
// grows with the square of the range over the eyes' baseline), and a process noise that lets
// the object be pushed. Used only under noise (StereoNoise::any), so true senses are untouched.
struct StereoFilter {
  bool valid = false;
  Vec2 center = Vec2::Zero();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  double time = -1e9;  // of the last fix fused
  int rejected = 0;    // fixes in a row too far from the estimate to be the same object
  // Fuses a fix `z` seen from eyes at `eyes_mid` (baseline `baseline`) at time `t`; returns the
  // estimate.
  Vec2 fuse(const Vec2& z, const Vec2& eyes_mid, double baseline, const StereoNoise& noise, double t);
};

// Roger's pose as it estimates it under joint or base noise, as a robot fuses its odometry with
// noisy absolute readings: each joint angle, the odometer and the base pose are predicted from
// the velocities the senses give (exact: the encoders' rates, the wheels' odometry) and pulled
// toward this tick's noisy reading by a fixed gain g (kPoseGain): white noise of deviation sigma
// leaves sigma sqrt(g / (2 - g)), about a quarter of it, and no lag, since the prediction follows
// the motion. A bias or a drift stays (no filter can tell it from the pose). Used only on a
// noisy channel, so true senses are untouched.
class PoseFilter {
 public:
  static constexpr double kPoseGain = 0.1;
  // Starts an episode: which channels are noisy.
  void reset(bool joints, bool base);
  // Replaces the noisy joints and base pose of `s` by the estimate (the first tick: the reading).
  void apply(SenseReadings& s, double dt);
  bool active() const { return joints_ || base_; }

 private:
  bool joints_ = false, base_ = false, valid_ = false;
  DofVector q_ = DofVector::Zero(), qdot_ = DofVector::Zero();  // the estimate, last tick's rates
  Pose pose_;
};

// Per-tick facts shared by every controller, computed once (see Percepts::update).
struct Percepts {
  VisualObject object;                   // what the eyes say
  VisualObject remembered;               // the last estimate (for controllers that may use it)
  double remembered_time = -1e9;         // when it was made
  VisualObject vision;                   // the last estimate from vision alone (no touch)
  double vision_time = -1e9;             // when it was made
  std::array<ArmPoints, 2> arms;         // forward kinematics from the joint senses
  bool contact_on_object[kTactileCount] = {false, false, false};  // touch on an object
  int touched_object = -1;               // the object touched by most sensors, or -1
  int felt_object = -1;                  // the object touch located this tick (see update), or -1
  StereoFilter stereo;                   // the fused fix, under noise only
  // Recomputes from this tick's senses. With the map of objects and the stimulus colour, touch
  // locates only an object of that colour (see update); without them, whatever it touches most.
  // Under noise (`noise` any) the stereo fix is fused over the ticks (StereoFilter).
  void update(const SenseReadings& senses, const RobotParams& robot,
              const std::vector<MapObject>* objects = nullptr, const Colour* stimulus = nullptr,
              const StereoNoise& noise = {});

 private:
  int felt_object_of(const SenseReadings& senses, const std::vector<MapObject>* objects,
                     const Colour* stimulus) const;
};

}  // namespace roger
