#include "control/predicate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"

namespace roger {
namespace {

class GammaIs final : public Predicate {
 public:
  GammaIs(ControllerPtr c, Gamma g, bool short_form) : c_(std::move(c)), g_(g), short_(short_form) {
    if (!c_) throw Error("predicate: needs a controller");
  }
  bool holds(const ControlInput& in) override { return c_->state(in) == g_; }
  std::string describe() const override {
    return short_ ? "converged(" + c_->name() + ")"
                  : "gamma(" + c_->name() + ") == " + gamma_name(g_);
  }
  void controllers(std::vector<const Controller*>& out) const override { out.push_back(c_.get()); }
  // converged() of a controller that never converges never holds (found by a probe: the goal
  // converged(p) of a policy p without `done` passed check and failed every episode).
  double earliest_seconds() const override { return g_ == Gamma::kConv && !c_->can_converge() ? INFINITY : 0.0; }
  PredicatePtr copy() const override { return std::make_shared<GammaIs>(*this); }
  void relink(Duplicates& done) override { c_ = duplicate(c_, done); }

 private:
  ControllerPtr c_;
  Gamma g_;
  bool short_;
};

class Combine final : public Predicate {
 public:
  Combine(std::vector<PredicatePtr> parts, bool all) : parts_(std::move(parts)), all_(all) {
    for (const auto& p : parts_) {
      if (!p) throw Error(std::string(all_ ? "all" : "any") + ": every part must be a predicate");
      timed_ = timed_ || p->timed();
    }
  }
  bool holds(const ControlInput& in) override {
    // With a held() timer inside, every part must see every tick; otherwise the first part that
    // decides the result ends the evaluation (a controller's own hold restarts after a gap).
    bool result = all_;
    for (auto& p : parts_) {
      const bool h = p->holds(in);
      result = all_ ? (result && h) : (result || h);
      if (!timed_ && result != all_) break;
    }
    return result;
  }
  bool timed() const override { return timed_; }
  double earliest_seconds() const override {
    double earliest = all_ ? 0.0 : INFINITY;
    for (const auto& p : parts_)
      earliest = all_ ? std::max(earliest, p->earliest_seconds()) : std::min(earliest, p->earliest_seconds());
    return earliest;
  }
  double certain_from() const override {
    double from = all_ ? 0.0 : INFINITY;  // all() of no parts holds at once; any() of none never
    for (const auto& p : parts_) from = all_ ? std::max(from, p->certain_from()) : std::min(from, p->certain_from());
    return from;
  }
  void reset() override {
    for (auto& p : parts_) p->reset();
  }
  std::string describe() const override {
    std::string s = all_ ? "all(" : "any(";
    for (size_t i = 0; i < parts_.size(); ++i) s += (i ? ", " : "") + parts_[i]->describe();
    return s + ")";
  }
  void controllers(std::vector<const Controller*>& out) const override {
    for (const auto& p : parts_) p->controllers(out);
  }
  PredicatePtr copy() const override { return std::make_shared<Combine>(*this); }
  void relink(Duplicates& done) override {
    for (auto& p : parts_) p = duplicate(p, done);
  }

 private:
  std::vector<PredicatePtr> parts_;
  bool all_;
  bool timed_ = false;
};

class Not final : public Predicate {
 public:
  explicit Not(PredicatePtr p) : p_(std::move(p)) {
    if (!p_) throw Error("not: needs a predicate");
  }
  bool holds(const ControlInput& in) override { return !p_->holds(in); }
  void reset() override { p_->reset(); }
  std::string describe() const override { return "not(" + p_->describe() + ")"; }
  void controllers(std::vector<const Controller*>& out) const override { p_->controllers(out); }
  bool timed() const override { return p_->timed(); }
  // The negation of a part that never holds holds always, and of one that always holds never
  // (found by a probe: roger.negate(roger.any{}) passed as a goal met at the first tick).
  double certain_from() const override { return std::isfinite(p_->earliest_seconds()) ? INFINITY : 0.0; }
  double earliest_seconds() const override { return p_->always_holds() ? INFINITY : 0.0; }
  PredicatePtr copy() const override { return std::make_shared<Not>(*this); }
  void relink(Duplicates& done) override { p_ = duplicate(p_, done); }

