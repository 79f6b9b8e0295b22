#pragma once
// Where a ray leaving a surface starts: moved off the surface along its normal by a bound on the
// rounding error of the surface point, so that it cannot hit the surface it leaves, and by no
// more, so that shadows and contacts stay where they are.

#include "core/scene/camera.h"
#include "core/util/lane_select.h"
#include "core/util/math.h"

#include <bit>
#include <cmath>
#include <cstdint>

namespace gibench {

// A bound, per coordinate, on how far a point computed in float as b0 v0 + b1 v1 + b2 v2 (a hit
// or a sampled point of the triangle v0 v1 v2) may lie from the exact point, with the margin that
// Embree's float intersection needs: 2^-19 (sum of |b_j| |v_j| per coordinate, pbrt-v4's
// interpolation bound with 32x its gamma) plus 2^-30 of the triangle's largest coordinate, so that
// a point on a plane exactly at a zero coordinate still moves. Every term scales with the
// triangle: a scene scaled by 1e-6 or moved by 1e7 (after rebasing, world_origin.h) keeps its
// offsets relative to its geometry, and a large ground plane does not push a small box's shadow
// rays off by its own size.
// Inline and without branches, as the functions below: next-event estimation runs them across
// SIMD lanes (DirectLightBatch).
inline vec3 interpolationError(float b0, float b1, float b2, const vec3& v0, const vec3& v1, const vec3& v2) {
    constexpr float kInterpolation = 0x1p-19f;
    constexpr float kFloor = 0x1p-30f;
    const vec3 a0 = glm::abs(v0), a1 = glm::abs(v1), a2 = glm::abs(v2);
    const float largest = maxComponent(glm::max(a0, glm::max(a1, a2)));
    return kInterpolation * (std::fabs(b0) * a0 + std::fabs(b1) * a1 + std::fabs(b2) * a2) + vec3(kFloor * largest);
}

// `x` moved one float towards the sign of `direction`: std::nextafter(x, ±∞) exactly (NaN and
// the infinity it moves towards stay), or x itself when direction is ±0 or NaN. Integer steps on
// the bits and selections without branches: the library call took a percent of a path's time,
// and a branch on each normal coordinate's sign was mispredicted as often as not.
inline float nextFloatTowards(float x, float direction) {
    constexpr uint32_t kInfinityBits = 0x7f800000u, kSmallestNegative = 0x80000001u;
    const uint32_t bits = std::bit_cast<uint32_t>(x), magnitude = bits & 0x7fffffffu;
    const uint32_t up = laneMask(direction > 0.0f), down = laneMask(direction < 0.0f);
    const uint32_t outward = laneSelect(0u - (bits >> 31), down, up);  // the magnitude grows
    const uint32_t stepped = laneSelect(laneMask(magnitude == 0), laneSelect(down, kSmallestNegative, 1u), laneSelect(outward, bits + 1, bits - 1));
    const uint32_t stays = laneMask(magnitude > kInfinityBits) | (laneMask(magnitude == kInfinityBits) & outward) | ~(up | down);
    return std::bit_cast<float>(laneSelect(stays, bits, stepped));
}

// `p` moved along unit normal `n` by the error bound projected on it, dot(|n|, error), each
// coordinate then rounded one float further along n so that the move cannot round away
// (pbrt-v4's OffsetRayOrigin).
inline vec3 offsetRayOrigin(const vec3& p, const vec3& error, const vec3& n) {
    const vec3 out = p + glm::dot(glm::abs(n), error) * n;
    return {nextFloatTowards(out.x, n.x), nextFloatTowards(out.y, n.y), nextFloatTowards(out.z, n.z)};
}

// The segment a shadow ray tests for occluders.
struct ShadowRay {
    Ray ray;
    float tMax;
};

// From a surface point to a point on an emitter, each end moved off its own surface along its
// own normal (pbrt-v4's SpawnRayTo), so that the segment can hit neither surface. Both normals
// must face the side the segment runs on. Offsetting only the start and aiming along the original
// direction would not do: far from the origin the start moves by more than the end's margin, and
// the segment then ends beyond the emitter's plane and hits the emitter itself.
// Coincident ends give a segment of length 0 along fromNormal.
inline ShadowRay shadowRayBetween(const vec3& from, const vec3& fromError, const vec3& fromNormal, const vec3& to, const vec3& toError,
                                  const vec3& toNormal) {
    const vec3 start = offsetRayOrigin(from, fromError, fromNormal);
    const vec3 d = offsetRayOrigin(to, toError, toNormal) - start;
    const float length = glm::length(d);
    // Both ends already stand off their surfaces by their error bounds: start + direction · tMax
    // may round past the end by an ULP or two, never onto the emitter.
    const uint32_t apart = laneMask(length > 0.0f);
    const vec3 direction = d * (1.0f / length);
    return {{start, vec3(laneSelect(apart, direction.x, fromNormal.x), laneSelect(apart, direction.y, fromNormal.y),
                         laneSelect(apart, direction.z, fromNormal.z))},
            laneSelect(apart, length, 0.0f)};
}
// From a surface point towards a light at infinity (a sun, the environment) in unit direction wi.
inline ShadowRay shadowRayTowards(const vec3& from, const vec3& fromError, const vec3& fromNormal, const vec3& wi) {
    return {{offsetRayOrigin(from, fromError, fromNormal), wi}, kInfinity};
}

}  // namespace gibench
