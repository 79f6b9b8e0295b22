#pragma once
// Direct lighting by spatiotemporal reservoir resampling (ReSTIR; Bitterli et al. 2020,
// "Spatiotemporal reservoir resampling for real-time ray tracing with dynamic direct lighting"),
// toned down as MAMBA does: few candidates, a capped history, two spatial neighbours, and a
// single shadow ray per pixel and frame.
//
// Candidates alone (no reuse) are exactly unbiased; reuse leaves the small bias of the paper's
// unbiased combination with a visibility-free target (the steps and the argument are at the top
// of restir.cpp; tests/core/render/restir_test.cpp measures it).
//
// Deterministic: pixel q of frame f draws from Rng::forPath(seed, f, q, stream) with one stream per
// pass (RandomStream::RestirCandidates, RandomStream::RestirSpatial), and each parallel pass
// writes only its own pixels, so the image does not depend on the thread count.

#include "core/render/gbuffer.h"
#include "core/render/prepared_scene.h"

#include <cstdint>
#include <vector>

namespace gibench {

struct RestirSettings {
    int candidates = 8;                 // light samples drawn per pixel and frame (>= 1)
    int temporalHistoryCap = 200;       // the previous frame's reservoir counts for at most this many candidates
    int spatialNeighbours = 2;          // neighbour pixels tried per pixel and frame
    float spatialRadiusPixels = 20.0f;  // neighbours are drawn uniformly from a disc of this radius
    bool temporal = true;
    bool spatial = true;
};

// The sample a reservoir keeps: enough to evaluate it again at any pixel.
struct RestirLightPoint {
    vec3 position{0.0f};   // on an emitting triangle: the point; for a sun or the environment: unit direction towards it
    vec3 normal{0.0f};     // the emitting triangle's front normal; zero for a sun or the environment
    vec3 positionError{0.0f};  // the point's rounding bound (interpolationError)
    Color radiance{0.0f};  // emitted radiance, W/(sr·m²); a sun's irradiance, W/m²
};

// One pixel's reservoir (60 bytes).
struct RestirReservoir {
    RestirLightPoint y;
    float wSum = 0.0f;  // sum of the resampling weights streamed through
    int m = 0;          // how many candidates this reservoir stands for
    float W = 0.0f;     // contribution weight of y, an estimate of 1 / (density of y); 0 when empty
};

class RestirDirect {
public:
    explicit RestirDirect(const RestirSettings& settings);

    // Fills out[pixel] (resized to the G-buffer) with the estimated direct radiance, W/(sr·m²),
    // reflected towards the camera at each valid G-buffer texel, 0 elsewhere; emission seen by
    // the camera is not included. Adds the shadow rays traced to `rays`. Temporal reuse assumes
    // the previous call saw the same view (a static camera, the G-buffer jittered within pixels
    // at most); pass `resetHistory` on frame 0 and whenever the camera moved or the scene
    // changed. Another PreparedScene or a G-buffer of another size resets the history too. Not thread-safe: one call at a
    // time per object (each call runs in parallel inside).
    void render(const PreparedScene& scene, const GBuffer& gbuffer, uint64_t seed, uint64_t frame, bool resetHistory,
                std::vector<Color>& out, uint64_t& rays);

    // Candidates and pixel results dropped during the last render() because a weight or a
    // radiance was not finite (0 in a healthy scene).
    uint64_t droppedNonFinite() const { return m_droppedNonFinite; }

private:
    RestirSettings m_settings;
    std::vector<RestirReservoir> m_history;          // the reservoir each pixel ended the last frame with
    GBuffer m_previousGBuffer;                       // the surfaces m_history was made at
    const PreparedScene* m_previousScene = nullptr;  // the scene they belong to (their materials point into it)
    std::vector<RestirReservoir> m_temporal;         // this frame's reservoirs after temporal reuse
    uint64_t m_droppedNonFinite = 0;
};

}  // namespace gibench
