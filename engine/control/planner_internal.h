// planner_internal.h: the harmonic planner's relaxation kernel (planner_sweep.cpp), shared with
// its tests. Private to control/.
#pragma once

#include <cstdint>

namespace roger {
namespace planner_internal {

// Slots each split row is padded to a multiple of: the widest kernel's lanes.
constexpr int kRelaxLanes = 8;

// The cells one vector of the kernel relaxes: `lanes` consecutive slots of one split row (see
// HarmonicPlanner::split_by_colour), its mask beside it. A half-sweep is one flat list of them,
// not runs of a row each with a loop of its own and a bit mask to read: the 8-object line's runs
// held 30 slots on average, and the flat list made its episodes 2% faster with 8 lanes and 18%
// with 2 (the same with 4), with the same bits. A grid has at most 1024 cells a side
// (world:arena), far inside `at`'s 32 bits; split_by_colour refuses a larger one.
struct RelaxGroup {
  // `word` packs the rest, so the kernel reads a group's 8 bytes in one or two loads where four
  // fields took four: nearest (bits 0-22: a flood distance is below the grid's 1024 x 1024 cells),
  // shift (bit 23) and mask (bits 24-31).
  static constexpr int32_t kMaxNearest = (int32_t(1) << 23) - 1;
  int32_t at = 0;     // its first slot, counted from the start of the colour's array (whole lanes)
  uint32_t word = 0;

  RelaxGroup() = default;
  // nearest: the least flood distance from the goal of its relaxed cells (at most kMaxNearest);
  // shift: 0 or 1, slot at + m has left neighbour at + m + shift - 1 of the other colour, right
  // one at + m + shift, and those above and below at + m -+ width; mask: bit m set when slot
  // at + m is relaxed (the others are fixed and keep their value).
  RelaxGroup(int32_t at_slot, int32_t nearest, int shift, unsigned mask)
      : at(at_slot), word(uint32_t(nearest) | uint32_t(shift) << 23 | uint32_t(mask) << 24) {}
  int32_t nearest() const { return int32_t(word & uint32_t(kMaxNearest)); }
  int shift() const { return int(word >> 23) & 1; }
  unsigned mask() const { return word >> 24; }
};

// One red-black half-sweep over `n` groups of one colour's array q: relaxes the cells their masks
// mark from their four neighbours in the other colour's array, passing over each group whose
// `nearest` exceeds `reached`, and returns how many cells changed by less than `tol` of their new
// value (a NaN did not). The cells of a half-sweep do not depend on each other, so the groups'
// order changes no bit.
using RelaxHalfSweep = int (*)(double* q, const double* other, int64_t width, const RelaxGroup* groups,
                               int n, int64_t reached, double omega, double tol);

// The kernel relaxing `lanes` cells per instruction (2, 4 or 8), for groups of that many slots;
// every width gives the same bits.
// Null when the processor cannot run that width (only 2 is always available).
RelaxHalfSweep relax_kernel(int lanes);

// A kernel and the lanes it relaxes per instruction (the slots of each of its groups).
struct RelaxKernel {
  RelaxHalfSweep half_sweep = nullptr;
  int lanes = 2;
};

// The widest kernel this processor runs, chosen once.
RelaxKernel widest_relax_kernel();

}  // namespace planner_internal
}  // namespace roger
