// Scene files (SPEC §2): a JSON document naming OBJ/MTL meshes, textures, materials, lights, the
// camera, a camera path, the display model and presets. docs/scene-format.md documents every key.
// Errors name the file and line (JSON and OBJ alike); zero-area triangles are dropped and
// counted in Scene::load_stats.
#pragma once

#include <string>

#include "ref/scene/scene.h"

namespace fovref {

/// Load a scene file. Throws fovref::Error("file:line: message") on any invalid input.
Scene load_scene_file(const std::string& path);

/// Load one OBJ file (with its MTL and textures) into `scene`, appending triangles and materials.
/// `transform` maps object to world space. Used by load_scene_file; exposed for tests.
/// Does not call finalize_scene.
void load_obj_into(Scene& scene, const std::string& obj_path, const glm::mat4& transform);

/// Write the scene as OBJ + MTL + PFM textures + scene.json into `directory` (created), so
/// that load_scene_file(directory + "/scene.json") gives back the same triangles, materials,
/// lights and camera. Positions are written with 9 significant digits, which round-trips binary32.
/// Files: scene.json, scene.obj, scene.mtl, textures/<name>.pfm.
void export_scene(const Scene& scene, const std::string& directory);

/// A scene argument as the CLI takes it: a procedural scene's name, a path to a scene file, or a
/// directory holding scene.json ("DIR: directory has no scene.json" when it holds none).
Scene load_scene(const std::string& name_or_path);

/// Instance transform T * Rz * Ry * Rx * S (docs/scene-format.md): scale first, then rotate about
/// X, then Y, then Z (angles in degrees, right-handed), then translate. Multiples of 90 degrees
/// use exact sines and cosines (0, +-1), so axis-aligned scenes stay exact.
glm::mat4 euler_xyz_transform(glm::vec3 translate, glm::vec3 rotate_deg, glm::vec3 scale);

/// MTL Blinn-Phong exponent Ns to GGX roughness (alpha = roughness^2): Walter et al. 2007's
/// alpha = sqrt(2 / (Ns + 2)), so roughness = (2 / (Ns + 2))^(1/4). Ns = 0 gives 1, Ns = 1000
/// gives about 0.21.
float ns_to_roughness(float ns);

}  // namespace fovref
