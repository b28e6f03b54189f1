// Scene files (SPEC §2): the JSON document of docs/scene-format.md, read with nlohmann::json and
// checked strictly: a wrong type, a missing or unknown key, a number that is not a finite binary32,
// a non-increasing camera path time all throw fovref::Error "file:line: /json/pointer: message",
// the line coming from JsonLocator (nlohmann does not keep lines).
#include <nlohmann/json.hpp>

#include <bit>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <string_view>

#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/core/json_locator.h"
#include "ref/image/image_io.h"
#include "ref/scene/gltf_loader.h"
#include "ref/scene/obj_loader.h"
#include "ref/scene/scene_file.h"

namespace fovref {

using nlohmann::json;

// --- Instance transforms ---------------------------------------------------------------------

namespace {

// sin and cos of an angle in degrees; exact at multiples of 90 degrees (dm::sin(radians(90)) is
// 1 but dm::cos of it is -4.4e-8, which would tilt an axis-aligned box).
void sin_cos_degrees(float degrees, float& sine, float& cosine) {
    const float quarter_turns = std::round(degrees / 90.0f);
    if (std::fabs(quarter_turns) < 1e6f && quarter_turns * 90.0f == degrees) {
        const long long q = ((static_cast<long long>(quarter_turns) % 4) + 4) % 4;
        const float sines[4] = {0.0f, 1.0f, 0.0f, -1.0f};
        const float cosines[4] = {1.0f, 0.0f, -1.0f, 0.0f};
        sine = sines[q];
        cosine = cosines[q];
        return;
    }
    const float radians = dm::radians(degrees);
    sine = dm::sin(radians);
    cosine = dm::cos(radians);
}

}  // namespace

glm::mat4 euler_xyz_transform(glm::vec3 translate, glm::vec3 rotate_deg, glm::vec3 scale) {
    float sx, cx, sy, cy, sz, cz;
    sin_cos_degrees(rotate_deg.x, sx, cx);
    sin_cos_degrees(rotate_deg.y, sy, cy);
    sin_cos_degrees(rotate_deg.z, sz, cz);
    // glm matrices are column-major: m[column][row].
    glm::mat4 rx(1.0f), ry(1.0f), rz(1.0f), s(1.0f), t(1.0f);
    rx[1][1] = cx, rx[2][1] = -sx, rx[1][2] = sx, rx[2][2] = cx;
    ry[0][0] = cy, ry[2][0] = sy, ry[0][2] = -sy, ry[2][2] = cy;
    rz[0][0] = cz, rz[1][0] = -sz, rz[0][1] = sz, rz[1][1] = cz;
    s[0][0] = scale.x, s[1][1] = scale.y, s[2][2] = scale.z;
    t[3] = glm::vec4(translate, 1.0f);
    return t * rz * ry * rx * s;
}

namespace {

// --- Checked access to the parsed document -----------------------------------------------------

class SceneJson {
public:
    SceneJson(const std::string& file, const std::string& text)
        : file_(file), locator_(text, file) {}

    [[noreturn]] void fail(const std::string& pointer, const std::string& message) const {
        throw file_error(file_, locator_.find(pointer).value_line, at(pointer) + message);
    }
    [[noreturn]] void fail_at_key(const std::string& pointer, const std::string& message) const {
        throw file_error(file_, locator_.find(pointer).key_line, at(pointer) + message);
    }
    /// "/camera/fov: " for a value, "the document: " for the whole file (empty pointer).
    static std::string at(const std::string& pointer) {
        return (pointer.empty() ? std::string("the document") : pointer) + ": ";
    }
    /// "file:line" of a value, for errors raised by the OBJ and texture loaders.
    std::string where(const std::string& pointer) const {
        return file_ + ":" + std::to_string(locator_.find(pointer).value_line);
    }

    void expect_object(const json& value, const std::string& pointer) const {
        if (!value.is_object())
            fail(pointer, std::string("expected an object, got ") + value.type_name());
    }

    /// An object whose keys are all in `allowed` (an unknown key is an error at its line).
    void expect_keys(const json& value, const std::string& pointer,
                     std::initializer_list<std::string_view> allowed) const {
        expect_object(value, pointer);
        for (auto it = value.begin(); it != value.end(); ++it) {
            bool known = false;
            for (std::string_view key : allowed) known = known || key == it.key();
            if (!known) {
                std::string list;
                for (std::string_view key : allowed)
                    list += (list.empty() ? "" : ", ") + std::string(key);
                fail_at_key(json_pointer_member(pointer, it.key()),
                            "unknown key \"" + it.key() + "\" (expected one of: " + list + ")");
            }
        }
    }

