#include "methods/probe_cache/stores/hash_grid/fingerprint_table.h"
#include "methods/probe_cache/stores/hash_grid/hash_grid_store.h"

#include "support/store_test_helpers.h"

#include "core/util/rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <vector>

namespace gibench {
namespace {

using namespace test;  // the store-test helpers (support/store_test_helpers.h)

std::unique_ptr<ProbeStore> makeStore(const Json& block) { return test::makeStore(block, test::storeRow("hash_grid")); }

std::unique_ptr<ProbeStore> preparedStore(const Json& block, const Scene& scene) { return test::prepared(makeStore(block), scene); }

const vec3 kUp(0, 1, 0), kEast(1, 0, 0);

uint64_t stat(const ProbeStore& store, const char* key) { return store.stats().at(key).get<uint64_t>(); }

TEST(HashGridStore, ThePointsOfOneCellShareItsEntryAndOtherCellsOrFacingsGetTheirOwn) {
    // Cells of 0.1 laid from half a cell outside the unit box: [-0.05, 0.05), [0.05, 0.15), ...
    auto store = preparedStore({{"cell_size", 0.1}}, sceneOf({boxMesh(vec3(0), vec3(1))}));
    const ProbeInsert first = store->insert(queryAt({0.51f, 1.0f, 0.52f}, kUp), 0);
    ASSERT_EQ(first.status, ProbeInsert::Status::Inserted);
    for (const vec3 p : {vec3(0.451f, 1.0f, 0.451f), vec3(0.549f, 1.0f, 0.549f), vec3(0.5f, 1.04f, 0.5f)}) {
        uint32_t id = 99;
        ASSERT_TRUE(store->receiverOf(queryAt(p, kUp), id)) << p.x << "," << p.y << "," << p.z;
        EXPECT_EQ(id, first.id);
        EXPECT_EQ(store->insert(queryAt(p, kUp), 0).status, ProbeInsert::Status::Refused) << "its cell has an entry";
    }
    EXPECT_EQ(stat(*store, "cell_occupied"), 3u);
    uint32_t id;
    EXPECT_FALSE(store->receiverOf(queryAt({0.551f, 1.0f, 0.5f}, kUp), id)) << "the next cell along x";
    EXPECT_FALSE(store->receiverOf(queryAt({0.51f, 1.0f, 0.52f}, kEast), id)) << "the same cell, facing +X";
    EXPECT_EQ(store->insert(queryAt({0.551f, 1.0f, 0.5f}, kUp), 0).status, ProbeInsert::Status::Inserted);
    EXPECT_EQ(store->insert(queryAt({0.51f, 1.0f, 0.52f}, kEast), 0).status, ProbeInsert::Status::Inserted);
    EXPECT_EQ(stat(*store, "probes"), 3u);
}

TEST(HashGridStore, ALookupServesOneEntryWithWeightOneAndCoversExactlyWhereTheOwnCellHasOne) {
    auto store = preparedStore({{"cell_size", 0.1}, {"jitter", false}}, sceneOf({boxMesh(vec3(0), vec3(1))}));
    ASSERT_EQ(store->insert(queryAt({0.5f, 1.0f, 0.5f}, kUp), 0).status, ProbeInsert::Status::Inserted);
    ProbeLookup served;
    store->lookup(queryAt({0.46f, 1.0f, 0.54f}, kUp), 4, served);
    ASSERT_EQ(served.count, 1);
    EXPECT_EQ(served.probes[0].id, 0u);
    EXPECT_EQ(served.probes[0].weight, 1.0f);
    EXPECT_TRUE(served.covered);
    EXPECT_NEAR(served.distance, std::sqrt(0.04f * 0.04f * 2.0f), 1e-6f);
    store->lookup(queryAt({0.56f, 1.0f, 0.5f}, kUp), 4, served);
    EXPECT_EQ(served.count, 0) << "a cell with no entry serves nothing, though a probe is 0.06 away";
    EXPECT_FALSE(served.covered);
}

TEST(HashGridStore, JitteredLookupsReadNeighbouringCellsInProportionToTheOverlapAndNeverDependOnThePointsCoordinates) {
    // A point 0.02 inside its cell's +x border, normal +Y: jittered by up to half a cell (0.05)
    // along the tangent axes, it reads the next cell when the jitter along x exceeds 0.02, which a
    // uniform jitter does with probability (0.05 − 0.02) / 0.1 = 0.3.
    auto store = preparedStore({{"cell_size", 0.1}}, sceneOf({boxMesh(vec3(0), vec3(1))}));
    ASSERT_EQ(store->insert(queryAt({0.5f, 1.0f, 0.5f}, kUp), 0).status, ProbeInsert::Status::Inserted);
    ASSERT_EQ(store->insert(queryAt({0.6f, 1.0f, 0.5f}, kUp), 0).status, ProbeInsert::Status::Inserted);
    ASSERT_EQ(store->insert(queryAt({0.4f, 1.0f, 0.5f}, kUp), 0).status, ProbeInsert::Status::Inserted);
    for (int dz = -1; dz <= 1; dz += 2)
        for (int dx = -1; dx <= 1; ++dx) store->insert(queryAt({0.5f + 0.1f * float(dx), 1.0f, 0.5f + 0.1f * float(dz)}, kUp), 0);
    const int n = 20000;
    std::map<uint32_t, int> reads;
    for (int i = 0; i < n; ++i) {
        ProbeQuery q = queryAt({0.53f, 1.0f, 0.5f}, kUp);
        q.jitter = Rng::forPath(1, 0, uint64_t(i), RandomStream::LookupJitter).next();
        ProbeLookup served;
        store->lookup(q, 1, served);
        ASSERT_EQ(served.count, 1);
        EXPECT_TRUE(served.covered);
        ++reads[served.probes[0].id];
    }
    EXPECT_TRUE(store->readsJitter());
    EXPECT_FALSE(preparedStore({{"cell_size", 0.1}, {"jitter", false}}, sceneOf({boxMesh(vec3(0), vec3(1))}))->readsJitter())
        << "without jitter the raster stage need not draw the bits";
    // Frame(+Y)'s tangent axes are ±x and ±z: the x offset is one of them. Binomial spread 0.0032.
    EXPECT_NEAR(double(reads[1]) / n, 0.3, 0.015) << "the cell along +x";
    EXPECT_EQ(reads[2], 0) << "the cell along -x is more than half a cell away";
    // The same bits read the same cell: nothing depends on the point's float bits.
    ProbeQuery q = queryAt({0.53f, 1.0f, 0.5f}, kUp);
    q.jitter = 12345u;
    ProbeLookup a, b;
    store->lookup(q, 1, a);
    store->lookup(q, 1, b);
    EXPECT_EQ(a.probes[0].id, b.probes[0].id);
}

TEST(HashGridStore, CellsGrowWithTheDistanceToTheCameraByLevels) {
    // lod_distance 10 level-0 edges of 0.1: level 0 within 1 of the camera, level 1 (edge 0.2) up
    // to 2, level 2 (edge 0.4) up to 4.
    auto store = preparedStore({{"cell_size", 0.1}, {"lod_distance", 10}}, sceneOf({boxMesh(vec3(-10), vec3(10))}));
    const ProbeQuery near = queryAt({0.5f, 0.0f, 0.0f}, kUp), middle = queryAt({1.5f, 0.0f, 0.0f}, kUp), far = queryAt({3.0f, 0.0f, 0.0f}, kUp);
    EXPECT_FLOAT_EQ(store->coverageRadius(far), 0.1f) << "before the first frame no camera is known: level 0";
    CameraPose pose;
    pose.eye = vec3(0.0f);
    store->beginFrame(pose, 0);
    EXPECT_FLOAT_EQ(store->coverageRadius(near), 0.1f);
    EXPECT_FLOAT_EQ(store->coverageRadius(middle), 0.2f);
    EXPECT_FLOAT_EQ(store->coverageRadius(far), 0.4f);
    EXPECT_FLOAT_EQ(store->searchRadius(far), kSearchRings * 0.4f);
    // At level 2 one entry serves 0.4 of the surface: points 0.3 apart share it.
    ASSERT_EQ(store->insert(queryAt({3.0f, 0.0f, 0.01f}, kUp), 0).status, ProbeInsert::Status::Inserted);
    uint32_t id;
    EXPECT_TRUE(store->receiverOf(queryAt({3.0f, 0.0f, 0.31f}, kUp), id));
}

TEST(HashGridStore, EntriesNoUpdateReachedForMoreThanStaleFramesAreEvictedAndTheirIdsReused) {
    auto store = preparedStore({{"cell_size", 0.1}, {"stale_frames", 4}}, sceneOf({boxMesh(vec3(0), vec3(1))}));
    CameraPose pose;
    pose.eye = vec3(0.5f, 0.5f, -1.0f);
    store->beginFrame(pose, 0);
    const ProbeQuery kept = queryAt({0.2f, 1.0f, 0.2f}, kUp), stale = queryAt({0.8f, 1.0f, 0.8f}, kUp);
    ASSERT_EQ(store->insert(kept, 0).status, ProbeInsert::Status::Inserted);
    const ProbeInsert old = store->insert(stale, 0);
    ASSERT_EQ(old.status, ProbeInsert::Status::Inserted);
    for (uint32_t frame = 1; frame <= 5; ++frame) {
        store->beginFrame(pose, frame);
        store->touch(0, frame);
        uint32_t id;
        EXPECT_EQ(store->receiverOf(stale, id), frame <= 4) << "frame " << frame << ": last updated in frame 0, stale after 4";
        EXPECT_TRUE(store->receiverOf(kept, id)) << "frame " << frame;
    }
    EXPECT_EQ(stat(*store, "stale_evictions"), 1u);
    EXPECT_EQ(stat(*store, "probes"), 1u);
    const ProbeInsert reused = store->insert(queryAt({0.5f, 1.0f, 0.5f}, kUp), 5);
    EXPECT_EQ(reused.status, ProbeInsert::Status::Evicted) << "a reused id: the pipeline must reset its cache";
    EXPECT_EQ(reused.id, old.id);
    EXPECT_EQ(store->idCapacity(), 2u);
}

TEST(HashGridStore, AFullTableRefusesAndCountsCollisionsAndEveryStoredKeyStaysFindable) {
    // 8 slots probed 8 deep: the ninth entry finds no room.
    auto store = preparedStore({{"cell_size", 0.1}, {"table_slots", 8}, {"max_probe_length", 8}}, sceneOf({boxMesh(vec3(0), vec3(1))}));
    std::vector<ProbeQuery> placed;
    for (int i = 0; i < 9; ++i) {
        const ProbeQuery q = queryAt({0.1f * float(i) + 0.1f, 1.0f, 0.5f}, kUp);  // a cell centre each
        const ProbeInsert r = store->insert(q, 0);
        if (i < 8) {
            ASSERT_EQ(r.status, ProbeInsert::Status::Inserted) << i;
            placed.push_back(q);
        } else {
            EXPECT_EQ(r.status, ProbeInsert::Status::Refused);
        }
    }
    EXPECT_EQ(stat(*store, "table_full"), 1u);
    // Eight keys in eight slots: every insert after the first home collision stepped over others.
    EXPECT_GE(stat(*store, "collisions"), 8u);
    EXPECT_DOUBLE_EQ(store->stats()["table_load"].get<double>(), 1.0);
    for (std::size_t i = 0; i < placed.size(); ++i) {
        uint32_t id;
        ASSERT_TRUE(store->receiverOf(placed[i], id)) << i;
        EXPECT_EQ(id, uint32_t(i));
    }
}

TEST(HashGridStore, KeysOneMillionUnitsFromTheOriginAndTinyCellsStayDistinct) {
    // Float positions near 1e6 are 0.0625 apart; cells of 1 (the finest ProbeSpacing admits that
    // far out) there still tell neighbours apart.
    {
        auto store = preparedStore({{"cell_size", 1.0}}, sceneOf({boxMesh(vec3(1e6f), vec3(1e6f + 8.0f))}));
        const vec3 base(1e6f + 4.0f, 1e6f + 8.0f, 1e6f + 4.0f);
        ASSERT_EQ(store->insert(queryAt(base, kUp), 0).status, ProbeInsert::Status::Inserted);
        uint32_t id;
        EXPECT_TRUE(store->receiverOf(queryAt(base + vec3(0.0625f, 0, 0), kUp), id));
        EXPECT_FALSE(store->receiverOf(queryAt(base + vec3(1.0f, 0, 0), kUp), id)) << "the next cell";
        EXPECT_EQ(store->insert(queryAt(base + vec3(1.0f, 0, 0), kUp), 0).status, ProbeInsert::Status::Inserted);
    }
    {
        auto store = preparedStore({{"cell_size", 1e-7}}, sceneOf({boxMesh(vec3(0), vec3(1e-5f))}));
        const vec3 base(5e-6f, 1e-5f, 5e-6f);
        ASSERT_EQ(store->insert(queryAt(base, kUp), 0).status, ProbeInsert::Status::Inserted);
        uint32_t id;
        EXPECT_TRUE(store->receiverOf(queryAt(base + vec3(1e-8f, 0, 0), kUp), id));
        EXPECT_FALSE(store->receiverOf(queryAt(base + vec3(1e-7f, 0, 0), kUp), id)) << "the next cell";
    }
}

TEST(FingerprintTable, ErasingShiftsEntriesBackSoThatEveryKeyLeftIsFoundWithinItsReach) {
    // Keys named by hashes chosen to pile up on few home slots of a 16-slot table; after erasing
    // any subset, the rest must still be found, and only where the reach allows.
    const uint32_t slots = 16;
    FingerprintTable table(slots, slots);
    std::vector<uint64_t> hashes;
    for (uint32_t i = 0; i < 12; ++i) hashes.push_back((uint64_t(0x9e3779b9u * (i + 1)) << 32) | (i % 3 == 0 ? 5u : 6u + i % 2));
    const auto homeOfId = [&](uint32_t id) { return table.homeOf(hashes[id]); };
    for (uint32_t id = 0; id < hashes.size(); ++id) ASSERT_TRUE(table.insert(hashes[id], id));
    EXPECT_GT(table.collisions(), 0u);
    std::vector<bool> erased(hashes.size(), false);
    for (const uint32_t id : {4u, 0u, 9u, 6u, 3u}) {
        table.erase(hashes[id], id, homeOfId);
        erased[id] = true;
        for (uint32_t other = 0; other < hashes.size(); ++other) {
            uint32_t found = 99;
            const bool present = table.find(hashes[other], [&](uint32_t candidate) { return candidate == other; }, found);
            EXPECT_EQ(present, !erased[other]) << "after erasing " << id << ", key " << other;
            if (present) {
                EXPECT_EQ(found, other);
            }
        }
    }
    EXPECT_EQ(table.used(), hashes.size() - 5);
}

TEST(FingerprintTable, AMatchingFingerprintOfAnotherKeyIsCountedAndNotTakenForIt) {
    FingerprintTable table(8, 8);
    const uint64_t hash = 0xabcdef0100000003ull;
    ASSERT_TRUE(table.insert(hash, 7));
    uint32_t id = 0;
    // The same hash, so the same fingerprint, but the owner's key check says it is another key.
    EXPECT_FALSE(table.find(hash, [](uint32_t) { return false; }, id));
    EXPECT_EQ(table.fingerprintCollisions(), 1u);
    EXPECT_TRUE(table.find(hash, [](uint32_t candidate) { return candidate == 7; }, id));
    EXPECT_EQ(id, 7u);
}

}  // namespace
}  // namespace gibench
