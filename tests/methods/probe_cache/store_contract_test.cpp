// The contract of a probe store (methods/probe_cache/probe_store.h), checked for every row of the
// store table (stores/store_table.h): a store added to the table is tested here with no edit to
// this file (in the spirit of pbrt-v4's integrators_test.cpp). Behaviour only one store has
// (cards' depth conflicts, the dense grid's full cells, MAMBA's hash-table policies) stays in the
// store's own test file under stores/.
//
// Every store is built through its row, its spacing set with `spacingKey` in scene units, and asked
// about points on the faces of box meshes with the faces' outward normals and the right mesh index,
// so that stores that read the mesh (cards) and stores that do not (the grids) see the same queries.
// Stores filter what nearest() offers by facing (a normal threshold, a card, a facing tag): the
// brute-force checks compare only against probes of the query's normal on the same flat face.

#include "core/util/rng.h"
#include "methods/probe_cache/stores/store_table.h"

#include "support/store_test_helpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <ostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace gibench {

// gtest prints a failing test's parameter: the row's name rather than its bytes.
static void PrintTo(const ProbeStoreInfo& info, std::ostream* os) { *os << info.name; }

namespace {

using namespace test;  // the store-test helpers (support/store_test_helpers.h)

const vec3 kUp(0, 1, 0), kEast(1, 0, 0), kWest(-1, 0, 0), kSouth(0, 0, 1);

// The probe spacing of most tests, in scene units: ten cells or texels along the unit box.
constexpr float kSpacing = 0.1f;

// Distances between points of the unit box: each coordinate is within half an ULP of 1 (6e-8), and
// a store may form |p − q| in another order or precision than the test, a few such ULPs apart.
// 1e-6 is ten times that, and still far below the 0.01 that separates the lattice points.
constexpr float kDistanceTolerance = 1e-6f;

// A point asking for a store's spacing: before the first frame no store knows the camera, so its
// cells or texels are the same size everywhere.
const ProbeQuery kBeforeAnyFrame = {vec3(0.5f), vec3(0, 1, 0), 0, 0};

bool before(const ProbeNeighbour& a, const ProbeNeighbour& b) { return a.distance < b.distance || (a.distance == b.distance && a.id < b.id); }

std::string describe(const ProbeQuery& q) {
    std::ostringstream s;
    s << "query (" << q.position.x << ", " << q.position.y << ", " << q.position.z << ") normal (" << q.normal.x << ", " << q.normal.y
      << ", " << q.normal.z << ") mesh " << q.mesh;
    return s.str();
}

// Whether every number anywhere in `j` is finite (a NaN would be written as null in the record).
bool allNumbersFinite(const Json& j) {
    if (j.is_number_float()) return std::isfinite(j.get<double>());
    if (j.is_structured())
        for (const Json& child : j)
            if (!allNumbersFinite(child)) return false;
    return true;
}

double storeBytes(const ProbeStore& store) { return store.stats().at("store_bytes").get<double>(); }

// A point on the top face (y = 1, facing +Y) of the unit box, mesh 0 of unitBox().
ProbeQuery onTop(float x, float z) { return queryAt({x, 1.0f, z}, kUp, 0); }

Scene unitBox() { return sceneOf({boxMesh(vec3(0), vec3(1))}); }

// A room with a wall 0.001 thick at x = 0.5 (mesh 1), far thinner than a cell or texel: its east face
// at x = 0.5005 faces +X, its west face at x = 0.4995 faces −X.
constexpr float kWallEast = 0.5005f, kWallWest = 0.4995f;
Scene roomWithThinWall() { return sceneOf({boxMesh(vec3(0), vec3(1)), boxMesh({kWallWest, 0, 0}, {kWallEast, 1, 1})}); }

// One point in each kSpacing × kSpacing square of the top face, each somewhere else inside its
// square: one probe per cell-sized patch, the density coverage needs, which every store must hold.
std::vector<ProbeQuery> oneProbePerSquareOfTheTop() {
    std::vector<ProbeQuery> points;
    for (int i = 0; i < 10; ++i)
        for (int k = 0; k < 10; ++k)
            points.push_back(onTop(0.1f * i + 0.01f + 0.08f * float((i * 7 + k * 3) % 10) / 9.0f,
                                   0.1f * k + 0.01f + 0.08f * float((i * 3 + k * 5) % 10) / 9.0f));
    return points;
}

// 24 × 24 points a lattice step of about 0.04 apart, neither aligned with the cells nor with the
// probes above: the first 12 rows on the top face, the rest on the east face.
std::vector<ProbeQuery> latticeOnTheTopAndEastFaces() {
    std::vector<ProbeQuery> points;
    for (int row = 0; row < 24; ++row)
        for (int column = 0; column < 24; ++column) {
            const float a = 0.002f + 0.0417f * column, b = 0.003f + 0.0413f * row;
            points.push_back(row < 12 ? onTop(a, b) : queryAt({1.0f, a, b}, kEast));
        }
    return points;
}

// A denser lattice on the top face, 0.033 apart: stores holding one probe per cell refuse most of
// it, stores holding several keep some.
std::vector<ProbeQuery> denseLatticeOnTheTop() {
    std::vector<ProbeQuery> points;
    for (int i = 0; i <= 30; ++i)
        for (int k = 0; k <= 30; ++k) points.push_back(onTop(0.005f + 0.033f * i, 0.005f + 0.033f * k));
    return points;
}

// Inserts spread over three faces of the unit box and several frames, for the tests that compare
// two stores.
std::vector<ProbeQuery> mixedInsertsOnTheBox() {
    std::vector<ProbeQuery> points;
    uint32_t state = 12345u;
    const auto next = [&state] {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) / float(1u << 24);
    };
    for (int i = 0; i < 300; ++i) {
        const float a = next(), b = next();
        switch (i % 3) {
            case 0: points.push_back(queryAt({a, 1.0f, b}, kUp)); break;
            case 1: points.push_back(queryAt({1.0f, a, b}, kEast)); break;
            default: points.push_back(queryAt({a, b, 1.0f}, kSouth)); break;
        }
    }
    return points;
}

