#pragma once
// MAMBA's probe index (paper §3.2, Figure 4): a sparse uniform grid of fine cells stored as a
// two-level hash table. The first level maps a coarse cell (fineCellsPerCoarseEdge³ fine cells) to a
// second-level table, created on demand; the second level maps a fine cell to a 32-bit value (the
// caller's probe index). Unlike the original there is no bound on the scene's extent, a full table
// degrades visibly (counted refusals or LRU evictions, docs/mamba.md item 6), neighbour queries cross
// coarse-cell borders (item 4) and a facing tag separates the two sides of thin walls (item 7).
//
// Memory: a second-level table starts with kInitialFineSlots slots of 8 bytes (a 32-bit key and
// its value), in buckets of four, and doubles whenever it would pass half full or an insert finds
// its probe run full, up to fineSlotsPerTable: 2 to 4 slots per key (issue 9). Allocated whole, the
// original's 512 KiB tables held the 2047 probes of a 64² Cornell box run in 18 MB; grown, they
// take a few hundred KB. Tables were kept a quarter full while neighbour queries probed every cell
// of their block (mostly misses, 2.5 slots each at half load); with the occupancy bitmaps below they
// probe only occupied cells, and half full takes half the memory. Slots were 16 bytes (a 64-bit key
// and a last-used frame beside the value); at 8 bytes a bucket's four keys are one SSE2 register,
// compared with a key at once (locate), and the tables take half the memory (docs/performance.md,
// "Lookups"). When a probe was last used is its owner's to know (LastUsedOf): the grid asks only
// when it must evict, and keeping a copy per slot cost a table lookup per use.
// Tables are kept for reuse when they empty. The first level is a power-of-two array of
// 40-byte slots kept at most 1/16 full (64 slots at first, grown with the peak number of live
// tables). With the original constants that is at most 1023 × 8192 buckets × 32 B ≈ 268 MB plus
// 16384 × 40 B = 640 KiB.
// When a coarse cell has at most kMaxOccupancyEdge fine cells per edge, each table also has an
// occupancy bitmap, one bit per fine cell of its coarse cell whatever the facing, so that
// neighbour queries skip empty cells without hashing (most cells of a block around a surface point
// are empty, and each miss cost a hashed probe): ⌈n³ / 64⌉ + 1 words, 1968 B at n = 25 (2 MB at
// 1023 tables), plus a 32-byte set of the facing tags the table has held since it was created or
// reused. Bitmaps are kept with their tables for reuse.

#include "core/util/math.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace gibench {

// Integer coordinates of a fine cell, plus a facing tag so the two sides of a thin wall are
// different cells (docs/mamba.md item 7). Every int64 coordinate and every tag value is valid.
struct CellKey {
    int64_t x, y, z;
    uint8_t facing;
    bool operator==(const CellKey&) const = default;
};

// The sum of a cell's coordinates scaled by distinct odd constants, modulo 2^64: the
// multiplicative part of hashCellKey. Its top bits depend on every input bit, all the grid's first
// level reads of it.
inline uint64_t scaledCoordinateSum(int64_t x, int64_t y, int64_t z) {
    return uint64_t(x) * 0x9e3779b97f4a7c15ull + uint64_t(y) * 0xc2b2ae3d27d4eb4full + uint64_t(z) * 0x165667b19e3779f9ull;
}

// 64-bit hash of a cell key: multiplicative ("Fibonacci") hashing of the coordinates and the tag,
// the high half folded onto the low half, so both ends of the hash are well mixed (why this hash:
// sparse_hash_grid.cpp). Exposed so that other maps can be compared on the same hash.
inline uint64_t hashCellKey(const CellKey& k) {
    const uint64_t h = scaledCoordinateSum(k.x, k.y, k.z) + uint64_t(k.facing) * 0x27d4eb2f165667c5ull;
    return h ^ (h >> 32);
}

enum class FullPolicy { Refuse, EvictLeastRecentlyUsed };

struct SparseHashGridConfig {
    double fineCellSize = 0.4;            // scene units, finite and > 0
    int fineCellsPerCoarseEdge = 25;      // in [1, 255]: a coarse cell is 25×25×25 fine cells (10 units in the original)
    uint32_t maxCoarseTables = 1023;      // >= 1: live second-level tables at most
    uint32_t fineSlotsPerTable = 32767;   // >= 1: slots of each second-level table
    uint32_t maxProbeLength = 32;         // in [1, fineSlotsPerTable]: slots examined per insert/find before the table counts as full there, rounded up to whole buckets (SparseHashGrid::kBucketSlots)
    FullPolicy policy = FullPolicy::EvictLeastRecentlyUsed;
};

