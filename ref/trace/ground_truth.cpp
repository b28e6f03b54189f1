#include "ref/trace/ground_truth.h"

#include "ref/core/halton.h"
#include "ref/trace/raycast_gbuffer.h"

namespace fovref {

Image render_ground_truth(const Scene& scene, const Bvh& bvh, const Camera& camera,
                          std::uint32_t frame, int width, int height, TraceStats& primary_stats,
                          ShadingStats& shading_stats) {
    Image image(width, height, 3);
    const float tan_half = tan_half_vfov(camera);
    const auto points = halton23_points16();
    const std::uint32_t dimensions = shading_dimensions(scene);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const auto pixel = static_cast<std::uint32_t>(y * width + x);
            glm::vec3 sum(0.0f);
            for (int s = 0; s < ground_truth_samples; ++s) {
                const Ray ray = primary_ray(camera, tan_half, width, height,
                                            static_cast<float>(x) + points[s].x,
                                            static_cast<float>(y) + points[s].y);
                const Hit hit = trace_closest(bvh, ray, primary_stats);
                if (!hit.hit()) continue;  // background is black
                const SurfacePoint surface = surface_at(scene, hit.primitive, hit.u, hit.v);
                if (scene.materials[static_cast<std::size_t>(surface.material)].texture >= 0)
                    ++shading_stats.texture_fetches;
                sum += shade_direct(scene, &bvh, surface, camera.position, frame, pixel,
                                    dimensions * static_cast<std::uint32_t>(s), shading_stats);
            }
            const glm::vec3 mean = sum * (1.0f / static_cast<float>(ground_truth_samples));
            for (int c = 0; c < 3; ++c) image.at(x, y, c) = mean[c];
        }
    return image;
}

}  // namespace fovref
