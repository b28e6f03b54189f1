// Stereo foveated ray casting (ref/log_polar/stereo.h, Gupta 2019): each eye's half of the
// side-by-side buffer is the mono pass with that eye's camera and map, IPD 0 gives two equal
// eyes, the barrel distortion by hand, and bad parameters.
#include <doctest/doctest.h>

#include <cstring>

#include "ref/bvh/bvh.h"
#include "ref/log_polar/stereo.h"
#include "ref/modes/modes.h"
#include "ref/scene/procedural.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

namespace {

bool same_texel(const Image& a, int ax, const Image& b, int bx, int y) {
    for (int c = 0; c < a.channels; ++c) {
        const float va = a.at(ax, y, c), vb = b.at(bx, y, c);
        if (std::memcmp(&va, &vb, sizeof va) != 0) return false;
    }
    return true;
}

}  // namespace

TEST_CASE("stereo: each eye's half is the mono pass with the eye's camera and map") {
    const Scene scene = make_procedural_scene("cornell");
    const Bvh bvh = build_bvh(scene.positions);
    StereoParams params = parse_stereo_params(
        Params(std::map<std::string, std::string>{{"ipd", "0.2"}, {"gaze", "30,20"}}));
    const Camera camera = camera_at(scene, 0.0f);
    const std::array<LogPolarMap, 2> maps = stereo_maps(params, scene, camera, 96, 54, 0);
    CHECK(maps[0].screen_width == 48);
    CHECK(maps[0].gaze == glm::vec2(30, 20));
    const std::array<Camera, 2> eyes = {eye_camera(camera, 0, 0.2f), eye_camera(camera, 1, 0.2f)};
    CHECK(eyes[1].position.x - eyes[0].position.x == doctest::Approx(0.2).epsilon(1e-6));
    Image points;
    FoveatedTraceStats stats;
    const MaskedGBuffer both =
        trace_stereo_gbuffer(maps, eye_views(scene, bvh, eyes, eyes), points, stats);
    const int w = maps[0].width;
    REQUIRE(both.valid.width == 2 * w);
    for (int eye = 0; eye < 2; ++eye) {
        Image mono_points;
        FoveatedTraceStats mono_stats;
        const Camera& camera_of_eye = eyes[static_cast<std::size_t>(eye)];
        const MaskedGBuffer mono = trace_lp_gbuffer(
            maps[static_cast<std::size_t>(eye)],
            PrimaryView(scene, bvh, camera_of_eye, camera_of_eye), mono_points, mono_stats);
        for (int j = 0; j < maps[0].height; ++j)
            for (int i = 0; i < w; ++i) {
                REQUIRE(same_texel(both.valid, eye * w + i, mono.valid, i, j));
                REQUIRE(same_texel(both.gbuffer.primitive_id, eye * w + i,
                                   mono.gbuffer.primitive_id, i, j));
                REQUIRE(same_texel(both.gbuffer.world_position, eye * w + i,
                                   mono.gbuffer.world_position, i, j));
                CHECK(points.at(eye * w + i, j, 0) ==
                      mono_points.at(i, j, 0) + static_cast<float>(48 * eye));
            }
    }
}

