#include "ref/log_polar/mip_resolve.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/core/vec.h"
#include "ref/log_polar/resolve_avx.h"

namespace fovref {

namespace {

MipLevel downsample(const MipLevel& in) {
    const int w = in.color.width, h = in.color.height, channels = in.color.channels;
    const int w2 = (w + 1) / 2, h2 = (h + 1) / 2;
    MipLevel out{Image(w2, h2, channels, 0.0f), Image(w2, h2, 1, 0.0f)};
    for (int j = 0; j < h2; ++j)
        for (int i = 0; i < w2; ++i) {
            const int rows[2] = {2 * j, (2 * j + 1) % h};
            const int cols[2] = {2 * i, 2 * i + 1};
            // The running mean m += (x - m) / k: equal children give exactly their value.
            float mean[4] = {0, 0, 0, 0};
            int count = 0;
            for (const int y : rows)
                for (const int x : cols) {
                    if (x >= w || in.valid.at(x, y) == 0.0f) continue;
                    ++count;
                    for (int c = 0; c < channels; ++c)
                        mean[c] += (in.color.at(x, y, c) - mean[c]) / static_cast<float>(count);
                }
            if (count == 0) continue;
            out.valid.at(i, j) = 1.0f;
            for (int c = 0; c < channels; ++c) out.color.at(i, j, c) = mean[c];
        }
    return out;
}

}  // namespace

std::vector<MipLevel> build_lp_mips(const Image& color, const Image& valid) {
    FOVREF_CHECK(color.channels <= 4, "a mip pyramid of more than 4 channels");
    std::vector<MipLevel> levels = {{color, valid}};
    while (levels.back().color.width > 1 || levels.back().color.height > 1)
        levels.push_back(downsample(levels.back()));
    return levels;
}

float mip_lambda(const LogPolarMap& map, glm::vec2 c) {
    const float r = std::max(gaze_distance(map.gaze, c), 0x1p-10f);
    const TexelsPerPixel s = texels_per_pixel(map, r);
    return dm::log2(std::max(s.radial, s.angular));
}

float mip_level(const LogPolarMap& map, glm::vec2 c, int levels) {
    return std::clamp(mip_lambda(map, c), 0.0f, static_cast<float>(levels - 1));
}

void resolve_mip_pixel(const LogPolarMap& map, const std::vector<MipLevel>& mips,
                       const GazeInput& gaze, Image& out, int x, int y, ResolveStats& stats,
                       float* lambda_out, const ForwardTable* table) {
    float* pixel = &out.at(x, y, 0);
    if (gaze_pixel(map, gaze, x, y, pixel, out.channels, stats)) return;
    ++stats.pixels_from_buffer;
    const glm::vec2 centre = pixel_centre(x, y);
    const std::size_t k = static_cast<std::size_t>(y) * map.screen_width + x;
    const int levels = static_cast<int>(mips.size());
    const float lambda =
        table ? std::clamp(table->mip_lambda[k], 0.0f, static_cast<float>(levels - 1))
              : mip_level(map, centre, levels);
    if (lambda_out) *lambda_out = lambda;
    const glm::vec2 uv = table ? table->uv[k] : lp_forward(map, centre);
    const int l0 = static_cast<int>(std::floor(lambda));
    const int l1 = std::min(l0 + 1, levels - 1);
    const float f = lambda - static_cast<float>(l0);
    float a[4] = {0, 0, 0, 0}, b[4] = {0, 0, 0, 0};
    const auto sample = [&](int level, float* value) {
        const MipLevel& m = mips[static_cast<std::size_t>(level)];
        const float scale = 1.0f / static_cast<float>(1 << level);  // exact: 2^-level
        return sample_lp_bilinear(m.color, m.valid, {uv.x * scale, uv.y * scale}, value);
    };
    const bool have_a = sample(l0, a);
    const bool have_b = l1 != l0 && f > 0.0f && sample(l1, b);
    for (int c = 0; c < out.channels; ++c) {
        if (have_a && have_b)
            pixel[c] = a[c] + f * (b[c] - a[c]);
        else if (have_a)
            pixel[c] = a[c];
        else
            pixel[c] = b[c];
    }
    if (!have_a && !have_b) ++stats.pixels_untraced_taps;
}

Image resolve_log_polar_mip(const LogPolarMap& map, const std::vector<MipLevel>& mips,
                            const GazeInput& gaze, ResolveStats& stats, const ForwardTable* table,
                            Image storage) {
    FOVREF_CHECK(!mips.empty(), "an empty mip pyramid");
    if (table)
        FOVREF_CHECK(table->map == map && table->mip_levels == static_cast<int>(mips.size()),
                     "a forward table made for another map or pyramid");
    FOVREF_CHECK_EQ(mips[0].color.width, map.width, "log-polar buffer width");
    Image out = std::move(storage);  // every pixel is written below
    keep_or_make(out, map.screen_width, map.screen_height, mips[0].color.channels);
    // Eight pixels at a time where the AVX2 path covers the resolve (the same bits:
    // resolve_avx.h); resolve_mip_pixel, the reference, does the rest.
    const bool avx = resolve_mip_avx_applies(map, mips, table);
    for (int y = 0; y < map.screen_height; ++y)
        for (int x = avx ? resolve_mip_row_avx(map, mips, gaze, *table, out, y, stats) : 0;
             x < map.screen_width; ++x)
            resolve_mip_pixel(map, mips, gaze, out, x, y, stats, nullptr, table);
    return out;
}

}  // namespace fovref
