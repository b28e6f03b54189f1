// Cross-check of the two independent primary-visibility paths (SPEC §4): the rasterizer and the
// ray caster must agree on the primitive id at every pixel centre that no triangle edge passes
// near, and, where they agree on the primitive, on every attribute bit for bit: the rasterizer
// evaluates its attributes where the pixel's primary ray meets the triangle's plane, with the
// ray caster's arithmetic (docs/raster.md). Both are also measured against a binary64 ray-plane
// intersection, which neither shares code with.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>

#include "ref/modes/modes.h"
#include "ref/raster/rasterizer.h"
#include "ref/scene/procedural.h"
#include "ref/trace/raycast_gbuffer.h"
#include "tests/core/build_speed.h"

using namespace fovref;

namespace {

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// A pixel "touches an edge" when a triangle edge passes within about a pixel of its centre: in
// either G-buffer on its own, some pixel of its 3x3 neighbourhood shows another primitive than
// the centre (the outside of the screen counts as another). The two G-buffers are not compared
// here, so a pixel where they disagree while each is uniform around it is an interior mismatch.
bool uniform_around(const Image& ids, int x, int y) {
    const float id = ids.at(x, y);
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if (nx < 0 || ny < 0 || nx >= ids.width || ny >= ids.height) return false;
            if (ids.at(nx, ny) != id) return false;
        }
    return true;
}

bool touches_edge(const Image& a, const Image& b, int x, int y) {
    return !uniform_around(a, x, y) || !uniform_around(b, x, y);
}

}  // namespace

TEST_CASE(
    "rasterized and ray-cast G-buffers agree away from triangle edges, on every procedural scene") {
    const int width = 160, height = 90;
    for (const ProceduralSceneInfo& info : procedural_scenes()) {
        // (million in the optimised build only: build_speed.h)
        if (test::slow_build && info.name == "million") continue;
        CAPTURE(info.name);
        const Scene scene = make_procedural_scene(info.name);
        const Bvh bvh = build_bvh(scene.positions);
        for (float time : {0.0f, 1.5f}) {
            const Camera camera = camera_at(scene, time);
            RasterStats raster_stats;
            RaycastStats trace_stats;
            const GBuffer r = rasterize_gbuffer(scene, camera, camera, width, height, raster_stats);
            const GBuffer t = raycast_gbuffer(PrimaryView(scene, bvh, camera, camera), width,
                                              height, trace_stats);
            std::int64_t interior = 0, interior_mismatch = 0, edge = 0, edge_mismatch = 0;
            std::int64_t same_primitive = 0, attribute_differences = 0;
            for (int y = 0; y < height; ++y)
                for (int x = 0; x < width; ++x) {
                    const bool same = r.primitive_id.at(x, y) == t.primitive_id.at(x, y);
                    if (touches_edge(r.primitive_id, t.primitive_id, x, y)) {
                        ++edge;
                        edge_mismatch += same ? 0 : 1;
                    } else {
                        ++interior;
                        interior_mismatch += same ? 0 : 1;
                    }
                    if (!same || r.primitive_id.at(x, y) < 0.0f) continue;
                    ++same_primitive;
                    for (const Image GBuffer::*channel :
                         {&GBuffer::view_depth, &GBuffer::hit_distance, &GBuffer::world_position,
                          &GBuffer::shading_normal, &GBuffer::geometric_normal, &GBuffer::albedo,
                          &GBuffer::material_id, &GBuffer::motion}) {
                        const Image& a = r.*channel;
                        const Image& b = t.*channel;
                        for (int c = 0; c < a.channels; ++c)
                            if (!same_bits(a.at(x, y, c), b.at(x, y, c))) {
                                if (attribute_differences++ < 5)
                                    MESSAGE("pixel (" << x << ", " << y << ") channel " << c
                                                      << ": raster " << a.at(x, y, c) << ", ray "
                                                      << b.at(x, y, c));
                            }
                    }
                }
            MESSAGE(info.name << " t=" << time << ": interior pixels " << interior << " ("
                              << interior_mismatch << " differ), edge pixels " << edge << " ("
                              << edge_mismatch << " differ), " << same_primitive
                              << " pixels with the same primitive, " << attribute_differences
                              << " attribute values differ");
            // Away from edges the two must agree exactly on visibility, and "away from edges"
            // must be a real share of the screen (sphere-grid and million are mostly edges at
            // this size: small triangles).
            CHECK(interior_mismatch == 0);
            CHECK(interior >= width * height / 4);
            // Same primitive -> same ray, same plane arithmetic, same surface_at: 0 ulp apart in
            // every channel (depth, distance, position, normals, albedo, material, motion).
            CHECK(same_primitive >= width * height / 4);
            CHECK(attribute_differences == 0);
            // Edge pixels may differ (the rasterizer samples coverage in 1/256-pixel fixed point,
            // the ray caster in float): a disagreement needs an edge within ~1/256 px of the pixel
            // centre. Measured at most 1.9% of edge pixels (million); bound 3%.
            CHECK(edge_mismatch * 100 <= edge * 3);
        }
    }
}

