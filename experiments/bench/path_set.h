#pragma once
// The path set the path tracer's benchmarks trace: size² pixels of a scene's view, spp paths each,
// traced as the path_traced method traces a frame (tracePixelPaths() over one 16×16 tile's paths
// of one sample index at a time).

#include "core/render/path_tracing.h"
#include "experiments/bench/bench_scenes.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace gibench {

// Traces the set; returns the rays its paths traced. makeSampler(pixel, sample) gives a path's
// numbers; `log` records every ray, if given.
template <PathSampler Sampler, typename MakeSampler>
uint64_t tracePathSet(const BenchScene& b, int size, int spp, const PathSettings& settings, MakeSampler makeSampler, RayLog* log = nullptr) {
    constexpr int kTile = 16;
    const PinholeCamera camera(b.pose(), size, size);
    uint64_t rays = 0;
    std::vector<PathResult> results;
    for (int y0 = 0; y0 < size; y0 += kTile)
        for (int x0 = 0; x0 < size; x0 += kTile)
            for (int s = 0; s < spp; ++s) {
                tracePixelPaths<Sampler>(
                    *b.scene, camera, size, x0, y0, std::min(x0 + kTile, size), std::min(y0 + kTile, size),
                    [&](uint64_t pixel) { return makeSampler(pixel, uint32_t(s)); }, settings, results, log);
                for (const PathResult& r : results) rays += r.rays;
            }
    return rays;
}

}  // namespace gibench
