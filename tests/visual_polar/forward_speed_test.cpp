// The forward map in lanes (ref/visual_polar/map_avx.h) gives vp_forward_angle's bits: points all
// around gazes inside and outside the screen, at every distance from the gaze (the fovea, its
// edge, the periphery, beyond the farthest corner), on the gaze's row and column and on the gaze
// itself, tiny offsets whose squares underflow, huge, infinite and NaN coordinates, and every
// mix of lanes asked for.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "ref/core/simd.h"
#include "ref/visual_polar/map_avx.h"
#include "ref/visual_polar/resolve.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

namespace {

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// A point near the gaze's ray at distance r and angle a (radians, through binary64 libm: test
// input only), or now and then a hostile one.
glm::vec2 test_point(test::SplitMix64& rng, const VisualPolarMap& m, float r_max) {
    const float inf = std::numeric_limits<float>::infinity();
    switch (rng.below(48)) {
        case 0: return m.gaze;                                             // dx = dy = 0
        case 1: return {m.gaze.x, m.gaze.y + rng.uniform(-r_max, r_max)};  // dx = 0
        case 2: return {m.gaze.x + rng.uniform(-r_max, r_max), m.gaze.y};  // dy = 0
        case 3: return {rng.below(2) ? 3e19f : -3e19f, 10.0f};             // dx dx overflows
        case 4: return {rng.below(2) ? inf : std::numeric_limits<float>::quiet_NaN(), 5.0f};
        case 5: {  // exactly on the fovea's edge, or a float away
            const float r = m.fovea_radius * (rng.below(2) ? 1.0f : 1.0000001f);
            return {m.gaze.x + r, m.gaze.y + 1e-3f};
        }
        case 6:  // tiny offsets: squares that underflow (subnormal with the gaze at 0, 0)
            return {m.gaze.x + (rng.below(2) ? 3e-39f : -2e-20f), m.gaze.y + 1e-38f};
        default: break;
    }
    const double a = rng.uniform(0.0f, 6.2831853f);
    const float r =
        rng.below(3) == 0 ? rng.uniform(0.0f, 1.2f * m.fovea_radius) : rng.uniform(0.0f, r_max);
    return {m.gaze.x + static_cast<float>(r * std::cos(a)),
            m.gaze.y + static_cast<float>(r * std::sin(a))};
}

}  // namespace

TEST_CASE("visual-polar forward map in lanes: vp_forward_angle's bits") {
    if (!cpu_has_avx2()) MESSAGE("no AVX2 on this CPU: both runs take the reference");
    test::SplitMix64 rng(17);
    const glm::vec2 gazes[] = {
        {640.0f, 720.0f}, {10.5f, 1300.25f}, {-200.0f, 50.0f}, {1279.9f, 0.1f}, {0.0f, 0.0f}};
    std::int64_t compared = 0, fovea = 0, periphery = 0, in_lanes_fovea = 0, in_lanes_periphery = 0;
    for (const glm::vec2& gaze : gazes) {
        CAPTURE(gaze.x);
        const VisualPolarMap m = make_visual_polar_map(1280, 1440, gaze, 853, 960);
        const float r_max = 1.2f * m.scale * vp_inverse_cdf(1.0f);
        for (int group = 0; group < 6000; ++group) {
            alignas(32) float x[8], y[8];
            for (int l = 0; l < 8; ++l) {
                const glm::vec2 p = test_point(rng, m, r_max);
                x[l] = p.x, y[l] = p.y;
            }
            const int lane_bits = group % 7 == 0 ? static_cast<int>(rng.below(256)) : 255;
            float u[8], t[8];
            for (int l = 0; l < 8; ++l) u[l] = t[l] = -7.0f;  // lanes not asked for keep these
            const int in_lanes = vp_forward_angle_lanes(m, x, y, lane_bits, u, t);
            REQUIRE((in_lanes & ~lane_bits) == 0);
            for (int l = 0; l < 8; ++l) {
                if (!(lane_bits >> l & 1)) {
                    REQUIRE(u[l] == -7.0f);
                    REQUIRE(t[l] == -7.0f);
                    continue;
                }
                const glm::vec2 ut = vp_forward_angle(m, {x[l], y[l]});
                CAPTURE(x[l]);
                CAPTURE(y[l]);
                REQUIRE((same_bits(u[l], ut.x) || (std::isnan(u[l]) && std::isnan(ut.x))));
                REQUIRE((same_bits(t[l], ut.y) || (std::isnan(t[l]) && std::isnan(ut.y))));
                ++compared;
                const float dx = x[l] - gaze.x, dy = y[l] - gaze.y;
                // P jumps at u0 (its branches differ there): a point whose P^-1 lies in the
                // table bracket [k, k + 1] / 65536 around u0 is found by the bisection, beyond
                // the lanes' 8 moves from any guess
                const float jump_end = vp_inverse_cdf(std::ceil(vp_u0 * 65536.0f) / 65536.0f);
                if (dx != 0.0f && dy != 0.0f && std::isfinite(dx * dx + dy * dy) &&
                    !(std::sqrt(dx * dx + dy * dy) >= m.fovea_radius &&
                      std::sqrt(dx * dx + dy * dy) / m.scale <= jump_end)) {
                    const bool inner = std::sqrt(dx * dx + dy * dy) < m.fovea_radius;
                    ++(inner ? fovea : periphery);
                    if (in_lanes >> l & 1) ++(inner ? in_lanes_fovea : in_lanes_periphery);
                }
            }
        }
    }
    MESSAGE(compared << " points compared: " << fovea << " in the fovea (" << in_lanes_fovea
                     << " in lanes), " << periphery << " beyond (" << in_lanes_periphery
                     << " in lanes)");
    CHECK(fovea > 20000);
    CHECK(periphery > 60000);
    if (cpu_has_avx2()) {  // the lanes settle every ordinary point: the reference is the exception
        CHECK(in_lanes_fovea == fovea);
        CHECK(in_lanes_periphery == periphery);
    }
}

