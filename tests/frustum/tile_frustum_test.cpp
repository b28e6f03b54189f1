// Tile frustum culling (ref/frustum/tile_frustum.h, Lund §3.7, §4.5): the frustum of a tile by
// hand, Lund's biased-box test against the exact one, and on every procedural scene the primary
// rays traced through each tile's culled BVH against the full BVH: is Lund's culling
// conservative? The same for shadow frusta towards a point light and for the composite modes'
// gaze buffer; the exported culled trees (culled_tree) traversed on their own.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "ref/bvh/bvh.h"
#include "ref/bvh/watertight.h"
#include "ref/core/rng.h"
#include "ref/frustum/tile_frustum.h"
#include "ref/modes/modes.h"
#include "ref/scene/camera.h"
#include "ref/scene/procedural.h"
#include "tests/core/build_speed.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

TEST_CASE("tile frustum: centre ray, factors, and the two box tests by hand") {
    // 90 degrees vertically on a 4 x 4 screen: t = 1, the plane at depth 1 spans [-1, 1] both ways
    const Camera camera = look_at({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90.0f);
    const TileFrustum f = tile_frustum(camera, 4, 4, 2, 0, 4, 2);  // the top-right quarter
    CHECK(f.a0 == 0.0f);
    CHECK(f.a1 == doctest::Approx(1.0f));
    CHECK(f.b0 == 0.0f);
    CHECK(f.b1 == doctest::Approx(1.0f));
    CHECK(f.width_factor == doctest::Approx(0.5f));
    CHECK(f.direction.z == doctest::Approx(-1.0f));  // V component 1, V = -z
    CHECK(f.direction.x == doctest::Approx(0.5f));
    CHECK(f.direction.y == doctest::Approx(0.5f));
    // A box around the centre ray at depth 10; one at the same depth in the bottom-left
    // quarter; one behind the camera; one just inside the frustum's corner (x = y = 9.9 at
    // depth 10, the frustum reaching 10)
    const auto both = [&](glm::vec3 lo, glm::vec3 hi) {
        return std::make_pair(lund_box_test(f, lo, hi), exact_box_test(f, lo, hi));
    };
    CHECK(both({4.5f, 4.5f, -10.5f}, {5.5f, 5.5f, -9.5f}) == std::make_pair(true, true));
    CHECK(both({-6.0f, -6.0f, -10.5f}, {-4.0f, -4.0f, -9.5f}) == std::make_pair(false, false));
    CHECK_FALSE(both({-1.0f, -1.0f, 5.0f}, {1.0f, 1.0f, 6.0f}).second);
    CHECK(both({9.8f, 9.8f, -10.0f}, {9.9f, 9.9f, -9.99f}) == std::make_pair(true, true));
    // Lund's test keeps more than the exact one: a long box below the frustum (y < 0, where the
    // tile has b >= 0) from depth 2 to 20; its biased box, widened by the cross-section at the
    // farthest depth (10 along x and y), holds the centre ray's point (1, 1, -2) at depth 2
    CHECK(both({2.5f, -1.0f, -20.0f}, {3.0f, -0.5f, -2.0f}) == std::make_pair(true, false));
}

namespace {

// Boxes tested by both tests: how many each keeps, and how many Lund's culls that the exact
// test keeps (lost hits if it ever happened).
struct BoxTally {
    std::int64_t exact_kept = 0, lund_kept = 0, lost = 0;
    void add(const TileFrustum& f, glm::vec3 lo, glm::vec3 hi) {
        const bool exact = exact_box_test(f, lo, hi);
        const bool lund = lund_box_test(f, lo, hi);
        exact_kept += exact;
        lund_kept += lund;
        lost += exact && !lund;
    }
};

}  // namespace

TEST_CASE("tile frustum: Lund's test keeps every box the exact test keeps (random boxes)") {
    const Camera camera = look_at({0.3f, 1.2f, 4.0f}, {-0.5f, 0.2f, -1.0f}, {0, 1, 0}, 50.0f);
    BoxTally tally;
    for (std::uint32_t i = 0; i < 20000; ++i) {
        const int tx = static_cast<int>(i % 8), ty = static_cast<int>((i / 8) % 5);
        const TileFrustum f =
            tile_frustum(camera, 128, 80, 16 * tx, 16 * ty, 16 * tx + 16, 16 * ty + 16);
        const glm::vec3 c{20.0f * rand_unit(1, i, 0) - 10.0f, 20.0f * rand_unit(1, i, 1) - 10.0f,
                          20.0f * rand_unit(1, i, 2) - 14.0f};
        const glm::vec3 half{0.05f + 2.0f * rand_unit(1, i, 3), 0.05f + 2.0f * rand_unit(1, i, 4),
                             0.05f + 2.0f * rand_unit(1, i, 5)};
        tally.add(f, c - half, c + half);
    }
    const auto [exact_kept, lund_kept, lost] = tally;
    MESSAGE("20000 boxes: exact keeps " << exact_kept << ", Lund keeps " << lund_kept
                                        << ", Lund culls " << lost << " the exact test keeps");
    CHECK(lost == 0);
    CHECK(lund_kept > exact_kept);  // conservative, at a cost
    CHECK(exact_kept > 100);
}

TEST_CASE(
    "tile frustum: where Lund's test could fail, it does not: wide fields of view, wide "
    "tiles, boxes straddling the camera plane or behind it, 1e-2 to 1e2 in size") {
    std::int64_t exact_kept = 0, lund_kept = 0, lost = 0, straddling = 0;
    for (std::uint32_t i = 0; i < 50000; ++i) {
        const float fov = 20.0f + 150.0f * rand_unit(2, i, 9);
        const glm::vec3 target{rand_unit(2, i, 10) * 2 - 1, rand_unit(2, i, 11) * 2 - 1,
                               rand_unit(2, i, 12) * 2 - 1};
        const Camera camera = look_at({0, 0, 0}, target, {0.3f, 1, 0.1f}, fov);
        const int size = 1 + static_cast<int>(64 * rand_unit(2, i, 13));
        const int x0 = static_cast<int>(63 * rand_unit(2, i, 14));
        const int y0 = static_cast<int>(35 * rand_unit(2, i, 15));
        const TileFrustum f =
            tile_frustum(camera, 64, 36, x0, y0, std::min(x0 + size, 64), std::min(y0 + size, 36));
        const float scale = std::pow(10.0f, 4.0f * rand_unit(2, i, 16) - 2.0f);
        const glm::vec3 c{(rand_unit(2, i, 0) * 2 - 1) * scale,
                          (rand_unit(2, i, 1) * 2 - 1) * scale,
                          (rand_unit(2, i, 2) * 2 - 1) * scale};
        const glm::vec3 h{rand_unit(2, i, 3) * scale, rand_unit(2, i, 4) * scale,
                          rand_unit(2, i, 5) * scale};
        const bool exact = exact_box_test(f, c - h, c + h), lund = lund_box_test(f, c - h, c + h);
        exact_kept += exact;
        lund_kept += lund;
        lost += exact && !lund;
        float near = INFINITY, far = -INFINITY;
        for (int k = 0; k < 8; ++k) {
            const glm::vec3 q{(k & 1) ? c.x + h.x : c.x - h.x, (k & 2) ? c.y + h.y : c.y - h.y,
                              (k & 4) ? c.z + h.z : c.z - h.z};
            near = std::min(near, glm::dot(q - f.origin, f.view));
            far = std::max(far, glm::dot(q - f.origin, f.view));
        }
        straddling += near < 0.0f && far > 0.0f;
    }
    MESSAGE("50000 boxes (" << straddling << " straddling the camera plane): exact keeps "
                            << exact_kept << ", Lund keeps " << lund_kept << ", Lund culls " << lost
                            << " the exact test keeps");
    CHECK(lost == 0);
    CHECK(straddling > 10000);
}

TEST_CASE("tile frustum: the exact test against sampling (120 boxes, a 120-degree camera)") {
    // a box it keeps has no separating direction among 20000 sampled ones; one it culls has no
    // point inside the frustum among 20000 sampled ones
    const Camera camera = look_at({0, 0, 0}, {0.4f, -0.3f, -1.0f}, {0, 1, 0}, 120.0f);
    const TileFrustum f = tile_frustum(camera, 64, 36, 0, 0, 40, 20);
    const glm::dvec3 e[4] = {glm::dvec3(f.view + f.a0 * f.right + f.b0 * f.up),
                             glm::dvec3(f.view + f.a1 * f.right + f.b0 * f.up),
                             glm::dvec3(f.view + f.a1 * f.right + f.b1 * f.up),
                             glm::dvec3(f.view + f.a0 * f.right + f.b1 * f.up)};
    int kept = 0, culled = 0;
    for (std::uint32_t i = 0; i < 120; ++i) {
        const glm::vec3 c{rand_unit(3, i, 0) * 8 - 4, rand_unit(3, i, 1) * 8 - 4,
                          rand_unit(3, i, 2) * 8 - 4};
        const glm::vec3 h{0.05f + rand_unit(3, i, 3), 0.05f + rand_unit(3, i, 4),
                          0.05f + rand_unit(3, i, 5)};
        const glm::vec3 lo = c - h, hi = c + h;
        if (exact_box_test(f, lo, hi)) {
            ++kept;
            for (std::uint32_t k = 0; k < 20000; ++k) {
                const glm::dvec3 n{rand_unit(4, k, 0) * 2 - 1, rand_unit(4, k, 1) * 2 - 1,
                                   rand_unit(4, k, 2) * 2 - 1};
                bool inside_dual = true, below = true;
                for (const glm::dvec3& edge : e)
                    inside_dual = inside_dual && glm::dot(n, edge) >= 0;
                for (int q = 0; q < 8 && inside_dual; ++q) {
                    const glm::dvec3 p{(q & 1) ? hi.x : lo.x, (q & 2) ? hi.y : lo.y,
                                       (q & 4) ? hi.z : lo.z};
                    below = below && glm::dot(n, p - glm::dvec3(f.origin)) < 0;
                }
                REQUIRE_FALSE((inside_dual && below));
            }
        } else {
            ++culled;
            for (std::uint32_t k = 0; k < 20000; ++k) {
                const glm::dvec3 p{lo.x + (hi.x - lo.x) * rand_unit(5, k, 0),
                                   lo.y + (hi.y - lo.y) * rand_unit(5, k, 1),
                                   lo.z + (hi.z - lo.z) * rand_unit(5, k, 2)};
                const glm::dvec3 d = p - glm::dvec3(f.origin);
                const double z = glm::dot(d, glm::dvec3(f.view));
                if (!(z > 0)) continue;
                const double a = glm::dot(d, glm::dvec3(f.right)) / z;
                const double b = glm::dot(d, glm::dvec3(f.up)) / z;
                REQUIRE_FALSE((a >= f.a0 && a <= f.a1 && b >= f.b0 && b <= f.b1));
            }
        }
    }
    CHECK(kept > 10);
    CHECK(culled > 10);
}

TEST_CASE(
    "tile frustum: on every procedural scene every primary ray hits through its tile's "
    "culled BVH what it hits through the whole BVH") {
    for (const std::string name :
         {"cornell", "sphere-grid", "checker-room", "glossy-floor", "million"}) {
        if (test::slow_build && name == "million") continue;  // (build_speed.h)
        CAPTURE(name);
        const Scene scene = make_procedural_scene(name);
        const Bvh bvh = build_bvh(scene.positions);
        const Camera camera = camera_at(scene, 0.0f);
        const int width = 64, height = 36, tile = 16;
        const float tan_half = tan_half_vfov(camera);
        std::int64_t rays = 0, lost_lund = 0, lost_exact = 0, kept_lund = 0, kept_exact = 0;
        std::int64_t triangles_lund = 0, triangles_exact = 0;
        for (int y0 = 0; y0 < height; y0 += tile)
            for (int x0 = 0; x0 < width; x0 += tile) {
                const int x1 = std::min(x0 + tile, width), y1 = std::min(y0 + tile, height);
                const TileFrustum f = tile_frustum(camera, width, height, x0, y0, x1, y1);
                CullOptions lund_options, exact_options;
                exact_options.exact = true;
                const TileCulling lund = cull_bvh(bvh, f, lund_options);
                const TileCulling exact = cull_bvh(bvh, f, exact_options);
                kept_lund += lund.nodes_kept;
                kept_exact += exact.nodes_kept;
                triangles_lund += lund.triangles_kept;
                triangles_exact += exact.triangles_kept;
                for (int y = y0; y < y1; ++y)
                    for (int x = x0; x < x1; ++x) {
                        Ray ray;
                        ray.origin = camera.position;
                        ray.direction = primary_ray_direction(camera, tan_half, width, height,
                                                              static_cast<float>(x) + 0.5f,
                                                              static_cast<float>(y) + 0.5f);
                        TraceStats stats;
                        const Hit full = trace_closest(bvh, ray, stats);
                        ++rays;
                        lost_lund += !(trace_culled(bvh, lund, ray) == full);
                        lost_exact += !(trace_culled(bvh, exact, ray) == full);
                    }
            }
        MESSAGE(name << ": " << rays << " rays; nodes kept Lund " << kept_lund << ", exact "
                     << kept_exact << "; triangles kept Lund " << triangles_lund << ", exact "
                     << triangles_exact << "; hits lost Lund " << lost_lund << ", exact "
                     << lost_exact);
        CHECK(lost_lund == 0);
        CHECK(lost_exact == 0);
        CHECK(triangles_lund >= triangles_exact);
    }
}

TEST_CASE(
    "tile frustum: trimming, the entry point and bridging change the tree, not its "
    "triangles") {
    const Scene scene = make_procedural_scene("sphere-grid");
    const Bvh bvh = build_bvh(scene.positions);
    const Camera camera = camera_at(scene, 0.0f);
    const TileFrustum f = tile_frustum(camera, 64, 36, 48, 20, 64, 36);
    CullOptions none;
    none.trim = none.entry = none.bridge = false;
    const TileCulling plain = cull_bvh(bvh, f, none);
    const TileCulling all = cull_bvh(bvh, f);
    CHECK(plain.triangles_kept == all.triangles_kept);
    CHECK(plain.leaves_kept == all.leaves_kept);
    CHECK(plain.entry == 0u);
    CHECK(plain.nodes_trimmed == 0);
    CHECK(plain.nodes_bridged == 0);
    CHECK(all.nodes_kept + all.nodes_bridged + all.nodes_trimmed <=
          plain.nodes_kept + all.nodes_trimmed);
    CHECK(all.nodes_kept < plain.nodes_kept);
    CHECK(all.bytes() == all.nodes_kept * 32);
    MESSAGE("sphere-grid, one corner tile: "
            << plain.nodes_kept
            << " nodes kept without the "
               "optimisations, "
            << all.nodes_kept << " with them (" << all.nodes_trimmed << " trimmed, "
            << all.nodes_bridged << " bridged, entry at depth " << all.entry_depth << "); "
            << all.triangles_kept << " triangles");
}

TEST_CASE(
    "frustum_cull stage (basic, frustum=lund|exact): per-tile buffers, no hit lost, the "
    "image unchanged, parameters checked") {
    const Scene scene = make_procedural_scene("checker-room");
    RenderSettings s;
    s.width = 100;
    s.height = 60;
    s.requested = {"all"};
    const FrameResult plain = render(&scene, "basic", s).at(0);
    CHECK(plain.find("frustum_tiles") == nullptr);
    for (const std::string test : {"lund", "exact"}) {
        CAPTURE(test);
        s.params =
            Params(std::map<std::string, std::string>{{"frustum", test}, {"tile_size", "32"}});
        const FrameResult f = render(&scene, "basic", s).at(0);
        const Image& tiles = f.find("frustum_tiles")->image;
        CHECK(tiles.width == 4);  // ceil(100 / 32)
        CHECK(tiles.height == 2);
        CHECK(tiles.channels == 6);
        CHECK(f.counters.get("frustum_tiles") == 8);
        CHECK(f.counters.get("frustum_hits_lost") == 0);
        // the traversal with and without culling: every pixel's ray, fewer BVH2 visits culled
        CHECK(f.counters.get("frustum_rays") == 100 * 60);
        CHECK(f.counters.get("frustum_visits_culled") > 0);
        CHECK(f.counters.get("frustum_visits_culled") < f.counters.get("frustum_visits_unculled"));
        for (const float lost : f.find("frustum_hit_lost")->image.data) REQUIRE(lost == 0.0f);
        const Image& a = f.find("final")->image;
        const Image& b = plain.find("final")->image;
        CHECK(std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)) == 0);
        double triangles = 0.0;
        for (int k = 0; k < 8; ++k) triangles += tiles.data[static_cast<std::size_t>(6 * k + 2)];
        CHECK(triangles == static_cast<double>(f.counters.get("frustum_triangles_kept")));
    }
    const auto message = [&](std::map<std::string, std::string> params) {
        RenderSettings r = s;
        r.params = Params(std::move(params));
        return test::error_message([&] { render(&scene, "basic", r); });
    };
    CHECK(test::contains(message({{"tile_size", "16"}}), "add frustum=lund"));
    CHECK(test::contains(message({{"frustum", "hunt"}}), "parameter 'frustum'"));
    CHECK(test::contains(message({{"frustum", "lund"}, {"tile_size", "0"}}), "tile_size"));
}

