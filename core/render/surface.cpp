#include "core/render/surface.h"

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

SurfacePoint surfaceAt(const Scene& scene, const Ray& ray, const RayHit& hit) {
    const Mesh& mesh = scene.meshes[hit.mesh];
    const uvec3 i = mesh.indices[hit.triangle];
    const float b0 = 1.0f - hit.b1 - hit.b2;
    SurfacePoint p;
    p.mesh = hit.mesh;
    p.triangle = hit.triangle;
    p.material = &scene.materials[mesh.materials[hit.triangle]];
    // Interpolating the vertices is more accurate than origin + t·direction far from the eye.
    p.position = b0 * mesh.positions[i.x] + hit.b1 * mesh.positions[i.y] + hit.b2 * mesh.positions[i.z];
    const float normalLength = glm::length(hit.normal);
    const vec3 ng = normalLength > 0.0f ? hit.normal / normalLength : triangleNormal(mesh, hit.triangle);
    p.frontFacing = glm::dot(ng, ray.direction) < 0.0f;
    p.geometricNormal = p.frontFacing ? ng : -ng;
    vec3 ns = p.geometricNormal;
    if (!mesh.normals.empty()) {
        const vec3 interpolated = b0 * mesh.normals[i.x] + hit.b1 * mesh.normals[i.y] + hit.b2 * mesh.normals[i.z];
        const float len = glm::length(interpolated);
        if (len > 0.0f) ns = interpolated / len;
        if (glm::dot(ns, p.geometricNormal) < 0.0f) ns = -ns;
    }
    p.shadingNormal = ns;
    if (!mesh.uvs.empty()) p.uv = b0 * mesh.uvs[i.x] + hit.b1 * mesh.uvs[i.y] + hit.b2 * mesh.uvs[i.z];
    return p;
}

Color albedoAt(const Scene& scene, const SurfacePoint& p) {
    const Material& m = *p.material;
    return m.albedoTexture >= 0 ? scene.textures[m.albedoTexture].lookup(p.uv) : m.albedo;
}

}  // namespace gibench
