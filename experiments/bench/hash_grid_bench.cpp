// Benchmarks of MAMBA's sparse hash grid against general-purpose hash maps keyed by the same
// CellKey and hashed by the same function (hashCellKey; the grid indexes its first level by that
// hash's top bits and its tables by the same multiplicative hash of a cell's offset in its coarse
// cell), on one key stream: 500k points sampled uniformly by area on the surfaces of a 30 × 12 × 30
// room holding four boxes, quantised to 0.4-unit cells and tagged with their face's facing, so the
// keys cluster on planes as a real scene's probes do (about 25k distinct keys in 18 coarse cells).
// The grid runs with the original's constants (SparseHashGridConfig defaults).
//  - insert: a fresh container per iteration (construction and destruction timed: for the grid,
//    a 64-slot table per coarse cell, grown as keys arrive), then insert-if-absent of every stream
//    key; items = stream keys.
//  - find: a container holding every distinct key; one lookup per stream key; items = lookups.
//  - find_pair (with absl): the grid's and absl::flat_hash_map's find passes over the stream,
//    alternated within each iteration (which goes first alternates too), each timed on its own:
//    this machine's speed drifts by up to 40 % between benchmarks run one after the other, which
//    moved the find ratio between 0.54 and 0.92; alternated, both see the same moments. Counters
//    grid_ms, absl_ms and ratio = absl_ms / grid_ms (the grid's rate in units of absl's);
//    grid_kib and absl_kib, the memory each pass walks over.
//  - neighbours27: the same container; the 3×3×3 block around every stream key, as the coverage
//    test and the gather query it (the grid's forEachNeighbour, 27 finds for the maps);
//    items = cells looked up (27 per stream key).
// The stream is in sampling order, i.e. spatially incoherent: a worst case next to the screen-order
// queries of the renderer.

#include "core/util/rng.h"
#include "methods/probe_cache/stores/mamba/sparse_hash_grid.h"

#include <benchmark/benchmark.h>

#ifdef GIBENCH_HAVE_ABSL
#include <absl/container/flat_hash_map.h>
#endif

#include <chrono>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace gibench {
namespace {

constexpr std::size_t kStreamKeys = 500000;
constexpr float kCellSize = 0.4f;

struct CellKeyHash {
    std::size_t operator()(const CellKey& k) const noexcept { return std::size_t(hashCellKey(k)); }
};

// An axis-aligned face: `axis` is constant at `at`, the other two axes span [lo, hi]; `facing` is
// the tag of its normal (1..6: +x, -x, +y, -y, +z, -z).
struct Face {
    int axis;
    float at;
    vec2 lo, hi;
    uint8_t facing;
    float area() const { return (hi.x - lo.x) * (hi.y - lo.y); }
};

// The six faces of box [lo, hi], normals pointing out (or into the box for a room).
void addBox(std::vector<Face>& faces, const vec3& lo, const vec3& hi, bool inward) {
    for (int axis = 0; axis < 3; ++axis) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        const vec2 spanLo(lo[u], lo[v]), spanHi(hi[u], hi[v]);
        const uint8_t positive = uint8_t(1 + 2 * axis), negative = uint8_t(2 + 2 * axis);
        faces.push_back({axis, hi[axis], spanLo, spanHi, inward ? negative : positive});
        faces.push_back({axis, lo[axis], spanLo, spanHi, inward ? positive : negative});
    }
}

struct KeyStream {
    std::vector<CellKey> stream;    // kStreamKeys keys, with repeats, in sampling order
    std::vector<CellKey> distinct;  // each key of the stream once, in first-seen order
};

