// BMFR's phase I and III with AVX (ref/bmfr/accumulate_avx.h) give bmfr_accumulate_noisy_pixel's
// and bmfr_accumulate_filtered_pixel's bits on frames built to reach every decision: taps
// accepted, rejected by position or by normal, off the image, behind the previous camera (both
// bmfr_behind_camera settings), NaN and Inf in the current and the history buffers, sample
// counts whose blend lies at x.5 (round half to even), corrupted accept bits and coordinates.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "ref/bmfr/accumulate_avx.h"
#include "ref/bmfr/bmfr.h"
#include "ref/bmfr/weighted_sum_avx.h"
#include "ref/core/simd.h"
#include "ref/visual_polar/map.h"
#include "tests/bmfr/vp_trial_maps.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();
constexpr float quiet_nan = std::numeric_limits<float>::quiet_NaN();

// One in `rate` values replaced by NaN, +-Inf, +-0 or a subnormal.
float hostile(test::SplitMix64& rng, float v, std::size_t rate) {
    if (rng.below(rate) != 0) return v;
    const float values[] = {quiet_nan, inf, -inf, 0.0f, -0.0f, 1e-40f};
    return values[rng.below(6)];
}

bool bit_equal_value(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Pixel (x, y) of a frame and its history: a point 2 to 5 along ray direction d with a normal
// near +y; the history holds the same point and normal moved by up to 0.1 and 0.6 (the limits
// are 0.1 and 0.5 in distance: some taps pass both tests, some not); whole sample counts and
// half ones now and then (blends that land on x.5); hostile values everywhere now and then.
void fill_pixel(test::SplitMix64& rng, glm::vec3 origin, glm::vec3 d, int x, int y, Image& world,
                Image& normal, Image& illumination, BmfrHistory& history) {
    const glm::vec3 p = origin + rng.uniform(2.0f, 5.0f) * d;
    const glm::vec3 n{rng.uniform(-0.3f, 0.3f), 1.0f, rng.uniform(-0.3f, 0.3f)};
    for (int c = 0; c < 3; ++c) {
        world.at(x, y, c) = hostile(rng, p[c], 211);
        normal.at(x, y, c) = hostile(rng, n[c], 211);
        history.world_position.at(x, y, c) = hostile(rng, p[c] + rng.uniform(-0.06f, 0.06f), 197);
        history.normal.at(x, y, c) = hostile(rng, n[c] + rng.uniform(-0.35f, 0.35f), 197);
        illumination.at(x, y, c) = hostile(rng, rng.uniform(0.0f, 4.0f), 193);
        history.accumulated_noisy.at(x, y, c) = hostile(rng, rng.uniform(0.0f, 4.0f), 191);
    }
    history.spp.at(x, y) = hostile(
        rng, static_cast<float>(1 + rng.below(40)) + (rng.below(8) == 0 ? 0.5f : 0.0f), 181);
}

// A frame of w x h pixels seen by `camera` and its history seen by `previous` (fill_pixel).
struct Frame {
    Image illumination, world, normal;
    BmfrHistory history;
};
Frame make_frame(test::SplitMix64& rng, int w, int h, const Camera& camera,
                 const Camera& previous) {
    Frame f{Image(w, h, 3), Image(w, h, 3), Image(w, h, 3), {}};
    f.history.valid = true;
    f.history.view_projection = view_projection(previous, w, h);
    f.history.world_position = Image(w, h, 3);
    f.history.normal = Image(w, h, 3);
    f.history.accumulated_noisy = Image(w, h, 3);
    f.history.spp = Image(w, h, 1);
    const float tan_half = tan_half_vfov(camera);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const glm::vec3 d = primary_ray_direction(
                camera, tan_half, w, h, static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
            fill_pixel(rng, camera.position, d, x, y, f.world, f.normal, f.illumination, f.history);
        }
    return f;
}

BmfrAccumulation accumulate(const BmfrParams& params, const Image& illumination, const Image& world,
                            const Image& normal, const BmfrHistory& history, BmfrStats& stats,
                            bool simd) {
    set_simd_allowed(simd);
    BmfrAccumulation a = bmfr_accumulate_noisy(params, illumination, world, normal, history, stats);
    set_simd_allowed(true);
    return a;
}

// Phase I written into unwritten_storage (a stage's recycled storage), with the AVX
// path and without: every value of its four outputs as `expected` has it.
void check_storage_written(const BmfrParams& params, const Image& illumination, const Image& world,
                           const Image& normal, const BmfrHistory& history, const BmfrSpace& space,
                           const BmfrAccumulation& expected) {
    const int w = illumination.width, h = illumination.height;
    for (const bool simd : {true, false}) {
        BmfrAccumulation storage;
        storage.accumulated = test::unwritten_storage(w, h, 3);
        storage.spp = test::unwritten_storage(w, h, 1);
        storage.accept = test::unwritten_storage(w, h, 1);
        storage.previous_pixel = test::unwritten_storage(w, h, 2);
        BmfrStats stats;
        set_simd_allowed(simd);
        const BmfrAccumulation into = bmfr_accumulate_noisy(
            params, illumination, world, normal, history, stats, space, true, std::move(storage));
        set_simd_allowed(true);
        CHECK(test::same_bits_nan_aside(into.accumulated, expected.accumulated));
        CHECK(test::same_bits_nan_aside(into.spp, expected.spp));
        CHECK(test::same_bits_nan_aside(into.accept, expected.accept));
        CHECK(test::same_bits_nan_aside(into.previous_pixel, expected.previous_pixel));
    }
}

// Phase III written into unwritten_storage, with the AVX path and without.
void check_filtered_storage(const BmfrParams& params, const Image& fitted, const Image& spp,
                            const Image& accept, const Image& previous_pixel, const Image& history,
                            const BmfrSpace& space, const Image& expected) {
    for (const bool simd : {true, false}) {
        set_simd_allowed(simd);
        const Image into =
            bmfr_accumulate_filtered(params, fitted, spp, accept, previous_pixel, history, space,
                                     test::unwritten_storage(fitted.width, fitted.height, 3));
        set_simd_allowed(true);
        CHECK(test::same_bits_nan_aside(into, expected));
    }
}

}  // namespace

