#include "core/image/metrics.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <functional>
#include <limits>

namespace gibench {
namespace {

Image imageOf(int w, int h, const std::vector<float>& rgb) {
    Image image(w, h, 3);
    image.data = rgb;
    return image;
}

// Reference p0 = (1,1,1), p1 = (0,0,0); test p0 = (2,1,1), p1 = (0,0,0.1). Only two channel
// terms are non-zero: (x=2, r=1) and (x=0.1, r=0).
const Image kTest = imageOf(2, 1, {2.0f, 1.0f, 1.0f, 0.0f, 0.0f, 0.1f});
const Image kReference = imageOf(2, 1, {1.0f, 1.0f, 1.0f, 0.0f, 0.0f, 0.0f});

// A smooth, varied image so that no two pixels have the same error by accident.
Image pattern(int w, int h, float phase) {
    Image image(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) image.at(x, y, c) = 0.6f + 0.5f * std::sin(0.37f * x + 0.23f * y + 1.3f * c + phase);
    return image;
}

TEST(Metrics, ErrorMeansMatchHandArithmetic) {
    const ImageMetrics m = computeMetrics(kTest, kReference);
    // MSE = (1² + 0.1²) / 6 = 1.01 / 6 = 0.1683333.
    EXPECT_NEAR(m.mse, 1.01 / 6.0, 1e-7);
    EXPECT_NEAR(m.rmse, std::sqrt(1.01 / 6.0), 1e-7);
    // relMSE = (1 / (1 + 0.01) + 0.01 / (0 + 0.01)) / 6 = (0.990099 + 1) / 6 = 0.3316832.
    EXPECT_NEAR(m.relMse, (1.0 / 1.01 + 1.0) / 6.0, 1e-7);
    // SMAPE = (1 / (2 + 1 + 0.01) + 0.1 / (0.1 + 0 + 0.01)) / 6 = (0.3322259 + 0.9090909) / 6 = 0.2068861.
    EXPECT_NEAR(m.smape, (1.0 / 3.01 + 0.1 / 0.11) / 6.0, 1e-7);
    // MAPE = (1 / (1 + 0.01) + 0.1 / (0 + 0.01)) / 6 = (0.990099 + 10) / 6 = 1.8316832.
    EXPECT_NEAR(m.mape, (1.0 / 1.01 + 10.0) / 6.0, 1e-6);
    // Only 2 pixels: nothing is dropped, the robust variants equal the plain ones.
    EXPECT_EQ(m.mseRobust, m.mse);
    EXPECT_EQ(m.relMseRobust, m.relMse);
    EXPECT_EQ(m.smapeRobust, m.smape);
    EXPECT_EQ(m.mapeRobust, m.mape);
    EXPECT_EQ(m.pixels, 2u);
    EXPECT_EQ(m.nonfinitePixels, 0u);
}

TEST(Metrics, PsnrIsOnReinhardThenSrgbValues) {
    // t(v) = sRGB(v / (1 + v)): t(2) = sRGB(2/3) = 1.055 (2/3)^(1/2.4) - 0.055 = 0.8360070,
    // t(1) = sRGB(0.5) = 0.7353570, t(0.1) = sRGB(1/11) = 0.3334533, t(0) = 0.
    // MSE_t = ((0.8360070 - 0.7353570)² + 0.3334533²) / 6 = (0.0101308 + 0.1111911) / 6 = 0.0202203.
    // PSNR = 10 log10(1 / 0.0202203) = 16.94213 dB.
    EXPECT_NEAR(computeMetrics(kTest, kReference).psnr, 16.94213, 1e-4);
}

TEST(Metrics, SsimOfConstantImagesIsTheLuminanceTerm) {
    // Every window is constant: σ = 0 and SSIM = (2 μx μr + C1) / (μx² + μr² + C1) per pixel.
    // Grey 1 shows as t(1) = 0.7353570, black as 0: SSIM = 0.0001 / (0.7353570² + 0.0001) = 1.848942e-4.
    const Image grey(6, 4, 3, 1.0f), black(6, 4, 3, 0.0f);
    EXPECT_NEAR(computeMetrics(grey, black).ssim, 1.848942e-4, 1e-9);
}

TEST(Metrics, SsimUsesTheInImagePartOfTheGaussianWindow) {
    // 2×1 grey images, test (1, 0), reference (0, 1); with t = t(1) = 0.7353570 the display values
    // are a = (t, 0), b = (0, t). Each window holds both pixels, weights 1 (own) and
    // g = exp(-1 / (2 · 1.5²)) = 0.8007374, renormalised: p = 1 / (1 + g) = 0.5553281, q = 1 - p.
    // At pixel 0: μa = p t, μb = q t, σa² = σb² = p q t², σab = -p q t² (two-point weights),
    //   SSIM = (2 p q t² + C1)(-2 p q t² + C2) / (((p² + q²) t² + C1)(2 p q t² + C2))
    //        = (0.267120 + 1e-4)(-0.267120 + 9e-4) / ((0.273630 + 1e-4)(0.267120 + 9e-4)) = -0.9692607,
    // and pixel 1 is its mirror image, so the mean is the same.
    const Image test = imageOf(2, 1, {1, 1, 1, 0, 0, 0});
    const Image reference = imageOf(2, 1, {0, 0, 0, 1, 1, 1});
    EXPECT_NEAR(computeMetrics(test, reference).ssim, -0.9692607, 1e-6);
}

TEST(Metrics, IdenticalImagesHaveNoErrorTheLargestPsnrAndSsimOne) {
    const Image image = pattern(37, 23, 0.0f);
    const ImageMetrics m = computeMetrics(image, image);
    EXPECT_EQ(m.mse, 0.0);
    EXPECT_EQ(m.rmse, 0.0);
    EXPECT_EQ(m.relMse, 0.0);
    EXPECT_EQ(m.smape, 0.0);
    EXPECT_EQ(m.mape, 0.0);
    EXPECT_EQ(m.mseRobust, 0.0);
    EXPECT_EQ(m.relMseRobust, 0.0);
    EXPECT_EQ(m.smapeRobust, 0.0);
    EXPECT_EQ(m.mapeRobust, 0.0);
    EXPECT_EQ(m.psnr, kMaxPsnrDb);
    EXPECT_EQ(m.ssim, 1.0);
}

TEST(Metrics, PsnrIsContinuousUpToItsCeiling) {
    // One value differs by 1e-9 in display units (t(v) ≈ 12.92 v near 0): mean squared difference
    // (12.92e-9)² / 3 ≈ 5.6e-17, PSNR ≈ 162.5 dB, below the ceiling and given by the formula.
    const Image reference(1, 1, 3, 0.0f);
    Image test = reference;
    test.at(0, 0, 0) = 1e-9f;
    const double d = 12.92 * double(1e-9f) / (1.0 + double(1e-9f));
    EXPECT_NEAR(computeMetrics(test, reference).psnr, 10.0 * std::log10(3.0 / (d * d)), 1e-6);
    EXPECT_LT(computeMetrics(test, reference).psnr, kMaxPsnrDb);
}

// The mean of metric `kind`'s per-pixel error (mean of the 3 channel terms) over every pixel but
// (skipX, skipY), written out plainly.
double meanWithout(const Image& test, const Image& reference, int skipX, int skipY,
                   const std::function<double(double, double)>& term) {
    double sum = 0.0;
    for (int y = 0; y < test.height; ++y)
        for (int x = 0; x < test.width; ++x)
            if (x != skipX || y != skipY)
                for (int c = 0; c < 3; ++c) sum += term(test.at(x, y, c), reference.at(x, y, c)) / 3.0;
    return sum / double(test.pixelCount() - 1);
}

void expectRobustIgnores(const Image& test, const Image& reference, int x, int y) {
    const ImageMetrics m = computeMetrics(test, reference);
    const double relTol = 1e-12;
    const double mse = meanWithout(test, reference, x, y, [](double a, double b) { return (a - b) * (a - b); });
    const double relMse = meanWithout(test, reference, x, y, [](double a, double b) { return (a - b) * (a - b) / (b * b + 0.01); });
    const double smape =
        meanWithout(test, reference, x, y, [](double a, double b) { return std::abs(a - b) / (std::abs(a) + std::abs(b) + 0.01); });
    const double mape = meanWithout(test, reference, x, y, [](double a, double b) { return std::abs(a - b) / (std::abs(b) + 0.01); });
    EXPECT_NEAR(m.mseRobust, mse, relTol * mse) << "outlier at " << x << "," << y;
    EXPECT_NEAR(m.relMseRobust, relMse, relTol * relMse) << "outlier at " << x << "," << y;
    EXPECT_NEAR(m.smapeRobust, smape, relTol * smape) << "outlier at " << x << "," << y;
    EXPECT_NEAR(m.mapeRobust, mape, relTol * mape) << "outlier at " << x << "," << y;
}

TEST(Metrics, RobustVariantsDropTheOneOutlierOfTenThousandPixels) {
    const Image reference = pattern(100, 100, 0.0f);
    Image test = pattern(100, 100, 0.2f);
    test.setRgb(37, 61, vec3(1e6f, -1e6f, 1e6f));
    expectRobustIgnores(test, reference, 37, 61);
    EXPECT_GT(computeMetrics(test, reference).mse, 1e7) << "the plain MSE keeps the outlier";
}

TEST(Metrics, RobustVariantsDropExactlyOnePixelAmongEqualErrors) {
    // Every pixel's squared error is 0.25² = 0.0625: dropping one leaves 9999 of them, mean 0.0625.
    const Image reference(100, 100, 3, 0.5f), test(100, 100, 3, 0.75f);
    const ImageMetrics m = computeMetrics(test, reference);
    EXPECT_NEAR(m.mseRobust, 0.0625, 1e-15);
    EXPECT_NEAR(m.mse, 0.0625, 1e-15);
}

TEST(Metrics, NonFinitePixelMakesPlainMetricsNanAndIsDroppedByRobustOnes) {
    const Image reference = pattern(100, 100, 0.0f);
    Image test = pattern(100, 100, 0.2f);
    test.at(5, 7, 1) = std::numeric_limits<float>::quiet_NaN();
    const ImageMetrics m = computeMetrics(test, reference);
    EXPECT_EQ(m.nonfinitePixels, 1u);
    for (double v : {m.mse, m.rmse, m.relMse, m.smape, m.mape, m.psnr, m.ssim}) EXPECT_TRUE(std::isnan(v)) << v;
    expectRobustIgnores(test, reference, 5, 7);
}

TEST(Metrics, NanInATinyImageIsCountedAndLeavesNoMetricFinite) {
    // 4 pixels: nothing is dropped, so the NaN pixel's +inf error stays in the robust means.
    Image test(2, 2, 3, 0.5f);
    const Image reference(2, 2, 3, 0.5f);
    test.at(1, 0, 2) = std::numeric_limits<float>::quiet_NaN();
    const ImageMetrics m = computeMetrics(test, reference);
    EXPECT_EQ(m.nonfinitePixels, 1u);
    EXPECT_TRUE(std::isnan(m.mse));
    EXPECT_TRUE(std::isnan(m.relMse));
    EXPECT_EQ(m.mseRobust, std::numeric_limits<double>::infinity());
    EXPECT_EQ(m.mapeRobust, std::numeric_limits<double>::infinity());
}

TEST(Metrics, SameNumbersWhateverTheThreadCount) {
    const Image reference = pattern(301, 203, 0.0f);
    const Image test = pattern(301, 203, 0.3f);
    ImageMetrics one, two;
    tbb::task_arena(1).execute([&] { one = computeMetrics(test, reference); });
    tbb::task_arena(2).execute([&] { two = computeMetrics(test, reference); });
    EXPECT_EQ(toJson(one).dump(), toJson(two).dump());
    EXPECT_EQ(one.ssim, two.ssim);
}

TEST(Metrics, JsonHoldsOnlyFiniteNumbersAndRefusesNonFiniteMetrics) {
    const Image image(3, 3, 3, 0.25f);
    const Json same = toJson(computeMetrics(image, image));
    EXPECT_EQ(same["psnr"], kMaxPsnrDb);
    EXPECT_EQ(same["mse"], 0.0);
    EXPECT_EQ(same["ssim"], 1.0);
    EXPECT_EQ(same["pixels"], 9);
    EXPECT_EQ(same["nonfinite_pixels"], 0);
    for (const char* key : {"rmse", "relmse", "smape", "mape", "mse_robust", "relmse_robust", "smape_robust", "mape_robust"})
        EXPECT_EQ(same[key], 0.0) << key;

    // JSON has no number for NaN or infinity; null or "inf" would read as a measurement.
    Image broken = image;
    broken.at(0, 0, 0) = std::numeric_limits<float>::infinity();
    try {
        toJson(computeMetrics(broken, image));
        FAIL() << "no error";
    } catch (const std::domain_error& e) {
        EXPECT_STREQ(e.what(), "metric mse is NaN (1 of 9 pixels not finite); JSON cannot hold it");
    }
}

TEST(Metrics, ErrorMapIsFiniteForFiniteImagesAndNanOnlyWhereAPixelIsNot) {
    // (3e38 − 0)² / 3 = 3e76 overflows a float: the map holds the largest float instead of +inf.
    const Image reference(2, 1, 3, 0.0f);
    Image test(2, 1, 3, 3e38f);
    test.at(1, 0, 2) = std::numeric_limits<float>::quiet_NaN();
    for (ErrorMapKind kind : {ErrorMapKind::SquaredError, ErrorMapKind::RelMse, ErrorMapKind::Smape, ErrorMapKind::Mape}) {
        const Image map = errorMap(test, reference, kind);
        EXPECT_TRUE(std::isfinite(map.at(0, 0, 0))) << int(kind) << ": " << map.at(0, 0, 0);
        EXPECT_TRUE(std::isnan(map.at(1, 0, 0))) << int(kind);
    }
    EXPECT_EQ(errorMap(test, reference, ErrorMapKind::SquaredError).at(0, 0, 0), std::numeric_limits<float>::max());
}

TEST(Metrics, ErrorMapHoldsThePerPixelMeanOfEachTerm) {
    // Pixel 0: (1² + 0 + 0) / 3 = 1/3; pixel 1: (0 + 0 + 0.1²) / 3 = 0.01/3. relMSE pixel 1:
    // (0.01 / 0.01) / 3 = 1/3. SMAPE pixel 0: (1 / 3.01) / 3. MAPE pixel 1: (0.1 / 0.01) / 3 = 10/3.
    const Image se = errorMap(kTest, kReference, ErrorMapKind::SquaredError);
    ASSERT_EQ(se.channels, 1);
    EXPECT_NEAR(se.at(0, 0, 0), 1.0 / 3.0, 1e-7);
    EXPECT_NEAR(se.at(1, 0, 0), 0.01 / 3.0, 1e-8);
    EXPECT_NEAR(errorMap(kTest, kReference, ErrorMapKind::RelMse).at(1, 0, 0), 1.0 / 3.0, 1e-6);
    EXPECT_NEAR(errorMap(kTest, kReference, ErrorMapKind::Smape).at(0, 0, 0), 1.0 / 3.01 / 3.0, 1e-7);
    EXPECT_NEAR(errorMap(kTest, kReference, ErrorMapKind::Mape).at(1, 0, 0), 10.0 / 3.0, 1e-5);
}

TEST(Metrics, SizeMismatchNamesBothSizes) {
    try {
        computeMetrics(Image(2, 2, 3), Image(3, 2, 3));
        FAIL() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "image sizes differ: test 2x2, reference 3x2");
    }
    EXPECT_THROW(errorMap(Image(2, 2, 3), Image(2, 1, 3), ErrorMapKind::Smape), std::invalid_argument);
}

}  // namespace
}  // namespace gibench
