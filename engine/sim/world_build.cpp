// world_build.cpp: World::reset, which builds an episode's Box2D world from its spec: the walls,
// the obstacles, the objects, Roger's base and its rail, the arms, and the servos' start state.
#include <algorithm>
#include <cmath>
#if defined(__SSE__) || defined(__x86_64__)
#include <xmmintrin.h>
#endif

#include "core/body.h"
#include "core/error.h"
#include "core/shape.h"
#include "sim/world_internal.h"

namespace roger {

using namespace world_internal;

namespace {

// Sets the processor's SSE control: flush subnormal results to zero, read subnormal inputs as zero.
void flush_subnormals_to_zero() {
#if defined(__SSE__) || defined(__x86_64__)
  _mm_setcsr(_mm_getcsr() | 0x8040u);  // FTZ (bit 15) | DAZ (bit 6)
#endif
}

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

// One of Roger's disks (the base, a hand) with its mass spread over it: it meets the walls, the
// obstacles and the objects, never another part of Roger (group -1).
void add_robot_disk(b2Body* body, const Vec2& center, double radius, double mass, double friction) {
  b2CircleShape cs;
  cs.m_radius = float(radius);
  cs.m_p = b2v(center);
  b2FixtureDef fd;
  fd.shape = &cs;
  fd.density = float(mass / (M_PI * radius * radius));
  fd.friction = float(friction);
  fd.filter.categoryBits = kCatRobot;
  fd.filter.maskBits = kCatWall | kCatObstacle | kCatObject;
  fd.filter.groupIndex = -1;
  body->CreateFixture(&fd);
}

// One arm link as a dynamic body from `from` to `to` at world angle `angle`: the forearm (l == 1)
// carries the tactile hand disk at its end; both carry the link's mass. The angle is the base's
// heading plus the joint angles before it, not atan2 of the link's direction: Box2D reads a
// revolute joint's angle as the difference of its bodies' angles, so a link angle wrapped to
// [-pi, pi] on its own would make the joint read its angle plus or minus 2 pi (a shoulder at 1.975
// read as -4.308), and the first command clamped to the joint limits would spin the arm round.
b2Body* create_link(b2World& w, const RobotParams& r, int side, int l, const Vec2& from,
                    const Vec2& to, double angle) {
  const Vec2 mid = 0.5 * (from + to);
  b2BodyDef ld;
  ld.type = b2_dynamicBody;
  ld.allowSleep = false;
  ld.position = b2v(mid);
  ld.angle = float(angle);
  b2Body* link = w.CreateBody(&ld);
  const double half = 0.5 * r.link_length[l];
  if (l == 1) {  // the hand: a tactile disk at the end of the forearm
    add_robot_disk(link, Vec2(half, 0.0), r.hand_radius, r.hand_mass, r.surface_friction);
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
  return link;
}

// The motorized revolute joint of link `l` to its parent at `from`.
b2RevoluteJoint* create_arm_joint(b2World& w, const RobotParams& r, b2Body* parent, b2Body* link,
                                  const Vec2& from, int l) {
  b2RevoluteJointDef jd;
  jd.Initialize(parent, link, b2v(from));
  jd.referenceAngle = 0.0f;  // joint angle = absolute joint coordinate, not relative to start
  // No Box2D joint limits: setpoints are clamped to the limits instead, which keeps the
  // solver cheaper (limits are the costliest part of a revolute joint) and nothing can push
  // an arm far past them, since links do not collide.
  const bool elbow = l == 1;
  jd.enableMotor = true;
  jd.maxMotorTorque = float(elbow ? r.elbow.max_effort : r.shoulder.max_effort);
  return static_cast<b2RevoluteJoint*>(w.CreateJoint(&jd));
}

}  // namespace

void World::reset(const WorldSpec& spec) {
  derive_world_model(spec, params_, -1.0, own_model_);
  reset(own_model_);
}

void World::reset(const WorldModel& model) {
  if (model.params.dt != params_.dt || model.params.substeps != params_.substeps ||
      model.params.velocity_iterations != params_.velocity_iterations ||
      model.params.position_iterations != params_.position_iterations)
    throw Error("world: the model was derived for other physics parameters than this world's");
  // Box2D's float solver lets a resting arm's velocities decay into subnormal numbers, which cost
  // the processor a hundred times a normal operation: with the arms at rest in the posture asked
  // for, b2RevoluteJoint's velocity solver took half of a transport trial's time. Subnormals are
  // flushed to zero on the thread that runs the episode, from its start, whichever thread it is.
  flush_subnormals_to_zero();
  // The model was checked when it was derived (check_world_spec): nothing here reaches one of
  // Box2D's asserts.
  model_ = &model;
  const WorldSpec& spec = model.spec;
  attention_ = Attention{spec.stimulus_colour, -1, -1};

  Impl& m = *impl_;
  m.objects.clear();
  m.pushes.clear();
  m.world = std::make_unique<b2World>(b2Vec2(0.0f, 0.0f));
  // Everything moves slowly against thick walls: continuous collision would cost time for nothing.
  m.world->SetContinuousPhysics(false);
  time_ = 0.0;

  m.add_walls(spec.arena);
  m.add_obstacles(spec.obstacles);
  m.add_objects(spec.objects);
  // Roger.
  const RobotParams& r = spec.body;
  m.add_base(r, spec.robot.pose);
  m.add_rail();
  m.add_arms(r, spec.robot);
  m.reset_servos(r, spec.robot);
  setpoint_ = q();
  locked_at_ = setpoint_;
  if (r.locked) m.lock_joints(r);
  senses_ = Senses{};
  noisy_ = Senses{};
  // The noise's own streams, a function of the world's seed alone (not of the episode's order,
  // the thread or --jobs).
  if (model.noise.any) noise_.reset(spec.noise, spec.seed, model.camera.pixels, model.tick_seconds());
  effort_ = nullptr;
  has_pending_ = false;
  sense();
}

void World::Impl::add_walls(const ArenaSpec& a) {
  b2World& w = *world;
  // Walls: four thick boxes just outside the arena (thick so nothing tunnels through).
  b2BodyDef gd;
  ground = w.CreateBody(&gd);
  ground->GetUserData().pointer = encode(SurfaceKind::kWall, -1);
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
    ground->CreateFixture(&fd);
  }
}

void World::Impl::add_obstacles(const std::vector<ObstacleSpec>& obstacles) {
  b2World& w = *world;
  // Obstacles: static bodies at their poses.
  surfaces.clear();
  surface_poses.clear();
  for (size_t i = 0; i < obstacles.size(); ++i) {
    const auto& o = obstacles[i];
    b2BodyDef bd;
    bd.position.Set(float(o.pose.x), float(o.pose.y));
    bd.angle = float(o.pose.theta);
    b2Body* body = w.CreateBody(&bd);
    body->GetUserData().pointer = encode(SurfaceKind::kObstacle, int(i));
    add_shape_fixtures(body, o.shape, 0.0f, 0.5f, kCatObstacle, 0xffff);
    append_seen_surfaces(surfaces, o.shape, o.pose, SurfaceKind::kObstacle, int(i), o.colour);
  }
  static_surfaces = surfaces.size();
}

void World::Impl::add_objects(const std::vector<ObjectSpec>& specs) {
  b2World& w = *world;
  // Objects: dynamic bodies held to the floor by a friction joint (static friction threshold) and
  // slowed by damping (viscosity).
  for (size_t i = 0; i < specs.size(); ++i) {
    const auto& o = specs[i];
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
    fj.Initialize(ground, body, body->GetWorldCenter());
    fj.maxForce = float(o.friction_force);
    fj.maxTorque = float(o.friction_torque);
    // The floor's friction acts through a joint to the ground body, which also carries the walls;
    // Box2D lets jointed bodies pass through each other unless told otherwise.
    fj.collideConnected = true;
    w.CreateJoint(&fj);
    objects.push_back(body);
  }
}

void World::Impl::add_base(const RobotParams& r, const Pose& start) {
  b2BodyDef bd;
  bd.type = b2_dynamicBody;
  bd.allowSleep = false;
  bd.position.Set(float(start.x), float(start.y));
  bd.angle = float(start.theta);
  base = world->CreateBody(&bd);
  base->GetUserData().pointer = encode(SurfaceKind::kNone, int(kBody));
  add_robot_disk(base, Vec2(0.0, 0.0), r.base_radius, r.base_mass, r.surface_friction);
}

void World::Impl::add_rail() {
  // The no-slip constraint: a wheel joint to a kinematic rail that is moved onto the base before
  // every step, so the solver itself removes sideways velocity whatever pushes the base.
  b2BodyDef rd;
  rd.type = b2_kinematicBody;
  rd.position = base->GetPosition();
  rd.angle = base->GetAngle();
  rail = world->CreateBody(&rd);
  b2WheelJointDef wj;
  wj.Initialize(rail, base, base->GetPosition(), rail->GetWorldVector(b2Vec2(1, 0)));
  wj.stiffness = 0.0f;
  wj.damping = 0.0f;
  world->CreateJoint(&wj);
}

void World::Impl::add_arms(const RobotParams& r, const RobotStart& start) {
  b2World& w = *world;
  const double start_q[2][2] = {{start.left_shoulder, start.left_elbow},
                                {start.right_shoulder, start.right_elbow}};
  const Pose& pose = start.pose;
  for (int side = 0; side < 2; ++side) {
    const ArmPoints p = arm_forward_kinematics(r, pose, side, start_q[side][0], start_q[side][1]);
    const Vec2 from[2] = {p.shoulder, p.elbow}, to[2] = {p.elbow, p.hand};
    const double angle[2] = {pose.theta + start_q[side][0],
                             pose.theta + start_q[side][0] + start_q[side][1]};
    b2Body* parent = base;
    for (int l = 0; l < 2; ++l) {
      b2Body* body = create_link(w, r, side, l, from[l], to[l], angle[l]);
      joint[side][l] = create_arm_joint(w, r, parent, body, from[l], l);
      link[side][l] = body;
      parent = body;
    }
  }
}

void World::Impl::lock_joints(const RobotParams& r) {
  // A locked arm joint is held by Box2D's limits closed on its start angle, whatever pushes it
  // (its setpoint stays there too: World::set_setpoints).
  for (int side = 0; side < 2; ++side)
    for (int l = 0; l < 2; ++l)
      if (is_locked(r, kLeftShoulder + 2 * side + l)) {
        b2RevoluteJoint* j = joint[side][l];
        const float at = j->GetJointAngle();
        j->SetLimits(at, at);
        j->EnableLimit(true);
      }
}

void World::Impl::reset_servos(const RobotParams& r, const RobotStart& start) {
  odometer = 0.0;
  eye[0] = std::clamp(start.left_eye, -r.eye_pan_limit, r.eye_pan_limit);
  eye[1] = std::clamp(start.right_eye, -r.eye_pan_limit, r.eye_pan_limit);
  eye_rate[0] = eye_rate[1] = 0.0;
  for (auto& t : touch) t.clear();
}

}  // namespace roger

// Box2D 2.4's b2World::Step times its phases for b2World::GetProfile() with b2Timer, which reads
// the wall clock about a dozen times per step: a quarter of the cost of a physics step of Roger's
// small world, for a profile the engine never reads. These definitions take the place of the
// library's (its calls to b2Timer go through the PLT, so the executable's definitions win), and
// make the profile all zeros. Nothing else changes: the timer never feeds back into the physics.
// test_world pins both: the profile stays zero, and a stepped world's hash is unchanged.
b2Timer::b2Timer() : m_start_sec(0), m_start_usec(0) {}
void b2Timer::Reset() {}
float b2Timer::GetMilliseconds() const { return 0.0f; }
