// Procedural scenes (SPEC §2): every scene builds, is reproducible bit for bit, and satisfies the
// invariants the later stages rely on (unit normals, no zero-area triangles, valid indices,
// consistent winding, lights, a camera that looks into the scene); plus per-scene facts from
// docs/procedural-scenes.md (exact triangle counts, bounds, materials, the checker texture).
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "ref/core/error.h"
#include "ref/core/vec.h"
#include "ref/scene/procedural.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

namespace {

// Printable forms, so that failed equality checks show both sides (doctest cannot print glm).
std::string show(glm::vec3 v) {
    std::ostringstream out;
    out.precision(9);
    out << "(" << v.x << ", " << v.y << ", " << v.z << ")";
    return out.str();
}
std::string show(const Bounds& b) { return show(b.min) + " - " + show(b.max); }
std::string show(const Camera& c) {
    return "position " + show(c.position) + " forward " + show(c.forward) + " up " + show(c.up);
}
#define CHECK_SAME(a, b) CHECK_MESSAGE((a) == (b), (show(a) + " vs " + show(b)))

/// Slab test: does the ray p + t d, t > 0, meet the closed box [lo, hi]?
bool ray_hits_box(glm::vec3 p, glm::vec3 d, Bounds box) {
    float t_enter = 0.0f, t_exit = INFINITY;
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0f) {
            if (p[a] < box.min[a] || p[a] > box.max[a]) return false;
            continue;
        }
        float t0 = (box.min[a] - p[a]) / d[a], t1 = (box.max[a] - p[a]) / d[a];
        if (t0 > t1) std::swap(t0, t1);
        t_enter = std::max(t_enter, t0);
        t_exit = std::min(t_exit, t1);
    }
    return t_enter <= t_exit && t_exit > 0.0f;
}

/// Camera axes finite and orthonormal. 1e-5: camera_from_quat rotates unit axes by a normalised
/// quaternion in float (a few ulp of error per component).
void check_camera_frame(const Camera& camera) {
    REQUIRE(is_finite(camera.position));
    CHECK(std::fabs(glm::length(camera.forward) - 1.0f) <= 1e-5f);
    CHECK(std::fabs(glm::length(camera.right) - 1.0f) <= 1e-5f);
    CHECK(std::fabs(glm::length(camera.up) - 1.0f) <= 1e-5f);
    CHECK(std::fabs(glm::dot(camera.forward, camera.right)) <= 1e-5f);
    CHECK(std::fabs(glm::dot(camera.forward, camera.up)) <= 1e-5f);
    CHECK(std::fabs(glm::dot(camera.right, camera.up)) <= 1e-5f);
    // Right-handed: cross(right, up) = -forward (camera.h).
    CHECK(glm::dot(glm::cross(camera.right, camera.up), camera.forward) <= -1.0f + 1e-5f);
}

