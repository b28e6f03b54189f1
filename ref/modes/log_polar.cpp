#include "ref/modes/log_polar.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include "ref/filters/gaussian_lerp.h"
#include "ref/filters/internal_aa.h"
#include "ref/filters/post_aa.h"
#include "ref/image/image.h"
#include "ref/log_polar/deferred_sample.h"
#include "ref/log_polar/mip_resolve.h"
#include "ref/log_polar/params.h"
#include "ref/log_polar/resolve.h"
#include "ref/log_polar/stereo.h"
#include "ref/log_polar/trace.h"
#include "ref/modes/mode_common.h"
#include "ref/modes/taa_stage.h"
#include "ref/raster/gbuffer.h"
#include "ref/raster/rasterizer.h"
#include "ref/temporal/taa_foveated.h"
#include "ref/trace/shade_basic.h"

namespace fovref {

namespace {

struct FoveatedModeState : TaaModeState {
    FoveatedParams params;
    BvhCache bvh;
    /// Pass 2's forward map, kept while the map stays the same (a static gaze).
    std::optional<ForwardTable> forward;
    /// The screen-space chain: pass 2's output, then TAA's and each filter's; the last is
    /// "final" (see foveated_pipeline).
    std::vector<std::string> chain;
    std::size_t lerp_link = 0, post_aa_link = 0;  ///< the filters' input in `chain`
};

// Pass 2's forward table for `map` (made again only when the map changed).
const ForwardTable& frame_forward_table(FoveatedModeState& state, const LogPolarMap& map,
                                        int mip_levels, bool* reused = nullptr) {
    const bool same =
        state.forward && state.forward->map == map && state.forward->mip_levels == mip_levels;
    if (!same) state.forward = forward_table(map, mip_levels);
    if (reused) *reused = same;
    return *state.forward;
}

glm::vec2 frame_gaze(const FrameContext& ctx) { return frame_log_polar_map(ctx).gaze; }

std::vector<std::string> shade_inputs(const std::string& prefix) {
    return {prefix + "world_position", prefix + "shading_normal", prefix + "geometric_normal",
            prefix + "albedo",         prefix + "material_id",    prefix + "primitive_id"};
}

/// The shading pass over one G-buffer (log-polar or gaze), as basic's shade_direct stage.
/// `window`: where the buffer lies on the screen (the gaze buffer), null for the log-polar one.
Image shade_gbuffer(FrameContext& ctx, const std::string& prefix,
                    const ScreenWindow* window = nullptr) {
    FoveatedModeState& state = ctx.mode_state<FoveatedModeState>();
    const Scene& scene = *ctx.scene;
    ShadeInputs inputs = shade_inputs_of(ctx, prefix);
    inputs.window = window;
    const Bvh* tree = scene.lights.empty() ? nullptr : &state.bvh.get(scene, ctx.result->counters);
    ShadingStats stats;
    Image out = shade_basic(scene, tree, inputs, ctx.camera, ctx.frame, stats);
    add_shading_counters(ctx.result->counters, stats);
    ctx.note = shadow_note(scene);
    return out;
}

void add_mask(FrameResult& result, const std::string& name, Image mask) {
    result.add(name, BufferKind::id, {"valid"}, std::move(mask));
}

// The buffer counters every log-polar frame reports (names read by scripts).
void add_buffer_counters(FrameContext& ctx, const LogPolarMap& map,
                         const FoveatedTraceStats& stats) {
    Counters& counters = ctx.result->counters;
    counters.add("buffer_width", map.width);
    counters.add("buffer_height", map.height);
    counters.add("texels_traced", stats.texels_traced);
    counters.add("texels_off_screen", stats.texels_off_screen);
    if (stats.texels_inside_gaze > 0) counters.add("texels_inside_gaze", stats.texels_inside_gaze);
}

// The clamp-buffer boxes of a frame (W x H x 6), as TAA reads them.
void add_taa_bounds(FrameContext& ctx, Image bounds) {
    ctx.result->add("taa_bounds", BufferKind::scalar,
                    {"min_r", "min_g", "min_b", "max_r", "max_g", "max_b"}, std::move(bounds));
}

// ", jittered to (x, y) in each texel" (nothing without jitter).
std::string jitter_note(Offset2 jitter, const char* unit) {
    if (jitter == Offset2{}) return "";
    char text[96];
    std::snprintf(text, sizeof text, ", jittered to (%.9g, %.9g) in each %s",
                  static_cast<double>(jitter.x), static_cast<double>(jitter.y), unit);
    return text;
}

// "gaze (x, y), w x h texels, K = x^a": the buffer stage's note.
std::string map_note(const LogPolarMap& map) {
    char gaze[64];
    std::snprintf(gaze, sizeof gaze, "gaze (%.9g, %.9g), ", static_cast<double>(map.gaze.x),
                  static_cast<double>(map.gaze.y));
    return gaze + std::to_string(map.width) + "x" + std::to_string(map.height) +
           " texels, K = " + kernel_text(map.kernel);
}

}  // namespace

LogPolarMap frame_log_polar_map(const FrameContext& ctx) {
    const FoveatedModeState& state = ctx.mode_state<FoveatedModeState>();
    return foveated_map(state.params, *ctx.scene, ctx.camera, ctx.settings->width,
                        ctx.settings->height, ctx.frame);
}

void lp_trace_stage(FrameContext& ctx) {
    FoveatedModeState& state = ctx.mode_state<FoveatedModeState>();
    const LogPolarMap map = frame_log_polar_map(ctx);
    Counters& counters = ctx.result->counters;
    FoveatedTraceStats stats;
    Image screen_points;
    const Offset2 jitter = frame_jitter(ctx);
    MaskedGBuffer lp =
        trace_lp_gbuffer(map, *ctx.scene, state.bvh.get(*ctx.scene, counters), ctx.camera,
                         ctx.previous_camera, screen_points, stats, jitter);
    add_buffer_counters(ctx, map, stats);
    add_trace_counters(counters, "primary", stats.rays.primary);
    ctx.note = map_note(map) + ", " + std::to_string(stats.texels_traced) + " traced" +
               jitter_note(jitter, "texel");
    add_gbuffer(*ctx.result, std::move(lp.gbuffer), "lp_gbuffer_");
    add_mask(*ctx.result, "lp_valid", std::move(lp.valid));
    ctx.result->add("lp_screen_point", BufferKind::scalar, {"x", "y"}, std::move(screen_points));
}

void gaze_trace_stage(FrameContext& ctx) {
    FoveatedModeState& state = ctx.mode_state<FoveatedModeState>();
    const LogPolarMap map = frame_log_polar_map(ctx);
    Counters& counters = ctx.result->counters;
    FoveatedTraceStats stats;
    const Offset2 jitter = frame_jitter(ctx);
    MaskedGBuffer gaze = trace_gaze_gbuffer(map, *ctx.scene, state.bvh.get(*ctx.scene, counters),
                                            ctx.camera, ctx.previous_camera, stats, jitter);
    counters.add("gaze_radius_px", static_cast<std::int64_t>(std::round(map.gaze_radius)));
    counters.add("gaze_pixels_traced", stats.gaze_pixels_traced);
    // Where the gaze buffer lies on the screen (its size is the buffers' size).
    const ScreenWindow window = gaze_window(map);
    counters.add("gaze_window_x0", window.x0);
    counters.add("gaze_window_y0", window.y0);
    add_trace_counters(counters, "primary", stats.rays.primary);
    ctx.note = "r_G = " + std::to_string(map.gaze_radius) + " px, " +
               std::to_string(stats.gaze_pixels_traced) + " pixels traced" +
               jitter_note(jitter, "pixel");
    add_gbuffer(*ctx.result, std::move(gaze.gbuffer), "gaze_gbuffer_");
    add_mask(*ctx.result, "gaze_valid", std::move(gaze.valid));
}

void lp_shade_stage(FrameContext& ctx) {
    ctx.result->add("lp_color", BufferKind::color, {"r", "g", "b"},
                    shade_gbuffer(ctx, "lp_gbuffer_"));
}

void gaze_shade_stage(FrameContext& ctx) {
    const ScreenWindow window = gaze_window(frame_log_polar_map(ctx));
    ctx.result->add("gaze_color", BufferKind::color, {"r", "g", "b"},
                    shade_gbuffer(ctx, "gaze_gbuffer_", &window));
}

void resolve_stage(FrameContext& ctx) {
    FoveatedModeState& state = ctx.mode_state<FoveatedModeState>();
    const LogPolarMap map = frame_log_polar_map(ctx);
    const GazeInput gaze =
        gaze_input(map, map.has_gaze_buffer() ? &ctx.input("gaze_color") : nullptr);
    const Image& color = ctx.input(resolve_color_name(state.params));
    const Image& valid = ctx.input("lp_valid");
    ResolveStats stats;
    std::vector<MipLevel> mips;
    if (state.params.mip_resolve) mips = build_lp_mips(color, valid);
    bool reused = false;
    const ForwardTable& table =
        frame_forward_table(state, map, static_cast<int>(mips.size()), &reused);
    Image out = state.params.mip_resolve
                    ? resolve_log_polar_mip(map, mips, gaze, stats, &table)
                    : resolve_log_polar(map, {color, valid, gaze}, stats, &table);
    ctx.result->counters.add("screen_pixels_untraced_taps", stats.pixels_untraced_taps);
    ctx.note = std::string(state.params.mip_resolve ? "mip" : "bilinear") +
               (reused ? ", forward map reused" : ", forward map computed") + ": " +
               std::to_string(stats.pixels_from_gaze) + " pixels from the gaze buffer, " +
               std::to_string(stats.pixels_from_buffer) + " from the log-polar buffer";
    ctx.result->add(state.chain.front(), BufferKind::color, {"r", "g", "b"}, std::move(out));
}

// The TAA inputs from the buffers (the gaze buffer's when there is one).
TaaBufferInputs taa_buffer_inputs(FrameContext& ctx, const LogPolarMap& map) {
    FoveatedModeState& state = ctx.mode_state<FoveatedModeState>();
    const int levels = state.forward ? state.forward->mip_levels : 0;
    return {map, frame_forward_table(state, map, levels), ctx.input("lp_valid"),
            map.has_gaze_buffer() ? &ctx.input("gaze_valid") : nullptr};
}

void taa_source_stage(FrameContext& ctx) {
    const FoveatedModeState& state = ctx.mode_state<FoveatedModeState>();
    const LogPolarMap map = frame_log_polar_map(ctx);
    const TaaBufferInputs in = taa_buffer_inputs(ctx, map);
    const bool boxes = state.taa.mode == TaaMode::clamp_buffer;
    std::optional<TaaBoxColors> colors;
    if (boxes)
        colors.emplace(TaaBoxColors{ctx.input(resolve_color_name(state.params)),
                                    in.gaze_valid ? &ctx.input("gaze_color") : nullptr,
                                    ctx.input(state.chain.front())});
    TaaSourceOutputs out =
        taa_source_pass(in, ctx.input("lp_gbuffer_view_depth"),
                        in.gaze_valid ? &ctx.input("gaze_gbuffer_view_depth") : nullptr,
                        colors ? &*colors : nullptr);
    ctx.note = std::string("the texel pass 2 sampled (nearest traced tap): ") +
               (state.params.deferred ? "its 3x3 box in the buffer"
                : boxes               ? "its view depth and its 3x3 box in the buffer"
                                      : "its view depth");
    // kfr reads the depth of its full-resolution G-buffer: its taa_source gives the boxes only.
    if (!state.params.deferred)
        ctx.result->add("taa_view_depth", BufferKind::depth, {"z"}, std::move(out.depth));
    if (boxes) add_taa_bounds(ctx, std::move(out.bounds));
}

void gbuffer_raster_stage(FrameContext& ctx) {
    const FoveatedModeState& state = ctx.mode_state<FoveatedModeState>();
    const RenderSettings& s = *ctx.settings;
    RasterStats stats;
    GBuffer g = rasterize_gbuffer(*ctx.scene, ctx.camera, ctx.previous_camera, s.width, s.height,
                                  stats, state.params.raster);
    add_raster_counters(ctx.result->counters, stats);
    ctx.note =
        std::string("rasterized, fill rule ") + fill_rule_name(state.params.raster.fill_rule);
    add_gbuffer(*ctx.result, std::move(g));
}

void lp_sample_stage(FrameContext& ctx) {
    const LogPolarMap map = frame_log_polar_map(ctx);
    const ScreenGBuffer screen{ctx.input("gbuffer_view_depth"),
                               ctx.input("gbuffer_hit_distance"),
                               ctx.input("gbuffer_world_position"),
                               ctx.input("gbuffer_shading_normal"),
                               ctx.input("gbuffer_geometric_normal"),
                               ctx.input("gbuffer_albedo"),
                               ctx.input("gbuffer_material_id"),
                               ctx.input("gbuffer_primitive_id"),
                               ctx.input("gbuffer_motion")};
    FoveatedTraceStats stats;
    Image screen_points;
    // Meng's TAA jitter comes after the inverse transform: o - (1/2, 1/2) screen pixels.
    const Offset2 jitter = frame_jitter(ctx);
    MaskedGBuffer lp =
        sample_lp_gbuffer(map, screen, screen_points, stats, {jitter.x - 0.5f, jitter.y - 0.5f});
    add_buffer_counters(ctx, map, stats);
    ctx.note =
        map_note(map) + ", " + std::to_string(stats.texels_traced) +
        " sampled from the rasterized G-buffer" +
        (jitter == Offset2{} ? std::string()
                             : ", screen points offset by (" + std::to_string(jitter.x - 0.5f) +
                                   ", " + std::to_string(jitter.y - 0.5f) + ") px");
    add_gbuffer(*ctx.result, std::move(lp.gbuffer), "lp_gbuffer_");
    add_mask(*ctx.result, "lp_valid", std::move(lp.valid));
    ctx.result->add("lp_screen_point", BufferKind::scalar, {"x", "y"}, std::move(screen_points));
}

void internal_aa_stage(FrameContext& ctx) {
    ctx.result->add("lp_color_aa", BufferKind::color, {"r", "g", "b"},
                    internal_aa(ctx.input("lp_color"), ctx.input("lp_valid")));
}

void gaussian_lerp_stage(FrameContext& ctx) {
    const FoveatedModeState& state = ctx.mode_state<FoveatedModeState>();
    const LogPolarMap map = frame_log_polar_map(ctx);
    const std::size_t k = state.lerp_link;
    ctx.result->add(state.chain[k + 1], BufferKind::color, {"r", "g", "b"},
                    gaussian_lerp(ctx.input(state.chain[k]), map.gaze));
}

void post_aa_stage(FrameContext& ctx) {
    const FoveatedModeState& state = ctx.mode_state<FoveatedModeState>();
    const LogPolarMap map = frame_log_polar_map(ctx);
    ctx.result->add("final", BufferKind::color, {"r", "g", "b"},
                    post_aa(ctx.input(state.chain[state.post_aa_link]), map.gaze, map.radius_max));
}

void ray_positions_stage(FrameContext& ctx) {
    const LogPolarMap map = frame_log_polar_map(ctx);
    const Image* gaze_valid = map.has_gaze_buffer() ? &ctx.input("gaze_valid") : nullptr;
    ctx.result->add(
        "ray_positions", BufferKind::scalar, {"rays"},
        ray_position_counts(map.screen_width, map.screen_height, ctx.input("lp_valid"),
                            ctx.input("lp_screen_point"), gaze_valid, gaze_window(map)));
}

std::vector<PixelFunction> foveated_pixel_functions(const Params& params) {
    std::vector<PixelFunction> functions = {
        {"lp_trace", "fovref::lp_gbuffer_texel", "x, y: the texel (i, j)"},
        {"gaze_trace", "fovref::gaze_gbuffer_pixel", "composite modes only"},
        {"lp_shade", "fovref::shade_basic_pixel", "x, y: the texel (i, j)"},
        {"resolve", "fovref::resolve_pixel", ""}};
    if (parse_taa_params(params).enabled())
        functions.push_back({"taa", "fovref::taa_pixel", "once per frame, frames 0 .. F"});
    return functions;
}

Pipeline foveated_pipeline(const std::string& preset_name, const Scene*,
                           const RenderSettings& settings) {
    const FoveationPreset& preset = find_foveation_preset(preset_name);
    auto state = std::make_shared<FoveatedModeState>();
    state->params = parse_foveated_params(settings.params, preset);
    const FoveatedParams& params = state->params;
    // Validate the map's parameters now (the buffer size, a_G), not in the first stage.
    log_polar_buffer_size(params.map, settings.width, settings.height);
    const bool composite = params.map.gaze_angle > 0.0f;
    std::vector<std::string> lp_outputs = gbuffer_names("lp_gbuffer_");
    lp_outputs.push_back("lp_valid");
    lp_outputs.push_back("lp_screen_point");
    std::vector<std::string> gaze_outputs = gbuffer_names("gaze_gbuffer_");
    gaze_outputs.push_back("gaze_valid");

    Pipeline p;
    p.state = state;
    // The buffers' G-buffers: traced, or sampled from the rasterized screen G-buffer.
    if (params.deferred) {
        p.stages.push_back({"gbuffer_raster", {}, gbuffer_names(), gbuffer_raster_stage});
        p.stages.push_back({"lp_sample", gbuffer_names(), lp_outputs, lp_sample_stage});
    } else {
        p.stages.push_back({"lp_trace", {}, lp_outputs, lp_trace_stage});
    }
    if (composite) p.stages.push_back({"gaze_trace", {}, gaze_outputs, gaze_trace_stage});
    // Shading in the buffers, buffer-space filters.
    p.stages.push_back({"lp_shade", shade_inputs("lp_gbuffer_"), {"lp_color"}, lp_shade_stage});
    if (composite)
        p.stages.push_back(
            {"gaze_shade", shade_inputs("gaze_gbuffer_"), {"gaze_color"}, gaze_shade_stage});
    if (params.internal_aa)
        p.stages.push_back(
            {"internal_aa", {"lp_color", "lp_valid"}, {"lp_color_aa"}, internal_aa_stage});
    // Pass 2, TAA, then the screen-space filters (SPEC §6).
    state->taa = parse_taa_params(settings.params);
    state->gaze = frame_gaze;
    std::vector<std::string>& chain = state->chain;
    chain = screen_chain(params, state->taa.enabled());
    std::vector<std::string> resolve_inputs = {resolve_color_name(params), "lp_valid"};
    if (composite) resolve_inputs.push_back("gaze_color");
    p.stages.push_back({"resolve", resolve_inputs, {chain[0]}, resolve_stage});
    std::size_t link = 0;
    if (state->taa.enabled()) {
        // The texel pass 2 sampled: the depth (kfr has its full-resolution G-buffer's) and, for
        // clamp-buffer, the box in the buffer.
        const bool boxes = state->taa.mode == TaaMode::clamp_buffer;
        std::string depth = "gbuffer_view_depth", bounds;
        if (!params.deferred || boxes) {
            std::vector<std::string> inputs = {"lp_gbuffer_view_depth", "lp_valid"};
            std::vector<std::string> outputs;
            if (!params.deferred) outputs.push_back("taa_view_depth");
            if (composite) {
                inputs.push_back("gaze_gbuffer_view_depth");
                inputs.push_back("gaze_valid");
            }
            if (boxes) {
                inputs.push_back(resolve_color_name(params));
                inputs.push_back(chain[0]);
                if (composite) inputs.push_back("gaze_color");
                outputs.push_back("taa_bounds");
                bounds = "taa_bounds";
            }
            p.stages.push_back({"taa_source", inputs, outputs, taa_source_stage});
            if (!params.deferred) depth = "taa_view_depth";
        }
        add_taa_stage(p, *state, chain[0], depth, bounds, chain[1]);
        ++link;
    }
    if (params.gaussian_lerp) {
        state->lerp_link = link;
        p.stages.push_back(
            {"gaussian_lerp", {chain[link]}, {chain[link + 1]}, gaussian_lerp_stage});
        ++link;
    }
    if (params.post_aa) {
        state->post_aa_link = link;
        p.stages.push_back({"post_aa", {chain[link]}, {chain[link + 1]}, post_aa_stage});
    }
    std::vector<std::string> position_inputs = {"lp_valid", "lp_screen_point"};
    if (composite) position_inputs.push_back("gaze_valid");
    p.stages.push_back({"ray_positions", position_inputs, {"ray_positions"}, ray_positions_stage});
    p.final_outputs = {"final"};
    return p;
}

namespace {

struct StereoModeState : TaaModeState {
    StereoParams params;
    BvhCache bvh;
    std::optional<StereoForwardTable> forward;  ///< pass 2's lookups, kept while the maps stay
    /// TAA runs on each eye's sub-screen with its own camera, gaze and history.
    std::array<TaaState, 2> eye_history;
    std::array<std::optional<ForwardTable>, 2> eye_forward;  ///< each eye's map (TAA's source)
};

// This frame's two eye maps and cameras (and the previous frame's cameras, for motion).
std::array<LogPolarMap, 2> frame_stereo_maps(const FrameContext& ctx) {
    const StereoModeState& state = ctx.mode_state<StereoModeState>();
    return stereo_maps(state.params, *ctx.scene, ctx.camera, ctx.settings->width,
                       ctx.settings->height, ctx.frame);
}

std::array<Camera, 2> eye_cameras(const Camera& camera, float ipd) {
    return {eye_camera(camera, 0, ipd), eye_camera(camera, 1, ipd)};
}

}  // namespace

void stereo_trace_stage(FrameContext& ctx) {
    StereoModeState& state = ctx.mode_state<StereoModeState>();
    const std::array<LogPolarMap, 2> maps = frame_stereo_maps(ctx);
    Counters& counters = ctx.result->counters;
    FoveatedTraceStats stats;
    Image screen_points;
    const Offset2 jitter = frame_jitter(ctx);
    MaskedGBuffer lp = trace_stereo_gbuffer(maps, *ctx.scene, state.bvh.get(*ctx.scene, counters),
                                            eye_cameras(ctx.camera, state.params.ipd),
                                            eye_cameras(ctx.previous_camera, state.params.ipd),
                                            screen_points, stats, jitter);
    add_buffer_counters(ctx, maps[0], stats);
    counters.add("eyes", 2);
    add_trace_counters(counters, "primary", stats.rays.primary);
    ctx.note = "eye 0: " + map_note(maps[0]) + "; eye 1: " + map_note(maps[1]) + "; " +
               std::to_string(stats.texels_traced) + " traced" + jitter_note(jitter, "texel");
    add_gbuffer(*ctx.result, std::move(lp.gbuffer), "lp_gbuffer_");
    add_mask(*ctx.result, "lp_valid", std::move(lp.valid));
    ctx.result->add("lp_screen_point", BufferKind::scalar, {"x", "y"}, std::move(screen_points));
}

void stereo_shade_stage(FrameContext& ctx) {
    StereoModeState& state = ctx.mode_state<StereoModeState>();
    const Scene& scene = *ctx.scene;
    const ShadeInputs inputs = shade_inputs_of(ctx, "lp_gbuffer_");
    const Bvh* tree = scene.lights.empty() ? nullptr : &state.bvh.get(scene, ctx.result->counters);
    ShadingStats stats;
    Image out = shade_stereo(scene, tree, inputs, eye_cameras(ctx.camera, state.params.ipd),
                             inputs.position.width / 2, ctx.frame, stats);
    add_shading_counters(ctx.result->counters, stats);
    ctx.note = shadow_note(scene);
    ctx.result->add("lp_color", BufferKind::color, {"r", "g", "b"}, std::move(out));
}

void stereo_resolve_stage(FrameContext& ctx) {
    StereoModeState& state = ctx.mode_state<StereoModeState>();
    const std::array<LogPolarMap, 2> maps = frame_stereo_maps(ctx);
    const bool reused = state.forward && state.forward->made_for(state.params, maps);
    if (!reused) state.forward = stereo_forward_table(state.params, maps);
    StereoResolveStats stats;
    Image out = resolve_stereo(state.params, maps, ctx.input("lp_color"), ctx.input("lp_valid"),
                               stats, &*state.forward);
    ctx.result->counters.add("screen_pixels_untraced_taps", stats.resolve.pixels_untraced_taps);
    if (state.params.barrel)
        ctx.result->counters.add("screen_pixels_outside_lens", stats.pixels_outside_lens);
    ctx.note = std::string(state.params.barrel ? "bilinear, barrel distortion" : "bilinear") +
               (reused ? ", lookups reused" : ", lookups computed");
    ctx.result->add(state.taa.enabled() ? "resolved" : "final", BufferKind::color, {"r", "g", "b"},
                    std::move(out));
}

// TAA of stereo-lp: each eye's W/2 x H half of the screen on its own, as a frame of its own
// (its camera, its gaze, its log-polar map, its history), then the halves side by side.
void stereo_taa_source_stage(FrameContext& ctx) {
    StereoModeState& state = ctx.mode_state<StereoModeState>();
    const std::array<LogPolarMap, 2> maps = frame_stereo_maps(ctx);
    const int w = maps[0].width, eye_width = maps[0].screen_width;
    const bool boxes = state.taa.mode == TaaMode::clamp_buffer;
    Image depth(ctx.settings->width, ctx.settings->height, 1, 0.0f), bounds;
    if (boxes) bounds = Image(ctx.settings->width, ctx.settings->height, 6, 0.0f);
    for (int e = 0; e < 2; ++e) {
        std::optional<ForwardTable>& table = state.eye_forward[static_cast<std::size_t>(e)];
        if (!table || !(table->map == maps[static_cast<std::size_t>(e)]))
            table = forward_table(maps[static_cast<std::size_t>(e)]);
        const Image valid = image_columns(ctx.input("lp_valid"), e * w, w);
        const Image lp_depth = image_columns(ctx.input("lp_gbuffer_view_depth"), e * w, w);
        // The colours only for clamp-buffer's boxes.
        const Image lp_color = boxes ? image_columns(ctx.input("lp_color"), e * w, w) : Image();
        const Image screen =
            boxes ? image_columns(ctx.input("resolved"), e * eye_width, eye_width) : Image();
        const TaaBoxColors colors{lp_color, nullptr, screen};
        const TaaSourceOutputs out =
            taa_source_pass({maps[static_cast<std::size_t>(e)], *table, valid, nullptr}, lp_depth,
                            nullptr, boxes ? &colors : nullptr);
        set_image_columns(depth, e * eye_width, out.depth);
        if (boxes) set_image_columns(bounds, e * eye_width, out.bounds);
    }
    ctx.note = "per eye: the texel pass 2 sampled (nearest traced tap)";
    ctx.result->add("taa_view_depth", BufferKind::depth, {"z"}, std::move(depth));
    if (boxes) add_taa_bounds(ctx, std::move(bounds));
}

void stereo_taa_stage(FrameContext& ctx) {
    StereoModeState& state = ctx.mode_state<StereoModeState>();
    const std::array<LogPolarMap, 2> maps = frame_stereo_maps(ctx);
    const int eye_width = maps[0].screen_width;
    const std::array<Camera, 2> cameras = eye_cameras(ctx.camera, state.params.ipd);
    const std::array<Camera, 2> previous = eye_cameras(ctx.previous_camera, state.params.ipd);
    const bool boxes = state.taa.mode == TaaMode::clamp_buffer;
    Image out(ctx.settings->width, ctx.settings->height, 3, 0.0f);
    Image age(ctx.settings->width, ctx.settings->height, 1, 0.0f);
    TaaStats stats;
    for (int e = 0; e < 2; ++e) {
        const auto x0 = e * eye_width;
        const Image color = image_columns(ctx.input("resolved"), x0, eye_width);
        const Image depth = image_columns(ctx.input("taa_view_depth"), x0, eye_width);
        const Image bounds =
            boxes ? image_columns(ctx.input("taa_bounds"), x0, eye_width) : Image();
        TaaState& history = state.eye_history[static_cast<std::size_t>(e)];
        if (!history.valid && ctx.has_previous) {
            // Resumed: the previous frame's halves from its dumped buffers.
            const TaaState whole = resumed_taa_state(ctx, "final", "taa_view_depth");
            history = next_taa_state(image_columns(whole.history, x0, eye_width),
                                     image_columns(whole.age, x0, eye_width),
                                     image_columns(whole.depth, x0, eye_width),
                                     previous[static_cast<std::size_t>(e)]);
        }
        const TaaInputs in{color, depth, cameras[static_cast<std::size_t>(e)],
                           maps[static_cast<std::size_t>(e)].gaze, boxes ? &bounds : nullptr};
        Image eye_out, eye_age;
        taa(state.taa.params, in, history, eye_out, eye_age, stats);
        set_image_columns(out, x0, eye_out);
        set_image_columns(age, x0, eye_age);
        history = next_taa_state(std::move(eye_out), std::move(eye_age), depth,
                                 cameras[static_cast<std::size_t>(e)]);
    }
    add_taa_counters(ctx, stats);
    ctx.note = std::string(taa_mode_name(state.taa.mode)) + ", each eye on its own";
    ctx.result->add("final", BufferKind::color, {"r", "g", "b"}, std::move(out));
    ctx.result->add("taa_age", BufferKind::scalar, {"age"}, std::move(age));
}

void stereo_ray_positions_stage(FrameContext& ctx) {
    ctx.result->add(
        "ray_positions", BufferKind::scalar, {"rays"},
        ray_position_counts(ctx.settings->width, ctx.settings->height, ctx.input("lp_valid"),
                            ctx.input("lp_screen_point"), nullptr));
}

Pipeline stereo_pipeline(const Scene*, const RenderSettings& settings) {
    auto state = std::make_shared<StereoModeState>();
    state->params = parse_stereo_params(settings.params);
    state->taa = parse_taa_params(settings.params);
    if (state->taa.enabled() && state->params.barrel)
        throw Error(std::string("parameter 'taa': ") + taa_mode_name(state->taa.mode) +
                    " with barrel=on is not supported yet (TAA would have to run before the "
                    "distortion that pass 2 applies): use barrel=off");
    log_polar_buffer_size(state->params.eye.map, stereo_eye_width(settings.width), settings.height);
    std::vector<std::string> lp_outputs = gbuffer_names("lp_gbuffer_");
    lp_outputs.push_back("lp_valid");
    lp_outputs.push_back("lp_screen_point");
    Pipeline p;
    p.state = state;
    p.stages.push_back({"stereo_trace", {}, lp_outputs, stereo_trace_stage});
    p.stages.push_back(
        {"stereo_shade", shade_inputs("lp_gbuffer_"), {"lp_color"}, stereo_shade_stage});
    const bool taa = state->taa.enabled();
    p.stages.push_back(
        {"resolve", {"lp_color", "lp_valid"}, {taa ? "resolved" : "final"}, stereo_resolve_stage});
    if (taa) {
        const bool boxes = state->taa.mode == TaaMode::clamp_buffer;
        std::vector<std::string> outputs = {"taa_view_depth"};
        if (boxes) outputs.push_back("taa_bounds");
        p.stages.push_back({"taa_source",
                            {"lp_gbuffer_view_depth", "lp_valid", "lp_color", "resolved"},
                            outputs,
                            stereo_taa_source_stage});
        std::vector<std::string> inputs = {"resolved", "taa_view_depth"};
        if (boxes) inputs.push_back("taa_bounds");
        p.stages.push_back({"taa", inputs, {"final", "taa_age"}, stereo_taa_stage});
    }
    p.stages.push_back({"ray_positions",
                        {"lp_valid", "lp_screen_point"},
                        {"ray_positions"},
                        stereo_ray_positions_stage});
    p.final_outputs = {"final"};
    return p;
}

std::vector<PixelFunction> stereo_pixel_functions(const Params& params) {
    std::vector<PixelFunction> functions = {
        {"stereo_trace", "fovref::stereo_gbuffer_texel", "x, y: the texel of both eyes' buffer"},
        {"stereo_shade", "fovref::shade_basic_pixel", "x, y: the texel"},
        {"resolve", "fovref::resolve_stereo_pixel", ""}};
    if (parse_taa_params(params).enabled())
        functions.push_back({"taa", "fovref::taa_pixel", "x, y: the pixel within its eye"});
    return functions;
}

Pipeline fov_pipeline(const Scene* scene, const RenderSettings& settings) {
    return foveated_pipeline("fov", scene, settings);
}
Pipeline kfov_pipeline(const Scene* scene, const RenderSettings& settings) {
    return foveated_pipeline("kfov", scene, settings);
}
Pipeline cfov_pipeline(const Scene* scene, const RenderSettings& settings) {
    return foveated_pipeline("cfov", scene, settings);
}
Pipeline ckfov_pipeline(const Scene* scene, const RenderSettings& settings) {
    return foveated_pipeline("ckfov", scene, settings);
}
Pipeline kfr_pipeline(const Scene* scene, const RenderSettings& settings) {
    return foveated_pipeline("kfr", scene, settings);
}

}  // namespace fovref
