// The kernel log-polar map (ref/log_polar/map.h, kernel.h; SPEC §5.1-5.2): buffer sizes
// computed by hand, the map against an independent binary64 evaluation of the formulas (libm),
// forward-inverse round trips at every texel of every preset for several gaze points, the
// kernels, and extreme parameters.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "ref/core/error.h"
#include "ref/log_polar/map.h"
#include "ref/log_polar/params.h"
#include "ref/modes/modes.h"
#include "ref/scene/procedural.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

namespace {

// The centre (x + 1/2, y + 1/2) of pixel or texel (x, y).
glm::vec2 centre(int x, int y) {
    return {static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f};
}

LogPolarParams preset_params(const std::string& name) { return find_foveation_preset(name).map; }

// d_px of the default display model for a 40 degree camera: (H/2) / tan(20 degrees).
float display_distance(int height) {
    return static_cast<float>(height / 2.0 / std::tan(20.0 * M_PI / 180.0));
}

// The forward map in binary64 with libm, written from SPEC §5.1 independently of the code.
void forward_d(const LogPolarMap& m, double x, double y, double& u, double& v) {
    const double dx = x - m.gaze.x, dy = y - m.gaze.y;
    const double r = std::sqrt(dx * dx + dy * dy);
    // K is defined on [0, 1]: rho beyond R (an off-screen gaze) is clamped to 1.
    const double rho = std::min(1.0, std::log1p(r) / std::log1p(static_cast<double>(m.radius_max)));
    const double alpha = m.kernel.alpha;
    const double g = m.composite;
    u = m.width * (std::pow(rho, alpha) - g) / (1.0 - g);
    double theta = std::atan2(dy, dx);
    if (theta < 0) theta += 2 * M_PI;
    v = m.height * theta / (2 * M_PI);
}

// Angular distance on the wrapped axis.
double wrapped(double a, double b, double period) {
    const double d = std::fabs(a - b);
    return std::min(d, period - d);
}

}  // namespace

TEST_CASE("log-polar: buffer sizes of the presets at 1280x720, computed by hand") {
    // lp_aspect: h = round(sqrt(W H / lp_aspect) / sigma), w = round(h lp_aspect).
    // fov:   sqrt(921600 / 1.2) = 876.356 / 0.75 = 1168.47 -> 1168; 1168 * 1.2 = 1401.6 -> 1402
    // kfov:  sqrt(921600 / 0.7) = 1147.42 / 1.0 -> 1147; 1147 * 0.7 = 802.9 -> 803
    // cfov:  sqrt(921600 / 0.33) = 1671.15 / 1.4 = 1193.68 -> 1194; 1194 * 0.33 = 394.02 -> 394
    // ckfov: sqrt(921600 / 0.35) = 1622.69 / 1.3 = 1248.22 -> 1248; 1248 * 0.35 = 436.8 -> 437
    CHECK(log_polar_buffer_size(preset_params("fov"), 1280, 720) == BufferSize{1402, 1168});
    CHECK(log_polar_buffer_size(preset_params("kfov"), 1280, 720) == BufferSize{803, 1147});
    CHECK(log_polar_buffer_size(preset_params("cfov"), 1280, 720) == BufferSize{394, 1194});
    CHECK(log_polar_buffer_size(preset_params("ckfov"), 1280, 720) == BufferSize{437, 1248});
    // Without lp_aspect (Meng): w = round(W / sigma), h = round(H / sigma); 1280 / 1.8 = 711.1.
    LogPolarParams meng;
    meng.sigma = 1.8f;
    CHECK(log_polar_buffer_size(meng, 1280, 720) == BufferSize{711, 400});
    // Never below one texel.
    meng.sigma = 8.0f;
    CHECK(log_polar_buffer_size(meng, 1, 1) == BufferSize{1, 1});
}

