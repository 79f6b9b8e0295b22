#pragma once
// `gibench sweep FILE --backend slurm` (issue 10 item 4): the sweep as one Slurm job array, one
// task per run not yet done, each task `gibench sweep FILE --index I` on the cluster.
//
// The sweep file's optional "slurm" block sets what every task asks for (kSlurmParams; a key set
// to null takes its default):
//   "slurm": {"cpus_per_task": 2, "mem": "2G", "time": "00:20:00", "partition": "batch",
//             "wait": true, "max_parallel": 8}
//
// Before anything is submitted every point is checked (as the local backend does) and
// <output root>/<experiment>/.sweep/ is written: sweep.json (the sweep file as it was), runs.json
// (the expected runs: index, name, run id; what `gibench collect` checks against, collect.h) and
// task.sh, the task's script. The array's indices are the points' indices, so task I runs point I
// and logs into .sweep/slurm-<job>_<I>.out; points already done with the same id are left out of
// the array. A task's run has cpus_per_task worker threads.

#include "core/config/params.h"
#include "experiments/sweep.h"

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace gibench {

extern const ParamTable kSlurmParams;

// The "slurm" block, read through kSlurmParams.
struct SlurmSettings {
    int cpusPerTask = 1;
    std::string mem;        // sbatch --mem; "" = the cluster's default
    std::string time;       // sbatch --time; "" = the partition's default
    std::string partition;  // "" = the cluster's default partition
    bool wait = false;
    int maxParallel = 0;  // the array's %N; 0 = no limit
};

// `block` is Sweep::slurm (null when the sweep file has none: every default). InputError naming
// `sweepFile`, /slurm/KEY and what was expected for an unknown key or a bad value.
SlurmSettings readSlurmSettings(const Json& block, const std::filesystem::path& sweepFile);

// Everything one submission needs; every path absolute.
struct SlurmSubmission {
    SlurmSettings settings;
    std::filesystem::path gibench;    // the executable the tasks run
    std::filesystem::path sweepFile;  // as the tasks read it
    std::filesystem::path sweepDir;   // <root>/<experiment>/.sweep: task.sh and the logs
    std::filesystem::path workDir;    // the tasks' working folder, where a relative output root lies
    std::string jobName;
    std::vector<std::size_t> indices;  // the points to run, ascending, not empty
    std::vector<std::string> runArguments;  // the sweep command's --set and --results, passed on to every task
};

// Indices as Slurm's --array list: ascending runs of consecutive numbers as ranges ("0-3,5,7-8").
std::string arrayIndexList(const std::vector<std::size_t>& indices);

// The argument vector of the one sbatch call (argv[0] = "sbatch"), a pure function: options, then
// task.sh and the task's command line `GIBENCH sweep FILE --threads CPUS --quiet` and the run
// arguments, to which task.sh appends `--index $SLURM_ARRAY_TASK_ID`.
std::vector<std::string> sbatchArguments(const SlurmSubmission& submission);

struct SlurmSweepOptions {
    bool wait = false;    // --wait: wait whatever the block says
    bool dryRun = false;  // check, print the sbatch command, write and submit nothing
    RunOverrides run;     // the sweep command's --set keys and --results (threads: the block's)
    bool showProgress = true;  // the progress of references rendered before submitting (--quiet: none)
};

// Checks every point, writes .sweep/, submits the array; with waiting, polls squeue until the job
// has left the queue and returns collect's status (0: every run done, 1: not), else prints the job
// id and the collect command and returns 0. InputError (exit 2) for a bad sweep, a missing sbatch or
// one that refuses the job; runs of one sweep must share one experiment folder.
int runSlurmSweep(const Sweep& sweep, const SlurmSweepOptions& options);

}  // namespace gibench
