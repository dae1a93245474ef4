// primitives_simple.cpp: the primitives that own a few DOFs outright and need no shared geometry:
// phi0 (track), search, and phi4 (kinematic conditioning).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "control/primitives_internal.h"
#include "core/shape.h"
#include "core/rng.h"

namespace roger {
namespace primitives_internal {
namespace {

// phi0: centre the stimulus in both eyes (eye pans) and turn the base towards it (heading).
// CONV once the stimulus is centred in both eyes with the base facing it (within epsilon), and
// then for as long as both eyes see it; NOREF as soon as one loses it, after which it must be
// reached again. Tracking, once reached, is not lost by a base that turns away to follow a path
// round an obstacle with the eyes still on the stimulus: asking for the heading on every tick
// made phi0 !CONV on each such detour, and a learned search-grasp policy then turned back to the
// stimulus (Phi6) and forward along the path (Phi7) in turn until the time-out, the most common
// of Table III's failures (scripts/failure_modes.py, "detour").
class Track final : public Primitive {
 public:
  Track() : Primitive("phi0", 0.1) {}
  PrimitivePtr clone() const override { return std::make_shared<Track>(*this); }
  void reset(uint64_t seed) override {
    Primitive::reset(seed);
    tracking_ = false;
  }

 protected:
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    own_dofs({kLeftEye, kRightEye, kBaseHeading}, out.jacobian);
    const SenseReadings& s = *in.senses;
    if (!s.stimulus[kLeft].seen || !s.stimulus[kRight].seen) {
      gamma = Gamma::kNoRef;
      tracking_ = false;
      return;
    }
    const double el = s.stimulus[kLeft].bearing, er = s.stimulus[kRight].bearing;
    // The gaze direction relative to the base: the mean of both eyes' lines of sight.
    const double eb = wrap_angle(0.5 * (s.q[kLeftEye] + el + s.q[kRightEye] + er));
    out.command[kLeftEye] = el;
    out.command[kRightEye] = er;
    out.command[kBaseHeading] = eb;
    out.phi = 0.5 * (el * el + er * er + eb * eb);
    out.residual = std::max({std::abs(el), std::abs(er), std::abs(eb)});
    tracking_ = tracking_ || out.residual <= epsilon();
    gamma = tracking_ ? Gamma::kConv : Gamma::kNotConv;
  }

 private:
  bool tracking_ = false;  // reached; kept while both eyes see the stimulus
};

// search: turn by randomly sampled steps, always the same way round (drawn per episode), eyes spread
// to widen the view, until both eyes see the stimulus; as soon as one eye glimpses it, turn that
// way. Once the eyes' fields of view have together swept every direction around Roger since the
// search began (or last glimpsed its stimulus) without a glimpse, there is nothing of its stimulus
// to be seen from here: NOREF, so that whoever runs it moves on ("nothing left to do" is a state,
// not a time-out). It goes on turning while it is run, and finds a stimulus that comes into view. When one eye has had it straight
// ahead for `one_eye` seconds and the other still has not, something stands in the other eye's line
// of sight (another object, an obstacle): turning cannot fix that, so the base steps sideways
// towards the seeing eye's side (turn a quarter, drive `sidestep` metres, turn back), moving the
// blind eye's line of sight off the occluder.
class Search final : public Primitive {
  // Where the constructor declared each parameter: reading one is an index, not a name search.
  struct {
    ParamSlot spread = 0, reached = 0, min_turn = 0, max_turn = 0, one_eye = 0, stuck = 0;
    BodySlot sidestep;
  } p_;
  enum class Step { kNone, kTurnOut, kDrive, kBackAway };

 public:
  Search() : Primitive("search", 0.0) {
    p_.spread = declare("spread", 0.6, 0.0, 1.5, "eye pan (rad) each side while looking around");
    p_.reached = declare("reached", 0.3, 0.01, 3.0, "heading error (rad) at which a new heading is sampled");
    p_.min_turn = declare("min_turn", 1.2, 0.0, 6.3, "smallest sampled turn (rad)");
    p_.max_turn = declare("max_turn", 3.2, 0.0, 6.3, "largest sampled turn (rad)");
    p_.one_eye = declare("one_eye", 1.0, 0.0, 1000.0,
                       "seconds one eye alone has the stimulus ahead before stepping sideways (0: never)");
    p_.sidestep = declare_body("sidestep", &BodyMetrics::sidestep, 0.0, 2.0, "sideways step (m) that clears the blind eye's view");
    p_.stuck = declare("stuck", 1.0, 0.0, 60.0,
                       "seconds the base may fail to turn before the search turns the other way (0: never)");
  }
  PrimitivePtr clone() const override { return std::make_shared<Search>(*this); }
  void reset(uint64_t seed) override {
    Primitive::reset(seed);
    rng_.reseed(Rng::mix(seed, 0x5ea4c4));
    has_target_ = false;
    one_eye_time_ = 0.0;
    one_eye_seen_at_ = -1e9;
    steps_taken_ = 0;
    step_ = Step::kNone;
    last_tick_ = UINT64_MAX;
    direction_ = rng_.uniform() < 0.5 ? -1.0 : 1.0;
    swept_.fill(false);
    swept_count_ = 0;
    stuck_time_ = 0.0;
  }

