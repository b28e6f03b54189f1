#include "ref/log_polar/resolve_decisions.h"

#include <algorithm>
#include <cmath>

#include "ref/core/dmath.h"
#include "ref/core/error.h"

namespace fovref {

float floor_margin(float x, int lo, int hi) {
    if (lo > hi || !std::isfinite(x)) return no_threshold;
    const float k = std::clamp(std::round(x), static_cast<float>(lo), static_cast<float>(hi));
    return std::fabs(x - k);
}

float wrap_margin(float x) {
    if (!std::isfinite(x)) return no_threshold;
    return std::fabs(x - std::round(x));
}

TapDecision lp_tap_decision(glm::vec2 uv, int width, int height) {
    const BilinearLookup l = lp_bilinear_index(width, height, uv);
    return {l.i0, l.j0,
            std::min(floor_margin(uv.x - 0.5f, 1, width - 1), wrap_margin(uv.y - 0.5f))};
}

ResolveDecisions lp_resolve_decisions(const ForwardTable& table, const GazeInput& gaze, int width,
                                      int height) {
    const LogPolarMap& map = table.map;
    const int sw = map.screen_width, sh = map.screen_height;
    FOVREF_CHECK(table.uv.size() == static_cast<std::size_t>(sw) * sh,
                 "a forward table of another size than its screen");
    // Each level's size: ceil halves, as build_lp_mips makes them
    const int levels = std::max(table.mip_levels, 1);
    std::vector<glm::ivec2> size = {{width, height}};
    while (static_cast<int>(size.size()) < levels)
        size.emplace_back((size.back().x + 1) / 2, (size.back().y + 1) / 2);
    ResolveDecisions d;
    d.tap = Image(sw, sh, 2, -1.0f);
    d.tap_margin = Image(sw, sh, 1, no_threshold);
    if (table.mip_levels > 0) {
        d.mip_level = Image(sw, sh, 1, -1.0f);
        d.mip_margin = Image(sw, sh, 1, no_threshold);
    }
    for (int y = 0; y < sh; ++y)
        for (int x = 0; x < sw; ++x) {
            if (reads_gaze_buffer(map, gaze, x, y)) continue;
            const std::size_t k = static_cast<std::size_t>(y) * sw + x;
            int l0 = 0;
            if (table.mip_levels > 0) {
                const float lambda = table.mip_lambda[k];
                l0 = static_cast<int>(
                    std::floor(std::clamp(lambda, 0.0f, static_cast<float>(levels - 1))));
                d.mip_level.at(x, y) = static_cast<float>(l0);
                d.mip_margin.at(x, y) = floor_margin(lambda, 1, levels - 1);
            }
            // (u, v) / 2^l0, exact: a power of two
            const float scale = 1.0f / static_cast<float>(1 << l0);  // exact: 2^-l0
            const glm::vec2 uv = table.uv[k] * scale;
            const glm::ivec2 n = size[static_cast<std::size_t>(l0)];
            const TapDecision tap = lp_tap_decision(uv, n.x, n.y);
            d.tap.at(x, y, 0) = static_cast<float>(tap.i0);
            d.tap.at(x, y, 1) = static_cast<float>(tap.j0);
            d.tap_margin.at(x, y) = tap.margin;
        }
    return d;
}

ResolveDecisions stereo_resolve_decisions(const StereoForwardTable& table, int width, int height) {
    const int sw = table.maps[0].screen_width * 2, sh = table.maps[0].screen_height;
    FOVREF_CHECK(table.uv.size() == static_cast<std::size_t>(sw) * sh,
                 "a stereo lookup table of another size than its screen");
    const int eye_width = width / 2;
    ResolveDecisions d;
    d.tap = Image(sw, sh, 2, -1.0f);
    d.tap_margin = Image(sw, sh, 1, no_threshold);
    for (int y = 0; y < sh; ++y)
        for (int x = 0; x < sw; ++x) {
            const std::size_t k = static_cast<std::size_t>(y) * sw + x;
            if (table.in_lens[k] == 0) continue;
            const int eye = x / table.maps[0].screen_width;
            const TapDecision tap = lp_tap_decision(table.uv[k], eye_width, height);
            d.tap.at(x, y, 0) = static_cast<float>(eye * eye_width + tap.i0);
            d.tap.at(x, y, 1) = static_cast<float>(tap.j0);
            d.tap_margin.at(x, y) = tap.margin;
        }
    return d;
}

}  // namespace fovref
