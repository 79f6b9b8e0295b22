#include "methods/probe_cache/probe_encoding.h"

#include "core/render/sampling.h"
#include "core/util/rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace gibench {
namespace {

struct Config {
    ProbeEncodingKind kind;
    int resolution;
};

// Every kind at its usual size, the grids also at an even and an odd size and as a single bin.
const Config kConfigs[] = {
    {ProbeEncodingKind::Hemispherical, 5}, {ProbeEncodingKind::Hemispherical, 4}, {ProbeEncodingKind::Hemispherical, 1},
    {ProbeEncodingKind::Octahedral, 8},    {ProbeEncodingKind::Octahedral, 5},    {ProbeEncodingKind::Octahedral, 1},
    {ProbeEncodingKind::SphericalHarmonics, 1}, {ProbeEncodingKind::SphericalHarmonics, 2},
};

bool isGrid(const Config& c) { return c.kind != ProbeEncodingKind::SphericalHarmonics; }

// π in double: the float kPi is itself off by 3e-8, more than the rounding some checks allow.
constexpr double kPiDouble = 3.14159265358979323846;

// Relative rounding of one float operation; a float sum of k terms is within k·kUlp of its value.
constexpr double kUlp = 0x1p-24;
// Relative rounding allowed where irradiance() sums over sub-cells: its float sums have fewer
// than 1024 terms at kProbeSubcellRadius = 0.1 (a few hundred sub-cells in the largest bin).
constexpr double kSubcellRounding = 1024 * kUlp;

using State = std::vector<float>;

// Cosine-weighted directions about the probe normal with their pdf, the way a diffuse bounce
// draws them, carrying the radiance radiance(ω).
template <class Radiance>
void feedCosineSamples(const ProbeEncoding& encoding, State& state, int count, uint64_t seed, Radiance radiance) {
    Rng rng(seed, 1);
    for (int i = 0; i < count; ++i) {
        const vec3 w = sampleCosineHemisphere(vec2(rng.uniform(), rng.uniform()));
        if (w.z > 0.0f) encoding.addSample(state.data(), w, radiance(w), cosineHemispherePdf(w.z));
    }
}

// A unit normal at polar angle alpha (radians) from the probe normal.
vec3 tiltedNormal(double alpha, double azimuth) {
    return vec3(float(std::sin(alpha) * std::cos(azimuth)), float(std::sin(alpha) * std::sin(azimuth)), float(std::cos(alpha)));
}

// ∫ over the upper hemisphere of max(0, n·ω) dω for n at polar angle alpha: π (1 + cos α) / 2
// (the cosine lobe's part above the horizon, from ∫ n·ω = π cos α over the hemisphere and the
// lobe's total π).
double hemisphereCosineIntegral(double alpha) { return kPiDouble * (1.0 + std::cos(alpha)) / 2.0; }

const double kTilts[] = {0.2, 0.7, 1.2, 1.5, 2.0, 2.9};      // radians from +z, up to nearly −z
const double kAzimuths[] = {0.1, 1.3, 2.2, 3.9, 5.5};

TEST(ProbeEncoding, NamesAndStateSizesFollowKindAndResolution) {
    EXPECT_EQ(makeProbeEncoding(ProbeEncodingKind::Hemispherical, 5)->name(), "hemispherical 5x5");
    EXPECT_EQ(makeProbeEncoding(ProbeEncodingKind::Hemispherical, 5)->floatsPerProbe(), 4 * 25 + 4);
    EXPECT_EQ(makeProbeEncoding(ProbeEncodingKind::Octahedral, 8)->name(), "octahedral 8x8");
    EXPECT_EQ(makeProbeEncoding(ProbeEncodingKind::Octahedral, 8)->floatsPerProbe(), 4 * 64 + 4);
    EXPECT_EQ(makeProbeEncoding(ProbeEncodingKind::SphericalHarmonics, 1)->name(), "sh order 1");
    EXPECT_EQ(makeProbeEncoding(ProbeEncodingKind::SphericalHarmonics, 1)->floatsPerProbe(), 3 * 4 + 1);
    EXPECT_EQ(makeProbeEncoding(ProbeEncodingKind::SphericalHarmonics, 2)->name(), "sh order 2");
    EXPECT_EQ(makeProbeEncoding(ProbeEncodingKind::SphericalHarmonics, 2)->floatsPerProbe(), 3 * 9 + 1);
}

TEST(ProbeEncoding, UnsupportedResolutionsThrowNamingTheValue) {
    auto message = [](ProbeEncodingKind kind, int resolution) {
        try {
            makeProbeEncoding(kind, resolution);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("no exception");
    };
    EXPECT_EQ(message(ProbeEncodingKind::Hemispherical, 0), "hemispherical probe resolution must be in [1, 64], got 0");
    EXPECT_EQ(message(ProbeEncodingKind::Octahedral, 65), "octahedral probe resolution must be in [1, 64], got 65");
    EXPECT_EQ(message(ProbeEncodingKind::SphericalHarmonics, 3), "spherical-harmonics probe order must be 1 or 2, got 3");
    EXPECT_EQ(message(ProbeEncodingKind::SphericalHarmonics, 0), "spherical-harmonics probe order must be 1 or 2, got 0");
}

TEST(ProbeEncoding, QuadratureCoversTheHemisphereWithUnitUpperDirections) {
    for (const Config& config : kConfigs) {
        const auto encoding = makeProbeEncoding(config.kind, config.resolution);
        double sum = 0.0;
        for (std::size_t i = 0; i < encoding->quadrature().size(); ++i) {
            const QuadraturePoint& q = encoding->quadrature()[i];
            EXPECT_NEAR(glm::length(q.direction), 1.0f, 4.0 * kUlp) << encoding->name() << " node " << i;
            EXPECT_GT(q.direction.z, 0.0f) << encoding->name() << " node " << i;
            EXPECT_GT(q.solidAngle, 0.0f) << encoding->name() << " node " << i;
            sum += q.solidAngle;
        }
        // Each solid angle is exact in double and rounded once to float (half an ulp, 2^-24
        // relative), so the float values sum to 2π within 2π·2^-24.
        EXPECT_NEAR(sum, 2.0 * kPiDouble, 2.0 * kPiDouble * kUlp + 1e-12) << encoding->name();
    }
}

// A state whose bin i (reached through its quadrature node) holds value(i) and every other bin
// holds a sample too, so no bin is empty.
template <class Value>
State everyBinSampled(const ProbeEncoding& encoding, Value value) {
    State state(encoding.floatsPerProbe(), 0.0f);
    for (std::size_t i = 0; i < encoding.quadrature().size(); ++i)
        EXPECT_TRUE(encoding.addSample(state.data(), encoding.quadrature()[i].direction, value(i), 1.0f));
    return state;
}

TEST(ProbeEncoding, EveryGridBinCentreMapsBackToItsOwnBin) {
    for (const Config& config : kConfigs) {
        if (!isGrid(config)) continue;
        const auto encoding = makeProbeEncoding(config.kind, config.resolution);
        const std::size_t bins = encoding->quadrature().size();
        ASSERT_EQ(bins, std::size_t(config.resolution * config.resolution)) << encoding->name();
        // Distinct values: two centres sharing a bin would average, and leave another bin empty.
        const State state = everyBinSampled(*encoding, [](std::size_t i) { return Color(float(i + 1), 0.5f, 0.0f); });
        EXPECT_EQ(encoding->sampleWeight(state.data()), float(bins)) << encoding->name();
        std::vector<Color> read(bins);
        encoding->radianceAt(state.data(), read.data());
        for (std::size_t i = 0; i < bins; ++i) EXPECT_EQ(read[i], Color(float(i + 1), 0.5f, 0.0f)) << encoding->name() << " bin " << i;
    }
}

TEST(ProbeEncoding, HemisphericalBinsFollowRingsEvenInSinThetaAndSectorsFromPlusX) {
    for (int r : {1, 4, 5}) {
        const auto encoding = makeProbeEncoding(ProbeEncodingKind::Hemispherical, r);
        const double sectorAngle = 2.0 * kPiDouble / r;
        double projectedSum = 0.0;
        for (int ring = 0; ring < r; ++ring)
            for (int sector = 0; sector < r; ++sector) {
                const int bin = ring * r + sector;
                const QuadraturePoint& q = encoding->quadrature()[bin];
                const double sa = double(ring) / r, sb = double(ring + 1) / r;
                // Closed forms: Ω = Δφ (cos θa − cos θb), projected Ω = Δφ (sb² − sa²) / 2.
                const double solidAngle = sectorAngle * (std::sqrt(1.0 - sa * sa) - std::sqrt(1.0 - sb * sb));
                const double projected = sectorAngle * (sb * sb - sa * sa) / 2.0;
                EXPECT_NEAR(q.solidAngle, solidAngle, solidAngle * kUlp + 1e-12) << "r " << r << " bin " << bin;
                // The centre lies inside its own ring and sector.
                double phi = std::atan2(q.direction.y, q.direction.x);
                if (phi < 0.0) phi += 2.0 * kPiDouble;
                const double sinTheta = std::hypot(q.direction.x, q.direction.y);
                EXPECT_TRUE(phi >= sector * sectorAngle && phi < (sector + 1) * sectorAngle) << "r " << r << " bin " << bin;
                EXPECT_TRUE(sinTheta >= sa && sinTheta < sb) << "r " << r << " bin " << bin;
                // The bin's projected solid angle is E(+z) of a probe that sees 1 in it and 0 elsewhere:
                // one product of float-rounded values, exact to a few ulps.
                const State state = everyBinSampled(*encoding, [bin](std::size_t i) { return Color(int(i) == bin ? 1.0f : 0.0f); });
                const float e = encoding->irradiance(state.data(), vec3(0, 0, 1)).x;
                EXPECT_NEAR(e, projected, 4.0 * kUlp * projected) << "r " << r << " bin " << bin;
                projectedSum += e;
            }
        EXPECT_NEAR(projectedSum, kPiDouble, 4.0 * kUlp * kPiDouble) << "r " << r;
    }
}

TEST(ProbeEncoding, GridProjectedSolidAnglesSumToPi) {
    for (const Config& config : kConfigs) {
        if (!isGrid(config)) continue;
        const auto encoding = makeProbeEncoding(config.kind, config.resolution);
        double sum = 0.0;
        for (std::size_t bin = 0; bin < encoding->quadrature().size(); ++bin) {
            const State state = everyBinSampled(*encoding, [bin](std::size_t i) { return Color(i == bin ? 1.0f : 0.0f); });
            const float projected = encoding->irradiance(state.data(), vec3(0, 0, 1)).x;
            EXPECT_GT(projected, 0.0f) << encoding->name() << " bin " << bin;
            sum += projected;
        }
        EXPECT_NEAR(sum, kPiDouble, 4.0 * kUlp * kPiDouble) << encoding->name();
    }
}

TEST(ProbeEncoding, ConstantRadianceGivesPiLAtTheNormalAndTheHemisphereCosineIntegralWhenTilted) {
    const Color l(0.5f, 1.0f, 2.0f);
    for (const Config& config : kConfigs) {
        if (!isGrid(config)) continue;
        const auto encoding = makeProbeEncoding(config.kind, config.resolution);
        State state(encoding->floatsPerProbe(), 0.0f);
        feedCosineSamples(*encoding, state, 8192, 3, [&](const vec3&) { return l; });
        // Every bin's mean is exactly L (so is the fill of any empty bin), and E(+z) is L times a
        // float sum of the bins' projected solid angles: within (bins + 1) ulps of π L.
        const double rounding = (encoding->quadrature().size() + 1) * kUlp;
        const Color atNormal = encoding->irradiance(state.data(), vec3(0, 0, 1));
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(atNormal[c], kPiDouble * l[c], rounding * kPiDouble * l[c]) << encoding->name() << " channel " << c;
        for (double alpha : kTilts)
            for (double azimuth : kAzimuths) {
                const Color e = encoding->irradiance(state.data(), tiltedNormal(alpha, azimuth));
                for (int c = 0; c < 3; ++c) {
                    // Never more than the exact value (beyond rounding), never less by more than
                    // kProbeIrradianceTolerance per unit radiance (derived in probe_encoding.h).
                    const double exact = l[c] * hemisphereCosineIntegral(alpha);
                    EXPECT_LE(e[c], exact + kSubcellRounding * kPiDouble * l[c])
                        << encoding->name() << " α " << alpha << " φ " << azimuth;
                    EXPECT_GE(e[c], exact - kProbeIrradianceTolerance * l[c])
                        << encoding->name() << " α " << alpha << " φ " << azimuth;
                }
            }
    }
}

// A grid bin as the header documents it: its direction and dω/(ds dt) at parameters (s, t) ∈ [0, 1]².
struct BinPoint {
    glm::dvec3 direction;
    double jacobian;
};

BinPoint hemisphericalBinPoint(int bin, int r, double s, double t) {
    const int ring = bin / r, sector = bin % r;
    const double thetaA = std::asin(double(ring) / r), thetaB = std::asin(double(ring + 1) / r);
    const double theta = thetaA + s * (thetaB - thetaA), phi = 2.0 * kPiDouble * (sector + t) / r;
    return {glm::dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)),
            std::sin(theta) * (thetaB - thetaA) * 2.0 * kPiDouble / r};
}

