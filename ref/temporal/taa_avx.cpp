#include "ref/temporal/taa_avx.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "ref/core/avx_lanes.h"
#include "ref/core/simd.h"

namespace fovref {

namespace {

using namespace avx;

/// taa_floor_int (taa.h) in binary32: the truncation, one less where it exceeds v.
FOVREF_AVX_INLINE __m256 floor_value(__m256 v) {
    const __m256 t = _mm256_round_ps(v, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC);
    return select(greater(t, v), _mm256_sub_ps(t, set(1.0f)), t);
}

/// One group's reads and writes, lane by lane (row-major images).
struct Group {
    alignas(32) float current[3][lanes];
    alignas(32) float history[3][lanes];
    alignas(32) float age_previous[lanes];
};

/// Eight consecutive pixels of three interleaved channels (split3_lanes) into a group's arrays.
FOVREF_AVX2_INLINE void split3_into(const float* p, float (*out)[lanes]) {
    __m256 v[3];
    split3_lanes(p, v);
#pragma GCC unroll 3
    for (int c = 0; c < 3; ++c) _mm256_store_ps(out[c], v[c]);
}

/// The blend, shared by both cases: `ok` lanes have a usable history, `keep` of them a
/// consistent one (kept with age min(max(age', 1) + 1, cap)), the rest of `ok` lanes beyond the
/// periphery radius (`periphery`) age 2; every other lane is rejected (the current pixel, age
/// 1). The colours go to result[0 .. 2]; returns the ages (blend_and_write writes them; the
/// callers write the margins).
FOVREF_AVX_INLINE __m256 blend(const TaaParams& params, const Group& g, __m256 ok, __m256 keep,
                               __m256 periphery, __m256* result) {
    const __m256 age_kept =
        std_min(_mm256_add_ps(std_max(_mm256_load_ps(g.age_previous), set(1.0f)), set(1.0f)),
                set(static_cast<float>(params.age_cap)));
    const __m256 reject = negation(both(ok, either(keep, periphery)));
    const __m256 age_new = select(keep, age_kept, set(2.0f));
    const __m256 w = _mm256_div_ps(set(1.0f), age_new);
    const __m256 one_minus_w = _mm256_sub_ps(set(1.0f), w);
#pragma GCC unroll 3
    for (int c = 0; c < 3; ++c) {
        const __m256 current = _mm256_load_ps(g.current[c]);
        const __m256 blended = _mm256_add_ps(
            _mm256_mul_ps(_mm256_load_ps(g.history[c]), one_minus_w), _mm256_mul_ps(current, w));
        result[c] = select(reject, current, blended);
    }
    return select(reject, set(1.0f), age_new);
}

/// blend, the colours interleaved by merge3_lanes (AVX2).
FOVREF_AVX2_INLINE void blend_and_write(const TaaParams& params, const Group& g, __m256 ok,
                                        __m256 keep, __m256 periphery, int x, int y, Image& out,
                                        Image& age) {
    __m256 result[3];
    _mm256_storeu_ps(&age.data[age.index(x, y)], blend(params, g, ok, keep, periphery, result));
    merge3_lanes(result, &out.data[out.index(x, y)]);
}

/// The `taa_margin` channels of pixels x .. x + 7 (when wanted).
FOVREF_AVX_INLINE void write_margins(Image* margin, int x, int y, __m256 depth,
                                     __m256 reprojection) {
    if (!margin) return;
    alignas(32) float dm[lanes], rm[lanes];
    _mm256_store_ps(dm, depth);
    _mm256_store_ps(rm, reprojection);
    float* m = &margin->data[margin->index(x, y)];
    for (int l = 0; l < lanes; ++l) {
        m[l * 2] = dm[l];
        m[l * 2 + 1] = rm[l];
    }
}

/// clamp_history of taa.cpp for pixels x .. x + 7: the history (g.history, replaced) clamped
/// per channel, glm::clamp = min(max(h, lo), hi), to the box of `in.bounds` (clamp-buffer) or
/// of the current 3x3 neighbourhood (clamp-screen: lo = hi = the pixel, then glm::min and
/// glm::max with the nine neighbours, rows and columns clamped to the screen, row by row, in
/// clamp_to_neighbourhood's order). Returns the lanes where the clamp moved the history.
FOVREF_AVX2_INLINE __m256 clamp_group(const TaaInputs& in, int x, int y, Group& g) {
    __m256 lo[3], hi[3];
    if (in.bounds) {
        // Pixel l's box is 6 floats (3 minima, 3 maxima): read as sixteen 3-float halves, half
        // 2 l its minima and 2 l + 1 its maxima, split into channels (pixels 0..3 in first[c],
        // 4..7 in second[c], minima and maxima alternating), then the even and the odd lanes
        // gathered in pixel order: the same floats, moved.
        const float* b = &in.bounds->data[in.bounds->index(x, y)];
        __m256 first[3], second[3];
        split3_lanes(b, first);
        split3_lanes(b + 24, second);
        for (int c = 0; c < 3; ++c) {
            // per 128-bit half: (first 0, 2, second 0, 2) and (first 1, 3, second 1, 3)
            const __m256 even = _mm256_shuffle_ps(first[c], second[c], _MM_SHUFFLE(2, 0, 2, 0));
            const __m256 odd = _mm256_shuffle_ps(first[c], second[c], _MM_SHUFFLE(3, 1, 3, 1));
            lo[c] = _mm256_castpd_ps(
                _mm256_permute4x64_pd(_mm256_castps_pd(even), _MM_SHUFFLE(3, 1, 2, 0)));
            hi[c] = _mm256_castpd_ps(
                _mm256_permute4x64_pd(_mm256_castps_pd(odd), _MM_SHUFFLE(3, 1, 2, 0)));
        }
    } else if (x >= 1 && x + lanes < in.color.width) {
        // No column clamped: each of the nine neighbours' eight pixels are consecutive, plain
        // loads of the same floats (rows clamped as below), in the same order. The minima and
        // maxima are taken on the interleaved floats (each float's own chain, channel by
        // channel as in the reference), and the channels sorted out once at the end.
        const Image& color = in.color;
        const float* centre = &color.data[color.index(x, y)];
        __m256 lo_rgb[3], hi_rgb[3];
        // (The loops fully unrolled whatever the flags, the minima and maxima in registers: as
        // loops, plain g++ -O2 kept them on the stack, a store and a reload in every step.)
#pragma GCC unroll 3
        for (int k = 0; k < 3; ++k) lo_rgb[k] = hi_rgb[k] = _mm256_loadu_ps(centre + 8 * k);
#pragma GCC unroll 3
        for (int r = 0; r < 3; ++r) {
            const int sy = std::clamp(y + r - 1, 0, color.height - 1);
#pragma GCC unroll 3
            for (int dx = 0; dx < 3; ++dx) {
                const float* p = &color.data[color.index(x + dx - 1, sy)];
#pragma GCC unroll 3
                for (int k = 0; k < 3; ++k) {
                    const __m256 v = _mm256_loadu_ps(p + 8 * k);
                    lo_rgb[k] = std_min(lo_rgb[k], v);  // glm::min(a, b) = (b < a) ? b : a
                    hi_rgb[k] = std_max(hi_rgb[k], v);  // glm::max(a, b) = (a < b) ? b : a
                }
            }
        }
        split3_registers(lo_rgb[0], lo_rgb[1], lo_rgb[2], lo);
        split3_registers(hi_rgb[0], hi_rgb[1], hi_rgb[2], hi);
    } else {
        // Rows y - 1 .. y + 1 and columns x - 1 .. x + 8, clamped, one array per channel.
        const Image& color = in.color;
        float rows[3][3][lanes + 2];
        for (int r = 0; r < 3; ++r) {
            const int sy = std::clamp(y + r - 1, 0, color.height - 1);
            for (int i = 0; i < lanes + 2; ++i) {
                const float* v =
                    &color.data[color.index(std::clamp(x + i - 1, 0, color.width - 1), sy)];
                for (int c = 0; c < 3; ++c) rows[r][c][i] = v[c];
            }
        }
        for (int c = 0; c < 3; ++c) lo[c] = hi[c] = _mm256_loadu_ps(&rows[1][c][1]);
        for (int r = 0; r < 3; ++r)
            for (int dx = 0; dx < 3; ++dx)
                for (int c = 0; c < 3; ++c) {
                    const __m256 v = _mm256_loadu_ps(&rows[r][c][dx]);
                    lo[c] = std_min(lo[c], v);  // glm::min(a, b) = (b < a) ? b : a
                    hi[c] = std_max(hi[c], v);  // glm::max(a, b) = (a < b) ? b : a
                }
    }
    __m256 unchanged = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
    for (int c = 0; c < 3; ++c) {
        const __m256 h = _mm256_load_ps(g.history[c]);
        const __m256 clamped = std_min(std_max(h, lo[c]), hi[c]);
        unchanged = both(unchanged, equal(clamped, h));
        _mm256_store_ps(g.history[c], clamped);
    }
    return negation(unchanged);
}

// A stationary camera's eight pixels: the history and age at the pixel itself, never rejected
// for depth.
__attribute__((target("avx2"))) void stationary_group(const TaaParams& params, const TaaInputs& in,
                                                      const TaaState& previous, int x, int y,
                                                      Image& out, Image& age, TaaStats& stats) {
    Group g;
    split3_into(&in.color.data[in.color.index(x, y)], g.current);
    split3_into(&previous.history.data[previous.history.index(x, y)], g.history);
    _mm256_store_ps(g.age_previous, _mm256_loadu_ps(&previous.age.data[previous.age.index(x, y)]));
    const __m256 ok =
        both(both(finite(_mm256_load_ps(g.history[0])), finite(_mm256_load_ps(g.history[1]))),
             both(finite(_mm256_load_ps(g.history[2])), finite(_mm256_load_ps(g.age_previous))));
    const int kept = count(ok);
    stats.kept += kept;
    stats.reprojection_skipped += kept;
    stats.rejected += lanes - kept;
    stats.nonfinite_history += lanes - kept;
    blend_and_write(params, g, ok, ok, _mm256_setzero_ps(), x, y, out, age);
}

/// taa_reproject for pixels x .. x + 7 of row y at view depths z: their centres' x (cx), the
/// points p' = (px, py) and their previous view depth; returns the lanes reprojected (a surface,
/// z finite, in front of the previous camera).
FOVREF_AVX_INLINE __m256 reproject_lanes(const TaaReprojection& p, int x, int y, __m256 z,
                                         __m256& cx, __m256& px, __m256& py,
                                         __m256& previous_depth) {
    const float w = static_cast<float>(p.width), h = static_cast<float>(p.height);
    cx = _mm256_add_ps(
        _mm256_cvtepi32_ps(_mm256_setr_epi32(x, x + 1, x + 2, x + 3, x + 4, x + 5, x + 6, x + 7)),
        set(0.5f));
    const float cy = static_cast<float>(y) + 0.5f;
    const __m256 sx =
        _mm256_mul_ps(_mm256_sub_ps(_mm256_div_ps(_mm256_mul_ps(set(2.0f), cx), set(w)), set(1.0f)),
                      set(p.sx_scale));
    const float sy = ((2.0f * cy) / h - 1.0f) * p.sy_scale;
    __m256 q[3];
    for (int i = 0; i < 3; ++i) {
        const __m256 d = _mm256_sub_ps(_mm256_add_ps(set(p.f[i]), _mm256_mul_ps(sx, set(p.r[i]))),
                                       set(sy * p.u[i]));
        q[i] = _mm256_add_ps(set(p.o[i]), _mm256_mul_ps(z, d));
    }
    previous_depth = q[2];
    px = _mm256_add_ps(_mm256_mul_ps(q[0], _mm256_div_ps(set(p.a.x), previous_depth)),
                       set(0.5f * w));
    py = _mm256_add_ps(_mm256_mul_ps(q[1], _mm256_div_ps(set(p.a.y), previous_depth)),
                       set(0.5f * h));
    return both(both(greater(z, zero()), finite(z)), greater(previous_depth, zero()));
}

/// The reprojection margin: border_distance(p', -1/2, -1/2, W + 1/2, H + 1/2) where reprojected,
/// taa_no_margin elsewhere.
FOVREF_AVX_INLINE __m256 reprojection_margin(__m256 px, __m256 py, __m256 reprojected, float wf,
                                             float hf) {
    const __m256 x0 = set(-0.5f), y0 = set(-0.5f), x1 = set(wf + 0.5f), y1 = set(hf + 0.5f);
    const __m256 dx = std_max(std_max(_mm256_sub_ps(x0, px), _mm256_sub_ps(px, x1)), zero());
    const __m256 dy = std_max(std_max(_mm256_sub_ps(y0, py), _mm256_sub_ps(py, y1)), zero());
    const __m256 outside = either(greater(dx, zero()), greater(dy, zero()));
    const __m256 outside_distance =
        negate(_mm256_sqrt_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy))));
    const __m256 inside_distance = std_min(
        std_min(std_min(_mm256_sub_ps(px, x0), _mm256_sub_ps(x1, px)), _mm256_sub_ps(py, y0)),
        _mm256_sub_ps(y1, py));
    return select(reprojected, select(outside, outside_distance, inside_distance),
                  set(taa_no_margin));
}

