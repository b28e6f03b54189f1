// BMFR in Visual-Polar space (ref/bmfr/bmfr.h BmfrSpace, SPEC §9 item 11, Koskela P5 §3.3): the
// staircase grid covers every texel that carries data with the block that gathered it; a block
// that straddles the phi wrap fits exactly what the same block fits on a rotated buffer where it
// does not straddle; the taps wrap per column; a static camera and gaze reproject every traced
// texel onto itself.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>

#include "ref/bmfr/bmfr.h"
#include "ref/core/rng.h"
#include "ref/visual_polar/params.h"
#include "ref/visual_polar/trace.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

namespace {

// A w x h buffer of smooth features and noisy colours: texel (x, y) of `rows_shift` rotated
// rows (the content of row (y + shift) mod h).
struct VpBuffers {
    Image accumulated, world, normal, valid;
};

VpBuffers make_buffers(const VisualPolarMap& map, int shift) {
    const int w = map.width, h = map.height;
    VpBuffers b{Image(w, h, 3), Image(w, h, 3), Image(w, h, 3), Image(w, h, 1)};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const int row = (y + shift) % h;
            const float a = 6.2831853f * static_cast<float>(row) / static_cast<float>(h);
            const float px = static_cast<float>(x) * 0.1f + std::cos(a);
            const float py = std::sin(a) * 2.0f;
            b.world.at(x, y, 0) = px;
            b.world.at(x, y, 1) = py;
            b.world.at(x, y, 2) = 3.0f + 0.01f * static_cast<float>(x);
            b.normal.at(x, y, 0) = std::cos(a);
            b.normal.at(x, y, 1) = 0.0f;
            b.normal.at(x, y, 2) = std::sin(a);
            for (int c = 0; c < 3; ++c)
                b.accumulated.at(x, y, c) = 0.5f * px + 0.25f * py +
                                            rand_unit(7u, static_cast<std::uint32_t>(row * w + x),
                                                      static_cast<std::uint32_t>(c));
            b.valid.at(x, y) = row < vp_column_rows(map, x) ? 1.0f : 0.0f;
        }
    return b;
}

}  // namespace

TEST_CASE("VP-BMFR: the staircase grid gives every texel with data the block that gathered it") {
    const VisualPolarMap map = make_visual_polar_map(320, 360, {160.0f, 180.0f}, 213, 240);
    for (int frame : {0, 3, 7}) {
        CAPTURE(frame);
        const BmfrGrid g = bmfr_grid(map.width, map.height, frame, &map);
        CHECK(g.cells_x == (213 + 31) / 32 + 1);
        CHECK(g.cells_y == (240 + 31) / 32);
        // The staircase: fovea cell columns hold fewer blocks, the periphery all
        int blocks = 0;
        for (int cx = 0; cx < g.cells_x; ++cx) blocks += g.cells_in_column(cx);
        CHECK(blocks < g.cells_x * g.cells_y);
        CHECK(g.cells_in_column(g.cells_x - 1) == g.cells_y);
        CHECK(g.cells_in_column(0) < g.cells_y);
        // Which texels each block gathers
        std::vector<int> gathered(static_cast<std::size_t>(map.width * map.height), -1);
        for (int cx = 0; cx < g.cells_x; ++cx)
            for (int cy = 0; cy < g.cells_in_column(cx); ++cy)
                for (int row = 0; row < bmfr_block_pixels; ++row) {
                    int x = 0, y = 0;
                    if (!g.source(cx, cy, row, x, y)) continue;
                    REQUIRE(y < vp_column_rows(map, x));
                    // the first block to hold it, unless it is the texel's own block below
                    const glm::ivec2 own = g.cell_of(x, y);
                    if (own.x == cx && own.y == cy)
                        gathered[static_cast<std::size_t>(y * map.width + x)] = 1;
                }
        for (int x = 0; x < map.width; ++x)
            for (int y = 0; y < vp_column_rows(map, x); ++y) {
                const glm::ivec2 c = g.cell_of(x, y);
                REQUIRE(c.y < g.cells_in_column(c.x));
                REQUIRE(gathered[static_cast<std::size_t>(y * map.width + x)] == 1);
            }
    }
}

