// The log-polar foveated ray tracers as render modes (Lund §3.3, Table 5.1; SPEC §5.1-5.2, §6,
// §12): fov, kfov, cfov, ckfov, kfr. This file only wires the passes of ref/foveation and
// ref/trace:
//
// clang-format off
//   lp_trace      one ray per log-polar texel through its inverse-mapped screen point
//                   -> lp_gbuffer_* (w x h), lp_valid, lp_screen_point
//   (primary=raster, kfr: gbuffer_raster  the full-resolution rasterized G-buffer -> gbuffer_*
//                         lp_sample       each texel copies the pixel under its screen point
//                                           -> lp_gbuffer_*, lp_valid, lp_screen_point)
//   gaze_trace    (a_G > 0) one ray per pixel centre inside the gaze circle
//                   -> gaze_gbuffer_* (the circle's window, gaze_window), gaze_valid
//   lp_shade      the basic ray tracer's shading of lp_gbuffer_*      -> lp_color
//   gaze_shade    (a_G > 0) the same shading of gaze_gbuffer_*       -> gaze_color
//   internal_aa   (filters=internal_aa) Meng §2.2.3, buffer space    -> lp_color_aa
//   resolve       pass 2 (bilinear or mip): gaze pixels inside the circle, lookups in the
//                   buffer outside -> final (resolved when TAA or a screen-space filter follows)
//   taa_source    (taa on) the texel pass 2 sampled: its view depth and (clamp-buffer) its
//                   3x3 box in the buffer -> taa_view_depth, taa_bounds (docs/temporal.md)
//   taa           (taa on) TAA (ref/modes/taa_stage.h) -> taa_color (final when last), taa_age
//   gaussian_lerp (filters=lerp) Lund §3.5                          -> final (or lerp_filtered)
//   post_aa       (filters=post_aa) Meng eq. 2.14                    -> final
//   ray_positions (for --dump) rays per screen pixel (Lund Fig. 3.3) -> ray_positions
// clang-format on
//
// Counters of every frame (names read by scripts): buffer_width, buffer_height, texels_traced,
// texels_off_screen, gaze_radius_px (rounded to an integer), gaze_pixels_traced, gaze_window_x0
// and gaze_window_y0 (the screen pixel of the gaze buffer's pixel (0, 0)), rays_primary
// (= texels_traced + gaze_pixels_traced), screen_pixels_untraced_taps, plus the tracing and
// shading counters of the basic ray tracer.
#pragma once

#include <string>
#include <vector>

#include "ref/log_polar/map.h"
#include "ref/stage/pipeline.h"

namespace fovref {

/// The pipeline of the log-polar mode named `preset` (fov, kfov, cfov or ckfov).
Pipeline foveated_pipeline(const std::string& preset, const Scene* scene,
                           const RenderSettings& settings);
Pipeline fov_pipeline(const Scene* scene, const RenderSettings& settings);
Pipeline kfov_pipeline(const Scene* scene, const RenderSettings& settings);
Pipeline cfov_pipeline(const Scene* scene, const RenderSettings& settings);
Pipeline ckfov_pipeline(const Scene* scene, const RenderSettings& settings);
Pipeline kfr_pipeline(const Scene* scene, const RenderSettings& settings);
/// Gupta's stereo-lp: both eyes side by side (ref/log_polar/stereo.h).
Pipeline stereo_pipeline(const Scene* scene, const RenderSettings& settings);
std::vector<PixelFunction> stereo_pixel_functions(const Params& params);

std::vector<PixelFunction> foveated_pixel_functions(const Params& params);

/// The log-polar map of frame `context` (the screen, the gaze and the mode's parameters).
LogPolarMap frame_log_polar_map(const FrameContext& context);

// The stages (each a named function, so a debugger can break on it).
void lp_trace_stage(FrameContext& context);
void gaze_trace_stage(FrameContext& context);
void lp_shade_stage(FrameContext& context);
void gaze_shade_stage(FrameContext& context);
void resolve_stage(FrameContext& context);
void gaussian_lerp_stage(FrameContext& context);
void gbuffer_raster_stage(FrameContext& context);
void lp_sample_stage(FrameContext& context);
void internal_aa_stage(FrameContext& context);
void post_aa_stage(FrameContext& context);
void stereo_trace_stage(FrameContext& context);
void stereo_shade_stage(FrameContext& context);
void stereo_resolve_stage(FrameContext& context);
void stereo_ray_positions_stage(FrameContext& context);
void ray_positions_stage(FrameContext& context);

}  // namespace fovref
