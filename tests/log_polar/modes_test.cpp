// The foveated modes end to end (ref/modes/log_polar.h) and pass 2 and the filters on
// hand-computed cases (ref/log_polar/resolve.h, gaussian_lerp.h): counters against direct
// counts, the composite gaze pixels against the basic ray tracer bit for bit, a constant buffer
// through pass 2, degenerate screens and parameters.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>

#include "ref/bvh/bvh.h"
#include "ref/core/simd.h"
#include "ref/filters/gaussian_lerp.h"
#include "ref/log_polar/params.h"
#include "ref/log_polar/resolve.h"
#include "ref/log_polar/trace.h"
#include "ref/modes/modes.h"
#include "ref/raster/gbuffer.h"
#include "ref/scene/camera.h"
#include "ref/scene/procedural.h"
#include "ref/trace/raycast_gbuffer.h"
#include "ref/visual_polar/map.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

namespace {

const Scene& cornell() {
    static const Scene scene = make_procedural_scene("cornell");
    return scene;
}

FrameResult render_one(const Scene& scene, const std::string& mode, int width, int height,
                       std::map<std::string, std::string> params = {},
                       std::vector<std::string> requested = {"all"}) {
    RenderSettings s;
    s.width = width;
    s.height = height;
    s.params = Params(std::move(params));
    s.requested = std::move(requested);
    std::vector<FrameResult> frames = render(&scene, mode, s);
    REQUIRE(frames.size() == 1);
    return std::move(frames[0]);
}

const Image& buffer(const FrameResult& f, const std::string& name) {
    const Buffer* b = f.find(name);
    REQUIRE_MESSAGE(b != nullptr, name);
    return b->image;
}

/// gaze_valid at screen pixel (x, y): the gaze buffer covers a window of the screen (its
/// counters say where); 0 outside it.
float gaze_valid_at(const FrameResult& f, int x, int y) {
    const Image& valid = buffer(f, "gaze_valid");
    const auto i = x - static_cast<int>(f.counters.get("gaze_window_x0"));
    const auto j = y - static_cast<int>(f.counters.get("gaze_window_y0"));
    if (i < 0 || j < 0 || i >= valid.width || j >= valid.height) return 0.0f;
    return valid.at(i, j);
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

glm::vec2 centre_of(int x, int y) {
    return {static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f};
}

}  // namespace

TEST_CASE("foveated modes: counters equal direct counts of the buffers") {
    // texels_traced = the texels whose stored screen point lies on screen = the mask's ones;
    // rays_primary = texels_traced + gaze_pixels_traced = the sum of ray_positions; the buffer's
    // size is the preset's.
    for (const std::string mode : {"fov", "kfov", "cfov", "ckfov"}) {
        const FrameResult f = render_one(cornell(), mode, 160, 90, {{"gaze", "50.5,30"}});
        const Image& valid = buffer(f, "lp_valid");
        const Image& points = buffer(f, "lp_screen_point");
        std::int64_t masked = 0, on_screen = 0;
        for (int j = 0; j < valid.height; ++j)
            for (int i = 0; i < valid.width; ++i) {
                masked += valid.at(i, j) != 0.0f;
                const float x = points.at(i, j, 0), y = points.at(i, j, 1);
                on_screen += x >= 0 && x < 160 && y >= 0 && y < 90;
            }
        INFO(mode);
        const Counters& c = f.counters;
        CHECK(c.get("buffer_width") == valid.width);
        CHECK(c.get("buffer_height") == valid.height);
        CHECK(c.get("texels_traced") == masked);
        CHECK(c.get("texels_traced") == on_screen);
        CHECK(c.get("texels_traced") + c.get("texels_off_screen") ==
              static_cast<std::int64_t>(valid.width) * valid.height);
        CHECK(c.get("rays_primary") == c.get("texels_traced") + c.get("gaze_pixels_traced"));
        double rays = 0.0;
        const Image& positions = buffer(f, "ray_positions");
        for (const float v : positions.data) rays += v;
        CHECK(rays == static_cast<double>(c.get("rays_primary")));
        const BufferSize size = log_polar_buffer_size(find_foveation_preset(mode).map, 160, 90);
        CHECK(valid.width == size.width);
        CHECK(valid.height == size.height);
        if (mode[0] == 'c') {
            // The gaze pixels: the pixel centres inside the circle, counted directly.
            const float d_px = f.display_distance_px;
            const float r_g = d_px * std::tan(find_foveation_preset(mode).map.gaze_angle);
            std::int64_t inside = 0, gaze_masked = 0;
            for (int y = 0; y < 90; ++y)
                for (int x = 0; x < 160; ++x) {
                    const double dx = x + 0.5 - 50.5, dy = y + 0.5 - 30.0;
                    inside += std::sqrt(dx * dx + dy * dy) < r_g;
                    gaze_masked += gaze_valid_at(f, x, y) != 0.0f;
                }
            CHECK(c.get("gaze_pixels_traced") == gaze_masked);
            // Pixels exactly on the circle may round either way: none here.
            CHECK(c.get("gaze_pixels_traced") == inside);
            CHECK(c.get("gaze_radius_px") == static_cast<std::int64_t>(std::round(r_g)));
        }
    }
}

TEST_CASE("foveated modes: composite gaze pixels equal the basic ray tracer's bit for bit") {
    const FrameResult basic = render_one(cornell(), "basic", 160, 90, {}, {});
    for (const std::string mode : {"cfov", "ckfov"})
        for (const std::string gaze : {"", "20,70.25", "-10,45"}) {
            const FrameResult f = render_one(cornell(), mode, 160, 90, {{"gaze", gaze}});
            const Image& out = buffer(f, "final");
            const Image& ref = buffer(basic, "final");
            std::int64_t compared = 0, differing = 0;
            for (int y = 0; y < 90; ++y)
                for (int x = 0; x < 160; ++x) {
                    if (gaze_valid_at(f, x, y) == 0.0f) continue;
                    ++compared;
                    for (int c = 0; c < 3; ++c)
                        differing += !same_bits(out.at(x, y, c), ref.at(x, y, c));
                }
            INFO(mode, " gaze '", gaze, "'");
            CHECK(compared == f.counters.get("gaze_pixels_traced"));
            CHECK(compared > 0);
            CHECK(differing == 0);
        }
}

TEST_CASE("foveated modes: a gaze circle covering the screen gives the basic image") {
    // a_G = 1.5 rad: r_G = 49.4 tan(1.5) = 699 px around the centre of 64x36: every pixel is a
    // gaze pixel, no texel is traced, and the image is basic's, bit for bit.
    const FrameResult basic = render_one(cornell(), "basic", 64, 36, {}, {});
    const FrameResult f = render_one(cornell(), "cfov", 64, 36, {{"gaze_angle", "1.5"}});
    CHECK(f.counters.get("gaze_pixels_traced") == 64 * 36);
    CHECK(f.counters.get("texels_traced") == 0);
    CHECK(f.counters.get("screen_pixels_untraced_taps") == 0);
    const Image& out = buffer(f, "final");
    const Image& ref = buffer(basic, "final");
    for (std::size_t k = 0; k < out.data.size(); ++k) REQUIRE(same_bits(out.data[k], ref.data[k]));
}

TEST_CASE("foveated modes: a 1x1 screen and extreme parameters render without NaN") {
    // 1x1: the one texel's centre maps off screen (log_polar_test), so the pixel is black and
    // counted as having no traced tap.
    const FrameResult tiny = render_one(cornell(), "fov", 1, 1);
    CHECK(tiny.counters.get("texels_traced") == 0);
    CHECK(tiny.counters.get("screen_pixels_untraced_taps") == 1);
    CHECK(buffer(tiny, "final").at(0, 0) == 0.0f);
    const std::vector<std::map<std::string, std::string>> extremes = {
        {{"sigma", "0.25"}},
        {{"sigma", "8"}},
        {{"alpha", "8"}},
        {{"lp_aspect", "0.1"}},
        {{"lp_aspect", "10"}},
        {{"lp_aspect", "0"}, {"L", "corners"}},
        {{"beta", "0,0.25,0.75"}},
        {{"gaze", "-500,-500"}},
        {{"gaze", "40,0"}, {"gaze_angle", "0.6"}},
        {{"filters", "lerp"}, {"gaze", "79,44"}},
    };
    for (const auto& params : extremes) {
        const FrameResult f = render_one(cornell(), "ckfov", 80, 45, params);
        for (const Buffer& b : f.buffers)
            for (const float v : b.image.data) REQUIRE_MESSAGE(std::isfinite(v), b.name);
    }
}

TEST_CASE("foveated modes: parameters override the preset and bad ones are named") {
    const FrameResult f = render_one(cornell(), "fov", 80, 45, {{"sigma", "2"}}, {"final"});
    // h = round(sqrt(3600 / 1.2) / 2) = round(27.39) = 27; w = round(32.4) = 32.
    CHECK(f.counters.get("buffer_width") == 32);
    CHECK(f.counters.get("buffer_height") == 27);
    const auto message = [](std::map<std::string, std::string> params) {
        return test::error_message([&] { render_one(cornell(), "kfov", 16, 9, params); });
    };
    CHECK(test::contains(message({{"beta", "0,-0.5,1.5"}}), "parameter 'beta': K'(0)"));
    CHECK(test::contains(message({{"beta", "0,1"}, {"alpha", "2"}}), "'alpha' and 'beta'"));
    CHECK(test::contains(message({{"gaze", "1"}}), "parameter 'gaze': expected X,Y"));
    CHECK(test::contains(message({{"gaze", "1,nan"}}), "parameter 'gaze'"));
    CHECK(test::contains(message({{"filters", "blur"}}), "parameter 'filters'"));
    CHECK(test::contains(message({{"L", "radius"}}), "parameter 'L'"));
    CHECK(test::contains(message({{"sigma", "0"}}), "parameter 'sigma'"));
    CHECK(test::contains(message({{"alpha", "0.5"}}), "parameter 'alpha'"));
    CHECK(test::contains(message({{"ipd", "0.06"}}), "not a parameter of mode 'kfov'"));
}

TEST_CASE("gaze window: holds every pixel inside the gaze circle, at least 1x1, on the screen") {
    LogPolarMap map;
    for (const auto& size : {std::pair{64, 36}, std::pair{1, 1}, std::pair{7, 300}})
        for (const glm::vec2& g :
             {glm::vec2{32.0f, 18.0f}, glm::vec2{0.0f, 0.0f}, glm::vec2{63.5f, 35.99f},
              glm::vec2{-3.0f, 10.0f}, glm::vec2{70.25f, -8.0f}, glm::vec2{-1e6f, 2e7f},
              glm::vec2{31.5f, 17.5f}})
            for (const float r : {0.25f, 0.5f, 1.0f, 7.5f, 40.0f, 700.0f}) {
                const int w = size.first, h = size.second;  // (not bindings: INFO captures)
                map.screen_width = w;
                map.screen_height = h;
                map.gaze = g;
                map.gaze_radius = r;
                const ScreenWindow win = gaze_window(map);
                INFO(w, "x", h, " gaze (", g.x, ", ", g.y, ") r ", r);
                CHECK(win.width >= 1);
                CHECK(win.height >= 1);
                CHECK(win.x0 >= 0);
                CHECK(win.y0 >= 0);
                CHECK(win.x0 + win.width <= w);
                CHECK(win.y0 + win.height <= h);
                CHECK(win.screen_width == w);
                CHECK(win.screen_height == h);
                // Not much larger than the circle: its box plus one pixel and rounding per side.
                CHECK(win.width <= static_cast<int>(2.0f * r) + 4);
                std::int64_t inside = 0;
                for (int y = 0; y < h; ++y)
                    for (int x = 0; x < w; ++x) {
                        if (!inside_gaze_circle(map, centre_of(x, y))) continue;
                        ++inside;
                        REQUIRE(x >= win.x0);
                        REQUIRE(x < win.x0 + win.width);
                        REQUIRE(y >= win.y0);
                        REQUIRE(y < win.y0 + win.height);
                    }
                if (g.x == 32.0f && r >= 1.0f && w == 64) CHECK(inside > 0);
            }
}

TEST_CASE("pass 2: a constant buffer resolves to exactly that constant where a tap is traced") {
    // A 3-channel buffer of constants with a pseudo-random validity mask (1 texel in 3 missing):
    // every screen pixel with a traced tap gets the constant bit for bit (the lerps of equal
    // values are exact), every other pixel is black and counted.
    LogPolarParams params;
    params.sigma = 1.5f;
    params.lp_aspect = 1.0f;
    const LogPolarMap map = make_log_polar_map(params, 96, 54, {30.5f, 20.25f}, 60.0f);
    Image lp(map.width, map.height, 3, 0.0f), valid(map.width, map.height, 1, 0.0f);
    test::SplitMix64 rng(7);
    for (int j = 0; j < map.height; ++j)
        for (int i = 0; i < map.width; ++i) {
            valid.at(i, j) = rng.below(3) != 0 ? 1.0f : 0.0f;
            lp.at(i, j, 0) = 0.3f;
            lp.at(i, j, 1) = 1.7f;
            lp.at(i, j, 2) = 1e-7f;
        }
    ResolveStats stats;
    const Image out = resolve_log_polar(map, {lp, valid, {}}, stats);
    std::int64_t black = 0;
    for (int y = 0; y < 54; ++y)
        for (int x = 0; x < 96; ++x) {
            if (out.at(x, y, 0) == 0.0f) {
                ++black;
                continue;
            }
            REQUIRE(out.at(x, y, 0) == 0.3f);
            REQUIRE(out.at(x, y, 1) == 1.7f);
            REQUIRE(out.at(x, y, 2) == 1e-7f);
        }
    CHECK(black == stats.pixels_untraced_taps);
    CHECK(stats.pixels_from_buffer == 96 * 54);
}

TEST_CASE("pass 2: bilinear lookups by hand, with wrap, clamp and missing taps") {
    // A 4x3 one-channel buffer with values 10 i + j.
    Image lp(4, 3, 1, 0.0f), valid(4, 3, 1, 1.0f);
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) lp.at(i, j) = static_cast<float>(10 * i + j);
    float out = 0.0f;
    BilinearLookup l;
    // All traced at (u, v) = (1.75, 1.25): s = 1.25, fu = 0.25; t = 0.75, fv = 0.75; taps
    // (1, 0), (2, 0), (1, 1), (2, 1): rows 12.5 and 13.5, result 12.5 + 0.75 = 13.25.
    REQUIRE(sample_lp_bilinear(lp, valid, {1.75f, 1.25f}, &out, &l));
    CHECK(out == 13.25f);
    CHECK(l.i0 == 1);
    CHECK(l.j0 == 0);
    // v wraps: v = 0.25 -> rows j0 = -1 -> 2 and j1 = 0, fv = 0.75: lerp(row 2, row 0, 0.75).
    REQUIRE(sample_lp_bilinear(lp, valid, {0.5f, 0.25f}, &out, &l));
    CHECK(l.j0 == 2);
    CHECK(l.j1 == 0);
    CHECK(out == 2.0f + 0.75f * (0.0f - 2.0f));
    // u clamps: u = 9 -> the last column's centre, u = -3 -> the first.
    REQUIRE(sample_lp_bilinear(lp, valid, {9.0f, 1.5f}, &out));
    CHECK(out == 31.0f);
    REQUIRE(sample_lp_bilinear(lp, valid, {-3.0f, 1.5f}, &out));
    CHECK(out == 1.0f);
    // A missing tap: (2, 1) untraced at (1.75, 1.25). Weights (1 - fu)(1 - fv) = 0.1875 for
    // 10, fu (1 - fv) = 0.0625 for 20, (1 - fu) fv = 0.5625 for 11: sum 0.8125;
    // (1.875 + 1.25 + 6.1875) / 0.8125 = 11.4615...
    valid.at(2, 1) = 0.0f;
    REQUIRE(sample_lp_bilinear(lp, valid, {1.75f, 1.25f}, &out, &l));
    CHECK(out == doctest::Approx((0.1875 * 10 + 0.0625 * 20 + 0.5625 * 11) / 0.8125).epsilon(1e-6));
    CHECK_FALSE(l.traced[3]);
    // Every tap missing: black, false.
    for (float& v : valid.data) v = 0.0f;
    out = 5.0f;
    CHECK_FALSE(sample_lp_bilinear(lp, valid, {1.75f, 1.25f}, &out));
    CHECK(out == 0.0f);
}

