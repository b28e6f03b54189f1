#include "ref/metrics/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <emmintrin.h>

#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/image/image_io.h"
#include "ref/image/srgb.h"

namespace fovref {

Image to_display(const Image& linear) {
    Image out(linear.width, linear.height, linear.channels);
    const dm::PowFixed& power = srgb_encode_power();
    // In blocks: the values on the power segment of the curve, (0.0031308, 1), go through
    // PowFixed::apply (vectorised; the same bits as srgb_encode); the others get 0.5 there and
    // their own segment below. Four values per SSE instruction; per lane the same operations as
    //   v <= 0.0031308 or NaN: v > 0 ? 12.92 v : +0;   v >= 1: 1 (srgb_encode(1) rounds to
    //   1 - 1 ulp in binary32: white stays exactly 1);   else min(1.055 v^(1/2.4) - 0.055, 1).
    constexpr std::size_t block = 1024;
    alignas(16) float argument[block], powered[block];
    const __m128 knee = _mm_set1_ps(0.0031308f), one = _mm_set1_ps(1.0f), half = _mm_set1_ps(0.5f);
    const __m128 slope = _mm_set1_ps(12.92f), zero = _mm_setzero_ps();
    const __m128 scale = _mm_set1_ps(1.055f), offset = _mm_set1_ps(0.055f);
    const auto select = [](__m128 mask, __m128 a, __m128 b) {
        return _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, b));
    };
    for (std::size_t start = 0; start < linear.data.size(); start += block) {
        const std::size_t n = std::min(block, linear.data.size() - start);
        const float* v = linear.data.data() + start;
        float* o = out.data.data() + start;
        std::size_t i = 0;
        for (; i + 4 <= n; i += 4) {
            const __m128 x = _mm_loadu_ps(v + i);
            const __m128 mid = _mm_and_ps(_mm_cmpgt_ps(x, knee), _mm_cmplt_ps(x, one));
            _mm_store_ps(argument + i, select(mid, x, half));
        }
        for (; i < n; ++i) argument[i] = v[i] > 0.0031308f && v[i] < 1.0f ? v[i] : 0.5f;
        power.apply(argument, powered, n);
        for (i = 0; i + 4 <= n; i += 4) {
            const __m128 x = _mm_loadu_ps(v + i);
            const __m128 linear_part = _mm_and_ps(_mm_cmpgt_ps(x, zero), _mm_mul_ps(slope, x));
            const __m128 curve =
                _mm_min_ps(_mm_sub_ps(_mm_mul_ps(scale, _mm_load_ps(powered + i)), offset), one);
            _mm_storeu_ps(o + i, select(_mm_cmpngt_ps(x, knee), linear_part,
                                        select(_mm_cmpge_ps(x, one), one, curve)));
        }
        for (; i < n; ++i) {
            if (!(v[i] > 0.0031308f))
                o[i] = v[i] > 0.0f ? 12.92f * v[i] : 0.0f;
            else if (v[i] >= 1.0f)
                o[i] = 1.0f;
            else
                o[i] = std::min(srgb_encode_from_power(powered[i]), 1.0f);
        }
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
