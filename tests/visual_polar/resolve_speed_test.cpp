// The Visual-Polar resolve with AVX2 (ref/visual_polar/resolve_avx.h) gives resolve_vp_pixel's
// bits: maps with the gaze at the centre, near a corner and off screen, screens whose width is not
// a multiple of eight, BMFR's staircase (levels the table holds for other rows, computed again),
// the trilinear and the bilinear lookups, masks with untraced texels (one tap, the other, none),
// buffer values of every sign, infinities (NaN payloads aside, docs/determinism.md), a forward
// table edited by hand so that lanes leave for the reference, and the same counters.
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "ref/core/simd.h"
#include "ref/visual_polar/map.h"
#include "ref/visual_polar/resolve.h"
#include "ref/visual_polar/resolve_avx.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

namespace {

/// The resolve with the SIMD path and without it (and, with `plain_too`, without the table),
/// from the pyramid and from the buffer itself (the packed pyramid built straight from it): the
/// same bits and counters. Returns the untraced pixels.
std::int64_t compare_resolves(const VisualPolarMap& map, const Image& color, const Image& valid,
                              const VpForwardTable& table, bool mip, bool plain_too,
                              VpResolveAvxInputs& packed) {
    const VpMips mips = build_vp_mips(map, color, valid);
    CHECK(resolve_vp_avx_applies(map, mips, &table) == cpu_has_avx2());
    CHECK(resolve_vp_avx_applies(map, color, valid, &table) == cpu_has_avx2());
    Image out[2];
    ResolveStats stats[2];
    for (const bool simd : {true, false}) {
        set_simd_allowed(simd);
        out[simd ? 0 : 1] = resolve_visual_polar(map, mips, stats[simd ? 0 : 1], mip, &table);
        set_simd_allowed(true);
    }
    REQUIRE(test::same_bits_nan_aside(out[0], out[1]));
    // written into storage that holds a value no pixel takes (a stage's recycled output): every
    // value is written
    for (const bool simd : {true, false}) {
        ResolveStats into_stats;
        set_simd_allowed(simd);
        const Image into = resolve_visual_polar(
            map, mips, into_stats, mip, &table,
            test::unwritten_storage(map.screen_width, map.screen_height, mips.color[0].channels));
        set_simd_allowed(true);
        CHECK(test::same_bits_nan_aside(into, out[0]));
    }
    CHECK(stats[0].pixels_from_buffer == stats[1].pixels_from_buffer);
    CHECK(stats[0].pixels_untraced_taps == stats[1].pixels_untraced_taps);
    // from the buffer, into a stage's kept packed storage (the caller's, last used for another
    // map), twice; then with the table's level-0 marks cleared (every group reads its levels)
    VpForwardTable unmarked = table;
    unmarked.level0.clear();
    for (int round = 0; round < 3; ++round) {
        ResolveStats buffer_stats;
        const Image from_buffer = resolve_visual_polar(
            map, color, valid, buffer_stats, mip, round < 2 ? &table : &unmarked,
            test::unwritten_storage(map.screen_width, map.screen_height, color.channels), &packed);
        CHECK(test::same_bits_nan_aside(from_buffer, out[0]));
        CHECK(buffer_stats.pixels_from_buffer == stats[1].pixels_from_buffer);
        CHECK(buffer_stats.pixels_untraced_taps == stats[1].pixels_untraced_taps);
    }
    if (plain_too) {
        ResolveStats plain;
        REQUIRE(test::same_bits_nan_aside(resolve_visual_polar(map, mips, plain, mip), out[1]));
        CHECK(plain.pixels_untraced_taps == stats[1].pixels_untraced_taps);
    }
    return stats[1].pixels_untraced_taps;
}

}  // namespace

