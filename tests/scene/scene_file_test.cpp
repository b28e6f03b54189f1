// Scene files (SPEC §2): the hand-written scene, every invalid input named with file and line,
// zero-area triangles, transforms, camera paths, and the export -> load round trip.
#include <doctest/doctest.h>
#include <unistd.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

#include "ref/core/error.h"
#include "ref/core/json_locator.h"
#include "ref/image/image_io.h"
#include "ref/scene/procedural.h"
#include "ref/scene/scene_file.h"
#include "tests/scene/scene_test_util.h"

using namespace fovref;
using fovref::test::contains;
using fovref::test::error_of;
using fovref::test::TempDir;
namespace fs = std::filesystem;

namespace {

const std::string room_scene = std::string(FOVREF_SOURCE_DIR) + "/scenes/textured-room/scene.json";

// Expect load_scene_file(scene) to throw, naming `location` ("file:line:") and `detail`.
void check_scene_error(const std::string& scene, const std::string& location,
                       const std::string& detail, const SceneLoadOptions& options = {}) {
    const std::string message = error_of([&] { load_scene_file(scene, options); });
    INFO("message: " << message);
    CHECK(contains(message, location));
    CHECK(contains(message, detail));
}

const char* triangle_obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

// A valid scene around one OBJ; tests replace one line to make it invalid. Line numbers:
// 1 "{", 2 version, 3 meshes, 4 lights, 5 camera, 6 "}".
std::string minimal_scene(const std::string& obj = "tri.obj") {
    return "{\n"
           "  \"version\": 1,\n"
           "  \"meshes\": [{\"obj\": \"" +
           obj +
           "\"}],\n"
           "  \"lights\": [{\"type\": \"point\", \"position\": [0, 1, 0], \"intensity\": 1}],\n"
           "  \"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0], \"vfov_deg\": 45}\n"
           "}\n";
}

// Bitwise equality of float vectors (positions, normals, uvs must round-trip exactly).
template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

}  // namespace

// --- The hand-written scene ----------------------------------------------------------------------

TEST_CASE("scene file: textured-room loads with the expected contents") {
    const Scene scene = load_scene_file(room_scene);
    CHECK(scene.name == "textured-room");
    // room: 5 quads + 2 lamp triangles = 12; box: 6 quads = 12 triangles, instanced twice.
    CHECK(scene.triangle_count() == 36);
    CHECK(scene.positions.size() == 108);
    CHECK(scene.load_stats.polygons_triangulated == 5 + 2 * 6);
    CHECK(scene.load_stats.normals_generated == 2 + 2 * 12);  // lamp and boxes have no vn
    CHECK(scene.load_stats.zero_area_triangles_dropped == 0);
    CHECK(scene.load_stats.warnings.empty());  // a clean scene: no tinyobjloader warnings either
    // room.mtl's 6 materials, once each although box.obj loads room.mtl twice more.
    REQUIRE(scene.materials.size() == 6);
    const char* names[6] = {"floor", "white", "red", "green", "lamp", "box"};
    for (int m = 0; m < 6; ++m) CHECK(scene.materials[m].name == names[m]);
    REQUIRE(scene.textures.size() == 1);
    CHECK(scene.textures[0].image.width == 32);
    CHECK(scene.textures[0].image.channels == 3);
    CHECK(scene.materials[0].texture == 0);
    CHECK(scene.materials[0].albedo == glm::vec3(1.0f));
    // JSON override of the floor; Ns 200 -> roughness for the box; Ke of the lamp.
    CHECK(scene.materials[0].specular == glm::vec3(0.04f));
    CHECK(scene.materials[0].roughness == 0.3f);
    CHECK(scene.materials[5].roughness == ns_to_roughness(200.0f));
    CHECK(scene.materials[5].specular == glm::vec3(0.04f));
    CHECK(scene.materials[4].emission == glm::vec3(8.0f, 7.0f, 5.0f));
    CHECK(scene.materials[1].roughness == 1.0f);  // no Pr, no Ns
    // Texel (1, 1) of checker.png is the light tone 222/255 on the G channel 205/255: sRGB
    // decoded. Tolerance 1e-5: the decode uses the deterministic pow (<= 2 ulp) vs libm here.
    const float encoded = 205.0f / 255.0f;
    const double expected = std::pow((encoded + 0.055) / 1.055, 2.4);
    CHECK(std::fabs(scene.textures[0].image.at(1, 1, 1) - expected) < 1e-5);
    // Lights: the explicit quad and point, then one per emissive lamp triangle (triangles 10, 11).
    REQUIRE(scene.lights.size() == 4);
    CHECK(scene.lights[0].type == Light::Type::quad);
    CHECK(scene.lights[0].intensity == glm::vec3(6.0f));
    CHECK(scene.lights[1].type == Light::Type::point);
    CHECK(scene.lights[1].position == glm::vec3(0.0f, 2.6f, 0.5f));
    CHECK(scene.lights[2].type == Light::Type::triangle);
    CHECK(scene.lights[2].primitive == 10);
    CHECK(scene.lights[3].primitive == 11);
    CHECK(scene.material_ids[10] == 4);
    // Bounds: the room's corners, exactly (the boxes are inside).
    const Bounds bounds = scene_bounds(scene);
    CHECK(bounds.min == glm::vec3(-2.0f, 0.0f, -2.0f));
    CHECK(bounds.max == glm::vec3(2.0f, 3.0f, 2.0f));
    // The floor quad (4 3 2 1) fans into (4 3 2) and (4 2 1) with normal +y and uvs 0..4.
    CHECK(scene.positions[0] == glm::vec3(-2.0f, 0.0f, 2.0f));
    CHECK(scene.positions[5] == glm::vec3(-2.0f, 0.0f, -2.0f));
    CHECK(scene.uvs[2] == glm::vec2(4.0f, 4.0f));
    CHECK(scene.normals[0] == glm::vec3(0.0f, 1.0f, 0.0f));
    // The lamp has no normals: geometric +z (exact: the panel lies in a plane z = const).
    CHECK(scene.normals[30] == glm::vec3(0.0f, 0.0f, 1.0f));
    // Box triangles have unit geometric normals and uv (0, 0).
    for (std::size_t c = 36; c < 108; ++c) {
        CHECK(std::fabs(glm::length(scene.normals[c]) - 1.0f) < 1e-6f);  // normalise: ~1 ulp
        CHECK(scene.uvs[c] == glm::vec2(0.0f));
    }
    // Camera, path, display, presets.
    CHECK(scene.camera.position == glm::vec3(0.0f, 1.5f, 1.9f));
    CHECK(scene.camera.vfov_deg == 60.0f);
    REQUIRE(scene.camera_path.size() == 3);
    CHECK(scene.camera_path[2].time == 2.0f);
    CHECK(scene.camera_path[1].position == glm::vec3(0.0f, 1.6f, 1.8f));
    CHECK(scene.display.kind == DisplayModel::Kind::field_of_view);
    REQUIRE(scene.presets.count("preview") == 1);
    CHECK(scene.presets.at("preview") == R"({"height":180,"mode":"basic","width":320})");
}