/// Invariants every procedural scene satisfies. Per-triangle failures are counted (so a
/// million-triangle scene makes a handful of assertions) and the first offender is printed.
void check_invariants(const Scene& scene, const std::string& name) {
    CHECK(scene.name == name);
    CHECK(scene.source == "procedural:" + name);
    const std::size_t triangles = scene.triangle_count();
    REQUIRE(triangles > 0);
    REQUIRE(scene.positions.size() == 3 * triangles);
    REQUIRE(scene.normals.size() == 3 * triangles);
    REQUIRE(scene.uvs.size() == 3 * triangles);

    // Materials: named uniquely, finite, texture indices valid.
    REQUIRE(!scene.materials.empty());
    std::set<std::string> names;
    for (const Material& material : scene.materials) {
        CHECK(!material.name.empty());
        CHECK(names.insert(material.name).second);
        CHECK(
            (material.texture >= -1 && material.texture < static_cast<int>(scene.textures.size())));
        CHECK(material.roughness > 0.0f);
    }
    for (const Texture& texture : scene.textures) {
        CHECK(texture.image.channels == 3);
        CHECK(texture.image.data.size() == texture.image.pixel_count() * 3);
    }

    // Triangles: valid material, positive area, unit normals, winding agrees with the normals.
    std::size_t bad_material = 0, zero_area = 0, bad_normal = 0, bad_winding = 0, bad_uv = 0;
    std::size_t first_bad = triangles;
    std::vector<int> material_use(scene.materials.size(), 0);
    for (std::size_t t = 0; t < triangles; ++t) {
        bool bad = false;
        const std::int32_t m = scene.material_ids[t];
        if (m < 0 || static_cast<std::size_t>(m) >= scene.materials.size()) {
            ++bad_material;
            bad = true;
        } else {
            material_use[m] = 1;
        }
        const glm::vec3 a = scene.positions[3 * t], b = scene.positions[3 * t + 1],
                        c = scene.positions[3 * t + 2];
        const float area2 = triangle_double_area(a, b, c);
        if (!(area2 > 0.0f) || !std::isfinite(area2)) {
            ++zero_area;
            bad = true;
        }
        const glm::vec3 geometric = glm::cross(b - a, c - a);
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 n = scene.normals[3 * t + k];
            // 1e-5: normals are normalised in float (error a few ulp, ~1e-7).
            if (!(std::fabs(glm::length(n) - 1.0f) <= 1e-5f)) {
                ++bad_normal;
                bad = true;
            }
            if (!(glm::dot(geometric, n) > 0.0f)) {
                ++bad_winding;
                bad = true;
            }
            const glm::vec2 uv = scene.uvs[3 * t + k];
            if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) {
                ++bad_uv;
                bad = true;
            }
        }
        if (bad && first_bad == triangles) first_bad = t;
    }
    INFO("first offending triangle: ", first_bad);
    CHECK(bad_material == 0);
    CHECK(zero_area == 0);
    CHECK(bad_normal == 0);
    CHECK(bad_winding == 0);
    CHECK(bad_uv == 0);
    // Every material is used by some triangle.
    for (std::size_t m = 0; m < scene.materials.size(); ++m) {
        INFO("material ", scene.materials[m].name);
        CHECK(material_use[m] == 1);
    }

    // Lights: at least one; triangle lights refer to emissive triangles; quads face down (-y).
    REQUIRE(!scene.lights.empty());
    for (const Light& light : scene.lights) {
        CHECK(light.intensity.x > 0.0f);
        CHECK(is_finite(light.position));
        if (light.type == Light::Type::triangle) {
            REQUIRE(light.primitive >= 0);
            REQUIRE(static_cast<std::size_t>(light.primitive) < triangles);
            const Material& material = scene.materials[scene.material_ids[light.primitive]];
            CHECK_SAME(material.emission, light.intensity);
        }
        if (light.type == Light::Type::quad) {
            CHECK(glm::cross(light.edge_u, light.edge_v).y < 0.0f);
            CHECK(glm::length(glm::cross(light.edge_u, light.edge_v)) > 0.0f);
        }
    }

    // Bounds and scale.
    const Bounds bounds = scene_bounds(scene);
    CHECK(scene.scene_scale == glm::length(bounds.max - bounds.min));
    CHECK(scene.display == DisplayModel{});

    // Camera path: 3-5 keys with increasing times; Scene::camera is the pose at the first key.
    const std::vector<CameraKey>& path = scene.camera_path;
    REQUIRE(path.size() >= 3);
    REQUIRE(path.size() <= 5);
    for (std::size_t k = 1; k < path.size(); ++k) CHECK(path[k].time > path[k - 1].time);
    CHECK_SAME(scene.camera, camera_at(scene, path.front().time));
    CHECK(scene.camera.vfov_deg > 0.0f);
    CHECK(scene.camera.vfov_deg < 180.0f);

    // The view ray of every key and of the scene camera enters the scene's bounds.
    CHECK(ray_hits_box(scene.camera.position, scene.camera.forward, bounds));
    for (const CameraKey& key : path) {
        const Camera camera =
            camera_from_quat(key.position, key.orientation, scene.camera.vfov_deg);
        CHECK(ray_hits_box(camera.position, camera.forward, bounds));
    }

    // Endpoints are reproduced exactly, also beyond the ends (clamped); interior keys within
    // 1e-5 relative (a + (b - a) * 1 need not round back to b).
    const float vfov = scene.camera.vfov_deg;
    const Camera first = camera_from_quat(path.front().position, path.front().orientation, vfov);
    const Camera last = camera_from_quat(path.back().position, path.back().orientation, vfov);
    CHECK_SAME(camera_at(scene, path.front().time), first);
    CHECK_SAME(camera_at(scene, path.front().time - 1.0f), first);
    CHECK_SAME(camera_at(scene, path.back().time), last);
    CHECK_SAME(camera_at(scene, path.back().time + 1.0f), last);
    for (std::size_t k = 1; k + 1 < path.size(); ++k) {
        const Camera at_key = camera_at(scene, path[k].time);
        const Camera expected = camera_from_quat(path[k].position, path[k].orientation, vfov);
        CHECK(glm::length(at_key.position - expected.position) <=
              1e-5f * glm::length(expected.position));
        CHECK(glm::dot(at_key.forward, expected.forward) >= 1.0f - 1e-5f);
    }
    // Along the path (in 1/20 s steps, a little beyond both ends) the frame stays orthonormal.
    for (float time = path.front().time - 0.25f; time <= path.back().time + 0.25f; time += 0.05f)
        check_camera_frame(camera_at(scene, time));
}

