#include "ref/filters/gaussian_lerp.h"

#include <algorithm>
#include <cmath>

#include "ref/core/vec.h"

namespace fovref {

LerpRamp gaussian_lerp_ramp(int width, int height, glm::vec2 gaze) {
    const float w = static_cast<float>(width), h = static_cast<float>(height);
    const float diagonal = std::sqrt(w * w + h * h);
    float farthest = 0.0f;
    const glm::vec2 corners[4] = {{0.0f, 0.0f}, {w, 0.0f}, {0.0f, h}, {w, h}};
    for (const glm::vec2& c : corners) farthest = std::max(farthest, gaze_distance(gaze, c));
    LerpRamp ramp;
    ramp.start = diagonal / 6.0f;
    ramp.span = farthest - ramp.start;
    return ramp;
}

float gaussian_lerp_amount(const LerpRamp& ramp, glm::vec2 gaze, glm::vec2 p) {
    return std::clamp((gaze_distance(gaze, p) - ramp.start) / ramp.span, 0.0f, 1.0f);
}

float gaussian3x3_clamped(const Image& in, int x, int y, int c) {
    static constexpr float k[3][3] = {{1, 2, 1}, {2, 4, 2}, {1, 2, 1}};
    float sum = 0.0f;
    for (int dy = -1; dy <= 1; ++dy) {
        const int yy = std::clamp(y + dy, 0, in.height - 1);
        for (int dx = -1; dx <= 1; ++dx) {
            const int xx = std::clamp(x + dx, 0, in.width - 1);
            sum += k[dy + 1][dx + 1] * in.at(xx, yy, c);
        }
    }
    return sum / 16.0f;
}

void gaussian_lerp_pixel(const Image& in, glm::vec2 gaze, const LerpRamp& ramp, Image& out, int x,
                         int y) {
    const glm::vec2 centre = pixel_centre(x, y);
    const float t = gaussian_lerp_amount(ramp, gaze, centre);
    for (int c = 0; c < in.channels; ++c) {
        const float value = in.at(x, y, c);
        out.at(x, y, c) =
            t == 0.0f ? value : value + t * (gaussian3x3_clamped(in, x, y, c) - value);
    }
}

Image gaussian_lerp(const Image& in, glm::vec2 gaze) {
    Image out(in.width, in.height, in.channels, 0.0f);
    const LerpRamp ramp = gaussian_lerp_ramp(in.width, in.height, gaze);
    for (int y = 0; y < in.height; ++y)
        for (int x = 0; x < in.width; ++x) gaussian_lerp_pixel(in, gaze, ramp, out, x, y);
    return out;
}

}  // namespace fovref
