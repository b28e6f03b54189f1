#include "ref/metrics/ssim.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/core/simd.h"
#include "ref/metrics/metrics.h"

namespace fovref {

namespace {

// The five filtered quantities of one pixel: a, b, a^2, b^2, ab.
constexpr int quantities = 5;

// One filtered row: dst[x] = w[0] centre[x] + w[1] (left[1][x] + right[1][x]) + ...
//                          + w[r] (left[r][x] + right[r][x]), summed in that order (the taps at -k
// and +k share a weight). SSE2 lanes do exactly the scalar operations, two columns at a time, so
// the result does not depend on the lane count.
void filter_row_taps(double* __restrict dst, const double* centre, const double* const* left_in,
                     const double* const* right_in, const double* w_in, int r, std::size_t n) {
    // Local copies (a store to dst cannot change them).
    constexpr int slots = 65;
    const double* left[slots];
    const double* right[slots];
    double w[slots];
    __m128d wv[slots];
    for (int k = 0; k <= r; ++k) {
        left[k] = k > 0 ? left_in[k] : centre;  // callers fill 1 .. r
        right[k] = k > 0 ? right_in[k] : centre;
        w[k] = w_in[k];
        wv[k] = _mm_set1_pd(w_in[k]);
    }
    std::size_t x = 0;
    for (; x + 2 <= n; x += 2) {
        __m128d sum = _mm_mul_pd(wv[0], _mm_loadu_pd(centre + x));
        for (int k = 1; k <= r; ++k) {
            const __m128d pair = _mm_add_pd(_mm_loadu_pd(left[k] + x), _mm_loadu_pd(right[k] + x));
            sum = _mm_add_pd(sum, _mm_mul_pd(wv[k], pair));
        }
        _mm_storeu_pd(dst + x, sum);
    }
    for (; x < n; ++x) {
        double sum = w[0] * centre[x];
        for (int k = 1; k <= r; ++k) sum += w[k] * (left[k][x] + right[k][x]);
        dst[x] = sum;
    }
}

// The default window (r = 5) written out: the same operations in the same order as
// filter_row_taps, with pointers and weights in registers (about twice as fast).
void filter_row_taps5(double* __restrict dst, const double* centre, const double* const* left,
                      const double* const* right, const double* w, std::size_t n) {
    const double *l1 = left[1], *l2 = left[2], *l3 = left[3], *l4 = left[4], *l5 = left[5];
    const double *r1 = right[1], *r2 = right[2], *r3 = right[3], *r4 = right[4], *r5 = right[5];
    const __m128d w0 = _mm_set1_pd(w[0]), w1 = _mm_set1_pd(w[1]), w2 = _mm_set1_pd(w[2]),
                  w3 = _mm_set1_pd(w[3]), w4 = _mm_set1_pd(w[4]), w5 = _mm_set1_pd(w[5]);
    auto tap = [](__m128d sum, __m128d weight, const double* a, const double* b) {
        return _mm_add_pd(sum, _mm_mul_pd(weight, _mm_add_pd(_mm_loadu_pd(a), _mm_loadu_pd(b))));
    };
    std::size_t x = 0;
    for (; x + 2 <= n; x += 2) {
        __m128d sum = _mm_mul_pd(w0, _mm_loadu_pd(centre + x));
        sum = tap(sum, w1, l1 + x, r1 + x);
        sum = tap(sum, w2, l2 + x, r2 + x);
        sum = tap(sum, w3, l3 + x, r3 + x);
        sum = tap(sum, w4, l4 + x, r4 + x);
        sum = tap(sum, w5, l5 + x, r5 + x);
        _mm_storeu_pd(dst + x, sum);
    }
    for (; x < n; ++x) {
        double sum = w[0] * centre[x];
        sum += w[1] * (l1[x] + r1[x]);
        sum += w[2] * (l2[x] + r2[x]);
        sum += w[3] * (l3[x] + r3[x]);
        sum += w[4] * (l4[x] + r4[x]);
        sum += w[5] * (l5[x] + r5[x]);
        dst[x] = sum;
    }
}

// The same kernel four columns at a time with 256-bit AVX (compiled for AVX only here and used
// only when the CPU has it): each lane still does w0*c, then + w_k*(l_k + r_k) for k = 1 .. 5,
// separately rounded (no FMA), so the result is bit-identical to filter_row_taps5.
__attribute__((target("avx"))) void filter_row_taps5_avx(double* __restrict dst,
                                                         const double* centre,
                                                         const double* const* left,
                                                         const double* const* right,
                                                         const double* w, std::size_t n) {
    const double *l1 = left[1], *l2 = left[2], *l3 = left[3], *l4 = left[4], *l5 = left[5];
    const double *r1 = right[1], *r2 = right[2], *r3 = right[3], *r4 = right[4], *r5 = right[5];
    const __m256d w0 = _mm256_set1_pd(w[0]), w1 = _mm256_set1_pd(w[1]), w2 = _mm256_set1_pd(w[2]),
                  w3 = _mm256_set1_pd(w[3]), w4 = _mm256_set1_pd(w[4]), w5 = _mm256_set1_pd(w[5]);
    std::size_t x = 0;
    for (; x + 4 <= n; x += 4) {
        __m256d sum = _mm256_mul_pd(w0, _mm256_loadu_pd(centre + x));
        sum = _mm256_add_pd(sum, _mm256_mul_pd(w1, _mm256_add_pd(_mm256_loadu_pd(l1 + x),
                                                                 _mm256_loadu_pd(r1 + x))));
        sum = _mm256_add_pd(sum, _mm256_mul_pd(w2, _mm256_add_pd(_mm256_loadu_pd(l2 + x),
                                                                 _mm256_loadu_pd(r2 + x))));
        sum = _mm256_add_pd(sum, _mm256_mul_pd(w3, _mm256_add_pd(_mm256_loadu_pd(l3 + x),
                                                                 _mm256_loadu_pd(r3 + x))));
        sum = _mm256_add_pd(sum, _mm256_mul_pd(w4, _mm256_add_pd(_mm256_loadu_pd(l4 + x),
                                                                 _mm256_loadu_pd(r4 + x))));
        sum = _mm256_add_pd(sum, _mm256_mul_pd(w5, _mm256_add_pd(_mm256_loadu_pd(l5 + x),
                                                                 _mm256_loadu_pd(r5 + x))));
        _mm256_storeu_pd(dst + x, sum);
    }
    // The last 0 .. 3 columns: the two-lane kernel (same operations).
    if (x < n) {
        const double* l_rest[6] = {nullptr, l1 + x, l2 + x, l3 + x, l4 + x, l5 + x};
        const double* r_rest[6] = {nullptr, r1 + x, r2 + x, r3 + x, r4 + x, r5 + x};
        filter_row_taps5(dst + x, centre + x, l_rest, r_rest, w, n - x);
    }
}

}  // namespace

std::vector<double> ssim_window(const SsimSettings& settings) {
    const int r = settings.radius;
    std::vector<double> w(static_cast<std::size_t>(2 * r + 1));
    double sum = 0.0;
    for (int k = -r; k <= r; ++k) {
        const double x = static_cast<double>(k);
        w[static_cast<std::size_t>(k + r)] =
            dm::exp_d(-(x * x) / (2.0 * settings.sigma * settings.sigma));
        sum += w[static_cast<std::size_t>(k + r)];
    }
    for (double& v : w) v /= sum;
    return w;
}

namespace {

// The separable Gaussian window of SSIM: its half weights (taps 0 .. r), its radius, and which
// kernel filters a row (the 11-tap AVX or SSE2 one, or the general one).
struct SsimKernel {
    const double* half_window = nullptr;
    int r = 0;
    bool use_avx = false;
};

// One filter pass over n outputs (dst[x] = w0 centre[x] + sum_k wk (left[k][x] + right[k][x])).
void filter_taps(const SsimKernel& kernel, double* dst, const double* centre,
                 const double* const* left, const double* const* right, std::size_t n) {
    if (kernel.r == 5) {
        if (kernel.use_avx)
            return filter_row_taps5_avx(dst, centre, left, right, kernel.half_window, n);
        filter_row_taps5(dst, centre, left, right, kernel.half_window, n);
    } else {
        filter_row_taps(dst, centre, left, right, kernel.half_window, kernel.r, n);
    }
}

// The working rows of one vertical strip: the horizontal pass results of the last `taps` image
// rows (a ring buffer indexed by row % taps: rows[(row % taps) * quantities + q][x] for strip
// output column x), the products of one input row, and the vertical pass results (mu).
struct SsimStrip {
    SsimKernel kernel;
    int taps = 0;
    std::size_t strip_width = 0;
    std::size_t input_width = 0;
    std::vector<std::vector<double>> rows;
    std::vector<double> products;
    std::vector<double> mu[quantities];