// Whether what nearest(query, count) returned in found[0, n) keeps the contract against `candidates`,
// the ids of every live probe that faces the query's way on the query's flat face (so no store may
// filter them out): at most `count` distinct live ids, sorted by (distance, id), each distance the
// true one and within searchRadius(), and every candidate left out either beyond the radius or, when
// `count` were returned, no nearer than the last of them.
testing::AssertionResult keepsTheNearestContract(const ProbeStore& store, const ProbeQuery& query, int count,
                                                  const ProbeNeighbour* found, int n, const std::vector<uint32_t>& candidates) {
    if (n < 0 || n > count) return testing::AssertionFailure() << "returned " << n << " entries for count " << count;
    const float radius = store.searchRadius(query);
    std::set<uint32_t> returned;
    for (int i = 0; i < n; ++i) {
        const ProbeNeighbour& f = found[i];
        if (f.id >= store.idCapacity()) return testing::AssertionFailure() << "rank " << i << ": id " << f.id << " >= idCapacity()";
        if (!returned.insert(f.id).second) return testing::AssertionFailure() << "rank " << i << ": id " << f.id << " twice";
        if (i > 0 && !before(found[i - 1], f))
            return testing::AssertionFailure() << "rank " << i << " (id " << f.id << ", " << f.distance << ") not after rank " << i - 1
                                               << " (id " << found[i - 1].id << ", " << found[i - 1].distance << ")";
        if (!(f.distance <= radius))
            return testing::AssertionFailure() << "rank " << i << ": distance " << f.distance << " beyond searchRadius() " << radius;
        const Probe& p = store.probe(f.id);
        const float truth = glm::length(p.position - query.position);
        if (!(std::fabs(f.distance - truth) <= kDistanceTolerance))
            return testing::AssertionFailure() << "rank " << i << ": id " << f.id << " reported at " << f.distance << ", lies at " << truth;
        if (!(glm::dot(p.normal, query.normal) > 0.0f))
            return testing::AssertionFailure() << "rank " << i << ": id " << f.id << " faces away from the query";
    }
    for (const uint32_t id : candidates) {
        if (returned.count(id)) continue;
        const float d = glm::length(store.probe(id).position - query.position);
        if (!(d <= radius - kDistanceTolerance)) continue;  // beyond the store's reach (or on its edge, up to rounding)
        if (n < count)
            return testing::AssertionFailure() << "probe " << id << " at " << d << " is within searchRadius() " << radius
                                               << " but left out, and only " << n << " of " << count << " were returned";
        if (d < found[n - 1].distance - kDistanceTolerance)
            return testing::AssertionFailure() << "probe " << id << " at " << d << " left out for a farther one, id " << found[n - 1].id
                                               << " at " << found[n - 1].distance;
    }
    return testing::AssertionSuccess();
}

class ProbeStoreContract : public testing::TestWithParam<ProbeStoreInfo> {
protected:
    const ProbeStoreInfo& info() const { return GetParam(); }
    // The block that sets the store's probe spacing in scene units, the store starting empty.
    Json spacing(float s) const { return startingEmpty(info(), {{info().spacingKey, s}}); }
    std::string relativeKey() const { return info().spacingKey + "_relative"; }

    std::unique_ptr<ProbeStore> make(const Json& block) const { return test::makeStore(block, info()); }
    std::unique_ptr<ProbeStore> prepared(const Json& block, const Scene& scene, RunNotes* notes = nullptr) const {
        return test::prepared(make(block), scene, notes);
    }
    std::unique_ptr<ProbeStore> preparedBox() const { return prepared(spacing(kSpacing), unitBox()); }

    // Inserts each query in frame 0; returns the ids of the probes placed (Inserted or Evicted).
    static std::vector<uint32_t> insertAll(ProbeStore& store, const std::vector<ProbeQuery>& queries) {
        std::vector<uint32_t> ids;
        for (const ProbeQuery& q : queries) {
            const ProbeInsert r = store.insert(q, 0);
            if (r.status != ProbeInsert::Status::Refused) ids.push_back(r.id);
        }
        return ids;
    }
};

// --- Building the store: parameters ------------------------------------------------------------

TEST_P(ProbeStoreContract, DefaultsBuildAndPrepareOnAScene) {
    std::unique_ptr<ProbeStore> store;
    ASSERT_EQ(errorOf([&] { store = prepared(Json::object(), unitBox()); }), "") << info().name;
    ASSERT_TRUE(store);
    // The default spacing is relative: 1/75 of the largest side (probe_spacing.h).
    EXPECT_NEAR(store->coverageRadius(kBeforeAnyFrame), 1.0f / 75.0f, 1e-7f) << info().name;
    // Probes placed in prepare() (cards' capture) are live: each has the position and normal of a
    // point on the box's faces.
    for (uint32_t id = 0; id < store->idCapacity(); ++id) {
        const Probe& p = store->probe(id);
        const vec3 onFace = glm::min(glm::abs(p.position), glm::abs(p.position - vec3(1.0f)));
        EXPECT_LT(std::min({onFace.x, onFace.y, onFace.z}), 1e-6f) << info().name << " probe " << id;
        EXPECT_NEAR(glm::length(p.normal), 1.0f, 1e-6f) << info().name << " probe " << id;
    }
}

TEST_P(ProbeStoreContract, ResolvedParametersReadBackToAStoreWithTheSameStats) {
    Params params(spacing(0.2f), "cfg.json", "/method", "method \"" + info().name + "\"", &info().parameters());
    auto store = info().create(params);
    params.finish();
    const Json resolved = params.resolved();

    // Every key of the table, with the value given or its default.
    EXPECT_EQ(resolved.size(), info().parameters().size()) << info().name << " " << resolved.dump();
    for (const ParamSpec& row : info().parameters()) {
        ASSERT_TRUE(resolved.contains(row.name)) << info().name << " " << row.name;
        const Json given = spacing(0.2f);
        EXPECT_EQ(resolved[row.name], given.contains(row.name) ? given[row.name] : row.defaultValue) << info().name << " " << row.name;
    }

    std::unique_ptr<ProbeStore> again;
    ASSERT_EQ(errorOf([&] { again = make(resolved); }), "") << info().name << " " << resolved.dump();
    RunNotes notes;
    store->prepare(unitBox(), notes);
    again->prepare(unitBox(), notes);
    EXPECT_FLOAT_EQ(store->coverageRadius(kBeforeAnyFrame), 0.2f) << info().name;
    EXPECT_EQ(again->coverageRadius(kBeforeAnyFrame), store->coverageRadius(kBeforeAnyFrame)) << info().name;
    for (const ProbeQuery& q : mixedInsertsOnTheBox()) {
        store->insert(q, 0);
        again->insert(q, 0);
    }
    EXPECT_EQ(again->stats(), store->stats()) << info().name;
}

TEST_P(ProbeStoreContract, AnUnknownKeyIsAnInputErrorNamingItAndTheKnownKeys) {
    std::string known;
    for (const ParamSpec& row : info().parameters()) known += (known.empty() ? "" : ", ") + row.name;
    EXPECT_EQ(errorOf([&] { make({{info().spacingKey + "_typo", 0.1}}); }),
              "cfg.json: /method/" + info().spacingKey + "_typo: unknown key for method \"" + info().name + "\" (known: " + known + ")");
}

