// Software rasterizer producing the G-buffer (SPEC §4). One deterministic pass, no threads:
//
//   for each triangle, in index order:                          setup_triangle
//     world -> view space (the same dot products as project_to_screen, camera.h)
//     clip against the near plane and the guard band (homogeneous clipping, Sutherland-Hodgman)
//     project, snap to 1/256 px fixed point, fan-triangulate the clipped polygon
//     for each fan triangle:                                      setup_edges
//       for each pixel centre in its bounding box:                edge_values (fill rule)
//         attributes where the pixel's primary ray meets the     raster_fragment
//         triangle's plane (the ray caster's arithmetic)
//         depth test "less" on view depth, ties to the lower id   depth_test
//   then per pixel: surface_at(scene, primitive, u, v) fills the channels (write_gbuffer_pixel).
//
// Coverage is decided in fixed point on the snapped polygon; attributes are not: they are
// evaluated at the exact pixel centre, so wherever the rasterizer and the ray caster pick the
// same triangle their G-buffers are the same bits. Conventions and choices: docs/raster.md.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "ref/core/halton.h"
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

/// A triangle gains at most one vertex per clip plane (3 + 5 = 8) while the clipped polygon is
/// convex; float rounding can dent it very slightly, and a plane through a dent crosses it twice
/// more, so the buffer has room for 16 and clipping checks the bound.
inline constexpr int raster_max_polygon_vertices = 16;

/// Largest accepted width or height: the screen must lie well inside the guard band.
inline constexpr int raster_max_dimension = 16384;

/// Near plane distance in front of the camera: 1e-4 x scene_scale (SPEC §3's epsilon), at least
/// raster_min_near (for a scene whose bounds are a point).
inline constexpr float raster_near_factor = 1e-4f;
inline constexpr float raster_min_near = 1e-30f;

/// Triangles with a view coordinate beyond +-1e20 (or not finite) are rejected and counted:
/// clip-plane distances multiply z by up to ~1e12, which must stay far below FLT_MAX.
inline constexpr float raster_max_view_coordinate = 1e20f;

/// Which edges own the pixel centres that lie exactly on them (SPEC §4 `fill_rule`).
enum class FillRule {
    d3d,  ///< Direct3D / Vulkan top-left rule in fovref's y-down frame (the default)
    gl,   ///< OpenGL's top-left rule in its y-up window: bottom-left in fovref's frame
};

/// "d3d" or "gl".
const char* fill_rule_name(FillRule rule);
/// Parses "d3d" / "gl"; throws fovref::Error naming `what` otherwise.
FillRule parse_fill_rule(const std::string& text, const std::string& what);

/// Rasterizer options (documented defaults).
struct RasterSettings {
    FillRule fill_rule = FillRule::d3d;
    /// Where in its pixel each pixel samples (a TAA jitter, as a jittered projection does):
    /// (0.5, 0.5) is the centre. The shift from the centre is rounded to the 1/256-pixel grid
    /// (raster_sample_shift) and applied to the snapped vertices, and the attribute ray goes
    /// through the shifted sample: coverage and attributes stay consistent.
    Offset2 sample{};
    bool operator==(const RasterSettings&) const = default;
};

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
    std::int64_t coverage_tests = 0;     ///< pixel centres tested against the edge functions
    std::int64_t fragments_tested = 0;   ///< covered pixel centres (depth tests)
    std::int64_t fragments_written = 0;  ///< depth tests passed
    /// Covered pixel centres whose primary ray does not meet the triangle's plane in front of the
    /// camera (parallel to it, or behind): the attributes have no point to be evaluated at, so
    /// the fragment is dropped (the ray caster misses the triangle there too).
    std::int64_t fragments_without_plane_hit = 0;
    std::int64_t pixels_covered = 0;          ///< non-background pixels of the result
    std::int64_t motion_behind_previous = 0;  ///< covered pixels behind the previous camera
    bool operator==(const RasterStats&) const = default;
};