TEST_CASE(
    "rasterized depth against a binary64 ray-plane intersection, grazing triangles included") {
    // For every covered pixel: the covering triangle's plane met by the same float primary ray,
    // in binary64 (plane from the float corners, t = n.(p0 - o) / n.d). The float result can be
    // no better than the conditioning allows: a relative change e of the ray's direction moves t
    // by about e / cos, cos = |n.d| / (|n| |d|), so the error is stated in units of
    // 2^-24 / cos. Measured at most 3.3 such units over the scenes at 320x180 (relative error
    // 8.2e-6 on checker-room's grazing triangles at cos 0.0022; 1.8e-6 elsewhere); bound 8.
    const int width = 320, height = 180;
    const double unit = std::ldexp(1.0, -24);
    for (const ProceduralSceneInfo& info : procedural_scenes()) {
        if (info.name == "million") continue;  // 1M triangles: covered by the cross-check above
        CAPTURE(info.name);
        const Scene scene = make_procedural_scene(info.name);
        const Camera camera = scene.camera;
        RasterStats stats;
        const GBuffer g = rasterize_gbuffer(scene, camera, camera, width, height, stats);
        const float tan_half = tan_half_vfov(camera);
        double worst_units = 0.0, worst_relative = 0.0, smallest_cos = 1.0;
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const float id = g.primitive_id.at(x, y);
                if (id < 0.0f) continue;
                const auto t = static_cast<std::size_t>(id);
                const glm::dvec3 p0(scene.positions[3 * t]), p1(scene.positions[3 * t + 1]),
                    p2(scene.positions[3 * t + 2]);
                const glm::dvec3 d(primary_ray_direction(camera, tan_half, width, height,
                                                         static_cast<float>(x) + 0.5f,
                                                         static_cast<float>(y) + 0.5f));
                const glm::dvec3 o(camera.position);
                const glm::dvec3 n = glm::cross(p1 - p0, p2 - p0);
                const double hit = glm::dot(n, p0 - o) / glm::dot(n, d);
                const double exact = glm::dot(hit * d, glm::dvec3(camera.forward));
                const double cosine = std::fabs(glm::dot(n, d)) / (glm::length(n) * glm::length(d));
                const double relative = std::fabs(g.view_depth.at(x, y) - exact) / exact;
                worst_relative = std::max(worst_relative, relative);
                worst_units = std::max(worst_units, relative * cosine / unit);
                smallest_cos = std::min(smallest_cos, cosine);
            }
        MESSAGE(info.name << ": worst relative depth error " << worst_relative << ", worst "
                          << worst_units << " x 2^-24 / cos, smallest cos " << smallest_cos);
        CHECK(worst_units <= 8.0);
    }
}

