#pragma once
// Ray queries against a scene's triangles through Embree 3. Built once per run and shared by
// every method; all queries are const and thread-safe.

#include "core/render/ray_offset.h"
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

class RayTracer {
public:
    // Copies the scene's triangles into Embree; a watertight (robust) BVH so closed meshes stay
    // closed for rays through edges and vertices.
    explicit RayTracer(const Scene& scene);
    ~RayTracer();
    RayTracer(const RayTracer&) = delete;
    RayTracer& operator=(const RayTracer&) = delete;

    RayHit intersect(const Ray& ray, float tMax = kInfinity) const;
    // The closest hits of n <= kPacketSize rays traced together, each as intersect() finds it (the
    // same triangle; t and barycentrics from the same arithmetic in SIMD lanes). Packets traverse
    // faster per ray than single rays even when their rays are unrelated (docs/ground_truth.md).
    // `coherent`: the rays start close together and run nearly parallel, as a row of pixels'
    // camera rays do; Embree then traverses the BVH once for the packet (the G-buffer's camera
    // rays 1.7× faster), which costs more than lane by lane when the rays scatter (a path's later
    // bounces).
    static constexpr int kPacketSize = 8;
    void intersect(const Ray* rays, int n, RayHit* hits, bool coherent) const;
    // True when anything blocks the segment origin + t·direction for t in (0, tMax).
    bool occluded(const Ray& ray, float tMax) const;
    // occluded() of n <= kPacketSize segments traced together, into blocked[0..n). Lane by lane:
    // even a row of pixels' shadow rays to one light took 6 % less time so than traversed as one
    // coherent packet.
    void occluded(const ShadowRay* segments, int n, bool* blocked) const;

    // Raw Embree handle, for benchmarks that time Embree alone on the same scene.
    RTCScene embreeScene() const { return m_scene; }

private:
    RTCDevice m_device = nullptr;
    RTCScene m_scene = nullptr;
};

}  // namespace gibench
