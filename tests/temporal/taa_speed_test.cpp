// The TAA speed-ups give the reference's bits: the AVX pass (ref/temporal/taa_avx.h) against
// taa_pixel on frames built to reach every decision in every rejection mode (kept, rejected,
// periphery, clamped to the 3x3 neighbourhood or to given boxes, behind the previous camera, off
// screen, NaN and Inf in every input), and the kept source table of the
// log-polar modes (TaaSourceTable) against the per-pixel taa_source.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "ref/core/error.h"
#include "ref/core/simd.h"
#include "ref/log_polar/map.h"
#include "ref/log_polar/params.h"
#include "ref/log_polar/trace.h"
#include "ref/temporal/taa.h"
#include "ref/temporal/taa_avx.h"
#include "ref/temporal/taa_foveated.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();
constexpr float nan = std::numeric_limits<float>::quiet_NaN();

// Turns the SIMD paths off for a scope (and back on).
struct Scalar {
    Scalar() { set_simd_allowed(false); }
    ~Scalar() { set_simd_allowed(true); }
};

// One in `rate` values replaced by a hostile one (NaN, +-Inf, +-0, a subnormal, negative).
float hostile(test::SplitMix64& rng, float v, std::size_t rate) {
    if (rng.below(rate) != 0) return v;
    const float values[] = {nan, inf, -inf, 0.0f, -0.0f, 1e-40f, -1.0f};
    return values[rng.below(7)];
}

Camera turned(float yaw_degrees, glm::vec3 position) {
    const double a = yaw_degrees * 3.14159265358979323846 / 180.0;
    const glm::vec3 forward{static_cast<float>(-std::sin(a)), 0.0f,
                            static_cast<float>(-std::cos(a))};
    return look_at(position, position + forward, {0, 1, 0}, 50.0f);
}

struct Run {
    Image out, age, margin;
    TaaStats stats;
};

// A pass into recycled storage (as the taa stage runs it: the history before last), filled
// with a value no pixel of these frames takes: a pixel the pass left unwritten keeps it.
Run run(const TaaParams& params, const TaaInputs& in, const TaaState& previous) {
    Run r;
    r.out = Image(in.color.width, in.color.height, 3, -7.25f);
    r.age = Image(in.color.width, in.color.height, 1, -7.25f);
    taa(params, in, previous, r.out, r.age, r.stats, &r.margin);
    return r;
}

void require_same(const Run& a, const Run& b) {
    REQUIRE(test::same_bits_nan_aside(a.out, b.out));
    REQUIRE(test::same_bits_nan_aside(a.age, b.age));
    REQUIRE(test::same_bits_nan_aside(a.margin, b.margin));
    CHECK(a.stats.kept == b.stats.kept);
    CHECK(a.stats.rejected == b.stats.rejected);
    CHECK(a.stats.periphery_kept == b.stats.periphery_kept);
    CHECK(a.stats.clamped == b.stats.clamped);
    CHECK(a.stats.reprojection_skipped == b.stats.reprojection_skipped);
    CHECK(a.stats.nonfinite_history == b.stats.nonfinite_history);
}

}  // namespace

