// LDR-FLIP (SPEC §10): the perceptual difference evaluator of Andersson, Nilsson, Akenine-Möller,
// Oskarsson, Åström and Fairchild, "FLIP: A Difference Evaluator for Alternating Images", HPG 2020,
// computed as the authors' reference code NVlabs/flip v1.x computes it (separable filters of
// v1.2+, linear-RGB clamp of v1.4+, pooled statistics of the v1.4+ C++/Python tool). Written
// here from the paper and from reading that code; docs/flip.md has the pipeline, the constants,
// the choices and a precision note.
//
// Inputs are display-space RGB: sRGB-encoded values in [0, 1], what LDR-FLIP takes (NVlabs's tool
// reads PNGs). The caller encodes linear renders first (SPEC §10 `--display`: clamp to [0, 1],
// sRGB-encode); values outside [0, 1] are clamped after sRGB decoding, as NVlabs does.
//
// Per-pixel math is in the small inline functions below (binary32, written in NVlabs's operation
// order) so that a GPU port can copy them; ldr_flip() in flip.cpp runs the loops over pixels.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "ref/core/dmath.h"
#include "ref/image/image.h"
#include "ref/image/srgb.h"

namespace fovref {

struct FlipParams {
    /// Pixels per degree of visual angle. Default: NVlabs's default observer, a 3840-pixel-wide,
    /// 0.7 m wide monitor seen from 0.7 m, i.e. flip_pixels_per_degree(3840) = 67.0206451
    /// (the same binary32 value as NVlabs's calculatePPD(0.7f, 3840.0f, 0.7f)).
    float pixels_per_degree = 67.0206451f;
};

/// Pixels per degree at the gaze point for a display seen from d_px pixels (SPEC §1 display
/// model): ppd = d_px * pi / 180, the derivative of x = d_px tan(e) at e = 0. This is NVlabs's
/// calculatePPD(distance, resolution_x, monitor_width) = distance * (resolution_x / monitor_width)
/// * pi / 180 with d_px = distance * resolution_x / monitor_width; it is 0.01% below d_px tan(1°)
/// (the pixels covered by the first degree). Throws fovref::Error unless d_px is finite and > 0.
float flip_pixels_per_degree(float viewing_distance_px);

/// Throws fovref::Error naming `what` (e.g. "--distance-px 1e9") when that viewing distance gives
/// a pixels-per-degree value LDR-FLIP does not accept ([flip_min_ppd, flip_max_ppd]), so a bad
/// option fails when it is given, not in the middle of a comparison.
void check_flip_viewing_distance(float viewing_distance_px, const std::string& what);

struct FlipResult {
    Image error_map;      ///< 1 channel, FLIP error in [0, 1] (see docs/flip.md on the range).
    Image color_error;    ///< 1 channel, the redistributed colour error (before the feature step).
    Image feature_error;  ///< 1 channel, the feature error (edges and points), in [0, 1].
    double mean = 0;      ///< binary64 sum of error_map, row-major, divided by W*H.
    /// NVlabs's "weighted" percentiles: the error values sorted ascending, each weighted by
    /// itself; the p-percentile is the first value at which the running sum exceeds p * total
    /// (0 when every error is 0). p = 0.5, 0.25, 0.75.
    double weighted_median = 0, first_quartile = 0, third_quartile = 0;
    double min = 0, max = 0;
    std::size_t nonfinite_inputs = 0;  ///< NaN/Inf input values (both images), replaced by 0.
};

/// LDR-FLIP of `test` against `reference` (3-channel sRGB-encoded images of one size).
/// Throws fovref::Error on a size or channel mismatch, an empty image, or a pixels_per_degree
/// that is not finite or outside [flip_min_ppd, flip_max_ppd].
FlipResult ldr_flip(const Image& reference, const Image& test, const FlipParams& params);

/// The accepted pixels_per_degree range: below it the filters are narrower than a pixel (and a
/// feature filter's sigma^2 could underflow), above it they are wider than any image we handle.
inline constexpr float flip_min_ppd = 1e-3f;
inline constexpr float flip_max_ppd = 1e4f;

// -------------------------------------------------------------------------------------------
// Filters (1D; every 2D filter of FLIP is separable or a sum of two separable ones).
// -------------------------------------------------------------------------------------------

struct FlipFilters {
    /// Contrast-sensitivity filters, taps -spatial_radius..spatial_radius at x / ppd degrees:
    /// Y and Cx are single Gaussians normalised to sum 1; the Cz filter is a sum of two 2D
    /// Gaussians, split into two separable 1D parts cz1, cz2 scaled together so that the 2D
    /// filter cz1(x) cz1(y) + cz2(x) cz2(y) sums to 1 (NVlabs misc/separatedConvolutions.pdf).
    int spatial_radius = 0;
    std::vector<float> y, cx, cz1, cz2;
    /// Feature filters, taps -feature_radius..feature_radius: Gaussian g (sum 1), its first
    /// derivative dg and second derivative ddg, whose positive taps sum to 1 and negative taps
    /// to -1 (as in the paper).
    int feature_radius = 0;
    std::vector<float> g, dg, ddg;
};

/// The filters for `pixels_per_degree` (assumed validated as in ldr_flip).
FlipFilters flip_filters(float pixels_per_degree);

// -------------------------------------------------------------------------------------------
// Per-pixel math (binary32). Constants are NVlabs's (FLIP.h, v1.1+ nine-digit constants).
// -------------------------------------------------------------------------------------------

namespace flip {

struct Color3 {
    float x = 0, y = 0, z = 0;
};

inline constexpr float qc = 0.7f;   ///< colour error exponent
inline constexpr float pc = 0.4f;   ///< redistribution knee, fraction of cmax
inline constexpr float pt = 0.95f;  ///< error assigned at the knee
inline constexpr float w = 0.082f;  ///< peak-to-trough width of the edge filter, degrees
inline constexpr float qf = 0.5f;   ///< feature error exponent

/// D65 reference white (row sums of the RGB->XYZ matrix) and its reciprocal.
inline constexpr Color3 illuminant{0.950428545f, 1.000000000f, 1.088900371f};
inline constexpr Color3 inv_illuminant{1.052156925f, 1.000000000f, 0.918357670f};

/// Linear sRGB (D65) to CIE XYZ, exact rational matrix coefficients.
inline Color3 linear_rgb_to_xyz(Color3 c) {
    constexpr float a11 = 10135552.0f / 24577794.0f, a12 = 8788810.0f / 24577794.0f,
                    a13 = 4435075.0f / 24577794.0f;
    constexpr float a21 = 2613072.0f / 12288897.0f, a22 = 8788810.0f / 12288897.0f,
                    a23 = 887015.0f / 12288897.0f;
    constexpr float a31 = 1425312.0f / 73733382.0f, a32 = 8788810.0f / 73733382.0f,
                    a33 = 70074185.0f / 73733382.0f;
    return {a11 * c.x + a12 * c.y + a13 * c.z, a21 * c.x + a22 * c.y + a23 * c.z,
            a31 * c.x + a32 * c.y + a33 * c.z};
}

/// CIE XYZ to linear sRGB (the inverse matrix, nine digits).
inline Color3 xyz_to_linear_rgb(Color3 c) {
    return {3.241003275f * c.x + -1.537398934f * c.y + -0.498615861f * c.z,
            -0.969224334f * c.x + 1.875930071f * c.y + 0.041554224f * c.z,
            0.055639423f * c.x + -0.204011202f * c.y + 1.057148933f * c.z};
}

/// XYZ to the linearised opponent space YCxCz (L*a*b* without the cube root).
inline Color3 xyz_to_ycxcz(Color3 c) {
    const float x = c.x * inv_illuminant.x, y = c.y * inv_illuminant.y, z = c.z * inv_illuminant.z;
    return {116.0f * y - 16.0f, 500.0f * (x - y), 200.0f * (y - z)};
}

inline Color3 ycxcz_to_xyz(Color3 c) {
    const float y = (c.x + 16.0f) / 116.0f;
    const float cx = c.y / 500.0f, cz = c.z / 200.0f;
    return {(y + cx) * illuminant.x, y * illuminant.y, (y - cz) * illuminant.z};
}

/// The fixed powers of the per-pixel math: dm::pow(x, y) for y = 1/3, qc and qf, read through
/// dm::PowFixed's tables (the same bits as dm::pow, several times faster).
inline float pow_one_third(float x) {
    static const dm::PowFixed power(1.0f / 3.0f);
    return power(x);
}
inline float pow_qc(float x) {
    static const dm::PowFixed power(qc);
    return power(x);
}
inline float pow_qf(float x) {
    static const dm::PowFixed power(qf);
    return power(x);
}

/// CIE 1976 L*a*b* from XYZ (D65 white).
inline Color3 xyz_to_lab(Color3 c) {
    constexpr float delta = 6.0f / 29.0f;
    constexpr float delta_square = delta * delta;
    constexpr float delta_cube = delta * delta_square;
    constexpr float factor = 1.0f / (3.0f * delta_square);
    constexpr float term = 4.0f / 29.0f;
    auto f = [&](float t) { return t > delta_cube ? pow_one_third(t) : factor * t + term; };
    const float fx = f(c.x * inv_illuminant.x), fy = f(c.y * inv_illuminant.y),
                fz = f(c.z * inv_illuminant.z);
    return {116.0f * fy - 16.0f, 500.0f * (fx - fy), 200.0f * (fy - fz)};
}

/// Hunt adjustment: chroma scaled by 0.01 L.
inline Color3 hunt(Color3 lab) { return {lab.x, 0.01f * lab.x * lab.y, 0.01f * lab.x * lab.z}; }

/// HyAB distance (Abasi et al. 2020, as in the paper): |dL| + ||(da, db)||.
inline float hyab(Color3 a, Color3 b) {
    const float dl = std::fabs(a.x - b.x);
    const float da = a.y - b.y, db = a.z - b.z;
    return dl + std::sqrt(da * da + db * db);
}

/// Clamp to [0, 1] written as NVlabs's Min(Max(v, 0), 1) macros: NaN and -0 become +0.
inline float clamp01(float v) {
    v = v > 0.0f ? v : 0.0f;
    return v > 1.0f ? 1.0f : v;
}

/// Filtered YCxCz to Hunt-adjusted L*a*b*, through the clamp to the linear RGB cube.
inline Color3 filtered_ycxcz_to_hunt_lab(Color3 ycxcz) {
    const Color3 rgb = xyz_to_linear_rgb(ycxcz_to_xyz(ycxcz));
    return hunt(xyz_to_lab(linear_rgb_to_xyz({clamp01(rgb.x), clamp01(rgb.y), clamp01(rgb.z)})));
}

/// cmax = HyAB(green, blue)^qc in Hunt-adjusted L*a*b*, the largest colour distance in the
/// linear RGB cube by the paper's convention.
inline float color_cmax() {
    const Color3 green = hunt(xyz_to_lab(linear_rgb_to_xyz({0.0f, 1.0f, 0.0f})));
    const Color3 blue = hunt(xyz_to_lab(linear_rgb_to_xyz({0.0f, 0.0f, 1.0f})));
    return pow_qc(hyab(green, blue));
}

/// Colour error from two Hunt-adjusted L*a*b* colours: HyAB^qc redistributed piecewise-linearly
/// to [0, 1] with [0, pc cmax) -> [0, pt) and [pc cmax, cmax] -> [pt, 1].
inline float color_error(Color3 reference_lab, Color3 test_lab, float cmax) {
    const float pccmax = pc * cmax;
    float error = pow_qc(hyab(reference_lab, test_lab));
    if (error < pccmax) return error * (pt / pccmax);
    error = pt + ((error - pccmax) / (cmax - pccmax)) * (1.0f - pt);
    return error;
}

/// Feature error from the edge (first-derivative) and point (second-derivative)
/// responses in x and y of both images: (max(|edge_r - edge_t|, |point_r - point_t|) / sqrt 2)^qf.
/// Mathematically <= 1 (each response is at most 1 in x and in y); the min(., 1) is ours, not
/// NVlabs's: filter-sum rounding can push the value an ulp past 1, and colour^(1 - feature)
/// would then be +inf for a colour error of 0 (SPEC §0: no Inf from finite inputs).
inline float feature_error(float dx_r, float dy_r, float ddx_r, float ddy_r, float dx_t, float dy_t,
                           float ddx_t, float ddy_t) {
    const float normalization = 1.0f / std::sqrt(2.0f);
    const float edge_r = std::sqrt(dx_r * dx_r + dy_r * dy_r);
    const float edge_t = std::sqrt(dx_t * dx_t + dy_t * dy_t);
    const float point_r = std::sqrt(ddx_r * ddx_r + ddy_r * ddy_r);
    const float point_t = std::sqrt(ddx_t * ddx_t + ddy_t * ddy_t);
    const float edge_difference = std::fabs(edge_r - edge_t);
    const float point_difference = std::fabs(point_r - point_t);
    return std::min(pow_qf(normalization * std::max(edge_difference, point_difference)), 1.0f);
}

/// Final FLIP error: colour_error^(1 - feature_error).
inline float final_error(float color, float feature) { return dm::pow(color, 1.0f - feature); }

}  // namespace flip
}  // namespace fovref
