#include "core/render/shading_triangles.h"

#include "core/render/surface.h"
#include "core/util/rng.h"

#include <gtest/gtest.h>

namespace gibench {
namespace {

// A bumpy height field with vertex normals and uvs, and a mesh with neither below it, each
// triangle with a material of its own so that a wrong index shows.
Scene twoMeshScene() {
    Rng rng(11, 12);
    Scene scene;
    const int n = 8;
    Mesh field;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x) {
            field.positions.push_back(vec3(float(x), 0.3f * rng.uniform(), float(y)));
            field.normals.push_back(glm::normalize(vec3(rng.uniform() - 0.5f, 1.0f, rng.uniform() - 0.5f)));
            field.uvs.push_back(vec2(rng.uniform(), rng.uniform()));
        }
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const uint32_t a = uint32_t(y * (n + 1) + x), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
            field.indices.push_back(uvec3(a, c, b));
            field.indices.push_back(uvec3(b, c, d));
        }
    Mesh floor;
    floor.positions = {vec3(-1, -1, -1), vec3(n + 1, -1, -1), vec3(n + 1, -1, n + 1), vec3(-1, -1, n + 1)};
    floor.indices = {uvec3(0, 2, 1), uvec3(0, 3, 2)};
    // The floor first, so that the field's records sit behind another mesh's.
    scene.meshes = {floor, field};
    for (Mesh& mesh : scene.meshes)
        for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
            mesh.materials.push_back(uint32_t(scene.materials.size()));
            scene.materials.push_back(Material{});
        }
    return scene;
}

TEST(ShadingTriangles, EveryRecordHoldsItsTrianglesVerticesAndMaterial) {
    const Scene scene = twoMeshScene();
    const ShadingTriangles triangles(scene);
    for (int m = 0; m < int(scene.meshes.size()); ++m) {
        const Mesh& mesh = scene.meshes[m];
        for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
            const ShadingTriangle& r = triangles.at(m, t);
            EXPECT_EQ(r.material, &scene.materials[mesh.materials[t]]) << "mesh " << m << " triangle " << t;
            EXPECT_EQ(r.hasNormals, !mesh.normals.empty()) << "mesh " << m;
            EXPECT_EQ(r.hasUvs, !mesh.uvs.empty()) << "mesh " << m;
            EXPECT_EQ(r.geometricNormal, triangleNormal(mesh, t)) << "mesh " << m << " triangle " << t;
            for (int k = 0; k < 3; ++k) {
                const uint32_t v = mesh.indices[t][k];
                EXPECT_EQ(r.positions[k], mesh.positions[v]) << "mesh " << m << " triangle " << t << " vertex " << k;
                if (r.hasNormals) {
                    EXPECT_EQ(r.normals[k], mesh.normals[v]) << "mesh " << m << " triangle " << t << " vertex " << k;
                }
                if (r.hasUvs) {
                    EXPECT_EQ(r.uvs[k], mesh.uvs[v]) << "mesh " << m << " triangle " << t << " vertex " << k;
                }
            }
        }
    }
}

TEST(ShadingTriangles, GiveTheSurfacePointTheMeshesGiveOnRandomHits) {
    const Scene scene = twoMeshScene();
    const ShadingTriangles triangles(scene);
    const RayTracer tracer(scene);
    Rng rng(13, 14);
    int hits[2] = {0, 0};
    for (int i = 0; i < 4000; ++i) {
        // From above and from below, so that both faces and bent shading normals come up.
        const bool below = i % 4 == 0;
        const vec3 origin(9.0f * rng.uniform() - 0.5f, below ? -0.5f : 3.0f, 9.0f * rng.uniform() - 0.5f);
        const vec3 direction = glm::normalize(vec3(rng.uniform() - 0.5f, below ? 0.3f : -1.0f, rng.uniform() - 0.5f));
        const Ray ray{origin, direction};
        const RayHit hit = tracer.intersect(ray);
        if (!hit.found()) continue;
        ++hits[hit.mesh];
        const SurfacePoint packed = surfaceAt(triangles, ray, hit);
        const SurfacePoint gathered = surfaceAt(scene, ray, hit);
        const Mesh& mesh = scene.meshes[hit.mesh];
        const uvec3 v = mesh.indices[hit.triangle];
        const float b0 = 1.0f - hit.b1 - hit.b2;
        ASSERT_EQ(packed.position, b0 * mesh.positions[v.x] + hit.b1 * mesh.positions[v.y] + hit.b2 * mesh.positions[v.z]) << "ray " << i;
        ASSERT_EQ(packed.material, &scene.materials[mesh.materials[hit.triangle]]) << "ray " << i;
        if (!mesh.uvs.empty()) {
            ASSERT_EQ(packed.uv, b0 * mesh.uvs[v.x] + hit.b1 * mesh.uvs[v.y] + hit.b2 * mesh.uvs[v.z]) << "ray " << i;
        }
        ASSERT_EQ(packed.position, gathered.position) << "ray " << i;
        ASSERT_EQ(packed.geometricNormal, gathered.geometricNormal) << "ray " << i;
        ASSERT_EQ(packed.shadingNormal, gathered.shadingNormal) << "ray " << i;
        ASSERT_EQ(packed.uv, gathered.uv) << "ray " << i;
        ASSERT_EQ(packed.material, gathered.material) << "ray " << i;
        ASSERT_EQ(packed.mesh, hit.mesh) << "ray " << i;
        ASSERT_EQ(packed.triangle, hit.triangle) << "ray " << i;
        ASSERT_EQ(packed.frontFacing, gathered.frontFacing) << "ray " << i;
        // The front is the counter-clockwise side, and the normal faces the ray's origin.
        const vec3 winding = glm::cross(mesh.positions[v.y] - mesh.positions[v.x], mesh.positions[v.z] - mesh.positions[v.x]);
        ASSERT_EQ(packed.frontFacing, glm::dot(winding, direction) < 0.0f) << "ray " << i;
        ASSERT_LT(glm::dot(packed.geometricNormal, direction), 0.0f) << "ray " << i;
        ASSERT_NEAR(glm::length(packed.geometricNormal), 1.0f, 1e-6f) << "ray " << i;
    }
    EXPECT_GT(hits[0], 100);  // the floor, through the field's gaps from above and from below
    EXPECT_GT(hits[1], 1000);
}

}  // namespace
}  // namespace gibench