// When the grid's owner last used the entry holding `value`, as a frame number (larger is more
// recent): what LRU eviction compares.
using LastUsedOf = std::function<uint32_t(uint32_t value)>;

struct InsertOutcome {
    enum class Status { Inserted, Existing, Evicted, Refused } status;
    uint32_t value;          // the value now stored for the key (Existing: the old one); undefined if Refused
    uint32_t evictedValue;   // Evicted: the value that was dropped to make room (the caller frees that probe)
    CellKey evictedKey;      // Evicted: its key
};

// Not thread-safe for writers; any number of threads may call the const members at once while no
// thread calls a non-const one. Movable, not copyable; a moved-from grid may only be destroyed or
// assigned to.
class SparseHashGrid {
public:
    static constexpr std::size_t kBytesPerFineSlot = 8;  // a key and its value, 32 bits each
    static constexpr uint32_t kBucketSlots = 4;          // slots of a bucket: a second-level table's unit of probing
    static constexpr int kMaxFineCellsPerCoarseEdge = 255;  // a cell's offset takes 8 bits per axis
    static constexpr uint32_t kInitialFineSlots = 64;     // a new table's slots (fewer if fineSlotsPerTable is smaller)

    // Throws std::invalid_argument naming the first invalid field (ranges in SparseHashGridConfig),
    // or when the policy evicts and `lastUsedOf` is empty.
    SparseHashGrid(const SparseHashGridConfig& config, LastUsedOf lastUsedOf);

    // Fine cell containing `position` (floor of position / fineCellSize per axis, computed in double),
    // tagged with `facingTag` (0 when facing is off, else 1..6 from the normal's dominant axis and
    // sign; the grid treats it as an opaque tag). Throws std::invalid_argument for a non-finite
    // position and std::out_of_range when a cell coordinate does not fit in int64.
    CellKey keyOf(const vec3& position, uint8_t facingTag) const;
    // The same, or std::nullopt where keyOf() throws: for positions the caller cannot vouch for.
    // Inline: returned through memory from a call, the key was read back wider than its last store
    // (the tag) was written, a stall on every query of the raster stage.
    std::optional<CellKey> tryKeyOf(const vec3& position, uint8_t facingTag) const {
        if (!isFinite(position)) return std::nullopt;
        int64_t cell[3];
        for (int a = 0; a < 3; ++a) {
            const double c = std::floor(double(position[a]) / m_config.fineCellSize);
            // Exactly the doubles in [-2^63, 2^63) convert to int64 without undefined behaviour; the
            // quotient may also have overflowed to infinity at tiny cell sizes.
            if (!(c >= -0x1p63 && c < 0x1p63)) return std::nullopt;
            cell[a] = int64_t(c);
        }
        return CellKey{cell[0], cell[1], cell[2], facingTag};
    }

    // Coarse cell of a fine cell: floor division by fineCellsPerCoarseEdge per axis, exact for every
    // int64 coordinate. Its facing is 0: all facings of a coarse cell share one second-level table.
    CellKey coarseOf(const CellKey& fine) const;

    // Stores `value` for `key` unless the key is present.
    //  - Inserted: the key was absent and is now stored.
    //  - Existing: the key was present; its value is unchanged and returned.
    //  - Evicted (policy EvictLeastRecentlyUsed): the key's table has fineSlotsPerTable slots (or
    //    could not grow without pushing a key beyond its probe sequence) and the key's probe
    //    sequence (maxProbeLength slots rounded up to whole buckets, from its home bucket) held other
    //    keys only; the one whose value has the smallest lastUsedOf (the first of them in probe order
    //    on a tie) was dropped, reported in evictedKey/evictedValue, and `key` took its slot. Counted
    //    in Stats::evictions.
    //  - Refused: under policy Refuse when the probe sequence is full in a table that cannot grow;
    //    under either policy when the key's coarse cell has no table and maxCoarseTables tables are
    //    live. Nothing changes but Stats::refusedInserts.
    // Runs in O(maxProbeLength) plus, when a table is created or grows, O(its slots); never blocks.
    InsertOutcome insert(const CellKey& key, uint32_t value);

    // Value stored for `key`, or std::nullopt. Allocation-free; safe for concurrent readers.
    std::optional<uint32_t> find(const CellKey& key) const;

    // Removes `key`; false if absent. Later entries of its probe run shift back (no tombstones), and a
    // table left empty is released (kept for reuse), so its coarse cell no longer counts against
    // maxCoarseTables.
    bool erase(const CellKey& key);

