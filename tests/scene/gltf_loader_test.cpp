// glTF 2.0 scenes (docs/gltf.md): hand-built .gltf (data: URIs, external .bin) and .glb files
// checked for node transforms, index types, strips and fans, normals, uv, winding, materials,
// textures, camera, lights, what is listed as unsupported, and every kind of invalid input.
#include <doctest/doctest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "ref/core/error.h"
#include "ref/image/image_io.h"
#include "ref/scene/gltf_loader.h"
#include "ref/scene/scene_file.h"
#include "tests/scene/scene_test_util.h"

using namespace fovref;
using fovref::test::base64;
using fovref::test::contains;
using fovref::test::error_of;
using fovref::test::TempDir;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

template <class T>
std::string raw_bytes(const std::vector<T>& values) {
    return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

constexpr int u8 = 5121, u16 = 5123, u32 = 5125, f32 = 5126;

// A glTF document with one buffer (buffer 0) that the helpers append to.
struct Gltf {
    std::string bin;
    json doc;
    Gltf() {
        doc["asset"] = {{"version", "2.0"}};
        for (const char* key : {"bufferViews", "accessors", "meshes", "nodes"})
            doc[key] = json::array();
    }
    int view(const std::string& bytes, int stride = 0) {
        while (bin.size() % 4 != 0) bin += '\0';
        json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes.size()}};
        if (stride > 0) v["byteStride"] = stride;
        bin += bytes;
        doc["bufferViews"].push_back(v);
        return static_cast<int>(doc["bufferViews"].size()) - 1;
    }
    int accessor(const std::string& bytes, int component_type, const char* type, std::size_t count,
                 bool normalized = false) {
        json a = {{"bufferView", view(bytes)},
                  {"componentType", component_type},
                  {"type", type},
                  {"count", count}};
        if (normalized) a["normalized"] = true;
        doc["accessors"].push_back(a);
        return static_cast<int>(doc["accessors"].size()) - 1;
    }
    int vec3(const std::vector<float>& v) {
        return accessor(raw_bytes(v), f32, "VEC3", v.size() / 3);
    }
    int vec2(const std::vector<float>& v) {
        return accessor(raw_bytes(v), f32, "VEC2", v.size() / 2);
    }
    int mesh(const json& primitive) {
        doc["meshes"].push_back({{"primitives", json::array({primitive})}});
        return static_cast<int>(doc["meshes"].size()) - 1;
    }
    int node(const json& n) {
        doc["nodes"].push_back(n);
        return static_cast<int>(doc["nodes"].size()) - 1;
    }
    void buffer_uri(const std::string& uri) {
        doc["buffers"] = json::array({{{"byteLength", bin.size()}, {"uri", uri}}});
    }
    // .gltf with the buffer as a data: URI.
    std::string text() {
        if (bin.empty()) return doc.dump(1);
        buffer_uri("data:application/octet-stream;base64," + base64(bin));
        return doc.dump(1);
    }
    // .glb: header, JSON chunk, BIN chunk.
    std::string glb() {
        doc["buffers"] = json::array({{{"byteLength", bin.size()}}});
        std::string json_text = doc.dump();
        while (json_text.size() % 4 != 0) json_text += ' ';
        std::string bin_chunk = bin;
        while (bin_chunk.size() % 4 != 0) bin_chunk += '\0';
        const auto u32le = [](std::uint32_t v) {
            return std::string(reinterpret_cast<char*>(&v), 4);
        };
        const std::uint32_t length =
            static_cast<std::uint32_t>(12 + 8 + json_text.size() + 8 + bin_chunk.size());
        return "glTF" + u32le(2) + u32le(length) +
               u32le(static_cast<std::uint32_t>(json_text.size())) + u32le(0x4E4F534Au) +
               json_text + u32le(static_cast<std::uint32_t>(bin_chunk.size())) +
               u32le(0x004E4942u) + bin_chunk;
    }
};

const std::vector<float> triangle = {0, 0, 0, 1, 0, 0, 0, 1, 0};

struct Loaded {
    Scene scene;
    GltfContents contents;
};

Loaded load(const std::string& path, const glm::mat4& transform = glm::mat4(1.0f)) {
    Loaded loaded;
    TextureCache cache;
    loaded.contents = load_gltf_into(loaded.scene, path, transform, cache, "");
    return loaded;
}

