// Module sim: the physical world of one episode. Owns the Box2D world (Box2D lives only here), the
// servos, touch accumulation and the occupancy grid. Depends only on senses and core.
//
// world.h: one episode of Roger in a world: Box2D bodies, servos, and senses.
// A World is reset from an immutable WorldModel (a fresh b2World each time) and then stepped.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/rng.h"
#include "core/robot.h"
#include "senses/noise.h"
#include "senses/senses.h"
#include "core/spec.h"
#include "sim/world_model.h"

class b2World;

namespace roger {

// Where the arm's joints and hand are, world frame.
struct ArmPoints {
  Vec2 shoulder = Vec2::Zero(), elbow = Vec2::Zero(), hand = Vec2::Zero();
};

// Everything needed to draw one moment of an episode.
struct Frame {
  double time = 0.0;
  Pose base;
  std::array<ArmPoints, 2> arms;
  std::array<Vec2, 2> eyes{Vec2::Zero(), Vec2::Zero()};  // positions
  std::array<double, 2> eye_heading{0.0, 0.0};          // world angle of each optical axis
  std::vector<Pose> objects;          // poses of WorldSpec objects
  Senses senses;
};

// What Roger attends to: the stimulus colour the eyes look for, optionally a goal region whose
// objects they ignore once Roger has let go of them (objects already put away draw no attention),
// and the goal region that goal='region' navigators deliver to. It belongs to the world, not to
// one controller, so that everything evaluated on a tick (the running skill, a goal predicate,
// a recorder watching the controllers) sees the same bindings.
struct Attention {
  Colour colour{220, 30, 30};
  int ignore_region = -1;  // index into WorldSpec::goals, -1 = none
  int region = -1;         // the delivery region, index into WorldSpec::goals; -1 = the navigator's own
  bool operator==(const Attention& o) const {
    return colour == o.colour && ignore_region == o.ignore_region && region == o.region;
  }
  bool operator!=(const Attention& o) const { return !(*this == o); }
};

// Forward kinematics of one arm (kLeft or kRight) from the base pose and its two joint angles.
ArmPoints arm_forward_kinematics(const RobotParams& robot, const Pose& base, int side,
                                 double shoulder, double elbow);

// An episode's mutable state. Not copyable; reset() makes it new again.
class World {
 public:
  explicit World(const WorldParams& params = {});
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  // Builds a fresh Box2D world from a model and senses once. The model is trusted (it was checked
  // when derived) and must outlive the episode; it must have been derived with this world's
  // params() (roger::Error otherwise).
  void reset(const WorldModel& model);
  // The same from a spec: derives a model of the world's own (checking the spec; roger::Error
  // names what is wrong) and resets from it.
  void reset(const WorldSpec& spec);

  // Writes one errors vector: each servo's setpoint becomes its current position plus the error.
  void command(const DofVector& errors);

  // Sets absolute setpoints (clamped to the joint limits).
  void set_setpoints(const DofVector& setpoints);

  // One control tick: `substeps` physics steps, then senses.
  void tick();

  // A tick's physics without its senses: the command delivered as the effort noise says (late,
  // lost, scaled), then `substeps` physics steps. The effort's streams draw the same every tick
  // whatever is sensed, so the commands of a run, replayed through it, retrace the run's physics
  // bit for bit, with noise or without (roger bench's physics alone).
  void tick_physics();

  // One physics step: servos, the no-slip constraint, Box2D, touch accumulation. No sensing.
  void step_physics();

  // Recomputes the senses from the current state (images, stimulus, stereo, touch, joints).
  void sense();

  // What the eyes attend to from the next sense() on. reset() sets the spec's stimulus colour and
  // no ignored region, so a world nobody redirects senses exactly as before.
  void set_attention(const Attention& attention) { attention_ = attention; }
  const Attention& attention() const { return attention_; }

