#include "ref/bmfr/display_avx.h"

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "ref/core/avx_lanes.h"
#include "ref/core/simd.h"

namespace fovref {

namespace {

using namespace avx;

/// taa_blend's clamp range for pixels x .. x + 7 of row y: the extents in YCoCg of the 3x3 box
/// and the 5-tap cross of the neighbours that exist (rows -1, 0, +1 on the image; every column
/// is), from +-infinity with glm::min(a, v) = (v < a) ? v : a and glm::max(a, v) = (a < v) ? v :
/// a in row-major order; lo = (box min + cross min) 0.5, hi = (box max + cross max) 0.5.
FOVREF_AVX2_INLINE void clamp_range(const Image& ycocg, int x, int y, __m256* lo, __m256* hi) {
    const __m256 inf = set(INFINITY);
    __m256 box_min[3], box_max[3], cross_min[3], cross_max[3];
    for (int c = 0; c < 3; ++c) {
        box_min[c] = cross_min[c] = inf;
        box_max[c] = cross_max[c] = negate(inf);
    }
    for (int dy = -1; dy <= 1; ++dy) {
        const int sy = y + dy;
        if (sy < 0 || sy >= ycocg.height) continue;
        for (int dx = -1; dx <= 1; ++dx) {
            __m256 v[3];
            split3_lanes(&ycocg.data[ycocg.index(x + dx, sy)], v);
            for (int c = 0; c < 3; ++c) {
                box_min[c] = std_min(box_min[c], v[c]);
                box_max[c] = std_max(box_max[c], v[c]);
                if (dx == 0 || dy == 0) {
                    cross_min[c] = std_min(cross_min[c], v[c]);
                    cross_max[c] = std_max(cross_max[c], v[c]);
                }
            }
        }
    }
    for (int c = 0; c < 3; ++c) {
        lo[c] = _mm256_mul_ps(_mm256_add_ps(box_min[c], cross_min[c]), set(0.5f));
        hi[c] = _mm256_mul_ps(_mm256_add_ps(box_max[c], cross_max[c]), set(0.5f));
    }
}

/// bmfr_taa_pixel in screen space for pixels x .. x + 7 of row y (columns x - 1 .. x + 8 on the
/// image).
__attribute__((target("avx2"))) int taa_group(const BmfrParams& params, const Image& display,
                                              const Image& ycocg, const Image& previous_pixel,
                                              const Image& history, Image& out, int x, int y) {
    const int width = display.width, height = display.height;
    const float wf = static_cast<float>(width), hf = static_cast<float>(height);
    __m256 current[3];
    split3_lanes(&display.data[display.index(x, y)], current);
    // q, and the reference's range test: floor(q) in [-1, W - 1] x [-1, H - 1]
    alignas(32) float q[2][lanes];
    const float* pp = &previous_pixel.data[previous_pixel.index(x, y)];
    for (int l = 0; l < lanes; ++l) q[0][l] = pp[2 * l], q[1][l] = pp[2 * l + 1];
    const __m256 qx = _mm256_load_ps(q[0]), qy = _mm256_load_ps(q[1]);
    const __m256 in_range = both(both(at_least(qx, set(-1.0f)), at_least(qy, set(-1.0f))),
                                 both(less(qx, set(wf)), less(qy, set(hf))));
    // bmfr_taps(q): q is finite in the lanes that use it, and clamped to +-1e6 as there (which
    // matters only on an image wider or taller than 1e6)
    const __m256 big = set(1e6f);
    const __m256 tx = select(in_range, std_min(std_max(qx, negate(big)), big), zero());
    const __m256 ty = select(in_range, std_min(std_max(qy, negate(big)), big), zero());
    BilinearLanes b;
    bilinear_lanes(tx, ty, floor(tx), floor(ty), in_range, wf, hf, b);

    __m256 lo[3], hi[3];
    clamp_range(ycocg, x, y, lo, hi);
    // The history over the taps inside the image, in tap order.
    alignas(32) float taps[4][3][lanes] = {};
    for (int k = 0; k < 4; ++k)
        for (int l = 0; l < lanes; ++l) {
            if (!(b.on_bits[k] >> l & 1)) continue;
            const float* p = &history.data[history.index(b.x0[l] + (k & 1), b.y0[l] + (k >> 1))];
            for (int c = 0; c < 3; ++c) taps[k][c][l] = p[c];
        }
    __m256 h[3];
    const __m256 total = tap_sums3(b.on, b.weight, taps, h);
    const __m256 used = both(in_range, greater(total, zero()));
    for (int c = 0; c < 3; ++c) h[c] = _mm256_div_ps(h[c], total);
    // rgb_to_ycocg(h), clamped to the extents' averages, ycocg_to_rgb, then the blend.
    const __m256 two = set(2.0f), quarter = set(0.25f);
    __m256 v[3] = {_mm256_add_ps(_mm256_add_ps(h[0], _mm256_mul_ps(two, h[1])), h[2]),
                   _mm256_sub_ps(_mm256_mul_ps(two, h[0]), _mm256_mul_ps(two, h[2])),
                   _mm256_sub_ps(_mm256_add_ps(negate(h[0]), _mm256_mul_ps(two, h[1])), h[2])};
    for (int c = 0; c < 3; ++c)
        v[c] = std_min(std_max(v[c], lo[c]), hi[c]);  // glm::clamp = min(max(v, lo), hi)
    const __m256 clamped[3] = {
        _mm256_mul_ps(_mm256_sub_ps(_mm256_add_ps(v[0], v[1]), v[2]), quarter),
        _mm256_mul_ps(_mm256_add_ps(v[0], v[2]), quarter),
        _mm256_mul_ps(_mm256_sub_ps(_mm256_sub_ps(v[0], v[1]), v[2]), quarter)};
    const __m256 alpha = set(params.taa_alpha), beta = set(1.0f - params.taa_alpha);
    __m256 o[3];
    for (int c = 0; c < 3; ++c)
        o[c] = select(
            used, _mm256_add_ps(_mm256_mul_ps(current[c], alpha), _mm256_mul_ps(clamped[c], beta)),
            current[c]);
    merge3_lanes(o, &out.data[out.index(x, y)]);
    return count(used);
}

}  // namespace

bool bmfr_taa_avx_applies(const Image& display, const Image& history, const BmfrSpace& space) {
    return !space.map && !history.empty() && display.channels == 3 && history.channels == 3 &&
           display.width >= 10 && simd_allowed() && cpu_has_avx2();
}

int bmfr_taa_row_avx(const BmfrParams& params, const Image& display, const Image& ycocg,
                     const Image& previous_pixel, const Image& history, Image& out, int y,
                     std::int64_t& used) {
    int x = 1;
    for (; x + lanes <= display.width - 1; x += lanes)
        used += taa_group(params, display, ycocg, previous_pixel, history, out, x, y);
    return x;
}

}  // namespace fovref
