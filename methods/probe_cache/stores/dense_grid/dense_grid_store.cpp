// Probe store "dense_grid" (GIBS-like, MAMBA paper §3.2): surface probes found through a dense
// uniform grid of cells over the scene's bounding box, padded by half a cell on every side. Each
// cell holds up to max_probes_per_cell probe ids. The whole grid is allocated in prepare(), so its
// memory grows with the volume of the scene's bounds, whatever the probes cover: the cost MAMBA's
// sparse hash grid avoids.
//
// Memory (stats "store_bytes"): cells × (4 × max_probes_per_cell + 2) bytes for the grid (a 32-bit id
// per slot and a 16-bit count per cell) plus a bit per cell (which cells hold a probe, in rows
// along x, so that lookups skip the empty cells that make up most of the block around a surface
// point without reading their counts), held from prepare() on, plus 24 bytes per probe (position
// and normal, std::vector capacity). lookup() reads per-group surfel lists (stats
// "surfel_list_bytes"): 4 bytes per group of 4³ cells, and 40 bytes per surfel in each of the
// 1 to 8 lists it is in.
//
// insert() puts the probe into the cell containing the query point, or refuses and counts why:
// the cell is full (cell_full), the point lies outside the grid (outside_grid), or the query names
// no surface point (invalid_queries: mesh < 0, a non-finite position or normal). There is no
// recycling: a full cell stays full, and its refusals show where the capacity ran out.
//
// lookup() is GIBS's: every probe is a surfel of radius surfel_radius cell edges, and every surfel
// whose sphere holds the point and whose normal agrees contributes (they lie in the cells within
// ceil(surfel_radius) of the point's), with a smooth radial weight
// (1 − (d/R)²)² times a normal weight (n_s·n − normal_threshold) / (1 − normal_threshold), both
// falling to 0 at the edge of what they accept so that a surfel fades in and out instead of
// popping; the kMaxServedProbes nearest of them when more cover the point. The point is covered
// when one of them lies within coverageRadius() of it in its tangent plane and along its normal:
// the allocation stage spawns surfels in coverage holes, as GIBS does. Like GIBS, which lists in
// each cell the surfels that overlap it, insert() lists each surfel in the groups of 4³ cells it
// can serve, so that a lookup reads one list instead of walking the cells around the point:
// path vertices read the cache one point at a time, far from each other.
//
// nearest() offers the probes within searchRadius() = kSearchRings cell edges of the query that
// face its way, nearest first. The (2k+1)³ block of cells around the query's cell holds every
// probe within k edges: such a point differs from the query by at most k edges on each axis,
// hence lies at most k cell indices away. The 3-wide block (k = 1) is searched first and settles
// the query when it already holds enough probes within one edge.

#include "methods/probe_cache/stores/dense_grid/dense_grid_store.h"

#include "core/util/error.h"
#include "core/util/lane_select.h"
#include "core/util/simd_clones.h"
#include "core/util/text_format.h"
#include "methods/probe_cache/probe_spacing.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <iomanip>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace gibench {

const ParamTable& denseGridStoreParams() {
    static const ParamTable table = joinTables(
        spacingParams("cell_size", "grid cell edge"),
        {
            {"max_probes_per_cell", ParamType::Int, 4, "probe ids a grid cell holds; inserts into a full cell are refused", 1, 4096},
            {"normal_threshold", ParamType::Float, 0.5,
             "nearest() and lookup() offer only probes whose normal has a dot product with the query's normal above this", -1.0, 1.0},
            {"surfel_radius", ParamType::Float, 2.0,
             "in cell edges: the radius of a surfel; lookup() blends every surfel whose sphere holds the point", 0.5, double(kSearchRings)},
            {"max_cells", ParamType::Int, 1 << 24, "grid cells at most; the grid over the scene's bounds is allocated whole", 1,
             double(1ll << 32)},
        },
        "dense_grid");
    return table;
}

namespace {

struct DenseGridSettings {
    ProbeSpacing cellSize;
    int maxProbesPerCell = 0;
    float normalThreshold = 0.0f;
    float surfelRadius = 0.0f;  // cell edges
    double maxCells = 0.0;
    // "FILE: /pointer/key: " prefixes for the errors only prepare() can find.
    std::string maxProbesPerCellWhere;
    std::string maxCellsWhere;
};

// A query names a surface point: a mesh, a finite position and a finite normal.
bool isSurfaceQuery(const ProbeQuery& query) { return query.mesh >= 0 && isFinite(query.position) && isFinite(query.normal); }

class DenseGridStore final : public ProbeStore {
    // The surfels of the blocks of all cells of one group of kGroupCells³ cells: every surfel a
    // lookup from a point in the group can meet, kept up to date by insert() (so each surfel is
    // listed in the 1 to 8 groups whose cells' blocks hold its cell). A coordinate per array, so
    // that the test of every surfel against a query compiles to vector instructions; each
    // surfel's cell, relative to the block's first, so that a query keeps only those of its own
    // cell's block. The float arrays lie one after another in one allocation, the integer ones in
    // another, so that a lookup reads consecutive lines (an allocation per array cost a cache
    // miss on each).
    struct SurfelBlock {
        enum FloatArray { X, Y, Z, NormalX, NormalY, NormalZ, kFloatArrays };
        enum IntArray { CellX, CellY, CellZ, Id, kIntArrays };  // an id as its int32_t, modulo 2^32
        int64_t lo[3] = {0, 0, 0};  // the block's first cell
        uint32_t size = 0, capacity = 0;
        std::unique_ptr<float[]> floatArrays;  // kFloatArrays arrays of `capacity`
        std::unique_ptr<int32_t[]> intArrays;  // kIntArrays arrays of `capacity`

