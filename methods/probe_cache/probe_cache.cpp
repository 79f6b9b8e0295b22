#include "methods/probe_cache/probe_cache.h"

#include "core/render/bsdf.h"
#include "core/render/gbuffer.h"
#include "core/render/path_tracing.h"
#include "core/util/error.h"
#include "core/util/rng.h"
#include "core/util/system_memory.h"
#include "core/util/text_format.h"
#include "methods/probe_cache/probe_light.h"
#include "methods/probe_cache/probe_views.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <span>
#include <utility>

namespace gibench {

namespace {

const EnumChoices<ProbePipelineSettings::Direct>& directLightingChoices() {
    static const EnumChoices<ProbePipelineSettings::Direct> choices = {
        {"nee", ProbePipelineSettings::Direct::Nee},
        {"restir", ProbePipelineSettings::Direct::Restir},
        {"cache", ProbePipelineSettings::Direct::Cache},
    };
    return choices;
}

const EnumChoices<ProbePipelineSettings::Lookup>& lookupChoices() {
    static const EnumChoices<ProbePipelineSettings::Lookup> choices = {
        {"native", ProbePipelineSettings::Lookup::Native},
        {"nearest", ProbePipelineSettings::Lookup::Nearest},
    };
    return choices;
}

}  // namespace

const ParamTable& probePipelineParams() {
    static const ParamTable table = {
        {"encoding", ParamType::String, "hemispherical", "probe radiance: 5x5 hemispherical grid, octahedral grid, or spherical harmonics",
         -INFINITY, INFINITY, choiceNames(probeEncodingChoices())},
        {"encoding_resolution", ParamType::Int, 5, "bins per side of the grids, or the SH order (1 or 2)", 1, 64},
        {"history", ParamType::Int, double(ProbePipelineSettings{}.historyFrames), "frames over which a probe's samples fade: each frame multiplies their weight by 1 - 1/history (an exponential blend in time; the largest: no fading, a running mean)", 1,
         double(kUnboundedHistory)},
        {"state_format", ParamType::String, "bfloat16",
         "probe states: float32, or bfloat16 means with float sample weights (0.64x the bytes of the 5x5 grid's)", -INFINITY, INFINITY,
         choiceNames(probeStateFormatChoices())},
        {"gather_neighbours", ParamType::Int, double(ProbePipelineSettings{}.gatherNeighbours),
         "N of an N-nearest lookup: mamba's own, and every store's with lookup = \"nearest\"", 1, kMaxServedProbes},
        {"vertex_neighbours", ParamType::Int, double(ProbePipelineSettings{}.vertexNeighbours),
         "N of the N-nearest cache reads at the secondary paths' vertices (the recursive update's light at v2 and v3); the paper reads the probe nearest to v2",
         1, kMaxServedProbes},
        {"lookup", ParamType::String, "native",
         "probes that serve a pixel and their weights: the store's own lookup, or for every store the nearest blended by distance", -INFINITY,
         INFINITY, choiceNames(lookupChoices())},
        {"direct_lighting", ParamType::String, "nee", "direct light at primary hits: next-event estimation, ReSTIR, or read from the cache",
         -INFINITY, INFINITY, choiceNames(directLightingChoices())},
        {"restir_candidates", ParamType::Int, 8, "ReSTIR: light samples resampled per pixel per frame", 1, 1024},
        {"restir_history_cap", ParamType::Int, 200, "ReSTIR: cap on the temporal history's sample count M", 0, 1 << 20},
        {"restir_spatial_neighbours", ParamType::Int, 2, "ReSTIR: neighbours merged by spatial reuse (0: none)", 0, 64},
        {"restir_spatial_radius", ParamType::Float, 20.0, "ReSTIR: radius in pixels spatial neighbours are drawn from", 1.0, 1024.0},
        {"secondary_block", ParamType::Int, 4, "one secondary path per block x block pixels per frame", 1, 64},
        {"allocation_tile", ParamType::Int, 16, "tile size in pixels of the allocation test", 2, 256},
        {"allocation_threshold", ParamType::Float, 0.4, "fraction of a tile's surface pixels uncovered that spawns a probe", 0.0, 1.0},
        {"allocate_at_updates", ParamType::Bool, true,
         "an update that finds no probe places one at its point, on screen or off (world-space allocation at secondary hits; false: the original's)"},
        {"recursive_update", ParamType::Bool, true, "radiance leaving v2 includes its cached indirect light (multiple bounces)"},
        {"temporal_history", ParamType::Int, 32, "frames of next-event direct light averaged while the camera is still (running mean, then exponential)", 1, 1 << 20},
        {"probe_views", ParamType::Bool, false,
         "add layers probe_centres (probes projected onto the image) and probe_splat (each pixel lit by its nearest serving probe alone)"},
    };
    return table;
}

ParamTable withPipelineParams(const ProbeStoreInfo& store) {
    return joinTables(probePipelineParams(), store.parameters(), "probe-cache pipeline and store \"" + store.name + "\"");
}

ProbePipelineSettings readProbePipelineSettings(Params& params) {
    ProbePipelineSettings s;
    s.encoding = params.getEnum("encoding", probeEncodingChoices());
    s.encodingResolution = int(params.getInt("encoding_resolution"));
    s.historyFrames = uint32_t(params.getInt("history"));
    s.stateFormat = params.getEnum("state_format", probeStateFormatChoices());
    if (s.encoding == ProbeEncodingKind::SphericalHarmonics && s.encodingResolution > 2)
        params.fail("encoding_resolution", "expected an SH order of 1 or 2 for encoding \"sh\", got " + std::to_string(s.encodingResolution));
    s.gatherNeighbours = int(params.getInt("gather_neighbours"));
    s.vertexNeighbours = int(params.getInt("vertex_neighbours"));
    s.lookup = params.getEnum("lookup", lookupChoices());
    s.direct = params.getEnum("direct_lighting", directLightingChoices());
    s.restir.candidates = int(params.getInt("restir_candidates"));
    s.restir.temporalHistoryCap = int(params.getInt("restir_history_cap"));
    s.restir.temporal = s.restir.temporalHistoryCap > 0;
    s.restir.spatialNeighbours = int(params.getInt("restir_spatial_neighbours"));
    s.restir.spatial = s.restir.spatialNeighbours > 0;
    s.restir.spatialRadiusPixels = params.getFloat("restir_spatial_radius");
    s.secondaryBlock = int(params.getInt("secondary_block"));
    s.allocationTile = int(params.getInt("allocation_tile"));
    s.allocationThreshold = params.getFloat("allocation_threshold");
    s.allocateAtUpdates = params.getBool("allocate_at_updates");
    s.recursiveUpdate = params.getBool("recursive_update");
    s.temporalHistory = int(params.getInt("temporal_history"));
    s.probeViews = params.getBool("probe_views");
    return s;
}

namespace {

// The query a surface point makes, written field by field into `q`: a query built whole and then
// copied is read back before its partial stores reach memory, a stall per pixel of the raster stage.
void setQuery(ProbeQuery& q, const SurfacePoint& p, uint32_t jitter = 0) {
    q.position = p.position;
    q.normal = p.shadingNormal;
    q.mesh = p.mesh;
    q.triangle = p.triangle;
    q.jitter = jitter;
}
ProbeQuery queryOf(const SurfacePoint& p, uint32_t jitter = 0) {
    ProbeQuery q;
    setQuery(q, p, jitter);
    return q;
}

// The jitter bits of the lookups a pixel's queries make in a frame (ProbeQuery::jitter).
uint32_t lookupJitter(uint64_t seed, int frame, std::size_t pixel) {
    return Rng::forPath(seed, uint64_t(frame), pixel, RandomStream::LookupJitter).next();
}

// One secondary path's contribution to the cache: up to two probe samples.
struct ProbeSample {
    bool valid = false;
    ProbeQuery query;
    vec3 direction{0.0f};  // world, arriving light travels along -direction
    float pdf = 0.0f;
    Color reflected{0.0f};
    Color emitted{0.0f};
};

struct SecondaryPath {
    ProbeSample atV1, atV2;
    uint32_t pixel = 0;                      // v1's: the raster stage looked up its point
    uint32_t receiverAtV2 = kReceiverUnknown;  // ProbeLookup::receiver of the cache read at v2
};

// What the update stage does to one probe's state, in the order the samples came: routed one
// after another (the store changes on the way), applied per probe in parallel.
struct ProbeWrite {
    static constexpr uint32_t kClear = ~uint32_t(0);
    static constexpr uint32_t kNone = ~uint32_t(0);  // no write: the end of a probe's list
    uint32_t id;
    uint32_t sample;  // 2 × path + (0 at v1, 1 at v2); kClear: the id went to a new probe, its state is emptied
    bool adds;        // false: the sample only fades the probe (it arrived from below its hemisphere)
    vec3 local;       // the sample's direction in the probe's frame
    uint32_t next = kNone;  // the probe's next write this frame
    float keep = 1.0f;      // the bounded history's fade before the sample (keepSinceLastSample)
};
// Past this many probes placed since a receiver was found (a cache filling up), it is looked
// up again rather than checked against each of them.
constexpr std::size_t kPlacedScanLimit = 32;

// Bayer order of a 4×4 block, generalised by row-major order for other sizes: consecutive frames
// visit pixels far apart in the block.
int blockOffset(int frame, int block) {
    static const int kBayer4[16] = {0, 10, 2, 8, 5, 15, 7, 13, 1, 11, 3, 9, 4, 14, 6, 12};
    const int n = block * block;
    const int k = frame % n;
    return block == 4 ? kBayer4[k] : k;
}

// What one frame did, for frames.jsonl.
struct FrameCounters {
    uint64_t allocated = 0, allocatedAtUpdates = 0, refused = 0, evicted = 0, uncoveredTiles = 0, paths = 0, updates = 0, updatesWithoutProbe = 0,
             updatesOverBudget = 0, updatesIgnored = 0, nonfinite = 0, rays = 0, pixelsWithoutProbe = 0;
    double coveredFraction = 0.0;
};

// Each counter under its name in the frame record: the one list frameStats() serialises.
constexpr std::pair<const char*, uint64_t FrameCounters::*> kFrameCounterNames[] = {
    {"probes_allocated", &FrameCounters::allocated},
    {"probes_allocated_at_updates", &FrameCounters::allocatedAtUpdates},
    {"inserts_refused", &FrameCounters::refused},
    {"inserts_evicted", &FrameCounters::evicted},
    {"uncovered_tiles", &FrameCounters::uncoveredTiles},
    {"secondary_paths", &FrameCounters::paths},
    {"updates", &FrameCounters::updates},
    {"updates_without_probe", &FrameCounters::updatesWithoutProbe},
    {"updates_over_budget", &FrameCounters::updatesOverBudget},
    {"updates_ignored", &FrameCounters::updatesIgnored},
    {"nonfinite_samples", &FrameCounters::nonfinite},
    {"rays", &FrameCounters::rays},
    {"pixels_without_probe", &FrameCounters::pixelsWithoutProbe},
};

class ProbeCache final : public Method {
public:
    // `spacingWhere`: "FILE: /pointer/<spacing key>: ", for a probe state too large for this machine.
    ProbeCache(std::unique_ptr<ProbeStore> store, const ProbePipelineSettings& settings, std::string spacingWhere)
        : m_store(std::move(store)),
          m_settings(settings),
          m_spacingWhere(std::move(spacingWhere)),
          m_encoding(makeProbeEncoding(settings.encoding, settings.encodingResolution)),
          m_reflected(*m_encoding, m_settings.stateFormat),
          m_emitted(*m_encoding, m_settings.stateFormat) {
        if (settings.direct == ProbePipelineSettings::Direct::Restir) m_restir = std::make_unique<RestirDirect>(settings.restir);
    }

