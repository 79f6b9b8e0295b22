#include "experiments/sweep_runner.h"

#include "core/util/error.h"
#include "experiments/child_process.h"
#include "experiments/manifest.h"
#include "experiments/output_dir.h"
#include "experiments/reference.h"
#include "experiments/run.h"
#include "experiments/run_id.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <thread>
#include <unistd.h>

namespace gibench {

std::filesystem::path failureRecordPath(const std::filesystem::path& runFolder) {
    return runFolder.parent_path() / ".failed" / (runFolder.filename().string() + ".json");
}

namespace {

void recordFailure(const PlannedRun& run, const std::string& error) {
    const std::filesystem::path file = failureRecordPath(run.folder);
    try {
        std::filesystem::create_directories(file.parent_path());
        writeFileAtomically(file, Json{{"run", run.name}, {"run_id", run.id}, {"error", error}, {"failed", utcNow()}}.dump(2) + "\n");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "note: could not record the failure of %s: %s\n", run.name.c_str(), e.what());
    }
}

void clearFailure(const PlannedRun& run) {
    std::error_code ignored;
    std::filesystem::remove(failureRecordPath(run.folder), ignored);
}

// The recorded error of a run that failed in a child process, or `fallback`.
std::string recordedError(const PlannedRun& run, const std::string& fallback) {
    std::ifstream in(failureRecordPath(run.folder));
    const Json record = in ? Json::parse(in, nullptr, false) : Json();
    if (record.is_object() && record.value("run_id", "") == run.id && record.contains("error") && record["error"].is_string())
        return record["error"].get<std::string>();
    return fallback;
}

std::string duration(double seconds) {
    char text[32];
    const long s = std::lround(seconds);
    if (s < 60)
        std::snprintf(text, sizeof text, "%lds", s);
    else if (s < 3600)
        std::snprintf(text, sizeof text, "%ldm%02lds", s / 60, s % 60);
    else
        std::snprintf(text, sizeof text, "%ldh%02ldm", s / 3600, (s % 3600) / 60);
    return text;
}

// The sweep's counts and ETA: appended to every line a point prints and, on a terminal, also
// kept on one status line that is redrawn in place while runs go on.
class SweepProgress {
public:
    SweepProgress(std::size_t points, std::size_t toRun, bool enabled)
        : m_points(points), m_toRun(toRun), m_enabled(enabled && isatty(fileno(stderr)) != 0) {}

