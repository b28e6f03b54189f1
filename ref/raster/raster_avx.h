// The rasterizer's per-triangle and per-fragment work eight at a time with AVX: the same bits as
// setup_triangle and raster_fragment, which stay the readable reference (docs/raster.md, "Eight
// at a time").
//
// setup_triangles_avx: eight triangles, one per lane: the corners' view coordinates
// (world_to_view), the range and clip-plane tests, and for a triangle inside every plane (most)
// the projection (view_to_screen) and the snap to 1/256 px (snap_to_fixed), each in the scalar
// order. A triangle that needs clipping, or lies out of range, is left to setup_triangle.
//
// raster_fragments_avx: eight covered pixel centres, which may be of different triangles and
// rows. Each lane builds its pixel's primary ray (primary_ray_direction), the watertight ray's
// permutation and shear (make_watertight_ray, the axes picked per lane by masks), its triangle's
// sheared corners, the scaled barycentrics and the plane point (intersect_watertight_plane), the
// surface position and its view depth, each operation in the scalar code's order. A lane whose
// scaled barycentrics need the binary64 recomputation (one of U, V, W exactly 0) runs
// raster_fragment itself.
#pragma once

#include <cstdint>

#include "ref/raster/rasterizer.h"

namespace fovref {

/// Whether raster_fragments_avx and setup_triangles_avx may run: simd_allowed() and a CPU with
/// AVX.
bool raster_fragments_avx_applies();

/// setup_triangle of triangles first .. first + count - 1 (count 1 .. 8): where triangle
/// first + l lies in view range and inside every clip plane, setup[l] receives what
/// setup_triangle gives (status ready, no clipping, its three snapped corners) and done[l] is
/// true; elsewhere done[l] is false and setup[l] is left as it is. Only where
/// raster_fragments_avx_applies.
void setup_triangles_avx(const Scene& scene, const RasterFrame& frame, std::int32_t first,
                         int count, TriangleSetup* setup, bool* done);

/// raster_fragment at site[l] for l < count (1 .. 8): fragment[l] and hit[l] receive what
/// raster_fragment gives for each (fragment[l] is left as it is where hit[l] is false). Only
/// where raster_fragments_avx_applies.
void raster_fragments_avx(const Scene& scene, const RasterFrame& frame, const RasterSite* site,
                          int count, RasterFragment* fragment, bool* hit);

}  // namespace fovref
