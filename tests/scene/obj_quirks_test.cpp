// OBJ quirks of real-world files (docs/obj-quirks.md) on the corpus of tests/scene/obj-quirks:
// each loads with its documented warning, or is the documented error with --strict-obj; polygon
// triangulation (fan for convex, ear clipping for concave); bare model files as scenes (default
// camera and light, --camera).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "ref/core/error.h"
#include "ref/scene/polygon.h"
#include "ref/scene/scene_file.h"
#include "tests/scene/scene_test_util.h"

using namespace fovref;
using fovref::test::base64;
using fovref::test::contains;
using fovref::test::error_message;
using fovref::test::TempDir;
using fovref::test::write_bytes;

namespace {

const std::string corpus = std::string(FOVREF_SOURCE_DIR) + "/tests/scene/obj-quirks/";

// The one warning that contains `part` (fails when none does).
std::string warning_with(const Scene& scene, const std::string& part) {
    for (const std::string& w : scene.load_stats.warnings)
        if (contains(w, part)) return w;
    FAIL("no warning contains '" << part << "'; warnings: " << scene.load_stats.warnings.size());
    return "";
}

SceneLoadOptions strict_options() {
    SceneLoadOptions options;
    options.strict_obj = true;
    return options;
}

int material_of(const Scene& scene, std::size_t index) { return scene.material_ids[index]; }

double signed_area_z(const Scene& scene, std::size_t t) {
    const glm::dvec3 a(scene.positions[3 * t]), b(scene.positions[3 * t + 1]),
        c(scene.positions[3 * t + 2]);
    return 0.5 * glm::cross(b - a, c - a).z;
}

// Whether (x, y) lies strictly inside one of the scene's triangles (all in the z = 0 plane).
bool covered(const Scene& scene, double x, double y) {
    for (std::size_t t = 0; t < scene.triangle_count(); ++t) {
        const glm::dvec3 p[3] = {glm::dvec3(scene.positions[3 * t]),
                                 glm::dvec3(scene.positions[3 * t + 1]),
                                 glm::dvec3(scene.positions[3 * t + 2])};
        double s[3];
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3 a = p[k], b = p[(k + 1) % 3];
            s[k] = (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x);
        }
        if ((s[0] > 0 && s[1] > 0 && s[2] > 0) || (s[0] < 0 && s[1] < 0 && s[2] < 0)) return true;
    }
    return false;
}

}  // namespace

// --- The corpus, one quirk per file -------------------------------------------------------------

TEST_CASE("OBJ quirks: usemtl of an undefined material gets the default material, with a warning") {
    const std::string obj = corpus + "undefined-material.obj";
    const Scene scene = load_model_file(obj);
    REQUIRE(scene.triangle_count() == 2);
    CHECK(scene.materials[material_of(scene, 0)].name == "Red");
    CHECK(scene.materials[material_of(scene, 0)].albedo == glm::vec3(0.8f, 0.1f, 0.1f));
    CHECK(scene.materials[material_of(scene, 1)].name == "default");
    CHECK(scene.materials[material_of(scene, 1)].albedo == glm::vec3(0.8f));
    CHECK(contains(warning_with(scene, "'Chrome'"),
                   "undefined-material.obj:13: material 'Chrome' is not defined by any MTL file"));
    CHECK(contains(error_message([&] { load_model_file(obj, strict_options()); }),
                   "undefined-material.obj:13: material 'Chrome' is not defined by an mtllib"));
}

TEST_CASE("OBJ quirks: a missing MTL file is a warning, and its materials' faces get the default") {
    const std::string obj = corpus + "missing-mtl.obj";
    const Scene scene = load_model_file(obj);
    REQUIRE(scene.triangle_count() == 2);
    CHECK(scene.materials.size() == 1);
    CHECK(scene.materials[0].name == "default");
    CHECK(contains(warning_with(scene, "nowhere.mtl"),
                   "missing-mtl.obj:2: MTL file 'nowhere.mtl' not found"));
    CHECK(contains(warning_with(scene, "'Red'"), "missing-mtl.obj:11: material 'Red'"));
    CHECK(contains(error_message([&] { load_model_file(obj, strict_options()); }),
                   "missing-mtl.obj:2: MTL file 'nowhere.mtl' not found"));
}

