#pragma once
// The uniform random numbers one camera path consumes, named by what they sample, from either of
// two samplers with the same interface (the PathSampler concept):
//  - IndependentSampler: PCG32 numbers (core/util/rng.h) in the order the path tracer has always
//    drawn them, so that its images stay bit-identical;
//  - SobolSampler: Sobol–Burley (Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4)),
//    a low-discrepancy sequence per pixel.
// Both are pure functions of (run seed, frame, pixel, sample index, dimension): images do not
// depend on the thread count. Neither allocates nor calls virtually.
//
// Sobol–Burley. The first four dimensions of the Sobol sequence (dimension 0 is van der Corput's,
// 1–3 use Joe and Kuo's direction numbers). Every value is Owen-scrambled (nested uniform
// scrambling) by a hash seeded by (seed, dimension), and the sample index is shuffled by the same
// kind of scramble seeded by (seed, group): "padding", so that each group of four dimensions is a
// Sobol point of its own, decorrelated from the other groups, and any number of dimensions is
// available. The seed is hashed from (run seed, frame, pixel). Owen scrambling keeps the
// stratification — in the first 2^k samples (and every later aligned block of 2^k) every
// dimension holds one value per interval [i/2^k, (i+1)/2^k), and dimensions (0, 1) of a group are
// a (0, 2)-sequence (one point per elementary interval of area 2^-k) — while making every value
// uniform on [0, 1): unbiased. No other pair of the four is a (0, 2)-sequence ((1, 2), (1, 3) and
// (2, 3) share their first two direction vectors; (0, 2) and (0, 3) fail from 8 points on), so
// every 2D sample below takes dimensions (0, 1) of a group of its own.
//
// Dimension layout of SobolSampler: global dimension 4 · group + k, k = Sobol dimension; depth b
// numbers the scattering vertices along the path (0 = the first hit), and every group is used at
// every depth whether or not a branch takes its numbers, so that samples line up.
//   group 0         camera jitter x, y (k = 0, 1)
//   group 1 + 2b    light sample at depth b: point on the light u (k = 0, 1), light selection (k = 2)
//   group 2 + 2b    BSDF sample at depth b: direction u (k = 0, 1), lobe (k = 2), Russian roulette (k = 3)

#include "core/util/math.h"
#include "core/util/rng.h"

#include <array>
#include <concepts>
#include <cstdint>

namespace gibench {

// What LightSampler::sample() takes (core/render/light_sampler.h).
struct LightSampleUniforms {
    float select;  // picks the light
    vec2 u;        // picks the point on it
};

// What Bsdf::sample() takes (core/render/bsdf.h).
struct BsdfSampleUniforms {
    float lobe;
    vec2 u;  // picks the direction
};

// The numbers of one path, by purpose; `depth` is the scattering vertex they are used at.
template <typename S>
concept PathSampler = requires(S s, int depth) {
    { s.cameraJitter() } -> std::same_as<vec2>;  // offsets in [0, 1)² within the pixel
    { s.light(depth) } -> std::same_as<LightSampleUniforms>;
    { s.bsdf(depth) } -> std::same_as<BsdfSampleUniforms>;
    { s.russianRoulette(depth) } -> std::same_as<float>;
};

// Light-sample numbers drawn from `rng`: select, then u.y, then u.x — y before x because that is
// the order GCC gave the unsequenced `vec2(rng.uniform(), rng.uniform())` the existing images were
// made with.
inline LightSampleUniforms drawLightSampleUniforms(Rng& rng) {
    const float select = rng.uniform();
    const float y = rng.uniform();
    const float x = rng.uniform();
    return {select, vec2(x, y)};
}

// PCG32 numbers, each drawn when asked for (Russian roulette only when a path reaches it).
class IndependentSampler {
public:
    explicit IndependentSampler(const Rng& rng) : m_rng(rng) {}

