// Per-pixel sparse sampling for the screen-space foveated path tracers (SPEC §5.4-5.5;
// docs/visual-polar.md): Weier et al.'s linear fall-off probability (Koskela eq. 4.1), the
// visual-acuity sample positions of Koskela P3/P4, and the push-pull fill of unsampled pixels
// (Koskela §4.4.3).
#pragma once

#include <cstdint>
#include <vector>

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

/// How the sparse modes turn a screen distance r (pixels from the gaze) into an eccentricity e
/// (degrees) and back (parameter `eccentricity`, docs/visual-polar.md): `exact` (default, the
/// display model of SPEC §1) e = atan(r / d_px) in degrees and r = d_px tan(e) (infinite from
/// 89.9 degrees on, off every screen); `linear` e = r / ppd and r = e ppd with ppd = d_px pi / 180
/// (the pixels per degree at the gaze, which overstates the periphery's degrees).
struct EccentricityModel {
    bool exact = true;
    float distance_px = 1.0f;  ///< d_px
    float degrees(float r) const;
    float radius(float e) const;
};
float linear_falloff_probability(const LinearFalloff& falloff, float eccentricity_deg);

/// Whether pixel `pixel` of frame `frame` is traced: rand(frame, pixel, 0) < probability.
bool linear_falloff_sampled(std::uint32_t frame, std::uint32_t pixel, float probability);

/// Visual-acuity sample k of frame f (SPEC §5.5): phi = 2 pi r1, e = P(r2) (the fitted inverse
/// CDF, ref/visual_polar/map.h), position g + r(e) (cos phi, sin phi) with the model's r(e);
/// r1, r2 = rand(frame, k, 0), rand(frame, k, 1).
glm::vec2 acuity_sample(std::uint32_t frame, std::uint32_t sample, glm::vec2 gaze,
                        const EccentricityModel& model);

/// The pixels traced in frame `frame` on a W x H screen (1 channel, 1 = traced): pixel (x, y)
/// with centre c is traced when linear_falloff_sampled(frame, y W + x, L(e)), e = the model's
/// degrees of |c - g| (exact: atan(|c - g| / d_px), dm::atan). `sampled` receives the count.
Image linear_falloff_mask(const LinearFalloff& falloff, int width, int height, glm::vec2 gaze,
                          const EccentricityModel& model, std::uint32_t frame,
                          std::int64_t& sampled);

/// The expected number of pixels linear_falloff_mask traces: sum of L(e) over the pixel
/// centres (binary64 sum in row order).
double linear_falloff_expected(const LinearFalloff& falloff, int width, int height, glm::vec2 gaze,
                               const EccentricityModel& model);

/// The N acuity samples of frame `frame` (acuity_sample k = 0 .. N - 1).
std::vector<glm::vec2> acuity_samples(std::uint32_t frame, int count, glm::vec2 gaze,
                                      const EccentricityModel& model);

/// Adds each traced sample's colour (`colors`, N x 1 x 3, `valid` N x 1) to the pixel floor(p)
/// that holds its point: sum (W x H x 3) += colour, count (W x H x 1) += 1, in sample order.
void splat_samples(const std::vector<glm::vec2>& points, const Image& valid, const Image& colors,
                   Image& sum, Image& count);

/// sum / count per pixel, black where count is 0 (the acuity mode's image); `weight` receives
/// 1 where count > 0.
Image sample_mean(const Image& sum, const Image& count, Image& weight);

/// Push-pull fill: `weight` (W x H x 1) is > 0 where `image` holds a sample. Pull: level k + 1
/// pixel = the average of its (up to 4) children that hold data, children in row order; push:
/// from the coarsest level down, a pixel without data takes its parent's value (nearest). A
/// pixel with a sample keeps it, so a fully sampled image comes back unchanged. With no sample
/// at all the result is black.
Image push_pull(const Image& image, const Image& weight);

}  // namespace fovref
