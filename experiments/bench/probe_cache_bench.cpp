// Benchmarks of the probe-cache pipeline and its stores (the registry's `main` prints ratios):
//  - probe_cache/frame/<store>/<scene>: one frame at 256², after 16 warm-up frames, with the mean
//    milliseconds of every stage as counters; probe_cache/frame/path_traced_1spp/<scene> is the
//    baseline a cache frame should undercut (one path per pixel, every bounce);
//  - probe_cache/frame_pair/<store>/<scene>: the same two frames timed in alternation, a store
//    frame and a baseline frame, which goes first alternating too, so that a drift of the
//    machine's speed during the benchmark moves both alike (timed one benchmark after the other,
//    the ratios moved by ±15 %): counters store_ms, path_ms and their ratio, and the store frame's
//    stages (<stage>_ms), which run here after a path-traced frame;
//  - probe_cache/nearest/<store>: nearest-2 queries for every G-buffer pixel of the Cornell box,
//    a tile at a time as the raster stage asks (ProbeStore::nearestBatch), against the same
//    probe set (one probe every 4th pixel of every 4th row);
//  - probe_cache/nearest_single/<store>: the same queries one at a time (ProbeStore::nearest) in a
//    shuffled order, as the vertices of secondary paths ask them.

#include "core/render/gbuffer.h"
#include "experiments/bench/bench_scenes.h"
#include "experiments/bench/probe_cache_bench.h"
#include "methods/probe_cache/stores/store_table.h"
#include "methods/registry.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <random>
#include <string>

namespace gibench {
namespace {

constexpr int kSize = 256;
constexpr int kWarmUpFrames = 16;

// One method rendering frames of a bench scene at kSize², warmed up by kWarmUpFrames frames.
class FrameRenderer {
public:
    FrameRenderer(const BenchScene& loaded, const std::string& methodName, const Json& block)
        : m_scene(*loaded.scene), m_pose(loaded.pose()) {
        const MethodInfo* info = findMethod(methodName);
        Params params(block, "bench", "/method", methodName, &info->parameters);
        m_method = info->create(params);
        RunNotes notes;
        m_method->prepare(m_scene, kSize, kSize, notes);
        while (m_frame < kWarmUpFrames) {
            StageTimer timer;
            render(timer);
        }
    }
    // As the frame loop does (experiments/frame_loop.cpp): the layers' memory is kept between frames.
    void render(StageTimer& timer) {
        m_image.clearLayersKeepingMemory();
        m_method->renderFrame({m_scene, m_pose, kSize, kSize, m_frame, 1 << 30, false, 1, timer, false}, m_image);
        ++m_frame;
    }
    const Method& method() const { return *m_method; }

private:
    const PreparedScene& m_scene;
    CameraPose m_pose;
    std::unique_ptr<Method> m_method;
    LayeredImage m_image{kSize, kSize};
    int m_frame = 0;
};

void frameTime(benchmark::State& state, const std::string& methodName, const Json& block, const std::string& sceneName) {
    const BenchScene* loaded = benchSceneOrSkip(state, sceneName);
    if (!loaded) return;
    FrameRenderer renderer(*loaded, methodName, block);
    StageTimer stages;
    int64_t frames = 0;
    for (auto _ : state) {
        renderer.render(stages);
        ++frames;
    }
    for (const auto& [name, seconds] : stages.stages()) state.counters[name + "_ms"] = 1000.0 * seconds / double(frames);
    const Json stats = renderer.method().frameStats();
    state.counters["probes"] = stats.value("probes", 0.0);
    state.counters["store_bytes"] = stats.value("store_bytes", 0.0);
}

const Json& pathTracedFrameBlock() {
    static const Json block = {{"spp", 1}, {"accumulate", false}};
    return block;
}

void framePair(benchmark::State& state, const std::string& store, const std::string& sceneName) {
    const BenchScene* loaded = benchSceneOrSkip(state, sceneName);
    if (!loaded) return;
    FrameRenderer cache(*loaded, store, Json::object()), path(*loaded, "path_traced", pathTracedFrameBlock());
    using Clock = std::chrono::steady_clock;
    double cacheSeconds = 0.0, pathSeconds = 0.0;
    bool cacheFirst = true;
    StageTimer cacheStages, pathStages;
    for (auto _ : state) {
        for (int pass = 0; pass < 2; ++pass) {
            const bool timeCache = (pass == 0) == cacheFirst;
            const auto start = Clock::now();
            (timeCache ? cache : path).render(timeCache ? cacheStages : pathStages);
            (timeCache ? cacheSeconds : pathSeconds) += std::chrono::duration<double>(Clock::now() - start).count();
        }
        cacheFirst = !cacheFirst;
    }
    const double pairs = double(state.iterations());
    // The store frame's stages as they run here, after a path-traced frame has taken the caches:
    // not as in probe_cache/frame, where each frame follows one of its own.
    for (const auto& [name, seconds] : cacheStages.stages()) state.counters[name + "_ms"] = 1000.0 * seconds / pairs;
    state.counters["store_ms"] = 1000.0 * cacheSeconds / pairs;
    state.counters["path_ms"] = 1000.0 * pathSeconds / pairs;
    state.counters["ratio"] = cacheSeconds / pathSeconds;
}

enum class QueryOrder { TileByTile, OneAtATimeShuffled };

void nearestQueries(benchmark::State& state, const ProbeStoreInfo& info, QueryOrder order) {
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
    // Tile by tile, as the raster stage asks (ProbeStore::nearestBatch).
    constexpr int kTiles = kSize / kLookupTile;
    std::vector<std::vector<ProbeQuery>> tiles(kTiles * kTiles);
    std::size_t queries = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const GBufferTexel& t = gbuffer.at(x, y);
            if (!t.valid) continue;
            const ProbeQuery q{t.surface.position, t.surface.shadingNormal, t.surface.mesh, t.surface.triangle};
            tiles[(y / kLookupTile) * kTiles + x / kLookupTile].push_back(q);
            ++queries;
            if (x % 4 == 0 && y % 4 == 0) store->insert(q, 0);
        }
    constexpr int kNeighbours = 2;
    std::vector<ProbeNeighbour> out(kLookupTile * kLookupTile * kNeighbours);
    std::vector<int> found(kLookupTile * kLookupTile);
    int64_t total = 0;
    if (order == QueryOrder::OneAtATimeShuffled) {
        std::vector<ProbeQuery> shuffled;
        for (const std::vector<ProbeQuery>& tile : tiles) shuffled.insert(shuffled.end(), tile.begin(), tile.end());
        std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937_64(1));
        for (auto _ : state)
            for (const ProbeQuery& q : shuffled) total += store->nearest(q, kNeighbours, out.data());
    } else {
        for (auto _ : state)
            for (const std::vector<ProbeQuery>& tile : tiles) {
                store->nearestBatch(tile.data(), int(tile.size()), kNeighbours, out.data(), found.data());
                for (std::size_t i = 0; i < tile.size(); ++i) total += found[i];
            }
    }
    benchmark::DoNotOptimize(total);
    state.SetItemsProcessed(state.iterations() * int64_t(queries));
    state.counters["probes"] = double(store->idCapacity());
}

