#pragma once
// Unidirectional path tracing with next-event estimation and multiple importance sampling
// (power heuristic), Russian roulette, and a direct/indirect split of the result.
//
// Depth convention (pbrt's maxdepth): `maxDepth` counts scattering events. 0 = only emission seen
// by the camera; 1 = direct lighting (emission seen + light reaching the first hit);
// n = up to n − 1 indirect bounces, so Cycles' "max bounces = b" matches maxDepth = b + 1.
//
// Split: "direct" is emission seen by the camera plus light arriving at the first hit straight
// from an emitter (by NEE or by a BSDF-sampled ray, MIS-weighted); everything else is "indirect".

#include "core/render/bsdf.h"
#include "core/render/prepared_scene.h"
#include "core/render/sampler.h"
#include "core/scene/camera.h"
#include "core/util/lane_select.h"
#include "core/util/rng.h"

#include <utility>
#include <vector>

namespace gibench {

struct PathSettings {
    int maxDepth = 1024;
    int russianRouletteDepth = 3;  // roulette may end paths from this many scattering events on
};

struct PathResult {
    Color direct{0.0f};
    Color indirect{0.0f};
    // First-hit data (zero albedo and normal and infinite depth when the camera ray escapes).
    Color albedo{0.0f};
    vec3 normal{0.0f};
    float depth = kInfinity;  // distance from the ray origin to the first hit
    uint32_t rays = 0;         // closest-hit and shadow rays traced
};

// Every ray a path traced, in order: benchmarks replay them through bare Embree.
struct RayLog {
    std::vector<Ray> closest;
    std::vector<std::pair<Ray, float>> shadow;  // with its tMax
};

// One path from the camera ray, its random numbers from `sampler` (core/render/sampler.h; the
// camera jitter is the caller's): tracePaths() of one path. Defined for IndependentSampler and
// SobolSampler, as is tracePaths().
template <PathSampler Sampler>
PathResult tracePath(const PreparedScene& scene, const Ray& cameraRay, Sampler& sampler, const PathSettings& settings,
                     RayLog* log = nullptr);

// n paths, path i from cameraRays[i] with samplers[i], into results[i]: each path's result is,
// bit for bit, what it gets traced alone (the same random numbers, hits and additions in the same
// order: a lone path's rays go through the same packets, of one lane). The paths go
// bounce by bounce together (a wavefront): at each depth the closest hits of the live paths are
// found RayTracer::kPacketSize at a time, then every one is shaded, and their shadow rays go in
// packets too. Packets of even unrelated rays traverse faster than single rays on this machine
// (recorded rays of the Cornell box 1.3×, Sponza 1.07×, docs/ground_truth.md), and shading many
// paths in a row, no ray cast between them, lets their arithmetic overlap. Pass neighbouring
// pixels' paths: their camera rays share the packets' traversals.
template <PathSampler Sampler>
void tracePaths(const PreparedScene& scene, const Ray* cameraRays, Sampler* samplers, int n, const PathSettings& settings, PathResult* results,
                RayLog* log = nullptr);

// One path per pixel of [x0, x1) × [y0, y1) of an image `width` pixels wide seen through
// `camera`, traced together (tracePaths()) into results[i], the pixels row by row. Each path's
// numbers come from makeSampler(y · width + x), its camera jitter drawn first. The path_traced
// method traces a frame so, a tile and a sample index at a time, and so do its benchmarks.
template <PathSampler Sampler, typename MakeSampler>
void tracePixelPaths(const PreparedScene& scene, const PinholeCamera& camera, int width, int x0, int y0, int x1, int y1,
                     MakeSampler makeSampler, const PathSettings& settings, std::vector<PathResult>& results, RayLog* log = nullptr) {
    const std::size_t n = std::size_t(x1 - x0) * std::size_t(y1 - y0);
    std::vector<Sampler> samplers;
    std::vector<Ray> cameraRays;
    samplers.reserve(n);
    cameraRays.reserve(n);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            samplers.push_back(makeSampler(uint64_t(y) * uint64_t(width) + uint64_t(x)));
            const vec2 jitter = samplers.back().cameraJitter();
            cameraRays.push_back(camera.generateRay(float(x) + jitter.x, float(y) + jitter.y));
        }
    results.resize(samplers.size());
    tracePaths(scene, cameraRays.data(), samplers.data(), int(samplers.size()), settings, results.data(), log);
}

