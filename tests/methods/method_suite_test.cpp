// Every registered method through the same checks (pbrt-v4's integrators_test.cpp style): a method
// added to the registry is tested here without a line of its own.

#include "support/render_helpers.h"
#include "support/temp_folder.h"

#include "experiments/run.h"

#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <cmath>
#include <fstream>

namespace gibench {
namespace {

std::string cornellScene() { return std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json"; }

// A few frames of the Cornell box at 24 × 24: enough for a cache to place and update probes.
constexpr int kSize = 24;
constexpr int kFrames = 3;

const PreparedScene& cornell() {
    static const PreparedScene scene(loadSceneFile(cornellScene()));
    return scene;
}

CameraDesc cornellCamera() {
    CameraDesc c = *cornell().scene.camera;
    c.width = c.height = kSize;
    return c;
}

// The last of kFrames frames with the method's defaults, on at most `threads` threads.
LayeredImage renderDefaults(const MethodInfo& method, int threads) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    return test::render(cornell(), cornellCamera(), {{"name", method.name}}, 11, kFrames);
}

class EveryMethod : public ::testing::TestWithParam<MethodInfo> {};

TEST_P(EveryMethod, DefaultsBuildAndEveryKeyOfTheTableIsRead) {
    const MethodInfo& method = GetParam();
    Params params(Json::object(), "cfg.json", "/method", "method \"" + method.name + "\"", &method.parameters);
    ASSERT_NE(method.create(params), nullptr);
    params.finish();
    const Json resolved = params.resolved();
    ASSERT_EQ(resolved.size(), method.parameters.size()) << resolved.dump();
    for (const ParamSpec& spec : method.parameters) EXPECT_EQ(resolved.at(spec.name), spec.defaultValue) << spec.name;
}

TEST_P(EveryMethod, ResolvedParametersRoundTripThroughTheManifest) {
    // The manifest's method block builds the same method again: its resolved parameters are the
    // ones the run used, and they render the same image.
    const MethodInfo& method = GetParam();
    TempFolder dir;
    const Json config = {{"experiment", "suite"},
                         {"run", method.name},
                         {"scene", cornellScene()},
                         {"camera", {{"resolution", {kSize, kSize}}}},
                         {"frames", kFrames},
                         {"seed", 11},
                         {"threads", 1},
                         {"method", {{"name", method.name}}},
                         {"output", {{"root", (dir / "results").string()}, {"png", false}}}};
    std::ofstream(dir / "run.json") << config.dump(2);
    RunConfig run = loadRunConfig(dir / "run.json");
    const RunResult result = executeRun(run, false);
    Json manifest;
    std::ifstream(result.directory / "manifest.json") >> manifest;
    Json block = manifest.at("config").at("method");
    ASSERT_EQ(block.at("name"), method.name);
    block.erase("name");
    Params again(block, "manifest.json", "/config/method", "method \"" + method.name + "\"", &method.parameters);
    method.create(again);
    again.finish();
    EXPECT_EQ(again.resolved(), block);

    block["name"] = method.name;
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    const LayeredImage rebuilt = test::render(cornell(), cornellCamera(), block, 11, kFrames);
    const LayeredImage written = readLayeredImage(result.directory / "image.exr");
    EXPECT_EQ(rebuilt.find("total")->image.data, written.find("total")->image.data);
}

TEST_P(EveryMethod, TinyRenderIsFiniteAndLit) {
    const LayeredImage image = renderDefaults(GetParam(), 2);
    for (const char* layer : {"total", "direct", "indirect", "albedo", "normal", "depth"}) ASSERT_NE(image.find(layer), nullptr) << layer;
    for (const Layer& l : image.layers)
        for (float v : l.image.data) ASSERT_TRUE(std::isfinite(v)) << "layer " << l.name;
    double total = 0.0;
    for (float v : image.find("total")->image.data) total += v;
    EXPECT_GT(total, 0.0);
}

TEST_P(EveryMethod, EveryLayerIsFiniteWhereTheCameraSeesNoSurface) {
    // A quad under a sky, seen so that half the pixels see only the sky: depth was +inf there.
    const PreparedScene scene(test::sceneFromJson(test::sunLitPlane(0.5f, 2.0f, 0.3f)));
    const LayeredImage image = test::render(scene, test::camera(vec3(0, 1, 0), vec3(0, 1, -5), 8, 8, 60.0f), {{"name", GetParam().name}}, 1, 2);
    for (const Layer& l : image.layers)
        for (float v : l.image.data) ASSERT_TRUE(std::isfinite(v)) << "layer " << l.name;
    EXPECT_EQ(image.find("depth")->image.at(4, 0, 0), 0.0f) << "a pixel that sees the sky has no surface: depth 0";
    EXPECT_GT(image.find("depth")->image.at(4, 7, 0), 0.0f) << "a pixel that sees the plane";
}

TEST_P(EveryMethod, OneAndTwoThreadsGiveTheSameBytes) {
    const LayeredImage one = renderDefaults(GetParam(), 1);
    const LayeredImage two = renderDefaults(GetParam(), 2);
    ASSERT_EQ(one.layers.size(), two.layers.size());
    for (std::size_t i = 0; i < one.layers.size(); ++i) {
        EXPECT_EQ(one.layers[i].name, two.layers[i].name);
        EXPECT_EQ(one.layers[i].image.data, two.layers[i].image.data) << "layer " << one.layers[i].name;
    }
}

INSTANTIATE_TEST_SUITE_P(Registry, EveryMethod, ::testing::ValuesIn(methodRegistry()),
                         [](const ::testing::TestParamInfo<MethodInfo>& info) { return info.param.name; });

}  // namespace
}  // namespace gibench
