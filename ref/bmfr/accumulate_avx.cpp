#include "ref/bmfr/accumulate_avx.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "ref/bmfr/vp_taps_avx.h"
#include "ref/core/avx_lanes.h"
#include "ref/core/simd.h"
#include "ref/visual_polar/map_avx.h"

namespace fovref {

namespace {

using namespace avx;

/// finite_or_zero of accumulate.cpp per lane, counting the replaced values (of every lane, or
/// of the `counted` lanes: those the reference reads).
FOVREF_AVX_INLINE __m256 finite_or_zero(const float* v, BmfrStats& stats) {
    const __m256 value = _mm256_load_ps(v);
    const __m256 ok = finite(value);
    stats.nonfinite_inputs += lanes - count(ok);
    return select(ok, value, zero());
}
FOVREF_AVX_INLINE __m256 finite_or_zero(const float* v, __m256 counted, BmfrStats& stats) {
    const __m256 value = _mm256_load_ps(v);
    const __m256 ok = finite(value);
    stats.nonfinite_inputs += count(both(counted, negation(ok)));
    return select(ok, value, zero());
}

/// distance_squared of accumulate.cpp: d = a - b, then (d.x d.x + d.y d.y) + d.z d.z.
FOVREF_AVX_INLINE __m256 distance_squared(const float (*a)[lanes], const __m256* b) {
    __m256 d[3];
    for (int c = 0; c < 3; ++c) d[c] = _mm256_sub_ps(_mm256_load_ps(a[c]), b[c]);
    return _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(d[0], d[0]), _mm256_mul_ps(d[1], d[1])),
                         _mm256_mul_ps(d[2], d[2]));
}

/// ((m0 p.x + m1 p.y) + m2 p.z) + m3: one row of bmfr_project's product.
FOVREF_AVX_INLINE __m256 row(const float* m, const __m256* p) {
    return _mm256_add_ps(
        _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(set(m[0]), p[0]), _mm256_mul_ps(set(m[1]), p[1])),
                      _mm256_mul_ps(set(m[2]), p[2])),
        set(m[3]));
}

/// A tap's history values, lane by lane: world position, normal, accumulated colour, spp.
struct Taps {
    alignas(32) float position[4][3][lanes];
    alignas(32) float normal[4][3][lanes];
    alignas(32) float color[4][3][lanes];
    alignas(32) float spp[4][lanes];
};

/// bmfr_project with the previous camera: the reprojected index q = (qx, qy), and the lanes that
/// have one (in front of the camera, or behind with project_behind_camera, and finite).
FOVREF_AVX_INLINE __m256 project_lanes(const BmfrParams& params, const ViewProjection& vp,
                                       const __m256* p, float wf, float hf, glm::vec2 offset,
                                       __m256& qx, __m256& qy) {
    const float* m = vp.m.data();
    const __m256 cx = row(m, p), cy = row(m + 4, p), cw = row(m + 12, p);
    const __m256 w_ok = params.project_behind_camera ? not_equal(cw, zero()) : greater(cw, zero());
    qx = _mm256_sub_ps(
        _mm256_mul_ps(_mm256_mul_ps(_mm256_add_ps(_mm256_div_ps(cx, cw), set(1.0f)), set(0.5f)),
                      set(wf)),
        set(offset.x));
    qy = _mm256_sub_ps(
        _mm256_mul_ps(_mm256_mul_ps(_mm256_sub_ps(set(1.0f), _mm256_div_ps(cy, cw)), set(0.5f)),
                      set(hf)),
        set(offset.y));
    return both(w_ok, both(finite(qx), finite(qy)));
}

/// The four taps of eight pixels: tap k of lane l is history pixel index(k, l), read where on[k]
/// is set (the reference's tap k that it reads), with weight weight[k]. Screen space: the
/// bilinear corners' taps (ScreenTaps); Visual-Polar space: each lane's own list (ListedTaps,
/// vp_taps_avx.h).
struct ScreenTaps {
    __m256 on[4], weight[4];
    const BilinearLanes* b = nullptr;
    std::size_t width = 0;
    std::size_t index(int k, int l) const { return b->pixel(k, l, width); }
};

