// planner_sweep.cpp: the harmonic planner's relaxation kernel, most of the planner's cost. One
// kernel, instantiated for 2 (SSE2, any x86-64), 4 (AVX) and 8 (AVX-512) doubles per instruction
// and chosen at run time: each lane computes exactly what the scalar code would, operation for
// operation and in the same order, so every width gives the same bits, and a solve the same
// sweeps and the same potential, on any processor.
#include "control/planner_internal.h"

#include <climits>
#include <cstring>
#include <initializer_list>

namespace roger {
namespace planner_internal {
namespace {

// Vectors of `Lanes` doubles and of as many 64-bit masks (GCC and Clang vector extensions).
template <int Lanes> struct Lanes_;
template <> struct Lanes_<2> {
  typedef double Vec __attribute__((vector_size(16)));
  typedef int64_t Mask __attribute__((vector_size(16)));
};
template <> struct Lanes_<4> {
  typedef double Vec __attribute__((vector_size(32)));
  typedef int64_t Mask __attribute__((vector_size(32)));
};
template <> struct Lanes_<8> {
  typedef double Vec __attribute__((vector_size(64)));
  typedef int64_t Mask __attribute__((vector_size(64)));
};

// `Lanes` cells relaxed together. Always inlined into a wrapper compiled for the instruction set
// of that width.
template <int Lanes>
__attribute__((always_inline)) inline int relax_lanes(double* __restrict q,
                                                     const int64_t* __restrict relaxed,
                                                     const double* other, int64_t width,
                                                     const RelaxRange* ranges, int n,
                                                     int64_t reached, double omega, double tol) {
  typedef typename Lanes_<Lanes>::Vec Vec;
  typedef typename Lanes_<Lanes>::Mask Mask;
  Vec om, quarter, tolerance;
  Mask no_sign, converged;  // a true comparison is -1 in its lane
  for (int k = 0; k < Lanes; ++k)
    om[k] = omega, quarter[k] = 0.25, tolerance[k] = tol, no_sign[k] = INT64_MAX, converged[k] = 0;
  for (const RelaxRange* range = ranges; range != ranges + n; ++range) {
    if (range->nearest > reached) continue;
    double* row = q + range->at;
    const int64_t* mask_row = relaxed + range->at;
    const double* left = other + range->at + range->shift - 1;
    const double* below = other + range->at - width;
    const double* above = other + range->at + width;
    for (int m = 0; m < range->count; m += Lanes) {
      Mask mask;
      Vec value, l, r, b, a;
      std::memcpy(&mask, mask_row + m, sizeof mask);
      std::memcpy(&value, row + m, sizeof value);
      std::memcpy(&l, left + m, sizeof l);
      std::memcpy(&r, left + m + 1, sizeof r);
      std::memcpy(&b, below + m, sizeof b);
      std::memcpy(&a, above + m, sizeof a);
      // No fused multiply-add may join this product to the subtraction below (it would round
      // once instead of twice, changing the bits): the file is compiled with -ffp-contract=off
      // (engine/control/CMakeLists.txt). AVX-512 brings FMA with it; SSE2 and plain AVX have none,
      // but the kernel must not depend on that.
      const Vec mean = quarter * (l + r + b + a);
      // The mask zeroes the change of a fixed cell: bits, not a branch.
      const Vec change = Vec(Mask(om * (mean - value)) & mask);
      const Vec next = value + change;
      std::memcpy(row + m, &next, sizeof next);
      const Vec size = Vec(Mask(change) & no_sign);  // |change|
      converged -= Mask(size < tolerance * next) & mask;
    }
  }
  int total = 0;
  for (int l = 0; l < Lanes; ++l) total += int(converged[l]);
  return total;
}

#define ROGER_RELAX_PARAMS                                                                   \
  double *__restrict q, const int64_t *__restrict relaxed, const double *other, int64_t width, \
      const RelaxRange *ranges, int n, int64_t reached, double omega, double tol
#define ROGER_RELAX_ARGS q, relaxed, other, width, ranges, n, reached, omega, tol

int relax_2(ROGER_RELAX_PARAMS) { return relax_lanes<2>(ROGER_RELAX_ARGS); }

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define ROGER_WIDE_KERNELS 1
__attribute__((target("avx"))) int relax_4(ROGER_RELAX_PARAMS) {
  return relax_lanes<4>(ROGER_RELAX_ARGS);
}
__attribute__((target("avx512f"))) int relax_8(ROGER_RELAX_PARAMS) {
  return relax_lanes<8>(ROGER_RELAX_ARGS);
}
#endif

}  // namespace

RelaxHalfSweep relax_kernel(int lanes) {
  if (lanes == 2) return relax_2;
#ifdef ROGER_WIDE_KERNELS
  if (lanes == 4 && __builtin_cpu_supports("avx")) return relax_4;
  if (lanes == 8 && __builtin_cpu_supports("avx512f")) return relax_8;
#endif
  return nullptr;
}

RelaxKernel widest_relax_kernel() {
  static const RelaxKernel widest = [] {
    for (int lanes : {8, 4})
      if (RelaxHalfSweep k = relax_kernel(lanes)) return RelaxKernel{k, lanes};
    return RelaxKernel{relax_kernel(2), 2};
  }();
  return widest;
}

}  // namespace planner_internal
}  // namespace roger