TEST_CASE("VP resolve speed: the AVX resolve gives resolve_vp_pixel's bits") {
    if (!cpu_has_avx2()) MESSAGE("no AVX2 on this CPU: both runs take resolve_vp_pixel");
    test::SplitMix64 rng(4);
    std::int64_t untraced = 0;
    VpResolveAvxInputs packed;  // a stage's kept storage, reused across the test's maps
    for (const int screen_width : {120, 101})
        for (const glm::vec2& gaze :
             {glm::vec2{60.0f, 45.0f}, glm::vec2{12.0f, 80.0f}, glm::vec2{-30.0f, 20.0f}})
            for (const int block : {0, 8}) {
                CAPTURE(screen_width);
                CAPTURE(gaze.x);
                CAPTURE(block);
                VisualPolarMap map = make_visual_polar_map(screen_width, 90, gaze, 80, 60);
                map.staircase_block = block;
                // The table is made for offset 0; the staircase then moves (offset 3): its
                // fovea columns' rows change, and the table's levels there are computed again
                const VpForwardTable made = vp_forward_table(map);
                map.staircase_offset = block > 0 ? 3 : 0;
                VpForwardTable table = made;
                table.map = map;
                for (const std::size_t untraced_rate : {2u, 7u, 1000000u}) {
                    Image color(map.width, map.height, 3), valid(map.width, map.height, 1);
                    for (float& v : color.data) v = rng.uniform(-2.0f, 2.0f);
                    color.data[5] = std::numeric_limits<float>::quiet_NaN();
                    color.data[9] = std::numeric_limits<float>::infinity();
                    for (float& v : valid.data) v = rng.below(untraced_rate) == 0 ? 0.0f : 1.0f;
                    for (const bool mip : {true, false})
                        untraced += compare_resolves(map, color, valid, table, mip, true, packed);
                }
            }
    CHECK(untraced > 100);

    // A table edited by hand: u beyond both clamps and infinite (the group is the reference's),
    // r of every size (every level, and the clamp at the last; with 300 rows, levels 8 and 9,
    // whose packed starts the lanes gather), theta past a turn either way (rows that wrap once;
    // below -n_c - 1 twice: those lanes are the reference's), and rows at exactly v = j + 1/2
    // (fv = 0: row j1 must not be read into the result). Then the periphery's groups (u beyond
    // the fovea, r large: level 0, one lookup for both columns), with lanes at a column centre
    // (fx = 0: column i1 is not read), beyond the last column's centre (the group is not the
    // periphery's), at a row centre, and with v near -n and 2 n (the range's edges, rows that
    // wrap twice: the reference's)
    for (const bool periphery : {false, true})
        for (const int rows : {33, 300}) {
            CAPTURE(periphery);
            CAPTURE(rows);
            const VisualPolarMap map = make_visual_polar_map(83, 50, {40.0f, 20.0f}, 55, rows);
            REQUIRE(map.fovea_columns + 4 < map.width);
            VpForwardTable table = vp_forward_table(map);
            const float two_pi = 6.28318530717958647692f;
            const auto w = static_cast<float>(map.width);
            const auto fovea = static_cast<float>(map.fovea_columns);
            int centred = 0;  // pixels whose first column's v is a row centre
            int high = 0;     // pixels whose first column's level is 8 or more
            for (int y = 0; y < map.screen_height; ++y)
                for (int x = 0; x < map.screen_width; ++x) {
                    float* p = &table.polar.data[table.polar.index(x, y)];
                    const std::uint64_t kind = rng.below(16);
                    if (!periphery) {
                        p[0] = kind == 0   ? std::numeric_limits<float>::infinity()
                               : kind == 1 ? -5.0f
                                           : rng.uniform(-3.0f, w + 3.0f);
                        p[1] = rng.below(4) == 0 ? rng.uniform(0.0f, 0.01f)
                                                 : rng.uniform(0.0f, 200.0f);
                        p[2] = kind == 3 ? rng.uniform(-two_pi, 0.0f)
                                         : rng.uniform(0.0f, 2.0f * two_pi);
                    } else {
                        const auto column = static_cast<float>(
                            rng.below(static_cast<std::size_t>(map.width - map.fovea_columns - 1)));
                        p[0] = kind == 0   ? fovea + column + 0.5f
                               : kind == 1 ? w + 1.0f
                                           : rng.uniform(fovea + 0.5f, w - 1.5f);
                        p[1] = rng.uniform(100.0f, 200.0f);
                        // (v within [-n, 2 n], which sample_vp_phi accepts)
                        p[2] = kind == 3 ? rng.uniform(-two_pi + 0.001f, -two_pi + 0.05f)
                               : kind == 4
                                   ? rng.uniform(2.0f * two_pi - 0.05f, 2.0f * two_pi - 0.001f)
                                   : rng.uniform(0.0f, two_pi);
                    }
                    const VpColumns rho = vp_rho_columns(map.width, p[0]);
                    if (kind == 2) {
                        // theta nudged float by float until column i0's v = (n theta) / two_pi
                        // is j + 1/2 exactly (where a few steps find it)
                        const int n = vp_column_rows(map, rho.i0);
                        const float j = static_cast<float>(rng.below(static_cast<std::size_t>(n)));
                        float theta = two_pi * (j + 0.5f) / static_cast<float>(n);
                        for (int step = 0; step < 8; ++step) {
                            const float v = static_cast<float>(n) * theta / two_pi;
                            if (v == j + 0.5f) break;
                            theta = std::nextafter(theta, v < j + 0.5f ? 10.0f : -10.0f);
                        }
                        p[2] = theta;
                        centred += static_cast<float>(n) * theta / two_pi == j + 0.5f;
                    }
                    // the levels as vp_forward_table makes them from the edited (u, r)
                    float* level = &table.levels.data[table.levels.index(x, y)];
                    for (int k = 0; k < 2; ++k) {
                        const int n = vp_column_rows(map, k == 0 ? rho.i0 : rho.i1);
                        level[2 * k] = static_cast<float>(n);
                        level[2 * k + 1] = vp_mip_level(n, p[1]);
                    }
                    // in the periphery, one column's level edited to a fraction (the other's
                    // 0): the pixel's group is not level 0 (VpForwardTable::level0)
                    if (periphery && (kind == 5 || kind == 6)) level[kind == 5 ? 1 : 3] = 0.5f;
                    high += std::isfinite(p[0]) && level[1] >= 8.0f;
                }
            // the groups whose levels were edited to level 0 everywhere, marked again
            vp_mark_level0_groups(table);
            std::size_t marked = 0;
            for (const std::uint8_t m : table.level0) marked += m;
            CHECK((!periphery || marked > 20));
            Image color(map.width, map.height, 3), valid(map.width, map.height, 1);
            for (float& v : color.data)
                v = rng.below(5) == 0 ? std::numeric_limits<float>::infinity()
                                      : rng.uniform(-1.0f, 1.0f);
            for (float& v : valid.data) v = rng.below(3) == 0 ? 0.0f : 1.0f;
            CHECK(centred > 50);
            CHECK((periphery || rows < 256 || high > 50));
            for (const bool mip : {true, false})
                compare_resolves(map, color, valid, table, mip, false, packed);
        }
}

