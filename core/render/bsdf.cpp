#include "core/render/bsdf.h"

#include <algorithm>
#include <cmath>

namespace gibench {

float ggxD(const vec3& m, float alpha) {
    if (m.z <= 0.0f) return 0.0f;
    const float a2 = alpha * alpha;
    const float d = m.z * m.z * (a2 - 1.0f) + 1.0f;
    return a2 / (kPi * d * d);
}

float ggxLambda(const vec3& w, float alpha) {
    const float cos2 = w.z * w.z;
    if (cos2 <= 0.0f) return 0.0f;
    const float tan2 = std::max(0.0f, 1.0f - cos2) / cos2;
    return 0.5f * (std::sqrt(1.0f + alpha * alpha * tan2) - 1.0f);
}

vec3 ggxSampleVisibleNormal(const vec3& wo, float alpha, const vec2& u) {
    // Stretch to the unit-roughness configuration, sample the projected hemisphere there.
    const vec3 vh = glm::normalize(vec3(alpha * wo.x, alpha * wo.y, wo.z));
    const float lenSq = vh.x * vh.x + vh.y * vh.y;
    const vec3 t1 = lenSq > 0.0f ? vec3(-vh.y, vh.x, 0.0f) / std::sqrt(lenSq) : vec3(1.0f, 0.0f, 0.0f);
    const vec3 t2 = glm::cross(vh, t1);
    const float r = std::sqrt(u.x);
    const float phi = 2.0f * kPi * u.y;
    const float p1 = r * std::cos(phi);
    float p2 = r * std::sin(phi);
    const float s = 0.5f * (1.0f + vh.z);
    p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * p2;
    const vec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
    return glm::normalize(vec3(alpha * nh.x, alpha * nh.y, std::max(1e-7f, nh.z)));
}

Bsdf::Bsdf(const Material& material, const Color& albedo, const SurfacePoint& p)
    : m_frame(p.shadingNormal), m_geometricNormal(p.geometricNormal), m_albedo(albedo), m_specularProbability(specularProbability(material, albedo)) {
    if (material.type == MaterialType::Glossy) {
        m_specular = material.specular;
        m_alpha = material.roughness * material.roughness;
    }
}

Color Bsdf::schlick(float cosTheta) const {
    const float c = std::clamp(cosTheta, 0.0f, 1.0f);
    return m_specular + (Color(1.0f) - m_specular) * std::pow(1.0f - c, 5.0f);
}

bool Bsdf::sameSide(const vec3& wo, const vec3& wi) const {
    return glm::dot(wi, m_geometricNormal) > 0.0f && glm::dot(wo, m_geometricNormal) > 0.0f;
}

Color Bsdf::evalLocal(const vec3& wo, const vec3& wi) const {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return Color(0.0f);
    if (m_specularProbability <= 0.0f) return m_albedo * kInvPi;
    // The diffuse base only gets the light the coating lets through, both ways; without the
    // (1 − F) factors albedo + F(θ) exceeds 1 at grazing angles and the surface gains energy.
    const Color diffuse = m_albedo * kInvPi * (Color(1.0f) - schlick(wo.z)) * (Color(1.0f) - schlick(wi.z));
    const vec3 m = glm::normalize(wo + wi);
    const float g2 = 1.0f / (1.0f + ggxLambda(wo, m_alpha) + ggxLambda(wi, m_alpha));
    return diffuse + schlick(glm::dot(wi, m)) * (ggxD(m, m_alpha) * g2 / (4.0f * wo.z * wi.z));
}

float Bsdf::pdfLocal(const vec3& wo, const vec3& wi) const {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    float pdf = (1.0f - m_specularProbability) * cosineHemispherePdf(wi.z);
    if (m_specularProbability > 0.0f) {
        const vec3 m = glm::normalize(wo + wi);
        // Visible-normal density D_wo(m) = G1(wo) max(0, wo·m) D(m) / cos θo, and the reflection
        // Jacobian 1 / (4 wo·m) cancels the wo·m.
        const float g1 = 1.0f / (1.0f + ggxLambda(wo, m_alpha));
        pdf += m_specularProbability * g1 * ggxD(m, m_alpha) / (4.0f * wo.z);
    }
    return pdf;
}

Color Bsdf::eval(const vec3& wo, const vec3& wi) const {
    if (!sameSide(wo, wi)) return Color(0.0f);
    return evalLocal(m_frame.toLocal(wo), m_frame.toLocal(wi));
}

float Bsdf::pdf(const vec3& wo, const vec3& wi) const {
    if (!sameSide(wo, wi)) return 0.0f;
    return pdfLocal(m_frame.toLocal(wo), m_frame.toLocal(wi));
}

BsdfSample Bsdf::sample(const vec3& woWorld, float uLobe, const vec2& u) const {
    if (m_specularProbability <= 0.0f) return sampleLambertian(m_frame, m_geometricNormal, m_albedo, woWorld, u);
    BsdfSample s;
    const vec3 wo = m_frame.toLocal(woWorld);
    if (wo.z <= 0.0f) return s;
    vec3 wi;
    if (uLobe < m_specularProbability) {
        const vec3 m = ggxSampleVisibleNormal(wo, m_alpha, u);
        wi = glm::reflect(-wo, m);
    } else {
        wi = sampleCosineHemisphere(u);
    }
    s.wi = m_frame.toWorld(wi);
    if (wi.z <= 0.0f || !sameSide(woWorld, s.wi)) return s;
    s.f = evalLocal(wo, wi);
    s.pdf = pdfLocal(wo, wi);
    return s;
}

}  // namespace gibench
