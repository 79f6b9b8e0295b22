#pragma once
// A run config file, read and checked completely before anything is rendered or written: a
// mistake anywhere is an InputError and no output directory is created.
//
// {
//   "experiment": "cornell",                 results/<experiment>/<run>/; both are folder names:
//   "run": "path_traced_16spp",              1 to 200 ASCII letters, digits, '_', '-', '.', no leading '.';
//                                            default: the config file's name without .json
//   "scene": "scenes/cornell_box.json",      a scene file (relative to this config) or an inline scene
//   "camera": { ... },                       keys overriding the scene's camera (core/scene/camera.h)
//   "frames": 1, "seed": 1, "threads": 0,    threads 0 = every core (`--threads` is checked alike)
//   "prune_stages": true,                    false runs every stage the scene has no use for (StagePlan)
//   "events": [ {"frame": 64, "type": "emission", ...} ],  scene changes at given frames (scene_events.h)
//   "budget": {"seconds": 2.0},              stop once the frames' render time reaches it (checkpoints.h)
//   "checkpoints": {"frames": [...], "seconds": [...]},  where metrics.json records the error
//   "method": { "name": "path_traced", ... },  the method and its parameters (`gibench methods`)
//   "reference": { "spp": 4096, ... } or { "file": "ref.exr" },  see reference.h
//   "output": { "root": "results", "image_every": 0, "png": true }   root (or `--results`): a folder
//                                            that exists or can be created, checked up front
// }

#include "core/render/method.h"
#include "core/scene/scene.h"
#include "experiments/checkpoints.h"
#include "experiments/config_overrides.h"
#include "experiments/scene_events.h"

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

namespace gibench {

extern const ParamTable kRunParams;
extern const ParamTable kOutputParams;
extern const ParamTable kReferenceParams;

// How the reference image of a run is obtained.
struct ReferenceSpec {
    enum class Kind { None, External, Rendered } kind = Kind::None;
    std::filesystem::path file;  // External: the image
    int spp = 4096;              // Rendered: path tracer settings
    int maxDepth = 1024;
    int russianRouletteDepth = 3;
    uint64_t seed = 0;
    std::string sampler = "independent";  // path_traced's "sampler"
    Json resolved;
};

struct RunConfig {
    std::filesystem::path file;
    std::string experiment;
    std::string run;
    std::shared_ptr<Scene> scene;
    double sceneLoadSeconds = 0.0;
    CameraDesc camera;
    int frames = 1;                      // the most frames; fewer when the budget runs out
    std::optional<double> budgetSeconds;  // checkpoints.h
    Checkpoints checkpoints;
    uint64_t seed = 1;
    int threads = 0;
    bool pruneStages = true;  // StagePlan (core/render/stage_plan.h)
    std::vector<SceneEvent> events;  // sorted by frame
    std::string methodName;
    std::unique_ptr<Method> method;
    Json methodResolved;
    ReferenceSpec reference;
    std::filesystem::path outputRoot;
    int imageEvery = 0;
    bool png = true;
    Json resolved;  // the whole configuration with every default filled in
    std::vector<std::string> overrides;  // the --set texts applied to the file, in order
    Json sweep;  // {"file", "index", "axes": {key: value}} when a sweep made this run, else null
};

struct RunOverrides {
    std::optional<int> threads;
    std::optional<std::filesystem::path> outputRoot;
    std::vector<ConfigOverride> keys;  // --set, laid over the file before it is read (config_overrides.h)
};

// Whether `c` may appear in an experiment or run name: an ASCII letter or digit, '_', '-', '.'.
bool isNameCharacter(char c);

// `threads` from the command line when it is in the range of the config's "threads" key, else
// InputError naming --threads.
int checkThreadsOption(int threads);

// An InputError about a key that an override set also names the override.
RunConfig loadRunConfig(const std::filesystem::path& file, const RunOverrides& overrides = {});

}  // namespace gibench
