// Module core: the vocabulary every layer speaks (world specs, Roger's dimensions, shapes, seeds,
// errors, atomic files). Owns plain data and small utilities. Depends on nothing of the engine.
//
// spec.h: the immutable description of one world, produced by a scenario script for one seed.
// A WorldSpec is plain data: the engine compiles it into Box2D bodies at episode reset and never
// changes it during an episode (MuJoCo's model/data split: this is the model).
#pragma once

#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/robot.h"

namespace roger {

using Vec2 = Eigen::Vector2d;

// An sRGB colour; objects are told apart by the eyes through their colours.
struct Colour {
  uint8_t r = 128, g = 128, b = 128;
  bool operator==(const Colour& o) const { return r == o.r && g == o.g && b == o.b; }
  bool operator!=(const Colour& o) const { return !(*this == o); }
  // "#rrggbb", as scripts write colours, pages draw them and messages name them.
  std::string hex() const {
    char text[8];
    std::snprintf(text, sizeof text, "#%02x%02x%02x", r, g, b);
    return text;
  }
};

// A planar pose: position in metres, heading in radians (counter-clockwise from +x).
struct Pose {
  double x = 0.0, y = 0.0, theta = 0.0;
};

// A disk in a shape's own frame.
struct Disk {
  Vec2 center = Vec2::Zero();
  double radius = 0.1;
};

// A convex polygon in a shape's own frame: 3 to 8 vertices, counter-clockwise after validation.
struct Polygon {
  std::vector<Vec2> vertices;
};

// A rigid shape: a union of convex polygons and disks (a non-convex object has several parts).
// Validate with validate_shape() before it reaches Box2D.
struct Shape {
  std::string name;
  std::vector<Polygon> polygons;
  std::vector<Disk> disks;
};

// A movable object (the paper's ball, triangle, pentagon, spade).
struct ObjectSpec {
  std::string name = "object";
  Shape shape;
  Colour colour{220, 30, 30};
  Pose pose;
  double mass = 0.5;               // kg
  double friction_force = 10.0;    // N: static-friction threshold against the floor
  double friction_torque = 1.0;    // N m: the same against spinning
  double viscosity = 1.0;          // 1/s: linear damping once it slides
  double angular_viscosity = 1.0;  // 1/s: angular damping
  double surface_friction = 0.8;   // Coulomb coefficient against hands and body
};

// A static obstacle: blocks motion and sight.
struct ObstacleSpec {
  std::string name = "obstacle";
  Shape shape;
  Colour colour{90, 90, 110};
  Pose pose;
};

// A circular goal region on the floor: seen by the planner, not by the eyes.
struct GoalRegion {
  std::string name = "goal";
  Vec2 center = Vec2::Zero();
  double radius = 0.25;
  Colour colour{60, 170, 80};
};

// The walled, rectangular arena and its occupancy-grid resolution.
struct ArenaSpec {
  double xmin = -2.0, xmax = 2.0, ymin = -2.0, ymax = 2.0;
  double cell = 0.0625;  // occupancy-grid cell size in metres: 64 x 64 on the default arena
  Colour wall_colour{200, 200, 200};
};

// Where Roger starts and in which posture.
struct RobotStart {
  Pose pose;
  // Shoulder and elbow of the left arm, then of the right arm (radians, see RobotParams).
  // The default folds the arms with the hands beside the body (hand centres at (0.14, +-0.27) m):
  // clear of anything ahead, so approaching an object never knocks it with a hand, and a narrow
  // footprint (0.35 m to each side) for the planner.
  double left_shoulder = 1.975, left_elbow = -2.81, right_shoulder = -1.975, right_elbow = 2.81;
  double left_eye = 0.0, right_eye = 0.0;  // pan relative to the base heading
};

// One world: everything a scenario script decides for one seed.
struct WorldSpec {
  std::string scenario;                       // the script that made it
  uint64_t seed = 0;                          // the seed it was made with
  std::map<std::string, std::string> params;  // the scenario parameters in force, as text
  ArenaSpec arena;
  RobotStart robot;
  RobotParams body;  // Roger's body (world:robot{ body = ... }); the default is the paper's Roger
  EyeParams eyes;    // its eyes (world:robot{ eyes = ... })
  NoiseParams noise; // its senses' and motors' noise (world:robot{ noise = ... }); none by default
  std::vector<ObjectSpec> objects;
  std::vector<ObstacleSpec> obstacles;
  std::vector<GoalRegion> goals;
  Colour stimulus_colour{220, 30, 30};  // the colour the eyes look for (the red ball)
};

}  // namespace roger
