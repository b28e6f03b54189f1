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

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "ref/bvh/bvh_cache.h"
#include "ref/stage/pipeline.h"
#include "ref/visual_polar/map.h"

namespace fovref {

ModeInfo visual_polar_mode();
ModeInfo visual_polar_basic_mode();

/// Path tracing on a polar buffer's traced texels and BMFR on the buffer (the Visual-Polar
/// buffer, family "vp", or a log-polar one seen as a polar buffer, "lp"): the stage
/// <family>_pathtrace over <family>_gbuffer_* where <family>_valid is set, -> <family>_color;
/// with denoise=bmfr (parsed from `params` as `specs` declare it) -> <family>_radiance,
/// <family>_emission, then BMFR's stages with the frame's map `map` -> <family>_color.
void add_polar_path_tracing(Pipeline& pipeline, const Params& params,
                            const std::vector<ParamSpec>& specs, const std::string& family,
                            std::function<VisualPolarMap(const FrameContext&, int frame)> map,
                            std::shared_ptr<BvhCache> bvh);

}  // namespace fovref
