// Watertight ray-triangle intersection (Woop, Benthin, Wald 2013, "Watertight Ray/Triangle
// Intersection", JCGT 2(1)), as small inline functions that a GPU port can copy line for line.
//
// The ray is transformed so that it starts at the origin and runs along +z of a sheared space:
// kz is the axis of the largest |direction| component, kx and ky the next two (swapped when
// direction[kz] < 0 so the winding of the projected triangle is preserved), and the shear
// (Sx, Sy, Sz) = (d[kx]/d[kz], d[ky]/d[kz], 1/d[kz]) maps the direction to (0, 0, 1). The scaled
// barycentrics U, V, W are 2D edge functions of the sheared corners; an edge shared by two
// triangles gives exactly opposite values in both (a*b is commutative in IEEE arithmetic), so no
// ray slips between them. When one of U, V, W is exactly 0 it is recomputed in binary64, where
// the products of two floats are exact, so its sign is exact too. Back faces are not culled: the
// edge test accepts U, V, W all >= 0 or all <= 0.
//
// A ray through an edge or vertex (U, V or W exactly 0) hits every triangle sharing it, at the
// same surface point; the closest-hit query then reports the lowest primitive index (SPEC §3).
#pragma once

#include <cmath>

#include <glm/glm.hpp>

// The per-triangle and per-box tests run in the innermost loop; GCC at -O2 does not inline them
// by itself (measured: 30% slower traversal), so they are marked for inlining.
#if defined(__GNUC__) || defined(__clang__)
#define FOVREF_FORCE_INLINE inline __attribute__((always_inline))
#else
#define FOVREF_FORCE_INLINE inline
#endif

