// The exported scene's loader (frame_scene.h): a plain OBJ/MTL/PFM reader, as a renderer has.
#include "tools/clients/vulkan/passes/frame_scene.h"

#include <nlohmann/json.hpp>

#include <array>
#include <charconv>
#include <cmath>
#include <functional>
#include <sstream>
#include <stdexcept>

#include "tools/clients/common/files.h"

namespace fovref_client {
namespace {

using json = nlohmann::json;

std::string directory_of(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? "." : path.substr(0, slash);
}

// One number of an OBJ or MTL statement, correctly rounded to binary32 (std::from_chars).
float number(const std::string& token, const std::string& where) {
    float value = 0.0f;
    const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (error != std::errc() || end != token.data() + token.size() || !std::isfinite(value))
        throw std::runtime_error(where + ": '" + token + "' is not a finite number");
    return value;
}

Vec3 vec3_of(std::istringstream& line, const std::string& where) {
    std::string a, b, c;
    line >> a >> b >> c;
    if (c.empty()) throw std::runtime_error(where + ": expected 3 numbers");
    return {number(a, where), number(b, where), number(c, where)};
}

Vec3 json_vec3(const json& value) {
    return {value.at(0).get<float>(), value.at(1).get<float>(), value.at(2).get<float>()};
}

// A PFM texture in top-row-first order (the file stores the bottom row first); grey becomes RGB.
FrameTexture load_texture(const std::string& path) {
    const PfmImage pfm = read_pfm(path);
    FrameTexture texture{pfm.width, pfm.height, {}};
    texture.rgb.resize(static_cast<std::size_t>(pfm.width) * pfm.height * 3);
    for (int y = 0; y < pfm.height; ++y)
        for (int x = 0; x < pfm.width; ++x)
            for (int c = 0; c < 3; ++c)
                texture.rgb[(static_cast<std::size_t>(y) * pfm.width + x) * 3 + c] =
                    pfm.bottom_up[(static_cast<std::size_t>(pfm.height - 1 - y) * pfm.width + x) *
                                      pfm.channels +
                                  (pfm.channels == 3 ? c : 0)];
    return texture;
}

// Calls statement(keyword, rest of the line, "file:line") for every line of the OBJ or MTL file
// at `path` (a trailing CR dropped; blank lines give an empty keyword).
void for_each_statement(const std::string& path,
                        const std::function<void(const std::string&, std::istringstream&,
                                                 const std::string&)>& statement) {
    std::istringstream text(read_text(path));
    std::string line;
    int number_of_line = 0;
    while (std::getline(text, line)) {
        ++number_of_line;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream in(line);
        std::string keyword;
        in >> keyword;
        statement(keyword, in, path + ":" + std::to_string(number_of_line));
    }
}

// The MTL's materials in file order (material id = their order in the scene).
void load_mtl(const std::string& path, FrameScene& scene) {
    for_each_statement(
        path, [&](const std::string& keyword, std::istringstream& in, const std::string& where) {
            if (keyword == "newmtl") {
                FrameMaterial material;
                in >> material.name;
                scene.materials.push_back(material);
                return;
            }
            if (keyword.empty() || keyword[0] == '#') return;
            if (scene.materials.empty())
                throw std::runtime_error(where + ": statement before newmtl");
            FrameMaterial& material = scene.materials.back();
            if (keyword == "Kd") material.albedo = vec3_of(in, where);
            if (keyword == "Ke") material.emission = vec3_of(in, where);
            if (keyword == "map_Kd") {
                std::string file;
                std::getline(in >> std::ws, file);
                if (file.size() < 4 || file.substr(file.size() - 4) != ".pfm")
                    throw std::runtime_error(where + ": texture '" + file +
                                             "': only PFM textures are read by this client");
                material.texture = static_cast<int>(scene.textures.size());
                scene.textures.push_back(load_texture(directory_of(path) + "/" + file));
            }
        });
}

int material_index(FrameScene& scene, const std::string& name) {
    for (std::size_t k = 0; k < scene.materials.size(); ++k)
        if (scene.materials[k].name == name) return static_cast<int>(k);
    FrameMaterial fallback;  // docs/scene-format.md: undefined materials use "default" (0.8)
    fallback.name = name;
    scene.materials.push_back(fallback);
    return static_cast<int>(scene.materials.size() - 1);
}

// One face corner "v/t/n" (1-based or negative) as indices into the lists read so far.
void corner_of(const std::string& token, std::size_t vs, std::size_t ts, std::size_t ns, int out[3],
               const std::string& where) {
    std::size_t start = 0;
    for (int k = 0; k < 3; ++k) {
        const std::size_t slash = token.find('/', start);
        const std::string part = token.substr(start, slash - start);
        const std::size_t count = k == 0 ? vs : k == 1 ? ts : ns;
        out[k] = -1;
        if (!part.empty()) {
            const long index = std::stol(part);
            out[k] = static_cast<int>(index < 0 ? static_cast<long>(count) + index : index - 1);
            if (out[k] < 0 || static_cast<std::size_t>(out[k]) >= count)
                throw std::runtime_error(where + ": face index " + part + " out of range");
        }
        if (slash == std::string::npos) {
            for (int rest = k + 1; rest < 3; ++rest) out[rest] = -1;
            return;
        }
        start = slash + 1;
    }
}

struct ObjLists {
    std::vector<Vec3> v, vn;
    std::vector<float> vt;  // pairs
};

// Adds triangle (a, b, c) of corner indices (v, t, n) with material `material`.
using Corner = std::array<int, 3>;  // v, t, n indices (-1: none)

void add_triangle(const ObjLists& obj, const Corner* corners[3], int material, FrameScene& scene) {
    Vec3 p[3], n[3];
    for (int k = 0; k < 3; ++k) p[k] = obj.v[static_cast<std::size_t>((*corners[k])[0])];
    const Vec3 g = cross(p[1] - p[0], p[2] - p[0]);
    const float g_length = std::sqrt(dot(g, g));
    if (!(g_length > 0.0f) || !std::isfinite(g_length)) return;  // zero area: dropped
    const Vec3 geometric{g.x / g_length, g.y / g_length, g.z / g_length};
    bool missing_normal = false;
    for (int k = 0; k < 3; ++k) {
        const int ni = (*corners[k])[2];
        if (ni < 0 ||
            dot(obj.vn[static_cast<std::size_t>(ni)], obj.vn[static_cast<std::size_t>(ni)]) == 0.0f)
            missing_normal = true;
    }
    for (int k = 0; k < 3; ++k) {
        n[k] = geometric;
        if (!missing_normal) {
            const Vec3 vn = obj.vn[static_cast<std::size_t>((*corners[k])[2])];
            const float length2 = dot(vn, vn);
            const float length = std::sqrt(length2);
            // Unit normals (within 1e-6 in squared length) are kept exactly as written.
            n[k] = std::fabs(length2 - 1.0f) <= 1e-6f
                       ? vn
                       : Vec3{vn.x / length, vn.y / length, vn.z / length};
        }
        scene.positions.push_back(p[k]);
        scene.normals.push_back(n[k]);
        const int ti = (*corners[k])[1];
        scene.uvs.push_back(ti < 0 ? 0.0f : obj.vt[2 * static_cast<std::size_t>(ti)]);
        scene.uvs.push_back(ti < 0 ? 0.0f : obj.vt[2 * static_cast<std::size_t>(ti) + 1]);
    }
    scene.material_ids.push_back(material);
}

// The OBJ's triangles (polygons as fans, which the exported files never need).
void load_obj(const std::string& path, FrameScene& scene) {
    ObjLists obj;
    int material = -1;
    for_each_statement(
        path, [&](const std::string& keyword, std::istringstream& in, const std::string& where) {
            if (keyword == "v") obj.v.push_back(vec3_of(in, where));
            if (keyword == "vn") obj.vn.push_back(vec3_of(in, where));
            if (keyword == "vt") {
                std::string u, v;
                in >> u >> v;
                obj.vt.push_back(number(u, where));
                obj.vt.push_back(v.empty() ? 0.0f : number(v, where));
            }
            if (keyword == "mtllib") {
                std::string file;
                std::getline(in >> std::ws, file);
                load_mtl(directory_of(path) + "/" + file, scene);
            }
            if (keyword == "usemtl") {
                std::string name;
                in >> name;
                material = material_index(scene, name);
            }
            if (keyword != "f") return;
            std::vector<Corner> corners;
            for (std::string token; in >> token;) {
                Corner c{};
                corner_of(token, obj.v.size(), obj.vt.size() / 2, obj.vn.size(), c.data(), where);
                corners.push_back(c);
            }
            if (corners.size() < 3) throw std::runtime_error(where + ": face with < 3 corners");
            if (material < 0) material = material_index(scene, "default");
            for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
                const Corner* fan[3] = {&corners[0], &corners[k], &corners[k + 1]};
                add_triangle(obj, fan, material, scene);
            }
        });
}

// The explicit lights of scene.json, then one triangle light per emissive triangle.
void add_lights(const json& lights, FrameScene& scene) {
    for (const json& l : lights) {
        FrameLight light;
        const std::string type = l.at("type").get<std::string>();
        if (type == "point") {
            light.position = json_vec3(l.at("position"));
            light.intensity = json_vec3(l.at("intensity"));
        } else if (type == "quad") {
            light.type = FrameLight::quad;
            light.position = json_vec3(l.at("corner"));
            light.edge_u = json_vec3(l.at("edge_u"));
            light.edge_v = json_vec3(l.at("edge_v"));
            light.intensity = json_vec3(l.at("radiance"));
        } else {
            throw std::runtime_error("scene.json: light type '" + type + "' is not supported");
        }
        scene.lights.push_back(light);
    }
    for (std::size_t t = 0; t < scene.triangles(); ++t) {
        const Vec3 e = scene.materials[static_cast<std::size_t>(scene.material_ids[t])].emission;
        if (!(e.x > 0.0f || e.y > 0.0f || e.z > 0.0f)) continue;
        FrameLight light;
        light.type = FrameLight::triangle;
        light.position = scene.positions[3 * t];
        light.edge_u = scene.positions[3 * t + 1] - scene.positions[3 * t];
        light.edge_v = scene.positions[3 * t + 2] - scene.positions[3 * t];
        light.intensity = e;
        scene.lights.push_back(light);
    }
}

}  // namespace

