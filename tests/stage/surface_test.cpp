#include <doctest/doctest.h>

#include "ref/core/error.h"
#include "ref/raster/gbuffer.h"
#include "ref/scene/procedural.h"
#include "ref/scene/surface.h"

using namespace fovref;

TEST_CASE("surface_at: corners, interpolation and the texture lookup") {
    Scene scene;
    scene.source = "test";
    scene.materials.push_back(Material{"m", {0.5f, 0.5f, 0.5f}});
    scene.positions = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
    scene.normals = {{0, 0, 1}, {0, 0, 1}, {0, 1, 0}};
    scene.uvs = {{0, 0}, {1, 0}, {0, 1}};
    scene.material_ids = {0};
    finalize_scene(scene);
    SurfacePoint corner1 = surface_at(scene, 0, 1.0f, 0.0f);
    CHECK(corner1.position == glm::vec3(2, 0, 0));
    CHECK(corner1.uv == glm::vec2(1, 0));
    SurfacePoint mid = surface_at(scene, 0, 0.25f, 0.5f);
    CHECK(mid.position == glm::vec3(0.5f, 1.0f, 0.0f));
    CHECK(mid.geometric_normal == glm::vec3(0, 0, 1));
    // Shading normal: 0.5 (0,0,1) + 0.5 (0,1,0) normalised.
    CHECK(mid.shading_normal.y == doctest::Approx(0.70710678f).epsilon(1e-6));
    CHECK(mid.shading_normal.z == doctest::Approx(0.70710678f).epsilon(1e-6));
    CHECK(mid.albedo == glm::vec3(0.5f));
    CHECK(mid.material == 0);
}

TEST_CASE("project_to_screen inverts primary_ray_direction") {
    Camera camera = look_at({1, 2, 3}, {0.3f, 1.5f, -4}, {0, 1, 0}, 50.0f);
    const float tan_half = tan_half_vfov(camera);
    for (float x : {0.5f, 13.25f, 99.75f})
        for (float y : {0.5f, 20.0f, 55.5f}) {
            glm::vec3 d = primary_ray_direction(camera, tan_half, 100, 56, x, y);
            glm::vec2 screen;
            float depth = 0.0f;
            REQUIRE(project_to_screen(camera, tan_half, 100, 56, camera.position + 7.0f * d, screen,
                                      depth));
            CHECK(screen.x == doctest::Approx(x).epsilon(1e-5));  // float round trip: ~1e-5 px
            CHECK(screen.y == doctest::Approx(y).epsilon(1e-5));
            CHECK(depth == doctest::Approx(7.0f * glm::dot(d, camera.forward)).epsilon(1e-6));
        }
    glm::vec2 screen;
    float depth = 0.0f;
    CHECK_FALSE(project_to_screen(camera, tan_half, 100, 56, camera.position - camera.forward,
                                  screen, depth));
}

TEST_CASE("G-buffer: background values and SPEC §4 buffer names") {
    GBuffer g(4, 3);
    CHECK(g.primitive_id.at(3, 2) == -1.0f);
    CHECK(g.material_id.at(0, 0) == -1.0f);
    CHECK(g.motion.channels == 2);
    FrameResult r;
    add_gbuffer(r, g);
    const auto names = gbuffer_names();
    REQUIRE(r.buffers.size() == names.size());
    for (std::size_t k = 0; k < names.size(); ++k) CHECK(r.buffers[k].name == names[k]);
}