TEST_CASE(
    "shadow frustum: apex at the light, every point inside, Lund's test conservative on "
    "random boxes, no frustum for a spread of 90 degrees or more") {
    const glm::vec3 light{1.0f, 4.0f, 2.0f};
    std::int64_t boxes = 0;
    BoxTally tally;
    for (std::uint32_t tile = 0; tile < 50; ++tile) {
        // a tile's shadow-ray origins: a patch of a tilted plane below the light
        std::vector<glm::vec3> points;
        const glm::vec3 centre{6.0f * rand_unit(2, tile, 0) - 3.0f, 0.5f * rand_unit(2, tile, 1),
                               6.0f * rand_unit(2, tile, 2) - 3.0f};
        const float extent = 0.02f + 1.5f * rand_unit(2, tile, 3);
        for (std::uint32_t k = 0; k < 40; ++k)
            points.push_back(centre + extent * glm::vec3(rand_unit(3, tile * 40 + k, 0) - 0.5f,
                                                         0.3f * rand_unit(3, tile * 40 + k, 1),
                                                         rand_unit(3, tile * 40 + k, 2) - 0.5f));
        TileFrustum f;
        REQUIRE(shadow_frustum(light, points, f));
        CHECK(f.origin == light);
        CHECK(std::fabs(glm::dot(f.right, f.view)) < 1e-6f);
        CHECK(std::fabs(glm::dot(f.up, f.view)) < 1e-6f);
        CHECK(std::fabs(glm::dot(f.right, f.up)) < 1e-6f);
        for (const glm::vec3& p : points) {
            // every point (a zero-size box) is in the pyramid, by both tests
            REQUIRE(exact_box_test(f, p, p));
            REQUIRE(lund_box_test(f, p, p));
        }
        for (std::uint32_t i = 0; i < 400; ++i, ++boxes) {
            const auto b = static_cast<std::uint32_t>(boxes);
            const glm::vec3 c = centre + glm::vec3(8.0f * rand_unit(4, b, 0) - 4.0f,
                                                   6.0f * rand_unit(4, b, 1) - 1.0f,
                                                   8.0f * rand_unit(4, b, 2) - 4.0f);
            const glm::vec3 half{0.02f + 0.5f * rand_unit(4, b, 3),
                                 0.02f + 0.5f * rand_unit(4, b, 4),
                                 0.02f + 0.5f * rand_unit(4, b, 5)};
            tally.add(f, c - half, c + half);
        }
    }
    const auto [exact_kept, lund_kept, lost] = tally;
    MESSAGE(boxes << " boxes against 50 shadow frusta: exact keeps " << exact_kept
                  << ", Lund keeps " << lund_kept << ", Lund culls " << lost
                  << " the exact test keeps");
    CHECK(lost == 0);
    CHECK(exact_kept > 100);
    CHECK(lund_kept >= exact_kept);
    // rays spreading close to 90 degrees: a wide flat grid 1e-4 beyond the light along a
    // generic direction n (so the basis is not axis-aligned and rounds); every point inside,
    // by both tests, or no frustum
    int grazing = 0;
    for (std::uint32_t t = 0; t < 200; ++t) {
        const glm::vec3 n = glm::normalize(glm::vec3(
            rand_unit(6, t, 0) - 0.5f, -1.0f - rand_unit(6, t, 1), rand_unit(6, t, 2) - 0.5f));
        const glm::vec3 x_axis = glm::normalize(glm::cross(n, glm::vec3(0.3f, 0.1f, 1.0f)));
        const glm::vec3 z_axis = glm::cross(n, x_axis);
        std::vector<glm::vec3> grid;
        for (int i = -4; i <= 4; ++i)
            for (int j = -4; j <= 4; ++j)
                grid.push_back(light + 0.3f * static_cast<float>(i) * x_axis +
                               0.3f * static_cast<float>(j) * z_axis + 1e-4f * n);
        TileFrustum g;
        if (!shadow_frustum(light, grid, g)) continue;
        ++grazing;
        for (const glm::vec3& p : grid) {
            REQUIRE(exact_box_test(g, p, p));
            REQUIRE(lund_box_test(g, p, p));
        }
    }
    MESSAGE(grazing << " of 200 grazing grids got a frustum, every point inside it");
    CHECK(grazing > 0);
    // no frustum: no point, a point at the light, points on both sides of it
    TileFrustum f;
    CHECK_FALSE(shadow_frustum(light, {}, f));
    CHECK_FALSE(shadow_frustum(light, {light}, f));
    CHECK_FALSE(shadow_frustum(light, {light + glm::vec3(1, 0, 0), light - glm::vec3(1, 0, 0)}, f));
    CHECK(shadow_frustum(light, {light + glm::vec3(1, 0, 0), light + glm::vec3(0, 0, 1)}, f));
}

