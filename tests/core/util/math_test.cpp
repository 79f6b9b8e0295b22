#include "core/util/math.h"

#include <gtest/gtest.h>

namespace gibench {
namespace {

TEST(DominantDirection, NamesTheAxisOfLargestMagnitudeAndItsSign) {
    EXPECT_EQ(dominantDirection(vec3(1, 0.2f, -0.3f)), 0);
    EXPECT_EQ(dominantDirection(vec3(-1, 0.2f, -0.3f)), 1);
    EXPECT_EQ(dominantDirection(vec3(0.1f, 2, 0)), 2);
    EXPECT_EQ(dominantDirection(vec3(0.1f, -2, 0)), 3);
    EXPECT_EQ(dominantDirection(vec3(0, 0, 1e-30f)), 4);
    EXPECT_EQ(dominantDirection(vec3(0.5f, 0.5f, -0.9f)), 5);
}

TEST(DominantDirection, TiesGoToTheLowestAxisAndZeroHasNone) {
    EXPECT_EQ(dominantDirection(vec3(1, 1, 1)), 0);
    EXPECT_EQ(dominantDirection(vec3(0, -1, 1)), 3);
    EXPECT_EQ(dominantDirection(vec3(-1, 1, 0)), 1);
    EXPECT_EQ(dominantDirection(vec3(0)), -1);
}

TEST(DominantDirection, OppositeVectorsFaceOppositeDirections) {
    // The property probe stores rely on: the two sides of a wall never share a direction.
    for (const vec3 v : {vec3(0.3f, -0.7f, 0.2f), vec3(1, 1, 0.5f), vec3(-0.1f, 0.1f, 0.99f)}) {
        const int a = dominantDirection(v), b = dominantDirection(-v);
        EXPECT_EQ(a / 2, b / 2);
        EXPECT_NE(a, b);
    }
}

}  // namespace
}  // namespace gibench