    // Calls f(const CellKey&, uint32_t value) for each stored key of the 3×3×3 block of fine cells
    // centred on `key` (the key itself included) with the same facing tag, across coarse-cell borders;
    // cells beyond the int64 range do not exist and are skipped. At most one first-level lookup per
    // distinct coarse cell of the block; allocation-free; safe for concurrent readers.
    template <class F>
    void forEachNeighbour(const CellKey& key, F&& f) const;

    // The same over the (2 rings + 1)³ block (rings 0 to kMaxBlockRings), in z, then y, then x
    // order. When fineCellsPerCoarseEdge <= kMaxOccupancyEdge, only the cells of the block that
    // hold a key of some facing tag are looked up.
    static constexpr int kMaxBlockRings = 2;
    template <class F>
    void forEachInBlock(const CellKey& key, int rings, F&& f) const {
        walkBlock(key, rings, f, false, [] { return BlockBox{}; });
    }
    // Cells of a block by their offsets from its centre cell, from[a]..to[a] on axis a (empty when
    // from > to on some axis).
    struct BlockBox {
        int from[3] = {0, 0, 0}, to[3] = {-1, -1, -1};
    };
    // The same in two passes set up once: the cells of the 3×3×3 block first, then those of the
    // box outer() returns (clamped to the block) outside it. For a nearest-probe search, which
    // mostly settles in the inner block, or needs the outer ring on a side or two: a second
    // forEachInBlock would split the axes and look up the coarse cells again.
    template <class F, class Outer>
    void forEachInBlockInnerFirst(const CellKey& key, int rings, F&& f, Outer&& outer) const {
        walkBlock(key, rings, f, true, outer);
    }

    // Calls f(const CellKey&, uint32_t value) for each stored key with tag `facing` in the box of
    // fine cells lo..hi (inclusive on every axis, lo <= hi), each key once, coarse cell by coarse
    // cell; with bitmaps only occupied cells are looked up. For the queries of a tile of pixels,
    // whose blocks overlap: one pass over the box they span replaces a pass per block.
    // Allocation-free; safe for concurrent readers.
    template <class F>
    void forEachInBox(const std::array<int64_t, 3>& lo, const std::array<int64_t, 3>& hi, uint8_t facing, F&& f) const;

    // Tables keep occupancy bitmaps when fineCellsPerCoarseEdge is at most this: 32 KiB per table
    // at 64; beyond, a bitmap would outgrow the slots of the table it serves.
    static constexpr int kMaxOccupancyEdge = 64;
    // Bytes of one table's occupancy bitmap (0 without bitmaps).
    std::size_t occupancyBytesPerTable() const { return m_occupancyWords * sizeof(uint64_t); }

    struct Stats {
        std::size_t entries;        // keys stored
        std::size_t coarseTables;   // live second-level tables
        std::size_t capacitySlots;  // slots of the live tables
        std::size_t bytes;          // memory held by both levels, including tables kept for reuse and their bitmaps
        double loadFactor;          // entries / capacitySlots, 0 without tables
        uint64_t refusedInserts;    // inserts that returned Refused
        uint64_t evictions;         // inserts that returned Evicted
    };
    // Counters and sizes at the time of the call; O(1).
    Stats stats() const;

    // The configuration the grid was built with.
    const SparseHashGridConfig& config() const { return m_config; }

private:
    // Four second-level slots, 32 bytes: their keys, then their values, so that one SSE2 register
    // holds the four keys. A key is stored exactly, as the fine cell's offset inside its coarse cell
    // plus the facing tag: together with the table's coarse key that is the full fine key, so a
    // match is never a false hit. Aligned to 32 bytes, a bucket never straddles a cache line.
    struct alignas(32) Bucket {
        uint32_t locals[kBucketSlots];  // packLocal(...), kEmptyLocal or kBlockedLocal
        uint32_t values[kBucketSlots];
    };
    static_assert(sizeof(Bucket) == kBucketSlots * kBytesPerFineSlot);

    // Coarse coordinates are kept biased: the coarse cell's coordinate plus m_biasCells, modulo
    // 2^64. That is the quotient splitAxis's fast path computes, so a find subtracts nothing.

    // One first-level slot: a coarse cell (biased) and its table; `table` is null when the slot is empty.
    struct CoarseSlot {
        uint64_t x, y, z;
        Bucket* table;
        uint32_t index;    // position of the table in m_tables
        uint32_t buckets;  // the table's size
    };
    static_assert(sizeof(CoarseSlot) == 40);

    // A fine key split into its coarse cell (biased) and its packed offset inside it.
    struct SplitKey {
        uint64_t cx, cy, cz;
        uint32_t local;
    };