        const float* floats(FloatArray a) const { return floatArrays.get() + std::size_t(a) * capacity; }
        const int32_t* ints(IntArray a) const { return intArrays.get() + std::size_t(a) * capacity; }
        uint32_t id(uint32_t k) const { return uint32_t(ints(Id)[k]); }
        void add(const vec3& position, const vec3& normal, const int32_t cell[3], uint32_t id) {
            if (size == capacity) grow();
            const float floatValues[kFloatArrays] = {position.x, position.y, position.z, normal.x, normal.y, normal.z};
            const int32_t intValues[kIntArrays] = {cell[0], cell[1], cell[2], int32_t(id)};
            for (int a = 0; a < kFloatArrays; ++a) floatArrays[std::size_t(a) * capacity + size] = floatValues[a];
            for (int a = 0; a < kIntArrays; ++a) intArrays[std::size_t(a) * capacity + size] = intValues[a];
            ++size;
        }
        void grow() {
            const uint32_t grown = std::max(2 * capacity, 4u);
            regrow(floatArrays, kFloatArrays, grown);
            regrow(intArrays, kIntArrays, grown);
            capacity = grown;
        }
        template <class T>
        void regrow(std::unique_ptr<T[]>& arrays, int count, uint32_t grown) const {
            std::unique_ptr<T[]> moved(new T[std::size_t(count) * grown]);
            for (int a = 0; a < count; ++a) std::copy_n(arrays.get() + std::size_t(a) * capacity, size, moved.get() + std::size_t(a) * grown);
            arrays = std::move(moved);
        }
    };
    // Measured on the Cornell box with the groups' lists filled by the lookups themselves:
    // groups of 4³ cells put the raster stage at 5.2 ms, of 2³ at 6.2–6.7, of 8³ at 5.5.
    static constexpr int64_t kGroupCells = 4;

    // lookupBatch()'s queries of one group as lanes, tested against kLaneSurfels surfels at a time:
    // a bit per surfel in each lane's `hits` and `covers`, and each surfel's distance to each
    // lane's point and its weight there. 16 lanes: a group of a tile's queries held 15.9 on average
    // on the Cornell box, so passes of 32 lanes ran half empty (raster stage 5.98 -> 5.61 ms).
    static constexpr int kLaneQueries = 16;
    static constexpr int kLaneSurfels = 32;
    // A surfel serving a lane, with what answer() needs of it.
    struct LaneServed {
        uint32_t id;
        float distance;
        float weight;  // surfelWeight()
        bool covers;   // coversPoint()
    };
    struct LaneTests {
        float x[kLaneQueries], y[kLaneQueries], z[kLaneQueries], nx[kLaneQueries], ny[kLaneQueries], nz[kLaneQueries];
        int32_t cell[3][kLaneQueries];  // relative to the block's first cell
        uint32_t hits[kLaneQueries], covers[kLaneQueries];
        float distance[kLaneSurfels][kLaneQueries], weight[kLaneSurfels][kLaneQueries];
        LaneServed served[kLaneQueries][kMaxServedProbes];
        int found[kLaneQueries];
    };
    // What lookupBatch() keeps between calls on a thread.
    struct BatchScratch {
        std::vector<uint32_t> blocks;  // the distinct blocks of the batch's queries, in order of first use
        std::vector<uint32_t> rankOf;  // per query: its block's position in `blocks`, kNoBlock for none
        std::vector<std::array<int64_t, 3>> cells;  // per query: blockCellOf()
        std::vector<int> members;        // the queries grouped by block, in order within each
        std::vector<uint32_t> firstMember;  // per block of `blocks`, then one past the last: where its queries start in `members`
        LaneTests lanes;
    };

public:
    explicit DenseGridStore(DenseGridSettings settings) : m_settings(std::move(settings)) {}

