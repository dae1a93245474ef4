#include "control/agent.h"

#include <cmath>
#include <cstring>

#include "core/shape.h"

namespace roger {

Agent::Agent(const WorldParams& world, const AgentParams& params) : world_(world), params_(params) {}

namespace {

// Whether two numbers have the same bits (a grid built from either would be the same).
bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same(const Vec2& a, const Vec2& b) { return same(a.x(), b.x()) && same(a.y(), b.y()); }

// Whether two shapes are the same to the bit.
bool same(const Shape& a, const Shape& b) {
  if (a.polygons.size() != b.polygons.size() || a.disks.size() != b.disks.size()) return false;
  for (size_t i = 0; i < a.polygons.size(); ++i) {
    const auto &u = a.polygons[i].vertices, &v = b.polygons[i].vertices;
    if (u.size() != v.size()) return false;
    for (size_t k = 0; k < u.size(); ++k)
      if (!same(u[k], v[k])) return false;
  }
  for (size_t i = 0; i < a.disks.size(); ++i)
    if (!same(a.disks[i].center, b.disks[i].center) || !same(a.disks[i].radius, b.disks[i].radius))
      return false;
  return true;
}

// Whether the occupancy grid of one world is that of the other: the same arena bounds and cell,
// and the same obstacles in the same places (all build_occupancy reads).
bool same_obstacles(const ArenaSpec& a, const std::vector<ObstacleSpec>& ao, const ArenaSpec& b,
                    const std::vector<ObstacleSpec>& bo) {
  if (!same(a.xmin, b.xmin) || !same(a.xmax, b.xmax) || !same(a.ymin, b.ymin) ||
      !same(a.ymax, b.ymax) || !same(a.cell, b.cell) || ao.size() != bo.size())
    return false;
  for (size_t k = 0; k < ao.size(); ++k) {
    const Pose &p = ao[k].pose, &q = bo[k].pose;
    if (!same(p.x, q.x) || !same(p.y, q.y) || !same(p.theta, q.theta) || !same(ao[k].shape, bo[k].shape))
      return false;
  }
  return true;
}

}  // namespace

void Agent::reset(const WorldSpec& spec) {
  world_.reset(spec);
  const WorldSpec& s = world_.spec();
  metrics_ = roger::body_metrics(s.body, s.eyes);
  const double inflate = params_.grid_inflate >= 0.0 ? params_.grid_inflate : metrics_.grid_inflate;
  // Episodes of one scenario mostly share the arena, its obstacles and Roger's body: the grid is
  // built again only when they differ.
  if (!grid_valid_ || !same(inflate, grid_inflate_) ||
      !same_obstacles(s.arena, s.obstacles, grid_arena_, grid_obstacles_)) {
    grid_valid_ = false;  // stays so if the build throws
    grid_ = build_occupancy(s, inflate);
    grid_inflate_ = inflate;
    grid_arena_ = s.arena;
    grid_obstacles_ = s.obstacles;
    grid_valid_ = true;
  }
  percepts_ = Percepts{};
  true_percepts_ = Percepts{};
  // How far a stereo fix of the noisy senses may be off: each eye's world bearing carries its
  // pan's noise and the image's (about a hundredth of a pixel per colour level, measured on the
  // stimulus' centre), the base its own.
  const NoiseParams& n = s.noise;
  stereo_noise_ = StereoNoise{std::hypot(n.joints, n.image / 100.0 / world_.camera().focal), n.base};
  objects_.assign(s.objects.size(), MapObject{});
  for (size_t i = 0; i < s.objects.size(); ++i) {
    objects_[i].radius = shape_bounding_radius(s.objects[i].shape);
    objects_[i].colour = s.objects[i].colour;
  }
  next_attention_ = world_.attention();
  input_.tick = 0;
  refresh_input();
}

void Agent::refresh_objects() {
  const WorldSpec& spec = world_.spec();
  // The map's `held` judges the task (sorted_objects): the true touch, never the noisy one.
  const Senses& s = world_.true_senses();
  for (size_t i = 0; i < objects_.size(); ++i) {
    MapObject& o = objects_[i];
    const Pose pose = world_.object_pose(int(i));
    o.center = Vec2(pose.x, pose.y);
    o.held = false;
    for (const Touch& t : s.touch) o.held |= t.contact && t.kind == SurfaceKind::kObject && t.index == int(i);
    o.region = -1;
    for (size_t g = 0; g < spec.goals.size() && o.region < 0; ++g)
      if ((o.center - spec.goals[g].center).norm() <= spec.goals[g].radius) o.region = int(g);
  }
}

void Agent::refresh_input() {
  refresh_objects();
  percepts_.update(world_.senses(), world_.body(), &objects_, &world_.attention().colour, stereo_noise_);
  input_.senses = &world_.senses();
  input_.percepts = &percepts_;
  input_.robot = &world_.body();
  input_.body = &metrics_;
  input_.camera = &world_.camera();
  input_.spec = &world_.spec();
  input_.grid = &grid_;
  input_.objects = &objects_;
  input_.time = world_.time();
  input_.dt = world_.tick_seconds();
  input_.attention = &world_.attention();
  input_.next_attention = &next_attention_;
  input_.region = world_.attention().region;
  refresh_truth();
}

void Agent::refresh_truth() {
  const bool noisy = &world_.senses() != &world_.true_senses();
  if (!noisy && !params_.always_judge_truth) {
    input_.truth = nullptr;
    return;
  }
  if (noisy) true_percepts_.update(world_.true_senses(), world_.body(), &objects_, &world_.attention().colour);
  true_input_ = input_;
  true_input_.senses = &world_.true_senses();
  true_input_.percepts = noisy ? &true_percepts_ : &percepts_;
  true_input_.truth = nullptr;
  // A judge never steers the eyes: a binding among its copies asks a scratch attention.
  judge_next_attention_ = next_attention_;
  true_input_.next_attention = &judge_next_attention_;
  input_.truth = &true_input_;
}

const ControlOutput& Agent::step(Controller& action) {
  const ControlOutput& out = action.evaluate(input_);
  action.executed(input_);
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
  refresh_input();
  return out;
}

}  // namespace roger
