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
    f(ps.lights.sampleExtended(p.position, p.shadingNormal, u.select, u.u));
}

}  // namespace

Color estimateDirect(const PreparedScene& ps, const SurfacePoint& p, const Bsdf& bsdf, const vec3& wo, const LightSampleUniforms& u,
                     uint32_t& rays, RayLog* log, bool bsdfSamplingFollows) {
    Color sum(0.0f);
    if (!ps.plan.nextEventEstimation) return sum;
    forEachDirectLightSample(ps, p, u, [&](const LightSample& ls) { sum += lightSampleContribution(ps, p, bsdf, wo, ls, rays, log, bsdfSamplingFollows); });
    return sum;
}

namespace {

// What unshadowedLight() and weightedLight() give for the light sample `ls` at a point with a
// Lambertian BSDF of `albedo` (Bsdf::eval and Bsdf::pdf without a specular lobe), in the same
// arithmetic and without branches, for the lanes: `arrives` all ones where unshadowedLight() is
// true, then `shadow` and `contribution` its ray and what weightedLight() adds. `misWeighted`:
// all ones where BSDF sampling follows and the light is not a delta light.
struct LaneLight {
    uint32_t arrives;
    ShadowRay shadow;
    Color contribution;
};
inline LaneLight lambertianLight(const vec3& position, const vec3& positionError, const vec3& ng, const vec3& ns, const vec3& wo, const Color& albedo,
                                 const LightSample& ls, uint32_t misWeighted) {
    // Bsdf::eval's and Bsdf::pdf's conditions: both directions on the geometric normal's side,
    // then above the shading normal (the local frame's z).
    const float cosO = glm::dot(wo, ns), cosI = glm::dot(ls.wi, ns);
    const uint32_t reflects = laneMask(glm::dot(ls.wi, ng) > 0.0f) & laneMask(glm::dot(wo, ng) > 0.0f) & ~laneMask(cosO <= 0.0f) & ~laneMask(cosI <= 0.0f);
    const Color diffuse = albedo * kInvPi;
    const Color f =
        Color(laneSelect(reflects, diffuse.x, 0.0f), laneSelect(reflects, diffuse.y, 0.0f), laneSelect(reflects, diffuse.z, 0.0f)) * std::fabs(cosI);
    const float bsdfPdf = laneSelect(reflects & laneMask(cosI > 0.0f), cosI * kInvPi, 0.0f);
    const ShadowRay between = shadowRayBetween(position, positionError, ng, ls.point, ls.pointError, ls.lightNormal);
    const ShadowRay towards = shadowRayTowards(position, positionError, ng, ls.wi);
    const uint32_t finite = laneMask(std::isfinite(ls.distance));
    const auto pick = [finite](vec3 a, vec3 b) { return laneSelect(finite, a, b); };
    LaneLight out;
    out.arrives = laneMask(ls.pdf > 0.0f) & ~laneMask(maxComponent(ls.radiance) <= 0.0f) & ~laneMask(maxComponent(f) <= 0.0f);
    out.shadow = {{pick(between.ray.origin, towards.ray.origin), pick(between.ray.direction, towards.ray.direction)},
                  laneSelect(finite, between.tMax, towards.tMax)};
    const float weight = laneSelect(misWeighted, powerHeuristic(ls.pdf, bsdfPdf), 1.0f);
    out.contribution = f * ls.radiance * (weight / ls.pdf);
    return out;
}

// lambertianLight() at lane k's receiver of lanes `l` (TriangleLightLanes or DistantLightLanes),
// written into its outputs. Always inlined: left as a call, the triangle lanes' loop stayed scalar.
template <class Lanes>
[[gnu::always_inline]] inline void takeLaneLight(Lanes& l, int k, const LightSample& ls, uint32_t misWeighted) {
    const DirectLightBatch::ReceiverLanes& r = l.receiver;
    const LaneLight light = lambertianLight(laneVector(r.position, k), laneVector(r.positionError, k), laneVector(r.geometricNormal, k),
                                            laneVector(r.shadingNormal, k), laneVector(r.wo, k), laneVector(r.albedo, k), ls, misWeighted);
    l.arrives[k] = light.arrives;
    setLaneVector(l.origin, k, light.shadow.ray.origin);
    setLaneVector(l.direction, k, light.shadow.ray.direction);
    l.tMax[k] = light.shadow.tMax;
    setLaneVector(l.contribution, k, light.contribution);
}

// Each lane's sampleEmissiveTriangle(), then lambertianLight().
GIBENCH_SIMD_CLONES void takeTriangleLights(DirectLightBatch::TriangleLightLanes& l) {
    for (int k = 0; k < DirectLightBatch::kLanes; ++k) {
        const EmissiveTriangle e{{laneVector(l.vertices[0], k), laneVector(l.vertices[1], k), laneVector(l.vertices[2], k)},
                                 laneVector(l.lightNormal, k), l.area[k], laneVector(l.emission, k)};
        const LightSample ls = sampleEmissiveTriangle(e, l.select[k], laneVector(l.receiver.position, k), vec2(l.u[0][k], l.u[1][k]));
        takeLaneLight(l, k, ls, l.misWeighted[k]);
    }
}

// Each lane's lambertianLight() of its sun or environment sample, the constant environment's
// sampled first where the lane holds one.
GIBENCH_SIMD_CLONES void takeDistantLights(DirectLightBatch::DistantLightLanes& l) {
    for (int k = 0; k < DirectLightBatch::kLanes; ++k) {
        LightSample ls;
        ls.distance = kInfinity;
        ls.radiance = laneVector(l.radiance, k);
        const LightSample environment =
            sampleConstantEnvironment(laneVector(l.receiver.shadingNormal, k), ls.radiance, l.select[k], vec2(l.u[0][k], l.u[1][k]));
        ls.wi = laneSelect(l.constantEnvironment[k], environment.wi, laneVector(l.wi, k));
        ls.pdf = laneSelect(l.constantEnvironment[k], environment.pdf, l.pdf[k]);
        takeLaneLight(l, k, ls, l.misWeighted[k]);
    }
}

}  // namespace

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
    addWith(p, bsdf.albedo(), !bsdf.hasSpecular(), [&]() -> const Bsdf& { return bsdf; }, wo, u, bsdfSamplingFollows, target, rays);
}

