#pragma once
// A scene with what every renderer builds from it once per run: the BVH, the packed triangles
// surface points are made from, the light sampler, and the stages the scene needs.

#include "core/render/light_sampler.h"
#include "core/render/ray_tracer.h"
#include "core/render/shading_triangles.h"
#include "core/render/stage_plan.h"
#include "core/render/surface.h"
#include "core/scene/scene.h"

namespace gibench {

struct PreparedScene {
    // `pruneStages` false: every optional stage runs (StagePlan), for checking that pruning changes nothing.
    explicit PreparedScene(Scene s, bool pruneStages = true)
        : scene(std::move(s)), tracer(scene), triangles(scene), lights(scene), plan(StagePlan::forScene(scene, pruneStages)) {}
    PreparedScene(const PreparedScene&) = delete;
    PreparedScene& operator=(const PreparedScene&) = delete;

    const Scene scene;  // declared first: the members below refer to it
    const RayTracer tracer;
    const ShadingTriangles triangles;  // for surfaceAt(ps.triangles, …), the fast way to a SurfacePoint
    const LightSampler lights;
    const StagePlan plan;
};

// Diffuse reflectance at the point, reading texels only where the plan keeps texture lookups.
inline Color albedoAt(const PreparedScene& ps, const SurfacePoint& p) {
    return ps.plan.textureLookups ? albedoAt(ps.scene, p) : p.material->albedo;
}

}  // namespace gibench
