// Lambertian direct lighting with one shadow ray per light sample (Lund §3.1 after the NVIDIA
// DXR tutorial; Gupta §2's "Lambertian plus shadows" pass).
//
//   L = Le (front side of an emitter seen directly)
//     + sum over lights l of  albedo / pi * E_l * V_l
// point light:      E = I cos(theta) / d^2
// quad / triangle:  one uniformly sampled point y on the light, E = Le cos(theta) cos(theta_l) A /
// d^2
//                   (area lights emit on the side of cross(edge_u, edge_v))
// Random numbers (SPEC §0): light l uses dimensions base + 2l and base + 2l + 1 of
// rand(frame, pixel, .); `base` separates the samples of a pixel (ground truth: 2 * lights * s).
// Surfaces are two-sided: normals are turned towards the viewer first.
// Shadow rays (SPEC §3): origin = P + eps n_g (n_g on the light's side), eps = 1e-4 * scene scale;
// direction = y - origin unnormalised, t in (0, 1 - 1e-4]: the ray stops just short of the light
// sample, so an emissive triangle never shadows itself. Lights behind the surface (or facing away)
// get no shadow ray. A scene without lights traces no shadow rays at all.
#pragma once

#include <cstdint>

#include "ref/bvh/bvh.h"
#include "ref/scene/scene.h"
#include "ref/trace/surface.h"

namespace fovref {

struct ShadingStats {
    std::int64_t shaded = 0;       ///< surface points shaded
    std::int64_t shadow_rays = 0;  ///< shadow rays traced
    std::int64_t shadow_rays_occluded = 0;
    std::int64_t lights_facing_away = 0;  ///< light samples skipped without a ray
    std::int64_t texture_fetches = 0;     ///< counted by the caller from textured materials
    TraceStats shadow_trace;              ///< traversal work of the shadow rays
};

inline constexpr float shadow_epsilon_scale = 1e-4f;
inline constexpr float shadow_t_max = 1.0f - 1e-4f;

/// Radiance leaving `surface` towards the viewer at `eye` (linear RGB).
glm::vec3 shade_direct(const Scene& scene, const Bvh* bvh, const SurfacePoint& surface,
                       glm::vec3 eye, std::uint32_t frame, std::uint32_t pixel,
                       std::uint32_t dimension_base, ShadingStats& stats);

/// Random-number dimensions one shading call uses.
inline std::uint32_t shading_dimensions(const Scene& scene) {
    return 2u * static_cast<std::uint32_t>(scene.lights.size());
}

}  // namespace fovref