void DirectLightBatch::addLambertian(const SurfacePoint& p, const Color& albedo, const vec3& wo, const LightSampleUniforms& u, bool bsdfSamplingFollows,
                                     Color& target, uint32_t* rays) {
    // Built only for a sample that takes the scalar path, each time it does (once per sun at
    // most): an empty std::optional<Bsdf> here was zero-filled on every call, a third of the
    // function's time.
    addWith(p, albedo, true, [&] { return Bsdf(*p.material, albedo, p); }, wo, u, bsdfSamplingFollows, target, rays);
}

template <class BsdfOf>
void DirectLightBatch::addWith(const SurfacePoint& p, const Color& albedo, bool lambertian, BsdfOf&& bsdfOf, const vec3& wo,
                               const LightSampleUniforms& u, bool bsdfSamplingFollows, Color& target, uint32_t* rays) {
    if (!m_scene.plan.nextEventEstimation) return;
    const LightSampler& lights = m_scene.lights;
    const auto take = [&](const LightSample& ls) {
        if (lambertian && !std::isfinite(ls.distance)) return addDistant(p, albedo, wo, ls, bsdfSamplingFollows, target, rays);
        const auto& bsdf = bsdfOf();  // the caller's Bsdf, or one built now and kept to the end of the scope
        Color fL;
        ShadowRay shadow;
        if (unshadowedLight(p, bsdf, wo, ls, fL, shadow)) queue(shadow, weightedLight(fL, bsdf, wo, ls, bsdfSamplingFollows), target, rays);
    };
    for (std::size_t i = 0; i < lights.sunCount(); ++i) take(lights.sun(i));
    const LightSampler::ExtendedChoice choice = lambertian ? lights.chooseExtended(u.select) : LightSampler::ExtendedChoice{};
    if (choice.constantEnvironment) return addConstantEnvironment(p, albedo, wo, choice.select, u.u, bsdfSamplingFollows, target, rays);
    const EmissiveTriangle* triangle = choice.triangle;
    if (!triangle) {
        take(lights.sampleExtended(p.position, p.shadingNormal, u.select, u.u));
        return;
    }
    TriangleLightLanes& l = m_lane;
    const int k = m_lanes;
    l.receiver.set(k, p, wo, albedo);
    l.u[0][k] = u.u.x;
    l.u[1][k] = u.u.y;
    l.select[k] = choice.select;
    l.misWeighted[k] = laneMask(bsdfSamplingFollows);
    for (int v = 0; v < 3; ++v) setLaneVector(l.vertices[v], k, triangle->vertices[v]);
    setLaneVector(l.lightNormal, k, triangle->normal);
    l.area[k] = triangle->area;
    setLaneVector(l.emission, k, triangle->emission);
    m_laneTargets[k] = &target;
    m_laneRays[k] = rays;
    if (++m_lanes == kLanes) takeLanes();
}

