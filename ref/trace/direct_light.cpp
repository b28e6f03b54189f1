#include "ref/trace/direct_light.h"

#include <cmath>

#include "ref/core/error.h"
#include "ref/core/rng.h"

namespace fovref {

namespace {

constexpr float inv_pi = 0.318309886183790671538f;

}  // namespace

bool sample_light_point(const Light& light, float r1, float r2, glm::vec3& y, glm::vec3& normal,
                        float& area) {
    y = light.position;
    normal = glm::vec3(0.0f);
    area = 0.0f;
    if (light.type == Light::Type::point) return true;
    const glm::vec3 cross = glm::cross(light.edge_u, light.edge_v);
    const float cross_length = std::sqrt(glm::dot(cross, cross));
    if (!(cross_length > 0.0f)) return false;
    normal = cross / cross_length;
    if (light.type == Light::Type::quad) {
        y = light.position + light.edge_u * r1 + light.edge_v * r2;
        area = cross_length;
    } else {  // uniform on the triangle: (1 - sqrt r1, sqrt r1 (1 - r2), sqrt r1 r2)
        const float s = std::sqrt(r1);
        y = light.position + light.edge_u * (s * (1.0f - r2)) + light.edge_v * (s * r2);
        area = 0.5f * cross_length;
    }
    return true;
}

bool shadow_visible(const Bvh& bvh, glm::vec3 origin, glm::vec3 target, ShadingStats& stats) {
    Ray ray;
    ray.origin = origin;
    ray.direction = target - origin;
    ray.t_min = 0.0f;
    ray.t_max = shadow_t_max;
    ++stats.shadow_rays;
    const bool occluded = trace_any(bvh, ray, stats.shadow_trace);
    if (occluded) ++stats.shadow_rays_occluded;
    return !occluded;
}

glm::vec3 shade_direct(const Scene& scene, const Bvh* bvh, const SurfacePoint& surface,
                       glm::vec3 eye, std::uint32_t frame, std::uint32_t pixel,
                       std::uint32_t dimension_base, ShadingStats& stats,
                       std::vector<LightSampleRecord>* record) {
    FOVREF_CHECK(bvh != nullptr || scene.lights.empty(), "shadow rays need a BVH");
    ++stats.shaded;
    const Material& material = scene.materials[static_cast<std::size_t>(surface.material)];
    const glm::vec3 to_eye = eye - surface.position;
    // Two-sided: turn both normals towards the viewer.
    const bool front = glm::dot(surface.geometric_normal, to_eye) >= 0.0f;
    const glm::vec3 n_g = front ? surface.geometric_normal : -surface.geometric_normal;
    // The shading normal goes to the geometric normal's side (vertex normals may disagree with
    // the winding: an OBJ wound clockwise with outward normals).
    const glm::vec3 n_s = glm::dot(surface.shading_normal, n_g) < 0.0f ? -surface.shading_normal
                                                                       : surface.shading_normal;

    glm::vec3 radiance = front ? material.emission : glm::vec3(0.0f);
    const glm::vec3 brdf = surface.albedo * inv_pi;
    const float epsilon = shadow_epsilon_scale * scene.scene_scale;

    for (std::size_t l = 0; l < scene.lights.size(); ++l) {
        const Light& light = scene.lights[l];
        const std::uint32_t dimension = dimension_base + 2u * static_cast<std::uint32_t>(l);
        LightSampleRecord dummy;
        LightSampleRecord& rec = record ? record->emplace_back() : dummy;
        rec.light = static_cast<int>(l);
        // Sample a point y on the light and its emitted quantity.
        glm::vec3 y, light_normal;
        float area = 0.0f;
        if (light.type != Light::Type::point) {
            rec.r1 = rand_unit(frame, pixel, dimension);
            rec.r2 = rand_unit(frame, pixel, dimension + 1);
        }
        if (!sample_light_point(light, rec.r1, rec.r2, y, light_normal, area)) {
            ++stats.light_samples_degenerate;
            rec.outcome = "degenerate";
            continue;
        }
        rec.sample = y;
        const glm::vec3 to_light = y - surface.position;
        const float d2 = glm::dot(to_light, to_light);
        if (!(d2 > min_light_distance2)) {  // on the light (or closer than float can divide by)
            ++stats.light_samples_degenerate;
            rec.outcome = "degenerate";
            continue;
        }
        const float d = std::sqrt(d2);
        const float cos_surface = glm::dot(n_s, to_light) / d;
        float geometry = cos_surface / d2;
        if (light.type != Light::Type::point)
            geometry *= area * (-glm::dot(light_normal, to_light) / d);
        rec.distance = d;
        rec.cos_surface = cos_surface;
        rec.geometry = geometry;
        if (!(cos_surface > 0.0f) || !(geometry > 0.0f) || glm::dot(n_g, to_light) <= 0.0f) {
            ++stats.lights_facing_away;
            rec.outcome = "facing away";
            continue;
        }
        rec.shadow_origin = surface.position + n_g * epsilon;
        if (!shadow_visible(*bvh, rec.shadow_origin, y, stats)) {
            rec.outcome = "occluded";
            continue;
        }
        rec.outcome = "lit";
        rec.contribution = brdf * light.intensity * geometry;
        radiance += rec.contribution;
    }
    return radiance;
}

}  // namespace fovref
