#pragma once
// The frames of a run: renders them in order with the run's method, times every stage, measures
// error against the reference where the camera is at the reference's pose, and appends one record
// per frame to frames.jsonl (error against time, frame by frame).

#include "core/image/image.h"
#include "experiments/run_config.h"

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace gibench {

struct FrameLoopResult {
    LayeredImage image;                          // the last frame
    std::map<std::string, double> stageSeconds;  // per stage, summed over the frames
    double frameSeconds = 0.0;                   // rendering only, summed over the frames
    double evaluationSeconds = 0.0;              // error measurement and frame images
    Json lastError = nullptr;                    // the last measured frame's error, or null
    Json events = Json::array();                 // recovery after each change of the scene (event_recovery.h)
    int frames = 0;                              // rendered: config.frames, or fewer when the budget ran out
    bool stoppedByBudget = false;
    Json checkpoints;                            // checkpointRecords()
};

// Writes frames.jsonl (and frame_NNNN.exr every config.imageEvery frames, with the attributes
// of run_writer.h's runExrAttributes and `commit`) into `dir`. `scene` is
// the scene as loaded; at each event's frame the loop prepares the changed scene
// (sceneOfSegment) and hands it to the method. `references` holds one image per segment
// (segmentStarts(config.events)), any of them null (that segment's error is not measured).
FrameLoopResult renderFrames(RunConfig& config, const PreparedScene& scene, const std::vector<const LayeredImage*>& references,
                             const std::filesystem::path& dir, const std::string& commit, bool showProgress);

}  // namespace gibench