void DirectLightBatch::addDistant(const SurfacePoint& p, const Color& albedo, const vec3& wo, const LightSample& ls, bool bsdfSamplingFollows,
                                  Color& target, uint32_t* rays) {
    DistantLightLanes& l = m_distant;
    const int k = m_distantLanes;
    setLaneVector(l.wi, k, ls.wi);
    setLaneVector(l.radiance, k, ls.radiance);
    l.pdf[k] = ls.pdf;
    l.misWeighted[k] = laneMask(bsdfSamplingFollows && !ls.isDelta);
    l.constantEnvironment[k] = 0;
    takeDistantLane(p, albedo, wo, target, rays);
}

void DirectLightBatch::addConstantEnvironment(const SurfacePoint& p, const Color& albedo, const vec3& wo, float select, const vec2& u,
                                              bool bsdfSamplingFollows, Color& target, uint32_t* rays) {
    DistantLightLanes& l = m_distant;
    const int k = m_distantLanes;
    setLaneVector(l.radiance, k, m_scene.lights.constantEnvironmentRadiance());
    l.u[0][k] = u.x;
    l.u[1][k] = u.y;
    l.select[k] = select;
    l.misWeighted[k] = laneMask(bsdfSamplingFollows);
    l.constantEnvironment[k] = ~0u;
    takeDistantLane(p, albedo, wo, target, rays);
}

void DirectLightBatch::takeDistantLane(const SurfacePoint& p, const Color& albedo, const vec3& wo, Color& target, uint32_t* rays) {
    const int k = m_distantLanes;
    m_distant.receiver.set(k, p, wo, albedo);
    m_distantTargets[k] = &target;
    m_distantRays[k] = rays;
    if (++m_distantLanes == kLanes) takeLanes();
}

namespace {

// Queues the shadow rays of the first `count` of lanes `l` that arrive.
template <class Lanes, class Queue>
void queueArriving(const Lanes& l, int count, Color* const* targets, uint32_t* const* rays, Queue&& queue) {
    for (int k = 0; k < count; ++k) {
        if (!l.arrives[k]) continue;
        queue(ShadowRay{{laneVector(l.origin, k), laneVector(l.direction, k)}, l.tMax[k]}, laneVector(l.contribution, k), *targets[k], rays[k]);
    }
}

}  // namespace

void DirectLightBatch::takeLanes() {
    // Unused lanes hold an earlier sample's numbers (or zeros), computed and not read.
    const auto queueRay = [this](const ShadowRay& shadow, const Color& contribution, Color& target, uint32_t* rays) {
        queue(shadow, contribution, target, rays);
    };
    if (m_distantLanes > 0) {
        takeDistantLights(m_distant);
        queueArriving(m_distant, m_distantLanes, m_distantTargets, m_distantRays, queueRay);
        m_distantLanes = 0;
    }
    if (m_lanes > 0) {
        takeTriangleLights(m_lane);
        queueArriving(m_lane, m_lanes, m_laneTargets, m_laneRays, queueRay);
        m_lanes = 0;
    }
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
    vec3 previousNormal{0.0f};  // the previous vertex's shading normal (LightSampler::pdfEnvironment)
    // This vertex's light sample, filled in as the batch's shadow rays come back, and the
    // throughput it is weighted by (beta before the BSDF sample).
    bool sampledLight = false;
    Color light{0.0f};
    Color lightBeta{0.0f};
};

// tracePaths()' arrays of a wave of paths, one element per path.
struct WaveArrays {
    std::vector<LivePath> live;
    std::vector<Ray> rays;
    std::vector<RayHit> hits;
    std::vector<char> goesOn;

    void resize(std::size_t n) {
        live.resize(n);
        rays.resize(n);
        hits.resize(n);
        goesOn.resize(n);
    }
};

// Light that reaches the vertex of index `receiver` (0 = camera, 1 = first hit, ...).
void addArriving(PathResult& result, int receiver, const Color& radiance) {
    (receiver <= 1 ? result.direct : result.indirect) += radiance;
}

