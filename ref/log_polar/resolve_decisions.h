// The threshold decisions of pass 2, and how far the oracle lies from each threshold, for
// diffing a port whose arithmetic differs by a few ulp (docs/diff.md, "Threshold decisions";
// docs/foveation.md, "Pass 2's decisions"). Written beside the resolve's image; they change no
// pixel.
//
// For each screen pixel pass 2 reads from the buffer, with (u, v) its forward-mapped centre:
//   level    the level the lookup reads first: l0 = floor(clamp(lambda, 0, levels - 1)) with
//            the mip resolve's lambda (mip_resolve.h), 0 for the bilinear resolve;
//   tap      (i0, j0), the first tap of the bilinear lookup at level l0, at (u, v) / 2^l0 in that
//            level's w_l x h_l texels (lp_bilinear_index): i0 = floor(clamp(s, 0, w_l - 1)) with
//            s = u / 2^l0 - 1/2, and j0 = floor(t) wrapped with t = v / 2^l0 - 1/2.
// Their margins, in the units of the value each decision rounds:
//   tap_margin   the smaller of s's distance from the nearest integer in [1, w_l - 1] (where i0
//                changes; u is clamped below 1 and above w_l - 1) and t's distance from the
//                nearest integer (the rows wrap, every integer is a threshold), in level-l0
//                texels;
//   level_margin the unclamped lambda's distance from the nearest integer in [1, levels - 1],
//                in levels.
// A pixel from the gaze buffer has tap (-1, -1) and level -1 and margins no_threshold: whether a
// pixel lies in the gaze circle is another decision, which these margins do not cover.
// Stereo (stereo_resolve_decisions): each pixel's lookup in its eye's half, bilinear; the tap's
// column is the side-by-side buffer's (e w + i0); a pixel whose barrel source leaves the eye's
// image has tap (-1, -1) and margin no_threshold (the lens test is not covered either).
#pragma once

#include "ref/image/image.h"
#include "ref/log_polar/resolve.h"
#include "ref/log_polar/stereo.h"

namespace fovref {

/// A margin where a decision has no threshold nearby (finite, so images stay finite).
constexpr float no_threshold = 1e30f;

/// The distance of x from the nearest integer k in [lo, hi], the points where floor(clamp(x, lo -
/// 1, hi)) changes; no_threshold when lo > hi or x is not finite.
float floor_margin(float x, int lo, int hi);
/// The distance of x from the nearest integer (a wrapped index changes at every integer);
/// no_threshold when x is not finite.
float wrap_margin(float x);

/// The first tap (i0, j0) of the bilinear lookup at uv in a width x height buffer
/// (lp_bilinear_index), and its margin: the smaller of s = u - 1/2's distance from the nearest
/// integer in [1, width - 1] and t = v - 1/2's from the nearest integer.
struct TapDecision {
    int i0 = 0, j0 = 0;
    float margin = no_threshold;
};
TapDecision lp_tap_decision(glm::vec2 uv, int width, int height);

/// Pass 2's decisions, screen-sized images. The mip level's are empty for a resolve without mips.
struct ResolveDecisions {
    Image tap;         ///< 2 channels: i0, j0 (-1 where no buffer is read)
    Image tap_margin;  ///< 1 channel, texels of the level read
    Image mip_level;   ///< 1 channel (log-polar) or 2 (Visual-Polar: columns i0 and i1); -1: none
    Image mip_margin;  ///< 1 channel, levels
};

/// The decisions of pass 2 for the map of `table` (its forward map and, with mip_levels > 0,
/// the mip resolve's levels) over a width x height buffer and `gaze`.
ResolveDecisions lp_resolve_decisions(const ForwardTable& table, const GazeInput& gaze, int width,
                                      int height);

/// The decisions of the stereo pass 2 (no mips) for the lookups of `table` over a side-by-side
/// buffer of width x height texels (each eye width / 2 wide).
ResolveDecisions stereo_resolve_decisions(const StereoForwardTable& table, int width, int height);

}  // namespace fovref
