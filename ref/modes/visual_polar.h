// The Visual-Polar and screen-space sparse path-tracing modes (Koskela P3-P5; SPEC §5.3-5.5, §6,
// §9 item 11; docs/visual-polar.md). Each stage calls one pass:
//
//   visual-polar, visual-polar-basic:
//     vp_trace        (trace_vp_gbuffer)            -> vp_gbuffer_*, vp_valid, vp_screen_point
//     vp_shade        (shade_basic)                 -> vp_color              (-basic)
//     vp_pathtrace    (pathtrace, traced texels)    -> vp_radiance, vp_emission, or vp_color
//     bmfr_*          (ref/bmfr in Visual-Polar space, denoise=bmfr, the default) -> vp_color
//     resolve         (resolve_visual_polar)        -> resolved (final without blur)
//     blur_horizontal, blur_vertical (the P5 blur ramp) -> blur_horizontal, final
//   linear-falloff:
//     primary_visibility (rasterized G-buffer)      -> gbuffer_*
//     falloff_mask    (linear_falloff_mask)         -> sample_mask
//     pathtrace       (sampled pixels only)         -> sparse_radiance (+ sparse_emission)
//     fill            (push_pull, or black)         -> filled (+ filled_emission), or final
//     bmfr_*          (screen space, denoise=bmfr)  -> final
//   acuity:
//     acuity_trace    (acuity_samples, trace_point_gbuffer) -> acuity_gbuffer_*, acuity_valid,
//                                                              acuity_point (N x 1)
//     acuity_shade    (pathtrace)                   -> acuity_radiance (N x 1)
//     acuity_accumulate (splat_samples, + the previous frame's with progressive=on)
//                                                   -> acuity_sum, acuity_count
//     acuity_resolve  (sample_mean, push_pull with fill=push-pull) -> final
#pragma once

#include <string>
#include <vector>

#include "ref/stage/pipeline.h"

namespace fovref {

Pipeline visual_polar_pipeline(const Scene* scene, const RenderSettings& settings);
Pipeline visual_polar_basic_pipeline(const Scene* scene, const RenderSettings& settings);
Pipeline linear_falloff_pipeline(const Scene* scene, const RenderSettings& settings);
Pipeline acuity_pipeline(const Scene* scene, const RenderSettings& settings);

/// The parameters of each mode (the preset's defaults).
std::vector<ParamSpec> visual_polar_param_specs(bool path_traced);
std::vector<ParamSpec> linear_falloff_param_specs();
std::vector<ParamSpec> acuity_param_specs();

std::vector<PixelFunction> visual_polar_pixel_functions(const Params& params);
std::vector<PixelFunction> visual_polar_basic_pixel_functions(const Params& params);

}  // namespace fovref
