#include "ref/visual_polar/trace.h"

#include "ref/core/error.h"

namespace fovref {

namespace {

// The primary ray through screen point p, written to texel (x, y) (valid 1).
void trace_texel(MaskedGBuffer& buffer, int x, int y, glm::vec2 p, int width, int height,
                 const Scene& scene, const Bvh& bvh, const Camera& camera, float tan_half,
                 const Camera& previous_camera, float previous_tan_half, VpTraceStats& stats) {
    ++stats.texels_traced;
    buffer.valid.at(x, y) = 1.0f;
    const Ray ray = primary_ray(camera, tan_half, width, height, p.x, p.y);
    const Hit hit = trace_closest(bvh, ray, stats.rays.primary);
    if (hit.hit() &&
        !write_gbuffer_sample(buffer.gbuffer, x, y, p, width, height, scene, camera,
                              previous_camera, previous_tan_half, hit.primitive, hit.u, hit.v))
        ++stats.rays.motion_behind_previous;
}

}  // namespace

VpTexel vp_gbuffer_texel(MaskedGBuffer& buffer, Image& screen_points, const VisualPolarMap& map,
                         const Scene& scene, const Bvh& bvh, const Camera& camera, float tan_half,
                         const Camera& previous_camera, float previous_tan_half, int x, int y,
                         VpTraceStats& stats) {
    glm::vec2 p{0.0f};
    const VpTexel status = vp_texel_status(map, x, y, p);
    screen_points.at(x, y, 0) = p.x;
    screen_points.at(x, y, 1) = p.y;
    if (status == VpTexel::clipped) {
        ++stats.texels_clipped;
    } else if (status == VpTexel::off_screen) {
        ++stats.texels_off_screen;
    } else {
        trace_texel(buffer, x, y, p, map.screen_width, map.screen_height, scene, bvh, camera,
                    tan_half, previous_camera, previous_tan_half, stats);
    }
    return status;
}

MaskedGBuffer trace_vp_gbuffer(const VisualPolarMap& map, const Scene& scene, const Bvh& bvh,
                               const Camera& camera, const Camera& previous_camera,
                               Image& screen_points, VpTraceStats& stats) {
    MaskedGBuffer buffer(map.width, map.height);
    screen_points = Image(map.width, map.height, 2, 0.0f);
    const float tan_half = tan_half_vfov(camera);
    const float previous_tan_half = tan_half_vfov(previous_camera);
    for (int y = 0; y < map.height; ++y)
        for (int x = 0; x < map.width; ++x)
            vp_gbuffer_texel(buffer, screen_points, map, scene, bvh, camera, tan_half,
                             previous_camera, previous_tan_half, x, y, stats);
    return buffer;
}

MaskedGBuffer trace_point_gbuffer(const std::vector<glm::vec2>& points, int width, int height,
                                  const Scene& scene, const Bvh& bvh, const Camera& camera,
                                  const Camera& previous_camera, VpTraceStats& stats) {
    FOVREF_CHECK(!points.empty(), "trace_point_gbuffer: no points");
    MaskedGBuffer buffer(static_cast<int>(points.size()), 1);
    const float tan_half = tan_half_vfov(camera);
    const float previous_tan_half = tan_half_vfov(previous_camera);
    for (std::size_t k = 0; k < points.size(); ++k) {
        const glm::vec2 p = points[k];
        if (!(p.x >= 0.0f && p.y >= 0.0f && p.x < static_cast<float>(width) &&
              p.y < static_cast<float>(height))) {
            ++stats.texels_off_screen;
            continue;
        }
        trace_texel(buffer, static_cast<int>(k), 0, p, width, height, scene, bvh, camera, tan_half,
                    previous_camera, previous_tan_half, stats);
    }
    return buffer;
}

}  // namespace fovref
