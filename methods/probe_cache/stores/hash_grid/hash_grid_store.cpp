// Probe store "hash_grid" (SHaRC-like: NVIDIA's Spatially Hashed Radiance Cache): one level of
// hashing, no explicit probe placement. The cell at a surface point *is* its cache entry.
//
// Key: the point's cell at its level of detail, cells laid from the scene's corner, and the
// dominant axis and sign of its normal (the two sides of a thin wall apart). Level 0 cells have the edge cell_size; beyond lod_distance
// level-0 edges from the camera a cell doubles its edge with every doubling of the distance
// (level = 1 + floor(log2(d / lod_distance)), at most kMaxLevel), so that cells cover roughly
// the same number of pixels wherever they are. Before the first frame (no camera yet) every point
// is at level 0. The key's 64-bit hash gives a home slot (low bits) and a fingerprint (high bits)
// in a FingerprintTable of table_slots slots, probed linearly up to max_probe_length slots; a
// matching fingerprint is confirmed against the key kept with the probe.
//
// insert() creates the entry of the query's cell at the query's position and normal, or refuses
// and counts why: the cell has one (cell_occupied), every slot within reach of its home is taken
// (table_full), or the query names no surface point (invalid_queries). With the pipeline's
// allocate_at_updates (its default) updates create entries wherever paths land, on screen or off,
// as SHaRC does. receiverOf() is the point's own cell.
//
// lookup() reads one entry, weight 1: the cell at the point moved by up to half a cell in its
// tangent plane (by ProbeQuery::jitter, bits of the pixel and frame asking), which trades
// SHaRC's blocky cells for noise; the point's own cell where the jittered one has no entry. The
// point is covered when its own cell has an entry.
//
// nearest() offers the entries of the same level and facing within searchRadius() = kSearchRings
// cell edges at the query's level, from the 27 cells around the query first, then the 5³ block.
//
// Eviction: beginFrame() removes every entry no update touched for more than stale_frames frames
// (stale_evictions); its id is reused by a later insert, reported as Evicted so that the pipeline
// resets its cache.
//
// Memory (stats "store_bytes"): table_slots × 8 bytes (fingerprint and id) from prepare() on, plus
// per probe its Probe, key and last-updated frame (std::vector capacities) and a free-list entry.

#include "methods/probe_cache/stores/hash_grid/hash_grid_store.h"

#include "core/util/error.h"
#include "core/util/rng.h"
#include "methods/probe_cache/probe_spacing.h"
#include "methods/probe_cache/stores/hash_grid/fingerprint_table.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <vector>

namespace gibench {

const ParamTable& hashGridStoreParams() {
    static const ParamTable table = joinTables(
        spacingParams("cell_size", "level-0 cell edge (the cells nearest the camera)"),
        {
            {"lod_distance", ParamType::Float, 64.0,
             "in level-0 cell edges: beyond this distance from the camera a cell doubles its edge with every doubling of the distance",
             1.0, 1e9},
            {"table_slots", ParamType::Int, 1 << 17, "hash table slots: the cache entries at most; allocated whole", 1, 1 << 23},
            {"max_probe_length", ParamType::Int, 16, "slots examined from a key's home slot; an insert finding none free is refused", 1, 4096},
            {"stale_frames", ParamType::Int, 64, "an entry no update reached for more than this many frames is evicted", 1, 1 << 30},
            {"jitter", ParamType::Bool, true, "lookups read the cell at the point moved by up to half a cell in its tangent plane"},
        },
        "hash_grid");
    return table;
}

namespace {

// Levels of detail at most: a cell 2^20 times the level-0 edge covers any scene ProbeSpacing admits.
constexpr int kMaxLevel = 20;

struct HashGridSettings {
    ProbeSpacing cellSize;
    double lodDistance = 0.0;  // level-0 cell edges
    uint32_t tableSlots = 0;
    uint32_t maxProbeLength = 0;
    uint32_t staleFrames = 0;
    bool jitter = true;
};

struct HashCellKey {
    int64_t x, y, z;
    uint8_t level;
    uint8_t facing;  // 1 + dominantDirection(normal)
    bool operator==(const HashCellKey&) const = default;
};

uint64_t hashOf(const HashCellKey& k) {
    uint64_t h = mix64(uint64_t(k.x));
    h = mix64(h ^ uint64_t(k.y));
    h = mix64(h ^ uint64_t(k.z));
    return mix64(h ^ (uint64_t(k.level) << 8 | k.facing));
}

class HashGridStore final : public ProbeStore {
public:
    explicit HashGridStore(HashGridSettings settings) : m_settings(std::move(settings)) {}