TEST_CASE("Gaussian lerp: the blend amount and a filtered pixel by hand") {
    // 60x80 screen, gaze (10, 10): D = 100, D/6 = 16.667, farthest corner (60, 80) at
    // sqrt(50^2 + 70^2) = 86.023. Pixel (40, 50): centre (40.5, 50.5), distance
    // sqrt(30.5^2 + 40.5^2) = 50.700: t = (50.700 - 16.667) / (86.023 - 16.667) = 0.49070.
    const glm::vec2 gaze{10, 10};
    const double t = (std::hypot(30.5, 40.5) - 100.0 / 6) / (std::hypot(50.0, 70.0) - 100.0 / 6);
    CHECK(gaussian_lerp_amount(gaussian_lerp_ramp(60, 80, gaze), gaze, centre_of(40, 50)) ==
          doctest::Approx(t).epsilon(1e-6));
    CHECK(gaussian_lerp_amount(gaussian_lerp_ramp(60, 80, gaze), gaze, centre_of(10, 10)) == 0.0f);
    CHECK(gaussian_lerp_amount(gaussian_lerp_ramp(60, 80, gaze), gaze, {60, 80}) == 1.0f);
    // An image that is 1 at (40, 50) and 0 elsewhere: the pixel keeps 1 - t + t 4/16, its right
    // neighbour gets t' 2/16 (its own t'), a far pixel stays 0.
    Image in(60, 80, 1, 0.0f);
    in.at(40, 50) = 1.0f;
    const Image out = gaussian_lerp(in, gaze);
    CHECK(out.at(40, 50) == doctest::Approx(1 - t + t * 0.25).epsilon(1e-6));
    const double t_right =
        (std::hypot(31.5, 40.5) - 100.0 / 6) / (std::hypot(50.0, 70.0) - 100.0 / 6);
    CHECK(out.at(41, 50) == doctest::Approx(t_right * 2 / 16).epsilon(1e-6));
    CHECK(out.at(10, 10) == 0.0f);
    // Border pixels clamp their neighbours: a constant image is unchanged everywhere.
    Image flat(60, 80, 1, 0.625f);
    const Image flat_out = gaussian_lerp(flat, gaze);
    for (const float v : flat_out.data) REQUIRE(v == 0.625f);
}

