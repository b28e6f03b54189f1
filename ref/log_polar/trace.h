// Ray generation and tracing in buffer space (Lund §3.3.1 LPRayGen, §3.3.3; SPEC §5.1-5.2): the
// G-buffers of a foveated frame, read by the basic ray tracer's shading pass (ref/trace).
//
//   trace_lp_gbuffer:   for each texel (i, j) of the w x h log-polar buffer, row by row:
//                         lp_gbuffer_texel(x = i, y = j):
//                           centre (i + 1/2, j + 1/2) -> lp_inverse -> screen point p
//                           (from lp_inverse_table: the same bits, w + h transcendentals)
//                           p off screen (or inside the gaze circle): no ray, no data, valid 0
//                           else the primary ray through p (SPEC §1), closest hit, the texel
//                           written by write_gbuffer_sample (motion relative to p), valid 1
//   trace_gaze_gbuffer: the gaze buffer covers gaze_window(map), the bounding box of the gaze
//                       circle on the screen; for each screen pixel (x, y) of the window whose
//                       centre lies inside the circle (|centre - g| < r_G), row by row: the basic
//                       ray tracer's per-pixel work (raycast_window_pixel), so these pixels equal
//                       basic's bit for bit; every other pixel keeps the background and valid 0.
//
// A texel or pixel that is not traced carries the G-buffer's background values (primitive id -1)
// and 0 in the validity mask; only the mask tells it from a traced miss.
#pragma once

#include "ref/bvh/bvh.h"
#include "ref/log_polar/map.h"
#include "ref/raster/gbuffer.h"
#include "ref/trace/raycast_gbuffer.h"

namespace fovref {

/// A G-buffer with a validity mask (1: a ray was traced for this texel or pixel, 0: not).
struct MaskedGBuffer {
    GBuffer gbuffer;
    Image valid;  ///< 1 channel, 0 or 1
    MaskedGBuffer() = default;
    MaskedGBuffer(int width, int height) : gbuffer(width, height), valid(width, height, 1, 0.0f) {}
};

/// What the buffer-space passes did (they add to it).
struct FoveatedTraceStats {
    RaycastStats rays;  ///< the primary rays' traversal work (log-polar texels and gaze pixels)
    std::int64_t texels_traced = 0;
    std::int64_t texels_off_screen = 0;
    std::int64_t texels_inside_gaze = 0;  ///< on screen but inside the gaze circle (G = 1 only)
    std::int64_t gaze_pixels_traced = 0;
};

/// What every buffer-space pass does first for texel (x, y): its screen point p (stored in
/// `screen_points`), its status, counted; a traced texel is marked valid.
TexelStatus begin_texel(MaskedGBuffer& buffer, Image& screen_points, const LogPolarMap& map,
                        const LpInverseTable& table, int x, int y, glm::vec2& p,
                        FoveatedTraceStats& stats);

/// Per-texel work of trace_lp_gbuffer for texel (x, y) = (i, j). `screen_points` (2 channels,
/// the buffer's size) receives the texel centre's inverse-mapped screen point, traced or not.
/// Returns the texel's status.
TexelStatus lp_gbuffer_texel(MaskedGBuffer& buffer, Image& screen_points, const LogPolarMap& map,
                             const LpInverseTable& table, const PrimaryView& view, int x, int y,
                             FoveatedTraceStats& stats);

/// The log-polar buffer's G-buffer (map.width x map.height) and the texels' screen points.
/// `jitter` (TAA, SPEC §7): each texel's ray launches at (i + o_x, j + o_y) in the buffer, before
/// the inverse map, instead of the texel centre.
MaskedGBuffer trace_lp_gbuffer(const LogPolarMap& map, const PrimaryView& view,
                               Image& screen_points, FoveatedTraceStats& stats,
                               Offset2 jitter = {});

/// The gaze buffer's window on the screen: the pixels x0 <= x < x0 + width, y0 <= y < y0 + height
/// with x0 = floor(g.x - r_G - 1), x0 + width = ceil(g.x + r_G + 1) and the same in y (in
/// binary64), clipped to the screen, and at least 1 x 1 (a circle off screen gives a window with
/// no pixel inside it, which can still be written). Every pixel whose centre lies inside the
/// gaze circle is in it (the box is one pixel wider than the circle on each side).
ScreenWindow gaze_window(const LogPolarMap& map);

/// Per-pixel work of trace_gaze_gbuffer: traces screen pixel (x, y) of `window` (its buffer pixel
/// is (x - x0, y - y0)) when its centre is inside the gaze circle; returns whether it did.
bool gaze_gbuffer_pixel(MaskedGBuffer& buffer, const ScreenWindow& window, const LogPolarMap& map,
                        const PrimaryView& view, int x, int y, FoveatedTraceStats& stats,
                        Offset2 jitter = {});

/// The gaze buffer: gaze_window(map)'s size, traced inside the gaze circle only (the circle test
/// on the pixel centre; with `jitter` the ray goes through (x + o_x, y + o_y), as basic's).
MaskedGBuffer trace_gaze_gbuffer(const LogPolarMap& map, const PrimaryView& view,
                                 FoveatedTraceStats& stats, Offset2 jitter = {});

/// Where the rays of a foveated frame went (Lund Fig. 3.3): a W x H count of the primary rays
/// whose screen point lies in each pixel (log-polar texels by their screen point, gaze pixels
/// by their centre; `gaze_valid` covers `gaze`, the gaze buffer's window).
Image ray_position_counts(int width, int height, const Image& lp_valid, const Image& screen_points,
                          const Image* gaze_valid, const ScreenWindow& gaze = {});

/// The pixel each log-polar texel's ray is counted in by ray_position_counts, a decision a port
/// can be diffed on (docs/foveation.md, "Buffers and counters"): the buffer's size, 2 channels,
/// (floor(x), floor(y)) of a traced texel's screen point on the width x height screen, (-1, -1)
/// for a texel not counted. Its margin is the point's distance from the nearest pixel edge (the
/// diff derives it: pixel_edge(lp_screen_point)).
Image ray_pixels(int width, int height, const Image& lp_valid, const Image& screen_points);

}  // namespace fovref
