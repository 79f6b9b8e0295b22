#include "core/render/path_tracing.h"
#include "tests/support/render_helpers.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gibench {
namespace {

// Next-event estimation under a sun and a sky: the sun is evaluated on every sample, so no
// estimate falls below the sun's share of the light, and the estimates average to the exact
// reflected radiance ρ (E cos θ / π + L).
TEST(DirectLighting, EverySampleCarriesEverySunAndTheMeanIsExact) {
    const float albedo = 0.7f, irradiance = 3.0f, sky = 0.4f, theta = 0.6f;
    Json json = test::sunLitPlane(albedo, irradiance, theta);
    json["lights"].push_back({{"type", "environment"}, {"radiance", sky}});
    const PreparedScene ps(test::sceneFromJson(json));
    ASSERT_EQ(ps.lights.sunCount(), 1u);

    const Ray down{vec3(0.1f, 1.0f, -0.2f), vec3(0, -1, 0)};
    const RayHit hit = ps.tracer.intersect(down);
    ASSERT_TRUE(hit.found());
    const SurfacePoint p = surfaceAt(ps.scene, down, hit);
    const Bsdf bsdf(*p.material, albedoAt(ps.scene, p), p);
    const vec3 wo(0, 1, 0);

    const double sunShare = albedo * irradiance * std::cos(theta) / kPi;
    const double exact = sunShare + albedo * sky;
    Rng rng(3, 4);
    const int n = 20000;
    double sum = 0.0, sumSq = 0.0;
    for (int i = 0; i < n; ++i) {
        uint32_t rays = 0;
        const double v = estimateDirect(ps, p, bsdf, wo, rng, rays, nullptr, false).x;
        // The sun's shadow ray always; the sky's unless its direction lies below the plane.
        ASSERT_GE(rays, 1u);
        ASSERT_LE(rays, 2u);
        ASSERT_GE(v, sunShare * (1.0 - 1e-5)) << "sample " << i << " left the sun out";
        sum += v;
        sumSq += v * v;
    }
    const double mean = sum / n, error = std::sqrt((sumSq / n - mean * mean) / n);
    EXPECT_NEAR(mean, exact, 5.0 * error + 1e-5 * exact);
}

}  // namespace
}  // namespace gibench
