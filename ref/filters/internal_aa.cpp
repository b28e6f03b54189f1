#include "ref/filters/internal_aa.h"

#include <algorithm>

#include "ref/core/error.h"

namespace fovref {

void internal_aa_texel(const Image& color, const Image& valid, Image& out, int x, int y) {
    const int w = color.width, h = color.height;
    if (valid.at(x, y) == 0.0f || 2 * x < w) {
        for (int c = 0; c < color.channels; ++c) out.at(x, y, c) = color.at(x, y, c);
        return;
    }
    static constexpr float k[3][3] = {{1, 2, 1}, {2, 4, 2}, {1, 2, 1}};
    float sum[4] = {0, 0, 0, 0};
    float weight = 0.0f;
    for (int dy = -1; dy <= 1; ++dy) {
        const int yy = ((y + dy) % h + h) % h;
        for (int dx = -1; dx <= 1; ++dx) {
            const int xx = std::clamp(x + dx, 0, w - 1);
            if (valid.at(xx, yy) == 0.0f) continue;
            const float kw = k[dy + 1][dx + 1];
            weight += kw;
            for (int c = 0; c < color.channels && c < 4; ++c) sum[c] += kw * color.at(xx, yy, c);
        }
    }
    for (int c = 0; c < color.channels && c < 4; ++c) out.at(x, y, c) = sum[c] / weight;
}

Image internal_aa(const Image& color, const Image& valid) {
    FOVREF_CHECK(color.channels <= 4, "internal anti-aliasing of more than 4 channels");
    Image out(color.width, color.height, color.channels, 0.0f);
    for (int y = 0; y < color.height; ++y)
        for (int x = 0; x < color.width; ++x) internal_aa_texel(color, valid, out, x, y);
    return out;
}

}  // namespace fovref
