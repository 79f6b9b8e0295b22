// The sweep runner (issue 10 item 3) as a user meets it through the `gibench` executable: parallel
// jobs give the runs one job gives, a failed point is recorded while the others go on, a sweep
// killed with SIGKILL resumes without losing a finished run or counting a half-written one, and a
// missing reference stops the sweep before it starts.

#include "support/gibench_cli.h"
#include "support/temp_folder.h"

#include "core/config/params.h"
#include "core/util/hash.h"
#include "experiments/child_process.h"
#include "experiments/run_config.h"
#include "experiments/run_id.h"

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <thread>

namespace gibench {
namespace {

using test::gibench;
using test::Outcome;

Json readJson(const std::filesystem::path& file) {
    std::ifstream in(file);
    return Json::parse(in);
}

// A base config of `frames` small path-traced frames, results under `results`.
Json baseConfig(const std::filesystem::path& results, int frames) {
    return {{"experiment", "runner"},
            {"scene", std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json"},
            {"frames", frames},
            {"camera", {{"resolution", {24, 24}}}},
            {"method", {{"name", "path_traced"}, {"spp", 2}}},
            {"output", {{"root", results.string()}}}};
}

std::filesystem::path writeSweep(const TempFolder& dir, const Json& base, const Json& sweep) {
    std::ofstream(dir / "base.json") << base.dump(2);
    std::ofstream(dir / "sweep.json") << sweep.dump(2);
    return dir / "sweep.json";
}

std::string imageHash(const std::filesystem::path& run) { return sha256File(run / "image.exr"); }

TEST(SweepRunner, ParallelJobsWriteTheRunsOneJobWrites) {
    TempFolder dir;
    const Json axes = {{"method", {{{"name", "path_traced"}, {"spp", 2}}, {{"name", "mamba"}}}}, {"seed", {0, 1}}};
    writeSweep(dir, baseConfig(dir / "one", 3), {{"base", "base.json"}, {"grid", axes}});
    const Outcome one = gibench("sweep " + (dir / "sweep.json").string() + " --quiet");
    ASSERT_EQ(one.exitCode, 0) << one.output;
    writeSweep(dir, baseConfig(dir / "two", 3), {{"base", "base.json"}, {"grid", axes}});
    const Outcome two = gibench("sweep " + (dir / "sweep.json").string() + " --jobs 2 --quiet");
    ASSERT_EQ(two.exitCode, 0) << two.output;
    EXPECT_NE(two.output.find("4 runs: 4 done, 0 skipped, 0 failed"), std::string::npos) << two.output;
    for (const char* run : {"method-path_traced-spp-2_seed-0", "method-path_traced-spp-2_seed-1", "method-mamba_seed-0", "method-mamba_seed-1"}) {
        const auto a = dir / "one" / "runner" / run, b = dir / "two" / "runner" / run;
        EXPECT_EQ(imageHash(a), imageHash(b)) << run << ": a run does not depend on how many ran beside it, or on its threads";
        const Json manifest = readJson(b / "manifest.json");
        EXPECT_EQ(manifest["run_id"], runId(manifest["config"]));
        EXPECT_EQ(manifest["run_id"], readJson(a / "manifest.json")["run_id"]);
        EXPECT_EQ(manifest["sweep"]["file"], (dir / "sweep.json").string());
        EXPECT_EQ(manifest["sweep"]["axes"]["seed"], manifest["config"]["seed"]);
        EXPECT_EQ(manifest["sweep"]["axes"]["method"]["name"], manifest["config"]["method"]["name"]);
    }
    EXPECT_TRUE(std::filesystem::exists(dir / "two" / "runner" / ".logs" / "method-mamba_seed-1.log")) << "each job's output is kept";
}

TEST(SweepRunner, SetAndResultsReachEveryRunAndEveryJob) {
    TempFolder dir;
    writeSweep(dir, baseConfig(dir / "unused", 1), {{"base", "base.json"}, {"grid", {{"seed", {0, 1}}}}});
    for (const char* jobs : {"1", "2"}) {
        const auto results = dir / (std::string("jobs") + jobs);
        const Outcome o = gibench("sweep " + (dir / "sweep.json").string() + " --jobs " + jobs + " --quiet --set method.spp=3 --results " +
                                  results.string());
        ASSERT_EQ(o.exitCode, 0) << o.output;
        for (const char* run : {"seed-0", "seed-1"}) {
            const Json manifest = readJson(results / "runner" / run / "manifest.json");
            EXPECT_EQ(manifest["config"]["method"]["spp"], 3) << jobs << " " << run;
            EXPECT_EQ(manifest["config_overrides"][0], "method.spp=3");
        }
    }
    EXPECT_FALSE(std::filesystem::exists(dir / "unused"));
}

TEST(SweepRunner, AFailedRunIsRecordedAndTheOthersGoOn) {
    TempFolder dir;
    // An external reference of 24x24: right for one resolution, the wrong size for the other,
    // which only shows when that run starts.
    ASSERT_EQ(gibench("run " + [&] {
                  Json config = baseConfig(dir / "made", 1);
                  std::ofstream(dir / "ref.json") << config.dump();
                  return (dir / "ref.json").string();
              }() + " --quiet")
                  .exitCode,
              0);
    Json base = baseConfig(dir / "results", 1);
    base["reference"] = {{"file", (dir / "made" / "runner" / "ref" / "image.exr").string()}};
    writeSweep(dir, base, {{"base", "base.json"}, {"zip", {{"camera.resolution", {{16, 16}, {24, 24}}}}}});
    const Outcome o = gibench("sweep " + (dir / "sweep.json").string() + " --jobs 2 --quiet");
    EXPECT_EQ(o.exitCode, 1) << o.output;
    EXPECT_NE(o.output.find("1 done, 0 skipped, 1 failed"), std::string::npos) << o.output;
    const auto failed = dir / "results" / "runner" / ".failed" / "resolution-16x16.json";
    ASSERT_TRUE(std::filesystem::exists(failed)) << o.output;
    const Json record = readJson(failed);
    EXPECT_NE(record["error"].get<std::string>().find("reference is 24x24, the run renders 16x16"), std::string::npos) << record.dump();
    EXPECT_EQ(record["run_id"].get<std::string>().size(), 16u);
    EXPECT_FALSE(std::filesystem::exists(dir / "results" / "runner" / "resolution-16x16"));
    EXPECT_TRUE(std::filesystem::exists(dir / "results" / "runner" / "resolution-24x24" / "manifest.json"));
    EXPECT_FALSE(std::filesystem::exists(dir / "results" / "runner" / ".failed" / "resolution-24x24.json"));
}

TEST(SweepRunner, ASweepKilledWithSigkillResumesWithoutLosingOrMiscountingARun) {
    TempFolder dir;
    const Json sweep = {{"base", "base.json"}, {"grid", {{"seed", {0, 1, 2, 3}}}}};
    writeSweep(dir, baseConfig(dir / "killed", 30), sweep);
    const pid_t pid = spawnChild({GIBENCH_EXE, "sweep", (dir / "sweep.json").string(), "--jobs", "2", "--threads", "1", "--quiet"}, dir / "log.txt");
    const auto runs = dir / "killed" / "runner";
    auto finished = [&] {
        int n = 0;
        for (int seed = 0; seed < 4; ++seed) n += finishedRunId(runs / ("seed-" + std::to_string(seed))).empty() ? 0 : 1;
        return n;
    };
    // Two jobs: seeds 2 and 3 start only when 0 or 1 has finished, so they cannot finish within
    // the few milliseconds between the first finish and the kill unless a whole run (a process
    // start, a scene load, 30 frames) takes less than that.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (finished() == 0 && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the jobs get their SIGKILL (PR_SET_PDEATHSIG) and die
    const int before = finished();
    ASSERT_GE(before, 1);
    ASSERT_LT(before, 4) << "the runs are too quick for the test to kill the sweep half-way";
    // What the kill left: finished runs, and nothing else that looks like one.
    std::vector<std::filesystem::file_time_type> written;
    for (const auto& entry : std::filesystem::directory_iterator(runs)) {
        const std::string name = entry.path().filename().string();
        if (name[0] == '.') continue;
        EXPECT_FALSE(finishedRunId(entry.path()).empty()) << name << ": a visible run folder is a finished run";
        written.push_back(std::filesystem::last_write_time(entry.path() / "manifest.json"));
    }

    const Outcome resumed = gibench("sweep " + (dir / "sweep.json").string() + " --jobs 2 --quiet");
    ASSERT_EQ(resumed.exitCode, 0) << resumed.output;
    std::size_t skipped = 0;
    for (std::size_t at = 0; (at = resumed.output.find("done before, skipped", at)) != std::string::npos; ++at) ++skipped;
    EXPECT_EQ(skipped, std::size_t(before)) << resumed.output;
    EXPECT_EQ(finished(), 4);

    writeSweep(dir, baseConfig(dir / "clean", 30), sweep);
    ASSERT_EQ(gibench("sweep " + (dir / "sweep.json").string() + " --quiet").exitCode, 0);
    for (int seed = 0; seed < 4; ++seed) {
        const std::string run = "seed-" + std::to_string(seed);
        EXPECT_EQ(imageHash(runs / run), imageHash(dir / "clean" / "runner" / run)) << run;
    }
}

TEST(SweepRunner, AMissingReferenceStopsTheSweepBeforeItStartsUnlessItMayRenderIt) {
    TempFolder dir;
    Json base = baseConfig(dir / "results", 1);
    base["reference"] = {{"spp", 4}};
    writeSweep(dir, base, {{"base", "base.json"}, {"grid", {{"seed", {0, 1}}}}});
    const Outcome o = gibench("sweep " + (dir / "sweep.json").string() + " --quiet");
    EXPECT_EQ(o.exitCode, 2) << o.output;
    EXPECT_NE(o.output.find("1 reference image the runs are measured against is missing"), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("\"render_references\": true"), std::string::npos) << o.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "results" / "runner")) << "nothing ran";

