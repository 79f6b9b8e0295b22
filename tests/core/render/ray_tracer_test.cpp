#include "core/render/ray_tracer.h"

#include "core/render/ray_offset.h"
#include "core/render/surface.h"

#include <glm/gtc/matrix_transform.hpp>

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
    EXPECT_FALSE(tracer.intersect({vec3(3.0f, 0.0f, 5.0f), vec3(0, 0, -1)}).found());
    EXPECT_TRUE(tracer.occluded({vec3(0, 0, 5), vec3(0, 0, -1)}, 10.0f));
    EXPECT_FALSE(tracer.occluded({vec3(0, 0, 5), vec3(0, 0, -1)}, 4.0f));
}

// The packet tests' scene: two overlapping quads, one a unit below the other.
Scene twoQuads() {
    Scene scene = quadScene(vec3(0), 1.0f);
    scene.meshes.push_back(quadScene(vec3(0.5f, 0.0f, -1.0f), 0.7f).meshes[0]);
    return scene;
}

// Rays from above aimed down at twoQuads(), some missing both, from a fixed sequence.
class DownwardRays {
public:
    explicit DownwardRays(uint32_t seed) : m_state(seed) {}
    float uniform() {
        m_state = m_state * 1664525u + 1013904223u;
        return float(m_state >> 8) / float(1u << 24);
    }
    Ray next() {
        return {vec3(3.0f * (uniform() - 0.5f), 3.0f * (uniform() - 0.5f), 4.0f),
                glm::normalize(vec3(0.6f * (uniform() - 0.5f), 0.6f * (uniform() - 0.5f), -1.0f))};
    }

private:
    uint32_t m_state;
};

// A packet finds what each of its rays finds alone, for every packet size, traversed as coherent
// or lane by lane: the triangle exactly, t and barycentrics to rounding (the same test in SIMD
// lanes), misses as misses; lanes past n are not written.
TEST(RayTracer, APacketOfRaysFindsWhatEachRayFindsAlone) {
    const RayTracer tracer(twoQuads());
    DownwardRays downward(7u);
    int hitsSeen = 0, missesSeen = 0;
    for (int packet = 0; packet < 200; ++packet) {
        const int n = 1 + packet % RayTracer::kPacketSize;
        Ray rays[RayTracer::kPacketSize];
        for (int i = 0; i < n; ++i) rays[i] = downward.next();
        RayHit hits[RayTracer::kPacketSize];
        if (n < RayTracer::kPacketSize) hits[n].triangle = 12345u;  // past the packet: must stay
        tracer.intersect(rays, n, hits, packet % 3 == 0);
        for (int i = 0; i < n; ++i) {
            const RayHit alone = tracer.intersect(rays[i]);
            ASSERT_EQ(hits[i].found(), alone.found()) << "packet " << packet << " lane " << i;
            if (!alone.found()) {
                ++missesSeen;
                continue;
            }
            ++hitsSeen;
            EXPECT_EQ(hits[i].mesh, alone.mesh);
            EXPECT_EQ(hits[i].triangle, alone.triangle);
            EXPECT_NEAR(hits[i].t, alone.t, 1e-6f * alone.t);
            EXPECT_NEAR(hits[i].b1, alone.b1, 1e-6f);
            EXPECT_NEAR(hits[i].b2, alone.b2, 1e-6f);
        }
        if (n < RayTracer::kPacketSize) {
            EXPECT_EQ(hits[n].triangle, 12345u) << "lane " << n << " is past the packet";
        }
    }
    EXPECT_GT(hitsSeen, 200);
    EXPECT_GT(missesSeen, 50);
}

