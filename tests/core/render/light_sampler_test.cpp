#include "core/render/light_sampler.h"

#include "core/util/rng.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gibench {
namespace {

// The receivers' shading normal where the test does not turn on it.
const vec3 kUp(0.0f, 1.0f, 0.0f);

// A small lat-long map with one bright texel and a gradient, rotated about +Y.
Scene environmentScene() {
    auto map = std::make_shared<Texture>();
    map->width = 8;
    map->height = 4;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) map->texels.push_back(Color(0.1f + 0.05f * x, 0.2f, 0.1f * y));
    map->texels[1 * 8 + 5] = Color(50.0f);
    Scene scene;
    EnvironmentLight env;
    env.map = map;
    env.scale = 2.0f;
    const float a = 0.7f;
    env.toWorld = mat3(vec3(std::cos(a), 0, -std::sin(a)), vec3(0, 1, 0), vec3(std::sin(a), 0, std::cos(a)));
    scene.environment = env;
    return scene;
}

TEST(LightSampler, EnvironmentSamplesCarryTheDensityPdfReportsForTheirDirection) {
    const Scene scene = environmentScene();
    const LightSampler lights(scene);
    Rng rng(2, 3);
    for (int i = 0; i < 2000; ++i) {
        const LightSample s = lights.sampleExtended(vec3(0), kUp, rng.uniform(), vec2(rng.uniform(), rng.uniform()));
        ASSERT_GT(s.pdf, 0.0f);
        ASSERT_NEAR(glm::length(s.wi), 1.0f, 1e-5f);
        EXPECT_NEAR(s.pdf, lights.pdfEnvironment(s.wi, kUp), 2e-3f * s.pdf) << "sample " << i;
        const Color l = lights.environmentRadiance(s.wi);
        EXPECT_NEAR(s.radiance.x, l.x, 1e-3f * (1.0f + l.x)) << "sample " << i;
    }
}

TEST(LightSampler, ImportanceSampledEnvironmentIntegratesToTheTexelSum) {
    // ∫ L(ω) dω over the sphere equals Σ L_texel · ΔΩ_texel for a piecewise-constant lat-long map.
    const Scene scene = environmentScene();
    const LightSampler lights(scene);
    const Texture& map = *scene.environment->map;
    double exact = 0.0;
    for (int y = 0; y < map.height; ++y) {
        const double solidAngle = (2.0 * kPi / map.width) * (std::cos(kPi * y / map.height) - std::cos(kPi * (y + 1) / map.height));
        for (int x = 0; x < map.width; ++x) exact += luminance(map.texels[y * map.width + x]) * scene.environment->scale * solidAngle;
    }
    Rng rng(4, 5);
    const int n = 200000;
    double sum = 0.0, sumSq = 0.0;
    for (int i = 0; i < n; ++i) {
        const LightSample s = lights.sampleExtended(vec3(0), kUp, rng.uniform(), vec2(rng.uniform(), rng.uniform()));
        const double v = luminance(s.radiance) / s.pdf;
        sum += v;
        sumSq += v * v;
    }
    const double mean = sum / n, error = std::sqrt((sumSq / n - mean * mean) / n);
    EXPECT_NEAR(mean, exact, 5.0 * error + 1e-3 * exact);
}

// A constant sky over a tilted receiver: every sample lies above the receiver, and its
// irradiance estimate L cos θ / pdf is π L exactly (the cosine-weighted density is the
// integrand's shape). A uniform sphere sent half its samples below the surface, each worth
// nothing but the draw.
TEST(LightSampler, AConstantSkyIsSampledAboveTheReceiverInProportionToTheCosine) {
    Scene scene;
    EnvironmentLight sky;
    sky.radiance = Color(0.5f, 0.7f, 1.1f);
    scene.environment = sky;
    const LightSampler lights(scene);
    const vec3 normal = glm::normalize(vec3(0.3f, 0.8f, -0.5f));
    Rng rng(10, 11);
    for (int i = 0; i < 4000; ++i) {
        const LightSample s = lights.sampleExtended(vec3(1e5f, -3.0f, 2.0f), normal, rng.uniform(), vec2(rng.uniform(), rng.uniform()));
        const float cosine = glm::dot(normal, s.wi);
        ASSERT_GT(cosine, 0.0f) << "sample " << i;
        ASSERT_NEAR(glm::length(s.wi), 1.0f, 1e-5f);
        ASSERT_NEAR(s.pdf, lights.pdfEnvironment(s.wi, normal), 1e-6f * s.pdf);
        const Color estimate = s.radiance * (cosine / s.pdf);
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(estimate[c], kPi * sky.radiance[c], 1e-4f * kPi * sky.radiance[c]) << "sample " << i;
    }
    EXPECT_EQ(lights.pdfEnvironment(-normal, normal), 0.0f);  // nothing is sampled below the receiver
}

