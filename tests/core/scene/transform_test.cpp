#include "core/scene/transform.h"

#include "core/scene/scene.h"
#include "core/util/error.h"

#include <gtest/gtest.h>

namespace gibench {
namespace {

Transform parse(const Json& block) {
    Params p(block, "scene.json", "/shapes/0/transform", "transform", &kTransformParams);
    return parseTransform(p);
}

std::string errorOf(const Json& block) {
    try {
        parse(block);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

void expectVec(const vec3& got, const vec3& want, float tolerance = 1e-5f) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], tolerance) << "component " << c;
}

TEST(Transform, AppliesScaleThenRotateThenTranslate) {
    const Transform t = parse(Json{{"scale", {2, 3, 4}}, {"rotate_deg", {0, 0, 1, 90}}, {"translate", {10, 20, 30}}});
    // (1,1,1) scales to (2,3,4); a right-handed quarter turn about +Z sends x to y: (-3,2,4).
    expectVec(t.point(vec3(1, 1, 1)), vec3(7, 22, 34));
    EXPECT_FALSE(t.flipsWinding());
}

TEST(Transform, MatrixIsReadRowMajor) {
    const Transform t = parse(Json{{"matrix", {{1, 0, 0, 5}, {0, 2, 0, 6}, {0, 0, 3, 7}, {0, 0, 0, 1}}}});
    expectVec(t.point(vec3(1, 1, 1)), vec3(6, 8, 10));
}

TEST(Transform, PlacesPointsFarAwayInDoubleSoTheyKeepTheirMillimetres) {
    // As a float, 1e7 + 0.001 is 1e7: the transform keeps what a float would round away.
    const Transform t = parse(Json{{"translate", {1e7, 0, 0}}});
    EXPECT_NEAR(t.point(vec3(0.001f, 0, 0)).x - 1e7, 0.001, 1e-9);
    Mesh mesh;
    mesh.positions = {{0.001f, 0, 0}};
    transformMesh(mesh, t, glm::dvec3(1e7, 0, 0));
    EXPECT_NEAR(mesh.positions[0].x, 0.001f, 1e-9f);
}

TEST(Transform, NormalsStayPerpendicularUnderNonUniformScale) {
    const Transform t = parse(Json{{"scale", {1, 4, 1}}, {"rotate_deg", {1, 1, 0, 30}}});
    // The plane x + y = 0 has normal (1,1,0)/sqrt(2) and contains (1,-1,0) and (0,0,1).
    const vec3 n = t.normal(glm::normalize(vec3(1, 1, 0)));
    EXPECT_NEAR(glm::length(n), 1.0f, 1e-6f);
    for (const vec3 inPlane : {vec3(1, -1, 0), vec3(0, 0, 1)})
        EXPECT_NEAR(glm::dot(glm::dvec3(n), t.point(inPlane) - t.point(vec3(0))), 0.0, 1e-5);
}

TEST(Transform, MirrorFlipsWindingSoTheFrontStaysTheFront) {
    const Transform t = parse(Json{{"scale", {-1, 1, 1}}});
    EXPECT_TRUE(t.flipsWinding());
    Mesh mesh;
    mesh.positions = {{1, 0, 0}, {2, 0, 0}, {1, 1, 0}};  // front +Z
    mesh.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    mesh.indices = {{0, 1, 2}};
    transformMesh(mesh, t, glm::dvec3(0.0));
    const uvec3 i = mesh.indices[0];
    const vec3 front = glm::cross(mesh.positions[i.y] - mesh.positions[i.x], mesh.positions[i.z] - mesh.positions[i.x]);
    EXPECT_GT(front.z, 0.0f);
    expectVec(mesh.normals[0], vec3(0, 0, 1));
    expectVec(mesh.positions[1], vec3(-2, 0, 0));
}

TEST(Transform, BadValuesAreErrorsWithTheirPointer) {
    EXPECT_EQ(errorOf(Json{{"scale", {1, 0, 1}}}),
              "scene.json: /shapes/0/transform/scale: expected a non-zero number or an array of 3 non-zero numbers, got [1,0,1]");
    EXPECT_EQ(errorOf(Json{{"rotate_deg", {0, 0, 0, 45}}}),
              "scene.json: /shapes/0/transform/rotate_deg: expected [axis_x, axis_y, axis_z, angle_deg] with a non-zero axis, got [0,0,0,45]");
    EXPECT_EQ(errorOf(Json{{"matrix", {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 1, 1}}}}),
              "scene.json: /shapes/0/transform/matrix: expected 4 rows of 4 numbers with the last row [0, 0, 0, 1], got "
              "[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,1,1]]");
    EXPECT_EQ(errorOf(Json{{"matrix", {{1, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}}}),
              "scene.json: /shapes/0/transform/matrix: expected an invertible matrix, got [[1,0,0,0],[0,0,0,0],[0,0,1,0],[0,0,0,1]]");
    EXPECT_EQ(errorOf(Json{{"matrix", {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}}, {"translate", {1, 2, 3}}}),
              "scene.json: /shapes/0/transform/matrix: expected either \"matrix\" or \"scale\"/\"rotate_deg\"/\"translate\", not both");
    EXPECT_EQ(errorOf(Json{{"rotate", {0, 1, 0, 90}}}),
              "scene.json: /shapes/0/transform/rotate: unknown key for transform (known: scale, rotate_deg, translate, matrix)");
}

}  // namespace
}  // namespace gibench
