#include "methods/probe_cache/probe_encoding.h"

#include "core/util/lane_select.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

// The bound kProbeIrradianceTolerance, with f = n·ω and ρ = kProbeSubcellRadius: irradiance()
// gives a sub-cell C that the plane n·ω = 0 cuts max(0, ∫_C f) in place of ∫_C max(0, f), losing
// min(∫_C f⁺, ∫_C f⁻) <= ∫ |f| over the part of C beyond the plane from C's centroid direction.
// That part lies within ρ of the plane, in the band |f| <= sin ρ, and the parts of different
// sub-cells are disjoint, so the loss is at most ∫ |f| over the band's upper half: π sin² ρ <= πρ².
// The tests measure about a seventh of it.

namespace gibench {
namespace {

using glm::dvec3;

constexpr double kTwoPi = 2.0 * 3.14159265358979323846;
constexpr int kMaxGridResolution = 64;
// Points per edge when a region's boundary is walked to bound it by a cone.
constexpr int kBoundarySamples = 32;
// Sub-cells are summed this many at a time (two SSE or one AVX register).
constexpr std::size_t kLanes = 8;

Color saturate(const Color& c) { return glm::clamp(c, Color(-kMaxProbeRadiance), Color(kMaxProbeRadiance)); }

// One more sample in a running mean of samples of total weight `count` so far (saturating at
// kMaxProbeSampleCount); returns the weight the new sample gets, 1/(count + 1).
float countOneMore(float& count) {
    count = std::min(count + 1.0f, float(kMaxProbeSampleCount));
    return 1.0f / count;
}

// fade(): the weight of a sampled bin or probe never reaches 0, which means empty.
constexpr float kSmallestFadedWeight = 0x1p-20f;
// Without a branch: whether a bin has samples is as unpredictable as which bins the paths reach
// (the same reason as servedRadiance's select).
void fadeWeight(float& count, float keep) {
    const float faded = count * keep;
    count = laneSelect(laneMask(count > 0.0f), laneSelect(laneMask(faded < kSmallestFadedWeight), kSmallestFadedWeight, faded), count);
}

// A running mean stays between its old value and the new sample, so it never overflows where a
// sum of saturated radiances could.
void foldIntoMean(float* mean, const Color& value, float weight) {
    for (int c = 0; c < 3; ++c) mean[c] += (value[c] - mean[c]) * weight;
}

// ---- Construction-time geometry (double precision) ----

// Angle between unit vectors, accurate also for nearly equal or opposite ones.
double angleBetween(const dvec3& a, const dvec3& b) { return 2.0 * std::atan2(glm::length(a - b), glm::length(a + b)); }

// A region of the hemisphere: its exact solid angle and first moment ∫ ω dω, and its boundary as
// a closed polyline of unit directions (for bounding cones only).
struct Region {
    double solidAngle = 0.0;
    dvec3 moment{0.0};
    std::vector<dvec3> boundary;
};

// Half-angle of the cone around the region's centroid direction that holds the whole region. The
// direction farthest from the axis lies on the boundary (the angular distance to the axis has no
// maximum inside a region that excludes the antipode). A boundary point lies within half an arc
// of a sample, and the arc between two samples (great or latitude circle, far shorter than π) is
// less than twice their angular spacing: padding by one spacing keeps the cone conservative.
double coneHalfAngle(const Region& region) {
    const dvec3 axis = glm::normalize(region.moment);
    double farthest = 0.0, spacing = 0.0;
    for (std::size_t i = 0; i < region.boundary.size(); ++i) {
        const dvec3& p = region.boundary[i];
        farthest = std::max(farthest, angleBetween(axis, p));
        spacing = std::max(spacing, angleBetween(p, region.boundary[(i + 1) % region.boundary.size()]));
    }
    return farthest + spacing;
}

dvec3 sphericalDirection(double theta, double phi) {
    return dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
}

// φ ∈ [phiA, phiB], θ ∈ [thetaA, thetaB], in closed form: solid angle Δφ (cos θa − cos θb);
// moment (Δ sin φ · I, −Δ cos φ · I, Δφ (sin² θb − sin² θa) / 2) with I = ∫ sin² θ dθ.
Region zoneSector(double phiA, double phiB, double thetaA, double thetaB) {
    auto sinSquaredIntegral = [](double t) { return 0.5 * t - 0.25 * std::sin(2.0 * t); };
    const double s = sinSquaredIntegral(thetaB) - sinSquaredIntegral(thetaA);
    const double sa = std::sin(thetaA), sb = std::sin(thetaB);
    Region r;
    r.solidAngle = (phiB - phiA) * (std::cos(thetaA) - std::cos(thetaB));
    r.moment = dvec3((std::sin(phiB) - std::sin(phiA)) * s, (std::cos(phiA) - std::cos(phiB)) * s,
                     (phiB - phiA) * (sb * sb - sa * sa) * 0.5);
    // Latitude edges at fixed θ, meridians at fixed φ, walked around the sector.
    auto walk = [&r](double theta0, double phi0, double theta1, double phi1) {
        for (int i = 0; i < kBoundarySamples; ++i) {
            const double t = double(i) / kBoundarySamples;
            r.boundary.push_back(sphericalDirection(theta0 + t * (theta1 - theta0), phi0 + t * (phi1 - phi0)));
        }
    };
    walk(thetaA, phiA, thetaA, phiB);
    walk(thetaA, phiB, thetaB, phiB);
    walk(thetaB, phiB, thetaB, phiA);
    walk(thetaB, phiA, thetaA, phiA);
    return r;
}

// Hemi-octahedral map: (u, v) ∈ [-1, 1]² turned by 45° onto the diamond |a| + |b| <= 1, lifted to
// the octahedron face (a, b, 1 − |a| − |b|) and projected onto the sphere.
dvec3 octahedralDirection(double u, double v) {
    const double a = 0.5 * (u + v), b = 0.5 * (u - v);
    return glm::normalize(dvec3(a, b, std::max(0.0, 1.0 - std::fabs(a) - std::fabs(b))));
}

// A spherical triangle with great-circle edges: solid angle by Van Oosterom & Strackee, moment by
// Lambert's formula ½ Σ_edges (edge angle) · (unit edge-plane normal), oriented outwards.
void addSphericalTriangle(Region& r, const dvec3& p0, const dvec3& p1, const dvec3& p2) {
    const double numerator = std::fabs(glm::dot(p0, glm::cross(p1, p2)));
    const double denominator = 1.0 + glm::dot(p0, p1) + glm::dot(p1, p2) + glm::dot(p2, p0);
    const dvec3 p[3] = {p0, p1, p2};
    dvec3 moment(0.0);
    for (int i = 0; i < 3; ++i) {
        const dvec3 normal = glm::cross(p[i], p[(i + 1) % 3]);
        const double length = glm::length(normal);
        if (length > 0.0) moment += angleBetween(p[i], p[(i + 1) % 3]) * normal / length;
    }
    moment *= 0.5;
    if (glm::dot(moment, p0 + p1 + p2) < 0.0) moment = -moment;
    r.solidAngle += 2.0 * std::atan2(numerator, denominator);
    r.moment += moment;
}

void addOctahedralBoundary(Region& r, double u0, double u1, double v0, double v1) {
    const double corners[5][2] = {{u0, v0}, {u1, v0}, {u1, v1}, {u0, v1}, {u0, v0}};
    for (int e = 0; e < 4; ++e)
        for (int i = 0; i < kBoundarySamples; ++i) {
            const double t = double(i) / kBoundarySamples;
            r.boundary.push_back(octahedralDirection(corners[e][0] + t * (corners[e + 1][0] - corners[e][0]),
                                                     corners[e][1] + t * (corners[e + 1][1] - corners[e][1])));
        }
}

// Cell (iu, iv) of an n × n grid over [-1, 1]². The octahedron's edges u = ±v meet the grid lines
// only at grid points, so each edge of a cell lies on one face and maps to a great-circle arc:
// the cell's image is the spherical quadrilateral through its corners, two spherical triangles.
Region octahedralCell(int iu, int iv, int n) {
    auto coordinate = [n](int i) { return double(2 * i - n) / n; };
    const double u0 = coordinate(iu), u1 = coordinate(iu + 1), v0 = coordinate(iv), v1 = coordinate(iv + 1);
    const dvec3 c00 = octahedralDirection(u0, v0), c10 = octahedralDirection(u1, v0);
    const dvec3 c11 = octahedralDirection(u1, v1), c01 = octahedralDirection(u0, v1);
    Region r;
    addSphericalTriangle(r, c00, c10, c11);
    addSphericalTriangle(r, c00, c11, c01);
    addOctahedralBoundary(r, u0, u1, v0, v1);
    return r;
}

// A bin as construction builds it: the bin itself, its sub-cells and its corners. Edges between
// corners are great-circle arcs, except the latitude edges of a hemispherical bin (its sector
// [phiA, phiB] at polar angles thetaA and thetaB).
struct BinShape {
    Region bin;
    std::vector<Region> subcells;
    dvec3 corners[4];
    bool hasLatitudeEdges = false;
    double phiA = 0.0, phiB = 0.0, thetaA = 0.0, thetaB = 0.0;
};

double largestConeHalfAngle(const std::vector<Region>& regions) {
    double largest = 0.0;
    for (const Region& r : regions) largest = std::max(largest, coneHalfAngle(r));
    return largest;
}

// Sector `sector`, ring `ring` of the hemispherical grid; sub-cells are uniform in θ and φ inside
// the bin, refined along whichever side is longer until every one fits in kProbeSubcellRadius.
BinShape hemisphericalBin(int sector, int ring, int resolution) {
    const double phiA = kTwoPi * sector / resolution, phiB = kTwoPi * (sector + 1) / resolution;
    const double thetaA = std::asin(double(ring) / resolution), thetaB = std::asin(double(ring + 1) / resolution);
    BinShape shape{zoneSector(phiA, phiB, thetaA, thetaB), {},
                   {sphericalDirection(thetaA, phiA), sphericalDirection(thetaA, phiB), sphericalDirection(thetaB, phiB),
                    sphericalDirection(thetaB, phiA)},
                   true, phiA, phiB, thetaA, thetaB};
    int thetaCells = 1, phiCells = 1;
    for (;;) {
        shape.subcells.clear();
        for (int i = 0; i < thetaCells; ++i)
            for (int j = 0; j < phiCells; ++j)
                shape.subcells.push_back(zoneSector(phiA + (phiB - phiA) * j / phiCells, phiA + (phiB - phiA) * (j + 1) / phiCells,
                                                    thetaA + (thetaB - thetaA) * i / thetaCells,
                                                    thetaA + (thetaB - thetaA) * (i + 1) / thetaCells));
        if (largestConeHalfAngle(shape.subcells) <= kProbeSubcellRadius) return shape;
        const double thetaSide = (thetaB - thetaA) / thetaCells, phiSide = std::sin(thetaB) * (phiB - phiA) / phiCells;
        (thetaSide > phiSide ? thetaCells : phiCells) += 1;
    }
}

// All bins of the octahedral grid, each cut into k × k sub-cells with the smallest k for which
// every sub-cell fits in kProbeSubcellRadius (the map stretches little, so one k suits all bins).
// The octahedron's edges u = ±v meet a bin's edges only at its corners, so those edges are
// great-circle arcs.
std::vector<BinShape> octahedralBins(int resolution) {
    for (int k = 1;; ++k) {
        const int n = resolution * k;
        std::vector<BinShape> bins(std::size_t(resolution) * resolution);
        bool fits = true;
        for (int row = 0; row < resolution && fits; ++row)
            for (int column = 0; column < resolution && fits; ++column) {
                BinShape& shape = bins[std::size_t(row) * resolution + column];
                for (int i = 0; i < k; ++i)
                    for (int j = 0; j < k; ++j) {
                        Region cell = octahedralCell(column * k + j, row * k + i, n);
                        shape.bin.solidAngle += cell.solidAngle;
                        shape.bin.moment += cell.moment;
                        shape.subcells.push_back(std::move(cell));
                    }
                fits = largestConeHalfAngle(shape.subcells) <= kProbeSubcellRadius;
                const double step = 2.0 / resolution;
                const double u0 = -1.0 + column * step, u1 = u0 + step, v0 = -1.0 + row * step, v1 = v0 + step;
                addOctahedralBoundary(shape.bin, u0, u1, v0, v1);
                shape.corners[0] = octahedralDirection(u0, v0);
                shape.corners[1] = octahedralDirection(u1, v0);
                shape.corners[2] = octahedralDirection(u1, v1);
                shape.corners[3] = octahedralDirection(u0, v1);
            }
        if (fits) return bins;
    }
}

// ---- Grids of bins ----

// State: the means first, per bin (R, G, B) in bin order and then the probe's (the running mean
// radiance of all its samples), then the sample counts in the same order, the probe's last.
class BinnedEncoding : public ProbeEncoding {
public:
    int floatsPerProbe() const override { return 4 * binCount() + 4; }
    int sampleWeightsOffset() const override { return 3 * binCount() + 3; }

