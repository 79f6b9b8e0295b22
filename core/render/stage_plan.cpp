#include "core/render/stage_plan.h"

#include <algorithm>

namespace gibench {

StagePlan StagePlan::forScene(const Scene& scene, bool prune) {
    StagePlan plan;
    plan.pruning = prune;
    bool emitters = !scene.suns.empty() || scene.environment.has_value();
    for (const Mesh& mesh : scene.meshes)
        for (uint32_t m : mesh.materials) emitters = emitters || scene.materials[m].isEmissive();
    const bool textures =
        std::any_of(scene.materials.begin(), scene.materials.end(), [](const Material& m) { return m.albedoTexture >= 0; });
    auto decide = [&](bool& flag, const std::string& stage, bool needed, const std::string& reason) {
        flag = needed || !prune;
        plan.decisions.push_back({stage, flag, flag ? std::string() : reason});
    };
    decide(plan.nextEventEstimation, "next_event_estimation", emitters,
           "the scene has no emitting triangle, sun or environment: light sampling at each vertex would find nothing");
    decide(plan.environmentLookup, "environment_lookup", scene.environment.has_value(),
           "the scene has no environment: escaped rays carry no light");
    decide(plan.textureLookups, "texture_lookups", textures, "no material has an albedo texture");
    // Not a switch: a material without a microfacet lobe has none to evaluate, pruning or not (a
    // Bsdf takes the Lambertian path by itself); listed so that the manifest says which BSDF ran.
    const bool glossy =
        std::any_of(scene.materials.begin(), scene.materials.end(), [](const Material& m) { return m.type == MaterialType::Glossy; });
    plan.decisions.push_back(
        {"glossy_lobes", glossy, glossy ? std::string() : "every material is Lambertian: each BSDF evaluates and samples its diffuse lobe only"});
    return plan;
}

Json StagePlan::manifest() const {
    Json ran = Json::array(), leftOut = Json::array();
    for (const Decision& d : decisions)
        if (d.runs)
            ran.push_back(d.stage);
        else
            leftOut.push_back({{"stage", d.stage}, {"reason", d.reason}});
    return {{"pruning", pruning}, {"ran", ran}, {"left_out", leftOut}};
}

}  // namespace gibench
