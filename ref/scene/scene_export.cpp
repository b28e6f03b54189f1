// Scene export (SPEC §2): writes a Scene as OBJ + MTL + PFM textures + scene.json, so that other
// tools (a GPU renderer under test) load exactly the triangles fovref renders, and
// load_scene_file gives back the same scene bit for bit.
//
// Exactness: every float is written with "%.9g". Nine significant digits identify a binary32
// value uniquely, and the decimal lies within 5e-9 (relative) of it while the nearest rounding
// boundary is at least 3e-8 away, so a correctly rounded parser (the loader's std::from_chars for
// OBJ and MTL numbers) reads it back exactly, and so does any parser accurate to binary64 before
// rounding to binary32 (nlohmann's strtod for scene.json). Textures are linear floats and go to
// PFM, which is lossless (an 8-bit PNG would quantise and need an sRGB round trip). Each file is
// written with write_file_atomic (temporary file + rename).
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "ref/core/error.h"
#include "ref/image/image_io.h"
#include "ref/scene/scene_file.h"

namespace fovref {

namespace {

using nlohmann::json;

std::string format_float(float value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.9g", static_cast<double>(value));
    return buffer;
}

// A JSON number that nlohmann prints as (at most) the 9-digit decimal of `value`: the double
// nearest that decimal, whose shortest representation nlohmann's dump writes.
json json_float(float value) { return std::strtod(format_float(value).c_str(), nullptr); }
json json_vec3(glm::vec3 v) {
    return json::array({json_float(v.x), json_float(v.y), json_float(v.z)});
}

// Names for MTL and file names: blanks, '#' and control characters become '_'; empty names get
// `fallback`; a repeated name gets "_<index>" appended.
std::string sanitize(const std::string& name, const std::string& fallback) {
    std::string result;
    for (char c : name) {
        const unsigned char u = static_cast<unsigned char>(c);
        result +=
            (std::isspace(u) || std::iscntrl(u) || c == '#' || c == '/' || c == '\\') ? '_' : c;
    }
    return result.empty() ? fallback : result;
}

std::string unique(const std::string& name, std::set<std::string>& used, std::size_t index) {
    std::string result = name;
    while (used.count(result) != 0) result = name + "_" + std::to_string(index++);
    used.insert(result);
    return result;
}

// nlohmann's dump(2) puts every array element on its own line; put arrays of numbers (vectors,
// quaternions, matrix rows) on one line, as a person would write them.
std::string compact_number_arrays(const std::string& text) {
    std::string result;
    std::size_t pos = 0;
    while (pos < text.size()) {
        const char c = text[pos];
        if (c == '"') {  // copy a string literal verbatim
            std::size_t end = pos + 1;
            while (end < text.size() && text[end] != '"') end += text[end] == '\\' ? 2 : 1;
            end = std::min(end + 1, text.size());
            result.append(text, pos, end - pos);
            pos = end;
            continue;
        }
        const std::size_t close =
            c == '[' ? text.find_first_of("[]{\"", pos + 1) : std::string::npos;
        bool numbers_only = close != std::string::npos && text[close] == ']';
        for (std::size_t i = pos + 1; numbers_only && i < close; ++i)
            numbers_only =
                std::string_view("0123456789+-.eE, \n").find(text[i]) != std::string_view::npos;
        if (!numbers_only) {
            result += c;
            ++pos;
            continue;
        }
        // Re-join the elements with ", ".
        result += '[';
        std::string element;
        bool first = true;
        for (std::size_t i = pos + 1; i <= close; ++i) {
            if (text[i] == ',' || text[i] == ']') {
                if (!element.empty()) result += (first ? "" : ", ") + element;
                first = false;
                element.clear();
            } else if (text[i] != ' ' && text[i] != '\n') {
                element += text[i];
            }
        }
        result += ']';
        pos = close + 1;
    }
    return result;
}

// The materials' names in the exported MTL, by material index: unique and without blanks (MTL
// names are single tokens).
std::vector<std::string> export_material_names(const Scene& scene) {
    std::vector<std::string> material_names;
    std::set<std::string> used_names;
    for (std::size_t m = 0; m < scene.materials.size(); ++m)
        material_names.push_back(unique(
            sanitize(scene.materials[m].name, "material_" + std::to_string(m)), used_names, m));
    return material_names;
}

// Writes the textures the materials use, in order of first use, as <root>/textures/<stem>.pfm;
// returns each texture's file name relative to root ("" for a texture no material uses).
std::vector<std::string> export_textures(const Scene& scene, const std::string& directory,
                                         const std::filesystem::path& root) {
    namespace fs = std::filesystem;
    std::error_code ec;
    std::vector<std::string> texture_files(scene.textures.size());
    std::set<std::string> used_files;
    for (const Material& material : scene.materials) {
        const int t = material.texture;
        if (t < 0 || !texture_files[static_cast<std::size_t>(t)].empty()) continue;
        if (static_cast<std::size_t>(t) >= scene.textures.size())
            throw Error(directory + ": material '" + material.name + "' has texture index " +
                        std::to_string(t) + " out of range");
        const Texture& texture = scene.textures[static_cast<std::size_t>(t)];
        const std::string stem =
            sanitize(fs::path(texture.name).stem().string(), "texture_" + std::to_string(t));
        const std::string file =
            "textures/" + unique(stem, used_files, static_cast<std::size_t>(t)) + ".pfm";
        fs::create_directories(root / "textures", ec);
        write_pfm((root / file).string(), texture.image);
        texture_files[static_cast<std::size_t>(t)] = file;
    }
    return texture_files;
}

// The MTL text: every material, in index order, with every value written (so the loader's
// defaults never apply).
std::string mtl_text(const Scene& scene, const std::vector<std::string>& material_names,
                     const std::vector<std::string>& texture_files) {
    std::string mtl =
        "# fovref export_scene: " + std::to_string(scene.materials.size()) + " materials\n";
    for (std::size_t m = 0; m < scene.materials.size(); ++m) {
        const Material& material = scene.materials[m];
        auto triple = [](glm::vec3 v) {
            return format_float(v.x) + " " + format_float(v.y) + " " + format_float(v.z) + "\n";
        };
        mtl += "\nnewmtl " + material_names[m] + "\n";
        mtl += "Kd " + triple(material.albedo);
        mtl += "Ks " + triple(material.specular);
        mtl += "Ke " + triple(material.emission);
        mtl += "Pr " + format_float(material.roughness) + "\n";
        if (material.texture >= 0)
            mtl += "map_Kd " + texture_files[static_cast<std::size_t>(material.texture)] + "\n";
    }
    return mtl;
}

// The OBJ text: one v, vt, vn per triangle corner (corner k of triangle t is element 3t + k + 1),
// faces in triangle order, usemtl where the material changes. Built in memory to be written in
// one piece (temporary file + rename); for the 1M-triangle scene this is ~0.3 GB, about what
// loading it back reads into memory too.
std::string obj_text(const Scene& scene, const std::vector<std::string>& material_names,
                     const std::string& directory) {
    std::string obj = "# fovref export_scene: " + std::to_string(scene.triangle_count()) +
                      " triangles, one v/vt/vn per corner\nmtllib scene.mtl\n";
    obj.reserve(scene.positions.size() * 100);
    for (const glm::vec3& p : scene.positions)
        obj += "v " + format_float(p.x) + " " + format_float(p.y) + " " + format_float(p.z) + "\n";
    for (const glm::vec2& uv : scene.uvs)
        obj += "vt " + format_float(uv.x) + " " + format_float(uv.y) + "\n";
    for (const glm::vec3& n : scene.normals)
        obj += "vn " + format_float(n.x) + " " + format_float(n.y) + " " + format_float(n.z) + "\n";
    int current_material = -1;
    for (std::size_t t = 0; t < scene.triangle_count(); ++t) {
        const int material = scene.material_ids[t];
        if (material < 0 || static_cast<std::size_t>(material) >= scene.materials.size())
            throw Error(directory + ": triangle " + std::to_string(t) + " has material " +
                        std::to_string(material) + " out of range");
        if (material != current_material) {
            obj += "usemtl " + material_names[static_cast<std::size_t>(material)] + "\n";
            current_material = material;
        }
        obj += "f";
        for (std::size_t k = 0; k < 3; ++k) {
            const std::string index = std::to_string(3 * t + k + 1);
            obj += " " + index + "/" + index + "/" + index;
        }
        obj += "\n";
    }
    return obj;
}

// scene.json's "camera_path": each key's time, position and orientation as a quaternion.
json camera_path_json(const std::vector<CameraKey>& camera_path) {
    json path = json::array();
    for (const CameraKey& key : camera_path) {
        const glm::quat& q = key.orientation;
        path.push_back({{"time", json_float(key.time)},
                        {"position", json_vec3(key.position)},
                        {"quaternion", json::array({json_float(q.x), json_float(q.y),
                                                    json_float(q.z), json_float(q.w)})}});
    }
    return path;
}

// scene.json's "lights": the explicit point and quad lights.
json lights_json(const std::vector<Light>& scene_lights) {
    json lights = json::array();
    for (const Light& light : scene_lights) {
        if (light.type == Light::Type::point) {
            lights.push_back({{"type", "point"},
                              {"position", json_vec3(light.position)},
                              {"intensity", json_vec3(light.intensity)}});
        } else if (light.type == Light::Type::quad) {
            lights.push_back({{"type", "quad"},
                              {"corner", json_vec3(light.position)},
                              {"edge_u", json_vec3(light.edge_u)},
                              {"edge_v", json_vec3(light.edge_v)},
                              {"radiance", json_vec3(light.intensity)}});
        }
    }
    return lights;
}

// scene.json: camera as its exact basis, the path as quaternions, explicit lights only
// (finalize_scene re-derives the emissive-triangle lights from the materials).
json scene_json(const Scene& scene) {
    json document;
    document["version"] = 1;
    document["name"] = scene.name;
    document["meshes"] = json::array({json{{"obj", "scene.obj"}}});
    document["camera"] = {{"position", json_vec3(scene.camera.position)},
                          {"basis",
                           {{"right", json_vec3(scene.camera.right)},
                            {"up", json_vec3(scene.camera.up)},
                            {"forward", json_vec3(scene.camera.forward)}}},
                          {"vfov_deg", json_float(scene.camera.vfov_deg)}};
    if (!scene.camera_path.empty()) document["camera_path"] = camera_path_json(scene.camera_path);
    document["lights"] = lights_json(scene.lights);
    switch (scene.display.kind) {
        case DisplayModel::Kind::field_of_view: document["display"] = {{"model", "fov"}}; break;
        case DisplayModel::Kind::diagonal:
            document["display"] = {
                {"model", "diagonal"},
                {"max_view_angle_deg", json_float(scene.display.max_view_angle_deg)}};
            break;
        case DisplayModel::Kind::fixed:
            document["display"] = {{"distance_px", json_float(scene.display.distance_px)}};
            break;
    }
    if (!scene.presets.empty()) {
        json presets = json::object();
        for (const auto& [name, text] : scene.presets) presets[name] = json::parse(text);
        document["presets"] = presets;
    }
    return document;
}

}  // namespace

void export_scene(const Scene& scene, const std::string& directory) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::create_directories(directory, ec);
    if (ec) throw Error(directory + ": cannot create directory: " + ec.message());
    const fs::path root(directory);

    const std::vector<std::string> material_names = export_material_names(scene);
    const std::vector<std::string> texture_files = export_textures(scene, directory, root);
    write_file_atomic((root / "scene.mtl").string(),
                      mtl_text(scene, material_names, texture_files));
    write_file_atomic((root / "scene.obj").string(), obj_text(scene, material_names, directory));
    write_file_atomic((root / "scene.json").string(),
                      compact_number_arrays(scene_json(scene).dump(
                          2, ' ', false, nlohmann::json::error_handler_t::replace)) +
                          "\n");
}

}  // namespace fovref