    bool addSample(float* state, const vec3& local, const Color& radiance, float pdf) const override {
        if (!acceptsSample(local, radiance, pdf)) return false;
        const Color value = saturate(radiance);
        const int bin = binIndex(local);
        foldIntoMean(state + 3 * bin, value, countOneMore(state[sampleWeightsOffset() + bin]));
        foldIntoMean(state + meanOffset(), value, countOneMore(state[countOffset()]));
        return true;
    }

    void fade(float* state, float keep) const override {
        for (int i = 0; i <= binCount(); ++i) fadeWeight(state[sampleWeightsOffset() + i], keep);  // the bins' and the probe's
    }

    float sampleWeight(const float* state) const override { return state[countOffset()]; }

    Color irradiance(const float* state, const vec3& n) const override {
        if (state[countOffset()] == 0.0f) return Color(0.0f);
        if (n.x == 0.0f && n.y == 0.0f && n.z == 1.0f) {  // the memo's normal (ProbeLight::refresh), every sampled probe every frame
            Color sum(0.0f);
            for (std::size_t i = 0; i < m_bins.size(); ++i) sum += m_poleCosine[i] * servedRadiance(state, int(i));
            return sum;
        }
        const float horizontal = std::sqrt(n.x * n.x + n.y * n.y);
        Color sum(0.0f);
        for (std::size_t i = 0; i < m_bins.size(); ++i) sum += cosineIntegral(m_bins[i], n, horizontal) * servedRadiance(state, int(i));
        return sum;
    }

