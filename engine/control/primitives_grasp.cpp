// primitives_grasp.cpp: the grasp family: phi2 (visual preshape), phi3 (contact configuration)
// and phi5 (dynamic contact adjustment), over the contact geometry of primitives_contact.cpp.
#include <algorithm>
#include <cmath>

#include "control/primitives_internal.h"

namespace roger {
namespace primitives_internal {
namespace {

// The DOFs a grasp stage may move: the arms, with the base forward, or the whole base.
const DofVector kArmsAndForward =
    mask({kBaseForward, kLeftShoulder, kLeftElbow, kRightShoulder, kRightElbow});
const DofVector kArmsOnly = mask({kLeftShoulder, kLeftElbow, kRightShoulder, kRightElbow});
const DofVector kArmsAndBase =
    mask({kBaseForward, kBaseHeading, kLeftShoulder, kLeftElbow, kRightShoulder, kRightElbow});

// phi2: visual preshape. From the stereo estimate of the object, the body goes to a standoff on
// the line to the object and the hands to a standoff circle at +-spread around it; phi is
// |sum of unit contact normals|^2 over body and hands. Effectors: base forward and arms; the task
// (5 rows) leaves the heading, with the arms compensating, free for a subordinate such as phi4.
// With body = "clear" the body's distance is only bounded below by the standoff (4 rows while
// clear of it), so a subordinate may also move the base along the line, arms compensating. That
// is the freedom phi4 needs: with only the heading free, as in "standoff", a preshape symmetric
// about the line leaves phi4 nothing to gain (turning opens one elbow and closes the other).
class Preshape final : public Primitive {
  // Where the constructor declared each parameter: reading one is an index, not a name search.
  struct {
    ParamSlot standoff = 0, spread = 0, swing = 0, phi_max = 0, memory = 0, damping = 0, body = 0;
    BodySlot reach;
  } p_;
 public:
  Preshape() : Primitive("phi2", 0.04) {
    p_.standoff = declare("standoff", 0.05, 0.0, 0.5, "gap (m) between the object's surface and the hands and body");
    // 1.7 rad, not 1.85: a hand sent less far round the object is less often caught on a
    // polygon's corner or an obstacle beside it on its way (docs/results.md).
    p_.spread = declare("spread", 1.7, 1.0, 3.0, "angle (rad) of each hand from the body around the object");
    p_.swing = declare("swing", 0.15, 0.0, 1.0, "how far (m) a hand swings out while going round the object");
    p_.phi_max = declare("phi_max", 1.0, 0.0, 9.0, "largest |sum of normals|^2 counted as preshaped");
    p_.reach = declare_body("reach", &BodyMetrics::preshape_reach, 0.3, 3.0, "objects farther (m) than this from the base are out of reach");
    p_.memory = declare("memory", 2.0, 0.0, 60.0, "seconds a lost object's last position stays usable");
    p_.damping = declare("damping", 0.05, 0.0, 1.0, "least-squares damping near singular postures");
    p_.body = declare_text("body", {"standoff", "clear"},
                           "body to the standoff, or only kept clear of it (its distance left to a subordinate)");
    on_params_changed();
  }
  PrimitivePtr clone() const override { return std::make_shared<Preshape>(*this); }
  void reset(uint64_t seed) override {
    Primitive::reset(seed);
    view_tick_ = UINT64_MAX;
  }
  // Nothing is carried from tick to tick (the view is only this tick's, shared by both paths).
  bool state_is_exact() const override { return true; }

 protected:
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    const View& v = view(in);
    if (!v.in_reach) {
      gamma = Gamma::kNoRef;
      return;
    }
    double worst = 0.0;
    // Hands and body distance, not the heading: it stays free for a subordinate such as phi4.
    reach_targets(in, v.obj.center, v.targets, false, kArmsAndForward, value(p_.damping), out, worst);
    cap_steps(out.command, 0.3, 0.6);
    report(v, worst, out, gamma);
  }

