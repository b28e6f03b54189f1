// glTF 2.0 meshes (.gltf + .bin, .glb) by Debian's tinygltf (internal to ref/scene; the public
// entry points are in scene_file.h). docs/gltf.md documents what is read and how it maps onto
// the scene model.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "ref/scene/obj_loader.h"
#include "ref/scene/scene.h"

namespace fovref {

/// What a glTF file holds beyond its triangles: its first camera (world space, after `transform`)
/// and what the loader could not represent.
struct GltfContents {
    std::optional<Camera> camera;  ///< the first perspective camera of the default scene's nodes
    int point_lights = 0;          ///< KHR_lights_punctual point lights appended
    /// "file: feature (what was done instead): where, ...", one line per feature, sorted
    std::vector<std::string> unsupported;
};

/// Loads the triangles of the glTF file's default scene (scene 0 when none is named) into
/// `scene`, each node's mesh with its node transform and then `transform` applied; appends its
/// materials (interned by name), base-colour textures and KHR_lights_punctual point lights.
/// Throws fovref::Error "file: message" (prefixed by `referenced_at` for a missing file) on any
/// invalid input. Does not call finalize_scene, and does not write scene.camera. Triangle
/// order: nodes depth-first (children in the order listed), then primitives, then indices.
GltfContents load_gltf_into(Scene& scene, const std::string& gltf_path, const glm::mat4& transform,
                            TextureCache& cache, const std::string& referenced_at);

}  // namespace fovref
