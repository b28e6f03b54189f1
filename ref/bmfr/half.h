// IEEE-754 binary16 ("half") in integer code (SPEC §9 item 5): BMFR stores its block matrix in
// binary16, as the authors' OpenCL code does (vstore_half, round to nearest even). The integer
// code is the reference and runs everywhere; on x86 CPUs with F16C the fit's row rounding takes
// the conversion instructions instead (round_to_half_span_f16c), which give the same bits
// (tests/bmfr/half_test.cpp compares them).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define FOVREF_HALF_F16C 1
#endif

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

#ifdef FOVREF_HALF_F16C
/// Whether this CPU converts with F16C (the x86 float <-> binary16 instructions).
bool cpu_has_f16c();

/// round_to_half_span<First> with F16C, the same bits: each lane clamped to [-65504, 65504]
/// (min and max), converted to binary16 by vcvtps2ph with round to nearest even from the
/// instruction (not MXCSR) and back by vcvtph2ps, exact IEEE conversions as round_to_half's.
/// NaN is the one input whose bits the instructions change (a quieted, shortened payload):
/// when a lane is NaN nothing is written and it returns false (the caller then takes
/// round_to_half_span). Call only when cpu_has_f16c(); First a multiple of 4.
template <int First>
__attribute__((target("f16c"))) inline bool round_to_half_span_f16c(float* v) {
    static_assert(First % 4 == 0 && First < 16, "whole groups of 4 lanes");
    constexpr int groups = (16 - First) / 4;
    __m128 x[groups];
    __m128 nan = _mm_setzero_ps();
    for (int k = 0; k < groups; ++k) {
        x[k] = _mm_loadu_ps(v + First + 4 * k);
        nan = _mm_or_ps(nan, _mm_cmpunord_ps(x[k], x[k]));
    }
    if (_mm_movemask_ps(nan) != 0) return false;
    const __m128 hi = _mm_set1_ps(half_max), lo = _mm_set1_ps(-half_max);
    for (int k = 0; k < groups; ++k) {
        const __m128 clamped = _mm_min_ps(_mm_max_ps(x[k], lo), hi);
        _mm_storeu_ps(v + First + 4 * k,
                      _mm_cvtph_ps(_mm_cvtps_ph(clamped, _MM_FROUND_TO_NEAREST_INT)));
    }
    return true;
}
#endif

}  // namespace fovref
