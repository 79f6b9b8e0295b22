#include "methods/probe_cache/stores/mamba/sparse_hash_grid.h"

#include "core/util/rng.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <map>
#include <ostream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

namespace gibench {

// Printed by GoogleTest when a comparison of keys fails.
void PrintTo(const CellKey& k, std::ostream* os) { *os << "(" << k.x << ", " << k.y << ", " << k.z << " | " << int(k.facing) << ")"; }

namespace {

using Status = InsertOutcome::Status;

std::string str(const CellKey& k) {
    std::ostringstream s;
    PrintTo(k, &s);
    return s.str();
}

struct KeyLess {
    bool operator()(const CellKey& a, const CellKey& b) const {
        return std::tie(a.x, a.y, a.z, a.facing) < std::tie(b.x, b.y, b.z, b.facing);
    }
};
using KeySet = std::set<CellKey, KeyLess>;
template <class T>
using KeyMap = std::map<CellKey, T, KeyLess>;

int64_t uniformInt(Rng& rng, int64_t lo, int64_t hi) { return lo + int64_t(rng.next() % uint32_t(hi - lo)); }

CellKey randomKey(Rng& rng, int64_t lo, int64_t hi) {
    return {uniformInt(rng, lo, hi), uniformInt(rng, lo, hi), uniformInt(rng, lo, hi), uint8_t(rng.next() % 7)};
}

// A grid with its owner's record of when each value was last used, kept as MambaStore keeps it:
// insert(key, value, frame) and touch(key, frame) stamp the value stored for the key with the frame.
class TestGrid : public SparseHashGrid {
public:
    explicit TestGrid(const SparseHashGridConfig& c) : SparseHashGrid(c, [this](uint32_t value) { return lastUsed(value); }) {}
    TestGrid(const TestGrid&) = delete;  // the grid asks this object
    TestGrid& operator=(const TestGrid&) = delete;