TEST_CASE("visual-polar forward map in lanes: log-polar maps and --scalar take the reference") {
    const VisualPolarMap m = make_visual_polar_map(320, 180, {100.0f, 90.0f}, 213, 120);
    alignas(32) const float x[8] = {0.5f, 10.0f, 100.0f, 300.0f, 319.5f, 150.0f, 99.0f, 101.0f};
    alignas(32) const float y[8] = {0.5f, 170.0f, 90.0f, 10.0f, 179.5f, 60.0f, 91.0f, 89.0f};
    for (const bool simd : {true, false}) {
        set_simd_allowed(simd);
        float u[8], t[8];
        vp_forward_angle_lanes(m, x, y, 255, u, t);
        set_simd_allowed(true);
        for (int l = 0; l < 8; ++l) {
            const glm::vec2 ut = vp_forward_angle(m, {x[l], y[l]});
            CHECK(same_bits(u[l], ut.x));
            CHECK(same_bits(t[l], ut.y));
        }
    }
    LogPolarParams params;
    const VisualPolarMap lp =
        vp_log_polar_map(make_log_polar_map(params, 320, 180, {100.0f, 90.0f}, 1000.0f));
    float u[8], t[8];
    vp_forward_angle_lanes(lp, x, y, 255, u, t);
    for (int l = 0; l < 8; ++l) {
        const glm::vec2 ut = vp_forward_angle(lp, {x[l], y[l]});
        CHECK(same_bits(u[l], ut.x));
        CHECK(same_bits(t[l], ut.y));
    }
}

TEST_CASE("visual-polar forward table (lanes, a row's logarithms at once): the per-pixel bits") {
    // Screens whose rows end in a group of fewer than eight, gazes inside and outside them, and
    // a staircase clip; each entry against vp_polar_pixel and vp_mip_level.
    const struct {
        int width, height;
        glm::vec2 gaze;
        int staircase;
    } cases[] = {{125, 61, {60.3f, 30.0f}, 0},
                 {203, 97, {-40.0f, 120.0f}, 8},
                 {64, 64, {32.0f, 32.0f}, 0},
                 {37, 290, {18.5f, 2.5f}, 8}};  // the gaze on a pixel centre: r = 0
    for (const auto& c : cases) {
        CAPTURE(c.width);
        VisualPolarMap map =
            make_visual_polar_map(c.width, c.height, c.gaze, c.width * 2 / 3, c.height * 2 / 3);
        map.staircase_block = c.staircase;
        std::int64_t differ = 0;
        for (const bool simd : {true, false}) {
            set_simd_allowed(simd);
            const VpForwardTable table = vp_forward_table(map);
            set_simd_allowed(true);
            for (int y = 0; y < c.height; ++y)
                for (int x = 0; x < c.width; ++x) {
                    float u = 0.0f, r = 0.0f, theta = 0.0f;
                    vp_polar_pixel(map, x, y, u, r, theta);
                    const float* p = &table.polar.data[table.polar.index(x, y)];
                    differ += !same_bits(p[0], u) + !same_bits(p[1], r) + !same_bits(p[2], theta);
                    const VpColumns rho = vp_rho_columns(map.width, u);
                    const float* level = &table.levels.data[table.levels.index(x, y)];
                    for (int k = 0; k < 2; ++k) {
                        const int n = vp_column_rows(map, k == 0 ? rho.i0 : rho.i1);
                        differ += !same_bits(level[2 * k], static_cast<float>(n)) +
                                  !same_bits(level[2 * k + 1], vp_mip_level(n, r));
                    }
                }
        }
        CHECK(differ == 0);
    }
}