TEST_CASE("scene file: instanced boxes stand on the floor") {
    const Scene scene = load_scene_file(room_scene);
    // Tall box: y in 0.9 +- 1.8/2; short box: 0.35 +- 0.7/2. Rotation is about y, so y is exact
    // up to the float rounding of 0.9 + 0.9 (tolerance 1e-6).
    float tall_min = 1e9f, tall_max = -1e9f, short_min = 1e9f, short_max = -1e9f;
    for (std::size_t c = 36; c < 72; ++c) {
        tall_min = std::min(tall_min, scene.positions[c].y);
        tall_max = std::max(tall_max, scene.positions[c].y);
    }
    for (std::size_t c = 72; c < 108; ++c) {
        short_min = std::min(short_min, scene.positions[c].y);
        short_max = std::max(short_max, scene.positions[c].y);
    }
    CHECK(std::fabs(tall_min) < 1e-6f);
    CHECK(std::fabs(tall_max - 1.8f) < 1e-6f);
    CHECK(std::fabs(short_min) < 1e-6f);
    CHECK(std::fabs(short_max - 0.7f) < 1e-6f);
}

// --- Transforms ------------------------------------------------------------------------------

TEST_CASE("scene file: instance transform lands a known vertex where expected") {
    TempDir dir("transform");
    dir.write("tri.obj", "v 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n");
    std::string scene = minimal_scene();
    const std::string mesh = R"([{"obj": "tri.obj"}])";
    SUBCASE("translate, rotate_deg, scale: S, then Rx, Ry, Rz, then T") {
        // Scale 2, rotate 90 degrees about y ((x, y, z) -> (z, y, -x)), translate (1, 2, 3).
        scene.replace(scene.find(mesh), mesh.size(),
                      R"([{"obj": "tri.obj", "transform": {"translate": [1, 2, 3], )"
                      R"("rotate_deg": [0, 90, 0], "scale": 2}}])");
        const Scene loaded = load_scene_file(dir.write("scene.json", scene));
        REQUIRE(loaded.triangle_count() == 1);
        CHECK(loaded.positions[0] == glm::vec3(1.0f, 2.0f, 1.0f));
        CHECK(loaded.positions[1] == glm::vec3(1.0f, 4.0f, 3.0f));
        CHECK(loaded.positions[2] == glm::vec3(3.0f, 2.0f, 3.0f));
    }
    SUBCASE("rotation order: X first, then Y") {
        // (0, 1, 0): Rx(90) -> (0, 0, 1), then Ry(90) -> (1, 0, 0). (Y first would give (0, 0, 1).)
        const glm::mat4 m = euler_xyz_transform(glm::vec3(0), glm::vec3(90, 90, 0), glm::vec3(1));
        CHECK(glm::vec3(m * glm::vec4(0, 1, 0, 1)) == glm::vec3(1, 0, 0));
    }
    SUBCASE("general angles agree with a libm rotation (tolerance 1e-6: float sin/cos, ~2 ulp)") {
        const glm::vec3 angles(30.0f, -45.0f, 10.0f);
        const glm::mat4 m = euler_xyz_transform(glm::vec3(0), angles, glm::vec3(1));
        const double pi = 3.14159265358979323846;
        const double rx = angles.x * pi / 180, ry = angles.y * pi / 180, rz = angles.z * pi / 180;
        double p[3] = {0.3, -0.7, 0.2};
        double q[3] = {p[0], std::cos(rx) * p[1] - std::sin(rx) * p[2],
                       std::sin(rx) * p[1] + std::cos(rx) * p[2]};
        double r[3] = {std::cos(ry) * q[0] + std::sin(ry) * q[2], q[1],
                       -std::sin(ry) * q[0] + std::cos(ry) * q[2]};
        double s[3] = {std::cos(rz) * r[0] - std::sin(rz) * r[1],
                       std::sin(rz) * r[0] + std::cos(rz) * r[1], r[2]};
        glm::vec3 got = glm::vec3(m * glm::vec4(0.3f, -0.7f, 0.2f, 1.0f));
        for (int k = 0; k < 3; ++k) CHECK(std::fabs(got[k] - s[k]) < 1e-6);
    }
    SUBCASE("a 4x4 matrix (rows) is applied as p' = M p") {
        scene.replace(scene.find(mesh), mesh.size(),
                      R"([{"obj": "tri.obj", "transform": {"matrix": [[0, 0, 2, 1], [0, 2, 0, 2], )"
                      R"([-2, 0, 0, 3], [0, 0, 0, 1]]}}])");
        const Scene loaded = load_scene_file(dir.write("scene.json", scene));
        CHECK(loaded.positions[0] == glm::vec3(1.0f, 2.0f, 1.0f));
        CHECK(loaded.positions[2] == glm::vec3(3.0f, 2.0f, 3.0f));
    }
    SUBCASE("a mirroring transform keeps the geometric normal's side") {
        dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");  // faces +z
        scene.replace(scene.find(mesh), mesh.size(),
                      R"([{"obj": "tri.obj", "transform": {"scale": [-1, 1, 1]}}])");
        const Scene loaded = load_scene_file(dir.write("scene.json", scene));
        CHECK(loaded.normals[0] == glm::vec3(0.0f, 0.0f, 1.0f));
        CHECK(loaded.positions[1] == glm::vec3(0.0f, 1.0f, 0.0f));  // corners 1, 2 swapped
    }
    SUBCASE("normals go through the inverse transpose") {
        dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 1 1 0\nf 1//1 2//1 3//1\n");
        scene.replace(scene.find(mesh), mesh.size(),
                      R"([{"obj": "tri.obj", "transform": {"scale": [2, 1, 1]}}])");
        const Scene loaded = load_scene_file(dir.write("scene.json", scene));
        // (1, 1, 0) -> (1/2, 1, 0) normalised; tolerance 1e-6 (one float normalisation).
        const glm::vec3 expected = glm::normalize(glm::vec3(0.5f, 1.0f, 0.0f));
        CHECK(glm::length(loaded.normals[0] - expected) < 1e-6f);
    }
}

