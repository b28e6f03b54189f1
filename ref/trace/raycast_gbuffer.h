// The G-buffer by ray casting (SPEC §4 channels; Lund §3.1's basic ray tracer's primary rays):
// one ray through each pixel centre, closest hit, attributes from surface_at, exactly as the
// rasterizer computes them from its perspective-correct barycentrics.
#pragma once

#include "ref/bvh/bvh.h"
#include "ref/core/halton.h"
#include "ref/raster/gbuffer.h"
#include "ref/scene/scene.h"

namespace fovref {

/// The primary ray through screen point (x, y) (SPEC §1): from the camera, t in (0, inf).
inline Ray primary_ray(const Camera& camera, float tan_half, int width, int height, float x,
                       float y) {
    Ray ray;
    ray.origin = camera.position;
    ray.direction = primary_ray_direction(camera, tan_half, width, height, x, y);
    return ray;
}

/// The primary ray through the centre (x + 0.5, y + 0.5) of pixel (x, y).
inline Ray pixel_centre_ray(const Camera& camera, float tan_half, int width, int height, int x,
                            int y) {
    return primary_ray(camera, tan_half, width, height, static_cast<float>(x) + 0.5f,
                       static_cast<float>(y) + 0.5f);
}

/// What the ray-cast G-buffer pass did (the counterpart of the rasterizer's RasterStats; the
/// pass adds to it).
struct RaycastStats {
    TraceStats primary;                       ///< traversal work of the primary rays
    std::int64_t motion_behind_previous = 0;  ///< hit pixels behind the previous camera (motion 0)
};

/// `jitter` (TAA, SPEC §7): the ray goes through (x + o_x, y + o_y) instead of the centre
/// (x + 1/2, y + 1/2), the default.
///
/// Per-pixel work of raycast_gbuffer: the primary ray through the centre of pixel (x, y), its
/// closest hit, and the G-buffer pixel written from it (write_gbuffer_pixel; a miss keeps the
/// background). Returns the hit.
Hit raycast_gbuffer_pixel(GBuffer& gbuffer, const Scene& scene, const Bvh& bvh,
                          const Camera& camera, float tan_half, const Camera& previous_camera,
                          float previous_tan_half, int x, int y, RaycastStats& stats,
                          Offset2 jitter = {});

/// raycast_gbuffer_pixel for a G-buffer that covers `window` of the screen: the ray through the
/// centre of screen pixel (x, y), written at buffer pixel (x - x0, y - y0). With
/// full_screen(W, H) this is raycast_gbuffer_pixel, which calls it.
Hit raycast_window_pixel(GBuffer& gbuffer, const ScreenWindow& window, const Scene& scene,
                         const Bvh& bvh, const Camera& camera, float tan_half,
                         const Camera& previous_camera, float previous_tan_half, int x, int y,
                         RaycastStats& stats, Offset2 jitter = {});

/// Primary rays through every pixel centre (t in (0, inf)); motion against `previous_camera`.
GBuffer raycast_gbuffer(const Scene& scene, const Bvh& bvh, const Camera& camera,
                        const Camera& previous_camera, int width, int height, RaycastStats& stats,
                        Offset2 jitter = {});

}  // namespace fovref