  // The state needs the task's errors, not its least-squares command.
  bool compute_state(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    const View& v = view(in);
    if (!v.in_reach) {
      out.residual = 0.0;
      gamma = Gamma::kNoRef;
      return true;
    }
    Eigen::Matrix<double, 6, 1> e = Eigen::Matrix<double, 6, 1>::Zero();
    bool body_row = true;
    report(v, reach_errors(in, v.obj.center, v.targets, e, body_row), out, gamma);
    return true;
  }

 private:
  // What this tick's senses give both paths: the object, if within reach, its standoff targets
  // and phi (|sum n|^2 by kinematics). Computed once per tick: a composite may ask for the state
  // and then for the command.
  struct View {
    bool in_reach = false;
    VisualObject obj;
    Targets targets{};
    double phi = 0.0;
  };
  const View& view(const ControlInput& in) {
    if (view_tick_ == in.tick) return view_;
    view_tick_ = in.tick;
    View& v = view_;
    const SenseReadings& s = *in.senses;
    v.obj = VisualObject{};
    v.in_reach = object_estimate(in, value(p_.memory), v.obj, true) &&
                 !((v.obj.center - Vec2(s.base.x, s.base.y)).norm() > value(in, p_.reach));
    if (!v.in_reach) return v;
    const double r = std::clamp(v.obj.radius, 0.05, 0.5);
    const double standoff = value(p_.standoff);
    v.targets = grasp_targets(in, v.obj.center, r + in.robot().base_radius + standoff,
                              r + in.robot().hand_radius + standoff, value(p_.spread),
                              value(p_.swing));
    v.targets.body_keep_out = body_clear_;
    const ContactGeometry g = kinematic_contacts(in, v.obj.center);
    v.phi = grasp_residual(g.normal, g.point, v.obj.center, r, 0.0, 0.0).phi;
    return v;
  }

  // Sets phi, the residual (the worst task error) and gamma.
  void report(const View& v, double worst, ControlOutput& out, Gamma& gamma) const {
    out.phi = v.phi;
    out.residual = worst;
    gamma = worst <= epsilon() && out.phi <= value(p_.phi_max) ? Gamma::kConv : Gamma::kNotConv;
  }

  void on_params_changed() override { body_clear_ = choice(p_.body) == "clear"; }

  bool body_clear_ = false;  // body = 'clear', read each tick (kept here, not compared as text)
  uint64_t view_tick_ = UINT64_MAX;
  View view_;
};

// phi3: contact configuration. Closes body and hands on the object (squeezing slightly inside its
// surface) at +-spread around it, and reports phi = the grasp residual of the touch contacts:
// |sum of unit contact normals|^2 plus the moment residual, less what `friction` lets each contact
// carry along the surface (grasp_residual). CONV needs all three contacts on one object and phi
// at most epsilon for `hold` seconds. Without friction a pentagon's best three faces leave 0.38,
// above any useful epsilon although the grasp holds; with the default 0.25 they leave 0.10.
class Grasp final : public Primitive {
  // Where the constructor declared each parameter: reading one is an index, not a name search.
  struct {
    ParamSlot squeeze = 0, body_squeeze = 0, creep = 0, slide = 0, light = 0,
        spread = 0, swing = 0, moment = 0, friction = 0, memory = 0, damping = 0, back_off = 0;
    BodySlot reach;
  } p_;
 public:
  Grasp() : Primitive("phi3", 0.2) {
    p_.squeeze = declare("squeeze", 0.03, 0.0, 0.2, "how far (m) inside the surface the hands aim");
    p_.body_squeeze = declare("body_squeeze", 0.02, 0.0, 0.2, "how far (m) inside the surface the body aims");
    p_.creep = declare("creep", 0.04, 0.0, 0.3, "step (m) per command of a body or hand closing until it touches");
    p_.slide = declare("slide", 0.5, 0.0, 5.0, "rate at which touching hands slide around to balance the normals");
    p_.light = declare("light", 0.0, 0.0, 0.2, "press depth (m) of a hand while it slides");
    p_.spread = declare("spread", 2.0944, 1.0, 3.0, "angle (rad) of each hand from the body around the object");
    p_.swing = declare("swing", 0.05, 0.0, 1.0, "how far (m) a hand swings out while going round the object");
    p_.moment = declare("moment", 0.25, 0.0, 10.0, "weight of the moment residual in phi");
    p_.friction = declare("friction", 0.25, 0.0, 2.0, "share of each contact's push that friction may carry in phi");
    // Just beyond phi1's approach ring (0.58 m), not the 1.25 m it was (more than the arms span):
    // phi3 drives the base straight at the object, so from farther it ran into the obstacles phi1
    // routes round, and learned policies took that shortcut in the paper's open worlds and failed
    // with it in cluttered ones (Table III 91.6% -> 94.6%; 0.8 and 0.7 gave less, docs/results.md).
    p_.reach = declare_body("reach", &BodyMetrics::grasp_reach, 0.3, 3.0, "objects farther (m) than this from the base are out of reach");
    p_.memory = declare("memory", 2.0, 0.0, 60.0, "seconds a lost object's last position stays usable");
    p_.damping = declare("damping", 0.05, 0.0, 1.0, "least-squares damping near singular postures");
    p_.back_off = declare("back_off", 0.03, 0.0, 0.3, "step (m) out along its touch normal of a hand that touches the object while the body does not");
    // A grasp counts once it has held for a few ticks: a hand that closes with a bounce touches
    // for a tick and is off again.
    set_number("hold", 0.1);
  }
  PrimitivePtr clone() const override { return std::make_shared<Grasp>(*this); }
  // Nothing is carried from tick to tick.
  bool state_is_exact() const override { return true; }