/// The history at the taps that are on (+0 elsewhere), every value of `t` written whole
/// (load3_pixels), so that accept_lanes' loads of whole registers take them from those stores.
template <class GroupTaps>
FOVREF_AVX_INLINE void gather_taps(const BmfrHistory& history, const GroupTaps& g, Taps& t) {
    const std::size_t pixels = history.spp.data.size();
    for (int k = 0; k < 4; ++k) {
        std::size_t at[lanes];
        tap_pixels(
            g.on[k], k, [&](int tap, int l) { return g.index(tap, l); }, at);
        load3_pixels(history.world_position.data.data(), pixels, at, g.on[k], t.position[k]);
        load3_pixels(history.normal.data.data(), pixels, at, g.on[k], t.normal[k]);
        load3_pixels(history.accumulated_noisy.data.data(), pixels, at, g.on[k], t.color[k]);
        const float* spp = history.spp.data.data();
        _mm256_store_ps(t.spp[k],
                        select(g.on[k],
                               _mm256_setr_ps(spp[at[0]], spp[at[1]], spp[at[2]], spp[at[3]],
                                              spp[at[4]], spp[at[5]], spp[at[6]], spp[at[7]]),
                               zero()));
    }
}

/// accepted_taps: the position test, then the normal test, each tap's bit in `accepted`, and
/// their margins (margin[0], margin[1], from bmfr_no_margin).
FOVREF_AVX_INLINE void accept_lanes(const BmfrParams& params, const Taps& t, const __m256* on,
                                    const __m256* p, const __m256* n, __m256* accepted,
                                    __m256* margin) {
    const __m256 position_limit = set(params.position_limit_squared);
    const __m256 normal_limit = set(params.normal_limit_squared);
    for (int k = 0; k < 4; ++k) {
        const __m256 dp = distance_squared(t.position[k], p);
        margin[0] = select(on[k],
                           std_min(margin[0], _mm256_div_ps(abs(_mm256_sub_ps(position_limit, dp)),
                                                            position_limit)),
                           margin[0]);
        const __m256 near = both(on[k], less(dp, position_limit));
        const __m256 dn = distance_squared(t.normal[k], n);
        margin[1] = select(
            near,
            std_min(margin[1], _mm256_div_ps(abs(_mm256_sub_ps(normal_limit, dn)), normal_limit)),
            margin[1]);
        accepted[k] = both(near, less(dn, normal_limit));
    }
}

/// round_half_even of accumulate.cpp: floor, up above 1/2 or at 1/2 from an odd whole number
/// (fmod(r, 2) != 0 for a whole r, as r - 2 floor(r / 2) != 0; d = 1/2 only for |r| < 2^23).
FOVREF_AVX_INLINE __m256 round_half_even(__m256 v) {
    const __m256 r = floor(v);
    const __m256 d = _mm256_sub_ps(v, r);
    const __m256 odd = not_equal(
        _mm256_sub_ps(r, _mm256_mul_ps(set(2.0f), floor(_mm256_mul_ps(r, set(0.5f))))), zero());
    const __m256 up = either(greater(d, set(0.5f)), both(equal(d, set(0.5f)), odd));
    return select(up, _mm256_add_ps(r, set(1.0f)), r);
}

/// Phase I's values of eight pixels, one array per channel, as they are written.
struct PhaseOne {
    alignas(32) float accumulated[3][lanes], spp[lanes], accept[lanes], previous[2][lanes],
        margin[3][lanes];
};

/// Writes `v` to pixels x .. x + 7 of `out`'s buffers (accept_margin when allocated).
FOVREF_AVX_INLINE void write_lanes(const PhaseOne& v, BmfrAccumulation& out, int x, int y) {
    store3_lanes(v.accumulated, &out.accumulated.data[out.accumulated.index(x, y)]);
    float* o_spp = &out.spp.data[out.spp.index(x, y)];
    float* o_accept = &out.accept.data[out.accept.index(x, y)];
    float* o_previous = &out.previous_pixel.data[out.previous_pixel.index(x, y)];
    for (int l = 0; l < lanes; ++l) {
        o_spp[l] = v.spp[l];
        o_accept[l] = v.accept[l];
        o_previous[2 * l] = v.previous[0][l];
        o_previous[2 * l + 1] = v.previous[1][l];
    }
    if (!out.accept_margin.data.empty())
        store3_lanes(v.margin, &out.accept_margin.data[out.accept_margin.index(x, y)]);
}