    const json& required(const json& object, const std::string& pointer,
                         const std::string& key) const {
        auto it = object.find(key);
        if (it == object.end()) fail(pointer, "missing key \"" + key + "\"");
        return *it;
    }

    float number(const json& value, const std::string& pointer) const {
        if (!value.is_number())
            fail(pointer, std::string("expected a number, got ") + value.type_name());
        // Correctly rounded from the text (not binary64 rounded again to binary32); the two
        // differ by at most one ulp, which also proves the pointer names this very number.
        const float via_double = static_cast<float>(value.get<double>());
        float result = via_double;
        if (locator_.number_as_float(pointer, result) && std::isfinite(via_double)) {
            // Distance in the binary32 ordering, in 64 bits: -0 and +0 are 0 apart (the
            // integer -0 reads as +0 through nlohmann, as -0 from the text).
            auto ordered = [](float x) {
                const auto bits = std::bit_cast<std::uint32_t>(x);
                return (bits & 0x80000000u) ? -static_cast<std::int64_t>(bits & 0x7fffffffu)
                                            : static_cast<std::int64_t>(bits);
            };
            const std::int64_t distance = ordered(result) - ordered(via_double);
            FOVREF_CHECK(distance <= 1 && distance >= -1,
                         "JSON number at " + pointer + " read inconsistently");
        }
        if (!std::isfinite(result)) fail(pointer, "number is not a finite binary32 value");
        return result;
    }

    glm::vec3 vec3(const json& value, const std::string& pointer) const {
        if (!value.is_array() || value.size() != 3) fail(pointer, "expected an array of 3 numbers");
        glm::vec3 result;
        for (int k = 0; k < 3; ++k)
            result[k] = number(value[static_cast<std::size_t>(k)],
                               json_pointer_element(pointer, static_cast<std::size_t>(k)));
        return result;
    }

    /// A colour: [r, g, b] or one number for grey; components >= 0.
    glm::vec3 color(const json& value, const std::string& pointer) const {
        glm::vec3 result =
            value.is_number() ? glm::vec3(number(value, pointer)) : vec3(value, pointer);
        if (!(result.x >= 0.0f && result.y >= 0.0f && result.z >= 0.0f))
            fail(pointer, "colour components must be >= 0");
        return result;
    }

    /// A scale: one number (uniform) or [x, y, z].
    glm::vec3 scale(const json& value, const std::string& pointer) const {
        return value.is_number() ? glm::vec3(number(value, pointer)) : vec3(value, pointer);
    }

    std::string string(const json& value, const std::string& pointer) const {
        if (!value.is_string())
            fail(pointer, std::string("expected a string, got ") + value.type_name());
        return value.get<std::string>();
    }

