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

#include <cmath>
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

// Per-bin and per-probe sample weights (counts, until fade() scales them) saturate at 2^24, the
// last integer a float counts exactly.
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

    // "hemispherical 5x5", "octahedral 8x8", "sh order 2".
    virtual std::string name() const = 0;
    // Floats of one probe's state; a zero-filled state is an empty probe.
    virtual int floatsPerProbe() const = 0;
    // The floats of a state from this one on are its sample weights (counts that fade() scales),
    // those before it means: a compact state format rounds the means and keeps the weights exact
    // (probe_light.h).
    virtual int sampleWeightsOffset() const = 0;

    // Adds one radiance sample (W/(sr·m²)) arriving from local direction `local` (unit), drawn by
    // the caller with solid-angle density `pdf` (sr⁻¹; the spherical harmonics need it, the grids
    // only check it). Samples acceptsSample() refuses are ignored: the state is unchanged and the
    // result is false.
    virtual bool addSample(float* state, const vec3& local, const Color& radiance, float pdf) const = 0;
    // False for samples with local.z <= 0, a non-finite direction or radiance, or a pdf that is
    // not finite and > 0.
    static bool acceptsSample(const vec3& local, const Color& radiance, float pdf) {
        return local.z > 0.0f && isFinite(local) && isFinite(radiance) && pdf > 0.0f && std::isfinite(pdf);
    }
    // The weight of the samples the probe has taken: their number (saturating at
    // kMaxProbeSampleCount), as fade() left it; 0 only for an empty probe, which the caller must
    // skip rather than count as black (docs/mamba.md item 5).
    virtual float sampleWeight(const float* state) const = 0;

    // Bounded history (issue 9; SHaRC's accumulation frame limit, DDGI's hysteresis): multiplies
    // the weight of every sample taken so far by `keep` in (0, 1], leaving the means as they are,
    // so the next sample of a bin (for the spherical harmonics, of the probe) gets the larger
    // share 1 / (keep·w + 1). The pipeline fades a probe by (1 − 1/H) per frame for a history
    // of H frames. A sampled bin or probe keeps a weight of at least 2^-20: only an empty one
    // weighs 0.
    virtual void fade(float* state, float keep) const = 0;

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
//    Both grids keep per bin the running mean of its samples' radiance and their count, and the
//    same for all the probe's samples: 4r² + 4 floats, the means first (the bins' in bin order,
//    then the probe's), then the counts in the same order. quadrature()[i] is bin i, at its centroid direction (the normalised
//    ∫ ω dω over the bin), with its exact solid angle. A bin with count c >= 1 serves its mean m,
//    one with less c m + (1 − c) P, P the probe's mean: an empty bin of a probe that has samples
//    serves P (a young probe has many empty bins, and black would darken it), and a bin whose
//    count the bounded history has faded follows the probe's samples rather than waiting for
//    its own.
//  - SphericalHarmonics order l ∈ {1, 2}: (l + 1)² real SH coefficients × RGB, each the running
//    mean of L(ω) Y(ω) / pdf(ω) (a Monte Carlo projection of the radiance times the hemisphere
//    indicator), then the count: 3(l + 1)² + 1 floats. Irradiance by the clamped-cosine
//    convolution (Ramamoorthi & Hanrahan 2001), clamped at 0. quadrature(): 8 sectors × 8 rings
//    uniform in cos θ (64 cells of 2π/64 sr), node ring·8 + sector at each cell's centroid
//    direction; radianceAt evaluates the SH there, clamped at 0. With cosine-weighted samples
//    Y_00 / pdf grows as 1 / cos θ towards the horizon: the projection is unbiased but its
//    variance is heavy-tailed (it grows with the log of the smallest cos θ drawn).
// Hemispherical and Octahedral take `resolution` bins per side, 1 to 64; SphericalHarmonics
// takes the order, 1 or 2. Anything else is std::invalid_argument.
std::unique_ptr<ProbeEncoding> makeProbeEncoding(ProbeEncodingKind kind, int resolution);

}  // namespace gibench
