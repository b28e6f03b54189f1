#include "ref/trace/shade_basic.h"

#include <cmath>

namespace fovref {

bool gbuffer_surface(const Scene& scene, const ShadeInputs& in, int x, int y, SurfacePoint& surface,
                     ShadingStats& stats) {
    // SPEC §0: NaN/Inf in an input buffer is replaced by 0 and counted.
    auto read = [&stats](const Image& image, int px, int py, int c) {
        const float v = image.at(px, py, c);
        if (std::isfinite(v)) return v;
        ++stats.nonfinite_inputs;
        return 0.0f;
    };
    const float id = read(in.primitive_id, x, y, 0);
    const float material_id = read(in.material_id, x, y, 0);
    if (id < 0.0f) return false;  // background
    // An id that is not a valid material index is treated as background.
    const auto material_count = static_cast<float>(scene.materials.size());
    if (!(material_id >= 0.0f && material_id < material_count) ||
        material_id != std::floor(material_id)) {
        ++stats.invalid_material_ids;
        return false;
    }
    for (int c = 0; c < 3; ++c) {
        surface.position[c] = read(in.position, x, y, c);
        surface.shading_normal[c] = read(in.shading_normal, x, y, c);
        surface.geometric_normal[c] = read(in.geometric_normal, x, y, c);
        surface.albedo[c] = read(in.albedo, x, y, c);
    }
    surface.material = static_cast<std::int32_t>(material_id);
    return true;
}

glm::vec3 shade_basic_pixel(const Scene& scene, const Bvh* bvh, const ShadeInputs& in,
                            const Camera& camera, int frame, int x, int y, ShadingStats& stats,
                            std::vector<LightSampleRecord>* record) {
    SurfacePoint surface;
    if (!gbuffer_surface(scene, in, x, y, surface, stats)) return glm::vec3(0.0f);
    return shade_direct(scene, bvh, surface, camera.position, static_cast<std::uint32_t>(frame),
                        shade_pixel_index(in, x, y), 0, stats, record);
}

Image shade_basic(const Scene& scene, const Bvh* bvh, const ShadeInputs& in, const Camera& camera,
                  int frame, ShadingStats& stats) {
    Image out(in.position.width, in.position.height, 3, 0.0f);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            const glm::vec3 l = shade_basic_pixel(scene, bvh, in, camera, frame, x, y, stats);
            for (int c = 0; c < 3; ++c) out.at(x, y, c) = l[c];
        }
    return out;
}

Image shade_stereo(const Scene& scene, const Bvh* bvh, const ShadeInputs& inputs,
                   const std::array<Camera, 2>& cameras, int eye_buffer_width, int frame,
                   ShadingStats& stats) {
    const int width = inputs.position.width, height = inputs.position.height;
    Image out(width, height, 3, 0.0f);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const Camera& camera = cameras[static_cast<std::size_t>(x / eye_buffer_width)];
            const glm::vec3 l = shade_basic_pixel(scene, bvh, inputs, camera, frame, x, y, stats);
            for (int c = 0; c < 3; ++c) out.at(x, y, c) = l[c];
        }
    return out;
}

}  // namespace fovref
