#include "ref/scene/scene.h"

#include <cmath>
#include <string>

#include "ref/core/error.h"
#include "ref/core/vec.h"

namespace fovref {

float triangle_double_area(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    return glm::length(glm::cross(b - a, c - a));
}

Bounds scene_bounds(const Scene& scene) {
    Bounds bounds;
    if (scene.positions.empty()) return bounds;
    bounds.min = bounds.max = scene.positions[0];
    for (const glm::vec3& p : scene.positions) {
        bounds.min = glm::min(bounds.min, p);
        bounds.max = glm::max(bounds.max, p);
    }
    return bounds;
}

void finalize_scene(Scene& scene) {
    const std::size_t triangles = scene.material_ids.size();
    // Check the invariants every stage relies on.
    if (scene.positions.size() != 3 * triangles || scene.normals.size() != 3 * triangles ||
        scene.uvs.size() != 3 * triangles)
        throw Error(scene.source + ": inconsistent triangle arrays: " + std::to_string(triangles) +
                    " triangles, " + std::to_string(scene.positions.size()) + " positions, " +
                    std::to_string(scene.normals.size()) + " normals, " +
                    std::to_string(scene.uvs.size()) + " uvs");
    for (std::size_t t = 0; t < triangles; ++t) {
        const std::int32_t m = scene.material_ids[t];
        if (m < 0 || static_cast<std::size_t>(m) >= scene.materials.size())
            throw Error(scene.source + ": triangle " + std::to_string(t) + " has material " +
                        std::to_string(m) + ", but the scene has " +
                        std::to_string(scene.materials.size()) + " materials");
        for (int k = 0; k < 3; ++k) {
            if (!is_finite(scene.positions[3 * t + k]) || !is_finite(scene.normals[3 * t + k]))
                throw Error(scene.source + ": triangle " + std::to_string(t) +
                            " has a non-finite position or normal");
        }
    }
    for (const Material& material : scene.materials) {
        if (material.texture < -1 || material.texture >= static_cast<int>(scene.textures.size()))
            throw Error(scene.source + ": material '" + material.name + "' has texture index " +
                        std::to_string(material.texture) + " out of range");
        if (!is_finite(material.albedo) || !is_finite(material.emission) ||
            !is_finite(material.specular) || !std::isfinite(material.roughness))
            throw Error(scene.source + ": material '" + material.name + "' has a non-finite value");
    }
    for (const Texture& texture : scene.textures)
        if (texture.image.channels != 3 || texture.image.empty())
            throw Error(scene.source + ": texture '" + texture.name + "' is empty or not RGB");

    // Emissive triangles become triangle lights, in triangle order (after the explicit lights).
    for (std::size_t t = 0; t < triangles; ++t) {
        const Material& material = scene.materials[scene.material_ids[t]];
        if (material.emission.x > 0.0f || material.emission.y > 0.0f ||
            material.emission.z > 0.0f) {
            Light light;
            light.type = Light::Type::triangle;
            light.position = scene.positions[3 * t];
            light.edge_u = scene.positions[3 * t + 1] - scene.positions[3 * t];
            light.edge_v = scene.positions[3 * t + 2] - scene.positions[3 * t];
            light.intensity = material.emission;
            light.primitive = static_cast<int>(t);
            scene.lights.push_back(light);
        }
    }
    Bounds bounds = scene_bounds(scene);
    float diagonal = glm::length(bounds.max - bounds.min);
    scene.scene_scale = diagonal > 0.0f ? diagonal : 1.0f;
}

Camera camera_at(const Scene& scene, float time) {
    const std::vector<CameraKey>& path = scene.camera_path;
    if (path.empty()) return scene.camera;
    auto make = [&](glm::vec3 position, glm::quat orientation) {
        return camera_from_quat(position, orientation, scene.camera.vfov_deg);
    };
    if (!(time > path.front().time)) return make(path.front().position, path.front().orientation);
    if (!(time < path.back().time)) return make(path.back().position, path.back().orientation);
    std::size_t k = 1;
    while (path[k].time < time) ++k;  // path times are strictly increasing (checked on load)
    if (path[k].time == time) return make(path[k].position, path[k].orientation);  // exact at keys
    const CameraKey& a = path[k - 1];
    const CameraKey& b = path[k];
    float t = (time - a.time) / (b.time - a.time);
    glm::vec3 position = a.position + (b.position - a.position) * t;
    return make(position, slerp_deterministic(a.orientation, b.orientation, t));
}

const char* light_type_name(Light::Type type) {
    switch (type) {
        case Light::Type::point: return "point";
        case Light::Type::quad: return "quad";
        case Light::Type::triangle: return "triangle";
    }
    return "?";
}

BilinearTaps bilinear_taps(const Texture& texture, glm::vec2 uv) {
    const Image& image = texture.image;
    BilinearTaps taps;
    // Texel centres at (i + 0.5) / W; v = 0 is the bottom row (the image's last row).
    const float x = uv.x * static_cast<float>(image.width) - 0.5f;
    const float y = (1.0f - uv.y) * static_cast<float>(image.height) - 0.5f;
    if (!std::isfinite(x) || !std::isfinite(y)) return taps;
    const float fx = std::floor(x);
    const float fy = std::floor(y);
    taps.tx = x - fx;
    taps.ty = y - fy;
    auto wrap = [](float i, int n) {
        // i is integral. Below 2^31 in magnitude the binary64 reduction below is exact (i / n is
        // at least 1 / |i| > 2^-31 away from an integer, so its floor is exact, and so is the
        // rest), the same as the integer remainder taken into [0, n); beyond, it avoids int
        // overflow for huge uvs.
        if (i > -0x1p31f && i < 0x1p31f) {
            const int k = static_cast<int>(i) % n;
            return k < 0 ? k + n : k;
        }
        double r = static_cast<double>(i) - std::floor(static_cast<double>(i) / n) * n;
        int k = static_cast<int>(r);
        return k >= n ? k - n : (k < 0 ? k + n : k);
    };
    taps.x0 = wrap(fx, image.width);
    taps.x1 = wrap(fx + 1.0f, image.width);
    taps.y0 = wrap(fy, image.height);
    taps.y1 = wrap(fy + 1.0f, image.height);
    taps.valid = true;
    return taps;
}

glm::vec3 sample_texture_bilinear(const Texture& texture, glm::vec2 uv, BilinearTrace* trace) {
    const BilinearTaps t = bilinear_taps(texture, uv);
    if (trace) trace->taps = t;
    if (!t.valid) return glm::vec3(0.0f);
    const Image& image = texture.image;
    glm::vec3 result(0.0f);
    for (int c = 0; c < 3; ++c) {
        float top = image.at(t.x0, t.y0, c) * (1.0f - t.tx) + image.at(t.x1, t.y0, c) * t.tx;
        float bottom = image.at(t.x0, t.y1, c) * (1.0f - t.tx) + image.at(t.x1, t.y1, c) * t.tx;
        result[c] = top * (1.0f - t.ty) + bottom * t.ty;
        if (trace) {
            trace->texels[0][c] = image.at(t.x0, t.y0, c);
            trace->texels[1][c] = image.at(t.x1, t.y0, c);
            trace->texels[2][c] = image.at(t.x0, t.y1, c);
            trace->texels[3][c] = image.at(t.x1, t.y1, c);
            trace->top[c] = top;
            trace->bottom[c] = bottom;
        }
    }
    return result;
}

}  // namespace fovref