 private:
  PredicatePtr p_;
};

class Held final : public Predicate {
 public:
  Held(PredicatePtr p, double seconds) : p_(std::move(p)), seconds_(seconds) {
    if (!p_) throw Error("held: needs a predicate");
    if (!(seconds >= 0.0)) throw Error("held: seconds must be a number >= 0");
  }
  bool holds(const ControlInput& in) override {
    if (!p_->holds(in)) {
      since_ = -1.0;
      return false;
    }
    if (since_ < 0.0) since_ = in.time;
    return in.time - since_ + 1e-9 >= seconds_;
  }
  void reset() override {
    since_ = -1.0;
    p_->reset();
  }
  std::string describe() const override {
    return "held(" + p_->describe() + ", " + std::to_string(seconds_).substr(0, 5) + " s)";
  }
  void controllers(std::vector<const Controller*>& out) const override { p_->controllers(out); }
  bool timed() const override { return true; }
  // Its part holds at the earliest at some time, and must then hold `seconds_` more.
  double earliest_seconds() const override { return p_->earliest_seconds() + seconds_; }
  // A part that holds for good from some time holds `seconds_` on from then, whatever happens.
  double certain_from() const override { return p_->certain_from() + seconds_; }
  PredicatePtr copy() const override { return std::make_shared<Held>(*this); }
  void relink(Duplicates& done) override { p_ = duplicate(p_, done); }

 private:
  PredicatePtr p_;
  double seconds_;
  double since_ = -1.0;
};

// "#dc1e1e x 2, #9628aa": each distinct colour of the objects once, in the order first seen.
std::string object_colours(const std::vector<MapObject>& objects) {
  std::vector<std::pair<Colour, int>> seen;
  for (const MapObject& o : objects) {
    auto it = std::find_if(seen.begin(), seen.end(), [&](const auto& s) { return s.first == o.colour; });
    if (it == seen.end()) seen.emplace_back(o.colour, 1);
    else ++it->second;
  }
  std::string s;
  for (const auto& [colour, n] : seen)
    s += (s.empty() ? "" : ", ") + colour.hex() + (n > 1 ? " x " + std::to_string(n) : "");
  return s;
}

// "circle #dc1e1e, triangle #2850dc", or "none".
std::string region_colours(const std::vector<GoalRegion>& goals) {
  std::string s;
  for (const GoalRegion& g : goals) s += (s.empty() ? "" : ", ") + g.name + " " + g.colour.hex();
  return s.empty() ? "none" : s;
}

// The world's judgement of a sorting task (see sorted_objects), over every colour or one.
class Sorted final : public Predicate {
 public:
  explicit Sorted(const Colour* colour) : only_(colour != nullptr), colour_(colour ? *colour : Colour{}) {}
  bool holds(const ControlInput& in) override {
    const SortCount c = sorted_objects(in, only_ ? &colour_ : nullptr);
    if (c.sortable == 0) check_counts_some(in);
    return c.sorted == c.sortable;
  }
  std::string describe() const override { return only_ ? "sorted(\"" + colour_.hex() + "\")" : "sorted()"; }
  void controllers(std::vector<const Controller*>&) const override {}
  PredicatePtr copy() const override { return std::make_shared<Sorted>(*this); }
  void relink(Duplicates&) override {}

 private:
  // Nothing counted is "sorted" for ever: right in a world without objects, or for one type
  // absent from a world whose other objects are counted, but a colour matching no region (a typo
  // in a region's or the predicate's colour) would make a do-nothing policy succeed at once. The
  // world's colours do not change within an episode, so the first evaluation raises.
  void check_counts_some(const ControlInput& in) const {
    if (!in.objects || !in.model || in.objects->empty()) return;
    const std::vector<GoalRegion>& goals = in.spec().goals;
    // Text only when it is thrown: this runs every tick while one type is absent.
    auto listing = [&] {
      return " (objects: " + object_colours(*in.objects) + "; goal regions: " + region_colours(goals) +
             "); roger.sorted matches an object to the region of its exact colour";
    };
    const bool has_region = std::any_of(goals.begin(), goals.end(), [&](const GoalRegion& g) { return g.colour == colour_; });
    if (only_ && !has_region)
      throw Error("roger." + describe() + ": no goal region has the colour " + colour_.hex() + ", so it would hold for ever" +
                  listing());
    if (sorted_objects(in).sortable == 0)
      throw Error("roger." + describe() + ": none of the world's " + std::to_string(in.objects->size()) +
                  " objects has the colour of a goal region, so it would hold for ever" + listing());
  }

