// What only the "mamba" store does: one probe per fine cell, the facing tag, and how a full hash
// table or probe pool degrades (evict or refuse, counted in stats). The behaviour every store shares
// is in tests/methods/probe_cache/store_contract_test.cpp; the hash grid under the store has its own
// tests (sparse_hash_grid_test.cpp).

#include "methods/probe_cache/stores/mamba/mamba_store.h"
#include "methods/probe_cache/stores/mamba/sparse_hash_grid.h"

#include "core/util/rng.h"
#include "support/store_test_helpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace gibench {
namespace {

using namespace test;  // the store-test helpers (support/store_test_helpers.h)

std::unique_ptr<ProbeStore> makeStore(const Json& block) { return test::makeStore(block, test::storeRow("mamba")); }

std::unique_ptr<ProbeStore> preparedStore(Json block, const Scene& scene) {
    if (!block.contains("fine_cell_size")) block["fine_cell_size"] = 0.1;
    return test::prepared(makeStore(block), scene);
}

const vec3 kUp(0, 1, 0), kEast(1, 0, 0), kWest(-1, 0, 0);

Scene unitBox() { return sceneOf({boxMesh(vec3(0), vec3(1))}); }
ProbeQuery onTop(float x, float z) { return queryAt({x, 1.0f, z}, kUp); }

TEST(MambaStore, OneProbePerFineCellASecondInsertThereIsRefusedAsCellOccupied) {
    auto store = preparedStore(Json::object(), unitBox());
    ASSERT_EQ(store->insert(onTop(0.52f, 0.47f), 0).status, ProbeInsert::Status::Inserted);
    // Fine cells are [0.5, 0.6) × [0.4, 0.5) here: the same cell.
    EXPECT_EQ(store->insert(onTop(0.55f, 0.43f), 0).status, ProbeInsert::Status::Refused);
    const std::vector<ProbeNeighbour> found = nearestOf(*store, onTop(0.55f, 0.43f), 4);
    ASSERT_EQ(found.size(), 1u) << "the cell's probe serves the point it refused";
    EXPECT_EQ(found[0].id, 0u);
    Json stats = store->stats();
    EXPECT_EQ(stats["cell_occupied"], 1);
    EXPECT_EQ(stats["probes"], 1);

    EXPECT_EQ(store->insert(onTop(0.62f, 0.47f), 0).status, ProbeInsert::Status::Inserted) << "the next cell";
    // The same point facing +X is another cell: the normal's dominant direction is part of the key.
    EXPECT_EQ(store->insert(queryAt({0.52f, 1.0f, 0.47f}, kEast), 0).status, ProbeInsert::Status::Inserted);
    stats = store->stats();
    EXPECT_EQ(stats["cell_occupied"], 1);
    EXPECT_EQ(stats["probes"], 3);
    EXPECT_EQ(stats["fine_cell_size"], 0.1f);
}

TEST(MambaStore, InvalidQueriesAreCountedApart) {
    auto store = preparedStore(Json::object(), unitBox());
    const float nan = std::nanf("");
    EXPECT_EQ(store->insert(queryAt({nan, 1.0f, 0.5f}, kUp), 0).status, ProbeInsert::Status::Refused);
    EXPECT_EQ(store->insert(queryAt({0.5f, 1.0f, 0.5f}, {0, kInfinity, 0}), 0).status, ProbeInsert::Status::Refused);
    const Json stats = store->stats();
    EXPECT_EQ(stats["refused_invalid"], 2);
    EXPECT_EQ(stats["cell_occupied"], 0);
    EXPECT_EQ(stats["table_refused"], 0);
    EXPECT_EQ(stats["pool_full"], 0);
}

TEST(MambaStore, AFinitePointTooFarOutForACellCoordinateIsRefusedNotThrown) {
    // 1e18 / 0.1 cells is past the int64 range of a cell coordinate (issue 8: this threw
    // std::out_of_range out of insert() and nearest()).
    auto store = preparedStore(Json::object(), unitBox());
    const ProbeQuery far = queryAt({1e18f, 1.0f, 0.5f}, kUp);
    EXPECT_EQ(errorOf([&] { EXPECT_EQ(store->insert(far, 0).status, ProbeInsert::Status::Refused); }), "");
    EXPECT_EQ(errorOf([&] { EXPECT_EQ(nearestOf(*store, far, 4).size(), 0u); }), "");
    EXPECT_EQ(store->stats()["refused_invalid"], 1);
}

TEST(MambaStore, LimitsThatCouldNeedMoreThanHalfTheMachinesMemoryAreRefusedUpFront) {
    // 2^20 tables × 2^22 slots × 8 B = 32 TiB: refused when the store is built, before any table.
    const std::string message = errorOf([] { makeStore({{"max_coarse_tables", 1 << 20}, {"fine_slots_per_table", 1 << 22}}); });
    EXPECT_EQ(message.rfind("cfg.json: /method/fine_slots_per_table: max_coarse_tables × fine_slots_per_table × 8 B = 32768 GiB of tables", 0),
              0u)
        << message;
    EXPECT_NE(message.find("more than half of this machine's"), std::string::npos) << message;
    EXPECT_EQ(errorOf([] { makeStore(Json::object()); }), "") << "the original constants: 0.5 GiB of tables at most";
}

TEST(MambaStore, WithoutTheFacingTagTheTwoSidesOfAThinWallShareOneProbe) {
    // A wall 0.001 thick inside fine cell [0.4, 0.5) on x: both faces fall into the same cells.
    const Scene room = sceneOf({boxMesh(vec3(0), vec3(1)), boxMesh({0.4495f, 0, 0}, {0.4505f, 1, 1})});
    const ProbeQuery east = queryAt({0.4505f, 0.55f, 0.55f}, kEast, 1), west = queryAt({0.4495f, 0.55f, 0.55f}, kWest, 1);

    // The original's shared probes: the west side is served by the east side's probe.
    auto shared = preparedStore({{"facing", false}}, room);
    ASSERT_EQ(shared->insert(east, 0).status, ProbeInsert::Status::Inserted);
    const std::vector<ProbeNeighbour> found = nearestOf(*shared, west, 4);
    ASSERT_EQ(found.size(), 1u);
    EXPECT_EQ(found[0].id, 0u);
    EXPECT_NEAR(found[0].distance, 0.001f, 1e-6f);  // the wall's thickness, up to the rounding of 0.4495 and 0.4505
    EXPECT_EQ(shared->insert(west, 0).status, ProbeInsert::Status::Refused);
    EXPECT_EQ(shared->stats()["cell_occupied"], 1);

    // With the tag (the default), each side has its own cell.
    auto tagged = preparedStore(Json::object(), room);
    ASSERT_EQ(tagged->insert(east, 0).status, ProbeInsert::Status::Inserted);
    EXPECT_EQ(nearestOf(*tagged, west, 4).size(), 0u);
    EXPECT_EQ(tagged->insert(west, 0).status, ProbeInsert::Status::Inserted);
    EXPECT_EQ(tagged->stats()["cell_occupied"], 0);
}

// Three probes in one coarse cell, more than 0.2 (searchRadius()) apart; a second-level table of
// two slots holds only two of them.
const ProbeQuery kA = onTop(0.15f, 0.15f), kB = onTop(0.85f, 0.15f), kC = onTop(0.5f, 0.85f);
const Json kTwoSlots = {{"fine_slots_per_table", 2}, {"max_probe_length", 2}};

TEST(MambaStore, AFullTableUnderRefuseRefusesAndCountsIt) {
    Json block = kTwoSlots;
    block["full_policy"] = "refuse";
    auto store = preparedStore(block, unitBox());
    ASSERT_EQ(store->insert(kA, 0).status, ProbeInsert::Status::Inserted);
    ASSERT_EQ(store->insert(kB, 1).status, ProbeInsert::Status::Inserted);
    EXPECT_EQ(store->insert(kC, 2).status, ProbeInsert::Status::Refused);
    EXPECT_EQ(nearestOf(*store, kC, 4).size(), 0u);
    ASSERT_EQ(nearestOf(*store, kA, 4).size(), 1u) << "the probes already there stay";
    const Json stats = store->stats();
    EXPECT_EQ(stats["table_refused"], 1);
    EXPECT_EQ(stats["table_evictions"], 0);
    EXPECT_EQ(stats["probes"], 2);
    EXPECT_EQ(store->idCapacity(), 2u);
}

TEST(MambaStore, AFullTableUnderEvictGivesTheLeastRecentlyUpdatedProbesIdToTheNewOne) {
    auto store = preparedStore(kTwoSlots, unitBox());  // full_policy "evict" by default
    ASSERT_EQ(store->insert(kA, 0).status, ProbeInsert::Status::Inserted);
    ASSERT_EQ(store->insert(kB, 1).status, ProbeInsert::Status::Inserted);
    const ProbeInsert c = store->insert(kC, 2);
    ASSERT_EQ(c.status, ProbeInsert::Status::Evicted);
    EXPECT_EQ(c.id, 0u) << "A, last updated in frame 0";
    EXPECT_EQ(store->probe(0).position, kC.position);
    EXPECT_EQ(nearestOf(*store, kA, 4).size(), 0u) << "A is gone";
    const std::vector<ProbeNeighbour> atC = nearestOf(*store, kC, 4);
    ASSERT_EQ(atC.size(), 1u);
    EXPECT_EQ(atC[0].id, 0u);
    Json stats = store->stats();
    EXPECT_EQ(stats["table_evictions"], 1);
    EXPECT_EQ(stats["table_refused"], 0);
    EXPECT_EQ(stats["probes"], 2);
    EXPECT_EQ(store->idCapacity(), 2u);

    // touch() marks an update: B, touched after C's insert, outlives C.
    store->touch(1, 5);
    const ProbeInsert a = store->insert(kA, 6);
    ASSERT_EQ(a.status, ProbeInsert::Status::Evicted);
    EXPECT_EQ(a.id, 0u) << "C, last updated in frame 2, before B's touch in frame 5";
    EXPECT_EQ(store->probe(1).position, kB.position);
    EXPECT_EQ(store->stats()["table_evictions"], 2);
}

TEST(MambaStore, AFullProbePoolEvictsAProbeNotUpdatedLastFrameOrRefuses) {
    const Json pool = {{"max_probes", 2}};
    auto evicting = preparedStore(pool, unitBox());
    ASSERT_EQ(evicting->insert(kA, 0).status, ProbeInsert::Status::Inserted);
    ASSERT_EQ(evicting->insert(kB, 0).status, ProbeInsert::Status::Inserted);
    EXPECT_EQ(evicting->insert(kC, 1).status, ProbeInsert::Status::Refused) << "both were updated in the last frame";
    EXPECT_EQ(evicting->stats()["pool_full"], 1);
    const ProbeInsert c = evicting->insert(kC, 5);
    ASSERT_EQ(c.status, ProbeInsert::Status::Evicted);
    EXPECT_LT(c.id, 2u);
    EXPECT_EQ(evicting->probe(c.id).position, kC.position);
    EXPECT_EQ(nearestOf(*evicting, c.id == 0 ? kA : kB, 4).size(), 0u) << "the evicted probe is no longer found";
    Json stats = evicting->stats();
    EXPECT_EQ(stats["table_evictions"], 1);
    EXPECT_EQ(stats["pool_full"], 1);
    EXPECT_EQ(stats["probes"], 2);
    EXPECT_EQ(evicting->idCapacity(), 2u);

    Json block = pool;
    block["full_policy"] = "refuse";
    auto refusing = preparedStore(block, unitBox());
    ASSERT_EQ(refusing->insert(kA, 0).status, ProbeInsert::Status::Inserted);
    ASSERT_EQ(refusing->insert(kB, 0).status, ProbeInsert::Status::Inserted);
    EXPECT_EQ(refusing->insert(kC, 5).status, ProbeInsert::Status::Refused);
    stats = refusing->stats();
    EXPECT_EQ(stats["pool_full"], 1);
    EXPECT_EQ(stats["table_evictions"], 0);
    EXPECT_EQ(stats["probes"], 2);
}

TEST(MambaStore, ANewCoarseCellBeyondMaxCoarseTablesIsRefusedUnderEitherPolicy) {
    for (const char* policy : {"evict", "refuse"}) {
        // Coarse cells of 5 fine cells, 0.5 units: A and B are in different ones.
        auto store = preparedStore({{"fine_cells_per_coarse_edge", 5}, {"max_coarse_tables", 1}, {"full_policy", policy}}, unitBox());
        ASSERT_EQ(store->insert(onTop(0.15f, 0.15f), 0).status, ProbeInsert::Status::Inserted) << policy;
        EXPECT_EQ(store->insert(onTop(0.35f, 0.35f), 0).status, ProbeInsert::Status::Inserted) << policy << ": the same coarse cell";
        EXPECT_EQ(store->insert(onTop(0.85f, 0.85f), 0).status, ProbeInsert::Status::Refused) << policy;
        const Json stats = store->stats();
        EXPECT_EQ(stats["table_refused"], 1) << policy;
        EXPECT_EQ(stats["coarse_tables"], 1) << policy;
        EXPECT_EQ(stats["probes"], 2) << policy;
    }
}

TEST(MambaStore, BytesGrowWithOccupiedCoarseCellsNotTheSceneVolume) {
    // A second-level table starts at 64 slots × 8 bytes when its coarse cell (25 fine cells,
    // 2.5 units) gets its first probe.
    const Json block = {{"fine_slots_per_table", 1000}};
    const double table = SparseHashGrid::kInitialFineSlots * 8;
    const auto bytes = [](const ProbeStore& s) { return s.stats()["store_bytes"].get<double>(); };
    auto small = preparedStore(block, unitBox());
    auto large = preparedStore(block, sceneOf({boxMesh(vec3(0), vec3(100))}));
    EXPECT_EQ(bytes(*small), bytes(*large)) << "nothing is allocated for the volume of the bounds";

    const double empty = bytes(*large);
    ASSERT_EQ(large->insert(queryAt({0.5f, 100.0f, 0.5f}, kUp), 0).status, ProbeInsert::Status::Inserted);
    const double one = bytes(*large);
    EXPECT_GE(one - empty, table) << "the first probe's coarse cell gets a table";
    ASSERT_EQ(large->insert(queryAt({0.9f, 100.0f, 0.5f}, kUp), 0).status, ProbeInsert::Status::Inserted);
    const double two = bytes(*large);
    EXPECT_LT(two - one, table) << "a probe in the same coarse cell needs no table";
    ASSERT_EQ(large->insert(queryAt({50.5f, 100.0f, 50.5f}, kUp), 0).status, ProbeInsert::Status::Inserted);
    EXPECT_GE(bytes(*large) - two, table) << "a probe 50 units away: another table";
    EXPECT_EQ(large->stats()["coarse_tables"], 2);
}

// nearest() and nearestBatch() against their definition, brute force over every probe: the count
// nearest probes of the query's facing within searchRadius, ranked by (distance, id). Batches of a
// tile's size take the tile-region path (the region's probes offered to the queries in SIMD
// lanes), a batch spanning two whole faces (per face a box of 104 × 104 × 5 cells of 0.01, more
// than a region holds) the per-cell blocks; single queries take the inner 27 cells first and the
// outer ring when it may hold a nearer probe (issue 9). Also 1000 units from the origin, where
// cell faces are placed in double.
TEST(MambaStore, SingleAndBatchedNearestAreTheBruteForceNearest) {
    for (const float offset : {0.0f, 1000.0f}) {
        const vec3 shift(offset);
        auto store = preparedStore({{"fine_cell_size", 0.01}}, sceneOf({boxMesh(shift, shift + vec3(1))}));
        Rng rng(3, uint64_t(offset));
        const auto onFace = [&](int face, float a, float b) {
            return face == 0 ? queryAt(shift + vec3(a, 1.0f, b), kUp) : queryAt(shift + vec3(1.0f, a, b), kEast);
        };
        for (int i = 0; i < 8000; ++i) store->insert(onFace(i % 2, rng.uniform(), rng.uniform()), 0);
        std::vector<ProbeQuery> queries;
        for (int face = 0; face < 2; ++face)
            for (int row = 0; row < 48; ++row)
                for (int column = 0; column < 48; ++column)
                    queries.push_back(onFace(face, (float(column) + rng.uniform()) / 48.0f, (float(row) + rng.uniform()) / 48.0f));
        const float radius = store->searchRadius(queries[0]);
        for (const int count : {1, 2, 4}) {
            const auto bruteForce = [&](const ProbeQuery& q) {
                std::vector<ProbeNeighbour> all;
                for (uint32_t id = 0; id < store->idCapacity(); ++id) {
                    const Probe& p = store->probe(id);
                    const float d = glm::length(p.position - q.position);
                    if (p.normal == q.normal && d <= radius) all.push_back({id, d});
                }
                std::sort(all.begin(), all.end(), [](const ProbeNeighbour& a, const ProbeNeighbour& b) {
                    return a.distance < b.distance || (a.distance == b.distance && a.id < b.id);
                });
                all.resize(std::min<std::size_t>(all.size(), std::size_t(count)));
                return all;
            };
            for (const int batchSize : {16, int(queries.size())}) {
                std::vector<ProbeNeighbour> batched(queries.size() * std::size_t(count));
                std::vector<int> found(queries.size());
                for (std::size_t first = 0; first < queries.size(); first += std::size_t(batchSize)) {
                    const int n = int(std::min(queries.size() - first, std::size_t(batchSize)));
                    store->nearestBatch(queries.data() + first, n, count, batched.data() + first * count, found.data() + first);
                }
                int checked = 0;
                for (std::size_t i = 0; i < queries.size(); ++i) {
                    const std::vector<ProbeNeighbour> expected = bruteForce(queries[i]), single = nearestOf(*store, queries[i], count);
                    ASSERT_EQ(single.size(), expected.size()) << "offset " << offset << " query " << i << " count " << count;
                    ASSERT_EQ(std::size_t(found[i]), expected.size()) << "offset " << offset << " query " << i << " batch " << batchSize;
                    for (std::size_t k = 0; k < expected.size(); ++k) {
                        EXPECT_EQ(single[k].id, expected[k].id) << "offset " << offset << " query " << i << " rank " << k;
                        EXPECT_EQ(single[k].distance, expected[k].distance) << "offset " << offset << " query " << i;
                        EXPECT_EQ(batched[i * count + k].id, expected[k].id) << "offset " << offset << " query " << i << " batch " << batchSize;
                        EXPECT_EQ(batched[i * count + k].distance, expected[k].distance) << "offset " << offset << " query " << i;
                    }
                    checked += int(expected.size());
                }
                EXPECT_GT(checked, int(queries.size()) * count / 2) << "most queries have probes within reach";
            }
        }
    }
}

TEST(MambaStore, MaxProbeLengthBeyondTheTableIsAnInputErrorNamingTheKey) {
    EXPECT_EQ(errorOf([] { makeStore({{"fine_slots_per_table", 16}}); }),
              "cfg.json: /method/max_probe_length: expected at most fine_slots_per_table (16), got 32");
    EXPECT_EQ(errorOf([] { makeStore({{"fine_slots_per_table", 16}, {"max_probe_length", 16}}); }), "");
    EXPECT_EQ(errorOf([] { makeStore({{"full_policy", "lru"}}); }),
              "cfg.json: /method/full_policy: expected one of \"evict\", \"refuse\", got \"lru\"");
}

}  // namespace
}  // namespace gibench