    void prepare(const PreparedScene& scene, int width, int height, RunNotes& notes) override {
        m_store->prepare(scene.scene, notes);
        rejectStatesThatCannotFitInMemory();
        growStates();  // a store may place probes in prepare() (cards capture the scene)
        if (m_settings.direct == ProbePipelineSettings::Direct::Cache)
            notes.skip("direct", "direct_lighting = \"cache\": primary hits read direct light from the probes");
        if (m_settings.direct != ProbePipelineSettings::Direct::Restir)
            notes.skip("restir", "direct_lighting is not \"restir\" (the paper's optional ReSTIR is off by default)");
        else
            notes.skip("reprojection", "ReSTIR's temporal reuse reads each pixel's own reservoir: a camera move restarts the history");
        const bool glossy = std::any_of(scene.scene.materials.begin(), scene.scene.materials.end(),
                                        [](const Material& m) { return m.type == MaterialType::Glossy; });
        if (!glossy) notes.skip("gather_quadrature", "no glossy material: every gather uses the probes' irradiance directly");
        m_direct.assign(std::size_t(width) * height, Color(0.0f));
        m_meanDirect.assign(std::size_t(width) * height, Color(0.0f));
        m_indirect.assign(std::size_t(width) * height, Color(0.0f));
        m_coverage.assign(std::size_t(width) * height, PixelCoverage::NoSurface);
        m_pixelReceivers.assign(std::size_t(width) * height, kReceiverUnknown);
        m_distance.assign(std::size_t(width) * height, kInfinity);
    }

