// The probe-cache pipeline over every store: closed-form scenes, invariants, determinism.

#include "support/render_helpers.h"

#include "core/image/metrics.h"
#include "methods/probe_cache/probe_cache.h"
#include "methods/probe_cache/stores/store_table.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gibench {
namespace {

using test::camera;
using test::render;
using test::sceneFromJson;

// A store method's block with its probe spacing (cell or texel edge) in scene units.
Json storeMethod(const ProbeStoreInfo& store, double spacing) { return {{"name", store.name}, {store.spacingKey, spacing}}; }

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
        for (float v : l.image.data) ASSERT_TRUE(std::isfinite(v)) << store << " layer " << l.name;
}

TEST(ProbeCache, PlaneUnderUniformSkyReadsAlbedoTimesSkyFromTheCache) {
    // With direct light read from the cache, a plane of albedo ρ under a sky of radiance L must
    // show ρ L: every sample a probe gets is L exactly (the sky is constant), so once a probe has a
    // sample its gather is exact; the only error allowed is float rounding.
    const float albedo = 0.6f, sky = 1.5f;
    const PreparedScene prepared(sceneFromJson(test::skyLitPlane(albedo, sky, 50.0)));
    for (const ProbeStoreInfo& info : probeStoreTable()) {
        const std::string& store = info.name;
        Json stats;
        Json method = storeMethod(info, 0.5);
        method["direct_lighting"] = "cache";
        const LayeredImage image = render(prepared, camera(vec3(0, 3, 3), vec3(0, 0, 0), 32, 32, 50.0f), method, 1, 24, &stats);
        expectAllFinite(image, store);
        // Every pixel on the plane shows ρ L, but for the few that no probe reaches (an allocation
        // tile stops spawning once under 40 % of it is uncovered), which show nothing.
        const Image& total = image.find("total")->image;
        const Image& albedos = image.find("albedo")->image;
        int onPlane = 0, unreached = 0;
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x) {
                if (albedos.at(x, y, 0) != albedo) continue;
                ++onPlane;
                if (total.at(x, y, 0) == 0.0f) {
                    ++unreached;
                    continue;
                }
                EXPECT_NEAR(total.at(x, y, 0), albedo * sky, 1e-4f * albedo * sky) << store << " pixel " << x << "," << y;
            }
        EXPECT_GT(onPlane, 500) << store;
        EXPECT_EQ(unreached, stats["pixels_without_probe"].get<int>()) << store;
        EXPECT_LE(unreached, onPlane / 100) << store << " " << stats.dump();
    }
}

TEST(ProbeCache, GlossyPlaneUnderUniformSkyIntegratesTheProbesAgainstItsBsdf) {
    // A glossy plane (a strong, broad specular lobe) under a sky of radiance L reflects L times its
    // directional albedo. With direct light read from the cache, every probe holds L in every bin,
    // so the gather's quadrature of the BSDF is all that stands between the cache and the path
    // tracer's one-bounce image (independent of the cache: BSDF sampling, NEE and MIS). Treating
    // the surface as diffuse would give ρ L = 0.3 L, a fifth below it. The quadrature's own error
    // falls with the bins: on this lobe the default 5 × 5 grid reads 5.3 % high, 10 × 10 1.5 %
    // (every store alike, measured), so 10 × 10 bins within 3 %; the reference's noise over the
    // ~700 pixels is far below that.
    const float sky = 1.5f;
    const Json scene = {{"materials", {{"coated", {{"type", "glossy"}, {"albedo", 0.3}, {"specular", 0.5}, {"roughness", 0.8}}}}},
                        {"shapes", {{{"type", "quad"}, {"transform", {{"scale", 50.0}}}, {"material", "coated"}}}},
                        {"lights", {{{"type", "environment"}, {"radiance", sky}}}}};
    const PreparedScene prepared(sceneFromJson(scene));
    const CameraDesc view = camera(vec3(0, 3, 3), vec3(0, 0, 0), 32, 32, 50.0f);
    const auto [truth, truthPixels] = meanOn(render(prepared, view, {{"name", "path_traced"}, {"spp", 256}, {"max_depth", 1}}, 7), "total", 0.3f);
    ASSERT_GT(truthPixels, 500);
    ASSERT_GT(truth, 1.15 * 0.3 * sky) << "the lobe must set the glossy gather apart from a diffuse one";
    for (const ProbeStoreInfo& info : probeStoreTable()) {
        Json method = storeMethod(info, 0.5);
        method["direct_lighting"] = "cache";
        method["encoding_resolution"] = 10;
        Json stats;
        const LayeredImage image = render(prepared, view, method, 1, 24, &stats);
        expectAllFinite(image, info.name);
        const auto [total, pixels] = meanOn(image, "total", 0.3f);
        ASSERT_EQ(pixels, truthPixels) << info.name;
        // The pixels no probe reaches (under 1 %, see above) show nothing and pull the mean down.
        const double reached = 1.0 - stats["pixels_without_probe"].get<double>() / pixels;
        EXPECT_NEAR(total / reached, truth, 0.03 * truth) << info.name << " " << stats.dump();
    }
}

