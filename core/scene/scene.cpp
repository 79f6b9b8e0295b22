#include "core/scene/scene.h"

#include <cfloat>
#include <cmath>

namespace gibench {
namespace {

// Texel index of integer coordinate `i` wrapped into [0, size), for any float i.
int wrap(float i, int size) {
    const float n = float(size);
    const float r = i - n * std::floor(i / n);
    // Rounding can land r on n for tiny negative i, and far outside [0, n) when i is so large that
    // i / n is not exact; the texel is then arbitrary anyway, but must be one of the texture's.
    return r >= 0.0f && r < n ? int(r) : 0;
}

}  // namespace

Color Texture::lookup(const vec2& uv) const {
    // Texel centres sit at half-integers; v runs up while rows run down.
    // A NaN or infinite uv (interpolated from huge ones, say) reads as texel (0, 0) rather than
    // indexing outside the texels or blending in NaN.
    float x = uv.x * float(width) - 0.5f;
    float y = (1.0f - uv.y) * float(height) - 0.5f;
    if (!std::isfinite(x)) x = 0.0f;
    if (!std::isfinite(y)) y = 0.0f;
    const float x0 = std::floor(x), y0 = std::floor(y);
    const float tx = x - x0, ty = y - y0;
    const int xa = wrap(x0, width), xb = wrap(x0 + 1.0f, width);
    const int ya = wrap(y0, height), yb = wrap(y0 + 1.0f, height);
    auto at = [&](int px, int py) { return texels[std::size_t(py) * std::size_t(width) + std::size_t(px)]; };
    const Color top = glm::mix(at(xa, ya), at(xb, ya), tx);
    const Color bottom = glm::mix(at(xa, yb), at(xb, yb), tx);
    return glm::mix(top, bottom, ty);
}

bool hasZeroArea(const Mesh& mesh, std::size_t t) {
    // In double, where the cross product of float edges neither overflows nor underflows.
    const uvec3 i = mesh.indices[t];
    const glm::dvec3 a(mesh.positions[i.x]), b(mesh.positions[i.y]), c(mesh.positions[i.z]);
    return !(0.5 * glm::length(glm::cross(b - a, c - a)) >= double(FLT_MIN));
}

Bounds3 Scene::bounds() const {
    Bounds3 b;
    for (const Mesh& mesh : meshes)
        for (const vec3& p : mesh.positions) b.extend(p);
    return b;
}

std::size_t Scene::triangleCount() const {
    std::size_t n = 0;
    for (const Mesh& mesh : meshes) n += mesh.triangleCount();
    return n;
}

}  // namespace gibench
