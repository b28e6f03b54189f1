// Kernel log-polar mapping between the screen and the log-polar buffer (Meng 2018 ch. 2, Lund 2020
// §3.3; SPEC §5.1-5.2). docs/foveation.md states every formula and choice below.
//
// Screen W x H, gaze g = (gx, gy) (any point, on screen or off), p = (x, y) a screen point,
// x' = x - gx, y' = y - gy, r = sqrt(x'^2 + y'^2). The buffer has w columns (radial axis u) and
// h rows (angular axis v); texel (i, j) has its centre at (u, v) = (i + 1/2, j + 1/2).
//
//   l(r)  = ln(1 + r)                    (choice: 0 at the gaze point; the papers' ln r is not)
//   L     = l(R),  R = sqrt(W^2 + H^2)   ("diagonal", Lund eq. 3.10)
//              or  R = max |corner - g|  ("corners", Meng eq. 2.12-2.13)
//   rho   = l(r) / L
//   G     = K(l(r_G) / L) with a gaze buffer of radius r_G (SPEC §5.2), else 0
//   forward (screen -> buffer), Lund eq. 3.7 with the composite renormalisation:
//     u = w (K(rho) - G) / (1 - G)
//     theta = atan2(y', x'); theta += 2 pi if theta < 0;  v = h theta / (2 pi); v -= h if v >= h
//   inverse (buffer -> screen), Lund eq. 3.8:
//     rho = K^-1(G + (1 - G) u / w);  r = e^(L rho) - 1;  theta = 2 pi v / h
//     p = g + r (cos theta, sin theta)
//
// The angle grows from +x towards +y, i.e. clockwise on a y-down screen. Per-point arithmetic is
// binary32 with the deterministic ln, exp, atan2, cos, sin of ref/core/dmath.h, in the operation
// order written in each function; the map's constants (L, r_G, G) are computed once in binary32
// too (make_log_polar_map), the buffer size in binary64 (log_polar_buffer_size).
#pragma once

#include <cmath>
#include <vector>

#include <glm/glm.hpp>

#include "ref/core/halton.h"
#include "ref/core/vec.h"
#include "ref/log_polar/kernel.h"

namespace fovref {

/// Which radius R the log-polar buffer's last column reaches (SPEC §5.1).
enum class RadiusMode {
    diagonal,  ///< R = sqrt(W^2 + H^2), whatever the gaze (Lund eq. 3.10)
    corners,   ///< R = the largest distance from the gaze to a screen corner (Meng eq. 2.12)
};

/// The parameters of the mapping (a mode's preset supplies them, `--param` overrides them).
struct LogPolarParams {
    float sigma = 1.0f;  ///< buffer reduction: the buffer has about W H / sigma^2 texels
    Kernel kernel;       ///< K; x^1 (the classic log-polar map) by default
    /// Aspect w / h of the buffer (Lund eq. 3.6); 0 = off: w = W / sigma, h = H / sigma (Meng,
    /// Lund eq. 3.1).
    float lp_aspect = 0.0f;
    RadiusMode radius = RadiusMode::diagonal;
    /// a_G, the gaze buffer's angular radius in radians (Lund §3.3.3); 0 = no gaze buffer.
    float gaze_angle = 0.0f;
    /// Lund §3.3.5's widening (`lp_widen=on`, L = diagonal only): the buffer is made wider by
    /// the share of its columns a centred gaze leaves off screen, so that the columns on screen
    /// are as many as the unwidened buffer's; the extra columns map beyond the farthest corner
    /// and are not traced.
    bool widen = false;
    bool operator==(const LogPolarParams&) const = default;
};

struct BufferSize {
    int width = 0;   ///< w: columns, the radial axis
    int height = 0;  ///< h: rows, the angular axis
    bool operator==(const BufferSize&) const = default;
};

/// The buffer's size for a W x H screen, in binary64, std::round (halves away from zero):
/// lp_aspect > 0: h = round(sqrt(W H / lp_aspect) / sigma), w = round(h lp_aspect);
/// lp_aspect = 0: w = round(W / sigma), h = round(H / sigma). Each at least 1. Throws
/// fovref::Error naming the parameter when sigma or lp_aspect is not usable (not finite,
/// sigma <= 0, lp_aspect < 0) or the buffer would exceed the image-size limit.
BufferSize log_polar_buffer_size(const LogPolarParams& params, int screen_width, int screen_height);

/// Everything the per-point maps need for one frame: the screen, the gaze and the constants
/// derived from the parameters once.
struct LogPolarMap {
    int screen_width = 0, screen_height = 0;
    glm::vec2 gaze{0.0f};
    int width = 0, height = 0;  ///< the buffer: w columns (u), h rows (v)
    Kernel kernel;
    float radius_max = 0.0f;      ///< R, in pixels
    float log_radius_max = 0.0f;  ///< L = ln(1 + R)
    float gaze_radius = 0.0f;     ///< r_G in pixels (0: no gaze buffer)
    float composite = 0.0f;       ///< G = K(ln(1 + r_G) / L), at most 1 (0: no gaze buffer)

