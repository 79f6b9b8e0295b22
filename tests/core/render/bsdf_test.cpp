#include "core/render/bsdf.h"

#include "core/render/sampling.h"
#include "core/util/rng.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gibench {
namespace {

SurfacePoint flatPoint() {
    SurfacePoint p;
    p.geometricNormal = p.shadingNormal = vec3(0, 0, 1);
    return p;
}

Material glossy(float roughness, float albedo, float specular) {
    Material m;
    m.type = MaterialType::Glossy;
    m.albedo = Color(albedo);
    m.specular = Color(specular);
    m.roughness = roughness;
    return m;
}

// Monte Carlo estimate of the directional albedo ∫ f cos dωi by sampling the BSDF itself, and
// of ∫ pdf dωi by uniform hemisphere sampling, with their standard errors.
struct Integrals {
    double albedo, albedoError, pdfIntegral, pdfError;
    double validFraction;  // samples that left above the surface: the mass the pdf must integrate to
};

Integrals integrate(const Bsdf& bsdf, const vec3& wo, int n) {
    Rng rng(11, 12);
    double a = 0, a2 = 0, q = 0, q2 = 0, valid = 0;
    for (int i = 0; i < n; ++i) {
        const BsdfSample s = bsdf.sample(wo, rng.uniform(), vec2(rng.uniform(), rng.uniform()));
        const double v = s.pdf > 0.0f ? double(luminance(s.f)) * s.wi.z / s.pdf : 0.0;
        valid += s.pdf > 0.0f;
        a += v;
        a2 += v * v;
        vec3 w = sampleUniformSphere(vec2(rng.uniform(), rng.uniform()));
        w.z = std::fabs(w.z);
        const double pq = bsdf.pdf(wo, w) * 2.0 * kPi;  // uniform hemisphere pdf is 1 / 2π
        q += pq;
        q2 += pq * pq;
    }
    auto se = [n](double s, double s2) { return std::sqrt(std::max(0.0, s2 / n - (s / n) * (s / n)) / n); };
    return {a / n, se(a, a2), q / n, se(q, q2), valid / n};
}

TEST(Bsdf, LambertianReflectsItsAlbedoAndItsPdfIntegratesToOne) {
    Material m;
    m.albedo = Color(0.6f);
    const Bsdf bsdf(m, m.albedo, flatPoint());
    const Integrals r = integrate(bsdf, glm::normalize(vec3(0.3f, 0.1f, 1.0f)), 100000);
    EXPECT_NEAR(r.albedo, 0.6, 1e-4);  // f cos / pdf is exactly the albedo for cosine sampling
    EXPECT_NEAR(r.pdfIntegral, 1.0, 5.0 * r.pdfError);
}

TEST(Bsdf, GlossyPdfIsTheDensityOfItsSamplesAndEnergyIsConserved) {
    // Visible-normal samples can reflect below the horizon; those fail, so the pdf over the
    // hemisphere integrates to the fraction of samples that succeed, not to 1.
    for (float roughness : {0.1f, 0.4f, 1.0f})
        for (float cosTheta : {0.95f, 0.5f, 0.15f}) {
            const Bsdf bsdf(glossy(roughness, 0.2f, 0.8f), Color(0.2f), flatPoint());
            const vec3 wo(std::sqrt(1.0f - cosTheta * cosTheta), 0.0f, cosTheta);
            const Integrals r = integrate(bsdf, wo, 200000);
            const double fractionError = std::sqrt(r.validFraction * (1.0 - r.validFraction) / 200000.0);
            EXPECT_NEAR(r.pdfIntegral, r.validFraction, 5.0 * (r.pdfError + fractionError)) << "roughness " << roughness << " cos " << cosTheta;
            // Single-scattering GGX loses energy, never gains it: albedo + specular = 1 bounds it.
            EXPECT_LE(r.albedo, 1.0 + 5.0 * r.albedoError) << "roughness " << roughness << " cos " << cosTheta;
        }
}

TEST(Bsdf, RoughestGgxMirrorReflectsOneMinusLnTwoAtNormalIncidence) {
    // With α = 1, D = 1/π and, at normal incidence, G2 = 2 cos θi / (1 + cos θi), so the
    // directional albedo of a Fresnel-1 lobe is ∫0^1 c / (1 + c) dc = 1 − ln 2.
    const Bsdf bsdf(glossy(1.0f, 0.0f, 1.0f), Color(0.0f), flatPoint());
    const Integrals r = integrate(bsdf, vec3(0, 0, 1), 400000);
    EXPECT_NEAR(r.albedo, 1.0 - std::log(2.0), 5.0 * r.albedoError);
}

TEST(Bsdf, SampledValuesAgreeWithEvalAndPdf) {
    const Bsdf bsdf(glossy(0.3f, 0.3f, 0.5f), Color(0.3f), flatPoint());
    const vec3 wo = glm::normalize(vec3(-0.4f, 0.2f, 0.8f));
    Rng rng(1, 1);
    for (int i = 0; i < 1000; ++i) {
        const BsdfSample s = bsdf.sample(wo, rng.uniform(), vec2(rng.uniform(), rng.uniform()));
        if (s.pdf == 0.0f) continue;
        const Color f = bsdf.eval(wo, s.wi);
        ASSERT_NEAR(s.f.x, f.x, 1e-4f * (1.0f + f.x));
        ASSERT_NEAR(s.pdf, bsdf.pdf(wo, s.wi), 1e-4f * (1.0f + s.pdf));
    }
}

TEST(Bsdf, NothingPassesBelowTheGeometricSurface) {
    SurfacePoint p = flatPoint();
    p.shadingNormal = glm::normalize(vec3(0.5f, 0.0f, 1.0f));  // tilted shading normal
    Material m;
    const Bsdf bsdf(m, Color(0.8f), p);
    const vec3 wo(0, 0, 1), below = glm::normalize(vec3(0.9f, 0.0f, -0.05f));
    EXPECT_EQ(bsdf.eval(wo, below), Color(0.0f));
    EXPECT_EQ(bsdf.pdf(wo, below), 0.0f);
}

TEST(Ggx, NormalDistributionIsNormalizedOverProjectedArea) {
    // ∫ D(m) cos θm dωm = 1 for any roughness.
    for (float alpha : {0.05f, 0.3f, 1.0f}) {
        // Midpoint rule in cos θ (dω = dcos θ dφ, symmetric in φ); fine enough for the narrow peak.
        const int n = 400000;
        double sum = 0.0;
        for (int i = 0; i < n; ++i) {
            const double cosTheta = (i + 0.5) / n;
            sum += ggxD(vec3(float(std::sqrt(1 - cosTheta * cosTheta)), 0.0f, float(cosTheta)), alpha) * cosTheta * (2.0 * kPi) / n;
        }
        EXPECT_NEAR(sum, 1.0, 1e-4) << "alpha " << alpha;
    }
}

}  // namespace
}  // namespace gibench
