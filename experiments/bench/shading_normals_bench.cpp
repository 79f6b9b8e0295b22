// Benchmark of the shading-normal convention (README, "Ground truth conventions") on Sponza, whose
// OBJ has vertex normals: `path_traced` renders the default view at its full 384×256 with the
// vertex normals and with `"normals": false` (geometric normals), same seed and spp, and prints
// how many pixels the shading normals leave below 0.1× the geometric-normal render (the measure of
// a black hole: before the convention, 2.75 % of the lit pixels, 2.5 % exactly black) and the
// ratio of the two image means (the change in brightness the normals make).
// Sponza reads ${GIBENCH_SCENES} and is skipped with the reason when its files are missing.

#include "core/config/params.h"
#include "core/render/prepared_scene.h"
#include "core/scene/scene_loader.h"
#include "core/util/math.h"
#include "core/util/stage_timer.h"
#include "methods/path_traced/path_traced.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

namespace gibench {
namespace {

constexpr int kSpp = 128;
// A pixel counts as lit where the geometric-normal render's luminance exceeds this fraction of
// its image mean: darker pixels are shadowed corners whose 0.1× test would judge noise.
constexpr double kLitFraction = 0.02;

// The `total` layer of Sponza's default view with its vertex normals or without them.
Image renderSponza(bool vertexNormals) {
    const std::filesystem::path file = std::filesystem::path(GIBENCH_SOURCE_DIR) / "configs" / "scenes" / "sponza.json";
    Json json = loadJsonFile(file);
    json["shapes"][0]["normals"] = vertexNormals;
    Params block(json, file.string(), "", "scene", nullptr);
    const PreparedScene scene(loadScene(block));
    const CameraDesc& camera = *scene.scene.camera;
    Params params(Json{{"spp", kSpp}}, "bench", "", "bench", &pathTracedParams());
    std::unique_ptr<Method> method = createPathTraced(params);
    RunNotes notes;
    method->prepare(scene, camera.width, camera.height, notes);
    StageTimer timer;
    LayeredImage image(camera.width, camera.height);
    method->renderFrame({scene, camera.keyframes.front().pose.relativeTo(scene.scene.worldOrigin), camera.width, camera.height, 0, 1, false, 1,
                         timer, false},
                        image);
    return image.find("total")->image;
}

double luminanceAt(const Image& image, int x, int y) { return luminance(Color(image.at(x, y, 0), image.at(x, y, 1), image.at(x, y, 2))); }

void sponzaShadingNormals(benchmark::State& state) {
    if (!std::filesystem::exists(scenesDirectory() / "sponza-dabrovic" / "sponza.obj")) {
        state.SkipWithError(("Sponza not found in " + scenesDirectory().string() + " (set GIBENCH_SCENES)").c_str());
        return;
    }
    Image shading(0, 0, 3), geometric(0, 0, 3);
    for (auto _ : state) {
        shading = renderSponza(true);
        geometric = renderSponza(false);
    }
    double sumShading = 0.0, sumGeometric = 0.0;
    for (int y = 0; y < geometric.height; ++y)
        for (int x = 0; x < geometric.width; ++x) {
            sumShading += luminanceAt(shading, x, y);
            sumGeometric += luminanceAt(geometric, x, y);
        }
    const double pixels = double(geometric.width) * geometric.height;
    const double litThreshold = kLitFraction * sumGeometric / pixels;
    int lit = 0, belowTenth = 0, black = 0;
    for (int y = 0; y < geometric.height; ++y)
        for (int x = 0; x < geometric.width; ++x) {
            const double g = luminanceAt(geometric, x, y), s = luminanceAt(shading, x, y);
            if (g <= litThreshold) continue;
            ++lit;
            belowTenth += s < 0.1 * g ? 1 : 0;
            black += s == 0.0 ? 1 : 0;
        }
    const double meanRatio = sumShading / sumGeometric;
    state.counters["lit_pixels"] = lit;
    state.counters["below_tenth"] = belowTenth;
    state.counters["black"] = black;
    state.counters["mean_ratio"] = meanRatio;
    std::printf("sponza %dx%d %d spp, vertex normals against geometric normals: %d of %d lit pixels below 0.1x (%.3f %%), %d black; "
                "image mean %.4fx\n",
                geometric.width, geometric.height, kSpp, belowTenth, lit, 100.0 * belowTenth / std::max(lit, 1), black, meanRatio);
}

const bool kRegistered = [] {
    benchmark::RegisterBenchmark("shading_normals/sponza", sponzaShadingNormals)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
    return true;
}();

}  // namespace
}  // namespace gibench
