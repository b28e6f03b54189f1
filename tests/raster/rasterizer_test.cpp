// Software rasterizer (SPEC §4): the fill rule on hand-checked and randomised cases, the
// projection against project_to_screen, clipping (near plane, guard band), the depth test and
// its tie-break, perspective-correct interpolation against analytic ray-plane intersections,
// motion vectors, statistics, determinism, and every procedural scene (smoke test plus a
// cross-check against a brute-force binary64 ray caster on the smaller ones).
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "ref/core/error.h"
#include "ref/core/rng.h"
#include "ref/core/simd.h"
#include "ref/raster/raster_avx.h"
#include "ref/raster/rasterizer.h"
#include "ref/scene/procedural.h"
#include "ref/scene/surface.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

namespace {

// ---- Helpers ----

/// Every channel of the two G-buffers, bit for bit.
void check_same_gbuffer(const GBuffer& a, const GBuffer& b) {
    CHECK(bit_equal(a.view_depth, b.view_depth));
    CHECK(bit_equal(a.hit_distance, b.hit_distance));
    CHECK(bit_equal(a.world_position, b.world_position));
    CHECK(bit_equal(a.shading_normal, b.shading_normal));
    CHECK(bit_equal(a.geometric_normal, b.geometric_normal));
    CHECK(bit_equal(a.albedo, b.albedo));
    CHECK(bit_equal(a.material_id, b.material_id));
    CHECK(bit_equal(a.primitive_id, b.primitive_id));
    CHECK(bit_equal(a.motion, b.motion));
}

using Tri = std::array<glm::vec3, 3>;

/// A scene of the given triangles, material k for triangle k (unless `materials` is 1), flat
/// normals, uvs (0,0), (1,0), (0,1) unless given.
Scene make_scene(const std::vector<Tri>& triangles, int materials = 1,
                 const std::vector<std::array<glm::vec2, 3>>& uvs = {}) {
    Scene scene;
    scene.name = "test";
    scene.source = "test";
    for (int m = 0; m < materials; ++m)
        scene.materials.push_back(
            Material{"m" + std::to_string(m), glm::vec3(0.1f * static_cast<float>(m + 1))});
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const Tri& tri = triangles[t];
        glm::vec3 n = glm::cross(tri[1] - tri[0], tri[2] - tri[0]);
        n /= glm::length(n);
        for (int k = 0; k < 3; ++k) {
            scene.positions.push_back(tri[k]);
            scene.normals.push_back(n);
            scene.uvs.push_back(
                uvs.empty()
                    ? std::array<glm::vec2, 3>{glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(0, 1)}[k]
                    : uvs[t][k]);
        }
        scene.material_ids.push_back(materials == 1 ? 0 : static_cast<std::int32_t>(t));
    }
    finalize_scene(scene);
    return scene;
}

/// The near plane is 1e-4 x scene_scale (docs/raster.md); scenes with far-away test geometry set
/// the scale back to 1 m so that the near plane stays at 0.1 mm.
Scene with_unit_scale(Scene scene) {
    scene.scene_scale = 1.0f;
    return scene;
}

/// Camera at the origin looking down -z, up +y: view (x, y, z) = world (x, y, -z).
Camera straight_camera(float vfov = 60.0f) {
    return look_at({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, vfov);
}

std::string show(glm::vec2 v) {
    std::ostringstream out;
    out.precision(9);
    out << "(" << v.x << ", " << v.y << ")";
    return out.str();
}

/// Pixels where the coverage count is not `expected`, as text (for failure messages).
std::string coverage_diff(const Image& coverage, const Image& expected) {
    std::ostringstream out;
    int shown = 0;
    for (int j = 0; j < coverage.height; ++j)
        for (int i = 0; i < coverage.width; ++i)
            if (coverage.at(i, j) != expected.at(i, j) && shown++ < 8)
                out << " (" << i << "," << j << "): got " << coverage.at(i, j) << " expected "
                    << expected.at(i, j);
    return out.str();
}

Image coverage_of(const std::vector<std::array<glm::vec2, 3>>& triangles, int w, int h,
                  FillRule rule = FillRule::d3d) {
    Image coverage(w, h, 1, 0.0f);
    for (const auto& t : triangles) rasterize_triangle_coverage(t[0], t[1], t[2], coverage, rule);
    return coverage;
}

const FillRule both_rules[] = {FillRule::d3d, FillRule::gl};

/// Binary64 primary ray through screen point (x, y) (SPEC §1, not normalised), with the
/// camera's float tan_half so the reference and the rasterizer see the same camera.
glm::dvec3 ray_direction_d(const Camera& camera, int w, int h, double x, double y) {
    const double t = tan_half_vfov(camera);
    const double sx = (2.0 * x / w - 1.0) * t * (static_cast<double>(w) / h);
    const double sy = (2.0 * y / h - 1.0) * t;
    return glm::dvec3(camera.forward) + sx * glm::dvec3(camera.right) - sy * glm::dvec3(camera.up);
}

/// Binary64 projection of p (the inverse of ray_direction_d).
glm::dvec2 project_d(const Camera& camera, int w, int h, glm::dvec3 p) {
    const glm::dvec3 d = p - glm::dvec3(camera.position);
    const double z = glm::dot(d, glm::dvec3(camera.forward));
    const double t = tan_half_vfov(camera);
    const double sx = glm::dot(d, glm::dvec3(camera.right)) / z;
    const double sy = -glm::dot(d, glm::dvec3(camera.up)) / z;
    return {(sx / (t * (static_cast<double>(w) / h)) + 1.0) * 0.5 * w, (sy / t + 1.0) * 0.5 * h};
}

/// Binary64 Moller-Trumbore: t (> 0) and barycentrics (b1, b2) of the ray o + t d, or t < 0.
struct HitD {
    double t = -1.0, b1 = 0.0, b2 = 0.0;
};
HitD intersect_d(glm::dvec3 o, glm::dvec3 d, glm::dvec3 p0, glm::dvec3 p1, glm::dvec3 p2) {
    const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0, pv = glm::cross(d, e2);
    const double det = glm::dot(e1, pv);
    HitD hit;
    if (det == 0.0) return hit;
    const glm::dvec3 tv = o - p0;
    const double b1 = glm::dot(tv, pv) / det;
    const glm::dvec3 qv = glm::cross(tv, e1);
    const double b2 = glm::dot(d, qv) / det;
    const double t = glm::dot(e2, qv) / det;
    if (b1 < 0.0 || b2 < 0.0 || b1 + b2 > 1.0 || !(t > 0.0)) return hit;
    return {t, b1, b2};
}

/// Closest primitive along the ray (binary64 brute force; ties to the lower index), -1 = miss.
int closest_d(const Scene& scene, glm::dvec3 o, glm::dvec3 d) {
    int best = -1;
    double best_t = INFINITY;
    for (std::size_t t = 0; t < scene.triangle_count(); ++t) {
        const HitD hit = intersect_d(o, d, glm::dvec3(scene.positions[3 * t]),
                                     glm::dvec3(scene.positions[3 * t + 1]),
                                     glm::dvec3(scene.positions[3 * t + 2]));
        if (hit.t > 0.0 && hit.t < best_t) {
            best_t = hit.t;
            best = static_cast<int>(t);
        }
    }
    return best;
}

std::int64_t exclusive_categories(const RasterStats& s) {
    return s.triangles_out_of_range + s.triangles_clipped_away + s.triangles_degenerate +
           s.triangles_culled_offscreen + s.triangles_rasterized;
}

}  // namespace

// ---- Projection ----

TEST_CASE("raster: view_to_screen(world_to_view(p)) equals project_to_screen bit for bit") {
    const Camera camera = look_at({0.3f, 1.2f, 4.0f}, {-0.2f, 0.7f, 0.0f}, {0, 1, 0}, 47.0f);
    const float tan_half = tan_half_vfov(camera);
    int tested = 0;
    for (std::uint32_t k = 0; k < 200; ++k) {
        const glm::vec3 p(rand_unit(1, k, 0) * 8.0f - 4.0f, rand_unit(1, k, 1) * 8.0f - 4.0f,
                          rand_unit(1, k, 2) * 8.0f - 6.0f);
        glm::vec2 expected;
        float depth = 0.0f;
        if (!project_to_screen(camera, tan_half, 160, 90, p, expected, depth)) continue;
        const glm::vec3 view = world_to_view(camera, p);
        CHECK(view.z == depth);
        const glm::vec2 got = view_to_screen(view, tan_half, 160, 90);
        CHECK_MESSAGE(got == expected, show(got) << " vs " << show(expected));
        ++tested;
    }
    CHECK(tested > 100);
}