    vec2 cameraJitter() {
        const float x = m_rng.uniform();
        const float y = m_rng.uniform();
        return {x, y};
    }
    LightSampleUniforms light(int) { return drawLightSampleUniforms(m_rng); }
    // lobe, then u.y, then u.x, as drawLightSampleUniforms() and for the same reason.
    BsdfSampleUniforms bsdf(int) {
        const float lobe = m_rng.uniform();
        const float y = m_rng.uniform();
        const float x = m_rng.uniform();
        return {lobe, vec2(x, y)};
    }
    float russianRoulette(int) { return m_rng.uniform(); }

private:
    Rng m_rng;
};

inline constexpr int kSobolDimensions = 4;

// Direction vectors of Sobol dimension `dimension` (0..3): bit j of the index xors in element j, a
// 32-bit binary fraction (element j = m_{j+1} · 2^(31−j) in Joe and Kuo's notation).
const std::array<uint32_t, 32>& sobolDirections(int dimension);

namespace sobol_detail {

constexpr uint32_t reverseBits(uint32_t x) {
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
    x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
    return (x >> 16) | (x << 16);
}

// A nested uniform scramble of bit-reversed fixed-point digits (Burley 2020, after Laine and
// Karras 2011): adding the seed, and xoring in the product with an even constant, change each bit
// only as a function of the bits below it. Reversed back, every binary digit of the value is
// flipped as a function of the digits before it alone — the structure of an Owen scramble — and
// adding a uniform seed first makes the result uniform over all 2^32 values.
inline uint32_t owenScrambleReversed(uint32_t reversed, uint32_t seed) {
    uint32_t x = reversed + seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

// The scrambles work on bit-reversed digits, so the index and the values stay reversed from the
// index shuffle to the last scramble: byte tables map the reversed shuffled index straight to the
// reversed Sobol value, and a last table look-up per byte reverses the digits the float keeps.
// That spares three of the four full reversals a value would otherwise take.
struct SobolTables {
    uint32_t reversedSobol[kSobolDimensions][4][256];  // [k][byte b of reverse(I)][its value]: xors to reverse(Sobol_k(I))
    uint8_t reversedByte[256];
};
extern const SobolTables kSobolTables;

inline uint32_t reversedSobol(uint32_t reversedIndex, int k) {
    const auto& t = kSobolTables.reversedSobol[k];
    return t[0][reversedIndex & 0xffu] ^ t[1][(reversedIndex >> 8) & 0xffu] ^ t[2][(reversedIndex >> 16) & 0xffu] ^ t[3][reversedIndex >> 24];
}

// The fraction whose binary digits are the bits of `reversed` from the lowest up, to 24 digits
// (the precision of Rng::uniform()): in [0, 1).
inline float fractionFromReversed(uint32_t reversed) {
    const uint8_t* r = kSobolTables.reversedByte;
    const uint32_t digits = uint32_t(r[reversed & 0xffu]) << 16 | uint32_t(r[(reversed >> 8) & 0xffu]) << 8 | r[(reversed >> 16) & 0xffu];
    return float(digits) * 0x1p-24f;
}

// Scramble seeds, hashed from the sequence's seed as SplitMix64 steps its state: step 3g seeds the
// index shuffle of group g, steps 3g + 1 and 3g + 2 its dimensions (0, 1) and (2, 3), one 32-bit
// half of the hash each, so that every dimension and every shuffle has a seed of its own.
inline uint64_t seedHash(uint64_t seed, uint64_t step) { return mix64(seed + 0x9e3779b97f4a7c15ull * step); }
inline uint32_t indexShuffleSeed(uint64_t seed, uint32_t group) { return uint32_t(seedHash(seed, 3 * uint64_t(group))); }
// The scramble seeds of the dimension pair (2j, 2j + 1) holding `dimension`: the low and high halves.
inline uint64_t valueScramblePairSeeds(uint64_t seed, uint64_t dimension) { return seedHash(seed, 3 * (dimension / 4) + 1 + (dimension % 4) / 2); }
inline uint32_t valueScrambleSeed(uint64_t seed, uint64_t dimension) {
    return uint32_t(valueScramblePairSeeds(seed, dimension) >> (32 * (dimension % 2)));
}

}  // namespace sobol_detail

// The seed of one pixel's Sobol–Burley sequence in one frame of a run.
inline uint64_t sobolSeed(uint64_t runSeed, uint64_t frame, uint64_t pixel) {
    return mix64(mix64(runSeed ^ mix64(frame + 0x2545f4914f6cdd1dull)) ^ mix64(pixel + 0x94d049bb133111ebull));
}

// Sample `index` of the Sobol–Burley sequence `seed` in the four dimensions of `group`
// (global dimensions 4 · group + k).
class SobolBurleyPoint {
public:
    SobolBurleyPoint(uint64_t seed, uint32_t index, uint32_t group) : SobolBurleyPoint(ReversedIndex{sobol_detail::reverseBits(index)}, seed, group) {}

