// The Visual-Polar and sparse modes (ref/modes/visual_polar.h; SPEC §5.3-5.5, §9 item 11): their
// counters agree with the map; a Visual-Polar buffer much finer than the screen resolves to
// nearly the basic ray tracer's image (an independent path: other rays, the resolve); linear
// fall-off sampling every pixel is the path tracer bit for bit, with and without BMFR; acuity
// sampling accumulates every traced sample once; a static camera and gaze reproject every traced
// texel onto itself in BMFR's phase I; a resumed sequence gives the bits of the whole one.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <map>

#include "ref/bvh/bvh.h"
#include "ref/filters/blur_ramp.h"
#include "ref/metrics/metrics.h"
#include "ref/modes/modes.h"
#include "ref/scene/camera.h"
#include "ref/scene/procedural.h"
#include "ref/visual_polar/map.h"
#include "ref/visual_polar/params.h"
#include "ref/visual_polar/resolve.h"
#include "ref/visual_polar/trace.h"
#include "tests/stage/mode_test_util.h"

using namespace fovref;

namespace {

using test::buffer;
using test::scene_named;

std::vector<FrameResult> run(const std::string& scene, const std::string& mode, int width,
                             int height, int frames, std::map<std::string, std::string> params,
                             float time_step = 1.0f / 30, int first_frame = 0,
                             std::vector<Buffer> state = {}) {
    return test::render_all(scene, mode, width, height, frames, std::move(params), time_step,
                            first_frame, std::move(state));
}

using test::counter;

using test::same_bits;

}  // namespace

TEST_CASE("VP modes: the buffer counters are the map's, clipped and off-screen texels get no ray") {
    for (const glm::vec2& gaze :
         {glm::vec2(80.0f, 90.0f), glm::vec2(0.0f, 0.0f), glm::vec2(-40.0f, 200.0f)}) {
        CAPTURE(gaze.x);
        const std::string g = std::to_string(gaze.x) + "," + std::to_string(gaze.y);
        const std::vector<FrameResult> f =
            run("cornell", "visual-polar-basic", 160, 180, 1, {{"gaze", g}});
        const VisualPolarMap map = make_visual_polar_map(160, 180, gaze, 107, 120);
        const VisualPolarCounts c = vp_count_texels(map);
        CHECK(counter(f[0], "buffer_width") == 107);
        CHECK(counter(f[0], "buffer_height") == 120);
        CHECK(counter(f[0], "texels_clipped") == c.clipped);
        CHECK(counter(f[0], "texels_off_screen") == c.off_screen);
        CHECK(counter(f[0], "texels_traced") == c.traced);
        CHECK(counter(f[0], "rays_primary") == c.traced);
        const Image& valid = buffer(f[0], "vp_valid");
        double traced = 0.0;
        for (float v : valid.data) traced += v;
        CHECK(traced == static_cast<double>(c.traced));
    }
}

