#include "ref/filters/blur_ramp.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
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

using avx::select;  // a comparison mask's lanes: `yes` where set, else `no`, bit for bit

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
        // a lane beyond its radius adds +0, which leaves its sum as it is (see sums_lanes)
        for (int d = -radius_max; d <= radius_max; ++d) {
            const int ad = d < 0 ? -d : d;
            const __m256 active =
                _mm256_cmp_ps(_mm256_set1_ps(static_cast<float>(ad)), radius, _CMP_LE_OQ);
            sum = _mm256_add_ps(sum, _mm256_and_ps(active, _mm256_load_ps(weights[ad])));
        }
    }
    const __m256 inverse = _mm256_div_ps(_mm256_set1_ps(1.0f), sum);
    for (int d = 0; d <= radius_max; ++d)
        _mm256_store_ps(weights[d], _mm256_mul_ps(_mm256_load_ps(weights[d]), inverse));
}

/// The sums of a run of G groups (8 G pixels of three interleaved channels: 3 G registers) whose
/// pixels all have the same weights and radius R (one sigma: beyond full_deg every pixel has it),
/// every tap active: each float's sum starts at 0 and adds w_|d| c_d (the product rounded, no
/// FMA) for d = -R .. R, blur_ramp_pixel's operations in its order. Tap d of the run's first
/// float lies at base + offsets[d], the run's other floats after it; the sums go to dest.
template <int G>
__attribute__((target("avx2"))) void sums_alike(const float* base, const std::ptrdiff_t* offsets,
                                                int radius, const float (*weights)[lanes],
                                                float* dest) {
    __m256 sums[3 * G];
    for (__m256& sum : sums) sum = _mm256_setzero_ps();
    for (int d = -radius; d <= radius; ++d) {
        const __m256 w = _mm256_set1_ps(weights[d < 0 ? -d : d][0]);  // every lane's
        const float* source = base + offsets[d];
#pragma GCC unroll 12
        for (int k = 0; k < 3 * G; ++k)
            sums[k] = _mm256_add_ps(sums[k], _mm256_mul_ps(w, _mm256_loadu_ps(source + lanes * k)));
    }
#pragma GCC unroll 12
    for (int k = 0; k < 3 * G; ++k) _mm256_storeu_ps(dest + lanes * k, sums[k]);
}