    void renderFrame(const FrameContext& ctx, LayeredImage& out) override {
        m_frameStats = FrameCounters{};
        const PreparedScene& ps = ctx.scene;
        const PinholeCamera camera(ctx.pose, ctx.width, ctx.height);
        m_store->beginFrame(ctx.pose, uint32_t(ctx.frame));
        {
            ScopedStage stage(ctx.timer, "gbuffer");
            renderGBuffer(ps, camera, ctx.seed, uint64_t(ctx.frame), m_gbuffer);
        }
        if (m_settings.direct == ProbePipelineSettings::Direct::Nee && ps.plan.nextEventEstimation) {
            ScopedStage stage(ctx.timer, "direct");
            directLighting(ctx);
        } else if (m_settings.direct == ProbePipelineSettings::Direct::Restir && ps.plan.nextEventEstimation) {
            ScopedStage stage(ctx.timer, "restir");
            uint64_t rays = 0;
            m_restir->render(ps, m_gbuffer, ctx.seed, uint64_t(ctx.frame), ctx.frame == 0 || ctx.cameraMoved || ctx.sceneChanged, m_direct, rays);
            m_frameStats.rays += rays;
            m_frameStats.nonfinite += m_restir->droppedNonFinite();
        } else {
            std::fill(m_direct.begin(), m_direct.end(), Color(0.0f));
        }
        {
            ScopedStage stage(ctx.timer, "secondary_paths");
            secondaryPaths(ctx);
        }
        {
            ScopedStage stage(ctx.timer, "raster");
            rasterCoverage(ctx);
        }
        {
            ScopedStage stage(ctx.timer, "allocate");
            allocate(ctx.frame);
        }
        {
            ScopedStage stage(ctx.timer, "update");
            update(ctx.frame);
        }
        {
            ScopedStage stage(ctx.timer, "gather");
            gather();
        }
        ScopedStage stage(ctx.timer, "resolve");
        resolve(ctx, out);
    }

    Json frameStats() const override {
        Json stats = m_store->stats();
        stats["probe_state_bytes"] = m_reflected.bytes() + m_emitted.bytes();
        stats["probe_state_bytes_per_probe"] = m_reflected.bytesPerProbe() * (cachesDirect() ? 2 : 1);
        stats["encoding"] = m_encoding->name();
        stats["covered_fraction"] = m_frameStats.coveredFraction;
        for (const auto& [name, counter] : kFrameCounterNames) stats[name] = m_frameStats.*counter;
        return stats;
    }

private:
    bool cachesDirect() const { return m_settings.direct == ProbePipelineSettings::Direct::Cache; }

    // A BSDF with a specular lobe, which gatherFrom() integrates the probes' radiance against; null
    // for a diffuse one.
    static const Bsdf* specularOf(const Bsdf& bsdf) { return bsdf.hasSpecular() ? &bsdf : nullptr; }

    // The lookup the config chose, the store's own or every store's `count` nearest, for `n`
    // queries: a tile of pixels at a time in the raster stage, one at a time at the vertices of paths.
    void lookup(const ProbeQuery* queries, int n, int count, ProbeLookup* out) const {
        if (m_settings.lookup == ProbePipelineSettings::Lookup::Native)
            m_store->lookupBatch(queries, n, count, out);
        else
            m_store->lookupNearestBatch(queries, n, count, out);
    }

    // The most probes lookup() serves a pixel.
    int servedPerPixel() const {
        return m_settings.lookup == ProbePipelineSettings::Lookup::Native ? m_store->servedAtMost(m_settings.gatherNeighbours)
                                                                          : m_settings.gatherNeighbours;
    }

    // The served probes' light blended by their weights, renormalised over the probes that hold
    // samples; where all of those have weight 0 (at the edge of a lookup), their plain mean rather
    // than nothing. A diffuse surface (`specular` null) reflects their irradiance times albedo / π,
    // one with a specular lobe their radiance integrated against `specular`.
    // `probes`: the store's probes().
    bool gatherFrom(const ProbeLight& light, std::span<const Probe> probes, const ProbeWeight* served, int found, const SurfacePoint& surface,
                    const Color& albedo, const Bsdf* specular, const vec3& wo, std::vector<Color>& scratch, Color& result) const {
        Color sum(0.0f);
        float weights = 0.0f, fallbackWeights = 0.0f;
        Color fallback(0.0f);
        for (int i = 0; i < found; ++i) {
            const uint32_t id = served[i].id;
            if (id >= light.probes() || !light.sampled(id)) continue;
            const vec3& probeNormal = probes[id].normal;
            Color reflected;
            if (!specular) {
                // A surface facing exactly as the probe (the same flat triangle) reads its memo
                // without a frame: what irradiance() of the local normal returns.
                const Color e = probeNormal == surface.shadingNormal ? light.irradianceAtOwnNormal(id)
                                                                     : light.irradiance(id, Frame(probeNormal).toLocal(surface.shadingNormal));
                reflected = albedo * kInvPi * e;
            } else {
                const Frame frame(probeNormal);
                const auto& quadrature = m_encoding->quadrature();
                scratch.resize(quadrature.size());
                m_encoding->radianceAt(light.read(id), scratch.data());
                reflected = Color(0.0f);
                for (std::size_t q = 0; q < quadrature.size(); ++q) {
                    const vec3 wi = frame.toWorld(quadrature[q].direction);
                    const float cosine = glm::dot(wi, surface.shadingNormal);
                    if (cosine <= 0.0f) continue;
                    reflected += scratch[q] * specular->eval(wo, wi) * (cosine * quadrature[q].solidAngle);
                }
            }
            const float w = served[i].weight;
            sum += w * reflected;
            weights += w;
            fallback += reflected;
            fallbackWeights += 1.0f;
        }
        if (weights > 0.0f) {
            result = sum / weights;
            return true;
        }
        if (fallbackWeights > 0.0f) {
            result = fallback / fallbackWeights;
            return true;
        }
        result = Color(0.0f);
        return false;
    }