TEST_CASE(
    "VP trace: the texel table kept for a static gaze gives the per-texel bits, with BMFR's "
    "staircase moved too") {
    const Scene scene = make_procedural_scene("cornell");
    const Bvh bvh = build_bvh(scene.positions);
    const Camera camera = camera_at(scene, 0.0f);
    const PrimaryView view(scene, bvh, camera, camera);
    for (const glm::vec2& gaze :
         {glm::vec2(70.0f, 40.0f), glm::vec2(-30.0f, 100.0f), glm::vec2(61.37f, 44.81f)})
        for (const int block : {0, 8}) {
            CAPTURE(gaze.x);
            CAPTURE(block);
            VisualPolarMap map = make_visual_polar_map(120, 90, gaze, 80, 60);
            map.staircase_block = block;
            map.staircase_offset = block > 0 ? 3 : 0;
            // Tables made for this map and (with the staircase) for other staircase offsets:
            // the periphery's columns from the table, the fovea's traced per texel.
            std::vector<VpTexelTable> tables = {vp_texel_table(map)};
            for (const int offset : {0, 5})
                if (block > 0) {
                    VisualPolarMap moved = map;
                    moved.staircase_offset = offset;
                    tables.push_back(vp_texel_table(moved));
                }
            Image points;
            VpTraceStats stats;
            const MaskedGBuffer plain = trace_vp_gbuffer(map, view, points, stats);
            for (const VpTexelTable& t : tables) {
                CAPTURE(t.map.staircase_offset);
                Image kept_points;
                VpTraceStats kept_stats;
                const MaskedGBuffer kept = trace_vp_gbuffer(map, view, kept_points, kept_stats, &t);
                CHECK(same_bits(points, kept_points));
                CHECK(same_bits(plain.valid, kept.valid));
                for (const auto& [a, b] :
                     {std::pair{&plain.gbuffer.view_depth, &kept.gbuffer.view_depth},
                      std::pair{&plain.gbuffer.world_position, &kept.gbuffer.world_position},
                      std::pair{&plain.gbuffer.primitive_id, &kept.gbuffer.primitive_id},
                      std::pair{&plain.gbuffer.motion, &kept.gbuffer.motion}})
                    CHECK(same_bits(*a, *b));
                CHECK(stats.texels_traced == kept_stats.texels_traced);
                CHECK(stats.texels_clipped == kept_stats.texels_clipped);
                CHECK(stats.texels_off_screen == kept_stats.texels_off_screen);
            }
            CHECK(stats.texels_traced > 300);
            CHECK(stats.texels_clipped + stats.texels_off_screen > 100);
            // a table made for another forward map is refused
            VisualPolarMap other = map;
            other.gaze.x += 1.0f;
            Image unused;
            VpTraceStats more;
            CHECK_THROWS(trace_vp_gbuffer(other, view, unused, more, &tables[0]));
        }
}

TEST_CASE("VP modes: a buffer much finer than the screen resolves to nearly the basic image") {
    // sphere-grid has point lights (no light sampling noise). With a 4W x 4H buffer every pixel
    // has many texels; the remaining differences are edges, where a pixel mixes texels that hit
    // different objects. Measured: about 31 dB; bound 26 dB. A wrong angle, radius or resolve
    // gives well under 15 dB.
    const int w = 96, h = 64;
    const Image basic = buffer(run("sphere-grid", "basic", w, h, 1, {})[0], "final");
    const Image vp =
        buffer(run("sphere-grid", "visual-polar-basic", w, h, 1,
                   {{"buffer_width", "384"}, {"buffer_height", "256"}, {"blur", "off"}})[0],
               "final");
    const double p = psnr(mse(basic, vp));
    MESSAGE("visual-polar-basic (4x buffer) vs basic: PSNR " << p << " dB");
    CHECK(p > 26.0);
}

TEST_CASE("VP modes: linear fall-off that samples every pixel is the path tracer bit for bit") {
    for (const char* denoise : {"none", "bmfr"}) {
        CAPTURE(denoise);
        const std::vector<FrameResult> a = run("cornell", "linear-falloff", 64, 48, 3,
                                               {{"falloff_min", "1"}, {"denoise", denoise}});
        const std::vector<FrameResult> b =
            run("cornell", "pathtrace", 64, 48, 3, {{"denoise", denoise}});
        for (int k = 0; k < 3; ++k) {
            CHECK(counter(a[static_cast<std::size_t>(k)], "pixels_sampled") == 64 * 48);
            CHECK(same_bits(buffer(a[static_cast<std::size_t>(k)], "final"),
                            buffer(b[static_cast<std::size_t>(k)], "final")));
        }
    }
}

TEST_CASE(
    "VP modes: linear fall-off with blur (P5's comparison) is the P5 blur ramp of the "
    "unblurred image, with the Visual-Polar preset's geometry") {
    for (const char* denoise : {"none", "bmfr"}) {
        CAPTURE(denoise);
        const std::vector<FrameResult> plain =
            run("cornell", "linear-falloff", 160, 90, 2, {{"denoise", denoise}});
        const std::vector<FrameResult> blurred =
            run("cornell", "linear-falloff", 160, 90, 2, {{"denoise", denoise}, {"blur", "on"}});
        const SparseParams params = parse_sparse_params(Params(), "visual-polar");
        for (int k = 0; k < 2; ++k) {
            const auto f = static_cast<std::size_t>(k);
            const Image& image = buffer(plain[f], "final");
            CHECK(same_bits(buffer(blurred[f], "unblurred"), image));
            const Image expected = blur_ramp(
                params.ramp, blur_ramp_geometry(sparse_vp_map(params, 160, 90, k)), image);
            CHECK(same_bits(buffer(blurred[f], "final"), expected));
            CHECK_FALSE(same_bits(expected, image));  // the periphery is blurred
        }
    }
}