/// Phase I from the taps on: the position and normal tests (accept_lanes), the blend of the
/// accepted taps, alpha, the sample count, written to `out` with q (qx, qy) where `reprojected`
/// (bmfr_behind_camera elsewhere) and the margins (margin[2]: `margin2`).
template <class GroupTaps>
FOVREF_AVX_INLINE void finish_group(const BmfrParams& params, const BmfrHistory& history,
                                    const float (*c)[lanes], const __m256* p, const __m256* n,
                                    __m256 reprojected, __m256 qx, __m256 qy, __m256 margin2,
                                    const GroupTaps& g, BmfrAccumulation& out, int x, int y,
                                    BmfrStats& stats) {
    Taps t;  // (every value written by gather_taps)
    gather_taps(history, g, t);
    const __m256 no_margin = set(bmfr_no_margin);
    __m256 margin[3] = {no_margin, no_margin, margin2};
    __m256 accepted[4];
    accept_lanes(params, t, g.on, p, n, accepted, margin);

    // blend_noisy_history over the accepted taps, in tap order.
    __m256 h[3] = {zero(), zero(), zero()}, h_spp = zero(), total = zero(), mask = zero();
    for (int k = 0; k < 4; ++k) {
        const __m256 w = g.weight[k];
        for (int ch = 0; ch < 3; ++ch)
            h[ch] = _mm256_add_ps(
                h[ch],
                select(accepted[k], _mm256_mul_ps(w, _mm256_load_ps(t.color[k][ch])), zero()));
        h_spp = _mm256_add_ps(
            h_spp, select(accepted[k], _mm256_mul_ps(w, _mm256_load_ps(t.spp[k])), zero()));
        total = _mm256_add_ps(total, select(accepted[k], w, zero()));
        mask = _mm256_add_ps(mask, select(accepted[k], set(static_cast<float>(1 << k)), zero()));
    }
    const __m256 has_history = both(reprojected, greater(total, zero()));
    stats.history_accepted += count(has_history);
    stats.history_rejected += count(reprojected) - count(has_history);
    for (int ch = 0; ch < 3; ++ch) h[ch] = _mm256_div_ps(h[ch], total);
    h_spp = _mm256_div_ps(h_spp, total);

    // alpha, the blend, the sample count.
    const __m256 alpha = std_max(_mm256_div_ps(set(1.0f), _mm256_add_ps(h_spp, set(1.0f))),
                                 set(params.noisy_alpha_min));
    const __m256 beta = _mm256_sub_ps(set(1.0f), alpha);
    PhaseOne v;
    for (int ch = 0; ch < 3; ++ch) {
        const __m256 current = _mm256_load_ps(c[ch]);
        _mm256_store_ps(v.accumulated[ch], select(has_history,
                                                  _mm256_add_ps(_mm256_mul_ps(alpha, current),
                                                                _mm256_mul_ps(beta, h[ch])),
                                                  current));
    }
    _mm256_store_ps(
        v.spp,
        select(has_history, std_min(_mm256_add_ps(round_half_even(h_spp), set(1.0f)), set(255.0f)),
               set(1.0f)));
    _mm256_store_ps(v.accept, select(has_history, mask, zero()));
    _mm256_store_ps(v.previous[0], select(reprojected, qx, set(bmfr_behind_camera.x)));
    _mm256_store_ps(v.previous[1], select(reprojected, qy, set(bmfr_behind_camera.y)));
    for (int k = 0; k < 3; ++k) _mm256_store_ps(v.margin[k], margin[k]);
    write_lanes(v, out, x, y);
}

