#include "core/render/gbuffer.h"

#include "core/util/rng.h"

#include <tbb/parallel_for.h>

namespace gibench {

void renderGBuffer(const PreparedScene& ps, const PinholeCamera& camera, uint64_t seed, uint64_t frame, GBuffer& out) {
    out.width = camera.width();
    out.height = camera.height();
    // Every texel is written by the loop below, in parallel: resize() only constructs texels on
    // the first frame (a serial reset of the whole buffer cost as much as a third of the rays).
    out.texels.resize(std::size_t(out.width) * out.height);
    tbb::parallel_for(0, out.height, [&](int y) {
        const ScopedFlushToZero flushToZero;
        for (int x = 0; x < out.width; ++x) {
            const uint64_t pixel = uint64_t(y) * out.width + x;
            Rng rng = Rng::forPath(seed, frame, pixel, RandomStream::GBuffer);
            const float jx = rng.uniform(), jy = rng.uniform();
            const Ray ray = camera.generateRay(float(x) + jx, float(y) + jy);
            GBufferTexel& t = out.texels[pixel];
            t = GBufferTexel{};
            const RayHit hit = ps.tracer.intersect(ray);
            if (!hit.found()) {
                if (ps.plan.environmentLookup) t.seen = ps.lights.environmentRadiance(ray.direction);
                continue;
            }
            t.valid = true;
            t.surface = surfaceAt(ps.triangles, ray, hit);
            t.albedo = albedoAt(ps, t.surface);
            t.wo = -ray.direction;
            t.depth = hit.t;
            t.seen = t.surface.emitted();
        }
    });
}

}  // namespace gibench
