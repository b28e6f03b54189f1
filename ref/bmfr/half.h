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
/// float_from_half(half_from_float(clamped f)) for every float (tests/bmfr/half_test.cpp), without
/// branches on the value's range, so the QR's inner loops can use it per element:
///   |f| >= 2^-14 (normal halves): the float's mantissa rounded to 10 bits in integer code
///     (add 0xfff plus the kept lowest bit, clear the 13 bits below; a carry moves into the
///     exponent);
///   |f| < 2^-14 (subnormal halves, steps of 2^-24): (|f| + 0.5) - 0.5 in binary32, whose
///     rounding is exactly to a multiple of 2^-24, ties to even.
inline float round_to_half(float f) {
    const float clamped = f < -half_max ? -half_max : (f > half_max ? half_max : f);
    std::uint32_t x;
    std::memcpy(&x, &clamped, sizeof x);
    const std::uint32_t sign = x & 0x80000000u;
    const std::uint32_t ax = x & 0x7fffffffu;
    const std::uint32_t normal_bits = sign | ((ax + 0x0fffu + ((ax >> 13) & 1u)) & 0xffffe000u);
    float normal;
    std::memcpy(&normal, &normal_bits, sizeof normal);
    const float magnitude = std::fabs(clamped);
    const float subnormal = std::copysign((magnitude + 0.5f) - 0.5f, clamped);
    if (ax > 0x7f800000u) return clamped;  // NaN
    return ax >= 0x38800000u ? normal : subnormal;
}

/// round_to_half of 16 consecutive floats in place, written as straight-line loops of integer
/// and float operations with selects (no branches), so that compilers vectorise it; the same
/// bits as round_to_half element by element.
inline void round_to_half_16(float* v) {
    std::uint32_t bits[16], magnitude_bits[16], subnormal_bits[16];
    float magnitude[16], subnormal[16];
    std::memcpy(bits, v, sizeof bits);
    // |v| clamped to 65504 in integer code (the bits of non-negative floats are ordered); NaN
    // (above 0x7f800000) is kept
    for (int j = 0; j < 16; ++j) {
        const auto ax = static_cast<std::int32_t>(bits[j] & 0x7fffffffu);
        magnitude_bits[j] =
            static_cast<std::uint32_t>(ax > 0x477fe000 && ax <= 0x7f800000 ? 0x477fe000 : ax);
    }
    std::memcpy(magnitude, magnitude_bits, sizeof magnitude);
    for (int j = 0; j < 16; ++j) subnormal[j] = (magnitude[j] + 0.5f) - 0.5f;
    std::memcpy(subnormal_bits, subnormal, sizeof subnormal_bits);
    for (int j = 0; j < 16; ++j) {
        const auto ax = static_cast<std::int32_t>(magnitude_bits[j]);
        const auto normal = static_cast<std::int32_t>(
            (magnitude_bits[j] + 0x0fffu + ((magnitude_bits[j] >> 13) & 1u)) & 0xffffe000u);
        std::int32_t r = ax >= 0x38800000 ? normal : static_cast<std::int32_t>(subnormal_bits[j]);
        r = ax > 0x7f800000 ? ax : r;
        bits[j] = (bits[j] & 0x80000000u) | static_cast<std::uint32_t>(r);
    }
    std::memcpy(v, bits, sizeof bits);
}

}  // namespace fovref
