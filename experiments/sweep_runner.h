#pragma once
// `gibench sweep FILE`: runs the points of a sweep (sweep.h) on this machine, in turn or as
// parallel child processes, resumable at any moment.
//
// Before anything runs every point is checked (an InputError for the first that fails) and
// every reference the runs need is found: a missing one is rendered once, before the runs, when
// the sweep says "render_references": true, and is an InputError otherwise, never a run whose
// error is silently null. A point whose folder already holds a finished run of the same id
// (run_id.h) is skipped, so a sweep killed at any moment (even by SIGKILL) resumes where it was:
// a run is written whole or not at all (output_dir.h), and only a written one counts as done.
// A point that fails is recorded in <experiment>/.failed/<run>.json (its id and error, removed
// once it succeeds) and the others go on.

#include "experiments/sweep.h"

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace gibench {

struct SweepOptions {
    // Laid over every point: --set keys (before the axes), --results, and threads per run
    // (default: the config's with one job, else cores / jobs).
    RunOverrides run;
    int jobs = 1;                      // runs at a time: more than one runs each in a child process
    std::optional<std::size_t> index;  // only this point (what a Slurm array task runs)
    bool dryRun = false;               // check and list, render nothing
    bool showProgress = true;          // the sweep's progress line, and each run's with one job
};

struct PlannedRun {
    std::size_t index = 0;
    std::string name, id;
    std::filesystem::path folder;  // <output root>/<experiment>/<run>
    bool done = false;             // a finished run of the same id is there
    // References not rendered yet: (first frame of the segment, image path).
    std::vector<std::pair<int, std::filesystem::path>> missingReferences;
};

// Checks the points (all, or only `only`) and finds what each needs; InputError for the first that
// fails, naming the sweep file and the run.
std::vector<PlannedRun> planSweep(const Sweep& sweep, const RunOverrides& run, std::optional<std::size_t> only = std::nullopt);

// The dry-run listing: a line per run (its id, <experiment>/<run>, whether it is done or misses a
// reference), then the count; the caller ends that last line.
void printPlannedRuns(const std::vector<PlannedRun>& runs);

// `run`'s --set keys and --results as command-line arguments, for a process that runs a point.
std::vector<std::string> overrideArguments(const RunOverrides& run);

// Renders each missing reference of `runs` once when the sweep says so; InputError listing them
// (and how to render them) otherwise. Afterwards no run in `runs` misses one.
void provideReferences(const Sweep& sweep, const RunOverrides& overrides, std::vector<PlannedRun>& runs, bool showProgress);

// Runs the sweep; returns the number of points that failed. Prints a line per point (its id,
// name and what happened) with the counts so far and an ETA.
int runSweep(const Sweep& sweep, const SweepOptions& options);

// Where the error of a failed run is kept until it succeeds.
std::filesystem::path failureRecordPath(const std::filesystem::path& runFolder);

}  // namespace gibench
