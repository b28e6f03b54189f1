// IEEE-754 binary16 ("half") in integer code (SPEC §9 item 5): BMFR stores its block matrix in
// binary16, as the authors' OpenCL code does (vstore_half, round to nearest even). No compiler
// extension or instruction set is used, so the bits are the same on every build.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

namespace fovref {

/// The binary16 nearest to f, ties to even; |f| >= 65520 gives +-inf, NaN a quiet NaN.
std::uint16_t half_from_float(float f);

/// The exact value of a binary16 (every half is a float).
float float_from_half(std::uint16_t h);

/// The largest finite binary16.
inline constexpr float half_max = 65504.0f;

/// What storing f as binary16 and loading it back gives, saturating instead of overflowing:
/// f is first clamped to [-65504, 65504] (so a finite input never becomes infinite; SPEC §0),
/// then rounded to the nearest binary16, ties to even. NaN stays NaN. Equal to
/// float_from_half(half_from_float(clamped f)) for every float (tests/bmfr/half_test.cpp). In
/// integer code: |f| >= 2^-14 (normal halves, and 0) rounds the float's mantissa to 10 bits (add
/// 0xfff plus the kept lowest bit, clear the 13 bits below; a carry moves into the exponent);
/// 0 < |f| < 2^-14 (subnormal halves, steps of 2^-24) goes through half_from_float.
inline float round_to_half(float f) {
    std::uint32_t x;
    std::memcpy(&x, &f, sizeof x);
    std::uint32_t ax = x & 0x7fffffffu;
    if (ax > 0x7f800000u) return f;          // NaN
    if (ax > 0x477fe000u) ax = 0x477fe000u;  // beyond 65504 (infinity too): 65504
    if (ax != 0 && ax < 0x38800000u) {       // a subnormal half
        const std::uint32_t clamped = (x & 0x80000000u) | ax;
        float c;
        std::memcpy(&c, &clamped, sizeof c);
        return float_from_half(half_from_float(c));
    }
    const std::uint32_t r = (x & 0x80000000u) | ((ax + 0x0fffu + ((ax >> 13) & 1u)) & 0xffffe000u);
    float out;
    std::memcpy(&out, &r, sizeof out);
    return out;
}

/// round_to_half of v[First] .. v[15] in place, with the same bits: straight-line loops of
/// integer operations with selects (no branches) that compilers vectorise for the common case,
/// then round_to_half for the rare elements in the subnormal range or NaN.
template <int First>
inline void round_to_half_span(float* v) {
    std::uint32_t bits[16];
    std::memcpy(bits + First, v + First, sizeof(float) * (16 - First));
    std::int32_t special = 0;
    for (int j = First; j < 16; ++j) {
        auto ax = static_cast<std::int32_t>(bits[j] & 0x7fffffffu);
        special |= (ax != 0 && ax < 0x38800000) || ax > 0x7f800000 ? 1 : 0;
        ax = ax > 0x477fe000 ? 0x477fe000 : ax;
        const auto a = static_cast<std::uint32_t>(ax);
        bits[j] = (bits[j] & 0x80000000u) | ((a + 0x0fffu + ((a >> 13) & 1u)) & 0xffffe000u);
    }
    if (special != 0) {
        for (int j = First; j < 16; ++j) {
            std::uint32_t x;
            std::memcpy(&x, &v[j], sizeof x);
            const std::uint32_t ax = x & 0x7fffffffu;
            if ((ax != 0 && ax < 0x38800000u) || ax > 0x7f800000u) {
                const float r = round_to_half(v[j]);
                std::memcpy(&bits[j], &r, sizeof r);
            }
        }
    }
    std::memcpy(v + First, bits + First, sizeof(float) * (16 - First));
}

/// round_to_half of 16 consecutive floats in place.
inline void round_to_half_16(float* v) { round_to_half_span<0>(v); }

}  // namespace fovref
