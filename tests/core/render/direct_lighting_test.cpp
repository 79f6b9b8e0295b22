#include "core/render/path_tracing.h"

#include "core/render/gbuffer.h"
#include "tests/support/render_helpers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

namespace gibench {
namespace {

// Next-event estimation under a sun and a sky: the sun is evaluated on every sample, and the sky
// sampled in proportion to its reflected light, so that every estimate is the exact reflected
// radiance ρ (E cos θ / π + L).
TEST(DirectLighting, EverySampleCarriesEverySunAndIsExactUnderAConstantSky) {
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
    for (int i = 0; i < 20000; ++i) {
        uint32_t rays = 0;
        const double v = estimateDirect(ps, p, bsdf, wo, rng, rays, nullptr, false).x;
        // The sun's shadow ray and the sky's: the sky is sampled above the plane, cosine-weighted,
        // which is the shape of its reflected light, so that every sample is the exact value.
        ASSERT_EQ(rays, 2u) << "sample " << i;
        ASSERT_NEAR(v, exact, 1e-5 * exact) << "sample " << i;
    }
}

// The batch adds at each point what estimateDirect() returns there, bit for bit, and traces as
// many rays: the Cornell box with a sun (blocked by the ceiling) and a sky (seen through the
// open front) besides its light, so that points queue up to three shadow rays, some blocked,
// and packets straddle points. The rays each add() says it took add up to what the batch traced.
// addLambertian(), given the albedo of these Lambertian walls instead of their Bsdf, adds the same.
TEST(DirectLighting, ABatchAddsWhatEstimateDirectReturnsAtEachPoint) {
    std::ifstream in(std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json");
    Json json = Json::parse(in);
    json["lights"] = {{{"type", "sun"}, {"direction", {0.2, -1.0, 0.3}}, {"irradiance", 2.0}},
                      {{"type", "environment"}, {"radiance", 0.5}}};
    const PreparedScene ps(test::sceneFromJson(json));
    ASSERT_EQ(ps.lights.sunCount(), 1u);
    ASSERT_GT(ps.lights.emissiveTriangleCount(), 0u);
    const int size = 24;
    GBuffer g;
    renderGBuffer(ps, PinholeCamera(ps.scene.camera->poseAt(0.0f).relativeTo(ps.scene.worldOrigin), size, size), 5, 0, g);

    std::vector<Color> batched(g.texels.size(), Color(0.0f)), alone(g.texels.size(), Color(0.0f));
    uint32_t aloneRays = 0;
    int lit = 0, dark = 0;
    for (const bool misFollows : {false, true}) {
        for (const bool byAlbedo : {false, true}) {
            DirectLightBatch batch(ps);
            uint32_t counted = 0;
            for (std::size_t i = 0; i < g.texels.size(); ++i) {
                const GBufferTexel& t = g.texels[i];
                if (!t.valid) continue;
                const Bsdf bsdf(*t.surface.material, t.albedo, t.surface);
                Rng rng(9, i);
                const LightSampleUniforms u = drawLightSampleUniforms(rng);
                batched[i] = alone[i] = Color(0.0f);
                ASSERT_FALSE(bsdf.hasSpecular());
                if (byAlbedo)
                    batch.addLambertian(t.surface, t.albedo, t.wo, u, misFollows, batched[i], &counted);
                else
                    batch.add(t.surface, bsdf, t.wo, u, misFollows, batched[i], &counted);
                alone[i] = estimateDirect(ps, t.surface, bsdf, t.wo, u, aloneRays, nullptr, misFollows);
            }
            batch.flush();
            for (std::size_t i = 0; i < g.texels.size(); ++i) {
                ASSERT_EQ(batched[i], alone[i]) << "pixel " << i << (misFollows ? " with" : " without") << " MIS";
                (maxComponent(alone[i]) > 0.0f ? lit : dark) += g.texels[i].valid;
            }
            EXPECT_EQ(batch.rays(), aloneRays);
            EXPECT_EQ(counted, aloneRays);
            aloneRays = 0;
        }
    }
    EXPECT_GT(lit, 200);
    EXPECT_GT(dark, 10);
}

}  // namespace
}  // namespace gibench
