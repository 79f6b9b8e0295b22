#include "core/image/flip.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <numeric>
#include <random>

namespace gibench {
namespace {

Image filled(int w, int h, const std::function<vec3(int, int)>& color) {
    Image image(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) image.setRgb(x, y, color(x, y));
    return image;
}

Image flat(int w, int h, vec3 color) {
    return filled(w, h, [&](int, int) { return color; });
}

Image noise(int w, int h, unsigned seed, float scale) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, scale);
    return filled(w, h, [&](int, int) { return vec3(u(rng), u(rng), u(rng)); });
}

double mean(const Image& map) { return flipStatistics(map).mean; }

// CIELAB (D65) of the sRGB primaries green and blue, as published (e.g. Lindbloom's calculator),
// then Hunt-adjusted: an independent route to the paper's cmax.
double powerCmaxFromPublishedLab() {
    const double green[3] = {87.7347, -86.1827, 83.1793}, blue[3] = {32.2970, 79.1875, -107.8602};
    const double dl = green[0] - blue[0];
    const double da = 0.01 * green[0] * green[1] - 0.01 * blue[0] * blue[1];
    const double db = 0.01 * green[0] * green[2] - 0.01 * blue[0] * blue[2];
    return std::pow(std::abs(dl) + std::hypot(da, db), kFlipQc);
}

TEST(Flip, DefaultObserverHas67PixelsPerDegree) {
    EXPECT_NEAR(kFlipDefaultPixelsPerDegree, 67.0206, 1e-4);
}

TEST(Flip, IdenticalImagesGiveZeroEverywhere) {
    const Image a = noise(40, 30, 1, 1.0f), bright = noise(40, 30, 2, 50.0f);
    for (const float v : ldrFlip(a, a).data) ASSERT_EQ(v, 0.0f);
    for (const float v : hdrFlip(bright, bright).data) ASSERT_EQ(v, 0.0f);
}

TEST(Flip, ValuesLieInTheUnitInterval) {
    for (unsigned seed = 0; seed < 4; ++seed) {
        const Image x = noise(32, 24, seed, 1.0f), r = noise(32, 24, seed + 100, 1.0f);
        for (const float v : ldrFlip(x, r).data) ASSERT_TRUE(v >= 0.0f && v <= 1.0f) << v;
        const Image hx = noise(32, 24, seed + 200, 1000.0f), hr = noise(32, 24, seed + 300, 0.01f);
        for (const float v : hdrFlip(hx, hr).data) ASSERT_TRUE(v >= 0.0f && v <= 1.0f) << v;
    }
    // The two most distant colours of the paper: the colour term reaches 1.
    const FlipTerms extreme = ldrFlipTerms(flat(16, 16, {0, 1, 0}), flat(16, 16, {0, 0, 1}));
    for (const float v : extreme.color.data) EXPECT_NEAR(v, 1.0f, 1e-5f);
}

TEST(Flip, BlackAgainstWhiteIsNearOneAsTheRedistributionPrescribes) {
    // Flat images: no features, FLIP = ΔEc. HyAB(black, white) = 100 (ΔL* only) lies above
    // pc·cmax, so the paper maps it into (pt, 1]: 0.95 + 0.05·(100^qc − pc·cmax)/(cmax − pc·cmax).
    const double cmax = powerCmaxFromPublishedLab(), power = std::pow(100.0, kFlipQc);
    const double expected = kFlipPt + (power - kFlipPc * cmax) / (cmax - kFlipPc * cmax) * (1.0 - kFlipPt);
    EXPECT_NEAR(expected, 0.967, 0.001);
    const Image black = flat(24, 24, vec3(0.0f)), white = flat(24, 24, vec3(1.0f));
    for (const float v : ldrFlip(black, white).data) ASSERT_NEAR(v, expected, 2e-4);
    // Feature weights of each sign cancel on a flat image up to float rounding (~1e-7), which
    // the square root of qf lifts to ~3e-4: still no visible feature.
    for (const float v : ldrFlipTerms(black, white).feature.data) ASSERT_LT(v, 1e-3f);
}

TEST(Flip, LdrFlipIsSymmetricInTestAndReference) {
    const Image a = noise(32, 32, 7, 1.0f), b = noise(32, 32, 8, 1.0f);
    const FlipTerms ab = ldrFlipTerms(a, b), ba = ldrFlipTerms(b, a);
    EXPECT_EQ(ab.color.data, ba.color.data);
    EXPECT_EQ(ab.feature.data, ba.feature.data);
    EXPECT_EQ(ab.flip.data, ba.flip.data);
}

