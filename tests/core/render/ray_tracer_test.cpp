#include "core/render/ray_tracer.h"

#include <gtest/gtest.h>

#include <pmmintrin.h>
#include <xmmintrin.h>

#include <utility>

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

TEST(RayTracer, ShadowRaysBetweenASurfaceAndAnEmitterFacingItHitNeither) {
    // A receiving quad facing +z and an emitter quad `gap` above it facing down, as the ceiling
    // light of a Cornell box faces the top of its tall block (1.2 and 1.98 units up). Segments
    // between points of the two must reach the emitter unblocked at any height: the receiver's
    // origin offset grows with its coordinates and must not carry the segment's end through the
    // emitter's plane (the bug that darkened the tall block's top to 15 % of its direct light).
    for (const float height : {0.6f, 1.2f, 1.9f, 10.0f, 100.0f}) {
        for (const float gap : {0.78f, 0.1f}) {
            Scene scene = quadScene(vec3(0, 0, height), 1.0f);
            Scene emitter = quadScene(vec3(0, 0, height + gap), 0.3f);
            std::swap(emitter.meshes[0].indices[0].y, emitter.meshes[0].indices[0].z);  // face down
            std::swap(emitter.meshes[0].indices[1].y, emitter.meshes[0].indices[1].z);
            scene.meshes.push_back(emitter.meshes[0]);
            const RayTracer tracer(scene);
            int blocked = 0, total = 0;
            for (int i = 0; i < 11; ++i)
                for (int j = 0; j < 11; ++j)
                    for (int k = 0; k < 5; ++k) {
                        const vec3 from(-0.9f + 0.18f * float(i), -0.9f + 0.18f * float(j), height);
                        const vec3 to(-0.29f + 0.145f * float(k), 0.29f - 0.145f * float(k), height + gap);
                        const ShadowRay shadow = shadowRayBetween(from, vec3(0, 0, 1), to, vec3(0, 0, -1));
                        blocked += tracer.occluded(shadow.ray, shadow.tMax);
                        ++total;
                    }
            EXPECT_EQ(blocked, 0) << "of " << total << " segments, receiver at z = " << height << ", emitter " << gap << " above";
        }
    }
}

TEST(RayTracer, ShadowRaysStillSeeAnOccluderBetweenTheEnds) {
    Scene scene = quadScene(vec3(0, 0, 0.5f), 1.0f);
    const RayTracer tracer(scene);
    const ShadowRay shadow = shadowRayBetween(vec3(0.1f, 0.1f, 0), vec3(0, 0, 1), vec3(0, 0, 1), vec3(0, 0, -1));
    EXPECT_TRUE(tracer.occluded(shadow.ray, shadow.tMax));
    const ShadowRay escape = shadowRayTowards(vec3(3, 0, 0), vec3(0, 0, 1), vec3(0, 0, 1));
    EXPECT_FALSE(tracer.occluded(escape.ray, escape.tMax));
}

TEST(RayTracer, FlushToZeroEndsWithItsScope) {
    // A render's tasks flush denormals; the thread that ran one must see them again afterwards
    // (once left on, a later 1e-320 cell size read as 0 and took another error path).
    const unsigned before = _MM_GET_FLUSH_ZERO_MODE(), beforeDaz = _MM_GET_DENORMALS_ZERO_MODE();
    {
        const ScopedFlushToZero flushToZero;
        volatile float tiny = 1e-38f;
        EXPECT_EQ(tiny * 1e-3f, 0.0f);
    }
    EXPECT_EQ(_MM_GET_FLUSH_ZERO_MODE(), before);
    EXPECT_EQ(_MM_GET_DENORMALS_ZERO_MODE(), beforeDaz);
    volatile float tiny = 1e-38f;
    EXPECT_GT(tiny * 1e-3f, 0.0f);
}

}  // namespace
}  // namespace gibench