 protected:
  // The state needs phi, from the contacts or kinematics, not the guarded moves.
  bool compute_state(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    VisualObject obj;
    if (!object_in_reach(in, obj)) {
      out.residual = 0.0;
      gamma = Gamma::kNoRef;
      return true;
    }
    const double r = std::clamp(obj.radius, 0.05, 0.5);
    GraspResidual grasp;  // what close_hands computes when all three contacts are on the object
    if (contacts_on_object(in) == kTactileCount) grasp = touch_residual(in, obj.center, r);
    report_phi(in, obj.center, r, grasp, out, gamma);
    return true;
  }

  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    const SenseReadings& s = *in.senses;
    const Percepts& p = *in.percepts;
    VisualObject obj;
    if (!object_in_reach(in, obj)) {
      gamma = Gamma::kNoRef;
      return;
    }
    const double r = std::clamp(obj.radius, 0.05, 0.5);
    // Guarded moves: vision's size estimate bounds the object, but a polygon's face may lie well
    // inside it, so the body creeps forward until it feels the object, and only then do the hands
    // close in, each creeping until it touches and then pressing `squeeze` into the surface.
    // Squeezing before the body touches would pin the object and keep the body from reaching it.
    // (A grasp that holds while the body is off is phi5's to keep, not phi3's.)
    const bool body_on = p.contact_on_object[kBody];
    const Vec2 base(s.base.x, s.base.y);
    const double creep = value(p_.creep);
    GraspResidual grasp;  // with all three contacts on the object, computed once per tick
    const double body_distance = body_on ? r + in.robot().base_radius - value(p_.body_squeeze)
                                         : (obj.center - base).norm() - creep;
    // While the body does not touch the object, a hand that touches it must not grip it: a
    // polygon's corners reach beyond vision's radius, and hands that gripped first carried the
    // object ahead of the creeping body (the base drives them forward with it), pushing it across
    // the floor until a wall stopped it. The same when the body loses the object while the hands
    // close: a triangle turned off the body is let go and closed on again, not carried off.
    Targets t = grasp_targets(in, obj.center, std::min(body_distance, r + in.robot().base_radius),
                              r + in.robot().hand_radius + 0.01, value(p_.spread), value(p_.swing));
    t.body_press = value(p_.body_squeeze);
    if (body_on) close_hands(in, obj, r, creep, t, grasp);
    else back_off_hands(in, t);
    double worst = 0.0;
    // Once the body and a hand touch, the arms alone place the hands: moving the base for them
    // would shove the object with the body or turn it off the object. The base only keeps the
    // body pressed on (its own row: the distance to the object along the heading).
    const bool hand_on = p.contact_on_object[kLeftHand] || p.contact_on_object[kRightHand];
    reach_targets(in, obj.center, t, true, !body_on ? kArmsAndBase : hand_on ? kArmsOnly : kArmsAndForward,
                  value(p_.damping), out, worst);
    if (body_on && hand_on) keep_body_pressed(s, obj.center, base, t, out);
    cap_steps(out.command, 0.15, 0.5);
    report_phi(in, obj.center, r, grasp, out, gamma);
  }

