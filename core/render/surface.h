#pragma once
// What renderers need to know about the point a ray hit.

#include "core/render/ray_tracer.h"
#include "core/render/shading_triangles.h"
#include "core/scene/camera.h"
#include "core/scene/scene.h"

namespace gibench {

// The fields a probe lookup reads come first, in one cache line of a G-buffer texel (GBufferTexel).
struct SurfacePoint {
    vec3 position{0.0f};
    // Unit normals, both turned towards the side the ray came from: surfaces reflect on both sides.
    // Shading: the interpolated vertex normal where the mesh has them, bent towards the geometric normal
    // where needed so that the mirror reflection of the direction to the ray's origin lies above
    // the surface (validShadingNormal): the viewer is always above it, so no pixel goes black.
    vec3 shadingNormal{0.0f, 0.0f, 1.0f};
    int mesh = -1;
    uint32_t triangle = 0;
    const Material* material = nullptr;
    vec3 geometricNormal{0.0f, 0.0f, 1.0f};  // the triangle's
    vec3 positionError{0.0f};  // per coordinate, for rays leaving the point (interpolationError)
    vec2 uv{0.0f};
    // The ray arrived on the front (counter-clockwise) side: only that side emits.
    bool frontFacing = true;

    // Radiance emitted towards the ray's origin, W/(sr m^2).
    Color emitted() const { return frontFacing ? material->emission : Color(0.0f); }
};

// The point `hit` found along `ray`, from the triangle it hit, written field by field into `p`:
// a point returned whole and then assigned to a longer-lived one (a G-buffer texel's) is copied
// from the stack before its partial stores reach memory, a stall per pixel.
void setSurfaceAt(const ShadingTriangle& triangle, const Ray& ray, const RayHit& hit, SurfacePoint& p);
// The same point returned; the three forms give the same point.
inline SurfacePoint surfaceAt(const ShadingTriangle& triangle, const Ray& ray, const RayHit& hit) {
    SurfacePoint p;
    setSurfaceAt(triangle, ray, hit, p);
    return p;
}
inline SurfacePoint surfaceAt(const ShadingTriangles& triangles, const Ray& ray, const RayHit& hit) {
    return surfaceAt(triangles.at(hit.mesh, hit.triangle), ray, hit);
}
inline SurfacePoint surfaceAt(const Scene& scene, const Ray& ray, const RayHit& hit) {
    return surfaceAt(packShadingTriangle(scene, hit.mesh, hit.triangle), ray, hit);
}

// The shading normal gibench uses for an interpolated normal `ns` seen from unit direction `wo`
// at a surface of unit geometric normal `ng` (both on wo's side): `ns` itself when the mirror
// reflection of wo about it lies at least min(0.9 ng·wo, 0.01) above the surface, else the normal
// nearest ns, in the plane of ns and ng, whose reflection lies exactly that far above it
// (Keller et al. 2017, "The Iray light transport simulation and rendering system", §A.3; Cycles
// does the same). Interpolated normals can face away from a viewer the geometry faces; shading with
// them as they are leaves such pixels black (wo below the shading hemisphere).
vec3 validShadingNormal(const vec3& ng, const vec3& ns, const vec3& wo);

// Diffuse reflectance at the point: the material's texture when it has one, else its albedo.
Color albedoAt(const Scene& scene, const SurfacePoint& p);

// Unit normal of a mesh triangle by its counter-clockwise winding, and its area.
vec3 triangleNormal(const Mesh& mesh, uint32_t triangle);
float triangleArea(const Mesh& mesh, uint32_t triangle);

}  // namespace gibench
