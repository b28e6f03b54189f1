// Meng's internal anti-aliasing (Meng 2018 §2.2.3; SPEC §6): a buffer-space filter on the shaded
// log-polar buffer before pass 2, on its peripheral half only, where one texel covers many
// screen pixels.
//
//   for each texel (i, j), row by row:   internal_aa_texel(x = i, y = j)
//     untraced texel, or i < w/2 (2 i < w): unchanged
//     otherwise sum k(dx, dy) c(i + dx, j + dy) over dy, dx in -1..1 (row by row, dy = -1 first,
//       left to right) and over traced neighbours only, k = [1 2 1; 2 4 2; 1 2 1]; the column
//       clamped to [0, w - 1], the row wrapped modulo h; divided by the sum of the weights used
//     binary32 throughout.
#pragma once

#include "ref/image/image.h"

namespace fovref {

/// Per-texel work of the filter: texel (x, y) of `out`.
void internal_aa_texel(const Image& color, const Image& valid, Image& out, int x, int y);

/// The filter: an image of `color`'s size and channels.
Image internal_aa(const Image& color, const Image& valid);

}  // namespace fovref