TEST_CASE("OBJ quirks: material names with blanks are read whole, in MTL and usemtl alike") {
    const std::string obj = corpus + "material-with-spaces.obj";
    const Scene scene = load_model_file(obj);
    REQUIRE(scene.triangle_count() == 2);
    CHECK(scene.materials[material_of(scene, 0)].name == "Red Paint");
    CHECK(scene.materials[material_of(scene, 0)].albedo == glm::vec3(0.8f, 0.1f, 0.1f));
    CHECK(scene.materials[material_of(scene, 1)].name == "Blue  Paint");
    CHECK(scene.materials[material_of(scene, 1)].albedo == glm::vec3(0.1f, 0.1f, 0.8f));
    CHECK(contains(warning_with(scene, "Red Paint"),
                   "spaces.mtl:1: material name 'Red Paint' contains blanks"));
    CHECK(contains(error_message([&] { load_model_file(obj, strict_options()); }),
                   "spaces.mtl:1: newmtl needs one material name without blanks"));
}

TEST_CASE("OBJ quirks: a texture path with backslashes is read with '/'") {
    const std::string obj = corpus + "backslash-texture.obj";
    const Scene scene = load_model_file(obj);
    REQUIRE(scene.triangle_count() == 2);
    const Material& material = scene.materials[material_of(scene, 0)];
    REQUIRE(material.texture >= 0);
    const Texture& texture = scene.textures[material.texture];
    CHECK(texture.image.width == 2);
    CHECK(texture.image.at(0, 0, 0) == 1.0f);  // the checker's white texel, sRGB decoded
    CHECK(texture.image.at(1, 0, 0) == 0.0f);
    CHECK(contains(warning_with(scene, "backslash.mtl"),
                   "backslash.mtl:3: texture path 'textures\\checker.png' uses '\\' as a path "
                   "separator; read as 'textures/checker.png'"));
    CHECK(contains(error_message([&] { load_model_file(obj, strict_options()); }),
                   "backslash.mtl:3: texture path 'textures\\checker.png' uses '\\'"));
}

TEST_CASE("OBJ quirks: a missing texture is a warning, the material is drawn without it") {
    const std::string obj = corpus + "missing-texture.obj";
    const Scene scene = load_model_file(obj);
    const Material& material = scene.materials[material_of(scene, 0)];
    CHECK(material.name == "Wall");
    CHECK(material.texture == -1);
    CHECK(material.albedo == glm::vec3(0.8f));  // no Kd: Material's default, not white
    CHECK(contains(warning_with(scene, "wal67ar_small.jpg"),
                   "missing-texture.mtl:2: texture 'wal67ar_small.jpg' not found"));
    CHECK(contains(error_message([&] { load_model_file(obj, strict_options()); }),
                   "missing-texture.mtl:2: texture 'wal67ar_small.jpg' not found"));
}

TEST_CASE("OBJ quirks: CR line ends and a missing final newline read like the LF file") {
    TempDir dir("obj-quirks-lf");
    write_bytes(dir.file("lf.obj"),
                "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1 2 3 4\n");
    const Scene lf = load_model_file(dir.file("lf.obj"));
    CHECK(lf.load_stats.warnings.empty());
    for (const char* name : {"cr-line-endings.obj", "no-final-newline.obj"}) {
        CAPTURE(name);
        const Scene scene = load_model_file(corpus + name);
        CHECK(scene.positions == lf.positions);
        CHECK(scene.normals == lf.normals);
        CHECK(scene.load_stats.warnings.size() == 1);
        // Accepted in strict mode too: nothing is lost.
        CHECK(load_model_file(corpus + name, strict_options()).positions == lf.positions);
    }
    CHECK(contains(warning_with(load_model_file(corpus + "cr-line-endings.obj"), "lone CR"),
                   "cr-line-endings.obj: lines end in a lone CR"));
    CHECK(contains(warning_with(load_model_file(corpus + "no-final-newline.obj"), "last line"),
                   "no-final-newline.obj: the last line has no line break"));
}

