#include "ref/trace/raycast_gbuffer.h"

namespace fovref {

GBuffer raycast_gbuffer(const Scene& scene, const Bvh& bvh, const Camera& camera,
                        const Camera& previous_camera, int width, int height, TraceStats& stats) {
    GBuffer g(width, height);
    const float tan_half = tan_half_vfov(camera);
    const float previous_tan_half = tan_half_vfov(previous_camera);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const Ray ray = primary_ray(camera, tan_half, width, height,
                                        static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
            const Hit hit = trace_closest(bvh, ray, stats);
            if (hit.hit())  // misses keep the background values
                write_gbuffer_pixel(g, x, y, scene, camera, previous_camera, previous_tan_half,
                                    hit.primitive, hit.u, hit.v);
        }
    return g;
}

}  // namespace fovref
