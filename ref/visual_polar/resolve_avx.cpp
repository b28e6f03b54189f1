#include "ref/visual_polar/resolve_avx.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "ref/core/avx_lanes.h"
#include "ref/core/error.h"
#include "ref/core/simd.h"

namespace fovref {

namespace {

using namespace avx;

constexpr float two_pi = 6.28318530717958647692f;  // resolve.cpp's

/// lerp of resolve.cpp: a + t (b - a).
FOVREF_AVX_INLINE __m256 lerp(__m256 a, __m256 b, __m256 t) {
    return _mm256_add_ps(a, _mm256_mul_ps(t, _mm256_sub_ps(b, a)));
}

/// The lanes' column along rho: its index, its rows n_c at level 0 and its last level.
struct ColumnLanes {
    __m256i column;
    __m256i rows;
    __m256 last;
};

/// The first packed texel of each lane's level in the lanes of `on` (0 in the others): from a
/// register of the first eight levels' starts where the lanes' levels are below 8 (a lambda of 8
/// or more is a column with 256 texels or more per screen pixel), else gathered.
FOVREF_AVX2_INLINE __m256i level_starts(const VpResolveAvxInputs& in, __m256i level, __m256 on) {
    const __m256i on_i = _mm256_castps_si256(on);
    if (_mm256_testz_si256(_mm256_and_si256(level, _mm256_set1_epi32(~7)), on_i))
        return _mm256_and_si256(
            _mm256_permutevar8x32_epi32(
                _mm256_load_si256(reinterpret_cast<const __m256i*>(in.first_starts)), level),
            on_i);
    return _mm256_mask_i32gather_epi32(_mm256_setzero_si256(), in.level_start.data(), level, on_i,
                                       4);
}

/// vp_phi_rows in lanes, for row coordinates v on columns of `rows` rows: t = v - 1/2, j0 =
/// floor(t) wrapped into [0, rows) by one step of rows (exact), j1 = (j0 + 1) mod rows, fv = t -
/// floor(t); `usable`: the lanes whose v lies in the range sample_vp_phi accepts ([-rows,
/// 2 rows]) and whose j0 needed at most that one step (the others are the reference's).
struct PhiRows {
    __m256 j0, j1, fv, usable;
};
FOVREF_AVX_INLINE PhiRows phi_rows(__m256 v, __m256 rows) {
    PhiRows p;
    const __m256 in_range =
        both(at_least(v, negate(rows)), at_most(v, _mm256_mul_ps(set(2.0f), rows)));
    const __m256 t = _mm256_sub_ps(v, set(0.5f));
    const __m256 j0_raw = floor(t);
    p.fv = _mm256_sub_ps(t, j0_raw);
    p.j0 = select(less(j0_raw, zero()), _mm256_add_ps(j0_raw, rows),
                  select(at_least(j0_raw, rows), _mm256_sub_ps(j0_raw, rows), j0_raw));
    p.usable = both(in_range, both(at_least(p.j0, zero()), less(p.j0, rows)));
    const __m256 j0_next = _mm256_add_ps(p.j0, set(1.0f));
    p.j1 = select(equal(j0_next, rows), zero(), j0_next);
    return p;
}

/// sample_vp_phi's value from the taps' colours and masks (c0, m0: row j0; c1, m1: row j1) in
/// the lanes of `on` (row j1 only where `second`, its weight fv > 0): both traced: the lerp; one:
/// that tap; none, or a lane not `on`: 0. Returns the lanes with a traced tap.
FOVREF_AVX2_INLINE int phi_value(const __m256* c0, __m256 m0, const __m256* c1, __m256 m1,
                                 __m256 fv, __m256 on, __m256 second, __m256* out) {
    const __m256 traced0 = both(on, not_equal(m0, zero()));
    const __m256 traced1 = both(both(on, second), not_equal(m1, zero()));
    const __m256 both_taps = both(traced0, traced1);
    for (int c = 0; c < 3; ++c)
        out[c] = select(both_taps, lerp(c0[c], c1[c], fv),
                        select(traced0, c0[c], select(traced1, c1[c], zero())));
    return bits(either(traced0, traced1));
}

/// sample_vp_phi in the lanes of `wanted`, each lane at its own pyramid level `level` (an
/// integer) and on its own column of n_c rows at level 0 (rows ceil(n_c / 2^level) there), at
/// v_c * 2^-level: the lanes' values into out[0 .. 2] (0 where no tap is traced and in the other
/// lanes). Returns the
/// lanes with a traced tap; the lanes whose lookup lies outside the range sample_vp_phi accepts,
/// or whose row needs more than one wrap, are added to `reference` (the reference's to do). Each
/// tap's colours and mask are one load from the packed pyramid (VpResolveAvxInputs).
FOVREF_AVX2_INLINE int phi_lanes(const VpResolveAvxInputs& in, __m256i level,
                                 const ColumnLanes& col, __m256 v, int wanted, __m256* out,
                                 int& reference) {
    // vp_mip_rows: ceil-halved `level` times = ceil(n / 2^level) (exact in binary32: n <= 2^24)
    const __m256i one = _mm256_set1_epi32(1);
    const __m256 rows = _mm256_cvtepi32_ps(_mm256_srlv_epi32(
        _mm256_sub_epi32(_mm256_add_epi32(col.rows, _mm256_sllv_epi32(one, level)), one), level));
    // 2^-level exactly (exponent 127 - level; level <= 24)
    const __m256 scale =
        _mm256_castsi256_ps(_mm256_slli_epi32(_mm256_sub_epi32(_mm256_set1_epi32(127), level), 23));
    const PhiRows phi = phi_rows(_mm256_mul_ps(v, scale), rows);
    const __m256 ok = both(mask_of(wanted), phi.usable);
    reference |= wanted & ~bits(ok);
    const __m256 second = both(ok, greater(phi.fv, zero()));  // weight fv > 0
    // The taps' texels: the level's first texel + j w + c, in the lanes of `ok` (`second` for
    // tap j1); the others read texel 0, whose value they never use
    const __m256i start = level_starts(in, level, ok);
    const int w = in.width;
    alignas(32) int at[2][lanes];
    _mm256_store_si256(
        reinterpret_cast<__m256i*>(at[0]),
        _mm256_and_si256(
            _mm256_add_epi32(start, row_major(col.column, _mm256_cvttps_epi32(phi.j0), w)),
            _mm256_castps_si256(ok)));
    _mm256_store_si256(
        reinterpret_cast<__m256i*>(at[1]),
        _mm256_and_si256(
            _mm256_add_epi32(start, row_major(col.column, _mm256_cvttps_epi32(phi.j1), w)),
            _mm256_castps_si256(second)));
    __m256 taps[2][4];  // per tap: R, G, B, mask of every lane
    for (int k = 0; k < 2; ++k) {
        __m128 q[lanes];
        for (int l = 0; l < lanes; ++l)
            q[l] = _mm_loadu_ps(in.texels.data() + 4 * static_cast<std::size_t>(at[k][l]));
        transpose4_lanes(q, taps[k]);
    }
    return phi_value(taps[0], taps[0][3], taps[1], taps[1][3], phi.fv, ok, second, out);
}

/// sample_column in the lanes of `wanted`: level floor(lambda) and, where lambda has a fraction
/// and a next level exists, that level, lerped (each lane at its own levels). Returns the lanes
/// with a value.
FOVREF_AVX2_INLINE int column_lanes(const VpResolveAvxInputs& in, const ColumnLanes& col, __m256 v,
                                    __m256 lambda, int wanted, __m256* out, int& reference) {
    const __m256 l0 = floor(lambda);
    const __m256 l1 = std_min(_mm256_add_ps(l0, set(1.0f)), col.last);
    const __m256 f = _mm256_sub_ps(lambda, l0);
    __m256 a[3] = {zero(), zero(), zero()}, b[3] = {zero(), zero(), zero()};
    const int have_a = phi_lanes(in, _mm256_cvttps_epi32(l0), col, v, wanted, a, reference);
    const int second = bits(both(not_equal(l1, l0), greater(f, zero()))) & wanted;
    const int have_b =
        second == 0 ? 0 : phi_lanes(in, _mm256_cvttps_epi32(l1), col, v, second, b, reference);
    const __m256 two = mask_of(have_a & have_b), only_a = mask_of(have_a);
    for (int c = 0; c < 3; ++c)
        out[c] = select(two, lerp(a[c], b[c], f), select(only_a, a[c], b[c]));
    return have_a | have_b;
}

/// The forward table's level entries (n_0, lambda_0, n_1, lambda_1) of eight consecutive pixels
/// (p: the first pixel's first value) as one register per entry.
FOVREF_AVX_INLINE void split4_lanes(const float* p, __m256* out) {
    __m128 q[lanes];
    for (int l = 0; l < lanes; ++l) q[l] = _mm_loadu_ps(p + 4 * l);
    transpose4_lanes(q, out);
}

/// The lanes' column `column` (in binary32) in the lanes of `wanted`: its index, its rows and
/// its last level (constants where every lane lies beyond the fovea, whose columns all have the
/// last column's h rows).
FOVREF_AVX2_INLINE ColumnLanes column_of(const VisualPolarMap& map, const VpResolveAvxInputs& in,
                                         __m256 column, int wanted) {
    ColumnLanes col;
    col.column = _mm256_cvttps_epi32(column);
    if (bits(at_least(column, set(static_cast<float>(map.fovea_columns)))) == 0xff) {
        col.rows = _mm256_set1_epi32(in.column_rows.back());
        col.last = set(static_cast<float>(in.last_levels.back()));
        return col;
    }
    const __m256i mask = _mm256_castps_si256(mask_of(wanted));
    col.rows = _mm256_mask_i32gather_epi32(_mm256_setzero_si256(), in.column_rows.data(),
                                           col.column, mask, 4);
    col.last = _mm256_cvtepi32_ps(_mm256_mask_i32gather_epi32(
        _mm256_setzero_si256(), in.last_levels.data(), col.column, mask, 4));
    return col;
}

/// The lanes' level lambda_c of a column of n rows at screen radius r: the table's (table_n,
/// table_lambda) where the pyramid's column still has the table's rows, else vp_mip_level as
/// the reference computes it (lane by lane, in the lanes of `wanted`).
FOVREF_AVX2_INLINE __m256 level_of(__m256 n, __m256 r, __m256 table_n, __m256 table_lambda,
                                   int wanted) {
    const __m256 same = equal(table_n, n);
    const __m256 lambda = select(same, table_lambda, zero());
    const int computed = wanted & ~bits(same);
    if (computed == 0) return lambda;
    alignas(32) float lambdas[lanes], rows[lanes], radius[lanes];
    _mm256_store_ps(lambdas, lambda);
    _mm256_store_ps(rows, n);
    _mm256_store_ps(radius, r);
    for (int l = 0; l < lanes; ++l)
        if (computed >> l & 1) lambdas[l] = vp_mip_level(static_cast<int>(rows[l]), radius[l]);
    return _mm256_load_ps(lambdas);
}

/// Eight lanes of eight floats each (rows[l]: lane l) as one register per float: out[e] holds
/// float e of every lane (the same floats, moved by shuffles).
FOVREF_AVX_INLINE void transpose8_lanes(const __m256* rows, __m256* out) {
    __m256 t[8], q[8];
    for (int k = 0; k < 4; ++k) {
        t[2 * k] = _mm256_unpacklo_ps(rows[2 * k], rows[2 * k + 1]);
        t[2 * k + 1] = _mm256_unpackhi_ps(rows[2 * k], rows[2 * k + 1]);
    }
    for (int h = 0; h < 2; ++h) {  // lanes 0..3, then 4..7
        q[4 * h] = _mm256_shuffle_ps(t[4 * h], t[4 * h + 2], _MM_SHUFFLE(1, 0, 1, 0));
        q[4 * h + 1] = _mm256_shuffle_ps(t[4 * h], t[4 * h + 2], _MM_SHUFFLE(3, 2, 3, 2));
        q[4 * h + 2] = _mm256_shuffle_ps(t[4 * h + 1], t[4 * h + 3], _MM_SHUFFLE(1, 0, 1, 0));
        q[4 * h + 3] = _mm256_shuffle_ps(t[4 * h + 1], t[4 * h + 3], _MM_SHUFFLE(3, 2, 3, 2));
    }
    for (int e = 0; e < 4; ++e) {
        out[e] = _mm256_permute2f128_ps(q[e], q[4 + e], 0x20);
        out[4 + e] = _mm256_permute2f128_ps(q[e], q[4 + e], 0x31);
    }
}

/// The columns' values of a group in the periphery, where the reference's steps come down to
/// one lookup at level 0 shared by both columns: every lane's columns i0 and i1 = i0 + 1 lie
/// beyond the fovea (both have the pyramid's h rows, so the same v = (h theta) / two_pi, rows
/// j0, j1 and fv), level 0 only (`mip` false, or the table's lambda 0 for both, made for h rows:
/// f = 0, no second level) and every lane's lookup in range. Column i1's texel then lies right
/// after column i0's in each row of the packed level 0, so that one 32-byte load per lane and
/// row reads both columns' taps. `levels`: the lanes' (n_0, lambda_0, n_1, lambda_1) from the
/// table, or null where the table marks the group level 0 (VpForwardTable::level0). values and
/// have as resolve_group's; false (nothing done) where a lane does not qualify: the general
/// lanes'.
FOVREF_AVX2_INLINE bool periphery_lanes(const VisualPolarMap& map, const VpResolveAvxInputs& in,
                                        bool mip, __m256 i0, __m256 fx, __m256 theta,
                                        const __m256* levels, __m256 (*values)[3], int* have) {
    const float h = static_cast<float>(in.column_rows.back());
    const __m256 rows = set(h);
    if (bits(both(at_least(i0, set(static_cast<float>(map.fovea_columns))),
                  less(i0, set(static_cast<float>(map.width - 1))))) != 0xff)
        return false;
    if (mip && levels &&
        bits(both(both(equal(levels[0], rows), equal(levels[2], rows)),
                  both(equal(levels[1], zero()), equal(levels[3], zero())))) != 0xff)
        return false;
    // phi_lanes at level 0 (scale 1: v itself) on h rows
    const PhiRows phi = phi_rows(_mm256_div_ps(_mm256_mul_ps(rows, theta), set(two_pi)), rows);
    if (bits(phi.usable) != 0xff) return false;
    const __m256 second = greater(phi.fv, zero());  // weight fv > 0
    const __m256i column = _mm256_cvttps_epi32(i0);
    alignas(32) int at[2][lanes];
    _mm256_store_si256(reinterpret_cast<__m256i*>(at[0]),
                       row_major(column, _mm256_cvttps_epi32(phi.j0), in.width));
    _mm256_store_si256(reinterpret_cast<__m256i*>(at[1]),
                       row_major(column, _mm256_cvttps_epi32(phi.j1), in.width));
    __m256 taps[2][8];  // per row: R, G, B, mask of column i0, then of column i1
    for (int k = 0; k < 2; ++k) {
        __m256 pair[lanes];
        for (int l = 0; l < lanes; ++l)
            pair[l] = _mm256_loadu_ps(in.texels.data() + 4 * static_cast<std::size_t>(at[k][l]));
        transpose8_lanes(pair, taps[k]);
    }
    const __m256 column1 = greater(fx, zero());  // wanted[1]: i1 != i0 for every lane here
    have[0] = phi_value(taps[0], taps[0][3], taps[1], taps[1][3], phi.fv, mask_of(0xff), second,
                        values[0]);
    have[1] = phi_value(taps[0] + 4, taps[0][7], taps[1] + 4, taps[1][7], phi.fv, column1, second,
                        values[1]);
    return true;
}

// Pixels x .. x + 7 of row y; the lanes the reference must do are done by resolve_vp_pixel.
__attribute__((target("avx2"))) void resolve_group(const VisualPolarMap& map, VpMipsSource& mips,
                                                   const VpResolveAvxInputs& in,
                                                   const VpForwardTable& table, bool mip,
                                                   Image& out, int x, int y, ResolveStats& stats) {
    const std::size_t pixel = static_cast<std::size_t>(y) * map.screen_width + x;
    __m256 polar[3];
    split3_lanes(&table.polar.data[3 * pixel], polar);
    const __m256 u = polar[0], r = polar[1], theta = polar[2];
    int reference = 0xff & ~bits(both(finite(u), both(finite(r), finite(theta))));
    if (reference == 0xff) {
        for (int l = 0; l < lanes; ++l)
            resolve_vp_pixel(map, mips.get(), out, x + l, y, stats, nullptr, mip, &table);
        return;
    }
    // The columns' levels: not read where the table marks the group level 0 (the periphery's
    // lanes need no more), else read
    __m256 levels[4] = {zero(), zero(), zero(), zero()};
    const std::size_t group = static_cast<std::size_t>(y) * (map.screen_width / lanes) + x / lanes;
    const bool level0 = group < table.level0.size() && table.level0[group] != 0 &&
                        table.level0_rows == in.column_rows.back();
    if (!level0) split4_lanes(&table.levels.data[4 * pixel], levels);

    // vp_rho_columns: s = clamp(u, 1/2, w - 1/2) - 1/2, i0 = floor(s), i1 = min(i0 + 1, w - 1)
    const float wf = static_cast<float>(map.width);
    const __m256 lo = set(0.5f), hi = set(wf - 0.5f);
    const __m256 s = _mm256_sub_ps(select(less(u, lo), lo, select(less(hi, u), hi, u)), lo);
    const __m256 i0 = floor(s);
    const __m256 fx = _mm256_sub_ps(s, i0);
    const __m256 i1 = std_min(_mm256_add_ps(i0, set(1.0f)), set(wf - 1.0f));
    const __m256 finite_lanes = mask_of(0xff & ~reference);
    const __m256 columns[2] = {select(finite_lanes, i0, zero()), select(finite_lanes, i1, zero())};
    const int wanted[2] = {0xff & ~reference,
                           bits(both(not_equal(i1, i0), greater(fx, zero()))) & ~reference};

    // Each column at the pixel's angle on its own rows, at its own phi level
    __m256 values[2][3] = {{zero(), zero(), zero()}, {zero(), zero(), zero()}};
    int have[2] = {0, 0};
    const bool periphery =
        reference == 0 &&
        periphery_lanes(map, in, mip, i0, fx, theta, level0 ? nullptr : levels, values, have);
    if (!periphery && level0) split4_lanes(&table.levels.data[4 * pixel], levels);
    for (int k = 0; k < 2 && !periphery; ++k) {
        if (wanted[k] == 0) continue;
        const ColumnLanes col = column_of(map, in, columns[k], wanted[k]);
        const __m256 n = _mm256_cvtepi32_ps(col.rows);
        const __m256 v = _mm256_div_ps(_mm256_mul_ps(n, theta), set(two_pi));
        const __m256 lambda =
            mip ? level_of(n, r, levels[2 * k], levels[2 * k + 1], wanted[k]) : zero();
        // (a level that is not finite or is negative, which no table made by vp_forward_table
        // holds, has no pyramid level: the reference's)
        const int bad = wanted[k] & ~bits(both(finite(lambda), at_least(lambda, zero())));
        reference |= bad;
        have[k] = column_lanes(in, col, v, lambda, wanted[k] & ~bad, values[k], reference);
    }

    // Lerp of the columns over those with a value
    const __m256 two = mask_of(have[0] & have[1]), first = mask_of(have[0]);
    __m256 result[3];
    for (int c = 0; c < 3; ++c)
        result[c] = select(two, lerp(values[0][c], values[1][c], fx),
                           select(first, values[0][c], values[1][c]));
    merge3_lanes(result, &out.at(x, y, 0));
    const int done = 0xff & ~reference;
    stats.pixels_from_buffer += __builtin_popcount(static_cast<unsigned>(done));
    stats.pixels_untraced_taps +=
        __builtin_popcount(static_cast<unsigned>(done & ~(have[0] | have[1])));
    for (int l = 0; l < lanes; ++l)
        if (reference >> l & 1)
            resolve_vp_pixel(map, mips.get(), out, x + l, y, stats, nullptr, mip, &table);
}

}  // namespace

namespace {

/// What the lanes need of any pyramid: a forward table, a map whose packed texels' indices (all
/// levels: at most w (2 h + 25) texels) are int32 and whose rows and columns are exact in
/// binary32 (up to 2^24), simd_allowed() and AVX2.
bool avx_covers(const VisualPolarMap& map, const VpForwardTable* table, bool need_table = true) {
    const std::int64_t texels = static_cast<std::int64_t>(map.width) * (2 * map.height + 25);
    return (!need_table || (table && table->polar.channels == 3 && table->levels.channels == 4)) &&
           map.width <= (1 << 24) && map.height <= (1 << 24) &&
           texels <= std::numeric_limits<std::int32_t>::max() && simd_allowed() && cpu_has_avx2();
}

}  // namespace

bool resolve_vp_avx_applies(const VisualPolarMap& map, const VpMips& mips,
                            const VpForwardTable* table) {
    // The lanes read every level and its one-channel mask (packed: the reference checks the
    // shapes as it reads, and throws)
    if (!avx_covers(map, table) || mips.color.empty() || mips.color.size() != mips.valid.size() ||
        mips.column_rows.size() != static_cast<std::size_t>(map.width) ||
        mips.color[0].height != map.height)
        return false;
    for (std::size_t k = 0; k < mips.color.size(); ++k) {
        const Image &color = mips.color[k], &valid = mips.valid[k];
        if (color.channels != 3 || color.width != map.width || valid.channels != 1 ||
            valid.width != color.width || valid.height != color.height)
            return false;
    }
    return true;
}

bool resolve_vp_avx_applies(const VisualPolarMap& map, const Image& color, const Image& valid,
                            const VpForwardTable* table, bool need_table) {
    return avx_covers(map, table, need_table) && color.channels == 3 && valid.channels == 1 &&
           color.width == map.width && color.height == map.height && valid.width == map.width &&
           valid.height == map.height;
}

namespace {

/// The levels' first texels (level k of height heights[k], all of width w) into in.level_start
/// and in.first_starts; returns the texels of all levels.
std::size_t start_levels(VpResolveAvxInputs& in, const std::vector<int>& heights) {
    in.level_start.clear();
    std::size_t texels = 0;
    for (const int height : heights) {
        in.level_start.push_back(static_cast<std::int32_t>(texels));
        texels += static_cast<std::size_t>(in.width) * static_cast<std::size_t>(height);
    }
    std::fill(std::begin(in.first_starts), std::end(in.first_starts), 0);
    std::copy_n(in.level_start.begin(), std::min<std::size_t>(lanes, in.level_start.size()),
                in.first_starts);
    return texels;
}

/// `texels` texels of a 3-channel level and its mask packed (R, G, B, mask): eight at a time
/// with AVX2 (the same floats, moved by shuffles), then one by one.
__attribute__((target("avx2"))) void pack_level(const float* color, const float* valid,
                                                std::size_t texels, float* packed) {
    std::size_t t = 0;
    for (; t + lanes <= texels; t += lanes) {
        __m256 channels[3];
        split3_lanes(color + 3 * t, channels);
        const __m256 mask = _mm256_loadu_ps(valid + t);
        for (int half = 0; half < 2; ++half) {  // texels t .. t + 3, then t + 4 .. t + 7
            __m128 q[4] = {
                half ? _mm256_extractf128_ps(channels[0], 1) : _mm256_castps256_ps128(channels[0]),
                half ? _mm256_extractf128_ps(channels[1], 1) : _mm256_castps256_ps128(channels[1]),
                half ? _mm256_extractf128_ps(channels[2], 1) : _mm256_castps256_ps128(channels[2]),
                half ? _mm256_extractf128_ps(mask, 1) : _mm256_castps256_ps128(mask)};
            _MM_TRANSPOSE4_PS(q[0], q[1], q[2], q[3]);
            for (int k = 0; k < 4; ++k) _mm_storeu_ps(packed + 4 * (t + 4 * half + k), q[k]);
        }
    }
    for (; t < texels; ++t) {
        float* p = packed + 4 * t;
        p[0] = color[3 * t], p[1] = color[3 * t + 1], p[2] = color[3 * t + 2], p[3] = valid[t];
    }
}

/// downsample_texel (resolve.cpp) on packed texels: texel (i, j) of level k + 1 (`out`) from
/// level k (`in`, w texels a row) whose column i has n rows: a column of one row carried down
/// (its colours where traced, its mask as 1 or 0), else the running mean of the traced ones of
/// rows 2j and (2j + 1) mod n, the reference's operations in its order; j >= ceil(n / 2): 0.
void downsample_packed_texel(const float* in, int w, int n, int i, int j, float* out) {
    std::fill_n(out, 4, 0.0f);
    const auto at = [&](int row) { return in + 4 * (static_cast<std::size_t>(row) * w + i); };
    if (n == 1) {
        if (j == 0 && at(0)[3] != 0.0f) {
            std::copy_n(at(0), 3, out);
            out[3] = 1.0f;
        }
        return;
    }
    if (j >= (n + 1) / 2) return;
    int count = 0;
    for (const int row : {2 * j, (2 * j + 1) % n}) {
        const float* texel = at(row);
        if (texel[3] == 0.0f) continue;
        ++count;
        for (int c = 0; c < 3; ++c) out[c] += (texel[c] - out[c]) / static_cast<float>(count);
    }
    if (count > 0) out[3] = 1.0f;
}

/// downsample_packed_texel for texels (i, j) and (i + 1, j) whose columns both have n > 1 rows
/// and j < ceil(n / 2): both texels' four floats in one register, each float's lane doing the
/// reference's operations (its texel's mask spread to its four floats); the mask's lane then
/// takes 1 or 0.
__attribute__((target("avx2"))) void downsample_packed_pair(const float* in, int w, int n, int i,
                                                            int j, float* out) {
    const auto at = [&](int row) { return in + 4 * (static_cast<std::size_t>(row) * w + i); };
    __m256 mean = zero(), count = zero();
    for (const int row : {2 * j, (2 * j + 1) % n}) {
        const __m256 texels = _mm256_loadu_ps(at(row));
        const __m256 traced = not_equal(_mm256_permute_ps(texels, _MM_SHUFFLE(3, 3, 3, 3)), zero());
        count = select(traced, _mm256_add_ps(count, set(1.0f)), count);
        mean = select(traced,
                      _mm256_add_ps(mean, _mm256_div_ps(_mm256_sub_ps(texels, mean), count)), mean);
    }
    const __m256 mask = select(greater(count, zero()), set(1.0f), zero());
    _mm256_storeu_ps(out, _mm256_blend_ps(mean, mask, 0b10001000));
}

}  // namespace

VpResolveAvxInputs vp_resolve_avx_inputs(const VpMips& mips) {
    VpResolveAvxInputs in;
    in.width = mips.color[0].width;
    in.column_rows = mips.column_rows;
    in.last_levels.reserve(mips.column_rows.size());
    for (const int n : mips.column_rows) in.last_levels.push_back(vp_mip_last_level(n));
    std::vector<int> heights;
    for (const Image& level : mips.valid) heights.push_back(level.height);
    in.texels.resize(4 * start_levels(in, heights));
    for (std::size_t k = 0; k < mips.color.size(); ++k)
        pack_level(mips.color[k].data.data(), mips.valid[k].data.data(), mips.valid[k].data.size(),
                   in.texels.data() + 4 * in.level_start[k]);
    return in;
}

void vp_resolve_avx_inputs(const VisualPolarMap& map, const Image& color, const Image& valid,
                           VpResolveAvxInputs& in) {
    FOVREF_CHECK(resolve_vp_avx_applies(map, color, valid, nullptr, false),
                 "a packed pyramid of another buffer's shape");
    const auto w = static_cast<std::size_t>(map.width);
    in.width = map.width;
    in.column_rows.resize(w);
    in.last_levels.resize(w);
    for (std::size_t i = 0; i < w; ++i) {
        in.column_rows[i] = vp_column_rows(map, static_cast<int>(i));
        in.last_levels[i] = vp_mip_last_level(in.column_rows[i]);
    }
    // build_vp_mips's levels: level 0 the buffer, then ceil-halved heights
    std::vector<int> heights = {map.height};
    for (int level = 1; level < vp_mip_levels(map); ++level)
        heights.push_back((heights.back() + 1) / 2);
    in.texels.resize(4 * start_levels(in, heights));  // every float is written below
    pack_level(color.data.data(), valid.data.data(), w * static_cast<std::size_t>(map.height),
               in.texels.data());
    std::vector<int> rows = in.column_rows;  // at level k
    for (std::size_t k = 0; k + 1 < heights.size(); ++k) {
        const float* from = in.texels.data() + 4 * static_cast<std::size_t>(in.level_start[k]);
        float* to = in.texels.data() + 4 * static_cast<std::size_t>(in.level_start[k + 1]);
        for (int j = 0; j < heights[k + 1]; ++j)
            for (int i = 0; i < map.width; ++i) {
                const auto col = static_cast<std::size_t>(i);
                const int n = rows[col];
                float* out = to + 4 * (static_cast<std::size_t>(j) * w + col);
                if (n > 1 && j < (n + 1) / 2 && col + 1 < w && rows[col + 1] == n) {
                    downsample_packed_pair(from, map.width, n, i, j, out);
                    ++i;
                } else {
                    downsample_packed_texel(from, map.width, n, i, j, out);
                }
            }
        for (int& n : rows) n = (n + 1) / 2;
    }
}

int resolve_vp_row_avx(const VisualPolarMap& map, VpMipsSource& mips, const VpResolveAvxInputs& in,
                       const VpForwardTable& table, bool mip, Image& out, int y,
                       ResolveStats& stats) {
    const int groups = map.screen_width / lanes;
    for (int group = 0; group < groups; ++group)
        resolve_group(map, mips, in, table, mip, out, group * lanes, y, stats);
    return groups * lanes;
}

namespace {

/// vp_table_arguments_avx for pixels k .. k + 7; false (nothing written) where a u is NaN.
__attribute__((target("avx2"))) bool table_arguments_group(int width, const int* rows,
                                                           const float* u, const float* r,
                                                           std::size_t k, int* const column[2],
                                                           float* const argument[2]) {
    const __m256 uk = _mm256_loadu_ps(u + k);
    if (bits(_mm256_cmp_ps(uk, uk, _CMP_UNORD_Q)) != 0) return false;
    // vp_rho_columns: s = clamp(u, 1/2, w - 1/2) - 1/2, i0 = floor(s), i1 = min(i0 + 1, w - 1)
    const __m256 lo = set(0.5f), hi = set(static_cast<float>(width) - 0.5f);
    const __m256 clamped = select(less(uk, lo), lo, select(less(hi, uk), hi, uk));
    const __m256i i0 = _mm256_cvttps_epi32(floor(_mm256_sub_ps(clamped, set(0.5f))));
    const __m256i i1 =
        _mm256_min_epi32(_mm256_add_epi32(i0, _mm256_set1_epi32(1)), _mm256_set1_epi32(width - 1));
    // rows / (2 pi max(r, 2^-10))
    const __m256 denominator =
        _mm256_mul_ps(set(two_pi), std_max(_mm256_loadu_ps(r + k), set(0x1p-10f)));
    const __m256i columns[2] = {i0, i1};
    for (int side = 0; side < 2; ++side) {
        const __m256i n = _mm256_i32gather_epi32(rows, columns[side], 4);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(column[side] + k), columns[side]);
        _mm256_storeu_ps(argument[side] + k, _mm256_div_ps(_mm256_cvtepi32_ps(n), denominator));
    }
    return true;
}

}  // namespace

