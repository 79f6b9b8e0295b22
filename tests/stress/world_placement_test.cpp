// The same scene scaled or moved together with its camera renders the same image, for every
// method: what a pixel sees cannot depend on where the world's origin or its unit of length is.
// (Issue 8 measured the Cornell box's mean radiance falling from 0.1215 to 0.0436 when moved by
// 1e4 and to black at 1e7, and to 0.0963 when scaled by 1e-6.)

#include "support/render_helpers.h"

#include "core/image/metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

namespace gibench {
namespace {

constexpr int kSize = 32;
constexpr int kFrames = 4;

struct Placement {
    const char* name;
    double scale;
    double offset;  // added to every coordinate after scaling
};

const Placement kPlacements[] = {
    {"scaled 1e-6", 1e-6, 0.0}, {"scaled 1e-3", 1e-3, 0.0}, {"scaled 1e4", 1e4, 0.0},  {"moved 1e4", 1.0, 1e4},
    {"moved 1e6", 1.0, 1e6},    {"moved 1e7", 1.0, 1e7},    {"moved -3.3e9", 1.0, -3.3e9}, {"scaled 1e-3, moved 12345.678", 1e-3, 12345.678},
};

Json cornellJson() {
    std::ifstream in(std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json");
    return Json::parse(in);
}

// The built-in Cornell box with every shape and the camera placed by `p`: a transform per shape,
// composed in the scene file as a user would write it.
Json placed(const Placement& p) {
    Json scene = cornellJson();
    for (Json& shape : scene["shapes"]) shape["transform"] = {{"scale", p.scale}, {"translate", {p.offset, p.offset, p.offset}}};
    for (const char* key : {"eye", "target"})
        for (Json& c : scene["camera"][key]) c = c.get<double>() * p.scale + p.offset;
    return scene;
}

CameraDesc cameraOf(const PreparedScene& scene) {
    CameraDesc c = *scene.scene.camera;
    c.width = c.height = kSize;
    return c;
}

double meanOf(const Image& image) {
    double sum = 0.0;
    for (const float v : image.data) sum += v;
    return sum / double(image.data.size());
}

class EveryMethodPlaced : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryMethodPlaced, RendersTheSameImageWhereverAndHoweverLargeTheWorldIs) {
    const std::string& method = GetParam();
    const Json run = {{"name", method}};
    const PreparedScene unit(test::sceneFromJson(cornellJson()));
    const LayeredImage expected = test::render(unit, cameraOf(unit), run, 3, kFrames);
    const Image& reference = expected.find("total")->image;
    const double unitMean = meanOf(reference);
    ASSERT_GT(unitMean, 0.0);
    for (const Placement& p : kPlacements) {
        const PreparedScene scene(test::sceneFromJson(placed(p)));
        LayeredImage rendered;
        try {
            rendered = test::render(scene, cameraOf(scene), run, 3, kFrames);
        } catch (const std::exception& e) {
            ADD_FAILURE() << method << ", " << p.name << ": " << e.what();
            continue;
        }
        const Image& image = rendered.find("total")->image;
        const ImageMetrics m = computeMetrics(image, reference);
        EXPECT_EQ(m.nonfinitePixels, 0u) << method << ", " << p.name;
        // The same random numbers on the same geometry up to rounding: the images agree far more
        // closely than independent renders would (relMSE 1e-11 and means within 1e-6 measured;
        // a move by a multiple of the origin's grid gives the identical image).
        EXPECT_NEAR(meanOf(image) / unitMean, 1.0, 1e-4)
            << method << ", " << p.name << ": mean " << meanOf(image) << " against " << unitMean << ", relMSE " << m.relMse;
        EXPECT_LT(m.relMse, 1e-8) << method << ", " << p.name;
    }
}

INSTANTIATE_TEST_SUITE_P(Registry, EveryMethodPlaced, ::testing::ValuesIn(methodNames()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
}  // namespace gibench
