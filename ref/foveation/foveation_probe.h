// `fovref probe` explanations of the log-polar modes (ModeInfo::explain of fov, kfov, cfov,
// ckfov): a screen pixel through pass 2 (the gaze circle test or the forward map, the four taps
// with their validity and weights, the lerps) and, for each tap, the texel's inverse-mapped
// screen point, ray, hit and shading; or, with `--texel I,J`, one buffer texel. The values come
// from the passes' own per-pixel functions (lp_gbuffer_texel, gaze_gbuffer_pixel,
// shade_basic_pixel, resolve_pixel, gaussian_lerp_pixel) and are checked against the rendered
// buffers bit for bit.
#pragma once

#include "ref/stage/probe.h"

namespace fovref {

void explain_foveated(const ProbeContext& context, ProbeReport& report);

}  // namespace fovref
