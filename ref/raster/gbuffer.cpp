#include "ref/raster/gbuffer.h"

#include <cmath>

#include "ref/core/vec.h"
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
    const glm::vec2 centre = pixel_centre(x, y);
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

namespace {

// Each channel with its name, kind and channel names, in SPEC §4 order: what add_gbuffer and
// output_gbuffer write.
template <class Add>
void each_channel(GBuffer& g, const Add& add) {
    const std::vector<std::string> xyz = {"x", "y", "z"};
    add("view_depth", BufferKind::depth, std::vector<std::string>{"z"}, g.view_depth);
    add("hit_distance", BufferKind::depth, std::vector<std::string>{"t"}, g.hit_distance);
    add("world_position", BufferKind::scalar, xyz, g.world_position);
    add("shading_normal", BufferKind::vector, xyz, g.shading_normal);
    add("geometric_normal", BufferKind::vector, xyz, g.geometric_normal);
    add("albedo", BufferKind::color, std::vector<std::string>{"r", "g", "b"}, g.albedo);
    add("material_id", BufferKind::id, std::vector<std::string>{"id"}, g.material_id);
    add("primitive_id", BufferKind::id, std::vector<std::string>{"id"}, g.primitive_id);
    add("motion", BufferKind::vector, std::vector<std::string>{"dx", "dy"}, g.motion);
}

const char* const shading_channels[] = {"world_position", "shading_normal", "geometric_normal",
                                        "albedo",         "material_id",    "primitive_id"};

}  // namespace

void add_gbuffer(FrameResult& result, GBuffer g, const std::string& prefix) {
    each_channel(
        g, [&](const char* name, BufferKind kind, std::vector<std::string> channels, Image& image) {
            result.add(prefix + name, kind, std::move(channels), std::move(image));
        });
}

std::vector<Port> gbuffer_ports(const std::string& prefix) {
    std::vector<Port> ports;
    for (const std::string& name : gbuffer_names("")) ports.emplace_back(name, prefix + name);
    return ports;
}

std::vector<Port> shading_ports(const std::string& prefix) {
    std::vector<Port> ports;
    for (const char* name : shading_channels) ports.emplace_back(name, prefix + name);
    return ports;
}

void output_gbuffer(const FrameContext& ctx, GBuffer g) {
    each_channel(
        g, [&](const char* name, BufferKind kind, std::vector<std::string> channels, Image& image) {
            if (!image.empty()) ctx.output(name, kind, std::move(channels), std::move(image));
        });
}

}  // namespace fovref
