#include "ref/raster/raster_avx.h"

#include "ref/core/avx_lanes.h"
#include "ref/core/simd.h"

namespace fovref {

namespace {

using namespace avx;

/// A vector of the scalar code's three components, one register each.
struct Lanes3 {
    __m256 x, y, z;
};

/// v[k] per lane, k given by the masks of k = 0 and k = 1 (else 2).
FOVREF_AVX_INLINE __m256 pick(const Lanes3& v, __m256 is0, __m256 is1) {
    return select(is0, v.x, select(is1, v.y, v.z));
}

/// One component of primary_ray_direction's F + sx R - sy U (before normalising).
FOVREF_AVX_INLINE __m256 ray_axis(float f, float r, float up, __m256 sx, __m256 sy) {
    return _mm256_sub_ps(_mm256_add_ps(set(f), _mm256_mul_ps(sx, set(r))),
                         _mm256_mul_ps(sy, set(up)));
}

/// One component of surface_at's position a w0 + b u + c v, minus the camera's (view_depth).
FOVREF_AVX_INLINE __m256 from_camera(__m256 a, __m256 b, __m256 c, __m256 w0, __m256 u, __m256 v,
                                     float origin) {
    return _mm256_sub_ps(_mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(a, w0), _mm256_mul_ps(b, u)),
                                       _mm256_mul_ps(c, v)),
                         set(origin));
}

/// Each lane's triangle corners (corner k's coordinate c): broadcast when all eight are of one
/// triangle (most batches), else gathered lane by lane.
FOVREF_AVX_INLINE void site_corners(const Scene& scene, const RasterSite* site, int count,
                                    __m256 (&position)[3][3]) {
    bool one_triangle = true;
    for (int l = 1; l < count; ++l)
        one_triangle = one_triangle && site[l].primitive == site[0].primitive;
    if (one_triangle) {
        const auto t = static_cast<std::size_t>(site[0].primitive);
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 p = scene.positions[3 * t + static_cast<std::size_t>(k)];
            position[k][0] = set(p.x), position[k][1] = set(p.y), position[k][2] = set(p.z);
        }
        return;
    }
    alignas(32) float corner[3][3][lanes];
    for (int l = 0; l < lanes; ++l) {
        const auto t = static_cast<std::size_t>(site[l < count ? l : 0].primitive);
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 p = scene.positions[3 * t + static_cast<std::size_t>(k)];
            corner[k][0][l] = p.x, corner[k][1][l] = p.y, corner[k][2][l] = p.z;
        }
    }
    for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) position[k][c] = _mm256_load_ps(corner[k][c]);
}

/// primary_ray_direction of each lane's pixel centre, moved by the frame's sample shift as
/// raster_fragment moves it.
FOVREF_AVX_INLINE Lanes3 primary_directions(const RasterFrame& frame, const RasterSite* site,
                                            int count) {
    alignas(32) float column[lanes], row[lanes];
    for (int l = 0; l < lanes; ++l) {
        column[l] = static_cast<float>(site[l < count ? l : 0].x);
        row[l] = static_cast<float>(site[l < count ? l : 0].y);
    }
    const float scale = static_cast<float>(raster_subpixel_scale);
    const float shift_x = static_cast<float>(frame.sample_shift.x) / scale;
    const float shift_y = static_cast<float>(frame.sample_shift.y) / scale;
    const __m256 cx = _mm256_add_ps(_mm256_add_ps(_mm256_load_ps(column), set(0.5f)), set(shift_x));
    const __m256 cy = _mm256_add_ps(_mm256_add_ps(_mm256_load_ps(row), set(0.5f)), set(shift_y));
    const Camera& camera = frame.camera;
    const float w = static_cast<float>(frame.width), h = static_cast<float>(frame.height);
    const __m256 sx = _mm256_mul_ps(
        _mm256_mul_ps(_mm256_sub_ps(_mm256_div_ps(_mm256_mul_ps(set(2.0f), cx), set(w)), set(1.0f)),
                      set(frame.tan_half)),
        set(w / h));
    const __m256 sy =
        _mm256_mul_ps(_mm256_sub_ps(_mm256_div_ps(_mm256_mul_ps(set(2.0f), cy), set(h)), set(1.0f)),
                      set(frame.tan_half));
    const Lanes3 raw{ray_axis(camera.forward.x, camera.right.x, camera.up.x, sx, sy),
                     ray_axis(camera.forward.y, camera.right.y, camera.up.y, sx, sy),
                     ray_axis(camera.forward.z, camera.right.z, camera.up.z, sx, sy)};
    const __m256 length = _mm256_sqrt_ps(
        _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(raw.x, raw.x), _mm256_mul_ps(raw.y, raw.y)),
                      _mm256_mul_ps(raw.z, raw.z)));
    return {_mm256_div_ps(raw.x, length), _mm256_div_ps(raw.y, length),
            _mm256_div_ps(raw.z, length)};
}

