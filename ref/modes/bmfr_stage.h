// The BMFR stages of the path-traced modes (SPEC §9, docs/bmfr.md): one stage per phase, each
// calling one function of ref/bmfr, so every phase's output can be dumped and diffed by name:
//
//   bmfr_demodulate           radiance, gbuffer_albedo, emission  -> bmfr_illumination
//   bmfr_accumulate_noisy     + world position, shading normal    -> bmfr_accumulated_noisy,
//                                                                    bmfr_spp, bmfr_accept,
//                                                                    bmfr_previous_pixel
//   bmfr_fit                  accumulated, world, normal          -> bmfr_weights (30 per block),
//                                                                    bmfr_feature_range (12)
//   bmfr_weighted_sum         weights, ranges, world, normal      -> bmfr_fitted
//   bmfr_accumulate_filtered  fitted, spp, accept, previous pixel -> bmfr_accumulated_filtered
//   bmfr_remodulate           filtered, gbuffer_albedo, emission  -> bmfr_display
//   bmfr_taa                  display, previous pixel             -> bmfr_taa
//   bmfr_output               bmfr_taa                            -> final (linear, x^2.2)
//
// The state carried to the next frame (the history) is written by the stage that computes each
// part of it; a frame rendered alone after frame 0 takes it from a dump of the previous frame
// (RenderSettings::state_buffers, `fovref render --resume DIR`).
#pragma once

#include <functional>
#include <string>

#include "ref/bmfr/bmfr.h"
#include "ref/bmfr/bmfr_params.h"
#include "ref/modes/taa_stage.h"
#include "ref/stage/pipeline.h"

namespace fovref {

/// The state of a mode that can run BMFR (derived from the TAA state so that one mode state
/// serves both stages).
struct BmfrModeState : TaaModeState {
    BmfrSettings bmfr;
    BmfrHistory bmfr_history;               ///< what the previous frame handed on
    BmfrHistory bmfr_next;                  ///< what this frame hands on (filled by the stages)
    int bmfr_frame = -1;                    ///< the frame bmfr_next belongs to
    std::string bmfr_radiance;              ///< the noisy radiance buffer (set by add_bmfr_stages)
    std::string bmfr_emission;              ///< the directly seen emission (kept out of the fit)
    std::string bmfr_output;                ///< the denoised linear image
    std::string bmfr_gbuffer = "gbuffer_";  ///< the G-buffer's prefix ("vp_gbuffer_")
    /// Visual-Polar space (SPEC §9 item 11): the validity mask's buffer and the map of a frame;
    /// empty: screen space.
    std::string bmfr_valid;
    std::function<VisualPolarMap(const FrameContext&, int frame)> bmfr_map;
};

/// Adds the BMFR stages, reading `radiance`, `emission` (bmfr_emission=separate) and the
/// G-buffer (state.bmfr_gbuffer; state.bmfr_valid and bmfr_map for Visual-Polar space), writing
/// `output`. state.bmfr must be set.
void add_bmfr_stages(Pipeline& pipeline, BmfrModeState& state, const std::string& radiance,
                     const std::string& emission, const std::string& output);

/// The bmfr_* counters of a frame (BmfrStats).
void add_bmfr_counters(Counters& counters, const BmfrStats& stats);

/// Adds every buffer of a denoised frame under the stages' names and kinds (bmfr_illumination …
/// bmfr_taa, and `output` for the linear result): what `fovref denoise bmfr` writes.
void add_bmfr_buffers(FrameResult& frame, BmfrFrame denoised, const std::string& output);

}  // namespace fovref
