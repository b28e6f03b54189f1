// The Visual-Polar map (ref/visual_polar/map.h, SPEC §5.3): P5's figures for 1280x1440
// (853x960, 12.0 % clipped, 60.9 % fewer texels than pixels), round trips at every texel for
// several gazes, P^-1 inverts P, and the texel density outside the fovea follows the acuity model.
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>

#include "ref/visual_polar/map.h"
#include "tests/core/build_speed.h"

using namespace fovref;

TEST_CASE(
    "visual-polar: P5's 1280x1440 buffer is 853x960 with 12.0% of its texels clipped and "
    "60.9% fewer unclipped texels than pixels") {
    const glm::ivec2 size = visual_polar_buffer_size(1280, 1440);
    CHECK(size == glm::ivec2(853, 960));
    const VisualPolarMap m = make_visual_polar_map(1280, 1440, {640.0f, 720.0f}, 853, 960);
    CHECK(m.fovea_columns == 205);
    const VisualPolarCounts c = vp_count_texels(m);
    const double clipped = 100.0 * static_cast<double>(c.clipped) / static_cast<double>(c.texels);
    const double fewer =
        100.0 * (1.0 - static_cast<double>(c.texels - c.clipped) / (1280.0 * 1440.0));
    MESSAGE("clipped " << clipped << "%, unclipped texels " << fewer << "% fewer than pixels, "
                       << c.off_screen << " off screen, " << c.traced << " traced");
    CHECK(clipped == doctest::Approx(12.0).epsilon(0.005));
    CHECK(fewer == doctest::Approx(60.9).epsilon(0.002));
    CHECK(c.traced + c.off_screen + c.clipped == c.texels);
}

TEST_CASE(
    "visual-polar: P^-1 inverts P, P is continuous to 0.1% at u0 and reaches the "
    "farthest corner at u = 1") {
    for (int k = 0; k <= 1000; ++k) {
        const float u = static_cast<float>(k) / 1000.0f;
        CHECK(vp_cdf(vp_inverse_cdf(u)) == doctest::Approx(u).epsilon(1e-5).scale(1.0));
    }
    CHECK(vp_inverse_cdf(vp_u0) == doctest::Approx(18.64 * std::sqrt(0.0965)).epsilon(1e-3));
    const VisualPolarMap m = make_visual_polar_map(1280, 720, {100.0f, 100.0f}, 853, 480);
    CHECK(vp_column_radius(m, m.width - 1) < std::hypot(1180.0f, 620.0f));
    CHECK(m.scale * vp_inverse_cdf(1.0f) == doctest::Approx(std::hypot(1180.0, 620.0)));
}

TEST_CASE("visual-polar: forward(inverse(texel)) is the texel centre for every texel and gaze") {
    for (const glm::vec2& gaze : {glm::vec2(640.0f, 360.0f), glm::vec2(0.0f, 0.0f),
                                  glm::vec2(1279.0f, 719.5f), glm::vec2(-300.0f, 900.0f)}) {
        const VisualPolarMap m = make_visual_polar_map(1280, 720, gaze, 320, 240);
        double worst_u = 0.0, worst_v = 0.0;
        for (int i = 0; i < m.width; ++i)
            for (int j = 0; j < m.height; ++j) {
                glm::vec2 p;
                if (!vp_inverse(m, i, j, p)) {
                    CHECK(j >= vp_column_rows(m, i));
                    continue;
                }
                const glm::vec2 uv = vp_forward(m, p);
                worst_u = std::max(worst_u, std::fabs(uv.x - (i + 0.5)));
                worst_v = std::max(worst_v, std::fabs(uv.y - (j + 0.5)));
            }
        CAPTURE(gaze.x);
        CAPTURE(gaze.y);
        MESSAGE("round trip: max |du| " << worst_u << ", |dv| " << worst_v << " texels");
        // float radii up to ~1500 px and the bisection's float resolution: about 1e-4 texel
        CHECK(worst_u < 1e-3);
        CHECK(worst_v < 1e-3);
    }
}

TEST_CASE(
    "visual-polar: outside the fovea the texel density follows the acuity model, inside "
    "it is above one sample per pixel") {
    const VisualPolarMap m = make_visual_polar_map(1280, 1440, {640.0f, 720.0f}, 853, 960);
    // Texels per pixel^2 at column i: h / (2 pi r dr/di); the model degree of r is r / s.
    double lo = 1e30, hi = 0.0;
    for (int i = m.fovea_columns + 1; i < m.width - 1; ++i) {
        const double r = vp_column_radius(m, i);
        const double dr = 0.5 * (vp_column_radius(m, i + 1) - vp_column_radius(m, i - 1));
        const double density = m.height / (2.0 * 3.14159265358979 * r * dr);
        const double ratio = density / vp_acuity(static_cast<float>(r / m.scale));
        lo = std::min(lo, ratio);
        hi = std::max(hi, ratio);
    }
    MESSAGE("density / m(e) outside the fovea: " << lo << " .. " << hi);
    // P is a polynomial fit of the model's inverse CDF: the ratio stays within 3% (bound 5%)
    CHECK(hi / lo < 1.05);
    for (int i = 0; i < m.fovea_columns; ++i) {
        const double r = vp_column_radius(m, i);
        const double dr = static_cast<double>(m.fovea_radius) / m.fovea_columns;
        const double density = vp_column_rows(m, i) / (2.0 * 3.14159265358979 * r * dr);
        CHECK(density > 1.0);
    }
}

