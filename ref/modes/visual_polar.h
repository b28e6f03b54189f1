// The Visual-Polar modes (Koskela P5; SPEC §5.3, §6, §9 item 11; docs/visual-polar.md), wired
// from the stages of ref/visual_polar, ref/trace, ref/filters and ref/bmfr (the screen-space
// sparse modes, linear-falloff and acuity: ref/modes/sparse_sampling.h):
//
//   visual-polar, visual-polar-basic:
//     vp_trace        -> vp_gbuffer_*, vp_valid, vp_screen_point
//     vp_shade        (shade, -basic)                  -> vp_color
//     vp_pathtrace    (pathtrace, traced texels)       -> vp_radiance, vp_emission, or vp_color
//     bmfr_*          (BMFR in Visual-Polar space, denoise=bmfr, the default) -> vp_color
//     resolve         (the φ-mip resolve)               -> resolved (final without blur)
//     blur_horizontal, blur_vertical (the P5 blur ramp) -> blur_horizontal, final
//
// Buffers: vp_* are Visual-Polar texels, the rest screen images.
#pragma once

#include "ref/stage/pipeline.h"

namespace fovref {

ModeInfo visual_polar_mode();
ModeInfo visual_polar_basic_mode();

}  // namespace fovref
