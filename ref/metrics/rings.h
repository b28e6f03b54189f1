// Error ranges (SPEC §10; Lund §3.6, §4.3.3, §5.3.4): the screen split into N rings of equal
// angular width around the gaze point, with the metrics of each ring.
// clang-format off
//
//   e(p)  = atan(|p - g| / d_px) in degrees        (p = pixel centre, g = gaze, SPEC §1)
//   e_max = e of the screen corner farthest from g (corners (0,0), (W,0), (0,H), (W,H))
//   E     = max_range * e_max,   ring width = E / N
//   ring k = [k E/N, (k+1) E/N)  (half-open: the rings partition the pixels with e < E;
//                                  pixels with e >= E are in no ring)
//
// Per ring: pixel count, MSE (mean over its pixels and the channels), RMSE, PSNR, SSIM (mean of
// the SSIM map over the ring's pixels inside the map's valid region) and SD, the population
// standard deviation of the per-pixel squared error (the channel mean of (a-b)^2), Lund's SD.
// Sums are binary64, row-major. Eccentricities are binary32 with dm::atan.
// clang-format on
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "ref/image/image.h"
#include "ref/metrics/ssim.h"

namespace fovref {

struct RingSettings {
    int count = 20;          ///< N (Lund §4.3.3)
    float max_range = 1.0f;  ///< fraction of e_max covered (Lund used 0.682 of his max_view_angle)
};

/// Which ring every pixel is in.
struct RingLayout {
    int width = 0, height = 0;
    glm::vec2 gaze{0.0f};
    float distance_px = 0.0f;
    int count = 0;
    float max_eccentricity_deg = 0.0f;  ///< e_max
    float outer_deg = 0.0f;             ///< E
    float ring_width_deg = 0.0f;        ///< E / N
    std::vector<std::int16_t> ring;     ///< per pixel, row-major; -1 = outside every ring
    float inner(int k) const { return static_cast<float>(k) * ring_width_deg; }
    float outer(int k) const { return static_cast<float>(k + 1) * ring_width_deg; }
};

/// Eccentricity of screen point p in degrees (SPEC §1).
float eccentricity_deg(glm::vec2 p, glm::vec2 gaze, float distance_px);

/// The ring of eccentricity e: the k with k w <= e < (k + 1) w (products in binary32, w = E/N),
/// or -1 when e >= N w or e is not finite.
int ring_of(float eccentricity, float ring_width, int count);

/// The mean of a 1-channel per-pixel map (e.g. LDR-FLIP's error map) over each ring's pixels,
/// summed in binary64 in row-major order; NaN for a ring without pixels. Throws fovref::Error
/// when the map is not 1-channel or not the layout's size.
std::vector<double> ring_means(const Image& map, const RingLayout& layout);

/// Throws fovref::Error naming the setting when N is not in 1..1000, max_range not in (0, 1],
/// the distance not finite and > 0, or the gaze not finite.
RingLayout ring_layout(int width, int height, glm::vec2 gaze, float distance_px,
                       const RingSettings& settings = {});

struct RingStats {
    int ring = 0;
    float inner_deg = 0.0f, outer_deg = 0.0f;
    std::int64_t pixels = 0;
    double mse = 0.0, rmse = 0.0, psnr = 0.0;
    double sd = 0.0;               ///< of the per-pixel squared error
    std::int64_t ssim_pixels = 0;  ///< ring pixels inside the SSIM map (0: ssim is NaN)
    double ssim = 0.0;
};

/// Ring statistics of a against b (same shape, any channel count; SSIM from `ssim`, which may be
/// null, when the caller has computed one for these images).
std::vector<RingStats> ring_errors(const Image& a, const Image& b, const RingLayout& layout,
                                   const SsimMap* ssim);

}  // namespace fovref