    void directLighting(const FrameContext& ctx) {
        std::atomic<uint64_t> rays{0};
        tbb::enumerable_thread_specific<std::vector<LightSampleUniforms>> rowUniforms;
        tbb::parallel_for(0, ctx.height, [&](int y) {
            const ScopedFlushToZero flushToZero;
            DirectLightBatch batch(ctx.scene);
            // The row's numbers first, in a loop of their own: drawn beside each pixel's light
            // sample, a generator's chain of hash and steps (about 40 cycles) waited for every
            // pixel, two thirds of this loop's own samples.
            std::vector<LightSampleUniforms>& uniforms = rowUniforms.local();
            uniforms.resize(std::size_t(ctx.width));
            for (int x = 0; x < ctx.width; ++x) {
                Rng rng = Rng::forPath(ctx.seed, uint64_t(ctx.frame), std::size_t(y) * ctx.width + x, RandomStream::Direct);
                uniforms[std::size_t(x)] = drawLightSampleUniforms(rng);
            }
            for (int x = 0; x < ctx.width; ++x) {
                const std::size_t pixel = std::size_t(y) * ctx.width + x;
                const GBufferTexel& t = m_gbuffer.texels[pixel];
                m_direct[pixel] = Color(0.0f);
                if (!t.valid) continue;
                const LightSampleUniforms& u = uniforms[std::size_t(x)];
                if (Bsdf::specularProbability(*t.surface.material, t.albedo) > 0.0f)
                    batch.add(t.surface, Bsdf(*t.surface.material, t.albedo, t.surface), t.wo, u, false, m_direct[pixel]);
                else
                    batch.addLambertian(t.surface, t.albedo, t.wo, u, false, m_direct[pixel]);
            }
            batch.flush();
            rays += batch.rays();
        });
        m_frameStats.rays += rays;
    }

    // One secondary path on its way: the vertex it left from or arrived at, and where the light
    // arriving there goes.
    struct Walk {
        SecondaryPath* path;
        Rng rng;
        uint32_t jitter;  // lookupJitter() of the path's pixel
        SurfacePoint at;
        vec3 wo;
        Color albedo;
        Ray ray{};                // leaving `at`
        Color indirect{0.0f};     // the cache read at `at`, added to its sample once its shadow rays are back
        bool gathered = false;
    };

    // Radiance the vertex `walk.at` sends back along the ray that found it, into `sample`:
    // emission apart, reflected direct light by NEE (its shadow rays queued in `batch`, added by
    // its flush()) plus, recursively, the indirect light its probes cache (in walk.indirect until
    // the flush), from `served`, the vertex's lookup (of vertex_neighbours; null when the update
    // is not recursive). `receiverAtV`: its ProbeLookup::receiver (kReceiverUnknown without one).
    void shadeVertex(const PreparedScene& ps, Walk& walk, const ProbeLookup* served, DirectLightBatch& batch, std::vector<Color>& scratch,
                     ProbeSample& sample, uint32_t& receiverAtV) const {
        const SurfacePoint& v = walk.at;
        walk.albedo = albedoAt(ps, v);
        const Bsdf bsdf(*v.material, walk.albedo, v);
        sample.emitted = v.emitted();
        sample.reflected = Color(0.0f);
        batch.add(v, bsdf, walk.wo, drawLightSampleUniforms(walk.rng), false, sample.reflected);
        receiverAtV = served ? served->receiver : kReceiverUnknown;
        walk.gathered = served && gatherFrom(m_reflected, m_store->probes(), served->probes, served->count, v, bsdf.albedo(), specularOf(bsdf),
                                             walk.wo, scratch, walk.indirect);
    }

    // Samples the BSDF at walk.at for the ray on (walk.ray) and records it in `sample`; false when
    // sampling fails.
    static bool leave(Walk& walk, ProbeSample& sample) {
        const Bsdf bsdf(*walk.at.material, walk.albedo, walk.at);
        const float uLobe = walk.rng.uniform();
        const vec2 u(walk.rng.uniform(), walk.rng.uniform());
        const BsdfSample bs = bsdf.sample(walk.wo, uLobe, u);
        if (!(bs.pdf > 0.0f)) return false;
        sample.query = queryOf(walk.at);
        sample.direction = bs.wi;
        sample.pdf = bs.pdf;
        sample.valid = true;
        walk.ray = {offsetRayOrigin(walk.at.position, walk.at.positionError, walk.at.geometricNormal), bs.wi};
        return true;
    }

