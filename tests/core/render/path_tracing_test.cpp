#include "core/render/path_tracing.h"

#include "tests/support/render_helpers.h"

#include <gtest/gtest.h>

#include <fstream>
#include <vector>

namespace gibench {
namespace {

// The Cornell box with a glossy floor, a sun (blocked by the ceiling) and a sky (seen through the
// open front): paths end on misses, at the depth limit, by Russian roulette and on failed BSDF
// samples, and vertices queue up to three shadow rays.
PreparedScene mixedCornellBox() {
    std::ifstream in(std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json");
    Json json = Json::parse(in);
    json["materials"]["white"] = {{"type", "glossy"}, {"albedo", {0.6, 0.6, 0.6}}, {"specular", 0.04}, {"roughness", 0.3}};
    json["lights"] = {{{"type", "sun"}, {"direction", {0.2, -1.0, 0.3}}, {"irradiance", 2.0}},
                      {{"type", "environment"}, {"radiance", 0.5}}};
    return PreparedScene(test::sceneFromJson(json));
}

// Paths traced together as one wavefront get, bit for bit, what each gets traced alone: the same
// random numbers, hits and additions in the same order, and the same ray counts, whatever the
// wave's size and however its paths end; the rays they count are the rays the wave traced.
// Independent and Sobol-Burley numbers, full depth and a depth limit of 3.
template <class Sampler, class MakeSampler>
void expectWaveEqualsPathsAlone(const PreparedScene& ps, int maxDepth, MakeSampler makeSampler) {
    const int size = 16;
    const PinholeCamera camera(ps.scene.camera->poseAt(0.0f).relativeTo(ps.scene.worldOrigin), size, size);
    std::vector<Sampler> samplers, alone;
    std::vector<Ray> rays;
    for (int pixel = 0; pixel < size * size; ++pixel) {
        samplers.push_back(makeSampler(uint64_t(pixel)));
        const vec2 jitter = samplers.back().cameraJitter();
        rays.push_back(camera.generateRay(float(pixel % size) + jitter.x, float(pixel / size) + jitter.y));
        alone.push_back(samplers.back());
    }
    PathSettings settings;
    settings.maxDepth = maxDepth;
    std::vector<PathResult> wave(rays.size());
    RayLog log;
    tracePaths(ps, rays.data(), samplers.data(), int(rays.size()), settings, wave.data(), &log);
    int misses = 0, bounced = 0;
    std::size_t counted = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const PathResult single = tracePath(ps, rays[i], alone[i], settings);
        const PathResult& w = wave[i];
        ASSERT_EQ(w.direct, single.direct) << "path " << i;
        ASSERT_EQ(w.indirect, single.indirect) << "path " << i;
        ASSERT_EQ(w.albedo, single.albedo) << "path " << i;
        ASSERT_EQ(w.normal, single.normal) << "path " << i;
        ASSERT_EQ(w.depth, single.depth) << "path " << i;
        ASSERT_EQ(w.rays, single.rays) << "path " << i;
        counted += w.rays;
        misses += w.depth == kInfinity;
        bounced += maxComponent(w.indirect) > 0.0f;
    }
    EXPECT_EQ(counted, log.closest.size() + log.shadow.size());
    EXPECT_GT(misses, 0);
    EXPECT_GT(bounced, int(rays.size()) / 5);
}

TEST(PathTracing, PathsTracedTogetherGetWhatEachGetsAlone) {
    const PreparedScene ps = mixedCornellBox();
    for (const int maxDepth : {3, 1024}) {
        SCOPED_TRACE("max_depth " + std::to_string(maxDepth));
        expectWaveEqualsPathsAlone<IndependentSampler>(ps, maxDepth, [](uint64_t pixel) { return IndependentSampler(Rng::forPath(7, 0, pixel, 0)); });
        expectWaveEqualsPathsAlone<SobolSampler>(ps, maxDepth, [](uint64_t pixel) { return SobolSampler(7, 0, pixel, 3); });
    }
}

}  // namespace
}  // namespace gibench