TEST_CASE("TAA speed: the AVX pass gives taa_pixel's bits, every decision reached") {
    if (!cpu_has_avx2()) MESSAGE("no AVX2 on this CPU: both runs take taa_pixel");
    // 67 columns: eight groups of eight and a scalar tail of three.
    const int w = 67, h = 29;
    test::SplitMix64 rng(33);
    TaaStats total;
    for (int trial = 0; trial < 7; ++trial) {
        const bool stationary = trial == 5;
        Image color(w, h, 3), depth(w, h, 1);
        TaaState previous;
        previous.valid = true;
        previous.history = Image(w, h, 3);
        previous.age = Image(w, h, 1);
        previous.depth = Image(w, h, 1);
        for (float& v : color.data) v = hostile(rng, rng.uniform(0.0f, 1.0f), 97);
        for (float& v : previous.history.data) v = hostile(rng, rng.uniform(0.0f, 1.0f), 89);
        for (float& v : previous.age.data) v = hostile(rng, rng.uniform(0.0f, 25.0f), 83);
        // Depths near 3 (consistent or not within tau) and hostile ones in both frames.
        for (float& v : depth.data) v = hostile(rng, rng.uniform(2.0f, 4.0f), 29);
        // Trial 6: one depth everywhere and a turn, so that each group's taps lie side by side
        // in one row (the lanes' plain loads instead of gathers) except where the floors step.
        if (trial == 6)
            for (float& v : depth.data) v = 3.0f;
        for (float& v : previous.depth.data) v = hostile(rng, rng.uniform(2.0f, 4.0f), 31);
        // Small turns and steps keep most points on screen; trial 3 turns 100 degrees (points
        // behind the previous camera), trial 4 steps sideways (points off the screen).
        const float yaw[] = {0.5f, -2.0f, 4.0f, 100.0f, 0.0f, 0.0f, 1.3f};
        const glm::vec3 step[] = {{0.0f, 0.0f, -0.1f}, {0.05f, 0.02f, 0.0f}, {0.0f, 0.0f, 0.3f},
                                  {0.0f, 0.0f, 0.0f},  {1.5f, 0.0f, 0.0f},   {0.0f, 0.0f, 0.0f},
                                  {0.01f, 0.0f, 0.0f}};
        previous.camera = turned(0.0f, {0.0f, 1.0f, 4.0f});
        const Camera camera = stationary
                                  ? previous.camera
                                  : turned(yaw[trial], glm::vec3{0.0f, 1.0f, 4.0f} + step[trial]);
        TaaParams params;
        params.tau = trial % 2 == 0 ? 0.2f : 0.01f;
        params.age_cap = trial == 2 ? 3 : 20;
        const glm::vec2 gaze{rng.uniform(0.0f, w), rng.uniform(0.0f, h)};
        // Boxes for clamp-buffer: around the colour, some empty or reversed, some hostile.
        Image bounds(w, h, 6);
        for (int p = 0; p < w * h; ++p)
            for (int c = 0; c < 3; ++c) {
                const float v = color.data[static_cast<std::size_t>(3 * p + c)];
                bounds.data[static_cast<std::size_t>(6 * p + c)] =
                    hostile(rng, v - rng.uniform(-0.05f, 0.3f), 151);
                bounds.data[static_cast<std::size_t>(6 * p + 3 + c)] =
                    hostile(rng, v + rng.uniform(-0.05f, 0.3f), 151);
            }
        CAPTURE(trial);
        for (const int mode : {0, 1, 2}) {  // depth, clamp-screen, clamp-buffer
            CAPTURE(mode);
            params.rejection = mode == 0 ? TaaRejection::depth : TaaRejection::clamp;
            const TaaInputs in{color, depth, camera, gaze, mode == 2 ? &bounds : nullptr};
            // The AVX path runs (where the CPU has it), with and without the margins, into
            // fresh storage and into recycled storage (run).
            CHECK(taa_constants(in, previous).stationary == stationary);
            CHECK(taa_avx_applies(in, previous) == cpu_has_avx2());
            const Run fast = run(params, in, previous);
            Run no_margins;
            taa(params, in, previous, no_margins.out, no_margins.age, no_margins.stats);
            REQUIRE(test::same_bits_nan_aside(no_margins.out, fast.out));
            REQUIRE(test::same_bits_nan_aside(no_margins.age, fast.age));
            Run reference;
            {
                Scalar scalar;
                reference = run(params, in, previous);
            }
            require_same(fast, reference);
            total.kept += reference.stats.kept;
            total.rejected += reference.stats.rejected;
            total.clamped += reference.stats.clamped;
            total.periphery_kept += reference.stats.periphery_kept;
            total.reprojection_skipped += reference.stats.reprojection_skipped;
            total.nonfinite_history += reference.stats.nonfinite_history;
        }
    }
    // The frames reach every decision the AVX path makes.
    CHECK(total.kept > 500);
    CHECK(total.rejected > 500);
    CHECK(total.periphery_kept > 50);
    CHECK(total.clamped > 500);
    CHECK(total.reprojection_skipped > 500);
    CHECK(total.nonfinite_history > 50);
}

