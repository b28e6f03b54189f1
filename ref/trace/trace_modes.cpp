#include "ref/trace/trace_modes.h"

#include <memory>
#include <optional>

#include "ref/bvh/bvh.h"
#include "ref/core/error.h"
#include "ref/raster/gbuffer.h"
#include "ref/raster/rasterizer.h"
#include "ref/trace/direct_light.h"
#include "ref/trace/ground_truth.h"
#include "ref/trace/raycast_gbuffer.h"
#include "ref/trace/shade_basic.h"

namespace fovref {

namespace {

// The scene's BVH, built on first use and kept for later frames.
struct LazyBvh {
    std::optional<Bvh> bvh;
    const Bvh& get(const Scene& scene, Counters& counters) {
        if (!bvh) {
            bvh = build_bvh(scene.positions);
            counters.add("bvh_built_nodes", bvh->stats.nodes);
            counters.add("bvh_built_leaves", bvh->stats.leaves);
        }
        return *bvh;
    }
};

void add_trace_counters(Counters& counters, const std::string& kind, const TraceStats& stats) {
    counters.add("rays_" + kind, stats.rays);
    counters.add(kind + "_nodes_visited", stats.nodes_visited);
    counters.add(kind + "_triangles_tested", stats.triangles_tested);
    counters.add(kind + "_hits", stats.hits);
}

void add_shading_counters(Counters& counters, const ShadingStats& stats) {
    counters.add("pixels_shaded", stats.shaded);
    counters.add("texture_fetches", stats.texture_fetches);
    counters.add("light_samples_facing_away", stats.lights_facing_away);
    counters.add("light_samples_degenerate", stats.light_samples_degenerate);
    counters.add("nonfinite_inputs_replaced", stats.nonfinite_inputs);
    counters.add("invalid_material_ids", stats.invalid_material_ids);
    counters.add("shadow_rays_occluded", stats.shadow_rays_occluded);
    add_trace_counters(counters, "shadow", stats.shadow_trace);
}

std::string shadow_note(const Scene& scene) {
    return scene.lights.empty() ? "no lights: no shadow rays traced" : "";
}

StageDef primary_visibility_stage(const Scene* scene, std::shared_ptr<LazyBvh> bvh,
                                  const std::string& primary, const RasterSettings& raster) {
    return StageDef{
        "primary_visibility",
        {},
        gbuffer_names(),
        [scene, bvh, primary, raster](FrameContext& ctx) {
            const RenderSettings& s = *ctx.settings;
            if (primary == "raster") {
                RasterStats stats;
                GBuffer g = rasterize_gbuffer(*scene, ctx.camera, ctx.previous_camera, s.width,
                                              s.height, stats, raster);
                ctx.result->counters.add("raster_triangles_rasterized", stats.triangles_rasterized);
                ctx.result->counters.add("raster_fragments_written", stats.fragments_written);
                if (stats.fragments_without_plane_hit > 0)
                    ctx.result->counters.add("raster_fragments_without_plane_hit",
                                             stats.fragments_without_plane_hit);
                ctx.note = std::string("rasterized, fill rule ") + fill_rule_name(raster.fill_rule);
                add_gbuffer(*ctx.result, std::move(g));
            } else {
                TraceStats stats;
                GBuffer g =
                    raycast_gbuffer(*scene, bvh->get(*scene, ctx.result->counters), ctx.camera,
                                    ctx.previous_camera, s.width, s.height, stats);
                add_trace_counters(ctx.result->counters, "primary", stats);
                ctx.note = "ray cast";
                add_gbuffer(*ctx.result, std::move(g));
            }
        }};
}

}  // namespace

std::vector<ParamSpec> basic_params() {
    return {
        {"primary", "ray", "primary visibility: 'ray' (ray casting) or 'raster' (the rasterizer)"},
        {"fill_rule", "d3d",
         "rasterizer fill rule for pixel centres exactly on an edge (primary=raster): 'd3d' "
         "(Direct3D/Vulkan top-left) or 'gl' (OpenGL; bottom-left in fovref's y-down frame)"}};
}

RasterSettings basic_raster_settings(const Params& params) {
    RasterSettings raster;
    raster.fill_rule =
        parse_fill_rule(params.get_string(basic_params(), "fill_rule"), "parameter 'fill_rule'");
    return raster;
}

std::vector<PixelFunction> basic_pixel_functions(const Params& params) {
    if (params.get_string(basic_params(), "primary") == "raster")
        return {{"primary_visibility", "fovref::raster_fragment",
                 "once per triangle whose snapped coverage contains the centre"},
                {"primary_visibility", "fovref::depth_test", "once per fragment found"},
                {"primary_visibility", "fovref::write_gbuffer_pixel", "the winner's attributes"},
                {"shade_direct", "fovref::shade_basic_pixel", ""}};
    return {{"primary_visibility", "fovref::raycast_gbuffer_pixel", ""},
            {"shade_direct", "fovref::shade_basic_pixel", ""}};
}

std::vector<PixelFunction> ground_truth_pixel_functions(const Params&) {
    return {{"primary_visibility", "fovref::raycast_gbuffer_pixel", ""},
            {"supersample", "fovref::ground_truth_pixel", ""}};
}

Pipeline basic_pipeline(const Scene* scene, const RenderSettings& settings) {
    const std::string primary = settings.params.get_string(basic_params(), "primary");
    if (primary != "ray" && primary != "raster")
        throw Error("parameter 'primary': '" + primary + "' is neither 'ray' nor 'raster'");
    const RasterSettings raster = basic_raster_settings(settings.params);
    if (primary == "ray" && settings.params.values().count("fill_rule") != 0)
        throw Error("parameter 'fill_rule' applies to the rasterizer only: add primary=raster");
    auto bvh = std::make_shared<LazyBvh>();
    Pipeline p;
    p.stages.push_back(primary_visibility_stage(scene, bvh, primary, raster));
    p.stages.push_back(
        {"shade_direct",
         {"gbuffer_world_position", "gbuffer_shading_normal", "gbuffer_geometric_normal",
          "gbuffer_albedo", "gbuffer_material_id", "gbuffer_primitive_id"},
         {"final"},
         [scene, bvh](FrameContext& ctx) {
             const ShadeInputs inputs{
                 ctx.input("gbuffer_world_position"),   ctx.input("gbuffer_shading_normal"),
                 ctx.input("gbuffer_geometric_normal"), ctx.input("gbuffer_albedo"),
                 ctx.input("gbuffer_material_id"),      ctx.input("gbuffer_primitive_id")};
             const Bvh* tree =
                 scene->lights.empty() ? nullptr : &bvh->get(*scene, ctx.result->counters);
             ShadingStats stats;
             Image out = shade_basic(*scene, tree, inputs, ctx.camera, ctx.frame, stats);
             add_shading_counters(ctx.result->counters, stats);
             ctx.note = shadow_note(*scene);
             ctx.result->add("final", BufferKind::color, {"r", "g", "b"}, std::move(out));
         }});
    p.final_outputs = {"final"};
    return p;
}

Pipeline ground_truth_pipeline(const Scene* scene, const RenderSettings&) {
    auto bvh = std::make_shared<LazyBvh>();
    Pipeline p;
    // The pixel-centre G-buffer: consumed by nothing here, produced for --dump and golden bundles.
    p.stages.push_back(primary_visibility_stage(scene, bvh, "ray", RasterSettings{}));
    p.stages.push_back(
        {"supersample", {}, {"final"}, [scene, bvh](FrameContext& ctx) {
             TraceStats primary;
             ShadingStats shading;
             Image image =
                 render_ground_truth(*scene, bvh->get(*scene, ctx.result->counters), ctx.camera,
                                     static_cast<std::uint32_t>(ctx.frame), ctx.settings->width,
                                     ctx.settings->height, primary, shading);
             add_trace_counters(ctx.result->counters, "primary", primary);
             add_shading_counters(ctx.result->counters, shading);
             ctx.note = shadow_note(*scene);
             ctx.result->add("final", BufferKind::color, {"r", "g", "b"}, std::move(image));
         }});
    p.final_outputs = {"final"};
    return p;
}

}  // namespace fovref
