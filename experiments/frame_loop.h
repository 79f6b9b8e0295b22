#pragma once
// The frames of a run: renders them in order with the run's method, times every stage, measures
// error against the reference where the camera is at the reference's pose, and appends one record
// per frame to frames.jsonl (error against time, frame by frame).

#include "core/image/image.h"
#include "experiments/run_config.h"

#include <filesystem>
#include <map>
#include <string>

namespace gibench {

struct FrameLoopResult {
    LayeredImage image;                          // the last frame
    std::map<std::string, double> stageSeconds;  // per stage, summed over the frames
    double frameSeconds = 0.0;                   // rendering only, summed over the frames
    double evaluationSeconds = 0.0;              // error measurement and frame images
    Json lastError = nullptr;                    // the last measured frame's error, or null
};

// Writes frames.jsonl (and frame_NNNN.exr every config.imageEvery frames) into `dir`. `reference`
// may be null (no error is measured).
FrameLoopResult renderFrames(RunConfig& config, const PreparedScene& scene, const LayeredImage* reference,
                             const std::filesystem::path& dir, bool showProgress);

}  // namespace gibench
