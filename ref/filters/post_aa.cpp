#include "ref/filters/post_aa.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/core/simd.h"
#include "ref/core/vec.h"

namespace fovref {

namespace {

constexpr int max_eta = 39;  // t = 1: 3 + 2 ceil(0.9 / 0.05)
constexpr int lanes = 8;     // pixels per AVX group

/// The slot (yy mod eta) of each row yy a pixel's window reads, rows top to bottom: the first by
/// a division, the next ones by a step (a clamped row at the edge repeats its slot).
struct RowSlots {
    int eta;
    int previous = -1, slot = 0;
    int next(int yy) {
        if (previous < 0)
            slot = yy % eta;
        else if (yy != previous)
            slot = slot + 1 == eta ? 0 : slot + 1;  // yy = previous + 1
        previous = yy;
        return slot;
    }
};

/// The cache of size eta, made on first use.
PostAaRowCache& row_cache(std::vector<PostAaRowCache>& cache, int eta, int width, int channels) {
    PostAaRowCache& r = cache[static_cast<std::size_t>(eta)];
    if (r.eta == 0) {
        r.eta = eta;
        const std::size_t entries = static_cast<std::size_t>(eta) * ((width + 7) / 8) * 8;
        r.value.assign(entries * channels, 0.0f);
        r.row.assign(entries, -1);
    }
    return r;
}

/// The running sums of 8 C contiguous floats in C registers (named: GCC keeps an array of them
/// in memory): add(w, p) does s += w p[8c ..] (the product rounded first) for each register c.
template <int C>
struct Sums {
    __m256 s0, s1, s2, s3;
    __attribute__((target("avx"))) Sums() : s0(_mm256_setzero_ps()), s1(s0), s2(s0), s3(s0) {}
    __attribute__((target("avx"))) void add(__m256 w, const float* p) {
        s0 = _mm256_add_ps(s0, _mm256_mul_ps(w, _mm256_loadu_ps(p)));
        if constexpr (C > 1) s1 = _mm256_add_ps(s1, _mm256_mul_ps(w, _mm256_loadu_ps(p + 8)));
        if constexpr (C > 2) s2 = _mm256_add_ps(s2, _mm256_mul_ps(w, _mm256_loadu_ps(p + 16)));
        if constexpr (C > 3) s3 = _mm256_add_ps(s3, _mm256_mul_ps(w, _mm256_loadu_ps(p + 24)));
    }
    __attribute__((target("avx"))) void store(float* p) const {
        _mm256_storeu_ps(p, s0);
        if constexpr (C > 1) _mm256_storeu_ps(p + 8, s1);
        if constexpr (C > 2) _mm256_storeu_ps(p + 16, s2);
        if constexpr (C > 3) _mm256_storeu_ps(p + 24, s3);
    }
};

/// Eight pixels x0 .. x0 + 7 of row y, computed as if all were of kernel size r.eta, C
/// channels: post_aa_cached_pixel's value for each, lane by lane, written to result[0 .. 8 C).
/// The 8 C floats of the group are contiguous in the image, in the cache and in each source row
/// shifted by dx, and every lane has the same weights, so each of the C registers does one
/// lane's scalar operations in order (0, then + g w, the product rounded). Near the left and
/// right edges the row is first copied with its clamped neighbours (the values post_aa_row
/// reads). The cache's entries are those the scalar pixels would make, and are read or made the
/// same way, eight at a time: a group's eight entries of a row are made together, so one tag
/// tells whether they are there (a row sum is the same computation whenever it is made, so an
/// entry keeps its bits).
template <int C>
__attribute__((target("avx"))) void post_aa_group_avx(const Image& in, const std::vector<float>& g,
                                                      PostAaRowCache& r, float* result, int x0,
                                                      int y) {
    const int width = in.width, eta = r.eta, half = (eta - 1) / 2;
    const bool clamped = x0 - half < 0 || x0 + lanes - 1 + half >= width;
    float padded[(lanes + max_eta - 1) * C];  // lane 0's taps from dx = -half on
    Sums<C> sum;
    RowSlots slots{eta};
    for (int dy = -half; dy <= half; ++dy) {
        const int yy = std::clamp(y + dy, 0, in.height - 1);
        const int slot = slots.next(yy);
        const std::size_t k = r.index(slot, x0);  // x0 is a multiple of 8: eight entries
        float* row = &r.value[k * C];
        // The eight entries of a group are always made together (below), so lane 0's tag is
        // the group's: the scalar pixels (the last W mod 8 of a row) use other columns.
        if (r.row[k] != yy) {
            const float* source = &in.data[(static_cast<std::size_t>(yy) * width + x0) * C];
            if (clamped) {
                for (int i = 0; i < lanes + 2 * half; ++i) {
                    const int xx = std::clamp(x0 - half + i, 0, width - 1);
                    for (int c = 0; c < C; ++c) padded[i * C + c] = in.at(xx, yy, c);
                }
                source = padded + half * C;
            }
            Sums<C> acc;
            for (int dx = -half; dx <= half; ++dx)
                acc.add(_mm256_set1_ps(g[static_cast<std::size_t>(dx + half)]),
                        source + static_cast<std::ptrdiff_t>(dx) * C);
            acc.store(row);
            for (int lane = 0; lane < lanes; ++lane) r.row[k + lane] = yy;
        }
        sum.add(_mm256_set1_ps(g[static_cast<std::size_t>(dy + half)]), row);
    }
    sum.store(result);
}

/// One group of eight pixels of row y with their kernel sizes eta[lane]: each size present runs
/// post_aa_group_avx for the whole group, and its lanes take their values from it (a group of
/// one size writes straight to the image); a lane of size 0 is copied.
template <int C>
__attribute__((target("avx"))) void post_aa_lanes_avx(
    const Image& in, const std::vector<std::vector<float>>& weights,
    std::vector<PostAaRowCache>& cache, const int* eta, Image& out, int x0, int y) {
    float* o = &out.data[out.index(x0, y)];
    bool same = true;
    for (int lane = 0; lane < lanes; ++lane) same = same && eta[lane] == eta[0];
    if (same && eta[0] > 0) {
        post_aa_group_avx<C>(in, weights[static_cast<std::size_t>(eta[0])],
                             row_cache(cache, eta[0], in.width, C), o, x0, y);
        return;
    }
    float result[lanes * C];
    for (int lane = 0; lane < lanes; ++lane) {
        const int e = eta[lane];
        bool first = true;  // the first lane of its size
        for (int before = 0; before < lane; ++before) first = first && eta[before] != e;
        if (!first) continue;
        if (e > 0)
            post_aa_group_avx<C>(in, weights[static_cast<std::size_t>(e)],
                                 row_cache(cache, e, in.width, C), result, x0, y);
        const float* from = e > 0 ? result : &in.data[in.index(x0, y)];
        for (int other = lane; other < lanes; ++other)
            if (eta[other] == e)
                for (int c = 0; c < C; ++c) o[other * C + c] = from[other * C + c];
    }
}

/// post_aa_size(gaze_distance(gaze, centre) / radius_max) of pixels x0 .. x0 + 7 of row y, lane
/// by lane in the scalar order (sqrt and the divisions are correctly rounded, ceil exact).
__attribute__((target("avx"))) void post_aa_sizes_avx(glm::vec2 gaze, float radius_max, int x0,
                                                      int y, int* eta) {
    alignas(32) float column[lanes];
    for (int lane = 0; lane < lanes; ++lane) column[lane] = static_cast<float>(x0 + lane);
    const __m256 dx = _mm256_sub_ps(_mm256_add_ps(_mm256_load_ps(column), _mm256_set1_ps(0.5f)),
                                    _mm256_set1_ps(gaze.x));
    const float dy = (static_cast<float>(y) + 0.5f) - gaze.y;
    const __m256 distance =
        _mm256_sqrt_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_set1_ps(dy * dy)));
    __m256 t = _mm256_div_ps(distance, _mm256_set1_ps(radius_max));
    // std::min(t, 1.0f) = (1 < t) ? 1 : t
    const __m256 one = _mm256_set1_ps(1.0f);
    t = _mm256_blendv_ps(t, one, _mm256_cmp_ps(one, t, _CMP_LT_OQ));
    const __m256 steps = _mm256_round_ps(
        _mm256_div_ps(_mm256_sub_ps(t, _mm256_set1_ps(0.1f)), _mm256_set1_ps(0.05f)),
        _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC);
    const int filtered = _mm256_movemask_ps(_mm256_cmp_ps(t, _mm256_set1_ps(0.05f), _CMP_GT_OQ));
    alignas(32) float step[lanes];
    _mm256_store_ps(step, steps);
    for (int lane = 0; lane < lanes; ++lane)
        eta[lane] =
            filtered >> lane & 1 ? std::min(3 + 2 * static_cast<int>(step[lane]), max_eta) : 0;
}

