#pragma once
// Directions read from scene files, made unit length whatever their length.

#include "core/util/math.h"

#include <optional>

namespace gibench {

// `v` / |v|, computed in double: float glm::normalize() squares the components, which overflows
// to a zero vector for |v| beyond 1.8e19 and underflows to NaN below 1e-19. Null for a zero `v`.
inline std::optional<vec3> unitVector(const vec3& v) {
    const glm::dvec3 d(v);
    if (d == glm::dvec3(0.0)) return std::nullopt;
    return vec3(glm::normalize(d));
}

}  // namespace gibench
