// Meng's KFR passes (ref/log_polar/deferred_sample.h, internal_aa.h, mip_resolve.h, post_aa.h)
// on hand-computed cases, and the kfr mode end to end: the deferred texels equal the rasterized
// G-buffer's pixel under their screen point, a constant buffer survives the mip resolve exactly.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <tuple>

#include "ref/core/simd.h"
#include "ref/filters/internal_aa.h"
#include "ref/filters/post_aa.h"
#include "ref/log_polar/mip_resolve.h"
#include "ref/modes/modes.h"
#include "ref/raster/gbuffer.h"
#include "ref/scene/procedural.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

namespace {

/// A kfr frame's traced texels against the rasterized G-buffer pixel under their screen point,
/// every channel: the (texel, channel) pairs and values compared, the values whose bits differ,
/// and the motion values above 0.01.
struct TexelComparison {
    std::int64_t texel_channels = 0, values = 0, differing = 0, moving = 0;
};
TexelComparison compare_texels(const FrameResult& f) {
    TexelComparison r;
    const Image& valid = f.find("lp_valid")->image;
    const Image& points = f.find("lp_screen_point")->image;
    for (const std::string& channel : gbuffer_names("")) {
        const Image& lp = f.find("lp_gbuffer_" + channel)->image;
        const Image& screen = f.find("gbuffer_" + channel)->image;
        for (int j = 0; j < valid.height; ++j)
            for (int i = 0; i < valid.width; ++i) {
                if (valid.at(i, j) == 0.0f) continue;
                ++r.texel_channels;
                const int x = static_cast<int>(std::floor(points.at(i, j, 0)));
                const int y = static_cast<int>(std::floor(points.at(i, j, 1)));
                for (int c = 0; c < lp.channels; ++c) {
                    const float a = lp.at(i, j, c), b = screen.at(x, y, c);
                    ++r.values;
                    r.differing += std::memcmp(&a, &b, sizeof a) != 0;
                    r.moving += channel == "motion" && std::fabs(a) > 0.01f;
                }
            }
    }
    return r;
}

}  // namespace

TEST_CASE("internal AA: outer half only, wrap on v, clamp on u, renormalised over traced") {
    // 4x3 buffer, value 10 i + j; texels of columns 2, 3 (2 i >= w = 4) are filtered.
    Image color(4, 3, 1, 0.0f), valid(4, 3, 1, 1.0f);
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) color.at(i, j) = static_cast<float>(10 * i + j);
    valid.at(3, 2) = 0.0f;
    const Image out = internal_aa(color, valid);
    CHECK(out.at(0, 1) == 1.0f);   // inner half: unchanged
    CHECK(out.at(1, 2) == 12.0f);  // inner half
    CHECK(out.at(3, 2) == 32.0f);  // untraced: unchanged
    // Texel (2, 0): rows -1 -> 2, 0, 1; columns 1, 2, 3; (3, 2) untraced (weight 2 left out):
    // row 2: 1*12 + 2*22 = 56 (w 3); row 0: 2*10 + 4*20 + 2*30 = 160 (w 8);
    // row 1: 11 + 2*21 + 31 = 84 (w 4): (56 + 160 + 84) / 15 = 20.
    CHECK(out.at(2, 0) == doctest::Approx(300.0 / 15.0).epsilon(1e-6));
    // Texel (3, 1): columns 2, 3, 3 (clamped), rows 0, 1, 2; (3, 2) untraced twice (weights 2, 1).
    const double sum = 1 * 20 + 2 * 30 + 1 * 30 + 2 * 21 + 4 * 31 + 2 * 31 + 1 * 22;
    CHECK(out.at(3, 1) == doctest::Approx(sum / 13.0).epsilon(1e-6));
}

TEST_CASE("internal AA: eight texels at a time (AVX) give internal_aa_texel's bits") {
    if (!cpu_has_avx()) MESSAGE("no AVX on this CPU: both runs take internal_aa_texel");
    test::SplitMix64 rng(21);
    std::int64_t filtered = 0;
    for (const auto& shape : {std::tuple{80, 45, 3}, std::tuple{711, 40, 3}, std::tuple{19, 3, 3},
                              std::tuple{33, 1, 3}, std::tuple{64, 9, 1}})
        for (const std::size_t untraced_rate : {3u, 40u, 1000000u}) {
            const int w = std::get<0>(shape), h = std::get<1>(shape);
            const int channels = std::get<2>(shape);
            Image color(w, h, channels), valid(w, h, 1);
            for (float& v : color.data) v = rng.full_float();  // sums round: order shows
            color.data[color.data.size() / 2] = std::numeric_limits<float>::infinity();
            for (float& v : valid.data) v = rng.below(untraced_rate) == 0 ? 0.0f : 1.0f;
            const Image fast = internal_aa(color, valid);
            set_simd_allowed(false);
            const Image reference = internal_aa(color, valid);
            set_simd_allowed(true);
            INFO(w, "x", h, "x", channels, " untraced 1/", untraced_rate);
            CHECK(test::same_bits_nan_aside(fast, reference));
            for (int y = 0; y < h; ++y)
                for (int x = w / 2; x < w; ++x) filtered += valid.at(x, y) != 0.0f;
        }
    CHECK(filtered > 20000);
}