TEST(LightSampler, TrianglePdfMatchesTheSampledDensity) {
    Scene scene;
    Material lamp;
    lamp.emission = Color(5.0f);
    scene.materials = {lamp};
    Mesh mesh;
    mesh.positions = {vec3(-1, 2, -1), vec3(1, 2, -1), vec3(1, 2, 1), vec3(-1, 2, 1)};
    mesh.indices = {uvec3(0, 1, 2), uvec3(0, 2, 3)};  // counter-clockwise seen from below: facing down
    mesh.materials = {0, 0};
    scene.meshes = {mesh};
    const LightSampler lights(scene);
    ASSERT_EQ(lights.emissiveTriangleCount(), 2u);
    const RayTracer tracer(scene);
    Rng rng(6, 7);
    const vec3 receiver(0.3f, 0.0f, -0.2f);
    double irradiance = 0.0, irradianceSq = 0.0;
    const int n = 100000;
    for (int i = 0; i < n; ++i) {
        const LightSample s = lights.sampleExtended(receiver, kUp, rng.uniform(), vec2(rng.uniform(), rng.uniform()));
        ASSERT_GT(s.pdf, 0.0f);
        const Ray ray{receiver, s.wi};
        const RayHit hit = tracer.intersect(ray);
        ASSERT_TRUE(hit.found());
        const SurfacePoint p = surfaceAt(scene, ray, hit);
        ASSERT_NEAR(lights.pdfTriangle(p, receiver), s.pdf, 1e-3f * s.pdf);
        const double v = s.radiance.x * s.wi.y / s.pdf;
        irradiance += v;
        irradianceSq += v * v;
    }
    const double mean = irradiance / n, error = std::sqrt((irradianceSq / n - mean * mean) / n);
    // Irradiance from a uniform square emitter of radiance L at height h: compare against a
    // midpoint-rule integration of L cos θ cos θl / r² over the square.
    double exact = 0.0;
    const int m = 400;
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) {
            const vec3 q(-1.0f + 2.0f * (i + 0.5f) / m, 2.0f, -1.0f + 2.0f * (j + 0.5f) / m);
            const vec3 d = q - receiver;
            const double r2 = glm::dot(d, d);
            exact += 5.0 * (d.y / std::sqrt(r2)) * (d.y / std::sqrt(r2)) / r2 * (4.0 / (m * m));
        }
    EXPECT_NEAR(mean, exact, 5.0 * error + 1e-4 * exact);  // 1e-4: the midpoint rule's own error
}