// --- Zero-area triangles, polygons, missing normals
// -----------------------------------------------

TEST_CASE("scene file: zero-area triangles are dropped and counted with their lines") {
    TempDir dir("zero_area");
    const std::string obj = dir.write("mesh.obj",
                                      "v 0 0 0\n"        // 1
                                      "v 1 0 0\n"        // 2
                                      "v 0 1 0\n"        // 3
                                      "v 2 0 0\n"        // 4
                                      "f 1 2 3\n"        // 5: fine
                                      "f 1 2 4\n"        // 6: collinear
                                      "f 3 3 1\n"        // 7: repeated vertex
                                      "f 1 2 4 3\n"      // 8: quad: (1 2 4) zero, (1 4 3) fine
                                      "f 1 2 3 1 2\n");  // 9: pentagon fan: 3 triangles, 2 zero
    Scene scene;
    load_obj_into(scene, obj, glm::mat4(1.0f));
    CHECK(scene.triangle_count() == 3);
    CHECK(scene.load_stats.zero_area_triangles_dropped == 5);
    CHECK(scene.load_stats.polygons_triangulated == 2);
    CHECK(scene.load_stats.normals_generated == 3);
    // The first 5 are listed with their lines, then a total.
    REQUIRE(scene.load_stats.warnings.size() >= 5);
    CHECK(contains(scene.load_stats.warnings[0], "mesh.obj:6: zero-area"));
    CHECK(contains(scene.load_stats.warnings[1], "mesh.obj:7: zero-area"));
    CHECK(contains(scene.load_stats.warnings[2], "mesh.obj:8: zero-area"));
    CHECK(contains(scene.load_stats.warnings[3], "mesh.obj:9: zero-area"));
    // Faces without usemtl get the "default" material; no uvs -> (0, 0).
    REQUIRE(scene.materials.size() == 1);
    CHECK(scene.materials[0].name == "default");
    CHECK(scene.uvs[0] == glm::vec2(0.0f));
    // Geometric normal of triangle (1 2 3) is +z.
    CHECK(scene.normals[0] == glm::vec3(0.0f, 0.0f, 1.0f));
}

TEST_CASE("scene file: load_obj_into reuses materials and textures of an OBJ loaded twice") {
    const std::string dir = std::string(FOVREF_SOURCE_DIR) + "/scenes/textured-room/";
    Scene scene;
    load_obj_into(scene, dir + "room.obj", glm::mat4(1.0f));
    load_obj_into(scene, dir + "room.obj", glm::mat4(1.0f));
    CHECK(scene.triangle_count() == 24);
    CHECK(scene.materials.size() == 6);
    CHECK(scene.textures.size() == 1);
}

// --- Invalid input: every error names the file and the line -------------------------------------

