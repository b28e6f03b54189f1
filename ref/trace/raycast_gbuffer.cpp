#include "ref/trace/raycast_gbuffer.h"

namespace fovref {

Hit raycast_sample(GBuffer& g, int x, int y, glm::vec2 p, int screen_width, int screen_height,
                   const PrimaryView& view, RaycastStats& stats) {
    const Ray ray = primary_ray(view.camera, view.tan_half, screen_width, screen_height, p.x, p.y);
    const Hit hit = trace_closest(view.bvh, ray, stats.primary);
    if (!hit.hit()) return hit;  // misses keep the background values
    if (!write_gbuffer_sample(g, x, y, p, screen_width, screen_height, view.scene, view.camera,
                              view.previous_camera, view.previous_tan_half, hit.primitive, hit.u,
                              hit.v))
        ++stats.motion_behind_previous;
    return hit;
}

Hit raycast_window_pixel(GBuffer& g, const ScreenWindow& window, const PrimaryView& view, int x,
                         int y, RaycastStats& stats, Offset2 jitter) {
    // The launch point: the pixel centre (x + 1/2, y + 1/2) unless TAA jitters it.
    const glm::vec2 point{static_cast<float>(x) + jitter.x, static_cast<float>(y) + jitter.y};
    return raycast_sample(g, x - window.x0, y - window.y0, point, window.screen_width,
                          window.screen_height, view, stats);
}

Hit raycast_gbuffer_pixel(GBuffer& g, const PrimaryView& view, int x, int y, RaycastStats& stats,
                          Offset2 jitter) {
    return raycast_window_pixel(g, full_screen(g.view_depth.width, g.view_depth.height), view, x, y,
                                stats, jitter);
}

GBuffer raycast_gbuffer(const PrimaryView& view, int width, int height, RaycastStats& stats,
                        Offset2 jitter) {
    GBuffer g(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) raycast_gbuffer_pixel(g, view, x, y, stats, jitter);
    return g;
}

}  // namespace fovref
