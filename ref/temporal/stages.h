// The TAA pass as stages (SPEC §6-7, docs/temporal.md): one stage after pass 2, before the
// screen-space filters. The stage owns what it carries from frame to frame (the history, its
// age, the previous depth and camera); the first frame rendered of a sequence that does not
// start at frame 0 takes it from the previous frame's dumped buffers
// (RenderSettings::state_buffers, `fovref render --resume DIR`).
//
//   taa          color, depth [, bounds] -> output, taa_age          (basic, the log-polar modes)
//   taa_source   lp_gbuffer_view_depth, lp_valid [, the gaze buffer's] [, clamp-buffer's colours]
//                -> taa_view_depth [, taa_bounds]: the texel pass 2 sampled (taa_foveated.h)
//   stereo-lp's per-eye TAA: ref/temporal/stereo_taa.h
//
// Counters of every frame with TAA on (names read by scripts): taa_history_kept,
// taa_history_rejected, taa_history_clamped, taa_periphery_kept, taa_reprojection_skipped
// (pixels of a stationary camera: no reprojection work), taa_history_nonfinite,
// taa_jitter_index (the Halton point used, -1: none, the camera moved).
#pragma once

#include <functional>
#include <string>

#include "ref/log_polar/stages.h"
#include "ref/stage/pipeline.h"
#include "ref/stage/probe.h"
#include "ref/temporal/taa.h"
#include "ref/temporal/taa_params.h"
#include "ref/trace/stages.h"

namespace fovref {

/// The frame's launch offset of the primary rays under `taa` (taa_jitter: the centre without
/// TAA or while the camera moves), for the ray-generation stages.
FrameJitter taa_frame_jitter(const TaaSettings& taa);

/// The buffers the TAA stage is wired to.
struct TaaPorts {
    std::string color;   ///< pass 2's output
    std::string depth;   ///< the current view depth of each screen pixel
    std::string bounds;  ///< clamp-buffer: the W x H x 6 bounds ("" otherwise)
    std::string output;  ///< the TAA output, the next frame's history ("final" if last)
};

/// The TAA stage; `gaze` gives the frame's gaze for the periphery rule (empty: the screen
/// centre).
StageDef taa_stage_def(const TaaSettings& taa, const TaaPorts& ports,
                       std::function<glm::vec2(const FrameContext&)> gaze = {});
void taa_stage(FrameContext& context);

/// The log-polar modes' taa_source stage: reads the buffers pass 2 read (`lp_color`: lp_color or
/// lp_color_aa; `resolved`: pass 2's output) and writes taa_view_depth (not for kfr, whose TAA
/// reads its full-resolution G-buffer's depth) and, for clamp-buffer, taa_bounds.
StageDef taa_source_stage_def(const LogPolarStage& shared, const TaaSettings& taa,
                              const std::string& lp_color, const std::string& resolved);
void taa_source_stage(FrameContext& context);

/// The TAA state of the frame before the first one rendered (frame > 0), from
/// RenderSettings::state_buffers: `output` (the TAA output), taa_age and `depth`, with the
/// previous camera. Throws fovref::Error naming --resume when a buffer is missing or misshapen.
TaaState resumed_taa_state(const FrameContext& context, const std::string& output,
                           const std::string& depth);

/// The taa_* counters of a frame (TaaStats and the jitter index).
void add_taa_counters(FrameContext& context, const TaaSettings& taa, const TaaStats& stats);

/// The probe's context with the frame's TAA jitter (ProbeContext::jitter).
ProbeContext probe_at_jitter(const ProbeContext& context);

/// `fovref probe` of a mode with a TAA stage: `explain` at the frame's TAA jitter, then (a pixel
/// of a frame whose TAA ran) the [taa] section; `gaze` is the frame's gaze (the periphery rule).
void explain_with_taa(const ProbeContext& context, ProbeReport& report,
                      void (*explain)(const ProbeContext&, ProbeReport&), glm::vec2 gaze);

}  // namespace fovref