const bool kRegistered = [] {
    const auto registerFrame = [](const std::string& name, const std::string& method, const Json& block) {
        for (const std::string scene : kFrameScenes)
            benchmark::RegisterBenchmark(("probe_cache/frame/" + name + "/" + scene).c_str(),
                                         [method, block, scene](benchmark::State& s) { frameTime(s, method, block, scene); })
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime()
                ->MinTime(2.0);
    };
    registerFrame(kPathTracedFrame, "path_traced", pathTracedFrameBlock());
    for (const ProbeStoreInfo& info : probeStoreTable()) {
        const std::string store = info.name;
        registerFrame(store, store, Json::object());
        for (const std::string scene : kFrameScenes)
            benchmark::RegisterBenchmark(("probe_cache/frame_pair/" + store + "/" + scene).c_str(),
                                         [store, scene](benchmark::State& s) { framePair(s, store, scene); })
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime()
                ->MinTime(4.0);
        benchmark::RegisterBenchmark(("probe_cache/nearest/" + store).c_str(),
                                     [&info](benchmark::State& s) { nearestQueries(s, info, QueryOrder::TileByTile); })
            ->Unit(benchmark::kMillisecond)
            ->MinTime(1.0);
        benchmark::RegisterBenchmark(("probe_cache/nearest_single/" + store).c_str(),
                                     [&info](benchmark::State& s) { nearestQueries(s, info, QueryOrder::OneAtATimeShuffled); })
            ->Unit(benchmark::kMillisecond)
            ->MinTime(1.0);
    }
    return true;
}();

}  // namespace
}  // namespace gibench