TEST_CASE(
    "frustum_shadow=on: on every procedural scene with a point light, every shadow ray's "
    "occlusion through its tile's shadow frustum is the whole BVH's") {
    // (million, the fourth point-lit scene, in optimised builds only: its 1 M-node culling
    // takes most of a minute at -O0 and under ASan; the bench's shadow rows cover it)
    std::vector<std::string> scenes = {"sphere-grid", "checker-room", "glossy-floor"};
    if (!test::slow_build) scenes.push_back("million");
    for (const std::string& name : scenes) {
        CAPTURE(name);
        const Scene scene = make_procedural_scene(name);
        RenderSettings s;
        s.width = 64;
        s.height = 36;
        s.requested = {"frustum_shadow_lost", "frustum_shadow_tiles"};
        for (const std::string test : {"lund", "exact"}) {
            CAPTURE(test);
            if (name == "million" && test == "exact") continue;  // CI time: Lund's on million
            s.params = Params(std::map<std::string, std::string>{
                {"frustum", test}, {"tile_size", "16"}, {"frustum_shadow", "on"}});
            const FrameResult f = render(&scene, "basic", s).at(0);
            MESSAGE(name << ", " << test << ": " << f.counters.get("frustum_shadow_rays")
                         << " shadow rays, " << f.counters.get("frustum_shadow_nodes_kept")
                         << " nodes kept, " << f.counters.get("frustum_shadow_tiles_unculled")
                         << " tiles unculled, " << f.counters.get("frustum_shadow_lost")
                         << " lost");
            CHECK(f.counters.get("frustum_shadow_rays") > 200);
            CHECK(f.counters.get("frustum_shadow_lost") == 0);
            for (const float lost : f.find("frustum_shadow_lost")->image.data)
                REQUIRE(lost == 0.0f);
            CHECK(f.find("frustum_shadow_tiles")->image.width == 4);
        }
    }
    // cornell has quad lights only: a clear error; frustum_light must name a point light
    const Scene cornell = make_procedural_scene("cornell");
    RenderSettings s;
    s.width = 32;
    s.height = 18;
    s.requested = {"frustum_shadow_lost"};
    s.params =
        Params(std::map<std::string, std::string>{{"frustum", "lund"}, {"frustum_shadow", "on"}});
    CHECK(test::contains(test::error_message([&] { render(&cornell, "basic", s); }),
                         "the scene has no point light"));
    s.params = Params(std::map<std::string, std::string>{
        {"frustum", "lund"}, {"frustum_shadow", "on"}, {"frustum_light", "7"}});
    CHECK(test::contains(test::error_message([&] { render(&cornell, "basic", s); }),
                         "parameter 'frustum_light'"));
}

