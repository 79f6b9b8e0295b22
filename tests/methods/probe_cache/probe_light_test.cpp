// ProbeLight: the states of a probe cache and the memo of each probe's irradiance at its normal.

#include "methods/probe_cache/probe_light.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

namespace gibench {
namespace {

// Radiance that varies strongly over the hemisphere, so that E(n) moves with n.
Color skyRadiance(const vec3& w) { return Color(1.0f + 4.0f * w.x * w.x, 0.5f + 3.0f * std::max(w.y, 0.0f), 2.0f * w.z); }

// A ProbeLight of `probes` probes whose states hold many samples of skyRadiance.
struct SampledLight {
    std::unique_ptr<ProbeEncoding> encoding;
    std::unique_ptr<ProbeLight> light;
    float largestRadiance = 5.0f;  // the largest component skyRadiance takes
};

SampledLight sampledLight(ProbeEncodingKind kind, int resolution, uint32_t probes) {
    SampledLight s{makeProbeEncoding(kind, resolution), nullptr};
    s.light = std::make_unique<ProbeLight>(*s.encoding);
    s.light->grow(probes);
    for (uint32_t id = 0; id < probes; ++id) {
        for (int i = 0; i < 4000; ++i) {
            // A stratified cosine-free walk over the hemisphere: uniform in z and azimuth.
            const float z = (float(i % 63) + 0.5f) / 63.0f, phi = 2.0f * kPi * (float(i / 63) + 0.5f) / 64.0f;
            const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
            const vec3 w(r * std::cos(phi), r * std::sin(phi), z);
            s.encoding->addSample(s.light->state(id), w, skyRadiance(w) * float(id + 1), 1.0f / (2.0f * kPi));
        }
    }
    return s;
}

TEST(ProbeLight, NewProbesAreEmptyAndAreNotSampledUntilRefreshed) {
    SampledLight s = sampledLight(ProbeEncodingKind::Hemispherical, 5, 3);
    for (uint32_t id = 0; id < 3; ++id) EXPECT_FALSE(s.light->sampled(id)) << "samples were added but the memo was not refreshed";
    std::vector<uint32_t> ids = {2, 0, 2};
    s.light->refresh(ids);
    EXPECT_EQ(ids, (std::vector<uint32_t>{0, 2})) << "sorted, without duplicates";
    EXPECT_TRUE(s.light->sampled(0));
    EXPECT_FALSE(s.light->sampled(1));
    EXPECT_TRUE(s.light->sampled(2));
    s.light->grow(5);
    EXPECT_FALSE(s.light->sampled(4));
    EXPECT_EQ(s.light->probes(), 5u);
    EXPECT_EQ(s.encoding->sampleWeight(s.light->state(4)), 0.0f);
}

TEST(ProbeLight, AtTheProbesNormalTheMemoIsTheEncodingsIrradiance) {
    for (const ProbeEncodingKind kind : {ProbeEncodingKind::Hemispherical, ProbeEncodingKind::Octahedral, ProbeEncodingKind::SphericalHarmonics}) {
        SampledLight s = sampledLight(kind, kind == ProbeEncodingKind::SphericalHarmonics ? 2 : 5, 4);
        std::vector<uint32_t> ids = {0, 1, 2, 3};
        s.light->refresh(ids);
        for (uint32_t id = 0; id < 4; ++id) {
            const Color exact = s.encoding->irradiance(s.light->state(id), vec3(0.0f, 0.0f, 1.0f));
            const Color memo = s.light->irradiance(id, vec3(0.0f, 0.0f, 1.0f));
            EXPECT_EQ(memo, exact) << s.encoding->name() << " probe " << id;
            EXPECT_GT(memo.y, 0.0f);
        }
    }
}

// Within kMemoTilt of +z the memo answers, within the bound the header derives (2π |n − z| max L);
// beyond it the encoding answers exactly.
TEST(ProbeLight, NearTheNormalTheMemoStaysWithinItsBoundAndFartherTheEncodingAnswers) {
    SampledLight s = sampledLight(ProbeEncodingKind::Hemispherical, 5, 2);
    std::vector<uint32_t> ids = {0, 1};
    s.light->refresh(ids);
    for (uint32_t id = 0; id < 2; ++id) {
        const float largest = s.largestRadiance * float(id + 1);
        for (const float tilt : {1e-5f, 1e-4f, 0.9f * ProbeLight::kMemoTilt, 2.0f * ProbeLight::kMemoTilt, 0.01f, 0.5f}) {
            for (const float azimuth : {0.0f, 1.0f, 2.5f, 4.0f}) {
                const vec3 n(std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth), std::cos(tilt));
                const Color exact = s.encoding->irradiance(s.light->state(id), n);
                const Color served = s.light->irradiance(id, n);
                if (tilt > ProbeLight::kMemoTilt) {
                    EXPECT_EQ(served, exact) << "tilt " << tilt;
                    continue;
                }
                const float bound = 2.0f * kPi * glm::length(n - vec3(0.0f, 0.0f, 1.0f)) * largest;
                for (int c = 0; c < 3; ++c) EXPECT_LE(std::fabs(served[c] - exact[c]), bound + 1e-5f * exact[c]) << "tilt " << tilt << " channel " << c;
            }
        }
        // The bound at the largest tilt the memo serves: a small part of the encoding's own tolerance.
        EXPECT_LT(2.0f * kPi * ProbeLight::kMemoTilt, 0.06f * kProbeIrradianceTolerance);
    }
}

TEST(ProbeLight, ClearingAProbeEmptiesItsStateAndItsMemo) {
    SampledLight s = sampledLight(ProbeEncodingKind::Hemispherical, 5, 2);
    std::vector<uint32_t> ids = {0, 1};
    s.light->refresh(ids);
    s.light->clear(1);
    EXPECT_FALSE(s.light->sampled(1));
    EXPECT_EQ(s.light->irradiance(1, vec3(0.0f, 0.0f, 1.0f)), Color(0.0f));
    EXPECT_EQ(s.encoding->sampleWeight(s.light->state(1)), 0.0f);
    EXPECT_TRUE(s.light->sampled(0)) << "the other probe keeps its light";
}

}  // namespace
}  // namespace gibench