    // Offsets take kLocalBits bits per axis, the facing tag the 8 above them. An offset is below
    // kMaxFineCellsPerCoarseEdge, never all ones, so neither kEmptyLocal nor kBlockedLocal (whose y
    // and z offsets are all ones) ever equals a packed key. A blocked slot is one a table of
    // fineSlotsPerTable slots does not have (its last bucket's lanes past that count): never free,
    // never a match, and not the end of a probe run.
    static constexpr int kLocalBits = 8;
    static constexpr uint32_t kLocalMask = (uint32_t(1) << kLocalBits) - 1;
    static constexpr int kFacingShift = 3 * kLocalBits;
    static constexpr uint32_t kCellMask = (uint32_t(1) << kFacingShift) - 1;  // a packed key without its facing
    static constexpr uint32_t kEmptyLocal = ~uint32_t(0);
    static constexpr uint32_t kBlockedLocal = ~uint32_t(1);
    static_assert(kMaxFineCellsPerCoarseEdge <= int(kLocalMask));
    static constexpr uint64_t kFastDividendLimit = uint64_t(1) << 31;

    struct AxisSplit {
        uint64_t coarse;  // biased
        uint64_t offset;
    };
    // splitAxis's fast path, for a biased coordinate u = v + m_bias below kFastDividendLimit.
    AxisSplit splitBiased(uint64_t u) const {
        const uint64_t q = (u * m_divisorMagic) >> m_divisorShift;
        return {q, u - q * uint64_t(m_edge)};
    }
    AxisSplit splitAxis(int64_t v) const {
        // Fast path, for |v| up to about 2^30 cells: v + m_bias (a multiple of n) is a 31-bit
        // dividend, which a multiplication by ceil(2^F / n) and a shift divide exactly (Lemire,
        // Kaser & Kurz 2019, "Faster remainder by direct computation", theorem 1) at a fraction of
        // the cost of a 64-bit division. Unsigned addition keeps v near the int64 ends defined.
        const uint64_t u = uint64_t(v) + uint64_t(m_bias);
        if (u < kFastDividendLimit) return splitBiased(u);
        // Remainder and quotient of the truncating division, corrected towards -∞ without forming
        // quotient × n, which overflows near INT64_MIN.
        int64_t q = v / m_edge, r = v % m_edge;
        if (r < 0) {
            r += m_edge;
            --q;
        }
        return {uint64_t(q) + uint64_t(m_biasCells), uint64_t(r)};
    }
    static uint32_t packLocal(uint64_t ox, uint64_t oy, uint64_t oz, uint8_t facing) {
        return uint32_t(ox | oy << kLocalBits | oz << (2 * kLocalBits) | uint64_t(facing) << kFacingShift);
    }
    SplitKey split(const CellKey& key) const {
        // splitAxis's fast path tested once for the three axes: one branch per key, not three.
        const uint64_t bias = uint64_t(m_bias), ux = uint64_t(key.x) + bias, uy = uint64_t(key.y) + bias, uz = uint64_t(key.z) + bias;
        const bool fast = (ux | uy | uz) < kFastDividendLimit;
        const AxisSplit sx = fast ? splitBiased(ux) : splitAxis(key.x), sy = fast ? splitBiased(uy) : splitAxis(key.y),
                        sz = fast ? splitBiased(uz) : splitAxis(key.z);
        return {sx.coarse, sy.coarse, sz.coarse, packLocal(sx.offset, sy.offset, sz.offset, key.facing)};
    }
    CellKey unsplit(uint64_t cx, uint64_t cy, uint64_t cz, uint32_t local) const {
        // (coarse - m_biasCells) × n + offset is a valid int64 whenever it came from split();
        // unsigned arithmetic wraps through intermediate values that would overflow a signed product.
        const auto join = [&](uint64_t coarse, uint64_t offset) { return int64_t(coarse * uint64_t(m_edge) + offset - uint64_t(m_bias)); };
        return {join(cx, local & kLocalMask), join(cy, (local >> kLocalBits) & kLocalMask),
                join(cz, (local >> (2 * kLocalBits)) & kLocalMask), uint8_t(local >> (3 * kLocalBits))};
    }

    // Home bucket of a packed key: its 32-bit multiplicative hash (Knuth's × 2^32/φ), scaled to the
    // table size by Lemire's multiply-shift, which reads the hash's well-mixed top bits, so any
    // bucket count works without a modulo. The cells of planes and of a filled cube, as surfaces
    // produce, fill a table without refusals (test SurfacePatternsFillATableWithoutRefusals).
    static uint32_t homeOf(uint32_t local, uint32_t buckets) { return uint32_t((uint64_t(local * 0x9e3779b9u) * buckets) >> 32); }
    static uint32_t nextBucket(uint32_t b, uint32_t buckets) { return b + 1 == buckets ? 0 : b + 1; }
    static uint32_t bucketsFor(uint32_t slots) { return (slots + kBucketSlots - 1) / kBucketSlots; }
    // Buckets of a key's probe sequence in a table of `buckets` buckets.
    uint32_t probeBuckets(uint32_t buckets) const { return std::min(m_probeBuckets, buckets); }