TEST_CASE(
    "bmfr phases I and III: the AVX paths give the reference's bits, every decision reached") {
    if (!cpu_has_avx()) MESSAGE("no AVX on this CPU: both runs take the reference");
    const int w = 67, h = 29;  // eight groups of eight and a tail of three per row
    test::SplitMix64 rng(12);
    BmfrStats seen;
    std::int64_t half_counts = 0, blended = 0;
    for (int trial = 0; trial < 6; ++trial) {
        CAPTURE(trial);
        const Camera camera = look_at({0.0f, 1.0f, 4.0f}, {0.0f, 1.0f, 0.0f}, {0, 1, 0}, 50.0f);
        // The previous camera: a small step (most points reproject near their pixel), a step
        // through the scene (points behind it), a sideways step (points off the image).
        const glm::vec3 steps[] = {{0.02f, 0.0f, 0.0f}, {0.0f, 0.01f, 0.05f}, {0.0f, 0.0f, -3.0f},
                                   {1.0f, 0.0f, 0.0f},  {0.0f, 0.0f, 0.0f},   {0.0f, 0.0f, -3.0f}};
        const Camera previous =
            look_at(camera.position + steps[trial % 5],
                    glm::vec3{0.0f, 1.0f, 0.0f} + steps[trial % 5], {0, 1, 0}, 50.0f);
        const Frame frame = make_frame(rng, w, h, camera, previous);
        const Image &illumination = frame.illumination, &world = frame.world,
                    &normal = frame.normal;
        const BmfrHistory& history = frame.history;
        BmfrParams params;
        params.project_behind_camera = trial == 5;
        params.pixel_offset = trial == 1 ? glm::vec2(0.25f, 0.75f) : glm::vec2(0.5f);
        // The AVX paths run (where the CPU has it).
        CHECK(bmfr_accumulate_noisy_avx_applies(true, BmfrSpace{}, illumination) == cpu_has_avx());
        BmfrStats fast_stats, reference_stats;
        const BmfrAccumulation fast =
            accumulate(params, illumination, world, normal, history, fast_stats, true);
        const BmfrAccumulation reference =
            accumulate(params, illumination, world, normal, history, reference_stats, false);
        REQUIRE(test::same_bits_nan_aside(fast.accumulated, reference.accumulated));
        REQUIRE(test::same_bits_nan_aside(fast.spp, reference.spp));
        REQUIRE(test::same_bits_nan_aside(fast.accept, reference.accept));
        REQUIRE(test::same_bits_nan_aside(fast.previous_pixel, reference.previous_pixel));
        REQUIRE(test::same_bits_nan_aside(fast.accept_margin, reference.accept_margin));
        check_storage_written(params, illumination, world, normal, history, BmfrSpace{}, reference);
        CHECK(fast_stats.nonfinite_inputs == reference_stats.nonfinite_inputs);
        CHECK(fast_stats.history_accepted == reference_stats.history_accepted);
        CHECK(fast_stats.history_rejected == reference_stats.history_rejected);
        CHECK(fast_stats.history_off_screen == reference_stats.history_off_screen);
        // Phase III on phase I's decisions, some of them corrupted (a foreign buffer).
        Image fitted(w, h, 3), filtered_history(w, h, 3);
        for (float& v : fitted.data) v = hostile(rng, rng.uniform(0.0f, 4.0f), 193);
        for (float& v : filtered_history.data) v = hostile(rng, rng.uniform(0.0f, 4.0f), 191);
        Image accept = reference.accept, previous_pixel = reference.previous_pixel;
        const float odd_bits[] = {17.0f, -1.0f, 3.7f, quiet_nan, 15.0f, 16.0f};
        for (float& v : accept.data)
            if (rng.below(53) == 0) v = odd_bits[rng.below(6)];
        for (float& v : previous_pixel.data) v = hostile(rng, v, 101);
        CHECK(bmfr_accumulate_filtered_avx_applies(filtered_history, fitted) == cpu_has_avx());
        Image filtered[2];
        for (const bool simd : {true, false}) {
            set_simd_allowed(simd);
            filtered[simd ? 0 : 1] = bmfr_accumulate_filtered(params, fitted, reference.spp, accept,
                                                              previous_pixel, filtered_history);
            set_simd_allowed(true);
        }
        REQUIRE(test::same_bits_nan_aside(filtered[0], filtered[1]));
        check_filtered_storage(params, fitted, reference.spp, accept, previous_pixel,
                               filtered_history, BmfrSpace{}, filtered[1]);
        for (std::size_t i = 0; i < fitted.data.size(); ++i)
            if (!bit_equal_value(filtered[1].data[i], fitted.data[i])) ++blended;

        seen.nonfinite_inputs += reference_stats.nonfinite_inputs;
        seen.history_accepted += reference_stats.history_accepted;
        seen.history_rejected += reference_stats.history_rejected;
        seen.history_off_screen += reference_stats.history_off_screen;
        // Pixels whose history is one whole tap at (x, y) holding a count x.5: the blend is
        // x.5 exactly, rounded half to even.
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const float qx = reference.previous_pixel.at(x, y, 0);
                const float qy = reference.previous_pixel.at(x, y, 1);
                if (qx != std::floor(qx) || qy != std::floor(qy) || qx < 0.0f || qy < 0.0f ||
                    qx >= static_cast<float>(w) || qy >= static_cast<float>(h) ||
                    (static_cast<int>(reference.accept.at(x, y)) & 1) == 0)
                    continue;
                const float s = history.spp.at(static_cast<int>(qx), static_cast<int>(qy));
                if (s - std::floor(s) == 0.5f) ++half_counts;
            }
    }
    CHECK(seen.nonfinite_inputs > 20);
    CHECK(seen.history_accepted > 500);
    CHECK(seen.history_rejected > 500);
    CHECK(seen.history_off_screen > 500);
    CHECK(half_counts > 20);
    CHECK(blended > 500);  // phase III blends its history in, not just copies the fit
}

