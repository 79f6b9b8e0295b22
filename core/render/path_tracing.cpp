#include "core/render/path_tracing.h"

#include "core/util/lane_select.h"
#include "core/util/simd_clones.h"

#include <algorithm>
#include <cmath>
#include <vector>

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

// Each lane's sampleEmissiveTriangle(), then unshadowedLight() and weightedLight() with a
// Lambertian BSDF (Bsdf::eval and Bsdf::pdf without a specular lobe), in the same arithmetic.
GIBENCH_SIMD_CLONES void takeTriangleLights(DirectLightBatch::TriangleLightLanes& l) {
    for (int k = 0; k < DirectLightBatch::kLanes; ++k) {
        const auto lane = [k](const float (&c)[3][DirectLightBatch::kLanes]) { return vec3(c[0][k], c[1][k], c[2][k]); };
        const EmissiveTriangle e{{lane(l.vertices[0]), lane(l.vertices[1]), lane(l.vertices[2])}, lane(l.lightNormal), l.area[k], lane(l.emission)};
        const vec3 position = lane(l.position), positionError = lane(l.positionError), ng = lane(l.geometricNormal), ns = lane(l.shadingNormal);
        const vec3 wo = lane(l.wo);
        const LightSample ls = sampleEmissiveTriangle(e, l.select[k], position, vec2(l.u[0][k], l.u[1][k]));
        // Bsdf::eval's and Bsdf::pdf's conditions: both directions on the geometric normal's side,
        // then above the shading normal (the local frame's z).
        const float cosO = glm::dot(wo, ns), cosI = glm::dot(ls.wi, ns);
        const uint32_t reflects = laneMask(glm::dot(ls.wi, ng) > 0.0f) & laneMask(glm::dot(wo, ng) > 0.0f) & ~laneMask(cosO <= 0.0f) & ~laneMask(cosI <= 0.0f);
        const Color diffuse = lane(l.albedo) * kInvPi;
        const Color f = Color(laneSelect(reflects, diffuse.x, 0.0f), laneSelect(reflects, diffuse.y, 0.0f), laneSelect(reflects, diffuse.z, 0.0f)) *
                        std::fabs(cosI);
        const float bsdfPdf = laneSelect(reflects & laneMask(cosI > 0.0f), cosI * kInvPi, 0.0f);
        const ShadowRay between = shadowRayBetween(position, positionError, ng, ls.point, ls.pointError, ls.lightNormal);
        const ShadowRay towards = shadowRayTowards(position, positionError, ng, ls.wi);
        const uint32_t finite = laneMask(std::isfinite(ls.distance));
        l.arrives[k] = laneMask(ls.pdf > 0.0f) & ~laneMask(maxComponent(ls.radiance) <= 0.0f) & ~laneMask(maxComponent(f) <= 0.0f);
        // Coordinate by coordinate: a loop over them keeps the rays in memory, unvectorized.
        l.origin[0][k] = laneSelect(finite, between.ray.origin.x, towards.ray.origin.x);
        l.origin[1][k] = laneSelect(finite, between.ray.origin.y, towards.ray.origin.y);
        l.origin[2][k] = laneSelect(finite, between.ray.origin.z, towards.ray.origin.z);
        l.direction[0][k] = laneSelect(finite, between.ray.direction.x, towards.ray.direction.x);
        l.direction[1][k] = laneSelect(finite, between.ray.direction.y, towards.ray.direction.y);
        l.direction[2][k] = laneSelect(finite, between.ray.direction.z, towards.ray.direction.z);
        l.tMax[k] = laneSelect(finite, between.tMax, towards.tMax);
        const float weight = laneSelect(l.misWeighted[k], powerHeuristic(ls.pdf, bsdfPdf), 1.0f);
        const Color contribution = f * ls.radiance * (weight / ls.pdf);
        l.contribution[0][k] = contribution.x;
        l.contribution[1][k] = contribution.y;
        l.contribution[2][k] = contribution.z;
    }
}

void DirectLightBatch::queue(const ShadowRay& shadow, const Color& contribution, Color& target, uint32_t* rays) {
    m_shadows[m_count] = shadow;
    if (m_log) m_log->shadow.push_back({shadow.ray, shadow.tMax});
    m_pending[m_count] = {contribution, &target};
    if (rays) ++*rays;
    if (++m_count == RayTracer::kPacketSize) traceQueued();
}

