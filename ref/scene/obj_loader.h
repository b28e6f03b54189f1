// OBJ/MTL and texture loading shared by load_obj_into and load_scene_file (internal to
// ref/scene; the public entry points are in scene_file.h).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "ref/scene/scene.h"

namespace fovref {

/// What one scene load remembers. As a map: textures already loaded, resolved file path ->
/// Scene::textures index, so that an OBJ instanced twice, or two MTLs naming the same file, share
/// one texture. Besides: the scene's material names (intern_material's index, so that interning
/// M materials costs M log M, not M^2) and directory listings (the case-insensitive texture
/// lookup of docs/obj-quirks.md lists each directory once).
struct TextureCache : std::map<std::string, int> {
    std::map<std::string, int> material_by_name;  ///< Scene::materials name -> index
    std::size_t materials_indexed = 0;            ///< scene.materials[0 .. this) are indexed
    std::map<std::string, std::vector<std::string>> directory_files;  ///< directory -> files
};

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
int intern_material(Scene& scene, const Material& material, const std::string& defined_at,
                    TextureCache& cache);

/// `text` as UTF-8: itself when it is valid UTF-8 (RFC 3629), else read as Latin-1 (every byte
/// one code point: what 8-bit MTL files from Windows tools mostly hold), so that names stay
/// printable and JSON-writable.
std::string utf8_or_latin1(const std::string& text);

/// The index of the scene's material named `name`, or -1 (through cache.material_by_name).
int find_material(const Scene& scene, const std::string& name, TextureCache& cache);

/// A texture from an image file's bytes already in memory (a glTF data: URI or bufferView
/// image), decoded by decode_image_bytes (PNG, JPEG, BMP by their magic bytes; sRGB to linear),
/// then treated exactly as load_texture_file treats a file (RGB, finite, reuse, the scene's
/// pixel limit). `key` identifies the image in the cache ("<file>#images[3]"); `name` becomes
/// Texture::name; `where` prefixes errors.
int load_texture_bytes(Scene& scene, const std::string& bytes, const std::string& name,
                       const std::string& key, TextureCache& cache, const std::string& where);

}  // namespace fovref