const KeyStream& keyStream() {
    static const KeyStream keys = [] {
        std::vector<Face> faces;
        addBox(faces, vec3(0.0f), vec3(30.0f, 12.0f, 30.0f), true);
        addBox(faces, vec3(4.0f, 0.0f, 4.0f), vec3(10.0f, 6.0f, 10.0f), false);
        addBox(faces, vec3(18.0f, 0.0f, 8.0f), vec3(26.0f, 3.0f, 14.0f), false);
        addBox(faces, vec3(12.0f, 0.0f, 20.0f), vec3(16.0f, 10.0f, 24.0f), false);
        addBox(faces, vec3(22.0f, 5.0f, 20.0f), vec3(28.0f, 5.2f, 28.0f), false);  // a thin shelf
        std::vector<float> cdf;
        float total = 0.0f;
        for (const Face& f : faces) cdf.push_back(total += f.area());

        SparseHashGridConfig config;
        config.fineCellSize = kCellSize;
        config.policy = FullPolicy::Refuse;  // only its keyOf()
        const SparseHashGrid quantiser(config, nullptr);
        KeyStream k;
        std::unordered_set<CellKey, CellKeyHash> seen;
        Rng rng(11, 0);
        while (k.stream.size() < kStreamKeys) {
            const float pick = rng.uniform() * total;
            std::size_t i = 0;
            while (i + 1 < faces.size() && cdf[i] <= pick) ++i;
            const Face& f = faces[i];
            vec3 p;
            p[f.axis] = f.at;
            p[(f.axis + 1) % 3] = f.lo.x + rng.uniform() * (f.hi.x - f.lo.x);
            p[(f.axis + 2) % 3] = f.lo.y + rng.uniform() * (f.hi.y - f.lo.y);
            const CellKey key = quantiser.keyOf(p, f.facing);
            k.stream.push_back(key);
            if (seen.insert(key).second) k.distinct.push_back(key);
        }
        return k;
    }();
    return keys;
}

// The three operations under test, one adapter per container, so every benchmark body is shared.
class GridIndex {
public:
    void insert(const CellKey& k, uint32_t v) { m_grid.insert(k, v); }
    std::optional<uint32_t> find(const CellKey& k) const { return m_grid.find(k); }
    template <class F>
    void forEachNeighbour(const CellKey& k, F&& f) const { m_grid.forEachNeighbour(k, f); }
    // Both levels' tables and their bitmaps.
    std::size_t bytes() const { return m_grid.stats().bytes; }

private:
    // The key stream stays well within the tables' capacity: nothing is evicted, so the owner's
    // record of use is never asked for.
    SparseHashGrid m_grid{SparseHashGridConfig{.fineCellSize = kCellSize}, [](uint32_t) { return 0u; }};
};

template <class Map>
class MapIndex {
public:
    void insert(const CellKey& k, uint32_t v) { m_map.try_emplace(k, v); }
    std::optional<uint32_t> find(const CellKey& k) const {
        const auto it = m_map.find(k);
        return it == m_map.end() ? std::nullopt : std::optional<uint32_t>(it->second);
    }
    template <class F>
    void forEachNeighbour(const CellKey& k, F&& f) const {
        for (int64_t dz = -1; dz <= 1; ++dz)
            for (int64_t dy = -1; dy <= 1; ++dy)
                for (int64_t dx = -1; dx <= 1; ++dx) {
                    const CellKey n{k.x + dx, k.y + dy, k.z + dz, k.facing};
                    const auto it = m_map.find(n);
                    if (it != m_map.end()) f(n, it->second);
                }
    }
    // A flat map's slots and its control bytes (one per slot), as absl lays them out; not meant
    // for node-based maps.
    std::size_t bytes() const { return m_map.capacity() * (sizeof(typename Map::value_type) + 1); }

private:
    Map m_map;
};

template <class Index>
const Index& filledIndex() {
    static const Index index = [] {
        Index i;
        const std::vector<CellKey>& distinct = keyStream().distinct;
        for (std::size_t n = 0; n < distinct.size(); ++n) i.insert(distinct[n], uint32_t(n));
        return i;
    }();
    return index;
}

template <class Index>
void insertKeys(benchmark::State& state) {
    const std::vector<CellKey>& stream = keyStream().stream;
    for (auto _ : state) {
        Index index;
        for (std::size_t n = 0; n < stream.size(); ++n) index.insert(stream[n], uint32_t(n));
        benchmark::DoNotOptimize(index);
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(stream.size()));
    state.counters["distinct_keys"] = double(keyStream().distinct.size());
}

template <class Index>
void findKeys(benchmark::State& state) {
    const std::vector<CellKey>& stream = keyStream().stream;
    const Index& index = filledIndex<Index>();
    for (auto _ : state) {
        uint64_t sum = 0, misses = 0;
        for (const CellKey& k : stream) {
            const std::optional<uint32_t> v = index.find(k);
            sum += v.value_or(0);
            misses += !v;
        }
        benchmark::DoNotOptimize(sum);
        if (misses) state.SkipWithError("a stored key was not found");
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(stream.size()));
}