// A packet of segments is blocked exactly where each segment alone is, for every packet size;
// entries past n are not written.
TEST(RayTracer, APacketOfSegmentsIsBlockedWhereEachSegmentAloneIs) {
    const RayTracer tracer(twoQuads());
    DownwardRays downward(11u);
    int blockedSeen = 0, clearSeen = 0;
    for (int packet = 0; packet < 200; ++packet) {
        const int n = 1 + packet % RayTracer::kPacketSize;
        ShadowRay segments[RayTracer::kPacketSize];
        for (int i = 0; i < n; ++i) {
            const Ray ray = downward.next();
            segments[i] = {ray, 7.0f * downward.uniform()};  // ends above, between or below the quads
        }
        bool blocked[RayTracer::kPacketSize + 1];
        blocked[n] = true;
        tracer.occluded(segments, n, blocked);
        for (int i = 0; i < n; ++i) {
            const bool alone = tracer.occluded(segments[i].ray, segments[i].tMax);
            ASSERT_EQ(blocked[i], alone) << "packet " << packet << " lane " << i;
            (alone ? blockedSeen : clearSeen) += 1;
        }
        EXPECT_TRUE(blocked[n]) << "entry " << n << " is past the packet";
    }
    EXPECT_GT(blockedSeen, 100);
    EXPECT_GT(clearSeen, 100);
}

// The surface point a ray from `above` along `direction` finds, with its rounding bound.
SurfacePoint pointHit(const Scene& scene, const RayTracer& tracer, const vec3& above, const vec3& direction) {
    const Ray ray{above, glm::normalize(direction)};
    const RayHit hit = tracer.intersect(ray);
    EXPECT_TRUE(hit.found());
    return surfaceAt(scene, ray, hit);
}

// Turns `scene`'s meshes by `angleDeg` about the axis (1, 1, 0) through `pivot`.
void tilt(Scene& scene, const vec3& pivot, float angleDeg) {
    const mat3 r = mat3(glm::rotate(mat4(1.0f), glm::radians(angleDeg), glm::normalize(vec3(1, 1, 0))));
    for (Mesh& mesh : scene.meshes)
        for (vec3& p : mesh.positions) p = pivot + r * (p - pivot);
}

TEST(RayTracer, OffsetOriginsDoNotSelfIntersectAtAnyScaleOrDistance) {
    // A ray leaving the surface at a grazing angle must not hit the surface it left, whether the
    // scene is tiny, huge, or far from the origin, the surface axis-aligned or tilted (at 1e6 a
    // float's spacing is 1/16, so the quad there is made large enough to be representable).
    const std::vector<std::pair<float, vec3>> cases = {{1e-6f, vec3(0.0f)},  {1e-3f, vec3(0.0f)},
                                                       {1.0f, vec3(0.0f)},   {1e3f, vec3(0.0f)},
                                                       {1.0f, vec3(5.0f)},   {1e2f, vec3(1e6f, -1e6f, 0.0f)},
                                                       {1e4f, vec3(-1e7f, 0.0f, 3e6f)}};
    for (const float angle : {0.0f, 37.0f})
        for (const auto& [scale, offset] : cases) {
            Scene scene = quadScene(offset, scale);
            tilt(scene, offset, angle);
            const RayTracer tracer(scene);
            const vec3 n = triangleNormal(scene.meshes[0], 0);
            int selfHits = 0;
            for (int i = 0; i < 100; ++i) {
                const vec3 start = offset + vec3((i % 10 - 4.5f) * 0.1f * scale, (i / 10 - 4.5f) * 0.1f * scale, 0.0f);
                const SurfacePoint p = pointHit(scene, tracer, start + 2.0f * scale * n, -n);
                const vec3 tangent = glm::normalize(glm::cross(n, vec3(0.3f, 0.7f, 0.1f)));
                const vec3 grazing = glm::normalize(tangent + 0.01f * p.geometricNormal);
                selfHits += tracer.intersect({offsetRayOrigin(p.position, p.positionError, p.geometricNormal), grazing}).found();
            }
            EXPECT_EQ(selfHits, 0) << "scale " << scale << " offset " << offset.x << " tilt " << angle;
        }
}