/// The history's colour and depth at the taps on the screen ([tap][r, g, b, depth], zero where a
/// tap is off) and the previous age of the pixel under p' (clamped to the screen; p' lies within
/// a pixel of it; zero in the lanes without taps), gathered (AVX2: plain loads of the same
/// floats). Tap t is (x0 + (t & 1), y0 + (t >> 1)); the int32 indices are those of the taps on
/// the screen (taa_avx_applies checks that 3 W H fits), the others are never loaded.
FOVREF_AVX2_INLINE void gather_history(const TaaState& previous, const BilinearLanes& b,
                                       __m256 has_taps, __m256 px, __m256 py, __m256 (&taps)[4][4],
                                       float* age_previous) {
    const int width = previous.history.width, height = previous.history.height;
    // Every tap of every lane on the screen, the lanes' corners side by side in one row (a small
    // motion, most groups): each tap's eight pixels are consecutive, so their colours and depths
    // are plain loads of the same floats (the colours' channels sorted out by blends and
    // permutes).
    bool row = b.on_bits[0] == 0xff && b.on_bits[1] == 0xff && b.on_bits[2] == 0xff &&
               b.on_bits[3] == 0xff;
    for (int l = 1; l < lanes && row; ++l) row = b.x0[l] == b.x0[0] + l && b.y0[l] == b.y0[0];
    if (row) {
        for (int t = 0; t < 4; ++t) {
            const std::size_t pixel = b.pixel(t, 0, static_cast<std::size_t>(width));
            split3_lanes(&previous.history.data[3 * pixel], taps[t]);
            taps[t][3] = _mm256_loadu_ps(&previous.depth.data[pixel]);
        }
    } else {
        const __m256i first =
            row_major(_mm256_load_si256(reinterpret_cast<const __m256i*>(b.x0)),
                      _mm256_load_si256(reinterpret_cast<const __m256i*>(b.y0)), width);
        for (int t = 0; t < 4; ++t) {
            const __m256i pixel =
                _mm256_add_epi32(first, _mm256_set1_epi32((t >> 1) * width + (t & 1)));
            gather3_lanes(previous.history.data.data(), pixel, b.on[t], taps[t]);
            taps[t][3] =
                _mm256_mask_i32gather_ps(zero(), previous.depth.data.data(), pixel, b.on[t], 4);
        }
    }
    // The age under p': (clamp(floor(p'x), 0, W - 1), clamp(floor(p'y), 0, H - 1)).
    const __m256i ax = _mm256_min_epi32(
        _mm256_max_epi32(_mm256_cvttps_epi32(floor_value(px)), _mm256_setzero_si256()),
        _mm256_set1_epi32(width - 1));
    const __m256i ay = _mm256_min_epi32(
        _mm256_max_epi32(_mm256_cvttps_epi32(floor_value(py)), _mm256_setzero_si256()),
        _mm256_set1_epi32(height - 1));
    // (the ages side by side in one row, most groups: a plain load; else lane by lane; a lane
    // without taps reads an age it never uses: it is rejected)
    const __m256i at = row_major(ax, ay, width);
    const __m256i side_by_side = _mm256_add_epi32(_mm256_set1_epi32(_mm256_extract_epi32(at, 0)),
                                                  _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    const __m256 ages =
        _mm256_movemask_epi8(_mm256_cmpeq_epi32(at, side_by_side)) == -1
            ? _mm256_loadu_ps(
                  &previous.age.data[static_cast<std::size_t>(_mm256_extract_epi32(at, 0))])
            : load_lanes(previous.age.data.data(), at, has_taps);
    _mm256_store_ps(age_previous, ages);
}

/// sample_history's sums over the taps on the screen, in tap order, then the divisions: the
/// history colour into `history`, its depth into `depth`; returns the weights' sum.
FOVREF_AVX_INLINE __m256 sample_lanes(const BilinearLanes& b, const __m256 (&taps)[4][4],
                                      float (*history)[lanes], __m256& depth) {
    __m256 sum = zero(), acc[4] = {sum, sum, sum, sum};
    // (fully unrolled: the sums in registers, not on the stack)
#pragma GCC unroll 4
    for (int t = 0; t < 4; ++t) {
        sum = _mm256_add_ps(sum, select(b.on[t], b.weight[t], zero()));
#pragma GCC unroll 4
        for (int c = 0; c < 4; ++c)
            acc[c] = _mm256_add_ps(acc[c],
                                   select(b.on[t], _mm256_mul_ps(b.weight[t], taps[t][c]), zero()));
    }
#pragma GCC unroll 3
    for (int c = 0; c < 3; ++c) _mm256_store_ps(history[c], _mm256_div_ps(acc[c], sum));
    depth = _mm256_div_ps(acc[3], sum);
    return sum;
}

// Moving camera: taa_reproject, border_distance, sample_history, then the depth test and the
// periphery rule (depth rejection) or the clamp (clamp_group) of taa.cpp, lane by lane.
__attribute__((target("avx2"))) void moving_group(const TaaParams& params, const TaaInputs& in,
                                                  const TaaState& previous, const TaaConstants& k,
                                                  int x, int y, Image& out, Image& age,
                                                  Image* margin, TaaStats& stats) {
    const float wf = static_cast<float>(in.color.width), hf = static_cast<float>(in.color.height);
    Group g;
    split3_into(&in.color.data[in.color.index(x, y)], g.current);
    const __m256 z = _mm256_loadu_ps(&in.depth.data[in.depth.index(x, y)]);

    __m256 cx, px, py, previous_depth;
    const __m256 reprojected = reproject_lanes(k.reprojection, x, y, z, cx, px, py, previous_depth);
    const __m256 border = reprojection_margin(px, py, reprojected, wf, hf);

    // taa_taps: a tap on the screen only within a pixel of it.
    const __m256 has_taps =
        both(both(reprojected, both(greater(px, set(-1.0f)), greater(py, set(-1.0f)))),
             both(less(px, set(wf + 1.0f)), less(py, set(hf + 1.0f))));
    const __m256 tx = _mm256_sub_ps(select(has_taps, px, zero()), set(0.5f));
    const __m256 ty = _mm256_sub_ps(select(has_taps, py, zero()), set(0.5f));
    BilinearLanes b;
    bilinear_lanes(tx, ty, floor_value(tx), floor_value(ty), has_taps, wf, hf, b);
    __m256 taps[4][4];
    gather_history(previous, b, has_taps, px, py, taps, g.age_previous);

    // sample_history: the weighted sums in tap order, then the divisions.
    __m256 history_depth;
    const __m256 sum = sample_lanes(b, taps, g.history, history_depth);
    const __m256 sampled = both(has_taps, greater(sum, zero()));

    // The depth test and its margin (the margin in depth rejection only).
    const bool clamp = params.rejection == TaaRejection::clamp;
    const __m256 tau_z = _mm256_mul_ps(set(params.tau), previous_depth);
    const __m256 difference = abs(_mm256_sub_ps(previous_depth, history_depth));
    const __m256 no_margin = set(taa_no_margin);
    const __m256 depth_margin =
        clamp ? no_margin
              : select(sampled, _mm256_div_ps(_mm256_sub_ps(tau_z, difference), previous_depth),
                       no_margin);
    const __m256 consistent = at_most(difference, tau_z);
    const __m256 all_finite = both(
        both(both(finite(_mm256_load_ps(g.history[0])), finite(_mm256_load_ps(g.history[1]))),
             both(finite(_mm256_load_ps(g.history[2])), finite(_mm256_load_ps(g.age_previous)))),
        finite(history_depth));
    const __m256 ok = both(sampled, all_finite);
    const __m256 nonfinite = _mm256_or_ps(negation(finite(z)), both(sampled, negation(all_finite)));

    if (clamp) {
        // Karis's clamp (clamp_history): never rejected for depth, no periphery rule.
        const __m256 moved = clamp_group(in, x, y, g);
        blend_and_write(params, g, ok, ok, zero(), x, y, out, age);
        stats.clamped += count(both(ok, moved));
        stats.kept += count(ok) - count(both(ok, moved));
        stats.rejected += lanes - count(ok);
        stats.nonfinite_history += count(nonfinite);
        write_margins(margin, x, y, depth_margin, border);
        return;
    }

    // The periphery rule: the pixel centre's distance from the gaze.
    const __m256 gx_ = _mm256_sub_ps(cx, set(in.gaze.x));
    const float gy_ = (static_cast<float>(y) + 0.5f) - in.gaze.y;
    const __m256 gaze_r = _mm256_sqrt_ps(_mm256_add_ps(_mm256_mul_ps(gx_, gx_), set(gy_ * gy_)));
    const __m256 periphery = greater(gaze_r, set(params.periphery * k.diagonal));

    const __m256 keep = both(ok, consistent);
    const __m256 periphery_kept = both(both(ok, negation(consistent)), periphery);
    blend_and_write(params, g, ok, consistent, periphery, x, y, out, age);
    stats.kept += count(keep);
    stats.periphery_kept += count(periphery_kept);
    stats.rejected += lanes - count(keep) - count(periphery_kept);
    stats.nonfinite_history += count(nonfinite);
    write_margins(margin, x, y, depth_margin, border);
}

}  // namespace

