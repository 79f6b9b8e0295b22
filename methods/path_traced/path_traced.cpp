// Method "path_traced": unbiased path tracing (core/render/path_tracing.h) over 16×16 pixel tiles,
// with independent or Sobol–Burley random numbers (core/render/sampler.h).
//
// Each frame writes layers total, direct, indirect, albedo, normal, depth, and variance: the
// per-pixel, per-channel sample variance of `total` over n, which tests and reports use as the
// noise floor. It is the variance of the mean for independent samples; Sobol–Burley samples of a
// pixel are not independent, and for them it is the variance independent samples of the same
// spread would give — an overestimate wherever stratification pays, i.e. a conservative floor. depth is the mean distance to the first hit over the samples that hit a surface (FrameLayers). Samples
// that come out NaN or infinite are dropped and counted, never averaged in.

#include "methods/path_traced/path_traced.h"

#include "core/render/path_tracing.h"
#include "core/render/sampler.h"
#include "core/util/progress.h"
#include "core/util/rng.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <vector>

namespace gibench {

namespace {

enum class SamplerKind { Independent, Sobol };

const EnumChoices<SamplerKind>& samplerChoices() {
    static const EnumChoices<SamplerKind> choices = {{"independent", SamplerKind::Independent}, {"sobol", SamplerKind::Sobol}};
    return choices;
}

}  // namespace

const ParamTable& pathTracedParams() {
    static const ParamTable table = {
        {"spp", ParamType::Int, 16, "samples per pixel per frame", 1, 1 << 24},
        {"max_depth", ParamType::Int, 1024, "scattering events per path, pbrt's convention: 1 = direct lighting only (Cycles' \"max bounces\" b is max_depth b + 1)", 0, 65536},
        {"rr_depth", ParamType::Int, 3, "depth from which Russian roulette may end a path", 1, 65536},
        {"accumulate", ParamType::Bool, true, "while the camera is still, average each frame with the frames before it"},
        {"sampler", ParamType::String, "sobol",
         "random numbers of the paths: independent (PCG32) or sobol (Sobol-Burley: low discrepancy, Owen-scrambled per pixel)", -INFINITY,
         INFINITY, choiceNames(samplerChoices())},
    };
    return table;
}

namespace {

constexpr int kTileSize = 16;

// Running sums of one pixel over the samples since accumulation last restarted.
struct PixelSums {
    double total[3] = {0, 0, 0};
    double totalSquared[3] = {0, 0, 0};
    double direct[3] = {0, 0, 0};
    double indirect[3] = {0, 0, 0};
    float albedo[3] = {0, 0, 0};
    float normal[3] = {0, 0, 0};
    float depth = 0.0f;        // over the samples that hit a surface
    uint32_t surfaceHits = 0;
    uint32_t samples = 0;
};

class PathTraced final : public Method {
public:
    PathTraced(int spp, PathSettings settings, bool accumulate, SamplerKind sampler)
        : m_spp(spp), m_settings(settings), m_accumulate(accumulate), m_sampler(sampler) {}

    void prepare(const PreparedScene& scene, int width, int height, RunNotes& notes) override {
        m_sums.assign(std::size_t(width) * height, PixelSums{});
    }

    void renderFrame(const FrameContext& ctx, LayeredImage& out) override {
        if (!m_accumulate || ctx.cameraMoved || ctx.sceneChanged || ctx.frame == 0) {
            std::fill(m_sums.begin(), m_sums.end(), PixelSums{});
            m_epochFrame = ctx.frame;
            m_epochSamples = 0;
        }
        {
            ScopedStage stage(ctx.timer, "path_trace");
            trace(ctx);
        }
        ScopedStage stage(ctx.timer, "resolve");
        resolve(out);
    }