    const std::vector<QuadraturePoint>& quadrature() const override { return m_quadrature; }

    void radianceAt(const float* state, Color* out) const override {
        const bool empty = state[countOffset()] == 0.0f;
        for (std::size_t i = 0; i < m_bins.size(); ++i) out[i] = empty ? Color(0.0f) : servedRadiance(state, int(i));
    }

protected:
    explicit BinnedEncoding(const std::vector<BinShape>& shapes) {
        for (const BinShape& shape : shapes) {
            Bin bin;
            bin.moment = vec3(shape.bin.moment);
            bin.solidAngle = float(shape.bin.solidAngle);
            bin.axis = vec3(glm::normalize(shape.bin.moment));
            const double halfAngle = coneHalfAngle(shape.bin);
            // A small margin covers the float rounding of n·axis; a cone of 90° or more never
            // lies on one side of a plane through the origin.
            bin.coneSin = halfAngle < 0.5 * kPi ? float(std::sin(halfAngle)) + 1e-5f : 2.0f;
            m_quadrature.push_back({bin.axis, bin.solidAngle});
            for (int c = 0; c < 4; ++c) bin.corners[c] = vec3(shape.corners[c]);
            // Within 45° of its axis, a bin cannot hold −m while its corners all lie on m's side;
            // a hemispherical bin's latitude edges rule that out at any size.
            bin.sideTestAnyDirection = shape.hasLatitudeEdges || halfAngle < 0.25 * kPi;
            if (shape.hasLatitudeEdges) {
                bin.latitudeEdges = true;
                bin.wholeCircle = shape.phiB - shape.phiA > kPi + 1e-9;
                bin.sectorStart = vec2(std::cos(shape.phiA), std::sin(shape.phiA));
                bin.sectorEnd = vec2(std::cos(shape.phiB), std::sin(shape.phiB));
                bin.sinTheta = vec2(std::sin(shape.thetaA), std::sin(shape.thetaB));
                bin.cosTheta = vec2(std::cos(shape.thetaA), std::cos(shape.thetaB));
            }
            bin.subBegin = uint32_t(m_subX.size());
            for (const Region& cell : shape.subcells) {
                m_subX.push_back(float(cell.moment.x));
                m_subY.push_back(float(cell.moment.y));
                m_subZ.push_back(float(cell.moment.z));
            }
            // Zero moments pad the bin to whole lanes; they add max(0, 0) = 0.
            while (m_subX.size() % kLanes != 0) {
                m_subX.push_back(0.0f);
                m_subY.push_back(0.0f);
                m_subZ.push_back(0.0f);
            }
            bin.subEnd = uint32_t(m_subX.size());
            m_bins.push_back(bin);
        }
        for (const Bin& bin : m_bins) m_poleCosine.push_back(cosineIntegral(bin, vec3(0.0f, 0.0f, 1.0f), 0.0f));
    }

