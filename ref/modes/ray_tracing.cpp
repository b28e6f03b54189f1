#include "ref/modes/ray_tracing.h"

#include <memory>

#include "ref/bvh/bvh.h"
#include "ref/core/error.h"
#include "ref/modes/bmfr_stage.h"
#include "ref/modes/mode_common.h"
#include "ref/modes/taa_stage.h"
#include "ref/raster/gbuffer.h"
#include "ref/raster/rasterizer.h"
#include "ref/trace/basic_params.h"
#include "ref/trace/direct_light.h"
#include "ref/trace/ground_truth.h"
#include "ref/trace/pathtrace.h"
#include "ref/trace/pathtrace_reference.h"
#include "ref/trace/raycast_gbuffer.h"
#include "ref/trace/shade_basic.h"

namespace fovref {

namespace {

// The state of a basic, ground-truth or path-traced render: the parameters, parsed once, the
// scene's BVH, built on first use and kept for later frames, and the TAA (basic) or BMFR
// (pathtrace) state.
struct TraceModeState : BmfrModeState {
    BasicParams params;
    BvhCache bvh;
};

const std::vector<std::string> shade_direct_inputs = {
    "gbuffer_world_position", "gbuffer_shading_normal", "gbuffer_geometric_normal",
    "gbuffer_albedo",         "gbuffer_material_id",    "gbuffer_primitive_id"};

}  // namespace

void primary_visibility_stage(FrameContext& ctx) {
    TraceModeState& state = ctx.mode_state<TraceModeState>();
    const Scene& scene = *ctx.scene;
    const RenderSettings& s = *ctx.settings;
    if (state.params.primary == PrimaryVisibility::raster) {
        RasterStats stats;
        GBuffer g = rasterize_gbuffer(scene, ctx.camera, ctx.previous_camera, s.width, s.height,
                                      stats, state.params.raster);
        add_raster_counters(ctx.result->counters, stats);
        ctx.note =
            std::string("rasterized, fill rule ") + fill_rule_name(state.params.raster.fill_rule);
        add_gbuffer(*ctx.result, std::move(g));
    } else {
        RaycastStats stats;
        const Offset2 jitter = frame_jitter(ctx);
        GBuffer g = raycast_gbuffer(scene, state.bvh.get(scene, ctx.result->counters), ctx.camera,
                                    ctx.previous_camera, s.width, s.height, stats, jitter);
        add_trace_counters(ctx.result->counters, "primary", stats.primary);
        ctx.note = jitter == Offset2{} ? "ray cast"
                                       : "ray cast, jittered to (" + std::to_string(jitter.x) +
                                             ", " + std::to_string(jitter.y) + ") in each pixel";
        add_gbuffer(*ctx.result, std::move(g));
    }
}

void shade_direct_stage(FrameContext& ctx) {
    TraceModeState& state = ctx.mode_state<TraceModeState>();
    const Scene& scene = *ctx.scene;
    const ShadeInputs inputs = shade_inputs_of(ctx, "gbuffer_");
    // No lights: no shadow rays, so no BVH is needed for shading.
    const Bvh* tree = scene.lights.empty() ? nullptr : &state.bvh.get(scene, ctx.result->counters);
    ShadingStats stats;
    Image out = shade_basic(scene, tree, inputs, ctx.camera, ctx.frame, stats);
    add_shading_counters(ctx.result->counters, stats);
    ctx.note = shadow_note(scene);
    const std::string name = state.taa.enabled() ? "shaded" : "final";
    ctx.result->add(name, BufferKind::color, {"r", "g", "b"}, std::move(out));
}

void supersample_stage(FrameContext& ctx) {
    TraceModeState& state = ctx.mode_state<TraceModeState>();
    const Scene& scene = *ctx.scene;
    TraceStats primary;
    ShadingStats shading;
    Image image = render_ground_truth(scene, state.bvh.get(scene, ctx.result->counters), ctx.camera,
                                      static_cast<std::uint32_t>(ctx.frame), ctx.settings->width,
                                      ctx.settings->height, primary, shading);
    add_trace_counters(ctx.result->counters, "primary", primary);
    add_shading_counters(ctx.result->counters, shading);
    ctx.note = shadow_note(scene);
    ctx.result->add("final", BufferKind::color, {"r", "g", "b"}, std::move(image));
}

namespace {

// The state of a path-traced render: the TAA-free trace state (rasterized primary visibility,
// the BVH) and the path tracer's parameters.
struct PathTraceModeState : TraceModeState {
    PathTraceParams path;
};

}  // namespace

void pathtrace_stage(FrameContext& ctx) {
    PathTraceModeState& state = ctx.mode_state<PathTraceModeState>();
    const Scene& scene = *ctx.scene;
    const ShadeInputs inputs = shade_inputs_of(ctx, "gbuffer_");
    PathTraceStats stats;
    Image emission;
    Image out = pathtrace(scene, state.bvh.get(scene, ctx.result->counters), state.path, inputs,
                          ctx.camera, ctx.frame, stats, state.bmfr.enabled ? &emission : nullptr);
    add_shading_counters(ctx.result->counters, stats.shading);
    add_trace_counters(ctx.result->counters, "secondary", stats.secondary);
    Counters& counters = ctx.result->counters;
    counters.add("paths", stats.paths);
    counters.add("paths_ended_background", stats.ended_background);
    counters.add("paths_ended_black", stats.ended_black);
    counters.add("paths_ended_roulette", stats.ended_roulette);
    counters.add("paths_ended_below_surface", stats.ended_below);
    ctx.note = "max_bounces " + std::to_string(state.path.max_bounces) +
               (scene.lights.empty() ? ", no lights: no shadow rays" : "");
    ctx.result->add(state.bmfr.enabled ? "radiance" : "final", BufferKind::color, {"r", "g", "b"},
                    std::move(out));
    if (state.bmfr.enabled)
        ctx.result->add("emission", BufferKind::color, {"r", "g", "b"}, std::move(emission));
}

std::vector<ParamSpec> pathtrace_param_specs() {
    std::vector<ParamSpec> specs = {
        {"fill_rule", "d3d", "rasterizer fill rule of the primary visibility: 'd3d' or 'gl'"},
        {"max_bounces", "1",
         "secondary rays per path: 1 = the sources' four rays per pixel (primary, two shadow "
         "rays, one secondary); more with Russian roulette"},
        {"rr", "0.8", "Russian-roulette continuation probability from the second bounce on"}};
    for (ParamSpec& spec : bmfr_param_specs()) specs.push_back(std::move(spec));
    return specs;
}

Pipeline pathtrace_pipeline(const Scene*, const RenderSettings& settings) {
    auto state = std::make_shared<PathTraceModeState>();
    const std::vector<ParamSpec> specs = pathtrace_param_specs();
    state->params.primary = PrimaryVisibility::raster;
    state->params.raster.fill_rule =
        parse_fill_rule(settings.params.get_string(specs, "fill_rule"), "parameter 'fill_rule'");
    state->path.max_bounces = settings.params.get_int(specs, "max_bounces", 1, 64);
    state->path.rr = settings.params.get_float(specs, "rr", 0.01f, 1.0f);
    if (state->path.max_bounces == 1 && settings.params.values().count("rr") != 0)
        throw Error("parameter 'rr' applies from the second bounce on: add max_bounces=2 or more");
    state->bmfr = parse_bmfr_params(settings.params);
    Pipeline p;
    p.state = state;
    p.stages.push_back({"primary_visibility", {}, gbuffer_names(), primary_visibility_stage});
    if (state->bmfr.enabled) {
        p.stages.push_back(
            {"pathtrace", shade_direct_inputs, {"radiance", "emission"}, pathtrace_stage});
        add_bmfr_stages(p, *state, "radiance", "emission", "final");
    } else {
        p.stages.push_back({"pathtrace", shade_direct_inputs, {"final"}, pathtrace_stage});
    }
    p.final_outputs = {"final"};
    return p;
}

namespace {

struct ReferenceModeState : TraceModeState {
    PathTraceParams path;
    int spp = 1024;
};

// The sums of an earlier run of the same frame (`fovref render --resume DIR`), or none.
PathReferenceSums resumed_reference_sums(const FrameContext& ctx) {
    const int width = ctx.settings->width, height = ctx.settings->height;
    PathReferenceSums sums = empty_reference_sums(width, height);
    const auto find = [&](const std::string& name) -> const Image* {
        for (const Buffer& b : ctx.settings->state_buffers)
            if (b.name == name) return &b.image;
        return nullptr;
    };
    const Image* count = find("reference_count");
    if (!count) return sums;
    const auto get = [&](const std::string& name) {
        const Image* image = find(name);
        if (!image || image->width != width || image->height != height || image->channels != 3)
            throw Error("--resume: buffer '" + name + "' is missing or not " +
                        std::to_string(width) + "x" + std::to_string(height) + "x3");
        return *image;
    };
    sums.sum = get("reference_sum");
    sums.compensation = get("reference_compensation");
    sums.squares = get("reference_squares");
    if (count->data.size() != 1 || !(count->data[0] >= 1.0f) || count->data[0] > 65536.0f ||
        count->data[0] != static_cast<float>(static_cast<int>(count->data[0])))
        throw Error("--resume: buffer 'reference_count' must hold one sample count in 1..65536");
    sums.count = static_cast<int>(count->data[0]);
    return sums;
}

}  // namespace

void pathtrace_reference_stage(FrameContext& ctx) {
    ReferenceModeState& state = ctx.mode_state<ReferenceModeState>();
    const Scene& scene = *ctx.scene;
    PathReferenceSums sums = resumed_reference_sums(ctx);
    const int resumed = sums.count;
    if (resumed > state.spp)
        throw Error("--resume: the bundle already holds " + std::to_string(resumed) +
                    " samples, more than spp=" + std::to_string(state.spp));
    TraceStats primary;
    PathTraceStats stats;
    pathtrace_reference(scene, state.bvh.get(scene, ctx.result->counters), state.path, ctx.camera,
                        ctx.frame, state.spp, sums, primary, stats,
                        [&](double f) { ctx.report(f); });
    add_trace_counters(ctx.result->counters, "primary", primary);
    add_shading_counters(ctx.result->counters, stats.shading);
    add_trace_counters(ctx.result->counters, "secondary", stats.secondary);
    Counters& counters = ctx.result->counters;
    counters.add("paths", stats.paths);
    counters.add("reference_samples", sums.count);
    counters.add("reference_samples_resumed", resumed);
    Image mean, error;
    reference_estimate(sums, mean, error);
    double total = 0.0;
    for (float v : error.data) total += v;
    const double mean_error = total / static_cast<double>(error.data.size());
    char text[160];
    std::snprintf(text, sizeof text,
                  "%d samples per pixel (%d resumed), mean standard error %.3g (linear radiance)",
                  sums.count, resumed, mean_error);
    ctx.note = text;
    // the mean standard error in units of 1e-9, for scripts that read counters
    counters.add("reference_mean_standard_error_e9", static_cast<std::int64_t>(mean_error * 1e9));
    const std::vector<std::string> rgb = {"r", "g", "b"};
    ctx.result->add("final", BufferKind::color, rgb, std::move(mean));
    ctx.result->add("standard_error", BufferKind::scalar, rgb, std::move(error));
    ctx.result->add("reference_sum", BufferKind::scalar, rgb, std::move(sums.sum));
    ctx.result->add("reference_compensation", BufferKind::scalar, rgb,
                    std::move(sums.compensation));
    ctx.result->add("reference_squares", BufferKind::scalar, rgb, std::move(sums.squares));
    ctx.result->add("reference_count", BufferKind::scalar, {"n"},
                    Image(1, 1, 1, static_cast<float>(sums.count)));
}

std::vector<ParamSpec> pathtrace_reference_param_specs() {
    return {{"spp", "1024", "samples per pixel (1..65536); --resume DIR continues an earlier run"},
            {"max_bounces", "1", "secondary rays per path, as pathtrace"},
            {"rr", "0.8", "Russian-roulette continuation probability, as pathtrace"}};
}

Pipeline pathtrace_reference_pipeline(const Scene*, const RenderSettings& settings) {
    auto state = std::make_shared<ReferenceModeState>();
    const std::vector<ParamSpec> specs = pathtrace_reference_param_specs();
    state->params.primary = PrimaryVisibility::ray;
    state->spp = settings.params.get_int(specs, "spp", 1, 65536);
    state->path.max_bounces = settings.params.get_int(specs, "max_bounces", 1, 64);
    state->path.rr = settings.params.get_float(specs, "rr", 0.01f, 1.0f);
    Pipeline p;
    p.state = state;
    const std::vector<std::string> outputs = {"final",
                                              "standard_error",
                                              "reference_sum",
                                              "reference_compensation",
                                              "reference_squares",
                                              "reference_count"};
    p.stages.push_back({"pathtrace_reference", {}, outputs, pathtrace_reference_stage});
    p.final_outputs = outputs;
    return p;
}

std::vector<PixelFunction> pathtrace_pixel_functions(const Params&) {
    return {{"primary_visibility", "fovref::raster_fragment",
             "once per triangle whose snapped coverage contains the centre"},
            {"pathtrace", "fovref::pathtrace_pixel", ""}};
}

std::vector<PixelFunction> basic_pixel_functions(const Params& params) {
    if (parse_taa_params(params).enabled())
        return {{"primary_visibility", "fovref::raycast_gbuffer_pixel", "jittered (TAA)"},
                {"shade_direct", "fovref::shade_basic_pixel", ""},
                {"taa", "fovref::taa_pixel", "once per frame, frames 0 .. F"}};
    if (parse_basic_params(params).primary == PrimaryVisibility::raster)
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

Pipeline basic_pipeline(const Scene*, const RenderSettings& settings) {
    auto state = std::make_shared<TraceModeState>();
    state->params = parse_basic_params(settings.params);
    state->taa = parse_taa_params(settings.params);
    if (state->taa.enabled() && state->params.primary == PrimaryVisibility::raster)
        throw Error(std::string("parameter 'taa': ") + taa_mode_name(state->taa.mode) +
                    " needs jittered primary rays, and primary=raster has no sub-pixel "
                    "jitter: use primary=ray");
    if (state->taa.mode == TaaMode::clamp_buffer)
        throw Error(
            "parameter 'taa': clamp-buffer is for the foveated modes; basic's buffer is "
            "the screen: use clamp-screen");
    Pipeline p;
    p.state = state;
    p.stages.push_back({"primary_visibility", {}, gbuffer_names(), primary_visibility_stage});
    if (state->taa.enabled()) {
        p.stages.push_back({"shade_direct", shade_direct_inputs, {"shaded"}, shade_direct_stage});
        add_taa_stage(p, *state, "shaded", "gbuffer_view_depth", "", "final");
        p.final_outputs = {"final"};
        return p;
    }
    p.stages.push_back({"shade_direct", shade_direct_inputs, {"final"}, shade_direct_stage});
    p.final_outputs = {"final"};
    return p;
}

Pipeline ground_truth_pipeline(const Scene*, const RenderSettings&) {
    auto state = std::make_shared<TraceModeState>();  // primary = ray: the BVH is shared
    Pipeline p;
    p.state = state;
    // The pixel-centre G-buffer: consumed by nothing here, produced for --dump and golden bundles.
    p.stages.push_back({"primary_visibility", {}, gbuffer_names(), primary_visibility_stage});
    p.stages.push_back({"supersample", {}, {"final"}, supersample_stage});
    p.final_outputs = {"final"};
    return p;
}

}  // namespace fovref
