#include "core/scene/camera.h"

#include "core/util/error.h"

#include <gtest/gtest.h>

namespace gibench {
namespace {

std::string errorOf(const std::string& json, const glm::dvec3& worldOrigin = glm::dvec3(0.0)) {
    try {
        Params p(Json::parse(json), "run.json", "/camera", "camera", &kCameraParams);
        parseCamera(p, worldOrigin);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

CameraDesc parse(const std::string& json) {
    Params p(Json::parse(json), "run.json", "/camera", "camera", &kCameraParams);
    return parseCamera(p, glm::dvec3(0.0));
}

bool isUnit(const vec3& v) { return isFinite(v) && std::abs(glm::length(v) - 1.0f) < 1e-6f; }

TEST(Camera, EyeBeyondWhatEmbreeTracesIsRefused) {
    EXPECT_EQ(errorOf(R"({"eye": [1e39, 0, 0], "target": [0, 0, 0]})"),
              "run.json: /camera/eye: expected an array of 3 numbers, got [1e+39,0,0] (1e+39 is too large for a float, whose "
              "magnitude is at most 3.4e38)");
    EXPECT_EQ(errorOf(R"({"eye": [0, 1e19, 0], "target": [0, 0, 0], "up": [1, 0, 0]})"),
              "run.json: /camera/eye: expected coordinates within +-9.22e+17 (beyond, Embree may reject the camera's rays), got "
              "[0,1e+19,0]");
}

TEST(Camera, PosesAreCheckedAsTheRenderersSeeThemRelativeToTheWorldOrigin) {
    // 3.3e9 units out, eye and target 1 apart round to the same float (spacing 256 there), but
    // relative to a world origin next to them they stay apart.
    const glm::dvec3 origin(0.0, 0.0, -3.3e9);
    const std::string far = R"({"eye": [0, 0, -3299999999], "target": [0, 0, -3.3e9]})";
    EXPECT_EQ(errorOf(far), "run.json: /camera/target: expected a target different from eye");
    EXPECT_EQ(errorOf(far, origin), "");
    const std::string path =
        R"({"eye": [0, 0, -3299999999], "target": [0, 0, -3.3e9], "path": [{"frame": 0, "eye": [0, 0, -3299999999], "target": [0, 0, -3.3e9]},)"
        R"( {"frame": 8, "eye": [0, 0, -3300000001], "target": [0, 0, -3.3e9]}]})";
    EXPECT_NE(errorOf(path, origin).find("keep eye and target apart, got eye == target near frame 4"), std::string::npos) << errorOf(path, origin);
}

TEST(Camera, KeyframeValuesMustFitAFloat) {
    EXPECT_EQ(errorOf(R"({"eye": [0, 0, 1], "target": [0, 0, 0], "path": [{"frame": 1e39, "eye": [0, 0, 1], "target": [0, 0, 0]}]})"),
              "run.json: /camera/path/0/frame: expected a number >= 0, got 1e+39 (too large for a float, whose magnitude is at "
              "most 3.4e38)");
    EXPECT_EQ(errorOf(R"({"eye": [0, 0, 1], "target": [0, 0, 0], "path": [{"frame": 0, "eye": [0, 0, 1], "target": [0, -1e39, 0]}]})"),
              "run.json: /camera/path/0/target: expected an array of 3 numbers, got [0,-1e+39,0] (-1e+39 is too large for a "
              "float, whose magnitude is at most 3.4e38)");
}

TEST(Camera, InterpolatedEyeMeetingTheTargetNamesBothKeyframes) {
    // The eye moves from one side of the target to the other, through it at frame 5.
    EXPECT_EQ(errorOf(R"({"eye": [0, 0, 1], "target": [0, 0, 0], "path": [
                  {"frame": 0, "eye": [0, 0, 1], "target": [0, 0, 0]},
                  {"frame": 10, "eye": [0, 0, -1], "target": [0, 0, 0]}]})"),
              "run.json: /camera/path/1: expected every pose interpolated between keyframes /camera/path/0 and /camera/path/1 to "
              "keep eye and target apart, got eye == target near frame 5");
}

TEST(Camera, InterpolatedUpAlongTheViewOrVanishingNamesBothKeyframes) {
    // Looking along -Z while up turns from +Y through -Z... to -Y: parallel to the view half way.
    EXPECT_EQ(errorOf(R"({"eye": [0, 0, 1], "target": [0, 0, 0], "path": [
                  {"frame": 2, "eye": [0, 0, 1], "target": [0, 0, 0], "up": [0, 1, -1]},
                  {"frame": 4, "eye": [0, 0, 1], "target": [0, 0, 0], "up": [0, -1, -1]}]})"),
              "run.json: /camera/path/1: expected every pose interpolated between keyframes /camera/path/0 and /camera/path/1 to "
              "keep up not parallel to the view direction, got them parallel near frame 3");
    // The view turns through the fixed up: from looking along -Z to looking along +Y... and on.
    EXPECT_EQ(errorOf(R"({"eye": [0, 0, 0], "target": [0, 0, -1], "path": [
                  {"frame": 0, "eye": [0, 0, 0], "target": [0, 1, -1]},
                  {"frame": 1, "eye": [0, 0, 0], "target": [0, 1, 1]}]})"),
              "run.json: /camera/path/1: expected every pose interpolated between keyframes /camera/path/0 and /camera/path/1 to "
              "keep up not parallel to the view direction, got them parallel near frame 0.5");
    EXPECT_EQ(errorOf(R"({"eye": [0, 0, 1], "target": [0, 0, 0], "path": [
                  {"frame": 0, "eye": [0, 0, 1], "target": [0, 0, 0], "up": [1, 0, 0]},
                  {"frame": 1, "eye": [0, 0, 1], "target": [0, 0, 0], "up": [-1, 0, 0]}]})"),
              "run.json: /camera/path/1: expected every pose interpolated between keyframes /camera/path/0 and /camera/path/1 to "
              "keep a non-zero up direction, got up == [0, 0, 0] near frame 0.5");
}

