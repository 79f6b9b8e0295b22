#include "experiments/run.h"

#include "core/image/metrics.h"
#include "core/util/error.h"
#include "core/util/hash.h"
#include "experiments/manifest.h"
#include "experiments/output_dir.h"
#include "experiments/reference.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>

namespace gibench {
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

bool samePose(const CameraPose& a, const CameraPose& b) {
    return a.eye == b.eye && a.target == b.target && a.up == b.up && a.vfovDeg == b.vfovDeg;
}

// Error of the frame's layer against the reference's, or null when either lacks the layer.
Json layerError(const LayeredImage& frame, const LayeredImage& reference, const std::string& layer) {
    const Layer* a = frame.find(layer);
    const Layer* b = reference.find(layer);
    if (!a || !b) return nullptr;
    return toJson(computeMetrics(a->image, b->image));
}

std::string frameName(int frame) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.exr", frame);
    return name;
}

}  // namespace

RunResult executeRun(RunConfig& config, bool showProgress) {
    const std::string started = utcNow();
    const int threads = config.threads > 0 ? config.threads : tbb::info::default_concurrency();
    tbb::global_control threadLimit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));

    // The reference is checked before any work so a size mismatch fails fast.
    std::optional<LayeredImage> reference = loadReference(config);
    Json referenceInfo = nullptr;
    if (config.reference.kind != ReferenceSpec::Kind::None) {
        referenceInfo = {{"image", referencePath(config).string()}, {"found", reference.has_value()}};
        if (config.reference.kind == ReferenceSpec::Kind::Rendered) referenceInfo["key"] = referenceKey(config);
        if (!reference)
            std::fprintf(stderr, "note: no reference image yet; `gibench reference %s` renders it\n", config.file.string().c_str());
        else if (reference->width != config.camera.width || reference->height != config.camera.height)
            throw InputError(referencePath(config).string() + ": reference is " + std::to_string(reference->width) + "x" +
                             std::to_string(reference->height) + ", the run renders " + std::to_string(config.camera.width) + "x" +
                             std::to_string(config.camera.height));
    }
    const CameraPose measuredPose = referencePose(config.camera);

    StagingDir staging(config.outputRoot / config.experiment / config.run);
    const std::filesystem::path dir = staging.path();

    auto start = std::chrono::steady_clock::now();
    const PreparedScene scene(*config.scene);
    const double prepareSeconds = secondsSince(start);
    RunNotes notes;
    start = std::chrono::steady_clock::now();
    config.method->prepare(scene, config.camera.width, config.camera.height, notes);
    const double methodPrepareSeconds = secondsSince(start);

    std::ofstream frames(dir / "frames.jsonl");
    std::map<std::string, double> stageTotals;
    double cumulative = 0.0, evaluation = 0.0;
    Json lastError = nullptr;
    LayeredImage image;
    CameraPose previous = config.camera.poseAt(0.0f);
    for (int f = 0; f < config.frames; ++f) {
        const CameraPose pose = config.camera.poseAt(float(f));
        StageTimer timer;
        image = LayeredImage(config.camera.width, config.camera.height);
        const FrameContext context{scene, pose, config.camera.width, config.camera.height, f, config.frames,
                                   f > 0 && !samePose(pose, previous), config.seed, timer, showProgress};
        start = std::chrono::steady_clock::now();
        config.method->renderFrame(context, image);
        const double frameSeconds = secondsSince(start);
        cumulative += frameSeconds;
        previous = pose;

        Json record = {{"frame", f}, {"seconds", frameSeconds}, {"cumulative_seconds", cumulative}};
        Json stages = Json::object();
        for (const auto& [name, seconds] : timer.stages()) {
            stages[name] = seconds;
            stageTotals[name] += seconds;
        }
        record["stages"] = stages;
        record["stats"] = config.method->frameStats();
        start = std::chrono::steady_clock::now();
        if (reference && samePose(pose, measuredPose)) {
            lastError = {{"total", layerError(image, *reference, "total")}, {"indirect", layerError(image, *reference, "indirect")}};
            record["error"] = lastError;
        }
        if (config.imageEvery > 0 && (f + 1) % config.imageEvery == 0) writeExr(dir / frameName(f), image);
        evaluation += secondsSince(start);
        frames << record.dump() << "\n";
    }
    frames.close();
    if (!frames) throw std::runtime_error((dir / "frames.jsonl").string() + ": cannot write");

    writeExr(dir / "image.exr", image);
    if (config.png) writePng(dir / "image.png", image.find("total")->image);

    Json metrics = {{"frames", config.frames}, {"seconds", cumulative}, {"reference", referenceInfo}, {"error", lastError}};
    writeFileAtomically(dir / "metrics.json", metrics.dump(2) + "\n");

    Json stages = Json::object();
    for (const auto& [name, seconds] : stageTotals) stages[name] = seconds;
    Json files = Json::array();
    for (const SceneFile& f : config.scene->files) files.push_back({{"path", f.path}, {"sha256", f.sha256}});
    const Bounds3 bounds = config.scene->bounds();
    Json manifest = {
        {"gibench", gitInfo()},
        {"config_file", config.file.string()},
        {"config_sha256", sha256File(config.file)},
        {"config", config.resolved},
        {"scene",
         {{"files", files},
          {"triangles", config.scene->triangleCount()},
          {"bounds", {{bounds.min.x, bounds.min.y, bounds.min.z}, {bounds.max.x, bounds.max.y, bounds.max.z}}},
          {"emissive_triangles", scene.lights.emissiveTriangleCount()},
          {"suns", scene.lights.sunCount()},
          {"environment", scene.lights.hasEnvironment()}}},
        {"seed", config.seed},
        {"threads", threads},
        {"machine", machineInfo()},
        {"started", started},
        {"finished", utcNow()},
        {"timings",
         {{"load_scene_seconds", config.sceneLoadSeconds},
          {"build_bvh_and_lights_seconds", prepareSeconds},
          {"method_prepare_seconds", methodPrepareSeconds},
          {"frames_seconds", cumulative},
          {"evaluation_seconds", evaluation},
          {"stages_seconds", stages}}},
        {"skipped", notes.skipped},
        {"reference", referenceInfo},
    };
    writeFileAtomically(dir / "manifest.json", manifest.dump(2) + "\n");

    staging.commit();
    return {config.outputRoot / config.experiment / config.run, metrics};
}

}  // namespace gibench
