// Probe state formats (issue 9: "a cheaper format, where it keeps the error within noise"): a
// bfloat16 state changes every store's image by far less than another seed does.

#include "support/render_helpers.h"

#include "core/image/metrics.h"
#include "core/util/error.h"
#include "methods/probe_cache/probe_cache.h"
#include "methods/probe_cache/stores/store_table.h"

#include <gtest/gtest.h>

namespace gibench {
namespace {

const Image& indirect(const LayeredImage& image) { return image.find("indirect")->image; }

TEST(ProbeStateFormat, BFloat16ChangesEveryStoresIndirectLightFarLessThanAnotherSeed) {
    const PreparedScene scene(loadSceneFile(std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json"));
    CameraDesc camera = *scene.scene.camera;
    camera.width = camera.height = 48;
    constexpr int kFrames = 64;  // two histories: the states have faded and refilled
    for (const ProbeStoreInfo& store : probeStoreTable()) {
        Json method = {{"name", store.name}, {"state_format", "float32"}};
        const LayeredImage reference = test::render(scene, camera, method, 1, kFrames);
        const LayeredImage otherSeed = test::render(scene, camera, method, 2, kFrames);
        method["state_format"] = "bfloat16";
        const LayeredImage compact = test::render(scene, camera, method, 1, kFrames);
        const ImageMetrics format = computeMetrics(indirect(compact), indirect(reference));
        const ImageMetrics seed = computeMetrics(indirect(otherSeed), indirect(reference));
        EXPECT_EQ(format.nonfinitePixels, 0u) << store.name;
        EXPECT_GT(seed.relMse, 0.0) << store.name;
        EXPECT_LT(format.relMse, 0.01 * seed.relMse) << store.name << ": relMSE of bfloat16 against float32 " << format.relMse
                                                     << ", of another seed " << seed.relMse;
        EXPECT_NEAR(format.mean / format.referenceMean, 1.0, 1e-3) << store.name << ": no drift of the mean";
    }
}

TEST(ProbeStateFormat, BFloat16WithALongHistoryIsAnInputErrorNamingTheKey) {
    Json method = {{"name", "mamba"}, {"history", int(kMaxBFloat16History) + 1}};
    try {
        test::createMethod(method);
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("state_format"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("float32"), std::string::npos) << e.what();
    }
    method["state_format"] = "float32";
    EXPECT_NO_THROW(test::createMethod(method));
    method = {{"name", "mamba"}, {"history", int(kMaxBFloat16History)}};
    EXPECT_NO_THROW(test::createMethod(method)) << "the default format at the longest history it allows";
}

}  // namespace
}  // namespace gibench
