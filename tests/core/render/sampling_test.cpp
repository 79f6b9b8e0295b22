#include "core/render/sampling.h"

#include "core/util/rng.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace gibench {
namespace {

TEST(Rng, SameCoordinatesGiveTheSameStreamAndNeighboursDiffer) {
    Rng a = Rng::forPath(7, 0, 12, 3), b = Rng::forPath(7, 0, 12, 3), c = Rng::forPath(7, 0, 12, 4), d = Rng::forPath(7, 0, 13, 3);
    int sameAsC = 0, sameAsD = 0;
    for (int i = 0; i < 64; ++i) {
        const uint32_t x = a.next();
        EXPECT_EQ(x, b.next());
        sameAsC += x == c.next();
        sameAsD += x == d.next();
    }
    EXPECT_LT(sameAsC, 2);
    EXPECT_LT(sameAsD, 2);
}

// Paths whose coordinates differ by one (pixel, sample, frame, seed or stream) share a PCG stream
// and start at hashed points of it: the k-th numbers of such neighbours must be uncorrelated and
// uniform. Over n pairs the sample correlation of independent uniforms has standard error 1/√n.
// Unhashed states (pixel ^ key) fail it: correlation 0.118 between neighbouring pixels, and a
// third or two thirds of first numbers below 1/2.
TEST(Rng, NeighbouringPathsDrawUncorrelatedUniformNumbers) {
    constexpr int kPairs = 40000;
    const auto correlation = [](auto neighbours) {
        double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
        int low = 0;
        for (int i = 0; i < kPairs; ++i) {
            auto [a, b] = neighbours(uint64_t(i));
            for (int k = 0; k < 3; ++k) {  // the first numbers are the ones a fresh hash must randomise
                const double x = a.uniform(), y = b.uniform();
                sx += x, sy += y, sxx += x * x, syy += y * y, sxy += x * y;
                low += x < 0.5;
            }
        }
        const double n = 3.0 * kPairs;
        EXPECT_NEAR(double(low) / n, 0.5, 5.0 * std::sqrt(0.25 / n)) << "uniform";
        return (sxy / n - sx / n * sy / n) / std::sqrt((sxx / n - sx / n * sx / n) * (syy / n - sy / n * sy / n));
    };
    const double tolerance = 5.0 / std::sqrt(3.0 * kPairs);
    EXPECT_NEAR(correlation([](uint64_t i) { return std::pair{Rng::forPath(3, 1, i, 0), Rng::forPath(3, 1, i + 1, 0)}; }), 0.0, tolerance) << "pixels";
    EXPECT_NEAR(correlation([](uint64_t i) { return std::pair{Rng::forPath(3, 1, 7, i), Rng::forPath(3, 1, 7, i + 1)}; }), 0.0, tolerance) << "samples";
    EXPECT_NEAR(correlation([](uint64_t i) { return std::pair{Rng::forPath(3, i, 7, 0), Rng::forPath(3, i + 1, 7, 0)}; }), 0.0, tolerance) << "frames";
    EXPECT_NEAR(correlation([](uint64_t i) { return std::pair{Rng::forPath(i, 1, 7, 0), Rng::forPath(i + 1, 1, 7, 0)}; }), 0.0, tolerance) << "seeds";
    // Streams of one pixel: the sample index in the path tracer and a RandomStream in a cache frame.
    EXPECT_NEAR(correlation([](uint64_t i) { return std::pair{Rng::forPath(3, 1, i, RandomStream::GBuffer), Rng::forPath(3, 1, i, RandomStream::Direct)}; }), 0.0,
                tolerance) << "streams";
}

TEST(Rng, UniformIsInUnitIntervalWithMeanOneHalf) {
    Rng rng(1, 2);
    const int n = 200000;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        const float u = rng.uniform();
        ASSERT_GE(u, 0.0f);
        ASSERT_LT(u, 1.0f);
        sum += u;
    }
    // Standard error of the mean of U(0,1): sqrt(1/12 / n); 5 sigma.
    EXPECT_NEAR(sum / n, 0.5, 5.0 * std::sqrt(1.0 / 12.0 / n));
}