TEST_CASE("bmfr phase I: AVX groups whose taps reach the image's last pixel give its bits") {
    // A width of eight pixels per group and no tail: the last group's taps reach the last pixel,
    // whose attributes the AVX path reads float by float (no fourth float after them). A static
    // camera: each pixel reprojects onto itself, so that tap is on and mostly accepted.
    if (!cpu_has_avx()) MESSAGE("no AVX on this CPU: both runs take the reference");
    test::SplitMix64 rng(31);
    const Camera camera = look_at({0.0f, 1.0f, 4.0f}, {0.0f, 1.0f, 0.0f}, {0, 1, 0}, 50.0f);
    for (const int w : {8, 16}) {
        const int h = 3;
        CAPTURE(w);
        const Frame f = make_frame(rng, w, h, camera, camera);
        BmfrParams params;
        BmfrStats fast_stats, reference_stats;
        const BmfrAccumulation fast =
            accumulate(params, f.illumination, f.world, f.normal, f.history, fast_stats, true);
        const BmfrAccumulation reference = accumulate(params, f.illumination, f.world, f.normal,
                                                      f.history, reference_stats, false);
        CHECK(test::same_bits_nan_aside(fast.accumulated, reference.accumulated));
        CHECK(test::same_bits_nan_aside(fast.spp, reference.spp));
        CHECK(test::same_bits_nan_aside(fast.accept, reference.accept));
        CHECK(fast_stats.history_accepted == reference_stats.history_accepted);
        CHECK(reference_stats.history_accepted > w * h / 2);
    }
}