    int binCount() const { return int(m_bins.size()); }
    // Where the probe's mean radiance and its count lie in its state.
    int meanOffset() const { return 3 * binCount(); }
    int countOffset() const { return sampleWeightsOffset() + binCount(); }

    // What a bin of a probe with samples serves: its mean where its count is at least one, else
    // a blend towards the probe's mean P by the weight it lacks, c m + (1 − c) P. An empty bin
    // serves P (a young probe has many, and black would darken it); a bin whose count the
    // bounded history has faded (ProbeEncoding::fade) follows the probe's samples, which arrive a
    // bin count (25) times as often as its own, so a change of the light leaves stale bins that
    // much sooner. Unfaded, a sampled bin serves its own mean.
    Color servedRadiance(const float* state, int i) const {
        const float* bin = state + 3 * i;
        const float* mean = state + meanOffset();
        // max(0, ·) as a select: GCC made std::max a branch here, taken or not as the bins happen
        // to be sampled, and mispredicted often enough to triple the cost of a probe's E(+z).
        const float lacking = 1.0f - state[sampleWeightsOffset() + i];
        const float pull = laneSelect(laneMask(lacking > 0.0f), lacking, 0.0f);
        return Color(bin[0] + (mean[0] - bin[0]) * pull, bin[1] + (mean[1] - bin[1]) * pull, bin[2] + (mean[2] - bin[2]) * pull);
    }

