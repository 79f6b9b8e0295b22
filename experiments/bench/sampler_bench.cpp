// Benchmarks of the path tracer's samplers (core/render/sampler.h), independent against
// Sobol–Burley, each pair measured in the same run:
//  - sampler/noise/<scene>/<spp>spp: two seeds of each sampler rendered by `path_traced` at
//    192×128 (all threads); counters relMSE between the two seeds, seconds per render, and
//    efficiency = 1 / (relMSE × seconds), and the ratios sobol/independent, also printed as one line
//    at the end of the run of each case;
//  - sampler/rays/<sampler>/<scene>: rays/s of the path tracer on the pixels of path_tracer_bench.cpp's
//    recorded path set (one thread, 64 bounces): what a sampler adds to the cost of a ray; the
//    sobol case prints its rate over the independent one's, which runs just before it.
// Sponza reads ${GIBENCH_SCENES} and is skipped with the reason when its files are missing.

#include "core/image/metrics.h"
#include "core/render/path_tracing.h"
#include "core/render/sampler.h"
#include "core/util/stage_timer.h"
#include "experiments/bench/bench_scenes.h"
#include "experiments/bench/path_set.h"
#include "methods/path_traced/path_traced.h"

#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <string>

namespace gibench {
namespace {

constexpr int kWidth = 192, kHeight = 128;
constexpr int kBounces = 64;       // as path_tracer_bench.cpp
constexpr int kRaysSize = 64;      // pixels per side of the set traced for rays/s
constexpr int kRaysSpp = 2;
constexpr double kRaysSeconds = 3.0;  // traced per sampler for rays/s

struct Render {
    LayeredImage image;
    double seconds;
};

Render renderPathTraced(const BenchScene& b, const std::string& sampler, int spp, uint64_t seed) {
    Params params(Json{{"spp", spp}, {"sampler", sampler}}, "bench", "", "bench", &pathTracedParams());
    std::unique_ptr<Method> method = createPathTraced(params);
    RunNotes notes;
    method->prepare(*b.scene, kWidth, kHeight, notes);
    StageTimer timer;
    Render r{LayeredImage(kWidth, kHeight), 0.0};
    const auto start = std::chrono::steady_clock::now();
    method->renderFrame({*b.scene, b.pose(), kWidth, kHeight, 0, 1, false, seed, timer, false}, r.image);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
}

// Seed-to-seed relMSE of one sampler and the mean seconds of its two renders.
struct Noise {
    double relMse, seconds;
    double efficiency() const { return 1.0 / (relMse * seconds); }
};

Noise seedToSeedNoise(const BenchScene& b, const std::string& sampler, int spp) {
    const Render one = renderPathTraced(b, sampler, spp, 1);
    const Render two = renderPathTraced(b, sampler, spp, 2);
    return {computeMetrics(one.image.find("total")->image, two.image.find("total")->image).relMse, 0.5 * (one.seconds + two.seconds)};
}

void noise(benchmark::State& state, const std::string& sceneName, int spp) {
    const BenchScene* b = benchSceneOrSkip(state, sceneName);
    if (!b) return;
    Noise independent{}, sobol{};
    for (auto _ : state) {
        independent = seedToSeedNoise(*b, "independent", spp);
        sobol = seedToSeedNoise(*b, "sobol", spp);
    }
    state.counters["relmse_independent"] = independent.relMse;
    state.counters["relmse_sobol"] = sobol.relMse;
    state.counters["s_independent"] = independent.seconds;
    state.counters["s_sobol"] = sobol.seconds;
    state.counters["relmse_ratio"] = sobol.relMse / independent.relMse;
    state.counters["efficiency_ratio"] = sobol.efficiency() / independent.efficiency();
    std::printf("%s %dx%d %d spp: seed-to-seed relMSE independent %.3g, sobol %.3g (sobol/independent %.3f); %.2f s vs %.2f s per render; "
                "efficiency 1/(relMSE s) sobol/independent %.2f\n",
                sceneName.c_str(), kWidth, kHeight, spp, independent.relMse, sobol.relMse, sobol.relMse / independent.relMse,
                independent.seconds, sobol.seconds, sobol.efficiency() / independent.efficiency());
}

template <PathSampler Sampler, typename MakeSampler>
uint64_t traceRaysSet(const BenchScene& b, MakeSampler makeSampler) {
    PathSettings settings;
    settings.maxDepth = kBounces + 1;
    return tracePathSet<Sampler>(b, kRaysSize, kRaysSpp, settings, makeSampler);
}

void rays(benchmark::State& state, const std::string& sampler, const std::string& sceneName) {
    static std::map<std::string, double> independentRaysPerSecond;  // by scene
    const ScopedFlushToZero flushToZero;
    const BenchScene* b = benchSceneOrSkip(state, sceneName);
    if (!b) return;
    // One benchmark iteration of kRaysSeconds, so that the function runs once and prints once.
    uint64_t rays = 0;
    double seconds = 0.0;
    for (auto _ : state) {
        const auto start = std::chrono::steady_clock::now();
        do {
            rays += sampler == "sobol"
                        ? traceRaysSet<SobolSampler>(*b, [](uint64_t pixel, uint32_t s) { return SobolSampler(1, 0, pixel, s); })
                        : traceRaysSet<IndependentSampler>(
                              *b, [](uint64_t pixel, uint32_t s) { return IndependentSampler(Rng::forPath(1, 0, pixel, s)); });
            seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        } while (seconds < kRaysSeconds);
    }
    const double rate = double(rays) / seconds;
    state.counters["rays_per_s"] = rate;
    if (sampler == "independent") independentRaysPerSecond[sceneName] = rate;
    const auto baseline = independentRaysPerSecond.find(sceneName);
    if (sampler == "sobol" && baseline != independentRaysPerSecond.end())
        std::printf("%s path tracer rays/s (1 thread): sobol %.2f M, independent %.2f M: ratio %.3f\n", sceneName.c_str(), rate * 1e-6,
                    baseline->second * 1e-6, rate / baseline->second);
}

const bool kRegistered = [] {
    for (const std::string scene : {"cornell_box", "sponza"}) {
        for (const int spp : {64, 1024})
            benchmark::RegisterBenchmark(("sampler/noise/" + scene + "/" + std::to_string(spp) + "spp").c_str(),
                                         [scene, spp](benchmark::State& s) { noise(s, scene, spp); })
                ->Unit(benchmark::kSecond)
                ->Iterations(1)
                ->UseRealTime();
        for (const std::string sampler : {"independent", "sobol"})
            benchmark::RegisterBenchmark(("sampler/rays/" + sampler + "/" + scene).c_str(),
                                         [sampler, scene](benchmark::State& s) { rays(s, sampler, scene); })
                ->Unit(benchmark::kSecond)
                ->Iterations(1)
                ->UseRealTime();
    }
    return true;
}();

}  // namespace
}  // namespace gibench
