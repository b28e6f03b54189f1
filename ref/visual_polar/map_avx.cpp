#include "ref/visual_polar/map_avx.h"

#include <algorithm>
#include <vector>

#include "ref/core/avx_lanes.h"
#include "ref/core/dmath.h"
#include "ref/core/simd.h"

namespace fovref {

namespace {

using namespace avx;

// dm::atan2's binary64 constants: pi and pi / 2 rounded once (pi / 2 exactly half of pi)
constexpr double pi = dm::pi_d, half_pi = dm::pi_d / 2.0;
static_assert(pi == 0x1.921fb54442d18p+1 && half_pi == 0x1.921fb54442d18p+0);

/// dm::atan's core for t >= 0 in binary64, four lanes: t halved twice by t / (1 + sqrt(1 + t t)),
/// then 4 (t + t (z q)) with q the odd series' Horner sum in z = t t from -1/23 down to -1/3.
FOVREF_AVX2_INLINE __m256d atan_core(__m256d t) {
    const __m256d one = _mm256_set1_pd(1.0);
    for (int halving = 0; halving < 2; ++halving)
        t = _mm256_div_pd(
            t, _mm256_add_pd(one, _mm256_sqrt_pd(_mm256_add_pd(one, _mm256_mul_pd(t, t)))));
    const __m256d z = _mm256_mul_pd(t, t);
    constexpr double series[] = {1.0 / 21.0,  -1.0 / 19.0, 1.0 / 17.0, -1.0 / 15.0, 1.0 / 13.0,
                                 -1.0 / 11.0, 1.0 / 9.0,   -1.0 / 7.0, 1.0 / 5.0,   -1.0 / 3.0};
    __m256d q = _mm256_set1_pd(-1.0 / 23.0);
    for (const double c : series) q = _mm256_add_pd(_mm256_set1_pd(c), _mm256_mul_pd(z, q));
    return _mm256_mul_pd(_mm256_set1_pd(4.0),
                         _mm256_add_pd(t, _mm256_mul_pd(t, _mm256_mul_pd(z, q))));
}

/// dm::atan2(y, x) for y, x finite and nonzero (binary64 of binary32 values), four lanes: the
/// first quadrant's angle of |y|, |x| (atan of the smaller over the larger, pi/2 minus it when
/// |y| > |x|), pi minus it for x < 0, y's sign.
FOVREF_AVX2_INLINE __m256d atan2_nonzero(__m256d y, __m256d x) {
    const __m256d sign = _mm256_set1_pd(-0.0);
    const __m256d ay = _mm256_andnot_pd(sign, y), ax = _mm256_andnot_pd(sign, x);
    const __m256d steep = _mm256_cmp_pd(ay, ax, _CMP_GT_OQ);  // not ay <= ax
    const __m256d core =
        atan_core(_mm256_div_pd(_mm256_blendv_pd(ay, ax, steep), _mm256_blendv_pd(ax, ay, steep)));
    __m256d a = _mm256_blendv_pd(core, _mm256_sub_pd(_mm256_set1_pd(half_pi), core), steep);
    a = _mm256_blendv_pd(a, _mm256_sub_pd(_mm256_set1_pd(pi), a),
                         _mm256_cmp_pd(x, _mm256_setzero_pd(), _CMP_LT_OQ));
    return _mm256_or_pd(a, _mm256_and_pd(y, sign));
}

/// dm::atan2(dy, dx) rounded to binary32, eight lanes (dy, dx finite and nonzero).
FOVREF_AVX2_INLINE __m256 atan2_lanes(__m256 dy, __m256 dx) {
    const __m128 low = _mm256_cvtpd_ps(atan2_nonzero(_mm256_cvtps_pd(_mm256_castps256_ps128(dy)),
                                                     _mm256_cvtps_pd(_mm256_castps256_ps128(dx))));
    const __m128 high =
        _mm256_cvtpd_ps(atan2_nonzero(_mm256_cvtps_pd(_mm256_extractf128_ps(dy, 1)),
                                      _mm256_cvtps_pd(_mm256_extractf128_ps(dx, 1))));
    return _mm256_insertf128_ps(_mm256_castps128_ps256(low), high, 1);
}

/// vp_inverse_cdf, eight lanes: 18.64 sqrt(max(u, 0)) for u <= u0, else the quartic by Horner.
FOVREF_AVX2_INLINE __m256 inverse_cdf(__m256 u) {
    const __m256 root = _mm256_mul_ps(set(18.64f), _mm256_sqrt_ps(std_max(u, zero())));
    __m256 poly = _mm256_add_ps(_mm256_mul_ps(set(25.09f), u), set(0.1680f));
    poly = _mm256_add_ps(_mm256_mul_ps(poly, u), set(27.61f));
    poly = _mm256_add_ps(_mm256_mul_ps(poly, u), set(23.87f));
    poly = _mm256_add_ps(_mm256_mul_ps(poly, u), set(3.232f));
    return select(at_most(u, set(vp_u0)), root, poly);
}

/// The float after (step 1) or before (step -1) each positive finite float of u.
FOVREF_AVX2_INLINE __m256 next_float(__m256 u, int step) {
    return _mm256_castsi256_ps(_mm256_add_epi32(_mm256_castps_si256(u), _mm256_set1_epi32(step)));
}

/// vp_cdf(e) in the lanes of `active` (0 < e < P(1)), without its search: the largest float u
/// with P(u) < e (P non-decreasing over the floats of [0, 1]) taken from a window of six floats
/// around a guess g (the guess bucket's quadratic, vp_cdf_tables), else moved float by float
/// from the window's edge, then 0.5 (u + next float), which is vp_cdf's result where its bracket
/// starts above 0 (P(2^-16) < e). The guess decides only how soon the answer is found, never
/// which float it is. `settled`: the active lanes so found (the others are the caller's).
FOVREF_AVX2_INLINE __m256 cdf_lanes(__m256 e, __m256 active, __m256& settled) {
    const VpCdfTables tables = vp_cdf_tables();
    // vp_cdf's bracket starts above 0 (lo >= 1) where P(2^-16) < e
    const __m256 pending = both(active, less(set(tables.p[1]), e));
    // the guess bucket's quadratic (e_c, c0, c1, c2): one 16-byte load per lane (bucket 0
    // where not pending), transposed
    const __m256i b = _mm256_min_epi32(
        _mm256_cvttps_epi32(_mm256_mul_ps(select(pending, e, zero()), set(tables.guess_scale))),
        _mm256_set1_epi32(static_cast<int>(tables.guess.size() / 4) - 1));
    alignas(32) int at[lanes];
    _mm256_store_si256(reinterpret_cast<__m256i*>(at), _mm256_slli_epi32(b, 2));
    __m128 q[lanes];
    for (int l = 0; l < lanes; ++l) q[l] = _mm_loadu_ps(tables.guess.data() + at[l]);
    __m256 quadratic[4];  // e_c, c0, c1, c2
    transpose4_lanes(q, quadratic);
    const __m256 d = _mm256_sub_ps(e, quadratic[0]);
    const __m256 guess = _mm256_add_ps(
        quadratic[1],
        _mm256_mul_ps(d, _mm256_add_ps(quadratic[2], _mm256_mul_ps(d, quadratic[3]))));
    // g in [2^-16, two floats below 1]: the window's floats lie in (0, 1]
    const __m256 g = std_min(std_max(guess, set(0x1p-16f)), set(0x1.fffffcp-1f));
    const __m256i zero_i = _mm256_setzero_si256();
    // below = how many of the six floats g - 3 .. g + 2 have P < e; 1 to 5: the answer
    // g - 4 + below (P(g - 3) < e <= P(g - 3 + below))
    __m256i below = zero_i;
    for (int k = -3; k <= 2; ++k)
        below =
            _mm256_sub_epi32(below, _mm256_castps_si256(less(inverse_cdf(next_float(g, k)), e)));
    const __m256i inside = _mm256_andnot_si256(_mm256_cmpeq_epi32(below, zero_i),
                                               _mm256_cmpgt_epi32(_mm256_set1_epi32(6), below));
    __m256 u = _mm256_castsi256_ps(
        _mm256_add_epi32(_mm256_castps_si256(g), _mm256_sub_epi32(below, _mm256_set1_epi32(4))));
    settled = both(pending, _mm256_castsi256_ps(inside));
    __m256 result =
        select(settled, _mm256_mul_ps(set(0.5f), _mm256_add_ps(u, next_float(u, 1))), zero());
    // the few lanes whose answer lies outside the window: moved float by float from the window's
    // edge (g - 4 when P(g - 3) >= e, g + 2 when P(g + 2) < e), at most 8 moves
    __m256 outside = both(pending, negation(settled));
    if (bits(outside) == 0) return result;
    u = select(_mm256_castsi256_ps(_mm256_cmpeq_epi32(below, zero_i)), next_float(g, -4),
               next_float(g, 2));
    for (int move = 0; move < 8 && bits(outside) != 0; ++move) {
        const __m256 under = less(inverse_cdf(u), e);
        const __m256 next = next_float(u, 1);
        const __m256 next_under = less(inverse_cdf(next), e);
        const __m256 down = both(outside, negation(under));
        const __m256 up = both(both(outside, under), next_under);
        const __m256 done = both(both(outside, under), negation(next_under));
        result = select(done, _mm256_mul_ps(set(0.5f), _mm256_add_ps(u, next)), result);
        u = select(down, next_float(u, -1), select(up, next, u));
        settled = either(settled, done);
        outside = both(outside, negation(done));
    }
    return result;
}

/// vp_polar in lanes: r and theta of the lanes of `lane_bits` whose angle the lanes compute (dx,
/// dy nonzero and r finite) stored into r_out, theta_out; returns those lanes.
__attribute__((target("avx2"))) int angle_group(const VisualPolarMap& m, const float* x,
                                                const float* y, int lane_bits, float* r_out,
                                                float* theta_out) {
    const __m256 dx = _mm256_sub_ps(_mm256_loadu_ps(x), set(m.gaze.x));
    const __m256 dy = _mm256_sub_ps(_mm256_loadu_ps(y), set(m.gaze.y));
    const __m256 r = _mm256_sqrt_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)));
    // the lanes whose angle atan2_nonzero computes, and whose distance is finite
    const __m256 nonzero =
        both(_mm256_cmp_ps(dx, zero(), _CMP_NEQ_OQ), _mm256_cmp_ps(dy, zero(), _CMP_NEQ_OQ));
    const __m256 settled = both(mask_of(lane_bits), both(nonzero, finite(r)));
    // theta in [0, 2 pi]; dx, dy of the other lanes replaced by 1 (a harmless angle)
    __m256 theta = atan2_lanes(select(settled, dy, set(1.0f)), select(settled, dx, set(1.0f)));
    theta = select(less(theta, zero()), _mm256_add_ps(theta, set(dm::two_pi)), theta);
    const __m256i store = _mm256_castps_si256(settled);
    _mm256_maskstore_ps(r_out, store, r);
    _mm256_maskstore_ps(theta_out, store, theta);
    return bits(settled);
}

