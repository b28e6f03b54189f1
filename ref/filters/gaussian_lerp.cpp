#include "ref/filters/gaussian_lerp.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "ref/core/avx_lanes.h"
#include "ref/core/simd.h"
#include "ref/core/vec.h"
#include "ref/filters/gaussian3x3_avx.h"

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

namespace {

/// gaussian_lerp_pixel for pixels x0 .. x0 + 7 of row y of a 3-channel image whose columns
/// x0 - 1 .. x0 + 8 lie on it (the caller checks; `rows`: y - 1, y, y + 1 clamped). Each lane's
/// t is the reference's: the centre (x + 1/2, y + 1/2) minus the gaze, sqrt(dx dx + dy dy),
/// (d - start) / span, std::clamp to [0, 1] (= std::min(std::max(v, 0), 1)); it is spread to
/// the pixel's three interleaved floats, and each float is its value where t = 0, else
/// value + t (G - value) with G from gaussian3x3_group. A group whose eight t are all 0 is
/// copied (G unused, as in the reference).
__attribute__((target("avx2"))) void lerp_group(const Image& in, glm::vec2 gaze,
                                                const LerpRamp& ramp, Image& out, int x0, int y,
                                                const int* rows) {
    using namespace avx;
    const __m256 cx =
        _mm256_add_ps(_mm256_cvtepi32_ps(_mm256_add_epi32(
                          _mm256_set1_epi32(x0), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7))),
                      set(0.5f));
    const __m256 dx = _mm256_sub_ps(cx, set(gaze.x));
    const float dy = (static_cast<float>(y) + 0.5f) - gaze.y;
    const __m256 distance = _mm256_sqrt_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), set(dy * dy)));
    const __m256 v = _mm256_div_ps(_mm256_sub_ps(distance, set(ramp.start)), set(ramp.span));
    const __m256 t = std_min(std_max(v, zero()), set(1.0f));
    const float* from = &in.data[in.index(x0, y)];
    float* to = &out.data[out.index(x0, y)];
    if (_mm256_movemask_ps(equal(t, zero())) == 0xff) {
        for (int k = 0; k < 3; ++k) _mm256_storeu_ps(to + 8 * k, _mm256_loadu_ps(from + 8 * k));
        return;
    }
    __m256 g[3];
    gaussian3x3_group(in, x0, rows, g);
    __m256 t_floats[3];  // pixel l's t at its floats 3 l .. 3 l + 2
    spread3_lanes(t, t_floats);
    for (int k = 0; k < 3; ++k) {
        const __m256 tk = t_floats[k];
        const __m256 value = _mm256_loadu_ps(from + 8 * k);
        const __m256 blended = _mm256_add_ps(value, _mm256_mul_ps(tk, _mm256_sub_ps(g[k], value)));
        _mm256_storeu_ps(to + 8 * k, select(equal(tk, zero()), value, blended));
    }
}

}  // namespace

Image gaussian_lerp(const Image& in, glm::vec2 gaze, Image storage) {
    Image out = std::move(storage);  // every pixel is written below
    keep_or_make(out, in.width, in.height, in.channels);
    const LerpRamp ramp = gaussian_lerp_ramp(in.width, in.height, gaze);
    // Eight pixels at a time (lerp_group, AVX2, the same bits) from column 1 while the group's
    // right neighbour lies on the image; gaussian_lerp_pixel, the reference, does the rest.
    const bool avx = in.channels == 3 && simd_allowed() && cpu_has_avx2();
    for (int y = 0; y < in.height; ++y) {
        const int rows[3] = {std::max(y - 1, 0), y, std::min(y + 1, in.height - 1)};
        int x = 0;
        if (avx && in.width > avx::lanes + 1) {
            gaussian_lerp_pixel(in, gaze, ramp, out, 0, y);
            for (x = 1; x + avx::lanes < in.width; x += avx::lanes)
                lerp_group(in, gaze, ramp, out, x, y, rows);
        }
        for (; x < in.width; ++x) gaussian_lerp_pixel(in, gaze, ramp, out, x, y);
    }
    return out;
}

}  // namespace fovref