    // First-level home of a coarse cell: the top bits of its hash, i.e. of its scaled coordinate
    // sum (the fold changes only its low 32 bits, which the first level would read only past 2^32
    // slots): two instructions fewer on every find's chain (find_pair, eight alternated runs:
    // medians 0.89 → 0.91× absl, faster in six of the eight pairs).
    std::size_t coarseHome(uint64_t cx, uint64_t cy, uint64_t cz) const {
        return std::size_t(scaledCoordinateSum(int64_t(cx), int64_t(cy), int64_t(cz)) >> m_coarseShift);
    }

    // Index of the first-level slot holding (cx, cy, cz), or of the empty slot that ends its probe
    // run. The first level always has empty slots, so the run ends.
    std::size_t coarseSlotIndex(uint64_t cx, uint64_t cy, uint64_t cz) const {
        std::size_t i = coarseHome(cx, cy, cz);
        // One test for the three coordinates: a branch each cost more than the comparisons.
        while (m_coarse[i].table && ((m_coarse[i].x ^ cx) | (m_coarse[i].y ^ cy) | (m_coarse[i].z ^ cz)) != 0) i = (i + 1) & m_coarseMask;
        return i;
    }
    const CoarseSlot& coarseSlotOf(uint64_t cx, uint64_t cy, uint64_t cz) const { return m_coarse[coarseSlotIndex(cx, cy, cz)]; }

    // Bit l set when lane l of `bucket` holds `local` (a key, kEmptyLocal or kBlockedLocal).
    static unsigned lanesHolding(const Bucket& bucket, uint32_t local) {
#ifdef __SSE2__  // every x86-64; elsewhere lane by lane
        const __m128i locals = _mm_load_si128(reinterpret_cast<const __m128i*>(bucket.locals));
        return unsigned(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(locals, _mm_set1_epi32(int(local))))));
#else
        unsigned lanes = 0;
        for (uint32_t l = 0; l < kBucketSlots; ++l) lanes |= unsigned(bucket.locals[l] == local) << l;
        return lanes;
