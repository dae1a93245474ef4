// planner_internal.h: the harmonic planner's relaxation kernel (planner_sweep.cpp), shared with
// its tests. Private to control/.
#pragma once

#include <cstdint>
#include <cstring>

namespace roger {
namespace planner_internal {

// Slots a split row's relaxed part is padded to a multiple of: the widest kernel's lanes.
constexpr int kRelaxLanes = 8;

// A run of slots a half-sweep relaxes: the part of one row of the split layout (see
// HarmonicPlanner::split_by_colour) that holds relaxed cells, padded to whole lanes.
struct RelaxRange {
  int64_t at = 0;       // its first slot, counted from the start of the colour's array
  int32_t shift = 0;    // 0 or 1: slot at + m has left neighbour at + m + shift - 1 of the other
                        // colour, right one at + m + shift, and those above and below at + m -+ width
  int32_t count = 0;    // slots, a multiple of the kernel's lanes
  int32_t nearest = 0;  // the least flood distance from the goal of its relaxed cells
  int32_t full = 0;     // 1: every slot of it is relaxed, so a kernel need not read the mask
};

// Bytes of the bit mask over `slots` slots: one bit per slot, and a byte to spare, since a kernel
// reads the mask two bytes at a time.
inline int64_t relax_mask_bytes(int64_t slots) { return slots / 8 + 2; }
// Marks slot k of a bit mask as relaxed (bit k % 8 of byte k / 8).
inline void set_relaxed(uint8_t* relaxed, int64_t k) { relaxed[k / 8] |= uint8_t(1u << (k % 8)); }
// The `lanes` (at most 8) bits of the mask from slot k on, in the low bits.
inline unsigned mask_bits(const uint8_t* relaxed, int64_t k, int lanes) {
  const uint64_t slot = uint64_t(k);  // never negative: shifts, not signed division
  uint16_t two;
  std::memcpy(&two, relaxed + slot / 8, sizeof two);
  return (unsigned(two) >> (slot % 8)) & ((1u << lanes) - 1u);
}

// One red-black half-sweep over `n` ranges of one colour's array q: relaxes the cells whose bit
// in `relaxed` is set from their four neighbours in the other colour's array, passing over each
// range whose `nearest` exceeds `reached`, and returns how many cells changed by less than `tol`
// of their new value (a NaN did not). A bit, not a mask of 64 per cell: the values and their
// mask then stay in the first-level cache through a solve's sweeps.
using RelaxHalfSweep = int (*)(double* q, const uint8_t* relaxed, const double* other,
                               int64_t width, const RelaxRange* ranges, int n, int64_t reached,
                               double omega, double tol);

// The kernel relaxing `lanes` cells per instruction (2, 4 or 8); every width gives the same bits.
// Null when the processor cannot run that width (only 2 is always available).
RelaxHalfSweep relax_kernel(int lanes);

// A kernel and the lanes it relaxes per instruction (the multiple each range's count must be).
struct RelaxKernel {
  RelaxHalfSweep half_sweep = nullptr;
  int lanes = 2;
};

// The widest kernel this processor runs, chosen once.
RelaxKernel widest_relax_kernel();

}  // namespace planner_internal
}  // namespace roger
