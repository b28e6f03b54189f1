#include "ref/filters/post_aa.h"

#include <algorithm>
#include <cmath>

#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/core/vec.h"

namespace fovref {

namespace {

constexpr int max_eta = 39;  // t = 1: 3 + 2 ceil(0.9 / 0.05)

}  // namespace

int post_aa_size(float t) {
    t = std::min(t, 1.0f);
    // eta = 3 + 2 ceil((t - 0.1) / 0.05) exactly as Meng's eq. 2.14: 3 for 0.05 < t <= 0.10,
    // 1 or less (unfiltered) for t <= 0.05
    if (!(t > 0.05f)) return 0;
    const int steps = static_cast<int>(std::ceil((t - 0.1f) / 0.05f));
    return std::min(3 + 2 * steps, max_eta);
}

std::vector<float> post_aa_weights(int eta) {
    const float sigma = static_cast<float>(eta) / 6.0f;
    const int half = (eta - 1) / 2;
    std::vector<float> g(static_cast<std::size_t>(eta));
    float sum = 0.0f;
    for (int d = -half; d <= half; ++d) {
        const float e = dm::exp(-static_cast<float>(d * d) / (2.0f * sigma * sigma));
        g[static_cast<std::size_t>(d + half)] = e;
        sum += e;
    }
    for (float& value : g) value /= sum;
    return g;
}

void post_aa_row(const Image& in, const std::vector<float>& g, int x, int yy, float* row) {
    const int half = (static_cast<int>(g.size()) - 1) / 2;
    for (int c = 0; c < in.channels; ++c) row[c] = 0.0f;
    for (int dx = -half; dx <= half; ++dx) {
        const int xx = std::clamp(x + dx, 0, in.width - 1);
        const float wx = g[static_cast<std::size_t>(dx + half)];
        for (int c = 0; c < in.channels; ++c) row[c] += wx * in.at(xx, yy, c);
    }
}

void post_aa_pixel(const Image& in, glm::vec2 gaze, float radius_max,
                   const std::vector<std::vector<float>>& weights, Image& out, int x, int y) {
    const glm::vec2 centre = pixel_centre(x, y);
    const int eta = post_aa_size(gaze_distance(gaze, centre) / radius_max);
    if (eta == 0) {
        for (int c = 0; c < in.channels; ++c) out.at(x, y, c) = in.at(x, y, c);
        return;
    }
    const std::vector<float>& g = weights[static_cast<std::size_t>(eta)];
    const int half = (eta - 1) / 2;
    float sum[4] = {0, 0, 0, 0};
    for (int dy = -half; dy <= half; ++dy) {
        const int yy = std::clamp(y + dy, 0, in.height - 1);
        float row[4];
        post_aa_row(in, g, x, yy, row);
        const float wy = g[static_cast<std::size_t>(dy + half)];
        for (int c = 0; c < in.channels; ++c) sum[c] += wy * row[c];
    }
    for (int c = 0; c < in.channels; ++c) out.at(x, y, c) = sum[c];
}

Image post_aa(const Image& in, glm::vec2 gaze, float radius_max) {
    FOVREF_CHECK(in.channels <= 4, "post anti-aliasing of more than 4 channels");
    std::vector<std::vector<float>> weights(max_eta + 1);
    for (int eta = 3; eta <= max_eta; eta += 2)
        weights[static_cast<std::size_t>(eta)] = post_aa_weights(eta);
    Image out(in.width, in.height, in.channels, 0.0f);
    std::vector<PostAaRowCache> cache(max_eta + 1);
    for (int y = 0; y < in.height; ++y)
        for (int x = 0; x < in.width; ++x)
            post_aa_cached_pixel(in, gaze, radius_max, weights, cache, out, x, y);
    return out;
}

void post_aa_cached_pixel(const Image& in, glm::vec2 gaze, float radius_max,
                          const std::vector<std::vector<float>>& weights,
                          std::vector<PostAaRowCache>& cache, Image& out, int x, int y) {
    const int width = in.width, channels = in.channels;
    const glm::vec2 centre = pixel_centre(x, y);
    const int eta = post_aa_size(gaze_distance(gaze, centre) / radius_max);
    if (eta == 0) {
        for (int c = 0; c < channels; ++c) out.at(x, y, c) = in.at(x, y, c);
        return;
    }
    const std::vector<float>& g = weights[static_cast<std::size_t>(eta)];
    PostAaRowCache& r = cache[static_cast<std::size_t>(eta)];
    if (r.eta == 0) {
        r.eta = eta;
        r.value.assign(static_cast<std::size_t>(eta) * width * channels, 0.0f);
        r.row.assign(static_cast<std::size_t>(eta) * width, -1);
    }
    const int half = (eta - 1) / 2;
    float sum[4] = {0, 0, 0, 0};
    int previous = -1, slot = 0;
    for (int dy = -half; dy <= half; ++dy) {
        const int yy = std::clamp(y + dy, 0, in.height - 1);
        if (previous < 0)
            slot = yy % eta;
        else if (yy != previous)
            slot = slot + 1 == eta ? 0 : slot + 1;  // yy = previous + 1
        previous = yy;
        const std::size_t k = static_cast<std::size_t>(slot) * width + x;
        float* row = &r.value[k * channels];
        if (r.row[k] != yy) {
            post_aa_row(in, g, x, yy, row);
            r.row[k] = yy;
        }
        const float wy = g[static_cast<std::size_t>(dy + half)];
        for (int c = 0; c < channels; ++c) sum[c] += wy * row[c];
    }
    for (int c = 0; c < channels; ++c) out.at(x, y, c) = sum[c];
}

}  // namespace fovref