  // What the controllers perceive: the senses with the spec's noise (world:robot{ noise = ... }),
  // the true senses when it has none.
  const Senses& senses() const { return model_->noise.any ? noisy_ : senses_; }
  // The true senses, without noise: what judges of success read (who holds what).
  const Senses& true_senses() const { return senses_; }
  // The world's immutable model, and parts of it.
  const WorldModel& model() const { return *model_; }
  const WorldSpec& spec() const { return model_->spec; }
  const WorldParams& params() const { return params_; }
  // Roger's body and eyes in this world (the spec's), and the eyes' camera model.
  const RobotParams& body() const { return model_->spec.body; }
  const Camera& camera() const { return model_->camera; }
  double time() const { return time_; }
  double tick_seconds() const { return params_.dt * params_.substeps; }

  DofVector q() const;                                // joint positions now
  DofVector qdot() const;                             // joint velocities now
  const DofVector& setpoints() const { return setpoint_; }
  Pose base_pose() const;
  Vec2 base_velocity() const;                         // world frame
  double base_lateral_speed() const;                  // sideways speed (m/s), ideally 0
  Pose object_pose(int i) const;
  // Whether Roger touches object i with the body or a hand at the last sensing (the true touch:
  // who holds what is the task's fact, never a noisy one).
  bool held(int i) const;
  // The goal region holding object i's centre, or -1: the region of its colour when that is one of
  // them (regions may overlap), else the first, by index into the spec's goals.
  int region_of(int i) const;
  Vec2 object_velocity(int i) const;
  Vec2 hand_position(int side) const;                 // centre of the hand body, world frame
  ArmPoints arm_points(int side) const;               // from the Box2D bodies
  Frame frame() const;

  // Pushes an object with a force (world frame, N) at its centre during the next physics step.
  void push_object(int i, const Vec2& force);

  // A 64-bit hash of every body's position, angle and velocities and the servo state (bitwise).
  uint64_t state_hash() const;

  // The underlying Box2D world, for tests and tools.
  b2World* physics();

 private:
  struct Impl;
  void update_surfaces();
  // Throws roger::Error when Roger's base or an object is past the arena's walls, which no body
  // passes: the physics went wrong (a body too light for its servos), and so would every result.
  void check_walls_hold() const;
  // The object both eyes keep to this tick, from the last tick's sightings in s (-1: the larger).
  static int kept_object(const Senses& s, bool several);
  // Pairs the two eyes' sightings (several: the right eye keeps to the left's object) and
  // triangulates the stimulus from eyes at these positions and headings.
  static void fix_stereo(Senses& s, const Vec2 eye_pos[2], const double eye_heading[2], bool several);
  // The touch sensors' records of the last tick, into senses_.
  void sense_touch();
  // The noisy senses (noisy_) from the true ones, with the spec's noise.
  void sense_noise(bool several);
  // Whether object i, at `pose`, lies in the attention's ignored region and Roger has let go of it.
  bool put_away(int i, const Pose& pose) const;
  // How many objects have the colour the eyes attend to (put away or not).
  int stimulus_objects() const;
  WorldParams params_;
  const WorldModel* model_;  // the world of this episode (own_model_ until the first reset)
  WorldModel own_model_;     // the model reset(spec) derives
  Senses senses_;
  Senses noisy_;            // senses_ with the spec's noise (only when it has some)
  SenseNoise noise_;        // the noise's streams and state, seeded by the spec's seed alone
  const double* effort_ = nullptr;  // this tick's effort factors, one per degree of freedom (or none)
  DofVector pending_ = DofVector::Zero();  // the errors given, when the effort noise delivers them
  bool has_pending_ = false;               //   late, lost or on a grid (applied at the next tick)
  DofVector locked_at_ = DofVector::Zero();  // where each locked joint is held (its start angle)
  Attention attention_;
  DofVector setpoint_ = DofVector::Zero();
  double time_ = 0.0;
  std::unique_ptr<Impl> impl_;
};

}  // namespace roger