    // The bin a local direction with z > 0 falls in.
    virtual int binIndex(const vec3& local) const = 0;

private:
    struct Bin {
        vec3 moment;  // ∫ ω dω over the bin: n·moment is its cosine integral when n·ω >= 0 all over it
        float solidAngle;
        vec3 axis;     // the bin's centroid direction (its quadrature node) and the axis of a cone
        float coneSin; // around it that holds the bin: sin of its half-angle, or > 1 for none
        vec3 corners[4];
        // Whether onPositiveSide(m) is exact for every m; else only for m.z > 0, where −m lies
        // below the horizon and so outside every bin.
        bool sideTestAnyDirection = false;
        bool latitudeEdges = false;  // hemispherical: edges at polar angles θa, θb over a sector
        bool wholeCircle = false;    // the sector is the whole circle (resolution 1)
        vec2 sectorStart{0.0f}, sectorEnd{0.0f};  // unit azimuth directions bounding the sector
        vec2 sinTheta{0.0f}, cosTheta{0.0f};      // of θa and θb
        uint32_t subBegin = 0, subEnd = 0;        // its sub-cells in m_subX/Y/Z
    };

    // Whether m·ω >= 0 all over the bin, if the bin cannot hold −m (see sideTestAnyDirection).
    // The lowest point of a linear function on a region of the sphere that excludes −m lies on
    // its boundary. A great-circle edge shorter than π between two corners on m's side stays
    // there; a latitude edge is lowest at a corner or, when its sector holds the azimuth of −m,
    // there, where m·ω = cos θ m_z − sin θ |m_xy|. With −m inside a hemispherical bin, that value
    // at θb is −cos(θb − θ(−m)) < 0 (or the pole corner is negative), so the test also fails.
    static bool onPositiveSide(const Bin& bin, const vec3& m, float horizontal) {
        for (const vec3& corner : bin.corners)
            if (glm::dot(m, corner) < 0.0f) return false;
        if (!bin.latitudeEdges) return true;
        const vec2 lowest(-m.x, -m.y);
        const bool inSector = bin.wholeCircle || (bin.sectorStart.x * lowest.y - bin.sectorStart.y * lowest.x >= 0.0f &&
                                                  lowest.x * bin.sectorEnd.y - lowest.y * bin.sectorEnd.x >= 0.0f);
        if (!inSector) return true;
        return bin.cosTheta.x * m.z - bin.sinTheta.x * horizontal >= 0.0f &&
               bin.cosTheta.y * m.z - bin.sinTheta.y * horizontal >= 0.0f;
    }