TEST_P(ProbeStoreContract, ASpacingOutOfRangeIsAnInputErrorNamingTheKey) {
    EXPECT_EQ(errorOf([&] { make(spacing(-0.5f)); }), "cfg.json: /method/" + info().spacingKey + ": expected a number >= 0, got -0.5");
    EXPECT_EQ(errorOf([&] { make({{relativeKey(), 0}}); }),
              "cfg.json: /method/" + relativeKey() + ": expected a number in [0.0001, 1], got 0");
}

TEST_P(ProbeStoreContract, EveryKeyGivenAValueItsTableRowRejectsIsAnInputErrorNamingIt) {
    // Whatever the key means, create() reads it through its row: a value of the wrong type, or
    // beyond the row's range, names the key.
    for (const ParamSpec& row : info().parameters()) {
        std::vector<Json> bad;
        switch (row.type) {
            case gibench::ParamType::Int:
            case gibench::ParamType::Float:
                bad.push_back("text");
                if (std::isfinite(row.min)) bad.push_back(row.min - 1.0);
                if (std::isfinite(row.max)) bad.push_back(row.max + 1.0);
                if (row.type == gibench::ParamType::Int) bad.push_back((std::isfinite(row.min) ? row.min : 0.0) + 0.5);
                break;
            case gibench::ParamType::Bool: bad = {"text", 1}; break;
            case gibench::ParamType::String: bad = {12, Json(row.choices.empty() ? Json(nullptr) : Json("not_a_choice"))}; break;
            default: bad = {Json::object()}; break;
        }
        for (const Json& value : bad) {
            if (value.is_null()) continue;
            const std::string message = errorOf([&] { make({{row.name, value}}); });
            const std::string where = "cfg.json: /method/" + row.name + ": expected ";
            EXPECT_EQ(message.rfind(where, 0), 0u) << info().name << " " << row.name << " = " << value.dump() << ": " << message;
        }
    }
}

// --- Spacing -----------------------------------------------------------------------------------

TEST_P(ProbeStoreContract, RelativeSpacingResolvesAgainstTheLargestSideOfTheScene) {
    struct Case {
        const char* what;
        Json block;
        Scene scene;
        float expected;
        float tolerance;  // the spacing is one float product: a few ULPs of it (1e-9 at 0.007, 1e-6 at 15) at most
    };
    const Scene cornell = sceneOf({boxMesh(vec3(0), {0.55f, 0.55f, 0.3f})});
    const Scene sponza = sceneOf({boxMesh({-15, 0, -9}, {15, 12, 9})});
    const Scene tallZ = sceneOf({boxMesh({1, 2, -4}, {3, 5, 8})});  // its largest side, 12, along z
    const std::vector<Case> cases = {
        {"cornell box, default 1/75", Json::object(), cornell, 0.55f / 75.0f, 1e-7f},
        {"sponza, default 1/75: MAMBA's 0.4-unit fine cell", Json::object(), sponza, 0.4f, 1e-6f},
        {"sponza, half of it", {{info().spacingKey, 0}, {relativeKey(), 0.5}}, sponza, 15.0f, 2e-6f},
        {"largest side along z", {{relativeKey(), 0.25}}, tallZ, 3.0f, 5e-7f},
        {"absolute spacing wins over relative", {{info().spacingKey, 0.25}, {relativeKey(), 0.5}}, sponza, 0.25f, 0.0f},
        {"absolute spacing", spacing(kSpacing), unitBox(), kSpacing, 0.0f},
    };
    for (const Case& c : cases) {
        const auto store = prepared(c.block, c.scene);
        EXPECT_NEAR(store->coverageRadius(kBeforeAnyFrame), c.expected, c.tolerance) << info().name << ": " << c.what;
        // The frame record reports the spacing used under its key.
        const Json stats = store->stats();
        ASSERT_TRUE(stats.contains(info().spacingKey)) << info().name << ": " << stats.dump();
        EXPECT_NEAR(stats[info().spacingKey].get<double>(), c.expected, c.tolerance) << info().name << ": " << c.what;
        // nearest() looks kSearchRings cells or texels far (probe_store.h).
        EXPECT_FLOAT_EQ(store->searchRadius(kBeforeAnyFrame), kSearchRings * store->coverageRadius(kBeforeAnyFrame)) << info().name << ": " << c.what;
        EXPECT_GE(store->searchRadius(kBeforeAnyFrame), store->coverageRadius(kBeforeAnyFrame)) << info().name << ": " << c.what;
    }
}

TEST_P(ProbeStoreContract, RelativeSpacingOnASceneWithNoExtentIsAnInputErrorNamingTheRelativeKey) {
    Mesh point;
    point.positions = {vec3(1, 2, 3), vec3(1, 2, 3), vec3(1, 2, 3)};
    point.indices = {{0, 1, 2}};
    point.materials = {0};
    EXPECT_EQ(errorOf([&] { prepared(Json::object(), sceneOf({point})); }),
              "cfg.json: /method/" + relativeKey() + ": the scene's bounding box has no extent to take a fraction of; give " +
                  info().spacingKey + " in scene units");
}

TEST_P(ProbeStoreContract, ASpacingFloatPositionsCannotResolveIsAnInputErrorNamingTheKeyInUse) {
    // The unit box reaches 1 unit from the origin: 1e-20 units is 1e20 spacings (issue 8: mamba
    // threw from its cell quantiser, an internal error). Relative spacing far from the origin too.
    const std::string absolute = errorOf([&] { prepared(spacing(1e-20f), unitBox()); });
    EXPECT_EQ(absolute.rfind("cfg.json: /method/" + info().spacingKey + ": a spacing of 1e-20 units is too fine for float positions", 0), 0u)
        << info().name << ": " << absolute;
    Scene far = sceneOf({boxMesh(vec3(1e7f), vec3(1e7f + 1.0f))});
    const std::string relative = errorOf([&] { prepared(Json::object(), far); });
    EXPECT_EQ(relative.rfind("cfg.json: /method/" + relativeKey() + ": a spacing of", 0), 0u) << info().name << ": " << relative;
    EXPECT_NE(relative.find("reaches 1e+07 units from the origin"), std::string::npos) << info().name << ": " << relative;
    EXPECT_EQ(errorOf([&] { prepared(spacing(0.05f), unitBox()); }), "") << info().name;
    // A spacing beyond float range is refused by name (issue 8: dense_grid's cell_size 1e39
    // became infinity, 0 probes); one as large as a float holds serves the scene with one cell.
    EXPECT_EQ(errorOf([&] { make({{info().spacingKey, 1e39}}); }),
              "cfg.json: /method/" + info().spacingKey + ": expected a number >= 0, got 1e+39 (too large for a float, whose magnitude is at most 3.4e38)")
        << info().name;
    auto huge = prepared({{info().spacingKey, 1e30}}, unitBox());
    EXPECT_EQ(huge->insert(onTop(0.5f, 0.5f), 0).status, ProbeInsert::Status::Inserted) << info().name;
}

