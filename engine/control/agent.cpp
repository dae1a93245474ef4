#include "control/agent.h"

#include <cmath>

namespace roger {

Agent::Agent(const WorldParams& world, const AgentParams& params) : world_(world), params_(params) {}

void Agent::reset(const WorldSpec& spec) {
  world_.reset(spec);
  grid_ = build_occupancy(world_.spec(), params_.grid_inflate);
  percepts_ = Percepts{};
  next_attention_ = world_.attention();
  input_.tick = 0;
  refresh_input();
}

void Agent::refresh_input() {
  percepts_.update(world_.senses(), world_.params().robot);
  input_.senses = &world_.senses();
  input_.percepts = &percepts_;
  input_.robot = &world_.params().robot;
  input_.spec = &world_.spec();
  input_.grid = &grid_;
  input_.time = world_.time();
  input_.dt = world_.tick_seconds();
  input_.attention = &world_.attention();
  input_.next_attention = &next_attention_;
  input_.region = world_.attention().region;
}

const ControlOutput& Agent::step(Controller& action) {
  const ControlOutput& out = action.evaluate(input_);
  action.executed(input_);
  if (next_attention_ != world_.attention()) {
    // A binding redirected the eyes: what was perceived of the old stimulus is not the new one's.
    const Attention& now = world_.attention();
    if (next_attention_.colour != now.colour || next_attention_.ignore_region != now.ignore_region)
      percepts_ = Percepts{};
    world_.set_attention(next_attention_);
  }
  DofVector errors = out.command;
  if (params_.gaze_reflex) {
    // Like a vestibulo-ocular reflex: an eye the action does not move keeps the stimulus centred.
    const Senses& s = world_.senses();
    for (int e = 0; e < 2; ++e)
      if (errors[kLeftEye + e] == 0.0 && s.stimulus[e].seen) errors[kLeftEye + e] = s.stimulus[e].bearing;
  }
  world_.command(errors);
  last_errors_ = errors;
  world_.tick();
  ++input_.tick;
  refresh_input();
  return out;
}

}  // namespace roger
