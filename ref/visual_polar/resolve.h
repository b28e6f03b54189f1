// Pass 2 of the Visual-Polar modes (Koskela P5 §3.4; SPEC §6 "Resolve, Visual-Polar"): the
// screen image from the Visual-Polar buffer (ref/visual_polar/map.h), bilinear along rho
// (clamped) and, along phi, trilinear over a pyramid built per column on the phi axis only.
//
// Near the gaze a column's n_i texels lie on a small circle, so one screen pixel covers many of
// them along phi; each column is therefore prefiltered along phi alone (rho is never
// downsampled: the columns already follow the acuity fall-off).
//
// Pyramid (build_vp_mips), for a w x h buffer `color` (any channel count) and its mask `valid`
// (1 channel, non-zero = traced):
//   level 0 is the buffer and its mask, unchanged (rows j >= n_i of column i are clipped: they
//     are never read, whatever they hold); column i has n_i = vp_column_rows(map, i) rows.
//   column i has rows(i, k) rows at level k: rows(i, 0) = n_i, rows(i, k + 1) =
//     ceil(rows(i, k) / 2) (= ceil(n_i / 2^k); vp_mip_rows).
//   level k + 1, column i, row j < rows(i, k + 1): the traced texels among level k's rows 2j and
//     (2j + 1) mod n (n = rows(i, k); the last row of an odd column wraps onto row 0), in that
//     order, averaged as the running mean m_k = m_(k-1) + (x_k - m_(k-1)) / k in binary32
//     (m_0 = 0: a constant stays exactly that constant); traced (1) when one of them is, else
//     colour 0 and mask 0. A column of one row is carried down unchanged, its mask as 1 or 0
//     (the wrap would pair row 0 with itself).
//   levels are stored as images of width w and height ceil(h / 2^k) (color[k]: the buffer's
//     channels; valid[k]: 1 channel); at levels k >= 1, rows j >= rows(i, k) of column i hold
//     0 (colour and mask) and are never read. Levels are added until every column has one
//     row: 1 + ceil(log2(max_i n_i)) levels (max_i n_i = h: the periphery's columns have h rows).
//   Column i's last level is L_i = ceil(log2(n_i)), the first with one row (vp_mip_last_level).
//
// Lookup of screen pixel (x, y) (resolve_vp_pixel), binary32 throughout, two_pi = 2 pi rounded:
//   c = (x + 1/2, y + 1/2); u = vp_forward(map, c).x (vp_forward_radius); (dx, dy) = c - g;
//   r = max(sqrt(dx^2 + dy^2), 2^-10); theta = dm::atan2(dy, dx), + two_pi if negative.
//   rho (clamp): s = clamp(u, 1/2, w - 1/2) - 1/2, i0 = floor(s), i1 = min(i0 + 1, w - 1),
//     fx = s - i0.
//   for each column c in {i0, i1} (i1 only when fx > 0 and i1 != i0):
//     n_c = vp_column_rows(map, c); v_c = n_c theta / two_pi, evaluated (n_c theta) / two_pi as
//       vp_forward does, so for the column vp_forward used (floor(u) in the fovea, any column in
//       the periphery) v_c is vp_forward's v bit for bit (choice: each column is sampled at the
//       pixel's angle on its own row count, rather than at vp_forward's v);
//     lambda_c = clamp(dm::log2(n_c / (two_pi r)), 0, L_c) (vp_mip_level): the column's texels
//       per screen pixel along the circle of radius r;
//     l0 = floor(lambda_c), l1 = min(l0 + 1, L_c), f = lambda_c - l0;
//     level l is sampled along phi at v_l = v_c * 2^-l (exact) over n = rows(c, l) rows
//       (sample_vp_phi): t = v_l - 1/2, j0 = floor(t) wrapped into [0, n), j1 = (j0 + 1) mod n,
//       fv = t - floor(t); taps: j0 (weight 1 - fv > 0) if traced, j1 if traced and fv > 0;
//       both: lerp(c(j0), c(j1), fv); one: that tap (weights renormalised); none: no value.
//       (Where n_c is not a multiple of 2^l, level l's last row wraps onto row 0 and its rows
//       are read at v_c / 2^l all the same, as the log-polar pyramid of mip_resolve.h does.)
//     the column's value: l1 sampled only when l1 != l0 and f > 0; both levels have a value:
//       lerp(level l0, level l1, f); one: that level; none: the column has no value.
//   the pixel: both columns have a value: lerp(column i0, column i1, fx); one: that column
//     (renormalised over the columns that produced a value); none: black, counted in
//     stats.pixels_untraced_taps. Every pixel counts in stats.pixels_from_buffer (there is no
//     gaze buffer in the Visual-Polar modes).
// lerp(a, b, t) = a + t (b - a), per channel, so a constant buffer resolves to exactly that
// constant and a fully traced neighbourhood gives plain trilinear filtering.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "ref/image/image.h"
#include "ref/log_polar/resolve.h"
#include "ref/visual_polar/map.h"

