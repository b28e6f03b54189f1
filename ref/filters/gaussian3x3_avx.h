// The 3x3 Gaussian [1 2 1; 2 4 2; 1 2 1] / 16 of eight pixels of a 3-channel image in AVX lanes,
// the same bits as the scalar sums: shared by internal anti-aliasing (internal_aa.cpp) and the
// Gaussian lerp (gaussian_lerp.cpp). Include only from code compiled for AVX.
#pragma once

#include <immintrin.h>

#include "ref/core/avx_lanes.h"
#include "ref/image/image.h"

namespace fovref {

/// Pixels x0 .. x0 + 7 of a 3-channel image, the rows rows[0] (above), rows[1] and rows[2]
/// (below), the columns x0 - 1 .. x0 + 8 on the image (the caller checks). The 24 floats of the
/// eight pixels are contiguous (as in each neighbouring row and shifted column), and every lane
/// has the same weights, so each of the three registers does one (pixel, channel)'s scalar
/// operations in order: 0, then + k c per tap (the product rounded), the row above first, left
/// to right; then / 16, the sum of the nine weights. `out` gets the three registers, the floats
/// interleaved as the image holds them.
FOVREF_AVX_INLINE void gaussian3x3_group(const Image& color, int x0, const int* rows, __m256* out) {
    static constexpr float k[3][3] = {{1, 2, 1}, {2, 4, 2}, {1, 2, 1}};
    __m256 sum[3] = {_mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps()};
    for (int dy = 0; dy < 3; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const float* p = &color.data[color.index(x0 + dx, rows[dy])];
            const __m256 kw = _mm256_set1_ps(k[dy][dx + 1]);
            for (int r = 0; r < 3; ++r)
                sum[r] = _mm256_add_ps(sum[r], _mm256_mul_ps(kw, _mm256_loadu_ps(p + 8 * r)));
        }
    for (int r = 0; r < 3; ++r) out[r] = _mm256_div_ps(sum[r], _mm256_set1_ps(16.0f));
}

}  // namespace fovref
