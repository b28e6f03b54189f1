#include "ref/trace/raycast_gbuffer.h"

#include <cmath>

#include "ref/trace/surface.h"

namespace fovref {

void write_gbuffer_pixel(GBuffer& g, int x, int y, const Scene& scene, const Camera& camera,
                         const Camera& previous_camera, float previous_tan_half, const Hit& hit) {
    if (!hit.hit()) return;  // background values are already in place
    const SurfacePoint s = surface_at(scene, hit.primitive, hit.u, hit.v);
    const glm::vec3 to_point = s.position - camera.position;
    g.view_depth.at(x, y) = glm::dot(to_point, camera.forward);
    g.hit_distance.at(x, y) = std::sqrt(glm::dot(to_point, to_point));
    for (int c = 0; c < 3; ++c) {
        g.world_position.at(x, y, c) = s.position[c];
        g.shading_normal.at(x, y, c) = s.shading_normal[c];
        g.geometric_normal.at(x, y, c) = s.geometric_normal[c];
        g.albedo.at(x, y, c) = s.albedo[c];
    }
    g.material_id.at(x, y) = static_cast<float>(s.material);
    g.primitive_id.at(x, y) = static_cast<float>(hit.primitive);
    // Motion (SPEC §4): previous-camera screen position of the point minus the pixel centre;
    // zero when the point was behind the previous camera.
    glm::vec2 previous;
    float previous_depth = 0.0f;
    if (project_to_screen(previous_camera, previous_tan_half, g.view_depth.width,
                          g.view_depth.height, s.position, previous, previous_depth)) {
        g.motion.at(x, y, 0) = previous.x - (static_cast<float>(x) + 0.5f);
        g.motion.at(x, y, 1) = previous.y - (static_cast<float>(y) + 0.5f);
    }
}

GBuffer raycast_gbuffer(const Scene& scene, const Bvh& bvh, const Camera& camera,
                        const Camera& previous_camera, int width, int height, TraceStats& stats) {
    GBuffer g(width, height);
    const float tan_half = tan_half_vfov(camera);
    const float previous_tan_half = tan_half_vfov(previous_camera);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            Ray ray;
            ray.origin = camera.position;
            ray.direction =
                primary_ray_direction(camera, tan_half, width, height, static_cast<float>(x) + 0.5f,
                                      static_cast<float>(y) + 0.5f);
            const Hit hit = trace_closest(bvh, ray, stats);
            write_gbuffer_pixel(g, x, y, scene, camera, previous_camera, previous_tan_half, hit);
        }
    return g;
}

}  // namespace fovref
