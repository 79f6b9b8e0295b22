// `gibench compare` as a regression check: its exit codes with --fail-above, and what it prints.

#include "support/gibench_cli.h"
#include "support/temp_folder.h"

#include "core/config/params.h"
#include "core/image/image.h"

#include <gtest/gtest.h>

namespace gibench {
namespace {

test::SeparateOutcome gibench(const TempFolder& dir, const std::string& arguments) {
    return test::gibenchSeparately(arguments, dir / "stderr.txt");
}

// A pair of 16×16 EXRs whose relMSE is exactly 0.25 / 1.01: test 0.5 everywhere, reference 1.
std::string writePair(const TempFolder& dir) {
    for (const auto& [name, value] : {std::pair{"test.exr", 0.5f}, std::pair{"reference.exr", 1.0f}}) {
        LayeredImage image(16, 16);
        for (float& v : image.add("total", {"R", "G", "B"}).data) v = value;
        writeExr(dir / name, image);
    }
    return (dir / "test.exr").string() + " " + (dir / "reference.exr").string();
}

TEST(CompareCli, WithinEveryLimitExitsZero) {
    TempFolder dir;
    const auto o = gibench(dir, "compare " + writePair(dir) + " --fail-above relmse=0.25 --fail-above flip_hdr=1");
    EXPECT_EQ(o.exitCode, 0) << o.err;
    EXPECT_EQ(o.err, "");
    const Json r = Json::parse(o.out);
    EXPECT_NEAR(r["metrics"]["relmse"].get<double>(), 0.25 / 1.01, 1e-12);
    EXPECT_EQ(r["flip"]["kind"], "hdr");
}

TEST(CompareCli, AMetricAboveItsLimitExitsOneAfterPrintingTheJson) {
    TempFolder dir;
    const auto o = gibench(dir, "compare " + writePair(dir) + " --fail-above relmse=0.2 --fail-above mse=1");
    EXPECT_EQ(o.exitCode, 1);
    EXPECT_NEAR(Json::parse(o.out)["metrics"]["relmse"].get<double>(), 0.25 / 1.01, 1e-12);
    EXPECT_EQ(o.err, "fail: relmse = 0.247525 is above --fail-above relmse=0.2 by 0.0475248\n");
}

TEST(CompareCli, ABadLimitExitsTwoListingTheMetrics) {
    TempFolder dir;
    const std::string pair = writePair(dir);
    for (const std::string bad : {"relmse=-0.1", "relmse=abc", "rel_mse=0.1"}) {
        const auto o = gibench(dir, "compare " + pair + " --fail-above " + bad);
        EXPECT_EQ(o.exitCode, 2) << bad;
        EXPECT_EQ(o.out, "") << bad;
        EXPECT_EQ(o.err.rfind("error: --fail-above: expected METRIC=VALUE, VALUE a finite number >= 0 and METRIC one of ", 0), 0u) << o.err;
        EXPECT_NE(o.err.find("relmse, "), std::string::npos) << o.err;
        EXPECT_NE(o.err.find("flip_ldr, flip_hdr, got \"" + bad + "\""), std::string::npos) << o.err;
    }
    // FLIP of radiance files is flip_hdr: asking for flip_ldr is an error, not a pass.
    const auto o = gibench(dir, "compare " + pair + " --fail-above flip_ldr=0.5");
    EXPECT_EQ(o.exitCode, 2);
    EXPECT_EQ(o.err, "error: --fail-above flip_ldr: this comparison has no such metric (FLIP is flip_ldr when both files are sRGB, "
                     "flip_hdr otherwise)\n");
}

}  // namespace
}  // namespace gibench
