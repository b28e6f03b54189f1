// Pass 2's bilinear and mip resolves with AVX2 (ref/log_polar/resolve_avx.h) give resolve_pixel's
// and resolve_mip_pixel's bits: fov and cfov maps (with and without a gaze buffer: groups inside
// its circle, across its edge and outside it), screens whose width is not a multiple of eight,
// masks with untraced texels (the lanes the reference takes over), buffer values of every sign (NaN
// payloads aside, docs/determinism.md), and the same counters.
#include <doctest/doctest.h>

#include <limits>

#include "ref/core/simd.h"
#include "ref/log_polar/map.h"
#include "ref/log_polar/mip_resolve.h"
#include "ref/log_polar/params.h"
#include "ref/log_polar/resolve.h"
#include "ref/log_polar/resolve_avx.h"
#include "ref/log_polar/trace.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

TEST_CASE("resolve speed: the AVX pass 2 gives resolve_pixel's bits") {
    if (!cpu_has_avx2()) MESSAGE("no AVX2 on this CPU: both runs take resolve_pixel");
    test::SplitMix64 rng(2);
    std::int64_t untraced = 0, from_gaze = 0, from_buffer = 0;
    for (const char* preset : {"fov", "cfov"})
        for (const int width : {131, 96}) {
            CAPTURE(preset);
            CAPTURE(width);
            const LogPolarMap map = make_log_polar_map(find_foveation_preset(preset).map, width, 61,
                                                       {50.0f, 27.0f}, 70.0f);
            const ForwardTable table = forward_table(map);
            for (const std::size_t untraced_rate : {2u, 9u, 1000000u}) {
                Image buffer(map.width, map.height, 3), valid(map.width, map.height, 1);
                for (float& v : buffer.data) v = rng.uniform(-2.0f, 2.0f);
                buffer.data[5] = std::numeric_limits<float>::quiet_NaN();
                buffer.data[9] = std::numeric_limits<float>::infinity();
                for (float& v : valid.data) v = rng.below(untraced_rate) == 0 ? 0.0f : 1.0f;
                Image gaze_image;
                GazeInput gaze;
                if (map.has_gaze_buffer()) {
                    const ScreenWindow window = gaze_window(map);
                    gaze_image = Image(window.width, window.height, 3);
                    for (float& v : gaze_image.data) v = rng.uniform(0.0f, 1.0f);
                    gaze = gaze_input(map, &gaze_image);
                }
                const ResolveInputs in{buffer, valid, gaze};
                CHECK(resolve_avx_applies(map, in, &table) == cpu_has_avx2());
                Image out[2];
                ResolveStats stats[2];
                for (const bool simd : {true, false}) {
                    set_simd_allowed(simd);
                    out[simd ? 0 : 1] = resolve_log_polar(map, in, stats[simd ? 0 : 1], &table);
                    set_simd_allowed(true);
                }
                REQUIRE(test::same_bits_nan_aside(out[0], out[1]));
                // written into storage holding a value no pixel takes (a stage's recycled
                // output): every pixel is written
                for (const bool simd : {true, false}) {
                    ResolveStats into_stats;
                    set_simd_allowed(simd);
                    const Image into = resolve_log_polar(
                        map, in, into_stats, &table,
                        test::unwritten_storage(map.screen_width, map.screen_height,
                                                in.buffer.channels));
                    set_simd_allowed(true);
                    CHECK(test::same_bits_nan_aside(into, out[0]));
                }
                CHECK(stats[0].pixels_from_gaze == stats[1].pixels_from_gaze);
                CHECK(stats[0].pixels_from_buffer == stats[1].pixels_from_buffer);
                CHECK(stats[0].pixels_untraced_taps == stats[1].pixels_untraced_taps);
                // Without the table every pixel takes the reference: the same image again.
                ResolveStats plain;
                REQUIRE(test::same_bits_nan_aside(resolve_log_polar(map, in, plain), out[1]));
                untraced += stats[1].pixels_untraced_taps;
                from_gaze += stats[1].pixels_from_gaze;
                from_buffer += stats[1].pixels_from_buffer;
            }
        }
    CHECK(untraced > 100);
    CHECK(from_gaze > 100);
    CHECK(from_buffer > 10000);

    // A forward table written by hand: (u, v) beyond the clamp of u and across the wrap of v,
    // rows at exactly v = j + 1/2 (fv = 0: row j1 must not be read into the result) next to
    // infinite texels.
    const LogPolarMap map =
        make_log_polar_map(find_foveation_preset("fov").map, 83, 40, {40.0f, 20.0f}, 50.0f);
    ForwardTable table = forward_table(map);
    const float w = static_cast<float>(map.width), h = static_cast<float>(map.height);
    for (glm::vec2& uv : table.uv) {
        uv.x = rng.uniform(-3.0f, w + 3.0f);
        uv.y = rng.below(2) == 0 ? static_cast<float>(rng.below(map.height)) + 0.5f
                                 : rng.uniform(-1.0f, h + 1.0f);
    }
    Image buffer(map.width, map.height, 3), valid(map.width, map.height, 1, 1.0f);
    for (float& v : buffer.data)
        v = rng.below(5) == 0 ? std::numeric_limits<float>::infinity() : rng.uniform(-1.0f, 1.0f);
    Image out[2];
    ResolveStats stats[2];
    for (const bool simd : {true, false}) {
        set_simd_allowed(simd);
        out[simd ? 0 : 1] = resolve_log_polar(map, {buffer, valid}, stats[simd ? 0 : 1], &table);
        set_simd_allowed(true);
    }
    REQUIRE(test::same_bits_nan_aside(out[0], out[1]));
}

