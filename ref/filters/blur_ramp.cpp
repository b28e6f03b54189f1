#include "ref/filters/blur_ramp.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "ref/core/avx_lanes.h"
#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/core/simd.h"
#include "ref/core/vec.h"

namespace fovref {

namespace {

void check_inputs(const BlurRamp& ramp, const BlurRampGeometry& geometry, const Image& image) {
    if (!(std::isfinite(ramp.sigma_deg) && ramp.sigma_deg >= 0.0f))
        throw Error("blur ramp: sigma_deg must be finite and >= 0 (got " +
                    check_value_text(ramp.sigma_deg) + ")");
    if (!std::isfinite(ramp.full_deg))
        throw Error("blur ramp: full_deg must be finite (got " + check_value_text(ramp.full_deg) +
                    ")");
    FOVREF_CHECK_EQ(image.width, geometry.screen_width, "blur ramp image width");
    FOVREF_CHECK_EQ(image.height, geometry.screen_height, "blur ramp image height");
}

/// The weights' base a = exp(-1 / (2 sigma^2)), 2 sigma first, then times sigma (one exp per
/// pixel: blur_ramp_weights, the AVX groups and the table all take it from here).
float blur_ramp_a(float sigma) { return dm::exp(-1.0f / (2.0f * sigma * sigma)); }

constexpr int lanes = 8;  // pixels per AVX group
constexpr int max_avx_channels = 4;

/// Lane by lane: `yes` where `mask` (a comparison's all-ones or zero lanes) is set, else `no`,
/// bit for bit.
__attribute__((target("avx"))) inline __m256 select(__m256 mask, __m256 yes, __m256 no) {
    return _mm256_or_ps(_mm256_and_ps(mask, yes), _mm256_andnot_ps(mask, no));
}

/// sum + w source (the product rounded first) where `active`, else sum; in every lane when
/// `Every` (no blend in the sum's dependency chain).
template <bool Every>
__attribute__((target("avx"))) inline __m256 add_tap(__m256 active, __m256 sum, __m256 w,
                                                     const float* source) {
    const __m256 added = _mm256_add_ps(sum, _mm256_mul_ps(w, _mm256_loadu_ps(source)));
    if constexpr (Every) return added;
    return select(active, added, sum);
}

/// blur_ramp_weights for eight pixels, lane by lane: a = exp(-1 / (2 sigma^2)) of each lane
/// (0 where its radius is 0), its radius, and the group's largest radius Rmax; fills
/// weights[0 .. Rmax][lane]. Each lane does blur_ramp_weights' operations in its order (the
/// normalising sum over its own d = -R .. R, a blend leaving it unchanged beyond); a lane's
/// weights beyond its radius are left finite and never used.
__attribute__((target("avx"))) void weights_avx(const float* a, const float* radius_f,
                                                int radius_max, float (*weights)[lanes]) {
    const __m256 radius = _mm256_load_ps(radius_f);
    const __m256 av = _mm256_load_ps(a);
    const __m256 a2 = _mm256_mul_ps(av, av);
    __m256 w = _mm256_set1_ps(1.0f), g = av;
    _mm256_store_ps(weights[0], w);
    for (int d = 1; d <= radius_max; ++d) {
        w = _mm256_mul_ps(w, g);
        g = _mm256_mul_ps(g, a2);
        _mm256_store_ps(weights[d], w);
    }
    __m256 sum = _mm256_setzero_ps();
    const bool uniform =
        _mm256_movemask_ps(_mm256_cmp_ps(radius, _mm256_set1_ps(static_cast<float>(radius_max)),
                                         _CMP_EQ_OQ)) == 0xff;
    if (uniform) {
        // every lane's radius is radius_max: every tap is active (no blend in the chain)
        for (int d = -radius_max; d <= radius_max; ++d)
            sum = _mm256_add_ps(sum, _mm256_load_ps(weights[d < 0 ? -d : d]));
    } else {
        for (int d = -radius_max; d <= radius_max; ++d) {
            const int ad = d < 0 ? -d : d;
            const __m256 active =
                _mm256_cmp_ps(_mm256_set1_ps(static_cast<float>(ad)), radius, _CMP_LE_OQ);
            sum = select(active, _mm256_add_ps(sum, _mm256_load_ps(weights[ad])), sum);
        }
    }
    const __m256 inverse = _mm256_div_ps(_mm256_set1_ps(1.0f), sum);
    for (int d = 0; d <= radius_max; ++d)
        _mm256_store_ps(weights[d], _mm256_mul_ps(_mm256_load_ps(weights[d]), inverse));
}

/// The weighted sums of eight pixels over their taps d = -Rmax .. Rmax, for C channels in
/// planes `plane` floats apart; lane 0's source of tap d is base + offsets[d] (offsets points at
/// d = 0's entry; the lanes' sources follow it). A lane adds w_|d| c_d only for |d| <= its radius
/// (select). Writes the sums to dest + c dest_plane in the lanes whose radius is not 0 (the
/// others keep what dest holds: the copied pixels).
template <int C, bool Uniform>
__attribute__((target("avx"))) void weighted_sums_avx(const float* base, std::size_t plane,
                                                      const std::ptrdiff_t* offsets,
                                                      const float (*weights)[lanes],
                                                      const float* radius_f, int radius_max,
                                                      float* dest, std::size_t dest_plane) {
    const __m256 radius = _mm256_load_ps(radius_f);
    // the channels' sums in registers (named: GCC keeps an array of them in memory)
    __m256 s0 = _mm256_setzero_ps(), s1 = s0, s2 = s0, s3 = s0;
    for (int d = -radius_max; d <= radius_max; ++d) {
        const int ad = d < 0 ? -d : d;
        const __m256 w = _mm256_load_ps(weights[ad]);
        // every lane's radius is radius_max (Uniform): every tap is active
        const __m256 active =
            Uniform ? _mm256_castsi256_ps(_mm256_set1_epi32(-1))
                    : _mm256_cmp_ps(_mm256_set1_ps(static_cast<float>(ad)), radius, _CMP_LE_OQ);
        const float* source = base + offsets[d];
        s0 = add_tap<Uniform>(active, s0, w, source);
        if constexpr (C > 1) s1 = add_tap<Uniform>(active, s1, w, source + plane);
        if constexpr (C > 2) s2 = add_tap<Uniform>(active, s2, w, source + 2 * plane);
        if constexpr (C > 3) s3 = add_tap<Uniform>(active, s3, w, source + 3 * plane);
    }
    const __m256 sum[4] = {s0, s1, s2, s3};
    const __m256 blurred = _mm256_cmp_ps(radius, _mm256_setzero_ps(), _CMP_NEQ_UQ);
    for (int c = 0; c < C; ++c) {
        float* to = dest + c * dest_plane;
        _mm256_storeu_ps(to, select(blurred, sum[c], _mm256_loadu_ps(to)));
    }
}

/// weighted_sums_avx<3, true> of G groups side by side (lane 0's sources base + 8 k + offsets[d]
/// for group k) with the same weights: each lane's sum in its order, the groups' 3 G sums in
/// flight together. Every lane is blurred (its radius is radius_max > 0).
template <int G>
__attribute__((target("avx"))) void weighted_sums_run3_avx(const float* base, std::size_t plane,
                                                           const std::ptrdiff_t* offsets,
                                                           const float (*weights)[lanes],
                                                           int radius_max, float* dest,
                                                           std::size_t dest_plane) {
    __m256 sums[3 * G];
    for (__m256& sum : sums) sum = _mm256_setzero_ps();
    const __m256 every = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
    for (int d = -radius_max; d <= radius_max; ++d) {
        const __m256 w = _mm256_load_ps(weights[d < 0 ? -d : d]);
        const float* source = base + offsets[d];
#pragma GCC unroll 12
        for (int k = 0; k < 3 * G; ++k)
            sums[k] = add_tap<true>(every, sums[k], w, source + (k / G) * plane + (k % G) * lanes);
    }
#pragma GCC unroll 12
    for (int k = 0; k < 3 * G; ++k)
        _mm256_storeu_ps(dest + (k / G) * dest_plane + (k % G) * lanes, sums[k]);
}

/// `count` pixels of `channels` interleaved channels at `from` as planes `plane` floats apart at
/// `to`, and back: plain copies of the same floats (three channels: eight pixels at a time with
/// AVX2 where the CPU has it).
__attribute__((target("avx2"))) void to_planes3_avx2(const float* from, std::size_t count,
                                                     float* to, std::size_t plane) {
    std::size_t k = 0;
    for (; k + lanes <= count; k += lanes) {
        __m256 rgb[3];
        avx::split3_lanes(from + 3 * k, rgb);
        for (int c = 0; c < 3; ++c) _mm256_storeu_ps(to + c * plane + k, rgb[c]);
    }
    for (; k < count; ++k)
        for (int c = 0; c < 3; ++c) to[c * plane + k] = from[3 * k + c];
}
__attribute__((target("avx2"))) void from_planes3_avx2(const float* from, std::size_t plane,
                                                       std::size_t count, float* to) {
    std::size_t k = 0;
    for (; k + lanes <= count; k += lanes) {
        const __m256 rgb[3] = {_mm256_loadu_ps(from + k), _mm256_loadu_ps(from + plane + k),
                               _mm256_loadu_ps(from + 2 * plane + k)};
        avx::merge3_lanes(rgb, to + 3 * k);
    }
    for (; k < count; ++k)
        for (int c = 0; c < 3; ++c) to[3 * k + c] = from[c * plane + k];
}
void to_planes(const float* from, int channels, std::size_t count, float* to, std::size_t plane) {
    if (channels == 3 && cpu_has_avx2()) return to_planes3_avx2(from, count, to, plane);
    for (std::size_t k = 0; k < count; ++k)
        for (int c = 0; c < channels; ++c) to[c * plane + k] = from[k * channels + c];
}
void from_planes(const float* from, std::size_t plane, int channels, std::size_t count, float* to) {
    if (channels == 3 && cpu_has_avx2()) return from_planes3_avx2(from, plane, count, to);
    for (std::size_t k = 0; k < count; ++k)
        for (int c = 0; c < channels; ++c) to[k * channels + c] = from[c * plane + k];
}

/// blur_ramp_radius of eight sigmas, lane by lane (as floats): 0 where !(sigma > 0), else
/// min(ceil(3 sigma), blur_ramp_max_radius) (roundps: std::ceil's value).
__attribute__((target("avx"))) inline __m256 radius_lanes(__m256 sigma) {
    const __m256 r = _mm256_round_ps(_mm256_mul_ps(_mm256_set1_ps(3.0f), sigma),
                                     _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC);
    const __m256 cap = _mm256_set1_ps(static_cast<float>(blur_ramp_max_radius));
    const __m256 capped = select(_mm256_cmp_ps(r, cap, _CMP_GE_OQ), cap, r);
    return select(_mm256_cmp_ps(sigma, _mm256_setzero_ps(), _CMP_GT_OQ), capped,
                  _mm256_setzero_ps());
}

/// A group's weights (weights_avx), kept for the next group: they depend only on each lane's a
/// and radius, so a group like the last one (beyond full_deg every pixel has the same sigma)
/// keeps them instead of making them again.
struct KeptWeights {
    alignas(32) float w[blur_ramp_max_radius + 1][lanes];
    float a[lanes] = {}, radius[lanes] = {};  ///< what `w` was made for
    int radius_max = -1;                      ///< -1: nothing made yet
    __attribute__((target("avx"))) void make(const float* lane_a, const float* lane_radius,
                                             int group_radius_max) {
        bool same = group_radius_max == radius_max;
        for (int lane = 0; lane < lanes; ++lane)
            same = same && lane_a[lane] == a[lane] && lane_radius[lane] == radius[lane];
        if (same) return;
        weights_avx(lane_a, lane_radius, group_radius_max, w);
        radius_max = group_radius_max;
        for (int lane = 0; lane < lanes; ++lane) {
            a[lane] = lane_a[lane];
            radius[lane] = lane_radius[lane];
        }
    }
};

/// The radii of a group's lanes of `sigma` (radius_lanes) into radius_f; returns their largest,
/// and whether every lane has it.
__attribute__((target("avx"))) float group_radii(__m256 sigma, float* radius_f, bool& uniform) {
    const __m256 radius = radius_lanes(sigma);
    _mm256_storeu_ps(radius_f, radius);
    __m256 largest = _mm256_max_ps(radius, _mm256_permute2f128_ps(radius, radius, 1));
    largest = _mm256_max_ps(largest, _mm256_permute_ps(largest, 0b01001110));
    largest = _mm256_max_ps(largest, _mm256_permute_ps(largest, 0b10110001));
    uniform = _mm256_movemask_ps(_mm256_cmp_ps(radius, largest, _CMP_EQ_OQ)) == 0xff;
    return _mm256_cvtss_f32(largest);
}

/// The exp of the last sigma (beyond full_deg every pixel has the same sigma).
struct KeptExp {
    float sigma = 0.0f, a = 0.0f;  // sigma > 0 wherever a is used
    float of(float lane_sigma) {
        if (!(lane_sigma == sigma)) {
            sigma = lane_sigma;
            a = blur_ramp_a(lane_sigma);
        }
        return a;
    }
};

/// The lanes' a: the exp of their sigma; a copied lane (radius 0) gets 0.5, whose finite dummy
/// weights are computed and never used.
void group_a(const float* sigma, const float* radius_f, KeptExp& exp, float* a) {
    for (int lane = 0; lane < lanes; ++lane)
        a[lane] = radius_f[lane] == 0.0f ? 0.5f : exp.of(sigma[lane]);
}

/// A group's sigma and a from the table (its sigma_a: sigma, a of each pixel, interleaved),
/// split by shuffles into whole registers: arrays filled lane by lane and then loaded whole
/// would make each load wait until the eight stores reach the cache.
__attribute__((target("avx"))) void split_sigma_a(const float* kept, __m256& sigma, __m256& a) {
    const __m256 even = _mm256_set_m128(_mm_loadu_ps(kept + 8), _mm_loadu_ps(kept));
    const __m256 odd = _mm256_set_m128(_mm_loadu_ps(kept + 12), _mm_loadu_ps(kept + 4));
    sigma = _mm256_shuffle_ps(even, odd, _MM_SHUFFLE(2, 0, 2, 0));
    a = _mm256_shuffle_ps(even, odd, _MM_SHUFFLE(3, 1, 3, 1));
}

/// How many groups from x0 on are summed with this uniform one (4, 2, or 1): the next groups
/// whose pixels all have sigma[0], as this group's do (beyond full_deg), so the same weights.
int groups_alike(const BlurRamp& ramp, const BlurRampGeometry& geometry, const float* kept,
                 const float* sigma, int x0, int y, int width) {
    for (int lane = 0; lane < lanes; ++lane)
        if (!(sigma[lane] == sigma[0])) return 1;
    int same = lanes;  // pixels from x0 on with sigma[0]
    while (same < 4 * lanes && x0 + same < width &&
           (kept ? kept[2 * same]
                 : blur_ramp_sigma_px(ramp, geometry, pixel_centre(x0 + same, y))) == sigma[0])
        ++same;
    for (const int groups : {4, 2})
        if (same >= groups * lanes) return groups;
    return 1;
}

/// The sums of `run` groups (1, 2 or 4; 2 and 4 uniform, three channels) into dest.
void sum_groups(int run, bool uniform, int channels, const float* base, std::size_t plane,
                const std::ptrdiff_t* offsets, const float (*weights)[lanes], const float* radius_f,
                int radius_max, float* dest, std::size_t dest_plane) {
    if (run == 4)
        return weighted_sums_run3_avx<4>(base, plane, offsets, weights, radius_max, dest,
                                         dest_plane);
    if (run == 2)
        return weighted_sums_run3_avx<2>(base, plane, offsets, weights, radius_max, dest,
                                         dest_plane);
    using SumsOf = void (*)(const float*, std::size_t, const std::ptrdiff_t*, const float(*)[lanes],
                            const float*, int, float*, std::size_t);
    static constexpr SumsOf kernels[8] = {weighted_sums_avx<1, false>, weighted_sums_avx<1, true>,
                                          weighted_sums_avx<2, false>, weighted_sums_avx<2, true>,
                                          weighted_sums_avx<3, false>, weighted_sums_avx<3, true>,
                                          weighted_sums_avx<4, false>, weighted_sums_avx<4, true>};
    kernels[(channels - 1) * 2 + (uniform ? 1 : 0)](base, plane, offsets, weights, radius_f,
                                                    radius_max, dest, dest_plane);
}

/// One output row of a pass, its groups summed one (or one run) at a time from the left
/// (blur_pass_avx): the row's tap offsets, its output in planes (the input's row, the groups'
/// sums written over it, then interleaved into `out` before the pixels that blur_ramp_pixel
/// writes there itself), and the weights and exp kept from one group to the next.
struct RowSums {
    RowSums(const BlurRamp& r, const BlurRampGeometry& g, const Image& i, const BlurRampTable* t,
            bool v, const float* p, std::size_t row_pitch, int row_pad, std::size_t plane_floats)
        : ramp(r),
          geometry(g),
          image(i),
          table(t),
          vertical(v),
          planes(p),
          pitch(row_pitch),
          pad(static_cast<std::size_t>(row_pad)),
          plane(plane_floats) {}
    const BlurRamp& ramp;
    const BlurRampGeometry& geometry;
    const Image& image;
    const BlurRampTable* table;
    bool vertical;
    const float* planes;
    std::size_t pitch, pad, plane;
    int y = 0, x0 = 0;
    std::vector<float> row = std::vector<float>(static_cast<std::size_t>(image.channels) *
                                                static_cast<std::size_t>(image.width));
    // The taps' offsets from lane 0's pixel, indexed by d = -Rmax .. Rmax around the middle: d
    // pixels along x, or rows y + d clamped to the image along y
    std::ptrdiff_t offsets[2 * blur_ramp_max_radius + 1] = {};
    KeptWeights weights;
    KeptExp exp;

