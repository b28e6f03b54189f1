#include "ref/trace/pathtrace_reference.h"

#include <algorithm>
#include <cmath>

#include "ref/core/error.h"
#include "ref/core/rng.h"
#include "ref/raster/gbuffer.h"
#include "ref/trace/raycast_gbuffer.h"

namespace fovref {

PathReferenceSums empty_reference_sums(int width, int height) {
    PathReferenceSums s;
    s.sum = Image(width, height, 3);
    s.compensation = Image(width, height, 3);
    s.squares = Image(width, height, 3);
    return s;
}

Offset2 reference_jitter(int sample, int pixel, ReferenceJitter mode) {
    const auto s = static_cast<std::uint32_t>(sample);
    Offset2 j{rand_unit(0xffffffffu, s, 0u), rand_unit(0xffffffffu, s, 1u)};
    if (mode == ReferenceJitter::shared) return j;
    // Both are multiples of 2^-24 below 1: the sum and the wrap are exact in binary32
    const auto p = static_cast<std::uint32_t>(pixel);
    j.x += rand_unit(0xfffffffeu, p, 0u);
    j.y += rand_unit(0xfffffffeu, p, 1u);
    if (j.x >= 1.0f) j.x -= 1.0f;
    if (j.y >= 1.0f) j.y -= 1.0f;
    return j;
}

std::uint32_t reference_seed(int frame, int sample) {
    return 0x80000000u |
           ((static_cast<std::uint32_t>(frame) << 16) ^ static_cast<std::uint32_t>(sample));
}

void pathtrace_reference(const Scene& scene, const Bvh& bvh, const PathTraceParams& params,
                         const Camera& camera, int frame, int total, ReferenceJitter jitter,
                         PathReferenceSums& sums, TraceStats& primary, PathTraceStats& stats,
                         const std::function<void(double)>& progress) {
    const int width = sums.sum.width, height = sums.sum.height;
    const int first = sums.count;
    for (int s = first; s < total; ++s) {
        // One sample of every pixel: jittered primary rays, then the paths
        RaycastStats raycast;
        const PrimaryView view(scene, bvh, camera, camera);
        GBuffer g(width, height);
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x)
                raycast_gbuffer_pixel(g, view, x, y, raycast,
                                      reference_jitter(s, y * width + x, jitter));
        primary += raycast.primary;
        const ShadeInputs in{g.world_position, g.shading_normal, g.geometric_normal,
                             g.albedo,         g.material_id,    g.primitive_id};
        const Image radiance = pathtrace(scene, bvh, params, in, camera,
                                         static_cast<int>(reference_seed(frame, s)), stats);
        // Neumaier summation of the sample into sum + compensation
        for (std::size_t i = 0; i < radiance.data.size(); ++i) {
            const float v = radiance.data[i];
            const float t = sums.sum.data[i] + v;
            if (std::fabs(sums.sum.data[i]) >= std::fabs(v))
                sums.compensation.data[i] += (sums.sum.data[i] - t) + v;
            else
                sums.compensation.data[i] += (v - t) + sums.sum.data[i];
            sums.sum.data[i] = t;
            sums.squares.data[i] += v * v;
        }
        sums.count = s + 1;
        if (progress) progress(static_cast<double>(s + 1 - first) / (total - first));
    }
}

void reference_estimate(const PathReferenceSums& sums, Image& mean, Image& standard_error) {
    FOVREF_CHECK(sums.count > 0, "reference_estimate: no samples");
    mean = Image(sums.sum.width, sums.sum.height, 3);
    standard_error = Image(sums.sum.width, sums.sum.height, 3);
    const auto n = static_cast<float>(sums.count);
    for (std::size_t i = 0; i < mean.data.size(); ++i) {
        const float m = (sums.sum.data[i] + sums.compensation.data[i]) / n;
        mean.data[i] = m;
        if (sums.count > 1) {
            const float variance = std::max(0.0f, sums.squares.data[i] / n - m * m);
            standard_error.data[i] = std::sqrt(variance / (n - 1.0f));
        }
    }
}

}  // namespace fovref