    writeSweep(dir, base, {{"base", "base.json"}, {"render_references", true}, {"grid", {{"seed", {0, 1}}}}});
    const Outcome rendered = gibench("sweep " + (dir / "sweep.json").string() + " --jobs 2 --quiet");
    ASSERT_EQ(rendered.exitCode, 0) << rendered.output;
    std::size_t renders = 0;
    for (std::size_t at = 0; (at = rendered.output.find("rendered reference", at)) != std::string::npos; ++at) ++renders;
    EXPECT_EQ(renders, 1u) << "one reference for both seeds, rendered once";
    for (const char* run : {"seed-0", "seed-1"}) {
        const Json metrics = readJson(dir / "results" / "runner" / run / "metrics.json");
        EXPECT_TRUE(metrics["error"]["total"].is_object()) << run << ": measured against the reference";
        EXPECT_GT(metrics["reference_noise"]["total"].get<double>(), 0.0);
    }
}

TEST(SweepRunner, AnIndexOutsideTheSweepIsAnErrorNamingTheOption) {
    TempFolder dir;
    writeSweep(dir, baseConfig(dir / "results", 1), {{"base", "base.json"}, {"grid", {{"seed", {0, 1}}}}});
    const Outcome o = gibench("sweep " + (dir / "sweep.json").string() + " --index 2");
    EXPECT_EQ(o.exitCode, 2);
    EXPECT_EQ(o.output, "error: --index: expected 0 to 1 (" + (dir / "sweep.json").string() + " has 2 runs), got 2\n");
    const Outcome one = gibench("sweep " + (dir / "sweep.json").string() + " --index 1 --quiet");
    EXPECT_EQ(one.exitCode, 0) << one.output;
    EXPECT_TRUE(std::filesystem::exists(dir / "results" / "runner" / "seed-1" / "manifest.json"));
    EXPECT_FALSE(std::filesystem::exists(dir / "results" / "runner" / "seed-0"));
}

TEST(SweepRunner, ARelativeOutputRootIsTheConfigFoldersLikeItsScene) {
    TempFolder dir;
    std::filesystem::create_directories(dir / "configs");
    Json config = baseConfig("out", 1);
    std::ofstream(dir / "configs" / "run.json") << config.dump();
    EXPECT_EQ(loadRunConfig(dir / "configs" / "run.json").outputRoot, dir / "configs" / "out");
    config.erase("output");
    std::ofstream(dir / "configs" / "run.json") << config.dump();
    EXPECT_EQ(loadRunConfig(dir / "configs" / "run.json").outputRoot, "results") << "the default stays the working directory's";
}

}  // namespace
}  // namespace gibench