/// The illumination, world position and normal of pixels x .. x + 7 (the latter two through
/// finite_or_zero, counted in every lane, or with `counted` in those lanes only).
FOVREF_AVX_INLINE void load_group(const Image& illumination, const Image& world_position,
                                  const Image& normal, int x, int y, const __m256* counted,
                                  float (*c)[lanes], __m256* p, __m256* n, BmfrStats& stats) {
    alignas(32) float pa[3][lanes], na[3][lanes];
    load3_lanes(&illumination.data[illumination.index(x, y)], c);
    load3_lanes(&world_position.data[world_position.index(x, y)], pa);
    load3_lanes(&normal.data[normal.index(x, y)], na);
    for (int k = 0; k < 3; ++k)
        p[k] = counted ? finite_or_zero(pa[k], *counted, stats) : finite_or_zero(pa[k], stats);
    for (int k = 0; k < 3; ++k)
        n[k] = counted ? finite_or_zero(na[k], *counted, stats) : finite_or_zero(na[k], stats);
}

// Phase I in screen space for pixels x .. x + 7: bmfr_project, bmfr_taps, then finish_group.
__attribute__((target("avx"))) void accumulate_group(
    const BmfrParams& params, const Image& illumination, const Image& world_position,
    const Image& normal, const BmfrHistory& history, BmfrAccumulation& out, int x, int y,
    BmfrStats& stats) {
    const int width = illumination.width, height = illumination.height;
    const float wf = static_cast<float>(width), hf = static_cast<float>(height);
    alignas(32) float c[3][lanes];
    __m256 p[3], n[3];
    load_group(illumination, world_position, normal, x, y, nullptr, c, p, n, stats);

    __m256 qx, qy;
    const __m256 reprojected =
        project_lanes(params, history.view_projection, p, wf, hf, params.pixel_offset, qx, qy);
    stats.history_off_screen += lanes - count(reprojected);

    // bmfr_taps (q finite where reprojected; elsewhere a point whose taps are never read).
    const __m256 tx = select(reprojected, std_min(std_max(qx, set(-1e6f)), set(1e6f)), set(-1e6f));
    const __m256 ty = select(reprojected, std_min(std_max(qy, set(-1e6f)), set(1e6f)), set(-1e6f));
    BilinearLanes b;
    bilinear_lanes(tx, ty, floor(tx), floor(ty), reprojected, wf, hf, b);
    ScreenTaps g;
    for (int k = 0; k < 4; ++k) {
        g.on[k] = b.on[k];
        g.weight[k] = b.weight[k];
    }
    g.b = &b;
    g.width = static_cast<std::size_t>(width);
    // The reprojected index's distance from the nearest integer.
    const __m256 margin2 =
        select(reprojected,
               std_min(std_min(std_min(_mm256_sub_ps(qx, floor(qx)), _mm256_sub_ps(ceil(qx), qx)),
                               _mm256_sub_ps(qy, floor(qy))),
                       _mm256_sub_ps(ceil(qy), qy)),
               set(bmfr_no_margin));
    finish_group(params, history, c, p, n, reprojected, qx, qy, margin2, g, out, x, y, stats);
}