    InsertOutcome insert(const CellKey& k, uint32_t value, uint32_t frame) {
        const InsertOutcome o = SparseHashGrid::insert(k, value);
        if (o.status != InsertOutcome::Status::Refused) m_lastUsed[o.value] = frame;
        return o;
    }
    bool touch(const CellKey& k, uint32_t frame) {
        const std::optional<uint32_t> value = find(k);
        if (value) m_lastUsed[*value] = frame;
        return value.has_value();
    }

private:
    uint32_t lastUsed(uint32_t value) const {
        const auto it = m_lastUsed.find(value);
        return it == m_lastUsed.end() ? 0u : it->second;
    }
    std::unordered_map<uint32_t, uint32_t> m_lastUsed;
};

SparseHashGridConfig tinyConfig(uint32_t tables, uint32_t slots, uint32_t probeLength, FullPolicy policy) {
    SparseHashGridConfig c;
    c.maxCoarseTables = tables;
    c.fineSlotsPerTable = slots;
    c.maxProbeLength = probeLength;
    c.policy = policy;
    return c;
}

std::string constructionError(const SparseHashGridConfig& c, LastUsedOf lastUsedOf = [](uint32_t) { return 0u; }) {
    try {
        SparseHashGrid grid(c, std::move(lastUsedOf));
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "no error";
}

// Inserts random keys of [lo, hi]³ until `count` distinct ones are in, each with the number of
// distinct keys before it as its value; returns them. Within the grid's capacity every insert must
// report Inserted, or Existing with the first value for a repeat.
KeyMap<uint32_t> insertRandomKeys(TestGrid& grid, Rng& rng, std::size_t count, int64_t lo, int64_t hi) {
    KeyMap<uint32_t> inserted;
    while (inserted.size() < count) {
        const CellKey k = randomKey(rng, lo, hi);
        const InsertOutcome o = grid.insert(k, uint32_t(inserted.size()), 0);
        const auto [it, added] = inserted.emplace(k, uint32_t(inserted.size()));
        EXPECT_EQ(o.status, added ? Status::Inserted : Status::Existing) << str(k);
        EXPECT_EQ(o.value, it->second) << str(k);
    }
    return inserted;
}

TEST(SparseHashGrid, InsertedKeysAreFoundWithTheirValuesAndAbsentKeysAreNot) {
    // 100k keys over 4³ coarse cells, well inside the default capacity: nothing may be refused.
    TestGrid grid(SparseHashGridConfig{});
    Rng rng(1, 1);
    const KeyMap<uint32_t> expected = insertRandomKeys(grid, rng, 100000, -50, 50);
    for (const auto& [k, v] : expected) {
        const std::optional<uint32_t> found = grid.find(k);
        ASSERT_TRUE(found.has_value()) << str(k);
        ASSERT_EQ(*found, v) << str(k);
    }
    int absent = 0;
    while (absent < 100000) {
        const CellKey k = randomKey(rng, -60, 60);
        if (expected.count(k)) continue;
        ++absent;
        ASSERT_FALSE(grid.find(k).has_value()) << str(k);
    }
    const SparseHashGrid::Stats s = grid.stats();
    EXPECT_EQ(s.entries, expected.size());
    EXPECT_EQ(s.coarseTables, 64u);
    EXPECT_EQ(s.refusedInserts, 0u);
    EXPECT_EQ(s.evictions, 0u);
}

TEST(SparseHashGrid, ValuesThatLookLikeKeysOrEmptySlotsAreOnlyValues) {
    // A slot holds a packed key (8 bits per offset inside the coarse cell, the tag above them; all
    // bits set when empty) beside its value, and lookups compare several slots at once: a value equal
    // to the key sought or to the empty marker must neither answer a lookup nor end it. One table of
    // 64 slots is filled with 56 keys (long probe runs), half of them holding the empty marker and
    // half the packed form of cell (7, 7, 7), which is never stored.
    TestGrid grid(tinyConfig(1, 64, 64, FullPolicy::Refuse));
    const uint32_t absentLookalike = 7 | 7 << 8 | 7 << 16;
    KeyMap<uint32_t> expected;
    for (int64_t n = 0; n < 56; ++n) {
        const CellKey k{n % 4, (n / 4) % 4, n / 16, 0};
        const uint32_t value = n % 2 ? absentLookalike : ~uint32_t(0);
        ASSERT_EQ(grid.insert(k, value, 0).status, Status::Inserted) << str(k);
        expected[k] = value;
    }
    for (const auto& [k, v] : expected) ASSERT_EQ(grid.find(k), std::optional<uint32_t>(v)) << str(k);
    EXPECT_FALSE(grid.find({7, 7, 7, 0}).has_value());
    int visited = 0;
    grid.forEachInBlock({7, 7, 7, 0}, 0, [&](const CellKey&, uint32_t) { ++visited; });
    EXPECT_EQ(visited, 0);
}

// A slot packs a key's offsets inside its coarse cell into 8 bits per axis and its tag above them,
// and marks empty slots with all bits set: at the largest edge, every offset 0..254 with every tag
// 0..255 (the last offset of each axis with tag 255 is one bit pattern short of the marker) is
// stored, found, visited by a block query, reported exactly when evicted, and erased.
TEST(SparseHashGrid, EveryOffsetAndTagRoundTripsAtTheLargestEdge) {
    SparseHashGridConfig config;
    config.fineCellsPerCoarseEdge = SparseHashGrid::kMaxFineCellsPerCoarseEdge;
    const int64_t n = config.fineCellsPerCoarseEdge;
    TestGrid grid(config);
    KeyMap<uint32_t> stored;
    uint32_t value = 0;
    for (const int64_t coarse : {int64_t(-1), int64_t(0), int64_t(3)})
        for (const int64_t offset : {int64_t(0), int64_t(1), n - 2, n - 1})
            for (const int tag : {0, 1, 6, 254, 255}) {
                const CellKey k{coarse * n + offset, coarse * n + (n - 1 - offset), coarse * n + offset, uint8_t(tag)};
                ASSERT_EQ(grid.insert(k, value, 0).status, Status::Inserted) << str(k);
                stored[k] = value++;
            }
    for (const auto& [k, v] : stored) {
        ASSERT_EQ(grid.find(k), std::optional<uint32_t>(v)) << str(k);
        int seen = 0;
        grid.forEachNeighbour(k, [&](const CellKey& found, uint32_t) { seen += found == k; });
        EXPECT_EQ(seen, 1) << str(k);
    }
    const CellKey last{n - 1, n - 1, n - 1, 255};
    ASSERT_EQ(grid.insert(last, value, 0).status, Status::Inserted);
    EXPECT_EQ(grid.find(last), std::optional<uint32_t>(value));
    EXPECT_FALSE(grid.find({n - 1, n - 1, n - 2, 255}).has_value());
    for (const auto& [k, v] : stored) ASSERT_TRUE(grid.erase(k)) << str(k);
    for (const auto& [k, v] : stored) ASSERT_FALSE(grid.find(k).has_value()) << str(k);
    EXPECT_EQ(grid.find(last), std::optional<uint32_t>(value));

    // A one-slot table evicts on every insert and reports the dropped key whole.
    SparseHashGridConfig tiny = tinyConfig(1, 1, 1, FullPolicy::EvictLeastRecentlyUsed);
    tiny.fineCellsPerCoarseEdge = config.fineCellsPerCoarseEdge;
    TestGrid full(tiny);
    ASSERT_EQ(full.insert(last, 7, 0).status, Status::Inserted);
    const InsertOutcome evicted = full.insert({0, 0, 0, 0}, 8, 1);
    ASSERT_EQ(evicted.status, Status::Evicted);
    EXPECT_EQ(evicted.evictedKey, last);
    EXPECT_EQ(evicted.evictedValue, 7u);
}

TEST(SparseHashGrid, ReinsertingAKeyReportsExistingAndKeepsTheFirstValue) {
    TestGrid grid(SparseHashGridConfig{});
    const CellKey k{3, -4, 5, 2};
    const InsertOutcome first = grid.insert(k, 7, 0);
    EXPECT_EQ(first.status, Status::Inserted);
    EXPECT_EQ(first.value, 7u);
    const InsertOutcome again = grid.insert(k, 9, 1);
    EXPECT_EQ(again.status, Status::Existing);
    EXPECT_EQ(again.value, 7u);
    EXPECT_EQ(grid.find(k), std::optional<uint32_t>(7));
    EXPECT_EQ(grid.stats().entries, 1u);
}

// Inserts the 27 cells around `centre` and checks that the neighbourhood query visits exactly them,
// once each, with their values, and not the cells two steps away or of another facing.
void expectBlockAroundIsVisited(const CellKey& centre, size_t expectedTables) {
    TestGrid grid(SparseHashGridConfig{});
    KeyMap<uint32_t> block;
    for (int dz = -2; dz <= 2; ++dz)
        for (int dy = -2; dy <= 2; ++dy)
            for (int dx = -2; dx <= 2; ++dx) {
                const CellKey k{centre.x + dx, centre.y + dy, centre.z + dz, centre.facing};
                const uint32_t value = uint32_t(100 + (dz + 2) * 25 + (dy + 2) * 5 + dx + 2);
                ASSERT_EQ(grid.insert(k, value, 0).status, Status::Inserted) << str(k);
                ASSERT_EQ(grid.insert({k.x, k.y, k.z, uint8_t(centre.facing + 1)}, 0, 0).status, Status::Inserted) << str(k);
                if (std::abs(dx) <= 1 && std::abs(dy) <= 1 && std::abs(dz) <= 1) block[k] = value;
            }
    KeyMap<int> visits;
    grid.forEachNeighbour(centre, [&](const CellKey& k, uint32_t value) {
        ++visits[k];
        const auto it = block.find(k);
        ASSERT_NE(it, block.end()) << "visited " << str(k) << " outside the block around " << str(centre);
        EXPECT_EQ(value, it->second) << str(k);
    });
    EXPECT_EQ(visits.size(), 27u) << "around " << str(centre);
    for (const auto& [k, n] : visits) EXPECT_EQ(n, 1) << str(k);
    KeySet coarse;
    for (const auto& [k, v] : block) coarse.insert(grid.coarseOf(k));
    EXPECT_EQ(coarse.size(), expectedTables) << "around " << str(centre);
}

TEST(SparseHashGrid, NeighboursOfACoarseCornerComeFromEightTables) {
    expectBlockAroundIsVisited({0, 0, 0, 0}, 8);
    expectBlockAroundIsVisited({-25, -25, -25, 3}, 8);
    expectBlockAroundIsVisited({24, -1, 49, 1}, 8);
}

TEST(SparseHashGrid, NeighboursInsideACoarseCellComeFromOneTable) {
    expectBlockAroundIsVisited({12, -13, 37, 0}, 1);
    expectBlockAroundIsVisited({-12, 5, 12, 0}, 1);
}

TEST(SparseHashGrid, NeighboursWithOneFineCellPerCoarseCellSpanTwentySevenTables) {
    SparseHashGridConfig c;
    c.fineCellsPerCoarseEdge = 1;
    c.fineSlotsPerTable = 16;
    c.maxProbeLength = 16;
    TestGrid grid(c);
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) ASSERT_EQ(grid.insert({dx - 5, dy, dz + 5, 0}, 0, 0).status, Status::Inserted);
    int visits = 0;
    grid.forEachNeighbour({-5, 0, 5, 0}, [&](const CellKey&, uint32_t) { ++visits; });
    EXPECT_EQ(visits, 27);
    EXPECT_EQ(grid.stats().coarseTables, 27u);
}

// forEachInBlockInnerFirst visits the 27 cells around the key, then those of the box outer()
// returns outside them (clamped to the 5³ block): each stored key of the key's facing once, none
// of another facing or outside. Around a point inside one coarse cell, on a coarse corner, and
// with coarse cells of one and two fine cells (every cell in its own table or in runs of two).
TEST(SparseHashGrid, InnerFirstVisitsTheInnerBlockThenTheOuterCellsOfABox) {
    const auto check = [](int edge, const CellKey& centre) {
        SparseHashGridConfig c;
        c.fineCellsPerCoarseEdge = edge;
        TestGrid grid(c);
        Rng rng(uint64_t(edge), uint64_t(centre.x));
        KeyMap<uint32_t> stored;
        for (int dz = -3; dz <= 3; ++dz)
            for (int dy = -3; dy <= 3; ++dy)
                for (int dx = -3; dx <= 3; ++dx) {
                    const CellKey k{centre.x + dx, centre.y + dy, centre.z + dz, centre.facing};
                    if (rng.uniform() < 0.5f) continue;  // half the cells are empty
                    ASSERT_EQ(grid.insert(k, uint32_t(stored.size()), 0).status, Status::Inserted) << str(k);
                    stored[k] = uint32_t(stored.size());
                    ASSERT_EQ(grid.insert({k.x, k.y, k.z, uint8_t(centre.facing + 1)}, 999, 0).status, Status::Inserted);
                }
        const auto ring = [&](const CellKey& k) {
            return std::max({std::abs(k.x - centre.x), std::abs(k.y - centre.y), std::abs(k.z - centre.z)});
        };
        using Box = SparseHashGrid::BlockBox;
        const Box whole{{-2, -2, -2}, {2, 2, 2}}, beyond{{-9, -9, -9}, {9, 9, 9}}, sides{{-2, -1, -1}, {1, 2, 2}};
        for (const Box& box : {Box{}, whole, beyond, sides, Box{{-1, -1, -1}, {1, 1, 1}}, Box{{2, 0, 0}, {2, 0, 0}}}) {
            const auto inBox = [&](const CellKey& k) {
                const int64_t d[3] = {k.x - centre.x, k.y - centre.y, k.z - centre.z};
                for (int a = 0; a < 3; ++a)
                    if (d[a] < box.from[a] || d[a] > box.to[a]) return false;
                return true;
            };
            KeyMap<uint32_t> visited;
            bool asked = false;
            grid.forEachInBlockInnerFirst(
                centre, 2,
                [&](const CellKey& k, uint32_t value) {
                    EXPECT_TRUE(visited.emplace(k, value).second) << "visited twice: " << str(k);
                    EXPECT_EQ(asked, ring(k) == 2) << str(k) << ": the inner block comes before outer() is asked, the outer ring after";
                },
                [&] {
                    asked = true;
                    return box;
                });
            EXPECT_TRUE(asked);
            KeyMap<uint32_t> expected;
            for (const auto& [k, v] : stored)
                if (ring(k) <= 1 || (ring(k) == 2 && inBox(k))) expected.emplace(k, v);
            EXPECT_EQ(visited, expected) << "edge " << edge << " around " << str(centre) << ", box " << box.from[0] << ".." << box.to[0] << " "
                                         << box.from[1] << ".." << box.to[1] << " " << box.from[2] << ".." << box.to[2];
        }
    };
    check(25, {12, -13, 37, 2});
    check(25, {0, 0, 0, 1});
    check(25, {-26, 24, 50, 3});
    check(2, {5, -4, 1, 1});
    check(1, {-5, 0, 5, 4});
}

TEST(SparseHashGrid, FacingTagsKeepTheTwoSidesOfAWallApart) {
    // A wall of thickness 0.1 at x = 1.8: both sides fall in the same fine cell of size 0.4.
    TestGrid grid(SparseHashGridConfig{});
    const CellKey front = grid.keyOf(vec3(1.75f, 0.5f, 0.5f), 2), back = grid.keyOf(vec3(1.85f, 0.5f, 0.5f), 1);
    ASSERT_EQ(front.x, back.x);
    ASSERT_NE(front, back);
    EXPECT_EQ(grid.insert(front, 10, 0).status, Status::Inserted);
    EXPECT_EQ(grid.insert(back, 20, 0).status, Status::Inserted);
    EXPECT_EQ(grid.find(front), std::optional<uint32_t>(10));
    EXPECT_EQ(grid.find(back), std::optional<uint32_t>(20));
    EXPECT_FALSE(grid.find({front.x, front.y, front.z, 0}).has_value());
    std::vector<uint32_t> seen;
    grid.forEachNeighbour(front, [&](const CellKey& k, uint32_t v) {
        EXPECT_EQ(k.facing, front.facing);
        seen.push_back(v);
    });
    EXPECT_EQ(seen, std::vector<uint32_t>{10});
    EXPECT_EQ(grid.stats().coarseTables, 1u) << "all facings of a coarse cell share its table";
}

// 1000 distinct keys spread over three coarse cells along x, in random order.
KeySet keysInThreeCoarseCells(Rng& rng) {
    KeySet keys;
    while (keys.size() < 1000) keys.insert({uniformInt(rng, -25, 50), uniformInt(rng, 0, 25), uniformInt(rng, 0, 25), uint8_t(rng.next() % 7)});
    return keys;
}

TEST(SparseHashGrid, SurfacePatternsFillATableWithoutRefusals) {
    // Regular sets of cells, as surfaces produce, in one coarse cell's 32767-slot table: the hash keeps
    // every key within two buckets (8 slots) of its home bucket even at half load.
    const auto refusals = [](const KeySet& keys) {
        SparseHashGridConfig c;
        c.maxProbeLength = 8;
        c.policy = FullPolicy::Refuse;
        TestGrid grid(c);
        for (const CellKey& k : keys) grid.insert(k, 0, 0);
        EXPECT_EQ(grid.stats().coarseTables, 1u);
        return grid.stats().refusedInserts;
    };
    KeySet planes, cube;
    for (int64_t a = 0; a < 25; ++a)
        for (int64_t b = 0; b < 25; ++b) {
            for (uint8_t f = 1; f <= 6; ++f) {
                const int64_t at = 3 * f % 25;  // one plane per facing and axis
                planes.insert({a, b, at, f});
                planes.insert({a, at, b, f});
                planes.insert({at, a, b, f});
            }
            for (int64_t c = 0; c < 25; ++c) cube.insert({a, b, c, 0});
        }
    EXPECT_EQ(refusals(planes), 0u) << planes.size() << " cells on 18 planes";
    EXPECT_EQ(refusals(cube), 0u) << "a filled cube of " << cube.size() << " cells";
}

TEST(SparseHashGrid, RefusePolicyCountsEveryRefusedInsertAndChangesNothing) {
    TestGrid grid(tinyConfig(2, 8, 4, FullPolicy::Refuse));
    Rng rng(2, 2);
    const KeySet keys = keysInThreeCoarseCells(rng);
    KeySet stored, refused;
    uint32_t value = 0;
    for (const CellKey& k : keys) {
        const InsertOutcome o = grid.insert(k, value++, 0);
        ASSERT_TRUE(o.status == Status::Inserted || o.status == Status::Refused) << str(k);
        (o.status == Status::Inserted ? stored : refused).insert(k);
    }
    const SparseHashGrid::Stats s = grid.stats();
    EXPECT_EQ(s.entries, stored.size());
    EXPECT_EQ(s.refusedInserts, refused.size());
    EXPECT_EQ(s.entries + s.refusedInserts, keys.size());
    EXPECT_EQ(s.evictions, 0u);
    EXPECT_EQ(s.coarseTables, 2u);
    EXPECT_EQ(s.capacitySlots, 16u);
    EXPECT_LE(s.entries, 16u);
    EXPECT_GE(s.entries, 8u) << "a table refuses only when a bucket, its probe sequence, is full";
    EXPECT_DOUBLE_EQ(s.loadFactor, double(s.entries) / 16.0);
    for (const CellKey& k : stored) EXPECT_TRUE(grid.find(k).has_value()) << str(k);
    for (const CellKey& k : refused) EXPECT_FALSE(grid.find(k).has_value()) << str(k);
    // The grid is unchanged by refusals, so a second pass gives the same answers.
    for (const CellKey& k : keys) EXPECT_EQ(grid.insert(k, 0, 1).status, stored.count(k) ? Status::Existing : Status::Refused) << str(k);
    EXPECT_EQ(grid.stats().refusedInserts, 2 * refused.size());
}

TEST(SparseHashGrid, EvictionDropsTheLeastRecentlyUsedEntryOfTheProbeSequence) {
    // 4 slots probed 4 at a time: every probe sequence is the whole table, so the evicted entry must
    // be one of the least recently used of all stored ones.
    TestGrid grid(tinyConfig(1, 4, 4, FullPolicy::EvictLeastRecentlyUsed));
    Rng rng(3, 3);
    KeyMap<uint32_t> lastUsed, values;
    uint32_t frame = 0;
    int evictions = 0;
    for (int step = 0; step < 2000; ++step) {
        frame += rng.next() % 2;  // repeated frames exercise ties
        if (!lastUsed.empty() && rng.next() % 3 == 0) {
            auto it = lastUsed.begin();
            std::advance(it, rng.next() % lastUsed.size());
            ASSERT_TRUE(grid.touch(it->first, frame)) << str(it->first);
            it->second = frame;
            continue;
        }
        const CellKey k = randomKey(rng, 0, 25);  // one coarse cell
        const uint32_t value = uint32_t(step);
        const InsertOutcome o = grid.insert(k, value, frame);
        if (lastUsed.count(k)) {
            ASSERT_EQ(o.status, Status::Existing) << str(k);
            ASSERT_EQ(o.value, values[k]);
            lastUsed[k] = frame;
            continue;
        }
        if (lastUsed.size() < 4) {
            ASSERT_EQ(o.status, Status::Inserted) << str(k);
        } else {
            ASSERT_EQ(o.status, Status::Evicted) << str(k);
            ++evictions;
            ASSERT_TRUE(lastUsed.count(o.evictedKey)) << "evicted " << str(o.evictedKey) << " was not stored";
            uint32_t oldest = std::numeric_limits<uint32_t>::max();
            for (const auto& [key, used] : lastUsed) oldest = std::min(oldest, used);
            EXPECT_EQ(lastUsed[o.evictedKey], oldest) << "step " << step << ": evicted " << str(o.evictedKey);
            EXPECT_EQ(o.evictedValue, values[o.evictedKey]);
            EXPECT_FALSE(grid.find(o.evictedKey).has_value());
            lastUsed.erase(o.evictedKey);
            values.erase(o.evictedKey);
        }
        EXPECT_EQ(o.value, value);
        lastUsed[k] = frame;
        values[k] = value;
        for (const auto& [key, v] : values) ASSERT_EQ(grid.find(key), std::optional<uint32_t>(v)) << "step " << step << " " << str(key);
    }
    EXPECT_EQ(grid.stats().evictions, uint64_t(evictions));
    EXPECT_GT(evictions, 500);
}

TEST(SparseHashGrid, EvictPolicyStaysBoundedAndRefusesOnlyWhenNoTableCanBeCreated) {
    TestGrid grid(tinyConfig(2, 8, 4, FullPolicy::EvictLeastRecentlyUsed));
    Rng rng(4, 4);
    const KeySet keys = keysInThreeCoarseCells(rng);
    KeyMap<uint32_t> stored;
    KeySet tables;  // coarse cells that got a table
    uint64_t refused = 0, evicted = 0;
    uint32_t frame = 0;
    for (const CellKey& k : keys) {
        const InsertOutcome o = grid.insert(k, frame, frame);
        ++frame;
        if (o.status == Status::Refused) {
            ++refused;
            EXPECT_EQ(tables.size(), 2u) << str(k);
            EXPECT_FALSE(tables.count(grid.coarseOf(k))) << str(k);
            continue;
        }
        tables.insert(grid.coarseOf(k));
        if (o.status == Status::Evicted) {
            ++evicted;
            EXPECT_EQ(grid.coarseOf(o.evictedKey), grid.coarseOf(k)) << "eviction stays in the key's table";
            ASSERT_TRUE(stored.count(o.evictedKey)) << str(o.evictedKey);
            EXPECT_EQ(o.evictedValue, stored[o.evictedKey]) << str(o.evictedKey);
            stored.erase(o.evictedKey);
        } else {
            ASSERT_EQ(o.status, Status::Inserted) << str(k);
        }
        stored[k] = o.value;
    }
    const SparseHashGrid::Stats s = grid.stats();
    EXPECT_EQ(s.entries, stored.size());
    EXPECT_EQ(s.evictions, evicted);
    EXPECT_EQ(s.refusedInserts, refused);
    EXPECT_EQ(s.entries + s.evictions + s.refusedInserts, keys.size());
    EXPECT_LE(s.entries, 16u);
    EXPECT_GT(evicted, 0u);
    for (const auto& [k, v] : stored) EXPECT_EQ(grid.find(k), std::optional<uint32_t>(v)) << str(k);
}

TEST(SparseHashGrid, EvictedKeyIsReportedExactlyEvenAtTheEndsOfTheInt64Range) {
    TestGrid grid(tinyConfig(1, 1, 1, FullPolicy::EvictLeastRecentlyUsed));
    constexpr int64_t kMin = std::numeric_limits<int64_t>::min(), kMax = std::numeric_limits<int64_t>::max();
    const CellKey a{kMin, kMax, -7, 5}, b{kMin + 1, kMax - 1, -8, 6};
    ASSERT_EQ(grid.coarseOf(a), grid.coarseOf(b));
    ASSERT_EQ(grid.insert(a, 1, 0).status, Status::Inserted);
    const InsertOutcome o = grid.insert(b, 2, 1);
    ASSERT_EQ(o.status, Status::Evicted);
    EXPECT_EQ(o.evictedKey, a);
    EXPECT_EQ(o.evictedValue, 1u);
    EXPECT_EQ(grid.find(b), std::optional<uint32_t>(2));
}

TEST(SparseHashGrid, KeysFarFromTheOriginAtTinyCellSizesRoundTrip) {
    SparseHashGridConfig c;
    c.fineCellSize = 1e-4;
    TestGrid grid(c);
    const vec3 p(1.0e6f, -1.0e6f, 999999.9375f);
    const CellKey centre = grid.keyOf(p, 4);
    EXPECT_EQ(centre.x, int64_t(std::floor(double(p.x) / 1e-4)));
    EXPECT_EQ(centre.y, int64_t(std::floor(double(p.y) / 1e-4)));
    EXPECT_EQ(centre.z, int64_t(std::floor(double(p.z) / 1e-4)));
    EXPECT_GT(centre.x, int64_t(9'999'999'000));
    EXPECT_LT(centre.y, int64_t(-9'999'999'000));
    KeyMap<uint32_t> block;
    for (int dz = -3; dz <= 3; ++dz)
        for (int dy = -3; dy <= 3; ++dy)
            for (int dx = -3; dx <= 3; ++dx) {
                const CellKey k{centre.x + dx, centre.y + dy, centre.z + dz, centre.facing};
                const uint32_t value = uint32_t(block.size());
                ASSERT_EQ(grid.insert(k, value, 0).status, Status::Inserted) << str(k);
                block[k] = value;
            }
    for (const auto& [k, v] : block) EXPECT_EQ(grid.find(k), std::optional<uint32_t>(v)) << str(k);
    EXPECT_FALSE(grid.find({centre.x, centre.y, centre.z + 4, centre.facing}).has_value());
    int visits = 0;
    grid.forEachNeighbour(centre, [&](const CellKey& k, uint32_t v) {
        ++visits;
        EXPECT_EQ(v, block.at(k)) << str(k);
    });
    EXPECT_EQ(visits, 27);
}

TEST(SparseHashGrid, NeighboursAtTheEndsOfTheInt64RangeSkipCellsThatDoNotExist) {
    TestGrid grid(SparseHashGridConfig{});
    constexpr int64_t kMin = std::numeric_limits<int64_t>::min(), kMax = std::numeric_limits<int64_t>::max();
    const CellKey corner{kMax, kMin, 0, 0};
    KeySet block;
    for (int64_t x : {kMax - 1, kMax})
        for (int64_t y : {kMin, kMin + 1})
            for (int64_t z : {-1, 0, 1}) {
                ASSERT_EQ(grid.insert({x, y, z, 0}, 0, 0).status, Status::Inserted);
                block.insert({x, y, z, 0});
            }
    KeySet visited;
    grid.forEachNeighbour(corner, [&](const CellKey& k, uint32_t) { EXPECT_TRUE(visited.insert(k).second) << str(k); });
    EXPECT_EQ(visited, block);
}

// A block walk (5³ cells) visits exactly the stored keys of its facing within two cells of the
// centre, whatever the centre's offset inside its coarse cell, i.e. however its rows split into
// runs of cells of one coarse cell. Every offset on each axis, for edges below and above the
// block's width of five, with coarse coordinates of both signs, and centres two and three cells
// from the ends of the int64 range.
TEST(SparseHashGrid, ABlockVisitsExactlyTheStoredKeysWithinItsRingsAtEveryOffset) {
    constexpr int64_t kMin = std::numeric_limits<int64_t>::min(), kMax = std::numeric_limits<int64_t>::max();
    const auto check = [](TestGrid& grid, const KeyMap<uint32_t>& stored, const CellKey& centre) {
        KeyMap<uint32_t> visited, expected;
        grid.forEachInBlock(centre, 2, [&](const CellKey& k, uint32_t value) { EXPECT_TRUE(visited.emplace(k, value).second) << str(k); });
        for (const auto& [k, v] : stored) {
            const auto near = [](int64_t a, int64_t b) { return (a >= b ? uint64_t(a) - uint64_t(b) : uint64_t(b) - uint64_t(a)) <= 2; };
            if (k.facing == centre.facing && near(k.x, centre.x) && near(k.y, centre.y) && near(k.z, centre.z)) expected.emplace(k, v);
        }
        EXPECT_EQ(visited, expected) << "around " << str(centre) << ", edge " << grid.config().fineCellsPerCoarseEdge;
    };
    for (const int edge : {3, 4, 5, 6, 25}) {
        SparseHashGridConfig c;
        c.fineCellsPerCoarseEdge = edge;
        TestGrid grid(c);
        std::vector<CellKey> centres;
        for (int64_t o = 0; o < edge; ++o) {
            centres.push_back({o, (o + 1) % edge, (2 * o + 2) % edge, 1});
            centres.push_back({-edge + o, -2 * edge + (o + 3) % edge, (o + edge - 1) % edge - edge, 2});
        }
        // Half the cells within three of a centre, of either facing: the ring beyond the block too.
        Rng rng(uint64_t(edge), 11);
        KeyMap<uint32_t> stored;
        for (const CellKey& centre : centres)
            for (int64_t dz = -3; dz <= 3; ++dz)
                for (int64_t dy = -3; dy <= 3; ++dy)
                    for (int64_t dx = -3; dx <= 3; ++dx)
                        for (const uint8_t facing : {uint8_t(1), uint8_t(2)}) {
                            const CellKey k{centre.x + dx, centre.y + dy, centre.z + dz, facing};
                            if (rng.uniform() < 0.5f || stored.count(k)) continue;
                            ASSERT_EQ(grid.insert(k, uint32_t(stored.size()), 0).status, Status::Inserted) << str(k);
                            stored[k] = uint32_t(stored.size());
                        }
        for (const CellKey& centre : centres) check(grid, stored, centre);
        KeyMap<uint32_t> atEnds;
        for (const int64_t v : {kMax - 4, kMax - 3, kMax - 2, kMax - 1, kMax, kMin, kMin + 1, kMin + 2, kMin + 3, kMin + 4})
            for (const int64_t w : {int64_t(-1), int64_t(0), int64_t(1)}) {
                const CellKey k{v, w, v, 1};
                ASSERT_EQ(grid.insert(k, uint32_t(atEnds.size()), 0).status, Status::Inserted) << str(k);
                atEnds[k] = uint32_t(atEnds.size());
            }
        for (const int64_t v : {kMax - 3, kMax - 2, kMin + 2, kMin + 3}) check(grid, atEnds, {v, 0, v, 1});
    }
}

// forEachInBox (the raster stage's tile regions, issue 9) visits exactly the stored keys of its
// facing inside the box, once each: boxes inside one coarse cell, across several, with one fine
// cell per coarse cell (no bitmaps past kMaxOccupancyEdge) and at the ends of the int64 range.
TEST(SparseHashGrid, ABoxVisitsExactlyItsStoredKeysOfOneFacing) {
    constexpr int64_t kMin = std::numeric_limits<int64_t>::min(), kMax = std::numeric_limits<int64_t>::max();
    for (const int edge : {25, 1, 7, 100}) {
        for (const int64_t origin : {int64_t(-40), kMax - 60, kMin}) {
            SparseHashGridConfig config;
            config.fineCellsPerCoarseEdge = edge;
            TestGrid grid(config);
            Rng rng(17, uint64_t(edge));
            KeyMap<uint32_t> stored;
            for (uint32_t value = 0; value < 600; ++value) {
                const CellKey k{origin + uniformInt(rng, 0, 60), origin + uniformInt(rng, 0, 60), origin + uniformInt(rng, 0, 60),
                                uint8_t(rng.next() % 3)};
                if (grid.insert(k, value, 0).status == Status::Inserted) stored[k] = value;
            }
            for (int box = 0; box < 40; ++box) {
                std::array<int64_t, 3> lo, hi;
                for (int a = 0; a < 3; ++a) {
                    lo[a] = origin + uniformInt(rng, 0, 60);
                    const int64_t room = lo[a] > kMax - 30 ? kMax - lo[a] : 30;  // hi stays within int64
                    hi[a] = lo[a] + uniformInt(rng, 0, room + 1);
                }
                const uint8_t facing = uint8_t(rng.next() % 3);
                KeyMap<uint32_t> visited;
                grid.forEachInBox(lo, hi, facing, [&](const CellKey& k, uint32_t value) {
                    EXPECT_TRUE(visited.emplace(k, value).second) << "visited twice: " << str(k);
                });
                KeyMap<uint32_t> expected;
                for (const auto& [k, value] : stored)
                    if (k.facing == facing && k.x >= lo[0] && k.x <= hi[0] && k.y >= lo[1] && k.y <= hi[1] && k.z >= lo[2] && k.z <= hi[2])
                        expected[k] = value;
                EXPECT_EQ(visited, expected) << "edge " << edge << " origin " << origin << " box " << box;
            }
        }
    }
}

TEST(SparseHashGrid, ErasingHalfOfADenseTableKeepsTheRestFindable) {
    for (uint32_t probeLength : {8u, 64u}) {
        TestGrid grid(tinyConfig(1, 64, probeLength, FullPolicy::Refuse));
        Rng rng(5, probeLength);
        std::vector<CellKey> stored;
        KeySet tried;
        while (tried.size() < 2000) {
            const CellKey k = randomKey(rng, 0, 25);
            if (!tried.insert(k).second) continue;
            if (grid.insert(k, uint32_t(stored.size()), 0).status == Status::Inserted) stored.push_back(k);
        }
        ASSERT_GE(stored.size(), probeLength == 64 ? 64u : 48u) << "probe length " << probeLength;
        for (size_t i = 0; i < stored.size(); i += 2) ASSERT_TRUE(grid.erase(stored[i])) << str(stored[i]);
        for (size_t i = 0; i < stored.size(); ++i) {
            if (i % 2 == 0) {
                EXPECT_FALSE(grid.find(stored[i]).has_value()) << "probe length " << probeLength << " " << str(stored[i]);
                EXPECT_FALSE(grid.erase(stored[i])) << str(stored[i]);
            } else {
                EXPECT_EQ(grid.find(stored[i]), std::optional<uint32_t>(uint32_t(i))) << "probe length " << probeLength << " " << str(stored[i]);
            }
        }
        EXPECT_EQ(grid.stats().entries, stored.size() / 2);
    }
}

TEST(SparseHashGrid, RandomInsertsAndErasesAgreeWithAReferenceMap) {
    // A small table under constant churn: backward-shift deletion must keep every stored key within
    // reach of its home and refuse only when the key's probe run is really full.
    TestGrid grid(tinyConfig(1, 32, 6, FullPolicy::Refuse));
    Rng rng(6, 6);
    KeyMap<uint32_t> expected;
    uint64_t refused = 0;
    for (int step = 0; step < 20000; ++step) {
        const CellKey k = randomKey(rng, 0, 6);
        if (rng.next() % 2 == 0) {
            EXPECT_EQ(grid.erase(k), expected.erase(k) == 1) << "step " << step << " " << str(k);
        } else {
            const InsertOutcome o = grid.insert(k, uint32_t(step), 0);
            if (expected.count(k)) {
                ASSERT_EQ(o.status, Status::Existing) << "step " << step << " " << str(k);
            } else if (o.status == Status::Refused) {
                ++refused;
                EXPECT_GE(expected.size(), 6u) << "a run of 6 cannot be full with fewer entries";
            } else {
                ASSERT_EQ(o.status, Status::Inserted) << "step " << step << " " << str(k);
                expected[k] = uint32_t(step);
            }
        }
        ASSERT_EQ(grid.stats().entries, expected.size()) << "step " << step;
        for (const auto& [key, v] : expected) ASSERT_EQ(grid.find(key), std::optional<uint32_t>(v)) << "step " << step << " " << str(key);
    }
    EXPECT_EQ(grid.stats().refusedInserts, refused);
    EXPECT_GT(refused, 0u) << "the churn should reach full runs";
}

// Tables are probed by buckets of four slots; a table of fineSlotsPerTable slots that is not a
// multiple of four has lanes of its last bucket it does not own. Those are never filled, and runs
// pass them and wrap to the first bucket; under churn, the bucket-wise backward shift keeps every
// key findable, and a key is refused only when every slot of its probe sequence is taken.
TEST(SparseHashGrid, TablesOfAnySlotCountHoldExactlyThatManyKeysUnderChurn) {
    for (const uint32_t slots : {1u, 7u, 30u}) {
        const uint32_t probeLength = std::min(slots, 9u);  // three buckets at most
        TestGrid grid(tinyConfig(1, slots, probeLength, FullPolicy::Refuse));
        Rng rng(8, slots);
        KeyMap<uint32_t> expected;
        uint64_t refused = 0;
        for (int step = 0; step < 20000; ++step) {
            const CellKey k = randomKey(rng, 0, 5);
            if (rng.next() % 3 == 0) {
                ASSERT_EQ(grid.erase(k), expected.erase(k) == 1) << slots << " slots, step " << step << " " << str(k);
            } else {
                const InsertOutcome o = grid.insert(k, uint32_t(step), 0);
                if (expected.count(k)) {
                    ASSERT_EQ(o.status, Status::Existing) << slots << " slots, step " << step << " " << str(k);
                    ASSERT_EQ(o.value, expected[k]);
                } else if (o.status == Status::Refused) {
                    ++refused;
                    // A probe sequence is ⌈probeLength / 4⌉ buckets; the last bucket may lack some lanes.
                    const uint32_t missingLanes = (4 - slots % 4) % 4;
                    ASSERT_GE(expected.size(), std::min(slots, 4 * ((probeLength + 3) / 4) - missingLanes)) << slots << " slots, step " << step;
                } else {
                    ASSERT_EQ(o.status, Status::Inserted) << slots << " slots, step " << step << " " << str(k);
                    expected[k] = uint32_t(step);
                }
            }
            ASSERT_LE(expected.size(), slots);
            ASSERT_EQ(grid.stats().entries, expected.size()) << slots << " slots, step " << step;
            for (const auto& [key, v] : expected)
                ASSERT_EQ(grid.find(key), std::optional<uint32_t>(v)) << slots << " slots, step " << step << " " << str(key);
        }
        EXPECT_EQ(grid.stats().capacitySlots, expected.empty() ? 0u : slots);
        EXPECT_GT(refused, 0u) << slots << " slots: the churn should fill the table";
    }
    // Where the probe sequence is the whole table, a table fills to exactly its slot count.
    TestGrid seven(tinyConfig(1, 7, 7, FullPolicy::Refuse));
    std::size_t stored = 0;
    for (int64_t i = 0; i < 25; ++i) stored += seven.insert({i, 0, 0, 0}, uint32_t(i), 0).status == Status::Inserted;
    EXPECT_EQ(stored, 7u);
    EXPECT_EQ(seven.stats().refusedInserts, 18u);
}

TEST(SparseHashGrid, EmptiedTableIsReleasedForAnotherCoarseCell) {
    TestGrid grid(tinyConfig(1, 8, 4, FullPolicy::Refuse));
    const CellKey a{1, 2, 3, 0}, b{100, 2, 3, 0};
    ASSERT_EQ(grid.insert(a, 1, 0).status, Status::Inserted);
    EXPECT_EQ(grid.insert(b, 2, 0).status, Status::Refused) << "the only table belongs to a's coarse cell";
    const size_t bytes = grid.stats().bytes;
    EXPECT_TRUE(grid.erase(a));
    EXPECT_EQ(grid.stats().coarseTables, 0u);
    EXPECT_EQ(grid.stats().bytes, bytes) << "the released table is kept for reuse";
    EXPECT_EQ(grid.insert(b, 2, 0).status, Status::Inserted);
    EXPECT_EQ(grid.find(b), std::optional<uint32_t>(2));
    EXPECT_FALSE(grid.find(a).has_value());
    EXPECT_EQ(grid.stats().bytes, bytes) << "reusing the table allocates nothing";
}

TEST(SparseHashGrid, ManyTablesCreatedAndReleasedKeepTheFirstLevelConsistent) {
    // Grows the first level past its initial size, then releases tables in a scattered order.
    SparseHashGridConfig c = tinyConfig(300, 4, 4, FullPolicy::Refuse);
    c.fineCellsPerCoarseEdge = 1;
    TestGrid grid(c);
    std::vector<CellKey> keys;
    for (int i = 0; i < 300; ++i) keys.push_back({i % 7 - 3, i / 7 % 7 - 3, i / 49 - 3, 0});
    for (const CellKey& k : keys) ASSERT_EQ(grid.insert(k, uint32_t(k.x + 10), 0).status, Status::Inserted) << str(k);
    EXPECT_EQ(grid.stats().coarseTables, 300u);
    for (size_t i = 0; i < keys.size(); i += 3) ASSERT_TRUE(grid.erase(keys[i]));
    for (size_t i = 0; i < keys.size(); ++i)
        EXPECT_EQ(grid.find(keys[i]).has_value(), i % 3 != 0) << str(keys[i]);
    EXPECT_EQ(grid.stats().coarseTables, 200u);
}

TEST(SparseHashGrid, StatsCountTheMemoryOfBothLevels) {
    TestGrid grid(SparseHashGridConfig{});
    const SparseHashGrid::Stats empty = grid.stats();
    EXPECT_EQ(empty.entries, 0u);
    EXPECT_EQ(empty.coarseTables, 0u);
    EXPECT_EQ(empty.capacitySlots, 0u);
    EXPECT_EQ(empty.loadFactor, 0.0);
    EXPECT_GT(empty.bytes, 0u) << "the first level exists from the start";
    for (int64_t i = 0; i < 3; ++i) grid.insert({i * 25, 0, 0, 0}, 0, 0);
    const SparseHashGrid::Stats s = grid.stats();
    EXPECT_EQ(s.coarseTables, 3u);
    constexpr size_t kSlots = SparseHashGrid::kInitialFineSlots;
    EXPECT_EQ(s.capacitySlots, 3u * kSlots) << "a new table starts small";
    EXPECT_DOUBLE_EQ(s.loadFactor, 3.0 / (3.0 * kSlots));
    const size_t tables = 3u * (kSlots * SparseHashGrid::kBytesPerFineSlot + grid.occupancyBytesPerTable());
    EXPECT_EQ(grid.occupancyBytesPerTable(), (25u * 25u * 25u / 64u + 2u) * 8u) << "a bit per fine cell, and a padding word";
    EXPECT_GE(s.bytes, tables + empty.bytes);
    EXPECT_LE(s.bytes, tables + empty.bytes + 1024u) << "bookkeeping beyond the slots stays small";
}

// Issue 9: tables sized to what they hold. A table doubles when it would pass half full, so n
// keys in one coarse cell take between 2n and 4n slots (and at least the initial 64), up to
// fineSlotsPerTable; every key stays findable across the moves, and a full table of the largest
// size still evicts as before.
TEST(SparseHashGrid, TablesGrowWithTheirKeysAndKeepEveryKeyFindable) {
    TestGrid grid(SparseHashGridConfig{});
    std::vector<CellKey> keys;
    for (int64_t z = 0; z < 25; ++z)
        for (int64_t x = 0; x < 25; ++x) keys.push_back({x, 3, z, 3});  // a plane of one coarse cell
    for (std::size_t n = 0; n < keys.size(); ++n) {
        ASSERT_EQ(grid.insert(keys[n], uint32_t(n), 0).status, InsertOutcome::Status::Inserted) << str(keys[n]);
        const std::size_t slots = grid.stats().capacitySlots, held = n + 1;
        EXPECT_GE(slots, std::max<std::size_t>(2 * held, SparseHashGrid::kInitialFineSlots)) << held << " keys";
        EXPECT_LE(slots, std::max<std::size_t>(4 * held, SparseHashGrid::kInitialFineSlots)) << held << " keys";
    }
    for (std::size_t n = 0; n < keys.size(); ++n) EXPECT_EQ(grid.find(keys[n]), std::optional<uint32_t>(uint32_t(n))) << str(keys[n]);
    EXPECT_EQ(grid.stats().capacitySlots, 2048u) << "625 keys: the first power of two over twice as many";
    EXPECT_EQ(grid.stats().refusedInserts + grid.stats().evictions, 0u);

    // At its largest a table fills and evicts, as a table allocated whole did.
    TestGrid small(tinyConfig(1, 100, 100, FullPolicy::EvictLeastRecentlyUsed));
    for (uint32_t n = 0; n < 100; ++n) ASSERT_EQ(small.insert({n % 10, n / 10, 0, 0}, n, n).status, InsertOutcome::Status::Inserted);
    EXPECT_EQ(small.stats().capacitySlots, 100u);
    const InsertOutcome evicted = small.insert({20, 20, 0, 0}, 100, 100);
    EXPECT_EQ(evicted.status, InsertOutcome::Status::Evicted);
    EXPECT_EQ(evicted.evictedValue, 0u) << "the least recently used key";
}

TEST(SparseHashGrid, ConcurrentReadersSeeEveryKey) {
    TestGrid grid(SparseHashGridConfig{});
    Rng rng(7, 7);
    const KeyMap<uint32_t> expected = insertRandomKeys(grid, rng, 20000, -40, 40);
    const std::vector<std::pair<CellKey, uint32_t>> pairs(expected.begin(), expected.end());
    std::vector<int> mismatches(4, 0);
    std::vector<std::thread> readers;
    for (int t = 0; t < 4; ++t)
        readers.emplace_back([&, t] {
            for (int pass = 0; pass < 2; ++pass)
                for (const std::pair<CellKey, uint32_t>& pair : pairs) {
                    const CellKey& k = pair.first;  // named, not bound: clang 14 cannot capture a structured binding
                    mismatches[t] += grid.find(k) != std::optional<uint32_t>(pair.second);
                    int inBlock = 0;
                    grid.forEachNeighbour(k, [&](const CellKey& n, uint32_t) { inBlock += n == k; });
                    mismatches[t] += inBlock != 1;
                }
        });
    for (std::thread& r : readers) r.join();
    for (int t = 0; t < 4; ++t) EXPECT_EQ(mismatches[t], 0) << "reader " << t;
}

TEST(SparseHashGrid, KeyOfFloorsOnCellBoundariesAndNegativeCoordinates) {
    TestGrid grid(SparseHashGridConfig{});  // cell 0.4
    EXPECT_EQ(grid.keyOf(vec3(-0.2f, 0.2f, 0.0f), 0), (CellKey{-1, 0, 0, 0}));
    EXPECT_EQ(grid.keyOf(vec3(-0.0f, 0.39f, -0.41f), 3), (CellKey{0, 0, -2, 3}));
    EXPECT_EQ(grid.keyOf(vec3(10.0f, -10.0f, 0.8f), 0), (CellKey{25, -25, 2, 0}));

    SparseHashGridConfig c;
    c.fineCellSize = 0.5;  // exactly representable, so the boundaries are exact
    TestGrid half(c);
    EXPECT_EQ(half.keyOf(vec3(0.5f, 1.0f, -0.5f), 0), (CellKey{1, 2, -1, 0}));
    EXPECT_EQ(half.keyOf(vec3(-1.0f, 0.49999997f, -0.50000006f), 0), (CellKey{-2, 0, -2, 0}));

    EXPECT_EQ(grid.coarseOf({-1, -25, -26, 4}), (CellKey{-1, -1, -2, 0}));
    EXPECT_EQ(grid.coarseOf({0, 24, 25, 0}), (CellKey{0, 0, 1, 0}));
    EXPECT_EQ(grid.coarseOf({std::numeric_limits<int64_t>::min(), std::numeric_limits<int64_t>::max(), 0, 0}),
              (CellKey{int64_t(-368934881474191033), int64_t(368934881474191032), 0, 0}));
}

TEST(SparseHashGrid, CoarseOfIsFloorDivisionForEveryEdgeAndCoordinate) {
    // Covers both ways the grid divides: a multiply-shift for coordinates within about ±2^30 cells and
    // a 64-bit division beyond, so coordinates around both ends of the fast range are included.
    constexpr int64_t kMin = std::numeric_limits<int64_t>::min(), kMax = std::numeric_limits<int64_t>::max();
    Rng rng(8, 8);
    for (int edge : {1, 2, 3, 7, 25, 254, 255}) {
        SparseHashGridConfig c;
        c.fineCellsPerCoarseEdge = edge;
        const TestGrid grid(c);
        std::vector<int64_t> coordinates = {kMin, kMin + 1, kMax - 1, kMax};
        for (const int64_t centre : {int64_t(0), int64_t(1) << 30, -(int64_t(1) << 30), int64_t(1) << 31, -(int64_t(1) << 31)})
            for (int64_t d = -3 * int64_t(edge) - 2; d <= 3 * int64_t(edge) + 2; d += std::max<int64_t>(1, edge / 64)) coordinates.push_back(centre + d);
        for (int i = 0; i < 2000; ++i) coordinates.push_back(int64_t(uint64_t(rng.next()) << 32 | rng.next()) >> (rng.next() % 64));
        for (const int64_t v : coordinates) {
            int64_t q = v / edge;
            if (v % edge != 0 && v < 0) --q;
            ASSERT_EQ(grid.coarseOf({v, 0, 0, 0}).x, q) << "edge " << edge << ", coordinate " << v;
        }
    }
}

TEST(SparseHashGrid, KeyOfRejectsNonFiniteAndUnrepresentablePositions) {
    TestGrid grid(SparseHashGridConfig{});
    const auto message = [](const SparseHashGrid& g, const vec3& p) -> std::string {
        try {
            g.keyOf(p, 0);
        } catch (const std::exception& e) {
            return e.what();
        }
        return "no error";
    };
    EXPECT_THROW(grid.keyOf(vec3(std::nanf(""), 0.0f, 0.0f), 0), std::invalid_argument);
    EXPECT_EQ(message(grid, vec3(std::nanf(""), 0.0f, 0.0f)), "SparseHashGrid::keyOf: position (nan, 0, 0) is not finite");
    EXPECT_EQ(message(grid, vec3(0.0f, -kInfinity, 1.0f)), "SparseHashGrid::keyOf: position (0, -inf, 1) is not finite");

    SparseHashGridConfig c;
    c.fineCellSize = 1e-30;
    TestGrid tiny(c);
    EXPECT_THROW(tiny.keyOf(vec3(1e10f, 0.0f, 0.0f), 0), std::out_of_range);
    EXPECT_EQ(message(tiny, vec3(0.0f, 0.0f, -1e10f)),
              "SparseHashGrid::keyOf: position (0, 0, -1e+10) has a cell coordinate outside the int64 range at fineCellSize 1e-30");
    c.fineCellSize = 1e-320;  // a subnormal: the quotient overflows to infinity
    EXPECT_THROW(TestGrid(c).keyOf(vec3(1.0f, 0.0f, 0.0f), 0), std::out_of_range);
    EXPECT_EQ(tiny.keyOf(vec3(1e-20f, 0.0f, 0.0f), 0).x, int64_t(std::floor(double(1e-20f) / 1e-30)));
}

TEST(SparseHashGrid, ConstructorRejectsInvalidConfigurations) {
    SparseHashGridConfig c;
    c.fineCellSize = 0.0;
    EXPECT_EQ(constructionError(c), "SparseHashGrid: fineCellSize must be finite and > 0, got 0");
    c.fineCellSize = std::numeric_limits<double>::infinity();
    EXPECT_EQ(constructionError(c), "SparseHashGrid: fineCellSize must be finite and > 0, got inf");
    c = {};
    c.fineCellsPerCoarseEdge = 0;
    EXPECT_EQ(constructionError(c), "SparseHashGrid: fineCellsPerCoarseEdge must be in [1, 255], got 0");
    c.fineCellsPerCoarseEdge = 256;
    EXPECT_EQ(constructionError(c), "SparseHashGrid: fineCellsPerCoarseEdge must be in [1, 255], got 256");
    c = {};
    c.maxCoarseTables = 0;
    EXPECT_EQ(constructionError(c), "SparseHashGrid: maxCoarseTables must be >= 1, got 0");
    c = {};
    c.fineSlotsPerTable = 0;
    EXPECT_EQ(constructionError(c), "SparseHashGrid: fineSlotsPerTable must be >= 1, got 0");
    c = {};
    c.maxProbeLength = 0;
    EXPECT_EQ(constructionError(c), "SparseHashGrid: maxProbeLength must be in [1, fineSlotsPerTable = 32767], got 0");
    c.fineSlotsPerTable = 16;
    c.maxProbeLength = 17;
    EXPECT_EQ(constructionError(c), "SparseHashGrid: maxProbeLength must be in [1, fineSlotsPerTable = 16], got 17");
    c.maxProbeLength = 16;
    EXPECT_EQ(constructionError(c), "no error");
    // Eviction compares when the owner last used each value: a grid that may evict must be able to ask.
    EXPECT_EQ(constructionError(c, nullptr), "SparseHashGrid: LRU eviction needs the entries' last use (lastUsedOf), got none");
    c.policy = FullPolicy::Refuse;
    EXPECT_EQ(constructionError(c, nullptr), "no error");
}

}  // namespace
}  // namespace gibench
