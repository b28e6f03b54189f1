// The Visual-Polar resolve (ref/visual_polar/resolve.h: phi-only pyramid, trilinear lookup) and
// the P5 blur ramp (ref/filters/blur_ramp.h): analytic cases (constants, a buffer linear in
// the radius or in the angle, hand-computed pyramid levels and levels lambda), a cross-check of
// every pixel against an independent binary64 implementation of the documented lookup, and the
// blur's invariants (fovea untouched, unit mass, constants, symmetry, the two passes' axes).
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <vector>

#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/core/simd.h"
#include "ref/core/vec.h"
#include "ref/filters/blur_ramp.h"
#include "ref/visual_polar/map.h"
#include "ref/visual_polar/resolve.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

namespace {

constexpr double two_pi_d = 6.283185307179586476925;

/// A deterministic value in [0, 1) for (a, b, c) (test data only).
float hash_unit(std::uint32_t a, std::uint32_t b, std::uint32_t c = 0) {
    std::uint32_t h =
        a * 0x9E3779B1u ^ (b + 0x7F4A7C15u) * 0x85EBCA77u ^ (c + 0x165667B1u) * 0xC2B2AE3Du;
    h ^= h >> 15;
    h *= 0x2C1B3C6Du;
    h ^= h >> 12;
    h *= 0x297A2D39u;
    h ^= h >> 15;
    return static_cast<float>(h >> 8) * 0x1p-24f;
}

/// A mask with every unclipped texel traced (rows j < n_i).
Image unclipped_mask(const VisualPolarMap& map) {
    Image valid(map.width, map.height, 1, 0.0f);
    for (int i = 0; i < map.width; ++i)
        for (int j = 0; j < vp_column_rows(map, i); ++j) valid.at(i, j) = 1.0f;
    return valid;
}

double gaze_distance_d(const VisualPolarMap& map, glm::vec2 p) {
    return std::hypot(static_cast<double>(p.x) - map.gaze.x, static_cast<double>(p.y) - map.gaze.y);
}

/// The documented lookup of one pixel in binary64 (every texel traced), written independently
/// of vp_resolve.cpp: only vp_forward's u (the normative forward map) and the pyramid's texels
/// (checked by their own tests) are shared.
double reference_pixel(const VisualPolarMap& map, const VpMips& mips, int x, int y, int channel) {
    const glm::vec2 c = pixel_centre(x, y);
    const double u = vp_forward(map, c).x;
    const double dx = static_cast<double>(c.x) - map.gaze.x,
                 dy = static_cast<double>(c.y) - map.gaze.y;
    const double r = std::max(std::hypot(dx, dy), std::ldexp(1.0, -10));
    double theta = std::atan2(dy, dx);
    if (theta < 0.0) theta += two_pi_d;
    const double s = std::clamp(u, 0.5, map.width - 0.5) - 0.5;
    const int i0 = static_cast<int>(std::floor(s));
    const int i1 = std::min(i0 + 1, map.width - 1);
    const double fx = s - i0;
    const auto column_value = [&](int column) {
        const int n = vp_column_rows(map, column);
        const int last = static_cast<int>(std::ceil(std::log2(static_cast<double>(n))));
        const double v = n * theta / two_pi_d;
        const double lambda =
            std::clamp(std::log2(n / (two_pi_d * r)), 0.0, static_cast<double>(last));
        const int l0 = static_cast<int>(std::floor(lambda));
        const int l1 = std::min(l0 + 1, last);
        const double f = lambda - l0;
        const auto level_value = [&](int level) {
            const int rows = static_cast<int>(std::ceil(n / std::ldexp(1.0, level)));
            const double t = std::ldexp(v, -level) - 0.5;
            const double fv = t - std::floor(t);
            int j0 = static_cast<int>(std::floor(t)) % rows;
            if (j0 < 0) j0 += rows;
            const int j1 = (j0 + 1) % rows;
            const Image& img = mips.color[static_cast<std::size_t>(level)];
            return (1.0 - fv) * img.at(column, j0, channel) + fv * img.at(column, j1, channel);
        };
        return (1.0 - f) * level_value(l0) + f * level_value(l1);
    };
    return (1.0 - fx) * column_value(i0) + fx * column_value(i1);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// The phi-only pyramid

TEST_CASE("VP resolve: the phi pyramid's sizes and row counts per column and level") {
    const VisualPolarMap map = make_visual_polar_map(64, 64, {32.0f, 32.0f}, 16, 12);
    REQUIRE(map.fovea_columns == 4);  // round(0.24 * 16)
    // n_i = clamp(ceil(12 (i + 1/2) / 4 - 1/2), 1, 12): 1, 4, 7, 10, then 12 in the periphery
    const int expected_rows[5] = {1, 4, 7, 10, 12};
    for (int i = 0; i < 5; ++i) CHECK(vp_column_rows(map, i) == expected_rows[i]);
    const VpMips mips = build_vp_mips(map, Image(16, 12, 3, 0.25f), unclipped_mask(map));
    // 12, 6, 3, 2, 1 rows: five levels
    REQUIRE(mips.color.size() == 5);
    REQUIRE(mips.valid.size() == 5);
    const int heights[5] = {12, 6, 3, 2, 1};
    for (int k = 0; k < 5; ++k) {
        CHECK(mips.color[static_cast<std::size_t>(k)].height == heights[k]);
        CHECK(mips.color[static_cast<std::size_t>(k)].width == 16);
        CHECK(mips.color[static_cast<std::size_t>(k)].channels == 3);
        CHECK(mips.valid[static_cast<std::size_t>(k)].channels == 1);
    }
    // column 2 (7 rows): 7, 4, 2, 1, 1; column 1 (4 rows): 4, 2, 1, 1, 1
    const int rows2[5] = {7, 4, 2, 1, 1}, rows1[5] = {4, 2, 1, 1, 1};
    for (int k = 0; k < 5; ++k) {
        CHECK(vp_mip_column_rows(mips, 2, k) == rows2[k]);
        CHECK(vp_mip_column_rows(mips, 1, k) == rows1[k]);
    }
    CHECK(vp_mip_last_level(1) == 0);
    CHECK(vp_mip_last_level(2) == 1);
    CHECK(vp_mip_last_level(7) == 3);
    CHECK(vp_mip_last_level(8) == 3);
    CHECK(vp_mip_last_level(9) == 4);
    // A constant stays exactly that constant on every traced texel of every level.
    for (std::size_t k = 0; k < mips.color.size(); ++k)
        for (int i = 0; i < 16; ++i)
            for (int j = 0; j < vp_mip_column_rows(mips, i, static_cast<int>(k)); ++j) {
                CHECK(mips.valid[k].at(i, j) == 1.0f);
                CHECK(mips.color[k].at(i, j, 1) == 0.25f);
            }
}

TEST_CASE(
    "VP resolve: phi pyramid: alternating rows average to 1/2, an odd column's last row wraps "
    "onto row 0, untraced texels are excluded") {
    const VisualPolarMap map = make_visual_polar_map(64, 64, {32.0f, 32.0f}, 16, 12);
    Image color(16, 12, 1, 0.0f);
    Image valid = unclipped_mask(map);
    // Clipped rows hold NaN (and are marked traced): they must never be read.
    for (int i = 0; i < 16; ++i)
        for (int j = vp_column_rows(map, i); j < 12; ++j) {
            color.at(i, j) = std::numeric_limits<float>::quiet_NaN();
            valid.at(i, j) = 1.0f;
        }
    for (int j = 0; j < 12; ++j) color.at(4, j) = static_cast<float>(j % 2);  // 0 1 0 1 ...
    for (int j = 0; j < 7; ++j) color.at(2, j) = static_cast<float>(j);       // 7 rows: 0 .. 6
    color.at(0, 0) = 0.75f;                                                   // 1 row
    // column 5: j + 1, rows 3, 4 and 5 untraced with a value that would show
    for (int j = 0; j < 12; ++j) color.at(5, j) = static_cast<float>(j + 1);
    for (const int j : {3, 4, 5}) {
        valid.at(5, j) = 0.0f;
        color.at(5, j) = 1000.0f;
    }
    const VpMips mips = build_vp_mips(map, color, valid);

    SUBCASE("alternating 0/1 rows: 1/2 at level 1 (6 rows) and level 2 (3 rows)") {
        for (int j = 0; j < 6; ++j) {
            CHECK(mips.color[1].at(4, j) == 0.5f);
            CHECK(mips.valid[1].at(4, j) == 1.0f);
        }
        for (int j = 0; j < 3; ++j) CHECK(mips.color[2].at(4, j) == 0.5f);
    }
    SUBCASE("7 rows 0..6: level 1 = (0+1)/2, (2+3)/2, (4+5)/2, (6+0)/2; then 1.5, 3.75; 2.625") {
        // the running mean of exact binary fractions: every value below is exact
        CHECK(mips.color[1].at(2, 0) == 0.5f);
        CHECK(mips.color[1].at(2, 1) == 2.5f);
        CHECK(mips.color[1].at(2, 2) == 4.5f);
        CHECK(mips.color[1].at(2, 3) == 3.0f);  // row 6 with row 0 (wrap)
        for (int j = 0; j < 4; ++j) CHECK(mips.valid[1].at(2, j) == 1.0f);
        // level 1's rows 4, 5 lie beyond the column's 4 rows: empty
        CHECK(mips.valid[1].at(2, 4) == 0.0f);
        CHECK(mips.color[1].at(2, 4) == 0.0f);
        CHECK(mips.color[2].at(2, 0) == 1.5f);
        CHECK(mips.color[2].at(2, 1) == 3.75f);
        CHECK(mips.color[3].at(2, 0) == 2.625f);
        CHECK(mips.color[4].at(2, 0) == 2.625f);  // one row: carried down
        CHECK(mips.valid[4].at(2, 0) == 1.0f);
    }
    SUBCASE("a one-row column is carried down unchanged") {
        for (std::size_t k = 0; k < mips.color.size(); ++k) {
            CHECK(mips.color[k].at(0, 0) == 0.75f);
            CHECK(mips.valid[k].at(0, 0) == 1.0f);
        }
    }
    SUBCASE("untraced texels are excluded; a pair of untraced texels is untraced") {
        CHECK(mips.color[1].at(5, 0) == 1.5f);  // rows 0, 1: (1 + 2) / 2
        CHECK(mips.color[1].at(5, 1) == 3.0f);  // rows 2, 3: row 2 alone
        CHECK(mips.valid[1].at(5, 1) == 1.0f);
        CHECK(mips.valid[1].at(5, 2) == 0.0f);  // rows 4, 5: neither traced
        CHECK(mips.color[1].at(5, 2) == 0.0f);
        CHECK(mips.color[1].at(5, 3) == 7.5f);   // rows 6, 7
        CHECK(mips.color[2].at(5, 0) == 2.25f);  // 1.5 then 3
        CHECK(mips.color[2].at(5, 1) == 7.5f);   // level 1's row 2 untraced, row 3 alone
    }
    SUBCASE("no NaN from a clipped row reached any level") {
        for (std::size_t k = 1; k < mips.color.size(); ++k)
            for (const float value : mips.color[k].data) CHECK(!std::isnan(value));
    }
}

// ---------------------------------------------------------------------------------------------
// The lookup

TEST_CASE(
    "VP resolve: a constant buffer resolves to exactly that constant at every pixel (every "
    "unclipped texel traced), with off-screen texels untraced, to the constant or black") {
    for (const glm::vec2& gaze : {glm::vec2(96.0f, 72.0f), glm::vec2(0.0f, 0.0f),
                                  glm::vec2(191.5f, 3.0f), glm::vec2(-60.0f, 200.0f)}) {
        CAPTURE(gaze.x);
        CAPTURE(gaze.y);
        const VisualPolarMap map = make_visual_polar_map(192, 144, gaze, 128, 96);
        const float constant[3] = {0.3f, 0.7f, 1.25f};
        // clipped rows hold NaN: they must never be read
        Image color(map.width, map.height, 3, 0.0f);
        Image valid = unclipped_mask(map);
        for (int i = 0; i < map.width; ++i)
            for (int j = 0; j < map.height; ++j)
                for (int c = 0; c < 3; ++c)
                    color.at(i, j, c) = j < vp_column_rows(map, i)
                                            ? constant[c]
                                            : std::numeric_limits<float>::quiet_NaN();

        // Every unclipped texel traced: the constant everywhere, bit for bit
        {
            ResolveStats stats;
            const Image out = resolve_visual_polar(map, build_vp_mips(map, color, valid), stats);
            CHECK(stats.pixels_from_buffer == 192 * 144);
            CHECK(stats.pixels_untraced_taps == 0);
            CHECK(stats.pixels_from_gaze == 0);
            long long wrong = 0;
            for (int y = 0; y < 144; ++y)
                for (int x = 0; x < 192; ++x)
                    for (int c = 0; c < 3; ++c) wrong += out.at(x, y, c) != constant[c];
            CHECK(wrong == 0);
        }
        // Off-screen texels untraced (as the trace leaves them): the constant or black, counted
        {
            for (int i = 0; i < map.width; ++i)
                for (int j = 0; j < vp_column_rows(map, i); ++j) {
                    glm::vec2 p;
                    REQUIRE(vp_inverse(map, i, j, p));
                    if (!(p.x >= 0.0f && p.y >= 0.0f && p.x < 192.0f && p.y < 144.0f))
                        valid.at(i, j) = 0.0f;
                }
            ResolveStats stats;
            const Image out = resolve_visual_polar(map, build_vp_mips(map, color, valid), stats);
            long long black = 0, wrong = 0;
            for (int y = 0; y < 144; ++y)
                for (int x = 0; x < 192; ++x) {
                    const bool is_black = out.at(x, y, 0) == 0.0f && out.at(x, y, 1) == 0.0f &&
                                          out.at(x, y, 2) == 0.0f;
                    black += is_black;
                    if (!is_black)
                        for (int c = 0; c < 3; ++c) wrong += out.at(x, y, c) != constant[c];
                }
            MESSAGE(black << " black pixels (no traced tap) with off-screen texels untraced");
            CHECK(wrong == 0);
            CHECK(black == stats.pixels_untraced_taps);
        }
    }
}

TEST_CASE("VP resolve: no traced texel gives black pixels, all counted") {
    const VisualPolarMap map = make_visual_polar_map(48, 36, {20.0f, 10.0f}, 32, 24);
    ResolveStats stats;
    const Image out = resolve_visual_polar(
        map, build_vp_mips(map, Image(32, 24, 3, 1.0f), Image(32, 24, 1, 0.0f)), stats);
    CHECK(stats.pixels_untraced_taps == 48 * 36);
    CHECK(out == Image(48, 36, 3, 0.0f));
}

TEST_CASE(
    "VP resolve: a buffer holding each column's radius resolves to the pixel's distance from "
    "the gaze (bilinear along rho)") {
    for (const glm::vec2& gaze :
         {glm::vec2(160.0f, 120.0f), glm::vec2(10.0f, 230.0f), glm::vec2(-50.0f, 100.0f)}) {
        CAPTURE(gaze.x);
        CAPTURE(gaze.y);
        const VisualPolarMap map = make_visual_polar_map(320, 240, gaze, 213, 160);
        Image color(map.width, map.height, 1, 0.0f);
        for (int i = 0; i < map.width; ++i)
            for (int j = 0; j < map.height; ++j) color.at(i, j) = vp_column_radius(map, i);
        ResolveStats stats;
        const Image out =
            resolve_visual_polar(map, build_vp_mips(map, color, unclipped_mask(map)), stats);
        REQUIRE(stats.pixels_untraced_taps == 0);

        // Periphery: r(u) = s P(U(u)), U = u0 + (u / w - rho_f)(1 - u0) / (1 - rho_f), is not
        // linear in u; linear interpolation between texel centres one texel apart errs by at
        // most max|r''(u)| / 8 with r'' = s P''(U) (dU/du)^2 <= s P''(1) (dU/du)^2 (P'' grows
        // with U). Float: vp_forward's u is within 1e-3 texel of exact (its round-trip test),
        // times dr/du <= s P'(1) dU/du; radii below 400 px round to 3e-5 px.
        const double rho_f = static_cast<double>(map.fovea_columns) / map.width;
        const double du_dU = map.width * (1.0 - rho_f) / (1.0 - vp_u0);
        const double P2_max = 12 * 25.09 + 6 * 0.1680 + 2 * 27.61;
        const double P1_max = 4 * 25.09 + 3 * 0.1680 + 2 * 27.61 + 23.87;
        const double curvature_bound = map.scale * P2_max / (du_dU * du_dU) / 8.0;
        const double float_bound = 1e-3 * map.scale * P1_max / du_dU + 1e-4;
        const double periphery_tolerance = curvature_bound + float_bound;
        // Fovea: r(u) is linear (r = F u / i_f): only float rounding, of r < 40 px and u < 60
        // (a few ulps: 1e-5 px); 1e-4 px.
        const double fovea_tolerance = 1e-4;

        const double r_fovea_lo = vp_column_radius(map, 0);
        const double r_fovea_hi = vp_column_radius(map, map.fovea_columns - 1);
        const double r_periphery_lo = vp_column_radius(map, map.fovea_columns);
        const double r_periphery_hi = vp_column_radius(map, map.width - 1);
        double worst_fovea = 0.0, worst_periphery = 0.0;
        long long fovea_pixels = 0, periphery_pixels = 0;
        for (int y = 0; y < 240; ++y)
            for (int x = 0; x < 320; ++x) {
                const double r = gaze_distance_d(map, pixel_centre(x, y));
                const double error = std::fabs(out.at(x, y) - r);
                if (r >= r_fovea_lo && r <= r_fovea_hi) {
                    worst_fovea = std::max(worst_fovea, error);
                    ++fovea_pixels;
                } else if (r >= r_periphery_lo && r <= r_periphery_hi) {
                    worst_periphery = std::max(worst_periphery, error);
                    ++periphery_pixels;
                }
            }
        MESSAGE("fovea: " << fovea_pixels << " pixels, max error " << worst_fovea
                          << " px; periphery: " << periphery_pixels << " pixels, max error "
                          << worst_periphery << " px (bound " << periphery_tolerance << ")");
        CHECK(periphery_pixels > 10000);
        CHECK(worst_fovea <= fovea_tolerance);
        CHECK(worst_periphery <= periphery_tolerance);
    }
}

TEST_CASE(
    "VP resolve: a buffer holding each row's centre (j + 1/2) resolves to v = h theta / 2 pi in "
    "the periphery at level 0 (linear along phi, texel centres at + 1/2)") {
    const VisualPolarMap map = make_visual_polar_map(320, 240, {140.0f, 130.0f}, 213, 160);
    Image color(map.width, map.height, 1, 0.0f);
    for (int i = 0; i < map.width; ++i)
        for (int j = 0; j < vp_column_rows(map, i); ++j)
            color.at(i, j) = static_cast<float>(j) + 0.5f;
    ResolveStats stats;
    const Image out =
        resolve_visual_polar(map, build_vp_mips(map, color, unclipped_mask(map)), stats);
    const double r_min =
        std::max<double>(vp_column_radius(map, map.fovea_columns), map.height / two_pi_d);
    double worst = 0.0;
    long long pixels = 0;
    for (int y = 0; y < 240; ++y)
        for (int x = 0; x < 320; ++x) {
            const glm::vec2 c = pixel_centre(x, y);
            // level 0 exactly: h / (2 pi r) <= 1 with a margin for float
            if (gaze_distance_d(map, c) < r_min * 1.001) continue;
            double theta = std::atan2(c.y - static_cast<double>(map.gaze.y),
                                      c.x - static_cast<double>(map.gaze.x));
            if (theta < 0.0) theta += two_pi_d;
            const double v = map.height * theta / two_pi_d;
            if (v < 1.0 || v > map.height - 1.0) continue;  // the wrap: not linear there
            worst = std::max(worst, std::fabs(out.at(x, y) - v));
            ++pixels;
        }
    // theta in float is within ~2e-7 rad, times h / 2 pi = 25 rows/rad; the lerp of values
    // below 160 adds ulps of 1.5e-5: 1e-4 rows.
    MESSAGE(pixels << " pixels, max |value - v| " << worst << " rows");
    CHECK(pixels > 40000);
    CHECK(worst < 1e-4);
}

TEST_CASE(
    "VP resolve: every pixel equals an independent binary64 evaluation of the documented "
    "trilinear lookup") {
    for (const glm::vec2& gaze :
         {glm::vec2(48.0f, 40.0f), glm::vec2(3.0f, 77.0f), glm::vec2(120.0f, -20.0f)}) {
        CAPTURE(gaze.x);
        CAPTURE(gaze.y);
        const VisualPolarMap map = make_visual_polar_map(96, 80, gaze, 64, 53);
        Image color(map.width, map.height, 2, 0.0f);
        for (int i = 0; i < map.width; ++i)
            for (int j = 0; j < map.height; ++j)
                for (int c = 0; c < 2; ++c)
                    color.at(i, j, c) =
                        hash_unit(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j),
                                  static_cast<std::uint32_t>(c));
        const VpMips mips = build_vp_mips(map, color, unclipped_mask(map));
        ResolveStats stats;
        const Image out = resolve_visual_polar(map, mips, stats);
        double worst = 0.0;
        for (int y = 0; y < 80; ++y)
            for (int x = 0; x < 96; ++x)
                for (int c = 0; c < 2; ++c)
                    worst = std::max(
                        worst, std::fabs(out.at(x, y, c) - reference_pixel(map, mips, x, y, c)));
        // Values in [0, 1) with contrast up to 1 per texel: float theta (2e-7 rad, times n / 2 pi
        // < 9 rows/rad), lambda (1 ulp), the fractions and three lerps (a few ulps each) stay
        // below 1e-5; the lookup is continuous where float and binary64 floor() disagree.
        MESSAGE("max |float - binary64| " << worst);
        CHECK(worst < 1e-5);
    }
}

TEST_CASE(
    "VP resolve: the level lambda = max(0, log2(n / (2 pi r))) at hand-picked pixels (P5's "
    "1280x1440 preset, gaze at the centre, s = 12.05 px/degree)") {
    const glm::ivec2 size = visual_polar_buffer_size(1280, 1440);
    const VisualPolarMap map = make_visual_polar_map(1280, 1440, {640.0f, 720.0f}, size.x, size.y);
    const Image color(size.x, size.y, 1, 0.5f);
    const VpMips mips = build_vp_mips(map, color, unclipped_mask(map));
    Image out(1280, 1440, 1, 0.0f);
    ResolveStats stats;
    // the level of column i0 = floor(u - 1/2) at pixel (x, y), by hand from the formula
    const auto expected = [&](int x, int y) {
        const glm::vec2 c = pixel_centre(x, y);
        const int i0 = static_cast<int>(std::floor(vp_forward(map, c).x - 0.5f));
        const double n = vp_column_rows(map, i0);
        const double r = std::max(gaze_distance_d(map, c), std::ldexp(1.0, -10));
        return std::max(0.0, std::log2(n / (two_pi_d * r)));
    };
    const auto lambda_at = [&](int x, int y) {
        float lambda = -1.0f;
        resolve_vp_pixel(map, mips, out, x, y, stats, &lambda);
        return lambda;
    };

    // (640, 720): r = 0.707 px, column 1 of 7 rows: log2(7 / (2 pi 0.707)) = 0.656
    CHECK(lambda_at(640, 720) == doctest::Approx(expected(640, 720)).epsilon(1e-5));
    CHECK(expected(640, 720) == doctest::Approx(0.656).epsilon(1e-3));
    // 40 px out (inside the fovea, radius 69.8 px): about 2.19 texels per pixel, lambda 1.13
    CHECK(lambda_at(680, 720) == doctest::Approx(expected(680, 720)).epsilon(1e-5));
    CHECK(expected(680, 720) == doctest::Approx(1.13).epsilon(1e-2));
    // 100 px out (periphery, h = 960 rows): log2(960 / (2 pi 100.5)) = 0.604
    CHECK(lambda_at(740, 720) == doctest::Approx(expected(740, 720)).epsilon(1e-5));
    CHECK(expected(740, 720) == doctest::Approx(0.604).epsilon(1e-3));
    // far out: fewer than one texel per pixel, level 0 exactly
    CHECK(lambda_at(1240, 720) == 0.0f);
    CHECK(lambda_at(0, 0) == 0.0f);
    // at the gaze (r guarded to 2^-10): column 0 has 2 rows, clamped to its last level, 1
    {
        const VisualPolarMap at_centre =
            make_visual_polar_map(1280, 1440, {640.5f, 720.5f}, size.x, size.y);
        REQUIRE(vp_column_rows(at_centre, 0) == 2);
        const VpMips mips_c = build_vp_mips(at_centre, color, unclipped_mask(at_centre));
        float lambda = -1.0f;
        resolve_vp_pixel(at_centre, mips_c, out, 640, 720, stats, &lambda);
        CHECK(lambda == 1.0f);
    }
    // lambda >= 0 and within the column's levels everywhere (a grid of pixels)
    for (int y = 0; y < 1440; y += 7)
        for (int x = 0; x < 1280; x += 7) {
            const float lambda = lambda_at(x, y);
            const int i0 =
                static_cast<int>(std::floor(std::clamp(vp_forward(map, pixel_centre(x, y)).x, 0.5f,
                                                       static_cast<float>(size.x) - 0.5f) -
                                            0.5f));
            REQUIRE(lambda >= 0.0f);
            REQUIRE(lambda <= static_cast<float>(vp_mip_last_level(vp_column_rows(map, i0))));
        }
    CHECK(vp_mip_level(960, 1000.0f) == 0.0f);
    CHECK(vp_mip_level(960, 960.0f / 6.28318530717958647692f / 4.0f) ==
          doctest::Approx(2.0).epsilon(1e-6));
}

// ---------------------------------------------------------------------------------------------
// The blur ramp

TEST_CASE(
    "VP blur: sigma_px follows the ramp: 0 to the fovea edge, 0.564 s at 30 degrees and beyond") {
    const VisualPolarMap map = make_visual_polar_map(1280, 1440, {640.0f, 720.0f}, 853, 960);
    const BlurRamp ramp;
    const float s = map.scale;
    CHECK(s == doctest::Approx(12.05).epsilon(1e-3));  // P5's setting
    const float e_f = vp_inverse_cdf(vp_u0);
    CHECK(e_f == doctest::Approx(5.79).epsilon(1e-3));
    const auto at_degrees = [&](double e) {
        return blur_ramp_sigma_px(ramp, blur_ramp_geometry(map),
                                  map.gaze + glm::vec2(static_cast<float>(e * s), 0.0f));
    };
    CHECK(at_degrees(0.0) == 0.0f);
    CHECK(at_degrees(e_f * 0.999) == 0.0f);
    CHECK(at_degrees(e_f * 1.001) > 0.0f);
    // midway along the ramp: half of sigma
    CHECK(at_degrees(0.5 * (e_f + 30.0)) == doctest::Approx(0.5 * 0.564 * s).epsilon(1e-5));
    // at 30 degrees: 0.564 s (6.8 px); (30 s) / s may round just below 30: within 1e-5
    CHECK(at_degrees(30.0) == doctest::Approx(0.564 * s).epsilon(1e-5));
    CHECK(0.564 * s == doctest::Approx(6.8).epsilon(2e-3));
    // beyond: exactly sigma_deg * s
    CHECK(at_degrees(30.5) == 0.564f * s);
    CHECK(at_degrees(70.0) == 0.564f * s);
    // the kernel's radius: ceil(3 sigma) capped at 64
    CHECK(blur_ramp_radius(0.0f) == 0);
    CHECK(blur_ramp_radius(0.1f) == 1);
    CHECK(blur_ramp_radius(0.564f * s) == 21);
    CHECK(blur_ramp_radius(100.0f) == blur_ramp_max_radius);
}

namespace {

Image random_image(int width, int height, int channels, std::uint32_t seed) {
    Image image(width, height, channels, 0.0f);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < channels; ++c)
                image.at(x, y, c) = hash_unit(static_cast<std::uint32_t>(x),
                                              static_cast<std::uint32_t>(y) * 7u + seed,
                                              static_cast<std::uint32_t>(c));
    return image;
}

Image transposed(const Image& image) {
    Image out(image.height, image.width, image.channels, 0.0f);
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            for (int c = 0; c < image.channels; ++c) out.at(y, x, c) = image.at(x, y, c);
    return out;
}

}  // namespace

