// Meng's deferred variant of the log-polar pass (Meng 2018 §2.2, "KFR"; SPEC §5.1): instead of
// tracing a ray per texel, each texel takes the full-resolution rasterized G-buffer's pixel
// nearest to its inverse-mapped screen point, and is then shaded in the buffer.
//
//   for each texel (i, j) of the w x h buffer, row by row:   deferred_gbuffer_texel(x = i, y = j)
//     centre (i + 1/2, j + 1/2) -> lp_inverse (the factored table) -> screen point p
//     p off screen (or inside the gaze circle): no data, valid 0
//     else pixel (floor(p.x), floor(p.y)) of the W x H G-buffer, every channel copied as it is
//     (its motion vector stays relative to that pixel's centre), valid 1
#pragma once

#include "ref/log_polar/trace.h"

namespace fovref {

/// The screen G-buffer's channels the deferred pass reads (a rasterized G-buffer's).
struct ScreenGBuffer {
    const Image& view_depth;
    const Image& hit_distance;
    const Image& world_position;
    const Image& shading_normal;
    const Image& geometric_normal;
    const Image& albedo;
    const Image& material_id;
    const Image& primitive_id;
    const Image& motion;
};

/// Per-texel work of sample_lp_gbuffer; returns the texel's status.
TexelStatus deferred_gbuffer_texel(MaskedGBuffer& buffer, Image& screen_points,
                                   const LogPolarMap& map, const LpInverseTable& table,
                                   const ScreenGBuffer& screen, int x, int y,
                                   FoveatedTraceStats& stats);

/// The log-polar buffer's G-buffer sampled from the screen G-buffer (W x H).
/// `screen_offset` (TAA in the kfr mode, Meng §2.3.2; SPEC §7): the Halton jitter applied after
/// the inverse transform, o - (1/2, 1/2) screen pixels added to every texel's screen point.
MaskedGBuffer sample_lp_gbuffer(const LogPolarMap& map, const ScreenGBuffer& screen,
                                Image& screen_points, FoveatedTraceStats& stats,
                                glm::vec2 screen_offset = glm::vec2(0.0f));

/// The offset lp_sample adds to every texel's screen point under the frame's TAA jitter o:
/// with a jittered rasterizer (`jitter_raster`) minus the sample's shift from the centre on the
/// 1/256-pixel grid (raster_sample_shift), so that floor picks the pixel whose jittered sample
/// is nearest; else o - (1/2, 1/2) (the points shifted, Meng §2.3.2 read literally).
glm::vec2 deferred_sample_offset(bool jitter_raster, Offset2 jitter);

}  // namespace fovref
