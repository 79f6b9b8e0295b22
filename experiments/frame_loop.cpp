#include "experiments/frame_loop.h"

#include "core/image/finite_values.h"
#include "core/image/metrics.h"
#include "core/util/progress.h"
#include "core/util/text_format.h"
#include "experiments/json_output.h"
#include "experiments/event_recovery.h"
#include "experiments/reference.h"
#include "experiments/run_writer.h"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <stdexcept>

namespace gibench {
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Error of every measured layer of the reference (isMeasured()) against the frame's layer of that
// name. "total" and "indirect" are always named (null when not measured), so that
// error-against-time tables find them. The reference is checked finite when loaded; a non-finite
// value in the frame is the method's defect, reported as such rather than as a metric.
Json frameError(const LayeredImage& frame, const LayeredImage& reference, const RunConfig& config, int frameIndex) {
    Json error = {{"total", nullptr}, {"indirect", nullptr}};
    for (const Layer& r : reference.layers) {
        const Layer* f = frame.find(r.name);
        if (!f || !isMeasured(r) || f->image.channels < 3) continue;
        const NonfiniteValues bad = findNonfinite(f->image, 3);
        if (bad.count > 0)
            throw std::runtime_error("method \"" + config.methodName + "\" rendered " + std::to_string(bad.count) +
                                     " non-finite values in frame " + std::to_string(frameIndex) + ", the first " +
                                     formatNumber(bad.value) + " in channel " + fileChannelName(*f, bad.channel) + " at pixel (" +
                                     std::to_string(bad.x) + ", " + std::to_string(bad.y) + ")");
        error[r.name] = toJson(computeMetrics(f->image, r.image));
    }
    return error;
}

std::string frameName(int frame) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.exr", frame);
    return name;
}

}  // namespace

FrameLoopResult renderFrames(RunConfig& config, const PreparedScene& loaded, const std::vector<const LayeredImage*>& references,
                             const std::filesystem::path& dir, const std::string& commit, bool showProgress) {
    FrameLoopResult result;
    const WorldPose measuredPose = referencePose(config.camera);
    const std::vector<int> segments = segmentStarts(config.events);
    std::ofstream frames(dir / "frames.jsonl");
    std::vector<Json> records;
    WorldPose previous = config.camera.poseAt(0.0f);
    std::unique_ptr<PreparedScene> changed;  // the scene of the current segment, after the first
    std::size_t segment = 0;
    std::vector<FrameSample> samples;
    // A run of many frames shows its frames; a single frame (a path-traced image) its own progress.
    Progress progress(config.experiment + "/" + config.run + ": frames", uint64_t(config.frames), showProgress && config.frames > 1);
    const bool methodShowsProgress = showProgress && config.frames == 1;
    result.image = LayeredImage(config.camera.width, config.camera.height);
    for (int f = 0; f < config.frames; ++f) {
        if (config.budgetSeconds && result.frameSeconds >= *config.budgetSeconds) {
            result.stoppedByBudget = true;
            break;
        }
        const bool sceneChanged = segment + 1 < segments.size() && f == segments[segment + 1];
        double sceneChangeSeconds = 0.0;
        if (sceneChanged) {
            ++segment;
            const auto start = std::chrono::steady_clock::now();
            changed = std::make_unique<PreparedScene>(sceneOfSegment(*config.scene, config.events, f), config.pruneStages);
            sceneChangeSeconds = secondsSince(start);
        }
        const PreparedScene& scene = changed ? *changed : loaded;
        const LayeredImage* reference = segment < references.size() ? references[segment] : nullptr;
        const WorldPose pose = config.camera.poseAt(float(f));
        StageTimer timer;
        result.image.clearLayersKeepingMemory();
        const FrameContext context{scene, pose.relativeTo(scene.scene.worldOrigin), config.camera.width, config.camera.height, f, config.frames,
                                   f > 0 && pose != previous, config.seed, timer, methodShowsProgress, sceneChanged};
        auto start = std::chrono::steady_clock::now();
        config.method->renderFrame(context, result.image);
        const double frameSeconds = secondsSince(start);
        result.frameSeconds += frameSeconds;
        previous = pose;

        Json record = {{"frame", f}, {"seconds", frameSeconds}, {"cumulative_seconds", result.frameSeconds}};
        if (sceneChanged) {
            Json now = Json::array();
            for (const SceneEvent& e : config.events)
                if (e.frame == f) now.push_back(e.resolved);
            record["scene_changed"] = {{"events", now}, {"prepare_seconds", sceneChangeSeconds}};
        }
        Json stages = Json::object();
        for (const auto& [name, seconds] : timer.stages()) {
            stages[name] = seconds;
            result.stageSeconds[name] += seconds;
        }
        record["stages"] = stages;
        record["stats"] = config.method->frameStats();
        start = std::chrono::steady_clock::now();
        if (reference && pose == measuredPose) {
            result.lastError = frameError(result.image, *reference, config, f);
            record["error"] = result.lastError;
        }
        samples.push_back({f, result.frameSeconds, record.contains("error") ? record["error"] : Json()});
        result.frames = f + 1;
        if (config.imageEvery > 0 && (f + 1) % config.imageEvery == 0) writeExr(dir / frameName(f), result.image, runExrAttributes(config, commit, f + 1));
        result.evaluationSeconds += secondsSince(start);
        frames << dumpFinite(record) << "\n";
        if (!config.events.empty()) records.push_back(std::move(record));
        progress.advance();
    }
    progress.finish();
    frames.close();
    result.checkpoints = checkpointRecords(config.checkpoints, samples);
    if (!config.events.empty()) result.events = eventRecovery(config.events, records);
    if (!frames) throw std::runtime_error((dir / "frames.jsonl").string() + ": cannot write");
    return result;
}

}  // namespace gibench
