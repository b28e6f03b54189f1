#include "ref/metrics/rings.h"

#include <cmath>
#include <limits>
#include <string>

#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/core/vec.h"
#include "ref/metrics/metrics.h"

namespace fovref {

float eccentricity_deg(glm::vec2 p, glm::vec2 gaze, float distance_px) {
    return dm::degrees(dm::atan(gaze_distance(gaze, p) / distance_px));
}

int ring_of(float eccentricity, float ring_width, int count) {
    if (!std::isfinite(eccentricity) || !(eccentricity >= 0.0f)) return -1;
    if (!(eccentricity < static_cast<float>(count) * ring_width)) return -1;
    // Estimate, then settle the half-open bounds with the same products as inner()/outer().
    int k = static_cast<int>(eccentricity / ring_width);
    if (k > count - 1) k = count - 1;
    while (k > 0 && static_cast<float>(k) * ring_width > eccentricity) --k;
    while (k < count - 1 && static_cast<float>(k + 1) * ring_width <= eccentricity) ++k;
    return k;
}

RingLayout ring_layout(int width, int height, glm::vec2 gaze, float distance_px,
                       const RingSettings& settings) {
    if (settings.count < 1 || settings.count > 1000)
        throw Error("rings: the number of rings must be 1..1000, got " +
                    std::to_string(settings.count));
    if (!(settings.max_range > 0.0f && settings.max_range <= 1.0f))
        throw Error("rings: max_range must be in (0, 1], got " +
                    std::to_string(settings.max_range));
    if (!(std::isfinite(distance_px) && distance_px > 0.0f))
        throw Error("rings: the viewing distance must be finite and > 0 pixels");
    if (!std::isfinite(gaze.x) || !std::isfinite(gaze.y))
        throw Error("rings: the gaze point must be finite");
    if (width < 1 || height < 1) throw Error("rings: empty image");
    RingLayout layout;
    layout.width = width;
    layout.height = height;
    layout.gaze = gaze;
    layout.distance_px = distance_px;
    layout.count = settings.count;
    const float w = static_cast<float>(width), h = static_cast<float>(height);
    const glm::vec2 corners[4] = {{0.0f, 0.0f}, {w, 0.0f}, {0.0f, h}, {w, h}};
    for (const glm::vec2& corner : corners)
        layout.max_eccentricity_deg =
            std::max(layout.max_eccentricity_deg, eccentricity_deg(corner, gaze, distance_px));
    layout.outer_deg = settings.max_range * layout.max_eccentricity_deg;
    layout.ring_width_deg = layout.outer_deg / static_cast<float>(settings.count);
    layout.ring.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), -1);
    if (!(layout.ring_width_deg > 0.0f)) return layout;  // gaze-sized screen: nothing to split
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const glm::vec2 centre = pixel_centre(x, y);
            layout.ring[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                        static_cast<std::size_t>(x)] =
                static_cast<std::int16_t>(ring_of(eccentricity_deg(centre, gaze, distance_px),
                                                  layout.ring_width_deg, layout.count));
        }
    return layout;
}

std::vector<double> ring_means(const Image& map, const RingLayout& layout) {
    if (map.channels != 1 || map.width != layout.width || map.height != layout.height)
        throw Error("ring means: the map is " + std::to_string(map.width) + "x" +
                    std::to_string(map.height) + "x" + std::to_string(map.channels) +
                    ", the ring layout " + std::to_string(layout.width) + "x" +
                    std::to_string(layout.height) + "x1");
    const auto n = static_cast<std::size_t>(layout.count);
    std::vector<double> sum(n, 0.0);
    std::vector<std::int64_t> count(n, 0);
    for (std::size_t p = 0; p < map.data.size(); ++p) {
        const int k = layout.ring[p];
        if (k < 0) continue;
        sum[static_cast<std::size_t>(k)] += map.data[p];
        ++count[static_cast<std::size_t>(k)];
    }
    for (std::size_t k = 0; k < n; ++k)
        sum[k] = count[k] > 0 ? sum[k] / static_cast<double>(count[k])
                              : std::numeric_limits<double>::quiet_NaN();
    return sum;
}

std::vector<RingStats> ring_errors(const Image& a, const Image& b, const RingLayout& layout,
                                   const SsimMap* ssim) {
    check_same_shape(a, b, "ring errors");
    if (a.width != layout.width || a.height != layout.height)
        throw Error("ring errors: the ring layout is for " + std::to_string(layout.width) + "x" +
                    std::to_string(layout.height) + ", the images are " + std::to_string(a.width) +
                    "x" + std::to_string(a.height));
    const auto n = static_cast<std::size_t>(layout.count);
    std::vector<double> sum(n, 0.0), ssim_sum(n, 0.0);
    std::vector<std::int64_t> ssim_count(n, 0);
    std::vector<RingStats> stats(n);
    // Per-pixel squared error, the channel mean of (a - b)^2, in binary64.
    std::vector<double> se(a.pixel_count());
    const auto channels = static_cast<std::size_t>(a.channels);
    for (std::size_t p = 0; p < se.size(); ++p) {
        double e = 0.0;
        for (std::size_t c = 0; c < channels; ++c) {
            const double d = static_cast<double>(a.data[p * channels + c]) -
                             static_cast<double>(b.data[p * channels + c]);
            e += d * d;
        }
        se[p] = e / static_cast<double>(channels);
    }
    // Pass 1: counts, means, SSIM sums.
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            const std::size_t p = static_cast<std::size_t>(y) * static_cast<std::size_t>(a.width) +
                                  static_cast<std::size_t>(x);
            const int k = layout.ring[p];
            if (k < 0) continue;
            const auto ks = static_cast<std::size_t>(k);
            ++stats[ks].pixels;
            sum[ks] += se[p];
            if (ssim && ssim->valid(x, y)) {
                ssim_sum[ks] += ssim->at_image(x, y);
                ++ssim_count[ks];
            }
        }
    // Pass 2: SD of the per-pixel squared error about the ring mean.
    std::vector<double> deviation(n, 0.0);
    for (std::size_t p = 0; p < layout.ring.size(); ++p) {
        const int k = layout.ring[p];
        if (k < 0) continue;
        const auto ks = static_cast<std::size_t>(k);
        const double d = se[p] - sum[ks] / static_cast<double>(stats[ks].pixels);
        deviation[ks] += d * d;
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t k = 0; k < n; ++k) {
        RingStats& s = stats[k];
        s.ring = static_cast<int>(k);
        s.inner_deg = layout.inner(static_cast<int>(k));
        s.outer_deg = layout.outer(static_cast<int>(k));
        const auto count = static_cast<double>(s.pixels);
        s.mse = s.pixels ? sum[k] / count : nan;
        s.rmse = s.pixels ? std::sqrt(s.mse) : nan;
        s.psnr = s.pixels ? psnr(s.mse) : nan;
        s.sd = s.pixels ? std::sqrt(deviation[k] / count) : nan;
        s.ssim_pixels = ssim_count[k];
        s.ssim = ssim_count[k] ? ssim_sum[k] / static_cast<double>(ssim_count[k]) : nan;
    }
    return stats;
}

}  // namespace fovref