    // Each path from its pixel's first hit v1 samples a direction, finds v2 and fills atV1 with
    // what arrives from there; then the same from v2 to v3 into atV2. A row of pixels' paths goes
    // together, step by step, as the path tracer's wavefronts do (tracePaths()): their rays in
    // packets, their shadow rays in packets, and each path's random numbers drawn in the order it
    // draws them alone.
    void secondaryPaths(const FrameContext& ctx) {
        const PreparedScene& ps = ctx.scene;
        const int block = m_settings.secondaryBlock;
        const int blocksX = (ctx.width + block - 1) / block, blocksY = (ctx.height + block - 1) / block;
        // Each row clears and counts its own paths inside the parallel loop, rather than one
        // thread clearing all of them before it and counting them after it.
        m_paths.resize(std::size_t(blocksX) * blocksY);
        const int offset = blockOffset(ctx.frame, block);
        std::atomic<uint64_t> rays{0}, paths{0};
        struct Scratch {
            std::vector<Color> colors;
            std::vector<Walk> walks;
            std::vector<Ray> rays;
            std::vector<RayHit> hits;
            std::vector<ProbeQuery> queries;  // of the vertices the wave's rays arrived at
            std::vector<ProbeLookup> lookups;  // their answers
        };
        tbb::enumerable_thread_specific<Scratch> scratches;
        tbb::parallel_for(0, blocksY, [&](int by) {
            const ScopedFlushToZero flushToZero;
            Scratch& scratch = scratches.local();
            std::vector<Walk>& walks = scratch.walks;
            walks.clear();
            SecondaryPath* row = m_paths.data() + std::size_t(by) * blocksX;
            for (int bx = 0; bx < blocksX; ++bx) {
                SecondaryPath& path = row[bx];
                path = SecondaryPath{};
                const int x = bx * block + offset % block, y = by * block + offset / block;
                if (x >= ctx.width || y >= ctx.height) continue;
                const std::size_t pixel = std::size_t(y) * ctx.width + x;
                const GBufferTexel& t = m_gbuffer.texels[pixel];
                if (!t.valid) continue;
                path.pixel = uint32_t(pixel);
                walks.push_back({&path, Rng::forPath(ctx.seed, uint64_t(ctx.frame), pixel, RandomStream::Secondary),
                                 lookupJitter(ctx.seed, ctx.frame, pixel), t.surface, t.wo, t.albedo});
            }
            DirectLightBatch batch(ps);
            uint32_t rowRays = 0;
            for (int step = 0; step < 2 && !walks.empty(); ++step) {
                const auto sampleOf = [step](Walk& w) -> ProbeSample& { return step == 0 ? w.path->atV1 : w.path->atV2; };
                std::size_t n = 0;
                for (Walk& w : walks)
                    if (leave(w, sampleOf(w))) walks[n++] = w;
                walks.erase(walks.begin() + std::ptrdiff_t(n), walks.end());
                scratch.rays.resize(n);
                scratch.hits.resize(n);
                scratch.queries.resize(n);
                scratch.lookups.resize(n);
                for (std::size_t k = 0; k < n; ++k) scratch.rays[k] = walks[k].ray;
                for (std::size_t k = 0; k < n; k += RayTracer::kPacketSize)
                    ps.tracer.intersect(&scratch.rays[k], int(std::min<std::size_t>(RayTracer::kPacketSize, n - k)), &scratch.hits[k], false);
                rowRays += uint32_t(n);
                std::size_t arrived = 0;
                for (std::size_t k = 0; k < n; ++k) {
                    Walk& w = walks[k];
                    const RayHit& hit = scratch.hits[k];
                    if (!hit.found()) {
                        if (ps.plan.environmentLookup) sampleOf(w).emitted = ps.lights.environmentRadiance(w.ray.direction);
                        continue;
                    }
                    setSurfaceAt(ps.triangles.at(hit.mesh, hit.triangle), w.ray, hit, w.at);
                    w.wo = -w.ray.direction;
                    if (m_settings.recursiveUpdate) scratch.queries[arrived] = queryOf(w.at, uint32_t(mix64(w.jitter + uint32_t(step))));
                    walks[arrived++] = w;
                }
                walks.erase(walks.begin() + std::ptrdiff_t(arrived), walks.end());
                // The cache reads of the wave's vertices: the store prefetches what all their
                // lookups read first, then every lookup is made and its probes' light prefetched,
                // then the vertices are shaded. Made one vertex at a time with its gather, every
                // lookup stalled on its own misses.
                if (m_settings.recursiveUpdate) {
                    m_store->prefetchLookups(scratch.queries.data(), int(arrived));
                    const std::span<const Probe> probes = m_store->probes();
                    for (std::size_t k = 0; k < arrived; ++k) {
                        lookup(&scratch.queries[k], 1, m_settings.vertexNeighbours, &scratch.lookups[k]);
                        for (int i = 0; i < scratch.lookups[k].count; ++i) {
                            const uint32_t id = scratch.lookups[k].probes[i].id;
                            m_reflected.prefetch(id);
                            if (id < probes.size()) __builtin_prefetch(&probes[id].normal);
                        }
                    }
                }
                for (std::size_t k = 0; k < arrived; ++k) {
                    Walk& w = walks[k];
                    uint32_t receiverAtV3;  // v3 receives no sample
                    shadeVertex(ps, w, m_settings.recursiveUpdate ? &scratch.lookups[k] : nullptr, batch, scratch.colors, sampleOf(w),
                                step == 0 ? w.path->receiverAtV2 : receiverAtV3);
                }
                batch.flush();
                for (Walk& w : walks)
                    if (w.gathered) sampleOf(w).reflected += w.indirect;
            }
            rays += rowRays + batch.rays();
            uint64_t rowPaths = 0;
            for (int bx = 0; bx < blocksX; ++bx) rowPaths += row[bx].atV1.valid;
            paths += rowPaths;
        });
        m_frameStats.rays += rays;
        m_frameStats.paths += paths;
    }

    // Looks up each pixel's probes once, a tile at a time (ProbeStore::lookupBatch): the
    // allocation stage reads its coverage, the gather its probes (probes spawned later this frame
    // join the gather next frame).
    void rasterCoverage(const FrameContext& ctx) {
        const int count = servedPerPixel();
        const bool jitters = m_store->readsJitter();
        const int width = m_gbuffer.width, height = m_gbuffer.height;
        const int edge = m_store->lookupTile();
        const int tilesX = (width + edge - 1) / edge, tilesY = (height + edge - 1) / edge;
        m_served.resize(std::size_t(tilesX) * tilesY * edge * edge * std::size_t(count));  // a share per tile
        m_servedOffsets.resize(m_gbuffer.texels.size());
        m_servedCounts.assign(m_gbuffer.texels.size(), 0);
        struct Batch {
            std::vector<ProbeQuery> queries;
            std::vector<int> pixels;
            std::vector<ProbeLookup> lookups;
        };
        tbb::enumerable_thread_specific<Batch> batches;
        std::atomic<uint64_t> covered{0}, surface{0};
        tbb::parallel_for(0, tilesX * tilesY, [&](int tile) {
            Batch& batch = batches.local();
            batch.queries.resize(std::size_t(edge) * edge);
            batch.pixels.resize(batch.queries.size());
            int n = 0;
            const int x0 = (tile % tilesX) * edge, y0 = (tile / tilesX) * edge;
            for (int y = y0; y < std::min(y0 + edge, height); ++y)
                for (int x = x0; x < std::min(x0 + edge, width); ++x) {
                    const std::size_t pixel = std::size_t(y) * width + x;
                    const GBufferTexel& t = m_gbuffer.texels[pixel];
                    m_coverage[pixel] = t.valid ? PixelCoverage::Uncovered : PixelCoverage::NoSurface;
                    m_distance[pixel] = kInfinity;
                    m_pixelReceivers[pixel] = kReceiverUnknown;
                    if (!t.valid) continue;
                    setQuery(batch.queries[n], t.surface, jitters ? lookupJitter(ctx.seed, ctx.frame, pixel) : 0);
                    batch.pixels[n++] = int(pixel);
                }
            batch.lookups.resize(batch.queries.size());
            lookup(batch.queries.data(), n, m_settings.gatherNeighbours, batch.lookups.data());
            uint64_t tileCovered = 0;
            // The tile's pixels' probes one after another in the tile's share of m_served: a pixel
            // gets its count's worth, not the most a lookup can serve (16 for dense_grid, which
            // serves 2.5 on average on the Cornell box; the gather read 2 of 16 slots per pixel).
            std::size_t offset = std::size_t(tile) * edge * edge * std::size_t(count);
            for (int i = 0; i < n; ++i) {
                const std::size_t pixel = std::size_t(batch.pixels[i]);
                const ProbeLookup& served = batch.lookups[i];
                m_servedCounts[pixel] = uint8_t(served.count);
                m_servedOffsets[pixel] = uint32_t(offset);
                std::copy_n(served.probes, served.count, m_served.data() + offset);
                offset += std::size_t(served.count);
                m_distance[pixel] = served.distance;
                if (served.covered) m_coverage[pixel] = PixelCoverage::Covered;
                m_pixelReceivers[pixel] = served.receiver;
                tileCovered += served.covered;
            }
            covered += tileCovered;
            surface += uint64_t(n);
        });
        m_frameStats.coveredFraction = surface > 0 ? double(covered) / double(surface) : 0.0;
    }

