#include "ref/raster/rasterizer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <utility>

#include "ref/bvh/watertight.h"
#include "ref/core/error.h"
#include "ref/core/vec.h"
#include "ref/raster/raster_avx.h"
#include "ref/scene/surface.h"

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
// <= 2^23 after the guard band, so |E| < 2^49). setup_edges orients the triangle clockwise on
// screen and turns the fill rule into per-edge biases; edge_values decides one pixel centre.
// `visit(i, j)` receives every covered pixel inside the screen, row by row.
template <class Visit>
TriangleOutcome rasterize_fixed_triangle(const EdgeSetup& e, int width, int height,
                                         std::int64_t& coverage_tests, Visit&& visit) {
    if (e.area == 0) return TriangleOutcome::degenerate;
    // Bounding box of the vertices -> range of pixel centres, clipped to the screen.
    const PixelRange cols =
        centres_in(std::min({e.a.x, e.b.x, e.c.x}), std::max({e.a.x, e.b.x, e.c.x}), width);
    const PixelRange rows =
        centres_in(std::min({e.a.y, e.b.y, e.c.y}), std::max({e.a.y, e.b.y, e.c.y}), height);
    if (cols.first > cols.last || rows.first > rows.last) return TriangleOutcome::offscreen;
    for (std::int64_t j = rows.first; j <= rows.last; ++j) {
        for (std::int64_t i = cols.first; i <= cols.last; ++i) {
            ++coverage_tests;
            if (edge_values(e, i, j).covered) visit(static_cast<int>(i), static_cast<int>(j));
        }
    }
    return TriangleOutcome::rasterized;
}

// ---- Clipping in homogeneous space ----
//
// Clip space here is view space (x along R, y along U, z along F): the projection of SPEC §1 is
// x_clip = x / (tan_half * W/H), y_clip = -y / tan_half, w = z, an invertible linear map of
// view space, so a plane test and a linear interpolation give the same point in either space.
// Clipping only decides coverage: attributes come from the original triangle's plane.
struct ClipVertex {
    glm::vec3 view{0.0f};
};

float plane_distance(const ClipPlane& plane, glm::vec3 view) {
    return plane.normal.x * view.x + plane.normal.y * view.y + plane.normal.z * view.z +
           plane.offset;
}

constexpr int max_polygon_vertices = raster_max_polygon_vertices;
using Polygon = std::array<ClipVertex, max_polygon_vertices>;

/// Intersection of edge inside -> outside with the plane. Always parameterised from the
/// inside vertex, so an edge shared by two triangles gives the same point whichever way each
/// triangle walks it. New near-plane vertices get z = near exactly.
ClipVertex intersect(const ClipVertex& inside, float d_inside, const ClipVertex& outside,
                     float d_outside, const ClipPlane& plane, float near) {
    const float t = d_inside / (d_inside - d_outside);  // d_inside >= 0 > d_outside: t in [0, 1]
    ClipVertex r;
    r.view = inside.view + t * (outside.view - inside.view);
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

}  // namespace

