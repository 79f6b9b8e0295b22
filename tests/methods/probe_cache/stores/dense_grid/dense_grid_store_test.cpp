#include "methods/probe_cache/stores/dense_grid/dense_grid_store.h"

#include "support/store_test_helpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

namespace gibench {
namespace {

using test::boxMesh;
using test::errorOf;
using test::queryAt;
using test::sceneOf;

std::unique_ptr<ProbeStore> makeStore(const Json& block) { return test::makeStore(block, "dense_grid", denseGridStoreParams(), &createDenseGridStore); }

std::unique_ptr<ProbeStore> preparedStore(const Json& block, const Scene& scene) {
    auto store = makeStore(block);
    RunNotes notes;
    store->prepare(scene, notes);
    return store;
}

const vec3 kUp(0, 1, 0);

TEST(DenseGridStore, InsertedProbeIsFoundByNearestWhereTheQueryPlacedIt) {
    auto store = preparedStore({{"cell_size", 0.1}}, sceneOf({boxMesh(vec3(0), vec3(1))}));
    EXPECT_EQ(store->idCapacity(), 0u);
    const ProbeInsert result = store->insert(queryAt({0.52f, 0.0f, 0.47f}, kUp), 0);
    ASSERT_EQ(result.status, ProbeInsert::Status::Inserted);
    EXPECT_EQ(result.id, 0u);
    EXPECT_EQ(store->idCapacity(), 1u);
    EXPECT_EQ(store->probe(0).position, vec3(0.52f, 0.0f, 0.47f));
    EXPECT_EQ(store->probe(0).normal, kUp);

    ProbeNeighbour found[4];
    ASSERT_EQ(store->nearest(queryAt({0.55f, 0.0f, 0.43f}, kUp), 4, found), 1);
    EXPECT_EQ(found[0].id, 0u);
    EXPECT_NEAR(found[0].distance, 0.05f, 1e-6f);
    EXPECT_EQ(store->insert(queryAt({0.2f, 0.0f, 0.2f}, kUp), 0).id, 1u) << "ids are dense from 0";
    EXPECT_EQ(store->stats()["probes"], 2);
}

TEST(DenseGridStore, NearestIsEveryFacingProbeWithinSearchRadiusNearestFirstAtMostCount) {
    auto store = preparedStore({{"cell_size", 0.1}, {"max_probes_per_cell", 64}}, sceneOf({boxMesh(vec3(0), vec3(1))}));
    // A lattice of probes on the floor, 0.03 apart, a quarter of them facing away.
    for (int i = 0; i <= 30; ++i)
        for (int k = 0; k <= 30; ++k) {
            const vec3 normal = (i + k) % 4 == 0 ? -kUp : kUp;
            ASSERT_EQ(store->insert(queryAt({0.05f + 0.03f * i, 0.0f, 0.05f + 0.03f * k}, normal), 0).status,
                      ProbeInsert::Status::Inserted);
        }
    const float radius = store->searchRadius();
    EXPECT_FLOAT_EQ(radius, 2 * 0.1f);  // kSearchRings cell edges
    for (int qi = 0; qi < 13; ++qi)
        for (int qk = 0; qk < 13; ++qk) {
            const ProbeQuery query = queryAt({0.013f + 0.077f * qi, 0.004f * (qi % 3), 0.021f + 0.074f * qk}, kUp);
            // Brute force over every probe: the searched cells must miss none within the radius.
            std::vector<ProbeNeighbour> expected;
            for (uint32_t id = 0; id < store->idCapacity(); ++id) {
                const Probe& p = store->probe(id);
                const float d = glm::length(p.position - query.position);
                if (glm::dot(p.normal, query.normal) > 0.5f && d <= radius) expected.push_back({id, d});
            }
            std::sort(expected.begin(), expected.end(), [](const ProbeNeighbour& a, const ProbeNeighbour& b) {
                return a.distance < b.distance || (a.distance == b.distance && a.id < b.id);
            });
            for (const int count : {1, 2, 5, 1000}) {
                std::vector<ProbeNeighbour> found(static_cast<std::size_t>(count));
                const int n = store->nearest(query, count, found.data());
                ASSERT_EQ(n, std::min<int>(count, int(expected.size()))) << "query " << qi << "," << qk << " count " << count;
                std::set<uint32_t> ids;
                for (int i = 0; i < n; ++i) {
                    EXPECT_EQ(found[i].id, expected[i].id) << "query " << qi << "," << qk << " rank " << i;
                    EXPECT_FLOAT_EQ(found[i].distance, expected[i].distance);
                    EXPECT_LE(found[i].distance, radius);
                    if (i > 0) {
                        EXPECT_LE(found[i - 1].distance, found[i].distance);
                    }
                    ids.insert(found[i].id);
                }
                EXPECT_EQ(int(ids.size()), n) << "distinct ids";
            }
        }
    ProbeNeighbour unused;
    EXPECT_EQ(store->nearest(queryAt({0.5f, 0.0f, 0.5f}, kUp), 0, &unused), 0);
}

TEST(DenseGridStore, TheTwoSidesOfAThinWallNeverShareAProbe) {
    // A wall 0.02 thick inside a room, much thinner than a cell: both sides share cells.
    auto store = preparedStore({{"cell_size", 0.1}}, sceneOf({boxMesh(vec3(0), vec3(1)), boxMesh({0.49f, 0, 0}, {0.51f, 1, 1})}));
    const vec3 east(1, 0, 0), west(-1, 0, 0);
    std::vector<uint32_t> eastIds, westIds;
    for (int i = 0; i < 5; ++i) {
        const float y = 0.1f + 0.2f * i, z = 0.9f - 0.2f * i;
        const ProbeInsert e = store->insert(queryAt({0.51f, y, z}, east, 1), 0);
        ASSERT_EQ(e.status, ProbeInsert::Status::Inserted);
        eastIds.push_back(e.id);
        ProbeNeighbour found[4];
        EXPECT_EQ(store->nearest(queryAt({0.49f, y, z}, west, 1), 4, found), 0) << "the west side sees no east probe, y " << y;
        const ProbeInsert w = store->insert(queryAt({0.49f, y, z}, west, 1), 0);
        ASSERT_EQ(w.status, ProbeInsert::Status::Inserted);
        westIds.push_back(w.id);
    }
    for (int i = 0; i < 5; ++i) {
        const float y = 0.1f + 0.2f * i, z = 0.9f - 0.2f * i;
        ProbeNeighbour found[4];
        ASSERT_EQ(store->nearest(queryAt({0.51f, y, z}, east, 1), 4, found), 1);
        EXPECT_EQ(found[0].id, eastIds[i]);
        ASSERT_EQ(store->nearest(queryAt({0.49f, y, z}, west, 1), 4, found), 1);
        EXPECT_EQ(found[0].id, westIds[i]);
    }
}

TEST(DenseGridStore, AFullCellRefusesInsertsAndCountsThem) {
    auto store = preparedStore({{"cell_size", 0.1}, {"max_probes_per_cell", 2}}, sceneOf({boxMesh(vec3(0), vec3(1))}));
    // Cells start half a cell below the bounds: [0.45, 0.55) holds all three points.
    EXPECT_EQ(store->insert(queryAt({0.46f, 0.0f, 0.5f}, kUp), 0).status, ProbeInsert::Status::Inserted);
    EXPECT_EQ(store->insert(queryAt({0.50f, 0.0f, 0.5f}, kUp), 0).status, ProbeInsert::Status::Inserted);
    EXPECT_EQ(store->insert(queryAt({0.54f, 0.0f, 0.5f}, kUp), 0).status, ProbeInsert::Status::Refused);
    EXPECT_EQ(store->insert(queryAt({0.56f, 0.0f, 0.5f}, kUp), 0).status, ProbeInsert::Status::Inserted) << "the next cell has room";
    const Json stats = store->stats();
    EXPECT_EQ(stats["probes"], 3);
    EXPECT_EQ(stats["cell_full"], 1);
    EXPECT_EQ(stats["refused"], 1);
    EXPECT_EQ(stats["outside_grid"], 0);
    EXPECT_EQ(stats["max_occupancy"], 2);
    EXPECT_EQ(stats["occupied_cells"], 2);
    EXPECT_DOUBLE_EQ(stats["mean_occupancy"].get<double>(), 3.0 / (11.0 * 11.0 * 11.0));
    EXPECT_EQ(store->idCapacity(), 3u);
}

TEST(DenseGridStore, PointsOutsideTheGridAndInvalidQueriesAreRefusedAndCountedApart) {
    auto store = preparedStore({{"cell_size", 0.1}}, sceneOf({boxMesh(vec3(0), vec3(1))}));
    const float nan = std::nanf(""), inf = kInfinity;
    // The grid covers [-0.05, 1.05]³: a rounding error off the bounds is inside.
    EXPECT_EQ(store->insert(queryAt({1.0f + 1e-6f, 0.5f, 0.5f}, {1, 0, 0}), 0).status, ProbeInsert::Status::Inserted);
    for (const vec3 p : {vec3(1.2f, 0.5f, 0.5f), vec3(-1e30f, 0.5f, 0.5f), vec3(0.5f, 3e38f, 0.5f)}) {
        EXPECT_EQ(store->insert(queryAt(p, kUp), 0).status, ProbeInsert::Status::Refused) << p.x << "," << p.y;
        ProbeNeighbour found;
        EXPECT_EQ(store->nearest(queryAt(p, kUp), 1, &found), 0);
    }
    const ProbeQuery invalid[] = {queryAt({nan, 0.5f, 0.5f}, kUp), queryAt({0.5f, inf, 0.5f}, kUp), queryAt({0.5f, 0.5f, 0.5f}, {nan, 1, 0}),
                                  queryAt({0.5f, 0.5f, 0.5f}, kUp, -1)};
    for (const ProbeQuery& q : invalid) {
        EXPECT_EQ(store->insert(q, 0).status, ProbeInsert::Status::Refused);
        ProbeNeighbour found;
        EXPECT_EQ(store->nearest(q, 1, &found), 0);
    }
    const Json stats = store->stats();
    EXPECT_EQ(stats["outside_grid"], 3);
    EXPECT_EQ(stats["invalid_queries"], 4);
    EXPECT_EQ(stats["cell_full"], 0);
    EXPECT_EQ(stats["refused"], 7);
    EXPECT_EQ(stats["probes"], 1);

    // A query just outside the grid still finds the probe on its border.
    ProbeNeighbour found;
    ASSERT_EQ(store->nearest(queryAt({1.07f, 0.5f, 0.5f}, {1, 0, 0}), 1, &found), 1);
    EXPECT_EQ(found.id, 0u);
}

TEST(DenseGridStore, BytesGrowWithTheVolumeOfTheSceneBounds) {
    // cells × (4 bytes × 4 slots + a 2-byte count), (extent / cell + 1)³ cells with the padding.
    const Json block = {{"cell_size", 0.03125}};
    const Json one = preparedStore(block, sceneOf({boxMesh(vec3(0), vec3(1))}))->stats();
    const Json two = preparedStore(block, sceneOf({boxMesh(vec3(0), vec3(2))}))->stats();
    EXPECT_EQ(one["grid_cells"], Json({33, 33, 33}));
    EXPECT_EQ(one["store_bytes"], 33 * 33 * 33 * 18);
    EXPECT_EQ(two["store_bytes"], 65 * 65 * 65 * 18);
    const double ratio = two["store_bytes"].get<double>() / one["store_bytes"].get<double>();
    EXPECT_GT(ratio, 7.5) << "double the bounds, about 8× the bytes";
    EXPECT_LT(ratio, 8.0);

    // Two unit boxes a unit apart: twice the surface of one box, 25× its grid.
    const Json apart = preparedStore(block, sceneOf({boxMesh(vec3(0), vec3(1)), boxMesh({2, 2, 2}, {3, 3, 3})}))->stats();
    EXPECT_EQ(apart["store_bytes"], 97 * 97 * 97 * 18);

    // Probes add 24 bytes each on top of the grid, which they do not change.
    auto store = preparedStore(block, sceneOf({boxMesh(vec3(0), vec3(1))}));
    for (int i = 0; i < 8; ++i) store->insert(queryAt({0.1f * i, 0.0f, 0.5f}, kUp), 0);
    const auto bytes = store->stats()["store_bytes"].get<std::size_t>();
    EXPECT_GE(bytes, std::size_t(33 * 33 * 33 * 18 + 8 * 24));
    EXPECT_LE(bytes, std::size_t(33 * 33 * 33 * 18 + 16 * 24)) << "std::vector growth";
}

TEST(DenseGridStore, RelativeCellSizeResolvesAgainstTheLargestSideOfTheScene) {
    const auto cornell = preparedStore(Json::object(), sceneOf({boxMesh(vec3(0), {0.55f, 0.55f, 0.3f})}));
    EXPECT_NEAR(cornell->coverageRadius(), 0.55f / 75.0f, 1e-7f);
    EXPECT_NEAR(cornell->coverageRadius(), 0.55f / 75.0f, 1e-7f);
    EXPECT_NEAR(cornell->stats()["cell_size"].get<double>(), 0.55 / 75.0, 1e-7);

    const auto sponza = preparedStore(Json::object(), sceneOf({boxMesh({-15, 0, -9}, {15, 12, 9})}));
    EXPECT_NEAR(sponza->coverageRadius(), 0.4f, 1e-6f) << "1/75 of 30 units: MAMBA's fine cell";

    const auto halved = preparedStore({{"cell_size_relative", 0.5}}, sceneOf({boxMesh({-15, 0, -9}, {15, 12, 9})}));
    EXPECT_FLOAT_EQ(halved->coverageRadius(), 15.0f);

    const auto absolute = preparedStore({{"cell_size", 0.25}, {"cell_size_relative", 0.5}}, sceneOf({boxMesh({-15, 0, -9}, {15, 12, 9})}));
    EXPECT_FLOAT_EQ(absolute->coverageRadius(), 0.25f) << "cell_size, when set, wins";
}

TEST(DenseGridStore, AGridTooLargeIsAnInputErrorNamingTheKey) {
    const Scene unitBox = sceneOf({boxMesh(vec3(0), vec3(1))});
    EXPECT_EQ(errorOf([&] { preparedStore({{"cell_size", 0.1}, {"max_cells", 1000}}, unitBox); }),
              "cfg.json: /method/max_cells: a dense grid of 0.1-unit cells over this scene (1 × 1 × 1 units) needs 11 × 11 × 11 = "
              "1331 cells, more than max_cells = 1000; raise max_cells or the cell size");
    EXPECT_EQ(errorOf([&] { preparedStore({{"cell_size", 0.1}, {"max_cells", 1331}}, unitBox); }), "");
    // A count no integer type holds is reported, not overflowed.
    const std::string huge = errorOf([&] { preparedStore({{"cell_size", 1e-9}}, unitBox); });
    EXPECT_EQ(huge.rfind("cfg.json: /method/max_cells: a dense grid of 1e-09-unit cells", 0), 0u) << huge;
    EXPECT_NE(huge.find(" cells, more than max_cells = 16777216;"), std::string::npos) << huge;
    EXPECT_EQ(errorOf([&] {
                  preparedStore({{"cell_size", 0.0099}, {"max_probes_per_cell", 4096}, {"max_cells", 1ll << 32}}, unitBox);
              }),
              "cfg.json: /method/max_probes_per_cell: 1092727 cells × 4096 probes per cell exceed the 2^32 - 1 probe ids; lower "
              "max_probes_per_cell or raise the cell size");

    Mesh point;
    point.positions = {vec3(1, 2, 3), vec3(1, 2, 3), vec3(1, 2, 3)};
    point.indices = {{0, 1, 2}};
    EXPECT_EQ(errorOf([&] { preparedStore(Json::object(), sceneOf({point})); }),
              "cfg.json: /method/cell_size_relative: the scene's bounding box has no extent to take a fraction of; give cell_size in "
              "scene units");
}

TEST(DenseGridStore, ParameterErrorsNameTheKeyAndTheExpectation) {
    EXPECT_EQ(errorOf([] { makeStore({{"cell_sise", 0.1}}); }),
              "cfg.json: /method/cell_sise: unknown key for method \"dense_grid\" (known: cell_size, cell_size_relative, "
              "max_probes_per_cell, normal_threshold, max_cells)");
    EXPECT_EQ(errorOf([] { makeStore({{"cell_size", -1}}); }), "cfg.json: /method/cell_size: expected a number >= 0, got -1");
    EXPECT_EQ(errorOf([] { makeStore({{"cell_size_relative", 0}}); }),
              "cfg.json: /method/cell_size_relative: expected a number in [0.0001, 1], got 0");
    EXPECT_EQ(errorOf([] { makeStore({{"max_probes_per_cell", 0}}); }),
              "cfg.json: /method/max_probes_per_cell: expected an integer in [1, 4096], got 0");
    EXPECT_EQ(errorOf([] { makeStore({{"normal_threshold", 1.5}}); }),
              "cfg.json: /method/normal_threshold: expected a number in [-1, 1], got 1.5");
    EXPECT_EQ(errorOf([] { makeStore({{"max_cells", 0}}); }),
              "cfg.json: /method/max_cells: expected an integer in [1, 4294967296], got 0");

    // The resolved parameters read back to the same store.
    Params params(Json{{"cell_size", 0.2}}, "cfg.json", "/method", "method \"dense_grid\"", &denseGridStoreParams());
    createDenseGridStore(params);
    const Json resolved = params.resolved();
    EXPECT_EQ(resolved["max_probes_per_cell"], 4);
    EXPECT_EQ(resolved["max_cells"], 1 << 24);
    EXPECT_EQ(errorOf([&] { preparedStore(resolved, sceneOf({boxMesh(vec3(0), vec3(1))})); }), "");
    EXPECT_FLOAT_EQ(preparedStore(resolved, sceneOf({boxMesh(vec3(0), vec3(1))}))->coverageRadius(), 0.2f);
}

TEST(DenseGridStore, AnEmptySceneHasNoCellsAndRefusesEveryInsert) {
    auto store = makeStore(Json::object());
    RunNotes notes;
    store->prepare(Scene{}, notes);
    EXPECT_EQ(store->insert(queryAt(vec3(0), kUp), 0).status, ProbeInsert::Status::Refused);
    ProbeNeighbour found;
    EXPECT_EQ(store->nearest(queryAt(vec3(0), kUp), 1, &found), 0);
    EXPECT_EQ(store->stats()["cells"], 0);
    EXPECT_EQ(store->stats()["outside_grid"], 1);
    ASSERT_EQ(notes.skipped.size(), 1u);
    EXPECT_EQ(notes.skipped[0]["stage"], "probes");
}

}  // namespace
}  // namespace gibench