TEST_CASE("raster: snapping to 1/256 px, guard-band clamp, halves away from zero") {
    CHECK(snap_to_fixed({0.5f, 2.0f}) == FixedPoint{128, 512});
    CHECK(snap_to_fixed({-0.5f, 0.0f}) == FixedPoint{-128, 0});
    // 1/512 is exactly half a step: std::round takes it away from zero.
    CHECK(snap_to_fixed({1.0f / 512.0f, -1.0f / 512.0f}) == FixedPoint{1, -1});
    CHECK(snap_to_fixed({1e9f, -1e9f}) == FixedPoint{32768 * 256, -32768 * 256});
    // Against std::round of the clamped value x 256 (snap_to_fixed rounds by truncation and the
    // exact fraction): every half step, the floats just below and above it, and random points of
    // the guard band.
    const auto reference = [](float v) {
        return static_cast<std::int64_t>(std::round(
            std::min(std::max(v, -raster_guard_band_px), raster_guard_band_px) * 256.0f));
    };
    test::SplitMix64 rng(5);
    std::int64_t checked = 0;
    for (int k = -20000; k <= 20000; ++k) {
        const float half = (static_cast<float>(k) + 0.5f) / 256.0f;
        for (const float v : {half, std::nextafter(half, -1e9f), std::nextafter(half, 1e9f),
                              static_cast<float>(k) * 128.0f / 256.0f + 0.25f / 256.0f}) {
            const FixedPoint p = snap_to_fixed({v, -v});
            REQUIRE(p.x == reference(v));
            REQUIRE(p.y == reference(-v));
            ++checked;
        }
    }
    for (int k = 0; k < 200000; ++k) {
        const float v = (static_cast<float>(rng.next() % 2000001) - 1000000.0f) * 0.0345f;
        REQUIRE(snap_to_fixed({v, 0.0f}).x == reference(v));
        ++checked;
    }
    CHECK(checked > 300000);
}

// ---- Fill rule ----

TEST_CASE("raster: fill rule on triangles whose edges pass through pixel centres") {
    // Each case is checked by hand: vertices at pixel centres, 8 x 8 screen. A centre on an
    // edge is covered only on a left edge, and on a top edge (horizontal, triangle below) under
    // d3d or a bottom edge (horizontal, triangle above) under gl: OpenGL's top-left rule in its
    // y-up window seen in fovref's y-down frame.
    struct Case {
        const char* name;
        std::array<glm::vec2, 3> v;
        bool (*inside_d3d)(int i, int j);
        int count_d3d;
        bool (*inside_gl)(int i, int j);
        int count_gl;
    };
    const Case cases[] = {
        // Top edge y = 0.5 (d3d only) and left edge x = 0.5 are in; hypotenuse i + j = 4
        // (right) is out.
        {"upper-left",
         {{{0.5f, 0.5f}, {4.5f, 0.5f}, {0.5f, 4.5f}}},
         [](int i, int j) { return i + j <= 3; },
         10,
         [](int i, int j) { return i + j <= 3 && j >= 1; },
         6},
        // Top edge (d3d only); hypotenuse j = i is a left edge (in); right edge x = 4.5 out.
        {"upper-right",
         {{{0.5f, 0.5f}, {4.5f, 0.5f}, {4.5f, 4.5f}}},
         [](int i, int j) { return j <= i && i <= 3; },
         10,
         [](int i, int j) { return j <= i && i <= 3 && j >= 1; },
         6},
        // Left edge in; hypotenuse j = i is a right edge (out); bottom edge y = 4.5 (gl only).
        {"lower-left",
         {{{0.5f, 0.5f}, {4.5f, 4.5f}, {0.5f, 4.5f}}},
         [](int i, int j) { return i < j && j <= 3; },
         6,
         [](int i, int j) { return i < j && j <= 4; },
         10},
        // Right edge x = 4.5 out, bottom edge y = 4.5 (gl only); hypotenuse i + j = 4 is a left
        // edge (in).
        {"lower-right",
         {{{4.5f, 0.5f}, {4.5f, 4.5f}, {0.5f, 4.5f}}},
         [](int i, int j) { return i + j >= 4 && i <= 3 && j <= 3; },
         6,
         [](int i, int j) { return i + j >= 4 && i <= 3 && j <= 4; },
         10},
    };
    for (const Case& c : cases) {
        for (const FillRule rule : both_rules) {
            for (bool reversed : {false, true}) {
                const std::string name = c.name;
                CAPTURE(name);
                CAPTURE(std::string(fill_rule_name(rule)));
                CAPTURE(reversed);
                const auto v = reversed ? std::array<glm::vec2, 3>{c.v[0], c.v[2], c.v[1]} : c.v;
                Image coverage(8, 8, 1, 0.0f), expected(8, 8, 1, 0.0f);
                const std::int64_t covered =
                    rasterize_triangle_coverage(v[0], v[1], v[2], coverage, rule);
                const auto inside = rule == FillRule::d3d ? c.inside_d3d : c.inside_gl;
                for (int j = 0; j < 8; ++j)
                    for (int i = 0; i < 8; ++i) expected.at(i, j) = inside(i, j) ? 1.0f : 0.0f;
                CHECK(covered == (rule == FillRule::d3d ? c.count_d3d : c.count_gl));
                CHECK_MESSAGE(coverage == expected, coverage_diff(coverage, expected));
            }
        }
    }
}

TEST_CASE("raster: gl coverage is d3d coverage in the y-flipped (OpenGL window) frame") {
    // OpenGL applies the top-left rule in its y-up window, y_gl = H - y. With vertices on the
    // 1/256 grid (snapping exact, flipping exact) and H an integer, pixel centres map to pixel
    // centres: gl coverage of T must equal the row-flipped d3d coverage of the flipped T.
    // Half of the cases on the half-pixel grid with a horizontal edge, where centres lie on
    // edges and vertices, and the rules differ.
    const int w = 19, h = 14;
    int differing_from_d3d = 0;
    for (std::uint32_t k = 0; k < 400; ++k) {
        auto coord = [&](std::uint32_t d, float size) {
            const float r = rand_unit(5, k, d) * (size + 4.0f) - 2.0f;
            return k % 2 ? std::floor(r * 2.0f) * 0.5f : std::floor(r * 256.0f) / 256.0f;
        };
        std::array<glm::vec2, 3> t, flipped;
        for (std::uint32_t n = 0; n < 3; ++n) {
            t[n] = {coord(2 * n, w), coord(2 * n + 1, h)};
        }
        if (k % 2) t[1].y = t[0].y;
        for (std::uint32_t n = 0; n < 3; ++n) flipped[n] = {t[n].x, static_cast<float>(h) - t[n].y};
        const Image gl = coverage_of({t}, w, h, FillRule::gl);
        const Image d3d_flipped = coverage_of({flipped}, w, h, FillRule::d3d);
        Image expected(w, h, 1, 0.0f);
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) expected.at(i, j) = d3d_flipped.at(i, h - 1 - j);
        CAPTURE(k);
        CHECK_MESSAGE(gl == expected, coverage_diff(gl, expected));
        differing_from_d3d += !(gl == coverage_of({t}, w, h, FillRule::d3d));
    }
    MESSAGE(differing_from_d3d << " of 400 triangles cover differently under d3d and gl");
    CHECK(differing_from_d3d > 50);  // the rules do differ on the half-pixel grid
}

