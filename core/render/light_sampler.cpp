#include "core/render/light_sampler.h"

#include "core/render/ray_offset.h"

#include <algorithm>
#include <cmath>

namespace gibench {

LightSampler::LightSampler(const Scene& scene) : m_suns(scene.suns) {
    // Power estimates choose lights as pbrt-v4's power light sampler does: infinite lights count
    // as if they fell on a disc of the scene's bounding radius.
    const float radius = 0.5f * glm::length(scene.bounds().extent());
    const float discArea = kPi * std::max(radius * radius, 1e-30f);
    std::vector<float> power;

    m_lightOfTriangle.resize(scene.meshes.size());
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
            const Material& material = scene.materials[mesh.materials[t]];
            if (!material.isEmissive()) continue;
            const float area = triangleArea(mesh, t);
            if (!(area > 0.0f)) continue;
            if (m_lightOfTriangle[m].empty()) m_lightOfTriangle[m].assign(mesh.triangleCount(), -1);
            m_lightOfTriangle[m][t] = int(m_triangles.size());
            const uvec3 i = mesh.indices[t];
            m_triangles.push_back({{mesh.positions[i.x], mesh.positions[i.y], mesh.positions[i.z]}, triangleNormal(mesh, t), area, material.emission});
            power.push_back(kPi * area * luminance(material.emission));
        }
    }
    for (const SunLight& sun : m_suns) power.push_back(discArea * luminance(sun.irradiance));

    if (scene.environment) {
        m_environment = *scene.environment;
        float meanRadiance = luminance(m_environment.radiance);
        if (m_environment.map) {
            const Texture& map = *m_environment.map;
            std::vector<float> weights(std::size_t(map.width) * map.height);
            double weighted = 0.0, solidAngle = 0.0;
            for (int y = 0; y < map.height; ++y) {
                const float sinTheta = std::sin(kPi * (float(y) + 0.5f) / float(map.height));
                for (int x = 0; x < map.width; ++x) {
                    const float l = std::max(0.0f, luminance(map.texels[std::size_t(y) * map.width + x]) * m_environment.scale);
                    weights[std::size_t(y) * map.width + x] = l * sinTheta;
                    weighted += double(l) * sinTheta;
                    solidAngle += sinTheta;
                }
            }
            m_environmentDistribution = Distribution2D(weights, map.width, map.height);
            meanRadiance = solidAngle > 0.0 ? float(weighted / solidAngle) : 0.0f;
        }
        m_hasEnvironment = meanRadiance > 0.0f;
        if (m_hasEnvironment) power.push_back(4.0f * kPi * discArea * meanRadiance);
    }
    std::vector<float> extendedPower(power.begin(), power.begin() + std::ptrdiff_t(m_triangles.size()));
    if (m_hasEnvironment) extendedPower.push_back(power.back());
    m_anySelection = Distribution1D(std::move(power));
    m_extendedSelection = Distribution1D(std::move(extendedPower));
}

vec2 LightSampler::environmentUv(const vec3& world) const {
    // Lat-long with +Y up, u = atan2(x, -z) / 2π, v = θ / π from the top row (Mitsuba's
    // convention, so rotations given for Mitsuba scenes carry over).
    const vec3 d = glm::transpose(m_environment.toWorld) * world;
    float u = std::atan2(d.x, -d.z) * (0.5f * kInvPi);
    if (u < 0.0f) u += 1.0f;
    const float v = std::acos(std::clamp(d.y, -1.0f, 1.0f)) * kInvPi;
    return vec2(std::min(u, 0x1.fffffep-1f), std::min(v, 0x1.fffffep-1f));
}

vec3 LightSampler::environmentDirection(const vec2& uv) const {
    const float phi = 2.0f * kPi * uv.x, theta = kPi * uv.y;
    const vec3 d(std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi));
    return m_environment.toWorld * d;
}

Color LightSampler::environmentRadiance(const vec3& wi) const {
    return m_environment.map ? mapRadiance(environmentUv(wi)) : m_environment.radiance;
}

