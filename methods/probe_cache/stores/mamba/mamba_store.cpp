// MAMBA's probe store: one probe per fine cell of a sparse uniform grid, the grid stored as a
// two-level hash table (sparse_hash_grid.h). The original constants are the defaults, cell sizes
// can follow the scene's extent, and a full table degrades visibly (docs/mamba.md items 4, 6, 7).
//
// A pixel is covered within one fine cell of a probe (the original's rule); nearest() looks
// kSearchRings fine cells far, through the 27 cells around the query first.

#include "methods/probe_cache/stores/mamba/mamba_store.h"

#include "core/util/error.h"
#include "core/util/system_memory.h"
#include "core/util/text_format.h"
#include "methods/probe_cache/probe_spacing.h"
#include "methods/probe_cache/stores/mamba/sparse_hash_grid.h"

#include <algorithm>
#include <cmath>

namespace gibench {

namespace {

const EnumChoices<FullPolicy>& fullPolicyChoices() {
    static const EnumChoices<FullPolicy> choices = {{"evict", FullPolicy::EvictLeastRecentlyUsed}, {"refuse", FullPolicy::Refuse}};
    return choices;
}

}  // namespace

const ParamTable& mambaStoreParams() {
    static const ParamTable table = joinTables(
        spacingParams("fine_cell_size", "fine cell edge"),
        {
            {"fine_cells_per_coarse_edge", ParamType::Int, 25, "fine cells per edge of a coarse cell (one second-level table)", 1, 1 << 18},
            {"max_coarse_tables", ParamType::Int, 1023, "second-level tables at most", 1, 1 << 20},
            {"fine_slots_per_table", ParamType::Int, 32767, "slots per second-level table", 1, 1 << 22},
            {"max_probe_length", ParamType::Int, 32, "slots examined per insert before that spot counts as full", 1, 1 << 26},
            {"full_policy", ParamType::String, "evict", "when full: evict the least recently updated probe, or refuse",
             -INFINITY, INFINITY, choiceNames(fullPolicyChoices())},
            {"max_probes", ParamType::Int, 1 << 20, "probes at most", 1, 1 << 26},
            {"facing", ParamType::Bool, true, "put the normal's dominant axis and sign in the key (a probe per side of thin walls)"},
        },
        "mamba");
    return table;
}

namespace {

static_assert(kSearchRings <= SparseHashGrid::kMaxBlockRings, "nearest() walks the block of kSearchRings through the grid");

// 1..6 for the direction the normal faces most (0 is the key of the original's shared probes).
uint8_t facingTag(const vec3& n) { return uint8_t(1 + std::max(dominantDirection(n), 0)); }

class MambaStore final : public ProbeStore {
public:

    // Held per probe: its Probe, last-used frame and a possible free-list entry.
    static constexpr std::size_t kBytesPerProbe = sizeof(Probe) + 2 * sizeof(uint32_t);

    MambaStore(ProbeSpacing spacing, SparseHashGridConfig config, uint32_t maxProbes, bool facing)
        : m_spacing(std::move(spacing)), m_config(config), m_maxProbes(maxProbes), m_facing(facing) {}

    void prepare(const Scene& scene, RunNotes& notes) override {
        m_cellSize = m_spacing.resolve(scene.bounds());
        m_grid.reset();
        if (scene.bounds().empty()) {
            // No geometry: nothing to place a probe on, so no grid; every insert is refused.
            notes.skip("probes", "the scene has no geometry: no probes");
            return;
        }
        m_config.fineCellSize = m_cellSize;
        m_grid = std::make_unique<SparseHashGrid>(m_config);
    }

