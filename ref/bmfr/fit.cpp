// BMFR phase II: the block grid, the features, the per-block least-squares fit by an augmented
// Householder QR, and the weighted sum (SPEC §9 items 3-8).
#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "ref/bmfr/bmfr.h"
#include "ref/bmfr/half.h"
#include "ref/bmfr/weighted_sum_avx.h"
#include "ref/core/block_offsets.h"
#include "ref/core/error.h"
#include "ref/core/rng.h"
#include "ref/core/simd.h"

namespace fovref {

namespace {

float clamp_feature(float v) {
    if (std::isnan(v)) return 0.0f;
    return std::clamp(v, -half_max, half_max);
}

// A gathered row's columns First .. 15 in the storage precision: round_to_half_span (by F16C
// where the CPU has it; the same bits), nothing for binary32 storage.
template <int First>
void store_row(const BmfrParams& params, float* a) {
    if (params.storage != BmfrStorage::half) return;
#ifdef FOVREF_HALF_F16C
    if (params.f16c && simd_allowed() && cpu_has_f16c() && round_to_half_span_f16c<First>(a))
        return;
#endif
    round_to_half_span<First>(a);
}

glm::vec3 load3(const Image& image, int x, int y) {
    const float* p = &image.data[image.index(x, y)];
    return {p[0], p[1], p[2]};
}

// The dot products u . a_j of columns J0 .. 15 over the rows c .. rows - 1 of the row-major block
// matrix `a` (stride 16), u_c = uc and u_i = a_i,col below: binary64, row order, rounded to float
// (bmfr_sums=binary64). J0, col + 1 rounded down to a multiple of 4, is a compile-time constant so
// that the loops vectorise; only columns col + 1 .. 12 are kept.
template <int J0>
void binary64_dots(const float* a, int rows, int col, int c, float uc, float* dot) {
    constexpr int stride = bmfr_matrix_stride;
    double d[stride] = {};
    for (int j = J0; j < stride; ++j)
        d[j] = static_cast<double>(uc) * static_cast<double>(a[c * stride + j]);
    for (int i = c + 1; i < rows; ++i) {
        const double u = a[i * stride + col];
        const float* row = &a[i * stride];
        for (int j = J0; j < stride; ++j) d[j] += u * static_cast<double>(row[j]);
    }
    for (int j = col + 1; j < bmfr_column_count; ++j) dot[j] = static_cast<float>(d[j]);
}

// One row's update a_ij -= ((2 u_i) d_j) / |u|^2 (u2 = 2 u_i), j = J0 .. 15, as the authors,
// through a local array, so that the row cannot alias d and the loop vectorises (each lane does
// one element's operations, in the same order).
template <int J0>
inline void update_row(float* row, float u2, const float* d, float u_length_squared) {
    float updated[bmfr_matrix_stride];
    for (int j = J0; j < bmfr_matrix_stride; ++j)
        updated[j] = row[j] - (u2 * d[j]) / u_length_squared;
    std::copy(updated + J0, updated + bmfr_matrix_stride, row + J0);
}

// The Householder reflection of columns J0 .. 15 over the rows c .. rows - 1 with the dot
// products `dot` (0 outside col + 1 .. 12, which leaves those columns unchanged: storing a stored
// value again changes nothing): update_row, each updated value rounded to the storage
// precision; the column col becomes 0 below row c.
template <int J0>
void reflect_columns(float* a, int rows, int col, int c, float uc, float u_length_squared,
                     const float* dot, bool half) {
    constexpr int stride = bmfr_matrix_stride;
    float d[stride];
    std::copy(dot, dot + stride, d);
    for (int i = c; i < rows; ++i) {
        float* row = &a[i * stride];
        update_row<J0>(row, 2.0f * (i == c ? uc : row[col]), d, u_length_squared);
        if (half) round_to_half_span<J0>(row);
        if (i > c) row[col] = 0.0f;
    }
}

// The sum over rows first .. rows - 1 of x_i y_i, (x_i, y_i) = factors(i), in the order `sums`
// names: binary64 products (exact) added in row order and rounded once, or float products added
// in the authors' work-group order.
template <typename Factors>
float block_dot(BmfrSums sums, int first, int rows, Factors factors) {
    if (sums == BmfrSums::binary64) {
        double sum = 0.0;
        for (int i = first; i < rows; ++i) {
            const auto [x, y] = factors(i);
            sum += static_cast<double>(x) * static_cast<double>(y);
        }
        return static_cast<float>(sum);
    }
    float partial[bmfr_workgroup_size];
    for (int t = 0; t < bmfr_workgroup_size; ++t) {
        float p = 0.0f;
        for (int i = t; i < rows; i += bmfr_workgroup_size)
            if (i >= first) {
                const auto [x, y] = factors(i);
                p = p + x * y;
            }
        partial[t] = p;
    }
    return bmfr_workgroup_sum(partial);
}

#ifdef FOVREF_HALF_F16C
// reflect_columns with binary16 storage on a CPU with F16C: the same operations in the same
// order (the target only adds instructions; -ffp-contract=off still holds), each row rounded by
// round_to_half_span_f16c (round_to_half_span where a lane is NaN): the same bits.
template <int J0>
__attribute__((target("f16c"))) void reflect_columns_f16c(float* a, int rows, int col, int c,
                                                          float uc, float u_length_squared,
                                                          const float* dot) {
    constexpr int stride = bmfr_matrix_stride;
    float d[stride];
    std::copy(dot, dot + stride, d);
    for (int i = c; i < rows; ++i) {
        float* row = &a[i * stride];
        update_row<J0>(row, 2.0f * (i == c ? uc : row[col]), d, u_length_squared);
        if (!round_to_half_span_f16c<J0>(row)) round_to_half_span<J0>(row);
        if (i > c) row[col] = 0.0f;
    }
}
#endif

// One reflection (columns J0 .. 15), by the F16C variant where it applies.
template <int J0>
void reflect(float* a, int rows, int col, int c, float uc, float u_length_squared, const float* dot,
             bool half, bool f16c) {
    (void)f16c;  // without the F16C path (not x86)
#ifdef FOVREF_HALF_F16C
    if (half && f16c && simd_allowed() && cpu_has_f16c()) {
        reflect_columns_f16c<J0>(a, rows, col, c, uc, u_length_squared, dot);
        return;
    }
#endif
    reflect_columns<J0>(a, rows, col, c, uc, u_length_squared, dot, half);
}

}  // namespace

float bmfr_regularisation_noise(float amount, BmfrNoiseHash hash, int row, int feature, int frame,
                                int block_pixels) {
    const auto pixels = static_cast<std::uint32_t>(block_pixels);
    const std::uint32_t seed = static_cast<std::uint32_t>(row) +
                               static_cast<std::uint32_t>(feature) * pixels +
                               static_cast<std::uint32_t>(frame) * 13u * pixels;
    const std::uint32_t h = hash == BmfrNoiseHash::jenkins ? jenkins_hash(seed) : wang_hash(seed);
    const float r = static_cast<float>(h) / 4294967295.0f;
    return amount * 2.0f * (r - 0.5f);
}

const std::array<glm::ivec2, 16>& bmfr_block_offsets() { return block_grid_offsets(); }

float bmfr_scale_feature(float v, float lo, float hi) {
    const float range = hi - lo;
    return range > 1.0f ? (v - lo) / range : v - lo;
}

BmfrGrid bmfr_grid(int width, int height, int frame, const VisualPolarMap* map, int block) {
    FOVREF_CHECK(width > 0 && height > 0 && frame >= 0, "bmfr_grid: bad size or frame");
    FOVREF_CHECK(block == 32 || block == 64, "bmfr_grid: a block edge other than 32 or 64");
    BmfrGrid g;
    g.width = width;
    g.height = height;
    g.block = block;
    g.cells_x = (width + block - 1) / block + 1;
    g.cells_y = (height + block - 1) / block + 1;
    g.offset = bmfr_block_offsets()[static_cast<std::size_t>(frame % 16)] * (block / 32);
    if (map) {
        FOVREF_CHECK(map->width == width && map->height == height,
                     "bmfr_grid: the Visual-Polar map is not the image's size");
        for (int c = 0; c < width; ++c) g.column_rows.push_back(vp_column_rows(*map, c));
        // The phi height of each cell column: the largest row count among its columns
        for (int cx = 0; cx < g.cells_x; ++cx) {
            int rows = 1;
            for (int k = 0; k < block; ++k) {
                const int c = std::clamp(g.origin(cx, 0).x + k, 0, width - 1);
                rows = std::max(rows, g.column_rows[static_cast<std::size_t>(c)]);
            }
            g.cell_rows.push_back(rows);
        }
        g.cells_y = (height + block - 1) / block;
    }
    return g;
}

namespace {

int wrap(int index, int size) {
    const int m = index % size;
    return m < 0 ? m + size : m;
}

}  // namespace

glm::ivec2 BmfrGrid::cell_of(int x, int y) const {
    // x - origin(0).x = x + B/2 - offset.x >= 2 B/32 for offsets in B/32 [-16, 14]
    const int cx = (x + block / 2 - offset.x) / block;
    if (visual_polar())
        return {cx, wrap(y - offset.y, cell_rows[static_cast<std::size_t>(cx)]) / block};
    return {cx, (y + block / 2 - offset.y) / block};
}

int BmfrGrid::cells_in_column(int cell_x) const {
    if (!visual_polar()) return cells_y;
    return (cell_rows[static_cast<std::size_t>(cell_x)] + block - 1) / block;
}

bool BmfrGrid::source(int cell_x, int cell_y, int row, int& x, int& y) const {
    const glm::ivec2 o = origin(cell_x, cell_y);
    if (!visual_polar()) {
        x = bmfr_mirror(o.x + row % block, width);
        y = bmfr_mirror(o.y + row / block, height);
        return true;
    }
    x = std::clamp(o.x + row % block, 0, width - 1);
    y = wrap(o.y + row / block, cell_rows[static_cast<std::size_t>(cell_x)]);
    return y < column_rows[static_cast<std::size_t>(x)];
}

int bmfr_mirror(int index, int size) {
    const int period = 2 * size;
    int m = index % period;
    if (m < 0) m += period;
    return m < size ? m : period - 1 - m;
}

void bmfr_features(glm::vec3 n, glm::vec3 w, float t[bmfr_feature_count]) {
    t[0] = 1.0f;
    t[1] = clamp_feature(n.x);
    t[2] = clamp_feature(n.y);
    t[3] = clamp_feature(n.z);
    t[4] = clamp_feature(w.x);
    t[5] = clamp_feature(w.y);
    t[6] = clamp_feature(w.z);
    t[7] = clamp_feature(w.x * w.x);
    t[8] = clamp_feature(w.y * w.y);
    t[9] = clamp_feature(w.z * w.z);
}

std::vector<float> bmfr_noise_table(float amount, BmfrNoiseHash hash, int frame, int block_pixels) {
    std::vector<float> table(static_cast<std::size_t>(block_pixels) * (bmfr_feature_count - 1));
    for (int row = 0; row < block_pixels; ++row)
        for (int f = 1; f < bmfr_feature_count; ++f)
            table[static_cast<std::size_t>(row) * (bmfr_feature_count - 1) + f - 1] =
                bmfr_regularisation_noise(amount, hash, row, f, frame, block_pixels);
    return table;
}

void bmfr_gather_block(const BmfrParams& params, const BmfrGrid& grid, int cell_x, int cell_y,
                       const Image& accumulated, const Image& world_position, const Image& normal,
                       int frame, bool noise, BmfrBlockMatrix& out, const Image* valid,
                       const std::vector<float>* noise_table) {
    float lo[bmfr_scaled_count], hi[bmfr_scaled_count];
    std::fill(lo, lo + bmfr_scaled_count, half_max);
    std::fill(hi, hi + bmfr_scaled_count, -half_max);
    // Rows without data (Visual-Polar): zero rows, no noise, not in the ranges
    const int rows = grid.block * grid.block;
    if (out.rows != rows) {
        out.rows = rows;
        out.a.assign(static_cast<std::size_t>(rows) * bmfr_matrix_stride, 0.0f);
    }
    std::vector<unsigned char> data(static_cast<std::size_t>(rows));
    int data_rows = 0;
    // Gather the raw features and colours (mirrored borders) in the storage precision, and the
    // ranges of features 4..9 over the stored values (the authors store the features in binary16
    // before the fit reads them)
    for (int row = 0; row < rows; ++row) {
        int x = 0, y = 0;
        float* a = &out.a[static_cast<std::size_t>(row) * bmfr_matrix_stride];
        data[row] = grid.source(cell_x, cell_y, row, x, y) && (!valid || valid->at(x, y) != 0.0f);
        if (!data[row]) {
            std::fill(a, a + bmfr_matrix_stride, 0.0f);
            continue;
        }
        ++data_rows;
        bmfr_features(load3(normal, x, y), load3(world_position, x, y), a);
        const glm::vec3 c = load3(accumulated, x, y);
        a[10] = clamp_feature(c.x);
        a[11] = clamp_feature(c.y);
        a[12] = clamp_feature(c.z);
        a[13] = a[14] = a[15] = 0.0f;  // the padding (the matrix is reused between blocks)
        store_row<0>(params, a);
        for (int k = 0; k < bmfr_scaled_count; ++k) {
            lo[k] = std::min(lo[k], a[bmfr_scaled_first + k]);
            hi[k] = std::max(hi[k], a[bmfr_scaled_first + k]);
        }
    }
    out.data_rows = data_rows;
    if (data_rows == 0) {
        std::fill(lo, lo + bmfr_scaled_count, 0.0f);
        std::fill(hi, hi + bmfr_scaled_count, 0.0f);
    }
    std::copy(lo, lo + bmfr_scaled_count, out.feature_min);
    std::copy(hi, hi + bmfr_scaled_count, out.feature_max);
    // Scale features 4..9 (stored again), then add the regularisation noise to features 1..9 in
    // float: the authors add it as the first Householder column reads the values, whose
    // reflection then stores them
    const std::vector<float> own_table =
        noise && !noise_table
            ? bmfr_noise_table(params.noise_amount, params.noise_hash, frame, rows)
            : std::vector<float>();
    const std::vector<float>& table = noise_table ? *noise_table : own_table;
    FOVREF_CHECK(
        !noise || table.size() == static_cast<std::size_t>(rows) * (bmfr_feature_count - 1),
        "bmfr_gather_block: the noise table is not the block's");
    for (int row = 0; row < rows; ++row) {
        if (!data[row]) continue;
        float* a = &out.a[static_cast<std::size_t>(row) * bmfr_matrix_stride];
        for (int k = 0; k < bmfr_scaled_count; ++k)
            a[bmfr_scaled_first + k] = bmfr_scale_feature(a[bmfr_scaled_first + k], lo[k], hi[k]);
        // stored again (columns 10 .. 15 are stored values already: rounding keeps them)
        store_row<bmfr_scaled_first>(params, a);
        if (noise) {
            const float* n = &table[static_cast<std::size_t>(row) * (bmfr_feature_count - 1)];
            for (int f = 1; f < bmfr_feature_count; ++f) a[f] = a[f] + n[f - 1];
        }
    }
}

float bmfr_workgroup_sum(const float* partial) {
    // parallel_reduction_sum of the authors' bmfr.cl: s[t] += (s[t + 64] + s[t + 128]) +
    // s[t + 192] for t < 64; s[t] += ((((((s[t + 8] + s[t + 16]) + ...) + s[t + 56]) for t < 8;
    // then ((((((s[0] + s[1]) + s[2]) + ...) + s[7]
    float s[bmfr_workgroup_size];
    std::copy(partial, partial + bmfr_workgroup_size, s);
    for (int t = 0; t < 64; ++t) s[t] = s[t] + ((s[t + 64] + s[t + 128]) + s[t + 192]);
    for (int t = 0; t < 8; ++t) {
        float rest = s[t + 8];
        for (int k = 2; k < 8; ++k) rest = rest + s[t + 8 * k];
        s[t] = s[t] + rest;
    }
    float sum = s[0];
    for (int t = 1; t < 8; ++t) sum = sum + s[t];
    return sum;
}

namespace {

// The dot products u . a_j of columns col + 1 .. 12 over the rows c .. rows - 1 (bmfr_sums:
// binary64 in row order, over whole groups of 4 columns from j0 = col + 1 rounded down to a
// multiple of 4 so that the loops vectorise, or the authors' work-group order in float);
// the other columns get 0, which leaves them unchanged in the reflection.
void column_dots(const BmfrParams& params, const float* a, int rows, int col, int c, float uc,
                 float* dot) {
    constexpr int stride = bmfr_matrix_stride;
    if (params.sums == BmfrSums::binary64) {
        switch ((col + 1) & ~3) {
            case 0: binary64_dots<0>(a, rows, col, c, uc, dot); break;
            case 4: binary64_dots<4>(a, rows, col, c, uc, dot); break;
            case 8: binary64_dots<8>(a, rows, col, c, uc, dot); break;
            default: binary64_dots<12>(a, rows, col, c, uc, dot); break;
        }
        return;
    }
    for (int j = col + 1; j < bmfr_column_count; ++j)
        dot[j] = block_dot(params.sums, c, rows, [&](int i) {
            return std::pair{a[i * stride + j], i == c ? uc : a[i * stride + col]};
        });
}

// The reflection of columns j0 .. 15, j0 = col + 1 rounded down to a multiple of 4 (reflect).
void reflect_from(const BmfrParams& params, float* a, int rows, int col, int c, float uc,
                  float u_length_squared, const float* dot) {
    const bool half = params.storage == BmfrStorage::half;
    switch ((col + 1) & ~3) {
        case 0: reflect<0>(a, rows, col, c, uc, u_length_squared, dot, half, params.f16c); break;
        case 4: reflect<4>(a, rows, col, c, uc, u_length_squared, dot, half, params.f16c); break;
        case 8: reflect<8>(a, rows, col, c, uc, u_length_squared, dot, half, params.f16c); break;
        default: reflect<12>(a, rows, col, c, uc, u_length_squared, dot, half, params.f16c); break;
    }
}

// Back substitution, row 9 to 0, per colour channel, in the authors' order: the row is divided
// by its pivot first, w_i = b_i / R_ii - sum_{k > i} (R_ik w_k) / R_ii (k ascending).
void back_substitute(const BmfrParams& params, const float* a, BmfrBlockFit& fit) {
    constexpr int stride = bmfr_matrix_stride;
    for (int ch = 0; ch < 3; ++ch) {
        float* w = fit.weights[ch];
        for (int i = bmfr_feature_count - 1; i >= 0; --i) {
            const float pivot = a[i * stride + i];
            if (!(std::fabs(pivot) >= params.pivot_epsilon)) {
                w[i] = 0.0f;
                if (ch == 0) ++fit.pivots_zeroed;
                continue;
            }
            float v = a[i * stride + bmfr_feature_count + ch] / pivot;
            for (int k = i + 1; k < bmfr_feature_count; ++k)
                v = v - (a[i * stride + k] * w[k]) / pivot;
            if (!std::isfinite(v)) {  // an overflow through a small pivot: counted, 0
                ++fit.weights_nonfinite;
                v = 0.0f;
            }
            w[i] = v;
        }
    }
}

}  // namespace

BmfrBlockFit bmfr_solve_block(const BmfrParams& params, BmfrBlockMatrix& m) {
    BmfrBlockFit fit;
    std::copy(m.feature_min, m.feature_min + bmfr_scaled_count, fit.feature_min);
    std::copy(m.feature_max, m.feature_max + bmfr_scaled_count, fit.feature_max);
    float* a = m.a.data();
    constexpr int stride = bmfr_matrix_stride;
    for (int col = 0; col < bmfr_column_count; ++col) {
        const int c = std::min(col, bmfr_feature_count);
        // The norm of the column below the pivot row (in the order bmfr_sums names)
        const float s = block_dot(params.sums, c + 1, m.rows, [&](int i) {
            return std::pair{a[i * stride + col], a[i * stride + col]};
        });
        const float xc = a[c * stride + col];
        const float r = std::sqrt(s + xc * xc);
        const float uc = xc - r;
        const float u_length_squared = s + uc * uc;
        if (!(u_length_squared > 0.0f)) {
            if (col < bmfr_feature_count) ++fit.reflections_skipped;
            continue;
        }
        float dot[stride] = {};
        column_dots(params, a, m.rows, col, c, uc, dot);
        reflect_from(params, a, m.rows, col, c, uc, u_length_squared, dot);
        // The diagonal stays in float (the authors keep R in local float memory)
        a[c * stride + col] = r;
    }
    back_substitute(params, a, fit);
    return fit;
}

BmfrFit bmfr_fit(const BmfrParams& params, const Image& accumulated, const Image& world_position,
                 const Image& normal, int frame, BmfrStats& stats, const BmfrSpace& space) {
    BmfrFit out;
    out.grid = bmfr_grid(accumulated.width, accumulated.height, frame,
                         space.map ? &*space.map : nullptr, params.block_size);
    const BmfrGrid& g = out.grid;
    out.weights = Image(g.cells_x, g.cells_y, bmfr_weight_count);
    out.feature_range = Image(g.cells_x, g.cells_y, 2 * bmfr_scaled_count);
    BmfrBlockMatrix matrix;
    const std::vector<float> noise =
        bmfr_noise_table(params.noise_amount, params.noise_hash, frame, g.block * g.block);
    // A block without data (Visual-Polar texels off screen) is gathered as zeros without noise,
    // the same matrix for every such block: solved once, its fit reused
    std::optional<BmfrBlockFit> empty_fit;
    for (int cy = 0; cy < g.cells_y; ++cy)
        for (int cx = 0; cx < g.cells_x; ++cx) {
            if (cy >= g.cells_in_column(cx)) continue;  // above a Visual-Polar staircase step
            bmfr_gather_block(params, g, cx, cy, accumulated, world_position, normal, frame, true,
                              matrix, space.valid, &noise);
            const bool empty = matrix.data_rows == 0;
            if (empty && !empty_fit) empty_fit = bmfr_solve_block(params, matrix);
            const BmfrBlockFit fit = empty ? *empty_fit : bmfr_solve_block(params, matrix);
            float* w = &out.weights.data[out.weights.index(cx, cy)];
            for (int ch = 0; ch < 3; ++ch)
                for (int i = 0; i < bmfr_feature_count; ++i)
                    w[ch * bmfr_feature_count + i] = fit.weights[ch][i];
            float* range = &out.feature_range.data[out.feature_range.index(cx, cy)];
            for (int k = 0; k < bmfr_scaled_count; ++k) {
                range[k] = fit.feature_min[k];
                range[bmfr_scaled_count + k] = fit.feature_max[k];
            }
            ++stats.blocks;
            stats.pivots_zeroed += fit.pivots_zeroed;
            stats.fit_nonfinite += fit.weights_nonfinite;
            stats.reflections_skipped += fit.reflections_skipped;
        }
    return out;
}

Image bmfr_weighted_sum(const BmfrFit& fit, const Image& world_position, const Image& normal,
                        BmfrStats& stats, const Image* valid) {
    const BmfrGrid& g = fit.grid;
    const auto shaped = [](const Image& i, int w, int h, int c) {
        return i.width == w && i.height == h && i.channels == c;
    };
    FOVREF_CHECK(shaped(fit.weights, g.cells_x, g.cells_y, bmfr_weight_count) &&
                     shaped(fit.feature_range, g.cells_x, g.cells_y, 2 * bmfr_scaled_count) &&
                     shaped(world_position, g.width, g.height, 3) &&
                     shaped(normal, g.width, g.height, 3),
                 "bmfr_weighted_sum: the weights, ranges, positions or normals do not match the "
                 "grid");
    Image out(g.width, g.height, 3);
    // Visual-Polar texels beyond their column's rows or untraced have no data: 0
    const auto has_data = [&](int x, int y) {
        return !g.visual_polar() || (y < g.column_rows[static_cast<std::size_t>(x)] &&
                                     (!valid || valid->at(x, y) != 0.0f));
    };
    // Eight pixels at a time where the AVX path applies (the same bits: weighted_sum_avx.h),
    // block span by block span; the reference does each span's last pixels, or every pixel.
    const bool avx = bmfr_weighted_sum_avx_applies(g, valid);
    for (int y = 0; y < g.height; ++y)
        for (int x = 0; x < g.width;) {
            const int cell_x = g.cell_of(x, y).x;
            const int end = std::min(g.width, g.origin(cell_x + 1, 0).x);
            if (avx)
                x = bmfr_weighted_sum_span_avx(fit, world_position, normal, valid, out, x, end, y,
                                               stats);
            for (; x < end; ++x)
                if (has_data(x, y))
                    bmfr_weighted_sum_pixel(fit, world_position, normal, out, x, y, stats);
        }
    return out;
}

void bmfr_weighted_sum_pixel(const BmfrFit& fit, const Image& world_position, const Image& normal,
                             Image& out, int x, int y, BmfrStats& stats) {
    const glm::ivec2 cell = fit.grid.cell_of(x, y);
    const float* w = &fit.weights.data[fit.weights.index(cell.x, cell.y)];
    const float* range = &fit.feature_range.data[fit.feature_range.index(cell.x, cell.y)];
    float t[bmfr_feature_count];
    bmfr_features(load3(normal, x, y), load3(world_position, x, y), t);
    for (int k = 0; k < bmfr_scaled_count; ++k)
        t[bmfr_scaled_first + k] =
            bmfr_scale_feature(t[bmfr_scaled_first + k], range[k], range[bmfr_scaled_count + k]);
    float* o = &out.data[out.index(x, y)];
    for (int ch = 0; ch < 3; ++ch) {
        float sum = 0.0f;
        for (int i = 0; i < bmfr_feature_count; ++i)
            sum = sum + w[ch * bmfr_feature_count + i] * t[i];
        if (!std::isfinite(sum)) {
            ++stats.fit_nonfinite;
            sum = 0.0f;
        }
        o[ch] = std::max(sum, 0.0f);
    }
}

}  // namespace fovref