TEST_CASE(
    "frustum culling of the composite modes' gaze buffer: tiles over its window, every pixel "
    "inside the gaze circle checked, no hit lost, the image unchanged, refused without one") {
    const Scene scene = make_procedural_scene("checker-room");
    for (const std::string mode : {"cfov", "ckfov"}) {
        CAPTURE(mode);
        RenderSettings s;
        s.width = 160;
        s.height = 90;
        s.requested = {"final"};
        const FrameResult plain = render(&scene, mode, s).at(0);
        s.requested = {"final", "gaze_frustum_tiles", "gaze_frustum_hit_lost",
                       "gaze_frustum_shadow_lost"};
        s.params = Params(std::map<std::string, std::string>{
            {"frustum", "lund"}, {"tile_size", "8"}, {"frustum_shadow", "on"}});
        const FrameResult f = render(&scene, mode, s).at(0);
        const std::int64_t gaze_pixels = f.counters.get("gaze_pixels_traced");
        MESSAGE(mode << ": " << gaze_pixels << " gaze pixels, "
                     << f.counters.get("gaze_frustum_tiles") << " tiles, "
                     << f.counters.get("gaze_frustum_nodes_kept") << " nodes kept, "
                     << f.counters.get("gaze_frustum_shadow_rays") << " shadow rays");
        CHECK(gaze_pixels > 100);
        CHECK(f.counters.get("gaze_frustum_hits_lost") == 0);
        CHECK(f.counters.get("gaze_frustum_shadow_lost") == 0);
        // every traced gaze pixel faces checker-room's light or not: at most one shadow ray each
        CHECK(f.counters.get("gaze_frustum_shadow_rays") <= gaze_pixels);
        CHECK(f.counters.get("gaze_frustum_shadow_rays") > gaze_pixels / 2);
        const Image& lost = f.find("gaze_frustum_hit_lost")->image;
        // the gaze window: a pixel wider than the circle on each side (not clipped here)
        CHECK(lost.width >= 2 * f.counters.get("gaze_radius_px"));
        CHECK(lost.height >= 2 * f.counters.get("gaze_radius_px"));
        CHECK(lost.width < s.width);
        CHECK(f.find("gaze_frustum_tiles")->image.width == (lost.width + 7) / 8);
        const Image& a = f.find("final")->image;
        const Image& b = plain.find("final")->image;
        CHECK(std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)) == 0);
    }
    RenderSettings s;
    s.width = 32;
    s.height = 18;
    s.params = Params(std::map<std::string, std::string>{{"frustum", "lund"}});
    CHECK(test::contains(test::error_message([&] { render(&scene, "kfov", s); }),
                         "needs gaze_angle > 0"));
}