namespace fovref {

/// The phi-only pyramid of a Visual-Polar buffer (layout above). Compared whole in tests.
struct VpMips {
    std::vector<int> column_rows;  ///< n_i of level 0, one per column (w entries)
    std::vector<Image> color;      ///< level k: w x ceil(h / 2^k), the buffer's channels
    std::vector<Image> valid;      ///< level k: w x ceil(h / 2^k), 1 channel, 1 = traced
    bool operator==(const VpMips&) const = default;
};

/// Rows of a column of `rows` rows at pyramid level `level`: ceil-halved `level` times
/// (= ceil(rows / 2^level)).
int vp_mip_rows(int rows, int level);
/// The first level at which a column of `rows` rows has one row: ceil(log2(rows)).
int vp_mip_last_level(int rows);
/// The pyramid's levels for `map`: 1 + vp_mip_last_level of its largest column.
int vp_mip_levels(const VisualPolarMap& map);
/// Rows of column `column` at level `level` of `mips`.
int vp_mip_column_rows(const VpMips& mips, int column, int level);

/// The pyramid of `color` (w x h, any channel count) and `valid` (w x h, 1 channel) for `map`.
/// Throws fovref::Error (a bug) for buffers of another size than the map's.
VpMips build_vp_mips(const VisualPolarMap& map, const Image& color, const Image& valid);

/// The phi level (continuous) of a column of `rows` rows seen at screen radius `radius`:
/// clamp(log2(rows / (2 pi max(radius, 2^-10))), 0, vp_mip_last_level(rows)).
float vp_mip_level(int rows, float radius);
/// The same level before its clamp: log2(rows / (2 pi max(radius, 2^-10))).
float vp_mip_lambda(int rows, float radius);

/// The columns a lookup at column coordinate u reads along rho: s = clamp(u, 1/2, width - 1/2)
/// - 1/2, i0 = floor(s), i1 = min(i0 + 1, width - 1), fx = s - i0; `count` is 2 when column i1
/// has a weight (i1 != i0 and fx > 0), else 1.
struct VpColumns {
    int i0 = 0, i1 = 0;
    float fx = 0.0f;
    int count = 1;
};
VpColumns vp_rho_columns(int width, float u);

/// The rows a lookup at row coordinate v reads along phi on a column of `rows` rows: t = v - 1/2,
/// j0 = floor(t) wrapped into [0, rows), j1 = (j0 + 1) mod rows, fv = t - floor(t).
struct VpRows {
    int j0 = 0, j1 = 0;
    float fv = 0.0f;
};
VpRows vp_phi_rows(int rows, float v);

/// Linear lookup along phi of column `column` of one level (`color`, `valid`) that has `rows`
/// rows there, at continuous row coordinate v (texel centres at + 1/2, wrap modulo rows) over
/// the traced taps; writes color.channels values to `out`. Returns false (out = 0) when no
/// traced tap has a non-zero weight. v must lie in [-rows, 2 rows] (the lookups give [0, rows]);
/// otherwise a check fails.
bool sample_vp_phi(const Image& color, const Image& valid, int column, int rows, float v,
                   float* out);

/// Each screen pixel's polar coordinates as the resolve computes them (u = vp_forward's u, the
/// distance r from the gaze, theta), kept by a mode while the map stays the same (a static gaze):
/// the same bits without the bisection and atan2 per pixel. polar: W x H x 3 (u, r, theta).
/// levels: W x H x 4, for the pixel's columns i0 and i1 (vp_rho_columns of u): n_0, lambda_0,
/// n_1, lambda_1, with n_k the column's rows in the map the table was made for and lambda_k =
/// vp_mip_level(n_k, r) (two logarithms per pixel): the resolve uses lambda_k where the
/// pyramid's column still has n_k rows (a BMFR staircase changes the fovea's rows between
/// frames) and computes it otherwise, the same bits either way.
/// level0: per group of eight pixels from the left of a row (row-major, floor(W / 8) a row), 1
/// where each of the eight pixels has n_0 = n_1 = level0_rows (the last column's rows) and
/// lambda_0 = lambda_1 = 0 (level 0 only, both columns), else 0: the resolve's AVX lanes then
/// skip reading those levels in the periphery (vp_mark_level0_groups; a table whose levels are
/// edited must be marked again).
struct VpForwardTable {
    VisualPolarMap map;
    Image polar;
    Image levels;
    std::vector<std::uint8_t> level0;
    int level0_rows = 0;
};
VpForwardTable vp_forward_table(const VisualPolarMap& map);
/// table.level0 and table.level0_rows from table.levels and table.map (vp_forward_table calls it).
void vp_mark_level0_groups(VpForwardTable& table);

/// Per-pixel work of the Visual-Polar resolve: screen pixel (x, y) of `out` (the screen's size,
/// the buffer's channel count). `lambda` (optional) receives the level lambda_c of column i0.
/// `mip` false (`resolve=bilinear`): lambda = 0, level 0 only (bilinear along rho and phi).
void resolve_vp_pixel(const VisualPolarMap& map, const VpMips& mips, Image& out, int x, int y,
                      ResolveStats& stats, float* lambda = nullptr, bool mip = true,
                      const VpForwardTable* table = nullptr);

/// Pass 2 of the Visual-Polar modes: a W x H image with the buffer's channel count, row by row.
/// `storage`: an image the output is written into when it has the output's shape (a stage
/// recycles an earlier frame's): every pixel is written, none of its values is read; otherwise
/// the output is made anew.
Image resolve_visual_polar(const VisualPolarMap& map, const VpMips& mips, ResolveStats& stats,
                           bool mip = true, const VpForwardTable* table = nullptr,
                           Image storage = {});

struct VpResolveAvxInputs;  // resolve_avx.h

/// resolve_visual_polar(map, build_vp_mips(map, color, valid), ...) from the buffer and its mask
/// themselves: the same image and counters. Where the AVX2 lanes cover the resolve
/// (resolve_avx.h) they read a packed pyramid built straight from the buffer (in `packed`, whose
/// storage a stage keeps from frame to frame, when given), and the pyramid above is built only
/// if a pixel needs the reference (the last W mod 8 of each row, or a lane the lanes leave).
Image resolve_visual_polar(const VisualPolarMap& map, const Image& color, const Image& valid,
                           ResolveStats& stats, bool mip = true,
                           const VpForwardTable* table = nullptr, Image storage = {},
                           VpResolveAvxInputs* packed = nullptr);

/// The polar coordinates of screen pixel (x, y)'s centre as the resolve computes them: u
/// (vp_forward's), the distance r from the gaze and theta.
void vp_polar_pixel(const VisualPolarMap& map, int x, int y, float& u, float& r, float& theta);

/// The texels pass 2 reads at level 0 for screen pixel (x, y), traced or not: the one or two
/// columns along rho (the second only with a non-zero weight), and in each the one or two rows
/// along phi at the pixel's angle on that column's own rows.
std::vector<glm::ivec2> vp_resolve_taps(const VisualPolarMap& map, int x, int y);

}  // namespace fovref
