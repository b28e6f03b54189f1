#include "ref/trace/raycast_gbuffer.h"

namespace fovref {

Hit raycast_window_pixel(GBuffer& g, const ScreenWindow& window, const Scene& scene, const Bvh& bvh,
                         const Camera& camera, float tan_half, const Camera& previous_camera,
                         float previous_tan_half, int x, int y, RaycastStats& stats) {
    const Ray ray =
        pixel_centre_ray(camera, tan_half, window.screen_width, window.screen_height, x, y);
    const Hit hit = trace_closest(bvh, ray, stats.primary);
    if (!hit.hit()) return hit;  // misses keep the background values
    const glm::vec2 centre{static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f};
    if (!write_gbuffer_sample(g, x - window.x0, y - window.y0, centre, window.screen_width,
                              window.screen_height, scene, camera, previous_camera,
                              previous_tan_half, hit.primitive, hit.u, hit.v))
        ++stats.motion_behind_previous;
    return hit;
}

Hit raycast_gbuffer_pixel(GBuffer& g, const Scene& scene, const Bvh& bvh, const Camera& camera,
                          float tan_half, const Camera& previous_camera, float previous_tan_half,
                          int x, int y, RaycastStats& stats) {
    return raycast_window_pixel(g, full_screen(g.view_depth.width, g.view_depth.height), scene, bvh,
                                camera, tan_half, previous_camera, previous_tan_half, x, y, stats);
}

GBuffer raycast_gbuffer(const Scene& scene, const Bvh& bvh, const Camera& camera,
                        const Camera& previous_camera, int width, int height, RaycastStats& stats) {
    GBuffer g(width, height);
    const float tan_half = tan_half_vfov(camera);
    const float previous_tan_half = tan_half_vfov(previous_camera);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            raycast_gbuffer_pixel(g, scene, bvh, camera, tan_half, previous_camera,
                                  previous_tan_half, x, y, stats);
    return g;
}

}  // namespace fovref
