#pragma once
// `gibench collect DIR`: whether every run a sweep submitted (slurm_backend.h) is there and done.
//
// A submitted sweep leaves in its experiment folder .sweep/runs.json, the runs expected:
//   {"sweep_file": "/abs/sweep.json", "runs": [{"index": 0, "name": "seed-0", "run_id": "0123..."}, ...]}
// and each run lands in <experiment>/<name>/. A run is
//   done     when <name>/manifest.json is finished, its "run_id" is the expected one and the
//            run's other files (metrics.json, frames.jsonl, image.exr) are there;
//   failed   when it is not done and the sweep recorded its failure (<experiment>/.failed/<name>.json
//            of the same id, sweep_runner.h: the error), or else the log its task left
//            (.sweep/slurm-<job>_<index>.out, the latest job's) has a line with "error:" or
//            ": failed: " (Slurm's time limit, a crash): the last such line;
//   missing  otherwise: never ran (or runs still: collect once the job has left the queue), its
//            folder holds another run (another id) or none, or its result was removed.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace gibench {

struct ExpectedRun {
    std::size_t index = 0;  // the point's index in the sweep (the array task's)
    std::string name;
    std::string runId;
};

// .sweep/runs.json of an experiment folder, written whole (a temporary file renamed).
void writeExpectedRuns(const std::filesystem::path& experimentDir, const std::filesystem::path& sweepFile,
                       const std::vector<ExpectedRun>& runs);
// The runs written there; InputError naming the folder when it is not a sweep's (no runs.json),
// or naming the file and entry when it is malformed.
std::vector<ExpectedRun> readExpectedRuns(const std::filesystem::path& experimentDir);

// "" when `runDir` holds the finished run `runId` whole, else why not ("no folder seed-0/", "holds
// run 0123... (another config), not 4567..."): the test of "done" for collect and for what a
// submission leaves out.
std::string whyNotDone(const std::filesystem::path& runDir, const std::string& runId);

enum class RunStatus { Done, Failed, Missing };
std::string statusName(RunStatus status);

struct CollectedRun {
    ExpectedRun expected;
    RunStatus status = RunStatus::Missing;
    std::string detail;  // why it is failed or missing; "" when done
};

// The verdict on every expected run of the sweep in `experimentDir`, in index order.
std::vector<CollectedRun> collectRuns(const std::filesystem::path& experimentDir);

// The table `gibench collect` prints (run, id, status, error) and its summary line
// ("4 runs: 3 done, 1 failed, 0 missing").
std::string collectTable(const std::vector<CollectedRun>& runs);

// `gibench collect DIR [--experiment NAME]`: DIR is the experiment folder, or the results root
// when `experiment` is given. Prints the table; returns 0 when every run is done, else 1.
int runCollect(const std::filesystem::path& dir, const std::optional<std::string>& experiment);

}  // namespace gibench
