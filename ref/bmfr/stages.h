// BMFR's phases as stages (SPEC §9, docs/bmfr.md): one stage per phase, each calling one
// function of ref/bmfr, so every phase's output can be dumped and diffed by name:
//
//   bmfr_demodulate           radiance, albedo [, emission]        -> bmfr_illumination
//   bmfr_accumulate_noisy     + world position, shading normal    -> bmfr_accumulated_noisy,
//                                                                    bmfr_spp, bmfr_accept,
//                                                                    bmfr_previous_pixel
//   bmfr_fit                  accumulated, world, normal          -> bmfr_weights (30 per block),
//                                                                    bmfr_feature_range (12)
//   bmfr_weighted_sum         weights, ranges, world, normal      -> bmfr_fitted
//   bmfr_accumulate_filtered  fitted, spp, accept, previous pixel -> bmfr_accumulated_filtered
//   bmfr_remodulate           filtered, albedo [, emission]       -> bmfr_display
//   bmfr_taa                  display, previous pixel             -> bmfr_taa
//   bmfr_output               bmfr_taa                            -> the output (linear, x^2.2)
//
// In Visual-Polar space (SPEC §9 item 11) the stages that address the buffer also read its
// validity mask. The eight stages share one state: the history carried to the next frame, each
// part written by the stage that computes it and handed on when phase I starts the next frame;
// a frame rendered alone after frame 0 takes it from a dump of the previous frame
// (RenderSettings::state_buffers, `fovref render --resume DIR`).
#pragma once

#include <functional>
#include <string>

#include "ref/bmfr/bmfr.h"
#include "ref/bmfr/bmfr_params.h"
#include "ref/stage/pipeline.h"

namespace fovref {

/// The buffers the BMFR stages are wired to, and the space they run in.
struct BmfrWiring {
    BmfrSettings settings;
    std::string radiance;  ///< the noisy radiance
    std::string emission;  ///< the directly seen emission (read with bmfr_emission=separate)
    std::string output;    ///< the denoised linear image
    std::string gbuffer = "gbuffer_";  ///< the G-buffer's prefix ("vp_gbuffer_")
    /// Visual-Polar space: the validity mask's buffer and the map of a frame; empty: the screen.
    std::string valid;
    std::function<VisualPolarMap(const FrameContext&, int frame)> map;
    /// The view-projection of frame `frame` (empty: view_projection of the frame's camera), for
    /// buffers from another renderer whose matrices are given (`denoise bmfr`).
    std::function<ViewProjection(const FrameContext&, int frame)> view_projection;
    /// Where the frame's samples lie in their pixels (empty: the centres; BmfrParams::
    /// pixel_offset).
    std::function<glm::vec2(const FrameContext&)> pixel_offset;

    /// Screen space, reading the G-buffer gbuffer_*.
    BmfrWiring(BmfrSettings bmfr, std::string radiance_buffer, std::string emission_buffer,
               std::string output_buffer)
        : settings(std::move(bmfr)),
          radiance(std::move(radiance_buffer)),
          emission(std::move(emission_buffer)),
          output(std::move(output_buffer)) {}
};

/// Appends the BMFR stages to `pipeline`.
void add_bmfr_stages(Pipeline& pipeline, const BmfrWiring& wiring);

// The stages (each a named function, so a debugger can break on it).
void bmfr_demodulate_stage(FrameContext& context);
void bmfr_accumulate_noisy_stage(FrameContext& context);
void bmfr_fit_stage(FrameContext& context);
void bmfr_weighted_sum_stage(FrameContext& context);
void bmfr_accumulate_filtered_stage(FrameContext& context);
void bmfr_remodulate_stage(FrameContext& context);
void bmfr_taa_stage(FrameContext& context);
void bmfr_output_stage(FrameContext& context);

/// The per-pixel functions of the BMFR phases (for `probe --debugger`), on the screen
/// (`family` empty) or on the texels of a buffer family ("vp_"); `block_of`: the grid cell of a
/// frame that covers a point (bmfr_screen_block for the screen).
std::vector<PixelFunction> bmfr_pixel_functions(
    const std::string& family,
    std::function<glm::ivec2(const RenderSettings&, int frame, glm::ivec2 point)> block_of);
/// The cell of frame `frame`'s screen grid (bmfr_grid) that covers pixel `point`.
glm::ivec2 bmfr_screen_block(const RenderSettings& settings, int frame, glm::ivec2 point);

/// The bmfr_* counters of a frame (BmfrStats).
void add_bmfr_counters(Counters& counters, const BmfrStats& stats);

}  // namespace fovref