    SsimStrip(const SsimKernel& k, std::size_t width)
        : kernel(k),
          taps(2 * k.r + 1),
          strip_width(width),
          input_width(width + 2 * static_cast<std::size_t>(k.r)),
          rows(static_cast<std::size_t>(taps * quantities), std::vector<double>(width)),
          products(input_width * quantities) {
        for (auto& m : mu) m.resize(width);
    }
    double* row(int image_row, int q) {
        return rows[static_cast<std::size_t>(image_row % taps) * quantities +
                    static_cast<std::size_t>(q)]
            .data();
    }
};

// Horizontal pass of image row y over the strip's n output columns from x0: the five products
// in binary64 (exact: float x float fits in a double), then the centre tap and the tap pairs
// (-k, +k) for k = 1 .. r, into the ring buffer's slot of row y.
void ssim_filter_row(const Image& a, const Image& b, int y, std::size_t x0, std::size_t n,
                     SsimStrip& work) {
    const int r = work.kernel.r;
    const std::size_t n_in = n + 2 * static_cast<std::size_t>(r);
    const auto width = static_cast<std::size_t>(a.width);
    const float* pa = &a.data[static_cast<std::size_t>(y) * width + x0];
    const float* pb = &b.data[static_cast<std::size_t>(y) * width + x0];
    double* src[quantities];
    for (int q = 0; q < quantities; ++q)
        src[q] = &work.products[static_cast<std::size_t>(q) * work.input_width];
    for (std::size_t x = 0; x < n_in; ++x) {
        const double va = pa[x], vb = pb[x];
        src[0][x] = va;
        src[1][x] = vb;
        src[2][x] = va * va;
        src[3][x] = vb * vb;
        src[4][x] = va * vb;
    }
    for (int q = 0; q < quantities; ++q) {
        const double* centre = src[q] + r;
        const double* left[65];
        const double* right[65];
        for (int k = 1; k <= r; ++k) {
            left[k] = centre - k;
            right[k] = centre + k;
        }
        filter_taps(work.kernel, work.row(y, q), centre, left, right, n);
    }
}

// SSIM at one map pixel from the five filtered quantities (Wang et al. 2004, eq. 13).
double ssim_pixel(double mu_a, double mu_b, double mean_aa, double mean_bb, double mean_ab,
                  double c1, double c2) {
    const double s_aa = mean_aa - mu_a * mu_a;
    const double s_bb = mean_bb - mu_b * mu_b;
    const double s_ab = mean_ab - mu_a * mu_b;
    return ((2.0 * mu_a * mu_b + c1) * (2.0 * s_ab + c2)) /
           ((mu_a * mu_a + mu_b * mu_b + c1) * (s_aa + s_bb + c2));
}

// Vertical pass for map row out_y (the centre row out_y + r, then the row pairs (-k, +k)), then
// SSIM of the strip's n columns of that row into out.
void ssim_output_row(int out_y, std::size_t n, double c1, double c2, SsimStrip& work, double* out) {
    const int r = work.kernel.r;
    for (int q = 0; q < quantities; ++q) {
        const int centre = out_y + r;
        const double* left[65];
        const double* right[65];
        for (int k = 1; k <= r; ++k) {
            left[k] = work.row(centre - k, q);
            right[k] = work.row(centre + k, q);
        }
        filter_taps(work.kernel, work.mu[q].data(), work.row(centre, q), left, right, n);
    }
    for (std::size_t x = 0; x < n; ++x)
        out[x] = ssim_pixel(work.mu[0][x], work.mu[1][x], work.mu[2][x], work.mu[3][x],
                            work.mu[4][x], c1, c2);
}

}  // namespace

SsimMap ssim_map(const Image& a, const Image& b, const SsimSettings& settings) {
    check_same_shape(a, b, "ssim");
    if (a.channels != 1)
        throw Error("ssim: needs 1-channel (luma) images, got " + std::to_string(a.channels) +
                    " channels");
    if (!(settings.radius >= 1 && settings.radius <= 64) || !(settings.sigma > 0.0) ||
        !(settings.data_range > 0.0))
        throw Error("ssim: window radius must be 1..64, sigma and data range > 0");
    const int r = settings.radius;
    const int taps = 2 * r + 1;
    if (a.width < taps || a.height < taps)
        throw Error("ssim: the image (" + std::to_string(a.width) + "x" + std::to_string(a.height) +
                    ") is smaller than the " + std::to_string(taps) + "x" + std::to_string(taps) +
                    " window");
    const std::vector<double> w = ssim_window(settings);
    // w[r .. 2r]: the weights of taps 0 .. r (the window is symmetric).
    const std::vector<double> half_window(w.begin() + r, w.end());
    const double c1 = (settings.k1 * settings.data_range) * (settings.k1 * settings.data_range);
    const double c2 = (settings.k2 * settings.data_range) * (settings.k2 * settings.data_range);
    // C1, C2 > 0 keep both denominators positive (a constant image has zero variance).
    if (!(c1 > 0.0) || !(c2 > 0.0) || !std::isfinite(c1) || !std::isfinite(c2))
        throw Error("ssim: K1, K2 and the data range must give finite C1, C2 > 0");

    SsimMap map;
    map.border = r;
    map.width = a.width - 2 * r;
    map.height = a.height - 2 * r;
    map.values.resize(static_cast<std::size_t>(map.width) * static_cast<std::size_t>(map.height));
    // The map is computed in vertical strips of at most `strip` output columns, so that the
    // rows a strip keeps (taps x 5 quantities) stay in the L2 cache at any image width. Every
    // map value is the same whatever the strip width: strips only change the loop order.
    constexpr std::size_t strip = 512;
    const auto map_width = static_cast<std::size_t>(map.width);
    const SsimKernel kernel{half_window.data(), r,
                            settings.allow_avx && simd_allowed() && cpu_has_avx()};
    SsimStrip work(kernel, std::min(strip, map_width));
    for (std::size_t x0 = 0; x0 < map_width; x0 += work.strip_width) {
        const std::size_t n = std::min(work.strip_width, map_width - x0);
        for (int y = 0; y < taps - 1; ++y) ssim_filter_row(a, b, y, x0, n, work);
        for (int out_y = 0; out_y < map.height; ++out_y) {
            ssim_filter_row(a, b, out_y + taps - 1, x0, n, work);
            ssim_output_row(out_y, n, c1, c2, work,
                            &map.values[static_cast<std::size_t>(out_y) * map_width + x0]);
        }
    }
    // Mean SSIM: row-major sum in binary64.
    double sum = 0.0;
    for (const double v : map.values) sum += v;
    map.mean = sum / static_cast<double>(map.values.size());
    return map;
}

double ssim(const Image& a, const Image& b, const SsimSettings& settings) {
    return ssim_map(luma(a), luma(b), settings).mean;
}

}  // namespace fovref
