#pragma once
// Where surface probes live and how they are found: the part of the probe-cache pipeline that
// MAMBA (sparse two-level hash), the dense grid (GIBS-like) and cards (Lumen-like) do
// differently. A store owns probe placement (position, normal) under stable ids; the pipeline
// (probe_cache.h) owns what the probes cache, indexed by the same ids.
//
// Threading: insert(), touch(), beginFrame() are called from one thread between parallel
// stages; lookup(), nearest() and probe() are const and called concurrently from many threads.

#include "core/render/method.h"
#include "core/scene/scene.h"
#include "core/util/math.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace gibench {

// A surface point asking for probes: the G-buffer's position, shading normal and triangle.
// How far nearest() looks, in cells (or texels) of the store: probes spaced one cell apart leave
// pixels up to about two cells from the nearest one (an allocation tile may stay 40 % uncovered),
// and the gather must still find the true nearest probes there (docs/mamba.md item 4). Stores
// search the 3-wide block first and widen to the 5-wide block only when it falls short.
inline constexpr int kSearchRings = 2;

struct ProbeQuery {
    vec3 position;
    vec3 normal;  // unit, facing the viewer
    int mesh = -1;
    uint32_t triangle = 0;
    // Random bits of the pixel and frame asking, for a store whose lookup jitters the point
    // (hash_grid): a function of where the query comes from, never of the point's coordinates, so
    // that a scene moved or scaled reads the same cells.
    uint32_t jitter = 0;
};

struct Probe {
    vec3 position;
    vec3 normal;  // unit; the probe caches radiance over the hemisphere around it
};

struct ProbeNeighbour {
    uint32_t id;
    float distance;  // scene units, from the query point to the probe
};

// Stores that compare a probe's squared distance with reach² before taking its square root scale
// reach² by this: the slack keeps every probe whose rounded distance could still be within reach.
inline constexpr float kReachSlack = 1.0f + 1e-5f;

// Adds `candidate` to `out`, the `found` nearest so far sorted by (distance, id), keeping at most
// `count`; returns the new size. The id breaks ties so results never depend on visiting order.
// Entry: a ProbeNeighbour, or a record with the same `id` and `distance` that carries more.
template <class Entry>
int insertNearest(Entry* out, int found, int count, Entry candidate) {
    auto before = [](const Entry& a, const Entry& b) {
        return a.distance < b.distance || (a.distance == b.distance && a.id < b.id);
    };
    if (found == count) {
        if (!before(candidate, out[found - 1])) return found;
        --found;
    }
    int i = found;
    for (; i > 0 && before(candidate, out[i - 1]); --i) out[i] = out[i - 1];
    out[i] = candidate;
    return found + 1;
}

// The raster stage looks up the pixels of a square tile of the screen at once
// (ProbeStore::lookupBatch): kLookupTile pixels a side unless the store's lookupTile() says otherwise.
inline constexpr int kLookupTile = 16;

// The most probes a lookup returns (the gather's "gather_neighbours" at most).
inline constexpr int kMaxServedProbes = 16;

// One probe serving a surface point and its interpolation weight. The weights of a lookup are
// >= 0 and sum to 1 (normaliseWeights); the gather renormalises over the probes that hold samples.
struct ProbeWeight {
    uint32_t id;
    float weight;
};

// What a store answers for a surface point (issue 9: the store decides what serves a point, and
// with which weights): the probes, and whether the point is covered, i.e. needs no new probe. The
// allocation stage spawns a probe in a tile with uncovered pixels, at the one farthest from the
// probes (`distance`).
// ProbeLookup::receiver when the lookup did not settle receiverOf() on its way.
inline constexpr uint32_t kReceiverUnknown = ~uint32_t(0);
// ProbeLookup::receiver when receiverOf() is false: no probe receives an update at the point.
inline constexpr uint32_t kNoReceiver = ~uint32_t(0) - 1;

struct ProbeLookup {
    int count = 0;
    ProbeWeight probes[kMaxServedProbes];
    bool covered = false;
    float distance = kInfinity;  // scene units, to the nearest probe offered; infinite when none
    // What receiverOf() answers for the point (an id, or kNoReceiver) when the lookup found it on
    // its way, e.g. the first of the N nearest; else kReceiverUnknown. The update stage routes
    // the samples of the points it looked up with it instead of asking again.
    uint32_t receiver = kReceiverUnknown;
};

