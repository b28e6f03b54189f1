// Texture files for scenes (SPEC §2): read with fovref's image reader, converted to linear RGB.
#include <cmath>
#include <filesystem>
#include <string>

#include "ref/core/error.h"
#include "ref/core/limits.h"
#include "ref/image/image_io.h"
#include "ref/scene/obj_loader.h"

namespace fovref {

namespace {

// Grey -> RGB (replicated), grey+alpha -> RGB, RGBA -> RGB (alpha dropped).
Image to_rgb(const Image& image, const std::string& where) {
    if (image.channels == 3) return image;
    if (image.channels < 1 || image.channels > 4)
        throw Error(where + ": texture has " + std::to_string(image.channels) + " channels");
    Image rgb(image.width, image.height, 3);
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            for (int c = 0; c < 3; ++c)
                rgb.at(x, y, c) = image.at(x, y, image.channels >= 3 ? c : 0);
    return rgb;
}

// The shared tail of load_texture_file and load_texture_bytes: to RGB, every value finite,
// reuse of an equal texture, the scene's texture pixel limit; records `key` in the cache.
int add_texture(Scene& scene, Texture texture, const std::string& key, TextureCache& cache,
                const std::string& where) {
    const std::string& name = texture.name;
    texture.image = to_rgb(texture.image, where);
    if (texture.image.empty()) throw Error(where + ": texture '" + name + "' is empty");
    for (std::size_t i = 0; i < texture.image.data.size(); ++i)
        if (!std::isfinite(texture.image.data[i])) {
            const std::size_t pixel = i / 3;
            throw Error(
                where + ": texture '" + name + "' has a NaN or infinite value at pixel (" +
                std::to_string(pixel % static_cast<std::size_t>(texture.image.width)) + ", " +
                std::to_string(pixel / static_cast<std::size_t>(texture.image.width)) + ")");
        }

    // A texture with the same name and bits (an OBJ loaded twice through load_obj_into without a
    // shared cache) is reused, so that materials that name it stay equal.
    int index = -1;
    for (std::size_t t = 0; t < scene.textures.size(); ++t)
        if (scene.textures[t].name == texture.name &&
            bit_equal(scene.textures[t].image, texture.image)) {
            index = static_cast<int>(t);
            break;
        }
    if (index < 0) {
        // Every texture of the scene together: bounded memory for a scene that names many
        // (or huge) textures.
        std::uint64_t total = texture.image.pixel_count();
        for (const Texture& t : scene.textures) total += t.image.pixel_count();
        check_limit(where + ": textures of the scene", total,
                    input_limits().max_scene_texture_pixels, "pixels", "FOVREF_MAX_SCENE_PIXELS");
        index = static_cast<int>(scene.textures.size());
        scene.textures.push_back(std::move(texture));
    }
    cache[key] = index;
    return index;
}

}  // namespace

int load_texture_file(Scene& scene, const std::string& path, const std::string& name,
                      TextureCache& cache, const std::string& referenced_at) {
    const std::string where = referenced_at.empty() ? path : referenced_at;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw Error(where + ": texture '" + name + "' not found (looked for " + path + ")");
    const std::string key = std::filesystem::weakly_canonical(path, ec).string();
    auto cached = cache.find(key);
    if (cached != cache.end()) return cached->second;

    // Read: 8-bit PNG, JPEG and BMP are sRGB-encoded; PFM (what export_scene writes) and EXR
    // hold linear floats. A .jpg/.jpeg/.bmp file is decoded by its magic bytes
    // (decode_image_bytes), so a PNG saved under a .jpg name still loads.
    Texture texture;
    texture.name = name;
    const std::string ext = lower_extension(path);
    try {
        if (ext == ".png") {
            texture.image = read_png(path, /*srgb_decode=*/true);
        } else if (ext == ".jpg" || ext == ".jpeg" || ext == ".bmp") {
            texture.image = decode_image_bytes(read_file(path), path, /*srgb_decode=*/true);
        } else if (ext == ".pfm") {
            texture.image = read_pfm(path);
        } else if (ext == ".exr") {
            texture.image = read_exr(path);
        } else {
            throw Error(path + ": unsupported texture format '" + ext +
                        "' (use .png, .jpg, .jpeg, .bmp, .pfm or .exr)");
        }
    } catch (const Error& e) {
        throw Error(where + ": cannot read texture '" + name + "': " + e.what());
    }
    return add_texture(scene, std::move(texture), key, cache, where);
}

int load_texture_bytes(Scene& scene, const std::string& bytes, const std::string& name,
                       const std::string& key, TextureCache& cache, const std::string& where) {
    auto cached = cache.find(key);
    if (cached != cache.end()) return cached->second;
    Texture texture;
    texture.name = name;
    try {
        texture.image = decode_image_bytes(bytes, name, /*srgb_decode=*/true);
    } catch (const Error& e) {
        throw Error(where + ": cannot read texture '" + name + "': " + e.what());
    }
    return add_texture(scene, std::move(texture), key, cache, where);
}

}  // namespace fovref