// (u, v) → (a, b) = ((u + v)/2, (u − v)/2) → P = (a, b, 1 − |a| − |b|) on the octahedron. A face
// has normal (±1, ±1, 1)/√3 and area √3 da db, seen from the origin at distance |P| and cosine
// 1/(√3 |P|): dω = da db / |P|³ = du dv / (2 |P|³).
BinPoint octahedralBinPoint(int bin, int r, double s, double t) {
    const int row = bin / r, column = bin % r;
    const double u = -1.0 + 2.0 * (column + s) / r, v = -1.0 + 2.0 * (row + t) / r;
    const double a = 0.5 * (u + v), b = 0.5 * (u - v);
    const glm::dvec3 p(a, b, std::max(0.0, 1.0 - std::fabs(a) - std::fabs(b)));
    const double length = glm::length(p);
    return {p / length, (2.0 / r) * (2.0 / r) / (2.0 * length * length * length)};
}

// Midpoint-rule integrals over one bin on a g × g grid: the cosine integral ∫ max(0, n·ω) dω and
// the band integral ∫_{|n·ω| <= sin ρ} |n·ω| dω, the most its cut sub-cells may lose (see
// kProbeIrradianceTolerance: the same argument restricted to one bin).
struct BinIntegrals {
    double cosine = 0.0, band = 0.0;
};