TEST_CASE("TAA speed: the log-polar source table gives taa_source's sources") {
    test::SplitMix64 rng(7);
    for (const char* preset : {"fov", "cfov"}) {
        CAPTURE(preset);
        const LogPolarMap map =
            make_log_polar_map(find_foveation_preset(preset).map, 97, 61, {40.0f, 33.0f}, 60.0f);
        const ForwardTable forward = forward_table(map);
        Image lp_valid(map.width, map.height, 1), lp_depth(map.width, map.height, 1);
        Image lp_color(map.width, map.height, 3), resolved(97, 61, 3);
        Image gaze_valid, gaze_depth, gaze_color;
        const bool composite = map.has_gaze_buffer();
        if (composite) {
            const ScreenWindow window = gaze_window(map);
            gaze_valid = Image(window.width, window.height, 1, 1.0f);
            gaze_depth = Image(window.width, window.height, 1);
            gaze_color = Image(window.width, window.height, 3);
            for (float& v : gaze_depth.data) v = rng.uniform(1.0f, 5.0f);
            for (float& v : gaze_color.data) v = rng.uniform(0.0f, 1.0f);
        }
        for (float& v : lp_depth.data) v = rng.uniform(1.0f, 5.0f);
        for (float& v : lp_color.data) v = rng.uniform(0.0f, 1.0f);
        for (float& v : resolved.data) v = rng.uniform(0.0f, 1.0f);
        const TaaSourceTable table =
            taa_source_table({map, forward, lp_valid, composite ? &gaze_valid : nullptr});
        // The same table for masks that change from frame to frame (TAA's jitter): a quarter of
        // the texels untraced, then half of them, then almost none.
        for (const std::size_t untraced : {3u, 1u, 1000000u}) {
            for (float& v : lp_valid.data) v = rng.below(untraced + 1) == 0 ? 0.0f : 1.0f;
            const TaaBufferInputs in{map, forward, lp_valid, composite ? &gaze_valid : nullptr};
            REQUIRE(taa_source_table_fits(table, in));
            const TaaBoxColors colors{lp_color, composite ? &gaze_color : nullptr, resolved};
            const Image* gd = composite ? &gaze_depth : nullptr;
            const TaaSourceOutputs kept = taa_source_pass(in, lp_depth, gd, &colors, &table);
            const TaaSourceOutputs each = taa_source_pass(in, lp_depth, gd, &colors);
            REQUIRE(bit_equal(kept.depth, each.depth));
            REQUIRE(bit_equal(kept.bounds, each.bounds));
        }
        // Another map does not fit.
        const LogPolarMap moved =
            make_log_polar_map(find_foveation_preset(preset).map, 97, 61, {41.0f, 33.0f}, 60.0f);
        CHECK_FALSE(taa_source_table_fits(
            table, {moved, forward_table(moved), lp_valid, composite ? &gaze_valid : nullptr}));
    }
}

// The texel records index the colours, depths and masks together, so taa_source_pass checks that
// they agree in size (and that the colours are RGB) before it reads any of them.
TEST_CASE("TAA speed: taa_source_pass refuses buffers of the wrong size") {
    const LogPolarMap map =
        make_log_polar_map(find_foveation_preset("cfov").map, 97, 61, {40.0f, 33.0f}, 60.0f);
    REQUIRE(map.has_gaze_buffer());
    const ForwardTable forward = forward_table(map);
    const ScreenWindow window = gaze_window(map);
    const Image lp_valid(map.width, map.height, 1, 1.0f), lp_depth(map.width, map.height, 1, 2.0f);
    const Image lp_color(map.width, map.height, 3, 0.5f), resolved(97, 61, 3, 0.5f);
    const Image gaze_valid(window.width, window.height, 1, 1.0f);
    const Image gaze_depth(window.width, window.height, 1, 2.0f);
    const Image gaze_color(window.width, window.height, 3, 0.5f);
    const TaaBufferInputs in{map, forward, lp_valid, &gaze_valid};
    const TaaBoxColors good{lp_color, &gaze_color, resolved};
    CHECK_NOTHROW(taa_source_pass(in, lp_depth, &gaze_depth, &good));
    const Image narrow(map.width - 1, map.height, 3), grey(97, 61, 1);
    const Image short_depth(map.width, map.height - 1, 1);
    const TaaBoxColors bad_lp{narrow, &gaze_color, resolved};
    const TaaBoxColors bad_screen{lp_color, &gaze_color, grey};
    const TaaBoxColors bad_gaze{lp_color, &narrow, resolved};
    for (const TaaBoxColors* bad : {&bad_lp, &bad_screen, &bad_gaze})
        CHECK_THROWS_WITH_AS(taa_source_pass(in, lp_depth, &gaze_depth, bad),
                             doctest::Contains("not RGB of its mask's or the screen's size"),
                             Error);
    CHECK_THROWS_WITH_AS(taa_source_pass(in, short_depth, &gaze_depth, &good),
                         doctest::Contains("view depth of another size"), Error);
    CHECK_THROWS_WITH_AS(taa_source_pass(in, lp_depth, &short_depth, &good),
                         doctest::Contains("view depth of another size"), Error);
}