TEST_CASE("mip pyramid: sizes, wrapped rows, traced children only, constants exact") {
    Image color(5, 3, 1, 0.0f), valid(5, 3, 1, 1.0f);
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 5; ++i) color.at(i, j) = static_cast<float>(10 * i + j);
    valid.at(1, 0) = 0.0f;
    const std::vector<MipLevel> mips = build_lp_mips(color, valid);
    REQUIRE(mips.size() == 4);  // 5x3, 3x2, 2x1, 1x1
    CHECK(mips[1].color.width == 3);
    CHECK(mips[1].color.height == 2);
    CHECK(mips[2].color.width == 2);
    CHECK(mips[2].color.height == 1);
    CHECK(mips[3].color.width == 1);
    // Level 1 (0, 0): children (0, 0), (1, 0) untraced, (0, 1), (1, 1): mean of 0, 1, 11 = 4.
    CHECK(mips[1].color.at(0, 0) == doctest::Approx(4.0).epsilon(1e-6));
    // Level 1 (2, 1): columns 4 (5 does not exist), rows 2 and 3 mod 3 = 0: mean of 42, 40.
    CHECK(mips[1].color.at(2, 1) == 41.0f);
    // A constant buffer with holes stays exactly constant at every level.
    Image flat(37, 23, 3, 0.1f), holes(37, 23, 1, 1.0f);
    test::SplitMix64 rng(3);
    for (float& v : holes.data) v = rng.below(4) == 0 ? 0.0f : 1.0f;
    for (const MipLevel& level : build_lp_mips(flat, holes))
        for (int j = 0; j < level.color.height; ++j)
            for (int i = 0; i < level.color.width; ++i)
                if (level.valid.at(i, j) != 0.0f) REQUIRE(level.color.at(i, j, 1) == 0.1f);
}

TEST_CASE("mip resolve: the level from the Jacobian, and a constant buffer resolves exactly") {
    LogPolarParams params;
    params.sigma = 1.0f;
    params.lp_aspect = 1.0f;
    const LogPolarMap map = make_log_polar_map(params, 200, 100, {100, 50}, 100.0f);
    // alpha = 1, G = 0: radial texels per pixel w / ((1 + r) L), angular h / (2 pi r).
    for (const float r : {3.0f, 20.0f, 60.0f}) {
        const double radial = map.width / ((1.0 + r) * map.log_radius_max);
        const double angular = map.height / (2 * M_PI * r);
        const double expected = std::max(0.0, std::log2(std::max(radial, angular)));
        CHECK(mip_level(map, {100.0f + r, 50.0f}, 9) == doctest::Approx(expected).epsilon(1e-5));
    }
    CHECK(mip_level(map, {100.0f, 50.0f}, 9) == 8.0f);  // at the gaze: the coarsest level
    Image flat(map.width, map.height, 3, 0.7f), valid(map.width, map.height, 1, 1.0f);
    ResolveStats stats;
    const Image out = resolve_log_polar_mip(map, build_lp_mips(flat, valid), {}, stats);
    for (const float v : out.data) REQUIRE(v == 0.7f);
    CHECK(stats.pixels_untraced_taps == 0);
}

