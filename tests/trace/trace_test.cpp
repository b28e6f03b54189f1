#include <doctest/doctest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "ref/bvh/bvh.h"
#include "ref/core/error.h"
#include "ref/core/rng.h"
#include "ref/image/image.h"
#include "ref/modes/modes.h"
#include "ref/scene/camera.h"
#include "ref/scene/procedural.h"
#include "ref/trace/direct_light.h"
#include "ref/trace/ground_truth.h"
#include "ref/trace/raycast_gbuffer.h"
#include "ref/trace/rays_file.h"
#include "ref/trace/shade_basic.h"

using namespace fovref;
namespace fs = std::filesystem;

namespace {

void add_quad(Scene& scene, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, int material) {
    // Two triangles a b c and a c d, normals from the winding.
    const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    for (glm::vec3 p : {a, b, c, a, c, d}) {
        scene.positions.push_back(p);
        scene.normals.push_back(n);
        scene.uvs.push_back(glm::vec2(0.0f));
    }
    scene.material_ids.push_back(material);
    scene.material_ids.push_back(material);
}

// A 20 x 20 floor at y = 0 (normal +y), albedo 0.5, a point light of intensity 4 at height 2,
// a camera looking straight down from height 1.
Scene floor_scene(bool with_light) {
    Scene scene;
    scene.source = "test:floor";
    scene.materials.push_back(Material{"floor", glm::vec3(0.5f)});
    add_quad(scene, {-10, 0, -10}, {-10, 0, 10}, {10, 0, 10}, {10, 0, -10}, 0);
    if (with_light) {
        Light light;
        light.type = Light::Type::point;
        light.position = {0, 2, 0};
        light.intensity = glm::vec3(4.0f);
        scene.lights.push_back(light);
    }
    scene.camera = look_at({0, 1, 0}, {0, 0, 0}, {0, 0, -1}, 60.0f);
    finalize_scene(scene);
    return scene;
}

// An upward-facing point of the floor (material 0) with a grey albedo.
SurfacePoint floor_point(glm::vec3 position, float albedo) {
    SurfacePoint s;
    s.position = position;
    s.shading_normal = s.geometric_normal = {0, 1, 0};
    s.albedo = glm::vec3(albedo);
    s.material = 0;
    return s;
}

}  // namespace

TEST_CASE("direct light: a point light above a Lambertian floor gives albedo/pi * I / d^2") {
    Scene scene = floor_scene(true);
    Bvh bvh = build_bvh(scene.positions);
    // 3x3 screen: the centre pixel looks straight down at (0, 0, 0), right below the light.
    RaycastStats primary;
    GBuffer g = raycast_gbuffer(PrimaryView(scene, bvh, scene.camera, scene.camera), 3, 3, primary);
    REQUIRE(g.primitive_id.at(1, 1) >= 0.0f);
    SurfacePoint s;
    for (int c = 0; c < 3; ++c) {
        s.position[c] = g.world_position.at(1, 1, c);
        s.shading_normal[c] = g.shading_normal.at(1, 1, c);
        s.geometric_normal[c] = g.geometric_normal.at(1, 1, c);
        s.albedo[c] = g.albedo.at(1, 1, c);
    }
    s.material = 0;
    CHECK(std::fabs(s.position.x) < 1e-6f);
    ShadingStats stats;
    glm::vec3 l = shade_direct(scene, &bvh, s, scene.camera.position, 0, 4, 0, stats);
    // 0.5 / pi * 4 / 2^2 = 0.5 / pi.
    CHECK(l.x == doctest::Approx(0.5 / 3.14159265358979).epsilon(1e-6));
    CHECK(stats.shadow_rays == 1);
    CHECK(stats.shadow_rays_occluded == 0);
    // At (1, 0, 0): cos = 2/sqrt(5), d^2 = 5 -> 0.5/pi * 4 * 2 / 5^1.5.
    s.position = {1, 0, 0};
    l = shade_direct(scene, &bvh, s, scene.camera.position, 0, 4, 0, stats);
    CHECK(l.y == doctest::Approx(0.5 / 3.14159265358979 * 8.0 / std::pow(5.0, 1.5)).epsilon(1e-6));
}