TEST_CASE("raster: a triangle split at an edge midpoint covers what the whole one covers") {
    // Vertices on a half-pixel grid (many pixel centres exactly on edges and vertices); M is
    // the exact midpoint of BC (a multiple of 1/4 px), so both halves have the edge lines of
    // ABC plus the shared edge AM. Top-left: every pixel once, and exactly ABC's pixels.
    const int w = 24, h = 20;
    int cases = 0;
    for (std::uint32_t k = 0; k < 300; ++k) {
        auto grid = [&](std::uint32_t d, float size) {
            return std::floor(rand_unit(2, k, d) * 2.0f * (size + 4.0f)) * 0.5f - 2.0f;
        };
        const glm::vec2 a(grid(0, w), grid(1, h)), b(grid(2, w), grid(3, h)),
            c(grid(4, w), grid(5, h));
        const glm::vec2 m = (b + c) * 0.5f;
        for (const FillRule rule : both_rules) {
            const Image whole = coverage_of({{{a, b, c}}}, w, h, rule);
            const Image halves = coverage_of({{{a, b, m}}, {{a, m, c}}}, w, h, rule);
            CAPTURE(k);
            CAPTURE(std::string(fill_rule_name(rule)));
            CHECK_MESSAGE(halves == whole, coverage_diff(halves, whole));
            ++cases;
        }
    }
    CHECK(cases == 600);
}

TEST_CASE("raster: the two diagonals of a convex quad give the same once-only coverage") {
    // Two triangles sharing an edge: each pixel of the quad covered exactly once, whichever
    // diagonal is shared, in both windings.
    const int w = 24, h = 20;
    int convex = 0;
    for (std::uint32_t k = 0; k < 400; ++k) {
        auto coord = [&](std::uint32_t d, float size) {
            // Half of the cases on the half-pixel grid, half on the 1/256 grid.
            const float r = rand_unit(3, k, d) * (size + 4.0f) - 2.0f;
            return k % 2 ? std::floor(r * 2.0f) * 0.5f : std::floor(r * 256.0f) / 256.0f;
        };
        std::array<glm::vec2, 4> q;
        for (std::uint32_t n = 0; n < 4; ++n) q[n] = {coord(2 * n, w), coord(2 * n + 1, h)};
        // Keep strictly convex quads (all turns the same sign).
        int sign = 0;
        bool ok = true;
        for (int n = 0; n < 4; ++n) {
            const glm::vec2 e1 = q[(n + 1) % 4] - q[n], e2 = q[(n + 2) % 4] - q[(n + 1) % 4];
            const float turn = e1.x * e2.y - e1.y * e2.x;  // exact: coordinates on a fine grid
            const int s = turn > 0 ? 1 : turn < 0 ? -1 : 0;
            if (s == 0 || (sign != 0 && s != sign)) ok = false;
            sign = s;
        }
        if (!ok) continue;
        ++convex;
        for (const FillRule rule : both_rules) {
            const Image ac = coverage_of({{{q[0], q[1], q[2]}}, {{q[0], q[2], q[3]}}}, w, h, rule);
            const Image bd = coverage_of({{{q[0], q[1], q[3]}}, {{q[1], q[2], q[3]}}}, w, h, rule);
            const Image reversed =
                coverage_of({{{q[2], q[1], q[0]}}, {{q[3], q[2], q[0]}}}, w, h, rule);
            CAPTURE(k);
            CAPTURE(std::string(fill_rule_name(rule)));
            CHECK(*std::max_element(ac.data.begin(), ac.data.end()) <= 1.0f);
            CHECK_MESSAGE(bd == ac, coverage_diff(bd, ac));
            CHECK_MESSAGE(reversed == ac, coverage_diff(reversed, ac));
        }
    }
    CHECK(convex > 50);
}

TEST_CASE("raster: a full-screen quad covers every pixel exactly once, both windings") {
    const int w = 13, h = 7;
    const Image ones(w, h, 1, 1.0f);
    const float fw = static_cast<float>(w), fh = static_cast<float>(h);
    for (float margin : {0.0f, 5.25f, 1e5f}) {
        const glm::vec2 a(-margin, -margin), b(fw + margin, -margin), c(fw + margin, fh + margin),
            d(-margin, fh + margin);
        CAPTURE(margin);
        for (const FillRule rule : both_rules) {
            CAPTURE(std::string(fill_rule_name(rule)));
            const Image cw = coverage_of({{{a, b, c}}, {{a, c, d}}}, w, h, rule);
            const Image ccw = coverage_of({{{a, c, b}}, {{a, d, c}}}, w, h, rule);
            const Image other_diagonal = coverage_of({{{b, c, d}}, {{b, d, a}}}, w, h, rule);
            CHECK_MESSAGE(cw == ones, coverage_diff(cw, ones));
            CHECK_MESSAGE(ccw == ones, coverage_diff(ccw, ones));
            CHECK_MESSAGE(other_diagonal == ones, coverage_diff(other_diagonal, ones));
        }
    }
}

TEST_CASE("raster: a fan around a vertex at a pixel centre covers it exactly once") {
    const int w = 11, h = 11;
    const glm::vec2 centre(5.5f, 5.5f);
    for (int spokes : {3, 4, 6, 8, 13}) {
        for (bool reversed : {false, true}) {
            std::vector<std::array<glm::vec2, 3>> fan;
            auto rim = [&](int n) {
                // Angles chosen so that some spokes are exactly horizontal/vertical.
                const float a =
                    6.2831853f * static_cast<float>(n % spokes) / static_cast<float>(spokes);
                return centre + 4.0f * glm::vec2(std::cos(a), std::sin(a));
            };
            for (int n = 0; n < spokes; ++n)
                fan.push_back(reversed ? std::array<glm::vec2, 3>{centre, rim(n + 1), rim(n)}
                                       : std::array<glm::vec2, 3>{centre, rim(n), rim(n + 1)});
            for (const FillRule rule : both_rules) {
                const Image coverage = coverage_of(fan, w, h, rule);
                CAPTURE(spokes);
                CAPTURE(reversed);
                CAPTURE(std::string(fill_rule_name(rule)));
                CHECK(coverage.at(5, 5) == 1.0f);
                CHECK(*std::max_element(coverage.data.begin(), coverage.data.end()) == 1.0f);
            }
        }
    }
}

TEST_CASE("raster: zero-area and off-screen triangles cover nothing") {
    Image coverage(8, 8, 1, 0.0f);
    CHECK(rasterize_triangle_coverage({1, 1}, {5, 5}, {3, 3}, coverage) == 0);  // collinear
    CHECK(rasterize_triangle_coverage({1, 1}, {1.001f, 1}, {1, 1.001f}, coverage) ==
          0);  // snaps flat
    CHECK(rasterize_triangle_coverage({-9, -9}, {-1, -9}, {-9, -1}, coverage) == 0);
    CHECK(rasterize_triangle_coverage({9, 1}, {20, 1}, {9, 6}, coverage) == 0);
    CHECK(*std::max_element(coverage.data.begin(), coverage.data.end()) == 0.0f);
}

// ---- The whole pass on world-space scenes ----

TEST_CASE("raster: a small triangle around a primary ray covers exactly that pixel") {
    // The rasterizer's screen point of a world point agrees with the primary ray through the
    // pixel centre (SPEC §1): a triangle +-0.3 px around the point where the ray through (i +
    // 0.5, j + 0.5) meets depth 3 covers pixel (i, j) and nothing else.
    const Camera camera = look_at({0.5f, 0.2f, 2.0f}, {0, 0, -1}, {0, 1, 0}, 55.0f);
    const int w = 40, h = 30;
    const float tan_half = tan_half_vfov(camera);
    const float px = 2.0f * tan_half * 3.0f / h;  // world size of one pixel at depth 3
    std::vector<Tri> tris;
    std::vector<std::pair<int, int>> pixels = {{0, 0}, {39, 29}, {17, 11}, {5, 22}, {33, 3}};
    for (auto [i, j] : pixels) {
        glm::vec3 d = primary_ray_direction(camera, tan_half, w, h, static_cast<float>(i) + 0.5f,
                                            static_cast<float>(j) + 0.5f);
        const glm::vec3 p = camera.position + d * (3.0f / glm::dot(d, camera.forward));
        tris.push_back({p - 0.3f * px * camera.right - 0.3f * px * camera.up,
                        p + 0.3f * px * camera.right - 0.3f * px * camera.up,
                        p + 0.3f * px * camera.up});
    }
    const Scene scene = make_scene(tris, static_cast<int>(tris.size()));
    RasterStats stats;
    const GBuffer g = rasterize_gbuffer(scene, camera, camera, w, h, stats);
    for (std::size_t k = 0; k < pixels.size(); ++k)
        CHECK(g.primitive_id.at(pixels[k].first, pixels[k].second) == static_cast<float>(k));
    CHECK(stats.pixels_covered == static_cast<std::int64_t>(pixels.size()));
    CHECK(stats.triangles_rasterized == 5);
}