TEST_CASE("scene file errors: JSON syntax and semantics name scene.json and the line") {
    TempDir dir("json_errors");
    dir.write("tri.obj", triangle_obj);
    const std::string base = minimal_scene();
    auto write_scene = [&](const std::string& text) { return dir.write("scene.json", text); };
    auto replace_line = [&](int line, const std::string& text) {
        std::istringstream in(base);
        std::string result, current;
        for (int n = 1; std::getline(in, current); ++n)
            result += (n == line ? text : current) + "\n";
        return write_scene(result);
    };

    REQUIRE(error_of([&] { load_scene_file(write_scene(base)); }).empty());

    SUBCASE("syntax error: line and column from nlohmann's byte offset") {
        // Missing comma after the version: nlohmann's byte offset is the last character of the
        // offending token, the closing '"' of "meshes" (line 3, column 10).
        check_scene_error(replace_line(2, "  \"version\": 1"), "scene.json:3:10:", "syntax error");
    }
    SUBCASE("truncated document") {
        check_scene_error(write_scene("{\n  \"version\": 1,\n"), "scene.json:", "syntax error");
    }
    SUBCASE("wrong type") {
        check_scene_error(
            replace_line(
                5,
                R"(  "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "vfov_deg": "45"})"),
            "scene.json:5:", "/camera/vfov_deg: expected a number, got string");
    }
    SUBCASE("wrong type on its own line inside a multi-line value") {
        check_scene_error(
            replace_line(5,
                         "  \"camera\": {\"position\": [0, 0, 5],\n  \"look_at\": [0, 0, 0],\n"
                         "  \"vfov_deg\": true}"),
            "scene.json:7:", "/camera/vfov_deg");
    }
    SUBCASE("missing key: the line of the object that lacks it") {
        check_scene_error(replace_line(5, R"(  "camera": {"look_at": [0, 0, 0], "vfov_deg": 45})"),
                          "scene.json:5:", "missing key \"position\"");
    }
    SUBCASE("missing version") {
        check_scene_error(replace_line(2, ""), "scene.json:1:", "missing key \"version\"");
    }
    SUBCASE("unknown top-level key") {
        check_scene_error(replace_line(2, "  \"version\": 1, \"lightz\": [],"),
                          "scene.json:2:", "unknown key \"lightz\"");
    }
    SUBCASE("unknown key in a light") {
        check_scene_error(
            replace_line(
                4,
                R"(  "lights": [{"type": "point", "position": [0, 1, 0], "intensity": 1, "radius": 2}],)"),
            "scene.json:4:", "/lights/0/radius: unknown key");
    }
    SUBCASE("duplicate key") {
        check_scene_error(replace_line(2, "  \"version\": 1, \"version\": 1,"),
                          "scene.json:2:", "duplicate key \"version\"");
    }
    SUBCASE("number beyond binary64 (nlohmann throws without a position)") {
        check_scene_error(
            replace_line(
                4,
                R"(  "lights": [{"type": "point", "position": [0, 1e999, 0], "intensity": 1}],)"),
            "scene.json:4:", "out of range");
    }
    SUBCASE("number beyond binary32") {
        check_scene_error(
            replace_line(
                4, R"(  "lights": [{"type": "point", "position": [0, 1e39, 0], "intensity": 1}],)"),
            "scene.json:4:", "/lights/0/position/1: number is not a finite binary32");
    }
    SUBCASE("unsupported version") {
        check_scene_error(replace_line(2, "  \"version\": 2,"),
                          "scene.json:2:", "unsupported version");
    }
    SUBCASE("unknown light type") {
        check_scene_error(replace_line(4, R"(  "lights": [{"type": "spot"}],)"),
                          "scene.json:4:", "unknown light type");
    }
    SUBCASE("zero-area quad light") {
        check_scene_error(replace_line(4,
                                       "  \"lights\": [{\"type\": \"quad\", \"corner\": [0, 0, 0], "
                                       "\"edge_u\": [1, 0, 0],\n"
                                       "               \"edge_v\": [2, 0, 0], \"radiance\": 1}],"),
                          "scene.json:5:", "zero area");
    }
    SUBCASE("missing OBJ file: the line of \"obj\"") {
        check_scene_error(replace_line(3, R"(  "meshes": [{"obj": "nothere.obj"}],)"),
                          "scene.json:3:", "OBJ file 'nothere.obj' not found");
    }
    SUBCASE("degenerate camera") {
        check_scene_error(
            replace_line(
                5, R"(  "camera": {"position": [0, 0, 5], "look_at": [0, 0, 5], "vfov_deg": 45})"),
            "scene.json:5:", "look_at target equals the position");
    }
    SUBCASE("camera with two orientations") {
        check_scene_error(
            replace_line(
                5,
                R"(  "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "quaternion": [0, 0, 0, 1], "vfov_deg": 45})"),
            "scene.json:5:", "exactly one of");
    }
    SUBCASE("zero quaternion") {
        check_scene_error(
            replace_line(
                5,
                R"(  "camera": {"position": [0, 0, 5], "quaternion": [0, 0, 0, 0], "vfov_deg": 45})"),
            "scene.json:5:", "quaternion is zero");
    }
    SUBCASE("unknown material override; missing override texture") {
        check_scene_error(
            replace_line(2, "  \"version\": 1, \"materials\": {\"marble\": {\"albedo\": 0.5}},"),
            "scene.json:2:", "no mesh defines a material named \"marble\"");
        check_scene_error(
            replace_line(
                2, "  \"version\": 1, \"materials\": {\"default\": {\"texture\": \"gone.png\"}},"),
            "scene.json:2:", "texture 'gone.png' not found");
    }
    SUBCASE("display: bad model, key of another model") {
        check_scene_error(replace_line(2, "  \"version\": 1, \"display\": {\"model\": \"hmd\"},"),
                          "scene.json:2:", "unknown display model");
        check_scene_error(
            replace_line(
                2, "  \"version\": 1, \"display\": {\"model\": \"fov\", \"distance_px\": 900},"),
            "scene.json:2:", "only used by the \"fixed\" model");
    }
    SUBCASE("non-increasing camera path times: the line of the offending time") {
        check_scene_error(
            replace_line(5,
                         "  \"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0], "
                         "\"vfov_deg\": 45},\n"
                         "  \"camera_path\": [\n"
                         "    {\"time\": 0, \"position\": [0, 0, 5], \"look_at\": [0, 0, 0]},\n"
                         "    {\"time\": 1, \"position\": [1, 0, 5], \"look_at\": [0, 0, 0]},\n"
                         "    {\"time\": 1, \"position\": [2, 0, 5], \"look_at\": [0, 0, 0]}\n"
                         "  ]"),
            "scene.json:9:", "strictly increasing");
    }
    SUBCASE("missing scene file") {
        const std::string message = error_of([&] { load_scene_file(dir.file("none.json")); });
        CHECK(contains(message, "none.json: scene file not found"));
    }
    SUBCASE("load_scene: a directory without scene.json, a name that is nothing") {
        fs::create_directories(dir.file("empty"));
        CHECK(error_of([&] { load_scene(dir.file("empty")); }) ==
              dir.file("empty") + ": directory has no scene.json");
        CHECK(contains(error_of([&] { load_scene(dir.file("nothing")); }),
                       "no such file, and not a procedural scene"));
        // A directory with a scene.json loads it.
        CHECK(load_scene(dir.path.string()).triangle_count() == 1);
    }
}