TEST(Sampling, CosineHemisphereHasTheMeanCosineOfItsDensity) {
    // E[cos θ] under p = cos θ / π is 2/3; every sample lies in the upper unit hemisphere.
    Rng rng(3, 4);
    const int n = 200000;
    double sum = 0.0, sumSq = 0.0;
    for (int i = 0; i < n; ++i) {
        const vec3 w = sampleCosineHemisphere(vec2(rng.uniform(), rng.uniform()));
        ASSERT_NEAR(glm::length(w), 1.0f, 1e-5f);
        ASSERT_GE(w.z, 0.0f);
        sum += w.z;
        sumSq += double(w.z) * w.z;
    }
    const double mean = sum / n, sd = std::sqrt((sumSq / n - mean * mean) / n);
    EXPECT_NEAR(mean, 2.0 / 3.0, 5.0 * sd);
}

TEST(Sampling, CosineHemisphereIsTheConcentricMapLiftedToTheHemisphere) {
    // Against Shirley & Chiu's map written out in double with the library's sine and cosine: a
    // 257² grid of the unit square (its centre, edges, corners and diagonals included) and the
    // floats just below 1.
    const auto reference = [](double ux, double uy) {
        const double ox = 2.0 * ux - 1.0, oy = 2.0 * uy - 1.0;
        if (ox == 0.0 && oy == 0.0) return glm::dvec3(0.0, 0.0, 1.0);
        double r, theta;
        if (std::fabs(ox) > std::fabs(oy)) {
            r = ox;
            theta = M_PI / 4.0 * (oy / ox);
        } else {
            r = oy;
            theta = M_PI / 2.0 - M_PI / 4.0 * (ox / oy);
        }
        const double x = r * std::cos(theta), y = r * std::sin(theta);
        return glm::dvec3(x, y, std::sqrt(std::max(0.0, 1.0 - x * x - y * y)));
    };
    std::vector<float> us;
    for (int i = 0; i <= 256; ++i) us.push_back(float(i) / 256.0f);
    us.back() = std::nextafter(1.0f, 0.0f);
    us.push_back(std::nextafter(0.5f, 0.0f));
    us.push_back(std::nextafter(0.5f, 1.0f));
    for (const float ux : us)
        for (const float uy : us) {
            const vec3 w = sampleCosineHemisphere(vec2(ux, uy));
            const glm::dvec3 expected = reference(ux, uy);
            ASSERT_NEAR(w.x, expected.x, 1e-6) << ux << " " << uy;
            ASSERT_NEAR(w.y, expected.y, 1e-6) << ux << " " << uy;
            // z = sqrt(1 − x² − y²) magnifies the disk point's rounding near the rim.
            ASSERT_NEAR(w.z, expected.z, 1e-3) << ux << " " << uy;
            ASSERT_GE(w.z, 0.0f);
        }
}

TEST(Sampling, UniformTriangleBarycentricsAreInsideWithMeanOneThird) {
    Rng rng(5, 6);
    const int n = 100000;
    vec2 sum(0.0f);
    for (int i = 0; i < n; ++i) {
        const vec2 b = sampleUniformTriangle(vec2(rng.uniform(), rng.uniform()));
        ASSERT_GE(b.x, 0.0f);
        ASSERT_GE(b.y, 0.0f);
        ASSERT_LE(b.x + b.y, 1.0f + 1e-6f);
        sum += b;
    }
    // Each barycentric of a uniform point has variance 1/18.
    const float tolerance = 5.0f * std::sqrt(1.0f / 18.0f / n);
    EXPECT_NEAR(sum.x / n, 1.0f / 3.0f, tolerance);
    EXPECT_NEAR(sum.y / n, 1.0f / 3.0f, tolerance);
}

TEST(Distribution1D, PicksBinsInProportionAndSkipsZeroBins) {
    const Distribution1D d({1.0f, 0.0f, 3.0f});
    float p, remapped;
    EXPECT_EQ(d.sample(0.0f, p, remapped), 0u);
    EXPECT_FLOAT_EQ(p, 0.25f);
    EXPECT_EQ(d.sample(0.2f, p, remapped), 0u);
    EXPECT_NEAR(remapped, 0.8f, 1e-6f);
    EXPECT_EQ(d.sample(0.25f, p, remapped), 2u);
    EXPECT_FLOAT_EQ(p, 0.75f);
    EXPECT_EQ(d.sample(0.999999f, p, remapped), 2u);
    EXPECT_FLOAT_EQ(d.probability(1), 0.0f);
}

