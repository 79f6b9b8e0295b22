#pragma once
// A sweep file: one base run config and the axes along which its runs differ (issue 10 item 1).
//
// {
//   "base": "../cornell_box.json",                  a run config file, relative to the sweep file
//   "experiment": "stores",                         optional: the runs' experiment (default the base's)
//   "grid": {"method.name": ["mamba", "cards"],     every combination of the grid's axes (the first
//            "seed": [0, 1, 2]},                    in key order, i.e. sorted, varies slowest)...
//   "zip": {"scene": ["a.json", "b.json"],          ...times the zipped axes, which vary together
//           "camera.eye": [[0, 1, 3], [2, 1, 0]]},  (each the same length)
//   "render_references": false,                     true: render each missing reference once before
//                                                   the runs (else a missing one is an error)
//   "slurm": {...}                                  how the Slurm backend submits it (slurm_backend.h)
// }
//
// An axis is a key as `--set` names it (config_overrides.h) with the list of its values. Each
// point of the sweep is the base with one value of every axis set. Its name is made of the axes'
// values ("method-mamba_seed-0"): grid axes then zipped ones, each in key order, each as its key's
// last part (the part before a last "name") and its value: a method block by its name and other
// keys, a .json file by its stem, [128, 128] as 128x128; axes of one value are left out unless
// every axis has one. A "run" axis names the points instead; two points of one name are an error.
// Its id is the first 16 hex digits of the SHA-256 of its resolved config without what does not
// change the result (run_id.h). sweep_runner.h runs them.

#include "experiments/config_overrides.h"
#include "experiments/run_config.h"

#include <filesystem>
#include <string>
#include <vector>

namespace gibench {

extern const ParamTable kSweepParams;

struct SweepPoint {
    std::size_t index = 0;  // in the order --dry-run lists the points
    std::string name;
    Json axes;  // {key: value} of every axis at this point
    std::vector<ConfigOverride> keys;  // the axes' values, then "run" (and "experiment") as the point sets them
};

struct Sweep {
    std::filesystem::path file;
    std::filesystem::path base;  // the base config
    std::vector<SweepPoint> points;
    // Whether a missing reference is rendered before the runs (else it is an error).
    bool renderReferences = false;
    Json slurm;  // the file's "slurm" block as written, null when absent (read by slurm_backend.h)
};

// Reads and expands a sweep file; InputError naming the file and key for anything malformed
// (no axes, a zipped axis of another length, an axis key that --set would refuse, two points
// with the same name).
Sweep loadSweep(const std::filesystem::path& file);

// The run config of a point, read and checked like `gibench run BASE --set ...`: `extra`'s keys
// (the sweep command's --set) first, then the point's; its manifest records the point
// (RunConfig::sweep).
RunConfig loadSweepPoint(const Sweep& sweep, const SweepPoint& point, const RunOverrides& extra = {});

}  // namespace gibench