// Phase I in Visual-Polar space for texels x .. x + 7 of row y: the lanes without data (an
// untraced texel) read nothing; the others are projected into the previous frame's screen in
// lanes, then each lane's q = vp_forward_angle(previous map, s + 1/2) - (1/2, 0) and its taps
// (bmfr_vp_taps: a tap is on inside the buffer on a texel traced in the previous frame) come
// from the reference's own functions; then finish_group.
__attribute__((target("avx"))) void vp_accumulate_group(
    const BmfrParams& params, const Image& illumination, const Image& world_position,
    const Image& normal, const BmfrHistory& history, const BmfrSpace& space, BmfrAccumulation& out,
    int x, int y, BmfrStats& stats) {
    const int width = illumination.width, height = illumination.height;
    const VisualPolarMap& previous = *history.map;
    // data: valid != 0 (NaN counts, as the reference's != does)
    const __m256 data =
        not_equal(_mm256_loadu_ps(&space.valid->data[space.valid->index(x, y)]), zero());
    if (bits(data) == 0) {  // no texel with data: finish_group's values without history
        PhaseOne v;
        load3_lanes(&illumination.data[illumination.index(x, y)], v.accumulated);
        for (int l = 0; l < lanes; ++l) {
            v.spp[l] = 1.0f, v.accept[l] = 0.0f;
            v.previous[0][l] = bmfr_behind_camera.x, v.previous[1][l] = bmfr_behind_camera.y;
            for (int k = 0; k < 3; ++k) v.margin[k][l] = bmfr_no_margin;
        }
        write_lanes(v, out, x, y);
        return;
    }
    alignas(32) float c[3][lanes];
    __m256 p[3], n[3];
    load_group(illumination, world_position, normal, x, y, &data, c, p, n, stats);

    __m256 sx, sy;
    const __m256 projected = both(
        data,
        project_lanes(params, history.view_projection, p, static_cast<float>(previous.screen_width),
                      static_cast<float>(previous.screen_height), glm::vec2(0.5f), sx, sy));
    alignas(32) float point[2][lanes], q[2][lanes] = {}, reprojected_lanes[lanes] = {};
    _mm256_store_ps(point[0], _mm256_add_ps(sx, set(0.5f)));
    _mm256_store_ps(point[1], _mm256_add_ps(sy, set(0.5f)));
    const int projected_bits = bits(projected);
    alignas(32) float ut[2][lanes];
    vp_forward_angle_lanes(previous, point[0], point[1], projected_bits, ut[0], ut[1]);
    for (int l = 0; l < lanes; ++l) {
        if (!(projected_bits >> l & 1)) continue;
        const glm::vec2 ql{ut[0][l] - 0.5f, ut[1][l]};
        if (!(std::isfinite(ql.x) && std::isfinite(ql.y))) continue;
        reprojected_lanes[l] = std::bit_cast<float>(-1);
        q[0][l] = ql.x;
        q[1][l] = ql.y;
    }
    const __m256 reprojected = _mm256_load_ps(reprojected_lanes);
    stats.history_off_screen += count(data) - count(reprojected);
    const __m256 qx = _mm256_load_ps(q[0]), qy = _mm256_load_ps(q[1]);
    // The taps (bmfr_vp_taps) on texels traced in the previous frame: in lanes, or listed
    LaneTaps lane_taps;
    if (vp_tap_lanes(previous, qx, qy, reprojected, width, height, lane_taps)) {
        mask_taps(lane_taps, history.valid_texels);
        finish_group(params, history, c, p, n, reprojected, qx, qy, set(bmfr_no_margin), lane_taps,
                     out, x, y, stats);
        return;
    }
    ListedTaps g;
    const int reprojected_bits = bits(reprojected);
    for (int l = 0; l < lanes; ++l) {
        if (!(reprojected_bits >> l & 1)) continue;
        const BmfrTaps taps = bmfr_vp_taps(previous, {q[0][l], q[1][l]});
        set_lane_taps(g, l, taps, width, height,
                      [&](int k) { return history.valid_texels.at(taps.x[k], taps.y[k]) != 0.0f; });
    }
    load_listed(g);
    finish_group(params, history, c, p, n, reprojected, qx, qy, set(bmfr_no_margin), g, out, x, y,
                 stats);
}

/// Phase I's accepted-tap bits of pixels x .. x + 7 (0 .. 15; anything else: none).
FOVREF_AVX_INLINE void accepted_bits_of(const Image& accept, int x, int y, unsigned* mask) {
    const float* bits_in = &accept.data[accept.index(x, y)];
    for (int l = 0; l < lanes; ++l) {
        const float value = bits_in[l];
        mask[l] = value >= 0.0f && value < 16.0f ? static_cast<unsigned>(value) : 0u;
    }
}

