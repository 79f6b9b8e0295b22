#include "core/render/ray_offset.h"

#include "core/util/rng.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace gibench {
namespace {

// The same float as std::nextafter, compared by bits (NaN only by being NaN).
void expectSameFloat(float got, float expected, float x) {
    if (std::isnan(expected)) {
        EXPECT_TRUE(std::isnan(got)) << "x = " << x;
        return;
    }
    EXPECT_EQ(std::bit_cast<uint32_t>(got), std::bit_cast<uint32_t>(expected)) << "x = " << x << ": got " << got << ", expected " << expected;
}

TEST(RayOffset, NextFloatTowardsIsStdNextafterTowardsTheInfinityOfTheDirection) {
    constexpr float kMin = std::numeric_limits<float>::min(), kMax = std::numeric_limits<float>::max();
    constexpr float kTiny = std::numeric_limits<float>::denorm_min();
    std::vector<float> xs = {0.0f, -0.0f, kTiny, -kTiny, kMin, -kMin, kMax, -kMax, kInfinity, -kInfinity, std::nanf(""), 1.0f, -1.0f,
                             std::nextafter(kMin, 0.0f), -std::nextafter(kMin, 0.0f), 1e7f, -3.5e-38f};
    Rng rng(3, 1);
    for (int i = 0; i < 100000; ++i) xs.push_back(std::bit_cast<float>(rng.next()));  // every sign, exponent and subnormal
    for (const float x : xs) {
        for (const float up : {1.0f, kTiny, kInfinity, 0.3f}) expectSameFloat(nextFloatTowards(x, up), std::nextafter(x, kInfinity), x);
        for (const float down : {-1.0f, -kTiny, -kInfinity, -0.3f}) expectSameFloat(nextFloatTowards(x, down), std::nextafter(x, -kInfinity), x);
        for (const float none : {0.0f, -0.0f, std::nanf("")}) expectSameFloat(nextFloatTowards(x, none), x, x);
    }
}

TEST(RayOffset, TheOriginMovesAlongTheNormalByTheProjectedErrorAndOneFloatMore) {
    // pbrt-v4's OffsetRayOrigin written out with std::nextafter, on random points, error bounds
    // and normals with zero, negative and positive coordinates.
    Rng rng(8, 2);
    const auto coordinate = [&](float scale) { return scale * (2.0f * rng.uniform() - 1.0f); };
    for (int i = 0; i < 20000; ++i) {
        const vec3 p(coordinate(100.0f), coordinate(1.0f), coordinate(1e4f));
        const vec3 error(1e-5f * rng.uniform(), 1e-6f * rng.uniform(), 1e-3f * rng.uniform());
        vec3 n(coordinate(1.0f), i % 3 == 0 ? 0.0f : coordinate(1.0f), i % 5 == 0 ? -0.0f : coordinate(1.0f));
        n = glm::normalize(n);
        const vec3 moved = p + glm::dot(glm::abs(n), error) * n;
        const vec3 got = offsetRayOrigin(p, error, n);
        for (int a = 0; a < 3; ++a) {
            const float expected = n[a] > 0.0f ? std::nextafter(moved[a], kInfinity) : n[a] < 0.0f ? std::nextafter(moved[a], -kInfinity) : moved[a];
            expectSameFloat(got[a], expected, p[a]);
        }
    }
}

}  // namespace
}  // namespace gibench