/// vp_forward_radius in lanes of the distances r[l] of the lanes `settled_bits` (angle_group's):
/// u_out of the lanes it settles, which it returns (the others run the reference).
__attribute__((target("avx2"))) int radius_group(const VisualPolarMap& m, const float* r_in,
                                                 int settled_bits, float* u_out) {
    __m256 settled = mask_of(settled_bits);
    const __m256 r = _mm256_maskload_ps(r_in, _mm256_castps_si256(settled));
    // vp_forward_radius: the fovea's linear part, else P^-1(r / s) mapped to rho
    const __m256 fovea = less(r, set(m.fovea_radius));
    const __m256 linear = _mm256_div_ps(_mm256_mul_ps(set(static_cast<float>(m.fovea_columns)), r),
                                        set(m.fovea_radius));
    const __m256 e = _mm256_div_ps(r, set(m.scale));
    const __m256 positive = greater(e, zero()), saturated = at_least(e, set(vp_inverse_cdf(1.0f)));
    const __m256 searched =
        both(both(settled, negation(fovea)), both(positive, negation(saturated)));
    __m256 found;
    const __m256 cdf = cdf_lanes(e, searched, found);
    settled = both(settled, either(negation(searched), found));
    const __m256 big_u = select(positive, select(saturated, set(1.0f), cdf), zero());
    const float rho_f = static_cast<float>(m.fovea_columns) / static_cast<float>(m.width);
    const __m256 rho = _mm256_add_ps(
        set(rho_f),
        _mm256_div_ps(_mm256_mul_ps(_mm256_sub_ps(big_u, set(vp_u0)), set(1.0f - rho_f)),
                      set(1.0f - vp_u0)));
    const __m256 u = select(fovea, linear, _mm256_mul_ps(set(static_cast<float>(m.width)), rho));
    _mm256_maskstore_ps(u_out, _mm256_castps_si256(settled), u);
    return bits(settled);
}