// --- insert() and nearest() ----------------------------------------------------------------------

TEST_P(ProbeStoreContract, InsertedProbeIsFoundByNearestWhereTheQueryPlacedIt) {
    auto store = preparedBox();
    EXPECT_EQ(store->idCapacity(), 0u) << info().name;
    EXPECT_EQ(store->stats()["probes"], 0) << info().name;

    const ProbeQuery q = onTop(0.52f, 0.47f);
    const ProbeInsert first = store->insert(q, 0);
    ASSERT_EQ(first.status, ProbeInsert::Status::Inserted) << info().name << " " << describe(q);
    EXPECT_EQ(first.id, 0u) << info().name << ": ids are dense from 0";
    EXPECT_EQ(store->idCapacity(), 1u) << info().name;
    EXPECT_EQ(store->probe(first.id).position, q.position) << info().name;
    EXPECT_EQ(store->probe(first.id).normal, q.normal) << info().name;

    const std::vector<ProbeNeighbour> here = nearestOf(*store, q, 4);
    ASSERT_EQ(here.size(), 1u) << info().name << " " << describe(q);
    EXPECT_EQ(here[0].id, first.id) << info().name;
    EXPECT_EQ(here[0].distance, 0.0f) << info().name << ": the query point itself";

    const ProbeQuery near = onTop(0.55f, 0.43f);
    const std::vector<ProbeNeighbour> beside = nearestOf(*store, near, 4);
    ASSERT_EQ(beside.size(), 1u) << info().name << " " << describe(near);
    EXPECT_EQ(beside[0].id, first.id) << info().name;
    EXPECT_NEAR(beside[0].distance, 0.05f, kDistanceTolerance) << info().name << ": |(0.03, 0, -0.04)|";

    const ProbeQuery other = onTop(0.2f, 0.2f);
    const ProbeInsert second = store->insert(other, 0);
    ASSERT_EQ(second.status, ProbeInsert::Status::Inserted) << info().name << " " << describe(other);
    EXPECT_EQ(second.id, 1u) << info().name << ": ids are dense from 0";
    EXPECT_EQ(store->idCapacity(), 2u) << info().name;
    EXPECT_EQ(store->stats()["probes"], 2) << info().name;
}

TEST_P(ProbeStoreContract, EveryPlacedProbeHasAnIdBelowIdCapacityAndTheQuerysPositionAndNormal) {
    auto store = preparedBox();
    std::vector<ProbeQuery> queries = oneProbePerSquareOfTheTop();
    const std::vector<ProbeQuery> more = mixedInsertsOnTheBox();
    queries.insert(queries.end(), more.begin(), more.end());
    for (const ProbeQuery& q : queries) {
        const uint32_t capacityBefore = store->idCapacity();
        const ProbeInsert r = store->insert(q, 0);
        if (r.status == ProbeInsert::Status::Refused) {
            EXPECT_EQ(store->idCapacity(), capacityBefore) << info().name << " " << describe(q);
            continue;
        }
        ASSERT_LT(r.id, store->idCapacity()) << info().name << " " << describe(q);
        if (r.status == ProbeInsert::Status::Inserted) {
            EXPECT_EQ(r.id, capacityBefore) << info().name << " " << describe(q) << ": a new id is the next dense one";
        }
        EXPECT_EQ(store->probe(r.id).position, q.position) << info().name << " " << describe(q);
        EXPECT_EQ(store->probe(r.id).normal, q.normal) << info().name << " " << describe(q);
    }
}

TEST_P(ProbeStoreContract, NearestIsEveryProbeOfTheSameFacingWithinSearchRadiusNearestFirstAtMostCount) {
    auto store = preparedBox();
    for (const ProbeQuery& q : oneProbePerSquareOfTheTop()) {
        if (store->insert(q, 0).status != ProbeInsert::Status::Refused) continue;
        // A store whose cells do not line up with the squares (hash_grid lays them from half a
        // cell outside the scene) may find two points in one cell: it refuses only a point it covers.
        ProbeLookup served;
        store->lookup(q, 1, served);
        EXPECT_TRUE(served.covered) << info().name << " " << describe(q) << ": refused where no probe covers it";
    }
    insertAll(*store, denseLatticeOnTheTop());
    // Every probe lies on the top face facing +Y: none may be filtered out for the queries below.
    std::vector<uint32_t> candidates;
    for (uint32_t id = 0; id < store->idCapacity(); ++id) candidates.push_back(id);

    for (int qi = 0; qi < 17; ++qi)
        for (int qk = 0; qk < 17; ++qk) {
            const ProbeQuery query = onTop(0.003f + 0.0617f * qi, 0.011f + 0.0589f * qk);
            for (const int count : {1, 2, 5, 9, 16, 1000}) {
                // Spare entries past `count`: a store returning too many writes there, not past the buffer.
                std::vector<ProbeNeighbour> found(std::size_t(count) + 16);
                const int n = store->nearest(query, count, found.data());
                EXPECT_TRUE(keepsTheNearestContract(*store, query, count, found.data(), n, candidates))
                    << info().name << " " << describe(query) << " count " << count;
                if (count == 1) {
                    EXPECT_EQ(n, 1) << info().name << " " << describe(query) << ": a probe in every square, one within reach";
                }
            }
        }

    ProbeNeighbour unused{};
    EXPECT_EQ(store->nearest(onTop(0.5f, 0.5f), 0, &unused), 0) << info().name << ": count 0";
}