    void prepare(const Scene& scene, RunNotes& notes) override {
        m_cellSize = m_settings.cellSize.resolve(scene.bounds());
        for (int level = 0; level <= kMaxLevel; ++level) m_edges[level] = std::ldexp(m_cellSize, level);
        const double lodDistance = m_settings.lodDistance * double(m_cellSize);
        m_inverseLodDistance2 = 1.0 / (lodDistance * lodDistance);
        // Cells are laid from the scene's corner, half a level-0 cell out: the same cells cover the
        // same geometry wherever the scene is placed and however it is scaled, and no face of its
        // bounding box lies on a cell border, where rounding would pick a side.
        m_anchor = scene.bounds().empty() ? vec3(0.0f) : scene.bounds().min - vec3(0.5f * m_cellSize);
        m_table.emplace(m_settings.tableSlots, m_settings.maxProbeLength);
        m_probes.clear();
        m_keys.clear();
        m_lastUsed.clear();
        m_alive.clear();
        m_free.clear();
        m_hasCamera = false;
        m_cellOccupied = m_tableFull = m_invalidQueries = m_staleEvictions = 0;
        if (scene.bounds().empty()) notes.skip("probes", "the scene has no geometry: nothing to hash");
    }

    void beginFrame(const CameraPose& pose, uint32_t frame) override {
        m_camera = pose.eye;
        m_hasCamera = true;
        if (frame > m_settings.staleFrames) evictStale(frame);
    }

    ProbeInsert insert(const ProbeQuery& query, uint32_t frame) override {
        const std::optional<HashCellKey> key = isSurfaceQuery(query) ? keyAt(query, levelOf(query.position), query.position) : std::nullopt;
        if (!key) {
            ++m_invalidQueries;
            return {ProbeInsert::Status::Refused};
        }
        const uint64_t hash = hashOf(*key);
        uint32_t existing;
        if (find(*key, hash, existing)) {
            ++m_cellOccupied;
            return {ProbeInsert::Status::Refused};
        }
        const bool reuse = !m_free.empty();
        const uint32_t id = reuse ? m_free.back() : uint32_t(m_probes.size());
        if (!m_table->insert(hash, id)) {
            ++m_tableFull;
            return {ProbeInsert::Status::Refused};
        }
        if (reuse) {
            m_free.pop_back();
            m_probes[id] = {query.position, query.normal};
            m_keys[id] = *key;
            m_lastUsed[id] = frame;
            m_alive[id] = 1;
        } else {
            m_probes.push_back({query.position, query.normal});
            m_keys.push_back(*key);
            m_lastUsed.push_back(frame);
            m_alive.push_back(1);
        }
        return {reuse ? ProbeInsert::Status::Evicted : ProbeInsert::Status::Inserted, id};
    }

    bool receiverIsNearest() const override { return false; }
    bool receiverOf(const ProbeQuery& query, uint32_t& id) const override {
        if (!isSurfaceQuery(query)) return false;
        const std::optional<HashCellKey> key = keyAt(query, levelOf(query.position), query.position);
        return key && find(*key, hashOf(*key), id);
    }

