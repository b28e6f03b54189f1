#include "ref/building_blocks/building_blocks.h"

#include <cmath>
#include <limits>

#include "ref/core/error.h"
#include "ref/core/halton.h"
#include "ref/core/rng.h"
#include "ref/core/vec.h"

namespace fovref {

Image camera_rays(const Camera& camera, int width, int height) {
    Image rays(width, height, 3);
    const float tan_half = tan_half_vfov(camera);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const glm::vec2 centre = pixel_centre(x, y);
            const glm::vec3 d =
                primary_ray_direction(camera, tan_half, width, height, centre.x, centre.y);
            for (int c = 0; c < 3; ++c) rays.at(x, y, c) = d[c];
        }
    return rays;
}

Image rng_image(std::uint32_t frame, int width, int height) {
    Image image(width, height, 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const auto pixel = static_cast<std::uint32_t>(y * width + x);
            for (int d = 0; d < 3; ++d)
                image.at(x, y, d) = rand_unit(frame, pixel, static_cast<std::uint32_t>(d));
        }
    return image;
}

Image halton_image(bool scaled) {
    const auto points = scaled ? halton23_offsets16() : halton23_points16();
    Image image(16, 1, 2);
    for (int i = 0; i < 16; ++i) {
        image.at(i, 0, 0) = points[i].x;
        image.at(i, 0, 1) = points[i].y;
    }
    return image;
}

SplatBuffers centroid_splat(const Scene& scene, const Camera& camera, int width, int height) {
    SplatBuffers out;
    out.depth = Image(width, height, 1, 0.0f);
    out.primitive = Image(width, height, 1, -1.0f);
    out.normal = Image(width, height, 3, 0.0f);
    out.albedo = Image(width, height, 3, 0.0f);
    const float tan_half = tan_half_vfov(camera);
    const float near = 1e-4f * scene.scene_scale;
    for (std::size_t t = 0; t < scene.triangle_count(); ++t) {
        const glm::vec3 a = scene.positions[3 * t], b = scene.positions[3 * t + 1],
                        c = scene.positions[3 * t + 2];
        const glm::vec3 centroid = (a + b + c) / 3.0f;
        glm::vec2 screen;
        float z = 0.0f;
        if (!project_to_screen(camera, tan_half, width, height, centroid, screen, z) ||
            !(z > near)) {
            ++out.behind;
            continue;
        }
        const float sx = screen.x, sy = screen.y;
        if (!(sx >= 0.0f && sx < static_cast<float>(width) && sy >= 0.0f &&
              sy < static_cast<float>(height))) {
            ++out.off_screen;
            continue;
        }
        const int px = static_cast<int>(sx), py = static_cast<int>(sy);
        ++out.splatted;
        // Nearest wins; triangles arrive in index order, so a strict '<' keeps the lowest id.
        const float current = out.depth.at(px, py);
        if (out.primitive.at(px, py) >= 0.0f && !(z < current)) continue;
        out.depth.at(px, py) = z;
        out.primitive.at(px, py) = static_cast<float>(t);
        glm::vec3 n = glm::cross(b - a, c - a);
        n /= std::sqrt(glm::dot(n, n));
        const Material& material = scene.materials[scene.material_ids[t]];
        glm::vec3 albedo = material.albedo;
        if (material.texture >= 0) {
            const glm::vec2 uv =
                (scene.uvs[3 * t] + scene.uvs[3 * t + 1] + scene.uvs[3 * t + 2]) / 3.0f;
            albedo *= sample_texture_bilinear(scene.textures[material.texture], uv);
        }
        for (int k = 0; k < 3; ++k) {
            out.normal.at(px, py, k) = n[k];
            out.albedo.at(px, py, k) = albedo[k];
        }
    }
    return out;
}

Image headlight_shade(const Image& albedo, const Image& normal, const Image& primitive,
                      const Camera& camera) {
    Image out(albedo.width, albedo.height, 3, 0.0f);
    for (int y = 0; y < albedo.height; ++y)
        for (int x = 0; x < albedo.width; ++x) {
            if (primitive.at(x, y) < 0.0f) continue;
            const glm::vec3 n(normal.at(x, y, 0), normal.at(x, y, 1), normal.at(x, y, 2));
            const float light = 0.2f + 0.8f * std::fabs(glm::dot(n, camera.forward));
            for (int c = 0; c < 3; ++c) out.at(x, y, c) = albedo.at(x, y, c) * light;
        }
    return out;
}

GeometryBuffers scene_geometry(const Scene& scene) {
    // One row per triangle: a scene without triangles has no rows, and a 0-row buffer can be
    // written in no image format: said here, not by a writer deep inside the bundle code.
    if (scene.triangle_count() == 0)
        throw Error("mode geometry: scene '" + scene.name +
                    "' has no triangles, so there are no rows to write (every triangle is one "
                    "row of the geometry buffers)");
    if (scene.triangle_count() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
        throw Error("mode geometry: scene '" + scene.name + "' has too many triangles");
    const int triangles = static_cast<int>(scene.triangle_count());
    GeometryBuffers out;
    out.positions = Image(3, triangles, 3);
    out.normals = Image(3, triangles, 3);
    out.uvs = Image(3, triangles, 2);
    out.material_ids = Image(1, triangles, 1);
    for (int t = 0; t < triangles; ++t) {
        for (int k = 0; k < 3; ++k) {
            const std::size_t corner = 3 * static_cast<std::size_t>(t) + k;
            for (int c = 0; c < 3; ++c) {
                out.positions.at(k, t, c) = scene.positions[corner][c];
                out.normals.at(k, t, c) = scene.normals[corner][c];
            }
            out.uvs.at(k, t, 0) = scene.uvs[corner].x;
            out.uvs.at(k, t, 1) = scene.uvs[corner].y;
        }
        out.material_ids.at(0, t) = static_cast<float>(scene.material_ids[t]);
    }
    return out;
}

}  // namespace fovref
