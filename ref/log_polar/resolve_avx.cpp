#include "ref/log_polar/resolve_avx.h"

#include <cstddef>

#include "ref/core/avx_lanes.h"
#include "ref/core/simd.h"

namespace fovref {

namespace {

using namespace avx;

/// lerp of resolve.cpp: a + t (b - a).
FOVREF_AVX_INLINE __m256 lerp(__m256 a, __m256 b, __m256 t) {
    return _mm256_add_ps(a, _mm256_mul_ps(t, _mm256_sub_ps(b, a)));
}

// Pixels x .. x + 7 of row y. Returns false (nothing written) when the group needs the
// reference for all its pixels: a pixel reads the gaze buffer, or a (u, v) lies outside the
// range lp_bilinear_index accepts (the reference then throws).
__attribute__((target("avx"))) bool resolve_group(const LogPolarMap& map, const ResolveInputs& in,
                                                  const ForwardTable& table, Image& out, int x,
                                                  int y, ResolveStats& stats) {
    for (int l = 0; l < lanes; ++l)
        if (reads_gaze_buffer(map, in.gaze, x + l, y)) return false;
    const int w = map.width, h = map.height;
    const float wf = static_cast<float>(w), hf = static_cast<float>(h);
    alignas(32) float u[lanes], v[lanes];
    const glm::vec2* uv = &table.uv[static_cast<std::size_t>(y) * map.screen_width + x];
    for (int l = 0; l < lanes; ++l) u[l] = uv[l].x, v[l] = uv[l].y;
    const __m256 uu = _mm256_load_ps(u), vv = _mm256_load_ps(v);
    const __m256 accepted =
        both(finite(uu), both(at_least(vv, set(-1.0f)), at_most(vv, set(hf + 1.0f))));
    if (bits(accepted) != 0xff) return false;
    // lp_bilinear_index: u clamped to the texel centres, v wrapped (floor(v - 1/2) in [-2, h],
    // one step of h puts it in [0, h) for h >= 3).
    const __m256 lo = set(0.5f), hi = set(wf - 0.5f);
    const __m256 s =
        _mm256_sub_ps(select(less(uu, lo), lo, select(less(hi, uu), hi, uu)), set(0.5f));
    const __m256 i0 = floor(s);
    const __m256 fu = _mm256_sub_ps(s, i0);
    const __m256 i1 = std_min(_mm256_add_ps(i0, set(1.0f)), set(wf - 1.0f));
    const __m256 t = _mm256_sub_ps(vv, set(0.5f));
    const __m256 j0_raw = floor(t);
    const __m256 fv = _mm256_sub_ps(t, j0_raw);
    const __m256 j0 =
        select(less(j0_raw, zero()), _mm256_add_ps(j0_raw, set(hf)),
               select(at_least(j0_raw, set(hf)), _mm256_sub_ps(j0_raw, set(hf)), j0_raw));
    const __m256 j0_next = _mm256_add_ps(j0, set(1.0f));
    const __m256 j1 = select(equal(j0_next, set(hf)), zero(), j0_next);
    alignas(32) int ci[2][lanes], rj[2][lanes];
    _mm256_store_si256(reinterpret_cast<__m256i*>(ci[0]), _mm256_cvttps_epi32(i0));
    _mm256_store_si256(reinterpret_cast<__m256i*>(ci[1]), _mm256_cvttps_epi32(i1));
    _mm256_store_si256(reinterpret_cast<__m256i*>(rj[0]), _mm256_cvttps_epi32(j0));
    _mm256_store_si256(reinterpret_cast<__m256i*>(rj[1]), _mm256_cvttps_epi32(j1));

    // The taps (i0, j0), (i1, j0), (i0, j1), (i1, j1) and their validity, lane by lane (all
    // inside the buffer); a lane with an untraced tap is left to the reference.
    alignas(32) float taps[4][3][lanes], traced[4][lanes];
    const float* valid = in.buffer_valid.data.data();
    const float* buffer = in.buffer.data.data();
    for (int l = 0; l < lanes; ++l)
        for (int k = 0; k < 4; ++k) {
            const std::size_t texel =
                static_cast<std::size_t>(rj[k >> 1][l]) * static_cast<std::size_t>(w) +
                static_cast<std::size_t>(ci[k & 1][l]);
            traced[k][l] = valid[texel];
            for (int c = 0; c < 3; ++c) taps[k][c][l] = buffer[3 * texel + c];
        }
    __m256 all = not_equal(_mm256_load_ps(traced[0]), zero());
    for (int k = 1; k < 4; ++k) all = both(all, not_equal(_mm256_load_ps(traced[k]), zero()));
    const int all_traced = bits(all);
    alignas(32) float result[3][lanes];
    const __m256 row1 = greater(fv, zero());
    for (int c = 0; c < 3; ++c) {
        const __m256 r0 = lerp(_mm256_load_ps(taps[0][c]), _mm256_load_ps(taps[1][c]), fu);
        const __m256 r1 = lerp(_mm256_load_ps(taps[2][c]), _mm256_load_ps(taps[3][c]), fu);
        _mm256_store_ps(result[c], select(row1, lerp(r0, r1, fv), r0));
    }
    float* o = &out.data[out.index(x, y)];
    for (int l = 0; l < lanes; ++l) {
        if (!(all_traced >> l & 1)) {
            resolve_pixel(map, in, out, x + l, y, stats, nullptr, &table);
            continue;
        }
        ++stats.pixels_from_buffer;
        for (int c = 0; c < 3; ++c) o[3 * l + c] = result[c][l];
    }
    return true;
}

}  // namespace

bool resolve_avx_applies(const LogPolarMap& map, const ResolveInputs& in,
                         const ForwardTable* table) {
    // The lanes read the buffer and a one-channel mask of the map's size directly (the reference
    // checks the shapes as it reads, and throws).
    return table && in.buffer.channels == 3 && map.height >= 3 && in.buffer.height == map.height &&
           in.buffer_valid.channels == 1 && in.buffer_valid.height == map.height &&
           simd_allowed() && cpu_has_avx();
}

int resolve_row_avx(const LogPolarMap& map, const ResolveInputs& in, const ForwardTable& table,
                    Image& out, int y, ResolveStats& stats) {
    const int groups = map.screen_width / lanes;
    for (int group = 0; group < groups; ++group) {
        const int x = group * lanes;
        if (!resolve_group(map, in, table, out, x, y, stats))
            for (int l = 0; l < lanes; ++l)
                resolve_pixel(map, in, out, x + l, y, stats, nullptr, &table);
    }
    return groups * lanes;
}

}  // namespace fovref
