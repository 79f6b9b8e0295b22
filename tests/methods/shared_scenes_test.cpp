// The third-party scenes load and render: tiny images, checked for finite, plausible light.

#include "support/render_helpers.h"

#include <gtest/gtest.h>

namespace gibench {
namespace {

// Renders a scene config at a tiny resolution and returns the mean of the total layer.
double renderMean(const std::string& sceneConfig, int width, int height) {
    Scene scene = loadSceneFile(std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/" + sceneConfig);
    CameraDesc camera = *scene.camera;
    camera.width = width;
    camera.height = height;
    const PreparedScene prepared(std::move(scene));
    Json stats;
    const LayeredImage image = test::render(prepared, camera, {{"name", "path_traced"}, {"spp", 4}}, 1, 1, &stats);
    EXPECT_EQ(stats["nonfinite_samples"], 0) << sceneConfig;
    double sum = 0.0;
    for (float v : image.find("total")->image.data) {
        EXPECT_TRUE(std::isfinite(v)) << sceneConfig;
        EXPECT_GE(v, 0.0f) << sceneConfig;
        sum += v;
    }
    return sum / double(image.find("total")->image.data.size());
}

TEST(SharedScenes, CornellBoxObjAndSponzaRenderFiniteNonBlackImages) {
    if (!std::filesystem::exists(test::sharedScenes() / "sponza-dabrovic" / "sponza.obj")) GTEST_SKIP() << "no ../shared/scenes";
    EXPECT_GT(renderMean("cornell_box_obj.json", 16, 16), 0.01);
    EXPECT_GT(renderMean("sponza.json", 24, 16), 0.01);
}

}  // namespace
}  // namespace gibench
