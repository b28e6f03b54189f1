#include "ref/visual_polar/sparse_sampling.h"

#include <cmath>
#include <limits>
#include <vector>

#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/core/rng.h"
#include "ref/core/vec.h"
#include "ref/visual_polar/map.h"

namespace fovref {

float linear_falloff_probability(const LinearFalloff& f, float e) {
    if (e <= f.fovea_deg) return 1.0f;
    if (e >= f.periphery_deg) return f.periphery_probability;
    const float t = (e - f.fovea_deg) / (f.periphery_deg - f.fovea_deg);
    return 1.0f + t * (f.periphery_probability - 1.0f);
}

bool linear_falloff_sampled(std::uint32_t frame, std::uint32_t pixel, float probability) {
    return rand_unit(frame, pixel, 0) < probability;
}

namespace {
constexpr float degrees_per_radian = 57.2957795130823208768f;
}  // namespace

float EccentricityModel::degrees(float r) const {
    if (exact) return dm::atan(r / distance_px) * degrees_per_radian;
    return r / (distance_px * 3.14159265358979323846f / 180.0f);
}

float EccentricityModel::radius(float e) const {
    if (!exact) return e * (distance_px * 3.14159265358979323846f / 180.0f);
    if (!(e < 89.9f)) return std::numeric_limits<float>::infinity();
    return distance_px * dm::tan(dm::radians(e));
}

glm::vec2 acuity_sample(std::uint32_t frame, std::uint32_t sample, glm::vec2 gaze,
                        const EccentricityModel& model) {
    const float phi = 6.28318530717958647692f * rand_unit(frame, sample, 0);
    const float e = vp_inverse_cdf(rand_unit(frame, sample, 1));
    const float r = model.radius(e);
    return gaze + glm::vec2(r * dm::cos(phi), r * dm::sin(phi));
}

namespace {

// L(e) at the centre of pixel (x, y), e the model's degrees of |c - g|.
float falloff_probability_at(const LinearFalloff& falloff, int x, int y, glm::vec2 gaze,
                             const EccentricityModel& model) {
    return linear_falloff_probability(falloff,
                                      model.degrees(gaze_distance(gaze, pixel_centre(x, y))));
}

}  // namespace

Image linear_falloff_mask(const LinearFalloff& falloff, int width, int height, glm::vec2 gaze,
                          const EccentricityModel& model, std::uint32_t frame,
                          std::int64_t& sampled) {
    FOVREF_CHECK(width > 0 && height > 0 && model.distance_px > 0.0f,
                 "linear_falloff_mask: bad size or viewing distance");
    Image mask(width, height, 1, 0.0f);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const auto pixel = static_cast<std::uint32_t>(y * width + x);
            if (!linear_falloff_sampled(frame, pixel,
                                        falloff_probability_at(falloff, x, y, gaze, model)))
                continue;
            mask.at(x, y) = 1.0f;
            ++sampled;
        }
    return mask;
}

double linear_falloff_expected(const LinearFalloff& falloff, int width, int height, glm::vec2 gaze,
                               const EccentricityModel& model) {
    double sum = 0.0;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) sum += falloff_probability_at(falloff, x, y, gaze, model);
    return sum;
}

std::vector<glm::vec2> acuity_samples(std::uint32_t frame, int count, glm::vec2 gaze,
                                      const EccentricityModel& model) {
    std::vector<glm::vec2> points;
    points.reserve(static_cast<std::size_t>(count));
    for (int k = 0; k < count; ++k)
        points.push_back(acuity_sample(frame, static_cast<std::uint32_t>(k), gaze, model));
    return points;
}