/// post_aa's rows with AVX groups (the CPU has AVX, 1 to 4 channels): groups of eight pixels
/// run post_aa_lanes_avx, the last W mod 8 pixels of a row post_aa_cached_pixel; the pixels run
/// row by row, so the cache is used as by the scalar pass. The kernel sizes come from `sizes`
/// when it was made for this gaze, else post_aa_sizes_avx (and are kept in `sizes`).
void post_aa_rows_avx(const Image& in, glm::vec2 gaze, float radius_max,
                      const std::vector<std::vector<float>>& weights,
                      std::vector<PostAaRowCache>& cache, Image& out, PostAaSizes* sizes) {
    const int width = in.width;
    // The sizes from the table when it was made for this frame's gaze, else computed (and kept
    // in the table when there is one)
    const bool read = sizes && sizes->made_for(gaze, radius_max, width, in.height);
    if (sizes && !read) {
        *sizes = PostAaSizes{gaze, radius_max, width, in.height, {}};
        sizes->eta.assign(static_cast<std::size_t>(width) * in.height, 0);
    }
    int eta[lanes];
    for (int y = 0; y < in.height; ++y) {
        int x0 = 0;
        for (; x0 + lanes <= width; x0 += lanes) {
            unsigned char* kept =
                sizes ? &sizes->eta[static_cast<std::size_t>(y) * width + x0] : nullptr;
            if (read) {
                for (int lane = 0; lane < lanes; ++lane) eta[lane] = kept[lane];
            } else {
                post_aa_sizes_avx(gaze, radius_max, x0, y, eta);
                if (kept)
                    for (int lane = 0; lane < lanes; ++lane)
                        kept[lane] = static_cast<unsigned char>(eta[lane]);
            }
            switch (in.channels) {
                case 1: post_aa_lanes_avx<1>(in, weights, cache, eta, out, x0, y); break;
                case 2: post_aa_lanes_avx<2>(in, weights, cache, eta, out, x0, y); break;
                case 3: post_aa_lanes_avx<3>(in, weights, cache, eta, out, x0, y); break;
                default: post_aa_lanes_avx<4>(in, weights, cache, eta, out, x0, y);
            }
        }
        for (int x = x0; x < width; ++x)
            post_aa_cached_pixel(in, gaze, radius_max, weights, cache, out, x, y);
    }
}

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

