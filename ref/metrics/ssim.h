// SSIM (SPEC §10; Wang, Bovik, Sheikh, Simoncelli 2004, the authors' ssim_index.m; Lund §4.3.2).
// clang-format off
//
//   mu_a = G * a,  mu_b = G * b,  s_aa = G * a^2 - mu_a^2,  s_bb = G * b^2 - mu_b^2,
//   s_ab = G * ab - mu_a mu_b                          (population covariance)
//   SSIM = (2 mu_a mu_b + C1)(2 s_ab + C2) / ((mu_a^2 + mu_b^2 + C1)(s_aa + s_bb + C2))
//   C1 = (K1 L)^2, C2 = (K2 L)^2, K1 = 0.01, K2 = 0.03
//
// G is the normalised 11x11 Gaussian window (sigma 1.5), applied separably (rows first, then
// columns). The map exists only where the window fits ('valid': a 5-pixel border is left out);
// mean SSIM is the mean of the map. This equals scikit-image's structural_similarity(
// gaussian_weights=True, sigma=1.5, use_sample_covariance=False, data_range=L).
//
// Precision: everything after the input values is binary64 (the variances are differences of
// nearly equal numbers, which binary32 would lose against C2 = 9e-4). Each filtered value is
// w_0 x_0 + w_1 (x_-1 + x_1) + ... + w_r (x_-r + x_r), summed in that order (rows first, then
// columns); SSE2 computes two columns at once with exactly these operations.
// clang-format on
#pragma once

#include <vector>

#include "ref/image/image.h"

namespace fovref {

struct SsimSettings {
    int radius = 5;           ///< window (2 radius + 1)^2 = 11 x 11
    double sigma = 1.5;       ///< Gaussian window
    double k1 = 0.01;         ///< C1 = (k1 L)^2
    double k2 = 0.03;         ///< C2 = (k2 L)^2
    double data_range = 1.0;  ///< L
    /// Use the 4-lane AVX filter kernel where the CPU has AVX (x86). Its results are
    /// bit-identical to the 2-lane SSE2 kernel; false forces SSE2 (the test that checks it).
    bool allow_avx = true;
};

/// The SSIM map on the 'valid' region: map pixel (x, y) is image pixel (x + border, y + border).
struct SsimMap {
    int width = 0;               ///< image width - 2 border
    int height = 0;              ///< image height - 2 border
    int border = 0;              ///< = radius
    std::vector<double> values;  ///< row-major
    double mean = 0.0;           ///< mean of values, summed row-major in binary64
    /// SSIM at image pixel (x, y); the pixel must be in the valid region.
    double at_image(int x, int y) const {
        return values[static_cast<std::size_t>(y - border) * static_cast<std::size_t>(width) +
                      static_cast<std::size_t>(x - border)];
    }
    bool valid(int x, int y) const {
        return x >= border && y >= border && x < border + width && y < border + height;
    }
};

/// The normalised 1-D Gaussian taps w[-radius .. radius] (exp in binary64 from ref/core).
std::vector<double> ssim_window(const SsimSettings& settings);

/// SSIM of two 1-channel images (e.g. luma from ref/metrics/metrics.h). Throws fovref::Error
/// when shapes differ, an image has other than 1 channel, or it is smaller than the window.
SsimMap ssim_map(const Image& a, const Image& b, const SsimSettings& settings = {});

/// Mean SSIM of two RGB (luma is taken) or 1-channel images.
double ssim(const Image& a, const Image& b, const SsimSettings& settings = {});

}  // namespace fovref