TEST_CASE("log-polar: R, L, r_G and G of the presets") {
    const float d_px = display_distance(720);  // 989.09 px
    const LogPolarMap fov = make_log_polar_map(preset_params("fov"), 1280, 720, {640, 360}, d_px);
    CHECK(fov.radius_max == doctest::Approx(std::sqrt(1280.0 * 1280 + 720 * 720)).epsilon(1e-7));
    CHECK(fov.log_radius_max == doctest::Approx(std::log1p(1468.60)).epsilon(1e-6));
    CHECK(fov.gaze_radius == 0.0f);
    CHECK(fov.composite == 0.0f);
    // cfov: r_G = d_px tan(0.2) = 989.09 * 0.20271 = 200.50 px; G = ln(201.50) / ln(1469.60).
    const LogPolarMap cfov = make_log_polar_map(preset_params("cfov"), 1280, 720, {640, 360}, d_px);
    CHECK(cfov.gaze_radius == doctest::Approx(989.0919 * std::tan(0.2)).epsilon(1e-6));
    CHECK(cfov.composite ==
          doctest::Approx(std::log1p(cfov.gaze_radius) / std::log1p(1468.6025)).epsilon(1e-6));
    // ckfov: G = (l(r_G) / L)^2.
    const LogPolarMap ckfov =
        make_log_polar_map(preset_params("ckfov"), 1280, 720, {640, 360}, d_px);
    const double rho_g = std::log1p(989.0919 * std::tan(0.15)) / std::log1p(1468.6025);
    CHECK(ckfov.composite == doctest::Approx(rho_g * rho_g).epsilon(1e-6));
    // corners: the farthest corner from a gaze at (100, 50) is (1280, 720).
    LogPolarParams corners = preset_params("fov");
    corners.radius = RadiusMode::corners;
    const LogPolarMap c = make_log_polar_map(corners, 1280, 720, {100, 50}, d_px);
    CHECK(c.radius_max == doctest::Approx(std::hypot(1180.0, 670.0)).epsilon(1e-7));
}

TEST_CASE("log-polar: the forward map agrees with a binary64 evaluation of SPEC §5.1") {
    // Every 7th pixel centre of a 320x180 screen for each preset and gaze; the float map's error
    // is at most a few ulp of L and of the angle: bounded here by 2e-3 texels in u and v.
    const float d_px = display_distance(180);
    const glm::vec2 gazes[] = {{160, 90}, {0, 0}, {320, 90}, {-50, 400}, {161.3f, 2.7f}};
    for (const FoveationPreset& preset : foveation_presets())
        for (const glm::vec2& gaze : gazes) {
            const LogPolarMap m = make_log_polar_map(preset.map, 320, 180, gaze, d_px);
            double worst_u = 0.0, worst_v = 0.0;
            for (int y = 0; y < 180; y += 7)
                for (int x = 0; x < 320; x += 7) {
                    const glm::vec2 p = centre(x, y);
                    const glm::vec2 uv = lp_forward(m, p);
                    double u = 0, v = 0;
                    forward_d(m, p.x, p.y, u, v);
                    worst_u = std::max(worst_u, std::fabs(uv.x - u));
                    worst_v = std::max(worst_v, wrapped(uv.y, v, m.height));
                    REQUIRE(uv.y >= 0.0f);
                    REQUIRE(uv.y < static_cast<float>(m.height));
                }
            INFO(preset.name, " gaze ", gaze.x, ",", gaze.y);
            CHECK(worst_u < 2e-3);
            CHECK(worst_v < 2e-3);
        }
}

