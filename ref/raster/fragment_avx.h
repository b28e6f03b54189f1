// The rasterizer's per-fragment work (raster_fragment) eight covered pixel centres at a time with
// AVX: the same bits as raster_fragment, which stays the readable reference (docs/raster.md,
// "Eight fragments at a time"). The eight may be of different triangles and rows. Each lane
// builds its pixel's primary ray (primary_ray_direction), the watertight ray's permutation and
// shear (make_watertight_ray, the axes picked per lane by masks), its triangle's sheared corners,
// the scaled barycentrics and the plane point (intersect_watertight_plane), the surface position
// and its view depth, each operation in the scalar code's order. A lane whose scaled barycentrics
// need the binary64 recomputation (one of U, V, W exactly 0) runs raster_fragment itself.
#pragma once

#include <cstdint>

#include "ref/raster/rasterizer.h"

namespace fovref {

/// Whether raster_fragments_avx may run: simd_allowed() and a CPU with AVX.
bool raster_fragments_avx_applies();

/// raster_fragment at site[l] for l < count (1 .. 8): fragment[l] and hit[l] receive what
/// raster_fragment gives for each (fragment[l] is left as it is where hit[l] is false). Only
/// where raster_fragments_avx_applies.
void raster_fragments_avx(const Scene& scene, const RasterFrame& frame, const RasterSite* site,
                          int count, RasterFragment* fragment, bool* hit);

}  // namespace fovref
