// `gibench report` (experiments/report_command.h): a missing folder is an input error before any
// process starts, and the analysis' exit code comes back as the command's.

#include "support/temp_folder.h"

#include "core/util/error.h"
#include "experiments/report_command.h"

#include <gtest/gtest.h>

#include <string>

namespace gibench {
namespace {

TEST(ReportCommand, AMissingFolderIsAnInputErrorNamingIt) {
    const TempFolder dir;
    try {
        runReport(dir / "nowhere", std::nullopt);
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), (dir / "nowhere").string() + ": not a folder (expected a results root, an experiment folder or a run)");
    }
}

TEST(ReportCommand, ReturnsTheAnalysisExitCodeAndWritesNothingForAFolderWithoutRuns) {
    const TempFolder dir;
    EXPECT_EQ(runReport(dir.path(), dir / "report"), 2) << "report.py's code for bad input";
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

}  // namespace
}  // namespace gibench
