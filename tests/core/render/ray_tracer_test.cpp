#include "core/render/ray_tracer.h"

#include <gtest/gtest.h>

namespace gibench {
namespace {

// A unit quad in the plane z = zPlane (two triangles, front facing +z), placed at `offset`.
Scene quadScene(const vec3& offset, float size) {
    Scene scene;
    scene.materials.push_back(Material{});
    Mesh mesh;
    mesh.positions = {offset + vec3(-size, -size, 0), offset + vec3(size, -size, 0), offset + vec3(size, size, 0), offset + vec3(-size, size, 0)};
    mesh.indices = {uvec3(0, 1, 2), uvec3(0, 2, 3)};
    mesh.materials = {0, 0};
    scene.meshes.push_back(mesh);
    return scene;
}

TEST(RayTracer, FindsTheQuadAndMissesBesideIt) {
    const Scene scene = quadScene(vec3(0), 1.0f);
    const RayTracer tracer(scene);
    const RayHit hit = tracer.intersect({vec3(0.2f, 0.3f, 5.0f), vec3(0, 0, -1)});
    ASSERT_TRUE(hit.found());
    EXPECT_NEAR(hit.t, 5.0f, 1e-5f);
    // The hit's normal follows the counter-clockwise winding (+z here), whichever side is hit.
    EXPECT_GT(hit.normal.z, 0.0f);
    EXPECT_GT(tracer.intersect({vec3(0.2f, 0.3f, -5.0f), vec3(0, 0, 1)}).normal.z, 0.0f);
    EXPECT_FALSE(tracer.intersect({vec3(3.0f, 0.0f, 5.0f), vec3(0, 0, -1)}).found());
    EXPECT_TRUE(tracer.occluded({vec3(0, 0, 5), vec3(0, 0, -1)}, 10.0f));
    EXPECT_FALSE(tracer.occluded({vec3(0, 0, 5), vec3(0, 0, -1)}, 4.0f));
}

TEST(RayTracer, OffsetOriginsDoNotSelfIntersectAtAnyScaleOrDistance) {
    // A ray leaving the surface at a grazing angle must not hit the surface it left, whether the
    // scene is tiny, huge, or far from the origin (at 1e6 a float's spacing is 1/16, so the quad
    // there is made large enough to be representable).
    const std::vector<std::pair<float, vec3>> cases = {
        {1e-3f, vec3(0.0f)}, {1.0f, vec3(0.0f)}, {1e3f, vec3(0.0f)}, {1e2f, vec3(1e6f, -1e6f, 0.0f)}, {1e4f, vec3(-1e7f, 0.0f, 3e6f)}};
    for (const auto& [scale, offset] : cases) {
            const Scene scene = quadScene(offset, scale);
            const RayTracer tracer(scene);
            int selfHits = 0;
            for (int i = 0; i < 100; ++i) {
                const vec3 start = offset + vec3((i % 10 - 4.5f) * 0.1f * scale, (i / 10 - 4.5f) * 0.1f * scale, 0.0f);
                const RayHit down = tracer.intersect({start + vec3(0, 0, scale), vec3(0, 0, -1)});
                ASSERT_TRUE(down.found());
                const vec3 p = start + vec3(0, 0, scale) + vec3(0, 0, -1) * down.t;
                const vec3 origin = offsetRayOrigin(p, vec3(0, 0, 1));
                const vec3 grazing = glm::normalize(vec3(1.0f, 0.5f, 0.01f));
                selfHits += tracer.intersect({origin, grazing}).found();
            }
            EXPECT_EQ(selfHits, 0) << "scale " << scale << " offset " << offset.x;
        }
}

}  // namespace
}  // namespace gibench
