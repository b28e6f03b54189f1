// Software rasterizer producing the G-buffer (SPEC §4). One deterministic pass, no threads:
//
//   for each triangle, in index order:
//     world -> view space (the same dot products as project_to_screen, camera.h)
//     clip against the near plane and the guard band (homogeneous clipping, Sutherland-Hodgman)
//     project, snap to 1/256 px fixed point, fan-triangulate the clipped polygon
//     for each pixel centre in the bounding box: 64-bit edge functions + top-left rule
//       perspective-correct barycentrics (u, v) of the original triangle
//       depth test "less" on view depth, ties to the lower primitive id
//   then per pixel: surface_at(scene, primitive, u, v) (ref/trace/surface.h) fills the channels.
//
// The first part writes a visibility buffer (primitive, u, v, depth per pixel); the G-buffer is
// resolved from it, so the rasterized and ray-cast G-buffers share all attribute arithmetic.
// Conventions and choices: docs/raster.md.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "ref/image/image.h"
#include "ref/raster/gbuffer.h"
#include "ref/scene/camera.h"
#include "ref/scene/scene.h"

namespace fovref {

/// Sub-pixel precision: screen positions are snapped to multiples of 1/256 pixel (SPEC §4).
inline constexpr int raster_subpixel_bits = 8;
inline constexpr std::int64_t raster_subpixel_scale = std::int64_t{1} << raster_subpixel_bits;

/// Guard band: after clipping, every screen coordinate lies in [-2^15, 2^15] pixels. Triangles
/// reaching beyond are clipped against these four lines in homogeneous space (exactly like the
/// near plane), so fixed-point values stay below 2^23 and edge functions below 2^49 (int64 holds
/// them with room to spare), and float barycentrics keep ~2^-24 * 2^16 px = 0.004 px accuracy.
inline constexpr float raster_guard_band_px = 32768.0f;

/// Largest accepted width or height: the screen must lie well inside the guard band.
inline constexpr int raster_max_dimension = 16384;

/// Near plane distance in front of the camera: 1e-4 x scene_scale (SPEC §3's epsilon), at least
/// raster_min_near (for a scene whose bounds are a point).
inline constexpr float raster_near_factor = 1e-4f;
inline constexpr float raster_min_near = 1e-30f;

/// Triangles with a view coordinate beyond +-1e20 (or not finite) are rejected and counted:
/// clip-plane distances multiply z by up to ~1e12, which must stay far below FLT_MAX.
inline constexpr float raster_max_view_coordinate = 1e20f;

/// Per-render statistics. Every input triangle ends in exactly one of the categories
/// out_of_range, clipped_away, degenerate, culled_offscreen, rasterized.
struct RasterStats {
    std::int64_t triangles_in = 0;                ///< triangles in the scene
    std::int64_t triangles_out_of_range = 0;      ///< a view coordinate beyond 1e20 or not finite
    std::int64_t triangles_clipped_away = 0;      ///< entirely behind the near plane
    std::int64_t triangles_near_clipped = 0;      ///< crossed the near plane, part kept
    std::int64_t triangles_guard_clipped = 0;     ///< crossed the guard band, part kept
    std::int64_t triangles_degenerate = 0;        ///< zero area after snapping
    std::int64_t triangles_culled_offscreen = 0;  ///< no pixel centre inside its bounding box
    std::int64_t triangles_rasterized = 0;        ///< reached the per-pixel loop
    std::int64_t coverage_tests = 0;          ///< pixel centres tested against the edge functions
    std::int64_t fragments_tested = 0;        ///< covered pixel centres (depth tests)
    std::int64_t fragments_written = 0;       ///< depth tests passed
    std::int64_t pixels_covered = 0;          ///< non-background pixels of the result
    std::int64_t motion_behind_previous = 0;  ///< covered pixels behind the previous camera
    bool operator==(const RasterStats&) const = default;
};

/// What the rasterizer decides per pixel, before attributes: the visible primitive (-1 =
/// background), its barycentrics (u weights corner 1, v corner 2) and the view depth used by
/// the depth test (+inf on background). Row-major, top row first.
struct VisibilityBuffer {
    int width = 0;
    int height = 0;
    std::vector<std::int32_t> primitive;
    std::vector<float> u;
    std::vector<float> v;
    std::vector<float> depth;
    bool operator==(const VisibilityBuffer&) const = default;
};

/// The G-buffer of SPEC §4 for `camera`; motion vectors against `previous_camera` (pass the
/// same camera for a static frame: motion is then ~0). Throws fovref::Error for a size outside
/// [1, raster_max_dimension], a camera with vfov outside (0, 180) or non-finite axes, or
/// inconsistent scene arrays.
GBuffer rasterize_gbuffer(const Scene& scene, const Camera& camera, const Camera& previous_camera,
                          int width, int height, RasterStats& stats);

/// First half of rasterize_gbuffer: coverage and depth only. Adds to `stats`.
VisibilityBuffer rasterize_visibility(const Scene& scene, const Camera& camera, int width,
                                      int height, RasterStats& stats);

/// Second half: the G-buffer channels from surface_at at each visible (primitive, u, v).
GBuffer resolve_gbuffer(const Scene& scene, const VisibilityBuffer& visibility,
                        const Camera& camera, const Camera& previous_camera, RasterStats& stats);

// ---- Building blocks, exposed so that tests (and a GPU port) can check them one by one ----

/// A screen point in fixed point: pixels x 256.
struct FixedPoint {
    std::int64_t x = 0;
    std::int64_t y = 0;
    bool operator==(const FixedPoint&) const = default;
};

/// Snap a screen point to the fixed-point grid: clamp each coordinate to the guard band, then
/// round(x * 256) with halves away from zero (std::round).
FixedPoint snap_to_fixed(glm::vec2 screen);

/// Edge function of the directed edge a -> b at p: cross(b - a, p - a), exact in int64.
/// For a triangle a, b, c it is positive inside when the triangle is clockwise on screen
/// (y down), which is the orientation the rasterizer normalises to.
inline std::int64_t edge_function(FixedPoint a, FixedPoint b, FixedPoint p) {
    return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
}

/// Top-left rule (Direct3D) for edge a -> b of a triangle clockwise on screen: a top edge is
/// horizontal with the triangle below it (it runs in +x), a left edge runs upwards (-y).
/// A pixel centre exactly on an edge is covered only when the edge is top or left.
inline bool is_top_left_edge(FixedPoint a, FixedPoint b) {
    const std::int64_t dx = b.x - a.x, dy = b.y - a.y;
    return (dy == 0 && dx > 0) || dy < 0;
}

/// Coverage of one screen-space triangle (either winding) by the rules above: adds 1 to
/// `coverage` (1 channel) at every covered pixel centre inside the image; returns the number
/// of covered pixels. Zero-area triangles (after snapping) cover nothing.
std::int64_t rasterize_triangle_coverage(glm::vec2 a, glm::vec2 b, glm::vec2 c, Image& coverage);

/// View-space coordinates of world point p: (dot(d, R), dot(d, U), dot(d, F)), d = p - position.
glm::vec3 world_to_view(const Camera& camera, glm::vec3 p);

/// Screen point of a view-space point with view.z > 0: the arithmetic of project_to_screen, so
/// view_to_screen(world_to_view(p)) equals project_to_screen(p) bit for bit.
glm::vec2 view_to_screen(glm::vec3 view, float tan_half, int width, int height);

}  // namespace fovref
