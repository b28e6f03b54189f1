// LDR-FLIP (SPEC §10). Andersson et al., "FLIP: A Difference Evaluator for Alternating Images",
// HPG 2020; the pipeline, constants, filter construction and pooling follow the authors' code,
// NVlabs/flip v1.x (FLIP.h: setSpatialFilters, setFeatureFilter, computeColorDifference,
// computeFeatureDifferenceAndFinalError; tool/pooling.h: getPercentile), re-written here.
//
//   1. Both images: replace NaN/Inf by 0 (SPEC §0), sRGB-decode, clamp to [0, 1], to YCxCz.
//   2. Colour pipeline: CSF filters (separable, x pass then y pass, clamp-to-edge borders), back
//      to linear RGB, clamp to the RGB cube, Hunt-adjusted L*a*b*, HyAB^qc, redistribution.
//   3. Feature pipeline on the normalised achromatic channel (Y + 16) / 116: edge and point
//      filters (separable, x pass then y pass, clamp-to-edge), feature error.
//   4. FLIP = colour_error^(1 - feature_error); pooled mean, weighted percentiles, min, max.
//
// Every filter sum runs over the taps in ascending order (-r..r) in binary32, as NVlabs's CPU
// code does; statistics are binary64 (docs/flip.md, precision note).
#include "ref/metrics/flip.h"

#include <algorithm>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include <emmintrin.h>

#include "ref/core/error.h"

