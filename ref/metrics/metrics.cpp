#include "ref/metrics/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/image/image_io.h"

namespace fovref {

Image to_display(const Image& linear) {
    Image out(linear.width, linear.height, linear.channels);
    for (std::size_t i = 0; i < linear.data.size(); ++i) {
        const float v = linear.data[i];
        // NaN fails both comparisons and ends at 0.
        const float clamped = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
        // srgb_encode(1) rounds to 1 - 1 ulp in binary32: white stays exactly 1.
        out.data[i] = clamped == 1.0f ? 1.0f : std::min(srgb_encode(clamped), 1.0f);
    }
    return out;
}

Image luma(const Image& image) {
    if (image.channels == 1) return image;
    if (image.channels != 3)
        throw Error("luma needs a 1- or 3-channel image, got " + std::to_string(image.channels) +
                    " channels");
    Image out(image.width, image.height, 1);
    for (std::size_t p = 0; p < image.pixel_count(); ++p) {
        const float* rgb = &image.data[3 * p];
        out.data[p] = 0.2126f * rgb[0] + 0.7152f * rgb[1] + 0.0722f * rgb[2];
    }
    return out;
}

void check_same_shape(const Image& a, const Image& b, const char* what) {
    if (a.same_shape(b)) return;
    auto shape = [](const Image& i) {
        return std::to_string(i.width) + "x" + std::to_string(i.height) + "x" +
               std::to_string(i.channels);
    };
    throw Error(std::string(what) + ": images differ in shape: " + shape(a) + " vs " + shape(b));
}

double mse(const Image& a, const Image& b) {
    check_same_shape(a, b, "mse");
    if (a.data.empty()) return 0.0;
    double sum = 0.0;
    for (std::size_t i = 0; i < a.data.size(); ++i) {
        const double d = static_cast<double>(a.data[i]) - static_cast<double>(b.data[i]);
        sum += d * d;
    }
    return sum / static_cast<double>(a.data.size());
}

double psnr(double mse_value, double data_range) {
    if (mse_value == 0.0) return std::numeric_limits<double>::infinity();
    return 10.0 * dm::log10_d(data_range * data_range / mse_value);
}

Image squared_error_map(const Image& a, const Image& b) {
    check_same_shape(a, b, "squared error map");
    Image out(a.width, a.height, 1);
    const auto channels = static_cast<std::size_t>(a.channels);
    for (std::size_t p = 0; p < a.pixel_count(); ++p) {
        double sum = 0.0;
        for (std::size_t c = 0; c < channels; ++c) {
            const double d = static_cast<double>(a.data[p * channels + c]) -
                             static_cast<double>(b.data[p * channels + c]);
            sum += d * d;
        }
        out.data[p] = static_cast<float>(sum / static_cast<double>(channels));
    }
    return out;
}

Image abs_error_map(const Image& a, const Image& b) {
    check_same_shape(a, b, "absolute error map");
    Image out(a.width, a.height, 1);
    const auto channels = static_cast<std::size_t>(a.channels);
    for (std::size_t p = 0; p < a.pixel_count(); ++p) {
        float largest = 0.0f;
        for (std::size_t c = 0; c < channels; ++c)
            largest =
                std::max(largest, std::fabs(a.data[p * channels + c] - b.data[p * channels + c]));
        out.data[p] = largest;
    }
    return out;
}

double temporal_error(const std::vector<Image>& frames) {
    if (frames.size() < 2) return 0.0;
    double total = 0.0;
    Image previous = luma(frames[0]);
    for (std::size_t t = 1; t < frames.size(); ++t) {
        Image current = luma(frames[t]);
        check_same_shape(previous, current, "temporal error");
        double sum = 0.0;
        for (std::size_t p = 0; p < current.data.size(); ++p)
            sum += std::fabs(static_cast<double>(current.data[p]) - previous.data[p]);
        total += current.data.empty() ? 0.0 : sum / static_cast<double>(current.data.size());
        previous = std::move(current);
    }
    return total / static_cast<double>(frames.size() - 1);
}

}  // namespace fovref