    void prepare(const Scene& scene, RunNotes& notes) override {
        const Bounds3 bounds = scene.bounds();
        m_probes.clear();
        m_blocks.clear();
        m_groupBlocks.clear();
        m_cellFull = m_outsideGrid = m_invalidQueries = 0;
        m_occupiedCells = 0;
        m_maxOccupancy = 0;
        if (bounds.empty()) {
            // Nothing to place probes on: a grid of no cells refuses every insert as outside.
            m_cellSize = m_settings.cellSize.resolve(bounds);
            m_dims[0] = m_dims[1] = m_dims[2] = 0;
            m_cellCount = 0;
            m_slots.clear();
            m_counts.clear();
            m_occupied.clear();
            notes.skip("probes", "the scene has no geometry: the dense grid has no cells");
            return;
        }

        const vec3 extent = bounds.extent();
        m_cellSize = m_settings.cellSize.resolve(bounds);

        // Counted in double: a grid too large to allocate must not overflow an integer first.
        double dims[3], cells = 1.0;
        for (int a = 0; a < 3; ++a) {
            // Half a cell of padding at each end keeps points a rounding error off the bounds inside the grid.
            dims[a] = std::ceil(double(extent[a]) / double(m_cellSize)) + 1.0;
            m_origin[a] = double(bounds.min[a]) - 0.5 * double(m_cellSize);
            cells *= dims[a];
        }
        const std::string shape = formatCount(dims[0]) + " × " + formatCount(dims[1]) + " × " + formatCount(dims[2]);
        if (cells > m_settings.maxCells)
            throw InputError(m_settings.maxCellsWhere + "a dense grid of " + formatNumber(m_cellSize) + "-unit cells over this scene (" +
                             formatNumber(extent.x) + " × " + formatNumber(extent.y) + " × " + formatNumber(extent.z) +
                             " units) needs " + shape + " = " + formatCount(cells) + " cells, more than max_cells = " +
                             formatCount(m_settings.maxCells) + "; raise max_cells or the cell size");
        if (cells * m_settings.maxProbesPerCell > double(std::numeric_limits<uint32_t>::max()))
            throw InputError(m_settings.maxProbesPerCellWhere + formatCount(cells) + " cells × " +
                             std::to_string(m_settings.maxProbesPerCell) +
                             " probes per cell exceed the 2^32 - 1 probe ids; lower max_probes_per_cell or raise the cell size");

        for (int a = 0; a < 3; ++a) m_dims[a] = int64_t(dims[a]);
        m_cellCount = std::size_t(cells);
        m_slots.assign(m_cellCount * std::size_t(m_settings.maxProbesPerCell), 0u);
        m_counts.assign(m_cellCount, uint16_t(0));
        m_wordsPerRow = (std::size_t(m_dims[0]) + 63) / 64;
        m_occupied.assign(m_wordsPerRow * std::size_t(m_dims[1]) * std::size_t(m_dims[2]), 0);
        // The groups of the cells from blockRings() before the grid to as far after it: where
        // blockCellOf() can put a query.
        std::size_t groups = 1;
        for (int a = 0; a < 3; ++a) {
            m_firstGroup[a] = groupOf(-blockRings());
            m_groupDims[a] = groupOf(m_dims[a] - 1 + blockRings()) - m_firstGroup[a] + 1;
            groups *= std::size_t(m_groupDims[a]);
        }
        m_groupBlocks.assign(groups, kNoBlock);
        notes.skip("probe_recycling", "dense_grid: a full cell refuses new probes (max_probes_per_cell = " +
                                          std::to_string(m_settings.maxProbesPerCell) + "); GIBS recycles surfels instead");
    }

    ProbeInsert insert(const ProbeQuery& query, uint32_t frame) override {
        if (!isSurfaceQuery(query)) {
            ++m_invalidQueries;
            return {ProbeInsert::Status::Refused};
        }
        int64_t cell[3];
        if (!cellOf(query.position, 0, cell)) {
            ++m_outsideGrid;
            return {ProbeInsert::Status::Refused};
        }
        const std::size_t index = linearIndex(cell);
        uint16_t& count = m_counts[index];
        if (count == m_settings.maxProbesPerCell) {
            ++m_cellFull;
            return {ProbeInsert::Status::Refused};
        }
        const uint32_t id = uint32_t(m_probes.size());
        m_probes.push_back({query.position, query.normal});
        listInGroups(id, cell);
        m_slots[index * std::size_t(m_settings.maxProbesPerCell) + count] = id;
        if (count == 0) {
            ++m_occupiedCells;
            m_occupied[rowOf(cell) * m_wordsPerRow + std::size_t(cell[0]) / 64] |= uint64_t(1) << (cell[0] % 64);
        }
        ++count;
        m_maxOccupancy = std::max(m_maxOccupancy, int(count));
        return {ProbeInsert::Status::Inserted, id};
    }

    int nearest(const ProbeQuery& query, int count, ProbeNeighbour* out) const override {
        if (count <= 0 || !isSurfaceQuery(query)) return 0;
        // The 3×3×3 block settles the query when it holds `count` probes within one cell edge: no
        // probe outside it is that close. Otherwise the 5×5×5 block, sound up to two edges.
        const int found = nearestInBlock(query, count, out, 1);
        if (found == count && out[count - 1].distance <= m_cellSize) return found;
        return nearestInBlock(query, count, out, kSearchRings);
    }

    // The surfels of the query's group serve it, those of its own cell's block (lookupIn()).
    void lookup(const ProbeQuery& query, int count, ProbeLookup& out) const override {
        int64_t cell[3];
        if (!blockCellOf(query, cell)) return answer(nullptr, 0, out);
        const uint32_t block = m_groupBlocks[groupIndex(cell)];
        if (block == kNoBlock) return answer(nullptr, 0, out);
        lookupIn(m_blocks[block], cell, query, out);
    }

