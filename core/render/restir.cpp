// ReSTIR as RestirDirect runs it.
//
// Per G-buffer pixel q and frame:
//  1. Candidates (resampled importance sampling, RIS): `candidates` light samples x_i from the
//     light sampler with density p, each weighted w_i = p̂_q(x_i) / p(x_i), one kept with
//     probability w_i / Σw by weighted reservoir sampling. The target p̂_q is the luminance of the
//     unshadowed reflected radiance f · L · cos (visibility left out, so targets cost no rays).
//  2. Temporal reuse: the reservoir this pixel ended the previous frame with, its M capped at
//     `temporalHistoryCap` so old samples cannot dominate forever, is merged in.
//  3. Spatial reuse: the reservoirs of step 2 at up to `spatialNeighbours` random pixels within
//     `spatialRadiusPixels` whose surfaces look alike (normals within dot 0.9, depth within 10 %)
//     are merged in.
//  4. Shading: one shadow ray towards the kept sample y; the pixel gets f · L · cos · V(y) · W.
//
// Merging reservoirs r_i (found at pixels q_i) at pixel q streams each kept sample y_i with weight
// p̂_q(y_i) · W_i · M_i, sums the M_i, and sets the result's contribution weight
// W = Σw / (Z · p̂_q(y)) where Z is the sum of M_i over the reservoirs whose own pixel could have
// produced y (p̂_{q_i}(y) > 0): the paper's unbiased combination (its Algorithm 6) with the
// visibility-free target, so Z needs no rays. It removes the darkening the plain 1/ΣM
// normalisation brings where neighbours see a light below their horizon that q sees. What it
// leaves, as in the paper: a reservoir that itself merged several pixels is judged by its own
// pixel's target only, and a history sample is judged at the previous frame's surface, which the
// jittered G-buffer moves by less than a pixel. Candidates alone (no reuse) are exactly unbiased.
//
// Samples are stored in a measure every pixel shares, so no Jacobian is needed when a sample
// moves between pixels: points on emitting triangles by area, environment directions by solid
// angle, suns by counting (their "density" is the selection probability).

#include "core/render/restir.h"

#include "core/render/bsdf.h"
#include "core/util/rng.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <stdexcept>

