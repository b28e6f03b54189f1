// BMFR's TAA with AVX2 (ref/bmfr/display_avx.h) gives bmfr_taa_pixel's bits: reprojected points
// near their pixel, off the image on every side, NaN and infinite; displays and histories with
// NaN, infinities, -0 and +0 (ties in the box's min and max); the first and last rows and
// columns, and a row's tail. In Visual-Polar space also: untraced texels now and in the previous
// frame (a NaN mask counts as traced), the history's map with other rows in the fovea, the
// angle's wrap at the first and last rows.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "ref/bmfr/bmfr.h"
#include "ref/bmfr/display_avx.h"
#include "ref/core/simd.h"
#include "ref/visual_polar/map.h"
#include "tests/bmfr/vp_trial_maps.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

namespace {

// One in `rate` values replaced by NaN, +-Inf, +-0 or a subnormal.
float hostile_value(test::SplitMix64& rng, float v, std::size_t rate) {
    if (rng.below(rate) != 0) return v;
    const float values[] = {std::numeric_limits<float>::quiet_NaN(),
                            std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity(),
                            0.0f,
                            -0.0f,
                            1e-40f};
    return values[rng.below(6)];
}

// bmfr_taa of a 67-pixel-wide frame with the AVX2 path (its span: pixels 1 .. 64) and with the
// reference: the same bits and the same count of pixels that used the history, returned.
std::int64_t taa_both_ways(const BmfrParams& params, const Image& display,
                           const Image& previous_pixel, const Image& history,
                           const BmfrSpace& space) {
    const BmfrTaaSpan span = bmfr_taa_avx_span(display, history, space);
    CHECK(span.first == (cpu_has_avx2() ? 1 : display.width));
    CHECK(span.end == (cpu_has_avx2() ? 65 : display.width));
    Image out[2];
    BmfrStats stats[2];
    for (const bool simd : {true, false}) {
        set_simd_allowed(simd);
        out[simd ? 0 : 1] =
            bmfr_taa(params, display, previous_pixel, history, stats[simd ? 0 : 1], space);
        set_simd_allowed(true);
    }
    REQUIRE(test::same_bits_nan_aside(out[0], out[1]));
    CHECK(stats[0].taa_history_used == stats[1].taa_history_used);
    // written into storage holding a value no pixel takes (a stage's recycled storage): every
    // pixel is written, with the AVX2 path and without
    for (const bool simd : {true, false}) {
        BmfrStats into_stats;
        set_simd_allowed(simd);
        const Image into = bmfr_taa(params, display, previous_pixel, history, into_stats, space,
                                    test::unwritten_storage(display.width, display.height, 3));
        set_simd_allowed(true);
        CHECK(test::same_bits_nan_aside(into, out[1]));
    }
    return stats[1].taa_history_used;
}

}  // namespace

TEST_CASE("bmfr TAA speed: the AVX2 pass gives bmfr_taa_pixel's bits") {
    if (!cpu_has_avx2()) MESSAGE("no AVX2 on this CPU: both runs take the reference");
    const int w = 67, h = 23;  // pixel 0, eight groups of eight, a tail of two per row
    test::SplitMix64 rng(41);
    std::int64_t used = 0, pixels = 0;
    for (int trial = 0; trial < 4; ++trial) {
        CAPTURE(trial);
        Image display(w, h, 3), history(w, h, 3), previous_pixel(w, h, 2);
        for (float& v : display.data)
            v = hostile_value(
                rng, trial == 3 ? (rng.below(2) ? 0.0f : -0.0f) : rng.uniform(0.0f, 1.0f), 89);
        for (float& v : history.data) v = hostile_value(rng, rng.uniform(0.0f, 1.0f), 83);
        // Trial 2: 3x3 blocks of NaN in one channel, so that some pixels' box and cross hold no
        // number (their clamp range is +inf .. -inf: the order of min and max decides).
        if (trial == 2)
            for (int by = 0; by + 3 <= h; by += 5)
                for (int bx = by % 7; bx + 3 <= w; bx += 9)
                    for (int y = by; y < by + 3; ++y)
                        for (int x = bx; x < bx + 3; ++x)
                            display.at(x, y, 1) = std::numeric_limits<float>::quiet_NaN();
        // q near the pixel (small motion), far off on any side now and then, hostile_value.
        const float reach = trial == 1 ? 6.0f : 1.5f;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                previous_pixel.at(x, y, 0) =
                    hostile_value(rng, static_cast<float>(x) + rng.uniform(-reach, reach), 61);
                previous_pixel.at(x, y, 1) =
                    hostile_value(rng, static_cast<float>(y) + rng.uniform(-reach, reach), 61);
            }
        BmfrParams params;
        if (trial == 2) params.taa_alpha = 0.37f;
        used += taa_both_ways(params, display, previous_pixel, history, BmfrSpace{});
        pixels += w * h;
    }
    MESSAGE("history used in " << used << " of " << pixels << " pixels");
    CHECK(used > pixels / 2);
    CHECK(used < pixels);
}

