#include "methods/probe_cache/stores/cards/cards_store.h"

#include "support/store_test_helpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

namespace gibench {
namespace {

using test::addQuad;
using test::boxMesh;
using test::errorOf;
using test::queryAt;
using test::sceneOf;

std::unique_ptr<ProbeStore> makeStore(const Json& block) { return test::makeStore(block, "cards", cardsStoreParams(), &createCardsStore); }

std::unique_ptr<ProbeStore> preparedStore(const Json& block, const Scene& scene) {
    auto store = makeStore(block);
    RunNotes notes;
    store->prepare(scene, notes);
    return store;
}

const vec3 kUp(0, 1, 0), kEast(1, 0, 0), kWest(-1, 0, 0);

TEST(CardsStore, InsertedProbeIsFoundByNearestWhereTheQueryPlacedIt) {
    auto store = preparedStore({{"texel_size", 0.1}}, sceneOf({boxMesh(vec3(0), vec3(1))}));
    const Json layout = store->stats();
    EXPECT_EQ(layout["cards"], 6);
    EXPECT_EQ(layout["atlas_texels"], 6 * 10 * 10);

    const ProbeInsert result = store->insert(queryAt({0.52f, 1.0f, 0.47f}, kUp), 0);
    ASSERT_EQ(result.status, ProbeInsert::Status::Inserted);
    EXPECT_EQ(result.id, 0u);
    EXPECT_EQ(store->idCapacity(), 1u);
    EXPECT_EQ(store->probe(0).position, vec3(0.52f, 1.0f, 0.47f));
    EXPECT_EQ(store->probe(0).normal, kUp);

    ProbeNeighbour found[9];
    ASSERT_EQ(store->nearest(queryAt({0.55f, 1.0f, 0.43f}, kUp), 9, found), 1);
    EXPECT_EQ(found[0].id, 0u);
    EXPECT_NEAR(found[0].distance, 0.05f, 1e-6f);
    EXPECT_EQ(store->insert(queryAt({0.2f, 1.0f, 0.2f}, kUp), 0).id, 1u) << "ids are dense from 0";
    EXPECT_EQ(store->stats()["probes"], 2);
}

TEST(CardsStore, NearestIsEveryProbeOfTheCardWithinSearchRadiusNearestFirstAtMostCount) {
    auto store = preparedStore({{"texel_size", 0.1}}, sceneOf({boxMesh(vec3(0), vec3(1))}));
    // One probe in every texel of the top card, each somewhere else inside its texel.
    for (int i = 0; i < 10; ++i)
        for (int k = 0; k < 10; ++k) {
            const vec3 p(0.1f * i + 0.01f + 0.08f * float((i * 7 + k * 3) % 10) / 9.0f, 1.0f,
                         0.1f * k + 0.01f + 0.08f * float((i * 3 + k * 5) % 10) / 9.0f);
            ASSERT_EQ(store->insert(queryAt(p, kUp), 0).status, ProbeInsert::Status::Inserted) << i << "," << k;
        }
    const float radius = store->searchRadius();
    EXPECT_FLOAT_EQ(radius, 2 * 0.1f);  // kSearchRings texel edges
    EXPECT_FLOAT_EQ(store->coverageRadius(), 0.1f);
    for (int qi = 0; qi < 17; ++qi)
        for (int qk = 0; qk < 17; ++qk) {
            const ProbeQuery query = queryAt({0.003f + 0.0617f * qi, 1.0f, 0.011f + 0.0589f * qk}, kUp);
            // Brute force over every probe: the 3×3 texels must miss none within the radius.
            std::vector<ProbeNeighbour> expected;
            for (uint32_t id = 0; id < store->idCapacity(); ++id) {
                const float d = glm::length(store->probe(id).position - query.position);
                if (d <= radius) expected.push_back({id, d});
            }
            std::sort(expected.begin(), expected.end(), [](const ProbeNeighbour& a, const ProbeNeighbour& b) {
                return a.distance < b.distance || (a.distance == b.distance && a.id < b.id);
            });
            for (const int count : {1, 2, 9, 16}) {
                std::vector<ProbeNeighbour> found(static_cast<std::size_t>(count));
                const int n = store->nearest(query, count, found.data());
                ASSERT_EQ(n, std::min<int>(count, int(expected.size()))) << "query " << qi << "," << qk << " count " << count;
                std::set<uint32_t> ids;
                for (int i = 0; i < n; ++i) {
                    EXPECT_EQ(found[i].id, expected[i].id) << "query " << qi << "," << qk << " rank " << i;
                    EXPECT_FLOAT_EQ(found[i].distance, expected[i].distance);
                    EXPECT_LE(found[i].distance, radius);
                    ids.insert(found[i].id);
                }
                EXPECT_EQ(int(ids.size()), n) << "distinct ids";
            }
        }
}

TEST(CardsStore, OppositeFacesOfAThinWallLandOnDifferentCards) {
    // A wall 0.02 thick, a fifth of a texel: its two faces project to the same texels of ±X cards.
    auto store = preparedStore({{"texel_size", 0.1}}, sceneOf({boxMesh(vec3(0), vec3(1)), boxMesh({0.49f, 0, 0}, {0.51f, 1, 1})}));
    std::vector<uint32_t> eastIds, westIds;
    for (int i = 0; i < 5; ++i) {
        const float y = 0.15f + 0.2f * i, z = 0.85f - 0.2f * i;
        const ProbeInsert e = store->insert(queryAt({0.51f, y, z}, kEast, 1), 0);
        ASSERT_EQ(e.status, ProbeInsert::Status::Inserted);
        eastIds.push_back(e.id);
        ProbeNeighbour found[9];
        EXPECT_EQ(store->nearest(queryAt({0.49f, y, z}, kWest, 1), 9, found), 0) << "the west side sees no east probe, y " << y;
        const ProbeInsert w = store->insert(queryAt({0.49f, y, z}, kWest, 1), 0);
        ASSERT_EQ(w.status, ProbeInsert::Status::Inserted) << "a west probe has its own texel";
        westIds.push_back(w.id);
    }
    for (int i = 0; i < 5; ++i) {
        const float y = 0.15f + 0.2f * i, z = 0.85f - 0.2f * i;
        ProbeNeighbour found[9];
        ASSERT_EQ(store->nearest(queryAt({0.51f, y, z}, kEast, 1), 9, found), 1);
        EXPECT_EQ(found[0].id, eastIds[i]);
        ASSERT_EQ(store->nearest(queryAt({0.49f, y, z}, kWest, 1), 9, found), 1);
        EXPECT_EQ(found[0].id, westIds[i]);
    }
    EXPECT_EQ(store->stats()["depth_conflicts"], 0);
    EXPECT_EQ(store->stats()["refused"], 0);
}

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

TEST(CardsStore, InvalidQueriesFindNoProbeAndAreCounted) {
    auto store = preparedStore({{"texel_size", 0.1}}, sceneOf({boxMesh(vec3(0), vec3(1))}));
    const float nan = std::nanf(""), inf = kInfinity;
    const ProbeQuery invalid[] = {queryAt({0.5f, 1.0f, 0.5f}, kUp, -1), queryAt({0.5f, 1.0f, 0.5f}, kUp, 1),
                                  queryAt({nan, 1.0f, 0.5f}, kUp), queryAt({0.5f, inf, 0.5f}, kUp), queryAt({0.5f, 1.0f, 0.5f}, {0, nan, 0})};
    for (const ProbeQuery& q : invalid) {
        ProbeNeighbour found;
        EXPECT_EQ(store->nearest(q, 1, &found), 0);
        EXPECT_EQ(store->insert(q, 0).status, ProbeInsert::Status::Refused);
    }
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

TEST(CardsStore, RelativeTexelSizeResolvesAgainstTheLargestSideOfTheScene) {
    const auto cornell = preparedStore(Json::object(), sceneOf({boxMesh(vec3(0), {0.55f, 0.55f, 0.3f})}));
    EXPECT_NEAR(cornell->coverageRadius(), 0.55f / 75.0f, 1e-7f);
    EXPECT_NEAR(cornell->coverageRadius(), 0.55f / 75.0f, 1e-7f);
    EXPECT_NEAR(cornell->stats()["texel_size"].get<double>(), 0.55 / 75.0, 1e-7);

    const auto sponza = preparedStore(Json::object(), sceneOf({boxMesh({-15, 0, -9}, {15, 12, 9})}));
    EXPECT_NEAR(sponza->coverageRadius(), 0.4f, 1e-6f);

    const auto absolute = preparedStore({{"texel_size", 0.25}, {"texel_size_relative", 0.5}}, sceneOf({boxMesh({-15, 0, -9}, {15, 12, 9})}));
    EXPECT_FLOAT_EQ(absolute->coverageRadius(), 0.25f) << "texel_size, when set, wins";
}

TEST(CardsStore, AnAtlasTooLargeIsAnInputErrorNamingTheKey) {
    const Scene unitBox = sceneOf({boxMesh(vec3(0), vec3(1))});
    EXPECT_EQ(errorOf([&] { preparedStore({{"texel_size", 0.125}, {"max_atlas_texels", 300}}, unitBox); }),
              "cfg.json: /method/max_atlas_texels: the scene's 6 cards need 384 texels of 0.125 units, more than max_atlas_texels = "
              "300; raise max_atlas_texels or the texel size");
    EXPECT_EQ(errorOf([&] { preparedStore({{"texel_size", 0.125}, {"max_atlas_texels", 384}}, unitBox); }), "");
    // A count no integer type holds is reported, not overflowed.
    const std::string huge = errorOf([&] { preparedStore({{"texel_size", 1e-12}}, unitBox); });
    EXPECT_EQ(huge.rfind("cfg.json: /method/max_atlas_texels: the scene's 6 cards need ", 0), 0u) << huge;

    Mesh point;
    point.positions = {vec3(1, 2, 3), vec3(1, 2, 3), vec3(1, 2, 3)};
    point.indices = {{0, 1, 2}};
    EXPECT_EQ(errorOf([&] { preparedStore(Json::object(), sceneOf({point})); }),
              "cfg.json: /method/texel_size_relative: the scene's bounding box has no extent to take a fraction of; give texel_size "
              "in scene units");
}

TEST(CardsStore, ParameterErrorsNameTheKeyAndTheExpectation) {
    EXPECT_EQ(errorOf([] { makeStore({{"texel_sise", 0.1}}); }),
              "cfg.json: /method/texel_sise: unknown key for method \"cards\" (known: texel_size, texel_size_relative, "
              "depth_tolerance, texel_update_budget, texel_capture_budget, max_atlas_texels)");
    EXPECT_EQ(errorOf([] { makeStore({{"texel_size", -0.5}}); }), "cfg.json: /method/texel_size: expected a number >= 0, got -0.5");
    EXPECT_EQ(errorOf([] { makeStore({{"depth_tolerance", -1}}); }),
              "cfg.json: /method/depth_tolerance: expected a number >= 0, got -1");
    EXPECT_EQ(errorOf([] { makeStore({{"texel_update_budget", 0}}); }),
              "cfg.json: /method/texel_update_budget: expected an integer in [1, 1073741824], got 0");
    EXPECT_EQ(errorOf([] { makeStore({{"texel_capture_budget", 2.5}}); }),
              "cfg.json: /method/texel_capture_budget: expected an integer in [1, 1073741824], got 2.5");
    EXPECT_EQ(errorOf([] { makeStore({{"max_atlas_texels", 1ll << 32}}); }),
              "cfg.json: /method/max_atlas_texels: expected an integer in [1, 4294967295], got 4294967296");

    // The resolved parameters read back to the same store.
    Params params(Json{{"texel_size", 0.2}}, "cfg.json", "/method", "method \"cards\"", &cardsStoreParams());
    createCardsStore(params);
    const Json resolved = params.resolved();
    EXPECT_EQ(resolved["texel_update_budget"], 4096);
    EXPECT_EQ(resolved["depth_tolerance"], 2.0);
    EXPECT_FLOAT_EQ(preparedStore(resolved, sceneOf({boxMesh(vec3(0), vec3(1))}))->coverageRadius(), 0.2f);
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
