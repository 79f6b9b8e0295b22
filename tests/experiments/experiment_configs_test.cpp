// Every config of configs/experiments loads: its keys, its scene and its camera path are checked
// as `gibench run` checks them, so an experiment folder cannot rot unnoticed (the thin-wall
// configs' camera jump passed through its target once pose interpolation was checked, and
// experiments/run_experiment.sh stopped at the first of them).

#include "experiments/run_config.h"
#include "experiments/sweep.h"

#include "core/util/error.h"
#include "support/render_helpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

namespace gibench {
namespace {

std::vector<std::filesystem::path> experimentConfigs() {
    std::vector<std::filesystem::path> configs;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(std::filesystem::path(GIBENCH_SOURCE_DIR) / "configs" / "experiments"))
        if (entry.is_regular_file() && entry.path().extension() == ".json") configs.push_back(entry.path());
    std::sort(configs.begin(), configs.end());
    return configs;
}

TEST(ExperimentConfigs, EveryConfigLoadsAsGibenchRunWouldLoadIt) {
    const std::vector<std::filesystem::path> configs = experimentConfigs();
    ASSERT_GE(configs.size(), 20u) << "the experiment folders were found";
    int loaded = 0, skipped = 0;
    for (const std::filesystem::path& config : configs) {
        std::ifstream in(config);
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        // Third-party scenes live outside the repository (experiments/fetch_scenes.sh).
        const bool thirdParty = text.find("sponza") != std::string::npos || text.find("living_room") != std::string::npos;
        if (thirdParty && !std::filesystem::exists(test::sharedScenes() / "sponza-dabrovic" / "sponza.obj")) {
            ++skipped;
            continue;
        }
        try {
            loadRunConfig(config);
            ++loaded;
        } catch (const InputError& e) {
            ADD_FAILURE() << config << ": " << e.what();
        }
    }
    EXPECT_GT(loaded, 0);
    if (skipped > 0) std::cout << "skipped " << skipped << " configs of third-party scenes: no ../shared/scenes\n";
}

// Every sweep of configs/sweeps expands and each of its runs loads (the check `gibench sweep
// --dry-run` makes).
TEST(ExperimentConfigs, EverySweepExpandsIntoRunsThatLoad) {
    int sweeps = 0;
    for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(GIBENCH_SOURCE_DIR) / "configs" / "sweeps")) {
        if (entry.path().extension() != ".json") continue;
        ++sweeps;
        try {
            const Sweep sweep = loadSweep(entry.path());
            EXPECT_GT(sweep.points.size(), 1u) << entry.path();
            for (const SweepPoint& point : sweep.points) loadSweepPoint(sweep, point);
        } catch (const InputError& e) {
            ADD_FAILURE() << entry.path() << ": " << e.what();
        }
    }
    EXPECT_GT(sweeps, 0);
}

}  // namespace
}  // namespace gibench