// Scales the weights of `lookup` to sum to 1; equal weights where they are all 0 (every probe
// at the edge of what the lookup accepts).
void normaliseWeights(ProbeLookup& lookup);

struct ProbeInsert {
    enum class Status {
        Inserted,  // a new probe `id`
        Evicted,   // a new probe `id` that reuses the slot of an older one: its cache must be reset
        Refused,   // the store is full there (counted in its stats, never silent)
    } status;
    uint32_t id = 0;
};

class ProbeStore {
public:
    virtual ~ProbeStore() = default;

    // Once per run, before anything else: size grids, lay out cards. Notes record what the
    // store leaves out for this scene.
    virtual void prepare(const Scene& scene, RunNotes& notes) {}
    // At the start of each frame (camera-centred grids move, per-frame budgets reset).
    virtual void beginFrame(const CameraPose& pose, uint32_t frame) {}

    // Places a probe at the query point (the allocation stage found it uncovered).
    virtual ProbeInsert insert(const ProbeQuery& query, uint32_t frame) = 0;
    // Up to `count` distinct probes the store offers for the query point, nearest first;
    // returns how many. Only probes within searchRadius(query) are returned.
    virtual int nearest(const ProbeQuery& query, int count, ProbeNeighbour* out) const = 0;
    // The store's own lookup and interpolation for the point, at most servedAtMost(count) probes;
    // lookupNearest() unless the store has its own. `count` (1 to kMaxServedProbes) is the N of
    // an N-nearest lookup; a store whose lookup is not N-nearest (surfels covering the point,
    // card texels around it) may ignore it.
    virtual void lookup(const ProbeQuery& query, int count, ProbeLookup& out) const { lookupNearest(query, count, out); }
    // lookup() of each of `n` queries in turn, as the raster stage asks them: the pixels of a
    // lookupTile()² tile of the screen, row by row. A store may share work between queries near each
    // other, with the results of one lookup() each.
    virtual void lookupBatch(const ProbeQuery* queries, int n, int count, ProbeLookup* out) const;
    // The edge of the raster stage's tiles in pixels: what the store's lookupBatch() shares work
    // across is measured best at this size.
    virtual int lookupTile() const { return kLookupTile; }
    // nearest() of each of `n` queries in turn (`count` neighbours per query in `out`, how many in
    // `found`), the same way.
    virtual void nearestBatch(const ProbeQuery* queries, int n, int count, ProbeNeighbour* out, int* found) const;
    // lookup() will be asked for each of `n` queries soon, one at a time with other work between
    // (the vertices of a wave of paths): a store may bring into cache what those lookups read
    // first, so that their misses overlap rather than stall one lookup after another.
    virtual void prefetchLookups(const ProbeQuery* queries, int n) const {}
    // The most probes lookup() serves when asked for `count` (at most kMaxServedProbes).
    virtual int servedAtMost(int count) const { return count; }
    // Whether lookup() reads ProbeQuery::jitter: the raster stage draws a pixel's jitter bits only
    // for a store that does (a hash per pixel and frame, 3 % of mamba's raster stage).
    virtual bool readsJitter() const { return false; }
    // One lookup for every store ("lookup": "nearest"): the `count` nearest probes, weighted by
    // (1 − t²)² with t = distance / searchRadius(query), so that probes at the edge of the search
    // fade out instead of popping; covered when the nearest lies within coverageRadius(query) of
    // the point in its tangent plane and along its normal.
    void lookupNearest(const ProbeQuery& query, int count, ProbeLookup& out) const;
    // lookupNearest() of each of `n` queries, through nearestBatch().
    void lookupNearestBatch(const ProbeQuery* queries, int n, int count, ProbeLookup* out) const {
        lookupNearestBatchOf(*this, queries, n, count, out);
    }
    // The same for a store of final type `Store`, whose calls of probe(), nearestBatch() and the
    // radii then bind statically: a store whose own lookup is lookupNearest() (mamba) spares four
    // virtual calls per query (0–2 % of its frame in alternated runs).
    template <class Store>
    static void lookupNearestBatchOf(const Store& store, const ProbeQuery* queries, int n, int count, ProbeLookup* out);
    // The probe an update at the query point goes to, or false when there is none: the nearest,
    // unless the store keys its cache by the point's own cell (hash_grid). Always a probe within
    // searchRadius(query): the update stage relies on it to tell whether a probe placed since
    // could change the answer. A store that overrides it answers false to receiverIsNearest().
    virtual bool receiverOf(const ProbeQuery& query, uint32_t& id) const;
    // Whether receiverOf() is the nearest probe, so that lookupNearest() can report it.
    virtual bool receiverIsNearest() const { return true; }
    // The probe received an update in `frame` (least-recently-used eviction).
    virtual void touch(uint32_t id, uint32_t frame) {}
    // Whether the store accepts one more update for probe `id` this frame (a per-frame budget);
    // a refusal is counted by the caller.
    virtual bool admitUpdate(uint32_t id) { return true; }

