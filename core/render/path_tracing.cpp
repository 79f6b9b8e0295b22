#include "core/render/path_tracing.h"

#include <algorithm>
#include <cmath>

namespace gibench {

namespace {

// A light sample's f · L · cos and the shadow ray that decides whether it arrives; false when it
// adds nothing whatever the ray finds (no ray is traced then).
bool unshadowedLight(const SurfacePoint& p, const Bsdf& bsdf, const vec3& wo, const LightSample& ls, Color& fL, ShadowRay& shadow) {
    if (!(ls.pdf > 0.0f) || maxComponent(ls.radiance) <= 0.0f) return false;
    const Color f = bsdf.eval(wo, ls.wi) * std::fabs(glm::dot(ls.wi, p.shadingNormal));
    if (maxComponent(f) <= 0.0f) return false;
    shadow = std::isfinite(ls.distance) ? shadowRayBetween(p.position, p.positionError, p.geometricNormal, ls.point, ls.pointError, ls.lightNormal)
                                        : shadowRayTowards(p.position, p.positionError, p.geometricNormal, ls.wi);
    fL = f * ls.radiance;
    return true;
}

// What an arriving light sample adds: f · L · cos / pdf, MIS-weighted against BSDF sampling when
// that follows and the light has extent.
Color weightedLight(const Color& fL, const Bsdf& bsdf, const vec3& wo, const LightSample& ls, bool bsdfSamplingFollows) {
    const float weight = ls.isDelta || !bsdfSamplingFollows ? 1.0f : powerHeuristic(ls.pdf, bsdf.pdf(wo, ls.wi));
    return fL * (weight / ls.pdf);
}

Color lightSampleContribution(const PreparedScene& ps, const SurfacePoint& p, const Bsdf& bsdf, const vec3& wo, const LightSample& ls,
                              uint32_t& rays, RayLog* log, bool bsdfSamplingFollows) {
    Color fL;
    ShadowRay shadow;
    if (!unshadowedLight(p, bsdf, wo, ls, fL, shadow)) return Color(0.0f);
    ++rays;
    if (log) log->shadow.push_back({shadow.ray, shadow.tMax});
    if (ps.tracer.occluded(shadow.ray, shadow.tMax)) return Color(0.0f);
    return weightedLight(fL, bsdf, wo, ls, bsdfSamplingFollows);
}

// Calls f(light sample) for the samples estimateDirect() takes at `p`, in the order it adds them.
template <class F>
void forEachDirectLightSample(const PreparedScene& ps, const SurfacePoint& p, const LightSampleUniforms& u, F&& f) {
    for (std::size_t i = 0; i < ps.lights.sunCount(); ++i) f(ps.lights.sun(i));
    f(ps.lights.sampleExtended(p.position, u.select, u.u));
}

}  // namespace

Color estimateDirect(const PreparedScene& ps, const SurfacePoint& p, const Bsdf& bsdf, const vec3& wo, const LightSampleUniforms& u,
                     uint32_t& rays, RayLog* log, bool bsdfSamplingFollows) {
    Color sum(0.0f);
    if (!ps.plan.nextEventEstimation) return sum;
    forEachDirectLightSample(ps, p, u, [&](const LightSample& ls) { sum += lightSampleContribution(ps, p, bsdf, wo, ls, rays, log, bsdfSamplingFollows); });
    return sum;
}

void DirectLightBatch::add(const SurfacePoint& p, const Bsdf& bsdf, const vec3& wo, const LightSampleUniforms& u, bool bsdfSamplingFollows,
                           Color& target) {
    if (!m_scene.plan.nextEventEstimation) return;
    forEachDirectLightSample(m_scene, p, u, [&](const LightSample& ls) {
        Color fL;
        if (!unshadowedLight(p, bsdf, wo, ls, fL, m_shadows[m_count])) return;
        m_pending[m_count] = {weightedLight(fL, bsdf, wo, ls, bsdfSamplingFollows), &target};
        if (++m_count == RayTracer::kPacketSize) flush();
    });
}

void DirectLightBatch::flush() {
    if (m_count == 0) return;
    bool blocked[RayTracer::kPacketSize];
    m_scene.tracer.occluded(m_shadows, m_count, blocked);
    for (int i = 0; i < m_count; ++i)
        if (!blocked[i]) *m_pending[i].target += m_pending[i].contribution;
    m_rays += uint32_t(m_count);
    m_count = 0;
}

template <PathSampler Sampler>
PathResult tracePath(const PreparedScene& ps, const Ray& cameraRay, Sampler& sampler, const PathSettings& settings, RayLog* log,
                     const RayHit* cameraHit) {
    PathResult result;
    Color beta(1.0f);
    Ray ray = cameraRay;
    float previousBsdfPdf = 0.0f;
    vec3 previousPosition = ray.origin;

    // Light that reaches the vertex of index `receiver` (0 = camera, 1 = first hit, ...).
    auto add = [&](int receiver, const Color& radiance) {
        (receiver <= 1 ? result.direct : result.indirect) += radiance;
    };

    for (int depth = 0;; ++depth) {
        if (log) log->closest.push_back(ray);
        const RayHit hit = depth == 0 && cameraHit ? *cameraHit : ps.tracer.intersect(ray);
        ++result.rays;
        if (!hit.found()) {
            if (ps.plan.environmentLookup) {
                const float weight = depth == 0 ? 1.0f : powerHeuristic(previousBsdfPdf, ps.lights.pdfEnvironment(ray.direction));
                add(depth, beta * ps.lights.environmentRadiance(ray.direction) * weight);
            }
            break;
        }
        const SurfacePoint p = surfaceAt(ps.triangles, ray, hit);
        const Color albedo = albedoAt(ps, p);
        if (depth == 0) {
            result.albedo = albedo;
            result.normal = p.shadingNormal;
            result.depth = hit.t;
        }
        const Color emitted = p.emitted();
        if (maxComponent(emitted) > 0.0f) {
            const float weight = depth == 0 ? 1.0f : powerHeuristic(previousBsdfPdf, ps.lights.pdfTriangle(p, previousPosition));
            add(depth, beta * emitted * weight);
        }
        if (depth == settings.maxDepth) break;

        const vec3 wo = -ray.direction;
        const Bsdf bsdf(*p.material, albedo, p);
        add(depth + 1, beta * estimateDirect(ps, p, bsdf, wo, sampler.light(depth), result.rays, log));

        const BsdfSampleUniforms u = sampler.bsdf(depth);
        const BsdfSample bs = bsdf.sample(wo, u.lobe, u.u);
        if (!(bs.pdf > 0.0f)) break;
        beta *= bs.f * (std::fabs(glm::dot(bs.wi, p.shadingNormal)) / bs.pdf);
        if (maxComponent(beta) <= 0.0f) break;
        previousBsdfPdf = bs.pdf;
        previousPosition = p.position;
        ray = {offsetRayOrigin(p.position, p.positionError, p.geometricNormal), bs.wi};

        if (depth + 1 >= settings.russianRouletteDepth) {
            const float survive = maxComponent(beta);
            if (survive < 1.0f) {
                if (sampler.russianRoulette(depth) >= survive) break;
                beta /= survive;
            }
        }
    }
    return result;
}

template PathResult tracePath(const PreparedScene&, const Ray&, IndependentSampler&, const PathSettings&, RayLog*, const RayHit*);
template PathResult tracePath(const PreparedScene&, const Ray&, SobolSampler&, const PathSettings&, RayLog*, const RayHit*);

}  // namespace gibench
