#include "core/render/path_tracing.h"

#include <algorithm>
#include <cmath>

namespace gibench {

namespace {

// One light sample's contribution: f · L · cos / pdf if the light is visible, MIS-weighted
// against BSDF sampling when that follows and the light has extent.
Color lightSampleContribution(const PreparedScene& ps, const SurfacePoint& p, const Bsdf& bsdf, const vec3& wo, const LightSample& ls,
                              uint32_t& rays, RayLog* log, bool bsdfSamplingFollows) {
    if (!(ls.pdf > 0.0f) || maxComponent(ls.radiance) <= 0.0f) return Color(0.0f);
    const Color f = bsdf.eval(wo, ls.wi) * std::fabs(glm::dot(ls.wi, p.shadingNormal));
    if (maxComponent(f) <= 0.0f) return Color(0.0f);

    const ShadowRay shadow = std::isfinite(ls.distance) ? shadowRayBetween(p.position, p.positionError, p.geometricNormal, ls.point, ls.pointError, ls.lightNormal)
                                                        : shadowRayTowards(p.position, p.positionError, p.geometricNormal, ls.wi);
    ++rays;
    if (log) log->shadow.push_back({shadow.ray, shadow.tMax});
    if (ps.tracer.occluded(shadow.ray, shadow.tMax)) return Color(0.0f);
    const float weight = ls.isDelta || !bsdfSamplingFollows ? 1.0f : powerHeuristic(ls.pdf, bsdf.pdf(wo, ls.wi));
    return f * ls.radiance * (weight / ls.pdf);
}

}  // namespace

Color estimateDirect(const PreparedScene& ps, const SurfacePoint& p, const Bsdf& bsdf, const vec3& wo, const LightSampleUniforms& u,
                     uint32_t& rays, RayLog* log, bool bsdfSamplingFollows) {
    if (!ps.plan.nextEventEstimation) return Color(0.0f);
    Color sum(0.0f);
    for (std::size_t i = 0; i < ps.lights.sunCount(); ++i)
        sum += lightSampleContribution(ps, p, bsdf, wo, ps.lights.sun(i), rays, log, bsdfSamplingFollows);
    return sum + lightSampleContribution(ps, p, bsdf, wo, ps.lights.sampleExtended(p.position, u.select, u.u), rays, log,
                                         bsdfSamplingFollows);
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