TEST(Flip, CombinationIsColourTermToThePowerOneMinusFeatureTerm) {
    const FlipTerms t = ldrFlipTerms(noise(24, 24, 3, 1.0f), noise(24, 24, 4, 1.0f));
    for (std::size_t p = 0; p < t.flip.data.size(); ++p)
        ASSERT_NEAR(t.flip.data[p], std::pow(t.color.data[p], 1.0 - t.feature.data[p]), 1e-6) << "pixel " << p;
}

TEST(Flip, ErrorOnAFlatRegionGrowsWithTheColourDifference) {
    const Image reference = flat(24, 24, vec3(0.3f, 0.3f, 0.3f));
    for (const vec3 direction : {vec3(1, 1, 1), vec3(1, 0, 0), vec3(0, 0, 1)}) {
        double previous = 0.0;
        for (int step = 1; step <= 14; ++step) {
            const double flip = mean(ldrFlip(flat(24, 24, vec3(0.3f) + 0.05f * float(step) * direction), reference));
            EXPECT_GT(flip, previous) << "step " << step << " along " << direction.x << "," << direction.y << "," << direction.z;
            previous = flip;
        }
    }
}

TEST(Flip, ShiftingASharpEdgeByOnePixelPeaksAboveTheSameEnergySpreadSmoothly) {
    // Reference: a vertical edge from 0.2 to 0.8. Test A moves it by one pixel (one column off by
    // 0.6); test B adds a smooth bump of the same squared error per row to the reference. B's
    // error covers every column, so its mean is the larger (0.20 against 0.028); where A differs,
    // its feature term lifts the colour term to a peak B reaches nowhere.
    const int w = 64, h = 32;
    const Image reference = filled(w, h, [](int x, int) { return vec3(x < 32 ? 0.2f : 0.8f); });
    const Image shifted = filled(w, h, [](int x, int) { return vec3(x < 33 ? 0.2f : 0.8f); });
    auto bump = [&](int x) { return std::sin(3.14159265 * (x + 0.5) / w); };
    double bumpEnergy = 0.0;
    for (int x = 0; x < w; ++x) bumpEnergy += bump(x) * bump(x);
    const double amplitude = 0.6 / std::sqrt(bumpEnergy);
    const Image smooth = filled(w, h, [&](int x, int y) { return reference.rgb(x, y) + vec3(float(amplitude * bump(x))); });
    const FlipTerms edge = ldrFlipTerms(shifted, reference), spread = ldrFlipTerms(smooth, reference);
    EXPECT_GT(flipStatistics(edge.flip).max, flipStatistics(spread.flip).max + 0.1);
    EXPECT_GT(flipStatistics(edge.feature).max, 2.0 * flipStatistics(spread.feature).max);
    // The feature term's lift ΔEc^(1 − ΔEf) − ΔEc, largest next to the moved edge (on the moved
    // column itself both edges are half a pixel away and their responses agree).
    auto largestLift = [](const FlipTerms& t) {
        float lift = 0.0f;
        for (std::size_t p = 0; p < t.flip.data.size(); ++p) lift = std::max(lift, t.flip.data[p] - t.color.data[p]);
        return lift;
    };
    EXPECT_GT(largestLift(edge), 0.1f);
    EXPECT_GT(largestLift(edge), 2.0f * largestLift(spread));
}

TEST(Flip, HdrFlipOfAnImageScaledBy1001IsSmall) {
    const Image reference = noise(32, 32, 11, 20.0f);
    Image scaled = reference;
    for (float& v : scaled.data) v *= 1.001f;
    const FlipStatistics s = flipStatistics(hdrFlip(scaled, reference));
    EXPECT_LT(s.max, 0.02);
}

TEST(Flip, HdrFlipAtOneExposureIsLdrFlipOfTheToneMappedImages) {
    const Image test = noise(24, 24, 21, 5.0f), reference = noise(24, 24, 22, 5.0f);
    const double exposure = -1.5;
    auto toneMapped = [&](const Image& image) {
        Image out = image;
        for (float& v : out.data) v = float(flipToneMap(std::exp2(exposure) * v));
        return out;
    };
    EXPECT_EQ(hdrFlip(test, reference, FlipExposures{exposure, exposure, 1}).data, ldrFlip(toneMapped(test), toneMapped(reference)).data);
    // More exposures can only raise each pixel: the map is the per-pixel maximum.
    const Image one = hdrFlip(test, reference, FlipExposures{exposure, exposure, 1});
    const Image three = hdrFlip(test, reference, FlipExposures{exposure - 2, exposure, 3});
    for (std::size_t p = 0; p < one.data.size(); ++p) ASSERT_GE(three.data[p], one.data[p]) << "pixel " << p;
}

