#pragma once
// Probe views: two layers the probe cache adds to each frame's image with "probe_views": true, to
// draw where its probes are and what each holds (the seed paper's Figures 5 and 6;
// analysis/probe_views.py draws them). They never change the other layers.
//
//  - "probe_centres" (Y): at each pixel, how many probes project onto it (a pixel's square on the
//    film holds the probe's projection), leaving out probes behind the camera and probes hidden by
//    the pixel's surface: one nearer the camera than the probe by more than the store's coverage
//    radius there (a probe lies on a surface, so the surface at its own pixel may be a little in
//    front of it; a wall between them is farther in front).
//  - "probe_splat" (R,G,B): at each surface pixel, the light of one probe alone, the nearest
//    (in scene units, ties to the lower id) of the probes that serve it and hold samples: its
//    cached irradiance at its own normal E(+z), divided by π (the radiance a white diffuse surface
//    facing the probe's normal reflects, in the units of the image). The cache as if every pixel
//    read only its nearest serving probe, with no blending and no BSDF: each probe shows as a flat
//    patch over its footprint. Black where no serving probe holds samples, and off surfaces.

#include "core/image/image.h"
#include "core/render/gbuffer.h"
#include "core/scene/camera.h"
#include "methods/probe_cache/probe_light.h"
#include "methods/probe_cache/probe_store.h"

#include <cstdint>

namespace gibench {

// The probes serving each pixel, as the raster stage found them: pixel p's are
// probes[offsets[p] .. offsets[p] + counts[p]).
struct ServedProbes {
    const ProbeWeight* probes;
    const uint32_t* offsets;
    const uint8_t* counts;
};

// Adds "probe_centres" and "probe_splat" (the top of this file) to `out`, sized like the G-buffer.
void addProbeViews(const PinholeCamera& camera, const GBuffer& gbuffer, const ProbeStore& store, const ProbeLight& light,
                   const ServedProbes& served, LayeredImage& out);

// Where a point appears on the film of `camera`: the inverse of PinholeCamera::generateRay, from
// its rays alone (a pinhole's ray directions, scaled to unit length along the central ray, lie on
// a plane and move on it linearly with the film position).
class FilmProjection {
public:
    explicit FilmProjection(const PinholeCamera& camera);
    // The film position in pixels of `point` (relative to the world origin, like the camera), (0, 0)
    // the top-left corner as in generateRay; false for a point not in front of the camera.
    bool project(const vec3& point, vec2& film) const;

private:
    vec3 m_eye, m_forward;
    vec3 m_topLeft;              // the plane's point at film (0, 0)
    vec3 m_perPixelX, m_perPixelY;  // its steps per pixel, orthogonal
};

}  // namespace gibench
