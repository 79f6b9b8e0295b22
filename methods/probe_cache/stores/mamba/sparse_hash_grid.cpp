#include "methods/probe_cache/stores/mamba/sparse_hash_grid.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

// hashCellKey: each coordinate and the tag are scaled by a distinct odd constant and summed modulo
// 2^64 (a sum, not a xor, under which small negative coordinates collide), then the high half is
// folded onto the low half. The top bits of a product depend on every input bit, which suits
// tables indexed by top bits (the first level uses them); the fold gives the low bits the same,
// for maps that take a tag from them (absl::flat_hash_map). One multiply per coordinate instead of
// a full finaliser keeps every lookup's dependency chain short, and MAMBA's keys are regular
// (planes and rows of cells), which multiplicative hashing spreads evenly.

namespace gibench {
namespace {

constexpr int kInitialCoarseBits = 6;
constexpr std::size_t kCoarseSparsity = 16;

template <class T>
std::string invalidField(const char* field, const std::string& range, T got) {
    std::ostringstream s;
    s << "SparseHashGrid: " << field << " must be " << range << ", got " << got;
    return s.str();
}

}  // namespace

SparseHashGrid::SparseHashGrid(const SparseHashGridConfig& config, LastUsedOf lastUsedOf)
    : m_config(config),
      m_lastUsedOf(std::move(lastUsedOf)),
      m_edge(config.fineCellsPerCoarseEdge),
      m_maxSlots(config.fineSlotsPerTable),
      m_probeBuckets(bucketsFor(config.maxProbeLength)),
      m_coarse(std::size_t(1) << kInitialCoarseBits, CoarseSlot{0, 0, 0, nullptr, 0, 0}),
      m_coarseMask(m_coarse.size() - 1),
      m_coarseShift(64 - kInitialCoarseBits) {
    if (!(std::isfinite(config.fineCellSize) && config.fineCellSize > 0.0))
        throw std::invalid_argument(invalidField("fineCellSize", "finite and > 0", config.fineCellSize));
    if (config.fineCellsPerCoarseEdge < 1 || config.fineCellsPerCoarseEdge > kMaxFineCellsPerCoarseEdge)
        throw std::invalid_argument(invalidField("fineCellsPerCoarseEdge", "in [1, " + std::to_string(kMaxFineCellsPerCoarseEdge) + "]",
                                                 config.fineCellsPerCoarseEdge));
    if (config.maxCoarseTables < 1) throw std::invalid_argument(invalidField("maxCoarseTables", ">= 1", config.maxCoarseTables));
    if (config.fineSlotsPerTable < 1) throw std::invalid_argument(invalidField("fineSlotsPerTable", ">= 1", config.fineSlotsPerTable));
    if (config.maxProbeLength < 1 || config.maxProbeLength > config.fineSlotsPerTable)
        throw std::invalid_argument(invalidField("maxProbeLength", "in [1, fineSlotsPerTable = " + std::to_string(config.fineSlotsPerTable) + "]",
                                                 config.maxProbeLength));
    if (config.policy == FullPolicy::EvictLeastRecentlyUsed && !m_lastUsedOf)
        throw std::invalid_argument("SparseHashGrid: LRU eviction needs the entries' last use (lastUsedOf), got none");
    int ceilLog2 = 0;
    while ((int64_t(1) << ceilLog2) < m_edge) ++ceilLog2;
    m_divisorShift = 31 + ceilLog2;
    m_divisorMagic = ((uint64_t(1) << m_divisorShift) + uint64_t(m_edge) - 1) / uint64_t(m_edge);
    m_biasCells = (int64_t(1) << 30) / m_edge;
    m_bias = m_biasCells * m_edge;
    const uint64_t cells = uint64_t(m_edge) * uint64_t(m_edge) * uint64_t(m_edge);
    m_occupancyWords = m_edge <= kMaxOccupancyEdge ? std::size_t((cells + 63) / 64 + 1) : 0;
}

CellKey SparseHashGrid::keyOf(const vec3& position, uint8_t facingTag) const {
    if (const std::optional<CellKey> key = tryKeyOf(position, facingTag)) return *key;
    std::ostringstream s;
    s << "SparseHashGrid::keyOf: position (" << position.x << ", " << position.y << ", " << position.z << ")";
    if (!isFinite(position)) throw std::invalid_argument(s.str() + " is not finite");
    s << " has a cell coordinate outside the int64 range at fineCellSize " << m_config.fineCellSize;
    throw std::out_of_range(s.str());
}

CellKey SparseHashGrid::coarseOf(const CellKey& fine) const {
    const auto coarse = [&](int64_t v) { return int64_t(splitAxis(v).coarse - uint64_t(m_biasCells)); };
    return {coarse(fine.x), coarse(fine.y), coarse(fine.z), 0};
}

InsertOutcome SparseHashGrid::insert(const CellKey& key, uint32_t value) {
    const SplitKey s = split(key);
    CoarseSlot* coarse = &m_coarse[coarseSlotIndex(s.cx, s.cy, s.cz)];
    if (!coarse->table) {
        if (m_tables.size() - m_freeTables.size() >= m_config.maxCoarseTables) {
            ++m_refusedInserts;
            return {InsertOutcome::Status::Refused, 0, 0, {}};
        }
        coarse = &createTable(s.cx, s.cy, s.cz);
    }

    for (;;) {
        Bucket* table = coarse->table;
        uint32_t b = homeOf(s.local, coarse->buckets);
        bool runFull = true;
        for (uint32_t probe = probeBuckets(coarse->buckets); probe > 0; --probe, b = nextBucket(b, coarse->buckets)) {
            if (const unsigned match = lanesHolding(table[b], s.local))
                return {InsertOutcome::Status::Existing, table[b].values[std::countr_zero(match)], 0, {}};
            if (lanesHolding(table[b], kEmptyLocal)) {
                runFull = false;
                break;
            }
        }
        // A table passing half full, or whose run for this key is full, grows first.
        const bool crowded = 2 * (uint64_t(m_tableEntries[coarse->index]) + 1) > m_tableSlots[coarse->index];
        if ((runFull || crowded) && growTable(*coarse)) continue;
        if (runFull) break;
        const uint32_t lane = uint32_t(std::countr_zero(lanesHolding(table[b], kEmptyLocal)));
        table[b].locals[lane] = s.local;
        table[b].values[lane] = value;
        markOccupied(coarse->index, s.local);
        ++m_entries;
        ++m_tableEntries[coarse->index];
        return {InsertOutcome::Status::Inserted, value, 0, {}};
    }

    if (m_config.policy == FullPolicy::Refuse) {
        ++m_refusedInserts;
        return {InsertOutcome::Status::Refused, 0, 0, {}};
    }
    // The replaced slot stays occupied, so no other key's probe run is broken.
    Bucket* table = coarse->table;
    Bucket* oldest = nullptr;
    uint32_t oldestLane = 0, oldestUse = 0;
    uint32_t b = homeOf(s.local, coarse->buckets);
    for (uint32_t probe = probeBuckets(coarse->buckets); probe > 0; --probe, b = nextBucket(b, coarse->buckets))
        for (uint32_t lane = 0; lane < kBucketSlots; ++lane) {
            if (table[b].locals[lane] == kBlockedLocal) continue;
            const uint32_t use = m_lastUsedOf(table[b].values[lane]);
            if (!oldest || use < oldestUse) {
                oldest = table + b;
                oldestLane = lane;
                oldestUse = use;
            }
        }
    const uint32_t droppedLocal = oldest->locals[oldestLane], droppedValue = oldest->values[oldestLane];
    oldest->locals[oldestLane] = s.local;
    oldest->values[oldestLane] = value;
    markOccupied(coarse->index, s.local);
    unmarkOccupied(*coarse, droppedLocal);
    ++m_evictions;
    return {InsertOutcome::Status::Evicted, value, droppedValue, unsplit(s.cx, s.cy, s.cz, droppedLocal)};
}

bool SparseHashGrid::erase(const CellKey& key) {
    const SplitKey s = split(key);
    const std::size_t coarseIndex = coarseSlotIndex(s.cx, s.cy, s.cz);
    const CoarseSlot& coarse = m_coarse[coarseIndex];
    if (!coarse.table) return false;
    const SlotRef slot = locate(coarse.table, coarse.buckets, s.local);
    if (!slot.bucket) return false;
    removeFine(coarse, uint32_t(slot.bucket - coarse.table), slot.lane);
    unmarkOccupied(coarse, s.local);
    --m_entries;
    const uint32_t index = m_coarse[coarseIndex].index;
    if (--m_tableEntries[index] == 0) {
        m_freeTables.push_back(index);
        removeCoarse(coarseIndex);
    }
    return true;
}

SparseHashGrid::Stats SparseHashGrid::stats() const {
    const std::size_t live = m_tables.size() - m_freeTables.size();
    std::size_t capacity = 0, allBuckets = 0;
    for (std::size_t t = 0; t < m_tables.size(); ++t) {
        allBuckets += bucketsFor(m_tableSlots[t]);
        if (m_tableEntries[t] > 0) capacity += m_tableSlots[t];
    }
    const std::size_t bytes = m_coarse.capacity() * sizeof(CoarseSlot) + allBuckets * sizeof(Bucket) +
                              m_tables.capacity() * sizeof(m_tables[0]) + m_occupancy.capacity() * sizeof(Occupancy) +
                              m_tables.size() * m_occupancyWords * sizeof(uint64_t) +
                              (m_tableSlots.capacity() + m_tableEntries.capacity() + m_freeTables.capacity()) * sizeof(uint32_t);
    return {m_entries, live, capacity, bytes, capacity ? double(m_entries) / double(capacity) : 0.0, m_refusedInserts, m_evictions};
}

SparseHashGrid::CoarseSlot& SparseHashGrid::createTable(uint64_t cx, uint64_t cy, uint64_t cz) {
    const std::size_t live = m_tables.size() - m_freeTables.size();
    if ((live + 1) * kCoarseSparsity > m_coarse.size()) growCoarse();
    uint32_t index;
    if (!m_freeTables.empty()) {
        index = m_freeTables.back();
        m_freeTables.pop_back();
    } else {
        // Everything that can throw comes before the first change, so a failed allocation leaves the
        // grid as it was; the reservation also means releasing a table never allocates, so erase
        // cannot throw.
        const uint32_t slots = std::min(kInitialFineSlots, m_maxSlots);
        auto storage = std::make_unique_for_overwrite<Bucket[]>(bucketsFor(slots));
        auto cells = m_occupancyWords ? std::make_unique<uint64_t[]>(m_occupancyWords) : nullptr;
        m_tableSlots.reserve(m_tables.size() + 1);
        m_tableEntries.reserve(m_tables.size() + 1);
        m_freeTables.reserve(m_tables.size() + 1);
        m_occupancy.reserve(m_tables.size() + 1);
        index = uint32_t(m_tables.size());
        m_tables.push_back(std::move(storage));
        m_tableSlots.push_back(slots);
        m_tableEntries.push_back(0);
        m_occupancy.push_back({std::move(cells), {}});
    }
    // A released table's bitmap is clear already (every key's removal cleared its cell); the
    // facings it held are forgotten, so that removals probe only the tags stored from now on.
    std::fill_n(m_occupancy[index].facings, 4, uint64_t(0));
    Bucket* table = m_tables[index].get();
    clearTable(table, m_tableSlots[index]);
    CoarseSlot& coarse = m_coarse[coarseSlotIndex(cx, cy, cz)];
    coarse = {cx, cy, cz, table, index, bucketsFor(m_tableSlots[index])};
    return coarse;
}

void SparseHashGrid::clearTable(Bucket* table, uint32_t slots) {
    const uint32_t buckets = bucketsFor(slots);
    for (uint32_t b = 0; b < buckets; ++b)
        for (uint32_t lane = 0; lane < kBucketSlots; ++lane) table[b].locals[lane] = kBucketSlots * b + lane < slots ? kEmptyLocal : kBlockedLocal;
}

bool SparseHashGrid::growTable(CoarseSlot& coarse) {
    const uint32_t oldSlots = m_tableSlots[coarse.index];
    if (oldSlots == m_maxSlots) return false;
    const uint32_t slots = uint32_t(std::min<uint64_t>(2 * uint64_t(oldSlots), m_maxSlots)), buckets = bucketsFor(slots);
    auto grown = std::make_unique_for_overwrite<Bucket[]>(buckets);
    clearTable(grown.get(), slots);
    for (uint32_t from = 0; from < coarse.buckets; ++from)
        for (uint32_t fromLane = 0; fromLane < kBucketSlots; ++fromLane) {
            const uint32_t local = coarse.table[from].locals[fromLane];
            if (local == kEmptyLocal || local == kBlockedLocal) continue;
            uint32_t b = homeOf(local, buckets), probe = probeBuckets(buckets);
            unsigned free = 0;
            for (; probe > 0 && !(free = lanesHolding(grown[b], kEmptyLocal)); --probe) b = nextBucket(b, buckets);
            // A key that would land beyond its probe sequence could not be found: keep the old table.
            if (!free) return false;
            const uint32_t lane = uint32_t(std::countr_zero(free));
            grown[b].locals[lane] = local;
            grown[b].values[lane] = coarse.table[from].values[fromLane];
        }
    coarse.table = grown.get();
    coarse.buckets = buckets;
    m_tableSlots[coarse.index] = slots;
    m_tables[coarse.index] = std::move(grown);
    return true;
}

void SparseHashGrid::markOccupied(uint32_t index, uint32_t local) {
    Occupancy& occupancy = m_occupancy[index];
    if (!occupancy.cells) return;
    const uint64_t bit = occupancyBit(local), facing = local >> kFacingShift;
    occupancy.cells[bit / 64] |= uint64_t(1) << (bit % 64);
    occupancy.facings[facing / 64] |= uint64_t(1) << (facing % 64);
}

void SparseHashGrid::unmarkOccupied(const CoarseSlot& coarse, uint32_t local) {
    Occupancy& occupancy = m_occupancy[coarse.index];
    if (!occupancy.cells) return;
    for (uint64_t word = 0; word < 4; ++word)
        for (uint64_t tags = occupancy.facings[word]; tags; tags &= tags - 1) {
            const uint64_t facing = 64 * word + uint64_t(std::countr_zero(tags));
            if (locate(coarse.table, coarse.buckets, (local & kCellMask) | uint32_t(facing) << kFacingShift).bucket) return;
        }
    const uint64_t bit = occupancyBit(local);
    occupancy.cells[bit / 64] &= ~(uint64_t(1) << (bit % 64));
}

void SparseHashGrid::growCoarse() {
    std::vector<CoarseSlot> old(m_coarse.size() * 2, CoarseSlot{0, 0, 0, nullptr, 0, 0});
    old.swap(m_coarse);
    m_coarseMask = m_coarse.size() - 1;
    --m_coarseShift;
    for (const CoarseSlot& s : old)
        if (s.table) m_coarse[coarseSlotIndex(s.x, s.y, s.z)] = s;
}

void SparseHashGrid::removeFine(const CoarseSlot& coarse, uint32_t bucket, uint32_t lane) {
    // Backward shift, by buckets: a bucket with a free slot ends every probe run through it, so a
    // bucket that was full and now has a hole takes in a key from further along whose home lies at
    // or before the hole's bucket; the slot that key left is the next hole. A key more than
    // probeBuckets - 1 buckets past the hole has its home past the hole, and a bucket that had a
    // free slot already ends every run that could need the hole: the scan stops at either.
    Bucket* table = coarse.table;
    const uint32_t buckets = coarse.buckets, span = probeBuckets(buckets);
    const bool wasFull = !lanesHolding(table[bucket], kEmptyLocal);
    table[bucket].locals[lane] = kEmptyLocal;
    if (!wasFull) return;
    uint32_t hole = bucket, holeLane = lane, j = bucket;
    for (uint32_t gap = 1; gap < span; ++gap) {
        j = nextBucket(j, buckets);
        const bool full = !lanesHolding(table[j], kEmptyLocal);
        for (uint32_t l = 0; l < kBucketSlots; ++l) {
            const uint32_t local = table[j].locals[l];
            if (local == kEmptyLocal || local == kBlockedLocal) continue;
            const uint32_t home = homeOf(local, buckets);
            if ((j >= home ? j - home : j + buckets - home) < gap) continue;
            table[hole].locals[holeLane] = local;
            table[hole].values[holeLane] = table[j].values[l];
            table[j].locals[l] = kEmptyLocal;
            if (!full) return;
            hole = j;
            holeLane = l;
            gap = 0;
            break;
        }
        if (!full) return;
    }
}

void SparseHashGrid::removeCoarse(std::size_t hole) {
    // Backward-shift deletion as in removeFine, without a probe bound: the first level always has
    // empty slots, one of which ends the scan.
    m_coarse[hole].table = nullptr;
    for (std::size_t j = (hole + 1) & m_coarseMask; m_coarse[j].table; j = (j + 1) & m_coarseMask) {
        const CoarseSlot& s = m_coarse[j];
        const std::size_t home = coarseHome(s.x, s.y, s.z);
        if (((j - home) & m_coarseMask) >= ((j - hole) & m_coarseMask)) {
            m_coarse[hole] = s;
            m_coarse[j].table = nullptr;
            hole = j;
        }
    }
}

}  // namespace gibench