  // Whether the eyes have swept every direction since the search began or last glimpsed its
  // stimulus (it is NOREF then).
  bool looked_everywhere() const { return swept_count_ == kSweepBins; }

 protected:
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    const SenseReadings& s = *in.senses;
    const double heading = s.q[kBaseHeading];
    const bool turned = watch_turning(heading, in);
    count_turn(heading, in.tick);
    const bool left = s.stimulus[kLeft].seen, right = s.stimulus[kRight].seen;
    if (left || right) {
      swept_.fill(false);  // a glimpse: whatever was swept before does not say "nothing here"
      swept_count_ = 0;
    } else {
      sweep(in);
    }
    // A sideways step under way is finished first: turning out swings the blind eye's line of
    // sight across the stimulus for a moment, and a glimpse is not a view.
    if (left && right && step_ == Step::kNone) {
      gamma = Gamma::kConv;  // found: both eyes have it
      own_dofs({kBaseHeading, kLeftEye, kRightEye}, out.jacobian);
      has_target_ = false;
      step_ = Step::kNone;
      return;
    }
    gamma = looked_everywhere() ? Gamma::kNoRef : Gamma::kNotConv;
    if (step_ == Step::kNone && (left != right)) watch_one_eye(in, left ? kLeft : kRight);
    if (step_ != Step::kNone) {
      own_dofs({kBaseForward, kBaseHeading, kLeftEye, kRightEye}, out.jacobian);
      step_aside(s, in.dt(), out);
      return;
    }
    own_dofs({kBaseHeading, kLeftEye, kRightEye}, out.jacobian);
    if (left || right) {
      // One eye sees it: turn towards it, bring both eyes to bear.
      const int e = left ? kLeft : kRight;
      const double rel = wrap_angle(s.q[kLeftEye + e] + s.stimulus[e].bearing);
      aim(heading, rel);
      out.command[kLeftEye] = rel - s.q[kLeftEye];
      out.command[kRightEye] = rel - s.q[kRightEye];
    } else {
      if (!turned) turn_back(s);  // the way it was turning is blocked
      if (!turned || !has_target_ || std::abs(turn_left_) < value(p_.reached)) {
        const double turn = rng_.uniform(value(p_.min_turn), value(p_.max_turn));
        aim(heading, direction_ * turn);
      }
      out.command[kLeftEye] = value(p_.spread) - s.q[kLeftEye];
      out.command[kRightEye] = -value(p_.spread) - s.q[kRightEye];
    }
    out.command[kBaseHeading] = clamp_abs(turn_left_, 1.0);
    out.residual = std::abs(turn_left_);
  }

 private:
  // Marks the directions (world bearings, in kSweepBins bins) that lie wholly inside either eye's
  // field of view this tick.
  void sweep(const ControlInput& in) {
    const SenseReadings& s = *in.senses;
    constexpr double kBin = 2.0 * M_PI / kSweepBins;
    for (int e = 0; e < 2; ++e) {
      const double axis = s.base.theta + s.q[kLeftEye + e];
      const double half_view = in.body().half_view;
      const double from = axis - half_view, to = axis + half_view;
      const int first = int(std::ceil((from + M_PI) / kBin)), last = int(std::floor((to + M_PI) / kBin)) - 1;
      for (int b = first; b <= last; ++b) {
        const int k = ((b % kSweepBins) + kSweepBins) % kSweepBins;
        if (!swept_[size_t(k)]) swept_[size_t(k)] = true, ++swept_count_;
      }
    }
  }

  // Sets a turn of `turn` radians from `heading` (either sign, and more than half a revolution
  // if sampled so).
  void aim(double heading, double turn) {
    turn_left_ = turn;
    target_ = wrap_angle(heading + turn);
    has_target_ = true;
  }

  // Keeps the turn still to make up to date with the heading, whatever its winding: the heading's
  // change since the last tick, wrapped, is what was turned. After a gap (another controller had
  // the base) the turn is what separates the heading from the target, the shorter way.
  void count_turn(double heading, uint64_t tick) {
    if (has_target_) {
      if (tick == last_tick_ + 1) turn_left_ -= wrap_angle(heading - last_heading_);
      else if (tick != last_tick_) turn_left_ = wrap_angle(target_ - heading);
    }
    last_heading_ = heading;
    last_tick_ = tick;
  }