namespace fovref {

/// Per-ray constants of the watertight test (the paper's precomputation).
struct WatertightRay {
    glm::vec3 origin{0.0f};
    int kx = 0, ky = 1, kz = 2;  ///< permutation: kz = axis of the largest |direction|
    float shear_x = 0.0f;        ///< Sx = d[kx] / d[kz]
    float shear_y = 0.0f;        ///< Sy = d[ky] / d[kz]
    float shear_z = 1.0f;        ///< Sz = 1 / d[kz]
    float t_min = 0.0f;
    float t_max = 0.0f;
};

/// The paper's per-ray setup. kz is the first axis with the largest |d| (strict '>', so ties go
/// to the lower axis). The direction must be finite and non-zero (trace_* check that first).
inline WatertightRay make_watertight_ray(glm::vec3 origin, glm::vec3 direction, float t_min,
                                         float t_max) {
    const float d[3] = {direction.x, direction.y, direction.z};
    WatertightRay r;
    r.origin = origin;
    r.t_min = t_min;
    r.t_max = t_max;
    int kz = std::fabs(d[1]) > std::fabs(d[0]) ? 1 : 0;
    kz = std::fabs(d[2]) > std::fabs(d[kz]) ? 2 : kz;
    const int next[3] = {1, 2, 0};
    int kx = next[kz];
    int ky = next[kx];
    // Swap kx and ky to preserve the winding direction of triangles.
    if (d[kz] < 0.0f) {
        const int swap = kx;
        kx = ky;
        ky = swap;
    }
    r.kx = kx;
    r.ky = ky;
    r.kz = kz;
    r.shear_x = d[kx] / d[kz];
    r.shear_y = d[ky] / d[kz];
    r.shear_z = 1.0f / d[kz];
    return r;
}

/// The 2D edge function of sheared corners, recomputed in binary64 (exact products, one
/// rounding) when the float value is exactly 0, as the paper prescribes.
FOVREF_FORCE_INLINE float watertight_edge_fallback(float px, float py, float qx, float qy) {
    const double e = static_cast<double>(qx) * static_cast<double>(py) -
                     static_cast<double>(qy) * static_cast<double>(px);
    return static_cast<float>(e);
}

/// The lanes of `zeros` among `lanes` lanes of sheared corners (a, b, c: x and y per lane) whose
/// U, V or W was exactly 0: all three recomputed with watertight_edge_fallback, as
/// watertight_edges does (the 4-wide and the packet tests, after storing their lanes).
FOVREF_FORCE_INLINE void watertight_edge_fallback_lanes(int lanes, unsigned zeros, const float* ax,
                                                        const float* ay, const float* bx,
                                                        const float* by, const float* cx,
                                                        const float* cy, float* u, float* v,
                                                        float* w) {
    for (int i = 0; i < lanes; ++i) {
        if (((zeros >> i) & 1u) == 0) continue;
        u[i] = watertight_edge_fallback(bx[i], by[i], cx[i], cy[i]);
        v[i] = watertight_edge_fallback(cx[i], cy[i], ax[i], ay[i]);
        w[i] = watertight_edge_fallback(ax[i], ay[i], bx[i], by[i]);
    }
}

/// The sheared triangle as the test sees it: the scaled barycentrics U, V, W (weights of a, b and
/// c; recomputed in binary64 when one is exactly 0) and the corners' kz coordinates relative to
/// the ray origin (unscaled). Shared by the hit test and by the plane intersection below, so the
/// two compute the same bits.
struct WatertightEdges {
    float U = 0.0f, V = 0.0f, W = 0.0f;
    float Az = 0.0f, Bz = 0.0f, Cz = 0.0f;
};

FOVREF_FORCE_INLINE WatertightEdges watertight_edges(const WatertightRay& ray, glm::vec3 a,
                                                     glm::vec3 b, glm::vec3 c) {
    // Corners relative to the ray origin (as arrays: the axes kx, ky, kz are chosen per ray).
    const float A[3] = {a.x - ray.origin.x, a.y - ray.origin.y, a.z - ray.origin.z};
    const float B[3] = {b.x - ray.origin.x, b.y - ray.origin.y, b.z - ray.origin.z};
    const float C[3] = {c.x - ray.origin.x, c.y - ray.origin.y, c.z - ray.origin.z};

    // Shear and scale of the corners (x and y; z follows once the triangle is known to be hit).
    const float Ax = A[ray.kx] - ray.shear_x * A[ray.kz];
    const float Ay = A[ray.ky] - ray.shear_y * A[ray.kz];
    const float Bx = B[ray.kx] - ray.shear_x * B[ray.kz];
    const float By = B[ray.ky] - ray.shear_y * B[ray.kz];
    const float Cx = C[ray.kx] - ray.shear_x * C[ray.kz];
    const float Cy = C[ray.ky] - ray.shear_y * C[ray.kz];

    // Scaled barycentrics: U weights a, V weights b, W weights c.
    WatertightEdges e;
    e.U = Cx * By - Cy * Bx;
    e.V = Ax * Cy - Ay * Cx;
    e.W = Bx * Ay - By * Ax;
    if (e.U == 0.0f || e.V == 0.0f || e.W == 0.0f) {
        e.U = watertight_edge_fallback(Bx, By, Cx, Cy);
        e.V = watertight_edge_fallback(Cx, Cy, Ax, Ay);
        e.W = watertight_edge_fallback(Ax, Ay, Bx, By);
    }
    e.Az = A[ray.kz];
    e.Bz = B[ray.kz];
    e.Cz = C[ray.kz];
    return e;
}

/// Scaled hit distance T = t * det from the sheared z coordinates.
FOVREF_FORCE_INLINE float watertight_scaled_distance(const WatertightRay& ray,
                                                     const WatertightEdges& e) {
    const float Az = ray.shear_z * e.Az;
    const float Bz = ray.shear_z * e.Bz;
    const float Cz = ray.shear_z * e.Cz;
    return e.U * Az + e.V * Bz + e.W * Cz;
}

/// Intersects the ray with triangle (a, b, c). On a hit with t in (t_min, t_max] it sets t and
/// the barycentrics (u, v) of corners b and c (P = (1 - u - v) a + u b + v c) and returns true.
/// NaN anywhere (non-finite corners) never produces a hit: every acceptance test is written so
/// that NaN fails it.
FOVREF_FORCE_INLINE bool intersect_watertight(const WatertightRay& ray, glm::vec3 a, glm::vec3 b,
                                              glm::vec3 c, float& t, float& u, float& v) {
    const WatertightEdges e = watertight_edges(ray, a, b, c);

    // Edge tests; both signs are accepted (no back-face culling).
    if ((e.U < 0.0f || e.V < 0.0f || e.W < 0.0f) && (e.U > 0.0f || e.V > 0.0f || e.W > 0.0f))
        return false;

    // Determinant: 0 when the ray lies in the triangle's plane (or misses it along an edge line).
    const float det = e.U + e.V + e.W;
    if (det == 0.0f) return false;

    // Scaled hit distance T = t * det, compared against t_min * |det| and t_max * |det| (the
    // sign of det flipped into T, as the paper's xorf(T, sign(det))).
    const float T = watertight_scaled_distance(ray, e);
    const float T_signed = det < 0.0f ? -T : T;
    const float det_abs = std::fabs(det);
    if (!(T_signed > ray.t_min * det_abs && T_signed <= ray.t_max * det_abs)) return false;

    // Normalise. The scaled comparison can accept t one rounding outside (t_min, t_max]; the
    // final test makes the returned t obey the contract exactly.
    const float rcp_det = 1.0f / det;
    const float t_hit = T * rcp_det;
    if (!(t_hit > ray.t_min && t_hit <= ray.t_max)) return false;
    t = t_hit;
    u = e.V * rcp_det;
    v = e.W * rcp_det;
    return true;
}

/// Where the ray's line meets the plane of triangle (a, b, c), with the hit test's arithmetic but
/// none of its tests: no edge test (u, v may lie outside the triangle: the point is extrapolated
/// on its plane) and no range test (t may be <= 0). Wherever intersect_watertight reports a hit,
/// this gives the same t, u, v bits. Returns false only when det == 0 (the ray is parallel to the
/// plane, or the sheared triangle is degenerate). The rasterizer evaluates its attributes here
/// (SPEC §4: at the exact pixel centre, on the pixel's primary ray).
FOVREF_FORCE_INLINE bool intersect_watertight_plane(const WatertightRay& ray, glm::vec3 a,
                                                    glm::vec3 b, glm::vec3 c, float& t, float& u,
                                                    float& v) {
    const WatertightEdges e = watertight_edges(ray, a, b, c);
    const float det = e.U + e.V + e.W;
    if (det == 0.0f) return false;
    const float T = watertight_scaled_distance(ray, e);
    const float rcp_det = 1.0f / det;
    t = T * rcp_det;
    u = e.V * rcp_det;
    v = e.W * rcp_det;
    return true;
}

/// Whether a triangle can ever be hit: finite corners and non-zero area. Degenerate triangles
/// are kept out of the BVH and skipped by the brute-force intersector alike (SPEC §2).
inline bool triangle_is_hittable(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    const bool finite = std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z) &&
                        std::isfinite(b.x) && std::isfinite(b.y) && std::isfinite(b.z) &&
                        std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z);
    if (!finite) return false;
    const glm::vec3 n = glm::cross(b - a, c - a);
    const float double_area_squared = glm::dot(n, n);
    return double_area_squared > 0.0f && std::isfinite(double_area_squared);
}

}  // namespace fovref
