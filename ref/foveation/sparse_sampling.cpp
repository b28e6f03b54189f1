#include "ref/foveation/sparse_sampling.h"

#include <vector>

#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/core/rng.h"
#include "ref/foveation/visual_polar.h"

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

glm::vec2 acuity_sample(std::uint32_t frame, std::uint32_t sample, glm::vec2 gaze,
                        float pixels_per_degree) {
    const float phi = 6.28318530717958647692f * rand_unit(frame, sample, 0);
    const float e = vp_inverse_cdf(rand_unit(frame, sample, 1));
    const float r = e * pixels_per_degree;
    return gaze + glm::vec2(r * dm::cos(phi), r * dm::sin(phi));
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
