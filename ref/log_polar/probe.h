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

/// stereo-lp: a screen pixel through its eye's pass 2 (the barrel source, the taps in the eye's
/// half of the side-by-side buffer) and each tap's texel; or, with `--texel I,J,EYE`, one texel
/// of one eye (stereo_gbuffer_texel, shade_basic_pixel with the eye's camera,
/// resolve_stereo_pixel), checked against the rendered buffers bit for bit.
void explain_stereo(const ProbeContext& context, ProbeReport& report);

}  // namespace fovref
