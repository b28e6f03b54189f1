// Pass 2's decision buffers (ref/log_polar/resolve_decisions.h, ref/visual_polar/
// resolve_decisions.h): the taps and levels are the ones the resolves read, and the margins are
// the distances from the thresholds, checked on hand-made coordinates and by moving each
// coordinate across its margin.
#include <doctest/doctest.h>

#include <cmath>

#include "ref/log_polar/mip_resolve.h"
#include "ref/log_polar/params.h"
#include "ref/log_polar/resolve_decisions.h"
#include "ref/log_polar/trace.h"
#include "ref/visual_polar/resolve_decisions.h"

using namespace fovref;

namespace {

// A 4 x 1 screen whose forward table holds the given (u, v) and lambda, over an 8 x 6 buffer
ForwardTable hand_table(const std::vector<glm::vec2>& uv, const std::vector<float>& lambda,
                        int mip_levels) {
    ForwardTable t;
    t.map.screen_width = static_cast<int>(uv.size());
    t.map.screen_height = 1;
    t.uv = uv;
    t.mip_lambda = lambda;
    t.mip_levels = mip_levels;
    return t;
}

}  // namespace

TEST_CASE("decision margins: distances from the thresholds, clamped ranges, no threshold") {
    CHECK(floor_margin(3.25f, 1, 7) == 0.25f);
    CHECK(floor_margin(3.75f, 1, 7) == 0.25f);
    CHECK(floor_margin(-0.3f, 1, 7) == 1.3f);         // clamped below: the first threshold is 1
    CHECK(floor_margin(9.5f, 1, 7) == 2.5f);          // clamped above: the last is 7
    CHECK(floor_margin(2.0f, 1, 0) == no_threshold);  // a range with one index
    CHECK(floor_margin(NAN, 1, 7) == no_threshold);
    CHECK(wrap_margin(-0.25f) == 0.25f);
    CHECK(wrap_margin(5.0f) == 0.0f);
    CHECK(wrap_margin(INFINITY) == no_threshold);
}

TEST_CASE("log-polar decisions: taps, levels and margins of hand-made coordinates") {
    // Pixel 0: s = 3.25, t = 2.0 (an exact integer: margin 0); pixel 1: u clamped below
    // (s = -0.3: i0 = 0, 1.3 from the first threshold), t = 4.4; pixel 2: lambda 2.9999 of 4
    // levels (level 2, 1e-4 from 3), (u, v) / 4 = (1.5, 1.125); pixel 3: lambda 7 (clamped to
    // 3, 4 from the last threshold 3), lambda -2 would give level 0.
    const std::vector<glm::vec2> uv = {{3.75f, 2.5f}, {0.2f, 4.9f}, {6.0f, 4.5f}, {7.9f, 0.2f}};
    const ForwardTable t = hand_table(uv, {-2.0f, 0.5f, 2.9999f, 7.0f}, 4);
    const ResolveDecisions d = lp_resolve_decisions(t, {}, 8, 6);
    CHECK(d.tap.at(0, 0, 0) == 3.0f);
    CHECK(d.tap.at(0, 0, 1) == 2.0f);
    CHECK(d.tap_margin.at(0, 0) == 0.0f);
    CHECK(d.mip_level.at(0, 0) == 0.0f);
    CHECK(d.mip_margin.at(0, 0) == 3.0f);
    CHECK(d.tap.at(1, 0, 0) == 0.0f);
    CHECK(d.tap.at(1, 0, 1) == 4.0f);
    CHECK(d.tap_margin.at(1, 0) == doctest::Approx(0.4f).epsilon(1e-6));
    CHECK(d.mip_margin.at(1, 0) == 0.5f);
    // level 2 of 8 x 6: 2 x 2 texels; (1.5, 1.125) - 1/2 = (1.0, 0.625): column 1, row 0
    CHECK(d.mip_level.at(2, 0) == 2.0f);
    CHECK(d.mip_margin.at(2, 0) == doctest::Approx(1e-4f).epsilon(1e-3));
    CHECK(d.tap.at(2, 0, 0) == 1.0f);
    CHECK(d.tap.at(2, 0, 1) == 0.0f);
    CHECK(d.tap_margin.at(2, 0) == 0.0f);  // s = 1.0 exactly: on the threshold
    // level 3 (1 x 1): one column, no column threshold; t = 0.2 / 8 - 1/2 = -0.475
    CHECK(d.mip_level.at(3, 0) == 3.0f);
    CHECK(d.mip_margin.at(3, 0) == 4.0f);
    CHECK(d.tap.at(3, 0, 0) == 0.0f);
    CHECK(d.tap.at(3, 0, 1) == 0.0f);
    CHECK(d.tap_margin.at(3, 0) == doctest::Approx(0.475f).epsilon(1e-6));
    // Without mips: level 0, no level buffers
    const ResolveDecisions b = lp_resolve_decisions(hand_table(uv, {}, 0), {}, 8, 6);
    CHECK(b.mip_level.data.empty());
    CHECK(b.tap.at(2, 0, 0) == 5.0f);
    CHECK(b.tap.at(2, 0, 1) == 4.0f);
    CHECK(b.tap_margin.at(2, 0) == 0.0f);
}

