#pragma once
// Reflection at a surface point: Lambertian, plus an optional GGX microfacet lobe (Walter et al.
// 2007) with Schlick's Fresnel, the height-correlated Smith masking term, and visible-normal
// sampling (Heitz 2018). With the lobe, the diffuse base is scaled by (1 − F(cos θo))(1 − F(cos θi)):
// the light the coating transmits on the way in and out. Directions point away from the
// surface; values exclude the cosine.

#include "core/render/sampling.h"
#include "core/render/surface.h"
#include "core/scene/scene.h"
#include "core/util/lane_select.h"
#include "core/util/math.h"

namespace gibench {

struct BsdfSample {
    vec3 wi{0.0f};   // world space, unit
    Color f{0.0f};   // BSDF value (no cosine)
    float pdf = 0.0f;  // solid angle density of wi; 0 when sampling failed
};

class Bsdf {
public:
    Bsdf(const Material& material, const Color& albedo, const SurfacePoint& p);

    Color eval(const vec3& wo, const vec3& wi) const;
    float pdf(const vec3& wo, const vec3& wi) const;
    // uLobe picks the lobe, u the direction within it.
    BsdfSample sample(const vec3& wo, float uLobe, const vec2& u) const;

    const Color& albedo() const { return m_albedo; }
    bool hasSpecular() const { return m_specularProbability > 0.0f; }
    // The probability that sample() picks the specular lobe of `material` over a diffuse base of
    // `albedo`; 0 when the BSDF has no specular lobe: a caller that finds 0 knows the BSDF is
    // Lambertian without building it (the path tracer's vertices).
    static float specularProbability(const Material& material, const Color& albedo) {
        if (material.type != MaterialType::Glossy) return 0.0f;
        const float ld = luminance(albedo), ls = luminance(material.specular);
        return ld + ls > 0.0f ? ls / (ld + ls) : 0.0f;
    }

private:
    // Both directions on the side of the geometric normal the ray came from (no light leaks
    // through a surface because the shading normal differs).
    bool sameSide(const vec3& wo, const vec3& wi) const;
    Color schlick(float cosTheta) const;
    Color evalLocal(const vec3& wo, const vec3& wi) const;
    float pdfLocal(const vec3& wo, const vec3& wi) const;

    Frame m_frame;
    vec3 m_geometricNormal;
    Color m_albedo;
    Color m_specular;
    float m_alpha = 1.0f;
    float m_specularProbability = 0.0f;
};

// Bsdf::sample() of a BSDF without a specular lobe (a Lambertian one, `albedo`, shading `frame`,
// `geometricNormal`), inline and without branches: a wave of paths samples its Lambertian
// vertices across SIMD lanes (tracePaths()).
inline BsdfSample sampleLambertian(const Frame& frame, const vec3& geometricNormal, const Color& albedo, const vec3& woWorld, const vec2& u) {
    const vec3 wi = sampleCosineHemisphere(u);
    BsdfSample s;
    s.wi = frame.toWorld(wi);
    // Both directions above the shading normal (the local z) and on the geometric normal's side.
    const uint32_t reflects = ~laneMask(glm::dot(woWorld, frame.n) <= 0.0f) & ~laneMask(wi.z <= 0.0f) &
                              laneMask(glm::dot(s.wi, geometricNormal) > 0.0f) & laneMask(glm::dot(woWorld, geometricNormal) > 0.0f);
    const Color f = albedo * kInvPi;
    s.f = Color(laneSelect(reflects, f.x, 0.0f), laneSelect(reflects, f.y, 0.0f), laneSelect(reflects, f.z, 0.0f));
    s.pdf = laneSelect(reflects, wi.z * kInvPi, 0.0f);  // cosineHemispherePdf(wi.z)
    return s;
}

// GGX pieces, exposed for tests.
float ggxD(const vec3& m, float alpha);
float ggxLambda(const vec3& w, float alpha);
vec3 ggxSampleVisibleNormal(const vec3& wo, float alpha, const vec2& u);

}  // namespace gibench