template <class Point>
BinIntegrals integrateBin(Point point, const glm::dvec3& n, int g) {
    const double bandEdge = std::sin(double(kProbeSubcellRadius));
    BinIntegrals sum;
    for (int i = 0; i < g; ++i)
        for (int j = 0; j < g; ++j) {
            const BinPoint p = point((i + 0.5) / g, (j + 0.5) / g);
            const double f = glm::dot(n, p.direction), weight = p.jacobian / (double(g) * g);
            sum.cosine += std::max(0.0, f) * weight;
            if (std::fabs(f) <= bandEdge) sum.band += std::fabs(f) * weight;
        }
    return sum;
}

TEST(ProbeEncoding, EachGridBinLosesNoMoreThanItsHorizonBandAndIsExactAwayFromIt) {
    // Bin by bin, against a probe that sees 1 in that bin and 0 in every other: irradiance(n)
    // is the bin's cosine integral W. A bin the plane n·ω = 0 misses must give W exactly; a cut
    // one may lose at most its band integral B, and never gain. The reference has the midpoint
    // rule's error, estimated by Richardson from grids of 64 and 32 (O(h²): error ≈ |Δ| / 3).
    constexpr int kGrid = 64;
    const std::vector<double> tilts = {0.1, 0.4, 0.8, 1.2, 1.45, 1.6, 1.9, 2.4, 2.9};
    for (const Config& config : {Config{ProbeEncodingKind::Hemispherical, 5}, Config{ProbeEncodingKind::Hemispherical, 1},
                                 Config{ProbeEncodingKind::Octahedral, 8}, Config{ProbeEncodingKind::Octahedral, 5},
                                 Config{ProbeEncodingKind::Octahedral, 2}, Config{ProbeEncodingKind::Octahedral, 1}}) {
        const auto encoding = makeProbeEncoding(config.kind, config.resolution);
        const int r = config.resolution;
        for (int bin = 0; bin < r * r; ++bin) {
            auto point = [&](double s, double t) {
                return config.kind == ProbeEncodingKind::Hemispherical ? hemisphericalBinPoint(bin, r, s, t)
                                                                       : octahedralBinPoint(bin, r, s, t);
            };
            const State state = everyBinSampled(*encoding, [bin](std::size_t i) { return Color(int(i) == bin ? 1.0f : 0.0f); });
            for (double alpha : tilts)
                for (int k = 0; k < 8; ++k) {
                    const double azimuth = 0.3 + k * kPiDouble / 4.0;
                    const vec3 n = tiltedNormal(alpha, azimuth);
                    const BinIntegrals fine = integrateBin(point, glm::dvec3(n), kGrid);
                    const BinIntegrals coarse = integrateBin(point, glm::dvec3(n), kGrid / 2);
                    // Three times the Richardson estimate, plus the encoding's float rounding.
                    const double slack = std::fabs(fine.cosine - coarse.cosine) + kSubcellRounding * fine.cosine + 1e-9;
                    const double w = encoding->irradiance(state.data(), n).x;
                    EXPECT_LE(w, fine.cosine + slack) << encoding->name() << " bin " << bin << " α " << alpha << " φ " << azimuth;
                    EXPECT_GE(w, fine.cosine - fine.band - slack)
                        << encoding->name() << " bin " << bin << " α " << alpha << " φ " << azimuth << " band " << fine.band;
                }
        }
    }
}

