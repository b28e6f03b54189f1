#include "ref/bmfr/weighted_sum_avx.h"

#include "ref/bmfr/half.h"
#include "ref/core/avx_lanes.h"
#include "ref/core/simd.h"

namespace fovref {

namespace {

using namespace avx;

/// clamp_feature of fit.cpp: NaN -> 0, then std::clamp to [-65504, 65504].
FOVREF_AVX_INLINE __m256 clamp_feature(__m256 v) {
    const __m256 lo = set(-half_max), hi = set(half_max);
    const __m256 clamped = select(less(v, lo), lo, select(less(hi, v), hi, v));
    return select(_mm256_cmp_ps(v, v, _CMP_UNORD_Q), zero(), clamped);
}

/// bmfr_weighted_sum_pixel of pixels x .. x + 7 of row y in the block of weights w and ranges
/// `range`; with `data`, only in its lanes (elsewhere +0, counting nothing: the reference's
/// texels without data).
__attribute__((target("avx"))) void weighted_sum_group(const float* w, const float* range,
                                                       const Image& world_position,
                                                       const Image& normal, const __m256* data,
                                                       Image& out, int x, int y, BmfrStats& stats) {
    alignas(32) float n[3][lanes], p[3][lanes];
    load3_lanes(&normal.data[normal.index(x, y)], n);
    load3_lanes(&world_position.data[world_position.index(x, y)], p);
    // bmfr_features, then the block's scaling of features 4 .. 9 (bmfr_scale_feature).
    __m256 t[bmfr_feature_count];
    t[0] = set(1.0f);
    for (int c = 0; c < 3; ++c) {
        const __m256 position = _mm256_load_ps(p[c]);
        t[1 + c] = clamp_feature(_mm256_load_ps(n[c]));
        t[4 + c] = clamp_feature(position);
        t[7 + c] = clamp_feature(_mm256_mul_ps(position, position));
    }
    for (int k = 0; k < bmfr_scaled_count; ++k) {
        const float lo = range[k], span = range[bmfr_scaled_count + k] - lo;
        __m256& v = t[bmfr_scaled_first + k];
        v = _mm256_sub_ps(v, set(lo));
        if (span > 1.0f) v = _mm256_div_ps(v, set(span));
    }
    alignas(32) float o[3][lanes];
    for (int ch = 0; ch < 3; ++ch) {
        __m256 sum = zero();
        for (int i = 0; i < bmfr_feature_count; ++i)
            sum = _mm256_add_ps(sum, _mm256_mul_ps(set(w[ch * bmfr_feature_count + i]), t[i]));
        const __m256 ok = finite(sum);
        stats.fit_nonfinite += data ? count(both(*data, negation(ok))) : lanes - count(ok);
        sum = std_max(select(ok, sum, zero()), zero());
        _mm256_store_ps(o[ch], data ? select(*data, sum, zero()) : sum);
    }
    store3_lanes(o, &out.data[out.index(x, y)]);
}

/// The Visual-Polar texels x .. x + 7 of row y with data: y below the column's rows, and a
/// traced `valid` texel where it is given (NaN counts, as the reference's == 0 test).
FOVREF_AVX_INLINE __m256 data_lanes(const BmfrGrid& grid, const Image* valid, int x, int y) {
    const __m256i rows = _mm256_loadu_si256(
        reinterpret_cast<const __m256i*>(&grid.column_rows[static_cast<std::size_t>(x)]));
    __m256 data = greater(_mm256_cvtepi32_ps(rows), set(static_cast<float>(y)));
    if (valid)
        data = both(data, not_equal(_mm256_loadu_ps(&valid->data[valid->index(x, y)]), zero()));
    return data;
}

/// The groups of eight of pixels x0 .. x1 - 1 of row y in one block; returns the first pixel
/// not done. Visual-Polar: a group without data is skipped.
__attribute__((target("avx"))) int span_groups(const float* w, const float* range,
                                               const BmfrGrid& grid, const Image& world_position,
                                               const Image& normal, const Image* valid, Image& out,
                                               int x0, int x1, int y, BmfrStats& stats) {
    int x = x0;
    for (; x + lanes <= x1; x += lanes) {
        if (!grid.visual_polar()) {
            weighted_sum_group(w, range, world_position, normal, nullptr, out, x, y, stats);
            continue;
        }
        const __m256 data = data_lanes(grid, valid, x, y);
        if (bits(data) != 0)
            weighted_sum_group(w, range, world_position, normal, &data, out, x, y, stats);
    }
    return x;
}

}  // namespace

bool bmfr_weighted_sum_avx_applies(const BmfrGrid& grid, const Image* valid) {
    // Visual-Polar: row counts compared in binary32 (exact below 2^24), a mask of the grid's size
    return (!grid.visual_polar() ||
            (grid.height < (1 << 24) &&
             (!valid || (valid->channels == 1 && valid->width == grid.width &&
                         valid->height == grid.height)))) &&
           simd_allowed() && cpu_has_avx();
}

int bmfr_weighted_sum_span_avx(const BmfrFit& fit, const Image& world_position, const Image& normal,
                               const Image* valid, Image& out, int x0, int x1, int y,
                               BmfrStats& stats) {
    const glm::ivec2 cell = fit.grid.cell_of(x0, y);
    const float* w = &fit.weights.data[fit.weights.index(cell.x, cell.y)];
    const float* range = &fit.feature_range.data[fit.feature_range.index(cell.x, cell.y)];
    return span_groups(w, range, fit.grid, world_position, normal, valid, out, x0, x1, y, stats);
}

}  // namespace fovref
