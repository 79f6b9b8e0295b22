// Sobol direction vectors, derived at compile time from the primitive polynomials and initial
// direction numbers (Joe and Kuo 2008, file new-joe-kuo-6.21201, its dimensions 2–4), and the
// byte tables sampler.h evaluates them and reverses bits with.

#include "core/render/sampler.h"

namespace gibench {
namespace {

using Directions = std::array<std::array<uint32_t, 32>, kSobolDimensions>;

// A primitive polynomial x^s + a_1 x^(s−1) + … + a_(s−1) x + 1 over GF(2) (a holds a_1 … a_(s−1),
// a_1 the highest bit) and the odd initial numbers m_1 … m_s, m_i < 2^i.
struct Polynomial {
    int degree;
    uint32_t a;
    std::array<uint32_t, 3> m;
};

constexpr Directions deriveDirections() {
    constexpr Polynomial kPolynomials[kSobolDimensions - 1] = {{1, 0, {1}}, {2, 1, {1, 3}}, {3, 1, {1, 3, 1}}};
    Directions v{};
    for (int j = 0; j < 32; ++j) v[0][j] = 1u << (31 - j);  // van der Corput: all m_k = 1
    for (int d = 1; d < kSobolDimensions; ++d) {
        const Polynomial& p = kPolynomials[d - 1];
        const int s = p.degree;
        std::array<uint32_t, 33> m{};  // m[k] for k = 1..32; m_k < 2^k, so it fits 32 bits
        for (int k = 1; k <= s; ++k) m[k] = p.m[k - 1];
        // m_k = 2 a_1 m_(k−1) ⊕ 2² a_2 m_(k−2) ⊕ … ⊕ 2^(s−1) a_(s−1) m_(k−s+1) ⊕ 2^s m_(k−s) ⊕ m_(k−s)
        for (int k = s + 1; k <= 32; ++k) {
            uint32_t next = m[k - s] ^ (m[k - s] << s);
            for (int i = 1; i < s; ++i)
                if ((p.a >> (s - 1 - i)) & 1u) next ^= m[k - i] << i;
            m[k] = next;
        }
        for (int j = 0; j < 32; ++j) v[d][j] = m[j + 1] << (31 - j);  // v_k = m_k / 2^k
    }
    return v;
}

constexpr Directions kDirections = deriveDirections();

// Bit b of reverse(I) is bit 31 − b of I, which xors in direction 31 − b; the table holds the
// reversed xor so that the value comes out reversed too.
constexpr sobol_detail::SobolTables buildTables() {
    sobol_detail::SobolTables t{};
    for (int k = 0; k < kSobolDimensions; ++k)
        for (int byte = 0; byte < 4; ++byte)
            for (uint32_t value = 0; value < 256; ++value) {
                uint32_t x = 0;
                for (int bit = 0; bit < 8; ++bit)
                    if ((value >> bit) & 1u) x ^= sobol_detail::reverseBits(kDirections[k][31 - (8 * byte + bit)]);
                t.reversedSobol[k][byte][value] = x;
            }
    for (uint32_t value = 0; value < 256; ++value) t.reversedByte[value] = uint8_t(sobol_detail::reverseBits(value) >> 24);
    return t;
}

}  // namespace

constinit const sobol_detail::SobolTables sobol_detail::kSobolTables = buildTables();

const std::array<uint32_t, 32>& sobolDirections(int dimension) { return kDirections[dimension]; }

}  // namespace gibench
