#include "ref/raster/gbuffer.h"

#include <cmath>

#include "ref/scene/surface.h"

namespace fovref {

GBuffer::GBuffer(int width, int height)
    : view_depth(width, height, 1, 0.0f),
      hit_distance(width, height, 1, 0.0f),
      world_position(width, height, 3, 0.0f),
      shading_normal(width, height, 3, 0.0f),
      geometric_normal(width, height, 3, 0.0f),
      albedo(width, height, 3, 0.0f),
      material_id(width, height, 1, -1.0f),
      primitive_id(width, height, 1, -1.0f),
      motion(width, height, 2, 0.0f) {}

bool write_gbuffer_pixel(GBuffer& g, int x, int y, const Scene& scene, const Camera& camera,
                         const Camera& previous_camera, float previous_tan_half,
                         std::int32_t primitive, float u, float v) {
    const glm::vec2 centre{static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f};
    return write_gbuffer_sample(g, x, y, centre, g.view_depth.width, g.view_depth.height, scene,
                                camera, previous_camera, previous_tan_half, primitive, u, v);
}

bool write_gbuffer_sample(GBuffer& g, int x, int y, glm::vec2 screen_point, int screen_width,
                          int screen_height, const Scene& scene, const Camera& camera,
                          const Camera& previous_camera, float previous_tan_half,
                          std::int32_t primitive, float u, float v) {
    const SurfacePoint s = surface_at(scene, primitive, u, v);
    const glm::vec3 to_point = s.position - camera.position;
    g.view_depth.at(x, y) = view_depth(camera, s.position);
    g.hit_distance.at(x, y) = std::sqrt(glm::dot(to_point, to_point));
    for (int c = 0; c < 3; ++c) {
        g.world_position.at(x, y, c) = s.position[c];
        g.shading_normal.at(x, y, c) = s.shading_normal[c];
        g.geometric_normal.at(x, y, c) = s.geometric_normal[c];
        g.albedo.at(x, y, c) = s.albedo[c];
    }
    g.material_id.at(x, y) = static_cast<float>(s.material);
    g.primitive_id.at(x, y) = static_cast<float>(primitive);
    glm::vec2 previous{0.0f};
    float previous_depth = 0.0f;
    if (!project_to_screen(previous_camera, previous_tan_half, screen_width, screen_height,
                           s.position, previous, previous_depth))
        return false;
    g.motion.at(x, y, 0) = previous.x - screen_point.x;
    g.motion.at(x, y, 1) = previous.y - screen_point.y;
    return true;
}

std::vector<std::string> gbuffer_names(const std::string& prefix) {
    return {prefix + "view_depth",     prefix + "hit_distance",     prefix + "world_position",
            prefix + "shading_normal", prefix + "geometric_normal", prefix + "albedo",
            prefix + "material_id",    prefix + "primitive_id",     prefix + "motion"};
}

void add_gbuffer(FrameResult& result, GBuffer g, const std::string& prefix) {
    const std::vector<std::string> xyz = {"x", "y", "z"};
    result.add(prefix + "view_depth", BufferKind::depth, {"z"}, std::move(g.view_depth));
    result.add(prefix + "hit_distance", BufferKind::depth, {"t"}, std::move(g.hit_distance));
    result.add(prefix + "world_position", BufferKind::scalar, xyz, std::move(g.world_position));
    result.add(prefix + "shading_normal", BufferKind::vector, xyz, std::move(g.shading_normal));
    result.add(prefix + "geometric_normal", BufferKind::vector, xyz, std::move(g.geometric_normal));
    result.add(prefix + "albedo", BufferKind::color, {"r", "g", "b"}, std::move(g.albedo));
    result.add(prefix + "material_id", BufferKind::id, {"id"}, std::move(g.material_id));
    result.add(prefix + "primitive_id", BufferKind::id, {"id"}, std::move(g.primitive_id));
    result.add(prefix + "motion", BufferKind::vector, {"dx", "dy"}, std::move(g.motion));
}

}  // namespace fovref
