#pragma once
// Selects for loops meant to run across SIMD lanes (GIBENCH_SIMD_CLONES), written as bit masks:
// GCC 12 leaves `c ? a : b` on a float comparison as a branch per lane ("control flow in loop")
// and does not vectorize the loop, even with -fno-trapping-math.

#include "core/util/math.h"

#include <bit>
#include <cstdint>

namespace gibench {

// All ones where `b`, else zero.
inline uint32_t laneMask(bool b) { return 0u - uint32_t(b); }
// `a` where `mask` is all ones, `b` where it is zero.
inline uint32_t laneSelect(uint32_t mask, uint32_t a, uint32_t b) { return (a & mask) | (b & ~mask); }
inline float laneSelect(uint32_t mask, float a, float b) {
    return std::bit_cast<float>(laneSelect(mask, std::bit_cast<uint32_t>(a), std::bit_cast<uint32_t>(b)));
}
// Coordinate by coordinate; by value, since references kept a lane loop's vectors in memory.
inline vec3 laneSelect(uint32_t mask, vec3 a, vec3 b) { return vec3(laneSelect(mask, a.x, b.x), laneSelect(mask, a.y, b.y), laneSelect(mask, a.z, b.z)); }

// Lane k of a vector kept coordinate by coordinate across N lanes, and its setter; each coordinate
// named, since a loop over them keeps the vectors of a lane loop in memory, unvectorized.
template <int N>
vec3 laneVector(const float (&c)[3][N], int k) {
    return vec3(c[0][k], c[1][k], c[2][k]);
}
template <int N>
void setLaneVector(float (&c)[3][N], int k, const vec3& v) {
    c[0][k] = v.x;
    c[1][k] = v.y;
    c[2][k] = v.z;
}

}  // namespace gibench
