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

/// The primary view of a frame, what every primary-ray pass takes together: the scene and its
/// BVH the rays are traced against, the frame's camera they start from, the previous frame's
/// camera the motion vectors are measured with, and both cameras' tan(vfov / 2) (made once).
struct PrimaryView {
    const Scene& scene;
    const Bvh& bvh;
    const Camera& camera;
    const Camera& previous_camera;
    float tan_half = 0.0f;           ///< tan_half_vfov(camera)
    float previous_tan_half = 0.0f;  ///< tan_half_vfov(previous_camera)
    PrimaryView(const Scene& s, const Bvh& b, const Camera& current, const Camera& previous)
        : scene(s),
          bvh(b),
          camera(current),
          previous_camera(previous),
          tan_half(tan_half_vfov(current)),
          previous_tan_half(tan_half_vfov(previous)) {}
};

/// What the ray-cast G-buffer pass did (the counterpart of the rasterizer's RasterStats; the
/// pass adds to it).
struct RaycastStats {
    TraceStats primary;                       ///< traversal work of the primary rays
    std::int64_t motion_behind_previous = 0;  ///< hit pixels behind the previous camera (motion 0)
};

/// What every primary-ray pass does per sample: the primary ray through screen point p of a
/// screen_width x screen_height screen, its closest hit, and texel (x, y) of `gbuffer` written
/// from it (write_gbuffer_sample: its motion relative to p; a miss keeps the background).
/// Returns the hit.
Hit raycast_sample(GBuffer& gbuffer, int x, int y, glm::vec2 p, int screen_width, int screen_height,
                   const PrimaryView& view, RaycastStats& stats);

/// `jitter` (TAA, SPEC §7): the ray goes through (x + o_x, y + o_y) instead of the centre
/// (x + 1/2, y + 1/2), the default.
///
/// Per-pixel work of raycast_gbuffer: the primary ray through the centre of pixel (x, y), its
/// closest hit, and the G-buffer pixel written from it (write_gbuffer_pixel; a miss keeps the
/// background). Returns the hit.
Hit raycast_gbuffer_pixel(GBuffer& gbuffer, const PrimaryView& view, int x, int y,
                          RaycastStats& stats, Offset2 jitter = {});

/// raycast_gbuffer_pixel for a G-buffer that covers `window` of the screen: the ray through the
/// centre of screen pixel (x, y), written at buffer pixel (x - x0, y - y0). With
/// full_screen(W, H) this is raycast_gbuffer_pixel, which calls it.
Hit raycast_window_pixel(GBuffer& gbuffer, const ScreenWindow& window, const PrimaryView& view,
                         int x, int y, RaycastStats& stats, Offset2 jitter = {});

/// Primary rays through every pixel centre (t in (0, inf)); motion against `previous_camera`.
GBuffer raycast_gbuffer(const PrimaryView& view, int width, int height, RaycastStats& stats,
                        Offset2 jitter = {});

}  // namespace fovref
