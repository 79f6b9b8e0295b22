// ProbeLight: the states of a probe cache and the memo of each probe's irradiance at its normal.

#include "methods/probe_cache/probe_light.h"

#include "core/util/bfloat16.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <memory>
#include <vector>

namespace gibench {
namespace {

// Radiance that varies strongly over the hemisphere, so that E(n) moves with n.
Color skyRadiance(const vec3& w) { return Color(1.0f + 4.0f * w.x * w.x, 0.5f + 3.0f * std::max(w.y, 0.0f), 2.0f * w.z); }

// Adds `count` samples of skyRadiance (scaled by id + 1) to `state`, from sample `first` of a
// stratified cosine-free walk over the hemisphere: uniform in z and azimuth.
void addSkySamples(const ProbeEncoding& encoding, float* state, uint32_t id, int first, int count) {
    for (int i = first; i < first + count; ++i) {
        const int k = i % 4032;
        const float z = (float(k % 63) + 0.5f) / 63.0f, phi = 2.0f * kPi * (float(k / 63) + 0.5f) / 64.0f;
        const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
        const vec3 w(r * std::cos(phi), r * std::sin(phi), z);
        encoding.addSample(state, w, skyRadiance(w) * float(id + 1), 1.0f / (2.0f * kPi));
    }
}

// A ProbeLight of `probes` probes whose states hold many samples of skyRadiance.
struct SampledLight {
    std::unique_ptr<ProbeEncoding> encoding;
    std::unique_ptr<ProbeLight> light;
    float largestRadiance = 5.0f;  // the largest component skyRadiance takes
};

constexpr ProbeStateFormat kFormats[] = {ProbeStateFormat::Float32, ProbeStateFormat::BFloat16};

SampledLight sampledLight(ProbeEncodingKind kind, int resolution, uint32_t probes, ProbeStateFormat format) {
    SampledLight s{makeProbeEncoding(kind, resolution), nullptr};
    s.light = std::make_unique<ProbeLight>(*s.encoding, format);
    s.light->grow(probes);
    for (uint32_t id = 0; id < probes; ++id) s.light->update(id, [&](float* state) { addSkySamples(*s.encoding, state, id, 0, 4000); });
    return s;
}

TEST(ProbeLight, NewProbesAreEmptyAndAProbeIsSampledOnceAnUpdateAddsASample) {
    for (const ProbeStateFormat format : kFormats) {
        const std::unique_ptr<ProbeEncoding> encoding = makeProbeEncoding(ProbeEncodingKind::Hemispherical, 5);
        ProbeLight light(*encoding, format);
        light.grow(3);
        for (uint32_t id = 0; id < 3; ++id) EXPECT_FALSE(light.sampled(id));
        light.update(1, [&](float*) {});
        EXPECT_FALSE(light.sampled(1)) << "an update that adds nothing";
        light.update(2, [&](float* state) { addSkySamples(*encoding, state, 2, 0, 1); });
        EXPECT_FALSE(light.sampled(0));
        EXPECT_FALSE(light.sampled(1));
        EXPECT_TRUE(light.sampled(2));
        light.grow(5);
        EXPECT_FALSE(light.sampled(4));
        EXPECT_EQ(light.probes(), 5u);
        EXPECT_EQ(encoding->sampleWeight(light.read(4)), 0.0f);
        EXPECT_TRUE(light.sampled(2)) << "growing keeps the probes";
    }
}

// The update stage hands a probe all its samples of a frame in one update: in float32 that is the
// state of one update per sample bit for bit; in bfloat16 it rounds once instead of after each
// sample, so the two stay within the rounding of the samples' count (2^-8 relative each).
TEST(ProbeLight, OneUpdateWithSeveralSamplesIsOneUpdatePerSample) {
    for (const ProbeStateFormat format : kFormats) {
        const std::unique_ptr<ProbeEncoding> encoding = makeProbeEncoding(ProbeEncodingKind::Hemispherical, 5);
        ProbeLight together(*encoding, format), apart(*encoding, format);
        together.grow(1);
        apart.grow(1);
        constexpr int kSamples = 7;
        together.update(0, [&](float* state) { addSkySamples(*encoding, state, 0, 0, kSamples); });
        for (int i = 0; i < kSamples; ++i) apart.update(0, [&](float* state) { addSkySamples(*encoding, state, 0, i, 1); });
        const int floats = encoding->floatsPerProbe();
        const std::vector<float> a(together.read(0), together.read(0) + floats), b(apart.read(0), apart.read(0) + floats);
        for (int i = 0; i < floats; ++i) {
            if (format == ProbeStateFormat::Float32 || i >= encoding->sampleWeightsOffset())
                EXPECT_EQ(a[i], b[i]) << i;
            else
                EXPECT_LE(std::fabs(a[i] - b[i]), std::fabs(b[i]) * kSamples * 0x1p-8f) << i;
        }
        EXPECT_EQ(together.irradianceAtOwnNormal(0), encoding->irradiance(together.read(0), vec3(0.0f, 0.0f, 1.0f))) << "the memo is current";
    }
}

TEST(ProbeLight, AtTheProbesNormalTheMemoIsTheEncodingsIrradiance) {
    for (const ProbeEncodingKind kind : {ProbeEncodingKind::Hemispherical, ProbeEncodingKind::Octahedral, ProbeEncodingKind::SphericalHarmonics}) {
        for (const ProbeStateFormat format : kFormats) {
            SampledLight s = sampledLight(kind, kind == ProbeEncodingKind::SphericalHarmonics ? 2 : 5, 4, format);
            for (uint32_t id = 0; id < 4; ++id) {
                const Color exact = s.encoding->irradiance(s.light->read(id), vec3(0.0f, 0.0f, 1.0f));
                const Color memo = s.light->irradiance(id, vec3(0.0f, 0.0f, 1.0f));
                EXPECT_EQ(memo, exact) << s.encoding->name() << " probe " << id;
                EXPECT_GT(memo.y, 0.0f);
            }
        }
    }
}

// Within kMemoTilt of +z the memo answers, within the bound the header derives (2π |n − z| max L);
// beyond it the encoding answers exactly.
TEST(ProbeLight, NearTheNormalTheMemoStaysWithinItsBoundAndFartherTheEncodingAnswers) {
    SampledLight s = sampledLight(ProbeEncodingKind::Hemispherical, 5, 2, ProbeStateFormat::Float32);
    for (uint32_t id = 0; id < 2; ++id) {
        const float largest = s.largestRadiance * float(id + 1);
        for (const float tilt : {1e-5f, 1e-4f, 0.9f * ProbeLight::kMemoTilt, 2.0f * ProbeLight::kMemoTilt, 0.01f, 0.5f}) {
            for (const float azimuth : {0.0f, 1.0f, 2.5f, 4.0f}) {
                const vec3 n(std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth), std::cos(tilt));
                const Color exact = s.encoding->irradiance(s.light->read(id), n);
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
    for (const ProbeStateFormat format : kFormats) {
        SampledLight s = sampledLight(ProbeEncodingKind::Hemispherical, 5, 2, format);
        s.light->clear(1);
        EXPECT_FALSE(s.light->sampled(1));
        EXPECT_EQ(s.light->irradiance(1, vec3(0.0f, 0.0f, 1.0f)), Color(0.0f));
        EXPECT_EQ(s.encoding->sampleWeight(s.light->read(1)), 0.0f);
        for (int i = 0; i < s.encoding->floatsPerProbe(); ++i) EXPECT_EQ(s.light->read(1)[i], 0.0f) << i;
        EXPECT_TRUE(s.light->sampled(0)) << "the other probe keeps its light";
    }
}

// A bfloat16 state stores what an edit leaves: the sample weights exactly, every other value
// rounded to the nearest bfloat16 (within half a spacing, at most 2^-8 relative), and nothing of one
// probe leaks into another.
TEST(ProbeLight, ABFloat16StateKeepsTheWeightsExactAndRoundsTheMeansToNearest) {
    for (const ProbeEncodingKind kind : {ProbeEncodingKind::Hemispherical, ProbeEncodingKind::SphericalHarmonics}) {
        const std::unique_ptr<ProbeEncoding> encoding = makeProbeEncoding(kind, kind == ProbeEncodingKind::SphericalHarmonics ? 2 : 5);
        ProbeLight light(*encoding, ProbeStateFormat::BFloat16);
        light.grow(3);
        const int floats = encoding->floatsPerProbe();
        const auto valueOf = [](uint32_t id, int i) { return (1.0f + 0.123456f * float(i)) * float(id + 1) * (i % 3 == 0 ? -1.0f : 1.0f) * 3.3333f; };
        for (uint32_t id = 0; id < 3; ++id)
            light.update(id, [&](float* state) {
                for (int i = 0; i < floats; ++i) state[i] = valueOf(id, i);
            });
        int weights = 0;
        for (uint32_t id = 0; id < 3; ++id) {
            const float* state = light.read(id);
            for (int i = 0; i < floats; ++i) {
                const float written = valueOf(id, i);
                if (i >= encoding->sampleWeightsOffset()) {
                    EXPECT_EQ(state[i], written) << encoding->name() << " weight " << i;
                    weights += id == 0;
                } else {
                    EXPECT_EQ(state[i], fromBFloat16(toBFloat16(written))) << encoding->name() << " value " << i;
                    EXPECT_LE(std::fabs(state[i] - written), std::fabs(written) * 0x1p-8f) << encoding->name() << " value " << i;
                }
            }
        }
        EXPECT_EQ(weights, kind == ProbeEncodingKind::SphericalHarmonics ? 1 : 26) << "the counts of 25 bins and of the probe";
        // Bytes: the weights as floats, the rest as halves, and the memo.
        const std::size_t memo = ProbeLight(*encoding, ProbeStateFormat::Float32).bytesPerProbe() - std::size_t(floats) * sizeof(float);
        EXPECT_EQ(light.bytesPerProbe(), std::size_t(weights) * 4 + std::size_t(floats - weights) * 2 + memo);
    }
}

TEST(BFloat16, RoundsToNearestTiesToEvenAndKeepsInfinityAndNaN) {
    EXPECT_EQ(toBFloat16(1.0f), 0x3f80);
    EXPECT_EQ(fromBFloat16(0x3f80), 1.0f);
    EXPECT_EQ(fromBFloat16(toBFloat16(1.0f + 0x1p-8f)), 1.0f) << "a tie goes to the even neighbour, 1";
    EXPECT_EQ(fromBFloat16(toBFloat16(1.0f + 3.0f * 0x1p-8f)), 1.0f + 0x1p-6f) << "a tie goes to the even neighbour, 1 + 2^-6";
    EXPECT_EQ(fromBFloat16(toBFloat16(1.0f + 0x1p-8f + 0x1p-20f)), 1.0f + 0x1p-7f) << "past the tie: up";
    EXPECT_EQ(fromBFloat16(toBFloat16(-2.5f)), -2.5f);
    EXPECT_EQ(fromBFloat16(toBFloat16(0x1p120f)), 0x1p120f) << "kMaxProbeRadiance is exact";
    EXPECT_EQ(fromBFloat16(toBFloat16(INFINITY)), INFINITY);
    EXPECT_EQ(fromBFloat16(toBFloat16(-INFINITY)), -INFINITY);
    EXPECT_TRUE(std::isnan(fromBFloat16(toBFloat16(NAN))));
    EXPECT_TRUE(std::isnan(fromBFloat16(toBFloat16(std::bit_cast<float>(0x7f800001u))))) << "a NaN whose payload lies in the low half only";
    // Every bfloat16 that is a number converts back to itself.
    for (uint32_t h = 0; h < 0x10000; ++h) {
        const float f = fromBFloat16(uint16_t(h));
        if (!std::isnan(f)) {
            EXPECT_EQ(toBFloat16(f), h) << std::hex << h;
        }
    }
}

// The gather reads irradianceAtOwnNormal() where a surface faces exactly as the probe: that is what
// irradiance() of the local normal returns, because every unit normal (axis-aligned ones, the
// poles, normals renormalised off unit length) lies within kMemoTilt of +z in its own frame.
TEST(ProbeLight, ASurfaceFacingAsItsProbeReadsWhatTheLocalNormalWould) {
    for (const ProbeStateFormat format : kFormats) {
        SampledLight s = sampledLight(ProbeEncodingKind::Hemispherical, 5, 1, format);
        uint32_t state = 7u;
        const auto next = [&state] {
            state = state * 747796405u + 2891336453u;
            return float(state >> 8) / float(1u << 24) * 2.0f - 1.0f;
        };
        std::vector<vec3> normals = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {1e-7f, 0, -1}, {0, 1e-7f, 1}};
        for (int i = 0; i < 100000; ++i) normals.push_back(glm::normalize(vec3(next(), next(), next())));
        for (int i = 0; i < 1000; ++i) normals.push_back(glm::normalize(vec3(next() * 1e-4f, next() * 1e-4f, next() < 0.0f ? -1.0f : 1.0f)));
        for (const vec3& n : normals) {
            const vec3 local = Frame(n).toLocal(n);
            ASSERT_GT(local.z, 0.0f) << n.x << " " << n.y << " " << n.z;
            ASSERT_LE(std::hypot(local.x, local.y), 1e-2f * ProbeLight::kMemoTilt) << n.x << " " << n.y << " " << n.z;
            ASSERT_EQ(s.light->irradianceAtOwnNormal(0), s.light->irradiance(0, local));
        }
    }
}

}  // namespace
}  // namespace gibench