// The path leaves its vertex at `position`, of shading normal `normal`, along a BSDF sample:
// direction `wi` of density `pdf`, throughput factor f·cos / pdf, from `origin`; then Russian
// roulette. False when it ends.
template <PathSampler Sampler>
bool leave(LivePath& path, Sampler& sampler, const vec3& wi, float pdf, const Color& factor, const vec3& position, const vec3& normal,
           const vec3& origin, int depth, const PathSettings& settings) {
    if (!(pdf > 0.0f)) return false;
    path.beta *= factor;
    if (maxComponent(path.beta) <= 0.0f) return false;
    path.previousBsdfPdf = pdf;
    path.previousPosition = position;
    path.previousNormal = normal;
    path.ray = {origin, wi};
    if (depth + 1 >= settings.russianRouletteDepth) {
        const float survive = maxComponent(path.beta);
        if (survive < 1.0f) {
            if (sampler.russianRoulette(depth) >= survive) return false;
            path.beta /= survive;
        }
    }
    return true;
}

// Lambertian vertices of a wave waiting to leave, one per lane, coordinates by lane: their
// BSDF samples are taken kLanes at a time (sampleLambertianLanes()), whose chain of polynomial,
// division and square root, one vertex at a time, was a fifth of a path's shading.
struct LambertianLanes {
    static constexpr int kLanes = 8;
    // In: the vertex and its BSDF sample's numbers.
    float shadingNormal[3][kLanes], geometricNormal[3][kLanes], wo[3][kLanes], albedo[3][kLanes], u[2][kLanes];
    float position[3][kLanes], positionError[3][kLanes];
    // Out: leave()'s arguments.
    float wi[3][kLanes], factor[3][kLanes], pdf[kLanes], origin[3][kLanes];
    int path[kLanes];  // the lane's path in the wave
    int count = 0;
};

// sampleLambertian() in every lane, with the throughput factor and the ray's origin as leave()
// takes them from Bsdf::sample().
GIBENCH_SIMD_CLONES void sampleLambertianLanes(LambertianLanes& l) {
    for (int k = 0; k < LambertianLanes::kLanes; ++k) {
        const vec3 ns = laneVector(l.shadingNormal, k), ng = laneVector(l.geometricNormal, k);
        const BsdfSample bs = sampleLambertian(Frame(ns), ng, laneVector(l.albedo, k), laneVector(l.wo, k), vec2(l.u[0][k], l.u[1][k]));
        setLaneVector(l.wi, k, bs.wi);
        setLaneVector(l.factor, k, bs.f * (std::fabs(glm::dot(bs.wi, ns)) / bs.pdf));
        l.pdf[k] = bs.pdf;
        setLaneVector(l.origin, k, offsetRayOrigin(laneVector(l.position, k), laneVector(l.positionError, k), ng));
    }
}

// What scatter() left the path to: nothing more, the next ray, or a BSDF sample in `lanes`.
enum class Scattered { Ends, GoesOn, Waits };

// The path's vertex at `depth`, found by `hit`: adds what the vertex's emission sends to the
// camera, queues its light sample's shadow rays in `batch`, and samples the BSDF for the next
// ray, a Lambertian one in `lanes` (path `k` of the wave).
template <PathSampler Sampler>
Scattered scatter(const PreparedScene& ps, LivePath& path, Sampler& sampler, const RayHit& hit, int depth, const PathSettings& settings,
                  DirectLightBatch& batch, PathResult& result, LambertianLanes& lanes, int k) {
    const Ray& ray = path.ray;
    if (!hit.found()) {
        if (ps.plan.environmentLookup) {
            const float weight = depth == 0 ? 1.0f : powerHeuristic(path.previousBsdfPdf, ps.lights.pdfEnvironment(ray.direction, path.previousNormal));
            addArriving(result, depth, path.beta * ps.lights.environmentRadiance(ray.direction) * weight);
        }
        return Scattered::Ends;
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
    if (depth == settings.maxDepth) return Scattered::Ends;

    const vec3 wo = -ray.direction;
    path.sampledLight = true;
    path.light = Color(0.0f);
    path.lightBeta = path.beta;
    // A Lambertian vertex needs no Bsdf (its frame was more than 1 % of the Cornell box's tracing).
    if (!(Bsdf::specularProbability(*p.material, albedo) > 0.0f)) {
        batch.addLambertian(p, albedo, wo, sampler.light(depth), true, path.light, &result.rays);
        const BsdfSampleUniforms u = sampler.bsdf(depth);
        const int lane = lanes.count++;
        setLaneVector(lanes.shadingNormal, lane, p.shadingNormal);
        setLaneVector(lanes.geometricNormal, lane, p.geometricNormal);
        setLaneVector(lanes.wo, lane, wo);
        setLaneVector(lanes.albedo, lane, albedo);
        lanes.u[0][lane] = u.u.x;
        lanes.u[1][lane] = u.u.y;
        setLaneVector(lanes.position, lane, p.position);
        setLaneVector(lanes.positionError, lane, p.positionError);
        lanes.path[lane] = k;
        return Scattered::Waits;
    }
    const Bsdf bsdf(*p.material, albedo, p);
    batch.add(p, bsdf, wo, sampler.light(depth), true, path.light, &result.rays);
    const BsdfSampleUniforms u = sampler.bsdf(depth);
    const BsdfSample bs = bsdf.sample(wo, u.lobe, u.u);
    if (!(bs.pdf > 0.0f)) return Scattered::Ends;
    const Color factor = bs.f * (std::fabs(glm::dot(bs.wi, p.shadingNormal)) / bs.pdf);
    return leave(path, sampler, bs.wi, bs.pdf, factor, p.position, p.shadingNormal, offsetRayOrigin(p.position, p.positionError, p.geometricNormal), depth, settings)
               ? Scattered::GoesOn
               : Scattered::Ends;
}

}  // namespace

