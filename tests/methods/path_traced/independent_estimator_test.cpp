// The ground truth agrees with an independent estimator: path_traced (NEE + MIS + Russian
// roulette over Embree) against the naive renderer of tests/support/naive_renderer.h (BSDF
// sampling only, brute-force double-precision intersection, no code of core/render), compared
// block by block with the variance-derived z-test of tests/support/block_z_test.h.
//
// Pass rule: every judged block and channel passes at the Šidák-corrected level, at least 90 % of
// the blocks are judged, and the image mean of each channel passes (Šidák over the three
// channels at α = 0.01). Šidák already spends α = 0.01
// over the whole image, so even one failing block is a 1 %-level event for two renders that
// agree; tolerating a fraction of failing blocks would hide exactly the bugs this suite exists
// for, which are local (wrong shadows on one face, a leak at one edge) and touch a handful of
// blocks while the image mean barely moves. Blocks are not judged where the naive renderer found
// light through fewer than 100 effective samples (dark corners lit only by rare paths), since its
// standard error is itself unreliable there (block_z_test.h); the image mean still counts them.
//
// Both renderers use the same max_depth (pbrt convention: scattering events per path), so they
// estimate the same truncated integral whatever light lies beyond it; "full depth" is
// max_depth 8 on both sides, enough for Russian roulette (path_traced only, from depth 3) to end
// most paths early, which must leave that integral unchanged.
//
// Budgets: 32 × 32 pixels, 4 × 4 blocks. path_traced converges 10–100 times faster per sample, so
// it gets 1024 spp and the naive renderer 1024–4096, as many as keep 90 % of its blocks judged (the
// Cornell lights are hit by a few % of BSDF-sampled directions, and at max_depth 1–2 by no other
// path). The whole file takes ~20 s on two cores.

#include "support/block_z_test.h"
#include "support/naive_renderer.h"
#include "support/render_helpers.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <string>

