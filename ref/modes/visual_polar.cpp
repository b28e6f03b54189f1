#include "ref/modes/visual_polar.h"

#include <memory>
#include <optional>

#include "ref/core/error.h"
#include "ref/filters/blur_ramp.h"
#include "ref/modes/bmfr_stage.h"
#include "ref/modes/mode_common.h"
#include "ref/raster/gbuffer.h"
#include "ref/raster/rasterizer.h"
#include "ref/trace/pathtrace.h"
#include "ref/visual_polar/params.h"
#include "ref/visual_polar/resolve.h"
#include "ref/visual_polar/sparse_sampling.h"
#include "ref/visual_polar/trace.h"

namespace fovref {

namespace {

const std::vector<std::string> rgb = {"r", "g", "b"};

struct SparseModeState : BmfrModeState {
    std::string mode;
    SparseParams params;
    PathTraceParams path;
    BvhCache bvh;
    RasterSettings raster;
    // acuity, progressive: the sums so far
    Image acuity_sum, acuity_count;
    int acuity_frame = -1;
    /// Pass 2's per-pixel polar coordinates, kept while the map stays the same (a static gaze)
    std::optional<VpForwardTable> forward;
};

SparseModeState& sparse_state(FrameContext& ctx) { return ctx.mode_state<SparseModeState>(); }

VisualPolarMap frame_vp_map(const FrameContext& ctx, int frame) {
    const SparseModeState& s = ctx.mode_state<SparseModeState>();
    return sparse_vp_map(s.params, ctx.settings->width, ctx.settings->height, frame);
}

std::vector<std::string> with(std::vector<std::string> names, const std::string& extra) {
    names.push_back(extra);
    return names;
}

std::vector<std::string> shade_inputs(const std::string& prefix) {
    return {prefix + "world_position", prefix + "shading_normal", prefix + "geometric_normal",
            prefix + "albedo",         prefix + "material_id",    prefix + "primitive_id"};
}

// The path tracer over a G-buffer (`prefix`), tracing where `mask` is not 0; adds the counters.
Image trace_paths(FrameContext& ctx, const std::string& prefix, const Image* mask,
                  Image* emission) {
    SparseModeState& s = sparse_state(ctx);
    const Scene& scene = *ctx.scene;
    PathTraceStats stats;
    Image out =
        pathtrace(scene, s.bvh.get(scene, ctx.result->counters), s.path,
                  shade_inputs_of(ctx, prefix), ctx.camera, ctx.frame, stats, emission, mask);
    add_shading_counters(ctx.result->counters, stats.shading);
    add_trace_counters(ctx.result->counters, "secondary", stats.secondary);
    ctx.result->counters.add("paths", stats.paths);
    ctx.note = "max_bounces " + std::to_string(s.path.max_bounces) +
               (scene.lights.empty() ? ", no lights: no shadow rays" : "");
    return out;
}

void add_vp_trace_counters(FrameContext& ctx, const VpTraceStats& stats) {
    Counters& counters = ctx.result->counters;
    counters.add("texels_traced", stats.texels_traced);
    counters.add("texels_clipped", stats.texels_clipped);
    counters.add("texels_off_screen", stats.texels_off_screen);
    add_trace_counters(counters, "primary", stats.rays.primary);
}

// ---- visual-polar ---------------------------------------------------------------------------

void vp_trace_stage(FrameContext& ctx) {
    SparseModeState& s = sparse_state(ctx);
    const VisualPolarMap map = frame_vp_map(ctx, ctx.frame);
    Counters& counters = ctx.result->counters;
    VpTraceStats stats;
    Image points;
    MaskedGBuffer vp = trace_vp_gbuffer(map, *ctx.scene, s.bvh.get(*ctx.scene, counters),
                                        ctx.camera, ctx.previous_camera, points, stats);
    counters.add("buffer_width", map.width);
    counters.add("buffer_height", map.height);
    counters.add("fovea_columns", map.fovea_columns);
    add_vp_trace_counters(ctx, stats);
    char text[192];
    std::snprintf(text, sizeof text,
                  "gaze (%.9g, %.9g), %dx%d texels, i_f = %d, s = %.6g px/deg: %lld traced, %lld "
                  "clipped, %lld off screen",
                  static_cast<double>(map.gaze.x), static_cast<double>(map.gaze.y), map.width,
                  map.height, map.fovea_columns, static_cast<double>(map.scale),
                  static_cast<long long>(stats.texels_traced),
                  static_cast<long long>(stats.texels_clipped),
                  static_cast<long long>(stats.texels_off_screen));
    ctx.note = text;
    add_gbuffer(*ctx.result, std::move(vp.gbuffer), "vp_gbuffer_");
    ctx.result->add("vp_valid", BufferKind::id, {"valid"}, std::move(vp.valid));
    ctx.result->add("vp_screen_point", BufferKind::scalar, {"x", "y"}, std::move(points));
}

void vp_shade_stage(FrameContext& ctx) {
    SparseModeState& s = sparse_state(ctx);
    const Scene& scene = *ctx.scene;
    const Bvh* tree = scene.lights.empty() ? nullptr : &s.bvh.get(scene, ctx.result->counters);
    ShadingStats stats;
    Image out =
        shade_basic(scene, tree, shade_inputs_of(ctx, "vp_gbuffer_"), ctx.camera, ctx.frame, stats);
    add_shading_counters(ctx.result->counters, stats);
    ctx.note = shadow_note(scene);
    ctx.result->add("vp_color", BufferKind::color, rgb, std::move(out));
}

void vp_pathtrace_stage(FrameContext& ctx) {
    const SparseModeState& s = sparse_state(ctx);
    Image emission;
    Image out = trace_paths(ctx, "vp_gbuffer_", &ctx.input("vp_valid"),
                            s.bmfr.enabled ? &emission : nullptr);
    ctx.result->add(s.bmfr.enabled ? "vp_radiance" : "vp_color", BufferKind::color, rgb,
                    std::move(out));
    if (s.bmfr.enabled) ctx.result->add("vp_emission", BufferKind::color, rgb, std::move(emission));
}

void vp_resolve_stage(FrameContext& ctx) {
    SparseModeState& s = sparse_state(ctx);
    const VisualPolarMap map = frame_vp_map(ctx, ctx.frame);
    const Image& color = ctx.input("vp_color");
    const Image& valid = ctx.input("vp_valid");
    const VpMips mips = build_vp_mips(map, color, valid);
    const bool reused = s.forward && s.forward->map == map;
    if (!reused) s.forward = vp_forward_table(map);
    ResolveStats stats;
    Image out = resolve_visual_polar(map, mips, stats, s.params.mip_resolve, &*s.forward);
    ctx.result->counters.add("screen_pixels_untraced_taps", stats.pixels_untraced_taps);
    ctx.note = (s.params.mip_resolve
                    ? "phi mips, trilinear (" + std::to_string(mips.color.size()) + " levels)"
                    : std::string("bilinear")) +
               (reused ? ", forward map reused" : ", forward map computed");
    ctx.result->add(s.params.blur ? "resolved" : "final", BufferKind::color, rgb, std::move(out));
}

void blur_horizontal_stage(FrameContext& ctx) {
    const SparseModeState& s = sparse_state(ctx);
    ctx.result->add(
        "blur_horizontal", BufferKind::color, rgb,
        blur_ramp_horizontal(s.params.ramp, blur_ramp_geometry(frame_vp_map(ctx, ctx.frame)),
                             ctx.input("resolved")));
}

void blur_vertical_stage(FrameContext& ctx) {
    const SparseModeState& s = sparse_state(ctx);
    ctx.result->add(
        "final", BufferKind::color, rgb,
        blur_ramp_vertical(s.params.ramp, blur_ramp_geometry(frame_vp_map(ctx, ctx.frame)),
                           ctx.input("blur_horizontal")));
}

PathTraceParams parse_path(const Params& params, const std::vector<ParamSpec>& specs) {
    PathTraceParams path;
    path.max_bounces = params.get_int(specs, "max_bounces", 1, 64);
    path.rr = params.get_float(specs, "rr", 0.01f, 1.0f);
    if (path.max_bounces == 1 && params.given("rr"))
        throw Error("parameter 'rr' applies from the second bounce on: add max_bounces=2 or more");
    return path;
}

std::vector<ParamSpec> path_specs() {
    return {{"max_bounces", "1",
             "secondary rays per path: 1 = the sources' four rays per sample (primary, two "
             "shadow rays, one secondary); more with Russian roulette"},
            {"rr", "0.8", "Russian-roulette continuation probability from the second bounce on"}};
}

std::vector<ParamSpec> concat(std::vector<ParamSpec> a, const std::vector<ParamSpec>& b) {
    for (const ParamSpec& spec : b) a.push_back(spec);
    return a;
}

Pipeline vp_pipeline(const RenderSettings& settings, bool path_traced) {
    auto state = std::make_shared<SparseModeState>();
    state->mode = path_traced ? "visual-polar" : "visual-polar-basic";
    state->params = parse_sparse_params(settings.params, state->mode);
    // Validate the map now (buffer size, gaze), not in the first stage
    sparse_vp_map(state->params, settings.width, settings.height, 0);
    Pipeline p;
    p.state = state;
    p.stages.push_back({"vp_trace",
                        {},
                        with(with(gbuffer_names("vp_gbuffer_"), "vp_valid"), "vp_screen_point"),
                        vp_trace_stage});
    if (path_traced) {
        const std::vector<ParamSpec> specs = visual_polar_param_specs(true);
        state->path = parse_path(settings.params, specs);
        state->bmfr = parse_bmfr_params(settings.params, "bmfr");
        const std::vector<std::string> inputs = with(shade_inputs("vp_gbuffer_"), "vp_valid");
        if (state->bmfr.enabled) {
            p.stages.push_back(
                {"vp_pathtrace", inputs, {"vp_radiance", "vp_emission"}, vp_pathtrace_stage});
            state->bmfr_gbuffer = "vp_gbuffer_";
            state->bmfr_valid = "vp_valid";
            state->bmfr_map = frame_vp_map;
            add_bmfr_stages(p, *state, "vp_radiance", "vp_emission", "vp_color");
        } else {
            p.stages.push_back({"vp_pathtrace", inputs, {"vp_color"}, vp_pathtrace_stage});
        }
    } else {
        p.stages.push_back({"vp_shade", shade_inputs("vp_gbuffer_"), {"vp_color"}, vp_shade_stage});
    }
    const bool blur = state->params.blur;
    p.stages.push_back(
        {"resolve", {"vp_color", "vp_valid"}, {blur ? "resolved" : "final"}, vp_resolve_stage});
    if (blur) {
        p.stages.push_back(
            {"blur_horizontal", {"resolved"}, {"blur_horizontal"}, blur_horizontal_stage});
        p.stages.push_back({"blur_vertical", {"blur_horizontal"}, {"final"}, blur_vertical_stage});
    }
    p.final_outputs = {"final"};
    return p;
}

// ---- linear fall-off ------------------------------------------------------------------------

void raster_stage(FrameContext& ctx) {
    const SparseModeState& s = sparse_state(ctx);
    RasterStats stats;
    GBuffer g = rasterize_gbuffer(*ctx.scene, ctx.camera, ctx.previous_camera, ctx.settings->width,
                                  ctx.settings->height, stats, s.raster);
    add_raster_counters(ctx.result->counters, stats);
    ctx.note = std::string("rasterized, fill rule ") + fill_rule_name(s.raster.fill_rule);
    add_gbuffer(*ctx.result, std::move(g));
}

void falloff_mask_stage(FrameContext& ctx) {
    const SparseModeState& s = sparse_state(ctx);
    const int width = ctx.settings->width, height = ctx.settings->height;
    const float d_px = display_distance_px(ctx.scene->display, width, height, ctx.camera.vfov_deg);
    std::int64_t sampled = 0;
    Image mask = linear_falloff_mask(s.params.falloff, width, height,
                                     sparse_gaze(s.params, width, height, ctx.frame), d_px,
                                     static_cast<std::uint32_t>(ctx.frame), sampled);
    ctx.result->counters.add("pixels_sampled", sampled);
    ctx.result->counters.add("pixels_unsampled",
                             static_cast<std::int64_t>(width) * height - sampled);
    char text[96];
    std::snprintf(text, sizeof text, "%lld of %lld pixels sampled (%.2f%%)",
                  static_cast<long long>(sampled), static_cast<long long>(width) * height,
                  100.0 * static_cast<double>(sampled) / (static_cast<double>(width) * height));
    ctx.note = text;
    ctx.result->add("sample_mask", BufferKind::id, {"sampled"}, std::move(mask));
}

void sparse_pathtrace_stage(FrameContext& ctx) {
    const SparseModeState& s = sparse_state(ctx);
    const bool emission = s.bmfr.enabled && s.bmfr.params.separate_emission;
    Image e;
    Image out = trace_paths(ctx, "gbuffer_", &ctx.input("sample_mask"), emission ? &e : nullptr);
    ctx.result->add("sparse_radiance", BufferKind::color, rgb, std::move(out));
    if (emission) ctx.result->add("sparse_emission", BufferKind::color, rgb, std::move(e));
}

void fill_stage(FrameContext& ctx) {
    const SparseModeState& s = sparse_state(ctx);
    const Image& mask = ctx.input("sample_mask");
    const std::string out = s.bmfr.enabled ? "filled" : "final";
    ctx.note = s.params.fill ? "push-pull" : "black where unsampled";
    ctx.result->add(out, BufferKind::color, rgb,
                    s.params.fill ? push_pull(ctx.input("sparse_radiance"), mask)
                                  : ctx.input("sparse_radiance"));
    if (s.bmfr.enabled && s.bmfr.params.separate_emission)
        ctx.result->add("filled_emission", BufferKind::color, rgb,
                        s.params.fill ? push_pull(ctx.input("sparse_emission"), mask)
                                      : ctx.input("sparse_emission"));
}

// ---- acuity ---------------------------------------------------------------------------------

std::vector<glm::vec2> frame_acuity_points(const FrameContext& ctx) {
    const SparseModeState& s = ctx.mode_state<SparseModeState>();
    const int width = ctx.settings->width, height = ctx.settings->height;
    return acuity_samples(static_cast<std::uint32_t>(ctx.frame),
                          acuity_samples_per_frame(s.params, width, height),
                          sparse_gaze(s.params, width, height, ctx.frame),
                          sparse_pixels_per_degree(*ctx.scene, ctx.camera, width, height));
}

void acuity_trace_stage(FrameContext& ctx) {
    SparseModeState& s = sparse_state(ctx);
    const std::vector<glm::vec2> points = frame_acuity_points(ctx);
    Counters& counters = ctx.result->counters;
    VpTraceStats stats;
    MaskedGBuffer g = trace_point_gbuffer(points, ctx.settings->width, ctx.settings->height,
                                          *ctx.scene, s.bvh.get(*ctx.scene, counters), ctx.camera,
                                          ctx.previous_camera, stats);
    counters.add("samples", static_cast<std::int64_t>(points.size()));
    counters.add("samples_traced", stats.texels_traced);
    counters.add("samples_off_screen", stats.texels_off_screen);
    add_trace_counters(counters, "primary", stats.rays.primary);
    ctx.note = std::to_string(points.size()) + " samples, " +
               std::to_string(stats.texels_off_screen) + " off screen (dropped)";
    Image where(static_cast<int>(points.size()), 1, 2);
    for (std::size_t k = 0; k < points.size(); ++k) {
        where.at(static_cast<int>(k), 0, 0) = points[k].x;
        where.at(static_cast<int>(k), 0, 1) = points[k].y;
    }
    add_gbuffer(*ctx.result, std::move(g.gbuffer), "acuity_gbuffer_");
    ctx.result->add("acuity_valid", BufferKind::id, {"valid"}, std::move(g.valid));
    ctx.result->add("acuity_point", BufferKind::scalar, {"x", "y"}, std::move(where));
}

void acuity_shade_stage(FrameContext& ctx) {
    ctx.result->add("acuity_radiance", BufferKind::color, rgb,
                    trace_paths(ctx, "acuity_gbuffer_", &ctx.input("acuity_valid"), nullptr));
}

void acuity_accumulate_stage(FrameContext& ctx) {
    SparseModeState& s = sparse_state(ctx);
    const int width = ctx.settings->width, height = ctx.settings->height;
    Image sum(width, height, 3, 0.0f), count(width, height, 1, 0.0f);
    if (s.params.progressive) {
        if (s.acuity_frame == ctx.frame - 1 && s.acuity_frame >= 0) {
            sum = s.acuity_sum;
            count = s.acuity_count;
        } else if (ctx.has_previous) {
            sum = resumed_buffer(ctx, "acuity_sum", 3, "progressive acuity sampling");
            count = resumed_buffer(ctx, "acuity_count", 1, "progressive acuity sampling");
        }
    }
    const Image& points_image = ctx.input("acuity_point");
    std::vector<glm::vec2> points;
    for (int k = 0; k < points_image.width; ++k)
        points.emplace_back(points_image.at(k, 0, 0), points_image.at(k, 0, 1));
    splat_samples(points, ctx.input("acuity_valid"), ctx.input("acuity_radiance"), sum, count);
    s.acuity_sum = sum;
    s.acuity_count = count;
    s.acuity_frame = ctx.frame;
    ctx.note =
        s.params.progressive ? "progressive: every sample since frame 0" : "this frame's samples";
    ctx.result->add("acuity_sum", BufferKind::scalar, rgb, std::move(sum));
    ctx.result->add("acuity_count", BufferKind::scalar, {"n"}, std::move(count));
}

void acuity_resolve_stage(FrameContext& ctx) {
    const SparseModeState& s = sparse_state(ctx);
    Image weight;
    Image mean = sample_mean(ctx.input("acuity_sum"), ctx.input("acuity_count"), weight);
    std::int64_t empty = 0;
    for (float w : weight.data) empty += w == 0.0f;
    ctx.result->counters.add("pixels_without_sample", empty);
    ctx.note = std::to_string(empty) + " pixels without a sample" +
               (s.params.fill ? ", push-pull filled" : ", black");
    ctx.result->add("final", BufferKind::color, rgb,
                    s.params.fill ? push_pull(mean, weight) : std::move(mean));
}

}  // namespace

std::vector<ParamSpec> visual_polar_param_specs(bool path_traced) {
    std::vector<ParamSpec> specs =
        sparse_param_specs(path_traced ? "visual-polar" : "visual-polar-basic");
    if (path_traced) specs = concat(concat(specs, path_specs()), bmfr_param_specs("bmfr"));
    return specs;
}

std::vector<ParamSpec> linear_falloff_param_specs() {
    std::vector<ParamSpec> specs = concat(sparse_param_specs("linear-falloff"), path_specs());
    specs.push_back({"fill_rule", "d3d", "rasterizer fill rule of the primary visibility"});
    return concat(specs, bmfr_param_specs());
}

std::vector<ParamSpec> acuity_param_specs() {
    return concat(sparse_param_specs("acuity"), path_specs());
}

Pipeline visual_polar_pipeline(const Scene*, const RenderSettings& settings) {
    return vp_pipeline(settings, true);
}

Pipeline visual_polar_basic_pipeline(const Scene*, const RenderSettings& settings) {
    return vp_pipeline(settings, false);
}

Pipeline linear_falloff_pipeline(const Scene*, const RenderSettings& settings) {
    auto state = std::make_shared<SparseModeState>();
    state->mode = "linear-falloff";
    state->params = parse_sparse_params(settings.params, state->mode);
    const std::vector<ParamSpec> specs = linear_falloff_param_specs();
    state->path = parse_path(settings.params, specs);
    state->raster.fill_rule =
        parse_fill_rule(settings.params.get_string(specs, "fill_rule"), "parameter 'fill_rule'");
    state->bmfr = parse_bmfr_params(settings.params);
    const bool separate = state->bmfr.enabled && state->bmfr.params.separate_emission;
    Pipeline p;
    p.state = state;
    p.stages.push_back({"primary_visibility", {}, gbuffer_names(), raster_stage});
    p.stages.push_back({"falloff_mask", {}, {"sample_mask"}, falloff_mask_stage});
    std::vector<std::string> traced = {"sparse_radiance"};
    if (separate) traced.push_back("sparse_emission");
    p.stages.push_back({"pathtrace", with(shade_inputs("gbuffer_"), "sample_mask"), traced,
                        sparse_pathtrace_stage});
    std::vector<std::string> filled = {state->bmfr.enabled ? "filled" : "final"};
    if (separate) filled.push_back("filled_emission");
    p.stages.push_back({"fill", with(traced, "sample_mask"), filled, fill_stage});
    if (state->bmfr.enabled) add_bmfr_stages(p, *state, "filled", "filled_emission", "final");
    p.final_outputs = {"final"};
    return p;
}

Pipeline acuity_pipeline(const Scene*, const RenderSettings& settings) {
    auto state = std::make_shared<SparseModeState>();
    state->mode = "acuity";
    state->params = parse_sparse_params(settings.params, state->mode);
    state->path = parse_path(settings.params, acuity_param_specs());
    acuity_samples_per_frame(state->params, settings.width, settings.height);  // validated now
    Pipeline p;
    p.state = state;
    p.stages.push_back(
        {"acuity_trace",
         {},
         with(with(gbuffer_names("acuity_gbuffer_"), "acuity_valid"), "acuity_point"),
         acuity_trace_stage});
    p.stages.push_back({"acuity_shade",
                        with(shade_inputs("acuity_gbuffer_"), "acuity_valid"),
                        {"acuity_radiance"},
                        acuity_shade_stage});
    p.stages.push_back({"acuity_accumulate",
                        {"acuity_point", "acuity_valid", "acuity_radiance"},
                        {"acuity_sum", "acuity_count"},
                        acuity_accumulate_stage});
    p.stages.push_back(
        {"acuity_resolve", {"acuity_sum", "acuity_count"}, {"final"}, acuity_resolve_stage});
    p.final_outputs = {"final"};
    return p;
}

std::vector<PixelFunction> visual_polar_pixel_functions(const Params&) {
    return {{"vp_trace", "fovref::vp_gbuffer_texel", "x, y: the texel (i, j)"},
            {"vp_pathtrace", "fovref::pathtrace_pixel", "x, y: the texel (i, j)"},
            {"resolve", "fovref::resolve_vp_pixel", ""}};
}

std::vector<PixelFunction> visual_polar_basic_pixel_functions(const Params&) {
    return {{"vp_trace", "fovref::vp_gbuffer_texel", "x, y: the texel (i, j)"},
            {"vp_shade", "fovref::shade_basic_pixel", "x, y: the texel (i, j)"},
            {"resolve", "fovref::resolve_vp_pixel", ""}};
}

}  // namespace fovref
