#include "methods/probe_cache/stores/dense_grid/dense_grid_store.h"

#include "support/store_test_helpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace gibench {
namespace {

using namespace test;  // the store-test helpers (support/store_test_helpers.h)

std::unique_ptr<ProbeStore> makeStore(const Json& block) { return test::makeStore(block, test::storeRow("dense_grid")); }

std::unique_ptr<ProbeStore> preparedStore(const Json& block, const Scene& scene) { return test::prepared(makeStore(block), scene); }

const vec3 kUp(0, 1, 0);

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
    // cells × (4 bytes × 4 slots + a 2-byte count) and a bit per cell in 64-bit words per row
    // along x, (extent / cell + 1)³ cells with the padding; and 4 bytes per group of 4³ cells for
    // the groups' surfel lists, from 2 cells before the grid (the surfel radius) to 2 after it.
    const auto gridBytes = [](int n) {
        const int groups = (n + 1) / 4 + 2;
        return n * n * n * 18 + n * n * ((n + 63) / 64) * 8 + groups * groups * groups * 4;
    };
    const std::size_t groupTableBytes = 10 * 10 * 10 * 4;  // of the 33³-cell grid
    const Json block = {{"cell_size", 0.03125}};
    const Json one = preparedStore(block, sceneOf({boxMesh(vec3(0), vec3(1))}))->stats();
    const Json two = preparedStore(block, sceneOf({boxMesh(vec3(0), vec3(2))}))->stats();
    EXPECT_EQ(one["grid_cells"], Json({33, 33, 33}));
    EXPECT_EQ(one["store_bytes"], gridBytes(33));
    EXPECT_EQ(two["store_bytes"], gridBytes(65));
    const double ratio = two["store_bytes"].get<double>() / one["store_bytes"].get<double>();
    EXPECT_GT(ratio, 7.5) << "double the bounds, about 8× the bytes";
    EXPECT_LT(ratio, 8.0);

    // Two unit boxes a unit apart: twice the surface of one box, 25× its grid.
    const Json apart = preparedStore(block, sceneOf({boxMesh(vec3(0), vec3(1)), boxMesh({2, 2, 2}, {3, 3, 3})}))->stats();
    EXPECT_EQ(apart["store_bytes"], gridBytes(97));

    // Probes add 24 bytes each on top of the grid, which they do not change, and 40 bytes in the
    // list of each of the 1 to 8 groups that can serve a point of their cell (lists of 4 or more).
    auto store = preparedStore(block, sceneOf({boxMesh(vec3(0), vec3(1))}));
    for (int i = 0; i < 8; ++i) store->insert(queryAt({0.1f * i, 0.0f, 0.5f}, kUp), 0);
    const Json stats = store->stats();
    const auto bytes = stats["store_bytes"].get<std::size_t>(), lists = stats["surfel_list_bytes"].get<std::size_t>();
    EXPECT_GE(lists, groupTableBytes + 8 * 40) << "every surfel listed once at least";
    EXPECT_LE(lists, groupTableBytes + 8 * 8 * (4 * 40 + 2 * 64)) << "at most 8 lists per surfel, of 4 at least, std::vector growth";
    EXPECT_GE(bytes - lists, std::size_t(gridBytes(33)) - groupTableBytes + 8 * 24);
    EXPECT_LE(bytes - lists, std::size_t(gridBytes(33)) - groupTableBytes + 16 * 24) << "std::vector growth";
}

TEST(DenseGridStore, AGridTooLargeIsAnInputErrorNamingTheKey) {
    const Scene unitBox = sceneOf({boxMesh(vec3(0), vec3(1))});
    EXPECT_EQ(errorOf([&] { preparedStore({{"cell_size", 0.1}, {"max_cells", 1000}}, unitBox); }),
              "cfg.json: /method/max_cells: a dense grid of 0.1-unit cells over this scene (1 × 1 × 1 units) needs 11 × 11 × 11 = "
              "1331 cells, more than max_cells = 1000; raise max_cells or the cell size");
    EXPECT_EQ(errorOf([&] { preparedStore({{"cell_size", 0.1}, {"max_cells", 1331}}, unitBox); }), "");
    // A count beyond every 32-bit type is reported, not overflowed.
    const std::string huge = errorOf([&] { preparedStore({{"cell_size", 1e-6}}, unitBox); });
    EXPECT_EQ(huge.rfind("cfg.json: /method/max_cells: a dense grid of 1e-06-unit cells", 0), 0u) << huge;
    EXPECT_NE(huge.find(" cells, more than max_cells = 16777216;"), std::string::npos) << huge;
    EXPECT_EQ(errorOf([&] {
                  preparedStore({{"cell_size", 0.0099}, {"max_probes_per_cell", 4096}, {"max_cells", 1ll << 32}}, unitBox);
              }),
              "cfg.json: /method/max_probes_per_cell: 1092727 cells × 4096 probes per cell exceed the 2^32 - 1 probe ids; lower "
              "max_probes_per_cell or raise the cell size");
}