#endif
    }

    // Where a key is stored: `bucket` is null when it is not.
    struct SlotRef {
        const Bucket* bucket;
        uint32_t lane;
    };
    // The slot of `local` in `table`. Keys live in the first bucket from their home that had a free
    // slot when they were inserted, and deletions keep it so (removeFine): every bucket between a
    // key's home and its own is full. So the search stops at the first bucket with a free slot. At
    // most half full, almost every key is in its home bucket: one aligned load and one comparison of
    // four keys, where probing from a home slot often had to look past a group of four slots, and
    // the group itself could straddle two cache lines (docs/performance.md, "Lookups").
    SlotRef locate(const Bucket* table, uint32_t buckets, uint32_t local) const {
        uint32_t b = homeOf(local, buckets);
        unsigned match = lanesHolding(table[b], local);
        // The home bucket apart: the loop's bookkeeping is for the rare key that overflowed it.
        for (uint32_t probe = probeBuckets(buckets); !match && --probe > 0 && !lanesHolding(table[b], kEmptyLocal);) {
            b = nextBucket(b, buckets);
            match = lanesHolding(table[b], local);
        }
        if (!match) return {nullptr, 0};
        return {table + b, uint32_t(std::countr_zero(match))};
    }
    std::optional<uint32_t> findValue(const Bucket* table, uint32_t buckets, uint32_t local) const {
        const SlotRef slot = locate(table, buckets, local);
        if (!slot.bucket) return std::nullopt;
        return slot.bucket->values[slot.lane];
    }

    // Occupancy: bit ox + n (oy + n oz) of a table's bitmap is set exactly when the table holds a
    // key of fine cell (ox, oy, oz) with some facing tag. Rows run along x, so the cells of a row
    // of a block are consecutive bits; the padding word lets occupiedRun read two words anywhere.
    struct Occupancy {
        std::unique_ptr<uint64_t[]> cells;  // m_occupancyWords words, null without bitmaps
        uint64_t facings[4];                // bit t: a key of tag t was stored since the table was (re)created
    };
    uint64_t occupancyBit(uint64_t ox, uint64_t oy, uint64_t oz) const { return ox + uint64_t(m_edge) * (oy + uint64_t(m_edge) * oz); }
    uint64_t occupancyBit(uint32_t local) const {
        return occupancyBit(local & kLocalMask, (local >> kLocalBits) & kLocalMask, (local >> (2 * kLocalBits)) & kLocalMask);
    }
    // Bits first .. first + length - 1 (length <= 57) of `cells` as the low bits of the result; all
    // set when there is no bitmap, so that every cell is probed.
    static uint64_t occupiedRun(const uint64_t* cells, uint64_t first, int length) {
        const uint64_t run = (uint64_t(1) << length) - 1;
        if (!cells) return run;
        const uint64_t word = first / 64;
        const int shift = int(first % 64);
        // The second word's bits above the first's; shifted in two steps, so shift 0 stays defined.
        return ((cells[word] >> shift) | (cells[word + 1] << 1 << (63 - shift))) & run;
    }
    // forEachInBlock (innerFirst false: one pass, `outer` unused) and forEachInBlockInnerFirst.
    template <class F, class Outer>
    void walkBlock(const CellKey& key, int rings, F& f, bool innerFirst, Outer&& outer) const;

    // Records the key `local` just stored in table `index`.
    void markOccupied(uint32_t index, uint32_t local);
    // After the key `local` left the table of `coarse`: clears its cell unless a key of another
    // facing tag holds it (looked up for the tags the table has held).
    void unmarkOccupied(const CoarseSlot& coarse, uint32_t local);

    // Makes a cleared table for coarse cell (cx, cy, cz), reusing a released one when there is one,
    // and returns its first-level slot. The caller checked maxCoarseTables.
    CoarseSlot& createTable(uint64_t cx, uint64_t cy, uint64_t cz);
    // Marks the first `slots` slots of `table` free and the rest of its last bucket blocked.
    static void clearTable(Bucket* table, uint32_t slots);
    // Doubles the table of `coarse` (up to fineSlotsPerTable) and moves its keys; false, with
    // nothing changed, when it is at its largest or a key would land beyond its probe sequence.
    bool growTable(CoarseSlot& coarse);
    // Doubles the first level so it stays at most 1/16 full.
    void growCoarse();
    // Empties lane `lane` of bucket `bucket` of a table / the slot `hole` of the first level,
    // keeping every other key findable.
    void removeFine(const CoarseSlot& coarse, uint32_t bucket, uint32_t lane);
    void removeCoarse(std::size_t hole);

    SparseHashGridConfig m_config;
    LastUsedOf m_lastUsedOf;
    int64_t m_edge;           // fineCellsPerCoarseEdge
    // splitAxis's exact division of 31-bit dividends by m_edge: with L = ceil(log2 n) and
    // F = 31 + L, magic = ceil(2^F / n) < 2^32, so dividend × magic < 2^63.
    uint64_t m_divisorMagic;
    int m_divisorShift;
    // The fast path covers coordinates in [-m_bias, 2^31 - m_bias).
    int64_t m_biasCells;      // 2^30 / n
    int64_t m_bias;           // m_biasCells × n
    uint32_t m_maxSlots;      // fineSlotsPerTable
    uint32_t m_probeBuckets;  // maxProbeLength in buckets, rounded up
    // First level, 2^k slots kept at most 1/16 full, so that almost every coarse lookup
    // finds its cell in the first slot it reads: a second probe costs a branch misprediction.
    std::vector<CoarseSlot> m_coarse;
    std::size_t m_coarseMask;  // 2^k - 1
    int m_coarseShift;         // 64 - k
    std::vector<std::unique_ptr<Bucket[]>> m_tables;    // second level, live and reusable
    std::vector<uint32_t> m_tableSlots;                 // slots of each table of m_tables (not counting blocked ones)
    std::vector<uint32_t> m_tableEntries;               // keys stored per table of m_tables
    std::vector<uint32_t> m_freeTables;                 // indices of empty tables kept for reuse
    std::vector<Occupancy> m_occupancy;                 // bitmap of each table of m_tables
    std::size_t m_occupancyWords;                       // per bitmap: ⌈n³ / 64⌉ + 1, or 0 without bitmaps
    std::size_t m_entries = 0;
    uint64_t m_refusedInserts = 0;
    uint64_t m_evictions = 0;
};

inline std::optional<uint32_t> SparseHashGrid::find(const CellKey& key) const {
    const SplitKey s = split(key);
    const CoarseSlot& coarse = coarseSlotOf(s.cx, s.cy, s.cz);
    if (!coarse.table) return std::nullopt;
    return findValue(coarse.table, coarse.buckets, s.local);
}

template <class F>
void SparseHashGrid::forEachNeighbour(const CellKey& key, F&& f) const {
    forEachInBlock(key, 1, f);
}

