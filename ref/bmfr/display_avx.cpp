#include "ref/bmfr/display_avx.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "ref/bmfr/vp_taps_avx.h"
#include "ref/core/avx_lanes.h"
#include "ref/core/simd.h"

namespace fovref {

namespace {

using namespace avx;

/// The neighbours' values where the mask `on` is set; elsewhere +inf for the minima and -inf
/// for the maxima, which leave every extent as it is (std_min(a, +inf) and std_max(a, -inf) are
/// a, NaN included).
FOVREF_AVX2_INLINE void keep_traced(__m256 on, __m256* v_min, __m256* v_max) {
    const __m256 inf = set(INFINITY);
    for (int c = 0; c < 3; ++c) {
        v_min[c] = select(on, v_min[c], inf);
        v_max[c] = select(on, v_max[c], negate(inf));
    }
}

/// The 3x3 neighbours of pixels x .. x + 7 on three shared rows (row[0 .. 2] for dy = -1, 0, +1;
/// -1: no such row), all of them (screen space) or, with a `valid` mask, the traced ones.
struct RowNeighbours {
    const Image& ycocg;
    const Image* valid;
    int row[3];
    int x;
    bool has_row(int dy) const { return row[dy + 1] >= 0; }
    FOVREF_AVX2_INLINE void load(int dx, int dy, __m256* v_min, __m256* v_max) const {
        const int sy = row[dy + 1];
        split3_lanes(&ycocg.data[ycocg.index(x + dx, sy)], v_min);
        for (int c = 0; c < 3; ++c) v_max[c] = v_min[c];
        if (valid)
            keep_traced(not_equal(_mm256_loadu_ps(&valid->data[valid->index(x + dx, sy)]), zero()),
                        v_min, v_max);
    }
};

/// The 3x3 neighbours of texels x .. x + 7 of row y in the fovea (vp_taa_pixel's): on column
/// x + l + dx, which has n rows, the base row min(floor(t n), n - 1) of t = (y + 1/2) / n_(x + l)
/// and its neighbours wrapped, the traced ones, read lane by lane.
struct ColumnNeighbours {
    const Image& ycocg;
    const Image& valid;
    const int* column_rows;  ///< n of every column
    int x;
    __m256 t;
    bool has_row(int) const { return true; }
    FOVREF_AVX2_INLINE void load(int dx, int dy, __m256* v_min, __m256* v_max) const {
        const __m256i rows =
            _mm256_loadu_si256(reinterpret_cast<const __m256i*>(column_rows + x + dx));
        const __m256i base =
            _mm256_min_epi32(_mm256_cvttps_epi32(_mm256_mul_ps(t, _mm256_cvtepi32_ps(rows))),
                             _mm256_sub_epi32(rows, _mm256_set1_epi32(1)));
        // vp_wrap_row(base + dy, n): base + dy lies in [-1, n]
        __m256i j = _mm256_add_epi32(base, _mm256_set1_epi32(dy));
        j = _mm256_add_epi32(j,
                             _mm256_and_si256(_mm256_cmpgt_epi32(_mm256_setzero_si256(), j), rows));
        j = _mm256_sub_epi32(j, _mm256_andnot_si256(_mm256_cmpgt_epi32(rows, j), rows));
        const __m256i column =
            _mm256_add_epi32(_mm256_set1_epi32(x + dx), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
        const __m256i pixel = row_major(column, j, ycocg.width);
        const __m256 all = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
        gather3_lanes(ycocg.data.data(), pixel, all, v_min);
        for (int c = 0; c < 3; ++c) v_max[c] = v_min[c];
        keep_traced(
            not_equal(_mm256_mask_i32gather_ps(zero(), valid.data.data(), pixel, all, 4), zero()),
            v_min, v_max);
    }
};

/// taa_blend's clamp range for eight pixels: the extents in YCoCg of the 3x3 box and the 5-tap
/// cross of the neighbours that are there (`n`: RowNeighbours or ColumnNeighbours), from
/// +-infinity with glm::min(a, v) = (v < a) ? v : a and glm::max(a, v) = (a < v) ? v : a in
/// row-major order; lo = (box min + cross min) 0.5, hi = (box max + cross max) 0.5.
template <class Neighbours>
FOVREF_AVX2_INLINE void clamp_range(const Neighbours& n, __m256* lo, __m256* hi) {
    const __m256 inf = set(INFINITY);
    __m256 box_min[3], box_max[3], cross_min[3], cross_max[3];
    for (int c = 0; c < 3; ++c) {
        box_min[c] = cross_min[c] = inf;
        box_max[c] = cross_max[c] = negate(inf);
    }
    for (int dy = -1; dy <= 1; ++dy) {
        if (!n.has_row(dy)) continue;
        for (int dx = -1; dx <= 1; ++dx) {
            __m256 v_min[3], v_max[3];
            n.load(dx, dy, v_min, v_max);
            for (int c = 0; c < 3; ++c) {
                box_min[c] = std_min(box_min[c], v_min[c]);
                box_max[c] = std_max(box_max[c], v_max[c]);
                if (dx == 0 || dy == 0) {
                    cross_min[c] = std_min(cross_min[c], v_min[c]);
                    cross_max[c] = std_max(cross_max[c], v_max[c]);
                }
            }
        }
    }
    for (int c = 0; c < 3; ++c) {
        lo[c] = _mm256_mul_ps(_mm256_add_ps(box_min[c], cross_min[c]), set(0.5f));
        hi[c] = _mm256_mul_ps(_mm256_add_ps(box_max[c], cross_max[c]), set(0.5f));
    }
}

/// taa_blend's end for pixels x .. x + 7 of row y: the history h over the taps that are on
/// (tap_sums3), renormalised; in the lanes of `candidate` whose total is positive, rgb_to_ycocg
/// of it clamped to [lo, hi], ycocg_to_rgb, then taa_alpha of the current colour blended with
/// the rest into `out`; the current colour elsewhere. Returns the lanes that used the history.
FOVREF_AVX2_INLINE int blend_group(const BmfrParams& params, const Image& display, const __m256* on,
                                   const __m256* weight, const float (*values)[3][lanes],
                                   __m256 candidate, const __m256* lo, const __m256* hi, Image& out,
                                   int x, int y) {
    __m256 current[3];
    split3_lanes(&display.data[display.index(x, y)], current);
    __m256 h[3];
    const __m256 total = tap_sums3(on, weight, values, h);
    const __m256 used = both(candidate, greater(total, zero()));
    for (int c = 0; c < 3; ++c) h[c] = _mm256_div_ps(h[c], total);
    // rgb_to_ycocg(h), clamped to the extents' averages, ycocg_to_rgb, then the blend.
    const __m256 two = set(2.0f), quarter = set(0.25f);
    __m256 v[3] = {_mm256_add_ps(_mm256_add_ps(h[0], _mm256_mul_ps(two, h[1])), h[2]),
                   _mm256_sub_ps(_mm256_mul_ps(two, h[0]), _mm256_mul_ps(two, h[2])),
                   _mm256_sub_ps(_mm256_add_ps(negate(h[0]), _mm256_mul_ps(two, h[1])), h[2])};
    for (int c = 0; c < 3; ++c)
        v[c] = std_min(std_max(v[c], lo[c]), hi[c]);  // glm::clamp = min(max(v, lo), hi)
    const __m256 clamped[3] = {
        _mm256_mul_ps(_mm256_sub_ps(_mm256_add_ps(v[0], v[1]), v[2]), quarter),
        _mm256_mul_ps(_mm256_add_ps(v[0], v[2]), quarter),
        _mm256_mul_ps(_mm256_sub_ps(_mm256_sub_ps(v[0], v[1]), v[2]), quarter)};
    const __m256 alpha = set(params.taa_alpha), beta = set(1.0f - params.taa_alpha);
    __m256 o[3];
    for (int c = 0; c < 3; ++c)
        o[c] = select(
            used, _mm256_add_ps(_mm256_mul_ps(current[c], alpha), _mm256_mul_ps(clamped[c], beta)),
            current[c]);
    merge3_lanes(o, &out.data[out.index(x, y)]);
    return count(used);
}

/// bmfr_taa_pixel in screen space for pixels x .. x + 7 of row y (columns x - 1 .. x + 8 on the
/// image).
__attribute__((target("avx2"))) int taa_group(const BmfrParams& params, const Image& display,
                                              const Image& ycocg, const Image& previous_pixel,
                                              const Image& history, Image& out, int x, int y) {
    const int width = display.width, height = display.height;
    const float wf = static_cast<float>(width), hf = static_cast<float>(height);
    // q, and the reference's range test: floor(q) in [-1, W - 1] x [-1, H - 1]
    alignas(32) float q[2][lanes];
    load2_lanes(&previous_pixel.data[previous_pixel.index(x, y)], q);
    const __m256 qx = _mm256_load_ps(q[0]), qy = _mm256_load_ps(q[1]);
    const __m256 in_range = both(both(at_least(qx, set(-1.0f)), at_least(qy, set(-1.0f))),
                                 both(less(qx, set(wf)), less(qy, set(hf))));
    // bmfr_taps(q): q is finite in the lanes that use it, and clamped to +-1e6 as there (which
    // matters only on an image wider or taller than 1e6)
    const __m256 big = set(1e6f);
    const __m256 tx = select(in_range, std_min(std_max(qx, negate(big)), big), zero());
    const __m256 ty = select(in_range, std_min(std_max(qy, negate(big)), big), zero());
    BilinearLanes b;
    bilinear_lanes(tx, ty, floor(tx), floor(ty), in_range, wf, hf, b);

    __m256 lo[3], hi[3];
    clamp_range(RowNeighbours{ycocg, nullptr, {y - 1, y, y + 1 < height ? y + 1 : -1}, x}, lo, hi);
    // The history over the taps inside the image, in tap order.
    alignas(32) float taps[4][3][lanes];
    const auto history_width = static_cast<std::size_t>(history.width);
    load3_taps(
        history.data.data(), history.data.size() / 3, b.on,
        [&](int k, int l) { return b.pixel(k, l, history_width); }, taps);
    return blend_group(params, display, b.on, b.weight, taps, in_range, lo, hi, out, x, y);
}

/// vp_taa_group's end: the taps' history, the clamp range, the blend.
template <class GroupTaps>
FOVREF_AVX2_INLINE int vp_taa_blend(const BmfrParams& params, const Image& display,
                                    const Image& ycocg, const Image& history, const Image& valid,
                                    int fovea_columns, const int* column_rows, const GroupTaps& g,
                                    __m256 candidate, Image& out, int x, int y) {
    alignas(32) float taps[4][3][lanes];
    load3_taps(
        history.data.data(), history.data.size() / 3, g.on,
        [&](int k, int l) { return g.index(k, l); }, taps);
    __m256 lo[3], hi[3];
    if (x - 1 >= fovea_columns) {
        // beyond the fovea every column has H rows: the same three rows for every lane
        const int height = display.height;
        const float t = (static_cast<float>(y) + 0.5f) / static_cast<float>(height);
        const int base = std::min(static_cast<int>(t * static_cast<float>(height)), height - 1);
        clamp_range(
            RowNeighbours{ycocg,
                          &valid,
                          {vp_wrap_row(base - 1, height), base, vp_wrap_row(base + 1, height)},
                          x},
            lo, hi);
    } else {
        const __m256 rows = _mm256_cvtepi32_ps(
            _mm256_loadu_si256(reinterpret_cast<const __m256i*>(column_rows + x)));
        clamp_range(ColumnNeighbours{ycocg, valid, column_rows, x,
                                     _mm256_div_ps(set(static_cast<float>(y) + 0.5f), rows)},
                    lo, hi);
    }
    return blend_group(params, display, g.on, g.weight, taps, candidate, lo, hi, out, x, y);
}

/// bmfr_taa_pixel in Visual-Polar space for texels x .. x + 7 of row y (columns x - 1 .. x + 8
/// on the image): the neighbours on three rows shared by the lanes where those columns all lie
/// beyond the fovea (each has H rows), else on each lane's columns' own rows (ColumnNeighbours);
/// the history's taps from vp_tap_lanes, or where a lane's columns lie in the history map's
/// fovea, listed lane by lane (bmfr_vp_taps).
__attribute__((target("avx2"))) int vp_taa_group(const BmfrParams& params, const Image& display,
                                                 const Image& ycocg, const Image& previous_pixel,
                                                 const Image& history, const BmfrSpace& space,
                                                 const int* column_rows, Image& out, int x, int y) {
    const int width = display.width, height = display.height;
    const Image& valid = *space.valid;
    const VisualPolarMap& history_map = space.history_map();
    // The candidates: traced texels whose reprojected column q.x lies in [-1, W)
    alignas(32) float q[2][lanes];
    load2_lanes(&previous_pixel.data[previous_pixel.index(x, y)], q);
    const __m256 qx = _mm256_load_ps(q[0]), qy = _mm256_load_ps(q[1]);
    const __m256 traced = not_equal(_mm256_loadu_ps(&valid.data[valid.index(x, y)]), zero());
    const __m256 candidate =
        both(traced, both(at_least(qx, set(-1.0f)), less(qx, set(static_cast<float>(width)))));
    if (bits(candidate) == 0) {  // no lane uses the history: each keeps its current colour
        std::copy_n(&display.data[display.index(x, y)], 3 * lanes, &out.data[out.index(x, y)]);
        return 0;
    }
    // The history's taps on texels traced in the previous frame
    LaneTaps lane_taps;
    if (vp_tap_lanes(history_map, qx, qy, candidate, width, height, lane_taps)) {
        if (space.previous_valid) mask_taps(lane_taps, *space.previous_valid);
        return vp_taa_blend(params, display, ycocg, history, valid, space.map->fovea_columns,
                            column_rows, lane_taps, candidate, out, x, y);
    }
    ListedTaps g;
    const int candidate_bits = bits(candidate);
    for (int l = 0; l < lanes; ++l) {
        if (!(candidate_bits >> l & 1)) continue;
        const BmfrTaps t = bmfr_vp_taps(history_map, {q[0][l], q[1][l]});
        set_lane_taps(g, l, t, width, height, [&](int k) {
            return !space.previous_valid || space.previous_valid->at(t.x[k], t.y[k]) != 0.0f;
        });
    }
    load_listed(g);
    return vp_taa_blend(params, display, ycocg, history, valid, space.map->fovea_columns,
                        column_rows, g, candidate, out, x, y);
}

}  // namespace

namespace {

bool same_mask_shape(const Image* mask, const Image& display) {
    return mask && mask->channels == 1 && mask->width == display.width &&
           mask->height == display.height;
}

bool same_map_shape(const VisualPolarMap& map, const Image& display) {
    return map.width == display.width && map.height == display.height;
}

}  // namespace

BmfrTaaSpan bmfr_taa_avx_span(const Image& display, const Image& history, const BmfrSpace& space) {
    const BmfrTaaSpan none{display.width, display.width, {}};
    if (history.empty() || display.channels != 3 || history.channels != 3 || !simd_allowed() ||
        !cpu_has_avx2())
        return none;
    BmfrTaaSpan span{1, 1, {}};
    if (space.map) {
        if (!same_mask_shape(space.valid, display) || !same_map_shape(*space.map, display) ||
            !same_map_shape(space.history_map(), display) ||
            (space.previous_valid && !same_mask_shape(space.previous_valid, display)) ||
            3.0 * display.width * display.height >= 2147483648.0)  // int32 gather indices
            return none;
        for (int c = 0; c < display.width; ++c)
            span.column_rows.push_back(vp_column_rows(*space.map, c));
    }
    // groups of eight while column x + 8 is on the image
    const int groups = std::max(display.width - 2, 0) / lanes;
    if (groups == 0) return none;
    span.end = 1 + groups * lanes;
    return span;
}

void bmfr_taa_row_avx(const BmfrParams& params, const Image& display, const Image& ycocg,
                      const Image& previous_pixel, const Image& history, const BmfrSpace& space,
                      const BmfrTaaSpan& span, Image& out, int y, std::int64_t& used) {
    for (int x = span.first; x < span.end; x += lanes)
        used += space.map ? vp_taa_group(params, display, ycocg, previous_pixel, history, space,
                                         span.column_rows.data(), out, x, y)
                          : taa_group(params, display, ycocg, previous_pixel, history, out, x, y);
}

}  // namespace fovref