TEST(DenseGridStore, ItsOwnKeysOutOfRangeAreInputErrorsNamingTheKey) {
    // The spacing keys, unknown keys and the resolved parameters are checked for every store in
    // store_contract_test.cpp.
    EXPECT_EQ(errorOf([] { makeStore({{"max_probes_per_cell", 0}}); }),
              "cfg.json: /method/max_probes_per_cell: expected an integer in [1, 4096], got 0");
    EXPECT_EQ(errorOf([] { makeStore({{"normal_threshold", 1.5}}); }),
              "cfg.json: /method/normal_threshold: expected a number in [-1, 1], got 1.5");
    EXPECT_EQ(errorOf([] { makeStore({{"max_cells", 0}}); }),
              "cfg.json: /method/max_cells: expected an integer in [1, 4294967296], got 0");

    // The defaults the resolved parameters report.
    Params params(Json{{"cell_size", 0.2}}, "cfg.json", "/method", "method \"dense_grid\"", &denseGridStoreParams());
    createDenseGridStore(params);
    const Json resolved = params.resolved();
    EXPECT_EQ(resolved["max_probes_per_cell"], 4);
    EXPECT_EQ(resolved["max_cells"], 1 << 24);
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

// GIBS's lookup by its definition, by brute force over every probe of `store`: the surfels
// within surfel_radius (1.5 cells) of the point whose normal passes `threshold`, the 16 nearest
// (ties by id), each weighted (1 − (d/R)²)² × (n_s·n − threshold) / (1 − threshold), normalised;
// covered when one lies within a cell of the point in its tangent plane and along its normal.
void expectTheDefinition(const ProbeStore& store, const ProbeQuery& query, const ProbeLookup& served, float cell, float threshold,
                         const std::string& label) {
    const float radius = 1.5f * cell;
    struct Candidate {
        float distance;
        uint32_t id;
        double weight;
    };
    std::vector<Candidate> candidates;
    for (uint32_t id = 0; id < store.idCapacity(); ++id) {
        const Probe& p = store.probe(id);
        const float facing = glm::dot(p.normal, query.normal);
        const float d = glm::length(p.position - query.position);
        if (!(facing > threshold) || !(d < radius)) continue;
        const double t = double(d) / radius;
        candidates.push_back({d, id, (1.0 - t * t) * (1.0 - t * t) * (facing - threshold) / (1.0 - threshold)});
    }
    std::sort(candidates.begin(), candidates.end(),
              [](const Candidate& a, const Candidate& b) { return a.distance < b.distance || (a.distance == b.distance && a.id < b.id); });
    if (candidates.size() > std::size_t(kMaxServedProbes)) candidates.resize(kMaxServedProbes);
    double sum = 0.0;
    bool covered = false;
    for (const Candidate& c : candidates) {
        sum += c.weight;
        const vec3 d = store.probe(c.id).position - query.position;
        const float along = glm::dot(d, query.normal);
        if (glm::length(d - along * query.normal) < cell && std::fabs(along) < cell) covered = true;
    }
    ASSERT_EQ(served.count, int(candidates.size())) << label;
    for (int i = 0; i < served.count; ++i) {
        EXPECT_EQ(served.probes[i].id, candidates[std::size_t(i)].id) << label;
        EXPECT_NEAR(served.probes[i].weight, candidates[std::size_t(i)].weight / sum, 1e-5) << label;
    }
    EXPECT_EQ(served.covered, covered) << label;
    if (!candidates.empty()) {
        EXPECT_FLOAT_EQ(served.distance, candidates[0].distance) << label;
    }
}

TEST(DenseGridStore, LookupBlendsEverySurfelHoldingThePointByARadialAndANormalWeight) {
    // GIBS's lookup against its definition (expectTheDefinition), also on a patch of a grid 81
    // cells wide, where lookups cross the 64-cell words of the occupancy rows. One query at a time
    // and as one batch in order, with queries up to 2.5 cells off the patch and the grid (negative
    // cells).
    struct Case {
        float cell, from, to;  // surfels and queries on [from, to]² of the top face
    };
    for (const Case c : {Case{0.1f, 0.0f, 1.0f}, Case{0.0125f, 0.7f, 0.9f}}) {
        const float cell = c.cell, threshold = 0.5f;
        auto store = preparedStore({{"cell_size", cell}, {"surfel_radius", 1.5}, {"max_probes_per_cell", 16}}, sceneOf({boxMesh(vec3(0), vec3(1))}));
        // Surfels scattered on and just off the top face, their normals tilted by up to ~50°.
        uint32_t state = 12345u;
        auto next = [&state] {
            state = state * 1664525u + 1013904223u;
            return float(state >> 8) / float(1u << 24);
        };
        const auto onPatch = [&] { return c.from + (c.to - c.from) * next(); };
        for (int i = 0; i < 600; ++i) {
            const vec3 p(onPatch(), 1.0f + 0.4f * cell * (next() - 0.5f), onPatch());
            const vec3 n = glm::normalize(vec3(1.2f * (next() - 0.5f), 1.0f, 1.2f * (next() - 0.5f)));
            store->insert(queryAt(p, n), 0);
        }
        ASSERT_GT(store->idCapacity(), 500u);
        std::vector<ProbeQuery> queries;
        for (int q = 0; q < 200; ++q) {
            const float x = q < 150 ? onPatch() : c.from - 2.5f * cell * next();
            queries.push_back(queryAt({x, 1.0f, onPatch()}, glm::normalize(vec3(0.6f * (next() - 0.5f), 1.0f, 0.6f * (next() - 0.5f)))));
        }
        std::vector<ProbeLookup> batched(queries.size());
        store->lookupBatch(queries.data(), int(queries.size()), 2, batched.data());
        for (int q = 0; q < 200; ++q) {
            ProbeLookup alone;
            store->lookup(queries[std::size_t(q)], 2, alone);
            expectTheDefinition(*store, queries[std::size_t(q)], alone, cell, threshold, "query " + std::to_string(q) + " alone");
            expectTheDefinition(*store, queries[std::size_t(q)], batched[std::size_t(q)], cell, threshold, "query " + std::to_string(q) + " batched");
        }
    }
}

// Every lookup reads the list of surfels that its group of cells was given as they were inserted:
// lookups between inserts, alone and batched, are the definition over the surfels inserted so far,
// also where a list holds more surfels than a lookup marks at once (256 alone; a batch tests 32 at
// a time against 16 queries) and where two stores hold surfels in the same cells.
TEST(DenseGridStore, LookupsBetweenInsertsAreTheDefinitionOverTheSurfelsSoFar) {
    const Scene scene = sceneOf({boxMesh(vec3(0), vec3(1))});
    const float cell = 0.1f, threshold = 0.5f;
    const Json block = {{"cell_size", cell}, {"surfel_radius", 1.5}, {"max_probes_per_cell", 128}};
    auto first = preparedStore(block, scene), second = preparedStore(block, scene);
    uint32_t state = 777u;
    auto next = [&state] {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) / float(1u << 24);
    };
    // 1 200 surfels each on a 0.4 × 0.4 patch of the top face (16 cells: about 600 in a group's
    // list), the second store's elsewhere in the same cells.
    const auto surfel = [&] { return queryAt({0.3f + 0.4f * next(), 1.0f, 0.3f + 0.4f * next()}, glm::normalize(vec3(next() - 0.5f, 1.0f, next() - 0.5f))); };
    for (int round = 0; round < 6; ++round) {
        for (int i = 0; i < 200; ++i) {
            ASSERT_EQ(first->insert(surfel(), uint32_t(round)).status, ProbeInsert::Status::Inserted);
            ASSERT_EQ(second->insert(surfel(), uint32_t(round)).status, ProbeInsert::Status::Inserted);
        }
        std::vector<ProbeQuery> queries;
        for (int q = 0; q < 24; ++q) queries.push_back(queryAt({0.25f + 0.5f * next(), 1.0f, 0.25f + 0.5f * next()}, kUp));
        for (const ProbeStore* store : {first.get(), second.get()}) {
            std::vector<ProbeLookup> batched(queries.size());
            store->lookupBatch(queries.data(), int(queries.size()), 2, batched.data());
            for (std::size_t q = 0; q < queries.size(); ++q) {
                const std::string label = "round " + std::to_string(round) + (store == first.get() ? ", first" : ", second") + " store, query " + std::to_string(q);
                ProbeLookup alone;
                store->lookup(queries[q], 2, alone);
                expectTheDefinition(*store, queries[q], alone, cell, threshold, label + " alone");
                expectTheDefinition(*store, queries[q], batched[q], cell, threshold, label + " batched");
            }
        }
    }
}

}  // namespace
}  // namespace gibench
