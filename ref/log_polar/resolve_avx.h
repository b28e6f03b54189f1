// Pass 2's bilinear resolve eight screen pixels at a time with AVX2: the same bits as
// resolve_pixel, which stays the readable reference (docs/foveation.md, "The screen passes made
// faster"). Each lane computes lp_bilinear_index from the forward table's (u, v) and, where all
// four taps are traced (most pixels), sample_lp_bilinear's two lerps in u and the lerp in v in
// their order; the taps' values and validity are gathered (AVX2 gathers: plain loads). A lane
// with an untraced tap, and every group that straddles the gaze circle's edge, runs the
// reference; a group inside the circle copies its 8 pixels from the gaze buffer as gaze_pixel
// does.
#pragma once

#include "ref/log_polar/mip_resolve.h"
#include "ref/log_polar/resolve.h"

namespace fovref {

/// Whether resolve_row_avx covers a resolve: a forward table, a 3-channel buffer at least 3
/// rows high (3 w h within int32, w and h at most 2^24) and a one-channel mask of the map's size,
/// simd_allowed() and AVX2.
bool resolve_avx_applies(const LogPolarMap& map, const ResolveInputs& in,
                         const ForwardTable* table);

/// Pixels 0 .. 8 floor(W / 8) - 1 of screen row y as resolve_pixel computes them (the counters
/// in `stats`); returns the pixels done. Only where resolve_avx_applies.
int resolve_row_avx(const LogPolarMap& map, const ResolveInputs& in, const ForwardTable& table,
                    Image& out, int y, ResolveStats& stats);

/// Whether resolve_mip_row_avx covers a mip resolve: a forward table made for the pyramid,
/// 3-channel levels with one-channel masks of their size (level 0 the map's, 3 w h within int32,
/// w and h at most 2^24), simd_allowed() and AVX2.
bool resolve_mip_avx_applies(const LogPolarMap& map, const std::vector<MipLevel>& mips,
                             const ForwardTable* table);

/// Pixels 0 .. 8 floor(W / 8) - 1 of screen row y as resolve_mip_pixel computes them, eight at a
/// time: each lane samples its level l0 and, where resolve_mip_pixel does, l1 (the lanes of one
/// level together, the level's taps gathered), and lerps them in its order. A lane with an
/// untraced tap, a level fewer than 3 rows high, or a group straddling the gaze circle's edge
/// runs the reference. Returns the pixels done. Only where resolve_mip_avx_applies.
int resolve_mip_row_avx(const LogPolarMap& map, const std::vector<MipLevel>& mips,
                        const GazeInput& gaze, const ForwardTable& table, Image& out, int y,
                        ResolveStats& stats);

}  // namespace fovref