TEST_CASE("scene file errors: OBJ and MTL problems name their file and line") {
    TempDir dir("obj_errors");
    const std::string scene = dir.write("scene.json", minimal_scene("mesh.obj"));
    // Strict (--strict-obj): the quirks of docs/obj-quirks.md (the undefined material, missing
    // MTL file and texture, duplicate material below) are errors; tests/scene/obj_quirks_test.cpp
    // checks their warnings.
    SceneLoadOptions strict;
    strict.strict_obj = true;
    auto check_obj = [&](const std::string& obj_text, const std::string& location,
                         const std::string& detail) {
        dir.write("mesh.obj", obj_text);
        check_scene_error(scene, location, detail, strict);
    };
    const std::string v3 = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

    SUBCASE("malformed number") {
        check_obj("v 0 0 0\nv 1 2.5x 0\nv 0 1 0\nf 1 2 3\n",
                  "mesh.obj:2:", "malformed number '2.5x'");
    }
    SUBCASE("too few coordinates") {
        check_obj("v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n", "mesh.obj:2:", "needs 3 to 7 numbers");
    }
    SUBCASE("NaN and infinite vertices") {
        check_obj("v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n", "mesh.obj:3:", "NaN or infinite");
        check_obj("v 0 0 0\nv 1 0 inf\nv 0 1 0\nf 1 2 3\n", "mesh.obj:2:", "NaN or infinite");
        check_obj("v 0 0 0\nv 1 0 1e39\nv 0 1 0\nf 1 2 3\n",
                  "mesh.obj:2:", "outside the binary32 range");
        check_obj(v3 + "vn 0 0 nan\nf 1//1 2//1 3//1\n", "mesh.obj:4:", "NaN or infinite");
    }
    SUBCASE("face index out of range") {
        check_obj(v3 + "f 1 2 3\nf 1 2 4\n", "mesh.obj:5:", "vertex index 4 out of range");
        check_obj(v3 + "f 1 2 -4\n", "mesh.obj:4:", "vertex index -4 out of range");
        check_obj(v3 + "f 0 1 2\n", "mesh.obj:4:", "vertex index 0 out of range");
        check_obj(v3 + "vt 0 0\nf 1/1 2/2 3/1\n",
                  "mesh.obj:5:", "texture coordinate index 2 out of range");
        check_obj(v3 + "vn 0 0 1\nf 1//1 2//1 3//2\n",
                  "mesh.obj:5:", "normal index 2 out of range");
        // Indices refer to elements defined before the face.
        check_obj("v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n",
                  "mesh.obj:3:", "vertex index 3 out of range");
    }
    SUBCASE("malformed faces") {
        check_obj(v3 + "f 1 2\n", "mesh.obj:4:", "at least 3 vertices");
        check_obj(v3 + "f 1 2 x\n", "mesh.obj:4:", "malformed vertex index 'x'");
        check_obj(v3 + "f 1 2 3 # comment\n", "mesh.obj:4:", "malformed vertex index '#'");
    }
    SUBCASE("relative (negative) indices are accepted") {
        dir.write("mesh.obj", v3 + "f -3 -2 -1\n");
        CHECK(load_scene_file(scene).triangle_count() == 1);
    }
    SUBCASE("missing MTL file: the OBJ's mtllib line") {
        check_obj("# a comment\nmtllib missing.mtl\n" + v3 + "f 1 2 3\n",
                  "mesh.obj:2:", "MTL file 'missing.mtl' not found");
    }
    SUBCASE("usemtl of an undefined material") {
        dir.write("mesh.mtl", "newmtl stone\nKd 0.5 0.5 0.5\n");
        check_obj("mtllib mesh.mtl\n" + v3 + "usemtl marble\nf 1 2 3\n",
                  "mesh.obj:5:", "material 'marble' is not defined");
    }
    SUBCASE("missing texture: the MTL's map_Kd line") {
        dir.write("mesh.mtl", "newmtl stone\nKd 0.5 0.5 0.5\n\nmap_Kd stone.png\n");
        check_obj("mtllib mesh.mtl\n" + v3 + "usemtl stone\nf 1 2 3\n",
                  "mesh.mtl:4:", "texture 'stone.png' not found");
    }
    SUBCASE("unreadable texture: the MTL's map_Kd line and the reader's reason") {
        dir.write("stone.png", "not a png");
        dir.write("mesh.mtl", "newmtl stone\nmap_Kd stone.png\n");
        check_obj("mtllib mesh.mtl\n" + v3 + "usemtl stone\nf 1 2 3\n",
                  "mesh.mtl:2:", "cannot read texture 'stone.png'");
    }
    SUBCASE("MTL malformed number, bad roughness, duplicate material") {
        dir.write("mesh.mtl", "newmtl stone\nKd 0.5 abc 0.5\n");
        check_obj("mtllib mesh.mtl\n" + v3 + "f 1 2 3\n", "mesh.mtl:2:", "malformed number 'abc'");
        dir.write("mesh.mtl", "newmtl stone\nPr 1.5\n");
        check_obj("mtllib mesh.mtl\n" + v3 + "f 1 2 3\n",
                  "mesh.mtl:2:", "Pr (roughness) must be in [0, 1]");
        dir.write("mesh.mtl", "newmtl stone\nKd 1 1 1\nnewmtl stone\n");
        check_obj("mtllib mesh.mtl\n" + v3 + "f 1 2 3\n", "mesh.mtl:3:", "already defined at");
    }
    SUBCASE("errors that are no quirk stay errors without --strict-obj") {
        dir.write("mesh.obj", v3 + "f 1 2 4\n");
        check_scene_error(scene, "mesh.obj:4:", "vertex index 4 out of range");
        dir.write("mesh.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
        check_scene_error(scene, "mesh.obj:3:", "NaN or infinite");
        dir.write("mesh.obj", v3 + "f 1 2\n");
        check_scene_error(scene, "mesh.obj:4:", "at least 3 vertices");
        dir.write("mesh.obj", "v 0 0 0\nv 1 x2 0\nv 0 1 0\nf 1 2 3\n");
        check_scene_error(scene, "mesh.obj:2:", "malformed number 'x2'");
    }
    SUBCASE("CRLF line endings count lines like LF") {
        check_obj("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 4\r\n", "mesh.obj:4:", "out of range");
    }
}

// --- Camera path and display -------------------------------------------------------------------

TEST_CASE("scene file: camera path keyframes and display models are parsed") {
    TempDir dir("path");
    dir.write("tri.obj", triangle_obj);
    std::string scene = minimal_scene();
    const std::string camera_line =
        R"(  "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "vfov_deg": 45})";
    scene.replace(scene.find(camera_line), camera_line.size(),
                  camera_line + ",\n" +
                      R"(  "camera_path": [
    {"time": 0.5, "position": [0, 0, 5], "look_at": [0, 0, 0]},
    {"time": 1.5, "position": [2, 0, 5], "look_at": [2, 0, 0], "up": [0, 1, 0]},
    {"time": 3, "position": [4, 1, 5], "quaternion": [0, 0.70710677, 0, 0.70710677]}
  ],
  "display": {"model": "diagonal", "max_view_angle_deg": 55})");
    const Scene loaded = load_scene_file(dir.write("scene.json", scene));
    REQUIRE(loaded.camera_path.size() == 3);
    CHECK(loaded.camera_path[0].time == 0.5f);
    CHECK(loaded.camera_path[1].time == 1.5f);
    CHECK(loaded.camera_path[2].time == 3.0f);
    CHECK(loaded.camera_path[1].position == glm::vec3(2, 0, 5));
    // look_at keys: the orientation of look_at(); quaternion keys: as written (unit within 1e-6).
    CHECK(loaded.camera_path[1].orientation ==
          camera_orientation(look_at({2, 0, 5}, {2, 0, 0}, {0, 1, 0}, 45.0f)));
    CHECK(loaded.camera_path[2].orientation == glm::quat(0.70710677f, 0.0f, 0.70710677f, 0.0f));
    // Half-way between the first two keys: position interpolated linearly (exact here).
    CHECK(camera_at(loaded, 1.0f).position == glm::vec3(1, 0, 5));
    CHECK(loaded.display.kind == DisplayModel::Kind::diagonal);
    CHECK(loaded.display.max_view_angle_deg == 55.0f);

    const std::string display = R"("display": {"model": "diagonal", "max_view_angle_deg": 55})";
    scene.replace(scene.find(display), display.size(), R"("display": {"distance_px": 1200})");
    const Scene fixed = load_scene_file(dir.write("scene.json", scene));
    CHECK(fixed.display.kind == DisplayModel::Kind::fixed);
    CHECK(fixed.display.distance_px == 1200.0f);
}

