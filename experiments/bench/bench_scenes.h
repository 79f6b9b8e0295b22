#pragma once
// The built-in scenes the benchmarks share (configs/scenes/<name>.json), each loaded and prepared
// once per process, with the camera its file suggests.

#include "core/render/prepared_scene.h"
#include "core/scene/camera.h"

#include <benchmark/benchmark.h>

#include <memory>
#include <string>

namespace gibench {

struct BenchScene {
    std::unique_ptr<PreparedScene> scene;
    CameraDesc camera;

    // The first keyframe, where the renderers see it.
    CameraPose pose() const { return camera.keyframes.front().pose.relativeTo(scene->scene.worldOrigin); }
};

// The scene, or null after marking the benchmark skipped with the reason when its files are
// missing (third-party scenes outside this machine: experiments/fetch_scenes.sh).
const BenchScene* benchSceneOrSkip(benchmark::State& state, const std::string& name);

}  // namespace gibench
