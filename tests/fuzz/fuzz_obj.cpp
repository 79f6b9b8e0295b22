// Fuzz target: the input is an OBJ file and an MTL file, split at the first line reading exactly
// kMtlMarker (no marker: an OBJ alone). Both are written beside each other as model.obj and
// model.mtl (an OBJ uses the MTL with "mtllib model.mtl"), loaded as the scene
// {"shapes": [{"type": "obj", "file": "model.obj"}]}, and prepared (Embree BVH, light sampler).

#include "core/render/prepared_scene.h"
#include "core/scene/scene_loader.h"
#include "finite_scene.h"
#include "private_folder.h"

#include <algorithm>
#include <cstdint>
#include <string_view>

namespace {

// A comment line in OBJ syntax, so that the OBJ half is an OBJ file as it stands.
constexpr std::string_view kMtlMarker = "#--- model.mtl";

const gibench::PrivateFolder& folder() {
    static const gibench::PrivateFolder instance("fuzz_obj");
    return instance;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace gibench;
    folder().empty();
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    std::string_view obj = input, mtl;
    for (std::size_t line = 0; line < input.size();) {
        const std::size_t end = std::min(input.find('\n', line), input.size());
        if (input.substr(line, end - line) == kMtlMarker) {
            obj = input.substr(0, line);
            mtl = input.substr(std::min(end + 1, input.size()));
            break;
        }
        line = end + 1;
    }
    folder().write("model.obj", obj);
    if (!mtl.empty()) folder().write("model.mtl", mtl);

    // scene.json is never written: it only makes relative paths resolve in the private folder.
    Params block(Json::parse(R"({"shapes": [{"type": "obj", "file": "model.obj"}]})"), (folder().path() / "scene.json").string(), "", "scene",
                 nullptr);
    Scene scene;
    if (!acceptsOrRejectsCleanly([&] { scene = loadScene(block); })) return 0;
    requireFiniteScene(scene);
    acceptsOrRejectsCleanly([&] { const PreparedScene prepared(std::move(scene)); });
    return 0;
}
