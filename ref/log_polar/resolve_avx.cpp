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

/// The lanes of `mask` whose (u, v) lp_bilinear_index accepts (a finite u, v within
/// [-1, h + 1]; the reference throws for the others).
FOVREF_AVX_INLINE int accepted_lanes(__m256 uu, __m256 vv, __m256 mask, float h) {
    return bits(
        both(mask, both(finite(uu), both(at_least(vv, set(-1.0f)), at_most(vv, set(h + 1.0f))))));
}

/// sample_lp_bilinear of a 3-channel buffer (its mask one channel of its size, at least 3 rows)
/// at (u, v) in the lanes of `mask`, which accepted_lanes accepts: the lanes' values in
/// out[0 .. 2], as the reference's path for four traced taps computes them; returns the lanes of
/// `mask` whose four taps are all traced (the others are the reference's to do). The taps'
/// validity and colours are masked gathers: a lane outside `mask` reads nothing.
FOVREF_AVX2_INLINE int bilinear_traced_lanes(__m256 uu, __m256 vv, __m256 mask, const Image& buffer,
                                             const Image& valid, __m256* out) {
    const int w = buffer.width;
    const float wf = static_cast<float>(w), hf = static_cast<float>(buffer.height);
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
    // The taps' texels j w + i: (i0, j0), (i1, j0), (i0, j1), (i1, j1), all inside the buffer in
    // the lanes of `mask`.
    const __m256i ci0 = _mm256_cvttps_epi32(i0), ci1 = _mm256_cvttps_epi32(i1);
    const __m256i cj0 = _mm256_cvttps_epi32(j0), cj1 = _mm256_cvttps_epi32(j1);
    const __m256i texels[4] = {row_major(ci0, cj0, w), row_major(ci1, cj0, w),
                               row_major(ci0, cj1, w), row_major(ci1, cj1, w)};
    __m256 taps[4][3];
    __m256 all = mask;
    for (int k = 0; k < 4; ++k) {
        const __m256 traced =
            _mm256_mask_i32gather_ps(zero(), valid.data.data(), texels[k], mask, 4);
        all = both(all, not_equal(traced, zero()));
        gather3_lanes(buffer.data.data(), texels[k], mask, taps[k]);
    }
    const __m256 row1 = greater(fv, zero());
    for (int c = 0; c < 3; ++c) {
        const __m256 r0 = lerp(taps[0][c], taps[1][c], fu);
        const __m256 r1 = lerp(taps[2][c], taps[3][c], fu);
        out[c] = select(row1, lerp(r0, r1, fv), r0);
    }
    return bits(all);
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
    alignas(32) float u[lanes], v[lanes];
    const glm::vec2* uv = &table.uv[static_cast<std::size_t>(y) * map.screen_width + x];
    for (int l = 0; l < lanes; ++l) u[l] = uv[l].x, v[l] = uv[l].y;
    const __m256 uu = _mm256_load_ps(u), vv = _mm256_load_ps(v);
    const __m256 every = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
    if (accepted_lanes(uu, vv, every, static_cast<float>(map.height)) != 0xff) return false;
    __m256 values[3];
    const int all_traced = bilinear_traced_lanes(uu, vv, every, in.buffer, in.buffer_valid, values);
    alignas(32) float result[3][lanes];
    for (int c = 0; c < 3; ++c) _mm256_store_ps(result[c], values[c]);
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

// One of resolve_mip_pixel's two samples (l0 or l1) in the lanes of `wanted`, each lane at its
// `level`: for each level among the lanes, the lanes of that level sampled at (u, v) / 2^level
// (exact) by bilinear_traced_lanes; their values go to out[0 .. 2]. Returns the lanes of
// `wanted` that need the reference: an untraced tap, a (u, v) that lp_bilinear_index would
// refuse, or a level fewer than 3 rows high (the single wrap step).
FOVREF_AVX2_INLINE int sample_levels(const std::vector<MipLevel>& mips, __m256 level, int wanted,
                                     __m256 uu, __m256 vv, __m256* out) {
    int reference = 0;
    for (int todo = wanted; todo != 0;) {
        float this_level = 0.0f;
        const int in_level = take_equal_lanes(level, todo, this_level);
        const int index = static_cast<int>(this_level);
        const MipLevel& m = mips[static_cast<std::size_t>(index)];
        if (m.color.height < 3) {
            reference |= in_level;
            continue;
        }
        const float scale = 1.0f / static_cast<float>(1 << index);  // exact: 2^-level
        const __m256 su = _mm256_mul_ps(uu, set(scale)), sv = _mm256_mul_ps(vv, set(scale));
        const int accepted =
            accepted_lanes(su, sv, mask_of(in_level), static_cast<float>(m.color.height));
        reference |= in_level & ~accepted;
        if (accepted == 0) continue;
        __m256 values[3];
        const int traced =
            bilinear_traced_lanes(su, sv, mask_of(accepted), m.color, m.valid, values);
        reference |= accepted & ~traced;
        const __m256 mine = mask_of(accepted);
        for (int c = 0; c < 3; ++c) out[c] = select(mine, values[c], out[c]);
    }
    return reference;
}

// Pixels x .. x + 7 of row y of the mip resolve, as resolve_group. A lane whose level is not
// finite leaves the group to the reference.
__attribute__((target("avx2"))) bool resolve_mip_group(const LogPolarMap& map,
                                                       const std::vector<MipLevel>& mips,
                                                       const GazeInput& gaze_in,
                                                       const ForwardTable& table, Image& out, int x,
                                                       int y, ResolveStats& stats) {
    const int gaze = gaze_lanes(map, gaze_in, x, y);
    if (gaze == 0xff && gaze_in.image->channels == 3) {
        copy_gaze_group(gaze_in, out, x, y, stats);
        return true;
    }
    if (gaze != 0) return false;
    const std::size_t k = static_cast<std::size_t>(y) * map.screen_width + x;
    const __m256 raw = _mm256_loadu_ps(&table.mip_lambda[k]);
    if (bits(finite(raw)) != 0xff) return false;
    // std::clamp(raw, 0, levels - 1), floor, l1 = min(l0 + 1, levels - 1), f = lambda - l0 (all
    // small integers, exact in binary32)
    const __m256 top = set(static_cast<float>(mips.size() - 1));
    const __m256 lambda = select(less(raw, zero()), zero(), select(less(top, raw), top, raw));
    const __m256 l0 = floor(lambda);
    const __m256 f = _mm256_sub_ps(lambda, l0);
    const __m256 l1 = std_min(_mm256_add_ps(l0, set(1.0f)), top);
    const int second = bits(both(not_equal(l1, l0), greater(f, zero())));
    alignas(32) float u[lanes], v[lanes];
    const glm::vec2* uv = &table.uv[k];
    for (int l = 0; l < lanes; ++l) u[l] = uv[l].x, v[l] = uv[l].y;
    const __m256 uu = _mm256_load_ps(u), vv = _mm256_load_ps(v);
    __m256 a[3] = {zero(), zero(), zero()}, b[3] = {zero(), zero(), zero()};
    int reference = sample_levels(mips, l0, 0xff, uu, vv, a);
    reference |= sample_levels(mips, l1, second & ~reference, uu, vv, b);
    alignas(32) float result[3][lanes];
    const __m256 two = mask_of(second);
    for (int c = 0; c < 3; ++c)
        _mm256_store_ps(
            result[c],
            select(two, _mm256_add_ps(a[c], _mm256_mul_ps(f, _mm256_sub_ps(b[c], a[c]))), a[c]));
    float* o = &out.data[out.index(x, y)];
    for (int l = 0; l < lanes; ++l) {
        if (reference >> l & 1) {
            resolve_mip_pixel(map, mips, gaze_in, out, x + l, y, stats, nullptr, &table);
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

bool resolve_mip_avx_applies(const LogPolarMap& map, const std::vector<MipLevel>& mips,
                             const ForwardTable* table) {
    // As resolve_avx_applies, for every level: a 3-channel colour and a one-channel mask of the
    // same size (level 0 the map's), read directly by the lanes.
    if (!table || table->mip_levels != static_cast<int>(mips.size()) || mips.empty() ||
        mips[0].color.width != map.width || mips[0].color.height != map.height)
        return false;
    const std::int64_t texels = static_cast<std::int64_t>(map.width) * map.height;
    if (map.width > (1 << 24) || map.height > (1 << 24) ||
        3 * texels > std::numeric_limits<std::int32_t>::max() || !simd_allowed() || !cpu_has_avx2())
        return false;
    for (const MipLevel& m : mips)
        if (m.color.channels != 3 || m.valid.channels != 1 || m.valid.width != m.color.width ||
            m.valid.height != m.color.height)
            return false;
    return true;
}

int resolve_mip_row_avx(const LogPolarMap& map, const std::vector<MipLevel>& mips,
                        const GazeInput& gaze, const ForwardTable& table, Image& out, int y,
                        ResolveStats& stats) {
    const int groups = map.screen_width / lanes;
    for (int group = 0; group < groups; ++group) {
        const int x = group * lanes;
        if (!resolve_mip_group(map, mips, gaze, table, out, x, y, stats))
            for (int l = 0; l < lanes; ++l)
                resolve_mip_pixel(map, mips, gaze, out, x + l, y, stats, nullptr, &table);
    }
    return groups * lanes;
}

}  // namespace fovref