    bool has_gaze_buffer() const { return gaze_radius > 0.0f; }
    bool operator==(const LogPolarMap&) const = default;
};

/// Makes the map for a W x H screen and gaze point: the buffer size (log_polar_buffer_size),
/// R and L = dm::log(1 + R) from params.radius, r_G = d_px dm::tan(a_G) (SPEC §5.2, d_px the
/// display model's viewing distance in pixels) and G = min(1, K(dm::log(1 + r_G) / L)). G = 1
/// means the gaze circle reaches R: the buffer then has no texel outside the circle, and every
/// texel maps inside it (see lp_texel_status). Throws fovref::Error naming the parameter for a
/// non-finite gaze, a_G outside [0, 1.5] rad, or a non-positive d_px with a_G > 0.
LogPolarMap make_log_polar_map(const LogPolarParams& params, int screen_width, int screen_height,
                               glm::vec2 gaze, float display_distance_px);

/// Forward map: the buffer coordinates (u, v) of screen point p (continuous; u < 0 inside the
/// gaze circle; u = w beyond R, where K clamps rho to 1). The denominator 1 - G is max(1 - G,
/// 2^-24) (SPEC §0's guard; G reaches 1 only when the gaze circle covers R).
glm::vec2 lp_forward(const LogPolarMap& map, glm::vec2 p);

/// Inverse map: the screen point of buffer coordinates (u, v).
glm::vec2 lp_inverse(const LogPolarMap& map, glm::vec2 uv);

/// Buffer texels per screen pixel at distance r (> 0) from the gaze, outside the gaze circle: the
/// map's Jacobian along the radius and along the circle (Lund §5.2 `mid_range_res`, SPEC §5.6),
/// what the mip resolve's level and `fovref density` read:
///   radial   s_u = w K'(rho) / ((1 + r) L (1 - G)),  rho = ln(1 + r) / L   (du/dr)
///   angular  s_v = h / (2 pi r)                                            (dv per pixel)
struct TexelsPerPixel {
    float radial = 0.0f;
    float angular = 0.0f;
};
TexelsPerPixel texels_per_pixel(const LogPolarMap& map, float r);

/// The inverse map at the texel centres, factored: the radius depends on the column only, the
/// angle on the row only. lp_inverse(map, (i + 1/2, j + 1/2)) is
/// (g.x + radius[i] cos_theta[j], g.y + radius[i] sin_theta[j]) with the very same operations, so
/// the table gives the same bits with w + h transcendental evaluations instead of 3 w h.
///
/// TAA jitter (SPEC §7): `jitter` replaces the centre (1/2, 1/2) by the Halton offset (o_x, o_y)
/// inside the texel, in the buffer's space before the inverse map: the table then holds the
/// inverse of (i + o_x, j + o_y). `screen_offset` (Meng's jitter after the inverse transform, the
/// kfr mode) is added to every screen point when it is not zero.
struct LpInverseTable {
    std::vector<float> radius;     ///< r of column i: exp(L K^-1(G + (1 - G) u / w)) - 1
    std::vector<float> cos_theta;  ///< cos(2 pi v / h) of row j
    std::vector<float> sin_theta;  ///< sin(2 pi v / h) of row j
    glm::vec2 screen_offset{0.0f};
};
LpInverseTable lp_inverse_table(const LogPolarMap& map, Offset2 jitter = {},
                                glm::vec2 screen_offset = glm::vec2(0.0f));

/// What the ray generation does with texel (i, j).
enum class TexelStatus {
    traced,       ///< its centre's inverse lies on screen and outside the gaze circle
    off_screen,   ///< its centre's inverse lies outside [0, W) x [0, H) (or is not finite)
    inside_gaze,  ///< on screen but inside the gaze circle (only possible when G = 1)
};

/// The texel's centre mapped to the screen (from the table), and whether a ray is traced
/// through it.
TexelStatus lp_texel_status(const LogPolarMap& map, const LpInverseTable& table, int i, int j,
                            glm::vec2& screen_point);

/// True when screen point p lies in [0, W) x [0, H) (false for NaN).
inline bool on_screen(int width, int height, glm::vec2 p) {
    return p.x >= 0.0f && p.x < static_cast<float>(width) && p.y >= 0.0f &&
           p.y < static_cast<float>(height);
}

/// True when screen point p lies inside the gaze circle: gaze_distance < r_G (strictly).
inline bool inside_gaze_circle(const LogPolarMap& map, glm::vec2 p) {
    return map.has_gaze_buffer() && gaze_distance(map.gaze, p) < map.gaze_radius;
}

}  // namespace fovref
