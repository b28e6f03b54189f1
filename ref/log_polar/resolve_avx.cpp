#include "ref/log_polar/resolve_avx.h"

#include <cstddef>
#include <cstdint>
#include <limits>

#include "ref/core/avx_lanes.h"
#include "ref/core/simd.h"

namespace fovref {

namespace {

using namespace avx;

/// lerp of resolve.cpp: a + t (b - a).
FOVREF_AVX_INLINE __m256 lerp(__m256 a, __m256 b, __m256 t) {
    return _mm256_add_ps(a, _mm256_mul_ps(t, _mm256_sub_ps(b, a)));
}

// The lanes of pixels x .. x + 7 of row y that read the gaze buffer (reads_gaze_buffer).
int gaze_lanes(const LogPolarMap& map, const GazeInput& gaze, int x, int y) {
    // A group outside the gaze buffer's window has none (reads_gaze_buffer's own first test).
    const ScreenWindow& w = gaze.window;
    if (!gaze.image || y < w.y0 || y >= w.y0 + w.height || x + lanes <= w.x0 || x >= w.x0 + w.width)
        return 0;
    int mask = 0;
    for (int l = 0; l < lanes; ++l) mask |= reads_gaze_buffer(map, gaze, x + l, y) ? 1 << l : 0;
    return mask;
}

// Pixels x .. x + 7 of row y, all inside the gaze circle: gaze_pixel's copies, one row of the
// gaze buffer (the circle lies inside the buffer's window, so the 8 pixels are consecutive there).
void copy_gaze_group(const GazeInput& gaze, Image& out, int x, int y, ResolveStats& stats) {
    const float* from =
        &gaze.image->data[gaze.image->index(x - gaze.window.x0, y - gaze.window.y0)];
    float* to = &out.at(x, y, 0);
    for (int k = 0; k < 3 * lanes; ++k) to[k] = from[k];
    stats.pixels_from_gaze += lanes;
}

// Pixels x .. x + 7 of row y. Returns false (nothing written) when the group needs the
// reference for all its pixels: some but not all of its pixels read the gaze buffer (or all do
// from a buffer that is not 3-channel), or a (u, v) lies outside the range lp_bilinear_index
// accepts (the reference then throws).
__attribute__((target("avx2"))) bool resolve_group(const LogPolarMap& map, const ResolveInputs& in,
                                                   const ForwardTable& table, Image& out, int x,
                                                   int y, ResolveStats& stats) {
    const int gaze = gaze_lanes(map, in.gaze, x, y);
    if (gaze == 0xff && in.gaze.image->channels == 3) {
        copy_gaze_group(in.gaze, out, x, y, stats);
        return true;
    }
    if (gaze != 0) return false;
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
    // The taps' texels j w + i: (i0, j0), (i1, j0), (i0, j1), (i1, j1), all inside the buffer;
    // their validity and colours gathered (AVX2), a lane with an untraced tap left to the
    // reference.
    const __m256i ci0 = _mm256_cvttps_epi32(i0), ci1 = _mm256_cvttps_epi32(i1);
    const __m256i cj0 = _mm256_cvttps_epi32(j0), cj1 = _mm256_cvttps_epi32(j1);
    const __m256i texels[4] = {row_major(ci0, cj0, w), row_major(ci1, cj0, w),
                               row_major(ci0, cj1, w), row_major(ci1, cj1, w)};
    const __m256 every = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
    __m256 taps[4][3];
    __m256 all = every;
    for (int k = 0; k < 4; ++k) {
        all = both(
            all, not_equal(_mm256_i32gather_ps(in.buffer_valid.data.data(), texels[k], 4), zero()));
        gather3_lanes(in.buffer.data.data(), texels[k], every, taps[k]);
    }
    const int all_traced = bits(all);
    alignas(32) float result[3][lanes];
    const __m256 row1 = greater(fv, zero());
    for (int c = 0; c < 3; ++c) {
        const __m256 r0 = lerp(taps[0][c], taps[1][c], fu);
        const __m256 r1 = lerp(taps[2][c], taps[3][c], fu);
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
    // checks the shapes as it reads, and throws); the gathers' indices 3 (j w + i) are int32, and
    // the tap columns are computed in binary32 (exact up to 2^24).
    const std::int64_t texels = static_cast<std::int64_t>(map.width) * map.height;
    return table && in.buffer.channels == 3 && map.height >= 3 && in.buffer.width == map.width &&
           in.buffer.height == map.height && in.buffer_valid.channels == 1 &&
           in.buffer_valid.width == map.width && in.buffer_valid.height == map.height &&
           map.width <= (1 << 24) && map.height <= (1 << 24) &&
           3 * texels <= std::numeric_limits<std::int32_t>::max() && simd_allowed() &&
           cpu_has_avx2();
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