void DirectLightBatch::traceQueued() {
    if (m_count == 0) return;
    bool blocked[RayTracer::kPacketSize];
    m_scene.tracer.occluded(m_shadows, m_count, blocked);
    for (int i = 0; i < m_count; ++i)
        if (!blocked[i]) *m_pending[i].target += m_pending[i].contribution;
    m_rays += uint32_t(m_count);
    m_count = 0;
}

void DirectLightBatch::add(const SurfacePoint& p, const Bsdf& bsdf, const vec3& wo, const LightSampleUniforms& u, bool bsdfSamplingFollows,
                           Color& target, uint32_t* rays) {
    if (!m_scene.plan.nextEventEstimation) return;
    const LightSampler& lights = m_scene.lights;
    const auto takeAlone = [&](const LightSample& ls) {
        Color fL;
        ShadowRay shadow;
        if (unshadowedLight(p, bsdf, wo, ls, fL, shadow)) queue(shadow, weightedLight(fL, bsdf, wo, ls, bsdfSamplingFollows), target, rays);
    };
    for (std::size_t i = 0; i < lights.sunCount(); ++i) takeAlone(lights.sun(i));
    float select;
    const EmissiveTriangle* triangle = lights.emissiveTriangleCount() > 0 && !bsdf.hasSpecular() ? lights.extendedTriangle(u.select, select) : nullptr;
    if (!triangle) {
        takeAlone(lights.sampleExtended(p.position, u.select, u.u));
        return;
    }
    TriangleLightLanes& l = m_lane;
    const int k = m_lanes;
    const auto set = [k](float (&c)[3][kLanes], const vec3& v) {
        for (int a = 0; a < 3; ++a) c[a][k] = v[a];
    };
    set(l.position, p.position);
    set(l.positionError, p.positionError);
    set(l.geometricNormal, p.geometricNormal);
    set(l.shadingNormal, p.shadingNormal);
    set(l.wo, wo);
    set(l.albedo, bsdf.albedo());
    l.u[0][k] = u.u.x;
    l.u[1][k] = u.u.y;
    l.select[k] = select;
    l.misWeighted[k] = laneMask(bsdfSamplingFollows);
    for (int v = 0; v < 3; ++v) set(l.vertices[v], triangle->vertices[v]);
    set(l.lightNormal, triangle->normal);
    l.area[k] = triangle->area;
    set(l.emission, triangle->emission);
    m_laneTargets[k] = &target;
    m_laneRays[k] = rays;
    if (++m_lanes == kLanes) takeLanes();
}

void DirectLightBatch::takeLanes() {
    if (m_lanes == 0) return;
    // Unused lanes hold an earlier sample's numbers (or zeros), computed and not read.
    takeTriangleLights(m_lane);
    const TriangleLightLanes& l = m_lane;
    for (int k = 0; k < m_lanes; ++k) {
        if (!l.arrives[k]) continue;
        const ShadowRay shadow{{vec3(l.origin[0][k], l.origin[1][k], l.origin[2][k]), vec3(l.direction[0][k], l.direction[1][k], l.direction[2][k])},
                               l.tMax[k]};
        queue(shadow, Color(l.contribution[0][k], l.contribution[1][k], l.contribution[2][k]), *m_laneTargets[k], m_laneRays[k]);
    }
    m_lanes = 0;
}

void DirectLightBatch::flush() {
    takeLanes();
    traceQueued();
}