TEST_CASE("direct light: a blocker casts a shadow, the light behind the surface casts no ray") {
    Scene scene = floor_scene(true);
    // A small blocker at height 1 facing down, between the light and the origin.
    scene.materials.push_back(Material{"blocker", glm::vec3(0.1f)});
    add_quad(scene, {-0.2f, 1, -0.2f}, {0.2f, 1, -0.2f}, {0.2f, 1, 0.2f}, {-0.2f, 1, 0.2f}, 1);
    scene.lights.clear();
    Light light;
    light.position = {0, 2, 0};
    light.intensity = glm::vec3(4.0f);
    scene.lights.push_back(light);
    finalize_scene(scene);
    Bvh bvh = build_bvh(scene.positions);
    SurfacePoint s = floor_point({0, 0, 0}, 0.5f);
    ShadingStats stats;
    CHECK(shade_direct(scene, &bvh, s, {0, 0.5f, 0.5f}, 0, 0, 0, stats) == glm::vec3(0.0f));
    CHECK(stats.shadow_rays_occluded == 1);
    // Seen from below, the floor's lit side faces away: no contribution, no shadow ray.
    s.position = {3, 0, 0};
    ShadingStats below;
    CHECK(shade_direct(scene, &bvh, s, {3, -1, 0}, 0, 0, 0, below) == glm::vec3(0.0f));
    CHECK(below.shadow_rays == 0);
    CHECK(below.lights_facing_away == 1);
}

TEST_CASE("direct light: emitters seen directly, and no shadow rays without lights") {
    Scene scene = floor_scene(false);
    scene.materials[0].emission = glm::vec3(0.5f);
    scene.lights.clear();
    finalize_scene(scene);  // the two emissive triangles become lights
    CHECK(scene.lights.size() == 2);
    Scene dark = floor_scene(false);
    CHECK(dark.lights.empty());
    SurfacePoint s = floor_point({0, 0, 0}, 0.5f);
    ShadingStats stats;
    CHECK(shade_direct(dark, nullptr, s, {0, 1, 0}, 0, 0, 0, stats) == glm::vec3(0.0f));
    CHECK(stats.shadow_rays == 0);
    dark.materials[0].emission = glm::vec3(0.5f);
    CHECK(shade_direct(dark, nullptr, s, {0, 1, 0}, 0, 0, 0, stats) == glm::vec3(0.5f));
    CHECK(shade_direct(dark, nullptr, s, {0, -1, 0}, 0, 0, 0, stats) ==
          glm::vec3(0.0f));  // back side
}

TEST_CASE("ground truth of a constant emitter equals the emission exactly") {
    Scene scene = floor_scene(false);
    scene.materials[0].emission = glm::vec3(0.5f);
    scene.materials[0].albedo = glm::vec3(0.0f);  // its own light adds nothing
    finalize_scene(scene);
    Bvh bvh = build_bvh(scene.positions);
    TraceStats primary;
    ShadingStats shading;
    Image image = render_ground_truth(scene, bvh, scene.camera, 0, 4, 3, primary, shading);
    for (float v : image.data) CHECK(v == 0.5f);
    CHECK(primary.rays == 16 * 12);
}

TEST_CASE("ray files: round trip, empty, truncated, NaN") {
    const fs::path dir = fs::temp_directory_path() / ("fovref-rays-" + std::to_string(getpid()));
    fs::create_directories(dir);
    Scene scene = floor_scene(true);
    std::vector<Ray> rays = random_rays(scene, 50, 7);
    for (const Ray& r : rays)
        CHECK(glm::dot(r.direction, r.direction) == doctest::Approx(1.0f).epsilon(1e-6));
    write_rays((dir / "r.bin").string(), rays);
    CHECK(fs::file_size(dir / "r.bin") == 50 * 32);
    std::vector<Ray> back = read_rays((dir / "r.bin").string());
    REQUIRE(back.size() == 50);
    CHECK(back[17].origin == rays[17].origin);
    CHECK(back[17].t_max == std::numeric_limits<float>::infinity());
    std::vector<Hit> hits = {Hit{1.5f, 3, 0.25f, 0.5f}, Hit{}};
    write_hits((dir / "h.bin").string(), hits);
    std::vector<Hit> hits_back = read_hits((dir / "h.bin").string());
    CHECK(hits_back[0] == hits[0]);
    CHECK(hits_back[1].t == -1.0f);
    CHECK(hits_back[1].primitive == -1);
    // Layout: the first record's bytes are the first ray's origin x as little-endian binary32.
    std::ifstream in(dir / "r.bin", std::ios::binary);
    float first = 0.0f;
    in.read(reinterpret_cast<char*>(&first), 4);
    CHECK(first == rays[0].origin.x);
    write_rays((dir / "empty.bin").string(), {});
    CHECK(read_rays((dir / "empty.bin").string()).empty());
    fs::resize_file(dir / "r.bin", 50 * 32 - 5);
    CHECK_THROWS_WITH_AS(read_rays((dir / "r.bin").string()), doctest::Contains("truncated"),
                         Error);
    rays[3].origin.y = std::nanf("");
    write_rays((dir / "nan.bin").string(), rays);
    CHECK_THROWS_WITH_AS(read_rays((dir / "nan.bin").string()), doctest::Contains("ray 3"), Error);
    rays[3].origin.y = 0.0f;
    rays[4].direction = glm::vec3(0.0f);
    write_rays((dir / "zero.bin").string(), rays);
    CHECK_THROWS_WITH_AS(read_rays((dir / "zero.bin").string()),
                         doctest::Contains("ray 4: the direction is zero"), Error);
    rays[4].direction = {0, 0, 1};
    rays[5].t_min = std::numeric_limits<float>::infinity();
    write_rays((dir / "inf.bin").string(), rays);
    CHECK_THROWS_WITH_AS(read_rays((dir / "inf.bin").string()), doctest::Contains("ray 5: t_min"),
                         Error);
    CHECK_THROWS_AS(read_rays((dir / "missing.bin").string()), Error);
    fs::remove_all(dir);
}