 private:
  // The object as the senses have it, if it is within reach.
  bool object_in_reach(const ControlInput& in, VisualObject& obj) const {
    const SenseReadings& s = *in.senses;
    return object_estimate(in, value(p_.memory), obj) &&
           !((obj.center - Vec2(s.base.x, s.base.y)).norm() > value(in, p_.reach));
  }

  // How many of the three contacts touch the object touched most.
  static int contacts_on_object(const ControlInput& in) {
    const SenseReadings& s = *in.senses;
    const Percepts& p = *in.percepts;
    int on = 0;
    for (int k = 0; k < kTactileCount; ++k)
      on += p.contact_on_object[k] && s.touch[k].index == p.touched_object;
    return on;
  }

  // The grasp residual (friction included) of the three touch contacts.
  GraspResidual touch_residual(const ControlInput& in, const Vec2& center, double r) const {
    const SenseReadings& s = *in.senses;
    Vec2 normal[kTactileCount], point[kTactileCount];
    for (int k = 0; k < kTactileCount; ++k) normal[k] = s.touch[k].normal, point[k] = s.touch[k].point;
    return grasp_residual(normal, point, center, r, value(p_.moment), value(p_.friction));
  }

  // While the body is off the object: a hand that touches it keeps only the part of its move
  // along the surface and steps `back_off` out along its touch normal, so it neither grips the
  // object (which would stay ahead of the creeping body) nor stalls on it while it swings round.
  void back_off_hands(const ControlInput& in, Targets& t) const {
    const SenseReadings& s = *in.senses;
    const Percepts& p = *in.percepts;
    for (int side = 0; side < 2; ++side) {
      const Touch& touch = s.touch[kLeftHand + side];
      if (!p.contact_on_object[kLeftHand + side] || touch.index != p.touched_object) continue;
      const Vec2 hand = in.percepts->arms[side].hand;
      Vec2 along = t.hand[side] - hand;
      along -= along.dot(touch.normal) * touch.normal;
      t.hand[side] = hand + along + value(p_.back_off) * touch.normal;
    }
  }

  // With the body on the object: each touching hand slides along the surface to balance the
  // grasp and presses in, each other hand creeps in along its line to the object. Fills `grasp`
  // when all three contacts are on the object.
  void close_hands(const ControlInput& in, const VisualObject& obj, double r, double creep,
                   Targets& t, GraspResidual& grasp) const {
    const SenseReadings& s = *in.senses;
    const Percepts& p = *in.percepts;
    // What the contacts leave unbalanced: with all three on the object, the grasp residual
    // (friction included); before that, the sum of the unit normals measured by touch (each
    // from the surface towards its sensor).
    Vec2 sum = Vec2::Zero();
    int touching_count = 0;
    for (int k = 0; k < kTactileCount; ++k)
      if (p.contact_on_object[k] && s.touch[k].index == p.touched_object)
        sum += s.touch[k].normal, ++touching_count;
    double unbalanced = sum.squaredNorm();
    if (touching_count == kTactileCount) {
      grasp = touch_residual(in, obj.center, r);
      sum = grasp.force;
      unbalanced = grasp.phi;
    }
    // Press lightly while the grasp is unbalanced, so the hands can slide, and firmly once it
    // balances.
    const double press = unbalanced > epsilon() ? value(p_.light) : value(p_.squeeze);
    for (int side = 0; side < 2; ++side) {
      const Vec2 hand = in.percepts->arms[side].hand;
      const double now = (hand - obj.center).norm();
      const bool touching = p.contact_on_object[kLeftHand + side];
      if (touching) {
        // Slide the contact along the surface down the gradient of the residual |S|^2 (S the
        // unbalanced force): moving a contact by d(angle) around the object turns its normal by
        // about d(angle), so d|S|^2/d(angle) is about 2 S . perp(n). The step follows the touched surface (its tangent,
        // pressing along its normal), not a circle about the centre, which would cut into a
        // polygon's corner and drag the object round instead of sliding over it.
        const Vec2 n = s.touch[kLeftHand + side].normal;
        const Vec2 tangent(-n.y(), n.x());
        const double slide = std::clamp(-value(p_.slide) * sum.dot(tangent), -0.3, 0.3);
        t.hand[side] = hand + slide * now * tangent - press * n;
      } else {
        const Vec2 out_dir = (t.hand[side] - obj.center).normalized();
        t.hand[side] = obj.center + (now - creep) * out_dir;
      }
    }
  }