// The lookup every store shares ("lookup": "nearest", issue 9), against its definition: the
// nearest() probes, each weighted (1 − t²)² with t = distance / searchRadius(), normalised; covered
// exactly when the nearest lies within coverageRadius() in the query's tangent plane and along its
// normal. And the store's own lookup: at most servedAtMost(count) probes. Both: distinct live ids,
// weights finite, >= 0 and summing to 1. Each store's own test checks its lookup's definition.
TEST_P(ProbeStoreContract, LookupsServeTheProbesTheirDefinitionNamesWithFiniteWeights) {
    auto store = preparedBox();
    insertAll(*store, oneProbePerSquareOfTheTop());
    for (int qi = 0; qi < 17; ++qi)
        for (int qk = 0; qk < 17; ++qk) {
            const ProbeQuery query = onTop(0.003f + 0.0617f * qi, 0.011f + 0.0589f * qk);
            const float radius = store->searchRadius(query), cover = store->coverageRadius(query);
            for (const int count : {1, 2, 5, kMaxServedProbes}) {
                ProbeNeighbour nearest[kMaxServedProbes];
                const int n = store->nearest(query, count, nearest);
                ProbeLookup shared;
                store->lookupNearest(query, count, shared);
                ASSERT_EQ(shared.count, n) << info().name << " " << describe(query);
                std::vector<double> expected;
                double expectedSum = 0.0;
                for (int i = 0; i < n; ++i) {
                    const double t = double(nearest[i].distance) / radius;
                    expected.push_back(t < 1.0 ? (1.0 - t * t) * (1.0 - t * t) : 0.0);
                    expectedSum += expected.back();
                }
                for (int i = 0; i < n; ++i) {
                    EXPECT_EQ(shared.probes[i].id, nearest[i].id) << info().name;
                    EXPECT_NEAR(shared.probes[i].weight, expectedSum > 0.0 ? expected[std::size_t(i)] / expectedSum : 1.0 / n, 1e-6) << info().name;
                }
                if (n > 0) {
                    const vec3 d = store->probe(nearest[0].id).position - query.position;
                    const float along = glm::dot(d, query.normal);
                    EXPECT_EQ(shared.covered, glm::length(d - along * query.normal) < cover && std::fabs(along) < cover) << info().name;
                    EXPECT_EQ(shared.distance, nearest[0].distance) << info().name;
                } else {
                    EXPECT_FALSE(shared.covered) << info().name;
                }

                ProbeLookup native;
                store->lookup(query, count, native);
                ASSERT_LE(native.count, store->servedAtMost(count)) << info().name;
                ASSERT_LE(store->servedAtMost(count), kMaxServedProbes) << info().name;
                for (const ProbeLookup* lookup : {&shared, &native}) {
                    std::set<uint32_t> ids;
                    double sum = 0.0;
                    for (int i = 0; i < lookup->count; ++i) {
                        EXPECT_LT(lookup->probes[i].id, store->idCapacity()) << info().name;
                        EXPECT_TRUE(ids.insert(lookup->probes[i].id).second) << info().name << ": id " << lookup->probes[i].id << " twice";
                        EXPECT_TRUE(std::isfinite(lookup->probes[i].weight) && lookup->probes[i].weight >= 0.0f) << info().name;
                        sum += lookup->probes[i].weight;
                    }
                    if (lookup->count > 0) {
                        EXPECT_NEAR(sum, 1.0, 1e-6) << info().name << " " << describe(query);
                    }
                }
            }
        }
}

// The raster stage's batches (issue 9): nearestBatch(), lookupBatch() and lookupNearestBatch()
// answer each query of a batch exactly as nearest(), lookup() and lookupNearest() answer it alone,
// for batches in raster order over several faces (queries revisit cells, change facing, cross
// cells and the store's coarser structure), with invalid queries among them.
TEST_P(ProbeStoreContract, ABatchOfQueriesGetsTheAnswersOfOneQueryAtATime) {
    auto store = preparedBox();
    insertAll(*store, oneProbePerSquareOfTheTop());
    insertAll(*store, mixedInsertsOnTheBox());
    const std::vector<ProbeQuery> lattice = latticeOnTheTopAndEastFaces();
    std::vector<ProbeQuery> batch;
    for (std::size_t i = 0; i < lattice.size(); ++i) {
        batch.push_back(lattice[i]);
        if (i % 97 == 0) batch.push_back(queryAt(vec3(std::numeric_limits<float>::quiet_NaN()), kUp));
    }
    const int n = int(batch.size());
    for (const int count : {1, 2, 5}) {
        std::vector<ProbeNeighbour> neighbours(std::size_t(n) * count);
        std::vector<int> found(static_cast<std::size_t>(n));
        store->nearestBatch(batch.data(), n, count, neighbours.data(), found.data());
        std::vector<ProbeLookup> native(static_cast<std::size_t>(n)), shared(static_cast<std::size_t>(n));
        store->lookupBatch(batch.data(), n, count, native.data());
        store->lookupNearestBatch(batch.data(), n, count, shared.data());
        for (int i = 0; i < n; ++i) {
            ProbeNeighbour alone[kMaxServedProbes];
            const int m = store->nearest(batch[std::size_t(i)], count, alone);
            ASSERT_EQ(found[std::size_t(i)], m) << info().name << " " << describe(batch[std::size_t(i)]) << " count " << count;
            for (int k = 0; k < m; ++k) {
                EXPECT_EQ(neighbours[std::size_t(i) * count + k].id, alone[k].id) << info().name << " query " << i << " rank " << k;
                EXPECT_EQ(neighbours[std::size_t(i) * count + k].distance, alone[k].distance) << info().name << " query " << i;
            }
            for (const bool nativeLookup : {true, false}) {
                ProbeLookup one;
                if (nativeLookup)
                    store->lookup(batch[std::size_t(i)], count, one);
                else
                    store->lookupNearest(batch[std::size_t(i)], count, one);
                const ProbeLookup& batched = nativeLookup ? native[std::size_t(i)] : shared[std::size_t(i)];
                ASSERT_EQ(batched.count, one.count) << info().name << " query " << i << (nativeLookup ? " native" : " nearest");
                EXPECT_EQ(batched.covered, one.covered) << info().name << " query " << i;
                EXPECT_EQ(batched.distance, one.distance) << info().name << " query " << i;
                for (int k = 0; k < one.count; ++k) {
                    EXPECT_EQ(batched.probes[k].id, one.probes[k].id) << info().name << " query " << i;
                    EXPECT_EQ(batched.probes[k].weight, one.probes[k].weight) << info().name << " query " << i;
                }
            }
        }
    }
}

// prefetchLookups() is a hint to the cache: over any queries, finite or not, inside the scene or far
// from it, it changes no answer and no stat (and under the sanitizers reads nothing out of bounds).
TEST_P(ProbeStoreContract, PrefetchingLookupsChangesNoAnswerNorStat) {
    auto store = preparedBox();
    insertAll(*store, oneProbePerSquareOfTheTop());
    insertAll(*store, mixedInsertsOnTheBox());
    std::vector<ProbeQuery> queries = latticeOnTheTopAndEastFaces();
    const float nan = std::nanf(""), far = 1e30f;
    for (const vec3& p : {vec3(nan, 1.0f, 0.5f), vec3(far, 1.0f, 0.5f), vec3(-far, -far, -far), vec3(0.5f, 1e7f, 0.5f)}) queries.push_back(queryAt(p, kUp));
    queries.push_back(queryAt({0.5f, 1.0f, 0.5f}, {nan, nan, nan}));
    const int count = 4;
    std::vector<ProbeLookup> before(queries.size());
    for (std::size_t i = 0; i < queries.size(); ++i) store->lookup(queries[i], count, before[i]);
    const Json statsBefore = store->stats();
    store->prefetchLookups(queries.data(), int(queries.size()));
    EXPECT_EQ(store->stats(), statsBefore) << info().name;
    for (std::size_t i = 0; i < queries.size(); ++i) {
        ProbeLookup after;
        store->lookup(queries[i], count, after);
        ASSERT_EQ(after.count, before[i].count) << info().name << " " << describe(queries[i]);
        EXPECT_EQ(after.covered, before[i].covered) << info().name << " " << describe(queries[i]);
        for (int k = 0; k < after.count; ++k) {
            EXPECT_EQ(after.probes[k].id, before[i].probes[k].id) << info().name << " " << describe(queries[i]);
            EXPECT_EQ(after.probes[k].weight, before[i].probes[k].weight) << info().name << " " << describe(queries[i]);
        }
    }
}