bool taa_avx_applies(const TaaInputs& in, const TaaState& previous) {
    // The lanes need AVX2 (the gathers, and the colours' blends and permutes). They read
    // one-channel depths and ages directly (taa() checks the other shapes); the gathers' indices
    // 3 (y W + x) are int32, and the taps' corners are computed in binary32 (exact up to 2^24).
    const std::int64_t pixels =
        static_cast<std::int64_t>(previous.history.width) * previous.history.height;
    return previous.valid && in.depth.channels == 1 && previous.depth.channels == 1 &&
           previous.age.channels == 1 && previous.history.width <= (1 << 24) &&
           previous.history.height <= (1 << 24) &&
           3 * pixels <= std::numeric_limits<std::int32_t>::max() && simd_allowed() &&
           cpu_has_avx2();
}

int taa_row_avx(const TaaParams& params, const TaaInputs& in, const TaaState& previous,
                const TaaConstants& k, int y, Image& out, Image& age, Image* margin,
                TaaStats& stats) {
    const int groups = in.color.width / lanes;
    for (int group = 0; group < groups; ++group) {
        const int x = group * lanes;
        if (k.stationary) {
            stationary_group(params, in, previous, x, y, out, age, stats);
            if (margin) {
                float* m = &margin->data[margin->index(x, y)];
                std::fill(m, m + 2 * lanes, taa_no_margin);
            }
        } else {
            moving_group(params, in, previous, k, x, y, out, age, margin, stats);
        }
    }
    return groups * lanes;
}

