// robot.h: Roger's numbers and the names of its eight degrees of freedom.
// Definition structs with defaults (Box2D style): every number of DESIGN.md lives here once.
#pragma once

#include <array>
#include <cmath>

#include <Eigen/Core>

namespace roger {

// The eight degrees of freedom every action writes an error for, in this order.
enum Dof : int {
  kBaseForward = 0,  // metres along the heading (an odometer)
  kBaseHeading,      // radians, wrapped to (-pi, pi] (docs/control.md, Angles)
  kLeftEye,          // pan relative to the base heading
  kRightEye,
  kLeftShoulder,     // relative to the base heading
  kLeftElbow,        // relative to the upper arm
  kRightShoulder,
  kRightElbow,
  kDofCount
};

// One value per degree of freedom.
using DofVector = Eigen::Matrix<double, kDofCount, 1>;

// Display names of the degrees of freedom, for messages and files.
extern const std::array<const char*, kDofCount> kDofNames;

// The tactile sensors: the base and the two hands (the paper's three elastic bodies).
enum Tactile : int { kBody = 0, kLeftHand, kRightHand, kTactileCount };

// Left and right eye, left and right arm.
enum Side : int { kLeft = 0, kRight = 1 };

// A servo's gains and limits. Position error -> desired rate (kp, clamped to max_rate) ->
// force or torque (kv times the rate error, clamped to max_effort).
struct ServoParams {
  double kp = 8.0;           // 1/s
  double max_rate = 2.0;     // m/s or rad/s
  double kv = 20.0;          // N/(m/s) or N m/(rad/s) (base only; arm joints use Box2D motors)
  double max_effort = 20.0;  // N or N m
};

// Roger's body, from the original Roger-the-Crab simulator.
struct RobotParams {
  double base_radius = 0.16;  // m
  double base_mass = 1.0;     // kg
  double axle_half_width = 0.20;
  double link_length[2] = {0.5, 0.5};  // upper arm, forearm (m)
  double link_mass = 0.2;              // kg each
  double link_width = 0.04;            // m (drawing only: links do not collide)
  double hand_radius = 0.08;           // m
  double hand_mass = 0.05;             // kg
  double shoulder_y = 0.18;            // shoulders at (0, +-0.18) in the base frame
  double eye_y = 0.08;                 // eyes at (0, +-0.08) in the base frame
  double eye_pan_limit = 1.5707963267948966;  // +-pi/2
  double shoulder_min = -3.0, shoulder_max = 3.0;  // left arm; the right arm is mirrored
  double elbow_min = -2.9, elbow_max = 2.9;
  double surface_friction = 1.0;  // Coulomb coefficient of the hands and body
  // Joints held at their start angle (bit 1 << Dof of an eye, shoulder or elbow): the freezing of
  // degrees of freedom of developmental robotics. Their setpoints never move and their limits
  // close on the start angle.
  unsigned locked = 0;

  ServoParams base_forward{6.0, 1.0, 60.0, 60.0};
  ServoParams base_heading{6.0, 3.0, 10.0, 12.0};
  ServoParams eye{20.0, 6.0, 0.0, 0.0};  // eyes are light: first-order rate servos
  ServoParams shoulder{10.0, 4.0, 0.0, 20.0};
  ServoParams elbow{10.0, 4.0, 0.0, 12.0};
};

// Whether degree of freedom d is locked in `body`.
inline bool is_locked(const RobotParams& body, int d) { return (body.locked >> d) & 1u; }

// The eyes: two 1-D pinhole cameras, 128 pixels over a 90 degree field of view by default.
struct EyeParams {
  int pixels = 128;
  double fov = 1.5707963267948966;  // the full field of view (rad)
};

// The pixel counts an eye may have, and the largest image the senses hold.
constexpr int kMinPixels = 16, kMaxPixels = 512;
// The field of view an eye may have (rad): a pinhole sees less than pi.
constexpr double kMinFov = 0.1, kMaxFov = 2.8;

// Sensor and actuator noise (world:robot{ noise = ... }): standard deviations of independent
// Gaussian noise drawn every control tick from a stream seeded by the world's seed alone. Zero
// draws nothing: a world without noise senses and moves exactly as before.
// One channel's noise (world:robot{ noise = { <channel> = sigma or {...} } }, docs/scenarios.md,
// Noise), each kind 0 for none; a channel with none draws nothing. sigma, bias and drift are in
// the channel's unit (image: colour levels; joints: rad; base: m and rad; touch and effort: a
// fraction of the force or command, multiplying it by max(0, 1 + n)); quantum too (touch: N;
// effort: of the commanded error).
struct ChannelNoise {
  double sigma = 0.0;      // white: N(0, sigma) per component and tick
  double bias = 0.0;       // N(0, bias) per component, drawn at the episode's start and held
  double drift = 0.0;      // a first-order Gauss-Markov process per component: its stationary sigma
  double drift_tau = 0.0;  // and its correlation time (s)
  int delay = 0;           // readings (effort: commands) arrive this many control ticks late
  double dropout = 0.0;    // probability per tick that a reading (effort: a command) is lost
  double quantum = 0.0;    // readings (effort: commands) rounded to multiples of this
  // Whether it offsets readings (white, bias or drift).
  bool offsets() const { return sigma > 0.0 || bias > 0.0 || (drift > 0.0 && drift_tau > 0.0); }
  bool any() const { return offsets() || delay > 0 || dropout > 0.0 || quantum > 0.0; }
};

// Roger's sensor and actuator noise, per channel (world:robot{ noise = ... }); none by default.
struct NoiseParams {
  ChannelNoise image;   // each colour channel of each pixel of both eyes
  ChannelNoise joints;  // each joint angle the controllers read (eye pans, shoulders, elbows)
  ChannelNoise base;    // the base pose and odometer
  ChannelNoise touch;   // each contact's normal and friction force
  ChannelNoise effort;  // each commanded force, torque and servo rate (delay, dropout, quantum: the
                        // commanded errors)
  bool any() const { return image.any() || joints.any() || base.any() || touch.any() || effort.any(); }
};

// One eye's pinhole model, derived from EyeParams: pixel u looks along atan2(u - principal, focal)
// in the eye frame, and the image's edges (u = -0.5 and pixels - 0.5) lie at -+half_fov.
struct Camera {
  int pixels = 128;
  double focal = 64.0;       // pixels
  double principal = 63.5;   // the pixel coordinate of the optical axis
  double half_fov = 0.7853981633974483;
  // Pixel coordinate (continuous) of an eye-frame angle, and back.
  double pixel_of_angle(double angle) const { return principal + focal * std::tan(angle); }
  double angle_of_pixel(double u) const { return std::atan2(u - principal, focal); }
};

// The camera of eyes with these parameters. A focal length within a nano-pixel of a whole number
// is that number, so the default eye's is 64 exactly (tan(pi/4) is 1 - 1e-16 in doubles).
Camera camera_of(const EyeParams& eyes);

}  // namespace roger
