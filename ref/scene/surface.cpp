#include "ref/scene/surface.h"

#include <cmath>

namespace fovref {

SurfacePoint surface_at(const Scene& scene, std::int32_t primitive, float u, float v) {
    const std::size_t base = 3 * static_cast<std::size_t>(primitive);
    const float w = 1.0f - u - v;
    const glm::vec3 p0 = scene.positions[base], p1 = scene.positions[base + 1],
                    p2 = scene.positions[base + 2];
    SurfacePoint s;
    s.material = scene.material_ids[static_cast<std::size_t>(primitive)];
    // Interpolate with the corner weights in a fixed order: w p0 + u p1 + v p2.
    s.position = p0 * w + p1 * u + p2 * v;
    glm::vec3 n =
        scene.normals[base] * w + scene.normals[base + 1] * u + scene.normals[base + 2] * v;
    float length = std::sqrt(glm::dot(n, n));
    glm::vec3 g = glm::cross(p1 - p0, p2 - p0);
    const float g_length = std::sqrt(glm::dot(g, g));
    s.geometric_normal = g_length > 0.0f ? g / g_length : glm::vec3(0.0f);
    // Opposite vertex normals can cancel: fall back to the geometric normal.
    s.shading_normal = length > 0.0f ? n / length : s.geometric_normal;
    s.uv = scene.uvs[base] * w + scene.uvs[base + 1] * u + scene.uvs[base + 2] * v;
    const Material& material = scene.materials[static_cast<std::size_t>(s.material)];
    s.albedo = material.albedo;
    if (material.texture >= 0)
        s.albedo *= sample_texture_bilinear(
            scene.textures[static_cast<std::size_t>(material.texture)], s.uv);
    return s;
}

}  // namespace fovref
