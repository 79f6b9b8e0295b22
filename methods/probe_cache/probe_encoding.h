#pragma once
// How one surface probe stores the radiance arriving over the hemisphere around its normal, how
// Monte Carlo samples update it, and how a final gather reads it back (paper §3.3: "grids ...
// or spherical harmonics"). Everything is in the probe-local frame, +z = probe normal; the
// caller owns the probe's state (floatsPerProbe() floats, zero-filled = empty) and the frame.
//
// Threading: an encoding is immutable after construction; every member is const and may be
// called concurrently, as long as no two threads write the same probe's state at once.

#include "core/config/params.h"
#include "core/util/math.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace gibench {

enum class ProbeEncodingKind { Hemispherical, Octahedral, SphericalHarmonics };
// The config names of the kinds (key "encoding").
const EnumChoices<ProbeEncodingKind>& probeEncodingChoices();

// One node of a fixed quadrature of the probe hemisphere.
struct QuadraturePoint {
    vec3 direction;    // local, unit, z > 0
    float solidAngle;  // sr; the solid angles of a quadrature sum to 2π
};

// Radiance (per RGB component) saturates at ±kMaxProbeRadiance when it enters a probe, so that
// every sum an encoding forms from its state stays finite: 2^120 ≈ 1.3e36 W/(sr·m²), far beyond
// any scene, and small enough that a sum whose weights total under 2^7 cannot overflow (the
// grids' weights total at most 2π, the spherical harmonics' about 30).
inline constexpr float kMaxProbeRadiance = 0x1p120f;

// Per-bin and per-probe sample counts saturate at the encoding's history (ProbeEncoding::
// history()), at most 2^24, the last integer a float counts exactly.
inline constexpr uint32_t kMaxProbeSampleCount = 1u << 24;

// Every bin of a grid encoding is cut into sub-cells that each lie within this angle (radians) of
// their centroid direction; irradiance() integrates max(0, n·ω) exactly over every bin and
// sub-cell on one side of the plane n·ω = 0, so its only error comes from sub-cells that plane cuts.
inline constexpr float kProbeSubcellRadius = 0.1f;

// Bound of |E(n) − irradiance(n)| per unit of the largest cached |radiance|, for any normal and any
// grid encoding: πρ² ≈ 0.031 with ρ = kProbeSubcellRadius, 1 % of the πL of a constant radiance L
// (derived in probe_encoding.cpp). For radiance >= 0 the error is never an overestimate, and it
// is zero (to float rounding) when no sub-cell is cut, as for n = +z.
inline constexpr float kProbeIrradianceTolerance = kPi * kProbeSubcellRadius * kProbeSubcellRadius;

class ProbeEncoding {
public:
    virtual ~ProbeEncoding() = default;

    // Bounded history (issue 9; SHaRC's accumulation limit, DDGI's hysteresis), counted in the
    // probe's samples: a bin's (for the spherical harmonics, the probe's) running mean weighs its
    // first `history` samples equally, and from then on gives each new sample the weight
    // 1/history, an exponential blend that forgets a sample's share by e after `history` more;
    // and in the grids every sample the probe takes into another bin multiplies a bin's count by
    // (1 − 1/history), so a bin's old samples fade with the probe's samples, not only with its own
    // (a 5×5 grid spreads them over 25 bins: each would otherwise wait 25 times as long). So samples
    // taken while the cache was still empty, or before a light changed, leave the mean: after a
    // step change the distance to the new value is (1 − 1/history)^k of the step after k samples,
    // 10 % after 2.3 history. history = kMaxProbeSampleCount keeps a plain running mean.
    uint32_t history() const { return m_history; }

    // "hemispherical 5x5", "octahedral 8x8", "sh order 2".
    virtual std::string name() const = 0;
    // Floats of one probe's state; a zero-filled state is an empty probe.
    virtual int floatsPerProbe() const = 0;

    // Adds one radiance sample (W/(sr·m²)) arriving from local direction `local` (unit), drawn by
    // the caller with solid-angle density `pdf` (sr⁻¹; the spherical harmonics need it, the grids
    // only check it). Samples with local.z <= 0, a non-finite direction or radiance, or a pdf that
    // is not finite and > 0 are ignored: the state is unchanged and the result is false.
    virtual bool addSample(float* state, const vec3& local, const Color& radiance, float pdf) const = 0;
    // Samples the probe has taken (saturating at history()); 0 for an empty probe,
    // which the caller must skip rather than count as black (docs/mamba.md item 5).
    virtual uint32_t sampleCount(const float* state) const = 0;