// clamp-buffer's boxes eight texels at a time (texel_boxes_row_avx) against the reference, through
// taa_source_pass with the SIMD paths on and off: buffers whose width is not a multiple of eight,
// wrapped rows (the log-polar buffer) and clamped ones (the gaze buffer), masks with untraced
// texels (a NaN mask counts as traced) and runs of them, and colours with -0, infinities and NaNs,
// whose min and max depend on the order of the comparisons.
TEST_CASE("TAA speed: the AVX texel boxes give the reference's bits") {
    if (!cpu_has_avx2()) MESSAGE("no AVX2 on this CPU: both runs take the reference");
    test::SplitMix64 rng(8);
    for (const int width : {97, 130})
        for (const char* preset : {"fov", "cfov"}) {
            CAPTURE(preset);
            CAPTURE(width);
            const LogPolarMap map = make_log_polar_map(find_foveation_preset(preset).map, width, 61,
                                                       {40.0f, 33.0f}, 60.0f);
            const ForwardTable forward = forward_table(map);
            const auto fill = [&](Image& image) {
                for (float& v : image.data) {
                    const std::size_t kind = rng.below(40);
                    v = kind == 0   ? -0.0f
                        : kind == 4 ? 0.0f
                        : kind == 1 ? std::numeric_limits<float>::infinity()
                        : kind == 2 ? -std::numeric_limits<float>::infinity()
                        : kind == 3 ? std::numeric_limits<float>::quiet_NaN()
                                    : rng.uniform(-1.0f, 1.0f);
                }
            };
            const auto mask = [&](Image& valid) {
                for (float& v : valid.data) {
                    const std::size_t kind = rng.below(5);
                    v = kind == 0   ? 0.0f
                        : kind == 1 ? std::numeric_limits<float>::quiet_NaN()
                                    : 1.0f;
                }
            };
            Image lp_valid(map.width, map.height, 1), lp_depth(map.width, map.height, 1, 2.0f);
            Image lp_color(map.width, map.height, 3), resolved(width, 61, 3);
            fill(lp_color);
            fill(resolved);
            mask(lp_valid);
            // Runs of untraced texels (as off-screen columns leave), some holding one traced
            // texel: the AVX path skips the groups of eight with none traced, and only those.
            for (int j = 0; j < map.height; ++j) {
                const int start = static_cast<int>(rng.below(static_cast<std::size_t>(map.width)));
                const int end = std::min(map.width, start + static_cast<int>(rng.below(40)));
                for (int i = start; i < end; ++i) lp_valid.at(i, j) = 0.0f;
                if (end > start && rng.below(2) == 0)
                    lp_valid.at(
                        start + static_cast<int>(rng.below(static_cast<std::size_t>(end - start))),
                        j) = 1.0f;
            }
            Image gaze_valid, gaze_depth, gaze_color;
            const bool composite = map.has_gaze_buffer();
            if (composite) {
                const ScreenWindow window = gaze_window(map);
                gaze_valid = Image(window.width, window.height, 1);
                gaze_depth = Image(window.width, window.height, 1, 3.0f);
                gaze_color = Image(window.width, window.height, 3);
                fill(gaze_color);
                mask(gaze_valid);
            }
            const TaaBufferInputs in{map, forward, lp_valid, composite ? &gaze_valid : nullptr};
            const TaaBoxColors colors{lp_color, composite ? &gaze_color : nullptr, resolved};
            const Image* gd = composite ? &gaze_depth : nullptr;
            TaaSourceOutputs out[2];
            for (const bool simd : {true, false}) {
                set_simd_allowed(simd);
                out[simd ? 0 : 1] = taa_source_pass(in, lp_depth, gd, &colors);
                set_simd_allowed(true);
            }
            REQUIRE(test::same_bits_nan_aside(out[0].bounds, out[1].bounds));
            REQUIRE(bit_equal(out[0].depth, out[1].depth));
            // Into an earlier frame's storage (here filled with a value no output takes) through
            // the table, as the stage runs it: the storage is used, every value is written, the
            // same bits; and so without colours (the depth alone).
            const TaaSourceTable table = taa_source_table(in);
            const auto stale = [&](int channels) { return Image(width, 61, channels, 12345.0f); };
            TaaSourceOutputs storage{stale(1), stale(6)};
            const float* where = storage.bounds.data.data();
            const TaaSourceOutputs recycled =
                taa_source_pass(in, lp_depth, gd, &colors, &table, std::move(storage));
            CHECK(recycled.bounds.data.data() == where);
            REQUIRE(test::same_bits_nan_aside(recycled.bounds, out[1].bounds));
            REQUIRE(bit_equal(recycled.depth, out[1].depth));
            const TaaSourceOutputs depth_only =
                taa_source_pass(in, lp_depth, gd, nullptr, &table, {stale(1), {}});
            REQUIRE(bit_equal(depth_only.depth, out[1].depth));
            CHECK(depth_only.bounds.empty());
        }
}