/// Phase III's blend for pixels x .. x + 7 from the taps used (GroupTaps: on = accepted by phase
/// I and inside the image): the sums in tap order, renormalised, then alpha = max(1 / spp, min).
template <class GroupTaps>
FOVREF_AVX_INLINE void finish_filtered(const BmfrParams& params, const Image& fitted,
                                       const Image& spp, const Image& history, const GroupTaps& g,
                                       Image& out, int x, int y) {
    alignas(32) float c[3][lanes];
    load3_lanes(&fitted.data[fitted.index(x, y)], c);
    alignas(32) float taps[4][3][lanes];
    load3_taps(
        history.data.data(), history.data.size() / 3, g.on,
        [&](int k, int l) { return g.index(k, l); }, taps);
    // blend_accepted: the sums in tap order, renormalised.
    __m256 h[3];
    const __m256 total = tap_sums3(g.on, g.weight, taps, h);
    const __m256 blended = greater(total, zero());
    const __m256 alpha =
        std_max(_mm256_div_ps(set(1.0f), _mm256_loadu_ps(&spp.data[spp.index(x, y)])),
                set(params.filtered_alpha_min));
    const __m256 beta = _mm256_sub_ps(set(1.0f), alpha);
    alignas(32) float o[3][lanes];
    for (int ch = 0; ch < 3; ++ch) {
        const __m256 current = _mm256_load_ps(c[ch]);
        _mm256_store_ps(o[ch],
                        select(blended,
                               _mm256_add_ps(_mm256_mul_ps(alpha, current),
                                             _mm256_mul_ps(beta, _mm256_div_ps(h[ch], total))),
                               current));
    }
    store3_lanes(o, &out.data[out.index(x, y)]);
}

// Phase III (bmfr_accumulate_filtered_pixel) in screen space for pixels x .. x + 7: the history
// blended over the taps phase I accepted that lie inside the image (bmfr_taps of q).
__attribute__((target("avx"))) void filtered_group(const BmfrParams& params, const Image& fitted,
                                                   const Image& spp, const Image& accept,
                                                   const Image& previous_pixel,
                                                   const Image& history, Image& out, int x, int y) {
    const int width = fitted.width, height = fitted.height;
    const float wf = static_cast<float>(width), hf = static_cast<float>(height);
    alignas(32) float q[2][lanes];
    load2_lanes(&previous_pixel.data[previous_pixel.index(x, y)], q);
    // The accepted-tap bits as all-ones lanes per tap.
    unsigned mask[lanes];
    accepted_bits_of(accept, x, y, mask);
    alignas(32) std::int32_t accepted_bits[4][lanes];
    for (int l = 0; l < lanes; ++l)
        for (int k = 0; k < 4; ++k) accepted_bits[k][l] = (mask[l] >> k & 1u) ? -1 : 0;
    // bmfr_taps(q): a non-finite coordinate goes far off, a finite one is clamped to +-1e6.
    __m256 tap_x0, tap_y0;
    {
        const __m256 qx = _mm256_load_ps(q[0]), qy = _mm256_load_ps(q[1]);
        tap_x0 = select(finite(qx), std_min(std_max(qx, set(-1e6f)), set(1e6f)), set(-1e6f));
        tap_y0 = select(finite(qy), std_min(std_max(qy, set(-1e6f)), set(1e6f)), set(-1e6f));
    }
    BilinearLanes b;
    const __m256 all = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
    bilinear_lanes(tap_x0, tap_y0, floor(tap_x0), floor(tap_y0), all, wf, hf, b);
    ScreenTaps g;
    for (int k = 0; k < 4; ++k) {
        g.on[k] = both(b.on[k], _mm256_load_ps(reinterpret_cast<const float*>(accepted_bits[k])));
        g.weight[k] = b.weight[k];
    }
    g.b = &b;
    g.width = static_cast<std::size_t>(width);
    finish_filtered(params, fitted, spp, history, g, out, x, y);
}

