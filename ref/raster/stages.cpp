#include "ref/raster/stages.h"

#include <memory>

#include "ref/raster/gbuffer.h"

namespace fovref {

namespace {

struct RasterizeState : StageState {
    RasterSettings settings;
    std::function<Offset2(const FrameContext&)> sample;
};

// "rasterized, fill rule d3d[, samples jittered by (x, y)/256 px]"
std::string raster_note(const RasterSettings& settings) {
    std::string note = std::string("rasterized, fill rule ") + fill_rule_name(settings.fill_rule);
    if (!(settings.sample == Offset2{})) {
        const FixedPoint shift = raster_sample_shift(settings.sample);
        note += ", samples jittered by (" + std::to_string(shift.x) + ", " +
                std::to_string(shift.y) + ")/256 px";
    }
    return note;
}

}  // namespace

void add_raster_counters(Counters& counters, const RasterStats& stats) {
    counters.add("raster_triangles_rasterized", stats.triangles_rasterized);
    counters.add("raster_fragments_written", stats.fragments_written);
    if (stats.fragments_without_plane_hit > 0)
        counters.add("raster_fragments_without_plane_hit", stats.fragments_without_plane_hit);
}

void rasterize_stage(FrameContext& ctx) {
    const RasterizeState& state = ctx.state<RasterizeState>();
    RasterSettings settings = state.settings;
    if (state.sample) settings.sample = state.sample(ctx);
    RasterStats stats;
    // The attribute pass only when a channel beyond the visibility pass's ids and depths is
    // wanted: kfr's lp_sample makes the few pixels it samples again from the ids
    // (write_rasterized_pixel), so a frame that dumps nothing skips W x H attribute lookups.
    bool attributes = false;
    for (const std::string& name : gbuffer_names(""))
        if (name != "primitive_id" && name != "view_depth" && ctx.wants(name)) attributes = true;
    if (!attributes) {
        const VisibilityBuffer vis = rasterize_visibility(
            *ctx.scene, ctx.camera, ctx.settings->width, ctx.settings->height, stats, settings);
        add_raster_counters(ctx.result->counters, stats);
        ctx.note = raster_note(settings) + ", visibility only (no other channel wanted)";
        GBuffer g;  // the channels left empty are not output
        if (ctx.wants("view_depth")) g.view_depth = visibility_view_depth(vis);
        if (ctx.wants("primitive_id")) g.primitive_id = visibility_primitive_ids(vis);
        output_gbuffer(ctx, std::move(g));
        return;
    }
    GBuffer g = rasterize_gbuffer(*ctx.scene, ctx.camera, ctx.previous_camera, ctx.settings->width,
                                  ctx.settings->height, stats, settings);
    add_raster_counters(ctx.result->counters, stats);
    ctx.note = raster_note(settings);
    output_gbuffer(ctx, std::move(g));
}

StageDef rasterize_stage_def(std::string name, RasterSettings settings,
                             std::function<Offset2(const FrameContext&)> sample) {
    auto state = std::make_shared<RasterizeState>();
    state->settings = settings;
    state->sample = std::move(sample);
    return {std::move(name), {}, gbuffer_ports(), rasterize_stage, state};
}

std::vector<PixelFunction> raster_pixel_functions(const std::string& stage,
                                                  const std::string& family, const std::string& why,
                                                  bool attribute_pass) {
    const std::string tail = why.empty() ? "" : "; " + why;
    const PixelArgs args = family.empty() ? PixelArgs::screen : PixelArgs::texel;
    std::vector<PixelFunction> functions = {
        {stage, "fovref::raster_fragment",
         "once per triangle whose snapped coverage contains the centre" + tail, args, family},
        {stage, "fovref::depth_test", "once per fragment found", args, family},
        {stage, "fovref::write_gbuffer_pixel", "the winner's attributes", args, family}};
    if (!attribute_pass) functions.pop_back();
    for (PixelFunction& f : functions) f.needs_geometry = true;
    return functions;
}

}  // namespace fovref
