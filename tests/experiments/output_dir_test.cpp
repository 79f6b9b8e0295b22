// Results whole or not at all: what failed and killed runs leave behind, and how the next run in
// the same folder cleans it.

#include "experiments/output_dir.h"

#include "support/temp_folder.h"

#include <gtest/gtest.h>

#include <iterator>
#include <set>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>

namespace gibench {
namespace {

// A PID no process has: that of a child that has exited and been reaped.
pid_t deadPid() {
    const pid_t child = fork();
    if (child == 0) _exit(0);
    waitpid(child, nullptr, 0);
    return child;
}

std::set<std::string> entries(const std::filesystem::path& folder) {
    std::set<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(folder)) names.insert(e.path().filename().string());
    return names;
}

std::string readText(const std::filesystem::path& file) {
    std::ifstream in(file);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(OutputDir, AFailedRunLeavesNoFolderItCreated) {
    TempFolder dir;
    {
        StagingDir staging(dir / "results" / "experiment" / "run");
        EXPECT_TRUE(std::filesystem::is_directory(staging.path()));
    }
    EXPECT_EQ(entries(dir.path()), std::set<std::string>{});
}

TEST(OutputDir, AFailedRunKeepsFoldersThatExistedOrHoldOtherResults) {
    TempFolder dir;
    dir.write("results/experiment/other/manifest.json", "{}");
    { StagingDir staging(dir / "results" / "experiment" / "run"); }
    EXPECT_EQ(entries(dir / "results" / "experiment"), std::set<std::string>{"other"});
}

TEST(OutputDir, AbandonedStagingFoldersAreRemovedAndThoseOfLiveProcessesKept) {
    TempFolder dir;
    const std::string dead = std::to_string(deadPid()), alive = std::to_string(getpid());
    dir.write("experiment/.staging-run-" + dead + "-0/frames.jsonl", "{}\n");
    dir.write("experiment/.staging-a-b-c-" + dead + "-12/frames.jsonl", "{}\n");  // names may hold dashes
    dir.write("experiment/.staging-run-" + alive + "-3/frames.jsonl", "{}\n");
    dir.write("experiment/.tmp-x.exr-" + dead + "-1", "half");
    dir.write("experiment/.staging-notours/kept", "");  // no PID: not gibench's, left alone
    StagingDir staging(dir / "experiment" / "next");
    EXPECT_EQ(entries(dir / "experiment"), (std::set<std::string>{".staging-run-" + alive + "-3", ".staging-notours",
                                                                  staging.path().filename().string()}));
}

TEST(OutputDir, AKillBetweenTheRenamesOfAReplacedRunRestoresTheEarlierResult) {
    // commit() moved run/ to .old-run-P-0 and died before renaming .staging-run-P-0 to run/: both
    // hold a complete result. The commit did not happen, so it is rolled back.
    TempFolder dir;
    const std::string tag = std::to_string(deadPid()) + "-0";
    dir.write("experiment/.old-run-" + tag + "/manifest.json", "earlier");
    dir.write("experiment/.staging-run-" + tag + "/manifest.json", "unfinished replacement");
    cleanAbandoned(dir / "experiment");
    EXPECT_EQ(entries(dir / "experiment"), std::set<std::string>{"run"});
    EXPECT_EQ(readText(dir / "experiment" / "run" / "manifest.json"), "earlier");
}

TEST(OutputDir, AKillAfterTheSecondRenameKeepsTheNewResult) {
    TempFolder dir;
    const std::string tag = std::to_string(deadPid()) + "-0";
    dir.write("experiment/.old-run-" + tag + "/manifest.json", "earlier");
    dir.write("experiment/run/manifest.json", "new");
    cleanAbandoned(dir / "experiment");
    EXPECT_EQ(entries(dir / "experiment"), std::set<std::string>{"run"});
    EXPECT_EQ(readText(dir / "experiment" / "run" / "manifest.json"), "new");
}

TEST(OutputDir, CommitReplacesAnEarlierResultAndLeavesNothingElse) {
    TempFolder dir;
    dir.write("experiment/run/manifest.json", "earlier");
    StagingDir staging(dir / "experiment" / "run");
    dir.write("experiment/" + staging.path().filename().string() + "/manifest.json", "new");
    staging.commit();
    EXPECT_EQ(entries(dir / "experiment"), std::set<std::string>{"run"});
    EXPECT_EQ(readText(dir / "experiment" / "run" / "manifest.json"), "new");
}

TEST(OutputDir, ATemporaryFileIsRemovedUnlessCommitted) {
    TempFolder dir;
    {
        TemporaryFile file(dir / "image.exr");
        dir.write(file.path().filename().string(), "half");
    }
    EXPECT_EQ(entries(dir.path()), std::set<std::string>{});
    TemporaryFile file(dir / "image.exr");
    dir.write(file.path().filename().string(), "whole");
    file.commit();
    EXPECT_EQ(entries(dir.path()), std::set<std::string>{"image.exr"});
}

}  // namespace
}  // namespace gibench
