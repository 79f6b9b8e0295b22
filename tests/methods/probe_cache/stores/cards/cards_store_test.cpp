#include "methods/probe_cache/stores/cards/cards_store.h"

#include "core/util/rng.h"
#include "support/store_test_helpers.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gibench {
namespace {

using namespace test;  // the store-test helpers (support/store_test_helpers.h)

std::unique_ptr<ProbeStore> makeStore(const Json& block) { return test::makeStore(block, test::storeRow("cards")); }

// Cards starting empty (capture "on_demand"): only the probes a test inserts.
std::unique_ptr<ProbeStore> preparedStore(const Json& block, const Scene& scene) {
    return test::prepared(makeStore(startingEmpty(storeRow("cards"), block)), scene);
}

// Cards as a run prepares them by default: every texel captured from the meshes.
std::unique_ptr<ProbeStore> capturedStore(const Json& block, const Scene& scene) { return test::prepared(makeStore(block), scene); }

// The probe whose position is `p` (to 1e-5), or -1.
int64_t probeAt(const ProbeStore& store, const vec3& p) {
    for (uint32_t id = 0; id < store.idCapacity(); ++id)
        if (glm::length(store.probe(id).position - p) < 1e-5f) return id;
    return -1;
}

// The weight `lookup` gives probe `id`, 0 when it does not serve it.
float weightOf(const ProbeLookup& lookup, int64_t id) {
    for (int i = 0; i < lookup.count; ++i)
        if (int64_t(lookup.probes[i].id) == id) return lookup.probes[i].weight;
    return 0.0f;
}

const vec3 kUp(0, 1, 0), kEast(1, 0, 0);

TEST(CardsStore, SurfacesFoldedOntoOneTexelAtAnotherDepthAreConflicts) {
    // One mesh, two parallel walls facing +X a unit apart: box projection folds them onto one card.
    Mesh walls;
    addQuad(walls, {0, 0, 0}, {0, 1, 0}, {0, 0, 1});
    addQuad(walls, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
    auto store = preparedStore({{"texel_size", 0.1}}, sceneOf({walls}));
    EXPECT_EQ(store->stats()["cards"], 1);
    ASSERT_EQ(store->insert(queryAt({0.0f, 0.55f, 0.55f}, kEast), 0).status, ProbeInsert::Status::Inserted);
    EXPECT_EQ(store->insert(queryAt({1.0f, 0.52f, 0.58f}, kEast), 0).status, ProbeInsert::Status::Refused);
    ProbeNeighbour found[9];
    EXPECT_EQ(store->nearest(queryAt({1.0f, 0.52f, 0.58f}, kEast), 9, found), 0);
    // Within depth_tolerance (2 texels) the texel's probe is the same surface's.
    EXPECT_EQ(store->insert(queryAt({0.05f, 0.58f, 0.52f}, kEast), 0).status, ProbeInsert::Status::Refused);
    Json stats = store->stats();
    EXPECT_EQ(stats["depth_conflicts"], 1);
    EXPECT_EQ(stats["texel_occupied"], 1);
    EXPECT_EQ(stats["refused"], 2);
    EXPECT_EQ(stats["probes"], 1);

    // Walls 0.8 texel apart with a tolerance of half a texel: the probe is within the search
    // radius but on the other surface, so nearest() rejects it.
    Mesh close;
    addQuad(close, {0, 0, 0}, {0, 1, 0}, {0, 0, 1});
    addQuad(close, {0.08f, 0, 0}, {0, 1, 0}, {0, 0, 1});
    auto strict = preparedStore({{"texel_size", 0.1}, {"depth_tolerance", 0.5}}, sceneOf({close}));
    ASSERT_EQ(strict->insert(queryAt({0.0f, 0.55f, 0.55f}, kEast), 0).status, ProbeInsert::Status::Inserted);
    EXPECT_EQ(strict->nearest(queryAt({0.08f, 0.55f, 0.55f}, kEast), 9, found), 0);
    EXPECT_EQ(strict->insert(queryAt({0.08f, 0.55f, 0.55f}, kEast), 0).status, ProbeInsert::Status::Refused);
    EXPECT_EQ(strict->stats()["depth_conflicts"], 1);
    ASSERT_EQ(strict->nearest(queryAt({0.02f, 0.55f, 0.55f}, kEast), 9, found), 1) << "the same surface is served";
}

TEST(CardsStore, OnlyDirectionsTheMeshFacesGetCardsAndOtherQueriesFindNone) {
    Mesh floor;
    addQuad(floor, {0, 0, 0}, {0, 0, 1}, {1, 0, 0});  // faces +Y
    auto store = preparedStore({{"texel_size", 0.1}}, sceneOf({floor}));
    EXPECT_EQ(store->stats()["cards"], 1);
    EXPECT_EQ(store->stats()["atlas_texels"], 100) << "a flat mesh's card is one texel thick only in depth";
    ASSERT_EQ(store->insert(queryAt({0.5f, 0.0f, 0.5f}, kUp), 0).status, ProbeInsert::Status::Inserted);

    ProbeNeighbour found[9];
    for (const ProbeQuery& q : {queryAt({0.5f, 0.0f, 0.5f}, -kUp), queryAt({0.5f, 0.0f, 0.5f}, kEast),
                                queryAt({1.2f, 0.0f, 0.5f}, kUp)}) {
        EXPECT_EQ(store->nearest(q, 9, found), 0);
        EXPECT_EQ(store->insert(q, 0).status, ProbeInsert::Status::Refused);
    }
    // A rounding error off the card's rectangle maps to its border texel.
    EXPECT_EQ(store->insert(queryAt({1.0f + 1e-6f, 0.0f, 0.5f}, kUp), 0).status, ProbeInsert::Status::Inserted);
    EXPECT_EQ(store->stats()["no_card"], 3);
    EXPECT_EQ(store->stats()["refused"], 3);
}

TEST(CardsStore, InvalidQueriesAndQueriesWithNoCardTexelAreRefusedAndCountedApart) {
    // That invalid queries find nothing holds for every store (store_contract_test.cpp); here, how
    // cards counts them.
    auto store = preparedStore({{"texel_size", 0.1}}, sceneOf({boxMesh(vec3(0), vec3(1))}));
    const float nan = std::nanf(""), inf = kInfinity;
    const ProbeQuery invalid[] = {queryAt({0.5f, 1.0f, 0.5f}, kUp, -1), queryAt({0.5f, 1.0f, 0.5f}, kUp, 1),
                                  queryAt({nan, 1.0f, 0.5f}, kUp), queryAt({0.5f, inf, 0.5f}, kUp), queryAt({0.5f, 1.0f, 0.5f}, {0, nan, 0})};
    for (const ProbeQuery& q : invalid) EXPECT_EQ(store->insert(q, 0).status, ProbeInsert::Status::Refused);
    // Far away, or with no direction: no card texel.
    for (const ProbeQuery& q : {queryAt({3e38f, 1.0f, 0.5f}, kUp), queryAt({0.5f, 1.0f, -1e30f}, kUp), queryAt({0.5f, 1.0f, 0.5f}, vec3(0))}) {
        ProbeNeighbour found;
        EXPECT_EQ(store->nearest(q, 1, &found), 0);
        EXPECT_EQ(store->insert(q, 0).status, ProbeInsert::Status::Refused);
    }
    const Json stats = store->stats();
    EXPECT_EQ(stats["invalid_queries"], 5);
    EXPECT_EQ(stats["no_card"], 3);
    EXPECT_EQ(stats["refused"], 8);
    EXPECT_EQ(stats["probes"], 0);
}

TEST(CardsStore, BytesGrowWithSurfaceAreaNotSceneVolume) {
    // 4 bytes per atlas texel, 40 per card, 24 per mesh while there are no probes.
    const Json block = {{"texel_size", 0.0625}};
    const Json one = preparedStore(block, sceneOf({boxMesh(vec3(0), vec3(1))}))->stats();
    const Json two = preparedStore(block, sceneOf({boxMesh(vec3(0), vec3(2))}))->stats();
    EXPECT_EQ(one["cards"], 6) << "one card per face of the box";
    EXPECT_EQ(one["atlas_texels"], 6 * 16 * 16);
    EXPECT_EQ(one["store_bytes"], 6 * 16 * 16 * 4 + 6 * 40 + 24);
    EXPECT_EQ(two["store_bytes"], 6 * 32 * 32 * 4 + 6 * 40 + 24);
    const double ratio = two["store_bytes"].get<double>() / one["store_bytes"].get<double>();
    EXPECT_GT(ratio, 3.8) << "double the bounds, about 4× the bytes";
    EXPECT_LT(ratio, 4.0);

    // Two unit boxes far apart: twice the bytes of one, whatever the volume between them.
    const Json apart = preparedStore(block, sceneOf({boxMesh(vec3(0), vec3(1)), boxMesh(vec3(20), vec3(21))}))->stats();
    EXPECT_EQ(apart["store_bytes"], 2 * (6 * 16 * 16 * 4 + 6 * 40 + 24));

    // Probes add 28 bytes each (position, normal, the frame of their last admitted update).
    auto store = preparedStore(block, sceneOf({boxMesh(vec3(0), vec3(1))}));
    for (int i = 0; i < 8; ++i) store->insert(queryAt({0.1f * i + 0.05f, 1.0f, 0.5f}, kUp), 0);
    EXPECT_EQ(store->stats()["probes"], 8);
    const auto bytes = store->stats()["store_bytes"].get<std::size_t>();
    EXPECT_GE(bytes, std::size_t(one["store_bytes"].get<std::size_t>() + 8 * 28));
    EXPECT_LE(bytes, std::size_t(one["store_bytes"].get<std::size_t>() + 16 * 28)) << "std::vector growth";
}

TEST(CardsStore, UpdateBudgetAdmitsAtMostThatManyDistinctTexelsPerFrame) {
    auto store = preparedStore({{"texel_size", 0.1}, {"texel_update_budget", 3}}, sceneOf({boxMesh(vec3(0), vec3(1))}));
    for (int i = 0; i < 5; ++i) ASSERT_EQ(store->insert(queryAt({0.1f * i + 0.05f, 1.0f, 0.5f}, kUp), 0).id, uint32_t(i));
    store->beginFrame(CameraPose{}, 1);
    EXPECT_TRUE(store->admitUpdate(0));
    EXPECT_TRUE(store->admitUpdate(1));
    EXPECT_TRUE(store->admitUpdate(2));
    EXPECT_TRUE(store->admitUpdate(1)) << "a texel admitted this frame takes more updates at no charge";
    EXPECT_FALSE(store->admitUpdate(3)) << "the fourth distinct texel";
    EXPECT_FALSE(store->admitUpdate(4));
    EXPECT_TRUE(store->admitUpdate(0));
    EXPECT_FALSE(store->admitUpdate(99)) << "no such probe";
    Json stats = store->stats();
    EXPECT_EQ(stats["budget_rejections"], 2);
    EXPECT_EQ(stats["frame_updates"], 3);

    store->beginFrame(CameraPose{}, 2);
    EXPECT_TRUE(store->admitUpdate(3)) << "the budget resets each frame";
    EXPECT_TRUE(store->admitUpdate(4));
    stats = store->stats();
    EXPECT_EQ(stats["frame_updates"], 2);
    EXPECT_EQ(stats["budget_rejections"], 2);
    EXPECT_EQ(stats["refused"], 0) << "update refusals are not insert refusals";
}

TEST(CardsStore, CaptureBudgetCapsProbesCreatedPerFrame) {
    auto store = preparedStore({{"texel_size", 0.1}, {"texel_capture_budget", 2}}, sceneOf({boxMesh(vec3(0), vec3(1))}));
    store->beginFrame(CameraPose{}, 0);
    EXPECT_EQ(store->insert(queryAt({0.15f, 1.0f, 0.5f}, kUp), 0).status, ProbeInsert::Status::Inserted);
    EXPECT_EQ(store->insert(queryAt({0.35f, 1.0f, 0.5f}, kUp), 0).status, ProbeInsert::Status::Inserted);
    EXPECT_EQ(store->insert(queryAt({0.55f, 1.0f, 0.5f}, kUp), 0).status, ProbeInsert::Status::Refused);
    EXPECT_EQ(store->stats()["capture_budget_rejections"], 1);
    EXPECT_EQ(store->stats()["refused"], 1);
    store->beginFrame(CameraPose{}, 1);
    EXPECT_EQ(store->insert(queryAt({0.55f, 1.0f, 0.5f}, kUp), 0).status, ProbeInsert::Status::Inserted);
    EXPECT_EQ(store->stats()["frame_captures"], 1);
    // Captures and updates have separate budgets.
    EXPECT_TRUE(store->admitUpdate(2));
}

TEST(CardsStore, AnAtlasTooLargeIsAnInputErrorNamingTheKey) {
    const Scene unitBox = sceneOf({boxMesh(vec3(0), vec3(1))});
    EXPECT_EQ(errorOf([&] { preparedStore({{"texel_size", 0.125}, {"max_atlas_texels", 300}}, unitBox); }),
              "cfg.json: /method/max_atlas_texels: the scene's 6 cards need 384 texels of 0.125 units, more than max_atlas_texels = "
              "300; raise max_atlas_texels or the texel size");
    EXPECT_EQ(errorOf([&] { preparedStore({{"texel_size", 0.125}, {"max_atlas_texels", 384}}, unitBox); }), "");
    // A count beyond every 32-bit type is reported, not overflowed.
    const std::string huge = errorOf([&] { preparedStore({{"texel_size", 1e-6}}, unitBox); });
    EXPECT_EQ(huge.rfind("cfg.json: /method/max_atlas_texels: the scene's 6 cards need ", 0), 0u) << huge;
}

TEST(CardsStore, ItsOwnKeysOutOfRangeAreInputErrorsNamingTheKey) {
    // The spacing keys, unknown keys and the resolved parameters are checked for every store in
    // store_contract_test.cpp.
    EXPECT_EQ(errorOf([] { makeStore({{"depth_tolerance", -1}}); }),
              "cfg.json: /method/depth_tolerance: expected a number >= 0, got -1");
    EXPECT_EQ(errorOf([] { makeStore({{"texel_update_budget", 0}}); }),
              "cfg.json: /method/texel_update_budget: expected an integer in [1, 1073741824], got 0");
    EXPECT_EQ(errorOf([] { makeStore({{"texel_capture_budget", 2.5}}); }),
              "cfg.json: /method/texel_capture_budget: expected an integer in [1, 1073741824], got 2.5");
    EXPECT_EQ(errorOf([] { makeStore({{"max_atlas_texels", 1ll << 32}}); }),
              "cfg.json: /method/max_atlas_texels: expected an integer in [1, 4294967295], got 4294967296");

    // The defaults the resolved parameters report.
    Params params(Json{{"texel_size", 0.2}}, "cfg.json", "/method", "method \"cards\"", &cardsStoreParams());
    createCardsStore(params);
    const Json resolved = params.resolved();
    EXPECT_EQ(resolved["texel_update_budget"], 4096);
    EXPECT_EQ(resolved["depth_tolerance"], 2.0);
}

TEST(CardsStore, AnEmptySceneHasNoCards) {
    auto store = makeStore(Json::object());
    RunNotes notes;
    store->prepare(Scene{}, notes);
    EXPECT_EQ(store->insert(queryAt(vec3(0), kUp), 0).status, ProbeInsert::Status::Refused);
    EXPECT_EQ(store->stats()["cards"], 0);
    EXPECT_EQ(store->stats()["invalid_queries"], 1) << "mesh 0 does not exist";
    ASSERT_EQ(notes.skipped.size(), 1u);
    EXPECT_EQ(notes.skipped[0]["stage"], "probes");
}

TEST(CardsStore, SceneCaptureGivesEveryTexelOfABoxFaceAProbeAtItsCentreOnTheFace) {
    auto store = capturedStore({{"texel_size", 0.1}}, sceneOf({boxMesh(vec3(0), vec3(1))}));
    // Six 10 × 10 cards, one probe per texel.
    ASSERT_EQ(store->idCapacity(), 600u);
    EXPECT_EQ(store->stats()["captured_at_prepare"], 600);
    for (int i = 0; i < 10; ++i)
        for (int k = 0; k < 10; ++k) {
            const float a = 0.05f + 0.1f * float(i), b = 0.05f + 0.1f * float(k);
            const int64_t top = probeAt(*store, {a, 1.0f, b}), bottom = probeAt(*store, {a, 0.0f, b});
            ASSERT_GE(top, 0) << a << "," << b;
            ASSERT_GE(bottom, 0) << a << "," << b;
            EXPECT_NEAR(store->probe(uint32_t(top)).normal.y, 1.0f, 1e-6f);
            EXPECT_NEAR(store->probe(uint32_t(bottom)).normal.y, -1.0f, 1e-6f);
        }
    // Captured texels are covered: an insert there is refused as occupied, not placed twice.
    EXPECT_EQ(store->insert(queryAt({0.5f, 1.0f, 0.5f}, kUp), 0).status, ProbeInsert::Status::Refused);
    EXPECT_EQ(store->stats()["texel_occupied"], 1);
}

TEST(CardsStore, SceneCaptureKeepsTheFrontMostSurfaceOfATexelAndTheOneBehindReadsNothingFromIt) {
    // One mesh with two floors facing up, at y = 0 (x, z in [0, 1]) and at y = 0.5 over x < 0.5:
    // the card of +Y sees the upper one where it lies over the lower one.
    Mesh floors;
    addQuad(floors, vec3(0, 0, 0), vec3(0, 0, 1), vec3(1, 0, 0));
    addQuad(floors, vec3(0, 0.5f, 0), vec3(0, 0, 1), vec3(0.5f, 0, 0));
    auto store = capturedStore({{"texel_size", 0.1}}, sceneOf({floors}));
    ASSERT_EQ(store->idCapacity(), 100u) << "one probe per texel of the 10 × 10 card of +Y";
    EXPECT_GE(probeAt(*store, {0.25f, 0.5f, 0.45f}), 0) << "the upper floor where the two overlap";
    EXPECT_LT(probeAt(*store, {0.25f, 0.0f, 0.45f}), 0) << "the lower floor hidden under it";
    EXPECT_GE(probeAt(*store, {0.75f, 0.0f, 0.45f}), 0) << "the lower floor where nothing hides it";

    ProbeLookup hidden, seen;
    store->lookup(queryAt({0.25f, 0.0f, 0.45f}, kUp), 2, hidden);
    EXPECT_EQ(hidden.count, 0) << "the texels above it hold the upper floor, 0.5 away: beyond depth_tolerance";
    EXPECT_FALSE(hidden.covered);
    store->lookup(queryAt({0.75f, 0.0f, 0.45f}, kUp), 2, seen);
    EXPECT_TRUE(seen.covered);
    EXPECT_GT(seen.count, 0);
}

TEST(CardsStore, LookupFiltersTwoByTwoTexelsBilinearlyOnEachCardAndBlendsCardsByTheNormalSquared) {
    auto store = capturedStore({{"texel_size", 0.1}}, sceneOf({boxMesh(vec3(0), vec3(1))}));
    // Near the +X edge of the top face, the normal tilted towards +X: n = (0.6, 0.8, 0) reads the
    // card of +Y with weight 0.64 and the card of +X with weight 0.36.
    const ProbeQuery query = queryAt({0.93f, 1.0f, 0.47f}, {0.6f, 0.8f, 0.0f});
    ProbeLookup served;
    store->lookup(query, 2, served);
    ASSERT_LE(served.count, store->servedAtMost(2));
    EXPECT_TRUE(served.covered) << "its own texel of the top card holds a probe";
    // On the top card the point sits 0.8 of a texel past the centre at x = 0.85 and 0.2 past z = 0.45.
    const struct {
        vec3 probe;
        float weight;
    } expected[] = {
        {{0.85f, 1.0f, 0.45f}, 0.64f * 0.2f * 0.8f},
        {{0.95f, 1.0f, 0.45f}, 0.64f * 0.8f * 0.8f},
        {{0.85f, 1.0f, 0.55f}, 0.64f * 0.2f * 0.2f},
        {{0.95f, 1.0f, 0.55f}, 0.64f * 0.8f * 0.2f},
        // On the +X card, y = 1 is half a texel past the last centre (y = 0.95): both of its rows
        // clamp to that texel, whose weights add up.
        {{1.0f, 0.95f, 0.45f}, 0.36f * 0.8f},
        {{1.0f, 0.95f, 0.55f}, 0.36f * 0.2f},
    };
    float sum = 0.0f;
    for (const auto& e : expected) {
        const int64_t id = probeAt(*store, e.probe);
        ASSERT_GE(id, 0) << e.probe.x << "," << e.probe.y << "," << e.probe.z;
        EXPECT_NEAR(weightOf(served, id), e.weight, 1e-5f) << e.probe.x << "," << e.probe.y << "," << e.probe.z;
        sum += e.weight;
    }
    EXPECT_NEAR(sum, 1.0f, 1e-6f);
    float servedSum = 0.0f;
    for (int i = 0; i < served.count; ++i) servedSum += served.probes[i].weight;
    EXPECT_NEAR(servedSum, 1.0f, 1e-5f) << "no probe beyond the six above carries weight";
}

TEST(CardsStore, LookupDropsTexelsWithNoProbeAndProbesFacingAwayAndCoversOnlyACapturedTexel) {
    auto store = preparedStore({{"texel_size", 0.1}}, sceneOf({boxMesh(vec3(0), vec3(1))}));
    // Two probes of the top card at the texel centres x = 0.45 and x = 0.55 (z = 0.45); the second
    // leans towards +X.
    const vec3 leaning = glm::normalize(vec3(0.6f, 0.8f, 0.0f));
    ASSERT_EQ(store->insert(queryAt({0.45f, 1.0f, 0.45f}, kUp), 0).status, ProbeInsert::Status::Inserted);
    ASSERT_EQ(store->insert(queryAt({0.55f, 1.0f, 0.45f}, leaning), 0).status, ProbeInsert::Status::Inserted);

    // 0.7 of a texel past x = 0.45 and 0.2 past z = 0.45: the texels at z = 0.55 hold no probe.
    ProbeLookup served;
    store->lookup(queryAt({0.52f, 1.0f, 0.47f}, kUp), 2, served);
    ASSERT_EQ(served.count, 2);
    EXPECT_NEAR(weightOf(served, 0), 0.3f, 1e-5f);
    EXPECT_NEAR(weightOf(served, 1), 0.7f, 1e-5f);
    EXPECT_TRUE(served.covered) << "its own texel, x in [0.5, 0.6), holds a probe";

    // A normal leaning towards −X faces away from the second probe (dot −0.19): it drops out. The
    // point's dominant direction is −X, whose card holds no probe: not covered.
    store->lookup(queryAt({0.52f, 1.0f, 0.47f}, glm::normalize(vec3(-0.9f, 0.436f, 0.0f))), 2, served);
    ASSERT_EQ(served.count, 1);
    EXPECT_EQ(served.probes[0].id, 0u);
    EXPECT_FLOAT_EQ(served.probes[0].weight, 1.0f);
    EXPECT_FALSE(served.covered);

    store->lookup(queryAt({0.48f, 1.0f, 0.37f}, kUp), 2, served);
    EXPECT_EQ(served.count, 2);
    EXPECT_FALSE(served.covered) << "its own texel, z in [0.3, 0.4), holds none";
}

// lookup() decides coverage and insert() decides "occupied" each on its own; the two must agree
// for every normal, including one so short that its largest component squares to 0, which reads
// no card at all (a version that took the coverage from the cards it filtered missed it).
TEST(CardsStore, LookupCoversExactlyWhereInsertFindsTheTexelOccupied) {
    auto store = preparedStore({{"texel_size", 0.1}}, sceneOf({boxMesh(vec3(0), vec3(1))}));
    Rng rng(7, 0);
    const auto onTopOrSide = [&](int i) {
        const float a = rng.uniform(), b = rng.uniform();
        return i % 2 == 0 ? vec3(a, 1.0f, b) : vec3(1.0f, a, b);
    };
    int covered = 0, occupiedRefusals = 0;
    for (int i = 0; i < 600; ++i) {
        const vec3 position = onTopOrSide(i);
        const vec3 facing = i % 2 == 0 ? kUp : kEast;
        // Tilted up to about 50° off the face, and every seventh one scaled to 1e-25 (its squared
        // components underflow; the dominant direction is still the face's).
        vec3 normal = glm::normalize(facing + 1.7f * vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f) * (vec3(1.0f) - facing));
        if (i % 7 == 0) normal *= 1e-25f;
        const ProbeQuery query = queryAt(position, normal);
        ProbeLookup served;
        store->lookup(query, 2, served);
        const uint64_t occupiedBefore = store->stats()["texel_occupied"];
        const ProbeInsert inserted = store->insert(query, 0);
        const bool occupied = store->stats()["texel_occupied"].get<uint64_t>() == occupiedBefore + 1;
        EXPECT_EQ(served.covered, occupied) << "query " << i;
        if (served.covered) {
            EXPECT_EQ(inserted.status, ProbeInsert::Status::Refused) << "query " << i;
        }
        covered += served.covered;
        occupiedRefusals += occupied;
    }
    EXPECT_GT(covered, 100) << "the texels fill up as the queries go: most later ones are covered";
    EXPECT_EQ(covered, occupiedRefusals);
}

}  // namespace
}  // namespace gibench
