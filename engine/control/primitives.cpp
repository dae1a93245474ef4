// primitives.cpp: the Primitive base class (named, validated parameters), the registry of
// primitives (make_primitive, primitive_names, primitive_descriptions), and the helpers every
// primitive's file uses. Each primitive lives in its own file: primitives_simple.cpp (phi0,
// search, phi4), primitives_navigate.cpp (phi1), primitives_grasp.cpp (phi2, phi3, phi5) over
// primitives_contact.cpp (their contact geometry).
#include "control/primitives.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "control/primitives_internal.h"
#include "core/error.h"
#include "core/text.h"

namespace roger {
namespace primitives_internal {

// Where the object is believed to be: this tick's estimate, or the last one if it is recent. With
// `vision_only`, touch-based estimates are ignored: controllers that work at a distance (approach,
// preshape) keep one consistent frame instead of flipping between what vision and a grazing
// contact say about a polygon.
bool object_estimate(const ControlInput& in, double memory, VisualObject& out,
                     bool vision_only) {
  const Percepts& p = *in.percepts;
  if (vision_only) {
    if (!p.vision.seen || in.time - p.vision_time > memory) return false;
    out = p.vision;
    return true;
  }
  if (p.object.seen) {
    out = p.object;
    return true;
  }
  if (p.remembered.seen && in.time - p.remembered_time <= memory) {
    out = p.remembered;
    return true;
  }
  return false;
}

DofVector mask(std::initializer_list<int> dofs) {
  DofVector m = DofVector::Zero();
  for (int d : dofs) m[d] = 1.0;
  return m;
}

// Rows of the identity for a set of DOFs: a task that owns those DOFs outright.
void own_dofs(std::initializer_list<int> dofs, TaskJacobian& J) {
  J.resize(int(dofs.size()), kDofCount);
  J.setZero();
  int r = 0;
  for (int d : dofs) J(r++, d) = 1.0;
}

}  // namespace primitives_internal

Primitive::Primitive(std::string kind, double default_epsilon) : kind_(std::move(kind)) {
  set_name(kind_);
  declare("epsilon", default_epsilon, 0.0, 1e6, "convergence threshold on the residual");
  declare("gain", 1.0, 0.0, 100.0, "scales the command");
  declare("hold", 0.0, 0.0, 60.0, "seconds the condition must hold before gamma is CONV");
  declare("stall", 0.01, 0.0, 1e6,
          "as a subordinate, converged once its projected command, or the change of its progress "
          "(its potential; phi1's distance to its goal) over `plateau` seconds, is this small");
  declare("plateau", 0.3, 0.0, 60.0, "seconds over which a subordinate's progress must settle");
}

Primitive::ParamSlot Primitive::declare(const std::string& name, double value, double min, double max,
                                        const std::string& help) {
  refuse_redeclared(name);
  ParamDef d;
  d.name = name, d.value = value, d.min = min, d.max = max, d.help = help;
  defs_.push_back(d);
  on_param(name, value);
  return defs_.size() - 1;
}

Primitive::ParamSlot Primitive::declare_whole(const std::string& name, double value, double min, double max,
                                              const std::string& help) {
  const ParamSlot slot = declare(name, value, min, max, help);
  defs_[slot].whole = true;
  return slot;
}

Primitive::BodySlot Primitive::declare_body(const std::string& name, double BodyMetrics::*metric, double min,
                                            double max, const std::string& help) {
  return follow_body(declare(name, BodyMetrics{}.*metric, min, max, help), metric);
}

Primitive::BodySlot Primitive::follow_body(ParamSlot slot, double BodyMetrics::*metric, bool from_body) {
  ParamDef& d = defs_[slot];
  d.body = metric;
  d.from_body = from_body;
  if (from_body) d.value = BodyMetrics{}.*metric;
  return BodySlot{slot};
}

void Primitive::refuse_redeclared(const std::string& name) const {
  // A second parameter of one name would be unreachable: setting it by name finds the first.
  for (const ParamDef& d : defs_)
    if (d.name == name) throw Error(kind_ + ": parameter '" + name + "' is declared twice");
}

Primitive::ParamSlot Primitive::declare_text(const std::string& name, std::vector<std::string> choices,
                                             const std::string& help) {
  refuse_redeclared(name);
  ParamDef d;
  d.name = name, d.choices = std::move(choices), d.help = help;
  d.text = d.choices.front();
  defs_.push_back(d);
  return defs_.size() - 1;
}

void Primitive::on_param(const std::string& name, double value) {
  if (name == "epsilon") params().epsilon = value;
  if (name == "gain") params().gain = value;
  if (name == "hold") params().hold = value;
  if (name == "stall") params().stall = value;
  if (name == "plateau") params().plateau = value;
}

ParamDef& Primitive::find(const std::string& name) {
  for (auto& d : defs_)
    if (d.name == name) return d;
  std::ostringstream os;
  os << kind_ << ": unknown parameter '" << name << "'; known parameters:";
  for (size_t i = 0; i < defs_.size(); ++i) os << (i ? ", " : " ") << defs_[i].name;
  throw Error(os.str());
}

const ParamDef& Primitive::find(const std::string& name) const {
  return const_cast<Primitive*>(this)->find(name);
}

void Primitive::set_number(const std::string& name, double value) {
  ParamDef& d = find(name);
  if (!d.choices.empty())
    throw Error(kind_ + ": parameter '" + name + "' takes a string, one of: " + [&] {
      std::string s;
      for (const auto& c : d.choices) s += (s.empty() ? "" : ", ") + c;
      return s;
    }());
  if (!std::isfinite(value) || value < d.min || value > d.max) {
    std::ostringstream os;
    os << kind_ << ": parameter '" << name << "' must be a number in [" << d.min << ", " << d.max
       << "], got " << value;
    throw Error(os.str());
  }
  // Found by a probe: region = 1.5 was taken and went to region 1, where roger.bind refuses it.
  if (d.whole && value != std::floor(value))
    throw Error(kind_ + ": parameter '" + name + "' must be a whole number in [" + format_number(d.min) + ", " +
                format_number(d.max) + "], got " + format_number(value));
  d.value = value;
  d.from_body = false;
  on_param(name, value);
  on_params_changed();
}

void Primitive::set_text(const std::string& name, const std::string& value) {
  ParamDef& d = find(name);
  if (d.body && value == "body") {
    d.from_body = true;
    d.value = BodyMetrics{}.*d.body;
    on_params_changed();
    return;
  }
  if (d.choices.empty())
    throw Error(kind_ + ": parameter '" + name + "' takes a number, not '" + value + "'");
  if (std::find(d.choices.begin(), d.choices.end(), value) == d.choices.end()) {
    std::string s;
    for (const auto& c : d.choices) s += (s.empty() ? "" : ", ") + c;
    throw Error(kind_ + ": parameter '" + name + "' must be one of " + s + ", got '" + value + "'");
  }
  d.text = value;
  on_params_changed();
}

double Primitive::number(const std::string& name) const {
  const ParamDef& d = find(name);
  return d.value;
}

const std::string& Primitive::text(const std::string& name) const { return find(name).text; }

std::string Primitive::settings() const {
  const PrimitivePtr fresh = make_primitive(kind_);
  std::string out;
  for (size_t k = 0; k < defs_.size(); ++k) {
    const ParamDef &d = defs_[k], &f = fresh->defs_[k];
    std::string value;
    if (!d.choices.empty()) {
      if (d.text != f.text) value = "\"" + d.text + "\"";
    } else if (d.from_body != f.from_body || (!d.from_body && d.value != f.value)) {
      value = d.from_body ? "\"body\"" : format_number(d.value);
    }
    if (!value.empty()) out += (out.empty() ? "" : ", ") + d.name + " = " + value;
  }
  return out;
}

PrimitivePtr make_primitive(const std::string& name) {
  using namespace primitives_internal;
  if (name == "phi0") return make_track();
  if (name == "search") return make_search();
  if (name == "phi1") return make_navigate();
  if (name == "phi2") return make_preshape();
  if (name == "phi3") return make_grasp();
  if (name == "phi4") return make_condition();
  if (name == "phi5") return make_hold();
  if (name == "release") return make_release();
  std::string known;
  for (const auto& n : primitive_names()) known += (known.empty() ? "" : ", ") + n;
  throw Error("unknown primitive '" + name + "'; known primitives: " + known);
}

const std::vector<std::string>& primitive_names() {
  static const std::vector<std::string> names = {"phi0", "search", "phi1", "phi2",
                                                 "phi3", "phi4",   "phi5", "release"};
  return names;
}

const std::map<std::string, std::string>& primitive_descriptions() {
  static const std::map<std::string, std::string> d = {
      {"phi0", "track: centre the stimulus in both eyes and turn the base to it"},
      {"search", "turn to sampled headings until both eyes see the stimulus"},
      {"phi1", "harmonic-function path planner to the object's approach ring or a goal region"},
      {"phi2", "visual preshape: body and hands to a standoff around the object"},
      {"phi3", "contact configuration: close on the object, balance the touch normals"},
      {"phi4", "kinematic conditioning: most manipulable arm posture (subordinate)"},
      {"phi5", "dynamic contact adjustment: hold the grasp while the base accelerates"},
      {"release", "let go: arms back to the start posture, then back the base off"}};
  return d;
}

namespace {

// Whether `p` navigates to the goal region its `region` parameter names.
bool navigates_to_region(const Primitive& p) {
  const auto& defs = p.param_defs();
  const auto goal = std::find_if(defs.begin(), defs.end(), [](const ParamDef& d) { return d.name == "goal"; });
  const bool has_region = std::any_of(defs.begin(), defs.end(), [](const ParamDef& d) { return d.name == "region"; });
  return goal != defs.end() && goal->text == "region" && has_region;
}

// first_region_beyond's walk; `bound` when a binding above names the region.
bool region_beyond(const Controller* c, int regions, bool bound, std::set<const Controller*>& seen, RegionUse& out) {
  if (!c || !seen.insert(c).second) return false;
  if (const auto* b = dynamic_cast<const Binding*>(c)) {
    if (b->bindings().region >= regions) return out = {c, b->bindings().region, true}, true;
    bound = bound || b->bindings().region >= 0;
  } else if (const auto* prim = dynamic_cast<const Primitive*>(c); prim && !bound && navigates_to_region(*prim)) {
    const int region = int(prim->number("region"));
    if (region >= regions) return out = {c, region, false}, true;
  }
  for (const Controller* child : c->children())
    if (region_beyond(child, regions, bound, seen, out)) return true;
  return false;
}

}  // namespace

RegionUse first_region_beyond(const Controller* root, int regions) {
  std::set<const Controller*> seen;
  RegionUse use;
  region_beyond(root, regions, false, seen, use);
  return use;
}

std::string region_use_problem(const RegionUse& use, const std::string& scenario, int regions) {
  if (!use.controller) return "";
  const std::string who = use.binding ? "the binding '" + use.controller->name() + "' delivers to"
                                      : "the navigator " + use.controller->name() + " {" +
                                            use.controller->settings() + "} goes to";
  return who + " goal region " + std::to_string(use.region) + ", but the worlds of scenario '" + scenario + "' have " +
         counted(regions, "goal region") +
         (regions > 0 ? " (0 to " + std::to_string(regions - 1) + ")" : std::string());
}

}  // namespace roger
