#pragma once
// Small helpers shared by the tests that render: a scene from inline JSON, one frame of a method.

#include "core/scene/scene_loader.h"
#include "core/util/error.h"
#include "methods/registry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

namespace gibench::test {

inline Scene sceneFromJson(const Json& json) {
    Params block(json, "inline-scene.json", "", "scene", nullptr);
    return loadScene(block);
}

// The method `info` describes, built from its JSON block (without "name").
inline std::unique_ptr<Method> createMethod(const MethodInfo& info, const Json& block) {
    Params params(block, "test", "/method", "method", &info.parameters);
    std::unique_ptr<Method> m = info.create(params);
    params.finish();
    return m;
}

// The registry method a JSON block (with "name") describes, built from the block.
inline std::unique_ptr<Method> createMethod(Json method) {
    const std::string name = method["name"];
    method.erase("name");
    return createMethod(*findMethod(name), method);
}

// Prepares `m` and renders `frames` frames of it; returns the last one.
inline LayeredImage renderFrames(Method& m, const PreparedScene& scene, const CameraDesc& camera, uint64_t seed, int frames) {
    RunNotes notes;
    m.prepare(scene, camera.width, camera.height, notes);
    LayeredImage image;
    for (int f = 0; f < frames; ++f) {
        StageTimer timer;
        image = LayeredImage(camera.width, camera.height);
        m.renderFrame({scene, camera.poseAt(float(f)).relativeTo(scene.scene.worldOrigin), camera.width, camera.height, f, frames, false, seed, timer, false}, image);
    }
    return image;
}

// Renders `frames` frames of `method` (a registry method's JSON block, with "name") and returns
// the last one.
inline LayeredImage render(const PreparedScene& scene, const CameraDesc& camera, const Json& method, uint64_t seed = 1, int frames = 1,
                           Json* stats = nullptr) {
    std::unique_ptr<Method> m = createMethod(method);
    LayeredImage image = renderFrames(*m, scene, camera, seed, frames);
    if (stats) *stats = m->frameStats();
    return image;
}

// A 200 × 200 plane of albedo ρ facing +Y under a sun of irradiance E arriving `thetaRadians` from
// the normal, and nothing else: every visible point reflects exactly ρ E cos θ / π.
inline Json sunLitPlane(float albedo, float irradiance, float thetaRadians) {
    return {{"materials", {{"ground", {{"type", "diffuse"}, {"albedo", albedo}}}}},
            {"shapes", {{{"type", "quad"}, {"transform", {{"scale", 100.0}}}, {"material", "ground"}}}},
            {"lights", {{{"type", "sun"}, {"direction", {std::sin(thetaRadians), -std::cos(thetaRadians), 0.0}}, {"irradiance", irradiance}}}}};
}

// A square plane of albedo ρ facing +Y, `scale` units from its centre to each edge, under a
// constant sky of radiance L and nothing else: every visible point reflects exactly ρ L.
inline Json skyLitPlane(float albedo, float sky, double scale) {
    return {{"materials", {{"ground", {{"type", "diffuse"}, {"albedo", albedo}}}}},
            {"shapes", {{{"type", "quad"}, {"transform", {{"scale", scale}}}, {"material", "ground"}}}},
            {"lights", {{{"type", "environment"}, {"radiance", sky}}}}};
}

inline CameraDesc camera(const vec3& eye, const vec3& target, int width, int height, float vfovDeg = 60.0f) {
    CameraDesc c;
    c.width = width;
    c.height = height;
    c.keyframes.push_back({0.0f, WorldPose{glm::dvec3(eye), glm::dvec3(target), vec3(0, 1, 0), vfovDeg}});
    return c;
}

inline std::filesystem::path sharedScenes() { return GIBENCH_SHARED_SCENES; }

}  // namespace gibench::test