template <PathSampler Sampler>
void tracePaths(const PreparedScene& ps, const Ray* cameraRays, Sampler* samplers, int n, const PathSettings& settings, PathResult* results,
                RayLog* log) {
    // The wave's arrays outlive the call on each thread: allocated and value-initialised per
    // call (a `rep stos` per path), they were half a percent of the Cornell box's tracing.
    static thread_local WaveArrays arrays;
    arrays.resize(std::size_t(n));
    std::vector<LivePath>& live = arrays.live;
    std::vector<Ray>& rays = arrays.rays;
    std::vector<RayHit>& hits = arrays.hits;
    std::vector<char>& goesOn = arrays.goesOn;
    for (int i = 0; i < n; ++i) {
        results[i] = PathResult{};
        live[i] = LivePath{};
        live[i].index = i;
        live[i].ray = cameraRays[i];
        live[i].previousPosition = cameraRays[i].origin;
    }
    DirectLightBatch batch(ps, log);
    LambertianLanes lanes{};
    int count = n;
    for (int depth = 0; count > 0; ++depth) {
        for (int k = 0; k < count; ++k) rays[k] = live[k].ray;
        if (log) log->closest.insert(log->closest.end(), rays.begin(), rays.begin() + count);
        // Packets even of one ray, so that a path finds the same hits whatever paths it goes with.
        // Past the camera rays the packets are incoherent; Embree's packet traversal for
        // coherent rays made the Cornell box's paths slower (docs/ground_truth.md).
        for (int k = 0; k < count; k += RayTracer::kPacketSize) {
            const int packet = std::min(RayTracer::kPacketSize, count - k);
            ps.tracer.intersect(&rays[k], packet, &hits[k], depth == 0);
            for (int i = k; i < k + packet; ++i)
                if (hits[i].found()) ps.triangles.prefetch(hits[i].mesh, hits[i].triangle);
        }
        // The waiting Lambertian vertices leave as soon as a full set of lanes is sampled: a
        // path's Russian roulette still draws its number after its BSDF sample's.
        const auto leaveFromLanes = [&] {
            if (lanes.count == 0) return;
            sampleLambertianLanes(lanes);  // unused lanes hold an earlier vertex's numbers, computed and not read
            for (int i = 0; i < lanes.count; ++i) {
                const int k = lanes.path[i];
                LivePath& path = live[k];
                goesOn[k] = leave(path, samplers[path.index], laneVector(lanes.wi, i), lanes.pdf[i], laneVector(lanes.factor, i),
                                  laneVector(lanes.position, i), laneVector(lanes.shadingNormal, i), laneVector(lanes.origin, i), depth, settings);
            }
            lanes.count = 0;
        };
        for (int k = 0; k < count; ++k) {
            LivePath& path = live[k];
            PathResult& result = results[path.index];
            ++result.rays;
            path.sampledLight = false;
            const Scattered scattered = scatter(ps, path, samplers[path.index], hits[k], depth, settings, batch, result, lanes, k);
            goesOn[k] = scattered == Scattered::GoesOn;
            if (lanes.count == LambertianLanes::kLanes) leaveFromLanes();
        }
        leaveFromLanes();
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