TEST_CASE("log-polar: forward(inverse(texel centre)) round trip at every texel") {
    // For every preset and gaze (centre, each corner, an edge, off screen), every texel centre
    // (i + 1/2, j + 1/2) is mapped to the screen and back. The screen point is a float: its
    // rounding, e = ulp(max(|x|, |y|)), moves it by up to e/2 per axis, which is a large angle
    // next to the gaze point. So the error grows as 1/r towards the gaze and with the gaze's
    // distance from the origin:
    //   |du| <= 2e-3 + 2 e w K'max / ((1 + r) L (1 - G))     (K'max = alpha)
    //   |dv| <= 2e-3 + 2 e h / (2 pi r)
    // Away from the gaze the map itself is accurate to a few 1e-4 texels. Measured at 320x180
    // with the gaze at the centre: u 4.4e-4, v 0.043 texels, the latter in the first column,
    // where r = 0.0085 px and e = 1.5e-5.
    const float d_px = display_distance(180);
    const glm::vec2 gazes[] = {{160, 90},  {0, 0},   {320, 0},   {0, 180},
                               {320, 180}, {160, 0}, {-200, 90}, {5000, -3000}};
    for (const FoveationPreset& preset : foveation_presets())
        for (const glm::vec2& gaze : gazes) {
            const LogPolarMap m = make_log_polar_map(preset.map, 320, 180, gaze, d_px);
            double worst_u = 0.0, worst_v = 0.0, worst_u_far = 0.0, worst_v_far = 0.0;
            for (int j = 0; j < m.height; ++j)
                for (int i = 0; i < m.width; ++i) {
                    const glm::vec2 uv = centre(i, j);
                    const glm::vec2 p = lp_inverse(m, uv);
                    REQUIRE(std::isfinite(p.x));
                    REQUIRE(std::isfinite(p.y));
                    const glm::vec2 back = lp_forward(m, p);
                    const double du = std::fabs(back.x - uv.x);
                    const double dv = wrapped(back.y, uv.y, m.height);
                    const double e =
                        std::nextafter(std::max(std::fabs(p.x), std::fabs(p.y)), INFINITY) -
                        std::max(std::fabs(p.x), std::fabs(p.y));
                    const double r = gaze_distance(m.gaze, p);
                    const double bound_u =
                        2e-3 + 2 * e * m.width * m.kernel.alpha /
                                   ((1 + r) * m.log_radius_max * (1 - m.composite));
                    const double bound_v = 2e-3 + 2 * e * m.height / (2 * M_PI * r);
                    if (du > bound_u || dv > bound_v) {
                        INFO(preset.name, " gaze ", gaze.x, ",", gaze.y, " texel ", i, ",", j,
                             " r ", r, ": du ", du, " (bound ", bound_u, "), dv ", dv, " (bound ",
                             bound_v, ")");
                        CHECK(false);
                    }
                    worst_u = std::max(worst_u, du);
                    worst_v = std::max(worst_v, dv);
                    if (r > 10.0) {
                        worst_u_far = std::max(worst_u_far, du);
                        worst_v_far = std::max(worst_v_far, dv);
                    }
                }
            // More than 10 px from the gaze point the round trip is within 2e-3 texels.
            INFO(preset.name, " gaze ", gaze.x, ",", gaze.y, ": worst u ", worst_u, ", v ", worst_v,
                 "; beyond 10 px: u ", worst_u_far, ", v ", worst_v_far);
            CHECK(worst_u_far < 2e-3);
            CHECK(worst_v_far < 2e-3);
        }
}

TEST_CASE("log-polar: inverse(forward(pixel centre)) returns to the pixel centre") {
    // Screen points outside the gaze circle (composite) and within R: back within 1e-3 px.
    const float d_px = display_distance(180);
    for (const FoveationPreset& preset : foveation_presets()) {
        const LogPolarMap m = make_log_polar_map(preset.map, 320, 180, {100.25f, 70.5f}, d_px);
        double worst = 0.0;
        for (int y = 0; y < 180; ++y)
            for (int x = 0; x < 320; ++x) {
                const glm::vec2 p = centre(x, y);
                if (inside_gaze_circle(m, p)) continue;
                const glm::vec2 back = lp_inverse(m, lp_forward(m, p));
                worst = std::max(worst, static_cast<double>(gaze_distance(p, back)));
            }
        INFO(preset.name, ": worst ", worst, " px");
        CHECK(worst < 1e-3);
    }
}

