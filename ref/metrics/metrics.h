// Image metrics (SPEC §10; Lund §2.4, §3.6, §4.3; Koskela P2 §7.1): MSE, RMSE, PSNR, per-pixel
// error maps, the display-space transform and the temporal error. SSIM is in ref/metrics/ssim.h,
// the error ranges (rings) in ref/metrics/rings.h, heatmaps in ref/metrics/heatmap.h.
//
// Precision (docs/metrics.md): metrics are reductions, so they accumulate in binary64 in a fixed
// order (row-major, then channel) from the binary32 pixel values; the per-pixel transforms that
// produce images (display encoding, luma) are binary32 like any stage.
#pragma once

#include <cstdint>
#include <vector>

#include "ref/image/image.h"

namespace fovref {

/// SPEC §10: the data range L of the compared values (stored values and display space alike).
inline constexpr double metric_data_range = 1.0;

/// Display space (SPEC §10 `--display`): every channel clamped to [0, 1] and sRGB-encoded
/// (IEC 61966-2-1), what a viewer sees. NaN becomes 0.
Image to_display(const Image& linear);

/// Rec. 709 luma Y = 0.2126 R + 0.7152 G + 0.0722 B (Lund eq. 4.1), evaluated in binary32 in this
/// order. A 1-channel image is returned as it is. Throws fovref::Error for 2 or 4+ channels.
Image luma(const Image& image);

/// Throws fovref::Error naming `what` when the two images differ in size or channel count.
void check_same_shape(const Image& a, const Image& b, const char* what);

/// Mean over pixels and channels of (a - b)^2, summed in binary64 row-major then channel.
double mse(const Image& a, const Image& b);

/// PSNR = 10 log10(L^2 / MSE) in dB; +infinity when mse == 0 (SPEC §10).
double psnr(double mse, double data_range = metric_data_range);

/// Per-pixel squared error, averaged over the channels (binary64 sum, stored as float): the
/// values the heatmap shows and whose ring mean is the ring MSE.
Image squared_error_map(const Image& a, const Image& b);

/// Per-pixel largest absolute channel difference (|a - b|, float).
Image abs_error_map(const Image& a, const Image& b);

/// Temporal error (SPEC §10, Koskela P2 Table 3): the mean over t >= 1 of the mean absolute luma
/// difference between frames t and t - 1. Frames must be display-space RGB (or luma) images of
/// one size. 0 for fewer than two frames.
double temporal_error(const std::vector<Image>& frames);

}  // namespace fovref