    // The pixel of the allocation tile at (tx, ty) to place a probe at, or -1 when the tile is
    // covered enough: the one farthest from the probes; among pixels with no probe near, the one
    // nearest the tile's centre.
    int pixelToCover(int tx, int ty) const {
        const int tile = m_settings.allocationTile;
        const int width = m_gbuffer.width, height = m_gbuffer.height;
        int surface = 0, uncovered = 0, chosen = -1;
        float chosenDistance = -1.0f, chosenCentre = kInfinity;
        const float cx = float(tx) + 0.5f * float(tile), cy = float(ty) + 0.5f * float(tile);
        for (int y = ty; y < std::min(ty + tile, height); ++y)
            for (int x = tx; x < std::min(tx + tile, width); ++x) {
                const int pixel = y * width + x;
                const PixelCoverage coverage = m_coverage[pixel];
                if (coverage == PixelCoverage::NoSurface) continue;
                ++surface;
                if (coverage == PixelCoverage::Covered) continue;
                ++uncovered;
                const float distance = m_distance[pixel];
                const float centre = (float(x) + 0.5f - cx) * (float(x) + 0.5f - cx) + (float(y) + 0.5f - cy) * (float(y) + 0.5f - cy);
                if (distance > chosenDistance || (distance == chosenDistance && centre < chosenCentre)) {
                    chosen = pixel;
                    chosenDistance = distance;
                    chosenCentre = centre;
                }
            }
        if (surface == 0 || float(uncovered) < m_settings.allocationThreshold * float(surface)) return -1;
        return chosen;
    }

    // The tiles' pixels are chosen in parallel (they read only the raster stage's coverage), the
    // probes placed in tile order.
    void allocate(int frame) {
        m_placedSinceLookups.clear();
        const int tile = m_settings.allocationTile;
        const int tilesX = (m_gbuffer.width + tile - 1) / tile, tilesY = (m_gbuffer.height + tile - 1) / tile;
        m_tilePixels.resize(std::size_t(tilesX) * tilesY);
        tbb::parallel_for(0, tilesX * tilesY, [&](int t) { m_tilePixels[t] = pixelToCover((t % tilesX) * tile, (t / tilesX) * tile); });
        for (const int chosen : m_tilePixels) {
            if (chosen < 0) continue;
            ++m_frameStats.uncoveredTiles;
            const ProbeInsert result = m_store->insert(queryOf(m_gbuffer.texels[chosen].surface), uint32_t(frame));
            if (result.status == ProbeInsert::Status::Refused) {
                ++m_frameStats.refused;
                continue;
            }
            ++m_frameStats.allocated;
            m_placedSinceLookups.push_back(result.id);
            growStates();
            if (result.status == ProbeInsert::Status::Evicted) {
                ++m_frameStats.evicted;
                clearState(result.id);
            }
        }
    }

    void rejectStatesThatCannotFitInMemory() const {
        const double bytes = double(m_store->idCapacity()) * double(m_reflected.bytesPerProbe()) * (cachesDirect() ? 2.0 : 1.0);
        const double available = 0.5 * double(physicalMemoryBytes());
        if (available > 0.0 && bytes > available) {
            constexpr double kGiB = double(1 << 30);
            throw InputError(m_spacingWhere + "the store placed " + formatCount(double(m_store->idCapacity())) + " probes in prepare, whose " +
                             m_encoding->name() + " states need " + formatNumber(bytes / kGiB) + " GiB, more than half of this machine's " +
                             formatNumber(2.0 * available / kGiB) + " GiB; raise the probe spacing");
        }
    }

    void growStates() {
        const std::size_t probes = m_store->idCapacity();
        m_reflected.grow(probes);
        if (m_lastSampled.size() < probes) m_lastSampled.resize(probes, 0);
        if (m_firstWrite.size() < probes) {
            m_firstWrite.resize(probes, ProbeWrite::kNone);
            m_lastWrite.resize(probes, ProbeWrite::kNone);
        }
        if (cachesDirect()) m_emitted.grow(probes);
    }

    void clearState(uint32_t id) {
        m_reflected.clear(id);
        if (cachesDirect()) m_emitted.clear(id);
    }

    static bool isUsable(const ProbeSample& sample) { return sample.valid && isFinite(sample.reflected) && isFinite(sample.emitted); }

    // A sample's receiver as the store stood when the update stage began (kNoReceiver for none),
    // with the sample's direction in that probe's frame and whether the probe accepts it.
    struct Receiver {
        uint32_t id = kNoReceiver;
        bool adds = false;
        vec3 local{0.0f};
    };
    Receiver receiverFor(const ProbeSample& sample, uint32_t id) const {
        if (id == kNoReceiver) return {};
        const vec3 local = Frame(m_store->probe(id).normal).toLocal(sample.direction);
        return {id, m_encoding->acceptsSample(local, sample.reflected, sample.pdf), local};
    }

    // Routes sample `index` of m_paths to its probe: a ProbeWrite, the counters, the store's
    // touch. `found` is looked up again only if a probe placed or reassigned since (from
    // m_placedSinceLookups[placedBefore] on) could change it.
    void routeSample(uint32_t index, int frame, const Receiver& found, std::size_t placedBefore) {
        const ProbeSample& sample = sampleOf(index);
        if (!sample.valid) return;
        if (!isUsable(sample)) {
            ++m_frameStats.nonfinite;
            return;
        }
        uint32_t id = found.id;
        const bool stale = mayHaveChanged(sample.query, found.id, placedBefore);
        if (stale && !m_store->receiverOf(sample.query, id)) id = kNoReceiver;
        if (id == kNoReceiver && !placeAtUpdate(sample.query, frame, id)) {
            ++m_frameStats.updatesWithoutProbe;
            return;
        }
        if (!m_store->admitUpdate(id)) {
            ++m_frameStats.updatesOverBudget;
            return;
        }
        const Receiver receiver = stale || id != found.id ? receiverFor(sample, id) : found;
        const bool adds = receiver.adds;
        addWrite({id, index, adds, receiver.local});
        if (!adds) {
            ++m_frameStats.updatesIgnored;  // arrived from below the probe's hemisphere
            return;
        }
        m_store->touch(id, uint32_t(frame));
        ++m_frameStats.updates;
    }