TEST_CASE("stereo: IPD 0 gives two equal eyes, counters, the barrel distortion by hand") {
    const Scene scene = make_procedural_scene("checker-room");
    RenderSettings s;
    s.width = 96;
    s.height = 54;
    s.requested = {"all"};
    s.params = Params(std::map<std::string, std::string>{{"ipd", "0"}});
    const FrameResult f = render(&scene, "stereo-lp", s).at(0);
    CHECK(f.counters.get("eyes") == 2);
    // sigma = sqrt 2 per 48x54 eye: w = round(48 / 1.414) = 34, h = round(54 / 1.414) = 38.
    CHECK(f.counters.get("buffer_width") == 34);
    CHECK(f.counters.get("buffer_height") == 38);
    const Image& ids = f.find("lp_gbuffer_primitive_id")->image;
    for (int j = 0; j < ids.height; ++j)
        for (int i = 0; i < 34; ++i) REQUIRE(ids.at(i, j) == ids.at(34 + i, j));
    const Image& out = f.find("final")->image;
    std::int64_t equal = 0;
    for (int y = 0; y < 54; ++y)
        for (int x = 0; x < 48; ++x) equal += out.at(x, y, 1) == out.at(48 + x, y, 1);
    CHECK(equal > 0);  // shading noise differs (rand's texel index), the geometry does not
    CHECK(f.counters.get("rays_primary") == f.counters.get("texels_traced"));

    // Barrel: the centre maps to itself; on a 48-wide eye (half-width 24) the point q = (1, 0)
    // maps to 24 (1 + 0.22 + 0.24) = 35.04 px from the centre, q = (0.5, 0) to
    // 12 (1 + 0.22 / 4 + 0.24 / 16) = 12.84 px.
    const glm::vec2 centre{24, 27};
    CHECK(barrel_source(centre, 48, 54, 0.22f, 0.24f) == centre);
    CHECK(barrel_source({48, 27}, 48, 54, 0.22f, 0.24f).x == doctest::Approx(24 + 35.04));
    CHECK(barrel_source({36, 27}, 48, 54, 0.22f, 0.24f).x == doctest::Approx(24 + 12.84));
    CHECK(barrel_source({24, 39}, 48, 54, 0.22f, 0.24f).y == doctest::Approx(27 + 12.84));
    // k1 = k2 = 0: the identity, so the image equals the one without distortion.
    RenderSettings flat = s;
    flat.params =
        Params(std::map<std::string, std::string>{{"barrel", "on"}, {"k1", "0"}, {"k2", "0"}});
    RenderSettings plain = s;
    plain.params = Params();
    const FrameResult a = render(&scene, "stereo-lp", flat).at(0);
    const FrameResult b = render(&scene, "stereo-lp", plain).at(0);
    CHECK(a.counters.get("screen_pixels_outside_lens") == 0);
    const Image& ia = a.find("final")->image;
    const Image& ib = b.find("final")->image;
    CHECK(std::memcmp(ia.data.data(), ib.data.data(), ia.data.size() * sizeof(float)) == 0);
    // The default distortion pushes the eyes' corners outside the lens: black and counted.
    RenderSettings lens = s;
    lens.params = Params(std::map<std::string, std::string>{{"barrel", "on"}});
    const FrameResult c = render(&scene, "stereo-lp", lens).at(0);
    CHECK(c.counters.get("screen_pixels_outside_lens") > 0);
    CHECK(c.find("final")->image.at(0, 0, 0) == 0.0f);
}

TEST_CASE("stereo: bad parameters are refused with their names") {
    const Scene scene = make_procedural_scene("cornell");
    const auto message = [&](int width, std::map<std::string, std::string> params) {
        RenderSettings s;
        s.width = width;
        s.height = 9;
        s.params = Params(std::move(params));
        return test::error_message([&] { render(&scene, "stereo-lp", s); });
    };
    CHECK(test::contains(message(15, {}), "the width 15 is odd"));
    CHECK(test::contains(message(16, {{"k1", "0.3"}}), "add barrel=on"));
    CHECK(test::contains(message(16, {{"ipd", "-1"}}), "parameter 'ipd'"));
    CHECK(test::contains(message(16, {{"gaze_angle", "0.2"}}), "not a parameter of mode"));
    CHECK(test::contains(message(16, {{"barrel", "maybe"}}), "parameter 'barrel'"));
    CHECK(test::contains(message(16, {{"blur", "gauss"}}), "parameter 'blur'"));
}