    // The same from the index bit-reversed once, for a caller that draws several groups of it.
    struct ReversedIndex {
        uint32_t bits;
    };
    SobolBurleyPoint(ReversedIndex index, uint64_t seed, uint32_t group)
        : m_seed(seed),
          m_firstDimension(4 * uint64_t(group)),
          m_reversedIndex(sobol_detail::owenScrambleReversed(index.bits, sobol_detail::indexShuffleSeed(seed, group))) {}

    // Dimension k (0..3) in [0, 1), 24 bits as Rng::uniform().
    float operator[](int k) const { return scrambled(k, sobol_detail::valueScrambleSeed(m_seed, m_firstDimension + k)); }
    // Dimensions k and k + 1 (k = 0 or 2), the same values as [k] and [k + 1]: their scramble seeds
    // are the two halves of one hash, computed once.
    vec2 pair(int k) const {
        const uint64_t seeds = sobol_detail::valueScramblePairSeeds(m_seed, m_firstDimension + uint64_t(k));
        return {scrambled(k, uint32_t(seeds)), scrambled(k + 1, uint32_t(seeds >> 32))};
    }

private:
    float scrambled(int k, uint32_t scrambleSeed) const {
        return sobol_detail::fractionFromReversed(sobol_detail::owenScrambleReversed(sobol_detail::reversedSobol(m_reversedIndex, k), scrambleSeed));
    }

    uint64_t m_seed;
    uint64_t m_firstDimension;
    uint32_t m_reversedIndex;  // the shuffled index, bit-reversed
};

// Sobol–Burley numbers in the dimension layout above.
class SobolSampler {
public:
    // `sampleIndex` counts the pixel's samples since accumulation restarted in `frame`.
    SobolSampler(uint64_t runSeed, uint64_t frame, uint64_t pixel, uint32_t sampleIndex)
        : m_seed(sobolSeed(runSeed, frame, pixel)), m_index{sobol_detail::reverseBits(sampleIndex)} {}

    vec2 cameraJitter() const { return point(kCameraGroup).pair(0); }
    LightSampleUniforms light(int depth) const {
        const SobolBurleyPoint p = point(lightGroup(depth));
        return {p[2], p.pair(0)};
    }
    BsdfSampleUniforms bsdf(int depth) const {
        const SobolBurleyPoint p = point(bsdfGroup(depth));
        return {p[2], p.pair(0)};
    }
    float russianRoulette(int depth) const { return point(bsdfGroup(depth))[3]; }

    static constexpr uint32_t kCameraGroup = 0;
    static uint32_t lightGroup(int depth) { return 1 + 2 * uint32_t(depth); }
    static uint32_t bsdfGroup(int depth) { return 2 + 2 * uint32_t(depth); }

private:
    SobolBurleyPoint point(uint32_t group) const { return SobolBurleyPoint(m_index, m_seed, group); }

    uint64_t m_seed;
    SobolBurleyPoint::ReversedIndex m_index;
};

}  // namespace gibench