TEST(ProbeEncoding, SphericalHarmonicsOfConstantRadianceAreUnbiasedForEveryNormal) {
    // E(n) = π L (1 + cos α) / 2 lies in SH bands 0 and 1, which both orders keep, and the
    // band-2 projections of the hemisphere indicator vanish (c_20 ∝ ∫ (3z² − 1) over the
    // hemisphere = 0, the others by symmetry): no truncation error at order 1 or 2. What is left
    // is Monte Carlo noise (heavy-tailed: Y_00 / pdf ∝ 1 / cos θ), measured from independent
    // probes: the mean of kProbes estimates must lie within 5 of its standard errors of E(n).
    constexpr int kProbes = 16, kSamples = 8192;
    const Color l(0.5f, 1.0f, 2.0f);
    for (int order : {1, 2}) {
        const auto encoding = makeProbeEncoding(ProbeEncodingKind::SphericalHarmonics, order);
        std::vector<State> probes(kProbes, State(encoding->floatsPerProbe(), 0.0f));
        for (int p = 0; p < kProbes; ++p) feedCosineSamples(*encoding, probes[p], kSamples, 100 + p, [&](const vec3&) { return l; });
        std::vector<vec3> normals = {vec3(0, 0, 1)};
        for (double alpha : kTilts) normals.push_back(tiltedNormal(alpha, 1.0));
        for (const vec3& n : normals) {
            const double alpha = std::acos(double(n.z));
            double sum = 0.0, sumSquares = 0.0;
            for (const State& state : probes) {
                const double e = encoding->irradiance(state.data(), n).y;  // the channel with L = 1
                EXPECT_GE(e, 0.0);
                sum += e;
                sumSquares += e * e;
            }
            const double mean = sum / kProbes;
            const double standardError = std::sqrt((sumSquares / kProbes - mean * mean) / (kProbes - 1));
            EXPECT_NEAR(mean, hemisphereCosineIntegral(alpha), 5.0 * standardError) << encoding->name() << " α " << alpha;
        }
    }
}