/// Closed, consistently wound surface made of triangles [first, last): every directed edge (end
/// points compared bit for bit, so shared corners must be computed once) occurs exactly once, and
/// so does its reverse. A crack or a flipped triangle breaks this.
void check_closed(const Scene& scene, std::size_t first, std::size_t last) {
    using Edge = std::array<std::uint32_t, 6>;
    std::map<Edge, int> edges;
    auto edge = [&](std::size_t from, std::size_t to) {
        const glm::vec3 a = scene.positions[from], b = scene.positions[to];
        return Edge{std::bit_cast<std::uint32_t>(a.x), std::bit_cast<std::uint32_t>(a.y),
                    std::bit_cast<std::uint32_t>(a.z), std::bit_cast<std::uint32_t>(b.x),
                    std::bit_cast<std::uint32_t>(b.y), std::bit_cast<std::uint32_t>(b.z)};
    };
    for (std::size_t t = first; t < last; ++t)
        for (int k = 0; k < 3; ++k) ++edges[edge(3 * t + k, 3 * t + (k + 1) % 3)];
    std::size_t repeated = 0, unmatched = 0;
    for (const auto& [e, count] : edges) {
        repeated += count != 1;
        const Edge reverse{e[3], e[4], e[5], e[0], e[1], e[2]};
        const auto it = edges.find(reverse);
        unmatched += (it == edges.end() || it->second != 1);
    }
    INFO("triangles ", first, " to ", last);
    CHECK(edges.size() == 3 * (last - first));
    CHECK(repeated == 0);
    CHECK(unmatched == 0);
}

std::size_t count_lights(const Scene& scene, Light::Type type) {
    std::size_t count = 0;
    for (const Light& light : scene.lights) count += light.type == type ? 1 : 0;
    return count;
}

int material_index(const Scene& scene, const std::string& name) {
    for (std::size_t m = 0; m < scene.materials.size(); ++m)
        if (scene.materials[m].name == name) return static_cast<int>(m);
    FAIL("no material named " << name);
    return -1;
}

}  // namespace

TEST_CASE("procedural scenes: the table, lookup and errors") {
    const std::vector<std::string> expected = {"cornell", "sphere-grid", "million", "checker-room",
                                               "glossy-floor"};
    const std::vector<ProceduralSceneInfo>& scenes = procedural_scenes();
    REQUIRE(scenes.size() == expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i) {
        CHECK(scenes[i].name == expected[i]);
        CHECK(!scenes[i].description.empty());
        CHECK(is_procedural_scene(expected[i]));
    }
    CHECK(!is_procedural_scene(""));
    CHECK(!is_procedural_scene("Cornell"));
    CHECK(!is_procedural_scene("cornell "));
    CHECK_THROWS_AS(make_procedural_scene("sponza"), Error);
    try {
        make_procedural_scene("sponza");
    } catch (const Error& error) {
        const std::string message = error.what();
        CHECK(message.find("'sponza'") != std::string::npos);
        for (const std::string& name : expected) CHECK(message.find(name) != std::string::npos);
    }
}