TEST_CASE("raster: background pixels, empty scene and statistics categories") {
    Scene empty = make_scene({});
    RasterStats stats;
    const Camera camera = straight_camera();
    const GBuffer g = rasterize_gbuffer(empty, camera, camera, 5, 4, stats);
    CHECK(bit_equal(g.primitive_id, Image(5, 4, 1, -1.0f)));
    CHECK(bit_equal(g.material_id, Image(5, 4, 1, -1.0f)));
    CHECK(bit_equal(g.view_depth, Image(5, 4, 1, 0.0f)));
    CHECK(bit_equal(g.motion, Image(5, 4, 2, 0.0f)));
    CHECK(stats == RasterStats{});

    // One triangle per category (camera looks down -z, 60 degrees, 16 x 12).
    const Scene scene = with_unit_scale(make_scene(
        {
            {{{-1, -1, -3}, {1, -1, -3}, {0, 1, -3}}},                 // 0 rasterized
            {{{-1, -1, 3}, {1, -1, 3}, {0, 1, 3}}},                    // 1 behind: clipped away
            {{{-30, -1, -3}, {-20, -1, -3}, {-25, 1, -3}}},            // 2 off screen (left)
            {{{0, 0, -3}, {1e-7f, 0, -3}, {0, 1e-7f, -3}}},            // 3 snaps to zero area
            {{{-1, -1, -3}, {1, -1, -3}, {0, 1.5f, 3}}},               // 4 crosses the near plane
            {{{-1e6f, -1e6f, -3}, {1e6f, -1e6f, -3}, {0, 1e6f, -3}}},  // 5 beyond the guard band
            {{{1e25f, 0, -3}, {1e25f, 1, -3}, {1e25f, 0, -4}}},  // 6 beyond 1e20: out of range
        },
        7));
    const GBuffer g2 = rasterize_gbuffer(scene, camera, camera, 16, 12, stats);
    CHECK(stats.triangles_in == 7);
    CHECK(stats.triangles_out_of_range == 1);
    CHECK(stats.triangles_clipped_away == 1);
    CHECK(stats.triangles_culled_offscreen == 1);
    CHECK(stats.triangles_degenerate == 1);
    CHECK(stats.triangles_rasterized == 3);
    CHECK(stats.triangles_near_clipped == 1);
    CHECK(stats.triangles_guard_clipped == 2);  // 5, and 4: its near-plane points project far
    CHECK(exclusive_categories(stats) == stats.triangles_in);
    CHECK(stats.fragments_written <= stats.fragments_tested);
    CHECK(stats.fragments_tested <= stats.coverage_tests);
    std::set<float> ids(g2.primitive_id.data.begin(), g2.primitive_id.data.end());
    CHECK(ids.count(1.0f) == 0);
    CHECK(ids.count(2.0f) == 0);
    CHECK(ids.count(3.0f) == 0);
}

TEST_CASE("raster: invalid sizes and cameras throw fovref::Error") {
    const Scene scene = make_scene({{{{-1, -1, -3}, {1, -1, -3}, {0, 1, -3}}}});
    const Camera camera = straight_camera();
    RasterStats stats;
    CHECK_THROWS_AS(rasterize_gbuffer(scene, camera, camera, 0, 4, stats), Error);
    CHECK_THROWS_AS(rasterize_gbuffer(scene, camera, camera, 4, 20000, stats), Error);
    Camera bad = camera;
    bad.vfov_deg = 180.0f;
    CHECK_THROWS_AS(rasterize_gbuffer(scene, bad, camera, 4, 4, stats), Error);
    CHECK_THROWS_AS(rasterize_gbuffer(scene, camera, bad, 4, 4, stats), Error);
    bad = camera;
    bad.forward.x = NAN;
    CHECK_THROWS_AS(rasterize_gbuffer(scene, bad, camera, 4, 4, stats), Error);
    Scene broken = scene;
    broken.material_ids[0] = 3;
    CHECK_THROWS_AS(rasterize_gbuffer(broken, camera, camera, 4, 4, stats), Error);
}

TEST_CASE("raster: near-plane clipping matches a binary64 ray cast of the clipped triangle") {
    // Camera at the origin looking down -z; the triangle has one corner behind the camera and
    // two in front. A second triangle lies entirely behind the camera.
    const Camera camera = straight_camera(70.0f);
    const int w = 40, h = 30;
    const Tri crossing = {{{-2, -1.5f, -2}, {2, -1, -2.5f}, {0.3f, 1, 1.5f}}};
    const Tri behind = {{{-1, -1, 1}, {1, -1, 1}, {0, 1, 2}}};
    const Scene scene = make_scene({crossing, behind}, 2);
    RasterStats stats;
    const GBuffer g = rasterize_gbuffer(scene, camera, camera, w, h, stats);
    CHECK(stats.triangles_near_clipped == 1);
    CHECK(stats.triangles_clipped_away == 1);
    CHECK(stats.triangles_rasterized == 1);
    // Reference coverage: ray through the pixel centre hits the triangle at t > 0. Pixels
    // whose four rays offset by +-0.01 px disagree touch an edge (the rasterizer moves edges
    // by at most sqrt(2)/512 = 0.0028 px when snapping) and are skipped.
    int sure = 0, edge = 0, covered = 0;
    double worst = 0.0;
    const glm::dvec3 o(0.0);
    for (int j = 0; j < h; ++j) {
        for (int i = 0; i < w; ++i) {
            auto hits = [&](double dx, double dy) {
                return intersect_d(o, ray_direction_d(camera, w, h, i + 0.5 + dx, j + 0.5 + dy),
                                   glm::dvec3(crossing[0]), glm::dvec3(crossing[1]),
                                   glm::dvec3(crossing[2]))
                           .t > 0.0;
            };
            const bool centre = hits(0, 0);
            if (hits(0.01, 0) != centre || hits(-0.01, 0) != centre || hits(0, 0.01) != centre ||
                hits(0, -0.01) != centre) {
                ++edge;
                continue;
            }
            ++sure;
            const float id = g.primitive_id.at(i, j);
            CHECK(id == (centre ? 0.0f : -1.0f));
            if (id == 0.0f) {
                ++covered;
                CHECK(g.view_depth.at(i, j) > 0.0f);
                const glm::dvec3 p(g.world_position.at(i, j, 0), g.world_position.at(i, j, 1),
                                   g.world_position.at(i, j, 2));
                worst = std::max(
                    worst, glm::length(project_d(camera, w, h, p) - glm::dvec2(i + 0.5, j + 0.5)));
            }
        }
    }
    MESSAGE("near clip: " << covered << " covered, " << sure << " decided, " << edge
                          << " edge pixels, worst reprojection " << worst << " px");
    // Clipping only shapes the coverage: the surface point lies on the pixel's primary ray up to
    // float rounding (measured 2.1e-4 px next to the near plane, where 1 mm is many pixels):
    // bound 1e-3 px.
    CHECK(worst < 1e-3);
    CHECK(covered > 100);  // the triangle covers a good part of the screen
    CHECK(edge < 80);      // edges cross the screen a few times, ~1 px each
}

