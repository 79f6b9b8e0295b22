#include "experiments/collect.h"

#include "core/config/params.h"
#include "core/util/error.h"
#include "experiments/output_dir.h"
#include "experiments/sweep_runner.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <set>

namespace gibench {

namespace {

std::filesystem::path runsFile(const std::filesystem::path& experimentDir) { return experimentDir / ".sweep" / "runs.json"; }

// The number N of a task log "slurm-N_INDEX.out" for `index`, or nullopt for any other file.
std::optional<unsigned long long> logJob(const std::string& fileName, std::size_t index) {
    const std::string prefix = "slurm-", suffix = std::string("_").append(std::to_string(index)).append(".out");
    if (fileName.size() <= prefix.size() + suffix.size() || !fileName.starts_with(prefix) || !fileName.ends_with(suffix)) return std::nullopt;
    const std::string job = fileName.substr(prefix.size(), fileName.size() - prefix.size() - suffix.size());
    if (job.empty() || job.size() > 18 || !std::all_of(job.begin(), job.end(), [](char c) { return c >= '0' && c <= '9'; })) return std::nullopt;
    return std::stoull(job);
}

// The log of the latest job that ran task `index`, or "" when no task of it left one.
std::filesystem::path latestLog(const std::filesystem::path& sweepDir, std::size_t index) {
    std::filesystem::path latest;
    unsigned long long latestJob = 0;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(sweepDir, ec)) {
        const auto job = logJob(entry.path().filename().string(), index);
        if (job && (latest.empty() || *job > latestJob)) {
            latest = entry.path();
            latestJob = *job;
        }
    }
    return latest;
}

// The last line of `log` that reports an error (gibench's "error: ..." and the sweep's
// "...: failed: ...", Slurm's "slurmstepd: error: *** ... DUE TO TIME LIMIT ***").
std::string lastErrorLine(const std::filesystem::path& log) {
    std::ifstream in(log);
    std::string found;
    for (std::string line; std::getline(in, line);)
        if (line.find("error:") != std::string::npos || line.find(": failed: ") != std::string::npos) found = line;
    return found;
}

// The error the sweep recorded for this run of this id (sweep_runner.h), or "".
std::string recordedFailure(const std::filesystem::path& runDir, const std::string& runId) {
    std::ifstream in(failureRecordPath(runDir));
    const Json record = in ? Json::parse(in, nullptr, false) : Json();
    if (!record.is_object() || record.value("run_id", "") != runId || !record.contains("error") || !record["error"].is_string()) return "";
    return record["error"].get<std::string>();
}

}  // namespace

std::string whyNotDone(const std::filesystem::path& runDir, const std::string& runId) {
    std::error_code ec;
    if (!std::filesystem::is_directory(runDir, ec)) return "no folder " + runDir.filename().string() + "/";
    std::ifstream in(runDir / "manifest.json");
    if (!in) return "no manifest.json in " + runDir.filename().string() + "/";
    const Json manifest = Json::parse(in, nullptr, false);
    if (manifest.is_discarded() || !manifest.is_object()) return "manifest.json is not a JSON object";
    if (!manifest.contains("finished")) return "manifest.json has no \"finished\": the run did not end";
    const auto id = manifest.find("run_id");
    if (id == manifest.end() || !id->is_string()) return "manifest.json has no \"run_id\"";
    if (*id != runId) return "holds run " + id->get<std::string>() + " (another config), not " + runId;
    for (const char* file : {"metrics.json", "frames.jsonl", "image.exr"})
        if (!std::filesystem::is_regular_file(runDir / file, ec)) return std::string("no ") + file + " beside the finished manifest";
    return "";
}

void writeExpectedRuns(const std::filesystem::path& experimentDir, const std::filesystem::path& sweepFile,
                       const std::vector<ExpectedRun>& runs) {
    Json list = Json::array();
    for (const ExpectedRun& run : runs) list.push_back({{"index", run.index}, {"name", run.name}, {"run_id", run.runId}});
    std::filesystem::create_directories(runsFile(experimentDir).parent_path());
    writeFileAtomically(runsFile(experimentDir), Json{{"sweep_file", sweepFile.string()}, {"runs", list}}.dump(2) + "\n");
}

