// analysis/error_vs_time.py over an experiment folder: which folders count as runs.

#include "support/temp_folder.h"

#include "core/config/params.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

namespace gibench {
namespace {

// A finished run's files as the analysis reads them: one measured frame.
void writeRun(const TempFolder& dir, const std::string& folder, const std::string& method, double relmse) {
    dir.write(folder + "/manifest.json", Json{{"config", {{"method", {{"name", method}}}}}}.dump());
    const Json frame = {{"frame", 0},
                        {"seconds", 0.5},
                        {"cumulative_seconds", 0.5},
                        {"stages", {{"path_trace", 0.5}}},
                        {"stats", Json::object()},
                        {"error", {{"total", {{"relmse", relmse}}}, {"indirect", nullptr}}}};
    dir.write(folder + "/frames.jsonl", frame.dump() + "\n");
}

TEST(ErrorVsTime, HiddenStagingAndOldFoldersAreNotRuns) {
    TempFolder dir;
    writeRun(dir, "experiment/run", "path_traced", 0.25);
    // What a run being written, or a killed one, leaves: complete-looking, but not results.
    writeRun(dir, "experiment/.staging-run-123-0", "path_traced", 0.5);
    writeRun(dir, "experiment/.old-run-123-0", "path_traced", 0.75);
    const std::string command = "/usr/bin/python3 " + std::string(GIBENCH_SOURCE_DIR) + "/analysis/error_vs_time.py " +
                                (dir / "experiment").string() + " > " + (dir / "log.txt").string() + " 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    std::ifstream summary(dir / "experiment" / "summary.csv");
    std::string header, row, extra;
    std::getline(summary, header);
    std::getline(summary, row);
    EXPECT_FALSE(std::getline(summary, extra)) << "a second run: " << extra;
    EXPECT_EQ(row.rfind("run,path_traced,1,0.5,0.25,", 0), 0u) << row;
}

}  // namespace
}  // namespace gibench