    // E(n) = ∫ over the probe hemisphere of L(ω) max(0, n·ω) dω (W/m²) from the cached radiance,
    // for a local unit normal n (the receiving surface's normal in probe coordinates; it may differ
    // from +z). Zero for an empty probe. Finite and >= 0 whenever the samples were >= 0.
    virtual Color irradiance(const float* state, const vec3& localNormal) const = 0;

    // A fixed quadrature of the hemisphere for integrals against other lobes (the GGX gather):
    // Σ_i L(ω_i) g(ω_i) ΔΩ_i. A lobe narrower than a quadrature cell is aliased, so a caller
    // normalises by the quadrature's own Σ_i g(ω_i) ΔΩ_i where that matters.
    virtual const std::vector<QuadraturePoint>& quadrature() const = 0;
    // out[i] = cached radiance at quadrature()[i] for every i (out holds quadrature().size()
    // colours); all zero for an empty probe.
    virtual void radianceAt(const float* state, Color* out) const = 0;

protected:
    explicit ProbeEncoding(uint32_t history) : m_history(history) {}
    float historyLimit() const { return float(m_history); }

private:
    uint32_t m_history;
};

// The encodings (probe-local ω = (x, y, z), z > 0):
//  - Hemispherical r×r (MAMBA's grid, r = 5 in the original): bin ring·r + sector, where sector s
//    holds azimuths φ = atan2(y, x) ∈ [2πs/r, 2π(s+1)/r) (φ in [0, 2π), from +x towards +y) and
//    ring k holds sin θ = |(x, y)| ∈ [k/r, (k+1)/r) (ring 0 around the normal): a projection of the
//    hemisphere onto the tangent disc. Bin solid angle Δφ (cos θa − cos θb), projected solid angle
//    Δφ (sin² θb − sin² θa) / 2: they differ ~30× between bins, and every integral weights by them.
//  - Octahedral r×r: (a, b) = (x, y) / (|x| + |y| + z), (u, v) = (a + b, a − b) ∈ [-1, 1]² (the
//    diamond |a| + |b| <= 1 turned by 45° to fill the square); bin row·r + column with
//    column = ⌊(u + 1) r / 2⌋, row = ⌊(v + 1) r / 2⌋.
//    Both grids keep per bin the running mean of its samples' radiance and their count
//    (4 floats), then the probe's count: 4r² + 1 floats. quadrature()[i] is bin i, at its
//    centroid direction (the normalised ∫ ω dω over the bin), with its exact solid angle.
//    An empty bin of a probe that has samples reads as the solid-angle-weighted mean radiance of
//    the probe's sampled bins: a young probe has many empty bins, and black would darken it.
//  - SphericalHarmonics order l ∈ {1, 2}: (l + 1)² real SH coefficients × RGB, each the running
//    mean of L(ω) Y(ω) / pdf(ω) (a Monte Carlo projection of the radiance times the hemisphere
//    indicator), then the count: 3(l + 1)² + 1 floats. Irradiance by the clamped-cosine
//    convolution (Ramamoorthi & Hanrahan 2001), clamped at 0. quadrature(): 8 sectors × 8 rings
//    uniform in cos θ (64 cells of 2π/64 sr), node ring·8 + sector at each cell's centroid
//    direction; radianceAt evaluates the SH there, clamped at 0. With cosine-weighted samples
//    Y_00 / pdf grows as 1 / cos θ towards the horizon: the projection is unbiased but its
//    variance is heavy-tailed (it grows with the log of the smallest cos θ drawn).
// Hemispherical and Octahedral take `resolution` bins per side, 1 to 64; SphericalHarmonics
// takes the order, 1 or 2; `history` is 1 to kMaxProbeSampleCount (the largest: a running mean
// of every sample). Anything else is std::invalid_argument.
std::unique_ptr<ProbeEncoding> makeProbeEncoding(ProbeEncodingKind kind, int resolution, uint32_t history = kMaxProbeSampleCount);

}  // namespace gibench
