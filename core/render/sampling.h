#pragma once
// Warps from the unit square to directions and points, with their densities, and discrete
// distributions for importance sampling lights.

#include "core/util/lane_select.h"
#include "core/util/math.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace gibench {

// Cosine-weighted direction about +Z (Malley's method); pdf = cos θ / π per steradian. The disk
// point comes from Shirley & Chiu's concentric map, which keeps strata compact. Inline and without
// a branch: which of |x|, |y| is larger is a coin flip per sample, and its misprediction and the
// library's sincosf took 6 % of a path's time. The map's angle is π/4 · (smaller / larger) in
// [−π/4, π/4], where the Taylor polynomials below are within 3e-7 of sine and cosine; the point is
// (r cos, r sin) about the larger axis, swapped when that is y.
inline vec3 sampleCosineHemisphere(const vec2& u) {
    const float ox = 2.0f * u.x - 1.0f, oy = 2.0f * u.y - 1.0f;
    // Selections through bit masks (std::max's among them), which the compiler keeps free of
    // branches, also when a loop takes many samples across SIMD lanes.
    const uint32_t alongX = laneMask(std::fabs(ox) > std::fabs(oy));
    const auto select = [alongX](float ifX, float ifY) { return laneSelect(alongX, ifX, ifY); };
    const float r = select(ox, oy), other = select(oy, ox);
    // At the centre r = other = 0, and the angle is 0.
    const float smallest = std::numeric_limits<float>::min();
    const float a = (kPi / 4.0f) * other / std::copysign(laneSelect(laneMask(std::fabs(r) < smallest), smallest, std::fabs(r)), r), a2 = a * a;
    const float sine = a * (1.0f - a2 * (1.0f / 6.0f - a2 * (1.0f / 120.0f - a2 * (1.0f / 5040.0f))));
    const float cosine = 1.0f - a2 * (0.5f - a2 * (1.0f / 24.0f - a2 * (1.0f / 720.0f - a2 * (1.0f / 40320.0f))));
    const float x = r * select(cosine, sine), y = r * select(sine, cosine);
    const float z2 = 1.0f - x * x - y * y;
    return vec3(x, y, std::sqrt(laneSelect(laneMask(0.0f < z2), z2, 0.0f)));
}
// Without a branch: the constant environment's samples are taken across SIMD lanes.
inline float cosineHemispherePdf(float cosTheta) { return laneSelect(laneMask(cosTheta > 0.0f), cosTheta * kInvPi, 0.0f); }

vec3 sampleUniformSphere(const vec2& u);
inline constexpr float kUniformSpherePdf = 1.0f / (4.0f * kPi);

// Uniform point on a triangle as barycentrics (b1, b2) of vertices 1 and 2 (Heitz 2019 low
// distortion map would do too; the square-root map is enough and simple).
inline vec2 sampleUniformTriangle(const vec2& u) {
    const float s = std::sqrt(u.x);
    return vec2(s * (1.0f - u.y), s * u.y);
}

// Veach's power heuristic (β = 2) for two strategies with densities fPdf and gPdf.
// Without branches: next-event estimation weighs its samples across SIMD lanes (DirectLightBatch).
inline float powerHeuristic(float fPdf, float gPdf) {
    const float f2 = fPdf * fPdf, g2 = gPdf * gPdf;
    return laneSelect(laneMask(f2 == kInfinity), 1.0f, laneSelect(laneMask(f2 + g2 > 0.0f), f2 / (f2 + g2), 0.0f));
}

// A piecewise-constant distribution over n bins, sampled by inversion of its CDF.
class Distribution1D {
public:
    Distribution1D() = default;
    // Negative or non-finite weights are errors of the caller (std::invalid_argument).
    explicit Distribution1D(std::vector<float> weights);

    std::size_t size() const { return m_weights.size(); }
    double total() const { return m_total; }
    bool empty() const { return m_total <= 0.0; }
    // Bin chosen for u in [0,1), its probability, and u rescaled to [0,1) within the bin.
    std::size_t sample(float u, float& probability, float& remapped) const;
    // The same bin and probability, for a caller that needs no second number from u.
    std::size_t sample(float u, float& probability) const {
        const std::size_t i = bin(u);
        probability = m_probabilities[i];
        return i;
    }
    float probability(std::size_t index) const { return m_total > 0.0 ? m_probabilities[index] : 0.0f; }

private:
    // Up to this many bins (a scene's few lights, picked at every path vertex) the bin is found by
    // counting the CDF starts at or below u: a binary search's branch per level goes either way at
    // random, a mispredict per pick, 2 % of a path-traced frame's samples on the Cornell box.
    static constexpr std::size_t kCountedBins = 16;
    std::size_t bin(float u) const;

    std::vector<float> m_weights;
    std::vector<float> m_probabilities;  // weight / total, kept so that sampling divides nothing
    std::vector<double> m_cdf;  // m_cdf[i] = sum of weights before bin i, normalized; size n + 1
    std::vector<uint32_t> m_nonZeroFrom;  // the first bin at or after i with a nonzero weight, else the last bin
    double m_total = 0.0;
};

// Piecewise-constant density on [0,1]² over a width × height grid of weights (rows from v = 0).
class Distribution2D {
public:
    Distribution2D() = default;
    Distribution2D(const std::vector<float>& weights, int width, int height);

    // Point in [0,1)² and its density with respect to area on the unit square.
    vec2 sample(const vec2& u, float& pdf) const;
    float pdf(const vec2& p) const;
    bool empty() const { return m_marginal.empty(); }

private:
    int m_width = 0, m_height = 0;
    std::vector<Distribution1D> m_rows;
    Distribution1D m_marginal;
};

}  // namespace gibench