TEST_CASE("procedural scene cornell") {
    const Scene scene = make_procedural_scene("cornell");
    check_invariants(scene, "cornell");
    CHECK(make_procedural_scene("cornell") == scene);
    // 5 walls x 2 + emissive panel 2 + 2 boxes x 12.
    CHECK(scene.triangle_count() == 36);
    CHECK(scene.materials.size() == 4);
    CHECK(scene.textures.empty());
    const Bounds expected_bounds{{-1.0f, 0.0f, -1.0f}, {1.0f, 2.0f, 1.0f}};
    CHECK_SAME(scene_bounds(scene), expected_bounds);
    // One explicit quad fill light plus the panel's two triangles (triangles 10 and 11).
    CHECK(scene.lights.size() == 3);
    CHECK(count_lights(scene, Light::Type::quad) == 1);
    REQUIRE(count_lights(scene, Light::Type::triangle) == 2);
    CHECK(scene.lights[1].primitive == 10);
    CHECK(scene.lights[2].primitive == 11);
    for (int k = 30; k < 36; ++k) CHECK(scene.positions[k].y == 1.99f);
    // Red wall on the left (x = -1) facing +x, green wall on the right facing -x.
    const int red = material_index(scene, "red"), green = material_index(scene, "green");
    for (std::size_t t = 0; t < scene.triangle_count(); ++t) {
        if (scene.material_ids[t] == red) {
            CHECK(scene.positions[3 * t].x == -1.0f);
            CHECK_SAME(scene.normals[3 * t], glm::vec3(1.0f, 0.0f, 0.0f));
        }
        if (scene.material_ids[t] == green) {
            CHECK(scene.positions[3 * t].x == 1.0f);
            CHECK_SAME(scene.normals[3 * t], glm::vec3(-1.0f, 0.0f, 0.0f));
        }
    }
    // The boxes (triangles 12..35) stand on the floor inside the room, 0.6 and 1.2 m tall.
    float short_top = 0.0f, tall_top = 0.0f;
    for (std::size_t k = 36; k < 108; ++k) {
        const glm::vec3 p = scene.positions[k];
        CHECK(p.y >= 0.0f);
        CHECK(std::fabs(p.x) < 0.8f);
        CHECK(std::fabs(p.z) < 0.8f);
        float& top = k < 72 ? short_top : tall_top;
        top = std::max(top, p.y);
    }
    CHECK(short_top == 0.6f);  // base y 0 + height, exact
    CHECK(tall_top == 1.2f);
    check_closed(scene, 12, 24);
    check_closed(scene, 24, 36);
    CHECK(scene.camera.vfov_deg == 40.0f);
}

TEST_CASE("procedural scene sphere-grid") {
    const Scene scene = make_procedural_scene("sphere-grid");
    check_invariants(scene, "sphere-grid");
    CHECK(make_procedural_scene("sphere-grid") == scene);
    // Ground 2 + 100 spheres x 2 x 50 segments x (26 - 1) bands.
    CHECK(scene.triangle_count() == 250002);
    CHECK(scene.materials.size() == 5);
    // Sphere tops at 0.4 + 0.4 (exact poles), bottoms touch the ground.
    const Bounds expected_bounds{{-6.0f, 0.0f, -6.0f}, {6.0f, 0.8f, 6.0f}};
    CHECK_SAME(scene_bounds(scene), expected_bounds);
    CHECK(scene.lights.size() == 2);
    CHECK(count_lights(scene, Light::Type::point) == 1);
    CHECK(count_lights(scene, Light::Type::quad) == 1);
    int glossy = 0;
    for (const Material& material : scene.materials) glossy += material.specular.x > 0.0f;
    CHECK(glossy == 2);
    // Every sphere vertex lies on its sphere and its normal is the radial direction.
    // 2e-6 m: centre + 0.4 d in float with |centre| <= 6.4 (half an ulp is 2.4e-7 per component)
    // and |d| = 1 within a few ulp. 1e-5 on the normal: the same rounding divided by r = 0.4.
    std::size_t off_sphere = 0, not_radial = 0;
    for (std::size_t t = 2; t < scene.triangle_count(); ++t) {
        const std::size_t s = (t - 2) / 2500;
        const glm::vec3 centre{-4.5f + static_cast<float>(s % 10), 0.4f,
                               -4.5f + static_cast<float>(s / 10)};
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 offset = scene.positions[3 * t + k] - centre;
            if (!(std::fabs(glm::length(offset) - 0.4f) <= 2e-6f)) ++off_sphere;
            if (!(glm::length(offset / 0.4f - scene.normals[3 * t + k]) <= 1e-5f)) ++not_radial;
        }
    }
    CHECK(off_sphere == 0);
    CHECK(not_radial == 0);
    // Spheres are closed: the seam and the poles share bit-identical vertices.
    check_closed(scene, 2, 2502);
    check_closed(scene, 2 + 99 * 2500, 2 + 100 * 2500);
}