template <class F, class Outer>
void SparseHashGrid::walkBlock(const CellKey& key, int rings, F& f, bool innerFirst, Outer&& outer) const {
    constexpr int kWidth = 2 * kMaxBlockRings + 1;
    rings = std::clamp(rings, 0, kMaxBlockRings);
    // Per axis and offset -rings..rings: the fine coordinate, its offset inside its coarse cell, and
    // which of the axis's distinct coarse coordinates it lies in.
    struct Axis {
        int64_t fine[kWidth];
        uint64_t offset[kWidth];
        int coarseId[kWidth];
        uint64_t coarse[kWidth];
        bool valid[kWidth];  // the coordinate fits in int64
        int coarseCount;
    };
    const auto axis = [this, rings](int64_t v) {
        Axis a;  // not zero-filled: entries are read only where valid, and this runs per query
        a.coarseCount = 0;
        for (int d = -rings; d <= rings; ++d) {
            const int i = d + rings;
            a.valid[i] = d < 0 ? v >= std::numeric_limits<int64_t>::min() - d : v <= std::numeric_limits<int64_t>::max() - d;
            if (!a.valid[i]) continue;
            a.fine[i] = v + d;
            const AxisSplit c = splitAxis(a.fine[i]);
            a.offset[i] = c.offset;
            int id = 0;
            while (id < a.coarseCount && a.coarse[id] != c.coarse) ++id;
            if (id == a.coarseCount) a.coarse[a.coarseCount++] = c.coarse;
            a.coarseId[i] = id;
        }
        return a;
    };
    const Axis ax = axis(key.x), ay = axis(key.y), az = axis(key.z);

    // Each distinct coarse cell's table, size and bitmap, copied out of the first level once.
    struct Table {
        const Bucket* buckets;
        uint32_t size;
        const uint64_t* occupancy;
    };
    Table tables[kWidth][kWidth][kWidth];
    for (int i = 0; i < ax.coarseCount; ++i)
        for (int j = 0; j < ay.coarseCount; ++j)
            for (int k = 0; k < az.coarseCount; ++k) {
                const CoarseSlot& coarse = coarseSlotOf(ax.coarse[i], ay.coarse[j], az.coarse[k]);
                tables[i][j][k] = {coarse.table, coarse.buckets, coarse.table ? m_occupancy[coarse.index].cells.get() : nullptr};
            }

    const int width = 2 * rings + 1;
    const auto visitRun = [&](const Table& table, uint64_t cells, int first, int j, int k) {
        for (; cells; cells &= cells - 1) {
            const int i = first + std::countr_zero(cells);
            const SlotRef slot = locate(table.buckets, table.size, packLocal(ax.offset[i], ay.offset[j], az.offset[k], key.facing));
            if (slot.bucket) f(CellKey{ax.fine[i], ay.fine[j], az.fine[k], key.facing}, slot.bucket->values[slot.lane]);
        }
    };
    // The row's offsets along x split into runs of valid cells inside one coarse cell each (one
    // per coarse cell the block crosses), found once for every row of both passes.
    struct XRun {
        int first, length;
        uint64_t bits;  // `length` low bits
    };
    XRun xRuns[kWidth];
    int xRunCount = 0;
    for (int i = 0; i < width;) {
        if (!ax.valid[i]) {
            ++i;
            continue;
        }
        int end = i + 1;
        while (end < width && ax.valid[end] && ax.coarseId[end] == ax.coarseId[i]) ++end;
        xRuns[xRunCount++] = {i, end - i, (uint64_t(1) << (end - i)) - 1};
        i = end;
    }
    // A pass visits the rows j of y0..y1 and k of z0..z1, and of row (j, k) the cells whose bits
    // are set in cellsOf(j, k).
    const uint64_t wholeRow = (uint64_t(1) << width) - 1;
    const auto innerCells = [rings](int j, int k) {
        return std::abs(j - rings) <= 1 && std::abs(k - rings) <= 1 ? uint64_t(7) << (rings - 1) : uint64_t(0);
    };
    const auto pass = [&](int y0, int y1, int z0, int z1, auto&& cellsOf) {
        // Mostly the block lies inside one coarse cell: its rows are runs of one bitmap at a fixed
        // stride (n bits per row, n² per layer).
        if (ax.coarseCount == 1 && ay.coarseCount == 1 && az.coarseCount == 1 && ax.valid[0] && ax.valid[width - 1] && ay.valid[0] &&
            ay.valid[width - 1] && az.valid[0] && az.valid[width - 1]) {
            const Table& table = tables[0][0][0];
            if (!table.buckets) return;
            const uint64_t first = occupancyBit(ax.offset[0], ay.offset[0], az.offset[0]);
            const uint64_t rowStride = uint64_t(m_edge), layerStride = rowStride * rowStride;
            for (int k = z0; k <= z1; ++k)
                for (int j = y0; j <= y1; ++j)
                    visitRun(table, occupiedRun(table.occupancy, first + uint64_t(j) * rowStride + uint64_t(k) * layerStride, width) & cellsOf(j, k), 0, j, k);
            return;
        }
        // Otherwise row by row; a row's cells inside one coarse cell are consecutive bits of its
        // bitmap (a run of xRuns), read at once unless the pass wants none of them, and only the
        // occupied ones are asked about and looked up.
        for (int k = z0; k <= z1; ++k)
            for (int j = y0; j <= y1; ++j) {
                if (!ay.valid[j] || !az.valid[k]) continue;
                const uint64_t cells = cellsOf(j, k);
                for (int r = 0; r < xRunCount; ++r) {
                    const XRun& run = xRuns[r];
                    const uint64_t wanted = (cells >> run.first) & run.bits;
                    if (!wanted) continue;
                    const Table& table = tables[ax.coarseId[run.first]][ay.coarseId[j]][az.coarseId[k]];
                    if (table.buckets)
                        visitRun(table, occupiedRun(table.occupancy, occupancyBit(ax.offset[run.first], ay.offset[j], az.offset[k]), run.length) & wanted,
                                 run.first, j, k);
                }
            }
    };
    if (!innerFirst || rings <= 1) return pass(0, width - 1, 0, width - 1, [wholeRow](int, int) { return wholeRow; });
    pass(rings - 1, rings + 1, rings - 1, rings + 1, innerCells);
    const BlockBox box = outer();
    int from[3], to[3];  // as indices 0..width - 1
    for (int a = 0; a < 3; ++a) {
        from[a] = std::max(box.from[a], -rings) + rings;
        to[a] = std::min(box.to[a], rings) + rings;
        if (from[a] > to[a]) return;
    }
    const uint64_t rowCells = ((uint64_t(1) << (to[0] + 1)) - 1) & ~((uint64_t(1) << from[0]) - 1);
    pass(from[1], to[1], from[2], to[2], [&](int j, int k) { return rowCells & ~innerCells(j, k); });
}