/// What the rasterizer decides per pixel, before attributes: the visible primitive (-1 =
/// background), its barycentrics (u weights corner 1, v corner 2) at the point where the pixel's
/// primary ray meets the triangle's plane, and the view depth of that point used by the depth
/// test (+inf on background). Row-major, top row first.
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
                          int width, int height, RasterStats& stats,
                          const RasterSettings& settings = {});

/// First half of rasterize_gbuffer: coverage and depth only. Adds to `stats`.
VisibilityBuffer rasterize_visibility(const Scene& scene, const Camera& camera, int width,
                                      int height, RasterStats& stats,
                                      const RasterSettings& settings = {});

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

/// OpenGL's rule seen in fovref's y-down frame, for the same orientation: OpenGL's window has y
/// up, so its "top" edge (triangle below it in y-up) is a bottom edge here: horizontal with the
/// triangle above it (it runs in -x). Left edges stay left (-y).
inline bool is_bottom_left_edge(FixedPoint a, FixedPoint b) {
    const std::int64_t dx = b.x - a.x, dy = b.y - a.y;
    return (dy == 0 && dx < 0) || dy < 0;
}

/// Whether edge a -> b (triangle clockwise on screen, y down) owns the centres on it.
inline bool edge_owns_centres(FillRule rule, FixedPoint a, FixedPoint b) {
    return rule == FillRule::d3d ? is_top_left_edge(a, b) : is_bottom_left_edge(a, b);
}

/// A snapped triangle ready for coverage tests. A counter-clockwise triangle (negative area) has
/// b and c swapped, so every triangle is tested clockwise-on-screen (two-sided, SPEC §4). The
/// fill rule becomes an integer bias per edge: a centre is covered when E - bias >= 0 on all
/// three edges, bias 0 on an edge that owns the centres on it and 1 otherwise.
struct EdgeSetup {
    FixedPoint a, b, c;  ///< clockwise on screen
    bool swapped = false;
    std::int64_t area = 0;  ///< doubled area, > 0 (0: degenerate, covers nothing)
    std::int64_t bias_a = 0, bias_b = 0, bias_c = 0;  ///< of the edges opposite a, b, c
};

EdgeSetup setup_edges(FixedPoint a, FixedPoint b, FixedPoint c, FillRule rule);

/// Fixed-point sample position of pixel (i, j): its centre, (256 i + 128, 256 j + 128).
/// A sample position's shift from the pixel centre on the 1/256-pixel grid (RasterSettings::
/// sample): round((sample - 1/2) 256), halves away from zero.
FixedPoint raster_sample_shift(Offset2 sample);

inline FixedPoint pixel_centre_fixed(std::int64_t i, std::int64_t j) {
    const std::int64_t half = raster_subpixel_scale / 2;
    return {i * raster_subpixel_scale + half, j * raster_subpixel_scale + half};
}

/// The three edge values at the centre of pixel (i, j) and the coverage decision.
struct EdgeValues {
    std::int64_t wa = 0, wb = 0, wc = 0;  ///< E_bc, E_ca, E_ab (>= 0 inside)
    bool covered = false;
};

inline EdgeValues edge_values(const EdgeSetup& e, std::int64_t i, std::int64_t j) {
    const FixedPoint p = pixel_centre_fixed(i, j);
    EdgeValues r;
    r.wa = edge_function(e.b, e.c, p);
    r.wb = edge_function(e.c, e.a, p);
    r.wc = edge_function(e.a, e.b, p);
    r.covered = r.wa - e.bias_a >= 0 && r.wb - e.bias_b >= 0 && r.wc - e.bias_c >= 0;
    return r;
}

/// Coverage of one screen-space triangle (either winding) by the rules above: adds 1 to
/// `coverage` (1 channel) at every covered pixel centre inside the image; returns the number
/// of covered pixels. Zero-area triangles (after snapping) cover nothing.
std::int64_t rasterize_triangle_coverage(glm::vec2 a, glm::vec2 b, glm::vec2 c, Image& coverage,
                                         FillRule rule = FillRule::d3d);

/// A clip plane in view space: normal . view + offset >= 0 is inside.
struct ClipPlane {
    glm::vec3 normal{0.0f};
    float offset = 0.0f;
    bool is_near = false;
};

