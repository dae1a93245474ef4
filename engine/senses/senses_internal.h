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

// The image noise on one eye's image (SenseNoise::images): its colours moved by `levels` (whole
// levels) or else by `noise` (float offsets), three per pixel, on the grid of `quantum` (none when
// 0); the stimulus coverage moved by each colour's change and its mask cleaned. `wide` picks the
// kernel built for AVX2 over the one for any x86-64 processor; false where this processor has no
// AVX2 (nothing is done then). Every image goes through the wide one where it can: the two give the
// same bits, which the tests check.
bool image_noise_kernel(bool wide, EyeImage& image, const int16_t* levels, const float* noise, int quantum);
// Whether this processor runs the wide kernel.
bool wide_image_noise();

}  // namespace senses_internal
}  // namespace roger
