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

namespace fovref::dm {

inline constexpr float pi = 3.14159265358979323846f;
inline constexpr double pi_d = 3.14159265358979323846;

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
double log10_d(double x);
double pow_d(double x, double y);  ///< C99 F.9.4.4 special cases; log in double-double.

}  // namespace fovref::dm