TEST(Flip, AutomaticExposuresPutTheBrightestAndTheMedianPixelOnTheTarget) {
    // Luminance 1 everywhere but one pixel of 64: max 64, median 1.
    Image reference = flat(9, 9, vec3(1.0f));
    reference.setRgb(4, 4, vec3(64.0f));
    const FlipExposures e = flipExposures(reference);
    EXPECT_NEAR(flipToneMap(std::exp2(e.start) * 64.0), kFlipExposureTarget, 1e-9);
    EXPECT_NEAR(flipToneMap(std::exp2(e.stop) * 1.0), kFlipExposureTarget, 1e-9);
    EXPECT_NEAR(e.stop - e.start, 6.0, 1e-9);
    EXPECT_EQ(e.count, 6);
    // A black reference: the paper's range collapses to 0.
    const FlipExposures black = flipExposures(flat(4, 4, vec3(0.0f)));
    EXPECT_EQ(black.start, 0.0);
    EXPECT_EQ(black.stop, 0.0);
    EXPECT_EQ(black.count, 2);
}

TEST(Flip, ToneMapIsTheAcesFitWithPreExposure) {
    // Narkowicz's curve x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14) of 0.6·v.
    for (const double v : {0.0, 0.01, 0.5, 1.0, 3.0, 100.0}) {
        const double x = 0.6 * v;
        EXPECT_NEAR(flipToneMap(v), std::min(1.0, x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14)), 1e-12) << v;
    }
    EXPECT_EQ(flipToneMap(-5.0), 0.0);
}

TEST(Flip, ContrastSensitivityKernelsSumToOneAndFollowTheSumOfGaussians) {
    const double ppd = kFlipDefaultPixelsPerDegree;
    for (const FlipOpponent channel : {FlipOpponent::Achromatic, FlipOpponent::RedGreen, FlipOpponent::BlueYellow}) {
        const Image k = flipContrastSensitivityKernel(channel, ppd);
        // r = ⌈3·√(0.04 / 2π²)·67.02⌉ = 10 for every channel.
        ASSERT_EQ(k.width, 21);
        EXPECT_NEAR(std::accumulate(k.data.begin(), k.data.end(), 0.0), 1.0, 1e-5);
        const FlipCsf& c = kFlipCsf[std::size_t(channel)];
        auto s = [&](double x, double y) {
            const double z = (x * x + y * y) / (ppd * ppd), pi2 = 3.14159265358979 * 3.14159265358979;
            double v = c.a1 * std::sqrt(3.14159265358979 / c.b1) * std::exp(-pi2 * z / c.b1);
            if (c.a2 > 0) v += c.a2 * std::sqrt(3.14159265358979 / c.b2) * std::exp(-pi2 * z / c.b2);
            return v;
        };
        for (const auto& [x, y] : {std::pair{1, 0}, std::pair{3, 2}, std::pair{-5, 4}})
            EXPECT_NEAR(k.at(10 + x, 10 + y, 0) / k.at(10, 10, 0), s(x, y) / s(0, 0), 1e-5) << x << "," << y;
    }
}

TEST(Flip, FeatureKernelsWeighEachSignToOne) {
    for (const FlipFeature feature : {FlipFeature::Edge, FlipFeature::Point}) {
        const Image k = flipFeatureKernel(feature);
        // σ = 0.5 · 0.082 · 67.02 = 2.75 pixels, r = ⌈3σ⌉ = 9.
        ASSERT_EQ(k.width, 19);
        double positive = 0.0, negative = 0.0;
        for (const float v : k.data) (v > 0 ? positive : negative) += v;
        EXPECT_NEAR(positive, 1.0, 1e-5);
        EXPECT_NEAR(negative, -1.0, 1e-5);
    }
}

TEST(Flip, A512SquareImageTakesWellUnderASecond) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "timing is meaningless under the sanitizers";
#endif
    const Image a = noise(512, 512, 5, 1.0f), b = noise(512, 512, 6, 1.0f);
    const auto start = std::chrono::steady_clock::now();
    const Image map = ldrFlip(a, b);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("512x512 LDR-FLIP: %.3f s\n", seconds);
    EXPECT_LT(seconds, 1.0);
}

TEST(Flip, MismatchedInputsAreRefused) {
    EXPECT_THROW(ldrFlip(flat(4, 4, vec3(0)), flat(4, 5, vec3(0))), std::invalid_argument);
    EXPECT_THROW(ldrFlip(Image(4, 4, 1), Image(4, 4, 1)), std::invalid_argument);
    EXPECT_THROW(ldrFlip(flat(4, 4, vec3(0)), flat(4, 4, vec3(0)), 0.0), std::invalid_argument);
    EXPECT_THROW(hdrFlip(flat(4, 4, vec3(0)), flat(4, 4, vec3(0)), FlipExposures{0, 1, 0}), std::invalid_argument);
}

}  // namespace
}  // namespace gibench