TEST_CASE(
    "VP-BMFR: a block across the phi wrap fits what it fits on a buffer rotated so that "
    "it does not straddle") {
    // Frame 0's offset is (-14, -14): block (cx, 0) covers rows -14 .. 17, i.e. h - 14 .. h - 1
    // and 0 .. 17 (it straddles the wrap). Block (cx, 1) covers rows 18 .. 49; on the buffer
    // rotated by 64 rows (texel y holds row (y + 64) mod 96) these are rows 82 .. 95, 0 .. 17,
    // the same rows in the same order: the gathered matrices and the fits must be bit-identical.
    const VisualPolarMap map = make_visual_polar_map(96, 96, {48.0f, 48.0f}, 64, 96);
    const BmfrGrid g = bmfr_grid(64, 96, 0, &map);
    REQUIRE(g.offset == glm::ivec2(-14, -14));
    const int cx = 2;  // columns 34 .. 63 (clamped): the periphery, all 96 rows
    REQUIRE(g.origin(cx, 0).x >= map.fovea_columns);
    const VpBuffers a = make_buffers(map, 0), b = make_buffers(map, 64);
    for (BmfrStorage storage : {BmfrStorage::half, BmfrStorage::single}) {
        BmfrParams params;
        params.storage = storage;
        BmfrBlockMatrix ma, mb;
        bmfr_gather_block(params, g, cx, 0, a.accumulated, a.world, a.normal, 0, true, ma,
                          &a.valid);
        bmfr_gather_block(params, g, cx, 1, b.accumulated, b.world, b.normal, 0, true, mb,
                          &b.valid);
        CHECK(std::memcmp(ma.a.data(), mb.a.data(), ma.a.size() * sizeof(float)) == 0);
        const BmfrBlockFit fa = bmfr_solve_block(params, ma), fb = bmfr_solve_block(params, mb);
        CHECK(std::memcmp(fa.weights, fb.weights, sizeof fa.weights) == 0);
        CHECK(fa.pivots_zeroed == 0);
        // and the fit is not trivial: the colour depends on the position
        CHECK(std::fabs(fa.weights[0][4]) + std::fabs(fa.weights[0][5]) > 0.01f);
    }
}

TEST_CASE("VP-BMFR: rows without data are zero rows, left out of the ranges") {
    const VisualPolarMap map = make_visual_polar_map(96, 96, {48.0f, 48.0f}, 64, 96);
    const BmfrGrid g = bmfr_grid(64, 96, 5, &map);
    VpBuffers b = make_buffers(map, 0);
    BmfrParams params;
    BmfrBlockMatrix m;
    bmfr_gather_block(params, g, 0, 0, b.accumulated, b.world, b.normal, 5, true, m, &b.valid);
    int zero = 0, data = 0;
    for (int row = 0; row < bmfr_block_pixels; ++row) {
        int x = 0, y = 0;
        const bool has = g.source(0, 0, row, x, y);
        bool all_zero = true;
        for (int c = 0; c < bmfr_column_count; ++c) all_zero = all_zero && m.at(row, c) == 0.0f;
        if (!has) {
            CHECK(all_zero);
            ++zero;
        } else {
            CHECK(m.at(row, 0) == 1.0f);
            ++data;
        }
    }
    CHECK(zero > 0);  // the fovea's first cell column reaches above its columns' n_c
    CHECK(data > 0);
}

