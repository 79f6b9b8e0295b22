#pragma once
// The G-buffer: what the primary ray of each pixel found, the first stage of every real-time
// pipeline (the probe cache's Figure 2).

#include "core/render/prepared_scene.h"
#include "core/render/surface.h"
#include "core/scene/camera.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace gibench {

// Two cache lines: the first holds what the probe cache's raster, allocation and (on a diffuse
// surface) gather stages read (validity, albedo, position, shading normal, mesh, triangle and
// material), which then read half the bytes.
struct alignas(64) GBufferTexel {
    bool valid = false;     // the primary ray hit a surface
    Color albedo{0.0f};
    SurfacePoint surface;   // normals face the camera
    vec3 wo{0.0f};          // towards the camera
    float depth = kInfinity;
    Color seen{0.0f};       // emission of the hit surface towards the camera, or the environment on a miss
};

static_assert(sizeof(GBufferTexel) == 128 && offsetof(GBufferTexel, surface) + offsetof(SurfacePoint, material) + sizeof(Material*) <= 64);

struct GBuffer {
    int width = 0;
    int height = 0;
    std::vector<GBufferTexel> texels;

    const GBufferTexel& at(int x, int y) const { return texels[std::size_t(y) * width + x]; }
};

// One primary ray per pixel, jittered within the pixel by a stream of (seed, frame, pixel), so
// accumulating frames antialiases like the reference. Parallel over rows.
void renderGBuffer(const PreparedScene& scene, const PinholeCamera& camera, uint64_t seed, uint64_t frame, GBuffer& out);

}  // namespace gibench