namespace {

/// Lanes a, a + 1, a + 2 of v, mod 8 (vpermps reads an index's low three bits), in lanes 0 .. 2.
FOVREF_AVX2_INLINE __m128 pick3(__m256 v, int a) {
    return _mm256_castps256_ps128(
        _mm256_permutevar8x32_ps(v, _mm256_setr_epi32(a, a + 1, a + 2, a + 2, 0, 0, 0, 0)));
}

/// The eight texels' triples of 24 interleaved floats (texel l's channel c is float 3 l + c of
/// v[0], v[1], v[2] in turn), texel l's three in lanes 0 .. 2 of triples[l] (lane 3 unspecified):
/// permutes within a register, and a blend first for the two texels whose floats straddle two.
FOVREF_AVX2_INLINE void texel_triples(const __m256* v, __m128* triples) {
    triples[0] = _mm256_castps256_ps128(v[0]);
    triples[1] = pick3(v[0], 3);
    // floats 6, 7 | 8: float 8 (v[1] lane 0) into lane 0 of v[0], then lanes 6, 7, 0
    triples[2] = pick3(_mm256_blend_ps(v[0], v[1], 0x01), 6);
    triples[3] = pick3(v[1], 1);
    triples[4] = _mm256_extractf128_ps(v[1], 1);
    // floats 15 | 16, 17: float 15 (v[1] lane 7) into lane 7 of v[2], then lanes 7, 0, 1
    triples[5] = pick3(_mm256_blend_ps(v[2], v[1], 0x80), 7);
    triples[6] = pick3(v[2], 2);
    triples[7] = pick3(v[2], 5);
}

}  // namespace