TEST_CASE("stereo: Gupta's pre-resolve blur is Meng's internal AA within each eye's half") {
    // Two 4 x 3 eyes side by side: eye 0 holds 10 i + j, eye 1 1000 + the same. The outer half
    // of each eye (eye-local columns 2, 3) is filtered; its columns clamp within the eye, so eye
    // 0's column 3 never reads eye 1's column 4 (which would pull it towards 1000).
    Image color(8, 3, 1, 0.0f), valid(8, 3, 1, 1.0f);
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 8; ++i)
            color.at(i, j) = static_cast<float>((i >= 4 ? 1000 : 0) + 10 * (i % 4) + j);
    const Image out = stereo_internal_aa(color, valid);
    for (int j = 0; j < 3; ++j) {
        CHECK(out.at(0, j) == color.at(0, j));  // inner half: unchanged
        CHECK(out.at(5, j) == color.at(5, j));
        CHECK(out.at(3, j) < 100.0f);  // clamped within eye 0
        CHECK(out.at(4, j) == color.at(4, j));
    }
    // Eye-local texel (3, 1): columns 2, 3, 3 (clamped), rows 0, 1, 2, weights [1 2 1; 2 4 2;
    // 1 2 1]: (20 + 2 30 + 30 + 2 21 + 4 31 + 2 31 + 22 + 2 32 + 32) / 16
    const double expected = (20 + 60 + 30 + 42 + 124 + 62 + 22 + 64 + 32) / 16.0;
    CHECK(out.at(3, 1) == doctest::Approx(expected).epsilon(1e-6));
    CHECK(out.at(7, 1) == doctest::Approx(1000 + expected).epsilon(1e-6));
    // In the mode: lp_color_aa is written and pass 2 reads it; pixels whose taps all lie in the
    // inner halves are unchanged, the periphery is smoother
    const Scene scene = make_procedural_scene("checker-room");
    RenderSettings s;
    s.width = 96;
    s.height = 54;
    s.requested = {"all"};
    const FrameResult plain = render(&scene, "stereo-lp", s).at(0);
    s.params = Params(std::map<std::string, std::string>{{"blur", "internal_aa"}});
    const FrameResult blurred = render(&scene, "stereo-lp", s).at(0);
    REQUIRE(blurred.find("lp_color_aa") != nullptr);
    CHECK(plain.find("lp_color_aa") == nullptr);
    const Image expected_aa =
        stereo_internal_aa(blurred.find("lp_color")->image, blurred.find("lp_valid")->image);
    CHECK(std::memcmp(blurred.find("lp_color_aa")->image.data.data(), expected_aa.data.data(),
                      expected_aa.data.size() * sizeof(float)) == 0);
    const Image& a = plain.find("final")->image;
    const Image& b = blurred.find("final")->image;
    const Image& taps = plain.find("resolve_tap")->image;
    const auto w = static_cast<int>(plain.counters.get("buffer_width"));
    std::int64_t inner = 0, changed = 0;
    for (int y = 0; y < 54; ++y)
        for (int x = 0; x < 96; ++x) {
            // i0 + 1 < w/2 within its eye: both columns read lie in the inner half
            const int i0 = static_cast<int>(taps.at(x, y, 0)) % w;
            const bool differs =
                std::memcmp(&a.data[a.index(x, y)], &b.data[b.index(x, y)], 3 * sizeof(float)) != 0;
            if (2 * (i0 + 1) < w) {
                ++inner;
                REQUIRE_FALSE(differs);
            }
            changed += differs ? 1 : 0;
        }
    CHECK(inner > 0);
    CHECK(changed > 0);
}

TEST_CASE("stereo: pass 2 from the kept lookup table gives the same bits") {
    const Scene scene = make_procedural_scene("cornell");
    const StereoParams params = parse_stereo_params(
        Params(std::map<std::string, std::string>{{"barrel", "on"}, {"gaze", "20,30"}}));
    const std::array<LogPolarMap, 2> maps =
        stereo_maps(params, scene, camera_at(scene, 0.0f), 96, 54, 0);
    Image color(2 * maps[0].width, maps[0].height, 3, 0.0f);
    Image valid(color.width, color.height, 1, 1.0f);
    test::SplitMix64 rng(5);
    for (float& v : color.data) v = rng.unit();
    for (float& v : valid.data) v = rng.below(5) == 0 ? 0.0f : 1.0f;
    StereoResolveStats a, b;
    const StereoForwardTable table = stereo_forward_table(params, maps);
    CHECK(table.made_for(params, maps));
    const Image direct = resolve_stereo(params, maps, color, valid, a);
    const Image cached = resolve_stereo(params, maps, color, valid, b, &table);
    CHECK(std::memcmp(direct.data.data(), cached.data.data(), direct.data.size() * 4) == 0);
    CHECK(a.pixels_outside_lens == b.pixels_outside_lens);
    CHECK(a.resolve.pixels_untraced_taps == b.resolve.pixels_untraced_taps);
}
