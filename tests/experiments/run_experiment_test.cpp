// experiments/run_experiment.sh as a new user meets it (issue 10): it does not stop at a config
// with an external reference, follows --results, analyses each experiment its configs name, and
// leaves out runs no config of the folder made.

#include "support/gibench_cli.h"
#include "support/temp_folder.h"

#include "core/config/params.h"
#include "core/image/image.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace gibench {
namespace {

std::string readText(const std::filesystem::path& file) {
    std::ifstream in(file);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

Json smallConfig(const std::string& experiment, const std::string& method) {
    return {{"experiment", experiment},
            {"scene", std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json"},
            {"camera", {{"resolution", {16, 16}}}},
            {"frames", 2},
            {"method", {{"name", method}}},
            {"reference", {{"spp", 8}}}};
}

TEST(RunExperiment, ExternalReferencesResultsFolderExperimentsAndRemovedConfigs) {
    TempFolder dir;
    const auto configs = dir / "configs";
    std::filesystem::create_directories(configs);
    const auto results = dir / "results";
    // A run of a config that is no longer in the folder.
    std::ofstream(dir / "removed.json") << smallConfig("one", "cards").dump();
    ASSERT_EQ(test::gibench("run --quiet --results " + results.string() + " " + (dir / "removed.json").string()).exitCode, 0);

    LayeredImage reference(16, 16);
    Image& total = reference.add("total", {"R", "G", "B"});
    for (float& v : total.data) v = 0.25f;
    writeExr(dir / "flat.exr", reference);
    Json external = smallConfig("two", "dense_grid");
    external["reference"] = {{"file", (dir / "flat.exr").string()}};
    std::ofstream(configs / "a_path_traced.json") << smallConfig("one", "path_traced").dump();
    std::ofstream(configs / "b_mamba.json") << smallConfig("one", "mamba").dump();
    std::ofstream(configs / "c_external.json") << external.dump();

    const std::string command = "cd " + std::string(GIBENCH_SOURCE_DIR) + " && GIBENCH=" + GIBENCH_EXE + " experiments/run_experiment.sh " +
                                configs.string() + " --results " + results.string() + " 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    std::string output;
    char buffer[512];
    while (std::fgets(buffer, sizeof buffer, pipe)) output += buffer;
    ASSERT_EQ(pclose(pipe), 0) << output;

    const std::string one = readText(results / "one" / "summary.csv");
    EXPECT_NE(one.find("a_path_traced"), std::string::npos) << one;
    EXPECT_NE(one.find("b_mamba"), std::string::npos) << one;
    EXPECT_EQ(one.find("removed"), std::string::npos) << "a run of a removed config is not in the analysis:\n" << one;
    EXPECT_EQ(readText(results / "one" / "paper" / "runs.csv").find("removed"), std::string::npos);
    EXPECT_TRUE(std::filesystem::exists(results / "one" / "removed")) << "it is left where it is";
    const std::string two = readText(results / "two" / "summary.csv");
    EXPECT_NE(two.find("c_external"), std::string::npos) << "the other experiment is analysed too:\n" << two;
    EXPECT_TRUE(std::filesystem::exists(results / "two" / "paper" / "runs.csv"));
    EXPECT_FALSE(std::filesystem::exists(std::string(GIBENCH_SOURCE_DIR) + "/results/one")) << "--results is followed";
}

}  // namespace
}  // namespace gibench
