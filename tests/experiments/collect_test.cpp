// `gibench collect`: its verdict on every run a submitted sweep expects, from fixture folders and
// from runs a real sweep wrote.

#include "experiments/collect.h"

#include "experiments/sweep_runner.h"

#include "support/temp_folder.h"

#include "core/config/params.h"
#include "core/util/error.h"

#include <gtest/gtest.h>

namespace gibench {
namespace {

const std::string kId = "0123456789abcdef";

// A run folder as a finished run leaves it, with the given manifest id.
void writeDoneRun(const TempFolder& dir, const std::string& name, const std::string& id) {
    dir.write(name + "/manifest.json", Json{{"run_id", id}, {"finished", "2026-12-03T05:00:00Z"}, {"config", Json::object()}}.dump());
    for (const char* file : {"metrics.json", "frames.jsonl", "image.exr"}) dir.write(name + "/" + file, "{}");
}

std::string errorOf(const std::filesystem::path& experimentDir) {
    try {
        collectRuns(experimentDir);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(Collect, EveryExpectedRunIsDoneFailedOrMissingWithWhy) {
    TempFolder dir;
    std::vector<ExpectedRun> expected;
    for (std::size_t i = 0; i < 8; ++i) expected.push_back({i, "run-" + std::to_string(i), kId});
    writeExpectedRuns(dir.path(), "/abs/sweep.json", expected);
    writeDoneRun(dir, "run-0", kId);
    // run-1: a failure the sweep recorded for this id, beside an older result of another config.
    writeDoneRun(dir, "run-1", "ffffffffffffffff");
    dir.write(".failed/run-1.json", Json{{"run", "run-1"}, {"run_id", kId}, {"error", "base.json: /frames: expected an integer"}}.dump());
    // run-2: killed by Slurm: only the latest job's log counts.
    dir.write(".sweep/slurm-9_2.out", "error: an older job's error\n");
    dir.write(".sweep/slurm-10_2.out", "rendering\nslurmstepd: error: *** JOB 10 ON localhost CANCELLED AT 05:00 DUE TO TIME LIMIT ***\n");
    // run-3: never ran (a log without an error is no failure). run-4: another config's finished run under the name.
    dir.write(".sweep/slurm-10_3.out", "[4/8] 0123456789abcdef run-3: done before, skipped\n");
    writeDoneRun(dir, "run-4", "ffffffffffffffff");
    // run-5: a manifest without "finished". run-6: a failure record of another id is stale.
    dir.write("run-5/manifest.json", Json{{"run_id", kId}}.dump());
    dir.write(".failed/run-6.json", Json{{"run_id", "ffffffffffffffff"}, {"error", "old"}}.dump());
    // run-7: done, but a file of a finished run is gone.
    writeDoneRun(dir, "run-7", kId);
    std::filesystem::remove(dir / "run-7/image.exr");

    const std::vector<CollectedRun> runs = collectRuns(dir.path());
    ASSERT_EQ(runs.size(), 8u);
    const std::vector<std::pair<RunStatus, std::string>> verdicts = {
        {RunStatus::Done, ""},
        {RunStatus::Failed, "base.json: /frames: expected an integer"},
        {RunStatus::Failed, "slurmstepd: error: *** JOB 10 ON localhost CANCELLED AT 05:00 DUE TO TIME LIMIT *** (.sweep/slurm-10_2.out)"},
        {RunStatus::Missing, "no folder run-3/ (its task's log .sweep/slurm-10_3.out names no error)"},
        {RunStatus::Missing, "holds run ffffffffffffffff (another config), not 0123456789abcdef"},
        {RunStatus::Missing, "manifest.json has no \"finished\": the run did not end"},
        {RunStatus::Missing, "no folder run-6/"},
        {RunStatus::Missing, "no image.exr beside the finished manifest"},
    };
    for (std::size_t i = 0; i < runs.size(); ++i) {
        EXPECT_EQ(runs[i].expected.name, "run-" + std::to_string(i));
        EXPECT_EQ(statusName(runs[i].status), statusName(verdicts[i].first)) << runs[i].expected.name << ": " << runs[i].detail;
        EXPECT_EQ(runs[i].detail, verdicts[i].second) << runs[i].expected.name;
    }
    const std::string table = collectTable(runs);
    EXPECT_NE(table.find("run    id                status   error\n"), std::string::npos) << table;
    EXPECT_NE(table.find("run-0  0123456789abcdef  done\n"), std::string::npos) << table;
    EXPECT_NE(table.find("run-6  0123456789abcdef  missing  no folder run-6/\n"), std::string::npos) << table;
    EXPECT_EQ(table.substr(table.rfind("8 runs")), "8 runs: 1 done, 2 failed, 5 missing\n");
    EXPECT_EQ(runCollect(dir.path(), std::nullopt), 1);
}

TEST(Collect, RunsASweepWroteAreDoneAndOneDeletedIsMissing) {
    TempFolder dir;
    dir.write("base.json", R"({"scene": ")" + std::string(GIBENCH_SOURCE_DIR) +
                               R"(/configs/scenes/cornell_box.json", "frames": 1, "camera": {"resolution": [8, 8]},
                               "method": {"name": "path_traced", "spp": 1}, "output": {"root": ")" + (dir / "results").string() + R"("}})");
    const Sweep sweep = loadSweep(dir.write("sweep.json", R"({"base": "base.json", "experiment": "swept", "grid": {"seed": [0, 1]}})"));
    SweepOptions options;
    options.showProgress = false;
    ASSERT_EQ(runSweep(sweep, options), 0);
    std::vector<ExpectedRun> expected;
    for (const PlannedRun& run : planSweep(sweep, {})) expected.push_back({run.index, run.name, run.id});
    writeExpectedRuns(dir / "results" / "swept", sweep.file, expected);
    EXPECT_EQ(runCollect(dir / "results", "swept"), 0) << "the results root with --experiment";
    EXPECT_EQ(runCollect(dir / "results" / "swept", std::nullopt), 0);
    std::filesystem::remove_all(dir / "results" / "swept" / "seed-1");
    EXPECT_EQ(runCollect(dir / "results" / "swept", std::nullopt), 1);
    EXPECT_EQ(statusName(collectRuns(dir / "results" / "swept")[1].status), "missing");
}

TEST(Collect, AFolderThatIsNoSweepsOrAMalformedListIsAnInputError) {
    TempFolder dir;
    EXPECT_EQ(errorOf(dir.path()), dir.path().string() +
                                       ": not a sweep's experiment folder (no .sweep/runs.json, which `gibench sweep FILE --backend slurm` writes)");
    const std::string file = (dir / ".sweep/runs.json").string();
    dir.write(".sweep/runs.json", R"({"runs": 3})");
    EXPECT_EQ(errorOf(dir.path()), file + ": expected an object with an array \"runs\"");
    dir.write(".sweep/runs.json", R"({"runs": [{"index": -1, "name": "a", "run_id": "x"}]})");
    EXPECT_EQ(errorOf(dir.path()), file + R"(: /runs/0: expected {"index": N >= 0, "name": "...", "run_id": "..."}, got {"index":-1,"name":"a","run_id":"x"})");
    dir.write(".sweep/runs.json", R"({"runs": [{"index": 0, "name": "../elsewhere", "run_id": "x"}]})");
    EXPECT_EQ(errorOf(dir.path()), file + ": /runs/0: expected a run name (a folder name not starting with '.'), got \"../elsewhere\"");
    dir.write(".sweep/runs.json", R"({"runs": [{"index": 0, "name": "a", "run_id": "x"}, {"index": 1, "name": "a", "run_id": "y"}]})");
    EXPECT_EQ(errorOf(dir.path()), file + ": /runs/1: run \"a\" is listed twice");
}

}  // namespace
}  // namespace gibench
