// The TAA stage of basic and the log-polar modes (SPEC §6-7, docs/temporal.md): one stage after
// pass 2, before the screen-space filters, wired by each mode's pipeline. The state carried from
// frame to frame (the history, its age, the previous depth and camera) lives in the mode's state;
// the first frame rendered of a sequence that does not start at frame 0 takes it from the
// previous frame's dumped buffers (RenderSettings::state_buffers, `fovref render --resume DIR`).
//
// Counters of every frame with TAA on (names read by scripts): taa_history_kept,
// taa_history_rejected, taa_history_clamped, taa_periphery_kept, taa_reprojection_skipped
// (pixels of a stationary camera: no reprojection work), taa_history_nonfinite,
// taa_jitter_index (the Halton point used, -1: none, the camera moved).
#pragma once

#include <string>

#include "ref/stage/pipeline.h"
#include "ref/stage/probe.h"
#include "ref/temporal/taa.h"
#include "ref/temporal/taa_params.h"

namespace fovref {

/// The part of a mode's state that TAA uses; the modes' states derive from it.
struct TaaModeState : ModeState {
    TaaSettings taa;
    TaaState history;  ///< what the previous frame handed on (invalid before the first frame)
    /// The buffers the stage reads and writes (set by the pipeline builder).
    std::string color_input;   ///< pass 2's output
    std::string depth_input;   ///< the current view depth of each screen pixel
    std::string bounds_input;  ///< clamp-buffer: the W x H x 6 bounds ("" otherwise)
    std::string output;        ///< the TAA output, the next frame's history ("final" if last)
    /// The gaze of a frame (the periphery rule); null: the screen centre.
    glm::vec2 (*gaze)(const FrameContext& context) = nullptr;
};

/// The launch offset of this frame's rays (taa_jitter: none without TAA or while the camera
/// moves).
Offset2 frame_jitter(const FrameContext& context);

void taa_stage(FrameContext& context);

/// The TAA state of the frame before the first one rendered (frame > 0), from
/// RenderSettings::state_buffers: `output` (the TAA output), taa_age and `depth`, with the
/// previous camera. Throws fovref::Error naming --resume when a buffer is missing or misshapen.
TaaState resumed_taa_state(const FrameContext& context, const std::string& output,
                           const std::string& depth);

/// The taa_* counters of a frame (TaaStats and the jitter index).
void add_taa_counters(FrameContext& context, const TaaStats& stats);

/// The probe's context with the frame's TAA jitter (ProbeContext::jitter).
ProbeContext probe_at_jitter(const ProbeContext& context);

/// `fovref probe` of a mode with a TAA stage: `explain` at the frame's TAA jitter, then (a pixel
/// of a frame whose TAA ran) the [taa] section; `gaze` is the frame's gaze (the periphery rule).
void explain_with_taa(const ProbeContext& context, ProbeReport& report,
                      void (*explain)(const ProbeContext&, ProbeReport&), glm::vec2 gaze);

/// Adds the TAA stage to `pipeline`, reading `color` and `depth` (and `bounds` when not empty),
/// writing `output` and taa_age; records the wiring in `state`.
void add_taa_stage(Pipeline& pipeline, TaaModeState& state, const std::string& color,
                   const std::string& depth, const std::string& bounds, const std::string& output);

}  // namespace fovref
