// senses_internal.h: pieces of the painter (senses.cpp) and of the noise (noise.cpp) shared with
// their tests. Private to senses/.
#pragma once

#include <cstdint>

#include "core/spec.h"
#include "senses/senses.h"

namespace roger {
namespace senses_internal {

// The least (side -1) or greatest (side +1) of 0 and the angles atan2(y, x) of the n vectors v,
// which must lie in a cone narrower than pi (a convex polygon's vertices seen from outside it):
// to the bit what std::min or std::max over all n arc tangents gives, from 0, for the arc
// tangents of only the vertices that can be the extreme.
double extreme_angle(const Vec2* v, int n, int side);

// The widths the image noise kernel is built for: any x86-64 processor, AVX2, AVX-512 (BW, VL, DQ).
enum class NoiseWidth { kGeneric, kAvx2, kAvx512 };

// The image noise on one eye's image (SenseNoise::images): its colours moved by `levels` (whole
// levels) or else by `noise` (float offsets), three per pixel, on the grid of `quantum` (none when
// 0); the stimulus coverage moved by each colour's change and its mask cleaned. By the kernel of
// `width`; false where this processor cannot run it (nothing is done then). Every image goes
// through the widest this processor runs: all give the same bits, which the tests check.
bool image_noise_kernel(NoiseWidth width, EyeImage& image, const int16_t* levels, const float* noise, int quantum);
// The widest kernel this processor runs.
NoiseWidth widest_image_noise();

}  // namespace senses_internal
}  // namespace roger