TEST(ProbeEncoding, SphericalHarmonicsScaleEachBandByItsCosineLobeCoefficient) {
    // L(ω) = cos θ over the hemisphere. With cosine-weighted samples L Y / pdf = π Y: no heavy
    // tail, so the noise is small. Projections: c_00 = √π / 2, c_10 = √(3/4π) · 2π/3,
    // c_20 = √(5/16π) · π/2 (from ∫ z (3z² − 1) over the hemisphere = π/2), the others 0 by
    // symmetry. So E(+z) = π/4 (band 0) + π/3 (band 1) + 5π/64 (band 2), truncating the exact
    // 2π/3 at order 1 to 7π/12 and at order 2 to 7π/12 + 5π/64; and the radiance reads back as
    // 1/4 + z/2, plus (5/32)(3z² − 1) at order 2. Means of kProbes probes, within 5 standard errors.
    constexpr int kProbes = 16, kSamples = 4096;
    for (int order : {1, 2}) {
        const auto encoding = makeProbeEncoding(ProbeEncodingKind::SphericalHarmonics, order);
        const auto& nodes = encoding->quadrature();
        std::vector<double> sum(nodes.size() + 1, 0.0), sumSquares(nodes.size() + 1, 0.0);
        for (int p = 0; p < kProbes; ++p) {
            State state(encoding->floatsPerProbe(), 0.0f);
            feedCosineSamples(*encoding, state, kSamples, 200 + p, [](const vec3& w) { return Color(w.z); });
            std::vector<Color> read(nodes.size());
            encoding->radianceAt(state.data(), read.data());
            for (std::size_t i = 0; i <= nodes.size(); ++i) {
                const double value = i < nodes.size() ? read[i].x : encoding->irradiance(state.data(), vec3(0, 0, 1)).x;
                sum[i] += value;
                sumSquares[i] += value * value;
            }
        }
        auto check = [&](std::size_t i, double expected, const std::string& what) {
            const double mean = sum[i] / kProbes;
            const double standardError = std::sqrt(std::max(0.0, sumSquares[i] / kProbes - mean * mean) / (kProbes - 1));
            EXPECT_NEAR(mean, expected, 5.0 * standardError + 1e-6) << encoding->name() << ": " << what;
        };
        check(nodes.size(), 7.0 * kPiDouble / 12.0 + (order == 2 ? 5.0 * kPiDouble / 64.0 : 0.0), "E(+z)");
        for (std::size_t i = 0; i < nodes.size(); ++i) {
            const double z = nodes[i].direction.z;
            check(i, 0.25 + 0.5 * z + (order == 2 ? 5.0 / 32.0 * (3.0 * z * z - 1.0) : 0.0), "radiance at node " + std::to_string(i));
        }
    }
}

TEST(ProbeEncoding, HemisphericalBinsAlignedWithAQuarterReproduceItsIrradianceExactly) {
    // L1 in the upper-left quarter of directions (x < 0, y > 0: sector 1 of 4), L2 elsewhere. At
    // resolution 4 the bins follow that boundary, so every bin's mean is exact.
    const Color l1(3.0f, 2.0f, 1.0f), l2(0.25f, 0.5f, 1.0f);
    auto radiance = [&](const vec3& w) { return w.x < 0.0f && w.y >= 0.0f ? l1 : l2; };
    const auto encoding = makeProbeEncoding(ProbeEncodingKind::Hemispherical, 4);
    State state(encoding->floatsPerProbe(), 0.0f);
    feedCosineSamples(*encoding, state, 8192, 5, radiance);
    std::vector<Color> read(16);
    encoding->radianceAt(state.data(), read.data());
    for (int bin = 0; bin < 16; ++bin) EXPECT_EQ(read[bin], bin % 4 == 1 ? l1 : l2) << "bin " << bin;

    // At the normal: the quarter's projected solid angle is π/4, the rest 3π/4; 17 terms of rounding.
    const double rounding = 17 * kUlp;
    const Color atNormal = encoding->irradiance(state.data(), vec3(0, 0, 1));
    for (int c = 0; c < 3; ++c) {
        const double exact = kPiDouble / 4.0 * l1[c] + 3.0 * kPiDouble / 4.0 * l2[c];
        EXPECT_NEAR(atNormal[c], exact, rounding * exact) << "channel " << c;
    }
    // Tilted by α towards the quarter, which stays wholly above n's horizon: its cosine integral is
    // n · (−π/4, π/4, π/4) (the first moment of an octant), exactly reproduced; the rest is cut
    // by the horizon and within kProbeIrradianceTolerance·L2.
    for (double alpha : {0.3, 0.7, 1.1}) {
        const vec3 n = tiltedNormal(alpha, 0.75 * kPiDouble);
        const double quarter = kPiDouble / 4.0 * (-n.x + n.y + n.z);
        const Color e = encoding->irradiance(state.data(), n);
        for (int c = 0; c < 3; ++c) {
            const double exact = l1[c] * quarter + l2[c] * (hemisphereCosineIntegral(alpha) - quarter);
            EXPECT_LE(e[c], exact + kSubcellRounding * exact) << "α " << alpha << " channel " << c;
            EXPECT_GE(e[c], exact - kProbeIrradianceTolerance * l2[c]) << "α " << alpha << " channel " << c;
        }
    }
}

