// BMFR's TAA (bmfr_taa) eight pixels at a time with AVX2 in screen space with a history: the same
// bits as bmfr_taa_pixel, which stays the readable reference (docs/bmfr.md, "Measured"). Each
// lane performs the reference's binary32 operations in its order: the reprojected point's range
// test, the taps (bmfr_taps) inside the image, the 3x3 box and 5-tap cross of the YCoCg
// neighbours (glm::min / glm::max from +-infinity, in the reference's row-major order), the
// history blended over the taps (a tap off the image adds a selected +0: the same bits, as a sum
// that starts at +0 is never -0), the clamp in YCoCg and the blend with taa_alpha.
#pragma once

#include "ref/bmfr/bmfr.h"

namespace fovref {

/// Whether bmfr_taa_row_avx covers a frame: screen space, a history, 3-channel images,
/// simd_allowed() and a CPU with AVX2.
bool bmfr_taa_avx_applies(const Image& display, const Image& history, const BmfrSpace& space);

/// Pixels 1 .. 8 k of row y (k = floor((W - 2) / 8): every neighbour's column lies on the image)
/// as bmfr_taa_pixel computes them; adds the pixels whose history was used to `used`. Returns
/// 1 + 8 k, the first pixel left to the reference (which also does pixel 0). Only where the above
/// applies.
int bmfr_taa_row_avx(const BmfrParams& params, const Image& display, const Image& ycocg,
                     const Image& previous_pixel, const Image& history, Image& out, int y,
                     std::int64_t& used);

}  // namespace fovref
