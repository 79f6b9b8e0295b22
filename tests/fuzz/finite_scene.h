#pragma once
// NaN and infinity must not get past the loaders: a loaded scene's floats are all finite, and so
// are the rays its camera generates. Each check calls finding() naming what is not finite.

#include "core/scene/camera.h"
#include "core/scene/scene.h"
#include "fuzz_outcome.h"

#include <cmath>
#include <string>
#include <vector>

namespace gibench {

inline void requireFinite(bool finite, const std::string& what) {
    if (!finite) finding("not finite after loading: " + what);
}

inline void requireFinite(const Color& c, const std::string& what) { requireFinite(isFinite(c), what); }

inline void requireFiniteScene(const Scene& scene) {
    for (const Mesh& mesh : scene.meshes) {
        for (const vec3& p : mesh.positions) requireFinite(p, "a position of mesh \"" + mesh.name + "\"");
        for (const vec3& n : mesh.normals) requireFinite(n, "a normal of mesh \"" + mesh.name + "\"");
        for (const vec2& uv : mesh.uvs) requireFinite(std::isfinite(uv.x) && std::isfinite(uv.y), "a uv of mesh \"" + mesh.name + "\"");
    }
    for (const Material& m : scene.materials) {
        requireFinite(m.albedo, "albedo of material \"" + m.name + "\"");
        requireFinite(m.specular, "specular of material \"" + m.name + "\"");
        requireFinite(m.emission, "emission of material \"" + m.name + "\"");
        requireFinite(std::isfinite(m.roughness), "roughness of material \"" + m.name + "\"");
    }
    for (const Texture& t : scene.textures)
        for (const Color& c : t.texels) requireFinite(c, "a texel");
    for (const SunLight& sun : scene.suns) {
        requireFinite(sun.direction, "a sun's direction");
        requireFinite(sun.irradiance, "a sun's irradiance");
    }
    if (const auto& env = scene.environment) {
        requireFinite(env->radiance, "the environment's radiance");
        requireFinite(std::isfinite(env->scale), "the environment's scale");
        for (int column = 0; column < 3; ++column) requireFinite(env->toWorld[column], "the environment's rotation");
        if (env->map)
            for (const Color& c : env->map->texels) requireFinite(c, "an environment texel");
    }
}

// The frames worth looking at: the whole frames next to every keyframe and to the midpoint of
// every pair of neighbours, since runs render whole frames only (an interpolated pose can have
// eye == target halfway between keyframes without any keyframe having it).
inline std::vector<float> probeFrames(const CameraDesc& camera) {
    std::vector<float> frames;
    auto addAround = [&](float frame) {
        frames.push_back(std::floor(frame));
        frames.push_back(std::ceil(frame));
    };
    for (std::size_t k = 0; k < camera.keyframes.size(); ++k) {
        addAround(camera.keyframes[k].frame);
        if (k + 1 < camera.keyframes.size()) addAround(0.5f * (camera.keyframes[k].frame + camera.keyframes[k + 1].frame));
    }
    return frames;
}

// A few camera rays per probe frame (the corners and the centre of the film), each one finite, in
// the coordinates of a scene whose world origin is `worldOrigin`.
inline std::vector<Ray> probeRays(const CameraDesc& camera, const glm::dvec3& worldOrigin) {
    std::vector<Ray> rays;
    const float w = float(camera.width), h = float(camera.height);
    for (float frame : probeFrames(camera)) {
        const PinholeCamera pinhole(camera.poseAt(frame).relativeTo(worldOrigin), camera.width, camera.height);
        for (const vec2& film : {vec2(0.5f * w, 0.5f * h), vec2(0.0f), vec2(w, 0.0f), vec2(0.0f, h), vec2(w, h)}) {
            const Ray ray = pinhole.generateRay(film.x, film.y);
            requireFinite(isFinite(ray.origin) && isFinite(ray.direction),
                          "the camera ray through film (" + std::to_string(film.x) + ", " + std::to_string(film.y) + ") at frame " +
                              std::to_string(frame));
            rays.push_back(ray);
        }
    }
    return rays;
}

}  // namespace gibench
