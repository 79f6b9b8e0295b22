#include "core/scene/primitives.h"

#include <gtest/gtest.h>

#include <map>
#include <utility>

namespace gibench {
namespace {

vec3 faceNormal(const Mesh& m, const uvec3& t) {
    return glm::normalize(glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]));
}

vec3 centroid(const Mesh& m, const uvec3& t) { return (m.positions[t.x] + m.positions[t.y] + m.positions[t.z]) / 3.0f; }

// Closed and consistently wound: every directed edge appears once and its reverse once.
void expectClosed(const Mesh& m) {
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    for (const uvec3& t : m.indices)
        for (const auto& e : {std::make_pair(t.x, t.y), std::make_pair(t.y, t.z), std::make_pair(t.z, t.x)}) ++directed[e];
    for (const auto& [edge, count] : directed) {
        EXPECT_EQ(count, 1) << "edge " << edge.first << "-" << edge.second;
        const auto reverse = directed.find({edge.second, edge.first});
        EXPECT_TRUE(reverse != directed.end() && reverse->second == 1) << "edge " << edge.first << "-" << edge.second << " has no twin";
    }
}

TEST(Primitives, UnitQuadFacesUpAndSpansMinusOneToOne) {
    const Mesh q = makeUnitQuad();
    ASSERT_EQ(q.indices.size(), 2u);
    for (const uvec3& t : q.indices) EXPECT_NEAR(faceNormal(q, t).y, 1.0f, 1e-6f);
    for (const vec3& p : q.positions) {
        EXPECT_EQ(std::abs(p.x), 1.0f);
        EXPECT_EQ(p.y, 0.0f);
        EXPECT_EQ(std::abs(p.z), 1.0f);
    }
    EXPECT_EQ(q.uvs.size(), 4u);
    EXPECT_TRUE(q.normals.empty());
}

TEST(Primitives, QuadSplitsAlongTheFirstDiagonal) {
    const Mesh q = makeQuad({vec3(0, 0, 0), vec3(1, 0, 0), vec3(1, 1, 0), vec3(0, 1, 0)});
    EXPECT_EQ(q.indices[0], uvec3(0, 1, 2));
    EXPECT_EQ(q.indices[1], uvec3(0, 2, 3));
}

TEST(Primitives, BoxFacesPointOutOrInAsAsked) {
    for (const bool inward : {false, true}) {
        const Mesh box = makeBox(inward);
        ASSERT_EQ(box.indices.size(), 12u);
        for (const vec3& p : box.positions) EXPECT_EQ(glm::max(std::abs(p.x), glm::max(std::abs(p.y), std::abs(p.z))), 1.0f);
        for (const uvec3& t : box.indices) {
            const vec3 c = centroid(box, t);
            // On a face of the cube the outward normal is the centroid's dominant axis.
            EXPECT_NEAR(glm::dot(faceNormal(box, t), c), inward ? -1.0f : 1.0f, 1e-5f) << "inward " << inward;
        }
    }
}

TEST(Primitives, SphereIsClosedWithNormalsAlongTheRadius) {
    const vec3 centre(1, -2, 3);
    for (const bool inward : {false, true}) {
        const Mesh s = makeSphere(centre, 2.0f, 2, inward);
        EXPECT_EQ(s.indices.size(), 20u * 16u);
        ASSERT_EQ(s.normals.size(), s.positions.size());
        expectClosed(s);
        const float sign = inward ? -1.0f : 1.0f;
        for (std::size_t i = 0; i < s.positions.size(); ++i) {
            EXPECT_NEAR(glm::length(s.positions[i] - centre), 2.0f, 1e-5f);
            const vec3 radial = glm::normalize(s.positions[i] - centre);
            EXPECT_NEAR(glm::dot(s.normals[i], radial), sign, 1e-5f) << "vertex " << i;
        }
        for (const uvec3& t : s.indices)
            EXPECT_GT(sign * glm::dot(faceNormal(s, t), glm::normalize(centroid(s, t) - centre)), 0.9f) << "inward " << inward;
    }
}

}  // namespace
}  // namespace gibench