TEST_CASE(
    "log-polar decisions: the taps and levels pass 2 reads, a level moved within its "
    "margin stays, moved across it changes") {
    const float d_px = static_cast<float>(45.0 / std::tan(20.0 * M_PI / 180.0));
    for (const std::string preset : {"cfov", "kfr"}) {
        CAPTURE(preset);
        const LogPolarMap map =
            make_log_polar_map(find_foveation_preset(preset).map, 160, 90, {70, 40}, d_px);
        const bool mip = preset == "kfr";
        const Image color(map.width, map.height, 1, 0.0f), valid(map.width, map.height, 1, 1.0f);
        const std::vector<MipLevel> mips = build_lp_mips(color, valid);
        const int levels = mip ? static_cast<int>(mips.size()) : 0;
        const ForwardTable table = forward_table(map, levels);
        const ScreenWindow window = gaze_window(map);
        const Image gaze_image(window.width, window.height, 1, 0.0f);
        const GazeInput gaze = gaze_input(map, map.has_gaze_buffer() ? &gaze_image : nullptr);
        const ResolveDecisions d = lp_resolve_decisions(table, gaze, map.width, map.height);
        std::int64_t from_gaze = 0, moved = 0;
        for (int y = 0; y < 90; ++y)
            for (int x = 0; x < 160; ++x) {
                if (reads_gaze_buffer(map, gaze, x, y)) {
                    ++from_gaze;
                    REQUIRE(d.tap.at(x, y, 0) == -1.0f);
                    REQUIRE(d.tap_margin.at(x, y) == no_threshold);
                    continue;
                }
                const std::size_t k = static_cast<std::size_t>(y) * 160 + x;
                int l0 = 0;
                if (mip) {
                    // the level resolve_mip_pixel reads first
                    Image out(160, 90, 1, 0.0f);
                    ResolveStats stats;
                    float lambda = -1.0f;
                    resolve_mip_pixel(map, mips, gaze, out, x, y, stats, &lambda, &table);
                    l0 = static_cast<int>(std::floor(lambda));
                    REQUIRE(d.mip_level.at(x, y) == static_cast<float>(l0));
                    // the unclamped level moved by 0.9 of its margin towards the nearest
                    // threshold keeps the level, by 1.1 of it changes it
                    const float m = d.mip_margin.at(x, y), raw = table.mip_lambda[k];
                    const auto level_of = [&](float l) {
                        return std::floor(std::clamp(l, 0.0f, static_cast<float>(levels - 1)));
                    };
                    if (m > 0.0f && m < 0.5f) {
                        const float towards = std::round(raw) > raw ? 1.0f : -1.0f;
                        REQUIRE(level_of(raw + towards * 0.9f * m) == static_cast<float>(l0));
                        REQUIRE(level_of(raw + towards * 1.1f * m) != static_cast<float>(l0));
                        ++moved;
                    }
                }
                // the first tap of the lookup at level l0, (u, v) / 2^l0 in its w_l x h_l texels
                const MipLevel& level = mips[static_cast<std::size_t>(l0)];
                const glm::vec2 uv = table.uv[k] * std::ldexp(1.0f, -l0);
                const BilinearLookup l = lp_bilinear_taps(level.valid, uv);
                REQUIRE(d.tap.at(x, y, 0) == static_cast<float>(l.i0));
                REQUIRE(d.tap.at(x, y, 1) == static_cast<float>(l.j0));
                // the margin is s's or t's distance from where its index changes
                const float m = d.tap_margin.at(x, y);
                const float s = uv.x - 0.5f, t = uv.y - 0.5f;
                const float w = static_cast<float>(level.valid.width);
                const bool by_s = s >= 0.5f && s < w - 0.5f &&
                                  std::fabs(std::fabs(s - std::round(s)) - m) < 1e-6f;
                const bool by_t = std::fabs(std::fabs(t - std::round(t)) - m) < 1e-6f;
                REQUIRE(m <= 0.5f);
                REQUIRE((by_s || by_t));
            }
        if (map.has_gaze_buffer()) CHECK(from_gaze > 0);
        if (mip) CHECK(moved > 50);
    }
}

