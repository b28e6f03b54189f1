// A bare model file (.obj, .gltf, .glb) as a scene: docs/model-files.md.
#include <cstdio>
#include <filesystem>
#include <string>

#include "ref/core/error.h"
#include "ref/core/vec.h"
#include "ref/image/image_io.h"
#include "ref/scene/gltf_loader.h"
#include "ref/scene/obj_loader.h"
#include "ref/scene/scene_file.h"

namespace fovref {

namespace {

// sin(30 degrees), exactly: the default camera's vfov is 60 degrees.
constexpr float default_vfov_deg = 60.0f;
constexpr float sin_half_default_vfov = 0.5f;
// pi in binary32: the default light's intensity is pi d^2.
constexpr float pi_f = 3.14159274f;

std::string number_text(float value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", static_cast<double>(value));
    return text;
}

std::string vec3_text(glm::vec3 v) {
    return "(" + number_text(v.x) + ", " + number_text(v.y) + ", " + number_text(v.z) + ")";
}

bool has_emission(const Scene& scene) {
    for (const std::int32_t m : scene.material_ids) {
        const glm::vec3 e = scene.materials[static_cast<std::size_t>(m)].emission;
        if (e.x > 0.0f || e.y > 0.0f || e.z > 0.0f) return true;
    }
    return false;
}

}  // namespace

bool is_model_file(const std::string& path) {
    const std::string ext = lower_extension(path);
    return ext == ".obj" || ext == ".gltf" || ext == ".glb";
}

Scene load_model_file(const std::string& path, const SceneLoadOptions& options) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw Error(path + ": model file not found");
    Scene scene;
    scene.source = path;
    scene.name = utf8_or_latin1(std::filesystem::path(path).stem().string());
    TextureCache cache;
    std::optional<Camera> file_camera;
    if (lower_extension(path) == ".obj") {
        load_obj_into(scene, path, glm::mat4(1.0f), cache, "", options.strict_obj);
    } else {
        GltfContents contents = load_gltf_into(scene, path, glm::mat4(1.0f), cache, "");
        file_camera = contents.camera;
        scene.load_stats.unsupported = contents.unsupported;
    }
    SceneLoadStats& stats = scene.load_stats;
    if (scene.triangle_count() == 0)
        throw Error(path + ": no triangles to render: " +
                    (stats.zero_area_triangles_dropped > 0
                         ? "all " + std::to_string(stats.zero_area_triangles_dropped) +
                               " triangles have zero area"
                         : std::string("the file has no faces")) +
                    " (" + std::to_string(stats.points_ignored) + " points and " +
                    std::to_string(stats.lines_ignored) + " lines ignored)");

    // The bounding sphere of the triangles: centre c, radius r (half the bounds' diagonal).
    const Bounds bounds = scene_bounds(scene);
    const glm::vec3 centre = (bounds.min + bounds.max) * 0.5f;
    const float radius = glm::length(bounds.max - bounds.min) * 0.5f;
    // From +Z, looking down -Z at the centre, at the distance where the sphere just fits the
    // 60-degree vertical field of view: d = r / sin(30 degrees) = 2r.
    const float distance = radius > 0.0f ? radius / sin_half_default_vfov : 1.0f;
    const glm::vec3 eye = centre + glm::vec3(0.0f, 0.0f, distance);
    if (!options.camera_file.empty()) {
        scene.camera = load_camera_file(options.camera_file);
        stats.defaulted.push_back("camera: from " + options.camera_file + " (--camera)");
    } else if (file_camera) {
        scene.camera = *file_camera;
    } else {
        // A model far from the origin for its size (or beyond binary32) cannot be framed so.
        try {
            if (!is_finite(centre) || !std::isfinite(radius) || !is_finite(eye))
                throw Error("its bounds are not finite in binary32");
            scene.camera = look_at(eye, centre, glm::vec3(0.0f, 1.0f, 0.0f), default_vfov_deg);
        } catch (const Error& e) {
            throw Error(path + ": cannot place the default camera (give --camera): " + e.what());
        }
        stats.defaulted.push_back("camera: at " + vec3_text(eye) + " looking down -Z at the " +
                                  "bounding sphere's centre " + vec3_text(centre) +
                                  ", vfov 60 deg, distance 2r = " + number_text(distance) +
                                  " (the file has no camera)");
    }
    // No light and no emissive triangle: a point light at the camera, bright enough that a
    // white diffuse surface facing it at the distance of the sphere's centre shows its albedo
    // (intensity pi d^2, d = that distance).
    if (scene.lights.empty() && !has_emission(scene)) {
        const float d = glm::length(centre - scene.camera.position);
        const float d_used = d > 0.0f ? d : distance;
        Light light;
        light.type = Light::Type::point;
        light.position = scene.camera.position;
        light.intensity = glm::vec3(pi_f * d_used * d_used);
        if (!is_finite(light.intensity))
            throw Error(path + ": cannot place the default light: its intensity pi d^2 (d = " +
                        number_text(d_used) + ") is not finite in binary32");
        scene.lights.push_back(light);
        stats.defaulted.push_back("light: point light at the camera " + vec3_text(light.position) +
                                  ", intensity pi d^2 = " + number_text(light.intensity.x) +
                                  " (d = " + number_text(d_used) +
                                  ", the camera's distance to the centre; the file has no light)");
    }
    finalize_scene(scene);
    return scene;
}

}  // namespace fovref
