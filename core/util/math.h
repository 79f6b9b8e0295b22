#pragma once
// Vector types and small geometric helpers shared by every part of gibench.

#include <glm/glm.hpp>

#include <cmath>
#include <limits>

namespace gibench {

using glm::vec2;
using glm::vec3;
using glm::vec4;
using glm::ivec2;
using glm::uvec3;
using glm::mat3;
using glm::mat4;

// Linear RGB radiance, irradiance or reflectance; units depend on use and are named there.
using Color = glm::vec3;

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.31830988618379067154f;
inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

// Rec. 709 luminance of linear RGB.
inline float luminance(const Color& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

inline bool isFinite(const vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

inline float maxComponent(const vec3& v) { return glm::max(v.x, glm::max(v.y, v.z)); }

// Which of the six axis directions (±X, ±Y, ±Z) a vector faces most: 2 × axis + (1 if that
// component is negative), for the axis of largest magnitude (the lowest such axis on ties), or
// -1 for a zero vector. Probe stores key probes by it so the two sides of a wall stay apart.
inline int dominantDirection(const vec3& v) {
    const vec3 a = glm::abs(v);
    const int axis = a.x >= a.y ? (a.x >= a.z ? 0 : 2) : (a.y >= a.z ? 1 : 2);
    if (!(a[axis] > 0.0f)) return -1;
    return 2 * axis + (v[axis] < 0.0f ? 1 : 0);
}

// Orthonormal frame around a unit normal (Duff et al. 2017, "Building an Orthonormal Basis,
// Revisited"): continuous everywhere but at n.z = -1 exactly, where it stays orthonormal.
struct Frame {
    vec3 s, t, n;

    Frame() = default;
    explicit Frame(const vec3& normal) : n(normal) {
        const float sign = std::copysign(1.0f, n.z);
        const float a = -1.0f / (sign + n.z);
        const float b = n.x * n.y * a;
        s = vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
        t = vec3(b, sign + n.y * n.y * a, -n.y);
    }
    vec3 toLocal(const vec3& v) const { return vec3(glm::dot(v, s), glm::dot(v, t), glm::dot(v, n)); }
    vec3 toWorld(const vec3& v) const { return s * v.x + t * v.y + n * v.z; }
};

// Axis-aligned bounds; empty when min > max.
struct Bounds3 {
    vec3 min{kInfinity};
    vec3 max{-kInfinity};

    void extend(const vec3& p) {
        min = glm::min(min, p);
        max = glm::max(max, p);
    }
    void extend(const Bounds3& b) {
        min = glm::min(min, b.min);
        max = glm::max(max, b.max);
    }
    bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
    vec3 extent() const { return empty() ? vec3(0.0f) : max - min; }
    vec3 centre() const { return 0.5f * (min + max); }
};

}  // namespace gibench
