// senses_internal.h: a piece of the painter (senses.cpp) shared with its tests. Private to senses/.
#pragma once

#include "core/spec.h"

namespace roger {
namespace senses_internal {

// The least (side -1) or greatest (side +1) of 0 and the angles atan2(y, x) of the n vectors v,
// which must lie in a cone narrower than pi (a convex polygon's vertices seen from outside it):
// to the bit what std::min or std::max over all n arc tangents gives, from 0, for the arc
// tangents of only the vertices that can be the extreme.
double extreme_angle(const Vec2* v, int n, int side);

}  // namespace senses_internal
}  // namespace roger