    // ∫ over the bin of max(0, n·ω) dω (horizontal = |n_xy|): exact for a bin wholly on one side of
    // the plane n·ω = 0 (a cheap cone test, then the exact side test), else summed over
    // sub-cells, each exact unless the plane cuts it.
    float cosineIntegral(const Bin& bin, const vec3& n, float horizontal) const {
        const float t = glm::dot(n, bin.axis);
        if (t >= bin.coneSin) return std::max(0.0f, glm::dot(n, bin.moment));
        if (t <= -bin.coneSin) return 0.0f;
        if ((bin.sideTestAnyDirection || n.z > 0.0f) && onPositiveSide(bin, n, horizontal))
            return std::max(0.0f, glm::dot(n, bin.moment));
        if ((bin.sideTestAnyDirection || n.z < 0.0f) && onPositiveSide(bin, -n, horizontal)) return 0.0f;
        // Independent lanes let the compiler vectorise the sum (it may not reorder one float sum).
        float lanes[kLanes] = {};
        const float* x = m_subX.data() + bin.subBegin;
        const float* y = m_subY.data() + bin.subBegin;
        const float* z = m_subZ.data() + bin.subBegin;
        for (std::size_t k = 0, end = bin.subEnd - bin.subBegin; k < end; k += kLanes)
            for (std::size_t l = 0; l < kLanes; ++l) lanes[l] += std::max(0.0f, n.x * x[k + l] + n.y * y[k + l] + n.z * z[k + l]);
        float sum = 0.0f;
        for (float lane : lanes) sum += lane;
        return sum;
    }

    std::vector<Bin> m_bins;
    std::vector<float> m_poleCosine;  // cosineIntegral() of each bin at n = +z, the same floats irradiance() would compute
    std::vector<float> m_subX, m_subY, m_subZ;  // sub-cell moments, structure of arrays for the inner loop
    std::vector<QuadraturePoint> m_quadrature;
};

class HemisphericalEncoding final : public BinnedEncoding {
public:
    explicit HemisphericalEncoding(int resolution) : BinnedEncoding(shapes(resolution)), m_resolution(resolution) {}

    std::string name() const override {
        return "hemispherical " + std::to_string(m_resolution) + "x" + std::to_string(m_resolution);
    }

private:
    static std::vector<BinShape> shapes(int resolution) {
        std::vector<BinShape> bins;
        for (int ring = 0; ring < resolution; ++ring)
            for (int sector = 0; sector < resolution; ++sector) bins.push_back(hemisphericalBin(sector, ring, resolution));
        return bins;
    }

    int binIndex(const vec3& w) const override {
        float phi = std::atan2(w.y, w.x);
        if (phi < 0.0f) phi += 2.0f * kPi;
        const float horizontal = w.x * w.x + w.y * w.y;
        const float sinTheta = std::sqrt(horizontal / (horizontal + w.z * w.z));  // tolerates a non-unit w
        const int sector = std::min(int(phi * (0.5f * kInvPi) * m_resolution), m_resolution - 1);
        const int ring = std::min(int(sinTheta * m_resolution), m_resolution - 1);
        return ring * m_resolution + sector;
    }

    int m_resolution;
};

class OctahedralEncoding final : public BinnedEncoding {
public:
    explicit OctahedralEncoding(int resolution) : BinnedEncoding(octahedralBins(resolution)), m_resolution(resolution) {}