    // The queries of a tile of pixels fall in few groups, whose blocks hold a dozen surfels or so
    // on the Cornell box. Here a group's queries are tested kLaneQueries at a time, each surfel
    // against all of them in SIMD lanes (testLanes), and each query then takes the surfels its
    // bits name: the same tests, distances and order as lookupIn().
    void lookupBatch(const ProbeQuery* queries, int n, int count, ProbeLookup* out) const override {
        if (n == 1) return lookup(queries[0], count, out[0]);  // a path vertex's: no lanes to fill
        static thread_local BatchScratch scratch;
        scratch.blocks.clear();
        scratch.rankOf.resize(std::size_t(n));
        scratch.cells.resize(std::size_t(n));
        scratch.firstMember.clear();  // counts per rank first
        // Neighbouring pixels mostly share a group: the previous query's block is tried first.
        uint32_t lastBlock = kNoBlock, lastRank = kNoBlock;
        for (int i = 0; i < n; ++i) {
            uint32_t block = kNoBlock, rank = kNoBlock;
            if (blockCellOf(queries[i], scratch.cells[i].data())) block = m_groupBlocks[groupIndex(scratch.cells[i].data())];
            if (block == kNoBlock) {
                answer(nullptr, 0, out[i]);
            } else if (block == lastBlock) {
                rank = lastRank;
            } else {
                rank = uint32_t(std::find(scratch.blocks.begin(), scratch.blocks.end(), block) - scratch.blocks.begin());
                if (rank == scratch.blocks.size()) {
                    scratch.blocks.push_back(block);
                    scratch.firstMember.push_back(0);
                }
                lastBlock = block;
                lastRank = rank;
            }
            scratch.rankOf[i] = rank;
            if (rank != kNoBlock) ++scratch.firstMember[rank];
        }
        // Counts to ends; the queries placed from the last, each before the later ones of its
        // block, leave each block's start behind.
        uint32_t total = 0;
        for (uint32_t& count : scratch.firstMember) count = total += count;
        scratch.members.resize(total);
        for (int i = n - 1; i >= 0; --i)
            if (scratch.rankOf[i] != kNoBlock) scratch.members[--scratch.firstMember[scratch.rankOf[i]]] = i;
        scratch.firstMember.push_back(total);
        for (std::size_t r = 0; r < scratch.blocks.size(); ++r) {
            const uint32_t end = scratch.firstMember[r + 1];
            for (uint32_t first = scratch.firstMember[r]; first < end; first += kLaneQueries)
                lookupLanes(m_blocks[scratch.blocks[r]], queries, scratch.cells.data(), scratch.members.data() + first,
                            int(std::min<uint32_t>(kLaneQueries, end - first)), out, scratch.lanes);
        }
    }

    // A lone lookup's first loads are its group's entry in m_groupBlocks, then the block and
    // its arrays: the entries of all the queries are prefetched first, then each block read.
    void prefetchLookups(const ProbeQuery* queries, int n) const override {
        constexpr int kChunk = 64;
        std::size_t groups[kChunk];
        for (int first = 0; first < n; first += kChunk) {
            int listed = 0;
            for (int i = first; i < std::min(n, first + kChunk); ++i) {
                int64_t cell[3];
                if (!blockCellOf(queries[i], cell)) continue;
                groups[listed] = groupIndex(cell);
                __builtin_prefetch(&m_groupBlocks[groups[listed++]]);
            }
            for (int i = 0; i < listed; ++i) {
                const uint32_t b = m_groupBlocks[groups[i]];
                if (b == kNoBlock) continue;
                const SurfelBlock& block = m_blocks[b];
                for (int a = 0; a < SurfelBlock::kFloatArrays; ++a) __builtin_prefetch(block.floats(SurfelBlock::FloatArray(a)));
                for (int a = 0; a < SurfelBlock::kIntArrays; ++a) __builtin_prefetch(block.ints(SurfelBlock::IntArray(a)));
            }
        }
    }

