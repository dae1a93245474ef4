// primitives_release.cpp: release, letting go of an object: the arms return to the start posture
// (hands beside the body, clear of anything ahead), then the base backs off, so that turning
// afterwards cannot sweep the object with a hand. The paper stops at transport; any task that
// moves more than one object (sorting, Figure 1) must let go of one before taking the next.
#include <algorithm>
#include <cmath>

#include "control/primitives_internal.h"

namespace roger {
namespace primitives_internal {
namespace {

class Release final : public Primitive {
  struct { ParamSlot distance = 0, step = 0; } p_;
 public:
  Release() : Primitive("release", 0.05) {
    p_.distance = declare("distance", 0.4, 0.0, 2.0, "how far (m) the base backs off once the arms are folded");
    p_.step = declare("step", 0.1, 0.01, 1.0, "largest backing error (m) per command");
  }
  PrimitivePtr clone() const override { return std::make_shared<Release>(*this); }
  void reset(uint64_t seed) override {
    Primitive::reset(seed);
    backing_ = false;
    executed_tick_ = UINT64_MAX;
  }
  void executed(const ControlInput& in) override { executed_tick_ = in.tick; }

 protected:
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma) override {
    own_dofs({kBaseForward, kLeftShoulder, kLeftElbow, kRightShoulder, kRightElbow}, out.jacobian);
    const Senses& s = *in.senses;
    const RobotStart& start = in.spec->robot;
    const double posture[4] = {start.left_shoulder, start.left_elbow, start.right_shoulder, start.right_elbow};
    double arm_error = 0.0;
    for (int k = 0; k < 4; ++k) {
      const int dof = kLeftShoulder + k;
      out.command[dof] = posture[k] - s.q[dof];
      arm_error = std::max(arm_error, std::abs(out.command[dof]));
    }
    const bool folded = arm_error <= epsilon();
    const Vec2 base(s.base.x, s.base.y);
    // Only its own execution lets go: evaluated while another action runs (a sequence asking its
    // last step's state), or after a pause, it starts over.
    const bool acting = executed_tick_ != UINT64_MAX && executed_tick_ + 1 == in.tick;
    if (!acting) backing_ = false;
    if (folded && acting && !backing_) {
      backing_ = true;
      origin_ = base;
    }
    double remaining = value(p_.distance);
    if (backing_) {
      remaining = std::max(0.0, value(p_.distance) - (base - origin_).norm());
      out.command[kBaseForward] = -std::min(remaining, value(p_.step));
    }
    out.phi = arm_error + remaining;
    out.residual = out.phi;
    gamma = folded && remaining <= 0.02 ? Gamma::kConv : Gamma::kNotConv;
  }

 private:
  bool backing_ = false;        // the arms were folded: the base is backing off
  uint64_t executed_tick_ = UINT64_MAX;  // the last tick its command was applied
  Vec2 origin_ = Vec2::Zero();  // where it started backing
};

}  // namespace

PrimitivePtr make_release() { return std::make_shared<Release>(); }

}  // namespace primitives_internal
}  // namespace roger