TEST(RayTracer, ThinWallsStayOpaqueAtEveryScale) {
    // Two walls a thousandth of the scene's size apart, as a thin wall's two faces: a ray leaving
    // the lower one upwards must meet the upper one. An offset fixed in scene units (1/65536, as
    // before) jumps over a gap of 1e-6 in a scene of size 1e-3, and light leaks through.
    for (const float scale : {1e-5f, 1e-3f, 1.0f, 1e3f}) {
        Scene scene = quadScene(vec3(0.0f), scale);
        Scene upper = quadScene(vec3(0.0f, 0.0f, 1e-3f * scale), scale);
        std::swap(upper.meshes[0].indices[0].y, upper.meshes[0].indices[0].z);  // face down
        std::swap(upper.meshes[0].indices[1].y, upper.meshes[0].indices[1].z);
        scene.meshes.push_back(upper.meshes[0]);
        const RayTracer tracer(scene);
        int leaks = 0;
        for (int i = 0; i < 100; ++i) {
            const vec3 p((float(i % 10) - 4.5f) * 0.1f * scale, (float(i / 10) - 4.5f) * 0.1f * scale, 0.0f);
            const SurfacePoint s = pointHit(scene, tracer, p - vec3(0, 0, scale), vec3(0, 0, 1));
            const Ray ray{offsetRayOrigin(s.position, s.positionError, -s.geometricNormal), glm::normalize(vec3(0.3f, 0.2f, 1.0f))};
            leaks += tracer.intersect(ray).mesh != 1;
        }
        EXPECT_EQ(leaks, 0) << "of 100 rays, scene size " << scale;
    }
}

TEST(RayOffset, ScalesWithTheTriangleNotWithTheScene) {
    // A triangle scaled by a power of two gets its offsets scaled by it exactly.
    const vec3 v0(-1.0f, 0.2f, 0.1f), v1(2.0f, 0.3f, -0.5f), v2(0.1f, -1.5f, 0.8f), n = glm::normalize(vec3(0.2f, 0.3f, 0.9f));
    const vec3 p = 0.2f * v0 + 0.3f * v1 + 0.5f * v2;
    const vec3 unit = offsetRayOrigin(p, interpolationError(0.2f, 0.3f, 0.5f, v0, v1, v2), n) - p;
    const float k = 0x1p-20f;
    const vec3 scaled = offsetRayOrigin(k * p, interpolationError(0.2f, 0.3f, 0.5f, k * v0, k * v1, k * v2), n) - k * p;
    for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(scaled[c], k * unit[c]) << "component " << c;
    // A plane 200 units wide at y = 1 moves its points by little more than a float's rounding of
    // 1: an offset tied to the scene's size instead (0.004 here) moved a small box's sun shadow on
    // it by 0.7 % of the box (the independent-estimator test of a box on a plane saw it).
    const vec3 a(-100, 1, -100), b(100, 1, -100), c(100, 1, 100), q = 0.25f * a + 0.25f * b + 0.5f * c;
    const vec3 moved = offsetRayOrigin(q, interpolationError(0.25f, 0.25f, 0.5f, a, b, c), vec3(0, 1, 0));
    EXPECT_GT(moved.y, q.y);
    EXPECT_LT(moved.y - q.y, 1e-5f);
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
                        const SurfacePoint a = pointHit(scene, tracer, from + vec3(0, 0, 0.5f * gap), vec3(0, 0, -1));
                        const SurfacePoint b = pointHit(scene, tracer, to - vec3(0, 0, 0.5f * gap), vec3(0, 0, 1));
                        const ShadowRay shadow =
                            shadowRayBetween(a.position, a.positionError, a.geometricNormal, b.position, b.positionError, b.geometricNormal);
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
    const vec3 error(1e-7f), up(0, 0, 1);
    const ShadowRay shadow = shadowRayBetween(vec3(0.1f, 0.1f, 0), error, up, vec3(0, 0, 1), error, -up);
    EXPECT_TRUE(tracer.occluded(shadow.ray, shadow.tMax));
    const ShadowRay escape = shadowRayTowards(vec3(3, 0, 0), error, up, up);
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