/// make_watertight_ray's per-lane constants: the axes as masks (k = 0, k = 1; else 2) and the
/// shear.
struct WatertightLanes {
    __m256 kz0, kz1, kx0, kx1, ky0, ky1;
    __m256 shear_x, shear_y, shear_z;
};

/// make_watertight_ray: kz the first axis of the largest |d|, kx and ky the next two, swapped
/// where d[kz] < 0.
FOVREF_AVX_INLINE WatertightLanes watertight_lanes(const Lanes3& d) {
    WatertightLanes r;
    const __m256 z_is1 = greater(abs(d.y), abs(d.x));
    const __m256 kz_abs = select(z_is1, abs(d.y), abs(d.x));
    const __m256 z_is2 = greater(abs(d.z), kz_abs);
    r.kz0 = negation(either(z_is1, z_is2)), r.kz1 = both(z_is1, negation(z_is2));
    const __m256 dz = pick(d, r.kz0, r.kz1);
    const __m256 swap = less(dz, zero());
    // next[kz]: 0 -> 1, 1 -> 2, 2 -> 0; next[next[kz]]: 0 -> 2, 1 -> 0, 2 -> 1
    const __m256 next0 = negation(either(r.kz0, r.kz1)), next1 = r.kz0;  // next[kz] == 0, == 1
    const __m256 after0 = r.kz1, after1 = negation(either(r.kz0, r.kz1));
    r.kx0 = select(swap, after0, next0), r.kx1 = select(swap, after1, next1);
    r.ky0 = select(swap, next0, after0), r.ky1 = select(swap, next1, after1);
    r.shear_x = _mm256_div_ps(pick(d, r.kx0, r.kx1), dz);
    r.shear_y = _mm256_div_ps(pick(d, r.ky0, r.ky1), dz);
    r.shear_z = _mm256_div_ps(set(1.0f), dz);
    return r;
}

/// intersect_watertight_plane's results per lane.
struct PlaneLanes {
    __m256 t, u, v;
    int accepted;   ///< raster_fragment's tests passed (det != 0, t > 0, t, u, v finite)
    int reference;  ///< U, V or W exactly 0: the lane needs raster_fragment's binary64 edges
};

/// watertight_edges on the corners relative to the camera, then intersect_watertight_plane.
FOVREF_AVX_INLINE PlaneLanes plane_lanes(const WatertightLanes& ray, const __m256 (&position)[3][3],
                                         const float* origin) {
    __m256 sheared_x[3], sheared_y[3], corner_z[3];
    for (int k = 0; k < 3; ++k) {
        const Lanes3 c{_mm256_sub_ps(position[k][0], set(origin[0])),
                       _mm256_sub_ps(position[k][1], set(origin[1])),
                       _mm256_sub_ps(position[k][2], set(origin[2]))};
        corner_z[k] = pick(c, ray.kz0, ray.kz1);
        sheared_x[k] =
            _mm256_sub_ps(pick(c, ray.kx0, ray.kx1), _mm256_mul_ps(ray.shear_x, corner_z[k]));
        sheared_y[k] =
            _mm256_sub_ps(pick(c, ray.ky0, ray.ky1), _mm256_mul_ps(ray.shear_y, corner_z[k]));
    }
    const __m256 U = _mm256_sub_ps(_mm256_mul_ps(sheared_x[2], sheared_y[1]),
                                   _mm256_mul_ps(sheared_y[2], sheared_x[1]));
    const __m256 V = _mm256_sub_ps(_mm256_mul_ps(sheared_x[0], sheared_y[2]),
                                   _mm256_mul_ps(sheared_y[0], sheared_x[2]));
    const __m256 W = _mm256_sub_ps(_mm256_mul_ps(sheared_x[1], sheared_y[0]),
                                   _mm256_mul_ps(sheared_y[1], sheared_x[0]));
    PlaneLanes r;
    r.reference = bits(either(equal(U, zero()), either(equal(V, zero()), equal(W, zero()))));
    const __m256 det = _mm256_add_ps(_mm256_add_ps(U, V), W);
    const __m256 T =
        _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(U, _mm256_mul_ps(ray.shear_z, corner_z[0])),
                                    _mm256_mul_ps(V, _mm256_mul_ps(ray.shear_z, corner_z[1]))),
                      _mm256_mul_ps(W, _mm256_mul_ps(ray.shear_z, corner_z[2])));
    const __m256 rcp_det = _mm256_div_ps(set(1.0f), det);
    r.t = _mm256_mul_ps(T, rcp_det);
    r.u = _mm256_mul_ps(V, rcp_det);
    r.v = _mm256_mul_ps(W, rcp_det);
    r.accepted = bits(both(both(not_equal(det, zero()), greater(r.t, zero())),
                           both(finite(r.t), both(finite(r.u), finite(r.v)))));
    return r;
}