FrameScene load_frame_scene(const std::string& scene_json) {
    const json file = json::parse(read_text(scene_json));
    FrameScene scene;
    for (const json& mesh : file.value("meshes", json::array())) {
        if (!mesh.contains("obj") || mesh.contains("transform"))
            throw std::runtime_error(scene_json +
                                     ": only meshes {\"obj\": FILE} without a transform are read "
                                     "(export the scene with `fovref golden export --with-scene`)");
        load_obj(directory_of(scene_json) + "/" + mesh.at("obj").get<std::string>(), scene);
    }
    if (file.contains("materials"))
        throw std::runtime_error(scene_json + ": material overrides are not read by this client");
    add_lights(file.value("lights", json::array()), scene);
    // The scene scale: the bounds' diagonal (shadow-ray offsets are 1e-4 of it).
    if (!scene.positions.empty()) {
        Vec3 lo = scene.positions[0], hi = scene.positions[0];
        for (const Vec3& p : scene.positions) {
            lo = {std::fmin(lo.x, p.x), std::fmin(lo.y, p.y), std::fmin(lo.z, p.z)};
            hi = {std::fmax(hi.x, p.x), std::fmax(hi.y, p.y), std::fmax(hi.z, p.z)};
        }
        const Vec3 d = hi - lo;
        const float diagonal = std::sqrt(dot(d, d));
        scene.scene_scale = diagonal > 0.0f ? diagonal : 1.0f;
    }
    return scene;
}

}  // namespace fovref_client
