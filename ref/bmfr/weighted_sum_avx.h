// BMFR's phase II weighted sum (bmfr_weighted_sum_pixel) eight pixels at a time with AVX, in
// screen space and in Visual-Polar space (where texels without data, beyond their column's rows
// or untraced, stay +0 and count nothing): the same bits, the scalar function staying the readable
// reference. Each lane computes the pixel's features (NaN to 0, clamped to the binary16 range),
// scales the world position terms by its block's range and sums w_i t_i in feature order, as the
// reference does; the groups of eight never straddle a block (a row is walked block span by block
// span, the ends of a span by the reference).
#pragma once

#include "ref/bmfr/bmfr.h"

namespace fovref {

/// Whether the AVX path covers this grid and mask (bmfr_weighted_sum's `valid`; Visual-Polar
/// only, one channel of the grid's size): simd_allowed() and AVX.
bool bmfr_weighted_sum_avx_applies(const BmfrGrid& grid, const Image* valid = nullptr);

/// Pixels x0 .. x0 + 8 floor((x1 - x0) / 8) - 1 of row y, all in one block, as bmfr_weighted_sum
/// computes them; returns the first pixel not done.
int bmfr_weighted_sum_span_avx(const BmfrFit& fit, const Image& world_position, const Image& normal,
                               const Image* valid, Image& out, int x0, int x1, int y,
                               BmfrStats& stats);

}  // namespace fovref