namespace {

// The slab test of a ray's segment against a box in binary64, widened like trace_culled's
bool meets(const Ray& ray, glm::vec3 lo, glm::vec3 hi) {
    double t0 = std::max(0.0, static_cast<double>(ray.t_min)), t1 = ray.t_max;
    for (int k = 0; k < 3; ++k) {
        const double pad = (std::fabs(lo[k]) + std::fabs(hi[k]) + 1.0) * 0x1p-20;
        const double o = ray.origin[k], d = ray.direction[k];
        if (d == 0.0) {
            if (o < lo[k] - pad || o > hi[k] + pad) return false;
            continue;
        }
        double a = (lo[k] - pad - o) / d, b = (hi[k] + pad - o) / d;
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
        if (t0 > t1) return false;
    }
    return true;
}

// An independent traversal of culled_tree's records (the format `fovref rays cull` writes):
// from record 0, children at first and first + 1, leaves' triangles in the BVH2's leaf order;
// the closest hit, lowest t then lowest primitive id. Counts the empty slots it meets.
Hit trace_records(const Bvh& bvh, const std::vector<BvhNode>& tree, const Ray& ray) {
    Hit best;
    if (tree.empty()) return best;
    const WatertightRay r = make_watertight_ray(ray.origin, ray.direction, ray.t_min, ray.t_max);
    std::vector<std::uint32_t> stack = {0};
    while (!stack.empty()) {
        const BvhNode& node = tree[stack.back()];
        stack.pop_back();
        if (node.count == 0 && node.first == culled_tree_empty) continue;  // an empty slot
        if (!meets(ray, node.bounds_min, node.bounds_max)) continue;
        if (node.count == 0) {
            REQUIRE(node.first + 1 < tree.size());
            stack.push_back(node.first);
            stack.push_back(node.first + 1);
            continue;
        }
        for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
            float t, u, v;
            const glm::vec3* p = &bvh.triangle_corners[3 * static_cast<std::size_t>(k)];
            if (!intersect_watertight(r, p[0], p[1], p[2], t, u, v)) continue;
            const auto primitive = static_cast<std::int32_t>(bvh.primitives[k]);
            if (best.primitive < 0 || t < best.t || (t == best.t && primitive < best.primitive))
                best = Hit{t, primitive, u, v};
        }
    }
    return best;
}

}  // namespace

