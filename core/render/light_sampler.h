#pragma once
// Light sampling for next-event estimation and for resampling: emissive triangles, directional
// suns, a constant or mapped environment.
//
// Two strategies, both choosing a light in proportion to its estimated power:
//  - sampleExtended() picks one light among those with extent (triangles, environment) and is
//    what next-event estimation takes together with every sun, each sun evaluated on its own
//    (suns()): a delta light needs no random number, and choosing it by chance only would turn
//    its sharp, often dominant, light into binary noise (on Sponza the sun got 1/3 of the
//    samples, each worth 3× its light) that no sampler stratifies jointly with the pixel;
//    pdfTriangle() and pdfEnvironment() are this strategy's densities, for MIS. It samples a
//    constant environment cosine-weighted about the receiver's shading normal, as a Lambertian
//    BSDF weighs it: a uniform sphere sent half its samples below the surface, where no light
//    is reflected (on Sponza those draws cost 3 % of the path tracer's time and traced nothing);
//  - sample() picks one among all lights, suns included: the candidates of resampled direct
//    lighting (core/render/restir.h), which weighs them itself. It keeps the uniform sphere,
//    whose density does not depend on the receiver, for the reuse of a sample at other pixels.

#include "core/render/ray_offset.h"
#include "core/render/sampling.h"
#include "core/render/surface.h"
#include "core/scene/scene.h"
#include "core/util/math.h"

#include <vector>

namespace gibench {

struct LightSample {
    vec3 wi{0.0f};            // unit direction from the receiving point towards the light
    float distance = 0.0f;    // to the sampled point; kInfinity for suns and the environment
    vec3 point{0.0f};         // the sampled point on an emitting triangle (unset for suns and environment)
    vec3 pointError{0.0f};    // its rounding bound, for shadow rays ending there (interpolationError)
    vec3 lightNormal{0.0f};   // emitting triangle's front normal (zero for suns and environment)
    Color radiance{0.0f};     // arriving radiance; for a sun (delta) its irradiance instead
    float pdf = 0.0f;         // solid angle density including the light's selection probability;
                              // for a delta light, the selection probability alone
    bool isDelta = false;
};

// An emissive triangle with all that sampling it reads, so that a sample follows no index into
// the meshes.
struct EmissiveTriangle {
    vec3 vertices[3];
    vec3 normal;  // unit, counter-clockwise front: the side that emits
    float area;
    Color emission;
};

// A uniform point of `e`, chosen with probability `select`, seen from `receiver`; pdf 0 where
// it sends no light there (the point at the receiver, the back of the emitter). Inline and
// without branches: next-event estimation samples triangles across SIMD lanes (DirectLightBatch).
inline LightSample sampleEmissiveTriangle(const EmissiveTriangle& e, float select, const vec3& receiver, const vec2& u) {
    LightSample s;
    const vec2 b = sampleUniformTriangle(u);
    s.point = (1.0f - b.x - b.y) * e.vertices[0] + b.x * e.vertices[1] + b.y * e.vertices[2];
    const vec3 d = s.point - receiver;
    const float dist2 = glm::dot(d, d);
    s.distance = std::sqrt(dist2);
    s.wi = d * (1.0f / s.distance);  // one division, not one per coordinate
    const float cosLight = -glm::dot(e.normal, s.wi);
    s.lightNormal = e.normal;
    s.pointError = interpolationError(1.0f - b.x - b.y, b.x, b.y, e.vertices[0], e.vertices[1], e.vertices[2]);
    s.radiance = e.emission;
    s.pdf = laneSelect(laneMask(dist2 > 0.0f) & laneMask(cosLight > 0.0f), select * dist2 / (e.area * cosLight), 0.0f);
    return s;
}

// A direction of a constant environment of `radiance`, chosen with probability `select`,
// cosine-weighted about the unit shading normal `normal` (sampleExtended()'s choice for a constant
// environment). Inline and without branches: next-event estimation samples it across SIMD lanes at
// Lambertian points (DirectLightBatch), where one at a time its chain of divisions and square root
// was a fifth of the path tracer's own time on Sponza.
inline LightSample sampleConstantEnvironment(const vec3& normal, const Color& radiance, float select, const vec2& u) {
    LightSample s;
    s.distance = kInfinity;
    s.wi = Frame(normal).toWorld(sampleCosineHemisphere(u));
    s.radiance = radiance;
    s.pdf = select * cosineHemispherePdf(glm::dot(normal, s.wi));
    return s;
}

class LightSampler {
public:
    explicit LightSampler(const Scene& scene);

    bool empty() const { return m_anySelection.empty(); }
    // One light of any kind; a sun's pdf is its selection probability.
    LightSample sample(const vec3& receiver, float uSelect, const vec2& u) const;
    // One light with extent, for a receiver of unit shading normal `normal`; an empty sample
    // (pdf 0) when the scene has none.
    LightSample sampleExtended(const vec3& receiver, const vec3& normal, float uSelect, const vec2& u) const;
    // The light sampleExtended() samples for uSelect, with the probability of choosing it: a
    // triangle (`triangle` set), the constant environment (`constantEnvironment`, of radiance
    // constantEnvironmentRadiance(), sampled by sampleConstantEnvironment()), or neither (a
    // mapped environment, or nothing to sample).
    struct ExtendedChoice {
        const EmissiveTriangle* triangle = nullptr;
        bool constantEnvironment = false;
        float select = 0.0f;
    };
    ExtendedChoice chooseExtended(float uSelect) const;
    const Color& constantEnvironmentRadiance() const { return m_environment.radiance; }
    // Sun `index` seen from anywhere: its direction and irradiance, pdf 1.
    LightSample sun(std::size_t index) const;

    // Density with which sampleExtended() at `receiver` yields the direction to point `onLight`
    // of the emissive triangle it lies on (for MIS of BSDF-sampled hits).
    float pdfTriangle(const SurfacePoint& onLight, const vec3& receiver) const;
    // Density with which sampleExtended() at a receiver of shading normal `normal` yields
    // environment direction `wi`.
    float pdfEnvironment(const vec3& wi, const vec3& normal) const;
    // Radiance the environment sends along -wi, i.e. arriving from direction wi.
    Color environmentRadiance(const vec3& wi) const;
    bool hasEnvironment() const { return m_hasEnvironment; }

    std::size_t emissiveTriangleCount() const { return m_triangles.size(); }
    std::size_t sunCount() const { return m_suns.size(); }

private:
    vec2 environmentUv(const vec3& worldDirection) const;
    vec3 environmentDirection(const vec2& uv) const;
    Color mapRadiance(const vec2& uv) const;
    // Light `index` of [triangles..., suns..., environment], chosen with probability `select`.
    LightSample sampleLight(std::size_t index, float select, const vec3& receiver, const vec2& u) const;
    // Index into [triangles..., suns..., environment] of entry `index` of [triangles...,
    // environment].
    std::size_t extendedToAny(std::size_t index) const {
        return index < m_triangles.size() ? index : m_triangles.size() + m_suns.size();
    }

    std::vector<EmissiveTriangle> m_triangles;
    std::vector<std::vector<int>> m_lightOfTriangle;  // per mesh: index into m_triangles or -1; empty if none
    std::vector<SunLight> m_suns;
    bool m_hasEnvironment = false;
    EnvironmentLight m_environment;
    Distribution2D m_environmentDistribution;  // over the map's texels, weighted by sin θ
    Distribution1D m_anySelection;       // over [triangles..., suns..., environment]
    Distribution1D m_extendedSelection;  // over [triangles..., environment]
};

}  // namespace gibench
