// MAMBA's probe store: one probe per fine cell of a sparse uniform grid, the grid stored as a
// two-level hash table (sparse_hash_grid.h). The original constants are the defaults, cell sizes
// can follow the scene's extent, and a full table degrades visibly (docs/mamba.md items 4, 6, 7).
//
// A pixel is covered within one fine cell of a probe (the original's rule); nearest() looks
// kSearchRings fine cells far, through the 27 cells around the query first.

#include "methods/probe_cache/stores/mamba/mamba_store.h"

#include "core/util/error.h"
#include "core/util/lane_select.h"
#include "core/util/simd_clones.h"
#include "core/util/system_memory.h"
#include "core/util/text_format.h"
#include "methods/probe_cache/probe_spacing.h"
#include "methods/probe_cache/stores/mamba/sparse_hash_grid.h"

#include <algorithm>
#include <array>
#include <bit>
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
            {"fine_cells_per_coarse_edge", ParamType::Int, 25, "fine cells per edge of a coarse cell (one second-level table)", 1, SparseHashGrid::kMaxFineCellsPerCoarseEdge},
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
        m_grid = std::make_unique<SparseHashGrid>(m_config, [this](uint32_t id) { return m_lastUsed[id]; });
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

        const InsertOutcome outcome = m_grid->insert(key, id);
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
            m_grid->insert(key, id);  // into the slot the erase just freed
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
        // The probes of the block's occupied cells are listed, then offered (offerWithin): testing
        // each cell against the nearest found so far before looking it up cost a mispredicted
        // branch per cell, more than the lookup it saved (single nearest-2 queries 15 % faster).
        // The 27 cells around the query come first: mostly they hold its count nearest, and the
        // outer ring is walked only on the sides where it lies within reach (outerRingWithin).
        BlockProbes block;
        block.size = 0;
        int found = 0, offered = 0;
        m_grid->forEachInBlockInnerFirst(
            centre, kSearchRings, [&](const CellKey&, uint32_t id) { listProbe(block, id); },
            [&] {
                readPositions(block, offered);
                found = offerWithin(block.probes, block.size, q, radius, count, found, out);
                offered = block.size;
                return outerRingWithin(q.position, centre, found == count ? out[count - 1].distance : radius);
            });
        readPositions(block, offered);
        return offerWithin(block.probes + offered, block.size - offered, q, radius, count, found, out);
    }

    // The queries of a tile of pixels lie on few surfaces and their blocks overlap. Per facing tag,
    // the probes of the box of cells that the tile's blocks span are listed once, by id
    // (gatherRegion), and offered to the queries kSweepQueries at a time, each probe to all of them
    // at once (ChunkSweep): the queries' nearest lists are columns, so a probe's distances and its
    // insertion run without a branch, across queries. Where that box is too big (a depth edge, a
    // grazing view), the block of each distinct cell is listed from the grid once (BlockCache) and
    // serves the queries in that cell. Either way a query is offered the probes of exactly the
    // cells nearest() visits, and ties rank by id: the same neighbours as nearest().
    void nearestBatch(const ProbeQuery* queries, int n, int count, ProbeNeighbour* out, int* found) const override {
        if (n == 1) {  // a lone query prunes as it goes
            found[0] = nearest(queries[0], count, out);
            return;
        }
        std::fill_n(found, n, 0);
        if (count <= 0 || !m_grid) return;
        static thread_local BatchScratch scratch;
        scratch.keys.resize(std::size_t(n));
        unsigned tags = 0;
        for (int i = 0; i < n; ++i) {
            scratch.keys[i] = keyOf(queries[i]);
            if (scratch.keys[i]) tags |= 1u << scratch.keys[i]->facing;
        }
        for (; tags; tags &= tags - 1) {
            const uint8_t facing = uint8_t(std::countr_zero(tags));
            scratch.members.clear();
            for (int i = 0; i < n; ++i)
                if (scratch.keys[i] && scratch.keys[i]->facing == facing) scratch.members.push_back(i);
            if (gatherRegion(scratch.keys.data(), scratch.members, facing, scratch.region)) {
                for (std::size_t first = 0; first < scratch.members.size(); first += kSweepQueries)
                    sweepChunk(scratch.region, queries, scratch.keys.data(), scratch.members.data() + first,
                               int(std::min<std::size_t>(kSweepQueries, scratch.members.size() - first)), count, out, found, scratch.sweep);
            } else {
                scratch.blocks.clear();
                for (const int i : scratch.members) {
                    const BlockProbes& block = scratch.blocks.of(*scratch.keys[i], [&](BlockProbes& b) { blockInGrid(b); });
                    found[i] = offerWithin(block.probes, block.size, queries[i], searchRadius(queries[i]), count, 0, out + std::size_t(i) * count);
                }
            }
        }
    }

    void lookupBatch(const ProbeQuery* queries, int n, int count, ProbeLookup* out) const override {
        lookupNearestBatchOf(*this, queries, n, count, out);
    }

    // The grid's LRU eviction reads the same frames (its LastUsedOf).
    void touch(uint32_t id, uint32_t frame) override { m_lastUsed[id] = frame; }

    std::span<const Probe> probes() const override { return m_probes; }
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

    static constexpr double kOuterRingMargin = 1.0 - 1e-4;
    static constexpr int kBlockWidth = 2 * kSearchRings + 1;
    static constexpr int kBlockCells = kBlockWidth * kBlockWidth * kBlockWidth;
    struct CellProbe {
        vec3 position;
        uint32_t id;
    };

    // The cells of the outer ring of `centre`'s block that can hold a probe within `reach` of
    // `position` (a point of that cell): on each axis and side, the ring's layer unless all of it
    // lies farther than the inner 3³ block's face, which it lies beyond. Ties rank by id, so a
    // layer is skipped only when strictly farther, with a margin for the rounding of the probes'
    // float distances (the faces are placed in double, as the grid places cells, so that they stay
    // exact far from the origin). Empty when no layer is within reach.
    SparseHashGrid::BlockBox outerRingWithin(const vec3& position, const CellKey& centre, float reach) const {
        const double size = m_grid->config().fineCellSize;
        const int64_t c[3] = {centre.x, centre.y, centre.z};
        SparseHashGrid::BlockBox box;
        bool any = false;
        for (int a = 0; a < 3; ++a) {
            const double below = double(position[a]) - (double(c[a]) - 1.0) * size, above = (double(c[a]) + 2.0) * size - double(position[a]);
            box.from[a] = double(reach) < below * kOuterRingMargin ? -1 : -kSearchRings;
            box.to[a] = double(reach) < above * kOuterRingMargin ? 1 : kSearchRings;
            any = any || box.from[a] < -1 || box.to[a] > 1;
        }
        return any ? box : SparseHashGrid::BlockBox{};
    }

    // The probes of one facing in a box of cells, by id, each with its cell relative to the box's
    // low corner. Up to kMaxRegionCells cells: a planar 16×16-pixel tile spans about 14×14×5 cells
    // with its blocks at the default spacing, and holds about 40 probes on the Cornell box.
    static constexpr uint64_t kMaxRegionCells = 1 << 14;
    struct RegionProbe {
        vec3 position;
        uint32_t id;
        int32_t cell[3];
    };
    struct TileRegion {
        std::array<int64_t, 3> lo;
        std::vector<RegionProbe> probes;
    };

    // Fills `region` with the probes of the box spanned by the blocks of the `members`' cells (all
    // of tag `facing`); false, leaving it unusable, when that box is too big for a region.
    bool gatherRegion(const std::optional<CellKey>* keys, const std::vector<int>& members, uint8_t facing, TileRegion& region) const {
        constexpr int64_t kRings = kSearchRings;
        std::array<int64_t, 3> lo = {INT64_MAX, INT64_MAX, INT64_MAX}, hi = {INT64_MIN, INT64_MIN, INT64_MIN};
        for (const int i : members) {
            const CellKey& k = *keys[i];
            const int64_t c[3] = {k.x, k.y, k.z};
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], c[a]);
                hi[a] = std::max(hi[a], c[a]);
            }
        }
        uint64_t cells = 1;
        for (int a = 0; a < 3; ++a) {
            // Blocks reaching past the ends of the int64 range stay with BlockCache, which skips
            // the cells that do not exist.
            if (lo[a] < INT64_MIN + kRings || hi[a] > INT64_MAX - kRings) return false;
            lo[a] -= kRings;
            hi[a] += kRings;
            const uint64_t size = uint64_t(hi[a]) - uint64_t(lo[a]) + 1;  // exact: hi >= lo
            if (size > kMaxRegionCells) return false;
            cells *= size;
        }
        if (cells > kMaxRegionCells) return false;
        region.lo = lo;
        region.probes.clear();
        // Positions are read after the walk, in id order (listProbe()).
        m_grid->forEachInBox(lo, hi, facing, [&](const CellKey& k, uint32_t id) {
            __builtin_prefetch(&m_probes[id]);
            region.probes.push_back({vec3(0.0f), id,
                                     {int32_t(uint64_t(k.x) - uint64_t(lo[0])), int32_t(uint64_t(k.y) - uint64_t(lo[1])),
                                      int32_t(uint64_t(k.z) - uint64_t(lo[2]))}});
        });
        std::sort(region.probes.begin(), region.probes.end(), [](const RegionProbe& a, const RegionProbe& b) { return a.id < b.id; });
        for (RegionProbe& p : region.probes) p.position = m_probes[p.id].position;
        return true;
    }

    // Up to kSweepQueries queries of one facing as columns, with their `count` nearest so far
    // (kInfinity where none), sorted by distance. Offered probes in increasing id, a probe goes
    // before an equally distant one only if it came first: the order (distance, id) of nearest().
    static constexpr int kSweepQueries = 32;
    struct ChunkSweep {
        float x[kSweepQueries], y[kSweepQueries], z[kSweepQueries];
        int32_t cell[3][kSweepQueries];  // relative to the region's low corner; far outside it for unused columns
        float distance[kSweepQueries];   // of the probe on offer, kInfinity where out of the query's block or reach
        float nearest[kMaxServedProbes][kSweepQueries];
        uint32_t ids[kMaxServedProbes][kSweepQueries];
        float aboveFirst[kSweepQueries];  // −kInfinity, which no distance beats: the level above the first
    };

    // nearest() of the `m` queries `members` (all in `region`'s box), into `out` and `found`.
    void sweepChunk(const TileRegion& region, const ProbeQuery* queries, const std::optional<CellKey>* keys, const int* members, int m,
                    int count, ProbeNeighbour* out, int* found, ChunkSweep& sweep) const {
        constexpr int32_t kRings = kSearchRings, kFar = 1 << 30;
        int32_t from[3] = {kFar, kFar, kFar}, to[3] = {-kFar, -kFar, -kFar};  // the cells whose probes some query's block holds
        for (int k = 0; k < kSweepQueries; ++k) {
            if (k >= m) {
                sweep.x[k] = sweep.y[k] = sweep.z[k] = 0.0f;
                for (int a = 0; a < 3; ++a) sweep.cell[a][k] = kFar;
                continue;
            }
            const ProbeQuery& q = queries[members[k]];
            sweep.x[k] = q.position.x;
            sweep.y[k] = q.position.y;
            sweep.z[k] = q.position.z;
            const CellKey& key = *keys[members[k]];
            const int64_t c[3] = {key.x, key.y, key.z};
            for (int a = 0; a < 3; ++a) {
                sweep.cell[a][k] = int32_t(uint64_t(c[a]) - uint64_t(region.lo[a]));
                from[a] = std::min(from[a], sweep.cell[a][k] - kRings);
                to[a] = std::max(to[a], sweep.cell[a][k] + kRings);
            }
        }
        for (int j = 0; j < count; ++j) std::fill_n(sweep.nearest[j], kSweepQueries, kInfinity);
        std::fill_n(sweep.aboveFirst, kSweepQueries, -kInfinity);
        const float radius = searchRadius(queries[members[0]]);
        for (const RegionProbe& p : region.probes) {
            if (p.cell[0] < from[0] || p.cell[0] > to[0] || p.cell[1] < from[1] || p.cell[1] > to[1] || p.cell[2] < from[2] || p.cell[2] > to[2])
                continue;
            offerToChunk(p, radius, count, sweep);
        }
        for (int k = 0; k < m; ++k) {
            ProbeNeighbour* list = out + std::size_t(members[k]) * count;
            int size = 0;
            for (; size < count && sweep.nearest[size][k] < kInfinity; ++size) list[size] = {sweep.ids[size][k], sweep.nearest[size][k]};
            found[members[k]] = size;
        }
    }

    // Offers probe `p` to every column of `sweep`: an insertion into each sorted list, level by
    // level from the last, each level a select across the columns.
    GIBENCH_SIMD_CLONES static void offerToChunk(const RegionProbe& p, float radius, int count, ChunkSweep& sweep) {
        constexpr uint32_t kBlockSpan = 2 * kSearchRings;
        for (int k = 0; k < kSweepQueries; ++k) {
            // As offer() computes it, glm::length(position - q.position), for the same rounding.
            const float dx = p.position.x - sweep.x[k], dy = p.position.y - sweep.y[k], dz = p.position.z - sweep.z[k];
            const float d = std::sqrt(dx * dx + dy * dy + dz * dz);
            // `&`, not `&&`: no branch, so that the loop runs across the columns in SIMD lanes.
            const bool within = (uint32_t(p.cell[0] - sweep.cell[0][k] + kSearchRings) <= kBlockSpan) &
                                (uint32_t(p.cell[1] - sweep.cell[1][k] + kSearchRings) <= kBlockSpan) &
                                (uint32_t(p.cell[2] - sweep.cell[2][k] + kSearchRings) <= kBlockSpan) & (d <= radius);
            sweep.distance[k] = laneSelect(laneMask(within), d, kInfinity);
        }
        for (int j = count - 1; j >= 0; --j) {
            float* nearest = sweep.nearest[j];
            uint32_t* ids = sweep.ids[j];
            const float* above = j > 0 ? sweep.nearest[j - 1] : sweep.aboveFirst;
            const uint32_t* aboveIds = j > 0 ? sweep.ids[j - 1] : sweep.ids[j];
            for (int k = 0; k < kSweepQueries; ++k) {
                const float d = sweep.distance[k];
                const uint32_t beatsAbove = laneMask(d < above[k]), beats = laneMask(d < nearest[k]);
                nearest[k] = laneSelect(beats, laneSelect(beatsAbove, above[k], d), nearest[k]);
                ids[k] = laneSelect(beats, laneSelect(beatsAbove, aboveIds[k], p.id), ids[k]);
            }
        }
    }

    // The probes of the block of cells within kSearchRings of a cell with its facing: all that a
    // query in that cell can be offered (one probe per cell).
    struct BlockProbes {
        CellKey centre;
        int size;
        CellProbe probes[kBlockCells];
    };
    // The blocks of the last kCachedBlocks distinct cells asked about, direct-mapped: a tile of
    // kLookupTile² pixels spans up to about ten cells each way, so a row of them stays cached
    // until the tile's next row of pixels meets them again.
    static constexpr int kCachedBlocks = 32;
    struct BlockCache {
        BlockProbes blocks[kCachedBlocks];
        void clear() {
            for (BlockProbes& block : blocks) block.size = -1;  // empty
        }
        // The block of `cell`, filled by fill(block) unless cached.
        template <class Fill>
        const BlockProbes& of(const CellKey& cell, Fill&& fill) {
            BlockProbes& block = blocks[hashCellKey(cell) % kCachedBlocks];
            if (block.size < 0 || !(block.centre == cell)) {
                block.centre = cell;
                block.size = 0;
                fill(block);
            }
            return block;
        }
    };

    // Offers the `size` probes to the sorted list of the `count` nearest within `radius`, which
    // holds `found`; returns its new size. Those within reach (or the list's last, when it is
    // full) are listed first without a branch per probe: about half of a block's are, so a
    // branch on each would be mispredicted as often as not.
    static int offerWithin(const CellProbe* probes, int size, const ProbeQuery& q, float radius, int count, int found, ProbeNeighbour* out) {
        const float reach = found == count ? std::min(radius, out[count - 1].distance) : radius;
        const float reach2 = reach * reach * kReachSlack;
        uint8_t within[kBlockCells];
        int n = 0;
        for (int k = 0; k < size; ++k) {
            const vec3 d = probes[k].position - q.position;
            within[n] = uint8_t(k);
            n += glm::dot(d, d) <= reach2;
        }
        for (int j = 0; j < n; ++j) found = offer(probes[within[j]].id, probes[within[j]].position, q, radius, count, found, out);
        return found;
    }

    // The probes of the block around `block.centre`, from the grid.
    void blockInGrid(BlockProbes& block) const {
        m_grid->forEachInBlock(block.centre, kSearchRings, [&](const CellKey&, uint32_t id) { listProbe(block, id); });
        readPositions(block, 0);
    }

    // A block's probes are listed by id as the grid finds them, each prefetched, and their
    // positions read once the walk is done (readPositions): the probes of neighbouring cells lie
    // anywhere in memory, and read as each cell was found, a position was one of a lone query's
    // two costliest loads in a frame (with its cell's bucket), its misses one after another.
    void listProbe(BlockProbes& block, uint32_t id) const {
        __builtin_prefetch(&m_probes[id]);
        block.probes[block.size++].id = id;
    }
    void readPositions(BlockProbes& block, int from) const {
        for (int k = from; k < block.size; ++k) block.probes[k].position = m_probes[block.probes[k].id].position;
    }


    // What nearestBatch() keeps between calls on a thread (64 KiB of blocks, no allocation per tile).
    struct BatchScratch {
        std::vector<std::optional<CellKey>> keys;
        std::vector<int> members;
        TileRegion region;
        ChunkSweep sweep;
        BlockCache blocks;
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