TEST_CASE("Gaussian lerp: eight pixels at a time (AVX2) give gaussian_lerp_pixel's bits") {
    if (!cpu_has_avx2()) MESSAGE("no AVX2 on this CPU: both runs take gaussian_lerp_pixel");
    test::SplitMix64 rng(33);
    const float specials[] = {std::numeric_limits<float>::quiet_NaN(),
                              std::numeric_limits<float>::infinity(),
                              -std::numeric_limits<float>::infinity(),
                              -0.0f,
                              0.0f,
                              std::numeric_limits<float>::denorm_min(),
                              -1e-40f,
                              3e38f};
    int compared = 0;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    // Widths around the group's edges (9 and 10: one group or none), a row, a column; gazes on a
    // pixel centre, at a corner, off the screen, on a row between pixel centres, and three whose
    // t leave [0, 1) in every lane: NaN (a NaN gaze, and an infinite one: (inf - start) / inf),
    // which the clamp's operand order must keep, and exactly 1 (at 1e19 every distance rounds to
    // the farthest corner's). No t exceeds 1: a centre is never farther than the farthest corner,
    // rounding included, so the clamp's upper bound cannot act. Values with full significands, so
    // that a 3x3 sum taken in another order gives other bits.
    for (const auto& size : {std::pair{64, 40}, std::pair{9, 5}, std::pair{10, 5}, std::pair{17, 1},
                             std::pair{1, 12}, std::pair{91, 23}}) {
        const int w = size.first, h = size.second;  // (not a structured binding: INFO captures)
        for (const glm::vec2& gaze :
             {glm::vec2{static_cast<float>(w) / 2 + 0.5f, 10.5f}, glm::vec2{0.0f, 0.0f},
              glm::vec2{-30.0f, 200.0f}, glm::vec2{7.25f, 3.0f}, glm::vec2{nan, nan},
              glm::vec2{inf, 0.0f}, glm::vec2{1e19f, 0.0f}})
            for (const int special_rate : {0, 50}) {
                Image in(w, h, 3);
                for (float& v : in.data)
                    v = special_rate != 0 && rng.below(special_rate) == 0
                            ? specials[rng.below(std::size(specials))]
                            : rng.full_float();
                const Image fast = gaussian_lerp(in, gaze);
                set_simd_allowed(false);
                const Image reference = gaussian_lerp(in, gaze);
                // written into storage holding a value no pixel takes (a stage's recycled
                // output), without SIMD and with it: every pixel is written
                const Image plain_into = gaussian_lerp(in, gaze, test::unwritten_storage(w, h, 3));
                set_simd_allowed(true);
                INFO(w, "x", h, " gaze ", gaze.x, ", ", gaze.y, " specials 1/", special_rate);
                CHECK(test::same_bits_nan_aside(fast, reference));
                CHECK(test::same_bits_nan_aside(plain_into, reference));
                CHECK(test::same_bits_nan_aside(
                    gaussian_lerp(in, gaze, test::unwritten_storage(w, h, 3)), reference));
                ++compared;
            }
    }
    CHECK(compared == 84);
}

