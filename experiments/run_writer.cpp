#include "experiments/run_writer.h"

#include "core/util/hash.h"
#include "experiments/json_output.h"
#include "experiments/manifest.h"
#include "experiments/output_dir.h"
#include "experiments/run_id.h"

namespace gibench {
namespace {

// The scene entries that need the prepared scene; the files are in manifestBeforeFrames().
void addLightSummary(Json& summary, const PreparedScene& scene) {
    summary["emissive_triangles"] = scene.lights.emissiveTriangleCount();
    summary["suns"] = scene.lights.sunCount();
    summary["environment"] = scene.lights.hasEnvironment();
}

}  // namespace

Json manifestBeforeFrames(const RunConfig& config, const RunRecord& record) {
    Json files = Json::array();
    for (const SceneFile& f : config.scene->files) files.push_back({{"path", f.path}, {"sha256", f.sha256}});
    const Bounds3 bounds = config.scene->bounds();
    const glm::dvec3 origin = config.scene->worldOrigin;
    const glm::dvec3 low = glm::dvec3(bounds.min) + origin, high = glm::dvec3(bounds.max) + origin;
    const Json manifest = {
        {"gibench", gitInfo()},
        {"config_file", config.file.string()},
        {"config_sha256", sha256File(config.file)},
        {"config", config.resolved},
        {"config_overrides", config.overrides},
        {"scene",
         {{"files", files},
          {"triangles", config.scene->triangleCount()},
          // In the scene file's coordinates; the renderers work relative to world_origin.
          {"bounds", {{low.x, low.y, low.z}, {high.x, high.y, high.z}}},
          {"world_origin", {origin.x, origin.y, origin.z}}}},
        {"seed", config.seed},
        {"threads", record.threads},
        {"machine", machineInfo()},
        {"started", record.started},
        {"reference", record.reference},
    };
    requireUtf8(manifest, config.file.string(), "the manifest");
    return manifest;
}

std::vector<ExrAttribute> runExrAttributes(const RunConfig& config, const std::string& commit, int frames) {
    std::vector<ExrAttribute> attributes = {{"gibench:method", config.methodName}, {"gibench:frames", frames}};
    if (config.methodResolved.contains("spp") && config.methodResolved["spp"].is_number_integer())
        attributes.push_back({"gibench:spp", config.methodResolved["spp"].get<int>()});
    attributes.push_back({"gibench:seed", std::to_string(config.seed)});
    attributes.push_back({"gibench:commit", commit});
    attributes.push_back({"gibench:run_id", runId(config)});
    return attributes;
}

Json writeRunFiles(const std::filesystem::path& dir, const RunConfig& config, const PreparedScene& scene, const RunRecord& record,
                   const FrameLoopResult& frames) {
    writeExr(dir / "image.exr", frames.image, runExrAttributes(config, record.manifest.at("gibench").at("commit").get<std::string>(), frames.frames));
    if (config.png) writePng(dir / "image.png", frames.image.find("total")->image);

    Json metrics = {{"frames", frames.frames},
                    {"stopped_by", frames.stoppedByBudget ? "budget" : "frames"},
                    {"seconds", frames.frameSeconds},
                    {"reference", record.reference},
                    {"reference_noise", record.referenceNoise},
                    {"error", frames.lastError},
                    {"checkpoints", frames.checkpoints}};
    if (!config.events.empty()) metrics["events"] = frames.events;
    writeFileAtomically(dir / "metrics.json", dumpFinite(metrics, 2) + "\n");

    Json stages = Json::object();
    for (const auto& [name, seconds] : frames.stageSeconds) stages[name] = seconds;
    Json manifest = record.manifest;
    addLightSummary(manifest["scene"], scene);
    manifest["finished"] = utcNow();
    manifest["timings"] = {{"load_scene_seconds", config.sceneLoadSeconds},
                           {"build_bvh_and_lights_seconds", record.prepareSceneSeconds},
                           {"method_prepare_seconds", record.prepareMethodSeconds},
                           {"frames_seconds", frames.frameSeconds},
                           {"evaluation_seconds", frames.evaluationSeconds},
                           {"stages_seconds", stages}};
    // What ran and what was left out: the scene's stages (StagePlan), then the method's own.
    Json plan = scene.plan.manifest();
    for (const Json& note : record.notes.skipped) plan["left_out"].push_back(note);
    manifest["stages"] = plan;
    writeFileAtomically(dir / "manifest.json", dumpFinite(manifest, 2) + "\n");
    return metrics;
}

}  // namespace gibench
