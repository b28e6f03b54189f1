// Temporal anti-aliasing (Lund §3.4, SPEC §7): the history of earlier frames blended into the
// current frame after pass 2 (SPEC §6: before the screen-space filters). docs/temporal.md.
//
// State carried between frames, explicitly (TaaState): the history colour (the previous TAA
// output), its per-pixel age, the previous frame's view depth and camera.
//
//   for each screen pixel p = (x, y), row by row:   taa_pixel(x, y)
//     no history (the first frame): output = current, age 1
//     stationary camera (its pose bit-equal to the previous one): the history pixel at p itself,
//       never rejected, no reprojection (counted: taa_reprojection_skipped)
//     otherwise reprojection (taa_reproject): z = the current view depth at p (0: no surface: the
//       history is rejected), d = the primary direction through p's centre,
//       P = camera + d z / (d . F), projected by the previous camera to p' with view depth z'
//       (behind it: rejected). The history colour and the previous depth z_h are sampled
//       bilinearly at p' (taa_sample: taps at pixel centres, taps off screen dropped and the
//       weights renormalised; no tap: rejected); the previous age is that of the pixel under p'
//       (clamped to the screen). A history with a non-finite value is rejected.
//       depth mode: consistent when |z' - z_h| <= tau z'; inconsistent -> rejected, except
//         beyond periphery x the diagonal from the gaze (Lund's flicker rule): kept, age 2
//       clamp mode (Karis): the history clamped per channel to the min/max of the current 3x3
//         neighbourhood (clamped at the screen border; or bounds given per pixel, from the
//         buffer's space); never rejected for depth
//     age_new = min(age_prev + 1, age_cap) (kept or clamped), 1 (rejected), 2 (periphery)
//     output = history (1 - 1/age_new) + current (1/age_new), per channel in binary32;
//       a rejected pixel's output is the current pixel itself
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "ref/image/image.h"
#include "ref/scene/camera.h"