// No rays for texels that map off screen (SPEC §5) is a rule, not an output-neutral skip: a
// pixel near the border has bilinear taps on such texels, and the resolve renormalises over the
// traced ones. Tracing them anyway (written into the buffer right after the trace stage, through
// the render's after_stage hook, exactly as the trace writes a texel) changes the final image
// only in pixels near the screen border, and leaves the interior bit-identical.
// docs/foveation.md, docs/visual-polar.md.
struct OffScreenTexels {
    int traced = 0;    ///< texels traced in addition
    int differ = 0;    ///< final pixels that changed
    int farthest = 0;  ///< the largest distance of a changed pixel from the screen border
};

/// Renders `mode` as it is and with its off-screen texels traced too: `point(i, j, p)` gives
/// texel (i, j)'s screen point and whether the rule left it untraced for being off screen.
OffScreenTexels trace_off_screen_too(
    const Scene& scene, const std::string& mode, const std::string& trace_stage,
    const std::string& prefix, const std::string& valid_name,
    const std::function<bool(const FrameResult&, int, int, glm::vec2&)>& point) {
    RenderSettings s;
    s.width = 160;
    s.height = 90;
    s.requested = {"all"};
    const std::vector<FrameResult> rule = render(&scene, mode, s);
    const Camera camera = camera_at(scene, 0.0f);
    const float tan_half = tan_half_vfov(camera);
    const Bvh bvh = build_bvh(scene.positions);
    OffScreenTexels out;
    s.after_stage = [&](const std::string& stage, FrameResult& result) {
        if (stage != trace_stage) return;
        Image* valid = nullptr;
        for (Buffer& b : result.buffers)
            if (b.name == valid_name) valid = &b.image;
        REQUIRE(valid != nullptr);
        GBuffer extra(valid->width, valid->height);
        Image traced(valid->width, valid->height, 1, 0.0f);
        for (int j = 0; j < valid->height; ++j)
            for (int i = 0; i < valid->width; ++i) {
                glm::vec2 p{0.0f};
                if (valid->at(i, j) != 0.0f || !point(result, i, j, p)) continue;
                TraceStats stats;
                const Hit hit = trace_closest(
                    bvh, primary_ray(camera, tan_half, s.width, s.height, p.x, p.y), stats);
                if (!hit.hit()) continue;
                write_gbuffer_sample(extra, i, j, p, s.width, s.height, scene, camera, camera,
                                     tan_half, hit.primitive, hit.u, hit.v);
                traced.at(i, j) = 1.0f;
                valid->at(i, j) = 1.0f;
                ++out.traced;
            }
        FrameResult named;
        add_gbuffer(named, std::move(extra), prefix);
        for (const Buffer& e : named.buffers)
            for (Buffer& b : result.buffers)
                if (b.name == e.name)
                    for (int j = 0; j < traced.height; ++j)
                        for (int i = 0; i < traced.width; ++i)
                            if (traced.at(i, j) != 0.0f)
                                for (int c = 0; c < b.image.channels; ++c)
                                    b.image.at(i, j, c) = e.image.at(i, j, c);
    };
    const std::vector<FrameResult> traced_too = render(&scene, mode, s);
    const Image& a = rule.front().find("final")->image;
    const Image& b = traced_too.front().find("final")->image;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            bool same = true;
            for (int c = 0; c < 3; ++c) same = same && a.at(x, y, c) == b.at(x, y, c);
            if (same) continue;
            ++out.differ;
            const int border =
                std::min(std::min(x, a.width - 1 - x), std::min(y, a.height - 1 - y));
            out.farthest = std::max(out.farthest, border);
        }
    MESSAGE(mode << ": tracing " << out.traced << " off-screen texels changes " << out.differ
                 << " pixels, all within " << out.farthest << " px of the border");
    return out;
}