TEST_CASE("raster: a triangle far beyond the guard band still covers the screen exactly") {
    // Vertices at +-1e4 m at depth 1 project ~1.2e5 px away (12 px per metre): the guard band
    // (2^15 px) clips them.
    const Camera camera = straight_camera(90.0f);
    const int w = 32, h = 24;
    const Scene scene =
        with_unit_scale(make_scene({{{{-1e4f, -1e4f, -1}, {1e4f, -1e4f, -1}, {0, 1e4f, -1}}}}));
    RasterStats stats;
    const GBuffer g = rasterize_gbuffer(scene, camera, camera, w, h, stats);
    CHECK(stats.triangles_guard_clipped == 1);
    CHECK(stats.pixels_covered == w * h);
    CHECK(stats.fragments_tested == w * h);  // the fan of the clipped polygon: each pixel once
    double worst = 0.0;
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const glm::dvec3 p(g.world_position.at(i, j, 0), g.world_position.at(i, j, 1),
                               g.world_position.at(i, j, 2));
            const glm::dvec2 s = project_d(camera, w, h, p);
            worst = std::max(worst, glm::length(s - glm::dvec2(i + 0.5, j + 0.5)));
        }
    MESSAGE("guard band: worst reprojection error " << worst << " px");
    // surface_at interpolates the position from corners 1e4 m away: float rounding of the
    // corner products and sums is a few ulp(1e4) = a few 1e-3 m, i.e. a few 0.01 px at 12 px
    // per metre (measured 0.023 px). Bound 0.1 px.
    // (The error grows with the triangle's unclipped extent; docs/raster.md.)
    CHECK(worst < 0.1);
}

TEST_CASE("raster: depth test 'less' and the equal-depth tie-break") {
    const Camera camera = straight_camera();
    const int w = 16, h = 12;
    // Both cover the whole screen.
    const Tri near_tri = {{{-50, -50, -2}, {50, -50, -2}, {0, 50, -2}}};
    const Tri far_tri = {{{-50, -50, -3}, {50, -50, -3}, {0, 50, -3}}};
    for (bool near_first : {true, false}) {
        const Scene scene = make_scene(
            near_first ? std::vector<Tri>{near_tri, far_tri} : std::vector<Tri>{far_tri, near_tri},
            2);
        RasterStats stats;
        const GBuffer g = rasterize_gbuffer(scene, camera, camera, w, h, stats);
        const float near_id = near_first ? 0.0f : 1.0f;
        for (float id : g.primitive_id.data) CHECK(id == near_id);
        // Depth 2 exactly? The interpolated z is a float sum of -2 w0, -2 u, -2 v: within 1 ulp.
        CHECK(g.view_depth.at(7, 5) == doctest::Approx(2.0f).epsilon(1e-6));
        CHECK(stats.fragments_written == (near_first ? w * h : 2 * w * h));
    }
    // Identical coplanar triangles (the same bits) tie: the lower primitive id wins; the
    // attributes (material) are those of the winner.
    const Tri slanted = {{{-50, -50, -2}, {50, -40, -3.3f}, {0, 50, -2.7f}}};
    const Scene twins = make_scene({slanted, slanted, slanted}, 3);
    RasterStats stats;
    const GBuffer g = rasterize_gbuffer(twins, camera, camera, w, h, stats);
    for (float id : g.primitive_id.data) CHECK(id == 0.0f);
    for (float id : g.material_id.data) CHECK(id == 0.0f);
    CHECK(stats.fragments_tested == 3 * w * h);
    CHECK(stats.fragments_written == w * h);
}

TEST_CASE("raster: perspective-correct uv on a tilted quad vs the analytic ray-plane hit") {
    // Quad O + s E1 + t E2, (s, t) in [0, 1]^2, uv = (s, t), steeply tilted away from the
    // camera (depth 1.2 .. 7.2), rasterized as two triangles.
    const glm::vec3 origin(-1.5f, -1.0f, -1.2f), e1(3.0f, 0.0f, 0.0f), e2(0.0f, 2.5f, -6.0f);
    const Tri t0 = {{origin, origin + e1, origin + e1 + e2}};
    const Tri t1 = {{origin, origin + e1 + e2, origin + e2}};
    const std::vector<std::array<glm::vec2, 3>> uvs = {{{{0, 0}, {1, 0}, {1, 1}}},
                                                       {{{0, 0}, {1, 1}, {0, 1}}}};
    const Scene scene = make_scene({t0, t1}, 1, uvs);
    const Camera camera = straight_camera(75.0f);
    const int w = 48, h = 36;
    RasterStats stats;
    const VisibilityBuffer vis = rasterize_visibility(scene, camera, w, h, stats);

    // Analytic uv of the ray through screen point (x, y): solve O + s E1 + t E2 = r d.
    const glm::dvec3 O(origin), E1(e1), E2(e2);
    const glm::dvec3 n = glm::cross(E1, E2);
    auto uv_at = [&](double x, double y) {
        const glm::dvec3 d = ray_direction_d(camera, w, h, x, y);
        const glm::dvec3 p = d * (glm::dot(O, n) / glm::dot(d, n));
        const glm::dvec3 q = p - O;
        // E1 is along x and E2 in the y-z plane: s from x, t from y.
        return glm::dvec2(q.x / E1.x, q.y / E2.y);
    };
    double worst_ratio = 0.0, worst_affine = 0.0;
    int pixels = 0;
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const std::size_t index = static_cast<std::size_t>(j) * w + i;
            if (vis.primitive[index] < 0) continue;
            const double x = i + 0.5, y = j + 0.5;
            const glm::dvec2 expected = uv_at(x, y);
            if (expected.x < 0.02 || expected.x > 0.98 || expected.y < 0.02 || expected.y > 0.98)
                continue;  // stay off the quad's border
            const SurfacePoint s =
                surface_at(scene, vis.primitive[index], vis.u[index], vis.v[index]);
            // Tolerance: the attributes are evaluated on the pixel's own primary ray (snapping
            // moves only the coverage), so only float rounding remains: the ray direction's
            // (~1e-7 relative, i.e. 1e-5 px times the uv gradient here) plus 2e-6 for u, v and
            // the uv sum. (Interpolating over the snapped triangle instead would be off by up to
            // 0.0028 px times the gradient: ~100x this tolerance.)
            const double gradient = glm::length(uv_at(x + 0.5, y) - uv_at(x - 0.5, y)) +
                                    glm::length(uv_at(x, y + 0.5) - uv_at(x, y - 0.5));
            const double tolerance = 1e-5 * gradient + 2e-6;
            const double error = glm::length(glm::dvec2(s.uv) - expected);
            CHECK(error <= tolerance);
            worst_ratio = std::max(worst_ratio, error / tolerance);
            // What affine (screen-space linear) interpolation would give, for contrast:
            // uv = screen barycentrics of the projected corners.
            const glm::dvec2 a = project_d(camera, w, h, glm::dvec3(origin)),
                             b = project_d(camera, w, h, glm::dvec3(origin + e1)),
                             c = project_d(camera, w, h, glm::dvec3(origin + e1 + e2)),
                             d = project_d(camera, w, h, glm::dvec3(origin + e2));
            const bool first = vis.primitive[index] == 0;
            const glm::dvec2 p1 = first ? b : c, p2 = first ? c : d;
            const glm::dvec2 q1 = first ? glm::dvec2(1, 0) : glm::dvec2(1, 1),
                             q2 = first ? glm::dvec2(1, 1) : glm::dvec2(0, 1);
            auto cross2 = [](glm::dvec2 u, glm::dvec2 v) { return u.x * v.y - u.y * v.x; };
            const double area = cross2(p1 - a, p2 - a);
            const glm::dvec2 pc(x, y);
            const double l1 = cross2(pc - a, p2 - a) / area, l2 = cross2(p1 - a, pc - a) / area;
            worst_affine = std::max(worst_affine, glm::length(l1 * q1 + l2 * q2 - expected));
            ++pixels;
        }
    MESSAGE("perspective uv: " << pixels << " pixels, worst error / tolerance " << worst_ratio
                               << ", affine interpolation would be off by " << worst_affine);
    CHECK(pixels > 300);
    CHECK(worst_affine > 0.05);  // the case discriminates: affine is visibly wrong here
}