std::size_t vp_table_arguments_avx(int width, const int* rows, const float* u, const float* r,
                                   std::size_t n, int* const column[2], float* const argument[2]) {
    if (!simd_allowed() || !cpu_has_avx2()) return 0;
    std::size_t k = 0;
    for (; k + lanes <= n; k += lanes)
        if (!table_arguments_group(width, rows, u, r, k, column, argument)) break;
    return k;
}

bool downsample_avx_applies(const Image& color, const Image& valid) {
    return color.channels == 3 && valid.channels == 1 && valid.width == color.width &&
           valid.height == color.height && simd_allowed() && cpu_has_avx2();
}

__attribute__((target("avx2"))) int downsample_group_avx(const Image& color, const Image& valid,
                                                         const std::vector<int>& rows, int i, int j,
                                                         Image& color_out, Image& valid_out) {
    const int n = rows[static_cast<std::size_t>(i)];
    if (n == 1 || j >= (n + 1) / 2) return 0;
    for (int l = 1; l < lanes; ++l)
        if (rows[static_cast<std::size_t>(i + l)] != n) return 0;
    // Rows 2j and (2j + 1) mod n of the eight columns: side by side in each row
    const int taps[2] = {2 * j, (2 * j + 1) % n};
    __m256 mean[3] = {zero(), zero(), zero()};
    __m256 count = zero();
    for (const int row : taps) {
        const __m256 traced = not_equal(_mm256_loadu_ps(&valid.data[valid.index(i, row)]), zero());
        count = select(traced, _mm256_add_ps(count, set(1.0f)), count);
        __m256 v[3];
        split3_lanes(&color.data[color.index(i, row)], v);
        for (int c = 0; c < 3; ++c)
            mean[c] = select(
                traced, _mm256_add_ps(mean[c], _mm256_div_ps(_mm256_sub_ps(v[c], mean[c]), count)),
                mean[c]);
    }
    merge3_lanes(mean, &color_out.data[color_out.index(i, j)]);
    _mm256_storeu_ps(&valid_out.data[valid_out.index(i, j)],
                     select(greater(count, zero()), set(1.0f), zero()));
    return lanes;
}

}  // namespace fovref
