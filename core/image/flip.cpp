#include "core/image/flip.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

namespace gibench {

namespace {

using Plane = std::vector<float>;  // one channel, rows from the top
using Kernel = std::vector<float>;  // odd length, centre in the middle

// One separable part of a filter: weight · (kernel along x) ⊗ (kernel along y).
struct SeparableTerm {
    double weight;
    Kernel alongX, alongY;
};
using SeparableFilter = std::vector<SeparableTerm>;

// linear sRGB → CIE XYZ (D65), IEC 61966-2-1 as exact fractions; glm takes columns, hence transpose.
const glm::dmat3 kRgbToXyz = glm::transpose(glm::dmat3(10135552.0 / 24577794, 8788810.0 / 24577794, 4435075.0 / 24577794,
                                                       2613072.0 / 12288897, 8788810.0 / 12288897, 887015.0 / 12288897,
                                                       1425312.0 / 73733382, 8788810.0 / 73733382, 70074185.0 / 73733382));
const glm::dmat3 kXyzToRgb = glm::inverse(kRgbToXyz);
// The white both YCxCz and CIELAB are relative to: the monitor's, RGB (1, 1, 1).
const glm::dvec3 kWhite = kRgbToXyz * glm::dvec3(1.0);

glm::dvec3 ycxczOfRgb(const glm::dvec3& rgb) {
    const glm::dvec3 v = kRgbToXyz * rgb / kWhite;
    return {116.0 * v.y - 16.0, 500.0 * (v.x - v.y), 200.0 * (v.y - v.z)};
}

glm::dvec3 rgbOfYcxcz(const glm::dvec3& ycxcz) {
    const double y = (ycxcz.x + 16.0) / 116.0;
    return kXyzToRgb * (glm::dvec3(y + ycxcz.y / 500.0, y, y - ycxcz.z / 200.0) * kWhite);
}

// CIELAB of linear RGB, then the Hunt adjustment (a*, b* scaled by 0.01 L*).
glm::dvec3 huntLabOfRgb(const glm::dvec3& rgb) {
    constexpr double delta = 6.0 / 29.0;
    const auto f = [](double t) { return t > delta * delta * delta ? std::cbrt(t) : t / (3.0 * delta * delta) + 4.0 / 29.0; };
    const glm::dvec3 v = kRgbToXyz * rgb / kWhite;
    const double fx = f(v.x), fy = f(v.y), fz = f(v.z);
    const double l = 116.0 * fy - 16.0;
    return {l, 0.01 * l * 500.0 * (fx - fy), 0.01 * l * 200.0 * (fy - fz)};
}

double hyab(const glm::dvec3& a, const glm::dvec3& b) { return std::abs(a.x - b.x) + std::hypot(a.y - b.y, a.z - b.z); }

// The largest colour distance, between green and blue, raised to qc (HPG 2020, section 4.1).
const double kPowerCmax = std::pow(hyab(huntLabOfRgb({0.0, 1.0, 0.0}), huntLabOfRgb({0.0, 0.0, 1.0})), kFlipQc);

double colorTerm(const glm::dvec3& testHuntLab, const glm::dvec3& referenceHuntLab) {
    const double power = std::pow(hyab(testHuntLab, referenceHuntLab), kFlipQc);
    const double knee = kFlipPc * kPowerCmax;
    const double value = power < knee ? kFlipPt / knee * power : kFlipPt + (power - knee) / (kPowerCmax - knee) * (1.0 - kFlipPt);
    // cmax is the largest distance in the RGB cube; the guard only absorbs rounding.
    return std::min(value, 1.0);
}

Kernel normalised(Kernel k) {
    const double sum = std::accumulate(k.begin(), k.end(), 0.0);
    for (float& v : k) v = float(v / sum);
    return k;
}

SeparableFilter contrastSensitivityFilter(FlipOpponent channel, double ppd) {
    double widest = 0.0;
    for (const FlipCsf& c : kFlipCsf) widest = std::max({widest, c.b1, c.b2});
    const int radius = int(std::ceil(3.0 * std::sqrt(widest / (2.0 * std::numbers::pi * std::numbers::pi)) * ppd));
    const FlipCsf& csf = kFlipCsf[std::size_t(channel)];

    // Each Gaussian of S(x) is separable; the 2D weights of the sum are normalised together.
    SeparableFilter terms;
    double total = 0.0;
    for (const auto& [a, b] : {std::pair{csf.a1, csf.b1}, std::pair{csf.a2, csf.b2}}) {
        if (a == 0.0) continue;
        Kernel g(std::size_t(2 * radius + 1));
        double sum = 0.0;
        for (int i = -radius; i <= radius; ++i) {
            const double degrees = i / ppd;
            g[i + radius] = float(std::exp(-std::numbers::pi * std::numbers::pi * degrees * degrees / b));
            sum += g[i + radius];
        }
        const double mass = a * std::sqrt(std::numbers::pi / b) * sum * sum;
        total += mass;
        g = normalised(g);
        terms.push_back({mass, g, g});
    }
    for (SeparableTerm& t : terms) t.weight /= total;
    return terms;
}

// The x-direction detector: (first or second derivative along x) ⊗ (Gaussian along y); positive
// and negative weights normalised apart, which stays separable since the sign depends on x alone.
SeparableFilter featureFilter(FlipFeature feature, double ppd) {
    const double sigma = 0.5 * kFlipFeatureWidthDeg * ppd;
    const int radius = int(std::ceil(3.0 * sigma));
    Kernel gauss(std::size_t(2 * radius + 1)), derivative(gauss.size());
    double positive = 0.0, negative = 0.0;
    for (int i = -radius; i <= radius; ++i) {
        const double g = std::exp(-double(i) * i / (2.0 * sigma * sigma));
        const double d = feature == FlipFeature::Edge ? -i * g : (double(i) * i / (sigma * sigma) - 1.0) * g;
        gauss[i + radius] = float(g);
        derivative[i + radius] = float(d);
        (d > 0.0 ? positive : negative) += d;
    }
    for (float& d : derivative) d = float(d > 0.0f ? d / positive : d / -negative);
    return {{1.0, derivative, normalised(gauss)}};
}

// Correlation along rows / columns, borders repeating the edge pixel.
Plane alongRows(const Plane& in, int w, int h, const Kernel& k) {
    const int r = int(k.size()) / 2;
    Plane out(in.size());
    tbb::parallel_for(0, h, [&](int y) {
        std::vector<float> padded(std::size_t(w + 2 * r));
        const float* row = &in[std::size_t(y) * w];
        for (int x = -r; x < w + r; ++x) padded[x + r] = row[std::clamp(x, 0, w - 1)];
        float* o = &out[std::size_t(y) * w];
        for (int x = 0; x < w; ++x) {
            float sum = 0.0f;
            for (int i = 0; i < int(k.size()); ++i) sum += k[i] * padded[x + i];
            o[x] = sum;
        }
    });
    return out;
}

Plane alongColumns(const Plane& in, int w, int h, const Kernel& k) {
    const int r = int(k.size()) / 2;
    Plane out(in.size(), 0.0f);
    tbb::parallel_for(0, h, [&](int y) {
        float* o = &out[std::size_t(y) * w];
        for (int i = 0; i < int(k.size()); ++i) {
            const float* row = &in[std::size_t(std::clamp(y + i - r, 0, h - 1)) * w];
            for (int x = 0; x < w; ++x) o[x] += k[i] * row[x];
        }
    });
    return out;
}

Plane filtered(const Plane& in, int w, int h, const SeparableFilter& filter) {
    Plane out(in.size(), 0.0f);
    for (const SeparableTerm& t : filter) {
        const Plane part = alongColumns(alongRows(in, w, h, t.alongX), w, h, t.alongY);
        for (std::size_t p = 0; p < out.size(); ++p) out[p] += float(t.weight) * part[p];
    }
    return out;
}

// The x and y responses' length of a detector whose y-direction version is the transpose.
Plane featureLength(const Plane& luminance, int w, int h, const SeparableFilter& alongX) {
    const SeparableTerm& t = alongX.front();
    const Plane x = alongColumns(alongRows(luminance, w, h, t.alongX), w, h, t.alongY);
    const Plane y = alongColumns(alongRows(luminance, w, h, t.alongY), w, h, t.alongX);
    Plane length(x.size());
    for (std::size_t p = 0; p < length.size(); ++p) length[p] = std::hypot(x[p], y[p]);
    return length;
}

struct Filters {
    SeparableFilter csf[3];
    SeparableFilter edge, point;
    explicit Filters(double ppd)
        : csf{contrastSensitivityFilter(FlipOpponent::Achromatic, ppd), contrastSensitivityFilter(FlipOpponent::RedGreen, ppd),
              contrastSensitivityFilter(FlipOpponent::BlueYellow, ppd)},
          edge(featureFilter(FlipFeature::Edge, ppd)),
          point(featureFilter(FlipFeature::Point, ppd)) {}
};

// What LDR-FLIP compares of one image: its filtered, Hunt-adjusted CIELAB and its features.
struct Perceived {
    std::vector<glm::dvec3> huntLab;
    Plane edges, points;
};

Perceived perceive(const Image& image, const Filters& filters) {
    const int w = image.width, h = image.height;
    const std::size_t n = image.pixelCount();
    Plane opponent[3] = {Plane(n), Plane(n), Plane(n)};
    Plane luminance(n);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t p) {
        const float* v = &image.data[p * image.channels];
        const glm::dvec3 rgb = glm::clamp(glm::dvec3(v[0], v[1], v[2]), 0.0, 1.0);
        const glm::dvec3 ycxcz = ycxczOfRgb(rgb);
        for (int c = 0; c < 3; ++c) opponent[c][p] = float(ycxcz[c]);
        luminance[p] = float((ycxcz.x + 16.0) / 116.0);
    });
    for (int c = 0; c < 3; ++c) opponent[c] = filtered(opponent[c], w, h, filters.csf[c]);