TEST(ProbeEncoding, EmptyProbeHasNoSamplesAndGivesZero) {
    for (const Config& config : kConfigs) {
        const auto encoding = makeProbeEncoding(config.kind, config.resolution);
        const State state(encoding->floatsPerProbe(), 0.0f);
        EXPECT_EQ(encoding->sampleWeight(state.data()), 0.0f) << encoding->name();
        EXPECT_EQ(encoding->irradiance(state.data(), vec3(0, 0, 1)), Color(0.0f)) << encoding->name();
        EXPECT_EQ(encoding->irradiance(state.data(), tiltedNormal(1.0, 2.0)), Color(0.0f)) << encoding->name();
        std::vector<Color> read(encoding->quadrature().size(), Color(7.0f));
        encoding->radianceAt(state.data(), read.data());
        for (std::size_t i = 0; i < read.size(); ++i) EXPECT_EQ(read[i], Color(0.0f)) << encoding->name() << " node " << i;
    }
}

TEST(ProbeEncoding, OneSampleFillsEveryGridBinWithItsRadiance) {
    const Color l(0.5f, 1.0f, 2.0f);
    for (const Config& config : kConfigs) {
        const auto encoding = makeProbeEncoding(config.kind, config.resolution);
        State state(encoding->floatsPerProbe(), 0.0f);
        ASSERT_TRUE(encoding->addSample(state.data(), glm::normalize(vec3(0.3f, -0.5f, 0.4f)), l, 0.2f));
        EXPECT_EQ(encoding->sampleWeight(state.data()), 1.0f) << encoding->name();
        const Color atNormal = encoding->irradiance(state.data(), vec3(0, 0, 1));
        if (!isGrid(config)) {
            // One sample is a (noisy) estimate, but a valid one.
            EXPECT_TRUE(isFinite(atNormal) && atNormal.x >= 0.0f) << encoding->name();
            continue;
        }
        std::vector<Color> read(encoding->quadrature().size());
        encoding->radianceAt(state.data(), read.data());
        // The fill is Σ Ω L / Σ Ω over one bin: L to a couple of roundings.
        for (std::size_t i = 0; i < read.size(); ++i)
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(read[i][c], l[c], 2.0 * kUlp * l[c]) << encoding->name() << " bin " << i;
        const double rounding = (read.size() + 2) * kUlp;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(atNormal[c], kPiDouble * l[c], rounding * kPiDouble * l[c]) << encoding->name();
        const Color tilted = encoding->irradiance(state.data(), tiltedNormal(0.9, 4.0));
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(tilted[c], l[c] * hemisphereCosineIntegral(0.9), kProbeIrradianceTolerance * l[c]) << encoding->name();
    }
}

// The grids answer n = +z (every refreshed memo) from cosine integrals computed once; a normal a
// hair away from +z takes the general path and must agree to rounding (a single bin that spans
// the hemisphere is summed over its sub-cells there, exactly at +z by its moment).
TEST(ProbeEncoding, IrradianceAtThePoleEqualsItsNeighboursThroughTheGeneralPath) {
    for (const Config& config : kConfigs) {
        const auto encoding = makeProbeEncoding(config.kind, config.resolution);
        State state(encoding->floatsPerProbe(), 0.0f);
        feedCosineSamples(*encoding, state, 40, 7, [](const vec3& w) { return Color(1.0f + w.x, 2.0f * w.z, 0.5f + w.y * w.y); });
        encoding->fade(state.data(), 0.3f);  // faded bins lean on the probe's mean
        const Color pole = encoding->irradiance(state.data(), vec3(0, 0, 1));
        const Color beside = encoding->irradiance(state.data(), vec3(0.0f, 1e-30f, 1.0f));
        EXPECT_GT(pole.y, 0.0f) << encoding->name();
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(pole[c], beside[c], kSubcellRounding * beside[c]) << encoding->name() << " channel " << c;
    }
}