  // The base command that keeps the body pressed on the object while the arms place the hands:
  // the distance to the object along the heading, towards t.body_distance, but never away from
  // it. The body touches, so the surface is where it is; vision's radius puts a polygon's face
  // further out than that, and backing off to it with both hands gripping dragged the object
  // across the floor for as long as phi3 ran (tests/test_primitives.cpp).
  static void keep_body_pressed(const SenseReadings& s, const Vec2& center, const Vec2& base,
                                const Targets& t, ControlOutput& out) {
    const Vec2 to_obj = center - base;
    const double d = to_obj.norm();
    const double along = unit(s.base.theta).dot(to_obj) / std::max(d, 1e-6);  // -d(d)/d(forward)
    const double e = std::clamp(t.body_distance - d, -t.body_press, 0.0);
    if (along > 0.3) out.command[kBaseForward] = -e / along;
  }

  // Sets phi, the residual and gamma (`grasp`: the residual close_hands found, if it found one).
  void report_phi(const ControlInput& in, const Vec2& center, double r, const GraspResidual& grasp,
                  ControlOutput& out, Gamma& gamma) const {
    // phi from touch when all three contacts are on one object, else from kinematics plus a
    // penalty per missing contact (so phi falls as contacts are made).
    const int on = contacts_on_object(in);
    if (on == kTactileCount) {
      out.phi = grasp.phi;  // all three on means the body touches: close_hands computed it
    } else {
      const ContactGeometry g = kinematic_contacts(in, center);
      out.phi = grasp_residual(g.normal, g.point, center, r, 0.0, 0.0).phi + (kTactileCount - on);
    }
    out.residual = out.phi;
    gamma = on == kTactileCount && out.phi <= epsilon() ? Gamma::kConv : Gamma::kNotConv;
  }

};

// phi5: dynamic contact adjustment. With all three contacts on the object, each hand presses
// `squeeze` into the surface along its touch normal, and leads by `lead` seconds of the base's
// acceleration so the grasp carries the object's inertia; its task is the hands' position in the
// base frame (the arm joints). Each hand's press fades as its contact force nears `press`, so the
// grasp regulates force rather than position. NOREF as soon as a hand's contact is lost, or the
// body's for longer than `grace`.
class Hold final : public Primitive {
  // Where the constructor declared each parameter: reading one is an index, not a name search.
  struct { ParamSlot squeeze = 0, pull = 0, press = 0, lead = 0, moment = 0, friction = 0, damping = 0, grace = 0; } p_;
 public:
  Hold() : Primitive("phi5", 0.3) {
    p_.squeeze = declare("squeeze", 0.03, 0.0, 0.2, "press depth (m) of each hand along its contact normal");
    p_.pull = declare("pull", 0.03, 0.0, 0.2, "how far (m) the hands draw the object onto the body");
    p_.press = declare("press", 50.0, 0.0, 1000.0,
                       "contact force (N) each hand presses towards: its squeeze, and its pull while the "
                       "body touches the object, fade as its force nears this (0: never)");
    p_.lead = declare("lead", 0.04, 0.0, 1.0, "hand lead per unit of base acceleration (m per m/s^2)");
    p_.moment = declare("moment", 0.25, 0.0, 10.0, "weight of the moment residual in phi");
    p_.friction = declare("friction", 0.5, 0.0, 2.0, "share of each contact's push that friction may carry in phi");
    p_.damping = declare("damping", 0.05, 0.0, 1.0, "least-squares damping near singular postures");
    p_.grace = declare("grace", 0.1, 0.0, 10.0, "seconds the body may lose the object, both hands holding, before the grasp counts as lost");
  }
  PrimitivePtr clone() const override { return std::make_shared<Hold>(*this); }
  void reset(uint64_t seed) override {
    Primitive::reset(seed);
    has_velocity_ = false;
    body_off_time_ = 0.0;
    memory_tick_ = phi_tick_ = UINT64_MAX;
  }
  // What it carries from tick to tick (the last velocity, the body's time off the object) is
  // updated by the state path as by compute().
  bool state_is_exact() const override { return true; }

