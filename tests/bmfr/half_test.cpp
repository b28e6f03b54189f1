// binary16 conversion (ref/bmfr/half.h): every half survives the round trip; rounding of floats
// between halves is to the nearest, ties to even, checked against a binary64 reference written
// here and (g++, which has _Float16 on x86-64) against the compiler's own conversion.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "ref/bmfr/bmfr.h"
#include "ref/bmfr/half.h"
#include "ref/core/rng.h"

using namespace fovref;

namespace {

float float_from_bits(std::uint32_t u) {
    float f;
    std::memcpy(&f, &u, sizeof f);
    return f;
}

// The nearest binary16 value of a finite float below 65520 in magnitude, ties to even, in binary64:
// the spacing of halves at |f| is 2^(max(e, -14) - 10) with e = floor(log2 |f|).
double nearest_half_reference(float f) {
    const double a = std::fabs(static_cast<double>(f));
    if (a == 0.0) return static_cast<double>(f);
    int e = 0;
    std::frexp(a, &e);  // a = m 2^e, m in [0.5, 1)
    const double spacing = std::ldexp(1.0, std::max(e - 1, -14) - 10);
    const double q = a / spacing;
    double r = std::floor(q);
    if (q - r > 0.5 || (q - r == 0.5 && std::fmod(r, 2.0) != 0.0)) r += 1.0;
    const double v = r * spacing;
    return f < 0 ? -v : v;
}

}  // namespace

TEST_CASE("every binary16 value survives float and back") {
    int checked = 0;
    for (std::uint32_t h = 0; h < 65536; ++h) {
        const auto half = static_cast<std::uint16_t>(h);
        const bool nan = (h & 0x7c00u) == 0x7c00u && (h & 0x3ffu) != 0;
        const float f = float_from_half(half);
        if (nan) {
            CHECK(std::isnan(f));
            continue;
        }
        REQUIRE(half_from_float(f) == half);
        ++checked;
    }
    CHECK(checked == 65536 - 2 * 1023);
    CHECK(float_from_half(0x3c00u) == 1.0f);
    CHECK(float_from_half(0x7bffu) == 65504.0f);
    CHECK(float_from_half(0x0001u) == std::ldexp(1.0f, -24));
    CHECK(float_from_half(0x0400u) == std::ldexp(1.0f, -14));
}

TEST_CASE("half_from_float rounds to nearest, ties to even (binary64 reference)") {
    // ties: halfway between consecutive halves in the normal and subnormal ranges
    CHECK(half_from_float(1.0f + std::ldexp(1.0f, -11)) == 0x3c00u);      // tie -> even 1.0
    CHECK(half_from_float(1.0f + 3 * std::ldexp(1.0f, -11)) == 0x3c02u);  // tie -> even up
    CHECK(half_from_float(std::ldexp(1.0f, -25)) == 0x0000u);             // tie with 0
    CHECK(half_from_float(3 * std::ldexp(1.0f, -25)) == 0x0002u);         // 1.5 units -> 2
    CHECK(half_from_float(65519.0f) == 0x7bffu);
    CHECK(half_from_float(65520.0f) == 0x7c00u);  // the tie with 2^16 rounds to infinity
    CHECK(half_from_float(-INFINITY) == 0xfc00u);
    CHECK(std::isnan(float_from_half(half_from_float(NAN))));
    // round_to_half saturates instead
    CHECK(round_to_half(1e30f) == 65504.0f);
    CHECK(round_to_half(-70000.0f) == -65504.0f);
    // every float of a large sample below 65520 in magnitude
    int checked = 0;
    for (std::uint32_t i = 0; i < 2000000; ++i) {
        const std::uint32_t bits = pcg_hash(i * 2654435761u + 7u);
        const float f = float_from_bits(bits);
        if (!std::isfinite(f) || std::fabs(f) >= 65520.0f) continue;
        const double expected = nearest_half_reference(f);
        const double got = static_cast<double>(float_from_half(half_from_float(f)));
        if (got != expected) {
            CAPTURE(bits);
            REQUIRE(got == expected);
        }
        ++checked;
    }
    CHECK(checked > 500000);
}

TEST_CASE("round_to_half equals the conversion there and back of the clamped value") {
    for (std::uint32_t i = 0; i < 4000000; ++i) {
        const std::uint32_t bits = pcg_hash(i * 747796405u + 1u) >> (i % 5u);  // small values too
        const float f = float_from_bits(bits ^ ((i & 1u) << 31));
        if (std::isnan(f)) continue;
        const float clamped = std::max(-65504.0f, std::min(65504.0f, f));
        const float expected = float_from_half(half_from_float(clamped));
        if (round_to_half(f) != expected ||
            std::signbit(round_to_half(f)) != std::signbit(expected)) {
            CAPTURE(bits);
            REQUIRE(round_to_half(f) == expected);
        }
    }
    float row[16];
    for (std::uint32_t i = 0; i < 400000; ++i) {
        float expected[16];
        for (std::uint32_t j = 0; j < 16; ++j) {
            row[j] = float_from_bits(pcg_hash(i * 16u + j) >> ((i + j) % 5u));
            expected[j] = round_to_half(row[j]);
        }
        round_to_half_16(row);
        for (int j = 0; j < 16; ++j)
            if (!std::isnan(expected[j])) REQUIRE(std::memcmp(&row[j], &expected[j], 4) == 0);
    }
    CHECK(std::isnan(round_to_half(NAN)));
    CHECK(round_to_half(INFINITY) == 65504.0f);
}

