#include "experiments/run_writer.h"

#include "core/util/hash.h"
#include "experiments/manifest.h"
#include "experiments/output_dir.h"

namespace gibench {
namespace {

Json sceneSummary(const RunConfig& config, const PreparedScene& scene) {
    Json files = Json::array();
    for (const SceneFile& f : config.scene->files) files.push_back({{"path", f.path}, {"sha256", f.sha256}});
    const Bounds3 bounds = config.scene->bounds();
    return {{"files", files},
            {"triangles", config.scene->triangleCount()},
            {"bounds", {{bounds.min.x, bounds.min.y, bounds.min.z}, {bounds.max.x, bounds.max.y, bounds.max.z}}},
            {"emissive_triangles", scene.lights.emissiveTriangleCount()},
            {"suns", scene.lights.sunCount()},
            {"environment", scene.lights.hasEnvironment()}};
}

}  // namespace

Json writeRunFiles(const std::filesystem::path& dir, const RunConfig& config, const PreparedScene& scene, const RunRecord& record,
                   const FrameLoopResult& frames) {
    writeExr(dir / "image.exr", frames.image);
    if (config.png) writePng(dir / "image.png", frames.image.find("total")->image);

    const Json metrics = {{"frames", config.frames}, {"seconds", frames.frameSeconds}, {"reference", record.reference}, {"error", frames.lastError}};
    writeFileAtomically(dir / "metrics.json", metrics.dump(2) + "\n");

    Json stages = Json::object();
    for (const auto& [name, seconds] : frames.stageSeconds) stages[name] = seconds;
    const Json manifest = {
        {"gibench", gitInfo()},
        {"config_file", config.file.string()},
        {"config_sha256", sha256File(config.file)},
        {"config", config.resolved},
        {"scene", sceneSummary(config, scene)},
        {"seed", config.seed},
        {"threads", record.threads},
        {"machine", machineInfo()},
        {"started", record.started},
        {"finished", utcNow()},
        {"timings",
         {{"load_scene_seconds", config.sceneLoadSeconds},
          {"build_bvh_and_lights_seconds", record.prepareSceneSeconds},
          {"method_prepare_seconds", record.prepareMethodSeconds},
          {"frames_seconds", frames.frameSeconds},
          {"evaluation_seconds", frames.evaluationSeconds},
          {"stages_seconds", stages}}},
        {"skipped", record.notes.skipped},
        {"reference", record.reference},
    };
    writeFileAtomically(dir / "manifest.json", manifest.dump(2) + "\n");
    return metrics;
}

}  // namespace gibench