    ProbeInsert insert(const ProbeQuery& q, uint32_t frame) override {
        const std::optional<CellKey> cell = keyOf(q);
        if (!cell) return refuse(m_refusedInvalid);
        const CellKey& key = *cell;
        if (m_grid->find(key)) return refuse(m_cellOccupied);  // one probe per fine cell

        // An id for the new probe: a freed one, a new one, or (pool full) the least recently updated.
        uint32_t id;
        bool reused = true;
        if (!m_freed.empty()) {
            id = m_freed.back();
            m_freed.pop_back();
        } else if (m_probes.size() < m_maxProbes) {
            id = uint32_t(m_probes.size());
            reused = false;
        } else if (m_config.policy == FullPolicy::Refuse || !evictOldest(frame, id)) {
            return refuse(m_poolFull);
        }

        const InsertOutcome outcome = m_grid->insert(key, id, frame);
        if (outcome.status == InsertOutcome::Status::Refused) {
            if (reused) m_freed.push_back(id);
            return refuse(m_tableFull);
        }
        if (outcome.status == InsertOutcome::Status::Evicted) {
            // The table gave the cell of another probe to the new key: that probe is gone and the
            // new one takes over its id, so the pipeline resets one cache state.
            if (reused) m_freed.push_back(id);
            id = outcome.evictedValue;
            m_grid->erase(key);
            m_grid->insert(key, id, frame);  // into the slot the erase just freed
            ++m_evictions;
            reused = true;
        }
        place(id, q, frame);
        return {reused ? ProbeInsert::Status::Evicted : ProbeInsert::Status::Inserted, id};
    }

    int nearest(const ProbeQuery& q, int count, ProbeNeighbour* out) const override {
        const std::optional<CellKey> cell = keyOf(q);
        if (!cell || count <= 0) return 0;
        const CellKey& centre = *cell;
        const float radius = searchRadius(q);
        // One pass over the block of cells within kSearchRings, skipping the cells that cannot
        // hold a probe nearer than the radius or than the count-th nearest found so far, so that
        // nothing within the radius is missed (item 4).
        int found = 0;
        const vec3 corner = vec3(float(centre.x), float(centre.y), float(centre.z)) * m_cellSize;
        const auto mayHoldANearer = [&](int64_t dx, int64_t dy, int64_t dz) {
            const vec3 lo = corner + vec3(float(dx), float(dy), float(dz)) * m_cellSize;
            const float reach = found == count ? out[count - 1].distance : radius;
            const vec3 gap = glm::max(glm::max(lo - q.position, q.position - (lo + vec3(m_cellSize))), vec3(0.0f));
            return glm::dot(gap, gap) <= reach * reach;
        };
        m_grid->forEachInBlock(centre, kSearchRings, mayHoldANearer,
                               [&](const CellKey&, uint32_t id) { found = offer(id, q, radius, count, found, out); });
        return found;
    }

    // The queries of a tile of pixels fall in few cells, each asked about again and again: the
    // probes of the block around a cell are gathered once (kept in a direct-mapped cache of
    // kCachedBlocks blocks), and each query of the cell ranks them. nearest() visits the same cells and prunes
    // only cells that hold no probe within reach, and ties rank by id, so both give the same
    // neighbours.
    void nearestBatch(const ProbeQuery* queries, int n, int count, ProbeNeighbour* out, int* found) const override {
        BlockProbes blocks[kCachedBlocks];
        for (BlockProbes& block : blocks) block.size = -1;  // empty
        for (int i = 0; i < n; ++i) {
            ProbeNeighbour* nearestOfQuery = out + std::size_t(i) * count;
            const ProbeQuery& q = queries[i];
            const std::optional<CellKey> cell = keyOf(q);
            found[i] = 0;
            if (!cell || count <= 0) continue;
            BlockProbes* block = &blocks[hashCellKey(*cell) % kCachedBlocks];  // direct-mapped
            if (block->size < 0 || !(block->centre == *cell)) {
                block->centre = *cell;
                block->size = 0;
                m_grid->forEachInBlock(*cell, kSearchRings, [](int64_t, int64_t, int64_t) { return true; },
                                       [&](const CellKey&, uint32_t id) { block->probes[block->size++] = {m_probes[id].position, id}; });
            }
            const float radius = searchRadius(q);
            // Squared distances first: most probes of the block lie beyond the count-th nearest.
            // The slack keeps every probe whose rounded length could still make the list.
            float reach2 = radius * radius * kReachSlack;
            for (int k = 0; k < block->size; ++k) {
                const vec3 d = block->probes[k].position - q.position;
                if (glm::dot(d, d) > reach2) continue;
                found[i] = offer(block->probes[k].id, block->probes[k].position, q, radius, count, found[i], nearestOfQuery);
                if (found[i] == count) reach2 = nearestOfQuery[count - 1].distance * nearestOfQuery[count - 1].distance * kReachSlack;
            }
        }
    }