TEST_CASE(
    "culled_tree (what `rays cull` exports): traversed on its own, every tile's records give "
    "every primary ray the whole BVH's hit, under every option") {
    for (const std::string name : {"cornell", "checker-room", "glossy-floor"}) {
        CAPTURE(name);
        const Scene scene = make_procedural_scene(name);
        const Bvh bvh = build_bvh(scene.positions);
        const Camera camera = camera_at(scene, 0.0f);
        const int width = 48, height = 32, tile = 16;
        const float tan_half = tan_half_vfov(camera);
        for (int variant = 0; variant < 4; ++variant) {
            CullOptions options;  // all on; then bridging off, trimming off, entry off
            options.bridge = variant != 1;
            options.trim = variant != 2;
            options.entry = variant != 3;
            options.exact = variant == 3;
            CAPTURE(variant);
            std::int64_t lost = 0, rays = 0;
            for (int y0 = 0; y0 < height; y0 += tile)
                for (int x0 = 0; x0 < width; x0 += tile) {
                    const TileCulling c = cull_bvh(
                        bvh, tile_frustum(camera, width, height, x0, y0, x0 + tile, y0 + tile),
                        options);
                    const std::vector<BvhNode> tree = culled_tree(bvh, c, options);
                    if (options.bridge && options.trim)
                        CHECK(static_cast<std::int64_t>(tree.size()) == c.nodes_kept);
                    else
                        CHECK(static_cast<std::int64_t>(tree.size()) >= c.nodes_kept);
                    for (int y = y0; y < y0 + tile; ++y)
                        for (int x = x0; x < x0 + tile; ++x) {
                            Ray ray;
                            ray.origin = camera.position;
                            ray.direction = primary_ray_direction(camera, tan_half, width, height,
                                                                  static_cast<float>(x) + 0.5f,
                                                                  static_cast<float>(y) + 0.5f);
                            TraceStats stats;
                            ++rays;
                            lost +=
                                !(trace_records(bvh, tree, ray) == trace_closest(bvh, ray, stats));
                        }
                }
            CHECK(rays == width * height);
            CHECK(lost == 0);
        }
    }
    // nothing kept: no record
    const Scene scene = make_procedural_scene("cornell");
    const Bvh bvh = build_bvh(scene.positions);
    TileCulling none;
    none.kept.assign(bvh.nodes.size(), 0);
    CHECK(culled_tree(bvh, none, CullOptions{}).empty());
}