    Perceived out;
    out.huntLab.resize(n);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t p) {
        const glm::dvec3 rgb = rgbOfYcxcz({opponent[0][p], opponent[1][p], opponent[2][p]});
        out.huntLab[p] = huntLabOfRgb(glm::clamp(rgb, 0.0, 1.0));
    });
    out.edges = featureLength(luminance, w, h, filters.edge);
    out.points = featureLength(luminance, w, h, filters.point);
    return out;
}

void checkInputs(const Image& test, const Image& reference, double ppd) {
    if (test.width != reference.width || test.height != reference.height)
        throw std::invalid_argument("FLIP: image sizes differ: test " + std::to_string(test.width) + "x" + std::to_string(test.height) +
                                    ", reference " + std::to_string(reference.width) + "x" + std::to_string(reference.height));
    if (test.channels < 3 || reference.channels < 3)
        throw std::invalid_argument("FLIP needs at least 3 channels, got test " + std::to_string(test.channels) + ", reference " +
                                    std::to_string(reference.channels));
    if (!(std::isfinite(ppd) && ppd > 0.0))
        throw std::invalid_argument("FLIP: expected a positive number of pixels per degree, got " + std::to_string(ppd));
}

FlipTerms flipTerms(const Image& test, const Image& reference, const Filters& filters) {
    const Perceived x = perceive(test, filters), r = perceive(reference, filters);
    FlipTerms terms{Image(test.width, test.height, 1), Image(test.width, test.height, 1), Image(test.width, test.height, 1)};
    tbb::parallel_for(std::size_t(0), test.pixelCount(), [&](std::size_t p) {
        const double color = colorTerm(x.huntLab[p], r.huntLab[p]);
        const double difference = std::max(std::abs(x.edges[p] - r.edges[p]), std::abs(x.points[p] - r.points[p]));
        // Each length is at most √2 (weights of each sign sum to 1 on values in [0, 1]).
        const double feature = std::pow(std::min(difference / std::numbers::sqrt2, 1.0), kFlipQf);
        terms.color.data[p] = float(color);
        terms.feature.data[p] = float(feature);
        terms.flip.data[p] = float(std::pow(color, 1.0 - feature));
    });
    return terms;
}

