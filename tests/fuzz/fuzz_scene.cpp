// Fuzz target: the input is a scene file (core/scene/scene_loader.h). An accepted scene is then
// prepared as every renderer prepares it (Embree BVH, light sampler), and when it has a camera, a
// few camera rays are traced and shaded far enough to reach the light sampler: bad input must be
// refused by the loader, not abort in Embree or turn into NaN at render time.

#include "core/render/prepared_scene.h"
#include "core/render/surface.h"
#include "core/scene/scene_loader.h"
#include "finite_scene.h"
#include "private_folder.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

namespace {

const gibench::PrivateFolder& folder() {
    static const gibench::PrivateFolder instance("fuzz_scene");
    return instance;
}

// Traces `ray` and, at a hit, shades it as far as choosing a light; each value on the way is finite.
void traceAndShade(const gibench::PreparedScene& prepared, const gibench::Ray& ray) {
    using namespace gibench;
    const RayHit hit = prepared.tracer.intersect(ray);
    if (!hit.found()) return;
    const SurfacePoint point = surfaceAt(prepared.scene, ray, hit);
    requireFinite(isFinite(point.position) && isFinite(point.shadingNormal) && isFinite(albedoAt(prepared.scene, point)),
                  "a camera ray's hit point, normal or albedo");
    if (prepared.lights.empty()) return;
    const LightSample light = prepared.lights.sample(point.position, 0.5f, vec2(0.5f));
    requireFinite(isFinite(light.wi) && isFinite(light.radiance) && std::isfinite(light.pdf), "a light sample at a camera ray's hit");
    if (light.pdf > 0.0f) prepared.tracer.occluded(Ray{offsetRayOrigin(point.position, point.positionError, point.geometricNormal), light.wi}, light.distance);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    setenv("GIBENCH_SCENES", folder().path().c_str(), 1);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace gibench;
    folder().empty();
    const auto file = folder().write("scene.json", std::string_view(reinterpret_cast<const char*>(data), size));
    Scene scene;
    if (!acceptsOrRejectsCleanly([&] { scene = loadSceneFile(file); })) return 0;
    requireFiniteScene(scene);
    acceptsOrRejectsCleanly([&] {
        const PreparedScene prepared(std::move(scene));
        if (!prepared.scene.camera) return;
        const ScopedFlushToZero flushToZero;
        for (const Ray& ray : probeRays(*prepared.scene.camera, prepared.scene.worldOrigin)) traceAndShade(prepared, ray);
    });
    return 0;
}
