// world.cpp: a World's episode once built (world_build.cpp): the servos and one physics step,
// the senses, and the state read back from Box2D.
#include "sim/world.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/error.h"
#include "core/shape.h"
#include "core/text.h"
#include "senses/noise.h"
#include "sim/world_internal.h"

namespace roger {

const std::array<const char*, kDofCount> kDofNames = {
    "base_forward", "base_heading", "left_eye",       "right_eye",
    "left_shoulder", "left_elbow",  "right_shoulder", "right_elbow"};

using namespace world_internal;

ArmPoints arm_forward_kinematics(const RobotParams& robot, const Pose& base, int side,
                                 double shoulder, double elbow) {
  const double sy = side == kLeft ? robot.shoulder_y : -robot.shoulder_y;
  ArmPoints p;
  p.shoulder = to_world(base, Vec2(0.0, sy));
  const double a1 = base.theta + shoulder, a2 = a1 + elbow;
  p.elbow = p.shoulder + robot.link_length[0] * Vec2(std::cos(a1), std::sin(a1));
  p.hand = p.elbow + robot.link_length[1] * Vec2(std::cos(a2), std::sin(a2));
  return p;
}

World::World(const WorldParams& params)
    : params_(params), model_(&own_model_), impl_(std::make_unique<Impl>()) {
  own_model_.params = params;
  if (!(params_.dt > 0.0) || params_.substeps < 1)
    throw Error("world parameters: dt must be positive and substeps at least 1");
}

World::~World() = default;

b2World* World::physics() { return impl_->world.get(); }

DofVector World::q() const {
  const Impl& m = *impl_;
  DofVector v;
  v[kBaseForward] = m.odometer;
  v[kBaseHeading] = wrap_angle(m.base->GetAngle());  // Box2D's angle winds on; the state does not
  v[kLeftEye] = m.eye[0];
  v[kRightEye] = m.eye[1];
  v[kLeftShoulder] = m.joint[0][0]->GetJointAngle();
  v[kLeftElbow] = m.joint[0][1]->GetJointAngle();
  v[kRightShoulder] = m.joint[1][0]->GetJointAngle();
  v[kRightElbow] = m.joint[1][1]->GetJointAngle();
  return v;
}

DofVector World::qdot() const {
  const Impl& m = *impl_;
  DofVector v;
  v[kBaseForward] = b2Dot(m.base->GetLinearVelocity(), m.base->GetWorldVector(b2Vec2(1, 0)));
  v[kBaseHeading] = m.base->GetAngularVelocity();
  v[kLeftEye] = m.eye_rate[0];
  v[kRightEye] = m.eye_rate[1];
  v[kLeftShoulder] = m.joint[0][0]->GetJointSpeed();
  v[kLeftElbow] = m.joint[0][1]->GetJointSpeed();
  v[kRightShoulder] = m.joint[1][0]->GetJointSpeed();
  v[kRightElbow] = m.joint[1][1]->GetJointSpeed();
  return v;
}

void World::set_setpoints(const DofVector& s) {
  const RobotParams& r = model_->spec.body;
  setpoint_ = s;
  if (!setpoint_.allFinite()) {  // a NaN or infinite command holds that joint still
    const DofVector now = q();
    for (int i = 0; i < kDofCount; ++i)
      if (!std::isfinite(setpoint_[i])) setpoint_[i] = now[i];
  }
  setpoint_[kLeftEye] = std::clamp(setpoint_[kLeftEye], -r.eye_pan_limit, r.eye_pan_limit);
  setpoint_[kRightEye] = std::clamp(setpoint_[kRightEye], -r.eye_pan_limit, r.eye_pan_limit);
  setpoint_[kLeftShoulder] = std::clamp(setpoint_[kLeftShoulder], r.shoulder_min, r.shoulder_max);
  setpoint_[kLeftElbow] = std::clamp(setpoint_[kLeftElbow], r.elbow_min, r.elbow_max);
  setpoint_[kRightShoulder] = std::clamp(setpoint_[kRightShoulder], -r.shoulder_max, -r.shoulder_min);
  setpoint_[kRightElbow] = std::clamp(setpoint_[kRightElbow], -r.elbow_max, -r.elbow_min);
  if (r.locked)
    for (int d = kLeftEye; d < kDofCount; ++d)
      if (is_locked(r, d)) setpoint_[d] = locked_at_[d];
}

void World::command(const DofVector& errors) {
  if (model_->noise.any && noise_.alters_commands()) {
    pending_ = errors, has_pending_ = true;  // delivered by the next tick, as its effort noise says
    return;
  }
  set_setpoints(q() + errors);
}

void World::push_object(int i, const Vec2& force) {
  Impl& m = *impl_;
  if (m.pushes.size() < m.objects.size()) m.pushes.assign(m.objects.size(), Vec2::Zero());
  m.pushes.at(size_t(i)) += force;
}

void World::step_physics() {
  Impl& m = *impl_;
  const RobotParams& r = model_->spec.body;
  const double dt = params_.dt;
  // Effort noise scales each command of this tick (none: no factor, not a factor of 1).
  const double* gain = effort_;
  const b2Vec2 mid_fwd = m.drive_base(r, setpoint_, dt, gain);
  m.drive_eyes(r, setpoint_, dt, gain);
  m.drive_arms(r, setpoint_, gain);
  m.apply_pushes();
  m.advance(params_, mid_fwd);
  time_ += dt;
  m.accumulate_touch();
}

b2Vec2 World::Impl::drive_base(const RobotParams& r, const DofVector& setpoint, double dt, const double* gain) {
  // Base servos: position error -> desired rate -> force, both clamped.
  const b2Vec2 fwd = base->GetWorldVector(b2Vec2(1, 0));
  const double v = b2Dot(base->GetLinearVelocity(), fwd);
  const double v_des = clamp_abs(r.base_forward.kp * (setpoint[kBaseForward] - odometer),
                                 r.base_forward.max_rate);
  double force = clamp_abs(r.base_forward.kv * (v_des - v), r.base_forward.max_effort);
  if (gain) force *= gain[kBaseForward];
  base->ApplyForceToCenter(float(force) * fwd, true);
  // The heading setpoint is in the state's convention (wrapped); Box2D's angle winds on. Their
  // difference, wrapped, is the turn left to make, whatever the turns made so far.
  const double heading_error = wrap_angle(setpoint[kBaseHeading] - base->GetAngle());
  const double w_des = clamp_abs(r.base_heading.kp * heading_error, r.base_heading.max_rate);
  double torque = clamp_abs(r.base_heading.kv * (w_des - base->GetAngularVelocity()), r.base_heading.max_effort);
  if (gain) torque *= gain[kBaseHeading];
  base->ApplyTorque(float(torque), true);
  // Over a step a wheeled base moves along the chord of its arc, which lies along the mid-step
  // heading: point the rail there (predicted from the current turn rate).
  const float mid_heading = base->GetAngle() + 0.5f * float(dt) * base->GetAngularVelocity();
  rail->SetTransform(base->GetPosition(), mid_heading);
  return b2Vec2(std::cos(mid_heading), std::sin(mid_heading));
}

void World::Impl::drive_eyes(const RobotParams& r, const DofVector& setpoint, double dt, const double* gain) {
  // Eyes: light, first-order rate servos.
  for (int e = 0; e < 2; ++e) {
    double rate = clamp_abs(r.eye.kp * (setpoint[kLeftEye + e] - eye[e]), r.eye.max_rate);
    if (gain) rate *= gain[kLeftEye + e];
    eye[e] = std::clamp(eye[e] + rate * dt, -r.eye_pan_limit, r.eye_pan_limit);
    eye_rate[e] = rate;
  }
}

void World::Impl::drive_arms(const RobotParams& r, const DofVector& setpoint, const double* gain) {
  // Arms: Box2D motors are implicit velocity servos with a torque limit: stable at any gain.
  for (int side = 0; side < 2; ++side)
    for (int l = 0; l < 2; ++l) {
      const ServoParams& sp = l == 0 ? r.shoulder : r.elbow;
      b2RevoluteJoint* j = joint[side][l];
      const int dof = kLeftShoulder + 2 * side + l;
      double speed = clamp_abs(sp.kp * (setpoint[dof] - j->GetJointAngle()), sp.max_rate);
      if (gain) speed *= gain[dof];
      j->SetMotorSpeed(float(speed));
    }
}

void World::Impl::apply_pushes() {
  for (size_t i = 0; i < pushes.size(); ++i)
    if (pushes[i] != Vec2::Zero()) objects[i]->ApplyForceToCenter(b2v(pushes[i]), true);
  pushes.clear();
}

void World::Impl::advance(const WorldParams& params, const b2Vec2& mid_fwd) {
  const b2Vec2 before = base->GetPosition();
  world->Step(float(params.dt), params.velocity_iterations, params.position_iterations);
  odometer += b2Dot(base->GetPosition() - before, mid_fwd);
  // The wheels turn with the base: the solver kept the velocity along the mid-step heading, so
  // carry it onto the new heading, where the next step starts.
  base->SetLinearVelocity(b2Dot(base->GetLinearVelocity(), mid_fwd) *
                          base->GetWorldVector(b2Vec2(1, 0)));
}

void World::Impl::accumulate_touch() {
  // Touch: impulses of this step, per sensor and touched body.
  for (int t = 0; t < kTactileCount; ++t) {
    b2Body* body = tactile(t);
    for (b2ContactEdge* edge = body->GetContactList(); edge; edge = edge->next) {
      b2Contact* c = edge->contact;
      if (!c->IsTouching()) continue;
      const bool sensor_is_a = c->GetFixtureA()->GetBody() == body;
      const b2Manifold* mf = c->GetManifold();
      b2WorldManifold wm;
      c->GetWorldManifold(&wm);
      const Vec2 normal = (sensor_is_a ? -1.0 : 1.0) * v2(wm.normal);  // towards the sensor
      double impulse = 0.0, tangent = 0.0;
      Vec2 point = Vec2::Zero();
      for (int p = 0; p < mf->pointCount; ++p) {
        impulse += mf->points[p].normalImpulse;
        tangent += mf->points[p].tangentImpulse;
        point += v2(wm.points[p]);
      }
      point /= std::max(1, mf->pointCount);
      TouchEntry& e = touch[t].entry(edge->other->GetUserData().pointer);
      e.impulse += impulse;
      e.tangent += std::abs(tangent);
      e.normal_sum += impulse * normal;
      e.point_sum += impulse * point;
      e.last_normal = normal;
      e.last_point = point;
    }
  }
}

void World::tick() {
  tick_physics();
  check_walls_hold();
  sense();
}

void World::tick_physics() {
  if (model_->noise.any) {
    effort_ = noise_.effort();  // one draw of the effort's streams per tick
    if (has_pending_) {
      // A lost command comes back as NaN: that joint keeps the setpoint it had.
      const DofVector errors = noise_.commands(pending_);
      DofVector setpoints = q() + errors;
      for (int d = 0; d < kDofCount; ++d)
        if (std::isnan(errors[d])) setpoints[d] = setpoint_[d];
      set_setpoints(setpoints);
      has_pending_ = false;
    }
  }
  for (int i = 0; i < params_.substeps; ++i) step_physics();
}

// Found by a probe: the light body of docs/scenarios.md (base_mass 0.01, link_mass 0.001) drove
// its base through a wall and 21 m out of a 4 m arena, and the episode went on as if nothing had
// happened. A centre past a wall's inner face is at least a radius past where any contact stops it.
void World::check_walls_hold() const {
  const ArenaSpec& a = model_->spec.arena;
  const auto inside = [&](const b2Vec2& p) { return p.x >= a.xmin && p.x <= a.xmax && p.y >= a.ymin && p.y <= a.ymax; };
  const auto escaped = [&](const std::string& who, const b2Vec2& p, const std::string& why) {
    const auto cm = [](double v) { return format_number(std::round(v * 100.0) / 100.0); };
    throw Error("the physics failed at t = " + cm(time_) + " s: " + who + " went through the arena's walls, to (" +
                cm(p.x) + ", " + cm(p.y) + "), outside [" + format_number(a.xmin) +
                ", " + format_number(a.xmax) + "] x [" + format_number(a.ymin) + ", " + format_number(a.ymax) + "]: " +
                why);
  };
  const RobotParams& r = model_->spec.body;
  if (!inside(impl_->base->GetPosition())) {
    const RobotParams defaults;
    const bool light = r.base_mass < defaults.base_mass || r.link_mass < defaults.link_mass ||
                       r.hand_mass < defaults.hand_mass;
    escaped("Roger's base", impl_->base->GetPosition(),
            "its servos are tuned for the default body (base_mass 1, link_mass 0.2, hand_mass 0.05 kg), and this one "
            "(" + format_number(r.base_mass) + ", " + format_number(r.link_mass) + ", " + format_number(r.hand_mass) +
            " kg) " + (light ? "is too light for them: make it heavier" : "still lost them: report it, with the scenario "
            "and the world seed"));
  }
  for (size_t i = 0; i < impl_->objects.size(); ++i)
    if (!inside(impl_->objects[i]->GetPosition())) {
      const ObjectSpec& o = model_->spec.objects[i];
      escaped("object '" + o.name + "'", impl_->objects[i]->GetPosition(),
              "an object of " + format_number(o.mass) + " kg struck hard passes through them; make it heavier");
    }
}

void World::update_surfaces() {
  Impl& m = *impl_;
  const size_t n = model_->spec.objects.size();
  const bool first_sensing = m.surface_poses.size() != n;
  if (first_sensing) {
    m.surfaces.resize(m.static_surfaces);
    m.surface_poses.resize(n);
  }
  // Each object's surfaces follow the static ones, in object order, as many as its shape has
  // parts; only an object that moved since the last sensing is placed again (most lie still).
  size_t first = m.static_surfaces;
  for (size_t i = 0; i < n; ++i) {
    const auto& o = model_->spec.objects[i];
    const Pose pose = object_pose(int(i));
    Pose& last = m.surface_poses[i];
    const size_t parts = o.shape.polygons.size() + o.shape.disks.size();
    if (first_sensing) {
      append_seen_surfaces(m.surfaces, o.shape, pose, SurfaceKind::kObject, int(i), o.colour);
      last = pose;
    } else if (pose.x != last.x || pose.y != last.y || pose.theta != last.theta) {
      m.placed.clear();
      append_seen_surfaces(m.placed, o.shape, pose, SurfaceKind::kObject, int(i), o.colour);
      std::copy(m.placed.begin(), m.placed.end(), m.surfaces.begin() + std::ptrdiff_t(first));
      last = pose;
    }
    const bool away = put_away(int(i), pose);
    for (size_t k = first; k < first + parts; ++k) m.surfaces[k].ignored = away;
    first += parts;
  }
}

bool World::put_away(int i, const Pose& pose) const {
  const int r = attention_.ignore_region;
  if (r < 0 || size_t(r) >= model_->spec.goals.size()) return false;
  const GoalRegion& g = model_->spec.goals[size_t(r)];
  if ((Vec2(pose.x, pose.y) - g.center).norm() > g.radius) return false;
  return !held(i);  // still held: not put away yet
}

bool World::held(int i) const {
  for (const Touch& t : senses_.touch)
    if (t.contact && t.kind == SurfaceKind::kObject && t.index == i) return true;
  return false;
}

int World::region_of(int i) const {
  const Pose pose = object_pose(i);
  const Vec2 center(pose.x, pose.y);
  const std::vector<GoalRegion>& goals = model_->spec.goals;
  const Colour& colour = model_->spec.objects[size_t(i)].colour;
  // Regions may overlap (a sorting world's grow with their objects): one inside its own region
  // lies there, whatever other region holds it too (found by a probe: every object of a 12-object
  // world in its own region, one of them also in a neighbour's listed first, and the sort failed).
  int first = -1;
  for (size_t g = 0; g < goals.size(); ++g) {
    if ((center - goals[g].center).norm() > goals[g].radius) continue;
    if (goals[g].colour == colour) return int(g);
    if (first < 0) first = int(g);
  }
  return first;
}

int World::stimulus_objects() const {
  int n = 0;
  for (const ObjectSpec& o : model_->spec.objects) n += o.colour == attention_.colour;
  return n;
}

int World::kept_object(const Senses& s, bool several) {
  return !several ? -1 : s.stimulus[kLeft].seen ? s.stimulus[kLeft].index : s.stimulus[kRight].index;
}

void World::fix_stereo(Senses& s, const Vec2 eye_pos[2], const double eye_heading[2], bool several) {
  // ...and, with several, for no other: were it to take another one (the left's hidden from it),
  // each eye would centre its own object and search would call that found, with no stereo fix to
  // approach. Seen by one eye only, search steps aside instead.
  if (several && s.stimulus[kLeft].seen && s.stimulus[kRight].seen &&
      s.stimulus[kRight].index != s.stimulus[kLeft].index)
    s.stimulus[kRight] = Sighting{};
  // Stereo pairs the same object in both eyes.
  s.stereo_valid = s.stimulus[0].seen && s.stimulus[1].seen && s.stimulus[0].index == s.stimulus[1].index &&
                   triangulate(eye_pos[0], eye_heading[0] + s.stimulus[0].bearing, eye_pos[1],
                               eye_heading[1] + s.stimulus[1].bearing, s.stimulus_world);
  if (s.stereo_valid) s.stimulus_base = to_local(s.base, s.stimulus_world);
}

void World::sense() {
  Impl& m = *impl_;
  const RobotParams& r = model_->spec.body;
  Senses& s = senses_;
  s.time = time_;
  s.q = q();
  s.qdot = qdot();
  s.base = base_pose();

  update_surfaces();
  Vec2 eye_pos[2];
  double eye_heading[2];
  // With several objects of the stimulus colour, both eyes keep to the object they saw last tick
  // (the left eye's, or the right's when the left saw none) while it stays in view: picking the
  // larger each tick would flip between them as they turn or hide each other, and everything
  // downstream (the estimate, the planner's goal, which object is no obstacle) would flip with it.
  // With one, nothing changes: its runs are all of the same object.
  const bool several = stimulus_objects() > 1;
  const int kept = kept_object(s, several);
  for (int e = 0; e < 2; ++e) {
    eye_pos[e] = to_world(s.base, Vec2(0.0, e == kLeft ? r.eye_y : -r.eye_y));
    eye_heading[e] = s.base.theta + m.eye[e];
    paint_eye(model_->camera, eye_pos[e], eye_heading[e], m.surfaces, model_->spec.arena.wall_colour,
              attention_.colour, s.image[e]);
    // The right eye looks first for the left eye's object.
    s.stimulus[e] = detect_stimulus(s.image[e], e == kRight ? s.stimulus[kLeft].index : kept);
  }
  fix_stereo(s, eye_pos, eye_heading, several);
  sense_touch();
  if (model_->noise.any) sense_noise(several);
}

void World::sense_touch() {
  Impl& m = *impl_;
  const double tick_time = params_.dt * params_.substeps;
  for (int t = 0; t < kTactileCount; ++t) {
    TouchAccumulator& acc = m.touch[t];
    Touch out;
    const TouchEntry* best = nullptr;
    for (int i = 0; i < acc.count; ++i)
      if (!best || acc.entries[i].impulse > best->impulse) best = &acc.entries[i];
    if (best) {
      out.contact = true;
      out.kind = kind_of(best->other);
      out.index = out.kind == SurfaceKind::kWall ? -1 : index_of(best->other);
      out.force = best->impulse / tick_time;
      out.friction = best->tangent / tick_time;
      if (best->impulse > 0.0 && best->normal_sum.norm() > 0.0) {
        out.normal = best->normal_sum.normalized();
        out.point = best->point_sum / best->impulse;
      } else {
        out.normal = best->last_normal;
        out.point = best->last_point;
      }
    }
    senses_.touch[t] = out;
    acc.clear();
  }
}

void World::sense_noise(bool several) {
  const RobotParams& r = model_->spec.body;
  Senses& z = noisy_;
  // What the noisy eyes saw last tick decides which object they keep to, and a stereo fix that
  // fails keeps the last one they made (as the true senses do).
  const int kept = kept_object(z, several);
  const Vec2 last_world = z.stimulus_world, last_base = z.stimulus_base;
  const Sighting last_sighting[2] = {z.stimulus[0], z.stimulus[1]};
  z = senses_;
  z.stimulus_world = last_world, z.stimulus_base = last_base;
  noise_.pose(z);
  bool arrived[2];
  noise_.images(z, arrived);
  Vec2 eye_pos[2];
  double eye_heading[2];
  for (int e = 0; e < 2; ++e) {
    // Where Roger believes its eyes are, and where they look: the noisy base and pans.
    eye_pos[e] = to_world(z.base, Vec2(0.0, e == kLeft ? r.eye_y : -r.eye_y));
    eye_heading[e] = z.base.theta + z.q[kLeftEye + e];
    // An eye whose frame did not arrive keeps what it saw in the last one.
    if (!arrived[e]) z.stimulus[e] = last_sighting[e];
    else if (model_->spec.noise.image.any())
      z.stimulus[e] = detect_stimulus(z.image[e], e == kRight ? z.stimulus[kLeft].index : kept);
  }
  fix_stereo(z, eye_pos, eye_heading, several);
  noise_.touch(z);
}

Pose World::base_pose() const {
  const b2Body* b = impl_->base;
  return {b->GetPosition().x, b->GetPosition().y, wrap_angle(b->GetAngle())};
}

Vec2 World::base_velocity() const { return v2(impl_->base->GetLinearVelocity()); }

double World::base_lateral_speed() const {
  const b2Body* b = impl_->base;
  return b2Dot(b->GetLinearVelocity(), b->GetWorldVector(b2Vec2(0, 1)));
}

Pose World::object_pose(int i) const {
  const b2Body* b = impl_->objects.at(size_t(i));
  return {b->GetPosition().x, b->GetPosition().y, wrap_angle(b->GetAngle())};
}

Vec2 World::object_velocity(int i) const {
  return v2(impl_->objects.at(size_t(i))->GetLinearVelocity());
}

Vec2 World::hand_position(int side) const {
  const b2Body* forearm = impl_->link[side][1];
  return v2(forearm->GetWorldPoint(b2Vec2(float(0.5 * model_->spec.body.link_length[1]), 0.0f)));
}

ArmPoints World::arm_points(int side) const {
  const Impl& m = *impl_;
  const RobotParams& r = model_->spec.body;
  ArmPoints p;
  p.shoulder = v2(m.base->GetWorldPoint(
      b2Vec2(0.0f, float(side == kLeft ? r.shoulder_y : -r.shoulder_y))));
  p.elbow = v2(m.link[side][0]->GetWorldPoint(b2Vec2(float(0.5 * r.link_length[0]), 0.0f)));
  p.hand = hand_position(side);
  return p;
}

Frame World::frame() const {
  const RobotParams& r = model_->spec.body;
  Frame f;
  f.time = time_;
  f.base = base_pose();
  for (int side = 0; side < 2; ++side) {
    f.arms[side] = arm_points(side);
    f.eyes[side] = to_world(f.base, Vec2(0.0, side == kLeft ? r.eye_y : -r.eye_y));
    f.eye_heading[side] = f.base.theta + impl_->eye[side];
  }
  for (size_t i = 0; i < model_->spec.objects.size(); ++i) f.objects.push_back(object_pose(int(i)));
  f.senses = senses();
  return f;
}

uint64_t World::state_hash() const {
  uint64_t h = 1469598103934665603ull;  // FNV-1a
  auto mix = [&h](const void* data, size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  };
  for (const b2Body* b = impl_->world->GetBodyList(); b; b = b->GetNext()) {
    const b2Transform& x = b->GetTransform();
    const b2Vec2 v = b->GetLinearVelocity();
    const float w = b->GetAngularVelocity();
    mix(&x.p, sizeof x.p);
    mix(&x.q, sizeof x.q);
    mix(&v, sizeof v);
    mix(&w, sizeof w);
  }
  mix(impl_->eye, sizeof impl_->eye);
  mix(&impl_->odometer, sizeof impl_->odometer);
  mix(setpoint_.data(), sizeof(double) * kDofCount);
  mix(&time_, sizeof time_);
  return h;
}

}  // namespace roger