/// The planes a triangle is clipped against, in this order: the near plane z >= near, then the
/// guard band |screen x|, |screen y| <= raster_guard_band_px written in view space
/// (docs/raster.md).
std::array<ClipPlane, 5> raster_clip_planes(float near, float tan_half, int width, int height);

/// Per-frame constants of the rasterizer (camera, screen, clip planes).
struct RasterFrame {
    Camera camera;
    int width = 0, height = 0;
    float tan_half = 0.0f;
    float near = 0.0f;  ///< near plane distance (docs/raster.md)
    RasterSettings settings;
    FixedPoint sample_shift;               ///< raster_sample_shift(settings.sample), once per frame
    std::array<ClipPlane, 5> clip_planes;  ///< raster_clip_planes(near, tan_half, width, height)
};

/// The constants for `camera` and a W x H screen; checks the size and the camera (throws
/// fovref::Error).
RasterFrame make_raster_frame(const Scene& scene, const Camera& camera, int width, int height,
                              const RasterSettings& settings);

/// What setup did with one triangle, and the snapped polygon it covers with.
struct TriangleSetup {
    enum class Status { out_of_range, clipped_away, offscreen, ready };
    Status status = Status::ready;
    bool near_clipped = false, guard_clipped = false;
    int count = 0;  ///< polygon vertices (>= 3 when ready)
    /// Snapped, fanned around vertex 0: fan triangle k - 1 is (0, k, k + 1).
    std::array<FixedPoint, raster_max_polygon_vertices> polygon;
};

/// Per-triangle setup of `primitive`: view transform, clipping, projection and snapping.
TriangleSetup setup_triangle(const Scene& scene, const RasterFrame& frame, std::int32_t primitive);
/// The same into `setup` (its status, clip flags, count and polygon[0 .. count) written), for the
/// visibility pass, which keeps one TriangleSetup for all its triangles.
void setup_triangle(const Scene& scene, const RasterFrame& frame, std::int32_t primitive,
                    TriangleSetup& setup);

/// A fragment: a covered pixel centre of one triangle with its attribute point.
struct RasterFragment {
    std::int32_t primitive = -1;
    float t = 0.0f;      ///< distance along the pixel's primary ray to the triangle's plane
    float u = 0.0f;      ///< barycentrics of that point (may lie slightly outside the triangle:
    float v = 0.0f;      ///< the coverage comes from the snapped polygon)
    float depth = 0.0f;  ///< view depth of surface_at's position there: what the depth test uses
};

/// Per-pixel work of the rasterizer for a centre of pixel (x, y) that `primitive` covers: the
/// pixel's primary ray (SPEC §1, exactly the ray caster's) meets the triangle's plane, by the
/// watertight test's arithmetic without its edge test (intersect_watertight_plane), at
/// barycentrics (u, v); the depth is the view depth of surface_at's position at (u, v). Returns
/// false when the ray is parallel to the plane or meets it at t <= 0 (the fragment is dropped).
bool raster_fragment(const Scene& scene, const RasterFrame& frame, int x, int y,
                     std::int32_t primitive, RasterFragment& fragment);

/// A pixel centre (x, y) of triangle `primitive`: one fragment to compute.
struct RasterSite {
    int x = 0, y = 0;
    std::int32_t primitive = -1;
};

/// The rasterized G-buffer's channels of screen pixel (sx, sy), made again from its visible
/// primitive and written to pixel (x, y) of `g` (of any size): raster_fragment at (sx, sy) gives
/// the (u, v) the visibility pass stored there, then write_gbuffer_sample with the pixel's centre,
/// as resolve_gbuffer does. The same bits as resolve_gbuffer's pixel (sx, sy), so a pass that
/// reads a few pixels of the G-buffer (kfr's lp_sample) needs only the primitive ids at full
/// resolution. `primitive_id` is the stored id (a float); a value that is not a triangle of the
/// scene (-1: background), or a triangle whose plane the pixel's ray misses, writes nothing and
/// returns false. `previous_tan_half` = tan_half_vfov(previous_camera).
bool write_rasterized_pixel(GBuffer& g, int x, int y, const Scene& scene, const RasterFrame& frame,
                            const Camera& previous_camera, float previous_tan_half,
                            float primitive_id, int sx, int sy);