namespace gibench {

namespace {

// Neighbours whose surfaces differ more than this are not reused: their targets would differ
// too much for their samples to help (Bitterli et al. 2020, §4 "spatial reuse").
constexpr float kMinNormalDot = 0.9f;
constexpr float kMaxRelativeDepth = 0.1f;

// The unshadowed reflected radiance f · L · cos that sample y sends towards the camera from a
// texel, in y's measure (for a point on a triangle it includes cos θ_light / d², the change from
// solid angle to area), and the shadow-ray geometry to test it.
struct Evaluation {
    Color value{0.0f};
    vec3 wi{0.0f};
    float distance = kInfinity;
};

bool isDistant(const RestirLightPoint& y) { return y.normal == vec3(0.0f); }

Evaluation evaluate(const GBufferTexel& at, const Bsdf& bsdf, const RestirLightPoint& y) {
    Evaluation e;
    float geometry = 1.0f;
    if (isDistant(y)) {
        e.wi = y.position;
    } else {
        const vec3 d = y.position - at.surface.position;
        const float dist2 = glm::dot(d, d);
        if (!(dist2 > 0.0f)) return e;
        e.distance = std::sqrt(dist2);
        e.wi = d / e.distance;
        const float cosLight = -glm::dot(y.normal, e.wi);
        if (cosLight <= 0.0f) return e;  // the back of a one-sided emitter
        geometry = cosLight / dist2;
    }
    e.value = bsdf.eval(at.wo, e.wi) * y.radiance * (std::fabs(glm::dot(e.wi, at.surface.shadingNormal)) * geometry);
    return e;
}

Bsdf bsdfOf(const GBufferTexel& t) { return Bsdf(*t.surface.material, t.albedo, t.surface); }

// The resampling target p̂: luminance of the unshadowed contribution; 0 when not finite, so a
// bad value can never be selected.
float target(const GBufferTexel& at, const Bsdf& bsdf, const RestirLightPoint& y) {
    const float t = luminance(evaluate(at, bsdf, y).value);
    return std::isfinite(t) ? std::max(t, 0.0f) : 0.0f;
}

// Weighted reservoir sampling: streams y with weight w, keeping it with probability w / Σw.
// Returns whether y was kept.
bool stream(RestirReservoir& r, const RestirLightPoint& y, float w, Rng& rng, uint64_t& dropped) {
    if (!std::isfinite(w)) {
        ++dropped;
        return false;
    }
    if (!(w > 0.0f)) return false;
    r.wSum += w;
    if (rng.uniform() * r.wSum >= w) return false;
    r.y = y;
    return true;
}

// W = Σw / (Z · p̂(y)), or an empty reservoir when that is not a finite positive number.
void setContributionWeight(RestirReservoir& r, float targetOfKept, float z) {
    const float W = r.wSum / (z * targetOfKept);
    r.W = r.wSum > 0.0f && targetOfKept > 0.0f && z > 0.0f && std::isfinite(W) ? W : 0.0f;
}

// RIS over `count` light sampler candidates at texel `at` (Bitterli et al. 2020, Algorithm 3):
// candidate x_i of density p(x_i) gets weight p̂(x_i) / p(x_i), and W = Σw / (M · p̂(y)).
RestirReservoir candidates(const PreparedScene& ps, const GBufferTexel& at, const Bsdf& bsdf, int count, Rng& rng, uint64_t& dropped) {
    RestirReservoir r;
    float targetOfKept = 0.0f;
    for (int i = 0; i < count; ++i) {
        const float uSelect = rng.uniform();
        const vec2 u(rng.uniform(), rng.uniform());
        const LightSample ls = ps.lights.sample(at.surface.position, uSelect, u);
        ++r.m;  // a failed draw still counts: M is the number of draws the density p refers to
        if (!(ls.pdf > 0.0f)) continue;
        RestirLightPoint y;
        y.radiance = ls.radiance;
        float density = ls.pdf;
        if (ls.isDelta || !std::isfinite(ls.distance)) {
            y.position = ls.wi;
        } else {
            y.position = ls.point;
            y.normal = ls.lightNormal;
            y.positionError = ls.pointError;
            // The sampler's solid-angle density in area measure, the measure y is kept in.
            density *= -glm::dot(ls.lightNormal, ls.wi) / (ls.distance * ls.distance);
            if (!(density > 0.0f)) continue;  // grazing: the area density underflowed, a failed draw
        }
        const float t = target(at, bsdf, y);
        if (stream(r, y, t / density, rng, dropped)) targetOfKept = t;
    }
    setContributionWeight(r, targetOfKept, float(r.m));
    return r;
}

// A reservoir to merge, the G-buffer texel it was made at and its M after any cap.
struct Source {
    const RestirReservoir* reservoir;
    const GBufferTexel* texel;
    int m;
};

// Merges reservoirs at texel `at` (Bitterli et al. 2020, Algorithm 6): y_i streams with weight
// p̂_at(y_i) · W_i · M_i; Z sums the M_i of the sources whose own texel gives the kept y a
// positive target, i.e. that could have produced it.
RestirReservoir merge(const GBufferTexel& at, const Bsdf& bsdf, const Source* sources, int count, Rng& rng, uint64_t& dropped) {
    RestirReservoir r;
    float targetOfKept = 0.0f;
    for (int i = 0; i < count; ++i) {
        const Source& s = sources[i];
        r.m += s.m;
        if (!(s.reservoir->W > 0.0f)) continue;
        const float t = target(at, bsdf, s.reservoir->y);
        if (stream(r, s.reservoir->y, t * s.reservoir->W * float(s.m), rng, dropped)) targetOfKept = t;
    }
    if (!(r.wSum > 0.0f)) return r;
    int z = 0;
    for (int i = 0; i < count; ++i) {
        const Source& s = sources[i];
        if (s.texel == &at ? targetOfKept > 0.0f : target(*s.texel, bsdfOf(*s.texel), r.y) > 0.0f) z += s.m;
    }
    setContributionWeight(r, targetOfKept, float(z));
    return r;
}

bool similar(const GBufferTexel& a, const GBufferTexel& b) {
    return b.valid && glm::dot(a.surface.shadingNormal, b.surface.shadingNormal) > kMinNormalDot &&
           std::fabs(b.depth - a.depth) <= kMaxRelativeDepth * a.depth;
}

}  // namespace

RestirDirect::RestirDirect(const RestirSettings& settings) : m_settings(settings) {
    if (settings.candidates < 1) throw std::invalid_argument("RestirSettings::candidates must be >= 1");
    if (settings.temporalHistoryCap < 0) throw std::invalid_argument("RestirSettings::temporalHistoryCap must be >= 0");
    if (settings.spatialNeighbours < 0) throw std::invalid_argument("RestirSettings::spatialNeighbours must be >= 0");
    if (!(settings.spatialRadiusPixels >= 0.0f) || !std::isfinite(settings.spatialRadiusPixels))
        throw std::invalid_argument("RestirSettings::spatialRadiusPixels must be finite and >= 0");
}

void RestirDirect::render(const PreparedScene& ps, const GBuffer& gbuffer, uint64_t seed, uint64_t frame, bool resetHistory,
                          std::vector<Color>& out, uint64_t& rays) {
    const int width = gbuffer.width, height = gbuffer.height;
    const std::size_t pixels = std::size_t(width) * height;
    out.assign(pixels, Color(0.0f));
    m_droppedNonFinite = 0;
    if (ps.lights.empty()) {
        m_history.clear();
        return;
    }
    const bool useHistory = m_settings.temporal && !resetHistory && m_previousScene == &ps && m_history.size() == pixels &&
                            m_previousGBuffer.width == width && m_previousGBuffer.height == height;
    std::atomic<uint64_t> dropped{0}, shadowRays{0};

    // Candidates, then temporal reuse.
    m_temporal.assign(pixels, RestirReservoir{});
    tbb::parallel_for(0, height, [&](int y) {
        // Every pass runs in the same floating-point mode, so which thread gets a row cannot
        // change the result.
        const ScopedFlushToZero flushToZero;
        uint64_t rowDropped = 0;
        for (int x = 0; x < width; ++x) {
            const std::size_t pixel = std::size_t(y) * width + x;
            const GBufferTexel& t = gbuffer.texels[pixel];
            if (!t.valid) continue;
            Rng rng = Rng::forPath(seed, frame, pixel, RandomStream::RestirCandidates);
            const Bsdf bsdf = bsdfOf(t);
            const RestirReservoir current = candidates(ps, t, bsdf, m_settings.candidates, rng, rowDropped);
            if (!useHistory || !m_previousGBuffer.texels[pixel].valid) {
                m_temporal[pixel] = current;
                continue;
            }
            const RestirReservoir& previous = m_history[pixel];
            const std::array<Source, 2> sources{Source{&current, &t, current.m},
                                                Source{&previous, &m_previousGBuffer.texels[pixel],
                                                       std::min(previous.m, m_settings.temporalHistoryCap)}};
            m_temporal[pixel] = merge(t, bsdf, sources.data(), int(sources.size()), rng, rowDropped);
        }
        dropped += rowDropped;
    });

    // Spatial reuse, then one shadow ray per pixel.
    std::vector<RestirReservoir> shaded(pixels);
    tbb::parallel_for(0, height, [&](int y) {
        const ScopedFlushToZero flushToZero;
        uint64_t rowDropped = 0, rowRays = 0;
        std::vector<Source> sources;
        for (int x = 0; x < width; ++x) {
            const std::size_t pixel = std::size_t(y) * width + x;
            const GBufferTexel& t = gbuffer.texels[pixel];
            if (!t.valid) continue;
            const Bsdf bsdf = bsdfOf(t);
            RestirReservoir& r = shaded[pixel];
            r = m_temporal[pixel];
            if (m_settings.spatial && m_settings.spatialNeighbours > 0) {
                Rng rng = Rng::forPath(seed, frame, pixel, RandomStream::RestirSpatial);
                sources.assign(1, Source{&m_temporal[pixel], &t, r.m});
                for (int k = 0; k < m_settings.spatialNeighbours; ++k) {
                    // Uniform in the disc of the radius around the pixel.
                    const float radius = m_settings.spatialRadiusPixels * std::sqrt(rng.uniform());
                    const float phi = 2.0f * kPi * rng.uniform();
                    const int nx = x + int(std::lround(radius * std::cos(phi)));
                    const int ny = y + int(std::lround(radius * std::sin(phi)));
                    if (nx < 0 || ny < 0 || nx >= width || ny >= height || (nx == x && ny == y)) continue;
                    const std::size_t neighbour = std::size_t(ny) * width + nx;
                    const GBufferTexel& n = gbuffer.texels[neighbour];
                    if (!similar(t, n)) continue;
                    sources.push_back(Source{&m_temporal[neighbour], &n, m_temporal[neighbour].m});
                }
                if (sources.size() > 1) r = merge(t, bsdf, sources.data(), int(sources.size()), rng, rowDropped);
            }
            if (!(r.W > 0.0f)) continue;

            const Evaluation e = evaluate(t, bsdf, r.y);
            const Color estimate = e.value * r.W;
            if (!isFinite(estimate)) {
                ++rowDropped;
                continue;
            }
            if (!(maxComponent(estimate) > 0.0f)) continue;
            const ShadowRay shadow = std::isfinite(e.distance)
                                         ? shadowRayBetween(t.surface.position, t.surface.positionError, t.surface.geometricNormal, r.y.position, r.y.positionError, r.y.normal)
                                         : shadowRayTowards(t.surface.position, t.surface.positionError, t.surface.geometricNormal, e.wi);
            ++rowRays;
            if (!ps.tracer.occluded(shadow.ray, shadow.tMax)) out[pixel] = estimate;
        }
        dropped += rowDropped;
        shadowRays += rowRays;
    });

    rays += shadowRays;
    m_droppedNonFinite = dropped;
    if (m_settings.temporal) {
        // The reservoir after spatial reuse is the history, as in the paper: reuse compounds
        // over frames, and the cap bounds how much it can weigh.
        m_history = std::move(shaded);
        m_previousGBuffer = gbuffer;
        m_previousScene = &ps;
    } else {
        m_history.clear();
    }
}

}  // namespace gibench
