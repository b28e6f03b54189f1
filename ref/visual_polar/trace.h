// Ray generation in Visual-Polar space and at scattered screen points (Koskela P5 §3.2, P3/P4;
// SPEC §5.3, §5.5): the G-buffers the Visual-Polar and acuity modes shade.
//
//   trace_vp_gbuffer: for each texel (i, j) of the w x h Visual-Polar buffer, row by row:
//     vp_gbuffer_texel(x = i, y = j):
//       vp_texel_status: clipped (j >= n_i) or off screen -> no ray, no data, valid 0, counted
//       else the primary ray through the centre's screen point p (SPEC §1), closest hit, the
//       texel written by write_gbuffer_sample (motion relative to p), valid 1
//     (with a VpTexelTable, the statuses and points are read from it: the same texels traced)
//   trace_point_gbuffer: an N x 1 G-buffer, texel k the primary ray through screen point k
//     (points off the screen [0, W) x [0, H) are not traced: valid 0, counted off screen)
//
// A texel that is not traced carries the G-buffer's background values (primitive id -1) and 0 in
// the validity mask; only the mask tells it from a traced miss.
#pragma once

#include <vector>

#include "ref/log_polar/trace.h"
#include "ref/visual_polar/map.h"

namespace fovref {

/// What the Visual-Polar and point passes did (they add to it).
struct VpTraceStats {
    RaycastStats rays;
    std::int64_t texels_traced = 0;
    std::int64_t texels_clipped = 0;
    std::int64_t texels_off_screen = 0;
};

/// Per-texel work of trace_vp_gbuffer for texel (x, y) = (i, j); `screen_points` (2 channels)
/// receives the centre's screen point (0, 0 for a clipped texel).
VpTexel vp_gbuffer_texel(MaskedGBuffer& buffer, Image& screen_points, const VisualPolarMap& map,
                         const PrimaryView& view, int x, int y, VpTraceStats& stats);

/// Each texel's status and screen point as vp_texel_status gives them, for one map: the trace
/// stage keeps it while the forward map stays the same (a static gaze; BMFR's staircase may
/// move), and trace_vp_gbuffer then traces the same texels through the same points without the
/// inverse map per texel. The periphery's columns (i >= i_f) do not depend on the clip, so the
/// table serves any map with the same forward map (VisualPolarMap::same_forward); the fovea's
/// columns are read from it only for the very map it was made for.
struct VpTexelTable {
    VisualPolarMap map;
    Image screen_points;          ///< w x h x 2, as trace_vp_gbuffer writes them
    std::vector<VpTexel> status;  ///< texel (i, j) at j w + i
};
VpTexelTable vp_texel_table(const VisualPolarMap& map);

/// The Visual-Polar buffer's G-buffer (map.width x map.height) and its texels' screen points;
/// with `table` (made for a map with `map`'s forward map; a check fails otherwise) the statuses
/// and points are read from it where it holds `map`'s (the fovea's columns computed by
/// vp_gbuffer_texel when the clips differ), the same bits.
MaskedGBuffer trace_vp_gbuffer(const VisualPolarMap& map, const PrimaryView& view,
                               Image& screen_points, VpTraceStats& stats,
                               const VpTexelTable* table = nullptr);

/// A G-buffer of points.size() x 1 texels on a W x H screen: texel k holds the closest hit of
/// the primary ray through points[k].
MaskedGBuffer trace_point_gbuffer(const std::vector<glm::vec2>& points, int width, int height,
                                  const PrimaryView& view, VpTraceStats& stats);

}  // namespace fovref