// The raster stage draws a pixel's jitter bits only for a store whose lookups read them
// (readsJitter()). A store that says they do not must answer every lookup the same whatever the
// bits (else the images would change with the bits skipped); one that says they do must answer some
// lookups differently (else the hash per pixel is wasted).
TEST_P(ProbeStoreContract, LookupsDependOnTheJitterBitsExactlyWhenTheStoreSaysTheyRead) {
    auto store = preparedBox();
    insertAll(*store, oneProbePerSquareOfTheTop());
    insertAll(*store, mixedInsertsOnTheBox());
    const std::vector<ProbeQuery> plain = latticeOnTheTopAndEastFaces();
    std::vector<ProbeQuery> jittered = plain;
    for (std::size_t i = 0; i < jittered.size(); ++i) jittered[i].jitter = uint32_t(mix64(uint64_t(i) + 1));
    const int n = int(plain.size());
    std::vector<ProbeLookup> withoutBits(static_cast<std::size_t>(n)), withBits(static_cast<std::size_t>(n));
    store->lookupBatch(plain.data(), n, 2, withoutBits.data());
    store->lookupBatch(jittered.data(), n, 2, withBits.data());
    int differ = 0;
    for (int i = 0; i < n; ++i) {
        const ProbeLookup &a = withoutBits[std::size_t(i)], &b = withBits[std::size_t(i)];
        bool same = a.count == b.count && a.covered == b.covered && a.distance == b.distance && a.receiver == b.receiver;
        for (int k = 0; same && k < a.count; ++k) same = a.probes[k].id == b.probes[k].id && a.probes[k].weight == b.probes[k].weight;
        differ += !same;
    }
    if (store->readsJitter())
        EXPECT_GT(differ, 0) << info().name << " says its lookups read the jitter bits, yet none of " << n << " answers changed with them";
    else
        EXPECT_EQ(differ, 0) << info().name << " says its lookups ignore the jitter bits, yet " << differ << " of " << n << " answers changed";
}

// The update stage routes a sample with the receiver a lookup of its point reported
// (ProbeLookup::receiver): whenever a lookup reports one, it is receiverOf()'s answer, for every
// lookup path, on faces with and without probes nearby and for invalid queries; and a store whose
// receiver is the nearest probe reports it from every nearest-N lookup.
TEST_P(ProbeStoreContract, ALookupThatReportsAReceiverReportsReceiverOfsAnswer) {
    auto store = preparedBox();
    insertAll(*store, oneProbePerSquareOfTheTop());
    insertAll(*store, mixedInsertsOnTheBox());
    std::vector<ProbeQuery> queries;
    for (int i = 0; i < 40; ++i)
        for (int k = 0; k < 40; ++k) {
            const float a = 0.001f + 0.0251f * i, b = 0.002f + 0.0249f * k;
            queries.push_back(onTop(a, b));
            queries.push_back(queryAt({1.0f, a, b}, kEast));
            queries.push_back(queryAt({0.0f, a, b}, kWest));  // a face without probes
        }
    queries.push_back(queryAt(vec3(std::numeric_limits<float>::quiet_NaN()), kUp));
    const int n = int(queries.size());
    int reported = 0;
    for (const int count : {1, 2, 5}) {
        std::vector<ProbeLookup> native(static_cast<std::size_t>(n)), shared(static_cast<std::size_t>(n));
        store->lookupBatch(queries.data(), n, count, native.data());
        store->lookupNearestBatch(queries.data(), n, count, shared.data());
        for (int i = 0; i < n; ++i) {
            const ProbeQuery& q = queries[std::size_t(i)];
            ProbeLookup one, oneNearest;
            store->lookup(q, count, one);
            store->lookupNearest(q, count, oneNearest);
            uint32_t expected = kNoReceiver;
            if (!store->receiverOf(q, expected)) expected = kNoReceiver;
            for (const ProbeLookup* l : {&native[std::size_t(i)], &shared[std::size_t(i)], &one, &oneNearest}) {
                if (l->receiver == kReceiverUnknown) continue;
                ++reported;
                ASSERT_EQ(l->receiver, expected) << info().name << " " << describe(q) << " count " << count;
            }
            if (store->receiverIsNearest()) {
                EXPECT_NE(shared[std::size_t(i)].receiver, kReceiverUnknown) << info().name << " " << describe(q);
                EXPECT_NE(oneNearest.receiver, kReceiverUnknown) << info().name << " " << describe(q);
            }
        }
    }
    EXPECT_GT(reported, n) << info().name << ": lookups that report their receiver";
}

// The update stage tells whether a probe placed since a sample's receiver was found could change
// it by the placed probe's distance (ProbeCache::mayHaveChanged): receiverOf()'s probe always lies
// within searchRadius() of the query, on faces with probes and past the edges of cards and cells.
TEST_P(ProbeStoreContract, TheReceiverLiesWithinTheSearchRadius) {
    auto store = preparedBox();
    insertAll(*store, oneProbePerSquareOfTheTop());
    insertAll(*store, mixedInsertsOnTheBox());
    int received = 0;
    for (int i = -2; i < 44; ++i)
        for (int k = -2; k < 44; ++k) {
            const float a = 0.001f + 0.0251f * i, b = 0.002f + 0.0249f * k;
            for (const ProbeQuery& q : {onTop(a, b), queryAt({1.0f, a, b}, kEast)}) {
                uint32_t id;
                if (!store->receiverOf(q, id)) continue;
                ++received;
                const vec3 d = store->probe(id).position - q.position;
                const float radius = store->searchRadius(q);
                EXPECT_FALSE(glm::dot(d, d) > radius * radius) << info().name << " " << describe(q) << ": probe " << id << " at "
                                                               << glm::length(d) << ", search radius " << radius;
            }
        }
    EXPECT_GT(received, 0) << info().name;
}