// One find per stream key; the sum of the values found, which a missing key would change.
template <class Index>
uint64_t findAll(const Index& index) {
    uint64_t sum = 0;
    for (const CellKey& k : keyStream().stream) sum += index.find(k).value_or(0);
    return sum;
}

template <class Index>
void findNeighbours(benchmark::State& state) {
    const std::vector<CellKey>& stream = keyStream().stream;
    const Index& index = filledIndex<Index>();
    uint64_t found = 0;
    for (auto _ : state) {
        uint64_t sum = 0;
        found = 0;
        for (const CellKey& k : stream)
            index.forEachNeighbour(k, [&](const CellKey&, uint32_t v) {
                sum += v;
                ++found;
            });
        benchmark::DoNotOptimize(sum);
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(stream.size()) * 27);
    // The same for every container: a cross-check that all of them answer the same query.
    state.counters["found_per_query"] = double(found) / double(stream.size());
}

using StdIndex = MapIndex<std::unordered_map<CellKey, uint32_t, CellKeyHash>>;

BENCHMARK(insertKeys<GridIndex>)->Name("hash_grid/insert/sparse_hash_grid")->Unit(benchmark::kMillisecond);
BENCHMARK(insertKeys<StdIndex>)->Name("hash_grid/insert/std_unordered_map")->Unit(benchmark::kMillisecond);
BENCHMARK(findKeys<GridIndex>)->Name("hash_grid/find/sparse_hash_grid")->Unit(benchmark::kMillisecond);
BENCHMARK(findKeys<StdIndex>)->Name("hash_grid/find/std_unordered_map")->Unit(benchmark::kMillisecond);
BENCHMARK(findNeighbours<GridIndex>)->Name("hash_grid/neighbours27/sparse_hash_grid")->Unit(benchmark::kMillisecond);
BENCHMARK(findNeighbours<StdIndex>)->Name("hash_grid/neighbours27/std_unordered_map")->Unit(benchmark::kMillisecond);

#ifdef GIBENCH_HAVE_ABSL
using AbslIndex = MapIndex<absl::flat_hash_map<CellKey, uint32_t, CellKeyHash>>;
BENCHMARK(insertKeys<AbslIndex>)->Name("hash_grid/insert/absl_flat_hash_map")->Unit(benchmark::kMillisecond);
BENCHMARK(findKeys<AbslIndex>)->Name("hash_grid/find/absl_flat_hash_map")->Unit(benchmark::kMillisecond);
void findPair(benchmark::State& state) {
    const GridIndex& grid = filledIndex<GridIndex>();
    const AbslIndex& absl = filledIndex<AbslIndex>();
    using Clock = std::chrono::steady_clock;
    double gridSeconds = 0.0, abslSeconds = 0.0;
    bool gridFirst = true;
    for (auto _ : state) {
        for (int pass = 0; pass < 2; ++pass) {
            const bool timeGrid = (pass == 0) == gridFirst;
            const auto start = Clock::now();
            const uint64_t sum = timeGrid ? findAll(grid) : findAll(absl);
            const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
            benchmark::DoNotOptimize(sum);
            (timeGrid ? gridSeconds : abslSeconds) += seconds;
        }
        gridFirst = !gridFirst;
    }
    const double iterations = double(state.iterations());
    state.counters["grid_ms"] = 1000.0 * gridSeconds / iterations;
    state.counters["absl_ms"] = 1000.0 * abslSeconds / iterations;
    state.counters["ratio"] = abslSeconds / gridSeconds;
    // What each find pass walks over, against the caches' sizes (the grid's speed falls further
    // than absl's when the machine is slow: docs/performance.md, "Lookups").
    state.counters["grid_kib"] = double(grid.bytes()) / 1024.0;
    state.counters["absl_kib"] = double(absl.bytes()) / 1024.0;
}
BENCHMARK(findPair)->Name("hash_grid/find_pair/sparse_hash_grid_vs_absl")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(findNeighbours<AbslIndex>)->Name("hash_grid/neighbours27/absl_flat_hash_map")->Unit(benchmark::kMillisecond);
#endif

}  // namespace
}  // namespace gibench
