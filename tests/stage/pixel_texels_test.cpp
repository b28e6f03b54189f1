// Each foveated mode's description of how a screen pixel maps to the buffer texels pass 2 reads
// for it (ModeInfo::pixel_texels), checked against pass 2 itself: with every texel traced, a
// buffer that is 1 on the texels named and 0 elsewhere resolves to exactly 1 at the pixel, and
// one that is 0 there and 1 elsewhere to exactly 0. So the pixel reads those texels and no
// other (a missing tap, a tap in the wrong row or column, or the wrong buffer fails).
#include <doctest/doctest.h>

#include <array>

#include "ref/image/image.h"
#include "ref/log_polar/params.h"
#include "ref/log_polar/resolve.h"
#include "ref/log_polar/stereo.h"
#include "ref/log_polar/trace.h"
#include "ref/modes/modes.h"
#include "ref/scene/procedural.h"
#include "ref/visual_polar/params.h"
#include "ref/visual_polar/resolve.h"

using namespace fovref;

namespace {

constexpr int width = 48, height = 28;

RenderSettings settings_with(std::map<std::string, std::string> params) {
    RenderSettings s;
    s.width = width;
    s.height = height;
    s.params = Params(std::move(params));
    return s;
}

// An RGB buffer of `size` that is `inside` on `texels` and `outside` elsewhere.
Image indicator(glm::ivec2 size, const std::vector<glm::ivec2>& texels, float inside,
                float outside) {
    Image image(size.x, size.y, 3, outside);
    for (const glm::ivec2& t : texels)
        for (int c = 0; c < 3; ++c) image.at(t.x, t.y, c) = inside;
    return image;
}

std::vector<glm::ivec2> texels_of(const std::vector<TexelRead>& reads, const std::string& family) {
    std::vector<glm::ivec2> texels;
    for (const TexelRead& r : reads)
        if (r.family == family) texels.push_back(r.texel);
    return texels;
}

// Pass 2 of a log-polar mode at pixel (x, y) with every texel traced.
float resolve_lp(const LogPolarMap& map, const Image& lp, const Image& gaze, int x, int y) {
    const Image valid(map.width, map.height, 1, 1.0f);
    Image out(width, height, 3, 0.0f);
    ResolveStats stats;
    resolve_pixel(map, {lp, valid, gaze_input(map, map.has_gaze_buffer() ? &gaze : nullptr)}, out,
                  x, y, stats);
    return out.at(x, y, 0);
}

void check_log_polar(const std::string& mode) {
    const Scene scene = make_procedural_scene("cornell");
    const RenderSettings s = settings_with({{"gaze", "30,9"}});
    const LogPolarMap map =
        foveated_map(parse_foveated_params(s.params, find_foveation_preset(mode)), scene,
                     camera_at(scene, 0.0f), width, height, 0);
    const ScreenWindow window = gaze_window(map);
    int from_gaze = 0;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const std::vector<TexelRead> reads = find_mode(mode).pixel_texels(scene, s, 0, x, y);
            INFO(mode << " pixel (" << x << ", " << y << ")");
            REQUIRE(!reads.empty());
            const std::vector<glm::ivec2> lp = texels_of(reads, "lp_"),
                                          gaze = texels_of(reads, "gaze_");
            REQUIRE(lp.size() + gaze.size() == reads.size());
            from_gaze += gaze.empty() ? 0 : 1;
            const glm::ivec2 lp_size{map.width, map.height}, gaze_size{window.width, window.height};
            CHECK(resolve_lp(map, indicator(lp_size, lp, 1, 0), indicator(gaze_size, gaze, 1, 0), x,
                             y) == 1.0f);
            CHECK(resolve_lp(map, indicator(lp_size, lp, 0, 1), indicator(gaze_size, gaze, 0, 1), x,
                             y) == 0.0f);
        }
    CHECK((from_gaze > 0) == map.has_gaze_buffer());
}

}  // namespace

TEST_CASE("pixel texels: a log-polar pixel reads exactly the texels its mode names") {
    check_log_polar("kfov");
    check_log_polar("cfov");  // with the gaze buffer: its pixels read the gaze buffer only
}

