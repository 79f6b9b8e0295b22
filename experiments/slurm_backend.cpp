#include "experiments/slurm_backend.h"

#include "core/config/input_file.h"
#include "core/util/error.h"
#include "experiments/collect.h"
#include "experiments/child_process.h"
#include "experiments/output_dir.h"
#include "experiments/run_id.h"
#include "experiments/sweep_runner.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <regex>
#include <thread>

namespace gibench {

const ParamTable kSlurmParams = {
    {"cpus_per_task", ParamType::Int, 1, "CPUs of each task (sbatch --cpus-per-task), and its run's worker threads", 1, 4096},
    {"mem", ParamType::String, "", "memory of each task (sbatch --mem): megabytes, or a number with K, M, G or T (\"2G\"); \"\": the cluster's default"},
    {"time", ParamType::String, "", "time limit of each task (sbatch --time): MM, MM:SS, HH:MM:SS, D-HH, D-HH:MM or D-HH:MM:SS; \"\": the partition's"},
    {"partition", ParamType::String, "", "partition (or comma-separated partitions) to submit to; \"\": the cluster's default"},
    {"wait", ParamType::Bool, false, "wait for the job array to finish, then collect (as --wait does)"},
    {"max_parallel", ParamType::Int, 0, "most tasks running at once (the array's %N); 0: no limit", 0, 100000},
};

namespace {

// The sbatch formats of --mem and --time, and a partition name.
const std::regex kMemory("[0-9]+[KMGT]?");
const std::regex kTimeLimit("[0-9]+(-[0-9]+(:[0-9]+(:[0-9]+)?)?|:[0-9]+(:[0-9]+)?)?");
const std::regex kPartitions("[A-Za-z0-9_.-]+(,[A-Za-z0-9_.-]+)*");

std::string checkedText(Params& block, const std::string& key, const std::regex& format, const std::string& expected) {
    const std::string value = block.getString(key);
    if (!value.empty() && !std::regex_match(value, format)) block.fail(key, "expected " + expected + ", got \"" + value + "\"");
    return value;
}

// '%' starts a Slurm file name pattern; "%%" is a literal one.
std::string slurmPatternLiteral(const std::string& text) {
    std::string out;
    for (const char c : text) out += c == '%' ? std::string("%%") : std::string(1, c);
    return out;
}

// What task.sh holds: the task's command comes as arguments, so no path is ever quoted into a
// shell string.
constexpr const char* kTaskScript =
    "#!/bin/sh\n"
    "# One task of a gibench sweep's Slurm job array, written by `gibench sweep FILE --backend slurm`:\n"
    "# runs the sweep's point whose index is the task's (the command line comes as arguments).\n"
    "exec \"$@\" --index \"$SLURM_ARRAY_TASK_ID\"\n";

std::string trimmed(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ' || text.back() == '\r')) text.pop_back();
    return text;
}

// An argument vector as one line a user can paste into a shell.
std::string shellLine(const std::vector<std::string>& argv) {
    std::string line;
    for (const std::string& a : argv) {
        const bool plain = !a.empty() && std::all_of(a.begin(), a.end(), [](char c) {
            return std::isalnum(static_cast<unsigned char>(c)) || std::strchr("_-./=:,%", c);
        });
        std::string quoted = "'";
        for (const char c : a) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
        line += (line.empty() ? "" : " ") + (plain ? a : quoted + "'");
    }
    return line;
}

// Polls squeue until `job` has left the queue: every 0.1 s at first (a short job on an idle
// cluster ends within seconds), growing to every 2 s. Returns "" then, or what went wrong when
// squeue keeps failing.
std::string waitForJob(const std::string& job) {
    auto interval = std::chrono::milliseconds(100);
    constexpr auto kLongest = std::chrono::milliseconds(2000);
    constexpr int kFailuresInARow = 20;
    int failures = 0;
    for (;;) {
        const auto outcome = runAndCapture({"squeue", "--noheader", "--jobs=" + job, "--format=%i"});
        if (!outcome) return "squeue not found on PATH";
        // A job that ended long enough ago is no longer known to squeue at all.
        if (outcome->exitCode == 0 && trimmed(outcome->out).empty()) return "";
        if (outcome->exitCode != 0 && outcome->err.find("Invalid job id") != std::string::npos) return "";
        if (outcome->exitCode != 0 && ++failures >= kFailuresInARow) return "squeue failed " + std::to_string(failures) + " times: " + trimmed(outcome->err);
        if (outcome->exitCode == 0) failures = 0;
        std::this_thread::sleep_for(interval);
        interval = std::min(kLongest, interval * 3 / 2);
    }
}

}  // namespace

SlurmSettings readSlurmSettings(const Json& block, const std::filesystem::path& sweepFile) {
    SlurmSettings settings;
    if (block.is_null()) return settings;
    Json given = block;
    if (given.is_object())
        for (auto it = given.begin(); it != given.end();) it = it->is_null() ? given.erase(it) : std::next(it);
    Params slurm(given, sweepFile.string(), "/slurm", "the sweep's slurm block", &kSlurmParams);
    settings.cpusPerTask = int(slurm.getInt("cpus_per_task"));
    settings.mem = checkedText(slurm, "mem", kMemory, "megabytes or a size with K, M, G or T such as \"2G\"");
    settings.time = checkedText(slurm, "time", kTimeLimit, "a time limit MM, MM:SS, HH:MM:SS, D-HH, D-HH:MM or D-HH:MM:SS such as \"00:20:00\"");
    settings.partition = checkedText(slurm, "partition", kPartitions, "a partition name (letters, digits, '_', '-', '.'; several joined by ',')");
    settings.wait = slurm.getBool("wait");
    settings.maxParallel = int(slurm.getInt("max_parallel"));
    slurm.finish();
    return settings;
}

std::string arrayIndexList(const std::vector<std::size_t>& indices) {
    std::string list;
    for (std::size_t i = 0; i < indices.size();) {
        std::size_t last = i;
        while (last + 1 < indices.size() && indices[last + 1] == indices[last] + 1) ++last;
        if (!list.empty()) list += ',';
        list += std::to_string(indices[i]);
        if (last > i) list.append("-").append(std::to_string(indices[last]));
        i = last + 1;
    }
    return list;
}

std::vector<std::string> sbatchArguments(const SlurmSubmission& s) {
    const SlurmSettings& settings = s.settings;
    std::vector<std::string> argv = {"sbatch", "--parsable", "--job-name=" + s.jobName,
                                     "--array=" + arrayIndexList(s.indices) + (settings.maxParallel > 0 ? "%" + std::to_string(settings.maxParallel) : ""),
                                     "--cpus-per-task=" + std::to_string(settings.cpusPerTask)};
    if (!settings.mem.empty()) argv.push_back("--mem=" + settings.mem);
    if (!settings.time.empty()) argv.push_back("--time=" + settings.time);
    if (!settings.partition.empty()) argv.push_back("--partition=" + settings.partition);
    argv.push_back("--chdir=" + s.workDir.string());
    argv.push_back("--output=" + slurmPatternLiteral((s.sweepDir / "slurm-").string()) + "%A_%a.out");
    for (const std::string& a : {(s.sweepDir / "task.sh").string(), s.gibench.string(), std::string("sweep"), s.sweepFile.string(),
                                 std::string("--threads"), std::to_string(settings.cpusPerTask), std::string("--quiet")})
        argv.push_back(a);
    argv.insert(argv.end(), s.runArguments.begin(), s.runArguments.end());
    return argv;
}

int runSlurmSweep(const Sweep& sweep, const SlurmSweepOptions& options) {
    const SlurmSettings settings = readSlurmSettings(sweep.slurm, sweep.file);

    // Every point checked (and its references found) before anything is written, all of them in
    // one experiment folder.
    RunOverrides overrides = options.run;
    overrides.threads = settings.cpusPerTask;
    std::vector<PlannedRun> runs = planSweep(sweep, overrides);
    const std::filesystem::path experimentDir = std::filesystem::absolute(runs.front().folder.parent_path()).lexically_normal();
    for (const PlannedRun& run : runs)
        if (std::filesystem::absolute(run.folder.parent_path()).lexically_normal() != experimentDir)
            throw InputError(sweep.file.string() + ": run \"" + run.name + "\" goes to " + run.folder.parent_path().string() + ", run \"" +
                             runs.front().name + "\" to " + experimentDir.string() +
                             ": the slurm backend needs every run of a sweep in one experiment folder");
    if (!options.dryRun) provideReferences(sweep, overrides, runs, options.showProgress);
    std::vector<std::size_t> pending;
    for (const PlannedRun& run : runs)
        if (!run.done) pending.push_back(run.index);

    SlurmSubmission submission;
    submission.settings = settings;
    submission.gibench = currentExecutable();
    submission.sweepFile = std::filesystem::absolute(sweep.file).lexically_normal();
    submission.sweepDir = experimentDir / ".sweep";
    submission.workDir = std::filesystem::current_path();
    submission.jobName = "gibench-" + experimentDir.filename().string();
    submission.indices = pending;
    submission.runArguments = overrideArguments(options.run);
    const std::vector<std::string> argv = sbatchArguments(submission);

    if (options.dryRun) {
        printPlannedRuns(runs);
        std::printf("; %zu to submit", pending.size());
        if (!pending.empty()) std::printf(" with:\n%s", shellLine(argv).c_str());
        std::printf("\n");
        return 0;
    }

    std::vector<ExpectedRun> expected;
    for (const PlannedRun& run : runs) expected.push_back({run.index, run.name, run.id});
    writeExpectedRuns(experimentDir, submission.sweepFile, expected);
    writeFileAtomically(submission.sweepDir / "sweep.json", readInputFile(sweep.file, sweep.file.string() + ": cannot read: "));
    writeFileAtomically(submission.sweepDir / "task.sh", kTaskScript);

    if (pending.empty()) {
        std::printf("every one of the %zu runs is done already; nothing submitted\n", runs.size());
        return runCollect(experimentDir, std::nullopt);
    }
    const auto outcome = runAndCapture(argv);
    if (!outcome) throw InputError("--backend slurm: sbatch not found on PATH (Slurm's client commands; Debian: slurm-client)");
    const std::string reply = trimmed(outcome->out);
    const std::string job = reply.substr(0, reply.find(';'));  // "JOB" or "JOB;CLUSTER"
    if (outcome->exitCode != 0 || job.empty() || !std::all_of(job.begin(), job.end(), [](char c) { return c >= '0' && c <= '9'; }))
        throw InputError(sweep.file.string() + ": sbatch refused the job array (exit " + std::to_string(outcome->exitCode) + "): " +
                         trimmed(outcome->err + outcome->out) + "\ncommand: " + shellLine(argv));
    std::printf("submitted job %s: %zu of %zu runs (array %s), logs in %s/\n", job.c_str(), pending.size(), runs.size(),
                arrayIndexList(pending).c_str(), submission.sweepDir.string().c_str());
    if (!options.wait && !settings.wait) {
        std::printf("when it has finished: gibench collect %s\n", experimentDir.string().c_str());
        return 0;
    }
    std::printf("waiting for job %s\n", job.c_str());
    std::fflush(stdout);
    if (const std::string problem = waitForJob(job); !problem.empty()) {
        std::fprintf(stderr, "error: cannot follow job %s: %s; once it has finished: gibench collect %s\n", job.c_str(), problem.c_str(),
                     experimentDir.string().c_str());
        return 1;
    }
    return runCollect(experimentDir, std::nullopt);
}

}  // namespace gibench
