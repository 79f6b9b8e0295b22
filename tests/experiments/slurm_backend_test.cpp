// The Slurm backend of sweeps (issue 10 item 4) without a cluster: the "slurm" block, the one
// sbatch argument vector, and a submission through stand-ins for sbatch and squeue on PATH. The
// round trip through a real private cluster is tests/slurm/slurm_roundtrip.sh.

#include "support/gibench_cli.h"
#include "experiments/slurm_backend.h"

#include "experiments/collect.h"
#include "experiments/sweep_runner.h"

#include "support/temp_folder.h"

#include "core/util/error.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <sys/wait.h>

namespace gibench {
namespace {

std::string readText(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string errorOf(const Json& block) {
    try {
        readSlurmSettings(block, "s.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(SlurmBlock, AbsentOrNullKeysTakeTheTableDefaults) {
    for (const Json& block : {Json(), Json::object(), Json{{"partition", nullptr}, {"max_parallel", nullptr}, {"mem", nullptr}}}) {
        const SlurmSettings s = readSlurmSettings(block, "s.json");
        EXPECT_EQ(s.cpusPerTask, 1) << block;
        EXPECT_EQ(s.mem, "") << block;
        EXPECT_EQ(s.time, "") << block;
        EXPECT_EQ(s.partition, "") << block;
        EXPECT_FALSE(s.wait) << block;
        EXPECT_EQ(s.maxParallel, 0) << block;
    }
    const SlurmSettings s = readSlurmSettings(
        {{"cpus_per_task", 4}, {"mem", "2G"}, {"time", "1-00:20:00"}, {"partition", "gpu,batch"}, {"wait", true}, {"max_parallel", 8}}, "s.json");
    EXPECT_EQ(s.cpusPerTask, 4);
    EXPECT_EQ(s.mem, "2G");
    EXPECT_EQ(s.time, "1-00:20:00");
    EXPECT_EQ(s.partition, "gpu,batch");
    EXPECT_TRUE(s.wait);
    EXPECT_EQ(s.maxParallel, 8);
    for (const char* time : {"20", "20:30", "00:20:00", "2-12", "2-12:30"}) EXPECT_EQ(errorOf({{"time", time}}), "") << time;
}

TEST(SlurmBlock, BadKeysAndValuesAreErrorsNamingTheFileAndKey) {
    EXPECT_EQ(errorOf({{"cpus", 2}}),
              "s.json: /slurm/cpus: unknown key for the sweep's slurm block (known: cpus_per_task, mem, time, partition, wait, max_parallel)");
    EXPECT_EQ(errorOf({{"cpus_per_task", 0}}), "s.json: /slurm/cpus_per_task: expected an integer in [1, 4096], got 0");
    EXPECT_EQ(errorOf({{"cpus_per_task", 1.5}}), "s.json: /slurm/cpus_per_task: expected an integer in [1, 4096], got 1.5");
    EXPECT_EQ(errorOf({{"mem", "2 GB"}}), "s.json: /slurm/mem: expected megabytes or a size with K, M, G or T such as \"2G\", got \"2 GB\"");
    EXPECT_EQ(errorOf({{"mem", 2048}}), "s.json: /slurm/mem: expected a string, got 2048");
    EXPECT_EQ(errorOf({{"time", "20 minutes"}}),
              "s.json: /slurm/time: expected a time limit MM, MM:SS, HH:MM:SS, D-HH, D-HH:MM or D-HH:MM:SS such as \"00:20:00\", got \"20 minutes\"");
    EXPECT_NE(errorOf({{"time", "1:2:3:4"}}), "");
    EXPECT_EQ(errorOf({{"partition", "a b"}}),
              "s.json: /slurm/partition: expected a partition name (letters, digits, '_', '-', '.'; several joined by ','), got \"a b\"");
    EXPECT_EQ(errorOf({{"wait", "yes"}}), "s.json: /slurm/wait: expected true or false, got \"yes\"");
    EXPECT_EQ(errorOf({{"max_parallel", -1}}), "s.json: /slurm/max_parallel: expected an integer in [0, 100000], got -1");
    EXPECT_EQ(errorOf(3), "s.json: /slurm: expected an object for the sweep's slurm block, got 3");
}

SlurmSubmission submission() {
    SlurmSubmission s;
    s.gibench = "/opt/gibench/build/gibench";
    s.sweepFile = "/home/me/sweeps/seeds.json";
    s.sweepDir = "/home/me/results/seeds/.sweep";
    s.workDir = "/home/me";
    s.jobName = "gibench-seeds";
    s.indices = {0, 1, 2, 3};
    return s;
}

TEST(SlurmSubmission, ArrayListsCompressConsecutiveIndicesIntoRanges) {
    EXPECT_EQ(arrayIndexList({0, 1, 2, 3}), "0-3");
    EXPECT_EQ(arrayIndexList({0, 2, 3, 4, 7}), "0,2-4,7");
    EXPECT_EQ(arrayIndexList({5}), "5");
    EXPECT_EQ(arrayIndexList({1, 3, 5, 6}), "1,3,5-6");
}

TEST(SlurmSubmission, OneSbatchCallWhoseTaskRunsItsPointWithTheBlocksCpus) {
    SlurmSubmission s = submission();
    s.settings = {2, "2G", "00:20:00", "batch", true, 3};
    const std::vector<std::string> expected = {"sbatch", "--parsable", "--job-name=gibench-seeds", "--array=0-3%3", "--cpus-per-task=2",
                                               "--mem=2G", "--time=00:20:00", "--partition=batch", "--chdir=/home/me",
                                               "--output=/home/me/results/seeds/.sweep/slurm-%A_%a.out", "/home/me/results/seeds/.sweep/task.sh",
                                               "/opt/gibench/build/gibench", "sweep", "/home/me/sweeps/seeds.json", "--threads", "2", "--quiet"};
    EXPECT_EQ(sbatchArguments(s), expected);
    // Defaults leave the cluster's choices alone; a '%' of a folder is no file name pattern.
    s.settings = {};
    s.sweepDir = "/home/me/100%/.sweep";
    s.indices = {1, 3};
    const std::vector<std::string> plain = {"sbatch", "--parsable", "--job-name=gibench-seeds", "--array=1,3", "--cpus-per-task=1", "--chdir=/home/me",
                                            "--output=/home/me/100%%/.sweep/slurm-%A_%a.out", "/home/me/100%/.sweep/task.sh",
                                            "/opt/gibench/build/gibench", "sweep", "/home/me/sweeps/seeds.json", "--threads", "1", "--quiet"};
    EXPECT_EQ(sbatchArguments(s), plain);
}

// A sweep of four tiny runs, a stand-in for Slurm's commands first on PATH while it lives.
class FakeSlurm {
public:
    FakeSlurm(const TempFolder& dir, const std::string& sbatchScript) : m_oldPath(std::getenv("PATH") ? std::getenv("PATH") : "") {
        dir.write("bin/sbatch", sbatchScript);
        dir.write("bin/squeue", "#!/bin/sh\nexit 0\n");  // an empty queue: the job has ended
        std::filesystem::permissions(dir / "bin/sbatch", std::filesystem::perms::owner_all);
        std::filesystem::permissions(dir / "bin/squeue", std::filesystem::perms::owner_all);
        setenv("PATH", ((dir / "bin").string() + ":" + m_oldPath).c_str(), 1);
    }
    ~FakeSlurm() { setenv("PATH", m_oldPath.c_str(), 1); }
    FakeSlurm(const FakeSlurm&) = delete;
    FakeSlurm& operator=(const FakeSlurm&) = delete;

private:
    std::string m_oldPath;
};

std::filesystem::path writeSweep(const TempFolder& dir, const std::string& slurmBlock) {
    dir.write("base.json", R"({"experiment": "x", "scene": ")" + std::string(GIBENCH_SOURCE_DIR) +
                               R"(/configs/scenes/cornell_box.json", "frames": 1, "camera": {"resolution": [8, 8]},
                               "method": {"name": "path_traced", "spp": 1}, "output": {"root": ")" + (dir / "results").string() + R"("}})");
    return dir.write("sweep.json", R"({"base": "base.json", "experiment": "fake", "grid": {"seed": [0, 1, 2, 3]}, "slurm": )" + slurmBlock + "}");
}

TEST(SlurmSweep, SubmitsOnlyThePointsNotDoneAndRecordsTheExpectedRuns) {
    TempFolder dir;
    const Sweep sweep = loadSweep(writeSweep(dir, R"({"cpus_per_task": 2, "max_parallel": 2})"));
    SweepOptions one;
    one.index = 1;
    one.showProgress = false;
    ASSERT_EQ(runSweep(sweep, one), 0) << "point 1 done before the submission";
    const FakeSlurm slurm(dir, "#!/bin/sh\nfor a in \"$@\"; do echo \"$a\"; done > \"$(dirname \"$0\")/../argv.txt\"\necho '4242;cluster'\n");
    EXPECT_EQ(runSlurmSweep(sweep, {}), 0);

    const std::filesystem::path sweepDir = dir / "results" / "fake" / ".sweep";
    std::istringstream lines(readText(dir / "argv.txt"));
    std::vector<std::string> argv = {"sbatch"};
    for (std::string line; std::getline(lines, line);) argv.push_back(line);
    SlurmSubmission expected;
    expected.settings = readSlurmSettings(sweep.slurm, sweep.file);
    expected.gibench = std::filesystem::read_symlink("/proc/self/exe");
    expected.sweepFile = sweep.file;
    expected.sweepDir = sweepDir;
    expected.workDir = std::filesystem::current_path();
    expected.jobName = "gibench-fake";
    expected.indices = {0, 2, 3};
    EXPECT_EQ(argv, sbatchArguments(expected)) << "the tasks run this executable; point 1 is left out";
    EXPECT_EQ(readText(sweepDir / "sweep.json"), readText(sweep.file));
    EXPECT_NE(readText(sweepDir / "task.sh").find("exec \"$@\" --index \"$SLURM_ARRAY_TASK_ID\""), std::string::npos);
    const std::vector<ExpectedRun> runs = readExpectedRuns(dir / "results" / "fake");
    ASSERT_EQ(runs.size(), 4u) << "every point is expected, done before or not";
    const std::vector<PlannedRun> planned = planSweep(sweep, {2, std::nullopt, {}});
    for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(runs[i].index, i);
        EXPECT_EQ(runs[i].name, "seed-" + std::to_string(i));
        EXPECT_EQ(runs[i].runId, planned[i].id);
    }
}

TEST(SlurmSweep, WaitingEndsWithCollectsVerdict) {
    TempFolder dir;
    const Sweep sweep = loadSweep(writeSweep(dir, R"({"wait": true})"));
    const FakeSlurm slurm(dir, "#!/bin/sh\necho 77\n");  // accepts the job, runs nothing
    EXPECT_EQ(runSlurmSweep(sweep, {}), 1) << "the queue is empty at once and no run is there";
    for (const CollectedRun& run : collectRuns(dir / "results" / "fake")) EXPECT_EQ(run.status, RunStatus::Missing) << run.expected.name;
}

TEST(SlurmSweep, ARefusingOrMissingSbatchIsAConfigurationError) {
    TempFolder dir;
    const Sweep sweep = loadSweep(writeSweep(dir, "{}"));
    {
        const FakeSlurm slurm(dir, "#!/bin/sh\necho 'sbatch: error: invalid partition specified: nope' >&2\nexit 1\n");
        try {
            runSlurmSweep(sweep, {});
            FAIL() << "expected an InputError";
        } catch (const InputError& e) {
            const std::string what = e.what();
            EXPECT_EQ(what.rfind(sweep.file.string() + ": sbatch refused the job array (exit 1): sbatch: error: invalid partition specified: nope\ncommand: sbatch ", 0), 0u)
                << what;
        }
    }
    const std::string oldPath = std::getenv("PATH");
    setenv("PATH", (dir / "empty").string().c_str(), 1);
    std::string what;
    try {
        runSlurmSweep(sweep, {});
    } catch (const InputError& e) {
        what = e.what();
    }
    setenv("PATH", oldPath.c_str(), 1);
    EXPECT_EQ(what, "--backend slurm: sbatch not found on PATH (Slurm's client commands; Debian: slurm-client)");
}

TEST(SlurmSweep, RunsInTwoExperimentFoldersAreRefusedBeforeAnythingIsWritten) {
    TempFolder dir;
    writeSweep(dir, "{}");
    dir.write("split.json", R"({"base": "base.json", "zip": {"experiment": ["a", "b"], "seed": [0, 1]}})");
    try {
        runSlurmSweep(loadSweep(dir / "split.json"), {});
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("the slurm backend needs every run of a sweep in one experiment folder"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(dir / "results")) << "nothing written";
}

using test::gibench;
using test::Outcome;

TEST(SlurmCli, OptionsThatDoNotGoWithTheBackendAndBadBlocksExitWith2) {
    TempFolder dir;
    const std::string file = writeSweep(dir, R"({"cpus_per_task": 2})").string();
    const Outcome threads = gibench("sweep " + file + " --backend slurm --threads 2");
    EXPECT_EQ(threads.exitCode, 2);
    EXPECT_EQ(threads.output, "error: --threads: not with --backend slurm (the sweep file's \"slurm\" block sets what each task gets)\n");
    EXPECT_EQ(gibench("sweep " + file + " --backend slurm --index 1").exitCode, 2);
    EXPECT_EQ(gibench("sweep " + file + " --backend slurm --jobs 2").exitCode, 2);
    const Outcome wait = gibench("sweep " + file + " --wait");
    EXPECT_EQ(wait.exitCode, 2);
    EXPECT_EQ(wait.output, "error: --wait: only with --backend slurm\n");
    EXPECT_EQ(gibench("sweep " + file + " --backend cluster").exitCode, 2);
    // The block is checked whatever the backend: a typo never waits for the first submission.
    const std::string typo = writeSweep(dir, R"({"cpus": 2})").string();
    const Outcome local = gibench("sweep " + typo + " --dry-run");
    EXPECT_EQ(local.exitCode, 2);
    EXPECT_NE(local.output.find("error: " + typo + ": /slurm/cpus: unknown key for the sweep's slurm block"), std::string::npos) << local.output;
    const Outcome collect = gibench("collect " + (dir / "results").string());
    EXPECT_EQ(collect.exitCode, 2);
    EXPECT_EQ(collect.output, "error: " + (dir / "results").string() +
                                  ": not a sweep's experiment folder (no .sweep/runs.json, which `gibench sweep FILE --backend slurm` writes)\n");
}

TEST(SlurmCli, ADryRunChecksEveryPointAndPrintsTheSbatchCommandWritingNothing) {
    TempFolder dir;
    const Outcome dry = gibench("sweep " + writeSweep(dir, R"({"cpus_per_task": 2, "mem": "1G"})").string() + " --backend slurm --dry-run");
    EXPECT_EQ(dry.exitCode, 0) << dry.output;
    EXPECT_NE(dry.output.find("4 runs, every one checked; 4 to submit with:\nsbatch --parsable --job-name=gibench-fake --array=0-3 "
                              "--cpus-per-task=2 --mem=1G --chdir="),
              std::string::npos)
        << dry.output;
    EXPECT_NE(dry.output.find(" sweep " + (dir / "sweep.json").string() + " --threads 2 --quiet\n"), std::string::npos) << dry.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "results")) << "a dry run writes nothing";
}

TEST(SlurmDocs, EveryKeyOfTheBlockIsDocumentedWithItsMeaning) {
    const std::string docs = readText(std::string(GIBENCH_SOURCE_DIR) + "/docs/slurm.md");
    for (const ParamSpec& spec : kSlurmParams) {
        EXPECT_NE(docs.find("| `" + spec.name + "` |"), std::string::npos) << spec.name;
        EXPECT_NE(docs.find(spec.meaning), std::string::npos) << spec.name << ": " << spec.meaning;
    }
}

}  // namespace
}  // namespace gibench