TEST_CASE("log-polar: analytic inverse of the classic map (alpha = 1, no gaze buffer)") {
    // r(i) = (1 + R)^((i + 1/2) / w) - 1 and theta(j) = 2 pi (j + 1/2) / h.
    LogPolarParams params;
    params.sigma = 1.0f;
    params.lp_aspect = 1.0f;
    const LogPolarMap m = make_log_polar_map(params, 64, 64, {32, 32}, 100.0f);
    REQUIRE(m.width == 64);
    for (int i = 0; i < m.width; i += 9)
        for (int j = 0; j < m.height; j += 5) {
            const glm::vec2 p = lp_inverse(m, centre(i, j));
            const double r = std::pow(1.0 + m.radius_max, (i + 0.5) / m.width) - 1.0;
            const double theta = 2 * M_PI * (j + 0.5) / m.height;
            CHECK(p.x == doctest::Approx(32 + r * std::cos(theta)).epsilon(1e-5));
            CHECK(p.y == doctest::Approx(32 + r * std::sin(theta)).epsilon(1e-5));
        }
    // The angle's convention: v grows from +x towards +y (down the screen); -0 and the negative
    // x axis land on the right side of the wrap.
    CHECK(lp_forward(m, {40, 32}).y == 0.0f);
    CHECK(lp_forward(m, {32, 40}).y == doctest::Approx(16.0));
    CHECK(lp_forward(m, {24, 32}).y == doctest::Approx(32.0));
    CHECK(lp_forward(m, {32, 24}).y == doctest::Approx(48.0));
    CHECK(lp_forward(m, {24, 32.0f - 1e-6f}).y < 64.0f);
    // The gaze point itself maps to u = 0.
    CHECK(lp_forward(m, {32, 32}).x == 0.0f);
}

TEST_CASE("log-polar: texel status: off screen, traced, the composite circle") {
    const float d_px = display_distance(180);
    const LogPolarMap m = make_log_polar_map(preset_params("cfov"), 320, 180, {160, 90}, d_px);
    const LpInverseTable table = lp_inverse_table(m);
    std::int64_t traced = 0, off = 0, inside = 0;
    for (int j = 0; j < m.height; ++j)
        for (int i = 0; i < m.width; ++i) {
            glm::vec2 p{0.0f};
            const TexelStatus s = lp_texel_status(m, table, i, j, p);
            // Independent check of the status from the screen point.
            const bool on = p.x >= 0 && p.x < 320 && p.y >= 0 && p.y < 180;
            if (s == TexelStatus::traced) {
                ++traced;
                CHECK(on);
                CHECK(gaze_distance(m.gaze, p) >= m.gaze_radius);
            } else if (s == TexelStatus::off_screen) {
                ++off;
                CHECK_FALSE(on);
            } else {
                ++inside;
            }
        }
    CHECK(traced + off == static_cast<std::int64_t>(m.width) * m.height);
    CHECK(inside == 0);  // G < 1: every texel maps outside the circle
    CHECK(traced > 0);
    CHECK(off > 0);  // the corners of the circle of radius R = diagonal lie off screen
}

TEST_CASE("log-polar: a gaze circle covering R leaves no texel to trace and no NaN") {
    // a_G = 1.5 rad on a 64x36 screen: r_G = 49.4 * tan(1.5) = 699 px > R = 73.4 px: G = 1.
    LogPolarParams params = preset_params("cfov");
    params.gaze_angle = 1.5f;
    const LogPolarMap m = make_log_polar_map(params, 64, 36, {32, 18}, display_distance(36));
    CHECK(m.composite == 1.0f);
    const LpInverseTable table = lp_inverse_table(m);
    for (int j = 0; j < m.height; ++j)
        for (int i = 0; i < m.width; ++i) {
            glm::vec2 p{0.0f};
            CHECK(lp_texel_status(m, table, i, j, p) != TexelStatus::traced);
        }
    const glm::vec2 uv = lp_forward(m, {200, 200});
    CHECK(std::isfinite(uv.x));
    CHECK(std::isfinite(uv.y));
}