TEST_CASE("post AA: the size eta, normalised weights, a filtered impulse by hand") {
    // Meng eq. 2.14 as written: eta = 3 + 2 ceil((t - 0.10) / 0.05), unfiltered below eta 3
    CHECK(post_aa_size(0.0f) == 0);
    CHECK(post_aa_size(0.05f) == 0);                        // ceil(-1) = -1: eta 1
    CHECK(post_aa_size(std::nextafter(0.05f, 1.0f)) == 3);  // ceil(-0.99..) = 0
    CHECK(post_aa_size(0.07f) == 3);
    CHECK(post_aa_size(0.1f) == 3);  // ceil(0) = 0
    CHECK(post_aa_size(std::numeric_limits<float>::quiet_NaN()) == 0);
    CHECK(post_aa_size(0.12f) == 5);   // ceil(0.4) = 1
    CHECK(post_aa_size(0.33f) == 13);  // ceil(4.6) = 5
    CHECK(post_aa_size(1.0f) == 39);
    CHECK(post_aa_size(3.0f) == 39);  // t clamped to 1
    for (int eta = 3; eta <= 39; eta += 2) {
        const std::vector<float> g = post_aa_weights(eta);
        double sum = 0.0;
        for (const float w : g) sum += w;
        CHECK(sum == doctest::Approx(1.0).epsilon(1e-6));
        CHECK(g[0] == g[g.size() - 1]);  // symmetric
    }
    // An impulse at (60, 10), gaze (10.5, 10.5), R = 100: the pixel (r = 50, t = 0.5) has
    // eta = 3 + 2 ceil((0.5 - 0.1) / 0.05) = 19 (8 in binary32, just below 8 exactly) and keeps
    // g(0)^2 of it; its neighbour (61, 10) (t = 0.51: eta 21) gets g(-1) g(0) of its own kernel.
    Image in(80, 20, 1, 0.0f);
    in.at(60, 10) = 1.0f;
    const Image out = post_aa(in, {10.5f, 10.5f}, 100.0f);
    REQUIRE(post_aa_size(0.5f) == 19);
    REQUIRE(post_aa_size(0.51f) == 21);
    const std::vector<float> g19 = post_aa_weights(19), g21 = post_aa_weights(21);
    CHECK(out.at(60, 10) == doctest::Approx(static_cast<double>(g19[9]) * g19[9]).epsilon(1e-6));
    CHECK(out.at(61, 10) == doctest::Approx(static_cast<double>(g21[9]) * g21[10]).epsilon(1e-6));
    CHECK(out.at(12, 10) == 0.0f);  // near the gaze: unfiltered
}

TEST_CASE("post AA: the pass (row sums kept) equals post_aa_pixel bit for bit at every pixel") {
    // Random images of 1-4 channels, screens shorter and narrower than the kernels (heavy
    // clamping), gazes inside, on the edge and far off screen (every size up to 39), an infinite
    // and a NaN value; the AVX groups (eight pixels, of one size or mixed, clamped at the left and
    // right edges or not) and the scalar pass alike.
    test::SplitMix64 rng(11);
    for (const auto& shape : {std::tuple{80, 45, 3}, std::tuple{7, 5, 1}, std::tuple{41, 12, 4},
                              std::tuple{1, 30, 2}, std::tuple{133, 36, 3}, std::tuple{96, 17, 2}})
        for (const glm::vec2& gaze :
             {glm::vec2{40.5f, 20.0f}, glm::vec2{0.0f, 44.0f}, glm::vec2{-300.0f, 900.0f}})
            for (const float radius : {60.0f, 25.0f}) {
                // (not structured bindings: INFO captures them, which clang 14 refuses)
                const int w = std::get<0>(shape), h = std::get<1>(shape);
                const int channels = std::get<2>(shape);
                Image in(w, h, channels, 0.0f);
                for (float& v : in.data)
                    v = static_cast<float>(rng.below(1 << 20)) * 0x1p-18f - 1.0f;
                if (w > 50) {
                    in.at(w / 3, h / 2, 0) = std::numeric_limits<float>::infinity();
                    in.at(w - 3, h / 3, channels - 1) = std::numeric_limits<float>::quiet_NaN();
                }
                const Image out = post_aa(in, gaze, radius);
                const Image scalar = post_aa(in, gaze, radius, false);
                CHECK(std::memcmp(out.data.data(), scalar.data.data(),
                                  out.data.size() * sizeof(float)) == 0);
                // written into storage holding a value no pixel takes (a stage's recycled
                // output), with SIMD and without: every pixel is written
                for (const bool simd : {true, false}) {
                    const Image into = post_aa(in, gaze, radius, simd, nullptr,
                                               test::unwritten_storage(w, h, channels));
                    CHECK(std::memcmp(into.data.data(), scalar.data.data(),
                                      into.data.size() * sizeof(float)) == 0);
                }
                // The sizes kept by the stage: made by a first frame, read by a second with the
                // same gaze, made again for another gaze; the same image each time.
                PostAaSizes sizes;
                const glm::vec2 frames[3] = {gaze, gaze, gaze + glm::vec2(3.0f, -1.0f)};
                for (int frame = 0; frame < 3; ++frame) {
                    const glm::vec2 g = frames[frame];
                    // Kept from the frame before only for the second frame (the same gaze)
                    CHECK(sizes.made_for(g, radius, w, h) == (frame == 1 && cpu_has_avx()));
                    const Image with = post_aa(in, g, radius, true, &sizes);
                    const Image plain = post_aa(in, g, radius, false);
                    CHECK(std::memcmp(with.data.data(), plain.data.data(),
                                      with.data.size() * sizeof(float)) == 0);
                    CHECK(sizes.made_for(g, radius, w, h) == cpu_has_avx());
                }
                std::vector<std::vector<float>> weights(40);
                for (int eta = 3; eta <= 39; eta += 2)
                    weights[static_cast<std::size_t>(eta)] = post_aa_weights(eta);
                Image mine(w, h, channels, 0.0f);
                std::int64_t differing = 0;
                for (int y = 0; y < h; ++y)
                    for (int x = 0; x < w; ++x) {
                        post_aa_pixel(in, gaze, radius, weights, mine, x, y);
                        for (int c = 0; c < channels; ++c) {
                            const float a = out.at(x, y, c), b = mine.at(x, y, c);
                            differing += std::memcmp(&a, &b, sizeof a) != 0;
                        }
                    }
                INFO(w, "x", h, "x", channels, " gaze (", gaze.x, ", ", gaze.y, ") R ", radius);
                CHECK(differing == 0);
            }
}

