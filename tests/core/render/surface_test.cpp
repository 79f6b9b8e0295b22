#include "core/render/surface.h"

#include "core/util/rng.h"
#include "support/render_helpers.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gibench {
namespace {

float reflectionHeight(const vec3& ng, const vec3& ns, const vec3& wo) { return glm::dot(ng, 2.0f * glm::dot(ns, wo) * ns - wo); }

TEST(ValidShadingNormal, KeepsANormalWhoseReflectionIsAboveTheSurface) {
    const vec3 ng(0, 0, 1), ns = glm::normalize(vec3(0.2f, 0.1f, 1.0f)), wo = glm::normalize(vec3(-0.3f, 0.2f, 1.0f));
    EXPECT_EQ(validShadingNormal(ng, ns, wo), ns);
}

TEST(ValidShadingNormal, BendsEveryNormalSoTheViewerIsAboveItAndItsReflectionAboveTheSurface) {
    // Random geometric normals, interpolated normals in their hemisphere and viewers above the
    // surface, many grazing: the result is a unit vector between ns and ng, the viewer lies above
    // it, and the mirror direction lies at least the threshold above the surface (up to float
    // rounding, 1e-4), exactly at it when ns had to be bent.
    Rng rng(3, 4);
    auto unitAbove = [&](const vec3& n, float minCos) {
        for (;;) {
            const vec3 v(2.0f * rng.uniform() - 1.0f, 2.0f * rng.uniform() - 1.0f, 2.0f * rng.uniform() - 1.0f);
            const float len = glm::length(v);
            if (len > 1.0f || len < 1e-3f) continue;
            const vec3 u = v / len;
            if (glm::dot(u, n) > minCos) return u;
        }
    };
    int bent = 0;
    for (int i = 0; i < 20000; ++i) {
        const vec3 ng = unitAbove(vec3(0, 0, 1), -2.0f);
        const vec3 ns = unitAbove(ng, 0.05f);
        const vec3 wo = unitAbove(ng, i % 2 ? 0.0f : 0.9f * float(i % 7) / 7.0f);
        const vec3 valid = validShadingNormal(ng, ns, wo);
        const float threshold = std::min(0.9f * glm::dot(ng, wo), 0.01f);
        ASSERT_NEAR(glm::length(valid), 1.0f, 1e-5f) << i;
        ASSERT_GT(glm::dot(valid, wo), 0.0f) << i;
        ASSERT_GE(reflectionHeight(ng, valid, wo), threshold - 1e-4f) << i << " ng " << ng.x << "," << ng.y << "," << ng.z << " ns " << ns.x << "," << ns.y << "," << ns.z << " wo " << wo.x << "," << wo.y << "," << wo.z << " valid " << valid.x << "," << valid.y << "," << valid.z;
        ASSERT_GE(glm::dot(valid, ng), glm::dot(ns, ng) - 1e-5f) << i << ": bent away from ng";
        if (valid != ns) {
            ++bent;
            EXPECT_NEAR(reflectionHeight(ng, valid, wo), threshold, 1e-3f) << i;
            EXPECT_NEAR(glm::dot(glm::cross(ns, ng), valid), 0.0f, 1e-4f) << i << ": left the plane of ns and ng";
        }
    }
    EXPECT_GT(bent, 2000);  // the sweep reaches the case it is about
}

TEST(SurfacePoint, TiltedVertexNormalsNeverLeaveAPixelBlack) {
    // A floor under a constant sky whose vertex normals lean 60° away from the camera: without
    // bending, the camera sits below the shading hemisphere of most of it and those pixels come
    // out black. Light arriving above the geometric surface is the same either way, so every
    // pixel must keep a fair part of the flat floor's ρ L: no energy created (≤ ρ L plus noise),
    // none lost wholesale (> 0.1 ρ L, the measure of a black hole).
    const float albedo = 0.5f, sky = 1.0f;
    const vec3 lean = glm::normalize(vec3(0.0f, 0.5f, -0.866f));  // 60° from +Y, away from a camera at +Z
    const Json scene = {{"materials", {{"ground", {{"type", "diffuse"}, {"albedo", albedo}}}}},
                        {"shapes",
                         {{{"type", "triangles"},
                           {"vertices", {{-50, 0, -50}, {50, 0, -50}, {50, 0, 50}, {-50, 0, 50}}},
                           {"indices", {{0, 2, 1}, {0, 3, 2}}},
                           {"normals", {{lean.x, lean.y, lean.z}, {lean.x, lean.y, lean.z}, {lean.x, lean.y, lean.z}, {lean.x, lean.y, lean.z}}},
                           {"material", "ground"}}}},
                        {"lights", {{{"type", "environment"}, {"radiance", sky}}}}};
    const PreparedScene prepared(test::sceneFromJson(scene));
    const LayeredImage image = test::render(prepared, test::camera(vec3(0, 1, 4), vec3(0, 0, -2), 24, 16, 50.0f),
                                            {{"name", "path_traced"}, {"spp", 64}, {"max_depth", 1}}, 5);
    const Image& total = image.find("total")->image;
    const Image& albedoLayer = image.find("albedo")->image;
    int floorPixels = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            if (albedoLayer.at(x, y, 0) != albedo) continue;  // the sky, or a pixel the horizon crosses
            ++floorPixels;
            EXPECT_GT(total.at(x, y, 0), 0.1f * albedo * sky) << "pixel " << x << "," << y;
            EXPECT_LT(total.at(x, y, 0), 1.3f * albedo * sky) << "pixel " << x << "," << y;
        }
    EXPECT_GT(floorPixels, 100);
}

}  // namespace
}  // namespace gibench
