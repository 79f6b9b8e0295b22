#pragma once
// When a run stops, and where its error is recorded for equal-time and equal-frame comparisons.
//
//   "budget": {"seconds": 2.0}    stop once the frames' render time reaches 2 s (the frame that
//                                 crosses it is the last); "frames" stays the most frames. The
//                                 frame count of such a run depends on the machine's speed.
//   "checkpoints": {"frames": [1, 4, 16], "seconds": [0.25, 1.0]}
//                                 error recorded after that many frames, and as it stood after
//                                 that much render time (the last frame finished by then);
//                                 ascending, positive. Default: frames 1, 2, 4, ... up to
//                                 "frames" and "frames" itself; seconds kDefaultSecondCheckpoints.
// Render time is the frames' own (FrameLoopResult::frameSeconds): error measurement and image
// output are not counted.

#include "core/config/params.h"

#include <optional>
#include <vector>

namespace gibench {

// The equal-time budgets of the default checkpoints, seconds.
inline constexpr double kDefaultSecondCheckpoints[] = {0.1, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0};

struct Checkpoints {
    std::vector<int> frames;      // after this many frames
    std::vector<double> seconds;  // after this much render time
    Json resolved;
};

extern const ParamTable kBudgetParams;
extern const ParamTable kCheckpointParams;

// "budget" of the run config: its seconds, or none. InputError naming the key otherwise.
std::optional<double> readBudgetSeconds(Params& runConfig);
// "checkpoints" of the run config, frames within 1..`frames`.
Checkpoints readCheckpoints(Params& runConfig, int frames);

// One rendered frame as the checkpoints see it.
struct FrameSample {
    int frame;
    double cumulativeSeconds;
    Json error;  // frame_loop's error record, or null when not measured
};

// {"frames": [{"at": n, "frame": i, "cumulative_seconds": t, "error": {...}}, ...], "seconds": [...]}:
// per checkpoint the frame it falls on, or "frame": null (and no time or error) when the run
// stopped before it (for seconds: when its frames' render time ends before the checkpoint). `samples` in frame order.
Json checkpointRecords(const Checkpoints& checkpoints, const std::vector<FrameSample>& samples);

}  // namespace gibench
