#include <filesystem>

#include "ref/core/error.h"
#include "ref/scene/procedural.h"
#include "ref/scene/scene_file.h"

namespace fovref {

Scene load_scene(const std::string& name_or_path) {
    if (is_procedural_scene(name_or_path)) return make_procedural_scene(name_or_path);
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
    return load_scene_file(path.string());
}

}  // namespace fovref
