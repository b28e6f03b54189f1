#include "ref/filters/internal_aa.h"

#include <immintrin.h>

#include <algorithm>

#include "ref/core/error.h"
#include "ref/core/simd.h"
#include "ref/filters/gaussian3x3_avx.h"

namespace fovref {

void internal_aa_texel(const Image& color, const Image& valid, Image& out, int x, int y) {
    const int w = color.width, h = color.height;
    if (valid.at(x, y) == 0.0f || 2 * x < w) {
        for (int c = 0; c < color.channels; ++c) out.at(x, y, c) = color.at(x, y, c);
        return;
    }
    static constexpr float k[3][3] = {{1, 2, 1}, {2, 4, 2}, {1, 2, 1}};
    float sum[4] = {0, 0, 0, 0};
    float weight = 0.0f;
    for (int dy = -1; dy <= 1; ++dy) {
        const int yy = ((y + dy) % h + h) % h;
        for (int dx = -1; dx <= 1; ++dx) {
            const int xx = std::clamp(x + dx, 0, w - 1);
            if (valid.at(xx, yy) == 0.0f) continue;
            const float kw = k[dy + 1][dx + 1];
            weight += kw;
            for (int c = 0; c < color.channels && c < 4; ++c) sum[c] += kw * color.at(xx, yy, c);
        }
    }
    for (int c = 0; c < color.channels && c < 4; ++c) out.at(x, y, c) = sum[c] / weight;
}

namespace {

constexpr int lanes = 8;

/// Texels x0 .. x0 + 7 of row y of a 3-channel buffer, where they and all their neighbours are
/// traced and need no clamp (the caller checks): internal_aa_texel's sums over nine traced taps,
/// divided by their weight 16 (gaussian3x3_group).
__attribute__((target("avx"))) void filter_group(const Image& color, Image& out, int x0, int y,
                                                 const int* rows) {
    __m256 filtered[3];
    gaussian3x3_group(color, x0, rows, filtered);
    float* o = &out.data[out.index(x0, y)];
    for (int r = 0; r < 3; ++r) _mm256_storeu_ps(o + 8 * r, filtered[r]);
}

}  // namespace

Image internal_aa(const Image& color, const Image& valid) {
    FOVREF_CHECK(color.channels <= 4, "internal anti-aliasing of more than 4 channels");
    FOVREF_CHECK(valid.width == color.width && valid.height == color.height,
                 "a validity mask of another size than its buffer");
    const int w = color.width, h = color.height;
    Image out(w, h, color.channels, 0.0f);
    // Groups of eight texels of the outer half with every neighbour traced and inside the
    // buffer's columns take filter_group (AVX, the same bits); the rest internal_aa_texel.
    const bool avx = color.channels == 3 && valid.channels == 1 && simd_allowed() && cpu_has_avx();
    for (int y = 0; y < h; ++y) {
        const int rows[3] = {y == 0 ? h - 1 : y - 1, y, y + 1 == h ? 0 : y + 1};
        int x = 0;
        while (x < w) {
            if (avx && 2 * x >= w && x >= 1 && x + lanes < w) {
                bool traced = true;
                for (const int row : rows)
                    for (int xx = x - 1; xx <= x + lanes && traced; ++xx)
                        traced = valid.at(xx, row) != 0.0f;
                if (traced) {
                    filter_group(color, out, x, y, rows);
                    x += lanes;
                    continue;
                }
            }
            internal_aa_texel(color, valid, out, x, y);
            ++x;
        }
    }
    return out;
}

}  // namespace fovref
