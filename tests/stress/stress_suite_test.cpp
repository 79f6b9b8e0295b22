// The stress suite of configs/stress/ (issue 8), every case by every method it names, and the
// runner's judgement on cases whose expectation is wrong.

#include "experiments/stress.h"

#include "support/temp_folder.h"

#include <gtest/gtest.h>

namespace gibench {
namespace {

TEST(StressSuite, EveryCaseByEveryMethodIsFiniteAndMeetsItsExpectation) {
    const std::vector<StressRow> rows = runStressSuite(defaultStressCases(), {}, false);
    EXPECT_GE(rows.size(), 80u);
    for (const StressRow& r : rows)
        EXPECT_TRUE(r.passed) << r.caseName << " by " << r.method << ": " << r.measure << " " << r.value << " against " << r.expected
                              << " (tolerance " << r.tolerance << ") " << r.note;
    std::cout << stressTable(rows);
}

const char* kFurnace = R"({"about": "a", "scene": {"materials": {"w": {"type": "diffuse", "albedo": 0, "emission": 2}},
    "shapes": [{"type": "box", "inward": true, "material": "w"}]},
    "camera": {"eye": [0, 0, 0], "target": [0, 0, -1], "resolution": [4, 4]}, "frames": 1, "methods": {"path_traced": {}},
    "expect": )";

TEST(StressSuite, AWrongExpectationFailsItsRow) {
    TempFolder folder;
    folder.write("wrong_mean.json", std::string(kFurnace) + R"({"mean": 1}})");
    folder.write("wrong_refusal.json", std::string(kFurnace) + R"({"refused": "anything"}})");
    folder.write("right_mean.json", std::string(kFurnace) + R"({"mean": 2}})");
    const std::vector<StressRow> rows = runStressSuite(folder.path(), {}, false);
    ASSERT_EQ(rows.size(), 3u);
    EXPECT_TRUE(rows[0].passed) << rows[0].caseName;
    EXPECT_EQ(rows[1].caseName, "wrong_mean");
    EXPECT_FALSE(rows[1].passed);
    EXPECT_EQ(rows[1].value, 2.0);
    EXPECT_EQ(rows[2].caseName, "wrong_refusal");
    EXPECT_FALSE(rows[2].passed);
}

}  // namespace
}  // namespace gibench