/// The sums of one group of eight pixels with weights of their own (the ramp's pixels), over
/// d = -Rmax .. Rmax of the group's largest radius: a float of pixel l adds w_|d|(l) c_d for
/// |d| <= its radius, and +0 beyond it (the product masked to +0, so that no value outside its
/// own taps reaches it, not even a NaN or an infinity; every lane adds its product when `Every`,
/// all radii being Rmax); the pixel's weights and masks spread to its three floats
/// (spread3_lanes). Adding +0 leaves a sum's bits as they are, because a sum is never -0: it
/// starts at +0, and a sum in round-to-nearest is -0 only when both terms are (with the default
/// MXCSR, which nothing in fovref changes: under flush-to-zero a cancelling subnormal sum could
/// round to -0). So each float's
/// sum is blur_ramp_pixel's, and the masking stays off the chain of dependent additions (a
/// blend of the sum after each addition made those chains twice as long). A pixel whose radius
/// is 0 keeps its input value (`input`: the group's 24 input floats). Taps as sums_alike's.
template <bool Every>
__attribute__((target("avx2"))) void sums_lanes(const float* base, const std::ptrdiff_t* offsets,
                                                int radius_max, const float (*weights)[lanes],
                                                const float* radius_f, const float* input,
                                                float* dest) {
    const __m256 radius = _mm256_load_ps(radius_f);
    __m256 s0 = _mm256_setzero_ps(), s1 = s0, s2 = s0;
    for (int d = -radius_max; d <= radius_max; ++d) {
        const int ad = d < 0 ? -d : d;
        __m256 w[3], active[3];
        avx::spread3_lanes(_mm256_loadu_ps(weights[ad]), w);  // (a plan pool: unaligned)
        if constexpr (!Every)
            avx::spread3_lanes(
                _mm256_cmp_ps(_mm256_set1_ps(static_cast<float>(ad)), radius, _CMP_LE_OQ), active);
        const float* source = base + offsets[d];
        __m256 products[3] = {_mm256_mul_ps(w[0], _mm256_loadu_ps(source)),
                              _mm256_mul_ps(w[1], _mm256_loadu_ps(source + lanes)),
                              _mm256_mul_ps(w[2], _mm256_loadu_ps(source + 2 * lanes))};
        if constexpr (!Every)
            for (int k = 0; k < 3; ++k) products[k] = _mm256_and_ps(active[k], products[k]);
        s0 = _mm256_add_ps(s0, products[0]);
        s1 = _mm256_add_ps(s1, products[1]);
        s2 = _mm256_add_ps(s2, products[2]);
    }
    __m256 blurred[3];
    avx::spread3_lanes(_mm256_cmp_ps(radius, _mm256_setzero_ps(), _CMP_NEQ_UQ), blurred);
    const __m256 sums[3] = {s0, s1, s2};
    for (int k = 0; k < 3; ++k)
        _mm256_storeu_ps(dest + lanes * k,
                         select(blurred[k], sums[k], _mm256_loadu_ps(input + lanes * k)));
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
    int made = 0;                             ///< sets of weights made so far
    __attribute__((target("avx"))) void make(const float* lane_a, const float* lane_radius,
                                             int group_radius_max) {
        bool same = group_radius_max == radius_max;
        for (int lane = 0; lane < lanes; ++lane)
            same = same && lane_a[lane] == a[lane] && lane_radius[lane] == radius[lane];
        if (same) return;
        ++made;
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
/// `sigma_at(x)`: the sigma of pixel x of the row.
template <class SigmaAt>
int groups_alike(const float* sigma, int x0, int width, SigmaAt sigma_at) {
    for (int lane = 0; lane < lanes; ++lane)
        if (!(sigma[lane] == sigma[0])) return 1;
    int same = lanes;  // pixels from x0 on with sigma[0]
    while (same < 4 * lanes && x0 + same < width && sigma_at(x0 + same) == sigma[0]) ++same;
    for (const int groups : {4, 2})
        if (same >= groups * lanes) return groups;
    return 1;
}

/// groups_alike with each pixel's sigma computed (no table): legacy-SSE code in a function of its
/// own, so that its caller's vzeroupper comes right before the call.
[[gnu::noinline]] int groups_alike_computed(const BlurRamp& ramp, const BlurRampGeometry& geometry,
                                            const float* sigma, int x0, int y, int width) {
    return groups_alike(sigma, x0, width, [&](int x) {
        return blur_ramp_sigma_px(ramp, geometry, pixel_centre(x, y));
    });
}

}  // namespace

/// What a pass does to a group of eight pixels (or a run of alike groups), decided from its
/// sigmas (RowPass::decide): copied (every radius 0), summed alike (sums_alike of `groups`
/// groups) or lane by lane (sums_lanes, every lane at Rmax or not), with its lanes' radii.
struct BlurRampJob {
    enum Kind : std::uint8_t { copied, alike, by_lane, by_lane_every } kind = copied;
    std::uint8_t groups = 1;
    std::uint8_t radius_max = 0;
    int x0 = 0;
    std::uint32_t weights = 0;  ///< in a plan: its weights' first float in the plan's pool
    alignas(32) float radius[lanes] = {};
    int pixels() const { return kind == alike ? lanes * groups : lanes; }
};

/// The AVX passes' decisions for every group of a table's ramp and geometry (a static gaze),
/// made once with the table: each row's jobs, and the weights they use (each set once, rows
/// 0 .. Rmax of eight floats). The horizontal and the vertical pass have the same groups with the
/// same sigmas, so both replay the same plan; the bits are those of deciding again.
struct BlurRampPlan {
    std::vector<BlurRampJob> jobs;     ///< row by row, from the left
    std::vector<std::size_t> row_end;  ///< row y's jobs end at row_end[y]
    std::vector<float> weights;
};

namespace {

/// One row of a pass, eight pixels (one group, or a run of alike groups) at a time from the left
/// (blur_pass_avx): the taps' offsets from a group's first float, where the row's taps lie
/// (`base`: the input's row itself along y, a copy with the clamped pixels around it along x),
/// and the weights and exp kept from one group to the next. A group is decided (decide), then
/// summed (execute); a table's plan replays decisions made once.
struct RowPass {
    RowPass(const BlurRamp& r, const BlurRampGeometry& g, const BlurRampTable* t)
        : ramp(r), geometry(g), table(t) {}
    const BlurRamp& ramp;
    const BlurRampGeometry& geometry;
    const BlurRampTable* table;
    const float* base = nullptr;  ///< pixel 0's first float of the taps' row
    const float* input = nullptr;
    float* output = nullptr;
    int y = 0, width = 0;
    // Indexed by d = -Rmax .. Rmax around the middle: d pixels along x, or rows y + d clamped to
    // the image along y
    std::ptrdiff_t offsets[2 * blur_ramp_max_radius + 1] = {};
    KeptWeights weights;
    KeptExp exp;

    /// The job of the group (or run of groups) at x0, its weights made (or kept) in `weights`.
    __attribute__((target("avx2"))) void decide(int x0, BlurRampJob& job) {
        alignas(32) float sigma[lanes], a[lanes];
        job.x0 = x0;
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
        const float radius_max_f = group_radii(sigma_lanes, job.radius, uniform);
        if (radius_max_f == 0.0f) {  // all copied
            job.kind = BlurRampJob::copied;
            return;
        }
        const int radius_max = static_cast<int>(radius_max_f);
        job.radius_max = static_cast<std::uint8_t>(radius_max);
        if (kept) {  // group_a with the table's a
            const __m256 copied =
                _mm256_cmp_ps(_mm256_load_ps(job.radius), _mm256_setzero_ps(), _CMP_EQ_OQ);
            _mm256_store_ps(a, select(copied, _mm256_set1_ps(0.5f), kept_a));
        } else {
            group_a(sigma, job.radius, exp, a);
        }
        weights.make(a, job.radius, radius_max);
        if (!uniform) {
            job.kind = BlurRampJob::by_lane;
            return;
        }
        // Every lane with one sigma (beyond full_deg): the weights alike, and so those of the
        // next groups with it (four or two groups' sums together)
        int run = 1;
        if (kept) {
            run = groups_alike(sigma, x0, width, [&](int x) { return kept[2 * (x - x0)]; });
        } else {
            avx::leave_for_scalar();  // blur_ramp_sigma_px
            run = groups_alike_computed(ramp, geometry, sigma, x0, y, width);
        }
        bool alike = true;
        for (int lane = 1; lane < lanes; ++lane) alike = alike && sigma[lane] == sigma[0];
        job.kind = run > 1 || alike ? BlurRampJob::alike : BlurRampJob::by_lane_every;
        job.groups = static_cast<std::uint8_t>(run);
    }

    /// The sums of a job with its weights w[0 .. Rmax][lane].
    __attribute__((target("avx2"))) void execute(const BlurRampJob& job, const float (*w)[lanes]) {
        const std::size_t first = 3 * static_cast<std::size_t>(job.x0);
        const std::ptrdiff_t* middle = offsets + blur_ramp_max_radius;
        const int radius = job.radius_max;
        switch (job.kind) {
            case BlurRampJob::copied: std::copy_n(input + first, 3 * lanes, output + first); return;
            case BlurRampJob::by_lane:
                sums_lanes<false>(base + first, middle, radius, w, job.radius, input + first,
                                  output + first);
                return;
            case BlurRampJob::by_lane_every:
                sums_lanes<true>(base + first, middle, radius, w, job.radius, input + first,
                                 output + first);
                return;
            case BlurRampJob::alike: break;
        }
        switch (job.groups) {
            case 4: sums_alike<4>(base + first, middle, radius, w, output + first); return;
            case 2: sums_alike<2>(base + first, middle, radius, w, output + first); return;
            default: sums_alike<1>(base + first, middle, radius, w, output + first); return;
        }
    }

    /// The group (or run of groups) at x0, decided and summed; returns the pixels done.
    __attribute__((target("avx2"))) int step(int x0) {
        BlurRampJob job;
        decide(x0, job);
        execute(job, weights.w);
        return job.pixels();
    }
};

/// The plan of a table (BlurRampPlan): every row's groups decided as the AVX passes decide them
/// with the table, each new set of weights appended to the pool.
__attribute__((target("avx2"))) std::shared_ptr<const BlurRampPlan> make_plan(
    const BlurRampTable& table) {
    auto plan = std::make_shared<BlurRampPlan>();
    const int width = table.geometry.screen_width;
    plan->jobs.reserve(static_cast<std::size_t>(width / lanes) *
                       static_cast<std::size_t>(table.geometry.screen_height));
    RowPass row(table.ramp, table.geometry, &table);
    row.width = width;
    int made = 0;  // the sets of weights made when the pool's last was appended
    for (int y = 0; y < table.geometry.screen_height; ++y) {
        row.y = y;
        for (int x = 0; x + lanes <= width;) {
            BlurRampJob& job = plan->jobs.emplace_back();
            row.decide(x, job);
            x += job.pixels();
            if (job.kind == BlurRampJob::copied) continue;
            if (row.weights.made != made) {
                made = row.weights.made;
                const auto rows = static_cast<std::size_t>(job.radius_max) + 1;
                plan->weights.insert(plan->weights.end(), &row.weights.w[0][0],
                                     &row.weights.w[0][0] + rows * lanes);
            }
            const std::size_t first =
                plan->weights.size() - (static_cast<std::size_t>(job.radius_max) + 1) * lanes;
            FOVREF_CHECK(first <= std::numeric_limits<std::uint32_t>::max(),
                         "a blur plan's weights beyond 2^32 floats");
            job.weights = static_cast<std::uint32_t>(first);
        }
        plan->row_end.push_back(plan->jobs.size());
    }
    return plan;
}

/// The pass on eight pixels at a time (AVX2; used only where the CPU has it, three channels),
/// on the interleaved image itself: a group's 24 floats are three registers, each float's lane
/// doing its own pixel's scalar operations in blur_ramp_pixel's order (the sum starts at 0 and
/// adds w_d c_d, the product rounded, no FMA, for d = -R .. R of that pixel's R), the pixel's
/// weights spread to its three floats. A group runs d over -Rmax .. Rmax of its largest radius,
/// and a lane whose |d| > R adds +0, its product masked by a bitwise and (not a zero weight, so
/// that no value read outside a lane's own taps can reach it), which leaves its sum's bits as
/// they are (sums_lanes): the same bits as blur_ramp_pixel, lane by lane.
/// A tap beyond the image reads the pixel the reference's clamp gives (the rows along y by the
/// offsets, the pixels along x from a copy of the row with its first and last pixel repeated
/// around it). The last W mod 8 pixels of a row are copied, then run blur_ramp_pixel itself.
__attribute__((target("avx2"))) void blur_pass_avx(const BlurRamp& ramp,
                                                   const BlurRampGeometry& geometry,
                                                   const Image& image, bool vertical, Image& out,
                                                   const BlurRampTable* table) {
    const int width = image.width, height = image.height;
    const std::size_t row_floats = 3 * static_cast<std::size_t>(width);
    constexpr int pad = blur_ramp_max_radius;
    // Along x, the row with `pad` copies of its first and last pixel on either side
    std::vector<float> line(vertical ? 0 : row_floats + 6 * pad);
    RowPass row(ramp, geometry, table);
    row.width = width;
    const BlurRampPlan* plan = table ? table->plan.get() : nullptr;
    for (int d = -pad; d <= pad; ++d) row.offsets[d + pad] = 3 * d;
    for (int y = 0; y < height; ++y) {
        row.y = y;
        row.input = &image.data[image.index(0, y)];
        row.output = &out.data[out.index(0, y)];
        if (vertical) {
            row.base = row.input;
            for (int d = -pad; d <= pad; ++d)
                row.offsets[d + pad] =
                    static_cast<std::ptrdiff_t>(std::clamp(y + d, 0, height - 1) - y) *
                    static_cast<std::ptrdiff_t>(row_floats);
        } else {
            std::copy_n(row.input, row_floats, line.data() + 3 * pad);
            for (int k = 0; k < pad; ++k) {
                std::copy_n(row.input, 3, line.data() + 3 * k);
                std::copy_n(row.input + row_floats - 3, 3, line.data() + 3 * (pad + width + k));
            }
            row.base = line.data() + 3 * pad;
        }
        int x = 0;
        if (plan) {
            const auto& jobs = plan->jobs;
            const std::size_t end = plan->row_end[static_cast<std::size_t>(y)];
            for (std::size_t k = y == 0 ? 0 : plan->row_end[static_cast<std::size_t>(y) - 1];
                 k < end; ++k) {
                // the weights of the job after next on their way to the cache while this sums
                if (k + 2 < jobs.size()) {
                    const float* next = plan->weights.data() + jobs[k + 2].weights;
                    for (int d = 0; d <= jobs[k + 2].radius_max + 1; d += 2)  // (lines of 2 rows)
                        _mm_prefetch(reinterpret_cast<const char*>(next + lanes * d), _MM_HINT_T0);
                }
                row.execute(jobs[k], reinterpret_cast<const float(*)[lanes]>(plan->weights.data() +
                                                                             jobs[k].weights));
                x += jobs[k].pixels();
            }
        } else {
            while (x + lanes <= width) x += row.step(x);
        }
        for (; x < width; ++x) {  // blur_ramp_pixel leaves a copied pixel (radius 0) as it is
            std::copy_n(row.input + 3 * x, 3, row.output + 3 * x);
            blur_ramp_pixel(ramp, geometry, image, vertical, out, x, y);
        }
    }
}

/// One pass along x (`vertical` false) or y (true): the AVX groups where the CPU has AVX (the
/// same bits), else blur_ramp_pixel pixel by pixel.
Image blur_pass(const BlurRamp& ramp, const BlurRampGeometry& geometry, const Image& image,
                bool vertical, bool simd, const BlurRampTable* table, Image storage) {
    check_inputs(ramp, geometry, image);
    FOVREF_CHECK(!table || table->made_for(ramp, geometry),
                 "a blur ramp table made for another ramp or geometry");
    if (simd && image.channels == 3 && simd_allowed() && cpu_has_avx2()) {
        // The AVX pass writes every pixel (each group's floats, copied pixels included): the
        // storage as it is, no copy of the image first
        Image out = std::move(storage);
        keep_or_make(out, image.width, image.height, image.channels);
        blur_pass_avx(ramp, geometry, image, vertical, out, table);
        return out;
    }
    // blur_ramp_pixel leaves a copied pixel (radius 0) as it is: the image copied first (into
    // the storage's memory where it has the image's size)
    Image out = std::move(storage);
    out = image;
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
    BlurRampTable table{ramp, geometry, Image(geometry.screen_width, geometry.screen_height, 2),
                        nullptr};
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

void add_blur_ramp_plan(BlurRampTable& table) {
    if (!table.plan && simd_allowed() && cpu_has_avx2()) table.plan = make_plan(table);
}

Image blur_ramp(const BlurRamp& ramp, const BlurRampGeometry& geometry, const Image& image,
                bool simd) {
    return blur_ramp_vertical(ramp, geometry, blur_ramp_horizontal(ramp, geometry, image, simd),
                              simd);
}

}  // namespace fovref