    const std::string& file() const { return file_; }

private:
    std::string file_;
    JsonLocator locator_;
};

std::string resolve(const std::string& directory, const std::string& name) {
    if (directory.empty()) return name;
    return (std::filesystem::path(directory) / name).string();
}

// --- Sections ----------------------------------------------------------------------------------

glm::mat4 read_transform(const SceneJson& doc, const json& value, const std::string& pointer) {
    doc.expect_keys(value, pointer, {"translate", "rotate_deg", "scale", "matrix"});
    glm::mat4 transform(1.0f);
    if (value.contains("matrix")) {
        if (value.size() != 1)
            doc.fail(pointer, "\"matrix\" cannot be combined with translate/rotate_deg/scale");
        // Four rows of four numbers; p' = M [p, 1]; the last row must be [0, 0, 0, 1] (affine).
        const std::string matrix_pointer = json_pointer_member(pointer, "matrix");
        const json& rows = value["matrix"];
        if (!rows.is_array() || rows.size() != 4)
            doc.fail(matrix_pointer, "expected 4 rows of 4 numbers");
        for (std::size_t r = 0; r < 4; ++r) {
            const std::string row_pointer = json_pointer_element(matrix_pointer, r);
            if (!rows[r].is_array() || rows[r].size() != 4)
                doc.fail(row_pointer, "expected a row of 4 numbers");
            for (std::size_t c = 0; c < 4; ++c)
                transform[static_cast<int>(c)][static_cast<int>(r)] =
                    doc.number(rows[r][c], json_pointer_element(row_pointer, c));
        }
        if (transform[0][3] != 0.0f || transform[1][3] != 0.0f || transform[2][3] != 0.0f ||
            transform[3][3] != 1.0f)
            doc.fail(json_pointer_element(matrix_pointer, 3), "the last row must be [0, 0, 0, 1]");
    } else {
        glm::vec3 translate(0.0f), rotate_deg(0.0f), scale(1.0f);
        if (value.contains("translate"))
            translate = doc.vec3(value["translate"], json_pointer_member(pointer, "translate"));
        if (value.contains("rotate_deg"))
            rotate_deg = doc.vec3(value["rotate_deg"], json_pointer_member(pointer, "rotate_deg"));
        if (value.contains("scale"))
            scale = doc.scale(value["scale"], json_pointer_member(pointer, "scale"));
        transform = euler_xyz_transform(translate, rotate_deg, scale);
    }
    const float determinant = glm::determinant(glm::mat3(transform));
    if (!(std::fabs(determinant) > 0.0f) || !std::isfinite(determinant))
        doc.fail(pointer, "the transform is singular (zero scale?) or not finite");
    return transform;
}

void read_meshes(const SceneJson& doc, const json& meshes, const std::string& directory,
                 Scene& scene, TextureCache& cache, const SceneLoadOptions& options) {
    const std::string pointer = "/meshes";
    if (!meshes.is_array()) doc.fail(pointer, "expected an array of meshes");
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        const std::string mesh_pointer = json_pointer_element(pointer, i);
        const json& mesh = meshes[i];
        doc.expect_keys(mesh, mesh_pointer, {"obj", "gltf", "transform"});
        if (mesh.contains("obj") == mesh.contains("gltf"))
            doc.fail(mesh_pointer, "give exactly one of \"obj\", \"gltf\"");
        const char* kind = mesh.contains("obj") ? "obj" : "gltf";
        const std::string file_pointer = json_pointer_member(mesh_pointer, kind);
        const std::string file = doc.string(mesh[kind], file_pointer);
        glm::mat4 transform(1.0f);
        if (mesh.contains("transform"))
            transform = read_transform(doc, mesh["transform"],
                                       json_pointer_member(mesh_pointer, "transform"));
        const std::string path = resolve(directory, file);
        std::error_code ec;
        if (!std::filesystem::is_regular_file(path, ec))
            doc.fail(file_pointer, std::string(mesh.contains("obj") ? "OBJ" : "glTF") + " file '" +
                                       file + "' not found (looked for " + path + ")");
        if (mesh.contains("obj")) {
            load_obj_into(scene, path, transform, cache, doc.where(file_pointer),
                          options.strict_obj);
        } else {
            // The scene file's camera and lights are the scene's: the glTF file's camera is not
            // used, its unsupported features are listed.
            const GltfContents contents =
                load_gltf_into(scene, path, transform, cache, doc.where(file_pointer));
            for (const std::string& feature : contents.unsupported)
                scene.load_stats.unsupported.push_back(feature);
        }
    }
}

void read_material_overrides(const SceneJson& doc, const json& overrides,
                             const std::string& directory, Scene& scene, TextureCache& cache) {
    const std::string pointer = "/materials";
    doc.expect_object(overrides, pointer);
    for (auto it = overrides.begin(); it != overrides.end(); ++it) {
        const std::string material_pointer = json_pointer_member(pointer, it.key());
        const json& value = it.value();
        doc.expect_keys(value, material_pointer,
                        {"albedo", "texture", "emission", "specular", "roughness"});
        Material* material = nullptr;
        for (Material& candidate : scene.materials)
            if (candidate.name == it.key()) material = &candidate;
        if (material == nullptr)
            doc.fail_at_key(material_pointer,
                            "no mesh defines a material named \"" + it.key() + "\"");
        auto member = [&](const char* key) { return json_pointer_member(material_pointer, key); };
        if (value.contains("albedo"))
            material->albedo = doc.color(value["albedo"], member("albedo"));
        if (value.contains("emission"))
            material->emission = doc.color(value["emission"], member("emission"));
        if (value.contains("specular"))
            material->specular = doc.color(value["specular"], member("specular"));
        if (value.contains("roughness")) {
            float roughness = doc.number(value["roughness"], member("roughness"));
            if (!(roughness >= 0.0f && roughness <= 1.0f))
                doc.fail(member("roughness"), "roughness must be in [0, 1]");
            material->roughness = roughness;
        }
        if (value.contains("texture")) {
            const json& texture = value["texture"];
            if (texture.is_null()) {
                material->texture = -1;
            } else {
                const std::string name = doc.string(texture, member("texture"));
                // load_texture_file may grow scene.textures, never scene.materials: the
                // material pointer stays valid.
                material->texture = load_texture_file(scene, resolve(directory, name), name, cache,
                                                      doc.where(member("texture")));
            }
        }
    }
}

void read_lights(const SceneJson& doc, const json& lights, Scene& scene) {
    const std::string pointer = "/lights";
    if (!lights.is_array()) doc.fail(pointer, "expected an array of lights");
    for (std::size_t i = 0; i < lights.size(); ++i) {
        const std::string light_pointer = json_pointer_element(pointer, i);
        const json& value = lights[i];
        doc.expect_object(value, light_pointer);
        auto member = [&](const char* key) { return json_pointer_member(light_pointer, key); };
        const std::string type =
            doc.string(doc.required(value, light_pointer, "type"), member("type"));
        Light light;
        if (type == "point") {
            doc.expect_keys(value, light_pointer, {"type", "position", "intensity"});
            light.type = Light::Type::point;
            light.position =
                doc.vec3(doc.required(value, light_pointer, "position"), member("position"));
            light.intensity =
                doc.color(doc.required(value, light_pointer, "intensity"), member("intensity"));
        } else if (type == "quad") {
            doc.expect_keys(value, light_pointer,
                            {"type", "corner", "edge_u", "edge_v", "radiance"});
            light.type = Light::Type::quad;
            light.position =
                doc.vec3(doc.required(value, light_pointer, "corner"), member("corner"));
            light.edge_u = doc.vec3(doc.required(value, light_pointer, "edge_u"), member("edge_u"));
            light.edge_v = doc.vec3(doc.required(value, light_pointer, "edge_v"), member("edge_v"));
            light.intensity =
                doc.color(doc.required(value, light_pointer, "radiance"), member("radiance"));
            const float double_area = glm::length(glm::cross(light.edge_u, light.edge_v));
            if (!(double_area > 0.0f) || !std::isfinite(double_area))
                doc.fail(member("edge_v"), "the quad's edges are parallel or zero (zero area)");
        } else {
            doc.fail(member("type"), "unknown light type \"" + type + "\" (point or quad)");
        }
        scene.lights.push_back(light);
    }
}

// A quaternion [x, y, z, w]: kept as written when unit length within 1e-6 in |q|^2 (so exported
// keys reload exactly), normalised otherwise; zero is an error.
glm::quat read_quaternion(const SceneJson& doc, const json& value, const std::string& pointer) {
    if (!value.is_array() || value.size() != 4)
        doc.fail(pointer, "expected a quaternion [x, y, z, w]");
    float q[4];
    for (std::size_t k = 0; k < 4; ++k)
        q[k] = doc.number(value[k], json_pointer_element(pointer, k));
    glm::quat result(q[3], q[0], q[1], q[2]);  // glm's constructor order is (w, x, y, z)
    const float length2 = glm::dot(result, result);
    if (!(length2 > 0.0f) || !std::isfinite(length2)) doc.fail(pointer, "the quaternion is zero");
    if (std::fabs(length2 - 1.0f) > 1e-6f) result = result / std::sqrt(length2);
    return result;
}

float read_vfov(const SceneJson& doc, const json& value, const std::string& pointer) {
    const float vfov = doc.number(value, pointer);
    if (!(vfov > 0.0f && vfov < 180.0f)) doc.fail(pointer, "vfov_deg must be in (0, 180)");
    return vfov;
}

void read_camera(const SceneJson& doc, const json& value, const std::string& pointer,
                 Scene& scene) {
    doc.expect_keys(value, pointer,
                    {"position", "look_at", "up", "quaternion", "basis", "vfov_deg"});
    auto member = [&](const char* key) { return json_pointer_member(pointer, key); };
    const glm::vec3 position =
        doc.vec3(doc.required(value, pointer, "position"), member("position"));
    const float vfov = read_vfov(doc, doc.required(value, pointer, "vfov_deg"), member("vfov_deg"));
    const int forms = static_cast<int>(value.contains("look_at")) +
                      static_cast<int>(value.contains("quaternion")) +
                      static_cast<int>(value.contains("basis"));
    if (forms != 1) doc.fail(pointer, "give exactly one of \"look_at\", \"quaternion\", \"basis\"");
    if (value.contains("up") && !value.contains("look_at"))
        doc.fail_at_key(member("up"), "\"up\" only goes with \"look_at\"");
    try {
        if (value.contains("look_at")) {
            const glm::vec3 target = doc.vec3(value["look_at"], member("look_at"));
            const glm::vec3 up =
                value.contains("up") ? doc.vec3(value["up"], member("up")) : glm::vec3(0, 1, 0);
            scene.camera = look_at(position, target, up, vfov);
        } else if (value.contains("quaternion")) {
            scene.camera = camera_from_quat(
                position, read_quaternion(doc, value["quaternion"], member("quaternion")), vfov);
        } else {
            // The camera's axes as written (what export_scene writes, so cameras reload exactly);
            // they must be orthonormal and right-handed within 1e-5.
            const std::string basis_pointer = member("basis");
            const json& basis = value["basis"];
            doc.expect_keys(basis, basis_pointer, {"right", "up", "forward"});
            auto axis = [&](const char* key) {
                return doc.vec3(doc.required(basis, basis_pointer, key),
                                json_pointer_member(basis_pointer, key));
            };
            Camera camera;
            camera.position = position;
            camera.right = axis("right");
            camera.up = axis("up");
            camera.forward = axis("forward");
            camera.vfov_deg = vfov;
            const float tolerance = 1e-5f;
            const glm::vec3 handedness = glm::cross(camera.right, camera.up) + camera.forward;
            const bool orthonormal =
                std::fabs(glm::dot(camera.right, camera.right) - 1.0f) <= tolerance &&
                std::fabs(glm::dot(camera.up, camera.up) - 1.0f) <= tolerance &&
                std::fabs(glm::dot(camera.forward, camera.forward) - 1.0f) <= tolerance &&
                std::fabs(glm::dot(camera.right, camera.up)) <= tolerance &&
                std::fabs(glm::dot(camera.right, camera.forward)) <= tolerance &&
                std::fabs(glm::dot(camera.up, camera.forward)) <= tolerance &&
                glm::dot(handedness, handedness) <= tolerance * tolerance;
            if (!orthonormal)
                doc.fail(basis_pointer,
                         "right, up, forward must be orthonormal with cross(right, up) = -forward");
            scene.camera = camera;
        }
    } catch (const Error& e) {
        const std::string message = e.what();
        if (message.rfind(doc.file(), 0) == 0) throw;  // already located
        doc.fail(pointer, message);
    }
}

void read_camera_path(const SceneJson& doc, const json& value, Scene& scene) {
    const std::string pointer = "/camera_path";
    if (!value.is_array()) doc.fail(pointer, "expected an array of keyframes");
    for (std::size_t i = 0; i < value.size(); ++i) {
        const std::string key_pointer = json_pointer_element(pointer, i);
        const json& key = value[i];
        doc.expect_keys(key, key_pointer, {"time", "position", "look_at", "up", "quaternion"});
        auto member = [&](const char* name) { return json_pointer_member(key_pointer, name); };
        CameraKey keyframe;
        keyframe.time = doc.number(doc.required(key, key_pointer, "time"), member("time"));
        if (!scene.camera_path.empty() && !(keyframe.time > scene.camera_path.back().time))
            doc.fail(member("time"), "keyframe times must be strictly increasing (previous " +
                                         std::to_string(scene.camera_path.back().time) + ")");
        keyframe.position =
            doc.vec3(doc.required(key, key_pointer, "position"), member("position"));
        const bool has_look_at = key.contains("look_at");
        if (has_look_at == key.contains("quaternion"))
            doc.fail(key_pointer, "give exactly one of \"look_at\", \"quaternion\"");
        if (key.contains("up") && !has_look_at)
            doc.fail_at_key(member("up"), "\"up\" only goes with \"look_at\"");
        if (has_look_at) {
            const glm::vec3 target = doc.vec3(key["look_at"], member("look_at"));
            const glm::vec3 up =
                key.contains("up") ? doc.vec3(key["up"], member("up")) : glm::vec3(0, 1, 0);
            try {
                keyframe.orientation = camera_orientation(
                    look_at(keyframe.position, target, up, scene.camera.vfov_deg));
            } catch (const Error& e) {
                doc.fail(key_pointer, e.what());
            }
        } else {
            keyframe.orientation = read_quaternion(doc, key["quaternion"], member("quaternion"));
        }
        scene.camera_path.push_back(keyframe);
    }
}

void read_display(const SceneJson& doc, const json& value, Scene& scene) {
    const std::string pointer = "/display";
    doc.expect_keys(value, pointer, {"model", "max_view_angle_deg", "distance_px"});
    auto member = [&](const char* key) { return json_pointer_member(pointer, key); };
    std::string model = value.contains("distance_px") ? "fixed" : "fov";
    if (value.contains("model")) model = doc.string(value["model"], member("model"));
    DisplayModel display;
    if (model == "fov") {
        display.kind = DisplayModel::Kind::field_of_view;
    } else if (model == "diagonal") {
        display.kind = DisplayModel::Kind::diagonal;
        display.max_view_angle_deg = doc.number(doc.required(value, pointer, "max_view_angle_deg"),
                                                member("max_view_angle_deg"));
        if (!(display.max_view_angle_deg > 0.0f && display.max_view_angle_deg < 90.0f))
            doc.fail(member("max_view_angle_deg"), "max_view_angle_deg must be in (0, 90)");
    } else if (model == "fixed") {
        display.kind = DisplayModel::Kind::fixed;
        display.distance_px =
            doc.number(doc.required(value, pointer, "distance_px"), member("distance_px"));
        if (!(display.distance_px > 0.0f))
            doc.fail(member("distance_px"), "distance_px must be > 0");
    } else {
        doc.fail(member("model"), "unknown display model \"" + model + "\" (fov, diagonal, fixed)");
    }
    if (value.contains("max_view_angle_deg") && model != "diagonal")
        doc.fail_at_key(member("max_view_angle_deg"), "only used by the \"diagonal\" model");
    if (value.contains("distance_px") && model != "fixed")
        doc.fail_at_key(member("distance_px"), "only used by the \"fixed\" model");
    scene.display = display;
}

void read_presets(const SceneJson& doc, const json& value, Scene& scene) {
    const std::string pointer = "/presets";
    doc.expect_object(value, pointer);
    for (auto it = value.begin(); it != value.end(); ++it) {
        doc.expect_object(it.value(), json_pointer_member(pointer, it.key()));
        scene.presets[it.key()] = it.value().dump();  // compact; keys sorted (std::map)
    }
}

}  // namespace