TEST_CASE("procedural scene million") {
    const Scene scene = make_procedural_scene("million");
    check_invariants(scene, "million");
    CHECK(make_procedural_scene("million") == scene);
    constexpr int quads = 708;
    CHECK(scene.triangle_count() == 2 * quads * quads);  // 1 002 528
    CHECK(scene.materials.size() == 2);
    CHECK(scene.lights.size() == 2);
    const Bounds bounds = scene_bounds(scene);
    CHECK(bounds.min.x == -32.0f);
    CHECK(bounds.max.x == 32.0f);
    CHECK(bounds.min.z == -32.0f);
    CHECK(bounds.max.z == 32.0f);
    // |h| <= 1.6 + 0.7 + 0.25 + 0.06 = 2.61, and the terrain really is displaced.
    CHECK(bounds.min.y >= -2.61f);
    CHECK(bounds.max.y <= 2.61f);
    CHECK(bounds.max.y - bounds.min.y > 2.0f);

    // Corner 0 of triangle 2 (j 708 + i) is grid vertex (i, j); compare with the documented
    // height function and its gradient in binary64 libm. 1e-5 m: the float arguments carry at
    // most half an ulp of 132 (7.6e-6 rad) times the amplitude 0.06 of the fastest term, and the
    // four-term float sum a few ulp of 2.61; the normal differs by the same relative amount.
    auto height = [](double x, double z, double& dh_dx, double& dh_dz) {
        const double s0x = std::sin(0.13 * x + 0.4), c0z = std::cos(0.11 * z - 0.2);
        const double s1x = std::sin(0.37 * x - 1.1), s1z = std::sin(0.29 * z + 0.6);
        const double c2x = std::cos(1.3 * x + 0.5), c2z = std::cos(0.9 * z - 0.3);
        const double s3x = std::sin(4.1 * x), c3z = std::cos(3.7 * z + 1.0);
        dh_dx = 1.6 * 0.13 * std::cos(0.13 * x + 0.4) * c0z +
                0.7 * 0.37 * std::cos(0.37 * x - 1.1) * s1z -
                0.25 * 1.3 * std::sin(1.3 * x + 0.5) * c2z + 0.06 * 4.1 * std::cos(4.1 * x) * c3z;
        dh_dz = -1.6 * s0x * 0.11 * std::sin(0.11 * z - 0.2) +
                0.7 * s1x * 0.29 * std::cos(0.29 * z + 0.6) -
                0.25 * c2x * 0.9 * std::sin(0.9 * z - 0.3) -
                0.06 * s3x * 3.7 * std::sin(3.7 * z + 1.0);
        return 1.6 * s0x * c0z + 0.7 * s1x * s1z + 0.25 * c2x * c2z + 0.06 * s3x * c3z;
    };
    const int samples[][2] = {{0, 0}, {707, 0}, {0, 707}, {354, 354}, {123, 456}, {600, 17}};
    for (const auto& ij : samples) {
        const std::size_t t = 2 * (static_cast<std::size_t>(ij[1]) * quads + ij[0]);
        const glm::vec3 p = scene.positions[3 * t];
        CHECK(p.x == doctest::Approx(-32.0 + 64.0 * ij[0] / quads).epsilon(1e-6));
        CHECK(p.z == doctest::Approx(-32.0 + 64.0 * ij[1] / quads).epsilon(1e-6));
        double dh_dx = 0.0, dh_dz = 0.0;
        const double h = height(p.x, p.z, dh_dx, dh_dz);
        CHECK(std::fabs(p.y - h) <= 1e-5);
        const double norm = std::sqrt(dh_dx * dh_dx + 1.0 + dh_dz * dh_dz);
        const glm::vec3 n = scene.normals[3 * t];
        CHECK(std::fabs(n.x + dh_dx / norm) <= 1e-5);
        CHECK(std::fabs(n.y - 1.0 / norm) <= 1e-5);
        CHECK(std::fabs(n.z + dh_dz / norm) <= 1e-5);
    }
    // The camera stays above the terrain along the whole path.
    for (float time = 0.0f; time <= 3.0f; time += 0.25f)
        CHECK(camera_at(scene, time).position.y > bounds.max.y);
}

