// The basic and ground-truth ray tracers as render modes (Lund §3.1, §3.2; SPEC §12). This file
// only wires the passes of ref/raster and ref/trace into pipelines:
//
// clang-format off
//   basic:         primary_visibility (G-buffer by rays or by the rasterizer)
//                    -> shade_direct (Lambert + one shadow ray per light)       -> final
//   ground-truth:  primary_visibility (G-buffer by rays; for --dump and goldens only)
//                  supersample (16 Halton rays per pixel, shaded, box-filtered) -> final
//   pathtrace:     primary_visibility (rasterized G-buffer)
//                    -> pathtrace (1-spp paths: NEE + secondary rays, SPEC §8)   -> final
//                    [denoise=bmfr: -> radiance -> the BMFR stages (ref/modes/bmfr_stage.h)]
//   pathtrace-reference: pathtrace_reference (N jittered samples of the same paths)
//                    -> final, standard_error, the running sums (resumable)
// clang-format on
//
// The BVH is built only when something traces a ray (ray primaries or shadow rays), once per
// render; its build appears in the counters of the frame that needed it.
#pragma once

#include <vector>

#include "ref/stage/pipeline.h"

namespace fovref {

Pipeline basic_pipeline(const Scene* scene, const RenderSettings& settings);
Pipeline ground_truth_pipeline(const Scene* scene, const RenderSettings& settings);
Pipeline pathtrace_pipeline(const Scene* scene, const RenderSettings& settings);
std::vector<ParamSpec> pathtrace_param_specs();
std::vector<PixelFunction> pathtrace_pixel_functions(const Params& params);
Pipeline pathtrace_reference_pipeline(const Scene* scene, const RenderSettings& settings);
std::vector<ParamSpec> pathtrace_reference_param_specs();

/// The per-pixel functions of basic's and ground-truth's passes (for `fovref probe --debugger`).
std::vector<PixelFunction> basic_pixel_functions(const Params& params);
std::vector<PixelFunction> ground_truth_pixel_functions(const Params& params);

// The stages (each a named function, so a debugger can break on it).
/// G-buffer of SPEC §4 by the rasterizer or by ray casting (basic's `primary` parameter).
void primary_visibility_stage(FrameContext& context);
/// basic's shading: shade_basic over the G-buffer (ref/trace/shade_basic.h).
void shade_direct_stage(FrameContext& context);
/// ground-truth's supersampling: render_ground_truth (ref/trace/ground_truth.h).
void supersample_stage(FrameContext& context);
/// pathtrace's paths: pathtrace (ref/trace/pathtrace.h) over the rasterized G-buffer.
void pathtrace_stage(FrameContext& context);
/// pathtrace-reference: pathtrace_reference (ref/trace/pathtrace_reference.h), resumable.
void pathtrace_reference_stage(FrameContext& context);

}  // namespace fovref