TEST_P(ProbeStoreContract, TheTwoSidesOfAThinWallNeverShareAProbe) {
    auto store = prepared(spacing(kSpacing), roomWithThinWall());
    std::vector<uint32_t> eastIds, westIds;
    for (int i = 0; i < 5; ++i) {
        // Diagonal steps of 0.28, beyond searchRadius(): each point sees only its own side's probe.
        const float y = 0.1f + 0.2f * i, z = 0.9f - 0.2f * i;
        const ProbeQuery east = queryAt({kWallEast, y, z}, kEast, 1), west = queryAt({kWallWest, y, z}, kWest, 1);
        const ProbeInsert e = store->insert(east, 0);
        ASSERT_EQ(e.status, ProbeInsert::Status::Inserted) << info().name << " " << describe(east);
        eastIds.push_back(e.id);
        EXPECT_EQ(nearestOf(*store, west, 4).size(), 0u) << info().name << " " << describe(west) << ": the west side sees no east probe";
        const ProbeInsert w = store->insert(west, 0);
        ASSERT_EQ(w.status, ProbeInsert::Status::Inserted) << info().name << " " << describe(west) << ": a west probe of its own";
        westIds.push_back(w.id);
    }
    for (int i = 0; i < 5; ++i) {
        const float y = 0.1f + 0.2f * i, z = 0.9f - 0.2f * i;
        const ProbeQuery east = queryAt({kWallEast, y, z}, kEast, 1), west = queryAt({kWallWest, y, z}, kWest, 1);
        const std::vector<ProbeNeighbour> e = nearestOf(*store, east, 4), w = nearestOf(*store, west, 4);
        ASSERT_EQ(e.size(), 1u) << info().name << " " << describe(east);
        EXPECT_EQ(e[0].id, eastIds[std::size_t(i)]) << info().name << " " << describe(east);
        ASSERT_EQ(w.size(), 1u) << info().name << " " << describe(west);
        EXPECT_EQ(w[0].id, westIds[std::size_t(i)]) << info().name << " " << describe(west);
    }
    // Anywhere along the wall, neither side is offered a probe of the other.
    for (int a = 0; a <= 20; ++a)
        for (int b = 0; b <= 20; ++b)
            for (const ProbeQuery& q : {queryAt({kWallEast, 0.05f * a, 0.05f * b}, kEast, 1), queryAt({kWallWest, 0.05f * a, 0.05f * b}, kWest, 1)})
                for (const ProbeNeighbour& f : nearestOf(*store, q, 16))
                    EXPECT_GT(glm::dot(store->probe(f.id).normal, q.normal), 0.0f) << info().name << " " << describe(q) << " id " << f.id;
}

TEST_P(ProbeStoreContract, NonFiniteQueriesAreRefusedFindNothingAndAreCounted) {
    auto store = preparedBox();
    // A probe right where the invalid queries point, so that finding nothing means refusing them.
    ASSERT_EQ(store->insert(onTop(0.5f, 0.5f), 0).status, ProbeInsert::Status::Inserted) << info().name;
    const float nan = std::nanf(""), inf = kInfinity;
    const ProbeQuery invalid[] = {
        queryAt({nan, 1.0f, 0.5f}, kUp),  queryAt({0.5f, inf, 0.5f}, kUp),  queryAt({0.5f, 1.0f, -inf}, kUp),
        queryAt({0.5f, 1.0f, 0.5f}, {0, nan, 0}), queryAt({0.5f, 1.0f, 0.5f}, {0, inf, 0}), queryAt({nan, nan, nan}, {nan, nan, nan}),
    };
    for (const ProbeQuery& q : invalid) {
        EXPECT_EQ(nearestOf(*store, q, 4).size(), 0u) << info().name << " " << describe(q);
        const Json before = store->stats();
        EXPECT_EQ(store->insert(q, 0).status, ProbeInsert::Status::Refused) << info().name << " " << describe(q);
        const Json after = store->stats();
        EXPECT_NE(after, before) << info().name << " " << describe(q) << ": a refusal is counted, never silent";
        EXPECT_EQ(after["probes"], 1) << info().name << " " << describe(q);
        EXPECT_EQ(store->idCapacity(), 1u) << info().name << " " << describe(q);
        EXPECT_TRUE(allNumbersFinite(after)) << info().name << " " << after.dump();
    }
}

TEST_P(ProbeStoreContract, QueriesNamingNoMeshOfTheSceneAreRefusedByStoresThatReadTheMesh) {
    // A store that reads the query's mesh refuses one the scene does not have, and finds nothing for
    // it; a store that places probes by position alone must answer exactly as for mesh 0. Two stores
    // with the same probe, one asked with the wrong mesh, the other with mesh 0.
    for (const int mesh : {-1, 1, 1 << 30}) {
        auto asked = preparedBox(), reference = preparedBox();
        // A probe within searchRadius() of the query, in another cell or texel of every store.
        ASSERT_EQ(asked->insert(onTop(0.42f, 0.42f), 0).status, ProbeInsert::Status::Inserted) << info().name;
        ASSERT_EQ(reference->insert(onTop(0.42f, 0.42f), 0).status, ProbeInsert::Status::Inserted) << info().name;
        ProbeQuery q = onTop(0.57f, 0.53f);
        const std::vector<ProbeNeighbour> expected = nearestOf(*reference, q, 4);
        ASSERT_EQ(expected.size(), 1u) << info().name << " " << describe(q);
        q.mesh = mesh;
        const std::vector<ProbeNeighbour> found = nearestOf(*asked, q, 4);
        const Json before = asked->stats();
        const ProbeInsert r = asked->insert(q, 0);
        if (r.status == ProbeInsert::Status::Refused) {
            EXPECT_EQ(found.size(), 0u) << info().name << " " << describe(q) << ": refused, yet nearest() serves it";
            EXPECT_NE(asked->stats(), before) << info().name << " " << describe(q) << ": a refusal is counted";
        } else {
            const ProbeInsert r0 = reference->insert(onTop(0.57f, 0.53f), 0);
            EXPECT_EQ(r.status, r0.status) << info().name << " " << describe(q);
            EXPECT_EQ(r.id, r0.id) << info().name << " " << describe(q);
            ASSERT_EQ(found.size(), expected.size()) << info().name << " " << describe(q);
            EXPECT_EQ(found[0].id, expected[0].id) << info().name << " " << describe(q);
            EXPECT_EQ(found[0].distance, expected[0].distance) << info().name << " " << describe(q);
        }
    }
}

// --- An empty scene ----------------------------------------------------------------------------

