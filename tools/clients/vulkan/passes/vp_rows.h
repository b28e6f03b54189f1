// The Visual-Polar buffer's row count per column, as docs/visual-polar.md gives it, computed on
// the host by the passes that need it (bmfr_fit, vp_resolve):
//   the triangular clip: the fovea's columns c < i_f = round(0.24 w) have
//     clamp(ceil(h (c + 1/2) / i_f - 1/2), 1, h) rows, the periphery's h;
//   BMFR's staircase (mode visual-polar with denoise=bmfr and vp_clip=staircase, the defaults;
//     P5 Fig. 4b): each fovea column takes the triangle's rows at the last column of its BMFR
//     block column, min(32 k + 15 + o, w - 1) with k = (c + 16 - o) div 32 and o the x of the
//     authors' block offset of frame f mod 16 (32 x 32 blocks only).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "tools/clients/vulkan/pass.h"

namespace fovref_client {

/// The x of the BMFR authors' block offset of frame `frame` (their BLOCK_OFFSETS table).
inline int bmfr_block_offset_x(int frame) {
    static const int x[16] = {-14, 4, -8, 8, -10, 2, 12, -10, 12, -8, 6, -2, 6, -16, 14, -6};
    return x[frame % 16];
}

/// Whether the case clips the Visual-Polar fovea as BMFR's staircase.
inline bool vp_staircase(const PassContext& ctx) {
    if (ctx.manifest.at("case").at("mode") != "visual-polar") return false;
    const std::string clip = ctx.param("vp_clip", "staircase");
    if (clip != "staircase" && clip != "triangle")
        throw std::runtime_error("vp_clip must be 'staircase' or 'triangle', got '" + clip + "'");
    if (clip != "staircase" || ctx.param("denoise", "bmfr") != "bmfr") return false;
    ctx.require_bmfr_block_32("the Visual-Polar staircase");
    return true;
}

/// n_c of every column of a w x h buffer in frame `frame`.
inline std::vector<std::int32_t> vp_column_rows(const PassContext& ctx, int width, int height,
                                                int frame) {
    const int fovea = std::clamp(static_cast<int>(std::lround(0.24 * width)), 1, width - 1);
    const auto triangle = [&](int c) {
        if (c >= fovea) return height;
        const float t = static_cast<float>(height) * (static_cast<float>(c) + 0.5f) /
                            static_cast<float>(fovea) -
                        0.5f;
        return std::clamp(static_cast<int>(std::ceil(t)), 1, height);
    };
    const bool staircase = vp_staircase(ctx);
    const int o = bmfr_block_offset_x(frame);
    std::vector<std::int32_t> rows(static_cast<std::size_t>(width));
    for (int c = 0; c < width; ++c) {
        const int k = (c + 16 - o) / 32;
        rows[static_cast<std::size_t>(c)] =
            staircase && c < fovea ? triangle(std::min(32 * k + 15 + o, width - 1)) : triangle(c);
    }
    return rows;
}

}  // namespace fovref_client
