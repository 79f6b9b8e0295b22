#pragma once
// A scene with what every renderer builds from it once per run: the BVH and the light sampler.

#include "core/render/light_sampler.h"
#include "core/render/ray_tracer.h"
#include "core/scene/scene.h"

namespace gibench {

struct PreparedScene {
    explicit PreparedScene(Scene s) : scene(std::move(s)), tracer(scene), lights(scene) {}
    PreparedScene(const PreparedScene&) = delete;
    PreparedScene& operator=(const PreparedScene&) = delete;

    const Scene scene;  // declared first: the members below refer to it
    const RayTracer tracer;
    const LightSampler lights;
};

}  // namespace gibench