TEST_CASE("VP modes: linear fall-off samples fewer pixels away from the gaze and fills them") {
    const std::vector<FrameResult> f =
        run("cornell", "linear-falloff", 160, 90, 1,
            {{"falloff_fovea_deg", "5"}, {"falloff_periphery_deg", "10"}});
    const Image& mask = buffer(f[0], "sample_mask");
    const Image& sparse = buffer(f[0], "sparse_radiance");
    const Image& out = buffer(f[0], "final");
    CHECK(mask.at(80, 45) == 1.0f);  // the gaze
    const std::int64_t sampled = counter(f[0], "pixels_sampled");
    CHECK(sampled < 160 * 90 / 2);
    // samples kept; unsampled pixels filled (cornell: the walls are lit, so filled values > 0)
    int filled = 0;
    for (int y = 0; y < 90; ++y)
        for (int x = 0; x < 160; ++x) {
            if (mask.at(x, y) != 0.0f) {
                for (int c = 0; c < 3; ++c) REQUIRE(out.at(x, y, c) == sparse.at(x, y, c));
            } else {
                filled += out.at(x, y, 0) + out.at(x, y, 1) + out.at(x, y, 2) > 0.0f;
            }
        }
    CHECK(filled > 0);
}

TEST_CASE("VP modes: acuity sampling accumulates every traced sample once, progressively") {
    const std::vector<FrameResult> f = run("cornell", "acuity", 96, 64, 3, {{"samples", "500"}});
    double traced = 0.0;
    for (const FrameResult& r : f) {
        CHECK(counter(r, "samples") == 500);
        traced += static_cast<double>(counter(r, "samples_traced"));
    }
    double counted = 0.0;
    for (float n : buffer(f[2], "acuity_count").data) counted += n;
    CHECK(counted == traced);
    // the default: 10% of the pixels
    CHECK(counter(run("cornell", "acuity", 96, 64, 1, {})[0], "samples") == 614);
    // off: this frame's only
    const std::vector<FrameResult> g =
        run("cornell", "acuity", 96, 64, 2, {{"samples", "500"}, {"progressive", "off"}});
    double one = 0.0;
    for (float n : buffer(g[1], "acuity_count").data) one += n;
    CHECK(one == static_cast<double>(counter(g[1], "samples_traced")));
}

TEST_CASE("VP-BMFR: a static camera and gaze reproject every traced texel onto itself") {
    const std::vector<FrameResult> f = run("cornell", "visual-polar", 96, 96, 2, {}, 0.0f);
    const Image& valid = buffer(f[1], "vp_valid");
    const Image& primitive = buffer(f[1], "vp_gbuffer_primitive_id");
    const Image& q = buffer(f[1], "bmfr_previous_pixel");
    // frame 1's map: BMFR's staircase clip gives its fovea columns frame 1's row counts
    const VisualPolarMap map =
        sparse_vp_map(parse_sparse_params(Params(), "visual-polar"), 96, 96, 1);
    CHECK(map.staircase_block == 32);
    double worst_u = 0.0, worst_t = 0.0;
    int traced = 0;
    for (int y = 0; y < valid.height; ++y)
        for (int x = 0; x < valid.width; ++x) {
            if (valid.at(x, y) == 0.0f) continue;
            ++traced;
            // a miss (cornell's open front) has no world position to reproject, as on the screen
            if (primitive.at(x, y) < 0.0f) continue;
            const double t = (y + 0.5) / vp_column_rows(map, x);
            worst_u = std::max(worst_u, std::fabs(static_cast<double>(q.at(x, y, 0)) - x));
            const double dt = std::fabs(static_cast<double>(q.at(x, y, 1)) - t);
            worst_t = std::max(worst_t, std::min(dt, 1.0 - dt));
        }
    MESSAGE("worst reprojection error: " << worst_u << " columns, " << worst_t << " turns");
    CHECK(worst_u < 2e-3);
    CHECK(worst_t < 1e-4);
    // the G-buffer is the same, so every traced texel that sees a surface keeps its history
    CHECK(counter(f[1], "bmfr_history_accepted") > traced * 8 / 10);
    CHECK(counter(f[1], "bmfr_history_rejected") + counter(f[1], "bmfr_history_accepted") +
              counter(f[1], "bmfr_history_off_screen") ==
          traced);
}

