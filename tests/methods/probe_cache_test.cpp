// The probe-cache pipeline over every store: closed-form scenes, invariants, determinism.

#include "render_helpers.h"

#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <cmath>

namespace gibench {
namespace {

using test::camera;
using test::render;
using test::sceneFromJson;

const std::vector<std::string> kStores = {"mamba", "dense_grid", "cards"};

// Mean of the first channel of a layer over pixels whose first hit has albedo `albedo` (pixels
// wholly on that surface), with the count of such pixels.
std::pair<double, int> meanOn(const LayeredImage& image, const std::string& layer, float albedo) {
    const Image& values = image.find(layer)->image;
    const Image& albedos = image.find("albedo")->image;
    double sum = 0.0;
    int count = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            if (std::fabs(albedos.at(x, y, 0) - albedo) > 1e-6f) continue;
            sum += values.at(x, y, 0);
            ++count;
        }
    return {count > 0 ? sum / count : 0.0, count};
}

void expectAllFinite(const LayeredImage& image, const std::string& store) {
    for (const Layer& l : image.layers)
        for (float v : l.image.data)
            if (l.name != "depth") ASSERT_TRUE(std::isfinite(v)) << store << " layer " << l.name;
}

TEST(ProbeCache, PlaneUnderUniformSkyReadsAlbedoTimesSkyFromTheCache) {
    // With direct light read from the cache, a plane of albedo ρ under a sky of radiance L must
    // show ρ L: every sample a probe gets is L exactly (the sky is constant), so once a probe has a
    // sample its gather is exact; the only error allowed is float rounding.
    const float albedo = 0.6f, sky = 1.5f;
    const Json scene = {{"materials", {{"ground", {{"type", "diffuse"}, {"albedo", albedo}}}}},
                        {"shapes", {{{"type", "quad"}, {"transform", {{"scale", 50.0}}}, {"material", "ground"}}}},
                        {"lights", {{{"type", "environment"}, {"radiance", sky}}}}};
    const PreparedScene prepared(sceneFromJson(scene));
    for (const std::string& store : kStores) {
        Json stats;
        const LayeredImage image = render(prepared, camera(vec3(0, 3, 3), vec3(0, 0, 0), 32, 32, 50.0f),
                                          {{"name", store}, {"direct_lighting", "cache"}}, 1, 24, &stats);
        expectAllFinite(image, store);
        const auto [mean, count] = meanOn(image, "total", albedo);
        ASSERT_GT(count, 200) << store;
        EXPECT_NEAR(mean, albedo * sky, 1e-4 * albedo * sky) << store << " " << stats.dump();
    }
}

TEST(ProbeCache, FurnaceConvergesToEmissionOverOneMinusAlbedo) {
    // Inside a closed sphere of albedo ρ emitting Le the radiance is Le / (1 − ρ). NEE gives the
    // first two terms (Le + ρ Le); the cache must supply the rest, ρ² Le / (1 − ρ), through its
    // recursive updates. The cache's running means still carry their first, one-bounce-short
    // frames: with ρ = 0.5 after 48 frames that bias is under 5 % of the indirect part.
    const float albedo = 0.5f;
    const Json scene = {{"materials", {{"shell", {{"type", "diffuse"}, {"albedo", albedo}, {"emission", 1.0}}}}},
                        {"shapes", {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1.0}, {"subdivisions", 3}, {"inward", true}, {"material", "shell"}}}}};
    const PreparedScene prepared(sceneFromJson(scene));
    const double expectedIndirect = albedo * albedo / (1.0 - albedo);
    for (const std::string& store : kStores) {
        Json stats;
        const LayeredImage image = render(prepared, camera(vec3(0.1f, 0.05f, 0), vec3(0, 0, -1), 32, 32, 90.0f), {{"name", store}}, 1, 48, &stats);
        expectAllFinite(image, store);
        const auto [indirect, count] = meanOn(image, "indirect", albedo);
        ASSERT_EQ(count, 32 * 32) << store;
        EXPECT_NEAR(indirect, expectedIndirect, 0.05 * expectedIndirect) << store << " " << stats.dump();
        EXPECT_EQ(stats["nonfinite_samples"], 0) << store;
    }
}

TEST(ProbeCache, SameImageWhateverTheThreadCount) {
    Scene cornell = loadSceneFile(std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json");
    CameraDesc cam = *cornell.camera;
    cam.width = cam.height = 32;
    const PreparedScene prepared(std::move(cornell));
    for (const std::string& store : kStores) {
        LayeredImage one, two;
        {
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
            one = render(prepared, cam, {{"name", store}}, 5, 6);
        }
        {
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
            two = render(prepared, cam, {{"name", store}}, 5, 6);
        }
        EXPECT_EQ(one.find("total")->image.data, two.find("total")->image.data) << store;
    }
}

}  // namespace
}  // namespace gibench