TEST_CASE(
    "kfr: the texels, moving and jittered, equal the G-buffer's pixel, nothing dumped, the same "
    "bits") {
    // A moving camera (motion vectors) under TAA's jitter, in the rasterizer (raster_jitter=raster,
    // the default) or added to the texels' points (lookup). A render that wants only the final
    // image lets gbuffer_raster skip its attribute pass (only the ids, and TAA's depths, are made):
    // lp_sample's buffers and the final image must keep their bits.
    const Scene scene = make_procedural_scene("glossy-floor");
    for (const char* jitter : {"raster", "lookup"}) {
        CAPTURE(jitter);
        RenderSettings s;
        s.width = 80;
        s.height = 45;
        s.frame_count = 3;
        s.params.set("taa", "depth");
        s.params.set("raster_jitter", jitter);
        s.requested = {"all"};
        const std::vector<FrameResult> all = render(&scene, "kfr", s);
        s.requested = {"final", "lp_gbuffer_motion", "lp_gbuffer_albedo"};
        const std::vector<FrameResult> lean = render(&scene, "kfr", s);
        // Without the SIMD paths (lp_sample's fragments eight at a time, the rasterizer's, the
        // resolve's): the same bits again.
        set_simd_allowed(false);
        const std::vector<FrameResult> scalar = render(&scene, "kfr", s);
        set_simd_allowed(true);
        for (std::size_t k = 0; k < all.size(); ++k) {
            CAPTURE(k);
            const FrameResult& f = all[k];
            const TexelComparison compared = compare_texels(f);
            const std::int64_t differing = compared.differing, moving = compared.moving;
            CHECK(differing == 0);
            if (k > 0) CHECK(moving > 0);  // the camera moves: the texels' motion is not 0
            // Without dumps: no attribute channel of the screen G-buffer is made
            CHECK(lean[k].find("gbuffer_albedo") == nullptr);
            CHECK(lean[k].find("gbuffer_world_position") == nullptr);
            for (const char* name : {"final", "lp_gbuffer_motion", "lp_gbuffer_albedo"}) {
                CHECK(bit_equal(lean[k].find(name)->image, f.find(name)->image));
                CHECK(bit_equal(scalar[k].find(name)->image, f.find(name)->image));
            }
        }
    }
}

TEST_CASE("kfr: deferred texels equal the rasterized G-buffer's pixel under their point") {
    const Scene scene = make_procedural_scene("checker-room");
    RenderSettings s;
    s.width = 96;
    s.height = 54;
    s.requested = {"all"};
    const FrameResult f = render(&scene, "kfr", s).at(0);
    const Image& valid = f.find("lp_valid")->image;
    CHECK(valid.width == 53);  // round(96 / 1.8)
    CHECK(valid.height == 30);
    // Every channel, bit for bit: lp_sample makes the pixel again from its primitive id
    // (write_rasterized_pixel) instead of copying it, which must not show.
    const TexelComparison compared = compare_texels(f);
    CHECK(compared.differing == 0);
    const std::int64_t sampled = compared.texel_channels;
    CHECK(sampled == 9 * f.counters.get("texels_traced"));
    CHECK(f.counters.get("rays_primary") == 0);  // no primary rays: the rasterizer's G-buffer
    CHECK(f.counters.get("raster_fragments_written") > 0);
    for (const char* name : {"lp_color_aa", "resolved", "final"}) CHECK(f.find(name) != nullptr);
    // a_G > 0 with the deferred variant is refused.
    s.params.set("gaze_angle", "0.1");
    CHECK(test::contains(test::error_message([&] { render(&scene, "kfr", s); }),
                         "the deferred variant has no gaze buffer"));
}
