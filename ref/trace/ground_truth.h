// The ground-truth ray tracer (Lund §3.2, SPEC §12): 16 rays per pixel at the screen points
// (i + h_x, j + h_y), h = Halton(2,3) points 1..16 (unscaled: the centre-relative offsets of Lund
// are h - 0.5), each shaded like the basic ray tracer with its own random-number dimensions, and
// box-filtered: the 16 radiances are summed in sample order in float and multiplied by 1/16.
#pragma once

#include "ref/bvh/bvh.h"
#include "ref/image/image.h"
#include "ref/trace/direct_light.h"

namespace fovref {

inline constexpr int ground_truth_samples = 16;

/// What one of a pixel's 16 samples did (for `fovref probe`).
struct GroundTruthSample {
    glm::vec2 offset{0.0f};     ///< Halton point inside the pixel
    glm::vec3 direction{0.0f};  ///< the primary ray's direction
    Hit hit;                    ///< closest hit (primitive -1: miss, black)
    glm::vec3 radiance{0.0f};
    glm::vec3 sum{0.0f};  ///< the pass's running sum after this sample (float, sample order)
};

/// Per-pixel work: the box-filtered radiance of pixel (x, y). `trace`, when given, receives the
/// 16 samples.
glm::vec3 ground_truth_pixel(const Scene& scene, const Bvh& bvh, const Camera& camera,
                             float tan_half, std::uint32_t frame, int width, int height, int x,
                             int y, TraceStats& primary_stats, ShadingStats& shading_stats,
                             std::vector<GroundTruthSample>* trace = nullptr);

/// The pass: ground_truth_pixel over the screen, row by row.
Image render_ground_truth(const Scene& scene, const Bvh& bvh, const Camera& camera,
                          std::uint32_t frame, int width, int height, TraceStats& primary_stats,
                          ShadingStats& shading_stats);

}  // namespace fovref
