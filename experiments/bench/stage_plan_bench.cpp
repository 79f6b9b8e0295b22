// The time pruning saves (StagePlan, core/render/stage_plan.h): every method renders frames of the
// built-in Cornell box with its stages pruned and with every stage run, in the same process; the
// registry's `main` prints the ratio (images are the same bit for bit: stage_plan_test.cpp).
//   pruning/<on|off>/<method>: frames of 128² after 4 warm-up frames

#include "core/scene/scene_loader.h"
#include "methods/registry.h"

#include <benchmark/benchmark.h>

#include <memory>
#include <string>

namespace gibench {
namespace {

constexpr int kSize = 128;

void prunedFrames(benchmark::State& state, const std::string& method, bool prune) {
    Scene loaded = loadSceneFile(std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json");
    const CameraDesc camera = *loaded.camera;
    const PreparedScene scene(std::move(loaded), prune);
    const CameraPose pose = camera.poseAt(0.0f).relativeTo(scene.scene.worldOrigin);
    const MethodInfo* info = findMethod(method);
    Params params(Json::object(), "bench", "/method", method, &info->parameters);
    std::unique_ptr<Method> m = info->create(params);
    RunNotes notes;
    m->prepare(scene, kSize, kSize, notes);
    int frame = 0;
    auto render = [&] {
        StageTimer timer;
        LayeredImage image(kSize, kSize);
        m->renderFrame({scene, pose, kSize, kSize, frame, 1 << 30, false, 1, timer, false}, image);
        ++frame;
    };
    while (frame < 4) render();
    for (auto _ : state) render();
    state.counters["frames_per_s"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
}

const bool kRegistered = [] {
    for (const std::string& method : methodNames())
        for (const bool prune : {true, false})
            benchmark::RegisterBenchmark(("pruning/" + std::string(prune ? "on/" : "off/") + method).c_str(),
                                         [method, prune](benchmark::State& s) { prunedFrames(s, method, prune); })
                ->Unit(benchmark::kMillisecond)
                ->MinTime(1.0)
                ->UseRealTime();
    return true;
}();

}  // namespace
}  // namespace gibench
