#include "methods/probe_cache/probe_views.h"

#include <tbb/parallel_for.h>

#include <cmath>

namespace gibench {

namespace {

// A ray direction scaled to unit length along the forward axis: a point of the film plane one unit
// in front of the eye.
vec3 onUnitPlane(const vec3& direction, const vec3& forward) { return direction / glm::dot(direction, forward); }

}  // namespace

FilmProjection::FilmProjection(const PinholeCamera& camera) : m_eye(camera.position()) {
    const float w = float(camera.width()), h = float(camera.height());
    m_forward = camera.generateRay(0.5f * w, 0.5f * h).direction;
    m_topLeft = onUnitPlane(camera.generateRay(0.0f, 0.0f).direction, m_forward);
    m_perPixelX = (onUnitPlane(camera.generateRay(w, 0.0f).direction, m_forward) - m_topLeft) / w;
    m_perPixelY = (onUnitPlane(camera.generateRay(0.0f, h).direction, m_forward) - m_topLeft) / h;
}

bool FilmProjection::project(const vec3& point, vec2& film) const {
    const vec3 toPoint = point - m_eye;
    const float along = glm::dot(toPoint, m_forward);
    if (!(along > 0.0f)) return false;
    const vec3 offset = onUnitPlane(toPoint, m_forward) - m_topLeft;
    film = vec2(glm::dot(offset, m_perPixelX) / glm::dot(m_perPixelX, m_perPixelX),
                glm::dot(offset, m_perPixelY) / glm::dot(m_perPixelY, m_perPixelY));
    return std::isfinite(film.x) && std::isfinite(film.y);
}

void addProbeViews(const PinholeCamera& camera, const GBuffer& gbuffer, const ProbeStore& store, const ProbeLight& light,
                   const ServedProbes& served, LayeredImage& out) {
    const int width = gbuffer.width, height = gbuffer.height;
    Image& centres = out.add("probe_centres", {"Y"});
    Image& splat = out.add("probe_splat", {"R", "G", "B"});

    const FilmProjection projection(camera);
    for (uint32_t id = 0; id < store.idCapacity(); ++id) {
        const vec3& position = store.probe(id).position;
        vec2 film;
        if (!projection.project(position, film) || !(film.x >= 0.0f && film.x < float(width) && film.y >= 0.0f && film.y < float(height)))
            continue;
        const int x = int(film.x), y = int(film.y);
        const GBufferTexel& t = gbuffer.at(x, y);
        if (t.valid) {
            const ProbeQuery query{t.surface.position, t.surface.shadingNormal, t.surface.mesh, t.surface.triangle, 0};
            if (t.depth < glm::length(position - camera.position()) - store.coverageRadius(query)) continue;
        }
        centres.at(x, y, 0) += 1.0f;
    }

    tbb::parallel_for(0, height, [&](int y) {
        for (int x = 0; x < width; ++x) {
            const std::size_t pixel = std::size_t(y) * width + x;
            const GBufferTexel& t = gbuffer.texels[pixel];
            if (!t.valid) continue;
            const ProbeWeight* probes = served.probes + served.offsets[pixel];
            uint32_t nearest = 0;
            float nearestDistance = kInfinity;
            bool found = false;
            for (int i = 0; i < served.counts[pixel]; ++i) {
                const uint32_t id = probes[i].id;
                if (id >= light.probes() || !light.sampled(id)) continue;
                const float distance = glm::length(store.probe(id).position - t.surface.position);
                if (!found || distance < nearestDistance || (distance == nearestDistance && id < nearest)) {
                    nearest = id;
                    nearestDistance = distance;
                    found = true;
                }
            }
            if (found) splat.setRgb(x, y, light.irradiance(nearest, vec3(0.0f, 0.0f, 1.0f)) * kInvPi);
        }
    });
}

}  // namespace gibench
