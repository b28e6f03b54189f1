// Meng's deferred variant of the log-polar pass (Meng 2018 §2.2, "KFR"; SPEC §5.1): instead of
// tracing a ray per texel, each texel takes the full-resolution rasterized G-buffer's pixel
// nearest to its inverse-mapped screen point, and is then shaded in the buffer.
//
//   for each texel (i, j) of the w x h buffer, row by row:   deferred_gbuffer_texel(x = i, y = j)
//     centre (i + 1/2, j + 1/2) -> lp_inverse (the factored table) -> screen point p
//     p off screen (or inside the gaze circle): no data, valid 0
//     else pixel (floor(p.x), floor(p.y)) of the W x H G-buffer, every channel as it is
//     (its motion vector stays relative to that pixel's centre), valid 1
//
// The pass reads only the G-buffer's primitive ids: the pixel's other channels are made again
// from its primitive (write_rasterized_pixel, the rasterizer's own per-pixel functions), the same
// bits as the rasterized G-buffer's, so the rasterizer need not run its attribute pass over every
// pixel for the ~1/4 of them that the buffer samples (docs/foveation.md, "Deferred variant").
#pragma once

#include "ref/log_polar/trace.h"
#include "ref/raster/rasterizer.h"

namespace fovref {

/// What lp_sample reads of the rasterized screen: the G-buffer's primitive ids (W x H, -1 =
/// background) and what makes a pixel's other channels again: the scene, the rasterizer's frame
/// (its camera, screen, fill rule and sample) and the previous camera (motion).
struct RasterizedScreen {
    const Scene& scene;
    const Image& primitive_id;
    RasterFrame frame;
    Camera previous_camera;
    float previous_tan_half = 0.0f;  ///< tan_half_vfov(previous_camera)
};

/// Per-texel work of sample_lp_gbuffer; returns the texel's status.
TexelStatus deferred_gbuffer_texel(MaskedGBuffer& buffer, Image& screen_points,
                                   const LogPolarMap& map, const LpInverseTable& table,
                                   const RasterizedScreen& screen, int x, int y,
                                   FoveatedTraceStats& stats);

/// The log-polar buffer's G-buffer sampled from the rasterized screen (W x H).
/// `screen_offset` (TAA in the kfr mode, Meng §2.3.2; SPEC §7): the Halton jitter applied after
/// the inverse transform, o - (1/2, 1/2) screen pixels added to every texel's screen point.
MaskedGBuffer sample_lp_gbuffer(const LogPolarMap& map, const RasterizedScreen& screen,
                                Image& screen_points, FoveatedTraceStats& stats,
                                glm::vec2 screen_offset = glm::vec2(0.0f));

/// The offset lp_sample adds to every texel's screen point under the frame's TAA jitter o:
/// with a jittered rasterizer (`jitter_raster`) minus the sample's shift from the centre on the
/// 1/256-pixel grid (raster_sample_shift), so that floor picks the pixel whose jittered sample
/// is nearest; else o - (1/2, 1/2) (the points shifted, Meng §2.3.2 read literally).
glm::vec2 deferred_sample_offset(bool jitter_raster, Offset2 jitter);

}  // namespace fovref
