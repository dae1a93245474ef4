// agent.h: Roger with a mind: a World, what it perceives, and the control loop that runs one
// controller (any action: primitive, composition or skill) per control tick.
#pragma once

#include <cstdint>

#include "control/control.h"
#include "control/predicate.h"
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

  // Starts an episode in a world: derives its model (checking the spec; roger::Error says what is
  // wrong) and resets the world from it. Controllers are reset by their owner with the same seed.
  void reset(const WorldSpec& spec);

  // Runs one control tick: evaluates the action, writes its errors (plus the gaze reflex),
  // steps the world and perceives. Returns the action's output for the tick that just ran.
  const ControlOutput& step(Controller& action);

  // The judge of the episode's goal (or none): under noise, told after each tick's command what
  // the controllers did, so its copies follow them on the true senses (Judge::follow). The caller
  // keeps it alive while it is set.
  void set_judge(Judge* judge) { judge_ = judge; }

  // The inputs every controller reads at the current tick (evaluate other controllers with it).
  const ControlInput& input() const { return input_; }
  // What judges read under noise: the same tick from the true senses (input().truth, or input()
  // itself when the senses are true).
  const ControlInput& true_input() const { return input_.truth ? *input_.truth : input_; }

  World& world() { return world_; }
  const World& world() const { return world_; }
  // The episode's world model (ControlInput::model) and parts of it.
  const WorldModel& model() const { return model_; }
  const OccupancyGrid& grid() const { return model_.grid; }
  const BodyMetrics& body_metrics() const { return model_.body; }
  double grid_inflate() const { return model_.grid_inflate; }
  const Percepts& percepts() const { return percepts_; }
  // The map of movable objects at the current tick (ControlInput::objects).
  const std::vector<MapObject>& objects() const { return objects_; }
  const AgentParams& params() const { return params_; }
  uint64_t ticks() const { return input_.tick; }
  // The errors vector written at the last step (the action's command plus the gaze reflex).
  const DofVector& last_errors() const { return last_errors_; }

 private:
  // The tick's percepts and input (the per-world fields are set by reset).
  void perceive();
  World world_;
  AgentParams params_;
  WorldModel model_;        // this episode's world (kept across episodes: its grid is reused)
  Percepts percepts_;
  // Under joint or base noise, what the controllers read: the noisy readings with the pose Roger
  // estimates (PoseFilter) in place of the noisy joints and base; without the images, which
  // control never reads (their copy took three times the filter's instructions: callgrind, 30
  // scripted episodes under M).
  PoseFilter pose_filter_;
  SenseReadings estimated_;
  Percepts true_percepts_;  // what the true senses make of the world (under noise only)
  ControlInput true_input_; // the tick as the true world gives it, for judges
  Attention judge_next_attention_;  // where judges' bindings ask to attend: ignored
  std::vector<MapObject> objects_;
  ControlInput input_;
  Attention next_attention_;  // where a binding asked the eyes to attend from the next tick
  DofVector last_errors_ = DofVector::Zero();
  Judge* judge_ = nullptr;
};

}  // namespace roger