    std::string name() const override {
        return "octahedral " + std::to_string(m_resolution) + "x" + std::to_string(m_resolution);
    }

private:
    int binIndex(const vec3& w) const override {
        const float norm1 = std::fabs(w.x) + std::fabs(w.y) + w.z;
        const float a = w.x / norm1, b = w.y / norm1;
        auto cell = [this](float t) { return std::clamp(int((t + 1.0f) * 0.5f * m_resolution), 0, m_resolution - 1); };
        return cell(a - b) * m_resolution + cell(a + b);
    }

    int m_resolution;
};

// ---- Spherical harmonics ----

constexpr int kShQuadratureSide = 8;
constexpr int kShQuadraturePoints = kShQuadratureSide * kShQuadratureSide;

// Real spherical harmonics Y_lm for l <= 2 in the order (0,0), (1,-1), (1,0), (1,1), (2,-2),
// (2,-1), (2,0), (2,1), (2,2); the first `count` of them.
void shBasis(const vec3& w, int count, float* y) {
    y[0] = 0.282094792f;  // 1 / (2 √π)
    if (count == 1) return;
    y[1] = 0.488602512f * w.y;  // √(3 / 4π)
    y[2] = 0.488602512f * w.z;
    y[3] = 0.488602512f * w.x;
    if (count == 4) return;
    y[4] = 1.092548431f * w.x * w.y;  // √(15 / 4π)
    y[5] = 1.092548431f * w.y * w.z;
    y[6] = 0.315391565f * (3.0f * w.z * w.z - 1.0f);  // √(5 / 16π)
    y[7] = 1.092548431f * w.x * w.z;
    y[8] = 0.546274215f * (w.x * w.x - w.y * w.y);  // √(15 / 16π)
}

// State: (order + 1)² coefficients × RGB (coefficient-major), then the sample count. Coefficient
// c_lm is the running mean of L(ω) Y_lm(ω) / pdf(ω): a Monte Carlo projection of the radiance
// times the hemisphere indicator.
class SphericalHarmonicsEncoding final : public ProbeEncoding {
public:
    explicit SphericalHarmonicsEncoding(int order)
        : m_order(order), m_coefficients((order + 1) * (order + 1)) {
        // Equal-solid-angle cells: 8 sectors × 8 rings uniform in cos θ, each read at its centroid.
        for (int ring = 0; ring < kShQuadratureSide; ++ring)
            for (int sector = 0; sector < kShQuadratureSide; ++sector) {
                const Region cell = zoneSector(kTwoPi * sector / kShQuadratureSide, kTwoPi * (sector + 1) / kShQuadratureSide,
                                               std::acos(1.0 - double(ring) / kShQuadratureSide),
                                               std::acos(1.0 - double(ring + 1) / kShQuadratureSide));
                m_quadrature.push_back({vec3(glm::normalize(cell.moment)), float(cell.solidAngle)});
            }
        m_basisAtQuadrature.resize(std::size_t(m_coefficients) * kShQuadraturePoints);
        for (int i = 0; i < kShQuadraturePoints; ++i) {
            float y[9];
            shBasis(m_quadrature[i].direction, m_coefficients, y);
            for (int k = 0; k < m_coefficients; ++k) m_basisAtQuadrature[std::size_t(k) * kShQuadraturePoints + i] = y[k];
        }
    }

    std::string name() const override { return "sh order " + std::to_string(m_order); }
    int floatsPerProbe() const override { return 3 * m_coefficients + 1; }
    int sampleWeightsOffset() const override { return 3 * m_coefficients; }

    bool addSample(float* state, const vec3& local, const Color& radiance, float pdf) const override {
        if (!acceptsSample(local, radiance, pdf)) return false;
        float y[9];
        shBasis(local, m_coefficients, y);
        const float weight = countOneMore(state[3 * m_coefficients]);
        const Color l = saturate(radiance);
        for (int k = 0; k < m_coefficients; ++k) {
            // In double: L Y / pdf overflows a float for a tiny pdf; saturated like the radiance.
            const glm::dvec3 projected = glm::dvec3(l) * double(y[k]) / double(pdf);
            foldIntoMean(state + 3 * k, Color(glm::clamp(projected, -double(kMaxProbeRadiance), double(kMaxProbeRadiance))),
                         weight);
        }
        return true;
    }

