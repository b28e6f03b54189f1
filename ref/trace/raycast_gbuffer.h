// The G-buffer by ray casting (SPEC §4 channels; Lund §3.1's basic ray tracer's primary rays):
// one ray through each pixel centre, closest hit, attributes from surface_at, exactly as the
// rasterizer computes them from its perspective-correct barycentrics.
#pragma once

#include "ref/bvh/bvh.h"
#include "ref/raster/gbuffer.h"
#include "ref/scene/scene.h"

namespace fovref {

/// Fills the G-buffer pixel (x, y) from a closest hit of the ray from `camera` (background when
/// `hit` is a miss). Shared by every primary-ray pass.
void write_gbuffer_pixel(GBuffer& gbuffer, int x, int y, const Scene& scene, const Camera& camera,
                         const Camera& previous_camera, float previous_tan_half, const Hit& hit);

/// Primary rays through every pixel centre (t in (0, inf)).
GBuffer raycast_gbuffer(const Scene& scene, const Bvh& bvh, const Camera& camera,
                        const Camera& previous_camera, int width, int height, TraceStats& stats);

}  // namespace fovref