TEST_CASE("VP blur: pixels inside the fovea (sigma = 0) are unchanged bit for bit") {
    // 256 x 256, gaze (40, 60): s = 3.65 px/degree, fovea radius 21 px, sigma up to 2.06 px
    const VisualPolarMap map = make_visual_polar_map(256, 256, {40.0f, 60.0f}, 171, 171);
    const Image image = random_image(256, 256, 3, 1);
    const Image out = blur_ramp(BlurRamp{}, blur_ramp_geometry(map), image);
    long long fovea = 0, changed = 0, blurred = 0;
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) {
            const glm::vec2 c = pixel_centre(x, y);
            const float sigma = blur_ramp_sigma_px(BlurRamp{}, blur_ramp_geometry(map), c);
            const double r = gaze_distance_d(map, c);
            if (r < 0.999 * map.fovea_radius) REQUIRE(sigma == 0.0f);
            if (r > 1.001 * map.fovea_radius) REQUIRE(sigma > 0.0f);
            if (sigma == 0.0f) {
                ++fovea;
                for (int k = 0; k < 3; ++k)
                    changed += std::bit_cast<std::uint32_t>(out.at(x, y, k)) !=
                               std::bit_cast<std::uint32_t>(image.at(x, y, k));
            } else if (out.at(x, y, 0) != image.at(x, y, 0)) {
                ++blurred;
            }
        }
    MESSAGE(fovea << " pixels with sigma 0, " << blurred << " others changed");
    CHECK(fovea > 1000);
    CHECK(changed == 0);
    CHECK(blurred > 50000);
}

