#include "core/render/surface.h"

#include "core/render/ray_offset.h"

#include <algorithm>
#include <cmath>

namespace gibench {

vec3 triangleNormal(const Mesh& mesh, uint32_t triangle) {
    const uvec3 i = mesh.indices[triangle];
    const vec3 n = glm::cross(mesh.positions[i.y] - mesh.positions[i.x], mesh.positions[i.z] - mesh.positions[i.x]);
    const float len = glm::length(n);
    return len > 0.0f ? n / len : vec3(0.0f, 0.0f, 1.0f);
}

float triangleArea(const Mesh& mesh, uint32_t triangle) {
    const uvec3 i = mesh.indices[triangle];
    return 0.5f * glm::length(glm::cross(mesh.positions[i.y] - mesh.positions[i.x], mesh.positions[i.z] - mesh.positions[i.x]));
}

vec3 validShadingNormal(const vec3& ng, const vec3& ns, const vec3& wo) {
    const float iz = glm::dot(ng, wo);
    const float threshold = std::min(0.9f * iz, 0.01f);
    const vec3 reflected = 2.0f * glm::dot(ns, wo) * ns - wo;
    if (glm::dot(ng, reflected) >= threshold) return ns;
    // ns' = x X + z ng with X the unit tangent part of ns: the reflection's height above the
    // surface, 2 (ns'·wo) z − iz, equals the threshold where z² is a root of
    // a Z² − (a + iz t) Z + (iz + t)² / 4 = 0, a = ix² + iz², t the threshold (squaring adds a false root: check both).
    const vec3 tangent = ns - glm::dot(ns, ng) * ng;
    const float tangentLength = glm::length(tangent);
    if (!(tangentLength > 0.0f) || !(iz > 0.0f)) return ng;
    const vec3 x = tangent / tangentLength;
    const double ix = glm::dot(wo, x), izd = iz, t = threshold;
    const double a = ix * ix + izd * izd;
    const double c = a + izd * t;
    const double b = std::sqrt(std::max(0.0, ix * ix * (a - t * t)));
    vec3 best = ng;
    float bestCosine = -2.0f;
    for (const double z2 : {(c + b) / (2.0 * a), (c - b) / (2.0 * a)}) {
        if (!(z2 > 1e-5 && z2 <= 1.0 + 1e-5)) continue;
        const double z = std::sqrt(std::min(z2, 1.0));
        const vec3 candidate = glm::normalize(float(std::sqrt(std::max(0.0, 1.0 - z * z))) * x + float(z) * ng);
        const vec3 r = 2.0f * glm::dot(candidate, wo) * candidate - wo;
        // The false root leaves the reflection elsewhere; the true one puts it at the threshold up
        // to float rounding (both coincide when wo lies in the plane of ng and ns's normal).
        if (glm::dot(ng, r) < threshold * (1.0f - 1e-3f) - 1e-6f) continue;
        const float cosine = glm::dot(candidate, ns);
        if (cosine > bestCosine) {
            best = candidate;
            bestCosine = cosine;
        }
    }
    return best;
}

void setSurfaceAt(const ShadingTriangle& t, const Ray& ray, const RayHit& hit, SurfacePoint& p) {
    const float b0 = 1.0f - hit.b1 - hit.b2;
    p.mesh = hit.mesh;
    p.triangle = hit.triangle;
    p.material = t.material;
    // Interpolating the vertices is more accurate than origin + t·direction far from the eye.
    p.position = b0 * t.positions[0] + hit.b1 * t.positions[1] + hit.b2 * t.positions[2];
    p.positionError = interpolationError(b0, hit.b1, hit.b2, t.positions[0], t.positions[1], t.positions[2]);
    const vec3& ng = t.geometricNormal;
    p.frontFacing = glm::dot(ng, ray.direction) < 0.0f;
    p.geometricNormal = p.frontFacing ? ng : -ng;
    vec3 ns = p.geometricNormal;
    if (t.hasNormals) {
        const vec3 interpolated = b0 * t.normals[0] + hit.b1 * t.normals[1] + hit.b2 * t.normals[2];
        const float len = glm::length(interpolated);
        if (len > 0.0f) ns = interpolated / len;
        if (glm::dot(ns, p.geometricNormal) < 0.0f) ns = -ns;
        ns = validShadingNormal(p.geometricNormal, ns, -ray.direction);
    }
    p.shadingNormal = ns;
    p.uv = t.hasUvs ? b0 * t.uvs[0] + hit.b1 * t.uvs[1] + hit.b2 * t.uvs[2] : vec2(0.0f);
}

Color albedoAt(const Scene& scene, const SurfacePoint& p) {
    const Material& m = *p.material;
    return m.albedoTexture >= 0 ? scene.textures[m.albedoTexture].lookup(p.uv) : m.albedo;
}

}  // namespace gibench
