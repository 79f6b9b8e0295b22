#include "core/render/ray_offset.h"

#include <bit>
#include <cmath>
#include <cstdint>

namespace gibench {

vec3 interpolationError(float b0, float b1, float b2, const vec3& v0, const vec3& v1, const vec3& v2) {
    constexpr float kInterpolation = 0x1p-19f;
    constexpr float kFloor = 0x1p-30f;
    const vec3 a0 = glm::abs(v0), a1 = glm::abs(v1), a2 = glm::abs(v2);
    const float largest = maxComponent(glm::max(a0, glm::max(a1, a2)));
    return kInterpolation * (std::fabs(b0) * a0 + std::fabs(b1) * a1 + std::fabs(b2) * a2) + vec3(kFloor * largest);
}

ShadowRay shadowRayBetween(const vec3& from, const vec3& fromError, const vec3& fromNormal, const vec3& to, const vec3& toError,
                           const vec3& toNormal) {
    const vec3 start = offsetRayOrigin(from, fromError, fromNormal);
    const vec3 d = offsetRayOrigin(to, toError, toNormal) - start;
    const float length = glm::length(d);
    if (!(length > 0.0f)) return {{start, fromNormal}, 0.0f};
    // Both ends already stand off their surfaces by their error bounds: start + direction · tMax
    // may round past the end by an ULP or two, never onto the emitter.
    return {{start, d * (1.0f / length)}, length};
}

ShadowRay shadowRayTowards(const vec3& from, const vec3& fromError, const vec3& fromNormal, const vec3& wi) {
    return {{offsetRayOrigin(from, fromError, fromNormal), wi}, kInfinity};
}

}  // namespace gibench