    void fade(float* state, float keep) const override { fadeWeight(state[3 * m_coefficients], keep); }
    float sampleWeight(const float* state) const override { return state[3 * m_coefficients]; }

    // Ramamoorthi & Hanrahan 2001: the clamped cosine convolves band l by Â_l (π, 2π/3, π/4).
    Color irradiance(const float* state, const vec3& n) const override {
        if (state[3 * m_coefficients] == 0.0f) return Color(0.0f);
        static constexpr float kBandScale[9] = {kPi,
                                                2.0f * kPi / 3.0f, 2.0f * kPi / 3.0f, 2.0f * kPi / 3.0f,
                                                0.25f * kPi, 0.25f * kPi, 0.25f * kPi, 0.25f * kPi, 0.25f * kPi};
        float y[9];
        shBasis(n, m_coefficients, y);
        Color e(0.0f);
        for (int k = 0; k < m_coefficients; ++k) e += (kBandScale[k] * y[k]) * coefficient(state, k);
        return glm::max(e, Color(0.0f));
    }

    const std::vector<QuadraturePoint>& quadrature() const override { return m_quadrature; }

    // Truncated SH ring below zero near sharp features; negative radiance is clamped to 0.
    void radianceAt(const float* state, Color* out) const override {
        // Channel by channel over all nodes: loops the compiler vectorises.
        float channels[3][kShQuadraturePoints] = {};
        for (int k = 0; k < m_coefficients; ++k) {
            const float* basis = &m_basisAtQuadrature[std::size_t(k) * kShQuadraturePoints];
            for (int c = 0; c < 3; ++c) {
                const float coefficient = state[3 * k + c];
                for (int i = 0; i < kShQuadraturePoints; ++i) channels[c][i] += coefficient * basis[i];
            }
        }
        for (int i = 0; i < kShQuadraturePoints; ++i)
            out[i] = glm::max(Color(channels[0][i], channels[1][i], channels[2][i]), Color(0.0f));
    }

private:
    static Color coefficient(const float* state, int k) { return Color(state[3 * k], state[3 * k + 1], state[3 * k + 2]); }

    int m_order;
    int m_coefficients;
    std::vector<QuadraturePoint> m_quadrature;
    std::vector<float> m_basisAtQuadrature;  // Y_lm at every quadrature node, coefficient-major
};

}  // namespace

const EnumChoices<ProbeEncodingKind>& probeEncodingChoices() {
    static const EnumChoices<ProbeEncodingKind> choices = {
        {"hemispherical", ProbeEncodingKind::Hemispherical},
        {"octahedral", ProbeEncodingKind::Octahedral},
        {"sh", ProbeEncodingKind::SphericalHarmonics},
    };
    return choices;
}

std::unique_ptr<ProbeEncoding> makeProbeEncoding(ProbeEncodingKind kind, int resolution) {
    switch (kind) {
    case ProbeEncodingKind::Hemispherical:
    case ProbeEncodingKind::Octahedral:
        if (resolution < 1 || resolution > kMaxGridResolution)
            throw std::invalid_argument(std::string(kind == ProbeEncodingKind::Hemispherical ? "hemispherical" : "octahedral") +
                                        " probe resolution must be in [1, " + std::to_string(kMaxGridResolution) + "], got " +
                                        std::to_string(resolution));
        if (kind == ProbeEncodingKind::Hemispherical) return std::make_unique<HemisphericalEncoding>(resolution);
        return std::make_unique<OctahedralEncoding>(resolution);
    case ProbeEncodingKind::SphericalHarmonics:
        if (resolution != 1 && resolution != 2)
            throw std::invalid_argument("spherical-harmonics probe order must be 1 or 2, got " + std::to_string(resolution));
        return std::make_unique<SphericalHarmonicsEncoding>(resolution);
    }
    throw std::invalid_argument("unknown probe encoding kind");
}

}  // namespace gibench
