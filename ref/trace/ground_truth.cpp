#include "ref/trace/ground_truth.h"

#include "ref/core/halton.h"
#include "ref/trace/raycast_gbuffer.h"

namespace fovref {

glm::vec3 ground_truth_pixel(const Scene& scene, const Bvh& bvh, const Camera& camera,
                             float tan_half, std::uint32_t frame, int width, int height, int x,
                             int y, TraceStats& primary_stats, ShadingStats& shading_stats,
                             std::vector<GroundTruthSample>* trace) {
    const auto points = halton23_points16();
    const std::uint32_t dimensions = shading_dimensions(scene);
    const auto pixel = static_cast<std::uint32_t>(y * width + x);
    glm::vec3 sum(0.0f);
    for (int s = 0; s < ground_truth_samples; ++s) {
        const Ray ray =
            primary_ray(camera, tan_half, width, height, static_cast<float>(x) + points[s].x,
                        static_cast<float>(y) + points[s].y);
        const Hit hit = trace_closest(bvh, ray, primary_stats);
        glm::vec3 radiance(0.0f);  // background is black
        if (hit.hit()) {
            const SurfacePoint surface = surface_at(scene, hit.primitive, hit.u, hit.v);
            if (scene.materials[static_cast<std::size_t>(surface.material)].texture >= 0)
                ++shading_stats.texture_fetches;
            radiance = shade_direct(scene, &bvh, surface, camera.position, frame, pixel,
                                    dimensions * static_cast<std::uint32_t>(s), shading_stats);
            sum += radiance;
        }
        if (trace)
            trace->push_back(
                {glm::vec2(points[s].x, points[s].y), ray.direction, hit, radiance, sum});
    }
    return sum * (1.0f / static_cast<float>(ground_truth_samples));
}

Image render_ground_truth(const Scene& scene, const Bvh& bvh, const Camera& camera,
                          std::uint32_t frame, int width, int height, TraceStats& primary_stats,
                          ShadingStats& shading_stats) {
    Image image(width, height, 3);
    const float tan_half = tan_half_vfov(camera);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const glm::vec3 mean = ground_truth_pixel(scene, bvh, camera, tan_half, frame, width,
                                                      height, x, y, primary_stats, shading_stats);
            for (int c = 0; c < 3; ++c) image.at(x, y, c) = mean[c];
        }
    return image;
}

}  // namespace fovref