/// The lanes of `lane_bits` not in `settled`: vp_polar and vp_forward_radius themselves.
void polar_reference(const VisualPolarMap& map, const float* x, const float* y, int lane_bits,
                     int settled, float* u, float* r, float* theta) {
    for (int l = 0; l < lanes; ++l) {
        if (!(lane_bits >> l & 1) || (settled >> l & 1)) continue;
        vp_polar(map, {x[l], y[l]}, r[l], theta[l]);
        u[l] = vp_forward_radius(map, r[l]);
    }
}

}  // namespace

int vp_polar_lanes(const VisualPolarMap& map, const float* x, const float* y, int lane_bits,
                   float* u, float* r, float* theta) {
    int settled = 0;
    if (lane_bits != 0 && simd_allowed() && cpu_has_avx2())
        settled = radius_group(map, r, angle_group(map, x, y, lane_bits, r, theta), u);
    polar_reference(map, x, y, lane_bits, settled, u, r, theta);
    return settled;
}

void vp_polar_span(const VisualPolarMap& map, const float* x, const float* y, std::size_t count,
                   float* u, float* r, float* theta) {
    const std::size_t groups = count / lanes;
    std::vector<unsigned char> settled(groups, 0);
    if (simd_allowed() && cpu_has_avx2()) {
        // every group's angle first: no search branch between their binary64 divisions
        for (std::size_t g = 0; g < groups; ++g)
            settled[g] = static_cast<unsigned char>(angle_group(
                map, x + g * lanes, y + g * lanes, 255, r + g * lanes, theta + g * lanes));
        for (std::size_t g = 0; g < groups; ++g)
            settled[g] = static_cast<unsigned char>(
                radius_group(map, r + g * lanes, settled[g], u + g * lanes));
    }
    for (std::size_t g = 0; g < groups; ++g)
        polar_reference(map, x + g * lanes, y + g * lanes, 255, settled[g], u + g * lanes,
                        r + g * lanes, theta + g * lanes);
    // the last points (fewer than eight) eight lanes at a time from copies
    const std::size_t done = groups * lanes;
    if (done == count) return;
    float tx[lanes] = {}, ty[lanes] = {}, tu[lanes], tr[lanes], tt[lanes];
    const auto rest = static_cast<int>(count - done);
    std::copy(x + done, x + count, tx);
    std::copy(y + done, y + count, ty);
    vp_polar_lanes(map, tx, ty, (1 << rest) - 1, tu, tr, tt);
    std::copy(tu, tu + rest, u + done);
    std::copy(tr, tr + rest, r + done);
    std::copy(tt, tt + rest, theta + done);
}

int vp_forward_angle_lanes(const VisualPolarMap& map, const float* x, const float* y, int lane_bits,
                           float* u, float* t) {
    if (map.log_polar) {  // log-polar's own forward map
        for (int l = 0; l < lanes; ++l) {
            if (!(lane_bits >> l & 1)) continue;
            const glm::vec2 ut = vp_forward_angle(map, {x[l], y[l]});
            u[l] = ut.x, t[l] = ut.y;
        }
        return 0;
    }
    // vp_forward_angle: vp_polar's angle as a fraction of the turn
    float r[lanes], theta[lanes];
    const int settled = vp_polar_lanes(map, x, y, lane_bits, u, r, theta);
    for (int l = 0; l < lanes; ++l)
        if (lane_bits >> l & 1) t[l] = theta[l] / dm::two_pi;
    return settled;
}

}  // namespace fovref
