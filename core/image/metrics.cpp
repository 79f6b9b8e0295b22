#include "core/image/metrics.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

namespace gibench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr float kLargestFloat = std::numeric_limits<float>::max();

std::string sizeText(const Image& image) { return std::to_string(image.width) + "x" + std::to_string(image.height); }

void checkComparable(const Image& test, const Image& reference) {
    if (test.width != reference.width || test.height != reference.height)
        throw std::invalid_argument("image sizes differ: test " + sizeText(test) + ", reference " + sizeText(reference));
    if (test.channels < 3 || reference.channels < 3)
        throw std::invalid_argument("metrics need at least 3 channels, got test " + std::to_string(test.channels) +
                                    ", reference " + std::to_string(reference.channels));
}

const float* pixel(const Image& image, std::size_t p) { return &image.data[p * image.channels]; }

bool finitePixel(const float* v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

// Rows in parallel, their sums added in row order: the same double whatever the thread count.
template <class RowSum>
double sumRows(int height, const RowSum& rowSum) {
    std::vector<double> sums(std::size_t(height), 0.0);
    tbb::parallel_for(0, height, [&](int y) { sums[y] = rowSum(y); });
    return std::accumulate(sums.begin(), sums.end(), 0.0);
}

// One channel's term of each metric, as documented in metrics.h.
double term(ErrorMapKind kind, double x, double r) {
    const double d = x - r;
    switch (kind) {
        case ErrorMapKind::SquaredError: return d * d;
        case ErrorMapKind::RelMse: return d * d / (r * r + kRelMseEpsilon);
        case ErrorMapKind::Smape: return std::abs(d) / (std::abs(x) + std::abs(r) + kSmapeEpsilon);
        case ErrorMapKind::Mape: return std::abs(d) / (std::abs(r) + kMapeEpsilon);
    }
    return kNaN;
}

double pixelError(ErrorMapKind kind, const float* x, const float* r) {
    return (term(kind, x[0], r[0]) + term(kind, x[1], r[1]) + term(kind, x[2], r[2])) / 3.0;
}

// Reinhard, then sRGB: the display value t(v) of metrics.h.
double toDisplay(double v) {
    const double c = std::max(v, 0.0);
    return srgbEncode(c / (1.0 + c));
}

struct MeanAndRobust {
    double mean;
    double robust;
};

// The mean of the per-pixel errors of `kind`, and the mean without the N / kRobustDropDivisor
// largest, a non-finite pixel's error being +inf.
MeanAndRobust meanAndRobust(const Image& test, const Image& reference, ErrorMapKind kind) {
    const int w = test.width, h = test.height;
    const std::size_t n = test.pixelCount();
    std::vector<double> errors(n);
    tbb::parallel_for(0, h, [&](int y) {
        for (std::size_t p = std::size_t(y) * w; p < std::size_t(y + 1) * w; ++p) {
            const float* x = pixel(test, p);
            const float* r = pixel(reference, p);
            errors[p] = finitePixel(x) && finitePixel(r) ? pixelError(kind, x, r) : kInf;
        }
    });
    auto sumOfErrors = [&] {
        return sumRows(h, [&](int y) {
            const auto row = errors.begin() + std::ptrdiff_t(y) * w;
            return std::accumulate(row, row + w, 0.0);
        });
    };
    const double mean = sumOfErrors() / double(n);
    const std::size_t drop = n / kRobustDropDivisor;
    if (drop == 0) return {mean, mean};

    // Errors above the smallest dropped one go; of those equal to it, the first in scan order go
    // until exactly `drop` are gone. A dropped error becomes 0 so the row sums stay in order.
    std::vector<double> sorted = errors;
    const auto firstDropped = sorted.begin() + std::ptrdiff_t(n - drop);
    std::nth_element(sorted.begin(), firstDropped, sorted.end());
    const double threshold = *firstDropped;
    std::size_t tiesToDrop = drop - std::size_t(std::count_if(firstDropped, sorted.end(), [&](double e) { return e > threshold; }));
    for (double& e : errors) {
        if (e > threshold) {
            e = 0.0;
        } else if (e == threshold && tiesToDrop > 0) {
            e = 0.0;
            --tiesToDrop;
        }
    }
    return {mean, sumOfErrors() / double(n - drop)};
}

double psnr(const Image& test, const Image& reference) {
    const int w = test.width;
    const double sum = sumRows(test.height, [&](int y) {
        double s = 0.0;
        for (std::size_t p = std::size_t(y) * w; p < std::size_t(y + 1) * w; ++p)
            for (int c = 0; c < 3; ++c) {
                const double d = toDisplay(pixel(test, p)[c]) - toDisplay(pixel(reference, p)[c]);
                s += d * d;
            }
        return s;
    });
    const double mse = sum / (3.0 * double(test.pixelCount()));
    const double smallestMse = kDisplayPeak * kDisplayPeak * std::pow(10.0, -kMaxPsnrDb / 10.0);
    return 10.0 * std::log10(kDisplayPeak * kDisplayPeak / std::max(mse, smallestMse));
}

// Gaussian-weighted sums over a window of the two display luminances a, b and their products.
struct WindowSums {
    double a = 0.0, b = 0.0, aa = 0.0, bb = 0.0, ab = 0.0;

    void add(double weight, const WindowSums& s) {
        a += weight * s.a;
        b += weight * s.b;
        aa += weight * s.aa;
        bb += weight * s.bb;
        ab += weight * s.ab;
    }
};

double meanSsim(const Image& test, const Image& reference) {
    const int w = test.width, h = test.height;
    constexpr int kTaps = 2 * kSsimRadius + 1;

    std::vector<double> a(test.pixelCount()), b(test.pixelCount());
    tbb::parallel_for(0, h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            a[std::size_t(y) * w + x] = toDisplay(luminance(test.rgb(x, y)));
            b[std::size_t(y) * w + x] = toDisplay(luminance(reference.rgb(x, y)));
        }
    });

    // The window is separable, and so is its in-image part: its weight is inside(x) · inside(y).
    std::array<double, kTaps> g;
    for (int k = -kSsimRadius; k <= kSsimRadius; ++k) g[k + kSsimRadius] = std::exp(-double(k * k) / (2.0 * kSsimSigma * kSsimSigma));
    auto insideWeights = [&](int size) {
        std::vector<double> weights(std::size_t(size), 0.0);
        for (int i = 0; i < size; ++i)
            for (int k = -kSsimRadius; k <= kSsimRadius; ++k)
                if (i + k >= 0 && i + k < size) weights[i] += g[k + kSsimRadius];
        return weights;
    };
    const std::vector<double> insideX = insideWeights(w), insideY = insideWeights(h);

    const double c1 = (kSsimK1 * kDisplayPeak) * (kSsimK1 * kDisplayPeak);
    const double c2 = (kSsimK2 * kDisplayPeak) * (kSsimK2 * kDisplayPeak);

    // Bands of rows in parallel; each filters horizontally the rows its windows reach (its own
    // and kSsimRadius more on each side), so memory stays per band. 64 rows keep that overlap small.
    constexpr int kBandRows = 64;
    std::vector<double> rowSums(std::size_t(h), 0.0);
    tbb::parallel_for(0, (h + kBandRows - 1) / kBandRows, [&](int band) {
        const int y0 = band * kBandRows, y1 = std::min(h, y0 + kBandRows);
        const int q0 = std::max(0, y0 - kSsimRadius), q1 = std::min(h, y1 + kSsimRadius);
        std::vector<WindowSums> horizontal(std::size_t(q1 - q0) * w);
        for (int q = q0; q < q1; ++q)
            for (int x = 0; x < w; ++x)
                for (int k = -kSsimRadius; k <= kSsimRadius; ++k)
                    if (x + k >= 0 && x + k < w) {
                        const std::size_t i = std::size_t(q) * w + x + k;
                        horizontal[std::size_t(q - q0) * w + x].add(g[k + kSsimRadius], {a[i], b[i], a[i] * a[i], b[i] * b[i], a[i] * b[i]});
                    }

        for (int y = y0; y < y1; ++y) {
            double rowSum = 0.0;
            for (int x = 0; x < w; ++x) {
                WindowSums s;
                for (int k = -kSsimRadius; k <= kSsimRadius; ++k)
                    if (y + k >= 0 && y + k < h) s.add(g[k + kSsimRadius], horizontal[std::size_t(y + k - q0) * w + x]);
                const double weight = insideX[x] * insideY[y];
                const double muA = s.a / weight, muB = s.b / weight;
                const double varA = s.aa / weight - muA * muA, varB = s.bb / weight - muB * muB;
                const double cov = s.ab / weight - muA * muB;
                rowSum += (2.0 * muA * muB + c1) * (2.0 * cov + c2) / ((muA * muA + muB * muB + c1) * (varA + varB + c2));
            }
            rowSums[y] = rowSum;
        }
    });
    return std::accumulate(rowSums.begin(), rowSums.end(), 0.0) / double(test.pixelCount());
}

