// Visual-Polar space (Koskela P5 §3.2; SPEC §5.3; docs/visual-polar.md): a buffer whose columns
// follow the eye's acuity fall-off with eccentricity and whose rows are angles around the gaze.
//
// Acuity model (Koskela P3/P4): m(e) = 1 for e <= 5.79 degrees, 7.49 / (0.3 e + 1)^2 beyond.
// Its fitted inverse CDF (P4 eq. 7; normative for the inverse map):
//   P(u) = 25.09 u^4 + 0.1680 u^3 + 27.61 u^2 + 23.87 u + 3.232   for u > u0 = 0.0965
//   P(u) = 18.64 sqrt(u)                                          for u <= u0     (degrees)
//
// Buffer w x h: column i (the radius rho), row j (the angle phi). s = R / P(1) pixels per model
// degree, R the largest gaze-to-corner distance (the farthest corner is the last column).
//   fovea, i < i_f = round(0.24 w): r_i = s P(u0) (i + 1/2) / i_f (linear);
//     n_i = clamp(ceil(h (i + 1/2) / i_f - 1/2), 1, h) rows (the triangular clip), theta_j =
//     2 pi (j + 1/2) / n_i for j < n_i; rows j >= n_i are clipped (never traced, no data).
//     With BMFR's staircase (P5 §3.3, Fig. 4b; staircase_block B > 0): every column of a BMFR
//     block column (B c - B/2 + o .. + B - 1, o the frame's block offset) has the rows of the
//     block column's last column in the buffer, n_i = tri(min(B c + B/2 - 1 + o, w - 1)), so
//     the phi height is the same within a block column and the steps move with the offset.
//   periphery, i >= i_f: U = u0 + (rho - rho_f)(1 - u0) / (1 - rho_f), rho = (i + 1/2) / w,
//     rho_f = i_f / w; r = s P(U); theta_j = 2 pi (j + 1/2) / h
//   forward (screen -> buffer, continuous): r < s P(u0): u = i_f r / (s P(u0)),
//     v = n(floor(u)) theta / (2 pi); else U = P^-1(r / s) by bisection, u = w (rho_f + (U - u0)
//     (1 - rho_f) / (1 - u0)), v = h theta / (2 pi); theta = atan2(y', x') (+ 2 pi if < 0)
//
// Per-point arithmetic is binary32 with the deterministic functions of ref/core/dmath.h.
#pragma once

#include <vector>

#include <glm/glm.hpp>
#include <optional>

#include "ref/filters/blur_ramp.h"
#include "ref/log_polar/map.h"