TEST_CASE("log-polar: extreme parameters stay finite and bounded") {
    // sigma 0.25..8, alpha 1..8, lp_aspect 0.1..10, gaze on and off screen: every texel's inverse
    // is finite, every forward lookup lies in [0, h) on v, and buffer sizes follow the formula.
    const float sigmas[] = {0.25f, 1.0f, 8.0f};
    const float alphas[] = {1.0f, 2.5f, 8.0f};
    const float aspects[] = {0.0f, 0.1f, 10.0f};
    const glm::vec2 gazes[] = {{20, 12}, {-1000, 5}, {40, 24}};
    for (const float sigma : sigmas)
        for (const float alpha : alphas)
            for (const float aspect : aspects)
                for (const glm::vec2& gaze : gazes) {
                    LogPolarParams p;
                    p.sigma = sigma;
                    p.kernel = power_kernel(alpha);
                    p.lp_aspect = aspect;
                    p.gaze_angle = 0.3f;
                    const LogPolarMap m = make_log_polar_map(p, 40, 24, gaze, 30.0f);
                    REQUIRE(m.width >= 1);
                    REQUIRE(m.height >= 1);
                    for (int j = 0; j < m.height; ++j)
                        for (int i = 0; i < m.width; ++i) {
                            const glm::vec2 s = lp_inverse(m, centre(i, j));
                            REQUIRE(std::isfinite(s.x));
                            REQUIRE(std::isfinite(s.y));
                        }
                    for (int y = 0; y < 24; y += 3)
                        for (int x = 0; x < 40; x += 3) {
                            const glm::vec2 uv = lp_forward(m, centre(x, y));
                            REQUIRE(std::isfinite(uv.x));
                            REQUIRE(uv.y >= 0.0f);
                            REQUIRE(uv.y < static_cast<float>(m.height));
                        }
                }
    // 1x1 and 16384x16384 screens.
    LogPolarParams fov = preset_params("fov");
    const LogPolarMap tiny = make_log_polar_map(fov, 1, 1, {0.5f, 0.5f}, 1.0f);
    CHECK(tiny.width == 1);
    CHECK(tiny.height == 1);
    // Its one texel's centre (u = 1/2: r = sqrt(1 + sqrt(2)) - 1 = 0.554 px at theta = pi) lies
    // at (-0.054, 0.5): off screen, so nothing is traced (pass 2 counts the pixel untraced).
    glm::vec2 p{0.0f};
    CHECK(lp_texel_status(tiny, lp_inverse_table(tiny), 0, 0, p) == TexelStatus::off_screen);
    CHECK(p.x == doctest::Approx(0.5 - (std::sqrt(1 + std::sqrt(2.0)) - 1)).epsilon(1e-5));
    // 16384x16384: cfov's buffer is 6723x20372 (h = round(16384 / sqrt(0.33) / 1.4)); a sample
    // of texels maps to finite points. fov's would be 23930x19942 texels (1.8x the screen),
    // beyond the image-size limit: refused with the parameters named, not allocated.
    const LogPolarMap huge =
        make_log_polar_map(preset_params("cfov"), 16384, 16384, {8192, 8192}, 20000.0f);
    CHECK(huge.width == 6723);
    CHECK(huge.height == 20372);
    for (int j = 0; j < huge.height; j += 997)
        for (int i = 0; i < huge.width; i += 331) {
            const glm::vec2 s = lp_inverse(huge, centre(i, j));
            REQUIRE(std::isfinite(s.x));
            REQUIRE(std::isfinite(s.y));
            const glm::vec2 uv = lp_forward(huge, s);
            CHECK(std::fabs(uv.x - centre(i, j).x) < 0.01f);
        }
    CHECK(test::contains(test::error_message([&] {
                             make_log_polar_map(fov, 16384, 16384, {0, 0}, 1.0f);
                         }),
                         "23930x19942 texels, more than the limit"));
}

TEST_CASE("log-polar: bad parameters are refused with the parameter named") {
    LogPolarParams p;
    p.sigma = 0.0f;
    CHECK(test::contains(test::error_message([&] { log_polar_buffer_size(p, 64, 64); }),
                         "parameter 'sigma'"));
    p.sigma = 0.001f;  // a 64000x64000 buffer
    CHECK(test::contains(test::error_message([&] { log_polar_buffer_size(p, 64000, 64000); }),
                         "more than the limit"));
    p.sigma = 1.0f;
    p.lp_aspect = -1.0f;
    CHECK(test::contains(test::error_message([&] { log_polar_buffer_size(p, 64, 64); }),
                         "parameter 'lp_aspect'"));
    p.lp_aspect = 0.0f;
    p.gaze_angle = 2.0f;
    CHECK(test::contains(test::error_message([&] {
                             make_log_polar_map(p, 64, 64, {0, 0}, 50);
                         }),
                         "parameter 'gaze_angle'"));
    p.gaze_angle = 0.0f;
    CHECK(test::contains(test::error_message([&] {
                             make_log_polar_map(p, 64, 64, {NAN, 0}, 50);
                         }),
                         "gaze"));
}