TEST_CASE("stereo decisions: each eye's first tap in side-by-side columns, none outside the lens") {
    StereoParams params;
    params.barrel = true;
    const float d_px = static_cast<float>(45.0 / std::tan(20.0 * M_PI / 180.0));
    const LogPolarMap eye =
        make_log_polar_map(find_foveation_preset("fov").map, 80, 90, {40, 45}, d_px);
    const std::array<LogPolarMap, 2> maps = {eye, eye};
    const StereoForwardTable table = stereo_forward_table(params, maps);
    const ResolveDecisions d = stereo_resolve_decisions(table, 2 * eye.width, eye.height);
    CHECK(d.mip_level.data.empty());
    std::int64_t outside = 0;
    for (int y = 0; y < 90; ++y)
        for (int x = 0; x < 160; ++x) {
            const std::vector<glm::ivec2> taps = stereo_pixel_taps(params, maps, x, y);
            if (taps.empty()) {
                ++outside;
                REQUIRE(d.tap.at(x, y, 0) == -1.0f);
                REQUIRE(d.tap_margin.at(x, y) == no_threshold);
                continue;
            }
            REQUIRE(d.tap.at(x, y, 0) == static_cast<float>(taps[0].x));
            REQUIRE(d.tap.at(x, y, 1) == static_cast<float>(taps[0].y));
            REQUIRE(d.tap.at(x, y, 0) >= (x < 80 ? 0.0f : static_cast<float>(eye.width)));
            REQUIRE(d.tap_margin.at(x, y) <= 0.5f);
        }
    CHECK(outside > 0);  // the barrel's corners leave the eye's image
}

TEST_CASE("Visual-Polar decisions: the taps and levels the resolve reads") {
    const VisualPolarMap map = make_visual_polar_map(160, 90, {70.0f, 40.0f}, 107, 60);
    const VpForwardTable table = vp_forward_table(map);
    const Image valid(map.width, map.height, 1, 1.0f);
    const VpMips mips = build_vp_mips(map, Image(map.width, map.height, 1, 0.0f), valid);
    for (const bool mip : {true, false}) {
        CAPTURE(mip);
        const ResolveDecisions d = vp_resolve_decisions(table, mip);
        CHECK(d.mip_level.data.empty() == !mip);
        std::int64_t second_column = 0, level0 = 0;
        for (int y = 0; y < 90; ++y)
            for (int x = 0; x < 160; ++x) {
                Image out(160, 90, 1, 0.0f);
                ResolveStats stats;
                float lambda = -1.0f;
                resolve_vp_pixel(map, mips, out, x, y, stats, &lambda, mip, &table);
                const int l0 = static_cast<int>(std::floor(lambda));
                if (mip) REQUIRE(d.mip_level.at(x, y, 0) == static_cast<float>(l0));
                if (mip && d.mip_level.at(x, y, 1) >= 0.0f) ++second_column;
                // at level 0 the tap is vp_resolve_taps' first
                if (l0 == 0) {
                    ++level0;
                    const std::vector<glm::ivec2> taps = vp_resolve_taps(map, x, y);
                    REQUIRE(d.tap.at(x, y, 0) == static_cast<float>(taps[0].x));
                    REQUIRE(d.tap.at(x, y, 1) == static_cast<float>(taps[0].y));
                }
                REQUIRE(d.tap_margin.at(x, y) >= 0.0f);
                REQUIRE(d.tap_margin.at(x, y) <= 0.5f);
            }
        if (mip) CHECK(second_column > 0);
        CHECK(level0 > 1000);
    }
}

TEST_CASE("ray_pixel: the pixel each traced texel's ray counts in, -1 where none") {
    // texels: on screen, on a pixel edge, off screen (left, right), untraced, NaN
    const float points[6][2] = {{1.5f, 2.999f}, {3.0f, 0.0f}, {-0.1f, 1.0f},
                                {8.0f, 1.0f},   {2.0f, 2.0f}, {NAN, 1.0f}};
    Image valid(6, 1, 1, 1.0f), screen(6, 1, 2, 0.0f);
    valid.at(4, 0) = 0.0f;
    for (int i = 0; i < 6; ++i)
        for (int c = 0; c < 2; ++c) screen.at(i, 0, c) = points[i][c];
    const Image pixels = ray_pixels(8, 4, valid, screen);
    const float expected[6][2] = {{1, 2}, {3, 0}, {-1, -1}, {-1, -1}, {-1, -1}, {-1, -1}};
    for (int i = 0; i < 6; ++i) {
        CAPTURE(i);
        CHECK(pixels.at(i, 0, 0) == expected[i][0]);
        CHECK(pixels.at(i, 0, 1) == expected[i][1]);
    }
    // ray_positions counts exactly these pixels
    const Image counts = ray_position_counts(8, 4, valid, screen, nullptr);
    double total = 0.0;
    for (const float v : counts.data) total += v;
    CHECK(total == 2.0);
    CHECK(counts.at(1, 2) == 1.0f);
    CHECK(counts.at(3, 0) == 1.0f);
}
