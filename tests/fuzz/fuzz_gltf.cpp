// libFuzzer target: glTF 2.0 (load_gltf_into). An input that starts with "glTF" is a .glb file;
// any other input is a .gltf JSON text, optionally followed by the line "#--bin--" and the bytes
// of buffer.bin (which the JSON may name as a buffer's uri). tex.png, a valid 2x2 PNG, exists
// for an image uri. A load that succeeds is run twice and must give the same scene, bit for bit.
// tests/fuzz/fuzz_util.h.
#include <cstring>

#include "ref/image/image_io.h"
#include "ref/scene/gltf_loader.h"
#include "tests/fuzz/fuzz_util.h"

namespace {

fovref::Scene load_once(const std::string& path, fovref::GltfContents& contents) {
    fovref::Scene scene;
    fovref::TextureCache cache;
    contents = fovref::load_gltf_into(scene, path, glm::mat4(1.0f), cache, "");
    return scene;
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const bool fixtures = [] {
        fovref::Image image(2, 2, 3);
        for (std::size_t i = 0; i < image.data.size(); ++i)
            image.data[i] = static_cast<float>(i) / 11.0f;
        fovref::fuzz::write("tex.png", fovref::encode_png(image, "tex.png"));
        return true;
    }();
    (void)fixtures;
    const std::string input(reinterpret_cast<const char*>(data), size);
    std::string path;
    if (input.compare(0, 4, "glTF") == 0) {
        path = fovref::fuzz::write("scene.glb", input);
    } else {
        const std::string separator = "\n#--bin--\n";
        const std::size_t split = input.find(separator);
        path = fovref::fuzz::write("scene.gltf", input.substr(0, split));
        fovref::fuzz::write("buffer.bin", split == std::string::npos
                                              ? std::string()
                                              : input.substr(split + separator.size()));
    }
    fovref::fuzz::expect_error_or_success([&] {
        fovref::GltfContents first_contents, second_contents;
        const fovref::Scene first = load_once(path, first_contents);
        const fovref::Scene second = load_once(path, second_contents);
        bool same = same_bits(first.positions, second.positions) &&
                    same_bits(first.normals, second.normals) && same_bits(first.uvs, second.uvs) &&
                    first.material_ids == second.material_ids &&
                    first.textures.size() == second.textures.size() &&
                    first.lights.size() == second.lights.size() &&
                    first_contents.unsupported == second_contents.unsupported &&
                    first.load_stats.warnings == second.load_stats.warnings;
        if (!same) {
            std::fprintf(stderr, "fuzz: glTF gave different results for the same input\n");
            std::abort();
        }
        for (std::size_t t = 0; t < first.textures.size(); ++t)
            fovref::fuzz::require_same(first.textures[t].image, second.textures[t].image,
                                       "glTF texture");
    });
    return 0;
}