TEST_CASE("bmfr phases I and III in Visual-Polar space: the AVX paths give the reference's bits") {
    if (!cpu_has_avx()) MESSAGE("no AVX on this CPU: both runs take the reference");
    // A 67 x 45 buffer (eight groups and a tail of three per row) on a 120 x 90 screen, BMFR's
    // staircase moved between the frames (the history's rows differ from this frame's in the
    // fovea), untraced texels now and in the previous frame (a NaN mask counts as traced).
    const int w = 67, h = 45;
    test::SplitMix64 rng(29);
    BmfrStats seen;
    std::int64_t blended = 0;
    for (int trial = 0; trial < 7; ++trial) {
        CAPTURE(trial);
        const test::VpTrialMaps maps = test::vp_trial_maps(trial, w, h);
        const glm::vec2 gaze = maps.gaze;
        const VisualPolarMap& map = maps.map;
        VisualPolarMap previous_map = maps.previous;
        // The previous map of another size (a foreign history: the taps follow its rows), or
        // with a wider fovea (the taps' rows differ from this map's in six more columns)
        if (trial == 5) previous_map = make_visual_polar_map(120, 90, gaze, w + 16, h + 10);
        if (trial == 6) previous_map.fovea_columns += 6;
        const Camera camera = look_at({0.0f, 1.0f, 4.0f}, {0.0f, 1.0f, 0.0f}, {0, 1, 0}, 50.0f);
        const float tan_half = tan_half_vfov(camera);
        const glm::vec3 steps[] = {{0.02f, 0.0f, 0.0f},
                                   {0.0f, 0.01f, 0.05f},
                                   {0.0f, 0.0f, 0.0f},
                                   {1.0f, 0.0f, 0.0f},
                                   {0.0f, 0.0f, -3.0f}};
        const Camera previous =
            look_at(camera.position + steps[trial % 5],
                    glm::vec3{0.0f, 1.0f, 0.0f} + steps[trial % 5], {0, 1, 0}, 50.0f);
        Image illumination(w, h, 3), world(w, h, 3), normal(w, h, 3), valid(w, h, 1);
        BmfrHistory history;
        history.valid = true;
        history.view_projection = view_projection(previous, 120, 90);
        history.map = previous_map;
        history.valid_texels = Image(w, h, 1);
        history.world_position = Image(w, h, 3);
        history.normal = Image(w, h, 3);
        history.accumulated_noisy = Image(w, h, 3);
        history.spp = Image(w, h, 1);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                glm::vec2 s{0.0f};
                const VpTexel status = vp_texel_status(map, x, y, s);
                valid.at(x, y) = status == VpTexel::traced && rng.below(17) != 0 ? 1.0f : 0.0f;
                if (rng.below(97) == 0) valid.at(x, y) = quiet_nan;
                history.valid_texels.at(x, y) = rng.below(11) != 0 ? 1.0f : 0.0f;
                const glm::vec3 d = primary_ray_direction(camera, tan_half, 120, 90, s.x, s.y);
                fill_pixel(rng, camera.position, d, x, y, world, normal, illumination, history);
            }
        BmfrSpace space;
        space.map = map;
        space.valid = &valid;
        space.previous_map = previous_map;
        BmfrParams params;
        params.project_behind_camera = trial == 2;
        CHECK(bmfr_accumulate_noisy_avx_applies(true, space, illumination) == cpu_has_avx());
        BmfrStats fast_stats, reference_stats;
        BmfrAccumulation runs[2];
        for (const bool simd : {true, false}) {
            set_simd_allowed(simd);
            runs[simd ? 0 : 1] = bmfr_accumulate_noisy(params, illumination, world, normal, history,
                                                       simd ? fast_stats : reference_stats, space);
            set_simd_allowed(true);
        }
        REQUIRE(test::same_bits_nan_aside(runs[0].accumulated, runs[1].accumulated));
        REQUIRE(test::same_bits_nan_aside(runs[0].spp, runs[1].spp));
        REQUIRE(test::same_bits_nan_aside(runs[0].accept, runs[1].accept));
        REQUIRE(test::same_bits_nan_aside(runs[0].previous_pixel, runs[1].previous_pixel));
        REQUIRE(test::same_bits_nan_aside(runs[0].accept_margin, runs[1].accept_margin));
        check_storage_written(params, illumination, world, normal, history, space, runs[1]);
        CHECK(fast_stats.nonfinite_inputs == reference_stats.nonfinite_inputs);
        CHECK(fast_stats.history_accepted == reference_stats.history_accepted);
        CHECK(fast_stats.history_rejected == reference_stats.history_rejected);
        CHECK(fast_stats.history_off_screen == reference_stats.history_off_screen);
        seen.nonfinite_inputs += reference_stats.nonfinite_inputs;
        seen.history_accepted += reference_stats.history_accepted;
        seen.history_rejected += reference_stats.history_rejected;
        seen.history_off_screen += reference_stats.history_off_screen;
        // Phase III on phase I's decisions, some of them corrupted (a foreign buffer).
        CHECK(bmfr_accumulate_filtered_avx_applies(history.accumulated_noisy, illumination) ==
              cpu_has_avx());
        Image fitted(w, h, 3), filtered_history(w, h, 3);
        for (float& v : fitted.data) v = hostile(rng, rng.uniform(0.0f, 4.0f), 193);
        for (float& v : filtered_history.data) v = hostile(rng, rng.uniform(0.0f, 4.0f), 191);
        Image accept = runs[1].accept, previous_pixel = runs[1].previous_pixel;
        const float odd_bits[] = {17.0f, -1.0f, 3.7f, quiet_nan, 15.0f, 16.0f};
        for (float& v : accept.data)
            if (rng.below(53) == 0) v = odd_bits[rng.below(6)];
        for (float& v : previous_pixel.data) v = hostile(rng, v, 101);
        Image filtered[2];
        for (const bool simd : {true, false}) {
            set_simd_allowed(simd);
            filtered[simd ? 0 : 1] = bmfr_accumulate_filtered(
                params, fitted, runs[1].spp, accept, previous_pixel, filtered_history, space);
            set_simd_allowed(true);
        }
        REQUIRE(test::same_bits_nan_aside(filtered[0], filtered[1]));
        check_filtered_storage(params, fitted, runs[1].spp, accept, previous_pixel,
                               filtered_history, space, filtered[1]);
        for (std::size_t i = 0; i < fitted.data.size(); ++i)
            if (!bit_equal_value(filtered[1].data[i], fitted.data[i])) ++blended;
    }
    CHECK(blended > 500);  // phase III blends its history in, not just copies the fit
    MESSAGE("accepted " << seen.history_accepted << ", rejected " << seen.history_rejected
                        << ", off screen " << seen.history_off_screen << ", non-finite "
                        << seen.nonfinite_inputs);
    CHECK(seen.nonfinite_inputs > 10);
    CHECK(seen.history_accepted > 500);
    CHECK(seen.history_rejected > 100);
    CHECK(seen.history_off_screen > 100);
}

