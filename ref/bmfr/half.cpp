#include "ref/bmfr/half.h"

#include <cstring>

#ifdef FOVREF_HALF_F16C
#include <cpuid.h>
#endif

namespace fovref {

namespace {

std::uint32_t bits_of(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}

float float_of(std::uint32_t u) {
    float f;
    std::memcpy(&f, &u, sizeof f);
    return f;
}

}  // namespace

std::uint16_t half_from_float(float f) {
    const std::uint32_t x = bits_of(f);
    const auto sign = static_cast<std::uint16_t>((x >> 16) & 0x8000u);
    const std::uint32_t ax = x & 0x7fffffffu;
    // NaN and infinity
    if (ax > 0x7f800000u) return static_cast<std::uint16_t>(sign | 0x7e00u);
    // 65520 and above round to infinity (65520 is the tie between 65504 and 2^16: even wins)
    if (ax >= 0x477ff000u) return static_cast<std::uint16_t>(sign | 0x7c00u);
    // Normal halves (|f| >= 2^-14): round the 23-bit mantissa to 10 bits, ties to even; a
    // carry moves into the exponent, which is rebiased from 127 to 15.
    if (ax >= 0x38800000u) {
        const std::uint32_t rounded = ax + 0x0fffu + ((ax >> 13) & 1u);
        return static_cast<std::uint16_t>(sign | ((rounded - (112u << 23)) >> 13));
    }
    // Below half of the smallest subnormal (2^-25, a tie with zero included): zero
    if (ax <= 0x33000000u) return sign;
    // Subnormal halves: units of 2^-24; the 24-bit significand m times 2^(e - 126) in those
    // units, e the biased exponent (102 .. 112), rounded to nearest even.
    const std::uint32_t e = ax >> 23;
    const std::uint32_t m = (ax & 0x7fffffu) | 0x800000u;
    const std::uint32_t shift = 126u - e;  // 14 .. 24
    std::uint32_t q = m >> shift;
    const std::uint32_t rest = m & ((1u << shift) - 1u);
    const std::uint32_t half_unit = 1u << (shift - 1u);
    if (rest > half_unit || (rest == half_unit && (q & 1u) != 0)) ++q;
    return static_cast<std::uint16_t>(sign | q);  // q = 0x400 is the smallest normal: correct
}

#ifdef FOVREF_HALF_F16C
namespace {

// CPUID leaf 1: F16C (ECX bit 29) and AVX (bit 28), whose VEX encoding F16C uses, with the
// operating system saving the AVX state (OSXSAVE, bit 27, and XCR0 bits 1 and 2). By hand:
// clang 14's __builtin_cpu_supports does not know "f16c".
bool detect_f16c() {
    unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
    if (!__get_cpuid(1, &eax, &ebx, &ecx, &edx)) return false;
    const unsigned needed = (1u << 27) | (1u << 28) | (1u << 29);
    if ((ecx & needed) != needed) return false;
    unsigned xcr0_low = 0, xcr0_high = 0;
    __asm__("xgetbv" : "=a"(xcr0_low), "=d"(xcr0_high) : "c"(0));
    return (xcr0_low & 6u) == 6u;
}

}  // namespace

bool cpu_has_f16c() {
    static const bool has = detect_f16c();
    return has;
}
#endif

float float_from_half(std::uint16_t h) {
    const std::uint32_t sign = static_cast<std::uint32_t>(h & 0x8000u) << 16;
    const std::uint32_t e = (h >> 10) & 0x1fu;
    const std::uint32_t m = h & 0x3ffu;
    if (e == 0x1fu) return float_of(sign | 0x7f800000u | (m << 13));
    if (e != 0) return float_of(sign | ((e + 112u) << 23) | (m << 13));
    // subnormal (or zero): m 2^-24, exact in float
    const float v = static_cast<float>(m) * (1.0f / 16777216.0f);
    return sign != 0 ? -v : v;
}

}  // namespace fovref