bool has_line(const std::vector<std::string>& lines, const std::string& part) {
    for (const std::string& line : lines)
        if (contains(line, part)) return true;
    return false;
}

}  // namespace

TEST_CASE("gltf: node TRS, matrix and parent chain place a triangle exactly") {
    TempDir dir("nodes");
    Gltf g;
    const int mesh = g.mesh({{"attributes", {{"POSITION", g.vec3(triangle)}}}});
    g.node({{"translation", {1, 2, 3}}, {"children", {1}}});                                  // 0
    g.node({{"scale", {2, 2, 2}}, {"rotation", {0, 0, 0, 1}}, {"mesh", mesh}});               // 1
    g.node({{"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 10, 0, 0, 1}}, {"mesh", mesh}});  // 2
    g.doc["scenes"] = json::array({{{"nodes", {0, 2}}}});
    g.doc["scene"] = 0;
    const std::string path = dir.write("nodes.gltf", g.text());
    const Loaded loaded = load(path, glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, 5)));
    const Scene& s = loaded.scene;
    REQUIRE(s.triangle_count() == 2);
    // Node order: node 0 -> its child 1 -> node 2.
    CHECK(s.positions[0] == glm::vec3(1, 2, 8));
    CHECK(s.positions[1] == glm::vec3(3, 2, 8));
    CHECK(s.positions[2] == glm::vec3(1, 4, 8));
    CHECK(s.positions[3] == glm::vec3(10, 0, 5));
    CHECK(s.positions[4] == glm::vec3(11, 0, 5));
    CHECK(s.positions[5] == glm::vec3(10, 1, 5));
    // No NORMAL: geometric normals, counted.
    CHECK(s.load_stats.normals_generated == 2);
    for (const glm::vec3& n : s.normals) CHECK(n == glm::vec3(0, 0, 1));
    for (const glm::vec2& uv : s.uvs) CHECK(uv == glm::vec2(0, 0));
    // No material: the glTF default (base 1, metallic 1, roughness 1).
    REQUIRE(s.materials.size() == 1);
    CHECK(s.materials[0].name == "gltf-default");
    CHECK(s.materials[0].albedo == glm::vec3(0.0f));
    CHECK(s.materials[0].specular == glm::vec3(1.0f));
    CHECK(s.materials[0].roughness == 1.0f);
    CHECK(s.material_ids == std::vector<std::int32_t>{0, 0});
    CHECK(!loaded.contents.camera);
    CHECK(loaded.contents.point_lights == 0);
}

TEST_CASE("gltf: a quaternion rotation of 90 degrees about z") {
    TempDir dir("quat");
    Gltf g;
    const float h = 0.70710678f;
    g.node({{"rotation", {0, 0, h, h}},
            {"mesh", g.mesh({{"attributes", {{"POSITION", g.vec3(triangle)}}}})}});
    const Loaded loaded = load(dir.write("q.gltf", g.text()));  // no scenes: every root node
    REQUIRE(loaded.scene.triangle_count() == 1);
    const glm::vec3 p1 = loaded.scene.positions[1];  // (1,0,0) -> (0,1,0)
    CHECK(p1.x == doctest::Approx(0.0).epsilon(1e-6));
    CHECK(p1.y == doctest::Approx(1.0).epsilon(1e-6));
    CHECK(std::fabs(p1.x) < 1e-6f);
}

TEST_CASE("gltf: unsigned byte, short and int indices give the same quad") {
    TempDir dir("indices");
    const std::vector<float> quad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    std::vector<std::vector<glm::vec3>> results;
    for (int type : {u8, u16, u32}) {
        Gltf g;
        const int positions = g.vec3(quad);
        int indices = -1;
        if (type == u8)
            indices =
                g.accessor(raw_bytes(std::vector<std::uint8_t>{0, 1, 2, 0, 2, 3}), u8, "SCALAR", 6);
        if (type == u16)
            indices = g.accessor(raw_bytes(std::vector<std::uint16_t>{0, 1, 2, 0, 2, 3}), u16,
                                 "SCALAR", 6);
        if (type == u32)
            indices = g.accessor(raw_bytes(std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}), u32,
                                 "SCALAR", 6);
        g.node(
            {{"mesh", g.mesh({{"attributes", {{"POSITION", positions}}}, {"indices", indices}})}});
        const Loaded loaded = load(dir.write("i" + std::to_string(type) + ".gltf", g.text()));
        results.push_back(loaded.scene.positions);
    }
    const std::vector<glm::vec3> expected = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0},
                                             {0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    for (const auto& r : results) CHECK(r == expected);
}

