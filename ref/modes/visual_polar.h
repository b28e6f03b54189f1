// The Visual-Polar and screen-space sparse path-tracing modes (Koskela P3-P5; SPEC §5.3-5.5, §6,
// §9 item 11; docs/visual-polar.md), wired from the stages of ref/visual_polar, ref/trace,
// ref/raster, ref/filters and ref/bmfr:
//
//   visual-polar, visual-polar-basic:
//     vp_trace        -> vp_gbuffer_*, vp_valid, vp_screen_point
//     vp_shade        (shade, -basic)                  -> vp_color
//     vp_pathtrace    (pathtrace, traced texels)       -> vp_radiance, vp_emission, or vp_color
//     bmfr_*          (BMFR in Visual-Polar space, denoise=bmfr, the default) -> vp_color
//     resolve         (the φ-mip resolve)               -> resolved (final without blur)
//     blur_horizontal, blur_vertical (the P5 blur ramp) -> blur_horizontal, final
//   linear-falloff:
//     primary_visibility (rasterize)                   -> gbuffer_*
//     falloff_mask                                     -> sample_mask
//     pathtrace       (sampled pixels only)            -> sparse_radiance (+ sparse_emission)
//     fill            (push_pull, or black)            -> filled (+ filled_emission), or final
//     bmfr_*          (screen space, denoise=bmfr)     -> final
//   acuity:
//     acuity_trace    -> acuity_gbuffer_*, acuity_valid, acuity_point (N x 1)
//     acuity_shade    (pathtrace)                      -> acuity_radiance (N x 1)
//     acuity_accumulate (+ the previous frame's sums with progressive=on) -> acuity_sum,
//                                                         acuity_count
//     acuity_resolve  (sample_mean, push_pull with fill=push-pull) -> final
//
// Buffers: vp_* are Visual-Polar texels, acuity_gbuffer_*, acuity_valid, acuity_point and
// acuity_radiance lists of samples, the rest screen images.
#pragma once

#include "ref/stage/pipeline.h"

namespace fovref {

ModeInfo visual_polar_mode();
ModeInfo visual_polar_basic_mode();
ModeInfo linear_falloff_mode();
ModeInfo acuity_mode();

}  // namespace fovref