TEST_CASE("pixel texels: a stereo pixel reads exactly the texels of its eye's half") {
    const Scene scene = make_procedural_scene("cornell");
    const RenderSettings s = settings_with({});
    const StereoParams params = parse_stereo_params(s.params);
    const std::array<LogPolarMap, 2> maps =
        stereo_maps(params, scene, camera_at(scene, 0.0f), width, height, 0);
    const int w = maps[0].width, h = maps[0].height;
    const std::array<Image, 2> valid = {Image(w, h, 1, 1.0f), Image(w, h, 1, 1.0f)};
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const std::vector<TexelRead> reads =
                find_mode("stereo-lp").pixel_texels(scene, s, 0, x, y);
            const std::vector<glm::ivec2> texels = texels_of(reads, "lp_");
            INFO("pixel (" << x << ", " << y << ")");
            REQUIRE(texels.size() == reads.size());
            const int eye = x / (width / 2);
            for (const glm::ivec2& t : texels) CHECK(t.x / w == eye);
            for (const auto& [inside, outside] : {std::pair{1.0f, 0.0f}, std::pair{0.0f, 1.0f}}) {
                const Image both = indicator({2 * w, h}, texels, inside, outside);
                const std::array<Image, 2> colors = {image_columns(both, 0, w),
                                                     image_columns(both, w, w)};
                Image out(width, height, 3, 0.0f);
                StereoResolveStats stats;
                resolve_stereo_pixel(params, maps, colors, valid, out, x, y, stats);
                CHECK(out.at(x, y, 0) == inside);
            }
        }
}

TEST_CASE("pixel texels: a Visual-Polar pixel reads exactly the texels its mode names") {
    const Scene scene = make_procedural_scene("cornell");
    const RenderSettings s = settings_with({{"gaze", "20,15"}});
    const VisualPolarMap map =
        sparse_vp_map(parse_sparse_params(s.params, "visual-polar-basic"), width, height, 0);
    Image valid(map.width, map.height, 1, 0.0f);
    for (int i = 0; i < map.width; ++i)
        for (int j = 0; j < vp_column_rows(map, i); ++j) valid.at(i, j) = 1.0f;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const std::vector<TexelRead> reads =
                find_mode("visual-polar-basic").pixel_texels(scene, s, 0, x, y);
            const std::vector<glm::ivec2> texels = texels_of(reads, "vp_");
            INFO("pixel (" << x << ", " << y << ")");
            REQUIRE(!texels.empty());
            REQUIRE(texels.size() == reads.size());
            for (const auto& [inside, outside] : {std::pair{1.0f, 0.0f}, std::pair{0.0f, 1.0f}}) {
                const VpMips mips = build_vp_mips(
                    map, indicator({map.width, map.height}, texels, inside, outside), valid);
                Image out(width, height, 3, 0.0f);
                ResolveStats stats;
                resolve_vp_pixel(map, mips, out, x, y, stats, nullptr, false);
                CHECK(out.at(x, y, 0) == inside);
            }
        }
}

TEST_CASE("pixel texels: modes whose pixels read screen images name none") {
    for (const char* mode : {"basic", "pathtrace", "splat"})
        CHECK_FALSE(static_cast<bool>(find_mode(mode).pixel_texels));
    CHECK(buffer_space(find_mode("cfov"), "lp_color") == BufferSpace::texel);
    CHECK(buffer_space(find_mode("cfov"), "gaze_color") == BufferSpace::screen_window);
    CHECK(buffer_space(find_mode("cfov"), "final") == BufferSpace::screen);
    CHECK(buffer_space(find_mode("stereo-lp"), "lp_valid") == BufferSpace::stereo_texel);
    CHECK(buffer_space(find_mode("visual-polar"), "vp_color") == BufferSpace::texel);
    CHECK(buffer_space(find_mode("acuity"), "acuity_point") == BufferSpace::samples);
    CHECK(buffer_space(find_mode("acuity"), "acuity_sum") == BufferSpace::screen);
}
