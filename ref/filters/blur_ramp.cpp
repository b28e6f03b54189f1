#include "ref/filters/blur_ramp.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/core/vec.h"

namespace fovref {

namespace {

void check_inputs(const BlurRamp& ramp, const BlurRampGeometry& geometry, const Image& image) {
    if (!(std::isfinite(ramp.sigma_deg) && ramp.sigma_deg >= 0.0f))
        throw Error("blur ramp: sigma_deg must be finite and >= 0 (got " +
                    check_value_text(ramp.sigma_deg) + ")");
    if (!std::isfinite(ramp.full_deg))
        throw Error("blur ramp: full_deg must be finite (got " + check_value_text(ramp.full_deg) +
                    ")");
    FOVREF_CHECK_EQ(image.width, geometry.screen_width, "blur ramp image width");
    FOVREF_CHECK_EQ(image.height, geometry.screen_height, "blur ramp image height");
}

/// One pass along x (`vertical` false) or y (true).
Image blur_pass(const BlurRamp& ramp, const BlurRampGeometry& geometry, const Image& image,
                bool vertical) {
    check_inputs(ramp, geometry, image);
    Image out = image;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            blur_ramp_pixel(ramp, geometry, image, vertical, out, x, y);
    return out;
}

}  // namespace

float blur_ramp_sigma_px(const BlurRamp& ramp, const BlurRampGeometry& geometry, glm::vec2 p) {
    const float e = gaze_distance(geometry.gaze, p) / geometry.scale;
    const float fovea_edge = geometry.fovea_deg;
    float sigma = 0.0f;  // model degrees
    if (e <= fovea_edge)
        sigma = 0.0f;
    else if (e >= ramp.full_deg)
        sigma = ramp.sigma_deg;
    else
        sigma = ramp.sigma_deg * (e - fovea_edge) / (ramp.full_deg - fovea_edge);
    return sigma * geometry.scale;
}

int blur_ramp_radius(float sigma_px) {
    if (!(sigma_px > 0.0f)) return 0;
    const float radius = std::ceil(3.0f * sigma_px);
    return radius >= static_cast<float>(blur_ramp_max_radius) ? blur_ramp_max_radius
                                                              : static_cast<int>(radius);
}

void blur_ramp_pixel(const BlurRamp& ramp, const BlurRampGeometry& geometry, const Image& image,
                     bool vertical, Image& out, int x, int y) {
    const int width = image.width, height = image.height, channels = image.channels;
    const glm::vec2 centre = pixel_centre(x, y);
    const float sigma = blur_ramp_sigma_px(ramp, geometry, centre);
    const int radius = blur_ramp_radius(sigma);
    if (radius == 0) return;  // copied

    // Gaussian weights w_|d| = a^(d^2), a = exp(-1 / (2 sigma^2)), d = 0 .. R, by the
    // recurrence w_d = w_(d-1) g_d, g_d = g_(d-1) a^2 (g_1 = a): one exp per pixel
    float weights[blur_ramp_max_radius + 1];
    const float a = dm::exp(-1.0f / (2.0f * sigma * sigma));
    const float a2 = a * a;
    weights[0] = 1.0f;
    float g = a;
    for (int d = 1; d <= radius; ++d) {
        weights[d] = weights[d - 1] * g;
        g = g * a2;
    }
    // Normalised: the sum over the taps -R .. R (from -R up), then each weight / sum
    float weight_sum = 0.0f;
    for (int d = -radius; d <= radius; ++d) weight_sum += weights[d < 0 ? -d : d];
    const float inverse = 1.0f / weight_sum;
    for (int d = 0; d <= radius; ++d) weights[d] = weights[d] * inverse;

    // The weighted sum over the taps -R .. R, clamped to the border
    const int extent = vertical ? height : width;
    const std::ptrdiff_t stride =  // floats from one pixel to the next along the pass
        vertical ? static_cast<std::ptrdiff_t>(width) * channels : channels;
    const int position = vertical ? y : x;
    const float* centre_pixel = &image.data[image.index(x, y)];
    const bool inside = position - radius >= 0 && position + radius < extent;
    const auto offset = [&](int d) -> std::ptrdiff_t {
        return (inside ? d : std::clamp(position + d, 0, extent - 1) - position) * stride;
    };
    float* o = &out.data[out.index(x, y)];
    if (channels == 3) {  // the colour images of the modes: sums kept in registers
        float m0 = 0.0f, m1 = 0.0f, m2 = 0.0f;
        for (int d = -radius; d <= radius; ++d) {
            const float weight = weights[d < 0 ? -d : d];
            const float* source = centre_pixel + offset(d);
            m0 += weight * source[0];
            m1 += weight * source[1];
            m2 += weight * source[2];
        }
        o[0] = m0, o[1] = m1, o[2] = m2;
        return;
    }
    std::vector<float> mean(static_cast<std::size_t>(channels), 0.0f);
    for (int d = -radius; d <= radius; ++d) {
        const float weight = weights[d < 0 ? -d : d];
        const float* source = centre_pixel + offset(d);
        for (int c = 0; c < channels; ++c) mean[static_cast<std::size_t>(c)] += weight * source[c];
    }
    for (int c = 0; c < channels; ++c) o[c] = mean[static_cast<std::size_t>(c)];
}

Image blur_ramp_horizontal(const BlurRamp& ramp, const BlurRampGeometry& geometry,
                           const Image& image) {
    return blur_pass(ramp, geometry, image, false);
}

Image blur_ramp_vertical(const BlurRamp& ramp, const BlurRampGeometry& geometry,
                         const Image& image) {
    return blur_pass(ramp, geometry, image, true);
}

Image blur_ramp(const BlurRamp& ramp, const BlurRampGeometry& geometry, const Image& image) {
    return blur_ramp_vertical(ramp, geometry, blur_ramp_horizontal(ramp, geometry, image));
}

}  // namespace fovref
