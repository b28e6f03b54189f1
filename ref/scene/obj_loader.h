// OBJ/MTL and texture loading shared by load_obj_into and load_scene_file (internal to
// ref/scene; the public entry points are in scene_file.h).
#pragma once

#include <map>
#include <string>

#include "ref/scene/scene.h"

namespace fovref {

/// Textures already loaded during one scene load: resolved file path -> Scene::textures index,
/// so that an OBJ instanced twice, or two MTLs naming the same file, share one texture.
using TextureCache = std::map<std::string, int>;

/// Load a texture file into scene.textures (or reuse it) and return its index. PNG is decoded
/// from sRGB to linear; PFM and EXR are linear already and are taken as stored. Grey is
/// replicated to RGB, alpha dropped. `name` is the file name as the referencing file wrote it;
/// `referenced_at` ("file:line") prefixes errors for a missing or unreadable file.
int load_texture_file(Scene& scene, const std::string& path, const std::string& name,
                      TextureCache& cache, const std::string& referenced_at);

/// load_obj_into with a shared texture cache; `referenced_at` ("scene.json:12", or empty)
/// prefixes the error when the OBJ file itself is missing. `strict`: the OBJ quirks of
/// docs/obj-quirks.md are errors instead of warnings (SceneLoadOptions::strict_obj).
void load_obj_into(Scene& scene, const std::string& obj_path, const glm::mat4& transform,
                   TextureCache& cache, const std::string& referenced_at, bool strict);

/// Append `material` to scene.materials, or return the index of an earlier material with the
/// same name when it is equal; a same-named material with other values is an error (names are
/// what JSON overrides and the exporter's MTL refer to, so they must be unambiguous).
int intern_material(Scene& scene, const Material& material, const std::string& defined_at);

/// A texture from an image file's bytes already in memory (a glTF data: URI or bufferView
/// image), decoded by decode_image_bytes (PNG, JPEG, BMP by their magic bytes; sRGB to linear),
/// then treated exactly as load_texture_file treats a file (RGB, finite, reuse, the scene's
/// pixel limit). `key` identifies the image in the cache ("<file>#images[3]"); `name` becomes
/// Texture::name; `where` prefixes errors.
int load_texture_bytes(Scene& scene, const std::string& bytes, const std::string& name,
                       const std::string& key, TextureCache& cache, const std::string& where);

}  // namespace fovref
