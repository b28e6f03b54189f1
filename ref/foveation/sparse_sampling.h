// Per-pixel sparse sampling for the screen-space foveated path tracers (SPEC §5.4-5.5;
// docs/visual-polar.md): Weier et al.'s linear fall-off probability (Koskela eq. 4.1), the
// visual-acuity sample positions of Koskela P3/P4, and the push-pull fill of unsampled pixels
// (Koskela §4.4.3).
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "ref/image/image.h"

namespace fovref {

/// Linear fall-off (SPEC §5.4): the probability of sampling a pixel at eccentricity e (degrees):
/// 1 for e <= fovea_deg, falling linearly to periphery_probability at periphery_deg, constant
/// beyond. P5's comparison: 10, 20, 0.2.
struct LinearFalloff {
    float fovea_deg = 10.0f;
    float periphery_deg = 20.0f;
    float periphery_probability = 0.2f;
};
float linear_falloff_probability(const LinearFalloff& falloff, float eccentricity_deg);

/// Whether pixel `pixel` of frame `frame` is traced: rand(frame, pixel, 0) < probability.
bool linear_falloff_sampled(std::uint32_t frame, std::uint32_t pixel, float probability);

/// Visual-acuity sample k of frame f (SPEC §5.5): phi = 2 pi r1, e = P(r2) (the fitted inverse
/// CDF, ref/foveation/visual_polar.h), position g + e s_e (cos phi, sin phi), s_e pixels per
/// degree; r1, r2 = rand(frame, k, 0), rand(frame, k, 1).
glm::vec2 acuity_sample(std::uint32_t frame, std::uint32_t sample, glm::vec2 gaze,
                        float pixels_per_degree);

/// Push-pull fill: `weight` (W x H x 1) is > 0 where `image` holds a sample. Pull: level k + 1
/// pixel = the average of its (up to 4) children that hold data, children in row order; push:
/// from the coarsest level down, a pixel without data takes its parent's value (nearest). A
/// pixel with a sample keeps it, so a fully sampled image comes back unchanged. With no sample
/// at all the result is black.
Image push_pull(const Image& image, const Image& weight);

}  // namespace fovref