Json finiteNumber(const char* name, double v, const ImageMetrics& m) {
    if (!std::isfinite(v))
        throw std::domain_error(std::string("metric ") + name + " is " + (std::isnan(v) ? "NaN" : v > 0.0 ? "+inf" : "-inf") + " (" +
                                std::to_string(m.nonfinitePixels) + " of " + std::to_string(m.pixels) +
                                " pixels not finite); JSON cannot hold it");
    return v;
}

}  // namespace

ImageMetrics computeMetrics(const Image& test, const Image& reference) {
    checkComparable(test, reference);
    ImageMetrics m;
    m.pixels = test.pixelCount();
    for (std::size_t p = 0; p < m.pixels; ++p)
        if (!finitePixel(pixel(test, p)) || !finitePixel(pixel(reference, p))) ++m.nonfinitePixels;

    const MeanAndRobust mse = meanAndRobust(test, reference, ErrorMapKind::SquaredError);
    const MeanAndRobust relMse = meanAndRobust(test, reference, ErrorMapKind::RelMse);
    const MeanAndRobust smape = meanAndRobust(test, reference, ErrorMapKind::Smape);
    const MeanAndRobust mape = meanAndRobust(test, reference, ErrorMapKind::Mape);
    m.mseRobust = mse.robust;
    m.relMseRobust = relMse.robust;
    m.smapeRobust = smape.robust;
    m.mapeRobust = mape.robust;

    if (m.nonfinitePixels > 0) {
        m.mse = m.rmse = m.relMse = m.smape = m.mape = m.psnr = m.ssim = m.mean = m.referenceMean = kNaN;
        return m;
    }
    for (std::size_t p = 0; p < m.pixels; ++p) {
        const float *x = pixel(test, p), *r = pixel(reference, p);
        m.mean += (double(x[0]) + double(x[1]) + double(x[2])) / 3.0;
        m.referenceMean += (double(r[0]) + double(r[1]) + double(r[2])) / 3.0;
    }
    if (m.pixels > 0) {
        m.mean /= double(m.pixels);
        m.referenceMean /= double(m.pixels);
    }
    m.mse = mse.mean;
    m.rmse = std::sqrt(mse.mean);
    m.relMse = relMse.mean;
    m.smape = smape.mean;
    m.mape = mape.mean;
    m.psnr = psnr(test, reference);
    m.ssim = meanSsim(test, reference);
    return m;
}

