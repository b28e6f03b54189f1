// Deterministic transcendental functions (SPEC §0).
//
// Every stage that feeds a golden uses these instead of libm, so that results are the same bits
// with any compiler, optimisation level and C library. Each function is written with + - * /,
// std::sqrt (IEEE correctly rounded) and integer bit manipulation only, in a fixed operation order,
// with no libm call (ref/core/dmath.cpp; build flag -ffp-contract=off, so no FMA contraction).
// The float functions widen to binary64, reduce the argument and evaluate the polynomial there
// (the logarithms and pow in double-double), and round once to float, so the error is below 1 ulp;
// tests/core/dmath_test.cpp measures the maximum ulp error of each function against libm's binary64
// result over 2^20 inputs and asserts the bound documented here (docs/determinism.md has the
// methods and the measured table: every float function measured 0.5 ulp, i.e. the float nearest to
// libm's binary64 value on every input tried). The same test checks a checksum of result bits that
// must not change between g++/clang++, -O0/-O2 and sanitizer builds.
//
// Special values follow C99 Annex F (NaN in -> NaN out, signed zeros, infinities); overflow gives
// +inf, underflow a correctly rounded subnormal or +0.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>

namespace fovref::dm {

inline constexpr float pi = 3.14159265358979323846f;
inline constexpr double pi_d = 3.14159265358979323846;
inline constexpr float two_pi = 6.28318530717958647692f;  ///< 2 pi rounded to binary32 once

float exp(float x);           ///< e^x. Max error 1 ulp (measured: see docs/determinism.md).
float exp2(float x);          ///< 2^x, exact for integer x. Max error 1 ulp.
float log(float x);           ///< natural log; log(0) = -inf, log(x<0) = NaN. Max error 1 ulp.
float log2(float x);          ///< log base 2, exact for powers of two. Max error 1 ulp.
float log10(float x);         ///< log base 10. Max error 1 ulp.
float pow(float x, float y);  ///< x^y with C99 special cases (pow_d rounded). Max error 1 ulp.
/// x^y like pow, evaluated in plain binary64 (no double-double) with short series: several
/// times faster, for per-pixel display conversions (gamma). ln of the mantissa by the atanh
/// series to s^17, e^r by Taylor to r^10; the error (below 2^-40 relative) is far below a
/// float ulp, so the result is the float nearest to x^y except within ~1e-5 ulp of a halfway
/// point. Max error 1 ulp (measured 0.5: tests/core/dmath_test.cpp).
/// Inputs other than finite x > 0 and finite y, and results outside [2^-149, 2^128), go to pow.
float pow_fast(float x, float y);
/// out[i] = pow_fast(x[i], y) for i < n, the same bits: on a CPU with AVX2 four lanes at a time,
/// each lane doing pow_series's binary64 operations in the same order (no FMA), and every lane it
/// declines (x not a finite normal > 0, x = 1, y ln x out of range) by pow_fast itself; the rest
/// by pow_fast. `x` and `out` may be the same array.
void pow_fast_array(const float* x, float y, float* out, std::size_t n);
/// out[i] = log2(x[i]) for i < n, the same bits: on a CPU with AVX2 four lanes at a time, each
/// lane doing log2's fast path (ln_series's binary64 operations in the same order, times 1/ln 2,
/// kept where it rounds like the true value) and every lane that path declines by log2 itself.
/// `x` and `out` may be the same array.
void log2_array(const float* x, float* out, std::size_t n);
/// out[i] = exp(x[i]) for i < n, the same bits: on a CPU with AVX2 four lanes at a time for
/// x in [-700, 700] (exp_core's binary64 operations in the same order, no FMA, scaled by 2^k
/// within the normal range), every other element by exp itself. `x` and `out` may be the same.
void exp_array(const float* x, float* out, std::size_t n);
namespace detail {
/// True when the binary64 value p, known to within 2^-41 relative of a value v (whose binary64
/// approximation is good to 2^-50), rounds to the same binary32 as v: p is a normal float's
/// magnitude, and its low 29 significand bits (what the rounding to binary32 drops; halfway is
/// 2^28) are more than 2^15 units from halfway, i.e. p is more than 2^-38 relative from every
/// binary32 rounding boundary.
inline bool rounds_like_truth(double p) {
    if (!(p >= 0x1p-126 && p < 0x1p128)) return false;
    const std::uint64_t low = std::bit_cast<std::uint64_t>(p) & ((1ull << 29) - 1);
    const std::uint64_t half = 1ull << 28;
    const std::uint64_t distance = low > half ? low - half : half - low;
    return distance > (1ull << 15);
}
}  // namespace detail

/// x^y for one exponent y fixed at construction, equal to pow(x, y) bit for bit for
/// every x and several times faster: for the per-pixel transfer curves (sRGB encode and decode,
/// FLIP's cube root and exponents). A normal x > 0 is 2^e m with m in [1, 2); tables hold
/// 2^(e y) for every e and c^y, 1/c at the 1024 midpoints c of m's top ten bits; (m/c)^y comes
/// from the binomial series to degree 4 (|m/c - 1| <= 2^-11). The binary64 product is within
/// 2^-47 of x^y; if it lies more than 2^-38 from every binary32 rounding boundary it rounds as
/// pow's value does, otherwise (about 1 input in 8192), and for zero, negative, subnormal,
/// non-finite x and results outside the normal range, the call goes to pow. Tables are built
/// with pow_d at construction (deterministic). An exponent outside [-4, 4] (or NaN) builds no
/// table and every call goes to pow.
class PowFixed {
public:
    explicit PowFixed(float y);
    float operator()(float x) const {
        const std::uint32_t xb = std::bit_cast<std::uint32_t>(x);
        if (tabled_ && xb - 0x00800000u < 0x7f000000u) {  // finite normal x > 0
            const std::uint32_t j = (xb >> 13) & 1023u;
            const double m =
                static_cast<double>(std::bit_cast<float>((xb & 0x007fffffu) | 0x3f800000u));
            const double c = 1.0 + static_cast<double>(2 * j + 1) * 0x1p-11;
            const double d = (m - c) * inv_[j];  // m - c exact: [1, 2) with 23 and 11 bits
            const double series = 1.0 + d * (c1_ + d * (c2_ + d * (c3_ + d * c4_)));
            const double p = scale_[xb >> 23] * base_[j] * series;
            if (detail::rounds_like_truth(p)) return static_cast<float>(p);
        }
        return pow(x, y_);
    }
    /// out[i] = (*this)(x[i]) for i < n (the same bits); four at a time with AVX2 where the CPU
    /// has it (each lane does the scalar code's binary64 operations in the same order, so it
    /// computes the same value and takes the same fallback decision). x and out must not
    /// overlap.
    void apply(const float* x, float* out, std::size_t n) const;
    float exponent() const { return y_; }

private:
    std::size_t apply_avx2(const float* x, float* out, std::size_t n) const;
    float y_;
    bool tabled_;
    double c1_, c2_, c3_, c4_;  ///< binomial coefficients y, y(y-1)/2, ...
    double scale_[256];         ///< 2^((E - 127) y) for the biased exponent E
    double base_[1024];         ///< c_j^y, c_j = 1 + (j + 1/2) 2^-10
    double inv_[1024];          ///< 1 / c_j
};

float sin(float x);             ///< full float range (Payne-Hanek reduction). Max error 1 ulp.
float cos(float x);             ///< full float range. Max error 1 ulp.
float tan(float x);             ///< full float range. Max error 1 ulp.
float atan(float x);            ///< Max error 1 ulp.
float atan2(float y, float x);  ///< C99 quadrant and zero/infinity rules. Max error 1 ulp.
float asin(float x);            ///< |x| > 1 -> NaN. Max error 1 ulp.
float acos(float x);            ///< |x| > 1 -> NaN. Max error 1 ulp.

/// Degrees to radians in float: x * (pi / 180) with the constant rounded once.
inline float radians(float degrees) { return degrees * 0.0174532925199432957692f; }
inline float degrees(float radians) { return radians * 57.2957795130823208768f; }

// Binary64 versions for reductions and reports (metrics, statistics); same methods, error at most
// 4 ulp in double against libm's long double functions (measured below 0.85 ulp in the same test).
double exp_d(double x);
double log_d(double x);
double log2_d(double x);  ///< log base 2 in double-double, rounded once to double
double log10_d(double x);
double pow_d(double x, double y);  ///< C99 F.9.4.4 special cases; log in double-double.

}  // namespace fovref::dm
