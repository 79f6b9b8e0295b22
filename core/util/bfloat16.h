#pragma once
// bfloat16: the upper half of an IEEE 754 single (sign, 8 exponent bits, 7 stored mantissa bits),
// so a float's whole range at a relative spacing of 2^-7 to 2^-8. Rounding is to nearest, ties to
// even, which is what the format's users (probe states) need: no drift from always rounding one
// way. A float beyond the largest bfloat16 (about 3.39e38) rounds to infinity; NaN stays NaN.

#include <bit>
#include <cstdint>

namespace gibench {

inline uint16_t toBFloat16(float x) {
    const uint32_t u = std::bit_cast<uint32_t>(x);
    if ((u & 0x7fffffffu) > 0x7f800000u) return uint16_t((u >> 16) | 0x0040u);  // NaN: keep it quiet, whatever its payload
    return uint16_t((u + 0x7fffu + ((u >> 16) & 1u)) >> 16);
}

inline float fromBFloat16(uint16_t h) { return std::bit_cast<float>(uint32_t(h) << 16); }

}  // namespace gibench