TEST_CASE("camera ray list: row-major pixel-centre rays that hit what the G-buffer pass sees") {
    Scene scene = floor_scene(true);
    std::vector<Ray> rays = camera_rays_list(scene.camera, 5, 4);
    REQUIRE(rays.size() == 20);
    Bvh bvh = build_bvh(scene.positions);
    RaycastStats stats;
    GBuffer g = raycast_gbuffer(PrimaryView(scene, bvh, scene.camera, scene.camera), 5, 4, stats);
    for (int k = 0; k < 20; ++k) {
        const Ray& ray = rays[static_cast<std::size_t>(k)];
        const Hit hit = trace_closest(bvh, ray, stats.primary);
        CHECK(static_cast<float>(hit.primitive) == g.primitive_id.at(k % 5, k / 5));
        // Ray k goes through the centre of pixel (k % 5, k / 5): it projects back there.
        glm::vec2 screen;
        float depth = 0.0f;
        REQUIRE(project_to_screen(scene.camera, tan_half_vfov(scene.camera), 5, 4,
                                  ray.origin + ray.direction, screen, depth));
        CHECK(screen.x == doctest::Approx(static_cast<float>(k % 5) + 0.5f).epsilon(1e-5));
        CHECK(screen.y == doctest::Approx(static_cast<float>(k / 5) + 0.5f).epsilon(1e-5));
    }
}

TEST_CASE("direct light: a quad light against E = Le cos cos A / d^2, and as two triangle lights") {
    // A 0.2 x 0.2 quad light at height 2 facing down over the floor point (0, 0, 0): small
    // enough that cos ~ 1 and d ~ 2 over it: E ~ Le A / d^2 = 3 * 0.04 / 4 = 0.03 (the exact
    // integral is within 0.5% of that). The mean over N = 4096 pixel indices has a relative
    // standard deviation below 0.5%; tolerance 2%.
    Scene scene = floor_scene(false);
    Light quad;
    quad.type = Light::Type::quad;
    quad.position = {-0.1f, 2, -0.1f};
    quad.edge_u = {0.2f, 0, 0};
    quad.edge_v = {0, 0, 0.2f};  // cross(u, v) = (0, -0.04, 0): facing down
    quad.intensity = glm::vec3(3.0f);
    scene.lights = {quad};
    finalize_scene(scene);
    Bvh bvh = build_bvh(scene.positions);
    SurfacePoint s = floor_point({0, 0, 0}, 1.0f);
    const int n = 4096;
    const double expected = 1.0 / 3.14159265358979 * 3.0 * 0.04 / 4.0;
    double sum = 0.0;
    ShadingStats stats;
    for (int p = 0; p < n; ++p)
        sum +=
            shade_direct(scene, &bvh, s, {0, 1, 0}, 0, static_cast<std::uint32_t>(p), 0, stats).x;
    CHECK(sum / n == doctest::Approx(expected).epsilon(0.02));
    CHECK(stats.shadow_rays == n);
    CHECK(stats.shadow_rays_occluded == 0);

    // The same quad as two triangle lights (same orientation) has the same expected value.
    Light t1 = quad, t2 = quad;
    t1.type = t2.type = Light::Type::triangle;
    t1.edge_u = {0.2f, 0, 0};
    t1.edge_v = {0.2f, 0, 0.2f};
    t2.edge_u = {0.2f, 0, 0.2f};
    t2.edge_v = {0, 0, 0.2f};
    scene.lights = {t1, t2};
    double sum_triangles = 0.0;
    for (int p = 0; p < n; ++p)
        sum_triangles +=
            shade_direct(scene, &bvh, s, {0, 1, 0}, 0, static_cast<std::uint32_t>(p), 0, stats).x;
    CHECK(sum_triangles / n == doctest::Approx(expected).epsilon(0.02));

    // Flipped, the quad faces away: no light and no shadow ray.
    std::swap(quad.edge_u, quad.edge_v);
    scene.lights = {quad};
    ShadingStats away;
    CHECK(shade_direct(scene, &bvh, s, {0, 1, 0}, 0, 0, 0, away) == glm::vec3(0.0f));
    CHECK(away.shadow_rays == 0);
    CHECK(away.lights_facing_away == 1);
}

