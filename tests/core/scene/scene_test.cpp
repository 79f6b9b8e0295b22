#include "core/scene/scene.h"

#include <gtest/gtest.h>

#include <limits>

namespace gibench {
namespace {

// Rows from the top: A B / C D.
const Color kA(1, 0, 0), kB(0, 1, 0), kC(0, 0, 1), kD(1, 1, 1);

Texture twoByTwo() {
    Texture t;
    t.width = 2;
    t.height = 2;
    t.texels = {kA, kB, kC, kD};
    return t;
}

void expectColor(const Color& got, const Color& want, const vec2& uv) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-6f) << "uv " << uv.x << "," << uv.y << " channel " << c;
}

TEST(Texture, LookupAtTexelCentresReturnsTheTexelWithUvOriginBottomLeft) {
    const Texture t = twoByTwo();
    for (const auto& [uv, want] : std::vector<std::pair<vec2, Color>>{
             {{0.25f, 0.75f}, kA}, {{0.75f, 0.75f}, kB}, {{0.25f, 0.25f}, kC}, {{0.75f, 0.25f}, kD}})
        expectColor(t.lookup(uv), want, uv);
}

TEST(Texture, LookupBetweenCentresIsBilinear) {
    const Texture t = twoByTwo();
    expectColor(t.lookup({0.5f, 0.75f}), 0.5f * (kA + kB), {0.5f, 0.75f});
    expectColor(t.lookup({0.25f, 0.5f}), 0.5f * (kA + kC), {0.25f, 0.5f});
    expectColor(t.lookup({0.5f, 0.5f}), 0.25f * (kA + kB + kC + kD), {0.5f, 0.5f});
    // A quarter of the way from A's centre towards D's in both directions.
    const Color quarter = 0.75f * 0.75f * kA + 0.25f * 0.75f * kB + 0.75f * 0.25f * kC + 0.25f * 0.25f * kD;
    expectColor(t.lookup({0.375f, 0.625f}), quarter, {0.375f, 0.625f});
}

TEST(Texture, LookupWrapsAroundInBothDirections) {
    const Texture t = twoByTwo();
    // Past the left edge the filter blends the rightmost column back in.
    expectColor(t.lookup({0.0f, 0.75f}), 0.5f * (kA + kB), {0.0f, 0.75f});
    expectColor(t.lookup({0.0f, 1.0f}), 0.25f * (kA + kB + kC + kD), {0.0f, 1.0f});
    for (const vec2 shift : {vec2(1, 0), vec2(-3, 2), vec2(7, -5)}) {
        const vec2 uv = vec2(0.375f, 0.625f) + shift;
        expectColor(t.lookup(uv), t.lookup({0.375f, 0.625f}), uv);
    }
}

TEST(Scene, BoundsAndTriangleCountCoverEveryMesh) {
    Scene scene;
    EXPECT_TRUE(scene.bounds().empty());
    Mesh a;
    a.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    a.indices = {{0, 1, 2}};
    Mesh b;
    b.positions = {{-2, 5, 1}, {0, 0, 3}, {0, 1, 0}, {1, 1, 1}};
    b.indices = {{0, 1, 2}, {1, 2, 3}};
    scene.meshes = {a, b};
    EXPECT_EQ(scene.triangleCount(), 3u);
    EXPECT_EQ(scene.bounds().min, vec3(-2, 0, 0));
    EXPECT_EQ(scene.bounds().max, vec3(1, 5, 3));
}

}  // namespace
}  // namespace gibench

namespace gibench {
namespace {

TEST(Texture, LookupOfANonFiniteOrHugeUvReadsATexelNeverOutsideTheImage) {
    Texture t;
    t.width = 3;
    t.height = 2;
    t.texels = {Color(0.1f), Color(0.2f), Color(0.3f), Color(0.4f), Color(0.5f), Color(0.6f)};
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    for (const vec2 uv : {vec2(nan, 0.5f), vec2(0.5f, nan), vec2(inf, -inf), vec2(1e30f, -1e30f), vec2(-3e38f, 3e38f), vec2(1e7f, 0.3f)}) {
        const Color c = t.lookup(uv);
        EXPECT_TRUE(isFinite(c)) << "uv " << uv.x << "," << uv.y;
        EXPECT_GE(glm::min(c.x, glm::min(c.y, c.z)), 0.1f) << "uv " << uv.x << "," << uv.y;
        EXPECT_LE(maxComponent(c), 0.6f) << "uv " << uv.x << "," << uv.y;
    }
}

}  // namespace
}  // namespace gibench
