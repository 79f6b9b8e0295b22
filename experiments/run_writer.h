#pragma once
// What a finished run leaves in its folder besides frames.jsonl: the last frame's image.exr (and
// image.png), metrics.json (final error and time) and manifest.json (everything needed to tell
// how the numbers came about: resolved config, code, content hashes, machine, timings per stage,
// stages left out and why).

#include "core/render/method.h"
#include "experiments/frame_loop.h"
#include "experiments/run_config.h"

#include <filesystem>
#include <string>
#include <vector>

namespace gibench {

// The parts of a run outside its frames, for the manifest.
struct RunRecord {
    std::string started;  // UTC, ISO 8601
    int threads = 0;
    double prepareSceneSeconds = 0.0;   // BVH and light sampler
    double prepareMethodSeconds = 0.0;  // Method::prepare
    Json reference;                     // where the reference is and whether it was found, or null
    Json referenceNoise;                // {layer: expected relMSE of the reference itself} (reference_noise.h), or null
    RunNotes notes;                     // what the method left out for this scene
    Json manifest;                      // manifestBeforeFrames(); writeRunFiles() adds the rest
};

// The manifest's entries known before the first frame (code, config, scene files, machine,
// reference): every string that reaches the manifest from outside gibench (file and folder
// names) is among them. Throws InputError naming the config file when one is not UTF-8, so that
// the run fails before it renders rather than when the manifest is written.
Json manifestBeforeFrames(const RunConfig& config, const RunRecord& record);

// The header attributes of the run's EXR files after `frames` frames (results/README.md):
// gibench:method, gibench:frames, gibench:spp (methods that have it), gibench:seed (decimal
// text: seeds are 64-bit), gibench:commit (the manifest's), gibench:run_id (run_id.h).
std::vector<ExrAttribute> runExrAttributes(const RunConfig& config, const std::string& commit, int frames);

// Writes the files into `dir`; returns the contents of metrics.json.
Json writeRunFiles(const std::filesystem::path& dir, const RunConfig& config, const PreparedScene& scene, const RunRecord& record,
                   const FrameLoopResult& frames);

}  // namespace gibench
