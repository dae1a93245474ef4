// predicate.h: declarative conditions over controller states, evaluated in C++ every control tick
// (no Lua in the loop): converged(c), gamma(c) == state, all/any/not, held for t seconds. Absorbing
// states of stages, success of evaluations and skill goals are written with them.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "control/control.h"

namespace roger {

// A condition over the current tick's controller states.
class Predicate {
 public:
  virtual ~Predicate() = default;
  // Whether the condition holds at this tick (controllers are evaluated, cached per tick).
  virtual bool holds(const ControlInput& in) = 0;
  // Starts an episode (clears timers).
  virtual void reset() {}
  // A readable form, e.g. "all(converged(phi1), converged(phi5))".
  virtual std::string describe() const = 0;
  // The controllers it reads, for validation and usage reports.
  virtual void controllers(std::vector<const Controller*>& out) const = 0;
  // Whether it keeps a timer (held) that must see every tick; all/any without one stop at the
  // first part that decides them, and so skip evaluating controllers nothing else needs.
  virtual bool timed() const { return false; }
  // The least simulated time from an episode's start before it can hold: a lower bound, 0 when it
  // may hold at once or nothing tells, infinity when it never holds (an empty any). held() adds its
  // seconds; all takes its parts' latest, any their earliest.
  virtual double earliest_seconds() const { return 0.0; }
  // The simulated time from which it holds at every tick whatever the controllers and the world
  // do, infinity when no such time is certain: 0 for an all of no parts and the negation of a
  // predicate that never holds; a held() of such a part adds its seconds (found by a probe:
  // roger.held(roger.all{}, 1) passed as a goal met after 1 s in every episode); all takes its
  // parts' latest, any their earliest.
  virtual double certain_from() const { return INFINITY; }
  // Whether it holds at every tick whatever happens: as a goal, met at an episode's first tick.
  bool always_holds() const { return certain_from() <= 0.0; }
  // A copy of this predicate alone (parts still the originals'), for duplicate() only.
  virtual std::shared_ptr<Predicate> copy() const = 0;
  // Replaces the parts of a fresh copy (predicates and controllers) by their duplicates.
  virtual void relink(Duplicates& done) = 0;
};

using PredicatePtr = std::shared_ptr<Predicate>;

// Whether `p` can hold within an episode of `time_limit` simulated seconds whose control ticks are
// `tick_seconds` long (its last tick is the limit rounded up to a tick, as EpisodeRun counts them).
bool can_hold_within(const Predicate& p, double time_limit, double tick_seconds);

// A deep copy with its own state and its own copies of the controllers it reads (see the
// controllers' duplicate, which shares `done`).
PredicatePtr duplicate(const PredicatePtr& p, Duplicates& done);

// A predicate that judges the true world: the verdict the predicate would give if its controllers
// read the true senses at every tick. Under noise the controllers a predicate reads see the noisy
// senses, as the actions sharing them must; the judge then keeps copies of the predicate and of
// every controller it reads (duplicate) that follow their originals on the true senses of the same
// tick: after each tick's command (Agent::step calls follow), each copy is evaluated as its
// original was on that tick (fully, or its state alone) and told of its original's execution
// (Controller::mirror_executed), so plateaus, invocations and holds go as they would; the copies
// never command. Without noise the true senses are the senses and the predicate itself is asked:
// the same verdict by the same rule, at no cost (test_noise checks the two agree, tick for tick,
// on learned policies and on the sort).
class Judge {
 public:
  // Judges `p` (may be null: then it never holds). The predicate must outlive the judge.
  explicit Judge(Predicate* p = nullptr) : predicate_(p) {}
  // Starts an episode: resets the copies, if made, with `seed` (the predicate's owner resets it).
  void reset(uint64_t seed);
  // Whether the predicate holds of the true world at this tick.
  bool holds(const ControlInput& in);
  // After the tick's command was executed, before the world moves: under noise (in.truth), the
  // copies follow what their originals did on this tick.
  void follow(const ControlInput& in);
  // Each controller the predicate reads and its copy (empty until the first tick judged on the truth).
  const Duplicates& copies() const { return done_; }
  // The predicate it judges.
  Predicate* predicate() const { return predicate_; }

 private:
  void make_copies();
  Predicate* predicate_ = nullptr;
  PredicatePtr copy_;  // the copy judged on the truth, once a noisy tick asked for it
  Duplicates done_;    // each original and its copy, parents before their parts
  uint64_t seed_ = 0;
};

// gamma(c) == CONV.
PredicatePtr converged(ControllerPtr c);
// gamma(c) == g.
PredicatePtr gamma_is(ControllerPtr c, Gamma g);
// Every part holds (true when empty).
PredicatePtr all_of(std::vector<PredicatePtr> parts);
// Some part holds (false when empty).
PredicatePtr any_of(std::vector<PredicatePtr> parts);
// The part does not hold.
PredicatePtr negate(PredicatePtr part);
// The part has held without interruption for at least `seconds` of simulated time.
PredicatePtr held(PredicatePtr part, double seconds);

// How many objects a sorting task counts (those whose colour is some goal region's colour) and
// how many of them are sorted: their centre in a region of their own colour, not held. The
// world's judgement, from the map of objects, not from any controller's state.
struct SortCount {
  int sortable = 0, sorted = 0;
};
// `only` (may be null) counts the objects of that colour alone.
SortCount sorted_objects(const ControlInput& in, const Colour* only = nullptr);
// Every object a sorting task counts is sorted (sorted_objects): the judge of "put every object
// in the region of its colour", whatever the number of objects. True in a world without objects;
// holds() throws Error in a world with objects none of which has a region of its colour.
PredicatePtr sorted();
// Every object of `colour` is sorted (true when there is none): one type's part of the judgement,
// e.g. the goal of a move that puts away one type. In a world with objects, holds() throws Error
// when no region has `colour` or no object has a region of its colour.
PredicatePtr sorted(const Colour& colour);

// Starts an episode for a predicate and every controller it reads (reset with `seed`): a goal
// controller outside the action set must not keep hold timers or a per-tick cache from the
// previous episode. Resetting one that the actions also reset, with the same seed, changes nothing.
void reset_predicate(Predicate& p, uint64_t seed);

}  // namespace roger
