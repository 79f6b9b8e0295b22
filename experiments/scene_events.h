#pragma once
// Scheduled changes of a run's scene (issue 9: lighting and scene changes over frames): a light's
// emission scaled or switched off, a sun turned, a shape moved, each from a given frame on. The
// frames between two changes are a segment; each segment has its own reference (reference.h) and
// every frame is measured against its segment's, so that a cache's recovery after a change is
// measured (event_recovery.h).
//
// "events": [
//   {"frame": 64, "type": "emission", "material": "light", "scale": 0},   emission = scale × as loaded
//   {"frame": 96, "type": "sun", "sun": 0, "direction": [0, -1, 0.2]},    direction of travel; optional "irradiance"
//   {"frame": 128, "type": "move", "shape": "tall_block", "translate": [0, 0, 0.1]}   every mesh of the shape,
//                                                                          by this much from where it was loaded
// ]
//
// A method sees the changed scene from the event's frame on (FrameContext::scene, with
// sceneChanged set on that frame); what it built in prepare() from the first scene (cards captured
// from the meshes, a dense grid over the first bounds) stays as it was, as in an engine that does
// not rebuild its cache on a change.

#include "core/config/params.h"
#include "core/scene/scene.h"

#include <string>
#include <utility>
#include <vector>

namespace gibench {

struct SceneEvent {
    enum class Kind { Emission, Sun, Move };
    int frame = 0;
    Kind kind = Kind::Emission;
    std::size_t material = 0;  // Emission: index into Scene::materials
    float scale = 1.0f;        // Emission
    std::size_t sun = 0;       // Sun: index into Scene::suns
    vec3 direction{0.0f};      // Sun: unit, direction of travel
    std::optional<Color> irradiance;  // Sun: replaces the sun's when given
    std::vector<std::size_t> meshes;  // Move: the shape's meshes
    vec3 translate{0.0f};             // Move
    Json resolved;                    // the event as written, defaults filled in
};

// The keys of each event type besides "type", by type name: the parameter reference lists them.
std::vector<std::pair<std::string, const ParamTable*>> sceneEventTables();

// Reads the run config's "events" (an array) against the loaded scene: names must exist, frames
// lie in [1, frames - 1]. InputError naming the file, the event's pointer and the key otherwise.
// The result is sorted by frame, events of one frame in the order written.
std::vector<SceneEvent> parseSceneEvents(Params& runConfig, const Scene& scene, int frames);

// The first frame of every segment: 0, then each distinct event frame, ascending.
std::vector<int> segmentStarts(const std::vector<SceneEvent>& events);

// The scene of the segment starting at `segmentStart`: `loaded` with every event of a frame up to
// it applied, in order.
Scene sceneOfSegment(const Scene& loaded, const std::vector<SceneEvent>& events, int segmentStart);

// The resolved events applied in that segment (for the manifest).
Json eventsUpTo(const std::vector<SceneEvent>& events, int segmentStart);

// How the segment's scene differs from the scene as loaded, one entry per material, sun and shape
// changed, by its last event (a scale of 1 or a move by 0 is no change): segments showing the same
// scene (a light switched off, then on again) give the same JSON, hence share a reference.
Json changesUpTo(const std::vector<SceneEvent>& events, int segmentStart);

}  // namespace gibench