  // Whether the base still turns as the search asks: false once it has turned less than
  // kStuckRate for `stuck` seconds in a row, each tick's turn the answer to the search's own
  // command of the tick before (a body or an arm pressed against an obstacle, and the turn
  // pressing them on: Roger stayed there until the time-out, every move's search and tracking
  // waiting for a turn that never came). Evaluations made only to read its state do not count:
  // another controller has the base then.
  bool watch_turning(double heading, const ControlInput& in) {
    const bool running =
        has_target_ && step_ == Step::kNone && in.tick == last_tick_ + 1 && acted_last_tick(in);
    if (!running || std::abs(wrap_angle(heading - last_heading_)) >= kStuckRate * in.dt()) {
      stuck_time_ = 0.0;
      return true;
    }
    stuck_time_ += in.dt();
    if (value(p_.stuck) <= 0.0 || stuck_time_ < value(p_.stuck)) return true;
    stuck_time_ = 0.0;
    return false;
  }

  // A blocked turn: the search turns the other way from now on, and if the body touches what
  // blocks it, first drives kBackAwayLength away from it (forward or back, whichever the touch
  // normal favours), so the body is not turning pressed against it.
  void turn_back(const SenseReadings& s) {
    direction_ = -direction_;
    const Touch& body = s.touch[kBody];
    if (!body.contact) return;
    back_away_sign_ = body.normal.dot(unit(s.base.theta)) >= 0.0 ? 1.0 : -1.0;
    step_ = Step::kBackAway;
    step_time_ = 0.0;
    odometer_ = s.q[kBaseForward];
  }

  // Times how long eye `e` alone has had the stimulus straight ahead; past `one_eye`, starts a
  // sideways step towards that eye's side. A glimpse by both eyes that did not last (tracking took
  // over and lost it at once, the occluder's edge swinging across the blind eye's view) does not
  // restart the count: otherwise search and tracking hand the stimulus to each other for ever
  // and the step never comes.
  void watch_one_eye(const ControlInput& in, int e) {
    const SenseReadings& s = *in.senses;
    const double time = in.time, dt = in.dt();
    const double rel = wrap_angle(s.q[kLeftEye + e] + s.stimulus[e].bearing);
    if (std::abs(rel) >= value(p_.reached)) {
      one_eye_time_ = 0.0;
      return;
    }
    if (time - one_eye_seen_at_ > kGlimpse) one_eye_time_ = 0.0;
    one_eye_time_ += dt;
    one_eye_seen_at_ = time;
    if (value(p_.one_eye) <= 0.0 || one_eye_time_ < value(p_.one_eye)) return;
    bearing_ = wrap_angle(s.q[kBaseHeading] + rel);
    // The left eye sits on the base's left (positive angles turn left).
    step_heading_ = wrap_angle(bearing_ + (e == kLeft ? 0.5 : -0.5) * M_PI);
    step_ = Step::kTurnOut;
    step_time_ = 0.0;
    one_eye_time_ = 0.0;
    // Each further step in a row goes further: an occluder wider than one step needs more.
    step_length_ = value(in, p_.sidestep) * std::min(1.0 + steps_taken_, 3.0);
    ++steps_taken_;
  }

  // One tick of the sideways step: turn to face across the line of sight, drive, then hand back
  // to the search aimed at the remembered bearing. Each phase is bounded in time, so a wall or
  // an obstacle in the way ends the step instead of the episode.
  void step_aside(const SenseReadings& s, double dt, ControlOutput& out) {
    const double heading = s.q[kBaseHeading];
    step_time_ += dt;
    if (step_ == Step::kBackAway) {
      const double remaining = kBackAwayLength - std::abs(s.q[kBaseForward] - odometer_);
      out.command[kBaseForward] = back_away_sign_ * std::clamp(remaining, 0.0, 0.1);
      out.command[kLeftEye] = value(p_.spread) - s.q[kLeftEye];
      out.command[kRightEye] = -value(p_.spread) - s.q[kRightEye];
      out.residual = std::max(remaining, 0.0);
      if (remaining <= 0.01 || step_time_ > 1.5) step_ = Step::kNone, has_target_ = false;
      return;
    }
    // The eyes keep looking along the remembered bearing, as far as they pan.
    const double rel = wrap_angle(bearing_ - heading);
    out.command[kLeftEye] = rel - s.q[kLeftEye];
    out.command[kRightEye] = rel - s.q[kRightEye];
    const double turn_out = wrap_angle(step_heading_ - heading);
    if (step_ == Step::kTurnOut) {
      out.command[kBaseHeading] = clamp_abs(turn_out, 1.0);
      out.residual = std::abs(turn_out);
      if (out.residual < 0.1 || step_time_ > 3.0) step_ = Step::kDrive, step_time_ = 0.0, odometer_ = s.q[kBaseForward];
      return;
    }
    const double remaining = step_length_ - std::abs(s.q[kBaseForward] - odometer_);
    out.command[kBaseForward] = std::clamp(remaining, 0.0, 0.1);
    out.command[kBaseHeading] = clamp_abs(turn_out, 1.0);
    out.residual = std::max(remaining, 0.0);
    if (remaining <= 0.01 || step_time_ > 3.0) {
      step_ = Step::kNone;
      aim(heading, rel);  // turn back to where the stimulus was
    }
  }

