#pragma once
// Do two Monte Carlo renders estimate the same image? A z-test per block of pixels and channel,
// in the spirit of Mitsuba 3's render tests, plus a z-test per channel on the image mean.
//
// Each render gives, per pixel and channel, a mean and the variance of that mean (its squared
// standard error). Pixels are independent, so a block's mean has variance Σ var / count², and
// the two renders are independent, so z = (a − b) / sqrt(se_a² + se_b²) is standard normal when
// both estimate the same value (the block means hold hundreds of samples or more: the central
// limit theorem applies). Every block and channel is one test; α is spread over all of them with
// Šidák's correction, α_test = 1 − (1 − α)^(1/tests), so that two agreeing renders fail *some*
// test with probability α in all. Channels of a block are correlated, and for correlated
// two-sided z-tests Šidák's correction is conservative (Šidák 1967), so α stays an upper bound.
// The image mean is tested per channel too (Šidák over the three), never summed over channels:
// the channels of a pixel come from the same paths, so their errors are strongly correlated and
// a sum's variance is not the sum of theirs (2.2 times more in the Cornell box).
//
// A z-test is only as good as its standard errors, and an estimated standard error is itself
// noise: where light arrives through rare paths, a block's mean rests on a few large samples, its
// estimated error is far too small (0 when no sample found the light) and z is meaningless. The
// effective sample count ESS = (Σ x)² / Σ x² over the block's samples says how many samples its
// mean really rests on (k for k equal non-zero samples among zeros). With ESS samples the
// relative error of the estimated standard error is about 1 / (2 sqrt(ESS)), so at ESS >= 100 it
// is within 5 % and z at the Šidák threshold (~4) within 0.2. Blocks below that are reported,
// not judged. The two sides are not symmetric: b is the reference (an estimator that may run
// short of samples in dark places), a is the renderer under test; a block where b is short is
// not judged, but a block where a is exactly zero while b is well sampled is judged (an `a` that
// is black where b sees light is the bug to find, not noise), and so is a block black in both.

#include "core/image/image.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace gibench::test {

// One render's estimate: per pixel and channel (3, interleaved, rows from the top) the mean and
// the variance of that mean, and the samples every pixel averages.
struct PixelEstimates {
    int width = 0;
    int height = 0;
    int samplesPerPixel = 0;
    std::vector<double> mean;
    std::vector<double> variance;

    PixelEstimates() = default;
    PixelEstimates(int w, int h, int samples)
        : width(w), height(h), samplesPerPixel(samples), mean(std::size_t(w) * h * 3, 0.0), variance(mean.size(), 0.0) {}
    std::size_t index(int x, int y, int c) const { return (std::size_t(y) * width + x) * 3 + c; }
};

// The "total" and "variance" layers of a path_traced frame of `samplesPerPixel` samples.
inline PixelEstimates estimatesFromLayers(const LayeredImage& image, int samplesPerPixel) {
    const Layer* total = image.find("total");
    const Layer* variance = image.find("variance");
    if (!total || !variance) throw std::invalid_argument("estimatesFromLayers: the image needs layers total and variance");
    PixelEstimates e(image.width, image.height, samplesPerPixel);
    for (std::size_t i = 0; i < e.mean.size(); ++i) {
        e.mean[i] = total->image.data[i];
        e.variance[i] = variance->image.data[i];
    }
    return e;
}

