// BMFR's phase I and phase III accumulations eight pixels at a time with AVX, with a previous
// frame (the case that costs a frame's time), in screen space and in Visual-Polar space: the
// same bits as bmfr_accumulate_noisy_pixel and bmfr_accumulate_filtered_pixel, which stay the
// readable references (docs/bmfr.md, "Measured"). Each lane performs the reference's
// binary32 operations in its order: the finite check of the world position and normal, the
// reprojection (bmfr_project; in Visual-Polar space then vp_forward_angle, called lane by lane),
// the taps (bmfr_taps; bmfr_vp_taps lane by lane), the position and normal tests with their
// margins, the blend of the accepted taps (a tap not accepted adds a selected +0 instead of
// being skipped: the same bits, as a sum that starts at +0 is never -0), alpha, the sample count
// rounded half to even. The taps' history values are read lane by lane.
#pragma once

#include "ref/bmfr/bmfr.h"

namespace fovref {

/// Whether bmfr_accumulate_noisy_row_avx covers a frame: a previous frame, a 3-channel
/// illumination (and in Visual-Polar space a one-channel mask of its size), simd_allowed() and
/// a CPU with AVX.
bool bmfr_accumulate_noisy_avx_applies(bool has_previous, const BmfrSpace& space,
                                       const Image& illumination);

/// Pixels 0 .. 8 floor(W / 8) - 1 of row y as bmfr_accumulate_noisy_pixel computes them (every
/// buffer of `out`, accept_margin when allocated; the counters in `stats`). Returns the pixels
/// done; the caller runs the reference on the rest of the row. Only where the above applies.
int bmfr_accumulate_noisy_row_avx(const BmfrParams& params, const Image& illumination,
                                  const Image& world_position, const Image& normal,
                                  const BmfrHistory& history, const BmfrSpace& space,
                                  BmfrAccumulation& out, int y, BmfrStats& stats);

/// Phase III the same way (bmfr_accumulate_filtered_pixel's bits), in either space: a history,
/// a 3-channel fit, simd_allowed() and AVX.
bool bmfr_accumulate_filtered_avx_applies(const Image& history, const Image& fitted);
int bmfr_accumulate_filtered_row_avx(const BmfrParams& params, const Image& fitted,
                                     const Image& spp, const Image& accept,
                                     const Image& previous_pixel, const Image& history,
                                     const BmfrSpace& space, Image& out, int y);

}  // namespace fovref