    const ProbeSample& sampleOf(uint32_t index) const { return index % 2 == 0 ? m_paths[index / 2].atV1 : m_paths[index / 2].atV2; }

    // Appends a write to m_writes and to its probe's list.
    void addWrite(const ProbeWrite& write) {
        const uint32_t index = uint32_t(m_writes.size());
        m_writes.push_back(write);
        uint32_t& last = m_lastWrite[write.id];
        if (last == ProbeWrite::kNone) {
            m_firstWrite[write.id] = index;
            m_written.push_back(write.id);
        } else {
            m_writes[last].next = index;
        }
        last = index;
    }

    // The writes of routeSample(), probe by probe in parallel, each probe's in their order: the
    // states come out as if applied one after another, with one decode, encode and memo per probe.
    void applyWrites(int frame) {
        tbb::parallel_for(std::size_t(0), m_written.size(), [&](std::size_t i) {
            const uint32_t id = m_written[i];
            for (uint32_t w = m_firstWrite[id]; w != ProbeWrite::kNone; w = m_writes[w].next)
                if (m_writes[w].sample != ProbeWrite::kClear) m_writes[w].keep = keepSinceLastSample(id, frame);
            const auto apply = [&](ProbeLight& light, Color ProbeSample::*radiance) {
                light.update(id, [&](float* state) {
                    for (uint32_t w = m_firstWrite[id]; w != ProbeWrite::kNone; w = m_writes[w].next) {
                        const ProbeWrite& write = m_writes[w];
                        if (write.sample == ProbeWrite::kClear) {
                            std::fill_n(state, m_encoding->floatsPerProbe(), 0.0f);
                            continue;
                        }
                        const ProbeSample& sample = sampleOf(write.sample);
                        if (write.keep < 1.0f) m_encoding->fade(state, write.keep);
                        if (write.adds) m_encoding->addSample(state, write.local, sample.*radiance, sample.pdf);
                    }
                });
            };
            apply(m_reflected, &ProbeSample::reflected);
            if (cachesDirect()) apply(m_emitted, &ProbeSample::emitted);
            m_firstWrite[id] = m_lastWrite[id] = ProbeWrite::kNone;
        });
    }

    // The bounded history, applied when a probe is next sampled: the frames since its last sample
    // fade its samples by (1 − 1/history) each. Only the weights change, and those only matter to
    // the probe's next sample (and to which of its bins lean on its mean), so deferring the fade
    // to then costs nothing in what the gather reads. Returns the factor to fade by (1: none) and
    // records the sample's frame.
    float keepSinceLastSample(uint32_t id, int frame) {
        const uint32_t last = std::exchange(m_lastSampled[id], uint32_t(frame));
        if (m_settings.historyFrames == kUnboundedHistory || uint32_t(frame) <= last) return 1.0f;
        const double keepPerFrame = 1.0 - 1.0 / double(m_settings.historyFrames);
        // Often the probe was sampled the frame before: pow(x, 1) is x exactly, without its cost.
        if (uint32_t(frame) - last == 1) return float(keepPerFrame);
        return float(std::pow(keepPerFrame, double(uint32_t(frame) - last)));
    }

    // With allocate_at_updates, a probe at an update's point that has none (off screen too, as
    // SHaRC and GIBS place theirs), counted like the allocation stage's.
    bool placeAtUpdate(const ProbeQuery& query, int frame, uint32_t& id) {
        if (!m_settings.allocateAtUpdates) return false;
        const ProbeInsert result = m_store->insert(query, uint32_t(frame));
        if (result.status == ProbeInsert::Status::Refused) {
            ++m_frameStats.refused;
            return false;
        }
        ++m_frameStats.allocatedAtUpdates;
        growStates();
        if (result.status == ProbeInsert::Status::Evicted) {
            ++m_frameStats.evicted;
            addWrite({result.id, ProbeWrite::kClear, false, vec3(0.0f)});
        }
        id = result.id;
        m_placedSinceLookups.push_back(id);
        return true;
    }

    // Whether a probe placed since m_placedSinceLookups[from] could be the receiver of a query
    // whose receiver was `found` before: a store's receiver lies within its search radius
    // (ProbeStore::receiverOf), and an id placed again names another probe now.
    bool mayHaveChanged(const ProbeQuery& query, uint32_t found, std::size_t from) const {
        if (m_placedSinceLookups.size() == from) return false;
        if (m_placedSinceLookups.size() - from > kPlacedScanLimit) return true;
        const float radius = m_store->searchRadius(query);
        for (std::size_t i = from; i < m_placedSinceLookups.size(); ++i) {
            const uint32_t placed = m_placedSinceLookups[i];
            if (placed == found) return true;
            const vec3 d = m_store->probe(placed).position - query.position;
            if (!(glm::dot(d, d) > radius * radius)) return true;
        }
        return false;
    }

    // As if sequential, in block order: the cache's state does not depend on the thread count.
    // The receivers are settled first, in parallel, against the store as it stands: the one a
    // lookup of the sample's point found earlier in the frame (the raster stage's at v1, the cache
    // read's at v2) unless the allocation stage placed a probe that could change it, else
    // receiverOf(). Then the samples are routed in order (a sample after a probe was placed near
    // it looks its receiver up again, so the outcome is that of one lookup after another), and
    // the states written in parallel, probe by probe.
    void update(int frame) {
        growStates();
        m_written.clear();
        m_writes.clear();
        const std::size_t allocated = m_placedSinceLookups.size();
        m_receivers.assign(2 * m_paths.size(), Receiver{});
        tbb::parallel_for(std::size_t(0), m_receivers.size(), [&](std::size_t i) {
            const ProbeSample& sample = sampleOf(uint32_t(i));
            if (!isUsable(sample)) return;
            const SecondaryPath& path = m_paths[i / 2];
            const uint32_t known = i % 2 == 0 ? m_pixelReceivers[path.pixel] : path.receiverAtV2;
            uint32_t id;
            if (known != kReceiverUnknown && !mayHaveChanged(sample.query, known, 0))
                m_receivers[i] = receiverFor(sample, known);
            else if (m_store->receiverOf(sample.query, id))
                m_receivers[i] = receiverFor(sample, id);
        });
        for (uint32_t i = 0; i < m_receivers.size(); ++i) routeSample(i, frame, m_receivers[i], allocated);
        applyWrites(frame);
    }