template <class F>
void SparseHashGrid::forEachInBox(const std::array<int64_t, 3>& lo, const std::array<int64_t, 3>& hi, uint8_t facing, F&& f) const {
    const AxisSplit first[3] = {splitAxis(lo[0]), splitAxis(lo[1]), splitAxis(lo[2])};
    const AxisSplit last[3] = {splitAxis(hi[0]), splitAxis(hi[1]), splitAxis(hi[2])};
    const uint64_t edge = uint64_t(m_edge);
    // The box's offsets inside coarse coordinate c of axis a.
    const auto from = [&](int a, uint64_t c) { return c == first[a].coarse ? first[a].offset : 0; };
    const auto to = [&](int a, uint64_t c) { return c == last[a].coarse ? last[a].offset : edge - 1; };
    // Coarse coordinates (biased) of the box on axis a, up to the last one included, counted modulo
    // 2^64 as the bias is.
    const auto forEachCoarse = [&](int a, auto&& visit) {
        for (uint64_t c = first[a].coarse;; ++c) {
            visit(c);
            if (c == last[a].coarse) break;
        }
    };
    forEachCoarse(2, [&](uint64_t cz) {
        forEachCoarse(1, [&](uint64_t cy) {
            forEachCoarse(0, [&](uint64_t cx) {
                const CoarseSlot& coarse = coarseSlotOf(cx, cy, cz);
                if (!coarse.table) return;
                const uint64_t* occupancy = m_occupancy[coarse.index].cells.get();
                const uint64_t x0 = from(0, cx), x1 = to(0, cx);
                for (uint64_t oz = from(2, cz); oz <= to(2, cz); ++oz)
                    for (uint64_t oy = from(1, cy); oy <= to(1, cy); ++oy)
                        // A row's cells are consecutive bits, read at most 57 at a time.
                        for (uint64_t run = x0; run <= x1; run += 57) {
                            const int length = int(std::min<uint64_t>(57, x1 - run + 1));
                            for (uint64_t cells = occupiedRun(occupancy, occupancyBit(run, oy, oz), length); cells; cells &= cells - 1) {
                                const uint64_t ox = run + uint64_t(std::countr_zero(cells));
                                const uint32_t local = packLocal(ox, oy, oz, facing);
                                const SlotRef slot = locate(coarse.table, coarse.buckets, local);
                                if (slot.bucket) f(unsplit(cx, cy, cz, local), slot.bucket->values[slot.lane]);
                            }
                        }
            });
        });
    });
}

}  // namespace gibench
