// log-polar-pathtrace (ref/modes/log_polar_pathtrace.cpp; Koskela P5 §4.3's log-polar method):
// the log-polar map seen as BMFR's polar buffer keeps every column's h rows and inverts
// lp_inverse; a static camera and gaze reproject every traced texel onto itself in BMFR's phase
// I; BMFR on the buffer lowers the error against the converged path tracer; a resumed sequence
// gives the bits of the whole one; the parameters it does not take are refused.
#include <doctest/doctest.h>

#include <cmath>
#include <map>

#include "ref/log_polar/map.h"
#include "ref/log_polar/params.h"
#include "ref/metrics/metrics.h"
#include "ref/visual_polar/map.h"
#include "tests/stage/mode_test_util.h"

using namespace fovref;

namespace {

using test::counter;

// Meng's map for a 96 x 64 screen (the mode's: sigma 1.8, alpha 4, R from the corners).
LogPolarMap meng_map(glm::vec2 gaze) {
    LogPolarParams p;
    p.sigma = 1.8f;
    p.kernel = power_kernel(4.0f);
    p.radius = RadiusMode::corners;
    return make_log_polar_map(p, 96, 64, gaze, 0.0f);
}

}  // namespace

TEST_CASE(
    "log-polar-pathtrace: the log-polar map as BMFR's polar buffer: h rows in every column, "
    "(u, v / h) of lp_forward, lp_inverse at the texel centres") {
    const LogPolarMap lp = meng_map({40.0f, 30.0f});
    const VisualPolarMap m = vp_log_polar_map(lp);
    REQUIRE(m.log_polar.has_value());
    CHECK(m.width == lp.width);
    CHECK(m.height == lp.height);
    CHECK(m.fovea_columns == 0);
    double worst_u = 0.0, worst_t = 0.0;
    for (int i = 0; i < m.width; ++i) {
        REQUIRE(vp_column_rows(m, i) == m.height);
        for (int j = 0; j < m.height; ++j) {
            glm::vec2 p{0.0f};
            REQUIRE(vp_inverse(m, i, j, p));
            const glm::vec2 centre{static_cast<float>(i) + 0.5f, static_cast<float>(j) + 0.5f};
            const glm::vec2 q = lp_inverse(lp, centre);
            REQUIRE(p.x == q.x);
            REQUIRE(p.y == q.y);
            const glm::vec2 ut = vp_forward_angle(m, p);
            const glm::vec2 uv = lp_forward(lp, p);
            REQUIRE(ut.x == uv.x);
            REQUIRE(ut.y == uv.y / static_cast<float>(m.height));
            worst_u = std::max(worst_u, std::fabs(static_cast<double>(ut.x) - centre.x));
            const double dt = std::fabs(ut.y - (j + 0.5) / m.height);
            worst_t = std::max(worst_t, std::min(dt, 1.0 - dt));
        }
    }
    MESSAGE("round trip: " << worst_u << " columns, " << worst_t << " turns");
    CHECK(worst_u < 1e-3);
    CHECK(worst_t < 1e-5);
    glm::vec2 p{0.0f};
    CHECK_FALSE(vp_inverse(m, 0, m.height, p));
    // the polar map's forward is compared with the log-polar map's
    CHECK(m.same_forward(vp_log_polar_map(lp)));
    CHECK_FALSE(m.same_forward(vp_log_polar_map(meng_map({41.0f, 30.0f}))));
}

TEST_CASE(
    "log-polar-pathtrace: a static camera and gaze reproject every traced texel onto itself") {
    const std::vector<FrameResult> f =
        test::render_all("cornell", "log-polar-pathtrace", 96, 64, 2, {}, 0.0f);
    const Image& valid = test::buffer(f[1], "lp_valid");
    const Image& primitive = test::buffer(f[1], "lp_gbuffer_primitive_id");
    const Image& q = test::buffer(f[1], "bmfr_previous_pixel");
    double worst_u = 0.0, worst_t = 0.0;
    int traced = 0, surface = 0;
    for (int y = 0; y < valid.height; ++y)
        for (int x = 0; x < valid.width; ++x) {
            if (valid.at(x, y) == 0.0f) continue;
            ++traced;
            if (primitive.at(x, y) < 0.0f) continue;  // a miss has no position to reproject
            ++surface;
            const double t = (y + 0.5) / valid.height;
            worst_u = std::max(worst_u, std::fabs(static_cast<double>(q.at(x, y, 0)) - x));
            const double dt = std::fabs(static_cast<double>(q.at(x, y, 1)) - t);
            worst_t = std::max(worst_t, std::min(dt, 1.0 - dt));
        }
    MESSAGE("worst reprojection error: " << worst_u << " columns, " << worst_t << " turns");
    REQUIRE(surface > traced / 4);
    CHECK(worst_u < 1e-3);
    CHECK(worst_t < 1e-5);
    CHECK(counter(f[1], "bmfr_history_accepted") > surface * 8 / 10);
    CHECK(counter(f[1], "bmfr_history_rejected") + counter(f[1], "bmfr_history_accepted") +
              counter(f[1], "bmfr_history_off_screen") ==
          traced);
}

TEST_CASE(
    "log-polar-pathtrace: BMFR on the buffer lowers the error against the converged path "
    "tracer, a resumed sequence gives the bits of the whole one") {
    const int w = 96, h = 64, frames = 4;
    const float still = 0.0f;
    // checker-room: no emitter in view (on cornell the ceiling light's smear dominates, as on
    // the screen; docs/bmfr.md)
    const char* scene = "checker-room";
    const std::vector<FrameResult> bmfr =
        test::render_all(scene, "log-polar-pathtrace", w, h, frames, {}, still);
    const std::vector<FrameResult> noisy =
        test::render_all(scene, "log-polar-pathtrace", w, h, frames, {{"denoise", "none"}}, still);
    const std::vector<FrameResult> reference =
        test::render_all(scene, "pathtrace-reference", w, h, 1, {{"spp", "64"}}, still);
    // in display space (BMFR's final is its display image linearised, clamped to [0, 1])
    const Image truth = to_display(test::buffer(reference[0], "final"));
    const double denoised = mse(to_display(test::buffer(bmfr[frames - 1], "final")), truth);
    const double raw = mse(to_display(test::buffer(noisy[frames - 1], "final")), truth);
    MESSAGE("display MSE against 64 spp: noisy " << raw << ", BMFR " << denoised);
    CHECK(denoised < 0.7 * raw);
    // resumed from a dump of frame 2 (BMFR's history, the previous frame's map)
    std::vector<Buffer> state;
    for (const Buffer& b : bmfr[frames - 2].buffers) state.push_back(b);
    const std::vector<FrameResult> resumed =
        test::render_all(scene, "log-polar-pathtrace", w, h, 1, {}, still, frames - 1, state);
    CHECK(test::same_bits(test::buffer(bmfr[frames - 1], "final"),
                          test::buffer(resumed[0], "final")));
}

TEST_CASE("log-polar-pathtrace: parameters it does not take are refused, by name") {
    for (const char* key : {"gaze_angle", "primary", "filters"}) {
        CAPTURE(key);
        CHECK_THROWS_WITH_AS(
            test::render_all("cornell", "log-polar-pathtrace", 32, 24, 1, {{key, "0"}}),
            doctest::Contains(key), Error);
    }
}