TEST(ProbeEncoding, EmptyGridBinsServeTheMeanOfAllTheProbesSamples) {
    // Three samples in two bins of different solid angle: the mean of the samples (2), not of
    // the bins (2.5) nor the solid-angle-weighted one.
    for (const Config& config : kConfigs) {
        if (!isGrid(config) || config.resolution < 4) continue;
        const auto encoding = makeProbeEncoding(config.kind, config.resolution);
        const auto& q = encoding->quadrature();
        State state(encoding->floatsPerProbe(), 0.0f);
        ASSERT_TRUE(encoding->addSample(state.data(), q[3].direction, Color(1.0f), 1.0f));
        ASSERT_TRUE(encoding->addSample(state.data(), q[3].direction, Color(1.0f), 1.0f));
        ASSERT_TRUE(encoding->addSample(state.data(), q[5].direction, Color(4.0f), 1.0f));
        std::vector<Color> read(q.size());
        encoding->radianceAt(state.data(), read.data());
        EXPECT_EQ(read[3], Color(1.0f)) << encoding->name();
        EXPECT_EQ(read[5], Color(4.0f)) << encoding->name();
        EXPECT_NEAR(read[0].x, 2.0, 4.0 * kUlp * 2.0) << encoding->name();
    }
}

TEST(ProbeEncoding, IgnoredSamplesLeaveTheStateUnchangedAndReturnFalse) {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const vec3 up = glm::normalize(vec3(0.2f, 0.1f, 1.0f));
    struct Invalid {
        const char* what;
        vec3 direction;
        Color radiance;
        float pdf;
    };
    const Invalid invalid[] = {
        {"direction on the horizon", vec3(1, 0, 0), Color(1.0f), 1.0f},
        {"direction below the horizon", vec3(0, 0.6f, -0.8f), Color(1.0f), 1.0f},
        {"NaN direction", vec3(nan, 0, 1), Color(1.0f), 1.0f},
        {"NaN radiance", up, Color(1.0f, nan, 1.0f), 1.0f},
        {"infinite radiance", up, Color(inf, 1.0f, 1.0f), 1.0f},
        {"zero pdf", up, Color(1.0f), 0.0f},
        {"negative pdf", up, Color(1.0f), -1.0f},
        {"NaN pdf", up, Color(1.0f), nan},
        {"infinite pdf", up, Color(1.0f), inf},
    };
    for (const Config& config : kConfigs) {
        const auto encoding = makeProbeEncoding(config.kind, config.resolution);
        State state(encoding->floatsPerProbe(), 0.0f);
        feedCosineSamples(*encoding, state, 16, 9, [](const vec3& w) { return Color(w.z); });
        const State before = state;
        for (const Invalid& sample : invalid) {
            EXPECT_FALSE(encoding->addSample(state.data(), sample.direction, sample.radiance, sample.pdf))
                << encoding->name() << ": " << sample.what;
            EXPECT_EQ(std::memcmp(state.data(), before.data(), state.size() * sizeof(float)), 0)
                << encoding->name() << ": " << sample.what;
        }
    }
}

TEST(ProbeEncoding, ExtremeFiniteRadianceNeverGivesNanOrInfinity) {
    const float largest = std::numeric_limits<float>::max();
    for (const Config& config : kConfigs) {
        const auto encoding = makeProbeEncoding(config.kind, config.resolution);
        State state(encoding->floatsPerProbe(), 0.0f);
        Rng rng(11, 12);
        int i = 0;
        // Huge and tiny radiance, the largest float, and densities from tiny to huge (SH divides).
        for (float radiance : {1e30f, 1e-30f, largest, 1e30f, 1e-30f})
            for (float pdf : {1e-30f, 1.0f, 1e30f}) {
                const vec3 w = sampleCosineHemisphere(vec2(rng.uniform(), rng.uniform()));
                EXPECT_TRUE(encoding->addSample(state.data(), w, Color(radiance), pdf)) << encoding->name() << " sample " << i;
                ++i;
            }
        std::vector<Color> read(encoding->quadrature().size());
        encoding->radianceAt(state.data(), read.data());
        for (std::size_t k = 0; k < read.size(); ++k) EXPECT_TRUE(isFinite(read[k])) << encoding->name() << " node " << k;
        for (double alpha : kTilts)
            for (double azimuth : kAzimuths) {
                const Color e = encoding->irradiance(state.data(), tiltedNormal(alpha, azimuth));
                EXPECT_TRUE(isFinite(e) && e.x >= 0.0f) << encoding->name() << " α " << alpha << " φ " << azimuth << ": " << e.x;
            }
    }
}

TEST(ProbeEncoding, SampleCountsSaturateAtTwoToTheTwentyFour) {
    // Counts are floats (a zero-filled state is an empty probe); set one to its limit through the
    // documented layout (the counts from sampleWeightsOffset() on, the probe's last, bin 0's first).
    const float limit = float(kMaxProbeSampleCount);
    for (const Config& config : kConfigs) {
        const auto encoding = makeProbeEncoding(config.kind, config.resolution);
        State state(encoding->floatsPerProbe(), 0.0f);
        const vec3 w = encoding->quadrature()[0].direction;
        ASSERT_TRUE(encoding->addSample(state.data(), w, Color(1.0f), 1.0f));
        state.back() = limit;
        const int bin0 = encoding->sampleWeightsOffset();  // the bin quadrature node 0 lies in
        if (isGrid(config)) state[bin0] = limit;
        ASSERT_TRUE(encoding->addSample(state.data(), w, Color(1.0f), 1.0f));
        EXPECT_EQ(encoding->sampleWeight(state.data()), float(kMaxProbeSampleCount)) << encoding->name();
        if (isGrid(config)) {
            EXPECT_EQ(state[bin0], limit) << encoding->name();
        }
        EXPECT_TRUE(isFinite(encoding->irradiance(state.data(), vec3(0, 0, 1)))) << encoding->name();
    }
}

