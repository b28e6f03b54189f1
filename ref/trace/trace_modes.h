// The basic and ground-truth ray tracers as render modes (Lund §3.1, §3.2; SPEC §12).
//
// basic:         primary_visibility (G-buffer by rays or by the rasterizer) -> shade_direct ->
// final ground-truth:  supersample (16 Halton rays per pixel, shaded, box-filtered) -> final The
// BVH is built only when something traces a ray (ray primaries or shadow rays), once per render;
// its build appears in the counters of the frame that needed it.
#pragma once

#include <vector>

#include "ref/raster/rasterizer.h"
#include "ref/stage/pipeline.h"

namespace fovref {

std::vector<ParamSpec> basic_params();
/// The rasterizer settings of basic's parameters (fill_rule), validated.
RasterSettings basic_raster_settings(const Params& params);
Pipeline basic_pipeline(const Scene* scene, const RenderSettings& settings);
Pipeline ground_truth_pipeline(const Scene* scene, const RenderSettings& settings);

/// The per-pixel functions of basic's and ground-truth's passes (for `fovref probe --debugger`).
std::vector<PixelFunction> basic_pixel_functions(const Params& params);
std::vector<PixelFunction> ground_truth_pixel_functions(const Params& params);

/// `fovref probe` explanations (ref/trace/trace_probe.cpp).
void explain_basic(const ProbeContext& context, ProbeReport& report);
void explain_ground_truth(const ProbeContext& context, ProbeReport& report);

}  // namespace fovref