namespace fovref {

enum class TaaRejection {
    depth,  ///< depth-based rejection with tau (Lund §3.4.1)
    clamp,  ///< neighbourhood clamping of the history, screen space (Karis 2014, Lund §3.4.2)
};

struct TaaParams {
    TaaRejection rejection = TaaRejection::depth;
    float tau = 0.01f;              ///< relative depth tolerance (SPEC §7 choice; Lund gives none)
    int age_cap = 20;               ///< Lund eq. 3.12
    float periphery = 1.0f / 3.0f;  ///< the flicker rule applies beyond this x the diagonal
};

/// What a frame hands to the next.
struct TaaState {
    bool valid = false;  ///< false before the first frame
    Image history;       ///< W x H x 3: the previous TAA output
    Image age;           ///< W x H x 1: its age, 1 .. age_cap
    Image depth;         ///< W x H x 1: the previous frame's view depth (0: no surface)
    Camera camera;       ///< the previous frame's camera
};

/// The current frame as TAA reads it.
struct TaaInputs {
    const Image& color;  ///< W x H x 3, pass 2's output
    const Image& depth;  ///< W x H x 1, the view depth at each pixel (0: no surface)
    const Camera& camera;
    glm::vec2 gaze{0.0f};  ///< for the periphery rule (screen pixels)
    /// Clamp mode: W x H x 6, per pixel the neighbourhood's min (r, g, b) then max (r, g, b),
    /// computed elsewhere (in the buffer's space, taa_buffer_bounds); null: the 3x3
    /// neighbourhood of `color` on the screen.
    const Image* bounds = nullptr;
};

enum class TaaDecision {
    first,       ///< no history: the current pixel
    stationary,  ///< static camera: the history at p, kept
    kept,        ///< reprojected and consistent
    rejected,    ///< no surface, behind the previous camera, off screen, non-finite, inconsistent
    periphery,   ///< inconsistent beyond the periphery radius: kept with age 2
    clamped,     ///< clamp mode: the history was outside the neighbourhood's box and clamped
                 ///< (inside it: kept)
};
const char* taa_decision_name(TaaDecision decision);

/// floor(v) for a finite v in (-2^31, 2^31) whose floor is a float: the same value as
/// std::floor (and the same zero: v here is never -0), without SSE2's long rounding sequence.
inline int taa_floor_int(float v) {
    const int i = static_cast<int>(v);  // truncation towards zero
    return static_cast<float>(i) > v ? i - 1 : i;
}

/// A bilinear sample at screen point q (pixel centres at +1/2) of `image`, over the taps that
/// lie on the screen, renormalised; `out` gets image.channels values. Returns the weight of the
/// taps used (0: none on screen, `out` zero). Taps: (x0, y0), (x0 + 1, y0), (x0, y0 + 1),
/// (x0 + 1, y0 + 1) with x0 = floor(q.x - 1/2), fx = q.x - 1/2 - x0 (y likewise), weights
/// (1 - fx)(1 - fy), fx (1 - fy), (1 - fx) fy, fx fy, summed in that order.
float taa_sample(const Image& image, glm::vec2 q, float* out);

/// The four taps of taa_sample at q on a W x H screen, in that order, with their weights; a tap
/// may lie off the screen (the sampler drops it). False when q lies a pixel or more off the
/// screen (no tap can be on it).
struct TaaTaps {
    int x[4] = {0, 0, 0, 0}, y[4] = {0, 0, 0, 0};
    float w[4] = {0, 0, 0, 0};
    bool on_screen(int k, int width, int height) const {
        return x[k] >= 0 && y[k] >= 0 && x[k] < width && y[k] < height;
    }
};
bool taa_taps(int width, int height, glm::vec2 q, TaaTaps& taps);

/// The reprojection of one frame, factored (every product below in binary32, in this order):
///   pixel (x, y) at view depth z: c = (x + 1/2, y + 1/2),
///     sx = ((2 c.x) / W - 1) tan (W / H), sy = ((2 c.y) / H - 1) tan  (as the primary ray)
///     the point P = camera + z d with the unnormalised d = F + sx R - sy U (d . F = 1 for the
///     orthonormal R, U, F: P is at view depth z), in the previous camera's axes:
///     q = o + z (f + sx r - sy u), o = (camera - camera') . (R', -U', F') and f, r, u = F, R, U
///     likewise (dot products once per frame)
///   z' = q.z (> 0, else behind the previous camera), p' = (q.x (a.x / z') + W / 2,
///     q.y (a.y / z') + H / 2) with a = (W / 2 / (tan' W / H), H / 2 / tan')
struct TaaReprojection {
    int width = 0, height = 0;
    float sx_scale = 0.0f, sy_scale = 0.0f;  ///< tan (W / H), tan
    glm::vec3 o{0.0f}, f{0.0f}, r{0.0f}, u{0.0f};
    glm::vec2 a{0.0f};
};
TaaReprojection taa_reprojection(const Camera& camera, float tan_half, const Camera& previous,
                                 float previous_tan_half, int width, int height);

/// Where pixel (x, y) at view depth z (> 0) was in the previous camera's view: its screen point
/// and view depth. False when the point is behind the previous camera.
bool taa_reproject(const TaaReprojection& k, int x, int y, float z, glm::vec2& previous_point,
                   float& previous_depth);
/// The same, the constants made for this one call.
bool taa_reproject(const Camera& camera, float tan_half, const Camera& previous,
                   float previous_tan_half, int width, int height, int x, int y, float z,
                   glm::vec2& previous_point, float& previous_depth);

/// A margin of a decision the pixel did not make (TaaPixelRecord).
inline constexpr float taa_no_margin = 1e30f;

/// What taa_pixel did at a pixel (for counters and `fovref probe`).
struct TaaPixelRecord {
    TaaDecision decision = TaaDecision::first;
    glm::vec2 previous_point{0.0f};  ///< p' (reprojected)
    float previous_depth = 0.0f;     ///< z'
    float history_depth = 0.0f;      ///< z_h
    float age_previous = 0.0f, age = 1.0f;
    glm::vec3 history{0.0f};  ///< the history used (after clamping)
    /// Rejected because the history, its age or depth, or the current depth was not finite.
    bool history_nonfinite = false;
    /// How far the pixel's decisions lay from their thresholds (the `taa_margin` buffer, for
    /// `fovref diff`'s threshold decisions): the depth test's (tau z' - |z' - z_h|) / z' (depth
    /// rejection only), and the reprojected point's distance in pixels from the border of the
    /// region where the history has a tap, (-1/2, W + 1/2) x (-1/2, H + 1/2), negative outside;
    /// taa_no_margin where the pixel made no such decision.
    float depth_margin = taa_no_margin, reprojection_margin = taa_no_margin;
};

/// What every pixel of a frame shares, computed once per pass: the two cameras' tan(vfov / 2),
/// the screen diagonal, whether the camera is stationary.
struct TaaConstants {
    float tan_half = 0.0f, previous_tan_half = 0.0f, diagonal = 0.0f;
    bool stationary = false;
    TaaReprojection reprojection;
};
TaaConstants taa_constants(const TaaInputs& in, const TaaState& previous);

/// Per-pixel work of the pass: pixel (x, y) of `out` (3 channels) and `age`. `constants`: those
/// of this frame (taa_constants), computed here when null. The record carries the margins.
TaaPixelRecord taa_pixel(const TaaParams& params, const TaaInputs& in, const TaaState& previous,
                         int x, int y, Image& out, Image& age,
                         const TaaConstants* constants = nullptr);

/// Counters of one frame's TAA.
struct TaaStats {
    std::int64_t kept = 0, rejected = 0, clamped = 0, periphery_kept = 0;
    std::int64_t reprojection_skipped = 0;  ///< pixels of a stationary camera
    std::int64_t nonfinite_history = 0;     ///< rejected: a non-finite history, age or depth
};

/// The pass: the TAA output (the next frame's history) and the age, W x H; `margin` (when not
/// null): W x H x 2, the record's depth and reprojection margins. `out` and `age` keep their
/// storage when they already have those shapes (a caller recycles the history before last:
/// every pixel is written, so nothing of their old values remains and no zero fill is paid);
/// otherwise they are made anew.
void taa(const TaaParams& params, const TaaInputs& in, const TaaState& previous, Image& out,
         Image& age, TaaStats& stats, Image* margin = nullptr);

/// The state the next frame reads: this frame's output, age, depth and camera.
TaaState next_taa_state(Image out, Image age, const Image& depth, const Camera& camera);

}  // namespace fovref