    void lookupBatch(const ProbeQuery* queries, int n, int count, ProbeLookup* out) const override { lookupNearestBatch(queries, n, count, out); }

    void touch(uint32_t id, uint32_t frame) override {
        m_lastUsed[id] = frame;
        m_grid->touch(keyOfProbe(id), frame);
    }

    const Probe& probe(uint32_t id) const override { return m_probes[id]; }
    uint32_t idCapacity() const override { return uint32_t(m_probes.size()); }
    float coverageRadius(const ProbeQuery&) const override { return m_cellSize; }
    float searchRadius(const ProbeQuery&) const override { return kSearchRings * m_cellSize; }

    Json stats() const override {
        const SparseHashGrid::Stats g = m_grid ? m_grid->stats() : SparseHashGrid::Stats{};
        const std::size_t probeBytes = m_probes.capacity() * sizeof(Probe) +
                                       m_lastUsed.capacity() * sizeof(uint32_t) + m_freed.capacity() * sizeof(uint32_t);
        const std::size_t live = m_probes.size() - m_freed.size();
        return {{"store", "mamba"},
                {"fine_cell_size", m_cellSize},
                {"probes", live},
                {"store_bytes", g.bytes + probeBytes},
                {"store_bytes_per_probe", live > 0 ? double(g.bytes + probeBytes) / double(live) : 0.0},
                {"coarse_tables", g.coarseTables},
                {"table_load", g.loadFactor},
                {"table_refused", m_tableFull},
                {"table_evictions", m_evictions},
                {"pool_full", m_poolFull},
                {"cell_occupied", m_cellOccupied},
                {"refused_invalid", m_refusedInvalid}};
    }

private:
    // The query's cell; none without a grid (an empty scene), for a non-finite query, or for a
    // position too far out for a cell coordinate (a query off the scene's surfaces).
    std::optional<CellKey> keyOf(const ProbeQuery& q) const {
        if (!m_grid || !isFinite(q.normal)) return std::nullopt;
        return m_grid->tryKeyOf(q.position, m_facing ? facingTag(q.normal) : 0);
    }

    // The cell of a placed probe: the key its query had, recomputed rather than stored (32 bytes
    // a probe).
    CellKey keyOfProbe(uint32_t id) const {
        const Probe& p = m_probes[id];
        return *m_grid->tryKeyOf(p.position, m_facing ? facingTag(p.normal) : 0);
    }

    // Adds probe `id` at `position` to the sorted list of the `count` nearest when within
    // `radius`; returns the new size.
    static int offer(uint32_t id, const vec3& position, const ProbeQuery& q, float radius, int count, int found, ProbeNeighbour* out) {
        const float d = glm::length(position - q.position);
        return d <= radius ? insertNearest(out, found, count, {id, d}) : found;
    }
    int offer(uint32_t id, const ProbeQuery& q, float radius, int count, int found, ProbeNeighbour* out) const {
        return offer(id, m_probes[id].position, q, radius, count, found, out);
    }

    // The probes of the block of cells within kSearchRings of `centre` with its facing: all that
    // a query in that cell can be offered (one probe per cell).
    static constexpr float kReachSlack = 1.0f + 1e-5f;
    static constexpr int kBlockCells = (2 * kSearchRings + 1) * (2 * kSearchRings + 1) * (2 * kSearchRings + 1);
    // A tile of kLookupTile² pixels spans up to about ten cells each way (64 KiB of blocks on the
    // stack): enough for a row of them to stay cached until the tile's next row of pixels meets
    // them again.
    static constexpr int kCachedBlocks = 32;
    struct BlockProbes {
        CellKey centre;
        int size;
        struct {
            vec3 position;
            uint32_t id;
        } probes[kBlockCells];
    };

    ProbeInsert refuse(uint64_t& counter) {
        ++counter;
        return {ProbeInsert::Status::Refused, 0};
    }

