#include "ref/raster/gbuffer.h"

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
