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

TEST(RayOffset, NextFloatUpAndDownAreStdNextafterTowardsTheInfinities) {
    constexpr float kMin = std::numeric_limits<float>::min(), kMax = std::numeric_limits<float>::max();
    constexpr float kTiny = std::numeric_limits<float>::denorm_min();
    std::vector<float> xs = {0.0f, -0.0f, kTiny, -kTiny, kMin, -kMin, kMax, -kMax, kInfinity, -kInfinity, std::nanf(""), 1.0f, -1.0f,
                             std::nextafter(kMin, 0.0f), -std::nextafter(kMin, 0.0f), 1e7f, -3.5e-38f};
    Rng rng(3, 1);
    for (int i = 0; i < 100000; ++i) xs.push_back(std::bit_cast<float>(rng.next()));  // every sign, exponent and subnormal
    for (const float x : xs) {
        expectSameFloat(nextFloatUp(x), std::nextafter(x, kInfinity), x);
        expectSameFloat(nextFloatDown(x), std::nextafter(x, -kInfinity), x);
    }
}

}  // namespace
}  // namespace gibench