TEST_P(ProbeStoreContract, AnEmptySceneIsPreparedWithNoProbesAndNotedAsSuch) {
    auto store = make(Json::object());
    RunNotes notes;
    ASSERT_EQ(errorOf([&] { store->prepare(Scene{}, notes); }), "") << info().name;
    EXPECT_TRUE(std::any_of(notes.skipped.begin(), notes.skipped.end(), [](const Json& n) { return n["stage"] == "probes"; }))
        << info().name << ": the notes say the scene gets no probes";
    const std::vector<ProbeQuery> queries = {queryAt(vec3(0), kUp), queryAt({0.5f, 1.0f, 0.5f}, kUp), queryAt({3, -2, 7}, kEast)};
    for (const ProbeQuery& q : queries) EXPECT_EQ(nearestOf(*store, q, 4).size(), 0u) << info().name << " " << describe(q);
    const Json stats = store->stats();
    EXPECT_EQ(stats["store"], info().name);
    EXPECT_EQ(stats["probes"], 0) << info().name;
    ASSERT_TRUE(stats["store_bytes"].is_number()) << info().name << " " << stats.dump();
    EXPECT_GE(stats["store_bytes"].get<double>(), 0.0) << info().name;
    EXPECT_TRUE(allNumbersFinite(stats)) << info().name << " " << stats.dump();
    // With no surface to serve, every insert is refused, without throwing.
    for (const ProbeQuery& q : queries)
        EXPECT_EQ(errorOf([&] { EXPECT_EQ(store->insert(q, 0).status, ProbeInsert::Status::Refused) << info().name << " " << describe(q); }),
                  "")
            << info().name << " " << describe(q);
    EXPECT_EQ(store->stats()["probes"], 0) << info().name;
    EXPECT_TRUE(allNumbersFinite(store->stats())) << info().name << " " << store->stats().dump();
    EXPECT_EQ(store->stats()["store"], info().name);
}

// --- stats() ---------------------------------------------------------------------------------------

TEST_P(ProbeStoreContract, StatsNameTheStoreCountLiveProbesAndHoldBytesThatNeverShrink) {
    auto store = preparedBox();
    Json stats = store->stats();
    EXPECT_EQ(stats["store"], info().name);
    EXPECT_EQ(stats["probes"], 0) << info().name;
    double bytes = storeBytes(*store);
    EXPECT_GT(bytes, 0.0) << info().name << ": prepared for a scene, the store holds something";

    std::vector<ProbeQuery> queries = oneProbePerSquareOfTheTop();
    for (const std::vector<ProbeQuery>& more : {denseLatticeOnTheTop(), mixedInsertsOnTheBox()}) queries.insert(queries.end(), more.begin(), more.end());
    std::set<uint32_t> live;
    for (const ProbeQuery& q : queries) {
        const ProbeInsert r = store->insert(q, 0);
        if (r.status != ProbeInsert::Status::Refused) live.insert(r.id);  // Evicted reuses the id of a probe that is gone
        stats = store->stats();
        EXPECT_EQ(stats["store"], info().name);
        EXPECT_EQ(stats["probes"], live.size()) << info().name << " " << describe(q);
        const double now = stats["store_bytes"].get<double>();
        EXPECT_GE(now, bytes) << info().name << " " << describe(q);
        bytes = now;
    }
    EXPECT_TRUE(allNumbersFinite(stats)) << info().name << " " << stats.dump();
}

// --- Determinism -------------------------------------------------------------------------------

TEST_P(ProbeStoreContract, TheSameInsertsGiveTheSameIdsAndTheSameNeighbours) {
    auto a = prepared(spacing(kSpacing), roomWithThinWall()), b = prepared(spacing(kSpacing), roomWithThinWall());
    std::vector<ProbeQuery> queries = mixedInsertsOnTheBox();
    for (int i = 0; i < 40; ++i) {
        queries.push_back(queryAt({kWallEast, 0.025f * i, 0.5f}, kEast, 1));
        queries.push_back(queryAt({kWallWest, 0.5f, 0.025f * i}, kWest, 1));
    }
    uint32_t frame = 0;
    for (std::size_t i = 0; i < queries.size(); ++i) {
        if (i % 50 == 0) {
            ++frame;
            a->beginFrame(CameraPose{}, frame);
            b->beginFrame(CameraPose{}, frame);
        }
        const ProbeInsert ra = a->insert(queries[i], frame), rb = b->insert(queries[i], frame);
        EXPECT_EQ(ra.status, rb.status) << info().name << " insert " << i << " " << describe(queries[i]);
        EXPECT_EQ(ra.id, rb.id) << info().name << " insert " << i << " " << describe(queries[i]);
    }
    EXPECT_EQ(a->idCapacity(), b->idCapacity()) << info().name;
    for (const ProbeQuery& q : queries) {
        const std::vector<ProbeNeighbour> fa = nearestOf(*a, q, 8), fb = nearestOf(*b, q, 8);
        ASSERT_EQ(fa.size(), fb.size()) << info().name << " " << describe(q);
        for (std::size_t i = 0; i < fa.size(); ++i) {
            EXPECT_EQ(fa[i].id, fb[i].id) << info().name << " " << describe(q) << " rank " << i;
            EXPECT_EQ(fa[i].distance, fb[i].distance) << info().name << " " << describe(q) << " rank " << i;
        }
    }
    EXPECT_EQ(a->stats(), b->stats()) << info().name;
}

// --- Frames: touch(), admitUpdate(), beginFrame() -----------------------------------------------------

TEST_P(ProbeStoreContract, TouchAndAdmitUpdateOnLiveProbesAndBeginFrameResetsTheBudget) {
    auto store = preparedBox();
    const std::vector<uint32_t> ids = insertAll(*store, oneProbePerSquareOfTheTop());
    ASSERT_FALSE(ids.empty()) << info().name;
    std::vector<Probe> placed;
    for (const uint32_t id : ids) placed.push_back(store->probe(id));
    for (uint32_t frame = 1; frame <= 4; ++frame) {
        store->beginFrame(CameraPose{}, frame);
        // A probe not yet updated this frame: a fresh budget admits it.
        const uint32_t first = ids[(frame * 37u) % ids.size()];
        EXPECT_TRUE(store->admitUpdate(first)) << info().name << " frame " << frame << " id " << first;
        for (int pass = 0; pass < 3; ++pass)
            for (const uint32_t id : ids) {
                store->touch(id, frame);
                store->admitUpdate(id);  // may refuse once a per-frame budget is spent
            }
    }
    for (std::size_t i = 0; i < ids.size(); ++i) {
        EXPECT_EQ(store->probe(ids[i]).position, placed[i].position) << info().name << " id " << ids[i] << ": updates move no probe";
        EXPECT_EQ(store->probe(ids[i]).normal, placed[i].normal) << info().name << " id " << ids[i];
    }
    EXPECT_TRUE(allNumbersFinite(store->stats())) << info().name << " " << store->stats().dump();
}

INSTANTIATE_TEST_SUITE_P(EveryStore, ProbeStoreContract, testing::ValuesIn(probeStoreTable()),
                         [](const testing::TestParamInfo<ProbeStoreInfo>& p) { return p.param.name; });

}  // namespace
}  // namespace gibench