TEST_CASE("gltf: triangle strips and fans follow the glTF corner order") {
    TempDir dir("strip");
    const std::vector<float> five = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0};
    const auto load_mode = [&](int mode) {
        Gltf g;
        g.node({{"mesh", g.mesh({{"attributes", {{"POSITION", g.vec3(five)}}}, {"mode", mode}})}});
        return load(dir.write("m" + std::to_string(mode) + ".gltf", g.text())).scene;
    };
    const auto v = [&](int i) { return glm::vec3(five[3 * i], five[3 * i + 1], five[3 * i + 2]); };
    const Scene strip = load_mode(5);
    // Triangle t: (v_t, v_{t+1+t%2}, v_{t+2-t%2}).
    REQUIRE(strip.triangle_count() == 3);
    const int strip_corners[9] = {0, 1, 2, 1, 3, 2, 2, 3, 4};
    for (int k = 0; k < 9; ++k) CHECK(strip.positions[k] == v(strip_corners[k]));
    const Scene fan = load_mode(6);
    // Triangle t: (v_{t+1}, v_{t+2}, v_0); (v3, v4, v0) is zero-area? No: (1,1),(0,2),(0,0).
    REQUIRE(fan.triangle_count() == 3);
    const int fan_corners[9] = {1, 2, 0, 2, 3, 0, 3, 4, 0};
    for (int k = 0; k < 9; ++k) CHECK(fan.positions[k] == v(fan_corners[k]));
    // Every strip triangle faces +z (the strip's alternation keeps the winding).
    for (const glm::vec3& n : strip.normals) CHECK(n.z > 0.0f);
    // Lines and points: ignored, with a warning.
    const Scene lines = load_mode(1);
    CHECK(lines.triangle_count() == 0);
    CHECK(has_line(lines.load_stats.warnings, "mode 1 (LINES) ignored"));
}

TEST_CASE("gltf: normals are transformed and normalised, uv flipped, mirrors keep the winding") {
    TempDir dir("attributes");
    Gltf g;
    const int positions = g.vec3(triangle);
    const int normals = g.vec3({0, 0, 2, 0, 0, 1, 0, 0, 1});
    const int uvs = g.vec2({0.25f, 0.75f, 1, 0, 0, 1});
    const int uv8 = g.accessor(raw_bytes(std::vector<std::uint8_t>{0, 255, 255, 0, 0, 51}), u8,
                               "VEC2", 3, true);
    g.node({{"mesh",
             g.mesh({{"attributes",
                      {{"POSITION", positions}, {"NORMAL", normals}, {"TEXCOORD_0", uvs}}}})}});
    g.node({{"scale", {-1, 1, 1}},
            {"mesh",
             g.mesh({{"attributes",
                      {{"POSITION", positions}, {"NORMAL", normals}, {"TEXCOORD_0", uv8}}}})}});
    const Loaded loaded = load(dir.write("attr.gltf", g.text()));
    const Scene& s = loaded.scene;
    REQUIRE(s.triangle_count() == 2);
    CHECK(s.load_stats.normals_generated == 0);
    CHECK(s.normals[0] == glm::vec3(0, 0, 1));   // (0,0,2) normalised
    CHECK(s.uvs[0] == glm::vec2(0.25f, 0.25f));  // v' = 1 - v
    CHECK(s.uvs[1] == glm::vec2(1, 1));
    CHECK(s.uvs[2] == glm::vec2(0, 0));
    // Mirrored (det < 0): corners 1 and 2 swapped, so the geometric normal still agrees with the
    // (inverse-transpose transformed) vertex normal.
    CHECK(s.positions[3] == glm::vec3(0, 0, 0));
    CHECK(s.positions[4] == glm::vec3(0, 1, 0));
    CHECK(s.positions[5] == glm::vec3(-1, 0, 0));
    const glm::vec3 geometric =
        glm::cross(s.positions[4] - s.positions[3], s.positions[5] - s.positions[3]);
    CHECK(glm::dot(geometric, s.normals[3]) > 0.0f);
    CHECK(s.uvs[3] == glm::vec2(0, 0));                      // (0, 255/255) -> (0, 0)
    CHECK(s.uvs[4] == glm::vec2(0, 1.0f - 51.0f / 255.0f));  // corner 2 of the source
    CHECK(s.uvs[5] == glm::vec2(1, 1));
}

