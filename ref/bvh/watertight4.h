// The watertight ray-triangle test of watertight.h on four triangles at once (SSE, baseline
// x86-64), for the BVH's leaf blocks (BvhTriangleBlock: corners stored per axis, one triangle per
// lane). Every lane performs exactly the operations of intersect_watertight, in the same order:
// SSE add, subtract, multiply, divide and compare are the IEEE binary32 operations of the scalar
// code, lane by lane (no FMA: fovref compiles with -ffp-contract=off, and SSE2 has none), and
// the binary64 recomputation of a zero edge function is done lane by lane with the scalar
// watertight_edge_fallback. So a lane accepts exactly when intersect_watertight would, with the
// same t, u, v bits; the leaf code then reduces the lanes with the SPEC §3 tie-break.
#pragma once

#include "ref/bvh/watertight.h"

// SSE (baseline x86-64) when available; FOVREF_BVH_SCALAR forces the plain per-lane path of
// bvh_traverse.cpp, which computes the same values with intersect_watertight (the tests can run
// either). The shadow-ray packets (bvh_packets.cpp) use AVX either way, where the CPU has it;
// their answers are trace_any's on both paths.
#if (defined(__SSE2__) || defined(_M_X64)) && !defined(FOVREF_BVH_SCALAR)
#define FOVREF_BVH_SSE 1
#include <xmmintrin.h>
#endif

