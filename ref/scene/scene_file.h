// Scene files (SPEC §2): a JSON document naming OBJ/MTL meshes, textures, materials, lights, the
// camera, a camera path, the display model and presets. docs/scene-format.md documents every key.
// Errors name the file and line (JSON and OBJ alike); zero-area triangles are dropped and
// counted in Scene::load_stats.
#pragma once

#include <string>

#include "ref/scene/scene.h"

namespace fovref {

/// How scenes are read (the command line's --strict-obj and --camera).
struct SceneLoadOptions {
    /// OBJ quirks that are accepted with a warning by default (docs/obj-quirks.md: an undefined
    /// material, a missing MTL or texture, backslashes in paths, ...) are errors instead.
    bool strict_obj = false;
    /// A JSON camera file ({"camera": {...}} or the camera object itself, as in a scene file)
    /// that replaces the scene's camera and camera path; "" = keep the scene's.
    std::string camera_file;
};

/// Load a scene file. Throws fovref::Error("file:line: message") on any invalid input.
Scene load_scene_file(const std::string& path, const SceneLoadOptions& options = {});

/// A bare model file (.obj, .gltf, .glb) as a scene (docs/model-files.md): its triangles,
/// materials and textures; the file's first camera and lights where it has them (glTF), else a
/// default camera framing the bounding sphere and a default point light at the camera, each
/// recorded in load_stats.defaulted. A file without triangles is an error.
Scene load_model_file(const std::string& path, const SceneLoadOptions& options = {});

/// Whether `path` names a model file by its extension (.obj, .gltf, .glb; any case).
bool is_model_file(const std::string& path);

/// The camera of a JSON camera file (SceneLoadOptions::camera_file). Throws "file:line: ...".
Camera load_camera_file(const std::string& path);

/// Load one OBJ file (with its MTL and textures) into `scene`, appending triangles and materials.
/// `transform` maps object to world space. Used by load_scene_file; exposed for tests.
/// Does not call finalize_scene.
void load_obj_into(Scene& scene, const std::string& obj_path, const glm::mat4& transform,
                   const SceneLoadOptions& options = {});

/// Write the scene as OBJ + MTL + PFM textures + scene.json into `directory` (created), so
/// that load_scene_file(directory + "/scene.json") gives back the same triangles, materials,
/// lights and camera. Positions are written with 9 significant digits, which round-trips binary32.
/// Files: scene.json, scene.obj, scene.mtl, textures/<name>.pfm.
void export_scene(const Scene& scene, const std::string& directory);

/// A scene argument as the CLI takes it: a procedural scene's name, a path to a scene file, or a
/// directory holding scene.json ("DIR: directory has no scene.json" when it holds none).
/// A model file (is_model_file) is loaded with load_model_file. options.camera_file, when given,
/// replaces the loaded scene's camera (and drops its camera path), noted in load_stats.defaulted.
Scene load_scene(const std::string& name_or_path, const SceneLoadOptions& options = {});

/// Instance transform T * Rz * Ry * Rx * S (docs/scene-format.md): scale first, then rotate about
/// X, then Y, then Z (angles in degrees, right-handed), then translate. Multiples of 90 degrees
/// use exact sines and cosines (0, +-1), so axis-aligned scenes stay exact.
glm::mat4 euler_xyz_transform(glm::vec3 translate, glm::vec3 rotate_deg, glm::vec3 scale);

/// MTL Blinn-Phong exponent Ns to GGX roughness (alpha = roughness^2): Walter et al. 2007's
/// alpha = sqrt(2 / (Ns + 2)), so roughness = (2 / (Ns + 2))^(1/4). Ns = 0 gives 1, Ns = 1000
/// gives about 0.21.
float ns_to_roughness(float ns);

}  // namespace fovref
