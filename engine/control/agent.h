// agent.h: Roger with a mind: a World, what it perceives, and the control loop that runs one
// controller (any action: primitive, composition or skill) per control tick.
#pragma once

#include <cstdint>

#include "control/control.h"
#include "core/body.h"
#include "sim/occupancy.h"
#include "sim/world.h"

namespace roger {

// How the agent runs its controllers.
struct AgentParams {
  // Obstacles grown by this (m) for the planner; negative: the body's (BodyMetrics::grid_inflate,
  // the folded footprint's half width: 0.36 m for the default Roger).
  double grid_inflate = -1.0;
  bool gaze_reflex = true;     // eyes keep the stimulus centred whenever the action leaves them idle
  // Gives the judges the true world's tick (ControlInput::truth) even without noise, where it is
  // the same as the senses': how tests show that judging through copies changes nothing.
  bool always_judge_truth = false;
};

// The control loop of one episode.
class Agent {
 public:
  explicit Agent(const WorldParams& world = {}, const AgentParams& params = {});

  // Starts an episode in a world; controllers are reset by their owner with the same seed.
  void reset(const WorldSpec& spec);

  // Runs one control tick: evaluates the action, writes its errors (plus the gaze reflex),
  // steps the world and perceives. Returns the action's output for the tick that just ran.
  const ControlOutput& step(Controller& action);

  // The inputs every controller reads at the current tick (evaluate other controllers with it).
  const ControlInput& input() const { return input_; }
  // What judges read under noise: the same tick from the true senses (input().truth, or input()
  // itself when the senses are true).
  const ControlInput& true_input() const { return input_.truth ? *input_.truth : input_; }

  World& world() { return world_; }
  const World& world() const { return world_; }
  const Percepts& percepts() const { return percepts_; }
  const OccupancyGrid& grid() const { return grid_; }
  // The map of movable objects at the current tick (ControlInput::objects).
  const std::vector<MapObject>& objects() const { return objects_; }
  const AgentParams& params() const { return params_; }
  // The controllers' numbers that follow from this episode's body (ControlInput::body).
  const BodyMetrics& body_metrics() const { return metrics_; }
  // The growth of the obstacles in grid() (m).
  double grid_inflate() const { return grid_inflate_; }
  uint64_t ticks() const { return input_.tick; }
  // The errors vector written at the last step (the action's command plus the gaze reflex).
  const DofVector& last_errors() const { return last_errors_; }

 private:
  void refresh_input();
  void refresh_objects();
  // Points input_.truth at the tick as the true senses give it, where judges need it.
  void refresh_truth();
  World world_;
  AgentParams params_;
  Percepts percepts_;
  Percepts true_percepts_;  // what the true senses make of the world (under noise only)
  StereoNoise stereo_noise_;  // how noisy this episode's stereo fixes are (none without noise)
  ControlInput true_input_; // the tick as the true world gives it, for judges (under noise only)
  Attention judge_next_attention_;  // where judges' bindings ask to attend: ignored
  BodyMetrics metrics_;
  OccupancyGrid grid_;
  // What grid_ was built from: an episode in the same arena among the same obstacles reuses it.
  bool grid_valid_ = false;
  double grid_inflate_ = 0.0;
  ArenaSpec grid_arena_;
  std::vector<ObstacleSpec> grid_obstacles_;
  std::vector<MapObject> objects_;
  ControlInput input_;
  Attention next_attention_;  // where a binding asked the eyes to attend from the next tick
  DofVector last_errors_ = DofVector::Zero();
};

}  // namespace roger
