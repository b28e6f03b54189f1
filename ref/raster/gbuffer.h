// The G-buffer (SPEC §4), produced by the rasterizer (ref/raster/rasterizer.h) and by the ray
// caster (ref/trace/raycast_gbuffer.h) from the same per-hit attribute code (surface.h), so the
// two can be cross-checked pixel by pixel.
#pragma once

#include <string>
#include <vector>

#include "ref/image/image.h"
#include "ref/stage/frame.h"

namespace fovref {

struct GBuffer {
    Image view_depth;        ///< 1: depth along F (SPEC §1); 0 on background
    Image hit_distance;      ///< 1: distance from the camera to the surface; 0 on background
    Image world_position;    ///< 3
    Image shading_normal;    ///< 3: normalised interpolated vertex normal
    Image geometric_normal;  ///< 3: normalised cross(p1 - p0, p2 - p0)
    Image albedo;            ///< 3: material albedo x bilinear texture (repeat wrap)
    Image material_id;       ///< 1: -1 on background
    Image primitive_id;      ///< 1: -1 on background
    Image motion;  ///< 2: previous-camera projection of the world point minus the pixel centre

    GBuffer() = default;
    GBuffer(int width, int height);  ///< background everywhere
};

/// The G-buffer's buffer names in SPEC §4 order, with a prefix ("gbuffer_" by default).
void add_gbuffer(FrameResult& result, GBuffer gbuffer, const std::string& prefix = "gbuffer_");
std::vector<std::string> gbuffer_names(const std::string& prefix = "gbuffer_");

}  // namespace fovref