TEST_CASE("scene file: Ns to roughness mapping") {
    CHECK(ns_to_roughness(0.0f) == 1.0f);
    // (2 / 4)^(1/4) and (2 / 1002)^(1/4); tolerance 1e-6: two float square roots.
    CHECK(std::fabs(ns_to_roughness(2.0f) - 0.840896415) < 1e-6);
    CHECK(std::fabs(ns_to_roughness(1000.0f) - std::pow(2.0 / 1002.0, 0.25)) < 1e-6);
}

// --- JSON locator ----------------------------------------------------------------------------

TEST_CASE("json locator: lines of nested values, array elements and escaped keys") {
    const std::string text =
        "{\n"                   // 1
        "  \"a\": {\n"          // 2
        "    \"b\": [1,\n"      // 3
        "          2],\n"       // 4
        "    \"c/d\": \"x\"\n"  // 5
        "  },\n"                // 6
        "  \"e~\\u0041\":\n"    // 7: key "e~A"
        "    true\n"            // 8
        "}\n";
    const JsonLocator locator(text, "t.json");
    CHECK(locator.find("").value_line == 1);
    CHECK(locator.find("/a").value_line == 2);
    CHECK(locator.find("/a/b").value_line == 3);
    CHECK(locator.find("/a/b/0").value_line == 3);
    CHECK(locator.find("/a/b/1").value_line == 4);
    CHECK(locator.find("/a/c~1d").value_line == 5);
    CHECK(locator.find("/e~0A").key_line == 7);
    CHECK(locator.find("/e~0A").value_line == 8);
    CHECK(locator.find("/nothing").value_line == 0);
    CHECK(json_pointer_member("/a", "c/d~") == "/a/c~1d~0");
    int line = 0, column = 0;
    json_line_column(text, text.find("\"c/d\""), line, column);
    CHECK(line == 5);
    CHECK(column == 5);
    const std::string deep(300, '[');
    CHECK(contains(error_of([&] { JsonLocator(deep + std::string(300, ']'), "d.json"); }),
                   "nested deeper"));
}

// --- Export round trip -------------------------------------------------------------------------

namespace {

void check_round_trip(const Scene& original, const std::string& directory) {
    export_scene(original, directory);
    const Scene reloaded = load_scene_file(directory + "/scene.json");
    // Geometry: bit-exact (9 significant digits round-trip binary32).
    CHECK(same_bits(reloaded.positions, original.positions));
    CHECK(same_bits(reloaded.normals, original.normals));
    CHECK(same_bits(reloaded.uvs, original.uvs));
    CHECK(reloaded.material_ids == original.material_ids);
    CHECK(reloaded.materials == original.materials);
    REQUIRE(reloaded.textures.size() == original.textures.size());
    for (std::size_t t = 0; t < original.textures.size(); ++t)
        CHECK(bit_equal(reloaded.textures[t].image, original.textures[t].image));  // PFM: lossless
    CHECK(reloaded.lights == original.lights);
    // Camera and path: exact (the camera is written as its basis, keys as quaternions).
    CHECK(reloaded.camera == original.camera);
    CHECK(reloaded.camera_path == original.camera_path);
    CHECK(reloaded.display == original.display);
    CHECK(reloaded.presets == original.presets);
    CHECK(reloaded.name == original.name);
    CHECK(reloaded.scene_scale == original.scene_scale);
    CHECK(reloaded.load_stats.zero_area_triangles_dropped == 0);
    CHECK(reloaded.load_stats.normals_generated == 0);  // every corner has its vn
    // Exporting the reloaded scene writes the same files again.
    export_scene(reloaded, directory + "/again");
    for (const char* file : {"scene.json", "scene.obj", "scene.mtl"})
        CHECK(read_file(directory + "/" + file) == read_file(directory + "/again/" + file));
}

}  // namespace

TEST_CASE("scene export: round trip of the hand-written scene is exact") {
    TempDir dir("export_room");
    const Scene original = load_scene_file(room_scene);
    check_round_trip(original, dir.file("out"));
    CHECK(fs::exists(dir.file("out/textures/checker.pfm")));
}

