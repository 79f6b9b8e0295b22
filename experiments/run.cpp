#include "experiments/run.h"

#include "core/util/error.h"
#include "core/util/hash.h"
#include "experiments/frame_loop.h"
#include "experiments/manifest.h"
#include "experiments/output_dir.h"
#include "experiments/reference.h"
#include "experiments/reference_noise.h"
#include "experiments/run_id.h"
#include "experiments/run_writer.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <cstdio>
#include <optional>

namespace gibench {
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The reference of the segment starting at `segment`, checked before any work so that a missing
// or mismatched one shows at once; `info` says where it is and whether it was found.
std::optional<LayeredImage> checkedReference(const RunConfig& config, int segment, Json& info) {
    std::optional<LayeredImage> reference = loadReference(config, segment);
    info = nullptr;
    if (config.reference.kind == ReferenceSpec::Kind::None) return reference;
    const std::filesystem::path image = referencePath(config, segment);
    info = {{"image", image.string()}, {"found", reference.has_value()}};
    if (reference) info["sha256"] = sha256File(image);
    if (config.reference.kind == ReferenceSpec::Kind::Rendered) info["key"] = referenceKey(config, segment);
    if (!reference)
        std::fprintf(stderr, "note: no reference image yet%s; `gibench reference %s` renders it\n",
                     segment > 0 ? (" for the frames from " + std::to_string(segment) + " on").c_str() : "", config.file.string().c_str());
    else if (reference->width != config.camera.width || reference->height != config.camera.height)
        throw InputError(image.string() + ": reference is " + std::to_string(reference->width) + "x" + std::to_string(reference->height) +
                         ", the run renders " + std::to_string(config.camera.width) + "x" + std::to_string(config.camera.height));
    return reference;
}

}  // namespace

RunResult executeRun(RunConfig& config, bool showProgress) {
    RunRecord record;
    record.started = utcNow();
    record.threads = config.threads > 0 ? config.threads : tbb::info::default_concurrency();
    tbb::global_control threadLimit(tbb::global_control::max_allowed_parallelism, std::size_t(record.threads));
    // One reference per segment of a scene that changes (scene_events.h); the manifest's
    // "reference" is the first segment's, with every segment's under "segments".
    std::vector<std::optional<LayeredImage>> references;
    Json segments = Json::array();
    for (const int segment : segmentStarts(config.events)) {
        Json info;
        references.push_back(checkedReference(config, segment, info));
        if (segment == 0) record.reference = info;
        if (!config.events.empty() && !info.is_null()) {
            info["first_frame"] = segment;
            segments.push_back(info);
        }
    }
    if (!segments.empty()) record.reference["segments"] = segments;
    std::vector<const LayeredImage*> referenceImages;
    for (const std::optional<LayeredImage>& r : references) referenceImages.push_back(r ? &*r : nullptr);
    if (!references.empty() && references.front()) record.referenceNoise = referenceNoise(*references.front());
    record.manifest = manifestBeforeFrames(config, record);
    record.manifest["run_id"] = runId(config);
    if (!config.sweep.is_null()) record.manifest["sweep"] = config.sweep;

    StagingDir staging(config.outputRoot / config.experiment / config.run);
    auto start = std::chrono::steady_clock::now();
    const PreparedScene scene(*config.scene, config.pruneStages);
    record.prepareSceneSeconds = secondsSince(start);
    start = std::chrono::steady_clock::now();
    config.method->prepare(scene, config.camera.width, config.camera.height, record.notes);
    record.prepareMethodSeconds = secondsSince(start);

    const FrameLoopResult frames = renderFrames(config, scene, referenceImages, staging.path(), record.manifest["gibench"]["commit"].get<std::string>(), showProgress);
    const Json metrics = writeRunFiles(staging.path(), config, scene, record, frames);
    staging.commit();
    return {config.outputRoot / config.experiment / config.run, metrics};
}

}  // namespace gibench
