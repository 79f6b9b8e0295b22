#pragma once
// What renderers need to know about the point a ray hit.

#include "core/render/ray_tracer.h"
#include "core/scene/camera.h"
#include "core/scene/scene.h"

namespace gibench {

struct SurfacePoint {
    vec3 position{0.0f};
    // Unit normals turned towards the side the ray came from: surfaces reflect on both sides.
    vec3 geometricNormal{0.0f, 0.0f, 1.0f};
    vec3 shadingNormal{0.0f, 0.0f, 1.0f};
    vec2 uv{0.0f};
    const Material* material = nullptr;
    int mesh = -1;
    uint32_t triangle = 0;
    // The ray arrived on the front (counter-clockwise) side: only that side emits.
    bool frontFacing = true;

    // Radiance emitted towards the ray's origin, W/(sr m^2).
    Color emitted() const { return frontFacing ? material->emission : Color(0.0f); }
};

SurfacePoint surfaceAt(const Scene& scene, const Ray& ray, const RayHit& hit);

// Diffuse reflectance at the point: the material's texture when it has one, else its albedo.
Color albedoAt(const Scene& scene, const SurfacePoint& p);

// Unit normal of a mesh triangle by its counter-clockwise winding, and its area.
vec3 triangleNormal(const Mesh& mesh, uint32_t triangle);
float triangleArea(const Mesh& mesh, uint32_t triangle);

}  // namespace gibench