TEST_CASE("basic mode: --primary raster and --primary ray give the same image away from edges") {
    const Scene scene = make_procedural_scene("cornell");
    RenderSettings settings;
    settings.width = 96;
    settings.height = 54;
    settings.requested = {"all"};
    const std::vector<FrameResult> by_ray = render(&scene, "basic", settings);
    settings.params.set("primary", "raster");
    const std::vector<FrameResult> by_raster = render(&scene, "basic", settings);
    const Image& ids_ray = by_ray[0].find("gbuffer_primitive_id")->image;
    const Image& ids_raster = by_raster[0].find("gbuffer_primitive_id")->image;
    const Image& a = by_ray[0].find("final")->image;
    const Image& b = by_raster[0].find("final")->image;
    double max_difference = 0.0;
    std::int64_t compared = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            if (touches_edge(ids_ray, ids_raster, x, y)) continue;
            ++compared;
            for (int c = 0; c < 3; ++c)
                max_difference = std::max(
                    max_difference, static_cast<double>(std::fabs(a.at(x, y, c) - b.at(x, y, c))));
        }
    MESSAGE("basic ray vs raster: " << compared << " interior pixels, max radiance difference "
                                    << max_difference);
    CHECK(compared > a.width * a.height / 2);
    // Same light samples (same rand dimensions); the shading points differ by ~0.003 px, which
    // moves the radiance by about that fraction of its gradient: relative (to max(1, L)) 2e-4,
    // measured 9.4e-5 on cornell.
    CHECK(max_difference <= 2e-4);
}

TEST_CASE("a jittered rasterizer samples where the ray caster's jittered rays go") {
    // RasterSettings::sample on the 1/256 grid (0.25, 0.8125): the rasterizer's coverage and
    // attribute ray at (x + 0.25, y + 0.8125), the ray caster's jitter the same: away from edges
    // the same primitive and the same bits; and the jitter really moves the samples.
    const int width = 160, height = 90;
    const Offset2 sample{0.25f, 0.8125f};
    RasterSettings jittered;
    jittered.sample = sample;
    CHECK(raster_sample_shift(jittered.sample) == FixedPoint{-64, 80});
    for (const char* name : {"cornell", "checker-room"}) {
        CAPTURE(name);
        const Scene scene = make_procedural_scene(name);
        const Bvh bvh = build_bvh(scene.positions);
        const Camera camera = camera_at(scene, 0.0f);
        RasterStats raster_stats;
        RaycastStats trace_stats;
        const GBuffer r =
            rasterize_gbuffer(scene, camera, camera, width, height, raster_stats, jittered);
        const GBuffer centre =
            rasterize_gbuffer(scene, camera, camera, width, height, raster_stats);
        const GBuffer t = raycast_gbuffer(PrimaryView(scene, bvh, camera, camera), width, height,
                                          trace_stats, sample);
        std::int64_t interior_mismatch = 0, same = 0, differences = 0, moved = 0;
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                bool any = false;
                for (int c = 0; c < 3; ++c)
                    any = any || r.world_position.at(x, y, c) != centre.world_position.at(x, y, c);
                moved += any ? 1 : 0;
                const bool agree = r.primitive_id.at(x, y) == t.primitive_id.at(x, y);
                if (!agree) {
                    interior_mismatch += touches_edge(r.primitive_id, t.primitive_id, x, y) ? 0 : 1;
                    continue;
                }
                if (r.primitive_id.at(x, y) < 0.0f) continue;
                ++same;
                for (int c = 0; c < 3; ++c)
                    differences +=
                        same_bits(r.world_position.at(x, y, c), t.world_position.at(x, y, c)) ? 0
                                                                                              : 1;
                differences += same_bits(r.view_depth.at(x, y), t.view_depth.at(x, y)) ? 0 : 1;
            }
        CHECK(interior_mismatch == 0);
        CHECK(same >= width * height / 3);
        CHECK(differences == 0);
        CHECK(moved >= width * height / 3);
    }
}
