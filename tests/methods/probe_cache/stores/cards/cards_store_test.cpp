#include "methods/probe_cache/stores/cards/cards_store.h"

#include "support/store_test_helpers.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gibench {
namespace {

using namespace test;  // the store-test helpers (support/store_test_helpers.h)

std::unique_ptr<ProbeStore> makeStore(const Json& block) { return test::makeStore(block, test::storeRow("cards")); }

std::unique_ptr<ProbeStore> preparedStore(const Json& block, const Scene& scene) { return test::prepared(makeStore(block), scene); }

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

}  // namespace
}  // namespace gibench