Json toJson(const ImageMetrics& m) {
    return Json{
        {"mse", finiteNumber("mse", m.mse, m)},
        {"rmse", finiteNumber("rmse", m.rmse, m)},
        {"relmse", finiteNumber("relmse", m.relMse, m)},
        {"smape", finiteNumber("smape", m.smape, m)},
        {"mape", finiteNumber("mape", m.mape, m)},
        {"psnr", finiteNumber("psnr", m.psnr, m)},
        {"ssim", finiteNumber("ssim", m.ssim, m)},
        {"mse_robust", finiteNumber("mse_robust", m.mseRobust, m)},
        {"relmse_robust", finiteNumber("relmse_robust", m.relMseRobust, m)},
        {"smape_robust", finiteNumber("smape_robust", m.smapeRobust, m)},
        {"mape_robust", finiteNumber("mape_robust", m.mapeRobust, m)},
        {"mean", finiteNumber("mean", m.mean, m)},
        {"reference_mean", finiteNumber("reference_mean", m.referenceMean, m)},
        {"pixels", m.pixels},
        {"nonfinite_pixels", m.nonfinitePixels},
    };
}

Image errorMap(const Image& test, const Image& reference, ErrorMapKind kind) {
    checkComparable(test, reference);
    Image map(test.width, test.height, 1);
    tbb::parallel_for(0, test.height, [&](int y) {
        for (std::size_t p = std::size_t(y) * test.width; p < std::size_t(y + 1) * test.width; ++p) {
            const float* x = pixel(test, p);
            const float* r = pixel(reference, p);
            map.data[p] = finitePixel(x) && finitePixel(r) ? float(std::min(pixelError(kind, x, r), double(kLargestFloat))) : float(kNaN);
        }
    });
    return map;
}

}  // namespace gibench
