// The rasterizer as a stage (SPEC §4; docs/raster.md): the one rasterize stage of every mode that
// rasterizes its primary visibility (basic with primary=raster, pathtrace, linear-falloff, and
// kfr's full-resolution G-buffer).
//
//   rasterize   (nothing)  ->  gbuffer_* (view_depth ... motion, SPEC §4 order; ports named by
//                              channel, wired to gbuffer_ + channel)
//
// The attribute pass (resolve_gbuffer) runs only when a channel other than primitive_id and
// view_depth is wanted; otherwise the stage outputs those two, as wanted, from the visibility
// pass (kfr's lp_sample reads only the ids).
//
// Counters: raster_triangles_rasterized, raster_fragments_written, and
// raster_fragments_without_plane_hit when not 0.
#pragma once

#include <string>

#include "ref/raster/rasterizer.h"
#include "ref/stage/pipeline.h"

namespace fovref {

/// The stage named `name` (modes call it "primary_visibility", kfr "gbuffer_raster") that
/// rasterizes the frame's G-buffer with `settings`; `sample` (may be empty) gives each frame's
/// RasterSettings::sample (kfr: TAA's jitter).
StageDef rasterize_stage_def(std::string name, RasterSettings settings,
                             std::function<Offset2(const FrameContext&)> sample = {});

/// The stage's body: rasterize_gbuffer (ref/raster/rasterizer.h) of the frame's camera.
void rasterize_stage(FrameContext& context);

void add_raster_counters(Counters& counters, const RasterStats& stats);

/// The rasterizer's per-pixel functions in stage `stage` (for `probe --debugger`), at the screen
/// pixel; with `family` set, at the pixels of that family the probed pixel reads (kfr: the
/// G-buffer pixels lp_sample samples, family "gbuffer_"), `why` saying what for. Without
/// `attribute_pass` (kfr, whose render without dumps skips it) write_gbuffer_pixel is left out.
std::vector<PixelFunction> raster_pixel_functions(const std::string& stage,
                                                  const std::string& family = "",
                                                  const std::string& why = "",
                                                  bool attribute_pass = true);

}  // namespace fovref
