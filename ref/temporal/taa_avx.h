// The TAA pass eight pixels at a time with AVX2: the same bits as
// taa_pixel, which stays the readable reference (docs/temporal.md, "Benchmark"). It covers every
// frame with a history: a stationary camera (every mode: the history at the pixel) and a moving
// camera (reprojection, the bilinear history and depth, then the depth test and the periphery rule,
// or the clamp to the 3x3 neighbourhood or to the buffer-space boxes). Each lane performs
// taa_pixel's binary32 operations in its order; a tap off the screen adds a selected +0 instead of
// being skipped, which leaves every sum's bits unchanged (a sum that starts at +0 is never -0). The
// taps are gathered (masked gathers: plain loads of the same floats, none for a tap off the
// screen); where every tap of the eight lanes is on the screen and their corners lie side by side
// in one row, the taps' colours and depths are plain loads, and the colours' channels are sorted
// out by blends and permutes (split3_lanes; merge3_lanes writes the output). The previous ages
// are one plain load where they lie side by side, else eight scalar loads (load_lanes).
#pragma once

#include "ref/temporal/taa.h"

namespace fovref {

/// Whether taa_row_avx covers a frame: a valid history, one-channel depths and ages, 3 W H within
/// int32 (W, H at most 2^24), simd_allowed() and a CPU with AVX2.
bool taa_avx_applies(const TaaInputs& in, const TaaState& previous);

/// Pixels 0 .. 8 floor(W / 8) - 1 of row y as taa_pixel computes them: `out`, `age` and (when
/// not null) `margin` written, the decisions counted in `stats`. Returns the pixels done; the
/// caller runs taa_pixel on the rest of the row. Only where taa_avx_applies.
int taa_row_avx(const TaaParams& params, const TaaInputs& in, const TaaState& previous,
                const TaaConstants& k, int y, Image& out, Image& age, Image* margin,
                TaaStats& stats);

/// Whether texel_boxes_row_avx covers a box pass (clamp-buffer's 3x3 boxes of traced texels,
/// taa_foveated.h): a 3-channel image and a one-channel mask of its size, at least 10 columns
/// wide, simd_allowed() and a CPU with AVX2.
bool texel_boxes_avx_applies(const Image& image, const Image& valid);

/// The channels of a texel's record in the box pass's output (taa_foveated.cpp): its box (min r,
/// g, b, max r, g, b), then its view depth and its traced mask, so that a pixel finds all it
/// reads of its source in one 32-byte record.
constexpr int taa_record_channels = 8;

/// The boxes of texels 1 .. 8 k of row sj (k = floor((W - 2) / 8): every tap of theirs lies
/// inside the row's columns, none clamped) into floats 0 .. 5 of their records (`records`: the
/// row's W records of taa_record_channels floats; float 6 of each of those texels is
/// overwritten, the caller writes it after), as the reference's per-texel box computes them: each
/// lane starts from its texel, then takes the min and max with each traced tap in the reference's
/// order (rows sj - 1, sj, sj + 1, wrapped or clamped as the reference does; columns -1, 0, +1),
/// as std::min and std::max do. With `traced_only`, a group of eight whose texels are all
/// untraced is skipped (its boxes left as they were: the log-polar buffer's, which no pixel reads
/// there). Returns 1 + 8 k, the first column left to the reference. Only where
/// texel_boxes_avx_applies.
int texel_boxes_row_avx(const Image& image, const Image& valid, bool wrap_rows, bool traced_only,
                        int sj, float* records);

}  // namespace fovref