    void place(uint32_t id, const ProbeQuery& q, uint32_t frame) {
        if (id == m_probes.size()) {
            m_probes.push_back({q.position, q.normal});
            m_lastUsed.push_back(frame);
            return;
        }
        m_probes[id] = {q.position, q.normal};
        m_lastUsed[id] = frame;
    }

    // Second-chance sweep for a probe not updated this frame or the last; removes it from the grid.
    bool evictOldest(uint32_t frame, uint32_t& id) {
        if (!m_freed.empty()) {
            id = m_freed.back();
            m_freed.pop_back();
            return true;
        }
        for (std::size_t step = 0; step < m_probes.size(); ++step) {
            m_hand = (m_hand + 1) % m_probes.size();
            if (m_lastUsed[m_hand] + 1 < frame) {
                id = uint32_t(m_hand);
                m_grid->erase(keyOfProbe(id));
                ++m_evictions;
                return true;
            }
        }
        return false;
    }

    ProbeSpacing m_spacing;
    float m_cellSize = 0.0f;  // resolved in prepare(), scene units
    SparseHashGridConfig m_config;
    uint32_t m_maxProbes;
    bool m_facing;
    std::unique_ptr<SparseHashGrid> m_grid;
    std::vector<Probe> m_probes;
    std::vector<uint32_t> m_lastUsed;
    std::vector<uint32_t> m_freed;  // ids whose cell the table evicted while the pool had room
    std::size_t m_hand = 0;
    uint64_t m_tableFull = 0, m_evictions = 0, m_poolFull = 0, m_cellOccupied = 0, m_refusedInvalid = 0;
};

// The tables and the probe pool may grow to their limits on a large scene: a config whose
// limits need more than half of this machine's memory is refused before anything is allocated.
void rejectWhatCannotFitInMemory(const Params& p, const SparseHashGridConfig& config, uint32_t maxProbes) {
    const double tableBytes = double(config.maxCoarseTables) * config.fineSlotsPerTable * double(SparseHashGrid::kBytesPerFineSlot);
    const double probeBytes = double(maxProbes) * MambaStore::kBytesPerProbe;
    const double available = 0.5 * double(physicalMemoryBytes());
    if (available > 0.0 && tableBytes + probeBytes > available) {
        constexpr double kGiB = double(1 << 30);
        p.fail(tableBytes >= probeBytes ? "fine_slots_per_table" : "max_probes",
               "max_coarse_tables × fine_slots_per_table × " + std::to_string(SparseHashGrid::kBytesPerFineSlot) + " B = " +
                   formatNumber(tableBytes / kGiB) + " GiB of tables and max_probes × " + std::to_string(MambaStore::kBytesPerProbe) +
                   " B = " + formatNumber(probeBytes / kGiB) + " GiB of probes can be needed, more than half of this machine's " +
                   formatNumber(2.0 * available / kGiB) + " GiB; lower them");
    }
}

}  // namespace

std::unique_ptr<ProbeStore> createMambaStore(Params& p) {
    SparseHashGridConfig config;
    ProbeSpacing spacing(p, "fine_cell_size");
    config.fineCellsPerCoarseEdge = int(p.getInt("fine_cells_per_coarse_edge"));
    config.maxCoarseTables = uint32_t(p.getInt("max_coarse_tables"));
    config.fineSlotsPerTable = uint32_t(p.getInt("fine_slots_per_table"));
    config.maxProbeLength = uint32_t(p.getInt("max_probe_length"));
    if (config.maxProbeLength > config.fineSlotsPerTable)
        p.fail("max_probe_length", "expected at most fine_slots_per_table (" + std::to_string(config.fineSlotsPerTable) + "), got " +
                                       std::to_string(config.maxProbeLength));
    config.policy = p.getEnum("full_policy", fullPolicyChoices());
    const uint32_t maxProbes = uint32_t(p.getInt("max_probes"));
    const bool facing = p.getBool("facing");
    rejectWhatCannotFitInMemory(p, config, maxProbes);
    return std::make_unique<MambaStore>(std::move(spacing), config, maxProbes, facing);
}

}  // namespace gibench