namespace {

// What a path carries from one scattering vertex to the next while it is traced with others.
struct LivePath {
    int index;  // into the caller's arrays
    Ray ray;
    Color beta{1.0f};
    float previousBsdfPdf = 0.0f;
    vec3 previousPosition{0.0f};
    // This vertex's light sample, filled in as the batch's shadow rays come back, and the
    // throughput it is weighted by (beta before the BSDF sample).
    bool sampledLight = false;
    Color light{0.0f};
    Color lightBeta{0.0f};
};

// Light that reaches the vertex of index `receiver` (0 = camera, 1 = first hit, ...).
void addArriving(PathResult& result, int receiver, const Color& radiance) {
    (receiver <= 1 ? result.direct : result.indirect) += radiance;
}

// The path's vertex at `depth`, found by `hit`: adds what the vertex's emission sends to the
// camera, queues its light sample's shadow rays in `batch`, and samples the BSDF for the next
// ray. False when the path ends here.
template <PathSampler Sampler>
bool scatter(const PreparedScene& ps, LivePath& path, Sampler& sampler, const RayHit& hit, int depth, const PathSettings& settings,
             DirectLightBatch& batch, PathResult& result) {
    const Ray& ray = path.ray;
    if (!hit.found()) {
        if (ps.plan.environmentLookup) {
            const float weight = depth == 0 ? 1.0f : powerHeuristic(path.previousBsdfPdf, ps.lights.pdfEnvironment(ray.direction));
            addArriving(result, depth, path.beta * ps.lights.environmentRadiance(ray.direction) * weight);
        }
        return false;
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
        const float weight = depth == 0 ? 1.0f : powerHeuristic(path.previousBsdfPdf, ps.lights.pdfTriangle(p, path.previousPosition));
        addArriving(result, depth, path.beta * emitted * weight);
    }
    if (depth == settings.maxDepth) return false;

    const vec3 wo = -ray.direction;
    const Bsdf bsdf(*p.material, albedo, p);
    path.sampledLight = true;
    path.light = Color(0.0f);
    path.lightBeta = path.beta;
    batch.add(p, bsdf, wo, sampler.light(depth), true, path.light, &result.rays);

    const BsdfSampleUniforms u = sampler.bsdf(depth);
    const BsdfSample bs = bsdf.sample(wo, u.lobe, u.u);
    if (!(bs.pdf > 0.0f)) return false;
    path.beta *= bs.f * (std::fabs(glm::dot(bs.wi, p.shadingNormal)) / bs.pdf);
    if (maxComponent(path.beta) <= 0.0f) return false;
    path.previousBsdfPdf = bs.pdf;
    path.previousPosition = p.position;
    path.ray = {offsetRayOrigin(p.position, p.positionError, p.geometricNormal), bs.wi};

    if (depth + 1 >= settings.russianRouletteDepth) {
        const float survive = maxComponent(path.beta);
        if (survive < 1.0f) {
            if (sampler.russianRoulette(depth) >= survive) return false;
            path.beta /= survive;
        }
    }
    return true;
}

}  // namespace

template <PathSampler Sampler>
void tracePaths(const PreparedScene& ps, const Ray* cameraRays, Sampler* samplers, int n, const PathSettings& settings, PathResult* results,
                RayLog* log) {
    std::vector<LivePath> live(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        results[i] = PathResult{};
        live[i].index = i;
        live[i].ray = cameraRays[i];
        live[i].previousPosition = cameraRays[i].origin;
    }
    std::vector<Ray> rays(static_cast<std::size_t>(n));
    std::vector<RayHit> hits(static_cast<std::size_t>(n));
    std::vector<char> goesOn(static_cast<std::size_t>(n));
    DirectLightBatch batch(ps, log);
    int count = n;
    for (int depth = 0; count > 0; ++depth) {
        for (int k = 0; k < count; ++k) rays[k] = live[k].ray;
        if (log) log->closest.insert(log->closest.end(), rays.begin(), rays.begin() + count);
        // Packets even of one ray, so that a path finds the same hits whatever paths it goes with.
        // Past the camera rays the packets are incoherent; Embree's packet traversal for
        // coherent rays made the Cornell box's paths slower (docs/ground_truth.md).
        for (int k = 0; k < count; k += RayTracer::kPacketSize)
            ps.tracer.intersect(&rays[k], std::min(RayTracer::kPacketSize, count - k), &hits[k], depth == 0);
        for (int k = 0; k < count; ++k) {
            LivePath& path = live[k];
            PathResult& result = results[path.index];
            ++result.rays;
            path.sampledLight = false;
            goesOn[k] = scatter(ps, path, samplers[path.index], hits[k], depth, settings, batch, result);
        }
        batch.flush();
        int next = 0;
        for (int k = 0; k < count; ++k) {
            const LivePath& path = live[k];
            if (path.sampledLight) addArriving(results[path.index], depth + 1, path.lightBeta * path.light);
            if (goesOn[k]) live[next++] = path;
        }
        count = next;
    }
}

template <PathSampler Sampler>
PathResult tracePath(const PreparedScene& ps, const Ray& cameraRay, Sampler& sampler, const PathSettings& settings, RayLog* log) {
    PathResult result;
    tracePaths(ps, &cameraRay, &sampler, 1, settings, &result, log);
    return result;
}

template void tracePaths(const PreparedScene&, const Ray*, IndependentSampler*, int, const PathSettings&, PathResult*, RayLog*);
template void tracePaths(const PreparedScene&, const Ray*, SobolSampler*, int, const PathSettings&, PathResult*, RayLog*);
template PathResult tracePath(const PreparedScene&, const Ray&, IndependentSampler&, const PathSettings&, RayLog*);
template PathResult tracePath(const PreparedScene&, const Ray&, SobolSampler&, const PathSettings&, RayLog*);

}  // namespace gibench