// Two-sided standard-normal quantile: the z with P(|Z| > z) = alpha, by bisection of erfc (no
// closed form; 100 halvings of [0, 40] are far below double precision).
inline double twoSidedNormalQuantile(double alpha) {
    double lo = 0.0, hi = 40.0;
    for (int i = 0; i < 100; ++i) {
        const double mid = 0.5 * (lo + hi);
        (std::erfc(mid / std::sqrt(2.0)) > alpha ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

// Šidák's per-test level for `tests` tests at family-wise level alpha.
inline double sidakAlpha(double alpha, std::size_t tests) { return 1.0 - std::pow(1.0 - alpha, 1.0 / double(tests)); }

struct BlockZ {
    int x0 = 0, y0 = 0;  // top-left pixel of the block
    int channel = 0;
    double meanA = 0.0, meanB = 0.0;
    double standardError = 0.0;  // of meanA − meanB
    double z = 0.0;               // 0 when both sides are exact and equal, ±inf when exact and unequal
    double effectiveSamplesA = 0.0, effectiveSamplesB = 0.0;  // ESS; 0 when every sample is 0
    bool judged = true;  // enough effective samples for the test (see the top of this file)
    bool pass = true;    // judged and |z| within the threshold, or not judged
};

struct BlockComparison {
    int blockSize = 0;
    double alpha = 0.0;
    double threshold = 0.0;  // |z| above this fails a block (Šidák-corrected)
    double minEffectiveSamples = 0.0;
    std::vector<BlockZ> blocks;  // every block × channel
    std::size_t judged = 0;      // blocks with enough effective samples
    std::size_t passed = 0;      // judged blocks within the threshold
    // The image mean of each channel over every pixel: three more tests, at level alpha together.
    double imageMeanA[3] = {0.0, 0.0, 0.0}, imageMeanB[3] = {0.0, 0.0, 0.0}, imageZ[3] = {0.0, 0.0, 0.0};
    double imageStandardError[3] = {0.0, 0.0, 0.0};  // of imageMeanA − imageMeanB
    double imageThreshold = 0.0;

    double judgedFraction() const { return blocks.empty() ? 1.0 : double(judged) / double(blocks.size()); }
    double passFraction() const { return judged == 0 ? 1.0 : double(passed) / double(judged); }  // of the judged blocks
    bool imageMeanPasses() const {
        return std::fabs(imageZ[0]) <= imageThreshold && std::fabs(imageZ[1]) <= imageThreshold && std::fabs(imageZ[2]) <= imageThreshold;
    }
    // The channel whose image mean differs most, in standard errors.
    int worstImageChannel() const {
        int w = 0;
        for (int c = 1; c < 3; ++c)
            if (std::fabs(imageZ[c]) > std::fabs(imageZ[w])) w = c;
        return w;
    }
    // The judged block of largest |z| (the first block when none is judged).
    const BlockZ& worst() const {
        const BlockZ* w = &blocks.front();
        for (const BlockZ& b : blocks)
            if (b.judged && (!w->judged || std::fabs(b.z) > std::fabs(w->z))) w = &b;
        return *w;
    }
};

namespace detail {

// z of two means with standard errors; two exact values (no noise on either side) agree only
// when they are equal up to the float rounding of a stored image (a few ulps of the larger).
inline double zScore(double a, double b, double varianceA, double varianceB) {
    const double variance = varianceA + varianceB;
    if (variance > 0.0) return (a - b) / std::sqrt(variance);
    const double rounding = 8.0 * double(std::numeric_limits<float>::epsilon()) * std::max(std::fabs(a), std::fabs(b));
    if (std::fabs(a - b) <= rounding) return 0.0;
    return a > b ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity();
}

// Σ x and Σ x² over the n samples behind a pixel mean and its variance (of the mean).
struct SampleSums {
    double sum = 0.0, sumSquares = 0.0;

    void add(double mean, double varianceOfMean, int n) {
        sum += n * mean;
        sumSquares += double(n) * (n - 1.0) * varianceOfMean + n * mean * mean;
    }
    double effectiveSamples() const { return sumSquares > 0.0 ? sum * sum / sumSquares : 0.0; }
};

}  // namespace detail

// The effective samples below which a block is not judged, from the 5 % bound above.
inline constexpr double kMinEffectiveSamples = 100.0;

// Compares render a (under test) with render b (the reference) over blockSize × blockSize blocks
// (edge blocks may be smaller) at family-wise level alpha. The Šidák correction counts every
// block, judged or not (fixed before looking at the data; conservative). Throws
// std::invalid_argument when the sizes differ or a sample count is unknown.
inline BlockComparison compareBlocks(const PixelEstimates& a, const PixelEstimates& b, int blockSize, double alpha = 0.01,
                                     double minEffectiveSamples = kMinEffectiveSamples) {
    if (a.width != b.width || a.height != b.height || blockSize < 1 || a.samplesPerPixel < 1 || b.samplesPerPixel < 1)
        throw std::invalid_argument("compareBlocks: images of different sizes, a block size below 1 or no sample count");
    BlockComparison out;
    out.blockSize = blockSize;
    out.alpha = alpha;
    out.minEffectiveSamples = minEffectiveSamples;
    const int blocksX = (a.width + blockSize - 1) / blockSize, blocksY = (a.height + blockSize - 1) / blockSize;
    out.threshold = twoSidedNormalQuantile(sidakAlpha(alpha, std::size_t(blocksX) * blocksY * 3));
    out.imageThreshold = twoSidedNormalQuantile(sidakAlpha(alpha, 3));

    double sumA[3] = {0.0, 0.0, 0.0}, sumB[3] = {0.0, 0.0, 0.0}, varA[3] = {0.0, 0.0, 0.0}, varB[3] = {0.0, 0.0, 0.0};
    for (int by = 0; by < blocksY; ++by)
        for (int bx = 0; bx < blocksX; ++bx)
            for (int c = 0; c < 3; ++c) {
                BlockZ block;
                block.x0 = bx * blockSize;
                block.y0 = by * blockSize;
                block.channel = c;
                double blockA = 0.0, blockB = 0.0, blockVarA = 0.0, blockVarB = 0.0;
                detail::SampleSums samplesA, samplesB;
                int count = 0;
                for (int y = block.y0; y < std::min(block.y0 + blockSize, a.height); ++y)
                    for (int x = block.x0; x < std::min(block.x0 + blockSize, a.width); ++x) {
                        const std::size_t i = a.index(x, y, c);
                        blockA += a.mean[i];
                        blockB += b.mean[i];
                        blockVarA += a.variance[i];
                        blockVarB += b.variance[i];
                        samplesA.add(a.mean[i], a.variance[i], a.samplesPerPixel);
                        samplesB.add(b.mean[i], b.variance[i], b.samplesPerPixel);
                        ++count;
                    }
                sumA[c] += blockA;
                sumB[c] += blockB;
                varA[c] += blockVarA;
                varB[c] += blockVarB;
                block.meanA = blockA / count;
                block.meanB = blockB / count;
                const double n2 = double(count) * count;
                block.standardError = std::sqrt((blockVarA + blockVarB) / n2);
                block.z = detail::zScore(block.meanA, block.meanB, blockVarA / n2, blockVarB / n2);
                block.effectiveSamplesA = samplesA.effectiveSamples();
                block.effectiveSamplesB = samplesB.effectiveSamples();
                const bool aBlack = samplesA.sumSquares == 0.0, bBlack = samplesB.sumSquares == 0.0;
                block.judged = (aBlack && bBlack) ||
                               (block.effectiveSamplesB >= minEffectiveSamples && (aBlack || block.effectiveSamplesA >= minEffectiveSamples));
                block.pass = !block.judged || std::fabs(block.z) <= out.threshold;
                out.judged += block.judged ? 1 : 0;
                out.passed += block.judged && block.pass ? 1 : 0;
                out.blocks.push_back(block);
            }
    const double n = double(a.width) * a.height, n2 = n * n;
    for (int c = 0; c < 3; ++c) {
        out.imageMeanA[c] = sumA[c] / n;
        out.imageMeanB[c] = sumB[c] / n;
        out.imageZ[c] = detail::zScore(out.imageMeanA[c], out.imageMeanB[c], varA[c] / n2, varB[c] / n2);
        out.imageStandardError[c] = std::sqrt((varA[c] + varB[c]) / n2);
    }
    return out;
}

// A summary for failure messages: the test levels, the image means and the worst blocks.
inline std::ostream& operator<<(std::ostream& os, const BlockComparison& r) {
    os << "blocks " << r.blockSize << "x" << r.blockSize << " x 3 channels: " << r.judged << "/" << r.blocks.size()
       << " judged (ESS >= " << r.minEffectiveSamples << "), " << r.passed << "/" << r.judged << " of those pass |z| <= " << r.threshold
       << " (Sidak, alpha " << r.alpha << "); image mean per channel (|z| <= " << r.imageThreshold << "):";
    for (int c = 0; c < 3; ++c)
        os << " " << "RGB"[c] << " a " << r.imageMeanA[c] << " b " << r.imageMeanB[c] << " a/b " << r.imageMeanA[c] / r.imageMeanB[c] << " z "
           << r.imageZ[c] << (c < 2 ? ";" : "");
    std::vector<BlockZ> failing;
    for (const BlockZ& b : r.blocks)
        if (!b.pass) failing.push_back(b);
    std::sort(failing.begin(), failing.end(), [](const BlockZ& a, const BlockZ& b) { return std::fabs(a.z) > std::fabs(b.z); });
    if (failing.empty() && !r.blocks.empty() && r.worst().judged) failing.push_back(r.worst());
    os << (failing.size() == 1 && failing.front().pass ? "\n  worst block:" : "\n  failing blocks, worst first:");
    for (std::size_t i = 0; i < std::min<std::size_t>(failing.size(), 8); ++i) {
        const BlockZ& b = failing[i];
        os << "\n    pixels (" << b.x0 << "," << b.y0 << ") channel " << "RGB"[b.channel] << ": a " << b.meanA << " b " << b.meanB
           << " a/b " << b.meanA / b.meanB << " se " << b.standardError << " z " << b.z << " ESS a " << b.effectiveSamplesA << " b "
           << b.effectiveSamplesB;
    }
    if (failing.size() > 8) os << "\n    ... and " << failing.size() - 8 << " more";
    return os;
}

}  // namespace gibench::test