TEST_CASE("kernel: x^alpha and its inverse, alpha = 1 is the identity") {
    const Kernel k1 = power_kernel(1.0f);
    CHECK(k1.identity());
    CHECK(kernel_forward(k1, 0.3f) == 0.3f);
    CHECK(kernel_inverse(k1, 0.3f) == 0.3f);
    const Kernel k3 = power_kernel(3.0f);
    CHECK(kernel_forward(k3, 0.5f) == 0.125f);
    CHECK(kernel_forward(k3, 0.0f) == 0.0f);
    CHECK(kernel_forward(k3, 1.0f) == 1.0f);
    CHECK(kernel_inverse(k3, 0.125f) == doctest::Approx(0.5).epsilon(1e-6));
    for (int k = 0; k <= 1000; ++k) {
        const float x = static_cast<float>(k) / 1000.0f;
        CHECK(std::fabs(kernel_inverse(k3, kernel_forward(k3, x)) - x) < 1e-6f);
    }
    // Clamped to [0, 1].
    CHECK(kernel_forward(k3, -0.5f) == 0.0f);
    CHECK(kernel_forward(k3, 2.0f) == 1.0f);
    CHECK(test::contains(test::error_message([] { power_kernel(0.5f); }), "alpha"));
    CHECK(test::contains(test::error_message([] { power_kernel(NAN); }), "alpha"));
}

TEST_CASE("kernel: Meng's polynomial, validated, inverted by bisection") {
    // K(x) = 0.25 x + 0.75 x^2: K(0.5) = 0.125 + 0.1875 = 0.3125.
    const Kernel k = polynomial_kernel({0.0f, 0.25f, 0.75f});
    CHECK(kernel_forward(k, 0.5f) == 0.3125f);
    CHECK(kernel_forward(k, 1.0f) == 1.0f);
    // The bisection ends within an ulp or two of the root (K' >= 0.25 here).
    for (int i = 0; i <= 1000; ++i) {
        const float x = static_cast<float>(i) / 1000.0f;
        const float back = kernel_inverse(k, kernel_forward(k, x));
        CHECK(std::fabs(back - x) <= 2.5e-7f);
    }
    // Closed-form root of 0.75 x^2 + 0.25 x - t = 0.
    const double t = 0.6;
    const double root = (-0.25 + std::sqrt(0.0625 + 3.0 * t)) / 1.5;
    CHECK(kernel_inverse(k, 0.6f) == doctest::Approx(root).epsilon(1e-6));
    // Refusals: beta_0, the sum, a negative slope, too few coefficients, NaN.
    CHECK(test::contains(test::error_message([] { polynomial_kernel({0.1f, 0.9f}); }), "beta_0"));
    CHECK(test::contains(test::error_message([] { polynomial_kernel({0.0f, 0.5f}); }), "sum to"));
    // K(x) = -0.5 x + 1.5 x^2: K'(0) = -0.5.
    CHECK(test::contains(test::error_message([] {
                             polynomial_kernel({0.0f, -0.5f, 1.5f});
                         }),
                         "K'(0) = -0.5 < 0"));
    CHECK(test::contains(test::error_message([] { polynomial_kernel({0.0f}); }), "1 <= n"));
    CHECK(test::contains(test::error_message([] {
                             polynomial_kernel({0.0f, NAN});
                         }),
                         "not a finite"));
}