namespace fovref {

inline constexpr float vp_u0 = 0.0965f;  ///< the fitted CDF's branch point (P4 eq. 7)

/// The acuity model's relative sampling density m(e), e in degrees.
float vp_acuity(float eccentricity_deg);
/// The fitted inverse CDF P(u) in degrees, u in [0, 1].
float vp_inverse_cdf(float u);
/// P^-1(e) by bisection on [0, 1] in float (at most 64 steps, until the midpoint equals an
/// endpoint); 0 for e <= 0 and 1 for e >= P(1). The first 16 steps compare e with P at dyadic
/// midpoints k / 65536 read from a table of those values (the same comparisons, faster). Beyond
/// them, where the bracket [k, k + 1] / 65536 has k >= 1, the result is found without the
/// remaining steps: P in float is non-decreasing over every float in [0, 1] (checked float by
/// float in the tests), so the bisection ends with lo the largest float u of the bracket with
/// P(u) < e and hi the next float, and returns 0.5 (lo + hi); a guess interpolated in the
/// bracket is moved float by float to that u (at most 8 moves, else the bisection goes on): the
/// same bits as vp_cdf_bisection with 2 to 3 evaluations of P instead of 7 to 23.
float vp_cdf(float eccentricity_deg);
/// vp_cdf by the bisection alone (the readable reference).
float vp_cdf_bisection(float eccentricity_deg);
/// What vp_cdf's lane version (map_avx.h) reads: p[k] = P(k / 65536), k = 0 .. 65536, and for
/// a guess of P^-1, per guess bucket g = min(floor(e guess_scale), 4095) four floats at
/// guess[4 g]: its middle e_c and a quadratic c0 + d (c1 + d c2), d = e - e_c, through P^-1 (in
/// binary64) at the bucket's ends and middle.
struct VpCdfTables {
    const std::vector<float>& p;
    float guess_scale;
    const std::vector<float>& guess;
};
VpCdfTables vp_cdf_tables();

/// The Visual-Polar map of one frame: a W x H screen, the gaze, the buffer w x h.
struct VisualPolarMap {
    int screen_width = 0, screen_height = 0;
    glm::vec2 gaze{0.0f};
    int width = 0, height = 0;  ///< w (columns, rho), h (rows, phi)
    int fovea_columns = 0;      ///< i_f
    float scale = 0.0f;         ///< s, pixels per model degree
    float fovea_radius = 0.0f;  ///< s P(u0) in pixels
    /// BMFR's staircase clip (P5 Fig. 4b): the block edge B (0: the triangular clip) and the
    /// x offset o of the frame's block grid.
    int staircase_block = 0;
    int staircase_offset = 0;
    /// A log-polar buffer seen as a polar buffer (vp_log_polar_map), for BMFR on log-polar
    /// texels (P5's log-polar + BMFR comparison): the columns are the log-polar map's u and every
    /// column has all h rows; vp_forward, vp_forward_angle and vp_inverse use lp_forward and
    /// lp_inverse. The Visual-Polar members (fovea, scale) are 0 and nothing else applies.
    std::optional<LogPolarMap> log_polar;
    bool operator==(const VisualPolarMap&) const = default;
    /// Whether the forward map (u, r, theta of a screen point) is the same as `other`'s: every
    /// member but the clip, which changes only row counts.
    bool same_forward(const VisualPolarMap& other) const;
};

/// The map for a W x H screen, gaze g and buffer w x h (SPEC §12's preset: w = round(W / 1.5),
/// h = round(H / 1.5)); i_f = round(0.24 w). Throws fovref::Error for a bad size.
VisualPolarMap make_visual_polar_map(int screen_width, int screen_height, glm::vec2 gaze, int width,
                                     int height);

/// The log-polar map `map` as a polar buffer (VisualPolarMap::log_polar): its screen, gaze and
/// buffer size, no fovea (every column has h rows), t = v / h the angle as a fraction of the turn.
VisualPolarMap vp_log_polar_map(const LogPolarMap& map);
/// The preset's buffer size: round(W / 1.5) x round(H / 1.5).
glm::ivec2 visual_polar_buffer_size(int screen_width, int screen_height);

/// Rows of fovea column i < i_f: the triangular clip's, or BMFR's staircase's.
int vp_fovea_column_rows(const VisualPolarMap& map, int column);
/// Rows of column i that carry data: n_i in the fovea (the triangular clip, or BMFR's
/// staircase), h in the periphery (inline: the per-texel passes ask for it at every tap).
inline int vp_column_rows(const VisualPolarMap& map, int column) {
    return column >= map.fovea_columns ? map.height : vp_fovea_column_rows(map, column);
}
/// j mod rows in [0, rows) (rows > 0) for any j, the remainder of a division only where j lies
/// outside [0, rows): the row of a wrapped lookup.
inline int vp_wrap_row(int j, int rows) {
    if (j >= 0 && j < rows) return j;
    const int m = j % rows;
    return m < 0 ? m + rows : m;
}
/// The triangular clip's rows of column i, clamp(ceil(h (i + 1/2) / i_f - 1/2), 1, h) in the
/// fovea, h beyond.
int vp_triangle_rows(const VisualPolarMap& map, int column);

/// The screen radius of column i's texel centres.
float vp_column_radius(const VisualPolarMap& map, int column);

/// The screen point of texel (i, j)'s centre; false when the texel is clipped (j >= n_i).
bool vp_inverse(const VisualPolarMap& map, int column, int row, glm::vec2& screen);

/// vp_inverse's angle of row j in a column of n rows: theta_j = (2 pi (j + 1/2)) / n.
float vp_row_angle(int row, int rows);
/// vp_inverse's point at radius r (vp_column_radius) and the angle's cosine and sine:
/// g + (r cos, r sin).
inline glm::vec2 vp_texel_point(const VisualPolarMap& map, float r, float cosine, float sine) {
    return map.gaze + glm::vec2(r * cosine, r * sine);
}
/// dm::cos and dm::sin of vp_row_angle(j, n) for the rows j < n of a column of n rows: every
/// column with n rows shares them (the periphery's columns all have h), so a pass over the
/// buffer computes them once per row count instead of per texel, the same bits.
struct VpRowAngles {
    explicit VpRowAngles(int rows);
    std::vector<float> cosine, sine;  ///< row j at j
};

/// The continuous buffer coordinates (u, v) of screen point p (texel centres at + 1/2).
glm::vec2 vp_forward(const VisualPolarMap& map, glm::vec2 p);

/// u of a screen point at distance r from the gaze (vp_forward's u without the angle).
float vp_forward_radius(const VisualPolarMap& map, float r);

/// The distance r = sqrt(dx dx + dy dy) of screen point p from the gaze and its angle
/// theta = dm::atan2(dy, dx), + 2 pi if negative (vp_forward's).
void vp_polar(const VisualPolarMap& map, glm::vec2 p, float& r, float& theta);

/// (u, t) of screen point p: u as vp_forward, t = theta / (2 pi) in [0, 1], the angle as a
/// fraction of the turn (column c's continuous row is then t n_c; BMFR's reprojection and the
/// resolve use it where neighbouring fovea columns have different row counts).
glm::vec2 vp_forward_angle(const VisualPolarMap& map, glm::vec2 p);

/// What texel (i, j) is: clipped (j >= n_i), off screen (its centre's inverse lies outside the
/// screen [0, W) x [0, H)), or traced; `screen` receives the centre's screen point (unchanged
/// for a clipped texel).
enum class VpTexel { clipped, off_screen, traced };
VpTexel vp_texel_status(const VisualPolarMap& map, int column, int row, glm::vec2& screen);
/// Whether screen point p lies on the screen [0, W) x [0, H) (false for NaN): a texel's centre
/// that does not is off screen.
inline bool vp_on_screen(const VisualPolarMap& map, glm::vec2 p) {
    return p.x >= 0.0f && p.y >= 0.0f && p.x < static_cast<float>(map.screen_width) &&
           p.y < static_cast<float>(map.screen_height);
}

/// What the texels of a map are: clipped, off screen (the centre's inverse lies outside the
/// screen: never traced), or traced.
struct VisualPolarCounts {
    long long texels = 0, clipped = 0, off_screen = 0, traced = 0;
};
VisualPolarCounts vp_count_texels(const VisualPolarMap& map);

/// Where the P5 blur ramp (ref/filters/blur_ramp.h) is measured from on this map's screen: its
/// gaze, its scale s and the fovea edge P(u0) (= vp_inverse_cdf(vp_u0), 5.79 model degrees).
BlurRampGeometry blur_ramp_geometry(const VisualPolarMap& map);

}  // namespace fovref