// A light switched off (issue 9): 64 samples of radiance 1 from one direction, a fade by `keep`,
// then one sample of 0: the means are untouched by the fade, and the 0 gets the share
// 1 / (64 keep + 1) where a running mean gives it 1/65.
TEST(ProbeEncoding, FadingKeepsTheMeansAndGivesTheNextSampleTheShareTheOldOnesLost) {
    const vec3 direction = glm::normalize(vec3(0.3f, 0.2f, 0.9f));
    for (const Config& config : kConfigs) {
        const auto encoding = makeProbeEncoding(config.kind, config.resolution);
        State state(encoding->floatsPerProbe(), 0.0f);
        std::vector<Color> before(encoding->quadrature().size()), faded(before.size()), after(before.size());
        for (int i = 0; i < 64; ++i) encoding->addSample(state.data(), direction, Color(1.0f), 1.0f);
        encoding->radianceAt(state.data(), before.data());
        constexpr float kKeep = 0.1f;
        encoding->fade(state.data(), kKeep);
        EXPECT_FLOAT_EQ(encoding->sampleWeight(state.data()), 64.0f * kKeep) << encoding->name();
        encoding->radianceAt(state.data(), faded.data());
        encoding->addSample(state.data(), direction, Color(0.0f), 1.0f);
        encoding->radianceAt(state.data(), after.data());
        const double expected = 1.0 - 1.0 / (64.0 * kKeep + 1.0);
        for (std::size_t i = 0; i < before.size(); ++i) {
            EXPECT_EQ(faded[i], before[i]) << encoding->name() << " node " << i;
            if (before[i].r > 0.0f) {
                EXPECT_NEAR(after[i].r / before[i].r, expected, 1e-5) << encoding->name() << " node " << i;
            }
        }
    }
}

TEST(ProbeEncoding, AFadedGridBinLeansOnTheProbesMeanByTheWeightItLacks) {
    // One sample of 1 into bin A, a fade to a quarter, then three samples of 4 into bin B: A
    // weighs 0.25 and serves 0.25 · 1 + 0.75 P with the probe's mean P = (0.25 · 1 + 3 · 4) / 3.25;
    // B weighs 3 and serves its own 4; an empty bin serves P.
    for (const Config& config : kConfigs) {
        if (!isGrid(config) || config.resolution < 2) continue;
        const auto encoding = makeProbeEncoding(config.kind, config.resolution);
        const auto& q = encoding->quadrature();
        State state(encoding->floatsPerProbe(), 0.0f);
        encoding->addSample(state.data(), q[0].direction, Color(1.0f), 1.0f);
        encoding->fade(state.data(), 0.25f);
        for (int i = 0; i < 3; ++i) encoding->addSample(state.data(), q[1].direction, Color(4.0f), 1.0f);
        std::vector<Color> read(q.size());
        encoding->radianceAt(state.data(), read.data());
        const double probeMean = (0.25 * 1.0 + 3.0 * 4.0) / 3.25;
        EXPECT_NEAR(read[0].r, 0.25 + 0.75 * probeMean, 1e-5) << encoding->name();
        EXPECT_FLOAT_EQ(read[1].r, 4.0f) << encoding->name();
        EXPECT_NEAR(read[2].r, probeMean, 1e-5) << encoding->name();
    }
}

TEST(ProbeEncoding, FadingNeverEmptiesASampledProbeNorFillsAnEmptyOne) {
    for (const Config& config : kConfigs) {
        const auto encoding = makeProbeEncoding(config.kind, config.resolution);
        State empty(encoding->floatsPerProbe(), 0.0f), sampled = empty;
        encoding->fade(empty.data(), 0.5f);
        EXPECT_EQ(encoding->sampleWeight(empty.data()), 0.0f) << encoding->name();
        encoding->addSample(sampled.data(), vec3(0, 0, 1), Color(2.0f), 1.0f);
        const Color before = encoding->irradiance(sampled.data(), vec3(0, 0, 1));
        for (int i = 0; i < 100; ++i) encoding->fade(sampled.data(), 0.0f);
        EXPECT_GT(encoding->sampleWeight(sampled.data()), 0.0f) << encoding->name();
        EXPECT_EQ(encoding->irradiance(sampled.data(), vec3(0, 0, 1)), before) << encoding->name();
    }
}

}  // namespace
}  // namespace gibench