namespace {

// A Visual-Polar weighted sum's mask: the map's traced texels, one in 13 untraced, one in 97 NaN
// (which counts as traced).
Image traced_mask(test::SplitMix64& rng, const VisualPolarMap& map) {
    Image valid(map.width, map.height, 1);
    for (int y = 0; y < map.height; ++y)
        for (int x = 0; x < map.width; ++x) {
            glm::vec2 s{0.0f};
            const bool on = vp_texel_status(map, x, y, s) == VpTexel::traced;
            valid.at(x, y) = on && rng.below(13) != 0 ? 1.0f : 0.0f;
            if (rng.below(97) == 0) valid.at(x, y) = quiet_nan;
        }
    return valid;
}

}  // namespace

TEST_CASE("bmfr weighted sum: the AVX path gives the reference's bits, block by block (B 32, 64)") {
    // 150 x 37: block spans cut at every frame's offset, groups of eight and scalar ends; on the
    // screen (trials 0 .. 3), then in Visual-Polar space (4 .. 7: BMFR's staircase, texels
    // beyond their column's rows and untraced ones, without data; trial 6 without a mask).
    const int w = 150, h = 37;
    test::SplitMix64 rng(5);
    std::int64_t nonfinite = 0;
    for (int frame = 0; frame < 8; ++frame) {
        CAPTURE(frame);
        BmfrFit fit;
        VisualPolarMap map = make_visual_polar_map(225, 56, glm::vec2(100.0f, 30.0f), w, h);
        map.staircase_block = frame % 2 == 0 ? 32 : 64;
        map.staircase_offset = frame;
        const bool vp = frame >= 4;
        fit.grid = bmfr_grid(w, h, frame * 5, vp ? &map : nullptr, frame % 2 == 0 ? 32 : 64);
        const Image valid = vp && frame != 6 ? traced_mask(rng, map) : Image();
        const Image* mask = valid.empty() ? nullptr : &valid;
        CHECK(bmfr_weighted_sum_avx_applies(fit.grid, mask) == cpu_has_avx());
        fit.weights = Image(fit.grid.cells_x, fit.grid.cells_y, bmfr_weight_count);
        fit.feature_range = Image(fit.grid.cells_x, fit.grid.cells_y, 2 * bmfr_scaled_count);
        // Weights, one in 97 huge (sums that overflow: counted and set to 0).
        for (float& v : fit.weights.data) v = rng.below(97) == 0 ? 3e38f : rng.uniform(-2.0f, 2.0f);
        // Ranges: lo, then hi = lo + a span below or above 1 (the scaling's two branches).
        for (int cy = 0; cy < fit.grid.cells_y; ++cy)
            for (int cx = 0; cx < fit.grid.cells_x; ++cx)
                for (int k = 0; k < bmfr_scaled_count; ++k) {
                    const float lo = rng.uniform(-3.0f, 1.0f);
                    fit.feature_range.at(cx, cy, k) = lo;
                    fit.feature_range.at(cx, cy, bmfr_scaled_count + k) =
                        lo + rng.uniform(0.2f, 6.0f);
                }
        Image world(w, h, 3), normal(w, h, 3);
        for (float& v : world.data) v = hostile(rng, rng.uniform(-3.0f, 4.0f), 89);
        for (float& v : normal.data) v = hostile(rng, rng.uniform(-1.0f, 1.0f), 89);
        world.data[7] = 1e20f;  // a square beyond the binary16 range: clamped
        Image sums[2];
        BmfrStats stats[2];
        for (const bool simd : {true, false}) {
            set_simd_allowed(simd);
            sums[simd ? 0 : 1] = bmfr_weighted_sum(fit, world, normal, stats[simd ? 0 : 1], mask);
            set_simd_allowed(true);
        }
        REQUIRE(test::same_bits_nan_aside(sums[0], sums[1]));
        CHECK(stats[0].fit_nonfinite == stats[1].fit_nonfinite);
        nonfinite += stats[1].fit_nonfinite;
        if (vp) {  // texels without data stay 0, the others mostly do not
            int zero_data = 0, nonzero_data = 0, written_without_data = 0;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const bool data = y < fit.grid.column_rows[static_cast<std::size_t>(x)] &&
                                      (!mask || valid.at(x, y) != 0.0f);
                    const bool zero = sums[1].at(x, y, 0) == 0.0f && sums[1].at(x, y, 1) == 0.0f &&
                                      sums[1].at(x, y, 2) == 0.0f;
                    if (!data && !zero) ++written_without_data;
                    (data && !zero ? nonzero_data : zero_data) += 1;
                }
            CHECK(written_without_data == 0);
            CHECK(zero_data > w * h / 10);
            CHECK(nonzero_data > w * h / 3);
        }
    }
    CHECK(nonfinite > 40);
}