 protected:
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    own_dofs({kLeftShoulder, kLeftElbow, kRightShoulder, kRightElbow}, out.jacobian);
    bool on[kTactileCount];
    const Vec2 accel = remember(in, on);
    // NOREF as soon as a contact is lost; but while both hands still hold the object the hands
    // keep pressing and draw it back onto the body, so a grasp that slipped can recover.
    if (!on[kLeftHand] || !on[kRightHand]) {
      gamma = Gamma::kNoRef;
      return;
    }
    press_hands(in, on, accel, out);
    report(in, on, out, gamma);
  }

  // The state needs phi, not the hands' command.
  bool compute_state(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    bool on[kTactileCount];
    remember(in, on);
    out.residual = 0.0;
    if (!on[kLeftHand] || !on[kRightHand]) gamma = Gamma::kNoRef;
    else report(in, on, out, gamma);
    return true;
  }

 private:
  // Which contacts are on the object (`on`), and the base's acceleration; updates what is carried
  // from tick to tick once per tick, however many of the state path and compute() run in it.
  Vec2 remember(const ControlInput& in, bool on[kTactileCount]) {
    const SenseReadings& s = *in.senses;
    const Percepts& p = *in.percepts;
    for (int k = 0; k < kTactileCount; ++k)
      on[k] = p.contact_on_object[k] && s.touch[k].index == p.touched_object;
    if (memory_tick_ == in.tick) return accel_;
    memory_tick_ = in.tick;
    accel_ = base_acceleration(s, in.dt());
    // A body contact that breaks for a moment while both hands hold (a light body contact, a
    // non-convex object rocking on it) is not a lost grasp: the pull is drawing the object back,
    // so for `grace` seconds the grasp counts as held, unconverged.
    if (on[kLeftHand] && on[kRightHand]) body_off_time_ = on[kBody] ? 0.0 : body_off_time_ + in.dt();
    return accel_;
  }

  // Sets phi (the contacts' grasp residual), the residual and gamma, with both hands on.
  void report(const ControlInput& in, const bool on[kTactileCount], ControlOutput& out,
              Gamma& gamma) {
    // Once per tick: a composite may ask for the state and then for the command.
    if (phi_tick_ != in.tick) phi_tick_ = in.tick, phi_ = contact_phi(in);
    out.phi = phi_;
    out.residual = out.phi;
    if (!on[kBody]) {
      gamma = body_off_time_ <= value(p_.grace) ? Gamma::kNotConv : Gamma::kNoRef;
      return;
    }
    gamma = out.phi <= epsilon() ? Gamma::kConv : Gamma::kNotConv;
  }

  // The base's acceleration from its velocity senses (world frame), since the last tick; zero on
  // the first.
  Vec2 base_acceleration(const SenseReadings& s, double dt) {
    const Vec2 v = s.qdot[kBaseForward] * unit(s.base.theta);
    const Vec2 accel = has_velocity_ ? Vec2((v - last_velocity_) / dt) : Vec2::Zero();
    last_velocity_ = v;
    has_velocity_ = true;
    return accel;
  }

