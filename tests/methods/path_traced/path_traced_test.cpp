// The ground truth is trusted because of these tests: analytic scenes whose radiance is known in
// closed form, with tolerances derived from the renderer's own per-pixel variance.

#include "support/render_helpers.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gibench {
namespace {

using test::camera;
using test::render;
using test::sceneFromJson;

// Mean of a layer over all pixels and channels, and the standard error of that mean from the
// per-pixel variance layer (pixels are independent: var(mean) = Σ var / count²).
struct MeanAndError {
    double mean, standardError;
};

// The mean of one channel of `total` over the image and its standard error, from the per-pixel
// variance of the mean. One channel: the channels of a pixel come from the same paths, so adding
// their variances as if independent would understate the error of a mean over channels.
MeanAndError imageMean(const LayeredImage& image, int channel) {
    const Image& total = image.find("total")->image;
    const Image& variance = image.find("variance")->image;
    double sum = 0.0, varianceSum = 0.0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            sum += total.at(x, y, channel);
            varianceSum += variance.at(x, y, channel);
        }
    const double n = double(total.pixelCount());
    return {sum / n, std::sqrt(varianceSum) / n};
}

Json furnace(float albedo, float emission) {
    return {{"materials", {{"shell", {{"type", "diffuse"}, {"albedo", albedo}, {"emission", emission}}}}},
            {"shapes", {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1.0}, {"subdivisions", 3}, {"inward", true}, {"material", "shell"}}}}};
}

TEST(PathTraced, FurnaceConvergesToEmissionOverOneMinusAlbedo) {
    // Inside a closed sphere of albedo ρ that emits Le everywhere, every path sees Le at each
    // vertex and the radiance is the geometric series Le / (1 − ρ), whatever the sphere's shape.
    for (const float albedo : {0.5f, 0.9f}) {
        const PreparedScene scene(sceneFromJson(furnace(albedo, 1.0f)));
        const LayeredImage image =
            render(scene, camera(vec3(0.1f, 0.05f, 0.0f), vec3(0, 0, -1), 8, 8, 90.0f), {{"name", "path_traced"}, {"spp", 256}, {"max_depth", 65536}});
        const double expected = 1.0 / (1.0 - albedo);
        for (int c = 0; c < 3; ++c) {
            const MeanAndError m = imageMean(image, c);
            ASSERT_GT(m.standardError, 0.0);
            EXPECT_NEAR(m.mean, expected, 5.0 * m.standardError) << "albedo " << albedo << " channel " << c << " (standard error "
                                                                  << m.standardError << ")";
        }
        // Each pixel on its own, 5.5 σ of its own estimate (64 pixels × 3 channels).
        const Image& total = image.find("total")->image;
        const Image& variance = image.find("variance")->image;
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x)
                EXPECT_NEAR(total.at(x, y, 1), expected, 5.5 * std::sqrt(variance.at(x, y, 1)) + 1e-4) << "pixel " << x << "," << y;
    }
}

TEST(PathTraced, SunOnAPlaneGivesLambertsLawExactly) {
    // A plane of albedo ρ under a sun of irradiance E arriving at 60° from the normal reflects
    // L = ρ E cos 60° / π, with no other light in the scene.
    const float albedo = 0.6f, irradiance = 3.0f;
    const float theta = 60.0f * kPi / 180.0f;
    const PreparedScene scene(sceneFromJson(test::sunLitPlane(albedo, irradiance, theta)));
    const LayeredImage image = render(scene, camera(vec3(0, 2, 0.5f), vec3(0, 0, 0), 8, 8, 40.0f), {{"name", "path_traced"}, {"spp", 4}});
    const float expected = albedo * irradiance * std::cos(theta) * kInvPi;
    const Image& total = image.find("total")->image;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
            for (int c = 0; c < 3; ++c) ASSERT_NEAR(total.at(x, y, c), expected, 1e-5f * expected) << "pixel " << x << "," << y;
}