namespace fovref {

namespace {

using flip::Color3;

/// Smallest divisor for filter normalisation sums: a sum is 0 only when every tap of that sign
/// underflowed (ppd near flip_min_ppd); the taps are then 0 and stay 0 instead of 0/0.
constexpr float tiny_sum = FLT_MIN;

// Gaussian constants of the contrast sensitivity functions (paper §4.1, Table 1), per opponent
// channel: g(x) = a1 sqrt(pi/b1) exp(-pi^2 x^2/b1) + a2 sqrt(pi/b2) exp(-pi^2 x^2/b2), x in
// degrees. Y and Cx have a2 = 0 (b2 = 1e-5 only avoids 0 in NVlabs's radius rule).
constexpr float a1_y = 1.0f, b1_y = 0.0047f;
constexpr float a1_cx = 1.0f, b1_cx = 0.0053f;
constexpr float a1_cz = 34.1f, b1_cz = 0.04f, a2_cz = 13.5f, b2_cz = 0.025f;
constexpr float b2_unused = 1.0e-5f;

/// a sqrt(pi/b) exp(-pi^2 x2 / b): one term of the CSF, x2 = x^2 in degrees^2.
float csf_gaussian(float x2, float a, float b) {
    const float pi_sq = dm::pi * dm::pi;
    return a * std::sqrt(dm::pi / b) * dm::exp(-pi_sq * x2 / b);
}

/// The separable factor of one 2D CSF term: sqrt(a sqrt(pi/b)) exp(-pi^2 x2 / b), so that
/// factor(x) factor(y) = a sqrt(pi/b) exp(-pi^2 (x^2 + y^2) / b).
float csf_gaussian_factor(float x2, float a, float b) {
    const float pi_sq = dm::pi * dm::pi;
    return std::sqrt(a * std::sqrt(dm::pi / b)) * dm::exp(-pi_sq * x2 / b);
}

/// Clamp-to-edge index (NVlabs: Min(Max(0, i), n - 1)).
int clamp_index(int i, int n) { return std::min(std::max(0, i), n - 1); }

/// Step 1 for one image: sanitised, decoded, clamped and converted to YCxCz, 3 planes.
struct Planes3 {
    std::vector<float> a, b, c;
};

Planes3 to_ycxcz(const Image& image, std::size_t& nonfinite) {
    const std::size_t n = image.pixel_count();
    Planes3 out{std::vector<float>(n), std::vector<float>(n), std::vector<float>(n)};
    for (std::size_t i = 0; i < n; ++i) {
        float rgb[3];
        for (int ch = 0; ch < 3; ++ch) {
            float v = image.data[i * 3 + ch];
            if (!std::isfinite(v)) {
                v = 0.0f;
                ++nonfinite;
            }
            // NVlabs v1.4+: decode, then clamp the linear value to [0, 1] (FLIP::evaluate).
            rgb[ch] = flip::clamp01(srgb_decode(v));
        }
        const Color3 ycxcz = flip::xyz_to_ycxcz(flip::linear_rgb_to_xyz({rgb[0], rgb[1], rgb[2]}));
        out.a[i] = ycxcz.x;
        out.b[i] = ycxcz.y;
        out.c[i] = ycxcz.z;
    }
    return out;
}

// The filters run row by row: one tap at a time over a whole row (acc[x] += w * in[x]), so each
// pixel's sum still adds its taps in ascending order from 0, one binary32 multiply and one add per
// tap, exactly as a per-pixel loop would (bit-identical), while the row loop runs four pixels per
// SSE2 instruction.

/// acc[x] += w * in[x] for x in [0, n): per lane the same multiply, then add (no FMA).
void add_tap(float* __restrict acc, const float* __restrict in, float w, int n) {
    const __m128 wv = _mm_set1_ps(w);
    int x = 0;
    for (; x + 4 <= n; x += 4)
        _mm_storeu_ps(acc + x,
                      _mm_add_ps(_mm_loadu_ps(acc + x), _mm_mul_ps(wv, _mm_loadu_ps(in + x))));
    for (; x < n; ++x) acc[x] += w * in[x];
}

/// Horizontal pass of one row, clamp-to-edge: out[x] = sum over ix = -r .. r (in that order) of
/// taps[ix + r] in[clamp(x + ix)]. `padded` is scratch for the row with r edge copies each side.
void filter_row(const float* in, float* out, const std::vector<float>& taps, int r, int width,
                std::vector<float>& padded) {
    padded.resize(static_cast<std::size_t>(width + 2 * r));
    for (int i = 0; i < width + 2 * r; ++i) padded[i] = in[clamp_index(i - r, width)];
    std::fill(out, out + width, 0.0f);
    for (int k = 0; k <= 2 * r; ++k) add_tap(out, padded.data() + k, taps[k], width);
}

/// Vertical pass at row y, clamp-to-edge: out[x] = sum over iy = -r .. r (in that order) of
/// taps[iy + r] plane[clamp(y + iy)][x].
void filter_column(const std::vector<float>& plane, float* out, const std::vector<float>& taps,
                   int r, int width, int height, int y) {
    std::fill(out, out + width, 0.0f);
    for (int k = 0; k <= 2 * r; ++k)
        add_tap(out,
                plane.data() + static_cast<std::size_t>(clamp_index(y + k - r, height)) * width,
                taps[k], width);
}

// Step 2's x pass of one image: Y*fy, Cx*fcx, Cz*fcz1, Cz*fcz2 (the two separable parts of Cz).
struct ColorXPass {
    std::vector<float> y, cx, cz1, cz2;
};

ColorXPass color_x_pass(const Planes3& in, const FlipFilters& f, int width, int height) {
    const std::size_t n = static_cast<std::size_t>(width) * height;
    const int r = f.spatial_radius;
    ColorXPass out{std::vector<float>(n), std::vector<float>(n), std::vector<float>(n),
                   std::vector<float>(n)};
    std::vector<float> padded;
    for (int y = 0; y < height; ++y) {
        const std::size_t row = static_cast<std::size_t>(y) * width;
        filter_row(&in.a[row], &out.y[row], f.y, r, width, padded);
        filter_row(&in.b[row], &out.cx[row], f.cx, r, width, padded);
        filter_row(&in.c[row], &out.cz1[row], f.cz1, r, width, padded);
        filter_row(&in.c[row], &out.cz2[row], f.cz2, r, width, padded);
    }
    return out;
}

/// Step 2's y pass of one image at row y: the filtered Y, Cx and the two parts of Cz.
struct ColorRows {
    std::vector<float> y, cx, cz1, cz2;
    explicit ColorRows(int width) : y(width), cx(width), cz1(width), cz2(width) {}
    void filter(const ColorXPass& in, const FlipFilters& f, int width, int height, int row) {
        const int r = f.spatial_radius;
        filter_column(in.y, y.data(), f.y, r, width, height, row);
        filter_column(in.cx, cx.data(), f.cx, r, width, height, row);
        filter_column(in.cz1, cz1.data(), f.cz1, r, width, height, row);
        filter_column(in.cz2, cz2.data(), f.cz2, r, width, height, row);
    }
    /// Filtered YCxCz at x (Cz = its two separable parts added).
    Color3 at(int x) const { return Color3{y[x], cx[x], cz1[x] + cz2[x]}; }
};

/// Step 2: CSF filtering and the colour error per pixel (y pass, then Hunt-adjusted L*a*b*).
std::vector<float> color_error_map(const Planes3& ref, const Planes3& test, const FlipFilters& f,
                                   int width, int height) {
    const float cmax = flip::color_cmax();
    const ColorXPass ref_x = color_x_pass(ref, f, width, height);
    const ColorXPass test_x = color_x_pass(test, f, width, height);
    std::vector<float> error(static_cast<std::size_t>(width) * height);
    ColorRows ref_rows(width), test_rows(width);
    for (int y = 0; y < height; ++y) {
        ref_rows.filter(ref_x, f, width, height, y);
        test_rows.filter(test_x, f, width, height, y);
        for (int x = 0; x < width; ++x) {
            const Color3 ref_lab = flip::filtered_ycxcz_to_hunt_lab(ref_rows.at(x));
            const Color3 test_lab = flip::filtered_ycxcz_to_hunt_lab(test_rows.at(x));
            error[static_cast<std::size_t>(y) * width + x] =
                flip::color_error(ref_lab, test_lab, cmax);
        }
    }
    return error;
}

// Step 3's x pass on the achromatic channel normalised to [0, 1]: Y/116 + 16/116 (NVlabs's
// order): first and second x-derivative and the x-Gaussian.
struct FeatureXPass {
    std::vector<float> dx, ddx, gx;
};

FeatureXPass feature_x_pass(const std::vector<float>& luma, const FlipFilters& f, int width,
                            int height) {
    const std::size_t n = static_cast<std::size_t>(width) * height;
    const int r = f.feature_radius;
    const float one_over_116 = 1.0f / 116.0f;
    const float sixteen_over_116 = 16.0f / 116.0f;
    FeatureXPass out{std::vector<float>(n), std::vector<float>(n), std::vector<float>(n)};
    std::vector<float> normalised(static_cast<std::size_t>(width)), padded;
    for (int y = 0; y < height; ++y) {
        const std::size_t row = static_cast<std::size_t>(y) * width;
        for (int x = 0; x < width; ++x)
            normalised[x] = luma[row + x] * one_over_116 + sixteen_over_116;
        filter_row(normalised.data(), &out.dx[row], f.dg, r, width, padded);
        filter_row(normalised.data(), &out.ddx[row], f.ddg, r, width, padded);
        filter_row(normalised.data(), &out.gx[row], f.g, r, width, padded);
    }
    return out;
}

// Step 3's y pass at row y: the x-derivatives are smoothed by the y-Gaussian; the
// y-derivatives are taken of the x-Gaussian-smoothed image.
struct FeatureRows {
    std::vector<float> dx, dy, ddx, ddy;
    explicit FeatureRows(int width) : dx(width), dy(width), ddx(width), ddy(width) {}
    void filter(const FeatureXPass& in, const FlipFilters& f, int width, int height, int row) {
        const int r = f.feature_radius;
        filter_column(in.dx, dx.data(), f.g, r, width, height, row);
        filter_column(in.ddx, ddx.data(), f.g, r, width, height, row);
        filter_column(in.gx, dy.data(), f.dg, r, width, height, row);
        filter_column(in.gx, ddy.data(), f.ddg, r, width, height, row);
    }
};

/// Step 3: edge and point responses of both images and the feature error per pixel.
std::vector<float> feature_error_map(const Planes3& ref, const Planes3& test, const FlipFilters& f,
                                     int width, int height) {
    const FeatureXPass ref_x = feature_x_pass(ref.a, f, width, height);
    const FeatureXPass test_x = feature_x_pass(test.a, f, width, height);
    std::vector<float> error(static_cast<std::size_t>(width) * height);
    FeatureRows a(width), b(width);
    for (int y = 0; y < height; ++y) {
        a.filter(ref_x, f, width, height, y);
        b.filter(test_x, f, width, height, y);
        for (int x = 0; x < width; ++x)
            error[static_cast<std::size_t>(y) * width + x] = flip::feature_error(
                a.dx[x], a.dy[x], a.ddx[x], a.ddy[x], b.dx[x], b.dy[x], b.ddx[x], b.ddy[x]);
    }
    return error;
}

/// NVlabs's weighted percentile (tool/pooling.h getPercentile(p, true)): values sorted
/// ascending, the first one at which the running sum exceeds p * total. Equal keys are equal
/// floats (the map holds no -0: every value is +0 or positive), so no tie-break can change the
/// result. The total is the sum in the same sorted order, so the running sum reaches it exactly
/// and a positive total always finds a value; an all-zero map gives 0.
double weighted_percentile(const std::vector<float>& sorted, double total, double p) {
    double running = 0.0;
    for (float v : sorted) {
        running += v;
        if (running > p * total) return v;
    }
    return 0.0;
}

/// The values in ascending order, for non-negative floats (+0 included, no -0, no NaN): their
/// bit patterns order as the values do, so an LSD radix sort on the bits (three passes of 11
/// bits) gives the same sequence as std::sort, in linear time.
std::vector<float> sorted_non_negative(const std::vector<float>& values) {
    std::vector<std::uint32_t> keys(values.size()), scratch(values.size());
    for (std::size_t i = 0; i < values.size(); ++i) {
        keys[i] = std::bit_cast<std::uint32_t>(values[i]);
        FOVREF_CHECK(keys[i] <= 0x7f800000u, "FLIP error map holds a negative value or NaN");
    }
    for (int shift = 0; shift < 32; shift += 11) {
        std::vector<std::size_t> start(2049, 0);
        for (std::uint32_t k : keys) ++start[((k >> shift) & 2047u) + 1];
        for (std::size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
        for (std::uint32_t k : keys) scratch[start[(k >> shift) & 2047u]++] = k;
        keys.swap(scratch);
    }
    std::vector<float> sorted(values.size());
    for (std::size_t i = 0; i < keys.size(); ++i) sorted[i] = std::bit_cast<float>(keys[i]);
    return sorted;
}

void check_input(const Image& image, const char* name) {
    if (image.channels != 3)
        throw Error(std::string("ldr_flip: ") + name + " has " + std::to_string(image.channels) +
                    " channels, LDR-FLIP needs 3 (sRGB-encoded RGB)");
    if (image.width <= 0 || image.height <= 0)
        throw Error(std::string("ldr_flip: ") + name + " is empty (" + std::to_string(image.width) +
                    "x" + std::to_string(image.height) + ")");
    if (image.data.size() != image.pixel_count() * 3)
        throw Error(std::string("ldr_flip: ") + name + " holds " +
                    std::to_string(image.data.size()) + " floats, expected " +
                    std::to_string(image.pixel_count() * 3));
}

}  // namespace

void check_flip_viewing_distance(float viewing_distance_px, const std::string& what) {
    const float ppd = flip_pixels_per_degree(viewing_distance_px);
    if (!(std::isfinite(ppd) && ppd >= flip_min_ppd && ppd <= flip_max_ppd)) {
        char text[160];
        std::snprintf(text, sizeof text,
                      ": with --flip the viewing distance must give %g to %g pixels per degree; "
                      "it gives %g",
                      static_cast<double>(flip_min_ppd), static_cast<double>(flip_max_ppd),
                      static_cast<double>(ppd));
        throw Error(what + text);
    }
}

float flip_pixels_per_degree(float viewing_distance_px) {
    if (!std::isfinite(viewing_distance_px) || viewing_distance_px <= 0.0f)
        throw Error("flip_pixels_per_degree: viewing distance must be finite and > 0, got " +
                    std::to_string(viewing_distance_px) + " px");
    return viewing_distance_px * dm::radians(1.0f);
}

namespace {

// Contrast sensitivity filters. Radius: 3 standard deviations of the widest Gaussian
// (b = 0.04: sigma = sqrt(b / (2 pi^2)) degrees), in pixels (NVlabs
// calculateSpatialFilterRadius).
void csf_filters(float ppd, FlipFilters& f) {
    const float pi_sq = dm::pi * dm::pi;
    const float max_b = std::max(std::max(std::max(b1_y, b1_cx), std::max(b1_cz, b2_unused)),
                                 std::max(b2_unused, b2_cz));
    f.spatial_radius = static_cast<int>(std::ceil(3.0f * std::sqrt(max_b / (2.0f * pi_sq)) * ppd));
    const int width = 2 * f.spatial_radius + 1;
    const float delta_x = 1.0f / ppd;  // degrees per pixel
    f.y.resize(width);
    f.cx.resize(width);
    f.cz1.resize(width);
    f.cz2.resize(width);
    float sum_y = 0.0f, sum_cx = 0.0f, sum_cz1 = 0.0f, sum_cz2 = 0.0f;
    for (int i = 0; i < width; ++i) {
        const float x = static_cast<float>(i - f.spatial_radius) * delta_x;
        const float x2 = x * x;
        f.y[i] = csf_gaussian(x2, a1_y, b1_y);
        f.cx[i] = csf_gaussian(x2, a1_cx, b1_cx);
        f.cz1[i] = csf_gaussian_factor(x2, a1_cz, b1_cz);
        f.cz2[i] = csf_gaussian_factor(x2, a2_cz, b2_cz);
        sum_y += f.y[i];
        sum_cx += f.cx[i];
        sum_cz1 += f.cz1[i];
        sum_cz2 += f.cz2[i];
    }
    // Y, Cx: each 1D filter sums to 1, so the 2D product does. Cz: the 2D filter
    // cz1 (x) cz1 + cz2 (x) cz2 sums to sum_cz1^2 + sum_cz2^2; one common factor fixes it.
    const float norm_y = 1.0f / sum_y;
    const float norm_cx = 1.0f / sum_cx;
    const float norm_cz = 1.0f / std::sqrt(sum_cz1 * sum_cz1 + sum_cz2 * sum_cz2);
    for (int i = 0; i < width; ++i) {
        f.y[i] *= norm_y;
        f.cx[i] *= norm_cx;
        f.cz1[i] *= norm_cz;
        f.cz2[i] *= norm_cz;
    }
}

// Feature filters: Gaussian of sigma = w/2 degrees = 0.5 w ppd pixels, radius 3 sigma; the
// derivatives' positive and negative taps are normalised separately (paper §4.2).
void feature_filters(float ppd, FlipFilters& f) {
    const float sigma = 0.5f * flip::w * ppd;
    f.feature_radius = static_cast<int>(std::ceil(3.0f * sigma));
    const int width = 2 * f.feature_radius + 1;
    f.g.resize(width);
    f.dg.resize(width);
    f.ddg.resize(width);
    float g_sum = 0.0f, dg_positive = 0.0f, dg_negative = 0.0f, ddg_positive = 0.0f,
          ddg_negative = 0.0f;
    for (int i = 0; i < width; ++i) {
        const float x = static_cast<float>(i - f.feature_radius);
        const float g = dm::exp(-(x * x) / (2.0f * sigma * sigma));
        const float dg = -x * g;
        const float ddg = (x * x / (sigma * sigma) - 1.0f) * g;
        g_sum += g;
        if (dg > 0.0f) {
            dg_positive += dg;
        } else {
            dg_negative -= dg;
        }
        if (ddg > 0.0f) {
            ddg_positive += ddg;
        } else {
            ddg_negative -= ddg;
        }
        f.g[i] = g;
        f.dg[i] = dg;
        f.ddg[i] = ddg;
    }
    for (int i = 0; i < width; ++i) {
        f.g[i] = f.g[i] / std::max(g_sum, tiny_sum);
        f.dg[i] = f.dg[i] / std::max(f.dg[i] > 0.0f ? dg_positive : dg_negative, tiny_sum);
        f.ddg[i] = f.ddg[i] / std::max(f.ddg[i] > 0.0f ? ddg_positive : ddg_negative, tiny_sum);
    }
}

}  // namespace

FlipFilters flip_filters(float ppd) {
    FlipFilters f;
    csf_filters(ppd, f);
    feature_filters(ppd, f);
    return f;
}

FlipResult ldr_flip(const Image& reference, const Image& test, const FlipParams& params) {
    // Check the inputs and the observer.
    check_input(reference, "reference");
    check_input(test, "test");
    if (reference.width != test.width || reference.height != test.height)
        throw Error("ldr_flip: reference is " + std::to_string(reference.width) + "x" +
                    std::to_string(reference.height) + ", test is " + std::to_string(test.width) +
                    "x" + std::to_string(test.height) + " (sizes must match)");
    const float ppd = params.pixels_per_degree;
    if (!std::isfinite(ppd) || ppd < flip_min_ppd || ppd > flip_max_ppd)
        throw Error("ldr_flip: pixels_per_degree must be finite and in [" +
                    std::to_string(flip_min_ppd) + ", " + std::to_string(flip_max_ppd) + "], got " +
                    std::to_string(ppd));

    const int width = reference.width, height = reference.height;
    const std::size_t n = reference.pixel_count();
    FlipResult result;

    // Step 1: to YCxCz.
    const Planes3 ref_ycxcz = to_ycxcz(reference, result.nonfinite_inputs);
    const Planes3 test_ycxcz = to_ycxcz(test, result.nonfinite_inputs);

    // Steps 2-4: colour error, feature error, FLIP.
    const FlipFilters filters = flip_filters(ppd);
    const std::vector<float> color = color_error_map(ref_ycxcz, test_ycxcz, filters, width, height);
    const std::vector<float> feature =
        feature_error_map(ref_ycxcz, test_ycxcz, filters, width, height);
    result.color_error = Image(width, height, 1);
    result.feature_error = Image(width, height, 1);
    result.error_map = Image(width, height, 1);
    for (std::size_t i = 0; i < n; ++i) {
        result.color_error.data[i] = color[i];
        result.feature_error.data[i] = feature[i];
        result.error_map.data[i] = flip::final_error(color[i], feature[i]);
        FOVREF_CHECK(std::isfinite(result.error_map.data[i]),
                     "FLIP error at pixel " + std::to_string(i) + " is not finite");
    }

    // Pooling: mean (binary64, row-major), min, max, weighted percentiles.
    double sum = 0.0;
    float lo = result.error_map.data[0], hi = result.error_map.data[0];
    for (float v : result.error_map.data) {
        sum += v;
        lo = std::min(lo, v);
        hi = std::max(hi, v);
    }
    result.mean = sum / static_cast<double>(n);
    result.min = lo;
    result.max = hi;
    const std::vector<float> sorted = sorted_non_negative(result.error_map.data);
    double total = 0.0;
    for (float v : sorted) total += v;
    result.weighted_median = weighted_percentile(sorted, total, 0.5);
    result.first_quartile = weighted_percentile(sorted, total, 0.25);
    result.third_quartile = weighted_percentile(sorted, total, 0.75);
    return result;
}

}  // namespace fovref
