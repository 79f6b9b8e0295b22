// Budgets and checkpoints (issue 10 item 2): a run stops at a frame count or a render-time
// budget, and records its error at fixed frames and times.

#include "experiments/checkpoints.h"

#include "core/util/error.h"

#include <gtest/gtest.h>

namespace gibench {
namespace {

Params runBlock(const Json& json) { return Params(json, "run.json", "", "run config", nullptr); }

std::string errorOf(const Json& checkpoints, int frames) {
    try {
        Params root = runBlock({{"checkpoints", checkpoints}});
        readCheckpoints(root, frames);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(Checkpoints, EachFallsOnTheFrameItNamesOrTheLastFrameFinishedByItsTime) {
    std::vector<FrameSample> samples;
    for (int f = 0; f < 5; ++f) samples.push_back({f, 0.1 * (f + 1), Json{{"total", f}}});  // frames end at 0.1, 0.2, ... 0.5 s
    Checkpoints c;
    c.frames = {1, 3, 8};
    c.seconds = {0.05, 0.25, 0.5, 0.6};
    const Json r = checkpointRecords(c, samples);
    EXPECT_EQ(r["frames"][0]["frame"], 0) << "after 1 frame: frame 0";
    EXPECT_EQ(r["frames"][1]["frame"], 2);
    EXPECT_EQ(r["frames"][1]["error"], Json({{"total", 2}}));
    EXPECT_EQ(r["frames"][1]["at"], 3);
    EXPECT_TRUE(r["frames"][2]["frame"].is_null()) << "8 frames were never rendered";
    EXPECT_FALSE(r["frames"][2].contains("error"));
    EXPECT_TRUE(r["seconds"][0]["frame"].is_null()) << "no frame had finished by 0.05 s";
    EXPECT_EQ(r["seconds"][1]["frame"], 1) << "at 0.25 s the last finished frame is the one ending at 0.2 s";
    EXPECT_DOUBLE_EQ(r["seconds"][1]["cumulative_seconds"].get<double>(), 0.2);
    EXPECT_EQ(r["seconds"][2]["frame"], 4) << "a frame ending exactly at the checkpoint counts";
    EXPECT_TRUE(r["seconds"][3]["frame"].is_null()) << "the run's frames ended at 0.5 s: what 0.6 s would show was not rendered";
}

TEST(Checkpoints, DefaultsArePowersOfTwoUpToTheFramesAndTheEqualTimeBudgets) {
    Params none = runBlock(Json::object());
    EXPECT_EQ(readCheckpoints(none, 10).frames, (std::vector<int>{1, 2, 4, 8, 10}));
    Params again = runBlock(Json::object());
    EXPECT_EQ(readCheckpoints(again, 8).frames, (std::vector<int>{1, 2, 4, 8}));
    Params one = runBlock(Json::object());
    const Checkpoints c = readCheckpoints(one, 1);
    EXPECT_EQ(c.frames, (std::vector<int>{1}));
    EXPECT_EQ(c.seconds, std::vector<double>(std::begin(kDefaultSecondCheckpoints), std::end(kDefaultSecondCheckpoints)));
    EXPECT_EQ(c.resolved["frames"], Json({1}));
}

TEST(Checkpoints, ListsThatAreNotAscendingInRangeNumbersAreErrorsNamingTheKey) {
    EXPECT_NE(errorOf({{"frames", {4, 2}}}, 8).find("run.json: /checkpoints/frames: expected ascending values, got 2 after 4 at index 1"),
              std::string::npos)
        << errorOf({{"frames", {4, 2}}}, 8);
    EXPECT_NE(errorOf({{"frames", {2, 2}}}, 8).find("expected ascending values"), std::string::npos);
    EXPECT_NE(errorOf({{"frames", {9}}}, 8).find("expected integers in [1, 8] (the run's frames), got 9"), std::string::npos);
    EXPECT_NE(errorOf({{"frames", {1.5}}}, 8).find("expected integers in [1, 8]"), std::string::npos);
    EXPECT_NE(errorOf({{"frames", 4}}, 8).find("/checkpoints/frames: expected an ascending array"), std::string::npos);
    EXPECT_NE(errorOf({{"seconds", {0.0}}}, 8).find("/checkpoints/seconds: expected numbers in [1e-9, 1e9], got 0.0"), std::string::npos)
        << errorOf({{"seconds", {0.0}}}, 8);
    EXPECT_NE(errorOf({{"seconds", {"1"}}}, 8).find("/checkpoints/seconds"), std::string::npos);
    EXPECT_NE(errorOf({{"second", {1}}}, 8).find("/checkpoints/second: unknown key"), std::string::npos) << errorOf({{"second", {1}}}, 8);
    EXPECT_EQ(errorOf({{"frames", Json::array()}, {"seconds", Json::array()}}, 8), "") << "no checkpoints at all is allowed";
}

TEST(Budget, SecondsArePositiveAndTheOnlyKey) {
    Params none = runBlock(Json::object());
    EXPECT_FALSE(readBudgetSeconds(none));
    Params two = runBlock({{"budget", {{"seconds", 2.0}}}});
    EXPECT_EQ(readBudgetSeconds(two), 2.0);
    for (const Json& bad : {Json{{"seconds", 0}}, Json{{"seconds", -1}}, Json{{"frames", 3}}, Json(2.0), Json::object()}) {
        Params root = runBlock({{"budget", bad}});
        try {
            readBudgetSeconds(root);
            ADD_FAILURE() << bad.dump();
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("run.json: /budget"), std::string::npos) << e.what();
        }
    }
}

}  // namespace
}  // namespace gibench