TEST(PathTraced, ConvexObjectUnderUniformSkyReflectsAlbedoTimesSky) {
    // A convex surface sees the whole sky over its hemisphere: irradiance π L, radiance ρ L. The
    // background pixels see L itself. Exercises MIS between sky sampling and BSDF sampling.
    const float albedo = 0.7f, sky = 2.0f;
    const Json json = {{"materials", {{"ball", {{"type", "diffuse"}, {"albedo", albedo}}}}},
                       {"shapes", {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1.0}, {"subdivisions", 3}, {"material", "ball"}}}},
                       {"lights", {{{"type", "environment"}, {"radiance", sky}}}}};
    const PreparedScene scene(sceneFromJson(json));
    const LayeredImage image =
        render(scene, camera(vec3(0, 0, 3), vec3(0, 0, 0), 12, 12, 60.0f), {{"name", "path_traced"}, {"spp", 128}});
    const Image& total = image.find("total")->image;
    const Image& variance = image.find("variance")->image;
    // The mean albedo tells pixels wholly on the ball (albedo) from wholly off it (0) and edges.
    const Image& firstHitAlbedo = image.find("albedo")->image;
    int onBall = 0;
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 12; ++x) {
            if (firstHitAlbedo.at(x, y, 0) == 0.0f) {
                EXPECT_FLOAT_EQ(total.at(x, y, 0), sky) << "background pixel " << x << "," << y;
                continue;
            }
            if (std::fabs(firstHitAlbedo.at(x, y, 0) - albedo) > 1e-6f) continue;
            ++onBall;
            EXPECT_NEAR(total.at(x, y, 0), albedo * sky, 5.5 * std::sqrt(variance.at(x, y, 0)) + 1e-4) << "pixel " << x << "," << y;
        }
    EXPECT_GT(onBall, 20);
}

Json cornellRun(int maxDepth) { return {{"name", "path_traced"}, {"spp", 8}, {"max_depth", maxDepth}}; }

TEST(PathTraced, DepthOneIsTheDirectLayerAndTotalIsDirectPlusIndirect) {
    Scene cornell = loadSceneFile(std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json");
    CameraDesc cam = *cornell.camera;
    cam.width = cam.height = 24;
    const PreparedScene scene(std::move(cornell));
    const LayeredImage full = render(scene, cam, cornellRun(1024));
    const LayeredImage directOnly = render(scene, cam, cornellRun(1));
    const Image& total = full.find("total")->image;
    const Image& direct = full.find("direct")->image;
    const Image& indirect = full.find("indirect")->image;
    const Image& depthOne = directOnly.find("total")->image;
    double indirectSum = 0.0;
    for (std::size_t i = 0; i < total.data.size(); ++i) {
        ASSERT_NEAR(depthOne.data[i], direct.data[i], 1e-6f * (1.0f + direct.data[i])) << "value " << i;
        ASSERT_NEAR(total.data[i], direct.data[i] + indirect.data[i], 1e-5f * (1.0f + total.data[i])) << "value " << i;
        indirectSum += indirect.data[i];
    }
    EXPECT_GT(indirectSum, 0.0);
    EXPECT_EQ(directOnly.find("indirect")->image.data, std::vector<float>(total.data.size(), 0.0f));
}

TEST(PathTraced, FramesAccumulateToTheSameImageAsOneFrameWithAllTheSamples) {
    const PreparedScene scene(sceneFromJson(furnace(0.5f, 1.0f)));
    const CameraDesc cam = camera(vec3(0.1f, 0, 0), vec3(0, 0, -1), 6, 6);
    const LayeredImage four = render(scene, cam, {{"name", "path_traced"}, {"spp", 4}}, 3, 4);
    const LayeredImage one = render(scene, cam, {{"name", "path_traced"}, {"spp", 16}}, 3, 1);
    const auto& a = four.find("total")->image.data;
    const auto& b = one.find("total")->image.data;
    for (std::size_t i = 0; i < a.size(); ++i) ASSERT_NEAR(a[i], b[i], 1e-5f * b[i]) << "value " << i;
}

}  // namespace
}  // namespace gibench
