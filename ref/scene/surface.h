// Surface attributes at a point of a triangle, shared by the rasterizer and the ray caster so
// that both G-buffers come from the same arithmetic (SPEC §4).
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "ref/scene/scene.h"

namespace fovref {

struct SurfacePoint {
    glm::vec3 position{0.0f};          ///< (1 - u - v) p0 + u p1 + v p2
    glm::vec3 shading_normal{0.0f};    ///< normalised interpolated vertex normal
    glm::vec3 geometric_normal{0.0f};  ///< normalised cross(p1 - p0, p2 - p0)
    glm::vec2 uv{0.0f};
    glm::vec3 albedo{0.0f};  ///< material albedo x bilinear texture lookup
    std::int32_t material = -1;
};

/// Attributes of triangle `primitive` at barycentrics (u, v) weighting corners 1 and 2.
SurfacePoint surface_at(const Scene& scene, std::int32_t primitive, float u, float v);

}  // namespace fovref