TEST_CASE("gltf: metallic-roughness materials, names, emission and triangle lights") {
    TempDir dir("materials");
    Gltf g;
    const int positions = g.vec3(triangle);
    g.doc["materials"] = json::array(
        {{{"name", "Mat"},
          {"pbrMetallicRoughness",
           {{"baseColorFactor", {0.5, 0.25, 1, 1}},
            {"metallicFactor", 0.5},
            {"roughnessFactor", 0.3}}}},
         {{"name", "Mat"}},
         {{"emissiveFactor", {0.5, 0.25, 0}},
          {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}}}}},
         {{"name", "Unique"}}});
    g.doc["extensionsUsed"] = {"KHR_materials_emissive_strength"};
    for (int m : {0, 1, 2})
        g.node({{"mesh", g.mesh({{"attributes", {{"POSITION", positions}}}, {"material", m}})}});
    Loaded loaded = load(dir.write("mat.gltf", g.text()));
    Scene& s = loaded.scene;
    REQUIRE(s.materials.size() == 4);
    CHECK(s.materials[0].name == "Mat#0");
    CHECK(s.materials[1].name == "Mat#1");
    CHECK(s.materials[2].name == "material#2");
    CHECK(s.materials[3].name == "Unique");
    const glm::vec3 base(0.5f, 0.25f, 1.0f);
    const float metallic = 0.5f;
    CHECK(s.materials[0].albedo == base * (1.0f - metallic));
    CHECK(s.materials[0].specular == glm::vec3(0.04f * (1.0f - metallic)) + base * metallic);
    CHECK(s.materials[0].roughness == 0.3f);
    CHECK(s.materials[1].albedo == glm::vec3(0.0f));  // glTF defaults: metallic 1
    CHECK(s.materials[1].specular == glm::vec3(1.0f));
    CHECK(s.materials[2].emission == glm::vec3(2.0f, 1.0f, 0.0f));
    CHECK(s.material_ids == std::vector<std::int32_t>{0, 1, 2});
    CHECK(loaded.contents.unsupported.empty() == false);  // doubleSided false
    finalize_scene(s);
    REQUIRE(s.lights.size() == 1);
    CHECK(s.lights[0].type == Light::Type::triangle);
    CHECK(s.lights[0].primitive == 2);
    CHECK(s.lights[0].intensity == glm::vec3(2.0f, 1.0f, 0.0f));
}

TEST_CASE("gltf: base-colour textures from a data URI, an external file and a glb bufferView") {
    TempDir dir("textures");
    Image image(2, 2, 3);
    for (std::size_t i = 0; i < image.data.size(); ++i)
        image.data[i] = static_cast<float>(i) / 11.0f;
    const std::string png = encode_png(image, "t.png");
    const Image expected = read_png(dir.write("expected.png", png));
    dir.write("my tex.png", png);

    for (int source = 0; source < 3; ++source) {
        Gltf g;
        const int positions = g.vec3(triangle);
        const int uvs = g.vec2({0, 0, 1, 0, 0, 1});
        json image_json;
        if (source == 0) image_json = {{"uri", "data:image/png;base64," + base64(png)}};
        if (source == 1) image_json = {{"uri", "my%20tex.png"}};
        if (source == 2) image_json = {{"bufferView", g.view(png)}, {"mimeType", "image/png"}};
        g.doc["images"] = json::array({image_json});
        g.doc["textures"] = json::array({{{"source", 0}}});
        g.doc["materials"] =
            json::array({{{"name", "tex"},
                          {"pbrMetallicRoughness",
                           {{"baseColorTexture", {{"index", 0}}}, {"metallicFactor", 0}}}}});
        g.node({{"mesh", g.mesh({{"attributes", {{"POSITION", positions}, {"TEXCOORD_0", uvs}}},
                                 {"material", 0}})}});
        const std::string path = source == 2
                                     ? dir.write("t.glb", g.glb())
                                     : dir.write("t" + std::to_string(source) + ".gltf", g.text());
        INFO("source " << source);
        const Loaded loaded = load(path);
        REQUIRE(loaded.scene.textures.size() == 1);
        CHECK(bit_equal(loaded.scene.textures[0].image, expected));
        CHECK(loaded.scene.materials[0].texture == 0);
        CHECK(loaded.scene.materials[0].albedo == glm::vec3(1.0f));
        if (source == 1) CHECK(loaded.scene.textures[0].name == "my tex.png");
        if (source == 2) CHECK(loaded.scene.textures[0].name == "t-image0.png");
    }
}