__attribute__((target("avx"))) void fragments(const Scene& scene, const RasterFrame& frame,
                                              const RasterSite* site, int count,
                                              RasterFragment* fragment, bool* hit) {
    __m256 position[3][3];  // corner k's coordinate c
    site_corners(scene, site, count, position);
    const Camera& camera = frame.camera;
    const float origin[3] = {camera.position.x, camera.position.y, camera.position.z};
    const PlaneLanes plane =
        plane_lanes(watertight_lanes(primary_directions(frame, site, count)), position, origin);
    // the position as surface_at computes it, its view depth
    const __m256 w0 = _mm256_sub_ps(_mm256_sub_ps(set(1.0f), plane.u), plane.v);
    __m256 to[3];
    for (int c = 0; c < 3; ++c)
        to[c] = from_camera(position[0][c], position[1][c], position[2][c], w0, plane.u, plane.v,
                            origin[c]);
    const __m256 depth = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(to[0], set(camera.forward.x)),
                                                     _mm256_mul_ps(to[1], set(camera.forward.y))),
                                       _mm256_mul_ps(to[2], set(camera.forward.z)));
    alignas(32) float out_t[lanes], out_u[lanes], out_v[lanes], out_depth[lanes];
    _mm256_store_ps(out_t, plane.t);
    _mm256_store_ps(out_u, plane.u);
    _mm256_store_ps(out_v, plane.v);
    _mm256_store_ps(out_depth, depth);
    for (int l = 0; l < count; ++l) {
        if (plane.reference >> l & 1) {
            hit[l] =
                raster_fragment(scene, frame, site[l].x, site[l].y, site[l].primitive, fragment[l]);
            continue;
        }
        hit[l] = (plane.accepted >> l & 1) != 0;
        if (!hit[l]) continue;
        fragment[l].primitive = site[l].primitive;
        fragment[l].t = out_t[l];
        fragment[l].u = out_u[l];
        fragment[l].v = out_v[l];
        fragment[l].depth = out_depth[l];
    }
}

/// Triangles first .. first + count - 1, one per lane: their corners' view coordinates
/// (world_to_view: d = p - position, (dot(d, R), dot(d, U), dot(d, F))) into view[k][axis];
/// returns the lanes in range (every |coordinate| <= raster_max_view_coordinate, NaN fails) and
/// inside every clip plane (every plane_distance >= 0).
FOVREF_AVX_INLINE __m256 view_corners(const Scene& scene, const RasterFrame& frame,
                                      std::int32_t first, int count, __m256 (&view)[3][3]) {
    const Camera& camera = frame.camera;
    alignas(32) float corner[3][3][lanes];  // corner k's coordinate c, per lane
    for (int l = 0; l < lanes; ++l) {
        const auto t = static_cast<std::size_t>(first + (l < count ? l : 0));
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 p = scene.positions[3 * t + static_cast<std::size_t>(k)];
            corner[k][0][l] = p.x, corner[k][1][l] = p.y, corner[k][2][l] = p.z;
        }
    }
    const glm::vec3 axes[3] = {camera.right, camera.up, camera.forward};
    const float position[3] = {camera.position.x, camera.position.y, camera.position.z};
    __m256 fast = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
    for (int k = 0; k < 3; ++k) {
        __m256 d[3];
        for (int c = 0; c < 3; ++c)
            d[c] = _mm256_sub_ps(_mm256_load_ps(corner[k][c]), set(position[c]));
        for (int a = 0; a < 3; ++a) {
            view[k][a] = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(d[0], set(axes[a].x)),
                                                     _mm256_mul_ps(d[1], set(axes[a].y))),
                                       _mm256_mul_ps(d[2], set(axes[a].z)));
            fast = both(fast, at_most(abs(view[k][a]), set(raster_max_view_coordinate)));
        }
        for (const ClipPlane& plane : frame.clip_planes) {
            const __m256 distance = _mm256_add_ps(
                _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(set(plane.normal.x), view[k][0]),
                                            _mm256_mul_ps(set(plane.normal.y), view[k][1])),
                              _mm256_mul_ps(set(plane.normal.z), view[k][2])),
                set(plane.offset));
            fast = both(fast, at_least(distance, zero()));
        }
    }
    return fast;
}

