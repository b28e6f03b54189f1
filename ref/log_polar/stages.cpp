#include "ref/log_polar/stages.h"

#include <cmath>
#include <cstdio>
#include <utility>

#include "ref/log_polar/deferred_sample.h"
#include "ref/log_polar/mip_resolve.h"
#include "ref/log_polar/trace.h"

namespace fovref {

namespace {

struct LogPolarState : StageState {
    LogPolarStage shared;
};

struct StereoState : StageState {
    StereoStage shared;
};

std::shared_ptr<LogPolarState> lp_state(const LogPolarStage& shared) {
    auto state = std::make_shared<LogPolarState>();
    state->shared = shared;
    return state;
}

std::shared_ptr<StereoState> stereo_state(const StereoStage& shared) {
    auto state = std::make_shared<StereoState>();
    state->shared = shared;
    return state;
}

Offset2 frame_jitter(const FrameContext& ctx, const FrameJitter& jitter) {
    return jitter ? jitter(ctx) : Offset2{};
}

// A buffer's G-buffer, mask and screen points: what lp_trace, lp_sample and stereo_trace write.
std::vector<Port> buffer_outputs() {
    std::vector<Port> ports = gbuffer_ports("lp_gbuffer_");
    ports.emplace_back("valid", "lp_valid");
    ports.emplace_back("screen_point", "lp_screen_point");
    return ports;
}

void output_buffer(const FrameContext& ctx, MaskedGBuffer lp, Image screen_points) {
    output_gbuffer(ctx, std::move(lp.gbuffer));
    ctx.output("valid", BufferKind::id, {"valid"}, std::move(lp.valid));
    ctx.output("screen_point", BufferKind::scalar, {"x", "y"}, std::move(screen_points));
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

LogPolarMap LogPolarFrames::map(const FrameContext& ctx) const {
    return foveated_map(params, *ctx.scene, ctx.camera, ctx.settings->width, ctx.settings->height,
                        ctx.frame);
}

const ForwardTable& LogPolarFrames::forward_table(const LogPolarMap& map, int mip_levels,
                                                  bool* reused) {
    const bool same = forward && forward->map == map && forward->mip_levels == mip_levels;
    if (!same) forward = fovref::forward_table(map, mip_levels);
    if (reused) *reused = same;
    return *forward;
}

std::function<ScreenWindow(const FrameContext&)> gaze_window_of(
    std::shared_ptr<LogPolarFrames> frames) {
    return [frames](const FrameContext& ctx) { return gaze_window(frames->map(ctx)); };
}

std::function<glm::vec2(const FrameContext&)> gaze_of(std::shared_ptr<LogPolarFrames> frames) {
    return [frames](const FrameContext& ctx) { return frames->map(ctx).gaze; };
}

void lp_trace_stage(FrameContext& ctx) {
    const LogPolarStage& s = ctx.state<LogPolarState>().shared;
    const LogPolarMap map = s.frames->map(ctx);
    Counters& counters = ctx.result->counters;
    FoveatedTraceStats stats;
    Image screen_points;
    const Offset2 jitter = frame_jitter(ctx, s.jitter);
    MaskedGBuffer lp =
        trace_lp_gbuffer(map, primary_view(ctx, *s.bvh), screen_points, stats, jitter);
    add_buffer_counters(ctx, map, stats);
    add_trace_counters(counters, "primary", stats.rays.primary);
    ctx.note = map_note(map) + ", " + std::to_string(stats.texels_traced) + " traced" +
               jitter_note(jitter, "texel");
    output_buffer(ctx, std::move(lp), std::move(screen_points));
}

StageDef lp_trace_stage_def(const LogPolarStage& shared) {
    return {"lp_trace", {}, buffer_outputs(), lp_trace_stage, lp_state(shared)};
}

void lp_sample_stage(FrameContext& ctx) {
    const LogPolarStage& s = ctx.state<LogPolarState>().shared;
    const LogPolarMap map = s.frames->map(ctx);
    FoveatedTraceStats stats;
    Image screen_points;
    // The TAA jitter: the rasterizer's sample moved (the nearest jittered sample copied), or
    // the texels' points shifted by o - (1/2, 1/2) (raster_jitter=lookup)
    const Offset2 jitter = frame_jitter(ctx, s.jitter);
    const FoveatedParams& params = s.frames->params;
    const glm::vec2 offset = deferred_sample_offset(params.jitter_raster, jitter);
    // The rasterizer's frame as gbuffer_raster made it (its settings, its sample under TAA)
    RasterSettings raster = params.raster;
    if (params.jitter_raster) raster.sample = jitter;
    const Scene& scene = *ctx.scene;
    if (scene.triangle_count() > (std::size_t{1} << 24))
        throw Error(
            "mode with primary=raster (kfr): lp_sample reads the rasterized G-buffer's "
            "primitive ids, which are exact below 2^24 = 16777216 triangles; the scene "
            "has " +
            std::to_string(scene.triangle_count()));
    const RasterizedScreen screen{
        scene, ctx.input("primitive_id"),
        make_raster_frame(scene, ctx.camera, ctx.settings->width, ctx.settings->height, raster),
        ctx.previous_camera, tan_half_vfov(ctx.previous_camera)};
    MaskedGBuffer lp = sample_lp_gbuffer(map, screen, screen_points, stats, offset);
    add_buffer_counters(ctx, map, stats);
    ctx.note = map_note(map) + ", " + std::to_string(stats.texels_traced) +
               " sampled from the rasterized G-buffer" +
               (jitter == Offset2{} ? std::string()
                                    : ", screen points offset by (" + std::to_string(offset.x) +
                                          ", " + std::to_string(offset.y) + ") px");
    output_buffer(ctx, std::move(lp), std::move(screen_points));
}

StageDef lp_sample_stage_def(const LogPolarStage& shared) {
    return {"lp_sample",
            {{"primitive_id", "gbuffer_primitive_id"}},
            buffer_outputs(),
            lp_sample_stage,
            lp_state(shared)};
}

void gaze_trace_stage(FrameContext& ctx) {
    const LogPolarStage& s = ctx.state<LogPolarState>().shared;
    const LogPolarMap map = s.frames->map(ctx);
    Counters& counters = ctx.result->counters;
    FoveatedTraceStats stats;
    const Offset2 jitter = frame_jitter(ctx, s.jitter);
    MaskedGBuffer gaze = trace_gaze_gbuffer(map, primary_view(ctx, *s.bvh), stats, jitter);
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
    output_gbuffer(ctx, std::move(gaze.gbuffer));
    ctx.output("valid", BufferKind::id, {"valid"}, std::move(gaze.valid));
}

StageDef gaze_trace_stage_def(const LogPolarStage& shared) {
    std::vector<Port> outputs = gbuffer_ports("gaze_gbuffer_");
    outputs.emplace_back("valid", "gaze_valid");
    return {"gaze_trace", {}, outputs, gaze_trace_stage, lp_state(shared)};
}

void resolve_stage(FrameContext& ctx) {
    const LogPolarStage& s = ctx.state<LogPolarState>().shared;
    LogPolarFrames& frames = *s.frames;
    const LogPolarMap map = frames.map(ctx);
    const GazeInput gaze = gaze_input(map, map.has_gaze_buffer() ? &ctx.input("gaze") : nullptr);
    const Image& color = ctx.input("color");
    const Image& valid = ctx.input("valid");
    ResolveStats stats;
    std::vector<MipLevel> mips;
    const bool mip = frames.params.mip_resolve;
    if (mip) mips = build_lp_mips(color, valid);
    bool reused = false;
    const ForwardTable& table = frames.forward_table(map, static_cast<int>(mips.size()), &reused);
    // The pass writes every pixel: an earlier frame's storage saves the zero fill
    Image storage = ctx.recycled("output", map.screen_width, map.screen_height, color.channels);
    Image out =
        mip ? resolve_log_polar_mip(map, mips, gaze, stats, &table, std::move(storage))
            : resolve_log_polar(map, {color, valid, gaze}, stats, &table, std::move(storage));
    ctx.result->counters.add("screen_pixels_untraced_taps", stats.pixels_untraced_taps);
    ctx.note = std::string(mip ? "mip" : "bilinear") +
               (reused ? ", forward map reused" : ", forward map computed") + ": " +
               std::to_string(stats.pixels_from_gaze) + " pixels from the gaze buffer, " +
               std::to_string(stats.pixels_from_buffer) + " from the log-polar buffer";
    ctx.output("output", BufferKind::color, {"r", "g", "b"}, std::move(out));
    if (wants_resolve_decisions(ctx))
        output_resolve_decisions(ctx, lp_resolve_decisions(table, gaze, color.width, color.height));
}

StageDef resolve_stage_def(const LogPolarStage& shared, std::string color, std::string output) {
    std::vector<Port> inputs = {{"color", std::move(color)}, {"valid", "lp_valid"}};
    if (shared.frames->params.map.gaze_angle > 0.0f) inputs.emplace_back("gaze", "gaze_color");
    std::vector<Port> outputs = {{"output", std::move(output)}};
    for (Port& port : resolve_decision_ports(shared.frames->params.mip_resolve))
        outputs.push_back(std::move(port));
    return {"resolve", inputs, outputs, resolve_stage, lp_state(shared)};
}

std::vector<Port> resolve_decision_ports(bool mip) {
    std::vector<Port> ports = {{"tap", "resolve_tap"}, {"tap_margin", "resolve_tap_margin"}};
    if (mip) {
        ports.emplace_back("mip_level", "resolve_mip_level");
        ports.emplace_back("mip_margin", "resolve_mip_margin");
    }
    return ports;
}

bool wants_resolve_decisions(const FrameContext& ctx) {
    for (const Port& decision : resolve_decision_ports(true))
        for (const Port& output : ctx.stage->outputs)
            if (output.slot == decision.slot && ctx.wants(output.slot)) return true;
    return false;
}

void output_resolve_decisions(const FrameContext& ctx, ResolveDecisions d) {
    ctx.output("tap", BufferKind::id, {"i0", "j0"}, std::move(d.tap));
    ctx.output("tap_margin", BufferKind::scalar, {"texels"}, std::move(d.tap_margin));
    if (d.mip_level.data.empty()) return;
    std::vector<std::string> levels = {"level"};
    if (d.mip_level.channels == 2) levels = {"i0_level", "i1_level"};
    ctx.output("mip_level", BufferKind::id, std::move(levels), std::move(d.mip_level));
    ctx.output("mip_margin", BufferKind::scalar, {"levels"}, std::move(d.mip_margin));
}

void ray_positions_stage(FrameContext& ctx) {
    const LogPolarMap map = ctx.state<LogPolarState>().shared.frames->map(ctx);
    const Image* gaze_valid = map.has_gaze_buffer() ? &ctx.input("gaze_valid") : nullptr;
    ctx.output("rays", BufferKind::scalar, {"rays"},
               ray_position_counts(map.screen_width, map.screen_height, ctx.input("valid"),
                                   ctx.input("screen_point"), gaze_valid, gaze_window(map)));
    ctx.output("pixel", BufferKind::id, {"x", "y"},
               ray_pixels(map.screen_width, map.screen_height, ctx.input("valid"),
                          ctx.input("screen_point")));
}

StageDef ray_positions_stage_def(const LogPolarStage& shared) {
    std::vector<Port> inputs = {{"valid", "lp_valid"}, {"screen_point", "lp_screen_point"}};
    if (shared.frames->params.map.gaze_angle > 0.0f) inputs.emplace_back("gaze_valid");
    return {"ray_positions",
            inputs,
            {{"rays", "ray_positions"}, {"pixel", "ray_pixel"}},
            ray_positions_stage,
            lp_state(shared)};
}

// ---- stereo ----------------------------------------------------------------------------------

std::array<LogPolarMap, 2> StereoFrames::maps(const FrameContext& ctx) const {
    return stereo_maps(params, *ctx.scene, ctx.camera, ctx.settings->width, ctx.settings->height,
                       ctx.frame);
}

std::array<Camera, 2> StereoFrames::cameras(const FrameContext& ctx, bool previous) const {
    const Camera& camera = previous ? ctx.previous_camera : ctx.camera;
    return {eye_camera(camera, 0, params.ipd), eye_camera(camera, 1, params.ipd)};
}

void stereo_trace_stage(FrameContext& ctx) {
    const StereoStage& s = ctx.state<StereoState>().shared;
    const std::array<LogPolarMap, 2> maps = s.frames->maps(ctx);
    Counters& counters = ctx.result->counters;
    FoveatedTraceStats stats;
    Image screen_points;
    const Offset2 jitter = frame_jitter(ctx, s.jitter);
    const std::array<Camera, 2> cameras = s.frames->cameras(ctx);
    const std::array<Camera, 2> previous = s.frames->cameras(ctx, true);
    MaskedGBuffer lp = trace_stereo_gbuffer(
        maps, eye_views(*ctx.scene, s.bvh->get(*ctx.scene, counters), cameras, previous),
        screen_points, stats, jitter);
    add_buffer_counters(ctx, maps[0], stats);
    counters.add("eyes", 2);
    add_trace_counters(counters, "primary", stats.rays.primary);
    ctx.note = "eye 0: " + map_note(maps[0]) + "; eye 1: " + map_note(maps[1]) + "; " +
               std::to_string(stats.texels_traced) + " traced" + jitter_note(jitter, "texel");
    output_buffer(ctx, std::move(lp), std::move(screen_points));
}

StageDef stereo_trace_stage_def(const StereoStage& shared) {
    return {"stereo_trace", {}, buffer_outputs(), stereo_trace_stage, stereo_state(shared)};
}

void stereo_resolve_stage(FrameContext& ctx) {
    StereoFrames& frames = *ctx.state<StereoState>().shared.frames;
    const StereoParams& params = frames.params;
    const std::array<LogPolarMap, 2> maps = frames.maps(ctx);
    const bool reused = frames.forward && frames.forward->made_for(params, maps);
    if (!reused) frames.forward = stereo_forward_table(params, maps);
    StereoResolveStats stats;
    Image out = resolve_stereo(params, maps, ctx.input("color"), ctx.input("valid"), stats,
                               &*frames.forward);
    ctx.result->counters.add("screen_pixels_untraced_taps", stats.resolve.pixels_untraced_taps);
    if (params.barrel)
        ctx.result->counters.add("screen_pixels_outside_lens", stats.pixels_outside_lens);
    ctx.note = std::string(params.barrel ? "bilinear, barrel distortion" : "bilinear") +
               (reused ? ", lookups reused" : ", lookups computed");
    ctx.output("output", BufferKind::color, {"r", "g", "b"}, std::move(out));
    const Image& color = ctx.input("color");
    if (wants_resolve_decisions(ctx))
        output_resolve_decisions(
            ctx, stereo_resolve_decisions(*frames.forward, color.width, color.height));
}

void stereo_internal_aa_stage(FrameContext& ctx) {
    ctx.output("output", BufferKind::color, {"r", "g", "b"},
               stereo_internal_aa(ctx.input("color"), ctx.input("valid")));
}

StageDef stereo_internal_aa_stage_def() {
    return {"internal_aa",
            {{"color", "lp_color"}, {"valid", "lp_valid"}},
            {{"output", "lp_color_aa"}},
            stereo_internal_aa_stage};
}

StageDef stereo_resolve_stage_def(const StereoStage& shared, std::string output) {
    std::vector<Port> outputs = {{"output", std::move(output)}};
    for (Port& port : resolve_decision_ports(false)) outputs.push_back(std::move(port));
    const std::string color = shared.frames->params.blur ? "lp_color_aa" : "lp_color";
    return {"resolve",
            {{"color", color}, {"valid", "lp_valid"}},
            outputs,
            stereo_resolve_stage,
            stereo_state(shared)};
}

void stereo_ray_positions_stage(FrameContext& ctx) {
    ctx.output("rays", BufferKind::scalar, {"rays"},
               ray_position_counts(ctx.settings->width, ctx.settings->height, ctx.input("valid"),
                                   ctx.input("screen_point"), nullptr));
    ctx.output("pixel", BufferKind::id, {"x", "y"},
               ray_pixels(ctx.settings->width, ctx.settings->height, ctx.input("valid"),
                          ctx.input("screen_point")));
}

StageDef stereo_ray_positions_stage_def(const StereoStage& shared) {
    return {"ray_positions",
            {{"valid", "lp_valid"}, {"screen_point", "lp_screen_point"}},
            {{"rays", "ray_positions"}, {"pixel", "ray_pixel"}},
            stereo_ray_positions_stage,
            stereo_state(shared)};
}

}  // namespace fovref