    // The pixel's indirect light (and in "cache" direct mode its direct light) from the probes
    // the raster stage found; false when none holds samples. `probes`: the store's probes().
    bool gatherPixel(std::span<const Probe> probes, std::size_t pixel, const GBufferTexel& t, const Bsdf* specular, std::vector<Color>& scratch) {
        const ProbeWeight* served = m_served.data() + m_servedOffsets[pixel];
        const int found = m_servedCounts[pixel];
        const bool gathered = gatherFrom(m_reflected, probes, served, found, t.surface, t.albedo, specular, t.wo, scratch, m_indirect[pixel]);
        if (cachesDirect()) gatherFrom(m_emitted, probes, served, found, t.surface, t.albedo, specular, t.wo, scratch, m_direct[pixel]);
        return gathered;
    }

    void gather() {
        std::atomic<uint64_t> withoutProbe{0};
        tbb::enumerable_thread_specific<std::vector<Color>> scratches;
        const std::span<const Probe> probes = m_store->probes();
        tbb::parallel_for(0, m_gbuffer.height, [&](int y) {
            std::vector<Color>& scratch = scratches.local();
            uint64_t rowWithout = 0;
            for (int x = 0; x < m_gbuffer.width; ++x) {
                const std::size_t pixel = std::size_t(y) * m_gbuffer.width + x;
                const GBufferTexel& t = m_gbuffer.texels[pixel];
                m_indirect[pixel] = Color(0.0f);
                if (!t.valid) continue;
                // Only a glossy surface needs its BSDF (its constructor, here and at path vertices,
                // took 2.4 % of a frame's samples), and a diffuse surface's texel is then read on
                // its first cache line only.
                bool gathered;
                if (t.surface.material->type == MaterialType::Glossy) {
                    const Bsdf bsdf(*t.surface.material, t.albedo, t.surface);
                    gathered = gatherPixel(probes, pixel, t, specularOf(bsdf), scratch);
                } else {
                    gathered = gatherPixel(probes, pixel, t, nullptr, scratch);
                }
                rowWithout += !gathered;
            }
            withoutProbe += rowWithout;
        });
        m_frameStats.pixelsWithoutProbe = withoutProbe;
    }

    void resolve(const FrameContext& ctx, LayeredImage& out) {
        if (ctx.frame == 0 || ctx.cameraMoved || ctx.sceneChanged) m_history = 0;
        m_history = std::min(m_history + 1, m_settings.temporalHistory);
        const float alpha = 1.0f / float(m_history);
        const FrameLayers layers = addFrameLayers(out);
        Image& coverage = out.addOverwritten("coverage", {"Y"});
        tbb::parallel_for(0, ctx.height, [&](int y) {
            for (int x = 0; x < ctx.width; ++x) {
                const std::size_t pixel = std::size_t(y) * ctx.width + x;
                const GBufferTexel& t = m_gbuffer.texels[pixel];
                // In "cache" mode m_direct is read from the cache: current frame only (see the top).
                const bool estimated = !cachesDirect();
                m_meanDirect[pixel] += alpha * (t.seen + (estimated ? m_direct[pixel] : Color(0.0f)) - m_meanDirect[pixel]);
                const Color d = m_meanDirect[pixel] + (estimated ? Color(0.0f) : m_direct[pixel]);
                layers.direct.setRgb(x, y, d);
                layers.indirect.setRgb(x, y, m_indirect[pixel]);
                layers.total.setRgb(x, y, d + m_indirect[pixel]);
                layers.albedo.setRgb(x, y, t.albedo);
                layers.normal.setRgb(x, y, t.valid ? t.surface.shadingNormal : vec3(0.0f));
                layers.depth.at(x, y, 0) = t.valid ? t.depth : 0.0f;
                coverage.at(x, y, 0) = float(m_coverage[pixel] == PixelCoverage::Covered);
            }
        });
        if (m_settings.probeViews)
            addProbeViews(PinholeCamera(ctx.pose, ctx.width, ctx.height), m_gbuffer, *m_store, m_reflected,
                          {m_served.data(), m_servedOffsets.data(), m_servedCounts.data()}, out);
    }

    std::unique_ptr<ProbeStore> m_store;
    ProbePipelineSettings m_settings;
    std::string m_spacingWhere;
    std::unique_ptr<ProbeEncoding> m_encoding;
    std::unique_ptr<RestirDirect> m_restir;  // direct_lighting = "restir" only

    ProbeLight m_reflected;  // per probe: reflected light arriving
    ProbeLight m_emitted;    // per probe, "cache" direct mode only: emission arriving
    std::vector<uint32_t> m_lastSampled;  // per probe: the frame of its last sample (keepSinceLastSample)
    std::vector<uint32_t> m_written;           // probes the update stage writes, in the order of their first write
    std::vector<uint32_t> m_firstWrite, m_lastWrite;  // per probe: its list in m_writes (ProbeWrite::next), kNone when empty
    std::vector<Receiver> m_receivers;         // per sample of m_paths (v1, v2 of each), as the update began
    std::vector<uint32_t> m_placedSinceLookups;  // probes the allocation stage placed, then those placed at updates
    std::vector<ProbeWrite> m_writes;          // the update stage's, routeSample() to applyWrites()

    GBuffer m_gbuffer;
    std::vector<SecondaryPath> m_paths;
    std::vector<Color> m_direct, m_indirect;
    std::vector<Color> m_meanDirect;  // emission seen and NEE, averaged over frames
    // What the raster stage found at each pixel, so that the allocation stage reads no G-buffer
    // texel (their `valid` flag cost it a cache line per pixel).
    enum class PixelCoverage : uint8_t { NoSurface, Uncovered, Covered };
    std::vector<PixelCoverage> m_coverage;
    std::vector<uint32_t> m_pixelReceivers;  // ProbeLookup::receiver of each pixel's raster lookup
    std::vector<ProbeWeight> m_served;  // from the raster stage, servedPerPixel() per pixel at most (ServedProbes)
    std::vector<uint32_t> m_servedOffsets;  // per pixel: where its probes start in m_served
    std::vector<uint8_t> m_servedCounts;
    std::vector<float> m_distance;
    std::vector<int> m_tilePixels;  // the allocation stage's pixelToCover() per tile
    int m_history = 0;
    FrameCounters m_frameStats;
};

}  // namespace

MethodInfo probeCacheMethod(const ProbeStoreInfo& store) {
    auto create = [createStore = store.create, spacingKey = store.spacingKey](Params& params) -> std::unique_ptr<Method> {
        const ProbePipelineSettings settings = readProbePipelineSettings(params);
        return std::make_unique<ProbeCache>(createStore(params), settings, params.where(spacingKey));
    };
    return {store.name, "probe cache: " + store.summary, withPipelineParams(store), create};
}

}  // namespace gibench