// Light arriving at `p` straight from the emitters, reflected towards wo: every sun, and one
// sample of the lights with extent (LightSampler::sampleExtended()). With `bsdfSamplingFollows`
// that sample carries its MIS weight against BSDF sampling and the caller adds the BSDF-sampled
// half (as tracePath does); without it, light sampling alone is the whole (unbiased) estimate.
// Counts its rays: a shadow ray per sun and one for the sample. 0 without a ray where the scene's
// plan leaves next-event estimation out (the caller has drawn the sample's numbers all the same,
// so that the random streams, hence the image, do not depend on pruning).
Color estimateDirect(const PreparedScene& scene, const SurfacePoint& p, const Bsdf& bsdf, const vec3& wo, const LightSampleUniforms& u,
                     uint32_t& rays, RayLog* log = nullptr, bool bsdfSamplingFollows = true);

// The same, with the light sample's numbers drawn from `rng` (drawLightSampleUniforms()).
inline Color estimateDirect(const PreparedScene& scene, const SurfacePoint& p, const Bsdf& bsdf, const vec3& wo, Rng& rng, uint32_t& rays,
                            RayLog* log = nullptr, bool bsdfSamplingFollows = true) {
    return estimateDirect(scene, p, bsdf, wo, drawLightSampleUniforms(rng), rays, log, bsdfSamplingFollows);
}

// estimateDirect() at many points, their shadow rays traced RayTracer::kPacketSize at a time: the
// points of neighbouring pixels send theirs to the same lights through the same BVH nodes, and a
// packet shares that traversal (the G-buffer's direct light). The light samples and their
// contributions are estimateDirect()'s, bit for bit, added to each target in its order. The
// commonest sample, a point of an emissive triangle seen from a Lambertian surface, waits until
// kLanes of them are taken together across SIMD lanes (TriangleLightLanes): one at a time, its
// chain of square roots and divisions was a fifth of a path's shading. Suns and the environment
// seen from a Lambertian surface wait in lanes of their own (DistantLightLanes).
class DirectLightBatch {
public:
    // `log`: where the shadow rays are recorded as they are queued, if anywhere.
    explicit DirectLightBatch(const PreparedScene& scene, RayLog* log = nullptr) : m_scene(scene), m_log(log) {}
    DirectLightBatch(const DirectLightBatch&) = delete;
    DirectLightBatch& operator=(const DirectLightBatch&) = delete;

    // Adds estimateDirect(p, bsdf, wo, u, ..., bsdfSamplingFollows) to `target` by the next
    // flush(), which must come before `target` is read or moves; counts the shadow rays it takes
    // into `*rays` (if given) by then too.
    void add(const SurfacePoint& p, const Bsdf& bsdf, const vec3& wo, const LightSampleUniforms& u, bool bsdfSamplingFollows, Color& target,
             uint32_t* rays = nullptr);
    // add() at a point whose BSDF is Lambertian (Bsdf::specularProbability() 0) of `albedo`: the
    // Bsdf is built only for the samples that are not taken in lanes.
    void addLambertian(const SurfacePoint& p, const Color& albedo, const vec3& wo, const LightSampleUniforms& u, bool bsdfSamplingFollows,
                       Color& target, uint32_t* rays = nullptr);
    // Takes the samples still waiting, traces the shadow rays still pending and adds what they
    // let through.
    void flush();
    // Shadow rays traced so far.
    uint32_t rays() const { return m_rays; }

    static constexpr int kLanes = 8;
    // The Lambertian points receiving the lanes' samples, coordinates by lane.
    struct ReceiverLanes {
        float position[3][kLanes], positionError[3][kLanes], geometricNormal[3][kLanes], shadingNormal[3][kLanes];
        float wo[3][kLanes], albedo[3][kLanes];