    void begin(int row_y) {
        y = row_y, x0 = 0;
        const int width = image.width, height = image.height;
        for (int d = -blur_ramp_max_radius; d <= blur_ramp_max_radius; ++d)
            offsets[d + blur_ramp_max_radius] =
                vertical ? static_cast<std::ptrdiff_t>(std::clamp(y + d, 0, height - 1) - y) *
                               static_cast<std::ptrdiff_t>(pitch)
                         : d;
        for (int c = 0; c < image.channels; ++c)
            std::copy_n(planes + c * plane + start(), width, row.data() + c * width);
    }
    std::size_t start() const { return static_cast<std::size_t>(y) * pitch + pad; }
    bool done() const { return x0 + lanes > image.width; }
    /// The group (or run of groups) at x0, then x0 past it.
    __attribute__((target("avx"))) void step() {
        alignas(32) float radius_f[lanes], sigma[lanes], a[lanes];
        const float* kept = table ? &table->sigma_a.data[table->sigma_a.index(x0, y)] : nullptr;
        __m256 sigma_lanes, kept_a = _mm256_setzero_ps();
        if (kept) {
            split_sigma_a(kept, sigma_lanes, kept_a);
            _mm256_store_ps(sigma, sigma_lanes);
        } else {
            avx::leave_for_scalar();
            for (int lane = 0; lane < lanes; ++lane)
                sigma[lane] = blur_ramp_sigma_px(ramp, geometry, pixel_centre(x0 + lane, y));
            sigma_lanes = _mm256_load_ps(sigma);
        }
        bool uniform = false;  // every lane of the group has the radius radius_max
        const float radius_max_f = group_radii(sigma_lanes, radius_f, uniform);
        if (radius_max_f == 0.0f) {  // all copied
            x0 += lanes;
            return;
        }
        const int radius_max = static_cast<int>(radius_max_f);
        if (kept) {  // group_a with the table's a
            const __m256 copied =
                _mm256_cmp_ps(_mm256_load_ps(radius_f), _mm256_setzero_ps(), _CMP_EQ_OQ);
            _mm256_store_ps(a, select(copied, _mm256_set1_ps(0.5f), kept_a));
        } else {
            group_a(sigma, radius_f, exp, a);
        }
        weights.make(a, radius_f, radius_max);
        // The next groups with the same sigma in every lane (beyond full_deg) have the same
        // weights: four or two groups' sums together (three channels)
        const int channels = image.channels, width = image.width;
        if (!kept && channels == 3 && uniform) avx::leave_for_scalar();  // blur_ramp_sigma_px
        const int run =
            channels == 3 && uniform ? groups_alike(ramp, geometry, kept, sigma, x0, y, width) : 1;
        sum_groups(run, uniform, channels, planes + start() + x0, plane,
                   offsets + blur_ramp_max_radius, weights.w, radius_f, radius_max, row.data() + x0,
                   static_cast<std::size_t>(width));
        x0 += run * lanes;
    }
    void finish(Image& out) {
        const auto width = static_cast<std::size_t>(image.width);
        from_planes(row.data(), width, image.channels, width, &out.data[out.index(0, y)]);
        for (int x = x0; x < image.width; ++x)
            blur_ramp_pixel(ramp, geometry, image, vertical, out, x, y);
    }
};

/// The pass on eight pixels at a time (AVX; used only where the CPU has it, `channels` <= 4).
/// Each lane does its own pixel's scalar operations in blur_ramp_pixel's order: the sum starts
/// at 0 and adds w_d c_d (the product rounded, no FMA) for d = -R .. R of that pixel's R. A
/// group runs d over -Rmax .. Rmax of its largest radius, and a lane whose |d| > R keeps its
/// sum unchanged (a blend, not a zero weight, so that no value read outside a lane's own taps
/// can reach it): the same bits as blur_ramp_pixel, lane by lane. A tap beyond the image reads
/// the pixel the reference's clamp gives (the rows along y by the offsets, the pixels along x from
/// the copies around each plane row). The last W mod 8 pixels of a row run blur_ramp_pixel
/// itself.
__attribute__((target("avx"))) void blur_pass_avx(const BlurRamp& ramp,
                                                  const BlurRampGeometry& geometry,
                                                  const Image& image, bool vertical, Image& out,
                                                  const BlurRampTable* table) {
    const int width = image.width, height = image.height, channels = image.channels;
    // The image in planes, so that a lane's taps along x or y are one unaligned load per channel.
    // Along x each plane row has the largest radius's pixels before and after it, copies of the
    // row's first and last pixel: a tap beyond the row reads the pixel its clamp gives.
    const int pad = vertical ? 0 : blur_ramp_max_radius;
    const std::size_t pitch = static_cast<std::size_t>(width + 2 * pad + (vertical ? 16 : 0));
    const std::size_t plane = pitch * static_cast<std::size_t>(height) + 16;
    // Not zero-filled: every float a group reads is written below (the 16 floats after each
    // vertical row and each plane are never read)
    const auto planes =
        std::make_unique_for_overwrite<float[]>(static_cast<std::size_t>(channels) * plane);
    for (int y = 0; y < height; ++y) {
        float* start = planes.get() + static_cast<std::size_t>(y) * pitch;
        to_planes(&image.data[image.index(0, y)], channels, static_cast<std::size_t>(width),
                  start + pad, plane);
        for (int c = 0; c < channels; ++c) {
            float* row_c = start + static_cast<std::size_t>(c) * plane;
            std::fill_n(row_c, pad, row_c[pad]);
            std::fill_n(row_c + pad + width, pad, row_c[pad + width - 1]);
        }
    }
    // Along y, rows in pairs whose groups alternate, the later row's group next: the second
    // row's taps are the first's rows but one, still in the cache. Each row the same sums.
    const int together = vertical ? 2 : 1;
    std::vector<RowSums> rows(
        together, RowSums(ramp, geometry, image, table, vertical, planes.get(), pitch, pad, plane));
    for (int y = 0; y < height; y += together) {
        const int count = std::min(together, height - y);
        for (int k = 0; k < count; ++k) rows[k].begin(y + k);
        for (;;) {
            RowSums* next = nullptr;  // the row whose next group lies furthest left
            for (int k = 0; k < count; ++k)
                if (!rows[k].done() && (!next || rows[k].x0 < next->x0)) next = &rows[k];
            if (!next) break;
            next->step();
        }
        for (int k = 0; k < count; ++k) rows[k].finish(out);
    }
}

/// One pass along x (`vertical` false) or y (true): the AVX groups where the CPU has AVX (the
/// same bits), else blur_ramp_pixel pixel by pixel.
Image blur_pass(const BlurRamp& ramp, const BlurRampGeometry& geometry, const Image& image,
                bool vertical, bool simd, const BlurRampTable* table, Image storage) {
    check_inputs(ramp, geometry, image);
    FOVREF_CHECK(!table || table->made_for(ramp, geometry),
                 "a blur ramp table made for another ramp or geometry");
    if (simd && image.channels >= 1 && image.channels <= max_avx_channels && simd_allowed() &&
        cpu_has_avx()) {
        // The AVX pass writes every pixel (each row whole from its planes, copied pixels
        // included): the storage as it is, no copy of the image first
        Image out = std::move(storage);
        keep_or_make(out, image.width, image.height, image.channels);
        blur_pass_avx(ramp, geometry, image, vertical, out, table);
        return out;
    }
    Image out = image;  // blur_ramp_pixel leaves a copied pixel (radius 0) as it is
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            blur_ramp_pixel(ramp, geometry, image, vertical, out, x, y);
    return out;
}

}  // namespace

float blur_ramp_sigma_px(const BlurRamp& ramp, const BlurRampGeometry& geometry, glm::vec2 p) {
    const float e = gaze_distance(geometry.gaze, p) / geometry.scale;
    const float fovea_edge = geometry.fovea_deg;
    float sigma = 0.0f;  // model degrees
    if (e <= fovea_edge)
        sigma = 0.0f;
    else if (e >= ramp.full_deg)
        sigma = ramp.sigma_deg;
    else
        sigma = ramp.sigma_deg * (e - fovea_edge) / (ramp.full_deg - fovea_edge);
    return sigma * geometry.scale;
}

void blur_ramp_weights(float sigma, int radius, float* weights) {
    // Gaussian weights w_|d| = a^(d^2), a = exp(-1 / (2 sigma^2)), d = 0 .. R, by the
    // recurrence w_d = w_(d-1) g_d, g_d = g_(d-1) a^2 (g_1 = a): one exp per pixel
    const float a = blur_ramp_a(sigma);
    const float a2 = a * a;
    weights[0] = 1.0f;
    float g = a;
    for (int d = 1; d <= radius; ++d) {
        weights[d] = weights[d - 1] * g;
        g = g * a2;
    }
    // Normalised: the sum over the taps -R .. R (from -R up), then each weight / sum
    float weight_sum = 0.0f;
    for (int d = -radius; d <= radius; ++d) weight_sum += weights[d < 0 ? -d : d];
    const float inverse = 1.0f / weight_sum;
    for (int d = 0; d <= radius; ++d) weights[d] = weights[d] * inverse;
}

int blur_ramp_radius(float sigma_px) {
    if (!(sigma_px > 0.0f)) return 0;
    const float radius = std::ceil(3.0f * sigma_px);
    return radius >= static_cast<float>(blur_ramp_max_radius) ? blur_ramp_max_radius
                                                              : static_cast<int>(radius);
}

namespace {

/// The floats from a pixel to its tap d along the pass: d pixels, clamped to the border unless
/// every tap lies `inside`.
std::ptrdiff_t tap_offset(bool inside, int position, int d, int extent, std::ptrdiff_t stride) {
    return (inside ? d : std::clamp(position + d, 0, extent - 1) - position) * stride;
}

}  // namespace

void blur_ramp_pixel(const BlurRamp& ramp, const BlurRampGeometry& geometry, const Image& image,
                     bool vertical, Image& out, int x, int y) {
    const int width = image.width, height = image.height, channels = image.channels;
    const glm::vec2 centre = pixel_centre(x, y);
    const float sigma = blur_ramp_sigma_px(ramp, geometry, centre);
    const int radius = blur_ramp_radius(sigma);
    if (radius == 0) return;  // copied

    float weights[blur_ramp_max_radius + 1];
    blur_ramp_weights(sigma, radius, weights);

    // The weighted sum over the taps -R .. R, clamped to the border
    const int extent = vertical ? height : width;
    const std::ptrdiff_t stride =  // floats from one pixel to the next along the pass
        vertical ? static_cast<std::ptrdiff_t>(width) * channels : channels;
    const int position = vertical ? y : x;
    const float* centre_pixel = &image.data[image.index(x, y)];
    const bool inside = position - radius >= 0 && position + radius < extent;
    float* o = &out.data[out.index(x, y)];
    if (channels == 3) {  // the colour images of the modes: sums kept in registers
        float m0 = 0.0f, m1 = 0.0f, m2 = 0.0f;
        for (int d = -radius; d <= radius; ++d) {
            const float weight = weights[d < 0 ? -d : d];
            const float* source = centre_pixel + tap_offset(inside, position, d, extent, stride);
            m0 += weight * source[0];
            m1 += weight * source[1];
            m2 += weight * source[2];
        }
        o[0] = m0, o[1] = m1, o[2] = m2;
        return;
    }
    std::vector<float> mean(static_cast<std::size_t>(channels), 0.0f);
    for (int d = -radius; d <= radius; ++d) {
        const float weight = weights[d < 0 ? -d : d];
        const float* source = centre_pixel + tap_offset(inside, position, d, extent, stride);
        for (int c = 0; c < channels; ++c) mean[static_cast<std::size_t>(c)] += weight * source[c];
    }
    for (int c = 0; c < channels; ++c) o[c] = mean[static_cast<std::size_t>(c)];
}

Image blur_ramp_horizontal(const BlurRamp& ramp, const BlurRampGeometry& geometry,
                           const Image& image, bool simd, const BlurRampTable* table,
                           Image storage) {
    return blur_pass(ramp, geometry, image, false, simd, table, std::move(storage));
}

Image blur_ramp_vertical(const BlurRamp& ramp, const BlurRampGeometry& geometry, const Image& image,
                         bool simd, const BlurRampTable* table, Image storage) {
    return blur_pass(ramp, geometry, image, true, simd, table, std::move(storage));
}

bool BlurRampTable::made_for(const BlurRamp& r, const BlurRampGeometry& g) const {
    return ramp == r && geometry == g;
}

namespace {

/// The table's sigma_px (blur_ramp_sigma_px at the pixel centres) and exp arguments
/// -1 / ((2 sigma) sigma) (0 where the radius is 0) of pixels x .. x + 7 of row y, each lane
/// doing the scalar operations in their order (AVX).
__attribute__((target("avx"))) void table_sigma_group(const BlurRamp& ramp,
                                                      const BlurRampGeometry& geometry, int x,
                                                      int y, float* sigma_out, float* argument) {
    using namespace avx;
    // x + l exactly (x + 7 < 2^24), then + 1/2: pixel_centre's x
    const __m256 px = _mm256_add_ps(
        _mm256_add_ps(set(static_cast<float>(x)), _mm256_setr_ps(0, 1, 2, 3, 4, 5, 6, 7)),
        set(0.5f));
    const __m256 dx = _mm256_sub_ps(px, set(geometry.gaze.x));
    const __m256 dy = set(static_cast<float>(y) + 0.5f - geometry.gaze.y);
    const __m256 e =
        _mm256_div_ps(_mm256_sqrt_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy))),
                      set(geometry.scale));
    // 0 for e <= e_f, sigma_deg for e >= full_deg, else the ramp (NaN: the ramp's NaN)
    const __m256 fovea_edge = set(geometry.fovea_deg);
    const __m256 ramped =
        _mm256_div_ps(_mm256_mul_ps(set(ramp.sigma_deg), _mm256_sub_ps(e, fovea_edge)),
                      _mm256_sub_ps(set(ramp.full_deg), fovea_edge));
    const __m256 sigma_deg =
        avx::select(at_most(e, fovea_edge), zero(),
                    avx::select(at_least(e, set(ramp.full_deg)), set(ramp.sigma_deg), ramped));
    const __m256 sigma = _mm256_mul_ps(sigma_deg, set(geometry.scale));
    const __m256 blurred = greater(radius_lanes(sigma), zero());
    _mm256_storeu_ps(sigma_out, sigma);
    _mm256_storeu_ps(
        argument, avx::select(blurred,
                              _mm256_div_ps(set(-1.0f),
                                            _mm256_mul_ps(_mm256_mul_ps(set(2.0f), sigma), sigma)),
                              zero()));
}

}  // namespace