TEST_CASE("gltf: the first perspective camera and KHR_lights_punctual point lights") {
    TempDir dir("camera");
    Gltf g;
    g.doc["cameras"] =
        json::array({{{"type", "orthographic"},
                      {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}}},
                     {{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}});
    g.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    g.doc["extensions"] = {
        {"KHR_lights_punctual",
         {{"lights", json::array({{{"type", "point"}, {"color", {1, 0.5, 0.25}}, {"intensity", 4}},
                                  {{"type", "spot"}, {"spot", json::object()}}})}}}};
    g.node({{"camera", 0}});
    g.node({{"camera", 1}, {"translation", {1, 2, 3}}});
    g.node({{"camera", 1}, {"translation", {7, 7, 7}}});
    g.node({{"translation", {0, 3, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    g.node({{"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
    Loaded loaded =
        load(dir.write("cam.gltf", g.text()), glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, 1)));
    REQUIRE(loaded.contents.camera);
    const Camera& camera = *loaded.contents.camera;
    CHECK(camera.position == glm::vec3(1, 2, 4));
    CHECK(camera.forward == glm::vec3(0, 0, -1));
    CHECK(camera.up == glm::vec3(0, 1, 0));
    CHECK(camera.right == glm::vec3(1, 0, 0));
    CHECK(camera.vfov_deg == 0.5f * 57.2957795130823208768f);
    CHECK(loaded.scene.camera == Camera{});  // not written
    CHECK(loaded.contents.point_lights == 1);
    REQUIRE(loaded.scene.lights.size() == 1);
    CHECK(loaded.scene.lights[0].type == Light::Type::point);
    CHECK(loaded.scene.lights[0].position == glm::vec3(0, 3, 1));
    CHECK(loaded.scene.lights[0].intensity == glm::vec3(4, 2, 1));
    const auto& unsupported = loaded.contents.unsupported;
    CHECK(has_line(unsupported, "spot light (skipped"));
    CHECK(has_line(unsupported, "camera type 'orthographic'"));
    CHECK(has_line(unsupported, "further cameras"));
}

TEST_CASE("gltf: unsupported features are listed, sorted, unknown required extensions fail") {
    TempDir dir("unsupported");
    Gltf g;
    const int positions = g.vec3(triangle);
    const int colours = g.vec3({1, 0, 0, 0, 1, 0, 0, 0, 1});
    g.doc["extensionsUsed"] = {"KHR_materials_clearcoat", "KHR_texture_transform"};
    g.doc["materials"] =
        json::array({{{"normalTexture", {{"index", 0}}},
                      {"alphaMode", "BLEND"},
                      {"doubleSided", true},
                      {"extensions", {{"KHR_materials_clearcoat", json::object()}}}}});
    g.node({{"mesh", g.mesh({{"attributes", {{"POSITION", positions}, {"COLOR_0", colours}}},
                             {"material", 0}})}});
    const std::string path = dir.write("u.gltf", g.text());
    const Loaded loaded = load(path);
    const auto& u = loaded.contents.unsupported;
    CHECK(std::is_sorted(u.begin(), u.end()));
    CHECK(has_line(u, path + ": normalTexture (ignored: vertex normals used): materials[0]"));
    CHECK(has_line(u, "alphaMode BLEND (rendered opaque)"));
    CHECK(has_line(u, "attribute COLOR_0 (ignored): meshes[0].primitives[0]"));
    CHECK(has_line(u, "extension KHR_materials_clearcoat (ignored)"));
    CHECK(has_line(u, "extension KHR_texture_transform (ignored)"));
    CHECK(!has_line(u, "doubleSided"));
    CHECK(loaded.scene.triangle_count() == 1);

    g.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    const std::string message = error_of([&] { load(dir.write("r.gltf", g.text())); });
    CHECK(contains(message, "r.gltf"));
    CHECK(contains(message, "KHR_draco_mesh_compression"));
}

TEST_CASE("gltf: external .bin buffers and .glb files load the same triangles") {
    TempDir dir("bin");
    Gltf g;
    g.node({{"mesh", g.mesh({{"attributes", {{"POSITION", g.vec3(triangle)}}}})}});
    const std::string data_uri =
        load(dir.write("a.gltf", g.text())).scene.positions.size() == 3 ? "ok" : "";
    CHECK(data_uri == "ok");
    dir.write("buf.bin", g.bin);
    g.buffer_uri("buf.bin");
    const Scene external = load(dir.write("b.gltf", g.doc.dump())).scene;
    const Scene binary = load(dir.write("c.glb", g.glb())).scene;
    CHECK(external.positions == std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    CHECK(binary.positions == external.positions);
    // A .glb with another extension is still read as binary (by its magic).
    CHECK(load(dir.write("d.gltf", g.glb())).scene.positions == external.positions);
}

TEST_CASE("gltf errors: each names the file and what is wrong") {
    TempDir dir("errors");
    const auto message_for = [&](const std::string& name, const std::string& bytes) {
        const std::string path = dir.write(name, bytes);
        return error_of([&] { load(path); });
    };
    const auto check_error = [&](const std::string& message, const std::string& name,
                                 const std::string& detail) {
        INFO("file: " << name << ", message: " << message);
        CHECK(contains(message, name));
        CHECK(contains(message, detail));
    };
    check_error(error_of([&] { load(dir.file("missing.gltf")); }), "missing.gltf", "not found");
    {
        Scene scene;
        TextureCache cache;
        check_error(error_of([&] {
                        load_gltf_into(scene, dir.file("nothere.glb"), glm::mat4(1.0f), cache,
                                       "scene.json:7");
                    }),
                    "scene.json:7", "not found");
    }
    check_error(message_for("bad.gltf", "{\"asset\": {\"version\": \"2.0\""), "bad.gltf",
                "tinygltf");

    Gltf base;
    const int positions = base.vec3(triangle);
    base.node({{"mesh", base.mesh({{"attributes", {{"POSITION", positions}}}})}});
    {
        Gltf g = base;
        g.buffer_uri("absent.bin");
        check_error(message_for("nobin.gltf", g.doc.dump()), "nobin.gltf", "absent.bin");
    }
    {
        Gltf g = base;
        g.doc["accessors"][0]["count"] = 4;  // 48 bytes from a 36-byte bufferView
        check_error(message_for("range.gltf", g.text()), "range.gltf",
                    "meshes[0].primitives[0]: accessor 0 (POSITION): 4 elements of 12 bytes");
    }
    {
        Gltf g = base;
        g.doc["bufferViews"][0]["byteLength"] = 400;  // beyond the 36-byte buffer
        check_error(message_for("view.gltf", g.text()), "view.gltf", "lie outside buffer 0");
    }
    {
        Gltf g;
        const int p = g.vec3(triangle);
        const int i = g.accessor(raw_bytes(std::vector<std::uint16_t>{0, 1, 3}), u16, "SCALAR", 3);
        g.node({{"mesh", g.mesh({{"attributes", {{"POSITION", p}}}, {"indices", i}})}});
        check_error(message_for("index.gltf", g.text()), "index.gltf",
                    "accessor 1 (indices): index 2 is 3, not below the vertex count 3");
    }
    {
        Gltf g;
        std::vector<float> nan_triangle = triangle;
        nan_triangle[4] = std::nanf("");
        g.node({{"mesh", g.mesh({{"attributes", {{"POSITION", g.vec3(nan_triangle)}}}})}});
        check_error(message_for("nan.gltf", g.text()), "nan.gltf",
                    "accessor 0 (POSITION): element 1 component 1 is NaN or infinite");
    }
    {
        Gltf g = base;
        g.doc["accessors"][0]["componentType"] = u16;
        check_error(message_for("type.gltf", g.text()), "type.gltf",
                    "componentType 5123 (UNSIGNED_SHORT), expected FLOAT");
    }
    {
        Gltf g = base;
        g.doc["accessors"][0]["count"] = 2;  // 2 vertices, not a multiple of 3
        check_error(message_for("count.gltf", g.text()), "count.gltf", "not a multiple of 3");
    }
    {
        Gltf g = base;
        const std::string glb = g.glb();
        for (std::size_t keep : {std::size_t{10}, std::size_t{30}, glb.size() - 4})
            check_error(message_for("cut.glb", glb.substr(0, keep)), "cut.glb", "truncated .glb");
        check_error(message_for("notglb.glb", "{}"), "notglb.glb", "no 'glTF' magic");
    }
    {
        Gltf g = base;
        g.doc["nodes"][0]["children"] = {0};
        check_error(message_for("cycle.gltf", g.text()), "cycle.gltf",
                    "nodes[0]: is part of a cycle");
        g.node({{"children", {0}}});
        check_error(message_for("parents.gltf", g.text()), "parents.gltf",
                    "nodes[0]: is a child of two nodes");
    }
    {
        Gltf g = base;
        g.doc["images"] = json::array({{{"uri", "nowhere.png"}}});
        g.doc["textures"] = json::array({{{"source", 0}}});
        g.doc["materials"] =
            json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
        check_error(message_for("noimage.gltf", g.text()), "noimage.gltf",
                    "images[0]: image file 'nowhere.png' not found");
    }
    {
        Gltf g = base;
        g.doc["accessors"][0]["sparse"] = {{"count", 1},
                                           {"indices", {{"bufferView", 0}, {"componentType", u32}}},
                                           {"values", {{"bufferView", 0}}}};
        check_error(message_for("sparse.gltf", g.text()), "sparse.gltf",
                    "accessor 0 (POSITION): is sparse (sparse accessors are not supported)");
    }
    check_error(message_for("deep.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"extras\": " +
                                             std::string(100, '[') + std::string(100, ']') + "}"),
                "deep.gltf", "JSON nested deeper than 64 levels");
    {
        Gltf g = base;
        g.doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"metallicFactor", 2}}}}});
        check_error(message_for("metal.gltf", g.text()), "metal.gltf",
                    "materials[0]: metallicFactor must be in [0, 1]");
    }
}

