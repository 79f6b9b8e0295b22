#include "experiments/bench/bench_scenes.h"

#include "core/scene/scene_loader.h"
#include "core/util/error.h"

#include <map>
#include <mutex>

namespace gibench {

const BenchScene* benchSceneOrSkip(benchmark::State& state, const std::string& name) {
    static std::map<std::string, BenchScene> scenes;
    static std::mutex mutex;
    const std::lock_guard<std::mutex> lock(mutex);
    auto it = scenes.find(name);
    if (it != scenes.end()) return &it->second;
    try {
        Scene scene = loadSceneFile(std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/" + name + ".json");
        BenchScene b;
        b.camera = *scene.camera;
        b.scene = std::make_unique<PreparedScene>(std::move(scene));
        return &scenes.emplace(name, std::move(b)).first->second;
    } catch (const InputError& e) {
        state.SkipWithError(e.what());
        return nullptr;
    }
}

}  // namespace gibench
