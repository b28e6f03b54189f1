// BMFR's TAA (bmfr_taa) eight pixels at a time with AVX2 where there is a history: the same bits
// as bmfr_taa_pixel, which stays the readable reference (docs/bmfr.md, "Measured"). Each lane
// performs the reference's binary32 operations in its order: the reprojected point's range test,
// the taps inside the image (bmfr_taps; in Visual-Polar space bmfr_vp_taps on the history's map,
// listed lane by lane, on texels traced in the previous frame), the 3x3 box and 5-tap cross of
// the YCoCg neighbours (glm::min / glm::max from +-infinity, in the reference's row-major order;
// in Visual-Polar space the traced ones on the wrapped rows: beyond the fovea three rows shared
// by the lanes, in the fovea each lane's own, read lane by lane), the
// history blended over the taps (a tap that is not used adds a selected +0: the same bits, as a
// sum that starts at +0 is never -0), the clamp in YCoCg and the blend with taa_alpha.
#pragma once

#include <vector>

#include "ref/bmfr/bmfr.h"

namespace fovref {

/// The pixels [first, end) of each row that bmfr_taa_row_avx computes, eight at a time; the
/// reference does the rest. first = end = W: none. Visual-Polar space: each column's rows.
struct BmfrTaaSpan {
    int first = 0, end = 0;
    std::vector<int> column_rows;
};

/// The span of a frame: where there is a history, the images have 3 channels, simd_allowed()
/// and the CPU has AVX2 (in Visual-Polar space where the mask and both maps have the frame's
/// shape and 3 W H fits in int32), the groups of eight from pixel 1 while column x + 8 lies on
/// the image.
BmfrTaaSpan bmfr_taa_avx_span(const Image& display, const Image& history, const BmfrSpace& space);

/// The pixels of `span` in row y as bmfr_taa_pixel computes them; adds the pixels whose history
/// was used to `used`.
void bmfr_taa_row_avx(const BmfrParams& params, const Image& display, const Image& ycocg,
                      const Image& previous_pixel, const Image& history, const BmfrSpace& space,
                      const BmfrTaaSpan& span, Image& out, int y, std::int64_t& used);

}  // namespace fovref