TEST_CASE("raster: motion vectors for a camera translation and a camera turned away") {
    // Fronto-parallel plane at depth D = 4; previous camera shifted by a along R. A point at
    // view x = X was at X - a before: its screen x moves by -a W / (2 k D), k = tan(vfov/2) W/H.
    const Camera camera = straight_camera(60.0f);
    const int w = 32, h = 20;
    const Scene scene = make_scene({{{{-10, -10, -4}, {10, -10, -4}, {0, 10, -4}}}});
    Camera previous = camera;
    previous.position += 0.25f * camera.right;
    RasterStats stats;
    const GBuffer g = rasterize_gbuffer(scene, camera, previous, w, h, stats);
    const double k = tan_half_vfov(camera) * (static_cast<double>(w) / h);
    const double expected = -0.25 * w / (2.0 * k * 4.0);
    double worst = 0.0;
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            worst = std::max({worst, std::fabs(g.motion.at(i, j, 0) - expected),
                              std::fabs(static_cast<double>(g.motion.at(i, j, 1)))});
        }
    MESSAGE("motion: expected " << expected << " px, worst error " << worst << " px");
    // The pixel's surface point lies on its primary ray up to float rounding, and float screen
    // arithmetic adds a little (measured 7.6e-6 px): bound 1e-4 px. (Interpolating over the
    // snapped triangle would be off by up to 0.0028 px.)
    CHECK(worst < 1e-4);
    CHECK(stats.motion_behind_previous == 0);

    // Same camera: the motion is the reprojection offset itself, bounded the same way.
    RasterStats still_stats;
    const GBuffer still = rasterize_gbuffer(scene, camera, camera, w, h, still_stats);
    for (float m : still.motion.data) CHECK(std::fabs(m) < 1e-4f);

    // Previous camera facing the other way: every point was behind it, motion 0.
    Camera turned = camera;
    turned.forward = -camera.forward;
    turned.right = -camera.right;
    RasterStats turned_stats;
    const GBuffer t = rasterize_gbuffer(scene, camera, turned, w, h, turned_stats);
    CHECK(bit_equal(t.motion, Image(w, h, 2, 0.0f)));
    CHECK(turned_stats.motion_behind_previous == w * h);
}

TEST_CASE("raster: deterministic, bit-equal over two runs") {
    const Scene scene = make_procedural_scene("cornell");
    const Camera previous = camera_at(scene, 0.5f);
    RasterStats s1, s2;
    const GBuffer a = rasterize_gbuffer(scene, scene.camera, previous, 64, 48, s1);
    const GBuffer b = rasterize_gbuffer(scene, scene.camera, previous, 64, 48, s2);
    CHECK(s1 == s2);
    check_same_gbuffer(a, b);
    // For comparing builds (g++ / clang++, -O0 / -O2): these must print the same.
    MESSAGE("cornell 64x48 world_position " << canonical_sha256(a.world_position).substr(0, 16)
                                            << " motion "
                                            << canonical_sha256(a.motion).substr(0, 16));
}

TEST_CASE(
    "raster: a pixel made again from its id, and the visibility channels, equal "
    "resolve_gbuffer's") {
    // kfr's lp_sample reads only the primitive ids and makes the pixels it samples again
    // (write_rasterized_pixel); the raster stage then outputs the visibility pass's ids and
    // depths alone (visibility_primitive_ids, visibility_view_depth). All must be resolve_gbuffer's
    // bits, every channel, motion included, with a jittered sample and a moving camera.
    const int w = 64, h = 36;
    for (const char* name : {"cornell", "checker-room", "glossy-floor", "sphere-grid"}) {
        CAPTURE(name);
        const Scene scene = make_procedural_scene(name);
        const Camera camera = camera_at(scene, 0.5f), previous = camera_at(scene, 0.25f);
        for (const Offset2 sample : {Offset2{}, Offset2{0.8125f, 0.1875f}}) {
            CAPTURE(sample.x);
            RasterSettings settings;
            settings.sample = sample;
            RasterStats stats;
            const VisibilityBuffer vis = rasterize_visibility(scene, camera, w, h, stats, settings);
            const GBuffer g = resolve_gbuffer(scene, vis, camera, previous, stats);
            CHECK(bit_equal(visibility_primitive_ids(vis), g.primitive_id));
            CHECK(bit_equal(visibility_view_depth(vis), g.view_depth));
            const RasterFrame frame = make_raster_frame(scene, camera, w, h, settings);
            GBuffer again(w, h);
            int written = 0;
            for (int j = 0; j < h; ++j)
                for (int i = 0; i < w; ++i)
                    written += write_rasterized_pixel(again, i, j, scene, frame, previous,
                                                      tan_half_vfov(previous),
                                                      g.primitive_id.at(i, j), i, j);
            CHECK(written == stats.pixels_covered);
            CHECK(written > w * h / 3);
            check_same_gbuffer(again, g);
            // Into another pixel of another buffer: the same values (a texel takes the pixel's).
            GBuffer one(1, 1);
            const int i = w / 2, j = h / 2;
            REQUIRE(g.primitive_id.at(i, j) >= 0.0f);
            CHECK(write_rasterized_pixel(one, 0, 0, scene, frame, previous, tan_half_vfov(previous),
                                         g.primitive_id.at(i, j), i, j));
            CHECK(one.albedo.at(0, 0, 1) == g.albedo.at(i, j, 1));
            CHECK(one.motion.at(0, 0, 0) == g.motion.at(i, j, 0));
            // Ids that name no triangle write nothing: background, a fraction, past the end,
            // NaN, infinity.
            const float n = static_cast<float>(scene.triangle_count());
            for (const float id :
                 {-1.0f, 0.5f, n, n + 7.0f, std::numeric_limits<float>::quiet_NaN(),
                  std::numeric_limits<float>::infinity()}) {
                GBuffer untouched(1, 1);
                CHECK_FALSE(write_rasterized_pixel(untouched, 0, 0, scene, frame, previous,
                                                   tan_half_vfov(previous), id, i, j));
                CHECK(untouched.primitive_id.at(0, 0) == -1.0f);
                CHECK(untouched.albedo.at(0, 0, 0) == 0.0f);
            }
        }
    }
}

TEST_CASE("raster: eight triangle setups at a time (AVX) give setup_triangle's") {
    if (!raster_fragments_avx_applies()) {
        MESSAGE("no AVX on this CPU: setup_triangle alone");
        return;
    }
    // Random triangles around a camera: most inside every clip plane, some crossing the near
    // plane or the guard band, behind the camera, beyond the view range, deep or off the side,
    // tiny ones; with and without a jittered sample, on a small screen and a large one. The scene
    // scale is set back to 1 so that the far corners do not push the near plane out.
    test::SplitMix64 rng(11);
    const auto coordinate = [&](float spread) {
        return (static_cast<float>(rng.below(2000001)) - 1000000.0f) * (spread / 1000000.0f);
    };
    std::vector<Tri> triangles;
    for (int k = 0; k < 4000; ++k) {
        const std::size_t kind = rng.below(10);
        const glm::vec3 centre{coordinate(3.0f), coordinate(2.0f), -0.2f - 6.0f * rng.unit()};
        Tri t;
        for (glm::vec3& p : t) {
            const float spread = kind == 0 ? 40.0f : kind == 1 ? 1e-4f : 0.3f;
            p = centre + glm::vec3(coordinate(spread), coordinate(spread), coordinate(spread));
        }
        if (kind == 2) t[1].z = 1.0f;                               // behind: near clip
        if (kind == 3) t = {{{-1, -1, 2}, {1, -1, 2}, {0, 1, 3}}};  // behind the camera
        if (kind == 4) t[2].x = 1e21f;                              // out of view range
        if (kind == 5) t[0].y = 1e19f;                // in range, outside the guard band
        if (kind == 7) t[2].z = -50.0f;               // deep
        if (kind == 8) t[0] = {-10.0f, 0.0f, -1.0f};  // off the side
        if (kind == 9) t[0].z = -0.99e-4f;  // just in front of the camera, behind the near plane
        if (kind == 6) t[1].x = 5e4f;       // guard band
        triangles.push_back(t);
    }
    const Scene scene = with_unit_scale(make_scene(triangles));
    std::int64_t fast = 0, reference = 0;
    for (const Offset2& sample : {Offset2{}, Offset2{0.3125f, 0.9f}})
        for (const glm::ivec2& size : {glm::ivec2(64, 36), glm::ivec2(1280, 720)}) {
            RasterSettings settings;
            settings.sample = sample;
            const RasterFrame frame =
                make_raster_frame(scene, straight_camera(), size.x, size.y, settings);
            for (std::size_t first = 0; first < triangles.size(); first += 8) {
                const int count =
                    static_cast<int>(std::min<std::size_t>(8, triangles.size() - first));
                TriangleSetup mine[8];
                bool done[8];
                setup_triangles_avx(scene, frame, static_cast<std::int32_t>(first), count, mine,
                                    done);
                for (int l = 0; l < count; ++l) {
                    const auto primitive = static_cast<std::int32_t>(first) + l;
                    const TriangleSetup expected = setup_triangle(scene, frame, primitive);
                    if (!done[l]) {
                        ++reference;
                        // Left to the reference only where it clips (or refuses) the triangle
                        CHECK((expected.status != TriangleSetup::Status::ready ||
                               expected.near_clipped || expected.guard_clipped));
                        continue;
                    }
                    ++fast;
                    CAPTURE(primitive);
                    CHECK(expected.status == TriangleSetup::Status::ready);
                    CHECK_FALSE(expected.near_clipped);
                    CHECK_FALSE(expected.guard_clipped);
                    REQUIRE(expected.count == 3);
                    CHECK(mine[l].status == expected.status);
                    CHECK(mine[l].count == 3);
                    for (std::size_t k = 0; k < 3; ++k)
                        CHECK(mine[l].polygon[k] == expected.polygon[k]);
                }
            }
        }
    CHECK(fast > 4000);
    CHECK(reference > 5000);
}