Image toneMapped(const Image& image, double exposure) {
    Image out(image.width, image.height, 3);
    const double scale = std::exp2(exposure);
    tbb::parallel_for(std::size_t(0), image.pixelCount(), [&](std::size_t p) {
        for (int c = 0; c < 3; ++c) out.data[p * 3 + c] = float(flipToneMap(scale * double(image.data[p * image.channels + c])));
    });
    return out;
}

// The median of `values` (the mean of the two middle ones for an even count); reorders them.
double medianOf(std::vector<double>& values) {
    const std::size_t mid = values.size() / 2;
    std::nth_element(values.begin(), values.begin() + mid, values.end());
    const double upper = values[mid];
    if (values.size() % 2 == 1) return upper;
    return 0.5 * (*std::max_element(values.begin(), values.begin() + mid) + upper);
}

}  // namespace

double flipToneMap(double v) {
    const auto& k = kFlipAces;
    const double x = std::max(v, 0.0);
    return std::clamp((k[0] * x * x + k[1] * x + k[2]) / (k[3] * x * x + k[4] * x + k[5]), 0.0, 1.0);
}

FlipTerms ldrFlipTerms(const Image& test, const Image& reference, double pixelsPerDegree) {
    checkInputs(test, reference, pixelsPerDegree);
    return flipTerms(test, reference, Filters(pixelsPerDegree));
}

