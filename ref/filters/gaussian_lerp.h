// Lund's Gaussian lerp (Lund §3.5; SPEC §6): a screen-space filter after pass 2 that blends each
// pixel with a 3x3 Gaussian of its neighbourhood, more so farther from the gaze point.
//
//   for each screen pixel (x, y), row by row:   gaussian_lerp_pixel(x, y)
//     c = (x + 1/2, y + 1/2), D = sqrt(W^2 + H^2), R_c = the largest gaze-to-corner distance
//     t = clamp((|c - g| - D/6) / (R_c - D/6), 0, 1)      (choice: Lund gives only the start D/6)
//     G = sum_{dy, dx in -1..1} k(dx, dy) I(clamp(x + dx), clamp(y + dy)) / 16,
//         k = [1 2 1; 2 4 2; 1 2 1], summed row by row (dy = -1 first), left to right, in binary32,
//         neighbours clamped to the screen
//     out = I where t = 0 (G is not computed there), else lerp(I, G, t) = I + t (G - I), per
//     channel
// R_c >= D/2 for any gaze point, so R_c - D/6 > 0.
#pragma once

#include <glm/glm.hpp>

#include "ref/image/image.h"

namespace fovref {

/// The ramp's constants for a W x H screen and gaze: D/6 and R_c - D/6 (computed once a pass).
struct LerpRamp {
    float start = 0.0f;  ///< D / 6
    float span = 0.0f;   ///< R_c - D / 6
};
LerpRamp gaussian_lerp_ramp(int width, int height, glm::vec2 gaze);

/// Per-pixel work of the filter: pixel (x, y) of `out` from `in` (`ramp`: for in's size and
/// `gaze`).
void gaussian_lerp_pixel(const Image& in, glm::vec2 gaze, const LerpRamp& ramp, Image& out, int x,
                         int y);

/// The filter: an image of `in`'s size and channels. `storage`: an image the output is written into
/// when it has the output's shape (a stage recycles an earlier frame's): every pixel is written,
/// none of its values is read; otherwise the output is made anew.
Image gaussian_lerp(const Image& in, glm::vec2 gaze, Image storage = {});

/// t of the blend at screen point p (0: unfiltered, 1: the full 3x3 Gaussian).
float gaussian_lerp_amount(const LerpRamp& ramp, glm::vec2 gaze, glm::vec2 p);

/// The 3x3 Gaussian [1 2 1; 2 4 2; 1 2 1] / 16 of channel c around pixel (x, y), neighbours
/// clamped to the image (also Meng's internal anti-aliasing kernel, SPEC §6).
float gaussian3x3_clamped(const Image& in, int x, int y, int c);

}  // namespace fovref
