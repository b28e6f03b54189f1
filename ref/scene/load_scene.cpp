#include <filesystem>

#include "ref/core/error.h"
#include "ref/scene/procedural.h"
#include "ref/scene/scene_file.h"

namespace fovref {

namespace {

// The scene with --camera's camera in place of its own (and without its camera path).
Scene with_camera_file(Scene scene, const SceneLoadOptions& options) {
    if (options.camera_file.empty()) return scene;
    scene.camera = load_camera_file(options.camera_file);
    const bool had_path = !scene.camera_path.empty();
    scene.camera_path.clear();
    scene.load_stats.defaulted.push_back("camera: from " + options.camera_file + " (--camera)" +
                                         (had_path ? "; the scene's camera path is dropped" : ""));
    return scene;
}

Scene load_by_name(const std::string& name_or_path, const SceneLoadOptions& options) {
    std::filesystem::path path(name_or_path);
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
        path /= "scene.json";
        if (!std::filesystem::exists(path, ec))
            throw Error(name_or_path + ": directory has no scene.json");
    }
    if (!std::filesystem::exists(path, ec)) {
        std::string names;
        for (const ProceduralSceneInfo& info : procedural_scenes())
            names += (names.empty() ? "" : ", ") + info.name;
        throw Error("scene '" + name_or_path + "': no such file, and not a procedural scene (" +
                    names + ")");
    }
    // A model file places its default light at the camera, so it takes --camera itself.
    if (is_model_file(path.string())) return load_model_file(path.string(), options);
    Scene scene = load_scene_file(path.string(), options);
    return with_camera_file(std::move(scene), options);
}

}  // namespace

Scene load_scene(const std::string& name_or_path, const SceneLoadOptions& options) {
    if (is_procedural_scene(name_or_path))
        return with_camera_file(make_procedural_scene(name_or_path), options);
    return load_by_name(name_or_path, options);
}

}  // namespace fovref