    // lookup() of `query`, in `cell`, from the surfels of its group's block: the same surfels and
    // tests as forEachFacingProbe()'s over the cell's block.
    void lookupIn(const SurfelBlock& block, const int64_t cell[3], const ProbeQuery& query, ProbeLookup& out) const {
        const float radius = surfelRadius();
        // The surfels facing the query's way within reach (or a rounding beyond it: the square
        // root is taken for those only) are marked in one vector pass, then listed without a
        // branch per surfel: about half of a block's pass, and a branch on each would be
        // mispredicted as often as not.
        const float reach2 = radius * radius * kReachSlack;
        const float *x = block.floats(SurfelBlock::X), *y = block.floats(SurfelBlock::Y), *z = block.floats(SurfelBlock::Z);
        const float *nx = block.floats(SurfelBlock::NormalX), *ny = block.floats(SurfelBlock::NormalY), *nz = block.floats(SurfelBlock::NormalZ);
        const int32_t *cx = block.ints(SurfelBlock::CellX), *cy = block.ints(SurfelBlock::CellY), *cz = block.ints(SurfelBlock::CellZ);
        const vec3 q = query.position, qn = query.normal;
        const float threshold = m_settings.normalThreshold;
        const int32_t rings = blockRings();
        const int32_t qx = int32_t(cell[0] - block.lo[0]), qy = int32_t(cell[1] - block.lo[1]), qz = int32_t(cell[2] - block.lo[2]);
        const float cover = coverageRadius(query);
        LaneServed covering[kMaxServedProbes];
        int found = 0;
        // In chunks, so that the marks live on the stack: thread-local vectors cost a TLS lookup and
        // a resize per lookup.
        constexpr std::size_t kChunk = 256;
        uint32_t passes[kChunk], within[kChunk];
        for (std::size_t start = 0; start < block.size; start += kChunk) {
            const std::size_t size = std::min(kChunk, block.size - start);
            for (std::size_t i = 0; i < size; ++i) {
                const std::size_t k = start + i;
                const float dx = x[k] - q.x, dy = y[k] - q.y, dz = z[k] - q.z;
                const uint32_t inBlock =
                    uint32_t(std::abs(cx[k] - qx) <= rings) & uint32_t(std::abs(cy[k] - qy) <= rings) & uint32_t(std::abs(cz[k] - qz) <= rings);
                passes[i] = inBlock & uint32_t(nx[k] * qn.x + ny[k] * qn.y + nz[k] * qn.z > threshold) & uint32_t(dx * dx + dy * dy + dz * dz <= reach2);
            }
            std::size_t n = 0;
            for (std::size_t i = 0; i < size; ++i) {
                within[n] = uint32_t(start + i);
                n += passes[i];
            }
            // A serving surfel's weight and coverage from the block's copy of its position and
            // normal, as testLanes() takes them: m_probes[id] would be one more miss per surfel.
            for (std::size_t j = 0; j < n; ++j) {
                const uint32_t k = within[j];
                const float dx = x[k] - q.x, dy = y[k] - q.y, dz = z[k] - q.z;
                const float distance = std::sqrt(dx * dx + dy * dy + dz * dz);
                if (!(distance < radius)) continue;
                const float normalDot = nx[k] * qn.x + ny[k] * qn.y + nz[k] * qn.z;
                const LaneServed served{block.id(k), distance, surfelWeight(distance, normalDot, radius, threshold),
                                        coversPoint(dx, dy, dz, qn.x, qn.y, qn.z, cover)};
                found = insertNearest(covering, found, kMaxServedProbes, served);
            }
        }
        answer(covering, found, out);
    }

    // lookupIn() of the `m` queries `members`, all of whose cells lie in `block`'s group.
    void lookupLanes(const SurfelBlock& block, const ProbeQuery* queries, const std::array<int64_t, 3>* cells, const int* members, int m,
                     ProbeLookup* out, LaneTests& lanes) const {
        constexpr int32_t kFar = 1 << 30;  // the cell of an unused lane: no surfel's block holds it
        for (int k = 0; k < kLaneQueries; ++k) {
            const bool used = k < m;
            const ProbeQuery& q = queries[used ? members[k] : members[0]];
            lanes.x[k] = q.position.x;
            lanes.y[k] = q.position.y;
            lanes.z[k] = q.position.z;
            lanes.nx[k] = q.normal.x;
            lanes.ny[k] = q.normal.y;
            lanes.nz[k] = q.normal.z;
            for (int a = 0; a < 3; ++a) lanes.cell[a][k] = used ? int32_t(cells[members[k]][a] - block.lo[a]) : kFar;
            lanes.found[k] = 0;
        }
        for (uint32_t start = 0; start < block.size; start += kLaneSurfels) {
            const uint32_t size = std::min<uint32_t>(kLaneSurfels, block.size - start);
            // m_cellSize: coverageRadius(), the same for every query of this store.
            testLanes(block, start, size, surfelRadius(), m_settings.normalThreshold, blockRings(), m_cellSize, lanes);
            for (int k = 0; k < m; ++k)
                for (uint32_t hits = lanes.hits[k]; hits; hits &= hits - 1) {
                    const int s = std::countr_zero(hits);
                    const LaneServed served{block.id(start + uint32_t(s)), lanes.distance[s][k], lanes.weight[s][k], bool(lanes.covers[k] >> s & 1)};
                    lanes.found[k] = insertNearest(lanes.served[k], lanes.found[k], kMaxServedProbes, served);
                }
        }
        for (int k = 0; k < m; ++k) answer(lanes.served[k], lanes.found[k], out[members[k]]);
    }

    // The answer of a lookup that found the `found` surfels `served`, nearest first.
    static void answer(const LaneServed* served, int found, ProbeLookup& out) {
        clearAnswer(out);
        for (int i = 0; i < found; ++i) {
            out.probes[i] = {served[i].id, served[i].weight};
            out.covered = out.covered || served[i].covers;
        }
        out.count = found;
        normaliseWeights(out);
        if (found > 0) {
            out.distance = served[0].distance;
            // Any probe nearer than the nearest covering surfel would cover the point too (the
            // surfel radius is at most the search radius, the normal test is nearest()'s): it is
            // receiverOf()'s nearest. Without a covering surfel the nearest may lie beyond the
            // surfel radius, unknown here.
            out.receiver = served[0].id;
        }
    }

