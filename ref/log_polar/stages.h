// The log-polar family's passes as stages (Lund §3.3, Meng ch. 2, Gupta §2; SPEC §5.1-5.2, §6;
// docs/foveation.md). Each is declared by a *_stage_def function (its ports and state) and runs
// as the plain function beside it:
//
// clang-format off
//   lp_trace       (nothing)            -> lp_gbuffer_*, lp_valid, lp_screen_point: one ray per
//                                          log-polar texel through its inverse-mapped point
//   lp_sample      gbuffer_* (screen)   -> the same outputs: each texel copies the rasterized
//                                          pixel under its screen point (Meng's deferred KFR)
//   gaze_trace     (nothing)            -> gaze_gbuffer_*, gaze_valid: one ray per pixel centre
//                                          inside the gaze circle (composite modes)
//   resolve        color, valid [, gaze] -> pass 2 (bilinear or mip) to the screen, and its
//                                          decisions: resolve_tap, resolve_tap_margin (mip:
//                                          resolve_mip_level, resolve_mip_margin)
//   ray_positions  valid, screen_point [, gaze_valid] -> rays per screen pixel (Lund Fig. 3.3)
//                                          and ray_pixel, the pixel each texel counts in
//   stereo_trace, stereo_resolve, stereo_ray_positions: the same for Gupta's two eyes side by
//                                          side
// clang-format on
//
// The shading of the buffers is trace's shade stage (ref/trace/stages.h); the gaze buffer's is
// given its window on the screen by gaze_window_of.
//
// Counters (names read by scripts): buffer_width, buffer_height, texels_traced,
// texels_off_screen (texels_inside_gaze when not 0), gaze_radius_px (rounded), gaze_pixels_traced,
// gaze_window_x0, gaze_window_y0 (the screen pixel of the gaze buffer's pixel (0, 0)),
// rays_primary and the other traversal counters, screen_pixels_untraced_taps; stereo adds eyes
// and, with barrel distortion, screen_pixels_outside_lens.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>

#include "ref/bvh/bvh_cache.h"
#include "ref/log_polar/params.h"
#include "ref/log_polar/resolve.h"
#include "ref/log_polar/resolve_decisions.h"
#include "ref/log_polar/stereo.h"
#include "ref/stage/pipeline.h"
#include "ref/trace/stages.h"

namespace fovref {

/// What the stages of one log-polar mode share: its parameters (parsed once) and pass 2's
/// forward table, made again only when the map changes (a moving gaze), as a GPU renderer keeps
/// such a table.
struct LogPolarFrames {
    FoveatedParams params;
    std::optional<ForwardTable> forward;
    /// The frame's map (foveated_map: the screen, the frame's gaze, the display model).
    LogPolarMap map(const FrameContext& context) const;
    /// The forward table of `map` with `mip_levels` levels; `reused` (optional) tells whether
    /// the table already held was kept.
    const ForwardTable& forward_table(const LogPolarMap& map, int mip_levels,
                                      bool* reused = nullptr);
};

/// What every log-polar stage holds: the mode's shared frames, the render's BVH and the frame's
/// TAA jitter (empty: none).
struct LogPolarStage {
    std::shared_ptr<LogPolarFrames> frames;
    std::shared_ptr<BvhCache> bvh;
    FrameJitter jitter;
};

StageDef lp_trace_stage_def(const LogPolarStage& shared);
void lp_trace_stage(FrameContext& context);
/// Meng's deferred variant: every texel samples the rasterized screen G-buffer (gbuffer_*) at
/// its screen point; the TAA jitter is applied after the inverse transform.
StageDef lp_sample_stage_def(const LogPolarStage& shared);
void lp_sample_stage(FrameContext& context);
StageDef gaze_trace_stage_def(const LogPolarStage& shared);
void gaze_trace_stage(FrameContext& context);
/// Pass 2 from `color` (lp_color, or lp_color_aa after the internal AA) and, in the composite
/// modes, gaze_color, to `output`.
StageDef resolve_stage_def(const LogPolarStage& shared, std::string color, std::string output);
void resolve_stage(FrameContext& context);
StageDef ray_positions_stage_def(const LogPolarStage& shared);
void ray_positions_stage(FrameContext& context);

/// A resolve stage's decision outputs (ref/log_polar/resolve_decisions.h), slots tap,
/// tap_margin and, with `mip`, mip_level, mip_margin, wired to the buffers resolve_<slot>.
std::vector<Port> resolve_decision_ports(bool mip);
/// Adds a resolve stage's decisions as its outputs (the mip level's when it has them).
void output_resolve_decisions(const FrameContext& context, ResolveDecisions decisions);
/// True when one of the running resolve stage's decision buffers is wanted: they cost about as
/// much as pass 2 itself, so a frame that wants none leaves them out.
bool wants_resolve_decisions(const FrameContext& context);

/// The gaze buffer's window on the screen in a frame (the gaze shading's ShadeView::window).
std::function<ScreenWindow(const FrameContext&)> gaze_window_of(
    std::shared_ptr<LogPolarFrames> frames);
/// The frame's gaze point (for TAA's periphery rule and the screen filters).
std::function<glm::vec2(const FrameContext&)> gaze_of(std::shared_ptr<LogPolarFrames> frames);

/// What the stages of stereo-lp share: its parameters and pass 2's lookups, kept while the maps
/// stay the same.
struct StereoFrames {
    StereoParams params;
    std::optional<StereoForwardTable> forward;
    /// The frame's two eye maps.
    std::array<LogPolarMap, 2> maps(const FrameContext& context) const;
    /// The frame's (or, with `previous`, the previous frame's) eye cameras, +-IPD/2.
    std::array<Camera, 2> cameras(const FrameContext& context, bool previous = false) const;
};

struct StereoStage {
    std::shared_ptr<StereoFrames> frames;
    std::shared_ptr<BvhCache> bvh;
    FrameJitter jitter;
};

StageDef stereo_trace_stage_def(const StereoStage& shared);
void stereo_trace_stage(FrameContext& context);
/// Gupta's pre-resolve blur (blur=internal_aa): lp_color, lp_valid -> lp_color_aa, Meng's internal
/// AA on each eye's half (stereo_internal_aa); pass 2 then reads lp_color_aa.
StageDef stereo_internal_aa_stage_def();
void stereo_internal_aa_stage(FrameContext& context);
StageDef stereo_resolve_stage_def(const StereoStage& shared, std::string output);
void stereo_resolve_stage(FrameContext& context);
StageDef stereo_ray_positions_stage_def(const StereoStage& shared);
void stereo_ray_positions_stage(FrameContext& context);

}  // namespace fovref
