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
    const LayeredImage a = test::render(scene, camera, method, 1), b = test::render(scene, camera, method, 2);
    const double floors = referenceNoise(a)["total"].get<double>() + referenceNoise(b)["total"].get<double>();
    const double measured = computeMetrics(a.find("total")->image, b.find("total")->image).relMse;
    // 576 pixels × 3 channels of a heavy-tailed difference: the measured relMSE is itself noisy.
    EXPECT_NEAR(measured / floors, 1.0, 0.25) << "measured " << measured << ", floors " << floors;
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
