// The log-polar foveated ray tracers as render modes (Lund §3.3, Table 5.1; Meng 2018; Gupta
// 2019; SPEC §5.1-5.2, §6, §12): fov, kfov, cfov, ckfov, kfr (presets of ref/log_polar/params.h)
// and stereo-lp, wired from the stages of ref/log_polar, ref/trace, ref/filters, ref/raster and
// ref/temporal:
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
//   taa           (taa on) TAA -> taa_color (final when last), taa_age
//   gaussian_lerp (filters=lerp) Lund §3.5                          -> final (or lerp_filtered)
//   post_aa       (filters=post_aa) Meng eq. 2.14                    -> final
//   ray_positions (for --dump) rays per screen pixel (Lund Fig. 3.3) -> ray_positions
//
//   stereo-lp:    stereo_trace -> stereo_shade (each eye's camera) -> resolve [-> taa_source
//                   -> taa, per eye] -> final; ray_positions
//
//   log-polar-pathtrace (Koskela P5 §4.3's log-polar method): lp_trace -> lp_pathtrace (one
//                   path per traced texel) -> lp_radiance, lp_emission -> BMFR's stages on the
//                   buffer (rows wrap around: the angle) -> lp_color -> resolve -> final;
//                   ray_positions (ref/modes/log_polar_pathtrace.cpp)
// clang-format on
//
// Buffers: lp_* are buffer texels (stereo: both eyes side by side), gaze_* a window of the
// screen, the rest screen images.
#pragma once

#include <string>

#include "ref/stage/pipeline.h"

namespace fovref {

/// The mode of the log-polar preset `preset` (fov, kfov, cfov, ckfov or kfr).
ModeInfo foveated_mode(const std::string& preset, const std::string& what);
/// Gupta's stereo-lp: both eyes side by side (ref/log_polar/stereo.h).
ModeInfo stereo_mode();
/// Path tracing in Meng's kernel log-polar buffer, denoised by BMFR there (Koskela P5 §4.3).
ModeInfo log_polar_pathtrace_mode();

}  // namespace fovref
