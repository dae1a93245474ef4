// primitives.h: the control basis's primitive controllers, written in C++ and parameterized from Lua.
//
//   phi0    track: centre the stimulus in both eyes and turn the base to it
//   search  turn to sampled headings until both eyes see the stimulus
//   phi1    harmonic-function path planner: drive to an approach pose near the object, or carry the
//           grasped object into a goal region
//   phi2    visual preshape: body and hands to a standoff circle around the object (from vision)
//   phi3    contact configuration: close body and hands on the object, balance the contact normals
//           measured by touch
//   phi4    kinematic conditioning: arm posture (manipulability), meant as a subordinate
//   phi5    dynamic contact adjustment: hold the three-contact grasp while the base accelerates
//
// docs/control.md gives each one's potential, effectors, Jacobian, gamma and parameters.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "control/control.h"

namespace roger {

// One parameter of a primitive: a number within bounds, or a string among choices.
struct ParamDef {
  std::string name;
  double value = 0.0;  // current value (numbers)
  double min = 0.0, max = 0.0;
  std::string text;                  // current value (strings)
  std::vector<std::string> choices;  // non-empty for string parameters
  std::string help;
  // A number the body decides (core/body.h): while from_body, the value in force is the episode's
  // BodyMetrics' member, and `value` is the default Roger's, for display.
  double BodyMetrics::*body = nullptr;
  bool from_body = false;
  bool whole = false;  // a whole number only (an index: phi1's region)
};

// A primitive controller with named, validated parameters.
class Primitive : public Controller {
 public:
  // The primitive's kind ("phi0" ... "phi5", "search").
  const char* kind() const override { return kind_.c_str(); }

  // Its parameters, including the common epsilon, gain and hold.
  const std::vector<ParamDef>& param_defs() const { return defs_; }

  // Sets a number parameter. Throws roger::Error naming the primitive and listing the known
  // parameters for an unknown name, or giving the bounds for a value outside them or not finite.
  void set_number(const std::string& name, double value);

  // Sets a string parameter. Throws roger::Error listing the choices. A number the body can decide
  // takes the string "body": it follows the episode's body again.
  void set_text(const std::string& name, const std::string& value);

  // Reads a number parameter (throws for an unknown name).
  double number(const std::string& name) const;

  // Reads a string parameter (throws for an unknown name).
  const std::string& text(const std::string& name) const;

  // The parameters set away from the kind's defaults: `goal = "region", region = 7`.
  std::string settings() const override;

  // A copy with the same parameters and fresh state.
  virtual std::shared_ptr<Primitive> clone() const = 0;
  // For duplicate(): the clone, a leaf.
  std::shared_ptr<Controller> copy() const override { return clone(); }


