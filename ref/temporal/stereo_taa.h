// TAA of Gupta's stereo-lp (docs/temporal.md, "Stereo"): each eye's W/2 x H half of the screen
// on its own, as a frame of its own (its camera, its gaze, its log-polar map, its history), then
// the halves side by side.
//
//   taa_source   lp_gbuffer_view_depth, lp_valid, lp_color, resolved -> taa_view_depth
//                [, taa_bounds]: per eye, the texel pass 2 sampled (taa_source_pass)
//   taa          resolved, taa_view_depth [, taa_bounds] -> final, taa_age: per eye, the taa
//                pass with that eye's camera, gaze and history
#pragma once

#include "ref/log_polar/stages.h"
#include "ref/stage/pipeline.h"
#include "ref/stage/probe.h"
#include "ref/temporal/taa_params.h"

namespace fovref {

StageDef stereo_taa_source_stage_def(const StereoStage& shared, const TaaSettings& taa);
void stereo_taa_source_stage(FrameContext& context);

StageDef stereo_taa_stage_def(const StereoStage& shared, const TaaSettings& taa);
void stereo_taa_stage(FrameContext& context);

/// `fovref probe` of stereo-lp: the ray generation at the frame's jitter (explain_stereo), then
/// the TAA of the pixel's eye, explained on that eye's half of the screen (its camera, gaze and
/// history).
void explain_stereo_taa(const ProbeContext& context, ProbeReport& report);

}  // namespace fovref