    // lookupIn()'s tests of surfels start .. start + size of `block` against every lane: a bit per
    // surfel in each lane's `hits` (it serves the lane's point) and `covers` (coversPoint() within
    // `cover`), and each surfel's distance to each lane's point and its weight there.
    GIBENCH_SIMD_CLONES static void testLanes(const SurfelBlock& block, uint32_t start, uint32_t size, float radius, float threshold, int32_t rings,
                                              float cover, LaneTests& lanes) {
        const float *x = block.floats(SurfelBlock::X), *y = block.floats(SurfelBlock::Y), *z = block.floats(SurfelBlock::Z);
        const float *nx = block.floats(SurfelBlock::NormalX), *ny = block.floats(SurfelBlock::NormalY), *nz = block.floats(SurfelBlock::NormalZ);
        const int32_t *cx = block.ints(SurfelBlock::CellX), *cy = block.ints(SurfelBlock::CellY), *cz = block.ints(SurfelBlock::CellZ);
        std::fill_n(lanes.hits, kLaneQueries, 0u);
        std::fill_n(lanes.covers, kLaneQueries, 0u);
        for (uint32_t s = 0; s < size; ++s) {
            const uint32_t i = start + s;
            // The surfel's values read once: the lanes' stores could alias the block's arrays for
            // all the compiler knows, which made it check at run time.
            const float sx = x[i], sy = y[i], sz = z[i], snx = nx[i], sny = ny[i], snz = nz[i];
            const int32_t scx = cx[i], scy = cy[i], scz = cz[i];
            for (int k = 0; k < kLaneQueries; ++k) {
                // `&` rather than `&&`, so that the lanes run without a branch.
                const float dx = sx - lanes.x[k], dy = sy - lanes.y[k], dz = sz - lanes.z[k];
                const float distance = std::sqrt(dx * dx + dy * dy + dz * dz);
                const float normalDot = snx * lanes.nx[k] + sny * lanes.ny[k] + snz * lanes.nz[k];
                const uint32_t serves = uint32_t(std::abs(scx - lanes.cell[0][k]) <= rings) & uint32_t(std::abs(scy - lanes.cell[1][k]) <= rings) &
                                        uint32_t(std::abs(scz - lanes.cell[2][k]) <= rings) & uint32_t(normalDot > threshold) &
                                        uint32_t(distance < radius);
                lanes.distance[s][k] = distance;
                lanes.weight[s][k] = surfelWeight(distance, normalDot, radius, threshold);
                lanes.hits[k] |= serves << s;
                lanes.covers[k] |= uint32_t(coversPoint(dx, dy, dz, lanes.nx[k], lanes.ny[k], lanes.nz[k], cover)) << s;
            }
        }
    }

    // A serving surfel's weight: a smooth radial falloff over `radius` times how far its normal
    // turns towards the point's beyond `threshold`. `normalDot`: the dot product of the two normals.
    // The clamp to [0, 1] is std::clamp's, as masks (testLanes() runs it in lanes). Both ratios
    // multiply by an inverse, which testLanes() computes once per call rather than per surfel and lane.
    static float surfelWeight(float distance, float normalDot, float radius, float threshold) {
        const float t = distance * (1.0f / radius);
        const float facing = (normalDot - threshold) * (1.0f / (1.0f - threshold));
        const float atLeastZero = laneSelect(laneMask(facing < 0.0f), 0.0f, facing);
        return (1.0f - t * t) * (1.0f - t * t) * laneSelect(laneMask(1.0f < atLeastZero), 1.0f, atLeastZero);
    }
    // The surfel at offset (dx, dy, dz) from a point of unit normal (nx, ny, nz) covers it: within
    // `cover` in its tangent plane and along its normal. Written out per coordinate so that the
    // lanes of testLanes() run it as lookupIn() does, to the bit.
    static bool coversPoint(float dx, float dy, float dz, float nx, float ny, float nz, float cover) {
        const float along = dx * nx + dy * ny + dz * nz;
        const float ex = dx - along * nx, ey = dy - along * ny, ez = dz - along * nz;
        return bool(uint32_t(std::sqrt(ex * ex + ey * ey + ez * ez) < cover) & uint32_t(std::fabs(along) < cover));
    }

    // An answer serving nothing, the start of every answer.
    static void clearAnswer(ProbeLookup& out) {
        out.count = 0;
        out.covered = false;
        out.distance = kInfinity;
        out.receiver = kReceiverUnknown;
    }

    int servedAtMost(int count) const override { return kMaxServedProbes; }
    // A tile of 32² pixels brings lookupBatch() four times the queries of 16² per group, which
    // fill testLanes()' lanes: the raster stage against the G-buffer stage (the machine's phases
    // cancel) 2.13 → 1.95 and 2.12 → 1.94 on the Cornell box, medians of three and four
    // alternated runs; 64² gave 2.12.
    int lookupTile() const override { return 32; }

    std::span<const Probe> probes() const override { return m_probes; }

    // One probe per cell-sized disc: the density of MAMBA's fine cells at the same cell edge.
    float coverageRadius(const ProbeQuery&) const override { return m_cellSize; }
    // kSearchRings cell edges: the (2 kSearchRings + 1)³ cells around the query hold every probe this close.
    float searchRadius(const ProbeQuery&) const override { return kSearchRings * m_cellSize; }