TEST(Camera, RaysCrossTheFilmAtTheAnglesOfThePinholeModel) {
    // Looking down -z with +y up and a 60° vertical field on a 64 × 32 film: the centre ray is the
    // view direction, the top edge's centre lies 30° up, the left edge's centre atan(2 tan 30°) to
    // the left, and a corner ray is (∓2 tan 30°, ±tan 30°, -1) normalised.
    const PinholeCamera camera(CameraPose{vec3(1, 2, 3), vec3(1, 2, 2), vec3(0, 1, 0), 60.0f}, 64, 32);
    const float t = std::tan(kPi / 6.0f);
    const auto expectDirection = [&](float x, float y, const vec3& expected) {
        const Ray ray = camera.generateRay(x, y);
        EXPECT_EQ(ray.origin, vec3(1, 2, 3));
        const vec3 unit = glm::normalize(expected);
        for (int a = 0; a < 3; ++a) EXPECT_NEAR(ray.direction[a], unit[a], 1e-6f) << "film (" << x << ", " << y << ") axis " << a;
    };
    expectDirection(32, 16, vec3(0, 0, -1));
    expectDirection(32, 0, vec3(0, t, -1));
    expectDirection(0, 16, vec3(-2 * t, 0, -1));
    expectDirection(64, 32, vec3(2 * t, -t, -1));
    expectDirection(0, 0, vec3(-2 * t, t, -1));
    expectDirection(16, 24, vec3(-t, -0.5f * t, -1));
}

TEST(Camera, PathsThatStayValidLoadAndGiveAUnitBasisEveryFrame) {
    // An orbit whose view passes close to (but not along) up, and a dolly far from the origin.
    const CameraDesc orbit = parse(R"({"eye": [0, 0, 1], "target": [0, 0, 0], "path": [
        {"frame": 0, "eye": [0, 0, 5], "target": [0, 0, 0]},
        {"frame": 10, "eye": [0, 5, 0.01], "target": [0, 0, 0]},
        {"frame": 20, "eye": [5, 0, 0], "target": [0, 0, 0], "up": [0, 0, 1]}]})");
    const CameraDesc far = parse(R"({"eye": [5e17, 0, 0], "target": [5e17, 0, -1e-20], "path": [
        {"frame": 0, "eye": [5e17, 5e17, 0], "target": [5e17, 5e17, -1e-20], "up": [0, 1e-30, 0]},
        {"frame": 5, "eye": [-5e17, 0, 0], "target": [-5e17, 0, -1], "up": [0, 1e30, 0]}]})");
    for (const CameraDesc* desc : {&orbit, &far})
        for (int frame = 0; frame <= 20; ++frame) {
            const PinholeCamera camera(desc->poseAt(float(frame)).relativeTo(glm::dvec3(0.0)), 4, 4);
            EXPECT_TRUE(isUnit(camera.forward())) << "frame " << frame;
            const Ray corner = camera.generateRay(0.5f, 3.5f), opposite = camera.generateRay(3.5f, 0.5f);
            EXPECT_TRUE(isUnit(corner.direction)) << "frame " << frame;
            EXPECT_LT(glm::dot(corner.direction, opposite.direction), 0.999f) << "frame " << frame << ": the film spans an angle";
        }
}

}  // namespace
}  // namespace gibench