TEST_CASE(
    "VP blur: an impulse where sigma is constant spreads with unit total weight as a "
    "symmetric Gaussian") {
    const VisualPolarMap map = make_visual_polar_map(256, 256, {40.0f, 60.0f}, 171, 171);
    const BlurRamp ramp;
    const int x0 = 200, y0 = 200;  // 212 px from the gaze; 30 degrees = 110 px
    const float sigma = 0.564f * map.scale;
    const int radius = blur_ramp_radius(sigma);
    REQUIRE(radius == 7);
    for (int d = -radius; d <= radius; ++d) {
        REQUIRE(blur_ramp_sigma_px(ramp, blur_ramp_geometry(map), pixel_centre(x0 + d, y0)) ==
                sigma);
        REQUIRE(blur_ramp_sigma_px(ramp, blur_ramp_geometry(map), pixel_centre(x0, y0 + d)) ==
                sigma);
    }
    Image impulse(256, 256, 1, 0.0f);
    impulse.at(x0, y0) = 1.0f;

    SUBCASE("horizontal pass") {
        const Image out = blur_ramp_horizontal(ramp, blur_ramp_geometry(map), impulse);
        double row_sum = 0.0, elsewhere = 0.0;
        for (int y = 0; y < 256; ++y)
            for (int x = 0; x < 256; ++x) (y == y0 ? row_sum : elsewhere) += out.at(x, y);
        // every output pixel normalises its own weights; with one sigma for all of them the
        // mass they gather from the impulse is sum(w_d) / sum(w_d) = 1, up to the float sums of
        // 15 weights: 1e-5.
        CHECK(row_sum == doctest::Approx(1.0).epsilon(1e-5));
        CHECK(elsewhere == 0.0);
        for (int d = 1; d <= radius; ++d) {
            // w_d / sum(w) at -d and +d; the running mean meets the impulse early at one and
            // late at the other, so the two round differently: within 1e-6 relative (a few ulps)
            CHECK(out.at(x0 - d, y0) == doctest::Approx(out.at(x0 + d, y0)).epsilon(1e-6));
            CHECK(out.at(x0 + d, y0) / out.at(x0, y0) ==
                  doctest::Approx(std::exp(-d * d / (2.0 * sigma * sigma))).epsilon(1e-5));
        }
        CHECK(out.at(x0 + radius + 1, y0) == 0.0f);
    }
    SUBCASE("both passes") {
        const Image out = blur_ramp(ramp, blur_ramp_geometry(map), impulse);
        double sum = 0.0;
        for (const float value : out.data) sum += value;
        CHECK(sum == doctest::Approx(1.0).epsilon(1e-5));
        // separable: the 2-D response is the product of the 1-D ones
        const Image h = blur_ramp_horizontal(ramp, blur_ramp_geometry(map), impulse);
        // (the vertical kernel at offset 2 is h(x0 + 2, y0): the same sigma, the same weights)
        for (int d = -radius; d <= radius; ++d)
            CHECK(out.at(x0 + d, y0 + 2) ==
                  doctest::Approx(h.at(x0 + d, y0) * h.at(x0 + 2, y0)).epsilon(1e-5));
    }
}