    // Probes within `rings` cell edges, from the (2 rings + 1)³ cells around the query's cell.
    int nearestInBlock(const ProbeQuery& query, int count, ProbeNeighbour* out, int rings) const {
        int64_t centre[3];
        // A query up to `rings` cells outside the grid still reaches the probes along its border.
        if (!cellOf(query.position, rings, centre)) return 0;
        const float radius = float(rings) * m_cellSize;
        int64_t lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::max<int64_t>(centre[a] - rings, 0);
            hi[a] = std::min(centre[a] + rings, m_dims[a] - 1);
        }
        int found = 0;
        forEachFacingProbe(query, lo, hi, radius, [&](uint32_t id, float distance) {
            if (distance <= radius) found = insertNearest(out, found, count, {id, distance});
        });
        return found;
    }

    // Calls f(id, distance to the query) for every probe of the cells lo..hi (inclusive, inside
    // the grid) whose normal passes normal_threshold against the query's, and that lies within
    // `reach` or a rounding beyond it: the squared distance is compared first, with a slack that
    // keeps every probe whose rounded distance could still equal `reach`, so that the square root
    // is taken for the probes of the cells' sphere only (about a quarter of a 5³ box's).
    template <class F>
    void forEachFacingProbe(const ProbeQuery& query, const int64_t lo[3], const int64_t hi[3], float reach, F&& f) const {
        const float reach2 = reach * reach * kReachSlack;
        forEachProbe(lo, hi, [&](uint32_t id, const int64_t*) {
            const Probe& p = m_probes[id];
            if (!(glm::dot(p.normal, query.normal) > m_settings.normalThreshold)) return;
            const vec3 d = p.position - query.position;
            if (glm::dot(d, d) > reach2) return;
            f(id, glm::length(d));
        });
    }

    // Calls f(id, cell) for every probe of the cells lo..hi (inclusive, inside the grid), reading
    // the counts of occupied cells only.
    template <class F>
    void forEachProbe(const int64_t lo[3], const int64_t hi[3], F&& f) const {
        const std::size_t perCell = std::size_t(m_settings.maxProbesPerCell);
        for (int64_t z = lo[2]; z <= hi[2]; ++z)
            for (int64_t y = lo[1]; y <= hi[1]; ++y) {
                const int64_t row[3] = {0, y, z};
                const std::size_t rowStart = linearIndex(row);
                const uint64_t* words = m_occupied.data() + rowOf(row) * m_wordsPerRow;
                for (int64_t word = lo[0] / 64; word <= hi[0] / 64; ++word) {
                    // The word's bits of the cells lo[0]..hi[0].
                    const int64_t first = std::max(lo[0], word * 64), last = std::min(hi[0], word * 64 + 63);
                    const uint64_t span = last - first == 63 ? ~uint64_t(0) : ((uint64_t(1) << (last - first + 1)) - 1) << (first % 64);
                    for (uint64_t cells = words[word] & span; cells; cells &= cells - 1) {
                        const std::size_t index = rowStart + std::size_t(word * 64 + std::countr_zero(cells));
                        const uint32_t* ids = m_slots.data() + index * perCell;
                        const int64_t cell[3] = {word * 64 + std::countr_zero(cells), y, z};
                        for (uint16_t k = 0; k < m_counts[index]; ++k) f(ids[k], cell);
                    }
                }
            }
    }

    Json stats() const override {
        std::size_t listBytes = m_groupBlocks.capacity() * sizeof(uint32_t) + m_blocks.capacity() * sizeof(SurfelBlock);
        for (const SurfelBlock& block : m_blocks)
            listBytes += std::size_t(block.capacity) * (SurfelBlock::kFloatArrays * sizeof(float) + SurfelBlock::kIntArrays * sizeof(int32_t));
        const std::size_t bytes = m_slots.capacity() * sizeof(uint32_t) + m_counts.capacity() * sizeof(uint16_t) +
                                  m_occupied.capacity() * sizeof(uint64_t) + m_probes.capacity() * sizeof(Probe) + listBytes;
        return {
            {"probes", m_probes.size()},
            {"cell_size", m_cellSize},
            {"grid_cells", {m_dims[0], m_dims[1], m_dims[2]}},
            {"cells", m_cellCount},
            {"occupied_cells", m_occupiedCells},
            {"max_occupancy", m_maxOccupancy},
            {"mean_occupancy", m_cellCount > 0 ? double(m_probes.size()) / double(m_cellCount) : 0.0},
            {"store", "dense_grid"},
            {"store_bytes", bytes},
            {"surfel_list_bytes", listBytes},
            {"refused", m_cellFull + m_outsideGrid + m_invalidQueries},
            {"cell_full", m_cellFull},
            {"outside_grid", m_outsideGrid},
            {"invalid_queries", m_invalidQueries},
        };
    }

private:
    // The cell of finite `p` on each axis, or false when it lies more than `margin` cells outside
    // the grid on some axis.
    bool cellOf(const vec3& p, int64_t margin, int64_t cell[3]) const {
        for (int a = 0; a < 3; ++a) {
            const double c = std::floor((double(p[a]) - m_origin[a]) / double(m_cellSize));
            // Compared as doubles first: a point far away must not overflow the integer conversion.
            if (!(c >= double(-margin) && c < double(m_dims[a] + margin))) return false;
            cell[a] = int64_t(c);
        }
        return true;
    }