Scene load_scene_file(const std::string& path, const SceneLoadOptions& options) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw Error(path + ": scene file not found");
    const std::string text = read_file(path);

    // Nesting, syntax (nlohmann's byte offset turned into line:column), numbers out of range.
    const json document = parse_json_document<json>(text, path);
    const SceneJson doc(path, text);  // duplicate keys are reported here
    doc.expect_keys(document, "",
                    {"version", "name", "description", "meshes", "materials", "lights", "camera",
                     "camera_path", "display", "presets"});
    const json& version = doc.required(document, "", "version");
    if (!version.is_number_integer() || version.get<long long>() != 1)
        doc.fail("/version", "unsupported version (this reader reads version 1)");

    Scene scene;
    scene.source = path;
    const std::filesystem::path file_path(path);
    scene.name = utf8_or_latin1(file_path.stem().string());
    if (scene.name == "scene" && file_path.has_parent_path())
        scene.name = utf8_or_latin1(file_path.parent_path().filename().string());
    if (document.contains("name")) scene.name = doc.string(document["name"], "/name");
    if (document.contains("description")) doc.string(document["description"], "/description");

    const std::string directory = file_path.parent_path().string();
    TextureCache cache;
    if (document.contains("meshes"))
        read_meshes(doc, document["meshes"], directory, scene, cache, options);
    if (document.contains("materials"))
        read_material_overrides(doc, document["materials"], directory, scene, cache);
    if (document.contains("lights")) read_lights(doc, document["lights"], scene);
    read_camera(doc, doc.required(document, "", "camera"), "/camera", scene);
    if (document.contains("camera_path")) read_camera_path(doc, document["camera_path"], scene);
    if (document.contains("display")) read_display(doc, document["display"], scene);
    if (document.contains("presets")) read_presets(doc, document["presets"], scene);

    finalize_scene(scene);
    return scene;
}

Camera load_camera_file(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw Error(path + ": camera file not found");
    const std::string text = read_file(path);
    const json document = parse_json_document<json>(text, path);
    const SceneJson doc(path, text);
    doc.expect_object(document, "");
    Scene scene;
    // {"camera": {...}} (a scene file, say) or the camera object itself.
    if (document.contains("camera"))
        read_camera(doc, document["camera"], "/camera", scene);
    else
        read_camera(doc, document, "", scene);
    return scene.camera;
}

}  // namespace fovref