TEST_CASE("resolve speed: the AVX mip resolve gives resolve_mip_pixel's bits") {
    if (!cpu_has_avx2()) MESSAGE("no AVX2 on this CPU: both runs take resolve_mip_pixel");
    test::SplitMix64 rng(3);
    // Resolves the pyramid of (buffer, valid) with and without the SIMD path, and without a
    // table; all three must agree, and the counters too.
    std::int64_t untraced = 0, from_gaze = 0, from_buffer = 0;
    const auto compare = [&](const LogPolarMap& map, const ForwardTable& table, const Image& buffer,
                             const Image& valid, const GazeInput& gaze, bool plain_too) {
        const std::vector<MipLevel> mips = build_lp_mips(buffer, valid);
        REQUIRE(table.mip_levels == static_cast<int>(mips.size()));
        CHECK(resolve_mip_avx_applies(map, mips, &table) == cpu_has_avx2());
        Image out[2];
        ResolveStats stats[2];
        for (const bool simd : {true, false}) {
            set_simd_allowed(simd);
            out[simd ? 0 : 1] = resolve_log_polar_mip(map, mips, gaze, stats[simd ? 0 : 1], &table);
            set_simd_allowed(true);
        }
        REQUIRE(test::same_bits_nan_aside(out[0], out[1]));
        // written into storage holding a value no pixel takes: every pixel is written
        for (const bool simd : {true, false}) {
            ResolveStats into_stats;
            set_simd_allowed(simd);
            const Image into =
                resolve_log_polar_mip(map, mips, gaze, into_stats, &table,
                                      test::unwritten_storage(map.screen_width, map.screen_height,
                                                              mips[0].color.channels));
            set_simd_allowed(true);
            CHECK(test::same_bits_nan_aside(into, out[0]));
        }
        CHECK(stats[0].pixels_from_gaze == stats[1].pixels_from_gaze);
        CHECK(stats[0].pixels_from_buffer == stats[1].pixels_from_buffer);
        CHECK(stats[0].pixels_untraced_taps == stats[1].pixels_untraced_taps);
        if (plain_too) {
            ResolveStats plain;
            REQUIRE(
                test::same_bits_nan_aside(resolve_log_polar_mip(map, mips, gaze, plain), out[1]));
        }
        untraced += stats[1].pixels_untraced_taps;
        from_gaze += stats[1].pixels_from_gaze;
        from_buffer += stats[1].pixels_from_buffer;
    };
    for (const char* preset : {"kfr", "fov", "ckfov"})
        for (const int width : {131, 96}) {
            CAPTURE(preset);
            CAPTURE(width);
            const LogPolarMap map = make_log_polar_map(find_foveation_preset(preset).map, width, 61,
                                                       {50.0f, 27.0f}, 70.0f);
            Image probe(map.width, map.height, 3), probe_valid(map.width, map.height, 1, 1.0f);
            const ForwardTable table =
                forward_table(map, static_cast<int>(build_lp_mips(probe, probe_valid).size()));
            for (const std::size_t untraced_rate : {2u, 9u, 1000000u}) {
                Image buffer(map.width, map.height, 3), valid(map.width, map.height, 1);
                for (float& v : buffer.data) v = rng.uniform(-2.0f, 2.0f);
                buffer.data[5] = std::numeric_limits<float>::quiet_NaN();
                buffer.data[9] = std::numeric_limits<float>::infinity();
                for (float& v : valid.data) v = rng.below(untraced_rate) == 0 ? 0.0f : 1.0f;
                Image gaze_image;
                GazeInput gaze;
                if (map.has_gaze_buffer()) {
                    const ScreenWindow window = gaze_window(map);
                    gaze_image = Image(window.width, window.height, 3);
                    for (float& v : gaze_image.data) v = rng.uniform(0.0f, 1.0f);
                    gaze = gaze_input(map, &gaze_image);
                }
                compare(map, table, buffer, valid, gaze, true);
            }
        }
    CHECK(untraced > 100);
    CHECK(from_gaze > 100);
    CHECK(from_buffer > 10000);

    // A table written by hand: levels below 0, beyond the top, infinite, on integers (f = 0: the
    // second level must not be read), and (u, v) beyond the clamp of u and across the wrap of v.
    const LogPolarMap map =
        make_log_polar_map(find_foveation_preset("kfr").map, 83, 40, {40.0f, 20.0f}, 50.0f);
    Image buffer(map.width, map.height, 3), valid(map.width, map.height, 1, 1.0f);
    for (float& v : buffer.data)
        v = rng.below(7) == 0 ? std::numeric_limits<float>::infinity() : rng.uniform(-1.0f, 1.0f);
    for (float& v : valid.data) v = rng.below(50) == 0 ? 0.0f : 1.0f;
    const int levels = static_cast<int>(build_lp_mips(buffer, valid).size());
    ForwardTable table = forward_table(map, levels);
    const float w = static_cast<float>(map.width), h = static_cast<float>(map.height);
    for (glm::vec2& uv : table.uv) {
        uv.x = rng.uniform(-3.0f, w + 3.0f);
        uv.y = rng.below(2) == 0 ? static_cast<float>(rng.below(map.height)) + 0.5f
                                 : rng.uniform(-1.0f, h + 1.0f);
    }
    for (float& lambda : table.mip_lambda) {
        const std::uint64_t kind = rng.below(8);
        lambda = kind == 0 ? static_cast<float>(rng.below(static_cast<std::uint64_t>(levels)))
                 : kind == 1
                     ? (rng.below(2) == 0 ? -1.0f : 1.0f) * std::numeric_limits<float>::infinity()
                     : rng.uniform(-2.0f, static_cast<float>(levels) + 2.0f);
    }
    compare(map, table, buffer, valid, GazeInput{}, false);
}