    // Cells a surfel holding a point can lie in on each axis: within ceil(surfel_radius) of its cell.
    int blockRings() const { return int(std::ceil(m_settings.surfelRadius)); }

    // The cell whose block holds every surfel that can hold the query point; false for an invalid
    // query or one too far outside the grid for any.
    bool blockCellOf(const ProbeQuery& query, int64_t cell[3]) const {
        return isSurfaceQuery(query) && m_cellCount > 0 && cellOf(query.position, blockRings(), cell);
    }

    float surfelRadius() const { return m_settings.surfelRadius * m_cellSize; }

    // Group of cell coordinate c on an axis (floor division: cells before the grid are negative).
    static int64_t groupOf(int64_t c) { return c >= 0 ? c / kGroupCells : -((kGroupCells - 1 - c) / kGroupCells); }

    // Index in m_groupBlocks of the group of `cell` (a cell blockCellOf() can return).
    std::size_t groupIndex(const int64_t cell[3]) const {
        std::size_t index = 0;
        for (int a = 2; a >= 0; --a) index = index * std::size_t(m_groupDims[a]) + std::size_t(groupOf(cell[a]) - m_firstGroup[a]);
        return index;
    }

    // Adds surfel `id` of `cell` to the lists of the groups whose cells' blocks hold that cell:
    // those of the cells within blockRings() of it on every axis.
    void listInGroups(uint32_t id, const int64_t cell[3]) {
        const int rings = blockRings();
        int64_t from[3], to[3];
        for (int a = 0; a < 3; ++a) {
            from[a] = groupOf(cell[a] - rings);
            to[a] = groupOf(cell[a] + rings);
        }
        const Probe& p = m_probes[id];
        for (int64_t gz = from[2]; gz <= to[2]; ++gz)
            for (int64_t gy = from[1]; gy <= to[1]; ++gy)
                for (int64_t gx = from[0]; gx <= to[0]; ++gx) {
                    const int64_t first[3] = {gx * kGroupCells, gy * kGroupCells, gz * kGroupCells};
                    uint32_t& index = m_groupBlocks[groupIndex(first)];
                    if (index == kNoBlock) {
                        index = uint32_t(m_blocks.size());
                        SurfelBlock& created = m_blocks.emplace_back();
                        for (int a = 0; a < 3; ++a) created.lo[a] = first[a] - rings;
                    }
                    SurfelBlock& block = m_blocks[index];
                    const int32_t relative[3] = {int32_t(cell[0] - block.lo[0]), int32_t(cell[1] - block.lo[1]), int32_t(cell[2] - block.lo[2])};
                    block.add(p.position, p.normal, relative, id);
                }
    }

    // Row (y, z) of the occupancy bitmap.
    std::size_t rowOf(const int64_t cell[3]) const { return std::size_t(cell[2]) * std::size_t(m_dims[1]) + std::size_t(cell[1]); }

    std::size_t linearIndex(const int64_t cell[3]) const {
        return (std::size_t(cell[2]) * std::size_t(m_dims[1]) + std::size_t(cell[1])) * std::size_t(m_dims[0]) + std::size_t(cell[0]);
    }

    DenseGridSettings m_settings;
    float m_cellSize = 0.0f;  // resolved in prepare(), scene units
    double m_origin[3] = {0.0, 0.0, 0.0};
    int64_t m_dims[3] = {0, 0, 0};
    std::size_t m_cellCount = 0;
    std::vector<uint32_t> m_slots;   // maxProbesPerCell ids per cell, the first m_counts[cell] in use
    std::vector<uint16_t> m_counts;  // per cell
    std::vector<uint64_t> m_occupied;  // bit x of row (y, z): the cell holds a probe
    std::size_t m_wordsPerRow = 0;
    std::vector<Probe> m_probes;     // by id
    static constexpr uint32_t kNoBlock = ~uint32_t(0);
    std::vector<SurfelBlock> m_blocks;        // of the groups holding surfels, in the order they got their first
    std::vector<uint32_t> m_groupBlocks;      // per group: its index in m_blocks, or kNoBlock
    int64_t m_firstGroup[3] = {0, 0, 0};      // per axis, the group of m_groupBlocks' first
    int64_t m_groupDims[3] = {0, 0, 0};
    uint64_t m_cellFull = 0, m_outsideGrid = 0, m_invalidQueries = 0, m_occupiedCells = 0;
    int m_maxOccupancy = 0;
};

}  // namespace

std::unique_ptr<ProbeStore> createDenseGridStore(Params& params) {
    DenseGridSettings s;
    s.cellSize = ProbeSpacing(params, "cell_size");
    s.maxProbesPerCell = int(params.getInt("max_probes_per_cell"));
    s.normalThreshold = params.getFloat("normal_threshold");
    s.surfelRadius = params.getFloat("surfel_radius");
    s.maxCells = double(params.getInt("max_cells"));
    s.maxProbesPerCellWhere = params.where("max_probes_per_cell");
    s.maxCellsWhere = params.where("max_cells");
    return std::make_unique<DenseGridStore>(std::move(s));
}

}  // namespace gibench
