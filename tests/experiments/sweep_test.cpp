// Sweep files (issue 10 item 1): a base config and axes, expanded into named runs with stable
// ids, every point checked before any runs.

#include "experiments/sweep.h"
#include "experiments/run_id.h"
#include "experiments/sweep_runner.h"

#include "support/temp_folder.h"

#include "core/util/error.h"

#include <gtest/gtest.h>

#include <fstream>

namespace gibench {
namespace {

void write(const std::filesystem::path& file, const std::string& text) { std::ofstream(file) << text; }

std::string baseConfig(const std::filesystem::path& results) {
    return R"({"experiment": "sweep", "scene": ")" + std::string(GIBENCH_SOURCE_DIR) + R"(/configs/scenes/cornell_box.json", "frames": 1,
               "camera": {"resolution": [8, 8]}, "method": {"name": "path_traced", "spp": 1}, "output": {"root": ")" +
           results.string() + R"("}})";
}

std::string errorOf(const std::filesystem::path& file) {
    try {
        loadSweep(file);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(Sweep, AGridCombinesItsAxesFirstSlowestAndZippedAxesVaryTogether) {
    TempFolder dir;
    write(dir / "base.json", baseConfig(dir / "results"));
    write(dir / "sweep.json", R"({"base": "base.json", "grid": {"method.spp": [1, 2], "seed": [0, 1, 2]},
                                  "zip": {"camera.resolution": [[8, 8], [4, 6]], "frames": [1, 2]}})");
    const Sweep sweep = loadSweep(dir / "sweep.json");
    ASSERT_EQ(sweep.points.size(), 12u) << "2 × 3 grid points, each with both zipped pairs";
    EXPECT_EQ(sweep.points[0].name, "spp-1_seed-0_resolution-8x8_frames-1");
    EXPECT_EQ(sweep.points[1].name, "spp-1_seed-0_resolution-4x6_frames-2") << "the zipped axes vary fastest, together";
    EXPECT_EQ(sweep.points[2].name, "spp-1_seed-1_resolution-8x8_frames-1");
    EXPECT_EQ(sweep.points[11].name, "spp-2_seed-2_resolution-4x6_frames-2");
    const RunConfig last = loadSweepPoint(sweep, sweep.points[11]);
    EXPECT_EQ(last.run, "spp-2_seed-2_resolution-4x6_frames-2");
    EXPECT_EQ(last.seed, 2u);
    EXPECT_EQ(last.frames, 2);
    EXPECT_EQ(last.camera.width, 4);
    EXPECT_EQ(last.methodResolved["spp"], 2);
}

TEST(Sweep, RunNamesReadLikeTheirAxes) {
    TempFolder dir;
    write(dir / "base.json", baseConfig(dir / "results"));
    write(dir / "sweep.json", R"({"base": "base.json", "grid": {"method.name": ["path_traced"], "method.spp": [1]}})");
    EXPECT_EQ(loadSweep(dir / "sweep.json").points[0].name, "method-path_traced_spp-1") << "not \"name-path_traced\"";
    write(dir / "sweep.json", R"({"base": "base.json", "grid": {"scene": ["../scenes/sponza.json"],
                                  "method": [{"name": "mamba"}, {"name": "mamba", "facing": false}]}})");
    const Sweep sweep = loadSweep(dir / "sweep.json");
    EXPECT_EQ(sweep.points[0].name, "method-mamba");
    write(dir / "sweep.json", R"({"base": "base.json", "grid": {"scene": ["../scenes/sponza.json", "a/cornell_box.json"]}})");
    EXPECT_EQ(loadSweep(dir / "sweep.json").points[1].name, "scene-cornell_box") << "a scene file by its stem";
    EXPECT_EQ(sweep.points[1].name, "method-mamba-facing-false") << "a method block by its name and other keys; an axis of one value left out";
}