TEST_CASE("direct light: an emissive panel lights the floor without shadowing itself") {
    Scene scene = floor_scene(false);
    scene.materials.push_back(Material{"panel", glm::vec3(0.0f)});
    scene.materials[1].emission = glm::vec3(2.0f);
    // A panel at height 1 facing down (the winding gives the normal -y).
    add_quad(scene, {-0.5f, 1, -0.5f}, {0.5f, 1, -0.5f}, {0.5f, 1, 0.5f}, {-0.5f, 1, 0.5f}, 1);
    finalize_scene(scene);
    REQUIRE(scene.lights.size() == 2);
    REQUIRE(glm::cross(scene.lights[0].edge_u, scene.lights[0].edge_v).y < 0.0f);
    Bvh bvh = build_bvh(scene.positions);
    SurfacePoint s = floor_point({0.05f, 0, 0.1f}, 0.5f);
    ShadingStats stats;
    for (std::uint32_t p = 0; p < 64; ++p)
        CHECK(shade_direct(scene, &bvh, s, {0, 0.5f, 0}, 0, p, 0, stats).x > 0.0f);
    CHECK(stats.shadow_rays == 128);
    CHECK(stats.shadow_rays_occluded == 0);
}

TEST_CASE("direct light: vertex normals opposite to the winding still light the front") {
    Scene scene = floor_scene(true);
    Bvh bvh = build_bvh(scene.positions);
    SurfacePoint s;
    s.position = {0, 0, 0};
    s.geometric_normal = {0, -1, 0};  // the winding says down
    s.shading_normal = {0, 1, 0};     // the vertex normals say up
    s.albedo = glm::vec3(0.5f);
    s.material = 0;
    ShadingStats stats;
    const glm::vec3 l = shade_direct(scene, &bvh, s, {0, 1, 0}, 0, 0, 0, stats);
    CHECK(l.x == doctest::Approx(0.5 / 3.14159265358979).epsilon(1e-6));
}

// No shadow rays without lights (SPEC: skip what the scene does not need): without lights the
// shading pass gets no BVH at all, and the image is the same bits as shading with the BVH at
// hand; neither traces a shadow ray, and the mode reports none.
TEST_CASE(
    "trace: without lights, shading without a BVH is bit-identical and traces no shadow ray") {
    Scene scene = make_procedural_scene("cornell");
    scene.lights.clear();  // the emissive triangles still glow; nothing to sample
    const Bvh bvh = build_bvh(scene.positions);
    const Camera camera = camera_at(scene, 0.0f);
    RaycastStats raycast;
    const GBuffer g = raycast_gbuffer(PrimaryView(scene, bvh, camera, camera), 64, 36, raycast);
    const ShadeInputs in{g.world_position, g.shading_normal, g.geometric_normal,
                         g.albedo,         g.material_id,    g.primitive_id};
    ShadingStats without, with;
    const Image a = shade_basic(scene, nullptr, in, camera, 0, without);
    const Image b = shade_basic(scene, &bvh, in, camera, 0, with);
    CHECK(canonical_sha256(a) == canonical_sha256(b));
    CHECK(without.shadow_trace.rays == 0);
    CHECK(with.shadow_trace.rays == 0);
    CHECK(without.shaded > 1000);
    double sum = 0.0;
    for (float v : a.data) sum += v;
    CHECK(sum > 0.0);  // the lamp itself is seen
    RenderSettings s;
    s.width = 64;
    s.height = 36;
    const FrameResult f = render(&scene, "basic", s).front();
    CHECK(f.counters.get("rays_shadow") == 0);
    CHECK(canonical_sha256(f.find("final")->image) == canonical_sha256(a));
}
