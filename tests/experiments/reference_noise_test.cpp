// The reference's noise floor (metrics.json "reference_noise") against an independent estimate:
// two path-traced images of different seeds differ, in expectation, by the sum of their floors.

#include "experiments/reference_noise.h"

#include "support/render_helpers.h"

#include "core/image/metrics.h"
#include "core/render/prepared_scene.h"

#include <gtest/gtest.h>

namespace gibench {
namespace {

TEST(ReferenceNoise, TwoSeedsDifferByTheSumOfTheirNoiseFloors) {
    const PreparedScene scene(loadSceneFile(std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json"));
    CameraDesc camera = *scene.scene.camera;
    camera.width = camera.height = 24;
    const Json method = {{"name", "path_traced"}, {"spp", 256}, {"sampler", "independent"}};
    // 576 pixels × 3 channels of a heavy-tailed difference: one pair's measured relMSE is itself
    // noisy (its ratio to the floors has a standard deviation of 0.28 over 20 pairs, from 0.69 to
    // 1.56), so the ratio is averaged over kPairs pairs of seeds: a standard error of about 0.07,
    // and the tolerance is 3.5 of those.
    constexpr int kPairs = 16;
    double sum = 0.0;
    for (int pair = 0; pair < kPairs; ++pair) {
        const uint64_t seed = 2 * uint64_t(pair) + 1;
        const LayeredImage a = test::render(scene, camera, method, seed), b = test::render(scene, camera, method, seed + 1);
        const double floors = referenceNoise(a)["total"].get<double>() + referenceNoise(b)["total"].get<double>();
        sum += computeMetrics(a.find("total")->image, b.find("total")->image).relMse / floors;
    }
    EXPECT_NEAR(sum / kPairs, 1.0, 0.25);
}

TEST(ReferenceNoise, AnImageWithoutItsVarianceHasNone) {
    LayeredImage image(4, 4);
    image.add("total", {"R", "G", "B"});
    EXPECT_TRUE(referenceNoise(image).is_null());
    image.add("variance", {"R", "G", "B"});
    EXPECT_EQ(referenceNoise(image)["total"].get<double>(), 0.0) << "a noiseless image";
}

}  // namespace
}  // namespace gibench