TEST_CASE("raster: eight fragments at a time (AVX) give raster_fragment's bits") {
    if (!cpu_has_avx()) MESSAGE("no AVX on this CPU: both runs take raster_fragment");
    CHECK(raster_fragments_avx_applies() == cpu_has_avx());
    const auto same_bits = [](const auto& a, const auto& b) {
        return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof a[0]) == 0;
    };
    // The straight camera's centre ray on a 33 x 33 screen is exactly (0, 0, -1): it runs through
    // the shared corner of a fan and along an edge, where U, V or W is exactly 0 (the lanes that
    // take the reference); beside them a tilted triangle seen almost edge-on.
    const Scene fan = make_scene({{{{0, 0, -4}, {2, 0, -4}, {0, 2, -4}}},
                                  {{{0, 0, -4}, {0, 2, -4}, {-2, -1, -4}}},
                                  {{{0, 0, -4}, {-2, -1, -4}, {2, 0, -4}}},
                                  {{{-1, 0, -3}, {1, 0, -3}, {0, 3, -3.0001f}}}},
                                 4);
    std::vector<std::pair<Scene, Camera>> cases = {{fan, straight_camera()}};
    for (const char* name : {"cornell", "sphere-grid", "checker-room", "glossy-floor"}) {
        Scene scene = make_procedural_scene(name);
        const Camera camera = camera_at(scene, 0.5f);
        cases.emplace_back(std::move(scene), camera);
    }
    std::int64_t fragments = 0;
    for (const auto& entry : cases) {
        const Scene& scene = entry.first;
        const Camera& camera = entry.second;
        CAPTURE(scene.name);
        for (const Offset2& sample : {Offset2{}, Offset2{0.8125f, 0.1875f}})
            for (const glm::ivec2& size : {glm::ivec2(33, 33), glm::ivec2(70, 39)}) {
                RasterSettings settings;
                settings.sample = sample;
                RasterStats stats[2];
                VisibilityBuffer vis[2];
                for (const bool simd : {true, false}) {
                    set_simd_allowed(simd);
                    vis[simd ? 0 : 1] = rasterize_visibility(scene, camera, size.x, size.y,
                                                             stats[simd ? 0 : 1], settings);
                    set_simd_allowed(true);
                }
                CHECK(stats[0] == stats[1]);
                CHECK(same_bits(vis[0].primitive, vis[1].primitive));
                CHECK(same_bits(vis[0].u, vis[1].u));
                CHECK(same_bits(vis[0].v, vis[1].v));
                CHECK(same_bits(vis[0].depth, vis[1].depth));
                fragments += stats[1].fragments_tested;
            }
    }
    CHECK(fragments > 10000);

    // The sites one by one against raster_fragment, in batches of 1 to 8 of mixed triangles and
    // rows, at every pixel of the fan's screen (covered or not: the plane point is extrapolated).
    if (!raster_fragments_avx_applies()) return;
    const RasterFrame frame = make_raster_frame(fan, straight_camera(), 33, 33, {});
    std::vector<RasterSite> sites;
    for (int y = 0; y < 33; ++y)
        for (int x = 0; x < 33; ++x)
            for (std::int32_t p = 0; p < 4; ++p) sites.push_back({x, y, p});
    std::int64_t hits = 0, compared = 0;
    for (std::size_t start = 0, count = 1; start < sites.size();
         start += count, count = count % 8 + 1) {
        const int n = static_cast<int>(std::min(count, sites.size() - start));
        RasterFragment mine[8];
        bool hit[8];
        raster_fragments_avx(fan, frame, &sites[start], n, mine, hit);
        for (int l = 0; l < n; ++l) {
            const RasterSite& site = sites[start + static_cast<std::size_t>(l)];
            RasterFragment reference;
            const bool expected =
                raster_fragment(fan, frame, site.x, site.y, site.primitive, reference);
            CAPTURE(site.x);
            CAPTURE(site.y);
            CAPTURE(site.primitive);
            REQUIRE(hit[l] == expected);
            ++compared;
            if (!expected) continue;
            ++hits;
            CHECK(mine[l].primitive == reference.primitive);
            CHECK(std::memcmp(&mine[l].t, &reference.t, sizeof(float)) == 0);
            CHECK(std::memcmp(&mine[l].u, &reference.u, sizeof(float)) == 0);
            CHECK(std::memcmp(&mine[l].v, &reference.v, sizeof(float)) == 0);
            CHECK(std::memcmp(&mine[l].depth, &reference.depth, sizeof(float)) == 0);
        }
    }
    CHECK(compared == static_cast<std::int64_t>(sites.size()));
    CHECK(hits > 3000);
}

// ---- Procedural scenes ----

TEST_CASE("raster: every procedural scene (smoke test and per-pixel invariants)") {
    const int w = 48, h = 27;
    for (const ProceduralSceneInfo& info : procedural_scenes()) {
        CAPTURE(info.name);
        const Scene scene = make_procedural_scene(info.name);
        const Camera previous = camera_at(scene, 0.25f);
        RasterStats stats;
        const GBuffer g = rasterize_gbuffer(scene, scene.camera, previous, w, h, stats);
        CHECK(stats.triangles_in == static_cast<std::int64_t>(scene.triangle_count()));
        CHECK(exclusive_categories(stats) == stats.triangles_in);
        CHECK(stats.triangles_out_of_range == 0);
        // Every scene's camera looks into the scene: at least a third of the screen is covered.
        CHECK(stats.pixels_covered * 3 >= w * h);
        double worst_reprojection = 0.0;
        int bad = 0;
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                const float id = g.primitive_id.at(i, j);
                if (id < 0.0f) {
                    bad += g.material_id.at(i, j) != -1.0f;
                    continue;
                }
                const auto prim = static_cast<std::size_t>(id);
                bad += !(prim < scene.triangle_count());
                bad += g.material_id.at(i, j) != static_cast<float>(scene.material_ids[prim]);
                const glm::vec3 p(g.world_position.at(i, j, 0), g.world_position.at(i, j, 1),
                                  g.world_position.at(i, j, 2));
                // The view depth channel is the depth-tested value (bit for bit).
                bad += g.view_depth.at(i, j) != view_depth(scene.camera, p);
                bad += !(g.view_depth.at(i, j) > 0.0f);
                bad += !(g.hit_distance.at(i, j) >= g.view_depth.at(i, j) * (1.0f - 1e-6f));
                const glm::vec3 n(g.shading_normal.at(i, j, 0), g.shading_normal.at(i, j, 1),
                                  g.shading_normal.at(i, j, 2));
                bad += !(std::fabs(glm::length(n) - 1.0f) < 1e-5f);  // normalised in float
                const glm::dvec2 s = project_d(scene.camera, w, h, glm::dvec3(p));
                worst_reprojection =
                    std::max(worst_reprojection, glm::length(s - glm::dvec2(i + 0.5, j + 0.5)));
            }
        MESSAGE(info.name << ": " << stats.pixels_covered << " of " << w * h << " pixels covered, "
                          << stats.triangles_rasterized << " of " << stats.triangles_in
                          << " triangles rasterized, " << stats.triangles_near_clipped
                          << " near-clipped, " << stats.triangles_guard_clipped
                          << " guard-clipped; worst "
                          << "reprojection " << worst_reprojection << " px");
        CHECK(bad == 0);
        // The surface point of each pixel projects back onto its centre: it lies on the pixel's
        // primary ray up to float rounding of the ray, the barycentrics and the position
        // (measured <= 1.2e-5 px). 1e-4 px is the stated bound (snapped-triangle interpolation
        // was off by up to 0.003 px).
        CHECK(worst_reprojection < 1e-4);
    }
}

