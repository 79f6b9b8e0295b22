#include "core/render/gbuffer.h"

#include "core/util/rng.h"

#include <tbb/parallel_for.h>

#include <algorithm>

namespace gibench {

void renderGBuffer(const PreparedScene& ps, const PinholeCamera& camera, uint64_t seed, uint64_t frame, GBuffer& out) {
    out.width = camera.width();
    out.height = camera.height();
    // Every texel is written by the loop below, in parallel: resize() only constructs texels on
    // the first frame (a serial reset of the whole buffer cost as much as a third of the rays).
    out.texels.resize(std::size_t(out.width) * out.height);
    tbb::parallel_for(0, out.height, [&](int y) {
        const ScopedFlushToZero flushToZero;
        // A row's primary rays are coherent: traced kPacketSize at a time.
        constexpr int kPacket = RayTracer::kPacketSize;
        for (int x0 = 0; x0 < out.width; x0 += kPacket) {
            const int n = std::min(kPacket, out.width - x0);
            Ray rays[kPacket];
            RayHit hits[kPacket];
            for (int i = 0; i < n; ++i) {
                Rng rng = Rng::forPath(seed, frame, uint64_t(y) * out.width + x0 + i, RandomStream::GBuffer);
                const float jx = rng.uniform(), jy = rng.uniform();
                rays[i].origin = camera.position();
                rays[i].direction = camera.directionThrough(float(x0 + i) + jx, float(y) + jy);
            }
            ps.tracer.intersect(rays, n, hits, true);
            for (int i = 0; i < n; ++i) {
                const Ray& ray = rays[i];
                const RayHit& hit = hits[i];
                GBufferTexel& t = out.texels[std::size_t(y) * out.width + x0 + i];
                if (!hit.found()) {
                    t = GBufferTexel{};
                    if (ps.plan.environmentLookup) t.seen = ps.lights.environmentRadiance(ray.direction);
                    continue;
                }
                // Written in place, field by field (setSurfaceAt), every field of a hit's texel.
                t.valid = true;
                setSurfaceAt(ps.triangles.at(hit.mesh, hit.triangle), ray, hit, t.surface);
                t.albedo = albedoAt(ps, t.surface);
                t.wo = -ray.direction;
                t.depth = hit.t;
                t.seen = t.surface.emitted();
            }
        }
    });
}

}  // namespace gibench
