// planner_internal.h: the harmonic planner's relaxation kernel (planner_sweep.cpp), shared with
// its tests. Private to control/.
#pragma once

#include <cstdint>

namespace roger {
namespace planner_internal {

// Slots a split row's relaxed part is padded to a multiple of: the widest kernel's lanes.
constexpr int kRelaxLanes = 8;

// One row of a red-black half-sweep on the split layout (see HarmonicPlanner::split_by_colour):
// relaxes the `count` (a multiple of kRelaxLanes) cells of q whose mask is all ones from their
// four neighbours in the other colour's rows, and returns how many of them changed by less than
// `tol` of their new value (a NaN did not).
using RelaxRow = int (*)(double* q, const int64_t* relaxed, const double* left, const double* right,
                         const double* below, const double* above, int count, double omega,
                         double tol);

// The kernel relaxing `lanes` cells per instruction (2, 4 or 8); every width gives the same bits.
// Null when the processor cannot run that width (only 2 is always available).
RelaxRow relax_row_kernel(int lanes);

// A kernel and the lanes it relaxes per instruction (the multiple its `count` must be).
struct RelaxKernel {
  RelaxRow row = nullptr;
  int lanes = 2;
};

// The widest kernel this processor runs, chosen once.
RelaxKernel widest_relax_kernel();

}  // namespace planner_internal
}  // namespace roger