    void lookup(const ProbeQuery& query, int count, ProbeLookup& out) const override {
        out.count = 0;
        out.covered = false;
        out.distance = kInfinity;
        out.receiver = kNoReceiver;  // receiverOf() is the own cell's entry, looked up here
        if (!isSurfaceQuery(query)) return;
        const int level = levelOf(query.position);
        const std::optional<HashCellKey> ownKey = keyAt(query, level, query.position);
        uint32_t own = 0;
        if (!ownKey || !find(*ownKey, hashOf(*ownKey), own)) return;
        out.covered = true;
        out.receiver = own;
        uint32_t served = own;
        if (m_settings.jitter) {
            const Frame tangent(query.normal);
            const float edge = edgeAt(level);
            const uint64_t h = mix64(query.jitter);
            const float du = float(h & 0xffffffu) * 0x1p-24f - 0.5f, dv = float((h >> 24) & 0xffffffu) * 0x1p-24f - 0.5f;
            const vec3 jittered = query.position + edge * (du * tangent.s + dv * tangent.t);
            uint32_t id;
            const std::optional<HashCellKey> key = keyAt(query, level, jittered);
            // Often the jittered point stays in the point's own cell, whose entry is known.
            if (key && *key != *ownKey && find(*key, hashOf(*key), id)) served = id;
        }
        out.count = 1;
        out.probes[0] = {served, 1.0f};
        out.distance = glm::length(m_probes[served].position - query.position);
    }
    int servedAtMost(int count) const override { return 1; }
    bool readsJitter() const override { return m_settings.jitter; }

    int nearest(const ProbeQuery& query, int count, ProbeNeighbour* out) const override {
        if (count <= 0 || !isSurfaceQuery(query)) return 0;
        const std::optional<HashCellKey> centre = keyAt(query, levelOf(query.position), query.position);
        if (!centre) return 0;
        const float edge = edgeAt(centre->level), radius = kSearchRings * edge;
        int found = 0;
        // The 27 cells around the query settle it when they hold `count` probes within one edge;
        // otherwise the rest of the 5³ block.
        for (int rings = 1; rings <= kSearchRings; ++rings) {
            if (rings > 1 && found == count && out[count - 1].distance <= edge) break;
            for (int64_t dz = -rings; dz <= rings; ++dz)
                for (int64_t dy = -rings; dy <= rings; ++dy)
                    for (int64_t dx = -rings; dx <= rings; ++dx) {
                        if (rings > 1 && std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) < rings) continue;  // visited with fewer rings
                        const HashCellKey key{centre->x + dx, centre->y + dy, centre->z + dz, centre->level, centre->facing};
                        uint32_t id;
                        if (!find(key, hashOf(key), id)) continue;
                        const float distance = glm::length(m_probes[id].position - query.position);
                        if (distance <= radius) found = insertNearest(out, found, count, {id, distance});
                    }
        }
        return found;
    }

    void touch(uint32_t id, uint32_t frame) override {
        if (id < m_lastUsed.size()) m_lastUsed[id] = frame;
    }

    std::span<const Probe> probes() const override { return m_probes; }

    float coverageRadius(const ProbeQuery& query) const override {
        return isFinite(query.position) ? edgeAt(levelOf(query.position)) : m_cellSize;
    }
    float searchRadius(const ProbeQuery& query) const override { return kSearchRings * coverageRadius(query); }

    Json stats() const override {
        const std::size_t slots = m_table ? m_table->slots() : 0;
        const std::size_t bytes = slots * FingerprintTable::kBytesPerSlot + m_probes.capacity() * sizeof(Probe) +
                                  m_keys.capacity() * sizeof(HashCellKey) + m_lastUsed.capacity() * sizeof(uint32_t) +
                                  m_alive.capacity() * sizeof(uint8_t) + m_free.capacity() * sizeof(uint32_t);
        const uint64_t live = m_table ? m_table->used() : 0;
        return {
            {"probes", live},
            {"cell_size", m_cellSize},
            {"table_slots", slots},
            {"table_load", slots > 0 ? double(live) / double(slots) : 0.0},
            {"store", "hash_grid"},
            {"store_bytes", bytes},
            {"store_bytes_per_probe", live > 0 ? double(bytes) / double(live) : 0.0},
            {"refused", m_cellOccupied + m_tableFull + m_invalidQueries},
            {"cell_occupied", m_cellOccupied},
            {"table_full", m_tableFull},
            {"invalid_queries", m_invalidQueries},
            {"collisions", m_table ? m_table->collisions() : 0},
            {"fingerprint_collisions", m_table ? m_table->fingerprintCollisions() : 0},
            {"stale_evictions", m_staleEvictions},
        };
    }

private:
    static bool isSurfaceQuery(const ProbeQuery& query) { return query.mesh >= 0 && isFinite(query.position) && isFinite(query.normal); }

