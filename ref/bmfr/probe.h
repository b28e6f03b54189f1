// `fovref probe` for BMFR in Visual-Polar space: the block that denoised a traced texel of the
// Visual-Polar buffer (its cell in the frame's staircase grid, the block column's phi height, the
// block's origin after the frame's offset, and the fitted red weights read from bmfr_weights).
#pragma once

#include "ref/stage/probe.h"
#include "ref/visual_polar/map.h"

namespace fovref {

/// Appends the [bmfr_fit] section for texel (i, j) of map `m`; the frame must hold bmfr_weights.
void explain_bmfr_block(const ProbeContext& context, const VisualPolarMap& m, int i, int j,
                        ProbeReport& report);

}  // namespace fovref
