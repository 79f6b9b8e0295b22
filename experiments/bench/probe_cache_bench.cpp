// Benchmarks of the probe-cache pipeline and its stores (the registry's `main` prints ratios):
//  - probe_cache/frame/<store>/<scene>: one frame at 256², after 16 warm-up frames, with the mean
//    milliseconds of every stage as counters;
//  - probe_cache/nearest/<store>: nearest-2 queries for every G-buffer pixel of the Cornell box
//    against the same probe set (one probe every 4th pixel of every 4th row).

#include "core/render/gbuffer.h"
#include "experiments/bench/bench_scenes.h"
#include "methods/probe_cache/stores/store_table.h"
#include "methods/registry.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <memory>
#include <string>

namespace gibench {
namespace {

constexpr int kSize = 256;
constexpr int kWarmUpFrames = 16;

void frameTime(benchmark::State& state, const std::string& store, const std::string& sceneName) {
    const BenchScene* loaded = benchSceneOrSkip(state, sceneName);
    if (!loaded) return;
    const PreparedScene& scene = *loaded->scene;
    const CameraPose pose = loaded->pose();
    const MethodInfo* info = findMethod(store);
    Params params(Json::object(), "bench", "/method", store, &info->parameters);
    std::unique_ptr<Method> method = info->create(params);
    RunNotes notes;
    method->prepare(scene, kSize, kSize, notes);
    int frame = 0;
    auto render = [&](StageTimer& timer) {
        LayeredImage image(kSize, kSize);
        method->renderFrame({scene, pose, kSize, kSize, frame, 1 << 30, false, 1, timer, false}, image);
        ++frame;
    };
    for (; frame < kWarmUpFrames;) {
        StageTimer timer;
        render(timer);
    }
    StageTimer stages;
    int64_t frames = 0;
    for (auto _ : state) {
        render(stages);
        ++frames;
    }
    for (const auto& [name, seconds] : stages.stages()) state.counters[name + "_ms"] = 1000.0 * seconds / double(frames);
    const Json stats = method->frameStats();
    state.counters["probes"] = stats.value("probes", 0.0);
}

void nearestQueries(benchmark::State& state, const ProbeStoreInfo& info) {
    const BenchScene* loaded = benchSceneOrSkip(state, "cornell_box");
    if (!loaded) return;
    const PreparedScene& scene = *loaded->scene;
    GBuffer gbuffer;
    renderGBuffer(scene, PinholeCamera(loaded->pose(), kSize, kSize), 1, 0, gbuffer);
    // The same probe set for every store: cards start empty instead of capturing the scene.
    const ParamTable& table = info.parameters();
    const bool captures = std::any_of(table.begin(), table.end(), [](const ParamSpec& row) { return row.name == "capture"; });
    Params params(captures ? Json{{"capture", "on_demand"}} : Json::object(), "bench", "/method", info.name, &table);
    std::unique_ptr<ProbeStore> store = info.create(params);
    RunNotes notes;
    store->prepare(scene.scene, notes);
    std::vector<ProbeQuery> queries;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const GBufferTexel& t = gbuffer.at(x, y);
            if (!t.valid) continue;
            const ProbeQuery q{t.surface.position, t.surface.shadingNormal, t.surface.mesh, t.surface.triangle};
            queries.push_back(q);
            if (x % 4 == 0 && y % 4 == 0) store->insert(q, 0);
        }
    int64_t found = 0;
    for (auto _ : state) {
        ProbeNeighbour out[2];
        for (const ProbeQuery& q : queries) found += store->nearest(q, 2, out);
    }
    benchmark::DoNotOptimize(found);
    state.SetItemsProcessed(state.iterations() * int64_t(queries.size()));
    state.counters["probes"] = double(store->idCapacity());
}

const bool kRegistered = [] {
    for (const ProbeStoreInfo& info : probeStoreTable()) {
        const std::string store = info.name;
        for (const std::string scene : {"cornell_box", "sponza"})
            benchmark::RegisterBenchmark(("probe_cache/frame/" + store + "/" + scene).c_str(),
                                         [store, scene](benchmark::State& s) { frameTime(s, store, scene); })
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime()
                ->MinTime(2.0);
        benchmark::RegisterBenchmark(("probe_cache/nearest/" + store).c_str(), [&info](benchmark::State& s) { nearestQueries(s, info); })
            ->Unit(benchmark::kMillisecond)
            ->MinTime(1.0);
    }
    return true;
}();

}  // namespace
}  // namespace gibench