TEST_CASE("visual-polar: P^-1 from the table of dyadic midpoints equals the plain bisection") {
    // The plain bisection on [0, 1] (SPEC §5.3): the table only replaces P at its first 16
    // midpoints, so every result must have the same bits.
    const auto plain = [](float e) {
        if (!(e > 0.0f)) return 0.0f;
        if (e >= vp_inverse_cdf(1.0f)) return 1.0f;
        float lo = 0.0f, hi = 1.0f;
        for (int step = 0; step < 64; ++step) {
            const float mid = 0.5f * (lo + hi);
            if (mid == lo || mid == hi) break;
            (vp_inverse_cdf(mid) < e ? lo : hi) = mid;
        }
        return 0.5f * (lo + hi);
    };
    int checked = 0;
    for (float e = 1e-6f; e < 81.0f; e = e * 1.0007f + 1e-7f, ++checked)
        REQUIRE(vp_cdf(e) == plain(e));
    // and at the table's own values (ties with the midpoints)
    for (int k = 0; k <= 65536; k += 7, ++checked) {
        const float e = vp_inverse_cdf(static_cast<float>(k) / 65536.0f);
        REQUIRE(vp_cdf(e) == plain(e));
        REQUIRE(vp_cdf(std::nextafter(e, 0.0f)) == plain(std::nextafter(e, 0.0f)));
    }
    CHECK(checked > 20000);
    // The search after the table (a guess moved float by float): e = P(u) at arbitrary floats u
    // (ties with a float the bisection may visit, plateaus of P) and the floats around it
    std::uint32_t state = 12345u;
    for (int n = 0; n < 20000; ++n) {
        state = state * 1664525u + 1013904223u;
        const float u = static_cast<float>(state >> 8) * 0x1p-24f;
        const float e = vp_inverse_cdf(u);
        for (const float x : {e, std::nextafter(e, 0.0f), std::nextafter(e, 100.0f)}) {
            REQUIRE(vp_cdf(x) == plain(x));
            REQUIRE(vp_cdf_bisection(x) == plain(x));
        }
    }
}

// vp_cdf's search after the table relies on P being non-decreasing over the floats of [0, 1]:
// checked at every float in optimised builds (1.07e9 floats, about 6 s), at every 61st in
// others.
TEST_CASE("visual-polar: P in float is non-decreasing over the floats of [0, 1]") {
    constexpr std::uint32_t stride = test::slow_build ? 61 : 1;
    const std::uint32_t one = std::bit_cast<std::uint32_t>(1.0f);
    float previous = vp_inverse_cdf(0.0f);
    std::int64_t decreases = 0, checked = 0;
    for (std::uint32_t bits = 1; bits <= one; bits += stride, ++checked) {
        // u and the float before it (the pair the property is about)
        const float u = std::bit_cast<float>(bits);
        if (stride > 1) previous = vp_inverse_cdf(std::bit_cast<float>(bits - 1));
        const float p = vp_inverse_cdf(u);
        decreases += p < previous;
        previous = p;
    }
    CHECK(checked > 17000000);
    CHECK(decreases == 0);
    // the branch point: the square root below u0, the polynomial above
    CHECK(vp_inverse_cdf(std::nextafter(vp_u0, 1.0f)) >= vp_inverse_cdf(vp_u0));
}

TEST_CASE("visual-polar: vp_wrap_row is j mod rows, from 0 to rows - 1, for every j") {
    for (const int rows : {1, 2, 7, 480})
        for (int j = -3 * rows - 2; j <= 3 * rows + 2; ++j) {
            INFO(j << " mod " << rows);
            CHECK(vp_wrap_row(j, rows) == ((j % rows) + rows) % rows);
        }
    CHECK(vp_wrap_row(std::numeric_limits<int>::min(), 7) ==
          ((std::numeric_limits<int>::min() % 7) + 7) % 7);
    // vp_column_rows: h beyond the fovea, the clip's inside (the inline shortcut and the fovea's)
    VisualPolarMap m = make_visual_polar_map(320, 180, {160.0f, 90.0f}, 213, 120);
    m.staircase_block = 32;
    m.staircase_offset = 5;
    for (int i = 0; i < m.width; ++i)
        CHECK(vp_column_rows(m, i) ==
              (i >= m.fovea_columns ? m.height : vp_fovea_column_rows(m, i)));
    CHECK(vp_fovea_column_rows(m, m.fovea_columns) == m.height);
}
