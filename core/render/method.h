#pragma once
// The interface every rendering method implements, and its registry row. Methods live in
// methods/<name>/ and are listed in methods/registry.cpp.

#include "core/config/params.h"
#include "core/image/image.h"
#include "core/render/prepared_scene.h"
#include "core/scene/camera.h"
#include "core/util/stage_timer.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace gibench {

// What a run leaves out for a given scene, and why: written to the manifest so a reader sees
// that a stage was not run rather than guessing it ran and cost nothing.
struct RunNotes {
    std::vector<Json> skipped;
    void skip(const std::string& stage, const std::string& reason) { skipped.push_back({{"stage", stage}, {"reason", reason}}); }
};

// Everything a method may use to render one frame.
struct FrameContext {
    const PreparedScene& scene;
    CameraPose pose;
    int width;
    int height;
    int frame;          // 0-based
    int frameCount;
    bool cameraMoved;   // the pose differs from the previous frame's (false on frame 0)
    uint64_t seed;      // the run's seed; derive every random stream from it (core/rng.h)
    StageTimer& timer;  // time each stage of the frame into it
    bool showProgress;  // draw a progress line (core/progress.h) for long frames
    // The scene differs from the previous frame's (a scheduled event, experiments/scene_events.h):
    // what a method averages over frames of one scene starts again; what it caches stays.
    bool sceneChanged = false;
};

// The layers every method writes, added to a frame's image with their channel names, so runs
// and reports find the same layers whatever the method.
struct FrameLayers {
    Image& total;
    Image& direct;
    Image& indirect;
    Image& albedo;
    Image& normal;
    Image& depth;
};

// depth is the distance to the first surface, 0 where a pixel sees none (Mitsuba's convention):
// no output image holds an infinity. The method writes every pixel of every layer
// (LayeredImage::addOverwritten).
inline FrameLayers addFrameLayers(LayeredImage& out) {
    Image& total = out.addOverwritten("total", {"R", "G", "B"});
    Image& direct = out.addOverwritten("direct", {"R", "G", "B"});
    Image& indirect = out.addOverwritten("indirect", {"R", "G", "B"});
    Image& albedo = out.addOverwritten("albedo", {"R", "G", "B"});
    Image& normal = out.addOverwritten("normal", {"X", "Y", "Z"});
    Image& depth = out.addOverwritten("depth", {"Z"});
    return {total, direct, indirect, albedo, normal, depth};
}

class Method {
public:
    virtual ~Method() = default;

    // Once per run, before frame 0. Records in `notes` what this scene lets the method leave out.
    virtual void prepare(const PreparedScene& scene, int width, int height, RunNotes& notes) {}

    // Renders one frame into `out` (already sized): at least layer "total", and "direct" /
    // "indirect" when the method separates them. Frames come in order 0, 1, ...
    virtual void renderFrame(const FrameContext& context, LayeredImage& out) = 0;

    // Counters describing the last frame (rays, probes, bytes, ...) for the per-frame record.
    virtual Json frameStats() const { return Json::object(); }
};

// One row of the registry. `create` is the only code that reads the method's JSON block, and it
// reads it only through `params` with the table `parameters`.
struct MethodInfo {
    std::string name;
    std::string summary;
    ParamTable parameters;
    std::function<std::unique_ptr<Method>(Params& params)> create;
};

}  // namespace gibench