TEST_CASE("OBJ quirks: a concave polygon is ear-clipped, its fan would cover the notch") {
    const Scene scene = load_model_file(corpus + "concave-polygon.obj");
    REQUIRE(scene.triangle_count() == 2);
    CHECK(scene.load_stats.concave_polygons == 1);
    double area = 0.0;
    for (std::size_t t = 0; t < 2; ++t) {
        CHECK(signed_area_z(scene, t) > 0.0);  // wound like the polygon (counter-clockwise)
        area += signed_area_z(scene, t);
    }
    CHECK(area == 4.0);                // the dart's area
    CHECK(!covered(scene, 2.0, 0.5));  // the notch below the reflex corner (2, 1)
    CHECK(covered(scene, 2.2, 1.5));
    CHECK(covered(scene, 1.8, 1.5));
    CHECK(covered(scene, 1.0, 0.6));
    // The fan from corner 0 would have produced (0,0) (2,1) (4,0): clockwise, over the notch.
    const bool first_is_fan_triangle = scene.positions[0] == glm::vec3(0, 0, 0) &&
                                       scene.positions[1] == glm::vec3(2, 1, 0) &&
                                       scene.positions[2] == glm::vec3(4, 0, 0);
    CHECK(!first_is_fan_triangle);
}

TEST_CASE("OBJ quirks: UTF-16 and NUL bytes are errors that say so, a UTF-8 BOM is skipped") {
    CHECK(contains(error_message([&] { load_model_file(corpus + "utf16.obj"); }),
                   "utf16.obj: the file is UTF-16 text (byte-order mark FF FE)"));
    TempDir dir("obj-quirks-bytes");
    write_bytes(dir.file("be.obj"), std::string("\xFE\xFF\0v", 4));
    CHECK(contains(error_message([&] { load_model_file(dir.file("be.obj")); }),
                   "the file is UTF-16 text (byte-order mark FE FF)"));
    write_bytes(dir.file("nul.obj"), std::string("v 0 0 0\nv 1 0 0\n\0v 0 1 0\nf 1 2 3\n", 33));
    CHECK(contains(error_message([&] { load_model_file(dir.file("nul.obj")); }),
                   "nul.obj:3: NUL byte at offset 16"));
    write_bytes(dir.file("bom.obj"), "\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const Scene bom = load_model_file(dir.file("bom.obj"));
    CHECK(bom.triangle_count() == 1);
    CHECK(bom.load_stats.warnings.empty());
}

TEST_CASE(
    "OBJ quirks: points and lines are counted and ignored, a file of lines only is an error") {
    const Scene scene = load_model_file(corpus + "points-and-lines.obj");
    CHECK(scene.triangle_count() == 1);
    CHECK(scene.load_stats.points_ignored == 3);
    CHECK(scene.load_stats.lines_ignored == 2);
    CHECK(contains(warning_with(scene, "ignored"),
                   "points-and-lines.obj: 3 points (p) and 2 lines (l) ignored"));
    CHECK(contains(error_message([&] { load_model_file(corpus + "only-lines.obj"); }),
                   "only-lines.obj: no triangles to render: the file has no faces (0 points and 1 "
                   "lines ignored)"));
}

TEST_CASE("OBJ quirks: duplicate materials, a clashing 'default', several mtllib files, case") {
    TempDir dir("obj-quirks-more");
    const std::string quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";
    SUBCASE("a material defined twice: the first definition is used") {
        write_bytes(dir.file("twice.mtl"),
                    "newmtl stone\nKd 0.5 0.5 0.5\nnewmtl stone\nKd 1 0 0\n");
        write_bytes(dir.file("twice.obj"), "mtllib twice.mtl\n" + quad + "usemtl stone\nf 1 2 3\n");
        const Scene scene = load_model_file(dir.file("twice.obj"));
        CHECK(scene.materials[material_of(scene, 0)].albedo == glm::vec3(0.5f));
        CHECK(contains(warning_with(scene, "defined again"),
                       "twice.mtl:3: material 'stone' is defined again (first at "));
    }
    SUBCASE("an MTL 'default' unlike the fallback: faces without usemtl get 'default-2'") {
        write_bytes(dir.file("d.mtl"), "newmtl default\nKd 1 0 0\n");
        write_bytes(dir.file("d.obj"),
                    "mtllib d.mtl\n" + quad + "f 1 2 3\nusemtl default\nf 1 3 4\n");
        const Scene scene = load_model_file(dir.file("d.obj"));
        CHECK(scene.materials[material_of(scene, 0)].name == "default-2");
        CHECK(scene.materials[material_of(scene, 0)].albedo == glm::vec3(0.8f));
        CHECK(scene.materials[material_of(scene, 1)].name == "default");
        CHECK(scene.materials[material_of(scene, 1)].albedo == glm::vec3(1, 0, 0));
    }
    SUBCASE("mtllib naming two files; an MTL file name with a blank") {
        write_bytes(dir.file("a.mtl"), "newmtl a\nKd 1 0 0\n");
        write_bytes(dir.file("b.mtl"), "newmtl b\nKd 0 1 0\n");
        write_bytes(dir.file("my model.mtl"), "newmtl c\nKd 0 0 1\n");
        write_bytes(dir.file("two.obj"), "mtllib a.mtl b.mtl\nmtllib my model.mtl\n" + quad +
                                             "usemtl b\nf 1 2 3\nusemtl c\nf 1 3 4\n");
        const Scene scene = load_model_file(dir.file("two.obj"));
        CHECK(scene.materials[material_of(scene, 0)].name == "b");
        CHECK(scene.materials[material_of(scene, 1)].name == "c");
        CHECK(contains(warning_with(scene, "my model.mtl"), "two.obj:2: MTL file name"));
        CHECK(contains(warning_with(scene, "mtllib names 2 files"), "two.obj:1: "));
        CHECK(
            contains(error_message([&] { load_model_file(dir.file("two.obj"), strict_options()); }),
                     "two.obj:1: mtllib needs exactly one file name"));
    }
    SUBCASE("a texture named in another letter case") {
        write_bytes(dir.file("Brick.PFM"), std::string("PF\n1 1\n-1\n") + std::string(12, '\0'));
        write_bytes(dir.file("case.mtl"), "newmtl brick\nmap_Kd brick.pfm\n");
        write_bytes(dir.file("case.obj"), "mtllib case.mtl\n" + quad + "usemtl brick\nf 1 2 3\n");
        const Scene scene = load_model_file(dir.file("case.obj"));
        CHECK(scene.materials[material_of(scene, 0)].texture == 0);
        CHECK(contains(warning_with(scene, "letter case"),
                       "case.mtl:2: texture 'brick.pfm' not found; using 'Brick.PFM'"));
        CHECK(contains(
            error_message([&] { load_model_file(dir.file("case.obj"), strict_options()); }),
            "case.mtl:2: texture 'brick.pfm' not found"));
    }
}

// --- Polygon triangulation
// ------------------------------------------------------------------------

TEST_CASE("triangulate_polygon: convex polygons keep the fan, concave ones are ear-clipped") {
    PolygonSplit split = PolygonSplit::triangle;
    const std::vector<glm::vec3> hexagon = {{2, 0, 0},  {1, 2, 0},   {-1, 2, 0},
                                            {-2, 0, 0}, {-1, -2, 0}, {1, -2, 0}};
    const auto fan = triangulate_polygon(hexagon, &split);
    CHECK(split == PolygonSplit::fan);
    REQUIRE(fan.size() == 4);
    for (int k = 0; k < 4; ++k)
        CHECK(fan[static_cast<std::size_t>(k)] == std::array<int, 3>{0, k + 1, k + 2});

    // An L in the y-z plane, wound clockwise seen from +x (its normal is -x): corner 3 is reflex.
    const std::vector<glm::vec3> ell = {{0, 0, 0}, {0, 0, 2}, {0, 1, 2},
                                        {0, 1, 1}, {0, 2, 1}, {0, 2, 0}};
    const auto clipped = triangulate_polygon(ell, &split);
    CHECK(split == PolygonSplit::ear_clipped);
    REQUIRE(clipped.size() == 4);
    double area = 0.0;
    for (const auto& t : clipped) {
        const glm::dvec3 a(ell[t[0]]), b(ell[t[1]]), c(ell[t[2]]);
        const glm::dvec3 n = glm::cross(b - a, c - a);
        CHECK(n.x < 0.0);  // every triangle faces like the polygon
        area += 0.5 * -n.x;
    }
    CHECK(area == 3.0);
}

TEST_CASE("triangulate_polygon: random star-shaped polygons give n-2 triangles covering the area") {
    fovref::test::SplitMix64 random(18);
    for (int trial = 0; trial < 200; ++trial) {
        const int n = 4 + static_cast<int>(random.below(40));
        // Star-shaped about the origin (radii vary, angles increase): simple, usually concave.
        std::vector<glm::vec3> polygon;
        std::vector<double> angles;
        for (int k = 0; k < n; ++k)
            angles.push_back((k + 0.5 * random.unit()) * 6.283185307179586 / n);
        for (int k = 0; k < n; ++k) {
            // cos/sin by a short series keeps the test free of libm (any smooth closed curve will
            // do)
            const double a = angles[static_cast<std::size_t>(k)] - 3.141592653589793;
            const double a2 = a * a;
            const double c = 1 - a2 / 2 + a2 * a2 / 24 - a2 * a2 * a2 / 720 +
                             a2 * a2 * a2 * a2 / 40320 - a2 * a2 * a2 * a2 * a2 / 3628800 +
                             a2 * a2 * a2 * a2 * a2 * a2 / 479001600;
            const double s = a * (1 - a2 / 6 + a2 * a2 / 120 - a2 * a2 * a2 / 5040 +
                                  a2 * a2 * a2 * a2 / 362880 - a2 * a2 * a2 * a2 * a2 / 39916800 +
                                  a2 * a2 * a2 * a2 * a2 * a2 / 6227020800.0);
            const double r = 0.3 + random.unit();
            polygon.emplace_back(static_cast<float>(-r * c), static_cast<float>(-r * s), 0.0f);
        }
        double polygon_area = 0.0;
        for (int k = 0; k < n; ++k) {
            const glm::dvec3 a(polygon[static_cast<std::size_t>(k)]);
            const glm::dvec3 b(polygon[static_cast<std::size_t>((k + 1) % n)]);
            polygon_area += 0.5 * (a.x * b.y - b.x * a.y);
        }
        CAPTURE(trial);
        REQUIRE(polygon_area > 0.0);
        PolygonSplit split = PolygonSplit::triangle;
        const auto triangles = triangulate_polygon(polygon, &split);
        CHECK(split != PolygonSplit::not_simple);
        REQUIRE(triangles.size() == static_cast<std::size_t>(n - 2));
        double sum = 0.0;
        std::vector<int> uses(static_cast<std::size_t>(n), 0);
        for (const auto& t : triangles) {
            const glm::dvec3 a(polygon[t[0]]), b(polygon[t[1]]), c(polygon[t[2]]);
            const double area = 0.5 * glm::cross(b - a, c - a).z;
            CHECK(area > 0.0);  // every triangle wound like the polygon, none degenerate
            sum += area;
            for (int k : t) ++uses[static_cast<std::size_t>(k)];
        }
        // All positive, so the sum is the area covered, counting overlaps twice: equal to the
        // polygon's, they do not overlap (a fan over a concave star would).
        CHECK(std::fabs(sum - polygon_area) <= 1e-9 * polygon_area);
        for (int u : uses) CHECK(u >= 1);
    }
}

// --- Model files as scenes
// ------------------------------------------------------------------------

TEST_CASE("model files: default camera frames the bounding sphere, default light at the camera") {
    TempDir dir("model-defaults");
    // Bounds (-1,-2,-3) .. (3,2,1): centre (1,0,-1), diagonal sqrt(16+16+16) = 4 sqrt(3).
    write_bytes(dir.file("box.obj"), "v -1 -2 -3\nv 3 -2 -3\nv 3 2 1\nf 1 2 3\n");
    const Scene scene = load_scene(dir.file("box.obj"));
    const float radius = glm::length(glm::vec3(4, 4, 4)) * 0.5f;
    CHECK(scene.camera.position == glm::vec3(1, 0, -1) + glm::vec3(0, 0, 2 * radius));
    CHECK(scene.camera.forward == glm::vec3(0, 0, -1));
    CHECK(scene.camera.up == glm::vec3(0, 1, 0));
    CHECK(scene.camera.vfov_deg == 60.0f);
    REQUIRE(scene.lights.size() == 1);
    CHECK(scene.lights[0].type == Light::Type::point);
    CHECK(scene.lights[0].position == scene.camera.position);
    const float d = 2 * radius;
    CHECK(scene.lights[0].intensity.x == 3.14159274f * d * d);
    REQUIRE(scene.load_stats.defaulted.size() == 2);
    CHECK(contains(scene.load_stats.defaulted[0], "camera: at"));
    CHECK(contains(scene.load_stats.defaulted[1], "light: point light at the camera"));
    // The sphere fits the vertical field of view: sin(30 deg) = r / d.
    CHECK(radius / d == 0.5f);
}

TEST_CASE("model files: an emissive material is the light, --camera replaces the camera") {
    TempDir dir("model-camera");
    write_bytes(dir.file("lamp.mtl"), "newmtl lamp\nKe 4 4 4\n");
    write_bytes(dir.file("lamp.obj"),
                "mtllib lamp.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl lamp\nf 1 2 3\n");
    write_bytes(dir.file("camera.json"),
                R"({"camera": {"position": [0, 0, 9], "look_at": [0, 0, 0], "vfov_deg": 40}})");
    SceneLoadOptions options;
    options.camera_file = dir.file("camera.json");
    const Scene scene = load_scene(dir.file("lamp.obj"), options);
    REQUIRE(scene.lights.size() == 1);
    CHECK(scene.lights[0].type == Light::Type::triangle);
    CHECK(scene.camera.position == glm::vec3(0, 0, 9));
    CHECK(scene.camera.vfov_deg == 40.0f);
    REQUIRE(scene.load_stats.defaulted.size() == 1);
    CHECK(contains(scene.load_stats.defaulted[0], "camera: from "));
    // A camera file that is the camera object itself; one with an error names its line.
    write_bytes(dir.file("bare.json"),
                "{\"position\": [1, 2, 3],\n \"look_at\": [0, 0, 0],\n \"vfov_deg\": 50}");
    CHECK(load_camera_file(dir.file("bare.json")).position == glm::vec3(1, 2, 3));
    write_bytes(dir.file("bad.json"),
                "{\"position\": [1, 2, 3],\n \"look_at\": [1, 2, 3],\n \"vfov_deg\": 50}");
    CHECK(contains(error_message([&] { load_camera_file(dir.file("bad.json")); }), "bad.json:"));
    // --camera also replaces a scene file's camera and drops its path.
    const Scene procedural = load_scene("cornell", options);
    CHECK(procedural.camera.position == glm::vec3(0, 0, 9));
}

TEST_CASE(
    "OBJ quirks: nameless materials, one-value colours, malformed numbers, Latin-1, long faces") {
    TempDir dir("obj-quirks-real");
    SUBCASE("newmtl and usemtl without a name (Blender's empty_mat.obj)") {
        write_bytes(dir.file("e.mtl"), "newmtl \nKd 0.1 0.2 0.3\nKs 0\n");
        write_bytes(dir.file("e.obj"),
                    "mtllib e.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl \nf 1 2 3\n");
        const Scene scene = load_model_file(dir.file("e.obj"));
        CHECK(scene.materials.size() == 1);
        CHECK(scene.materials[0].name == "default");
        CHECK(contains(warning_with(scene, "newmtl without a name"), "e.mtl:1:"));
        CHECK(contains(warning_with(scene, "usemtl without"), "e.obj:5:"));
        CHECK(contains(error_message([&] { load_model_file(dir.file("e.obj"), strict_options()); }),
                       "e.mtl:1: newmtl needs a material name"));
    }
    SUBCASE("Kd with one value is grey (the MTL format's rule); two values are an error") {
        write_bytes(dir.file("g.mtl"), "newmtl grey\nKd 0.25\nKs 0.5\n");
        write_bytes(dir.file("g.obj"),
                    "mtllib g.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl grey\nf 1 2 3\n");
        const Scene scene = load_model_file(dir.file("g.obj"));
        CHECK(scene.materials[0].albedo == glm::vec3(0.25f));
        CHECK(scene.materials[0].specular == glm::vec3(0.5f));
        write_bytes(dir.file("g.mtl"), "newmtl grey\nKd 0.25 0.5\n");
        CHECK(contains(error_message([&] { load_model_file(dir.file("g.obj")); }),
                       "g.mtl:2: 'Kd' needs 1 or 3 numbers, got 2"));
    }
    SUBCASE("a malformed number is read from its valid start, with a warning (strict: an error)") {
        write_bytes(dir.file("n.obj"), "v 0 0 0\nv 1 0 0\nv 0 3.1+e2 0\nf 1 2 3\n");
        const Scene scene = load_model_file(dir.file("n.obj"));
        CHECK(scene.positions[2] == glm::vec3(0.0f, 3.1f, 0.0f));
        CHECK(contains(warning_with(scene, "malformed number"),
                       "n.obj:3: v: malformed number '3.1+e2' read as 3.1 (its valid start)"));
        CHECK(contains(error_message([&] { load_model_file(dir.file("n.obj"), strict_options()); }),
                       "n.obj:3: v: malformed number '3.1+e2'"));
        // Nothing valid at the start, or NaN: an error either way.
        write_bytes(dir.file("n.obj"), "v 0 0 0\nv 1 0 0\nv 0 x1 0\nf 1 2 3\n");
        CHECK(contains(error_message([&] { load_model_file(dir.file("n.obj")); }),
                       "n.obj:3: v: malformed number 'x1'"));
        write_bytes(dir.file("n.obj"), "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n");
        CHECK(contains(error_message([&] { load_model_file(dir.file("n.obj")); }),
                       "NaN or infinite"));
    }
    SUBCASE("a material name that is not UTF-8 is read as Latin-1") {
        write_bytes(dir.file("l.mtl"), "newmtl K\xF6rper\nKd 1 0 0\n");
        write_bytes(dir.file("l.obj"),
                    "mtllib l.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl K\xF6rper\nf 1 2 3\n");
        const Scene scene = load_model_file(dir.file("l.obj"));
        CHECK(scene.materials[0].name == "K\xC3\xB6rper");
        CHECK(scene.materials[0].albedo == glm::vec3(1, 0, 0));
        CHECK(contains(warning_with(scene, "Latin-1"), "l.mtl:1: material name"));
    }
    SUBCASE("a face of 300 corners (more than tinyobjloader's unsigned char counts)") {
        std::string obj;
        const int n = 300;
        // A convex polygon: the fan, n - 2 triangles, every one counter-clockwise.
        for (int k = 0; k < n; ++k) {
            const float t = static_cast<float>(k) / n;
            obj += "v " + std::to_string(t) + " " + std::to_string(t * t) + " 0\n";
        }
        obj += "f";
        for (int k = n; k >= 1; --k) obj += " " + std::to_string(k);
        obj += "\n";
        write_bytes(dir.file("long.obj"), obj);
        const Scene scene = load_model_file(dir.file("long.obj"));
        CHECK(scene.triangle_count() == n - 2);
        CHECK(scene.load_stats.zero_area_triangles_dropped == 0);
        CHECK(scene.load_stats.polygons_triangulated == 1);
        CHECK(scene.load_stats.concave_polygons == 0);  // convex: the fan
        // The fan of the file's order, every triangle wound the same way.
        const double first = signed_area_z(scene, 0);
        for (std::size_t t = 0; t < scene.triangle_count(); ++t)
            CHECK(signed_area_z(scene, t) * first > 0.0);
    }
}

namespace {

// A glTF file of one triangle (0,0,0) (1,0,0) (0,1,0) in a node translated by `offset`, with an
// emissive material when `emissive`.
std::string triangle_gltf(float offset_x, bool emissive) {
    const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::string bytes(reinterpret_cast<const char*>(positions), sizeof positions);
    return std::string(R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
 "nodes": [{"mesh": 0, "translation": [)") +
           std::to_string(offset_x) + R"(, 0, 0]}],
 "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
 "materials": [{"name": "lamp", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0},
   "emissiveFactor": [)" +
           (emissive ? "1, 1, 1" : "0, 0, 0") + R"(]}],
 "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,)" +
           base64(bytes) + R"("}],
 "bufferViews": [{"buffer": 0, "byteLength": 36}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
   "min": [0, 0, 0], "max": [1, 1, 0]}]})";
}

}  // namespace