TEST(Distribution1D, SamplingWithoutTheRemappedNumberPicksTheSameBinWithTheSameProbability) {
    const std::vector<float> weights = {0.0f, 2.0f, 0.5f, 0.0f, 0.0f, 7.0f, 1e-3f, 0.0f};
    const Distribution1D d(weights);
    double total = 0.0;
    for (const float w : weights) total += w;
    for (std::size_t i = 0; i < weights.size(); ++i) EXPECT_EQ(d.probability(i), float(weights[i] / total)) << "bin " << i;
    Rng rng(5, 6);
    for (int i = 0; i < 10000; ++i) {
        const float u = i < 9 ? float(i) / 8.0f * 0x1.fffffep-1f : rng.uniform();
        float withRemap, without, remapped;
        const std::size_t bin = d.sample(u, withRemap, remapped);
        ASSERT_EQ(d.sample(u, without), bin) << "u " << u;
        ASSERT_EQ(without, withRemap) << "u " << u;
        ASSERT_EQ(without, d.probability(bin)) << "u " << u;
    }
}

// The bin of u is the last nonzero-weight bin whose CDF start is <= u, found here by a plain scan
// of the normalised prefix sums: sample() must agree at every bin's start, just below it, and at
// random u, with runs of empty bins, bins of very different widths, and many bins.
TEST(Distribution1D, PicksTheBinAScanOfTheCdfPicks) {
    Rng rng(11, 12);
    for (const int n : {1, 2, 3, 7, 64, 100, 1000}) {
        std::vector<float> weights(static_cast<std::size_t>(n));
        for (float& w : weights) w = rng.uniform() < 0.3f ? 0.0f : std::exp(8.0f * rng.uniform());
        weights[std::size_t(n) / 2] = 1.0f;
        const Distribution1D d(weights);
        std::vector<double> cdf(std::size_t(n) + 1, 0.0);
        for (int i = 0; i < n; ++i) cdf[i + 1] = cdf[i] + weights[i];
        for (double& c : cdf) c /= cdf.back();
        const auto scanned = [&](float u) {
            std::size_t bin = 0;
            for (int i = 0; i < n; ++i)
                if (cdf[i] <= double(u)) bin = std::size_t(i);
            while (bin + 1 < std::size_t(n) && weights[bin] == 0.0f) ++bin;
            return bin;
        };
        std::vector<float> us = {0.0f, 0x1.fffffep-1f};
        for (int i = 0; i < n; ++i) {
            const float start = float(cdf[i]);
            us.push_back(start);
            us.push_back(std::nextafter(start, 0.0f));
            us.push_back(std::nextafter(start, 1.0f));
        }
        for (int i = 0; i < 2000; ++i) us.push_back(rng.uniform());
        for (const float u : us) {
            if (!(u >= 0.0f && u < 1.0f)) continue;
            float p;
            ASSERT_EQ(d.sample(u, p), scanned(u)) << n << " bins, u " << u;
        }
    }
}

TEST(Distribution2D, DensityIntegratesToOneAndMatchesSampling) {
    const std::vector<float> w = {1, 2, 0, 4, 1, 1};  // 3 × 2
    const Distribution2D d(w, 3, 2);
    double integral = 0.0;
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x) integral += d.pdf(vec2((x + 0.5f) / 3.0f, (y + 0.5f) / 2.0f)) / 6.0;
    EXPECT_NEAR(integral, 1.0, 1e-6);
    Rng rng(9, 9);
    for (int i = 0; i < 1000; ++i) {
        float pdf;
        const vec2 p = d.sample(vec2(rng.uniform(), rng.uniform()), pdf);
        ASSERT_NEAR(pdf, d.pdf(p), 1e-4f * pdf) << p.x << "," << p.y;
        ASSERT_GT(pdf, 0.0f);
    }
}

TEST(Sampling, PowerHeuristicWeightsOfTwoStrategiesSumToOne) {
    for (float a : {0.1f, 1.0f, 7.0f})
        for (float b : {0.0f, 0.5f, 3.0f}) EXPECT_NEAR(powerHeuristic(a, b) + powerHeuristic(b, a), 1.0f, 1e-6f);
}

}  // namespace
}  // namespace gibench