/// write_rasterized_pixel in two steps, for a caller that computes the fragments in batches
/// (raster_fragments_avx): the site of screen pixel (sx, sy) when `primitive_id` names a triangle
/// of the scene (false otherwise), and the channels of its fragment written to pixel (x, y) of
/// `g`.
bool rasterized_site(const Scene& scene, float primitive_id, int sx, int sy, RasterSite& site);
void write_rasterized_fragment(GBuffer& g, int x, int y, const Scene& scene,
                               const RasterFrame& frame, const Camera& previous_camera,
                               float previous_tan_half, const RasterSite& site,
                               const RasterFragment& fragment);

/// The visibility pass's primitive ids as the G-buffer channel `primitive_id` (-1: background):
/// resolve_gbuffer's channel, bit for bit.
Image visibility_primitive_ids(const VisibilityBuffer& visibility);
/// The visibility pass's depths as the G-buffer channel `view_depth` (0: background):
/// resolve_gbuffer's channel, bit for bit (raster_fragment's depth is view_depth of surface_at's
/// position).
Image visibility_view_depth(const VisibilityBuffer& visibility);

/// Depth test "less" at pixel (x, y): the fragment wins when its depth is smaller than the stored
/// one, or equal with a lower primitive id (SPEC §3, §4's tie-break). Writes it and returns true
/// when it wins.
bool depth_test(VisibilityBuffer& visibility, int x, int y, const RasterFragment& fragment);

/// The visibility pass's work at one covered pixel centre (x, y) of `primitive`: raster_fragment,
/// then depth_test, counted in `stats` (fragments tested, without a plane hit, written).
void rasterize_fragment(const Scene& scene, const RasterFrame& frame, std::int32_t primitive, int x,
                        int y, VisibilityBuffer& visibility, RasterStats& stats);

/// `fovref probe` for a rasterized pixel: every triangle whose snapped coverage contains the
/// centre of pixel (x, y), in index order, with what decided it.
struct RasterCandidate {
    std::int32_t primitive = -1;
    int fan_triangle = 0;  ///< which triangle of the clipped polygon's fan
    bool near_clipped = false, guard_clipped = false;
    FixedPoint a, b, c;  ///< snapped corners (1/256 px), clockwise on screen
    EdgeValues edges;    ///< at the pixel centre
    std::int64_t area = 0;
    bool owns[3] = {false, false, false};  ///< whether each edge (opposite a, b, c) owns centres
    bool fragment = false;                 ///< raster_fragment found the plane point
    RasterFragment value;
    bool won_depth_test = false;  ///< replaying the depth tests in index order
    float stored_depth = 0.0f;    ///< what the depth test compared against (+inf: nothing yet)
    std::int32_t stored_primitive = -1;
};

struct RasterPixelExplanation {
    FillRule fill_rule = FillRule::d3d;
    FixedPoint centre;
    std::vector<RasterCandidate> candidates;
    std::int32_t winner = -1;  ///< -1: background
};

/// Reruns the visibility pass for one pixel with the pass's own functions (setup_triangle,
/// setup_edges, edge_values, raster_fragment, depth_test).
RasterPixelExplanation explain_raster_pixel(const Scene& scene, const Camera& camera, int width,
                                            int height, const RasterSettings& settings, int x,
                                            int y);

/// View-space coordinates of world point p: (dot(d, R), dot(d, U), dot(d, F)), d = p - position.
glm::vec3 world_to_view(const Camera& camera, glm::vec3 p);

/// Screen point of a view-space point with view.z > 0: the arithmetic of project_to_screen, so
/// view_to_screen(world_to_view(p)) equals project_to_screen(p) bit for bit.
glm::vec2 view_to_screen(glm::vec3 view, float tan_half, int width, int height);

}  // namespace fovref
