#pragma once
// Deterministic random numbers: one small generator per (seed, frame, pixel, sample) stream, so an
// image is the same whatever the thread count or the order tiles are rendered in.

#include <cstdint>

namespace gibench {

// SplitMix64 finaliser: a bijective 64-bit mix, used to turn stream coordinates into seeds.
inline uint64_t mix64(uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

// The per-pixel random streams of a frame, one id per stage that draws numbers, so that no two
// stages of a method draw the same ones. (path_traced numbers its streams by sample index.)
enum class RandomStream : uint64_t {
    GBuffer = 0x6b0ffe4,          // primary-ray jitter
    Direct = 0xd14ec7,            // next-event estimation at primary hits
    Secondary = 0x5ec0d,          // the probe cache's secondary paths
    RestirCandidates = 0x4e5719a, // ReSTIR's light candidates and temporal merge
    RestirSpatial = 0x4e5719b,    // ReSTIR's spatial neighbours and merge
    LookupJitter = 0x11771e,      // the probe cache's per-lookup jitter bits (ProbeQuery::jitter)
};

// PCG32 (O'Neill 2014, XSH-RR output): 64-bit state, 32-bit outputs, selectable stream.
class Rng {
public:
    Rng(uint64_t seed, uint64_t stream) {
        m_inc = (stream << 1u) | 1u;
        m_state = 0;
        next();
        m_state += seed;
        next();
    }

    // The generator of one path: a pure function of its coordinates. Its state is a hash of them
    // and every path steps along one stream: a per-pixel stream and seeding through the
    // constructor cost three hashes and two steps per pixel, most of the time a probe-cache frame
    // spends drawing a pixel's light sample. Paths start at independent points of the one
    // 2^64-long cycle: among 2^26 paths of up to 2^9 numbers (256² pixels at 1024 spp), the
    // expected number of pairs whose stretches of the cycle overlap at all is 2^-3.
    static Rng forPath(uint64_t runSeed, uint64_t frame, uint64_t pixel, uint64_t sample) {
        // The first hashes depend on the frame and sample only: a loop over pixels computes them once.
        const uint64_t key = mix64(runSeed ^ mix64(frame + 0x632be59bd9b4e019ull)) ^ mix64(sample + 0x8cb92ba72f3d8dd7ull);
        return Rng(State{mix64(pixel ^ key)});
    }

    static Rng forPath(uint64_t runSeed, uint64_t frame, uint64_t pixel, RandomStream stream) {
        return forPath(runSeed, frame, pixel, uint64_t(stream));
    }

    uint32_t next() {
        const uint64_t old = m_state;
        m_state = old * 6364136223846793005ull + m_inc;
        const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
        const uint32_t rot = uint32_t(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
    }

    // Uniform in [0, 1): 24 random bits, so 1 is never returned.
    float uniform() { return float(next() >> 8) * 0x1p-24f; }

private:
    struct State {
        uint64_t bits;
    };
    // PCG's default stream (O'Neill's pcg32 increment), from a given state.
    explicit Rng(State state) : m_state(state.bits), m_inc(1442695040888963407ull) {}

    uint64_t m_state;
    uint64_t m_inc;
};

}  // namespace gibench