  static constexpr int kSweepBins = 72;                  // 5 degrees each
  Rng rng_{0};
  double direction_ = 1.0;                              // +1 turns left, -1 right
  std::array<bool, kSweepBins> swept_{};                // directions swept without a glimpse
  int swept_count_ = 0;
  double target_ = 0.0;        // the heading the current turn ends at (wrapped)
  double turn_left_ = 0.0;     // what is still to turn (rad, signed; may exceed pi)
  bool has_target_ = false;
  double last_heading_ = 0.0;  // the heading at the last tick this search ran
  uint64_t last_tick_ = UINT64_MAX;
  static constexpr double kGlimpse = 0.5;  // s: a two-eye sighting shorter than this is a glimpse
  static constexpr double kStuckRate = 0.05;  // rad/s: turning slower than this is not turning
  double stuck_time_ = 0.0;    // seconds in a row the base has not turned while asked to
  static constexpr double kBackAwayLength = 0.2;  // m the base drives away from what blocks a turn
  double back_away_sign_ = 1.0;  // +1 forward, -1 back
  double one_eye_time_ = 0.0;  // seconds one eye alone has had the stimulus ahead
  double one_eye_seen_at_ = -1e9;  // when one eye alone last had it ahead
  int steps_taken_ = 0;        // sideways steps so far
  double step_length_ = 0.0;   // metres of the step under way
  Step step_ = Step::kNone;     // the phase of a sideways step, if one is under way
  double step_time_ = 0.0;      // seconds in the current phase
  double bearing_ = 0.0;        // world bearing (wrapped) at which the seeing eye had the stimulus
  double step_heading_ = 0.0;   // heading (wrapped) the base drives along while stepping
  double odometer_ = 0.0;       // kBaseForward when the drive began
};

// phi4: kinematic conditioning. phi = sum over arms of cos^2(elbow): zero at the most manipulable
// posture (elbows at +-90 degrees, where L1 L2 |sin(elbow)| peaks). Its command descends phi on the
// elbows; as a subordinate, the projection turns it into base and shoulder motions that keep the
// superior's contacts where they are. It is an optimization, not a constraint: as a superior it
// protects only its gradient direction (a one-row Jacobian).
class Condition final : public Primitive {
  // Where the constructor declared each parameter: reading one is an index, not a name search.
  struct { ParamSlot rate = 0; } p_;
 public:
  Condition() : Primitive("phi4", 0.05) {
    p_.rate = declare("rate", 0.15, 0.0, 5.0, "step per tick per unit gradient (rad)");
  }
  PrimitivePtr clone() const override { return std::make_shared<Condition>(*this); }
  // Nothing is carried from tick to tick (and its command is its state's own arithmetic).
  bool state_is_exact() const override { return true; }

 protected:
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    const SenseReadings& s = *in.senses;
    double grad2 = 0.0;
    out.phi = 0.0;
    for (int dof : {int(kLeftElbow), int(kRightElbow)}) {
      const double q = s.q[dof];
      out.phi += std::cos(q) * std::cos(q);
      const double g = -std::sin(2.0 * q);  // d/dq cos^2(q)
      grad2 += g * g;
      out.command[dof] = -value(p_.rate) * g;
    }
    out.jacobian.resize(grad2 > 0.0 ? 1 : 0, kDofCount);
    if (grad2 > 0.0) out.jacobian.row(0) = -out.command.transpose();
    out.residual = std::sqrt(grad2);
    gamma = out.residual <= epsilon() ? Gamma::kConv : Gamma::kNotConv;
  }
};

}  // namespace

PrimitivePtr make_track() { return std::make_shared<Track>(); }
PrimitivePtr make_search() { return std::make_shared<Search>(); }
PrimitivePtr make_condition() { return std::make_shared<Condition>(); }

}  // namespace primitives_internal
}  // namespace roger
