// body.h: what follows from Roger's body and eyes. The controllers' numbers that depend on the
// body (approach ring, reaches, the planner's inflation, the fold posture, the half view, the
// carried object's centre) are derived here, once per world, and nowhere else.
//
// Each number is anchored at the value tuned for the default Roger and moves with the body
// quantity it depends on: value(body) = tuned * q(body) / q(default) for a length, or
// tuned + (q(body) - q(default)) for an angle. The default body therefore gives the tuned value
// to the bit (q / q is exactly 1, q - q exactly 0), and any other body the same geometric rule.
// docs/control.md ("Bodies") gives each rule.
#pragma once

#include <string>
#include <vector>

#include "core/robot.h"
#include "core/spec.h"

namespace roger {

// The numbers of the controllers that depend on the body.
struct BodyMetrics {
  double approach = 0.58;        // phi1: base-to-object distance of the approach ring (m)
  double preshape_reach = 1.25;  // phi2: objects farther from the base are out of reach (m)
  double grasp_reach = 0.9;      // phi3: the same for closing on the object (m)
  double grid_inflate = 0.36;    // the planner's obstacle growth: the folded footprint's half width (m)
  double objects_growth = 0.4;   // phi1: other objects grown as obstacles (m)
  double squeeze = 0.25;         // phi1: the narrower growth of a squeeze past them (m)
  double release_distance = 0.4; // release: how far the base backs off (m)
  double half_view = 0.75;       // search: a bearing within this (rad) is in both eyes' view
  double sidestep = 0.3;         // search: the sideways step that clears a blind eye (m)
  double carry = 0.36;           // phi1 carrying: the grasped object's centre ahead of the base (m)
  double footprint_radius = 0.0; // base centre to the far edge of the folded footprint (m)
  // The fold posture of the left arm (the right arm mirrors it): hands beside the body.
  double fold_shoulder = 1.975, fold_elbow = -2.81;
};

// Derives the metrics of a body and its eyes (see the top of this file).
BodyMetrics body_metrics(const RobotParams& body, const EyeParams& eyes);

// The default start posture of a body: both arms folded, eyes straight ahead, at `pose`.
RobotStart folded_start(const RobotParams& body, const Pose& pose = Pose{});

// Where a hand's centre is in the base frame for the arm's joint angles (side kLeft or kRight).
Vec2 hand_in_base(const RobotParams& body, int side, double shoulder, double elbow);

// Why a body or its eyes cannot be built, one sentence each (empty when it can): non-positive
// lengths and masses, inverted joint ranges, pixels or field of view out of range, hands that
// cannot fold clear of the base.
std::vector<std::string> body_problems(const RobotParams& body, const EyeParams& eyes);

// The names of the joints a body may lock ("left_eye" ... "right_elbow") and their Dof.
const std::vector<std::pair<std::string, int>>& lockable_joints();

}  // namespace roger
