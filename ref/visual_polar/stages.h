// The Visual-Polar family's passes as stages (Koskela P3-P5; SPEC §5.3-5.5, §6;
// docs/visual-polar.md). Each is declared by a *_stage_def function and runs as the plain
// function beside it:
//
//   vp_trace           (nothing)        -> vp_gbuffer_*, vp_valid, vp_screen_point
//   resolve            vp_color, vp_valid -> the φ-mip (or bilinear) resolve to the screen and
//                      its decisions (resolve_tap, ...: ref/visual_polar/resolve_decisions.h)
//   falloff_mask       (nothing)        -> sample_mask: the pixels linear fall-off traces
//   fill               sparse_radiance [, sparse_emission], sample_mask -> push-pull (or black)
//   acuity_trace       (nothing)        -> acuity_gbuffer_*, acuity_valid, acuity_point (N x 1)
//   acuity_accumulate  acuity_point, acuity_valid, acuity_radiance -> acuity_sum, acuity_count
//   acuity_resolve     acuity_sum, acuity_count -> final
//
// The shading and path tracing are trace's stages (ref/trace/stages.h), the blur ramp the
// filters' (ref/filters/stages.h), BMFR in Visual-Polar space ref/bmfr/stages.h.
//
// Counters (names read by scripts): buffer_width, buffer_height, fovea_columns, texels_traced,
// texels_clipped, texels_off_screen, pixels_sampled, pixels_unsampled, samples, samples_traced,
// samples_off_screen, pixels_without_sample, screen_pixels_untraced_taps, and the traversal
// counters.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "ref/bvh/bvh_cache.h"
#include "ref/filters/blur_ramp.h"
#include "ref/stage/pipeline.h"
#include "ref/visual_polar/params.h"
#include "ref/visual_polar/resolve.h"
#include "ref/visual_polar/resolve_avx.h"
#include "ref/visual_polar/trace.h"

namespace fovref {

/// What the stages of one sparse mode (visual-polar, visual-polar-basic, linear-falloff, acuity)
/// share: the mode's parameters (parsed once) and pass 2's polar coordinates, kept while the
/// map stays the same (a static gaze).
struct SparseFrames {
    SparseParams params;
    std::optional<VpForwardTable> forward;
    /// The trace's texel statuses and points (not under `--scalar`), made for the frame's forward
    /// map and kept while it stays the same (VisualPolarMap::same_forward).
    std::optional<VpTexelTable> texels;
    /// The resolve's packed pyramid, its storage kept from frame to frame.
    VpResolveAvxInputs packed;
    /// The Visual-Polar map of frame `frame` (the screen of `context`).
    VisualPolarMap map(const FrameContext& context, int frame) const;
};

/// The shared frames of the sparse mode `mode`, its parameters parsed from `params`.
std::shared_ptr<SparseFrames> sparse_frames(const Params& params, const std::string& mode);

/// The frame's blur-ramp geometry (the map's gaze and scale; the filters' blur stages).
std::function<BlurRampGeometry(const FrameContext&)> blur_geometry_of(
    std::shared_ptr<SparseFrames> frames);

StageDef vp_trace_stage_def(std::shared_ptr<SparseFrames> frames, std::shared_ptr<BvhCache> bvh);
void vp_trace_stage(FrameContext& context);
/// Pass 2 of vp_color over vp_valid, to `output`.
StageDef vp_resolve_stage_def(std::shared_ptr<SparseFrames> frames, std::string output);
void vp_resolve_stage(FrameContext& context);

StageDef falloff_mask_stage_def(std::shared_ptr<SparseFrames> frames);
void falloff_mask_stage(FrameContext& context);
/// The fill of the sparse radiance (and with `emission` the sparse emission) to `output`
/// (`emission_output`).
StageDef fill_stage_def(std::shared_ptr<SparseFrames> frames, std::string output, bool emission);
void fill_stage(FrameContext& context);

StageDef acuity_trace_stage_def(std::shared_ptr<SparseFrames> frames,
                                std::shared_ptr<BvhCache> bvh);
void acuity_trace_stage(FrameContext& context);
StageDef acuity_accumulate_stage_def(std::shared_ptr<SparseFrames> frames);
void acuity_accumulate_stage(FrameContext& context);
StageDef acuity_resolve_stage_def(std::shared_ptr<SparseFrames> frames);
void acuity_resolve_stage(FrameContext& context);

}  // namespace fovref
