#pragma once
// Ray queries against a scene's triangles through Embree 3. Built once per run and shared by
// every method; all queries are const and thread-safe.

#include "core/scene/camera.h"
#include "core/scene/scene.h"

#include <embree3/rtcore.h>

namespace gibench {

// What a closest-hit query found; `mesh` < 0 means the ray escaped.
struct RayHit {
    float t = kInfinity;
    int mesh = -1;
    uint32_t triangle = 0;
    float b1 = 0.0f, b2 = 0.0f;  // barycentrics of vertices 1 and 2
    vec3 normal{0.0f};           // unnormalised geometric normal, counter-clockwise front (as Mesh winds it)

    bool found() const { return mesh >= 0; }
};

// Embree asks each tracing thread to flush denormals to zero: declare one at the top of every
// task that traces (cheap: control-register writes). The thread's previous mode comes back when
// it goes out of scope, so that code running on the same thread after a render (metrics, hash
// keys of tiny cells, tests) still sees denormals.
class ScopedFlushToZero {
public:
    ScopedFlushToZero();
    ~ScopedFlushToZero();
    ScopedFlushToZero(const ScopedFlushToZero&) = delete;
    ScopedFlushToZero& operator=(const ScopedFlushToZero&) = delete;

private:
    unsigned m_flushZero;
    unsigned m_denormalsZero;
};

// Moves a ray origin off a surface along its normal by a few float ULPs of the position, so
// the offset scales with the coordinates (Wächter & Binder, Ray Tracing Gems, ch. 6): robust
// for tiny scenes and for geometry far from the origin alike.
vec3 offsetRayOrigin(const vec3& p, const vec3& geometricNormal);

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
ShadowRay shadowRayBetween(const vec3& from, const vec3& fromNormal, const vec3& to, const vec3& toNormal);
// From a surface point towards a light at infinity (a sun, the environment) in unit direction wi.
ShadowRay shadowRayTowards(const vec3& from, const vec3& fromNormal, const vec3& wi);

class RayTracer {
public:
    // Copies the scene's triangles into Embree; a watertight (robust) BVH so closed meshes stay
    // closed for rays through edges and vertices.
    explicit RayTracer(const Scene& scene);
    ~RayTracer();
    RayTracer(const RayTracer&) = delete;
    RayTracer& operator=(const RayTracer&) = delete;

    RayHit intersect(const Ray& ray, float tMax = kInfinity) const;
    // True when anything blocks the segment origin + t·direction for t in (0, tMax).
    bool occluded(const Ray& ray, float tMax) const;

    // Raw Embree handle, for benchmarks that time Embree alone on the same scene.
    RTCScene embreeScene() const { return m_scene; }

private:
    RTCDevice m_device = nullptr;
    RTCScene m_scene = nullptr;
};

}  // namespace gibench
