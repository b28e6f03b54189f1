// Eight lanes' history taps in Visual-Polar space (bmfr_vp_taps) for the AVX paths (phases I and
// III, the TAA): in lanes where each lane's columns lie beyond the history map's fovea
// (vp_tap_lanes), else listed one lane at a time with bmfr_vp_taps itself (ListedTaps); each
// lane's four taps as the reference reads them.
#pragma once

#include <bit>
#include <cstddef>

#include "ref/bmfr/bmfr.h"
#include "ref/core/avx_lanes.h"
#include "ref/visual_polar/map.h"

namespace fovref::avx {

/// The four taps of eight pixels: tap k of lane l is history pixel at[k][l] (row-major), read
/// where on[k] is set, with weight weight[k].
struct ListedTaps {
    __m256 on[4], weight[4];
    alignas(32) std::size_t at[4][lanes] = {};
    alignas(32) float on_lanes[4][lanes] = {}, weight_lanes[4][lanes] = {};
    std::size_t index(int k, int l) const { return at[k][l]; }
};

/// Lane l's taps (bmfr_vp_taps) into `g`: every weight kept, tap k on where `usable(k)` and
/// inside the W x H buffer. load_listed then fills g.on and g.weight from the lanes set.
template <class Usable>
void set_lane_taps(ListedTaps& g, int l, const BmfrTaps& taps, int width, int height,
                   Usable usable) {
    for (int k = 0; k < 4; ++k) {
        g.weight_lanes[k][l] = taps.w[k];
        if (taps.x[k] < 0 || taps.y[k] < 0 || taps.x[k] >= width || taps.y[k] >= height ||
            !usable(k))
            continue;
        g.on_lanes[k][l] = std::bit_cast<float>(-1);
        g.at[k][l] = static_cast<std::size_t>(taps.y[k]) * static_cast<std::size_t>(width) +
                     static_cast<std::size_t>(taps.x[k]);
    }
}
FOVREF_AVX_INLINE void load_listed(ListedTaps& g) {
    for (int k = 0; k < 4; ++k) {
        g.on[k] = _mm256_load_ps(g.on_lanes[k]);
        g.weight[k] = _mm256_load_ps(g.weight_lanes[k]);
    }
}

/// The four taps of eight lanes: on (the reference reads tap k), weight, and the history pixel
/// (row-major) where on.
struct LaneTaps {
    __m256 on[4], weight[4];
    alignas(32) int at[4][lanes];
    std::size_t index(int k, int l) const { return static_cast<std::size_t>(at[k][l]); }
};

/// bmfr_vp_taps(map, q) of eight lanes whose columns lie beyond the map's fovea or off the W x H
/// buffer (the map's size, W H < 2^24: the indices are exact in binary32), each tap on where it
/// lies on the buffer and the lane is `wanted`: q.x clamped to +-1e6 (-1e6 if not finite), the
/// fraction of q.y's turn (0 if not finite), the columns x0 = floor(q.x), x0 + 1 with weights 1 -
/// fx and fx, and on both (each has H rows) the rows of v = q.y H - 1/2, wrapped, with weights 1 -
/// fy and fy; the columns and rows are exact integers in binary32. False, with `g` unset, where a
/// wanted lane has a column in the fovea (its rows differ from column to column: the caller lists
/// its taps with bmfr_vp_taps), or the map is not the buffer's size, or W H >= 2^24.
FOVREF_AVX_INLINE bool vp_tap_lanes(const VisualPolarMap& map, __m256 qx, __m256 qy, __m256 wanted,
                                    int width, int height, LaneTaps& g) {
    if (map.width != width || map.height != height ||
        static_cast<double>(width) * static_cast<double>(height) >= 16777216.0)
        return false;
    const __m256 big = set(1e6f);
    qx = select(finite(qx), std_min(std_max(qx, negate(big)), big), negate(big));
    qy = select(finite(qy), _mm256_sub_ps(qy, floor(qy)), zero());
    const __m256 x0 = floor(qx), fx = _mm256_sub_ps(qx, x0);
    const __m256 wf = set(static_cast<float>(width)), hf = set(static_cast<float>(height));
    const __m256 columns[2] = {x0, _mm256_add_ps(x0, set(1.0f))};
    __m256 on_buffer[2];
    for (int side = 0; side < 2; ++side) {
        const __m256 c = columns[side];
        on_buffer[side] = both(wanted, both(at_least(c, zero()), less(c, wf)));
        const __m256 fovea = less(c, set(static_cast<float>(map.fovea_columns)));
        if (bits(both(on_buffer[side], fovea)) != 0) return false;
    }
    // v in [-1/2, H - 1/2]: floor(v) in [-1, H - 1], wrapped from -1 to H - 1
    const __m256 v = _mm256_sub_ps(_mm256_mul_ps(qy, hf), set(0.5f));
    const __m256 fv0 = floor(v), fy = _mm256_sub_ps(v, fv0);
    const __m256 y0 = select(less(fv0, zero()), _mm256_add_ps(fv0, hf), fv0);
    const __m256 next = _mm256_add_ps(y0, set(1.0f));
    const __m256 y1 = select(equal(next, hf), zero(), next);
    const __m256 wx[2] = {_mm256_sub_ps(set(1.0f), fx), fx};
    const __m256 gy = _mm256_sub_ps(set(1.0f), fy);
    for (int k = 0; k < 4; ++k) {
        const int side = k & 1;
        g.weight[k] = _mm256_mul_ps(wx[side], k < 2 ? gy : fy);
        g.on[k] = on_buffer[side];
        // y W + c, exact: the indices on the buffer are below 2^24
        const __m256 at = _mm256_add_ps(_mm256_mul_ps(k < 2 ? y0 : y1, wf), columns[side]);
        _mm256_store_si256(reinterpret_cast<__m256i*>(g.at[k]),
                           _mm256_cvttps_epi32(select(g.on[k], at, zero())));
    }
    return true;
}

/// Turns off the taps of `g` (ListedTaps or LaneTaps, whose on[k] are set) on pixels whose
/// `mask` value is 0 (NaN counts as nonzero, as the reference's != 0 does).
template <class GroupTaps>
FOVREF_AVX_INLINE void mask_taps(GroupTaps& g, const Image& mask) {
    for (int k = 0; k < 4; ++k) {
        const int on = bits(g.on[k]);
        alignas(32) float keep[lanes] = {};
        for (int l = 0; l < lanes; ++l)
            if ((on >> l & 1) && mask.data[g.index(k, l)] != 0.0f)
                keep[l] = std::bit_cast<float>(-1);
        g.on[k] = _mm256_load_ps(keep);
    }
}

}  // namespace fovref::avx