    // floor(log2(d)) = floor(floor(log2(d²)) / 2), and ilogb gives floor(log2) exactly: no square
    // root, no logarithm (this runs for every pixel and every path vertex).
    int levelOf(const vec3& p) const {
        if (!m_hasCamera) return 0;
        const glm::dvec3 offset = glm::dvec3(p) - glm::dvec3(m_camera);
        const double d2 = glm::dot(offset, offset) * m_inverseLodDistance2;
        if (!(d2 >= 1.0)) return 0;
        return std::min(kMaxLevel, 1 + std::ilogb(d2) / 2);
    }

    float edgeAt(int level) const { return m_edges[level]; }

    // The key of the cell holding `p` at `level` (that of the query's point), facing the query's
    // normal; none when the store has no cells or `p` lies too far out for 62-bit cell
    // coordinates. Dividing by the level-0 edge and then scaling by 2^-level rounds exactly as
    // dividing by the level's edge would.
    std::optional<HashCellKey> keyAt(const ProbeQuery& query, int level, const vec3& p) const {
        if (!(m_cellSize > 0.0f)) return std::nullopt;
        const double scale = std::ldexp(1.0, -level);
        double c[3];
        for (int a = 0; a < 3; ++a) {
            c[a] = std::floor((double(p[a]) - double(m_anchor[a])) / double(m_cellSize) * scale);
            if (!(std::fabs(c[a]) < 0x1p62)) return std::nullopt;
        }
        return HashCellKey{int64_t(c[0]), int64_t(c[1]), int64_t(c[2]), uint8_t(level), uint8_t(1 + std::max(dominantDirection(query.normal), 0))};
    }

    bool find(const HashCellKey& key, uint64_t hash, uint32_t& id) const {
        return m_table && m_table->find(hash, [&](uint32_t candidate) { return m_keys[candidate] == key; }, id);
    }

    void evictStale(uint32_t frame) {
        for (uint32_t id = 0; id < m_probes.size(); ++id) {
            if (!m_alive[id] || frame - m_lastUsed[id] <= m_settings.staleFrames) continue;
            m_table->erase(hashOf(m_keys[id]), id, [this](uint32_t other) { return m_table->homeOf(hashOf(m_keys[other])); });
            m_alive[id] = 0;
            m_free.push_back(id);
            ++m_staleEvictions;
        }
    }

    HashGridSettings m_settings;
    float m_cellSize = 0.0f;  // level 0, resolved in prepare(), scene units
    std::array<float, kMaxLevel + 1> m_edges{};  // by level: the cell edge, m_cellSize × 2^level
    double m_inverseLodDistance2 = 0.0;           // 1 / (lod_distance level-0 edges)²
    vec3 m_anchor{0.0f};      // the corner of cell (0, 0, 0) at every level
    std::optional<FingerprintTable> m_table;
    std::vector<Probe> m_probes;        // by id
    std::vector<HashCellKey> m_keys;    // by id
    std::vector<uint32_t> m_lastUsed;   // by id: the frame of its last update (or its insert)
    std::vector<uint8_t> m_alive;       // by id: 0 once evicted, until an insert reuses the id
    std::vector<uint32_t> m_free;       // evicted ids, reused last-in first-out
    vec3 m_camera{0.0f};
    bool m_hasCamera = false;
    uint64_t m_cellOccupied = 0, m_tableFull = 0, m_invalidQueries = 0, m_staleEvictions = 0;
};

}  // namespace

std::unique_ptr<ProbeStore> createHashGridStore(Params& params) {
    HashGridSettings s;
    s.cellSize = ProbeSpacing(params, "cell_size");
    s.lodDistance = params.getFloat("lod_distance");
    s.tableSlots = uint32_t(params.getInt("table_slots"));
    s.maxProbeLength = uint32_t(params.getInt("max_probe_length"));
    if (s.maxProbeLength > s.tableSlots)
        params.fail("max_probe_length", "expected at most table_slots (" + std::to_string(s.tableSlots) + "), got " + std::to_string(s.maxProbeLength));
    s.staleFrames = uint32_t(params.getInt("stale_frames"));
    s.jitter = params.getBool("jitter");
    return std::make_unique<HashGridStore>(std::move(s));
}

}  // namespace gibench
