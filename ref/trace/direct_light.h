// Lambertian direct lighting with one shadow ray per light sample (Lund §3.1 after the NVIDIA
// DXR tutorial; Gupta §2's "Lambertian plus shadows" pass). docs/trace.md has the details.
// clang-format off
//
//   L = Le  (front side of an emitter seen directly)
//     + sum over lights l of  albedo / pi * E_l * V_l
//
//   point light:      E = I cos(theta) / d^2
//   quad / triangle:  one uniformly sampled point y on the light,
//                     E = Le cos(theta) cos(theta_l) A / d^2
//                     (area lights emit on the side of cross(edge_u, edge_v))
//
// Random numbers (SPEC §0): light l uses dimensions base + 2l and base + 2l + 1 of
// rand(frame, pixel, .); `base` separates the samples of a pixel (ground truth: 2 * lights * s).
// Surfaces are two-sided: the geometric normal is turned towards the viewer and the shading
// normal to the geometric normal's side. Only the diffuse lobe is shaded (a material's specular
// part is ignored by these ray tracers).
// Shadow rays (SPEC §3): origin = P + eps n_g (n_g on the light's side), eps = 1e-4 * scene
// scale (absolute); direction = y - origin unnormalised, t in (0, 1 - 1e-4] (relative: the ray
// stops 1e-4 d short of the light sample, so an emissive triangle never shadows itself). Light
// samples behind the surface, facing away, or degenerate get no shadow ray and are counted.
// clang-format on
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ref/bvh/bvh.h"
#include "ref/scene/scene.h"
#include "ref/scene/surface.h"

namespace fovref {

struct ShadingStats {
    std::int64_t shaded = 0;       ///< surface points shaded
    std::int64_t shadow_rays = 0;  ///< shadow rays traced
    std::int64_t shadow_rays_occluded = 0;
    std::int64_t lights_facing_away = 0;        ///< light samples skipped without a ray
    std::int64_t light_samples_degenerate = 0;  ///< zero-area light, or the point is on the light
    std::int64_t nonfinite_inputs = 0;          ///< NaN/Inf input values replaced by 0 (SPEC §0)
    std::int64_t invalid_material_ids = 0;      ///< pixels with no valid material: left black
    std::int64_t texture_fetches = 0;           ///< counted by the caller from textured materials
    TraceStats shadow_trace;                    ///< traversal work of the shadow rays
};

inline constexpr float shadow_epsilon_scale = 1e-4f;
inline constexpr float shadow_t_max = 1.0f - 1e-4f;
/// Squared distances to a light sample at or below this are skipped (guards cos / d^2, SPEC §0).
inline constexpr float min_light_distance2 = 1e-20f;

/// What shade_direct did with one light (for `fovref probe`).
struct LightSampleRecord {
    int light = 0;
    float r1 = 0.0f, r2 = 0.0f;     ///< random numbers (dimensions base + 2l, base + 2l + 1)
    glm::vec3 sample{0.0f};         ///< the point y on the light
    float distance = 0.0f;          ///< |y - P|
    float cos_surface = 0.0f;       ///< n_s . (y - P) / d
    float geometry = 0.0f;          ///< cos / d^2 (x A cos_l for area lights)
    const char* outcome = "";       ///< "lit", "occluded", "facing away", "degenerate"
    glm::vec3 shadow_origin{0.0f};  ///< P + eps n_g (when a shadow ray was traced)
    glm::vec3 contribution{0.0f};   ///< added radiance
};

/// A point y on `light` from two numbers in [0, 1) (unused for a point light: y = its position):
/// quad y = corner + r1 edge_u + r2 edge_v; triangle uniformly, (1 - sqrt r1, sqrt r1 (1 - r2),
/// sqrt r1 r2). `normal` and `area` of the emitting side (point: 0). False for a zero-area light.
bool sample_light_point(const Light& light, float r1, float r2, glm::vec3& y, glm::vec3& normal,
                        float& area);

/// One shadow ray from `origin` to `target` (t in (0, shadow_t_max]), counted; true when
/// nothing blocks it.
bool shadow_visible(const Bvh& bvh, glm::vec3 origin, glm::vec3 target, ShadingStats& stats);

/// Radiance leaving `surface` towards the viewer at `eye` (linear RGB). `record`, when given,
/// receives one entry per light (the probe's view of the computation; costs nothing otherwise).
glm::vec3 shade_direct(const Scene& scene, const Bvh* bvh, const SurfacePoint& surface,
                       glm::vec3 eye, std::uint32_t frame, std::uint32_t pixel,
                       std::uint32_t dimension_base, ShadingStats& stats,
                       std::vector<LightSampleRecord>* record = nullptr);

/// Random-number dimensions one shading call uses.
inline std::uint32_t shading_dimensions(const Scene& scene) {
    return 2u * static_cast<std::uint32_t>(scene.lights.size());
}

}  // namespace fovref
