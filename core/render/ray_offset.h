#pragma once
// Where a ray leaving a surface starts: moved off the surface along its normal by a bound on the
// rounding error of the surface point, so that it cannot hit the surface it leaves, and by no
// more, so that shadows and contacts stay where they are.

#include "core/scene/camera.h"
#include "core/util/math.h"

#include <bit>
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
vec3 interpolationError(float b0, float b1, float b2, const vec3& v0, const vec3& v1, const vec3& v2);

// `x` moved one float towards the sign of `direction`: std::nextafter(x, ±∞) exactly (NaN and
// the infinity it moves towards stay), or x itself when direction is ±0 or NaN. Integer steps on
// the bits and selections without branches: the library call took a percent of a path's time,
// and a branch on each normal coordinate's sign was mispredicted as often as not.
inline float nextFloatTowards(float x, float direction) {
    constexpr uint32_t kInfinityBits = 0x7f800000u, kSmallestNegative = 0x80000001u;
    const uint32_t bits = std::bit_cast<uint32_t>(x), magnitude = bits & 0x7fffffffu;
    const bool up = direction > 0.0f, down = direction < 0.0f;
    const bool outward = (bits >> 31) ? down : up;  // the magnitude grows
    const uint32_t stepped = magnitude == 0 ? (down ? kSmallestNegative : 1u) : (outward ? bits + 1 : bits - 1);
    const bool stays = magnitude > kInfinityBits || (magnitude == kInfinityBits && outward) || !(up || down);
    return std::bit_cast<float>(stays ? bits : stepped);
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
ShadowRay shadowRayBetween(const vec3& from, const vec3& fromError, const vec3& fromNormal, const vec3& to, const vec3& toError,
                           const vec3& toNormal);
// From a surface point towards a light at infinity (a sun, the environment) in unit direction wi.
ShadowRay shadowRayTowards(const vec3& from, const vec3& fromError, const vec3& fromNormal, const vec3& wi);

}  // namespace gibench
