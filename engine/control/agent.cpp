#include "control/agent.h"

namespace roger {

Agent::Agent(const WorldParams& world, const AgentParams& params) : world_(world), params_(params) {}

void Agent::reset(const WorldSpec& spec) {
  derive_world_model(spec, world_.params(), params_.grid_inflate, model_);
  world_.reset(model_);
  percepts_ = Percepts{};
  true_percepts_ = Percepts{};
  start_object_map(model_.spec, objects_);
  next_attention_ = world_.attention();
  // What stays the same all episode: the model, where the senses, percepts and object map live.
  input_ = ControlInput{};
  input_.model = &model_;
  pose_filter_.reset(model_.noise.params.joints.any(), model_.noise.params.base.any());
  input_.senses = pose_filter_.active() ? &estimated_ : &world_.senses();
  input_.percepts = &percepts_;
  input_.objects = &objects_;
  input_.attention = &world_.attention();
  input_.next_attention = &next_attention_;
  // Judges read the same tick from the true senses: under noise, or when asked to even without.
  const bool judge_truth = model_.noise.any || params_.always_judge_truth;
  if (judge_truth) {
    true_input_ = input_;
    true_input_.senses = &world_.true_senses();
    true_input_.percepts = model_.noise.any ? &true_percepts_ : &percepts_;
    // A judge never steers the eyes: a binding among its copies asks a scratch attention.
    true_input_.next_attention = &judge_next_attention_;
    input_.truth = &true_input_;
  }
  perceive();
}

void Agent::perceive() {
  // The map's `held` and `region` judge the task (sorted_objects): the true world, never the noise.
  update_object_map(world_, objects_);
  const Colour* stimulus = &world_.attention().colour;
  if (pose_filter_.active()) {
    estimated_ = world_.senses();  // the readings only: the images are not copied
    pose_filter_.apply(estimated_, model_.tick_seconds());
  }
  percepts_.update(*input_.senses, model_.robot(), &objects_, stimulus, model_.noise.stereo);
  input_.time = world_.time();
  input_.region = world_.attention().region;
  if (!input_.truth) return;
  if (model_.noise.any) true_percepts_.update(world_.true_senses(), model_.robot(), &objects_, stimulus);
  true_input_.time = input_.time;
  true_input_.tick = input_.tick;
  true_input_.region = input_.region;
  judge_next_attention_ = next_attention_;
}

const ControlOutput& Agent::step(Controller& action) {
  const ControlOutput& out = action.evaluate(input_);
  action.executed(input_);
  if (judge_) judge_->follow(input_);  // the judge's copies follow, on this tick's true senses
  if (next_attention_ != world_.attention()) {
    // A binding redirected the eyes: what was perceived of the old stimulus is not the new one's.
    const Attention& now = world_.attention();
    if (next_attention_.colour != now.colour || next_attention_.ignore_region != now.ignore_region)
      percepts_ = true_percepts_ = Percepts{};
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
  perceive();
  return out;
}

}  // namespace roger
