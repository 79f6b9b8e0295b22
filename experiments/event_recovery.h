#pragma once
// How a run recovers from each change of its scene (scene_events.h): for the segment starting at
// the event's frame e, per measured layer ("total", "indirect"), with relMSE against each
// segment's own reference:
//   before              the error at frame e − 1, the last frame of the scene before;
//   first               the error at frame e, the first frame of the changed scene;
//   recovery_frames     frames rendered from e on until the error is back within 10 % of
//                       `before` (1: frame e already is), null when it never is within the segment;
//   recovery_seconds    the rendering time of those frames;
//   lag_frames          frames until the error has come down halfway from `first` to `before`
//                       (the response's half-life; 1 when `first` is already there);
//   end                 the error at the segment's last frame;
//   mean_ratio_first/_end   the layer's mean over its reference's at those frames: the bias that
//                       relMSE, regularised on dim pixels, understates (null for a black reference).
// Frames without an error (the camera away from the reference's pose) are skipped; an event
// whose frames have none gets nulls.

#include "core/config/params.h"
#include "experiments/scene_events.h"

#include <vector>

namespace gibench {

// `frames`: the run's frame records in order, as written to frames.jsonl ("frame",
// "cumulative_seconds", and "error" where measured).
Json eventRecovery(const std::vector<SceneEvent>& events, const std::vector<Json>& frames);

}  // namespace gibench
