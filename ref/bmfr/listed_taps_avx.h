// Eight lanes' history taps listed one lane at a time (bmfr_vp_taps), for the AVX paths in
// Visual-Polar space (phases I and III, the TAA): each lane's four taps as the reference reads
// them, then loaded as lane masks and weights.
#pragma once

#include <bit>
#include <cstddef>

#include "ref/bmfr/bmfr.h"
#include "ref/core/avx_lanes.h"

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

}  // namespace fovref::avx
