// `fovref probe` for the Visual-Polar modes (visual-polar, visual-polar-basic): a screen pixel's
// polar coordinates, columns, rows and phi-mip levels in pass 2 (recomputed by resolve_vp_pixel
// and checked against the rendered buffer) and its blur-ramp sigma; or a buffer texel (--texel
// I,J): its column (fovea or periphery, U, r), row (theta), the clipped and off-screen flags,
// its screen point (with BMFR, the block that denoised it: explain_bmfr_block in
// ref/bmfr/probe.h).
#pragma once

#include "ref/stage/probe.h"

namespace fovref {

void explain_visual_polar(const ProbeContext& context, ProbeReport& report);

}  // namespace fovref
