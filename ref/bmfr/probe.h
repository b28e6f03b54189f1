// `fovref probe` for BMFR: a screen pixel of a denoised frame phase by phase - phase I's
// reprojection, taps, accept bits and blend; the pixel's block (with the frame's offset), its
// scaled features and fitted weights, its fitted value; phase III; the remodulation; the authors'
// TAA - each recomputed by the phase's own per-pixel function and checked bit for bit against the
// rendered buffers. In Visual-Polar space: the block that denoised a traced texel (its cell in
// the frame's staircase grid, the block column's phi height, the origin after the frame's offset
// and the fitted red weights).
#pragma once

#include "ref/stage/probe.h"
#include "ref/visual_polar/map.h"

namespace fovref {

/// Appends the screen-space BMFR sections for pixel (x, y) of a frame that ran BMFR on the
/// screen G-buffer (nothing for a frame without bmfr_weights, or a texel probe).
void explain_bmfr_pixel(const ProbeContext& context, ProbeReport& report);

/// Appends the [bmfr_fit] section for texel (i, j) of map `m`; the frame must hold bmfr_weights.
void explain_bmfr_block(const ProbeContext& context, const VisualPolarMap& m, int i, int j,
                        ProbeReport& report);

}  // namespace fovref
