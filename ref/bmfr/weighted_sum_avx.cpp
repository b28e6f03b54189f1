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

__attribute__((target("avx"))) void weighted_sum_group(const float* w, const float* range,
                                                       const Image& world_position,
                                                       const Image& normal, Image& out, int x,
                                                       int y, BmfrStats& stats) {
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
        stats.fit_nonfinite += lanes - count(ok);
        sum = select(ok, sum, zero());
        _mm256_store_ps(o[ch], std_max(sum, zero()));
    }
    store3_lanes(o, &out.data[out.index(x, y)]);
}

}  // namespace

bool bmfr_weighted_sum_avx_applies(const BmfrGrid& grid) {
    return !grid.visual_polar() && simd_allowed() && cpu_has_avx();
}

int bmfr_weighted_sum_span_avx(const BmfrFit& fit, const Image& world_position, const Image& normal,
                               Image& out, int x0, int x1, int y, BmfrStats& stats) {
    const glm::ivec2 cell = fit.grid.cell_of(x0, y);
    const float* w = &fit.weights.data[fit.weights.index(cell.x, cell.y)];
    const float* range = &fit.feature_range.data[fit.feature_range.index(cell.x, cell.y)];
    int x = x0;
    for (; x + lanes <= x1; x += lanes)
        weighted_sum_group(w, range, world_position, normal, out, x, y, stats);
    return x;
}

}  // namespace fovref