TEST_CASE("VP blur: a constant image stays constant (normalised weights)") {
    for (const glm::vec2& gaze : {glm::vec2(40.0f, 60.0f), glm::vec2(-80.0f, 300.0f)}) {
        const VisualPolarMap map = make_visual_polar_map(200, 150, gaze, 133, 100);
        const Image image(200, 150, 3, 0.37f);
        // sum of (w_d / W) c over at most 129 taps, twice: within 2 * 129 ulp of c; measured
        // a few ulp
        for (const BlurRamp& ramp : {BlurRamp{}, BlurRamp{2.0f, 20.0f}}) {
            const Image out = blur_ramp(ramp, blur_ramp_geometry(map), image);
            float worst = 0.0f;
            for (float v : out.data) worst = std::max(worst, std::fabs(v - 0.37f));
            CHECK(worst <= 258.0f * 0.37f * 5.96e-8f);
        }
    }
}

TEST_CASE(
    "VP blur: mirror-symmetric input about the gaze gives mirror-symmetric output, the vertical "
    "pass is the horizontal one transposed") {
    SUBCASE("mirror symmetry (within 1e-6: the mirrored sum runs in the opposite order)") {
        const VisualPolarMap map = make_visual_polar_map(200, 160, {100.0f, 80.0f}, 133, 107);
        Image image = random_image(200, 160, 1, 2);
        for (int y = 0; y < 160; ++y)
            for (int x = 100; x < 200; ++x) image.at(x, y) = image.at(199 - x, 159 - y);
        const Image out =
            blur_ramp(BlurRamp{2.0f, 20.0f}, blur_ramp_geometry(map), image);  // sigma up to 3.9 px
        double worst = 0.0;
        for (int y = 0; y < 160; ++y)
            for (int x = 0; x < 200; ++x)
                worst = std::max(
                    worst, std::fabs(static_cast<double>(out.at(x, y)) - out.at(199 - x, 159 - y)));
        MESSAGE("max asymmetry " << worst);
        // values in [0, 1), 2 passes of up to 25 taps in float: a few ulps of 1
        CHECK(worst < 1e-6);
    }
    SUBCASE("vertical(image) == transpose(horizontal(transpose(image))), bit for bit") {
        // a square screen with the gaze on the diagonal: sigma(x, y) == sigma(y, x) exactly
        const VisualPolarMap map = make_visual_polar_map(128, 128, {30.0f, 30.0f}, 85, 85);
        const Image image = random_image(128, 128, 2, 3);
        const BlurRamp ramp{1.5f, 20.0f};
        const Image vertical = blur_ramp_vertical(ramp, blur_ramp_geometry(map), image);
        CHECK(bit_equal(vertical, transposed(blur_ramp_horizontal(ramp, blur_ramp_geometry(map),
                                                                  transposed(image)))));
        CHECK(!bit_equal(vertical, image));
        // and the two passes in order
        CHECK(bit_equal(
            blur_ramp(ramp, blur_ramp_geometry(map), image),
            blur_ramp_vertical(ramp, blur_ramp_geometry(map),
                               blur_ramp_horizontal(ramp, blur_ramp_geometry(map), image))));
    }
}