bool PostAaSizes::made_for(glm::vec2 g, float r, int w, int h) const {
    // Equal values give the same sizes (-0 and +0 alike); a NaN gaze never matches.
    return !eta.empty() && gaze == g && radius_max == r && width == w && height == h;
}

Image post_aa(const Image& in, glm::vec2 gaze, float radius_max, bool simd, PostAaSizes* sizes,
              Image storage) {
    FOVREF_CHECK(in.channels <= 4, "post anti-aliasing of more than 4 channels");
    std::vector<std::vector<float>> weights(max_eta + 1);
    for (int eta = 3; eta <= max_eta; eta += 2)
        weights[static_cast<std::size_t>(eta)] = post_aa_weights(eta);
    Image out = std::move(storage);  // every pixel is written below
    keep_or_make(out, in.width, in.height, in.channels);
    std::vector<PostAaRowCache> cache(max_eta + 1);
    if (simd && in.channels >= 1 && simd_allowed() && cpu_has_avx()) {
        post_aa_rows_avx(in, gaze, radius_max, weights, cache, out, sizes);
        return out;
    }
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
    PostAaRowCache& r = row_cache(cache, eta, width, channels);
    const int half = (eta - 1) / 2;
    float sum[4] = {0, 0, 0, 0};
    RowSlots slots{eta};
    for (int dy = -half; dy <= half; ++dy) {
        const int yy = std::clamp(y + dy, 0, in.height - 1);
        const int slot = slots.next(yy);
        const std::size_t k = r.index(slot, x);
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