namespace gibench {
namespace {

using test::BlockComparison;
using test::compareBlocks;
using test::PixelEstimates;

constexpr int kBlockSize = 4;
// Blocks the naive renderer reaches through too few samples are not judged (block_z_test.h);
// the suite's spp are chosen so that this is the exception, and this bound keeps it so.
constexpr double kMinJudgedFraction = 0.9;

// ---- The statistics on synthetic images ----------------------------------------------------------

// A width × height image whose pixels each average `samples` draws of value + uniform noise of
// half-width `spread`, with the variance of each mean estimated from those draws.
PixelEstimates noisyConstant(int width, int height, double value, double spread, int samples, uint64_t seed) {
    PixelEstimates e(width, height, samples);
    for (std::size_t i = 0; i < e.mean.size(); ++i) {
        Rng rng = Rng::forPath(seed, 0, i, 0);
        double sum = 0.0, sumSquared = 0.0;
        for (int s = 0; s < samples; ++s) {
            const double v = value + spread * (2.0 * rng.uniform() - 1.0);
            sum += v;
            sumSquared += v * v;
        }
        const double mean = sum / samples;
        e.mean[i] = mean;
        e.variance[i] = (sumSquared - samples * mean * mean) / (samples - 1.0) / samples;
    }
    return e;
}

// The same with every sample's noise shared by the three channels, as a path's R, G and B are.
PixelEstimates noisyGrey(int width, int height, double value, double spread, int samples, uint64_t seed) {
    PixelEstimates e = noisyConstant(width, height, value, spread, samples, seed);
    for (std::size_t i = 0; i < e.mean.size(); i += 3)
        for (int c = 1; c < 3; ++c) {
            e.mean[i + c] = e.mean[i];
            e.variance[i + c] = e.variance[i];
        }
    return e;
}

// Standard error of one pixel mean of noisyConstant: uniform noise of half-width w has variance w²/3.
double pixelSigma(double spread, int samples) { return spread / std::sqrt(3.0 * samples); }

TEST(BlockZTest, AcceptsTwoIndependentNoisyRendersOfTheSameConstant) {
    const PixelEstimates a = noisyConstant(32, 32, 1.0, 0.5, 64, 1), b = noisyConstant(32, 32, 1.0, 0.5, 64, 2);
    const BlockComparison r = compareBlocks(a, b, kBlockSize);
    EXPECT_EQ(r.blocks.size(), 8u * 8u * 3u);
    EXPECT_EQ(r.passed, r.blocks.size()) << r;
    EXPECT_TRUE(r.imageMeanPasses()) << r;
    // The per-test level is Šidák's for 192 tests at 0.01: z ≈ 4.04.
    EXPECT_NEAR(r.threshold, test::twoSidedNormalQuantile(1.0 - std::pow(0.99, 1.0 / 192.0)), 1e-12);
    EXPECT_GT(r.threshold, 3.9);
    EXPECT_LT(r.threshold, 4.2);
}

TEST(BlockZTest, RejectsAnImageShiftedByThreeSigma) {
    // Every pixel moved by 3 of its own standard errors: a 4 × 4 block's mean moves by 12 of the
    // block's, i.e. 8.5 standard errors of the difference of two such blocks.
    const double spread = 0.5;
    const int samples = 64;
    const PixelEstimates a = noisyConstant(32, 32, 1.0, spread, samples, 1);
    const PixelEstimates b = noisyConstant(32, 32, 1.0 + 3.0 * pixelSigma(spread, samples), spread, samples, 2);
    const BlockComparison r = compareBlocks(a, b, kBlockSize);
    EXPECT_LT(r.passFraction(), 0.05) << r;
    EXPECT_FALSE(r.imageMeanPasses()) << r;
}

TEST(BlockZTest, RejectsOneShiftedBlockThatTheImageMeanHides) {
    // A local bug (one 4 × 4 block 3 pixel-sigmas too dark) fails its block while the image mean,
    // diluted over 64 blocks, stays within its test: why every block must pass.
    const double spread = 0.5;
    const int samples = 64;
    const PixelEstimates a = noisyConstant(32, 32, 1.0, spread, samples, 1);
    PixelEstimates b = noisyConstant(32, 32, 1.0, spread, samples, 2);
    for (int y = 8; y < 12; ++y)
        for (int x = 20; x < 24; ++x)
            for (int c = 0; c < 3; ++c) b.mean[b.index(x, y, c)] -= 3.0 * pixelSigma(spread, samples);
    const BlockComparison r = compareBlocks(a, b, kBlockSize);
    EXPECT_EQ(r.passed, r.blocks.size() - 3) << r;
    EXPECT_EQ(r.worst().x0, 20) << r;
    EXPECT_EQ(r.worst().y0, 8) << r;
    EXPECT_TRUE(r.imageMeanPasses()) << r;
}

TEST(BlockZTest, ImageMeansAreTestedPerChannelSoCorrelatedChannelsKeepTheLevel) {
    // Renders whose channels share their noise: summing channels would treat three copies of one
    // error as independent and understate the sum's variance threefold (z √3 too large: 14 % of
    // agreeing pairs would fail at α = 0.01). Tested per channel, agreeing pairs fail the image
    // test at a rate of at most α = 1 %: of 400 pairs, more than 12 failures has binomial
    // probability below 1e-3.
    int failures = 0;
    for (uint64_t pair = 0; pair < 400; ++pair) {
        const BlockComparison r = compareBlocks(noisyGrey(8, 8, 1.0, 0.5, 16, 2 * pair + 10), noisyGrey(8, 8, 1.0, 0.5, 16, 2 * pair + 11), 4);
        failures += r.imageMeanPasses() ? 0 : 1;
    }
    EXPECT_LE(failures, 12);
}

TEST(BlockZTest, NoiselessBlocksAgreeOnlyWhenEqualAndOneNoiselessSideUsesTheOthersError) {
    PixelEstimates exact(4, 4, 16), same(4, 4, 16), other(4, 4, 16), noisy(4, 4, 16);
    for (std::size_t i = 0; i < exact.mean.size(); ++i) {
        exact.mean[i] = same.mean[i] = 0.25;
        other.mean[i] = 0.26;
        noisy.mean[i] = 0.26;
        noisy.variance[i] = 1e-4;  // block: se = sqrt(16e-4) / 16 = 0.0025, so z = -4 against 0.25
    }
    const BlockComparison equal = compareBlocks(exact, same, 4);
    EXPECT_EQ(equal.passed, 3u) << equal;
    EXPECT_EQ(equal.worst().z, 0.0) << equal;
    const BlockComparison unequal = compareBlocks(exact, other, 4);
    EXPECT_EQ(unequal.passed, 0u) << unequal;
    EXPECT_TRUE(std::isinf(unequal.worst().z)) << unequal;
    const BlockComparison oneSided = compareBlocks(exact, noisy, 4);
    EXPECT_NEAR(oneSided.worst().z, -4.0, 1e-9) << oneSided;
}

// A render where light arrives through rare samples: in every pixel `hits` of the `samples`
// samples are `value`, the others 0.
PixelEstimates rareHits(int width, int height, int samples, int hits, double value) {
    PixelEstimates e(width, height, samples);
    const double n = samples, mean = hits * value / n;
    for (std::size_t i = 0; i < e.mean.size(); ++i) {
        e.mean[i] = mean;
        e.variance[i] = (hits * value * value - n * mean * mean) / (n - 1.0) / n;
    }
    return e;
}

TEST(BlockZTest, BlocksTheReferenceReachesThroughFewSamplesAreReportedNotJudged) {
    // 16 pixels with 2 hits each: the block's mean rests on 32 samples, its estimated error is
    // untrustworthy, and a far-off z there says nothing.
    const PixelEstimates a = noisyConstant(8, 8, 0.01, 0.005, 1024, 1);
    const PixelEstimates b = rareHits(8, 8, 1024, 2, 1.0);
    const BlockComparison r = compareBlocks(a, b, 4);
    EXPECT_EQ(r.judged, 0u) << r;
    EXPECT_NEAR(r.blocks.front().effectiveSamplesB, 32.0, 1e-6) << r;
    EXPECT_GT(std::fabs(r.blocks.front().z), r.threshold) << r;
    // With 20 hits per pixel (320 per block) the same comparison is judged.
    const BlockComparison enough = compareBlocks(a, rareHits(8, 8, 1024, 20, 0.01 * 1024 / 20), 4);
    EXPECT_EQ(enough.judged, enough.blocks.size()) << enough;
}

TEST(BlockZTest, ABlackRenderAgainstAWellSampledReferenceIsJudgedAndFails) {
    const PixelEstimates black(8, 8, 64);
    const PixelEstimates b = noisyConstant(8, 8, 0.1, 0.05, 64, 2);
    const BlockComparison r = compareBlocks(black, b, 4);
    EXPECT_EQ(r.judged, r.blocks.size()) << r;
    EXPECT_EQ(r.passed, 0u) << r;
    // Black in both: judged, and they agree.
    const BlockComparison bothBlack = compareBlocks(black, black, 4);
    EXPECT_EQ(bothBlack.passed, bothBlack.blocks.size()) << bothBlack;
}

// ---- The naive renderer on closed forms ------------------------------------------------------------

TEST(NaiveRenderer, SunAndSkyOnAPlaneGiveLambertsLawPlusAlbedoTimesSky) {
    // Every path hits the plane, then escapes: exactly ρ E cos θ / π from the sun plus ρ L from the
    // sky, in every sample (no noise at all).
    const float albedo = 0.6f, irradiance = 3.0f, sky = 0.5f, theta = 60.0f * kPi / 180.0f;
    Json json = test::sunLitPlane(albedo, irradiance, theta);
    json["lights"].push_back({{"type", "environment"}, {"radiance", sky}});
    const Scene scene = test::sceneFromJson(json);
    const PixelEstimates e = naive::Renderer(scene).render(test::camera(vec3(0, 2, 0.5f), vec3(0), 8, 8, 40.0f), {4, 16});
    const double expected = albedo * (irradiance * std::cos(double(theta)) / naive::kPiD + sky);
    for (std::size_t i = 0; i < e.mean.size(); ++i) {
        ASSERT_NEAR(e.mean[i], expected, 1e-6 * expected) << "value " << i;
        ASSERT_LT(e.variance[i], 1e-12 * expected * expected) << "value " << i;
    }
}

TEST(NaiveRenderer, FurnaceBoxGivesTheTruncatedGeometricSeriesExactly) {
    // Inside a closed box of albedo ρ emitting Le inward, each vertex adds Le·ρ^k: with max_depth
    // d the radiance is Le (1 + ρ + … + ρ^d), in every sample.
    const double albedo = 0.5;
    const int maxDepth = 5;
    const Json json = {{"materials", {{"shell", {{"type", "diffuse"}, {"albedo", albedo}, {"emission", 1.0}}}}},
                       {"shapes", {{{"type", "box"}, {"inward", true}, {"material", "shell"}}}}};
    const Scene scene = test::sceneFromJson(json);
    const PixelEstimates e = naive::Renderer(scene).render(test::camera(vec3(0.1f, 0.05f, 0), vec3(0, 0, -1), 6, 6, 90.0f), {maxDepth, 16});
    const double expected = (1.0 - std::pow(albedo, maxDepth + 1)) / (1.0 - albedo);
    for (std::size_t i = 0; i < e.mean.size(); ++i) ASSERT_NEAR(e.mean[i], expected, 1e-12) << "value " << i;
}

TEST(NaiveRenderer, ShadingNormalIsBentJustEnoughToKeepTheViewersReflectionAboveTheSurface) {
    // A shading normal tilted 30° away from a viewer 80° off the geometric normal would mirror the
    // view below the surface; the convention bends it towards ng, in the plane of the two, until
    // the reflection lies min(0.9 cos θo, 0.01) = 0.01 above. A viewer on the other side keeps ns.
    naive::Surface s;
    s.geometricNormal = naive::dvec3(0, 0, 1);
    s.interpolatedNormal = naive::dvec3(std::sin(naive::kPiD / 6.0), 0.0, std::cos(naive::kPiD / 6.0));
    const double viewDeg = 80.0 * naive::kPiD / 180.0;
    const naive::dvec3 wo(-std::sin(viewDeg), 0.0, std::cos(viewDeg));
    const naive::dvec3 bent = naive::shadingNormal(s, wo);
    const naive::dvec3 reflected = 2.0 * glm::dot(bent, wo) * bent - wo;
    EXPECT_NEAR(reflected.z, 0.01, 1e-12);
    EXPECT_NEAR(glm::length(bent), 1.0, 1e-12);
    EXPECT_NEAR(bent.y, 0.0, 1e-15);
    EXPECT_GT(bent.x, 0.0) << "bent towards ng, not past it";
    EXPECT_LT(bent.x, s.interpolatedNormal.x);
    const naive::dvec3 otherSide(std::sin(viewDeg), 0.0, std::cos(viewDeg));
    EXPECT_EQ(naive::shadingNormal(s, otherSide), s.interpolatedNormal);
}

TEST(NaiveRenderer, GlossyMixtureSamplingAgreesWithUniformHemisphereSampling) {
    // The directional albedo ∫ f cos dω of the coated material, estimated by the renderer's own
    // mixture sampling (f cos / density) and by uniform hemisphere sampling (f cos · 2π): a wrong
    // density or Jacobian shows as a difference far beyond the two standard errors combined.
    Material glossy;
    glossy.type = MaterialType::Glossy;
    glossy.albedo = Color(0.6f);
    glossy.specular = Color(0.25f);
    glossy.roughness = 0.3f;
    naive::Triangle triangle;
    triangle.material = &glossy;
    naive::Surface s;
    s.position = naive::dvec3(0.0);
    s.geometricNormal = s.interpolatedNormal = naive::dvec3(0, 0, 1);
    s.triangle = &triangle;
    s.material = &glossy;
    s.albedo = naive::dvec3(0.6);
    for (const double thetaDeg : {10.0, 60.0}) {
        const double theta = thetaDeg * naive::kPiD / 180.0;
        const naive::dvec3 wo(std::sin(theta), 0.0, std::cos(theta));
        const naive::Reflection reflection(s, wo);
        const int n = 400000;
        double sumMixture = 0.0, sumMixtureSquared = 0.0, sumUniform = 0.0, sumUniformSquared = 0.0;
        Rng rng(7, uint64_t(thetaDeg));
        for (int i = 0; i < n; ++i) {
            const naive::dvec3 wi = reflection.sampleDirection(wo, rng.uniform(), rng.uniform(), rng.uniform());
            const double pdf = reflection.density(wo, wi);
            const double mixture = wi.z > 0.0 && pdf > 0.0 ? reflection.f(wo, wi).x * wi.z / pdf : 0.0;
            sumMixture += mixture;
            sumMixtureSquared += mixture * mixture;
            const double z = rng.uniform(), phi = 2.0 * naive::kPiD * rng.uniform(), r = std::sqrt(std::max(0.0, 1.0 - z * z));
            const naive::dvec3 uniformWi(r * std::cos(phi), r * std::sin(phi), z);
            const double uniform = reflection.f(wo, uniformWi).x * z * 2.0 * naive::kPiD;
            sumUniform += uniform;
            sumUniformSquared += uniform * uniform;
        }
        const double meanMixture = sumMixture / n, meanUniform = sumUniform / n;
        const double varMixture = (sumMixtureSquared / n - meanMixture * meanMixture) / n;
        const double varUniform = (sumUniformSquared / n - meanUniform * meanUniform) / n;
        const double z = (meanMixture - meanUniform) / std::sqrt(varMixture + varUniform);
        EXPECT_LT(std::fabs(z), test::twoSidedNormalQuantile(test::sidakAlpha(0.01, 2)))
            << "theta " << thetaDeg << ": mixture " << meanMixture << " uniform " << meanUniform;
        EXPECT_GT(meanMixture, 0.3) << "theta " << thetaDeg;
        EXPECT_LT(meanMixture, 1.0) << "theta " << thetaDeg;
    }
}

// ---- path_traced against the naive renderer --------------------------------------------------------

struct Budget {
    int pathTracedSpp;
    int naiveSpp;
};

// Renders `camera` with both renderers at the same max_depth, prints one line of numbers for the
// record, and expects every block and the image mean to agree; with a `meanTolerance`, also each
// channel's image mean within that relative distance of the naive one's, measured precisely enough
// for the bound to mean something (2.5 standard errors inside the tolerance: two agreeing renders
// pass with about 99 % probability, a bias of twice the tolerance fails with more than 99 %). path_traced runs its independent
// sampler, whose variance layer is the exact variance of its mean, so that the z-tests keep their
// stated α; that the default sobol sampler has the same mean is tests/core/render/sampler_test.cpp's.
void expectAgreement(const std::string& name, const PreparedScene& scene, const CameraDesc& camera, int maxDepth, Budget budget,
                     double meanTolerance = 0.0) {
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    Json stats;
    const LayeredImage traced =
        test::render(scene, camera, {{"name", "path_traced"}, {"spp", budget.pathTracedSpp}, {"max_depth", maxDepth}, {"sampler", "independent"}},
                     1, 1, &stats);
    const auto traceEnd = Clock::now();
    const PixelEstimates naiveImage = naive::Renderer(scene.scene).render(camera, {maxDepth, budget.naiveSpp});
    const auto naiveEnd = Clock::now();
    EXPECT_EQ(stats["nonfinite_samples"], 0) << name;

    const BlockComparison r = compareBlocks(test::estimatesFromLayers(traced, budget.pathTracedSpp), naiveImage, kBlockSize);
    const test::BlockZ& worst = r.worst();
    std::cout << "[ naive    ] " << name << ": " << camera.width << "x" << camera.height << " max_depth " << maxDepth << ", path_traced "
              << budget.pathTracedSpp << " spp " << std::chrono::duration<double>(traceEnd - start).count() << " s, naive "
              << budget.naiveSpp << " spp " << std::chrono::duration<double>(naiveEnd - traceEnd).count() << " s; judged " << r.judged
              << "/" << r.blocks.size() << ", passing " << r.passed << "/" << r.judged << " (" << 100.0 * r.passFraction()
              << " %), worst z " << worst.z << " at (" << worst.x0 << "," << worst.y0 << ") " << "RGB"[worst.channel] << " ratio "
              << worst.meanA / worst.meanB << "; image mean path_traced/naive, worst channel " << "RGB"[r.worstImageChannel()] << ": "
              << r.imageMeanA[r.worstImageChannel()] / r.imageMeanB[r.worstImageChannel()] << " z " << r.imageZ[r.worstImageChannel()] << "\n";
    EXPECT_EQ(r.passed, r.judged) << name << " (a = path_traced, b = naive): " << r;
    EXPECT_GE(r.judgedFraction(), kMinJudgedFraction) << name << ": too few blocks have samples enough to judge; raise the spp. " << r;
    EXPECT_TRUE(r.imageMeanPasses()) << name << " (a = path_traced, b = naive): " << r;
    if (meanTolerance > 0.0)
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(r.imageMeanA[c] / r.imageMeanB[c], 1.0, meanTolerance) << name << ", channel " << "RGB"[c] << ": " << r;
            EXPECT_LT(2.5 * r.imageStandardError[c] / r.imageMeanB[c], meanTolerance)
                << name << ", channel " << "RGB"[c] << ": the image means are too noisy to test a " << meanTolerance << " tolerance";
        }
}

CameraDesc resized(CameraDesc camera, int width, int height) {
    camera.width = width;
    camera.height = height;
    return camera;
}

std::filesystem::path sceneConfig(const std::string& name) { return std::filesystem::path(GIBENCH_SOURCE_DIR) / "configs" / "scenes" / name; }

#define SKIP_WITHOUT_CORNELL_BOX_OBJ()                                                                          \
    if (!std::filesystem::exists(scenesDirectory() / "cornell-box" / "CornellBox-Original.obj"))               \
    GTEST_SKIP() << "third-party scenes not found in " << scenesDirectory() << " (set GIBENCH_SCENES)"

TEST(IndependentEstimator, AgreesOnCornellBoxObjAtDepthTwo) {
    SKIP_WITHOUT_CORNELL_BOX_OBJ();
    Scene scene = loadSceneFile(sceneConfig("cornell_box_obj.json"));
    const CameraDesc camera = resized(*scene.camera, 32, 32);
    expectAgreement("CornellBox-Original, max_depth 2", PreparedScene(std::move(scene)), camera, 2, {1024, 4096});
}

TEST(IndependentEstimator, AgreesOnCornellBoxObjAtFullDepth) {
    SKIP_WITHOUT_CORNELL_BOX_OBJ();
    Scene scene = loadSceneFile(sceneConfig("cornell_box_obj.json"));
    const CameraDesc camera = resized(*scene.camera, 32, 32);
    expectAgreement("CornellBox-Original, max_depth 8", PreparedScene(std::move(scene)), camera, 8, {1024, 2048});
}

// The default Cornell image's mean (the tall-block bug once darkened it by ~3 %) within 0.5 % of
// the naive renderer's in each channel. At the budget above the image means carry a standard
// error of 0.53 %, too much to test 0.5 %; 16 times the naive samples bring it to 0.19 %, at
// ~50 s on two cores: a measurement, not a test of the suite, so disabled there.
// Run it with --gtest_also_run_disabled_tests --gtest_filter='*CornellBoxObjMean*'.
TEST(IndependentEstimator, DISABLED_CornellBoxObjMeanWithinHalfAPercent) {
    SKIP_WITHOUT_CORNELL_BOX_OBJ();
    Scene scene = loadSceneFile(sceneConfig("cornell_box_obj.json"));
    const CameraDesc camera = resized(*scene.camera, 32, 32);
    expectAgreement("CornellBox-Original, max_depth 8, precise", PreparedScene(std::move(scene)), camera, 8, {8192, 32768}, 0.005);
}

// The top of the tall block seen from above and in front, where shadow rays towards the ceiling
// light once were wrongly occluded at the back-left of the face.
CameraDesc tallBlockTopView() { return test::camera(vec3(-0.3f, 1.7f, 0.9f), vec3(-0.33f, 1.2f, -0.29f), 32, 32, 40.0f); }

TEST(IndependentEstimator, AgreesOnTopOfTheTallBlockWithDirectLightOnly) {
    SKIP_WITHOUT_CORNELL_BOX_OBJ();
    const PreparedScene scene(loadSceneFile(sceneConfig("cornell_box_obj.json")));
    expectAgreement("tall block top, max_depth 1", scene, tallBlockTopView(), 1, {1024, 4096});
}

TEST(IndependentEstimator, AgreesOnTopOfTheTallBlockAtDepthTwo) {
    SKIP_WITHOUT_CORNELL_BOX_OBJ();
    const PreparedScene scene(loadSceneFile(sceneConfig("cornell_box_obj.json")));
    expectAgreement("tall block top, max_depth 2", scene, tallBlockTopView(), 2, {1024, 4096});
}

TEST(IndependentEstimator, AgreesOnTheBuiltInCornellBox) {
    Scene scene = loadSceneFile(sceneConfig("cornell_box.json"));
    const CameraDesc camera = resized(*scene.camera, 32, 32);
    expectAgreement("built-in Cornell box, max_depth 8", PreparedScene(std::move(scene)), camera, 8, {1024, 4096});
}

TEST(IndependentEstimator, AgreesOnTheBuiltInCornellBoxWithAGlossyTallBlock) {
    // The tall block coated: GGX roughness 0.3 (α = 0.09) and F0 = 0.25 over its white base.
    Json json = loadJsonFile(sceneConfig("cornell_box.json"));
    json["materials"]["glossy_white"] = {{"type", "glossy"}, {"albedo", {0.725, 0.71, 0.68}}, {"specular", 0.25}, {"roughness", 0.3}};
    int coated = 0;
    for (Json& shape : json["shapes"])
        if (shape["name"].get<std::string>().rfind("tall_block", 0) == 0) {
            shape["material"] = "glossy_white";
            ++coated;
        }
    ASSERT_EQ(coated, 5);
    Scene scene = test::sceneFromJson(json);
    const CameraDesc camera = resized(*scene.camera, 32, 32);
    expectAgreement("built-in Cornell box, glossy tall block, max_depth 8", PreparedScene(std::move(scene)), camera, 8, {1024, 4096});
}

TEST(IndependentEstimator, AgreesOnABoxOnAPlaneUnderSunAndSky) {
    // Sun at 60° and a blue-ish sky over a plane with a box on it: sun shadows, sky occlusion and
    // light bounced between box and ground. The sun is turned 30° about +Y so that it grazes no
    // face of the box: at exactly 90° float and double rounding disagree on which side it is.
    Json json = test::sunLitPlane(0.6f, 3.0f, 60.0f * kPi / 180.0f);
    json["lights"][0]["direction"] = {std::sin(kPi / 3.0) * std::cos(kPi / 6.0), -std::cos(kPi / 3.0), std::sin(kPi / 3.0) * std::sin(kPi / 6.0)};
    json["lights"].push_back({{"type", "environment"}, {"radiance", {0.4, 0.5, 0.7}}});
    json["materials"]["block"] = {{"type", "diffuse"}, {"albedo", {0.7, 0.4, 0.3}}};
    json["shapes"].push_back({{"type", "box"}, {"transform", {{"scale", 0.25}, {"translate", {0.0, 0.25, 0.0}}}}, {"material", "block"}});
    const PreparedScene scene(test::sceneFromJson(json));
    expectAgreement("box on a plane under sun and sky, max_depth 8", scene, test::camera(vec3(1.2f, 1.0f, 1.4f), vec3(0, 0.15f, 0), 32, 32, 50.0f),
                    8, {1024, 1024});
}

TEST(IndependentEstimator, AgreesOnACoarseSphereWithVertexNormals) {
    // An 80-triangle icosphere with radial shading normals, lit by a low sun and the sky, on a
    // ground plane: the shading normals differ from the facets' by up to ~20°, so the convention
    // (naive::shadingNormal and shadingCosines: cosines, sides, and the bending near the
    // silhouette) decides the terminator and the rim. The sun is parallel to no facet (one facet
    // faces (-1, 1, 1): a sun along (-0.8, -0.5, -0.3) would graze it exactly, where float and
    // double rounding disagree on which side it is).
    const Json json = {{"materials", {{"ball", {{"type", "diffuse"}, {"albedo", {0.8, 0.7, 0.6}}}}, {"ground", {{"type", "diffuse"}, {"albedo", 0.5}}}}},
                       {"shapes",
                        {{{"type", "sphere"}, {"center", {0.0, 0.5, 0.0}}, {"radius", 0.5}, {"subdivisions", 1}, {"material", "ball"}},
                         {{"type", "quad"}, {"transform", {{"scale", 4.0}}}, {"material", "ground"}}}},
                       {"lights",
                        {{{"type", "sun"}, {"direction", {-0.71, -0.52, -0.33}}, {"irradiance", 2.0}},
                         {{"type", "environment"}, {"radiance", 0.3}}}}};
    Scene raw = test::sceneFromJson(json);
    ASSERT_FALSE(raw.meshes.front().normals.empty()) << "the sphere is meant to carry vertex normals";
    const PreparedScene scene(std::move(raw));
    expectAgreement("coarse sphere with vertex normals, max_depth 8", scene, test::camera(vec3(0.2f, 0.9f, 1.8f), vec3(0, 0.45f, 0), 32, 32, 45.0f),
                    8, {1024, 1024});
}

}  // namespace
}  // namespace gibench

