#include "sim/world.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <box2d/box2d.h>

#include "core/error.h"
#include "core/shape.h"

namespace roger {

const std::array<const char*, kDofCount> kDofNames = {
    "base_forward", "base_heading", "left_eye",       "right_eye",
    "left_shoulder", "left_elbow",  "right_shoulder", "right_elbow"};

namespace {

// Collision categories: the robot's hands and body touch everything but each other; arm links are
// drawn but never collide (as in the original simulator, only the three elastic bodies touch).
constexpr uint16 kCatWall = 0x1, kCatObstacle = 0x2, kCatObject = 0x4, kCatRobot = 0x8;

// Body identity, kept in Box2D's user data so a contact tells what was touched.
uintptr_t encode(SurfaceKind kind, int index) {
  return (uintptr_t(kind) << 32) | uint32_t(index + 1);
}
SurfaceKind kind_of(uintptr_t id) { return SurfaceKind(id >> 32); }
int index_of(uintptr_t id) { return int(uint32_t(id & 0xffffffffu)) - 1; }

double clamp_abs(double v, double limit) { return std::clamp(v, -limit, limit); }

b2Vec2 b2v(const Vec2& v) { return b2Vec2(float(v.x()), float(v.y())); }
Vec2 v2(const b2Vec2& v) { return Vec2(v.x, v.y); }

// Adds the fixtures of a validated shape to a body, spreading `density` over its parts.
void add_shape_fixtures(b2Body* body, const Shape& shape, float density, float friction,
                        uint16 category, uint16 mask) {
  b2FixtureDef fd;
  fd.density = density;
  fd.friction = friction;
  fd.restitution = 0.0f;
  fd.filter.categoryBits = category;
  fd.filter.maskBits = mask;
  for (const auto& poly : shape.polygons) {
    b2Vec2 pts[kMaxPolygonVertices];
    const int n = int(poly.vertices.size());
    for (int i = 0; i < n; ++i) pts[i] = b2v(poly.vertices[i]);
    b2PolygonShape ps;
    ps.Set(pts, n);
    fd.shape = &ps;
    body->CreateFixture(&fd);
  }
  for (const auto& disk : shape.disks) {
    b2CircleShape cs;
    cs.m_p = b2v(disk.center);
    cs.m_radius = float(disk.radius);
    fd.shape = &cs;
    body->CreateFixture(&fd);
  }
}

// Touch accumulated over the physics steps of one control tick, per touched body.
struct TouchEntry {
  uintptr_t other = 0;
  double impulse = 0.0, tangent = 0.0;
  Vec2 normal_sum = Vec2::Zero(), point_sum = Vec2::Zero(), last_normal = Vec2::Zero(),
       last_point = Vec2::Zero();
};
constexpr int kTouchEntries = 4;
struct TouchAccumulator {
  std::array<TouchEntry, kTouchEntries> entries;
  int count = 0;
  void clear() { count = 0; }
  TouchEntry& entry(uintptr_t other) {
    for (int i = 0; i < count; ++i)
      if (entries[i].other == other) return entries[i];
    if (count == kTouchEntries) return entries[kTouchEntries - 1];  // rare: merge the surplus
    entries[count] = TouchEntry{};
    entries[count].other = other;
    return entries[count++];
  }
};

}  // namespace

struct World::Impl {
  std::unique_ptr<b2World> world;
  b2Body* ground = nullptr;
  b2Body* rail = nullptr;  // kinematic body that carries the base's no-slip (wheel) constraint
  b2Body* base = nullptr;
  b2Body* link[2][2] = {{nullptr, nullptr}, {nullptr, nullptr}};  // [side][upper, forearm]
  b2RevoluteJoint* joint[2][2] = {{nullptr, nullptr}, {nullptr, nullptr}};
  std::vector<b2Body*> objects;
  std::vector<Vec2> pushes;
  double odometer = 0.0;
  double eye[2] = {0.0, 0.0}, eye_rate[2] = {0.0, 0.0};
  std::array<TouchAccumulator, kTactileCount> touch;
  std::vector<SeenSurface> surfaces;  // obstacles (static) first, then objects (moved each tick)
  size_t static_surfaces = 0;
  b2Body* tactile(int t) const { return t == kBody ? base : link[t == kLeftHand ? 0 : 1][1]; }
};

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

World::World(const WorldParams& params) : params_(params), impl_(std::make_unique<Impl>()) {
  if (!(params_.dt > 0.0) || params_.substeps < 1)
    throw Error("world parameters: dt must be positive and substeps at least 1");
}

World::~World() = default;

b2World* World::physics() { return impl_->world.get(); }

void World::reset(const WorldSpec& spec_in) {
  spec_ = spec_in;
  for (auto& o : spec_.objects) validate_shape(o.shape);
  for (auto& o : spec_.obstacles) validate_shape(o.shape);
  const auto& a = spec_.arena;
  if (!(a.xmax > a.xmin && a.ymax > a.ymin))
    throw Error("arena: xmax must exceed xmin and ymax exceed ymin");

  Impl& m = *impl_;
  m.objects.clear();
  m.pushes.clear();
  m.world = std::make_unique<b2World>(b2Vec2(0.0f, 0.0f));
  b2World& w = *m.world;
  // Everything moves slowly against thick walls: continuous collision would cost time for nothing.
  w.SetContinuousPhysics(false);
  time_ = 0.0;

  // Walls: four thick boxes just outside the arena (thick so nothing tunnels through).
  b2BodyDef gd;
  m.ground = w.CreateBody(&gd);
  m.ground->GetUserData().pointer = encode(SurfaceKind::kWall, -1);
  {
    const float t = 0.25f;
    const float cx = float(0.5 * (a.xmin + a.xmax)), cy = float(0.5 * (a.ymin + a.ymax));
    const float hw = float(0.5 * (a.xmax - a.xmin)), hh = float(0.5 * (a.ymax - a.ymin));
    b2FixtureDef fd;
    fd.friction = 0.3f;
    fd.filter.categoryBits = kCatWall;
    b2PolygonShape box;
    const b2Vec2 centers[4] = {{cx, float(a.ymax) + t}, {cx, float(a.ymin) - t},
                               {float(a.xmin) - t, cy}, {float(a.xmax) + t, cy}};
    const b2Vec2 halves[4] = {{hw + 2 * t, t}, {hw + 2 * t, t}, {t, hh + 2 * t}, {t, hh + 2 * t}};
    for (int i = 0; i < 4; ++i) {
      box.SetAsBox(halves[i].x, halves[i].y, centers[i], 0.0f);
      fd.shape = &box;
      m.ground->CreateFixture(&fd);
    }
  }

  // Obstacles: static bodies at their poses.
  m.surfaces.clear();
  for (size_t i = 0; i < spec_.obstacles.size(); ++i) {
    const auto& o = spec_.obstacles[i];
    b2BodyDef bd;
    bd.position.Set(float(o.pose.x), float(o.pose.y));
    bd.angle = float(o.pose.theta);
    b2Body* body = w.CreateBody(&bd);
    body->GetUserData().pointer = encode(SurfaceKind::kObstacle, int(i));
    add_shape_fixtures(body, o.shape, 0.0f, 0.5f, kCatObstacle, 0xffff);
    append_seen_surfaces(m.surfaces, o.shape, o.pose, SurfaceKind::kObstacle, int(i), o.colour);
  }
  m.static_surfaces = m.surfaces.size();

  // Objects: dynamic bodies held to the floor by a friction joint (static friction threshold) and
  // slowed by damping (viscosity).
  for (size_t i = 0; i < spec_.objects.size(); ++i) {
    const auto& o = spec_.objects[i];
    if (!(o.mass > 0.0) || !std::isfinite(o.mass))
      throw Error("object '" + o.name + "': mass must be a positive number");
    b2BodyDef bd;
    bd.type = b2_dynamicBody;
    bd.position.Set(float(o.pose.x), float(o.pose.y));
    bd.angle = float(o.pose.theta);
    bd.linearDamping = float(o.viscosity);
    bd.angularDamping = float(o.angular_viscosity);
    b2Body* body = w.CreateBody(&bd);
    body->GetUserData().pointer = encode(SurfaceKind::kObject, int(i));
    add_shape_fixtures(body, o.shape, float(o.mass / shape_area(o.shape)),
                       float(o.surface_friction), kCatObject, 0xffff);
    b2FrictionJointDef fj;
    fj.Initialize(m.ground, body, body->GetWorldCenter());
    fj.maxForce = float(o.friction_force);
    fj.maxTorque = float(o.friction_torque);
    w.CreateJoint(&fj);
    m.objects.push_back(body);
  }

  // Roger.
  const RobotParams& r = params_.robot;
  const Pose& start = spec_.robot.pose;
  b2BodyDef bd;
  bd.type = b2_dynamicBody;
  bd.allowSleep = false;
  bd.position.Set(float(start.x), float(start.y));
  bd.angle = float(start.theta);
  m.base = w.CreateBody(&bd);
  m.base->GetUserData().pointer = encode(SurfaceKind::kNone, int(kBody));
  {
    b2CircleShape cs;
    cs.m_radius = float(r.base_radius);
    b2FixtureDef fd;
    fd.shape = &cs;
    fd.density = float(r.base_mass / (M_PI * r.base_radius * r.base_radius));
    fd.friction = float(r.surface_friction);
    fd.filter.categoryBits = kCatRobot;
    fd.filter.maskBits = kCatWall | kCatObstacle | kCatObject;
    fd.filter.groupIndex = -1;
    m.base->CreateFixture(&fd);
  }
  // The no-slip constraint: a wheel joint to a kinematic rail that is moved onto the base before
  // every step, so the solver itself removes sideways velocity whatever pushes the base.
  {
    b2BodyDef rd;
    rd.type = b2_kinematicBody;
    rd.position = m.base->GetPosition();
    rd.angle = m.base->GetAngle();
    m.rail = w.CreateBody(&rd);
    b2WheelJointDef wj;
    wj.Initialize(m.rail, m.base, m.base->GetPosition(), m.rail->GetWorldVector(b2Vec2(1, 0)));
    wj.stiffness = 0.0f;
    wj.damping = 0.0f;
    w.CreateJoint(&wj);
  }
  const double start_q[2][2] = {{spec_.robot.left_shoulder, spec_.robot.left_elbow},
                                {spec_.robot.right_shoulder, spec_.robot.right_elbow}};
  for (int side = 0; side < 2; ++side) {
    const ArmPoints p = arm_forward_kinematics(r, start, side, start_q[side][0], start_q[side][1]);
    const Vec2 from[2] = {p.shoulder, p.elbow}, to[2] = {p.elbow, p.hand};
    b2Body* parent = m.base;
    for (int l = 0; l < 2; ++l) {
      const Vec2 mid = 0.5 * (from[l] + to[l]);
      const Vec2 d = to[l] - from[l];
      b2BodyDef ld;
      ld.type = b2_dynamicBody;
      ld.allowSleep = false;
      ld.position = b2v(mid);
      ld.angle = float(std::atan2(d.y(), d.x()));
      b2Body* link = w.CreateBody(&ld);
      const double half = 0.5 * r.link_length[l];
      if (l == 1) {  // the hand: a tactile disk at the end of the forearm
        b2CircleShape hs;
        hs.m_radius = float(r.hand_radius);
        hs.m_p.Set(float(half), 0.0f);
        b2FixtureDef hd;
        hd.shape = &hs;
        hd.density = float(r.hand_mass / (M_PI * r.hand_radius * r.hand_radius));
        hd.friction = float(r.surface_friction);
        hd.filter.categoryBits = kCatRobot;
        hd.filter.maskBits = kCatWall | kCatObstacle | kCatObject;
        hd.filter.groupIndex = -1;
        link->CreateFixture(&hd);
        link->GetUserData().pointer =
            encode(SurfaceKind::kNone, side == kLeft ? kLeftHand : kRightHand);
      }
      // Links never collide, so they carry mass but no fixture of their own: nothing for the
      // broad phase to do. Their mass is added to whatever the hand fixture gave the body
      // (Box2D's I is about the body origin, which is the link's centre).
      b2MassData md;
      md.mass = 0.0f, md.center.SetZero(), md.I = 0.0f;
      // (A dynamic body without fixtures reports Box2D's default mass of 1 kg: skip it.)
      if (link->GetFixtureList()) link->GetMassData(&md);
      const double link_mass = r.link_mass, total = md.mass + link_mass;
      md.center = float(md.mass / total) * md.center;
      md.I += float(link_mass * r.link_length[l] * r.link_length[l] / 12.0);
      md.mass = float(total);
      link->SetMassData(&md);
      b2RevoluteJointDef jd;
      jd.Initialize(parent, link, b2v(from[l]));
      jd.referenceAngle = 0.0f;  // joint angle = absolute joint coordinate, not relative to start
      // No Box2D joint limits: setpoints are clamped to the limits instead, which keeps the
      // solver cheaper (limits are the costliest part of a revolute joint) and nothing can push
      // an arm far past them, since links do not collide.
      const bool elbow = l == 1;
      jd.enableMotor = true;
      jd.maxMotorTorque = float(elbow ? r.elbow.max_effort : r.shoulder.max_effort);
      m.joint[side][l] = static_cast<b2RevoluteJoint*>(w.CreateJoint(&jd));
      m.link[side][l] = link;
      parent = link;
    }
  }
  m.odometer = 0.0;
  m.eye[0] = std::clamp(spec_.robot.left_eye, -r.eye_pan_limit, r.eye_pan_limit);
  m.eye[1] = std::clamp(spec_.robot.right_eye, -r.eye_pan_limit, r.eye_pan_limit);
  m.eye_rate[0] = m.eye_rate[1] = 0.0;
  for (auto& t : m.touch) t.clear();
  setpoint_ = q();
  senses_ = Senses{};
  sense();
}

DofVector World::q() const {
  const Impl& m = *impl_;
  DofVector v;
  v[kBaseForward] = m.odometer;
  v[kBaseHeading] = m.base->GetAngle();
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
  const RobotParams& r = params_.robot;
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
}

void World::command(const DofVector& errors) { set_setpoints(q() + errors); }

void World::push_object(int i, const Vec2& force) {
  Impl& m = *impl_;
  if (m.pushes.size() < m.objects.size()) m.pushes.assign(m.objects.size(), Vec2::Zero());
  m.pushes.at(size_t(i)) += force;
}

void World::step_physics() {
  Impl& m = *impl_;
  const RobotParams& r = params_.robot;
  const double dt = params_.dt;

  // Base servos: position error -> desired rate -> force, both clamped.
  const b2Vec2 fwd = m.base->GetWorldVector(b2Vec2(1, 0));
  const double v = b2Dot(m.base->GetLinearVelocity(), fwd);
  const double v_des = clamp_abs(r.base_forward.kp * (setpoint_[kBaseForward] - m.odometer),
                                 r.base_forward.max_rate);
  const double force = clamp_abs(r.base_forward.kv * (v_des - v), r.base_forward.max_effort);
  m.base->ApplyForceToCenter(float(force) * fwd, true);
  const double w_des = clamp_abs(r.base_heading.kp * (setpoint_[kBaseHeading] - m.base->GetAngle()),
                                 r.base_heading.max_rate);
  const double torque =
      clamp_abs(r.base_heading.kv * (w_des - m.base->GetAngularVelocity()), r.base_heading.max_effort);
  m.base->ApplyTorque(float(torque), true);
  // Over a step a wheeled base moves along the chord of its arc, which lies along the mid-step
  // heading: point the rail there (predicted from the current turn rate).
  const float mid_heading = m.base->GetAngle() + 0.5f * float(dt) * m.base->GetAngularVelocity();
  m.rail->SetTransform(m.base->GetPosition(), mid_heading);
  const b2Vec2 mid_fwd(std::cos(mid_heading), std::sin(mid_heading));

  // Eyes: light, first-order rate servos.
  for (int e = 0; e < 2; ++e) {
    const double rate = clamp_abs(r.eye.kp * (setpoint_[kLeftEye + e] - m.eye[e]), r.eye.max_rate);
    m.eye[e] = std::clamp(m.eye[e] + rate * dt, -r.eye_pan_limit, r.eye_pan_limit);
    m.eye_rate[e] = rate;
  }
  // Arms: Box2D motors are implicit velocity servos with a torque limit: stable at any gain.
  for (int side = 0; side < 2; ++side)
    for (int l = 0; l < 2; ++l) {
      const ServoParams& sp = l == 0 ? r.shoulder : r.elbow;
      b2RevoluteJoint* j = m.joint[side][l];
      const int dof = kLeftShoulder + 2 * side + l;
      j->SetMotorSpeed(float(clamp_abs(sp.kp * (setpoint_[dof] - j->GetJointAngle()), sp.max_rate)));
    }
  for (size_t i = 0; i < m.pushes.size(); ++i)
    if (m.pushes[i] != Vec2::Zero()) m.objects[i]->ApplyForceToCenter(b2v(m.pushes[i]), true);
  m.pushes.clear();

  const b2Vec2 before = m.base->GetPosition();
  m.world->Step(float(dt), params_.velocity_iterations, params_.position_iterations);
  m.odometer += b2Dot(m.base->GetPosition() - before, mid_fwd);
  // The wheels turn with the base: the solver kept the velocity along the mid-step heading, so
  // carry it onto the new heading, where the next step starts.
  m.base->SetLinearVelocity(b2Dot(m.base->GetLinearVelocity(), mid_fwd) *
                            m.base->GetWorldVector(b2Vec2(1, 0)));
  time_ += dt;

  // Touch: impulses of this step, per sensor and touched body.
  for (int t = 0; t < kTactileCount; ++t) {
    b2Body* body = m.tactile(t);
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
      TouchEntry& e = m.touch[t].entry(edge->other->GetUserData().pointer);
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
  for (int i = 0; i < params_.substeps; ++i) step_physics();
  sense();
}

void World::update_surfaces() {
  Impl& m = *impl_;
  m.surfaces.resize(m.static_surfaces);
  for (size_t i = 0; i < spec_.objects.size(); ++i) {
    const auto& o = spec_.objects[i];
    append_seen_surfaces(m.surfaces, o.shape, object_pose(int(i)), SurfaceKind::kObject, int(i), o.colour);
  }
}

void World::sense() {
  Impl& m = *impl_;
  const RobotParams& r = params_.robot;
  Senses& s = senses_;
  s.time = time_;
  s.q = q();
  s.qdot = qdot();
  s.base = base_pose();

  update_surfaces();
  Vec2 eye_pos[2];
  double eye_heading[2];
  for (int e = 0; e < 2; ++e) {
    eye_pos[e] = to_world(s.base, Vec2(0.0, e == kLeft ? r.eye_y : -r.eye_y));
    eye_heading[e] = s.base.theta + m.eye[e];
    paint_eye(eye_pos[e], eye_heading[e], m.surfaces, spec_.arena.wall_colour,
              spec_.stimulus_colour, s.image[e]);
    s.stimulus[e] = detect_stimulus(s.image[e]);
  }
  s.stereo_valid = s.stimulus[0].seen && s.stimulus[1].seen &&
                   triangulate(eye_pos[0], eye_heading[0] + s.stimulus[0].bearing, eye_pos[1],
                               eye_heading[1] + s.stimulus[1].bearing, s.stimulus_world);
  if (s.stereo_valid) s.stimulus_base = to_local(s.base, s.stimulus_world);

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
    s.touch[t] = out;
    acc.clear();
  }
}

Pose World::base_pose() const {
  const b2Body* b = impl_->base;
  return {b->GetPosition().x, b->GetPosition().y, b->GetAngle()};
}

Vec2 World::base_velocity() const { return v2(impl_->base->GetLinearVelocity()); }

double World::base_lateral_speed() const {
  const b2Body* b = impl_->base;
  return b2Dot(b->GetLinearVelocity(), b->GetWorldVector(b2Vec2(0, 1)));
}

Pose World::object_pose(int i) const {
  const b2Body* b = impl_->objects.at(size_t(i));
  return {b->GetPosition().x, b->GetPosition().y, b->GetAngle()};
}

Vec2 World::object_velocity(int i) const {
  return v2(impl_->objects.at(size_t(i))->GetLinearVelocity());
}

Vec2 World::hand_position(int side) const {
  const b2Body* forearm = impl_->link[side][1];
  return v2(forearm->GetWorldPoint(b2Vec2(float(0.5 * params_.robot.link_length[1]), 0.0f)));
}

ArmPoints World::arm_points(int side) const {
  const Impl& m = *impl_;
  const RobotParams& r = params_.robot;
  ArmPoints p;
  p.shoulder = v2(m.base->GetWorldPoint(
      b2Vec2(0.0f, float(side == kLeft ? r.shoulder_y : -r.shoulder_y))));
  p.elbow = v2(m.link[side][0]->GetWorldPoint(b2Vec2(float(0.5 * r.link_length[0]), 0.0f)));
  p.hand = hand_position(side);
  return p;
}

Frame World::frame() const {
  const RobotParams& r = params_.robot;
  Frame f;
  f.time = time_;
  f.base = base_pose();
  for (int side = 0; side < 2; ++side) {
    f.arms[side] = arm_points(side);
    f.eyes[side] = to_world(f.base, Vec2(0.0, side == kLeft ? r.eye_y : -r.eye_y));
    f.eye_heading[side] = f.base.theta + impl_->eye[side];
  }
  for (size_t i = 0; i < spec_.objects.size(); ++i) f.objects.push_back(object_pose(int(i)));
  f.senses = senses_;
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