    // Every probe by id (ids are dense from 0), valid until the next insert(). A loop over many
    // points reads them through this one call: a virtual probe(id) per served probe cost the
    // gather stage 15–21 % of its time (every store on the Cornell box).
    virtual std::span<const Probe> probes() const = 0;
    const Probe& probe(uint32_t id) const { return probes()[id]; }
    // One more than the largest id handed out so far.
    uint32_t idCapacity() const { return uint32_t(probes().size()); }

    // A pixel is covered when a probe lies within this distance of it in its tangent plane
    // (scene units; a store whose cells grow with the distance to the camera answers per point).
    virtual float coverageRadius(const ProbeQuery& query) const = 0;
    // nearest() looks this far from the query point (scene units): kSearchRings × coverageRadius.
    virtual float searchRadius(const ProbeQuery& query) const = 0;

    // Live probes, bytes held, table load, refused inserts, evictions, ... for the frame record.
    virtual Json stats() const = 0;

private:
    // lookupNearest()'s weights and coverage from the `found` nearest.
    template <class Store>
    static void weighNearest(const Store& store, const ProbeQuery& query, const ProbeNeighbour* neighbours, int found, ProbeLookup& out);
};

template <class Store>
void ProbeStore::lookupNearestBatchOf(const Store& store, const ProbeQuery* queries, int n, int count, ProbeLookup* out) {
    // A tile's worth at a time, so that the neighbours need no allocation.
    constexpr int kChunk = kLookupTile * kLookupTile;
    ProbeNeighbour neighbours[kChunk * kMaxServedProbes];
    int found[kChunk];
    for (int first = 0; first < n; first += kChunk) {
        const int size = std::min(kChunk, n - first);
        store.nearestBatch(queries + first, size, count, neighbours, found);
        for (int i = 0; i < size; ++i) weighNearest(store, queries[first + i], neighbours + std::size_t(i) * count, found[i], out[first + i]);
    }
}

template <class Store>
void ProbeStore::weighNearest(const Store& store, const ProbeQuery& query, const ProbeNeighbour* neighbours, int found, ProbeLookup& out) {
    out.count = found;
    out.covered = false;
    out.distance = kInfinity;
    // nearest() ranks by (distance, id) within searchRadius(query) whatever the count: its first is
    // nearest(query, 1)'s, the default receiverOf().
    out.receiver = !store.receiverIsNearest() ? kReceiverUnknown : found > 0 ? neighbours[0].id : kNoReceiver;
    if (found == 0) return;
    const float radius = store.searchRadius(query);
    for (int i = 0; i < found; ++i) {
        const float t = neighbours[i].distance / radius;
        out.probes[i] = {neighbours[i].id, t < 1.0f ? (1.0f - t * t) * (1.0f - t * t) : 0.0f};
    }
    normaliseWeights(out);
    out.distance = neighbours[0].distance;
    const vec3 d = store.probe(neighbours[0].id).position - query.position;
    const float along = glm::dot(d, query.normal);
    const float tangential = glm::length(d - along * query.normal);
    const float cover = store.coverageRadius(query);
    out.covered = tangential < cover && std::fabs(along) < cover;
}

// One row of the store table (stores/store_table.cpp), the one list of stores: the registry makes
// a method of each row, and the tests and benchmarks over every store read the same rows.
struct ProbeStoreInfo {
    std::string name;     // the method's name too
    std::string summary;  // what the store is, for `gibench methods`
    std::string spacingKey;  // its key of the probe spacing in scene units (a cell or texel edge; probe_spacing.h)
    const ParamTable& (*parameters)();
    // Reads only the keys of parameters() through `params`; invalid values throw InputError
    // naming the key.
    std::unique_ptr<ProbeStore> (*create)(Params& params);
};

}  // namespace gibench