TEST_CASE(
    "fov and visual-polar-basic: tracing the off-screen texels too changes only border pixels") {
    const Scene scene = make_procedural_scene("checker-room");
    const OffScreenTexels lp =
        trace_off_screen_too(scene, "fov", "lp_trace", "lp_gbuffer_", "lp_valid",
                             [](const FrameResult& r, int i, int j, glm::vec2& p) {
                                 const Image& points = r.find("lp_screen_point")->image;
                                 p = {points.at(i, j, 0), points.at(i, j, 1)};
                                 return std::isfinite(p.x) && std::isfinite(p.y);
                             });
    CHECK(lp.traced > 100);
    CHECK(lp.differ > 0);     // the rule matters at the border
    CHECK(lp.farthest <= 3);  // measured: 804 of 14 400 pixels, within 3 px
    const VisualPolarMap map =
        make_visual_polar_map(160, 90, {80.0f, 45.0f}, visual_polar_buffer_size(160, 90).x,
                              visual_polar_buffer_size(160, 90).y);
    const OffScreenTexels vp = trace_off_screen_too(
        scene, "visual-polar-basic", "vp_trace", "vp_gbuffer_", "vp_valid",
        [&map](const FrameResult&, int i, int j, glm::vec2& p) {
            return vp_texel_status(map, i, j, p) == VpTexel::off_screen;  // clipped: no point
        });
    CHECK(vp.traced > 100);
    CHECK(vp.differ > 0);
    // measured: 2 369 of 14 400 pixels, within 8 px (texels are larger there, and the phi mips
    // and the blur ramp reach further than a bilinear tap)
    CHECK(vp.farthest <= 8);
}