#if defined(__FLT16_MAX__) && !defined(__clang__)
TEST_CASE("half_from_float equals the compiler's _Float16 conversion") {
    for (std::uint32_t i = 0; i < 4000000; ++i) {
        const std::uint32_t bits = pcg_hash(i ^ 0x9e3779b9u) ^ (i << 16);
        const float f = float_from_bits(bits);
        if (std::isnan(f)) continue;
        const _Float16 h = static_cast<_Float16>(f);
        std::uint16_t expected;
        std::memcpy(&expected, &h, sizeof expected);
        if (half_from_float(f) != expected) {
            CAPTURE(bits);
            REQUIRE(half_from_float(f) == expected);
        }
    }
}
#endif

#ifdef FOVREF_HALF_F16C
TEST_CASE(
    "round_to_half_span_f16c (the F16C path of the fit's rows) gives round_to_half_span's bits "
    "on 4 M random bit patterns and on every special range, and refuses NaN") {
    if (!cpu_has_f16c()) {
        MESSAGE("this CPU has no F16C: the scalar path is the only one (nothing to compare)");
        return;
    }
    std::int64_t compared = 0;
    const auto compare = [&](const float* values) {
        float a[16], b[16];
        std::memcpy(a, values, sizeof a);
        std::memcpy(b, values, sizeof b);
        round_to_half_span<0>(a);
        if (!round_to_half_span_f16c<0>(b)) {
            // a NaN lane: nothing written, the scalar path decides
            bool nan = false;
            for (int k = 0; k < 16; ++k) nan = nan || std::isnan(values[k]);
            REQUIRE(nan);
            REQUIRE(std::memcmp(b, values, sizeof b) == 0);
            return;
        }
        REQUIRE(std::memcmp(a, b, sizeof a) == 0);
        compared += 16;
    };
    float v[16];
    // random bit patterns (every exponent, both signs; NaNs among them)
    for (std::uint32_t i = 0; i < 250000; ++i) {
        for (int k = 0; k < 16; ++k) {
            const std::uint32_t bits = pcg_hash(i * 16u + static_cast<std::uint32_t>(k) + 7u);
            std::memcpy(&v[k], &bits, sizeof bits);
        }
        compare(v);
    }
    // the ranges where the two paths could part: subnormal halves, ties, the top of the range,
    // beyond it, infinities, zeros
    const float specials[] = {0.0f,       -0.0f,           0x1p-25f,        0x1.8p-25f, 0x1p-24f,
                              0x1.8p-24f, 0x1p-15f,        0x1.ff8p-15f,    0x1p-14f,   65504.0f,
                              65519.0f,   65520.0f,        65536.0f,        1e30f,      INFINITY,
                              -INFINITY,  1.0f + 0x1p-11f, 1.0f + 0x3p-11f, -2049.0f,   1e-40f};
    for (std::size_t start = 0; start < sizeof specials / sizeof specials[0]; ++start) {
        for (int k = 0; k < 16; ++k)
            v[k] = specials[(start + static_cast<std::size_t>(k)) %
                            (sizeof specials / sizeof specials[0])];
        compare(v);
    }
    // the spans the fit uses (columns 4, 8, 12 .. 15) and a NaN in one of them
    for (std::uint32_t i = 0; i < 10000; ++i) {
        float a[16], b[16];
        for (int k = 0; k < 16; ++k)
            a[k] = b[k] = 200.0f * (rand_unit(5, i, static_cast<std::uint32_t>(k)) - 0.5f);
        round_to_half_span<4>(a);
        REQUIRE(round_to_half_span_f16c<4>(b));
        REQUIRE(std::memcmp(a, b, sizeof a) == 0);
        round_to_half_span<12>(a);
        REQUIRE(round_to_half_span_f16c<12>(b));
        REQUIRE(std::memcmp(a, b, sizeof a) == 0);
    }
    v[3] = NAN;
    CHECK_FALSE(round_to_half_span_f16c<0>(v));
    MESSAGE(compared << " values compared bit for bit");
    CHECK(compared > 3000000);
}
#endif

#ifdef FOVREF_HALF_F16C
TEST_CASE(
    "BMFR fit: the F16C path and the integer code give the same bits on whole blocks "
    "(random and rank-deficient matrices, NaN included)") {
    if (!cpu_has_f16c()) {
        MESSAGE("this CPU has no F16C: the integer code is the only path");
        return;
    }
    for (std::uint32_t block = 0; block < 40; ++block) {
        BmfrBlockMatrix m;
        m.rows = 1024;
        m.a.assign(static_cast<std::size_t>(m.rows) * bmfr_matrix_stride, 0.0f);
        for (int r = 0; r < m.rows; ++r)
            for (int col = 0; col < bmfr_column_count; ++col) {
                const float u = rand_unit(7, block * 1024u + static_cast<std::uint32_t>(r),
                                          static_cast<std::uint32_t>(col));
                // block 3k: a flat wall (columns 1..9 constant, rank-deficient), 3k + 1: wide
                // values, 3k + 2: small ones; one NaN in block 10
                float v = col == 0                     ? 1.0f
                          : block % 3 == 0 && col < 10 ? 0.25f
                          : block % 3 == 1             ? 3000.0f * (u - 0.5f)
                                                       : 1e-3f * u;
                if (block == 10 && r == 77 && col == 11) v = NAN;
                m.a[static_cast<std::size_t>(r) * bmfr_matrix_stride + col] = round_to_half(v);
            }
        BmfrParams vector_path, integer_path;
        integer_path.f16c = false;
        BmfrBlockMatrix a = m, b = m;
        const BmfrBlockFit fa = bmfr_solve_block(vector_path, a);
        const BmfrBlockFit fb = bmfr_solve_block(integer_path, b);
        CAPTURE(block);
        REQUIRE(std::memcmp(a.a.data(), b.a.data(), a.a.size() * sizeof(float)) == 0);
        REQUIRE(std::memcmp(fa.weights, fb.weights, sizeof fa.weights) == 0);
    }
}
#endif
