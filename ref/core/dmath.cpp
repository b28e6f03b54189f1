// Deterministic transcendental functions (SPEC §0). See dmath.h for the contract and
// docs/determinism.md for the methods, the error bounds and the measured errors.
//
// Rules this file keeps so that every compiler and optimisation level gives the same bits:
//   * only + - * /, std::sqrt (IEEE correctly rounded) and integer bit manipulation; no libm call
//     (not even ldexp/frexp/copysign: exponents and signs are handled on the bits);
//   * no std::fma and no contraction (the build uses -ffp-contract=off), so every expression is
//     evaluated exactly as written, one IEEE rounding per operation, left to right;
//   * float functions widen to binary64, reduce and evaluate there, and round once to float.
//
// Rounding to the nearest integer uses the "shifter" trick (t + 1.5*2^52) - 1.5*2^52, exact round
// half to even for |t| < 2^51; it is a plain IEEE addition and subtraction, which no
// value-preserving compiler may fold.
#include "ref/core/dmath.h"
#include "ref/core/avx_lanes.h"
#include "ref/core/simd.h"

#include <bit>
#include <cmath>  // std::sqrt only
#include <cstdint>
#include <limits>

#include <immintrin.h>

namespace fovref::dm {
namespace {

using u32 = std::uint32_t;
using u64 = std::uint64_t;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---- Constants ------------------------------------------------------------------------------
// ln 2 split as in fdlibm: kLn2Hi has 32 significant bits, so k * kLn2Hi is exact for |k| < 2^21;
// kLn2Hi + kLn2Lo equals ln 2 to 2^-85 relative.
constexpr double kLn2Hi = 0x1.62e42fee00000p-1;
constexpr double kLn2Lo = 0x1.a39ef35793c76p-33;
constexpr double kInvLn2 = 0x1.71547652b82fep+0;      // 1/ln 2 rounded
constexpr double kInvLn2Lo = 0x1.777d0ffda0d24p-56;   // 1/ln 2 - kInvLn2
constexpr double kInvLn10 = 0x1.bcb7b1526e50ep-2;     // 1/ln 10 rounded
constexpr double kInvLn10Lo = 0x1.95355baaafad3p-57;  // 1/ln 10 - kInvLn10
constexpr double kTwoThirds = 0x1.5555555555555p-1;   // 2/3 rounded
constexpr double kTwoThirdsLo = 0x1.5555555555555p-55;
constexpr double kSqrt2 = 0x1.6a09e667f3bcdp+0;
constexpr double kPi = 0x1.921fb54442d18p+1;
constexpr double kPiOver2 = 0x1.921fb54442d18p+0;  // exactly kPi / 2
constexpr double kTwoOverPi = 0x1.45f306dc9c883p-1;
// pi/2 in three parts (fdlibm pio2_1, pio2_2, pio2_2t): the first two have 33 significant bits,
// so k * part is exact for |k| < 2^20; the sum equals pi/2 to 1e-37.
constexpr double kPio2Part1 = 0x1.921fb54400000p+0;
constexpr double kPio2Part2 = 0x1.0b4611a600000p-34;
constexpr double kPio2Part3 = 0x1.3198a2e037073p-69;

// ---- Bits -----------------------------------------------------------------------------------
inline u64 bits_of(double x) { return std::bit_cast<u64>(x); }
inline double double_of(u64 b) { return std::bit_cast<double>(b); }
inline u32 bits_of(float x) { return std::bit_cast<u32>(x); }
inline float float_of(u32 b) { return std::bit_cast<float>(b); }

inline bool is_nan(double x) {
    return (bits_of(x) & 0x7fffffffffffffffull) > 0x7ff0000000000000ull;
}
inline bool sign_bit(double x) { return (bits_of(x) >> 63) != 0; }
inline double abs_of(double x) { return double_of(bits_of(x) & 0x7fffffffffffffffull); }
/// |magnitude| with the sign of `sign`.
inline double with_sign(double magnitude, bool negative) {
    return double_of((bits_of(magnitude) & 0x7fffffffffffffffull) | (negative ? 1ull << 63 : 0));
}

/// 2^k as a double, for -1022 <= k <= 1023 (built from the exponent bits).
inline double pow2i(int k) { return double_of(static_cast<u64>(k + 1023) << 52); }

/// v * 2^k with a single rounding, for v in [0.5, 2] and -1122 <= k <= 2046. Results below the
/// normal range are scaled in two steps whose first is exact, so a subnormal is rounded once.
inline double scale_pow2(double v, int k) {
    if (k > 1023) return v * pow2i(1023) * pow2i(k - 1023);
    if (k < -1022) return v * pow2i(k + 100) * pow2i(-100);
    return v * pow2i(k);
}

/// Nearest integer (ties to even) for |t| < 2^51.
inline double nearest_int(double t) {
    constexpr double shifter = 0x1.8p52;
    return (t + shifter) - shifter;
}

// ---- Double-double helpers (Dekker 1971, Knuth TAOCP 4.2.2); exact without FMA ---------------
struct DD {
    double hi;
    double lo;
};

/// a + b = s + e exactly, any order of magnitude.
inline DD two_sum(double a, double b) {
    double s = a + b;
    double bb = s - a;
    double e = (a - (s - bb)) + (b - bb);
    return {s, e};
}

/// a + b = s + e exactly, requires |a| >= |b| (or a == 0).
inline DD fast_two_sum(double a, double b) {
    double s = a + b;
    return {s, b - (s - a)};
}

/// Veltkamp split: a = hi + lo with hi, lo on 26 bits each.
inline DD split(double a) {
    double t = 134217729.0 * a;  // 2^27 + 1
    double hi = t - (t - a);
    return {hi, a - hi};
}

/// a * b = p + e exactly (Dekker), barring overflow and underflow.
inline DD two_prod(double a, double b) {
    double p = a * b;
    DD as = split(a);
    DD bs = split(b);
    double e = ((as.hi * bs.hi - p) + as.hi * bs.lo + as.lo * bs.hi) + as.lo * bs.lo;
    return {p, e};
}

/// (a.hi + a.lo) * (c_hi + c_lo) to about 2^-100 relative, as a double-double.
inline DD mul_dd(DD a, double c_hi, double c_lo) {
    DD p = two_prod(a.hi, c_hi);
    double lo = p.lo + (a.hi * c_lo + a.lo * c_hi);
    return fast_two_sum(p.hi, lo);
}

// ---- exp ------------------------------------------------------------------------------------
// exp(hi + lo) for -746 <= hi <= 710 and |lo| <= 2^-40 |hi|:
//   k = nearest(hi / ln2), r = (hi - k*ln2_hi) - (k*ln2_lo - lo), |r| <= ln2/2 + tiny,
//   exp(r) = 1 + r + r^2 (1/2! + r/3! + ... + r^11/13!)   (Taylor; the r^14 term is < 2^-57)
//   exp(hi + lo) = exp(r) * 2^k.
// hi - k*ln2_hi is exact (the product is exact and the difference is a Sterbenz subtraction);
// r_hi is kept apart from the small terms so that 1 + (r_hi + (p - r_lo)) rounds only twice.
double exp_core(double hi, double lo) {
    double kd = nearest_int(hi * kInvLn2);
    int k = static_cast<int>(kd);
    double r_hi = hi - kd * kLn2Hi;
    double r_lo = kd * kLn2Lo - lo;
    double r = r_hi - r_lo;
    // Taylor coefficients 1/n! for n = 2..13, Horner from the highest degree.
    double q = 1.0 / 6227020800.0;
    q = 1.0 / 479001600.0 + r * q;
    q = 1.0 / 39916800.0 + r * q;
    q = 1.0 / 3628800.0 + r * q;
    q = 1.0 / 362880.0 + r * q;
    q = 1.0 / 40320.0 + r * q;
    q = 1.0 / 5040.0 + r * q;
    q = 1.0 / 720.0 + r * q;
    q = 1.0 / 120.0 + r * q;
    q = 1.0 / 24.0 + r * q;
    q = 1.0 / 6.0 + r * q;
    q = 0.5 + r * q;
    double p = (r * r) * q;
    double v = 1.0 + (r_hi + (p - r_lo));
    return scale_pow2(v, k);
}

// ---- log ------------------------------------------------------------------------------------
// log(x) for finite x > 0 as a double-double, to about 2^-64 relative:
//   x = m * 2^e with m in [sqrt(1/2), sqrt(2)) (exponent and mantissa taken from the bits,
//   subnormals first scaled by 2^54), f = m - 1 (exact, Sterbenz), s = f / (m + 1) = f / (2 + f),
//   log(m) = 2 atanh(s) = 2s + (2/3) s^3 + sum_{j>=2} 2/(2j+1) s^(2j+1),   |s| <= 0.1716.
// 2s and (2/3)s^3 are carried in double-double (s = s_hi + s_lo from the exact division
// remainder); the rest is below 2^-12.5 |log m| and is summed in double up to s^25 (the first
// omitted term is below 2^-70 |log m|). log(x) = e*ln2_hi (exact) + e*ln2_lo + log(m).
DD log_dd(double x) {
    int e = 0;
    u64 b = bits_of(x);
    if ((b >> 52) == 0) {  // subnormal
        x = x * 0x1p54;
        b = bits_of(x);
        e = -54;
    }
    e += static_cast<int>(b >> 52) - 1023;
    double m = double_of((b & 0x000fffffffffffffull) | 0x3ff0000000000000ull);  // [1, 2)
    if (m >= kSqrt2) {
        m = m * 0.5;  // exact
        e += 1;
    }
    double ed = static_cast<double>(e);
    double f = m - 1.0;

    // s = f / (m + 1) in double-double.
    DD u = two_sum(m, 1.0);
    double s_hi = f / u.hi;
    DD su = two_prod(s_hi, u.hi);
    double s_lo = (((f - su.hi) - su.lo) - s_hi * u.lo) / u.hi;

    // (2/3) s^3 in double-double.
    DD s2 = two_prod(s_hi, s_hi);
    DD s3 = two_prod(s_hi, s2.hi);
    double s3_lo = s3.lo + (s_hi * s2.lo + 3.0 * s2.hi * s_lo);
    DD t1 = two_prod(s3.hi, kTwoThirds);
    double t1_lo = t1.lo + (s3.hi * kTwoThirdsLo + s3_lo * kTwoThirds);

    // sum_{j=2..12} 2/(2j+1) s^(2j+1) in double.
    double z = s2.hi;
    double q = 2.0 / 25.0;
    q = 2.0 / 23.0 + z * q;
    q = 2.0 / 21.0 + z * q;
    q = 2.0 / 19.0 + z * q;
    q = 2.0 / 17.0 + z * q;
    q = 2.0 / 15.0 + z * q;
    q = 2.0 / 13.0 + z * q;
    q = 2.0 / 11.0 + z * q;
    q = 2.0 / 9.0 + z * q;
    q = 2.0 / 7.0 + z * q;
    q = 2.0 / 5.0 + z * q;
    double rest = (s_hi * (z * z)) * q;

    // Assemble e*ln2 + 2s + (2/3)s^3 + rest, large parts exactly, small parts in order.
    DD a = two_sum(2.0 * s_hi, t1.hi);
    DD h = two_sum(ed * kLn2Hi, a.hi);
    double lo = h.lo + (a.lo + (2.0 * s_lo + (t1_lo + (rest + ed * kLn2Lo))));
    return fast_two_sum(h.hi, lo);
}

// ---- pow ------------------------------------------------------------------------------------
/// 0: y is not an integer, 1: odd integer, 2: even integer (y finite).
int integer_kind(double y) {
    u64 b = bits_of(y) & 0x7fffffffffffffffull;
    int exponent = static_cast<int>(b >> 52) - 1023;
    if (b == 0) return 2;
    if (exponent < 0) return 0;
    if (exponent >= 53) return 2;  // every double >= 2^53 is even
    u64 significand = (b & 0x000fffffffffffffull) | (1ull << 52);
    int frac_bits = 52 - exponent;
    if (frac_bits > 0 && (significand & ((1ull << frac_bits) - 1)) != 0) return 0;
    return ((significand >> frac_bits) & 1) ? 1 : 2;
}

// ---- atan -----------------------------------------------------------------------------------
// atan(t) for 0 <= t <= 1: two argument halvings atan(t) = 2 atan(t / (1 + sqrt(1 + t^2)))
// bring t below tan(pi/16) = 0.199, then the Taylor series to t^23 (first omitted term below
// 2^-55 relative), times 4.
double atan_core(double t) {
    t = t / (1.0 + std::sqrt(1.0 + t * t));
    t = t / (1.0 + std::sqrt(1.0 + t * t));
    double z = t * t;
    double q = -1.0 / 23.0;
    q = 1.0 / 21.0 + z * q;
    q = -1.0 / 19.0 + z * q;
    q = 1.0 / 17.0 + z * q;
    q = -1.0 / 15.0 + z * q;
    q = 1.0 / 13.0 + z * q;
    q = -1.0 / 11.0 + z * q;
    q = 1.0 / 9.0 + z * q;
    q = -1.0 / 7.0 + z * q;
    q = 1.0 / 5.0 + z * q;
    q = -1.0 / 3.0 + z * q;
    return 4.0 * (t + t * (z * q));
}

/// atan2 for ay, ax >= 0, finite, not both zero: angle in [0, pi/2].
double atan2_first_quadrant(double ay, double ax) {
    if (ay <= ax) return atan_core(ay / ax);
    return kPiOver2 - atan_core(ax / ay);
}

/// Full atan2 on doubles holding float values (finite or infinite, no NaN), C99 Annex F rules.
double atan2_core(double y, double x) {
    bool y_neg = sign_bit(y);
    bool x_neg = sign_bit(x);
    double ay = abs_of(y);
    double ax = abs_of(x);
    double a;
    if (ay == 0.0) {
        a = x_neg ? kPi : 0.0;  // atan2(±0, -0 or x<0) = ±pi, atan2(±0, +0 or x>0) = ±0
    } else if (ax == kInf) {
        if (ay == kInf)
            a = x_neg ? 3.0 * (kPi / 4.0) : kPi / 4.0;
        else
            a = x_neg ? kPi : 0.0;
    } else if (ay == kInf) {
        a = kPiOver2;
    } else {
        a = atan2_first_quadrant(ay, ax);  // also covers x = ±0: ratio 0 -> pi/2
        if (x_neg) a = kPi - a;
    }
    return with_sign(a, y_neg);
}

// ---- sin, cos, tan --------------------------------------------------------------------------
// sin(r), cos(r) for |r| <= pi/4 (+ tiny): Taylor to r^15 and r^16 (first omitted terms below
// 2^-54 relative).
double sin_poly(double r) {
    double z = r * r;
    double q = -1.0 / 1307674368000.0;
    q = 1.0 / 6227020800.0 + z * q;
    q = -1.0 / 39916800.0 + z * q;
    q = 1.0 / 362880.0 + z * q;
    q = -1.0 / 5040.0 + z * q;
    q = 1.0 / 120.0 + z * q;
    q = -1.0 / 6.0 + z * q;
    return r + r * (z * q);
}

double cos_poly(double r) {
    double z = r * r;
    double q = 1.0 / 20922789888000.0;
    q = -1.0 / 87178291200.0 + z * q;
    q = 1.0 / 479001600.0 + z * q;
    q = -1.0 / 3628800.0 + z * q;
    q = 1.0 / 40320.0 + z * q;
    q = -1.0 / 720.0 + z * q;
    q = 1.0 / 24.0 + z * q;
    q = -0.5 + z * q;
    return 1.0 + z * q;
}

struct Reduced {
    double r;    ///< x - q*pi/2, |r| <= pi/4 (+ tiny)
    unsigned q;  ///< quadrant, q mod 4
};

// 2/pi in binary, 32 bits per word, most significant first (bits 1..256 after the point), with
// one leading zero word for the bits at and before the point. Checked against mpmath.
constexpr u32 kTwoOverPiBits[9] = {0x00000000, 0xa2f9836e, 0x4e441529, 0xfc2757d1, 0xf534ddc0,
                                   0xdb629599, 0x3c439041, 0xfe5163ab, 0xdebbc561};

// Payne-Hanek reduction of a finite float |x| >= 2^19 (Payne & Hanek 1983). With x = m * 2^E
// (m the 24-bit integer significand) and 2/pi = sum_i b_i 2^-i, the bits b_i with i <= E - 2
// give multiples of 4 quarter turns and are dropped; the 96 bits b_{E-1} .. b_{E+94} form the
// integer W, and x * 2/pi mod 4 = m * W / 2^94 (an exact 120-bit product) up to the omitted
// bits, less than 2^-70. The top two bits of the product are the quadrant, the next 94 the
// fraction, which is rounded to the nearest quarter turn and converted to double exactly in two
// pieces before one multiplication by pi/2.
__extension__ typedef unsigned __int128 u128;

Reduced reduce_payne_hanek(float ax) {
    u32 b = bits_of(ax);
    int exponent = static_cast<int>((b >> 23) & 0xff) - 150;  // ax = m * 2^exponent
    u64 m = (b & 0x7fffff) | 0x800000;
    // Bit b_i sits at 0-based position i + 31 of kTwoOverPiBits; the window starts at i = E - 1.
    int start = exponent + 30;
    int word = start / 32;
    int shift = start % 32;
    u128 v = (static_cast<u128>(kTwoOverPiBits[word]) << 96) |
             (static_cast<u128>(kTwoOverPiBits[word + 1]) << 64) |
             (static_cast<u128>(kTwoOverPiBits[word + 2]) << 32) |
             static_cast<u128>(kTwoOverPiBits[word + 3]);
    u128 window = (v << shift) >> 32;  // 96 bits
    u128 product = static_cast<u128>(m) * window;
    unsigned q = static_cast<unsigned>(product >> 94) & 3u;
    u128 frac = product & ((static_cast<u128>(1) << 94) - 1);
    bool negative = false;
    if (frac >= (static_cast<u128>(1) << 93)) {  // fraction >= 1/2: round up the quadrant
        frac = (static_cast<u128>(1) << 94) - frac;
        q = (q + 1) & 3u;
        negative = true;
    }
    double f_hi = static_cast<double>(static_cast<std::int64_t>(frac >> 41));  // < 2^53: exact
    double f_lo = static_cast<double>(static_cast<std::int64_t>(frac & ((u128{1} << 41) - 1)));
    double f = f_hi * 0x1p-53 + f_lo * 0x1p-94;
    double r = f * kPiOver2;
    return {negative ? -r : r, q};
}

/// x = q*pi/2 + r for finite float x.
Reduced reduce_pio2(float x) {
    float ax = float_of(bits_of(x) & 0x7fffffffu);
    if (ax < 0x1p19f) {
        // Cody-Waite: k < 2^19, so k * part1 and k * part2 are exact; x - k*part1 is exact
        // (Sterbenz) and the remainder keeps about 119 bits of pi/2.
        double xd = x;
        double kd = nearest_int(xd * kTwoOverPi);
        double r = ((xd - kd * kPio2Part1) - kd * kPio2Part2) - kd * kPio2Part3;
        unsigned q = static_cast<unsigned>(static_cast<std::int64_t>(kd)) & 3u;
        return {r, q};
    }
    Reduced red = reduce_payne_hanek(ax);
    if (x < 0.0f) {  // -x = (-q) pi/2 + (-r)
        red.r = -red.r;
        red.q = (4u - red.q) & 3u;
    }
    return red;
}

inline bool float_not_finite(float x) { return (bits_of(x) & 0x7f800000u) == 0x7f800000u; }
inline float float_abs(float x) { return float_of(bits_of(x) & 0x7fffffffu); }

// Below 2^-12 the correctly rounded sin, tan, atan and asin of a float x is x itself (the
// relative correction x^2/3 is below 2^-25.5, less than half the float spacing); returning x
// also keeps the sign of zero.
constexpr float kTinyArg = 0x1p-12f;

}  // namespace

// ---- Public binary64 functions ----------------------------------------------------------------

double exp_d(double x) {
    if (is_nan(x)) return x + x;
    if (x > 710.0) return kInf;  // exp(709.79) already overflows; below 710 scale_pow2 does it
    if (x < -746.0) return 0.0;  // exp(-745.14) already rounds to 0
    return exp_core(x, 0.0);
}

double log_d(double x) {
    if (is_nan(x)) return x + x;
    if (x < 0.0) return kNaN;
    if (x == 0.0) return -kInf;
    if (x == kInf) return kInf;
    return log_dd(x).hi;
}

double log10_d(double x) {
    if (is_nan(x)) return x + x;
    if (x < 0.0) return kNaN;
    if (x == 0.0) return -kInf;
    if (x == kInf) return kInf;
    DD l = mul_dd(log_dd(x), kInvLn10, kInvLn10Lo);
    return l.hi;
}

// pow(x, y) = exp(y * log|x|) with log in double-double and the product y * log|x| formed
// exactly (two_prod), so that the argument of exp is good to about 2^-63 relative even near
// the overflow threshold; the sign comes from the parity of y. Special cases: C99 F.9.4.4.
double pow_d(double x, double y) {
    // Special cases that hold even for NaN.
    if (y == 0.0) return 1.0;
    if (x == 1.0) return 1.0;
    if (is_nan(x) || is_nan(y)) return x + y;

    int kind = (abs_of(y) == kInf) ? 2 : integer_kind(y);
    bool x_neg = sign_bit(x);
    double ax = abs_of(x);

    if (abs_of(y) == kInf) {
        if (ax == 1.0) return 1.0;  // pow(-1, ±inf) = 1
        bool big = (ax > 1.0) == (y > 0.0);
        return big ? kInf : 0.0;
    }
    if (ax == 0.0) {  // pow(±0, y): sign kept only for odd integer y
        bool neg = x_neg && kind == 1;
        return with_sign(y < 0.0 ? kInf : 0.0, neg);
    }
    if (ax == kInf) {
        bool neg = x_neg && kind == 1;
        return with_sign(y < 0.0 ? 0.0 : kInf, neg);
    }
    if (x_neg && kind == 0) return kNaN;  // negative base, non-integer exponent
    bool negate = x_neg && kind == 1;

    // |y| >= 2^64 with |x| != 1 always overflows or underflows: |log|x|| >= 2^-53.
    if (abs_of(y) >= 0x1p64 && ax != 1.0) {
        bool big = (ax > 1.0) == (y > 0.0);
        return with_sign(big ? kInf : 0.0, negate);
    }
    DD l = log_dd(ax);
    DD p = two_prod(y, l.hi);
    double p_lo = p.lo + y * l.lo;
    double r;
    if (p.hi > 710.0)
        r = kInf;
    else if (p.hi < -746.0)
        r = 0.0;
    else
        r = exp_core(p.hi, p_lo);
    return with_sign(r, negate);
}

// ---- Public binary32 functions ----------------------------------------------------------------

float exp(float x) { return static_cast<float>(exp_d(x)); }

// 2^x = 2^k * e^(r ln 2) with k = nearest(x) and r = x - k exact, so integer x gives exactly 2^k.
float exp2(float x) {
    double xd = x;
    if (is_nan(xd)) return x + x;
    if (xd > 200.0) return std::numeric_limits<float>::infinity();
    if (xd < -200.0) return 0.0f;
    double kd = nearest_int(xd);
    double r = xd - kd;
    double v = exp_core(r * kLn2Hi + r * kLn2Lo, 0.0);  // |r ln2| <= 0.35: k = 0 inside
    return static_cast<float>(scale_pow2(v, static_cast<int>(kd)));
}

namespace {
bool ln_series(float xf, double& ln_x);  // below, beside pow_series
}  // namespace

// log and log2 of a float: ln_series's binary64 value where it lies more than 2^-38 (relative)
// from every float rounding boundary, which its error (below 2^-46) cannot cross, so it rounds
// to the same float as the double-double below; the rest (about 1 input in 8192, x = 1, the
// subnormals and the special values) takes the double-double.
float log(float x) {
    double ln_x = 0.0;
    if (ln_series(x, ln_x) && detail::rounds_like_truth(std::fabs(ln_x)))
        return static_cast<float>(ln_x);
    return static_cast<float>(log_d(x));
}

float log10(float x) { return static_cast<float>(log10_d(x)); }

// log2 = log * (1/ln2) in double-double; for x = 2^k the product is k(1 + O(2^-84)), which
// rounds to exactly k.
double log2_d(double x) {
    if (is_nan(x)) return x + x;
    if (x < 0.0) return kNaN;
    if (x == 0.0) return -kInf;
    if (x == kInf) return kInf;
    return mul_dd(log_dd(x), kInvLn2, kInvLn2Lo).hi;
}

float log2(float x) {
    double ln_x = 0.0;
    if (ln_series(x, ln_x)) {  // the fast path of log (above)
        const double p = ln_x * kInvLn2;
        if (detail::rounds_like_truth(std::fabs(p))) return static_cast<float>(p);
    }
    return static_cast<float>(log2_d(x));
}

namespace {

/// x^y in plain binary64 with short series, for finite normal x > 0 (x != 1) and finite y with
/// y ln x in [t_min, t_max]. False for other inputs.
/// Relative error below 2^-41 (docs/determinism.md): ln of the mantissa by the atanh series to
/// s^17 (first omitted term below 2^-51 absolute), t = y ln x to about |t| 2^-50 absolute,
/// e^r by Taylor to r^10 (r^11/11! < 2^-42 relative for |r| <= ln2/2), Horner roundings 2^-52.
/// ln x in plain binary64 for a finite normal float x > 0 other than 1; false for other x.
/// Relative error below 2^-46: ln of the mantissa by the atanh series to s^17 (first omitted term
/// below 2^-51 absolute, |ln m| >= |s|), then e ln 2 + ln m (cancellation at most a factor 2).
bool ln_series(float xf, double& ln_x) {
    const u32 xb = bits_of(xf);
    if (xb - 0x00800000u >= 0x7f000000u || xf == 1.0f) return false;
    // x = m 2^e, m in [sqrt(1/2), sqrt(2))
    int e = static_cast<int>(xb >> 23) - 127;
    double m = static_cast<double>(float_of((xb & 0x007fffffu) | 0x3f800000u));  // [1, 2)
    if (m >= kSqrt2) {
        m = m * 0.5;
        e += 1;
    }
    // ln m = 2 atanh(s), s = (m - 1) / (m + 1), |s| <= 0.1716
    const double s = (m - 1.0) / (m + 1.0);
    const double z = s * s;
    double q = 2.0 / 17.0;
    q = 2.0 / 15.0 + z * q;
    q = 2.0 / 13.0 + z * q;
    q = 2.0 / 11.0 + z * q;
    q = 2.0 / 9.0 + z * q;
    q = 2.0 / 7.0 + z * q;
    q = 2.0 / 5.0 + z * q;
    q = 2.0 / 3.0 + z * q;
    const double ln_m = 2.0 * s + s * (z * q);
    // ln x = e ln 2 + ln m
    ln_x = static_cast<double>(e) * (kLn2Hi + kLn2Lo) + ln_m;
    return true;
}

bool pow_series(float xf, float yf, double t_min, double t_max, double& out) {
    double ln_x = 0.0;
    if (float_not_finite(yf) || !ln_series(xf, ln_x)) return false;
    // t = y ln x = y (e ln 2 + ln m)
    const double t = static_cast<double>(yf) * ln_x;
    if (!(t >= t_min && t <= t_max)) return false;
    // e^t = 2^k e^r, r = t - k ln 2 in [-ln2/2, ln2/2]
    const double kd = nearest_int(t * kInvLn2);
    const double r = (t - kd * kLn2Hi) - kd * kLn2Lo;
    double p = 1.0 / 3628800.0;
    p = 1.0 / 362880.0 + r * p;
    p = 1.0 / 40320.0 + r * p;
    p = 1.0 / 5040.0 + r * p;
    p = 1.0 / 720.0 + r * p;
    p = 1.0 / 120.0 + r * p;
    p = 1.0 / 24.0 + r * p;
    p = 1.0 / 6.0 + r * p;
    p = 0.5 + r * p;
    p = 1.0 + r * p;
    p = 1.0 + r * p;
    out = scale_pow2(p, static_cast<int>(kd));
    return true;
}

}  // namespace

// The series value is within 2^-41 of x^y and pow_d within 2^-50; when the series value lies
// more than 2^-38 from every rounding boundary both round to the same float, so the fast path
// returns exactly what static_cast<float>(pow_d(x, y)) would. The rest (about 1 input in 8192,
// and the special and out-of-range cases) takes pow_d.
float pow(float x, float y) {
    double p;
    // t in [-87, 88]: the result is a normal float's magnitude
    if (pow_series(x, y, -87.0, 88.0, p) && detail::rounds_like_truth(p))
        return static_cast<float>(p);
    return static_cast<float>(pow_d(x, y));
}

float pow_fast(float xf, float yf) {
    double p;
    // beyond t = 88.8 (overflow) or below -103.5 (deep subnormal) pow_d decides
    if (pow_series(xf, yf, -103.5, 88.8, p)) return static_cast<float>(p);
    return static_cast<float>(pow_d(xf, yf));
}

namespace {

// pow_fast_array's AVX2 kernel: pow_series for four lanes (the same operations in the same
// order), t in [-103.5, 88.8] as pow_fast's; lanes pow_series declines are redone by pow_fast.
// Four groups of four run side by side (pow_groups<4>: their Horner chains interleaved, each
// latency-bound), then single groups. pow_fast_avx2 returns the number of elements done; y is
// finite.
struct PowLanes {
    __m256d yd, one, two, half, sqrt2, ln2, ln2_hi, ln2_lo, inv_ln2, shifter, t_min, t_max;
    __m128i low, sign, range, mantissa, one_bits;
};

// The steps of pow_series for four lanes, in its order: set-up to ln x, then e^t from t.
struct PowGroup {
    __m128 xf;
    int good;
    __m256d ed, s, z;
};

__attribute__((target("avx2"), always_inline)) inline PowGroup pow_start(const PowLanes& c,
                                                                         const float* x) {
    PowGroup g;
    g.xf = _mm_loadu_ps(x);
    const __m128i xb = _mm_castps_si128(g.xf);
    // a finite normal x > 0 (xb - 0x00800000 < 0x7f000000 unsigned) other than 1
    const __m128i in_range =
        _mm_cmplt_epi32(_mm_xor_si128(_mm_sub_epi32(xb, c.low), c.sign), c.range);
    g.good = _mm_movemask_ps(
        _mm_and_ps(_mm_castsi128_ps(in_range), _mm_cmpneq_ps(g.xf, _mm_set1_ps(1.0f))));
    // x = m 2^e, m in [sqrt(1/2), sqrt(2))
    __m256d ed = _mm256_cvtepi32_pd(_mm_sub_epi32(_mm_srli_epi32(xb, 23), _mm_set1_epi32(127)));
    __m256d m =
        _mm256_cvtps_pd(_mm_castsi128_ps(_mm_or_si128(_mm_and_si128(xb, c.mantissa), c.one_bits)));
    const __m256d big = _mm256_cmp_pd(m, c.sqrt2, _CMP_GE_OQ);
    m = _mm256_blendv_pd(m, _mm256_mul_pd(m, c.half), big);
    g.ed = _mm256_blendv_pd(ed, _mm256_add_pd(ed, c.one), big);
    // ln m = 2 atanh(s)
    g.s = _mm256_div_pd(_mm256_sub_pd(m, c.one), _mm256_add_pd(m, c.one));
    g.z = _mm256_mul_pd(g.s, g.s);
    return g;
}

__attribute__((target("avx2"), always_inline)) inline __m256d pow_t(const PowLanes& c, PowGroup& g,
                                                                    __m256d q) {
    const __m256d ln_m =
        _mm256_add_pd(_mm256_mul_pd(c.two, g.s), _mm256_mul_pd(g.s, _mm256_mul_pd(g.z, q)));
    const __m256d ln_x = _mm256_add_pd(_mm256_mul_pd(g.ed, c.ln2), ln_m);
    const __m256d t = _mm256_mul_pd(c.yd, ln_x);
    g.good &= _mm256_movemask_pd(_mm256_and_pd(_mm256_cmp_pd(t, c.t_min, _CMP_GE_OQ),
                                               _mm256_cmp_pd(t, c.t_max, _CMP_LE_OQ)));
    return t;
}

// e^t = 2^k e^r: k and r
__attribute__((target("avx2"), always_inline)) inline __m256d pow_k(const PowLanes& c, __m256d t) {
    return _mm256_sub_pd(_mm256_add_pd(_mm256_mul_pd(t, c.inv_ln2), c.shifter), c.shifter);
}
__attribute__((target("avx2"), always_inline)) inline __m256d pow_r(const PowLanes& c, __m256d t,
                                                                    __m256d kd) {
    return _mm256_sub_pd(_mm256_sub_pd(t, _mm256_mul_pd(kd, c.ln2_hi)),
                         _mm256_mul_pd(kd, c.ln2_lo));
}

// p 2^k to out (a lane out of range gets any bits here: the caller redoes it)
__attribute__((target("avx2"), always_inline)) inline void pow_finish(__m256d p, __m256d kd,
                                                                      float* out) {
    // 2^k from its exponent bits (k in [-150, 128] for t in range: -1022 <= k <= 1023)
    const __m128i k = _mm256_cvtpd_epi32(kd);
    const __m256d scale = _mm256_castsi256_pd(
        _mm256_slli_epi64(_mm256_cvtepi32_epi64(_mm_add_epi32(k, _mm_set1_epi32(1023))), 52));
    _mm_storeu_ps(out, _mm256_cvtpd_ps(_mm256_mul_pd(p, scale)));
}

// G groups of four lanes side by side: pow_series in each lane, the Horner chains of the groups
// interleaved; the lanes pow_series declines redone by pow_fast. `out` may be `x`.
template <int G>
__attribute__((target("avx2"), always_inline)) inline void pow_groups(
    const PowLanes& c, const double* qc, const double* pc, const float* x, float y, float* out) {
    PowGroup g[G];
    __m256d q[G], t[G], kd[G], r[G], p[G];
#pragma GCC unroll 4
    for (int h = 0; h < G; ++h) {
        g[h] = pow_start(c, x + 4 * h);
        q[h] = _mm256_set1_pd(qc[0]);
    }
    for (int k = 1; k < 8; ++k)
#pragma GCC unroll 4
        for (int h = 0; h < G; ++h)
            q[h] = _mm256_add_pd(_mm256_set1_pd(qc[k]), _mm256_mul_pd(g[h].z, q[h]));
#pragma GCC unroll 4
    for (int h = 0; h < G; ++h) {
        t[h] = pow_t(c, g[h], q[h]);
        kd[h] = pow_k(c, t[h]);
        r[h] = pow_r(c, t[h], kd[h]);
        p[h] = _mm256_set1_pd(pc[0]);
    }
    for (int k = 1; k < 11; ++k)
#pragma GCC unroll 4
        for (int h = 0; h < G; ++h)
            p[h] = _mm256_add_pd(_mm256_set1_pd(pc[k]), _mm256_mul_pd(r[h], p[h]));
    float xs[4 * G];  // the inputs, kept: `out` may be `x`
    int good = 0;
#pragma GCC unroll 4
    for (int h = 0; h < G; ++h) {
        _mm_storeu_ps(xs + 4 * h, g[h].xf);
        good |= g[h].good << (4 * h);
    }
#pragma GCC unroll 4
    for (int h = 0; h < G; ++h) pow_finish(p[h], kd[h], out + 4 * h);
    avx::redo_lanes(good, 4 * G, xs, out, [y](float v) { return pow_fast(v, y); });
}

__attribute__((target("avx2"))) std::size_t pow_fast_avx2(const float* x, float y, float* out,
                                                          std::size_t n) {
    PowLanes c;
    c.yd = _mm256_set1_pd(static_cast<double>(y));
    c.one = _mm256_set1_pd(1.0), c.two = _mm256_set1_pd(2.0), c.half = _mm256_set1_pd(0.5);
    c.sqrt2 = _mm256_set1_pd(kSqrt2);
    c.ln2 = _mm256_set1_pd(kLn2Hi + kLn2Lo), c.ln2_hi = _mm256_set1_pd(kLn2Hi);
    c.ln2_lo = _mm256_set1_pd(kLn2Lo), c.inv_ln2 = _mm256_set1_pd(kInvLn2);
    c.shifter = _mm256_set1_pd(0x1.8p52);
    c.t_min = _mm256_set1_pd(-103.5), c.t_max = _mm256_set1_pd(88.8);
    c.low = _mm_set1_epi32(0x00800000), c.sign = _mm_set1_epi32(INT32_MIN);
    c.range = _mm_set1_epi32(static_cast<int>(0x7f000000u ^ 0x80000000u));
    c.mantissa = _mm_set1_epi32(0x007fffff), c.one_bits = _mm_set1_epi32(0x3f800000);
    const double qc[8] = {2.0 / 17.0, 2.0 / 15.0, 2.0 / 13.0, 2.0 / 11.0,
                          2.0 / 9.0,  2.0 / 7.0,  2.0 / 5.0,  2.0 / 3.0};
    const double pc[11] = {
        1.0 / 3628800.0, 1.0 / 362880.0, 1.0 / 40320.0, 1.0 / 5040.0, 1.0 / 720.0, 1.0 / 120.0,
        1.0 / 24.0,      1.0 / 6.0,      0.5,           1.0,          1.0};
    std::size_t i = 0;
    for (; i + 16 <= n; i += 16) pow_groups<4>(c, qc, pc, x + i, y, out + i);
    for (; i + 4 <= n; i += 4) pow_groups<1>(c, qc, pc, x + i, y, out + i);
    return i;
}

// log2_array's AVX2 kernel, four lanes at a time: pow_start's ln x (ln_series's operations),
// p = ln x / ln 2 as log2's fast path, kept where |p| rounds like the truth
// (detail::rounds_like_truth: a normal float's magnitude whose low 29 bits lie more than 2^15
// from halfway); the other lanes by log2. Returns the number of elements done.
__attribute__((target("avx2"))) std::size_t log2_avx2(const float* x, float* out, std::size_t n) {
    PowLanes c;
    c.one = _mm256_set1_pd(1.0), c.two = _mm256_set1_pd(2.0), c.half = _mm256_set1_pd(0.5);
    c.sqrt2 = _mm256_set1_pd(kSqrt2), c.ln2 = _mm256_set1_pd(kLn2Hi + kLn2Lo);
    c.low = _mm_set1_epi32(0x00800000), c.sign = _mm_set1_epi32(INT32_MIN);
    c.range = _mm_set1_epi32(static_cast<int>(0x7f000000u ^ 0x80000000u));
    c.mantissa = _mm_set1_epi32(0x007fffff), c.one_bits = _mm_set1_epi32(0x3f800000);
    const double qc[8] = {2.0 / 17.0, 2.0 / 15.0, 2.0 / 13.0, 2.0 / 11.0,
                          2.0 / 9.0,  2.0 / 7.0,  2.0 / 5.0,  2.0 / 3.0};
    const __m256d inv_ln2 = _mm256_set1_pd(kInvLn2), magnitude = _mm256_set1_pd(-0.0);
    const __m256i low_bits = _mm256_set1_epi64x((1ll << 29) - 1),
                  half = _mm256_set1_epi64x(1ll << 28);
    const __m256i far = _mm256_set1_epi64x(1ll << 15), near = _mm256_set1_epi64x(-(1ll << 15));
    std::size_t i = 0;
    for (; i + 4 <= n; i += 4) {
        PowGroup g = pow_start(c, x + i);
        __m256d q = _mm256_set1_pd(qc[0]);
        for (int k = 1; k < 8; ++k) q = _mm256_add_pd(_mm256_set1_pd(qc[k]), _mm256_mul_pd(g.z, q));
        const __m256d ln_m =
            _mm256_add_pd(_mm256_mul_pd(c.two, g.s), _mm256_mul_pd(g.s, _mm256_mul_pd(g.z, q)));
        const __m256d ln_x = _mm256_add_pd(_mm256_mul_pd(g.ed, c.ln2), ln_m);
        const __m256d p = _mm256_mul_pd(ln_x, inv_ln2);
        // rounds_like_truth(|p|)
        const __m256d a = _mm256_andnot_pd(magnitude, p);
        const __m256d normal = _mm256_and_pd(_mm256_cmp_pd(a, _mm256_set1_pd(0x1p-126), _CMP_GE_OQ),
                                             _mm256_cmp_pd(a, _mm256_set1_pd(0x1p128), _CMP_LT_OQ));
        const __m256i from_half =
            _mm256_sub_epi64(_mm256_and_si256(_mm256_castpd_si256(a), low_bits), half);
        const __m256i clear = _mm256_or_si256(_mm256_cmpgt_epi64(from_half, far),
                                              _mm256_cmpgt_epi64(near, from_half));
        const int good =
            g.good & _mm256_movemask_pd(_mm256_and_pd(normal, _mm256_castsi256_pd(clear)));
        float xs[4];  // the inputs, kept: `out` may be `x`
        _mm_storeu_ps(xs, g.xf);
        _mm_storeu_ps(out + i, _mm256_cvtpd_ps(p));
        avx::redo_lanes(good, 4, xs, out + i, [](float v) { return log2(v); });
    }
    return i;
}

// exp_array's AVX2 kernel, four lanes at a time: exp_core(x, 0) for x in [-700, 700] (k in
// [-1010, 1010]: scale_pow2 is one product by 2^k), its operations in its order; the other
// lanes (NaN, out of range) by exp. Returns the number of elements done.
__attribute__((target("avx2"))) std::size_t exp_avx2(const float* x, float* out, std::size_t n) {
    const double qc[12] = {1.0 / 6227020800.0, 1.0 / 479001600.0, 1.0 / 39916800.0, 1.0 / 3628800.0,
                           1.0 / 362880.0,     1.0 / 40320.0,     1.0 / 5040.0,     1.0 / 720.0,
                           1.0 / 120.0,        1.0 / 24.0,        1.0 / 6.0,        0.5};
    const __m256d shifter = _mm256_set1_pd(0x1.8p52), inv_ln2 = _mm256_set1_pd(kInvLn2);
    const __m256d ln2_hi = _mm256_set1_pd(kLn2Hi), ln2_lo = _mm256_set1_pd(kLn2Lo);
    const __m256d one = _mm256_set1_pd(1.0);
    std::size_t i = 0;
    for (; i + 4 <= n; i += 4) {
        const __m128 xf = _mm_loadu_ps(x + i);
        const __m256d hi = _mm256_cvtps_pd(xf);
        const int good =
            _mm256_movemask_pd(_mm256_and_pd(_mm256_cmp_pd(hi, _mm256_set1_pd(-700.0), _CMP_GE_OQ),
                                             _mm256_cmp_pd(hi, _mm256_set1_pd(700.0), _CMP_LE_OQ)));
        const __m256d kd =
            _mm256_sub_pd(_mm256_add_pd(_mm256_mul_pd(hi, inv_ln2), shifter), shifter);
        const __m256d r_hi = _mm256_sub_pd(hi, _mm256_mul_pd(kd, ln2_hi));
        const __m256d r_lo = _mm256_sub_pd(_mm256_mul_pd(kd, ln2_lo), _mm256_setzero_pd());
        const __m256d r = _mm256_sub_pd(r_hi, r_lo);
        __m256d q = _mm256_set1_pd(qc[0]);
        for (int k = 1; k < 12; ++k) q = _mm256_add_pd(_mm256_set1_pd(qc[k]), _mm256_mul_pd(r, q));
        const __m256d p = _mm256_mul_pd(_mm256_mul_pd(r, r), q);
        const __m256d v = _mm256_add_pd(one, _mm256_add_pd(r_hi, _mm256_sub_pd(p, r_lo)));
        // 2^k from its exponent bits (the other lanes' k may be anything: redone below)
        const __m128i k = _mm256_cvtpd_epi32(kd);
        const __m256d scale = _mm256_castsi256_pd(
            _mm256_slli_epi64(_mm256_cvtepi32_epi64(_mm_add_epi32(k, _mm_set1_epi32(1023))), 52));
        float xs[4];  // the inputs, kept: `out` may be `x`
        _mm_storeu_ps(xs, xf);
        _mm_storeu_ps(out + i, _mm256_cvtpd_ps(_mm256_mul_pd(v, scale)));
        avx::redo_lanes(good, 4, xs, out + i, [](float a) { return exp(a); });
    }
    return i;
}

}  // namespace

void exp_array(const float* x, float* out, std::size_t n) {
    const std::size_t done = simd_allowed() && cpu_has_avx2() ? exp_avx2(x, out, n) : 0;
    for (std::size_t i = done; i < n; ++i) out[i] = exp(x[i]);
}

void log2_array(const float* x, float* out, std::size_t n) {
    const std::size_t done = simd_allowed() && cpu_has_avx2() ? log2_avx2(x, out, n) : 0;
    for (std::size_t i = done; i < n; ++i) out[i] = log2(x[i]);
}

void pow_fast_array(const float* x, float y, float* out, std::size_t n) {
    const bool avx2 = simd_allowed() && cpu_has_avx2();
    const std::size_t done = avx2 && !float_not_finite(y) ? pow_fast_avx2(x, y, out, n) : 0;
    for (std::size_t i = done; i < n; ++i) out[i] = pow_fast(x[i], y);
}

PowFixed::PowFixed(float y) : y_(y), tabled_(y >= -4.0f && y <= 4.0f) {
    if (!tabled_) return;  // every call goes to pow
    const double yd = y;
    c1_ = yd;
    c2_ = c1_ * (yd - 1.0) / 2.0;
    c3_ = c2_ * (yd - 2.0) / 3.0;
    c4_ = c3_ * (yd - 3.0) / 4.0;
    for (int e = 0; e < 256; ++e) scale_[e] = pow_d(2.0, static_cast<double>(e - 127) * yd);
    for (int j = 0; j < 1024; ++j) {
        const double c = 1.0 + static_cast<double>(2 * j + 1) * 0x1p-11;
        base_[j] = pow_d(c, yd);
        inv_[j] = 1.0 / c;
    }
}

// PowFixed::apply's AVX2 kernel, four lanes at a time: each lane does the binary64 operations of
// operator() in the same order (no FMA), so it computes the same value p; a lane whose x is not a
// finite normal > 0 or whose p fails detail::rounds_like_truth is redone by operator() (which then
// takes pow). Returns the number of elements done.
__attribute__((target("avx2"))) std::size_t PowFixed::apply_avx2(const float* x, float* out,
                                                                 std::size_t n) const {
    const __m256d one = _mm256_set1_pd(1.0), step = _mm256_set1_pd(0x1p-11);
    const __m256d c1 = _mm256_set1_pd(c1_), c2 = _mm256_set1_pd(c2_), c3 = _mm256_set1_pd(c3_),
                  c4 = _mm256_set1_pd(c4_);
    const __m128i mantissa = _mm_set1_epi32(0x007fffff), one_bits = _mm_set1_epi32(0x3f800000);
    const __m128i ten_bits = _mm_set1_epi32(1023), eight_bits = _mm_set1_epi32(255);
    const __m128i unit = _mm_set1_epi32(1);
    const __m256d low_limit = _mm256_set1_pd(0x1p-126), high_limit = _mm256_set1_pd(0x1p128);
    const __m256i low_bits = _mm256_set1_epi64x((1ll << 29) - 1);
    const __m256i near_start = _mm256_set1_epi64x((1ll << 28) - (1ll << 15));
    const __m256i near_span = _mm256_set1_epi64x((1ll << 16) + 1), zero64 = _mm256_setzero_si256();
    const __m128i min_normal = _mm_set1_epi32(0x00800000), sign = _mm_set1_epi32(INT32_MIN);
    const __m128i normal_limit = _mm_set1_epi32(static_cast<int>(0x7f000000u ^ 0x80000000u));
    // masked gathers with a zero source (the plain one trips g++ 12's uninitialised warning)
    std::size_t i = 0;
    for (; i + 4 <= n; i += 4) {
        const __m128i xb = _mm_loadu_si128(reinterpret_cast<const __m128i*>(x + i));
        const __m128i j = _mm_and_si128(_mm_srli_epi32(xb, 13), ten_bits);
        const __m128i e = _mm_and_si128(_mm_srli_epi32(xb, 23), eight_bits);  // sign: see below
        const __m256d m =
            _mm256_cvtps_pd(_mm_castsi128_ps(_mm_or_si128(_mm_and_si128(xb, mantissa), one_bits)));
        const __m256d odd = _mm256_cvtepi32_pd(_mm_add_epi32(_mm_add_epi32(j, j), unit));
        const __m256d c = _mm256_add_pd(one, _mm256_mul_pd(odd, step));
        const int j0 = _mm_extract_epi32(j, 0), j1 = _mm_extract_epi32(j, 1),
                  j2 = _mm_extract_epi32(j, 2), j3 = _mm_extract_epi32(j, 3);
        const int e0 = _mm_extract_epi32(e, 0), e1 = _mm_extract_epi32(e, 1),
                  e2 = _mm_extract_epi32(e, 2), e3 = _mm_extract_epi32(e, 3);
        const __m256d d = _mm256_mul_pd(_mm256_sub_pd(m, c),
                                        _mm256_set_pd(inv_[j3], inv_[j2], inv_[j1], inv_[j0]));
        __m256d series = _mm256_add_pd(c3, _mm256_mul_pd(d, c4));
        series = _mm256_add_pd(c2, _mm256_mul_pd(d, series));
        series = _mm256_add_pd(c1, _mm256_mul_pd(d, series));
        series = _mm256_add_pd(one, _mm256_mul_pd(d, series));
        const __m256d p = _mm256_mul_pd(
            _mm256_mul_pd(_mm256_set_pd(scale_[e3], scale_[e2], scale_[e1], scale_[e0]),
                          _mm256_set_pd(base_[j3], base_[j2], base_[j1], base_[j0])),
            series);
        // detail::rounds_like_truth on four lanes: p in [2^-126, 2^128) and the low 29 bits
        // outside [2^28 - 2^15, 2^28 + 2^15]; and x a finite normal > 0 (unsigned compare by
        // flipping the sign bit).
        const __m256d in_range = _mm256_and_pd(_mm256_cmp_pd(p, low_limit, _CMP_GE_OQ),
                                               _mm256_cmp_pd(p, high_limit, _CMP_LT_OQ));
        const __m256i t =
            _mm256_sub_epi64(_mm256_and_si256(_mm256_castpd_si256(p), low_bits), near_start);
        const __m256i near =
            _mm256_andnot_si256(_mm256_cmpgt_epi64(zero64, t), _mm256_cmpgt_epi64(near_span, t));
        const __m128i normal =
            _mm_cmplt_epi32(_mm_xor_si128(_mm_sub_epi32(xb, min_normal), sign), normal_limit);
        const int good = _mm256_movemask_pd(_mm256_andnot_pd(_mm256_castsi256_pd(near), in_range)) &
                         _mm_movemask_ps(_mm_castsi128_ps(normal));
        _mm_storeu_ps(out + i, _mm256_cvtpd_ps(p));
        avx::redo_lanes(good, 4, x + i, out + i, [this](float v) { return (*this)(v); });
    }
    return i;
}

void PowFixed::apply(const float* x, float* out, std::size_t n) const {
    const bool avx2 = simd_allowed() && cpu_has_avx2();
    const std::size_t done = tabled_ && avx2 ? apply_avx2(x, out, n) : 0;
    for (std::size_t i = done; i < n; ++i) out[i] = (*this)(x[i]);
}

float sin(float x) {
    if (float_not_finite(x)) return x - x;  // NaN for NaN and ±inf
    if (float_abs(x) < kTinyArg) return x;
    Reduced red = reduce_pio2(x);
    double v;
    switch (red.q) {
        case 0: v = sin_poly(red.r); break;
        case 1: v = cos_poly(red.r); break;
        case 2: v = -sin_poly(red.r); break;
        default: v = -cos_poly(red.r); break;
    }
    return static_cast<float>(v);
}

float cos(float x) {
    if (float_not_finite(x)) return x - x;
    Reduced red = reduce_pio2(x);
    double v;
    switch (red.q) {
        case 0: v = cos_poly(red.r); break;
        case 1: v = -sin_poly(red.r); break;
        case 2: v = -cos_poly(red.r); break;
        default: v = sin_poly(red.r); break;
    }
    return static_cast<float>(v);
}

float tan(float x) {
    if (float_not_finite(x)) return x - x;
    if (float_abs(x) < kTinyArg) return x;
    Reduced red = reduce_pio2(x);
    double s = sin_poly(red.r);
    double c = cos_poly(red.r);
    double v = (red.q & 1u) ? -c / s : s / c;
    return static_cast<float>(v);
}

float atan(float x) {
    double xd = x;
    if (is_nan(xd)) return x + x;
    if (float_abs(x) < kTinyArg) return x;
    double t = abs_of(xd);
    double a = (t <= 1.0) ? atan_core(t) : kPiOver2 - atan_core(1.0 / t);
    return static_cast<float>(with_sign(a, sign_bit(xd)));
}

float atan2(float y, float x) {
    if (is_nan(static_cast<double>(x)) || is_nan(static_cast<double>(y))) return x + y;
    return static_cast<float>(atan2_core(y, x));
}

// asin x = atan2(x, sqrt((1 - x)(1 + x))): near |x| = 1 the factor 1 - |x| is exact (Sterbenz),
// so there is no cancellation; for small |x| the product is 1 - x^2 to 2^-52.
float asin(float x) {
    double xd = x;
    if (is_nan(xd)) return x + x;
    double ax = abs_of(xd);
    if (ax > 1.0) return std::numeric_limits<float>::quiet_NaN();
    if (ax < kTinyArg) return x;
    double c = std::sqrt((1.0 - ax) * (1.0 + ax));
    return static_cast<float>(with_sign(atan2_first_quadrant(ax, c), sign_bit(xd)));
}

// acos x = atan2(sqrt((1 - x)(1 + x)), x): acos(1) = +0, acos(-1) = pi rounded.
float acos(float x) {
    double xd = x;
    if (is_nan(xd)) return x + x;
    double ax = abs_of(xd);
    if (ax > 1.0) return std::numeric_limits<float>::quiet_NaN();
    double c = std::sqrt((1.0 - ax) * (1.0 + ax));
    double a = atan2_first_quadrant(c, ax);
    if (sign_bit(xd)) a = kPi - a;
    return static_cast<float>(a);
}

}  // namespace fovref::dm
