// Pass 2 (SPEC §6, Lund §3.3 "inverse transform", Meng §2.2 "inverse log-polar transformation"):
// the screen image from the log-polar buffer and, inside the gaze circle, the gaze buffer.
//
//   for each screen pixel (x, y), row by row:   resolve_pixel(x, y)
//     c = (x + 1/2, y + 1/2)
//     |c - g| < r_G: the gaze buffer's pixel for screen pixel (x, y), (x - x0, y - y0) in the
//                    buffer that covers gaze_window (traced: the circle test is the same one)
//     otherwise (u, v) = lp_forward(c) and the log-polar buffer sampled bilinearly
//       (sample_lp_bilinear): texel centres at +1/2, v wraps modulo h, u clamped to
//       [1/2, w - 1/2]; only traced texels count, with their weights renormalised; no traced
//       tap with a non-zero weight: black, counted.
//
// The bilinear filter is written as lerps (lerp(a, b, t) = a + t (b - a), binary32, per
// channel) so that a constant buffer resolves to exactly that constant and a fully traced
// neighbourhood gives plain bilinear filtering:
//   a row j: taps i0 = floor(s), i1 = min(i0 + 1, w - 1), s = clamp(u, 1/2, w - 1/2) - 1/2,
//            fu = s - i0. Both traced: lerp(c(i0), c(i1), fu), row weight 1; one traced: that
//            tap, row weight 1 - fu (i0) or fu (i1); none: row weight 0.
//   the rows j0 = floor(v - 1/2) mod h and j1 = (j0 + 1) mod h, fv = (v - 1/2) - floor(v - 1/2),
//            weights W0 = (1 - fv) w(j0), W1 = fv w(j1). Both > 0: lerp(row0, row1, t) with
//            t = fv when w(j0) = w(j1), else t = W1 / (W0 + W1); one > 0: that row; none: black.
// This equals sum(weight_k c_k) / sum(weight_k) over the traced taps, with bilinear weights.
#pragma once

#include <cstdint>
#include <vector>

#include "ref/image/image.h"
#include "ref/log_polar/map.h"
#include "ref/raster/gbuffer.h"

namespace fovref {

/// The taps of one bilinear lookup, as sample_lp_bilinear reads them (for `fovref probe`).
struct BilinearLookup {
    glm::vec2 uv{0.0f};
    int i0 = 0, i1 = 0, j0 = 0, j1 = 0;  ///< columns and rows of the four taps
    float fu = 0.0f, fv = 0.0f;
    bool traced[4] = {false, false, false, false};  ///< (i0,j0), (i1,j0), (i0,j1), (i1,j1)
    float row_weight[2] = {0.0f, 0.0f};             ///< W0, W1 (see above)
    float t = 0.0f;                                 ///< the final lerp's parameter
};

/// The columns, rows and fractions of the bilinear lookup at buffer coordinates uv in a
/// width x height buffer, as sample_lp_bilinear computes them (traced, row_weight and t are
/// left false and 0). Throws fovref::Error (a bug) for a v more than a row outside [0, height].
BilinearLookup lp_bilinear_index(int width, int height, glm::vec2 uv);

/// The four taps of the bilinear lookup at buffer coordinates uv (columns, rows, fractions and
/// which are traced, from `valid`), as sample_lp_bilinear reads them; row_weight and t are 0.
BilinearLookup lp_bilinear_taps(const Image& valid, glm::vec2 uv);

/// Bilinear lookup of `buffer` (any channel count) at buffer coordinates uv over the traced
/// texels of `valid`; writes buffer.channels values to `out`. Returns false (out = 0) when no
/// traced tap has a non-zero weight. `lookup` (optional) receives the taps.
bool sample_lp_bilinear(const Image& buffer, const Image& valid, glm::vec2 uv, float* out,
                        BilinearLookup* lookup = nullptr);

/// What pass 2 did.
struct ResolveStats {
    std::int64_t pixels_from_gaze = 0;      ///< copied from the gaze buffer
    std::int64_t pixels_from_buffer = 0;    ///< sampled from the log-polar buffer
    std::int64_t pixels_untraced_taps = 0;  ///< no traced tap: black
};

/// The composite modes' gaze buffer as pass 2 reads it.
struct GazeInput {
    const Image* image = nullptr;  ///< null: no gaze buffer
    ScreenWindow window;           ///< where it lies on the screen (gaze_window of the map)
};
/// The gaze input of a frame: `image` (null: none) covering gaze_window(map).
GazeInput gaze_input(const LogPolarMap& map, const Image* image);

/// Whether pass 2 takes screen pixel (x, y) from the gaze buffer: there is one and the pixel's
/// centre lies inside the gaze circle.
bool reads_gaze_buffer(const LogPolarMap& map, const GazeInput& gaze, int x, int y);

/// Pass 2 inside the gaze circle: when screen pixel (x, y)'s centre lies inside it and there is
/// a gaze buffer, copies that buffer's pixel to `pixel` (channels values), counts it and returns
/// true; otherwise returns false.
bool gaze_pixel(const LogPolarMap& map, const GazeInput& gaze, int x, int y, float* pixel,
                int channels, ResolveStats& stats);

/// The inputs of pass 2: the log-polar buffer and its mask, and (composite foveation) the gaze
/// buffer, with the same channel count.
struct ResolveInputs {
    const Image& buffer;
    const Image& buffer_valid;
    GazeInput gaze{};
};

/// Pass 2's forward map of every pixel centre, made once for a map and reused while the map (the
/// gaze, the sizes, the constants) stays the same, as a GPU renderer keeps such a table: the
/// values are lp_forward's, bit for bit, and with `mip_levels` > 0 also mip_lambda's (the level
/// before its clamp: clamped to [0, mip_levels - 1] it is mip_level's).
struct ForwardTable {
    LogPolarMap map;
    int mip_levels = 0;
    std::vector<glm::vec2> uv;      ///< W x H, row-major
    std::vector<float> mip_lambda;  ///< W x H when mip_levels > 0, unclamped
};
ForwardTable forward_table(const LogPolarMap& map, int mip_levels = 0);

/// Per-pixel work of pass 2: screen pixel (x, y) of `out`. With `table` (made for this map) the
/// forward map is read from it instead of computed: the same bits.
void resolve_pixel(const LogPolarMap& map, const ResolveInputs& in, Image& out, int x, int y,
                   ResolveStats& stats, BilinearLookup* lookup = nullptr,
                   const ForwardTable* table = nullptr);

/// Pass 2: a W x H image with the buffer's channel count. `storage`: an image the output is written
/// into when it has the output's shape (a stage recycles an earlier frame's): every pixel is
/// written, none of its values is read; otherwise the output is made anew.
Image resolve_log_polar(const LogPolarMap& map, const ResolveInputs& in, ResolveStats& stats,
                        const ForwardTable* table = nullptr, Image storage = {});

/// The texels pass 2 reads for screen pixel (x, y), traced or not (a mip resolve's level 0): with
/// a gaze buffer and the centre inside the gaze circle, that buffer's pixel (x - x0, y - y0)
/// (`from_gaze` true); otherwise the taps (i0, j0), (i1, j0), (i0, j1), (i1, j1) of the
/// forward-mapped centre's bilinear lookup, each once. What a GPU developer looks at when a pixel
/// differs: the buffer texels it came from.
std::vector<glm::ivec2> resolve_pixel_taps(const LogPolarMap& map, int x, int y, bool& from_gaze);

}  // namespace fovref