Color LightSampler::mapRadiance(const vec2& uv) const {
    // Nearest texel: the same piecewise-constant function the sampling distribution follows.
    const Texture& map = *m_environment.map;
    const int x = std::min(int(uv.x * float(map.width)), map.width - 1);
    const int y = std::min(int(uv.y * float(map.height)), map.height - 1);
    return map.texels[std::size_t(y) * map.width + x] * m_environment.scale;
}

float LightSampler::pdfEnvironment(const vec3& wi, const vec3& normal) const {
    if (!m_hasEnvironment) return 0.0f;
    const float select = m_extendedSelection.probability(m_extendedSelection.size() - 1);
    if (!m_environment.map) return select * cosineHemispherePdf(glm::dot(normal, wi));
    const vec2 uv = environmentUv(wi);
    const float sinTheta = std::sin(kPi * uv.y);
    if (sinTheta <= 0.0f) return 0.0f;
    return select * m_environmentDistribution.pdf(uv) / (2.0f * kPi * kPi * sinTheta);
}

float LightSampler::pdfTriangle(const SurfacePoint& onLight, const vec3& receiver) const {
    const auto& lights = m_lightOfTriangle[onLight.mesh];
    if (lights.empty() || lights[onLight.triangle] < 0 || !onLight.frontFacing) return 0.0f;
    const EmissiveTriangle& e = m_triangles[lights[onLight.triangle]];
    const vec3 d = onLight.position - receiver;
    const float dist2 = glm::dot(d, d);
    const float cosLight = std::fabs(glm::dot(onLight.geometricNormal, d)) / std::sqrt(dist2);
    if (cosLight <= 0.0f) return 0.0f;
    return m_extendedSelection.probability(std::size_t(lights[onLight.triangle])) * dist2 / (e.area * cosLight);
}

LightSample LightSampler::sample(const vec3& receiver, float uSelect, const vec2& u) const {
    if (m_anySelection.empty()) return {};
    float select;
    const std::size_t index = m_anySelection.sample(uSelect, select);
    return sampleLight(index, select, receiver, u);
}

LightSample LightSampler::sampleExtended(const vec3& receiver, const vec3& normal, float uSelect, const vec2& u) const {
    if (m_extendedSelection.empty() || !(m_extendedSelection.total() > 0.0)) return {};
    float select;
    const std::size_t index = m_extendedSelection.sample(uSelect, select);
    if (index < m_triangles.size() || m_environment.map) return sampleLight(extendedToAny(index), select, receiver, u);
    return sampleConstantEnvironment(normal, m_environment.radiance, select, u);
}

LightSampler::ExtendedChoice LightSampler::chooseExtended(float uSelect) const {
    ExtendedChoice choice;
    if (m_extendedSelection.empty() || !(m_extendedSelection.total() > 0.0)) return choice;
    const std::size_t index = m_extendedSelection.sample(uSelect, choice.select);
    if (index < m_triangles.size())
        choice.triangle = &m_triangles[index];
    else
        choice.constantEnvironment = !m_environment.map;
    return choice;
}

LightSample LightSampler::sun(std::size_t index) const {
    LightSample s;
    s.wi = -m_suns[index].direction;
    s.distance = kInfinity;
    s.radiance = m_suns[index].irradiance;
    s.pdf = 1.0f;
    s.isDelta = true;
    return s;
}

LightSample LightSampler::sampleLight(std::size_t index, float select, const vec3& receiver, const vec2& u) const {
    LightSample s;
    if (index < m_triangles.size()) return sampleEmissiveTriangle(m_triangles[index], select, receiver, u);
    if (index < m_triangles.size() + m_suns.size()) {
        s = sun(index - m_triangles.size());
        s.pdf = select;
        return s;
    }
    s.distance = kInfinity;
    if (!m_environment.map) {
        s.wi = sampleUniformSphere(u);
        s.radiance = m_environment.radiance;
        s.pdf = select * kUniformSpherePdf;
        return s;
    }
    float pdfUv;
    const vec2 uv = m_environmentDistribution.sample(u, pdfUv);
    const float sinTheta = std::sin(kPi * uv.y);
    if (!(pdfUv > 0.0f) || sinTheta <= 0.0f) return s;
    s.wi = environmentDirection(uv);
    s.radiance = mapRadiance(uv);
    s.pdf = select * pdfUv / (2.0f * kPi * kPi * sinTheta);
    return s;
}

}  // namespace gibench