TEST_CASE("raster: primitive ids agree with a binary64 ray caster except on edge pixels") {
    // SPEC §4 cross-check, against a brute-force binary64 closest hit on the smaller scenes.
    // A pixel touches an edge when one of the rays offset by +-0.01 px in x or y hits another
    // primitive than the centre ray (snapping moves edges by <= 0.0028 px). Off-edge
    // disagreements are bounded by 0.
    const int w = 40, h = 24;
    for (const std::string name : {"cornell", "checker-room", "glossy-floor"}) {
        CAPTURE(name);
        const Scene scene = make_procedural_scene(name);
        RasterStats stats;
        const GBuffer g = rasterize_gbuffer(scene, scene.camera, scene.camera, w, h, stats);
        const glm::dvec3 o(scene.camera.position);
        int edge = 0, disagree = 0;
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                auto cast = [&](double dx, double dy) {
                    return closest_d(
                        scene, o, ray_direction_d(scene.camera, w, h, i + 0.5 + dx, j + 0.5 + dy));
                };
                const int centre = cast(0, 0);
                if (cast(0.01, 0) != centre || cast(-0.01, 0) != centre ||
                    cast(0, 0.01) != centre || cast(0, -0.01) != centre) {
                    ++edge;
                    continue;
                }
                if (g.primitive_id.at(i, j) != static_cast<float>(centre)) {
                    ++disagree;
                    MESSAGE("pixel (" << i << ", " << j << "): raster " << g.primitive_id.at(i, j)
                                      << ", ray " << centre);
                }
            }
        MESSAGE(name << ": " << edge << " edge pixels of " << w * h << ", " << disagree
                     << " off-edge disagreements");
        CHECK(disagree == 0);
    }
}

TEST_CASE("raster: covered centres whose rays run parallel to the plane") {
    // A floor y = -1 reaching to z = -1e7 seen from y = 0: its far edge projects onto the
    // horizon, screen y = H/2 = 4.5, the centre row of a 9-pixel-high screen, and snaps there
    // exactly. It is a top edge, so under the d3d rule the row's centres are covered, but their
    // rays have d.y = 0 exactly: parallel to the floor. Where the sheared determinant is exactly
    // 0 the fragment is dropped and counted; where rounding leaves it non-zero, the "plane point"
    // lies absurdly far along the ray (as the ray caster's would): never NaN, never behind.
    const Camera camera = straight_camera(60.0f);
    const int w = 9, h = 9;
    const glm::vec3 n0(-2, -1, -2), n1(2, -1, -2), f0(-1e7f, -1, -1e7f), f1(1e7f, -1, -1e7f);
    const Scene scene = with_unit_scale(make_scene({{{n0, n1, f1}}, {{n0, f1, f0}}}));
    for (const FillRule rule : {FillRule::d3d, FillRule::gl}) {
        CAPTURE(std::string(fill_rule_name(rule)));
        RasterSettings settings;
        settings.fill_rule = rule;
        RasterStats stats;
        const GBuffer g = rasterize_gbuffer(scene, camera, camera, w, h, stats, settings);
        int horizon_covered = 0, below_covered = 0;
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                const bool covered = g.primitive_id.at(i, j) >= 0.0f;
                if (j == 4 && covered) {
                    ++horizon_covered;
                    CHECK(g.view_depth.at(i, j) > 1e7f);  // beyond the floor's far edge
                }
                if (j > 4) below_covered += covered;
                if (covered) CHECK(g.view_depth.at(i, j) > 0.0f);
                for (float value : {g.view_depth.at(i, j), g.world_position.at(i, j, 0)})
                    CHECK(std::isfinite(value));
            }
        // The near edge projects to y = 4.5 + 3.9: rows 5..7 are covered, row 8 is not.
        CHECK(below_covered == w * 3);
        MESSAGE(std::string(fill_rule_name(rule))
                << ": horizon row: " << stats.fragments_without_plane_hit << " fragments dropped, "
                << horizon_covered << " far points kept");
        if (rule == FillRule::d3d) {
            CHECK(stats.fragments_without_plane_hit + horizon_covered == w);
            CHECK(stats.fragments_without_plane_hit > 0);
        } else {  // gl: the far edge is a top edge, which owns no centres under OpenGL's rule
            CHECK(stats.fragments_without_plane_hit == 0);
            CHECK(horizon_covered == 0);
        }
    }
}

TEST_CASE("raster: explain_raster_pixel replays the pass for one pixel") {
    // Two coplanar triangles covering the same pixels (equal depths: the lower id wins) and a
    // nearer one in front of part of them; plus a shared edge through pixel centres.
    const Camera camera = straight_camera(60.0f);
    const int w = 16, h = 12;
    const Tri far_a = {{{-5, -5, -4}, {5, -5, -4}, {0, 5, -4}}};
    const Tri near = {{{-0.2f, -0.2f, -2}, {0.2f, -0.2f, -2}, {0, 0.2f, -2}}};
    const Scene scene = make_scene({far_a, far_a, near}, 3);
    RasterStats stats;
    const VisibilityBuffer vis = rasterize_visibility(scene, camera, w, h, stats);
    for (const FillRule rule : both_rules) {
        RasterSettings settings;
        settings.fill_rule = rule;
        const VisibilityBuffer ruled = rasterize_visibility(scene, camera, w, h, stats, settings);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const RasterPixelExplanation e =
                    explain_raster_pixel(scene, camera, w, h, settings, x, y);
                CAPTURE(x);
                CAPTURE(y);
                // The replay finds the pass's winner at every pixel.
                CHECK(e.winner == ruled.primitive[static_cast<std::size_t>(y * w + x)]);
                for (const RasterCandidate& c : e.candidates) CHECK(c.edges.covered);
            }
    }
    // The centre pixel: all three cover it; 0 first, 1 ties with 0 and loses (equal depth, higher
    // id), 2 is nearer and wins.
    const RasterPixelExplanation e = explain_raster_pixel(scene, camera, w, h, {}, 8, 6);
    REQUIRE(e.candidates.size() == 3);
    CHECK(e.candidates[0].won_depth_test);
    CHECK(e.candidates[0].stored_primitive == -1);
    CHECK_FALSE(e.candidates[1].won_depth_test);
    CHECK(e.candidates[1].value.depth == e.candidates[1].stored_depth);
    CHECK(e.candidates[1].stored_primitive == 0);
    CHECK(e.candidates[2].won_depth_test);
    CHECK(e.candidates[2].value.depth < e.candidates[2].stored_depth);
    CHECK(e.winner == 2);
    CHECK(vis.primitive[6 * w + 8] == 2);
    CHECK(e.centre == FixedPoint{8 * 256 + 128, 6 * 256 + 128});

    // A centre exactly on a horizontal edge: owned under d3d by the triangle below (a top edge)
    // and under gl by the triangle above (a bottom edge). Screen-space corners on the 1/256 grid
    // via a coverage-only check of the edge bookkeeping.
    const EdgeSetup below = setup_edges(snap_to_fixed({2.5f, 3.5f}), snap_to_fixed({6.5f, 3.5f}),
                                        snap_to_fixed({4.5f, 7.5f}), FillRule::d3d);
    const EdgeValues on_edge = edge_values(below, 4, 3);
    CHECK(on_edge.wc == 0);  // E_ab: the horizontal edge through (4.5, 3.5)
    CHECK(on_edge.covered);
    const EdgeSetup below_gl = setup_edges(below.a, below.b, below.c, FillRule::gl);
    CHECK_FALSE(edge_values(below_gl, 4, 3).covered);
}