// The pyramid's levels eight columns at a time (downsample_group_avx) give the reference's bits:
// columns with one row and with the fovea's differing rows (the reference's), odd row counts (the
// last row wraps onto row 0), masks with untraced texels (none, one or both taps traced), -0 and
// non-finite values.
TEST_CASE("VP resolve speed: the AVX pyramid gives build_vp_mips's bits") {
    if (!cpu_has_avx2()) MESSAGE("no AVX2 on this CPU: both builds take the reference");
    test::SplitMix64 rng(5);
    for (const int block : {0, 8})
        for (const int height : {60, 45})
            for (const std::size_t untraced : {3u, 2u}) {  // one texel in 3, one in 2
                CAPTURE(block);
                CAPTURE(height);
                CAPTURE(untraced);
                VisualPolarMap map = make_visual_polar_map(120, 90, {50.0f, 40.0f}, 83, height);
                map.staircase_block = block;
                Image color(map.width, map.height, 3), valid(map.width, map.height, 1);
                for (float& v : color.data) {
                    const std::size_t kind = rng.below(30);
                    v = kind == 0   ? -0.0f
                        : kind == 1 ? std::numeric_limits<float>::infinity()
                        : kind == 2 ? std::numeric_limits<float>::quiet_NaN()
                                    : static_cast<float>(rng.below(1 << 20)) * 0x1p-19f - 1.0f;
                }
                // any non-zero mask is traced (level 0 keeps it, the next levels hold 1); the
                // columns of one row (the first without the staircase) carry their texel down,
                // traced or not
                for (float& v : valid.data) {
                    const std::size_t kind = rng.below(untraced * 4);
                    v = kind < 4    ? 0.0f
                        : kind == 4 ? 2.5f
                        : kind == 5 ? -1.0f
                        : kind == 6 ? std::numeric_limits<float>::quiet_NaN()
                                    : 1.0f;
                }
                valid.at(0, 0) = height == 45 ? 0.0f : 1.0f;
                VpMips mips[2];
                for (const bool simd : {true, false}) {
                    set_simd_allowed(simd);
                    mips[simd ? 0 : 1] = build_vp_mips(map, color, valid);
                    set_simd_allowed(true);
                }
                CHECK(mips[0].column_rows == mips[1].column_rows);
                REQUIRE(mips[0].color.size() == mips[1].color.size());
                CHECK(mips[1].color.size() == static_cast<std::size_t>(vp_mip_levels(map)));
                for (std::size_t k = 0; k < mips[0].color.size(); ++k) {
                    CAPTURE(k);
                    CHECK(test::same_bits_nan_aside(mips[0].color[k], mips[1].color[k]));
                    CHECK(test::same_bits_nan_aside(mips[0].valid[k], mips[1].valid[k]));
                }
                // the packed pyramid built straight from the buffer (level 0 packed, each next
                // level downsampled from the packed one, two texels at a time in lanes): the packed
                // copy of the reference's levels, float for float
                if (!cpu_has_avx2()) continue;
                const VpResolveAvxInputs copy = vp_resolve_avx_inputs(mips[1]);
                VpResolveAvxInputs direct;
                vp_resolve_avx_inputs(map, color, valid, direct);
                CHECK(direct.width == copy.width);
                CHECK(direct.column_rows == copy.column_rows);
                CHECK(direct.last_levels == copy.last_levels);
                CHECK(direct.level_start == copy.level_start);
                CHECK(std::equal(std::begin(direct.first_starts), std::end(direct.first_starts),
                                 std::begin(copy.first_starts)));
                REQUIRE(direct.texels.size() == copy.texels.size());
                std::size_t differ = 0;
                for (std::size_t t = 0; t < copy.texels.size(); ++t) {
                    const float a = direct.texels[t], b = copy.texels[t];
                    differ += !(std::isnan(a) && std::isnan(b)) &&
                              std::bit_cast<std::uint32_t>(a) != std::bit_cast<std::uint32_t>(b);
                }
                CHECK(differ == 0);
            }
}