TEST_CASE(
    "VP-BMFR: taps wrap per column, in the periphery they are the screen taps of (q.x, t h "
    "- 1/2) modulo h") {
    const VisualPolarMap map = make_visual_polar_map(320, 360, {100.0f, 200.0f}, 213, 240);
    // periphery: columns 120, 121
    const BmfrTaps p = bmfr_vp_taps(map, {120.25f, 0.999f});
    const BmfrTaps s = bmfr_taps({120.25f, 0.999f * 240.0f - 0.5f});
    for (int k = 0; k < 4; ++k) {
        CHECK(p.x[k] == s.x[k]);
        CHECK(p.y[k] == s.y[k] % 240);
        CHECK(p.w[k] == s.w[k]);
    }
    CHECK(p.y[2] == 0);  // row 240 wrapped
    // fovea: each column its own rows
    const int i = 10;
    const int na = vp_column_rows(map, i), nb = vp_column_rows(map, i + 1);
    REQUIRE(na != nb);
    const BmfrTaps f = bmfr_vp_taps(map, {static_cast<float>(i) + 0.5f, 0.5f});
    CHECK(f.y[0] == static_cast<int>(std::floor(0.5f * static_cast<float>(na) - 0.5f)));
    CHECK(f.y[1] == static_cast<int>(std::floor(0.5f * static_cast<float>(nb) - 0.5f)));
    float total = 0.0f;
    for (float w : f.w) total += w;
    CHECK(total == doctest::Approx(1.0f).epsilon(1e-6));
    // outside the buffer
    const BmfrTaps o = bmfr_vp_taps(map, {-1.5f, 0.5f});
    CHECK(o.y[0] == -1);
}

TEST_CASE(
    "VP-BMFR: P5's staircase clip (vp_clip=staircase): one phi height per BMFR block "
    "column, moving with the block offsets") {
    // By hand: w = 40, h = 30, i_f = round(9.6) = 10; frame 0's offset x is -14, so block column
    // 0 covers columns -30 .. 1 and block column 1 columns 2 .. 33. Triangle rows of column 1:
    // ceil(30 1.5 / 10 - 1/2) = 4; column 33 is in the periphery: 30.
    VisualPolarMap hand = make_visual_polar_map(60, 45, {30.0f, 22.0f}, 40, 30);
    hand.staircase_block = 32;
    hand.staircase_offset = -14;
    CHECK(vp_column_rows(hand, 0) == 4);
    CHECK(vp_column_rows(hand, 1) == 4);
    for (int c = 2; c < 40; ++c) CHECK(vp_column_rows(hand, c) == 30);
    CHECK(vp_triangle_rows(hand, 0) == 1);  // ceil(30 0.5 / 10 - 1/2) = ceil(1.0)
    // Every frame of the modes' map: within each block column every column has the same rows,
    // the grid's phi height; never fewer rows than the triangle; the steps move with the offset
    const SparseParams params = parse_sparse_params(Params(), "visual-polar");
    CHECK(params.staircase_block == 32);
    std::vector<int> previous;
    int moved = 0;
    for (int frame = 0; frame < 16; ++frame) {
        CAPTURE(frame);
        const VisualPolarMap map = sparse_vp_map(params, 320, 180, frame);
        CHECK(map.staircase_offset == bmfr_block_offsets()[frame].x);
        const BmfrGrid g = bmfr_grid(map.width, map.height, frame, &map);
        std::vector<int> rows;
        for (int c = 0; c < map.width; ++c) {
            rows.push_back(vp_column_rows(map, c));
            REQUIRE(rows.back() >= vp_triangle_rows(map, c));
            REQUIRE(rows.back() == g.cell_rows[static_cast<std::size_t>(g.cell_of(c, 0).x)]);
        }
        if (!previous.empty() && rows != previous) ++moved;
        previous = rows;
    }
    CHECK(moved > 10);
    // Without BMFR, or with vp_clip=triangle: the triangle
    for (const auto& p : {std::map<std::string, std::string>{{"denoise", "none"}},
                          std::map<std::string, std::string>{{"vp_clip", "triangle"}}}) {
        const VisualPolarMap map =
            sparse_vp_map(parse_sparse_params(Params(p), "visual-polar"), 320, 180, 3);
        CHECK(map.staircase_block == 0);
        for (int c = 0; c < map.width; ++c)
            REQUIRE(vp_column_rows(map, c) == vp_triangle_rows(map, c));
    }
    CHECK(parse_sparse_params(Params(std::map<std::string, std::string>{{"bmfr_block", "64"}}),
                              "visual-polar")
              .staircase_block == 64);
    CHECK(test::contains(test::error_message([] {
                             parse_sparse_params(
                                 Params(std::map<std::string, std::string>{{"vp_clip", "stairs"}}),
                                 "visual-polar");
                         }),
                         "parameter 'vp_clip'"));
}