namespace fovref {

/// t, u, v of four lanes (valid in the lanes whose bit the test returns).
struct Hits4 {
    alignas(16) float t[4];
    alignas(16) float u[4];
    alignas(16) float v[4];
};

#if FOVREF_BVH_SSE

/// The per-ray constants of WatertightRay broadcast to four lanes. The sheared axes are chosen
/// per ray, so they become offsets (in floats) into a block's [corner][axis][lane] array.
struct WatertightRay4 {
    __m128 origin_x, origin_y, origin_z;  ///< origin[kx], origin[ky], origin[kz]
    __m128 shear_x, shear_y, shear_z;
    __m128 t_min, t_max;
    int offset_x, offset_y, offset_z;  ///< 4 * kx, 4 * ky, 4 * kz
};

inline WatertightRay4 make_watertight_ray4(const WatertightRay& r) {
    const float origin[3] = {r.origin.x, r.origin.y, r.origin.z};
    WatertightRay4 r4;
    r4.origin_x = _mm_set1_ps(origin[r.kx]);
    r4.origin_y = _mm_set1_ps(origin[r.ky]);
    r4.origin_z = _mm_set1_ps(origin[r.kz]);
    r4.shear_x = _mm_set1_ps(r.shear_x);
    r4.shear_y = _mm_set1_ps(r.shear_y);
    r4.shear_z = _mm_set1_ps(r.shear_z);
    r4.t_min = _mm_set1_ps(r.t_min);
    r4.t_max = _mm_set1_ps(r.t_max);
    r4.offset_x = 4 * r.kx;
    r4.offset_y = 4 * r.ky;
    r4.offset_z = 4 * r.kz;
    return r4;
}

/// The setup for one permutation (kx, ky, kz), known at compile time: the shear
/// (d[kx] / d[kz], d[ky] / d[kz], 1 / d[kz]) is one 4-wide division with the scalar setup's
/// operands in its lanes, and every per-ray constant is a shuffle.
template <int kx, int ky, int kz>
WatertightRay4 make_watertight_ray4_axes(__m128 origin, __m128 direction, float t_min,
                                         float t_max) {
    const __m128 numerator =
        _mm_shuffle_ps(direction, _mm_set1_ps(1.0f), _MM_SHUFFLE(0, 0, ky, kx));
    const __m128 denominator = _mm_shuffle_ps(direction, direction, _MM_SHUFFLE(kz, kz, kz, kz));
    const __m128 shear = _mm_div_ps(numerator, denominator);  // (Sx, Sy, Sz, Sz)
    WatertightRay4 r4;
    r4.origin_x = _mm_shuffle_ps(origin, origin, _MM_SHUFFLE(kx, kx, kx, kx));
    r4.origin_y = _mm_shuffle_ps(origin, origin, _MM_SHUFFLE(ky, ky, ky, ky));
    r4.origin_z = _mm_shuffle_ps(origin, origin, _MM_SHUFFLE(kz, kz, kz, kz));
    r4.shear_x = _mm_shuffle_ps(shear, shear, _MM_SHUFFLE(0, 0, 0, 0));
    r4.shear_y = _mm_shuffle_ps(shear, shear, _MM_SHUFFLE(1, 1, 1, 1));
    r4.shear_z = _mm_shuffle_ps(shear, shear, _MM_SHUFFLE(2, 2, 2, 2));
    r4.t_min = _mm_set1_ps(t_min);
    r4.t_max = _mm_set1_ps(t_max);
    r4.offset_x = 4 * kx;
    r4.offset_y = 4 * ky;
    r4.offset_z = 4 * kz;
    return r4;
}

/// make_watertight_ray4(make_watertight_ray(origin, direction, t_min, t_max)) without the scalar
/// detour: kz and the winding swap are chosen exactly as make_watertight_ray chooses them, then
/// one of the six permutations is set up (the tests compare both paths bit for bit).
inline WatertightRay4 make_watertight_ray4(glm::vec3 origin, glm::vec3 direction, float t_min,
                                           float t_max) {
    const float ax = std::fabs(direction.x), ay = std::fabs(direction.y),
                az = std::fabs(direction.z);
    int kz = ay > ax ? 1 : 0;
    kz = az > (kz == 1 ? ay : ax) ? 2 : kz;
    const float d_kz = kz == 0 ? direction.x : (kz == 1 ? direction.y : direction.z);
    const __m128 o = _mm_setr_ps(origin.x, origin.y, origin.z, 0.0f);
    const __m128 d = _mm_setr_ps(direction.x, direction.y, direction.z, 1.0f);
    // kx = kz + 1, ky = kx + 1 (mod 3), swapped when d[kz] < 0.
    switch (2 * kz + (d_kz < 0.0f ? 1 : 0)) {
        case 0: return make_watertight_ray4_axes<1, 2, 0>(o, d, t_min, t_max);
        case 1: return make_watertight_ray4_axes<2, 1, 0>(o, d, t_min, t_max);
        case 2: return make_watertight_ray4_axes<2, 0, 1>(o, d, t_min, t_max);
        case 3: return make_watertight_ray4_axes<0, 2, 1>(o, d, t_min, t_max);
        case 4: return make_watertight_ray4_axes<0, 1, 2>(o, d, t_min, t_max);
        default: return make_watertight_ray4_axes<1, 0, 2>(o, d, t_min, t_max);
    }
}

/// The lanes of `zeros` whose U, V or W is exactly 0: all three recomputed in binary64 (scalar,
/// rare), as the scalar test does.
FOVREF_FORCE_INLINE void watertight4_edge_fallback(__m128 Ax, __m128 Ay, __m128 Bx, __m128 By,
                                                   __m128 Cx, __m128 Cy, unsigned zeros, __m128& U,
                                                   __m128& V, __m128& W) {
    alignas(16) float ax[4], ay[4], bx[4], by[4], cx[4], cy[4], u[4], v[4], w[4];
    _mm_store_ps(ax, Ax);
    _mm_store_ps(ay, Ay);
    _mm_store_ps(bx, Bx);
    _mm_store_ps(by, By);
    _mm_store_ps(cx, Cx);
    _mm_store_ps(cy, Cy);
    _mm_store_ps(u, U);
    _mm_store_ps(v, V);
    _mm_store_ps(w, W);
    watertight_edge_fallback_lanes(4, zeros, ax, ay, bx, by, cx, cy, u, v, w);
    U = _mm_load_ps(u);
    V = _mm_load_ps(v);
    W = _mm_load_ps(w);
}

/// intersect_watertight on the four triangles of `corners` ([corner][axis][lane], 16-byte
/// aligned). Returns the mask of the lanes hit (bit i: lane i), their t, u, v in `hits`; lanes
/// outside `lanes` are never reported. The comments name the steps of the scalar test.
FOVREF_FORCE_INLINE unsigned intersect_watertight4(const WatertightRay4& ray, const float* corners,
                                                   unsigned lanes, Hits4& hits) {
    const float* a = corners;
    const float* b = corners + 12;
    const float* c = corners + 24;
    // Corners relative to the ray origin, on the permuted axes: A[kx], A[ky], A[kz], ...
    const __m128 A_kx = _mm_sub_ps(_mm_load_ps(a + ray.offset_x), ray.origin_x);
    const __m128 A_ky = _mm_sub_ps(_mm_load_ps(a + ray.offset_y), ray.origin_y);
    const __m128 A_kz = _mm_sub_ps(_mm_load_ps(a + ray.offset_z), ray.origin_z);
    const __m128 B_kx = _mm_sub_ps(_mm_load_ps(b + ray.offset_x), ray.origin_x);
    const __m128 B_ky = _mm_sub_ps(_mm_load_ps(b + ray.offset_y), ray.origin_y);
    const __m128 B_kz = _mm_sub_ps(_mm_load_ps(b + ray.offset_z), ray.origin_z);
    const __m128 C_kx = _mm_sub_ps(_mm_load_ps(c + ray.offset_x), ray.origin_x);
    const __m128 C_ky = _mm_sub_ps(_mm_load_ps(c + ray.offset_y), ray.origin_y);
    const __m128 C_kz = _mm_sub_ps(_mm_load_ps(c + ray.offset_z), ray.origin_z);

    // Shear and scale of the corners (x and y).
    const __m128 Ax = _mm_sub_ps(A_kx, _mm_mul_ps(ray.shear_x, A_kz));
    const __m128 Ay = _mm_sub_ps(A_ky, _mm_mul_ps(ray.shear_y, A_kz));
    const __m128 Bx = _mm_sub_ps(B_kx, _mm_mul_ps(ray.shear_x, B_kz));
    const __m128 By = _mm_sub_ps(B_ky, _mm_mul_ps(ray.shear_y, B_kz));
    const __m128 Cx = _mm_sub_ps(C_kx, _mm_mul_ps(ray.shear_x, C_kz));
    const __m128 Cy = _mm_sub_ps(C_ky, _mm_mul_ps(ray.shear_y, C_kz));

    // Scaled barycentrics U, V, W; a lane with one of them exactly 0 recomputes all three in
    // binary64 (scalar, rare).
    __m128 U = _mm_sub_ps(_mm_mul_ps(Cx, By), _mm_mul_ps(Cy, Bx));
    __m128 V = _mm_sub_ps(_mm_mul_ps(Ax, Cy), _mm_mul_ps(Ay, Cx));
    __m128 W = _mm_sub_ps(_mm_mul_ps(Bx, Ay), _mm_mul_ps(By, Ax));
    const __m128 zero = _mm_setzero_ps();
    const unsigned zeros = static_cast<unsigned>(_mm_movemask_ps(
        _mm_or_ps(_mm_or_ps(_mm_cmpeq_ps(U, zero), _mm_cmpeq_ps(V, zero)), _mm_cmpeq_ps(W, zero))));
    if ((zeros & lanes) != 0) watertight4_edge_fallback(Ax, Ay, Bx, By, Cx, Cy, zeros, U, V, W);

    // Edge tests: reject lanes with some of U, V, W negative and some positive.
    const __m128 negative =
        _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(U, zero), _mm_cmplt_ps(V, zero)), _mm_cmplt_ps(W, zero));
    const __m128 positive =
        _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(U, zero), _mm_cmpgt_ps(V, zero)), _mm_cmpgt_ps(W, zero));
    // Determinant; 'det != 0' is true for NaN, as '!(det == 0)' in the scalar test.
    const __m128 det = _mm_add_ps(_mm_add_ps(U, V), W);
    const __m128 inside = _mm_andnot_ps(_mm_and_ps(negative, positive), _mm_cmpneq_ps(det, zero));

    // Scaled hit distance T with the sign of det moved into it (T_signed = det < 0 ? -T : T;
    // negation flips the sign bit, as the scalar unary minus does), against the scaled interval.
    const __m128 Az = _mm_mul_ps(ray.shear_z, A_kz);
    const __m128 Bz = _mm_mul_ps(ray.shear_z, B_kz);
    const __m128 Cz = _mm_mul_ps(ray.shear_z, C_kz);
    const __m128 T =
        _mm_add_ps(_mm_add_ps(_mm_mul_ps(U, Az), _mm_mul_ps(V, Bz)), _mm_mul_ps(W, Cz));
    const __m128 sign_bit = _mm_set1_ps(-0.0f);
    const __m128 det_negative = _mm_cmplt_ps(det, zero);
    const __m128 T_signed = _mm_xor_ps(T, _mm_and_ps(det_negative, sign_bit));
    const __m128 det_abs = _mm_andnot_ps(sign_bit, det);
    const __m128 in_range = _mm_and_ps(_mm_cmpgt_ps(T_signed, _mm_mul_ps(ray.t_min, det_abs)),
                                       _mm_cmple_ps(T_signed, _mm_mul_ps(ray.t_max, det_abs)));
    unsigned mask = static_cast<unsigned>(_mm_movemask_ps(_mm_and_ps(inside, in_range))) & lanes;
    if (mask == 0) return 0;

    // Normalise, and the exact final test of t against (t_min, t_max].
    const __m128 rcp_det = _mm_div_ps(_mm_set1_ps(1.0f), det);
    const __m128 t = _mm_mul_ps(T, rcp_det);
    mask &= static_cast<unsigned>(
        _mm_movemask_ps(_mm_and_ps(_mm_cmpgt_ps(t, ray.t_min), _mm_cmple_ps(t, ray.t_max))));
    _mm_store_ps(hits.t, t);
    _mm_store_ps(hits.u, _mm_mul_ps(V, rcp_det));
    _mm_store_ps(hits.v, _mm_mul_ps(W, rcp_det));
    return mask;
}

#endif  // FOVREF_BVH_SSE

}  // namespace fovref