TEST_CASE("gltf: export_scene of a glTF scene loads back equal") {
    TempDir dir("export");
    Image image(2, 1, 3);
    image.data = {0.2f, 0.4f, 0.6f, 0.8f, 1.0f, 0.0f};
    const std::string png = encode_png(image, "t.png");
    Gltf g;
    const int positions = g.vec3({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
    const int normals = g.vec3({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
    const int uvs = g.vec2({0, 0, 1, 0, 0, 1, 0.5f, 0.125f});
    const int indices =
        g.accessor(raw_bytes(std::vector<std::uint16_t>{0, 1, 2, 1, 3, 2}), u16, "SCALAR", 6);
    g.doc["images"] = json::array({{{"uri", "data:image/png;base64," + base64(png)}}});
    g.doc["textures"] = json::array({{{"source", 0}}});
    g.doc["materials"] = json::array({{{"name", "textured"},
                                       {"pbrMetallicRoughness",
                                        {{"baseColorTexture", {{"index", 0}}},
                                         {"metallicFactor", 0.25},
                                         {"roughnessFactor", 0.5}}}},
                                      {{"name", "lamp"}, {"emissiveFactor", {1, 1, 0.5}}}});
    g.doc["extensions"] = {{"KHR_lights_punctual",
                            {{"lights", json::array({{{"type", "point"}, {"intensity", 3}}})}}}};
    g.node({{"mesh", g.mesh({{"attributes",
                              {{"POSITION", positions}, {"NORMAL", normals}, {"TEXCOORD_0", uvs}}},
                             {"indices", indices},
                             {"material", 0}})}});
    g.node({{"translation", {0, 0, 2}},
            {"mesh", g.mesh({{"attributes", {{"POSITION", positions}}},
                             {"indices", indices},
                             {"material", 1}})}});
    g.node({{"translation", {0, 5, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    g.node({{"translation", {0, 0, 10}}, {"camera", 0}});
    g.doc["cameras"] =
        json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.75}, {"znear", 0.1}}}}});
    Loaded loaded = load(dir.write("scene.gltf", g.text()));
    Scene& original = loaded.scene;
    REQUIRE(loaded.contents.camera);
    original.camera = *loaded.contents.camera;
    original.name = "gltf";
    finalize_scene(original);
    REQUIRE(original.triangle_count() == 4);
    export_scene(original, dir.file("out"));
    const Scene reloaded = load_scene_file(dir.file("out/scene.json"));
    CHECK(reloaded.positions == original.positions);
    CHECK(reloaded.normals == original.normals);
    CHECK(reloaded.uvs == original.uvs);
    CHECK(reloaded.material_ids == original.material_ids);
    CHECK(reloaded.materials == original.materials);
    REQUIRE(reloaded.textures.size() == original.textures.size());
    CHECK(bit_equal(reloaded.textures[0].image, original.textures[0].image));
    CHECK(reloaded.lights == original.lights);
    CHECK(reloaded.camera == original.camera);
}