TEST(ProbeCache, OneBounceFurnaceConvergesToAlbedoSquaredTimesEmission) {
    // Inside a closed sphere of albedo ρ emitting Le, light that reflected exactly once before
    // reaching a point is ρ · (ρ Le): without recursive updates every probe sample is the NEE
    // estimate of ρ Le at v2, and the gather integrates it with the albedo. The probes' running
    // means are noisy (a few dozen samples per probe); averaged over the ~900 pixels on the sphere
    // the noise left is a fraction of a percent, so 2 % bounds what must be bias.
    const float albedo = 0.5f;
    const Json scene = {{"materials", {{"shell", {{"type", "diffuse"}, {"albedo", albedo}, {"emission", 1.0}}}}},
                        {"shapes", {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1.0}, {"subdivisions", 3}, {"inward", true}, {"material", "shell"}}}}};
    const PreparedScene prepared(sceneFromJson(scene));
    const double expectedIndirect = albedo * albedo;
    for (const ProbeStoreInfo& info : probeStoreTable()) {
        const std::string& store = info.name;
        Json method = storeMethod(info, 0.15);
        method["recursive_update"] = false;
        method["allocation_tile"] = 8;
        Json stats;
        const LayeredImage image = render(prepared, camera(vec3(0.1f, 0.05f, 0), vec3(0, 0, -1), 32, 32, 90.0f), method, 1, 64, &stats);
        expectAllFinite(image, store);
        const auto [indirect, count] = meanOn(image, "indirect", albedo);
        ASSERT_EQ(count, 32 * 32) << store;
        EXPECT_NEAR(indirect, expectedIndirect, 0.02 * expectedIndirect) << store << " " << stats.dump();
        EXPECT_EQ(stats["nonfinite_samples"], 0) << store;
        EXPECT_LE(stats["pixels_without_probe"].get<int>(), 10) << store;  // under 1 %: allocation leaves small holes
    }
}