TEST_CASE("scene export: round trip of polygons, missing normals and odd values") {
    TempDir dir("export_poly");
    // A pentagon and a quad without normals, a triangle with non-unit normals and uvs, negative
    // relative indices, awkward decimals, a material without Kd, a camera given as a quaternion.
    dir.write("poly.mtl",
              "newmtl plain\n"
              "newmtl shiny\nKd 0.1 0.2 0.3\nKs 0.5 0.5 0.5\nNs 37\nKe 0 0.25 0\n");
    dir.write("poly.obj",
              "mtllib poly.mtl\n"
              "v 0.1 0.2 0.3\nv 1.0000001 0 0\nv 1.3 0.9 -0.1\nv 0.5 1.7 0\nv -0.3 0.8 1e-3\n"
              "usemtl shiny\nf 1 2 3 4 5\n"
              "v 3 0 0\nv 4 0 0\nv 4 1 0\nv 3 1 0.3333333\n"
              "usemtl plain\nf -4 -3 -2 -1\n"
              "vt 0.123456789 0.987654321\nvt 1e-7 3.3\nvt -2 0.5\n"
              "vn 0.3 0.4 0.5\nvn 0 0 2\nvn 1 1 1\n"
              "f 1/1/1 3/2/2 5/3/3\n");
    dir.write("scene.json", R"({
  "version": 1,
  "name": "odd",
  "meshes": [{"obj": "poly.obj", "transform": {"rotate_deg": [10, 20, 30], "translate": [0.1, 0.2, 0.3]}}],
  "lights": [{"type": "point", "position": [0.1, 2.2, 3.3], "intensity": [1.5, 0.7, 0.3]},
             {"type": "quad", "corner": [0, 3, 0], "edge_u": [0.1, 0, 0], "edge_v": [0, 0, 0.7], "radiance": 9}],
  "camera": {"position": [1, 2, 3], "quaternion": [0.1, 0.2, 0.3, 0.9], "vfov_deg": 47.5},
  "camera_path": [
    {"time": 0, "position": [1, 2, 3], "quaternion": [0.1, 0.2, 0.3, 0.9]},
    {"time": 0.1, "position": [1.1, 2, 3], "look_at": [0, 0, 0]}
  ],
  "display": {"distance_px": 1234.5},
  "presets": {"b": {"sigma": 0.75, "alpha": 1, "names": ["x", "y"]}, "a": {},
              "c": {"note": "see [1,2] \\\"q\\\" ]", "grid": [[1, 2], [3, -4.5e-3]]}}
})");
    const Scene original = load_scene_file(dir.file("scene.json"));
    CHECK(original.triangle_count() == 3 + 2 + 1);
    CHECK(original.load_stats.polygons_triangulated == 2);
    CHECK(original.load_stats.normals_generated == 5);
    CHECK(original.materials[0].albedo == glm::vec3(0.8f));  // no Kd, no texture: the default
    CHECK(original.materials[1].roughness == ns_to_roughness(37.0f));
    check_round_trip(original, dir.file("out"));
}

TEST_CASE("scene file: OBJ and MTL numbers are correctly rounded to binary32") {
    // Each decimal lies just above the midpoint between two adjacent floats. Correct rounding
    // (std::from_chars) goes up; rounding to binary64 first lands exactly on the midpoint and
    // then ties to even, one ulp lower (what tinyobjloader's parser does).
    const char* above_one = "1.00000005960464477539062500001";   // 1 + 2^-24 + 1e-29
    const char* above_half = "0.50000002980232238769531250001";  // 0.5 + 2^-25 + 1e-29
    const char* above_200 = "200.00000762939453125001";          // 200 + 2^-17 + 1e-20
    auto correctly_rounded = [](const char* text) {
        float value = 0.0f;
        const auto [end, ec] = std::from_chars(text, text + std::strlen(text), value);
        REQUIRE(ec == std::errc());
        REQUIRE(*end == '\0');
        return value;
    };
    for (const char* text : {above_one, above_half, above_200}) {
        INFO(text);
        // The inputs are hard cases: double rounding gives another float (else this test
        // could not tell the parsers apart).
        CHECK(correctly_rounded(text) != static_cast<float>(std::strtod(text, nullptr)));
        CHECK(correctly_rounded(text) ==
              std::nextafter(static_cast<float>(std::strtod(text, nullptr)), 1e30f));
    }
    const float one_up = correctly_rounded(above_one);
    CHECK(one_up == std::nextafter(1.0f, 2.0f));

    TempDir dir("rounding");
    dir.write("mesh.mtl", std::string("newmtl hard\n") + "Kd 0.1 " + above_half + " 0.25\n" +
                              "Ks " + above_half + " 0 0\nKe 0 " + above_200 + " 0\nNs " +
                              above_200 + "\n" + "newmtl rough\nPr " + above_half + "\n");
    dir.write("mesh.obj", std::string("mtllib mesh.mtl\n") + "v " + above_one + " 0.1 " +
                              above_200 + "\nv 2 0 0\nv 0 2 0\n" + "vt " + above_one + " 0.1\n" +
                              "vn 0 0 " + above_one + "\n" + "usemtl hard\nf 1/1/1 2/1/1 3/1/1\n" +
                              "usemtl rough\nf 1 3 2\n");
    dir.write("scene.json", minimal_scene("mesh.obj"));
    const Scene scene = load_scene_file(dir.file("scene.json"));
    REQUIRE(scene.triangle_count() == 2);
    // Positions, uvs, normals: bit-exact (no instance transform, so taken as parsed; the normal's
    // |n|^2 - 1 = 2.4e-7 is within the loader's 1e-6 unit-length tolerance, so it is kept).
    const glm::vec3 p = scene.positions[0];
    CHECK(std::bit_cast<std::uint32_t>(p.x) == std::bit_cast<std::uint32_t>(one_up));
    CHECK(std::bit_cast<std::uint32_t>(p.y) == std::bit_cast<std::uint32_t>(0.1f));
    CHECK(std::bit_cast<std::uint32_t>(p.z) ==
          std::bit_cast<std::uint32_t>(correctly_rounded(above_200)));
    CHECK(scene.uvs[0].x == one_up);
    CHECK(scene.uvs[0].y == 0.1f);
    CHECK(scene.normals[0].z == one_up);
    // MTL values.
    const Material& hard = scene.materials[static_cast<std::size_t>(scene.material_ids[0])];
    CHECK(hard.albedo.x == 0.1f);
    CHECK(hard.albedo.y == correctly_rounded(above_half));
    CHECK(hard.specular.x == correctly_rounded(above_half));
    CHECK(hard.emission.y == correctly_rounded(above_200));
    CHECK(hard.roughness == ns_to_roughness(correctly_rounded(above_200)));
    const Material& rough = scene.materials[static_cast<std::size_t>(scene.material_ids[1])];
    CHECK(rough.name == "rough");
    CHECK(rough.roughness == correctly_rounded(above_half));
    // And the exported scene reloads to the same bits.
    check_round_trip(scene, dir.file("out"));
}

