#include "ref/trace/raycast_gbuffer.h"

namespace fovref {

Hit raycast_window_pixel(GBuffer& g, const ScreenWindow& window, const Scene& scene, const Bvh& bvh,
                         const Camera& camera, float tan_half, const Camera& previous_camera,
                         float previous_tan_half, int x, int y, RaycastStats& stats,
                         Offset2 jitter) {
    // The launch point: the pixel centre (x + 1/2, y + 1/2) unless TAA jitters it.
    const glm::vec2 point{static_cast<float>(x) + jitter.x, static_cast<float>(y) + jitter.y};
    const Ray ray =
        primary_ray(camera, tan_half, window.screen_width, window.screen_height, point.x, point.y);
    const Hit hit = trace_closest(bvh, ray, stats.primary);
    if (!hit.hit()) return hit;  // misses keep the background values
    if (!write_gbuffer_sample(g, x - window.x0, y - window.y0, point, window.screen_width,
                              window.screen_height, scene, camera, previous_camera,
                              previous_tan_half, hit.primitive, hit.u, hit.v))
        ++stats.motion_behind_previous;
    return hit;
}

Hit raycast_gbuffer_pixel(GBuffer& g, const Scene& scene, const Bvh& bvh, const Camera& camera,
                          float tan_half, const Camera& previous_camera, float previous_tan_half,
                          int x, int y, RaycastStats& stats, Offset2 jitter) {
    return raycast_window_pixel(g, full_screen(g.view_depth.width, g.view_depth.height), scene, bvh,
                                camera, tan_half, previous_camera, previous_tan_half, x, y, stats,
                                jitter);
}

GBuffer raycast_gbuffer(const Scene& scene, const Bvh& bvh, const Camera& camera,
                        const Camera& previous_camera, int width, int height, RaycastStats& stats,
                        Offset2 jitter) {
    GBuffer g(width, height);
    const float tan_half = tan_half_vfov(camera);
    const float previous_tan_half = tan_half_vfov(previous_camera);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            raycast_gbuffer_pixel(g, scene, bvh, camera, tan_half, previous_camera,
                                  previous_tan_half, x, y, stats, jitter);
    return g;
}

}  // namespace fovref