 protected:
  Primitive(std::string kind, double default_epsilon);
  // Where a parameter sits among param_defs(): the hot loops read parameters by slot, since a name
  // search per read cost several per cent of the whole pipeline.
  using ParamSlot = size_t;
  // The slot of a number parameter the body can decide: its value in force is read with the
  // ControlInput of the evaluation (the world's body), so it has a type of its own.
  struct BodySlot {
    ParamSlot slot = 0;
  };
  // Declares a number parameter with its default, bounds and one-line help; returns its slot.
  ParamSlot declare(const std::string& name, double value, double min, double max, const std::string& help);
  // Declares a number parameter that takes whole numbers only (an index); returns its slot.
  ParamSlot declare_whole(const std::string& name, double value, double min, double max, const std::string& help);
  // Declares a string parameter with its choices (the first is the default); returns its slot.
  ParamSlot declare_text(const std::string& name, std::vector<std::string> choices, const std::string& help);
  // Declares a number parameter the body decides (its default: the default Roger's value of
  // `metric`, core/body.h); returns its slot.
  BodySlot declare_body(const std::string& name, double BodyMetrics::*metric, double min, double max,
                        const std::string& help);
  // Makes the number parameter at `slot` one the body can decide, following it from now on when
  // `from_body` (until set to a number); returns its slot as a body's.
  BodySlot follow_body(ParamSlot slot, double BodyMetrics::*metric, bool from_body = true);
  // The value of the number parameter declared at `slot`.
  double value(ParamSlot slot) const { return defs_[slot].value; }
  // The value in force of a number parameter the body can decide: the world's (in.body()) where it
  // follows the body.
  double value(const ControlInput& in, BodySlot slot) const {
    const ParamDef& d = defs_[slot.slot];
    return d.from_body ? in.body().*d.body : d.value;
  }
  // The value of the string parameter declared at `slot`.
  const std::string& choice(ParamSlot slot) const { return defs_[slot].text; }
  // Called after any parameter changes, so subclasses can cache them.
  virtual void on_params_changed() {}
  // Mirrors the common parameters (epsilon, gain, hold) into ControllerParams.
  void on_param(const std::string& name, double value);
  // The convergence threshold in force.
  double epsilon() const { return params().epsilon; }
  // Whether its command was applied on the tick before, so this tick continues its own run. A tick
  // after one on which it was only evaluated to read its state (another action had the robot)
  // begins a new run.
  bool acted_last_tick(const ControlInput& in) const {
    return executed_tick() != UINT64_MAX && executed_tick() + 1 == in.tick;
  }

 private:
  ParamDef& find(const std::string& name);
  const ParamDef& find(const std::string& name) const;
  // Throws when `name` is declared already (a kind's own parameter shadowing a common one).
  void refuse_redeclared(const std::string& name) const;
  std::string kind_;
  std::vector<ParamDef> defs_;
};

using PrimitivePtr = std::shared_ptr<Primitive>;

// The grasp residual of three contacts (body, left hand, right hand) on an object: how far the
// contacts' pushes fail to balance. Each contact pushes along its unit normal n_i (from the
// surface towards the sensor) and may add up to `friction` times that push along the surface;
// the residual is the least |sum of the contact forces|^2 + moment_weight * (their moment about
// `center` / size)^2 over those friction allowances. With friction 0 and moment_weight 0 it is the
// paper's |sum n_i|^2. Friction matters for polygons: a pentagon's best three faces leave
// |sum n|^2 = 0.38 although the grasp holds firmly.
struct GraspResidual {
  double phi = 0.0;             // the residual
  Vec2 force = Vec2::Zero();    // the unbalanced force (the sum at the optimum)
  double friction_used[kTactileCount] = {0.0, 0.0, 0.0};  // each contact's tangential share
};
GraspResidual grasp_residual(const Vec2 normal[kTactileCount], const Vec2 point[kTactileCount],
                             const Vec2& center, double size, double moment_weight,
                             double friction);

// Makes a primitive by name with default parameters. Throws roger::Error listing the known names.
PrimitivePtr make_primitive(const std::string& name);

// The names make_primitive knows, in order.
const std::vector<std::string>& primitive_names();

// One-line descriptions of the primitives, for documentation and `roger check`.
const std::map<std::string, std::string>& primitive_descriptions();

// A goal region a controller sends Roger to: a binding's delivery region, or a navigator's own
// `region` (goal = "region") where no binding above it names the region.
struct RegionUse {
  const Controller* controller = nullptr;  // null: none found
  int region = -1;
  bool binding = false;
};
// The first region use reached from `root` (children after their parent, each controller once)
// at `regions` or beyond: what `roger check` refuses in worlds of `regions` goal regions.
RegionUse first_region_beyond(const Controller* root, int regions);
// What is wrong with a use found in worlds of `scenario` with `regions` goal regions: "the binding
// 'to seven' delivers to goal region 7, but the worlds of scenario 'sorting' have 4 goal regions
// (0 to 3)", or the navigator's "phi1 {goal = "region", region = 7} goes to ...".
std::string region_use_problem(const RegionUse& use, const std::string& scenario, int regions);

}  // namespace roger