TEST_CASE("VP modes: a resumed sequence gives the bits of the whole one") {
    const std::map<std::string, std::string> gaze_moves = {{"gaze", "30,40"}};
    for (const char* mode : {"visual-polar", "acuity"}) {
        CAPTURE(mode);
        const std::vector<FrameResult> whole = run("cornell", mode, 64, 48, 3, {});
        std::vector<Buffer> state;
        for (const Buffer& b : whole[1].buffers) state.push_back(b);
        const std::vector<FrameResult> resumed =
            run("cornell", mode, 64, 48, 1, {}, 1.0f / 30, 2, state);
        CHECK(same_bits(buffer(whole[2], "final"), buffer(resumed[0], "final")));
    }
}

TEST_CASE("VP modes: bad parameters are clear errors") {
    CHECK_THROWS_WITH_AS(run("cornell", "visual-polar", 64, 48, 1, {{"buffer_width", "1"}}),
                         doctest::Contains("visual-polar"), Error);
    CHECK_THROWS_WITH_AS(run("cornell", "linear-falloff", 64, 48, 1,
                             {{"falloff_fovea_deg", "30"}, {"falloff_periphery_deg", "20"}}),
                         doctest::Contains("falloff_periphery_deg"), Error);
    CHECK_THROWS_WITH_AS(run("cornell", "acuity", 64, 48, 1, {{"fill", "grey"}}),
                         doctest::Contains("fill"), Error);
    CHECK_THROWS_WITH_AS(run("cornell", "visual-polar-basic", 64, 48, 1, {{"denoise", "bmfr"}}),
                         doctest::Contains("denoise"), Error);
}

TEST_CASE("VP resolve: the forward table kept for a static gaze gives the per-pixel bits") {
    const VisualPolarMap map = make_visual_polar_map(120, 90, {70.0f, 30.0f}, 80, 60);
    Image color(80, 60, 3), valid(80, 60, 1);
    for (int y = 0; y < 60; ++y)
        for (int x = 0; x < 80; ++x) {
            for (int c = 0; c < 3; ++c)
                color.at(x, y, c) = static_cast<float>((x * 7 + y * 13 + c * 5) % 17) / 16.0f;
            glm::vec2 p;
            valid.at(x, y) = vp_texel_status(map, x, y, p) == VpTexel::traced ? 1.0f : 0.0f;
        }
    const VpMips mips = build_vp_mips(map, color, valid);
    const VpForwardTable table = vp_forward_table(map);
    for (bool mip : {true, false}) {
        ResolveStats a, b;
        CHECK(same_bits(resolve_visual_polar(map, mips, a, mip),
                        resolve_visual_polar(map, mips, b, mip, &table)));
        CHECK(a.pixels_untraced_taps == b.pixels_untraced_taps);
    }
    // BMFR's staircase moves between frames and the stage keeps the table (the same forward
    // map): the levels it holds for rows the pyramid no longer has are recomputed, the same bits
    VisualPolarMap stairs = map;
    stairs.staircase_block = 8;
    VpForwardTable kept = vp_forward_table(stairs);
    int rows_changed = 0;
    for (int i = 0; i < map.width; ++i)
        rows_changed += vp_column_rows(stairs, i) != vp_column_rows(map, i);
    for (const int offset : {3, -2}) {
        stairs.staircase_offset = offset;
        int moved = 0;
        for (int i = 0; i < map.width; ++i)
            moved += vp_column_rows(stairs, i) != vp_column_rows(kept.map, i);
        CHECK(moved > 0);
        kept.map = stairs;
        const VpMips stair_mips = build_vp_mips(stairs, color, valid);
        ResolveStats a, b;
        CHECK(same_bits(resolve_visual_polar(stairs, stair_mips, a, true),
                        resolve_visual_polar(stairs, stair_mips, b, true, &kept)));
    }
    CHECK(rows_changed > 0);
    // a table made for another gaze is refused
    const VpForwardTable other =
        vp_forward_table(make_visual_polar_map(120, 90, {0.0f, 0.0f}, 80, 60));
    ResolveStats c;
    CHECK_THROWS(resolve_visual_polar(map, mips, c, true, &other));
}