TEST_CASE("procedural scene checker-room") {
    const Scene scene = make_procedural_scene("checker-room");
    check_invariants(scene, "checker-room");
    CHECK(make_procedural_scene("checker-room") == scene);
    // Room 6 x 2 + sphere 2 x 32 x 15 + box 12.
    CHECK(scene.triangle_count() == 984);
    CHECK(scene.materials.size() == 5);
    const Bounds expected_bounds{{-3.0f, 0.0f, -3.0f}, {3.0f, 3.0f, 3.0f}};
    CHECK_SAME(scene_bounds(scene), expected_bounds);
    CHECK(scene.lights.size() == 2);
    // The camera stands inside the closed room.
    const Bounds bounds = scene_bounds(scene);
    for (float time = 0.0f; time <= 3.0f; time += 0.5f) {
        const glm::vec3 p = camera_at(scene, time).position;
        CHECK((p.x > bounds.min.x && p.y > bounds.min.y && p.z > bounds.min.z));
        CHECK((p.x < bounds.max.x && p.y < bounds.max.y && p.z < bounds.max.z));
    }

    // The texture: 512 x 512, 2 x 2-texel squares alternating 0.8 / 0.05, texel (0, 0) light.
    REQUIRE(scene.textures.size() == 1);
    const Texture& texture = scene.textures[0];
    REQUIRE(texture.image.width == 512);
    REQUIRE(texture.image.height == 512);
    std::size_t wrong = 0, light_texels = 0;
    for (int y = 0; y < 512; ++y)
        for (int x = 0; x < 512; ++x)
            for (int c = 0; c < 3; ++c) {
                const float expected = ((x / 2 + y / 2) % 2 == 0) ? 0.8f : 0.05f;
                wrong += texture.image.at(x, y, c) != expected;
                light_texels += (c == 0 && texture.image.at(x, y, c) == 0.8f);
            }
    CHECK(wrong == 0);
    CHECK(light_texels == 512 * 512 / 2);
    CHECK(texture.image.at(1, 1, 0) == texture.image.at(0, 0, 0));
    CHECK(texture.image.at(2, 0, 0) != texture.image.at(0, 0, 0));
    CHECK(texture.image.at(0, 2, 0) != texture.image.at(0, 0, 0));
    CHECK(texture.image.at(2, 2, 0) == texture.image.at(0, 0, 0));
    // Bilinear lookups at square centres fall between two texels of one square: exact values,
    // alternating along u and v, and the same one tile (uv + 1) further (repeat wrap).
    for (int a = 0; a < 8; ++a)
        for (int b = 0; b < 8; ++b) {
            const float fa = static_cast<float>(a), fb = static_cast<float>(b);
            const glm::vec2 uv{(2.0f * fa + 1.0f) / 512.0f, 1.0f - (2.0f * fb + 1.0f) / 512.0f};
            const float expected = ((a + b) % 2 == 0) ? 0.8f : 0.05f;
            CHECK_SAME(sample_texture_bilinear(texture, uv), glm::vec3(expected));
            CHECK_SAME(sample_texture_bilinear(texture, uv + glm::vec2(1.0f, 0.0f)),
                       glm::vec3(expected));
        }

    // Floor and walls use the texture and tile it once per metre (6 times along the floor).
    const int floor = material_index(scene, "checker-floor");
    const int wall = material_index(scene, "checker-wall");
    CHECK(scene.materials[floor].texture == 0);
    CHECK(scene.materials[wall].texture == 0);
    float floor_uv_max = 0.0f;
    int wall_triangles = 0;
    for (std::size_t t = 0; t < scene.triangle_count(); ++t) {
        if (scene.material_ids[t] == floor)
            for (int k = 0; k < 3; ++k)
                floor_uv_max =
                    std::max({floor_uv_max, scene.uvs[3 * t + k].x, scene.uvs[3 * t + k].y});
        wall_triangles += scene.material_ids[t] == wall;
    }
    CHECK(floor_uv_max == 6.0f);
    CHECK(wall_triangles == 8);
    // Room, sphere and box are each closed and none shares an edge with another.
    check_closed(scene, 0, scene.triangle_count());
}