Image ldrFlip(const Image& test, const Image& reference, double pixelsPerDegree) {
    return ldrFlipTerms(test, reference, pixelsPerDegree).flip;
}

FlipExposures flipExposures(const Image& reference) {
    std::vector<double> luminances(reference.pixelCount());
    for (std::size_t p = 0; p < luminances.size(); ++p) {
        const float* v = &reference.data[p * reference.channels];
        luminances[p] = 0.2126 * std::max(v[0], 0.0f) + 0.7152 * std::max(v[1], 0.0f) + 0.0722 * std::max(v[2], 0.0f);
    }
    const double brightest = luminances.empty() ? 0.0 : *std::max_element(luminances.begin(), luminances.end());
    if (!(brightest > 0.0)) return {0.0, 0.0, 2};
    double median = medianOf(luminances);
    if (!(median > 0.0)) {
        std::erase_if(luminances, [](double y) { return !(y > 0.0); });
        median = medianOf(luminances);
    }

    // v_t solves (k0 − t·k3)·v² + (k1 − t·k4)·v + (k2 − t·k5) = 0, its positive root.
    const auto& k = kFlipAces;
    const double t = kFlipExposureTarget;
    const double c0 = (k[1] - k[4] * t) / (k[0] - k[3] * t), c1 = (k[2] - k[5] * t) / (k[0] - k[3] * t);
    const double target = -0.5 * c0 + std::sqrt(0.25 * c0 * c0 - c1);
    FlipExposures range;
    range.start = std::log2(target / brightest);
    range.stop = std::log2(target / median);
    range.count = std::max(2, int(std::ceil(range.stop - range.start)));
    return range;
}

Image hdrFlip(const Image& test, const Image& reference, const FlipExposures& exposures, double pixelsPerDegree) {
    checkInputs(test, reference, pixelsPerDegree);
    if (exposures.count < 1 || !std::isfinite(exposures.start) || !std::isfinite(exposures.stop))
        throw std::invalid_argument("HDR-FLIP: expected at least 1 exposure between finite bounds, got " +
                                    std::to_string(exposures.count) + " from " + std::to_string(exposures.start) + " to " +
                                    std::to_string(exposures.stop));
    const Filters filters(pixelsPerDegree);
    const double step = (exposures.stop - exposures.start) / std::max(exposures.count - 1, 1);
    Image worst(test.width, test.height, 1, 0.0f);
    for (int i = 0; i < exposures.count; ++i) {
        const double exposure = exposures.start + i * step;
        const Image flip = flipTerms(toneMapped(test, exposure), toneMapped(reference, exposure), filters).flip;
        for (std::size_t p = 0; p < worst.data.size(); ++p) worst.data[p] = std::max(worst.data[p], flip.data[p]);
    }
    return worst;
}

Image hdrFlip(const Image& test, const Image& reference, double pixelsPerDegree) {
    checkInputs(test, reference, pixelsPerDegree);
    return hdrFlip(test, reference, flipExposures(reference), pixelsPerDegree);
}

FlipStatistics flipStatistics(const Image& flipMap) {
    if (flipMap.data.empty()) throw std::invalid_argument("flipStatistics: empty map");
    std::vector<double> values(flipMap.data.begin(), flipMap.data.end());
    const double sum = std::accumulate(values.begin(), values.end(), 0.0);
    FlipStatistics s;
    s.mean = sum / double(values.size());
    s.max = *std::max_element(values.begin(), values.end());
    s.median = medianOf(values);
    return s;
}

Image flipContrastSensitivityKernel(FlipOpponent channel, double pixelsPerDegree) {
    const SeparableFilter filter = contrastSensitivityFilter(channel, pixelsPerDegree);
    const int size = int(filter.front().alongX.size());
    Image kernel(size, size, 1, 0.0f);
    for (const SeparableTerm& t : filter)
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) kernel.at(x, y, 0) += float(t.weight * t.alongX[x] * t.alongY[y]);
    return kernel;
}

Image flipFeatureKernel(FlipFeature feature, double pixelsPerDegree) {
    const SeparableTerm t = featureFilter(feature, pixelsPerDegree).front();
    const int size = int(t.alongX.size());
    Image kernel(size, size, 1);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) kernel.at(x, y, 0) = t.alongX[x] * t.alongY[y];
    return kernel;
}

}  // namespace gibench