void splat_samples(const std::vector<glm::vec2>& points, const Image& valid, const Image& colors,
                   Image& sum, Image& count) {
    FOVREF_CHECK(valid.width == static_cast<int>(points.size()) && colors.width == valid.width &&
                     colors.channels == 3 && sum.channels == 3 && count.channels == 1 &&
                     sum.width == count.width && sum.height == count.height,
                 "splat_samples: buffers of different shapes");
    for (std::size_t k = 0; k < points.size(); ++k) {
        const int i = static_cast<int>(k);
        if (valid.at(i, 0) == 0.0f) continue;
        const int x = static_cast<int>(std::floor(points[k].x));
        const int y = static_cast<int>(std::floor(points[k].y));
        if (x < 0 || y < 0 || x >= sum.width || y >= sum.height) continue;
        for (int c = 0; c < 3; ++c) sum.at(x, y, c) += colors.at(i, 0, c);
        count.at(x, y) += 1.0f;
    }
}

Image sample_mean(const Image& sum, const Image& count, Image& weight) {
    Image out(sum.width, sum.height, 3, 0.0f);
    weight = Image(sum.width, sum.height, 1, 0.0f);
    for (int y = 0; y < sum.height; ++y)
        for (int x = 0; x < sum.width; ++x) {
            const float n = count.at(x, y);
            if (!(n > 0.0f)) continue;
            weight.at(x, y) = 1.0f;
            for (int c = 0; c < 3; ++c) out.at(x, y, c) = sum.at(x, y, c) / n;
        }
    return out;
}

Image push_pull(const Image& image, const Image& weight) {
    FOVREF_CHECK(
        weight.width == image.width && weight.height == image.height && weight.channels == 1,
        "push_pull: the weight buffer does not match the image");
    const int channels = image.channels;
    // Level 0: the samples and where they are
    std::vector<Image> values{image};
    std::vector<std::vector<unsigned char>> has{std::vector<unsigned char>(image.pixel_count(), 0)};
    for (std::size_t i = 0; i < image.pixel_count(); ++i) {
        has[0][i] = weight.data[i] > 0.0f;
        if (!has[0][i])
            for (int c = 0; c < channels; ++c) values[0].data[i * channels + c] = 0.0f;
    }
    // Pull: 2x2 averages of the children that hold data
    while (values.back().width > 1 || values.back().height > 1) {
        const Image& fine = values.back();
        const std::vector<unsigned char>& fine_has = has.back();
        Image coarse((fine.width + 1) / 2, (fine.height + 1) / 2, channels);
        std::vector<unsigned char> coarse_has(coarse.pixel_count(), 0);
        for (int y = 0; y < coarse.height; ++y)
            for (int x = 0; x < coarse.width; ++x) {
                int count = 0;
                for (int dy = 0; dy < 2; ++dy)
                    for (int dx = 0; dx < 2; ++dx) {
                        const int fx = 2 * x + dx, fy = 2 * y + dy;
                        if (fx >= fine.width || fy >= fine.height) continue;
                        if (!fine_has[static_cast<std::size_t>(fy) * fine.width + fx]) continue;
                        for (int c = 0; c < channels; ++c) coarse.at(x, y, c) += fine.at(fx, fy, c);
                        ++count;
                    }
                if (count > 0) {
                    for (int c = 0; c < channels; ++c)
                        coarse.at(x, y, c) = coarse.at(x, y, c) / static_cast<float>(count);
                    coarse_has[static_cast<std::size_t>(y) * coarse.width + x] = 1;
                }
            }
        values.push_back(std::move(coarse));
        has.push_back(std::move(coarse_has));
    }
    // Push: fill from the parent, coarsest first
    for (std::size_t level = values.size() - 1; level-- > 0;) {
        Image& fine = values[level];
        const Image& parent = values[level + 1];
        std::vector<unsigned char>& fine_has = has[level];
        for (int y = 0; y < fine.height; ++y)
            for (int x = 0; x < fine.width; ++x) {
                const std::size_t i = static_cast<std::size_t>(y) * fine.width + x;
                if (fine_has[i] || !has[level + 1][static_cast<std::size_t>(y / 2) * parent.width +
                                                   static_cast<std::size_t>(x / 2)])
                    continue;
                for (int c = 0; c < channels; ++c) fine.at(x, y, c) = parent.at(x / 2, y / 2, c);
                fine_has[i] = 1;
            }
    }
    return values[0];
}

}  // namespace fovref