// The AVX2 groups (eight pixels of three channels, each lane with its own radius) give
// blur_ramp_pixel's bits, pixel by pixel: sizes that are not multiples of 8, the gaze inside and
// off the screen, radii from 1 to the cap of 64, runs of alike groups, non-finite values, which a
// lane outside its own taps must never see, and -0 in copied pixels; other channel counts (1, 2,
// 4, 5) take the scalar path, and so do --scalar runs.
TEST_CASE("VP blur: the AVX pass gives the scalar pass's bits, with and without the kept table") {
    struct Case {
        int width, height, channels;
        glm::vec2 gaze;
        float scale, fovea_deg;
        BlurRamp ramp;
    };
    const Case cases[] = {
        {77, 45, 3, {30.0f, 20.0f}, 3.0f, 2.0f, BlurRamp{}},
        {64, 33, 1, {-40.0f, 70.0f}, 5.0f, 1.0f, BlurRamp{2.0f, 12.0f}},
        {131, 70, 4, {65.0f, 35.0f}, 40.0f, 0.2f, BlurRamp{1.0f, 1.5f}},  // radius capped at 64
        {131, 70, 3, {65.0f, 35.0f}, 40.0f, 0.2f, BlurRamp{1.0f, 1.5f}},
        {64, 33, 3, {-40.0f, 70.0f}, 5.0f, 1.0f, BlurRamp{2.0f, 12.0f}},  // gaze off the screen
        {200, 9, 3, {100.0f, 4.0f}, 1.0f, 3.0f, BlurRamp{0.9f, 60.0f}},
        {41, 29, 5, {10.0f, 10.0f}, 4.0f, 0.5f, BlurRamp{1.0f, 5.0f}},
        {200, 9, 2, {100.0f, 4.0f}, 1.0f, 3.0f, BlurRamp{0.9f, 60.0f}},
        // sigma constant beyond 12 px from the gaze: runs of four and of two groups together
        {107, 52, 3, {25.0f, 30.0f}, 4.0f, 0.5f, BlurRamp{1.0f, 3.0f}},
    };
    for (const Case& k : cases) {
        INFO(k.width << "x" << k.height << "x" << k.channels);
        const BlurRampGeometry geometry{k.width, k.height, k.gaze, k.scale, k.fovea_deg};
        Image image = random_image(k.width, k.height, k.channels, 9);
        for (int c = 0; c < k.channels; ++c) image.at(k.width / 2, k.height / 2, c) *= -1.0f;
        image.at(3, 2, 0) = std::numeric_limits<float>::infinity();
        image.at(k.width - 2, k.height - 1, 0) = std::numeric_limits<float>::quiet_NaN();
        // -0 in every seventh value: a copied pixel (radius 0) keeps its sign (0 + 1 (-0) is +0)
        for (std::size_t i = 0; i < image.data.size(); i += 7) image.data[i] = -0.0f;
        for (const bool vertical : {false, true}) {
            const Image simd = vertical ? blur_ramp_vertical(k.ramp, geometry, image, true)
                                        : blur_ramp_horizontal(k.ramp, geometry, image, true);
            const Image scalar = vertical ? blur_ramp_vertical(k.ramp, geometry, image, false)
                                          : blur_ramp_horizontal(k.ramp, geometry, image, false);
            CHECK(std::memcmp(simd.data.data(), scalar.data.data(),
                              scalar.data.size() * sizeof(float)) == 0);
            // with the per-pixel sigma and exp kept (a static gaze), then with the groups'
            // plan as well (replayed instead of deciding group by group)
            BlurRampTable table = blur_ramp_table(k.ramp, geometry);
            for (const bool planned : {false, true}) {
                if (planned) add_blur_ramp_plan(table);
                CHECK(static_cast<bool>(table.plan) == (planned && cpu_has_avx2()));
                const Image kept =
                    vertical ? blur_ramp_vertical(k.ramp, geometry, image, true, &table)
                             : blur_ramp_horizontal(k.ramp, geometry, image, true, &table);
                CHECK(std::memcmp(kept.data.data(), scalar.data.data(),
                                  scalar.data.size() * sizeof(float)) == 0);
            }
            // written into storage that holds a value no pixel takes (a stage's recycled
            // output), with SIMD and without: every value is written
            for (const bool with_simd : {true, false}) {
                Image storage = test::unwritten_storage(k.width, k.height, k.channels);
                const Image into = vertical
                                       ? blur_ramp_vertical(k.ramp, geometry, image, with_simd,
                                                            &table, std::move(storage))
                                       : blur_ramp_horizontal(k.ramp, geometry, image, with_simd,
                                                              &table, std::move(storage));
                CHECK(std::memcmp(into.data.data(), scalar.data.data(),
                                  scalar.data.size() * sizeof(float)) == 0);
            }
            // both passes from one table and its plan, as the stages share them: the
            // horizontal pass's output blurred vertically
            if (vertical) {
                BlurRampTable shared = blur_ramp_table(k.ramp, geometry);
                add_blur_ramp_plan(shared);
                const Image both_passes = blur_ramp_vertical(
                    k.ramp, geometry, blur_ramp_horizontal(k.ramp, geometry, image, true, &shared),
                    true, &shared);
                const Image reference = blur_ramp_vertical(
                    k.ramp, geometry, blur_ramp_horizontal(k.ramp, geometry, image, false), false);
                CHECK(std::memcmp(both_passes.data.data(), reference.data.data(),
                                  reference.data.size() * sizeof(float)) == 0);
            }
            // the reference itself: every pixel as blur_ramp_pixel makes it
            Image by_pixel = image;
            for (int y = 0; y < k.height; ++y)
                for (int x = 0; x < k.width; ++x)
                    blur_ramp_pixel(k.ramp, geometry, image, vertical, by_pixel, x, y);
            CHECK(std::memcmp(by_pixel.data.data(), scalar.data.data(),
                              scalar.data.size() * sizeof(float)) == 0);
        }
    }
}

