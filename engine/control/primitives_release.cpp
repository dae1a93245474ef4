// primitives_release.cpp: release, letting go of an object: the arms return to the start posture
// (hands beside the body, clear of anything ahead), then the base backs off, so that turning
// afterwards cannot sweep the object with a hand. A hand that touches something first steps out
// along its touch normal: folding straight back in joint space can drive a hand that has the
// object pinned against the body further into it, and then neither moves. Arms that still do not
// fold (an object wedged between them and the body) back off first, and a base that cannot back
// (a wall behind it) has backed off as far as it can: release always ends. The paper stops at
// transport; any task that moves more than one object (sorting, Figure 1) must let go of one
// before taking the next.
#include <algorithm>
#include <cmath>

#include "control/primitives_internal.h"

namespace roger {
namespace primitives_internal {
namespace {

class Release final : public Primitive {
  struct {
    ParamSlot step = 0, clear = 0, blocked = 0;
    BodySlot distance;
  } p_;
 public:
  Release() : Primitive("release", 0.05) {
    p_.distance = declare_body("distance", &BodyMetrics::release_distance, 0.0, 2.0, "how far (m) the base backs off once the arms are folded");
    p_.step = declare("step", 0.1, 0.01, 1.0, "largest backing error (m) per command");
    p_.clear = declare("clear", 0.05, 0.0, 0.3, "step (m) out along its touch normal of a hand that touches something");
    p_.blocked = declare("blocked", 1.0, 0.0, 10.0,
                         "seconds the arms may come no nearer their posture, or the base back no further, "
                         "before release goes on regardless (0: wait for ever)");
  }
  PrimitivePtr clone() const override { return std::make_shared<Release>(*this); }
  void reset(uint64_t seed) override {
    Primitive::reset(seed);
    // Not acting (Primitive::reset): compute() starts the stall watches over.
    backing_ = blocked_ = false;
  }

 protected:
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    own_dofs({kBaseForward, kLeftShoulder, kLeftElbow, kRightShoulder, kRightElbow}, out.jacobian);
    const SenseReadings& s = *in.senses;
    const RobotStart& start = in.spec().robot;
    const double posture[4] = {start.left_shoulder, start.left_elbow, start.right_shoulder, start.right_elbow};
    double arm_error = 0.0;
    for (int k = 0; k < 4; ++k) {
      const int dof = kLeftShoulder + k;
      out.command[dof] = posture[k] - s.q[dof];
      arm_error = std::max(arm_error, std::abs(out.command[dof]));
    }
    for (int side = 0; side < 2; ++side)
      if (s.touch[kLeftHand + side].contact && value(p_.clear) > 0.0) step_out(in, side, out);
    const bool folded = arm_error <= epsilon();
    const Vec2 base(s.base.x, s.base.y);
    // Only its own execution lets go: evaluated while another action runs (a sequence asking its
    // last step's state), or after a pause, it starts over.
    const bool acting = acted_last_tick(in);
    if (!acting) {
      backing_ = blocked_ = false;
      fold_stalled_ = back_stalled_ = 0.0;
      best_fold_ = best_back_ = kInfinity;
    }
    // Arms that come no nearer their posture are blocked (an object wedged between them and the
    // body, a hand stepping out and folding back in turn): backing away first frees them, where
    // folding on the spot would wait for ever.
    const double patience = value(p_.blocked);
    if (acting && !folded && !backing_) fold_stalled_ = stalled(arm_error, kFoldProgress, in.dt(), best_fold_, fold_stalled_);
    if ((folded || (patience > 0.0 && fold_stalled_ > patience)) && acting && !backing_) {
      backing_ = true;
      blocked_ = !folded;
      origin_ = base;
    }
    double remaining = value(in, p_.distance);
    if (backing_) {
      remaining = std::max(0.0, value(in, p_.distance) - (base - origin_).norm());
      // A base that backs no further (a wall or an obstacle behind it) has backed off as far as
      // it can.
      back_stalled_ = stalled(remaining, kBackProgress, in.dt(), best_back_, back_stalled_);
      if (patience > 0.0 && back_stalled_ > patience) remaining = 0.0;
      out.command[kBaseForward] = -std::min(remaining, value(p_.step));
    }
    out.phi = arm_error + remaining;
    out.residual = out.phi;
    // Arms that were blocked may still be (the object came along, wedged): once the base has
    // backed off, release has done what it can, and ends.
    gamma = (folded || blocked_) && remaining <= 0.02 ? Gamma::kConv : Gamma::kNotConv;
  }

 private:
  // The arm's joints move the hand `clear` out along its touch normal (from the touched surface
  // towards the hand) instead of towards the folded posture.
  void step_out(const ControlInput& in, int side, ControlOutput& out) const {
    Eigen::Matrix<double, 2, kDofCount> J;
    hand_jacobian(in, side, J);
    const Eigen::Matrix<double, 2, 1> e = value(p_.clear) * in.senses->touch[kLeftHand + side].normal;
    const int shoulder = kLeftShoulder + 2 * side, elbow = shoulder + 1;
    const DofVector dq = damped_solve<2>(J, e, mask({shoulder, elbow}), 0.05);
    out.command[shoulder] = clamp_abs(dq[shoulder], 0.5);
    out.command[elbow] = clamp_abs(dq[elbow], 0.5);
  }

  // Seconds an error has gone without falling `progress` below its best (`best`, updated).
  static double stalled(double error, double progress, double dt, double& best, double since) {
    if (error < best - progress) {
      best = error;
      return 0.0;
    }
    return since + dt;
  }
  static constexpr double kInfinity = 1e300;
  static constexpr double kFoldProgress = 0.02;  // rad of the largest joint error: progress folding
  static constexpr double kBackProgress = 0.01;  // m of the distance left: progress backing

  bool backing_ = false;        // the arms were folded (or blocked): the base is backing off
  bool blocked_ = false;        // ...and it was because they were blocked
  double fold_stalled_ = 0.0;   // s the arms have come no nearer their posture
  double back_stalled_ = 0.0;   // s the base has backed no further
  double best_fold_ = kInfinity, best_back_ = kInfinity;  // the least errors so far
  Vec2 origin_ = Vec2::Zero();  // where it started backing
};

}  // namespace

PrimitivePtr make_release() { return std::make_shared<Release>(); }

}  // namespace primitives_internal
}  // namespace roger