    void report(const PlannedRun& run, const char* what, const std::string& detail, bool failed) {
        ++m_finished;
        if (failed) ++m_failed;
        clearStatus();
        std::printf("[%zu/%zu] %s %s: %s%s%s  (%s)\n", run.index + 1, m_points, run.id.c_str(), run.name.c_str(), what,
                    detail.empty() ? "" : " ", detail.c_str(), counts().c_str());
        std::fflush(stdout);
    }
    void skipped(const PlannedRun& run) {
        std::printf("[%zu/%zu] %s %s: done before, skipped\n", run.index + 1, m_points, run.id.c_str(), run.name.c_str());
        std::fflush(stdout);
    }
    void status(const std::vector<std::string>& running) {
        if (!m_enabled) return;
        std::string line = "sweep: " + counts() + ", running";
        for (const std::string& r : running) line += " " + r;
        if (line.size() > 160) line = line.substr(0, 157) + "...";
        std::fprintf(stderr, "\r\033[K%s", line.c_str());
        std::fflush(stderr);
        m_statusShown = true;
    }
    void clearStatus() {
        if (!m_statusShown) return;
        std::fprintf(stderr, "\r\033[K");
        m_statusShown = false;
    }
    std::string counts() const {
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
        std::string text = std::to_string(m_finished - m_failed) + " done, " + std::to_string(m_failed) + " failed of " +
                           std::to_string(m_toRun) + " to run";
        if (m_finished >= m_toRun)
            text += ", " + duration(elapsed);
        else if (m_finished > 0)
            text += ", ETA " + duration(elapsed / double(m_finished) * double(m_toRun - m_finished));
        else
            text += ", ETA unknown";
        return text;
    }

private:
    std::size_t m_points, m_toRun;
    bool m_enabled;
    std::size_t m_finished = 0, m_failed = 0;
    bool m_statusShown = false;
    std::chrono::steady_clock::time_point m_start = std::chrono::steady_clock::now();
};

PlannedRun planPoint(const Sweep& sweep, const SweepPoint& point, const RunOverrides& overrides) {
    const RunConfig config = loadSweepPoint(sweep, point, overrides);
    PlannedRun run{point.index, point.name, runId(config), config.outputRoot / config.experiment / config.run, false, {}};
    run.done = finishedRunId(run.folder) == run.id;
    if (config.reference.kind == ReferenceSpec::Kind::Rendered)
        for (const int segment : segmentStarts(config.events))
            if (!std::filesystem::exists(referencePath(config, segment))) run.missingReferences.push_back({segment, referencePath(config, segment)});
    return run;
}

// Renders the run in this process; the line it prints says how it went.
bool runInProcess(const Sweep& sweep, const PlannedRun& run, const RunOverrides& overrides, bool showProgress, SweepProgress& progress) {
    try {
        RunConfig config = loadSweepPoint(sweep, sweep.points[run.index], overrides);
        const RunResult result = executeRun(config, showProgress);
        clearFailure(run);
        progress.report(run, "wrote", result.directory.string(), false);
        return true;
    } catch (const std::exception& e) {
        recordFailure(run, e.what());
        progress.report(run, "failed:", e.what(), true);
        return false;
    }
}

int runInChildren(const Sweep& sweep, const std::vector<const PlannedRun*>& toRun, const SweepOptions& options, SweepProgress& progress) {
    const int threads = options.run.threads.value_or(std::max(1, int(std::thread::hardware_concurrency()) / options.jobs));
    const std::vector<std::string> overrides = overrideArguments(options.run);
    const std::string executable = currentExecutable().string();
    const std::string sweepFile = std::filesystem::absolute(sweep.file).string();
    std::map<pid_t, const PlannedRun*> running;
    std::size_t next = 0;
    int failed = 0;
    auto lastStatus = std::chrono::steady_clock::now() - std::chrono::seconds(1);
    while (next < toRun.size() || !running.empty()) {
        while (next < toRun.size() && running.size() < std::size_t(options.jobs)) {
            const PlannedRun& run = *toRun[next++];
            const std::filesystem::path log = run.folder.parent_path() / ".logs" / (run.name + ".log");
            try {
                std::filesystem::create_directories(log.parent_path());
                std::filesystem::remove(log);
                std::vector<std::string> argv = {executable, "sweep", sweepFile, "--index", std::to_string(run.index), "--threads",
                                                 std::to_string(threads), "--quiet"};
                argv.insert(argv.end(), overrides.begin(), overrides.end());
                running[spawnChild(argv, log)] = &run;
            } catch (const std::exception& e) {
                recordFailure(run, e.what());
                progress.report(run, "failed:", e.what(), true);
                ++failed;
            }
        }
        if (running.empty()) continue;
        const ChildExit exit = waitForChild(true);
        if (exit.pid == 0) {
            if (std::chrono::steady_clock::now() - lastStatus >= std::chrono::seconds(1)) {
                std::vector<std::string> names;
                for (const auto& entry : running) names.push_back(entry.second->name);
                progress.status(names);
                lastStatus = std::chrono::steady_clock::now();
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
            continue;
        }
        const auto found = running.find(exit.pid);
        if (found == running.end()) continue;  // not one of ours
        const PlannedRun& run = *found->second;
        running.erase(found);
        const std::string log = (run.folder.parent_path() / ".logs" / (run.name + ".log")).string();
        if (exit.exitCode == 0 && finishedRunId(run.folder) == run.id) {
            progress.report(run, "wrote", run.folder.string(), false);
            continue;
        }
        ++failed;
        std::string error = exit.exitCode > 128 ? "killed by signal " + std::to_string(exit.exitCode - 128)
                                                : "exit code " + std::to_string(exit.exitCode);
        error = recordedError(run, error + ", see " + log);
        if (exit.exitCode != 1) recordFailure(run, error);  // the child could not record it itself
        progress.report(run, "failed:", error, true);
    }
    progress.clearStatus();
    return failed;
}

}  // namespace

std::vector<std::string> overrideArguments(const RunOverrides& run) {
    std::vector<std::string> arguments;
    for (const ConfigOverride& o : run.keys) arguments.insert(arguments.end(), {"--set", o.text});
    if (run.outputRoot) arguments.insert(arguments.end(), {"--results", std::filesystem::absolute(*run.outputRoot).string()});
    return arguments;
}

std::vector<PlannedRun> planSweep(const Sweep& sweep, const RunOverrides& run, std::optional<std::size_t> only) {
    if (only && *only >= sweep.points.size())
        throw InputError("--index: expected 0 to " + std::to_string(sweep.points.size() - 1) + " (" + sweep.file.string() + " has " +
                         std::to_string(sweep.points.size()) + " runs), got " + std::to_string(*only));
    std::vector<PlannedRun> runs;
    for (const SweepPoint& point : sweep.points)
        if (!only || point.index == *only) runs.push_back(planPoint(sweep, point, run));
    return runs;
}

void provideReferences(const Sweep& sweep, const RunOverrides& overrides, std::vector<PlannedRun>& runs, bool showProgress) {
    std::set<std::filesystem::path> rendered;
    std::string missing;
    std::size_t count = 0;
    for (PlannedRun& run : runs) {
        if (run.done) continue;
        for (const auto& [segment, image] : run.missingReferences) {
            if (rendered.count(image) || std::filesystem::exists(image)) continue;
            if (!sweep.renderReferences) {
                if (++count <= 5) missing += "\n  " + image.string() + " (run " + run.name + ")";
                rendered.insert(image);
                continue;
            }
            const RunConfig config = loadSweepPoint(sweep, sweep.points[run.index], overrides);
            const ReferenceOutcome outcome = ensureReference(config, false, showProgress, segment);
            std::printf("rendered reference %s in %.1f s\n", outcome.image.string().c_str(), outcome.seconds);
            rendered.insert(image);
        }
        if (sweep.renderReferences) run.missingReferences.clear();
    }
    if (count > 0)
        throw InputError(sweep.file.string() + ": " + std::to_string(count) + " reference image" + (count > 1 ? "s" : "") +
                         " the runs are measured against " + (count > 1 ? "are" : "is") + " missing:" + missing +
                         (count > 5 ? "\n  ..." : "") +
                         "\nrender them with `gibench reference` (the base config with the run's --set keys) or set "
                         "\"render_references\": true in the sweep file");
}

void printPlannedRuns(const std::vector<PlannedRun>& runs) {
    for (const PlannedRun& run : runs)
        std::printf("%s  %s%s%s\n", run.id.c_str(), (run.folder.parent_path().filename() / run.name).string().c_str(),
                    run.done ? "  (done)" : "", run.missingReferences.empty() ? "" : "  (reference missing)");
    std::printf("%zu runs, every one checked", runs.size());
}

int runSweep(const Sweep& sweep, const SweepOptions& options) {
    std::vector<PlannedRun> runs = planSweep(sweep, options.run, options.index);
    if (options.dryRun) {
        printPlannedRuns(runs);
        std::printf("\n");
        return 0;
    }
    provideReferences(sweep, options.run, runs, options.showProgress);
    std::vector<const PlannedRun*> toRun;
    for (const PlannedRun& run : runs)
        if (run.done)
            clearFailure(run);
        else
            toRun.push_back(&run);
    SweepProgress progress(sweep.points.size(), toRun.size(), options.showProgress && !options.index);
    for (const PlannedRun& run : runs)
        if (run.done) progress.skipped(run);
    int failed = 0;
    if (options.jobs > 1 && toRun.size() > 1 && !options.index) {
        failed = runInChildren(sweep, toRun, options, progress);
    } else {
        for (const PlannedRun* run : toRun)
            if (!runInProcess(sweep, *run, options.run, options.showProgress, progress)) ++failed;
    }
    if (!options.index)
        std::printf("%zu runs: %zu done, %zu skipped, %d failed\n", runs.size(), toRun.size() - std::size_t(failed), runs.size() - toRun.size(),
                    failed);
    return failed;
}

}  // namespace gibench