BlurRampTable blur_ramp_table(const BlurRamp& ramp, const BlurRampGeometry& geometry) {
    BlurRampTable table{ramp, geometry, Image(geometry.screen_width, geometry.screen_height, 2)};
    // Row by row: each pixel's sigma (eight at a time with AVX, the same bits), then
    // blur_ramp_a's exp of the row's arguments -1 / ((2 sigma) sigma) at once (dm::exp_array,
    // the same bits); 0 where the radius is 0
    const auto width = static_cast<std::size_t>(geometry.screen_width);
    const std::size_t in_lanes = simd_allowed() && cpu_has_avx() ? width / lanes * lanes : 0;
    std::vector<float> sigmas(width), argument(width), a(width);
    for (int y = 0; y < geometry.screen_height; ++y) {
        for (std::size_t x = 0; x < in_lanes; x += lanes)
            table_sigma_group(ramp, geometry, static_cast<int>(x), y, &sigmas[x], &argument[x]);
        for (std::size_t x = in_lanes; x < width; ++x) {
            const float sigma =
                blur_ramp_sigma_px(ramp, geometry, pixel_centre(static_cast<int>(x), y));
            sigmas[x] = sigma;
            argument[x] = blur_ramp_radius(sigma) > 0 ? -1.0f / (2.0f * sigma * sigma) : 0.0f;
        }
        dm::exp_array(argument.data(), a.data(), width);
        float* row = &table.sigma_a.data[table.sigma_a.index(0, y)];
        for (std::size_t x = 0; x < width; ++x)
            row[2 * x] = sigmas[x], row[2 * x + 1] = blur_ramp_radius(sigmas[x]) > 0 ? a[x] : 0.0f;
    }
    return table;
}

Image blur_ramp(const BlurRamp& ramp, const BlurRampGeometry& geometry, const Image& image,
                bool simd) {
    return blur_ramp_vertical(ramp, geometry, blur_ramp_horizontal(ramp, geometry, image, simd),
                              simd);
}

}  // namespace fovref
