// world_internal.h: what the world's two source files share: the Box2D side of a World (its
// Impl), the touch accumulated between senses, and the small conversions between Box2D and
// Eigen. world_build.cpp builds an Impl in World::reset; world.cpp steps and senses it.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <box2d/box2d.h>

#include "sim/world.h"

namespace roger {
namespace world_internal {

// Collision categories: the robot's hands and body touch everything but each other; arm links are
// drawn but never collide (as in the original simulator, only the three elastic bodies touch).
constexpr uint16 kCatWall = 0x1, kCatObstacle = 0x2, kCatObject = 0x4, kCatRobot = 0x8;

// Body identity, kept in Box2D's user data so a contact tells what was touched.
inline uintptr_t encode(SurfaceKind kind, int index) {
  return (uintptr_t(kind) << 32) | uint32_t(index + 1);
}
inline SurfaceKind kind_of(uintptr_t id) { return SurfaceKind(id >> 32); }
inline int index_of(uintptr_t id) { return int(uint32_t(id & 0xffffffffu)) - 1; }

// v clamped to [-limit, limit].
inline double clamp_abs(double v, double limit) { return std::clamp(v, -limit, limit); }

// Eigen to Box2D (single precision) and back.
inline b2Vec2 b2v(const Vec2& v) { return b2Vec2(float(v.x()), float(v.y())); }
inline Vec2 v2(const b2Vec2& v) { return Vec2(v.x, v.y); }

// Touch accumulated over the physics steps of one control tick, per touched body.
struct TouchEntry {
  uintptr_t other = 0;
  double impulse = 0.0, tangent = 0.0;
  Vec2 normal_sum = Vec2::Zero(), point_sum = Vec2::Zero(), last_normal = Vec2::Zero(),
       last_point = Vec2::Zero();
};
constexpr int kTouchEntries = 4;
struct TouchAccumulator {
  std::array<TouchEntry, kTouchEntries> entries;
  int count = 0;
  void clear() { count = 0; }
  TouchEntry& entry(uintptr_t other) {
    for (int i = 0; i < count; ++i)
      if (entries[i].other == other) return entries[i];
    if (count == kTouchEntries) return entries[kTouchEntries - 1];  // rare: merge the surplus
    entries[count] = TouchEntry{};
    entries[count].other = other;
    return entries[count++];
  }
};

}  // namespace world_internal

// The Box2D world of an episode and the state of the servos Box2D does not model.
struct World::Impl {
  std::unique_ptr<b2World> world;
  b2Body* ground = nullptr;
  b2Body* rail = nullptr;  // kinematic body that carries the base's no-slip (wheel) constraint
  b2Body* base = nullptr;
  b2Body* link[2][2] = {{nullptr, nullptr}, {nullptr, nullptr}};  // [side][upper, forearm]
  b2RevoluteJoint* joint[2][2] = {{nullptr, nullptr}, {nullptr, nullptr}};
  std::vector<b2Body*> objects;
  std::vector<Vec2> pushes;
  double odometer = 0.0;
  double eye[2] = {0.0, 0.0}, eye_rate[2] = {0.0, 0.0};
  std::array<world_internal::TouchAccumulator, kTactileCount> touch;
  std::vector<SeenSurface> surfaces;  // obstacles (static), then objects (placed anew when moved)
  size_t static_surfaces = 0;
  // Each object's pose when its surfaces were last placed (empty until the first sensing of an
  // episode): an object at rest keeps its surfaces, bit for bit, without placing them again.
  std::vector<Pose> surface_poses;
  std::vector<SeenSurface> placed;    // scratch: one object's surfaces, placed anew
  b2Body* tactile(int t) const { return t == kBody ? base : link[t == kLeftHand ? 0 : 1][1]; }

  // ---- Building (world_build.cpp), in the order World::reset calls them ----

  // The ground body with four thick walls just outside the arena.
  void add_walls(const ArenaSpec& a);
  // The obstacles as static bodies, and their surfaces as the static part of `surfaces`.
  void add_obstacles(const std::vector<ObstacleSpec>& obstacles);
  // The objects as dynamic bodies held to the floor by friction joints.
  void add_objects(const std::vector<ObjectSpec>& specs);
  // Roger's base, a disk at its start pose.
  void add_base(const RobotParams& r, const Pose& start);
  // The kinematic rail that holds the base to its heading (the no-slip constraint).
  void add_rail();
  // Both arms at their start postures: links, hands and motorized joints.
  void add_arms(const RobotParams& r, const RobotStart& start);
  // The odometer, the eyes' pans and rates, and the touch accumulators, as at the start.
  void reset_servos(const RobotParams& r, const RobotStart& start);
  // Closes the limits of the locked arm joints on their angles now.
  void lock_joints(const RobotParams& r);

  // ---- One physics step (world.cpp), in the order World::step_physics calls them ----
  // (Inline, defined in world.cpp alone, which alone calls them: the physics step is the
  // simulator's hot loop, and a call per stage would cost about half a per cent of it.)

  // The base's forward and heading servos, and the rail turned to the mid-step heading; returns
  // that heading's direction. `gain` (null: none) scales each degree of freedom's command.
  inline b2Vec2 drive_base(const RobotParams& r, const DofVector& setpoint, double dt, const double* gain);
  // The eyes' first-order rate servos.
  inline void drive_eyes(const RobotParams& r, const DofVector& setpoint, double dt, const double* gain);
  // The arm joints' motor speeds.
  inline void drive_arms(const RobotParams& r, const DofVector& setpoint, const double* gain);
  // The forces push_object asked for, applied once.
  inline void apply_pushes();
  // Box2D's step, the odometer along the mid-step heading and the wheels' velocity carried on.
  inline void advance(const WorldParams& params, const b2Vec2& mid_fwd);
  // Adds this step's contact impulses to each tactile sensor's accumulator.
  inline void accumulate_touch();
};

}  // namespace roger
