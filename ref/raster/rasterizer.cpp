#include "ref/raster/rasterizer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <utility>

#include "ref/core/error.h"
#include "ref/core/vec.h"
#include "ref/trace/surface.h"

namespace fovref {

namespace {

// ---- Fixed-point helpers ----

/// floor(a / b) for b > 0 (C++ division truncates towards zero).
std::int64_t floor_div(std::int64_t a, std::int64_t b) {
    const std::int64_t q = a / b;
    return (a % b != 0 && a < 0) ? q - 1 : q;
}

/// Pixel columns (or rows) whose centre 256 i + 128 lies in [lo, hi] (fixed point), clamped to
/// [0, size - 1]; empty when first > last.
struct PixelRange {
    std::int64_t first = 0;
    std::int64_t last = -1;
};
PixelRange centres_in(std::int64_t lo, std::int64_t hi, int size) {
    const std::int64_t half = raster_subpixel_scale / 2;
    PixelRange r;
    r.first = -floor_div(-(lo - half), raster_subpixel_scale);  // ceil((lo - 128) / 256)
    r.last = floor_div(hi - half, raster_subpixel_scale);
    if (r.first < 0) r.first = 0;
    if (r.last > size - 1) r.last = size - 1;
    return r;
}

enum class TriangleOutcome { degenerate, offscreen, rasterized };

// ---- One screen-space triangle: coverage by integer edge functions ----
//
// Edge function of a -> b at p: E_ab(p) = cross(b - a, p - a), exact in int64 (|coordinates|
// <= 2^23 after the guard band, so |E| < 2^49). The signed double area is E_ab(c). A
// counter-clockwise triangle (area < 0) has b and c swapped first, so one orientation and one
// top-left classification serve both windings (two-sided, SPEC §4). A pixel centre p is covered
// when each of E_bc(p), E_ca(p), E_ab(p) is > 0, or == 0 on a top-left edge. `visit(i, j, wa,
// wb, wc, area)` receives the three edge values as weights of a, b, c in the caller's order
// (wa + wb + wc == area > 0, every weight >= 0).
template <class Visit>
TriangleOutcome rasterize_fixed_triangle(FixedPoint a, FixedPoint b, FixedPoint c, int width,
                                         int height, std::int64_t& coverage_tests, Visit&& visit) {
    std::int64_t area = edge_function(a, b, c);
    if (area == 0) return TriangleOutcome::degenerate;
    const bool swapped = area < 0;
    if (swapped) {
        std::swap(b, c);
        area = -area;
    }
    // Bounding box of the vertices -> range of pixel centres, clipped to the screen.
    const PixelRange cols = centres_in(std::min({a.x, b.x, c.x}), std::max({a.x, b.x, c.x}), width);
    const PixelRange rows =
        centres_in(std::min({a.y, b.y, c.y}), std::max({a.y, b.y, c.y}), height);
    if (cols.first > cols.last || rows.first > rows.last) return TriangleOutcome::offscreen;

    // Top-left rule as an integer bias: covered <=> E - bias >= 0, bias 0 on top-left edges.
    const std::int64_t bias_a = is_top_left_edge(b, c) ? 0 : 1;  // edge opposite a
    const std::int64_t bias_b = is_top_left_edge(c, a) ? 0 : 1;
    const std::int64_t bias_c = is_top_left_edge(a, b) ? 0 : 1;
    const std::int64_t half = raster_subpixel_scale / 2;
    for (std::int64_t j = rows.first; j <= rows.last; ++j) {
        for (std::int64_t i = cols.first; i <= cols.last; ++i) {
            const FixedPoint p{i * raster_subpixel_scale + half, j * raster_subpixel_scale + half};
            ++coverage_tests;
            const std::int64_t wa = edge_function(b, c, p);
            const std::int64_t wb = edge_function(c, a, p);
            const std::int64_t wc = edge_function(a, b, p);
            if (wa - bias_a < 0 || wb - bias_b < 0 || wc - bias_c < 0) continue;
            if (swapped)
                visit(static_cast<int>(i), static_cast<int>(j), wa, wc, wb, area);
            else
                visit(static_cast<int>(i), static_cast<int>(j), wa, wb, wc, area);
        }
    }
    return TriangleOutcome::rasterized;
}

// ---- Clipping in homogeneous space ----
//
// Clip space here is view space (x along R, y along U, z along F): the projection of SPEC §1 is
// x_clip = x / (tan_half * W/H), y_clip = -y / tan_half, w = z, an invertible linear map of
// view space, so a plane test and a linear interpolation give the same point in either space.
// Each vertex also carries the barycentrics (u, v) it has in the original triangle.
struct ClipVertex {
    glm::vec3 view{0.0f};
    glm::vec2 bary{0.0f};
};

/// Plane normal . view + offset >= 0 is inside.
struct ClipPlane {
    glm::vec3 normal{0.0f};
    float offset = 0.0f;
    bool is_near = false;
};

float plane_distance(const ClipPlane& plane, glm::vec3 view) {
    return plane.normal.x * view.x + plane.normal.y * view.y + plane.normal.z * view.z +
           plane.offset;
}

// A triangle gains at most one vertex per plane (3 + 5 = 8) while the clipped polygon is
// convex; float rounding can dent it very slightly, and a plane through a dent crosses it twice
// more, so the buffer has room for 16 and clip_polygon checks the bound.
constexpr int max_polygon_vertices = 16;
using Polygon = std::array<ClipVertex, max_polygon_vertices>;

/// Intersection of edge inside -> outside with the plane. Always parameterised from the
/// inside vertex, so an edge shared by two triangles gives the same point whichever way each
/// triangle walks it. New near-plane vertices get z = near exactly.
ClipVertex intersect(const ClipVertex& inside, float d_inside, const ClipVertex& outside,
                     float d_outside, const ClipPlane& plane, float near) {
    const float t = d_inside / (d_inside - d_outside);  // d_inside >= 0 > d_outside: t in [0, 1]
    ClipVertex r;
    r.view = inside.view + t * (outside.view - inside.view);
    r.bary = inside.bary + t * (outside.bary - inside.bary);
    if (plane.is_near) r.view.z = near;
    return r;
}

/// Sutherland-Hodgman against one plane; returns the new vertex count (0 = nothing left).
int clip_polygon(const Polygon& in, int count, const ClipPlane& plane, float near, Polygon& out) {
    int n = 0;
    for (int k = 0; k < count; ++k) {
        const ClipVertex& cur = in[static_cast<std::size_t>(k)];
        const ClipVertex& next = in[static_cast<std::size_t>((k + 1) % count)];
        const float d_cur = plane_distance(plane, cur.view);
        const float d_next = plane_distance(plane, next.view);
        FOVREF_CHECK(n + 2 <= max_polygon_vertices, "clipped polygon exceeds its vertex buffer");
        if (d_cur >= 0.0f) out[static_cast<std::size_t>(n++)] = cur;
        if (d_cur >= 0.0f && d_next < 0.0f)
            out[static_cast<std::size_t>(n++)] = intersect(cur, d_cur, next, d_next, plane, near);
        else if (d_cur < 0.0f && d_next >= 0.0f)
            out[static_cast<std::size_t>(n++)] = intersect(next, d_next, cur, d_cur, plane, near);
    }
    return n;
}

/// View coordinates within +-raster_max_view_coordinate (NaN fails), so that no plane distance
/// (coefficients up to ~1e12 for vfov near 180 degrees) overflows.
bool in_view_range(glm::vec3 view) {
    const float m = raster_max_view_coordinate;
    return std::fabs(view.x) <= m && std::fabs(view.y) <= m && std::fabs(view.z) <= m;
}

bool all_inside(const Polygon& poly, int count, const ClipPlane& plane) {
    for (int k = 0; k < count; ++k)
        if (!(plane_distance(plane, poly[static_cast<std::size_t>(k)].view) >= 0.0f)) return false;
    return true;
}

/// Near plane z >= near, then the guard band |screen x|, |screen y| <= G, written in view space:
/// screen x >= -G  <=>  x + (2G/W + 1) k z >= 0, screen x <= G  <=>  (2G/W - 1) k z - x >= 0,
/// screen y >= -G  <=>  (2G/H + 1) t z - y >= 0, screen y <= G  <=>  (2G/H - 1) t z + y >= 0,
/// with t = tan_half, k = t W/H (screen y grows along -U).
std::array<ClipPlane, 5> clip_planes(float near, float tan_half, int width, int height) {
    const float w = static_cast<float>(width), h = static_cast<float>(height);
    const float g = raster_guard_band_px;
    const float k = tan_half * (w / h), t = tan_half;
    return {{
        {{0.0f, 0.0f, 1.0f}, -near, true},
        {{1.0f, 0.0f, (2.0f * g / w + 1.0f) * k}, 0.0f, false},
        {{-1.0f, 0.0f, (2.0f * g / w - 1.0f) * k}, 0.0f, false},
        {{0.0f, -1.0f, (2.0f * g / h + 1.0f) * t}, 0.0f, false},
        {{0.0f, 1.0f, (2.0f * g / h - 1.0f) * t}, 0.0f, false},
    }};
}

void check_size(int width, int height) {
    if (width < 1 || height < 1 || width > raster_max_dimension || height > raster_max_dimension)
        throw Error("rasterizer: width and height must be in [1, " +
                    std::to_string(raster_max_dimension) + "], got " + std::to_string(width) +
                    " x " + std::to_string(height));
}

void check_camera(const Camera& camera, const char* name) {
    if (!(camera.vfov_deg > 0.0f && camera.vfov_deg < 180.0f))
        throw Error(std::string("rasterizer: ") + name + " vfov_deg must be in (0, 180), got " +
                    std::to_string(camera.vfov_deg));
    if (!is_finite(camera.position) || !is_finite(camera.right) || !is_finite(camera.up) ||
        !is_finite(camera.forward))
        throw Error(std::string("rasterizer: ") + name + " position and axes must be finite");
}

/// What surface_at indexes without checking (finalize_scene guarantees it for loaded scenes).
void check_scene(const Scene& scene) {
    const std::size_t n = scene.triangle_count();
    if (scene.positions.size() != 3 * n || scene.normals.size() != 3 * n ||
        scene.uvs.size() != 3 * n)
        throw Error("rasterizer: scene '" + scene.name +
                    "' has inconsistent per-corner arrays (finalize_scene checks them)");
    for (std::size_t t = 0; t < n; ++t) {
        const std::int32_t m = scene.material_ids[t];
        if (m < 0 || static_cast<std::size_t>(m) >= scene.materials.size())
            throw Error("rasterizer: scene '" + scene.name + "' triangle " + std::to_string(t) +
                        " has material index " + std::to_string(m) + " out of range");
    }
    for (const Material& material : scene.materials)
        if (material.texture < -1 ||
            (material.texture >= 0 &&
             static_cast<std::size_t>(material.texture) >= scene.textures.size()))
            throw Error("rasterizer: scene '" + scene.name + "' material '" + material.name +
                        "' has texture index " + std::to_string(material.texture) +
                        " out of range");
    for (const Texture& texture : scene.textures)
        if (texture.image.channels != 3 || texture.image.empty())
            throw Error("rasterizer: scene '" + scene.name + "' texture '" + texture.name +
                        "' is empty or not RGB");
}

}  // namespace

// ---- Building blocks ----

FixedPoint snap_to_fixed(glm::vec2 screen) {
    const float g = raster_guard_band_px;
    const float scale = static_cast<float>(raster_subpixel_scale);
    const float x = std::min(std::max(screen.x, -g), g);  // NaN-free inputs: clipping ran first
    const float y = std::min(std::max(screen.y, -g), g);
    // x * 256 is exact (power of two); std::round: halves away from zero.
    return {static_cast<std::int64_t>(std::round(x * scale)),
            static_cast<std::int64_t>(std::round(y * scale))};
}

glm::vec3 world_to_view(const Camera& camera, glm::vec3 p) {
    const glm::vec3 d = p - camera.position;
    return {glm::dot(d, camera.right), glm::dot(d, camera.up), glm::dot(d, camera.forward)};
}

glm::vec2 view_to_screen(glm::vec3 view, float tan_half, int width, int height) {
    // project_to_screen's operations, in its order (camera.cpp).
    const float w = static_cast<float>(width), h = static_cast<float>(height);
    const float sx = view.x / view.z;
    const float sy = -view.y / view.z;
    return {(sx / (tan_half * (w / h)) + 1.0f) * 0.5f * w, (sy / tan_half + 1.0f) * 0.5f * h};
}

std::int64_t rasterize_triangle_coverage(glm::vec2 a, glm::vec2 b, glm::vec2 c, Image& coverage) {
    FOVREF_CHECK(coverage.channels == 1, "coverage image must have 1 channel");
    std::int64_t tests = 0, covered = 0;
    rasterize_fixed_triangle(
        snap_to_fixed(a), snap_to_fixed(b), snap_to_fixed(c), coverage.width, coverage.height,
        tests, [&](int i, int j, std::int64_t, std::int64_t, std::int64_t, std::int64_t) {
            coverage.at(i, j) += 1.0f;
            ++covered;
        });
    return covered;
}

// ---- Visibility: clip, snap, cover, interpolate, depth test ----

VisibilityBuffer rasterize_visibility(const Scene& scene, const Camera& camera, int width,
                                      int height, RasterStats& stats) {
    check_size(width, height);
    check_camera(camera, "camera");
    check_scene(scene);
    VisibilityBuffer vis;
    vis.width = width;
    vis.height = height;
    const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    vis.primitive.assign(pixels, -1);
    vis.u.assign(pixels, 0.0f);
    vis.v.assign(pixels, 0.0f);
    vis.depth.assign(pixels, std::numeric_limits<float>::infinity());

    const float tan_half = tan_half_vfov(camera);
    const float near = std::max(raster_near_factor * scene.scene_scale, raster_min_near);
    const std::array<ClipPlane, 5> planes = clip_planes(near, tan_half, width, height);

    Polygon scratch;
    const std::size_t n = scene.triangle_count();
    stats.triangles_in += static_cast<std::int64_t>(n);
    for (std::size_t t = 0; t < n; ++t) {
        const std::int32_t primitive = static_cast<std::int32_t>(t);
        const glm::vec3 p0 = scene.positions[3 * t], p1 = scene.positions[3 * t + 1],
                        p2 = scene.positions[3 * t + 2];

        // World -> view space; the corners' barycentrics are (0,0), (1,0), (0,1).
        Polygon poly;
        poly[0] = {world_to_view(camera, p0), {0.0f, 0.0f}};
        poly[1] = {world_to_view(camera, p1), {1.0f, 0.0f}};
        poly[2] = {world_to_view(camera, p2), {0.0f, 1.0f}};
        int count = 3;
        if (!in_view_range(poly[0].view) || !in_view_range(poly[1].view) ||
            !in_view_range(poly[2].view)) {
            ++stats.triangles_out_of_range;
            continue;
        }

        // Clip: near plane first (so z > 0 afterwards), then the guard band; each plane only
        // when some vertex is outside it.
        bool near_clipped = false, guard_clipped = false, offscreen = false;
        for (std::size_t k = 0; k < planes.size(); ++k) {
            if (all_inside(poly, count, planes[k])) continue;
            count = clip_polygon(poly, count, planes[k], near, scratch);
            poly = scratch;
            (k == 0 ? near_clipped : guard_clipped) = true;
            if (count == 0) {
                offscreen = k != 0;
                break;
            }
        }
        if (count == 0) {
            if (offscreen)
                ++stats.triangles_culled_offscreen;
            else
                ++stats.triangles_clipped_away;
            continue;
        }
        if (near_clipped) ++stats.triangles_near_clipped;
        if (guard_clipped) ++stats.triangles_guard_clipped;

        // Project and snap; 1/w = 1/z for perspective-correct interpolation.
        std::array<FixedPoint, max_polygon_vertices> fixed{};
        std::array<float, max_polygon_vertices> inv_w{};
        for (int k = 0; k < count; ++k) {
            const ClipVertex& cv = poly[static_cast<std::size_t>(k)];
            fixed[static_cast<std::size_t>(k)] =
                snap_to_fixed(view_to_screen(cv.view, tan_half, width, height));
            inv_w[static_cast<std::size_t>(k)] = 1.0f / cv.view.z;
        }

        // Fan-triangulate the convex clipped polygon around vertex 0 (a triangle is one fan).
        bool any_nonzero_area = false, any_rasterized = false;
        for (int k = 1; k + 1 < count; ++k) {
            const std::size_t ia = 0, ib = static_cast<std::size_t>(k),
                              ic = static_cast<std::size_t>(k + 1);
            const TriangleOutcome outcome = rasterize_fixed_triangle(
                fixed[ia], fixed[ib], fixed[ic], width, height, stats.coverage_tests,
                [&](int i, int j, std::int64_t wa, std::int64_t wb, std::int64_t wc,
                    std::int64_t area) {
                    ++stats.fragments_tested;
                    // Screen-space barycentrics from the exact edge values, then the
                    // perspective-correct weights q_k = lambda_k / w_k, normalised.
                    const float area_f = static_cast<float>(area);
                    const float qa = (static_cast<float>(wa) / area_f) * inv_w[ia];
                    const float qb = (static_cast<float>(wb) / area_f) * inv_w[ib];
                    const float qc = (static_cast<float>(wc) / area_f) * inv_w[ic];
                    // sum > 0: the weights are >= 0 and sum to 1, 1/w > 0; guard anyway.
                    const float sum = std::max(qa + qb + qc, std::numeric_limits<float>::min());
                    const glm::vec2 ba = poly[ia].bary, bb = poly[ib].bary, bc = poly[ic].bary;
                    const float u = (qa * ba.x + qb * bb.x + qc * bc.x) / sum;
                    const float v = (qa * ba.y + qb * bb.y + qc * bc.y) / sum;
                    // World position exactly as surface_at computes it, then view depth.
                    const float w0 = 1.0f - u - v;
                    const glm::vec3 position = p0 * w0 + p1 * u + p2 * v;
                    const float depth = view_depth(camera, position);
                    // Depth test "less"; equal depth -> lower primitive id (SPEC §3, §4).
                    const std::size_t index =
                        static_cast<std::size_t>(j) * static_cast<std::size_t>(width) +
                        static_cast<std::size_t>(i);
                    const float stored = vis.depth[index];
                    if (depth < stored || (depth == stored && primitive < vis.primitive[index])) {
                        vis.depth[index] = depth;
                        vis.primitive[index] = primitive;
                        vis.u[index] = u;
                        vis.v[index] = v;
                        ++stats.fragments_written;
                    }
                });
            if (outcome != TriangleOutcome::degenerate) any_nonzero_area = true;
            if (outcome == TriangleOutcome::rasterized) any_rasterized = true;
        }
        if (any_rasterized)
            ++stats.triangles_rasterized;
        else if (any_nonzero_area)
            ++stats.triangles_culled_offscreen;
        else
            ++stats.triangles_degenerate;
    }
    return vis;
}

// ---- Resolve: attributes from the shared surface code ----

GBuffer resolve_gbuffer(const Scene& scene, const VisibilityBuffer& vis, const Camera& camera,
                        const Camera& previous_camera, RasterStats& stats) {
    check_size(vis.width, vis.height);
    check_camera(camera, "camera");
    check_camera(previous_camera, "previous_camera");
    check_scene(scene);
    const std::size_t pixels =
        static_cast<std::size_t>(vis.width) * static_cast<std::size_t>(vis.height);
    FOVREF_CHECK(vis.primitive.size() == pixels && vis.u.size() == pixels &&
                     vis.v.size() == pixels && vis.depth.size() == pixels,
                 "visibility buffer arrays must have width x height entries");
    GBuffer g(vis.width, vis.height);
    const float previous_tan_half = tan_half_vfov(previous_camera);
    for (int j = 0; j < vis.height; ++j) {
        for (int i = 0; i < vis.width; ++i) {
            const std::size_t index =
                static_cast<std::size_t>(j) * static_cast<std::size_t>(vis.width) +
                static_cast<std::size_t>(i);
            const std::int32_t primitive = vis.primitive[index];
            if (primitive < 0) continue;
            FOVREF_CHECK(
                static_cast<std::size_t>(primitive) < scene.triangle_count(),
                "visibility buffer primitive " + std::to_string(primitive) + " out of range");
            ++stats.pixels_covered;
            if (!write_gbuffer_pixel(g, i, j, scene, camera, previous_camera, previous_tan_half,
                                     primitive, vis.u[index], vis.v[index]))
                ++stats.motion_behind_previous;  // motion 0: no meaningful reprojection
        }
    }
    return g;
}

GBuffer rasterize_gbuffer(const Scene& scene, const Camera& camera, const Camera& previous_camera,
                          int width, int height, RasterStats& stats) {
    check_camera(previous_camera, "previous_camera");  // fail before the long pass
    const VisibilityBuffer vis = rasterize_visibility(scene, camera, width, height, stats);
    return resolve_gbuffer(scene, vis, camera, previous_camera, stats);
}

}  // namespace fovref
