#include "experiments/reference.h"

#include "core/image/finite_values.h"
#include "core/util/error.h"
#include "core/util/hash.h"
#include "experiments/json_output.h"
#include "experiments/manifest.h"
#include "experiments/output_dir.h"
#include "methods/path_traced/path_traced.h"

#include <chrono>

namespace gibench {

// Bump when a change to the renderer changes reference images, so old ones are not reused.
// 2: shadow rays offset both ends, shading normals bent towards the viewer, a sampler choice.
// 3: ray offsets from the error bounds of surface points; scenes rebased on a world origin.
constexpr int kReferenceFormat = 3;

WorldPose referencePose(const CameraDesc& camera) { return camera.keyframes.back().pose; }

static Json poseJson(const WorldPose& p) {
    return {{"eye", {p.eye.x, p.eye.y, p.eye.z}},
            {"target", {p.target.x, p.target.y, p.target.z}},
            {"up", {p.up.x, p.up.y, p.up.z}},
            {"vfov_deg", p.vfovDeg}};
}

static Json keyInputs(const RunConfig& config, int segmentStart) {
    Json files = Json::array();
    for (const SceneFile& f : config.scene->files) files.push_back(f.sha256);
    const ReferenceSpec& r = config.reference;
    Json inputs = {{"format", kReferenceFormat},
            {"scene", config.scene->description},
            {"scene_files_sha256", files},
            {"camera", poseJson(referencePose(config.camera))},
            {"resolution", {config.camera.width, config.camera.height}},
            {"path_tracer", {{"spp", r.spp}, {"max_depth", r.maxDepth}, {"rr_depth", r.russianRouletteDepth}, {"seed", r.seed}, {"sampler", r.sampler}}}};
    // How the events before the segment changed the scene; absent for an unchanged scene, so that
    // references rendered before events existed keep their keys.
    const Json changes = changesUpTo(config.events, segmentStart);
    if (!changes.empty()) inputs["scene_changes"] = changes;
    return inputs;
}

std::string referenceKey(const RunConfig& config, int segmentStart) {
    if (config.reference.kind != ReferenceSpec::Kind::Rendered)
        throw InputError(config.file.string() + ": /reference: expected path tracer settings for a rendered reference");
    return sha256Hex(keyInputs(config, segmentStart).dump());
}

std::filesystem::path referencePath(const RunConfig& config, int segmentStart) {
    if (config.reference.kind == ReferenceSpec::Kind::External) return config.reference.file;
    return config.outputRoot / "references" / (referenceKey(config, segmentStart) + ".exr");
}

ReferenceOutcome ensureReference(const RunConfig& config, bool force, bool showProgress, int segmentStart) {
    ReferenceOutcome outcome;
    outcome.image = referencePath(config, segmentStart);
    if (config.reference.kind == ReferenceSpec::Kind::External) return outcome;
    if (std::filesystem::exists(outcome.image) && !force) return outcome;

    Json record = keyInputs(config, segmentStart);
    record["config_file"] = config.file.string();
    record["gibench"] = gitInfo();
    requireUtf8(record, config.file.string(), "the reference record");

    const auto start = std::chrono::steady_clock::now();
    const ReferenceSpec& spec = config.reference;
    Params params(Json{{"spp", spec.spp}, {"max_depth", spec.maxDepth}, {"rr_depth", spec.russianRouletteDepth}, {"accumulate", false},
                       {"sampler", spec.sampler}},
                  config.file.string(), "/reference", "reference", &pathTracedParams());
    std::unique_ptr<Method> method = createPathTraced(params);
    const PreparedScene scene(config.events.empty() ? *config.scene : sceneOfSegment(*config.scene, config.events, segmentStart));
    RunNotes notes;
    method->prepare(scene, config.camera.width, config.camera.height, notes);
    StageTimer timer;
    LayeredImage image(config.camera.width, config.camera.height);
    method->renderFrame({scene, referencePose(config.camera).relativeTo(scene.scene.worldOrigin), config.camera.width, config.camera.height, 0, 1, false, spec.seed, timer,
                         showProgress},
                        image);
    outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    const std::filesystem::path folder = outcome.image.parent_path();
    std::filesystem::create_directories(folder);
    cleanAbandoned(folder);
    TemporaryFile temporary(outcome.image);
    writeExr(temporary.path(), image,
             {{"gibench:method", "path_traced"},
              {"gibench:frames", 1},
              {"gibench:spp", spec.spp},
              {"gibench:seed", std::to_string(spec.seed)},
              {"gibench:commit", record["gibench"]["commit"].get<std::string>()},
              {"gibench:reference_key", referenceKey(config, segmentStart)}});
    record["seconds"] = outcome.seconds;
    record["stats"] = method->frameStats();
    record["created"] = utcNow();
    std::filesystem::path recordFile = outcome.image;
    writeFileAtomically(recordFile.replace_extension(".json"), dumpFinite(record, 2) + "\n");
    temporary.commit();
    outcome.rendered = true;
    return outcome;
}

bool isMeasured(const Layer& referenceLayer) { return referenceLayer.name != "variance" && referenceLayer.image.channels >= 3; }

std::optional<LayeredImage> loadReference(const RunConfig& config, int segmentStart) {
    if (config.reference.kind == ReferenceSpec::Kind::None) return std::nullopt;
    const std::filesystem::path path = referencePath(config, segmentStart);
    if (!std::filesystem::exists(path)) return std::nullopt;
    LayeredImage image = readLayeredImage(path);
    const Layer* total = image.find("total");
    if (!total || total->image.channels < 3) {
        std::string found;
        for (const Layer& layer : image.layers)
            for (int c = 0; c < layer.image.channels; ++c) found += (found.empty() ? "" : ", ") + fileChannelName(layer, c);
        throw InputError(path.string() + ": expected channels R, G, B (or Y), the radiance runs are measured on, found " +
                         (found.empty() ? "no channels" : found));
    }
    for (const Layer& layer : image.layers)
        if (isMeasured(layer)) requireFinite(path, layer, 3);
    return image;
}

}  // namespace gibench