std::vector<ExpectedRun> readExpectedRuns(const std::filesystem::path& experimentDir) {
    const std::filesystem::path file = runsFile(experimentDir);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
        throw InputError(experimentDir.string() + ": not a sweep's experiment folder (no .sweep/runs.json, which `gibench sweep FILE "
                                                  "--backend slurm` writes)");
    const Json root = loadJsonFile(file);
    if (!root.is_object() || !root.contains("runs") || !root["runs"].is_array())
        throw InputError(file.string() + ": expected an object with an array \"runs\"");
    std::vector<ExpectedRun> runs;
    std::set<std::string> names;
    for (std::size_t i = 0; i < root["runs"].size(); ++i) {
        const Json& entry = root["runs"][i];
        const std::string where = file.string() + ": /runs/" + std::to_string(i) + ": ";
        if (!entry.is_object() || !entry.contains("index") || !entry["index"].is_number_unsigned() || !entry.contains("name") ||
            !entry["name"].is_string() || !entry.contains("run_id") || !entry["run_id"].is_string())
            throw InputError(where + "expected {\"index\": N >= 0, \"name\": \"...\", \"run_id\": \"...\"}, got " + entry.dump());
        ExpectedRun run{entry["index"].get<std::size_t>(), entry["name"].get<std::string>(), entry["run_id"].get<std::string>()};
        // A name is a folder inside the experiment's: nothing that leads out of it.
        if (run.name.empty() || run.name.front() == '.' || run.name.find('/') != std::string::npos)
            throw InputError(where + "expected a run name (a folder name not starting with '.'), got \"" + run.name + "\"");
        if (!names.insert(run.name).second) throw InputError(where + "run \"" + run.name + "\" is listed twice");
        runs.push_back(std::move(run));
    }
    std::sort(runs.begin(), runs.end(), [](const ExpectedRun& a, const ExpectedRun& b) { return a.index < b.index; });
    return runs;
}

std::string statusName(RunStatus status) {
    switch (status) {
        case RunStatus::Done: return "done";
        case RunStatus::Failed: return "failed";
        case RunStatus::Missing: return "missing";
    }
    return "?";
}

std::vector<CollectedRun> collectRuns(const std::filesystem::path& experimentDir) {
    std::vector<CollectedRun> out;
    for (const ExpectedRun& expected : readExpectedRuns(experimentDir)) {
        CollectedRun run{expected, RunStatus::Done, whyNotDone(experimentDir / expected.name, expected.runId)};
        if (!run.detail.empty()) {
            run.status = RunStatus::Missing;
            const std::filesystem::path log = latestLog(experimentDir / ".sweep", expected.index);
            if (const std::string recorded = recordedFailure(experimentDir / expected.name, expected.runId); !recorded.empty()) {
                run.status = RunStatus::Failed;
                run.detail = recorded;
            } else if (!log.empty()) {
                const std::string error = lastErrorLine(log), logName = ".sweep/" + log.filename().string();
                if (error.empty()) {
                    run.detail += " (its task's log " + logName + " names no error)";
                } else {
                    run.status = RunStatus::Failed;
                    run.detail = error + " (" + logName + ")";
                }
            }
        }
        out.push_back(std::move(run));
    }
    return out;
}

std::string collectTable(const std::vector<CollectedRun>& runs) {
    std::size_t nameWidth = 3;
    for (const CollectedRun& r : runs) nameWidth = std::max(nameWidth, r.expected.name.size());
    const auto row = [&](const std::string& name, const std::string& id, const std::string& status, const std::string& detail) {
        std::string line = name + std::string(nameWidth - name.size() + 2, ' ') + id + std::string(id.size() < 18 ? 18 - id.size() : 1, ' ') +
                           status + (detail.empty() ? "" : std::string(status.size() < 9 ? 9 - status.size() : 1, ' ') + detail);
        return line + "\n";
    };
    std::string out = row("run", "id", "status", "error");
    std::size_t counts[3] = {0, 0, 0};
    for (const CollectedRun& r : runs) {
        out += row(r.expected.name, r.expected.runId, statusName(r.status), r.detail);
        ++counts[int(r.status)];
    }
    out += std::to_string(runs.size()) + " runs: " + std::to_string(counts[int(RunStatus::Done)]) + " done, " +
           std::to_string(counts[int(RunStatus::Failed)]) + " failed, " + std::to_string(counts[int(RunStatus::Missing)]) + " missing\n";
    return out;
}

int runCollect(const std::filesystem::path& dir, const std::optional<std::string>& experiment) {
    const std::filesystem::path experimentDir = experiment ? dir / *experiment : dir;
    const std::vector<CollectedRun> runs = collectRuns(experimentDir);
    std::fputs(collectTable(runs).c_str(), stdout);
    std::fflush(stdout);
    return std::all_of(runs.begin(), runs.end(), [](const CollectedRun& r) { return r.status == RunStatus::Done; }) ? 0 : 1;
}

}  // namespace gibench