TEST_CASE("model files: a scene file names glTF meshes as it names OBJ meshes, a bare .gltf") {
    TempDir dir("model-gltf");
    write_bytes(dir.file("tri.gltf"), triangle_gltf(2.0f, false));
    write_bytes(dir.file("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    write_bytes(dir.file("scene.json"), R"({"version": 1,
  "meshes": [{"obj": "tri.obj"}, {"gltf": "tri.gltf", "transform": {"translate": [0, 0, 5]}}],
  "camera": {"position": [0, 0, 9], "look_at": [0, 0, 0], "vfov_deg": 45}})");
    const Scene scene = load_scene(dir.file("scene.json"));
    REQUIRE(scene.triangle_count() == 2);
    CHECK(scene.positions[3] == glm::vec3(2, 0, 5));  // the node's, then the instance's transform
    CHECK(scene.positions[4] == glm::vec3(3, 0, 5));
    CHECK(scene.materials[static_cast<std::size_t>(material_of(scene, 1))].albedo ==
          glm::vec3(0.5f));
    CHECK(scene.camera.position == glm::vec3(0, 0, 9));  // the scene file's camera
    // Both keys, or neither, is an error naming the line.
    write_bytes(dir.file("both.json"), R"({"version": 1,
  "meshes": [{"obj": "tri.obj", "gltf": "tri.gltf"}],
  "camera": {"position": [0, 0, 9], "look_at": [0, 0, 0], "vfov_deg": 45}})");
    CHECK(contains(error_message([&] { load_scene(dir.file("both.json")); }),
                   "both.json:2: /meshes/0: give exactly one of \"obj\", \"gltf\""));

    // A bare glTF file: its emissive triangle is the light, so no default light.
    write_bytes(dir.file("lamp.gltf"), triangle_gltf(0.0f, true));
    const Scene lamp = load_scene(dir.file("lamp.gltf"));
    REQUIRE(lamp.lights.size() == 1);
    CHECK(lamp.lights[0].type == Light::Type::triangle);
    REQUIRE(lamp.load_stats.defaulted.size() == 1);
    CHECK(contains(lamp.load_stats.defaulted[0], "camera: at"));
}

TEST_CASE("model files: what cannot be framed or named is an error or repaired, never a crash") {
    TempDir dir("model-edges");
    // Far from the origin for its size: the default camera 2r away is the centre in binary32.
    write_bytes(dir.file("far.obj"), "v 0 0 1e8\nv 1 0 1e8\nv 0 1 1e8\nf 1 2 3\n");
    CHECK(contains(error_message([&] { load_model_file(dir.file("far.obj")); }),
                   "far.obj: cannot place the default camera (give --camera): "));
    // ... which --camera solves.
    write_bytes(dir.file("camera.json"),
                R"({"position": [0, 0, 100000010], "look_at": [0, 0, 1e8], "vfov_deg": 40})");
    SceneLoadOptions options;
    options.camera_file = dir.file("camera.json");
    CHECK(load_model_file(dir.file("far.obj"), options).triangle_count() == 1);
    // A file name that is not UTF-8 gives a UTF-8 scene name (read as Latin-1).
    write_bytes(dir.file("K\xF6rper.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    CHECK(load_model_file(dir.file("K\xF6rper.obj")).name == "K\xC3\xB6rper");
    // A NUL byte after lone-CR lines is named on its line as the statements count lines.
    write_bytes(dir.file("cr-nul.obj"), std::string("v 0 0 0\rv 1 0 0\r\0", 17));
    CHECK(contains(error_message([&] { load_model_file(dir.file("cr-nul.obj")); }),
                   "cr-nul.obj:3: NUL byte"));
}

TEST_CASE("triangulate_polygon: the ear-clipping budget is spent per point test, then a fan") {
    const std::vector<glm::vec3> dart = {{0, 0, 0}, {2, 1, 0}, {4, 0, 0}, {2, 3, 0}};
    PolygonSplit split = PolygonSplit::triangle;
    std::int64_t budget = 100;
    CHECK(triangulate_polygon(dart, &split, &budget).size() == 2);
    CHECK(split == PolygonSplit::ear_clipped);
    CHECK(budget == 96);  // one candidate ear, tested against the 4 corners
    budget = 3;
    const auto fanned = triangulate_polygon(dart, &split, &budget);
    CHECK(split == PolygonSplit::not_simple);
    REQUIRE(fanned.size() == 2);
    CHECK(fanned[0] == std::array<int, 3>{0, 1, 2});
}