  // The arms' command: each hand presses into the surface, draws the object onto the body and
  // leads with the base's acceleration (`on`: which contacts are on the object).
  void press_hands(const ControlInput& in, const bool on[kTactileCount], const Vec2& accel,
                   ControlOutput& out) const {
    const SenseReadings& s = *in.senses;
    Eigen::Matrix<double, 4, kDofCount> J;
    Eigen::Matrix<double, 4, 1> e;
    Eigen::Matrix<double, 2, kDofCount> Jh;
    // From the object towards the body: the body's touch normal, or, with the body off the
    // object, the direction from the hands' midpoint to the base.
    const Vec2 base(s.base.x, s.base.y);
    const Vec2 mid = 0.5 * (in.percepts->arms[kLeft].hand + in.percepts->arms[kRight].hand);
    const Vec2 to_body = on[kBody] ? s.touch[kBody].normal : Vec2((base - mid).normalized());
    const double pull = on[kBody] ? value(p_.pull) : 2.0 * value(p_.pull);
    for (int side = 0; side < 2; ++side) {
      hand_jacobian(in, side, Jh);
      J.middleRows<2>(2 * side) = Jh;
      const Touch& touch = s.touch[kLeftHand + side];
      // Press into the surface, draw the object onto the body (so its contact is kept while the
      // base pulls and turns), and lead with the base's acceleration where that pushes inward.
      // The press and the pull fade as the hand's contact force nears `press`. The arms are rate
      // servos with torque limits: a step that never fades drives both hands to their limits,
      // which differ with the arms' postures, and in every turn the difference walks the object
      // round the body until a shoulder reaches its stop. Fading, a hand the object pushes into
      // stands and resists (up to its limit), and a hand the object leaves presses after it.
      // With the body off the object the pull does not fade: what the hands feel then is their
      // own squeeze, not the object resting on the body, and only the pull brings it back.
      const double press = value(p_.press);
      const double fade = press > 0.0 ? std::clamp(1.0 - touch.force / press, 0.0, 1.0) : 1.0;
      Vec2 err = -fade * value(p_.squeeze) * touch.normal + (on[kBody] ? fade : 1.0) * pull * to_body;
      const double inward = -accel.dot(touch.normal);
      if (inward > 0) err += -value(p_.lead) * inward * touch.normal;
      e.segment<2>(2 * side) = err;
    }
    static const DofVector arms = mask({kLeftShoulder, kLeftElbow, kRightShoulder, kRightElbow});
    out.command = damped_solve<4>(J, e, arms, value(p_.damping));
    cap_steps(out.command, 0.1, 0.3);
  }

  // The grasp residual of the three touch contacts, about the object's estimated centre (or the
  // contacts' centroid when there is no estimate).
  double contact_phi(const ControlInput& in) const {
    const SenseReadings& s = *in.senses;
    Vec2 normal[kTactileCount], point[kTactileCount];
    for (int k = 0; k < kTactileCount; ++k) normal[k] = s.touch[k].normal, point[k] = s.touch[k].point;
    VisualObject obj;
    const Vec2 center = object_estimate(in, 1e9, obj)
                            ? obj.center
                            : Vec2((point[0] + point[1] + point[2]) / 3.0);
    return grasp_residual(normal, point, center, std::max(obj.radius, 0.1), value(p_.moment),
                          value(p_.friction)).phi;
  }

  Vec2 last_velocity_ = Vec2::Zero();
  bool has_velocity_ = false;
  double body_off_time_ = 0.0;  // seconds since the body last touched the object
  uint64_t memory_tick_ = UINT64_MAX;  // the tick remember() last updated the memory on
  Vec2 accel_ = Vec2::Zero();          // the base's acceleration found on that tick
  uint64_t phi_tick_ = UINT64_MAX;     // the tick phi_ was found on
  double phi_ = 0.0;                   // the contacts' grasp residual then
};

}  // namespace

PrimitivePtr make_preshape() { return std::make_shared<Preshape>(); }
PrimitivePtr make_grasp() { return std::make_shared<Grasp>(); }
PrimitivePtr make_hold() { return std::make_shared<Hold>(); }

}  // namespace primitives_internal
}  // namespace roger