TEST_CASE("scene export: round trip of floats over the whole binary32 range is exact") {
    // Triangles with coordinates of every exponent from 2^-60 to 2^30, both signs, random
    // mantissas (a fixed LCG), written as %.9g like the exporter does. (Larger values would
    // overflow the area test, |cross|^2 > 2^128, and be dropped as not finite.)
    TempDir dir("export_range");
    std::uint32_t state = 12345u;
    auto next_float = [&state] {
        state = state * 1664525u + 1013904223u;  // LCG (Numerical Recipes constants)
        const std::uint32_t exponent = 127u - 60u + (state >> 8) % 91u;
        const std::uint32_t bits =
            (state & 0x80000000u) | (exponent << 23) | ((state * 2654435761u) & 0x7fffffu);
        return std::bit_cast<float>(bits);
    };
    std::vector<glm::vec3> expected;
    std::string obj;
    char buffer[32];
    for (int t = 0; t < 300; ++t) {
        // Corner 0 random, corners 1 and 2 offset along x and y so the area is never zero.
        glm::vec3 p0(next_float(), next_float(), next_float());
        for (glm::vec3 p : {p0, p0 + glm::vec3(std::fabs(p0.x) + 1.0f, 0.0f, 0.0f),
                            p0 + glm::vec3(0.0f, std::fabs(p0.y) + 1.0f, 0.0f)}) {
            std::snprintf(buffer, sizeof buffer, "v %.9g", static_cast<double>(p.x));
            obj += buffer;
            std::snprintf(buffer, sizeof buffer, " %.9g", static_cast<double>(p.y));
            obj += buffer;
            std::snprintf(buffer, sizeof buffer, " %.9g\n", static_cast<double>(p.z));
            obj += buffer;
            expected.push_back(p);
        }
        obj += "f -3 -2 -1\n";
    }
    dir.write("mesh.obj", obj);
    dir.write("scene.json", minimal_scene("mesh.obj"));
    const Scene scene = load_scene_file(dir.file("scene.json"));
    REQUIRE(scene.load_stats.zero_area_triangles_dropped == 0);
    CHECK(same_bits(scene.positions, expected));
    check_round_trip(scene, dir.file("out"));
}

// --- Robustness ----------------------------------------------------------------------------------

TEST_CASE("scene file: corrupted inputs load or throw fovref::Error, never anything else") {
    // Deterministic single-character corruptions and truncations of the hand-written scene's
    // JSON, OBJ and MTL; run under ASan/UBSan in CI, so a crash or UB would also fail.
    TempDir dir("corrupt");
    const fs::path source = fs::path(FOVREF_SOURCE_DIR) / "scenes/textured-room";
    for (const char* name : {"scene.json", "room.obj", "box.obj", "room.mtl", "checker.png"})
        fs::copy_file(source / name, dir.path / name);
    const std::string replacements = "{}[],:\"0-.e \n/#x";
    int errors = 0, loads = 0;
    for (const char* name : {"scene.json", "room.obj", "room.mtl"}) {
        const std::string original = read_file(dir.file(name));
        for (std::size_t k = 0; k < 150; ++k) {
            std::string text = original;
            if (k % 10 == 9) {
                text.resize((k * 7919) % text.size());  // truncation
            } else {
                text[(k * 7919 + 13) % text.size()] = replacements[k % replacements.size()];
            }
            dir.write(name, text);
            try {
                load_scene_file(dir.file("scene.json"));
                ++loads;
            } catch (const Error&) {
                ++errors;
            } catch (const std::exception& e) {
                FAIL("not a fovref::Error after corrupting " << name << " (" << k
                                                             << "): " << e.what());
            }
        }
        dir.write(name, original);
    }
    CHECK(errors + loads == 450);
    CHECK(errors > 100);  // most corruptions are errors; some (in comments, digits) still load
}

TEST_CASE("scene export: round trip of the small procedural scenes is exact") {
    // Procedural scenes are built in code (their textures, names and cameras were not made by
    // the loader), so they exercise the exporter on scenes it did not read itself.
    for (const char* name : {"cornell", "checker-room", "glossy-floor"}) {
        INFO("scene " << name);
        TempDir dir(std::string("export_") + name);
        check_round_trip(make_procedural_scene(name), dir.file("out"));
    }
}

TEST_CASE("scene JSON numbers are rounded to binary32 once, from the text") {
    // 1 + 2^-24 + 2^-80 lies just above the midpoint between 1 and the next float: correctly
    // rounded it is 1.0000001f, but rounded to binary64 first it becomes exactly the midpoint
    // 1 + 2^-24 and then rounds (to even) down to 1.0f.
    const std::string hard = "1.00000005960464477539062500001";
    REQUIRE(static_cast<float>(std::stod(hard)) == 1.0f);
    const auto dir =
        std::filesystem::temp_directory_path() / ("fovref-json-round-" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    {
        std::ofstream out(dir / "scene.json");
        out << R"({"version": 1, "camera": {"position": [0, 0, )" << hard
            << R"(], "look_at": [0, 0, -1], "vfov_deg": 60}})";
    }
    Scene scene = load_scene_file((dir / "scene.json").string());
    CHECK(scene.camera.position.z == std::nextafter(1.0f, 2.0f));
    std::filesystem::remove_all(dir);
}

TEST_CASE("scene JSON: the integer -0 is read as -0.0f (no overflow in the rounding check)") {
    // nlohmann reads the integer -0 as +0, the text's own rounding gives -0.0f: their distance
    // in the binary32 ordering is 0. (The check used to subtract the bit patterns as int32,
    // which overflows for -0.0f: undefined behaviour, an UBSan abort.)
    TempDir dir("minus_zero");
    dir.write("tri.obj", triangle_obj);
    std::string scene = minimal_scene();
    scene.replace(scene.find("[0, 0, 5]"), 9, "[0, -0, 5]");
    const Scene loaded = load_scene_file(dir.write("scene.json", scene));
    CHECK(loaded.camera.position.y == 0.0f);
    CHECK(std::signbit(loaded.camera.position.y));
    CHECK(loaded.camera.position.z == 5.0f);
}
