#pragma once
// The probe-cache pipeline of MAMBA's Figure 2, shared by every probe store:
//
//   gbuffer → direct → secondary_paths → raster → allocate → update → gather → resolve
//
// - gbuffer: one jittered primary ray per pixel.
// - direct: next-event estimation at the primary hits (one light sample per pixel per frame),
//   ReSTIR (core/render/restir.h: 8 candidates, temporal and spatial reuse), or none when direct light
//   is read from the cache (direct_lighting = "cache").
// - secondary_paths: one path per block × block pixels per frame, the pixel cycling through the
//   block frame by frame: v1 → v2 by BSDF sampling at v1, NEE at v2 (never at v1: defect 1 of
//   the original), and on to v3 for the probe at v2.
// - raster: asks the store which probes serve each pixel and with which weights (once per frame:
//   the gather reuses them) and whether the pixel is covered: ProbeStore::lookup(), each store's
//   own (MAMBA's N nearest, GIBS-like surfels covering the point, Lumen-like card texels), or
//   with lookup = "nearest" the N nearest blended by distance for every store.
// - allocate: each tile of allocation_tile² pixels with at least allocation_threshold of its
//   surface pixels uncovered spawns one probe, at its uncovered pixel farthest from any probe.
// - update: the probe receiving updates at v1 (the nearest; hash_grid: v1's own cell) gets
//   (radiance leaving v2 towards v1, ω1), the one at v2 gets (radiance leaving v3 towards v2, ω2);
//   with allocate_at_updates a point with no such probe gets one, on screen or off. A probe's
//   earlier samples first fade by 1 − 1/history per frame since its last (bounded history). With
//   recursive_update the radiance leaving v2 (v3) includes the light its own probes cache,
//   integrated with its BSDF (multiple bounces).
// - gather: the probes the raster stage found for each pixel, blended by their weights, each
//   integrated with the pixel's BSDF in the probe's own frame (one frame, one cosine: defect 3);
//   probes with no samples are skipped (defect 5).
// - resolve: next-event estimates of direct light are averaged over the frames since the camera
//   last moved (a running mean, exponential after temporal_history frames); what is read from the
//   cache is shown as the current frame reads it: the cache improves frame by frame, so averaging
//   its early, emptier states in would only drag the image back.
//
// Probes cache the *reflected* light arriving at them (radiance leaving a surface minus its
// emission), so the gather is exactly the "indirect" of the path tracer's split; emission
// arriving directly (from emitters, the sky) is direct light, computed by NEE or, in "cache"
// mode, cached in a second state per probe.

#include "core/render/method.h"
#include "core/render/restir.h"
#include "methods/probe_cache/probe_encoding.h"
#include "methods/probe_cache/probe_light.h"
#include "methods/probe_cache/probe_store.h"

#include <memory>

namespace gibench {

// The largest `history`: samples never fade, every probe keeps a running mean.
inline constexpr uint32_t kUnboundedHistory = 1u << 24;

struct ProbePipelineSettings {
    ProbeEncodingKind encoding = ProbeEncodingKind::Hemispherical;
    int encodingResolution = 5;
    uint32_t historyFrames = 32;  // key "history": ProbeEncoding::fade() per frame
    ProbeStateFormat stateFormat = ProbeStateFormat::BFloat16;
    int gatherNeighbours = 2;  // the final gather's N nearest (the paper's N = 2)
    int vertexNeighbours = 1;  // at path vertices: the paper's "secondary probe nearest to v2"
    enum class Lookup { Native, Nearest } lookup = Lookup::Native;
    enum class Direct { Nee, Restir, Cache } direct = Direct::Nee;
    RestirSettings restir;
    int secondaryBlock = 4;
    int allocationTile = 16;
    float allocationThreshold = 0.4f;
    bool allocateAtUpdates = true;
    bool recursiveUpdate = true;
    int temporalHistory = 32;
    bool probeViews = false;  // layers probe_centres and probe_splat (probe_views.h)
};

// The pipeline's keys; a store method's table is these followed by the store's own. A store key
// that repeats a pipeline key is a programming error (std::logic_error naming both).
const ParamTable& probePipelineParams();
ParamTable withPipelineParams(const ProbeStoreInfo& store);
ProbePipelineSettings readProbePipelineSettings(Params& params);

// The registry row of the probe-cache method over `store`: the pipeline's keys and the store's,
// and a `create` that reads the pipeline's keys, then the store's through store.create.
MethodInfo probeCacheMethod(const ProbeStoreInfo& store);

}  // namespace gibench