// chooseExtended() names what sampleExtended() samples for the same number, with the same
// selection probability: a triangle (the sample lies on it), the constant sky (the sample is
// sampleConstantEnvironment()'s, bit for bit) or, for a mapped sky, neither. The lanes of
// next-event estimation (DirectLightBatch) rely on it to sample the sky themselves.
TEST(LightSampler, TheExtendedChoiceIsWhatTheExtendedSampleSamples) {
    for (const bool mapped : {false, true}) {
        Scene scene = mapped ? environmentScene() : Scene{};
        if (!mapped) {
            EnvironmentLight sky;
            sky.radiance = Color(0.3f, 0.4f, 0.6f);
            scene.environment = sky;
        }
        Material lamp;
        lamp.emission = Color(2.0f, 1.0f, 0.5f);
        scene.materials = {lamp};
        Mesh mesh;
        mesh.positions = {vec3(-1, 2, -1), vec3(1, 2, -1), vec3(1, 2, 1), vec3(0, 3, 0)};
        mesh.indices = {uvec3(0, 1, 2), uvec3(0, 2, 3)};
        mesh.materials = {0, 0};
        scene.meshes = {mesh};
        const LightSampler lights(scene);
        ASSERT_EQ(lights.emissiveTriangleCount(), 2u);
        Rng rng(12, 13);
        int triangles = 0, skies = 0;
        for (int i = 0; i < 4000; ++i) {
            const float uSelect = rng.uniform();
            const vec2 u(rng.uniform(), rng.uniform());
            const vec3 normal = glm::normalize(vec3(rng.uniform() - 0.5f, 1.0f, rng.uniform() - 0.5f));
            const LightSampler::ExtendedChoice choice = lights.chooseExtended(uSelect);
            const LightSample s = lights.sampleExtended(vec3(0.1f, 0.0f, 0.2f), normal, uSelect, u);
            ASSERT_FALSE(choice.triangle && choice.constantEnvironment);
            if (choice.triangle) {
                ++triangles;
                ASSERT_TRUE(std::isfinite(s.distance));
                const EmissiveTriangle& t = *choice.triangle;
                for (int e = 0; e < 3; ++e) {
                    const vec3& a = t.vertices[e];
                    const vec3& b = t.vertices[(e + 1) % 3];
                    ASSERT_GE(glm::dot(glm::cross(b - a, s.point - a), t.normal), -1e-5f) << "the sample lies off the chosen triangle";
                }
                ASSERT_EQ(s.pdf, sampleEmissiveTriangle(t, choice.select, vec3(0.1f, 0.0f, 0.2f), u).pdf);
                continue;
            }
            ASSERT_FALSE(std::isfinite(s.distance));
            ASSERT_EQ(choice.constantEnvironment, !mapped);
            if (!choice.constantEnvironment) continue;
            ++skies;
            const LightSample sky = sampleConstantEnvironment(normal, lights.constantEnvironmentRadiance(), choice.select, u);
            ASSERT_EQ(sky.wi, s.wi);
            ASSERT_EQ(sky.pdf, s.pdf);
            ASSERT_EQ(sky.radiance, s.radiance);
        }
        EXPECT_GT(triangles, 100);
        if (!mapped) {
            EXPECT_GT(skies, 100);
        }
    }
}

// A sun and a constant sky: next-event estimation takes the sun on its own, so the strategy for
// lights with extent holds only the sky, while resampling candidates (sample()) see both.
TEST(LightSampler, SunsAreLeftOutOfTheExtendedStrategyAndKeptInTheOneOverAllLights) {
    Scene scene;
    scene.suns.push_back(SunLight{glm::normalize(vec3(0.3f, -1.0f, 0.2f)), Color(3.0f)});
    EnvironmentLight sky;
    sky.radiance = Color(0.5f);
    scene.environment = sky;
    const LightSampler lights(scene);
    ASSERT_EQ(lights.sunCount(), 1u);
    const LightSample sun = lights.sun(0);
    EXPECT_TRUE(sun.isDelta);
    EXPECT_EQ(sun.pdf, 1.0f);
    EXPECT_EQ(sun.wi, -scene.suns[0].direction);
    EXPECT_EQ(sun.radiance, Color(3.0f));

    Rng rng(8, 9);
    int sunsPicked = 0;
    const int n = 4000;
    for (int i = 0; i < n; ++i) {
        const float uSelect = rng.uniform();
        const vec2 u(rng.uniform(), rng.uniform());
        const LightSample extended = lights.sampleExtended(vec3(0), kUp, uSelect, u);
        ASSERT_FALSE(extended.isDelta);
        // The sky is the only light with extent: chosen always, cosine-weighted about the normal.
        ASSERT_NEAR(extended.pdf, extended.wi.y * kInvPi, 1e-6f);
        ASSERT_NEAR(lights.pdfEnvironment(extended.wi, kUp), extended.pdf, 1e-6f);
        sunsPicked += lights.sample(vec3(0), uSelect, u).isDelta;
    }
    // Power shares as in the constructor: sun E·πR², sky 4π·L·πR².
    const double pSun = 3.0 / (3.0 + 4.0 * kPi * 0.5);
    EXPECT_NEAR(double(sunsPicked) / n, pSun, 5.0 * std::sqrt(pSun * (1.0 - pSun) / n));
}

}  // namespace
}  // namespace gibench
