// Pass 2 with mipmap interpolation (Meng 2018 §5.1 "mipmap interpolation"; SPEC §6, `resolve=mip`,
// the KFR preset's default): near the gaze point one screen pixel covers many buffer texels, so
// the buffer is prefiltered into a pyramid and each pixel samples the level that matches its
// footprint.
//
// Pyramid (build_lp_mips): level 0 is the buffer and its validity mask; level k + 1 has
//   w' = ceil(w / 2) columns and h' = ceil(h / 2) rows; its texel (i, j) averages the traced
//   texels among level k's columns {2i, 2i + 1} (those < w) and rows {2j, (2j + 1) mod h} (rows
//   wrap), in the order (2i, 2j), (2i + 1, 2j), (2i, 2j + 1), (2i + 1, 2j + 1), as the running
//   mean m_k = m_(k-1) + (x_k - m_(k-1)) / k in binary32 (m_0 = 0: a constant stays exactly that
//   constant); it is traced when one of them is. Levels until 1 x 1. Level l's texel i covers
//   level 0's texels [2^l i, 2^l (i + 1)); where h is not a multiple of 2^l, a level's last row
//   wraps onto its first rows.
// Level of a screen point c outside the gaze circle (mip_level): with r = max(|c - g|, 2^-10),
//   rho = ln(1 + r) / L, the buffer texels per screen pixel are
//     radial   s_u = w K'(rho) / ((1 + r) L (1 - G))      (du/dr)
//     angular  s_v = h / (2 pi r)                          (dv per pixel along the circle)
//   lambda = log2(max(s_u, s_v)), clamped to [0, levels - 1].
// Lookup (resolve_mip_pixel): (u, v) = lp_forward(c); levels l0 = floor(lambda) and l0 + 1 (if
//   it exists) are each sampled with sample_lp_bilinear at (u / 2^l, v / 2^l) over their traced
//   texels; the two are lerped with f = lambda - l0 (a level without a traced tap gives way to
//   the other; neither: black, counted). Inside the gaze circle the gaze buffer's pixel, as the
//   bilinear resolve.
#pragma once

#include <vector>

#include "ref/image/image.h"
#include "ref/log_polar/map.h"
#include "ref/log_polar/resolve.h"

namespace fovref {

struct MipLevel {
    Image color;
    Image valid;
};

/// The pyramid of a buffer (level 0 = the buffer itself).
std::vector<MipLevel> build_lp_mips(const Image& color, const Image& valid);

/// The pyramid level (continuous) of screen point c before its clamp: log2(max(s_u, s_v)).
float mip_lambda(const LogPolarMap& map, glm::vec2 c);
/// The pyramid level (continuous) of screen point c, for a pyramid of `levels` levels: mip_lambda
/// clamped to [0, levels - 1].
float mip_level(const LogPolarMap& map, glm::vec2 c, int levels);

/// Per-pixel work of the mip resolve: screen pixel (x, y) of `out`. `lambda` (optional)
/// receives the level.
void resolve_mip_pixel(const LogPolarMap& map, const std::vector<MipLevel>& mips,
                       const GazeInput& gaze, Image& out, int x, int y, ResolveStats& stats,
                       float* lambda = nullptr, const ForwardTable* table = nullptr);

/// Pass 2 with the mip resolve: a W x H image with the buffer's channel count. `table` (made
/// for this map with mip_levels = the pyramid's size) replaces the per-pixel forward map and
/// level: the same bits. `storage`: an image the output is written into when it has the output's
/// shape (a stage recycles an earlier frame's): every pixel is written, none of its values is read;
/// otherwise the output is made anew.
Image resolve_log_polar_mip(const LogPolarMap& map, const std::vector<MipLevel>& mips,
                            const GazeInput& gaze, ResolveStats& stats,
                            const ForwardTable* table = nullptr, Image storage = {});

}  // namespace fovref