bool texel_boxes_avx_applies(const Image& image, const Image& valid) {
    return image.channels == 3 && valid.channels == 1 && valid.width == image.width &&
           valid.height == image.height && image.width >= 10 && simd_allowed() && cpu_has_avx2();
}

__attribute__((target("avx2"))) int texel_boxes_row_avx(const Image& image, const Image& valid,
                                                        bool wrap_rows, bool traced_only, int sj,
                                                        float* records) {
    const int w = image.width, h = image.height;
    int rows[3];
    for (int dj = -1; dj <= 1; ++dj)
        rows[dj + 1] = wrap_rows ? (sj + dj + h) % h : std::clamp(sj + dj, 0, h - 1);
    // The eight texels' 24 floats in three registers, as the image holds them (texel l's channel
    // c is float 3 l + c): each float's min and max chain is its own, so the taps' colours need
    // no sorting into channels; a texel's traced mask is spread to its three floats
    // (spread3_lanes).
    const __m256 inf = set(std::numeric_limits<float>::infinity());
    int si = 1;
    for (; si + lanes <= w - 1; si += lanes) {
        if (traced_only && _mm256_movemask_ps(not_equal(
                               _mm256_loadu_ps(&valid.data[valid.index(si, sj)]), zero())) == 0)
            continue;
        const float* own = &image.data[image.index(si, sj)];
        __m256 lo[3], hi[3];
        // (Fully unrolled, lo and hi in registers: see clamp_group.)
#pragma GCC unroll 3
        for (int k = 0; k < 3; ++k) lo[k] = hi[k] = _mm256_loadu_ps(own + 8 * k);
#pragma GCC unroll 3
        for (const int j : rows)
#pragma GCC unroll 3
            for (int di = -1; di <= 1; ++di) {
                // a tap counts where its mask is not 0 (NaN counts, as valid != 0 does)
                const __m256 traced =
                    not_equal(_mm256_loadu_ps(&valid.data[valid.index(si + di, j)]), zero());
                __m256 traced_floats[3];
                spread3_lanes(traced, traced_floats);
                const float* tap = &image.data[image.index(si + di, j)];
#pragma GCC unroll 3
                for (int k = 0; k < 3; ++k) {
                    const __m256 t = traced_floats[k];
                    const __m256 v = _mm256_loadu_ps(tap + 8 * k);
                    // std::min(lo, v) = (v < lo) ? v : lo and std::max(hi, v) = (hi < v) ? v :
                    // hi where traced; an untraced tap is +inf for the min (never < lo) and -inf
                    // for the max (hi never < it). t is a comparison's full lane mask, so
                    // blendv's sign-bit choice is select's.
                    lo[k] = std_min(lo[k], _mm256_blendv_ps(inf, v, t));
                    hi[k] = std_max(hi[k], _mm256_blendv_ps(negate(inf), v, t));
                }
            }
        // Texel l's box is its three minima then its three maxima: four floats stored from each
        // (the fourth overwritten by the next store; the last one lands on the texel's float 6,
        // which the caller writes after this group), taken from the registers (texel_triples)
        float* to = records + static_cast<std::size_t>(si) * taa_record_channels;
        __m128 lows[lanes], highs[lanes];
        texel_triples(lo, lows);
        texel_triples(hi, highs);
        for (int l = 0; l < lanes; ++l) {
            _mm_storeu_ps(to + taa_record_channels * l, lows[l]);
            _mm_storeu_ps(to + taa_record_channels * l + 3, highs[l]);
        }
    }
    return si;
}

}  // namespace fovref