// Phase III in Visual-Polar space for texels x .. x + 7: each lane with accepted taps takes its
// taps from bmfr_vp_taps (the history's map) of its stored q, a tap used where phase I accepted
// it and it lies inside the buffer; then finish_filtered.
__attribute__((target("avx"))) void vp_filtered_group(const BmfrParams& params, const Image& fitted,
                                                      const Image& spp, const Image& accept,
                                                      const Image& previous_pixel,
                                                      const Image& history, const BmfrSpace& space,
                                                      Image& out, int x, int y) {
    const int width = fitted.width, height = fitted.height;
    unsigned mask[lanes];
    accepted_bits_of(accept, x, y, mask);
    if (std::all_of(mask, mask + lanes, [](unsigned m) { return m == 0u; })) {
        // no accepted tap: finish_filtered keeps every lane's fitted colour
        std::copy_n(&fitted.data[fitted.index(x, y)], 3 * lanes, &out.data[out.index(x, y)]);
        return;
    }
    alignas(32) float q[2][lanes], wanted_lanes[lanes] = {}, accepted_lanes[4][lanes] = {};
    load2_lanes(&previous_pixel.data[previous_pixel.index(x, y)], q);
    for (int l = 0; l < lanes; ++l) {
        if (mask[l] != 0) wanted_lanes[l] = std::bit_cast<float>(-1);
        for (int k = 0; k < 4; ++k)
            if (mask[l] >> k & 1u) accepted_lanes[k][l] = std::bit_cast<float>(-1);
    }
    // The taps (bmfr_vp_taps of the history's map) that phase I accepted: in lanes, or listed
    LaneTaps lane_taps;
    if (vp_tap_lanes(space.history_map(), _mm256_load_ps(q[0]), _mm256_load_ps(q[1]),
                     _mm256_load_ps(wanted_lanes), width, height, lane_taps)) {
        for (int k = 0; k < 4; ++k)
            lane_taps.on[k] = both(lane_taps.on[k], _mm256_load_ps(accepted_lanes[k]));
        finish_filtered(params, fitted, spp, history, lane_taps, out, x, y);
        return;
    }
    ListedTaps g;
    for (int l = 0; l < lanes; ++l) {
        if (mask[l] == 0) continue;
        set_lane_taps(g, l, bmfr_vp_taps(space.history_map(), {q[0][l], q[1][l]}), width, height,
                      [&](int k) { return (mask[l] >> k & 1u) != 0; });
    }
    load_listed(g);
    finish_filtered(params, fitted, spp, history, g, out, x, y);
}

}  // namespace

bool bmfr_accumulate_noisy_avx_applies(bool has_previous, const BmfrSpace& space,
                                       const Image& illumination) {
    // The lanes read a 3-channel illumination directly (the other buffers' shapes are checked:
    // bmfr_accumulate_noisy), and in Visual-Polar space a one-channel mask of its size.
    const bool mask = !space.map || (space.valid && space.valid->channels == 1 &&
                                     space.valid->width == illumination.width &&
                                     space.valid->height == illumination.height);
    return has_previous && mask && illumination.channels == 3 && simd_allowed() && cpu_has_avx();
}

int bmfr_accumulate_noisy_row_avx(const BmfrParams& params, const Image& illumination,
                                  const Image& world_position, const Image& normal,
                                  const BmfrHistory& history, const BmfrSpace& space,
                                  BmfrAccumulation& out, int y, BmfrStats& stats) {
    const int groups = illumination.width / lanes;
    for (int group = 0; group < groups; ++group) {
        if (space.map)
            vp_accumulate_group(params, illumination, world_position, normal, history, space, out,
                                group * lanes, y, stats);
        else
            accumulate_group(params, illumination, world_position, normal, history, out,
                             group * lanes, y, stats);
    }
    return groups * lanes;
}

}  // namespace fovref

namespace fovref {

bool bmfr_accumulate_filtered_avx_applies(const Image& history, const Image& fitted) {
    // either space (the history's shape is checked: bmfr_accumulate_filtered)
    return !history.empty() && fitted.channels == 3 && simd_allowed() && cpu_has_avx();
}

int bmfr_accumulate_filtered_row_avx(const BmfrParams& params, const Image& fitted,
                                     const Image& spp, const Image& accept,
                                     const Image& previous_pixel, const Image& history,
                                     const BmfrSpace& space, Image& out, int y) {
    const int groups = fitted.width / lanes;
    for (int group = 0; group < groups; ++group) {
        if (space.map)
            vp_filtered_group(params, fitted, spp, accept, previous_pixel, history, space, out,
                              group * lanes, y);
        else
            filtered_group(params, fitted, spp, accept, previous_pixel, history, out, group * lanes,
                           y);
    }
    return groups * lanes;
}

}  // namespace fovref