/// One corner's view_to_screen, then snap_to_fixed (before the sample shift): clamped to the
/// guard band, x 256 (exact), rounded with halves away from zero (truncation and the exact
/// fraction; |x 256| <= 2^23), as exact integers in binary32, into snapped[0] (x), [1] (y).
/// Lanes outside `fast` convert a safe 0.
FOVREF_AVX_INLINE void snap_corner(const RasterFrame& frame, const __m256 (&view)[3], __m256 fast,
                                   float (*snapped)[lanes]) {
    const float w = static_cast<float>(frame.width), h = static_cast<float>(frame.height);
    const float kx = frame.tan_half * (w / h);
    const float g = raster_guard_band_px, scale = static_cast<float>(raster_subpixel_scale);
    const __m256 sx = _mm256_div_ps(view[0], view[2]);
    const __m256 sy = _mm256_div_ps(negate(view[1]), view[2]);
    const __m256 screen[2] = {
        _mm256_mul_ps(
            _mm256_mul_ps(_mm256_add_ps(_mm256_div_ps(sx, set(kx)), set(1.0f)), set(0.5f)), set(w)),
        _mm256_mul_ps(
            _mm256_mul_ps(_mm256_add_ps(_mm256_div_ps(sy, set(frame.tan_half)), set(1.0f)),
                          set(0.5f)),
            set(h))};
    for (int c = 0; c < 2; ++c) {
        const __m256 v = _mm256_mul_ps(std_min(std_max(screen[c], set(-g)), set(g)), set(scale));
        const __m256 truncated = _mm256_cvtepi32_ps(_mm256_cvttps_epi32(select(fast, v, zero())));
        const __m256 fraction = _mm256_sub_ps(v, truncated);
        const __m256 up = _mm256_and_ps(at_least(fraction, set(0.5f)), set(1.0f));
        const __m256 down = _mm256_and_ps(at_most(fraction, set(-0.5f)), set(1.0f));
        _mm256_store_ps(snapped[c], _mm256_sub_ps(_mm256_add_ps(truncated, up), down));
    }
}

__attribute__((target("avx"))) void setups(const Scene& scene, const RasterFrame& frame,
                                           std::int32_t first, int count, TriangleSetup* setup,
                                           bool* done) {
    __m256 view[3][3];
    const __m256 fast = view_corners(scene, frame, first, count, view);
    const int ready = bits(fast) & ((1 << count) - 1);
    for (int l = 0; l < count; ++l) done[l] = (ready >> l & 1) != 0;
    if (ready == 0) return;
    alignas(32) float snapped[3][2][lanes];
    for (int k = 0; k < 3; ++k) snap_corner(frame, view[k], fast, snapped[k]);
    const FixedPoint shift = frame.sample_shift;
    for (int l = 0; l < count; ++l) {
        if (!done[l]) continue;
        TriangleSetup& s = setup[l];
        s.status = TriangleSetup::Status::ready;
        s.near_clipped = s.guard_clipped = false;
        s.count = 3;
        for (int k = 0; k < 3; ++k)
            s.polygon[static_cast<std::size_t>(k)] = {
                static_cast<std::int64_t>(snapped[k][0][l]) - shift.x,
                static_cast<std::int64_t>(snapped[k][1][l]) - shift.y};
    }
}

}  // namespace

void setup_triangles_avx(const Scene& scene, const RasterFrame& frame, std::int32_t first,
                         int count, TriangleSetup* setup, bool* done) {
    setups(scene, frame, first, count, setup, done);
}

bool raster_fragments_avx_applies() { return simd_allowed() && cpu_has_avx(); }

void raster_fragments_avx(const Scene& scene, const RasterFrame& frame, const RasterSite* site,
                          int count, RasterFragment* fragment, bool* hit) {
    fragments(scene, frame, site, count, fragment, hit);
}

}  // namespace fovref
