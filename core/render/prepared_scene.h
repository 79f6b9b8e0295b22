#pragma once
// A scene with what every renderer builds from it once per run: the BVH, the packed triangles
// surface points are made from, and the light sampler.

#include "core/render/light_sampler.h"
#include "core/render/ray_tracer.h"
#include "core/render/shading_triangles.h"
#include "core/scene/scene.h"

namespace gibench {

struct PreparedScene {
    explicit PreparedScene(Scene s) : scene(std::move(s)), tracer(scene), triangles(scene), lights(scene) {}
    PreparedScene(const PreparedScene&) = delete;
    PreparedScene& operator=(const PreparedScene&) = delete;

    const Scene scene;  // declared first: the members below refer to it
    const RayTracer tracer;
    const ShadingTriangles triangles;  // for surfaceAt(ps.triangles, …), the fast way to a SurfacePoint
    const LightSampler lights;
};

}  // namespace gibench