TEST_CASE("kernel: Meng's sine and exponential kernels, their inverses and slopes") {
    // sin(x pi/2): K(1/2) = sin(pi/4) = 0.70710678, K'(x) = pi/2 cos(x pi/2): K'(0) = pi/2
    const Kernel s = named_kernel(KernelKind::sine);
    CHECK(kernel_forward(s, 0.5f) == doctest::Approx(0.70710678).epsilon(1e-6));
    CHECK(kernel_derivative(s, 0.0f) == doctest::Approx(1.57079633).epsilon(1e-6));
    CHECK(kernel_derivative(s, 1.0f) == doctest::Approx(0.0).epsilon(1e-6));
    // (e^x - 1)/(e - 1): K(1/2) = 0.64872127 / 1.71828183 = 0.37754067, K'(x) = e^x / (e - 1)
    const Kernel e = named_kernel(KernelKind::exponential);
    CHECK(kernel_forward(e, 0.5f) == doctest::Approx(0.37754067).epsilon(1e-6));
    CHECK(kernel_derivative(e, 0.0f) == doctest::Approx(0.58197671).epsilon(1e-6));
    for (const Kernel& k : {s, e}) {
        CHECK(kernel_forward(k, 0.0f) == 0.0f);
        CHECK(kernel_forward(k, 1.0f) == doctest::Approx(1.0).epsilon(1e-7));
        CHECK(kernel_forward(k, 2.0f) <= 1.0f);  // clamped
        float previous = -1.0f;
        for (int i = 0; i <= 1000; ++i) {
            const float x = static_cast<float>(i) / 1000.0f;
            const float y = kernel_forward(k, x);
            CHECK(y >= previous);  // monotone
            previous = y;
            CHECK(std::fabs(kernel_inverse(k, y) - x) <= 3e-4f);  // asin's slope at 1 is steep
        }
    }
    CHECK(kernel_text(s) == "sin(x pi/2)");
    // The mode parameter selects them, and refuses them with alpha or beta
    Params p;
    p.set("kernel", "sine");
    CHECK(parse_foveated_params(p, find_foveation_preset("kfov")).map.kernel.kind ==
          KernelKind::sine);
    p.set("kernel", "exp");
    CHECK(parse_foveated_params(p, find_foveation_preset("kfov")).map.kernel.kind ==
          KernelKind::exponential);
    p.set("alpha", "2");
    CHECK(test::contains(
        test::error_message([&] { parse_foveated_params(p, find_foveation_preset("kfov")); }),
        "takes no 'alpha'"));
    Params bad;
    bad.set("kernel", "cubic");
    CHECK(test::contains(
        test::error_message([&] { parse_foveated_params(bad, find_foveation_preset("kfov")); }),
        "parameter 'kernel'"));
}

TEST_CASE("log-polar: the factored inverse table gives lp_inverse's bits at every texel") {
    const float d_px = display_distance(180);
    for (const FoveationPreset& preset : foveation_presets())
        for (const glm::vec2& gaze : {glm::vec2{160, 90}, glm::vec2{-30.25f, 17}}) {
            const LogPolarMap m = make_log_polar_map(preset.map, 320, 180, gaze, d_px);
            const LpInverseTable table = lp_inverse_table(m);
            for (int j = 0; j < m.height; ++j)
                for (int i = 0; i < m.width; ++i) {
                    glm::vec2 p{0.0f};
                    lp_texel_status(m, table, i, j, p);
                    const glm::vec2 direct = lp_inverse(m, centre(i, j));
                    REQUIRE(std::memcmp(&p, &direct, sizeof p) == 0);
                }
        }
}