    Json frameStats() const override {
        return {{"rays", m_rays}, {"samples", m_samples}, {"nonfinite_samples", m_nonfinite}, {"spp_accumulated", m_epochSamples}};
    }

private:
    void trace(const FrameContext& ctx) {
        const PinholeCamera camera(ctx.pose, ctx.width, ctx.height);
        const int tilesX = (ctx.width + kTileSize - 1) / kTileSize;
        const int tilesY = (ctx.height + kTileSize - 1) / kTileSize;
        Progress progress("frame " + std::to_string(ctx.frame + 1) + "/" + std::to_string(ctx.frameCount), uint64_t(tilesX) * tilesY,
                          ctx.showProgress);
        std::atomic<uint64_t> rays{0}, nonfinite{0};
        const uint32_t firstSample = m_epochSamples;

        tbb::parallel_for(0, tilesX * tilesY, [&](int tile) {
            const ScopedFlushToZero flushToZero;
            const int x0 = (tile % tilesX) * kTileSize, y0 = (tile / tilesX) * kTileSize;
            const int xEnd = std::min(x0 + kTileSize, ctx.width);
            uint64_t tileRays = 0, tileNonfinite = 0;
            const auto add = [&](PixelSums& sums, const PathResult& r) {
                tileRays += r.rays;
                const Color total = r.direct + r.indirect;
                if (!isFinite(total)) {
                    ++tileNonfinite;
                    return;
                }
                for (int c = 0; c < 3; ++c) {
                    sums.total[c] += total[c];
                    sums.totalSquared[c] += double(total[c]) * total[c];
                    sums.direct[c] += r.direct[c];
                    sums.indirect[c] += r.indirect[c];
                    sums.albedo[c] += r.albedo[c];
                    sums.normal[c] += r.normal[c];
                }
                if (std::isfinite(r.depth)) {
                    sums.depth += r.depth;
                    ++sums.surfaceHits;
                }
                ++sums.samples;
            };
            // A tile's paths of one sample index go together (tracePixelPaths): neighbouring
            // pixels' camera rays share packets, and the tile has paths enough to keep the
            // packets of later bounces full. Each pixel still gets its samples in order.
            const int yEnd = std::min(y0 + kTileSize, ctx.height);
            std::vector<PathResult> results;
            const auto traceTile = [&](auto makeSampler) {
                using Sampler = decltype(makeSampler(uint64_t(0)));
                tracePixelPaths<Sampler>(ctx.scene, camera, ctx.width, x0, y0, xEnd, yEnd, makeSampler, m_settings, results);
                std::size_t i = 0;
                for (int y = y0; y < yEnd; ++y)
                    for (int x = x0; x < xEnd; ++x) add(m_sums[uint64_t(y) * ctx.width + x], results[i++]);
            };
            for (int s = 0; s < m_spp; ++s) {
                const uint32_t sample = firstSample + uint32_t(s);
                if (m_sampler == SamplerKind::Sobol)
                    traceTile([&](uint64_t pixel) { return SobolSampler(ctx.seed, uint64_t(m_epochFrame), pixel, sample); });
                else
                    traceTile([&](uint64_t pixel) { return IndependentSampler(Rng::forPath(ctx.seed, uint64_t(m_epochFrame), pixel, sample)); });
            }
            rays += tileRays;
            nonfinite += tileNonfinite;
            progress.advance();
        });
        progress.finish();
        m_epochSamples += uint32_t(m_spp);
        m_rays = rays.load();
        m_nonfinite = nonfinite.load();
        m_samples = uint64_t(m_spp) * ctx.width * ctx.height;
    }

    void resolve(LayeredImage& out) const {
        const FrameLayers layers = addFrameLayers(out);
        Image& variance = out.addOverwritten("variance", {"R", "G", "B"});
        tbb::parallel_for(0, out.height, [&](int y) {
            for (int x = 0; x < out.width; ++x) {
                const PixelSums& s = m_sums[std::size_t(y) * out.width + x];
                const double n = std::max<double>(s.samples, 1.0);
                for (int c = 0; c < 3; ++c) {
                    const double mean = s.total[c] / n;
                    layers.total.at(x, y, c) = float(mean);
                    layers.direct.at(x, y, c) = float(s.direct[c] / n);
                    layers.indirect.at(x, y, c) = float(s.indirect[c] / n);
                    layers.albedo.at(x, y, c) = float(s.albedo[c] / n);
                    layers.normal.at(x, y, c) = float(s.normal[c] / n);
                    // Unbiased sample variance, divided by n: the variance of the pixel's mean.
                    const double sampleVariance = s.samples > 1 ? std::max(0.0, (s.totalSquared[c] - n * mean * mean) / (n - 1.0)) : 0.0;
                    variance.at(x, y, c) = float(sampleVariance / n);
                }
                layers.depth.at(x, y, 0) = s.surfaceHits > 0 ? s.depth / float(s.surfaceHits) : 0.0f;
            }
        });
    }

    int m_spp;
    PathSettings m_settings;
    bool m_accumulate;
    SamplerKind m_sampler;
    std::vector<PixelSums> m_sums;
    int m_epochFrame = 0;
    uint32_t m_epochSamples = 0;
    uint64_t m_rays = 0, m_samples = 0, m_nonfinite = 0;
};

}  // namespace

std::unique_ptr<Method> createPathTraced(Params& params) {
    PathSettings settings;
    const int spp = int(params.getInt("spp"));
    settings.maxDepth = int(params.getInt("max_depth"));
    settings.russianRouletteDepth = int(params.getInt("rr_depth"));
    const bool accumulate = params.getBool("accumulate");
    const SamplerKind sampler = params.getEnum("sampler", samplerChoices());
    return std::make_unique<PathTraced>(spp, settings, accumulate, sampler);
}

}  // namespace gibench
