// What the TAA pass of a log-polar mode reads from the buffers (SPEC §7): the current view depth
// of each screen pixel, and for clamp-buffer the neighbourhood bounds taken in the buffer's own
// space. Both start from the texel that pass 2 sampled for the pixel (taa_source):
//
//   pixel centre inside the gaze circle (composite modes): the gaze buffer's pixel
//   otherwise (u, v) = the forward map of the centre (pass 2's ForwardTable), the four bilinear
//     taps of sample_lp_bilinear, and of the traced ones the nearest: the largest bilinear
//     weight ((1 - fu)(1 - fv), fu (1 - fv), (1 - fu) fv, fu fv), ties to the first in that
//     order; no traced tap with a non-zero weight: none (depth 0, bounds of the pixel itself)
//
// taa_source_pass, one pass over the screen (the stage taa_source):
//   depth:  the source's view depth (never interpolated across edges), 0 for none
//   bounds: (clamp-buffer) per channel the min and max over the source's 3x3 neighbourhood of
//           traced texels (columns clamped, rows wrapped: the angle axis) or of traced
//           gaze-buffer pixels (clamped to its window), the texel itself included, widened to
//           hold the pixel's own pass-2 value (a mip resolve can lie outside the level-0 box);
//           no source: the pass-2 value alone. The boxes are made once per texel, as a GPU's
//           buffer-space min/max pass would, and read by the pixels; in the log-polar buffer only
//           the traced texels' (a pixel's source there is always traced), so the off-screen and
//           gaze-circle texels cost nothing. Each texel's box, depth and mask are kept together
//           in one 32-byte record (texel_records), so that a pixel's source costs one cache line.
#pragma once

#include <array>

#include <cstdint>
#include <vector>

#include "ref/log_polar/resolve.h"

namespace fovref {

struct TaaSource {
    enum class Kind { none, gaze, buffer };
    Kind kind = Kind::none;
    int i = 0, j = 0;  ///< the texel (buffer) or the gaze buffer's pixel (gaze)
};

/// The buffers a log-polar frame's TAA reads from (the gaze ones null without a gaze buffer).
struct TaaBufferInputs {
    const LogPolarMap& map;
    const ForwardTable& forward;  ///< made for `map`
    const Image& lp_valid;
    const Image* gaze_valid = nullptr;  ///< covers gaze_window(map)
};

/// The texel or gaze pixel pass 2 sampled for screen pixel (x, y), as above.
TaaSource taa_source(const TaaBufferInputs& in, int x, int y);

/// The colours the clamp boxes come from (clamp-buffer).
struct TaaBoxColors {
    const Image& lp_color;      ///< the buffer pass 2 read
    const Image* gaze_color;    ///< the gaze buffer (null without one)
    const Image& screen_color;  ///< pass 2's output (pixels without a source)
};

struct TaaSourceOutputs {
    Image depth;   ///< W x H: the view depth (0: no surface or no source)
    Image bounds;  ///< W x H x 6: min r, g, b, max r, g, b (empty without `colors`)
};

/// What taa_source reads from the map alone, per screen pixel, so that a frame only looks up
/// the validity of a few texels: kept by a stage while the map repeats (a static gaze; TAA's
/// jitter moves the texels and so the mask, not the map). The same sources as taa_source.
/// Per screen pixel p (W x H, row-major): the buffer texels (j w + i) of the bilinear taps with a
/// non-zero weight, the largest weight first (ties: the tap order); the source is the first
/// traced one. They are stored apart, so that a frame reads five bytes a pixel where the first
/// tap is traced (most pixels): count[p] taps, the first in first[p], the others in rest[p].
/// count[p] = -1: the gaze buffer's pixel, first[p] its row-major index in the gaze buffer.
struct TaaSourceTable {
    LogPolarMap map;
    bool gaze = false;  ///< made with a gaze buffer
    std::vector<std::int8_t> count;
    std::vector<std::int32_t> first;
    std::vector<std::array<std::int32_t, 3>> rest;
};
/// The table of `in` (its map and forward table; whether it has a gaze buffer).
TaaSourceTable taa_source_table(const TaaBufferInputs& in);
/// Whether `table` was made for `in`'s map and gaze buffer.
bool taa_source_table_fits(const TaaSourceTable& table, const TaaBufferInputs& in);

/// The pass: every pixel's source, its depth and, with `colors`, its clamp box. `table` (made
/// for `in`: taa_source_table) replaces the per-pixel taa_source: the same sources. `storage`:
/// images the outputs are written into when they have the outputs' shapes (W x H x 1, W x H x 6;
/// a stage recycles an earlier frame's): every value is written, none of theirs is read;
/// otherwise the outputs are made anew. Throws fovref::Error when a depth is not one channel of
/// its mask's size or a colour is not RGB of its mask's (the buffers) or the screen's size (pass
/// 2's output).
TaaSourceOutputs taa_source_pass(const TaaBufferInputs& in, const Image& lp_depth,
                                 const Image* gaze_depth, const TaaBoxColors* colors = nullptr,
                                 const TaaSourceTable* table = nullptr,
                                 TaaSourceOutputs storage = {});

}  // namespace fovref