TEST_CASE("bmfr TAA speed: the AVX2 pass gives bmfr_taa_pixel's bits in Visual-Polar space") {
    if (!cpu_has_avx2()) MESSAGE("no AVX2 on this CPU: both runs take the reference");
    // A 67 x 45 buffer on a 120 x 90 screen: 16 fovea columns (each lane's neighbours on its own
    // columns' rows), groups from column 1 and a tail of two per row; BMFR's staircase moved
    // between the frames.
    const int w = 67, h = 45;
    test::SplitMix64 rng(43);
    std::int64_t used = 0, traced = 0;
    for (int trial = 0; trial < 5; ++trial) {
        CAPTURE(trial);
        const test::VpTrialMaps maps = test::vp_trial_maps(trial, w, h);
        const VisualPolarMap& map = maps.map;
        VisualPolarMap previous_map = maps.previous;
        if (trial == 4) previous_map.fovea_columns += 6;  // the history's taps: its own fovea
        Image display(w, h, 3), history(w, h, 3), previous_pixel(w, h, 2), valid(w, h, 1),
            previous_valid(w, h, 1);
        for (float& v : display.data) v = hostile_value(rng, rng.uniform(0.0f, 1.0f), 89);
        for (float& v : history.data) v = hostile_value(rng, rng.uniform(0.0f, 1.0f), 83);
        const float reach = trial == 1 ? 6.0f : 1.5f;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                glm::vec2 s{0.0f};
                const bool on = vp_texel_status(map, x, y, s) == VpTexel::traced;
                valid.at(x, y) = on && rng.below(13) != 0 ? 1.0f : 0.0f;
                if (rng.below(97) == 0) valid.at(x, y) = std::numeric_limits<float>::quiet_NaN();
                previous_valid.at(x, y) = rng.below(11) != 0 ? 1.0f : 0.0f;
                traced += valid.at(x, y) != 0.0f;
                // q: the column near x, the angle (a fraction of the turn) near the row's, both
                // hostile_value now and then; trial 1 far on every side
                previous_pixel.at(x, y, 0) =
                    hostile_value(rng, static_cast<float>(x) + rng.uniform(-reach, reach), 61);
                previous_pixel.at(x, y, 1) = hostile_value(
                    rng, (static_cast<float>(y) + rng.uniform(-reach, reach)) / h, 61);
            }
        BmfrSpace space;
        space.map = map;
        space.valid = &valid;
        space.previous_valid = trial == 2 ? nullptr : &previous_valid;
        space.previous_map = previous_map;
        BmfrParams params;
        if (trial == 2) params.taa_alpha = 0.37f;
        used += taa_both_ways(params, display, previous_pixel, history, space);
    }
    MESSAGE("history used in " << used << " of " << traced << " traced texels");
    CHECK(used > traced / 2);
    CHECK(used < traced);
}
