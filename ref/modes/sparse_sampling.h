// The screen-space sparse path-tracing modes (Koskela P3/P4, Weier et al.; SPEC §5.4-5.5;
// docs/visual-polar.md): path tracing of a subset of the screen's pixels or of points the acuity
// model places, then filled. Wired from the stages of ref/raster, ref/trace, ref/visual_polar
// (the sampling and fill passes) and ref/bmfr:
//
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
// Buffers: acuity_gbuffer_*, acuity_valid, acuity_point and acuity_radiance are lists of samples,
// the rest screen images.
#pragma once

#include "ref/stage/pipeline.h"

namespace fovref {

ModeInfo linear_falloff_mode();
ModeInfo acuity_mode();

}  // namespace fovref