TEST_CASE("VP blur: the table holds each pixel's sigma and a, eight pixels at a time or one") {
    // fractional gazes (their subtractions round), rows that end in a partial group, the fovea,
    // the ramp and the constant part, a gaze off screen
    const BlurRampGeometry geometries[] = {{93, 41, {30.37f, 17.81f}, 3.3f, 1.7f},
                                           {64, 20, {-6.6f, 10.2f}, 3.0f, 1.0f},
                                           {37, 53, {18.5f, 26.5f}, 7.1f, 0.3f}};
    for (const BlurRampGeometry& g : geometries) {
        INFO(g.screen_width << "x" << g.screen_height);
        for (const bool simd : {true, false}) {
            set_simd_allowed(simd);
            const BlurRampTable table = blur_ramp_table(BlurRamp{0.7f, 9.0f}, g);
            set_simd_allowed(true);
            int ramped = 0;
            for (int y = 0; y < g.screen_height; ++y)
                for (int x = 0; x < g.screen_width; ++x) {
                    const float sigma =
                        blur_ramp_sigma_px(BlurRamp{0.7f, 9.0f}, g, pixel_centre(x, y));
                    const float a = blur_ramp_radius(sigma) > 0
                                        ? dm::exp(-1.0f / (2.0f * sigma * sigma))
                                        : 0.0f;
                    REQUIRE(std::bit_cast<std::uint32_t>(table.sigma_a.at(x, y, 0)) ==
                            std::bit_cast<std::uint32_t>(sigma));
                    REQUIRE(std::bit_cast<std::uint32_t>(table.sigma_a.at(x, y, 1)) ==
                            std::bit_cast<std::uint32_t>(a));
                    ramped += sigma > 0.0f && sigma < 0.7f * g.scale;
                }
            CHECK(ramped > 50);
        }
    }
}

TEST_CASE("VP blur: a table is refused for another geometry") {
    const BlurRampGeometry geometry{40, 20, {10.0f, 10.0f}, 3.0f, 1.0f};
    BlurRampGeometry moved = geometry;
    moved.gaze.x += 1.0f;
    const BlurRampTable table = blur_ramp_table(BlurRamp{}, moved);
    CHECK(table.made_for(BlurRamp{}, moved));
    CHECK_FALSE(table.made_for(BlurRamp{}, geometry));
    CHECK_THROWS_WITH_AS(
        blur_ramp_horizontal(BlurRamp{}, geometry, random_image(40, 20, 3, 2), true, &table),
        doctest::Contains("another ramp or geometry"), Error);
}
