// planner_sweep.cpp: the harmonic planner's relaxation kernel, most of the planner's cost. One
// kernel, instantiated for 2 (SSE2, any x86-64), 4 (AVX) and 8 (AVX-512) doubles per instruction
// and chosen at run time: each lane computes exactly what the scalar code would, operation for
// operation and in the same order, so every width gives the same bits, and a solve the same
// sweeps and the same potential, on any processor.
#include "control/planner_internal.h"

#include <climits>
#include <cstring>
#include <initializer_list>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace roger {
namespace planner_internal {
namespace {

// Vectors of `Lanes` doubles and of as many 64-bit masks (GCC and Clang vector extensions).
template <int Lanes> struct Lanes_;
template <> struct Lanes_<2> {
  typedef double Vec __attribute__((vector_size(16)));
  typedef int64_t Mask __attribute__((vector_size(16)));
};

// The slots one group of a half-sweep reads and writes: its own, and in the other colour's array
// the left neighbours (the right ones are one further), those below and those above.
struct GroupSlots {
  double* row;
  const double *left, *below, *above;
  GroupSlots(const RelaxGroup& g, double* q, const double* other, int64_t width)
      : row(q + g.at), left(other + g.at + g.shift() - 1), below(other + g.at - width), above(other + g.at + width) {}
};

// `Lanes` cells relaxed together, with vector extensions. Always inlined into a wrapper compiled
// for the instruction set of that width.
template <int Lanes>
__attribute__((always_inline)) inline int relax_lanes(double* __restrict q, const double* other, int64_t width,
                                                     const RelaxGroup* groups, int n, int64_t reached,
                                                     double omega, double tol) {
  typedef typename Lanes_<Lanes>::Vec Vec;
  typedef typename Lanes_<Lanes>::Mask Mask;
  Vec om, quarter, tolerance;
  Mask no_sign, converged, lane_bit;  // a true comparison is -1 in its lane
  for (int k = 0; k < Lanes; ++k) {
    om[k] = omega, quarter[k] = 0.25, tolerance[k] = tol, no_sign[k] = INT64_MAX, converged[k] = 0;
    lane_bit[k] = int64_t(1) << k;
  }
  for (const RelaxGroup* g = groups; g != groups + n; ++g) {
    const RelaxGroup group = *g;
    if (group.nearest() > reached) continue;
    const GroupSlots at(group, q, other, width);
    const Mask mask = ((Mask{} + int64_t(group.mask())) & lane_bit) != 0;
    Vec value, l, r, b, a;
    std::memcpy(&value, at.row, sizeof value);
    std::memcpy(&l, at.left, sizeof l);
    std::memcpy(&r, at.left + 1, sizeof r);
    std::memcpy(&b, at.below, sizeof b);
    std::memcpy(&a, at.above, sizeof a);
    // No fused multiply-add may join this product to the subtraction below (it would round
    // once instead of twice, changing the bits): the file is compiled with -ffp-contract=off
    // (engine/control/CMakeLists.txt).
    const Vec mean = quarter * (l + r + b + a);
    // The mask zeroes the change of a fixed cell: bits, not a branch.
    const Vec change = Vec(Mask(om * (mean - value)) & mask);
    const Vec next = value + change;
    std::memcpy(at.row, &next, sizeof next);
    const Vec size = Vec(Mask(change) & no_sign);  // |change|
    converged -= Mask(size < tolerance * next) & mask;
  }
  int total = 0;
  for (int l = 0; l < Lanes; ++l) total += int(converged[l]);
  return total;
}

#define ROGER_RELAX_PARAMS                                                                              \
  double *__restrict q, const double *other, int64_t width, const RelaxGroup *groups, int n, int64_t reached, \
      double omega, double tol
#define ROGER_RELAX_ARGS q, other, width, groups, n, reached, omega, tol

int relax_2(ROGER_RELAX_PARAMS) { return relax_lanes<2>(ROGER_RELAX_ARGS); }

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define ROGER_WIDE_KERNELS 1
// Four cells at once with AVX, which has no 256-bit integer operations: relax_lanes<4> built the
// lane mask and counted converged cells with scalar moves and 128-bit halves (about 25 of the
// kernel's 50 instructions per four cells). Here the mask is one load from a table of the 16
// patterns, and the converged cells are counted in doubles (exact far beyond any grid's size):
// the floating-point operations are those of relax_lanes, in the same order, so the bits are the
// narrower kernels'.
struct LaneMasks4 {
  alignas(32) int64_t lanes[16][4];
  constexpr LaneMasks4() : lanes{} {
    for (int b = 0; b < 16; ++b)
      for (int k = 0; k < 4; ++k) lanes[b][k] = (b >> k) & 1 ? -1 : 0;
  }
};
constexpr LaneMasks4 kLaneMasks4;

__attribute__((target("avx"))) int relax_4(ROGER_RELAX_PARAMS) {
  const __m256d om = _mm256_set1_pd(omega), quarter = _mm256_set1_pd(0.25), tolerance = _mm256_set1_pd(tol);
  const __m256d no_sign = _mm256_castsi256_pd(_mm256_set1_epi64x(INT64_MAX)), one = _mm256_set1_pd(1.0);
  __m256d counts = _mm256_setzero_pd();
  for (const RelaxGroup* g = groups; g != groups + n; ++g) {
    const RelaxGroup group = *g;
    if (group.nearest() > reached) continue;
    const GroupSlots at(group, q, other, width);
    const __m256d mask = _mm256_load_pd(reinterpret_cast<const double*>(kLaneMasks4.lanes[group.mask() & 15]));
    __m256d value = _mm256_loadu_pd(at.row);
    __asm__("" : "+x"(value));  // one load, kept in a register (see relax_8)
    const __m256d sum = _mm256_add_pd(_mm256_add_pd(_mm256_add_pd(_mm256_loadu_pd(at.left), _mm256_loadu_pd(at.left + 1)),
                                                    _mm256_loadu_pd(at.below)),
                                      _mm256_loadu_pd(at.above));
    const __m256d mean = _mm256_mul_pd(quarter, sum);
    const __m256d change = _mm256_and_pd(_mm256_mul_pd(om, _mm256_sub_pd(mean, value)), mask);
    const __m256d next = _mm256_add_pd(value, change);
    _mm256_storeu_pd(at.row, next);
    const __m256d size = _mm256_and_pd(change, no_sign);
    const __m256d met = _mm256_and_pd(_mm256_cmp_pd(size, _mm256_mul_pd(tolerance, next), _CMP_LT_OQ), mask);
    counts = _mm256_add_pd(counts, _mm256_and_pd(met, one));
  }
  alignas(32) double lanes[4];
  _mm256_store_pd(lanes, counts);
  return int(lanes[0]) + int(lanes[1]) + int(lanes[2]) + int(lanes[3]);
}

// Eight cells at once with AVX-512's own mask registers: the group's mask is the lane mask, and
// the same operations, in the same order, as relax_lanes. No multiply-add is formed from them
// (-ffp-contract=off, as above), so the bits are those of the narrower kernels.
__attribute__((target("avx512f"))) int relax_8(ROGER_RELAX_PARAMS) {
  const __m512d om = _mm512_set1_pd(omega), quarter = _mm512_set1_pd(0.25), tolerance = _mm512_set1_pd(tol);
  const __m512i no_sign = _mm512_set1_epi64(INT64_MAX), one = _mm512_set1_epi64(1);
  // Converged cells counted per lane and summed once at the end, as relax_lanes does: a popcount
  // per vector (mask to a general register, count, add) cost 2 to 3% of the whole 8-object
  // pipeline in `roger bench`.
  __m512i counts = _mm512_setzero_si512();
  for (const RelaxGroup* g = groups; g != groups + n; ++g) {
    const RelaxGroup group = *g;
    if (group.nearest() > reached) continue;
    const GroupSlots at(group, q, other, width);
    const __mmask8 mask = __mmask8(group.mask());
    __m512d value = _mm512_loadu_pd(at.row);
    // Left to itself the compiler reads the cell's value from memory twice (once for the
    // difference, once for the sum): the loop is bound by its loads, so it is read once.
    __asm__("" : "+v"(value));
    const __m512d sum = _mm512_add_pd(_mm512_add_pd(_mm512_add_pd(_mm512_loadu_pd(at.left), _mm512_loadu_pd(at.left + 1)),
                                                    _mm512_loadu_pd(at.below)),
                                      _mm512_loadu_pd(at.above));
    const __m512d mean = _mm512_mul_pd(quarter, sum);
    const __m512d change = _mm512_maskz_mul_pd(mask, om, _mm512_sub_pd(mean, value));
    const __m512d next = _mm512_add_pd(value, change);
    _mm512_storeu_pd(at.row, next);
    const __m512d size = _mm512_castsi512_pd(_mm512_and_si512(_mm512_castpd_si512(change), no_sign));
    const __mmask8 met = _mm512_mask_cmp_pd_mask(mask, size, _mm512_mul_pd(tolerance, next), _CMP_LT_OQ);
    counts = _mm512_mask_add_epi64(counts, met, counts, one);
  }
  int64_t lanes[8];
  _mm512_storeu_si512(lanes, counts);
  int total = 0;
  for (int64_t c : lanes) total += int(c);
  return total;
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