TEST_CASE("procedural scene glossy-floor") {
    const Scene scene = make_procedural_scene("glossy-floor");
    check_invariants(scene, "glossy-floor");
    CHECK(make_procedural_scene("glossy-floor") == scene);
    // Floor 2 + wall 2 + 3 spheres x 2 x 48 x 23 + box 12 + emissive panel 2.
    CHECK(scene.triangle_count() == 6642);
    CHECK(scene.materials.size() == 7);
    const Bounds expected_bounds{{-4.0f, 0.0f, -4.0f}, {4.0f, 4.0f, 4.0f}};
    CHECK_SAME(scene_bounds(scene), expected_bounds);
    // A point light plus the panel's two triangles.
    CHECK(scene.lights.size() == 3);
    CHECK(count_lights(scene, Light::Type::triangle) == 2);
    // The floor (triangles 0, 1) is the only glossy material: GGX, roughness in [0.1, 0.2].
    const int floor = material_index(scene, "glossy-floor");
    CHECK(scene.material_ids[0] == floor);
    CHECK(scene.material_ids[1] == floor);
    for (std::size_t m = 0; m < scene.materials.size(); ++m) {
        const Material& material = scene.materials[m];
        if (static_cast<int>(m) == floor) {
            CHECK(material.specular.x > 0.0f);
            CHECK(material.roughness >= 0.1f);
            CHECK(material.roughness <= 0.2f);
        } else {
            CHECK_SAME(material.specular, glm::vec3(0.0f));
        }
    }
    CHECK_SAME(scene.normals[0], glm::vec3(0.0f, 1.0f, 0.0f));
    for (int sphere = 0; sphere < 3; ++sphere)
        check_closed(scene, 4 + 2208 * sphere, 4 + 2208 * (sphere + 1));
    check_closed(scene, 4 + 3 * 2208, 4 + 3 * 2208 + 12);  // the box
}

TEST_CASE("textures: bilinear taps wrap every texel index into the texture (repeat)") {
    // texel centres at (i + 1/2) / W, v = 0 the last row; indices outside [0, n) wrap around
    Texture texture{"t", Image(5, 3, 3)};
    int wrapped = 0;
    for (int k = -230; k <= 370; ++k) {
        const float u = static_cast<float>(k) / 100.0f, v = static_cast<float>(k) / 61.0f;
        const BilinearTaps t = bilinear_taps(texture, {u, v});
        REQUIRE(t.valid);
        const float x = u * 5.0f - 0.5f, y = (1.0f - v) * 3.0f - 0.5f;
        const auto wrap = [](float i, int n) {
            const int m = static_cast<int>(i) % n;
            return m < 0 ? m + n : m;
        };
        CHECK(t.x0 == wrap(std::floor(x), 5));
        CHECK(t.x1 == wrap(std::floor(x) + 1.0f, 5));
        CHECK(t.y0 == wrap(std::floor(y), 3));
        CHECK(t.y1 == wrap(std::floor(y) + 1.0f, 3));
        CHECK(t.tx == x - std::floor(x));
        CHECK(t.ty == y - std::floor(y));
        wrapped += std::floor(x) < 0.0f || std::floor(x) >= 4.0f;
    }
    CHECK(wrapped > 300);
    CHECK_FALSE(bilinear_taps(texture, {std::nanf(""), 0.5f}).valid);
    // large coordinates, up to and beyond 2^31 texels: the binary64 reduction's indices, without
    // overflowing an int
    const auto reduced = [](float i, int n) {
        const double r = static_cast<double>(i) - std::floor(static_cast<double>(i) / n) * n;
        const int k = static_cast<int>(r);
        return k >= n ? k - n : (k < 0 ? k + n : k);
    };
    test::SplitMix64 rng(5);
    for (int k = 0; k < 20000; ++k) {
        const float scale = std::ldexp(1.0f, static_cast<int>(rng.below(40)));
        const float u = (rng.uniform(0.0f, 2.0f) - 1.0f) * scale;
        const BilinearTaps t = bilinear_taps(texture, {u, 0.5f});
        const float x = std::floor(u * 5.0f - 0.5f);
        REQUIRE(t.valid);
        REQUIRE(t.x0 == reduced(x, 5));
        REQUIRE(t.x1 == reduced(x + 1.0f, 5));
    }
}