  bool only_;
  Colour colour_;
};

}  // namespace

SortCount sorted_objects(const ControlInput& in, const Colour* only) {
  SortCount c;
  if (!in.objects || !in.model) return c;
  const std::vector<GoalRegion>& goals = in.spec().goals;
  for (const MapObject& o : *in.objects) {
    if (only && !(o.colour == *only)) continue;
    bool has_region = false;
    for (const GoalRegion& g : goals) has_region |= g.colour == o.colour;
    if (!has_region) continue;
    ++c.sortable;
    const bool in_own = o.region >= 0 && goals[size_t(o.region)].colour == o.colour;
    c.sorted += in_own && !o.held;
  }
  return c;
}

PredicatePtr sorted() { return std::make_shared<Sorted>(nullptr); }
PredicatePtr sorted(const Colour& colour) { return std::make_shared<Sorted>(&colour); }

PredicatePtr converged(ControllerPtr c) {
  return std::make_shared<GammaIs>(std::move(c), Gamma::kConv, true);
}
PredicatePtr gamma_is(ControllerPtr c, Gamma g) {
  return std::make_shared<GammaIs>(std::move(c), g, false);
}
PredicatePtr all_of(std::vector<PredicatePtr> parts) {
  return std::make_shared<Combine>(std::move(parts), true);
}
PredicatePtr any_of(std::vector<PredicatePtr> parts) {
  return std::make_shared<Combine>(std::move(parts), false);
}
PredicatePtr negate(PredicatePtr part) { return std::make_shared<Not>(std::move(part)); }
PredicatePtr held(PredicatePtr part, double seconds) {
  return std::make_shared<Held>(std::move(part), seconds);
}

bool can_hold_within(const Predicate& p, double time_limit, double tick_seconds) {
  // An episode's goal is first judged after its first tick (EpisodeRun asks once a tick has run),
  // so a held() timer starts at one tick at the earliest, and compares as Held does (found by a
  // probe: held(p, 5) in a 5 s episode passed, and could never hold).
  const double last_tick = std::ceil(time_limit / tick_seconds - 1e-9) * tick_seconds;
  return tick_seconds + p.earliest_seconds() <= last_tick + 1e-9;
}

PredicatePtr duplicate(const PredicatePtr& p, Duplicates& done) {
  return control_detail::duplicate_in(p, done, done.predicates);
}

void Judge::reset(uint64_t seed) {
  seed_ = seed;
  if (copy_) reset_predicate(*copy_, seed);
}

void Judge::make_copies() {
  // The predicate is not owned here; an aliasing pointer lets duplicate() read it.
  done_ = Duplicates{};
  copy_ = duplicate(PredicatePtr(PredicatePtr(), predicate_), done_);
  reset_predicate(*copy_, seed_);
}

bool Judge::holds(const ControlInput& in) {
  if (!predicate_) return false;
  if (!in.truth) return predicate_->holds(in);
  if (!copy_) make_copies();
  return copy_->holds(*in.truth);
}

void Judge::follow(const ControlInput& in) {
  if (!predicate_ || !in.truth) return;
  if (!copy_) make_copies();
  const ControlInput& truth = *in.truth;
  // Evaluations first (a composite's bookkeeping of its execution reads its parts' outputs of the
  // tick), parents before their parts; a state read before a full evaluation first, so the hold
  // time is settled once, as in the original.
  const uint64_t tick = in.tick;
  for (const auto& [original, copy] : done_.controllers) {
    if (original->observed_tick() == tick) copy->state(truth);
    if (original->evaluated_tick() == tick) copy->evaluate(truth);
  }
  for (const auto& [original, copy] : done_.controllers)
    if (original->executed_tick() == tick) copy->mirror_executed(truth);
}

void reset_predicate(Predicate& p, uint64_t seed) {
  // Predicate::controllers lists them as const only because most readers just look; the
  // controllers themselves are not const objects.
  std::vector<const Controller*> read;
  p.controllers(read);
  for (const Controller* c : read) const_cast<Controller*>(c)->reset(seed);
  p.reset();
}

}  // namespace roger