TEST(Sweep, AnIdNamesTheComputationWhateverTheKeyOrderNameAndOutput) {
    TempFolder dir;
    write(dir / "base.json", baseConfig(dir / "results"));
    // The same run written with its keys in another order, another name, folder and thread count.
    write(dir / "other.json", R"({"method": {"spp": 1, "name": "path_traced"}, "camera": {"resolution": [8, 8]}, "frames": 1, "threads": 1,
                                  "output": {"root": ")" + (dir / "elsewhere").string() + R"("}, "run": "renamed", "experiment": "x",
                                  "scene": ")" + std::string(GIBENCH_SOURCE_DIR) + R"(/configs/scenes/cornell_box.json"})");
    const std::string a = runId(loadRunConfig(dir / "base.json")), b = runId(loadRunConfig(dir / "other.json"));
    EXPECT_EQ(a.size(), 16u);
    EXPECT_EQ(a, b);
    EXPECT_NE(runId(loadRunConfig(dir / "base.json", {std::nullopt, std::nullopt, {parseConfigOverride("seed=2")}})), a);
    EXPECT_NE(runId(loadRunConfig(dir / "base.json", {std::nullopt, std::nullopt, {parseConfigOverride("method.max_depth=3")}})), a)
        << "a default made explicit otherwise is part of the resolved config";
}

TEST(Sweep, MalformedSweepsAreErrorsNamingFileAndKey) {
    TempFolder dir;
    write(dir / "base.json", baseConfig(dir / "results"));
    const auto check = [&](const std::string& text, const std::string& expected) {
        write(dir / "s.json", text);
        const std::string error = errorOf(dir / "s.json");
        EXPECT_NE(error.find(expected), std::string::npos) << text << "\n" << error;
    };
    check(R"({"base": "base.json"})", "expected at least one axis");
    check(R"({"base": "base.json", "zip": {"seed": [1, 2], "frames": [1]}})", "/zip: expected axes of one length");
    check(R"({"base": "base.json", "grid": {"seed": []}})", "/grid: seed: expected a non-empty array");
    check(R"({"base": "base.json", "grid": {"seed": 3}})", "/grid: seed: expected a non-empty array");
    check(R"({"base": "base.json", "grid": {"method..spp": [1]}})", "not a key --set could name");
    check(R"({"base": "base.json", "grid": {"seed": [1, "1"]}})", "two runs would be named \"seed-1\"");
    check(R"({"grid": {"seed": [1]}})", "missing key \"base\"");
    check(R"({"base": "base.json", "grid": {"seed": [1]}, "axes": {}})", "/axes: unknown key");
    // A point whose config is wrong is named, with the axis that set the value.
    write(dir / "s.json", R"({"base": "base.json", "grid": {"method.spp": [1, "many"]}})");
    const Sweep sweep = loadSweep(dir / "s.json");
    try {
        loadSweepPoint(sweep, sweep.points[1]);
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("s.json: run \"spp-many\":"), std::string::npos) << what;
        EXPECT_NE(what.find("/method/spp was set by the sweep's axis \"method.spp\" to \"many\""), std::string::npos) << what;
    }
}

TEST(Sweep, ARunOfASweepIsSkippedOnceDoneAndADryRunWritesNothing) {
    TempFolder dir;
    write(dir / "base.json", baseConfig(dir / "results"));
    write(dir / "sweep.json", R"({"base": "base.json", "experiment": "swept", "grid": {"seed": [0, 1]}})");
    const Sweep sweep = loadSweep(dir / "sweep.json");
    EXPECT_EQ(runSweep(sweep, {{1, std::nullopt, {}}, 1, std::nullopt, true, false}), 0);
    EXPECT_FALSE(std::filesystem::exists(dir / "results" / "swept")) << "a dry run renders nothing";
    EXPECT_EQ(runSweep(sweep, {{1, std::nullopt, {}}, 1, std::nullopt, false, false}), 0);
    const auto manifest = dir / "results" / "swept" / "seed-1" / "manifest.json";
    ASSERT_TRUE(std::filesystem::exists(manifest));
    const auto written = std::filesystem::last_write_time(manifest);
    EXPECT_EQ(runSweep(sweep, {{1, std::nullopt, {}}, 1, std::nullopt, false, false}), 0);
    EXPECT_EQ(std::filesystem::last_write_time(manifest), written) << "a run already done with the same id is not rendered again";
    // Another value behind the same name is another run: rendered again.
    write(dir / "base.json", baseConfig(dir / "results").replace(baseConfig(dir / "results").find("\"spp\": 1"), 8, "\"spp\": 2"));
    EXPECT_EQ(runSweep(loadSweep(dir / "sweep.json"), {{1, std::nullopt, {}}, 1, std::nullopt, false, false}), 0);
    EXPECT_NE(std::filesystem::last_write_time(manifest), written);
}

}  // namespace
}  // namespace gibench