TEST(ProbeCache, CornellIndirectErrorFallsOverFramesBelowOneFrameOfPathTracing) {
    // Against a 1024-spp path-traced reference, each store's indirect relMSE must fall over the
    // frames (the last frame's under half the 8th's) and end below that of a 1-spp path-traced
    // frame: after 64 frames the cache has to beat one sample per pixel of the ground truth, or it
    // is not worth its bias.
    Scene cornell = loadSceneFile(std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json");
    CameraDesc cam = *cornell.camera;
    cam.width = cam.height = 48;
    const PreparedScene prepared(std::move(cornell));
    const LayeredImage reference = render(prepared, cam, {{"name", "path_traced"}, {"spp", 1024}}, 99);
    const Image& truth = reference.find("indirect")->image;
    auto indirectError = [&](const LayeredImage& image) { return computeMetrics(image.find("indirect")->image, truth).relMse; };
    const double onePathPerPixel = indirectError(render(prepared, cam, {{"name", "path_traced"}, {"spp", 1}}, 7));
    for (const ProbeStoreInfo& info : probeStoreTable()) {
        const std::string& store = info.name;
        Json method = storeMethod(info, 0.03);
        method["allocation_tile"] = 8;
        const double early = indirectError(render(prepared, cam, method, 7, 8));
        const double late = indirectError(render(prepared, cam, method, 7, 64));
        EXPECT_LT(late, 0.5 * early) << store;
        EXPECT_LT(late, onePathPerPixel) << store << " (1-spp path tracing: " << onePathPerPixel << ")";
    }
}

TEST(ProbeCache, RestirDirectLightAgreesWithNextEventEstimation) {
    // Both estimate the same direct light; averaged over 32 frames and 1024 pixels each mean's
    // noise is ~0.3 %, and ReSTIR's reuse bias was measured at −0.1 % (tests/core/render/restir_test.cpp), so
    // 2 % separates a real error from noise.
    Scene cornell = loadSceneFile(std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json");
    CameraDesc cam = *cornell.camera;
    cam.width = cam.height = 32;
    const PreparedScene prepared(std::move(cornell));
    auto meanDirect = [&](const std::string& mode) {
        Json stats;
        const LayeredImage image = render(prepared, cam, {{"name", "mamba"}, {"direct_lighting", mode}}, 3, 32, &stats);
        EXPECT_EQ(stats["nonfinite_samples"], 0) << mode;
        double sum = 0.0;
        for (float v : image.find("direct")->image.data) sum += v;
        return sum / double(image.find("direct")->image.data.size());
    };
    const double nee = meanDirect("nee"), restir = meanDirect("restir");
    EXPECT_NEAR(restir, nee, 0.02 * nee);
}

TEST(ProbeCache, AStoreKeyThatRepeatsAPipelineKeyIsRejected) {
    // A store's "encoding" would be read by the pipeline, not the store: a clash is a programming
    // error found when the registry is built, never a silently shared key.
    static const ParamTable clashing = {{"encoding", ParamType::String, "mine", "a store's own encoding"}};
    ProbeStoreInfo clash{"clashing", "a store repeating a pipeline key", "cell_size", []() -> const ParamTable& { return clashing; }, nullptr};
    EXPECT_THROW(withPipelineParams(clash), std::logic_error);
    for (const ProbeStoreInfo& store : probeStoreTable()) EXPECT_NO_THROW(withPipelineParams(store)) << store.name;
}

TEST(ProbeCache, UpdatesPlaceProbesWhereNoneIsSoAClosedRoomKeepsTheLightOfSurfacesOffScreen) {
    // Issue 9 item 6: in the thin-wall room, seen from the lit side, a quarter of the updates
    // landed where no probe existed (surfaces off screen), so the multi-bounce light that returns
    // through them was lost: every store showed about a third of the reference's indirect light
    // (0.39 here). With allocate_at_updates those updates place probes and no update is lost;
    // the light then builds up bounce by bounce over the frames (measured after 48 frames: 0.67
    // for the grids, 0.66 cards, 0.61 hash_grid; 0.74 after 128), so the test asks for 0.55 and
    // 1.4 times what the same store shows without it. Cards capture every surface in prepare(),
    // so no update of theirs ever finds no probe: the setting changes nothing for them.
    Json scene = Json::parse(R"({
      "materials": {"wall": {"type": "diffuse", "albedo": 0.8}, "lamp": {"type": "diffuse", "albedo": 0.0, "emission": 10.0}},
      "shapes": [
        {"type": "box", "name": "room", "inward": true, "transform": {"scale": [2, 1, 1]}, "material": "wall"},
        {"type": "quad", "name": "wall_lit_side", "material": "wall", "vertices": [[-0.0005, -1, -1], [-0.0005, -1, 1], [-0.0005, 1, 1], [-0.0005, 1, -1]]},
        {"type": "quad", "name": "wall_dark_side", "material": "wall", "vertices": [[0.0005, -1, -1], [0.0005, 1, -1], [0.0005, 1, 1], [0.0005, -1, 1]]},
        {"type": "quad", "name": "lamp", "material": "lamp", "vertices": [[-1.5, 0.999, -0.5], [-0.5, 0.999, -0.5], [-0.5, 0.999, 0.5], [-1.5, 0.999, 0.5]]}
      ]})");
    const PreparedScene prepared(sceneFromJson(scene));
    const CameraDesc view = camera(vec3(-1.8f, 0, 0), vec3(0, 0, 0), 64, 64, 70.0f);
    const LayeredImage truth = render(prepared, view, {{"name", "path_traced"}, {"spp", 256}}, 7);
    const auto meanIndirect = [](const LayeredImage& image) {
        double sum = 0.0;
        for (const float v : image.find("indirect")->image.data) sum += v;
        return sum / double(image.find("indirect")->image.data.size());
    };
    const double reference = meanIndirect(truth);
    ASSERT_GT(reference, 0.3);
    for (const ProbeStoreInfo& info : probeStoreTable()) {
        double means[2];
        for (const bool placeAtUpdates : {false, true}) {
            Json method = storeMethod(info, 0.25);
            method["allocate_at_updates"] = placeAtUpdates;
            Json stats;
            const LayeredImage image = render(prepared, view, method, 1, 48, &stats);
            means[placeAtUpdates] = meanIndirect(image);
            if (placeAtUpdates) {
                EXPECT_EQ(stats["updates_without_probe"], 0) << info.name << " " << stats.dump();
            }
        }
        EXPECT_GT(means[1] / reference, 0.55) << info.name << ": probes placed at updates, against the path tracer's " << reference;
        if (info.name != "cards") {
            EXPECT_GT(means[1], 1.4 * means[0]) << info.name << ": probes only where the camera looks show " << means[0] / reference;
        }
    }
}

}  // namespace
}  // namespace gibench