        void set(int k, const SurfacePoint& p, const vec3& towardsViewer, const Color& lambertianAlbedo) {
            setLaneVector(position, k, p.position);
            setLaneVector(positionError, k, p.positionError);
            setLaneVector(geometricNormal, k, p.geometricNormal);
            setLaneVector(shadingNormal, k, p.shadingNormal);
            setLaneVector(wo, k, towardsViewer);
            setLaneVector(albedo, k, lambertianAlbedo);
        }
    };
    // Triangle light samples at Lambertian points, one per lane, coordinates by lane.
    struct TriangleLightLanes {
        // In: the receiving point and the sample's numbers.
        ReceiverLanes receiver;
        float u[2][kLanes], select[kLanes];
        uint32_t misWeighted[kLanes];  // all ones where BSDF sampling follows
        float vertices[3][3][kLanes], lightNormal[3][kLanes], area[kLanes], emission[3][kLanes];
        // Out: the shadow ray and what it carries if it arrives, where `arrives` is all ones.
        uint32_t arrives[kLanes];
        float origin[3][kLanes], direction[3][kLanes], tMax[kLanes], contribution[3][kLanes];
    };

    // Samples of suns and of the environment (at infinite distance) at Lambertian points, one per
    // lane: taken from the light sampler as they come, or, for a constant environment, its
    // direction sampled in the lane (sampleConstantEnvironment()) from `u` and `select`.
    struct DistantLightLanes {
        // In: the receiving point and the sample.
        ReceiverLanes receiver;
        float wi[3][kLanes], radiance[3][kLanes], pdf[kLanes];
        uint32_t misWeighted[kLanes];  // all ones where BSDF sampling follows and the light has extent
        uint32_t constantEnvironment[kLanes];  // all ones where the lane samples it: wi and pdf are its
        float u[2][kLanes], select[kLanes];
        // Out, as TriangleLightLanes'.
        uint32_t arrives[kLanes];
        float origin[3][kLanes], direction[3][kLanes], tMax[kLanes], contribution[3][kLanes];
    };

private:
    struct Pending {
        Color contribution;
        Color* target;
    };
    // add() with the point's albedo, whether its BSDF is Lambertian, and bsdfOf() returning its Bsdf
    // (a reference to the caller's, or one built on the call).
    template <class BsdfOf>
    void addWith(const SurfacePoint& p, const Color& albedo, bool lambertian, BsdfOf&& bsdfOf, const vec3& wo, const LightSampleUniforms& u,
                 bool bsdfSamplingFollows, Color& target, uint32_t* rays);
    // Queues a shadow ray and what it adds to `target` if it arrives.
    void queue(const ShadowRay& shadow, const Color& contribution, Color& target, uint32_t* rays);
    void traceQueued();
    // Puts a sun's or the environment's sample `ls` at the Lambertian point `p` in a lane.
    void addDistant(const SurfacePoint& p, const Color& albedo, const vec3& wo, const LightSample& ls, bool bsdfSamplingFollows, Color& target,
                    uint32_t* rays);
    // Puts a sample of the constant environment, chosen with probability `select`, at the
    // Lambertian point `p` in a lane, its direction to be drawn there from `u`.
    void addConstantEnvironment(const SurfacePoint& p, const Color& albedo, const vec3& wo, float select, const vec2& u, bool bsdfSamplingFollows,
                                Color& target, uint32_t* rays);
    // Completes the next distant lane, whose sample the callers above have set, with its receiver,
    // target and ray count; takes the lanes when they are full.
    void takeDistantLane(const SurfacePoint& p, const Color& albedo, const vec3& wo, Color& target, uint32_t* rays);
    // Takes the samples waiting in lanes (takeDistantLights(), then takeTriangleLights(): a
    // point's suns come before its triangle, as estimateDirect() adds them) and queues their
    // shadow rays.
    void takeLanes();

    const PreparedScene& m_scene;
    RayLog* m_log;
    int m_count = 0;
    ShadowRay m_shadows[RayTracer::kPacketSize];
    Pending m_pending[RayTracer::kPacketSize];
    uint32_t m_rays = 0;
    int m_lanes = 0;
    TriangleLightLanes m_lane{};
    Color* m_laneTargets[kLanes];
    uint32_t* m_laneRays[kLanes];
    int m_distantLanes = 0;
    DistantLightLanes m_distant{};
    Color* m_distantTargets[kLanes];
    uint32_t* m_distantRays[kLanes];
};

}  // namespace gibench
