// The G-buffer (SPEC §4), produced by the rasterizer (ref/raster/rasterizer.h) and by the ray
// caster (ref/trace/raycast_gbuffer.h) from the same per-hit attribute code (surface.h), so the
// two can be cross-checked pixel by pixel.
#pragma once

#include <string>
#include <vector>

#include <cstdint>

#include "ref/image/image.h"
#include "ref/scene/scene.h"
#include "ref/stage/frame.h"
#include "ref/stage/pipeline.h"

namespace fovref {

/// Where a screen-aligned buffer lies on the screen: its pixel (i, j) is screen pixel
/// (x0 + i, y0 + j) of a screen_width x screen_height screen. A screen-sized buffer is
/// full_screen(W, H); the composite modes' gaze buffer is a window around the gaze circle.
struct ScreenWindow {
    int x0 = 0, y0 = 0;         ///< the screen pixel of the buffer's pixel (0, 0)
    int width = 0, height = 0;  ///< the buffer's size
    int screen_width = 0, screen_height = 0;
    bool operator==(const ScreenWindow&) const = default;
};
inline ScreenWindow full_screen(int width, int height) {
    return {0, 0, width, height, width, height};
}

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

/// Fills pixel (x, y) from triangle `primitive` at barycentrics (u, v) (surface_at): view depth
/// and hit distance of the surface point, its attributes, and the motion vector (the point's
/// screen position under `previous_camera` minus the pixel centre). Returns false when the point
/// is not in front of the previous camera; the motion is then 0. Both the rasterizer and the ray
/// caster write their pixels with this one function.
bool write_gbuffer_pixel(GBuffer& gbuffer, int x, int y, const Scene& scene, const Camera& camera,
                         const Camera& previous_camera, float previous_tan_half,
                         std::int32_t primitive, float u, float v);

/// write_gbuffer_pixel for a G-buffer that is not the screen (a foveation buffer): texel (x, y)
/// holds the sample through screen point `screen_point` of a screen_width x screen_height screen,
/// and its motion is the point's previous-camera projection minus `screen_point`.
/// write_gbuffer_pixel is this with the pixel centre and the G-buffer's own size.
bool write_gbuffer_sample(GBuffer& gbuffer, int x, int y, glm::vec2 screen_point, int screen_width,
                          int screen_height, const Scene& scene, const Camera& camera,
                          const Camera& previous_camera, float previous_tan_half,
                          std::int32_t primitive, float u, float v);

/// The G-buffer's buffer names in SPEC §4 order, with a prefix ("gbuffer_" by default).
void add_gbuffer(FrameResult& result, GBuffer gbuffer, const std::string& prefix = "gbuffer_");
std::vector<std::string> gbuffer_names(const std::string& prefix = "gbuffer_");

/// A G-buffer as a stage's ports: slot = the channel's name ("view_depth", ...), buffer =
/// prefix + the name, in SPEC §4 order.
std::vector<Port> gbuffer_ports(const std::string& prefix = "gbuffer_");
/// The G-buffer view the shading passes read (world_position, shading_normal, geometric_normal,
/// albedo, material_id, primitive_id) as ports: slot = channel, buffer = prefix + channel.
std::vector<Port> shading_ports(const std::string& prefix = "gbuffer_");
/// Writes every channel of `gbuffer` to the running stage's output slot of the same name (a
/// channel left empty is not written: a stage that produces only the wanted channels).
void output_gbuffer(const FrameContext& context, GBuffer gbuffer);

}  // namespace fovref
