// Leaving out the stages a scene does not need changes time, not results (issue 8): every method
// renders the same image bit for bit with pruning off, on scenes where each stage is left out.

#include "core/render/stage_plan.h"

#include "support/render_helpers.h"

#include <gtest/gtest.h>

#include <fstream>

namespace gibench {
namespace {

Json cornellJson() {
    std::ifstream in(std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json");
    return Json::parse(in);
}

// A lamp-lit box without environment, a sky-lit plane without emitters or textures, and a
// scene with no light at all: together they leave every stage out at least once.
std::vector<std::pair<std::string, Json>> scenes() {
    Json dark = {{"shapes", {{{"type", "box"}, {"inward", true}}}}};
    return {{"cornell", cornellJson()}, {"sky plane", test::sunLitPlane(0.5f, 2.0f, 0.4f)}, {"no light", dark}};
}

TEST(StagePlan, TheCornellBoxLeavesOutTheEnvironmentAndTextures) {
    const Scene scene = test::sceneFromJson(cornellJson());
    const Json plan = StagePlan::forScene(scene, true).manifest();
    EXPECT_EQ(plan["ran"], Json::array({"next_event_estimation"}));
    ASSERT_EQ(plan["left_out"].size(), 3u);
    EXPECT_EQ(plan["left_out"][0]["stage"], "environment_lookup");
    EXPECT_EQ(plan["left_out"][1]["stage"], "texture_lookups");
    EXPECT_EQ(plan["left_out"][2]["stage"], "glossy_lobes");
    // Pruning off runs every stage; the Lambertian box still has no glossy lobe to evaluate.
    const Json all = StagePlan::forScene(scene, false).manifest();
    ASSERT_EQ(all["left_out"].size(), 1u);
    EXPECT_EQ(all["left_out"][0]["stage"], "glossy_lobes");
    EXPECT_EQ(all["pruning"], false);
}

class EveryMethodPruned : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryMethodPruned, RendersTheSameBytesWithPruningOff) {
    for (const auto& [name, json] : scenes()) {
        const PreparedScene pruned(test::sceneFromJson(json), true);
        const PreparedScene full(test::sceneFromJson(json), false);
        const CameraDesc camera = pruned.scene.camera ? [&] {
            CameraDesc c = *pruned.scene.camera;
            c.width = c.height = 16;
            return c;
        }()
                                                       : test::camera(vec3(0, 0.8f, 0.9f), vec3(0, 0, 0), 16, 16);
        const LayeredImage a = test::render(pruned, camera, {{"name", GetParam()}}, 3, 2);
        const LayeredImage b = test::render(full, camera, {{"name", GetParam()}}, 3, 2);
        ASSERT_EQ(a.layers.size(), b.layers.size());
        for (std::size_t i = 0; i < a.layers.size(); ++i)
            EXPECT_EQ(a.layers[i].image.data, b.layers[i].image.data) << name << ", layer " << a.layers[i].name;
    }
}

INSTANTIATE_TEST_SUITE_P(Registry, EveryMethodPruned, ::testing::ValuesIn(methodNames()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
}  // namespace gibench