TEST_CASE(
    "log-polar: the rays Lund's presets trace at 1280x720 (Table 5.3), counted "
    "independently in binary64") {
    // cornell's viewing distance d_px = 360 / tan(20 deg), gaze at the centre. The traced
    // texels are those whose centre's inverse map lies on the screen (Lund eq. 3.8 in binary64
    // with libm's exp, cos, sin: t = G + (1 - G) u / w, r = exp(L t^(1/alpha)) - 1), plus the
    // gaze buffer's pixels inside r_G. The shares pin docs/foveation.md's table (151.9%, 62.8%,
    // 37.6%, 36.7%; Lund's 154%, 65.7%, 37.5%, 37.7%) and agree with fovref's own binary32 count
    // to within a few texels on the screen's border.
    const int W = 1280, H = 720;
    const double d_px = 360.0 / std::tan(20.0 * M_PI / 180.0);
    const std::vector<std::pair<std::string, double>> expected = {
        {"fov", 151.9}, {"kfov", 62.8}, {"cfov", 37.6}, {"ckfov", 36.7}};
    for (const auto& entry : expected) {
        const std::string& name = entry.first;
        const double share = entry.second;
        const FoveationPreset& preset = find_foveation_preset(name);
        const LogPolarMap m =
            make_log_polar_map(preset.map, W, H, {640, 360}, static_cast<float>(d_px));
        const double alpha = preset.map.kernel.alpha;
        const double L = std::log(1.0 + std::sqrt(double(W) * W + double(H) * H));
        const double r_g = preset.map.gaze_angle > 0.0f
                               ? d_px * std::tan(static_cast<double>(preset.map.gaze_angle))
                               : 0.0;
        const double G = r_g > 0.0 ? std::min(1.0, std::pow(std::log(1.0 + r_g) / L, alpha)) : 0.0;
        long independent = 0, ours = 0;
        const LpInverseTable table = lp_inverse_table(m);
        for (int j = 0; j < m.height; ++j)
            for (int i = 0; i < m.width; ++i) {
                const double t = G + (1.0 - G) * (i + 0.5) / m.width;
                const double r = std::exp(L * std::pow(t, 1.0 / alpha)) - 1.0;
                const double theta = 2.0 * M_PI * (j + 0.5) / m.height;
                const double x = 640.0 + r * std::cos(theta), y = 360.0 + r * std::sin(theta);
                independent += (x >= 0.0 && x < W && y >= 0.0 && y < H) ? 1 : 0;
                glm::vec2 p{0.0f};
                ours += lp_texel_status(m, table, i, j, p) == TexelStatus::traced ? 1 : 0;
            }
        long gaze_pixels = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x)
                gaze_pixels += std::hypot(x + 0.5 - 640.0, y + 0.5 - 360.0) < r_g ? 1 : 0;
        const double traced = 100.0 * double(independent + gaze_pixels) / (W * H);
        INFO(name, ": ", m.width, "x", m.height, ", independent ", independent, ", fovref ", ours,
             ", gaze ", gaze_pixels, ", traced ", traced, "%");
        CHECK(std::abs(independent - ours) <= 8);
        CHECK(std::fabs(traced - share) < 0.05);
    }
}

TEST_CASE(
    "log-polar: Lund §3.3.5's widening (lp_widen=on): as many columns on screen as the "
    "unwidened buffer has, the rest beyond the farthest corner") {
    for (const std::string preset : {"fov", "kfov", "cfov"}) {
        CAPTURE(preset);
        LogPolarParams params = preset_params(preset);
        const float d_px = display_distance(720);
        const LogPolarMap plain = make_log_polar_map(params, 1280, 720, {640, 360}, d_px);
        params.widen = true;
        const LogPolarMap wide = make_log_polar_map(params, 1280, 720, {640, 360}, d_px);
        CHECK(wide.height == plain.height);
        CHECK(wide.width > plain.width);
        // binary64, independently: the used share f = (K(ln(1 + D/2) / ln(1 + D)) - G) / (1 - G)
        const double diagonal = std::sqrt(1280.0 * 1280.0 + 720.0 * 720.0);
        const double rho = std::log1p(diagonal / 2) / std::log1p(diagonal);
        const double alpha = params.kernel.alpha, g = plain.composite;
        const double used = (std::pow(rho, alpha) - g) / (1.0 - g);
        CHECK(std::fabs(wide.width - plain.width / used) <= 1.0);
        // a centred gaze's farthest corner maps to the unwidened width (within a column)
        CHECK(lp_forward(wide, {0.0f, 0.0f}).x == doctest::Approx(plain.width).epsilon(1e-3));
    }
    // the columns beyond the corner are off screen, never traced
    const Scene scene = make_procedural_scene("cornell");
    RenderSettings s;
    s.width = 160;
    s.height = 90;
    s.params = Params(std::map<std::string, std::string>{{"lp_widen", "on"}});
    const FrameResult f = render(&scene, "kfov", s).at(0);
    s.params = Params();
    const FrameResult g = render(&scene, "kfov", s).at(0);
    CHECK(f.counters.get("buffer_width") > g.counters.get("buffer_width"));
    CHECK(f.counters.get("texels_traced") > g.counters.get("texels_traced"));
    CHECK(f.counters.get("texels_traced") + f.counters.get("texels_off_screen") ==
          f.counters.get("buffer_width") * f.counters.get("buffer_height"));
    s.params = Params(std::map<std::string, std::string>{{"lp_widen", "on"}, {"L", "corners"}});
    CHECK(test::contains(test::error_message([&] { render(&scene, "kfov", s); }),
                         "parameter 'lp_widen'"));
}
