// Fuzz target: the input is a run config file (experiments/run_config.h), read as `gibench run`
// reads it. The config may name an inline scene or files beside it in the private folder;
// ${GIBENCH_SCENES} points at that folder too, so no input reaches the large shared scenes.

#include "experiments/run_config.h"
#include "finite_scene.h"
#include "private_folder.h"

#include <cstdint>
#include <cstdlib>
#include <string_view>

namespace {

const gibench::PrivateFolder& folder() {
    static const gibench::PrivateFolder instance("fuzz_config");
    return instance;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    setenv("GIBENCH_SCENES", folder().path().c_str(), 1);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace gibench;
    folder().empty();
    const auto file = folder().write("run.json", std::string_view(reinterpret_cast<const char*>(data), size));
    RunConfig config;
    if (acceptsOrRejectsCleanly([&] { config = loadRunConfig(file); })) {
        requireFiniteScene(*config.scene);
        probeRays(config.camera, config.scene->worldOrigin);
    }
    return 0;
}