/// Near plane z >= near, then the guard band |screen x|, |screen y| <= G, written in view space:
/// screen x >= -G  <=>  x + (2G/W + 1) k z >= 0, screen x <= G  <=>  (2G/W - 1) k z - x >= 0,
/// screen y >= -G  <=>  (2G/H + 1) t z - y >= 0, screen y <= G  <=>  (2G/H - 1) t z + y >= 0,
/// with t = tan_half, k = t W/H (screen y grows along -U).
std::array<ClipPlane, 5> raster_clip_planes(float near, float tan_half, int width, int height) {
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

namespace {

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

const char* fill_rule_name(FillRule rule) { return rule == FillRule::d3d ? "d3d" : "gl"; }

FillRule parse_fill_rule(const std::string& text, const std::string& what) {
    if (text == "d3d") return FillRule::d3d;
    if (text == "gl") return FillRule::gl;
    throw Error(what + ": '" + text +
                "' is neither 'd3d' (Direct3D/Vulkan top-left) nor 'gl' (OpenGL, bottom-left in "
                "fovref's y-down frame)");
}

FixedPoint snap_to_fixed(glm::vec2 screen) {
    const float g = raster_guard_band_px;
    const float scale = static_cast<float>(raster_subpixel_scale);
    const float x = std::min(std::max(screen.x, -g), g);  // NaN-free inputs: clipping ran first
    const float y = std::min(std::max(screen.y, -g), g);
    // x * 256 is exact (power of two), and rounded with halves away from zero (std::round):
    // |x * 256| <= 2^23, so the truncation t and the fraction v - t are exact, and the result is
    // t, moved one away from zero when |v - t| >= 1/2.
    const auto round_away = [](float v) {
        const auto t = static_cast<std::int64_t>(v);
        const float f = v - static_cast<float>(t);
        return t + static_cast<std::int64_t>(f >= 0.5f) - static_cast<std::int64_t>(f <= -0.5f);
    };
    return {round_away(x * scale), round_away(y * scale)};
}

EdgeSetup setup_edges(FixedPoint a, FixedPoint b, FixedPoint c, FillRule rule) {
    EdgeSetup e;
    std::int64_t area = edge_function(a, b, c);
    if (area < 0) {
        std::swap(b, c);
        area = -area;
        e.swapped = true;
    }
    e.a = a;
    e.b = b;
    e.c = c;
    e.area = area;
    e.bias_a = edge_owns_centres(rule, b, c) ? 0 : 1;  // edge opposite a
    e.bias_b = edge_owns_centres(rule, c, a) ? 0 : 1;
    e.bias_c = edge_owns_centres(rule, a, b) ? 0 : 1;
    return e;
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

std::int64_t rasterize_triangle_coverage(glm::vec2 a, glm::vec2 b, glm::vec2 c, Image& coverage,
                                         FillRule rule) {
    FOVREF_CHECK_EQ(coverage.channels, 1, "channels of the coverage image");
    std::int64_t tests = 0, covered = 0;
    const EdgeSetup e = setup_edges(snap_to_fixed(a), snap_to_fixed(b), snap_to_fixed(c), rule);
    rasterize_fixed_triangle(e, coverage.width, coverage.height, tests, [&](int i, int j) {
        coverage.at(i, j) += 1.0f;
        ++covered;
    });
    return covered;
}

FixedPoint raster_sample_shift(Offset2 sample) {
    const auto grid = [](float s) {
        const float d = (s - 0.5f) * static_cast<float>(raster_subpixel_scale);
        return static_cast<std::int64_t>(d < 0.0f ? -std::floor(0.5f - d) : std::floor(d + 0.5f));
    };
    FOVREF_CHECK(sample.x >= 0.0f && sample.x <= 1.0f && sample.y >= 0.0f && sample.y <= 1.0f,
                 "rasterizer sample position outside its pixel");
    return {grid(sample.x), grid(sample.y)};
}

RasterFrame make_raster_frame(const Scene& scene, const Camera& camera, int width, int height,
                              const RasterSettings& settings) {
    check_size(width, height);
    check_camera(camera, "camera");
    RasterFrame f;
    f.camera = camera;
    f.width = width;
    f.height = height;
    f.tan_half = tan_half_vfov(camera);
    f.near = std::max(raster_near_factor * scene.scene_scale, raster_min_near);
    f.settings = settings;
    f.sample_shift = raster_sample_shift(settings.sample);
    f.clip_planes = raster_clip_planes(f.near, f.tan_half, width, height);
    return f;
}

// ---- Per triangle: view transform, clipping, projection, snapping ----

void setup_triangle(const Scene& scene, const RasterFrame& frame, std::int32_t primitive,
                    TriangleSetup& setup) {
    const auto t = static_cast<std::size_t>(primitive);
    setup.status = TriangleSetup::Status::ready;
    setup.near_clipped = setup.guard_clipped = false;
    setup.count = 0;
    const glm::vec3 view[3] = {world_to_view(frame.camera, scene.positions[3 * t]),
                               world_to_view(frame.camera, scene.positions[3 * t + 1]),
                               world_to_view(frame.camera, scene.positions[3 * t + 2])};
    if (!in_view_range(view[0]) || !in_view_range(view[1]) || !in_view_range(view[2])) {
        setup.status = TriangleSetup::Status::out_of_range;
        return;
    }

    // Clip: near plane first (so z > 0 afterwards), then the guard band; each plane only when
    // some vertex is outside it. Most triangles are inside every plane and keep their three
    // corners (the polygon buffers, made only for the others, are then not filled).
    const std::array<ClipPlane, 5>& planes = frame.clip_planes;
    std::size_t first_cut = 0;
    while (first_cut < planes.size() && plane_distance(planes[first_cut], view[0]) >= 0.0f &&
           plane_distance(planes[first_cut], view[1]) >= 0.0f &&
           plane_distance(planes[first_cut], view[2]) >= 0.0f)
        ++first_cut;
    const FixedPoint shift = frame.sample_shift;
    const auto project = [&](int k, glm::vec3 v) {
        FixedPoint& p = setup.polygon[static_cast<std::size_t>(k)];
        p = snap_to_fixed(view_to_screen(v, frame.tan_half, frame.width, frame.height));
        p.x -= shift.x;
        p.y -= shift.y;
    };
    if (first_cut == planes.size()) {
        setup.count = 3;
        for (int k = 0; k < 3; ++k) project(k, view[k]);
        return;
    }
    Polygon poly, scratch;
    for (int k = 0; k < 3; ++k) poly[static_cast<std::size_t>(k)] = {view[k]};
    int count = 3;
    for (std::size_t k = first_cut; k < planes.size(); ++k) {
        if (all_inside(poly, count, planes[k])) continue;
        count = clip_polygon(poly, count, planes[k], frame.near, scratch);
        poly = scratch;
        (k == 0 ? setup.near_clipped : setup.guard_clipped) = true;
        if (count == 0) {
            setup.status =
                k == 0 ? TriangleSetup::Status::clipped_away : TriangleSetup::Status::offscreen;
            return;
        }
    }

    // Project and snap; a jittered sample moves the triangle the other way (so the pixel centres
    // sample where the jittered samples lie)
    setup.count = count;
    for (int k = 0; k < count; ++k) project(k, poly[static_cast<std::size_t>(k)].view);
}

TriangleSetup setup_triangle(const Scene& scene, const RasterFrame& frame, std::int32_t primitive) {
    TriangleSetup setup;
    setup_triangle(scene, frame, primitive, setup);
    return setup;
}

// ---- Per pixel: the attribute point and the depth test ----

bool raster_fragment(const Scene& scene, const RasterFrame& frame, int x, int y,
                     std::int32_t primitive, RasterFragment& fragment) {
    // The pixel's primary ray, exactly as the ray caster builds it (raycast_gbuffer.h,
    // bvh_traverse.cpp: t in (0, inf), the watertight per-ray setup).
    const FixedPoint shift = frame.sample_shift;
    const glm::vec2 centre =
        pixel_centre(x, y) + glm::vec2(static_cast<float>(shift.x), static_cast<float>(shift.y)) /
                                 static_cast<float>(raster_subpixel_scale);
    const glm::vec3 direction = primary_ray_direction(frame.camera, frame.tan_half, frame.width,
                                                      frame.height, centre.x, centre.y);
    const WatertightRay ray = make_watertight_ray(frame.camera.position, direction, 0.0f,
                                                  std::numeric_limits<float>::max());
    const auto t = static_cast<std::size_t>(primitive);
    const glm::vec3 p0 = scene.positions[3 * t], p1 = scene.positions[3 * t + 1],
                    p2 = scene.positions[3 * t + 2];
    float hit_t = 0.0f, u = 0.0f, v = 0.0f;
    if (!intersect_watertight_plane(ray, p0, p1, p2, hit_t, u, v)) return false;
    if (!(hit_t > 0.0f) || !std::isfinite(hit_t) || !std::isfinite(u) || !std::isfinite(v))
        return false;
    // World position exactly as surface_at computes it, then its view depth.
    const float w0 = 1.0f - u - v;
    const glm::vec3 position = p0 * w0 + p1 * u + p2 * v;
    fragment.primitive = primitive;
    fragment.t = hit_t;
    fragment.u = u;
    fragment.v = v;
    fragment.depth = view_depth(frame.camera, position);
    return true;
}

bool depth_test(VisibilityBuffer& vis, int x, int y, const RasterFragment& f) {
    const std::size_t index = static_cast<std::size_t>(y) * static_cast<std::size_t>(vis.width) +
                              static_cast<std::size_t>(x);
    const float stored = vis.depth[index];
    if (!(f.depth < stored || (f.depth == stored && f.primitive < vis.primitive[index])))
        return false;
    vis.depth[index] = f.depth;
    vis.primitive[index] = f.primitive;
    vis.u[index] = f.u;
    vis.v[index] = f.v;
    return true;
}

// ---- Visibility: every triangle, every covered pixel ----

void rasterize_fragment(const Scene& scene, const RasterFrame& frame, std::int32_t primitive, int x,
                        int y, VisibilityBuffer& visibility, RasterStats& stats) {
    ++stats.fragments_tested;
    RasterFragment fragment;
    if (!raster_fragment(scene, frame, x, y, primitive, fragment)) {
        ++stats.fragments_without_plane_hit;
        return;
    }
    if (depth_test(visibility, x, y, fragment)) ++stats.fragments_written;
}

namespace {

/// The visibility pass's fragments (covered pixel centres) on their way to the depth test: with
/// AVX eight at a time through raster_fragments_avx (the same bits as raster_fragment), their
/// depth tests then run in the order the fragments came, as they would one by one; without it,
/// rasterize_fragment each.
struct FragmentBatch {
    const Scene& scene;
    const RasterFrame& frame;
    VisibilityBuffer& vis;
    RasterStats& stats;
    bool avx = raster_fragments_avx_applies();
    RasterSite site[8];
    int count = 0;

    FragmentBatch(const Scene& s, const RasterFrame& f, VisibilityBuffer& v, RasterStats& st)
        : scene(s), frame(f), vis(v), stats(st) {}

    void add(int x, int y, std::int32_t primitive) {
        if (!avx) {
            rasterize_fragment(scene, frame, primitive, x, y, vis, stats);
            return;
        }
        site[count++] = {x, y, primitive};
        if (count == 8) flush();
    }
    void flush() {
        if (count == 0) return;
        RasterFragment fragment[8];
        bool hit[8];
        raster_fragments_avx(scene, frame, site, count, fragment, hit);
        for (int l = 0; l < count; ++l) {
            ++stats.fragments_tested;
            if (!hit[l])
                ++stats.fragments_without_plane_hit;
            else if (depth_test(vis, site[l].x, site[l].y, fragment[l]))
                ++stats.fragments_written;
        }
        count = 0;
    }
};

/// A visibility buffer of background: primitive -1, depth +inf.
VisibilityBuffer background_visibility(int width, int height) {
    VisibilityBuffer vis;
    vis.width = width;
    vis.height = height;
    const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    vis.primitive.assign(pixels, -1);
    vis.u.assign(pixels, 0.0f);
    vis.v.assign(pixels, 0.0f);
    vis.depth.assign(pixels, std::numeric_limits<float>::infinity());
    return vis;
}

}  // namespace

VisibilityBuffer rasterize_visibility(const Scene& scene, const Camera& camera, int width,
                                      int height, RasterStats& stats,
                                      const RasterSettings& settings) {
    const RasterFrame frame = make_raster_frame(scene, camera, width, height, settings);
    check_scene(scene);
    VisibilityBuffer vis = background_visibility(width, height);
    FragmentBatch batch(scene, frame, vis, stats);
    const std::size_t n = scene.triangle_count();
    stats.triangles_in += static_cast<std::int64_t>(n);
    // Set up eight triangles at a time where setup_triangles_avx applies (the others of the
    // eight: setup_triangle); the setups are kept for all triangles (their polygon buffers are
    // not cleared each time).
    TriangleSetup setups[8];
    bool done[8] = {false, false, false, false, false, false, false, false};
    for (std::size_t t = 0; t < n; ++t) {
        const auto primitive = static_cast<std::int32_t>(t);
        const std::size_t lane = t % 8;
        if (lane == 0 && batch.avx)
            setup_triangles_avx(scene, frame, primitive,
                                static_cast<int>(std::min<std::size_t>(8, n - t)), setups, done);
        TriangleSetup& setup = setups[lane];
        if (!done[lane]) setup_triangle(scene, frame, primitive, setup);
        switch (setup.status) {
            case TriangleSetup::Status::out_of_range: ++stats.triangles_out_of_range; continue;
            case TriangleSetup::Status::clipped_away: ++stats.triangles_clipped_away; continue;
            case TriangleSetup::Status::offscreen: ++stats.triangles_culled_offscreen; continue;
            case TriangleSetup::Status::ready: break;
        }
        if (setup.near_clipped) ++stats.triangles_near_clipped;
        if (setup.guard_clipped) ++stats.triangles_guard_clipped;

        // The fan of the convex clipped polygon around vertex 0 (a triangle is one fan).
        bool any_nonzero_area = false, any_rasterized = false;
        for (int k = 1; k + 1 < setup.count; ++k) {
            const EdgeSetup edges =
                setup_edges(setup.polygon[0], setup.polygon[static_cast<std::size_t>(k)],
                            setup.polygon[static_cast<std::size_t>(k + 1)], settings.fill_rule);
            const TriangleOutcome outcome =
                rasterize_fixed_triangle(edges, width, height, stats.coverage_tests,
                                         [&](int x, int y) { batch.add(x, y, primitive); });
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
    batch.flush();
    return vis;
}

RasterPixelExplanation explain_raster_pixel(const Scene& scene, const Camera& camera, int width,
                                            int height, const RasterSettings& settings, int x,
                                            int y) {
    const RasterFrame frame = make_raster_frame(scene, camera, width, height, settings);
    check_scene(scene);
    FOVREF_CHECK(x >= 0 && y >= 0 && x < width && y < height, "pixel outside the screen");
    RasterPixelExplanation out;
    out.fill_rule = settings.fill_rule;
    out.centre = pixel_centre_fixed(x, y);
    // A one-pixel visibility buffer replays the depth tests in the pass's order.
    VisibilityBuffer one;
    one.width = 1;
    one.height = 1;
    one.primitive = {-1};
    one.u = {0.0f};
    one.v = {0.0f};
    one.depth = {std::numeric_limits<float>::infinity()};
    for (std::size_t t = 0; t < scene.triangle_count(); ++t) {
        const auto primitive = static_cast<std::int32_t>(t);
        const TriangleSetup setup = setup_triangle(scene, frame, primitive);
        if (setup.status != TriangleSetup::Status::ready) continue;
        for (int k = 1; k + 1 < setup.count; ++k) {
            const EdgeSetup e =
                setup_edges(setup.polygon[0], setup.polygon[static_cast<std::size_t>(k)],
                            setup.polygon[static_cast<std::size_t>(k + 1)], settings.fill_rule);
            if (e.area == 0) continue;
            const EdgeValues values = edge_values(e, x, y);
            if (!values.covered) continue;
            RasterCandidate c;
            c.primitive = primitive;
            c.fan_triangle = k - 1;
            c.near_clipped = setup.near_clipped;
            c.guard_clipped = setup.guard_clipped;
            c.a = e.a;
            c.b = e.b;
            c.c = e.c;
            c.edges = values;
            c.area = e.area;
            c.owns[0] = e.bias_a == 0;
            c.owns[1] = e.bias_b == 0;
            c.owns[2] = e.bias_c == 0;
            c.fragment = raster_fragment(scene, frame, x, y, primitive, c.value);
            c.stored_depth = one.depth[0];
            c.stored_primitive = one.primitive[0];
            if (c.fragment) c.won_depth_test = depth_test(one, 0, 0, c.value);
            out.candidates.push_back(c);
        }
    }
    out.winner = one.primitive[0];
    return out;
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
    const char* const entries = "visibility buffer arrays have width x height entries";
    FOVREF_CHECK_EQ(vis.primitive.size(), pixels, entries);
    FOVREF_CHECK_EQ(vis.u.size(), pixels, entries);
    FOVREF_CHECK_EQ(vis.v.size(), pixels, entries);
    FOVREF_CHECK_EQ(vis.depth.size(), pixels, entries);
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

bool rasterized_site(const Scene& scene, float primitive_id, int sx, int sy, RasterSite& site) {
    // An id that names no triangle (background, or a buffer altered upstream) has none.
    if (!(primitive_id >= 0.0f && primitive_id < static_cast<float>(scene.triangle_count())) ||
        primitive_id != std::floor(primitive_id))
        return false;
    site = {sx, sy, static_cast<std::int32_t>(primitive_id)};
    return true;
}

void write_rasterized_fragment(GBuffer& g, int x, int y, const Scene& scene,
                               const RasterFrame& frame, const Camera& previous_camera,
                               float previous_tan_half, const RasterSite& site,
                               const RasterFragment& fragment) {
    write_gbuffer_sample(g, x, y, pixel_centre(site.x, site.y), frame.width, frame.height, scene,
                         frame.camera, previous_camera, previous_tan_half, site.primitive,
                         fragment.u, fragment.v);
}

bool write_rasterized_pixel(GBuffer& g, int x, int y, const Scene& scene, const RasterFrame& frame,
                            const Camera& previous_camera, float previous_tan_half,
                            float primitive_id, int sx, int sy) {
    RasterSite site;
    RasterFragment fragment;
    if (!rasterized_site(scene, primitive_id, sx, sy, site) ||
        !raster_fragment(scene, frame, sx, sy, site.primitive, fragment))
        return false;
    write_rasterized_fragment(g, x, y, scene, frame, previous_camera, previous_tan_half, site,
                              fragment);
    return true;
}

Image visibility_primitive_ids(const VisibilityBuffer& vis) {
    Image ids(vis.width, vis.height, 1, -1.0f);
    for (std::size_t k = 0; k < vis.primitive.size(); ++k)
        if (vis.primitive[k] >= 0) ids.data[k] = static_cast<float>(vis.primitive[k]);
    return ids;
}

Image visibility_view_depth(const VisibilityBuffer& vis) {
    Image depth(vis.width, vis.height, 1, 0.0f);
    for (std::size_t k = 0; k < vis.primitive.size(); ++k)
        if (vis.primitive[k] >= 0) depth.data[k] = vis.depth[k];
    return depth;
}

GBuffer rasterize_gbuffer(const Scene& scene, const Camera& camera, const Camera& previous_camera,
                          int width, int height, RasterStats& stats,
                          const RasterSettings& settings) {
    check_camera(previous_camera, "previous_camera");  // fail before the long pass
    const VisibilityBuffer vis =
        rasterize_visibility(scene, camera, width, height, stats, settings);
    return resolve_gbuffer(scene, vis, camera, previous_camera, stats);
}

}  // namespace fovref
